"""The mechanism in motion (issue 32): the frames the library computes, against closed-form geometry, for
every follower type, the linkage after the follower, and the files written from them."""

from __future__ import annotations

import json
import math
import re
import shutil

import numpy as np
import pytest
from conftest import SAMPLES

import camcad
from camcad.errors import CamcadError
from camcad.linkage.analysis import analyse
from camcad.profile.animation import cam_frames, frame_angles
from camcad.profile.followers import arm_angle_on_base_circle
from camcad.scene.animation import mechanism_frames
from camcad.scene.pipeline import PipelineOptions, analyse_scene

LAW = [("rise", 100), ("dwell", 80), ("return", 100), ("dwell", 80)]
SETTINGS = camcad.ProfileSettings(plots=False, design=False)


def _cam(follower: camcad.Follower, lift: float = 20.0):
    law = camcad.compose(LAW, lift)
    return camcad.synthesize(law, follower, SETTINGS)


def _distance_to_polyline(point: np.ndarray, curve: np.ndarray) -> float:
    """Least distance (mm) from ``point`` to the closed polyline ``curve``."""
    a, b = curve, np.roll(curve, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - point).T)))


def _on_the_cam(frames, points: np.ndarray, curve: np.ndarray, every: int = 7) -> float:
    """Largest distance of ``points`` (one per frame) from the cam ``curve`` turned to its frame."""
    return max(_distance_to_polyline(points[k], frames.cam_points(curve, k)) for k in range(0, frames.count, every))


@pytest.mark.reference("closed form", "translating roller: centre (e, d + s), d = sqrt(Rp^2 - e^2), docs/INTERFACE.md")
@pytest.mark.parametrize("offset, cw", [(0.0, False), (12.0, False), (-8.0, True)])
def test_translating_roller_follows_its_axis_and_touches_the_turned_profile(offset, cw):
    follower = camcad.Follower("roller", base_radius=45.0, roller_radius=12.0, offset=offset, cw=cw)
    result = _cam(follower)
    frames = cam_frames(result)
    assert frames.count == 360 and frames.theta_deg[1] == 1.0
    law = result.law.kinematics(np.radians(frames.theta_deg))
    d = math.sqrt(57.0**2 - offset**2)
    assert np.allclose(frames.centre[:, 0], offset, atol=1e-12)
    assert np.allclose(frames.centre[:, 1], d + law.s, atol=1e-9)
    assert np.allclose(frames.cam_turn_deg, (-1.0 if cw else 1.0) * frames.theta_deg, atol=1e-12)
    assert np.allclose(np.hypot(*(frames.centre - frames.contact).T), 12.0, atol=1e-9)
    # the contact lies on the written profile turned with the cam (chord tolerance 1 µm)
    assert _on_the_cam(frames, frames.contact, frames.profile) < 2e-3
    # pressure angle: the angle of the common normal from the axis is atan((v - sigma e)/(d + s)) (docs/INTERFACE.md)
    sigma = -1.0 if cw else 1.0
    expected = np.degrees(np.arctan((law.v - sigma * offset) / (d + law.s)))
    assert np.allclose(frames.pressure_angle_deg, expected, atol=1e-9)
    tilt = np.degrees(np.arctan2(-sigma * frames.normal[:, 0], frames.normal[:, 1]))
    assert np.allclose(np.abs(tilt), np.abs(expected), atol=1e-9)


@pytest.mark.reference("closed form", "a disc rolling on a circle turns by -theta Rb/Rr relative to the fixed frame")
@pytest.mark.parametrize("cw", [False, True])
def test_the_roller_rolls_against_the_cam_at_the_ratio_of_the_radii_on_a_dwell(cw):
    follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, cw=cw)
    frames = cam_frames(_cam(follower))
    sigma = -1.0 if cw else 1.0
    # the near dwell 280..360 deg: the pitch curve is the circle Rp = 50 mm, the profile the base circle
    k0, k1 = 285, 355
    turned = frames.roller_turn_deg[k1] - frames.roller_turn_deg[k0]
    assert turned == pytest.approx(-sigma * (k1 - k0) * 40.0 / 10.0, rel=1e-9)
    # over one whole turn the roller turns by sigma (360 - S/Rr), S the pitch curve's length
    pitch = np.asarray(frames.pitch)
    length = float(np.sum(np.hypot(*(np.roll(pitch, -1, axis=0) - pitch).T)))
    whole = frames.roller_turn_deg[-1] + (frames.roller_turn_deg[-1] - frames.roller_turn_deg[-2])
    assert whole == pytest.approx(sigma * (360.0 - math.degrees(length / 10.0)), rel=2e-4)


