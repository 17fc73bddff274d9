"""``camcad compare A B [--scene S]`` as one library function (``run_compare``): two laws on one mechanism, side by
side (the scene's ``[compare]`` section: ``camcad.scene.sections.compare``).

The laws run through the scene pipeline's own mechanism steps — the [linkage] step (the working member
through Π when the scene has one), the unit of the law (``law_unit``), the elastic follower of [dynamics]
(``run_dynamics``, as step 5 runs it) and the contact stress of [contact] (``contact_step``, step 7) — so
each figure is the one ``camcad profile``, ``dynamics`` and ``contact`` give for that law. The kernel that
puts them side by side is ``camcad.dynamics.compare.compare_laws``. The laws are taken as given: a scene's
[filter] is not applied to them (compare the filtered law by naming it).

A scene's ``[compare]`` section names the laws (``a``, ``b``, and further ``[compare.laws]``) and, in
``[[compare.published]]`` tables, published figures to put beside camcad's: each names the figure, the
law (A, B, A/B, B/A, or the reduction 1 − B/A in %), the pair of laws, the speed and motion, and is marked
"published" (an input taken from the source), "reproduced" (within its tolerance), "depends on chosen
inputs" (which) or "not reproduced" (why).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from camcad.dynamics.compare import START_WINDOW_DEG, LawComparison, compare_laws
from camcad.dynamics.runs import run_dynamics
from camcad.errors import CamcadError
from camcad.law.source import load_law
from camcad.scene.commands.source import LAW_UNITS, require_file
from camcad.scene.contact import contact_step
from camcad.scene.fields import parse_speeds
from camcad.scene.file import read_scene
from camcad.scene.laws import BuiltLaw, law_unit, mechanism_law
from camcad.scene.linkage import prepare as prepare_linkage
from camcad.scene.sections.compare import (
    CONTACT_CURVE_POINTS,
    CONTACT_SAMPLES,
    parse_compare,
)
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.scene.sections.follower import profile_follower


@dataclass(frozen=True)
class CompareRequest:
    """What ``camcad compare`` can be asked: the two laws (files; None: the scene's [compare] or its [law];
    one file with a scene is B, compared with the scene's law),
    the scene, the speeds (--rpm text; None: the scene's [machine] rpm), the mechanism of a group scene, the
    harmonics listed, the start-of-motion window (deg) and the working angle of law files (deg)."""

    a: Path | None = None
    b: Path | None = None
    scene: Path | None = None
    rpm: str | None = None
    mechanism: str | None = None
    harmonics: int | None = None
    window_deg: float | None = None
    cycle: float = 360.0
    unit: str | None = None


@dataclass
class PublishedFigure:
    """A published figure beside camcad's, and its status."""

    name: str
    published: Any
    unit: str
    camcad: float | None
    status: str
    applies: str = ""
    source: str = ""
    detail: str = ""
    figure: str | None = None
    law: str = "A"
    rpm: float | None = None

    def to_dict(self) -> dict:
        return {"name": self.name, "published": self.published, "unit": self.unit, "camcad": self.camcad,
                "status": self.status, "applies": self.applies, "source": self.source, "detail": self.detail,
                "figure": self.figure, "law": self.law, "rpm": self.rpm}


@dataclass
class CompareReport:
    """What ``camcad compare`` found: the comparison of A and B, the published figures beside camcad's,
    the laws' sources, and the denser contact sweeps for the plot (``curves``)."""

    comparison: LawComparison
    names: tuple[str, str]
    sources: tuple[dict, dict]
    scene: str | None
    published: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    curves: tuple[Any, Any] = (None, None)
    outputs: list = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        """0: a comparison has no verdict of its own."""
        return 0

    def to_dict(self) -> dict:
        body = {"A": {"name": self.names[0], **self.sources[0]}, "B": {"name": self.names[1], **self.sources[1]},
                **self.comparison.to_dict()}
        if self.published:
            body["published"] = [p.to_dict() for p in self.published]
        body["notes"] = list(self.notes) + list(body.get("notes", []))
        out: dict[str, Any] = {"compare": body}
        if self.scene is not None:
            out["scene"] = self.scene
        if self.outputs:
            out["outputs"] = [str(p) for p in self.outputs]
        return out


@dataclass
class _Context:
    """A scene's mechanism as compare needs it (or nothing, for two law files)."""

    scene: Any = None
    mech: Any = None
    speeds: list = field(default_factory=list)
    unit: str = "mm"
    settings: Any = None
    notes: list = field(default_factory=list)
    laws: dict = field(default_factory=dict)       # name -> (law, source dict)
    runs: dict = field(default_factory=dict)       # name -> DynamicsRun
    sweeps: dict = field(default_factory=dict)     # name -> (table sweep, curve sweep)


def run_compare(request: CompareRequest, progress=None) -> CompareReport:
    """``camcad compare``: two laws on one mechanism, side by side (module docstring).

    Parameters
    ----------
    request : CompareRequest
    progress : callable or None
        Called with a short text as each step starts.

    Returns
    -------
    CompareReport
        ``to_dict()`` is ``{"compare": {...}}`` (A, B and A/B of every figure).
    """
    say = progress or (lambda _text: None)
    if request.unit is not None and request.unit not in LAW_UNITS:
        raise CamcadError(f"unknown unit {request.unit!r}", "--unit", f"use one of {', '.join(LAW_UNITS)}")
    context = _context(request)
    section = _compare_section(context)
    if request.a is not None and request.b is None and context.scene is not None and section.get("a") is None:
        # one law with a scene: compared with the scene's own law
        request = replace(request, a=None, b=request.a)
        context.notes.append("one law given: A is the scene's law, B the law given")
    names: list[str] = ["", ""]
    laws = []
    for index, (given, key) in enumerate(((request.a, "a"), (request.b, "b"))):
        if given is not None:
            laws.append(_law_from_file(context, Path(given), request.cycle))
            names[index] = Path(given).stem
        elif section.get(key) is not None:
            laws.append(_law_from_file(context, context.scene.base_dir / section[key], request.cycle))
            names[index] = section.get(f"name_{key}") or Path(section[key]).stem
        elif index == 0 and context.scene is not None:
            laws.append(_scene_law(context))
            names[index] = section.get("name_a") or "the scene's law"
        else:
            raise CamcadError(f"no law {key.upper()} given", "command line",
                              "give two law files (camcad compare A B), or a scene whose [compare] names b")
    context.laws["A"], context.laws["B"] = laws
    name_a = section.get("name_a") or names[0]
    name_b = section.get("name_b") or names[1]
    harmonics = request.harmonics or section.get("harmonics") or 32
    window = request.window_deg or section.get("start_window_deg") or START_WINDOW_DEG
    comparison = _compare(context, "A", "B", harmonics, window, say)
    published = [_published(context, entry, comparison, harmonics, window, say)
                 for entry in section.get("published", [])]
    curves = (context.sweeps.get("A", (None, None))[1], context.sweeps.get("B", (None, None))[1])
    return CompareReport(comparison, (name_a, name_b), (laws[0][1], laws[1][1]),
                         str(context.scene.path) if context.scene is not None else None, published, context.notes,
                         curves)


def _context(request: CompareRequest) -> _Context:
    context = _Context()
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else None
    if request.scene is not None:
        scene = read_scene(require_file(Path(request.scene), "scene file"))
        if not scene.mechanisms:
            raise CamcadError("the scene has no mechanism", str(scene.path), "add [law] and [follower]")
        if request.mechanism is None and len(scene.mechanisms) > 1:
            names = ", ".join(m.name for m in scene.mechanisms)
            raise CamcadError(f"the scene holds {len(scene.mechanisms)} mechanisms ({names})", str(scene.path),
                              "pick one with --mechanism")
        mech = scene.mechanisms[0] if request.mechanism is None else scene.mechanism(request.mechanism)
        context.scene, context.mech = scene, mech
        if speeds is None and scene.speeds_rpm:
            speeds = list(scene.speeds_rpm)
        if mech.has("filter"):
            context.notes.append("the scene's [filter] is not applied: compare takes both laws as given")
    elif request.mechanism is not None:
        raise CamcadError("--mechanism needs a scene", "--mechanism", "give --scene SCENE.toml")
    if not speeds:
        raise CamcadError("no speed given", "command line", "pass --rpm N1:N2[:STEP], or a scene with [machine] rpm")
    context.speeds = [float(s) for s in speeds]
    context.unit = request.unit or "mm"
    return context


def _compare_section(context: _Context) -> dict:
    if context.scene is None or not context.mech.has("compare"):
        return {"published": []}
    return parse_compare(context.mech.sections["compare"], context.mech.where(context.scene.path, "compare"))


def _settle_unit(context: _Context, law, unit_given: str | None) -> None:
    """The unit of the laws (the scene's for its mechanism, the file's own, or --unit) and the elastic
    follower's settings, once, from the first law."""
    if context.settings is not None or context.laws:
        return
    if context.scene is not None:
        unit, why = law_unit(context.scene, context.mech, unit_given, law)
        context.unit = unit
        if context.mech.has("dynamics"):
            settings = parse_dynamics(context.mech.sections["dynamics"],
                                      context.mech.where(context.scene.path, "dynamics"), math.degrees(law.cycle))
            if unit in ("mm", "rad"):
                context.settings = replace(settings, output_unit=unit)
            else:
                context.notes.append(f"the elastic follower is not run on a law in {unit} ({why})")
        else:
            context.notes.append("no [dynamics] in the scene: the elastic figures are not computed")
    else:
        context.unit = unit_given or context.unit
        context.notes.append("no scene: the rigid and harmonic figures only (give --scene for the elastic follower "
                             "and the contact stress)")


def _scene_law(context: _Context):
    built = mechanism_law(context.scene, context.mech)
    _settle_unit(context, built.law, None)
    return built.law, {"where": str(context.mech.where(context.scene.path, "law")), "notes": list(built.notes),
                       "phases": _phases(built.law)}


def _law_from_file(context: _Context, path: Path, cycle: float):
    path = require_file(path, "law file")
    follower = None
    if context.scene is not None and context.mech.has("follower"):
        follower = profile_follower(context.mech.sections["follower"],
                                    context.mech.where(context.scene.path, "follower"))
    loaded = load_law(path, cycle_deg=cycle, follower=follower)
    unit_given = loaded.unit if context.scene is None else None
    _settle_unit(context, loaded.law, unit_given)
    if loaded.unit is not None and context.unit != loaded.unit:
        raise CamcadError(f"the law is in {loaded.unit}, the mechanism's laws in {context.unit}", str(path),
                          f"give a law in {context.unit} (or --unit)")
    return loaded.law, {"where": str(path), "notes": [loaded.source, *loaded.notes], "phases": _phases(loaded.law)}


def _phases(law) -> str:
    return ",".join(f"{math.degrees(p.start):.6g}:{math.degrees(p.end):.6g}:{p.kind}" for p in law.phases)


def _law_named(context: _Context, name: str, say):
    if name in context.laws:
        return context.laws[name][0]
    if name == "law" and context.scene is not None:
        context.laws["law"] = _scene_law(context)
        return context.laws["law"][0]
    section = _compare_section(context)
    if name not in section.get("laws", {}):
        raise CamcadError(f"no law named {name!r}", context.mech.where(context.scene.path, "compare")
                          if context.scene is not None else "compare",
                          "name A, B, law, or a law of [compare.laws]")
    say(f"reading law {name}")
    context.laws[name] = _law_from_file(context, context.scene.base_dir / section["laws"][name], 360.0)
    return context.laws[name][0]


def _run(context: _Context, name: str, law, say):
    """The elastic follower for one law, once (the pipeline's step 5, through the [linkage] when there is one)."""
    if context.settings is None:
        return None
    if name not in context.runs:
        say(f"law {name}: elastic follower over {len(context.speeds)} speeds")
        working = law
        built, linkage = prepare_linkage(context.scene, context.mech, BuiltLaw(law))
        if linkage is not None:
            working = linkage.working_law(built.law)
        context.runs[name] = run_dynamics(working, context.settings, context.speeds)
    return context.runs[name]


def _sweeps(context: _Context, name: str, law, say):
    """(contact sweep at the compare's speeds, a denser one for the plot), once per law (step 7)."""
    if context.scene is None or not (context.mech.has("contact") and context.mech.has("follower")):
        return None, None
    if name not in context.sweeps:
        say(f"law {name}: contact stress")
        built, linkage = prepare_linkage(context.scene, context.mech, BuiltLaw(law))
        extra = None if linkage is None else (lambda theta: linkage.load_on(built.law, theta))
        table = contact_step(context.scene, context.mech, built.law, context.speeds, CONTACT_SAMPLES, least={},
                             extra_load=extra).sweep
        low, high = min(context.speeds), max(context.speeds)
        dense = sorted(set(np.linspace(0.5 * low, 1.25 * high, CONTACT_CURVE_POINTS).tolist()) | set(context.speeds))
        curve = contact_step(context.scene, context.mech, built.law, dense, CONTACT_SAMPLES, least={},
                             extra_load=extra).sweep
        context.sweeps[name] = (table, curve)
    return context.sweeps[name]


def _compare(context: _Context, first: str, second: str, harmonics: int, window: float, say) -> LawComparison:
    law_a, law_b = _law_named(context, first, say), _law_named(context, second, say)
    runs = (_run(context, first, law_a, say), _run(context, second, law_b, say))
    sweeps = (_sweeps(context, first, law_a, say)[0], _sweeps(context, second, law_b, say)[0])
    return compare_laws(law_a, law_b, context.speeds, settings=context.settings, unit=context.unit,
                        harmonics=harmonics, window_deg=window, contact=sweeps,
                        runs=runs if context.settings is not None else None)


def _published(context: _Context, entry: dict, main: LawComparison, harmonics: int, window: float,
               say) -> PublishedFigure:
    """One published figure beside camcad's (module docstring)."""
    pair = entry["pair"] or ["A", "B"]
    value = entry.get("value")
    unit = entry["unit"]
    camcad_value, applies = None, ""
    if entry["figure"] is not None:
        if len(pair) != 2 or not all(isinstance(p, str) for p in pair):
            raise CamcadError(f"published {entry['name']!r}: pair must name two laws", "[compare]",
                              'write pair = ["A", "B"]')
        comparison = main if tuple(pair) == ("A", "B") else _compare(context, pair[0], pair[1], harmonics, window,
                                                                     say)
        found = comparison.find(entry["figure"], rpm=entry["rpm"], motion=entry["motion"])
        if found is None:
            raise CamcadError(f"published {entry['name']!r}: camcad has no figure {entry['figure']!r}"
                              + (f" at {entry['rpm']:g} rpm" if entry["rpm"] else ""), "[compare]",
                              "name a figure of camcad compare's table (and a speed of the comparison)")
        camcad_value = _select(found, entry["law"])
        which = {"A": pair[0], "B": pair[1], "A/B": f"{pair[0]}/{pair[1]}", "B/A": f"{pair[1]}/{pair[0]}",
                 "reduction": f"1 - {pair[1]}/{pair[0]}"}[entry["law"]]
        applies = f"{which}: {found.label}, {found.applies}"
    status, detail = _status(entry, value, camcad_value)
    return PublishedFigure(entry["name"], value, unit, camcad_value, status, applies, entry["source"] or "", detail,
                           entry["figure"], entry["law"], entry["rpm"])


def _select(found, law: str) -> float | None:
    if law == "A":
        return found.a
    if law == "B":
        return found.b
    if found.a is None or found.b is None or found.a == 0 or found.b == 0:
        return None
    if law == "A/B":
        return found.a / found.b
    if law == "B/A":
        return found.b / found.a
    return 100.0 * (1.0 - found.b / found.a)


def _status(entry: dict, value, camcad_value) -> tuple[str, str]:
    """(status, why): "published" for an input taken from the source or a figure the inputs were chosen to
    meet; "not reproduced" with the entry's why; "depends on chosen inputs" (which, and how far camcad's
    figure is from the published one) when it depends on inputs the source does not give; "reproduced" when
    camcad's figure, independent of chosen inputs, is within the tolerance; else "not reproduced"."""
    off = _offset(value, camcad_value, entry["tolerance"])
    if entry["why_not"] is not None:
        return "not reproduced", entry["why_not"]
    if entry["input"]:
        return "published", "an input taken from the source" + (f" ({off})" if off else "")
    if entry["calibrated"]:
        return "published", f"calibrated: {entry['depends_on'] or 'camcad inputs chosen to meet it'}" + (
            f" ({off})" if off else "")
    if camcad_value is None or value is None:
        return "not reproduced", "camcad has no value for it"
    if entry["depends_on"] is not None:
        return "depends on chosen inputs", f"{entry['depends_on']}; {off}"
    if off.startswith("within"):
        return "reproduced", off
    return "not reproduced", off


def _offset(value, camcad_value, tol: float) -> str:
    """camcad's figure against the published one, in words ("within 5 %", "+8.8 % off", "below the range")."""
    if value is None or camcad_value is None:
        return ""
    low, high = (value, value) if isinstance(value, float) else (float(value[0]), float(value[1]))
    low, high = min(low, high), max(low, high)
    if low * (1 - tol) <= camcad_value <= high * (1 + tol) or (
            high < 0 and high * (1 - tol) >= camcad_value >= low * (1 + tol)):
        return f"within {100 * tol:g} %"
    reference = high if camcad_value > high else low
    if reference == 0:
        return "off"
    return f"{100 * (camcad_value - reference) / abs(reference):+.3g} % off the published value"


__all__ = ["CompareReport", "CompareRequest", "PublishedFigure", "run_compare"]
