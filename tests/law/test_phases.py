"""Phase detection from drawn laws, and the --phases override."""

import numpy as np
import pytest

from camcad.errors import CamcadError
from camcad.law.phases import detect_phases, parse_phases
from camcad.law.standard import compose


def _drawn(phases_deg, shape="cycloidal", step_deg=1.0):
    law = compose(phases_deg, 10.0, shape)
    theta = np.radians(np.arange(0, 360 + step_deg / 2, step_deg))
    return law, theta, law.kinematics(theta).a


def _as_deg(phases):
    return [(p.kind, round(np.degrees(p.start), 6), round(np.degrees(p.end), 6)) for p in phases]


@pytest.mark.reference("closed form", "the phase boundaries the law was composed with (whole degrees on the grid)")
@pytest.mark.parametrize("layout", [
    [("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)],
    [("dwell", 80), ("rise", 100), ("return", 100), ("dwell", 80)],
    [("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)],
    [("dwell", 30), ("rise", 100), ("dwell", 30), ("return", 100), ("dwell", 100)],
])
def test_detected_phases_equal_the_composed_ones(layout):
    # Reference: the phase boundaries the law was composed with (exact, whole degrees on the grid).
    _law, theta, a = _drawn(layout)
    found = detect_phases(theta, a, 2 * np.pi)
    expected = []
    start = 0.0
    for kind, width in layout:
        expected.append((kind, start, start + width))
        start += width
    assert _as_deg(found) == [(k, pytest.approx(s, abs=1e-6), pytest.approx(e, abs=1e-6)) for k, s, e in expected]


@pytest.mark.reference("closed form", "the boundaries of a constant-acceleration law drawn with jumps, set here")
def test_jumps_and_constant_acceleration_phases():
    x = np.radians([0, 60, 60, 110, 110, 160, 160, 200, 200, 250, 250, 300, 300, 360])
    a = np.array([0, 0, 1, 1, -1, -1, 0, 0, -1, -1, 1, 1, 0, 0.0])
    found = detect_phases(x, a, 2 * np.pi)
    assert _as_deg(found) == [("dwell", 0, 60), ("rise", 60, 160), ("dwell", 160, 200), ("return", 200, 300),
                              ("dwell", 300, 360)]


@pytest.mark.reference("closed form", "a + 0 - sign pattern inside a rise is coasting: the rise ends at the drawn 150 "
                                      "deg")
def test_constant_velocity_stretch_is_part_of_the_motion_not_a_dwell():
    # + 0 − inside a rise is coasting at constant speed; + 0 + between lobes would be a dwell
    x = np.radians([0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330, 360])
    a = np.array([0, 1, 0, 0, -1, 0, 0, -1, 0, 0, 1, 0, 0.0])
    found = detect_phases(x, a, 2 * np.pi)
    kinds = [p.kind for p in found]
    assert kinds == ["rise", "dwell", "return", "dwell"]
    assert np.degrees(found[0].end) == pytest.approx(150)


@pytest.mark.reference("closed form", "v = 0 at the top of a symmetric rise-return: 180 deg")
def test_rise_return_split_is_where_the_velocity_is_zero():
    _law, theta, a = _drawn([("dwell", 80), ("rise", 100), ("return", 100), ("dwell", 80)], "poly345", 0.5)
    found = detect_phases(theta, a, 2 * np.pi)
    from camcad.law.law import PiecewiseLinearLaw

    drawn = PiecewiseLinearLaw(theta, a, 2 * np.pi, found)
    split = found[1].end
    assert abs(drawn.kinematics(np.array([split])).v[0]) < 1e-12
    # the drawn (interpolated) law is a hair off the composed one, so its top is within 1e-5 deg of 180
    assert np.degrees(split) == pytest.approx(180, abs=1e-5)


@pytest.mark.reference("property", "bad input: an all-zero law is refused with one line (docs/INTERFACE.md)")
def test_zero_law_is_rejected():
    with pytest.raises(CamcadError, match="zero everywhere"):
        detect_phases(np.array([0, 1, 2.0]), np.zeros(3), 2.0)


@pytest.mark.reference("property", "--phases parsed as written; malformed lists refused with the reason")
def test_parse_phases_and_its_errors():
    phases = parse_phases("0:90:rise,90:180:dwell,180:270:return,270:360:dwell", 360)
    assert [p.kind for p in phases] == ["rise", "dwell", "return", "dwell"]
    for bad, match in [("0:90:rise,100:360:dwell", "gap"), ("0:90:lift,90:360:dwell", "kind"),
                       ("0:90,90:360:dwell", "start:end:kind"), ("10:360:rise", "not the cycle"),
                       ("0:x:rise", "numbers"), ("", "no phases")]:
        with pytest.raises(CamcadError, match=match):
            parse_phases(bad, 360)
