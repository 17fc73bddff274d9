"""`camcad sweep` end to end: each design's figures against an independent route, the feasible boundary
against the closed-form least base radius and against `camcad profile --auto-rb`, checks-only against the
full pipeline, resume after a stop with every design computed exactly once, engines giving identical
Parquet, the outputs, and bad input as one line. Sweeps are small (tens of designs): the full sweep of the
issue is run by docs/make_sweep_figures.py."""

from __future__ import annotations

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from camcad.scene.default import default_tables
from camcad.scene.file import scene_from_dict
from camcad.scene.pipeline import PipelineOptions, analyse_scene
from camcad.sweep.evaluate import design_checks

pytest.importorskip("pyarrow")

SCENES = Path(__file__).resolve().parents[2] / "samples" / "scenes"
LIFT, RR, LIMIT_RISE = 25.0, 10.0, 30.0   # the default design (camcad.scene.default)


def least_rb_closed_form(rise_deg: float) -> float:
    """The least base radius (mm) of the default design's cycloidal rise over ``rise_deg`` at the 30 deg limit,
    from the closed form alone: translating roller, no offset, tan φ = v / (Rb + Rr + s) with
    s = h(u − sin 2πu / 2π), v = ds/dθ = (h/β)(1 − cos 2πu), u = θ/β; so Rb = max over u of v / tan 30° − s − Rr,
    the maximum refined on a dense grid (1e6 points: error far below 1e-6 mm)."""
    beta = math.radians(rise_deg)
    u = np.linspace(0.0, 1.0, 1_000_001)
    s = LIFT * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    v = LIFT / beta * (1 - np.cos(2 * np.pi * u))
    return float(np.max(v / math.tan(math.radians(LIMIT_RISE)) - s)) - RR


def read(folder: Path):
    from camcad.sweep.store import read_results

    return read_results(folder)


# --------------------------------------------------------------------------------------------
# a design's row against independent routes
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("second method", "the same design written by hand as a scene and run by camcad profile; tan "
                                        "phi = v/(Rb + Rr + s) in closed form")
def test_a_row_holds_the_figures_of_the_scene_written_by_hand(tmp_path, cli):
    result = cli("sweep", "--vary", "law.phases.rise=75", "--vary", "follower.base_radius=44.5", "--workers", "1",
                 "-o", tmp_path, "--no-plots", "--no-best", "--json")
    assert result.code in (0, 1), result.err
    row = read(tmp_path).to_pylist()[0]
    assert result.code == (0 if row["feasible"] else 1)     # exit 1: no feasible design
    # the same design written by hand: the rise ends at 75 deg, the dwell after it starts there
    tables = default_tables()
    tables["law"]["phases"] = "0:75:rise,75:180:dwell,180:300:return,300:360:dwell"
    tables["follower"]["base_radius"] = 44.5
    report = analyse_scene(scene_from_dict(tables, Path("by hand"), from_file=False), PipelineOptions(plots=())).report
    for name, check in report["checks"].items():
        for part in ("value", "limit", "margin"):
            expected = check[part]
            assert row[f"{name}.{part}"] == pytest.approx(expected, rel=0, abs=0), (name, part)
        assert row[f"{name}.passed"] == check["passed"]
    # and the rise's pressure angle against the closed form: tan φ = v / (Rb + Rr + s), its maximum
    beta = math.radians(75)
    u = np.linspace(0, 1, 2_000_001)
    s = LIFT * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    v = LIFT / beta * (1 - np.cos(2 * np.pi * u))
    phi = math.degrees(float(np.max(np.arctan(v / (44.5 + RR + s)))))
    assert row["pressure angle, rise.value"] == pytest.approx(phi, abs=1e-6)
    assert row["feasible"] == (phi <= LIMIT_RISE) and row["governing"] == "pressure angle, rise"


def without_least_phase_angles(figures):
    """The checks of a phase angle against the least angle the design step solves for [sigma_H]: the
    full pipeline has them, checks_only does not solve those angles (its contact stress check, at the
    scene's own phase angles, decides the same pass or fail)."""
    return [f for f in figures if not f.name.endswith(" phase angle")]


