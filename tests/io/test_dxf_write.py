"""The profile DXF, re-read with ezdxf: closed, in mm, and within the chord tolerance of the exact profile."""

from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest
from scipy.spatial import cKDTree

from camcad.errors import CamcadError
from camcad.io.dxf_write import Drawing, DxfSpline, ascii_text, build_document
from camcad.law.standard import compose
from camcad.profile import default_design
from camcad.profile.followers import Follower
from camcad.profile.scaled_law import swing_law
from camcad.profile.synth import ProfileSettings, synthesize
from camcad.report.profile_files import write_outputs

NAME, LAW, FOLLOWER = default_design()


def make(tmp_path, follower=FOLLOWER, law=LAW, **options):
    settings = ProfileSettings(design=False, plots=False, **options)
    result = synthesize(law, follower, settings, name="t")
    write_outputs(result, tmp_path, settings)
    return result, ezdxf.readfile(tmp_path / "profile.dxf")


# ---- an independent measure of the distance between two curves ---------------------------------

def segment_distance(points, start, end):
    seg = end - start
    t = np.clip(np.einsum("ij,ij->i", points - start, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300), 0, 1)
    return np.linalg.norm(points - (start + t[:, None] * seg), axis=1)


def distance_to_ring(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Distance from each point to the closed dense polyline ``ring`` (last point joins the first):
    nearest vertex by a k-d tree, then the exact distance to the segments around it (two on each
    side, so a very short segment cannot hide its neighbour)."""
    if np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]
    n = len(ring)
    _, k = cKDTree(ring).query(points)
    best = np.full(len(points), np.inf)
    for shift in (-2, -1, 0, 1):
        j = (k + shift) % n
        best = np.minimum(best, segment_distance(points, ring[j], ring[(j + 1) % n]))
    return best


def written_curve(entity, step: float = 0.005) -> np.ndarray:
    """Dense points along a re-read (LW)POLYLINE, following its exact LINE and ARC pieces."""
    pieces = []
    for part in entity.virtual_entities():
        if part.dxftype() == "LINE":
            a, b = np.array(part.dxf.start)[:2], np.array(part.dxf.end)[:2]
            n = max(2, int(np.linalg.norm(b - a) / step) + 2)
            pts = a + (b - a) * np.linspace(0, 1, n)[:, None]
        else:  # ARC: ezdxf gives it counter-clockwise from start_angle to end_angle
            c, r = np.array(part.dxf.center)[:2], part.dxf.radius
            a0, a1 = math.radians(part.dxf.start_angle), math.radians(part.dxf.end_angle)
            a1 = a1 if a1 > a0 else a1 + 2 * math.pi
            n = max(2, int((a1 - a0) * r / step) + 2)
            ang = np.linspace(a0, a1, n)
            pts = c + r * np.stack((np.cos(ang), np.sin(ang)), axis=1)
        pieces.append(pts)
    # ezdxf gives every ARC counter-clockwise; turn pieces round so the walk is continuous
    if np.min(np.linalg.norm(pieces[0][0] - np.array([pieces[1][0], pieces[1][-1]]), axis=1)) < \
            np.min(np.linalg.norm(pieces[0][-1] - np.array([pieces[1][0], pieces[1][-1]]), axis=1)):
        pieces[0] = pieces[0][::-1]
    for i in range(1, len(pieces)):
        if np.linalg.norm(pieces[i][-1] - pieces[i - 1][-1]) < np.linalg.norm(pieces[i][0] - pieces[i - 1][-1]):
            pieces[i] = pieces[i][::-1]
    return np.concatenate(pieces)


def deviation(result, written: np.ndarray, samples: int = 200_001) -> float:
    """Largest distance between written and exact curve, both ways (mm). The exact profile is
    sampled every ~2 µm of arc, so its own chords err by < 2e-8 mm."""
    exact = result.geometry.profile(np.linspace(0.0, 2 * math.pi, samples)).points
    return max(distance_to_ring(written, exact).max(), distance_to_ring(exact, written).max())


def only(doc, layer: str, kind: str):
    entities = [e for e in doc.modelspace() if e.dxf.layer == layer]
    assert [e.dxftype() for e in entities] == [kind]
    return entities[0]


# ---- tests ---------------------------------------------------------------------------------------

@pytest.mark.reference("second method", "the drawing re-read with ezdxf: closed, mm, every vertex as computed, "
                                        "extents holding ezdxf's boxes")
def test_r2000_profile_is_closed_in_mm_and_within_tolerance(tmp_path):
    result, doc = make(tmp_path)
    assert doc.dxfversion == "AC1015"
    assert doc.header["$INSUNITS"] == 4
    assert {"PROFILE", "PITCH", "BASE_CIRCLE", "CENTER", "ROLLER", "TEXT"} <= {layer.dxf.name for layer in doc.layers}
    profile = only(doc, "PROFILE", "LWPOLYLINE")
    assert profile.closed
    vertices = np.array(profile.get_points("xy"))
    # what was written is exactly what was computed (DXF keeps the full float precision)
    assert np.array_equal(vertices, result.profile.polyline.points)
    assert deviation(result, written_curve(profile)) <= 1e-3
    assert only(doc, "PITCH", "LWPOLYLINE").closed
    circle = only(doc, "BASE_CIRCLE", "CIRCLE")
    assert circle.dxf.radius == 50.0 and tuple(circle.dxf.center)[:2] == (0.0, 0.0)
    roller = only(doc, "ROLLER", "CIRCLE")
    assert roller.dxf.radius == 10.0 and tuple(roller.dxf.center)[:2] == pytest.approx((0.0, 60.0), abs=1e-12)
    assert len([e for e in doc.modelspace() if e.dxf.layer == "CENTER"]) == 2
    texts = [e.dxf.text for e in doc.modelspace() if e.dxftype() == "TEXT"]
    joined = "\n".join(texts)
    assert all(t.isascii() for t in texts)
    for needed in ("law: rise cycloidal 0-120", "phases (deg): rise 0-120", "Rb 50 mm", "Rr 10 mm", "e 0 mm",
                   "lift 25 mm"):
        assert needed in joined
    # extents come from the content (LibreOffice collapses ±1e20)
    assert doc.header["$EXTMAX"][0] == pytest.approx(np.max(vertices[:, 0]), abs=60.0)
    assert abs(doc.header["$EXTMIN"][1]) < 1e3
    # the text boxes are estimated without fonts: the extents hold ezdxf's font-measured box of every
    # entity and exceed it by less than a third of its size on each side
    from ezdxf import bbox

    measured = bbox.extents(doc.modelspace(), fast=False)
    low, high = np.array(doc.header["$EXTMIN"])[:2], np.array(doc.header["$EXTMAX"])[:2]
    size = np.array(measured.size)[:2]
    assert np.all(low <= np.array(measured.extmin)[:2] + 1e-9) and np.all(high >= np.array(measured.extmax)[:2] - 1e-9)
    assert (np.all(np.array(measured.extmin)[:2] - low < size / 3)
            and np.all(high - np.array(measured.extmax)[:2] < size / 3))


@pytest.mark.reference("closed form", "an arc over chord c with bulge b leaves at angle(c) - 2 atan b and arrives at "
                                      "angle(c) + 2 atan b")
def test_arcs_are_tangent_continuous_and_within_tolerance(tmp_path):
    result, doc = make(tmp_path, arcs=True)
    profile = only(doc, "PROFILE", "LWPOLYLINE")
    assert profile.closed
    bulges = np.array([b for *_, b in profile.get_points("xyb")])
    assert np.count_nonzero(bulges) > 0.9 * len(bulges)
    assert len(bulges) < len(result.profile.polyline.points) / 5   # arcs need far fewer segments
    assert deviation(result, written_curve(profile)) <= 1e-3
    # G1: at every vertex the arc arriving and the arc leaving share the tangent. For an arc over
    # chord c with bulge b the tangent leaves at angle(c) − 2 atan b and arrives at angle(c) + 2 atan b.
    pts = np.array(profile.get_points("xy"))
    chords = np.roll(pts, -1, axis=0) - pts
    direction = np.arctan2(chords[:, 1], chords[:, 0])
    leaving = direction - 2 * np.arctan(bulges)
    arriving = direction + 2 * np.arctan(bulges)
    kink = np.angle(np.exp(1j * (leaving - np.roll(arriving, 1))))
    assert np.max(np.abs(kink)) < 1e-8


@pytest.mark.reference("second method", "the R12 drawing re-read with ezdxf, its distance from the exact profile")
@pytest.mark.parametrize("arcs", [False, True])
def test_r12_profile_is_a_closed_polyline_within_tolerance(tmp_path, arcs):
    result, doc = make(tmp_path, r12=True, arcs=arcs)
    assert doc.dxfversion == "AC1009"
    profile = only(doc, "PROFILE", "POLYLINE")
    assert profile.is_closed
    assert deviation(result, written_curve(profile)) <= 1e-3


@pytest.mark.reference("second method", "the drawing re-read with ezdxf, its distance from the exact profile at each "
                                        "tolerance")
@pytest.mark.parametrize("tol, arcs", [(1e-2, False), (1e-2, True), (1e-4, False), (1e-4, True)])
def test_oscillating_profile_meets_other_tolerances(tmp_path, tol, arcs):
    follower = Follower("oscillating", 40.0, 10.0, pivot=120.0, arm=100.0)
    law = swing_law(LAW, arm_mm=100.0)
    result, doc = make(tmp_path, follower, law, tol_mm=tol, arcs=arcs)
    measured = deviation(result, written_curve(only(doc, "PROFILE", "LWPOLYLINE"), step=min(0.005, 20 * tol)))
    assert measured <= tol
    assert measured > 0.5 * tol   # the point count follows the tolerance, it is not just dense


@pytest.mark.reference("second method", "the re-read control points and knots evaluated as a B-spline by scipy")
def test_spline_is_closed_by_control_points_and_within_tolerance(tmp_path):
    result, doc = make(tmp_path, spline=True)
    spline = only(doc, "PROFILE_SPLINE", "SPLINE")
    assert spline.dxf.degree == 3 and spline.fit_point_count() == 0
    control = np.array(spline.control_points)[:, :2]
    assert len(control) == len(result.profile.polyline.points) + 3   # nodes + closing node + 2 end conditions
    # the re-read control points and knots as a B-spline (scipy; ezdxf's own tool rounds knots to
    # 10 decimals): it closes, with one tangent at the seam
    from scipy.interpolate import BSpline

    knots = np.array(spline.knots)
    curve_fn = BSpline(knots, control, 3)
    t_end = knots[-1]
    assert np.linalg.norm(curve_fn(0.0) - curve_fn(t_end)) < 1e-12
    d0, d1 = curve_fn.derivative()(0.0), curve_fn.derivative()(t_end)
    assert np.linalg.norm(d0 - d1) < 1e-12 * np.linalg.norm(d0)
    # and the curve ezdxf draws from it stays within the chord tolerance of the exact profile
    tool = spline.construction_tool()
    curve = np.array([(p.x, p.y) for p in tool.points(np.linspace(0.0, tool.max_t, 200_001))])
    assert deviation(result, curve) <= 1e-3


@pytest.mark.reference("closed form", "the flat face's line at theta = 0 lies at y = Rb and spans the contact points "
                                      "x = v")
def test_groove_counter_cam_flat_and_knife_drawings(tmp_path):
    groove = Follower("roller", 50.0, 10.0, groove=True, pair_distance=150.0)
    _, doc = make(tmp_path / "g", groove)
    for layer in ("GROOVE_OUTER", "COUNTER_PROFILE", "COUNTER_PITCH"):
        assert only(doc, layer, "LWPOLYLINE").closed
    assert len([e for e in doc.modelspace() if e.dxf.layer == "ROLLER" and e.dxftype() == "CIRCLE"]) == 2
    result, doc = make(tmp_path / "f", Follower("flat", 50.0))
    face = [e for e in doc.modelspace() if e.dxf.layer == "ROLLER" and e.dxftype() == "LINE"]
    # the face line at θ = 0 is at y = Rb and spans the contact points' range x = v
    y = face[0].dxf.start[1]
    assert y == pytest.approx(50.0)
    lo, hi = result.face_extent
    assert min(face[0].dxf.start[0], face[0].dxf.end[0]) < lo and max(face[0].dxf.start[0], face[0].dxf.end[0]) > hi
    _, doc = make(tmp_path / "k", Follower("knife", 50.0, 0.0))
    assert [e.dxftype() for e in doc.modelspace() if e.dxf.layer == "ROLLER"] == ["LINE"]


@pytest.mark.reference("property", "an unbalanced law's profile is written open, not closed by a segment")
def test_open_profile_is_written_open(tmp_path):
    # an unbalanced law: the drawing must show the break, not hide it with a closing segment
    from camcad.law.law import PiecewiseLinearLaw

    beta, h = math.pi / 2, 20.0
    peak = 4 * h / beta**2
    x = np.array([0, 0, 0.5, 0.5, 1, 1, 2, 2, 2.5, 2.5, 3, 3, 4]) * beta
    a = np.array([0, peak, peak, -peak, -peak, 0, 0, -0.9 * peak, -0.9 * peak, 0.9 * peak, 0.9 * peak, 0, 0])
    _, doc = make(tmp_path, law=PiecewiseLinearLaw(x, a, 2 * math.pi))
    assert not only(doc, "PROFILE", "LWPOLYLINE").closed


@pytest.mark.reference("property", "text written as ASCII transliterations; R12 refuses splines in one line")
def test_text_is_ascii_and_r12_refuses_splines():
    assert ascii_text("cam Ø50 – 30° ψ ≤ 2") == "cam D50 - 30 deg psi <= 2"
    assert ascii_text("Kulachok: profil\u0300 ok\u00e9") == "Kulachok: profil oke"
    spline = DxfSpline("PROFILE_SPLINE", np.zeros((4, 2)), np.array([0, 0, 0, 0, 1, 1, 1, 1.0]))
    with pytest.raises(CamcadError, match="R12"):
        build_document(Drawing(splines=(spline,)), "R12")


@pytest.mark.reference("property", "every file written is listed in report.json's outputs, nothing else in the folder")
def test_outputs_are_atomic_and_listed(tmp_path):
    law = compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 10.0, "modified_trapezoid")
    settings = ProfileSettings(design=False, plots=False)
    result = synthesize(law, Follower("roller", 30.0, 6.0), settings)
    written = write_outputs(result, tmp_path, settings, extra={"skipped": {"impact": "no [stops] in scene"}})
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in written)
    import json

    data = json.loads((tmp_path / "report.json").read_text())
    assert data["skipped"] == {"impact": "no [stops] in scene"}
    assert data["outputs"] == [str(p) for p in written]
