"""Linkage: atlas time per class, and speed against error of every function-generator method.

Atlas rows: time to enumerate one class of chains; error = |count − reference| where the reference is the
published count (ordinary chains: Tsai 2001) or Sunkuev 1984's Table 1 (adjustable chains; the n' = 8 row is
not reproduced, see docs/linkage.md), unit "chains".

Function-generator rows: y = log10(x) on [1, 2], input 60 deg, output 90 deg, mu >= 30 deg, link ratio
<= 10, 5 Chebyshev nodes; error = largest |structural error| on a 2001-point grid (deg); the setting
names the position computations the method used. Plus Sunkuev 1984's claim (Q against deviation
minimisation from the same random starts, single local searches): median error of the admissible
results and median positions.

Run: python benchmarks/bench_linkage.py [--quick]
"""

from __future__ import annotations

import argparse

import numpy as np
from timing import median_time

from camcad.linkage.atlas import (
    PUBLISHED_ORDINARY,
    SEED_TABLE1,
    adjustable_chains,
    ordinary_chains,
)
from camcad.linkage.claims import compare_objectives
from camcad.linkage.fgen import Limits
from camcad.linkage.synthesis import FgenOptions, synthesize
from camcad.linkage.target import make_target


def _row(kernel: str, method: str, setting: str, time_s: float, error: float, unit: str) -> dict:
    return {"kernel": kernel, "method": method, "setting": setting, "time_s": time_s, "error": error,
            "error_unit": unit}


def atlas_rows(quick: bool) -> list[dict]:
    rows = []
    ordinary = [(4, 1), (6, 1), (8, 1), (5, 2), (7, 2)] + ([] if quick else [(9, 2), (10, 1)])
    for links, dof in ordinary:
        elapsed, result = median_time(lambda n=links, w=dof: ordinary_chains(n, w), 1 if quick or links >= 9 else 3)
        rows.append(_row("linkage atlas", "ordinary chains (contracted graphs)",
                         f"n={links} W={dof}: {len(result.chains)} chains, {result.candidates} candidates", elapsed,
                         abs(len(result.chains) - PUBLISHED_ORDINARY[(links, dof)]), "chains vs published"))
    table = [(4, 1, 1), (4, 1, 2), (4, 1, 3), (6, 1, 1), (6, 1, 2)] + ([] if quick else [(8, 1, 1)])
    for key in table:
        elapsed, result = median_time(lambda k=key: adjustable_chains(*k), 1 if quick or key[0] >= 8 else 3)
        rows.append(_row("linkage atlas", "adjustable chains (coloured, contracted check)",
                         f"n'={key[0]} W'={key[1]} m={key[2]}: {len(result.chains)} (Sunkuev 1984: {SEED_TABLE1[key]})",
                         elapsed, abs(len(result.chains) - SEED_TABLE1[key]), "chains vs seed Table 1"))
    return rows


def fgen_rows(quick: bool) -> list[dict]:
    target = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    rows = []
    methods = ["precision", "q"] + ([] if quick else ["lsq", "minimax"])
    for method in methods:
        elapsed, result = median_time(lambda m=method: synthesize(target, FgenOptions(method=m)), 1)
        rows.append(_row("linkage fgen log10", method,
                         f"{result.work.positions} positions, mu_min {result.evaluation.mu_min_deg:.1f} deg", elapsed,
                         result.evaluation.max_error_deg, "deg (max |error|)"))
    starts = 2 if quick else 12
    claim = compare_objectives(target, Limits(30.0, 10.0), starts=starts, seed=0)
    s = claim["summary"]
    for name, label in (("q", "Q, one local search"), ("max_deviation", "max deviation, one local search"),
                        ("least_squares", "least squares, one local search")):
        rows.append(_row("linkage claim (same starts)", label,
                         f"{starts} starts: {s[name]['admissible']} admissible, {s[name]['reaching_best']} reach its "
                         f"best ({s[name]['best_error_deg']:.4g} deg), median {s[name]['median_positions']:.0f} "
                         "positions", s[name]["median_seconds"],
                         s[name]["median_error_deg"], "deg (median max |error|)"))
    return rows


def run(quick: bool) -> list[dict]:
    return atlas_rows(quick) + fgen_rows(quick)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small classes, two fgen methods, 2 starts")
    args = parser.parse_args()
    for row in run(args.quick):
        print(row)


if __name__ == "__main__":
    main()
