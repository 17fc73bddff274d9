"""Two motion laws on one mechanism, side by side: the figures the batten study compares its laws by.

The PhD abstract on the batten mechanism of the STB loom (Novosibirsk) judges every new law against the old
one on the same machine: the acceleration at the start of motion (−61 % after the resonant harmonic and its
neighbours were removed), the summary dynamic load at the start (3.45× lower with 14° lead-ins at 0.1 of
the peak), the accelerations (3.54× lower than the serial law's) and contact stresses (1.88× lower), the
contact-stress safety factor against shaft speed for both laws (its Fig. 10), and the deviation of the new
law's displacement from the old one (about 0.001 rad). ``compare_laws`` computes each of these for two
laws with the same models camcad's other commands use — rigid kinematics, the elastic follower of
``camcad dynamics`` (``run_dynamics``: the steady state over the speeds, the start-of-motion load with and
without the summary pulse, the residual vibration), the harmonic amplitudes of ``camcad spectrum`` and the
contact stress of ``camcad contact`` (given as its speed sweeps) — and puts them side by side as A, B and
A/B, each with the phase and the speed it applies to.

Units: the laws' displacement unit (mm, or rad/deg of swing); velocities and accelerations in SI (m/s,
m/s² for mm; rad/s, rad/s² for rad; deg/s, deg/s² for deg), as ``camcad dynamics`` reports them; stresses
MPa; speeds rpm; angles deg. Figures of one motion (the start of the rise) pair the n-th rise of A with
the n-th rise of B (each at its own angle, both named).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.model import rpm_to_rad_s
from camcad.dynamics.residual import motion_phases
from camcad.dynamics.runs import run_dynamics
from camcad.errors import CamcadError
from camcad.fourier.analysis import analyse
from camcad.law.law import MotionLaw

#: the window after a motion starts in which the start-of-motion figures are taken (deg): the batten study's
#: strain records show the load at the start within about the first 7°
START_WINDOW_DEG = 7.0
#: harmonics listed side by side
HARMONICS = 32
#: samples of the cycle for the displacement deviation (plus every knot and phase end)
DEVIATION_SAMPLES = 1 << 14
#: (SI scale, velocity unit, acceleration unit) of each law unit
RATE_UNITS = {"mm": (1e-3, "m/s", "m/s²"), "rad": (1.0, "rad/s", "rad/s²"), "deg": (1.0, "deg/s", "deg/s²")}


@dataclass(frozen=True)
class ComparedFigure:
    """One figure of two laws: its key ``name``, words, unit, the values for A and B, what it applies to
    (phase and speed), and the speed (rpm) and motion ("rise", "return", "rise_2", ...) when it has them."""

    name: str
    label: str
    unit: str
    a: float | None
    b: float | None
    applies: str
    rpm: float | None = None
    motion: str | None = None

    @property
    def ratio(self) -> float | None:
        """A/B (None when either is missing or B is zero)."""
        if self.a is None or self.b is None or self.b == 0.0:
            return None
        return self.a / self.b

    def to_dict(self) -> dict:
        out = {"name": self.name, "label": self.label, "unit": self.unit, "A": self.a, "B": self.b,
               "A/B": self.ratio, "applies": self.applies}
        if self.rpm is not None:
            out["rpm"] = self.rpm
        if self.motion is not None:
            out["motion"] = self.motion
        return out


@dataclass(frozen=True)
class LawComparison:
    """What ``compare_laws`` found: the figures side by side, the harmonic table, and the runs the plots
    need (``runs``: the DynamicsRun of A and B or None; ``contact``: their contact speed sweeps or None)."""

    figures: tuple[ComparedFigure, ...]
    harmonics: tuple[dict, ...]
    unit: str
    speeds: tuple[float, ...]
    laws: tuple[Any, Any]
    runs: tuple[Any, Any] = (None, None)
    contact: tuple[Any, Any] = (None, None)
    deviation: tuple[np.ndarray, np.ndarray] | None = None
    notes: tuple[str, ...] = ()
    window_deg: float = START_WINDOW_DEG

    def find(self, name: str, *, rpm: float | None = None, motion: str | None = None) -> ComparedFigure | None:
        """The figure ``name`` at ``rpm`` (None: the first one listed) of ``motion`` (None: the first)."""
        for figure in self.figures:
            if figure.name != name:
                continue
            if rpm is not None and (figure.rpm is None or abs(figure.rpm - rpm) > 1e-9 * max(rpm, 1.0)):
                continue
            if motion is not None and figure.motion != motion:
                continue
            return figure
        return None

    def to_dict(self) -> dict:
        return {"unit": self.unit, "speeds_rpm": list(self.speeds), "start_window_deg": self.window_deg,
                "figures": [f.to_dict() for f in self.figures], "harmonics": list(self.harmonics),
                "notes": list(self.notes)}


def _motion_labels(law: MotionLaw) -> list[tuple[str, Any]]:
    counts: dict[str, int] = {}
    labels = []
    for phase in motion_phases(law):
        counts[phase.kind] = counts.get(phase.kind, 0) + 1
        labels.append((phase.kind if counts[phase.kind] == 1 else f"{phase.kind}_{counts[phase.kind]}", phase))
    return labels


def _pairs(law_a: MotionLaw, law_b: MotionLaw) -> list[tuple[str, Any, Any]]:
    """(label, phase of A, phase of B) of the motions both laws have, in A's order."""
    theirs = dict(_motion_labels(law_b))
    return [(label, phase, theirs[label]) for label, phase in _motion_labels(law_a) if label in theirs]


