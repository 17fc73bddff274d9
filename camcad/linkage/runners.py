"""`camcad linkage` commands as library calls: a request in, a typed report out (Sunkuev 1984).

Each command that needs no scene has a ``run_linkage_<command>(request) -> report`` here (``atlas``, ``fgen``,
``path``, ``family``); the scene-aware ones (``analyse``, ``adjust``, ``tune``) are in
``camcad.scene.linkage_commands``. A report has ``to_dict()`` (the JSON the command prints with ``--json`` and
writes), ``exit_code`` (0 passed, 1 a check failed) and ``lines()`` (the text the command prints); the report
layer (``camcad.report.linkage_commands``) writes its files. Requests take lengths in mm and angles in deg; a
pair or a list may be given as a sequence or as the command line writes it ("1:2", "40,120,90").

Source: B. S. Sunkuev, *Optimisation synthesis of adjustable linkages of light-industry machines*, doctoral
abstract, Moscow Technological Institute of Light Industry, 1984 (ch. 1: the atlas; ch. 2: function
generators and the Q method; ch. 4: families of position functions; ch. 5: guiding mechanisms).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, overload

import numpy as np

from camcad.errors import CamcadError
from camcad.io.input_file import decode_text, read_input
from camcad.linkage.atlas import AtlasReport, atlas
from camcad.linkage.expr import parse_expression
from camcad.linkage.family import FamilyResult, Member, synthesize_family
from camcad.linkage.fgen import Limits
from camcad.linkage.path import (
    DEFAULT_TOLERANCE,
    OPTIONS,
    TASKS,
    PathFamilyResult,
    PathResult,
    PathTarget,
    deviation_synthesis,
    path_family,
    q_synthesis,
    read_target,
)
from camcad.linkage.path import make_target as make_path_target
from camcad.linkage.schemes import annotate_schemes
from camcad.linkage.sixbar import SixbarOptions, SixbarResult, synthesize_sixbar
from camcad.linkage.sixbar import report as sixbar_report
from camcad.linkage.synthesis import CONSTRAINED, METHODS, FgenOptions, FgenResult, report, synthesize
from camcad.linkage.target import Target, make_target, target_from_table
from camcad.linkage.variator import VariatorResult, synthesise_variator

# --------------------------------------------------------------------------------------------
# Options as the command line writes them, or as values
# --------------------------------------------------------------------------------------------

@overload
def numbers(value: Any, option: str, count: Literal[2], example: str = ...) -> tuple[float, float] | None: ...


@overload
def numbers(value: Any, option: str, count: Literal[3], example: str = ...) -> tuple[float, float, float] | None: ...


@overload
def numbers(value: Any, option: str, count: int | None = None, example: str = ...) -> tuple[float, ...] | None: ...


def numbers(value: Any, option: str, count: int | None = None, example: str = "1:2") -> tuple[float, ...] | None:
    """A list of numbers from a sequence or from text ("1:2", "40,120,90", "10;20"); None stays None.

    Examples
    --------
    >>> numbers("40,120,90", "--links", 3), numbers((1, 2), "--x", 2), numbers(None, "--x")
    ((40.0, 120.0, 90.0), (1.0, 2.0), None)
    """
    if value is None:
        return None
    parts: list[Any]
    if isinstance(value, str):
        parts = [p for p in value.replace(";", ",").replace(":", ",").split(",") if p.strip()]
    elif isinstance(value, (int, float)):
        parts = [value]
    else:
        parts = list(value)
    try:
        out = tuple(float(p) for p in parts)
    except (TypeError, ValueError):
        raise CamcadError(f"{value!r} is not a list of numbers", option, f"write {option} {example}") from None
    if count is not None and len(out) != count:
        raise CamcadError(f"{value!r} is not {count} numbers", option, f"write {option} {example}")
    if not all(math.isfinite(v) for v in out):
        raise CamcadError(f"{value!r} is not finite", option, f"write {option} {example}")
    return out


def outputs_line(outputs: Sequence) -> list[str]:
    """The "wrote" line of a command's text output."""
    if not outputs:
        return []
    return [f"  wrote          {Path(outputs[0]).parent}/: {', '.join(Path(p).name for p in outputs)}"]


@dataclass
class LinkageReport:
    """What a ``camcad linkage`` command found: the JSON payload, the verdict, the text.

    Attributes
    ----------
    command : str
        The command (``"fgen"``, ``"path"``, …); it names the JSON file (``<command>.json``).
    payload : dict
        The JSON object (lengths mm, angles deg).
    passed : bool
        Every check passed (a comparison, ``fgen --method all``, passes).
    summary : list of str
        The text the command prints.
    name : str
        The default output folder's name (``./camcad-out/<name>/``).
    inputs : tuple of Path
        Files the command read (never replaced by an output).
    """

    command: str
    payload: dict
    passed: bool
    summary: list[str] = field(default_factory=list)
    name: str = "linkage"
    inputs: tuple[Path, ...] = ()
    #: ``--animate``: the animation files asked for ("html", "gif", "mp4") and their frames
    #: (``camcad.scene.animation.MechanismFrames`` or ``LinkageMotion``), None when not asked or not drawable
    animate: tuple[str, ...] = field(default=(), kw_only=True)
    animation: Any = field(default=None, kw_only=True)

    @property
    def exit_code(self) -> int:
        """0 when every check passed, 1 when one failed."""
        return 0 if self.passed else 1

    def to_dict(self) -> dict:
        """The JSON object (``--json`` and ``<command>.json``)."""
        return dict(self.payload)

    def lines(self) -> list[str]:
        """The text output."""
        return list(self.summary)


# --------------------------------------------------------------------------------------------
# atlas
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AtlasRequest:
    """What ``camcad linkage atlas`` enumerates (Sunkuev 1984, ch. 1 and Table 1).

    Parameters
    ----------
    links : int
        Number of links n, the frame counted; with ``adjustable``, n' of the adjustable chain.
    dof : int
        Mobility W; with ``adjustable``, W'.
    adjustable : int or None
        m locked pairs: enumerate adjustable chains (n = n' + m, W = W' + m, m pairs locked).

    Examples
    --------
    >>> run_linkage_atlas(AtlasRequest(4, 1, adjustable=2)).to_dict()["count"]
    3
    """

    links: int
    dof: int = 1
    adjustable: int | None = None


@dataclass
class LinkageAtlasReport(LinkageReport):
    """The atlas (``atlas``: the chains, their layouts are drawn by the report layer)."""

    atlas: AtlasReport | None = None


