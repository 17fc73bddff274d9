"""Elementary pieces of a motion law: polynomial and sine terms of the acceleration, integrated exactly.

On a piece [start, end] (rad) the acceleration analog is

    a(τ) = Σ_m p_m τ^m + Σ_k A_k sin(ω_k τ + φ_k),      τ = θ − start,

and v, s follow by exact integration from the values v0, s0 at the piece's start:

    v(τ) = v0 + Σ_m p_m τ^(m+1)/(m+1) + Σ_k (A_k/ω_k)(cos φ_k − cos(ω_k τ + φ_k))
    s(τ) = s0 + v0 τ + Σ_m p_m τ^(m+2)/((m+1)(m+2))
              + Σ_k [(A_k/ω_k) cos φ_k · τ − (A_k/ω_k²)(sin(ω_k τ + φ_k) − sin φ_k)]
    j(τ) = Σ_m m p_m τ^(m−1) + Σ_k A_k ω_k cos(ω_k τ + φ_k).

Every law of the VDI 2143 catalogue (camcad.law.vdi) is a chain of such pieces: the polynomials, the
inclined sine, the modified sine and trapezoid, the harmonic laws. A chain is built from its
accelerations alone (``integrate_pieces``): each piece starts where the previous one ends, so s and v
are continuous by construction and the values at every joint are exact to round-off.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Piece:
    """One piece of a law on [start, end] (rad): a = Σ p_m τ^m + Σ A_k sin(ω_k τ + φ_k), τ = θ − start.

    ``poly`` holds p_0, p_1, … (mm/rad^(2+m)); ``trig`` holds the triples (A_k in mm/rad², ω_k in 1/rad,
    φ_k in rad); ``s0`` (mm) and ``v0`` (mm/rad) are the displacement and velocity at ``start``.
    """

    start: float
    end: float
    s0: float
    v0: float
    poly: tuple[float, ...] = ()
    trig: tuple[tuple[float, float, float], ...] = ()

    @property
    def width(self) -> float:
        return self.end - self.start

    def evaluate(self, theta, order: int) -> np.ndarray:
        """s (order 0), v (1), a (2) or j (3) at θ (rad, inside the piece; extrapolated outside)."""
        tau = np.asarray(theta, dtype=float) - self.start
        return self.evaluate_tau(tau, order)

    def evaluate_tau(self, tau, order: int) -> np.ndarray:
        """The same at τ = θ − start (τ may be complex: the formulas are analytic)."""
        tau = np.asarray(tau)
        out = np.zeros_like(tau, dtype=np.result_type(tau, float))
        if order == 0:
            out = out + self.s0 + self.v0 * tau
        elif order == 1:
            out = out + self.v0
        elif order not in (2, 3):
            raise ValueError(f"order must be 0..3, got {order}")
        for m, p in enumerate(self.poly):
            if p == 0.0:
                continue
            power = m + 2 - order   # the power of τ in the order-th derivative of p τ^(m+2)/((m+1)(m+2))
            if power < 0:
                continue
            factor = _falling(m + 2, order) / ((m + 1) * (m + 2))
            out = out + p * factor * tau**power
        for amp, omega, phase in self.trig:
            if amp == 0.0:
                continue
            arg = omega * tau + phase
            if order == 0:
                out = out + (amp / omega) * np.cos(phase) * tau - (amp / omega**2) * (np.sin(arg) - np.sin(phase))
            elif order == 1:
                out = out + (amp / omega) * (np.cos(phase) - np.cos(arg))
            elif order == 2:
                out = out + amp * np.sin(arg)
            else:
                out = out + amp * omega * np.cos(arg)
        return out

    def end_values(self) -> tuple[float, float, float, float]:
        """(s, v, a, j) at the piece's end (its left limits there)."""
        tau = np.array([self.width])
        return tuple(float(self.evaluate_tau(tau, order)[0]) for order in range(4))  # type: ignore[return-value]

    def start_values(self) -> tuple[float, float, float, float]:
        """(s, v, a, j) at the piece's start (its right limits there)."""
        tau = np.array([0.0])
        return tuple(float(self.evaluate_tau(tau, order)[0]) for order in range(4))  # type: ignore[return-value]

    def scaled(self, factor: float) -> Piece:
        """The piece with its acceleration (and s0, v0) multiplied by ``factor``."""
        return Piece(self.start, self.end, self.s0 * factor, self.v0 * factor,
                     tuple(p * factor for p in self.poly), tuple((a * factor, w, f) for a, w, f in self.trig))


