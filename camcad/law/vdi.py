"""The VDI 2143 catalogue of motion laws: every transition between rest, constant velocity and reversal.

VDI 2143 Blatt 1 sorts the motion tasks of a cam by the state of the follower at each end of a
transition: R rest (v = 0, a = 0), G constant velocity (v ≠ 0, a = 0), U reversal (v = 0, a ≠ 0) and
B general motion (v ≠ 0, a ≠ 0). A law of the catalogue is a closed form that takes the position at both
ends and the values its class allows, and is written here in the cam angle θ (rad) as elementary pieces
of the acceleration (``camcad.law.pieces``), integrated exactly:

- ``poly3``, ``poly5``, ``poly7``: polynomials of degree 3, 5, 7 through the stated boundary values
  (s, v; s, v, a; s, v, a, j at both ends) — every class, R, G, U or B at either end.
- ``inclined_sine`` (the inclined sine line of Bestehorn, "geneigte Sinuslinie"; the cycloid for
  λ = 1/2), ``modified_sine``, ``modified_trapezoid`` and ``constant_acceleration`` (the quadratic
  parabola): the acceleration is a positive lobe on [0, λ] and a negative lobe on [λ, 1] of the
  normalised angle z = (θ − θ0)/β; λ, the inflection point of the displacement ("Wendepunkt", the
  law's parameter), defaults to 1/2. With the end velocities v0, v1 stated the two lobe amplitudes
  follow from two linear conditions (v(1) = v1, s(1) = s1), whose determinant is positive for every λ
  in (0, 1): R-R, R-G, G-R and G-G all solve.
- ``harmonic_combination``: the modified sine with the reversal end's ramp left out, so the
  acceleration stays at its extreme at the reversal: R-U and G-U (into a reversal), or U-R and U-G
  (out of one) when the segment starts where the previous one ends with a non-zero acceleration.
- ``harmonic`` (the simple sine line, "einfache Sinuslinie") and ``double_harmonic`` (R-U, or U-R out of
  a reversal), fixed shapes: the acceleration of ``harmonic`` jumps against a rest.

The lobes, in the lobe's own coordinate u ∈ [0, 1] with peak 1: inclined sine sin(πu); modified sine
sin(2πu) on [0, 1/4], cos(2π(u − 1/4)/3) on [1/4, 1]; modified trapezoid sin(2πu), 1, cos(2π(u − 3/4))
on [0, 1/4], [1/4, 3/4], [3/4, 1]; constant acceleration 1. The decelerating lobe is the accelerating
one read backwards. For λ = 1/2 and rest at both ends these are the classical laws, whose peak
coefficients C_v = max|f'|, C_a = max|f''|, C_j = max|f'''| (f the normalised rise) are published:
inclined sine 2, 2π, 4π²; modified sine 1.76, 5.53, 69.47; modified trapezoid 2, 4.8881, 61.43;
3-4-5 polynomial 1.875, 5.7735, 60 (tests/law/test_vdi.py lists each value with its source).

References
----------
VDI 2143 Blatt 1, Bewegungsgesetze für Kurvengetriebe — Theoretische Grundlagen (VDI, 1980): the motion
tasks R, G, U, B and the catalogue of laws with the inflection-point parameter.
R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3 (the laws' formulas and
peak coefficients).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from camcad.law.coefficients import PeakCoefficients
from camcad.law.pieces import AccelTerm, Piece, ShapePiece, integrate_pieces
from camcad.numerics import bounded_minimum, brent_root

PI = math.pi

# --------------------------------------------------------------------------------------------
# The lobes (u ∈ [0, 1], peak 1) and the lobe laws built from them
# --------------------------------------------------------------------------------------------

HALF_SINE = (AccelTerm(0.0, 1.0, trig=((1.0, PI, 0.0),)),)
MODIFIED_SINE_LOBE = (AccelTerm(0.0, 0.25, trig=((1.0, 2.0 * PI, 0.0),)),
                      AccelTerm(0.25, 1.0, trig=((1.0, 2.0 * PI / 3.0, PI / 2.0),)))
TRAPEZOID_LOBE = (AccelTerm(0.0, 0.25, trig=((1.0, 2.0 * PI, 0.0),)), AccelTerm(0.25, 0.75, poly=(1.0,)),
                  AccelTerm(0.75, 1.0, trig=((1.0, 2.0 * PI, PI / 2.0),)))
CONSTANT_LOBE = (AccelTerm(0.0, 1.0, poly=(1.0,)),)
#: the harmonic combination's lobe at a reversal: a quarter sine from 0 to its peak at the lobe's end
QUARTER_TO_PEAK = (AccelTerm(0.0, 1.0, trig=((1.0, PI / 2.0, 0.0),)),)

#: boundary values a law may take from its neighbour at its start, or have stated at its end
ORDERS = ("v", "a", "j")


@dataclass(frozen=True)
class Bounds:
    """The boundary values of one transition (mm, mm/rad, mm/rad², mm/rad³ at its start and end)."""

    s0: float
    s1: float
    v0: float = 0.0
    v1: float = 0.0
    a0: float = 0.0
    a1: float = 0.0
    j0: float = 0.0
    j1: float = 0.0


def _mirror(terms: tuple[AccelTerm, ...]) -> tuple[AccelTerm, ...]:
    return tuple(t.mirrored() for t in reversed(terms))


def _place(terms: tuple[AccelTerm, ...], origin: float, width: float, factor: float) -> list[AccelTerm]:
    return [t.mapped(origin, width).scaled(factor) for t in terms]


@dataclass(frozen=True)
class LobeLaw:
    """A law whose acceleration is a positive lobe on [0, λ] and a negative one on [λ, 1] of z (module docstring).

    ``rise_lobe`` and ``fall_lobe`` are the lobes (u ∈ [0, 1], peak 1); ``fall_lobe`` None reads the
    rise lobe backwards. ``reversal`` is "" for the R/G laws, "end" for the harmonic combination (its
    acceleration ends at its extreme) — a start out of a reversal mirrors it (``at_start_reversal``).
    """

    name: str
    rise_lobe: tuple[AccelTerm, ...]
    fall_lobe: tuple[AccelTerm, ...] | None = None
    reversal: str = ""
    classes: str = "R-R, R-G, G-R, G-G"
    parameter: str = "lambda"
    default: float = 0.5
    takes: frozenset = frozenset({"v"})
    stated: frozenset = frozenset({"v"})

    def lobes(self, start_reversal: bool) -> tuple[tuple[AccelTerm, ...], tuple[AccelTerm, ...]]:
        if self.reversal and start_reversal:          # out of a reversal: the end's lobe, read backwards
            return _mirror(QUARTER_TO_PEAK), _mirror(self.rise_lobe)
        fall = self.fall_lobe if self.fall_lobe is not None else _mirror(self.rise_lobe)
        return self.rise_lobe, fall

    def terms(self, theta0: float, width: float, bounds: Bounds, param: float | None,
              start_reversal: bool = False) -> list[AccelTerm]:
        lam = self.default if param is None else float(param)
        rise, fall = self.lobes(start_reversal)
        # unit responses of each lobe over the whole transition, from rest at s = 0
        first = [t.mapped(theta0, width) for t in (_place(rise, 0.0, lam, 1.0))]
        second = [t.mapped(theta0, width) for t in (_place(fall, lam, 1.0 - lam, -1.0))]
        zero_first = [t.scaled(0.0) for t in first]
        zero_second = [t.scaled(0.0) for t in second]
        s_a, v_a = integrate_pieces(first + zero_second)[-1].end_values()[:2]
        s_b, v_b = integrate_pieces(zero_first + second)[-1].end_values()[:2]
        # v0 + A v_a + B v_b = v1 ;  s0 + v0 β + A s_a + B s_b = s1
        matrix = np.array([[v_a, v_b], [s_a, s_b]])
        rhs = np.array([bounds.v1 - bounds.v0, bounds.s1 - bounds.s0 - bounds.v0 * width])
        amp_a, amp_b = np.linalg.solve(matrix, rhs)
        return [t.scaled(float(amp_a)) for t in first] + [t.scaled(float(amp_b)) for t in second]

    def build(self, theta0: float, width: float, bounds: Bounds, param: float | None = None,
              start_reversal: bool = False) -> tuple[Piece, ...]:
        """The law's pieces on [θ0, θ0 + width] (rad) through ``bounds`` (s0, s1, v0, v1)."""
        return integrate_pieces(self.terms(theta0, width, bounds, param, start_reversal), bounds.s0, bounds.v0)

    def demand(self, width: float, s0: float, s1: float, v0: float, param: float | None = None,
               start_reversal: bool = False) -> dict:
        """The start values the law sets itself (its start acceleration and jerk), given what it takes."""
        pieces = self.build(0.0, width, Bounds(s0, s1, v0, 0.0), param, start_reversal)
        _, _, a, j = pieces[0].start_values()
        return {"a": a, "j": j}

    def check_param(self, param: float | None) -> str | None:
        if param is None:
            return None
        if not (math.isfinite(param) and 0.0 < param < 1.0):
            return f"lambda = {param:g} is not an inflection point inside the segment (0 < lambda < 1)"
        return None


