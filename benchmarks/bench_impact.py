"""Speed against error of the stop-impact response: the closed-form Duhamel solution and scipy's solve_ivp,
both against an exact solution by a third route.

The lever on its stop (the shuttle-lift sample's figures: 768 Hz on the stop, ζ = 0.05, the source's 4.137 N
peak force over half the period on the stop, from rest) responds to the triangular pulse; q(t) is evaluated
on 2000 points over the pulse and two periods after it.

Reference (independent of both methods): the equation is linear with a piecewise-linear force, so on each
piece the state [q, q̇, t − t0, 1] obeys z' = A z with a constant 4×4 matrix and z(t) = expm(A (t − t0)) z(t0)
exactly (scipy.linalg.expm, round-off only). Error = max |q − q_ref| / max |q_ref|.

Times: the closed form evaluated on the 2000 points; solve_ivp integrating piece by piece (the kinks at τ and
2τ are piece ends), one solve per piece with the evaluation points and the piece's end in ``t_eval``.

Run: python benchmarks/bench_impact.py [--quick]
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import itertools

from timing import median_time

from camcad.dynamics.impact import triangular_pulse, triangular_pulse_response

MASS = 0.0075911          # kg, reduced mass of the lever (sample shuttle_lift.toml)
F_STOP = 768.0            # Hz (published, Podgorny et al. 2018)
ZETA = 0.05
PEAK_FORCE = 4.137        # N (published at 280 rpm)
OMEGA = 2 * math.pi * F_STOP
TAU = 0.5 / F_STOP        # half the period on the stop
V0 = 0.0
REFERENCE = "exact piecewise solution by matrix exponentials (scipy.linalg.expm)"


def exact_response(t: np.ndarray) -> np.ndarray:
    """q(t) by matrix exponentials of the augmented linear system, piece by piece (module docstring)."""
    from scipy.linalg import expm

    pieces = [(0.0, 0.0, PEAK_FORCE / TAU), (TAU, PEAK_FORCE, -PEAK_FORCE / TAU), (2 * TAU, 0.0, 0.0)]
    ends = [TAU, 2 * TAU, math.inf]
    state = np.array([0.0, V0])
    out = np.empty_like(t)
    for (start, c0, c1), end in zip(pieces, ends):
        a = np.array([[0.0, 1.0, 0.0, 0.0], [-OMEGA**2, -2 * ZETA * OMEGA, c1 / MASS, c0 / MASS],
                      [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]])
        z0 = np.array([state[0], state[1], 0.0, 1.0])
        inside = (t >= start) & (t < end)
        for i in np.flatnonzero(inside):
            out[i] = (expm(a * (t[i] - start)) @ z0)[0]
        if math.isfinite(end):
            state = (expm(a * (end - start)) @ z0)[:2]
    return out


def _integrate(method: str, rtol: float, t: np.ndarray) -> np.ndarray:
    from scipy.integrate import solve_ivp

    def rhs(time_s, state):
        q, qd = state
        force = float(triangular_pulse(np.array([time_s]), PEAK_FORCE, TAU)[0])
        return [qd, force / MASS - 2 * ZETA * OMEGA * qd - OMEGA**2 * q]

    # the pulse has kinks at τ and 2τ: integrate piece by piece so the solver never steps over them; one solve
    # per piece, its end appended to t_eval for the next piece's start
    cuts = [0.0, TAU, 2 * TAU, t[-1]]
    state = np.array([0.0, V0])
    out = np.empty_like(t)
    for a, b in itertools.pairwise(cuts):
        inside = (t >= a) & (t < b)
        sol = solve_ivp(rhs, (a, b), state, method=method, rtol=rtol, atol=rtol * 1e-9,
                        t_eval=np.append(t[inside], b))
        out[inside] = sol.y[0][:-1]
        state = sol.y[:, -1]
    out[-1] = state[0]
    return out


def _timed(function, repeats: int):
    return median_time(function, repeats, warm_up=True)


def run(quick: bool = False) -> list[dict]:
    repeats = 3 if quick else 7
    t = np.linspace(0.0, 2 * TAU + 2 / F_STOP, 2000)
    reference = exact_response(t)
    scale = np.max(np.abs(reference))
    unit = "fraction of peak q vs expm exact"
    rows = []
    elapsed, q = _timed(lambda: triangular_pulse_response(t, omega=OMEGA, damping_ratio=ZETA, mass=MASS,
                                                          peak_force=PEAK_FORCE, rise_time=TAU)[0], repeats)
    rows.append({"kernel": "stop impact response", "method": "closed-form Duhamel", "setting": "-", "time_s": elapsed,
                     "error": float(np.max(np.abs(q - reference)) / scale), "error_unit": unit, "reference": REFERENCE})
    settings = [("RK45", 1e-4), ("RK45", 1e-8)] if quick else [("RK45", 1e-4), ("RK45", 1e-6), ("RK45", 1e-8),
                                                               ("DOP853", 1e-10)]
    for method, rtol in settings:
        elapsed, q = _timed(lambda method=method, rtol=rtol: _integrate(method, rtol, t), max(1, repeats // 2))
        rows.append({"kernel": "stop impact response", "method": f"solve_ivp {method}", "setting": f"rtol={rtol:g}",
                         "time_s": elapsed, "error": float(np.max(np.abs(q - reference)) / scale), "error_unit": unit,
                         "reference": REFERENCE})
    return rows


def main() -> None:
    rows = run("--quick" in sys.argv)
    print(f"reference: {REFERENCE}")
    print(f"{'method':24} {'setting':12} {'time':>12} {'error':>10}")
    for r in rows:
        print(f"{r['method']:24} {r['setting']:12} {r['time_s'] * 1e3:9.3f} ms {r['error']:10.2e}  {r['error_unit']}")
    closed = rows[0]
    for r in rows[1:]:
        print(f"closed form vs {r['method']} {r['setting']}: {r['time_s'] / closed['time_s']:.0f}x faster, "
              f"error {closed['error']:.1e} vs {r['error']:.1e}")


if __name__ == "__main__":
    main()