def _window_max(theta: np.ndarray, values: np.ndarray, start: float, width: float, cycle: float) -> float:
    inside = np.mod(theta - start, cycle) <= width
    return float(np.max(np.abs(values[inside]))) if inside.any() else 0.0


def _start_grid(law: MotionLaw, start: float, width: float) -> np.ndarray:
    grid = start + np.linspace(0.0, width, 701)
    knots = getattr(law, "x", None)
    if knots is not None:
        knots = np.asarray(knots, dtype=float)
        grid = np.concatenate((grid, knots[(knots >= start) & (knots <= start + width)]))
    return unique(grid)


def displacement_deviation(law_a: MotionLaw, law_b: MotionLaw, samples: int = DEVIATION_SAMPLES
                           ) -> tuple[np.ndarray, np.ndarray]:
    """(θ rad, s_B − s_A) with both laws read from rest at s = 0 at θ = 0, on a uniform grid plus every knot
    and phase end of both laws."""
    cycle = law_a.cycle
    parts = [np.arange(samples + 1) * (cycle / samples)]
    for law in (law_a, law_b):
        parts.append(np.array([p.start for p in law.phases] + [p.end for p in law.phases]))
        knots = getattr(law, "x", None)
        if knots is not None:
            parts.append(np.asarray(knots, dtype=float))
    grid = np.concatenate(parts)
    grid = unique(grid[(grid >= 0.0) & (grid <= cycle)])
    s_a = law_a.kinematics(grid).s - law_a.kinematics(np.zeros(1)).s[0]
    s_b = law_b.kinematics(grid).s - law_b.kinematics(np.zeros(1)).s[0]
    return grid, s_b - s_a


