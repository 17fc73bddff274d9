"""Adjustable linkages: one element of the chain is moved and locked at settings (Sunkuev 1984, ch. 3 and 6).

The adjustable elements (``Adjustment``), in the frame of ``camcad.linkage.analysis`` with the follower
on its base circle (ψ = 0):

- ``pivot`` — a frame pivot (C, or F of a six-bar) carried by an adjustable link: on an arc of centre M
  and radius |M − C₀| locked at the angle x of M→C (rad), or on a slot through C₀ in the direction
  ``direction``, at the distance x (mm) from C₀;
- ``joint`` — a moving joint on its lever: A on the input lever (its arc or slot is fixed to the lever; x
  as above, measured in the lever's position at ψ = 0), B or E on an output lever;
- ``link_angle`` — the input link clamped to the follower's arm at the angle θ₀ + x.

Kinematic characteristics of the extreme positions (Sunkuev 1984's notation): the input's extreme positions
φ₁, φ₂ and the working member's ψ₁, ψ₂, the swing ψ₁₂ = ψ₂ − ψ₁, the setting x₁. Sunkuev 1984's Table 2
(rotating input, a crank) and Table 3 (non-rotating input) list the regulation tasks (ch. 3, the paragraph
"В табл. 2 приведен перечень задач"; the symbols: var — regulated within given limits, f — a functional
relation with another characteristic, const — constant while another is regulated). In the cam case the
linkage's input is the follower's rocker, whose extreme positions φ₁ = 0 and φ₂ = ψ_max are fixed by the
cam: Table 3 applies, "в непроворачивающихся регулируемых механизмах координаты φ1 и φ2 неизменны".
Table 3 as the OCR prints it has the columns "φ1, ψ2, α1, ψ12" — read here as ψ₁, ψ₂, x₁, ψ₁₂ (the text
around it names exactly these four; the OCR turned ψ into φ and x into α):

====  ======  ======  ======  ======
task  ψ₁      ψ₂      x₁      ψ₁₂
====  ======  ======  ======  ======
1     const   var
2     f       f
3     f               f
4     const   f       f
5     f       f       f
6                     f       f
====  ======  ======  ======  ======

camcad measures ψ₁ and ψ₂ as the working member's angle at the follower's two extreme positions, from
its position at ψ = 0 in the nominal geometry, positive in the working member's positive sense (deg).

Task 1 has an exact construction (Sunkuev 1984's method: the adjustable mechanism reduced to a fixed one
by the chains it forms in its extreme positions, ch. 3 "синтез регулируемого механизма сводится к синтезу
нерегулируемого вспомогательного"): put A on an arc fixed to the input lever whose centre is B's position
at the first extreme position and whose radius is the coupler b. At ψ = 0, whatever the setting, the
coupler's end B stays at that centre, so ψ₁ is constant; at ψ_max the chain M₂–A–B–C (M₂ the arc's
centre turned with the input lever) is an ordinary four-bar whose input is the setting and whose output is
ψ₂: the *auxiliary mechanism*. Tasks 2–6 are fitted (least squares over the arc's centre, its radius and
the settings) with that auxiliary mechanism computed at each setting.

Sources: B. S. Sunkuev, doctoral abstract (Moscow 1984), Sunkuev 1984, ch. 3 (Tables 2 and 3, the auxiliary
mechanism), ch. 6 (settings).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, cast

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, analyse
from camcad.linkage.fourbar import grashof

#: Table 3 of Sunkuev 1984 (non-rotating input), as camcad reads the OCR (module docstring)
TABLE3 = {1: {"psi1": "const", "psi2": "var"},
          2: {"psi1": "f", "psi2": "f"},
          3: {"psi1": "f", "x1": "f"},
          4: {"psi1": "const", "psi2": "f", "x1": "f"},
          5: {"psi1": "f", "psi2": "f", "x1": "f"},
          6: {"x1": "f", "psi12": "f"}}
#: Table 2 of Sunkuev 1984 (rotating input): columns φ1, ψ1, φ2, ψ2, x1, ψ12 (the OCR's α1 read as x1)
TABLE2 = {1: {"psi12": "var"}, 2: {"phi1": "const", "psi1": "const", "psi2": "var"},
          3: {"psi1": "f", "psi2": "f"}, 4: {"phi1": "const", "psi1": "const", "phi2": "var", "psi2": "const"},
          5: {"phi1": "const", "psi1": "f", "phi2": "const", "psi2": "f"},
          6: {"phi1": "const", "psi1": "const", "phi2": "const", "psi2": "var"},
          7: {"phi1": "var", "psi1": "const"}, 8: {"phi1": "const", "psi1": "var"}, 9: {"phi1": "f", "psi1": "f"},
          10: {"phi1": "f", "psi1": "f", "x1": "f"}, 11: {"phi1": "f", "psi1": "const", "x1": "f"},
          12: {"phi1": "const", "psi1": "f", "x1": "f"}, 13: {"psi1": "f", "psi2": "f", "x1": "f"},
          14: {"phi1": "const", "psi1": "const", "psi2": "f", "x1": "f"},
          15: {"phi1": "const", "psi1": "const", "phi2": "const", "psi2": "f", "x1": "f"},
          16: {"x1": "f", "psi12": "f"}, 17: {"psi1": "const", "psi2": "f", "x1": "f"}}


@dataclass(frozen=True)
class Adjustment:
    """One adjustable element (module docstring). ``centre`` complex mm (arc), ``direction`` rad (slot).

    Examples
    --------
    >>> Adjustment("pivot", "C", "arc", 10 + 0j).describe()
    'pivot C on an arc, centre (10, 0) mm'
    """

    element: str
    joint: str = ""
    path: str = "arc"
    centre: complex | None = None
    direction: float = 0.0

    def describe(self) -> str:
        if self.element == "link_angle":
            return "input link locked at angles to the follower's arm"
        centre = cast(complex, self.centre)  # an arc has its centre
        where = (f"an arc, centre ({centre.real:.6g}, {centre.imag:.6g}) mm" if self.path == "arc"
                 else f"a slot at {math.degrees(self.direction):.6g} deg")
        return f"{self.element} {self.joint} on {where}"

    @property
    def unit(self) -> str:
        """Unit of a setting: "rad" (arc lock angle, link angle) or "mm" (slot position)."""
        return "mm" if self.path == "slot" and self.element != "link_angle" else "rad"


@lru_cache(maxsize=256)
def _nominal_joints(linkage: Linkage) -> dict:
    """The joints at ψ = 0 (complex mm); cached: the scans and fits ask them of one nominal linkage."""
    return {k: complex(np.asarray(v)) for k, v in linkage.joints(0.0).items()}


@lru_cache(maxsize=256)
def _reference(linkage: Linkage) -> float:
    """The working member's absolute angle at ψ = 0 (rad), cached as ``_nominal_joints``."""
    return float(linkage.working_angle(np.array([0.0]))[0])


