"""`camcad linkage atlas|fgen`: JSON contract, exit codes, one-line errors, deterministic files, DXF that
GDAL, LibreCAD and Inkscape read, and the layering of the new modules."""

from __future__ import annotations

import ast
import json
import os
import subprocess
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, file_digest
from dxf_readers import INKSCAPE_DXF
from dxf_readers import ezdxf_counts as _ezdxf_counts
from dxf_readers import gdal_features as _gdal
from dxf_readers import require_reader as _reader

LOG10 = ["--function", "log10(x)", "--x", "1:2", "--input-range", "60", "--output-range", "90"]


@pytest.fixture(scope="module")
def atlas_run(tmp_path_factory):
    from camcad.cli import main

    folder = tmp_path_factory.mktemp("atlas")
    runs = []
    for name in ("a", "b"):
        out = folder / name
        with pytest.raises(SystemExit) as stop:
            main(["linkage", "atlas", "--links", "6", "--dof", "1", "--adjustable", "2", "-o", str(out), "--json"])
        runs.append((stop.value.code, out))
    return runs


@pytest.fixture(scope="module")
def fgen_run(tmp_path_factory):
    from camcad.cli import main

    folder = tmp_path_factory.mktemp("fgen")
    runs = []
    for name in ("a", "b"):
        out = folder / name
        with pytest.raises(SystemExit) as stop:     # plots in the first run only (the atlas checks PNG bytes)
            main(["linkage", "fgen", *LOG10, "-o", str(out), "--json"] + (["--no-plots"] if name == "b" else []))
        runs.append((stop.value.code, out))
    return runs


def test_atlas_json_contract(cli, tmp_path):
    result = cli("linkage", "atlas", "--links", "6", "--dof", "1", "--adjustable", "1", "-o", tmp_path, "--json",
                 "--no-plots")
    assert result.code == 0, result.err
    payload = result.json()
    assert payload["count"] == payload["seed_count"] == 7
    assert len(payload["chains"]) == 7 and "rule" in payload
    assert all(len(c["locked_pairs"]) == 1 for c in payload["chains"])
    ordinary = cli("linkage", "atlas", "--links", "7", "--dof", "2", "-o", tmp_path / "o", "--json", "--no-plots")
    assert ordinary.json()["count"] == ordinary.json()["published_count"] == 4
    assert [c["fractionated"] for c in ordinary.json()["chains"]].count(True) == 1   # two four-bar loops on one link


def test_atlas_text_states_the_table1_discrepancy():
    from camcad.linkage.runners import AtlasRequest, run_linkage_atlas

    out = "\n".join(run_linkage_atlas(AtlasRequest(8, 1, 1)).lines())
    assert "285" in out and "137" in out and "287" in out and "NOT reproduced" in out


def test_atlas_outputs_are_written_and_deterministic(atlas_run):
    (code_a, a), (code_b, b) = atlas_run
    assert code_a == code_b == 0
    for name in ("atlas.json", "atlas.csv", "atlas.dxf", "atlas.png"):
        assert (a / name).stat().st_size > 0
        if name != "atlas.json":      # the JSON names its own folder
            assert file_digest(a / name) == file_digest(b / name), name
    data = json.loads((a / "atlas.json").read_text())
    assert data["count"] == 38


@pytest.mark.parametrize("args, words", [
    (["--links", "5", "--dof", "1"], ["odd", "--links"]),
    (["--links", "12", "--dof", "1"], ["beyond", "--links 10"]),
    (["--links", "4", "--dof", "1", "--adjustable", "0"], ["--adjustable"]),
    (["--links", "4", "--dof", "3"], ["W <= 1"]),
])
def test_atlas_bad_input_is_one_line_and_exit_2(cli, tmp_path, args, words):
    result = cli("linkage", "atlas", *args, "-o", tmp_path)
    assert result.code == 2
    assert result.err.count("\n") == 1 and result.err.startswith("camcad: error:")
    for word in words:
        assert word in result.err


def test_fgen_json_contract_and_files(fgen_run):
    (code_a, a), (code_b, b) = fgen_run
    assert code_a == code_b == 0
    payload = json.loads((a / "fgen.json").read_text())
    for key in ("method", "links", "max_error_deg", "rms_error_deg", "mu_min_deg", "position_evaluations",
                "nodes_deg"):
        assert key in payload
    assert set(payload["links"]) == {"a", "b", "c", "d"}
    assert payload["method"] == "q" and len(payload["nodes_deg"]) == 5
    assert payload["checks"]["transmission_angle"]["margin"] >= -1e-9
    for name in ("error.png", "positions.png", "pivots.png"):
        assert (a / name).stat().st_size > 10_000, name
    for name in ("error.csv", "linkage.dxf"):
        assert file_digest(a / name) == file_digest(b / name), name
    # the CSV's error column is the target minus the mechanism, as the header says
    rows = np.loadtxt(a / "error.csv", delimiter=",", comments="#", skiprows=2)
    assert rows[:, 4] == pytest.approx(rows[:, 3] - rows[:, 2], abs=1e-8)
    assert np.abs(rows[:, 4]).max() == pytest.approx(payload["max_error_deg"], rel=1e-3)


@pytest.mark.parametrize("args, words", [
    (["--function", "log10(x", "--x", "1:2"], ["position 8", "--function"]),
    (["--function", "__import__('os')", "--x", "1:2"], ["unknown name", "position 1"]),
    (["--function", "sin(x)", "--x", "0:4"], ["monotone", "--function"]),
    (["--function", "log10(x)", "--x", "-1:1"], ["not defined", "x = -1"]),
    (["--function", "log10(x)", "--x", "1:2", "--nodes", "4"], ["--nodes", "S >= 5"]),
    (["--function", "log10(x)", "--x", "1:2", "--nodes", "6"], ["--nodes", "not whole"]),
    (["--function", "log10(x)", "--x", "1:2", "--method", "nope"], ["--method"]),
    (["--function", "log10(x)", "--x", "1to2"], ["--x"]),
    (["--x", "1:2"], ["--function", "--table"]),
])
def test_fgen_bad_input_is_one_line_and_exit_2(cli, tmp_path, args, words):
    result = cli("linkage", "fgen", *args, "--input-range", "60", "--output-range", "90", "-o", tmp_path,
                 "--no-plots")
    assert result.code == 2, result.out
    assert result.err.count("\n") == 1 and result.err.startswith("camcad: error:")
    for word in words:
        assert word in result.err


def test_fgen_from_a_table_and_never_over_the_input(cli, tmp_path):
    x = np.linspace(1.0, 2.0, 41)
    table = tmp_path / "error.csv"
    table.write_text("x,y\n" + "\n".join(f"{a:.12g},{np.log10(a):.15g}" for a in x) + "\n")
    before = table.read_bytes()
    refused = cli("linkage", "fgen", "--table", table, "--input-range", "60", "--output-range", "90",
                  "--method", "precision", "--phi0", "45", "--psi0", "135", "-o", tmp_path, "--no-plots")
    assert refused.code == 2 and "overwrite" in refused.err
    assert table.read_bytes() == before
    done = cli("linkage", "fgen", "--table", table, "--input-range", "60", "--output-range", "90", "--method",
               "precision", "--phi0", "45", "--psi0", "135", "-o", tmp_path / "out", "--no-plots", "--json")
    payload = done.json()
    assert payload["method"] == "precision" and len(payload["nodes_deg"]) == 3
    # the same closed form from the expression: the spline table reproduces it closely
    same = cli("linkage", "fgen", *LOG10, "--method", "precision", "--phi0", "45", "--psi0", "135",
               "-o", tmp_path / "expr", "--no-plots", "--json").json()
    assert payload["links"]["a"] == pytest.approx(same["links"]["a"], rel=1e-4)


