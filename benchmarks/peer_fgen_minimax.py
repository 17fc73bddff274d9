"""A fair peer for camcad's four-bar function generator: a straightforward scipy SLSQP minimax with the
transmission-angle and link-ratio limits as constraints, written without camcad (its own closed-form four-bar,
its own Freudenstein starts, its own limits).

What a user would write with scipy alone:

1. starts: Freudenstein's three-precision-point equation K1 cos β − K2 cos θ + K3 = cos(θ − β) at the three
   Chebyshev points, the offsets φ0, ψ0 scanned on a ``grid_deg`` grid; the admissible solutions of least
   maximum error on 41 points are kept (``starts`` of them);
2. from each: minimise E over (log b, log c, log d, φ0, ψ0, E), a = 1, subject to |Δψ(φ_k)| <= E on
   ``points`` Chebyshev points of the range, |cos μ| <= cos μ_min at the range's ends and where the crank lies
   on the frame line, and log(l_i/l_j) <= log R_max (SLSQP);
3. the result of least maximum error on a 4001-point check.

Run ``python benchmarks/peer_fgen_minimax.py [--random N]`` for the log10 and x² figures the docs quote
(``--random N`` adds N random starts per branch: the multistart evidence for the global optimum).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.optimize import minimize


def output_angle(a, b, c, d, theta, sigma):
    """Output angle of the four-bar O=(0,0), C=(d,0), crank a at θ, coupler b, rocker c; NaN if it opens."""
    ax, ay = a * np.cos(theta), a * np.sin(theta)
    vx, vy = ax - d, ay
    f = np.hypot(vx, vy)
    cos_g = (c * c + f * f - b * b) / (2 * c * f)
    with np.errstate(invalid="ignore"):
        return np.where(np.abs(cos_g) <= 1, np.arctan2(vy, vx) + sigma * np.arccos(np.clip(cos_g, -1, 1)), np.nan)


def cos_mu(a, b, c, d, theta):
    return (b * b + c * c - (a * a + d * d - 2 * a * d * np.cos(theta))) / (2 * b * c)


class Problem:
    """y = f(x) on [x0, x1] → ψ(φ) with φ in [0, Δφ], ψ in [0, Δψ] (deg given, rad inside)."""

    def __init__(self, f, x0, x1, in_deg, out_deg, mu_min_deg=30.0, ratio_max=10.0):
        self.f, self.x0, self.x1 = f, x0, x1
        self.dphi, self.dpsi = math.radians(in_deg), math.radians(out_deg)
        self.bound = math.cos(math.radians(mu_min_deg))
        self.mu_min = math.radians(mu_min_deg)
        self.ratio = ratio_max
        self.y0, self.y1 = f(x0), f(x1)

    def psi(self, phi):
        x = self.x0 + (self.x1 - self.x0) * phi / self.dphi
        return self.dpsi * (self.f(x) - self.y0) / (self.y1 - self.y0)

    def error(self, p, sigma, phi):
        a, (b, c, d) = 1.0, np.exp(p[:3])
        beta = output_angle(a, b, c, d, p[3] + phi, sigma)
        err = np.angle(np.exp(1j * (beta - p[4] - self.psi(phi))))
        return np.where(np.isfinite(err), err, math.pi)

    def limits(self, p):
        b, c, d = np.exp(p[:3])
        lo, hi = p[3], p[3] + self.dphi
        angles = [lo, hi]
        for base in (0.0, math.pi):
            k = math.ceil((lo - base) / (2 * math.pi))
            angles.append(min(base + 2 * math.pi * k, hi) if base + 2 * math.pi * k <= hi else lo)
        cm = cos_mu(1.0, b, c, d, np.array(angles))
        logs = np.log([1.0, b, c, d])
        ratio = [math.log(self.ratio) - (logs[i] - logs[j]) for i in range(4) for j in range(4) if i != j]
        return np.concatenate([self.bound - cm, self.bound + cm, ratio])

    def check(self, p, sigma, points=4001):
        phi = np.linspace(0.0, self.dphi, points)
        b, c, d = np.exp(p[:3])
        theta = p[3] + phi
        f2 = 1 + d * d - 2 * d * np.cos(theta)
        mu = np.arccos(np.clip((b * b + c * c - f2) / (2 * b * c), -1, 1))
        links = np.array([1.0, b, c, d])
        return {"max_error_deg": math.degrees(float(np.max(np.abs(self.error(p, sigma, phi))))),
                "mu_min_deg": math.degrees(float(np.min(np.minimum(mu, math.pi - mu)))),
                "ratio": float(links.max() / links.min()), "links_over_a": [float(v) for v in links],
                "offsets_deg": [math.degrees(p[3]) % 360, math.degrees(p[4]) % 360], "branch": sigma,
                "limits_met": bool(self.limits(p).min() >= -1e-9)}


def freudenstein_starts(problem: Problem, grid_deg: float = 10.0, keep: int = 5):
    """Three Chebyshev precision points, offsets scanned: the ``keep`` admissible mechanisms of least error."""
    k = np.arange(1, 4)
    nodes = problem.dphi * (1 - np.cos((2 * k - 1) * np.pi / 6)) / 2
    check = np.linspace(0, problem.dphi, 41)
    found = []
    for phi0 in np.radians(np.arange(0, 360, grid_deg)):
        for psi0 in np.radians(np.arange(0, 360, grid_deg)):
            theta, beta = phi0 + nodes, psi0 + problem.psi(nodes)
            m = np.column_stack([np.cos(beta), -np.cos(theta), np.ones(3)])
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            k1, k2, k3 = np.linalg.solve(m, np.cos(theta - beta))
            if k1 == 0 or k2 == 0:
                continue
            a, c = 1 / k1, 1 / k2
            b2 = a * a + c * c + 1 - 2 * a * c * k3
            if b2 <= 0:
                continue
            t0, s0 = phi0, psi0
            if a < 0:
                a, t0 = -a, t0 + math.pi
            if c < 0:
                c, s0 = -c, s0 + math.pi
            b = math.sqrt(b2)
            p = np.array([math.log(b / a), math.log(c / a), math.log(1 / a), t0, s0])
            for sigma in (1, -1):
                if np.max(np.abs(problem.error(p, sigma, nodes))) > 1e-6:
                    continue
                if problem.limits(p).min() < 0:
                    continue
                found.append((float(np.max(np.abs(problem.error(p, sigma, check)))), sigma, p))
    found.sort(key=lambda item: item[0])
    return [(sigma, p) for _, sigma, p in found[:keep]]


def slsqp_minimax(problem: Problem, p0, sigma, points: int = 161):
    k = np.arange(points)
    phi = problem.dphi * (1 - np.cos(k * np.pi / (points - 1))) / 2
    z0 = np.append(p0, np.max(np.abs(problem.error(p0, sigma, phi))))
    span = math.log(problem.ratio) + 1
    grad = np.zeros(6)
    grad[5] = 1.0

    def cons(z):
        e = problem.error(z[:5], sigma, phi)
        return np.concatenate([z[5] - e, z[5] + e, problem.limits(z[:5])])

    res = minimize(lambda z: z[5], z0, jac=lambda z: grad, method="SLSQP",
                   bounds=[(-span, span)] * 3 + [(None, None)] * 2 + [(0, None)],
                   constraints=[{"type": "ineq", "fun": cons}], options={"maxiter": 500, "ftol": 1e-14})
    return res.x[:5]


def peer_minimax(f, x0, x1, in_deg, out_deg, mu_min_deg=30.0, ratio_max=10.0, starts=5, grid_deg=10.0,
                 points=161, random_starts=0, seed=0):
    """The peer's best admissible minimax four-bar (a dict of its checked figures)."""
    problem = Problem(f, x0, x1, in_deg, out_deg, mu_min_deg, ratio_max)
    pool = freudenstein_starts(problem, grid_deg, starts)
    rng = np.random.default_rng(seed)
    for _ in range(random_starts):
        for sigma in (1, -1):
            p = np.array([*rng.uniform(-2.3, 2.3, 3), rng.uniform(0, 2 * math.pi), 0.0])
            b, c, d = np.exp(p[:3])
            beta = output_angle(1.0, b, c, d, p[3], sigma)
            if np.isfinite(beta):
                p[4] = float(beta)
                pool.append((sigma, p))
    best = None
    for sigma, p in pool:
        p = slsqp_minimax(problem, p, sigma, points)
        got = problem.check(p, sigma)
        if got["limits_met"] and (best is None or got["max_error_deg"] < best["max_error_deg"]):
            best = got
    return {**(best or {}), "starts": len(pool)}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--random", type=int, default=0, help="random starts per branch (multistart evidence)")
    args = parser.parse_args()
    for label, f, x0, x1 in (("log10(x) on [1, 2]", np.log10, 1.0, 2.0), ("x^2 on [1, 2]", np.square, 1.0, 2.0),
                             ("x^2 on [0, 1]", np.square, 0.0, 1.0)):
        t = time.process_time()
        got = peer_minimax(f, x0, x1, 60.0, 90.0, random_starts=args.random)
        print(f"{label}, 60/90 deg, mu >= 30 deg, ratio <= 10: max error {got['max_error_deg']:.5f} deg, mu min "
              f"{got['mu_min_deg']:.3f} deg, ratio {got['ratio']:.4f}, {got['starts']} starts, "
              f"{time.process_time() - t:.1f} s CPU")
