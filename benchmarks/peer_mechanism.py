"""Run the PyPI package ``mechanism`` (the peer) on the peer-comparison cam; print one JSON object.

This script runs inside ``benchmarks/.peer-venv`` (made by ``bench_peer.py``), never in camcad's
environment, and imports nothing from camcad. It reads its settings as one JSON object on stdin:

    {"lift_mm": 20, "base_radius_mm": 40, "roller_radius_mm": 10, "steps_rad": [0.0062, ...],
     "repeats": 5, "max_pressure_angle_deg": 23.23...}

and prints, for each step h of the package's θ grid (``np.arange(0, 2π, h)``):

- ``theta``: the grid (rad);
- ``profile_x/y``: the points ``Cam.save_coordinates(kind="cycloidal", base=Rb)`` writes (read
  back from its CSV file), and ``pitch_x/y``: ``Motion.get_profile(Rb + Rr, thetas_r)``, the call
  ``Cam.profile(show_pitch=True, roller_radius=Rr)`` draws its pitch curve with. Both are in the
  package's own frame (mm): the point of cam angle θ at polar angle −θ (ccw), radius base + s(θ);
  ``bench_peer.py`` turns them into camcad's frame;
- ``time_profile_s``: median time of ``Cam(...)`` plus ``cam.cycloidal.get_profile(Rb, ...)``
  (building the motion on the grid and the profile coordinates, no file, no plot);
- ``time_base_circle_s``: median time of ``Cam.get_base_circle(kind="cycloidal",
  follower="roller", roller_radius=Rr, max_pressure_angle=φ)`` without its plot;
- ``base_circle``: the base radius it returns and its minimum pitch radius of curvature, and
  ``phis_deg``: the |pressure angle| (deg) on the grid at that base radius, which the package
  returns only when asked to plot (the plot goes to matplotlib's Agg backend and is closed).

The package takes the law as ``[("Dwell", 90), ("Rise", h, 90), ("Dwell", 90), ("Fall", h, 90)]``
with ``degrees=True``; ``omega=1`` rad/s makes its time derivatives V/ω, A/ω² equal to the
analogs ds/dθ, d²s/dθ² it uses for sizing.

Run (by bench_peer.py): .peer-venv/bin/python benchmarks/peer_mechanism.py < settings.json
"""

from __future__ import annotations

import csv
import json
import os
import sys
import tempfile
import warnings

from timing import median_time


def timed(function, repeats: int):
    return median_time(function, repeats, warm_up=False)


def read_coordinates(path: str) -> tuple[list[float], list[float]]:
    """The x, y columns of a CSV file written by ``Cam.save_coordinates(..., solidworks=False)``."""
    xs, ys = [], []
    with open(path, newline="") as handle:
        rows = csv.reader(handle)
        next(rows)  # header "x,y"
        for row in rows:
            xs.append(float(row[0]))
            ys.append(float(row[1]))
    return xs, ys


def main() -> None:
    os.environ.setdefault("MPLBACKEND", "Agg")
    warnings.filterwarnings("ignore")  # the package's plot=True path calls plt.show() on Agg
    import importlib.metadata

    import matplotlib.pyplot as plt
    import numpy as np
    from mechanism import Cam

    settings = json.load(sys.stdin)
    lift = float(settings["lift_mm"])
    rb = float(settings["base_radius_mm"])
    rr = float(settings["roller_radius_mm"])
    repeats = int(settings["repeats"])
    phi_limit = float(settings["max_pressure_angle_deg"])
    motion = [("Dwell", 90), ("Rise", lift, 90), ("Dwell", 90), ("Fall", lift, 90)]

    runs = []
    for step in settings["steps_rad"]:
        def build(step=step):
            cam = Cam(motion=motion, degrees=True, omega=1.0, rotation="ccw", h=step)
            x, y = cam.cycloidal.get_profile(rb, cam.thetas_r)
            return cam, x, y

        def size(cam):
            return cam.get_base_circle(kind="cycloidal", follower="roller", roller_radius=rr,
                                       max_pressure_angle=phi_limit)

        time_profile, (cam, x, y) = timed(build, repeats)
        time_base, _ = timed(lambda cam=cam: size(cam), repeats)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "cam.csv")
            cam.save_coordinates(path, kind="cycloidal", base=rb)
            saved_x, saved_y = read_coordinates(path)
        pitch_x, pitch_y = cam.cycloidal.get_profile(rb + rr, cam.thetas_r)
        sized = cam.get_base_circle(kind="cycloidal", follower="roller", roller_radius=rr,
                                    max_pressure_angle=phi_limit, plot=True)
        plt.close("all")
        runs.append({
            "step_rad": step,
            "theta": cam.thetas.tolist(),
            "profile_x": saved_x, "profile_y": saved_y,
            "saved_vs_memory_mm": float(max(np.max(np.abs(np.asarray(saved_x) - x)),
                                            np.max(np.abs(np.asarray(saved_y) - y)))),
            "pitch_x": pitch_x.tolist(), "pitch_y": pitch_y.tolist(),
            "time_profile_s": time_profile, "time_base_circle_s": time_base,
            "base_circle": {"rb_mm": float(sized["Rb"]), "min_rho_pitch_mm": float(sized["Min Rho"])},
            "phis_deg": np.asarray(sized["phis"], dtype=float).tolist(),
        })
    json.dump({"version": importlib.metadata.version("mechanism"), "runs": runs}, sys.stdout)


if __name__ == "__main__":
    main()
