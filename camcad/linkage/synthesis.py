"""One entry point for four-bar function-generator synthesis: ``synthesize(target, method, ...)``.

Methods (all return a mechanism scaled to the frame length asked for, its check on a dense grid and
the work done):

- ``precision``: three precision points, Freudenstein's closed form (``camcad.linkage.precision``);
- ``lsq``: least squares over N points (``camcad.linkage.deviation``), started from ``precision``;
- ``q``: Sunkuev 1984's Q method (``camcad.linkage.qmethod``);
- ``minimax``: the least maximum error under the limits (``camcad.linkage.minimax.constrained_minimax``),
  started from the admissible results of ``lsq`` and ``q`` (and of the other methods with ``--method all``);
- ``remez``: the equal-ripple four-bar without limits (``camcad.linkage.minimax.minimax_synthesis``), started
  from the Q method run without the transmission-angle limit: what the limits cost, not a design (its
  limits are checked and usually fail).

``position_evaluations`` counts the positions a method computed to find its mechanism (a method
started from another includes the other's count; ``position_breakdown`` splits it); the final check
on the dense grid is ``verification_positions``, the same for every method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

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
    structural_error,
)
from camcad.linkage.minimax import (
    ConstrainedMinimax,
    MinimaxResult,
    constrained_minimax,
    minimax_synthesis,
)
from camcad.linkage.precision import precision_synthesis
from camcad.linkage.qmethod import QResult, node_subsets, q_synthesis
from camcad.linkage.target import Target

METHODS = ("q", "precision", "lsq", "minimax", "remez")
#: the methods whose optimisation keeps the limits (remez is the unconstrained reference)
CONSTRAINED = ("q", "precision", "lsq", "minimax")
DEFAULT_LSQ_POINTS = 41
#: the accuracy asked for when --max-error is not given: this fraction of the output range
DEFAULT_TOLERANCE = 0.01


@dataclass(frozen=True)
class FgenOptions:
    """What to synthesise and how; angles in deg, lengths in mm."""

    method: str = "q"
    nodes: int | None = None           # q: S (odd, >= 5); precision: 3; lsq: N points; minimax, remez: none
    spacing: str = "chebyshev"
    limits: Limits = field(default_factory=Limits)
    frame_mm: float = 100.0
    phi0_deg: float | None = None      # precision only
    psi0_deg: float | None = None
    seed: int = 0                      # q: shift of the scan grid
    grid: tuple[int, int] = (32, 64)   # q: scan grid (n_b, n_alpha)
    keep: int = 4                      # q: local runs
    pick: str = "centre"               # q: Sunkuev 1984's last step, centre or search
    max_error_deg: float | None = None   # the accuracy asked for; None: 1 % of the output range


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
    constrained: ConstrainedMinimax | None = None

    @property
    def admissible(self) -> bool:
        """The limits are met: transmission angle, link ratio, one branch without a dead point."""
        ev, limits = self.evaluation, self.options.limits
        links = self.mechanism.links()
        return bool(ev.mu_min_deg >= limits.mu_min_deg and max(links) / min(links) <= limits.ratio_max
                    and ev.branch_continuous)

    @property
    def q_subsets(self) -> list[tuple[int, ...]]:
        return node_subsets(len(self.q_nodes_phi)) if self.q_nodes_phi is not None else []


def _unit(fg: FunctionGenerator) -> FunctionGenerator:
    """The same mechanism with the crank a = 1."""
    return replace(fg, a=1.0, b=fg.b / fg.a, c=fg.c / fg.a, d=fg.d / fg.a)


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
    if options.method in ("minimax", "remez") and n is not None:
        raise CamcadError(f"the {options.method} method has no nodes to choose (it finds its own points)",
                          "--nodes", "drop --nodes")
    if options.max_error_deg is not None and not (options.max_error_deg > 0 and math.isfinite(options.max_error_deg)):
        raise CamcadError(f"--max-error {options.max_error_deg:g} deg must be positive", "--max-error",
                          "give the accuracy asked for in deg, e.g. --max-error 0.5")
    if options.method != "precision" and (options.phi0_deg is not None or options.psi0_deg is not None):
        raise CamcadError("--phi0/--psi0 are the offsets of the precision-point method", "--phi0/--psi0",
                          "drop them or use --method precision")
    if options.pick not in ("centre", "search"):
        raise CamcadError(f"unknown pick {options.pick!r}", "--pick", "use centre or search")


def synthesize(target: Target, options: FgenOptions, starts: list[FgenResult] | None = None) -> FgenResult:
    """Synthesise a four-bar function generator for ``target`` by ``options.method``.

    ``starts``: results of other methods for ``minimax`` to start from (``--method all`` passes them; without
    them minimax runs ``lsq`` and ``q`` itself and counts their positions).

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
    cm_result = None
    q_nodes = None
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
    elif method == "minimax":
        given = list(starts or [])
        if not given:
            for name in ("lsq", "q"):
                before = work.positions
                given.append(synthesize(target, FgenOptions(method=name, spacing=options.spacing, limits=limits,
                                                             seed=options.seed)))
                breakdown[name] = given[-1].work.positions
                work.positions = before + given[-1].work.positions
        else:
            notes.append("minimax: started from the results of " + ", ".join(r.method for r in given)
                         + " (their positions are not counted here)")
        pool = [(r.method, _unit(r.mechanism)) for r in given if r.method != "remez" and r.admissible]
        if not pool:
            pool = [(r.method, _unit(r.mechanism)) for r in given]
            notes.append("minimax: no start meets the limits; started from the others' results anyway")
        before = work.positions
        cm_result = constrained_minimax(target, pool, limits, work)
        breakdown["minimax"] = work.positions - before
        fg = cm_result.mechanism
        node_phi = np.array([])
        if not cm_result.admissible:
            notes.append(f"minimax: {cm_result.message}")
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
        if method == "remez":
            before = work.positions
            mm_result = minimax_synthesis(target, fg, work)
            fg = mm_result.mechanism
            breakdown["remez"] = work.positions - before
            node_phi = np.radians(mm_result.references_deg)
            notes.append("remez is the equal-ripple four-bar without limits (started from the Q method's S-point "
                         "interpolant): what the limits cost; its limits are checked, not imposed")
            if not mm_result.converged:
                notes.append(f"remez: {mm_result.message}")
    scaled = fg.scaled(options.frame_mm)
    evaluation = evaluate(scaled, target)
    return FgenResult(method, target, options, scaled, evaluation, np.asarray(node_phi), work, breakdown,
                      q_result, mm_result, notes, None if q_nodes is None else np.asarray(q_nodes), cm_result)


