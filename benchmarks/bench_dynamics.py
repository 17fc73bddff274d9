"""Speed against error of the single-DOF elastic follower over a speed sweep, against an exact solution.

The model: cycloidal dwell–rise–dwell–return (90° each, lift 25 mm), fn = 40 Hz, ζ = 0.05, the periodic
steady state at 141 speeds 280…420 rpm (quick: 15 speeds). Paths under test:
- frequency: harmonics of the sampled law through the frequency response (knob: samples N);
- time: solve_ivp with periodic shooting (knobs: method, rtol; atol = rtol × 1e-3 × lift).

Reference (a third route, shared by neither path): in θ the equation x'' + 2ζr x' + r² x = −a(θ), r = ωn/ω,
has on each phase a forcing that is zero (dwell) or ∓(2πh/β²) sin(2πu/β) (rise, return). With the state
[x, x', sin(2πu/β), cos(2πu/β)] it is z' = A z with a constant 4×4 matrix per phase, so the cycle map is a
product of matrix exponentials (scipy.linalg.expm), the periodic state solves (I − M) z0 = b exactly, and
ÿ = −ω² (r² x + 2ζr x') at every output point is one more exponential: exact to round-off.
Error: the largest |ÿ − ÿ_ref| over the sweep and 256 cam angles per cycle, as a fraction of the speed's
peak rigid acceleration. Times are for the whole sweep (median of repeats for runs under a second).

Run: python benchmarks/bench_dynamics.py [--quick]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

from camcad import dynamics
from camcad.law.standard import compose

GRID = 256          # output points per cycle where the paths are compared
LIFT = 25.0
PHASES = [("dwell", 90.0), ("rise", 90.0), ("dwell", 90.0), ("return", 90.0)]
FN, ZETA = 40.0, 0.05
REFERENCE = "exact piecewise solution by matrix exponentials (scipy.linalg.expm)"
ERROR_UNIT = "fraction of peak rigid acceleration vs expm exact"


def _case(quick: bool):
    law = compose(PHASES, LIFT, "cycloidal")
    follower = dynamics.ElasticFollower(FN, ZETA)
    speeds = np.linspace(280.0, 420.0, 15 if quick else 141)
    return law, follower, speeds


def exact_elastic_accel(rpm: float, grid: int = GRID) -> tuple[np.ndarray, float]:
    """(ÿ at θ_j = 2πj/grid (mm/s²), peak rigid acceleration (mm/s²)) by matrix exponentials (module docstring)."""
    from scipy.linalg import expm

    omega = 2 * math.pi * rpm / 60.0
    r = 2 * math.pi * FN / omega
    k, c = r * r, 2 * ZETA * r
    starts, matrices = [], []
    position = 0.0
    for kind, width in PHASES:
        beta = math.radians(width)
        p = 2 * math.pi / beta
        amplitude = {"rise": 1.0, "return": -1.0, "dwell": 0.0}[kind] * 2 * math.pi * LIFT / beta**2
        a = np.array([[0.0, 1.0, 0.0, 0.0], [-k, -c, -amplitude, 0.0], [0.0, 0.0, 0.0, p], [0.0, 0.0, -p, 0.0]])
        starts.append((math.radians(position), beta))
        matrices.append(a)
        position += width
    # the cycle map on (x, x'): each phase starts with sin = 0, cos = 1
    m, b = np.eye(2), np.zeros(2)
    transfers = [expm(a * beta) for a, (_, beta) in zip(matrices, starts)]
    for e in transfers:
        m, b = e[:2, :2] @ m, e[:2, :2] @ b + e[:2, 3]
    state = np.linalg.solve(np.eye(2) - m, b)
    phase_states = []
    for e in transfers:
        phase_states.append(state.copy())
        state = e[:2, :2] @ state + e[:2, 3]
    theta = 2 * math.pi * np.arange(grid) / grid
    accel = np.empty(grid)
    for j, th in enumerate(theta):
        i = max(index for index, (start, _) in enumerate(starts) if start <= th + 1e-15)
        z = expm(matrices[i] * (th - starts[i][0])) @ np.array([*phase_states[i], 0.0, 1.0])
        accel[j] = -omega**2 * (k * z[0] + c * z[1])
    peak = 2 * math.pi * LIFT / math.radians(90.0) ** 2 * omega**2
    return accel, peak


def _timed(work, max_repeats: int = 5):
    """(median time, result): repeat while a single run is under a second."""
    times, result = [], None
    for _ in range(max_repeats):
        start = time.perf_counter()
        result = work()
        times.append(time.perf_counter() - start)
        if times[-1] > 1.0:
            break
    return statistics.median(times), result


def _frequency_sweep(law, follower, speeds, samples: int):
    spectrum = dynamics.law_spectrum(law, samples)
    step = samples // GRID
    return [dynamics.steady_state_frequency(spectrum, follower, rpm).accel_elastic[::step] for rpm in speeds]


def _time_sweep(law, follower, speeds, method: str, rtol: float):
    return [dynamics.steady_state_time(law, follower, rpm, samples=GRID, method=method, rtol=rtol).accel_elastic
            for rpm in speeds]


def _error(accels, reference) -> float:
    return float(max(np.max(np.abs(a - r)) / p for a, (r, p) in zip(accels, reference)))


def run(quick: bool = False) -> list[dict]:
    law, follower, speeds = _case(quick)
    reference = [exact_elastic_accel(float(rpm)) for rpm in speeds]
    rows = []
    sample_counts = (256, 1024, 4096, 16384) if quick else (256, 512, 1024, 2048, 4096, 8192, 16384, 65536)
    for samples in sample_counts:
        seconds, accels = _timed(lambda samples=samples: _frequency_sweep(law, follower, speeds, samples))
        rows.append({"kernel": "sdof sweep", "method": "frequency", "setting": f"N={samples}", "time_s": seconds,
                     "error": _error(accels, reference), "error_unit": ERROR_UNIT, "reference": REFERENCE})
    settings = [("RK45", r) for r in ((1e-4, 1e-6) if quick else (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8))]
    settings += [("DOP853", r) for r in ((1e-8,) if quick else (1e-6, 1e-8, 1e-10))]
    for method, rtol in settings:
        seconds, accels = _timed(lambda method=method, rtol=rtol: _time_sweep(law, follower, speeds, method, rtol),
                                 max_repeats=3)
        rows.append({"kernel": "sdof sweep", "method": f"camcad time path {method} (per speed)",
                     "setting": f"rtol={rtol:g}", "time_s": seconds, "error": _error(accels, reference),
                     "error_unit": ERROR_UNIT, "reference": REFERENCE})
    return rows


def speedups(rows: list[dict]) -> list[tuple[str, str, float, float]]:
    """For each RK45 row: the cheapest frequency row at least as accurate, and the time ratio RK45/frequency."""
    frequency = [r for r in rows if r["method"] == "frequency"]
    out = []
    for row in rows:
        if row["method"] != "camcad time path RK45 (per speed)":
            continue
        matching = [f for f in frequency if f["error"] <= row["error"]]
        if matching:
            best = min(matching, key=lambda f: f["time_s"])
            out.append((row["setting"], best["setting"], row["error"], row["time_s"] / best["time_s"]))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="15 speeds and fewer settings")
    args = parser.parse_args()
    rows = run(args.quick)
    count = 15 if args.quick else 141
    print(f"single-DOF elastic follower, {count} speeds 280…420 rpm; error vs {REFERENCE}")
    print(f"{'method':<14} | {'setting':<12} | {'time (s)':>10} | {'error':>10}")
    print("-" * 56)
    for row in rows:
        print(f"{row['method']:<14} | {row['setting']:<12} | {row['time_s']:>10.4g} | {row['error']:>10.3g}")
    print()
    print("equal error: RK45 setting | frequency setting with error <= it | RK45 error | speed-up (RK45 / frequency)")
    for rk, freq, error, ratio in speedups(rows):
        print(f"  RK45 {rk:<10} | {freq:<8} | {error:.3g} | {ratio:.0f}x")


if __name__ == "__main__":
    main()
