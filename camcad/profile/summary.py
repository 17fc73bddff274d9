"""The report of a synthesised profile: the docs/INTERFACE.md ``profile`` keys with every check's margin.

Angles in degrees, lengths in mm; figures rounded to their meaningful digits by the JSON writer.
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np

from camcad.profile.followers import Follower
from camcad.profile.scaled_law import describe_law, describe_phases
from camcad.profile.synth import CurveResult, Extremum, PressureAngleCheck, ProfileResult
from camcad.profile.verdict import profile_verdict
from camcad.verdict import Verdict


def _verdict_keys(verdict: Verdict) -> dict:
    data = verdict.to_dict()
    return {"checks": data["checks"], "tightest": data["tightest"], "warnings": data["warnings"],
            "passed": data["passed"]}



def _deg(x: float | None) -> float | None:
    return None if x is None else math.degrees(x)


def _value(e: Extremum | None) -> float | None:
    return None if e is None else e.value


def _at_deg(e: Extremum | None) -> float | None:
    return None if e is None else math.degrees(e.at)


def _pressure_dict(check: PressureAngleCheck, follower: Follower) -> dict:
    return {
        "passed": check.passed,
        "limit_rise_deg": follower.pressure_angle_limit_rise_deg,
        "limit_return_deg": follower.pressure_angle_limit_return_deg,
        "reversible": follower.reversible,
        "max_deg": _deg(check.maximum.value), "max_at_deg": _at_deg(check.maximum),
        "min_deg": _deg(check.minimum.value), "min_at_deg": _at_deg(check.minimum),
        "rise_max_deg": _deg(_value(check.rise_max)), "rise_max_at_deg": _at_deg(check.rise_max),
        "return_max_deg": _deg(_value(check.return_max)), "return_max_at_deg": _at_deg(check.return_max),
        "worst_margin_deg": _deg(_value(check.worst_margin)),
        "worst_margin_at_deg": _at_deg(check.worst_margin),
    }


def _curve_dict(curve: CurveResult) -> dict:
    return {"points": len(curve.polyline.points), "closed": curve.closed,
            "closure_gap_mm": curve.closure_gap, "simple": curve.simple,
            "rho_min_mm": _value(curve.rho_convex_min), "rho_min_at_deg": _at_deg(curve.rho_convex_min),
            "rho_concave_min_mm": _value(curve.rho_concave_min),
            "max_deviation_mm": curve.polyline.max_deviation,
            "arc_segments": None if curve.arcs is None else len(curve.arcs.bulges)}


def stroke(result: ProfileResult) -> float:
    """max(s) − min(s) over the cycle, follower units (mm, or rad for the oscillating follower)."""
    return float(np.ptp(result.table.s))


def profile_report(result: ProfileResult, phases: str = "the law's own phase angles") -> dict:
    """The report of a synthesised cam: the docs/INTERFACE.md ``profile`` keys with every check's margin.

    ``checks`` holds every check as ``{"value", "limit", "margin", "passed", "why", ...}``
    (``camcad.profile.verdict``), ``tightest`` their names with the least relative margin first,
    ``warnings`` what an engineer would flag, ``passed`` the verdict; ``phase_angles`` says whose
    phase angles the law has.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``synthesize``).
    phases : str
        Whose phase angles the law has, in words (no unit), repeated in each check's ``why``.

    Returns
    -------
    dict
        JSON-ready: angles in deg (keys ``..._deg``), lengths in mm (``..._mm``): e.g.
        ``pressure_angle_max_deg`` and its ``..._at_deg``, ``rho_pitch_min_mm``, ``rho_profile_min_mm``,
        ``undercut``, ``closed``, ``closure_gap_mm``, ``lift_mm`` (``swing_deg`` for an oscillating
        follower), ``design`` (base radii, mm), ``checks``, ``tightest``, ``warnings``, ``passed``.

    Examples
    --------
    The rise's pressure-angle check of a 20 mm cycloidal cycle: its margin is the limit less the value:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> figures = profile_report(result)
    >>> figures["lift_mm"], figures["passed"]
    (20.0, True)
    >>> rise = figures["checks"]["pressure angle, rise"]
    >>> rise["limit"], round(rise["value"], 3), abs(rise["limit"] - rise["value"] - rise["margin"]) < 1e-6
    (30.0, 23.233, True)
    """
    f = result.follower
    pa = result.pressure_angle
    profile = result.profile
    rho_profile = profile.rho_convex_min
    out = {
        "name": result.name,
        "law": describe_law(result.law),
        "phases": describe_phases(result.law),
        "follower": f.as_dict(),
        "pressure_angle_max_deg": _deg(pa.maximum.value),
        "pressure_angle_max_at_deg": _at_deg(pa.maximum),
        "pressure_angle_min_deg": _deg(pa.minimum.value),
        "pressure_angle_min_at_deg": _at_deg(pa.minimum),
        "rho_pitch_min_mm": _value(result.rho_pitch_min),
        "rho_pitch_min_at_deg": _at_deg(result.rho_pitch_min),
        "rho_pitch_concave_min_mm": _value(result.rho_pitch_concave_min),
        "rho_profile_min_mm": _value(rho_profile),
        "rho_profile_min_at_deg": _at_deg(rho_profile),
        "undercut": result.undercut,
        "undercut_reasons": list(result.undercut_reasons),
        "closed": profile.closed,
        "closure_gap_mm": profile.closure_gap,
        "closure_kink_deg": math.degrees(result.closure_kink),
        "profile_points": (len(profile.arcs.vertices) if profile.arcs is not None
                           else len(profile.polyline.points)),
        "profile_representation": "arcs" if profile.arcs is not None else "chords",
        "chord_tolerance_mm": result.settings.tol_mm,
        "max_deviation_mm": (profile.arcs.max_deviation if profile.arcs is not None
                             else profile.polyline.max_deviation),
        "lobes": result.geometry.lobes,
        "pressure_angle": _pressure_dict(pa, f),
        "curvature": {"passed": result.curvature_passed, "limit_mm": f.rho_min,
                      "rho_profile_min_mm": _value(rho_profile),
                      "rho_profile_concave_min_mm": _value(profile.rho_concave_min)},
        "phase_angles": phases,
        **_verdict_keys(profile_verdict(result, phases)),
        "notes": list(result.notes),
        "outputs": [],
    }
    if f.kind == "oscillating":
        out["swing_deg"] = math.degrees(stroke(result))
    else:
        out["lift_mm"] = stroke(result)
    if result.design is not None:
        out["design"] = result.design.as_dict()
    if result.face_extent is not None:
        out["face_extent_mm"] = list(result.face_extent)
    if result.outer is not None:
        out["groove"] = _curve_dict(result.outer)
    if result.counter is not None:
        counter = _curve_dict(result.counter)
        # a counter-cam comes with its pitch curve and pressure angles
        counter["pressure_angle"] = _pressure_dict(cast(PressureAngleCheck, result.counter_pressure_angle), f)
        counter["rho_pitch_min_mm"] = _value(cast(CurveResult, result.counter_pitch).rho_convex_min)
        out["counter_cam"] = counter
    return out