def _falling(n: int, k: int) -> float:
    """n (n − 1) … (n − k + 1): the factor the k-th derivative brings down from τ^n."""
    out = 1.0
    for i in range(k):
        out *= n - i
    return out


@dataclass(frozen=True)
class AccelTerm:
    """The acceleration of one piece before integration: a = Σ p_m τ^m + Σ A sin(ω τ + φ) on [start, end]."""

    start: float
    end: float
    poly: tuple[float, ...] = ()
    trig: tuple[tuple[float, float, float], ...] = ()

    def scaled(self, factor: float) -> AccelTerm:
        return AccelTerm(self.start, self.end, tuple(p * factor for p in self.poly),
                         tuple((a * factor, w, f) for a, w, f in self.trig))

    def mapped(self, origin: float, width: float) -> AccelTerm:
        """The term of normalised z ∈ [0, 1] placed on θ = origin + z·width (rad): the same acceleration
        values at corresponding points (a polynomial in z becomes one in τ/width, ω becomes ω/width)."""
        return AccelTerm(origin + self.start * width, origin + self.end * width,
                         tuple(p / width**m for m, p in enumerate(self.poly)),
                         tuple((a, w / width, f) for a, w, f in self.trig))

    def mirrored(self) -> AccelTerm:
        """The term of z ↦ 1 − z (a lobe read backwards): on [1 − end, 1 − start] its value at z is this
        term's value at 1 − z."""
        length = self.end - self.start
        # p(L − τ') as a polynomial in τ'
        poly = np.polynomial.Polynomial(self.poly or (0.0,))
        flipped = poly(np.polynomial.Polynomial([length, -1.0]))
        trig = tuple((a, -w, w * length + f) for a, w, f in self.trig)
        return AccelTerm(1.0 - self.end, 1.0 - self.start, tuple(float(c) for c in flipped.coef), trig)


def integrate_pieces(terms: Sequence[AccelTerm], s0: float = 0.0, v0: float = 0.0) -> tuple[Piece, ...]:
    """Pieces of the acceleration terms (in order, each starting where the previous ends), with s and v
    carried exactly from (s0, v0) at the first start."""
    pieces = []
    s, v = float(s0), float(v0)
    for term in terms:
        piece = Piece(term.start, term.end, s, v, term.poly, term.trig)
        pieces.append(piece)
        s, v, _, _ = piece.end_values()
    return tuple(pieces)


@dataclass(frozen=True)
class ShapePiece:
    """A rest-to-rest shape f(u) of ``camcad.law.standard`` on [start, end] (rad): s = s0 + h f(u),
    u = (θ − start)/(end − start); h = ``lift`` (mm, negative for a return). Offers ``Piece``'s evaluation."""

    start: float
    end: float
    s0: float
    lift: float
    shape: Any

    @property
    def width(self) -> float:
        return self.end - self.start

    def evaluate(self, theta, order: int) -> np.ndarray:
        u = np.clip((np.asarray(theta, dtype=float) - self.start) / self.width, 0.0, 1.0)
        value = self.lift * np.asarray(self.shape.evaluate(u, order)) / self.width**order
        return value + self.s0 if order == 0 else value

    def end_values(self) -> tuple[float, float, float, float]:
        at = np.array([self.end])
        return tuple(float(self.evaluate(at, order)[0]) for order in range(4))  # type: ignore[return-value]

    def start_values(self) -> tuple[float, float, float, float]:
        at = np.array([self.start])
        return tuple(float(self.evaluate(at, order)[0]) for order in range(4))  # type: ignore[return-value]

    def inner_breakpoints(self) -> tuple[float, ...]:
        inner = getattr(self.shape, "breakpoints", None)
        return tuple(self.start + u * self.width for u in inner()) if inner is not None else ()


def evaluate_chain(pieces: Sequence[Piece], starts: np.ndarray, theta: np.ndarray, order: int) -> np.ndarray:
    """s, v, a or j of a chain of pieces at θ (rad): each θ evaluated on the last piece starting at or
    before it (``starts`` the pieces' starts, increasing; a θ before the first start uses the first)."""
    theta = np.asarray(theta, dtype=float)
    index = np.clip(np.searchsorted(starts, theta, side="right") - 1, 0, len(pieces) - 1)
    out = np.empty_like(theta)
    for k in np.unique(index):
        inside = index == k
        out[inside] = pieces[int(k)].evaluate(theta[inside], order)
    return out
