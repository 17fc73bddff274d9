"""The kernel table of ``camcad bench``: each kernel against its numpy floor and its fair peer, in one run.

Every row times camcad, the floor (``camcad.bench.floors``) and the peer (``camcad.bench.peers``) on the same
input, interleaved, in CPU time (``camcad.bench.timing``), and measures the error of each against one
independent reference (``camcad.bench.references``), named in the row's ``reference`` (its kind: closed
form, second method, property) and ``reference_source``. ``floor_ratio`` is camcad's CPU time over the
floor's (the target is ≤ 2 at equal error); ``peer_ratio`` is the peer's over camcad's (> 1: camcad is
faster); ``floor_figures`` is the largest relative difference between the floor's figures and camcad's (the
floor must reproduce them).

Kernels: profile synthesis (the default cam; the peer's cam with the package ``mechanism``), min-change
balancing of a 10,000-vertex drawn law, the elastic follower over 141 speeds, Fourier coefficients of a
standard law, and reading a 499,999-row table (the most camcad reads).
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any, cast

import numpy as np

from camcad import balance, dynamics, fourier
from camcad.bench import floors, peers, references
from camcad.bench.timing import cpu_interleaved, cpu_once
from camcad.io.table_read import MAX_TABLE_LINES, read_table
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.phases import detect_phases
from camcad.law.standard import compose
from camcad.profile.followers import Follower
from camcad.profile.synth import Extremum, ProfileSettings, synthesize

DEFAULT_CAM = (("rise", 120.0, "cycloidal"), ("dwell", 60.0, None), ("return", 120.0, "poly345"),
               ("dwell", 60.0, None))
PEER_CAM = (("dwell", 90.0, None), ("rise", 90.0, "cycloidal"), ("dwell", 90.0, None),
            ("return", 90.0, "cycloidal"))


def row(kernel: str, setting: str, times: dict, errors: dict, error_unit: str, reference: str, source: str, *,
        peer: str, floor_figures: float | None, **extra) -> dict:
    """One row of the kernel table (module docstring); ``times`` and ``errors`` keyed camcad/floor/peer."""
    camcad_s, floor_s, peer_s = times.get("camcad"), times.get("floor"), times.get("peer")
    return {"benchmark": "kernels", "kernel": kernel, "method": "camcad | floor | peer", "setting": setting,
            "camcad_s": camcad_s, "floor_s": floor_s, "peer": peer, "peer_s": peer_s,
            "camcad_error": errors.get("camcad"), "floor_error": errors.get("floor"), "peer_error": errors.get("peer"),
            "error_unit": error_unit, "reference": reference, "reference_source": source,
            "floor_ratio": camcad_s / floor_s if camcad_s and floor_s else None,
            "peer_ratio": peer_s / camcad_s if camcad_s and peer_s else None,
            "floor_figures": floor_figures, "time_s": camcad_s, "error": errors.get("camcad"), **extra}


def _relative(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


# =============================================================================================
# Profile synthesis
# =============================================================================================


def camcad_law(segments, lift: float):
    shapes = [s for _, _, s in segments if s]
    return compose([(k, w) for k, w, _ in segments], lift, shapes[0], shapes[-1])


def profile_rows(rounds: int, quick: bool, install: bool) -> list[dict]:
    out = []
    for name, segments, lift, rb, rr in (("default cam", DEFAULT_CAM, 25.0, 50.0, 10.0),
                                         ("the peer's cam", PEER_CAM, 20.0, 40.0, 10.0)):
        law = camcad_law(segments, lift)
        follower = Follower("roller", rb, rr)
        settings = ProfileSettings(design=False, plots=False)
        tol = settings.tol_mm
        floor_segments = [(k, w, s) for k, w, s in segments]
        times = cpu_interleaved({"camcad": partial(synthesize, law, follower, settings),
                                 "floor": partial(floors.profile_floor, floor_segments, lift, rb, rr, tol)}, rounds)
        result = synthesize(law, follower, settings)
        floor = floors.profile_floor(floor_segments, lift, rb, rr, settings.tol_mm)
        exact = references.RollerCam(segments, lift, rb, rr)
        ref = exact.extremes()
        errors = {"camcad": references.polyline_deviation(result.profile.polyline.points, exact.profile),
                  "floor": references.polyline_deviation(floor["profile"], exact.profile)}
        figures_camcad = [result.pressure_angle.maximum.value, result.pressure_angle.minimum.value,
                          cast(Extremum, result.rho_pitch_min).value]
        figures_floor = [floor["phi_max"], floor["phi_min"], floor["rho_pitch_min"]]
        figures_ref = [ref["max"], ref["min"], ref["rho_pitch_min"]]
        counts: dict[str, int] = {"camcad": len(result.profile.polyline.points), "floor": len(floor["profile"])}
        extra: dict[str, Any] = {"points": counts,
                 "figure_errors": {"camcad": _relative(figures_camcad, figures_ref),
                                   "floor": _relative(figures_floor, figures_ref)}}
        peer_name = "mechanism 1.1.10 + normal offset"
        status = "ok"
        if name == "the peer's cam":
            try:
                python = peers.peer_python(install)
                steps = [0.0062, 0.0031] if quick else [0.0124, 0.0062, 0.0031, 0.00155]
                found = peers.run_mechanism(python, lift, rb, rr, steps, max(3, rounds))
                runs = []
                for one in found["runs"]:
                    points = peers.mechanism_to_camcad_frame(one["profile"])
                    runs.append((one["cpu_s"], references.polyline_deviation(points, exact.profile), one["step_rad"],
                                 len(points)))
                equal = [r for r in runs if r[1] <= errors["camcad"]] or [min(runs, key=lambda r: r[1])]
                chosen = max(equal, key=lambda r: r[2])
                times["peer"], errors["peer"] = chosen[0], chosen[1]
                extra["peer_step_rad"], counts["peer"] = chosen[2], chosen[3]
                extra["peer_runs"] = [{"step_rad": r[2], "cpu_s": r[0], "error": r[1], "points": r[3]} for r in runs]
            except peers.PeerUnavailable as err:
                status = f"peer unavailable: {err}"
        else:
            peer_name = "none (mechanism has uniform, harmonic and cycloidal motions, not a 3-4-5 return)"
        out.append(row("profile synthesis", f"{name}, tol {settings.tol_mm:g} mm", times, errors,
                       "mm (written profile polyline to the exact profile, Hausdorff)", "closed form",
                       "polar closed form of the roller cam (Norton 2009, eq. 3.8, §3.9, ch. 8)",
                       peer=peer_name, floor_figures=_relative(figures_floor, figures_camcad), status=status,
                       **extra))
    return out


# =============================================================================================
# Min-change balancing
# =============================================================================================


def drawn_law(vertices: int, seed: int = 0) -> PiecewiseLinearLaw:
    """A cycloidal dwell-rise-dwell-return law (lift 25 mm) drawn with ``vertices`` vertices and drawing
    errors: the rise's accelerating lobe 4 % high, 1 % noise on every vertex."""
    law = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0)
    theta = np.linspace(0.0, 2 * np.pi, vertices)
    a = law.kinematics(theta).a
    a = np.where((theta > np.radians(60)) & (theta < np.radians(120)), 1.04 * a, a)
    a = a * (1 + 0.01 * np.random.default_rng(seed).standard_normal(vertices))
    return PiecewiseLinearLaw(theta, a, 2 * np.pi, detect_phases(theta, a, 2 * np.pi))


