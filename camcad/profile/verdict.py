"""The profile's verdict: every design check as a figure, a limit and a margin, and the warnings a senior
engineer would give even where no limit is set.

Checks (``camcad.verdict.Check``; degrees and mm):

- ``pressure angle, rise`` / ``pressure angle, return``: the largest |φ| while the follower moves out /
  back, against the phase's limit (a reversible cam applies the stricter limit to both);
  ``counter-cam pressure angle, …`` likewise for a conjugate pair;
- ``undercut``: the smallest convex radius of the pitch curve against the roller radius (it must stay
  above it), or for a flat face the smallest Rb + s + a against 0; a profile polygon that is not simple
  fails it whatever the radii say;
- ``convex radius``: the smallest convex radius of the profile against ``rho_min`` (when given);
- ``closure``: the gap between the profile's end and start against the chord tolerance.

Warnings (``camcad.verdict.Warning``):

- a convex profile radius below ``SHARP_RADIUS_FRACTION`` of the roller radius (near undercut: high
  contact stress, a worn cam loses its shape);
- a pressure angle within ``NEAR_LIMIT_DEG`` of its limit;
- a written profile with fewer than ``MIN_POINTS_PER_LOBE`` points per lobe (the chord tolerance is
  coarse for a cam of this size).
"""

from __future__ import annotations

import math
from dataclasses import replace

from camcad.profile.synth import Extremum, PressureAngleCheck, ProfileResult
from camcad.verdict import Check, Verdict, Warning

#: a convex profile radius below this fraction of the roller radius is flagged
SHARP_RADIUS_FRACTION = 0.25
#: a pressure angle this close to its limit (deg) is flagged
NEAR_LIMIT_DEG = 0.5
#: fewer written points per lobe than this is flagged
MIN_POINTS_PER_LOBE = 32
#: a margin below this fraction of the limit counts as "at the limit" (a cyclogram holds phases there)
AT_LIMIT_RATIO = 1e-5


def _at(extremum: Extremum | None) -> str:
    return "" if extremum is None else f"at {math.degrees(extremum.at):.3f} deg"


def _pressure_checks(check: PressureAngleCheck, result: ProfileResult, prefix: str, phases: str) -> list[Check]:
    f = result.follower
    if f.kind == "flat":
        return []
    rise_limit = f.pressure_angle_limit_rise_deg
    return_limit = f.pressure_angle_limit_return_deg
    if f.reversible:
        given = [x for x in (rise_limit, return_limit) if x]
        rise_limit = return_limit = min(given) if given else None
    out = []
    for label, extremum, limit in (("rise", check.rise_max, rise_limit), ("return", check.return_max, return_limit)):
        if extremum is None or not math.isfinite(extremum.value):
            continue
        applies = " ".join(x for x in (_at(extremum), f"({phases})") if x)
        out.append(Check(f"{prefix}pressure angle, {label}", math.degrees(extremum.value), limit or None, "deg",
                         "max", applies=applies,
                         note="reversible cam: the stricter limit applies both ways" if f.reversible else ""))
    return out


def profile_verdict(result: ProfileResult, phases: str = "the law's own phase angles") -> Verdict:
    """The checks and warnings of a synthesised profile (module docstring).

    Parameters
    ----------
    result : ProfileResult
        What ``synthesize`` found.
    phases : str
        Which phase angles the law has (the law's own, or the cyclogram's), said in every check.

    Returns
    -------
    Verdict
    """
    f = result.follower
    checks = _pressure_checks(result.pressure_angle, result, "", phases)
    if result.counter_pressure_angle is not None:
        checks += _pressure_checks(result.counter_pressure_angle, result, "counter-cam ", phases)
    simple = result.profile.simple and (result.outer is None or result.outer.simple) and \
        (result.counter is None or result.counter.simple)
    polygon_note = "" if simple else "the profile polygon is not simple (loop or cusp)"
    if f.kind == "flat":
        lowest = min(result.table.rho_profile) if len(result.table.rho_profile) else None
        checks.append(Check("undercut (flat-face radius Rb + s + a)", float(lowest) if lowest is not None else None,
                            0.0, "mm", "min", applies="sampled every step of law.csv", note=polygon_note,
                            passed_override=False if not simple or result.undercut else None))
    elif f.roller_radius > 0.0 and result.rho_pitch_min is not None:
        checks.append(Check("undercut (convex pitch radius vs roller)", result.rho_pitch_min.value,
                            f.roller_radius, "mm", "min", applies=_at(result.rho_pitch_min), note=polygon_note,
                            passed_override=False if not simple else None))
    elif not simple:
        checks.append(Check("undercut", None, None, "", "min", note=polygon_note, passed_override=False))
    rho = result.profile.rho_convex_min
    if f.rho_min is not None and rho is not None:
        checks.append(Check("convex radius of the profile", rho.value, f.rho_min, "mm", "min", applies=_at(rho)))
    tol = result.settings.tol_mm
    checks.append(Check("closure gap of the profile", result.profile.closure_gap, tol, "mm", "max",
                        note="" if result.profile.closed else "the law's displacement does not come back: "
                        "balance it with camcad fix"))

    warnings: list[Warning] = []
    if f.has_roller and rho is not None and rho.value < SHARP_RADIUS_FRACTION * f.roller_radius:
        warnings.append(Warning(
            f"convex profile radius {rho.value:.4g} mm {_at(rho)} is {rho.value / f.roller_radius:.2f} of the "
            f"roller radius {f.roller_radius:g} mm: near undercut, high contact stress; a larger base radius or "
            "a longer phase helps", rho.value, f"convex profile radius < {SHARP_RADIUS_FRACTION:g} x roller radius"))
    if "cyclogram" in phases:
        # the cyclogram shortens each phase to its least admissible angle: a check at its limit is held there
        checks = [replace(c, note=(c.note + "; " if c.note else "") + "held at its limit by the cyclogram, margin 0")
                  if c.margin_ratio is not None and 0.0 <= c.margin_ratio < AT_LIMIT_RATIO else c for c in checks]
    for check in checks:
        if "held at its limit" in check.note:
            continue
        if check.name.endswith(("pressure angle, rise", "pressure angle, return")) and check.margin is not None \
                and 0.0 <= check.margin < NEAR_LIMIT_DEG:
            warnings.append(Warning(f"{check.name} {check.value:.4g} deg is within {check.margin:.3g} deg of its "
                                    f"limit {check.limit:g} deg", check.value,
                                    f"pressure angle within {NEAR_LIMIT_DEG:g} deg of the limit"))
    points = len(result.profile.polyline.points) / max(result.geometry.lobes, 1)
    if points < MIN_POINTS_PER_LOBE:
        size = f.base_radius + float(max(result.table.s) - min(result.table.s))
        warnings.append(Warning(
            f"the written profile has only {points:.0f} points per lobe: the chord tolerance {tol:g} mm is coarse "
            f"for a cam of {size:.3g} mm; give --tol-mm {max(size * 1e-4, 1e-12):.2g}", points,
            f"fewer than {MIN_POINTS_PER_LOBE} points per lobe"))
    return Verdict(tuple(checks), tuple(warnings))