def atlas_lines(payload: dict, seconds: float) -> list[str]:
    """The text of an atlas report."""
    lines = []
    if payload["kind"] == "adjustable":
        lines.append(f"camcad linkage atlas: adjustable chains n'={payload['links']}, W'={payload['dof']}, "
                     f"m={payload['adjustable']} (from {payload['base_chains']} ordinary chains with "
                     f"n={payload['base_links']}, W={payload['base_dof']}; {payload['colourings']} colourings)")
    else:
        lines.append(f"camcad linkage atlas: ordinary chains n={payload['links']}, W={payload['dof']}, "
                     f"p={payload['pairs']} pairs")
    lines.append(f"  count          {payload['count']}  (enumerated in {seconds:.2f} s)")
    if "published_count" in payload:
        same = "matches" if payload["published_count"] == payload["count"] else "DIFFERS from"
        lines.append(f"  published      {payload['published_count']} ({same} the count)")
    if "seed_count" in payload:
        same = "reproduced" if payload["seed_count"] == payload["count"] else "NOT reproduced"
        lines.append(f"  Sunkuev 1984, Table 1   {payload['seed_count']} ({same})")
    if payload.get("counts"):
        c = payload["counts"]
        lines.append(f"  weaker rules   no condition {c['unconditional']}, contracted chain simple "
                     f"{c['contracted_simple']}, rule {c['rule']}")
    if payload.get("by_assortment"):
        lines.append("  by assortment  " + ", ".join(f"{k}: {v}" for k, v in payload["by_assortment"].items()))
    if payload.get("discrepancy"):
        lines.append(f"  discrepancy    {payload['discrepancy']}")
    if "adjustable_jointed_to_frame" in payload:
        lines.append(f"  schemes        {payload['adjustable_jointed_to_frame']} of {payload['count']} have the "
                     "adjustable link jointed to the frame")
    if payload.get("guide"):
        lines.append(f"  choosing       {payload['guide']}")
    lines.append(f"  rule           {payload['rule']}")
    return lines


def run_linkage_atlas(request: AtlasRequest) -> LinkageAtlasReport:
    """Enumerate planar chains with revolute pairs (or adjustable chains) up to isomorphism.

    Parameters
    ----------
    request : AtlasRequest
        Links n (frame counted), mobility W, and m locked pairs for adjustable chains.

    Returns
    -------
    LinkageAtlasReport
        ``to_dict()``: ``count``, ``chains``, ``rule``, ``seed_count`` (Table 1), ``published_count``,
        ``discrepancy``; each chain with its kinematic scheme's joints (``scheme``) and a short guide.

    References
    ----------
    Sunkuev 1984, ch. 1 and Table 1; L.-W. Tsai, Mechanism Design: Enumeration of Kinematic Structures
    According to Function (CRC 2001) for the published counts of ordinary chains.

    Examples
    --------
    >>> r = run_linkage_atlas(AtlasRequest(6, 1, adjustable=2))
    >>> r.to_dict()["count"], r.to_dict()["seed_count"], r.exit_code
    (38, 38, 0)
    """
    result = atlas(request.links, request.dof, request.adjustable)
    annotate_schemes(result)
    name = f"atlas-n{request.links}-w{request.dof}" + (f"-m{request.adjustable}" if request.adjustable else "")
    return LinkageAtlasReport("atlas", result.payload, True, atlas_lines(result.payload, result.seconds), name,
                              atlas=result)


# --------------------------------------------------------------------------------------------
# fgen
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FgenRequest:
    """What ``camcad linkage fgen`` synthesises: a four-bar function generator for y = f(x).

    Parameters
    ----------
    function : str or None
        y = f(x) as an expression of x (``"log10(x)"``); or give ``table``.
    table : Path or None
        A two-column table x, y (.csv/.txt).
    x : str or sequence of float
        The interval X0, X1 of x (``"1:2"`` or ``(1, 2)``), in the function's own unit.
    input_range, output_range : float
        The input and output links' turns over the interval, deg (signed).
    method : str
        q (Sunkuev 1984's Q method), precision, lsq, minimax (least maximum error under the limits), remez (equal
        ripple without limits: a reference), or all.
    nodes : int or None
        q: S nodes (odd, default 5); lsq: N points (default 41).
    spacing : str
        chebyshev or uniform nodes.
    mu_min : float
        Smallest transmission angle, deg.
    ratio_max : float
        Largest link-length ratio (dimensionless).
    frame : float
        Frame length OC of the result, mm.
    phi0, psi0 : float or None
        precision: the input and output offsets, deg (default scanned).
    pick : str
        q, the last step: ``centre`` of the Q rectangle or ``search`` it.
    seed : int
        q: the scan grid's random shift.
    max_error : float or None
        The accuracy asked for, deg; default 1 % of the output range.
    chain : str
        ``fourbar`` (default) or ``sixbar``: two four-bars in series by the six-bar Q method
        (``camcad.linkage.sixbar``; method q only, S >= 9 nodes, default 9).

    Examples
    --------
    >>> r = run_linkage_fgen(FgenRequest(function="log10(x)", x="1:2", input_range=60, output_range=90,
    ...                                  method="precision", phi0=45, psi0=135))
    >>> r.to_dict()["method"], len(r.to_dict()["nodes_deg"])
    ('precision', 3)
    """

    function: str | None = None
    table: Path | None = None
    x: Any = None
    input_range: float | None = None
    output_range: float | None = None
    method: str = "q"
    nodes: int | None = None
    spacing: str = "chebyshev"
    mu_min: float = 30.0
    ratio_max: float = 10.0
    frame: float = 100.0
    phi0: float | None = None
    psi0: float | None = None
    pick: str = "centre"
    seed: int = 0
    max_error: float | None = None
    chain: str = "fourbar"


@dataclass
class SixbarReport(LinkageReport):
    """A six-bar function generator (``fgen --chain sixbar``)."""

    result: SixbarResult | None = None


def _sixbar_lines(p: dict) -> list[str]:
    l1, l2 = p["links"], p["links_2"]
    q = p["q"]
    lines = [f"camcad linkage fgen: {p['function']} on [{p['x'][0]:g}, {p['x'][1]:g}], input "
             f"{p['input_range_deg']:g} deg, output {p['output_range_deg']:g} deg, six-bar (two four-bars in "
             "series), method q",
             f"  max error      {p['max_error_deg']:.5g} deg, RMS {p['rms_error_deg']:.5g} deg",
             f"  mu min         loop 1 {p['mu_loop_deg'][0]:.2f} deg, loop 2 {p['mu_loop_deg'][1]:.2f} deg",
             f"  loop 1 (mm)    OA {l1['a']:.3f}, AB {l1['b']:.3f}, CB {l1['c']:.3f}, OC {l1['d']:.3f}, branch "
             f"{p['branch']:+d}, phi0 {p['offsets_deg']['phi0']:.4f} deg",
             f"  loop 2 (mm)    CD {l2['e']:.3f}, DE {l2['f']:.3f}, FE {l2['g']:.3f}, CF {l2['h']:.3f}, branch "
             f"{p['branch_2']:+d}, lever angle BCD {p['coupling_2_deg']:.1f} deg, psi0 "
             f"{p['offsets_deg']['psi0']:.4f} deg",
             f"  pivot F (mm)   {p['pivots']['F'][0]:.3f}, {p['pivots']['F'][1]:.3f}; link ratio {p['link_ratio']:.4g}",
             f"  Q              {q['value']:.4e} {q['unit']}; subsets {q['subsets']}; pivot: centre",
             f"  positions      q {p['position_evaluations']} (+ {p['verification_positions']} to check the result)"]
    for name, c in p["checks"].items():
        lines.append(f"  check {name:<15} value {c['value']:.5g}, limit {c['limit']:.5g}, margin {c['margin']:+.4g}: "
                     + ("ok" if c["passed"] else "FAILED") + (f" ({c['note']})" if c.get("note") else ""))
    lines += [f"  note           {note}" for note in p.get("notes", [])]
    return lines


