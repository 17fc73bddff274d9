"""Several lifts per cycle in a drawn law: intermediate stops detected, stated positions checked and reached by fix."""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcad
from camcad.balance.checking import check
from camcad.balance.correction import correct
from camcad.errors import CamcadError
from camcad.law.phases import parse_phases

# triangular lobes (θ deg, a): a rise 0-60, a stop 60-100, a second rise 100-160, a dwell, a return 200-300;
# each rise lobe pair moves the follower by A(π/6)²·... : both rises equal, the return twice as wide
STOPS = [(0, 0), (15, 1), (30, 0), (45, -1), (60, 0), (100, 0), (115, 1), (130, 0), (145, -1), (160, 0), (200, 0),
         (225, -1), (250, 0), (275, 1), (300, 0), (360, 0)]
STATED = "0:60:rise:1,60:100:dwell,100:160:rise:2.5,160:200:dwell,200:300:return:0,300:360:dwell"


@pytest.fixture
def stops(tmp_path):
    path = tmp_path / "stops.csv"
    path.write_text("".join(f"{t},{a}\n" for t, a in STOPS))
    return path


@pytest.mark.reference("closed form", "the phases the law was drawn with: rise 0-60, dwell 60-100, rise 100-160, ...")
def test_intermediate_stop_is_a_dwell_not_a_constant_velocity(stops):
    loaded = camcad.load_law(stops)
    kinds = [(p.kind, round(math.degrees(p.start), 6), round(math.degrees(p.end), 6)) for p in loaded.law.phases]
    assert kinds == [("rise", 0, 60), ("dwell", 60, 100), ("rise", 100, 160), ("dwell", 160, 200),
                     ("return", 200, 300), ("dwell", 300, 360)]


@pytest.mark.reference("closed form", "+ 0 - is one rise coasting at constant velocity, as drawn")
def test_a_zero_stretch_in_motion_stays_a_constant_velocity(tmp_path):
    path = tmp_path / "cv.csv"
    # + 0 − : accelerate, coast at constant velocity, decelerate: one rise
    rows = [(0, 0), (20, 1), (40, 0), (100, 0), (120, -1), (140, 0), (180, 0), (200, -1), (220, 0), (280, 0),
            (300, 1), (320, 0), (360, 0)]
    path.write_text("".join(f"{t},{a}\n" for t, a in rows))
    kinds = [p.kind for p in camcad.load_law(path).law.phases]
    assert kinds == ["rise", "dwell", "return", "dwell"]


@pytest.mark.reference("closed form", "s of triangular lobes: a lobe of height A and base b/2 followed by its negative "
                                      "moves the follower A b²/8 (b in rad)")
def test_check_holds_each_stated_position(stops):
    loaded = camcad.load_law(stops, phases=STATED)
    report = check(loaded.law)
    by_name = dict(zip(report.condition_names, report.residuals))
    # rise 1: a lobe pair of base 60 deg, A = 1: s = (π/3)²/8
    moved = (math.pi / 3) ** 2 / 8
    assert by_name["displacement at the end of the rise (60 deg) = 1 mm"] == pytest.approx(moved - 1.0, abs=1e-12)
    assert by_name["displacement at the end of the rise (160 deg) = 2.5 mm"] == pytest.approx(2 * moved - 2.5,
                                                                                             abs=1e-12)
    assert not report.balanced


@pytest.mark.reference("property", "the stated positions and rest at every phase end, after the least change")
def test_fix_brings_every_stated_position(stops):
    loaded = camcad.load_law(stops, phases=STATED)
    fixed = correct(loaded.law)
    assert fixed.after.balanced
    ends = fixed.law.kinematics(np.array([p.end for p in fixed.law.phases]))
    assert np.allclose(ends.s, [1.0, 1.0, 2.5, 2.5, 0.0, 0.0], rtol=0, atol=1e-12)
    assert np.max(np.abs(ends.v)) <= 1e-12
    with pytest.raises(CamcadError, match="state end positions or velocities"):
        correct(loaded.law, "phase")


@pytest.mark.reference("property", "fix with stated positions: balanced after, the 2.5 mm position named among the "
                                   "conditions")
def test_fix_from_the_command_line_with_stated_positions(stops, cli, tmp_path):
    result = cli("fix", stops, "--phases", STATED, "-o", tmp_path / "fixed.csv", "--no-plots", "--json")
    assert result.code == 0, result.err
    assert result.json()["after"]["balanced"]
    names = [c["name"] for c in result.json()["after"]["conditions"]]
    assert "displacement at the end of the rise (160 deg) = 2.5 mm" in names


@pytest.mark.reference("closed form", "a stated 0.1 mm/deg is 0.1 x 180/pi mm/rad")
def test_stated_velocity_is_the_target_at_a_phase_end():
    phases = parse_phases("0:90:rise:5:0.1,90:180:rise:20,180:360:return:0", 360.0)
    assert phases[0].v_end == pytest.approx(math.degrees(0.1))
    assert phases[0].as_deg()["v_end_mm_per_deg"] == pytest.approx(0.1)
