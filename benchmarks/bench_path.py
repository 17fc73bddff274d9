"""How often ``camcad linkage path`` recovers a four-bar from nine points of its coupler curve, and at what cost.

Random crank-rockers (crank 10–40 mm, other links 40–160 mm, Grashof with the crank shortest, worst transmission
angle over a turn above 30 deg, coupler point anywhere within ±1.5 coupler lengths), nine points of each coupler
curve taken at crank angles

- ``uniform``: 40 deg apart (a whole turn),
- ``arc``: 25 deg apart (200 deg of the turn),
- ``random``: nine sorted random angles over the turn;

a case is recovered when the deviation method returns an admissible mechanism (μ >= 30 deg, ratio <= 10) whose
coupler curve passes every point within 1e-3 of the points' size. The points are made by this file's own closed
form. Run: ``python benchmarks/bench_path.py [N]`` (N crank-rockers per mode; prints one line per case and the
rates). The figures quoted in docs/linkage/path.md came from this script.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from camcad.linkage.fgen import Limits
from camcad.linkage.path import admissible, deviation_synthesis, make_target


def crank_rocker(rng):
    while True:
        a, b, c, d = rng.uniform(10, 40), rng.uniform(40, 160), rng.uniform(40, 160), rng.uniform(40, 160)
        if a + max(b, c, d) < sum((b, c, d)) - max(b, c, d) and a < min(b, c, d):
            theta = np.linspace(0, 2 * np.pi, 721)
            cos_mu = (b * b + c * c - (a * a + d * d - 2 * a * d * np.cos(theta))) / (2 * b * c)
            mu = np.degrees(np.arccos(np.clip(cos_mu, -1, 1)))
            if min(mu.min(), 180 - mu.max()) > 30:
                return a, b, c, d, rng.uniform(-0.5, 1.5) * b, rng.uniform(-1, 1) * b


def points(a, b, c, d, u, v, theta):
    a_pt = a * np.exp(1j * theta)
    f = np.abs(a_pt - d)
    b_pt = d + c * np.exp(1j * (np.angle(a_pt - d) + np.arccos((c * c + f * f - b * b) / (2 * c * f))))
    return a_pt + (u + 1j * v) * (b_pt - a_pt) / b


def main(count: int) -> None:
    limits = Limits(30.0, 10.0)
    for mode in ("uniform", "arc", "random"):
        rng = np.random.default_rng(7)
        hits, seconds = 0, []
        for case in range(count):
            a, b, c, d, u, v = crank_rocker(rng)
            start = rng.uniform(0, 2 * np.pi)
            if mode == "uniform":
                theta = start + np.radians(40.0 * np.arange(9))
            elif mode == "arc":
                theta = start + np.radians(25.0 * np.arange(9))
            else:
                theta = start + np.sort(rng.uniform(0, 2 * np.pi, 9))
            pts = points(a, b, c, d, u, v, theta)
            target = make_target("points", np.column_stack([pts.real, pts.imag]))
            t0 = time.process_time()
            result = deviation_synthesis(target, limits)
            seconds.append(time.process_time() - t0)
            ok = admissible(result.mechanism, result.check, limits) and \
                result.check.max_deviation <= 1e-3 * target.size
            hits += ok
            print(f"{mode:8s} case {case:2d}: deviation/size {result.check.max_deviation / target.size:.2e}, mu "
                  f"{result.check.mu_min_deg:.1f} deg, {'recovered' if ok else 'NOT recovered'}, "
                  f"{seconds[-1]:.1f} s CPU", flush=True)
        print(f"{mode}: {hits}/{count} recovered; CPU median {np.median(seconds):.1f} s, max {max(seconds):.1f} s",
              flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
