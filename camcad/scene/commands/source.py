"""What every analysis command works on: the law (from a file, a standard shape, or a scene's mechanism as the
scene pipeline builds it), its unit, the speeds, and the phase angles analysed.

- ``LawRequest``: how the user named the law (the docs/INTERFACE.md law-choosing options, ``--unit``,
  ``--phase-angles``, ``--mechanism``, ``--rpm``).
- ``resolve_source(request)`` → ``AnalysisSource``. For a law file or a standard shape: the law itself. For a
  scene: the scene and the mechanism; ``AnalysisSource.machine(options)`` then runs the scene pipeline
  (``camcad.scene.pipeline.analyse_scene``) on it — the [law] and its balance, the [filter], the [linkage]
  (``law_of = "output"``, the working member's inertia through Π), the cyclogram's phase angles and the units —
  so every stand-alone command computes the machine ``camcad profile`` computes, restricted to its model.
  The command's options that stand for a scene key (``--fn`` for ``[dynamics] natural_frequency_hz``, ``--rpm``
  for ``[machine] rpm``, …) are written into the scene first (``AnalysisSource.with_overrides``), and are
  validated as those keys.

File kinds: a ``.toml`` file is a scene; so is any other file whose text is TOML with a scene's keys
(``looks_like_scene``). A DXF or table file given to a command that needs a scene (and the reverse) gets
one line saying which command takes it (``require_scene``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from camcad.errors import CamcadError
from camcad.io.input_file import is_regular_file
from camcad.law.source import load_law
from camcad.law.standard import SHAPES
from camcad.scene.analysis_report import PhaseAngles
from camcad.scene.fields import parse_speeds
from camcad.scene.file import Mechanism, Scene, read_scene
from camcad.scene.laws import build_law, pipeline_angles
from camcad.scene.models import model_law, model_unit
from camcad.scene.pipeline import MechanismRun, PipelineOptions, analyse_scene
from camcad.scene.sections.law import LawSpec

#: the units a law's displacement may have: mm (translating follower), rad or deg of swing (oscillating)
LAW_UNITS = ("mm", "rad", "deg")
PHASE_ANGLE_CHOICES = ("auto", "law", "cyclogram")
#: cam-angle samples per phase for the contact-stress maximum and its phase limits (the pipeline's default)
CONTACT_SAMPLES = 2000
_SCENE_KEYS = ("law", "mechanisms", "cyclogram", "machine", "follower", "contact", "dynamics", "stops", "filter",
               "linkage")


# --------------------------------------------------------------------------------------------
# What the user asked for, and what it resolves to
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LawRequest:
    """How the law was named: a file or ``standard`` with the docs/INTERFACE.md options, the unit of its
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


