"""The scene pipeline end to end: only the models a scene asks for, the cyclogram's phase angles fed back
into the laws and profiles, every output written, bad scene files answered in one line."""

import json
import math
import re
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from conftest import SAMPLES

from camcad.report.scene import run_scene
from camcad.scene.pipeline import PipelineOptions

SCENES = SAMPLES / "scenes"


def _phases(text: str) -> list[tuple[float, float, str]]:
    """"a:b:kind,..." (cyclogram) or "kind a-b, ..." (profile report) → [(a, b, kind)]."""
    if ":" in text:
        return [(float(a), float(b), k) for a, b, k in (item.split(":") for item in text.split(","))]
    found = re.findall(r"(\w+) ([-\d.e]+)-([-\d.e]+)", text)
    return [(float(a), float(b), k) for k, a, b in found]


@pytest.fixture(scope="module")
def group_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("loom")
    return run_scene(SCENES / "loom_group1.toml", PipelineOptions(output=out, plots=False)), out


@pytest.mark.reference("published", "Podgorny et al. 2018: a = -0.003 t + 0.208 <= 0.1 mm gives t >= 36 deg; the "
                                    "retimed law has v = 0 on every new dwell")
def test_group_scene_writes_every_output_and_feeds_the_cyclogram_back(group_run):
    result, out = group_run
    report = result.report
    assert report["passed"] is True
    cyclogram = report["cyclogram"]
    assert cyclogram["feasible"] is True
    # the limiting operation of the sample: the shuttle lift's rise held at its vibration limit
    # a = -0.003 t + 0.208 <= 0.1 mm  ->  t >= 36 deg (published relation, Podgorny et al. 2018)
    assert "3->7" in cyclogram["active_bounds"]
    assert cyclogram["phase_angles_deg"]["3->7"] == pytest.approx(36.0, abs=1e-6)
    on_disk = json.loads((out / "report.json").read_text())
    assert on_disk["cyclogram"]["makespan_deg"] == pytest.approx(cyclogram["makespan_deg"])
    for name, mech in report["mechanisms"].items():
        folder = out / name
        for file in ("profile.dxf", "law.csv"):
            assert (folder / file).stat().st_size > 0, (name, file)
        # the profile's phase angles are the cyclogram's, to the printed precision of either
        fed = _phases(cyclogram["phases"][name])
        used = [(p["start_deg"], p["end_deg"], p["kind"]) for p in mech["law"]["phases_deg"]]
        assert [k for *_, k in fed] == [k for *_, k in used]
        for (a0, b0, _), (a1, b1, _) in zip(fed, used):
            assert a1 == pytest.approx(a0, abs=1e-6) and b1 == pytest.approx(b0, abs=1e-6)
        assert mech["retimed_by_cyclogram"] == cyclogram["phases"][name]
        # law.csv follows the retimed law: zero velocity on every dwell of the new phases
        table = np.loadtxt(folder / "law.csv", delimiter=",", skiprows=1)
        theta, v = table[:, 0], table[:, 2]
        for a, b, kind in fed:
            inside = (theta > a + 1e-6) & (theta < b - 1e-6)
            if kind == "dwell" and inside.any():
                assert np.max(np.abs(v[inside])) < 1e-9, (name, a, b)
        # and the profile drawing is a closed LWPOLYLINE in mm
        doc = ezdxf.readfile(folder / "profile.dxf")
        assert doc.units == 4
        assert doc.modelspace().query("LWPOLYLINE[layer=='PROFILE']")[0].closed
    for path in report["outputs"]:
        assert (out / path.split(str(out) + "/", 1)[-1]).exists() or __import__("pathlib").Path(path).exists()


@pytest.mark.reference("property", "every phase angle is at least its least admissible value, from each kind of limit")
def test_group_scene_limits_come_from_every_source(group_run):
    result, _ = group_run
    bounds = result.report["cyclogram"]["lower_bounds_deg"]
    sources = {entry["source"] for entry in bounds.values()}
    assert {"vibration", "contact", "pressure angle", "bounds_deg"} <= sources
    # each phase angle respects its least admissible value
    angles = result.report["cyclogram"]["phase_angles_deg"]
    for label, least in bounds.items():
        assert angles[label] >= least["deg"] - 1e-7, label