@dataclass(frozen=True)
class PolyLaw:
    """The polynomial of degree 3, 5 or 7 through s, v (, a (, j)) at both ends (every class)."""

    name: str
    degree: int
    classes: str = "every class (R, G, U, B at either end)"
    parameter: str = ""
    default: float | None = None

    @property
    def order(self) -> int:
        """How many derivatives are fixed at each end besides s: 1 (v), 2 (v, a) or 3 (v, a, j)."""
        return (self.degree - 1) // 2

    @property
    def takes(self) -> frozenset:
        return frozenset(ORDERS[: self.order])

    @property
    def stated(self) -> frozenset:
        return self.takes

    def coefficients(self, width: float, bounds: Bounds) -> np.ndarray:
        """c_k of s(z) = Σ c_k z^k, z = (θ − θ0)/width (mm)."""
        n = self.degree + 1
        k = self.order
        start = [bounds.s0, bounds.v0 * width, bounds.a0 * width**2, bounds.j0 * width**3][: k + 1]
        end = [bounds.s1, bounds.v1 * width, bounds.a1 * width**2, bounds.j1 * width**3][: k + 1]
        c = np.zeros(n)
        for i, value in enumerate(start):
            c[i] = value / math.factorial(i)
        # the end conditions on the remaining coefficients c_{k+1} .. c_degree
        rows, rhs = [], []
        for order, value in enumerate(end):
            row = [_falling(p, order) for p in range(k + 1, n)]
            known = sum(_falling(p, order) * c[p] for p in range(k + 1))
            rows.append(row)
            rhs.append(value - known)
        c[k + 1:] = np.linalg.solve(np.array(rows, dtype=float), np.array(rhs))
        return c

    def build(self, theta0: float, width: float, bounds: Bounds, param: float | None = None,
              start_reversal: bool = False) -> tuple[Piece, ...]:
        c = self.coefficients(width, bounds)
        # a(τ) = Σ k(k−1) c_k (τ/β)^(k−2) / β²: p_m = (m+2)(m+1) c_{m+2} / β^(m+2)
        poly = tuple(float((m + 2) * (m + 1) * c[m + 2] / width ** (m + 2)) for m in range(self.degree - 1))
        return (Piece(theta0, theta0 + width, float(c[0]), float(c[1] / width), poly),)

    def demand(self, width: float, s0: float, s1: float, v0: float, param: float | None = None,
               start_reversal: bool = False) -> dict:
        if self.degree == 3:   # the cubic takes only v: its start acceleration is its own
            pieces = self.build(0.0, width, Bounds(s0, s1, v0, 0.0))
            _, _, a, j = pieces[0].start_values()
            return {"a": a, "j": j}
        return {}

    def check_param(self, param: float | None) -> str | None:
        return None if param is None else f"{self.name} has no parameter"