@dataclass
class AnalysisSource:
    """The law an analysis runs on and where it came from (see the module docstring).

    A law file or standard shape: ``law`` is the law, ``unit`` the unit of its displacement, ``angles`` its
    phase angles. A scene: ``scene`` and ``mechanism`` (``law`` is None until ``machine`` has run the
    pipeline; then ``law``, ``unit`` and ``angles`` are those of the model law the pipeline analyses).
    ``speeds``: the speeds asked for (--rpm, else the scene's [machine] rpm; None when neither).
    """

    law: Any
    name: str
    where: str
    notes: list = field(default_factory=list)
    scene: Scene | None = None
    mechanism: Mechanism | None = None
    loaded: Any = None
    unit: str = "mm"
    angles: PhaseAngles | None = None
    speeds: list | None = None
    inputs: list = field(default_factory=list)
    phase_angles: str = "auto"
    run: MechanismRun | None = None

    def section(self, name: str):
        """The raw table of the mechanism's section ``name``, or None."""
        return None if self.mechanism is None else self.mechanism.sections.get(name)

    def section_where(self, name: str) -> str:
        return self.mechanism.where(self.scene.path, name) if self.mechanism is not None and self.scene is not None \
            else self.where

    def require_speeds(self, command: str) -> list[float]:
        if self.speeds:
            return list(self.speeds)
        where = f"{self.where} [machine]" if self.scene is not None else "command line"
        raise CamcadError("no speed given", where,
                          f"add [machine] rpm = ... to the scene or pass --rpm N1:N2[:STEP] to camcad {command}")

    def with_overrides(self, section: str, values: dict, drop: tuple[str, ...] = ()) -> AnalysisSource:
        """This source with the mechanism's ``[section]`` keys set to ``values`` (and ``drop`` removed), as a
        command's options ask; the section is made when the scene lacks it. A law file is returned as it is."""
        if self.scene is None or self.mechanism is None or not (values or drop):
            return self
        table = {k: v for k, v in dict(self.mechanism.sections.get(section) or {}).items() if k not in drop}
        table.update(values)
        mech = replace(self.mechanism, sections={**self.mechanism.sections, section: table})
        scene = replace(self.scene, mechanisms=tuple(mech if m.name == mech.name else m
                                                     for m in self.scene.mechanisms), built_laws={})
        return replace(self, scene=scene, mechanism=mech)

    def machine(self, models: tuple[str, ...], **options: Any) -> MechanismRun:
        """The scene pipeline's run of the mechanism (``camcad.scene.pipeline.analyse_scene``), with only
        ``models`` in its analysis pass, the speeds asked for and the phase angles asked for; sets ``law``,
        ``unit``, ``angles`` and ``notes`` from it. ``options``: further ``PipelineOptions`` fields."""
        if self.scene is None or self.mechanism is None:
            raise CamcadError("a scene's machine needs a scene", self.where, "give the scene file")
        scene = self.scene if self.speeds is None else replace(self.scene, speeds_rpm=tuple(self.speeds))
        settings = PipelineOptions(plots=(), models=models, mechanisms=(self.mechanism.name,),
                                   use_cyclogram=self.phase_angles != "law", **options)
        result = analyse_scene(scene, settings)
        cyclogram = result.report.get("cyclogram")
        if cyclogram is not None and not cyclogram["feasible"]:
            raise CamcadError("the scene's cyclogram is infeasible, so it has no phase angles "
                              f"({cyclogram.get('explanation', '')})", f"{scene.path} [cyclogram]",
                              "run camcad cyclogram to see the conflict, or use --phase-angles law")
        run = result.runs[self.mechanism.name]
        self.run = run
        self.law, self.unit = model_law(run), model_unit(run)
        angles = pipeline_angles(scene, self.mechanism, run.law)
        if scene.cyclogram is not None and self.mechanism.prefix and self.phase_angles == "law":
            angles = replace(angles, note="asked for with --phase-angles law")
        self.angles = angles
        self.notes = list(run.report["law"]["notes"])
        if run.linkage is not None:
            self.notes.append(f"the working member behind the [linkage] is analysed ({self.unit}), as camcad profile "
                              "does")
        elif run.unit == "deg":
            self.notes.append("the law's swing in deg is analysed in rad, as camcad profile does")
        elif run.unit != "mm":
            self.notes.append(f"the law's displacement is in {run.unit} (the scene's follower)")
        if "filter" in run.ran:
            self.notes.append("the scene's [filter] was applied first, as camcad profile does (its law is analysed)")
        return run

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



def resolve_source(request: LawRequest, *, allow_scene: bool = True, scene_only: bool = False,
                   command: str = "", require: tuple[tuple[str, str], ...] = ()) -> AnalysisSource:
    """The law of a drawn law file or a standard shape, or a scene (.toml) and its mechanism (one picked with
    --mechanism), with the speeds and the phase angles asked for (module docstring).

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
            return _scene_source(source, request, speeds, require)
    if scene_only:
        raise CamcadError("no scene given", "command line", f"give a scene file: camcad {command} SCENE.toml")
    if request.phase_angles == "cyclogram":
        raise CamcadError("--phase-angles cyclogram needs a scene with a [cyclogram]", "--phase-angles",
                          "give the scene, or leave --phase-angles out")
    unit = request.unit or "mm"
    if standard is not None:
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
    loaded = load_law(source, layer=request.layer, handle=request.handle, cycle_deg=request.cycle, lift=request.lift,
                      phases=request.phases, x_deg=request.x_deg)
    note = ("given with --phases" if request.phases is not None else "restored from camcad's record in the file"
            if loaded.phases_from_record else "detected from the law")
    unit = request.unit or loaded.unit or "mm"   # a swing table, or camcad's record, says its unit
    return AnalysisSource(loaded.law, source.stem, str(source), [loaded.source, *loaded.notes], loaded=loaded,
                          unit=unit, angles=PhaseAngles.of_law(loaded.law, note=note), speeds=speeds,
                          inputs=[source])


def _scene_source(path: Path, request: LawRequest, speeds, require: tuple[tuple[str, str], ...] = ()) \
        -> AnalysisSource:
    for option, value in (("--standard", request.standard), ("--phases", request.phases), ("--lift", request.lift),
                          ("--layer", request.layer), ("--handle", request.handle), ("--unit", request.unit)):
        if value is not None:
            raise CamcadError(f"{option} given with a scene", option,
                              "change the scene's [law] instead (the scene decides the law and its unit), "
                              "or give the law file itself")
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
    if request.phase_angles == "cyclogram" and not (scene.cyclogram is not None and mech.prefix):
        raise CamcadError("the scene has no [cyclogram]", str(scene.path),
                          "use --phase-angles law (the law's own), or add a [cyclogram]")
    if speeds is None and scene.speeds_rpm:
        speeds = list(scene.speeds_rpm)
    name = mech.name if len(scene.mechanisms) > 1 or mech.prefix else scene.name
    return AnalysisSource(None, name, str(path), [], scene, mech, speeds=speeds, inputs=scene.input_files(),
                          phase_angles=request.phase_angles)