def _base_point(linkage: Linkage, joint: str) -> complex:
    return _nominal_joints(linkage)[joint]


def radius(linkage: Linkage, adj: Adjustment) -> float:
    """The arc's radius |M − P₀| (mm) for the adjusted joint's position P₀ at ψ = 0.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.0)
    >>> radius(lk, Adjustment("pivot", "C", "arc", 100 + 10j))
    10.0
    """
    return abs(_base_point(linkage, adj.joint) - cast(complex, adj.centre))


def base_setting(linkage: Linkage, adj: Adjustment) -> float:
    """The setting that gives ``linkage`` itself: the angle of M→P₀ (arc, rad), 0 (slot, link angle).

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.0)
    >>> round(math.degrees(base_setting(lk, Adjustment("pivot", "C", "arc", 100 + 10j))), 9)
    -90.0
    """
    if adj.element == "link_angle" or adj.path == "slot":
        return 0.0
    d = _base_point(linkage, adj.joint) - cast(complex, adj.centre)
    return math.atan2(d.imag, d.real)


def _place(linkage: Linkage, adj: Adjustment, x: float) -> complex:
    p0 = _base_point(linkage, adj.joint)
    if adj.path == "slot":
        return p0 + x * complex(math.cos(adj.direction), math.sin(adj.direction))
    centre = cast(complex, adj.centre)
    return centre + abs(p0 - centre) * complex(math.cos(x), math.sin(x))


def adjusted(linkage: Linkage, adj: Adjustment, x: float) -> Linkage:
    """The linkage with its adjustable element locked at setting ``x`` (rad, or mm for a slot).

    The working member keeps its positive sense; a joint moved on an output lever changes the angle
    between the lever and the line QB (``output_offset``, or the next loop's coupling). The assembly
    branch is the one that keeps the moved loop nearest its nominal configuration at ψ = 0.

    Examples
    --------
    The nominal setting gives the nominal linkage back:

    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.0)
    >>> adj = Adjustment("pivot", "C", "arc", 100 + 10j)
    >>> again = adjusted(lk, adj, base_setting(lk, adj))
    >>> round(float(again.position(0.3)[0] - lk.position(0.3)[0]), 12)
    0.0
    """
    if adj.element == "link_angle":
        return replace(linkage, theta0=linkage.theta0 + x)
    new = _place(linkage, adj, x)
    loops = list(linkage.loops)
    if adj.element == "pivot":
        point = (new.real, new.imag)
        if adj.joint == "C":
            loops[0] = replace(loops[0], q=point)
            if len(loops) > 1:
                loops[1] = replace(loops[1], p=point)
        elif adj.joint == "F":
            loops[1] = replace(loops[1], q=point)
        else:
            raise ValueError(f"no pivot {adj.joint}")
        return replace(linkage, loops=tuple(loops))
    j0 = _nominal_joints(linkage)
    if adj.joint == "A":
        origin = complex(*loops[0].p)
        theta0 = math.atan2(new.imag - origin.imag, new.real - origin.real)
        loops[0] = replace(loops[0], a=abs(new - origin)).with_branch_through(theta0, complex(np.asarray(j0["B"])))
        return replace(linkage, loops=tuple(loops), theta0=theta0)
    index = {"B": 0, "E": 1}[adj.joint]
    pivot = complex(*loops[index].q)
    old = complex(np.asarray(j0[adj.joint]))
    delta = math.atan2((new - pivot).imag, (new - pivot).real) - math.atan2((old - pivot).imag, (old - pivot).real)
    loop = replace(loops[index], c=abs(new - pivot))
    theta_in = float(linkage.angles(np.array([0.0]))[index][0][0])
    loops[index] = loop.with_branch_through(theta_in, new)
    if index == len(loops) - 1:
        return replace(linkage, loops=tuple(loops), output_offset=linkage.output_offset - delta)
    couplings = list(linkage.couplings)
    couplings[index] -= delta
    return replace(linkage, loops=tuple(loops), couplings=tuple(couplings))


