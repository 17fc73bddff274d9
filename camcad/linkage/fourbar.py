"""Position analysis of the planar four-bar: Freudenstein's equation, both assembly branches,
transmission angle, Grashof class and the exact derivatives of the output angle.

Convention (used by every function of ``camcad.linkage``). Input pivot O at the origin, output pivot
C = (d, 0) on the +x axis (the frame line O→C). Input link (crank) OA of length a at angle θ from
the frame line; coupler AB of length b; output link (rocker) CB of length c at angle β, also from
the +x direction; all angles counter-clockwise. Loop closure:

    a e^{iθ} + b e^{iλ} = d + c e^{iβ}         (λ: coupler angle)

Eliminating λ gives Freudenstein's equation

    K1 cos β − K2 cos θ + K3 = cos(θ − β),   K1 = d/a,  K2 = d/c,  K3 = (a² − b² + c² + d²)/(2ac).

For a given θ two configurations close the loop (the two *assembly branches*): with f = |CA| the
diagonal and δ the direction of C→A, β = δ + σ γ, cos γ = (c² + f² − b²)/(2 c f), σ = ±1; σ = +1
puts B to the left of the directed diagonal C→A. The branch cannot change while the linkage moves
except through a dead point (γ = 0 or π, i.e. f = b + c or f = |b − c|).

The transmission angle μ is the angle between coupler and rocker at B,
cos μ = (b² + c² − f²)/(2 b c), 0 ≤ μ ≤ 180°; it does not depend on the branch. The deviation from
a right angle, |90° − μ|, is what matters: a design limit μ_min means min(μ, 180° − μ) ≥ μ_min.

Angles in this module are radians unless a name ends in ``_deg``; lengths in any one unit (mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def freudenstein_coefficients(a: float, b: float, c: float, d: float) -> tuple[float, float, float]:
    """Freudenstein's K1, K2, K3 of a four-bar.

    K1 = d/a, K2 = d/c, K3 = (a² − b² + c² + d²)/(2 a c), in
    K1 cos β − K2 cos θ + K3 = cos(θ − β) (Freudenstein, Trans. ASME 77 (1955) 853–861).

    Parameters
    ----------
    a, b, c, d : float
        Crank, coupler, rocker and frame lengths (any one unit).

    Returns
    -------
    tuple of float
        (K1, K2, K3), dimensionless.

    Examples
    --------
    >>> freudenstein_coefficients(1.0, 3.0, 2.0, 3.0)
    (3.0, 1.5, 1.25)
    """
    return d / a, d / c, (a * a - b * b + c * c + d * d) / (2.0 * a * c)


def diagonal(a: float, d: float, theta):
    """Length f = |CA| = sqrt(a² + d² − 2 a d cos θ) of the diagonal from the output pivot to A.

    Examples
    --------
    >>> float(diagonal(3.0, 4.0, math.pi / 2))
    5.0
    """
    return np.sqrt(a * a + d * d - 2.0 * a * d * np.cos(theta))


def output_angle(a: float, b: float, c: float, d: float, theta, branch: int = 1):
    """Output angle β (rad) for input angle θ (rad) on assembly branch ``branch`` (±1); NaN where the
    loop cannot close.

    β = δ + σ γ with δ = atan2(a sin θ, a cos θ − d) the direction of C→A,
    cos γ = (c² + f² − b²)/(2 c f), f = |CA| (module docstring).

    Parameters
    ----------
    a, b, c, d : float
        Link lengths (crank, coupler, rocker, frame).
    theta : float or ndarray
        Input angle(s) θ from the frame line, rad.
    branch : {1, -1}
        Assembly branch σ: +1 puts B left of the directed diagonal C→A.

    Returns
    -------
    float or ndarray
        β in rad, in (−π, 3π); NaN where |cos γ| > 1.

    Examples
    --------
    A parallelogram (a = c, b = d) on its open branch keeps β = θ:

    >>> round(float(output_angle(1.0, 3.0, 1.0, 3.0, 0.7, branch=-1)), 12)
    0.7
    """
    theta = np.asarray(theta, dtype=float)
    ax, ay = a * np.cos(theta), a * np.sin(theta)
    f = np.hypot(ax - d, ay)
    delta = np.arctan2(ay, ax - d)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_gamma = (c * c + f * f - b * b) / (2.0 * c * f)
        gamma = np.where(np.abs(cos_gamma) <= 1.0, np.arccos(np.clip(cos_gamma, -1.0, 1.0)), np.nan)
    beta = delta + branch * gamma
    return beta if beta.ndim else float(beta)


def coupler_angle(a: float, b: float, c: float, d: float, theta, beta):
    """Coupler angle λ (rad) from the loop closure: b e^{iλ} = d + c e^{iβ} − a e^{iθ}.

    Examples
    --------
    >>> round(float(coupler_angle(1.0, 3.0, 1.0, 3.0, 0.7, 0.7)), 12)
    0.0
    """
    theta = np.asarray(theta, dtype=float)
    beta = np.asarray(beta, dtype=float)
    return np.arctan2(c * np.sin(beta) - a * np.sin(theta), d + c * np.cos(beta) - a * np.cos(theta))


def transmission_angle(a: float, b: float, c: float, d: float, theta):
    """Transmission angle μ (rad, 0…π) at input angle θ: cos μ = (b² + c² − f²)/(2bc); NaN where the
    loop cannot close.

    Examples
    --------
    A square four-bar (all links 1) at θ = 90°: f = √2, μ = 90°.

    >>> round(math.degrees(float(transmission_angle(1, 1, 1, 1, math.pi / 2))), 9)
    90.0
    """
    f2 = a * a + d * d - 2.0 * a * d * np.cos(np.asarray(theta, dtype=float))
    cos_mu = (b * b + c * c - f2) / (2.0 * b * c)
    with np.errstate(invalid="ignore"):
        mu = np.where(np.abs(cos_mu) <= 1.0, np.arccos(np.clip(cos_mu, -1.0, 1.0)), np.nan)
    return mu if mu.ndim else float(mu)


def worst_transmission_angle(a: float, b: float, c: float, d: float, theta_start: float, theta_end: float) -> float:
    """Smallest min(μ, π − μ) (rad) over the input interval [θ_start, θ_end] (rad), in closed form.

    |cos μ| is monotone in the diagonal f, and f² = a² + d² − 2ad cos θ is extreme at the interval's
    ends and at θ ≡ 0 and θ ≡ π (crank along the frame line), so the worst value is found among at
    most four angles. NaN if the loop cannot close somewhere in the interval.

    Examples
    --------
    Crank-rocker a=1, b=3, c=2.5, d=3 over a full turn: the extremes are at θ = 0 and π,
    cos μ = (b² + c² − (d ∓ a)²)/(2bc).

    >>> ref = min(math.acos((9 + 6.25 - 4) / 15), math.pi - math.acos((9 + 6.25 - 16) / 15))
    >>> abs(worst_transmission_angle(1, 3, 2.5, 3, 0.0, 2 * math.pi) - ref) < 1e-12
    True
    """
    lo, hi = min(theta_start, theta_end), max(theta_start, theta_end)
    angles = [lo, hi]
    for base in (0.0, math.pi):
        k = math.ceil((lo - base) / (2 * math.pi))
        while base + 2 * math.pi * k <= hi:
            angles.append(base + 2 * math.pi * k)
            k += 1
    worst = math.pi
    for theta in angles:
        cos_mu = (b * b + c * c - (a * a + d * d - 2.0 * a * d * math.cos(theta))) / (2.0 * b * c)
        if not -1.0 <= cos_mu <= 1.0:
            return float("nan")
        mu = math.acos(cos_mu)
        worst = min(worst, mu, math.pi - mu)
    return worst


def output_derivatives(a: float, b: float, c: float, d: float, theta, branch: int = 1):
    """Exact first and second derivatives of the output angle: (β, β', β'') with ' = d/dθ.

    Differentiating the loop closure a e^{iθ} + b e^{iλ} = d + c e^{iβ} once and taking the part
    normal to the coupler:

        β' = a sin(θ − λ) / (c sin(β − λ)),   λ' = a sin(θ − β) / (b sin(β − λ)),

    and once more (normal to the coupler again):

        β'' = [a cos(θ − λ) + b λ'² − c β'² cos(β − λ)] / (c sin(β − λ)).

    Both blow up at a dead point (sin(β − λ) = 0).

    Examples
    --------
    A parallelogram has β = θ, so β' = 1 and β'' = 0:

    >>> beta, d1, d2 = output_derivatives(1.0, 3.0, 1.0, 3.0, 0.4, branch=-1)
    >>> round(float(d1), 12), abs(round(float(d2), 12))
    (1.0, 0.0)
    """
    theta = np.asarray(theta, dtype=float)
    beta = output_angle(a, b, c, d, theta, branch)
    lam = coupler_angle(a, b, c, d, theta, beta)
    s = np.sin(beta - lam)
    with np.errstate(divide="ignore", invalid="ignore"):  # inf/nan at a dead point, as documented: no warning
        d_beta = a * np.sin(theta - lam) / (c * s)
        d_lam = a * np.sin(theta - beta) / (b * s)
        dd_beta = (a * np.cos(theta - lam) + b * d_lam ** 2 - c * d_beta ** 2 * np.cos(beta - lam)) / (c * s)
    return beta, d_beta, dd_beta


def joints(a: float, b: float, c: float, d: float, theta, branch: int = 1) -> dict[str, np.ndarray]:
    """Joint positions O, A, B, C (each (N, 2), or (2,) for a scalar θ) in the frame of the module
    docstring (O at the origin, C on +x); lengths in the links' unit.

    Examples
    --------
    >>> j = joints(1.0, 3.0, 1.0, 3.0, math.pi / 2, branch=-1)
    >>> [round(float(v), 12) for v in j["B"]]
    [3.0, 1.0]
    """
    theta = np.asarray(theta, dtype=float)
    beta = output_angle(a, b, c, d, theta, branch)
    zero = np.zeros_like(theta)
    return {"O": np.stack([zero, zero], axis=-1),
            "A": np.stack([a * np.cos(theta), a * np.sin(theta)], axis=-1),
            "B": np.stack([d + c * np.cos(beta), c * np.sin(beta)], axis=-1),
            "C": np.stack([zero + d, zero], axis=-1)}


def branch_of(a: float, d: float, theta: float, b_point) -> int:
    """Assembly branch σ (±1) of the configuration with input angle θ and joint B at ``b_point``:
    the sign of the cross product (A − C) × (B − C) (+1: B left of the directed diagonal C→A).

    Examples
    --------
    >>> branch_of(1.0, 3.0, 0.5, (3.2, -2.0)), branch_of(1.0, 3.0, 0.5, (3.2, 2.0))
    (1, -1)
    """
    ax, ay = a * math.cos(theta) - d, a * math.sin(theta)
    bx, by = b_point[0] - d, b_point[1]
    return 1 if ax * by - ay * bx > 0 else -1


@dataclass(frozen=True)
class GrashofClass:
    """Grashof classification: ``name``, the Grashof sum s + l − (p + q) (``margin``: < 0 Grashof,
    0 change point, > 0 non-Grashof) and whether the input and the output can turn fully."""

    name: str
    margin: float
    input_rotates: bool
    output_rotates: bool


def grashof(a: float, b: float, c: float, d: float, tol: float = 1e-12) -> GrashofClass:
    """Grashof class of a four-bar with crank a, coupler b, rocker c and frame d.

    With s the shortest and l the longest link and p, q the others, the linkage has a link that
    turns fully relative to the others when s + l ≤ p + q (Grashof 1883). Which one is the crank
    depends on where the shortest link is: on the frame → double crank; adjacent to the frame
    (a or c) → crank-rocker / rocker-crank; the coupler → double rocker. Otherwise (s + l > p + q)
    no link turns fully: triple rocker. Equality is a change-point linkage.

    Examples
    --------
    >>> grashof(1, 3, 2.5, 3).name
    'crank-rocker'
    >>> grashof(3, 1, 3, 2.5).name
    'double-rocker (Grashof)'
    >>> grashof(2, 2.5, 3, 4.5).name
    'triple-rocker (non-Grashof)'
    """
    links = {"a": a, "b": b, "c": c, "d": d}
    ordered = sorted(links.values())
    s, p, q, long = ordered
    margin = (s + long) - (p + q)
    scale = max(ordered)
    shortest = min(links, key=lambda k: (links[k], "dacb".index(k)))
    if margin > tol * scale:
        return GrashofClass("triple-rocker (non-Grashof)", margin, False, False)
    if abs(margin) <= tol * scale:
        return GrashofClass("change point (s+l = p+q)", margin, shortest in ("a", "d"), shortest in ("c", "d"))
    name = {"d": "double-crank", "a": "crank-rocker", "c": "rocker-crank", "b": "double-rocker (Grashof)"}[shortest]
    return GrashofClass(name, margin, shortest in ("a", "d"), shortest in ("c", "d"))
