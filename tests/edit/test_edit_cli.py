"""`camcad edit --script` end to end: replaying edits headless, the must-show comparison with
`camcad fix`, the JSON keys, and every kind of bad input (one line, exit 2)."""

from __future__ import annotations

import json
import shutil
import sys
from collections import Counter

import ezdxf
import numpy as np
import pytest
from conftest import SAMPLES, file_digest

from camcad.law.source import load_law

CHECK_KEYS = {"areas", "velocity_closure", "displacement_closure", "rise", "return", "balanced", "tolerance"}


def _script(tmp_path, ops, name="edits.json"):
    path = tmp_path / name
    path.write_text(json.dumps(ops))
    return path


def _copy(tmp_path, name):
    target = tmp_path / name
    shutil.copy(SAMPLES / "dxf" / name, target)
    return target


@pytest.mark.parametrize("name", ["fig2_rise_area_too_large.dxf", "drawing_with_axes_grid_text.dxf"])
def test_move_undo_min_change_save_equals_fix(cli, tmp_path, name):
    """The issue's must-show: move, undo, min-change, save == `camcad fix --mode min-change`, to 1e-12."""
    source = _copy(tmp_path, name)
    digest = file_digest(source)
    script = _script(tmp_path, [{"op": "move", "x_deg": 100, "y": 1.0}, {"op": "undo"},
                                {"op": "correct", "mode": "min-change"}, {"op": "save", "path": "edited.dxf"}])
    result = cli("edit", source, "--script", script, "--json")
    assert result.code == 0, result.err
    payload = result.json()
    assert CHECK_KEYS <= set(payload) and payload["operations"] == 4 and payload["balanced"] is True
    edited = tmp_path / "edited.dxf"                       # relative to the script's folder
    assert payload["outputs"] == [str(edited)]
    check = cli("check", edited, "--json")
    assert check.code == 0 and check.json()["balanced"] is True
    fixed = tmp_path / "fixed.dxf"
    assert cli("fix", source, "--mode", "min-change", "-o", fixed, "--no-plots", "--json").code == 0
    ours, theirs = load_law(edited), load_law(fixed)
    scale = float(np.max(np.abs(theirs.law.a)))
    assert np.array_equal(ours.law.x, theirs.law.x)
    assert np.max(np.abs(ours.law.a - theirs.law.a)) <= 1e-12 * scale
    # the drawings: the same entities, every other entity kept, the original curve kept
    doc_in, doc_ed, doc_fx = ezdxf.readfile(source), ezdxf.readfile(edited), ezdxf.readfile(fixed)

    def kinds(doc):
        return Counter((e.dxftype(), e.dxf.layer) for e in doc.modelspace())

    assert kinds(doc_ed) == kinds(doc_fx)
    handle = ours.curve.handle
    in_other = Counter((e.dxftype(), e.dxf.layer) for e in doc_in.modelspace() if e.dxf.handle != handle)
    ed_other = Counter((e.dxftype(), e.dxf.layer) for e in doc_ed.modelspace()
                       if e.dxf.handle != handle and e.dxf.layer != "CAMCAD_ORIGINAL")
    assert in_other == ed_other
    # the original curve is kept as fix keeps it: in the block CAMCAD_ORIGINAL, which no reader draws
    original = list(doc_ed.blocks.get("CAMCAD_ORIGINAL"))
    drawn = doc_in.entitydb[handle]
    assert len(original) == 1 and np.array_equal(np.array(original[0].get_points("xy")),
                                                 np.array(drawn.get_points("xy")))
    edited_curve = np.array(doc_ed.entitydb[handle].get_points("xy"))
    fixed_curve = np.array(doc_fx.entitydb[handle].get_points("xy"))
    assert np.max(np.abs(edited_curve - fixed_curve)) <= 1e-12 * max(scale, 1.0)
    assert file_digest(source) == digest