def balance_rows(rounds: int, quick: bool) -> list[dict]:
    law = drawn_law(10_000)
    x, a = law.x, law.a
    motions = [p.end for p in law.phases if p.kind in ("rise", "return")]
    dwells = [(p.start, p.end) for p in law.phases if p.kind == "dwell"]
    rise = next((p.start, p.end) for p in law.phases if p.kind == "rise")
    back = next((p.start, p.end) for p in law.phases if p.kind == "return")
    lift = float(law.kinematics(np.array([rise[1]])).s[0] - law.kinematics(np.array([rise[0]])).s[0])

    def fresh() -> PiecewiseLinearLaw:      # a new law object each call: nothing cached on it
        return PiecewiseLinearLaw(x, a, law.cycle, law.phases)

    bounds = [(p.start, p.end) for p in law.phases]

    def floor():
        return floors.min_change_floor(x, a, motions, dwells, [rise], bounds)

    # the paper's knobs: the last lobe of each motion (its decelerating half), the whole return, the rise
    knobs = [((rise[0] + rise[1]) / 2, rise[1]), ((back[0] + back[1]) / 2, back[1]), back, rise]
    out = []
    for step in ((0.1,) if quick else (0.1, 0.01)):
        def peer(step=step):
            return peers.paper_loop(x, a, motions, rise, knobs, step_deg=step)

        times = cpu_interleaved({"camcad": lambda: balance.correct(fresh(), "min-change"), "floor": floor,
                                 "peer": peer}, rounds)
        fixed, floored, looped = balance.correct(law, "min-change"), floor(), peer()
        errors = {"camcad": references.simpson_closure(x, fixed.law.a, motions, lift),
                  "floor": references.simpson_closure(x, floored["a"], motions, lift),
                  "peer": references.simpson_closure(x, looped["a"], motions, lift)}
        areas = np.array([[r["area_positive"], r["area_negative"]] for r in fixed.after.phases])
        v_end = np.array([r["v_end"] for r in fixed.after.phases])
        moved = np.array([r["displacement"] for r in fixed.after.phases])
        v, s = floored["phase_motion_after"][0].reshape(-1, 2)[:, 1], floored["phase_motion_after"][1].reshape(-1, 2)
        same = max(float(np.max(np.abs(floored["a"] - fixed.law.a)) / np.max(np.abs(a))),
                   abs(floored["rms_change"] - fixed.rms_change) / fixed.rms_change,
                   float(np.max(np.abs(floored["areas_after"] - areas))) / float(np.max(np.abs(areas))),
                   float(np.max(np.abs(v - v_end))) / lift,   # v in mm/rad against the lift (mm)
                   float(np.max(np.abs((s[:, 1] - s[:, 0]) - moved))) / lift)
        out.append(row("min-change balancing", f"10,000-vertex drawn law; peer's step {step:g} deg", times, errors,
                       "closure / lift", "second method",
                       "Simpson's rule per drawn segment (exact for its quadratic and cubic integrands), math.fsum",
                       peer=f"the paper's loop, plainly (trapezoid at {step:g} deg, secant)", floor_figures=same,
                       status="ok", integrations=looped["integrations"]))
    return out