# --------------------------------------------------------------------------------------------
# Characteristics of the extreme positions
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SettingResult:
    """One setting: its value x (rad or mm), ψ₁, ψ₂, ψ₁₂ (rad, module docstring), the worst transmission
    angle (rad), whether the loops close and keep their branch over the swing, and the analysis."""

    x: float
    psi1: float
    psi2: float
    swing: float
    mu_min: float
    branch_continuous: bool
    monotone: bool
    analysis: object

    def as_dict(self, unit: str) -> dict:
        return {("setting_deg" if unit == "rad" else "setting_mm"): math.degrees(self.x) if unit == "rad" else self.x,
                "psi1_deg": math.degrees(self.psi1), "psi2_deg": math.degrees(self.psi2),
                "swing_deg": math.degrees(self.swing), "mu_min_deg": math.degrees(self.mu_min),
                "branch_continuous": self.branch_continuous, "monotone": self.monotone}


def characteristics(linkage: Linkage, adj: Adjustment, x: float, psi_max: float, points: int = 181,
                    quick: bool = False) -> SettingResult:
    """ψ₁, ψ₂ and the swing of the working member at setting ``x`` over the follower's swing [0, ψ_max],
    measured from the nominal linkage's working angle at ψ = 0 in the working member's positive sense.
    ``quick``: no full analysis (``analysis`` None): the loops' closure on ``points`` samples, the dead points
    and the worst transmission angles in closed form over each loop's input interval — what scans and fits
    need.

    Examples
    --------
    Task 1's arc: ψ₁ does not move with the setting.

    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.5, input_sense=-1)
    >>> adj = task1_adjustment(lk, 0.5)
    >>> [abs(characteristics(lk, adj, base_setting(lk, adj) + dx, 0.5).psi1) < 1e-12 for dx in (-0.2, 0.1)]
    [True, True]
    """
    s = linkage.output_sense
    ref = _reference(linkage)
    lk = adjusted(linkage, adj, x)
    if quick:
        return _quick(lk, x, psi_max, s, ref, points)
    res = analyse(lk, psi_max, points)
    w = lk.working_angle(np.array([0.0, psi_max]))
    psi1, psi2 = s * math.remainder(float(w[0]) - ref, 2 * math.pi), s * math.remainder(float(w[1]) - ref, 2 * math.pi)
    mu = min(res.mu_min) if res.closes else float("nan")
    return SettingResult(x, psi1, psi2, psi2 - psi1, mu, res.branch_continuous, res.monotone, res)


def _quick(lk: Linkage, x: float, psi_max: float, s: int, ref: float, points: int) -> SettingResult:
    psi = np.linspace(0.0, psi_max, max(points, 3))
    w = lk.working_angle(psi)
    closes = bool(np.all(np.isfinite(w)))
    mu = math.inf
    dead = False
    if closes:
        for loop, (theta, _) in zip(lk.loops, lk.angles(psi, order=1)):
            lo, hi = float(np.min(theta)), float(np.max(theta))
            mu = min(mu, loop.worst_transmission(lo, hi))
            dead = dead or any(_strictly_inside(t, lo, hi) for t in loop.dead_points())
    else:
        mu = math.nan
    turn = np.remainder(w - w[0] + np.pi, 2 * np.pi) - np.pi if closes else w
    step = np.diff(turn)
    monotone = closes and bool(np.all(step > 0) or np.all(step < 0))
    psi1 = s * math.remainder(float(w[0]) - ref, 2 * math.pi)
    psi2 = s * math.remainder(float(w[-1]) - ref, 2 * math.pi)
    return SettingResult(x, psi1, psi2, psi2 - psi1, mu, closes and not dead, monotone, None)


def _strictly_inside(angle: float, lo: float, hi: float) -> bool:
    k = math.ceil((lo - angle) / (2 * math.pi))
    return lo < angle + 2 * math.pi * k < hi


def task1_adjustment(linkage: Linkage, psi_max: float, keep: str = "psi1") -> Adjustment:
    """Table 3 task 1 (ψ₁ const, ψ₂ regulated): the arc of joint A on the input lever centred at B's
    position in the kept extreme position (brought back to the lever's position at ψ = 0), radius the
    coupler b (module docstring). ``keep = "psi2"`` keeps ψ₂ instead.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.5, input_sense=-1)
    >>> round(radius(lk, task1_adjustment(lk, 0.5)), 9)
    120.0
    """
    if keep not in ("psi1", "psi2"):
        raise CamcadError(f"keep must be psi1 or psi2, got {keep!r}", "--keep", "use --keep psi1 or --keep psi2")
    at = 0.0 if keep == "psi1" else psi_max
    b_point = complex(np.asarray(linkage.joints(np.array([at]))["B"])[0])
    origin = complex(*linkage.loops[0].p)
    turn = linkage.input_sense * at
    centre = origin + (b_point - origin) * complex(math.cos(-turn), math.sin(-turn))
    return Adjustment("joint", "A", "arc", centre)


