"""One machine, whatever the command: every stand-alone analysis of a scene gives the figures ``camcad profile``
reports for the same scene (report.json), to 1e-9 relative.

The reference is ``camcad profile``'s report.json; the property tested is that the commands compute the same
machine (the [linkage] with ``law_of = "output"``, the working member's inertia through Π, the law's unit, the
[filter]ed law, the cyclogram's phase angles). Where a figure's unit decides whether a design passes, the figure is
also checked against a closed form written here (the batten's rigid acceleration in rad/s²).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import pytest
from conftest import SAMPLES

#: the sample scenes with a model a stand-alone command computes (a scene of a law and a follower has none)
#: (a machine scene of several groups is camcad machine's: its groups are group scenes like these)
SCENES = sorted(path for path in (SAMPLES / "scenes").glob("*.toml")
                if any(f"{section}]" in path.read_text() for section in ("dynamics", "stops", "contact", "filter",
                                                                          "cyclogram"))
                and "[groups." not in path.read_text())
REL = 1e-9


def _toml(data: dict) -> str:
    """A scene dict as TOML (the values the samples use: numbers, text, lists, tables)."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, float) and math.isinf(v):
            return "inf" if v > 0 else "-inf"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines: list[str] = []

    def table(prefix: str, data: dict) -> None:
        scalars = {k: v for k, v in data.items() if not isinstance(v, dict) and not (
            isinstance(v, list) and v and all(isinstance(x, dict) for x in v))}
        if prefix:
            lines.append(f"[{prefix}]")
        lines.extend(f"{k} = {value(v)}" for k, v in scalars.items())
        for k, v in data.items():
            if isinstance(v, dict):
                table(f"{prefix}.{k}" if prefix else k, v)
            elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                for item in v:
                    lines.append(f"[[{prefix}.{k}]]" if prefix else f"[[{k}]]")
                    lines.extend(f"{kk} = {value(vv)}" for kk, vv in item.items())

    table("", data)
    return "\n".join(lines) + "\n"


