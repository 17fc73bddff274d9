"""The reading rules of docs/reading.md, one test per rule: zero axis and origin, joining pieces of any kind,
axes and grids left out, warnings, cycle coverage, units, the options that override, and the curve handed
to the writers.

References are independent of camcad: the law's own vertices (θ in deg, a) that each test draws, its areas
by the trapezoid rule on them, and closed forms for arcs and ellipse arcs (a semicircle's area πr²/2, a
half-ellipse's πab/2, each with its centroid at the lobe's middle).
"""

from __future__ import annotations

import itertools
import math

import ezdxf
import numpy as np
import pytest
from conftest import cpu_seconds

from camcad.errors import CamcadError
from camcad.law.source import load_law

# a balanced dwell–rise–dwell–return law drawn as a polyline: (θ deg, a)
LAW = [(0, 0), (60, 0), (90, 12), (120, 0), (150, -12), (180, 0), (210, 0), (240, -12), (270, 0), (300, 12),
       (330, 0), (360, 0)]
PEAK = 12.0


def _save(tmp_path, build, name="law.dxf", version="R2000", units=None):
    doc = ezdxf.new(version)
    if units is not None:
        doc.units = units
    build(doc.modelspace(), doc)
    path = tmp_path / name
    doc.saveas(path)
    return path


def _placed(x0=0.0, y0=0.0, sx=1.0, sy=1.0, points=LAW):
    return [(x0 + t * sx, y0 + a * sy) for t, a in points]


def _assert_law(loaded, points=LAW, sy=1.0):
    theta = np.array([t for t, _ in points], dtype=float)
    a = np.array([v for _, v in points], dtype=float) * sy
    assert np.allclose(np.degrees(loaded.law.x), theta, rtol=0, atol=1e-9 * 360)
    assert np.allclose(loaded.law.a, a, rtol=0, atol=1e-9 * PEAK * sy)


def _trapezoid_areas(points=LAW):
    """Signed areas (θ in rad) of the law's lobes, from its vertices: rise accel, rise decel, return accel,
    return decel (the lobes of LAW lie between 60–120, 120–180, 210–270, 270–330 deg)."""
    t = np.radians([p[0] for p in points])
    a = np.array([p[1] for p in points], dtype=float)
    out = []
    for lo, hi in ((60, 120), (120, 180), (210, 270), (270, 330)):
        inside = (np.degrees(t) >= lo - 1e-9) & (np.degrees(t) <= hi + 1e-9)
        out.append(float(np.trapezoid(a[inside], t[inside])))
    return out


# ---------------------------------------------------------------------------------------------- zero axis

@pytest.mark.reference("closed form", "Inkscape's page coordinates: the axis LINE at y = 104.3 is the zero, agreeing "
                                      "with the dwell level")
def test_axis_line_at_page_coordinates_is_the_zero_and_does_not_close_the_chain(tmp_path):
    # Inkscape's case: the graph at y = 104.3 (page coordinates), the axis a LINE on the law's layer whose
    # ends touch the law's ends (the chain law + axis is closed; the law alone is read)
    x0, y0 = 1000.0, 104.3

    def build(msp, doc):
        msp.add_lwpolyline(_placed(x0, y0, sx=0.5))
        msp.add_line((x0, y0), (x0 + 180, y0))
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded)
    assert loaded.y0 == y0 and loaded.x_min == x0
    zero = next(n for n in loaded.notes if n.startswith("zero axis"))
    assert "y = 104.3, LINE" in zero and "agreeing with the dwell level" in zero


@pytest.mark.reference("property", "a LINE chain touching its axis at both ends is the law, the axis left out and said")
def test_a_line_chain_law_touching_its_axis_at_both_ends_is_read(tmp_path):
    x0, y0 = -50.0, 20.0

    def build(msp, doc):
        pts = _placed(x0, y0)
        for p, q in itertools.pairwise(pts):
            msp.add_line(p, q)
        msp.add_line((x0, y0), (x0 + 360, y0))
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded)
    assert loaded.curve.kind == "LINE chain" and len(loaded.curve.handles) == len(LAW) - 1
    assert any("left out as axis or grid lines" in n for n in loaded.notes) or \
        any("zero axis: y = 20, LINE" in n for n in loaded.notes)


