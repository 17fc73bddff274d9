"""Cyclogram optimisation: solve time against network size, error against an exact longest path.

Networks: random precedence DAGs (events in topological order, each with 1–3 predecessors, lower
bounds 1…60 deg). Reference: the longest path by one forward sweep in topological order (exact for
a DAG). Methods: ``camcad.cyclogram.optimise`` (longest paths by Bellman–Ford in topological order);
the source's LP in two stages by scipy's HiGHS (written here, for comparison: what ``optimise`` used
before); the conflict search ``find_conflict`` on a network made infeasible by one
upper bound (dense max-plus search up to 120 events, Bellman–Ford above).

Run: python benchmarks/bench_cyclogram.py [--quick]
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from timing import median_time

from camcad.cyclogram import Constraint, constraints_of
from camcad.cyclogram.conflicts import find_conflict
from camcad.cyclogram.lp import optimise
from camcad.cyclogram.network import Operation, make_network

REFERENCE = "exact longest path of the DAG by one forward sweep in topological order (written here)"


def random_network(events: int, seed: int):
    """A random DAG on events 0..n−1 and its exact longest-path makespan (forward sweep)."""
    rng = np.random.default_rng(seed)
    ops = []
    earliest = np.zeros(events)
    has_successor = np.zeros(events, dtype=bool)
    for j in range(1, events):
        count = int(rng.integers(1, 4))
        tails = sorted({int(t) for t in rng.integers(max(0, j - 8), j, count)})
        for i in tails:
            weight = float(rng.uniform(1.0, 60.0))
            ops.append(Operation(str(i), str(j), weight))
            has_successor[i] = True
    for i in range(events - 1):
        if not has_successor[i]:
            ops.append(Operation(str(i), str(events - 1), 0.0))
    for op in ops:   # operations are listed with heads in increasing order: one sweep is exact
        earliest[int(op.head)] = max(earliest[int(op.head)], earliest[int(op.tail)] + op.min_deg)
    network = make_network(ops, cycle_deg=1e9)
    return network, float(earliest[-1])


def lp_makespan(network) -> float:
    """The source's LP (minimise p(end) − p(start) under the difference constraints) and its second stage
    (the earliest schedule), by scipy's HiGHS; the makespan (deg)."""
    from scipy.optimize import linprog
    from scipy.sparse import csr_matrix

    constraints = constraints_of(network)
    index = {event: k for k, event in enumerate(network.events)}
    n, m = len(index), len(constraints)
    cols = np.array([[index[c.tail], index[c.head]] for c in constraints]).ravel()
    a_ub = csr_matrix((np.tile([1.0, -1.0], m), (np.repeat(np.arange(m), 2), cols)), shape=(m, n))
    b_ub = np.array([-c.weight for c in constraints])
    bounds: list = [(None, None)] * n
    bounds[index[network.start]] = (network.start_deg, network.start_deg)
    goal = np.zeros(n)
    goal[index[network.end]] = 1.0
    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
    first = linprog(goal, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    bounds[index[network.end]] = (None, first.x[index[network.end]] + 1e-9)
    second = linprog(np.ones(n), A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    return float(second.x[index[network.end]]) - network.start_deg


def _median_time(function, repeats: int):
    return median_time(function, repeats, warm_up=False)


def run(quick: bool) -> list[dict]:
    sizes = [10, 100, 1000] if quick else [10, 100, 1000, 5000]
    repeats = 3 if quick else 5
    rows = []
    import scipy.optimize  # noqa: F401 - imported before the LP is timed, so that the rows time the solve only

    for events in sizes:
        network, reference = random_network(events, seed=events)
        setting = f"events={events} ops={len(network.operations)}"
        elapsed, result = _median_time(lambda network=network: optimise(network), repeats)
        rows.append({"kernel": "cyclogram", "method": "optimise: longest paths", "setting": setting, "time_s": elapsed,
                         "error": abs(result.makespan_deg - reference), "error_unit": "deg vs exact longest path",
                         "reference": REFERENCE})
        if events <= 1000:
            elapsed, makespan = _median_time(lambda network=network: lp_makespan(network), 1)
            rows.append({"kernel": "cyclogram", "method": "linprog HiGHS (2 stages)", "setting": setting,
                             "time_s": elapsed, "error": abs(makespan - reference),
                             "error_unit": "deg vs exact longest path", "reference": REFERENCE})
        # infeasible: cap the makespan 5 deg below the longest path; the conflict found must be a
        # closed cycle of constraints with positive excess (error 0 when it is, inf when not)
        capped = [c for c in constraints_of(network) if c.kind != "cycle"]
        capped.append(Constraint("cycle", "makespan", reference - 5.0, "cycle_deg", network.end, network.start))
        elapsed, conflict = _median_time(lambda network=network, capped=capped: find_conflict(network.events, capped),
                                         1)
        closed = bool(conflict) and all(a.head == b.tail for a, b in zip(conflict, conflict[1:] + conflict[:1]))
        valid = closed and sum(c.weight for c in conflict) > 0
        method = "conflict: max-plus (fewest)" if events <= 120 else "conflict: Bellman-Ford"
        rows.append({"kernel": "cyclogram", "method": method, "setting": f"{setting} arcs={len(conflict)}",
                         "time_s": elapsed, "error": 0.0 if valid else math.inf,
                         "error_unit": "0: a closed cycle of positive excess (checked here)",
                         "reference": "the conflict checked to be a closed cycle of constraints "
                                      "with positive total weight"})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller networks, fewer repeats")
    args = parser.parse_args()
    rows = run(args.quick)
    print(f"{'method':32} | {'setting':38} | {'time (median)':>13} | error vs exact longest path")
    print("-" * 116)
    for row in rows:
        print(f"{row['method']:32} | {row['setting']:38} | {row['time_s'] * 1e3:10.2f} ms | "
              f"{row['error']:.3g} {row['error_unit']}")


if __name__ == "__main__":
    main()