@pytest.mark.reference("second method", "the full pipeline on the same design: the same checks")
def test_checks_only_gives_the_same_checks_as_the_full_pipeline():
    tables = default_tables()
    weft = tomllib.loads((SCENES / "loom_group1.toml").read_text())["mechanisms"]["weft_returner"]
    with_contact = {"name": "weft", "machine": {"rpm": [280.0, 420.0]}, **copy.deepcopy(weft)}
    groove = copy.deepcopy(tables)
    groove["follower"].update(groove=True, base_radius=35.0)           # fails its rise pressure angle
    pair = copy.deepcopy(tables)
    pair["follower"].update(pair_distance=145.0, rho_min=3.0)          # a conjugate cam, a curvature limit
    knife = copy.deepcopy(tables)
    knife["follower"].update(type="knife", roller_radius=0.0, base_radius=12.0)   # undercut by a loop
    scenes = [scene_from_dict(t, Path("t"), from_file=False) for t in (tables, groove, pair, knife)]
    scenes += [SCENES / "shuttle_lift.toml", scene_from_dict(with_contact, Path("weft"), from_file=False)]
    for scene in scenes:
        full = analyse_scene(scene, PipelineOptions(plots=())).report
        quick = analyse_scene(scene, PipelineOptions(plots=(), checks_only=True)).report
        assert quick["checks"] == full["checks"] and quick["passed"] == full["passed"]
        assert design_checks(quick) == without_least_phase_angles(design_checks(full))
        for model in ("dynamics", "impact"):
            if model in full:
                assert quick[model] == full[model]
        if "contact" in full:
            for key in ("sigma_max_MPa", "allowable_MPa", "safety_factor", "separation", "passed", "versus_speed"):
                assert quick["contact"][key] == full["contact"][key]
        assert "design" not in quick and "phase_limits" not in quick


@pytest.mark.reference("second method", "the full pipeline on the same group: the same retimed laws and figures")
def test_checks_only_gives_the_same_figures_for_a_group_with_a_cyclogram():
    # the cyclogram retimes the laws: its least phase angles are solved as in the full pipeline (same memo),
    # so the retimed laws, and every figure after them, are the same to the last bit
    full = analyse_scene(SCENES / "loom_group1.toml", PipelineOptions(plots=())).report
    quick = analyse_scene(SCENES / "loom_group1.toml", PipelineOptions(plots=(), checks_only=True)).report
    # 4 mechanisms x 6 checks, less the spring's normal force of shuttle_lift (a groove: form-closed), + each
    # mechanism's rise and return against the least angle contact stress allows (the cyclogram's limits), + the
    # cyclogram's own 11 (makespan and one phase angle per arc of the network)
    assert design_checks(quick) == design_checks(full) and len(design_checks(full)) == 4 * 6 - 1 + 4 * 2 + 11
    assert quick["cyclogram"]["phase_angles_deg"] == full["cyclogram"]["phase_angles_deg"]


# --------------------------------------------------------------------------------------------
# the feasible boundary
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "the least base radius meeting the pressure-angle limit (the per-angle closed "
                                      "form) and profile --auto-rb")
def test_the_boundary_agrees_with_the_closed_form_and_with_auto_rb(tmp_path, cli):
    step = 2.0
    rises = (60.0, 66.0, 80.0, 100.0)   # least Rb above the grid (61 mm), inside it (53.5, 40.5), below it (28.4)
    result = cli("sweep", "--vary", "follower.base_radius=30:58:2", "--vary", "law.phases.rise=60,66,80,100",
                 "--plot", "law.phases.rise,follower.base_radius", "--workers", "1", "-o", tmp_path, "--no-best",
                 "--json")
    assert result.code == 0, result.err
    report = result.json()
    boundary = {b["x"]: b for b in report["region"]["boundary"]}
    from camcad.scene.follower import follower_for_law
    from camcad.scene.laws import build_law
    from camcad.scene.sections.law import parse_law

    for rise in rises:
        exact = least_rb_closed_form(rise)
        # camcad profile --auto-rb: the scene's follower sized by min_base_radius on the same law
        tables = default_tables()
        tables["law"]["phases"] = f"0:{rise:g}:rise,{rise:g}:180:dwell,180:300:return,300:360:dwell"
        follower_table = {**tables["follower"], "auto_base_radius": True}
        del follower_table["base_radius"]
        law = build_law(parse_law(tables["law"], "t", Path("."))).law
        auto = follower_for_law(follower_table, "t", law)[0].base_radius
        assert auto == pytest.approx(exact, abs=1e-6)
        b = boundary[rise]
        assert b["monotone"]
        if exact <= 30.0:   # the whole column is feasible: the boundary lies below the grid
            assert b["least_feasible"] == 30.0 and b["greatest_infeasible"] is None
        elif exact > 58.0:  # no design of the column is feasible: the boundary lies above the grid
            assert b["least_feasible"] is None and b["greatest_infeasible"] == 58.0
        else:
            assert b["greatest_infeasible"] < exact <= b["least_feasible"] < exact + step
    png = tmp_path / "region.png"
    assert png.read_bytes()[:4] == b"\x89PNG" and (tmp_path / "pareto.png").exists()


# --------------------------------------------------------------------------------------------
# resume, engines, outputs
# --------------------------------------------------------------------------------------------

