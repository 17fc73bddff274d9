"""The public API (``import camcad``): the workflow script runs, every exported name resolves and is
documented, and importing camcad loads no numerical library."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import ezdxf

import camcad

ROOT = Path(__file__).resolve().parents[2]


def test_the_workflow_script_runs_with_only_import_camcad(tmp_path):
    script = ROOT / "docs" / "examples" / "workflow.py"
    assert "from camcad." not in script.read_text() and "import camcad." not in script.read_text()
    done = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "balanced after: True" in done.stdout
    doc = ezdxf.readfile(tmp_path / "profile.dxf")
    assert doc.modelspace().query("LWPOLYLINE[layer=='PROFILE']")[0].closed
    assert (tmp_path / "summary.png").stat().st_size > 10_000


def test_every_public_name_resolves_and_has_a_docstring():
    for name in camcad.__all__:
        value = getattr(camcad, name)
        if name == "__version__":
            continue
        assert (value.__doc__ or "").strip(), name


def test_import_camcad_loads_no_numerical_library():
    code = "import sys, camcad; print(sorted(m for m in ('numpy', 'scipy', 'matplotlib', 'ezdxf') if m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "[]", done.stdout
