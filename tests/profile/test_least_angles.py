"""Least phase angles bound by the follower's geometry: the pressure angle, the roller's undercut, the flat face's cusp.

At the least angle ``profile`` reports, the cam built with that angle (the next dwell taking up the change, as the
search stretches it) has no undercut and meets its pressure-angle limit within the root tolerance; a hair shorter
it breaks the limit that binds — so the angle is the least, not the search's bracket.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import camcad
from camcad.law.standard import shape_named
from camcad.scene.default import default_tables
from camcad.scene.file import scene_from_dict
from camcad.scene.mechanism import law_with_phases, phases_deg, stretched_phase
from camcad.scene.pipeline import PipelineOptions, analyse_scene

#: the pressure-angle limits aim 1e-6 deg inside; the root is found to 1e-10 deg
PRESSURE_TOLERANCE_DEG = 1e-6


def _run(follower: dict, law: dict | None = None):
    tables = default_tables()
    tables["follower"] = follower
    if law is not None:
        tables["law"] = law
    scene = scene_from_dict(tables, Path("least"), from_file=False)
    result = analyse_scene(scene, PipelineOptions(plots=()))
    run = next(iter(result.runs.values()))
    return result.report, run.law


def _built_at(law, index: int, width_deg: float, follower: camcad.Follower):
    phases = phases_deg(law)
    stretched, (start, end) = stretched_phase(phases, index, width_deg)
    cam_law = law_with_phases(law, stretched, "test")
    return camcad.synthesize(cam_law, follower, camcad.ProfileSettings(plots=False, design=False)), (start, end)


def _phase_pressure_max(result, start: float, end: float) -> float:
    theta = np.radians(np.linspace(start, end, 20001))
    return float(np.degrees(np.max(np.abs(result.geometry.pressure_angle(theta)))))


ROLLERS = [  # (Rb, Rr): which limit binds differs by phase
    (100.0, 30.0),
    (200.0, 40.0),
    (50.0, 10.0),
]


@pytest.mark.reference("property", "the profile's own undercut and pressure-angle checks at the least angle and a "
                                   "hair below it")
@pytest.mark.parametrize("rb, rr", ROLLERS)
def test_roller_at_its_least_angles_neither_undercuts_nor_breaks_the_pressure_limit(rb, rr):
    report, law = _run({"type": "roller", "base_radius": rb, "roller_radius": rr,
                        "pressure_angle_limit_rise": 30.0, "pressure_angle_limit_return": 45.0})
    follower = camcad.Follower("roller", base_radius=rb, roller_radius=rr)
    limits = {"rise": 30.0, "return": 45.0}
    for index, label in ((0, "rise"), (2, "return")):
        sources = report["phase_limits"][label]
        least = sources["least_deg"]
        result, (start, end) = _built_at(law, index, least, follower)
        assert not result.undercut, (rb, rr, label, result.undercut_reasons)
        assert _phase_pressure_max(result, start, end) <= limits[label] + PRESSURE_TOLERANCE_DEG
        # a hair shorter, the binding limit breaks: the angle is the least one
        shorter, (s0, s1) = _built_at(law, index, least - 0.05, follower)
        binding = [k for k, v in sources.items() if k != "least_deg" and v == least]
        if binding == ["undercut"]:
            assert shorter.undercut
        else:
            assert binding == ["pressure angle"]
            assert _phase_pressure_max(shorter, s0, s1) > limits[label]


@pytest.mark.reference("regression", "issue 31: the pressure-angle-only least return angle (18.91 deg at Rb 100, "
                                     "Rr 30) makes the cam loop")
def test_the_pressure_angle_alone_would_make_the_cam_loop():
    report, law = _run({"type": "roller", "base_radius": 100.0, "roller_radius": 30.0})
    sources = report["phase_limits"]["return"]
    assert sources["undercut"] > sources["pressure angle"]
    result, _ = _built_at(law, 2, sources["pressure angle"], camcad.Follower("roller", base_radius=100.0,
                                                                          roller_radius=30.0))
    assert result.undercut            # what today's report gave: the cam undercuts
    assert sources["least_deg"] == sources["undercut"]


def _flat_least_by_hand(rb: float, lift: float, shape: str, beta_deg: float) -> float:
    """The least width t (deg) with Rb + s(u) + a(u)·(β/t)² ≥ 0 at every u: a dense grid of u and Brent's method on
    t, from the shape's f alone (s = h f, a at width t = h f''/t²)."""
    f = shape_named(shape)
    u = np.linspace(0.0, 1.0, 400001)
    s, second = lift * f.evaluate(u, 0), lift * f.evaluate(u, 2)

    def margin(t_deg: float) -> float:
        t = math.radians(t_deg)
        return float(np.min(rb + s + second / t**2))

    return brentq(margin, 1.0, beta_deg * 3, xtol=1e-12)


@pytest.mark.reference("second method", "the cusp condition Rb + s + a = 0 solved by Brent's method on a dense grid")
@pytest.mark.parametrize("rb", [60.0, 30.0])
def test_flat_face_least_angle_is_bound_by_the_cusp_condition_and_says_so(rb):
    report, law = _run({"type": "flat", "base_radius": rb})
    follower = camcad.Follower("flat", base_radius=rb)
    for index, label, shape in ((0, "rise", "cycloidal"), (2, "return", "poly345")):
        sources = report["phase_limits"][label]
        assert set(sources) == {"cusp", "least_deg"}          # no pressure angle: zero by construction
        least = sources["least_deg"]
        assert least == pytest.approx(_flat_least_by_hand(rb, 25.0, shape, 120.0), abs=1e-6)
        assert least > 12.0                                   # not the search's lower bracket (a tenth of 120 deg)
        assert not _built_at(law, index, least, follower)[0].undercut
        assert _built_at(law, index, least - 0.05, follower)[0].undercut
    assert any("cusp condition" in note for note in report["phase_limit_notes"])


@pytest.mark.reference("regression", "the least angles of the cams built at them in this file's other tests, printed "
                                     "to 6 digits")
def test_profile_prints_what_binds(cli, tmp_path):
    result = cli("profile", "--follower", "flat", "--rb", "60", "--no-plots", "-o", tmp_path)
    assert result.code == 0
    # printed rounded up (78.99842... -> 78.9985), so the printed angle given back still passes
    assert "least rise angle 78.9985 deg (bound by cusp 78.9985 deg)" in result.out
    assert "cusp condition Rb + s + a > 0" in result.out
    result = cli("profile", "--rb", "100", "--rr", "30", "--no-plots", "-o", tmp_path / "r")
    assert "least return angle 26.0777 deg (bound by undercut 26.0777 deg)" in result.out


@pytest.mark.reference("property", "a least angle read off the screen and given back as the phase angle passes the "
                                   "check that bound it (the printed figure is rounded up)")
def test_the_printed_least_angle_given_back_passes(cli, tmp_path):
    result = cli("profile", "--rb", "100", "--rr", "30", "--no-plots", "-o", tmp_path / "a")
    line = next(x for x in result.out.splitlines() if "least return angle" in x)
    printed = float(line.split("least return angle ")[1].split()[0])
    end = 180.0 + printed
    phases = f"0:120:rise,120:180:dwell,180:{end:.4f}:return,{end:.4f}:360:dwell"
    again = cli("profile", "--rb", "100", "--rr", "30", "--phases", phases, "--no-plots", "-o", tmp_path / "b")
    assert again.code == 0, again.out[-2000:]
