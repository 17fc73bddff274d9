"""Motion laws: the common interface, and the piecewise-linear acceleration law integrated exactly.

Conventions (docs/INTERFACE.md): the cam angle θ is in radians inside the library; the
follower displacement s is in mm (or in rad of arm swing for an oscillating
follower); v = ds/dθ, a = d²s/dθ², j = d³s/dθ³ are analogs per radian of cam
angle (mm/rad, mm/rad², mm/rad³). A law is periodic with period ``cycle``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

PHASE_KINDS = ("rise", "return", "dwell")


@dataclass(frozen=True)
class Phase:
    """One phase of the cycle: ``kind`` in {"rise", "return", "dwell"}, from ``start`` to ``end`` (rad).

    A phase may state where it ends: ``s_end`` the displacement there (mm from s(0) = 0; None: not
    stated) and ``v_end`` the velocity there (mm/rad; 0, the default, for a motion that ends at rest). A
    rise to an intermediate stop states its position; a motion that blends into the next one (a rise
    into a constant-velocity stretch) states its velocity. The balance check holds every phase to them.

    Parameters
    ----------
    kind : str
        "rise", "return" or "dwell".
    start, end : float
        Where the phase starts and ends, rad of cam angle (end > start).
    s_end : float, optional
        The displacement stated at the end, mm from s(0) = 0 (None: not stated).
    v_end : float
        The velocity stated at the end, mm/rad (0: the motion ends at rest).

    Examples
    --------
    >>> import math
    >>> from camcad.law import Phase
    >>> rise = Phase("rise", math.radians(60), math.radians(150), s_end=12.0)
    >>> round(math.degrees(rise.width), 6), rise.states_end, rise.as_deg()["s_end_mm"]
    (90.0, True, 12.0)
    """

    kind: str
    start: float
    end: float
    s_end: float | None = None
    v_end: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in PHASE_KINDS:
            raise ValueError(f"phase kind must be one of {PHASE_KINDS}, not {self.kind!r}")
        if not self.end > self.start:
            raise ValueError(f"phase must have end > start, got {self.start}..{self.end}")

    @property
    def width(self) -> float:
        return self.end - self.start

    @property
    def states_end(self) -> bool:
        """True when the phase states a position, or a velocity other than rest, at its end."""
        return self.s_end is not None or self.v_end != 0.0

    def as_deg(self) -> dict:
        out = {"kind": self.kind, "start_deg": float(np.degrees(self.start)), "end_deg": float(np.degrees(self.end))}
        if self.s_end is not None:
            out["s_end_mm"] = float(self.s_end)
        if self.v_end != 0.0:
            out["v_end_mm_per_deg"] = float(np.radians(self.v_end))
        return out

    def with_bounds(self, start: float, end: float) -> Phase:
        """The same phase (kind and stated end values) between other angles (rad)."""
        return Phase(self.kind, start, end, self.s_end, self.v_end)


@dataclass(frozen=True)
class Kinematics:
    """s, v, a, j of a law sampled at ``theta`` (rad); units mm, mm/rad, mm/rad², mm/rad³.

    What ``MotionLaw.kinematics`` returns; the example is there.

    Attributes
    ----------
    theta : ndarray
        The cam angles sampled, rad.
    s : ndarray
        Displacement, mm (rad for a swing).
    v : ndarray
        Velocity analog ds/dθ, mm/rad.
    a : ndarray
        Acceleration analog d²s/dθ², mm/rad².
    j : ndarray
        Jerk analog d³s/dθ³, mm/rad³.
    """

    theta: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray


@runtime_checkable
class MotionLaw(Protocol):
    """What every law offers: periodic s, v, a, j at any θ (rad), its cycle and its phases.

    A protocol: ``cycle`` (rad), ``phases`` (a tuple of ``Phase``) and ``kinematics(theta)`` (a
    ``Kinematics`` at the angles θ in rad, mm and its derivatives per rad). Standard laws
    (``camcad.compose``), drawn laws (``PiecewiseLinearLaw``), Fourier series and filtered laws all offer it;
    every analysis takes any of them.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import camcad
    >>> from camcad.law import MotionLaw
    >>> law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 20.0)
    >>> isinstance(law, MotionLaw), round(law.cycle, 12) == round(2 * math.pi, 12)
    (True, True)
    >>> round(float(law.kinematics(np.radians([180.0])).s[0]), 9)     # the top of the 20 mm rise, mm
    20.0
    """

    @property
    def cycle(self) -> float: ...

    @property
    def phases(self) -> tuple[Phase, ...]: ...

    def kinematics(self, theta: np.ndarray) -> Kinematics: ...


def wrap_angle(theta: float, cycle: float) -> float:
    """``wrap`` for one angle, without array overhead (Python's float modulo is numpy's: fmod, then the
    divisor's sign)."""
    wrapped = theta % cycle
    return cycle if wrapped == 0.0 and theta > 0.0 else wrapped


def wrap(theta, cycle: float) -> np.ndarray:
    """θ reduced to [0, cycle]; the cycle end itself is kept (not folded to 0) so s(cycle) is reachable."""
    theta = np.asarray(theta, dtype=float)
    if theta.size and theta.min() >= 0.0 and theta.max() <= cycle:
        return theta + 0.0      # already in [0, cycle] (np.mod would return it unchanged; + 0.0 makes −0.0 +0.0)
    wrapped = np.mod(theta, cycle)
    # keep exact multiples > 0 at the end of the cycle: s(T) of an unbalanced law differs from s(0)
    at_end = (wrapped == 0.0) & (theta > 0.0)
    return np.where(at_end, cycle, wrapped)


# --------------------------------------------------------------------------------------------
# Exact integration of a piecewise-linear acceleration
# --------------------------------------------------------------------------------------------

def integrate_exact(x: np.ndarray, a: np.ndarray, v0: float = 0.0, s0: float = 0.0
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and displacement at the knots of a piecewise-linear acceleration, exactly.

    On a segment of length L from knot k to k+1 the acceleration is linear, so
        v_{k+1} = v_k + L (a_k + a_{k+1}) / 2
        s_{k+1} = s_k + v_k L + L² (2 a_k + a_{k+1}) / 6
    (the velocity is piecewise quadratic and the displacement piecewise cubic).
    Zero-length segments (vertical jumps of a) add nothing. Exact up to round-off.

    Parameters
    ----------
    x : ndarray
        Knots, rad, non-decreasing; a repeated x is a jump of acceleration.
    a : ndarray
        Acceleration analog at the knots, mm/rad².
    v0, s0 : float
        Velocity (mm/rad) and displacement (mm) at x[0].

    Returns
    -------
    v, s : ndarray
        Velocity (mm/rad) and displacement (mm) at the knots, arrays like x.

    Examples
    --------
    a rises 0 → 2 mm/rad² over 1 rad, then jumps to −1 and rises to 1 over 2 rad:

    >>> import numpy as np
    >>> from camcad.law import integrate_exact
    >>> v, s = integrate_exact(np.array([0.0, 1.0, 1.0, 3.0]), np.array([0.0, 2.0, -1.0, 1.0]))
    >>> v.tolist(), [round(float(x), 12) for x in s]
    ([0.0, 1.0, 1.0, 1.0], [0.0, 0.333333333333, 0.333333333333, 1.666666666667])
    """
    x = np.asarray(x, dtype=float)
    a = np.asarray(a, dtype=float)
    length = np.diff(x)
    dv = length * (a[:-1] + a[1:]) / 2.0
    v = np.concatenate(([v0], v0 + np.cumsum(dv)))
    ds = v[:-1] * length + length**2 * (2.0 * a[:-1] + a[1:]) / 6.0
    s = np.concatenate(([s0], s0 + np.cumsum(ds)))
    return v, s


def integrate_trapezoid(x: np.ndarray, a: np.ndarray, step: float, v0: float = 0.0, s0: float = 0.0
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The source's method: resample a at a uniform step, then integrate twice with the trapezoidal rule.

    Dupliak & Kotsiyba (2018, *Methods for optimization of the cam mechanisms modeling*): "recompute all points
    of the graph with a step (default 0.1), then integrate again with the trapezoid method". The grid covers
    [x0, x_end] with the last interval shortened to end exactly at x_end. A jump of the
    acceleration (a repeated knot) keeps both its values at its own angle, so a vertical
    segment stays vertical instead of becoming a one-step ramp.

    Error: resampling a piecewise-linear a at points that miss its knots replaces it by
    chords, an O(step²·|Δa'|) change near each knot; the trapezoidal rule on the
    quadratic v adds at most step²/12 · max|a'| · (x_end − x0) to s. Both are measured
    against ``integrate_exact`` in the tests and the benchmark.

    Parameters
    ----------
    x : ndarray
        Knots, rad, non-decreasing; a repeated x is a jump of acceleration.
    a : ndarray
        Acceleration analog at the knots, mm/rad².
    step : float
        The resampling step, rad.
    v0, s0 : float
        Velocity (mm/rad) and displacement (mm) at x[0].

    Returns
    -------
    grid, a_grid, v_grid, s_grid : ndarray
        The grid (rad), and a (mm/rad²), v (mm/rad) and s (mm) on it.

    Examples
    --------
    A linear a is integrated exactly for v on any grid; s carries the rule's error h²/12 per unit slope:

    >>> import numpy as np
    >>> from camcad.law import integrate_trapezoid
    >>> grid, a, v, s = integrate_trapezoid(np.array([0.0, 1.0]), np.array([0.0, 1.0]), 0.25)
    >>> grid.tolist(), float(v[-1]), round(float(s[-1]), 6)          # exact: v(1) = 1/2, s(1) = 1/6
    ([0.0, 0.25, 0.5, 0.75, 1.0], 0.5, 0.171875)
    """
    x = np.asarray(x, dtype=float)
    a = np.asarray(a, dtype=float)
    grid, a_grid = resample(x, a, step)
    dx = np.diff(grid)
    v = np.concatenate(([v0], v0 + np.cumsum(dx * (a_grid[:-1] + a_grid[1:]) / 2.0)))
    s = np.concatenate(([s0], s0 + np.cumsum(dx * (v[:-1] + v[1:]) / 2.0)))
    return grid, a_grid, v, s


def resample(x: np.ndarray, a: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The polyline sampled every ``step`` from x[0] to x[-1]; each jump keeps its two values."""
    grid = uniform_grid(float(x[0]), float(x[-1]), step)
    a_grid = sample_piecewise_linear(x, a, grid)
    jump = np.flatnonzero(np.diff(x) == 0)
    if len(jump) == 0:
        return grid, a_grid
    at = x[jump]
    cut = np.searchsorted(grid, at)
    on_grid = (cut < len(grid)) & (grid[np.minimum(cut, len(grid) - 1)] == at)
    # drop grid points that coincide with a jump, then insert (left, right) at each jump
    keep = np.ones(len(grid), dtype=bool)
    keep[cut[on_grid]] = False
    grid, a_grid = grid[keep], a_grid[keep]
    cut = np.searchsorted(grid, at)
    grid = np.insert(grid, np.repeat(cut, 2), np.repeat(at, 2))
    a_grid = np.insert(a_grid, np.repeat(cut, 2), np.column_stack((a[jump], a[jump + 1])).ravel())
    return grid, a_grid


def uniform_grid(start: float, end: float, step: float) -> np.ndarray:
    """Points start, start+step, … with the end included exactly (last interval may be short)."""
    if step <= 0:
        raise ValueError("step must be positive")
    count = int(np.floor((end - start) / step + 1e-9))
    grid = start + step * np.arange(count + 1)
    if end - grid[-1] > 1e-12 * max(1.0, abs(end)):
        grid = np.append(grid, end)
    else:
        grid[-1] = end
    return grid


def sample_piecewise_linear(x: np.ndarray, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Value of the polyline (x, y) at t; at a jump (repeated x) the right-hand value is taken."""
    index = segment_index(x, t)
    x0, x1 = x[index], x[index + 1]
    length = x1 - x0
    frac = np.divide(t - x0, length, out=np.zeros_like(t, dtype=float), where=length > 0)
    return y[index] + frac * (y[index + 1] - y[index])


def segment_index(x: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Index k of the segment [x_k, x_{k+1}] holding t; jumps resolve to the right-hand segment."""
    index = np.searchsorted(x, t, side="right") - 1
    return np.clip(index, 0, len(x) - 2)


@dataclass(frozen=True)
class PiecewiseLinearLaw:
    """A motion law whose acceleration analog is piecewise linear in θ (a drawn polyline).

    Knots ``x`` (rad) are non-decreasing; a repeated knot is a jump of acceleration.
    Velocity and displacement are the exact piecewise-quadratic and -cubic integrals
    (see ``integrate_exact``), starting from rest at s = 0 at x[0] = 0 unless v0/s0 say otherwise.
    The jerk is the slope of each segment (the Dirac part at a jump is not represented).

    Parameters
    ----------
    x : ndarray
        The knots, rad of cam angle, non-decreasing from 0; a repeated knot is a jump of a.
    a : ndarray
        The acceleration analog at the knots, mm/rad².
    cycle : float
        The cycle, rad (2π for one cam turn).
    phases : tuple of Phase
        The law's phases (``camcad.law.phases.detect_phases`` finds them in a drawn law).
    v0, s0 : float
        Velocity (mm/rad) and displacement (mm) at x[0].

    Examples
    --------
    A constant acceleration of 1 mm/rad² for 2 rad from rest: v = θ, s = θ²/2.

    >>> import numpy as np
    >>> from camcad.law import PiecewiseLinearLaw
    >>> law = PiecewiseLinearLaw(np.array([0.0, 2.0]), np.array([1.0, 1.0]), 2.0)
    >>> kin = law.kinematics(np.array([1.0, 2.0]))
    >>> kin.v.tolist(), kin.s.tolist()
    ([1.0, 2.0], [0.5, 2.0])
    """

    x: np.ndarray
    a: np.ndarray
    cycle: float
    phases: tuple[Phase, ...] = ()
    v0: float = 0.0
    s0: float = 0.0
    v_knots: np.ndarray = field(init=False, repr=False, compare=False)
    s_knots: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        x = np.ascontiguousarray(self.x, dtype=float)
        a = np.ascontiguousarray(self.a, dtype=float)
        if x.ndim != 1 or x.shape != a.shape or len(x) < 2:
            raise ValueError("x and a must be 1-D arrays of equal length >= 2")
        if np.any(np.diff(x) < 0):
            raise ValueError("knots must be non-decreasing")
        v, s = integrate_exact(x, a, self.v0, self.s0)
        for name, value in (("x", x), ("a", a), ("v_knots", v), ("s_knots", s)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    def kinematics(self, theta) -> Kinematics:
        theta = np.asarray(theta, dtype=float)
        t_cycle = wrap(theta, self.cycle)
        x = self.x
        k = segment_index(x, t_cycle)
        length = x[k + 1] - x[k]
        slope = np.divide(self.a[k + 1] - self.a[k], length,
                          out=np.zeros_like(length), where=length > 0)
        t = t_cycle - x[k]
        a0, v0, s0 = self.a[k], self.v_knots[k], self.s_knots[k]
        a = a0 + slope * t
        v = v0 + a0 * t + slope * t**2 / 2.0
        s = s0 + v0 * t + a0 * t**2 / 2.0 + slope * t**3 / 6.0
        return Kinematics(theta=theta, s=s, v=v, a=a, j=slope)

    def acceleration_at(self, theta: float) -> float:
        """a(θ) (mm/rad²) at one cam angle θ (rad), without array overhead (ODE right-hand sides call it
        at every step); equal to ``kinematics(np.array([theta])).a[0]`` (the right-hand value at a jump)."""
        t = float(wrap(np.float64(theta), self.cycle))
        x = self.x
        k = min(max(int(np.searchsorted(x, t, side="right")) - 1, 0), len(x) - 2)
        length = x[k + 1] - x[k]
        if length <= 0.0:
            return float(self.a[k + 1])
        return float(self.a[k] + (t - x[k]) / length * (self.a[k + 1] - self.a[k]))

    def with_ordinates(self, a: np.ndarray) -> PiecewiseLinearLaw:
        """The same knots and phases with new acceleration ordinates."""
        return PiecewiseLinearLaw(self.x, a, self.cycle, self.phases, self.v0, self.s0)

    def with_phases(self, phases: tuple[Phase, ...]) -> PiecewiseLinearLaw:
        return PiecewiseLinearLaw(self.x, self.a, self.cycle, tuple(phases), self.v0, self.s0)