@pytest.mark.reference("closed form", "the law drawn with its dwells at y = 250: that is the zero")
def test_dwell_level_is_the_zero_without_an_axis(tmp_path):
    loaded = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(_placed(30.0, 250.0))))
    _assert_law(loaded)
    assert loaded.y0 == 250.0
    assert any("the dwell level (the flat stretches at both ends" in n for n in loaded.notes)


@pytest.mark.reference("property", "no dwell, no axis: y = 0 of the drawing, the note names --y0")
def test_nothing_evident_keeps_y_zero_and_says_how_to_override(tmp_path):
    # no dwell, no axis: the drawing's own y = 0 is taken, and the note names --y0
    pts = [(0, 5), (90, 15), (180, -5), (270, 5), (360, 5.5)]
    loaded = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(pts)), phases="0:360:rise")
    assert loaded.y0 == 0.0
    assert any(n.startswith("zero axis: none found") and "--y0" in n for n in loaded.notes)


@pytest.mark.reference("property", "grid, frame and axes left out; the axis agreeing with the dwell level is the zero")
def test_grid_frame_and_axes_are_left_out_and_the_axis_agreeing_with_the_dwell_wins(tmp_path):
    x0, y0 = 100.0, 300.0

    def build(msp, doc):
        msp.add_lwpolyline(_placed(x0, y0), dxfattribs={"layer": "LAW"})
        for level in (-15, -10, -5, 5, 10, 15):                     # grid wider than the law, at other levels
            msp.add_line((x0 - 10, y0 + level), (x0 + 370, y0 + level), dxfattribs={"layer": "GRID"})
        for t in range(0, 361, 30):                                  # vertical grid lines
            msp.add_line((x0 + t, y0 - 15), (x0 + t, y0 + 15), dxfattribs={"layer": "GRID"})
        msp.add_line((x0 - 20, y0), (x0 + 380, y0), dxfattribs={"layer": "AXES"})
        msp.add_line((x0, y0), (x0, y0 + 40), dxfattribs={"layer": "AXES"})       # y axis from the origin up
        frame = [(x0 - 30, y0 - 30), (x0 + 390, y0 - 30), (x0 + 390, y0 + 50), (x0 - 30, y0 + 50), (x0 - 30, y0 - 30)]
        for p, q in itertools.pairwise(frame):                      # a frame of LINEs
            msp.add_line(p, q, dxfattribs={"layer": "FRAME"})
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded)
    assert loaded.curve.layer == "LAW" and loaded.y0 == y0


@pytest.mark.reference("property", "of several spanning horizontal lines, the one nearest the curve's mean height, "
                                   "said")
def test_several_horizontal_lines_without_a_dwell_pick_the_one_nearest_the_mean(tmp_path):
    # a law with no flat stretch (rise–return, no dwells); grid lines at y0 ± 10 and y0 span it too
    y0 = 40.0
    pts = [(0, 0), (45, 10), (90, 0), (135, -10), (180, 0), (225, -10), (270, 0), (315, 10), (360, 0)]

    def build(msp, doc):
        msp.add_lwpolyline(_placed(0, y0, points=pts))
        for level in (-10, 0, 10):
            msp.add_line((0, y0 + level), (360, y0 + level), dxfattribs={"layer": "GRID"})
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded, pts)
    assert any("of 3 horizontal lines spanning the law, the one nearest the curve's mean height" in n
               for n in loaded.notes)


@pytest.mark.reference("property", "plateaus at +A at both ends are not dwells: y = 0 stays the zero")
def test_constant_acceleration_plateaus_at_the_ends_are_not_dwells(tmp_path):
    # flat at +A at both ends: the curve never rises above it, so it is no zero; y = 0 of the drawing stays
    pts = [(0, 8), (90, 8), (90, -8), (180, -8), (180, -8), (270, -8), (270, 8), (360, 8)]
    loaded = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(pts)), phases="0:180:rise,180:360:return")
    assert loaded.y0 == 0.0


@pytest.mark.reference("closed form", "the dwell drawn 0.3 above the axis over x 180..210: the warning says so")
def test_a_dwell_drawn_off_the_axis_is_warned_of(tmp_path):
    y0 = 100.0
    pts = _placed(0, y0)
    pts[5] = (pts[5][0], y0 + 0.3)   # the far dwell 180..210 drawn 0.3 above the axis
    pts[6] = (pts[6][0], y0 + 0.3)

    def build(msp, doc):
        msp.add_lwpolyline(pts)
        msp.add_line((-10, y0), (370, y0))
    loaded = load_law(_save(tmp_path, build))
    warning = [n for n in loaded.notes if n.startswith("warning: 1 dwell is not at zero")]
    assert warning and "0.3 above the zero axis" in warning[0] and "x 180..210" in warning[0]


