"""The documentation builds with Sphinx with warnings as errors (numpydoc API reference, MyST guides, the
tutorial and the API walkthrough with the output of their scripts), as ``sphinx-build -W -b html docs OUT``.

Runs in a temporary folder; takes about 20 s on an idle machine (most of it the two example scripts, which
run side by side). Skipped where Sphinx, numpydoc or myst-parser is missing (``pip install -e '.[docs]'``);
CI installs them.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_the_documentation_builds_without_a_warning(tmp_path):
    for module in ("sphinx", "numpydoc", "myst_parser"):
        pytest.importorskip(module)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
                           "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(tmp_path / "html")],
                          capture_output=True, text=True, timeout=300, env=env, cwd=tmp_path, check=False)
    assert done.returncode == 0, (done.stderr or done.stdout)[-4000:]
    assert not done.stderr.strip(), done.stderr[-4000:]
    html = tmp_path / "html"
    for page in ("index", "tutorial", "walkthrough", "SCENE", "reading", "analyses", "edit", "linkage",
                 "api/laws", "api/balance", "api/profile", "api/fourier", "api/dynamics", "api/contact",
                 "api/cyclogram", "api/scenes", "api/plots", "api/linkage", "api/errors"):
        assert (html / f"{page}.html").is_file(), page
    # every public name has its entry in the API reference
    import camcad

    reference = "".join((html / "api" / f"{p}.html").read_text(encoding="utf-8") for p in
                        ("laws", "balance", "profile", "fourier", "dynamics", "contact", "cyclogram", "scenes",
                         "plots", "linkage", "errors"))
    for name in camcad.__all__:
        if name == "__version__":
            continue
        anchor = "camcad.profile.summary.report" if name == "report" else f"camcad.{name}"
        assert f'id="{anchor}"' in reference, name
    # the tutorial and the walkthrough show what their scripts printed at build time
    assert "balanced after: True" in (html / "tutorial.html").read_text(encoding="utf-8")
    assert "== errors" in (html / "walkthrough.html").read_text(encoding="utf-8")