def _run_sixbar(request: FgenRequest, target: Target, inputs: tuple[Path, ...]) -> SixbarReport:
    if request.method != "q":
        raise CamcadError(f"the six-bar is synthesised by the Q method only, not {request.method!r}", "--method",
                          "drop --method (or give --method q) with --chain sixbar")
    for given, option in ((request.phi0 is not None or request.psi0 is not None, "--phi0/--psi0"),
                          (request.pick != "centre", "--pick")):
        if given:
            raise CamcadError("is not an option of the six-bar Q method", option, "drop it with --chain sixbar")
    options = SixbarOptions(nodes=9 if request.nodes is None else request.nodes, spacing=request.spacing,
                            limits=Limits(request.mu_min, request.ratio_max), frame_mm=request.frame,
                            max_error_deg=request.max_error, seed=request.seed)
    result = synthesize_sixbar(target, options)
    payload = sixbar_report(result)
    return SixbarReport("fgen", payload, bool(payload["passed"]), _sixbar_lines(payload), "fgen-sixbar", inputs,
                        result)


@dataclass
class FgenReport(LinkageReport):
    """One synthesis, or every method side by side (``method == "all"``)."""

    method: str = "q"
    target: Target | None = None
    results: list[FgenResult] = field(default_factory=list)
    payloads: list[dict] = field(default_factory=list)

    @property
    def compare_text(self) -> str:
        """The side-by-side table of the methods."""
        return fgen_table(self.payloads)


def fgen_table(reports: list[dict]) -> str:
    """Methods side by side: errors, transmission angle, positions, links, checks."""
    head = (f"{'method':<10} {'max error':>11} {'RMS error':>11} {'mu min':>8} {'positions':>10}  "
            f"{'a (OA)':>9} {'b (AB)':>9} {'c (CB)':>9} {'d (OC)':>9}  checks")
    rows = [head, "-" * len(head)]
    for r in reports:
        links = r["links"]
        failed = [k for k, c in r["checks"].items() if not c["passed"]]
        rows.append(f"{r['method']:<10} {r['max_error_deg']:>9.4g}° {r['rms_error_deg']:>9.4g}° "
                    f"{r['mu_min_deg']:>7.2f}° {r['position_evaluations']:>10d}  "
                    f"{links['a']:>9.3f} {links['b']:>9.3f} {links['c']:>9.3f} {links['d']:>9.3f}  "
                    + ("ok" if not failed else "FAILED: " + ", ".join(failed))
                    + ("" if r.get("constrained", True) else " (no limits: reference)"))
    return "\n".join(rows)


def _fgen_lines(payload: dict) -> list[str]:
    lines = [f"camcad linkage fgen: {payload['function']} on [{payload['x'][0]:g}, {payload['x'][1]:g}], input "
             f"{payload['input_range_deg']:g} deg, output {payload['output_range_deg']:g} deg, method "
             f"{payload['method']}", fgen_table([payload]),
             (f"  offsets        phi0 {payload['offsets_deg']['phi0']:.4f} deg, psi0 "
              f"{payload['offsets_deg']['psi0']:.4f} deg, branch {payload['branch']:+d}, "
              f"{payload['grashof']['class']}")]
    if payload["nodes_deg"]:
        lines.append("  nodes (deg)    " + ", ".join(f"{v:.4f}" for v in payload["nodes_deg"][:12])
                     + (" ..." if len(payload["nodes_deg"]) > 12 else ""))
    lines.append("  positions      " + ", ".join(f"{k} {v}" for k, v in payload["position_breakdown"].items())
                 + f" (+ {payload['verification_positions']} to check the result)")
    if "q" in payload:
        q = payload["q"]
        lines.append(f"  Q              {q['value']:.4e} {q['unit']}; subsets {q['subsets']}; pivot: {q['pick']}")
    if "minimax" in payload:
        m = payload["minimax"]
        lines.append(f"  minimax        level {m['level_deg']:.5g} deg under the limits, {m['points']} points, "
                     f"{m['rounds']} rounds, from {m['winning_start']} ({m['message']})")
    if "remez" in payload:
        m = payload["remez"]
        lines.append(f"  equal ripple   level {m['level_deg']:.5g} deg at {len(m['references_deg'])} points, spread "
                     f"{100 * m['ripple_spread']:.3g} % ({m['message']}); no limits")
    for name, c in payload["checks"].items():
        lines.append(f"  check {name:<15} value {c['value']:.5g}, limit {c['limit']:.5g}, margin {c['margin']:+.4g}: "
                     + ("ok" if c["passed"] else "FAILED") + (f" ({c['note']})" if c.get("note") else ""))
    lines += [f"  note           {note}" for note in payload.get("notes", [])]
    return lines


def fgen_target(request: FgenRequest) -> Target:
    """The request's target ψ(φ) (``camcad.linkage.target``)."""
    if (request.function is None) == (request.table is None):
        raise CamcadError("give the function either as --function or as --table", "command line",
                          'e.g. --function "log10(x)" --x 1:2')
    for option, value in (("--input-range", request.input_range), ("--output-range", request.output_range)):
        if value is None:
            raise CamcadError("missing", option, f"give {option} DEG (the link's turn over the interval)")
    assert request.input_range is not None and request.output_range is not None  # refused above
    interval = numbers(request.x, "--x", 2)
    if request.function is not None:
        if interval is None:
            raise CamcadError("missing", "--x", "give the interval of x, e.g. --x 1:2")
        expression = parse_expression(request.function)
        return make_target(expression, interval[0], interval[1], request.input_range, request.output_range,
                           request.function, expression.derivative)
    table = Path(request.table)  # type: ignore[arg-type]  # checked above: exactly one is given
    if table.exists() and table.is_dir():
        raise CamcadError("is a folder", str(table), "give a .csv/.txt table of x, y")
    x0, x1 = interval if interval is not None else (None, None)
    return target_from_table(table, x0, x1, request.input_range, request.output_range)


