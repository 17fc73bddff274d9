"""`camcad linkage analyse --animate` (issue 32 item 1): the linkage alone moving over the follower's swing and
back, and a scene's cam, follower and linkage over a turn; the frames against closed forms and the linkage's own
analysis, the files written, and the options refused where they cannot apply."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from conftest import SAMPLES

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, Loop, analyse
from camcad.scene.animation import linkage_motion, sweep_angles
from camcad.scene.linkage_commands import LinkageSource, resolve

#: a crank-rocker-like four-bar after an oscillating follower (mm, deg): O (0, 0), C (100, 20)
OPTIONS = ["--links", "40,120,90", "--output-pivot", "100,20", "--input-angle", "80", "--swing", "30",
           "--sense", "-1"]


def _command(**extra):
    return resolve(LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1,
                                 **extra))


def _page_data(page: str) -> dict:
    return json.loads(re.search(r'<script type="application/json" id="camcad-animation-data">(.*?)</script>', page,
                                re.S).group(1))


@pytest.mark.reference("closed form", "the four-bar's loop closure: |OA|, |AB|, |CB| and the frame OC constant")
@pytest.mark.parametrize("step", [1.0, 0.5, 5.0])
def test_every_frame_closes_the_loop_and_turns_the_input_link_by_the_swing(step):
    command = _command(coupler_point="30,10")
    motion = linkage_motion(command.linkage, command.psi_max, step)
    j = motion.linkage.joints
    for (a, b), length in zip((("O", "A"), ("A", "B"), ("C", "B")), (40.0, 120.0, 90.0)):
        assert np.max(np.abs(np.hypot(*(j[a] - j[b]).T) - length)) < 1e-9, (a, b)
    assert np.max(np.abs(j["O"])) < 1e-12 and np.max(np.abs(j["C"] - [100.0, 20.0])) < 1e-12
    # the input link at 80 deg - psi (sense -1) at every frame
    angle = np.degrees(np.arctan2(j["A"][:, 1], j["A"][:, 0]))
    assert np.max(np.abs(angle - (80.0 - motion.input_deg))) < 1e-9
    # the coupler point rides on AB: 30 mm along it, 10 mm to its left
    ab = (j["B"] - j["A"]) / 120.0
    left = np.stack((-ab[:, 1], ab[:, 0]), axis=-1)
    assert np.max(np.abs(j["A"] + 30.0 * ab + 10.0 * left - j["P"])) < 1e-9


@pytest.mark.reference("second method", "the output link's angle atan2(B - C) from the frames against the "
                                        "analysis's Pi(psi) (Freudenstein's loop equation, its derivatives chained)")
def test_the_output_link_turns_as_the_analysis_says_at_the_same_swing():
    command = _command()
    motion = linkage_motion(command.linkage, command.psi_max, 1.0)
    bc = motion.linkage.joints["B"] - motion.linkage.joints["C"]
    turn = np.degrees(np.unwrap(np.arctan2(bc[:, 1], bc[:, 0])))
    geometric = command.linkage.output_sense * (turn - turn[0])
    assert np.max(np.abs(geometric - motion.output_deg)) < 1e-9
    up = motion.input_deg[: motion.count // 2 + 1]              # 0, 1, ..., 30 deg: the analysis's own grid
    result = analyse(command.linkage, command.psi_max, up.size)
    assert np.allclose(result.psi, np.radians(up), atol=1e-12)
    assert np.max(np.abs(np.degrees(result.pi) - geometric[: up.size])) < 1e-9
    # the transmission angle at B: the angle between the coupler and the output link
    ab = motion.linkage.joints["B"] - motion.linkage.joints["A"]
    cos_mu = np.einsum("ij,ij->i", ab, bc) / (120.0 * 90.0)
    mu = np.degrees(np.arccos(np.clip(cos_mu, -1, 1)))
    assert np.max(np.abs(np.minimum(mu, 180 - mu) - np.minimum(motion.linkage.transmission_deg[0],
                                                                 180 - motion.linkage.transmission_deg[0]))) < 1e-7


@pytest.mark.reference("closed form", "a parallelogram four-bar: the output turns with the input, Pi = psi")
def test_a_parallelogram_turns_its_output_with_its_input():
    lk = Linkage((Loop((0.0, 0.0), (50.0, 0.0), 20.0, 50.0, 20.0, -1),), theta0=math.radians(60.0))
    motion = linkage_motion(lk, math.radians(40.0), 2.0)
    assert np.max(np.abs(motion.output_deg - motion.input_deg)) < 1e-9


@pytest.mark.reference("closed form", "a there-and-back sweep of |span| at step h: 2 ceil(|span| / h) frames")
def test_the_sweep_goes_out_and_back_in_equal_steps():
    assert sweep_angles(30.0, 1.0).size == 60 and sweep_angles(25.0, 2.0).size == 26
    angles = sweep_angles(-25.0, 2.0)
    assert angles[13] == -25.0 and np.allclose(np.abs(np.diff(angles)), 25.0 / 13.0)
    for bad in (7.0, 0.0, float("nan")):
        with pytest.raises(CamcadError):
            sweep_angles(30.0, bad)
    with pytest.raises(CamcadError):
        sweep_angles(0.0, 1.0)


def test_analyse_writes_the_linkage_alone_with_its_other_files(cli, tmp_path):
    result = cli("linkage", "analyse", *OPTIONS, "--animate-format", "html,gif", "--animate-step", "2", "-o",
                 tmp_path, "--json")
    assert result.code == 0, result.err
    payload = result.json()
    assert payload["animation"]["frames"] == 30 and payload["animation"]["files"] == ["animation.html",
                                                                                      "animation.gif"]
    assert {str(tmp_path / "animation.html"), str(tmp_path / "animation.gif")} <= set(payload["outputs"])
    page = (tmp_path / "animation.html").read_text(encoding="utf-8")
    assert 'data-frames="30"' in page and "http" not in page
    data = _page_data(page)
    assert len(data["joints"]["B"][0]) == 30 and data["input"][15] == 30.0
    from PIL import Image

    with Image.open(tmp_path / "animation.gif") as gif:
        assert gif.n_frames == 30


def test_analyse_of_a_scene_animates_the_cam_with_its_linkage(cli, tmp_path):
    scene = SAMPLES / "scenes" / "batten_linkage.toml"
    result = cli("linkage", "analyse", scene, "--animate-step", "5", "--no-plots", "-o", tmp_path / "cam", "--json")
    assert result.code == 0, result.err
    assert result.json()["animation"]["frames"] == 72
    data = _page_data((tmp_path / "cam" / "animation.html").read_text(encoding="utf-8"))
    assert data["n"] == 72 and "working" in data and set(data["joints"]) >= {"O", "A", "B", "C"}
    result = cli("linkage", "analyse", scene, "--animate", "--no-cam", "--no-plots", "-o", tmp_path / "alone",
                 "--json")
    assert result.code == 0, result.err
    swing = result.json()["linkage"]["swing_deg"]
    assert result.json()["animation"]["frames"] == 2 * math.ceil(swing)


def test_the_options_are_refused_where_they_cannot_apply(cli, tmp_path):
    for args, word in ((["--animate-step", "7"], "divide"), (["--animate-format", "avi"], "avi"),
                       (["--animate-format", ","], "no animation format")):
        result = cli("linkage", "analyse", *OPTIONS, *args, "-o", tmp_path / "a")
        assert result.code == 2 and word in result.err and len(result.err.strip().splitlines()) == 1, args
        assert not (tmp_path / "a").exists()
    for command in ("adjust", "tune", "variator"):
        assert cli("linkage", command, "--animate").code == 2


def test_a_linkage_that_breaks_in_its_swing_is_not_animated_and_says_why(cli, tmp_path):
    result = cli("linkage", "analyse", "--links", "40,120,30", "--output-pivot", "100,20", "--input-angle", "80",
                 "--swing", "30", "--sense", "-1", "--animate", "--no-plots", "-o", tmp_path, "--json")
    assert result.code == 1, result.err
    assert "does not close" in result.json()["animation"]["skipped"]
    text = cli("linkage", "analyse", "--links", "40,120,30", "--output-pivot", "100,20", "--input-angle", "80",
               "--swing", "30", "--sense", "-1", "--animate", "--no-plots", "-o", tmp_path / "text")
    assert "animation      not written" in text.out
    assert not (tmp_path / "animation.html").exists()
