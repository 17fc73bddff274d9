"""Every ``Examples`` section in the package runs and prints what it says (doctest), one test per module.

The modules are found by their text (a ``>>>`` in the file), so a new example is run without a change here.
They are imported and run in this process with ``doctest``, not with ``--doctest-modules``: that would
import every module of the package, the command-line entry point (``camcad/__main__.py``) and the editor's
GUI among them. An example that writes files writes into a temporary folder it makes itself.
"""

from __future__ import annotations

import doctest
import importlib
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "camcad"
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def modules_with_examples() -> list[str]:
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if ">>>" not in path.read_text(encoding="utf-8"):
            continue
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        names.append(".".join(parts))
    return names


@pytest.mark.parametrize("module_name", modules_with_examples())
def test_examples_run(module_name, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    module = importlib.import_module(module_name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    tests = finder.find(module, module_name)
    assert tests, f"{module_name} has '>>>' but doctest finds no example in it"
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {module_name} failed (see stdout)"


def test_the_public_api_is_covered():
    # every module that defines a public name has its examples run here
    import camcad

    found = set(modules_with_examples())
    defining = {camcad._EXPORTS[name] for name in camcad.__all__ if name != "__version__"}
    owned_elsewhere = {"camcad.balance.checking", "camcad.balance.correction", "camcad.io.law_write"}
    assert not (defining - owned_elsewhere - found), sorted(defining - owned_elsewhere - found)