def run_linkage_fgen(request: FgenRequest) -> FgenReport | SixbarReport:
    """Synthesise a four-bar function generator y = f(x) (``camcad linkage fgen``).

    Parameters
    ----------
    request : FgenRequest
        The function and its interval, the links' turns (deg), the method, the limits (deg, ratio) and the
        accuracy asked for (deg).

    Returns
    -------
    FgenReport or SixbarReport
        ``to_dict()``: ``method``, ``links`` (mm), ``max_error_deg``, ``rms_error_deg``, ``mu_min_deg``,
        ``position_evaluations``, ``nodes_deg``, ``checks``; with ``method="all"`` the methods side by side
        (``table``, ``results``; the comparison exits 0). Every optimiser keeps the limits as constraints;
        ``remez`` is the reference without limits. With ``chain="sixbar"`` a ``SixbarReport`` whose JSON adds
        ``chain``, ``links_2`` (e, f, g, h mm), ``mu_loop_deg``, ``pivots`` (``camcad.linkage.sixbar.report``).

    References
    ----------
    Sunkuev 1984, ch. 2 (the Q method); F. Freudenstein, Trans. ASME 77 (1955) 853–861 (precision points).

    Examples
    --------
    >>> r = run_linkage_fgen(FgenRequest(function="log10(x)", x="1:2", input_range=60, output_range=90,
    ...                                  method="precision", phi0=45, psi0=135))
    >>> round(r.to_dict()["links"]["d"], 6), r.to_dict()["position_evaluations"]
    (100.0, 3)
    """
    if request.method != "all" and request.method not in METHODS:
        raise CamcadError(f"unknown method {request.method!r}", "--method", f"use one of {', '.join(METHODS)} or all")
    if request.chain not in ("fourbar", "sixbar"):
        raise CamcadError(f"unknown chain {request.chain!r}", "--chain", "use fourbar or sixbar")
    target = fgen_target(request)
    limits = Limits(request.mu_min, request.ratio_max)
    inputs = () if request.table is None else (Path(request.table),)
    if request.chain == "sixbar":
        return _run_sixbar(request, target, inputs)
    methods = list(METHODS) if request.method == "all" else [request.method]
    results: list[FgenResult] = []
    for name in methods:
        options = FgenOptions(method=name, nodes=request.nodes if request.method != "all" or name == "q" else None,
                              spacing=request.spacing, limits=limits, frame_mm=request.frame,
                              phi0_deg=request.phi0 if name == "precision" else None,
                              psi0_deg=request.psi0 if name == "precision" else None, seed=request.seed,
                              pick=request.pick, max_error_deg=request.max_error)
        starts = [r for r in results if r.method in CONSTRAINED] if name == "minimax" and results else None
        results.append(synthesize(target, options, starts))
    payloads = [report(r) for r in results]
    if request.method != "all":
        payload = payloads[0]
        return FgenReport("fgen", payload, bool(payload["passed"]), _fgen_lines(payload), f"fgen-{request.method}",
                          inputs, request.method, target, results, payloads)
    keys = ("method", "max_error_deg", "rms_error_deg", "mu_min_deg", "position_evaluations", "links", "passed",
            "admissible", "constrained")
    summary = {"method": "all", "function": target.label, "x": [target.x0, target.x1],
               "input_range_deg": target.input_range_deg, "output_range_deg": target.output_range_deg,
               "limits": {"mu_min_deg": request.mu_min, "ratio_max": request.ratio_max},
               "table": [{k: p[k] for k in keys} for p in payloads], "results": payloads}
    admissible = [p for p in payloads if p["constrained"] and p["admissible"]]
    if admissible:
        best = min(admissible, key=lambda p: p["max_error_deg"])
        summary["best_admissible"] = {"method": best["method"], "max_error_deg": best["max_error_deg"]}
    text = [f"camcad linkage fgen: {target.label} on [{target.x0:g}, {target.x1:g}], input "
            f"{target.input_range_deg:g} deg, output {target.output_range_deg:g} deg, limits mu >= "
            f"{request.mu_min:g} deg, ratio <= {request.ratio_max:g}", fgen_table(payloads)]
    if admissible:
        text.append(f"  best admissible {best['method']}: {best['max_error_deg']:.5g} deg")
    text += [f"  note ({p['method']}): {note}" for p in payloads for note in p.get("notes", [])]
    return FgenReport("compare", summary, True, text, "fgen-all", inputs, "all", target, results, payloads)


# --------------------------------------------------------------------------------------------
# family
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FamilyRequest:
    """What ``camcad linkage family`` synthesises: one adjustable four-bar for a family of position functions.

    Parameters
    ----------
    members : tuple of str
        Each member ψ⁽ʲ⁾(x) as an expression of the input angle x (deg) giving deg.
    table : Path or None
        Instead of ``members``: x (deg), then one column per member (deg).
    phi : str or sequence of float
        The input interval A, B, deg (``"0:60"``).
    nodes : int
        S nodes per member (odd).
    crank : float
        Crank length OA, mm.
    phi0 : float
        The crank's angle at x = 0, deg.
    spacing : str
        chebyshev or uniform nodes.
    ratio_max : float
        Largest link-length ratio (dimensionless).
    mu_min : float
        Transmission-angle limit, deg (a constraint of the search).

    Examples
    --------
    >>> r = run_linkage_family(FamilyRequest(members=("0.5*x", "0.6*x", "0.7*x"), phi="0:40", crank=40, phi0=60))
    >>> r.to_dict()["members"]
    3
    """

    members: tuple[str, ...] = ()
    table: Path | None = None
    phi: Any = None
    nodes: int = 5
    crank: float = 40.0
    phi0: float = 0.0
    spacing: str = "chebyshev"
    ratio_max: float = 10.0
    mu_min: float = 30.0


@dataclass
class FamilyReport(LinkageReport):
    """The family's adjustable four-bar (``result``) and the members it was made for."""

    result: FamilyResult | None = None
    members: list[Member] = field(default_factory=list)
    phi_end: float = 0.0


def in_radians(expr, argument_in_deg: bool = False):
    """A callable rad → rad of an expression giving deg (of x in deg when ``argument_in_deg``, else of x)."""
    if argument_in_deg:
        return lambda u: math.radians(float(expr(math.degrees(u))))
    return lambda u: math.radians(float(expr(u)))


