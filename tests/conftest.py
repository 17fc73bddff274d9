"""Shared test helpers: running the CLI in-process, sample paths, the real-drawing corpus, CPU time and the
``timing`` marker."""

from __future__ import annotations

import hashlib
import json
import math
import os
import resource
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples"
#: real drawings written by other programs, in the repository (tests/fixtures/dxf-real/README.md: the MIT-licensed
#: ones copied with their licence notes, our own stand-ins for the GPL-licensed ones)
REAL_DXF = ROOT / "tests" / "fixtures" / "dxf-real"
#: the corpus they come from, beside the project when it is there (it also holds the GPL-licensed originals)
SHARED_DXF = ROOT.parent / "shared" / "dxf-real"
#: a ``timing`` test is skipped when the machine runs more than this many processes per core (1-minute load)
LOAD_PER_CORE_LIMIT = 2.0


#: the kinds of independent reference a numerical test may rest on (``@pytest.mark.reference(KIND, source)``)
REFERENCE_KINDS = ("closed form", "second method", "published", "property", "regression")
#: the test folders of the analysis packages and the readers (tests/README.md): every test there names its reference
REFERENCE_FOLDERS = ("law", "balance", "fourier", "profile", "dynamics", "contact", "cyclogram", "linkage", "scene",
                     "sweep", "io")
#: every folder of tests/ and what it tests (tests/README.md)
TEST_FOLDERS = REFERENCE_FOLDERS + ("edit", "report", "cli", "project")


def pytest_configure(config):
    """Register the markers; byte-compile camcad once, so the many ``camcad`` subprocesses of the tests load
    bytecode instead of compiling ~40 modules from source each (an editable install under ``PYTHONDONTWRITEBYTECODE=1``
    never writes ``__pycache__``; 0.14 s per process here). The test outcomes do not depend on it."""
    config.addinivalue_line(
        "markers",
        "reference(kind, source): the independent reference a numerical test checks against; kind is one of "
        + ", ".join(REFERENCE_KINDS) + "; source names the formula, paper, second method or property")
    config.addinivalue_line(
        "markers",
        "timing: asserts a bound on CPU time (process and children, never wall time); skipped on a machine loaded "
        f"above {LOAD_PER_CORE_LIMIT:g} runnable processes per core")
    import compileall

    compileall.compile_dir(str(ROOT / "camcad"), quiet=1)


@dataclass(frozen=True)
class CosineLaw:
    """s = (h/2)(1 − cos θ) (mm, θ rad): a single harmonic, whose steady-state response is a closed form."""

    lift: float = 25.0
    cycle: float = 2 * math.pi
    phases: tuple = ()

    def kinematics(self, theta):
        from camcad.law.law import Kinematics

        theta = np.asarray(theta, dtype=float)
        h = self.lift / 2
        return Kinematics(theta, h * (1 - np.cos(theta)), h * np.sin(theta), h * np.cos(theta), -h * np.sin(theta))


def folder_of(path: Path) -> str:
    """The package folder a test file belongs to: <folder> of tests/<folder>/test_x.py."""
    return Path(path).parent.name


def pytest_collection_modifyitems(config, items):
    """Every test in the analysis packages' and the readers' folders names its reference
    (``@pytest.mark.reference(KIND, source)``, KIND one of REFERENCE_KINDS): collection fails otherwise, listing
    the tests that do not, so that ``pytest --collect-only -m reference`` lists every one of them. (In an xdist
    worker an exception here would end the worker without the list: there each such test errors instead.)"""
    problems = {}
    for item in items:
        marker = item.get_closest_marker("reference")
        if marker is None:
            if folder_of(item.path) in REFERENCE_FOLDERS:
                problems[item.nodeid] = "names no reference"
            continue
        kind, source = (tuple(marker.args) + (None, None))[:2]
        if len(marker.args) != 2 or kind not in REFERENCE_KINDS or not isinstance(source, str) or not source.strip():
            problems[item.nodeid] = f"has reference{marker.args!r}, not (KIND, source) with a known KIND"
    if not problems:
        return
    how = (f"mark each @pytest.mark.reference(KIND, source), KIND one of {', '.join(REFERENCE_KINDS)}; every test "
           f"in tests/{{{','.join(REFERENCE_FOLDERS)}}}/ needs one")
    if hasattr(config, "workerinput"):
        for item in items:
            if item.nodeid in problems:
                item.stash[_REFERENCE_PROBLEM] = f"{item.nodeid} {problems[item.nodeid]}: {how}"
        return
    raise pytest.UsageError("\n".join([f"{len(problems)} tests without a proper reference marker ({how}):"]
                                      + [f"  {nodeid} {why}" for nodeid, why in problems.items()]))


_REFERENCE_PROBLEM = pytest.StashKey[str]()


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
    """The folder of real drawings written by other programs (tests/fixtures/dxf-real, in the repository)."""
    assert REAL_DXF.is_dir(), REAL_DXF
    return REAL_DXF


def load_per_core() -> float:
    """The 1-minute load average per core (runnable processes per core)."""
    return os.getloadavg()[0] / (os.cpu_count() or 1)


def pytest_runtest_setup(item):
    """A test without its reference marker errors (in an xdist worker: see pytest_collection_modifyitems). A
    ``timing`` test is skipped, saying why, on a loaded machine (``CAMCAD_TIMING=always`` runs it anyway): CPU time
    is far steadier than wall time, but a core shared by several processes still stretches it (caches,
    frequency)."""
    if _REFERENCE_PROBLEM in item.stash:
        pytest.fail(item.stash[_REFERENCE_PROBLEM], pytrace=False)
    if item.get_closest_marker("timing") is not None and os.environ.get("CAMCAD_TIMING") != "always":
        load = load_per_core()
        if load > LOAD_PER_CORE_LIMIT:
            pytest.skip(f"timing: the machine is loaded ({load:.1f} runnable processes per core over the last "
                        f"minute, above {LOAD_PER_CORE_LIMIT:g}); the CPU-time bound is not checked")


def cpu_seconds() -> float:
    """CPU seconds used so far by this process and its waited-for children (user + system)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime
