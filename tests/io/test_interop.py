"""Every kind of DXF camcad writes, read by independent CAD readers: GDAL (ogr2ogr), LibreCAD (dxf2pdf) and
Inkscape (its DXF import extension).

The readers are Debian packages that `.ci/run` installs and then requires (CAMCAD_REQUIRE_READERS=1): in
CI a missing reader is a failure, not a skip. On a machine without them these tests are skipped.
Checks per reader: GDAL — entity types and counts per layer equal ezdxf's, the profile is closed, its
coordinates lie on the exact profile within the chord tolerance; LibreCAD — the drawing renders to a PDF
page with ink on it; Inkscape — every layer with entities becomes a layer with as many drawn elements.
"""

from __future__ import annotations

import os
import subprocess
from collections import Counter

import numpy as np
import pytest
from conftest import SAMPLES
from dxf_readers import INKSCAPE_DXF
from dxf_readers import ezdxf_counts as _ezdxf_counts
from dxf_readers import gdal_features as _gdal
from dxf_readers import require_reader as _reader

TOL_MM = 1e-3


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """{kind: (path, exact profile or None)} for every kind of DXF camcad writes."""
    from camcad.io.law_write import write_law_dxf
    from camcad.law.standard import compose
    from camcad.profile.followers import Follower
    from camcad.profile.geometry import CamGeometry
    from camcad.profile.synth import ProfileSettings, synthesize
    from camcad.report.profile_files import write_outputs

    root = tmp_path_factory.mktemp("interop")
    law = compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 25.0, "cycloidal", "poly345")
    roller = Follower("roller", base_radius=50.0, roller_radius=10.0)
    swinging = Follower("oscillating", base_radius=40.0, roller_radius=8.0, pivot=110.0, arm=80.0)
    from camcad.profile.scaled_law import swing_law

    cases = {
        "profile_r2000": (law, roller, dict()),
        "profile_r12": (law, roller, dict(r12=True)),
        "profile_arcs": (law, roller, dict(arcs=True)),
        "profile_r12_arcs": (law, roller, dict(r12=True, arcs=True)),
        "profile_spline": (law, roller, dict(spline=True)),
        "profile_oscillating": (swing_law(law, arm_mm=80.0, swing_deg=15.0), swinging, dict(arcs=True)),
    }
    files = {}
    for name, (case_law, follower, flags) in cases.items():
        settings = ProfileSettings(tol_mm=TOL_MM, plots=False, design=False, name=name, **flags)
        result = synthesize(case_law, follower, settings)
        write_outputs(result, root / name, settings)
        files[name] = (root / name / "profile.dxf", CamGeometry(case_law, follower))
    theta = np.linspace(0, 360, 721)
    accel = law.kinematics(np.radians(theta)).a
    files["law_r2000"] = (write_law_dxf(root / "law.dxf", theta, accel), None)
    files["law_r12"] = (write_law_dxf(root / "law12.dxf", theta, accel, r12=True), None)
    # a corrected copy of a user's drawing (axes, grid, text, dimension and the kept original)
    from camcad.cli import main

    fixed = root / "fixed.dxf"
    with pytest.raises(SystemExit) as stop:
        main(["fix", str(SAMPLES / "dxf" / "drawing_with_axes_grid_text.dxf"), "-o", str(fixed), "--no-plots",
              "--json"])
    assert stop.value.code == 0
    files["fixed_drawing"] = (fixed, None)
    return files


KINDS = ["profile_r2000", "profile_r12", "profile_arcs", "profile_r12_arcs", "profile_spline", "profile_oscillating",
         "law_r2000", "law_r12", "fixed_drawing"]


GDAL_KIND = {"AcDbPolyline": "LWPOLYLINE", "AcDb2dPolyline": "POLYLINE", "AcDbLine": "LINE", "AcDbCircle": "CIRCLE",
             "AcDbText": "TEXT", "AcDbSpline": "SPLINE", "AcDbMText": "MTEXT", "AcDbArc": "ARC"}