@pytest.mark.reference("closed form", "oscillating roller: B = A + L(-cos g, sin g), g = g0 + psi")
def test_oscillating_roller_swings_on_its_arm_and_touches_the_profile():
    follower = camcad.Follower("oscillating", base_radius=40.0, roller_radius=10.0, pivot=110.0, arm=80.0)
    law = camcad.compose(LAW, math.radians(20.0))
    result = camcad.synthesize(law, follower, SETTINGS)
    frames = cam_frames(result)
    psi = result.law.kinematics(np.radians(frames.theta_deg)).s
    gamma = arm_angle_on_base_circle(result.follower) + psi
    expected = np.stack((110.0 - 80.0 * np.cos(gamma), 80.0 * np.sin(gamma)), axis=-1)
    assert frames.pivot == (110.0, 0.0)
    assert np.allclose(frames.centre, expected, atol=1e-9)
    assert np.allclose(np.hypot(*(frames.centre - np.array(frames.pivot)).T), 80.0, atol=1e-9)
    assert _on_the_cam(frames, frames.contact, frames.profile) < 2e-3


@pytest.mark.reference("closed form", "flat face: contact (sigma v, Rb + s) on the face; knife: the tip")
def test_flat_face_and_knife_edge_touch_where_the_closed_forms_say():
    flat = _cam(camcad.Follower("flat", base_radius=50.0), lift=15.0)
    frames = cam_frames(flat)
    law = flat.law.kinematics(np.radians(frames.theta_deg))
    assert np.allclose(frames.contact, np.stack((law.v, 50.0 + law.s), axis=-1), atol=1e-9)
    assert np.allclose(frames.centre[:, 1], 50.0 + law.s, atol=1e-9)
    assert np.all(frames.pressure_angle_deg == 0.0) and np.all(frames.roller_turn_deg == 0.0)
    assert _on_the_cam(frames, frames.contact, frames.profile) < 2e-3
    knife = cam_frames(_cam(camcad.Follower("knife", base_radius=50.0, offset=5.0)))
    assert knife.kind == "knife" and knife.roller_radius == 0.0
    assert np.allclose(knife.contact, knife.centre, atol=1e-12)
    assert _on_the_cam(knife, knife.contact, knife.profile) < 2e-3


@pytest.mark.reference("closed form", "conjugate pair: the second roller pair_distance below the first on the axis")
def test_the_second_roller_of_a_pair_and_the_groove_flank_touch_their_curves():
    follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, pair_distance=150.0)
    frames = cam_frames(_cam(follower))
    assert np.allclose(frames.second_centre, frames.centre - np.array([0.0, 150.0]), atol=1e-9)
    assert np.allclose(np.hypot(*(frames.second_centre - frames.second_contact).T), 10.0, atol=1e-9)
    assert _on_the_cam(frames, frames.second_contact, frames.counter) < 2e-3
    dwell = frames.second_roller_turn_deg[355] - frames.second_roller_turn_deg[285]
    rp2 = float(np.hypot(*frames.second_centre[300]))     # the second roller's circle on the dwell
    assert dwell == pytest.approx(-70.0 * (rp2 - 10.0) / 10.0, rel=1e-6)
    groove = cam_frames(_cam(camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, groove=True)))
    far = groove.centre + 10.0 * groove.normal          # the roller's far side touches the outer flank
    assert _on_the_cam(groove, far, groove.outer) < 2e-3
    swing = cam_frames(camcad.synthesize(camcad.compose(LAW, math.radians(15.0)), camcad.Follower(
        "oscillating", base_radius=40.0, roller_radius=10.0, pivot=110.0, arm=80.0, pair_angle_deg=70.0), SETTINGS))
    assert np.allclose(np.hypot(*(swing.second_centre - np.array(swing.pivot)).T), 80.0, atol=1e-9)
    assert _on_the_cam(swing, swing.second_contact, swing.counter) < 2e-3