def settings_for(linkage: Linkage, adj: Adjustment, psi_max: float, quantity: str, targets, span: float = math.pi,
                 step: float = math.radians(0.5), mu_min: float = 0.0) -> list[float | None]:
    """The setting for each target value of ``quantity`` ("psi1", "psi2" or "swing"; rad): scan the settings
    from the nominal one outwards over ±``span`` while the linkage works (closes, keeps its branch), bracket
    every sign change of quantity − target and refine by Brent; the root nearest the nominal setting is taken
    (None when the working interval does not reach the target).

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.5, input_sense=-1)
    >>> adj = task1_adjustment(lk, 0.5)
    >>> x = settings_for(lk, adj, 0.5, "swing", [0.2])[0]
    >>> round(characteristics(lk, adj, x, 0.5).swing, 12)
    0.2
    """

    x_b = base_setting(linkage, adj)
    interval = working_interval(linkage, adj, psi_max, span, step, mu_min)
    grid = np.arange(interval[0], interval[1] + 0.5 * step, step)
    grid = np.clip(grid, interval[0], interval[1])

    def value(x):
        r = characteristics(linkage, adj, float(x), psi_max, points=9, quick=True)
        return getattr(r, quantity)

    values = np.array([value(x) for x in grid])
    found: list[float | None] = []
    for target in np.atleast_1d(np.asarray(targets, dtype=float)):
        diff = values - target
        roots = []
        for i in range(len(grid) - 1):
            if not (np.isfinite(diff[i]) and np.isfinite(diff[i + 1])):
                continue
            if diff[i] == 0.0:
                roots.append(float(grid[i]))
            elif diff[i] * diff[i + 1] < 0.0:
                root = bracketed_root(lambda x, t=target: value(x) - t, float(grid[i]), float(grid[i + 1]))
                if root is not None:
                    roots.append(root)
        if len(diff) and diff[-1] == 0.0:
            roots.append(float(grid[-1]))
        found.append(min(roots, key=lambda r: abs(r - x_b)) if roots else None)
    return found


def bracketed_root(fn, lo: float, hi: float, pieces: int = 16) -> float | None:
    """A root of ``fn`` between ``lo`` and ``hi`` (finite values of opposite signs there) by Brent's method;
    where ``fn`` is NaN somewhere inside (the linkage opens between two working settings) the bracket is cut
    into ``pieces`` and the first sub-bracket with finite values of opposite signs is refined; None when there
    is none.

    Examples
    --------
    >>> round(bracketed_root(lambda x: x * x - 2.0, 0.0, 2.0), 12)
    1.414213562373
    >>> f = lambda x: float("nan") if 0.4 < x < 0.6 else x - 0.8
    >>> round(bracketed_root(f, 0.0, 1.0), 12)
    0.8
    """
    from scipy.optimize import brentq

    try:
        return float(brentq(fn, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps))
    except ValueError:
        pass
    grid = np.linspace(lo, hi, pieces + 1)
    values = [fn(float(x)) for x in grid]
    for k in range(pieces):
        f0, f1 = values[k], values[k + 1]
        if math.isfinite(f0) and math.isfinite(f1) and f0 * f1 <= 0.0:
            if f0 == 0.0:
                return float(grid[k])
            return bracketed_root(fn, float(grid[k]), float(grid[k + 1]), pieces) if pieces > 2 else None
    return None


def working_interval(linkage: Linkage, adj: Adjustment, psi_max: float, span: float = math.pi,
                     step: float = math.radians(0.5), mu_min: float = 0.0) -> tuple[float, float]:
    """The interval of settings around the nominal one over which the linkage closes over the whole swing,
    keeps its branch and its transmission angle stays ≥ ``mu_min`` (rad); scanned in steps of ``step``."""
    x_b = base_setting(linkage, adj)

    def works(x):
        r = characteristics(linkage, adj, x, psi_max, points=17, quick=True)
        return r.branch_continuous and np.isfinite(r.mu_min) and r.mu_min >= mu_min

    if not works(x_b):
        raise CamcadError("the nominal linkage does not work over the swing (it does not close, reaches a dead point "
                          "or breaks the transmission-angle limit)", "linkage",
                          "check the linkage with camcad linkage analyse first")
    ends = []
    for sign in (-1.0, 1.0):
        x = x_b
        while abs(x - x_b) < span and works(x + sign * step):
            x += sign * step
        ends.append(x)
    return ends[0], ends[1]


# --------------------------------------------------------------------------------------------
# Task 1 (exact) and tasks 2–6 (fitted)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AdjustResult:
    """An adjustable mechanism for a regulation task: the element, its settings (rad or mm) against the
    regulating variable u, each setting's characteristics, the deviations from the task (rad) and checks."""

    task: int
    adjustment: Adjustment
    radius: float
    u: np.ndarray
    settings: np.ndarray
    rows: list
    deviation: dict
    monotone: bool
    notes: tuple[str, ...] = ()
    evidence: dict | None = None


