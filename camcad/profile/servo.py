"""Servo (electronic cam) tables: the follower's motion as a slave axis against the camshaft as master.

A servo axis that replaces the cam does the follower's law s(θ) directly: the master is the camshaft's angle
θ (deg), the slave the follower's position (mm of lift, or deg of swing for an oscillating follower). The table
gives, at every ``step`` deg of the master, the slave's position and its derivatives per master degree,

    ds/dθ° = (π/180) v,   d²s/dθ°² = (π/180)² a,   d³s/dθ°³ = (π/180)³ j    (v, a, j per rad: the law's analogs)

and, at a master speed n (rpm, ω = 2πn/60 rad/s), per second: ṡ = v ω, s̈ = a ω², s⃛ = j ω³. Normalised, the
slave is a fraction of its stroke (max s − min s) and its derivatives are divided by the stroke too.

The slave's peak velocity, acceleration and jerk at the speed size the servo: they are refined between the
law's breakpoints (``camcad.extrema.zoom_max``), not read off the table. A law whose acceleration jumps (a
harmonic rise from a dwell, a drawn law's vertical step) asks for an infinite jerk there: the jumps are listed
and the jerk reported is the largest finite one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.extrema import zoom_max

FORMATS = ("csv", "codesys", "twincat")
#: an acceleration step larger than this fraction of the law's peak acceleration is a jump (infinite jerk)
JUMP_FRACTION = 1e-9
#: master steps the tables take: 1e-3 deg to 90 deg (at most 360 000 rows)
MIN_STEP_DEG, MAX_STEP_DEG = 1e-3, 90.0


@dataclass(frozen=True)
class ServoExport:
    """What ``camcad profile --export servo`` writes.

    Parameters
    ----------
    step_deg : float
        Master step of the table, deg.
    fmt : str
        "csv" (servo_table.csv only), "codesys" (also servo_codesys.txt) or "twincat" (also servo_twincat.st).
    normalise : bool
        The slave as a fraction of its stroke (no unit) instead of mm or deg.
    rpm : float or None
        The master speed for the columns per second and the peaks, rpm; None: the scene's highest speed.

    Examples
    --------
    >>> ServoExport(step_deg=0.5, fmt="codesys").validated().step_deg
    0.5
    """

    step_deg: float = 1.0
    fmt: str = "csv"
    normalise: bool = False
    rpm: float | None = None

    def validated(self) -> ServoExport:
        """The settings, or a one-line CamcadError naming the option at fault."""
        if not (math.isfinite(self.step_deg) and MIN_STEP_DEG <= self.step_deg <= MAX_STEP_DEG):
            raise CamcadError(f"--servo-step {self.step_deg:g} deg is not in {MIN_STEP_DEG:g}..{MAX_STEP_DEG:g} deg",
                              "--servo-step", "give the master step in deg, e.g. 1 or 0.5")
        if self.fmt not in FORMATS:
            raise CamcadError(f"--servo-format {self.fmt!r} is not one of {', '.join(FORMATS)}", "--servo-format",
                              "use csv, codesys (CODESYS SoftMotion ASCII table) or twincat (TwinCAT motion function)")
        if self.rpm is not None and not (math.isfinite(self.rpm) and self.rpm > 0.0):
            raise CamcadError(f"--servo-rpm {self.rpm:g} is not a speed", "--servo-rpm", "give the master speed in rpm")
        return self


def servo_export(kinds: str | None, step_deg: float = 1.0, fmt: str = "csv", normalise: bool = False,
                 rpm: float | None = None) -> ServoExport | None:
    """The servo export ``--export KINDS`` asks for (a comma list, whose kinds ``camcad.scene.sections.export``
    checks; None or without "servo": None), validated; a --servo-* option without ``--export servo`` is a one-line
    CamcadError.

    Examples
    --------
    >>> servo_export("servo", 0.5).step_deg, servo_export(None)
    (0.5, None)
    """
    wanted = [k.strip().lower() for k in (kinds or "").split(",") if k.strip()]   # checked by the part's parser
    if "servo" not in wanted:
        if (step_deg, fmt, normalise, rpm) != (1.0, "csv", False, None):
            raise CamcadError("--servo-* options shape the servo table, which is not asked for", "--export",
                              "add --export servo")
        return None
    return ServoExport(float(step_deg), fmt.strip().lower(), bool(normalise), rpm).validated()


@dataclass(frozen=True)
class ServoTable:
    """The table: ``master_deg`` and the slave's ``position``, ``velocity``, ``acceleration``, ``jerk`` per
    master degree (``unit``: "mm", "deg" or "1" for normalised; per deg, deg², deg³); ``rpm`` the master speed
    (None: none given) and ``stroke`` (the slave's travel in its own unit, mm or deg)."""

    master_deg: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    unit: str
    stroke: float
    rpm: float | None = None

    @property
    def omega_deg_s(self) -> float | None:
        """The master speed in deg/s (None without a speed)."""
        return None if self.rpm is None else 6.0 * self.rpm

    def per_second(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(velocity, acceleration, jerk) per second at ``rpm`` (unit/s, /s², /s³), or None."""
        w = self.omega_deg_s
        if w is None:
            return None
        return self.velocity * w, self.acceleration * w**2, self.jerk * w**3


def slave_law(law, unit: str):
    """(scale, unit): the factor from the law's s to the slave's unit — 1 for mm, 180/π for a swing in rad."""
    if unit == "rad":
        return 180.0 / math.pi, "deg"
    return 1.0, unit


def servo_table(law, step_deg: float = 1.0, *, scale: float = 1.0, unit: str = "mm", normalise: bool = False,
                rpm: float | None = None) -> ServoTable:
    """The servo table of a law: master θ (deg) every ``step_deg`` over one turn, 0 and 360 included.

    Parameters
    ----------
    law : MotionLaw
        The follower's law (θ rad; s in its unit, v, a, j per rad).
    step_deg : float
        Master step, deg; it must divide 360 within 1e-9.
    scale : float
        The slave's unit per unit of the law's s, a ratio (1 for mm; 180/π for a swing in rad → deg).
    unit : str
        The slave's unit after ``scale`` ("mm" or "deg").
    normalise : bool
        The slave as a fraction of its stroke (unit "1").
    rpm : float, optional
        The master speed, rpm.

    Returns
    -------
    ServoTable
        Master angles (deg), the slave's position (mm, deg or a fraction) and its derivatives per master degree.

    Examples
    --------
    A cycloidal rise of 10 mm over 90°: halfway the slave is at 5 mm moving at 2h/β = 12.732 mm/rad,
    0.2222 mm per master degree:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 10.0)
    >>> table = servo_table(law, 45.0)
    >>> table.master_deg[:2].tolist(), round(float(table.position[1]), 12), round(float(table.velocity[1]), 6)
    ([0.0, 45.0], 5.0, 0.222222)
    """
    count = 360.0 / step_deg
    if abs(count - round(count)) > 1e-9 * count:
        raise CamcadError(f"--servo-step {step_deg:g} deg does not divide 360 deg", "--servo-step",
                          "give a step that divides a turn, e.g. 1, 0.5, 0.25 or 2")
    master = np.arange(round(count) + 1) * step_deg
    master[-1] = 360.0
    kin = law.kinematics(np.radians(master))
    per = math.pi / 180.0
    s, v, a, j = kin.s * scale, kin.v * scale * per, kin.a * scale * per**2, kin.j * scale * per**3
    dense = law.kinematics(np.linspace(0.0, float(law.cycle), 20001)).s * scale
    stroke = float(np.ptp(dense))
    if normalise:
        if not stroke > 0.0:
            raise CamcadError("the law has no stroke to normalise", "--servo-normalise", "drop --servo-normalise")
        base = float(np.min(dense))
        s, v, a, j = (s - base) / stroke, v / stroke, a / stroke, j / stroke
        unit = "1"
    return ServoTable(master, s, v, a, j, unit, stroke, rpm)


@dataclass(frozen=True)
class SlavePeaks:
    """The slave's peaks over the turn (per master degree and, with a speed, per second) and where (deg);
    ``jumps_deg`` the master angles where the acceleration jumps (infinite jerk) with their size per deg²."""

    velocity_per_deg: float
    velocity_at_deg: float
    acceleration_per_deg2: float
    acceleration_at_deg: float
    jerk_per_deg3: float
    jerk_at_deg: float
    jumps_deg: tuple[tuple[float, float], ...]
    unit: str
    rpm: float | None

    def to_dict(self) -> dict:
        """The figures with their units in the keys (the slave's unit: mm, deg or 1 for normalised)."""
        u = self.unit
        out = {"unit": u, f"velocity_peak_{u}_per_deg": self.velocity_per_deg,
               "velocity_peak_at_deg": self.velocity_at_deg,
               f"acceleration_peak_{u}_per_deg2": self.acceleration_per_deg2,
               "acceleration_peak_at_deg": self.acceleration_at_deg,
               f"jerk_peak_{u}_per_deg3": self.jerk_per_deg3, "jerk_peak_at_deg": self.jerk_at_deg,
               "acceleration_jumps": [{"at_deg": at, f"size_{u}_per_deg2": size} for at, size in self.jumps_deg],
               "jerk_infinite": bool(self.jumps_deg), "rpm": self.rpm}
        if self.rpm is not None:
            w = 6.0 * self.rpm
            out.update({f"velocity_peak_{u}_s": self.velocity_per_deg * w,
                        f"acceleration_peak_{u}_s2": self.acceleration_per_deg2 * w**2,
                        f"jerk_peak_{u}_s3": self.jerk_per_deg3 * w**3})
        return out


def slave_peaks(law, breakpoints, *, scale: float = 1.0, unit: str = "mm", rpm: float | None = None,
                stroke: float | None = None) -> SlavePeaks:
    """Peak |velocity|, |acceleration| and |jerk| of the slave (per master degree; refined between the law's
    ``breakpoints``, rad) and the acceleration's jumps. ``stroke`` divides everything (normalised tables).

    Examples
    --------
    Cycloidal rise of h = 10 mm over β = 90°: peaks 2h/β, 2πh/β² and 4π²h/β³ per rad (Norton 2009, §3.8):

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 10.0)
    >>> p = slave_peaks(law, [0.0, math.pi / 2, math.pi, 1.5 * math.pi, 2 * math.pi])
    >>> beta = math.pi / 2
    >>> round(p.velocity_per_deg / (math.pi / 180), 9) == round(2 * 10 / beta, 9)
    True
    >>> round(p.jerk_per_deg3 / (math.pi / 180) ** 3, 6) == round(4 * math.pi**2 * 10 / beta**3, 6), p.jumps_deg
    (True, ())
    """
    cycle = float(law.cycle)
    edges = unique(np.concatenate((np.asarray(breakpoints, dtype=float), [0.0, cycle])))
    inner = 1e-12 * cycle
    grid = unique(np.concatenate((np.linspace(0.0, cycle, 7201), edges, np.clip(edges - inner, 0, cycle),
                                  np.clip(edges + inner, 0, cycle))))

    def rows(u):
        u = np.asarray(u, dtype=float)
        flat = u.ravel() if u.ndim > 1 else u
        kin = law.kinematics(flat)
        values = np.stack((np.abs(kin.v), np.abs(kin.a), np.abs(kin.j)))
        if u.ndim > 1:
            values = values.reshape((3,) + u.shape)[np.arange(3), np.arange(3)]
        return values

    top, at = zoom_max(rows, grid, 3)
    per = math.pi / 180.0
    divide = stroke if stroke else 1.0
    factors = np.array([per, per**2, per**3]) * scale / divide
    peak_a = float(top[1])
    jumps = []
    for b in edges:
        left = law.kinematics(np.array([max(b - inner, 0.0)])).a[0]
        right = law.kinematics(np.array([min(b + inner, cycle)])).a[0]
        if b in (0.0, cycle):
            left = law.kinematics(np.array([cycle - inner])).a[0]
            right = law.kinematics(np.array([inner])).a[0]
        if abs(right - left) > JUMP_FRACTION * max(peak_a, 1e-300):
            jumps.append((math.degrees(b % cycle), float((right - left) * factors[1])))
    found = sorted({round(at_deg, 9): size for at_deg, size in jumps}.items())
    degrees = np.degrees(np.mod(at, cycle))
    return SlavePeaks(float(top[0] * factors[0]), float(degrees[0]), float(top[1] * factors[1]), float(degrees[1]),
                      float(top[2] * factors[2]), float(degrees[2]), tuple(found), "1" if stroke else unit, rpm)
