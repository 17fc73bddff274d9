"""The ``[law]`` section of a scene: a standard law, or a drawn law from a DXF or table file.

Keys (angles deg, lengths mm):
    standard         shape of the rises (cycloidal, harmonic, poly345, ...), with ``phases`` and ``lift``
    return_standard  shape of the returns (default: the same as ``standard``)
    phases           "0:90:dwell,90:180:rise,..." — required for a standard law; overrides detection for a file
    lift             rise in mm (deg of swing for an oscillating follower); scales a drawn law when given
    file             a DXF drawing or a .csv/.txt table, relative to the scene file
    layer, handle, cycle, x_deg   choose and map the drawn curve (as the CLI options)
    y0, x0           the drawing's zero axis (y of zero acceleration) and the x of the cycle's start,
                     overriding what camcad finds (as --y0, --x0)
    fix              balance a drawn law first with this mode (min-change, ...); "none" only checks it
    tol              balance tolerance (fraction of the rise)
    law_of           "follower" (default), or "output": the law is the working member's after the [linkage],
                     and the cam is designed for psi = Pi^-1(y) (camcad.scene.linkage)
    smoothing_error  a motion table's measurement error (its unit): the quintic spline's smoothing; absent:
                     generalised cross-validation (camcad.law.motion_table)
    accel_smoothing  "gcv" (default) or "none": the cubic re-smoothing of a motion table's second derivative;
    accel_smoothing_error  its stated error instead (unit per rad^2)
A table of radius-vectors (``theta_deg,r_mm``) becomes a motion through the scene's [follower].
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

from camcad.errors import CamcadError, excerpt
from camcad.law.motion_table import ProfileFollower
from camcad.scene.fields import Field, read_table
from camcad.scene.follower import FOLLOWER_FIELDS


def _shape_names() -> tuple[str, ...]:
    from camcad.law.standard import SHAPES

    return tuple(sorted(SHAPES))


def law_fields() -> list[Field]:
    from camcad.balance.conditions import DEFAULT_TOL, MODES

    shapes = _shape_names()
    return [
        Field("standard", "str", help=f"(a standard shape: {', '.join(shapes)}, or scca:b:c:d)"),
        Field("return_standard", "str", help="(the returns' shape; default: standard)"),
        Field("phases", "str", help='"0:90:dwell,90:180:rise,180:270:dwell,270:360:return" (deg)'),
        Field("lift", "float", "mm, or deg of swing", positive=True),
        Field("file", "str", help="(a DXF drawing or a .csv table of the acceleration)"),
        Field("layer", "str"),
        Field("handle", "str"),
        Field("y0", "float", "drawing units", help="(drawing y of zero acceleration; found when absent)"),
        Field("x0", "float", "drawing units", help="(drawing x of the cycle's start; the curve's start when absent)"),
        Field("cycle", "float", "deg", default=360.0, positive=True, maximum=360.0),
        Field("x_deg", "bool", default=False),
        Field("fix", "str", choices=MODES + ("none",), default="none"),
        Field("tol", "float", default=DEFAULT_TOL, positive=True),
        Field("law_of", "str", choices=("follower", "output"), default="follower",
              help="(what the law describes: the follower, or the working member after the [linkage])"),
        Field("smoothing_error", "float", "the table's unit", positive=True,
              help="(a motion table's measurement error; absent: smoothing by generalised cross-validation)"),
        Field("accel_smoothing", "str", choices=("gcv", "none"), default="gcv",
              help="(a motion table's second derivative smoothed again by a cubic spline, or not)"),
        Field("accel_smoothing_error", "float", "the table's unit per rad^2", positive=True,
              help="(the stated error of the second derivative, instead of gcv)"),
    ]


@dataclass(frozen=True)
class LawSpec:
    """What the ``[law]`` section asks for (validated)."""

    where: str
    standard: str | None = None
    return_standard: str | None = None
    phases: str | None = None
    lift: float | None = None
    file: Path | None = None
    layer: str | None = None
    handle: str | None = None
    y0: float | None = None
    x0: float | None = None
    cycle: float = 360.0
    cycle_stated: bool = True
    x_deg: bool = False
    fix: str = "none"
    tol: float = 1e-5
    law_of: str = "follower"
    smoothing_error: float | None = None
    accel_smoothing: str | float = "gcv"


@dataclass(frozen=True)
class BuiltLaw:
    """The law a scene runs with, and how it came to be."""

    law: object
    notes: tuple[str, ...] = ()
    loaded: object | None = None          # LoadedLaw for a drawn law
    balance: dict | None = None           # check of the drawn law (before any fix)
    correction: object | None = None      # balance.Correction when fixed
    extra: dict = field(default_factory=dict)


def parse_law(table: dict, where: str, base_dir: Path) -> LawSpec:
    values = read_table(table, law_fields(), where)
    if values["standard"] is None and values["file"] is None:
        raise CamcadError("the law has no source", where,
                          'add standard = "cycloidal" (with phases and lift) or file = "accel.dxf"')
    if values["standard"] is not None and values["file"] is not None:
        raise CamcadError("the law has both 'standard' and 'file'", where, "keep one of them")
    for key in ("standard", "return_standard"):
        if values[key] is not None:
            from camcad.law.standard import shape_named

            try:
                shape_named(values[key])
            except KeyError as err:
                raise CamcadError(str(err.args[0]), f"{where} {key}", "pick one of the names listed") from None
    if values["standard"] is not None:
        for key in ("phases", "lift"):
            if values[key] is None:
                raise CamcadError(f"missing value '{key}' for a standard law", where,
                                  'add phases = "0:90:dwell,90:180:rise,180:270:dwell,270:360:return" and lift = 25.0'
                                  if key == "phases" else "add lift = 25.0 (mm)")
    file = None
    if values["file"] is not None:
        if "\x00" in values["file"] or not values["file"].strip():
            raise CamcadError(f"law file name {excerpt(values['file'])} is not a file name", where,
                              'write file = "accel.dxf" (relative to the scene file)')
        file = _as_shown((base_dir / values["file"]).resolve())
        if not file.exists():
            raise CamcadError(f"law file {excerpt(values['file'])} not found", where,
                              "give the path relative to the scene file")
    return LawSpec(where=where, standard=values["standard"], return_standard=values["return_standard"],
                   phases=values["phases"], lift=values["lift"], file=file, layer=values["layer"],
                   handle=values["handle"], y0=values["y0"], x0=values["x0"], cycle=values["cycle"],
                   cycle_stated="cycle" in table, x_deg=values["x_deg"], fix=values["fix"], tol=values["tol"],
                   law_of=values["law_of"], smoothing_error=values["smoothing_error"],
                   accel_smoothing=(values["accel_smoothing_error"] if values["accel_smoothing_error"] is not None
                                    else values["accel_smoothing"]))


def _as_shown(path: Path) -> Path:
    """``path`` relative to the working folder when it lies inside it (what the user typed, in messages
    and reports), else absolute."""
    try:
        return path.relative_to(Path.cwd())
    except ValueError:
        return path


def profile_follower(table, where: str):
    """The follower of a scene's [follower] table as a radius-vector table needs it (kind, roller, offset,
    pivot, arm, turn), or None without a table."""
    if not isinstance(table, dict):
        return None
    values = read_table(table, FOLLOWER_FIELDS, where)
    kind = "oscillating" if values["type"] == "oscillating" else "translating"
    if values["type"] == "flat":
        raise CamcadError("a radius-vector table needs a roller follower (a flat face touches the profile "
                          "elsewhere)", where, "give type = \"roller\", \"knife\" or \"oscillating\"")
    return ProfileFollower(kind, float(values["roller_radius"] or 0.0), float(values["offset"]), values["pivot"],
                           values["arm"], bool(values["cw"]))


def build_law(spec: LawSpec, follower_table=None, follower_where: str = "[follower]") -> BuiltLaw:
    """The law of a scene: composed from standard shapes, or read (and balanced when asked) from a file; a
    radius-vector table through the scene's [follower] (``follower_table``)."""
    from camcad.law.phases import parse_phases
    from camcad.law.standard import compose

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
    from camcad.balance.checking import check
    from camcad.balance.correction import correct
    from camcad.law.source import load_law

    loaded = load_law(cast(Path, spec.file), layer=spec.layer, handle=spec.handle,
                      cycle_deg=spec.cycle if spec.cycle_stated else None, lift=spec.lift,
                      phases=spec.phases, x_deg=spec.x_deg, y0=spec.y0, x0=spec.x0,
                      follower=profile_follower(follower_table, follower_where), smoothing=spec.smoothing_error,
                      accel_smoothing=spec.accel_smoothing)
    report = check(loaded.law, spec.tol)
    notes = [loaded.source, *loaded.notes]
    if spec.fix == "none":
        if not report.balanced:
            notes.append("the drawn law is NOT balanced (fix = \"min-change\" in [law] corrects it)")
        return BuiltLaw(loaded.law, tuple(notes), loaded, report.to_dict())
    result = correct(loaded.law, spec.fix, tol=spec.tol, where=str(spec.file))
    notes.append(f"balanced with mode {spec.fix}: RMS change {result.rms_change / loaded.y_scale:.4g}, "
                 f"max change {result.max_change / loaded.y_scale:.4g} (input y units)")
    return BuiltLaw(result.law, tuple(notes), loaded, report.to_dict(), result)
