"""Hard cases, timed: a 1,000,000-vertex drawn law and a 3-vertex law through read, check, fix and profile.

The large law is the cycloidal dwell–rise–dwell–return law (lift 25 mm, rise and return over 120°)
sampled at 1,000,000 vertices, written to a temporary table (.csv, every value exact) and, in the
full run, to a temporary DXF (one LWPOLYLINE). Each stage is timed (median of repeats, without
tracemalloc) and then run once more under tracemalloc for its peak memory (Python and numpy
allocations, MB). The error of each stage is against a closed form computed here:

- read: largest distance of the detected phase edges from 60°, 180°, 240°, 360° (rad);
- check: |rise − 25 mm| (mm), the drawn law's own discretisation error;
- fix (min-change, of the law with its rise's accelerating lobe drawn 4 % too large): the largest
  closure after the fix (v at the end of rise and return, s at the end of the cycle) over the lift,
  from the law's exact integration;
- write fixed DXF (full run): camcad fix's corrected copy of the drawing, re-read: the largest
  change of a against the corrected law, over max|a|;
- profile (roller, Rb 50, Rr 10, chord tolerance 1 µm): |φ_max − closed form| (deg), with
  φ = atan(v/(Rp + s)) of the cycloid maximised by a bounded Brent search.

The 3-vertex law is a = 10 → −10 → 10 at 0°, 180°, 360° (rise 0–180°, return 180–360°, h = Aπ²/6):
read (phase edge against π), check (|rise − Aπ²/6|), fix (already balanced: nothing to do), fix of
the unbalanced 10 → −10 → 10 at 0°, 120°, 360° (refused: no motion would be left; error "-"),
and profile (|φ_max − closed form|).

Run: python benchmarks/bench_hard.py [--quick]
(quick: 100,000 vertices, the table only, one repeat, no peak memory of the read)
"""

from __future__ import annotations

import io
import math
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from camcad import balance
from camcad.errors import CamcadError
from camcad.law.source import load_law
from camcad.law.standard import compose
from camcad.profile.followers import Follower
from camcad.profile.summary import profile_report as report
from camcad.profile.synth import ProfileSettings, synthesize

LIFT = 25.0
BETA = 2 * math.pi / 3
VERTICES = 1_000_000
#: the same cases in a quick run
QUICK_VERTICES = 100_000
A3 = 10.0
SETTINGS = ProfileSettings(plots=False, design=False)
FOLLOWER = Follower("roller", 50.0, 10.0)


def measure(fn, repeats: int, trace: bool = True):
    """(median time s, peak MB under tracemalloc, result): timed runs first, then one traced run
    (``trace=False``: no traced run, peak None)."""
    times = []
    result = None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    if not trace:
        return float(np.median(times)), None, result
    tracemalloc.start()
    try:
        result = fn()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return float(np.median(times)), peak / 1e6, result


def brent_max(fn, lo: float, hi: float, samples: int = 20001) -> float:
    """Largest value of a smooth fn on [lo, hi]: grid, then a bounded Brent search around the best point."""
    grid = np.linspace(lo, hi, samples)
    values = np.array([fn(t) for t in grid])
    k = int(np.argmax(values))
    res = minimize_scalar(lambda t: -fn(t), bounds=(grid[max(k - 1, 0)], grid[min(k + 1, samples - 1)]),
                          method="bounded", options={"xatol": 1e-15})
    return max(float(values[k]), -float(res.fun))


def cycloid_pressure_angle_max(rp: float) -> float:
    """max over the rise of atan(v/(Rp + s)) (deg) for the cycloid s = h(u − sin 2πu/2π), v = (h/β)(1 − cos 2πu)."""
    def phi(u):
        s = LIFT * (u - math.sin(2 * math.pi * u) / (2 * math.pi))
        v = LIFT / BETA * (1 - math.cos(2 * math.pi * u))
        return math.degrees(math.atan(v / (rp + s)))
    return brent_max(phi, 0.0, 1.0)


def write_table(path: Path, theta_deg: np.ndarray, accel: np.ndarray) -> Path:
    path.write_text("".join(f"{t!r},{a!r}\n" for t, a in zip(theta_deg.tolist(), accel.tolist())))
    return path