def _falling(n: int, k: int) -> float:
    out = 1.0
    for i in range(k):
        out *= n - i
    return out


@dataclass(frozen=True)
class FixedLaw:
    """A rest-to-rest shape (or rest-to-reversal, ``reversal`` "end") scaled to the segment's rise: it takes
    nothing from its neighbours and sets every value itself.

    ``terms`` gives the normalised acceleration f''(z) as pieces (None: evaluate ``shape`` through
    ``ShapePiece``). A start out of a reversal reads the shape backwards (U-R).
    """

    name: str
    shape: object
    terms_z: tuple[AccelTerm, ...] | None = None
    reversal: str = ""
    classes: str = "R-R"
    parameter: str = ""
    default: float | None = None
    takes: frozenset = frozenset()
    stated: frozenset = frozenset()

    def build(self, theta0: float, width: float, bounds: Bounds, param: float | None = None,
              start_reversal: bool = False) -> tuple[Piece, ...]:
        lift = bounds.s1 - bounds.s0
        if self.terms_z is None:
            return (ShapePiece(theta0, theta0 + width, bounds.s0, lift, self.shape),)  # type: ignore[return-value]
        if self.reversal and start_reversal:    # out of a reversal: s = s1 − h f(1 − z), h = s1 − s0
            terms = [t.mapped(theta0, width).scaled(-lift / width**2) for t in _mirror(self.terms_z)]
            return integrate_pieces(terms, bounds.s0, 0.0)
        terms = [t.mapped(theta0, width).scaled(lift / width**2) for t in self.terms_z]
        return integrate_pieces(terms, bounds.s0, 0.0)

    def demand(self, width: float, s0: float, s1: float, v0: float, param: float | None = None,
               start_reversal: bool = False) -> dict:
        pieces = self.build(0.0, width, Bounds(s0, s1), None, start_reversal)
        _, v, a, j = pieces[0].start_values()
        return {"v": v, "a": a, "j": j}

    def check_param(self, param: float | None) -> str | None:
        return None if param is None else f"{self.name} has no parameter"


