"""A mechanism's law as the scene pipeline carries it: built from its ``[law]`` section (a standard law, or a drawn
law read and balanced when asked), retimed to other phase angles, the unit of its displacement, and the phase
angles an analysis of it runs with.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import cast

import numpy as np

from camcad.balance.checking import check
from camcad.balance.correction import correct
from camcad.errors import CamcadError
from camcad.law.law import Phase
from camcad.law.phases import parse_phases
from camcad.law.retime import retime
from camcad.law.segments import solve_segments
from camcad.law.source import load_law
from camcad.law.standard import compose
from camcad.scene.analysis_report import PhaseAngles
from camcad.scene.file import Mechanism, Scene
from camcad.scene.sections.follower import profile_follower
from camcad.scene.sections.law import LawSpec, parse_law


@dataclass(frozen=True)
class BuiltLaw:
    """The law a scene runs with, and how it came to be."""

    law: object
    notes: tuple[str, ...] = ()
    loaded: object | None = None          # LoadedLaw for a drawn law
    balance: dict | None = None           # check of the drawn law (before any fix)
    correction: object | None = None      # balance.Correction when fixed
    extra: dict = field(default_factory=dict)


def build_law(spec: LawSpec, follower_table=None, follower_where: str = "[follower]") -> BuiltLaw:
    """The law of a scene: composed from standard shapes or segments, or read (and balanced when asked) from a
    file; a radius-vector table through the scene's [follower] (``follower_table``)."""
    if spec.segments is not None:
        segment_law = solve_segments(spec.segments, spec.cycle, f"{spec.where} segments")
        classes = ", ".join(sorted({j.class_ for j in segment_law.joints}))
        return BuiltLaw(segment_law, (f"segment law: {segment_law.describe()}",
                                      f"joints {classes} ({', '.join(j.class_ for j in segment_law.joints)})"))
    if spec.standard is not None:
        # parse_law refuses a standard law without phases and lift
        phases = parse_phases(cast(str, spec.phases), spec.cycle, where=f"{spec.where} phases")
        widths = [(p.kind, (p.end - p.start) * 180.0 / 3.141592653589793) for p in phases]
        try:
            law = compose(widths, cast(float, spec.lift), spec.standard, spec.return_standard, cycle_deg=spec.cycle)
        except ValueError as err:
            raise CamcadError(str(err), spec.where, "give as many returns as rises, covering the cycle") from None
        name = spec.standard + (f"/{spec.return_standard}" if spec.return_standard else "")
        return BuiltLaw(law, (f"standard law {name}, lift {spec.lift:g}, phases {spec.phases}",))
    loaded = load_law(cast(Path, spec.file), layer=spec.layer, handle=spec.handle,
                      cycle_deg=spec.cycle if spec.cycle_stated else None, lift=spec.lift,
                      phases=spec.phases, x_deg=spec.x_deg, y0=spec.y0, x0=spec.x0,
                      follower=profile_follower(follower_table, follower_where), smoothing=spec.smoothing_error,
                      accel_smoothing=spec.accel_smoothing)
    report = check(loaded.law, spec.tol)
    notes = [loaded.source, *loaded.notes]
    if loaded.mm_per_unit != 1.0:   # a drawing in inches or centimetres: its lengths become mm here
        unit, factor = loaded.length_unit, loaded.mm_per_unit
        notes.append(f"the law is drawn in {unit}: rise {report.rise:.6g} {unit} = {report.rise * factor:.6g} mm, "
                     f"return {report.return_:.6g} {unit}; converted to mm (x {factor:g}) for the follower")
        loaded = replace(loaded, law=loaded.law.with_ordinates(loaded.law.a * factor), y_scale=loaded.y_scale * factor,
                         length_unit="mm", mm_per_unit=1.0)
        report = check(loaded.law, spec.tol)
    if spec.fix == "none":
        if not report.balanced:
            notes.append("the drawn law is NOT balanced (fix = \"min-change\" in [law] corrects it)")
        return BuiltLaw(loaded.law, tuple(notes), loaded, report.to_dict())
    result = correct(loaded.law, spec.fix, tol=spec.tol, where=str(spec.file))
    notes.append(f"balanced with mode {spec.fix}: RMS change {result.rms_change / loaded.y_scale:.4g}, "
                 f"max change {result.max_change / loaded.y_scale:.4g} (input y units)")
    return BuiltLaw(result.law, tuple(notes), loaded, report.to_dict(), result)


