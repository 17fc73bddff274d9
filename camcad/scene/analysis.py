"""What every analysis command works on, and what it returns: the law (from a file, a standard shape or a
scene), its unit, the phase angles analysed, and the report object the CLI, ``--json`` and the scene
pipeline share.

- ``LawRequest``: how the user named the law (the SPEC.md law-choosing options, ``--unit``,
  ``--phase-angles``, ``--mechanism``).
- ``resolve_source(request)`` → ``AnalysisSource``: the law, a name for the outputs, the scene and the
  mechanism when there is one, the unit of the law's displacement (mm, rad, deg) and the phase angles
  analysed (``PhaseAngles``: the law's own, or the cyclogram's — the ones ``camcad profile SCENE`` ends
  with). A scene with a [cyclogram] is analysed with the cyclogram's phase angles by default, so every
  command agrees with ``camcad profile``; ``--phase-angles law`` asks for the law's own.
- ``AnalysisReport``: the analysis object under its SPEC.md key (figures, ``checks``, ``warnings``,
  ``passed``), the source it ran on, and the objects the plots need. ``to_dict`` is the JSON of the
  command; ``analysis_dict`` the object the pipeline puts in report.json — one definition of each key.

File kinds: a ``.toml`` file is a scene; so is any other file whose text is TOML with a scene's keys
(``looks_like_scene``). A DXF or table file given to a command that needs a scene (and the reverse) gets
one line saying which command takes it (``require_scene``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from camcad.errors import CamcadError
from camcad.io.input_file import is_regular_file
from camcad.verdict import Verdict, rounded

#: the units a law's displacement may have: mm (translating follower), rad or deg of swing (oscillating)
LAW_UNITS = ("mm", "rad", "deg")
PHASE_ANGLE_CHOICES = ("auto", "law", "cyclogram")
#: cam-angle samples per phase for the contact-stress maximum and its phase limits (the pipeline's default)
CONTACT_SAMPLES = 2000
_SCENE_KEYS = ("law", "mechanisms", "cyclogram", "machine", "follower", "contact", "dynamics", "stops", "filter")


# --------------------------------------------------------------------------------------------
# What the user asked for, and what it resolves to
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LawRequest:
    """How the law was named: a file or ``standard`` with the SPEC.md options, the unit of its
    displacement (None: mm for a law file, from the scene for a scene), which phase angles to analyse
    ("auto": the cyclogram's when the scene has one), the mechanism of a group scene, and the speeds
    (``rpm``: the --rpm text, None: the scene's [machine] rpm)."""

    source: Path | None = None
    standard: str | None = None
    return_standard: str | None = None
    phases: str | None = None
    lift: float | None = None
    layer: str | None = None
    handle: str | None = None
    cycle: float = 360.0
    x_deg: bool = False
    mechanism: str | None = None
    unit: str | None = None
    phase_angles: str = "auto"
    rpm: str | None = None
    samples: int = CONTACT_SAMPLES


@dataclass(frozen=True)
class PhaseAngles:
    """Which phase angles an analysis ran with: ``source`` "law" (the law's own: given, detected or the
    scene's [law] phases) or "cyclogram" (the optimised cyclogram's, as ``camcad profile`` uses them),
    the phases (start_deg, end_deg, kind) and a note (e.g. held at a limit by the cyclogram)."""

    source: str
    phases_deg: tuple[tuple[float, float, str], ...]
    note: str = ""

    @property
    def text(self) -> str:
        """"0:90:dwell,90:180:rise,..." (deg)."""
        return ",".join(f"{float(a):.10g}:{float(b):.10g}:{k}" for a, b, k in self.phases_deg)

    def describe(self) -> str:
        """One line: whose phase angles, and the motions' angles."""
        motions = ", ".join(f"{k} {rounded(float(b) - float(a), 6):g} deg" for a, b, k in self.phases_deg
                            if k != "dwell")
        whose = "the cyclogram's phase angles" if self.source == "cyclogram" else "the law's own phase angles"
        return f"{whose} ({motions})" if motions else whose

    def to_dict(self) -> dict:
        out = {"source": self.source, "phases": self.text}
        if self.note:
            out["note"] = self.note
        return out

    @classmethod
    def of_law(cls, law, source: str = "law", note: str = "") -> PhaseAngles:
        return cls(source, tuple((math.degrees(p.start), math.degrees(p.end), p.kind) for p in law.phases), note)


@dataclass
class AnalysisSource:
    """The law an analysis runs on and where it came from (see the module docstring).

    ``law`` is the law with the phase angles analysed (retimed by the cyclogram when ``angles.source`` is
    "cyclogram"); ``unit`` the unit of its displacement; ``speeds`` the speeds asked for (--rpm, else the
    scene's [machine] rpm; None when neither); ``cyclogram`` the ``CyclogramAngles`` when they were used.
    """

    law: Any
    name: str
    where: str
    notes: list = field(default_factory=list)
    scene: Any = None
    mechanism: Any = None
    loaded: Any = None
    unit: str = "mm"
    angles: PhaseAngles | None = None
    speeds: list | None = None
    cyclogram: Any = None
    inputs: list = field(default_factory=list)

    def section(self, name: str):
        """The raw table of the mechanism's section ``name``, or None."""
        return None if self.mechanism is None else self.mechanism.sections.get(name)

    def section_where(self, name: str) -> str:
        return self.mechanism.where(self.scene.path, name) if self.mechanism is not None else self.where

    def require_speeds(self, command: str) -> list[float]:
        if self.speeds:
            return list(self.speeds)
        where = f"{self.where} [machine]" if self.scene is not None else "command line"
        raise CamcadError("no speed given", where,
                          f"add [machine] rpm = ... to the scene or pass --rpm N1:N2[:STEP] to camcad {command}")

    def summary(self) -> dict:
        out: dict[str, Any] = {"name": self.name, "where": self.where, "unit": self.unit, "notes": list(self.notes)}
        if self.angles is not None:
            out["phase_angles"] = self.angles.to_dict()
        if self.mechanism is not None and self.scene is not None and len(self.scene.mechanisms) > 1:
            out["mechanism"] = self.mechanism.name
        return out


def looks_like_scene(path: Path) -> bool:
    """True when ``path`` is a scene: named .toml, or TOML text holding a scene's top-level keys."""
    path = Path(path)
    if path.suffix.lower() == ".toml":
        return True
    if not is_regular_file(path):   # a FIFO or a device is never read here (it would block or never end)
        return False
    try:
        with open(path, "rb") as stream:
            head = stream.read(1 << 20)
    except OSError:
        return False
    if b"\0" in head[:4096]:
        return False
    try:
        import tomllib

        data = tomllib.loads(head.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        return False
    return any(key in data for key in _SCENE_KEYS)


def _kind_of_law_file(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix == ".dxf":
        return "a DXF drawing"
    if suffix in (".csv", ".txt", ".tsv", ".dat"):
        return "a table of the acceleration law"
    if not is_regular_file(path):
        return "not a regular file (a FIFO, a device or a socket)"
    try:
        with open(path, "rb") as stream:
            start = stream.read(256)
    except OSError:
        return "not a scene"
    head = start[:64].lstrip()
    if head.startswith(b"0") and b"SECTION" in start:
        return "a DXF drawing"
    return "not a scene (TOML)"


def require_file(path: Path, what: str = "file") -> Path:
    """``path`` when it is an existing file; else one line saying what is wrong with it."""
    path = Path(path)
    if path.is_dir():
        raise CamcadError(f"is a folder, not a {what}", str(path), f"give the {what} itself")
    if not path.exists():
        raise CamcadError(f"no such {what}", str(path), "check the path")
    return path


def require_scene(path: Path, command: str) -> Path:
    """``path`` when it is a scene; a law file given instead gets one line naming the commands that take it."""
    path = require_file(path, "scene file")
    if not looks_like_scene(path):
        raise CamcadError(f"is {_kind_of_law_file(path)}, not a scene; camcad {command} needs a scene (.toml, "
                          "docs/SCENE.md)", str(path),
                          "write a scene whose [law] file = names it, or analyse the law itself with camcad "
                          "spectrum, dynamics or impact")
    return path


def law_unit(scene, mech, override: str | None, law=None) -> tuple[str, str]:
    """(unit of the law's displacement, how it was decided) for a scene's mechanism.

    Order: ``override`` (--unit); [dynamics] output_unit; an oscillating [follower]: rad, or deg when its
    ``swing`` (deg) equals the law's stroke (within 1e-6) — the [law] lift is then in deg of swing; else mm.
    """
    if override is not None:
        return override, "--unit"
    if mech is None:
        return "mm", "a law file: mm unless --unit says otherwise"
    dynamics = mech.sections.get("dynamics")
    if isinstance(dynamics, dict) and dynamics.get("output_unit") in ("mm", "rad"):
        return dynamics["output_unit"], f"[{mech.prefix}dynamics] output_unit"
    follower = mech.sections.get("follower")
    if isinstance(follower, dict) and follower.get("type") == "oscillating":
        swing = follower.get("swing")
        if law is not None and isinstance(swing, (int, float)) and not isinstance(swing, bool):
            import numpy as np

            stroke = float(np.ptp(law.kinematics(np.linspace(0.0, law.cycle, 4097)).s))
            if abs(stroke - float(swing)) <= 1e-6 * float(swing):
                return "deg", f"[{mech.prefix}follower] oscillating, stroke = swing in deg"
        return "rad", f"[{mech.prefix}follower] oscillating: the law is its swing in rad"
    return "mm", "translating follower"


def resolve_source(request: LawRequest, *, allow_scene: bool = True, scene_only: bool = False,
                   command: str = "", require: tuple[tuple[str, str], ...] = ()) -> AnalysisSource:
    """The law of a scene (.toml, one mechanism picked with --mechanism), a drawn law file, or a standard
    shape, with its unit, its speeds and the phase angles analysed (module docstring).

    Parameters
    ----------
    request : LawRequest
    allow_scene : bool
        False for commands that take a law only.
    scene_only : bool
        True for commands that take a scene only.
    command : str
        The command's name, for messages.
    require : tuple of (section, fix)
        Sections a scene's mechanism must have (checked before anything is computed), with how to add them.

    Returns
    -------
    AnalysisSource
    """
    from camcad.scene.fields import parse_speeds

    if request.unit is not None and request.unit not in LAW_UNITS:
        raise CamcadError(f"unknown unit {request.unit!r}", "--unit", f"use one of {', '.join(LAW_UNITS)}")
    if request.phase_angles not in PHASE_ANGLE_CHOICES:
        raise CamcadError(f"--phase-angles {request.phase_angles!r} is not one of {', '.join(PHASE_ANGLE_CHOICES)}",
                          "--phase-angles", "use law (the law's own) or cyclogram (the optimised cyclogram's)")
    source, standard = request.source, request.standard
    if source is not None and standard is not None:
        raise CamcadError("both a file and --standard given", "command line", "give one law source")
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else None
    if source is not None:
        source = Path(source)
        if scene_only:
            require_scene(source, command)
        else:
            require_file(source, "law or scene file")
        if looks_like_scene(source):
            if not allow_scene:
                raise CamcadError("is a scene, not a law", str(source), "give the law file the scene's [law] names")
            return _scene_source(source, request, speeds, command, require)
    if scene_only:
        raise CamcadError("no scene given", "command line", f"give a scene file: camcad {command} SCENE.toml")
    if request.phase_angles == "cyclogram":
        raise CamcadError("--phase-angles cyclogram needs a scene with a [cyclogram]", "--phase-angles",
                          "give the scene, or leave --phase-angles out")
    unit = request.unit or "mm"
    if standard is not None:
        from camcad.law.standard import SHAPES
        from camcad.scene.law import LawSpec, build_law

        if request.phases is None or request.lift is None:
            raise CamcadError("a standard law needs its phases and lift", "--standard",
                              'add --phases "0:90:dwell,90:180:rise,180:270:dwell,270:360:return" --lift 25')
        for option, shape in (("--standard", standard), ("--return-standard", request.return_standard)):
            if shape is not None and shape not in SHAPES:
                raise CamcadError(f"unknown law {shape!r}", option, f"use one of {', '.join(sorted(SHAPES))}")
        built = build_law(LawSpec(where="--standard", standard=standard, return_standard=request.return_standard,
                                  phases=request.phases, lift=request.lift, cycle=request.cycle))
        return AnalysisSource(built.law, standard, "--standard", list(built.notes), unit=unit,
                              angles=PhaseAngles.of_law(built.law, note="given with --phases"), speeds=speeds)
    if source is None:
        raise CamcadError("no law given", "command line", "give a scene, a law file, or --standard NAME")
    from camcad.law.source import load_law

    loaded = load_law(source, layer=request.layer, handle=request.handle, cycle_deg=request.cycle, lift=request.lift,
                      phases=request.phases, x_deg=request.x_deg)
    note = "given with --phases" if request.phases is not None else "detected from the law"
    return AnalysisSource(loaded.law, source.stem, str(source), [loaded.source, *loaded.notes], loaded=loaded,
                          unit=unit, angles=PhaseAngles.of_law(loaded.law, note=note), speeds=speeds,
                          inputs=[source])


def _scene_source(path: Path, request: LawRequest, speeds, command: str,
                  require: tuple[tuple[str, str], ...] = ()) -> AnalysisSource:
    from camcad.scene.file import mechanism_law, read_scene

    for option, value in (("--standard", request.standard), ("--phases", request.phases), ("--lift", request.lift),
                          ("--layer", request.layer), ("--handle", request.handle)):
        if value is not None:
            raise CamcadError(f"{option} given with a scene", option,
                              "change the scene's [law] instead, or give the law file itself")
    scene = read_scene(path)
    if not scene.mechanisms:
        raise CamcadError("the scene has no mechanism with a law", str(path),
                          "add [law], or [mechanisms.NAME] tables (camcad cyclogram runs a bare network)")
    if request.mechanism is None:
        if len(scene.mechanisms) > 1:
            names = ", ".join(m.name for m in scene.mechanisms)
            raise CamcadError(f"the scene holds {len(scene.mechanisms)} mechanisms ({names})", str(path),
                              "pick one with --mechanism")
        mech = scene.mechanisms[0]
    else:
        mech = scene.mechanism(request.mechanism)
    for section, fix in require:
        if not mech.has(section):
            raise CamcadError(f"the scene has no [{section}] section", mech.where(scene.path, section), fix)
    if speeds is None and scene.speeds_rpm:
        speeds = list(scene.speeds_rpm)
    built = mechanism_law(scene, mech)
    name = mech.name if len(scene.mechanisms) > 1 or mech.prefix else scene.name
    law, notes = built.law, list(built.notes)
    angles, cyclogram = scene_phase_angles(scene, mech, law, request, speeds)
    if angles.source == "cyclogram":
        from camcad.scene.mechanism import law_with_phases

        law = law_with_phases(law, list(angles.phases_deg), mech.where(scene.path, "law"))
    unit, why = law_unit(scene, mech, request.unit, law)
    if unit != "mm":
        notes.append(f"the law's displacement is in {unit} ({why})")
    return AnalysisSource(law, name, str(path), notes, scene, mech, built.loaded, unit, angles, speeds, cyclogram,
                          scene.input_files())


def scene_phase_angles(scene, mech, law, request: LawRequest, speeds) -> tuple[PhaseAngles, Any]:
    """The phase angles to analyse a scene's mechanism with, and the CyclogramAngles when they are the
    cyclogram's (see the module docstring)."""
    choice = request.phase_angles
    has_cyclogram = scene.cyclogram is not None and bool(mech.prefix)
    if choice == "cyclogram" and not has_cyclogram:
        raise CamcadError("the scene has no [cyclogram]", str(scene.path),
                          "use --phase-angles law (the law's own), or add a [cyclogram]")
    if choice == "law" or not has_cyclogram:
        note = "asked for with --phase-angles law" if choice == "law" and has_cyclogram else "the scene's [law]"
        return PhaseAngles.of_law(law, note=note), None
    from camcad.scene.phase_angles import cyclogram_angles

    found = cyclogram_angles(scene, speeds, request.samples)
    if not found.result.feasible:
        raise CamcadError("the scene's cyclogram is infeasible, so it has no phase angles "
                          f"({found.result.explanation})",
                          f"{scene.path} [cyclogram]", "run camcad cyclogram to see the conflict, or use "
                          "--phase-angles law")
    phases = found.phases.get(mech.name)
    if phases is None:
        return PhaseAngles.of_law(law, note="no operation of the cyclogram moves this mechanism"), found
    return PhaseAngles("cyclogram", tuple(tuple(p) for p in phases), found.held_note(mech.name)), found


def pipeline_angles(scene, mech, law) -> PhaseAngles:
    """The phase angles of ``law`` in the scene pipeline: the cyclogram's when the scene has a [cyclogram]
    and ``law``'s phases differ from the mechanism's [law] (the pipeline's retimed pass), else the law's own."""
    if scene.cyclogram is not None and mech.prefix:
        from camcad.scene.file import mechanism_law

        own = PhaseAngles.of_law(mechanism_law(scene, mech).law)
        mine = PhaseAngles.of_law(law)
        if len(own.phases_deg) != len(mine.phases_deg) or any(
                abs(a[0] - b[0]) > 1e-9 or abs(a[1] - b[1]) > 1e-9 or a[2] != b[2]
                for a, b in zip(own.phases_deg, mine.phases_deg)):
            return PhaseAngles("cyclogram", mine.phases_deg, "retimed by the cyclogram")
    return PhaseAngles.of_law(law)


# --------------------------------------------------------------------------------------------
# The report every analysis command returns
# --------------------------------------------------------------------------------------------

def rounded_tree(value: Any, digits: int | None = None) -> Any:
    """Every float in a JSON-like tree rounded to its meaningful digits (``camcad.verdict.rounded``).

    Examples
    --------
    >>> rounded_tree({"a": [169.99999999999997, 1], "b": {"c": 0.30000000000000004}})
    {'a': [170.0, 1], 'b': {'c': 0.3}}
    """
    if isinstance(value, dict):
        return {k: rounded_tree(v, digits) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [rounded_tree(v, digits) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        return rounded_tree(value.tolist(), digits)
    if isinstance(value, float):
        return rounded(value) if digits is None else rounded(value, digits)
    return value


@dataclass
class AnalysisReport:
    """What an analysis command returns (module docstring).

    ``key``: the SPEC.md key of the analysis object (spectrum, dynamics, impact, contact, cyclogram);
    ``body``: its figures; ``verdict``: its checks and warnings; ``source``: ``AnalysisSource.summary()``
    (or the scene for contact and cyclogram); ``result``: the analysis objects the plots need;
    ``skipped``: steps not run and why.
    """

    key: str
    body: dict
    verdict: Verdict
    source: dict = field(default_factory=dict)
    result: Any = None
    skipped: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.verdict.passed

    @property
    def exit_code(self) -> int:
        """SPEC.md: 0 when every check passed, 1 when one failed."""
        return 0 if self.passed else 1

    def analysis_dict(self) -> dict:
        """The analysis object: its figures, ``passed``, ``checks``, ``tightest`` and ``warnings`` (rounded)."""
        return rounded_tree({**self.body, **self.verdict.to_dict()})

    def to_dict(self) -> dict:
        """The command's JSON: the source, the phase angles analysed and the analysis object."""
        out = rounded_tree(dict(self.source))
        if self.skipped:
            out["skipped"] = dict(self.skipped)
        out[self.key] = self.analysis_dict()
        return out
