"""Closed-form standard motion laws, and full cycles composed of them with dwells.

A rise shape is a normalised function f(u), u ∈ [0, 1], f(0) = 0, f(1) = 1, with
derivatives f', f'', f''' (per unit of u). A rise of lift h over the angle β gives
    s = h f(u),  v = h f'(u)/β,  a = h f''(u)/β²,  j = h f'''(u)/β³,   u = (θ − θ0)/β,
and a return of the same shape s = h (1 − f(u)). Peak coefficients Cv = max f',
Ca = max f'', Cj = max |f'''| are the dimensionless figures of every textbook table.
Cj is taken over the smooth pieces of a shape; ``PeakCoefficients.acceleration_jumps``
says whether f'' jumps inside the rise or against a dwell at its ends (the jerk then has
a Dirac part, which Norton's tables list as Cj = ∞).

Shapes: cycloidal, simple harmonic, the 3-4-5 and 4-5-6-7 polynomials, and Norton's
sine–constant–cosine–acceleration (SCCA) family, whose members include the modified
trapezoid, the modified sine and constant acceleration (cycloidal and harmonic too).

Source: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3;
H. A. Rothbart, Cam Design Handbook (2004), ch. 4.
"""

from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from camcad.arrays import present
from camcad.law.coefficients import PeakCoefficients
from camcad.law.law import Kinematics, Phase, wrap, wrap_angle
from camcad.law.vdi import catalogue_rest_shape


class RiseShape(Protocol):
    """A normalised rise f(u) on u ∈ [0, 1] with f(0) = 0 and f(1) = 1."""

    @property
    def name(self) -> str: ...

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        """f (order 0), f' (1), f'' (2) or f''' (3) at u ∈ [0, 1]."""
        ...


def peak_coefficients(shape: RiseShape) -> PeakCoefficients:
    """Closed-form peak coefficients of ``shape`` (every shape of this module has them)."""
    peaks = getattr(shape, "peaks", None)
    if peaks is None:
        raise TypeError(f"shape {getattr(shape, 'name', shape)!r} does not expose peak coefficients")
    return peaks()


@dataclass(frozen=True)
class Cycloidal:
    """f = u − sin(2πu)/(2π); Cv = 2, Ca = 2π, Cj = 4π². Norton (2009) eq. 3.8."""

    name: str = "cycloidal"

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        w = 2.0 * np.pi
        if order == 0:
            return u - np.sin(w * u) / w
        if order == 1:
            return 1.0 - np.cos(w * u)
        if order == 2:
            return w * np.sin(w * u)
        if order >= 3:   # f^(k) = w^(k-1) sin(w u + (k - 2) π/2), k ≥ 2
            return w ** (order - 1) * np.sin(w * u + (order - 2) * np.pi / 2)
        raise ValueError(f"order must be >= 0, got {order}")

    def peaks(self) -> PeakCoefficients:
        """f' peaks at u = 1/2, f'' at u = 1/4, |f'''| at u = 0 and 1."""
        return PeakCoefficients(2.0, 2.0 * math.pi, 4.0 * math.pi**2, False)


@dataclass(frozen=True)
class SimpleHarmonic:
    """f = (1 − cos πu)/2; Cv = π/2, Ca = π²/2, Cj = π³/2. Norton (2009) eq. 3.5."""

    name: str = "harmonic"

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        p = np.pi
        if order == 0:
            return (1.0 - np.cos(p * u)) / 2.0
        if order == 1:
            return p * np.sin(p * u) / 2.0
        if order == 2:
            return p**2 * np.cos(p * u) / 2.0
        if order >= 3:   # f^(k) = −(π^k/2) cos(π u + k π/2), k ≥ 1
            return -(p**order) * np.cos(p * u + order * np.pi / 2) / 2.0
        raise ValueError(f"order must be >= 0, got {order}")

    def peaks(self) -> PeakCoefficients:
        """f' peaks at u = 1/2, f'' at the ends (a jump from a dwell's 0), |f'''| at u = 1/2."""
        p = math.pi
        return PeakCoefficients(p / 2.0, p**2 / 2.0, p**3 / 2.0, True)


