"""The README's worked example, run as written: every command's exit code and printed lines must match.

The commands and their expected output are read from README.md (docs/worked_example.py parses them), so
the README cannot drift from what camcad prints. The LibreCAD step needs LibreCAD; it is skipped without
it unless CAMCAD_REQUIRE_READERS is set (as in CI).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _worked_example():
    spec = importlib.util.spec_from_file_location("worked_example", ROOT / "docs" / "worked_example.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


worked = _worked_example()


def test_the_worked_example_has_its_steps():
    commands = [step.words()[:2] for step in worked.steps()]
    assert commands == [["camcad", "check"], ["camcad", "fix"], ["camcad", "check"], ["camcad", "profile"],
                        ["librecad", "dxf2pdf"]]
    assert worked.steps()[0].code == 1
    assert all(step.expected for step in worked.steps())


def test_a_step_may_set_the_environment_of_its_program():
    # LibreCAD's printer needs a display unless Qt is told to draw offscreen: the README may say so on the line
    step = worked.Step("QT_QPA_PLATFORM=offscreen librecad dxf2pdf -a p.dxf", [], 0)
    assert step.words() == ["librecad", "dxf2pdf", "-a", "p.dxf"]
    assert step.environment() == {"QT_QPA_PLATFORM": "offscreen"}
    assert worked.Step("camcad check a=b.dxf", [], 0).words() == ["camcad", "check", "a=b.dxf"]


def test_the_matcher_can_fail():
    assert worked.matches(["a", "...", "c"], ["a", "b", "b", "c"])
    assert not worked.matches(["a", "...", "c"], ["a", "b", "d"])
    assert not worked.matches(["a 1.0"], ["a 1.00"])


def test_the_worked_example_prints_what_the_readme_says(tmp_path):
    have_librecad = shutil.which("librecad") is not None
    if not have_librecad and os.environ.get("CAMCAD_REQUIRE_READERS"):
        pytest.fail("LibreCAD is required (CAMCAD_REQUIRE_READERS) but not installed")
    camcad = str(Path(sys.executable).parent / "camcad")
    results = worked.run(tmp_path, camcad, skip=() if have_librecad else ("librecad",))
    assert len(results) >= 4
    for step, done in results:
        printed = (done.stdout + done.stderr).rstrip("\n").splitlines()
        assert done.returncode == step.code, f"{step.command}: exit {done.returncode}\n" + "\n".join(printed)
        assert worked.matches(step.expected, printed), (
            f"{step.command} printed:\n" + "\n".join(printed) + "\n\nthe README says:\n" + "\n".join(step.expected))
    assert (tmp_path / "press_feed" / "profile.dxf").is_file()
    if have_librecad:
        assert (tmp_path / "press_feed" / "profile.pdf").stat().st_size > 1000


def test_the_architecture_page_lists_every_module_with_its_docstring():
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_architecture", ROOT / "docs" / "make_architecture.py")
    make = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make)
    assert (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8") == make.generated(), \
        "docs/architecture.md is stale: run python docs/make_architecture.py"
