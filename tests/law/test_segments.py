"""Laws designed from segments: solved boundary values, continuity at the joints, refusals, scenes and retiming."""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcad
from camcad.errors import CamcadError
from camcad.law.phases import parse_phases
from camcad.law.retime import retime
from camcad.law.segments import SegmentSpec, format_segments, parse_segments, solve_segments

FILLING = [SegmentSpec(60, "dwell"), SegmentSpec(140, "poly5", 12.0, v_end="match"),
           SegmentSpec(200, "constant_velocity", 30.0), SegmentSpec(240, "poly5", 36.0),
           SegmentSpec(330, "modified_sine", 0.0), SegmentSpec(360, "dwell")]
LIFT = 36.0

NODES, RADIUS = 64, 0.02


def _cauchy(piece, theta: float, order: int) -> float:
    """order-th derivative of a piece's s at θ by Cauchy's integral formula (s alone; see tests/law/test_vdi.py)."""
    w = np.exp(2j * math.pi * np.arange(NODES) / NODES)
    values = piece.evaluate_tau(theta - piece.start + RADIUS * w, 0)
    return float(np.real(math.factorial(order) / (NODES * RADIUS**order) * np.sum(values * w ** (-order))))


@pytest.mark.reference("property", "one-sided limits of s, v, a at every joint (and v, a again by Cauchy-integral "
                                   "differentiation of s on each side, a second method)")
def test_filling_law_is_continuous_in_s_v_a_at_every_joint():
    law = solve_segments(FILLING)
    segments = law.segments
    for before, after in zip(segments, (*segments[1:], segments[0])):
        joint = before.end
        left_piece, right_piece = before.pieces[-1], after.pieces[0]
        at_right = after.start
        for order in range(3):
            left = float(left_piece.evaluate(np.array([joint]), order)[0])
            right = float(right_piece.evaluate(np.array([at_right]), order)[0])
            assert abs(right - left) <= 1e-12 * LIFT, (before.number, order, left, right)
        for order in (1, 2):
            left = _cauchy(left_piece, joint, order)
            right = _cauchy(right_piece, at_right, order)
            assert abs(right - left) <= 1e-9 * LIFT, (before.number, order)
    assert [j.class_ for j in law.joints] == ["C2", "C2", "C2", "C2", "C2", "C3"]


@pytest.mark.reference("closed form", "v = (30 − 12) mm / 60 deg = 0.3 mm/deg, a = 0 on the constant velocity")
def test_constant_velocity_segment_moves_at_exactly_its_velocity():
    law = solve_segments(FILLING)
    theta = np.radians(np.linspace(140.0, 200.0, 601))[:-1]   # at 200 deg the next segment (its right side) holds
    kin = law.kinematics(theta)
    assert np.max(np.abs(np.radians(kin.v) - 0.3)) <= 1e-15 * 0.3 * 4
    assert np.max(np.abs(kin.a)) == 0.0 and np.max(np.abs(kin.j)) == 0.0
    assert np.max(np.abs(kin.s - (12.0 + 0.3 * np.degrees(theta - math.radians(140.0))))) <= 1e-12 * LIFT


@pytest.mark.reference("property", "the cam profile of the law closes (synthesis' own closure check)")
def test_filling_law_profile_closes_and_passes():
    law = solve_segments(FILLING)
    result = camcad.synthesize(law, camcad.Follower("roller", base_radius=45.0, roller_radius=12.0))
    assert result.profile.closed and result.profile.closure_gap <= 1e-9
    assert not result.undercut and result.passed


@pytest.mark.reference("property", "stated end values reached; every phase ends where the law says")
def test_several_lifts_to_intermediate_stops():
    law = solve_segments([SegmentSpec(40, "dwell"), SegmentSpec(100, "poly5", 10.0), SegmentSpec(150, "dwell"),
                          SegmentSpec(210, "modified_sine", 25.0, param=0.4), SegmentSpec(240, "dwell"),
                          SegmentSpec(320, "inclined_sine", 0.0), SegmentSpec(360, "dwell")])
    assert [p.kind for p in law.phases] == ["dwell", "rise", "dwell", "rise", "dwell", "return", "dwell"]
    assert [p.s_end for p in law.phases] == [0.0, 10.0, 10.0, 25.0, 25.0, 0.0, 0.0]
    ends = law.kinematics(np.array([p.end for p in law.phases]))
    assert np.allclose(ends.s, [0, 10, 10, 25, 25, 0, 0], rtol=0, atol=1e-12 * 25)
    assert np.max(np.abs(ends.v)) <= 1e-12 * 25
    assert all(j.class_ == "C2" or j.class_ == "C3" for j in law.joints)


@pytest.mark.reference("closed form", "v_end = match takes the next segment's start velocity (0.3 rad/rad here), else "
                                      "rest")
