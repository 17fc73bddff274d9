"""The function a four-bar function generator must reproduce: y = F(x) on [x0, x1] mapped to angles.

The input link turns by φ ∈ [0, Δφ] while x runs over [x0, x1], the output link by ψ ∈ [0, Δψ]
while y runs from F(x0) to F(x1) (the usual linear scaling of function generators, e.g.
Freudenstein 1955; Sunkuev 1984 ch. 2 writes the target as ψ = F(φ) on [φ0, φm]):

    φ = Δφ (x − x0)/(x1 − x0),    ψ_target(φ) = Δψ (F(x) − F(x0))/(F(x1) − F(x0)).

Δφ and Δψ are signed: a negative range turns the link clockwise. F must be finite and strictly
monotone on [x0, x1] (checked on a dense grid), so that ψ_target runs once over [0, Δψ].
Angles are radians inside this module; the public attributes ending ``_deg`` are degrees.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.table_read import read_table

#: points of the grid on which a target is checked for being defined and monotone
CHECK_POINTS = 4001


@dataclass(frozen=True)
class Target:
    """ψ_target(φ) (rad) from y = F(x); see the module docstring."""

    label: str
    x0: float
    x1: float
    input_range_deg: float
    output_range_deg: float
    function: Callable[[np.ndarray], np.ndarray]
    derivative: Callable[[np.ndarray], np.ndarray]
    y0: float
    y1: float

    @property
    def dphi(self) -> float:
        """Input range Δφ, rad (signed)."""
        return math.radians(self.input_range_deg)

    @property
    def dpsi(self) -> float:
        """Output range Δψ, rad (signed)."""
        return math.radians(self.output_range_deg)

    def x_of(self, phi):
        return self.x0 + (self.x1 - self.x0) * np.asarray(phi, dtype=float) / self.dphi

    def psi(self, phi):
        """ψ_target(φ), rad."""
        y = self.function(self.x_of(phi))
        return self.dpsi * (y - self.y0) / (self.y1 - self.y0)

    def dpsi_dphi(self, phi):
        """dψ_target/dφ (dimensionless)."""
        return (self.dpsi / (self.y1 - self.y0)) * self.derivative(self.x_of(phi)) * (self.x1 - self.x0) / self.dphi


def make_target(function: Callable, x0: float, x1: float, input_range_deg: float, output_range_deg: float,
                label: str, derivative: Callable | None = None, where: str = "--function") -> Target:
    """Build and check a ``Target``: F finite and strictly monotone on [x0, x1], ranges non-zero.

    Parameters
    ----------
    function : callable
        F, vectorised over numpy arrays.
    x0, x1 : float
        The interval of x (x0 < x1 or x0 > x1, not equal).
    input_range_deg, output_range_deg : float
        Δφ and Δψ, deg (signed, non-zero, magnitude below 360).
    label : str
        How the function is shown in reports.
    derivative : callable, optional
        F'; default a 4th-order central difference.
    where : str
        The option or file the function came from (for error messages).

    Examples
    --------
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> round(math.degrees(float(t.psi(t.dphi))), 12), round(math.degrees(float(t.psi(t.dphi / 2))), 6)
    (90.0, 52.646625)
    """
    for name, value in (("--x", x0), ("--x", x1), ("--input-range", input_range_deg),
                        ("--output-range", output_range_deg)):
        if not math.isfinite(value):
            raise CamcadError(f"{value} is not a finite number", name, "give finite numbers")
    if x0 == x1:
        raise CamcadError(f"the interval of x is empty ({x0:g}:{x1:g})", "--x", "give --x X0:X1 with X0 != X1")
    if input_range_deg == 0 or abs(input_range_deg) >= 360:
        raise CamcadError(f"input range {input_range_deg:g} deg is not in (0, 360) in magnitude", "--input-range",
                          "give the input link's turn in deg, e.g. --input-range 60")
    if output_range_deg == 0 or abs(output_range_deg) >= 360:
        raise CamcadError(f"output range {output_range_deg:g} deg is not in (0, 360) in magnitude",
                          "--output-range", "give the output link's turn in deg, e.g. --output-range 90")
    grid = np.linspace(x0, x1, CHECK_POINTS)
    with np.errstate(all="ignore"):
        values = np.asarray(function(grid), dtype=float) * np.ones_like(grid)
    bad = ~np.isfinite(values)
    if bad.any():
        at = grid[np.argmax(bad)]
        raise CamcadError(f"{label} is not defined (or not finite) at x = {at:.6g}", where,
                          f"choose --x inside the function's domain (the first bad point is x = {at:.6g})")
    steps = np.diff(values)
    rising = steps > 0
    if not (rising.all() or (steps < 0).all()):
        k = int(np.argmax(~rising)) if rising[0] else int(np.argmax(rising))
        raise CamcadError(f"{label} is not strictly monotone on [{x0:g}, {x1:g}]: it turns near x = {grid[k]:.6g}",
                          where, "a function generator needs a monotone function: narrow --x to one monotone piece")
    if derivative is None:
        step = 1e-5 * max(1.0, abs(x1 - x0))

        def derivative(x, f=function, h=step):
            x = np.asarray(x, dtype=float)
            return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)
    return Target(label, float(x0), float(x1), float(input_range_deg), float(output_range_deg), function, derivative,
                  float(values[0]), float(values[-1]))


def target_from_table(path: Path, x0: float | None, x1: float | None, input_range_deg: float,
                      output_range_deg: float) -> Target:
    """A ``Target`` from a two-column table (x, y) read by ``camcad.io.table_read`` and interpolated by a
    not-a-knot cubic spline (its derivative is the spline's). --x defaults to the table's x-range and
    must lie inside it.

    Examples
    --------
    >>> import tempfile, os
    >>> folder = tempfile.mkdtemp()
    >>> path = Path(folder) / "squares.csv"
    >>> _ = path.write_text(chr(10).join(["x,y"] + [f"{k / 10},{(k / 10) ** 2}" for k in range(11)]))
    >>> t = target_from_table(path, None, None, 60.0, 90.0)
    >>> round(math.degrees(float(t.psi(t.dphi / 2))), 9)        # a cubic spline is exact for x^2: 90 * 0.25
    22.5
    """
    from scipy.interpolate import CubicSpline

    table = read_table(path)
    x, y = table.theta_deg, table.accel
    if len(x) < 4:
        raise CamcadError(f"the table has {len(x)} rows, need at least 4", str(path), "give more (x, y) rows")
    if np.any(np.diff(x) <= 0):
        k = int(np.argmax(np.diff(x) <= 0))
        raise CamcadError(f"x repeats at line {int(table.line_numbers[k + 1])} (x = {x[k + 1]:g})", str(path),
                          "give each x once")
    lo = float(x[0]) if x0 is None else x0
    hi = float(x[-1]) if x1 is None else x1
    if min(lo, hi) < x[0] - 1e-12 or max(lo, hi) > x[-1] + 1e-12:
        raise CamcadError(f"--x {lo:g}:{hi:g} reaches outside the table's x-range [{x[0]:g}, {x[-1]:g}]", "--x",
                          "choose --x inside the table or omit it")
    spline = CubicSpline(x, y)
    return make_target(spline, lo, hi, input_range_deg, output_range_deg, Path(path).name, spline.derivative(),
                       where=str(path))