DOUBLE_HARMONIC_TERMS = (AccelTerm(0.0, 1.0, trig=((PI**2 / 2.0, PI, PI / 2.0), (-(PI**2) / 2.0, 2.0 * PI, PI / 2.0))),)
HARMONIC_TERMS = (AccelTerm(0.0, 1.0, trig=((PI**2 / 2.0, PI, PI / 2.0),)),)

#: name -> the catalogue law
CATALOGUE: dict[str, LobeLaw | PolyLaw | FixedLaw] = {
    "inclined_sine": LobeLaw("inclined_sine", HALF_SINE),
    "modified_sine": LobeLaw("modified_sine", MODIFIED_SINE_LOBE),
    "modified_trapezoid": LobeLaw("modified_trapezoid", TRAPEZOID_LOBE),
    "constant_acceleration": LobeLaw("constant_acceleration", CONSTANT_LOBE),
    "harmonic_combination": LobeLaw("harmonic_combination", MODIFIED_SINE_LOBE, QUARTER_TO_PEAK, reversal="end",
                                    classes="R-U, G-U; U-R, U-G out of a reversal"),
    "poly3": PolyLaw("poly3", 3),
    "poly5": PolyLaw("poly5", 5),
    "poly7": PolyLaw("poly7", 7),
    "harmonic": FixedLaw("harmonic", None, HARMONIC_TERMS),
    "double_harmonic": FixedLaw("double_harmonic", None, DOUBLE_HARMONIC_TERMS, reversal="end",
                                classes="R-U; U-R out of a reversal"),
}
#: other names a segment may use: the classical rest-to-rest names of ``camcad.law.standard``
ALIASES = {"cycloidal": "inclined_sine", "poly345": "poly5", "poly4567": "poly7"}


def catalogue_law(name: str):
    """The catalogue law called ``name`` (or an alias), or a KeyError listing the names."""
    key = ALIASES.get(name, name)
    try:
        return CATALOGUE[key]
    except KeyError:
        raise KeyError(f"unknown law {name!r}; the catalogue has {', '.join(sorted(CATALOGUE))}") from None


