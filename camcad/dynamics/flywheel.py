"""Speed fluctuation and flywheel of a camshaft: the energy method over one turn; the motor through a gearbox.

Energy method (the classical one: a constant driving torque equal to the mean load torque T_m, a constant
reduced inertia J of everything turning with the camshaft). Over one turn the shaft's kinetic energy changes
by E(θ) = ∫₀^θ (T_m − T(t)) dt (J); with ΔE = max E − min E,

    ½ J (ω_max² − ω_min²) = ΔE   ⇒   δ = (ω_max − ω_min)/ω_m = ΔE/(J ω_m²),   ω_m = (ω_max + ω_min)/2,

exactly (no small-δ approximation: ω_max² − ω_min² = 2 ω_m (ω_max − ω_min)). So the inertia that holds the
coefficient of speed fluctuation δ is J = ΔE/(δ ω_m²), and a given inertia gives δ = ΔE/(J ω_m²). The
extremes of E lie where T = T_m; they are found by root finding between grid samples (Brent), and E there by
Gauss–Legendre quadrature, so ΔE is exact to round-off for a torque smooth between its breakpoints.

The motor: through a gearbox of ratio i = n_motor/n_cam and efficiency η, the motor torque is T/(i η) while
it drives and T η/i while the camshaft drives it back; its speed is i n.

Sources: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 10 (camshaft torque,
flywheel sizing by the energy method); I. I. Artobolevsky, Theory of Mechanisms and Machines (the coefficient
of speed fluctuation δ and its usual values); Vulfson, Dynamics of Cyclic Machines (2015), ch. 1.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.torque import cycle_nodes
from camcad.errors import CamcadError

#: the grid (rad) on which T − T_m changes sign are looked for before Brent refines them
ENERGY_STEP_RAD = math.radians(0.25)


@dataclass(frozen=True)
class EnergyFluctuation:
    """The shaft's energy over one turn at one speed.

    ``mean_torque`` T_m (N·m); ``delta_energy`` ΔE = max E − min E (J); E is largest at ``max_at`` and
    smallest (``energy_min``, J, E(0) = 0) at ``min_at`` (rad); ``theta`` (rad) and ``energy`` (J) sample E(θ)
    for plots.
    """

    rpm: float
    mean_torque: float
    delta_energy: float
    max_at: float
    min_at: float
    theta: np.ndarray
    energy: np.ndarray
    energy_min: float = 0.0

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.rpm / 60.0

    def inertia_for(self, delta: float) -> float:
        """J = ΔE/(δ ω²), kg·m², that holds the coefficient of speed fluctuation ``delta``."""
        return self.delta_energy / (delta * self.omega**2)

    def delta_with(self, inertia: float) -> float:
        """δ = ΔE/(J ω²) with the reduced inertia ``inertia`` (kg·m²); inf for J = 0."""
        if inertia <= 0.0:
            return math.inf if self.delta_energy > 0.0 else 0.0
        return self.delta_energy / (inertia * self.omega**2)

    def speed_range_rpm(self, inertia: float) -> tuple[float, float]:
        """(n_min, n_max), rpm, with the inertia ``inertia`` (kg·m²) about the mean speed."""
        delta = self.delta_with(inertia)
        return self.rpm * (1.0 - delta / 2.0), self.rpm * (1.0 + delta / 2.0)


def energy_fluctuation(torque: Callable[[np.ndarray], np.ndarray], breakpoints, rpm: float,
                       mean_torque: float | None = None) -> EnergyFluctuation:
    """The kinetic-energy swing ΔE of the camshaft over one turn (module docstring).

    Parameters
    ----------
    torque : callable
        θ (rad, 1-D array) → the load torque T (N·m) at ``rpm``.
    breakpoints : array_like
        θ (rad) where T may be non-smooth.
    rpm : float
        The mean speed, rpm.
    mean_torque : float, optional
        T_m, N·m; default the mean of T over the turn.

    Returns
    -------
    EnergyFluctuation
        T_m (N·m), ΔE (J) and where E is largest and smallest (rad); ``inertia_for(δ)`` (kg·m²),
        ``delta_with(J)`` (dimensionless).

    Examples
    --------
    T = T_m + A sin θ gives E = A (cos θ − 1), so ΔE = 2A; at 600 rpm J = 2A/(δ ω²):

    >>> e = energy_fluctuation(lambda t: 10.0 + 4.0 * np.sin(t), [], 600.0)
    >>> round(e.delta_energy, 12), round(e.inertia_for(1 / 30), 9), round(8.0 * 30 / (20 * math.pi) ** 2, 9)
    (8.0, 0.06079271, 0.06079271)
    """
    edges = unique(np.concatenate((np.asarray(breakpoints, dtype=float), [0.0, 2.0 * math.pi])))
    if mean_torque is None:
        x, w = cycle_nodes(edges)
        mean_torque = float(np.sum(w * np.asarray(torque(x), dtype=float))) / (2.0 * math.pi)
    grid = unique(np.concatenate((np.arange(0.0, 2.0 * math.pi, ENERGY_STEP_RAD), edges)))

    def excess(t):
        return mean_torque - np.asarray(torque(np.atleast_1d(np.asarray(t, dtype=float))), dtype=float)

    # E at the grid points: Gauss–Legendre over each interval (the edges are grid points: smooth inside)
    u, weight = np.polynomial.legendre.leggauss(8)
    lo, hi = grid[:-1], grid[1:]
    half, mid = 0.5 * (hi - lo), 0.5 * (hi + lo)
    nodes = mid[:, None] + half[:, None] * u[None, :]
    pieces = np.sum(excess(nodes.ravel()).reshape(nodes.shape) * weight[None, :], axis=1) * half
    energy = np.concatenate(([0.0], np.cumsum(pieces)))
    values = excess(grid)
    candidates = [(float(e), float(t)) for e, t in zip(energy, grid)]
    change = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0.0)
    if change.size:
        roots = bracketed_roots(excess, grid[change], grid[change + 1], values[change], values[change + 1])
        lo = grid[change]
        nodes_k = lo[:, None] + 0.5 * (roots - lo)[:, None] * (u[None, :] + 1.0)
        parts = np.sum(excess(nodes_k.ravel()).reshape(nodes_k.shape) * weight[None, :], axis=1) * 0.5 * (roots - lo)
        candidates += [(float(e), float(t)) for e, t in zip(energy[change] + parts, roots)]
    top = max(candidates)
    bottom = min(candidates)
    return EnergyFluctuation(float(rpm), float(mean_torque), top[0] - bottom[0], top[1] % (2 * math.pi),
                             bottom[1] % (2 * math.pi), grid, energy, bottom[0])


def bracketed_roots(fn, lo, hi, f_lo, f_hi, xtol: float = 1e-13, iterations: int = 100) -> np.ndarray:
    """Roots of ``fn`` (1-D array → array) in the brackets [lo, hi] (arrays; f_lo f_hi < 0), all at once: the
    Illinois variant of regula falsi, one vectorised call of ``fn`` per step, until every bracket is narrower
    than ``xtol`` (rad) or a root is hit exactly.

    Examples
    --------
    >>> bracketed_roots(np.cos, np.array([1.0, 4.0]), np.array([2.0, 5.0]), np.cos([1.0, 4.0]), np.cos([2.0, 5.0]))
    array([1.57079633, 4.71238898])
    """
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    f_lo, f_hi = np.array(f_lo, dtype=float), np.array(f_hi, dtype=float)
    root = 0.5 * (lo + hi)
    side = np.zeros(lo.shape, dtype=int)
    for _ in range(iterations):
        open_ = (hi - lo) > xtol
        if not open_.any():
            break
        with np.errstate(divide="ignore", invalid="ignore"):
            guess = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        bad = ~np.isfinite(guess) | (guess <= lo) | (guess >= hi)
        guess = np.where(bad, 0.5 * (lo + hi), guess)
        value = np.asarray(fn(guess), dtype=float)
        root = np.where(open_, guess, root)
        exact = value == 0.0
        left = np.sign(value) == np.sign(f_lo)
        # Illinois: halve the function value kept at an end that stays twice in a row
        new_lo = open_ & left & ~exact
        new_hi = open_ & ~left & ~exact
        f_hi = np.where(new_lo & (side == 1), 0.5 * f_hi, f_hi)
        f_lo = np.where(new_hi & (side == -1), 0.5 * f_lo, f_lo)
        lo, f_lo = np.where(new_lo, guess, lo), np.where(new_lo, value, f_lo)
        hi, f_hi = np.where(new_hi, guess, hi), np.where(new_hi, value, f_hi)
        side = np.where(new_lo, 1, np.where(new_hi, -1, side))
        lo = np.where(open_ & exact, guess, lo)
        hi = np.where(open_ & exact, guess, hi)
    return np.where((hi - lo) <= xtol, 0.5 * (lo + hi), root)


def motor_torque(shaft_torque, ratio: float = 1.0, efficiency: float = 1.0) -> np.ndarray:
    """The motor's torque (N·m) for a camshaft torque (N·m) through a gearbox of ratio i = n_motor/n_cam
    (dimensionless) and efficiency η (fraction): T/(i η) while the motor drives, T η/i while the shaft
    drives it back.

    Examples
    --------
    >>> motor_torque(np.array([100.0, -100.0]), ratio=10.0, efficiency=0.8).tolist()
    [12.5, -8.0]
    """
    if not ratio > 0.0 or not 0.0 < efficiency <= 1.0:
        raise CamcadError(f"gear ratio {ratio:g} and efficiency {efficiency:g} are not a gearbox", "drive",
                          "give a ratio > 0 and an efficiency in (0, 1]")
    shaft_torque = np.asarray(shaft_torque, dtype=float)
    return np.where(shaft_torque >= 0.0, shaft_torque / (ratio * efficiency), shaft_torque * efficiency / ratio)
