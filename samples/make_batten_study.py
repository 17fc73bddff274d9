"""Regenerate the batten study's files in samples/batten/ (run: python samples/make_batten_study.py).

The batten study (PhD abstract, Novosibirsk; docs/references.md section 2) starts from the serial STB
2-220 cam's tabulated radius-vectors, which it does not publish. So the table here is MADE, not measured:

1. a serial law is CHOSEN to meet the published figures that describe it: a swing of 0.421 rad and peak
   velocities of 23 and 30 rad/s at 330 and 420 rpm. A cycloidal rise and return of 72 deg each
   (v_max = 2h/beta = 0.670 rad/rad: 23.2 and 29.5 rad/s) after a 90 deg dwell; its peak accelerations,
   a_max = 2 pi h / beta^2 = 1.676 rad/rad^2, are 2001 and 3242 rad/s^2 against the published 2100 and 3000
   (which are not in the ratio (420/330)^2 of any rigid law: 2100 x 1.62 = 3402);
2. the cam profile for it is built with camcad's own geometry (camcad.profile.geometry.CamGeometry) on the
   batten's oscillating roller follower of samples/scenes/batten.toml (pivot 160 mm, arm 120 mm, base radius
   55 mm, roller 25 mm, counter-clockwise), and its radius-vectors are tabulated at every whole degree of
   polar angle, rounded to 0.001 mm as a drawing's table would be: serial_cam_r.csv;
3. the rest is camcad's commands on that table, in the order docs/batten.md gives them: the law the table
   gives (the scene's [law]), the law synthesised from the harmonic database with the serial law's own shapes
   and tachogram (synthesised.dxf), the synthesised law with the resonant harmonics and their neighbours
   removed (filtered.dxf), and the same with 14 deg lead-ins at 0.1 of the peak (new_law.dxf).
Deterministic: the same files every run.
"""

from __future__ import annotations

import math
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from camcad.cli import main  # noqa: E402 - the path above first
from camcad.law.standard import compose  # noqa: E402
from camcad.profile.followers import Follower  # noqa: E402
from camcad.profile.geometry import CamGeometry  # noqa: E402

HERE = Path(__file__).resolve().parent / "batten"
SCENE = Path(__file__).resolve().parent / "scenes" / "batten_study.toml"
PHASES = [("dwell", 90.0), ("rise", 72.0), ("return", 72.0), ("dwell", 126.0)]
SWING = 0.421   # rad (published)


def radius_table() -> str:
    law = compose(PHASES, SWING, "cycloidal")
    follower = Follower("oscillating", base_radius=55.0, roller_radius=25.0, pivot=160.0, arm=120.0)
    theta = np.radians(np.arange(0.0, 360.0, 0.002))
    points = CamGeometry(law, follower).profile(theta).points
    alpha = np.degrees(np.unwrap(np.arctan2(points[:, 1], points[:, 0])))
    radius = np.hypot(points[:, 0], points[:, 1])
    order = np.argsort(alpha)
    alpha, radius = alpha[order], radius[order]
    grid = np.arange(0.0, 360.0, 1.0)
    r = np.interp((grid - alpha[0]) % 360.0 + alpha[0], alpha, radius)
    rows = "".join(f"{t:g},{v:.3f}\n" for t, v in zip(grid, r))
    return ("# The serial batten cam's radius-vectors: MADE by samples/make_batten_study.py, not measured (the\n"
            "# source publishes no table): the profile of a chosen law (cycloidal rise and return of 72 deg, swing\n"
            "# 0.421 rad) on the batten's oscillating roller (pivot 160, arm 120, Rb 55, Rr 25 mm), polar angle in\n"
            "# the cam's frame (deg), radius rounded to 0.001 mm.\n"
            "theta_deg,r_mm\n" + rows)


def run(*args: str) -> None:
    try:
        main([str(a) for a in args])
    except SystemExit as stop:
        if stop.code not in (0, None):
            raise SystemExit(f"camcad {' '.join(map(str, args))} exited {stop.code}") from None


def main_() -> None:
    HERE.mkdir(exist_ok=True)
    (HERE / "serial_cam_r.csv").write_text(radius_table())
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        run("synth", "--shape-from", SCENE, "--shape", "drawn", "--harmonics", "48", "--dwell-tol", "0.002",
            "-o", out / "synth", "--no-plots")
        shutil.copy(out / "synth" / "synth.dxf", HERE / "synthesised.dxf")
        run("spectrum", HERE / "synthesised.dxf", "--fn", "113", "--rpm", "330:420", "--filter", "-o",
            out / "filtered", "--no-plots", "--unit", "rad")
        shutil.copy(out / "filtered" / "filtered.dxf", HERE / "filtered.dxf")
        run("spectrum", HERE / "synthesised.dxf", "--fn", "113", "--rpm", "330:420", "--filter", "--lead-in", "14",
            "--lead-in-fraction", "0.1", "-o", out / "new", "--no-plots", "--unit", "rad")
        shutil.copy(out / "new" / "filtered.dxf", HERE / "new_law.dxf")
    print(f"written: {', '.join(sorted(p.name for p in HERE.iterdir()))}; peak velocity "
          f"{2 * SWING / math.radians(72.0):.4f} rad/rad")


if __name__ == "__main__":
    main_()
