"""The summary dynamic load at the start of a motion (the batten study: a half-sine pulse of half the free period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.dynamics.model import ElasticFollower, HalfSinePulse, rpm_to_rad_s
from camcad.dynamics.residual import motion_phases
from camcad.dynamics.steady import Response
from camcad.law.law import MotionLaw, Phase

#: a law whose displacement or velocity does not return to its start within this fraction of the
#: lift (per rad for the velocity) has a break: its periodic response is meaningless. The same
#: tolerance as ``camcad check``, so every law that passes the check can be analysed.
CLOSURE_TOLERANCE = BALANCE_TOLERANCE
DEFAULT_SAMPLES = 16384
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: frequency path: a harmonic whose |D_k| = |ωn² − Ω_k² + 2iζωnΩ_k| is at most this fraction of ωn² is in
#: resonance. The exact response there is unbounded (ζ = 0) and the computed one is ruled by the round-off
#: of Ω_k (relative error ≈ 4e-16/|D_k/ωn²|, 4e-6 at this bound), so it is refused instead.
RESONANCE_DETUNING = 1e-10
#: time path: an eigenvalue λ of the monodromy matrix with |1 − λ| ≤ this × rtol is resonance. The shooting
#: solve divides by 1 − λ, and the marched monodromy carries an error of the order of rtol, so the response
#: would be ruled by integration error (measured: relative error ≈ 0.02–0.1 rtol/|1 − λ|, ≤ 1e-3 here).
RESONANCE_GAP_PER_RTOL = 100.0



# --------------------------------------------------------------------------------------------
# Load at the start of motion
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StartLoad:
    """Peak force in the elastic link within one free period after a motion phase starts (``start_loads``).

    Attributes
    ----------
    phase : Phase
        The motion (rad).
    peak_link_accel : float
        The peak, law units/s² (mm/s² or rad/s²; × mass = force).
    at_deg : float
        The cam angle of the peak, deg.
    peak_rigid_accel : float
        The law's own peak in the same window, law units/s².
    force_n : float, optional
        The force, N (N·m for a rad output); None when the mass is unknown.
    """

    phase: Phase
    peak_link_accel: float
    at_deg: float
    peak_rigid_accel: float
    force_n: float | None


def start_pulse(law: MotionLaw, follower: ElasticFollower, rpm: float, phase: Phase, ratio: float) -> HalfSinePulse:
    """The summary dynamic load at the start of ``phase``: a half-sine lasting half the free period.

    Applied as an external load opposing the motion's initial acceleration, of amplitude
    ``ratio`` × the phase's peak rigid acceleration (mm/s²). Source: the batten study (a jump of
    acceleration at the start of motion, varying sinusoidally, lasting about half the free period).

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    follower : ElasticFollower
        The follower (Hz).
    rpm : float
        The speed, rpm.
    phase : Phase
        The motion (rad).
    ratio : float
        The pulse over the phase's peak rigid acceleration (dimensionless).

    Returns
    -------
    HalfSinePulse
        Start and width in rad, amplitude in mm/s².

    Examples
    --------
    At 60 rpm (1 rev/s) half the free period of a 10 Hz follower is 0.05 s, 18 deg of cam angle:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> import math
    >>> from camcad.dynamics import start_pulse
    >>> pulse = start_pulse(law, camcad.ElasticFollower(10.0), 60.0, law.phases[0], 0.3)
    >>> round(math.degrees(pulse.start), 9), round(math.degrees(pulse.width), 9), pulse.amplitude < 0
    (0.0, 18.0, True)
    """
    omega = rpm_to_rad_s(rpm)
    theta = np.linspace(phase.start, phase.end, 513)
    a = law.kinematics(theta).a
    peak = float(np.max(np.abs(a))) * omega**2
    first = a[np.flatnonzero(np.abs(a) > 1e-9 * np.max(np.abs(a)))[0]] if np.any(a) else 1.0
    width = omega * 0.5 / follower.natural_frequency_hz
    return HalfSinePulse(phase.start, width, -math.copysign(ratio * peak, first), law.cycle)


def start_loads(response: Response, law: MotionLaw, follower: ElasticFollower, unit_scale: float = 1e-3
                ) -> list[StartLoad]:
    """Start-of-motion loads of every rise and return, read from a steady-state response.

    ``unit_scale`` turns the law's unit into SI (1e-3 for mm → m, 1 for rad), so the force is
    mass × peak × unit_scale in N (N·m for a rad output with the mass in kg·m²).

    Parameters
    ----------
    response : Response
        A steady state (``camcad.steady_state``).
    law : MotionLaw
        Its law (θ in rad).
    follower : ElasticFollower
        Its follower (Hz, kg).
    unit_scale : float
        SI units per law unit (1e-3 for mm; dimensionless ratio).

    Returns
    -------
    list of StartLoad
        One per motion: the peak link acceleration (law units/s²), its angle (deg), the force (N).

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> from camcad.dynamics import start_loads
    >>> follower = camcad.ElasticFollower(40.0, damping_ratio=0.1, mass_kg=1.0)
    >>> loads = start_loads(camcad.steady_state(law, follower, 120.0), law, follower)
    >>> [load.phase.kind for load in loads], all(load.force_n > 0 for load in loads)
    (['rise', 'return'], True)
    """
    omega = rpm_to_rad_s(response.rpm)
    window = omega / follower.natural_frequency_hz   # one free period, in rad of cam angle
    out = []
    for phase in motion_phases(law):
        u = np.mod(response.theta - phase.start, law.cycle)
        mask = u <= window
        if not np.any(mask):
            continue
        link = np.abs(response.link_accel[mask])
        i = int(np.argmax(link))
        peak = float(link[i])
        at = float(np.degrees(response.theta[mask][i]))
        rigid = float(np.max(np.abs(response.accel_rigid[mask])))
        force = None if follower.mass_kg is None else follower.mass_kg * peak * unit_scale
        out.append(StartLoad(phase, peak, at, rigid, force))
    return out




