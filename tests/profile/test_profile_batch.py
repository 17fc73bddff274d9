"""Many followers on one law at once (camcad.profile.batch) and the sweep's batch of designs (camcad.sweep.batch).

The batch must give every follower exactly what ``synthesize`` gives it alone: the same report, check by check
(a second run of the same figures by another route: arrays over followers × angles instead of one follower's
angles). Speed is measured by ``camcad bench``, not here.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camcad.law.standard import compose
from camcad.profile import default_design
from camcad.profile.batch import supports, synthesize_many
from camcad.profile.followers import Follower
from camcad.profile.summary import profile_report
from camcad.profile.synth import ProfileSettings, synthesize

SETTINGS = ProfileSettings(plots=False, design=False, checks_only=True)


@pytest.mark.reference("second method", "synthesize, one follower at a time")
def test_a_batch_of_followers_gives_each_the_report_synthesize_gives_it():
    _, law, base = default_design()
    followers = [replace(base, base_radius=rb, roller_radius=rr, offset=e)
                 for rb in (30.0, 45.0, 60.0) for rr in (5.0, 14.0) for e in (0.0, 3.0)]
    followers += [replace(base, pressure_angle_limit_rise_deg=15.0, rho_min=40.0)]   # failed limits
    many = synthesize_many(law, followers, SETTINGS)
    for follower, batched in zip(followers, many):
        alone = synthesize(law, follower, SETTINGS)
        assert batched is not None
        assert profile_report(batched) == profile_report(alone)
        assert np.array_equal(batched.profile.polyline.points, alone.profile.polyline.points)
        assert batched.notes == alone.notes
    assert not all(r.passed for r in many if r is not None)


@pytest.mark.reference("second method", "synthesize, one follower at a time")
def test_undercut_followers_in_a_batch_are_found_as_synthesize_finds_them():
    # a short rise: the pitch curve's nose is sharper than a large roller, the profile loops
    law = compose([("rise", 40), ("dwell", 140), ("return", 40), ("dwell", 140)], 25.0, "cycloidal", "poly345")
    followers = [Follower("roller", rb, rr) for rb, rr in ((20.0, 15.0), (30.0, 25.0), (60.0, 5.0))]
    for follower, batched in zip(followers, synthesize_many(law, followers, SETTINGS)):
        alone = synthesize(law, follower, SETTINGS)
        assert batched is not None and profile_report(batched) == profile_report(alone)
        assert batched.undercut_reasons == alone.undercut_reasons
    assert [synthesize(law, f, SETTINGS).undercut for f in followers] == [True, True, False]


@pytest.mark.reference("second method", "synthesize, one follower at a time")
def test_a_clockwise_cam_and_a_reversible_follower_batch_too():
    law = compose([("rise", 100), ("dwell", 80), ("return", 100), ("dwell", 80)], 18.0, "cycloidal", "poly345")
    followers = [Follower("roller", rb, 8.0, offset=-4.0, cw=True, reversible=True) for rb in (35.0, 50.0)]
    for follower, batched in zip(followers, synthesize_many(law, followers, SETTINGS)):
        assert profile_report(batched) == profile_report(synthesize(law, follower, SETTINGS))


@pytest.mark.reference("property", "the batch refuses what it does not compute and leaves it to synthesize")
def test_the_batch_takes_only_what_it_supports():
    _, law, base = default_design()
    assert supports([base], SETTINGS)
    assert not supports([base], ProfileSettings(plots=False))                       # a written pitch curve
    assert not supports([replace(base, groove=True)], SETTINGS)
    assert not supports([base, replace(base, cw=True)], SETTINGS)
    flat = Follower("flat", 50.0)
    assert not supports([flat], SETTINGS)
    with pytest.raises(ValueError):
        synthesize_many(law, [flat], SETTINGS)


@pytest.mark.reference("second method", "the scene pipeline, one design at a time (evaluate_design)")
def test_a_sweep_over_follower_dimensions_gives_the_rows_of_one_design_at_a_time():
    from camcad.scene.default import default_tables
    from camcad.sweep.batch import batch_keys, groups
    from camcad.sweep.evaluate import evaluate_chunk, evaluate_design, make_task, prepared

    vary = ["follower.base_radius=14:50:6", "follower.roller_radius=6,12", "law.phases.rise=100,120"]
    task = make_task(default_tables(), "built-in default", None, vary, None, 0)
    prep = prepared(task)
    assert batch_keys(prep) == {"follower.base_radius", "follower.roller_radius"}
    assert len(groups(prep, list(range(prep.space.size)))) == 2          # one law per rise angle
    rows = evaluate_chunk(task, 0, 0, prep.space.size).rows
    assert [r["design"] for r in rows] == list(range(prep.space.size))
    for design in range(prep.space.size):
        alone = evaluate_design(prep, design)
        batched = rows[design]
        for key, value in alone.items():
            other = batched[key]
            assert value == other or (isinstance(value, float) and math.isnan(value) and math.isnan(other)), key
    assert {r["feasible"] for r in rows} == {True, False}
