"""Dynamics of the driven chain: the elastic follower (single DOF and the multi-mass model) and stop impacts.

Modules, one concept each:

- ``model``: the follower's reduced mass on the chain's spring (units, stiffness tables, loads);
- ``spectrum``: the sampled displacement spectrum the frequency-domain response uses;
- ``steady``: the periodic steady state (frequency domain and time marching) and speed sweeps;
- ``residual``: residual vibration after a motion phase that starts from rest;
- ``startload``: the summary dynamic load at the start of a motion;
- ``multimass``: flywheel, elastic shaft, cam, position function and elastic chain (Lagrange);
- ``impact``: a lever on a limit stop: impulse, triangular pulse, Duhamel response, rebound;
- ``runs``: the analyses over a speed range with their reports, shared by the CLI and the scene pipeline.

The scene sections ``[dynamics]`` and ``[stops]`` are read by ``camcad.scene.sections.dynamics`` and
``camcad.scene.sections.stops``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camcad.lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
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
    from camcad.dynamics.multimass import MotorDrive, MultiMassModel, MultiMassResult, SpeedDrive, simulate
    from camcad.dynamics.residual import Residual, cycloidal_residual_amplitude, residual_vibration
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

#: public name -> the module that defines it (imported on first use: importing this package stays cheap)
_EXPORTS: dict[str, str] = {
    "ElasticFollower": "camcad.dynamics.model",
    "HalfSinePulse": "camcad.dynamics.model",
    "Impact": "camcad.dynamics.impact",
    "ImpactSweep": "camcad.dynamics.impact",
    "LawSpectrum": "camcad.dynamics.spectrum",
    "MotorDrive": "camcad.dynamics.multimass",
    "MultiMassModel": "camcad.dynamics.multimass",
    "MultiMassResult": "camcad.dynamics.multimass",
    "ReboundRelation": "camcad.dynamics.impact",
    "Residual": "camcad.dynamics.residual",
    "ResonanceError": "camcad.dynamics.steady",
    "Response": "camcad.dynamics.steady",
    "SpeedDrive": "camcad.dynamics.multimass",
    "StartLoad": "camcad.dynamics.startload",
    "StiffnessTable": "camcad.dynamics.model",
    "StopModel": "camcad.dynamics.impact",
    "Sweep": "camcad.dynamics.steady",
    "check_closure": "camcad.dynamics.spectrum",
    "cycloidal_residual_amplitude": "camcad.dynamics.residual",
    "damping_ratio_from_psi": "camcad.dynamics.model",
    "find_contact": "camcad.dynamics.impact",
    "first_rebound": "camcad.dynamics.impact",
    "impact_at": "camcad.dynamics.impact",
    "impact_force": "camcad.dynamics.impact",
    "impact_impulse": "camcad.dynamics.impact",
    "impact_sweep": "camcad.dynamics.impact",
    "law_spectrum": "camcad.dynamics.spectrum",
    "lever_stiffness": "camcad.dynamics.impact",
    "reduced_mass": "camcad.dynamics.impact",
    "residual_vibration": "camcad.dynamics.residual",
    "response_after_impact": "camcad.dynamics.impact",
    "rpm_to_rad_s": "camcad.dynamics.model",
    "simulate": "camcad.dynamics.multimass",
    "start_loads": "camcad.dynamics.startload",
    "start_pulse": "camcad.dynamics.startload",
    "steady_state": "camcad.dynamics.steady",
    "steady_state_frequency": "camcad.dynamics.steady",
    "steady_state_time": "camcad.dynamics.steady",
    "sweep": "camcad.dynamics.steady",
    "transient_time": "camcad.dynamics.steady",
    "triangular_pulse": "camcad.dynamics.impact",
    "triangular_pulse_response": "camcad.dynamics.impact",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


__all__ = [
    "ElasticFollower",
    "HalfSinePulse",
    "Impact",
    "ImpactSweep",
    "LawSpectrum",
    "MotorDrive",
    "MultiMassModel",
    "MultiMassResult",
    "ReboundRelation",
    "Residual",
    "ResonanceError",
    "Response",
    "SpeedDrive",
    "StartLoad",
    "StiffnessTable",
    "StopModel",
    "Sweep",
    "check_closure",
    "cycloidal_residual_amplitude",
    "damping_ratio_from_psi",
    "find_contact",
    "first_rebound",
    "impact_at",
    "impact_force",
    "impact_impulse",
    "impact_sweep",
    "law_spectrum",
    "lever_stiffness",
    "reduced_mass",
    "residual_vibration",
    "response_after_impact",
    "rpm_to_rad_s",
    "simulate",
    "start_loads",
    "start_pulse",
    "steady_state",
    "steady_state_frequency",
    "steady_state_time",
    "sweep",
    "transient_time",
    "triangular_pulse",
    "triangular_pulse_response",
]