def mechanism_law(scene: Scene, mech: Mechanism, phases=None):
    """The law a mechanism's [law] section describes, balanced when it asks, optionally retimed to ``phases``.

    Parameters
    ----------
    scene : Scene
        The scene (``read_scene``); the law is built once and cached in it.
    mech : Mechanism
        One of ``scene.mechanisms``.
    phases : tuple of Phase, optional
        New phases (start and end in rad) to retime the law to, as a cyclogram gives them; None: as
        written.

    Returns
    -------
    BuiltLaw
        ``law`` (a MotionLaw: θ in rad, s in mm, or rad for a swing), ``notes`` (how it was made, in words),
        and for a drawn law ``loaded``, ``balance`` (its check) and ``correction`` (when fixed).

    Raises
    ------
    CamcadError
        A scene without [law], or a [law] section that cannot be built (naming the key).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [machine]
    ... rpm = [300.0, 400.0]
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... ''')
    >>> scene = camcad.read_scene(folder / "cam.toml")
    >>> from camcad.scene import mechanism_law
    >>> built = mechanism_law(scene, scene.mechanisms[0])
    >>> [p.kind for p in built.law.phases]
    ['rise', 'dwell', 'return', 'dwell']
    >>> import math
    >>> from camcad.law import Phase
    >>> edges = [math.radians(d) for d in (0, 120, 180, 270, 360)]
    >>> phases = [Phase(k, a, b) for k, a, b in zip(["rise", "dwell", "return", "dwell"], edges, edges[1:])]
    >>> retimed = mechanism_law(scene, scene.mechanisms[0], tuple(phases))
    >>> round(math.degrees(retimed.law.phases[0].end), 9)
    120.0
    """
    if phases is None and mech.name in scene.built_laws:
        return scene.built_laws[mech.name]
    if not mech.has("law"):
        raise CamcadError("missing [law] section", mech.where(scene.path, "law")[:-len("law]")] + "]",
                          "add [law] with standard, phases and lift (or file)")
    spec = parse_law(mech.sections["law"], mech.where(scene.path, "law"), scene.base_dir)
    built = build_law(spec, mech.sections.get("follower"), mech.where(scene.path, "follower"))
    if phases is None:
        scene.built_laws[mech.name] = built
        return built
    return replace(built, law=retime(built.law, tuple(phases), mech.where(scene.path, "law")))


def law_unit(scene, mech, override: str | None, law=None) -> tuple[str, str]:
    """(unit of the law's displacement, how it was decided) for a scene's mechanism.

    Order: ``override`` (--unit); with ``law_of = "output"`` the [linkage]'s output_unit (deg by default);
    [dynamics] output_unit; an oscillating [follower]: rad, or deg when its
    ``swing`` (deg) equals the law's stroke (within 1e-6) — the [law] lift is then in deg of swing; else mm.
    """
    if override is not None:
        return override, "--unit"
    if mech is None:
        return "mm", "a law file: mm unless --unit says otherwise"
    law_table, linkage = mech.sections.get("law"), mech.sections.get("linkage")
    if isinstance(law_table, dict) and law_table.get("law_of") == "output" and isinstance(linkage, dict):
        unit = linkage.get("output_unit") or ("mm" if linkage.get("type") == "ratio" else "deg")
        return str(unit), f"[{mech.prefix}linkage] output_unit: the [law] is the working member's"
    dynamics = mech.sections.get("dynamics")
    if isinstance(dynamics, dict) and dynamics.get("output_unit") in ("mm", "rad"):
        return dynamics["output_unit"], f"[{mech.prefix}dynamics] output_unit"
    follower = mech.sections.get("follower")
    if isinstance(follower, dict) and follower.get("type") == "oscillating":
        swing = follower.get("swing")
        if law is not None and isinstance(swing, (int, float)) and not isinstance(swing, bool):
            stroke = float(np.ptp(law.kinematics(np.linspace(0.0, law.cycle, 4097)).s))
            if abs(stroke - float(swing)) <= 1e-6 * float(swing):
                return "deg", f"[{mech.prefix}follower] oscillating, stroke = swing in deg"
        return "rad", f"[{mech.prefix}follower] oscillating: the law is its swing in rad"
    return "mm", "translating follower"


def pipeline_angles(scene, mech, law) -> PhaseAngles:
    """The phase angles of ``law`` in the scene pipeline: the cyclogram's when the scene has a [cyclogram]
    and ``law``'s phases differ from the mechanism's [law] (the pipeline's retimed pass), else the law's own."""
    if scene.cyclogram is not None and mech.prefix:
        own = PhaseAngles.of_law(mechanism_law(scene, mech).law)
        mine = PhaseAngles.of_law(law)
        if len(own.phases_deg) != len(mine.phases_deg) or any(
                abs(a[0] - b[0]) > 1e-9 or abs(a[1] - b[1]) > 1e-9 or a[2] != b[2]
                for a, b in zip(own.phases_deg, mine.phases_deg)):
            return PhaseAngles("cyclogram", mine.phases_deg, "retimed by the cyclogram")
    return PhaseAngles.of_law(law)


def phases_deg(law) -> list[tuple[float, float, str]]:
    """(start_deg, end_deg, kind) of each phase of a law."""
    return [(math.degrees(p.start), math.degrees(p.end), p.kind) for p in law.phases]


def law_with_phases(law, phases: list[tuple[float, float, str]], where: str):
    """The law retimed to the given (start_deg, end_deg, kind) phases (shape and lift kept)."""
    return retime(law, tuple(Phase(kind, math.radians(start), math.radians(end)) for start, end, kind in phases),
                  where)