@dataclass(frozen=True)
class Polynomial:
    """f = Σ c_k u^k, e.g. 3-4-5: 10u³ − 15u⁴ + 6u⁵ (Cv = 1.875, Ca = 5.7735, Cj = 60). Norton (2009) §3.9."""

    name: str
    coefficients: tuple[float, ...]  # c_0, c_1, … (powers of u)

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        if order >= len(self._derivatives):
            return np.zeros_like(u, dtype=float)
        coefficients = self._derivatives[order]
        out = np.full_like(u, coefficients[-1], dtype=float)
        for c in reversed(coefficients[:-1]):  # Horner's rule, highest power first
            out *= u
            out += c
        return out

    @functools.cached_property
    def _derivatives(self) -> tuple[tuple[float, ...], ...]:
        """Coefficients of f and its derivatives up to the sixth (computed once): d/du Σ c_k u^k = Σ k c_k u^(k−1)."""
        out = [tuple(float(c) for c in self.coefficients)]
        for _ in range(max(6, len(self.coefficients))):   # every non-zero derivative, at least to the sixth
            previous = out[-1]
            out.append(tuple(k * previous[k] for k in range(1, len(previous))) or (0.0,))
        return tuple(out)

    def peaks(self) -> PeakCoefficients:
        """sup |f^(k)|, k = 1..3, taken at the real roots of f^(k+1) in [0, 1] and at the ends.

        Algebraic, so exact to round-off. By hand: 3-4-5 gives Cv = 15/8, Ca = 10/√3 (at
        u = 1/2 − √3/6), Cj = 60; 4-5-6-7 gives Cv = 35/16, Ca = 84√5/25 (at u = 1/2 − 1/√20),
        Cj = 105/2.
        """
        poly = np.polynomial.Polynomial(self.coefficients)
        found = []
        for order in (1, 2, 3):
            candidates = [0.0, 1.0]
            for root in poly.deriv(order + 1).roots():
                # numpy types the roots as object_ as well: they are float or complex
                if abs(root.imag) < 1e-12 and -1e-12 <= root.real <= 1.0 + 1e-12:  # type: ignore[operator]
                    candidates.append(min(max(float(root.real), 0.0), 1.0))
            found.append(float(np.max(np.abs(poly.deriv(order)(np.array(candidates))))))
        second = poly.deriv(2)
        jumps = bool(abs(second(0.0)) > 1e-12 or abs(second(1.0)) > 1e-12)
        return PeakCoefficients(found[0], found[1], found[2], jumps)


POLY_345 = Polynomial("poly345", (0, 0, 0, 10, -15, 6))
POLY_4567 = Polynomial("poly4567", (0, 0, 0, 0, 35, -84, 70, -20))
#: 5-6-7-8-9: f^(k)(0) = f^(k)(1) = 0 for k = 1..4, a law of class C⁴ (the smoothstep polynomial of degree 9):
#: what a polydyne cam needs for a continuous acceleration (camcad.dynamics.polydyne)
POLY_56789 = Polynomial("poly56789", (0, 0, 0, 0, 0, 126, -420, 540, -315, 70))