@pytest.mark.reference("property", "a scene runs the models its sections ask for and says which it skipped and why")
def test_a_scene_runs_only_what_it_has(tmp_path):
    shuttle = run_scene(SCENES / "shuttle_lift.toml", PipelineOptions(output=tmp_path / "s", plots=False)).report
    assert shuttle["models_run"] == ["law", "profile", "dynamics", "impact"]
    assert shuttle["skipped"]["contact"] == "no [contact] in scene"
    assert shuttle["skipped"]["filter"] == "no [filter] in scene"
    assert shuttle["skipped"]["cyclogram"] == "no [cyclogram] in scene"
    # the published behaviour of the shuttle lift: its 35 deg rise rebounds past 0.1 mm at the top speeds
    assert shuttle["impact"]["passed"] is False and shuttle["passed"] is False
    assert shuttle["phase_limits"]["rise"]["vibration (impact rebound)"] == pytest.approx(36.75, abs=0.01)
    batten = run_scene(SCENES / "batten.toml", PipelineOptions(output=tmp_path / "b", plots=False)).report
    assert "impact" not in batten and batten["skipped"]["impact"] == "no [stops] in scene"
    assert batten["dynamics"]["passed"] is True


@pytest.mark.reference("property", "no speed in the scene: dynamics and impact skipped with the reason, never "
                                   "defaulted")
def test_elastic_data_without_speeds_is_skipped_not_defaulted(tmp_path):
    text = (SCENES / "shuttle_lift.toml").read_text()
    text = re.sub(r"\[machine\]\nrpm = .*\n", "", text)
    scene = tmp_path / "nospeed.toml"
    scene.write_text(text)
    report = run_scene(scene, PipelineOptions(output=tmp_path / "o", plots=False)).report
    assert report["skipped"]["dynamics"] == "no [machine] rpm in scene"
    assert report["skipped"]["impact"] == "no [machine] rpm in scene"


@pytest.mark.reference("property", "an unbalanced drawn law, fixed on request: balanced after, the profile closes "
                                   "(gap < 1e-9 mm)")
def test_a_drawn_law_scene_is_balanced_when_asked(tmp_path):
    scene = tmp_path / "drawn.toml"
    scene.write_text(f"""
name = "drawn"
[law]
file = "{(SAMPLES / 'dxf' / 'fig2_rise_area_too_large.dxf').as_posix()}"
lift = 20.0
fix = "min-change"
[follower]
type = "roller"
base_radius = 60.0
roller_radius = 10.0
""")
    report = run_scene(scene, PipelineOptions(output=tmp_path / "o", plots=False)).report
    assert report["law"]["balance"]["balanced"] is False
    assert report["law"]["fixed"]["after"]["balanced"] is True
    assert report["closed"] is True and report["closure_gap_mm"] < 1e-9


