"""The editor's model alone (camcad.edit.session): every operation against closed forms of the
piecewise-linear law, undo/redo symmetry, gestures, corrections, saving, the script format, and a
property test that random operation sequences never corrupt the law nor lose the drawing."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from collections import Counter

import ezdxf
import numpy as np
import pytest
from conftest import ROOT, SAMPLES, cpu_seconds, file_digest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from camcad.balance import MODES, correct, difference_norms
from camcad.edit.session import (
    EditSession,
    law_problems,
    load_script,
    loaded_from_law,
    normalize_operation,
    sampled_law,
    validate_script,
)
from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.phases import detect_phases
from camcad.law.source import load_law

DXF = SAMPLES / "dxf"
T = 2 * math.pi


def triangles() -> PiecewiseLinearLaw:
    """Dwell 0–60, rise 60–180 (two triangles ±10), dwell 180–240, return 240–360: balanced by symmetry."""
    x = np.radians([0, 60, 90, 120, 150, 180, 240, 270, 300, 330, 360.0])
    a = np.array([0, 0, 10, 0, -10, 0, 0, -10, 0, 10, 0.0])
    return PiecewiseLinearLaw(x, a, T, detect_phases(x, a, T))


def session_of(law: PiecewiseLinearLaw) -> EditSession:
    return EditSession(loaded_from_law(law, "test law"))


def rise_v_end(session: EditSession) -> float:
    return next(r["v_end"] for r in session.report.phases if r["kind"] == "rise")


def hat_moments(x: np.ndarray, i: int, cycle: float) -> tuple[float, float]:
    """∫φ_i dθ and ∫(T − θ)φ_i dθ of the hat function of vertex i: a triangle of height 1 on
    [x_{i−1}, x_{i+1}], area (h1 + h2)/2, centroid (3x_i − h1 + h2)/3 (independent of the library)."""
    h1, h2 = x[i] - x[i - 1], x[i + 1] - x[i]
    area = (h1 + h2) / 2
    centroid = (3 * x[i] - h1 + h2) / 3
    return area, area * (cycle - centroid)


def exact_areas(x: np.ndarray, a: np.ndarray, start: float, end: float) -> tuple[float, float]:
    """(positive, negative) area of the polyline on [start, end], a plain loop over segments cut at zero."""
    pos = neg = 0.0
    for x0, x1, a0, a1 in zip(x[:-1], x[1:], a[:-1], a[1:]):
        if x1 <= start or x0 >= end or x1 == x0:
            continue
        if a0 * a1 < 0:
            xc = x0 + (x1 - x0) * a0 / (a0 - a1)
            parts = [(xc - x0) * a0 / 2, (x1 - xc) * a1 / 2]
        else:
            parts = [(x1 - x0) * (a0 + a1) / 2]
        for p in parts:
            if p > 0:
                pos += p
            else:
                neg += p
    return pos, neg


# --- the operations against closed forms ---------------------------------------------------------

def test_move_changes_the_closures_by_the_hat_function_moments():
    s = session_of(triangles())
    before_v, before_s = rise_v_end(s), s.report.displacement_closure
    assert abs(before_v) < 1e-12 and abs(before_s) < 1e-12
    x = s.law.x.copy()
    s.apply({"op": "move", "x_deg": 90.2, "y": 13.0})  # vertex at 90 deg: 10 -> 13
    area, moment = hat_moments(x, 2, T)
    assert rise_v_end(s) - before_v == pytest.approx(3.0 * area, rel=1e-12)
    assert s.report.displacement_closure - before_s == pytest.approx(3.0 * moment, rel=1e-12)
    assert s.law.a[2] == 13.0 and np.array_equal(s.law.x, x)


def test_insert_on_and_off_the_polyline():
    s = session_of(triangles())
    s.apply({"op": "insert", "x_deg": 75, "y": 5.0})     # on the segment 60..90 (0 -> 10): no change
    assert len(s.law.x) == 12
    assert abs(rise_v_end(s)) < 1e-12 and abs(s.report.displacement_closure) < 1e-12
    s.apply({"op": "undo"})
    s.apply({"op": "insert", "x_deg": 75, "y": 8.0})     # 3 above the segment: a triangle over 60..90
    assert rise_v_end(s) == pytest.approx(3.0 * math.radians(30) / 2, rel=1e-12)
    with pytest.raises(CamcadError, match="already at 75"):
        s.apply({"op": "insert", "x_deg": 75, "y": 1.0})
    with pytest.raises(CamcadError, match="strictly inside"):
        s.apply({"op": "insert", "x_deg": 360, "y": 1.0})


def test_delete_refuses_the_ends_and_too_few_vertices():
    s = session_of(triangles())
    s.apply({"op": "insert", "x_deg": 75, "y": 5.0})
    s.apply({"op": "delete", "x_deg": 75})                # a vertex on a straight segment: no change
    assert np.array_equal(s.law.x, triangles().x) and np.array_equal(s.law.a, triangles().a)
    for end in (0, 360):
        with pytest.raises(CamcadError, match="ends of the cycle"):
            s.apply({"op": "delete", "x_deg": end})
    law = PiecewiseLinearLaw(np.array([0, 1, T]), np.array([1.0, -2.0, 1.0]), T, ())
    three = session_of(law)
    with pytest.raises(CamcadError, match="at least 3"):
        three.apply({"op": "delete", "x_deg": math.degrees(1)})
    assert len(three.law.x) == 3


def test_jump_make_and_remove():
    s = session_of(triangles())
    x = s.law.x.copy()
    s.apply({"op": "jump", "x_deg": 90, "y": 6.0})       # after 90 deg the segment to 120 starts at 6, not 10
    assert np.count_nonzero(s.law.x == x[2]) == 2
    assert rise_v_end(s) == pytest.approx((6.0 - 10.0) * (x[3] - x[2]) / 2, rel=1e-12)
    with pytest.raises(CamcadError, match="already a jump"):
        s.apply({"op": "jump", "x_deg": 90})
    s.apply({"op": "move", "x_deg": 90, "y": 2.0, "end": "right"})
    assert s.law.a[3] == 2.0 and s.law.a[2] == 10.0
    s.apply({"op": "unjump", "x_deg": 90})                # ends merge at their mean (10 + 2)/2
    assert len(s.law.x) == 11 and s.law.a[2] == 6.0
    with pytest.raises(CamcadError, match="no jump"):
        s.apply({"op": "unjump", "x_deg": 90})
    with pytest.raises(CamcadError, match="ends of the cycle"):
        s.apply({"op": "jump", "x_deg": 0})


def test_move_in_angle_clamps_at_the_neighbours():
    s = session_of(triangles())
    s.apply({"op": "move", "x_deg": 90, "y": 10.0, "to_x_deg": 200})   # past 120: stops there, a jump
    assert s.law.x[2] == s.law.x[3] == pytest.approx(math.radians(120), abs=0)
    assert not law_problems(s.law)
    # a jump's two ends move together and never join a third vertex
    s.apply({"op": "move", "x_deg": 120, "y": 10.0, "to_x_deg": 170})
    assert s.law.x[2] == s.law.x[3] < s.law.x[4]
    assert math.degrees(s.law.x[4] - s.law.x[3]) == pytest.approx(1e-6, rel=1e-6)
    # the cycle's ends never move in angle
    s.apply({"op": "move", "x_deg": 0, "y": 0.0, "to_x_deg": 30})
    assert s.law.x[0] == 0.0
    with pytest.raises(CamcadError, match="outside the cycle"):
        s.apply({"op": "move", "x_deg": 400, "y": 1.0})


def test_lobe_drag_scales_the_lobe_and_its_area():
    loaded = load_law(DXF / "fig2_rise_area_too_large.dxf")
    s = EditSession(loaded)
    a0 = s.law.a.copy()
    rise = next(p for p in s.law.phases if p.kind == "rise")
    pos0, _ = exact_areas(s.law.x, a0, rise.start, rise.end)
    peak = int(np.argmax(a0))
    s.apply({"op": "move_lobe", "x_deg": math.degrees(s.law.x[peak]), "y": a0[peak] * 0.9})
    changed = np.flatnonzero(s.law.a != a0)
    assert np.all(a0[changed] > 0) and len(changed) > 50
    assert np.allclose(s.law.a[changed], a0[changed] * 0.9, rtol=1e-15, atol=0)
    pos1, _ = exact_areas(s.law.x, s.law.a, rise.start, rise.end)
    assert s.report.areas["rise_accel"] == pytest.approx(pos1, rel=1e-12)
    assert pos1 == pytest.approx(0.9 * pos0, rel=2e-3)  # the crossing segment is not scaled exactly
    # a lobe is not dragged through the axis: it flattens onto it
    s.apply({"op": "move_lobe", "x_deg": math.degrees(s.law.x[peak]), "y": -1.0})
    assert np.all(s.law.a[changed] == 0)
    with pytest.raises(CamcadError, match="on the axis"):
        s.apply({"op": "move_lobe", "x_deg": 10, "y": 1.0})


def test_extremum_group_moves_together():
    s = EditSession(load_law(DXF / "constant_accel_jumps.dxf"))
    a0 = s.law.a.copy()
    top = float(a0.max())
    group = np.flatnonzero(a0 == top)
    assert len(group) >= 2  # a constant-acceleration plateau
    s.apply({"op": "move_extrema", "x_deg": math.degrees(s.law.x[group[0]]), "y": top * 1.1})
    assert np.all(s.law.a[group] == top * 1.1)
    assert np.array_equal(np.delete(s.law.a, group), np.delete(a0, group))


def test_phase_boundary_stretches_both_phases():
    s = session_of(triangles())
    rows0 = {r["kind"] + str(i): r for i, r in enumerate(s.report.phases)}
    s.apply({"op": "move_phase", "from_deg": 180.3, "to_deg": 190})   # rise 60..180 -> 60..190
    f = 130 / 120
    rise = s.report.phases[1]
    assert (rise["start_deg"], rise["end_deg"]) == pytest.approx((60, 190), abs=1e-12)
    assert rise["area_positive"] == pytest.approx(f * rows0["rise1"]["area_positive"], rel=1e-12)
    assert rise["area_negative"] == pytest.approx(f * rows0["rise1"]["area_negative"], rel=1e-12)
    assert np.degrees(s.law.x[2]) == pytest.approx(60 + 30 * f, rel=1e-12)
    assert np.array_equal(s.law.a, triangles().a)
    with pytest.raises(CamcadError, match="must stay between"):
        s.apply({"op": "move_phase", "from_deg": 190, "to_deg": 250})
    with pytest.raises(CamcadError, match="no phase boundary near"):
        s.apply({"op": "move_phase", "from_deg": 100, "to_deg": 101})
    s.apply({"op": "detect_phases"})
    assert [p.kind for p in s.law.phases] == ["dwell", "rise", "dwell", "return"]


# --- corrections --------------------------------------------------------------------------------

def test_correct_equals_the_library_and_preview_accept_reject():
    loaded = load_law(DXF / "fig2_rise_area_too_large.dxf")
    s = EditSession(loaded)
    law0 = s.law
    preview = s.preview_correction("min-change")
    assert s.law is law0                                    # a preview changes nothing
    expected = correct(loaded.law, "min-change")
    assert np.max(np.abs(preview.correction.law.a - expected.law.a)) <= 1e-12 * np.max(np.abs(expected.law.a))
    assert preview.max_change == pytest.approx(expected.max_change / loaded.y_scale, rel=1e-12)
    s.reject()
    assert s.preview is None and s.law is law0 and s.applied == 0
    s.preview_correction("min-change")
    s.accept()
    assert s.report.balanced and s.operations == [{"op": "correct", "mode": "min-change"}]
    s.apply({"op": "undo"})
    assert s.law is law0


def test_correct_on_a_range_holds_the_rest():
    s = EditSession(load_law(DXF / "fig2_rise_area_too_large.dxf"))
    a0 = s.law.a.copy()
    s.apply({"op": "correct", "mode": "keypoints", "segment": [100, 360]})
    outside = s.law.x < math.radians(100)
    assert np.array_equal(s.law.a[outside], a0[outside])
    assert s.report.balanced


def test_an_impossible_correction_leaves_the_law_unchanged():
    s = EditSession(load_law(DXF / "fig2_rise_area_too_large.dxf"))
    law0 = s.law
    with pytest.raises(CamcadError):
        s.apply({"op": "correct", "mode": "segment", "segment": [0, 50]})  # only a dwell: nothing to move
    with pytest.raises(CamcadError):
        s.preview_correction("segment", (0, 50))
    assert s.law is law0 and s.preview is None and s.applied == 0 and not s.can_undo


def test_compare_all_modes():
    s = EditSession(load_law(DXF / "fig2_rise_area_too_large.dxf"))
    rows = {r.mode: r for r in s.compare_modes()}
    assert set(rows) == set(MODES)
    assert rows["min-change"].balanced and rows["segment"].error
    # min-change has the least RMS change of the modes that balance (it minimises exactly that)
    rms = [r.rms_change for r in rows.values() if r.balanced]
    assert rows["min-change"].rms_change == pytest.approx(min(rms), rel=1e-9)


# --- undo / redo, gestures ----------------------------------------------------------------------

OPS_FOR_UNDO = [
    {"op": "move", "x_deg": 90, "y": 12.5},
    {"op": "move", "x_deg": 90, "y": 7.0, "to_x_deg": 100},
    {"op": "move_lobe", "x_deg": 90, "y": 4.0},
    {"op": "move_extrema", "x_deg": 150, "y": -12.0},
    {"op": "insert", "x_deg": 200, "y": 0.5},
    {"op": "delete", "x_deg": 270},
    {"op": "jump", "x_deg": 300, "y": 2.0},
    {"op": "move_phase", "from_deg": 240, "to_deg": 235},
    {"op": "correct", "mode": "min-change"},
]


@pytest.mark.parametrize("op", OPS_FOR_UNDO, ids=lambda op: op["op"])
def test_undo_restores_the_exact_arrays_and_redo_the_result(op):
    s = session_of(triangles())
    s.apply({"op": "move", "x_deg": 150, "y": -11.0})   # unbalanced, so corrections do something
    before = (s.law.x.tobytes(), s.law.a.tobytes(), s.law.phases)
    s.apply(op)
    after = (s.law.x.tobytes(), s.law.a.tobytes(), s.law.phases)
    assert after != before
    s.apply({"op": "undo"})
    assert (s.law.x.tobytes(), s.law.a.tobytes(), s.law.phases) == before
    s.apply({"op": "redo"})
    assert (s.law.x.tobytes(), s.law.a.tobytes(), s.law.phases) == after


def test_detect_phases_and_its_undo():
    from camcad.law.law import Phase

    law = triangles()
    given = (Phase("rise", 0.0, math.radians(200)), Phase("return", math.radians(200), T))
    s = session_of(PiecewiseLinearLaw(law.x, law.a, T, given))
    s.apply({"op": "detect_phases"})
    assert [p.kind for p in s.law.phases] == ["dwell", "rise", "dwell", "return"]
    assert np.array_equal(s.law.a, law.a)
    s.apply({"op": "undo"})
    assert s.law.phases == given


def test_nothing_to_undo_or_redo_is_an_error():
    s = session_of(triangles())
    with pytest.raises(CamcadError, match="nothing to undo"):
        s.apply({"op": "undo"}, index=0, where="e.json")
    with pytest.raises(CamcadError, match="nothing to redo"):
        s.apply({"op": "redo"})
    assert s.applied == 0


def test_a_gesture_is_one_undo_step_and_one_operation():
    s = session_of(triangles())
    law0 = s.law
    s.begin_gesture()
    for y in np.linspace(10, 20, 15):
        s.apply({"op": "move_lobe", "x_deg": 90, "y": float(y)})
    op = s.end_gesture()
    assert op == {"op": "move_lobe", "x_deg": 90.0, "y": 20.0}
    assert s.operations == [op]
    single = session_of(triangles())
    single.apply(op)
    assert s.law.a.tobytes() == single.law.a.tobytes()   # the gesture = its last step from the start
    s.apply({"op": "undo"})
    assert s.law is law0 and not s.can_undo
    s.begin_gesture()
    s.apply({"op": "move", "x_deg": 90, "y": 11.0})
    s.cancel_gesture()
    assert s.law is law0 and s.applied == 2   # the drag and its undo


def _dense_drag(session):
    """Drag the first lobe of the dense law in 20 steps; returns the CPU seconds per step."""
    peak = math.degrees(session.law.x[int(np.argmax(session.law.a))])
    start = cpu_seconds()
    session.begin_gesture()
    for y in np.linspace(1.0, 0.9, 20):
        session.apply({"op": "move_lobe", "x_deg": peak, "y": float(y)})
        assert session.report.tolerance > 0
    session.end_gesture()
    return (cpu_seconds() - start) / 20


def _dense_session():
    x = np.linspace(0, T, 10_000)
    a = np.where(x < math.pi, np.sin(2 * x), 1.02 * np.sin(2 * x))
    return session_of(PiecewiseLinearLaw(x, a, T, detect_phases(x, a, T)))


def test_dense_law_lobe_drag_keeps_every_vertex_and_a_sound_law():
    s = _dense_session()
    _dense_drag(s)
    assert len(s.law.x) == 10_000 and not law_problems(s.law)


@pytest.mark.timing
def test_dense_law_lobe_drag_stays_fast():
    # per drag step: the law, its integral and its check, under 0.05 s of CPU
    assert _dense_drag(_dense_session()) < 0.05


# --- saving -------------------------------------------------------------------------------------

def test_save_never_overwrites_the_input_even_through_a_link(tmp_path):
    source = tmp_path / "law.dxf"
    shutil.copy(DXF / "fig2_rise_area_too_large.dxf", source)
    digest = file_digest(source)
    s = EditSession.from_file(source)
    link = tmp_path / "link.dxf"
    link.symlink_to(source)
    for target in (source, link, tmp_path / "." / "law.dxf"):
        with pytest.raises(CamcadError, match="would replace the input"):
            s.save(target)
    with pytest.raises(CamcadError, match=r"cannot save as \.png"):
        s.save(tmp_path / "x.png")
    assert file_digest(source) == digest


def test_save_dxf_csv_and_script(tmp_path):
    source = tmp_path / "law.dxf"
    shutil.copy(DXF / "drawing_with_axes_grid_text.dxf", source)
    s = EditSession.from_file(source)
    s.apply({"op": "correct", "mode": "min-change"})
    s.save(tmp_path / "out.dxf")
    s.save(tmp_path / "out.csv")
    s.save(tmp_path / "out.json")
    again = load_law(tmp_path / "out.dxf")
    assert np.allclose(again.law.a, s.law.a, rtol=0, atol=1e-9 * np.max(np.abs(s.law.a)))
    table = load_law(tmp_path / "out.csv")
    assert np.allclose(table.law.a, s.law.a, rtol=0, atol=1e-9 * np.max(np.abs(s.law.a)))
    assert json.loads((tmp_path / "out.json").read_text()) == [{"op": "correct", "mode": "min-change"}]
    assert [op["op"] for op in s.operations] == ["correct", "save", "save", "save"]


def test_standard_law_is_sampled_with_its_jumps():
    from camcad.law.standard import compose

    law = compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 25.0, "harmonic", "harmonic")
    poly = sampled_law(law, 0.5)
    assert not law_problems(poly)
    # harmonic: a jumps at the phase ends; each becomes two vertices at one angle
    assert np.count_nonzero(np.diff(poly.x) == 0) >= 3
    theta = np.linspace(0, T, 7201)
    s_exact = law.kinematics(theta).s
    assert np.max(np.abs(poly.kinematics(theta).s - s_exact)) < 2e-3 * 25


# --- the script format ----------------------------------------------------------------------------

@pytest.mark.parametrize("ops, pattern", [
    ({"op": "move"}, "not a list"),
    ([{"op": "move", "x_deg": 1}], r"operation 0 \(move\).*'y' is missing"),
    ([{"op": "undo"}, {"op": "move", "x_deg": "a", "y": 1}], r"operation 1 \(move\).*'x_deg' must be a finite number"),
    ([{"op": "wiggle"}], "operation 0.*unknown operation 'wiggle'"),
    ([{"op": "move", "x_deg": 1, "y": 1, "yy": 2}], r"operation 0 \(move\).*'yy' is not a field"),
    ([{"op": "correct", "mode": "best"}], "unknown mode 'best'"),
    ([{"op": "correct", "mode": "segment", "segment": [1]}], "'segment' must be a list of two numbers"),
    ([{"op": "move", "x_deg": 1, "y": 1, "end": "middle"}], "'end' must be"),
    (["move"], "operation 0.*JSON object"),
    ([{"x_deg": 1}], 'key "op" is missing'),
])
def test_malformed_scripts_name_the_operation_and_key(ops, pattern):
    with pytest.raises(CamcadError, match=pattern):
        validate_script(ops, "e.json")


def test_load_script_errors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("[{\"op\": \"undo\"},")
    with pytest.raises(CamcadError, match="not valid JSON"):
        load_script(bad)
    with pytest.raises(CamcadError, match="file not found"):
        load_script(tmp_path / "missing.json")


def test_script_round_trip_replays_bit_for_bit(tmp_path):
    s = EditSession(load_law(DXF / "constant_accel_jumps.dxf"))
    law = s.law
    s.begin_gesture()
    for y in (1.0, 2.0, 3.3):
        s.apply({"op": "move", "x_deg": math.degrees(law.x[4]), "y": y * float(law.a[4]) / 2})
    s.end_gesture()
    s.apply({"op": "insert", "x_deg": 123.4567, "y": 0.25})
    s.apply({"op": "undo"})
    s.apply({"op": "redo"})
    s.apply({"op": "move_phase", "from_deg": math.degrees(law.phases[1].end), "to_deg": 158.0})
    s.apply({"op": "correct", "mode": "min-change"})
    path = tmp_path / "edits.json"
    s.save(path)
    again = EditSession(load_law(DXF / "constant_accel_jumps.dxf"))
    again.replay(load_script(path))
    assert again.law.x.tobytes() == s.law.x.tobytes() and again.law.a.tobytes() == s.law.a.tobytes()
    assert again.law.phases == s.law.phases


def test_normalize_keeps_plain_values():
    op = normalize_operation({"op": "correct", "mode": "segment", "segment": (1, 2)}, 3, "x")
    assert op == {"op": "correct", "mode": "segment", "segment": [1.0, 2.0]}
    assert json.loads(json.dumps(op)) == op


def test_session_module_imports_no_matplotlib():
    code = ("import sys; import camcad.edit.session, camcad.edit.app; "
            "bad = [m for m in sys.modules if m.split('.')[0] == 'matplotlib']; assert not bad, bad")
    result = subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True, cwd=ROOT,
                            env={"PYTHONPATH": str(ROOT), "PATH": ""})
    assert result.returncode == 0, result.stderr


# --- the property: random sequences never corrupt the law nor lose the drawing ----------------------

_op = st.one_of(
    st.builds(lambda x, y: {"op": "move", "x_deg": x, "y": y}, st.floats(0, 360), st.floats(-20, 20)),
    st.builds(lambda x, y, t: {"op": "move", "x_deg": x, "y": y, "to_x_deg": t}, st.floats(0, 360),
              st.floats(-20, 20), st.floats(0, 360)),
    st.builds(lambda x, y: {"op": "move_lobe", "x_deg": x, "y": y}, st.floats(0, 360), st.floats(-20, 20)),
    st.builds(lambda x, y: {"op": "move_extrema", "x_deg": x, "y": y}, st.floats(0, 360), st.floats(-20, 20)),
    st.builds(lambda x, y: {"op": "insert", "x_deg": x, "y": y}, st.floats(0.001, 359.999), st.floats(-20, 20)),
    st.builds(lambda x: {"op": "delete", "x_deg": x}, st.floats(0, 360)),
    st.builds(lambda x: {"op": "jump", "x_deg": x}, st.floats(0, 360)),
    st.builds(lambda x: {"op": "unjump", "x_deg": x}, st.floats(0, 360)),
    st.builds(lambda a, b: {"op": "move_phase", "from_deg": a, "to_deg": b}, st.floats(0, 360), st.floats(0, 360)),
    st.builds(lambda m: {"op": "correct", "mode": m}, st.sampled_from(["min-change", "keypoints", "extrema"])),
    st.just({"op": "undo"}), st.just({"op": "redo"}), st.just({"op": "detect_phases"}),
)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(_op, min_size=1, max_size=12))
@example(ops=[{"op": "move", "x_deg": 2.0, "y": 1.0, "to_x_deg": 3.0}])   # a vertex moved onto a jump's angle
def test_random_operation_sequences_never_corrupt_the_law(tmp_path, ops):
    source = SAMPLES / "dxf" / "drawing_with_axes_grid_text.dxf"
    s = _SESSION.setdefault("s", None) or EditSession.from_file(source)
    s = EditSession(s.loaded, input_path=source)
    for op in ops:
        before = s.law
        try:
            s.apply(op)
        except CamcadError:
            assert s.law is before     # a refused operation changes nothing
        assert not law_problems(s.law), (op, law_problems(s.law))
    out = tmp_path / "random.dxf"
    s.save(out)
    doc_in, doc_out = ezdxf.readfile(source), ezdxf.readfile(out)
    handle = s.loaded.curve.handle
    others_in = Counter((e.dxftype(), e.dxf.layer) for e in doc_in.modelspace() if e.dxf.handle != handle)
    others_out = Counter((e.dxftype(), e.dxf.layer) for e in doc_out.modelspace()
                         if e.dxf.layer != "CAMCAD_ORIGINAL" and e.dxf.handle != handle)
    law_layer = s.loaded.curve.layer
    extra = others_out - others_in
    assert set(extra) <= {("LWPOLYLINE", law_layer)}   # at most the law's new polyline
    assert not (others_in - others_out)                # every other entity kept
    if "CAMCAD_ORIGINAL" in doc_out.blocks:      # a copy with a changed law keeps the original in this block
        assert len(list(doc_out.blocks.get("CAMCAD_ORIGINAL"))) >= 1
    else:                                       # a law saved unchanged: nothing to keep
        assert not [e for e in doc_out.modelspace() if e.dxf.layer == "CAMCAD_ORIGINAL"]
    again = load_law(out)   # the same function (a zero-height jump made by a drag is read as one vertex)
    # RMS over the cycle, not the largest difference: a vertex moved onto the angle of a jump is written
    # through the drawing's x mapping and may land an ulp beside its partner, which moves the jump by
    # ~1e-15 rad and makes the pointwise difference there the jump's height (found by hypothesis: move
    # 2 -> 3 deg next to a vertex at 3 deg). An RMS of 1e-9 x peak bounds a misplaced jump of that
    # height to ~1e-15 rad of the cycle.
    _, rms_change = difference_norms(again.law, s.law)
    assert rms_change <= 1e-9 * max(np.max(np.abs(s.law.a)), 1e-300)


_SESSION: dict = {}