def write_dxf(path: Path, theta_deg: np.ndarray, accel: np.ndarray) -> Path:
    """One LWPOLYLINE in an R2000 drawing made by ezdxf, with its vertex block written directly (ezdxf
    1.4's add_lwpolyline costs O(N²) time: hours for a million vertices)."""
    import ezdxf

    doc = ezdxf.new("R2000")
    doc.modelspace().add_lwpolyline([(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)])
    stream = io.StringIO()
    doc.write(stream)
    template = " 90\n3\n 70\n0\n 10\n0.0\n 20\n0.0\n 10\n1.0\n 20\n1.0\n 10\n2.0\n 20\n0.0\n"
    text = stream.getvalue()
    if text.count(template) != 1:
        raise RuntimeError("unexpected ezdxf output: the LWPOLYLINE template is not found once")
    body = "".join(f" 10\n{t!r}\n 20\n{a!r}\n" for t, a in zip(theta_deg.tolist(), accel.tolist()))
    path.write_text(text.replace(template, f" 90\n{len(theta_deg)}\n 70\n0\n" + body))
    return path


def phase_edge_error(law, expected_deg) -> float:
    found = [law.phases[0].start] + [p.end for p in law.phases]
    if len(found) != len(expected_deg):
        return math.inf
    return float(np.max(np.abs(np.array(found) - np.radians(expected_deg))))


def closure_error(law, lift: float) -> float:
    """The largest balance residual over the lift by Simpson's rule per drawn segment (an independent route:
    camcad.bench.references, not camcad's own integration)."""
    from camcad.bench.references import simpson_closure

    motion_ends = [p.end for p in law.phases if p.kind in ("rise", "return")]
    return simpson_closure(law.x, law.a, motion_ends, lift)


def million_rows(quick: bool, folder: Path) -> list[dict]:
    repeats = 1 if quick else 3
    vertices = QUICK_VERTICES if quick else VERTICES
    kernel = f"hard case: {vertices:,}-vertex law"
    setting = f"{vertices:,} vertices"
    exact = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], LIFT)
    theta_deg = np.linspace(0.0, 360.0, vertices)
    accel = exact.kinematics(np.radians(theta_deg)).a
    edges = [0, 60, 180, 240, 360]
    rows = []
    table = write_table(folder / "million.csv", theta_deg, accel)
    sources = [("read table (.csv)", table)]
    if not quick:
        sources.append(("read DXF (LWPOLYLINE)", write_dxf(folder / "million.dxf", theta_deg, accel)))
    loaded = None
    for method, path in sources:
        # tracemalloc slows the reader's per-row Python loop fourfold (12 s): the full run only
        t, peak, loaded = measure(lambda path=path: load_law(path), repeats, trace=not quick)
        rows.append({"kernel": kernel, "method": method, "setting": setting, "time_s": t, "peak_mb": peak,
                     "error": phase_edge_error(loaded.law, edges), "error_unit": "rad (phase edges vs exact)"})
    law = loaded.law
    t, peak, checked = measure(lambda: balance.check(law), repeats)
    rows.append({"kernel": kernel, "method": "check", "setting": setting, "time_s": t, "peak_mb": peak,
                 "error": abs(checked.rise - LIFT), "error_unit": "mm (rise vs 25 mm)"})
    x = law.x
    wrong = law.with_ordinates(np.where((x > math.radians(60)) & (x < math.radians(120)), 1.04 * law.a, law.a))
    t, peak, fixed = measure(lambda: balance.correct(wrong, "min-change"), repeats)
    rows.append({"kernel": kernel, "method": "fix min-change", "setting": setting, "time_s": t, "peak_mb": peak,
                 "error": closure_error(fixed.law, LIFT), "error_unit": "closure / lift (Simpson per segment)"})
    if loaded.curve is not None:
        # camcad fix's output: the corrected vertices moved in place in a copy of the drawing
        from camcad.io.law_write import write_corrected_drawing

        fixed_here = balance.correct(wrong, "min-change").law
        out = folder / "million.fixed.dxf"
        t, peak, _ = measure(lambda: write_corrected_drawing(loaded, fixed_here, out), 1)
        again = load_law(out).law
        rows.append({"kernel": kernel, "method": "write fixed DXF", "setting": setting, "time_s": t,
                     "peak_mb": peak, "error": float(np.max(np.abs(again.a - fixed_here.a)) / np.max(np.abs(law.a))),
                     "error_unit": "re-read a vs written / max|a|"})
    t, peak, result = measure(lambda: synthesize(law, FOLLOWER, SETTINGS), repeats)
    figures = report(result)
    rows.append({"kernel": kernel, "method": "profile synthesis", "setting": f"{setting}, tol 1 um",
                 "time_s": t, "peak_mb": peak,
                 "error": abs(figures["pressure_angle_max_deg"] - cycloid_pressure_angle_max(60.0)),
                 "error_unit": f"deg (max pressure angle; {figures['profile_points']} profile points)"})
    return rows