def table_members(path: Path, a: float, b: float) -> list[Member]:
    """Members from a table: x (deg) then one column per member (deg), a not-a-knot cubic spline each."""
    from scipy.interpolate import CubicSpline

    text, _ = decode_text(read_input(path, "a table of x and member columns (.csv/.txt)"))
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        cells = [c for c in content.replace(";", ",").replace("\t", ",").split(",")]
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if rows:
                raise CamcadError(f"line {number} is not numbers", str(path), "fix or delete that line") from None
    if len(rows) < 4 or len({len(r) for r in rows}) != 1 or len(rows[0]) < 4:
        raise CamcadError("the table needs at least 4 rows of x and 3 or more member columns", str(path),
                          "write x, psi1, psi2, psi3 per line (deg)")
    data = np.array(rows, dtype=float)
    data = data[np.argsort(data[:, 0])]
    if np.any(np.diff(data[:, 0]) <= 0):
        raise CamcadError("x repeats in the table", str(path), "give each x once")
    if a < data[0, 0] - 1e-12 or b > data[-1, 0] + 1e-12:
        raise CamcadError(f"--phi {a:g}:{b:g} is outside the table's x range", str(path), "narrow --phi")
    return [Member(CubicSpline(np.radians(data[:, 0]), np.radians(data[:, k])), math.radians(a), math.radians(b),
                   f"column {k}") for k in range(1, data.shape[1])]


def run_linkage_family(request: FamilyRequest) -> FamilyReport:
    """One adjustable four-bar for a family of position functions (``camcad linkage family``).

    Stage 1 the Q method over every member, stage 2 the circle through the members' pivots.

    Parameters
    ----------
    request : FamilyRequest
        Members (deg of deg) or their table, the input interval (deg), nodes, crank (mm), the crank's angle at
        x = 0 (deg), the limits (deg, ratio).

    Returns
    -------
    FamilyReport
        ``to_dict()``: links (mm), the arc's centre and radius (mm), the settings (deg), per member its error
        and worst transmission angle (deg).

    References
    ----------
    Sunkuev 1984, ch. 4 (the two-stage synthesis; the circle through C⁽¹⁾, C⁽²⁾, C⁽³⁾).

    Examples
    --------
    >>> r = run_linkage_family(FamilyRequest(members=("0.5*x", "0.6*x", "0.7*x"), phi="0:40", crank=40, phi0=60))
    >>> r.to_dict()["members"], len(r.to_dict()["settings_deg"])
    (3, 3)
    """
    if (not request.members) == (request.table is None):
        raise CamcadError("give the members either as --member (repeated) or as --table", "command line",
                          'e.g. --member "0.5*x" --member "0.6*x" --member "0.7*x" --phi 0:60')
    interval = numbers(request.phi, "--phi", 2, "0:60")
    if interval is None:
        raise CamcadError("missing", "--phi", "give the input interval, e.g. --phi 0:60 (deg)")
    a, b = interval
    if b <= a:
        raise CamcadError(f"--phi {a:g}:{b:g}: the interval must grow", "--phi", "write --phi A:B with B > A")
    if request.spacing not in ("chebyshev", "uniform"):
        raise CamcadError(f"unknown spacing {request.spacing!r}", "--spacing", "use chebyshev or uniform")
    if not request.crank > 0 or not request.ratio_max > 1:
        raise CamcadError("--crank must be > 0 and --ratio-max > 1", "--crank", "give positive values")
    members = []
    for k, text in enumerate(request.members, start=1):
        try:
            expr = parse_expression(text)
        except CamcadError as err:
            raise CamcadError(err.what, f"--member {k}", err.fix) from None
        members.append(Member(in_radians(expr, True), math.radians(a), math.radians(b), text))
    if request.table is not None:
        members = table_members(Path(request.table), a, b)
    result = synthesize_family(members, request.nodes, request.crank, math.radians(request.phi0), request.spacing,
                               ratio_max=request.ratio_max, mu_min=math.radians(request.mu_min))
    rows = [{"member": m.label or str(k + 1), "setting_deg": math.degrees(x), "pivot_x_mm": p.real,
             "pivot_y_mm": p.imag, "q_member": q, "output_link_mm": c, "max_error_deg": math.degrees(e),
             "mu_min_deg": math.degrees(mu), "branch_ok": ok}
            for k, (m, x, p, q, c, e, mu, ok) in enumerate(zip(members, result.settings, result.pivots,
                                                               result.q_members, result.c_members, result.max_error,
                                                               result.mu_min, result.branch_ok))]
    passed = all(r["branch_ok"] and r["mu_min_deg"] >= request.mu_min for r in rows)
    payload = {"command": "linkage family", "members": len(members), "nodes": request.nodes,
               "crank_mm": result.crank, "coupler_mm": result.coupler, "output_link_mm": result.output_link,
               "phi0_deg": request.phi0, "q": result.q,
               "q_unit": "crank lengths (sum of the members' Q plus the output-link spread)",
               "arc_centre_mm": [result.centre.real, result.centre.imag], "arc_radius_mm": result.radius,
               "circle_residual_mm": result.circle_residual,
               "settings_deg": [math.degrees(x) for x in result.settings], "rows": rows,
               "limits": {"mu_min_deg": request.mu_min, "ratio_max": request.ratio_max},
               "position_evaluations": result.evaluations, "passed": passed}
    summary = [f"camcad linkage family: {len(members)} members on [{a:g}, {b:g}] deg, {request.nodes} nodes each",
               (f"  stage 1        Q = {result.q:.4g} crank lengths; OA {result.crank:.6g}, AB {result.coupler:.6g}, "
                f"CB {result.output_link:.6g} mm"),
               (f"  stage 2        arc centre F ({result.centre.real:.6f}, {result.centre.imag:.6f}) mm, radius "
                f"{result.radius:.6f} mm (residual {result.circle_residual:.3g} mm)")]
    summary += [f"  member {r['member']:<14} setting {r['setting_deg']:10.5f} deg, max error {r['max_error_deg']:.3g} "
                f"deg, mu min {r['mu_min_deg']:.2f} deg" + ("" if r["branch_ok"] else ", BRANCH BROKEN") for r in rows]
    inputs = () if request.table is None else (Path(request.table),)
    return FamilyReport("family", payload, passed, summary, "family", inputs, result, members, math.radians(b))


