"""`camcad linkage analyse|adjust|family|tune`: outputs, JSON keys, exit codes, one-line errors, and the
kinematic diagrams read by independent CAD readers (GDAL, LibreCAD, Inkscape; required in CI like
tests/io/test_interop.py, skipped on a machine without them)."""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from collections import Counter
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from camcad.cli import app, register_all
from camcad.cli.common import run_app

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "scenes" / "batten_linkage.toml"
FOURBAR = ["--links", "40,120,90", "--output-pivot", "100,20", "--input-angle", "80", "--swing", "30",
           "--sense", "-1"]
INKSCAPE_DXF = Path("/usr/share/inkscape/extensions/dxf_input.py")
REQUIRED = os.environ.get("CAMCAD_REQUIRE_READERS") == "1"


def run(args, capsys):
    register_all()
    code = run_app(app, ["linkage", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_analyse_from_options_writes_its_files(tmp_path, capsys):
    code, out, err = run(["analyse", *FOURBAR, "--coupler-point", "60,10", "-o", str(tmp_path), "--json"], capsys)
    assert code == 0, err
    payload = json.loads(out)
    rep = payload["linkage"]
    assert rep["type"] == "fourbar" and rep["branch_continuous"] and rep["monotone"]
    assert {"stroke_deg", "mu_min_deg", "dead_points_swing_deg", "limit_positions_swing_deg", "checks"} <= set(rep)
    names = sorted(Path(p).name for p in payload["outputs"])
    assert names == ["analysis.csv", "analysis.dxf", "analysis.json", "analysis.png", "diagram.png"]
    rows = np.loadtxt(tmp_path / "analysis.csv", delimiter=",", skiprows=2)
    assert rows.shape[1] == 8 and rows[-1, 0] == pytest.approx(30.0)
    doc = ezdxf.readfile(tmp_path / "analysis.dxf")
    layers = Counter(e.dxf.layer for e in doc.modelspace())
    assert {"FRAME", "LINKS", "EXTREME_POSITIONS", "JOINTS", "PATHS", "TEXT"} <= set(layers)


def test_analyse_exit_1_when_the_transmission_angle_fails(tmp_path, capsys):
    code, out, _ = run(["analyse", *FOURBAR, "--mu-min", "60", "-o", str(tmp_path), "--no-plots"], capsys)
    assert code == 1 and "transmission_angle   FAILED" in out


def test_analyse_the_sample_scene_with_its_cam_and_settings(tmp_path, capsys):
    code, out, err = run(["analyse", str(SAMPLE), "-o", str(tmp_path), "--no-plots", "--json"], capsys)
    assert code == 0, err
    payload = json.loads(out)
    assert payload["law_of"] == "output" and payload["working_member"]["round_trip_max"] < 1e-12
    assert [round(r["swing_deg"], 6) for r in payload["settings"]["rows"]] == [20.0, 22.0, 24.12, 26.0, 28.0]
    doc = ezdxf.readfile(tmp_path / "analysis.dxf")
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert {"PROFILE", "PITCH", "BASE_CIRCLE", "SETTINGS", "ADJUSTMENT", "FOLLOWER", "LINKS"} <= layers
    assert (tmp_path / "working.csv").exists() and (tmp_path / "settings.csv").exists()


def test_adjust_task1_from_options(tmp_path, capsys):
    code, out, err = run(["adjust", *FOURBAR, "--task", "1", "--swing-range", "10:20", "--count", "3", "-o",
                          str(tmp_path), "--no-plots", "--json"], capsys)
    assert code == 0, err
    payload = json.loads(out)
    assert payload["requirements"]["psi1"]["passed"] and payload["monotone"]
    assert payload["arc_radius_mm"] == pytest.approx(120.0)
    assert [round(r["swing_deg"], 9) for r in payload["rows"]] == [10.0, 15.0, 20.0]
    assert max(abs(r["psi1_deg"]) for r in payload["rows"]) < 1e-7


def test_family_from_a_table_of_members(tmp_path, capsys):
    """Three members made by one adjustable four-bar (output pivot on the arc F = (100, 10) mm, R = 15 mm at
    200, 240, 280 deg), tabulated every 0.25 deg: the command recovers the arc to the table's interpolation
    error (the library test recovers it to 1e-7 from the functions themselves)."""
    import cmath

    from camcad.linkage.analysis import Loop

    x = np.arange(0.0, 60.0001, 0.25)
    columns = [x]
    for setting in (200.0, 240.0, 280.0):
        c = complex(100.0, 10.0) + 15.0 * cmath.exp(1j * math.radians(setting))
        loop = Loop((0.0, 0.0), (c.real, c.imag), 40.0, 120.0, 90.0, 1)
        columns.append(np.degrees(np.unwrap(loop.output(np.radians(60.0 + x)))))
    table = tmp_path / "members.csv"
    table.write_text("x,m1,m2,m3\n" + "\n".join(",".join(f"{v:.17g}" for v in row) for row in np.column_stack(columns)))
    code, out, err = run(["family", "--table", str(table), "--phi", "0:60", "--crank", "40", "--phi0", "60", "-o",
                          str(tmp_path / "out"), "--no-plots", "--json"], capsys)
    assert code == 0, err
    payload = json.loads(out)
    assert payload["arc_centre_mm"] == pytest.approx([100.0, 10.0], abs=1e-3)
    assert payload["settings_deg"] == pytest.approx([-160.0, -120.0, -80.0], abs=1e-3)
    assert {"q", "arc_radius_mm", "rows", "position_evaluations"} <= set(payload)


def test_tune_finds_every_root_and_reproduces_the_extremes(tmp_path, capsys):
    code, out, err = run(["tune", *FOURBAR, "--element", "pivot", "--joint", "C", "--centre", "100,5", "--psi1",
                          "-2", "--psi2", "12", "--points", "361", "-o", str(tmp_path), "--no-plots", "--json"], capsys)
    assert code == 0, err
    roots = json.loads(out)["roots"]
    assert len(roots) >= 2 and all(r["error_deg"] < 1e-8 for r in roots)


@pytest.mark.parametrize("args, where", [
    (["analyse"], "--links"),
    (["analyse", "--links", "40,120", "--output-pivot", "100,20", "--input-angle", "80", "--swing", "30"], "--links"),
    (["analyse", *FOURBAR[:-2], "--sense", "2"], "--sense"),
    (["analyse", str(SAMPLE), "--links", "1,2,3"], "--links"),
    (["adjust", *FOURBAR, "--task", "9"], "--task"),
    (["adjust", *FOURBAR, "--task", "1"], "--swing-range"),
    (["family", "--member", "x", "--phi", "0:60"], "family"),
    (["family", "--member", "x^", "--member", "x", "--member", "x", "--phi", "0:60"], "--member 1"),
    (["tune", *FOURBAR, "--psi1", "1"], "--element"),
])
def test_bad_input_is_one_line_exit_2(args, where, capsys, tmp_path):
    code, _, err = run([*args, "-o", str(tmp_path)], capsys)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error:") and where in lines[0] and len(lines[0]) < 300


# --------------------------------------------------------------------------------------------
# the drawings in independent readers
# --------------------------------------------------------------------------------------------

def _reader(name: str) -> None:
    available = {"gdal": shutil.which("ogr2ogr") is not None,
                 "librecad": shutil.which("librecad") is not None and shutil.which("pdftoppm") is not None,
                 "inkscape": INKSCAPE_DXF.exists() and Path("/usr/bin/python3").exists()}[name]
    if not available:
        if REQUIRED:
            pytest.fail(f"DXF reader {name} is not installed but CAMCAD_REQUIRE_READERS=1")
        pytest.skip(f"DXF reader {name} is not installed")


@pytest.fixture(scope="module")
def diagram(tmp_path_factory):
    """The sample's combined sheet (linkage, settings, arc and cam) and an adjust drawing."""
    register_all()
    folder = tmp_path_factory.mktemp("linkage-dxf")
    assert run_app(app, ["linkage", "analyse", str(SAMPLE), "-o", str(folder / "a"), "--no-plots"]) == 0
    assert run_app(app, ["linkage", "adjust", *FOURBAR, "--task", "1", "--swing-range", "10:20", "--count", "3",
                         "-o", str(folder / "b"), "--no-plots"]) == 0
    return [folder / "a" / "analysis.dxf", folder / "b" / "adjust.dxf"]


def _counts(path: Path) -> Counter:
    return Counter(e.dxf.layer for e in ezdxf.readfile(path).modelspace())


def test_gdal_reads_every_entity_of_the_diagrams(diagram):
    _reader("gdal")
    for path in diagram:
        done = subprocess.run(["ogr2ogr", "-f", "GeoJSON", "/vsistdout/", str(path)], capture_output=True, text=True,
                              timeout=60, check=False)
        assert done.returncode == 0 and "ERROR" not in done.stderr, done.stderr
        features = json.loads(done.stdout)["features"]
        assert Counter(f["properties"]["Layer"] for f in features) == _counts(path)


def test_librecad_renders_the_diagrams(diagram, tmp_path):
    _reader("librecad")
    import matplotlib.image as mpimg

    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen", "XDG_RUNTIME_DIR": str(tmp_path)}
    for path in diagram:
        subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(tmp_path), str(path)], capture_output=True,
                       timeout=60, env=env, check=False)
        pdf = tmp_path / (path.stem + ".pdf")
        assert pdf.exists() and pdf.stat().st_size > 0
        subprocess.run(["pdftoppm", "-png", "-r", "40", "-singlefile", str(pdf), str(tmp_path / "page")], check=True,
                       timeout=60)
        page = mpimg.imread(tmp_path / "page.png")
        assert (np.mean(page[..., :3], axis=2) < 0.6).sum() > 200


def test_inkscape_imports_every_layer_of_the_diagrams(diagram):
    _reader("inkscape")
    import xml.etree.ElementTree as ET

    label = "{http://www.inkscape.org/namespaces/inkscape}label"
    for path in diagram:
        done = subprocess.run(["/usr/bin/python3", str(INKSCAPE_DXF), str(path)], capture_output=True, text=True,
                              timeout=60, cwd=INKSCAPE_DXF.parent, check=False)
        assert done.returncode == 0, done.stderr[-500:]
        drawn = {g.get(label): len(list(g)) for g in ET.fromstring(done.stdout).iter("{http://www.w3.org/2000/svg}g")
                 if g.get(label) is not None}
        for layer, n in _counts(path).items():
            assert drawn.get(layer, 0) >= n, (path.name, layer)