def test_match_resolves_to_the_next_segments_start_and_defaults_to_rest():
    law = solve_segments(FILLING)
    poly_in, cv, poly_out = law.segments[1:4]
    assert poly_in.end_values[1] == pytest.approx(math.degrees(0.3), rel=1e-14)
    assert poly_out.end_values[1] == pytest.approx(0.0, abs=1e-12)
    assert poly_in.motion_class(1e-9, 1e-9) == "R-G" and cv.motion_class(1e-9, 1e-9) == "G-G"
    assert poly_out.motion_class(1e-9, 1e-9) == "G-R"


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("specs, match", [
    ([SegmentSpec(60, "dwell"), SegmentSpec(180, "poly5", 20.0, v_end=0.2), SegmentSpec(200, "dwell"),
      SegmentSpec(360, "poly5", 0.0)], r"segment 3 \(dwell\) rests but segment 2 \(poly5\) arrives"),
    ([SegmentSpec(60, "dwell"), SegmentSpec(120, "poly5", 10.0, v_end=0.1), SegmentSpec(200, "constant_velocity", 30.0),
      SegmentSpec(360, "poly5", 0.0)], r"segment 3 \(constant_velocity\) moves at 0.25 mm/deg"),
    ([SegmentSpec(100, "constant_velocity", 20.0), SegmentSpec(200, "harmonic", 30.0),
      SegmentSpec(360, "poly5", 0.0)], r"segment 2 \(harmonic\) starts at 0 mm/deg"),
    ([SegmentSpec(180, "poly5", 20.0), SegmentSpec(360, "poly5", 5.0)], "ends at 5 mm but the cycle starts at 0 mm"),
    ([SegmentSpec(180, "poly5", 20.0), SegmentSpec(170, "poly5", 0.0)], "segment 2 ends at 170 deg, not after"),
    ([SegmentSpec(180, "poly5", 20.0), SegmentSpec(350, "poly5", 0.0)], "not at the cycle's end 360"),
    ([SegmentSpec(180, "bestehorn", 20.0), SegmentSpec(360, "poly5", 0.0)], "unknown segment shape 'bestehorn'"),
    ([SegmentSpec(180, "poly5"), SegmentSpec(360, "poly5", 0.0)], "segment 1 \\(poly5\\) does not say where it ends"),
    ([SegmentSpec(180, "constant_velocity", 20.0, v_end=0.1), SegmentSpec(360, "poly5", 0.0)],
     "v_end is not a free end value of constant_velocity"),
    ([SegmentSpec(180, "poly5", 20.0, v_end="match"), SegmentSpec(360, "poly5", 0.0)],
     "takes its start v from this one"),
    ([SegmentSpec(180, "modified_sine", 20.0, param=1.2), SegmentSpec(360, "poly5", 0.0)], "0 < lambda < 1"),
    ([SegmentSpec(100, "dwell", 4.0), SegmentSpec(360, "poly5", 0.0)], "is a dwell at 0 mm but its to_mm is 4"),
])
def test_impossible_specifications_are_refused_in_one_line_naming_the_segment(specs, match):
    with pytest.raises(CamcadError, match=match) as caught:
        solve_segments(specs, where="scene [law] segments")
    message = caught.value.message()
    assert "\n" not in message and "segment" in caught.value.where


@pytest.mark.reference("property", "parse(format(specs)) == specs; malformed text refused with the reason")
def test_text_form_round_trips():
    text = "0:60:dwell,60:140:poly5:12:v_end=match,140:200:constant_velocity:30,200:240:poly5:36,240:330:" \
           "modified_sine:0:lambda=0.4,330:360:dwell"
    specs = parse_segments(text)
    assert parse_segments(format_segments(specs)) == specs
    assert specs[4].param == 0.4 and specs[1].v_end == "match"
    for bad, match in (("0:60", "is not start:end:shape"), ("0:60:dwell,70:360:poly5:0", "not where the previous"),
                       ("0:360:poly5:0:speed=3", "is not v_end=, a_end=, j_end= or lambda="),
                       ("0:360:poly5:x", "to_mm 'x' is not a number")):
        with pytest.raises(CamcadError, match=match):
            parse_segments(bad)


@pytest.mark.reference("property", "retiming keeps every segment's stated end values")
def test_retimed_segment_keeps_its_end_values():
    law = solve_segments(FILLING)
    # the first poly5 lengthened from 80 to 100 deg, taking 20 deg of the first dwell
    phases = [p.with_bounds(p.start, p.end) for p in law.phases]
    phases[0] = phases[0].with_bounds(0.0, math.radians(40.0))
    phases[1] = phases[1].with_bounds(math.radians(40.0), phases[1].end)
    stretched = retime(law, tuple(phases))
    seg = stretched.segments[1]
    assert math.degrees(seg.end - seg.start) == pytest.approx(100.0)
    assert seg.end_values[0] == pytest.approx(12.0, abs=1e-12) and seg.end_values[1] == pytest.approx(
        math.degrees(0.3), rel=1e-13)


@pytest.mark.reference("property", "a segment law through the scene pipeline: its phases as written, the profile "
                                   "closed, the limits noted")
