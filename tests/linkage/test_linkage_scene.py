"""The [linkage] scene section through the pipeline: the constant ratio as the special case Π = kψ, the cam
designed for the working member (law_of = "output"), every setting of [linkage.adjust], and bad input."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from camcad.errors import CamcadError
from camcad.scene.pipeline import analyse_scene

ROOT = Path(__file__).resolve().parents[2]
SHUTTLE = (ROOT / "samples" / "scenes" / "shuttle_lift.toml").read_text()


def _without(text: str, section: str) -> str:
    return re.sub(rf"\n\[{section}\].*?(?=\n\[|\Z)", "\n", text, flags=re.DOTALL)


def _compare(a, b, path=""):
    """Every figure of two reports equal within 1e-12 relative (rounding), every other value equal;
    returns the keys only one of them has."""
    extra = []
    if isinstance(a, dict):
        for key in set(a) | set(b):
            if key not in a or key not in b:
                extra.append(f"{path}/{key}")
            else:
                extra += _compare(a[key], b[key], f"{path}/{key}")
    elif path == "/models_run":
        assert [m for m in b if m != "linkage"] == a
    elif isinstance(a, list) and not isinstance(b, str):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            extra += _compare(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-300), path
    elif path != "/scene":
        assert a == b, path
    return extra


@pytest.mark.reference("second method", "the same scene with [stops] ratio = 1.5: every figure within 1e-12")
def test_a_table_of_k_psi_gives_the_report_of_ratio_k(tmp_path):
    """[stops] ratio = 1.5 against [linkage] type = "table" with Π = 1.5ψ (and [stops] ratio left at its
    default 1): the same report — every figure within 1e-12 relative — plus the linkage's own entries."""
    # without [stops.published]: its errors (camcad − published) cancel to a few digits, not the point here
    base = _without(_without(SHUTTLE, "dynamics"), r"stops\.published").replace("lift = 11.12 ", "lift = 7.4133 ")
    ratio = base.replace('stop = "upper"', 'stop = "upper"\nratio = 1.5')
    rows = ", ".join(f"[{x:g}, {1.5 * x!r}]" for x in range(13))
    table = base.replace("[stops]", f'[linkage]\ntype = "table"\ninput_unit = "mm"\noutput_unit = "mm"\n'
                                    f"table = [{rows}]\n\n[stops]")
    (tmp_path / "ratio.toml").write_text(ratio)
    (tmp_path / "table.toml").write_text(table)
    a = analyse_scene(tmp_path / "ratio.toml").report
    b = analyse_scene(tmp_path / "table.toml").report
    extra = _compare(a, b)
    assert sorted(extra) == ["/checks_by_model/linkage", "/linkage"]
    assert a["impact"]["rebound_mm"][0] == pytest.approx(b["impact"]["rebound_mm"][0], rel=1e-12)


BATTEN = (ROOT / "samples" / "scenes" / "batten_linkage.toml").read_text()


def _light_batten(tmp_path: Path, settings: str | None = None) -> Path:
    text = _without(_without(BATTEN, "contact"), "dynamics")
    if settings is not None:
        text = re.sub(r"settings = \[.*?\]", f"settings = [{settings}]", text, flags=re.DOTALL)
    path = tmp_path / "batten.toml"
    path.write_text(text)
    return path


@pytest.mark.reference("property", "the round trip through Pi within 1e-12 rad; the stroke 24.12 deg; psi2 constant "
                                   "over the settings")
def test_law_of_output_designs_the_cam_for_the_working_member(tmp_path):
    """The [law] is the batten's: the profile's follower law is Π⁻¹(y), and y through Π comes back to the law
    (round trip ≤ 1e-12 rad over the cycle); the settings are reported with ψ₂ (beat-up) constant."""
    result = analyse_scene(_light_batten(tmp_path, "-148.1849311344786, -153.9785415411006"))
    report = result.report["linkage"]
    assert report["law_of"] == "output"
    assert report["working_member"]["round_trip_max"] <= 1e-12
    # the stroke over the cycle is sampled (4097 points): it meets the law's 24.12 deg to the sampling
    assert report["working_member"]["stroke"] == pytest.approx(math.radians(24.12), rel=1e-7)
    rows = report["settings"]["rows"]
    assert [round(r["swing_deg"], 9) for r in rows] == [20.0, 28.0]
    assert max(abs(r["psi2_deg"] - 24.12) for r in rows) < 1e-9
    assert report["settings"]["governing"]["transmission_angle"]["setting"] in (-148.1849311344786,
                                                                                -153.9785415411006)
    assert result.report["checks_by_model"]["linkage"] is True