# ------------------------------------------------------------------------------------------ the options

@pytest.mark.reference("closed form", "--y0 shifted by 2 adds 2 to every ordinate; --origin and --x0/--y0 agree; "
                                      "conflicts refused")
def test_y0_x0_and_origin_override_what_is_found(tmp_path, cli):
    x0, y0 = 1000.0, 104.3
    path = _save(tmp_path, lambda msp, doc: msp.add_lwpolyline(_placed(x0, y0)))
    shifted = load_law(path, y0=y0 - 2.0, cycle_deg=360)   # a zero 2 below the dwells: a law with no dwell
    assert np.allclose(shifted.law.a, np.array([a for _, a in LAW]) + 2.0, atol=1e-9)
    assert any(n == f"zero axis: y = {y0 - 2.0:.9g} as given" for n in shifted.notes)
    # x in degrees from an origin: the curve's start unless --x0 says otherwise
    in_degrees = load_law(path, x_deg=True)
    _assert_law(in_degrees)
    with pytest.raises(CamcadError, match="starts at x 1000, right of the origin x0 = 990"):
        load_law(path, x_deg=True, x0=990.0)
    by_origin = cli("check", path, "--origin", f"{x0},{y0}", "--x-deg", "--json")
    by_options = cli("check", path, "--x0", str(x0), "--y0", str(y0), "--x-deg", "--json")
    assert by_origin.code in (0, 1) and by_origin.json()["areas"] == by_options.json()["areas"]
    both = cli("check", path, "--origin", "1,2", "--y0", "3")
    assert both.code == 2 and "--origin and --x0/--y0 both given" in both.err
    bad = cli("check", path, "--origin", "12")
    assert bad.code == 2 and len(bad.err.strip().splitlines()) == 1 and "--origin X,Y" in bad.err


@pytest.mark.reference("closed form", "the scene's y0 = 68, x0 = 500: ordinates shifted by 2")
def test_scene_keys_y0_and_x0(tmp_path):
    from camcad.scene.laws import build_law
    from camcad.scene.sections.law import parse_law

    path = _save(tmp_path, lambda msp, doc: msp.add_lwpolyline(_placed(500.0, 70.0)))
    spec = parse_law({"file": path.name, "y0": 68.0, "x0": 500.0, "cycle": 360.0}, "scene.toml [law]", tmp_path)
    built = build_law(spec)
    assert built.loaded.y0 == 68.0 and built.loaded.x_min == 500.0
    assert np.allclose(built.law.a, np.array([a for _, a in LAW]) + 2.0, atol=1e-9)


# ------------------------------------------------------------------------------------- joining pieces

def _mixed_pieces(msp, x0, y0, layers=("0",) * 7):
    """The law with lobes of four kinds, in shuffled order and mixed directions:
    dwell LINE 0–60 (reversed), rise-accelerating half ELLIPSE 60–120 (height 12), rise-decelerating
    LWPOLYLINE triangle 120–180 (to −12, drawn right to left), far dwell POLYLINE 180–210, return-
    accelerating semicircle ARC 210–270 (radius 30, below), return-decelerating degree-1 SPLINE triangle
    270–330 (to 30), near dwell LINE 330–360."""
    def p(t, a):
        return (x0 + t, y0 + a)

    msp.add_lwpolyline([p(180, 0), p(150, -12), p(120, 0)], dxfattribs={"layer": layers[2]})
    msp.add_open_spline([p(270, 0) + (0,), p(300, 30) + (0,), p(330, 0) + (0,)], degree=1,
                        dxfattribs={"layer": layers[5]})
    msp.add_line(p(360, 0), p(330, 0), dxfattribs={"layer": layers[6]})
    msp.add_arc((x0 + 240, y0), 30, 180, 360, dxfattribs={"layer": layers[4]})
    msp.add_ellipse((x0 + 90, y0), major_axis=(30, 0), ratio=12 / 30, start_param=0, end_param=math.pi,
                    dxfattribs={"layer": layers[1]})
    msp.add_polyline2d([p(180, 0), p(210, 0)], dxfattribs={"layer": layers[3]})
    msp.add_line(p(60, 0), p(0, 0), dxfattribs={"layer": layers[0]})


