"""A corrected drawing shows one law in LibreCAD, Inkscape and LibreOffice, not the corrected and the original.

The corrected law here is the drawn one mirrored (a → −a), so a drawn original would add a whole second
curve. Each reader renders the input, the corrected copy and a control (the copy with the original put
back in model space, as a reader that drew the kept original would show it):
- LibreCAD (dxf2pdf) and LibreOffice (soffice --convert-to pdf): the ink of the page (pixels that are
  not white, pdftoppm at 50 dpi) — the copy's must match the input's, the control's must be clearly more;
- Inkscape (its DXF import): the drawn paths of the SVG (outside <defs>, where unreferenced blocks go).
The readers are Debian packages that .ci/run installs; with CAMCAD_REQUIRE_READERS=1 a missing one fails.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from ezdxf import appsettings

from camcad.io.law_write import write_corrected_drawing
from camcad.law.source import load_law

INKSCAPE_DXF = Path("/usr/share/inkscape/extensions/dxf_input.py")
REQUIRED = os.environ.get("CAMCAD_REQUIRE_READERS") == "1"


def _need(*programs: str) -> None:
    missing = [p for p in programs if shutil.which(p) is None and not Path(p).exists()]
    if missing:
        if REQUIRED:
            pytest.fail(f"{', '.join(missing)} not installed but CAMCAD_REQUIRE_READERS=1")
        pytest.skip(f"{', '.join(missing)} not installed")


@pytest.fixture(scope="module")
def drawings(tmp_path_factory):
    """{input, fixed, control}: the drawn law, its corrected copy, and the copy with the original drawn too."""
    root = tmp_path_factory.mktemp("render")
    doc = ezdxf.new("R2000")
    doc.units = 4
    doc.layers.add("ACCEL", color=1)
    doc.layers.add("AXES", color=8)
    theta = np.linspace(0, 360, 181)
    accel = 40 * np.sin(np.radians(theta)) + 25 * np.sin(np.radians(3 * theta))
    doc.modelspace().add_lwpolyline(list(zip(theta, accel)), dxfattribs={"layer": "ACCEL"})
    doc.modelspace().add_line((0, 0), (360, 0), dxfattribs={"layer": "AXES"})
    appsettings.update_extents(doc)
    source = root / "input.dxf"
    doc.saveas(source)
    loaded = load_law(source, cycle_deg=360.0)   # a sine over the sheet: the cycle is stated
    fixed, _ = write_corrected_drawing(loaded, loaded.law.with_ordinates(-loaded.law.a), root / "fixed.dxf")
    control_doc = ezdxf.readfile(fixed)
    for entity in control_doc.blocks.get("CAMCAD_ORIGINAL"):
        copy = entity.copy()
        copy.dxf.layer = "ACCEL"
        control_doc.modelspace().add_entity(copy)
    control = root / "control.dxf"
    control_doc.saveas(control)
    return {"input": source, "fixed": fixed, "control": control}


def _ink(pdf: Path) -> int:
    from PIL import Image

    png = pdf.with_suffix("")
    subprocess.run(["pdftoppm", "-png", "-r", "50", "-singlefile", str(pdf), str(png)], check=True, timeout=60)
    pixels = np.asarray(Image.open(png.with_suffix(".png")).convert("RGB")).astype(int)
    return int(np.count_nonzero(pixels.min(axis=2) < 235))


def _assert_one_law(ink: dict) -> None:
    assert ink["input"] > 0
    assert 0.8 <= ink["fixed"] / ink["input"] <= 1.25, ink      # one law, as in the input
    assert ink["control"] / ink["input"] >= 1.4, ink              # two laws are clearly more ink


@pytest.mark.reference("second method", "LibreCAD's rendering (an independent reader): one law drawn, not two")
def test_librecad_draws_one_law(drawings, tmp_path):
    _need("librecad", "pdftoppm")
    ink = {}
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    for name, path in drawings.items():
        # LibreCAD exits 0 whatever happens: the PDF it writes (or not) is the evidence
        subprocess.run(["librecad", "dxf2pdf", "-a", "-t", str(tmp_path), str(path)], env=env, timeout=60,
                       capture_output=True, check=False)
        ink[name] = _ink(tmp_path / f"{path.stem}.pdf")
    _assert_one_law(ink)


@pytest.mark.reference("second method", "LibreOffice's rendering (an independent reader): one law drawn, not two")
def test_libreoffice_draws_one_law(drawings, tmp_path):
    _need("soffice", "pdftoppm")
    profile = tmp_path / "profile"
    subprocess.run(["soffice", f"-env:UserInstallation=file://{profile}", "--headless", "--convert-to", "pdf",
                    "--outdir", str(tmp_path), *map(str, drawings.values())], timeout=180, capture_output=True,
                   check=True)
    ink = {name: _ink(tmp_path / f"{path.stem}.pdf") for name, path in drawings.items()}
    _assert_one_law(ink)


@pytest.mark.reference("second method", "Inkscape's import (an independent reader): one law drawn, the control shows "
                                        "two")
def test_inkscape_draws_one_law(drawings):
    _need(str(INKSCAPE_DXF), "/usr/bin/python3")
    drawn = {}
    for name, path in drawings.items():
        svg = subprocess.run(["/usr/bin/python3", INKSCAPE_DXF.name, str(path)], cwd=INKSCAPE_DXF.parent,
                             capture_output=True, timeout=60, check=True).stdout
        tree = ET.fromstring(svg)
        defs = {id(e) for d in tree.iter("{http://www.w3.org/2000/svg}defs") for e in d.iter()}
        drawn[name] = sum(1 for e in tree.iter("{http://www.w3.org/2000/svg}path") if id(e) not in defs)
    assert drawn["fixed"] == drawn["input"], drawn
    assert drawn["control"] == drawn["input"] + 1, drawn
