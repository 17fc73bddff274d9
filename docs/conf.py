"""Sphinx configuration of camcad's documentation.

Build (tests/project/test_docs_build.py runs exactly this, warnings as errors):
    sphinx-build -W -b html docs docs/_build/html
The API reference is autodoc + numpydoc on the public API (``camcad.__all__``); the guides are the Markdown
pages beside this file (MyST); the tutorial and the API walkthrough run their scripts at build time and show
what they print (``docs/_ext/camcad_examples.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))          # the camcad of this checkout, installed or not
sys.path.insert(0, str(HERE / "_ext"))

import camcad

project = "camcad"
author = "the camcad authors"
copyright = "the camcad authors, MIT licence"
version = release = camcad.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "camcad_examples",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "bench", "img", "linkage/*.png", "examples", "_ext", "Thumbs.db", ".DS_Store"]
# pages that other branches add; index.rst lists them only when they exist (camcad_examples.optional_pages)
optional_pages = ["fix", "sweep", "laws"]

# autodoc: the public API only, signatures as written, in source order
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
# numpydoc: the sections as written; no automatic member tables (they would list every private helper)
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = True

myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]
suppress_warnings = ["myst.header"]

html_theme = "alabaster"
html_title = f"camcad {release}"
html_static_path: list[str] = []
html_theme_options = {"description": "cam mechanisms from drawn acceleration laws", "fixed_sidebar": True,
                      "page_width": "1340px", "sidebar_width": "240px"}