def _mixed_reference() -> dict:
    k = math.pi / 180  # 1 drawing unit of x = 1 deg
    areas = {"rise_accel": math.pi * 30 * 12 / 2, "rise_decel": -0.5 * 60 * 12,
             "return_accel": -math.pi * 30 ** 2 / 2, "return_decel": 0.5 * 60 * 30}
    centres = {"rise_accel": 90, "rise_decel": 150, "return_accel": 240, "return_decel": 300}
    m0 = sum(areas.values())
    m1 = sum(areas[n] * centres[n] for n in areas)
    return {"areas": {n: k * v for n, v in areas.items()}, "v_rise": k * (areas["rise_accel"] + areas["rise_decel"]),
            "v_return": k * m0, "s_end": k * 2 * math.pi * m0 - k * k * m1}


def _assert_mixed(payload):
    ref = _mixed_reference()
    tol = 1e-4 * 30
    for name, value in ref["areas"].items():
        assert payload["areas"][name] == pytest.approx(value, abs=tol), name
    assert payload["velocity_closure"]["rise"] == pytest.approx(ref["v_rise"], abs=tol)
    assert payload["velocity_closure"]["return"] == pytest.approx(ref["v_return"], abs=tol)
    assert payload["displacement_closure"] == pytest.approx(ref["s_end"], abs=tol * 2 * math.pi)


@pytest.mark.reference("property", "LINE, ARC, ELLIPSE, SPLINE and polylines in any order and direction join into one "
                                   "law")
def test_pieces_of_every_kind_in_any_order_and_direction_form_one_law(tmp_path):
    from camcad.balance.checking import check

    path = _save(tmp_path, lambda msp, doc: _mixed_pieces(msp, 40.0, 90.0))
    loaded = load_law(path, flatten_tol=1e-7)
    assert loaded.curve.kind == "chain" and len(loaded.curve.pieces) == 7
    assert {p.kind for p in loaded.curve.pieces} == {"LINE", "ELLIPSE", "LWPOLYLINE", "POLYLINE", "ARC", "SPLINE"}
    assert loaded.y0 == 90.0 and not loaded.curve.editable
    _assert_mixed(check(loaded.law).to_dict())


@pytest.mark.reference("property", "pieces on several layers are joined when no layer holds the law, said")
def test_pieces_on_several_layers_are_joined_when_no_layer_holds_the_law(tmp_path, cli):
    layers = ("DWELL", "LOBES", "LOBES", "DWELL", "LOBES", "LOBES", "DWELL")
    path = _save(tmp_path, lambda msp, doc: _mixed_pieces(msp, 0.0, 0.0, layers))
    result = cli("check", path, "--json")
    assert result.code in (0, 1), result.err
    payload = result.json()
    assert any("joined across layers" in n for n in payload["notes"])
    _assert_mixed(payload)


def _thousands_of_pieces():
    # 20 000 LINE pieces of a law, shuffled and half reversed, with 2 000 drawn twice over
    from camcad.io.dxf_read import Piece, PieceSet

    rng = np.random.default_rng(5)
    t = np.linspace(0, 360, 20_001)
    a = np.where((t > 60) & (t < 180), 10 * np.sin(np.radians(3 * (t - 60))), 0.0)
    a = np.where((t > 210) & (t < 330), -10 * np.sin(np.radians(3 * (t - 210))), a)
    pts = np.column_stack((t, a))
    order = list(rng.permutation(len(pts) - 1)) + list(rng.integers(0, len(pts) - 1, 2000))
    pieces = []
    for k, i in enumerate(order):
        ends = pts[[i + 1, i]] if i % 2 else pts[[i, i + 1]]
        pieces.append(Piece(ends, "LINE", f"{k + 0x30:X}", "0", k, exact=True, breakpoints=ends))
    return pts, PieceSet(tuple(pieces)), rng


@pytest.mark.reference("closed form", "the chain is the law's 20,001 points in order, each piece once")
def test_thousands_of_pieces_join_into_the_drawn_law(tmp_path):
    # the chain is the law's points in order, each piece once; the same through a file with 2 000 LINEs
    from camcad.io.chain import find_law

    pts, pieces, rng = _thousands_of_pieces()
    chain = find_law(pieces, "memory")
    assert len(chain.curve.points) == len(pts) and np.array_equal(chain.curve.points, pts)
    assert any("2000 pieces drawn twice over counted once" in n for n in chain.notes)

    t, a = pts[:, 0], pts[:, 1]
    small = np.column_stack((t[::10], a[::10]))

    def build(msp, doc):
        for i in rng.permutation(len(small) - 1):
            msp.add_line(small[i + 1], small[i]) if i % 2 else msp.add_line(small[i], small[i + 1])
    loaded = load_law(_save(tmp_path, build))
    assert np.allclose(np.degrees(loaded.law.x), small[:, 0], atol=1e-9) and np.allclose(loaded.law.a, small[:, 1])