def _gdal_kind(feature: dict) -> str:
    classes = (feature["properties"].get("SubClasses") or "").split(":")
    for name in reversed(classes):
        if name in GDAL_KIND:
            return GDAL_KIND[name]
    # R12 files carry no subclass markers: tell the entity by its geometry
    geometry = feature["geometry"]["type"] if feature["geometry"] else ""
    return {"Point": "TEXT"}.get(geometry, "?")


@pytest.mark.reference("second method", "GDAL's ogr2ogr (an independent reader): every entity by layer and the exact "
                                        "coordinates")
@pytest.mark.parametrize("kind", KINDS)
def test_gdal_reads_every_entity_and_the_exact_coordinates(written, kind):
    _reader("gdal")
    path, cam = written[kind]
    features = _gdal(path)
    ours = _ezdxf_counts(path)
    by_layer = Counter(f["properties"]["Layer"] for f in features)
    expected_by_layer = Counter()
    for (layer, _), n in ours.items():
        expected_by_layer[layer] += n
    if kind == "fixed_drawing":
        # the dimension's own parts appear as extra features on its layer; every other layer matches
        for layer, n in expected_by_layer.items():
            assert by_layer[layer] >= n, layer
    else:
        assert by_layer == expected_by_layer
        if not kind.endswith("r12") and "r12" not in kind:
            assert Counter((f["properties"]["Layer"], _gdal_kind(f)) for f in features) == ours
    if cam is None:
        return
    profile = [f for f in features if f["properties"]["Layer"] == "PROFILE"]
    assert len(profile) == 1
    points = np.array(profile[0]["geometry"]["coordinates"])[:, :2]
    assert np.allclose(points[0], points[-1], atol=1e-9)            # closed
    theta = np.linspace(0.0, 2 * np.pi, 400_001)
    exact = cam.profile(theta).points
    from scipy.spatial import cKDTree

    distance, _ = cKDTree(exact).query(points)
    assert distance.max() <= TOL_MM * 1.001 + 1e-6, distance.max()


@pytest.mark.reference("second method", "LibreCAD's dxf2pdf (an independent reader) draws each file")
@pytest.mark.parametrize("kind", KINDS)
def test_librecad_renders_every_file(written, kind, tmp_path):
    _reader("librecad")
    path, _ = written[kind]
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen", "XDG_RUNTIME_DIR": str(tmp_path)}
    subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(tmp_path), str(path)], capture_output=True,
                   timeout=60, env=env)
    pdf = tmp_path / (path.stem + ".pdf")
    assert pdf.exists() and pdf.stat().st_size > 0, "LibreCAD wrote no PDF"
    subprocess.run(["pdftoppm", "-png", "-r", "40", "-singlefile", str(pdf), str(tmp_path / "page")], check=True,
                   timeout=60)
    import matplotlib.image as mpimg

    page = mpimg.imread(tmp_path / "page.png")
    ink = np.mean(page[..., :3], axis=2) < 0.6
    assert ink.sum() > 200, f"the rendered page is (nearly) blank: {ink.sum()} dark pixels"


@pytest.mark.reference("second method", "Inkscape's DXF import (an independent reader): every layer drawn")
@pytest.mark.parametrize("kind", KINDS)
def test_inkscape_imports_every_layer(written, kind):
    _reader("inkscape")
    path, _ = written[kind]
    done = subprocess.run(["/usr/bin/python3", str(INKSCAPE_DXF), str(path)], capture_output=True, text=True,
                          timeout=60, cwd=INKSCAPE_DXF.parent)
    assert done.returncode == 0, done.stderr[-500:]
    import xml.etree.ElementTree as ET

    root = ET.fromstring(done.stdout)
    label = "{http://www.inkscape.org/namespaces/inkscape}label"
    drawn = {}
    for group in root.iter("{http://www.w3.org/2000/svg}g"):
        if group.get(label) is not None:
            drawn[group.get(label)] = [c.tag.split("}")[1] for c in group]
    ours = _ezdxf_counts(path)
    for (layer, _entity), _ in ours.items():
        expected = sum(n for (other, _e), n in ours.items() if other == layer)
        if kind == "fixed_drawing" and layer == "CAMCAD_ORIGINAL":
            continue  # a layer that is switched off is not imported as drawn geometry by every reader
        assert len(drawn.get(layer, [])) >= expected, (layer, drawn.get(layer))
