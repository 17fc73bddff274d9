"""Dynamics of the driven chain: the elastic follower (single DOF and the multi-mass model) and stop impacts.

- ``sdof``: the follower's reduced mass on the chain's spring; periodic steady state in the frequency
  domain and by time marching, speed sweeps, residual vibration, load at the start of motion; the
  scene's ``[dynamics]`` section (``DYNAMICS_FIELDS``, ``parse_dynamics``).
- ``multimass``: flywheel, elastic shaft, cam, position function and elastic chain (Lagrange).
- ``impact``: lever on a limit stop, impulse, triangular pulse, Duhamel response, rebound against speed
  and phase angle; the scene's ``[stops]`` section (``STOPS_FIELDS``, ``parse_stops``).
"""

from camcad.dynamics.impact import (STOPS_FIELDS, Impact, ImpactSweep, ReboundRelation, StopModel, find_contact, impact_at,
                     impact_force, impact_impulse, impact_sweep, lever_stiffness, parse_stops, reduced_mass,
                     triangular_pulse_response)
from camcad.dynamics.multimass import MotorDrive, MultiMassModel, MultiMassResult, SpeedDrive, simulate
from camcad.dynamics.sdof import (DYNAMICS_FIELDS, DynamicsSettings, ElasticFollower, HalfSinePulse, LawSpectrum, Residual,
                   Response, StartLoad, StiffnessTable, Sweep, cycloidal_residual_amplitude, damping_ratio_from_psi,
                   law_spectrum, parse_dynamics, residual_vibration, rpm_to_rad_s, start_loads, start_pulse,
                   steady_state, steady_state_frequency, steady_state_time, sweep, transient_time)

__all__ = [
    "DYNAMICS_FIELDS", "DynamicsSettings", "ElasticFollower", "HalfSinePulse", "LawSpectrum", "Residual", "Response",
    "StartLoad", "StiffnessTable", "Sweep", "cycloidal_residual_amplitude", "damping_ratio_from_psi", "law_spectrum",
    "parse_dynamics", "residual_vibration", "rpm_to_rad_s", "start_loads", "start_pulse", "steady_state",
    "steady_state_frequency", "steady_state_time", "sweep", "transient_time",
    "MotorDrive", "MultiMassModel", "MultiMassResult", "SpeedDrive", "simulate",
    "STOPS_FIELDS", "Impact", "ImpactSweep", "ReboundRelation", "StopModel", "find_contact", "impact_at",
    "impact_force", "impact_impulse", "impact_sweep", "lever_stiffness", "parse_stops", "reduced_mass",
    "triangular_pulse_response",
]
