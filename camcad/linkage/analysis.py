"""Analysis of the linkage after the cam: the position function Π of the working member and its exact
derivatives, transmission angles, dead points, limit positions, branch continuity and the coupler path.

The chain is one four-bar, or a six-bar made of two four-bars in series (the output link of the first
loop is rigid with the input link of the second, both pivoting at the first loop's output pivot, the
Sunkuev 1984's "two four-bars connected in series", ch. 4, the paragraph "Регулируемый шестизвенник состоит из
двух последовательно соединенных четырехзвенников"). The input is the follower's rocker: it turns by
the follower's swing ψ (rad) from its position with the roller on the base circle.

Frame and conventions (mm, rad, counter-clockwise): every joint has absolute coordinates. A loop
(``Loop``) has its input pivot P, output pivot Q, input link PA = a, coupler AB = b, output link QB = c
and the assembly branch σ of ``camcad.linkage.fourbar`` taken in the loop's own frame (P at the origin,
Q on +x). Loop k's input angle θ_k is the absolute direction of P→A, its output angle β_k the absolute
direction of Q→B. The input of loop 1 is θ_1 = θ_0 + s_in ψ (s_in = ±1: the input link turns with the
follower arm; camcad's oscillating follower turns clockwise as ψ grows, s_in = −1); loop k + 1 has
θ_{k+1} = β_k + κ_k (κ_k the fixed angle between the two links of the ternary link). The working member
is the last output link; its position function is

    Π(ψ) = s_out (β_last(ψ) − β_last(0))   (rad; s_out = ±1 makes the stroke over the swing positive).

Exact derivatives (closed form from the loop closure, no finite differences). Differentiating
a e^{iθ} + b e^{iλ} − c e^{iβ} − d e^{iε} = 0 (λ the coupler angle, ε the frame direction) n times with
respect to θ gives i b λ⁽ⁿ⁾ e^{iλ} − i c β⁽ⁿ⁾ e^{iβ} = R_n, and projecting on the normals of the two links

    β⁽ⁿ⁾ = Re(R_n e^{−iλ}) / (c sin(β − λ)),   λ⁽ⁿ⁾ = Re(R_n e^{−iβ}) / (b sin(β − λ)),
    R_1 = −i a e^{iθ},
    R_2 = a e^{iθ} + b λ'² e^{iλ} − c β'² e^{iβ},
    R_3 = i a e^{iθ} + b (3λ'λ'' + iλ'³) e^{iλ} − c (3β'β'' + iβ'³) e^{iβ}

(the n-th derivative of e^{iα} is (iα⁽ⁿ⁾ + …) e^{iα}: e.g. (iα''' − 3α'α'' − iα'³) e^{iα} for n = 3).
The loops compose by Faà di Bruno's formula: (f∘g)' = f'g', (f∘g)'' = f''g'² + f'g'',
(f∘g)''' = f'''g'³ + 3f''g'g'' + f'g'''. Everything blows up at a dead point, sin(β − λ) = 0.

Special positions of a loop over its input interval:

- *dead points* (the input cannot drive the loop: coupler and output link aligned, transmission angle 0°
  or 180°) where the diagonal f = |QA| equals b + c or |b − c|: cos(θ − ε) = (a² + d² − f²)/(2ad), in
  closed form. The branch can only change there, so a swing without dead points and with the loop
  closed everywhere keeps its branch (``branch_continuous``).
- *limit positions* of the output (Π' = 0: input link and coupler aligned) — found as the roots of the
  closed-form Π' by bracketing every sign change on the sampled swing and Brent's method. A position
  function with a limit position inside the swing is not monotone there and cannot be inverted.

The transmission angle μ of a loop is the angle between coupler and output link, cos μ = (b² + c² − f²)/
(2bc); its worst value min(μ, 180° − μ) over an input interval is exact (``fourbar.worst_transmission_angle``).

Sources: F. Freudenstein, Trans. ASME 77 (1955) 853–861 (the loop equation); R. L. Norton, Design of
Machinery (vector-loop velocity and acceleration analysis); B. S. Sunkuev 1984, ch. 4 (the
six-bar of two four-bars in series); the batten's position function Π.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from itertools import pairwise

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.fourbar import output_angle, worst_transmission_angle

#: points of the analysis grid over the swing (ends included)
ANALYSIS_POINTS = 721


def _unit(angle):
    angle = np.asarray(angle, dtype=float)
    out = np.empty(angle.shape, dtype=complex)
    out.real = np.cos(angle)
    out.imag = np.sin(angle)
    return out


@dataclass(frozen=True)
class Loop:
    """One four-bar loop in absolute coordinates (module docstring).

    Parameters
    ----------
    p, q : tuple of float
        Input pivot P and output pivot Q, mm.
    a, b, c : float
        Input link PA, coupler AB, output link QB, mm.
    branch : {1, -1}
        Assembly branch σ in the loop's own frame (``camcad.linkage.fourbar``).

    Examples
    --------
    A parallelogram on its open branch: the output turns with the input.

    >>> loop = Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1)
    >>> round(float(loop.output(0.7)), 12)
    0.7
    """

    p: tuple[float, float]
    q: tuple[float, float]
    a: float
    b: float
    c: float
    branch: int = 1

    @property
    def d(self) -> float:
        """Frame length |PQ|, mm."""
        return math.hypot(self.q[0] - self.p[0], self.q[1] - self.p[1])

    @property
    def frame_angle(self) -> float:
        """Direction ε of P→Q, rad."""
        return math.atan2(self.q[1] - self.p[1], self.q[0] - self.p[0])

    def output(self, theta):
        """Absolute output angle β (rad) at absolute input angle θ (rad); NaN where the loop cannot close.

        Examples
        --------
        >>> round(float(Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1).output(1.2)), 12)
        1.2
        """
        eps = self.frame_angle
        return np.asarray(output_angle(self.a, self.b, self.c, self.d, np.asarray(theta, dtype=float) - eps,
                                       self.branch)) + eps

    def derivatives(self, theta, order: int = 3):
        """β, β', β'', β''' and λ (rad; ' = d/dθ) at absolute input angles θ (rad), exact (module docstring).

        Returns
        -------
        tuple of ndarray
            (β, β', β'', β''', λ); NaN where the loop cannot close, ±inf at a dead point.

        Examples
        --------
        A parallelogram: β = θ, so β' = 1 and β'' = β''' = 0.

        >>> beta, d1, d2, d3, lam = Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1).derivatives(0.4)
        >>> round(float(d1), 12), abs(round(float(d2), 12)), abs(round(float(d3), 12))
        (1.0, 0.0, 0.0)
        """
        theta = np.asarray(theta, dtype=float)
        beta = np.asarray(self.output(theta), dtype=float)
        a, b, c = self.a, self.b, self.c
        eq = self.q[0] - self.p[0] + 1j * (self.q[1] - self.p[1])
        coupler = eq + c * _unit(beta) - a * _unit(theta)
        lam = np.angle(coupler)
        e_t, e_l, e_b = _unit(theta), _unit(lam), _unit(beta)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.sin(beta - lam)
            el_inv, eb_inv = np.conj(e_l), np.conj(e_b)

            def solve(r):
                return (np.real(r * eb_inv) / (b * s), np.real(r * el_inv) / (c * s))

            l1, b1 = solve(-1j * a * e_t)
            if order < 2:
                zero = np.zeros_like(b1)
                return beta, b1, zero, zero, lam
            l2, b2 = solve(a * e_t + b * l1 ** 2 * e_l - c * b1 ** 2 * e_b)
            _, b3 = solve(1j * a * e_t + b * (3 * l1 * l2 + 1j * l1 ** 3) * e_l
                          - c * (3 * b1 * b2 + 1j * b1 ** 3) * e_b)
        return beta, b1, b2, b3, lam

    def joints(self, theta) -> tuple[np.ndarray, np.ndarray]:
        """Joints A and B (complex, mm) at absolute input angles θ (rad).

        Examples
        --------
        >>> a_pt, b_pt = Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1).joints(math.pi / 2)
        >>> round(float(b_pt.real), 12), round(float(b_pt.imag), 12)
        (3.0, 1.0)
        """
        theta = np.asarray(theta, dtype=float)
        p = complex(*self.p)
        q = complex(*self.q)
        return p + self.a * _unit(theta), q + self.c * _unit(self.output(theta))

    def transmission(self, theta):
        """Transmission angle μ (rad, 0…π) at absolute input angles θ; NaN where the loop cannot close.

        Examples
        --------
        >>> round(math.degrees(float(Loop((0.0, 0.0), (1.0, 0.0), 1.0, 1.0, 1.0).transmission(math.pi / 2))), 9)
        90.0
        """
        f2 = self.a ** 2 + self.d ** 2 - 2 * self.a * self.d * np.cos(np.asarray(theta, dtype=float) - self.frame_angle)
        cos_mu = (self.b ** 2 + self.c ** 2 - f2) / (2 * self.b * self.c)
        with np.errstate(invalid="ignore"):
            return np.where(np.abs(cos_mu) <= 1.0, np.arccos(np.clip(cos_mu, -1.0, 1.0)), np.nan)

    def worst_transmission(self, theta_start: float, theta_end: float) -> float:
        """Smallest min(μ, π − μ) (rad) over the input interval, closed form; NaN if the loop opens.

        Examples
        --------
        >>> round(math.degrees(Loop((0.0, 0.0), (1.0, 0.0), 1.0, 1.0, 1.0).worst_transmission(1.0, 2.0)), 6)
        57.29578
        """
        eps = self.frame_angle
        return worst_transmission_angle(self.a, self.b, self.c, self.d, theta_start - eps, theta_end - eps)

    def dead_points(self) -> list[float]:
        """Absolute input angles (rad, in (−π, π]) at which the diagonal |QA| equals b + c or |b − c|:
        the transmission angle is 0° or 180° and the input cannot drive the loop (closed form).

        Examples
        --------
        Crank 1, frame 3, coupler 1.5, output 1: f = b + c = 2.5 at cos θ = (1 + 9 − 6.25)/6.

        >>> [round(math.degrees(t), 6) for t in Loop((0, 0), (3, 0), 1.0, 1.5, 1.0).dead_points()]
        [51.317813, -51.317813]
        """
        out = []
        eps = self.frame_angle
        a, d = self.a, self.d
        for f in (self.b + self.c, abs(self.b - self.c)):
            cos_t = (a * a + d * d - f * f) / (2 * a * d)
            if -1.0 <= cos_t <= 1.0:
                t = math.acos(cos_t)
                for sign in ((1.0,) if t in (0.0, math.pi) else (1.0, -1.0)):
                    out.append(math.remainder(eps + sign * t, 2 * math.pi))
        return out

    def with_branch_through(self, theta: float, b_point: complex) -> Loop:
        """The same loop on the branch that puts B at ``b_point`` (mm) at input angle θ (rad).

        Examples
        --------
        >>> loop = Loop((0, 0), (3, 0), 1.0, 3.0, 1.0, 1)
        >>> loop.with_branch_through(math.pi / 2, 3 + 1j).branch
        -1
        """
        candidates = [replace(self, branch=s) for s in (1, -1)]
        dist = [abs(complex(np.asarray(c.joints(theta)[1])) - b_point) for c in candidates]
        dist = [d if math.isfinite(d) else math.inf for d in dist]
        return candidates[int(np.argmin(dist))]


def compose(inner, outer):
    """Derivatives of f∘g up to the third from those of g (``inner`` = (g, g', g'', g''')) and of f at g
    (``outer`` = (f, f', f'', f''')): Faà di Bruno.

    Examples
    --------
    f = sin, g = 2x at x = 0.3: (f∘g)''' = −8 cos(0.6).

    >>> x = 0.3
    >>> d = compose((2 * x, 2.0, 0.0, 0.0), (math.sin(2 * x), math.cos(2 * x), -math.sin(2 * x), -math.cos(2 * x)))
    >>> round(d[3] + 8 * math.cos(0.6), 12)
    0.0
    """
    _, g1, g2, g3 = inner
    f, f1, f2, f3 = outer
    return (f, f1 * g1, f2 * g1 ** 2 + f1 * g2, f3 * g1 ** 3 + 3 * f2 * g1 * g2 + f1 * g3)


@dataclass(frozen=True)
class Linkage:
    """The linkage after the follower: one or two loops in series (module docstring).

    Parameters
    ----------
    loops : tuple of Loop
        Loop 1 (input pivot = the follower's pivot), and optionally loop 2 (input pivot = loop 1's
        output pivot).
    theta0 : float
        Absolute angle of loop 1's input link at ψ = 0 (rad).
    input_sense : {1, -1}
        dθ_1/dψ: +1 when the input link turns counter-clockwise as ψ grows.
    couplings : tuple of float
        κ_k (rad): loop k + 1's input angle is loop k's output angle + κ_k.
    output_sense : {1, -1}
        s_out of Π = s_out (β_last(ψ) − β_last(0)).
    output_offset : float
        The working member's absolute angle is β_last + ``output_offset`` (rad): 0 unless an adjustment
        moves the joint B on the output lever (``camcad.linkage.adjust``).
    coupler_point : tuple or None
        (loop index 0|1, u, v): a point of that loop's coupler, u mm along A→B, v mm to its left.

    Examples
    --------
    >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=0.5, input_sense=1)
    >>> y, y1, y2, y3 = lk.position(0.2)
    >>> round(float(y), 12), round(float(y1), 12)
    (0.2, 1.0)
    """

    loops: tuple[Loop, ...]
    theta0: float
    input_sense: int = 1
    couplings: tuple[float, ...] = ()
    output_sense: int = 1
    output_offset: float = 0.0
    coupler_point: tuple | None = None

    def __post_init__(self) -> None:
        if len(self.couplings) != len(self.loops) - 1:
            raise ValueError("one coupling angle per pair of loops")

    @property
    def kind(self) -> str:
        return "fourbar" if len(self.loops) == 1 else "sixbar"

    def angles(self, psi, order: int = 3) -> list[tuple[np.ndarray, tuple]]:
        """Per loop: (its input angle θ_k, its (β, β', β'', β''', λ) w.r.t. θ_k) at swings ψ (rad)."""
        theta = self.theta0 + self.input_sense * np.asarray(psi, dtype=float)
        out = []
        for k, loop in enumerate(self.loops):
            d = loop.derivatives(theta, order)
            out.append((theta, d))
            if k < len(self.couplings):
                theta = d[0] + self.couplings[k]
        return out

    def absolute_derivatives(self, psi, order: int = 3):
        """β_last and its derivatives with respect to ψ (rad/rad), chained through every loop."""
        psi = np.asarray(psi, dtype=float)
        g = (self.theta0 + self.input_sense * psi, self.input_sense * np.ones_like(psi), np.zeros_like(psi),
             np.zeros_like(psi))
        for _, d in self.angles(psi, order):
            g = compose(g, d[:4])
            # the next loop's input differs by a constant: the same derivatives
        return g

    def position(self, psi, order: int = 3):
        """Π, Π', Π'', Π''' at swings ψ (rad): rad of the working member per rad of follower swing.

        Examples
        --------
        >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=0.5, input_sense=1)
        >>> [round(float(v), 12) + 0.0 for v in lk.position(0.1)]
        [0.1, 1.0, 0.0, 0.0]
        """
        beta, d1, d2, d3 = self.absolute_derivatives(psi, order)
        base = float(self.absolute_derivatives(0.0, 1)[0])
        s = self.output_sense
        # the output angle of fourbar.output_angle jumps by 2π where A crosses the frame line beyond Q; a
        # rocker turns less than half a turn, so the turn from ψ = 0 is taken in (−π, π]
        turn = np.remainder(beta - base + np.pi, 2 * np.pi) - np.pi
        return s * turn, s * d1, s * d2, s * d3

    def working_angle(self, psi):
        """The working member's absolute angle β_last + output_offset (rad) at swings ψ."""
        return self.absolute_derivatives(psi, order=1)[0] + self.output_offset

    def joints(self, psi) -> dict[str, np.ndarray]:
        """Named joints (complex mm) at swings ψ: O, A, B, C and, for a six-bar, D, E, F; ``P`` the coupler point.

        Examples
        --------
        >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=math.pi / 2)
        >>> j = lk.joints(0.0)
        >>> round(float(j["B"].real), 12), round(float(j["B"].imag), 12)
        (3.0, 1.0)
        """
        names = (("O", "A", "B", "C"), ("C", "D", "E", "F"))
        out: dict[str, np.ndarray] = {}
        for k, (theta, _) in enumerate(self.angles(psi)):
            loop = self.loops[k]
            a_pt, b_pt = loop.joints(theta)
            n = names[k]
            out[n[0]] = complex(*loop.p) + 0 * a_pt
            out[n[1]], out[n[2]] = a_pt, b_pt
            out[n[3]] = complex(*loop.q) + 0 * a_pt
            if self.coupler_point is not None and self.coupler_point[0] == k:
                _, u, v = self.coupler_point
                e = (b_pt - a_pt) / loop.b
                out["P"] = a_pt + (u + 1j * v) * e
        return out

    def transmission(self, psi) -> list[np.ndarray]:
        """Transmission angle μ (rad) of every loop at swings ψ."""
        return [loop.transmission(theta) for loop, (theta, _) in zip(self.loops, self.angles(psi))]