# --------------------------------------------------------------------------------------------
# path
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PathRequest:
    """What ``camcad linkage path`` synthesises: a guiding four-bar for a curve, a timed curve or a distance.

    Parameters
    ----------
    points : Path, list of Path, or None
        A curve: a table with the header ``x_mm,y_mm`` (the points in order along it); three or more tables: a
        family, one adjustable mechanism for all (Sunkuev 1984, ch. 5).
    timed : Path, list of Path, or None
        A curve with its timing: ``phi_deg,x_mm,y_mm`` (φ the input's turn from the first row); or a family.
    distance : Path, list of Path, or None
        A distance to the fixed point: ``phi_deg,L_mm``; or a family.
    fixed_point : str or sequence of float
        The fixed point X, Y of a distance task, mm.
    rows : sequence or None
        Instead of a table: the rows (mm, deg as the headers say), with ``task``.
    task : str or None
        points, timed or distance (with ``rows``).
    method : str
        q (Sunkuev 1984's Q method), deviation, or all (both; the best is reported).
    nodes : int
        The Q method's subsets: 2 or 3 nodes each.
    mu_min : float
        Smallest transmission angle over the input's range, deg.
    ratio_max : float
        Largest link-length ratio (dimensionless).
    max_deviation : float or None
        The accuracy asked for, mm; default 0.1 % of the target's size.
    seed : int
        Random starts' seed.
    starts : int
        A family's random starts of stage 1 (beside the first member's own synthesis).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.path import GuidingFourBar
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> pts = m.positions(0.3 + np.radians([0, 30, 60, 90, 120, 150]))[2]
    >>> request = PathRequest(rows=[(30 * k, z.real, z.imag) for k, z in enumerate(pts)], task="timed")
    >>> request.task, len(request.rows)
    ('timed', 6)
    """

    points: Any = None
    timed: Any = None
    distance: Any = None
    fixed_point: Any = None
    rows: Any = None
    task: str | None = None
    method: str = "all"
    nodes: int = 3
    mu_min: float = 30.0
    ratio_max: float = 10.0
    max_deviation: float | None = None
    seed: int = 0
    starts: int = 20


@dataclass
class PathReport(LinkageReport):
    """The guiding four-bar of each method run, the target, and which result the top-level figures are; for a
    family the adjustable mechanism (``family``)."""

    target: PathTarget | None = None
    results: list[PathResult] = field(default_factory=list)
    best: PathResult | None = None
    family: PathFamilyResult | None = None


def path_targets(request: PathRequest) -> list[PathTarget]:
    """The request's targets (a table, several tables of one task for a family, or rows)."""
    fixed = numbers(request.fixed_point, "--fixed-point", 2, "120,40")
    if request.rows is not None:
        if any(v for v in (request.points, request.timed, request.distance)) or request.task not in TASKS:
            raise CamcadError("give the rows with their task, or one table", "linkage path",
                              "rows=..., task='points' (or timed, distance)")
        return [make_path_target(request.task, request.rows, fixed)]

    def tables(value) -> list[Path]:
        if value is None:
            return []
        return [Path(v) for v in value] if isinstance(value, (list, tuple)) else [Path(value)]

    given = [(task, tables(v)) for task, v in (("points", request.points), ("timed", request.timed),
                                               ("distance", request.distance)) if tables(v)]
    if len(given) != 1:
        raise CamcadError("give exactly one of --points, --timed, --distance (repeated for a family)", "command line",
                          "e.g. --points curve.csv (a table x_mm,y_mm)")
    task, paths = given[0]
    if task == "distance" and fixed is None:
        raise CamcadError("a distance task needs the fixed point", "--fixed-point", "give --fixed-point X,Y (mm)")
    if task != "distance" and fixed is not None:
        raise CamcadError("--fixed-point belongs to a distance task", "--fixed-point", "drop it, or use --distance")
    if len(paths) == 2:
        raise CamcadError("two tables: a family needs three or more members", OPTIONS[task],
                          "give one table, or three or more for an adjustable mechanism")
    return [read_target(p, task, fixed) for p in paths]


def _path_row(result: PathResult, target: PathTarget, limits: Limits, tolerance: float) -> dict:
    mech, chk = result.mechanism, result.check
    links = mech.links()
    ratio = max(links) / min(links)
    checks = {
        "deviation": {"value": chk.max_deviation, "limit": tolerance, "margin": tolerance - chk.max_deviation,
                      "passed": bool(chk.max_deviation <= tolerance),
                      "why": "largest deviation of a row (mm): " + {
                          "points": "distance from the point to the coupler curve",
                          "timed": "distance from the point to the coupler point at its input angle",
                          "distance": "| |MX| - L | at its input angle"}[target.task]},
        "transmission_angle": {"value": chk.mu_min_deg, "limit": limits.mu_min_deg,
                               "margin": chk.mu_min_deg - limits.mu_min_deg,
                               "passed": bool(chk.mu_min_deg >= limits.mu_min_deg),
                               "why": "smallest min(mu, 180 - mu) over the crank's range through the rows (deg), "
                                      "closed form"},
        "link_ratio": {"value": ratio, "limit": limits.ratio_max, "margin": limits.ratio_max - ratio,
                       "passed": bool(ratio <= limits.ratio_max), "why": "longest / shortest link"},
        "branch": {"value": chk.branch_ok, "passed": chk.branch_ok,
                   "why": "the loop closes over the crank's range without a dead point"},
    }
    row = {"method": result.method, "max_deviation_mm": chk.max_deviation, "rms_deviation_mm": chk.rms_deviation,
           "mu_min_deg": chk.mu_min_deg, "position_evaluations": result.work.positions,
           "objective_evaluations": result.work.evaluations, "starts": result.starts,
           "links": dict(zip(("a", "b", "c", "d"), links)),
           "link_names": {"a": "crank OA", "b": "coupler AB", "c": "rocker CB", "d": "frame OC"},
           "input_pivot_mm": [mech.o.real, mech.o.imag], "output_pivot_mm": [mech.pivot.real, mech.pivot.imag],
           "coupler_point_mm": {"u": mech.point.real, "v": mech.point.imag}, "branch": mech.branch,
           "input_range_deg": [math.degrees(chk.lo), math.degrees(chk.hi)], "in_order": chk.in_order,
           "input_angles_deg": [math.degrees(t) for t in chk.theta],
           "deviations_mm": [float(d) for d in chk.deviations],
           "checks": checks, "passed": all(c["passed"] for c in checks.values()), "notes": list(result.notes)}
    if result.q is not None:
        pivots: list[complex] | np.ndarray = ([] if result.q_pivots is None
                                              else np.atleast_1d(np.asarray(result.q_pivots)))
        row["q"] = {"value_mm": result.q, "pivots_mm": [[p.real, p.imag] for p in pivots]}
    return row


