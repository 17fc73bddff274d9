"""Dynamics of the driven chain: the elastic follower (single DOF and the multi-mass model) and stop impacts.

Modules, one concept each:

- ``model``: the follower's reduced mass on the chain's spring (units, stiffness tables, loads);
- ``spectrum``: the sampled displacement spectrum the frequency-domain response uses;
- ``steady``: the periodic steady state (frequency domain and time marching) and speed sweeps;
- ``residual``: residual vibration after a motion phase that starts from rest;
- ``startload``: the summary dynamic load at the start of a motion (seed 001);
- ``multimass``: flywheel, elastic shaft, cam, position function and elastic chain (Lagrange);
- ``impact``: a lever on a limit stop: impulse, triangular pulse, Duhamel response, rebound (seed 000);
- ``runs``: the analyses over a speed range with their reports, shared by the CLI and the scene pipeline.

The scene sections ``[dynamics]`` and ``[stops]`` are read by ``camcad.scene.dynamics`` and
``camcad.scene.stops``.
"""

from __future__ import annotations

from camcad.dynamics.impact import (
                                    Impact,
                                    ImpactSweep,
                                    ReboundRelation,
                                    StopModel,
                                    find_contact,
                                    first_rebound,
                                    impact_at,
                                    impact_force,
                                    impact_impulse,
                                    impact_sweep,
                                    lever_stiffness,
                                    reduced_mass,
                                    response_after_impact,
                                    triangular_pulse,
                                    triangular_pulse_response,
)
from camcad.dynamics.model import (
                                    ElasticFollower,
                                    HalfSinePulse,
                                    StiffnessTable,
                                    damping_ratio_from_psi,
                                    rpm_to_rad_s,
)
from camcad.dynamics.multimass import (
                                    MotorDrive,
                                    MultiMassModel,
                                    MultiMassResult,
                                    SpeedDrive,
                                    simulate,
)
from camcad.dynamics.residual import (
                                    Residual,
                                    cycloidal_residual_amplitude,
                                    residual_vibration,
)
from camcad.dynamics.spectrum import LawSpectrum, check_closure, law_spectrum
from camcad.dynamics.startload import StartLoad, start_loads, start_pulse
from camcad.dynamics.steady import (
                                    ResonanceError,
                                    Response,
                                    Sweep,
                                    steady_state,
                                    steady_state_frequency,
                                    steady_state_time,
                                    sweep,
                                    transient_time,
)

__all__ = [
    "ElasticFollower", "HalfSinePulse", "Impact", "ImpactSweep", "LawSpectrum", "MotorDrive", "MultiMassModel",
    "MultiMassResult", "ReboundRelation", "Residual", "ResonanceError", "Response", "SpeedDrive", "StartLoad", "StiffnessTable",
    "StopModel", "Sweep", "check_closure", "cycloidal_residual_amplitude", "damping_ratio_from_psi", "find_contact",
    "first_rebound", "impact_at", "impact_force", "impact_impulse", "impact_sweep", "law_spectrum",
    "lever_stiffness", "reduced_mass", "residual_vibration", "response_after_impact", "rpm_to_rad_s", "simulate",
    "start_loads", "start_pulse", "steady_state", "steady_state_frequency", "steady_state_time", "sweep",
    "transient_time", "triangular_pulse", "triangular_pulse_response",
]