@pytest.mark.reference("property", "the join is O(n log n): 22,000 pieces in under 10 s of CPU")
@pytest.mark.timing
def test_thousands_of_pieces_join_in_under_10_s_of_cpu():
    # the join is O(n log n): 22 000 pieces in well under 10 s of CPU (a quadratic join took minutes)
    from camcad.io.chain import find_law

    _, pieces, _ = _thousands_of_pieces()
    began = cpu_seconds()
    find_law(pieces, "memory")
    assert cpu_seconds() - began < 10


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_chain_that_goes_back_in_x_is_explained_with_where(tmp_path):
    pts = _placed()
    pts[3] = (pts[2][0] - 5, pts[3][1])   # vertex 3 drawn left of vertex 2

    def build(msp, doc):
        for p, q in itertools.pairwise(pts):
            msp.add_line(p, q)
    with pytest.raises(CamcadError, match=r"goes back in x in LINE \w+ \(x 85 after 90\)"):
        load_law(_save(tmp_path, build))


@pytest.mark.reference("property", "an open border round three sides is no law: the law inside it is read")
def test_a_border_that_turns_round_does_not_hide_the_law(tmp_path):
    # an open polyline round three sides of the sheet, wider than the law: it goes back in x by its whole
    # width, so it is no mis-drawn law and the law inside it is read
    def build(msp, doc):
        msp.add_lwpolyline(_placed(0.0, 50.0))
        msp.add_lwpolyline([(-20, 0), (-20, 100), (380, 100), (380, 0)], dxfattribs={"layer": "BORDER"})
        msp.add_lwpolyline([(-30, -10), (390, -10), (390, 110), (-40, 110)], dxfattribs={"layer": "BORDER"})
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded)


@pytest.mark.reference("property", "a y axis touching the law's start is left out of the chain")
def test_a_y_axis_touching_the_laws_start_is_left_out(tmp_path):
    def build(msp, doc):
        pts = _placed(10.0, 10.0)
        for p, q in itertools.pairwise(pts):
            msp.add_line(p, q)
        msp.add_line((10.0, 10.0), (10.0, 40.0))   # from the origin up past the curve's top
    loaded = load_law(_save(tmp_path, build))
    _assert_law(loaded)
    assert len(loaded.curve.handles) == len(LAW) - 1


# ---------------------------------------------------------------------------- cycle coverage and units

@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_a_rise_alone_is_not_stretched_to_a_cycle(tmp_path, cli):
    rise = [(0, 0), (30, 10), (60, 0), (90, -10), (120, 0)]
    path = _save(tmp_path, lambda msp, doc: msp.add_lwpolyline(rise))
    with pytest.raises(CamcadError, match=r"covers x 0\.\.120 and holds a rise but no return.*"
                                          r"--x-deg --cycle 120; if it is the whole cycle pass --cycle 360"):
        load_law(path)
    result = cli("check", path)
    assert result.code == 2 and len(result.err.strip().splitlines()) == 1 and len(result.err) < 300
    stated = load_law(path, x_deg=True, cycle_deg=120)
    assert np.degrees(stated.law.x[-1]) == pytest.approx(120)
    assert cli("check", path, "--cycle", "360", "--json").code in (0, 1)


@pytest.mark.reference("property", "$INSUNITS is reported, not applied: mm and inch drawings give the same numbers")
def test_units_are_reported_not_applied(tmp_path):
    mm = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(LAW), "mm.dxf", units=4))
    inch = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(LAW), "in.dxf", units=1))
    assert np.array_equal(mm.law.a, inch.law.a)
    assert any("inches ($INSUNITS 1); y is read as in/rad²" in n for n in inch.notes)
    assert (mm.length_unit, inch.length_unit, inch.mm_per_unit) == ("mm", "in", 25.4)
    lifted = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(LAW), "lift.dxf", units=1), lift=10.0)
    assert any("not used: x is mapped to the cycle and y is scaled by --lift" in n for n in lifted.notes)
    r12 = load_law(_save(tmp_path, lambda msp, doc: msp.add_polyline2d(LAW), "r12.dxf", version="R12"))
    assert any("states no units" in n for n in r12.notes)