def run_linkage_path(request: PathRequest) -> PathReport:
    """A guiding four-bar for a curve, a timed curve or a distance (``camcad linkage path``).

    Parameters
    ----------
    request : PathRequest
        The target (a table or rows; mm, deg), the method, the Q method's nodes, the limits (deg, ratio) and the
        accuracy asked for (mm).

    Returns
    -------
    PathReport
        ``to_dict()``: ``max_deviation_mm``, ``mu_min_deg``, ``position_evaluations``, ``passed`` of the best
        admissible result (top level) and every method's under ``methods``; the mechanism's pivots, links and
        coupler point (mm).

    References
    ----------
    Sunkuev 1984, ch. 2 and 5 (the three task groups of guiding mechanisms; the Q objective from two- or
    three-node interpolation); F. Freudenstein and G. N. Sandor, Trans. ASME B 81 (1959) (dyads).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.path import GuidingFourBar
    >>> m = GuidingFourBar(0j, 100 + 0j, 40.0, 120.0, 90.0, 1, 60 + 20j, 0.3)
    >>> phi = np.arange(0, 160, 20)
    >>> pts = m.positions(0.3 + np.radians(phi))[2]
    >>> r = run_linkage_path(PathRequest(rows=[(p, z.real, z.imag) for p, z in zip(phi, pts)], task="timed",
    ...                                  method="deviation"))
    >>> r.exit_code, r.to_dict()["max_deviation_mm"] < 1e-6
    (0, True)
    """
    if request.method not in ("q", "deviation", "all"):
        raise CamcadError(f"unknown method {request.method!r}", "--method", "use q, deviation or all")
    if request.max_deviation is not None and not (request.max_deviation > 0 and math.isfinite(request.max_deviation)):
        raise CamcadError(f"--max-deviation {request.max_deviation:g} mm must be positive", "--max-deviation",
                          "give the accuracy asked for in mm")
    limits = Limits(request.mu_min, request.ratio_max)
    if not (0.0 <= request.mu_min < 90.0) or not request.ratio_max > 1.0:
        raise CamcadError("--mu-min must be in [0, 90) deg and --ratio-max above 1", "--mu-min",
                          "e.g. --mu-min 30 --ratio-max 10")
    targets = path_targets(request)
    inputs = tuple(p for v in (request.points, request.timed, request.distance) if v
                   for p in ([Path(x) for x in v] if isinstance(v, (list, tuple)) else [Path(v)]))
    if len(targets) > 1:
        return _path_family_report(targets, limits, request, inputs)
    target = targets[0]
    tolerance = request.max_deviation if request.max_deviation is not None else DEFAULT_TOLERANCE * target.size
    results: list[PathResult] = []
    if request.method in ("deviation", "all"):
        results.append(deviation_synthesis(target, limits, request.seed, tolerance))
    if request.method in ("q", "all"):
        starts = [r.mechanism for r in results]
        results.append(q_synthesis(target, limits, request.nodes, request.seed, starts=starts))
    rows = [_path_row(r, target, limits, tolerance) for r in results]
    ranked = sorted(range(len(rows)), key=lambda k: (not rows[k]["passed"], rows[k]["max_deviation_mm"]))
    top = rows[ranked[0]]
    payload = {"command": "linkage path", "task": target.task, "rows": target.count, "source": target.source,
               "size_mm": target.size, "tolerance_mm": tolerance,
               "limits": {"mu_min_deg": request.mu_min, "ratio_max": request.ratio_max},
               "method": request.method, "best_method": top["method"],
               **{k: top[k] for k in ("max_deviation_mm", "rms_deviation_mm", "mu_min_deg", "links", "input_pivot_mm",
                                      "output_pivot_mm", "coupler_point_mm", "branch", "input_range_deg", "checks",
                                      "passed")},
               "position_evaluations": sum(r["position_evaluations"] for r in rows),
               "methods": rows}
    if target.fixed is not None:
        payload["fixed_point_mm"] = [target.fixed.real, target.fixed.imag]
    lines = [f"camcad linkage path: {target.task} ({target.count} rows, size {target.size:.4g} mm), tolerance "
             f"{tolerance:.3g} mm, limits mu >= {request.mu_min:g} deg, ratio <= {request.ratio_max:g}",
             f"{'method':<10} {'max dev mm':>12} {'rms mm':>11} {'mu min':>8} {'positions':>11}  {'OA':>8} {'AB':>8} "
             f"{'CB':>8} {'OC':>8}  checks"]
    for r in rows:
        failed = [k for k, c in r["checks"].items() if not c["passed"]]
        lk = r["links"]
        lines.append(f"{r['method']:<10} {r['max_deviation_mm']:>12.4g} {r['rms_deviation_mm']:>11.4g} "
                     f"{r['mu_min_deg']:>7.2f}° {r['position_evaluations']:>11d}  {lk['a']:>8.3f} {lk['b']:>8.3f} "
                     f"{lk['c']:>8.3f} {lk['d']:>8.3f}  " + ("ok" if not failed else "FAILED: " + ", ".join(failed)))
        if "q" in r:
            lines.append(f"  Q = {r['q']['value_mm']:.4g} mm over {len(r['q']['pivots_mm'])} pivots")
        lines += [f"  note ({r['method']}): {n}" for n in r["notes"]]
    lines.append(f"  best           {top['method']}: O ({top['input_pivot_mm'][0]:.4f}, "
                 f"{top['input_pivot_mm'][1]:.4f}), "
                 f"C ({top['output_pivot_mm'][0]:.4f}, {top['output_pivot_mm'][1]:.4f}) mm, coupler point u "
                 f"{top['coupler_point_mm']['u']:.4f} v {top['coupler_point_mm']['v']:.4f} mm")
    best = results[ranked[0]]
    return PathReport("path", payload, bool(top["passed"]), lines, f"path-{target.task}", inputs, target, results,
                      best)


def _path_family_report(targets: list[PathTarget], limits: Limits, request: PathRequest, inputs: tuple) -> PathReport:
    """A family of guiding targets: one adjustable four-bar (``camcad.linkage.path.path_family``)."""
    if not 0 <= request.starts <= 1000:
        raise CamcadError(f"{request.starts} random starts is out of range", "--starts", "give 0 to 1000")
    fam = path_family(targets, limits, request.seed, random_starts=request.starts)
    rows = []
    for k, (t, mech, chk) in enumerate(zip(targets, fam.mechanisms, fam.checks)):
        tolerance = request.max_deviation if request.max_deviation is not None else DEFAULT_TOLERANCE * t.size
        result = PathResult("q", mech, chk, fam.work, fam.q_members[k])
        row = _path_row(result, t, limits, tolerance)
        row.update({"member": k + 1, "source": t.source, "setting_deg": math.degrees(fam.settings[k]),
                    "tolerance_mm": tolerance})
        rows.append(row)
    worst = max(rows, key=lambda r: r["max_deviation_mm"])
    passed = all(r["passed"] for r in rows)
    payload = {"command": "linkage path", "task": targets[0].task, "family": True, "members": len(targets),
               "moved_pivot": fam.moved, "arc_centre_mm": [fam.centre.real, fam.centre.imag],
               "arc_radius_mm": fam.radius, "circle_residual_mm": fam.circle_residual,
               "settings_deg": [math.degrees(x) for x in fam.settings], "q_mm": fam.q,
               "limits": {"mu_min_deg": request.mu_min, "ratio_max": request.ratio_max},
               "max_deviation_mm": worst["max_deviation_mm"], "mu_min_deg": min(r["mu_min_deg"] for r in rows),
               "position_evaluations": fam.work.positions, "passed": passed, "rows": rows}
    if targets[0].fixed is not None:
        payload["fixed_point_mm"] = [targets[0].fixed.real, targets[0].fixed.imag]
    pivot = "crank pivot O" if fam.moved == "O" else "rocker pivot C"
    lines = [f"camcad linkage path: a family of {len(targets)} {targets[0].task} targets, one adjustable four-bar "
             f"(the {pivot} on an arc)",
             f"  stage 1        sum of Q = {fam.q:.4g} mm",
             f"  stage 2        arc centre ({fam.centre.real:.6f}, {fam.centre.imag:.6f}) mm, radius "
             f"{fam.radius:.6f} mm (residual {fam.circle_residual:.3g} mm)"]
    lines += [f"  member {r['member']} {r['source']:<16} setting {r['setting_deg']:10.5f} deg, max deviation "
              f"{r['max_deviation_mm']:.4g} mm (tolerance {r['tolerance_mm']:.3g}), mu min {r['mu_min_deg']:.2f} deg"
              + ("" if r["passed"] else ", FAILED") for r in rows]
    mech = fam.mechanisms[0]
    links = mech.links()
    lines.append(f"  shared         OA {links[0]:.4f}, AB {links[1]:.4f}, CB {links[2]:.4f} mm; coupler point u "
                 f"{mech.point.real:.4f} v {mech.point.imag:.4f} mm")
    return PathReport("path", payload, passed, lines, f"path-{targets[0].task}-family", inputs, targets[0], [], None,
                      fam)


