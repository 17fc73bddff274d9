"""`camcad law`: a designed law written as a drawing, a table and plots; the drawing reads back with its phases."""

from __future__ import annotations

import json
import math

import ezdxf
import numpy as np
import pytest

from camcad.law.segments import parse_segments, solve_segments
from camcad.law.source import load_law

SEGMENTS = ("0:60:dwell,60:140:poly5:12:v_end=match,140:200:constant_velocity:30,200:240:poly5:36,"
            "240:330:modified_sine:0,330:360:dwell")


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    from camcad.cli import main

    folder = tmp_path_factory.mktemp("law")
    with pytest.raises(SystemExit) as stop:
        main(["law", "samples/scenes/filling_stroke.toml", "-o", str(folder), "--json"])
    assert stop.value.code == 0
    return folder


def test_law_writes_the_drawing_the_table_the_plot_and_the_report(written):
    names = sorted(p.name for p in written.iterdir())
    assert names == ["law.csv", "law.dxf", "law.json", "law.png"]
    report = json.loads((written / "law.json").read_text())["law"]
    assert [j["class"] for j in report["joints"]] == ["C2", "C2", "C2", "C2", "C2", "C3"]
    assert [s["class"] for s in report["segments"]] == ["R-R", "R-G", "G-G", "G-R", "R-R", "R-R"]
    assert report["segments"][2]["v_start_mm_per_deg"] == pytest.approx(0.3, rel=1e-14)
    assert report["drawing"]["balanced"] and report["drawing"]["largest_residual"] < 1e-9
    header = (written / "law.csv").read_text().splitlines()[0]
    assert header == "theta_deg,s_mm,v_mm_per_rad,a_mm_per_rad2,j_mm_per_rad3"


def test_drawing_has_the_layers_a_cad_user_recognises(written):
    doc = ezdxf.readfile(written / "law.dxf")
    msp = doc.modelspace()
    layers = {e.dxf.layer for e in msp}
    assert layers == {"ACCELERATION", "AXES", "PHASE_MARKS", "TEXT"}
    marks = [e for e in msp.query("LINE") if e.dxf.layer == "PHASE_MARKS"]
    assert sorted(round(e.dxf.start.x, 9) for e in marks) == [60, 140, 200, 240, 330]
    (curve,) = msp.query("LWPOLYLINE")
    assert curve.dxf.layer == "ACCELERATION" and curve.has_xdata("CAMCAD")


@pytest.mark.reference("closed form", "the segment law's own s at its phase ends: 0, 12, 30, 36, 0 mm")
def test_check_reads_the_drawing_back_with_the_same_phases_and_balanced(written, cli):
    result = cli("check", written / "law.dxf", "--json")
    assert result.code == 0, result.err
    checked = result.json()
    report = json.loads((written / "law.json").read_text())["law"]
    assert [(p["kind"], round(p["start_deg"], 9), round(p["end_deg"], 9)) for p in checked["phases"]] == \
        [(p["kind"], round(p["start_deg"], 9), round(p["end_deg"], 9)) for p in report["phases"]]
    assert checked["balanced"]
    # the drawing moves the follower where the law does: its s at the phase ends, to the drawing's accuracy
    loaded = load_law(written / "law.dxf")
    ends = loaded.law.kinematics(np.array([p.end for p in loaded.law.phases])).s
    assert np.allclose(ends, [0.0, 12.0, 30.0, 36.0, 0.0, 0.0], rtol=0, atol=1e-9)
    law = solve_segments(parse_segments(SEGMENTS))
    theta = np.linspace(0.0, 2 * math.pi, 3601)
    assert np.max(np.abs(loaded.law.kinematics(theta).s - law.kinematics(theta).s)) <= 1e-4 * 36.0


def test_edit_opens_the_drawing_and_saves_it(written, cli, tmp_path):
    script = tmp_path / "ops.json"
    script.write_text(json.dumps([{"op": "save", "path": "edited.dxf"}]))   # saves go into the output folder
    (tmp_path / "out").mkdir()
    result = cli("edit", written / "law.dxf", "--script", script, "-o", tmp_path / "out", "--json")
    assert result.code == 0, result.err
    assert result.json()["balanced"]
    assert cli("check", tmp_path / "out" / "edited.dxf").code == 0


def test_law_from_the_command_line(cli, tmp_path):
    result = cli("law", "--segments", SEGMENTS, "-o", tmp_path / "seg", "--no-plots", "--json")
    assert result.code == 0, result.err
    assert [p["kind"] for p in result.json()["law"]["phases"]] == ["dwell", "rise", "rise", "rise", "return", "dwell"]
    result = cli("law", "--rise-law", "inclined_sine", "--return-law", "modified_sine:0.4", "--phases",
                 "0:100:rise,100:180:dwell,180:300:return,300:360:dwell", "--lift", "20", "-o", tmp_path / "std",
                 "--no-plots", "--json")
    assert result.code == 0, result.err
    shapes = result.json()["law"]["shapes"]
    assert shapes[0]["coefficients"]["cv"] == pytest.approx(2.0, rel=1e-12)
    assert cli("check", tmp_path / "std" / "law.dxf").code == 0


@pytest.mark.parametrize("args, match", [
    (["--segments", "0:180:poly5:20:v_end=0.3,180:200:dwell,200:360:poly5:0"],
     "segment 2 (dwell) rests but segment 1 (poly5) arrives"),
    (["--rise-law", "bestehorn", "--phases", "0:180:rise,180:360:return", "--lift", "10"], "unknown law 'bestehorn'"),
    (["--segments", "0:180:poly5:20,180:360:poly5:0", "--lift", "3"], "--segments give the whole law"),
    (["samples/scenes/filling_stroke.toml", "--lift", "3"], "a scene holds its own"),
    (["samples/scenes/batten_linkage.toml"], None),
])
def test_law_refuses_bad_input_in_one_line(cli, tmp_path, args, match):
    result = cli("law", *args, "-o", tmp_path / "x", "--no-plots")
    if match is None:   # a scene with a standard law draws fine
        assert result.code == 0, result.err
        return
    assert result.code == 2 and match in result.err
    assert len(result.err.strip().splitlines()) == 1


def test_catalogue_list(cli):
    result = cli("law", "--list", "--json")
    assert result.code == 0
    names = {row["name"] for row in result.json()["catalogue"]}
    assert {"inclined_sine", "poly5", "poly7", "harmonic_combination", "double_harmonic"} <= names
    text = cli("law", "--list").out
    assert "modified_sine" in text and "Cv 1.7596" in text


def test_profile_takes_the_catalogue_names(cli, tmp_path):
    result = cli("profile", "--rise-law", "inclined_sine", "--return-law", "poly7", "--no-plots", "-o", tmp_path,
                 "--json")
    assert result.code == 0, result.err
    assert "inclined_sine/poly7" in result.json()["law"]["notes"][0]
