"""The linkage as the rest of camcad sees it: the working member's position function y = Π(ψ) of the
follower's motion ψ, the working member's law through the chain rule, the follower's law from the
working member's by inversion, and the rigid model's reduced inertia and loads.

Coordinates. θ is the cam angle (rad). ψ(θ) is the follower's motion in follower units: rad of swing for
an oscillating follower, mm for a translating one. y = Π(ψ) is the working member's motion: rad for a
turning member (a four-bar or six-bar, or a table in deg/rad), mm for a sliding one (a table in mm, or a
constant ratio). Four kinds of Π:

- ``RatioTransfer``: Π = kψ, the constant ratio camcad's [stops] ``ratio`` always meant;
- ``TableTransfer``: a table of (ψ, y), interpolated by a quintic spline (C⁴; Π''' continuous);
- ``LinkageTransfer``: a four-bar or six-bar (``camcad.linkage.analysis``), exact derivatives.

Chain rule (' = d/dθ for the laws, Π⁽ⁿ⁾ = dⁿΠ/dψⁿ):

    y' = Π' ψ',  y'' = Π'' ψ'² + Π' ψ'',  y''' = Π''' ψ'³ + 3 Π'' ψ' ψ'' + Π' ψ''',

and, inverted on a monotone branch (Π' ≠ 0), the follower's law from the working member's:

    ψ' = y'/Π',  ψ'' = (y'' − Π'' ψ'²)/Π',  ψ''' = (y''' − Π''' ψ'³ − 3 Π'' ψ' ψ'')/Π'.

The rigid driven system (the batten study's batten: the driven mass J₂ behind the position function Π). With J
the working member's inertia (kg·m², or kg for a sliding member) and Q the load on it (N·m or N, positive
against its motion), its kinetic energy is T = ½ J ẏ² = ½ J Π'² ψ̇²: the inertia reduced to the follower
is J Π'² and Lagrange's equation in ψ gives the generalised force the follower must supply

    M_ψ = J Π'² ψ̈ + J Π' Π'' ψ̇² + Π' Q   (N·m per rad of swing, or N per m of a sliding follower),

the velocity-squared term J Π' Π'' ψ̇² coming from the variable reduced inertia (½ d(JΠ'²)/dψ ψ̇²). It
equals Π'(J ÿ + Q): the working member's inertia and load reduced through Π'. Along the roller's path
the force is M_ψ / L (L the arm, m) for an oscillating follower, M_ψ for a translating one; the pressure
angle then gives the contact force (camcad.contact.normal_force). With θ = ωt, ψ̇ = ψ' ω and
ψ̈ = ψ'' ω², so that force is A(θ) ω² + B(θ) (``LinkageLoad``).

Sources: the batten's dynamic model with the position function П(φ) and its Lagrange function
(the batten study, ch. 3); I. I. Vulfson, Dynamics of Cyclic Machines (Springer 2015), ch. 1 (reduced inertia,
the ½ J' ψ̇² term); R. L. Norton, Cam Design and Manufacturing Handbook (2009), ch. 9 (force analysis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Kinematics, PiecewiseLinearLaw

UNITS_IN = ("rad", "mm")
UNITS_OUT = ("rad", "mm")


# --------------------------------------------------------------------------------------------
# Position functions
# --------------------------------------------------------------------------------------------

class Transfer:
    """A position function y = Π(ψ) on [0, ψ_max]: derivatives, inverse, monotonicity (module docstring).

    Subclasses set ``kind``, ``unit_in`` (rad or mm), ``unit_out`` (rad or mm), ``psi_max`` and implement
    ``derivatives``.
    """

    kind = "transfer"
    unit_in = "rad"
    unit_out = "rad"
    psi_max = math.inf

    def derivatives(self, psi):
        """(Π, Π', Π'', Π''') at ψ (arrays)."""
        raise NotImplementedError

    def slope(self, psi):
        """(Π, Π') at ψ: what the inverse needs (a subclass may compute less than ``derivatives``)."""
        return self.derivatives(psi)[:2]

    def __call__(self, psi):
        return self.derivatives(psi)[0]

    def describe(self) -> str:
        return self.kind

    def limit_positions(self, psi_max: float, points: int = 2001) -> list[float]:
        """Swings ψ in (0, ψ_max) where Π' changes sign (roots refined by Brent's method)."""
        from scipy.optimize import brentq

        grid = np.linspace(0.0, psi_max, points)
        d1 = np.asarray(self.derivatives(grid)[1], dtype=float)
        roots = []
        for i in range(points - 1):
            if d1[i] == 0.0 and 0 < i:
                roots.append(float(grid[i]))
            elif d1[i] * d1[i + 1] < 0.0:
                roots.append(float(brentq(lambda x: float(self.derivatives(np.array([x]))[1][0]), grid[i],
                                          grid[i + 1], xtol=1e-15)))
        return roots

    def check_monotone(self, psi_max: float, where: str) -> int:
        """The sign of Π' on [0, ψ_max]; a CamcadError naming the first limit position (Π' = 0) if it changes.

        Returns
        -------
        int
            +1 (Π increasing) or −1.
        """
        grid = np.linspace(0.0, psi_max, 2001)
        pi, d1 = (np.asarray(v, dtype=float) for v in self.derivatives(grid)[:2])
        if not np.all(np.isfinite(pi)):
            bad = float(grid[np.argmax(~np.isfinite(pi))])
            raise CamcadError(f"the linkage does not close at swing {_show(bad, self.unit_in)}", where,
                              "change the link lengths or the follower's swing")
        roots = self.limit_positions(psi_max)
        if roots or (np.any(d1 == 0.0) and not (np.all(d1 >= 0) or np.all(d1 <= 0))):
            at = roots[0] if roots else float(grid[np.argmax(d1 == 0.0)])
            raise CamcadError(f"the position function is not monotone on the swing: the working member has a "
                              f"dead point (limit position, Pi' = 0) at swing {_show(at, self.unit_in)}", where,
                              "shorten the swing or change the linkage so that the working member moves one way")
        return 1 if float(np.nanmean(d1)) > 0 else -1

    def inverse(self, y, psi_max: float | None = None):
        """ψ with Π(ψ) = y on the monotone branch [0, ψ_max] (safeguarded Newton, to rounding).

        The start comes from Π tabulated on 513 points of the branch; Newton steps that leave the bracket
        kept around each root are replaced by bisection. Values outside Π's range on the branch (by more
        than 1e-9 of the stroke) give NaN.
        """
        psi_max = self.psi_max if psi_max is None else psi_max
        if not math.isfinite(psi_max):
            raise ValueError("the inverse needs the branch [0, psi_max]")
        y = np.asarray(y, dtype=float)
        shape = y.shape
        y = y.ravel()
        table = self._inverse_table(psi_max)
        grid, values = table
        sign = 1.0 if values[-1] > values[0] else -1.0
        tol = 1e-9 * abs(values[-1] - values[0])
        inside = (sign * (y - values[0]) >= -tol) & (sign * (values[-1] - y) >= -tol)
        x = np.interp(sign * y, sign * values, grid)
        # the bracket reaches a hair beyond the branch: a law's y at its ends carries rounding
        index = np.clip(np.searchsorted(sign * values, sign * y), 1, len(grid) - 1)
        lo = np.where(index == 1, -1e-9 * psi_max, grid[index - 1])
        hi = np.where(index == len(grid) - 1, psi_max * (1 + 1e-9), grid[index])
        active = np.flatnonzero(inside)
        scale = max(abs(values[-1]), abs(values[0]), 1e-300)
        for _ in range(60):
            if active.size == 0:
                break
            xa = x[active]
            f, d = (np.asarray(v, dtype=float) for v in self.slope(xa))
            r = f - y[active]
            below = sign * r < 0
            lo[active] = np.where(below, np.maximum(lo[active], xa), lo[active])
            hi[active] = np.where(below, hi[active], np.minimum(hi[active], xa))
            with np.errstate(divide="ignore", invalid="ignore"):
                nxt = xa - np.where(d != 0, r / d, 0.0)
            bad = ~np.isfinite(nxt) | (nxt < lo[active]) | (nxt > hi[active])
            nxt = np.where(bad, 0.5 * (lo[active] + hi[active]), nxt)
            x[active] = nxt
            # converged: the step is a few ulps (Π itself carries rounding of that order), or r vanishes
            done = (np.abs(nxt - xa) <= 2e-15 * np.maximum(1.0, np.abs(xa))) | (np.abs(r) <= 2e-16 * scale)
            active = active[~done]
        return np.where(inside, x, np.nan).reshape(shape)

    def _inverse_table(self, psi_max: float):
        cached = getattr(self, "_table_cache", None)
        if cached is not None and cached[0] == psi_max:
            return cached[1]
        grid = np.linspace(0.0, psi_max, 513)
        values = np.asarray(self.derivatives(grid)[0], dtype=float)
        if not (np.all(np.isfinite(values)) and (np.all(np.diff(values) > 0) or np.all(np.diff(values) < 0))):
            raise CamcadError("the position function is not monotone (or does not close) on the branch it is "
                              "inverted on", "linkage", "check the linkage with camcad linkage analyse")
        try:
            object.__setattr__(self, "_table_cache", (psi_max, (grid, values)))
        except AttributeError:
            pass
        return grid, values


def _show(psi: float, unit: str) -> str:
    return f"{math.degrees(psi):.6g} deg" if unit == "rad" else f"{psi:.6g} mm"


@dataclass(frozen=True)
class RatioTransfer(Transfer):
    """Π = kψ (k in y units per ψ unit): today's constant ``ratio``.

    Examples
    --------
    >>> RatioTransfer(2.5, "mm", "mm").derivatives(np.array([1.0, 2.0]))[0]
    array([2.5, 5. ])
    """

    k: float
    unit_in: str = "mm"
    unit_out: str = "mm"
    kind = "ratio"
    psi_max = math.inf

    def derivatives(self, psi):
        psi = np.asarray(psi, dtype=float)
        zero = np.zeros_like(psi)
        return self.k * psi, self.k + zero, zero, zero.copy()

    def inverse(self, y, psi_max: float | None = None):
        return np.asarray(y, dtype=float) / self.k

    def limit_positions(self, psi_max: float, points: int = 2001) -> list[float]:
        return []

    def describe(self) -> str:
        return f"constant ratio {self.k:.6g} {self.unit_out}/{self.unit_in}"


class TableTransfer(Transfer):
    """Π from a table of (ψ, y) pairs (follower units, working-member units), interpolated by a spline of
    degree min(5, rows − 1) through the rows (not-a-knot): Π''' is continuous for six rows or more.

    Parameters
    ----------
    psi, y : array_like
        The rows: ψ strictly increasing (sorted here; duplicated ψ must carry the same y), starting at 0
        (the follower on the base circle).
    unit_in, unit_out : str
        "rad" or "mm".

    Examples
    --------
    A linear table reproduces Π = kψ exactly (to rounding):

    >>> t = TableTransfer([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [0.0, 2.0, 4.0, 6.0, 8.0, 10.0, 12.0], "mm", "mm")
    >>> [round(float(v[0]), 12) for v in t.derivatives(np.array([2.5]))[:2]]
    [5.0, 2.0]
    """

    kind = "table"

    def __init__(self, psi, y, unit_in: str = "rad", unit_out: str = "rad", where: str = "table"):
        from scipy.interpolate import make_interp_spline

        psi = np.asarray(psi, dtype=float).ravel()
        y = np.asarray(y, dtype=float).ravel()
        if psi.shape != y.shape or len(psi) < 2:
            raise CamcadError("the table of the position function needs at least two rows of (psi, y)", where,
                              "give two columns: the follower's motion and the working member's")
        if not (np.all(np.isfinite(psi)) and np.all(np.isfinite(y))):
            raise CamcadError("the table of the position function holds a value that is not a number", where,
                              "give finite numbers")
        order = np.argsort(psi, kind="stable")
        psi, y = psi[order], y[order]
        keep = np.r_[True, np.diff(psi) > 0]
        for i in np.flatnonzero(~keep):
            if y[i] != y[i - 1]:
                raise CamcadError(f"the table gives two values of y at psi = {psi[i]:g} (rows out of order or a "
                                  "vertical step)", where, "a position function has one y per psi; remove one row")
        psi, y = psi[keep], y[keep]
        if len(psi) < 2:
            raise CamcadError("the table of the position function needs at least two distinct psi", where,
                              "add rows")
        if abs(psi[0]) > 1e-12 * max(1.0, abs(psi[-1])):
            raise CamcadError(f"the table starts at psi = {psi[0]:g}, not 0 (the follower on the base circle)",
                              where, "start the table at psi = 0")
        self.psi_rows, self.y_rows = psi, y
        self.unit_in, self.unit_out = unit_in, unit_out
        self.psi_max = float(psi[-1])
        degree = int(min(5, len(psi) - 1))
        self._spline = make_interp_spline(psi, y, k=degree)
        self._d = [self._spline.derivative(n) for n in (1, 2, 3)] if degree >= 3 else None
        self.degree = degree

    def derivatives(self, psi):
        psi = np.asarray(psi, dtype=float)
        value = self._spline(psi)
        if self._d is not None:
            return value, self._d[0](psi), self._d[1](psi), self._d[2](psi)
        ders = [self._spline.derivative(n)(psi) if n <= self.degree else np.zeros_like(psi) for n in (1, 2, 3)]
        return (value, *ders)

    def describe(self) -> str:
        return (f"table of {len(self.psi_rows)} rows ({self.unit_in} -> {self.unit_out}), spline of degree "
                f"{self.degree}")


class LinkageTransfer(Transfer):
    """Π of a four-bar or six-bar (``camcad.linkage.analysis.Linkage``) on the swing [0, ψ_max] (rad).

    Examples
    --------
    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=0.5)
    >>> t = LinkageTransfer(lk, 0.4)
    >>> round(float(t.inverse(np.array([0.25]))[0]), 12)
    0.25
    """

    unit_in = "rad"
    unit_out = "rad"

    def __init__(self, linkage, psi_max: float):
        self.linkage = linkage
        self.psi_max = float(psi_max)
        self.kind = linkage.kind

    def derivatives(self, psi):
        return self.linkage.position(psi)

    def slope(self, psi):
        return self.linkage.position(psi, order=1)[:2]

    def describe(self) -> str:
        loops = "; ".join(f"a {lp.a:.6g}, b {lp.b:.6g}, c {lp.c:.6g}, d {lp.d:.6g} mm" for lp in self.linkage.loops)
        return f"{self.kind} ({loops})"


# --------------------------------------------------------------------------------------------
# Laws through Π
# --------------------------------------------------------------------------------------------

def chain_rule(d, psi_kin: Kinematics, scale: float = 1.0) -> Kinematics:
    """The working member's kinematics from the follower's: y, y', y'', y''' (module docstring).

    Parameters
    ----------
    d : tuple of ndarray
        (Π, Π', Π'', Π''') at the follower's positions ``psi_kin.s``.
    psi_kin : Kinematics
        The follower's ψ, ψ', ψ'', ψ''' per rad of cam angle.
    scale : float
        Multiplies y and its derivatives (units of the result per unit of Π).

    Examples
    --------
    >>> from camcad.law.law import Kinematics
    >>> k = Kinematics(np.zeros(1), np.array([0.2]), np.array([1.5]), np.array([-0.7]), np.array([3.0]))
    >>> out = chain_rule((np.sin(k.s), np.cos(k.s), -np.sin(k.s), -np.cos(k.s)), k)
    >>> round(float(out.a[0] - (-np.sin(0.2) * 1.5 ** 2 + np.cos(0.2) * -0.7)), 15)
    0.0
    """
    pi, p1, p2, p3 = d
    v, a, j = psi_kin.v, psi_kin.a, psi_kin.j
    return Kinematics(psi_kin.theta, scale * pi, scale * p1 * v, scale * (p2 * v ** 2 + p1 * a),
                      scale * (p3 * v ** 3 + 3 * p2 * v * a + p1 * j))


def inverse_chain_rule(d, y_kin: Kinematics, psi) -> Kinematics:
    """The follower's kinematics ψ, ψ', ψ'', ψ''' from the working member's y (module docstring), with
    (Π, Π', Π'', Π''') = ``d`` at ``psi``.

    Examples
    --------
    >>> from camcad.law.law import Kinematics
    >>> d = (2 * np.array([0.3]), np.array([2.0]), np.zeros(1), np.zeros(1))
    >>> y = Kinematics(np.zeros(1), np.array([0.6]), np.array([1.0]), np.array([4.0]), np.array([8.0]))
    >>> k = inverse_chain_rule(d, y, np.array([0.3]))
    >>> float(k.v[0]), float(k.a[0]), float(k.j[0])
    (0.5, 2.0, 4.0)
    """
    _, p1, p2, p3 = d
    v = y_kin.v / p1
    a = (y_kin.a - p2 * v ** 2) / p1
    j = (y_kin.j - p3 * v ** 3 - 3 * p2 * v * a) / p1
    return Kinematics(y_kin.theta, np.asarray(psi, dtype=float), v, a, j)


class _LawLike:
    """Shared parts of the laws below: cycle, phases and breakpoints of the underlying law."""

    base: Any = None

    @property
    def cycle(self) -> float:
        return self.base.cycle

    @property
    def phases(self):
        return self.base.phases

    def breakpoints(self) -> np.ndarray:
        inner = getattr(self.base, "breakpoints", None)
        points = list(np.asarray(inner()) if inner is not None else [])
        if isinstance(self.base, PiecewiseLinearLaw):
            points += list(self.base.x[:-1][np.diff(self.base.x) == 0])
        return np.array(sorted({float(p) for p in points}))


class WorkingLaw(_LawLike):
    """The working member's law y(θ) = Π(ψ(θ)) of a follower law ψ(θ) (follower units), through the chain
    rule; ``scale`` turns Π into the law's unit (e.g. 1 for rad).

    Examples
    --------
    >>> from camcad.law.standard import compose
    >>> law = compose([("rise", 180.0), ("return", 180.0)], 10.0, "cycloidal")
    >>> y = WorkingLaw(law, RatioTransfer(3.0, "mm", "mm"))
    >>> round(float(y.kinematics(np.array([math.pi])).s[0]), 12)
    30.0
    """

    def __init__(self, follower_law, transfer: Transfer, scale: float = 1.0):
        self.base = follower_law
        self.transfer = transfer
        self.scale = scale

    def kinematics(self, theta) -> Kinematics:
        psi = self.base.kinematics(np.asarray(theta, dtype=float))
        return chain_rule(self.transfer.derivatives(psi.s), psi, self.scale)

    def describe(self) -> str:
        inner = getattr(self.base, "describe", None)
        text = inner() if inner is not None else type(self.base).__name__
        return f"working member through {self.transfer.describe()}: {text}"


class FollowerLaw(_LawLike):
    """The follower's law ψ(θ) = Π⁻¹(y(θ)) designed for a working member's law y(θ) (``scale``: Π's unit
    per unit of that law, e.g. π/180 for a law in deg and Π in rad), then multiplied by ``out_scale`` (e.g. the arm
    length, to give the roller's arc in mm that camcad's oscillating follower turns back into ψ).

    Examples
    --------
    >>> from camcad.law.standard import compose
    >>> law = compose([("rise", 180.0), ("return", 180.0)], 30.0, "cycloidal")
    >>> psi = FollowerLaw(law, RatioTransfer(3.0, "mm", "mm"), psi_max=20.0)
    >>> round(float(psi.kinematics(np.array([math.pi])).s[0]), 12)
    10.0
    """

    def __init__(self, output_law, transfer: Transfer, psi_max: float, scale: float = 1.0, out_scale: float = 1.0):
        self.base = output_law
        self.transfer = transfer
        self.psi_max = float(psi_max)
        self.scale = scale
        self.out_scale = out_scale

    def kinematics(self, theta) -> Kinematics:
        y = self.base.kinematics(np.asarray(theta, dtype=float))
        f = self.scale
        y = Kinematics(y.theta, y.s * f, y.v * f, y.a * f, y.j * f)
        psi = self.transfer.inverse(y.s, self.psi_max)
        k = inverse_chain_rule(self.transfer.derivatives(psi), y, psi)
        f = self.out_scale
        return Kinematics(k.theta, f * k.s, f * k.v, f * k.a, f * k.j)

    def describe(self) -> str:
        inner = getattr(self.base, "describe", None)
        text = inner() if inner is not None else type(self.base).__name__
        return f"follower law designed through {self.transfer.describe()} for: {text}"


# --------------------------------------------------------------------------------------------
# The rigid driven system reduced to the follower
# --------------------------------------------------------------------------------------------

def reduced_inertia(inertia, d1):
    """The working member's inertia reduced to the follower, J Π'² (kg·m² per rad², or kg per …).

    Parameters
    ----------
    inertia : float
        J of the working member about its own coordinate (kg·m², or kg for a sliding member).
    d1 : array_like
        Π' in SI units (rad/rad, rad/m, m/rad or m/m).

    Returns
    -------
    ndarray
        J Π'².

    References
    ----------
    The batten study (the batten's J₂ behind П(φ)); Vulfson (2015) ch. 1.

    Examples
    --------
    >>> float(reduced_inertia(2.0, 0.5))
    0.5
    """
    return inertia * np.asarray(d1, dtype=float) ** 2


def follower_generalised_force(inertia, d1, d2, psi_dot, psi_ddot, load=0.0):
    """The generalised force the follower must supply to drive the rigid working member,
    M_ψ = J Π'² ψ̈ + J Π' Π'' ψ̇² + Π' Q (module docstring). SI units throughout: J kg·m² (or kg), Π' and
    Π'' per rad (or per m) of the follower, ψ̇ rad/s (m/s), ψ̈ rad/s² (m/s²), Q N·m (N, positive against
    the working member's motion); M_ψ N·m (N).

    Examples
    --------
    Constant ratio k: M = J k² ψ̈ + k Q.

    >>> float(follower_generalised_force(3.0, 2.0, 0.0, 10.0, 5.0, 1.0))
    62.0
    """
    d1 = np.asarray(d1, dtype=float)
    return inertia * d1 * (d1 * np.asarray(psi_ddot, dtype=float) + np.asarray(d2, dtype=float)
                           * np.asarray(psi_dot, dtype=float) ** 2) + d1 * np.asarray(load, dtype=float)


def kinetic_energy(inertia, d1, psi_dot):
    """T = ½ J Π'² ψ̇² (J), SI units as ``follower_generalised_force``.

    Examples
    --------
    >>> float(kinetic_energy(2.0, 0.5, 4.0))
    4.0
    """
    return 0.5 * reduced_inertia(inertia, d1) * np.asarray(psi_dot, dtype=float) ** 2


def si_factor(unit: str) -> float:
    """SI per unit of a coordinate: rad → 1, mm → 1e-3 (m).

    Examples
    --------
    >>> si_factor("mm"), si_factor("rad")
    (0.001, 1.0)
    """
    return 1e-3 if unit == "mm" else 1.0


@dataclass(frozen=True)
class LinkageLoad:
    """The working member's inertia and load reduced to the roller's path: F(θ, ω) = A(θ) ω² + B(θ), N, on
    the cam angles ``theta`` (rad); A in N·s² (N per (rad/s)²), B in N. Positive presses the follower
    on the cam (it resists the follower's motion away from the cam).

    Examples
    --------
    >>> load = LinkageLoad(np.zeros(2), np.array([1.0, 2.0]), np.array([0.5, 0.5]))
    >>> load.at(60.0 / (2 * math.pi))
    array([1.5, 2.5])
    """

    theta: np.ndarray
    per_omega2: np.ndarray
    static: np.ndarray

    def at(self, rpm: float) -> np.ndarray:
        """Force along the roller's path (N) at ``rpm``."""
        omega = 2.0 * math.pi * float(rpm) / 60.0
        return self.per_omega2 * omega ** 2 + self.static


def linkage_load(transfer: Transfer, psi_kin: Kinematics, inertia: float, load=0.0,
                 arm_mm: float | None = None) -> LinkageLoad:
    """The rigid working member reduced to the follower's roller path on the cam angles of ``psi_kin``
    (the follower's ψ, ψ', ψ'' per rad of cam angle, follower units).

    F = M_ψ / L (oscillating follower, L = ``arm_mm``) or M_ψ (translating), with ψ̇ = ψ' ω, ψ̈ = ψ'' ω²:
    A = J Π' (Π' ψ'' + Π'' ψ'²) / L and B = Π' Q / L (SI; Π' converted from the transfer's units).

    Parameters
    ----------
    transfer : Transfer
        Π with its units.
    psi_kin : Kinematics
        The follower's motion.
    inertia : float
        J, kg·m² (turning working member) or kg (sliding).
    load : float or ndarray
        Q on the working member, N·m or N (positive against its motion), per cam angle or constant.
    arm_mm : float or None
        The oscillating follower's arm length L (mm); None for a translating follower.

    Returns
    -------
    LinkageLoad

    Examples
    --------
    A sliding member of 2 kg through k = 3 on a translating follower with ψ'' = 100 mm/rad²:
    F = 2 · 3 · 3 · 0.1 m ω² = 1.8 ω² N.

    >>> k = Kinematics(np.zeros(1), np.zeros(1), np.zeros(1), np.array([100.0]), np.zeros(1))
    >>> round(float(linkage_load(RatioTransfer(3.0, "mm", "mm"), k, 2.0).per_omega2[0]), 12)
    1.8
    """
    d = transfer.derivatives(psi_kin.s)
    fin, fout = si_factor(transfer.unit_in), si_factor(transfer.unit_out)
    p1 = np.asarray(d[1], dtype=float) * fout / fin
    p2 = np.asarray(d[2], dtype=float) * fout / fin ** 2
    v = psi_kin.v * fin
    a = psi_kin.a * fin
    per_omega2 = follower_generalised_force(inertia, p1, p2, v, a, 0.0)
    static = p1 * np.asarray(load, dtype=float) * np.ones_like(p1)
    if arm_mm is not None:
        if transfer.unit_in != "rad":
            raise ValueError("an oscillating follower's motion is in rad")
        per_omega2 = per_omega2 / (arm_mm * 1e-3)
        static = static / (arm_mm * 1e-3)
    return LinkageLoad(np.asarray(psi_kin.theta, dtype=float), per_omega2, static)