# --------------------------------------------------------------------------------------------
# The rest-to-rest member of a catalogue law as a normalised shape f(u) (for compose and the tables)
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CatalogueShape:
    """The rest-to-rest rise f(u), u ∈ [0, 1], f(0) = 0, f(1) = 1, of a catalogue law (``RiseShape``).

    ``param`` is the law's parameter (λ for the lobe laws; None: its default). The peaks are found
    exactly on each piece: the extremes of f^(k) where f^(k+1) changes sign (Brent's method to
    round-off) and at the pieces' ends.
    """

    law_name: str
    param: float | None = None

    @property
    def name(self) -> str:
        return self.law_name if self.param is None else f"{self.law_name}:{self.param:g}"

    @functools.cached_property
    def pieces(self) -> tuple:
        law = CATALOGUE[self.law_name]
        return law.build(0.0, 1.0, Bounds(0.0, 1.0), self.param)

    @functools.cached_property
    def _starts(self) -> np.ndarray:
        return np.array([p.start for p in self.pieces])

    def evaluate(self, u: np.ndarray, order: int) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        index = np.clip(np.searchsorted(self._starts, u, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty_like(u)
        for k in np.unique(index):
            inside = index == k
            out[inside] = self.pieces[int(k)].evaluate(u[inside], order)
        return out

    def breakpoints(self) -> tuple[float, ...]:
        return tuple(float(p.start) for p in self.pieces[1:])

    def peaks(self) -> PeakCoefficients:
        """C_v, C_a, C_j (dimensionless) and whether f'' jumps: inside, or against a rest at an end (a law into a
        reversal ends at a non-zero f'' by design: that end is not a jump)."""
        found = [_piece_peak(self.pieces, order) for order in (1, 2, 3)]
        ends = (0.0,) if _reversal(CATALOGUE[self.law_name]) else (0.0, 1.0)
        second_ends = [abs(float(self.evaluate(np.array([x]), 2)[0])) for x in ends]
        jumps = any(x > 1e-12 for x in second_ends) or _inner_jump(self.pieces, 2)
        return PeakCoefficients(found[0], found[1], found[2], jumps)


def _reversal(law) -> str:
    """The end of a law that is a reversal ("end"), or "" (the polynomials have none of their own)."""
    return str(getattr(law, "reversal", ""))


def _piece_peak(pieces, order: int, samples: int = 2049) -> float:
    """sup |f^(order)| over the pieces: the pieces' ends and every sign change of f^(order+1), by Brent."""
    best = 0.0
    for piece in pieces:
        ends = np.array([piece.start, piece.end])
        best = max(best, float(np.max(np.abs(piece.evaluate(ends, order)))))
        if order == 3:
            # f'''' is not offered: the jerk's extremes are where its sampled slope changes sign
            grid = np.linspace(piece.start, piece.end, samples)
            values = np.abs(piece.evaluate(grid, order))
            k = int(np.argmax(values))
            lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, samples - 1)]
            best = max(best, float(values[k]))
            if hi > lo:
                def jerk(t: float, p=piece) -> float:
                    return -abs(float(p.evaluate(np.array([t]), 3)[0]))

                _, value = bounded_minimum(jerk, float(lo), float(hi), xatol=1e-15)
                best = max(best, -value)
            continue
        grid = np.linspace(piece.start, piece.end, samples)
        slope = piece.evaluate(grid, order + 1)
        change = np.flatnonzero(np.sign(slope[1:]) != np.sign(slope[:-1]))
        for i in change:
            lo, hi = float(grid[i]), float(grid[i + 1])
            def slope_at(t: float, p=piece) -> float:
                return float(p.evaluate(np.array([t]), order + 1)[0])

            try:
                root = brent_root(slope_at, lo, hi, xtol=1e-16, rtol=4 * np.finfo(float).eps)
            except ValueError:
                root = lo
            best = max(best, abs(float(piece.evaluate(np.array([root]), order)[0])))
    return best


