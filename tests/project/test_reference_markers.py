"""The evidence rule of tests/conftest.py: a test of an analysis package or a reader names its reference
(``@pytest.mark.reference(KIND, source)``), or the collection fails listing it."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import conftest
import pytest


def _item(path: str, *markers):
    marks = {m.name: m for m in markers}
    return SimpleNamespace(path=Path(conftest.ROOT / path), nodeid=f"{path}::test_x",
                           get_closest_marker=marks.get, stash={})


def _mark(*args):
    return SimpleNamespace(name="reference", args=args)


def test_an_analysis_test_without_a_reference_fails_the_collection_naming_it():
    config = SimpleNamespace()
    good = _item("tests/law/test_a.py", _mark("closed form", "s = h/2 at the half rise"))
    elsewhere = _item("tests/cli/test_b.py")                       # the CLI's tests are not held to it
    for unmarked in (_item("tests/dynamics/test_c.py"), _item("tests/io/test_d.py")):
        with pytest.raises(pytest.UsageError, match=r"test_[cd]\.py::test_x names no reference"):
            conftest.pytest_collection_modifyitems(config, [good, elsewhere, unmarked])
    conftest.pytest_collection_modifyitems(config, [good, elsewhere])


@pytest.mark.parametrize("args", [("closed-form", "x"), ("property",), ("published", ""), ("regression", 3)])
def test_a_reference_of_an_unknown_kind_or_without_its_source_fails(args):
    with pytest.raises(pytest.UsageError, match="not \\(KIND, source\\) with a known KIND"):
        conftest.pytest_collection_modifyitems(SimpleNamespace(), [_item("tests/cli/test_e.py", _mark(*args))])


def test_in_an_xdist_worker_each_unmarked_test_errors_instead():
    item = _item("tests/balance/test_f.py")
    conftest.pytest_collection_modifyitems(SimpleNamespace(workerinput={}), [item])
    assert "names no reference" in item.stash[conftest._REFERENCE_PROBLEM]


def test_every_test_file_sits_in_a_package_folder():
    # a test file at the top of tests/, or in a folder tests/README.md does not list, would escape the rule
    tests = Path(conftest.__file__).resolve().parent
    assert not list(tests.glob("test_*.py"))
    folders = {p.parent.name for p in tests.glob("*/test_*.py")}
    assert folders == set(conftest.TEST_FOLDERS), folders ^ set(conftest.TEST_FOLDERS)
    readme = (tests / "README.md").read_text(encoding="utf-8")
    assert all(f"`{folder}/`" in readme for folder in conftest.TEST_FOLDERS)