# ----------------------------------------------------------------------------- the curve for the writers

@pytest.mark.reference("property", "each vertex's reference names its entity and place (LINE end, polyline vertex)")
def test_the_curve_says_how_to_write_back(tmp_path):
    from camcad.io.dxf_read import curve_entities, open_drawing

    def chain(msp, doc):
        pts = _placed()
        for i, (p, q) in enumerate(itertools.pairwise(pts)):
            msp.add_line(*((q, p) if i % 2 else (p, q)))
    loaded = load_law(_save(tmp_path, chain, "chain.dxf"))
    curve = loaded.curve
    assert curve.editable and curve.kind == "LINE chain" and len(curve.vertex_refs) == len(curve.points)
    entities = curve_entities(open_drawing(loaded.path).doc, curve)
    for refs, point in zip(curve.vertex_refs, curve.points):
        for handle, end in refs:   # every referred LINE end sits at its point
            line = entities[curve.handles.index(handle)]
            assert np.allclose(tuple(getattr(line.dxf, end))[:2], point)

    def mixed(msp, doc):
        pts = _placed()
        msp.add_lwpolyline(pts[:6])
        for p, q in itertools.pairwise(pts):
            msp.add_line(p, q)
    loaded = load_law(_save(tmp_path, mixed, "mixed.dxf"))
    assert not loaded.curve.editable and loaded.curve.kind == "chain"
    assert loaded.curve.vertex_refs[3] == ((loaded.curve.handles[0], 3),)
    assert len(loaded.curve.vertex_refs[5]) == 2   # the polyline's last vertex and the first LINE's start

    backwards = load_law(_save(tmp_path, lambda msp, doc: msp.add_lwpolyline(_placed()[::-1]), "back.dxf"))
    assert backwards.curve.editable and np.array_equal(backwards.curve.points, np.array(_placed()[::-1], float))


@pytest.mark.reference("property", "with duplicate handles the drawn LINEs are found again by position, not the BLOCK")
def test_entities_are_found_again_when_handles_are_not_unique(tmp_path):
    # a LINE of the law whose handle is also a BLOCK's (as in tests/fixtures/dxf-real/ezdxf__duplicate_handles.dxf):
    # ezdxf's handle lookup gives the BLOCK, curve_entities gives the LINE (found by model-space position)
    import re

    from camcad.io.dxf_read import curve_entities, open_drawing

    doc = ezdxf.new("R2000")
    lines = [doc.modelspace().add_line(p, q) for p, q in itertools.pairwise(_placed())]
    path = tmp_path / "dup.dxf"
    doc.saveas(path)
    text = path.read_text()
    block = re.search(r"\n  0\nBLOCK\n  5\n([0-9A-F]+)\n", text).group(1)
    text = text.replace(f"\n  0\nLINE\n  5\n{lines[1].dxf.handle}\n", f"\n  0\nLINE\n  5\n{block}\n", 1)
    path.write_text(text)
    loaded = load_law(path)
    assert loaded.curve.handles[1] == block
    fresh = open_drawing(path).doc
    assert fresh.entitydb.get(block).dxftype() == "BLOCK"
    entities = curve_entities(fresh, loaded.curve)
    assert [e.dxftype() for e in entities] == ["LINE"] * len(lines)
    for refs, point in zip(loaded.curve.vertex_refs, loaded.curve.points):
        for handle, end in refs:
            assert np.allclose(tuple(getattr(entities[loaded.curve.handles.index(handle)].dxf, end))[:2], point)


@pytest.mark.reference("property", "the corrected law written where it was drawn: the zero axis and the dwells "
                                   "unmoved, it checks balanced")