def test_a_target_no_four_bar_can_follow(cli, tmp_path):
    # a steep S-curve: the Q method's pivot circles never meet (exit 2, saying why); the precision method
    # returns its best mechanism, whose error check fails (exit 1, with the margin)
    common = ["--function", "tanh(12*(x-0.5))", "--x", "0:1", "--input-range", "60", "--output-range", "90",
              "--no-plots"]
    q = cli("linkage", "fgen", *common, "-o", tmp_path / "q")
    assert q.code == 2 and "beyond a four-bar" in q.err and q.err.count("\n") == 1
    result = cli("linkage", "fgen", *common, "--method", "precision", "--max-error", "0.5", "-o", tmp_path / "p",
                 "--json")
    assert result.code == 1
    payload = result.json()
    assert payload["checks"]["max_error"]["passed"] is False
    assert payload["max_error_deg"] > 0.5 and payload["checks"]["max_error"]["margin"] < 0


def _dxf_files(atlas_run, fgen_run):
    return {"atlas": atlas_run[0][1] / "atlas.dxf", "linkage": fgen_run[0][1] / "linkage.dxf"}


@pytest.mark.parametrize("kind", ["atlas", "linkage"])
def test_gdal_reads_every_entity(atlas_run, fgen_run, kind):
    _reader("gdal")
    path = _dxf_files(atlas_run, fgen_run)[kind]
    features = _gdal(path)
    ours = _ezdxf_counts(path)
    expected = Counter()
    for (layer, _), n in ours.items():
        expected[layer] += n
    assert Counter(f["properties"]["Layer"] for f in features) == expected


@pytest.mark.parametrize("kind", ["atlas", "linkage"])
def test_librecad_renders(atlas_run, fgen_run, kind, tmp_path):
    _reader("librecad")
    path = _dxf_files(atlas_run, fgen_run)[kind]
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen", "XDG_RUNTIME_DIR": str(tmp_path)}
    subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(tmp_path), str(path)], capture_output=True, timeout=60,
                   env=env, check=False)
    pdf = tmp_path / (path.stem + ".pdf")
    assert pdf.exists() and pdf.stat().st_size > 0
    subprocess.run(["pdftoppm", "-png", "-r", "40", "-singlefile", str(pdf), str(tmp_path / "page")], check=True,
                   timeout=60)
    import matplotlib.image as mpimg

    page = mpimg.imread(tmp_path / "page.png")
    assert (np.mean(page[..., :3], axis=2) < 0.6).sum() > 200


@pytest.mark.parametrize("kind", ["atlas", "linkage"])
def test_inkscape_imports_every_layer(atlas_run, fgen_run, kind):
    _reader("inkscape")
    path = _dxf_files(atlas_run, fgen_run)[kind]
    done = subprocess.run(["/usr/bin/python3", str(INKSCAPE_DXF), str(path)], capture_output=True, text=True,
                          timeout=60, cwd=INKSCAPE_DXF.parent, check=False)
    assert done.returncode == 0, done.stderr[-500:]
    import xml.etree.ElementTree as ET

    root = ET.fromstring(done.stdout)
    label = "{http://www.inkscape.org/namespaces/inkscape}label"
    drawn = {g.get(label): len(list(g)) for g in root.iter("{http://www.w3.org/2000/svg}g") if g.get(label)}
    per_layer = Counter()
    for (layer, _), n in _ezdxf_counts(path).items():
        per_layer[layer] += n
    for layer, n in per_layer.items():
        assert drawn.get(layer, 0) >= n, (layer, drawn.get(layer))


FORBIDDEN = {"camcad/linkage": ("matplotlib", "camcad.report", "camcad.cli", "..report", "..cli"),
             "camcad/report/linkage.py": ("camcad.cli", "..cli")}


def test_layering_of_the_linkage_modules():
    files = list((ROOT / "camcad" / "linkage").glob("*.py")) + [ROOT / "camcad" / "report" / "linkage.py"]
    for path in files:
        key = "camcad/report/linkage.py" if path.name == "linkage.py" and path.parent.name == "report" \
            else "camcad/linkage"
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = ["." * node.level + (node.module or "")]
            for name in names:
                assert not any(name == f or name.startswith(f + ".") for f in FORBIDDEN[key]), (path, name)
    assert Path(ROOT / "camcad" / "cli" / "linkage.py").exists()