def test_scene_with_segments_runs_the_pipeline(cli, tmp_path):
    result = cli("profile", "samples/scenes/filling_stroke.toml", "-o", tmp_path / "out", "--no-plots", "--json")
    assert result.code == 0, result.err
    report = result.json()
    assert [p["kind"] for p in report["law"]["phases_deg"]] == ["dwell", "rise", "rise", "rise", "return", "dwell"]
    assert report["closed"] and not report["undercut"]
    limits = report["phase_limits"]
    assert limits["rise"]["least_deg"] is not None and limits["rise_2"]["least_deg"] is None
    assert any("no neighbouring dwell" in note for note in report["phase_limit_notes"])


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("segment, match", [
    ('v_end = "fast"', "'v_end' must be \"match\" or a number"),
    ("speed = 3", "unknown key 'speed'"),
])
def test_scene_segment_errors(cli, tmp_path, segment, match):
    scene = tmp_path / "bad.toml"
    scene.write_text(f'name = "bad"\n[law]\n[[law.segments]]\nto_deg = 180\nshape = "poly5"\nto_mm = 10\n{segment}\n'
                     '[[law.segments]]\nto_deg = 360\nshape = "poly5"\nto_mm = 0\n'
                     '[follower]\ntype = "roller"\nbase_radius = 40\nroller_radius = 10\n')
    result = cli("profile", scene, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2 and match in result.err and "segment 1" in result.err
    assert len(result.err.strip().splitlines()) == 1


@pytest.mark.reference("property", "stated end positions and velocities parsed as written; a dwell with a velocity "
                                   "refused")
def test_stated_phases_parse_with_positions_and_velocities():
    phases = parse_phases("0:60:rise:12:0.3,60:100:rise:20,100:300:return:0,300:360:dwell", 360.0)
    assert phases[0].s_end == 12.0 and phases[0].v_end == pytest.approx(math.degrees(0.3))
    assert phases[1].s_end == 20.0 and phases[1].v_end == 0.0 and phases[3].s_end is None
    with pytest.raises(CamcadError, match="a dwell rests"):
        parse_phases("0:60:rise:12,60:360:dwell:12:0.1", 360.0)


@pytest.mark.reference("second method", "the equivalent standard law (cycloidal) of samples/scenes/loom_group1.toml: "
                                        "its least angles by rescaling the phase, the segments' by solving again")
def test_segments_in_a_cyclogram_scene_retime_like_the_standard_law(cli, tmp_path):
    from conftest import SAMPLES

    text = (SAMPLES / "scenes" / "loom_group1.toml").read_text()
    standard = ('[mechanisms.weft_returner.law]\nstandard = "cycloidal"\n'
                'phases = "0:40:dwell,40:110:rise,110:170:dwell,170:240:return,240:360:dwell"\nlift = 30.0\n')
    segments = ('[mechanisms.weft_returner.law]\nsegments = [{to_deg = 40, shape = "dwell"}, {to_deg = 110, shape = '
                '"inclined_sine", to_mm = 30.0}, {to_deg = 170, shape = "dwell"}, {to_deg = 240, shape = '
                '"inclined_sine", to_mm = 0.0}, {to_deg = 360, shape = "dwell"}]\n')
    assert standard in text
    scene = tmp_path / "loom_segments.toml"
    scene.write_text(text.replace(standard, segments))
    reports = []
    for path, out in ((SAMPLES / "scenes" / "loom_group1.toml", "std"), (scene, "seg")):
        result = cli("profile", path, "--no-plots", "--json", "-o", tmp_path / out)
        assert result.code == 0, result.err
        reports.append(result.json())
    ours, theirs = reports[1], reports[0]
    assert ours["cyclogram"]["makespan_deg"] == pytest.approx(theirs["cyclogram"]["makespan_deg"], abs=1e-9)
    assert ours["mechanisms"]["weft_returner"]["retimed_by_cyclogram"] == \
        theirs["mechanisms"]["weft_returner"]["retimed_by_cyclogram"]
    for label in ("rise", "return"):
        mine, other = (r["mechanisms"]["weft_returner"]["phase_limits"][label] for r in (ours, theirs))
        for source in ("pressure angle", "undercut", "contact stress"):
            assert mine[source] == pytest.approx(other[source], abs=1e-8), (label, source)


@pytest.mark.reference("property", "profile --segments gives the law described; with --phases it is refused")
def test_profile_takes_segments_on_the_command_line(cli, tmp_path):
    text = ",".join(f"{start:g}:{spec.to_deg:g}:{spec.shape}" + (f":{spec.to_mm:g}" if spec.to_mm is not None else "")
                    + (":v_end=match" if spec.v_end == "match" else "")
                    for start, spec in zip([0, *[s.to_deg for s in FILLING[:-1]]], FILLING))
    result = cli("profile", "--segments", text, "--no-plots", "--json", "-o", tmp_path)
    assert result.code == 0, result.err
    assert result.json()["law"]["notes"][0].startswith("segment law: dwell 0-60, poly5 60-140 to 12 mm")
    refused = cli("profile", "--segments", text, "--lift", "3", "--no-plots", "-o", tmp_path)
    assert refused.code == 2 and "--segments give the whole law" in refused.err
