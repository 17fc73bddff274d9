"""Speed against error: law integration (exact vs the source's trapezoid) and balance correction
(min-change solved exactly vs the source's iterative 0.1° loop) on a 10,000-vertex drawn law.

Run: python benchmarks/bench_balance.py [--quick]
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from timing import median_time

from camcad import balance
from camcad.law.law import PiecewiseLinearLaw, integrate_exact, integrate_trapezoid
from camcad.law.phases import detect_phases
from camcad.law.standard import compose


def drawn_law(vertices: int, seed: int = 0) -> PiecewiseLinearLaw:
    """A cycloidal dwell–rise–dwell–return law (lift 25 mm) drawn with ``vertices`` vertices and
    drawing errors: the rise's accelerating lobe 4 % high, 1 % noise on every vertex."""
    law = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0)
    theta = np.linspace(0.0, 2 * np.pi, vertices)
    a = law.kinematics(theta).a
    a = np.where((theta > np.radians(60)) & (theta < np.radians(120)), 1.04 * a, a)
    a = a * (1 + 0.01 * np.random.default_rng(seed).standard_normal(vertices))
    return PiecewiseLinearLaw(theta, a, 2 * np.pi, detect_phases(theta, a, 2 * np.pi))


def simpson_reference(x: np.ndarray, a: np.ndarray, end: float) -> tuple[float, float]:
    """v(end) and s(end) of a polyline a(θ) starting from rest, by an independent route: on each segment
    the integrands a(τ) and (end − τ) a(τ) are of degree 1 and 2, so the trapezoid and Simpson's rule are
    exact there; the pieces are summed with math.fsum (camcad integrates by cumulative cubic pieces)."""
    keep = x <= end
    xs, ys = x[keep], a[keep]
    if xs[-1] < end:
        xs = np.append(xs, end)
        ys = np.append(ys, np.interp(end, x, a))
    h = np.diff(xs)
    v = math.fsum((h * (ys[:-1] + ys[1:]) / 2).tolist())
    mid = (xs[:-1] + xs[1:]) / 2
    f0, f1, fm = (end - xs[:-1]) * ys[:-1], (end - xs[1:]) * ys[1:], (end - mid) * (ys[:-1] + ys[1:]) / 2
    s = math.fsum((h / 6 * (f0 + 4 * fm + f1)).tolist())
    return v, s


def closure_error(law: PiecewiseLinearLaw, lift: float) -> float:
    """The largest balance residual of ``law`` by ``simpson_reference``, relative to the lift: the velocity
    at the end of every rise and return and the displacement at the end of the cycle."""
    ends = [p.end for p in law.phases if p.kind in ("rise", "return")]
    residuals = [simpson_reference(law.x, law.a, e)[0] for e in ends]
    residuals.append(simpson_reference(law.x, law.a, law.x[-1])[1])
    return max(abs(r) for r in residuals) / lift


def timed(function, repeats: int):
    return median_time(function, repeats, warm_up=False)


def run(quick: bool = False) -> list[dict]:
    repeats = 3 if quick else 7
    rows = []
    law = drawn_law(10_000)
    lift = balance.check(law).rise
    # integration: the reference is s(T) by Simpson's rule per drawn segment (exact there), not camcad's
    # cumulative cubic integral; each method's error is its s(T) against it
    _, s_ref = simpson_reference(law.x, law.a, law.x[-1])
    t_exact, (_v, s_exact) = timed(lambda: integrate_exact(law.x, law.a), repeats)
    rows.append({"kernel": "law integration (10k vertices)", "method": "exact piecewise cubic", "setting": "-",
                 "time_s": t_exact, "error": abs(float(s_exact[-1]) - s_ref), "error_unit": "mm (s at cycle end)"})
    for step_deg in ((0.5, 0.1) if quick else (1.0, 0.5, 0.1, 0.05, 0.01)):
        t_trap, (_, _, _, s) = timed(lambda step_deg=step_deg: integrate_trapezoid(law.x, law.a, np.radians(step_deg)),
                                     repeats)
        rows.append({"kernel": "law integration (10k vertices)", "method": "trapezoid (source)",
                     "setting": f"step {step_deg} deg", "time_s": t_trap, "error": abs(float(s[-1]) - s_ref),
                     "error_unit": "mm (s at cycle end)"})
    # correction: error = the largest balance residual of the result by the Simpson reference, over the lift
    t_min, fixed = timed(lambda: balance.correct(law, "min-change"), repeats)
    rows.append({"kernel": "balance fix (10k vertices)", "method": "min-change (exact solve)", "setting": "-",
                 "time_s": t_min, "error": closure_error(fixed.law, lift),
                 "error_unit": "closure / lift", "rms_change": fixed.rms_change})
    for tol in ((1e-4,) if quick else (1e-3, 1e-4, 1e-5)):
        t_it, looped = timed(lambda tol=tol: balance.correct(law, "keypoints", method="iterate", step_deg=0.1, tol=tol),
                             max(1, repeats // 2))
        rows.append({"kernel": "balance fix (10k vertices)",
                     "method": "camcad --method iterate (the source's trial steps)",
                     "setting": f"step 0.1 deg, tol {tol:g}", "time_s": t_it,
                     "error": closure_error(looped.law, lift), "error_unit": "closure / lift",
                     "rms_change": looped.rms_change, "integrations": looped.iterations})
    return rows


def main() -> None:
    quick = "--quick" in sys.argv
    rows = run(quick)
    print(f"{'kernel':32s} {'method':26s} {'setting':24s} {'time':>10s} {'error':>10s}  unit")
    for row in rows:
        print(f"{row['kernel']:32s} {row['method']:26s} {row['setting']:24s} {row['time_s'] * 1e3:8.2f}ms "
              f"{row['error']:10.2e}  {row['error_unit']}")
    base = next(r for r in rows if r["method"].startswith("min-change"))
    for row in rows:
        if row["method"].startswith("camcad --method iterate"):
            print(f"min-change vs iterative ({row['setting']}): {row['time_s'] / base['time_s']:.1f}x faster, "
                  f"residual {base['error']:.1e} vs {row['error']:.1e}, RMS change {base['rms_change']:.4g} vs "
                  f"{row['rms_change']:.4g} mm/rad^2, {row['integrations']} trapezoid integrations")


if __name__ == "__main__":
    main()