def three_vertex_rows(quick: bool, folder: Path) -> list[dict]:
    repeats = 3 if quick else 15
    kernel = "hard case: 3-vertex law"
    rows = []
    balanced = write_table(folder / "three.csv", np.array([0.0, 180.0, 360.0]), np.array([A3, -A3, A3]))
    unbalanced = write_table(folder / "three_bad.csv", np.array([0.0, 120.0, 360.0]), np.array([A3, -A3, A3]))
    t, peak, loaded = measure(lambda: load_law(balanced), repeats)
    rows.append({"kernel": kernel, "method": "read table (.csv)", "setting": "3 vertices", "time_s": t,
                 "peak_mb": peak, "error": phase_edge_error(loaded.law, [0, 180, 360]),
                 "error_unit": "rad (phase edges vs exact)"})
    law = loaded.law
    t, peak, checked = measure(lambda: balance.check(law), repeats)
    rise = A3 * math.pi**2 / 6   # v = A(θ − θ²/π), h = ∫₀^π v dθ
    rows.append({"kernel": kernel, "method": "check", "setting": "3 vertices", "time_s": t, "peak_mb": peak,
                 "error": abs(checked.rise - rise), "error_unit": "mm (rise vs A pi^2/6)"})
    t, peak, fixed = measure(lambda: balance.correct(law, "min-change"), repeats)
    rows.append({"kernel": kernel, "method": "fix min-change", "setting": "3 vertices, balanced", "time_s": t,
                 "peak_mb": peak, "error": closure_error(fixed.law, rise), "error_unit": "closure / lift"})
    bad = load_law(unbalanced).law

    def refused():
        try:
            balance.correct(bad, "min-change")
        except CamcadError as err:
            return err.what
        return None

    t, peak, message = measure(refused, repeats)
    rows.append({"kernel": kernel, "method": "fix min-change", "setting": "3 vertices, unbalanced", "time_s": t,
                 "peak_mb": peak, "error": None,
                 "error_unit": "refused (expected): " + (message or "NOT REFUSED")[:60]})
    rp = 30.0
    t, peak, result = measure(lambda: synthesize(law, Follower("roller", 20.0, 10.0), SETTINGS), repeats)

    def phi(theta):
        v = A3 * (theta - theta * theta / math.pi)
        s = A3 * (theta * theta / 2 - theta**3 / (3 * math.pi))
        return math.degrees(math.atan(v / (rp + s)))

    rows.append({"kernel": kernel, "method": "profile synthesis", "setting": "3 vertices, tol 1 um", "time_s": t,
                 "peak_mb": peak,
                 "error": abs(report(result)["pressure_angle_max_deg"] - brent_max(phi, 0.0, math.pi)),
                 "error_unit": "deg (max pressure angle)"})
    return rows


def run(quick: bool = False) -> list[dict]:
    with tempfile.TemporaryDirectory(prefix="camcad-bench-hard-") as tmp:
        folder = Path(tmp)
        return three_vertex_rows(quick, folder) + million_rows(quick, folder)


def main() -> None:
    quick = "--quick" in sys.argv
    rows = run(quick)
    print(f"{'kernel':34s} {'method':22s} {'setting':30s} {'time':>10s} {'peak':>10s} {'error':>10s}  unit")
    for row in rows:
        error = "-" if row["error"] is None else f"{row['error']:.2e}"
        peak = "-" if row["peak_mb"] is None else f"{row['peak_mb']:.3g}MB"
        print(f"{row['kernel']:34s} {row['method']:22s} {row['setting']:30s} {row['time_s'] * 1e3:8.1f}ms "
              f"{peak:>10s} {error:>10s}  {row['error_unit']}")


if __name__ == "__main__":
    main()