# --------------------------------------------------------------------------------------------
# The analysis over a swing
# --------------------------------------------------------------------------------------------

def _angle_in(angle: float, start: float, end: float) -> float | None:
    """``angle`` (mod 2π) inside [min, max] of (start, end), returned in that interval, else None."""
    lo, hi = min(start, end), max(start, end)
    k = math.ceil((lo - angle) / (2 * math.pi))
    candidate = angle + 2 * math.pi * k
    return candidate if candidate <= hi else None


def _roots(fn, x: np.ndarray, values: np.ndarray) -> list[float]:
    """Every root of ``fn`` on the grid ``x``: a zero sample, or a sign change bracketed and refined by Brent."""
    from scipy.optimize import brentq

    roots = []
    for i in range(len(x) - 1):
        v0, v1 = values[i], values[i + 1]
        if not (np.isfinite(v0) and np.isfinite(v1)):
            continue
        if v0 == 0.0:
            roots.append(float(x[i]))
        elif v0 * v1 < 0.0:
            roots.append(float(brentq(fn, x[i], x[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)))
    if len(values) and values[-1] == 0.0:
        roots.append(float(x[-1]))
    return roots


@dataclass(frozen=True)
class LinkageAnalysis:
    """What ``analyse`` found over the swing [0, ψ_max] (rad); arrays over ``psi``.

    ``pi`` Π (rad), ``d1`` Π', ``d2`` Π'', ``d3`` Π''' (per rad of swing); ``mu`` the transmission angle of
    each loop (rad); ``mu_min`` each loop's worst min(μ, π − μ) over the swing (closed form, rad);
    ``dead_points`` swings (rad) at which a loop reaches a dead point; ``limit_positions`` swings where
    Π' = 0; ``closes`` the loops close over the whole swing; ``branch_continuous`` they close and no dead
    point is inside the swing; ``monotone`` Π' keeps one sign (no limit position inside).
    """

    linkage: Linkage
    psi_max: float
    psi: np.ndarray
    pi: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    mu: list
    mu_min: list
    dead_points: list
    limit_positions: list
    closes: bool
    branch_continuous: bool
    monotone: bool
    joints: dict = field(repr=False, default_factory=dict)

    @property
    def stroke(self) -> float:
        """Π(ψ_max), rad."""
        return float(self.pi[-1])

    def worst_mu_deg(self) -> float:
        return float(np.degrees(min(self.mu_min))) if self.mu_min and all(np.isfinite(self.mu_min)) else float("nan")

    def report(self, mu_limit_deg: float | None = None) -> dict:
        """JSON-ready figures (deg, mm) and checks ({value, limit, margin, passed})."""
        rad = math.degrees
        lk = self.linkage
        out = {
            "type": lk.kind,
            "swing_deg": rad(self.psi_max),
            "stroke_deg": rad(self.stroke),
            "ratio_mean": self.stroke / self.psi_max if self.psi_max else None,
            "pi_prime_range": [float(np.nanmin(self.d1)), float(np.nanmax(self.d1))],
            "pi_second_abs_max": float(np.nanmax(np.abs(self.d2))),
            "pi_third_abs_max": float(np.nanmax(np.abs(self.d3))),
            "output_direction": "ccw" if lk.output_sense > 0 else "cw",
            "mu_min_deg": [rad(m) for m in self.mu_min],
            "dead_points_swing_deg": [rad(x) for x in self.dead_points],
            "limit_positions_swing_deg": [rad(x) for x in self.limit_positions],
            "closes": self.closes,
            "branch_continuous": self.branch_continuous,
            "monotone": self.monotone,
            "loops": [{"input_pivot_mm": list(loop.p), "output_pivot_mm": list(loop.q), "a_mm": loop.a,
                       "b_mm": loop.b, "c_mm": loop.c, "d_mm": loop.d, "branch": loop.branch}
                      for loop in lk.loops],
            "input_angle_at_zero_deg": rad(lk.theta0),
            "couplings_deg": [rad(k) for k in lk.couplings],
        }
        checks = {"branch_continuous": {"value": self.branch_continuous, "passed": self.branch_continuous,
                                        "why": "the loops close over the whole swing without a dead point"},
                  "monotone": {"value": self.monotone, "passed": self.monotone,
                               "why": "no limit position of the working member inside the swing"}}
        if mu_limit_deg is not None:
            worst = self.worst_mu_deg()
            ok = bool(np.isfinite(worst) and worst >= mu_limit_deg)
            checks["transmission_angle"] = {"value": worst, "limit": mu_limit_deg,
                                            "margin": worst - mu_limit_deg if np.isfinite(worst) else None,
                                            "passed": ok, "why": "smallest min(mu, 180 - mu) over the swing"}
        out["checks"] = checks
        out["passed"] = all(c["passed"] for c in checks.values())
        return out


def analyse(linkage: Linkage, psi_max: float, points: int = ANALYSIS_POINTS) -> LinkageAnalysis:
    """Analyse ``linkage`` over the swing [0, ψ_max] (rad): Π and its exact derivatives on ``points``
    points, transmission angles (sampled and worst in closed form), dead points (closed form), limit
    positions (roots of Π'), closure and branch continuity.

    Parameters
    ----------
    linkage : Linkage
        The chain.
    psi_max : float
        The follower's swing, rad (> 0).
    points : int
        Samples over the swing, ends included.

    Returns
    -------
    LinkageAnalysis

    Examples
    --------
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0, 1),), theta0=math.radians(80))
    >>> res = analyse(lk, math.radians(30))
    >>> res.closes, res.branch_continuous, res.monotone
    (True, True, True)
    """
    if not psi_max > 0.0:
        raise CamcadError(f"the swing must be positive, got {math.degrees(psi_max):g} deg", "linkage",
                          "give the follower's swing (deg)")
    psi = np.linspace(0.0, psi_max, points)
    pi, d1, d2, d3 = linkage.position(psi)
    closes = bool(np.all(np.isfinite(pi)))
    mus, worst, dead = [], [], []
    for loop, (theta, _) in zip(linkage.loops, linkage.angles(psi)):
        mus.append(loop.transmission(theta))
        # the loop's input sweeps each monotone piece of its samples (one piece unless a loop before it has a
        # limit position); a dead point is looked for where the input is known, also when the loop opens
        # beyond it — that is where it opens
        finite = np.isfinite(theta)
        count = int(np.argmin(finite)) if not np.all(finite) else len(theta)
        pieces = _monotone_pieces(theta[:count]) if count > 1 else []
        worst.append(min(loop.worst_transmission(float(theta[i]), float(theta[j])) for i, j in pieces)
                     if closes else float("nan"))
        for angle in loop.dead_points():
            for i, j in pieces:
                hit = _angle_in(angle, float(theta[i]), float(theta[j]))
                if hit is not None:
                    dead.append(_swing_at(linkage, len(mus) - 1, hit, psi[:count], theta[:count]))
    dead_at = sorted({round(x, 15) for x in dead if x is not None})
    limits = []
    if closes:
        def first(x):
            return float(linkage.position(np.array([x]))[1][0])

        limits = [x for x in _roots(first, psi, d1) if 0.0 < x < psi_max]
    inner_dead = [x for x in dead_at if 0.0 < x < psi_max]
    continuous = closes and not inner_dead and _no_jumps(pi, d1, psi)
    monotone = closes and not limits and bool(np.all(d1 > 0) or np.all(d1 < 0))
    return LinkageAnalysis(linkage, psi_max, psi, pi, d1, d2, d3, mus, worst, dead_at, limits, closes, continuous,
                           monotone, linkage.joints(psi))


def _monotone_pieces(theta: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) indices of the pieces of ``theta`` between its turning points: the loop's input sweeps
    each piece monotonically (one piece unless a loop before it has a limit position in the swing)."""
    d = np.diff(theta)
    turns = [0] + [i + 1 for i in range(len(d) - 1) if d[i] * d[i + 1] < 0] + [len(theta) - 1]
    return list(pairwise(turns))


def _swing_at(linkage: Linkage, loop_index: int, theta_hit: float, psi: np.ndarray, theta: np.ndarray) -> float | None:
    """The swing ψ at which loop ``loop_index``'s input reaches ``theta_hit`` (bracketed on the samples)."""
    from scipy.optimize import brentq

    diff = theta - theta_hit
    for i in range(len(psi) - 1):
        if diff[i] == 0.0:
            return float(psi[i])
        if diff[i] * diff[i + 1] < 0.0:
            def f(x):
                return float(linkage.angles(np.array([x]))[loop_index][0][0]) - theta_hit
            try:
                return float(brentq(f, psi[i], psi[i + 1], xtol=1e-15))
            except ValueError:
                return float(psi[i])
    if diff[-1] == 0.0:
        return float(psi[-1])
    return None


def _no_jumps(pi: np.ndarray, d1: np.ndarray, psi: np.ndarray) -> bool:
    """No step of Π larger than 1.5 max|Π'| h: the samples stay on one branch."""
    h = float(psi[1] - psi[0]) if len(psi) > 1 else 0.0
    return bool(np.all(np.abs(np.diff(pi)) <= 1.5 * float(np.max(np.abs(d1))) * h + 1e-12))