VARY = ["--vary", "follower.base_radius=30:50:4", "--vary", "law.phases.rise=60,90,120,200"]   # 200: refused


@pytest.mark.reference("property", "a stopped sweep resumes from its chunks and computes each design once; mixing "
                                   "sweeps refused")
def test_a_stopped_sweep_resumes_where_it_stopped_and_computes_each_design_once(tmp_path, cli):
    stopped = tmp_path / "stopped"
    first = cli("sweep", *VARY, "--chunk", "4", "--workers", "1", "-o", stopped, "--stop-after-chunks", "2",
                "--no-plots", "--no-best")
    assert first.code == 130 and "--resume" in first.err and len(first.err.strip().splitlines()) == 1
    written = sorted((stopped / "results").glob("chunk-*.parquet"))
    assert [p.name for p in written] == ["chunk-00000000.parquet", "chunk-00000001.parquet"]
    before = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in written}
    again = cli("sweep", *VARY, "-o", stopped, "--no-plots", "--no-best", "--json")   # without --resume: refused
    assert again.code == 2 and "add --resume" in again.err
    other = cli("sweep", "--vary", "follower.base_radius=30:50:5", "-o", stopped, "--resume", "--no-plots")
    assert other.code == 2 and "another sweep" in other.err
    resumed = cli("sweep", *VARY, "--workers", "2", "-o", stopped, "--resume", "--no-plots", "--no-best", "--json")
    assert resumed.code == 0, resumed.err
    speed = resumed.json()["throughput"]
    assert speed["chunks_on_disk_before"] == 2 and speed["chunks_computed"] == 4 and speed["designs_computed"] == 16
    for path in written:   # the chunks of the first run were not computed or written again
        assert (path.stat().st_ino, path.stat().st_mtime_ns) == before[path.name]
    table = read(stopped)
    assert table.column("design").to_pylist() == list(range(24))     # every design exactly once
    fresh = tmp_path / "fresh"
    assert cli("sweep", *VARY, "--chunk", "4", "--workers", "1", "-o", fresh, "--no-plots", "--no-best").code == 0
    assert read(fresh).equals(table)                                 # in-process = pool, stopped + resumed = fresh
    complete = cli("sweep", *VARY, "-o", stopped, "--resume", "--no-plots", "--no-best", "--json")
    assert complete.code == 0 and complete.json()["throughput"]["designs_computed"] == 0   # nothing left to do
    refused = [r for r in table.to_pylist() if r["status"] == "bad input"]
    assert len(refused) == 6 and all("rise cannot be made 200 deg wide" in r["error"] for r in refused)
    assert all(r["law.phases.rise"] == 200 and not r["feasible"] for r in refused)


@pytest.mark.reference("second method", "the best design recomputed here: the least feasible radius of the grid, then "
                                        "the widest rise")
def test_outputs_best_scene_and_report(tmp_path, cli):
    result = cli("sweep", "--vary", "follower.base_radius=30:46:8", "--vary", "law.phases.rise=60,90,120",
                 "--objective", "min:follower.base_radius", "--objective", "max:pressure angle, rise",
                 "--workers", "1", "-o", tmp_path, "--json")
    assert result.code == 0, result.err
    report = result.json()
    run = json.loads((tmp_path / "throughput.json").read_text())
    assert {**json.loads((tmp_path / "report.json").read_text()), **run} == report
    assert set(run) == {"chunks", "chunk_designs", "throughput"}
    counts = report["counts"]
    assert counts["designs"] == 9 and counts["feasible"] + counts["infeasible"] == 9
    assert counts["failed_by"] == {"pressure angle, rise": counts["infeasible"]}
    best = report["best"]
    # independent: the least feasible radius of the grid, then the widest rise (largest margin)
    table = read(tmp_path).to_pylist()
    feasible = [r for r in table if r["feasible"]]
    smallest = min(r["follower.base_radius"] for r in feasible)
    widest = max((r for r in feasible if r["follower.base_radius"] == smallest),
                 key=lambda r: r["pressure angle, rise.margin"])
    assert best["design"] == widest["design"] and best["values"]["follower.base_radius"] == smallest
    scene = tomllib.loads((tmp_path / "best.toml").read_text())
    assert scene["follower"]["base_radius"] == smallest
    assert scene["law"]["phases"].startswith(f"0:{widest['law.phases.rise']:g}:rise,")
    assert best["profile"]["passed"] and (tmp_path / "best" / "profile.dxf").exists()
    profile = json.loads((tmp_path / "best" / "report.json").read_text())
    assert profile["checks"]["pressure angle, rise"]["value"] == widest["pressure angle, rise.value"]
    lines = (tmp_path / "pareto.csv").read_text().splitlines()
    assert lines[0].startswith("design,follower.base_radius,law.phases.rise,pressure angle, rise.margin") or \
        lines[0].startswith('design,follower.base_radius,law.phases.rise,"pressure angle, rise.margin"')
    assert len(lines) - 1 == report["pareto"]["designs"] >= 1
    header = next(__import__("csv").reader(lines[:1]))
    assert len(header) == len(set(header)) and header.count("min_margin_ratio") == 1   # each column once
    speed = report["throughput"]
    assert speed["designs_computed"] == 9 and speed["designs_per_cpu_s"] > 0 and speed["wall_s"] > 0
    import pyarrow.parquet as pq

    schema = pq.read_schema(next((tmp_path / "results").glob("*.parquet")))
    assert schema.field("follower.base_radius").metadata[b"unit"] == b"mm"
    assert schema.field("pressure angle, rise.value").metadata[b"unit"] == b"deg"
    assert not any("time" in name for name in schema.names)     # timings are in report.json only