# =============================================================================================
# Elastic follower over a speed range
# =============================================================================================

FN_HZ, ZETA, LIFT = 40.0, 0.05, 25.0


def dynamics_rows(rounds: int, quick: bool) -> list[dict]:
    phases = references.SDOF_PHASES
    law = compose(list(phases), LIFT, "cycloidal")
    follower = dynamics.ElasticFollower(FN_HZ, ZETA)
    speeds = np.linspace(280.0, 420.0, 141)
    checked = speeds[::10]                                   # the error is measured at every 10th speed
    reference = [references.sdof_exact(float(rpm), FN_HZ, ZETA, LIFT) for rpm in checked]
    samples = dynamics.steady.DEFAULT_SAMPLES
    floor_law = floors.Law([(k, w, "cycloidal") for k, w in phases], LIFT)
    grid = 2 * np.pi * np.arange(samples) / samples

    def floor():
        s, _, a, _ = floor_law(grid)
        return floors.sweep_floor(s, a, 2 * np.pi, FN_HZ, ZETA, speeds)

    def accel(t: float) -> float:
        return float(floor_law(np.array([t]))[2][0])

    method, rtol = ("DOP853", 1e-10)

    def peer():
        return peers.solve_ivp_sweep(accel, FN_HZ, ZETA, speeds, method=method, rtol=rtol)

    candidates = {"camcad": lambda: dynamics.sweep(law, follower, speeds), "floor": floor}
    if not quick:
        candidates["peer"] = peer
    times = cpu_interleaved(candidates, rounds if not quick else 3)
    if quick:       # the peer takes seconds: one timed call

        times["peer"], peer_result = cpu_once(peer)
    else:
        peer_result = peer()
    kept = dynamics.sweep(law, follower, checked, keep=checked)
    step = samples // 256

    def error_of(accels) -> float:
        return float(max(np.max(np.abs(got - ref[0])) / ref[2] for got, ref in zip(accels, reference)))

    floor_result = floor()
    index = np.arange(0, 141, 10)
    errors = {"camcad": error_of([kept.responses[float(r)].accel_elastic[::step] for r in checked]),
              "floor": error_of(floor_result["accel"][index, ::step]),
              "peer": error_of(peer_result[index])}
    sweep = dynamics.sweep(law, follower, speeds)
    same = max(_relative(floor_result["peak_ratio"], sweep.peak_accel_ratio),
               _relative(floor_result["error_max"], sweep.dynamic_error_max))
    return [row("elastic follower over a speed range", f"141 speeds 280..420 rpm, N={samples}", times, errors,
                "fraction of the peak rigid acceleration", "closed form",
                "periodic solution by matrix exponentials per phase (scipy.linalg.expm), every 10th speed",
                peer=f"solve_ivp {method} rtol {rtol:g}, all speeds as one system", floor_figures=same,
                status="ok")]


# =============================================================================================
# Fourier coefficients of a standard law
# =============================================================================================

FOURIER_PHASES = (("dwell", 65.0), ("rise", 110.0), ("dwell", 115.0), ("return", 70.0))
HARMONICS = 32


