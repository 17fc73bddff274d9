"""One entry point for four-bar function-generator synthesis: ``synthesize(target, method, ...)``.

Methods (all return a mechanism scaled to the frame length asked for, its check on a dense grid and
the work done):

- ``precision``: three precision points, Freudenstein's closed form (``camcad.linkage.precision``);
- ``lsq``: least squares over N points (``camcad.linkage.deviation``), started from ``precision``;
- ``q``: the seed's Q method (``camcad.linkage.qmethod``);
- ``minimax``: the equal-ripple accuracy reference (``camcad.linkage.minimax``), started from the Q
  method run without the transmission-angle limit (an S-point interpolant); limits checked, not imposed.

``position_evaluations`` counts the positions a method computed to find its mechanism (a method
started from another includes the other's count; ``position_breakdown`` splits it); the final check
on the dense grid is ``verification_positions``, the same for every method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.deviation import least_squares_synthesis
from camcad.linkage.fgen import (
    Evaluation,
    FunctionGenerator,
    Limits,
    Work,
    evaluate,
    nodes,
)
from camcad.linkage.minimax import MinimaxResult, minimax_synthesis
from camcad.linkage.precision import precision_synthesis
from camcad.linkage.qmethod import QResult, node_subsets, q_synthesis
from camcad.linkage.target import Target

METHODS = ("q", "precision", "lsq", "minimax")
DEFAULT_LSQ_POINTS = 41


@dataclass(frozen=True)
class FgenOptions:
    """What to synthesise and how; angles in deg, lengths in mm."""

    method: str = "q"
    nodes: int | None = None           # q: S (odd, >= 5); precision: 3; lsq: N points; minimax: none
    spacing: str = "chebyshev"
    limits: Limits = field(default_factory=Limits)
    frame_mm: float = 100.0
    phi0_deg: float | None = None      # precision only
    psi0_deg: float | None = None
    seed: int = 0                      # q: shift of the scan grid
    grid: tuple[int, int] = (32, 64)   # q: scan grid (n_b, n_alpha)
    keep: int = 4                      # q: local runs
    pick: str = "centre"               # q: the seed's last step, centre or search
    max_error_deg: float | None = None


@dataclass
class FgenResult:
    """A synthesis: the target, the options, the mechanism (scaled to ``frame_mm``), its check, the nodes,
    the work done, and the Q-method and minimax details when those ran."""

    method: str
    target: Target
    options: FgenOptions
    mechanism: FunctionGenerator        # scaled to frame_mm
    evaluation: Evaluation
    nodes_phi: np.ndarray               # rad
    work: Work
    breakdown: dict[str, int]
    q: QResult | None = None
    minimax: MinimaxResult | None = None
    notes: list[str] = field(default_factory=list)
    q_nodes_phi: np.ndarray | None = None   # rad, the Q method's nodes (also when it started minimax)

    @property
    def q_subsets(self) -> list[tuple[int, ...]]:
        return node_subsets(len(self.q_nodes_phi)) if self.q_nodes_phi is not None else []


def _check_options(options: FgenOptions) -> None:
    if options.method not in METHODS:
        raise CamcadError(f"unknown method {options.method!r}", "--method", f"use one of {', '.join(METHODS)}")
    if options.spacing not in ("chebyshev", "uniform"):
        raise CamcadError(f"unknown spacing {options.spacing!r}", "--spacing", "use chebyshev or uniform")
    if not (0.0 <= options.limits.mu_min_deg < 90.0):
        raise CamcadError(f"--mu-min {options.limits.mu_min_deg:g} deg is not in [0, 90)", "--mu-min",
                          "give the smallest transmission angle in deg, e.g. --mu-min 30")
    if not options.limits.ratio_max > 1.0:
        raise CamcadError(f"--ratio-max {options.limits.ratio_max:g} must exceed 1", "--ratio-max",
                          "give the largest allowed link-length ratio, e.g. --ratio-max 10")
    if not (options.frame_mm > 0 and math.isfinite(options.frame_mm)):
        raise CamcadError(f"--frame {options.frame_mm:g} mm must be positive", "--frame", "give the frame length in mm")
    n = options.nodes
    if options.method == "precision" and n not in (None, 3):
        raise CamcadError(f"precision-point synthesis uses 3 nodes, not {n}", "--nodes",
                          "drop --nodes, or use --method q (S nodes) or lsq (N points)")
    if options.method == "q" and n is not None:
        if n < 5:
            raise CamcadError(f"the Q method needs S >= 5 nodes (the four-bar has S = 5 parameters), got {n}",
                              "--nodes", "give --nodes 5 (or 7, 9, ... for more subsets)")
        node_subsets(n)
    if options.method == "lsq" and n is not None and n < 6:
        raise CamcadError(f"least squares needs more points than the 5 parameters, got {n}", "--nodes",
                          "give --nodes 41 or so")
    if options.method == "minimax" and n is not None:
        raise CamcadError("the minimax method has no nodes to choose (it finds S + 1 = 6 references)", "--nodes",
                          "drop --nodes")
    if options.method != "precision" and (options.phi0_deg is not None or options.psi0_deg is not None):
        raise CamcadError("--phi0/--psi0 are the offsets of the precision-point method", "--phi0/--psi0",
                          "drop them or use --method precision")
    if options.pick not in ("centre", "search"):
        raise CamcadError(f"unknown pick {options.pick!r}", "--pick", "use centre or search")


def synthesize(target: Target, options: FgenOptions) -> FgenResult:
    """Synthesise a four-bar function generator for ``target`` by ``options.method``.

    Examples
    --------
    Three precision points: the error vanishes at the three Chebyshev nodes (closed form).

    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0, frame_mm=100.0))
    >>> from camcad.linkage.fgen import structural_error
    >>> float(np.max(np.abs(structural_error(r.mechanism, t, r.nodes_phi)))) < 1e-12, r.mechanism.d
    (True, 100.0)
    """
    _check_options(options)
    limits = options.limits
    work = Work()
    breakdown: dict[str, int] = {}
    notes: list[str] = []
    q_result = None
    mm_result = None
    method = options.method
    if method in ("precision", "lsq"):
        node_phi = nodes(3, target.dphi, options.spacing)
        fg = precision_synthesis(target, node_phi, limits, work, options.phi0_deg, options.psi0_deg)
        breakdown["precision"] = work.positions
        if options.phi0_deg is None:
            notes.append("precision: offsets phi0, psi0 scanned on a 5 deg grid (the least max error on 21 points)")
        if method == "lsq":
            points = options.nodes or DEFAULT_LSQ_POINTS
            node_phi = nodes(points, target.dphi, options.spacing)
            before = work.positions
            fg = least_squares_synthesis(target, fg, limits, work, points, phi=node_phi)
            breakdown["least squares"] = work.positions - before
    else:
        count = options.nodes or 5
        node_phi = nodes(count, target.dphi, options.spacing)
        q_limits = limits if method == "q" else Limits(0.0, limits.ratio_max)
        q_nodes = node_phi
        q_result = q_synthesis(target, node_phi, q_limits, work, grid=options.grid, seed=options.seed,
                               keep=options.keep, pick=options.pick)
        fg = q_result.mechanism
        breakdown["q"] = work.positions
        if not q_result.feasible:
            notes.append(q_result.message)
        if method == "minimax":
            before = work.positions
            mm_result = minimax_synthesis(target, fg, work)
            fg = mm_result.mechanism
            breakdown["remez"] = work.positions - before
            node_phi = np.radians(mm_result.references_deg)
            notes.append("minimax is the accuracy reference: the equal-ripple four-bar near the S-point "
                         "interpolant of the Q method run without the transmission-angle limit; the limits are "
                         "checked, not imposed")
            if not mm_result.converged:
                notes.append(f"minimax: {mm_result.message}")
    scaled = fg.scaled(options.frame_mm)
    evaluation = evaluate(scaled, target)
    return FgenResult(method, target, options, scaled, evaluation, np.asarray(node_phi), work, breakdown,
                      q_result, mm_result, notes, None if q_result is None else np.asarray(q_nodes))


def _check(value: float, limit: float, margin: float, passed: bool, why: str) -> dict:
    return {"value": value, "limit": limit, "margin": margin, "passed": passed, "why": why}


def report(result: FgenResult) -> dict:
    """The JSON report of a synthesis (SPEC.md keys: method, links, max_error_deg, rms_error_deg,
    mu_min_deg, position_evaluations, nodes_deg; every check as {value, limit, margin, passed, why}).

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> out = report(synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0)))
    >>> sorted(out["links"]), out["position_evaluations"], len(out["nodes_deg"])
    (['a', 'b', 'c', 'd'], 3, 3)
    """
    fg, ev, t, o = result.mechanism, result.evaluation, result.target, result.options
    links = fg.links()
    ratio = max(links) / min(links)
    checks = {
        "transmission_angle": _check(ev.mu_min_deg, o.limits.mu_min_deg, ev.mu_min_deg - o.limits.mu_min_deg,
                                     bool(ev.mu_min_deg >= o.limits.mu_min_deg - 1e-9),
                                     "smallest min(mu, 180 - mu) over the working range (deg), closed form"),
        "link_ratio": _check(ratio, o.limits.ratio_max, o.limits.ratio_max - ratio,
                             bool(ratio <= o.limits.ratio_max * (1 + 1e-12)),
                             "longest / shortest link"),
        "branch": _check(ev.largest_step_deg, ev.step_bound_deg, ev.step_bound_deg - ev.largest_step_deg,
                         bool(ev.branch_continuous),
                         f"largest step of the output angle between {len(ev.phi)} grid points (deg) against "
                         "1.5 max|dbeta/dtheta| h: no jump to the other assembly branch, no dead point"),
    }
    if o.max_error_deg is not None:
        checks["max_error"] = _check(ev.max_error_deg, o.max_error_deg, o.max_error_deg - ev.max_error_deg,
                                     bool(ev.max_error_deg <= o.max_error_deg), "largest |structural error| (deg)")
    nodes_deg = [math.degrees(v) for v in result.nodes_phi]
    out = {
        "method": result.method,
        "function": t.label,
        "x": [t.x0, t.x1],
        "input_range_deg": t.input_range_deg,
        "output_range_deg": t.output_range_deg,
        "links": {"a": links[0], "b": links[1], "c": links[2], "d": links[3]},
        "link_names": {"a": "input crank OA", "b": "coupler AB", "c": "output rocker CB", "d": "frame OC"},
        "offsets_deg": {"phi0": math.degrees(fg.phi0) % 360.0, "psi0": math.degrees(fg.psi0) % 360.0},
        "branch": fg.branch,
        "grashof": {"class": ev.grashof, "s_plus_l_minus_p_plus_q_mm": ev.grashof_margin},
        "max_error_deg": ev.max_error_deg,
        "rms_error_deg": ev.rms_error_deg,
        "mu_min_deg": ev.mu_min_deg,
        "mu_min_at_deg": ev.mu_min_at_deg,
        "position_evaluations": result.work.positions,
        "position_breakdown": dict(result.breakdown),
        "objective_evaluations": result.work.objective_evaluations,
        "verification_positions": ev.positions,
        "nodes_deg": nodes_deg,
        "nodes_x": [float(v) for v in t.x_of(result.nodes_phi)],
        "spacing": o.spacing,
        "error_extrema": [{"phi_deg": p, "error_deg": e} for p, e in ev.extrema],
        "checks": checks,
        "passed": all(c["passed"] for c in checks.values()),
        "notes": list(result.notes),
    }
    if result.q is not None:
        st = result.q.state
        xs = [c.real for c in st.pivots]
        ys = [c.imag for c in st.pivots]
        out["q"] = {
            "value": st.q,
            "unit": "crank lengths (a = 1 during the search; camcad's normalisation)",
            "nodes": len(result.nodes_phi) if result.method == "q" else 5,
            "subsets": node_subsets(len(result.nodes_phi) if result.method == "q" else 5),
            "free_parameters": {"b_over_a": st.b, "alpha_deg": math.degrees(st.alpha) % 360.0},
            "pivots": [[c.real, c.imag] for c in st.pivots],
            "rectangle": {"x": [min(xs), max(xs)], "y": [min(ys), max(ys)]},
            "pick": result.q.pick,
            "limits_met": result.q.feasible,
            "scan_points": result.q.samples,
            "local_runs": result.q.local_runs,
        }
    if result.minimax is not None:
        mm = result.minimax
        out["minimax"] = {"level_deg": mm.level_deg, "references_deg": mm.references_deg,
                          "extrema_deg": mm.extrema_deg, "ripple_spread": mm.ripple_spread,
                          "iterations": mm.iterations, "converged": mm.converged, "message": mm.message}
    return out