@pytest.mark.reference("property", "every grid point sees the same draws; feasible-in-every-draw counted per grid "
                                   "point")
def test_a_monte_carlo_sweep_is_judged_per_grid_point(tmp_path, cli):
    result = cli("sweep", "--vary", "follower.base_radius=36,60", "--vary", "law.phases.rise=80",
                 "--vary", "follower.roller_radius=normal(10,2)", "--samples", "3", "--seed", "5",
                 "--workers", "1", "-o", tmp_path, "--no-best", "--no-plots", "--json")
    assert result.code in (0, 1), result.err
    report = result.json()
    table = read(tmp_path).to_pylist()
    assert [r["sample"] for r in table] == [0, 1, 2, 0, 1, 2]
    assert [r["follower.roller_radius"] for r in table[:3]] == [r["follower.roller_radius"] for r in table[3:]]
    robust = [all(r["feasible"] for r in table[i:i + 3]) for i in (0, 3)]
    assert report["counts"]["grid_points"] == 2
    assert report["counts"]["grid_points_feasible_in_every_draw"] == sum(robust)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("args, words", [
    (["--vary", "follower.base_radus=30:40:1"], "did you mean 'follower.base_radius'?"),
    (["--vary", "follower.base_radius=40:30:1"], "runs backwards"),
    (["--vary", "contact.width=5:10:1"], "no [contact] section"),
    (["--vary", "follower.roller_radius=normal(10,0.1)"], "add --samples N"),
    ([], "nothing to vary"),
    (["--vary", "follower.base_radius=30:40:5", "--objective", "min:stress"], "no column 'stress'"),
    (["--vary", "follower.base_radius=30:40:5", "--plot", "follower.base_radius,law.lift"], "--plot"),
    (["--vary", "follower.base_radius=30:40:5", "--scheduler", "nowhere"], "neither tcp://HOST:PORT"),
    (["--vary", "follower.base_radius=30:40:5", "--scheduler", "tcp://127.0.0.1:9", "--connect-timeout", "1"],
     "cannot reach the Dask scheduler"),
    (["--vary", "law.phases.rise=200"], "design 0"),
])
def test_bad_input_is_one_line(tmp_path, cli, args, words):
    result = cli("sweep", *args, "-o", tmp_path / "out")
    assert result.code == 2, (result.code, result.err)
    line = result.err.strip()
    assert words in line and "\n" not in line and len(line) < 300 and "Traceback" not in line


@pytest.mark.reference("property", "without the sweep extra: one line naming pip install 'camcad[sweep]'")
def test_a_missing_extra_is_one_line(tmp_path, cli, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pyarrow", None)      # import pyarrow now raises ImportError
    result = cli("sweep", "--vary", "follower.base_radius=30:40:5", "-o", tmp_path)
    assert result.code == 2 and "pip install 'camcad[sweep]'" in result.err
    monkeypatch.delitem(sys.modules, "pyarrow")
    monkeypatch.setitem(sys.modules, "distributed", None)
    result = cli("sweep", "--vary", "follower.base_radius=30:40:5", "--scheduler", "tcp://127.0.0.1:9", "-o", tmp_path)
    assert result.code == 2 and "dask.distributed" in result.err and "camcad[sweep]" in result.err


@pytest.mark.reference("property", "an output folder that would replace the input is refused; the scene unchanged")
def test_an_output_never_replaces_an_input(tmp_path, cli):
    scene = tmp_path / "best.toml"
    scene.write_text((SCENES / "shuttle_lift.toml").read_text())
    before = scene.read_bytes()
    result = cli("sweep", scene, "--vary", "follower.base_radius=50", "-o", tmp_path, "--no-plots")
    assert result.code == 2 and "would replace the input" in result.err
    assert scene.read_bytes() == before and not (tmp_path / "results").exists()