@dataclass(frozen=True)
class SCCA:
    """Norton's sine–constant–cosine–acceleration rise; b + c + d = 1, each ≥ 0.

    Over the first half of the rise the acceleration f'' is a quarter sine rising to Ca on
    u ∈ [0, b/2], the constant Ca on [b/2, (b + c)/2] and a quarter cosine falling to 0 on
    [(b + c)/2, 1/2]; the second half is its negative mirror, f''(1 − u) = −f''(u), hence
    f(1 − u) = 1 − f(u). Integrating the pieces and requiring f(1/2) = 1/2 gives

        Ca = 4π² / ((π² − 8)(b² − d²) − 2π(π − 2) b + π²)
        Cv = Ca (b/π + c/2 + d/π)                     (f' at u = 1/2)
        Cj = Ca π / min(b, d) over the non-zero ones   (0 when b = d = 0)

    Members: modified trapezoid b = d = 0.25, c = 0.5; modified sine b = 0.25, c = 0,
    d = 0.75; cycloidal b = d = 0.5; simple harmonic d = 1; constant acceleration
    (parabolic) c = 1. f'' is continuous across dwell–rise–dwell exactly when b > 0 and d > 0.

    Source: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), §3.10
    (eqs. 3.27–3.28, table 3-2).
    """

    b: float
    c: float
    d: float
    name: str = "scca"

    def __post_init__(self) -> None:
        parts = (self.b, self.c, self.d)
        if not all(math.isfinite(x) and x >= 0.0 for x in parts):
            raise ValueError(f"SCCA factors must be finite and >= 0, got b={self.b}, c={self.c}, d={self.d}")
        if abs(sum(parts) - 1.0) > 1e-12:
            raise ValueError(f"SCCA factors must add up to 1, got b + c + d = {sum(parts)!r}")
        for label, width in (("b", self.b), ("d", self.d)):
            # a narrower sine or cosine piece is a jump in practice, and π/width would overflow
            if 0.0 < width < 1e-9:
                raise ValueError(f"SCCA factor {label} = {width!r} is too small; use 0 or at least 1e-9")

    @property
    def ca(self) -> float:
        """Peak acceleration coefficient, Norton (2009) eq. 3.28."""
        b, d, p = self.b, self.d, math.pi
        return 4.0 * p**2 / ((p**2 - 8.0) * (b**2 - d**2) - 2.0 * p * (p - 2.0) * b + p**2)

    def peaks(self) -> PeakCoefficients:
        ca = self.ca
        cv = ca * (self.b / math.pi + self.c / 2.0 + self.d / math.pi)
        smooth_widths = [w for w in (self.b, self.d) if w > 0.0]
        cj = ca * math.pi / min(smooth_widths) if smooth_widths else 0.0
        return PeakCoefficients(cv, ca, cj, not (self.b > 0.0 and self.d > 0.0))

    def breakpoints(self) -> tuple[float, ...]:
        """u in (0, 1) where the acceleration pieces meet (f'' or f''' is not smooth there)."""
        b, c = self.b, self.c
        points = {b / 2.0, (b + c) / 2.0, 0.5, 1.0 - (b + c) / 2.0, 1.0 - b / 2.0}
        return tuple(sorted(u for u in points if 0.0 < u < 1.0))

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        if order not in (0, 1, 2, 3):
            raise ValueError(f"order must be 0..3, got {order}")
        u = np.asarray(u, dtype=float)
        second_half = u > 0.5
        half = self._first_half(np.where(second_half, 1.0 - u, u), order)
        if order == 0:
            return np.where(second_half, 1.0 - half, half)
        if order == 2:
            return np.where(second_half, -half, half)
        return half  # f' and f''' are even about u = 1/2

    def _first_half(self, u: np.ndarray, order: int) -> np.ndarray:
        """f^(order) on u ∈ [0, 1/2], from the three integrated pieces of the class docstring."""
        b, c, d, ca, p = self.b, self.c, self.d, self.ca, math.pi
        u1, u2 = b / 2.0, (b + c) / 2.0
        # slope and value of f where the sine piece and the constant piece end
        v1, s1 = ca * b / p, ca * (b / p) * (b / 2.0 - b / p)
        v2, s2 = v1 + ca * c / 2.0, s1 + v1 * c / 2.0 + ca * c**2 / 8.0
        in_sine = u < u1
        in_cosine = (u >= u2) & (d > 0.0)
        flat = ~in_sine & ~in_cosine
        out = np.empty_like(u)
        if b > 0.0:
            t, w = u[in_sine], p / b
            out[in_sine] = (ca / w * (t - np.sin(w * t) / w), ca / w * (1.0 - np.cos(w * t)),
                            ca * np.sin(w * t), ca * w * np.cos(w * t))[order]
        t = u[flat] - u1
        out[flat] = (s1 + v1 * t + ca * t**2 / 2.0, v1 + ca * t, np.full_like(t, ca),
                     np.zeros_like(t))[order]
        if d > 0.0:
            t, w = u[in_cosine] - u2, p / d
            out[in_cosine] = (s2 + v2 * t + ca / w**2 * (1.0 - np.cos(w * t)),
                              v2 + ca / w * np.sin(w * t), ca * np.cos(w * t),
                              -ca * w * np.sin(w * t))[order]
        return out