def compare_laws(law_a: MotionLaw, law_b: MotionLaw, speeds: list[float], *, settings=None, unit: str = "mm",
                 harmonics: int = HARMONICS, window_deg: float = START_WINDOW_DEG, contact=(None, None),
                 runs=None, progress: Callable[[str], None] | None = None) -> LawComparison:
    """Two laws on one mechanism, side by side (module docstring).

    Parameters
    ----------
    law_a, law_b : MotionLaw
        The laws (same cycle, θ in rad; displacement in mm, or rad/deg of swing: ``unit``).
    speeds : list of float
        Cam speeds, rpm (the first is the residual-vibration speed, the fastest the start-of-motion one,
        as ``camcad dynamics`` takes them).
    settings : camcad.scene.dynamics.DynamicsSettings or None
        The elastic follower (None: the rigid, harmonic and contact figures only).
    unit : str
        The laws' displacement unit: "mm", "rad" or "deg".
    harmonics : int
        Harmonics listed side by side.
    window_deg : float
        The start-of-motion window after each motion starts, deg.
    contact : (SpeedSweep or None, SpeedSweep or None)
        The contact stress of A and B against speed (``camcad.contact.stress_versus_speed``), when the
        mechanism has it.
    runs : (DynamicsRun, DynamicsRun) or None
        ``run_dynamics`` of A and B at ``speeds`` already computed (e.g. of the working member through a
        [linkage]); None: computed here from ``settings``.
    progress : callable or None
        Called with a short text as each law's elastic model runs.

    Returns
    -------
    LawComparison
        The figures of A and B and A/B: lengths in the laws' unit (mm, or rad/deg), velocities m/s (rad/s),
        accelerations m/s² (rad/s²), stresses MPa, speeds rpm; the harmonic amplitudes in the laws' unit.

    Examples
    --------
    A law against itself: every ratio is 1. A cycloidal rise of 20 mm over 90° peaks at
    a = 2πh/β² = 50.93 mm/rad², i.e. 50.93e-3 × (2π·300/60)² = 50.27 m/s² at 300 rpm:

    >>> import camcad
    >>> law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 20.0)
    >>> found = compare_laws(law, law, [300.0])
    >>> {f.ratio for f in found.figures if f.ratio is not None}
    {1.0}
    >>> round(found.find("peak_accel_rigid").a, 2)
    50.27
    """
    if abs(law_a.cycle - law_b.cycle) > 1e-9 * law_a.cycle:
        raise CamcadError(f"the laws have different cycles ({math.degrees(law_a.cycle):g} and "
                          f"{math.degrees(law_b.cycle):g} deg)", "compare", "compare laws of one cycle")
    say = progress or (lambda _text: None)
    scale, v_unit, a_unit = RATE_UNITS[unit]
    speeds = [float(s) for s in speeds]
    fastest = max(speeds)
    shown = sorted({speeds[0], fastest})
    window = math.radians(window_deg)
    cycle = law_a.cycle
    figures: list[ComparedFigure] = []
    notes: list[str] = []
    grid = np.linspace(0.0, cycle, 8193)
    kin = []
    for law in (law_a, law_b):
        knots = getattr(law, "x", None)
        points = grid if knots is None else unique(np.concatenate((grid, np.asarray(knots, dtype=float))))
        kin.append(law.kinematics(points))
    stroke = [float(np.ptp(k.s)) for k in kin]
    figures.append(ComparedFigure("stroke", "stroke (lift or swing)", unit, stroke[0], stroke[1], "over the cycle"))
    deviation = displacement_deviation(law_a, law_b)
    worst = int(np.argmax(np.abs(deviation[1])))
    figures.append(ComparedFigure("displacement_deviation", "largest |s_B - s_A| (both from rest at s = 0)", unit,
                                  float(abs(deviation[1][worst])), None,
                                  f"at {math.degrees(deviation[0][worst]):.4g} deg"))
    figures.append(ComparedFigure("displacement_deviation_rms", "RMS of s_B - s_A", unit,
                                  float(np.sqrt(np.mean(deviation[1] ** 2))), None, "over the cycle"))
    for rpm in speeds:
        omega = rpm_to_rad_s(rpm)
        v = [float(np.max(np.abs(k.v))) * omega * scale for k in kin]
        a = [float(np.max(np.abs(k.a))) * omega**2 * scale for k in kin]
        figures.append(ComparedFigure("peak_velocity", "peak velocity (rigid)", v_unit, v[0], v[1],
                                      f"over the cycle at {rpm:g} rpm", rpm))
        figures.append(ComparedFigure("peak_accel_rigid", "peak acceleration (rigid)", a_unit, a[0], a[1],
                                      f"over the cycle at {rpm:g} rpm", rpm))
    pairs = _pairs(law_a, law_b)
    if len(pairs) < max(len(motion_phases(law_a)), len(motion_phases(law_b))):
        notes.append("the laws have different motions: only the rises and returns both have are paired")
    omega = rpm_to_rad_s(fastest)
    for label, pa, pb in pairs:
        values = []
        for law, phase in ((law_a, pa), (law_b, pb)):
            theta = _start_grid(law, phase.start, window)
            values.append(float(np.max(np.abs(law.kinematics(theta).a))) * omega**2 * scale)
        figures.append(ComparedFigure(
            "start_accel_rigid", f"acceleration at the start of the {label} (rigid)", a_unit, values[0], values[1],
            f"first {window_deg:g} deg of the {label} (A from {math.degrees(pa.start):.4g}, B from "
            f"{math.degrees(pb.start):.4g} deg) at {fastest:g} rpm", fastest, label))
    if runs is None and settings is not None:
        found = []
        for name, law in (("A", law_a), ("B", law_b)):
            say(f"law {name}: elastic follower over {len(speeds)} speeds")
            found.append(run_dynamics(law, settings, speeds))
        runs = (found[0], found[1])
    if runs is not None and runs[0] is not None and runs[1] is not None:
        figures.extend(_elastic_figures(runs, pairs, speeds, fastest, window, window_deg, scale, a_unit, unit))
    sweeps = contact
    if sweeps[0] is not None and sweeps[1] is not None:
        for index, rpm in enumerate(np.asarray(sweeps[0].rpm, dtype=float)):
            other = int(np.argmin(np.abs(np.asarray(sweeps[1].rpm) - rpm)))
            figures.append(ComparedFigure("sigma_max", "largest contact stress", "MPa",
                                          float(sweeps[0].sigma_max[index]), float(sweeps[1].sigma_max[other]),
                                          f"over the cycle at {rpm:g} rpm", float(rpm)))
            figures.append(ComparedFigure("safety_factor", "contact-stress safety factor [sigma_H]/sigma_max", "",
                                          float(sweeps[0].safety_factor[index]),
                                          float(sweeps[1].safety_factor[other]), f"at {rpm:g} rpm", float(rpm)))
    count = max(1, int(harmonics))
    spectra = [analyse(law, count) for law in (law_a, law_b)]
    table = []
    for k in range(1, count + 1):
        amp_a, amp_b = float(spectra[0].amplitudes[k - 1]), float(spectra[1].amplitudes[k - 1])
        table.append({"k": k, f"A_{unit}": amp_a, f"B_{unit}": amp_b, "A/B": amp_a / amp_b if amp_b else None,
                      "A_phase_deg": float(np.degrees(spectra[0].phases[k - 1])),
                      "B_phase_deg": float(np.degrees(spectra[1].phases[k - 1]))})
    figures.sort(key=lambda f: (_ORDER.get(f.name, 99), f.rpm not in shown if f.rpm is not None else False))
    return LawComparison(tuple(figures), tuple(table), unit, tuple(speeds), (law_a, law_b),
                         tuple(runs) if runs is not None else (None, None), sweeps, deviation, tuple(notes), window_deg)