@pytest.mark.reference("second method", "the plain law in rad through the dynamics: the same figures to 1e-9")
def test_dynamics_runs_on_the_working_member(tmp_path):
    """With law_of = output the dynamics sees y = Π(Π⁻¹(y_law)): the same figures as the plain law in rad."""
    from camcad.dynamics.runs import run_dynamics
    from camcad.law.standard import compose
    from camcad.profile.scaled_law import ScaledLaw
    from camcad.scene.sections.dynamics import parse_dynamics

    text = _without(BATTEN, "contact")
    text = re.sub(r"\n\[linkage\.adjust\].*?(?=\n\[dynamics\])", "\n", text, flags=re.DOTALL)
    path = tmp_path / "dyn.toml"
    path.write_text(text)
    report = analyse_scene(path).report["dynamics"]
    law = ScaledLaw(compose([("dwell", 100.0), ("rise", 64.0), ("return", 64.0), ("dwell", 132.0)], 24.12,
                            "harmonic"), math.pi / 180)
    settings = parse_dynamics({"output_unit": "rad", "natural_frequency_hz": 113.0, "psi": 0.3, "mass_kg": 1.2,
                               "allowed_peak_accel_ratio": 2.5}, "x", 360.0)
    direct = run_dynamics(law, settings, [330.0, 375.0, 420.0]).to_dict()
    for key in ("peak_accel_ratio", "dynamic_error_max_rad"):     # a swing law: its error is in rad
        assert np.allclose(report[key], direct[key], rtol=1e-9, atol=0)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace('law_of = "output"', 'law_of = "output"').replace("[linkage]", "[linkagex]"),
     "unknown section"),
    (lambda t: t.replace("input_link = 90.0", "input_lnk = 90.0"), "did you mean 'input_link'"),
    (lambda t: t.replace("input_angle = 103.4", "input_angle = 103.4\ninput_offset = 10.0"), "both place"),
    (lambda t: t.replace("coupler = 300.17", "coupler = 150.0"), "does not close|dead point|limit position"),
    (lambda t: re.sub(r"\n(pivot|arm) = .*", "", t.replace('type = "oscillating"', 'type = "roller"')),
     "driven by a rocker"),
    (lambda t: t.replace("[follower]", "[follower]\nswing = 20.0"), "sets the follower's swing"),
    (lambda t: re.sub(r"\n\[linkage\].*?(?=\n\[dynamics\])", "\n", t, flags=re.DOTALL), "there is no \\[linkage\\]"),
    (lambda t: t.replace('output_unit = "rad"               # the batten', 'output_unit = "mm"   # the batten'),
     "output_unit"),
    (lambda t: t.replace('joint = "A"', 'joint = "Q"'), "cannot be a joint"),
    (lambda t: t.replace("branch = -1", "branch = 0"), "must be \\+1 or -1"),
])
def test_bad_linkage_sections_are_one_line_errors(tmp_path, edit, message):
    path = tmp_path / "bad.toml"
    path.write_text(edit(BATTEN))
    with pytest.raises(CamcadError, match=message) as err:
        analyse_scene(path)
    from camcad.cli.common import _one_line

    text = err.value.message()
    assert "\n" not in text and len(_one_line(text)) < 300


@pytest.mark.reference("closed form", "the table turns back at swing 45 deg (Pi' = 0): refused naming it")
def test_a_non_monotone_position_function_is_refused_with_the_dead_point_angle(tmp_path):
    """A table that turns back inside the needed swing: law_of = output refuses it, naming the swing angle
    of the limit position (Π' = 0)."""
    text = _without(_without(_without(BATTEN, "contact"), "dynamics"), "linkage.adjust")
    rows = ", ".join(f"[{x:g}, {30.0 * math.sin(math.radians(x) * 2.0)!r}]" for x in range(0, 61, 2))
    text = re.sub(r"\n\[linkage\].*?(?=\Z)", f'\n[linkage]\ntype = "table"\ninput_unit = "deg"\noutput_unit = "deg"\n'
                                            f"table = [{rows}]\n", text, flags=re.DOTALL)
    path = tmp_path / "bump.toml"
    path.write_text(text)
    with pytest.raises(CamcadError, match=r"dead point \(limit position, Pi' = 0\) at swing 45 deg"):
        analyse_scene(path)