MODIFIED_TRAPEZOID = SCCA(0.25, 0.5, 0.25, "modified_trapezoid")
MODIFIED_SINE = SCCA(0.25, 0.0, 0.75, "modified_sine")
CONSTANT_ACCELERATION = SCCA(0.0, 1.0, 0.0, "constant_acceleration")


def scca(b: float, c: float, d: float) -> SCCA:
    """The SCCA member with factors b, c, d (b + c + d = 1), named ``scca:b:c:d``."""
    return SCCA(b, c, d, f"scca:{b:g}:{c:g}:{d:g}")


@dataclass(frozen=True)
class Segment:
    """One phase of a composed cycle: a rise or return of ``lift`` mm with ``shape``, or a dwell."""

    kind: str          # "rise", "return" or "dwell"
    start: float       # rad
    end: float         # rad
    lift: float = 0.0  # mm (rise and return)
    shape: RiseShape | None = None


@dataclass(frozen=True)
class CompositeLaw:
    """A full cycle of standard rises, returns and dwells; exact s, v, a, j everywhere.

    Built with ``compose``. Displacement starts at 0 at θ = 0.
    """

    segments: tuple[Segment, ...]
    cycle: float

    @property
    def phases(self) -> tuple[Phase, ...]:
        return tuple(Phase(seg.kind, seg.start, seg.end) for seg in self.segments)

    @property
    def lift(self) -> float:
        return max(seg.lift for seg in self.segments)

    def breakpoints(self) -> np.ndarray:
        """θ (rad) where s, v, a or j may be non-smooth: segment ends and the pieces inside shapes."""
        points = {0.0, float(self.cycle)}
        for seg in self.segments:
            points.update((float(seg.start), float(seg.end)))
            inner = getattr(seg.shape, "breakpoints", None)
            if inner is not None:
                points.update(float(seg.start + u * (seg.end - seg.start)) for u in inner())
        return np.array(sorted(points))

    def describe(self) -> str:
        """One ASCII line, e.g. "rise cycloidal 0-120, dwell 120-180, return poly345 180-300" (deg)."""
        parts = []
        for seg in self.segments:
            shape = f" {seg.shape.name}" if seg.shape is not None else ""
            parts.append(f"{seg.kind}{shape} {np.degrees(seg.start):.6g}-{np.degrees(seg.end):.6g}")
        return ", ".join(parts)

    def kinematics(self, theta) -> Kinematics:
        theta = np.asarray(theta, dtype=float)
        t = wrap(theta, self.cycle)
        s = np.zeros_like(t)
        v = np.zeros_like(t)
        a = np.zeros_like(t)
        j = np.zeros_like(t)
        # each θ belongs to one segment, [start, end) (the last one closed at the cycle's end); a
        # zero-width segment holds no θ
        index = np.clip(np.searchsorted(self._starts, t, side="right") - 1, 0, len(self.segments) - 1)
        for k in present(index, len(self.segments)):
            seg = self.segments[k]
            inside = index == k
            level = self._levels[k]
            if seg.kind == "dwell":
                s[inside] = level
                continue
            beta = seg.end - seg.start
            u = np.clip((t[inside] - seg.start) / beta, 0.0, 1.0)
            h = seg.lift if seg.kind == "rise" else -seg.lift
            s[inside] = level + h * seg.shape.evaluate(u, 0)
            v[inside] = h * seg.shape.evaluate(u, 1) / beta
            a[inside] = h * seg.shape.evaluate(u, 2) / beta**2
            j[inside] = h * seg.shape.evaluate(u, 3) / beta**3
        return Kinematics(theta=theta, s=s, v=v, a=a, j=j)

    def motion(self, theta) -> tuple[np.ndarray, np.ndarray]:
        """(s, v) at θ (rad): ``kinematics``' s and v (the same arithmetic) without a and j, for callers that need
        positions and tangents only (placing chords)."""
        theta = np.asarray(theta, dtype=float)
        t = wrap(theta, self.cycle)
        s = np.zeros_like(t)
        v = np.zeros_like(t)
        index = np.clip(np.searchsorted(self._starts, t, side="right") - 1, 0, len(self.segments) - 1)
        for k in present(index, len(self.segments)):
            seg = self.segments[k]
            inside = index == k
            level = self._levels[k]
            if seg.kind == "dwell":
                s[inside] = level
                continue
            beta = seg.end - seg.start
            u = np.clip((t[inside] - seg.start) / beta, 0.0, 1.0)
            h = seg.lift if seg.kind == "rise" else -seg.lift
            s[inside] = level + h * seg.shape.evaluate(u, 0)
            v[inside] = h * seg.shape.evaluate(u, 1) / beta
        return s, v

    def derivative(self, theta, order: int) -> np.ndarray:
        """d^k s/dθ^k (mm/rad^k) of order k ≥ 0 at θ (rad), each segment's shape differentiated exactly (a shape
        without that order raises ValueError); order 0 is s itself."""
        theta = np.asarray(theta, dtype=float)
        if order == 0:
            return self.kinematics(theta).s
        t = wrap(theta, self.cycle)
        out = np.zeros_like(t)
        index = np.clip(np.searchsorted(self._starts, t, side="right") - 1, 0, len(self.segments) - 1)
        for k in present(index, len(self.segments)):
            seg = self.segments[k]
            if seg.kind == "dwell":
                continue
            inside = index == k
            beta = seg.end - seg.start
            u = np.clip((t[inside] - seg.start) / beta, 0.0, 1.0)
            h = seg.lift if seg.kind == "rise" else -seg.lift
            out[inside] = h * seg.shape.evaluate(u, order) / beta**order
        return out

    def _at(self, theta: float):
        """Segment index, segment, u ∈ [0, 1] (a 1-element array), width β and signed lift h at one cam
        angle θ (rad): ``kinematics``'s lookup without array overhead (u and h are None in a dwell)."""
        t = wrap_angle(float(theta), self.cycle)
        k = min(max(bisect.bisect_right(self._starts_list, t) - 1, 0), len(self.segments) - 1)
        seg = self.segments[k]
        beta = seg.end - seg.start
        if seg.kind == "dwell":
            return k, seg, None, beta, None
        u = np.array([min(max((t - seg.start) / beta, 0.0), 1.0)])
        return k, seg, u, beta, seg.lift if seg.kind == "rise" else -seg.lift

    def acceleration_at(self, theta: float) -> float:
        """a(θ) (mm/rad²) at one cam angle θ (rad), without array overhead (ODE right-hand sides call it
        at every step); equal to ``kinematics(np.array([theta])).a[0]``."""
        _, seg, u, beta, h = self._at(theta)
        if u is None:
            return 0.0
        return float(h * seg.shape.evaluate(u, 2)[0] / beta**2)

    def motion_at(self, theta: float) -> tuple[float, float]:
        """(s, v) (mm, mm/rad) at one cam angle θ (rad), without array overhead (ODE right-hand sides call it
        at every step); equal to ``kinematics(np.array([theta]))``'s s[0] and v[0]."""
        k, seg, u, beta, h = self._at(theta)
        level = float(self._levels[k])
        if u is None:
            return level, 0.0
        return float(level + h * seg.shape.evaluate(u, 0)[0]), float(h * seg.shape.evaluate(u, 1)[0] / beta)

    @functools.cached_property
    def _starts_list(self) -> list[float]:
        return [float(seg.start) for seg in self.segments]

    @functools.cached_property
    def _starts(self) -> np.ndarray:
        """Start of each segment (rad)."""
        return np.array([seg.start for seg in self.segments])

    @functools.cached_property
    def _levels(self) -> tuple[float, ...]:
        """Displacement at the start of each segment (mm)."""
        levels, level = [], 0.0
        for seg in self.segments:
            levels.append(level)
            if seg.kind != "dwell":
                level += seg.lift if seg.kind == "rise" else -seg.lift
        return tuple(levels)