def test_output_option_default_output_and_exit_code(cli, tmp_path):
    source = _copy(tmp_path, "fig2_rise_area_too_large.dxf")
    script = _script(tmp_path, [{"op": "move_lobe", "x_deg": 61, "y": 7.0}])
    result = cli("edit", source, "--script", script, "--json")
    assert result.code == 1                                  # still unbalanced: exit 1 like check
    assert result.json()["outputs"] == [str(tmp_path / "fig2_rise_area_too_large.edited.dxf")]
    out = tmp_path / "o.csv"
    result = cli("edit", source, "--script", script, "-o", out)
    assert result.code == 1 and out.exists() and "1 operations applied" in result.out
    assert "the profile does not close (gap" in result.out and "[" not in result.out.split("applied;")[1]  # no markup


def test_table_and_standard_law_inputs(cli, tmp_path):
    table = tmp_path / "law.csv"
    shutil.copy(SAMPLES / "law_table.csv", table)
    script = _script(tmp_path, [{"op": "correct", "mode": "min-change"}])
    result = cli("edit", table, "--script", script, "--json")
    assert result.code == 0, result.err
    assert result.json()["outputs"] == [str(tmp_path / "law.edited.csv")]
    assert load_law(tmp_path / "law.edited.csv").law.x.shape == load_law(table).law.x.shape
    out = tmp_path / "std.csv"
    result = cli("edit", "--standard", "cycloidal", "--phases", "0:120:rise,120:180:dwell,180:300:return,300:360:dwell",
                 "--lift", "25", "--script", script, "-o", out, "--json")
    assert result.code == 0, result.err
    assert result.json()["rise"] == pytest.approx(25.0, rel=1e-3)


@pytest.mark.parametrize("ops, words", [
    ([{"op": "move", "x_deg": 100}], ["operation 0", "'y' is missing"]),
    ([{"op": "undo"}], ["operation 0", "nothing to undo"]),
    ([{"op": "move", "x_deg": 400, "y": 1}], ["operation 0", "outside the cycle"]),
    ([{"op": "correct", "mode": "fastest"}], ["operation 0", "unknown mode"]),
    ([{"op": "spin"}], ["operation 0", "unknown operation 'spin'"]),
    ([{"op": "redo"}, {"op": "move", "x_deg": 1, "y": 1, "z": 0}], ["operation 1", "'z' is not a field"]),
    ([{"op": "correct", "mode": "segment", "segment": [0, 50]}], ["operation 0", "holds no vertex"]),
])
def test_bad_scripts_are_one_line_errors(cli, tmp_path, ops, words):
    source = _copy(tmp_path, "fig2_rise_area_too_large.dxf")
    result = cli("edit", source, "--script", _script(tmp_path, ops))
    assert result.code == 2, result.out
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error: ")
    for word in words:
        assert word in lines[0]
    assert not list(tmp_path.glob("*.edited.dxf"))


def test_a_save_over_the_input_is_refused(cli, tmp_path):
    source = _copy(tmp_path, "fig2_rise_area_too_large.dxf")
    digest = file_digest(source)
    (tmp_path / "link.dxf").symlink_to(source)
    for path in (source.name, "link.dxf"):
        result = cli("edit", source, "--script", _script(tmp_path, [{"op": "save", "path": path}]))
        assert result.code == 2 and "would replace the input" in result.err
    result = cli("edit", source, "--script", _script(tmp_path, [{"op": "save", "path": str(source)}]))
    assert result.code == 2 and "is absolute" in result.err     # save paths are relative to the output folder
    result = cli("edit", source, "--script", _script(tmp_path, []), "-o", source)
    assert result.code == 2 and "would replace the input" in result.err
    assert file_digest(source) == digest


def test_web_without_tornado_says_what_to_install(cli, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "tornado", None)
    source = _copy(tmp_path, "fig2_rise_area_too_large.dxf")
    result = cli("edit", source, "--web", "--no-browser")
    assert result.code == 2
    assert "install camcad[edit]" in result.err and len(result.err.strip().splitlines()) == 1


def test_malformed_json_script(cli, tmp_path):
    source = _copy(tmp_path, "fig2_rise_area_too_large.dxf")
    bad = tmp_path / "bad.json"
    bad.write_text('{"op": "move"')
    result = cli("edit", source, "--script", bad)
    assert result.code == 2 and "not valid JSON" in result.err
