"""The scene's ``[load]`` section: a mechanism's process force, its higher pair's friction, its cam's inertia
and, when stated, gravity — what ``camcad drive`` adds to the follower's inertia, spring and preload of
``[contact]``.

- ``force`` (N) constant over ``phase`` (a motion phase of the law as the pipeline ends with it: "rise",
  "return", "rise_2", …) or over ``range_deg`` = [start, end] (cam angles, deg); or a ``table`` of
  [[theta_deg, force_N], …] rows, or a ``file`` (.csv/.txt, two columns θ deg, F N), the force against the cam
  angle, periodic, ``interpolation`` "linear" or "step" (each row's force holds until the next row). The force
  acts along the follower's path and resists its motion away from the cam (positive presses the follower onto
  the cam), as ``[contact] load`` does; it adds to that load.
- ``pair_friction``: the friction coefficient of the higher pair — sliding for a flat face or a knife edge;
  for a roller, its bearing and rolling resistance referred to its rim (μ_pin r_pin/Rr + f_roll/Rr). The
  guide's friction is ``[contact] friction``.
- ``cam_inertia`` (kg·m²): the cam's own moment of inertia about the camshaft (the flywheel and the run-up
  count it).
- ``gravity_up_deg``: the direction of "up" in the cam's drawing (deg from +x, counter-clockwise; a
  translating follower moves along +y, so 90 means it lifts straight up). Without it gravity is not counted.
  The follower's weight m g (m the ``[contact]`` mass) acts on its path point; its component along the path
  direction resists the motion away from the cam when that direction points up.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from camcad.errors import CamcadError, excerpt
from camcad.io.table_read import read_table as read_rows
from camcad.scene.fields import Field, read_table

#: standard gravity, m/s² (CGPM 1901)
STANDARD_GRAVITY = 9.80665
INTERPOLATIONS = ("linear", "step")

LOAD_FIELDS: list[Field] = [
    Field("force", unit="N", help="(a constant process force over 'phase' or 'range_deg'; or give 'table')"),
    Field("phase", "str", help="(the motion phase the force acts in: rise, return, rise_2, ...)"),
    Field("range_deg", "list", unit="deg", help="([start, end] cam angles where 'force' acts)"),
    Field("table", "list", unit="[deg, N]", help="([[theta_deg, force_N], ...]: the force against the cam angle)"),
    Field("file", "str", help="(a .csv/.txt table of theta_deg, force_N rows, beside the scene)"),
    Field("interpolation", "str", default="linear", choices=INTERPOLATIONS,
          help="between the table's rows: linear, or step (each row's force holds until the next row)"),
    Field("pair_friction", minimum=0.0, maximum=1.0,
          help="(friction coefficient of the higher pair; a roller's bearing friction referred to its rim)"),
    Field("cam_inertia", unit="kg m^2", minimum=0.0, help="(the cam's own moment of inertia about the camshaft)"),
    Field("gravity_up_deg", unit="deg",
          help="(the direction of up in the cam's drawing, deg from +x; 90: the follower lifts straight up)"),
]


@dataclass(frozen=True)
class ProcessLoad:
    """A process force along the follower's path, N, as a function of the cam angle (rad).

    Either a constant ``force`` over the angles [``start``, ``end``] (rad, periodic) or a table
    (``theta`` rad, ``values`` N) interpolated linearly or held stepwise (``step``), periodic over 2π.
    """

    force: float = 0.0
    start: float | None = None
    end: float | None = None
    theta: np.ndarray | None = None
    values: np.ndarray | None = None
    step: bool = False

    def __call__(self, theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        t = np.mod(theta, 2.0 * math.pi)
        if self.theta is None:
            if self.start is None or self.end is None:
                return np.full_like(t, self.force)
            inside = np.mod(t - self.start, 2.0 * math.pi) <= np.mod(self.end - self.start, 2.0 * math.pi)
            return np.where(inside, self.force, 0.0)
        xs, ys = self.theta, self.values
        assert ys is not None
        if self.step:
            index = np.searchsorted(xs, t, side="right") - 1     # -1: before the first row, the last one holds
            return ys[index]
        # one period of knots with the wrap-around segment
        x = np.concatenate(([xs[-1] - 2.0 * math.pi], xs, [xs[0] + 2.0 * math.pi]))
        y = np.concatenate(([ys[-1]], ys, [ys[0]]))
        return np.interp(t, x, y)

    def breakpoints(self) -> np.ndarray:
        """θ (rad) where the force may jump or kink."""
        if self.theta is not None:
            return np.mod(self.theta, 2.0 * math.pi)
        if self.start is None or self.end is None:
            return np.zeros(0)
        return np.mod(np.array([self.start, self.end]), 2.0 * math.pi)


@dataclass(frozen=True)
class LoadSpec:
    """A parsed ``[load]``: the process force (None: none), the pair friction, the cam inertia (kg·m²),
    the direction of up (deg, None: no gravity) and the phase the force names (resolved on the law)."""

    where: str
    force: ProcessLoad | None
    pair_friction: float
    cam_inertia: float
    gravity_up_deg: float | None
    phase: str | None = None
    notes: tuple[str, ...] = ()

    def on_law(self, law) -> ProcessLoad | None:
        """The process force with its ``phase`` placed on ``law``'s phases (as the pipeline ends with them)."""
        if self.force is None or self.phase is None:
            return self.force
        counts: dict[str, int] = {}
        for phase in law.phases:
            if phase.kind == "dwell":
                continue
            counts[phase.kind] = counts.get(phase.kind, 0) + 1
            label = phase.kind if counts[phase.kind] == 1 else f"{phase.kind}_{counts[phase.kind]}"
            if label == self.phase:
                return ProcessLoad(self.force.force, float(phase.start), float(phase.end))
        labels = []
        counts = {}
        for phase in law.phases:
            if phase.kind != "dwell":
                counts[phase.kind] = counts.get(phase.kind, 0) + 1
                labels.append(phase.kind if counts[phase.kind] == 1 else f"{phase.kind}_{counts[phase.kind]}")
        raise CamcadError(f"the law has no phase {excerpt(self.phase)}", self.where,
                          f"use one of {', '.join(labels) or '(none: the law has no motion)'} or range_deg")


