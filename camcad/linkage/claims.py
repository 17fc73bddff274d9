"""Measuring Sunkuev 1984's two claims about Q (Sunkuev 1984, ch. 2, conclusions 2 and 3 of the chapter):

1. minimising Q gives mechanisms "of higher accuracy than those obtained under the same initial
   conditions by minimising deviation functions";
2. one value of Q costs S positions of the mechanism, one value of a deviation N (usually several
   times S), so Q should need less computing time for the same number of steps.

The experiment (``compare_objectives``): random starts (b, α) of the Q method's free parameters; the
mechanism at a start is the centre mechanism of its pivots (skipped if the pivots do not exist).
From the *same* start, three single local searches run under the same limits:

- Q: ``qmethod.local_minimum`` (Nelder–Mead on the penalised Q, polishing as in the Q method);
- max deviation: ``deviation.max_deviation_synthesis`` (Nelder–Mead on max |Δψ| over N points);
- least squares: ``deviation.least_squares_synthesis`` (trust region on Σ Δψ² over N points).

Each result is checked on the dense grid (``fgen.evaluate``); positions and objective evaluations are
counted per run. No scan, no multistart: this isolates the objective function, as Sunkuev 1984's claim does.
"""

from __future__ import annotations

import math
import statistics
import time
from typing import Any

import numpy as np

from camcad.linkage.deviation import least_squares_synthesis, max_deviation_synthesis
from camcad.linkage.fgen import FunctionGenerator, Limits, Work, evaluate, nodes
from camcad.linkage.qmethod import QProblem, local_minimum
from camcad.linkage.target import Target


def _unit(fg: FunctionGenerator) -> FunctionGenerator:
    return FunctionGenerator(1.0, fg.b / fg.a, fg.c / fg.a, fg.d / fg.a, fg.phi0, fg.psi0, fg.branch)


def _admissible(fg: FunctionGenerator, target: Target, limits: Limits) -> bool:
    ev = evaluate(fg, target)
    links = fg.links()
    return bool(ev.branch_continuous and ev.mu_min_deg >= limits.mu_min_deg - 1e-6
                and max(links) / min(links) <= limits.ratio_max * (1 + 1e-9))


def compare_objectives(target: Target, limits: Limits, starts: int = 20, seed: int = 0, points: int = 41,
                       count: int = 5, spacing: str = "chebyshev", max_evaluations: int = 4000) -> dict:
    """Run the experiment of the module docstring; returns per-start rows and a summary.

    Errors are the largest |structural error| on the dense grid, deg; an inadmissible result (a limit
    violated, or the branch not continuous) counts as a failure of that run.

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> out = compare_objectives(t, Limits(30.0, 10.0), starts=1, seed=0, max_evaluations=100)
    >>> out["positions_per_evaluation"]["q"], out["positions_per_evaluation"]["deviation"], len(out["rows"])
    (5, 41, 1)
    """
    rng = np.random.default_rng(seed)
    node_phi = nodes(count, target.dphi, spacing)
    lo, hi = 1.0 / limits.ratio_max, limits.ratio_max
    rows: list[dict[str, Any]] = []
    tries = 0
    while len(rows) < starts and tries < 50 * starts:
        tries += 1
        start = (math.exp(rng.uniform(math.log(lo), math.log(hi))), rng.uniform(0.0, 2 * math.pi))
        probe = QProblem(target, node_phi, limits, Work())
        initial = probe.state(*start).mechanism
        if initial is None:
            continue
        row: dict[str, Any] = {"start_b": start[0], "start_alpha_deg": math.degrees(start[1]),
               "start_error_deg": evaluate(initial, target).max_error_deg}
        work = Work()
        problem = QProblem(target, node_phi, limits, work)
        clock = time.perf_counter()
        x, _ = local_minimum(problem, start)
        mech = problem.state(float(x[0]), float(x[1])).mechanism
        row["q"] = _outcome(mech, target, limits, work, time.perf_counter() - clock)
        for name in ("max_deviation", "least_squares"):
            work = Work()
            clock = time.perf_counter()
            if name == "max_deviation":
                mech = max_deviation_synthesis(target, _unit(initial), limits, work, points, max_evaluations)
            else:
                mech = least_squares_synthesis(target, _unit(initial), limits, work, points)
            row[name] = _outcome(mech, target, limits, work, time.perf_counter() - clock)
        rows.append(row)
    return {"rows": rows, "summary": summarise(rows), "points": points, "nodes": count, "seed": seed,
            "positions_per_evaluation": {"q": count, "deviation": points,
                                         "note": "plus at most 4 for the transmission-angle check of either"}}


def _outcome(mech: FunctionGenerator | None, target: Target, limits: Limits, work: Work, seconds: float) -> dict:
    if mech is None:
        return {"max_error_deg": math.inf, "admissible": False, "positions": work.positions,
                "evaluations": work.objective_evaluations, "seconds": seconds}
    ev = evaluate(mech, target)
    return {"max_error_deg": ev.max_error_deg, "admissible": _admissible(mech, target, limits),
            "positions": work.positions, "evaluations": work.objective_evaluations, "seconds": seconds}


def summarise(rows: list[dict]) -> dict:
    """Medians, best values, success counts (admissible; within 1e-6 deg of the best of that method:
    ``reaching_best``) and head-to-head wins of Q over each deviation method.

    Examples
    --------
    >>> run = lambda e: {"max_error_deg": e, "admissible": True, "positions": 5, "evaluations": 1, "seconds": 0.0}
    >>> rows = [{"q": run(0.1), "max_deviation": run(0.2), "least_squares": run(0.05)}]
    >>> s = summarise(rows)
    >>> s["q_more_accurate_than_max_deviation"], s["q_more_accurate_than_least_squares"]
    (1, 0)
    """
    out: dict[str, Any] = {"starts": len(rows)}
    for name in ("q", "max_deviation", "least_squares"):
        ok = [r[name]["max_error_deg"] for r in rows if r[name]["admissible"]]
        out[name] = {"admissible": len(ok),
                     "median_error_deg": statistics.median(ok) if ok else math.inf,
                     "best_error_deg": min(ok) if ok else math.inf,
                     "reaching_best": sum(1 for e in ok if e <= min(ok) + 1e-6),
                     "median_positions": statistics.median(r[name]["positions"] for r in rows),
                     "median_evaluations": statistics.median(r[name]["evaluations"] for r in rows),
                     "median_seconds": statistics.median(r[name]["seconds"] for r in rows)}
    for name in ("max_deviation", "least_squares"):
        wins = 0
        for r in rows:
            q_err = r["q"]["max_error_deg"] if r["q"]["admissible"] else math.inf
            other = r[name]["max_error_deg"] if r[name]["admissible"] else math.inf
            wins += q_err < other
        out[f"q_more_accurate_than_{name}"] = wins
    return out