_ORDER = {name: i for i, name in enumerate((
    "stroke", "displacement_deviation", "displacement_deviation_rms", "peak_velocity", "peak_accel_rigid",
    "peak_accel_elastic", "peak_accel_ratio", "dynamic_error_max", "start_accel_rigid", "start_accel_elastic",
    "start_load", "start_load_pulse", "start_deformation", "residual_vibration", "sigma_max", "safety_factor"))}


def _elastic_figures(runs: tuple[Any, Any], pairs, speeds, fastest, window, window_deg, scale, a_unit,
                     unit) -> list[ComparedFigure]:
    """Figures of the elastic follower (``run_dynamics`` of A and B)."""
    figures = []
    for index, rpm in enumerate(speeds):
        for name, label, key, u in (("peak_accel_elastic", "peak acceleration (elastic)", "peak_accel_elastic", a_unit),
                                    ("peak_accel_ratio", "peak acceleration elastic/rigid", "peak_accel_ratio", ""),
                                    ("dynamic_error_max", "largest dynamic error |y - s|", "dynamic_error_max",
                                     unit)):
            values = []
            for run in runs:
                array = getattr(run.sweep, key)
                value = float(array[index]) * (scale if key == "peak_accel_elastic" else 1.0)
                values.append(value if math.isfinite(value) else None)
            figures.append(ComparedFigure(name, label, u, values[0], values[1], f"over the cycle at {rpm:g} rpm",
                                          rpm))
    responses = [run.sweep.responses.get(fastest) for run in runs]
    loads = [run.report.get("start_load", {}).get("phases", []) for run in runs]
    accel_key = next((k for k in (loads[0][0] if loads[0] else {}) if k.startswith("peak_link_accel_")), None)
    for label, pa, pb in pairs:
        applies = (f"first {window_deg:g} deg of the {label} (A from {math.degrees(pa.start):.4g}, B from "
                   f"{math.degrees(pb.start):.4g} deg) at {fastest:g} rpm")
        if all(r is not None for r in responses):
            accel = [_window_max(r.theta, r.accel_elastic, p.start, window, law_cycle(r)) * scale
                     for r, p in zip(responses, (pa, pb))]
            figures.append(ComparedFigure("start_accel_elastic", f"acceleration at the start of the {label} "
                                          "(elastic)", a_unit, accel[0], accel[1], applies, fastest, label))
            deformation = [_window_max(r.theta, r.dynamic_error, p.start, window, law_cycle(r))
                           for r, p in zip(responses, (pa, pb))]
            figures.append(ComparedFigure("start_deformation", f"deformation |y - s| at the start of the {label}",
                                          unit, deformation[0], deformation[1], applies, fastest, label))
        found = [next((e for e in load if abs(e["start_deg"] - math.degrees(p.start)) < 1e-9), None)
                 for load, p in zip(loads, (pa, pb))]
        entries = [e for e in found if e is not None]
        if accel_key is not None and len(entries) == 2:
            one_period = (f"one free period after the start of the {label} (A {math.degrees(pa.start):.4g}, B "
                          f"{math.degrees(pb.start):.4g} deg) at {fastest:g} rpm")
            figures.append(ComparedFigure("start_load", f"load in the elastic link at the start of the {label} "
                                          "(per unit mass)", a_unit, entries[0][accel_key], entries[1][accel_key],
                                          one_period, fastest, label))
            if all("with_pulse" in e for e in entries):
                ratio = entries[0]["with_pulse"]["pulse_ratio"]
                figures.append(ComparedFigure(
                    "start_load_pulse", f"summary dynamic load at the start of the {label} (pulse "
                    f"{ratio:g} x peak, half the free period)", a_unit, entries[0]["with_pulse"][accel_key],
                    entries[1]["with_pulse"][accel_key], one_period, fastest, label))
    for label, pa, pb in pairs:
        found = [next((r for r in run.report["residual_vibration_phases"]
                       if abs(r["start_deg"] - math.degrees(p.start)) < 1e-9), None)
                 for run, p in zip(runs, (pa, pb))]
        entries = [e for e in found if e is not None]
        if len(entries) == 2:
            key = next(k for k in entries[0] if k.startswith("amplitude"))
            figures.append(ComparedFigure(
                "residual_vibration", f"residual vibration after the {label} (started from rest)", unit,
                entries[0][key], entries[1][key], f"after the {label} at {speeds[0]:g} rpm", speeds[0], label))
    return figures


def law_cycle(response) -> float:
    """The cycle (rad) a steady-state response covers: its samples are uniform over one cycle."""
    theta = np.asarray(response.theta, dtype=float)
    return float(theta[1] - theta[0]) * len(theta) if len(theta) > 1 else 2.0 * math.pi


__all__ = ["HARMONICS", "START_WINDOW_DEG", "ComparedFigure", "LawComparison", "compare_laws",
           "displacement_deviation"]

