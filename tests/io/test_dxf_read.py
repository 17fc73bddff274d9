"""Reading laws from drawings and tables: entity kinds, curve choice, real drawings from other programs."""

import importlib.util
import re
import shutil
import subprocess
import sys

import ezdxf
import numpy as np
import pytest
from conftest import REAL_DXF, SAMPLES, SHARED_DXF, file_digest

from camcad.errors import CamcadError
from camcad.law.source import load_law
from camcad.law.standard import compose

CYCLE = [("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)]


def _write(tmp_path, build, name="law.dxf", version="R2000"):
    doc = ezdxf.new(version)
    build(doc.modelspace(), doc)
    path = tmp_path / name
    doc.saveas(path)
    return path


def _sampled(step=2.0):
    law = compose(CYCLE, 25.0)
    theta = np.radians(np.arange(0, 360 + step / 2, step))
    return np.degrees(theta), law.kinematics(theta).a


@pytest.mark.reference("second method", "ezdxf's own entity kinds and vertex counts of each sample drawing")
@pytest.mark.parametrize("name,kind", [
    ("dxf/balanced_drdr_cycloidal.dxf", "LWPOLYLINE"),
    ("dxf/r12_polyline_harmonic.dxf", "POLYLINE"),
    ("dxf/line_chain_trapezoid.dxf", "LINE chain"),
    ("dxf/constant_accel_jumps.dxf", "LWPOLYLINE"),
    ("dxf/drawing_with_axes_grid_text.dxf", "LWPOLYLINE"),
])
def test_samples_read_as_the_entity_they_are(name, kind):
    loaded = load_law(SAMPLES / name)
    assert loaded.curve.kind == kind
    # vertex count straight from ezdxf: a polyline's own vertices, or one more than the LINEs of a chain
    msp = ezdxf.readfile(SAMPLES / name).modelspace()
    if kind == "LWPOLYLINE":
        expected = len(msp.query("LWPOLYLINE[layer=='ACCEL']")[0])
    elif kind == "POLYLINE":
        expected = len(msp.query("POLYLINE")[0].vertices)
    else:
        expected = len(msp.query("LINE")) + 1
    assert len(loaded.law.x) == expected
    assert loaded.law.x[0] == 0 and loaded.law.x[-1] == pytest.approx(2 * np.pi)


@pytest.mark.reference("closed form", "the cycloidal law drawn at 1/2 unit per degree and 1/50 scale: lift exactly 25 "
                                      "mm, ordinates within 1 %")
def test_lwpolyline_x_extent_maps_to_the_cycle_and_lift_scales(tmp_path):
    t, a = _sampled()
    # drawn at x 100..280 (half a unit per degree) and y at 1/50 scale
    path = _write(tmp_path, lambda msp, doc: msp.add_lwpolyline(list(zip(100 + t / 2, a / 50))))
    loaded = load_law(path, lift=25.0)
    reference = compose(CYCLE, 25.0)
    theta = loaded.law.x
    assert np.array_equal(np.round(np.degrees(theta), 9), np.round(t, 9))
    # the drawn law integrates to a lift of exactly 25 mm, and its ordinates track the closed form
    s_top = loaded.law.kinematics(np.array([np.pi])).s[0]
    assert s_top == pytest.approx(25.0, rel=1e-12)
    assert np.max(np.abs(loaded.law.a - reference.kinematics(theta).a)) < 0.01 * np.abs(loaded.law.a).max()


@pytest.mark.reference("second method", "ezdxf's own flattening of the spline (20,000 points) within the stated "
                                        "tolerance")
def test_spline_is_flattened_within_its_tolerance(tmp_path):
    t, a = _sampled(10.0)
    path = _write(tmp_path, lambda msp, doc: msp.add_open_spline(list(zip(t, a, 0 * t)), degree=3))
    loaded = load_law(path, flatten_tol=1e-4)
    doc = ezdxf.readfile(path)
    spline = doc.modelspace().query("SPLINE")[0].construction_tool()
    dense = np.array([[p.x, p.y] for p in spline.approximate(20000)])
    theta_deg = np.degrees(loaded.law.x)
    # every point of the exact spline is within the flattening tolerance of the polyline read
    # (vertical distance is an upper bound of the true distance for a function of x)
    chord_y = np.interp(dense[:, 0], theta_deg, loaded.law.a)
    slope = np.gradient(dense[:, 1], dense[:, 0])
    assert np.max(np.abs(chord_y - dense[:, 1]) / np.sqrt(1 + slope**2)) <= 1.01e-4


@pytest.mark.reference("closed form", "a bulge-1 arc of radius 10: flattened points on the circle, sagittas within "
                                      "1e-3")
def test_bulge_polyline_is_flattened_exactly(tmp_path):
    # one arc of radius 10 (bulge 1 = half circle) between two straight parts: the flattening's
    # points lie on the circle to round-off and its chords within the stated tolerance
    def build(msp, doc):
        msp.add_lwpolyline([(0, 0, 0), (10, 0, 1), (30, 0, 0), (40, 0, 0)], format="xyb")
    loaded = load_law(_write(tmp_path, build), flatten_tol=1e-3, phases="0:360:rise")
    points = loaded.curve.points
    on_arc = (points[:, 0] > 10) & (points[:, 0] < 30)
    radius = np.hypot(points[on_arc, 0] - 20, points[on_arc, 1])
    assert np.max(np.abs(radius - 10)) < 1e-12
    mids = (points[:-1] + points[1:]) / 2
    mid_arc = (mids[:, 0] > 10) & (mids[:, 0] < 30)
    sagitta = 10 - np.hypot(mids[mid_arc, 0] - 20, mids[mid_arc, 1])
    assert sagitta.max() <= 1e-3 + 1e-12


@pytest.mark.reference("property", "a law drawn right to left or with duplicates is the same law")
def test_right_to_left_and_duplicates_give_the_same_law(tmp_path):
    forward = load_law(SAMPLES / "dxf" / "balanced_drdr_cycloidal.dxf")
    t, a = _sampled()
    pts = list(zip(t, a))
    pts = pts[:50] + [pts[50]] * 4 + pts[50:]
    path = _write(tmp_path, lambda msp, doc: msp.add_lwpolyline(pts[::-1]))
    backward = load_law(path)
    assert np.array_equal(forward.law.x, backward.law.x)
    assert np.allclose(forward.law.a, backward.law.a, rtol=0, atol=1e-12)
    assert any("right to left" in n for n in backward.notes)


@pytest.mark.reference("closed form", "the dropped middle points of a vertical run map back at their fractions 0.25 "
                                      "and 0.75")
def test_vertical_runs_keep_first_and_last(tmp_path):
    pts = [(0, 0), (60, 0), (60, 1), (60, 3), (60, 4), (120, 4), (120, -4), (180, -4), (180, 0), (200, 0),
           (200, -4), (260, -4), (260, 4), (320, 4), (320, 0), (360, 0)]
    path = _write(tmp_path, lambda msp, doc: msp.add_lwpolyline(pts))
    loaded = load_law(path)
    assert len(loaded.law.x) == len(pts) - 2
    # the dropped middle points map back onto the vertical segment by their fraction
    assert loaded.vertex_map.weight[2] == pytest.approx(0.25)
    assert loaded.vertex_map.weight[3] == pytest.approx(0.75)


@pytest.mark.reference("property", "the widest chain is the law; the notes name it, the candidates and the zero axis")
def test_largest_x_range_is_chosen_and_reported(tmp_path):
    t, a = _sampled()

    def build(msp, doc):
        msp.add_lwpolyline(list(zip(t, a)), dxfattribs={"layer": "LAW"})
        msp.add_lwpolyline(list(zip(t[40:120] / 2, a[40:120])), dxfattribs={"layer": "SKETCH"})
        msp.add_line((0, 0), (400, 0), dxfattribs={"layer": "AXES"})  # wider, but straight
    loaded = load_law(_write(tmp_path, build))
    assert loaded.curve.layer == "LAW"
    assert any(n.startswith("law: LWPOLYLINE") and "the widest chain" in n and "of 2 candidates" in n
               for n in loaded.notes)
    assert any(n.startswith("zero axis: y = 0, LINE") and "(x 0..400)" in n for n in loaded.notes)


@pytest.mark.reference("property", "two curves of one width are ambiguous; --layer and --handle pick the same law")
def test_layer_and_handle_pick_the_curve(tmp_path):
    t, a = _sampled()

    def build(msp, doc):
        msp.add_lwpolyline(list(zip(t, a)), dxfattribs={"layer": "A"})
        msp.add_lwpolyline(list(zip(t, -a)), dxfattribs={"layer": "B"})
    path = _write(tmp_path, build)
    with pytest.raises(CamcadError, match="same x-range"):
        load_law(path)
    by_layer = load_law(path, layer="B")
    assert by_layer.curve.layer == "B"
    by_handle = load_law(path, handle=by_layer.curve.handle)
    assert np.array_equal(by_handle.law.a, by_layer.law.a)


@pytest.mark.reference("closed form", "the block inserted at y = 5: the dwells give that zero, the peak unchanged")
def test_insert_of_a_block_is_exploded(tmp_path):
    t, a = _sampled()

    def build(msp, doc):
        block = doc.blocks.new("LAWBLOCK")
        block.add_lwpolyline(list(zip(t, a)))
        msp.add_blockref("LAWBLOCK", (10, 5))
    loaded = load_law(_write(tmp_path, build))
    # the block's insertion point moves the law to y = 5: its dwells say that is the zero
    assert loaded.y0 == pytest.approx(5.0) and any("zero axis: y = 5" in n for n in loaded.notes)
    assert loaded.law.a.max() == pytest.approx(a.max())
    assert not loaded.curve.editable and loaded.curve.handles[0] == loaded.curve.handle  # the INSERT's handle


@pytest.mark.reference("property", "a binary DXF gives the law of its ASCII twin")
def test_binary_dxf_is_read(tmp_path):
    t, a = _sampled()
    doc = ezdxf.new("R2000")
    doc.modelspace().add_lwpolyline(list(zip(t, a)))
    path = tmp_path / "binary.dxf"
    doc.saveas(path, fmt="bin")
    loaded = load_law(path)
    assert len(loaded.law.x) == len(t)


@pytest.mark.reference("property", "comma and semicolon tables of one law read alike")
def test_table_dialects_read_alike():
    comma = load_law(SAMPLES / "law_table.csv")
    semicolon = load_law(SAMPLES / "law_table_semicolon.txt")
    assert np.allclose(comma.law.a, semicolon.law.a, atol=1e-9)
    assert any("closed periodically" in n for n in semicolon.notes)


@pytest.mark.reference("property", "unsorted rows sorted, and the notes say so")
def test_unsorted_table_rows_are_sorted_and_reported(tmp_path):
    rows = ["0,0", "180,0", "90,1", "135,-1", "45,1", "270,-1", "225,-1", "315,1", "360,0"]
    path = tmp_path / "t.csv"
    path.write_text("\n".join(rows))
    loaded = load_law(path)
    assert np.all(np.diff(loaded.law.x) >= 0)
    assert any("sorted" in n for n in loaded.notes)


# --- real drawings written by other programs (tests/fixtures/dxf-real) --------------------------------

@pytest.mark.reference("property", "every real drawing of 33 (tests/fixtures/dxf-real): a law or one clear line, the "
                                   "input unchanged")
def test_every_real_drawing_gets_a_result_or_one_clear_line(real_dxf, cli, tmp_path):
    paths = sorted(real_dxf.glob("*.[dD][xX][fF]"))
    assert len(paths) == 33, len(paths)       # 23 copied, 10 stand-ins (the folder's README)
    for path in paths:
        before = file_digest(path)
        result = cli("check", path, "--json")
        assert result.code in (0, 1, 2), path.name
        if result.code == 2:
            lines = result.err.strip().splitlines()
            assert len(lines) == 1 and lines[0].startswith("camcad: error: "), (path.name, result.err)
            assert "internal error" not in lines[0], (path.name, lines[0])
        else:
            payload = result.json()
            assert set(payload["areas"]) == {"rise_accel", "rise_decel", "return_accel", "return_decel"}
        assert file_digest(path) == before, path.name


@pytest.mark.reference("property", "drawings that hold no law say why (closed, 3D, goes back in x, straight)")
@pytest.mark.parametrize("name,expected", [
    ("ezdxf__Minimal_DXF_AC1009.dxf", "no curve found"),
    ("gdal__closed_polyline_with_bulge.dxf", "it is closed"),
    ("ezdxf__no_layouts.dxf", "it is closed"),
    ("ezdxf__cc_dxflib.dxf", "3D polyline"),
    ("camcad__crlf_inch_polyline.dxf", "goes back in x at vertex 3"),
    ("camcad__crlf_inch_polygon.dxf", "it is closed"),
    ("camcad__r13_lines.dxf", "is a straight line"),
    ("camcad__l_chain.dxf", "goes back in x in ARC"),
])
def test_real_drawings_without_a_law_say_why(real_dxf, cli, name, expected):
    result = cli("check", real_dxf / name)
    assert result.code == 2
    assert expected in result.err


def _stand_ins() -> dict[str, str]:
    """stand-in -> the GPL-licensed original it replaces (tests/fixtures/dxf-real/make_own.py)."""
    spec = importlib.util.spec_from_file_location("make_own", REAL_DXF / "make_own.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return {name: original for name, (_, original, _) in module.STAND_INS.items()}


STAND_INS = _stand_ins()


def _answer(result) -> tuple:
    """What camcad's check said, without the file's own handles and numbers: for a refusal, why the largest
    curve cannot be a law; for a law, its kind of entity and what the drawing's units note says."""
    if result.code == 2:
        why = re.search(r": it (.*?)(;|$)", result.err).group(1)
        return 2, re.sub(r"\s+", " ", re.sub(r"\(.*?\)|\b[0-9A-F]+\b", "", why)).strip()
    payload = result.json()
    kind = re.sub(r"\(.*?\)|\b[0-9A-F]+\b", "", payload["source"].split(", ")[1].split(" on layer")[0]).strip()
    units = [n.split(";")[0] for n in payload["notes"] if n.startswith(("drawing units", "the drawing states"))]
    return result.code, kind, units


@pytest.mark.reference("second method", "the GPL-licensed original of ../shared/dxf-real answered alike (skipped "
                                        "without it)")
@pytest.mark.parametrize("stand_in", sorted(STAND_INS), ids=lambda name: STAND_INS[name])
def test_a_stand_in_is_read_as_its_gpl_original(cli, stand_in):
    # our own drawing in place of a GPL-licensed one that is not copied here (tests/fixtures/dxf-real/README.md):
    # where the original is beside the project, camcad answers both alike
    original = SHARED_DXF / STAND_INS[stand_in]
    if not original.is_file():
        pytest.skip(f"{SHARED_DXF} is not beside the project: the GPL-licensed original {original.name} is not "
                    "copied into the repository; its stand-in is read in every other test")
    assert _answer(cli("check", REAL_DXF / stand_in, "--json")) == _answer(cli("check", original, "--json"))


@pytest.mark.reference("property", "ezdxf's recover reads the damaged drawing; the notes report the repair")
def test_damaged_drawing_is_recovered_and_the_repair_reported(real_dxf):
    # two chains of the same width in the repaired drawing: ambiguous without --handle
    with pytest.raises(CamcadError, match="same x-range"):
        load_law(real_dxf / "ezdxf__recover01.dxf")
    loaded = load_law(real_dxf / "ezdxf__recover01.dxf", handle="42", cycle_deg=360)
    assert any("recover" in n for n in loaded.notes)


@pytest.mark.reference("property", "GDAL's header-less R2000 excerpt keeps its closed flag (129)")
def test_headerless_r2000_excerpt_keeps_its_closed_flag(real_dxf):
    # without the $ACADVER injection ezdxf would read it as R12 and drop the closed flag (129)
    from camcad.io.dxf_read import collect_pieces, open_drawing

    pieces = collect_pieces(open_drawing(real_dxf / "gdal__closed_polyline_with_bulge.dxf")).pieces
    assert pieces[0].closed


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_no_traceback_in_a_real_process(tmp_path):
    # the console script itself, not the in-process runner: stderr holds one line and no traceback
    bad = tmp_path / "bad.dxf"
    bad.write_bytes(b"0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n90\n3\n10\n1e999x\n")
    exe = shutil.which("camcad") or sys.executable
    args = [exe, "check", str(bad)] if exe.endswith("camcad") else [exe, "-m", "camcad", "check", str(bad)]
    done = subprocess.run(args, capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