SHAPES: dict[str, RiseShape] = {
    "cycloidal": Cycloidal(),
    "harmonic": SimpleHarmonic(),
    "poly345": POLY_345,
    "poly4567": POLY_4567,
    "poly56789": POLY_56789,
    "modified_trapezoid": MODIFIED_TRAPEZOID,
    "modified_sine": MODIFIED_SINE,
    "constant_acceleration": CONSTANT_ACCELERATION,
}


def shape_named(name: str) -> RiseShape:
    """A shape by name: one of ``SHAPES``, an SCCA member written ``scca:b:c:d`` (b + c + d = 1), or the
    rest-to-rest member of a VDI 2143 catalogue law (``camcad.law.vdi``): inclined_sine, poly3, poly5,
    poly7, and inclined_sine:λ, modified_sine:λ, modified_trapezoid:λ, constant_acceleration:λ with the
    inflection point λ (0 < λ < 1)."""
    try:
        return SHAPES[name]
    except KeyError:
        pass
    if name.startswith("scca:"):
        try:
            b, c, d = (float(part) for part in name[5:].split(":"))
            return scca(b, c, d)
        except ValueError as err:
            raise KeyError(f"bad SCCA law {name!r} ({err}); write scca:b:c:d with b + c + d = 1") from None
    catalogue = catalogue_rest_shape(name)
    if catalogue is not None:
        return catalogue
    raise KeyError(f"unknown law {name!r}; known: {', '.join(sorted(SHAPES))}, inclined_sine, poly3, poly5, poly7, "
                   "scca:b:c:d, and LAW:lambda for the lobe laws") from None