def fourier_rows(rounds: int, quick: bool) -> list[dict]:
    law = compose(list(FOURIER_PHASES), LIFT, "cycloidal")
    exact = 2.0 * np.abs(references.cycloidal_coefficients(FOURIER_PHASES, LIFT, HARMONICS))
    floor_law = floors.Law([(k, w, "cycloidal") for k, w in FOURIER_PHASES], LIFT)
    samples = 1 << 13
    grid = 2 * np.pi * np.arange(samples) / samples

    def floor():
        s, _, a, _ = floor_law(grid)
        return floors.fourier_floor(s, a, HARMONICS)

    def peer():
        return peers.fft_adaptive(lambda t: floor_law(t)[0], HARMONICS, 1e-13)

    times = cpu_interleaved({"camcad": lambda: fourier.analyse(law, HARMONICS), "floor": floor, "peer": peer},
                            rounds)
    spectrum, floored, peered = fourier.analyse(law, HARMONICS), floor(), peer()
    errors = {"camcad": float(np.max(np.abs(spectrum.amplitudes - exact))),
              "floor": float(np.max(np.abs(floored["amplitudes"] - exact))),
              "peer": float(np.max(np.abs(peered["amplitudes"] - exact)))}
    same = float(np.max(np.abs(floored["amplitudes"] - spectrum.amplitudes)) / np.max(spectrum.amplitudes))
    return [row("Fourier coefficients of a standard law", f"cycloidal D-R-D-R, {HARMONICS} harmonics of s and a",
                times, errors, "mm (largest amplitude error)", "closed form",
                "c_k of the cycloidal motions in closed form, written out in camcad.bench.references",
                peer=f"numpy.fft.rfft of s, sampling doubled to 1e-13 mm (M={peered['samples']})",
                floor_figures=same, status="ok", floor_samples=samples)]


# =============================================================================================
# Reading a table
# =============================================================================================


def table_rows(rounds: int, quick: bool) -> list[dict]:
    count = 100_000 if quick else MAX_TABLE_LINES - 1   # the most lines camcad reads
    theta = np.linspace(0.0, 360.0, count)
    a = np.sin(np.radians(theta)) * 3.0 + 0.001 * np.cos(np.radians(7 * theta))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "law.csv"
        path.write_text("theta_deg,a\n" + "".join(f"{t!r},{v!r}\n" for t, v in zip(theta.tolist(), a.tolist())))
        times = cpu_interleaved({"camcad": lambda: read_table(path), "floor": lambda: floors.table_floor(path),
                                 "peer": lambda: peers.csv_reader(path)}, max(1, rounds // 2) if not quick else 2)
        table, floored, peered = read_table(path), floors.table_floor(path), peers.csv_reader(path)
    errors = {"camcad": float(max(np.max(np.abs(table.theta_deg - theta)), np.max(np.abs(table.values - a)))),
              "floor": float(max(np.max(np.abs(floored[:, 0] - theta)), np.max(np.abs(floored[:, 1] - a)))),
              "peer": float(max(np.max(np.abs(peered[:, 0] - theta)), np.max(np.abs(peered[:, 1] - a))))}
    same = float(max(np.max(np.abs(floored[:, 1] - table.values)), np.max(np.abs(floored[:, 0] - table.theta_deg))))
    return [row("reading a table", f"{count:,} rows theta_deg,a (CSV)", times, errors,
                "largest |value read − value written|", "property",
                "the values written (17 significant digits: read back exactly)",
                peer="the csv module and float()", floor_figures=same, status="ok")]


KERNELS: dict[str, Callable[..., list[dict]]] = {
    "profile": profile_rows, "balance": balance_rows, "dynamics": dynamics_rows, "fourier": fourier_rows,
    "table": table_rows}


def run(quick: bool = False, install_peers: bool | None = None, only=None) -> list[dict]:
    """The kernel table's rows (module docstring); ``install_peers`` (default: a full run) lets the profile
    row install the package ``mechanism`` into its own environment."""
    rounds = 3 if quick else 7
    install = (not quick) if install_peers is None else install_peers
    rows: list[dict] = []
    for name, make in KERNELS.items():
        if only and name not in only:
            continue
        rows += make(rounds, quick, install) if name == "profile" else make(rounds, quick)
    return rows


def floor_ratio_ok(rows: list[dict], limit: float = 2.0) -> bool:
    """Every kernel within ``limit`` × its floor (CPU time, same run)."""
    return all(r["floor_ratio"] is not None and r["floor_ratio"] <= limit for r in rows)


if __name__ == "__main__":
    import sys

    for r in run("--quick" in sys.argv):
        print(f"{r['kernel']:40s} {r['setting']:45s} camcad {r['camcad_s'] * 1e3:8.3f} ms  floor "
              f"{r['floor_s'] * 1e3:8.3f} ms  x{r['floor_ratio']:.2f}  peer "
              f"{(r['peer_s'] or math.nan) * 1e3:8.3f} ms  err {r['camcad_error']:.2e} {r['floor_error']:.2e} "
              f"{r['peer_error'] if r['peer_error'] is None else format(r['peer_error'], '.2e')}  "
              f"figs {r['floor_figures']:.1e}  {r.get('status')}")
