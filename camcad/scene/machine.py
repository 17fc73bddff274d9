"""Machine scenes: several groups of mechanisms on one main shaft, their shared events and the machine's
cyclogram (Podgorny et al. 2018, Fig. 1), analysed as ``camcad machine`` does.

A machine scene (TOML) holds:

- ``[machine]``: ``rpm`` (every group runs at these speeds), ``cycle_deg`` (360: one turn of the main
  shaft), ``start_deg`` (where the machine's first event sits on the shaft), ``objective`` ("least_cycle"
  or "limiting"), ``limiting`` (the limiting operation: a label "x->y" or a name of ``[[network.operations]]``),
  optional ``start`` and ``end`` events, ``name``;
- ``[groups.NAME]``: a group, either ``scene = "group.toml"`` (a group scene file: ``[mechanisms.*]`` and
  ``[cyclogram]``, found beside the machine file) or inline ``[groups.NAME.mechanisms.*]`` and
  ``[groups.NAME.cyclogram]`` tables, written as in a group scene;
- ``[network]``: the machine's own ``[[network.operations]]`` (``from``, ``to``, ``bounds_deg``, ``name``),
  whose events are machine events (plain names) or groups' events ("GROUP:EVENT"), and ``shared``: lists of
  events that are one event of the machine (``shared = [["group1:8", "10.1"]]``).

The analysis (``analyse_machine``): every group's phase limits (``camcad.scene.phase_angles.group_limits``,
as ``camcad cyclogram`` computes them at the machine's speeds), the joined network optimised for the
objective (``camcad.cyclogram.machine``), the slack spread by the max–min rule, and every group run through
the scene pipeline at the phase angles the machine gives it (``camcad.scene.pipeline.analyse_scene`` with
``angles``), so every group's profiles are regenerated at the machine's phase angles.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from camcad.cyclogram.machine import OBJECTIVES, SEP, Group, Machine, MachineResult, make_machine, optimise_machine
from camcad.cyclogram.network import Operation
from camcad.dynamics.shaft import ElasticShaft, ShaftCam, simulate_shaft
from camcad.errors import CamcadError, excerpt, nearest_name
from camcad.scene.analysis_report import rounded_tree
from camcad.scene.fields import Field, parse_speeds, read_table
from camcad.scene.file import MECHANISM_SECTIONS, Mechanism, Scene, read_scene, read_toml, scene_from_dict
from camcad.scene.mechanism import retimed_phases
from camcad.scene.phase_angles import CyclogramAngles, group_limits
from camcad.scene.pipeline import PipelineOptions, SceneResult, analyse_scene
from camcad.scene.sections.cyclogram import parse_cyclogram
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.verdict import Check, Verdict, Warning

TOP_LEVEL = ("name", "description", "machine", "groups", "network", "shaft")

MACHINE_FIELDS: list[Field] = [
    Field("rpm", "list", "rpm", help="(speeds of the main shaft: a list, or \"280:420:10\"; every group runs at them)"),
    Field("cycle_deg", unit="deg", default=360.0, positive=True, help="(the machine's cycle: one turn of the shaft)"),
    Field("start_deg", unit="deg", default=0.0, minimum=0.0, maximum=360.0,
          help="(where the machine's first event sits on the main shaft)"),
    Field("objective", "str", default="least_cycle", choices=OBJECTIVES,
          help="(least_cycle: the shortest machine cycle; limiting: the longest limiting operation in the cycle)"),
    Field("limiting", "str", help="(the limiting operation: a label \"x->y\" or the name of a [[network.operations]])"),
    Field("start", "str", help="(the machine's first event; default: the only event without predecessors)"),
    Field("end", "str", help="(the machine's last event; default: the only event without successors)"),
    Field("name", "str", default="", help="(a title for the machine's cyclogram)"),
]

GROUP_FIELDS: list[Field] = [
    Field("scene", "str", help="(a group scene file, beside the machine file; or inline mechanisms and cyclogram)"),
    Field("mechanisms", "table", help="(inline: [groups.NAME.mechanisms.MECH.*] as in a group scene)"),
    Field("cyclogram", "table", help="(inline: [groups.NAME.cyclogram] as in a group scene)"),
    Field("description", "str", default=""),
]

NETWORK_FIELDS: list[Field] = [
    Field("operations", "list", required=True,
          help="([[network.operations]] with from, to, bounds_deg: the machine's own operations)"),
    Field("shared", "list", default=[],
          help="(lists of events that are one event of the machine, e.g. [[\"group1:8\", \"10.1\"]])"),
]

SHAFT_FIELDS: list[Field] = [
    Field("cams", "list", required=True,
          help="(the cams on the main shaft in order from the drive: \"GROUP:MECHANISM\"; each needs [dynamics] "
               "with natural_frequency_hz, damping_ratio and mass_kg)"),
    Field("stiffness_N_m_per_rad", "list", "N·m/rad", required=True,
          help="(torsional stiffness of each segment: drive to the first cam, then cam to cam)"),
    Field("cam_inertia_kg_m2", "list", "kg·m²", required=True, help="(each cam's moment of inertia)"),
    Field("damping_ratio", unit="", default=0.0, minimum=0.0, maximum=0.99, help="(of each shaft segment)"),
    Field("rpm", unit="rpm", positive=True, help="(the speed simulated; default the machine's fastest)"),
    Field("revolutions", "int", default=4, minimum=1, maximum=200,
          help="(turns simulated from the rigid start; the last one is reported)"),
    Field("samples", "int", default=2048, minimum=64, maximum=2**18, help="(samples of the reported turn)"),
]

MACHINE_OPERATION_FIELDS: list[Field] = [
    Field("from", "str", required=True, help="(a machine event, or \"GROUP:EVENT\")"),
    Field("to", "str", required=True, help="(a machine event, or \"GROUP:EVENT\")"),
    Field("bounds_deg", "list", unit="deg", required=True, help="([min, max] phase angle in deg; max may be inf)"),
    Field("name", "str", default="", help="(e.g. \"weft insertion\"; the limiting operation may be named by it)"),
]


@dataclass(frozen=True)
class MachineScene:
    """A machine scene read from its file (``read_machine``): the groups as Scenes, the machine's settings
    (deg, rpm) and its own operations and shared events, not yet analysed."""

    path: Path
    name: str
    description: str
    speeds_rpm: tuple[float, ...] | None
    settings: dict
    groups: dict[str, Scene]
    group_where: dict[str, str]
    operations: tuple[Operation, ...]
    shared: tuple[tuple[str, ...], ...]
    notes: tuple[str, ...] = ()
    shaft: dict | None = None

    def input_files(self) -> list[Path]:
        """The machine file, the group scene files and every law file they read."""
        found = [self.path]
        for scene in self.groups.values():
            for item in scene.input_files():
                if item not in found:
                    found.append(item)
        return found


def _text(value: Any, key: str, where: str) -> str:
    if isinstance(value, bool) or not isinstance(value, (str, int)):
        raise CamcadError(f"'{key}' must be an event name, got {excerpt(value)}", where, f'write {key} = "3"')
    return str(value)


def read_machine(path: str | Path) -> MachineScene:
    """Read a machine scene (module docstring) and check its structure; every group is read as a scene.

    Parameters
    ----------
    path : str or Path
        The machine file (.toml); group scene files and law files are found beside it.

    Returns
    -------
    MachineScene

    Raises
    ------
    CamcadError
        A file that cannot be read, an unknown section or key, a group that is neither a scene file nor an
        inline group, a group scene without [cyclogram], malformed operations.
    """
    path = Path(path)
    raw = read_toml(path)
    where = str(path)
    for key in raw:
        if key not in TOP_LEVEL:
            fix = nearest_name(key, list(TOP_LEVEL))
            if key in MECHANISM_SECTIONS or key in ("mechanisms", "cyclogram"):
                fix = "a machine scene holds [machine], [groups.NAME] and [network]; put mechanisms in a group"
            raise CamcadError(f"unknown section or key '{key}'", where, fix)
    name = raw.get("name", path.stem)
    if not isinstance(name, str) or not name.strip():
        raise CamcadError(f"'name' must be text, got {excerpt(name)}", where, 'write name = "loom"')
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise CamcadError(f"'description' must be text, got {excerpt(description)}", where, 'write description = "..."')
    machine = dict(raw.get("machine") or {})
    if not isinstance(raw.get("machine", {}), dict):
        raise CamcadError("[machine] must be a table", where, "write [machine] with rpm, cycle_deg, objective")
    rpm = machine.pop("rpm", None)
    for key in ("start", "end"):
        if key in machine:
            machine[key] = _text(machine[key], key, f"{where} [machine]")
    settings = read_table(machine, [f for f in MACHINE_FIELDS if f.name != "rpm"], f"{where} [machine]")
    speeds = tuple(parse_speeds(rpm, f"{where} [machine] rpm")) if rpm is not None else None
    groups_raw = raw.get("groups")
    if not isinstance(groups_raw, dict) or not groups_raw:
        raise CamcadError("the machine has no groups", where,
                          "add [groups.NAME] with scene = \"group.toml\" (or inline mechanisms and cyclogram)")
    groups: dict[str, Scene] = {}
    group_where: dict[str, str] = {}
    notes: list[str] = []
    for gname, table in groups_raw.items():
        here = f"{where} [groups.{gname}]"
        if SEP in gname:
            raise CamcadError(f"group name {gname!r} holds {SEP!r}", here, "rename the group without it")
        values = read_table(table, GROUP_FIELDS, here)
        inline = values["mechanisms"] is not None or values["cyclogram"] is not None
        if values["scene"] is not None and inline:
            raise CamcadError("a group is either a scene file or inline mechanisms and cyclogram, not both", here,
                              "drop scene, or drop the inline tables")
        if values["scene"] is not None:
            file = path.parent / values["scene"]
            if file.resolve() == path.resolve():
                raise CamcadError("the group's scene is the machine file itself", here, "name a group scene file")
            scene = read_scene(file)
            group_where[gname] = f"{file} [cyclogram]"
        elif inline:
            body = {"name": gname, "description": values["description"]}
            for key in ("mechanisms", "cyclogram"):
                if values[key] is None:
                    raise CamcadError(f"an inline group needs [groups.{gname}.{key}]", here,
                                      f"add [groups.{gname}.{key}]")
                body[key] = values[key]
            scene = scene_from_dict(body, path)
            scene = replace(scene, mechanisms=tuple(
                Mechanism(m.name, m.sections, f"groups.{gname}.{m.prefix}") for m in scene.mechanisms))
            group_where[gname] = f"{here[:-1]}.cyclogram]"
        else:
            raise CamcadError("the group is empty", here,
                              "give scene = \"group.toml\", or inline [groups.NAME.mechanisms.*] and cyclogram")
        if scene.cyclogram is None:
            raise CamcadError("the group has no [cyclogram]", here,
                              "a group of the machine is a group scene: [mechanisms.*] and [cyclogram]")
        if scene.speeds_rpm is not None and speeds is not None and tuple(scene.speeds_rpm) != speeds:
            notes.append(f"group {gname}: its own [machine] rpm {list(scene.speeds_rpm)} is replaced by the "
                         f"machine's {list(speeds)}")
        groups[gname] = replace(scene, speeds_rpm=speeds)
    network = raw.get("network")
    if network is None:
        raise CamcadError("the machine has no [network]", where,
                          "add [[network.operations]] joining the groups' events (\"GROUP:EVENT\")")
    values = read_table(network, NETWORK_FIELDS, f"{where} [network]")
    operations = tuple(_operation(raw_op, f"{where} [network] operations[{k}]")
                       for k, raw_op in enumerate(values["operations"], start=1))
    shared = []
    for k, item in enumerate(values["shared"], start=1):
        here = f"{where} [network] shared[{k}]"
        if not isinstance(item, list) or not item:
            raise CamcadError(f"shared[{k}] must be a list of event names, got {excerpt(item)}", here,
                              'write shared = [["group1:8", "10.1"]]')
        shared.append(tuple(_text(e, "shared", here) for e in item))
    shaft = None
    if raw.get("shaft") is not None:
        shaft = read_table(raw["shaft"], SHAFT_FIELDS, f"{where} [shaft]")
        for cam in shaft["cams"]:
            if not isinstance(cam, str) or SEP not in cam or cam.split(SEP, 1)[0] not in groups:
                raise CamcadError(f"shaft cam {excerpt(cam)} is not \"GROUP:MECHANISM\" of a group", f"{where} [shaft]",
                                  f"name the cams as {', '.join(f'{g}:...' for g in groups)}")
            gname, mech = cam.split(SEP, 1)
            names = [m.name for m in groups[gname].mechanisms]
            if mech not in names:
                raise CamcadError(f"group {gname!r} has no mechanism {mech!r}", f"{where} [shaft]",
                                  nearest_name(mech, names).replace("valid keys", "mechanisms"))
        for key in ("stiffness_N_m_per_rad", "cam_inertia_kg_m2"):
            items = shaft[key]
            if len(items) != len(shaft["cams"]) or any(isinstance(x, bool) or not isinstance(x, (int, float))
                                                       or not math.isfinite(x) or not x > 0 for x in items):
                raise CamcadError(f"'{key}' must hold {len(shaft['cams'])} positive numbers (one per cam), got "
                                  f"{excerpt(items)}", f"{where} [shaft]", f"give {key} = [..., ...]")
        if len(set(shaft["cams"])) != len(shaft["cams"]):
            raise CamcadError("a cam is on the shaft twice", f"{where} [shaft]", "list each cam once")
    return MachineScene(path, name.strip(), description, speeds, settings, groups, group_where, operations,
                        tuple(shared), tuple(notes), shaft)


def _operation(raw: Any, where: str) -> Operation:
    if isinstance(raw, dict):
        raw = dict(raw)
        for key in ("from", "to"):
            if key in raw:
                raw[key] = _text(raw[key], key, where)
    op = read_table(raw, MACHINE_OPERATION_FIELDS, where)
    bounds = op["bounds_deg"]
    if (len(bounds) != 2 or any(isinstance(b, bool) or not isinstance(b, (int, float)) for b in bounds)
            or any(math.isnan(b) for b in bounds)):
        raise CamcadError(f"'bounds_deg' must be [min, max] in deg, got {excerpt(bounds)}", where,
                          "write bounds_deg = [0.0, inf]")
    low, high = float(bounds[0]), float(bounds[1])
    if not math.isfinite(low) or low < 0 or high < low:
        raise CamcadError(f"bounds_deg [{low:g}, {high:g}] must have 0 <= min <= max (min finite)", where,
                          "correct them")
    return Operation(op["from"], op["to"], low, high, name=op["name"])


# --------------------------------------------------------------------------------------------
# The analysis
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class MachineAnalysis:
    """What ``analyse_machine`` found: the machine network, its optimal cyclogram for the objective, and
    every group's scene pipeline run at the machine's phase angles.

    ``result``: MachineResult of the objective; ``other``: of the other objective, when the machine has a
    limiting operation (for the comparison); ``groups``: {group: SceneResult}; ``angles``: {group:
    CyclogramAngles fed to its pipeline}; ``report``: the JSON; ``verdict``: the machine's checks.
    """

    scene: MachineScene
    machine: Machine
    result: MachineResult
    other: MachineResult | None
    groups: dict[str, SceneResult]
    angles: dict[str, Any]
    report: dict
    verdict: Verdict = field(default_factory=Verdict)
    shaft: Any = None       # camcad.dynamics.shaft.ShaftResult, when the scene gives the shaft's stiffness

    @property
    def passed(self) -> bool:
        return bool(self.report["passed"])


def analyse_machine(source: str | Path | MachineScene, options: PipelineOptions = PipelineOptions(),
                    progress: Callable[[str], None] | None = None, objective: str | None = None
                    ) -> MachineAnalysis:
    """A machine scene's cyclogram and every group's profiles at its phase angles (module docstring).

    Parameters
    ----------
    source : str, Path or MachineScene
        The machine file or the scene read from it.
    options : PipelineOptions
        How each group's pipeline runs (``contact_samples`` a count per phase; outputs are written by
        ``camcad.report.machine``).
    progress : callable, optional
        Called with a short text (no unit) as each step starts.
    objective : {"least_cycle", "limiting"}, optional
        Overrides the scene's [machine] objective.

    Returns
    -------
    MachineAnalysis
        ``report["machine"]``: the docs/INTERFACE.md cyclogram keys of the joined network (deg), the objective, the
        limiting operation under both objectives; ``report["groups"]``: each group's pipeline report.

    Raises
    ------
    CamcadError
        Bad input anywhere: one line naming the file and section.
    """
    scene = source if isinstance(source, MachineScene) else read_machine(source)
    say = progress or (lambda _text: None)
    where = f"{scene.path} [network]"
    goal = objective or scene.settings["objective"]
    if goal not in OBJECTIVES:
        raise CamcadError(f"unknown objective {goal!r}", "--objective", f"choose one of {', '.join(OBJECTIVES)}")
    speeds = list(scene.speeds_rpm) if scene.speeds_rpm else None
    groups: list[Group] = []
    found: dict[str, tuple] = {}
    for name, group_scene in scene.groups.items():
        say(f"{name}: phase limits")
        # a broken group network is named where it is written (an inline group is in the machine file)
        parse_cyclogram(group_scene.cyclogram, scene.group_where[name],
                        [m.name for m in group_scene.mechanisms if m.prefix])
        network, limits, skipped, impacts = group_limits(group_scene, speeds, options.contact_samples)
        groups.append(Group(name, network, limits))
        found[name] = (limits, skipped, impacts)
    settings = scene.settings
    machine = make_machine(groups, scene.operations, scene.shared, cycle_deg=settings["cycle_deg"],
                           start_deg=settings["start_deg"], limiting=settings["limiting"],
                           start=settings["start"], end=settings["end"], where=where)
    if goal == "limiting" and machine.limiting is None:
        raise CamcadError("the objective 'limiting' needs a limiting operation", f"{scene.path} [machine]",
                          "name it with limiting = \"x->y\" (or the operation's name)")
    say("machine cyclogram")
    result = optimise_machine(machine, goal, where=where)
    other = None
    if machine.limiting is not None:
        other = optimise_machine(machine, "least_cycle" if goal == "limiting" else "limiting", where=where)
    runs: dict[str, SceneResult] = {}
    angles: dict[str, Any] = {}
    if result.feasible:
        for group in groups:
            limits, skipped, impacts = found[group.name]
            own = result.groups[group.name]
            group_scene = scene.groups[group.name]
            angles[group.name] = CyclogramAngles(own, group.network, limits, skipped,
                                                 retimed_phases(group_scene, own), speeds, impacts)
            say(f"{group.name}: the mechanisms at the machine's phase angles")
            runs[group.name] = analyse_scene(group_scene, options, say, angles=angles[group.name])
    verdict = machine_verdict(result, other)
    report = _report(scene, machine, result, other, runs, verdict)
    shaft = None
    if scene.shaft is None:
        report["skipped"] = {"shaft": "no [shaft] in scene: the main shaft is rigid"}
    elif not runs:
        report["skipped"] = {"shaft": "the machine's cyclogram is infeasible"}
    else:
        say("the elastic main shaft")
        shaft = shaft_run(scene, runs)
        report["shaft"] = shaft_report(shaft)
    return MachineAnalysis(scene, machine, result, other, runs, angles, report, verdict, shaft)


def shaft_run(scene: MachineScene, runs: dict[str, SceneResult]):
    """Simulate the scene's [shaft]: its cams (each with its law at the machine's phase angles and the chain
    of its [dynamics]) on the elastic main shaft, at [shaft] rpm or the machine's fastest speed."""
    table = scene.shaft or {}
    where = f"{scene.path} [shaft]"
    cams = []
    for name, inertia in zip(table["cams"], table["cam_inertia_kg_m2"]):
        gname, mech_name = name.split(SEP, 1)
        group = scene.groups[gname]
        mech = group.mechanism(mech_name)
        if not mech.has("dynamics"):
            raise CamcadError(f"cam {name} has no [dynamics]: its follower chain is unknown", where,
                              f"add [{mech.prefix}dynamics] with natural_frequency_hz, damping_ratio and mass_kg")
        settings = parse_dynamics(mech.sections["dynamics"], mech.where(group.path, "dynamics"))
        if settings.follower.mass_kg is None:
            raise CamcadError(f"cam {name}: its [dynamics] has no mass_kg", mech.where(group.path, "dynamics"),
                              "add mass_kg = ... (the reduced mass of the follower chain)")
        law = runs[gname].runs[mech_name].law
        scale = 1e-3 if settings.output_unit == "mm" else 1.0
        cams.append(ShaftCam(name, law, float(inertia), settings.follower, scale))
    shaft = ElasticShaft(tuple(cams), tuple(float(c) for c in table["stiffness_N_m_per_rad"]),
                         float(table["damping_ratio"]))
    rpm = table["rpm"] if table["rpm"] is not None else (max(scene.speeds_rpm) if scene.speeds_rpm else None)
    if rpm is None:
        raise CamcadError("no speed for the shaft", where, "give [shaft] rpm or [machine] rpm")
    return simulate_shaft(shaft, float(rpm), revolutions=float(table["revolutions"]), samples=table["samples"])


