"""Shared test helpers: running the CLI in-process, sample paths, the real-drawing corpus."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"
REAL_DXF = ROOT.parent / "shared" / "dxf-real"


#: the kinds of independent reference a numerical test may rest on (``@pytest.mark.reference(KIND, source)``)
REFERENCE_KINDS = ("closed form", "second method", "published", "property", "regression")


def pytest_configure(config):
    """Register the markers; byte-compile camcad once, so the many ``camcad`` subprocesses of the tests load
    bytecode instead of compiling ~40 modules from source each (an editable install under ``PYTHONDONTWRITEBYTECODE=1``
    never writes ``__pycache__``; 0.14 s per process here). The test outcomes do not depend on it."""
    config.addinivalue_line(
        "markers",
        "reference(kind, source): the independent reference a numerical test checks against; kind is one of "
        + ", ".join(REFERENCE_KINDS) + "; source names the formula, paper, second method or property")
    import compileall

    compileall.compile_dir(str(ROOT / "camcad"), quiet=1)


def file_digest(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class CliResult:
    def __init__(self, code: int, out: str, err: str):
        self.code, self.out, self.err = code, out, err

    def json(self) -> dict:
        return json.loads(self.out)


@pytest.fixture
def cli(capsys):
    """Run ``camcad ARGS`` in this process; returns CliResult(code, stdout, stderr)."""
    from camcad.cli import main

    def run(*args: str) -> CliResult:
        capsys.readouterr()
        try:
            main([str(a) for a in args])
            code = 0
        except SystemExit as stop:
            code = int(stop.code or 0)
        captured = capsys.readouterr()
        return CliResult(code, captured.out, captured.err)

    return run


@pytest.fixture
def real_dxf():
    """The corpus of real drawings beside the project; missing: a skip, or a failure in CI
    (CAMCAD_REQUIRE_READERS=1)."""
    import os

    if not REAL_DXF.is_dir():
        if os.environ.get("CAMCAD_REQUIRE_READERS") == "1":
            pytest.fail("../shared/dxf-real is not beside the project but CAMCAD_REQUIRE_READERS=1")
        pytest.skip("../shared/dxf-real is not beside the project")
    return REAL_DXF