def shape_names() -> tuple[str, ...]:
    """Every rest-to-rest shape name ``shape_named`` takes (scca:b:c:d and law:λ stand for families)."""
    return (*sorted(SHAPES), "inclined_sine", "poly3", "poly5", "poly7", "scca:b:c:d", "inclined_sine:λ",
            "modified_sine:λ", "modified_trapezoid:λ", "constant_acceleration:λ")


def compose(phases_deg: list[tuple[str, float]] | tuple[tuple[str, float], ...], lift: float,
            shape: str | RiseShape = "cycloidal", return_shape: str | RiseShape | None = None,
            cycle_deg: float = 360.0) -> CompositeLaw:
    """A full cycle of standard rises, returns and dwells, from (kind, width in deg) pairs.

    Rises use ``shape``, returns ``return_shape`` (default: the same). Widths must add up to ``cycle_deg``.
    Every rise and return has the same ``lift`` (mm), so the cycle closes. A rise of lift h over the
    angle β with the normalised shape f(u), u = (θ − θ0)/β, has s = h f, v = h f′/β, a = h f″/β²,
    j = h f‴/β³ (mm, mm/rad, mm/rad², mm/rad³); a return is s = h (1 − f).

    Parameters
    ----------
    phases_deg : sequence of (str, float)
        The phases in order, e.g. ``[("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)]``:
        kind "rise", "return" or "dwell" and width in deg. As many returns as rises.
    lift : float
        The lift h of every rise and return, mm (or rad of swing for an oscillating follower's law).
    shape : str or RiseShape
        The rises' shape: "cycloidal", "harmonic", "poly345", "poly4567", "modified_trapezoid",
        "modified_sine", "constant_acceleration", or a member of Norton's SCCA family written
        "scca:b:c:d" (b + c + d = 1, dimensionless fractions of the rise).
    return_shape : str or RiseShape, optional
        The returns' shape; None: the same as ``shape``.
    cycle_deg : float
        The cycle the widths add up to, deg (360 for one lobe per turn).

    Returns
    -------
    CompositeLaw
        A ``MotionLaw``: ``kinematics(theta)`` takes θ in rad and gives s (mm), v (mm/rad),
        a (mm/rad²), j (mm/rad³); ``camcad.kinematics_deg`` takes deg. ``phases`` and ``cycle`` in rad.

    Raises
    ------
    ValueError
        Widths that do not add up to the cycle, unequal numbers of rises and returns, an unknown kind.
    KeyError
        An unknown shape name.

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3 (the shapes, their peak
    coefficients, the SCCA family: eqs. 3.27–3.28 and table 3-2).
    H. A. Rothbart, Cam Design Handbook (2004), ch. 4.

    Examples
    --------
    A cycloidal rise of h = 20 mm over β = 90°: Norton's peak coefficients are Cv = 2 and Ca = 2π,
    i.e. v_max = 2h/β and a_max = 2πh/β² (β in rad):

    >>> import math
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0, "cycloidal")
    >>> k = camcad.kinematics_deg(law, np.linspace(0.0, 90.0, 9001))
    >>> beta = math.radians(90.0)
    >>> round(float(k.v.max()) * beta / 20.0, 9), round(float(k.a.max()) * beta**2 / 20.0 / math.pi, 6)
    (2.0, 2.0)
    >>> law.describe()
    'rise cycloidal 0-90, dwell 90-180, return cycloidal 180-270, dwell 270-360'

    The modified trapezoid (SCCA b = d = 0.25, c = 0.5) has Ca = 4.8881 (Norton, table 3-2):

    >>> law = camcad.compose([("rise", 180), ("return", 180)], 1.0, "modified_trapezoid")
    >>> a = camcad.kinematics_deg(law, np.linspace(0.0, 180.0, 18001)).a
    >>> round(float(a.max()) * math.pi**2, 4)
    4.8881
    """
    rise_shape = shape_named(shape) if isinstance(shape, str) else shape
    if return_shape is None:
        back_shape = rise_shape
    else:
        back_shape = shape_named(return_shape) if isinstance(return_shape, str) else return_shape
    total = sum(width for _, width in phases_deg)
    if abs(total - cycle_deg) > 1e-9 * cycle_deg:
        raise ValueError(f"phase widths add up to {total} deg, not the cycle {cycle_deg} deg")
    rises = sum(1 for kind, _ in phases_deg if kind == "rise")
    returns = sum(1 for kind, _ in phases_deg if kind == "return")
    if rises != returns:
        raise ValueError("a composed cycle needs as many returns as rises to close")
    segments = []
    start = 0.0
    for kind, width in phases_deg:
        end = start + np.radians(width)
        if kind == "dwell":
            segments.append(Segment("dwell", start, end))
        elif kind in ("rise", "return"):
            segments.append(Segment(kind, start, end, lift,
                                    rise_shape if kind == "rise" else back_shape))
        else:
            raise ValueError(f"phase kind must be rise, return or dwell, not {kind!r}")
        start = end
    return CompositeLaw(tuple(segments), float(np.radians(cycle_deg)))