def parse_load(table: Any, where: str, base_dir: Path) -> LoadSpec:
    """A scene's ``[load]`` table → LoadSpec; every mistake is one line naming ``where``.

    Parameters
    ----------
    table : dict
        The raw TOML table.
    where : str
        "scene.toml [load]" for messages.
    base_dir : Path
        The scene's folder (a ``file`` is relative to it).

    Returns
    -------
    LoadSpec
    """
    values = read_table(table, LOAD_FIELDS, where)
    force, phase, span, rows, file = (values[k] for k in ("force", "phase", "range_deg", "table", "file"))
    given = [k for k, v in (("force", force), ("table", rows), ("file", file)) if v is not None]
    if len(given) > 1:
        raise CamcadError(f"{' and '.join(given)} both give the process force", where,
                          "give a constant force (with phase or range_deg), a table or a file")
    if force is None and (phase is not None or span is not None):
        raise CamcadError("'phase' and 'range_deg' place a constant 'force', which is not given", where,
                          "add force = ... (N)")
    if phase is not None and span is not None:
        raise CamcadError("'phase' and 'range_deg' both place the force", where, "give one of them")
    if values["interpolation"] != "linear" and rows is None and file is None:
        raise CamcadError("'interpolation' is for a table of forces", where, "drop it or give table = [...]")
    process = None
    notes: list[str] = []
    if force is not None:
        if span is not None:
            start, end = _span(span, where)
            process = ProcessLoad(force, math.radians(start), math.radians(end))
        else:
            process = ProcessLoad(force)
            if phase is None:
                notes.append(f"the process force {force:g} N acts over the whole cycle")
    elif rows is not None or file is not None:
        theta, forces = _rows(rows, file, where, base_dir)
        process = ProcessLoad(theta=np.radians(theta), values=forces, step=values["interpolation"] == "step")
    up = values["gravity_up_deg"]
    return LoadSpec(where, process, values["pair_friction"] or 0.0, values["cam_inertia"] or 0.0, up, phase,
                    tuple(notes))


def _span(value, where: str) -> tuple[float, float]:
    if (len(value) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x)
                               for x in value)):
        raise CamcadError(f"'range_deg' must be [start, end] in deg, got {excerpt(value)}", where,
                          "write range_deg = [40.0, 110.0]")
    return float(value[0]), float(value[1])


def _rows(rows, file, where: str, base_dir: Path) -> tuple[np.ndarray, np.ndarray]:
    if file is not None:
        path = (base_dir / file).resolve()
        if not path.is_file():
            raise CamcadError(f"load table {excerpt(file)} not found", where, "give the path relative to the scene")
        found = read_rows(path)
        theta, forces = np.asarray(found.theta_deg, dtype=float), np.asarray(found.accel, dtype=float)
        where = f"{where} file {file}"
    else:
        pairs = []
        for i, row in enumerate(rows):
            if (not isinstance(row, list) or len(row) != 2 or any(
                    isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in row)):
                raise CamcadError(f"table row {i + 1} is {excerpt(row)}, not [theta_deg, force_N]", where,
                                  "write table = [[0.0, 0.0], [90.0, 250.0], ...]")
            pairs.append((float(row[0]), float(row[1])))
        if not pairs:
            raise CamcadError("the load table is empty", where, "give at least one [theta_deg, force_N] row")
        theta, forces = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    if np.any(np.diff(theta) <= 0.0):
        raise CamcadError("the load table's angles must increase", where, "sort the rows by angle, no repeats")
    if theta[0] < 0.0 or theta[-1] >= 360.0:
        raise CamcadError(f"the load table's angles {theta[0]:g}..{theta[-1]:g} deg are not within [0, 360)",
                          where, "give cam angles from 0 to below 360 deg (the table is periodic)")
    if np.any(np.abs(forces) > 1e9):
        raise CamcadError("a load of more than 1e9 N", where, "give forces in N")
    return theta, forces


def gravity_load(mass_kg: float, up_deg: float, cam):
    """The follower's weight along its path, N (θ rad → array), for a [contact] mass (kg) and "up" at
    ``up_deg`` (deg from +x in the cam's drawing): F = m g (d · u), d the unit direction of the path point's
    motion away from the cam (``Track.outward`` of the CamGeometry ``cam``), u the unit vector up — positive
    when moving away from the cam lifts the mass.
    """
    up = np.array([math.cos(math.radians(up_deg)), math.sin(math.radians(up_deg))])

    def weight(theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        outward = cam.track(theta).outward
        return mass_kg * STANDARD_GRAVITY * (outward @ up)

    return weight