def test_fix_writes_the_corrected_law_back_where_it_was_drawn(tmp_path, cli):
    # an unbalanced law on a sheet (axis at y = 104.3): the corrected copy keeps the zero axis and the dwells
    x0, y0 = 1000.0, 104.3
    pts = _placed(x0, y0)
    pts[2] = (pts[2][0], y0 + 13.0)   # the accelerating lobe of the rise 8 % too high

    def build(msp, doc):
        msp.add_lwpolyline(pts, dxfattribs={"layer": "LAW"})
        msp.add_line((x0 - 10, y0), (x0 + 370, y0), dxfattribs={"layer": "AXES"})
    path = _save(tmp_path, build)
    out = tmp_path / "fixed.dxf"
    result = cli("fix", path, "-o", out, "--no-plots", "--json")
    assert result.code == 0, result.err
    again = load_law(out)
    assert again.y0 == y0 and cli("check", out, "--json").code == 0
    fixed = ezdxf.readfile(out).modelspace().query("LWPOLYLINE[layer=='LAW']")[0]
    vertices = np.array([p[:2] for p in fixed.get_points()])
    assert np.array_equal(vertices[[0, 1, 5, 6, 10, 11], 1], np.full(6, y0))   # the dwells did not move


@pytest.mark.reference("closed form", "a fit-point spline passes through its fit points (1e-4)")
def test_fit_point_spline_passes_through_its_fit_points(tmp_path):
    fit = [(t, a) for t, a in LAW if t not in (180, 330)]   # no two fit points at one place

    def build(msp, doc):
        msp.add_spline([(t, a, 0) for t, a in fit])
    loaded = load_law(_save(tmp_path, build), flatten_tol=1e-6, cycle_deg=360)
    theta = np.radians([t for t, _ in fit])
    values = np.interp(theta, loaded.law.x, loaded.law.a)
    assert np.allclose(values, [a for _, a in fit], atol=1e-4)


@pytest.mark.reference("property", "a piece 0.5 units short: the gap named with its piece and distance")
def test_a_piece_stopping_just_short_of_the_chain_is_warned_of(tmp_path):
    # The law in three pieces; the last is drawn 0.5 units (0.14 % of the width) short of the middle one: the
    # widest chain is then only part of the law, and the reader says which piece and how far. A tick mark at
    # the chain's start that points inward (it would not carry the chain further) is not warned of.
    def build(msp, doc, gap):
        msp.add_lwpolyline(LAW[:6], dxfattribs={"layer": "LAW"})                   # 0..180
        msp.add_line((180, 0), (210, 0), dxfattribs={"layer": "LAW"})               # the far dwell
        tail = [(t + gap, a) for t, a in LAW[6:]]
        msp.add_lwpolyline(tail, dxfattribs={"layer": "LAW"})                       # 210 + gap .. 360 + gap
        msp.add_line((0.4, 0.3), (3, 0.3), dxfattribs={"layer": "LAW"})            # a tick mark near the start

    # the widest part (0..210) holds a rise but no return: refused, and the reason given is the gap
    with pytest.raises(CamcadError) as refused:
        load_law(_save(tmp_path, lambda msp, doc: build(msp, doc, 0.5), "broken.dxf"))
    assert refused.value.fix.startswith("the chain read stops at x = 210, 0.5 drawing units short of LWPOLYLINE")
    assert refused.value.fix.endswith("close that gap in the drawing") and len(refused.value.fix) < 120
    # the same law in two halves of equal width that do not meet: not "the same x-range", but the gap
    def halves(msp, doc):
        msp.add_lwpolyline(LAW[:6], dxfattribs={"layer": "LAW"})
        msp.add_lwpolyline([(t + 0.5, a) for t, a in LAW[5:]], dxfattribs={"layer": "LAW"})
    with pytest.raises(CamcadError) as refused:
        load_law(_save(tmp_path, halves, "halves.dxf"))
    assert "2 curves of the same width side by side (x 0..180, 180.5..360.5" in refused.value.what
    assert refused.value.fix.startswith("the chain read stops at x = 180, 0.5 drawing units short of")
    # a gap late in the return: the part before it (0..300) is read, with the warning
    def late(msp, doc):
        msp.add_lwpolyline(LAW[:10], dxfattribs={"layer": "LAW"})
        msp.add_lwpolyline([(t + 0.5, a) for t, a in LAW[9:]], dxfattribs={"layer": "LAW"})
    partial = load_law(_save(tmp_path, late, "late.dxf"))
    warned = [n for n in partial.notes if n.startswith("warning: the law's chain ends")]
    assert len(warned) == 1 and "x = 300, 0.5 drawing units short of LWPOLYLINE" in warned[0], partial.notes
    whole = load_law(_save(tmp_path, lambda msp, doc: build(msp, doc, 0.0), "whole.dxf"))
    assert not [n for n in whole.notes if "short of" in n] and np.degrees(whole.law.x[-1]) == pytest.approx(360)
