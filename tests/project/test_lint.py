"""The tree stays lint- and type-clean: ``ruff check`` and ``mypy camcad`` with the configuration in
pyproject.toml ([tool.ruff], [tool.mypy]). Each is skipped when its tool is not installed (the ``test``
extra installs both).

mypy keeps its cache in the system's temporary folder (one per checkout), so a second run takes about a
second; a cold run takes some 35 s on two busy cores.
"""

from __future__ import annotations

import hashlib
import importlib.util
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from conftest import ROOT

#: what ruff checks: the package, the tests, the benchmarks and the Python under docs/ and samples/
RUFF_PATHS = ["camcad", "tests", "benchmarks", "docs/examples", "docs/worked_example.py", "samples/make_samples.py"]


def _require(module: str) -> None:
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not installed (pip install -e .[test])")


def _run(*args: str, timeout: float) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, check=False)


def test_ruff_check_is_clean():
    _require("ruff")
    paths = [p for p in RUFF_PATHS if (ROOT / p).exists()]
    done = _run("ruff", "check", "--no-cache", "--output-format", "concise", *paths, timeout=120)
    assert done.returncode == 0, f"ruff check {' '.join(paths)}:\n{done.stdout}{done.stderr}"


def test_mypy_camcad_is_clean():
    _require("mypy")
    key = hashlib.sha256(str(ROOT).encode()).hexdigest()[:12]
    cache = Path(tempfile.gettempdir()) / f"camcad-mypy-cache-{key}"
    done = _run("mypy", "--cache-dir", str(cache), "camcad", timeout=600)
    assert done.returncode == 0, f"mypy camcad:\n{done.stdout}{done.stderr}"
