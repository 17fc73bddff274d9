"""The fast route to least phase angles (camcad.scene.stretch) against the direct one.

Direct route (``phase_pressure_function``, ``phase_stress_function`` in camcad.scene.mechanism): for each
trial width, retime the law (``camcad.law.retime``), build the cam (``CamGeometry``) and sample the
stretched phase; the pressure-angle peak is refined by a bounded Brent search, the contact stress is
evaluated at every speed of the range with ``camcad.contact.contact_stress``.
Fast route (``PhaseStretch``): sample the phase once, rescale v by β/t and a by (β/t)², evaluate every
width in one pass, refine the peak by zooming grids, and evaluate the contact stress at the two end speeds
only (the axial force is affine in ω²). The two routes share only the elementary formulas.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcad.contact import ContactParams
from camcad.cyclogram.limits import least_phase_angle
from camcad.law.standard import compose
from camcad.scene.laws import phases_deg
from camcad.scene.mechanism import phase_pressure_function, phase_stress_function, pressure_stretch, stress_relation
from camcad.scene.stretch import least_angle

LAW = compose([("dwell", 40), ("rise", 70), ("dwell", 60), ("return", 70), ("dwell", 120)], 30.0, "cycloidal")
FOLLOWERS = {
    "roller": {"type": "roller", "base_radius": 60.0, "roller_radius": 12.0},
    "offset roller, cw": {"type": "roller", "base_radius": 45.0, "roller_radius": 10.0, "offset": 6.0, "cw": True},
    "oscillating": {"type": "oscillating", "base_radius": 40.0, "roller_radius": 10.0, "pivot": 120.0, "arm": 100.0},
}
PARAMS = ContactParams(cam_modulus=2.1e5, cam_poisson=0.3, follower_modulus=2.1e5, follower_poisson=0.3, width=12.0,
                       mass=0.9, allowable_stress=1100.0, closure="force", spring_rate=6.0, preload=120.0, load=15.0,
                       load_range_deg=(30.0, 200.0), friction=0.05)
SPEEDS = [280.0, 300.0, 330.0, 360.0, 390.0, 420.0]


@pytest.mark.reference("second method", "the direct route: the law retimed and the cam rebuilt at each width")
@pytest.mark.parametrize("name", sorted(FOLLOWERS))
@pytest.mark.parametrize("index", [1, 3])
def test_pressure_relation_equals_the_direct_route(name, index):
    table = FOLLOWERS[name]
    widths = np.array([30.0, 45.0, 70.0, 95.0, 125.0])
    fast = pressure_stretch(LAW, table, index, "x", 361).pressure_max_deg(widths)
    direct = np.array([phase_pressure_function(LAW, table, index, "x", 361)(w) for w in widths])
    np.testing.assert_allclose(fast, direct, rtol=1e-9)


@pytest.mark.reference("second method", "the direct route's contact stress, infinite where it is inadmissible")
@pytest.mark.parametrize("name", ["roller", "offset roller, cw"])
@pytest.mark.parametrize("index", [1, 3])
def test_stress_relation_equals_the_direct_route_including_inadmissible_widths(name, index):
    table = FOLLOWERS[name]
    widths = np.array([12.0, 20.0, 30.0, 45.0, 70.0, 110.0])
    fast = stress_relation(LAW, table, PARAMS, SPEEDS, index, "x", 2000)(widths)
    direct = np.array([phase_stress_function(LAW, table, PARAMS, SPEEDS, index, "x", 2000)(w) for w in widths])
    assert np.array_equal(np.isinf(fast), np.isinf(direct))
    assert np.isinf(fast).any() and np.isfinite(fast).any()   # both kinds of width are exercised
    finite = np.isfinite(direct)
    np.testing.assert_allclose(fast[finite], direct[finite], rtol=1e-9)


@pytest.mark.reference("second method", "the scalar root finder (camcad.cyclogram.limits.least_phase_angle) on the "
                                        "same relation")
def test_least_angle_equals_the_scalar_root_finder():
    table = FOLLOWERS["roller"]
    for index in (1, 3):
        start, end, _ = phases_deg(LAW)[index]
        relation = stress_relation(LAW, table, PARAMS, SPEEDS, index, "x", 2000)
        fast = least_angle(relation, 900.0, 0.1 * (end - start), 150.0, source="contact")
        scalar = least_phase_angle(lambda t, relation=relation: float(relation(np.array([t]))[0]), 900.0,
                                   0.1 * (end - start), 150.0, source="contact")
        assert fast.binding == scalar.binding
        assert fast.angle_deg == pytest.approx(scalar.angle_deg, abs=1e-8)
        assert fast.value <= 900.0 + 1e-6


@pytest.mark.reference("closed form", "hand-made relations with known crossings at 50 and 20 deg")
def test_least_angle_bounds_behave_like_the_scalar_root_finder():
    def relation(widths):   # a falling stress with an inadmissible region below 20 deg
        widths = np.asarray(widths, dtype=float)
        return np.where(widths < 20.0, np.inf, 5000.0 / widths)

    found = least_angle(relation, 100.0, 5.0, 90.0, source="s")
    assert found.binding and found.angle_deg == pytest.approx(50.0, abs=1e-9)
    at_jump = least_angle(relation, 400.0, 5.0, 90.0, source="s")
    assert at_jump.angle_deg == pytest.approx(20.0, abs=1e-8) and "inadmissible" in at_jump.note
    assert not least_angle(relation, 100.0, 60.0, 90.0, source="s").binding
    with pytest.raises(Exception, match="longest phase angle"):
        least_angle(relation, 10.0, 5.0, 90.0, source="s")
    assert math.isfinite(at_jump.value)


@pytest.mark.reference("closed form", "centred roller: tan phi_max(t) = (beta/t) tan phi_max(beta)")
@pytest.mark.parametrize("index", [1, 3])
def test_closed_form_least_width_of_a_centred_roller_equals_root_finding_and_the_direct_route(index):
    # tan φ_max(t) = (β/t) tan φ_max(β) for a translating roller without offset: the closed form must give
    # the root Brent's method finds on the same relation, and the direct route (law retimed, cam rebuilt,
    # Brent-refined peak) must reach the limit there
    table = FOLLOWERS["roller"]
    stretch = pressure_stretch(LAW, table, index, "x", 361)
    start, end, _ = phases_deg(LAW)[index]
    for limit in (20.0, 30.0, 45.0):
        closed = least_angle(stretch.pressure_max_deg, limit, 0.1 * (end - start), 200.0,
                             inverse=stretch.pressure_inverse)
        searched = least_angle(stretch.pressure_max_deg, limit, 0.1 * (end - start), 200.0)
        assert closed.binding and searched.binding
        assert closed.evaluations < searched.evaluations
        assert closed.angle_deg == pytest.approx(searched.angle_deg, abs=1e-8)
        direct = phase_pressure_function(LAW, table, index, "x", 361)(closed.angle_deg)
        assert direct == pytest.approx(limit, abs=1e-9)
    # no closed form with an offset or an oscillating follower: the search is used
    for name in ("offset roller, cw", "oscillating"):
        assert pressure_stretch(LAW, FOLLOWERS[name], index, "x", 361).pressure_inverse(30.0) is None