# --------------------------------------------------------------------------------------------
# variator
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class VariatorRequest:
    """What ``camcad linkage variator`` synthesises: an impulse variator's transforming six-bar (Sunkuev 1984, Fig. 7).

    Parameters
    ----------
    u_mean : str or sequence of float
        The regulated mean velocity analog U_cp of the output over the working interval, from A to B
        (dimensionless: rad of output per rad of crank).
    interval : float
        The crank's working interval φ_p, deg.
    settings : int
        The settings p (U_cp spread evenly from A to B).
    crank : float
        Crank length OA, mm.
    mu_min : float
        Transmission-angle limit, deg.
    ratio_max : float
        Largest link-length ratio (dimensionless).
    starts : int
        Random starts of the second stage.
    seed : int
        Their seed.
    max_delta : float or None
        The non-uniformity [δ] allowed (dimensionless); None: reported, not judged.

    Examples
    --------
    >>> VariatorRequest(u_mean="0.05:0.15", interval=90.0).settings
    3
    """

    u_mean: Any = None
    interval: float = 90.0
    settings: int = 3
    crank: float = 20.0
    mu_min: float = 30.0
    ratio_max: float = 10.0
    starts: int = 24
    seed: int = 0
    max_delta: float | None = None


@dataclass
class VariatorReport(LinkageReport):
    """The variator and each setting's figures."""

    result: VariatorResult | None = None


def run_linkage_variator(request: VariatorRequest) -> VariatorReport:
    """The transforming six-bar of an impulse variator (``camcad linkage variator``, Sunkuev 1984, ch. 4, Fig. 7).

    Parameters
    ----------
    request : VariatorRequest
        The regulated mean ratio range (dimensionless), the working interval (deg), the settings, the crank (mm)
        and the limits (deg, ratio).

    Returns
    -------
    VariatorReport
        ``to_dict()``: the links (mm), the pivots (mm), per setting the setting angle of C about O (deg), U_cp, δ
        (dimensionless) and the worst transmission angles (deg); ``delta_max`` = max δ.

    References
    ----------
    Sunkuev 1984, ch. 4 (the two-stage synthesis of the impulse variator's transforming six-bar).

    Examples
    --------
    >>> r = run_linkage_variator(VariatorRequest(u_mean="0.05:0.15", interval=180.0, starts=6))
    >>> [round(row["u_mean"], 6) for row in r.to_dict()["rows"]]
    [0.05, 0.1, 0.15]
    """
    span = numbers(request.u_mean, "--u-mean", 2, "0.05:0.15")
    if span is None:
        raise CamcadError("missing", "--u-mean", "give the mean ratios to regulate, e.g. --u-mean 0.05:0.15")
    result = synthesise_variator(span, request.interval, request.settings, request.crank, request.mu_min,
                                 request.ratio_max, request.starts, request.seed)
    v = result.variator
    rows = result.rows
    delta_max = result.delta_max
    checks = {"transmission_angle": {
        "value": min(min(r["mu_min_first_deg"], r["mu_min_second_deg"]) for r in rows), "limit": request.mu_min,
        "passed": all(min(r["mu_min_first_deg"], r["mu_min_second_deg"]) >= request.mu_min - 1e-6 for r in rows),
        "why": "worst min(mu, 180 - mu) of the first loop over the turn and the second over the working interval"}}
    checks["transmission_angle"]["margin"] = checks["transmission_angle"]["value"] - request.mu_min
    if request.max_delta is not None:
        checks["non_uniformity"] = {"value": delta_max, "limit": request.max_delta,
                                    "margin": request.max_delta - delta_max, "passed": delta_max <= request.max_delta,
                                    "why": "max over the settings of (U_max - U_min)/U_cp over the working interval"}
    passed = all(c["passed"] for c in checks.values())
    payload = {"command": "linkage variator", "links_mm": {"OA": v.a, "AB": v.b, "CB": v.c, "OC": v.radius,
                                                           "BD": v.e, "ED": v.f},
               "pivot_e_mm": [v.pivot_e.real, v.pivot_e.imag], "interval_deg": math.degrees(v.interval),
               "interval_start_deg": math.degrees(v.start), "branches": [v.branch1, v.branch2],
               "delta_w": result.delta_w, "delta_max": delta_max, "rows": rows, "checks": checks,
               "position_evaluations": result.evaluations, "passed": passed, "notes": result.notes}
    lines = [f"camcad linkage variator: U_cp {span[0]:g} .. {span[1]:g} over a working interval of "
             f"{request.interval:g} deg, {request.settings} settings",
             f"  links          OA {v.a:.4f}, AB {v.b:.4f}, CB {v.c:.4f}, |OC| {v.radius:.4f}, BD {v.e:.4f}, ED "
             f"{v.f:.4f} mm; E ({v.pivot_e.real:.4f}, {v.pivot_e.imag:.4f}) mm",
             f"  stage 1        delta_w = {result.delta_w:.4g} (the first four-bar alone)"]
    lines += [f"  setting {r['setting_deg']:9.4f} deg: U_cp {r['u_mean']:.5f}, delta {r['delta']:.4f}, mu min "
              f"{r['mu_min_first_deg']:.2f} / {r['mu_min_second_deg']:.2f} deg" for r in rows]
    lines.append(f"  max delta      {delta_max:.4f}")
    lines += [f"  check {k:<18} " + ("ok" if c["passed"] else "FAILED") for k, c in checks.items()]
    return VariatorReport("variator", payload, passed, lines, "variator", (), result)
