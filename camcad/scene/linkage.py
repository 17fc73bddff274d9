"""What the pipeline does with a scene's ``[linkage]`` (parsed by ``camcad.scene.sections.linkage``): the linkage
between the follower and the working member, built for the follower, and its step in the pipeline.

The keys of ``[linkage]`` and ``[linkage.adjust]``, their units and frames, are in
``camcad.scene.sections.linkage``'s docstring (and docs/SCENE.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

import numpy as np

from camcad.arrays import union
from camcad.errors import CamcadError
from camcad.extrema import zoom_max
from camcad.linkage.adjust import Adjustment, adjusted, characteristics
from camcad.linkage.analysis import Linkage, Loop, analyse
from camcad.linkage.transfer import (
    FollowerLaw,
    LinkageTransfer,
    RatioTransfer,
    TableTransfer,
    WorkingLaw,
    linkage_load,
)
from camcad.profile.followers import arm_angle_on_base_circle
from camcad.profile.scaled_law import swing_law
from camcad.profile.synth import ProfileSettings, synthesize
from camcad.scene.fields import read_table
from camcad.scene.file import read_scene
from camcad.scene.follower import follower_for_law
from camcad.scene.laws import mechanism_law
from camcad.scene.sections.follower import FOLLOWER_FIELDS, parse_follower
from camcad.scene.sections.linkage import AdjustSpec, LinkageSpec, parse_linkage

# --------------------------------------------------------------------------------------------
# Building the linkage from the section and the follower
# --------------------------------------------------------------------------------------------

def build_linkage(spec: LinkageSpec, pivot_xy: tuple[float, float], arm_angle0: float | None,
                  input_sense: int = -1):
    """The four-bar or six-bar (``camcad.linkage.analysis.Linkage``) of a spec, with the follower's pivot at
    ``pivot_xy`` (mm) and its arm at the absolute angle ``arm_angle0`` (rad) on the base circle (None when
    ``input_angle`` places the input link). ``input_sense``: dθ/dψ of the arm (−1 for camcad's oscillating
    follower, whose arm turns clockwise as ψ grows). The output sense is left +1 (``orient``)."""
    v = spec.values
    if v["input_angle"] is not None:
        theta0 = math.radians(v["input_angle"])
    else:
        if arm_angle0 is None:
            raise CamcadError("input_offset needs the follower's arm angle on the base circle", spec.where,
                              "give input_angle (deg, absolute) instead")
        theta0 = arm_angle0 + math.radians(v["input_offset"])
    loops = [Loop((pivot_xy[0], pivot_xy[1]), v["output_pivot"], v["input_link"], v["coupler"], v["output_link"],
                  v["branch"])]
    couplings: tuple[float, ...] = ()
    if spec.type == "sixbar":
        loops.append(Loop(v["output_pivot"], v["output_pivot_2"], v["input_link_2"], v["coupler_2"],
                          v["output_link_2"], v["branch_2"]))
        couplings = (math.radians(v["coupling_2"]),)
    point = None
    if v["coupler_point"] is not None:
        point = (0, float(v["coupler_point"][0]), float(v["coupler_point"][1]))
    return Linkage(tuple(loops), theta0, input_sense, couplings, 1, 0.0, point)


def orient(linkage, direction: str, where: str):
    """``linkage`` with its output sense: "ccw" +1, "cw" −1, "auto" the sense the working member turns in
    when the follower leaves the base circle (Π'(0) > 0)."""
    if direction == "ccw":
        return replace(linkage, output_sense=1)
    if direction == "cw":
        return replace(linkage, output_sense=-1)
    d1 = float(replace(linkage, output_sense=1).position(np.array([0.0]))[1][0])
    if not math.isfinite(d1):
        raise CamcadError("the linkage does not close with the follower on the base circle", where,
                          "check the link lengths, the pivots and the input link's angle")
    if d1 == 0.0:
        raise CamcadError("the working member is at a limit position (Pi' = 0) with the follower on the base circle",
                          where, "set output_direction, or move the input link's angle")
    return replace(linkage, output_sense=1 if d1 > 0 else -1)


def unit_scale(unit: str) -> float:
    """Π's unit per unit of the scene: deg → rad (π/180), rad and mm → 1."""
    return math.pi / 180.0 if unit == "deg" else 1.0


@dataclass
class LinkageContext:
    """The linkage of one mechanism as the pipeline uses it: the spec, Π (``transfer``) with its swing, the
    follower's law → ψ map, the working member's law, its load on the follower, and the settings."""

    spec: LinkageSpec
    transfer: Any
    psi_max: float
    follower_kind: str
    arm_mm: float | None
    to_psi: Any                       # callable: the follower's law (law units) → a law of ψ (follower units)
    law_of: str = "follower"
    linkage: Any = None               # the nominal Linkage (four/six-bar)
    setting: float | None = None      # the setting this context is for (None: the nominal geometry)
    notes: list = field(default_factory=list)

    def working_law(self, follower_law):
        """The working member's law y(θ) = Π(ψ(θ)) (rad or mm), chain rule."""
        return WorkingLaw(self.to_psi(follower_law), self.transfer)

    def load_on(self, follower_law, theta):
        """The working member's inertia and load reduced to the roller's path on the cam angles ``theta``
        (``camcad.linkage.transfer.LinkageLoad``), or None when [linkage] gives neither."""
        v = self.spec.values
        if v["output_inertia"] is None and v["output_load"] is None:
            return None
        theta = np.asarray(theta, dtype=float)
        kin = self.to_psi(follower_law).kinematics(theta)
        load = 0.0
        if v["output_load"] is not None:
            load = np.full_like(theta, v["output_load"])
            if v["output_load_range_deg"] is not None:
                start, end = np.radians(v["output_load_range_deg"])
                inside = np.mod(theta - start, 2 * np.pi) <= np.mod(end - start, 2 * np.pi)
                load = np.where(inside, load, 0.0)
        return linkage_load(self.transfer, kin, v["output_inertia"] or 0.0, load,
                            self.arm_mm if self.follower_kind == "oscillating" else None)

    def for_setting(self, value: float) -> LinkageContext:
        """The context of one setting of [linkage.adjust] (the same cam and follower law)."""
        adj_spec = cast(AdjustSpec, self.spec.adjust)  # asked only of a linkage with [linkage.adjust]
        adj = adjustment_of(adj_spec)
        lk = adjusted(self.linkage, adj, setting_value(adj_spec, value))
        return replace(self, transfer=LinkageTransfer(lk, self.psi_max), linkage=lk, setting=value, notes=[]) \
            if isinstance(adj, Adjustment) else self


def adjustment_of(spec: AdjustSpec):
    """The ``camcad.linkage.adjust.Adjustment`` of an ``[linkage.adjust]`` spec."""
    centre = None if spec.centre is None else complex(*spec.centre)
    return Adjustment(spec.element, spec.joint, spec.path, centre, math.radians(spec.direction_deg))


def setting_value(spec: AdjustSpec, value: float) -> float:
    """A setting in the scene's unit (deg, or mm for a slot) → the adjustment's (rad or mm)."""
    return value if spec.path == "slot" else math.radians(value)


def _law_of(mech_sections: dict, where: str) -> str:
    law = mech_sections.get("law")
    value = law.get("law_of", "follower") if isinstance(law, dict) else "follower"
    return value


def linkage_context(scene, mech, law) -> LinkageContext:
    """Read ``[linkage]`` and build Π for ``law`` (the [law]'s law: the follower's, or the working member's
    when ``law_of = "output"``) with the mechanism's follower."""
    where = mech.where(scene.path, "linkage")
    spec = parse_linkage(mech.sections["linkage"], where, scene.base_dir)
    law_of = _law_of(mech.sections, where)
    if not mech.has("follower"):
        raise CamcadError("a [linkage] needs the [follower] that drives it", where,
                          "add the [follower] section (an oscillating follower for a four-bar or six-bar)")
    follower_where = mech.where(scene.path, "follower")
    table = mech.sections["follower"]
    follower = parse_follower(table, follower_where)
    follower_values = read_table(table, FOLLOWER_FIELDS, follower_where)
    rotary_in = follower.kind == "oscillating"
    unit_in = "rad" if rotary_in else "mm"
    if spec.type in ("fourbar", "sixbar") and not rotary_in:
        raise CamcadError(f"a {spec.type} is driven by a rocker: the follower is {follower.kind!r}", where,
                          'use type = "oscillating" in [follower], or a table / ratio linkage')
    if law_of == "output" and follower_values["swing"] is not None:
        raise CamcadError("with law_of = \"output\" the linkage sets the follower's swing", follower_where,
                          "drop swing from [follower]")
    arm = follower.arm if rotary_in else None

    def to_psi(follower_law):
        if not rotary_in:
            return follower_law
        return swing_law(follower_law, arm_mm=follower.arm, swing_deg=follower_values["swing"])

    notes: list[str] = []
    # by spec.type: a RatioTransfer, TableTransfer or LinkageTransfer; the Linkage of a four/six-bar; ψ_max
    transfer: Any = None
    linkage: Any = None
    psi_max: Any = None
    out_scale = unit_scale(spec.output_unit)
    if spec.type == "ratio":
        k = spec.values["ratio"]
        transfer = RatioTransfer(k, unit_in, "mm" if spec.output_unit == "mm" else "rad")
    elif spec.type == "table":
        in_unit = spec.values["input_unit"]
        if (in_unit == "mm") == rotary_in:
            raise CamcadError(f"input_unit {in_unit!r} does not fit a {follower.kind} follower", where,
                              'use input_unit = "deg" (or "rad") for an oscillating follower, '
                              '"mm" for a translating one')
        rows = np.array(spec.rows, dtype=float)
        transfer = TableTransfer(rows[:, 0] * unit_scale(in_unit), rows[:, 1] * out_scale, unit_in,
                                 "mm" if spec.output_unit == "mm" else "rad", where)
        psi_max = transfer.psi_max
    if spec.type in ("fourbar", "sixbar"):
        arm_angle0 = None
        if spec.values["input_angle"] is None:
            if law_of == "output" and follower_values["auto_base_radius"]:
                raise CamcadError("input_offset needs the base radius, which auto_base_radius sizes from the "
                                  "follower's law this linkage gives", where,
                                  "give input_angle (the input link's absolute angle, deg) instead of input_offset")
            sized = follower_for_law(table, follower_where, law)[0] if law_of == "follower" else follower
            arm_angle0 = math.pi - arm_angle_on_base_circle(sized)
        pivot = cast(float, follower.pivot)  # a four/six-bar has an oscillating follower (refused above)
        linkage = orient(build_linkage(spec, (pivot, 0.0), arm_angle0), spec.values["output_direction"], where)
    if law_of == "output":
        (y_min, at_min), (y_max, _) = _law_range(law)
        if y_min < -1e-9 * abs(y_max):
            shown = f"{y_min:.6g} {spec.output_unit}"          # the law's own unit
            raise CamcadError(f"the working member's law goes below its start position, to {shown} at cam angle "
                              f"{math.degrees(at_min):.6g} deg, where the linkage, laid out from that start, cannot "
                              "follow", mech.where(scene.path, "law"),
                              "the law must stay at or above its start (run camcad check on it: an unbalanced "
                              "acceleration law drifts)")
        y_max *= out_scale
        if spec.type in ("fourbar", "sixbar"):
            psi_max = _swing_for(linkage, y_max, where)
            transfer = LinkageTransfer(linkage, psi_max)
        elif spec.type == "ratio":
            psi_max = y_max / transfer.k * 1.0000001
        else:
            if float(transfer(np.array([psi_max]))[0]) < y_max * (1 - 1e-12):
                raise CamcadError(f"the table's y reaches {float(transfer(np.array([psi_max]))[0]) / out_scale:.6g} "
                                  f"{spec.output_unit}, the law asks for {y_max / out_scale:.6g}", where,
                                  "extend the table to the working member's full stroke")
        sense = transfer.check_monotone(psi_max, where)
        if sense < 0:
            raise CamcadError("the working member moves backwards as the follower rises (Pi' < 0)", where,
                              "for a four-bar set output_direction, for a table give y rising with psi")
    else:
        psi = to_psi(law).kinematics(np.linspace(0.0, law.cycle, 4097)).s
        if float(np.min(psi)) < -1e-9 * max(1.0, float(np.max(np.abs(psi)))):
            raise CamcadError("the follower's law goes below its base-circle position", where,
                              "a linkage's position function starts at psi = 0")
        psi_max = float(np.max(psi)) if psi_max is None or spec.type != "table" else psi_max
        if spec.type == "table" and float(np.max(psi)) > transfer.psi_max * (1 + 1e-12):
            raise CamcadError(f"the follower moves to {_fmt(float(np.max(psi)), unit_in)}, beyond the table's "
                              f"{_fmt(transfer.psi_max, unit_in)}", where,
                              "extend the table over the follower's stroke")
        if spec.type == "table":
            psi_max = float(np.max(psi))
        if spec.type in ("fourbar", "sixbar"):
            transfer = LinkageTransfer(linkage, psi_max)
    context = LinkageContext(spec, transfer, float(psi_max), follower.kind, arm, to_psi, law_of, linkage,
                             notes=notes)
    return context


def _fmt(psi: float, unit: str) -> str:
    return f"{math.degrees(psi):.6g} deg" if unit == "rad" else f"{psi:.6g} mm"


def _law_range(law) -> tuple[tuple[float, float], tuple[float, float]]:
    """The law's smallest and largest displacement, each with its cam angle (rad): sampled (phase ends
    included), refined by zooming grids (``camcad.extrema.zoom_max``, both at once)."""
    theta = union(np.linspace(0.0, law.cycle, 8193), [p.end for p in law.phases] + [p.start for p in law.phases])
    signs = np.array([[-1.0], [1.0]])            # row 0: −s (its peak is the minimum), row 1: s

    def both(u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        return signs * law.kinematics(u.ravel()).s.reshape(1 if u.ndim == 1 else 2, -1)

    peak, at = zoom_max(both, theta, 2)
    return (-float(peak[0]), float(at[0])), (float(peak[1]), float(at[1]))


def _swing_for(linkage, y_max: float, where: str, step_deg: float = 0.25, limit_deg: float = 180.0) -> float:
    """The least swing ψ (rad) at which Π reaches ``y_max`` on the monotone, closed stretch from ψ = 0."""
    grid = np.radians(np.arange(0.0, limit_deg + step_deg, step_deg))
    pi, d1 = (np.asarray(v, dtype=float) for v in linkage.position(grid)[:2])
    if y_max <= 0.0:
        raise CamcadError("the working member's law has no stroke", where, "check [law]")
    for i in range(1, len(grid)):
        if not (np.isfinite(pi[i]) and np.isfinite(d1[i])) or d1[i] <= 0.0:
            what = "does not close" if not np.isfinite(pi[i]) else "reaches a limit position (Pi' = 0)"
            reach = float(np.nanmax(pi[:i])) if i > 0 else 0.0
            raise CamcadError(f"the linkage {what} at swing {math.degrees(grid[i]):.4g} deg, where the working member "
                              f"has turned {math.degrees(reach):.6g} deg of the {math.degrees(y_max):.6g} deg the law "
                              "asks for", where, "lengthen the input link, or shorten the output link")
        if pi[i] >= y_max:
            from scipy.optimize import brentq  # here, not at the top: a scene without a linkage does not need it

            return float(brentq(lambda x: float(linkage.position(np.array([x]))[0][0]) - y_max, grid[i - 1],
                                grid[i], xtol=1e-15))
    raise CamcadError(f"the linkage does not turn the working member {math.degrees(y_max):.6g} deg within a "
                      f"{limit_deg:g} deg swing", where, "change the link lengths")


def prepare(scene, mech, built):
    """The pipeline's linkage step before the profile: returns (built, LinkageContext or None). With
    ``[law] law_of = "output"`` the built law is replaced by the follower's law designed for it (the roller's
    arc in mm for an oscillating follower, so that [follower] turns it into ψ as for any law)."""
    law_of = _law_of(mech.sections, "")
    if not mech.has("linkage"):
        if law_of == "output":
            raise CamcadError("law_of = \"output\" describes the working member, but there is no [linkage]",
                              mech.where(scene.path, "law"), "add the [linkage] section, or drop law_of")
        return built, None
    context = linkage_context(scene, mech, built.law)
    _check_models(scene, mech, context)
    if law_of != "output":
        return built, context
    out_scale = 1.0 if context.follower_kind != "oscillating" else float(context.arm_mm)
    follower_law = FollowerLaw(built.law, context.transfer, context.psi_max, unit_scale(context.spec.output_unit),
                               out_scale)
    note = (f"law_of = output: the [law] is the working member's ({context.spec.output_unit}); the cam is designed "
            f"for the follower's psi = Pi^-1(y) through {context.transfer.describe()}, swing "
            f"{_fmt(context.psi_max, context.transfer.unit_in)}")
    context.notes.append(note)
    return replace(built, law=follower_law, notes=tuple(built.notes) + (note,)), context


def _check_models(scene, mech, context: LinkageContext) -> None:
    """The models' units fit the working member: [dynamics] output_unit, [stops] ratio for a turning one."""
    unit = context.transfer.unit_out
    dyn = mech.sections.get("dynamics")
    if isinstance(dyn, dict):
        given = dyn.get("output_unit", "mm")
        if (given == "rad") != (unit == "rad"):
            raise CamcadError(f"the working member after the [linkage] moves in {unit}, [dynamics] output_unit is "
                              f"{given!r}", mech.where(scene.path, "dynamics"),
                              f'set output_unit = "{unit}" (the [dynamics] data are the working member\'s)')
    stops = mech.sections.get("stops")
    if isinstance(stops, dict) and unit == "rad" and "ratio" not in stops:
        raise CamcadError("the working member after the [linkage] turns (rad): the stop's contact point needs its "
                          "distance from the working member's pivot", mech.where(scene.path, "stops"),
                          "give ratio = ... (mm of the contact point per rad of the working member)")
    if scene.cyclogram is not None and context.law_of == "output":
        named = {str(op.get("mechanism")) for op in scene.cyclogram.get("operations", []) if isinstance(op, dict)}
        if mech.name in named:
            raise CamcadError("a law_of = \"output\" mechanism in a [cyclogram] is not supported (the cyclogram's "
                              "limits read the [law] as the follower's)", mech.where(scene.path, "law"),
                              "give the follower's law (law_of = \"follower\") for a mechanism the cyclogram retimes")


def working_report(context: LinkageContext, follower_law, built_law=None, samples: int = 4096) -> dict:
    """The working member's motion over the cycle (y in rad or mm, per rad of cam angle) and, with
    ``law_of = "output"``, the round trip: max |Π(ψ(θ)) − y_law(θ)| of the designed follower law."""
    theta = np.linspace(0.0, follower_law.cycle, samples + 1)
    y = context.working_law(follower_law).kinematics(theta)
    unit = context.transfer.unit_out
    out = {"unit": unit, "stroke": float(np.ptp(y.s)), "velocity_analog_max": float(np.max(np.abs(y.v))),
           "acceleration_analog_max": float(np.max(np.abs(y.a))), "jerk_analog_max": float(np.max(np.abs(y.j)))}
    if context.law_of == "output" and built_law is not None:
        law = built_law.kinematics(theta)
        scale = unit_scale(context.spec.output_unit)
        out["round_trip_max"] = float(np.max(np.abs(y.s - law.s * scale)))
        out["round_trip_unit"] = unit
    return out


def linkage_step(scene, mech, run, speeds, options, steps: dict) -> None:
    """The pipeline's linkage step after the models: the linkage's analysis (Π and its derivatives,
    transmission angles, dead points, branch), the working member's motion, and with [linkage.adjust] every
    setting through the models that ran (``steps``: the pipeline's dynamics, impact and contact functions),
    each setting's figures and the governing one. Writes ``run.report["linkage"]``."""
    context: LinkageContext = run.linkage
    spec = context.spec
    mu_limit = spec.values["mu_min"]
    report: dict[str, Any] = {"type": spec.type, "law_of": context.law_of, "position_function":
                              context.transfer.describe(), "swing": context.psi_max,
                              "swing_unit": context.transfer.unit_in, "notes": list(context.notes)}
    if context.linkage is not None:
        nominal = analyse(context.linkage, context.psi_max)
        report["analysis"] = nominal.report(mu_limit)
        checks = dict(report["analysis"]["checks"])
        if context.law_of == "follower" and not nominal.monotone:
            checks["monotone"] = {**checks["monotone"], "passed": True,
                                  "why": "informative with law_of = follower: the working member may reverse"}
    else:
        checks = {}
    report["working_member"] = working_report(context, run.law, _built_output_law(run))
    if spec.adjust is not None:
        report["settings"] = _settings_report(scene, mech, run, speeds, options, steps, context, mu_limit)
        for item in report["settings"]["rows"]:
            if not item["passed"]:
                checks["settings"] = {"value": item["setting"], "passed": False,
                                      "why": "a setting fails a check (see settings.rows)"}
                break
        else:
            checks["settings"] = {"value": len(report["settings"]["rows"]), "passed": True,
                                  "why": "every setting passes"}
    report["checks"] = checks
    report["passed"] = all(c["passed"] for c in checks.values())
    run.report["linkage"] = report


def _built_output_law(run):
    law = run.law
    return getattr(law, "base", None) if type(law).__name__ == "FollowerLaw" else None


MODEL_FIGURES = {"dynamics": ("peak_accel_ratio", max), "impact": ("rebound_mm", max),
                 "contact": ("sigma_max_MPa", max)}


def _settings_report(scene, mech, run, speeds, options, steps, context: LinkageContext, mu_limit) -> dict:
    adj_spec = cast(AdjustSpec, context.spec.adjust)  # reported only for a linkage with [linkage.adjust]
    adj = adjustment_of(adj_spec)
    rows = []
    for value in adj_spec.settings:
        item: dict[str, Any] = {"setting": value, "unit": "mm" if adj_spec.path == "slot" else "deg"}
        try:
            ch = characteristics(context.linkage, adj, setting_value(adj_spec, value), context.psi_max)
        except CamcadError as err:
            item.update({"passed": False, "error": err.message()})
            rows.append(item)
            continue
        item.update({k: v for k, v in ch.as_dict("rad").items() if not k.startswith("setting")})
        ok = ch.branch_continuous and math.isfinite(ch.mu_min) and math.degrees(ch.mu_min) >= mu_limit
        item["linkage_passed"] = bool(ok)
        models: dict[str, Any] = {}
        if ch.branch_continuous:
            sub = context.for_setting(value)
            for key, step in steps.items():
                section = "stops" if key == "impact" else key
                if key not in run.report or not mech.has(section) or speeds is None:
                    continue
                trial = type(run)(run.name, law=run.law, memo=None, linkage=sub, unit=run.unit,
                                  given_law=run.given_law, output_law=run.output_law)
                try:
                    step(scene, mech, trial, speeds, options, mech.where(scene.path, section), False)
                except CamcadError as err:
                    models[key] = {"passed": False, "error": err.message()}
                    continue
                figure, pick = MODEL_FIGURES[key]
                value_k = trial.report[key].get(figure)
                value_k = pick(value_k) if isinstance(value_k, list) else value_k
                models[key] = {"passed": bool(trial.report[key].get("passed", True)), figure: value_k}
        item["models"] = models
        item["passed"] = bool(ok and all(m["passed"] for m in models.values()))
        rows.append(item)
    governing: dict[str, Any] = {}
    valid = [r for r in rows if "mu_min_deg" in r]
    if valid:
        worst = min(valid, key=lambda r: r["mu_min_deg"] if math.isfinite(r["mu_min_deg"]) else -math.inf)
        governing["transmission_angle"] = {"setting": worst["setting"], "mu_min_deg": worst["mu_min_deg"]}
    for key, (figure, _) in MODEL_FIGURES.items():
        with_key = [r for r in rows if key in r.get("models", {}) and figure in r["models"][key]]
        if with_key:
            worst = max(with_key, key=lambda r: r["models"][key][figure])
            governing[key] = {"setting": worst["setting"], figure: worst["models"][key][figure]}
    failing = [r["setting"] for r in rows if not r["passed"]]
    return {"element": adj.describe(), "rows": rows, "governing": governing, "failing": failing}


# --------------------------------------------------------------------------------------------
# The linkage of a command: from a scene, or from the command's options
# --------------------------------------------------------------------------------------------

@dataclass
class CommandLinkage:
    """What ``camcad linkage analyse|adjust|tune`` work on: the nominal linkage, the follower's swing ψ_max
    (rad), and for a scene its context, mechanism, law and follower."""

    linkage: Any
    psi_max: float
    mu_min: float
    context: LinkageContext | None = None
    scene: Any = None
    mechanism: Any = None
    follower_law: Any = None
    output_law: Any = None
    name: str = "linkage"


def from_scene(path: Path, mechanism: str | None = None) -> CommandLinkage:
    """The [linkage] of a scene's mechanism with its follower's swing (the law's ψ range, or the swing the
    law of the working member needs with ``law_of = "output"``)."""
    scene = read_scene(path)
    if mechanism is None:
        candidates = [m for m in scene.mechanisms if m.has("linkage")]
        if len(candidates) != 1:
            names = ", ".join(m.name for m in candidates) or "none"
            raise CamcadError(f"the scene has {len(candidates)} mechanisms with a [linkage] ({names})", str(path),
                              "add [linkage] to a mechanism, or pick one with --mechanism")
        mech = candidates[0]
    else:
        mech = scene.mechanism(mechanism)
    if not mech.has("linkage"):
        raise CamcadError(f"mechanism {mech.name!r} has no [linkage]", str(path), "add the [linkage] section")
    built = mechanism_law(scene, mech)
    built2, context = prepare(scene, mech, built)
    if context.linkage is None:
        raise CamcadError(f"the [linkage] is a {context.spec.type}: there are no links to analyse",
                          mech.where(scene.path, "linkage"), 'describe it as type = "fourbar" or "sixbar"')
    name = mech.name if mech.prefix else scene.name
    return CommandLinkage(context.linkage, context.psi_max, context.spec.values["mu_min"], context, scene, mech,
                          built2.law, built.law if context.law_of == "output" else None, name)


def from_options(values: dict, swing_deg: float | None, sense: int, where: str = "command line") -> CommandLinkage:
    """A linkage from a command's options, given as the keys of ``[linkage]`` (``values``), with the input
    pivot ``values["input_pivot"]`` (mm), the swing (deg) and the input's sense (+1: the input link turns
    counter-clockwise as ψ grows)."""
    if swing_deg is None or not swing_deg > 0:
        raise CamcadError("the follower's swing is missing", "--swing", "give --swing DEG (> 0)")
    pivot = values.pop("input_pivot", (0.0, 0.0))
    table = {k: v for k, v in values.items() if v is not None}
    spec = parse_linkage(table, where, Path("."))
    if spec.type not in ("fourbar", "sixbar"):
        raise CamcadError("the options describe a four-bar or six-bar", where, "give --links and --output-pivot")
    lk = orient(build_linkage(spec, tuple(pivot), None, sense), spec.values["output_direction"], where)
    return CommandLinkage(lk, math.radians(swing_deg), spec.values["mu_min"])


def cam_profile(command: CommandLinkage):
    """The cam profile of a scene's mechanism (``camcad.profile.synth.synthesize``) for the combined drawing."""
    mech, scene = command.mechanism, command.scene
    follower, law, _, _ = follower_for_law(mech.sections["follower"], mech.where(scene.path, "follower"),
                                           command.follower_law)
    return synthesize(law, follower, ProfileSettings(plots=False, name=mech.name).validate(), name=mech.name)
