"""``camcad profile … --export servo``: the servo (electronic cam) table of each mechanism, as a CSV and in the
text forms two servo systems read (``camcad.profile.servo`` computes the numbers).

- ``servo_table.csv``: ``#`` comment lines (the mechanism, the units, the speed, the slave's peaks), then the
  columns master angle (deg), slave position, velocity per master degree, acceleration per master degree²
  (docs/INTERFACE.md: these four first), jerk per master degree³ and, with a speed, velocity, acceleration and jerk per
  second.
- ``servo_codesys.txt`` (``--servo-format codesys``): the ASCII table of the CODESYS SoftMotion cam editor
  (CODESYS V3.5, SM3_Basic; commands "Read Cam Data from ASCII Table" / "Write Cam Data to ASCII Table"): one
  X/Y pair per line — master position, a tab, slave position — with no header, since "the ASCII table does not
  contain any information about cams". The editor interpolates the points with fifth-degree polynomials and
  lets the user thin them ("Number of points"). Not covered: the editor's .CAM online files (SMC_ReadCAM),
  tappets, the element-optimised (two-dimensional) tables and the slave's derivatives, which this format cannot
  carry.
- ``servo_twincat.st`` (``--servo-format twincat``): a TwinCAT 3 NC Camming (TF5050, PLC library
  Tc2_MC2_Camming) motion function — an IEC 61131-3 Structured Text global variable list holding
  ``ARRAY[1..N] OF MC_MotionFunctionPoint`` for MC_WriteMotionFunction, one point per table row with
  PointIndex 1..N, FunctionType MOTIONFUNCTYPE_POLYNOM5_MM (a fifth-order polynomial between points with the
  given position, velocity and acceleration at both ends), PointType REST/VELOCITY/TURN/MOTION from the
  slave's state, RelIndexNextPoint 1, MasterPos, SlavePos, SlaveVelo, SlaveAcc, SlaveJerk (velocity,
  acceleration and jerk per master unit: the motion function's master velocity is normed to 1). Not covered:
  the XAE cam-design editor's project files, position tables (MC_TableType), the TF55xx MC3 MotionFunctionPoint
  structure, the scaling and activation options of MC_CamIn.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.profile.scaled_law import law_breakpoints
from camcad.profile.servo import ServoExport, servo_table, slave_law, slave_peaks

#: a slave velocity or acceleration below this fraction of its peak is zero when the TwinCAT point type is chosen
POINT_ZERO = 1e-9
_UNIT_WORDS = {"mm": "mm", "deg": "deg", "1": "stroke"}


def _number(value: float) -> str:
    return f"{value:.12g}"


def servo_csv(table, peaks, name: str) -> str:
    """The text of servo_table.csv (module docstring)."""
    u = table.unit
    word = _UNIT_WORDS[u]
    what = {"mm": "the follower's lift, mm", "deg": "the follower's swing, deg",
            "1": f"the follower's position as a fraction of its stroke ({table.stroke:.9g})"}[u]
    header = [f"camcad servo table: {name}; master = the camshaft's angle, deg; slave = {what}",
              f"units: master_deg deg; position {word}; velocity {word}/deg, acceleration {word}/deg^2, jerk "
              f"{word}/deg^3 (per master degree)" + (f"; at {table.rpm:g} rpm: {word}/s, {word}/s^2, {word}/s^3"
                                                     if table.rpm is not None else "; no speed given")]
    p = peaks.to_dict()
    line = (f"peaks: velocity {p[f'velocity_peak_{u}_per_deg']:.6g} {word}/deg at {p['velocity_peak_at_deg']:.4g} deg, "
            f"acceleration {p[f'acceleration_peak_{u}_per_deg2']:.6g} {word}/deg^2 at "
            f"{p['acceleration_peak_at_deg']:.4g} deg, jerk {p[f'jerk_peak_{u}_per_deg3']:.6g} {word}/deg^3 at "
            f"{p['jerk_peak_at_deg']:.4g} deg")
    header.append(line)
    if table.rpm is not None:
        header.append(f"peaks at {table.rpm:g} rpm: velocity {p[f'velocity_peak_{u}_s']:.6g} {word}/s, acceleration "
                      f"{p[f'acceleration_peak_{u}_s2']:.6g} {word}/s^2, jerk {p[f'jerk_peak_{u}_s3']:.6g} {word}/s^3")
    if peaks.jumps_deg:
        where = ", ".join(f"{a:.6g} deg" for a, _ in peaks.jumps_deg)
        header.append(f"the acceleration jumps (infinite jerk) at {where}; the jerk above is the largest finite one")
    tag = {"mm": "mm", "deg": "deg", "1": "norm"}[u]
    names = ["master_deg", f"position_{tag}", f"velocity_{tag}_per_deg", f"accel_{tag}_per_deg2",
             f"jerk_{tag}_per_deg3"]
    columns = [table.master_deg, table.position, table.velocity, table.acceleration, table.jerk]
    timed = table.per_second()
    if timed is not None:
        names += [f"velocity_{tag}_s", f"accel_{tag}_s2", f"jerk_{tag}_s3"]
        columns += list(timed)
    data = np.column_stack(columns)
    lines = [f"# {text}" for text in header] + [",".join(names)]
    lines.extend(",".join(_number(v) for v in row) for row in data)
    return "\n".join(lines) + "\n"


def st_real(value: float) -> str:
    """An IEC 61131-3 REAL literal (digits, a point, digits, an optional exponent): 0.0, 12.5, 1.5E-05.

    Examples
    --------
    >>> st_real(0.0), st_real(12.0), st_real(-1.5e-5), st_real(1e20)
    ('0.0', '12.0', '-1.5E-05', '1.0E+20')
    """
    text = f"{float(value):.12g}".upper()
    mantissa, _, exponent = text.partition("E")
    if "." not in mantissa:
        mantissa += ".0"
    return mantissa + (f"E{exponent}" if exponent else "")


def codesys_table(table) -> str:
    """The CODESYS SoftMotion ASCII table: "X<TAB>Y" per line, master deg and slave position, no header."""
    return "".join(f"{x:.9f}\t{y:.12g}\n" for x, y in zip(table.master_deg, table.position))


def _identifier(name: str) -> str:
    text = re.sub(r"\W", "_", name, flags=re.ASCII).strip("_") or "cam"
    return ("cam_" + text) if not text[0].isalpha() else text


def point_type(velocity: float, acceleration: float, v_peak: float, a_peak: float) -> str:
    """MC_MotionPointType of a point: REST (v = a = 0), VELOCITY (a = 0), TURN (v = 0), MOTION (neither)."""
    still = abs(velocity) <= POINT_ZERO * max(v_peak, 1e-300)
    even = abs(acceleration) <= POINT_ZERO * max(a_peak, 1e-300)
    if still and even:
        return "MOTIONPOINTTYPE_REST"
    if even:
        return "MOTIONPOINTTYPE_VELOCITY"
    if still:
        return "MOTIONPOINTTYPE_TURN"
    return "MOTIONPOINTTYPE_MOTION"


def twincat_motion_function(table, name: str) -> str:
    """The TwinCAT 3 NC Camming motion function as a Structured Text GVL (module docstring)."""
    ident = _identifier(name)
    count = len(table.master_deg)
    v_peak = float(np.max(np.abs(table.velocity))) if count else 0.0
    a_peak = float(np.max(np.abs(table.acceleration))) if count else 0.0
    unit = {"mm": "mm", "deg": "deg", "1": "fraction of the stroke"}[table.unit]
    rows = []
    for k in range(count):
        kind = point_type(table.velocity[k], table.acceleration[k], v_peak, a_peak)
        rows.append(f"        (PointIndex := {k + 1}, FunctionType := MOTIONFUNCTYPE_POLYNOM5_MM, PointType := {kind}, "
                    f"RelIndexNextPoint := 1, MasterPos := {st_real(table.master_deg[k])}, "
                    f"SlavePos := {st_real(table.position[k])}, SlaveVelo := {st_real(table.velocity[k])}, "
                    f"SlaveAcc := {st_real(table.acceleration[k])}, SlaveJerk := {st_real(table.jerk[k])})")
    return (f"(* camcad servo cam: {name}. TwinCAT 3 NC Camming (TF5050, Tc2_MC2_Camming): a motion function for\n"
            f"   MC_WriteMotionFunction. Master: the camshaft's angle, deg (0..360); slave: {unit}; SlaveVelo,\n"
            f"   SlaveAcc, SlaveJerk per master degree (the master velocity normed to 1). {count} points. *)\n"
            "VAR_GLOBAL\n"
            f"    {ident}_points : ARRAY[1..{count}] OF MC_MotionFunctionPoint := [\n"
            + ",\n".join(rows) + "\n    ];\nEND_VAR\n")


def servo_files(export) -> tuple[str, ...]:
    """The files ``write_servo`` writes for the servo export ``export`` (None: none)."""
    if export is None:
        return ()
    own = {"codesys": ("servo_codesys.txt",), "twincat": ("servo_twincat.st",)}.get(export.fmt, ())
    return ("servo_table.csv", *own)


def write_servo(run, out, sub: tuple[str, ...], export: ServoExport, speeds) -> tuple[list[Path], dict]:
    """servo_table.csv (and the format's own file) of one mechanism of the scene pipeline (``run``: a
    MechanismRun) into the OutputFolder ``out`` (subfolder ``sub``); returns (paths, the report's ``servo``
    object). The slave is the follower's motion the cam makes (its profile's law: mm, or deg of swing)."""
    export = export.validated()
    if run.profile is not None:
        law = run.profile.geometry.law
        unit = "rad" if run.profile.follower.kind == "oscillating" else "mm"
    else:
        law, unit = run.law, "mm"
    scale, slave_unit = slave_law(law, unit)
    rpm = export.rpm if export.rpm is not None else (max(speeds) if speeds else None)
    table = servo_table(law, export.step_deg, scale=scale, unit=slave_unit, normalise=export.normalise, rpm=rpm)
    peaks = slave_peaks(law, law_breakpoints(law), scale=scale, unit=slave_unit, rpm=rpm,
                        stroke=table.stroke if export.normalise else None)
    written = [write_text_atomic(out.path(*sub, "servo_table.csv"), servo_csv(table, peaks, run.name))]
    if export.fmt == "codesys":
        written.append(write_text_atomic(out.path(*sub, "servo_codesys.txt"), codesys_table(table)))
    elif export.fmt == "twincat":
        written.append(write_text_atomic(out.path(*sub, "servo_twincat.st"), twincat_motion_function(table, run.name)))
    report = {"step_deg": export.step_deg, "format": export.fmt, "normalised": export.normalise,
              "rows": len(table.master_deg), "stroke": table.stroke, "stroke_unit": slave_unit,
              "slave": peaks.to_dict(), "outputs": [str(p) for p in written]}
    if rpm is None:
        report["note"] = "no speed: give --servo-rpm or [machine] rpm for the slave's figures per second"
    if not math.isclose(float(law.cycle), 2.0 * math.pi):
        report["note_lobes"] = f"the law repeats every {math.degrees(float(law.cycle)):g} deg of the master"
    return written, report