@pytest.mark.reference("property", "link lengths are constant and the input link is rigid with the follower's arm")
def test_the_linkage_after_the_follower_keeps_its_links_and_turns_the_working_member():
    result = analyse_scene(SAMPLES / "scenes" / "batten_linkage.toml", PipelineOptions(plots=(), models=("profile",
                                                                                                        "linkage")))
    run = result.runs["batten_linkage"]
    frames = mechanism_frames(run)
    joints = frames.linkage.joints
    for a, b, _ in frames.linkage.links:
        length = np.hypot(*(joints[a] - joints[b]).T)
        assert np.ptp(length) < 1e-9 * length[0], (a, b)
    assert np.allclose(joints["O"], np.array(frames.cam.pivot), atol=1e-12)
    arm = frames.cam.centre - np.array(frames.cam.pivot)
    link = joints["A"] - joints["O"]
    between = np.unwrap(np.arctan2(link[:, 1], link[:, 0]) - np.arctan2(arm[:, 1], arm[:, 0]))
    assert np.ptp(between) < 1e-9
    # the working member's stroke: the linkage's own analysis over the follower's swing (a second route)
    analysis = analyse(run.linkage.linkage, float(np.max(frames.cam.s)))
    assert math.degrees(np.ptp(frames.working)) == pytest.approx(math.degrees(analysis.stroke), abs=1e-3)
    assert frames.working_unit == "rad" and frames.working[0] == 0.0


def test_frame_steps_must_divide_the_turn():
    assert len(frame_angles(2.0)) == 180 and frame_angles(0.5)[1] == 0.5
    for bad in (7.0, 0.0, -1.0, float("nan"), 100.0):
        with pytest.raises(CamcadError):
            frame_angles(bad)


def test_the_cli_refuses_a_step_or_format_it_cannot_make(cli, tmp_path):
    result = cli("profile", "--animate-step", "7", "-o", tmp_path / "a", "--no-plots")
    assert result.code == 2 and "divide" in result.err and len(result.err.splitlines()) == 1
    result = cli("profile", "--animate-format", "avi", "-o", tmp_path / "b", "--no-plots")
    assert result.code == 2 and "avi" in result.err
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_the_animation_page_is_self_contained_and_holds_every_frame(cli, tmp_path):
    result = cli("profile", "--animate", "--animate-step", "2", "--no-plots", "-o", tmp_path / "out", "--json")
    assert result.code == 0, result.err
    page = (tmp_path / "out" / "animation.html").read_text(encoding="utf-8")
    assert 'data-frames="180"' in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", page) and "@import" not in page
    data = json.loads(re.search(r'<script type="application/json" id="camcad-animation-data">(.*?)</script>', page,
                                re.S).group(1))
    assert data["n"] == 180 and len(data["cx"]) == 180 and data["theta"][1] == 2.0
    assert result.json()["animation"] == {"files": ["animation.html"], "frames": 180, "step_deg": 2.0}


def test_a_gif_and_an_mp4_of_the_mechanism(cli, tmp_path):
    kinds = "html,gif,mp4" if shutil.which("ffmpeg") else "html,gif"
    result = cli("profile", "--animate-format", kinds, "--animate-step", "30", "--no-plots", "-o", tmp_path)
    assert result.code == 0, result.err
    from PIL import Image

    with Image.open(tmp_path / "animation.gif") as gif:
        assert gif.n_frames == 12
    if "mp4" in kinds:
        head = (tmp_path / "animation.mp4").read_bytes()[:64]
        assert b"ftyp" in head