def error_tolerance(options: FgenOptions, target: Target) -> float:
    """The largest structural error (deg) the verdict allows: ``max_error_deg``, else 1 % of |output range|.

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> error_tolerance(FgenOptions(), make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)"))
    0.9
    """
    if options.max_error_deg is not None:
        return float(options.max_error_deg)
    return DEFAULT_TOLERANCE * abs(target.output_range_deg)


def _check(value: float, limit: float, margin: float, passed: bool, why: str) -> dict:
    return {"value": value, "limit": limit, "margin": margin, "passed": passed, "why": why}


def report(result: FgenResult) -> dict:
    """The JSON report of a synthesis (docs/INTERFACE.md keys: method, links, max_error_deg, rms_error_deg,
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
    tolerance = error_tolerance(o, t)
    checks = {
        "transmission_angle": _check(ev.mu_min_deg, o.limits.mu_min_deg, ev.mu_min_deg - o.limits.mu_min_deg,
                                     bool(ev.mu_min_deg >= o.limits.mu_min_deg),
                                     "smallest min(mu, 180 - mu) over the working range (deg), closed form"),
        "link_ratio": _check(ratio, o.limits.ratio_max, o.limits.ratio_max - ratio,
                             bool(ratio <= o.limits.ratio_max), "longest / shortest link"),
        "branch": _check(ev.largest_step_deg, ev.step_bound_deg, ev.step_bound_deg - ev.largest_step_deg,
                         bool(ev.branch_continuous),
                         f"largest step of the output angle between {len(ev.phi)} grid points (deg) against "
                         "1.5 max|dbeta/dtheta| h, and no dead point (transmission angle 0 or 180 deg) in the "
                         "range: no jump to the other assembly branch"),
        "max_error": _check(ev.max_error_deg, tolerance, tolerance - ev.max_error_deg,
                            bool(ev.max_error_deg <= tolerance),
                            "largest |structural error| (deg) against " + (
                                "--max-error" if o.max_error_deg is not None else
                                f"{100 * DEFAULT_TOLERANCE:g} % of the output range (the default; set --max-error)")),
    }
    for name in ("transmission_angle", "link_ratio"):
        c = checks[name]
        if c["passed"] and abs(c["margin"]) <= 1e-6 * abs(c["limit"]):
            c["note"] = "at its limit (the optimisation holds it there): no reserve"
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
        "node_errors_deg": [float(v) for v in np.degrees(structural_error(fg, t, result.nodes_phi))],
        "constrained": result.method in CONSTRAINED,
        "admissible": result.admissible,
        "max_error_tolerance_deg": tolerance,
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
    if result.constrained is not None:
        cm = result.constrained
        out["minimax"] = {"problem": "least max |error| under the limits (epigraph form, SLSQP, points exchanged)",
                          "level_deg": cm.level_deg, "points": cm.points, "rounds": cm.rounds, "starts": cm.runs,
                          "winning_start": cm.start, "message": cm.message}
    if result.minimax is not None:
        mm = result.minimax
        out["remez"] = {"level_deg": mm.level_deg, "references_deg": mm.references_deg,
                          "extrema_deg": mm.extrema_deg, "ripple_spread": mm.ripple_spread,
                          "iterations": mm.iterations, "converged": mm.converged, "message": mm.message}
    return out
