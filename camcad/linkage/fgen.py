"""A four-bar as a function generator: its structural error against a target, its checks, its nodes.

The mechanism (``FunctionGenerator``) is the four-bar of ``camcad.linkage.fourbar`` with two angle
offsets: the input link stands at θ = φ0 + φ and the output link at β = ψ0 + ψ when the target's
input coordinate is φ (``camcad.linkage.target``). The *structural error* is

    Δψ(φ) = β(φ0 + φ) − ψ0 − ψ_target(φ)   (wrapped to (−π, π]),

the output angle the mechanism gives minus the one the function asks for. Scheme parameters:
a, b, c, d (up to scale: three ratios), φ0 and ψ0 — S = 5 (Sunkuev 1984 ch. 2: S is the number of
parameters of the kinematic scheme).

Every synthesis method counts the *position computations* it makes (``Work``): one position is
the configuration of the linkage at one input angle (an output angle from the loop closure, or a
transmission angle from the diagonal). The verification of a result on a dense grid is counted
apart (``evaluate``), the same for every method.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from camcad.linkage.fourbar import (
    grashof,
    output_angle,
    output_derivatives,
    transmission_angle,
    worst_transmission_angle,
)
from camcad.linkage.target import Target

#: points of the verification grid (uniform in φ, ends included)
CHECK_POINTS = 2001
#: a transmission angle this close to 0 or 180 deg (rad) is a dead point: the output is not driven there
DEAD_POINT = 1e-6


@dataclass
class Work:
    """Counters of a synthesis run: position computations and objective evaluations."""

    positions: int = 0
    objective_evaluations: int = 0
    notes: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class FunctionGenerator:
    """A four-bar function generator: links a, b, c, d (one length unit), offsets φ0, ψ0 (rad), branch ±1."""

    a: float
    b: float
    c: float
    d: float
    phi0: float
    psi0: float
    branch: int

    def links(self) -> tuple[float, float, float, float]:
        return self.a, self.b, self.c, self.d

    def scaled(self, frame: float) -> FunctionGenerator:
        """The same mechanism with the frame length d = ``frame`` (angles unchanged)."""
        k = frame / self.d
        return replace(self, a=self.a * k, b=self.b * k, c=self.c * k, d=frame)

    def output(self, phi, work: Work | None = None):
        """β(φ0 + φ), rad; counts the positions in ``work``."""
        phi = np.asarray(phi, dtype=float)
        if work is not None:
            work.positions += int(phi.size)
        return output_angle(self.a, self.b, self.c, self.d, self.phi0 + phi, self.branch)


def wrap(angle):
    """Angle wrapped to (−π, π].

    Examples
    --------
    >>> round(float(wrap(3 * math.pi / 2)), 12) == round(-math.pi / 2, 12)
    True
    """
    return -np.remainder(-np.asarray(angle, dtype=float) + math.pi, 2 * math.pi) + math.pi


def structural_error(fg: FunctionGenerator, target: Target, phi, work: Work | None = None):
    """Structural error Δψ(φ) = β(φ0 + φ) − ψ0 − ψ_target(φ), rad, wrapped to (−π, π]; NaN where
    the linkage does not close (Sunkuev 1984 ch. 2: the deviation of the reproduced from the given
    dependence). Counts ``len(phi)`` positions in ``work``.

    Examples
    --------
    A parallelogram (β = θ on branch −1) judged against ψ = φ has no error:

    >>> from camcad.linkage.target import make_target
    >>> t = make_target(lambda x: x, 0.0, 1.0, 60.0, 60.0, "x")
    >>> fg = FunctionGenerator(1.0, 3.0, 1.0, 3.0, 0.5, 0.5, -1)
    >>> w = Work()
    >>> float(np.max(np.abs(structural_error(fg, t, np.linspace(0, t.dphi, 5), w)))) < 1e-12, w.positions
    (True, 5)
    """
    return wrap(fg.output(phi, work) - fg.psi0 - target.psi(phi))


def error_slope(fg: FunctionGenerator, target: Target, phi, work: Work | None = None):
    """dΔψ/dφ = β'(θ) − ψ_target'(φ) with the exact β' of ``fourbar.output_derivatives`` (dimensionless).

    Examples
    --------
    The parallelogram against ψ = φ: slope 0.

    >>> from camcad.linkage.target import make_target
    >>> t = make_target(lambda x: x, 0.0, 1.0, 60.0, 60.0, "x", derivative=lambda x: np.ones_like(x))
    >>> fg = FunctionGenerator(1.0, 3.0, 1.0, 3.0, 0.5, 0.5, -1)
    >>> abs(float(error_slope(fg, t, 0.3))) < 1e-12
    True
    """
    phi = np.asarray(phi, dtype=float)
    if work is not None:
        work.positions += int(phi.size)
    _, d_beta, _ = output_derivatives(fg.a, fg.b, fg.c, fg.d, fg.phi0 + phi, fg.branch)
    return d_beta - target.dpsi_dphi(phi)


def nodes(count: int, span: float, spacing: str = "chebyshev") -> np.ndarray:
    """``count`` interpolation nodes on [0, span] (rad or deg alike).

    Chebyshev spacing: φ_k = span (1 − cos((2k − 1)π/(2 count)))/2, k = 1..count (the zeros of
    the Chebyshev polynomial mapped to the interval, Freudenstein's usual choice of precision
    points); uniform: φ_k = span (k − ½)/count.

    Examples
    --------
    >>> [round(float(v), 4) for v in nodes(3, 60.0)]
    [4.0192, 30.0, 55.9808]
    """
    k = np.arange(1, count + 1)
    if spacing == "chebyshev":
        return span * (1.0 - np.cos((2 * k - 1) * np.pi / (2 * count))) / 2.0
    if spacing == "uniform":
        return span * (k - 0.5) / count
    raise ValueError(f"unknown spacing {spacing!r}")


@dataclass(frozen=True)
class Limits:
    """Design limits: smallest transmission angle μ_min (deg) and largest link ratio max/min."""

    mu_min_deg: float = 30.0
    ratio_max: float = 10.0

    def ratio_margin(self, fg: FunctionGenerator) -> float:
        """log(ratio_max) − log(max link / min link) (≥ 0: within the limit); a link of no length (a degenerate
        start an optimiser may reach, e.g. for a linear function) is −1000, far outside, not a division by 0."""
        links = fg.links()
        shortest, longest = min(links), max(links)
        if not (shortest > 0.0 and math.isfinite(longest)):
            return -1000.0
        return math.log(self.ratio_max) - math.log(longest / shortest)

    def mu_margin(self, fg: FunctionGenerator, target: Target, work: Work | None = None) -> float:
        """Worst min(μ, 180° − μ) over the working range minus μ_min, rad (closed form, ≤ 4 positions);
        −1 when the linkage does not close somewhere in the range."""
        lo = fg.phi0 + min(0.0, target.dphi)
        hi = fg.phi0 + max(0.0, target.dphi)
        if work is not None:
            work.positions += 2 + sum(1 for base in (0.0, math.pi)
                                      for k in range(math.ceil((lo - base) / (2 * math.pi)),
                                                     math.floor((hi - base) / (2 * math.pi)) + 1))
        worst = worst_transmission_angle(fg.a, fg.b, fg.c, fg.d, lo, hi)
        return -1.0 if math.isnan(worst) else worst - math.radians(self.mu_min_deg)


def pack(fg: FunctionGenerator) -> np.ndarray:
    """The five scheme parameters the optimisers vary (a = 1): log b/a, log c/a, log d/a, φ0, ψ0 (rad).

    Examples
    --------
    >>> [round(float(v), 6) for v in pack(FunctionGenerator(2.0, 2.0, 4.0, 2.0, 0.5, 0.25, 1))]
    [0.0, 0.693147, 0.0, 0.5, 0.25]
    """
    return np.array([math.log(fg.b / fg.a), math.log(fg.c / fg.a), math.log(fg.d / fg.a), fg.phi0, fg.psi0])


def unpack(x, branch: int) -> FunctionGenerator:
    """The function generator (a = 1) of the parameters of ``pack``.

    Examples
    --------
    >>> unpack([0.0, math.log(2.0), 0.0, 0.5, 0.25], 1).links()
    (1.0, 1.0, 2.0, 1.0)
    """
    return FunctionGenerator(1.0, math.exp(x[0]), math.exp(x[1]), math.exp(x[2]), float(x[3]), float(x[4]), branch)


#: how far inside its limits an optimiser keeps a mechanism (on cos μ and on log of the link ratio), so that
#: the check after it, which allows no violation, is met: 1e-9 of cos μ is 6e-8 deg of μ at 30 deg
INSIDE = 1e-9


def limit_margins(fg: FunctionGenerator, target: Target, limits: Limits, work: Work | None = None,
                  inside: float = INSIDE) -> np.ndarray:
    """The limits as smooth inequality constraints (every entry >= 0 when the mechanism is admissible).

    Transmission angle: min(μ, 180° − μ) >= μ_min is |cos μ| <= cos μ_min, written as the two smooth
    conditions cos μ_min ∓ cos μ >= 0 at the angles where |cos μ| can be largest over the working range — its
    ends and the input angles θ ≡ 0, π inside it (the diagonal f is extreme there; closed form, as
    ``fourbar.worst_transmission_angle``); they are defined where the loop does not close too (|cos μ| > 1
    then), so an optimiser is pushed back into the closing region. Link ratio: log R_max − log(l_i/l_j) >= 0
    for every ordered pair of links. Each entry is reduced by ``inside``.

    Examples
    --------
    The lsq mechanism of log10 on [1, 2] (60 deg, 90 deg) meets μ >= 30 deg (its worst μ is 35.4 deg):

    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> fg = FunctionGenerator(2.4321, 3.4329, 1.1837, 1.0, math.radians(85.82), math.radians(339.71), -1)
    >>> bool(limit_margins(fg, t, Limits(30.0, 10.0)).min() > 0)
    True
    """
    lo = fg.phi0 + min(0.0, target.dphi)
    hi = fg.phi0 + max(0.0, target.dphi)
    angles = [lo, hi]
    for base in (0.0, math.pi):      # one angle per base, so the number of constraints never changes
        inside_angle = base + 2 * math.pi * math.ceil((lo - base) / (2 * math.pi))
        angles.append(inside_angle if inside_angle <= hi else lo)
    if work is not None:
        work.positions += len(angles)
    theta = np.array(angles)
    f2 = fg.a ** 2 + fg.d ** 2 - 2.0 * fg.a * fg.d * np.cos(theta)
    cos_mu = (fg.b ** 2 + fg.c ** 2 - f2) / (2.0 * fg.b * fg.c)
    bound = math.cos(math.radians(limits.mu_min_deg))
    logs = np.log(np.array(fg.links()))
    ratio = [math.log(limits.ratio_max) - (logs[i] - logs[j]) for i in range(4) for j in range(4) if i != j]
    return np.concatenate([bound - cos_mu, bound + cos_mu, ratio]) - inside


@dataclass(frozen=True)
class Evaluation:
    """A mechanism checked on the dense grid (``CHECK_POINTS`` points over the working range)."""

    phi: np.ndarray              # rad
    error: np.ndarray            # rad
    max_error_deg: float
    rms_error_deg: float
    mu_min_deg: float            # worst min(μ, 180 − μ) over the range, closed form
    mu_min_at_deg: float         # input coordinate φ where it occurs (grid)
    branch_continuous: bool
    largest_step_deg: float      # largest change of β between neighbouring grid points
    step_bound_deg: float        # what a continuous motion allows: 1.5 max|β'| h
    grashof: str
    grashof_margin: float
    extrema: list[tuple[float, float]]   # (φ deg, error deg) at the local extrema of the error, ends included
    positions: int               # position computations of this check


def _local_extrema(phi: np.ndarray, err: np.ndarray) -> list[int]:
    """Indices of local extrema of ``err`` on the grid, both ends included."""
    idx = [0]
    d = np.diff(err)
    for k in range(1, len(err) - 1):
        if d[k - 1] * d[k] < 0 or (d[k - 1] != 0 and d[k] == 0):
            idx.append(k)
    idx.append(len(err) - 1)
    return idx


def evaluate(fg: FunctionGenerator, target: Target, points: int = CHECK_POINTS) -> Evaluation:
    """Check a function generator on a dense grid: structural error, transmission angle, branch.

    The branch is continuous when the linkage closes at every grid point and no step of the output
    angle between neighbours exceeds 1.5 × max|β'| × h (the exact β' of ``output_derivatives``): a
    jump would mean the loop closure passed to the other assembly branch.

    Examples
    --------
    A four-bar judged against its own position function has no error:

    >>> from camcad.linkage.target import make_target
    >>> from camcad.linkage.fourbar import output_angle
    >>> fg = FunctionGenerator(1.0, 3.0, 2.5, 3.0, 1.0, 0.0, 1)
    >>> beta0 = output_angle(1.0, 3.0, 2.5, 3.0, 1.0, 1)
    >>> t = make_target(lambda x: output_angle(1.0, 3.0, 2.5, 3.0, 1.0 + x, 1), 0.0, 0.5,
    ...                 math.degrees(0.5), math.degrees(output_angle(1.0, 3.0, 2.5, 3.0, 1.5, 1) - beta0), "self")
    >>> fg = FunctionGenerator(1.0, 3.0, 2.5, 3.0, 1.0, beta0, 1)
    >>> evaluate(fg, t).max_error_deg < 1e-9
    True
    """
    phi = np.linspace(0.0, target.dphi, points)
    work = Work()
    beta = fg.output(phi, work)
    err = wrap(beta - fg.psi0 - target.psi(phi))
    finite = np.isfinite(err)
    _, d_beta, _ = output_derivatives(fg.a, fg.b, fg.c, fg.d, fg.phi0 + phi, fg.branch)
    work.positions += points
    h = abs(phi[1] - phi[0])
    steps = np.abs(wrap(np.diff(beta)))
    bound = 1.5 * np.nanmax(np.abs(d_beta)) * h if finite.any() else 0.0
    mu = transmission_angle(fg.a, fg.b, fg.c, fg.d, fg.phi0 + phi)
    dev = np.minimum(mu, math.pi - mu)
    worst = worst_transmission_angle(fg.a, fg.b, fg.c, fg.d, fg.phi0 + min(0.0, target.dphi),
                                     fg.phi0 + max(0.0, target.dphi))
    # at a dead point β' is unbounded, so the step bound grows without limit there: a transmission angle of
    # 0 or 180 deg anywhere in the range (closed form) breaks the branch by itself
    continuous = bool(finite.all() and np.all(np.isfinite(d_beta)) and steps.max() <= bound + 1e-15
                      and math.isfinite(worst) and worst > DEAD_POINT)
    g = grashof(fg.a, fg.b, fg.c, fg.d)
    if finite.all():
        ext = _local_extrema(phi, err)
        extrema = [(math.degrees(phi[k]), math.degrees(err[k])) for k in ext]
        max_err = float(np.max(np.abs(err)))
        rms = float(np.sqrt(np.trapezoid(err ** 2, phi) / (phi[-1] - phi[0])))
    else:
        extrema, max_err, rms = [], float("inf"), float("inf")
    k_mu = int(np.nanargmin(dev)) if np.isfinite(dev).any() else 0
    return Evaluation(phi, err, math.degrees(max_err), math.degrees(rms),
                      math.degrees(worst) if math.isfinite(worst) else float("nan"), math.degrees(phi[k_mu]),
                      continuous, float(np.degrees(steps.max())) if steps.size else 0.0, float(np.degrees(bound)),
                      g.name, g.margin, extrema, work.positions)


def from_pivots(a_point: complex, b_point: complex, c_point: complex, phi_1: float, psi_1: float) -> FunctionGenerator:
    """The function generator whose input pivot is the origin, whose crank end A and coupler end B stand
    at ``a_point``, ``b_point`` (complex, any frame) when φ = ``phi_1``, and whose output pivot is
    ``c_point``; ψ0 makes node 1 exact (ψ(φ_1) = ``psi_1``).

    Examples
    --------
    >>> fg = from_pivots(1 + 0j, 1 + 3j, 3 + 0j, 0.0, 0.0)
    >>> [round(v, 12) for v in fg.links()], fg.branch
    ([1.0, 3.0, 3.605551275464, 3.0], -1)
    """
    frame = math.atan2(c_point.imag, c_point.real)
    turn = complex(math.cos(-frame), math.sin(-frame))
    a_l, b_l, c_l = a_point * turn, b_point * turn, c_point * turn
    a = abs(a_l)
    d = c_l.real
    theta_1 = math.atan2(a_l.imag, a_l.real)
    beta_1 = math.atan2((b_l - c_l).imag, (b_l - c_l).real)
    cross = ((a_l - c_l).conjugate() * (b_l - c_l)).imag
    return FunctionGenerator(a, abs(b_l - a_l), abs(b_l - c_l), d, theta_1 - phi_1, beta_1 - psi_1,
                             1 if cross > 0 else -1)