def solve_task1(linkage: Linkage, psi_max: float, swing_range: tuple[float, float], count: int = 7,
                keep: str = "psi1", mu_min: float = 0.0) -> AdjustResult:
    """Table 3 task 1: ψ₁ constant, the swing regulated over ``swing_range`` (rad): the exact arc
    (``task1_adjustment``) and the settings giving ``count`` swings evenly spread over the range, among the
    settings where the linkage works (closes, keeps its branch, transmission angle ≥ ``mu_min`` rad).

    Raises CamcadError when the linkage cannot reach a requested swing without a dead point.
    """
    adj = task1_adjustment(linkage, psi_max, keep)
    lo, hi = swing_range
    targets = np.linspace(lo, hi, count)
    found = settings_for(linkage, adj, psi_max, "swing", targets, mu_min=mu_min)
    missing = [math.degrees(t) for t, x in zip(targets, found) if x is None]
    if missing:
        interval = working_interval(linkage, adj, psi_max, mu_min=mu_min)
        swings = [characteristics(linkage, adj, x, psi_max).swing for x in interval]
        raise CamcadError(f"no setting of the arc gives a swing of {missing[0]:.6g} deg: over the settings where the "
                          f"linkage works (mu >= {math.degrees(mu_min):.4g} deg) the swing runs "
                          f"{math.degrees(min(swings)):.6g} to "
                          f"{math.degrees(max(swings)):.6g} deg", "--swing-range",
                          "ask for a swing range inside that, or change the linkage")
    xs = np.array(found, dtype=float)
    rows = [characteristics(linkage, adj, float(x), psi_max) for x in xs]
    dense = np.linspace(xs.min(), xs.max(), 201)
    dense_swings = np.array([characteristics(linkage, adj, float(x), psi_max, points=9, quick=True).swing
                             for x in dense])
    monotone = bool(np.all(np.diff(dense_swings) > 0) or np.all(np.diff(dense_swings) < 0))
    fixed = "psi1" if keep == "psi1" else "psi2"
    spread = max(abs(getattr(r, fixed) - getattr(rows[0], fixed)) for r in rows)
    deviation = {f"{fixed}_spread": spread,
                 "swing": max(abs(r.swing - t) for r, t in zip(rows, targets))}
    return AdjustResult(1, adj, radius(linkage, adj), targets, xs, rows, deviation, monotone)


def fit_task(linkage: Linkage, psi_max: float, task: int, u_range: tuple[float, float], functions: dict,
             count: int = 21, starts: int = 3, max_evaluations: int = 100, mu_min: float = 0.0,
             ring_starts: int = 4) -> AdjustResult:
    """Tasks 2–6 of Table 3 fitted by least squares on ``count`` values of the regulating variable u
    over ``u_range``: the arc of joint A on the input lever (centre M, radius r) and the settings
    x(u) = x₀ + (x₁ − x₀)(u − u₀)/(u₁ − u₀); task 4 keeps task 1's arc (ψ₁ exact) and fits x₀, x₁ only.

    ``functions`` (callables of u, rad): task 2 {"psi2_of_psi1"} with u = ψ₁; task 3 {"psi1"}; task 4
    {"psi2"}; task 5 {"psi1", "psi2"}; task 6 {"swing"}. The fit starts from task 1's arc with settings
    spans of 10°, 20°, … (``starts``) in both directions, ``max_evaluations`` residual evaluations each; it is
    a local least-squares fit: the deviation it reports is what it reached, not a proven optimum.
    ``mu_min`` (rad): the transmission-angle limit, a constraint of the fit (10 × the violation in rad added to
    the residuals at every setting). Besides task 1's arc, ``ring_starts`` arc centres on a ring of radius b/2
    around it start fits too (spans of 10°, 20°, 30° by default); ``evidence`` says how many starts end at the
    best cost (within 1e-3 relative).

    Returns
    -------
    AdjustResult
        ``deviation``: the largest |characteristic − function| (rad) per fitted characteristic.
    """
    from scipy.optimize import least_squares

    if task not in (2, 3, 4, 5, 6):
        raise CamcadError(f"task {task} is not fitted", "--task", "tasks 2-6 are fitted; task 1 has its own solver")
    u = np.linspace(u_range[0], u_range[1], count)
    base = task1_adjustment(linkage, psi_max)
    x_b = base_setting(linkage, base)
    b_len = linkage.loops[0].b

    def unpack(p):
        if task == 4:
            return base, p[0], p[1]
        return Adjustment("joint", "A", "arc", complex(p[2], p[3])), p[0], p[1]

    def residuals(p):
        adj, x0, x1 = unpack(p)
        out = []
        for uk in u:
            x = x0 + (x1 - x0) * (uk - u[0]) / (u[-1] - u[0])
            try:
                r = characteristics(linkage, adj, x, psi_max, points=3, quick=True)
            except (CamcadError, ValueError, ZeroDivisionError):
                out += [1.0, 1.0, 1.0]
                continue
            if not r.branch_continuous:
                out += [1.0, 1.0, 1.0]
                continue
            out += _task_residual(task, r, uk, functions)
            out.append(10.0 * max(0.0, mu_min - r.mu_min) if math.isfinite(r.mu_min) else 1.0)
        return np.array(out)

    centre = cast(complex, base.centre)
    centres = [centre] + ([centre + 0.5 * b_len * complex(math.cos(2 * math.pi * k / ring_starts),
                                                          math.sin(2 * math.pi * k / ring_starts))
                           for k in range(ring_starts)] if task != 4 else [])
    fits = []
    for c0 in centres:
        for k in range(starts):
            width = math.radians(10.0 + 10.0 * k)
            x_mid = x_b if c0 == centre else math.atan2((_base_point(linkage, "A") - c0).imag,
                                                        (_base_point(linkage, "A") - c0).real)
            for sign in (1.0, -1.0):
                p0 = [x_mid - sign * width / 2, x_mid + sign * width / 2]
                if task != 4:
                    p0 += [c0.real, c0.imag]
                try:
                    fits.append(least_squares(residuals, np.array(p0), x_scale=[1.0, 1.0] + (
                        [b_len, b_len] if task != 4 else []), xtol=1e-15, ftol=1e-15, gtol=1e-15,
                        max_nfev=max_evaluations))
                except ValueError:
                    continue
            if fits and min(f.cost for f in fits) < 1e-24:
                break
    fits.sort(key=lambda f: f.cost)
    best: Any = fits[0]
    reach = sum(1 for f in fits if f.cost <= best.cost * (1 + 1e-3) + 1e-24)
    evidence = {"starts": len(fits), "reaching_best": reach, "tolerance_deg": 1e-3,
                "spread_deg": math.degrees(math.sqrt(2 * fits[min(len(fits) - 1, 4)].cost / max(len(best.fun), 1))),
                "note": "a multistart over arc centres and setting spans; the best of the starts is not a proof of "
                        "the global optimum"}
    adj, x0, x1 = unpack(best.x)
    xs = x0 + (x1 - x0) * (u - u[0]) / (u[-1] - u[0])
    rows = [characteristics(linkage, adj, float(x), psi_max) for x in xs]
    deviation = _task_deviation(task, rows, u, functions)
    quantity = {2: "psi2", 3: "psi1", 4: "psi2", 5: "psi2", 6: "swing"}[task]
    values = np.array([getattr(r, quantity) for r in rows])
    monotone = bool(np.all(np.diff(values) > 0) or np.all(np.diff(values) < 0))
    notes = () if all(r.branch_continuous for r in rows) else ("some settings do not keep the branch",)
    return AdjustResult(task, adj, radius(linkage, adj), u, xs, rows, deviation, monotone, notes, evidence)