BAD_SCENES = [
    ("[law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\nlift = 10\n"
     "[folower]\ntype = \"roller\"\n",
     "did you mean 'follower'"),
    ("[law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\n", "missing value 'lift'"),
    ("[law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\nlift = \"ten\"\n",
     "'lift' (mm, or deg of swing) must be a number"),
    ("[law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\nlift = 10\n[follower]\n"
     "type = \"roller\"\nbase_radius = 50\nroller_radius = -3\n", "roller"),
    ("[machine]\nrpm = \"fast\"\n[law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\nlift = 10\n",
     "rpm 'fast'"),
    ("[mechanisms.m.law]\nstandard = \"cycloidal\"\nphases = \"0:180:rise,180:360:return\"\nlift = 10\n"
     "[cyclogram]\n[[cyclogram.operations]]\nfrom = 1\nto = 2\nbounds_deg = [10.0, 20.0]\n"
     "[[cyclogram.operations]]\nfrom = 2\nto = 1\nbounds_deg = [10.0, 20.0]\n", "cycle: 1 -> 2 -> 1"),
    ("[law\nstandard = 1\n", "not valid TOML"),
    # found by the fuzz campaign: a 20 MB scene (a million speeds) took 10 s of CPU in the TOML parser
    ("[machine]\nrpm = [" + ", ".join(["0.123456789012345"] * 70_000) + "]\n", "is too large (at most 1 MB)"),
]


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("text,expected", BAD_SCENES)
def test_bad_scene_files_get_one_clear_line(cli, tmp_path, text, expected):
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    result = cli("profile", scene, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2, (result.out, result.err)
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error: ") and "internal error" not in lines[0], result.err
    assert expected in lines[0], lines[0]
    assert "bad.toml" in lines[0]


@pytest.mark.reference("property", "profile on a scene prints one JSON object with its documented keys")
def test_profile_command_on_a_scene_prints_json(cli, tmp_path):
    result = cli("profile", SCENES / "batten.toml", "-o", tmp_path, "--json", "--no-plots")
    assert result.code == 0, result.err
    payload = result.json()
    for key in ("pressure_angle_max_deg", "rho_pitch_min_mm", "undercut", "closed", "closure_gap_mm",
                "profile_points", "outputs", "dynamics", "skipped"):
        assert key in payload
    assert math.isfinite(payload["pressure_angle_max_deg"])


@pytest.mark.reference("property", "docs/SCENE.md holds the tables generated from the parsers")
def test_scene_doc_lists_every_key_of_every_section():
    # docs/SCENE.md is generated from the parsers; regenerate it with docs/make_scene_doc.py when this fails
    import sys

    sys.path.insert(0, str(SAMPLES.parent / "docs"))
    from make_scene_doc import tables

    assert tables() in (SAMPLES.parent / "docs" / "SCENE.md").read_text()


@pytest.mark.reference("regression", "fuzz campaign seed 11 case 490: a law file name with a NUL byte ended in an "
                                     "internal error")
@pytest.mark.parametrize("command", ["profile", "contact", "dynamics"])
def test_a_law_file_name_with_a_nul_byte_is_one_clear_line(cli, tmp_path, command):
    # found by the fuzz campaign (case 490, seed 11): the output folder's input guard resolved the name
    # before the law's reader could refuse it, and `contact` ended in an internal error
    scene = tmp_path / "nul.toml"
    scene.write_text('[law]\nfile = "law\\u0000.dxf"\nlift = 10\n[follower]\ntype = "roller"\nbase_radius = 50\n'
                     'roller_radius = 10\n')
    result = cli(command, scene, "-o", tmp_path / "out", "--no-plots", "--zeta", "0.05", "--fn", "300",
                 "--rpm", "300") if command == "dynamics" else cli(command, scene, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2, (result.out, result.err)
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error: ") and "internal error" not in lines[0], result.err


@pytest.mark.reference("property", "a pass with warnings says how many warnings, never a clean pass")
def test_the_verdict_line_counts_the_warnings_a_signer_must_weigh(cli, tmp_path):
    # loom group 1 passes every check, but a profile radius of 1.43 mm and a contact safety factor of 1
    # are warned of: the last line must not read as a clean pass
    result = cli("profile", SCENES / "loom_group1.toml", "-o", tmp_path, "--no-plots")
    warned = [line for line in result.out.splitlines() if line.strip().startswith("WARN")]
    assert any("1.43 mm" in line for line in warned)
    last = result.out.strip().splitlines()[-1]
    assert last == f"verdict: all checks passed; {len(warned)} warnings (WARN above) to weigh before signing", last


@pytest.mark.reference("property", "every PNG on disk is listed in the report's outputs and is a name the writer "
                                   "checks")
def test_a_group_s_plots_are_drawn_in_parallel_and_every_one_is_listed(tmp_path):
    # the loom group's default plots: a summary page per mechanism and the cyclogram's two pages, drawn by
    # forked workers; every PNG on disk is listed in the report's outputs and is one of the names the
    # writer checks against the run's inputs before drawing
    from camcad.report.profile import PLOTS
    from camcad.report.scene import CYCLOGRAM_PLOT_FILES, MECHANISM_PLOT_FILES

    assert {f"{name}.png" for name in PLOTS} <= set(MECHANISM_PLOT_FILES)
    out = tmp_path / "loom"
    report = run_scene(SCENES / "loom_group1.toml", PipelineOptions(output=out)).report
    on_disk = {p for p in out.rglob("*.png")}
    assert on_disk == {p for p in map(Path, report["outputs"]) if p.suffix == ".png"}
    assert {p.name for p in on_disk if p.parent == out} == set(CYCLOGRAM_PLOT_FILES)
    for name, mechanism in report["mechanisms"].items():
        assert {Path(p).name for p in mechanism["outputs"] if p.endswith(".png")} == {"summary.png"}, name
        assert (out / name / "summary.png").stat().st_size > 10_000
    # the models' plots of a scene with dynamics and stops: their names are among the checked ones
    shuttle = run_scene(SCENES / "shuttle_lift.toml",
                        PipelineOptions(output=tmp_path / "s", plots=("dynamics", "impact"))).report
    drawn = {Path(p).name for p in shuttle["outputs"] if p.endswith(".png")}
    assert drawn and drawn <= set(MECHANISM_PLOT_FILES)