def shaft_report(found) -> dict:
    """The shaft's figures per cam (twist deg, the law's distortion by the twist and the whole dynamic error in
    the law's unit, the peak acceleration ratio) and the shaft's own torsional frequencies (Hz)."""
    cams = []
    for cam, row in zip(found.shaft.cams, found.summary()):
        unit = "mm" if cam.position_scale == 1e-3 else "rad"
        cams.append({"mechanism": row["mechanism"], "twist_max_deg": row["twist_max_deg"],
                     "twist_mean_deg": row["twist_mean_deg"], f"law_distortion_max_{unit}": row["law_distortion_max"],
                     f"dynamic_error_max_{unit}": row["dynamic_error_max"],
                     "peak_accel_ratio": row["peak_accel_ratio"]})
    return rounded_tree({"rpm": found.rpm, "stiffness_N_m_per_rad": list(found.shaft.stiffness_n_m_per_rad),
                         "cam_inertia_kg_m2": [c.cam_inertia_kg_m2 for c in found.shaft.cams],
                         "damping_ratio": found.shaft.damping_ratio,
                         "torsional_frequencies_hz": found.shaft.torsional_frequencies_hz(),
                         "turn_reported": "the last simulated turn", "cams": cams})


def machine_verdict(result: MachineResult, other: MachineResult | None = None) -> Verdict:
    """The machine's checks: the network is feasible; its makespan within the cycle; the limiting operation
    at least its least admissible angle; every machine operation at least its least angle. Warnings: an
    objective whose limiting operation is not longer than the other objective's."""
    found = result.result
    if not found.feasible:
        return Verdict((Check("machine cyclogram feasible", None, None, passed_override=False,
                              note=found.explanation),), ())
    network = found.network
    if result.objective == "limiting":   # the cycle is full by design: the limiting operation takes the rest
        checks = [Check("machine makespan", float(found.makespan_deg or 0.0), None, "deg",
                        applies=f"p({network.end}) - p({network.start}); the limiting operation takes what the "
                                f"groups leave of the {network.cycle_deg:g} deg cycle")]
    else:
        checks = [Check("machine makespan", float(found.makespan_deg or 0.0), float(network.cycle_deg), "deg",
                        applies=f"p({network.end}) - p({network.start}) within the machine cycle")]
    warnings = []
    for label, (owner, _) in result.machine.origin.items():
        if owner:
            continue
        op = network.operation(label)
        if op.min_deg <= 0 and label != result.machine.limiting:
            continue
        angle = float(found.phase_angles_deg[label])
        what = "the limiting operation" if label == result.machine.limiting else "a machine operation"
        checks.append(Check(f"phase angle {label} {op.name}".strip(), angle, float(op.min_deg), "deg", sense="min",
                            applies=f"{what}; least angle from bounds_deg"))
    if (result.limiting_deg is not None and other is not None and other.limiting_deg is not None
            and result.objective == "limiting"):
        gain = result.limiting_deg - other.limiting_deg
        if gain <= 1e-9:
            warnings.append(Warning(f"the limiting operation is no longer ({result.limiting_deg:.6g} deg) than with "
                                    f"the least cycle ({other.limiting_deg:.6g} deg): the groups do not stand in its "
                                    "way", gain, "limiting objective gains nothing"))
    return Verdict(tuple(checks), tuple(warnings))


def _report(scene: MachineScene, machine: Machine, result: MachineResult, other: MachineResult | None,
            runs: dict[str, SceneResult], verdict: Verdict) -> dict:
    body = result.report()
    objectives = {result.objective: _objective_summary(result)}
    if other is not None:
        objectives[other.objective] = _objective_summary(other)
    groups = {name: run.report for name, run in runs.items()}
    passed = verdict.passed and all(run.passed for run in runs.values())
    return {"scene": str(scene.path), "name": scene.name, "description": scene.description,
            "speeds_rpm": None if scene.speeds_rpm is None else list(scene.speeds_rpm),
            "notes": list(scene.notes),
            "machine": rounded_tree({**body, **verdict.to_dict()}),
            "objectives": rounded_tree(objectives), "groups": groups, "passed": passed}


def _objective_summary(result: MachineResult) -> dict:
    if not result.feasible:
        return {"feasible": False, "explanation": result.result.explanation}
    return {"feasible": True, "makespan_deg": result.result.makespan_deg, "least_cycle_deg": result.least_cycle_deg,
            "limiting_deg": result.limiting_deg,
            "group_makespans_deg": {name: found.makespan_deg for name, found in result.groups.items()}}