def _task_residual(task: int, r: SettingResult, u: float, f: dict) -> list[float]:
    if task == 2:
        return [r.psi1 - u, r.psi2 - f["psi2_of_psi1"](u)]
    if task == 3:
        return [r.psi1 - f["psi1"](u), 0.0]
    if task == 4:
        return [r.psi2 - f["psi2"](u), 0.0]
    if task == 5:
        return [r.psi1 - f["psi1"](u), r.psi2 - f["psi2"](u)]
    return [r.swing - f["swing"](u), 0.0]


def _task_deviation(task: int, rows, u, f: dict) -> dict:
    out: dict[str, float] = {}
    for r, uk in zip(rows, u):
        if task == 2:
            pairs = [("psi1", r.psi1 - uk), ("psi2", r.psi2 - f["psi2_of_psi1"](uk))]
        elif task == 3:
            pairs = [("psi1", r.psi1 - f["psi1"](uk))]
        elif task == 4:
            pairs = [("psi1_spread", r.psi1 - rows[0].psi1), ("psi2", r.psi2 - f["psi2"](uk))]
        elif task == 5:
            pairs = [("psi1", r.psi1 - f["psi1"](uk)), ("psi2", r.psi2 - f["psi2"](uk))]
        else:
            pairs = [("swing", r.swing - f["swing"](uk))]
        for name, value in pairs:
            out[name] = max(out.get(name, 0.0), abs(float(value)))
    return out


# --------------------------------------------------------------------------------------------
# Table 2: a rotating input (crank) — the extreme positions in closed form
# --------------------------------------------------------------------------------------------

def crank_extremes(loop) -> list[tuple[float, float]]:
    """The output's extreme positions (φ, β) (rad, absolute) of a loop whose input link turns fully:
    input link and coupler collinear, |PB| = a + b (extended) or |a − b| (folded); B on the circle
    (Q, c), kept when the loop's own branch puts it there. Empty if the input cannot turn fully.

    Examples
    --------
    Crank-rocker a = 1, b = 3, c = 2.5, d = 3: β at the extended position has cos β = −(d² + c² − 16)/(2cd) mirrored.

    >>> from camcad.linkage.analysis import Loop
    >>> ext = crank_extremes(Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 2.5, 1))
    >>> len(ext)
    2
    """
    from camcad.linkage.qmethod import circle_intersections

    p, q = complex(*loop.p), complex(*loop.q)
    out = []
    for reach, sign in ((loop.a + loop.b, 1.0), (abs(loop.a - loop.b), 1.0 if loop.a >= loop.b else -1.0)):
        points, _ = circle_intersections(p, reach, q, loop.c)
        for b_pt in points:
            if reach == 0.0:
                continue
            direction = (b_pt - p) / abs(b_pt - p) * sign
            theta = math.atan2(direction.imag, direction.real)
            beta = float(loop.output(theta))
            if np.isfinite(beta) and abs(complex(math.cos(beta), math.sin(beta)) * loop.c + q - b_pt) < 1e-9 * max(
                    1.0, loop.c):
                out.append((theta, beta))
    return out


def crank_characteristics(linkage: Linkage, adj: Adjustment, x: float) -> dict:
    """Table 2's characteristics at setting ``x`` for a linkage whose input turns fully (a four-bar):
    φ₁, ψ₁ (the output's first extreme: the folded position), φ₂, ψ₂ (the extended one) and ψ₁₂, in deg
    (absolute angles), or an empty dict if the input cannot turn fully.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 2.5, 1),), theta0=0.0)
    >>> sorted(crank_characteristics(lk, Adjustment("link_angle"), 0.0))
    ['phi1_deg', 'phi2_deg', 'psi12_deg', 'psi1_deg', 'psi2_deg']
    """
    lk = adjusted(linkage, adj, x)
    loop = lk.loops[0]
    if len(lk.loops) != 1 or not grashof(loop.a, loop.b, loop.c, loop.d).input_rotates:
        return {}
    ext = crank_extremes(loop)
    if len(ext) != 2:
        return {}
    (phi2, psi2), (phi1, psi1) = ext[0], ext[1]
    return {"phi1_deg": math.degrees(phi1), "psi1_deg": math.degrees(psi1), "phi2_deg": math.degrees(phi2),
            "psi2_deg": math.degrees(psi2), "psi12_deg": math.degrees(math.remainder(psi2 - psi1, 2 * math.pi))}