def _inner_jump(pieces, order: int) -> bool:
    for before, after in pairwise(pieces):
        left = before.end_values()[order]
        right = after.start_values()[order]
        if abs(left - right) > 1e-9 * (1.0 + abs(left)):
            return True
    return False


def catalogue_rest_shape(name: str) -> CatalogueShape | None:
    """The rest-to-rest shape a name such as "inclined_sine", "poly7" or "modified_sine:0.4" (law:λ) stands
    for, or None when the name is not one of the catalogue's (``camcad.law.standard.shape_named`` asks)."""
    head, sep, tail = name.partition(":")
    key = ALIASES.get(head, head)
    if key not in CATALOGUE:
        return None
    param = None
    if sep:
        try:
            param = float(tail)
        except ValueError:
            raise KeyError(f"bad parameter in {name!r}; write {head}:lambda with 0 < lambda < 1") from None
    return rest_shape(key, param)


def rest_shape(name: str, param: float | None = None) -> CatalogueShape:
    """The rest-to-rest member of a catalogue law as a shape f(u) for ``camcad.compose``.

    Parameters
    ----------
    name : str
        A catalogue law with a rest-to-rest member: inclined_sine, modified_sine, modified_trapezoid,
        constant_acceleration, poly3, poly5, poly7.
    param : float, optional
        Its parameter: the inflection point λ of a lobe law (a fraction of the rise, 0 < λ < 1).

    Returns
    -------
    CatalogueShape
        f(u) with f(0) = 0, f(1) = 1 (dimensionless) and its peak coefficients.

    References
    ----------
    VDI 2143 Blatt 1 (1980); R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3.

    Examples
    --------
    The inclined sine with λ = 1/2 is the cycloid: C_v = 2, C_a = 2π, C_j = 4π² (Norton 2009, eq. 3.8):

    >>> import math
    >>> peaks = rest_shape("inclined_sine").peaks()
    >>> round(peaks.cv, 12), round(peaks.ca / math.pi, 12), round(peaks.cj / math.pi**2, 9)
    (2.0, 2.0, 4.0)
    """
    key = ALIASES.get(name, name)
    law = CATALOGUE.get(key)
    if law is None or _reversal(law):
        raise KeyError(f"{name!r} has no rest-to-rest member in the catalogue (it ends in a reversal); use it in "
                       "segments")
    problem = law.check_param(param)
    if problem:
        raise KeyError(problem)
    return CatalogueShape(key, param)


def catalogue_table() -> list[dict]:
    """The catalogue: one row per law with its motion classes and coefficients.

    Returns
    -------
    list of dict
        ``name``, ``classes`` (the VDI 2143 motion tasks it solves), ``parameter``, ``takes`` and ``states``
        (the start values it takes from the previous segment and the end values it may state), ``member``
        ("R-R", or "R-U" for a law into a reversal), and that member's peak coefficients ``cv``, ``ca``, ``cj``
        (dimensionless; ``cj`` None where the acceleration jumps), ``acceleration_jumps``.

    References
    ----------
    VDI 2143 Blatt 1 (1980); R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 3.

    Examples
    --------
    >>> row = next(r for r in catalogue_table() if r["name"] == "modified_sine")
    >>> row["classes"], round(row["cv"], 4), round(row["ca"], 4), round(row["cj"], 3)
    ('R-R, R-G, G-R, G-G', 1.7596, 5.528, 69.466)
    """
    rows = []
    for name, law in CATALOGUE.items():
        row: dict = {"name": name, "classes": law.classes, "parameter": law.parameter or None,
                     "takes": sorted(law.takes), "states": sorted(law.stated)}
        peaks = CatalogueShape(name).peaks()
        row.update({"member": "R-U" if _reversal(law) else "R-R", "cv": peaks.cv, "ca": peaks.ca,
                    "cj": None if peaks.acceleration_jumps else peaks.cj,
                    "acceleration_jumps": peaks.acceleration_jumps})
        rows.append(row)
    return rows
