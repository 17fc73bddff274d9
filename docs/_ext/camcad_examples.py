"""Sphinx helpers of camcad's documentation.

- ``.. camcad-example-output:: NAME`` shows what ``docs/examples/NAME.py`` prints, run at build time (the
  scripts run side by side when the build starts, each in a fresh temporary folder, with this checkout's
  camcad; the documents are read after that, so parallel reading sees the output), so the tutorial and
  the walkthrough always show the output of the code beside them. A script that fails fails the build.
- ``index.rst`` lists the optional pages (``optional_pages`` in conf.py: pages that land from other
  branches) only when they exist, in place of the line ``%OPTIONAL_PAGES%``.
- The guides' links relative to the repository root (their "README section") are made relative to docs/.
- Docstrings use ``|x|`` for absolute values, which reStructuredText reads as a substitution: the bars are
  escaped outside literals and doctest blocks.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from docutils import nodes
from sphinx.errors import ExtensionError
from sphinx.util.docutils import SphinxDirective

EXAMPLES = ("workflow", "api_walkthrough")
_OUTPUT: dict[str, str] = {}


def _root(app) -> Path:
    return Path(app.srcdir).resolve().parent


def run_examples(app) -> None:
    """Run every example script at once (in parallel with each other) and keep what each prints."""
    root = _root(app)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(
        [str(root)] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH") else [])))
    runs = {}
    for name in EXAMPLES:
        folder = tempfile.TemporaryDirectory(prefix=f"camcad-doc-{name}-")
        script = Path(app.srcdir) / "examples" / f"{name}.py"
        process = subprocess.Popen([sys.executable, str(script), str(Path(folder.name) / "out")], cwd=folder.name,
                                   env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        runs[name] = (process, folder)
    for name, (process, folder) in runs.items():
        out, err = process.communicate(timeout=600)
        folder.cleanup()
        if process.returncode != 0:
            raise ExtensionError(f"docs/examples/{name}.py failed (exit {process.returncode}):\n{err}")
        _OUTPUT[name] = out.replace(str(root) + os.sep, "")


class ExampleOutput(SphinxDirective):
    required_arguments = 1

    def run(self):
        name = self.arguments[0]
        if name not in _OUTPUT:
            raise self.error(f"unknown example {name!r}; known: {', '.join(EXAMPLES)}")
        text = _OUTPUT[name]
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


def optional_pages(app, docname: str, source: list[str]) -> None:
    if docname != app.config.root_doc or "%OPTIONAL_PAGES%" not in source[0]:
        return
    src = Path(app.srcdir)
    present = [page for page in app.config.optional_pages
               if (src / f"{page}.md").exists() or (src / f"{page}.rst").exists()]
    lines = "\n".join(f"   {page}" for page in present)
    source[0] = re.sub(r"^[ \t]*%OPTIONAL_PAGES%[ \t]*$", lines, source[0], flags=re.MULTILINE)


def root_relative_links(app, docname: str, source: list[str]) -> None:
    """The Markdown guides end with a "README section" whose links are relative to the repository root
    (``docs/edit.md``, ``docs/img/x.png``); inside the site they are relative to docs/."""
    if app.env.doc2path(docname).suffix == ".md":
        source[0] = re.sub(r"\]\(docs/", "](", source[0])


def _escape_bars(text: str) -> str:
    parts = text.split("``")
    for i in range(0, len(parts), 2):               # outside ``inline literals``
        parts[i] = re.sub(r"(?<!\\)\|", r"\\|", parts[i])
    return "``".join(parts)


def escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    in_doctest = False
    for i, line in enumerate(lines):
        stripped = line.strip()
        if stripped.startswith(">>>"):
            in_doctest = True
        elif not stripped:
            in_doctest = False
        if not in_doctest and "|" in line:
            lines[i] = _escape_bars(line)


def setup(app):
    app.add_config_value("optional_pages", [], "env")
    app.add_directive("camcad-example-output", ExampleOutput)
    app.connect("builder-inited", run_examples)
    app.connect("source-read", optional_pages)
    app.connect("source-read", root_relative_links)
    app.connect("autodoc-process-docstring", escape_bars, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