def check_requirements(rows: list[dict], task: int, table: int = 3, tol_deg: float = 1e-9, kept: str = "psi1"
                       ) -> dict:
    """Which of the task's requirements the rows of characteristics (deg) meet: a "const" column must not
    move by more than ``tol_deg``; "var" and "f" columns must change monotonically over the rows.

    ``kept = "psi2"``: Table 3 task 1 solved with the second extreme kept (``solve_task1(keep="psi2")``) — the
    columns ψ₁ and ψ₂ trade roles, so the task's "ψ₁ const, ψ₂ var" is judged on ψ₂ const, ψ₁ var and reported
    under the names of the columns judged.

    Examples
    --------
    >>> rows = [{"psi1_deg": 0.0, "psi2_deg": 10.0}, {"psi1_deg": 0.0, "psi2_deg": 12.0}]
    >>> check_requirements(rows, 1)["passed"]
    True
    >>> kept2 = [{"psi1_deg": 4.0, "psi2_deg": 24.0}, {"psi1_deg": 2.0, "psi2_deg": 24.0}]
    >>> out = check_requirements(kept2, 1, kept="psi2")
    >>> out["psi2"]["need"], out["psi1"]["need"], out["passed"]
    ('const', 'var', True)
    """
    if kept not in ("psi1", "psi2"):
        raise CamcadError(f"keep must be psi1 or psi2, got {kept!r}", "--keep", "use --keep psi1 or --keep psi2")
    if kept == "psi2":
        swapped = [{**r, "psi1_deg": r["psi2_deg"], "psi2_deg": r["psi1_deg"]} for r in rows]
        verdict = check_requirements(swapped, task, table, tol_deg)
        return {{"psi1": "psi2", "psi2": "psi1"}.get(k, k): v for k, v in verdict.items()}
    spec = (TABLE3 if table == 3 else TABLE2).get(task)
    if spec is None:
        raise CamcadError(f"Table {table} has no task {task}", "--task",
                          f"tasks are 1-{max(TABLE3 if table == 3 else TABLE2)}")
    out: dict[str, object] = {}
    ok = True
    for column, need in spec.items():
        key = {"psi12": "swing_deg" if table == 3 else "psi12_deg", "x1": None}.get(column, f"{column}_deg")
        if key is None or key not in rows[0]:
            continue
        values = np.array([r[key] for r in rows], dtype=float)
        if need == "const":
            spread = float(np.ptp(values))
            passed = spread <= tol_deg
            out[column] = {"need": need, "spread_deg": spread, "passed": passed}
        else:
            d = np.diff(values)
            passed = bool(np.all(d > 0) or np.all(d < 0))
            out[column] = {"need": need, "range_deg": [float(values.min()), float(values.max())], "monotone": passed,
                           "passed": passed}
        ok = ok and passed
    out["passed"] = ok
    return out


# --------------------------------------------------------------------------------------------
# Table 2 synthesised (crank input)
# --------------------------------------------------------------------------------------------

#: the characteristics of Table 2 (crank input), deg, as changes from the nominal setting's values
TABLE2_COLUMNS = ("phi1", "psi1", "phi2", "psi2", "psi12")


@dataclass(frozen=True)
class Table2Result:
    """An element found for a Table 2 task: the element, its settings (deg or mm) over the regulating variable u,
    the largest deviation of each constrained characteristic (deg) and the multistart evidence."""

    adjustment: Adjustment
    u: np.ndarray
    settings: list
    deviation: dict
    evidence: dict
    notes: tuple[str, ...] = ()


def _relative(linkage: Linkage, adj: Adjustment, x: float, nominal: dict) -> dict | None:
    ch = crank_characteristics(linkage, adj, x)
    if not ch:
        return None
    out = {k: math.remainder(math.radians(ch[f"{k}_deg"]) - math.radians(nominal[f"{k}_deg"]), 2 * math.pi)
           for k in TABLE2_COLUMNS}
    return out


def table2_targets(task: int, u: np.ndarray, functions: dict, var_range: tuple[float, float] | None) -> dict:
    """The target of each constrained column of Table 2 task ``task`` over u (rad, changes from nominal):
    const 0; var a linear sweep over ``var_range`` (rad); f the given function of u (rad)."""
    spec = TABLE2[task]
    targets = {}
    for column, need in spec.items():
        if column == "x1":
            continue                          # the setting follows u by construction (x linear in u)
        if need == "const":
            targets[column] = np.zeros_like(u)
        elif need == "var":
            if var_range is None:
                raise CamcadError(f"task {task} regulates {column} within limits", "--var-range",
                                  f"give --var-range A:B (deg, the change of {column} from the nominal)")
            targets[column] = var_range[0] + (var_range[1] - var_range[0]) * (u - u[0]) / (u[-1] - u[0])
        else:
            if column not in functions:
                option = {"psi12": "--swing-function"}.get(column, f"--{column.replace('_', '-')}")
                raise CamcadError(f"task {task} relates {column} to the regulating variable", option,
                                  f"give {option} EXPR (deg, the change from the nominal, a function of x)")
            targets[column] = np.array([functions[column](v) for v in u])
    return targets


