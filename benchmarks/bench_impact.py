"""Speed against error of the stop-impact response: the closed-form Duhamel solution against scipy's
solve_ivp at several tolerances.

The lever on its stop (the shuttle-lift sample's figures: 768 Hz on the stop, ζ = 0.05, the source's
4.137 N peak force over half the period on the stop, approach velocity from rest) responds to the
triangular pulse; q(t) is evaluated on 2000 points over the pulse and two periods after it. Reference:
solve_ivp DOP853 at rtol 1e-13 (an independent route); error = max |q − q_ref| / max |q_ref|.

Run: python benchmarks/bench_impact.py [--quick]
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from camcad.dynamics.impact import triangular_pulse, triangular_pulse_response  # noqa: E402
from timing import median_time  # noqa: E402

MASS = 0.0075911          # kg, reduced mass of the lever (sample shuttle_lift.toml)
F_STOP = 768.0            # Hz (published, seed 000)
ZETA = 0.05
PEAK_FORCE = 4.137        # N (published at 280 rpm)
OMEGA = 2 * math.pi * F_STOP
TAU = 0.5 / F_STOP        # half the period on the stop
V0 = 0.0


def _integrate(method: str, rtol: float, t: np.ndarray) -> np.ndarray:
    from scipy.integrate import solve_ivp

    def rhs(time_s, state):
        q, qd = state
        force = float(triangular_pulse(np.array([time_s]), PEAK_FORCE, TAU)[0])
        return [qd, force / MASS - 2 * ZETA * OMEGA * qd - OMEGA**2 * q]

    # the pulse has kinks at τ and 2τ: integrate piece by piece so the solver never steps over them
    cuts = [0.0, TAU, 2 * TAU, t[-1]]
    state = np.array([0.0, V0])
    out = np.empty_like(t)
    for a, b in zip(cuts[:-1], cuts[1:]):
        inside = (t >= a) & (t <= b)
        sol = solve_ivp(rhs, (a, b), state, method=method, rtol=rtol, atol=rtol * 1e-9, t_eval=t[inside],
                        dense_output=False)
        out[inside] = sol.y[0]
        end = solve_ivp(rhs, (a, b), state, method=method, rtol=rtol, atol=rtol * 1e-9)
        state = end.y[:, -1]
    return out


def _timed(function, repeats: int):
    return median_time(function, repeats, warm_up=True)


def run(quick: bool = False) -> list[dict]:
    repeats = 3 if quick else 7
    t = np.linspace(0.0, 2 * TAU + 2 / F_STOP, 2000)
    reference = _integrate("DOP853", 1e-13, t)
    scale = np.max(np.abs(reference))
    rows = []
    elapsed, q = _timed(lambda: triangular_pulse_response(t, omega=OMEGA, damping_ratio=ZETA, mass=MASS,
                                                          peak_force=PEAK_FORCE, rise_time=TAU)[0], repeats)
    rows.append(dict(kernel="stop impact response", method="closed-form Duhamel", setting="-", time_s=elapsed,
                     error=float(np.max(np.abs(q - reference)) / scale), error_unit="fraction of peak q"))
    settings = [("RK45", 1e-4), ("RK45", 1e-8)] if quick else [("RK45", 1e-4), ("RK45", 1e-6), ("RK45", 1e-8),
                                                               ("DOP853", 1e-10)]
    for method, rtol in settings:
        elapsed, q = _timed(lambda: _integrate(method, rtol, t), max(1, repeats // 2))
        rows.append(dict(kernel="stop impact response", method=f"solve_ivp {method}", setting=f"rtol={rtol:g}",
                         time_s=elapsed, error=float(np.max(np.abs(q - reference)) / scale),
                         error_unit="fraction of peak q"))
    return rows


def main() -> None:
    rows = run("--quick" in sys.argv)
    print(f"{'method':24} {'setting':12} {'time':>12} {'error':>10}")
    for r in rows:
        print(f"{r['method']:24} {r['setting']:12} {r['time_s'] * 1e3:9.3f} ms {r['error']:10.2e}  {r['error_unit']}")
    closed = rows[0]
    for r in rows[1:]:
        print(f"closed form vs {r['method']} {r['setting']}: {r['time_s'] / closed['time_s']:.0f}x faster, "
              f"error {closed['error']:.1e} vs {r['error']:.1e}")


if __name__ == "__main__":
    main()
