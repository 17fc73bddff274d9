"""The scene's ``[drive]`` section: the speed fluctuation allowed, the motor, its gearbox and the inertias on the
camshaft (``camcad drive``, ``camcad.scene.commands.drive``).

``[drive]`` (all optional):

- ``delta``: the coefficient of speed fluctuation allowed, δ = (ω_max − ω_min)/ω_m (a number or "1/30");
- ``motor``: "servo" (a speed-controlled drive holds the speed: the motor gives the torque as the cam asks, its
  RMS and peak are checked) or "induction" (a mains motor on a flywheel: it gives the mean torque and the
  flywheel takes the fluctuation, δ is checked);
- ``gear_ratio`` i = n_motor/n_cam, ``gear_efficiency`` η; ``motor_rated_torque``, ``motor_peak_torque``
  (N·m at the motor), ``motor_max_speed`` (rpm), ``motor_inertia`` (kg·m², rotor and gearbox input);
- ``flywheel_inertia`` and ``shaft_inertia`` (kg·m², on the camshaft), with each ``[load] cam_inertia``;
- ``run_up_s``: the time to reach the speed from rest (s), for the run-up torque.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from camcad.errors import CamcadError, excerpt
from camcad.scene.fields import Field, read_table

MOTORS = ("servo", "induction")

DRIVE_FIELDS: list[Field] = [
    Field("delta", minimum=0.0, maximum=1.0,
          help="(allowed coefficient of speed fluctuation (n_max - n_min)/n_mean, e.g. 0.0333 or \"1/30\")"),
    Field("motor", "str", default="servo", choices=MOTORS,
          help="servo: the drive holds the speed; induction: a mains motor, the flywheel takes the fluctuation"),
    Field("gear_ratio", default=1.0, positive=True, help="(motor speed / camshaft speed)"),
    Field("gear_efficiency", default=1.0, minimum=0.01, maximum=1.0, help="(of the gearbox, a fraction)"),
    Field("motor_rated_torque", unit="N m", positive=True, help="(the motor's rated (continuous) torque)"),
    Field("motor_peak_torque", unit="N m", positive=True, help="(the motor's peak (short-time) torque)"),
    Field("motor_max_speed", unit="rpm", positive=True, help="(the motor's highest speed)"),
    Field("motor_inertia", unit="kg m^2", minimum=0.0, help="(rotor and gearbox input, at the motor shaft)"),
    Field("flywheel_inertia", unit="kg m^2", minimum=0.0, help="(a flywheel on the camshaft)"),
    Field("shaft_inertia", unit="kg m^2", minimum=0.0, help="(the camshaft's other turning parts: gears, pulleys)"),
    Field("run_up_s", unit="s", positive=True, help="(time to reach the speed from rest, for the run-up torque)"),
]


@dataclass(frozen=True)
class DriveSpec:
    """A parsed ``[drive]`` (module docstring); None where the scene does not give a value."""
    delta: float | None = None
    motor: str = "servo"
    gear_ratio: float = 1.0
    gear_efficiency: float = 1.0
    motor_rated_torque: float | None = None
    motor_peak_torque: float | None = None
    motor_max_speed: float | None = None
    motor_inertia: float = 0.0
    flywheel_inertia: float | None = None
    shaft_inertia: float = 0.0
    run_up_s: float | None = None
    given: tuple[str, ...] = ()


def parse_fraction(value: Any, where: str, key: str = "delta") -> Any:
    """``value`` as given, or a text "a/b" as the number a/b (for δ = "1/30")."""
    if not isinstance(value, str):
        return value
    parts = value.replace(" ", "").split("/")
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        numbers = []
    if len(numbers) not in (1, 2) or (len(numbers) == 2 and numbers[1] == 0.0):
        raise CamcadError(f"'{key}' is {excerpt(value)}, not a number or a fraction", where,
                          f'write {key} = 0.0333 or {key} = "1/30"')
    return numbers[0] if len(numbers) == 1 else numbers[0] / numbers[1]


def parse_drive(table: Any, where: str) -> DriveSpec:
    """A scene's ``[drive]`` table → DriveSpec (None → no drive data); every mistake is one line."""
    if table is None:
        return DriveSpec()
    if isinstance(table, dict) and "delta" in table:
        table = {**table, "delta": parse_fraction(table["delta"], where)}
    values = read_table(table, DRIVE_FIELDS, where)
    if values["delta"] is not None and not 0.0 < values["delta"] < 1.0:
        raise CamcadError(f"'delta' {values['delta']:g} is not a speed fluctuation in (0, 1)", where,
                          'write delta = "1/30" (a loom), "1/50" or smaller for a precise drive')
    if (values["motor_rated_torque"] is not None and values["motor_peak_torque"] is not None
            and values["motor_peak_torque"] < values["motor_rated_torque"]):
        raise CamcadError(f"motor_peak_torque {values['motor_peak_torque']:g} N m is below motor_rated_torque "
                          f"{values['motor_rated_torque']:g} N m", where, "give the motor's short-time peak torque")
    given = tuple(k for k in table if k in values)
    return DriveSpec(values["delta"], values["motor"], values["gear_ratio"], values["gear_efficiency"],
                     values["motor_rated_torque"], values["motor_peak_torque"], values["motor_max_speed"],
                     values["motor_inertia"] or 0.0, values["flywheel_inertia"], values["shaft_inertia"] or 0.0,
                     values["run_up_s"], given)
