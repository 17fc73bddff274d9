"""The independent DXF readers the tests drive (GDAL's ogr2ogr, LibreCAD, Inkscape's DXF import), shared by
tests/io/test_interop.py and tests/cli/test_linkage_cli.py.

The readers are Debian packages that `.ci/run` installs and then requires (CAMCAD_REQUIRE_READERS=1): in CI a
missing reader is a failure, not a skip; elsewhere the test is skipped and says which reader is missing.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from collections import Counter
from pathlib import Path

import ezdxf
import pytest

INKSCAPE_DXF = Path("/usr/share/inkscape/extensions/dxf_input.py")
REQUIRED = os.environ.get("CAMCAD_REQUIRE_READERS") == "1"


def require_reader(name: str) -> None:
    """Skip (or, with CAMCAD_REQUIRE_READERS=1, fail) unless the reader ``name`` (gdal, librecad, inkscape) is
    installed."""
    available = {"gdal": shutil.which("ogr2ogr") is not None,
                 "librecad": shutil.which("librecad") is not None and shutil.which("pdftoppm") is not None,
                 "inkscape": INKSCAPE_DXF.exists() and Path("/usr/bin/python3").exists()}[name]
    if not available:
        if REQUIRED:
            pytest.fail(f"DXF reader {name} is not installed but CAMCAD_REQUIRE_READERS=1")
        pytest.skip(f"DXF reader {name} is not installed")


def ezdxf_counts(path: Path) -> Counter:
    """{(layer, entity type): count} of the model space, as ezdxf reads it (dimensions left out: GDAL explodes
    a dimension into its lines, arrows and text)."""
    doc = ezdxf.readfile(path)
    counts: Counter = Counter()
    for entity in doc.modelspace():
        kind = entity.dxftype()
        if kind == "DIMENSION":
            continue
        counts[(entity.dxf.layer, kind)] += 1
    return counts


def gdal_features(path: Path) -> list[dict]:
    """The drawing's features as GDAL's ogr2ogr reads them (GeoJSON), with no error on its stderr."""
    done = subprocess.run(["ogr2ogr", "-f", "GeoJSON", "/vsistdout/", str(path)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert "ERROR" not in done.stderr, done.stderr
    return json.loads(done.stdout)["features"]