def _close(a, b, path=""):
    """Every number of ``a`` equals the one in ``b`` at the same key, to REL relative."""
    if isinstance(a, dict):
        for key in a:
            assert key in b, f"{path}/{key} missing"
            _close(a[key], b[key], f"{path}/{key}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, (int, float)) and not isinstance(b, bool):
        assert b == pytest.approx(a, rel=REL, abs=1e-300), f"{path}: {a} against {b}"
    else:
        assert a == b, f"{path}: {a!r} against {b!r}"


def _profile(cli, scene: Path, out: Path) -> dict:
    done = cli("profile", scene, "-o", out, "--no-plots")
    assert done.code in (0, 1), done.err
    return json.loads((out / "report.json").read_text())


def _mechanisms(report: dict) -> dict:
    return report["mechanisms"] if "mechanisms" in report else {report["name"]: report}


FIGURES = {
    "contact": ("sigma_max_MPa", "at_deg", "safety_factor", "rpm", "separation", "phase_limit_deg"),
    "impact": ("rebound_mm", "force_N", "impulse_Ns", "f_free_hz", "f_stop_hz", "phase_limit_deg"),
}


def _dynamics_figures(obj: dict) -> dict:
    return {k: v for k, v in obj.items() if k.startswith(("peak_accel", "dynamic_error_max", "residual_vibration"))
            and k != "residual_vibration_phases"}


def _commands_agree(cli, scene: Path, tmp_path: Path) -> int:
    """Run contact, dynamics, impact and spectrum on every mechanism the scene analyses with them; compare
    with profile's report.json. Returns the number of figures compared."""
    report = _profile(cli, scene, tmp_path / "profile")
    compared = 0
    for name, mech in _mechanisms(report).items():
        pick = ["--mechanism", name] if "mechanisms" in report else []
        for command in ("dynamics", "impact"):
            if command not in mech:
                continue
            done = cli(command, scene, *pick, "--json", "--no-plots", "-o", tmp_path / f"{command}-{name}")
            assert done.code in (0, 1), done.err
            got = done.json()[command]
            want = _dynamics_figures(mech[command]) if command == "dynamics" else \
                {k: mech[command][k] for k in FIGURES[command] if k in mech[command]}
            assert want, (command, name)
            _close(want, got, f"{scene.name} {name} {command}")
            compared += len(want)
        if "spectrum" in mech:
            done = cli("spectrum", scene, *pick, "--json", "--no-plots", "-o", tmp_path / f"spectrum-{name}")
            assert done.code in (0, 1), done.err
            got = done.json()["spectrum"]
            keys = [k for k in mech["spectrum"] if k.startswith(("max_deviation", "dwell_deviation", "lift",
                                                                "closure_gap", "peak_accel_ratio"))]
            _close({k: mech["spectrum"][k] for k in keys}, got, f"{scene.name} {name} spectrum")
            assert got["removed"] == mech["spectrum"]["removed"]
            compared += len(keys)
    contacts = {name: mech["contact"] for name, mech in _mechanisms(report).items() if "contact" in mech}
    if contacts:
        done = cli("contact", scene, "--json", "--no-plots", "-o", tmp_path / "contact")
        assert done.code in (0, 1), done.err
        got = done.json()["contact"]["mechanisms"]
        for name, want in contacts.items():
            _close({k: want[k] for k in FIGURES["contact"]}, got[name], f"{scene.name} {name} contact")
            compared += len(FIGURES["contact"])
    if "cyclogram" in report:
        done = cli("cyclogram", scene, "--json", "--no-plots", "-o", tmp_path / "cyclogram")
        assert done.code in (0, 1), done.err
        got = done.json()["cyclogram"]
        _close({k: report["cyclogram"][k] for k in ("makespan_deg", "phase_angles_deg", "event_times_deg")}, got,
               f"{scene.name} cyclogram")
        compared += 1 + len(got["phase_angles_deg"]) + len(got["event_times_deg"])
    return compared


@pytest.mark.reference("property", "camcad profile's report.json on the same scene (one machine in every command)")
@pytest.mark.parametrize("scene", SCENES, ids=[s.stem for s in SCENES])
def test_every_command_reports_the_figures_profile_reports(cli, tmp_path, scene):
    assert _commands_agree(cli, scene, tmp_path) > 0


@pytest.fixture
def batten_machine(tmp_path) -> Path:
    """batten_linkage.toml with a [stops] at the batten (its contact point 250 mm from the batten shaft): every
    model behind the [linkage], law_of = "output"."""
    data = tomllib.loads((SAMPLES / "scenes" / "batten_linkage.toml").read_text())
    data["machine"]["rpm"] = "330:420:90"
    data["stops"] = {"stiffness_N_per_m": 2.6e4, "mass_kg": 0.05, "stop_stiffness_N_per_m": 1.5e5,
                     "restitution": 5 / 9, "damping_ratio": 0.05, "preload_mm": 0.25, "stop": "upper",
                     "ratio": 250.0, "allowed_amplitude_mm": 0.5}
    data["linkage"].pop("adjust")
    path = tmp_path / "batten_machine.toml"
    path.write_text(_toml(data))
    return path


@pytest.mark.reference("property", "camcad profile's report.json on the same scene (one machine in every command)")
def test_a_linkage_with_a_stop_is_one_machine_in_every_command(cli, tmp_path, batten_machine):
    assert _commands_agree(cli, batten_machine, tmp_path) >= 10


@pytest.mark.reference("property", "camcad profile's report.json on the same scene (one machine in every command)")
def test_a_filtered_law_is_one_machine_in_every_command(cli, tmp_path):
    # batten.toml with a [filter]: its 113 Hz batten's resonance band removed from the law first, as profile does
    data = tomllib.loads((SAMPLES / "scenes" / "batten.toml").read_text())
    data["filter"] = {"harmonics": 64}
    data["dynamics"]["method"] = "frequency"
    data["dynamics"].pop("stiffness_variation")
    data["machine"]["rpm"] = "330:420:90"
    scene = tmp_path / "batten_filter.toml"
    scene.write_text(_toml(data))
    report = _profile(cli, scene, tmp_path / "first")
    assert "filter" in report["models_run"]
    assert _commands_agree(cli, scene, tmp_path) >= 10


@pytest.mark.reference("closed form", "simple harmonic rise: a_max = (pi^2/2) h / beta^2 * omega^2, in rad/s^2")
def test_the_batten_dynamics_is_in_rad_whatever_the_law_is_drawn_in(cli, tmp_path):
    # batten_linkage.toml gives the batten's law in deg (24.12 deg, law_of = "output"); the dynamics of the batten
    # must be in rad/s^2: (pi^2/2) * 0.421 rad / (64 deg in rad)^2 * (2 pi 420/60)^2 = 3220.8 rad/s^2, not the
    # 184,539 a law read as rad would give
    done = cli("dynamics", SAMPLES / "scenes" / "batten_linkage.toml", "--json", "--no-plots", "-o", tmp_path)
    assert done.code in (0, 1), done.err
    dynamics = done.json()["dynamics"]
    h, beta, omega = math.radians(24.12), math.radians(64.0), 2 * math.pi * 420 / 60
    assert dynamics["unit"] == "rad"
    assert dynamics["peak_accel_rigid_rad_s2"][-1] == pytest.approx(math.pi**2 / 2 * h / beta**2 * omega**2, rel=1e-6)