def synthesise_table2(linkage: Linkage, task: int, u_range: tuple[float, float] = (0.0, 1.0),
                      functions: dict | None = None, var_range: tuple[float, float] | None = None,
                      joint: str = "C", count: int = 11, mu_min: float = 0.0, rings: int = 3,
                      per_ring: int = 8) -> Table2Result:
    """An adjustable element for Table 2 task ``task`` (crank input): the pivot C (or the joint B on the rocker,
    ``joint="B"``) on an arc of centre M, locked at x(u) = x₀ + (x₁ − x₀)(u − u₀)/(u₁ − u₀), fitted by least
    squares to the task's columns (changes from the nominal linkage's values, rad): const → 0, var → a linear
    sweep over ``var_range``, f → ``functions[column](u)``; the crank must turn fully at every setting and the
    transmission angle over the turn stay ≥ ``mu_min`` (rad; exact penalties). Starts: arc centres on ``rings``
    rings (radius 0.5, 1, 2 × the rocker) × ``per_ring`` directions, settings spans ±10°; the best fit and how
    many starts reach it (within 1e-3 deg) are the evidence (a multistart, not a proof of the global optimum).

    Examples
    --------
    Task 3 (ψ₁ and ψ₂ functions of the setting) of a crank-rocker: both extremes move 3° apart per unit of u.

    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 30.0, 110.0, 90.0),), theta0=0.0)
    >>> f = {"psi1": lambda u: -math.radians(3.0) * u, "psi2": lambda u: math.radians(3.0) * u}
    >>> r = synthesise_table2(lk, 3, (0.0, 1.0), f, rings=1, per_ring=2, count=5)
    >>> r.deviation["psi1"] < 0.2, r.deviation["psi2"] < 0.2
    (True, True)
    """
    from scipy.optimize import least_squares

    if len(linkage.loops) != 1:
        raise CamcadError("Table 2 synthesis is for a four-bar with a crank", "--table 2", "give a four-bar")
    functions = functions or {}
    u = np.linspace(u_range[0], u_range[1], count)
    targets = table2_targets(task, u, functions, var_range)
    nominal = crank_characteristics(linkage, Adjustment("link_angle"), 0.0)
    if not nominal:
        raise CamcadError("the nominal linkage's input cannot turn fully (not a crank)", "--table 2",
                          "Table 2 is for a rotating input; the cam's rocker input is Table 3")
    loop = linkage.loops[0]
    p0 = complex(np.asarray(linkage.joints(0.0)[joint]))
    scale = loop.c

    def unpack(p):
        return Adjustment("pivot" if joint == "C" else "joint", joint, "arc", complex(p[0], p[1])), p[2], p[3]

    def residuals(p):
        adj, x0, x1 = unpack(p)
        out = []
        for k, uk in enumerate(u):
            x = x0 + (x1 - x0) * (uk - u[0]) / (u[-1] - u[0]) if u[-1] != u[0] else x0
            rel = _relative(linkage, adj, x, nominal)
            if rel is None:
                out += [1.0] * (len(targets) + 1)
                continue
            out += [rel[c] - targets[c][k] for c in targets]
            lk = adjusted(linkage, adj, x).loops[0]
            worst = lk.worst_transmission(0.0, 2 * math.pi)
            out.append(10.0 * max(0.0, mu_min - worst) if math.isfinite(worst) else 1.0)
        return np.array(out)

    fits = []
    for ring in range(rings):
        for k in range(per_ring):
            centre = p0 + (0.5 * 2 ** ring) * scale * complex(math.cos(2 * math.pi * k / per_ring),
                                                                  math.sin(2 * math.pi * k / per_ring))
            x_b = math.atan2((p0 - centre).imag, (p0 - centre).real)
            for sign in (1.0, -1.0):
                start = [centre.real, centre.imag, x_b, x_b + sign * math.radians(10.0)]
                try:
                    fits.append(least_squares(residuals, start, x_scale=[scale, scale, 1.0, 1.0], xtol=1e-12,
                                              ftol=1e-14, gtol=1e-14, max_nfev=200))
                except (ValueError, CamcadError):
                    continue
    if not fits:
        raise CamcadError(f"no element was found for Table 2 task {task}", "--synthesise",
                          "change the requirements or the linkage")
    fits.sort(key=lambda f: f.cost)
    best = fits[0]
    adj, x0, x1 = unpack(best.x)
    xs = [x0 + (x1 - x0) * (uk - u[0]) / (u[-1] - u[0]) for uk in u]
    deviation: dict[str, float] = {}
    for k, x in enumerate(xs):
        rel = _relative(linkage, adj, x, nominal)
        for c in targets:
            value = abs(rel[c] - targets[c][k]) if rel is not None else math.inf
            deviation[c] = max(deviation.get(c, 0.0), math.degrees(value))
    worst = max(deviation.values()) if deviation else 0.0
    reach = 0
    for f in fits:
        a2, y0, y1 = unpack(f.x)
        dev = 0.0
        for k, uk in enumerate(u):
            rel = _relative(linkage, a2, y0 + (y1 - y0) * (uk - u[0]) / (u[-1] - u[0]), nominal)
            dev = max([dev] + [math.degrees(abs(rel[c] - targets[c][k])) if rel else math.inf for c in targets])
        reach += dev <= worst + 1e-3
    evidence = {"starts": len(fits), "reaching_best": int(reach), "tolerance_deg": 1e-3, "best_deg": worst,
                "spread_deg": math.degrees(math.sqrt(2 * fits[min(len(fits) - 1, 4)].cost / len(best.fun)))
                if len(fits) > 1 else 0.0}
    settings = [math.degrees(x) for x in xs]
    notes = ("the columns are changes from the nominal linkage's values (deg)",)
    return Table2Result(adj, u, settings, deviation, evidence, notes)
