"""What every command shares: error handling, JSON output, common options."""

from __future__ import annotations

import contextlib
import json
import shutil
import sys
import warnings
from pathlib import Path
from typing import Annotated

import typer

from camcad.errors import CamcadError

#: exit codes (docs/INTERFACE.md)
EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def run_app(app: typer.Typer, argv: list[str]) -> int:
    """Run ``app`` on ``argv``; return the exit code.

    Bad input (CamcadError, a usage error) → one line on stderr, exit 2. A bug (any other exception,
    MemoryError included) → one line asking for a report, exit 3; ``--debug`` anywhere on the command
    line shows its traceback instead.
    """
    debug = "--debug" in argv
    argv = [arg for arg in argv if arg != "--debug"]
    if not argv:
        argv = ["--help"]
    command = typer.main.get_command(app)
    try:
        with warnings.catch_warnings():
            # numerical warnings would break the one-line contract of stderr; results carry their notes
            warnings.simplefilter("ignore")
            result = command.main(args=argv, prog_name="camcad", standalone_mode=False)
    except CamcadError as err:
        if debug:
            raise
        print(f"camcad: error: {_one_line(err.message())}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except typer.Abort:
        print("camcad: error: aborted", file=sys.stderr)
        return EXIT_BAD_INPUT
    except typer.Exit as stop:
        return int(stop.exit_code or 0)
    except typer.TyperException as err:  # usage errors from the argument parser
        if _asks_for_help(err):   # a group given no command: its help, as written, as `camcad` alone prints it
            print(err.format_message())
            return EXIT_OK
        if debug:
            raise
        print(f"camcad: error: {_one_line(err.format_message())}; see camcad --help", file=sys.stderr)
        return getattr(err, "exit_code", EXIT_BAD_INPUT) or EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("camcad: error: interrupted", file=sys.stderr)
        return 130
    except BaseException as err:  # noqa: BLE001 - a user never sees a traceback without --debug
        if debug or isinstance(err, SystemExit):
            raise
        what = "out of memory" if isinstance(err, MemoryError) else f"{type(err).__name__}: {err}"
        print(f"camcad: internal error ({_one_line(what, 160)}) - please report it; rerun with --debug for the "
              "traceback", file=sys.stderr)
        return EXIT_INTERNAL
    return result if isinstance(result, int) else EXIT_OK


def _asks_for_help(err: Exception) -> bool:
    """A group run without a command (click's ``NoArgsIsHelpError``, e.g. ``camcad linkage``): the user asks what
    it offers; its help is printed in full, never squashed into one error line."""
    return type(err).__name__ == "NoArgsIsHelpError"


def _one_line(text: str, limit: int = 280) -> str:
    """``text`` on one line, at most ``limit`` characters (a long excerpt is cut with an ellipsis)."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


@contextlib.contextmanager
def progress_line(enabled: bool = True):
    """Progress messages on one line of stderr while a command works, when stderr is a terminal; yields
    ``say(text)``. Plain escape codes, no rich: a command's start-up pays only for what it uses."""
    stream = sys.stderr
    if not enabled or not stream.isatty():
        yield lambda _text: None
        return
    width = shutil.get_terminal_size((80, 24)).columns - 1

    def say(text: str) -> None:
        stream.write("\r\033[K" + " ".join(str(text).split())[:width])
        stream.flush()

    try:
        yield say
    finally:
        stream.write("\r\033[K")
        stream.flush()


def echo(text: str = "") -> None:
    """One line on stdout, printed as written (no markup)."""
    print(text)


def print_json(payload: dict) -> None:
    """``payload`` as indented JSON on stdout (numpy values and paths made plain)."""
    from camcad.io.jsonout import to_jsonable

    print(json.dumps(to_jsonable(payload), indent=2))


# --- the law-choosing options (docs/INTERFACE.md: the same meaning in every command) --------------------

LawArg = Annotated[Path, typer.Argument(help="Acceleration law: a DXF drawing or a .csv/.txt table (θ deg, a).",
                                        show_default=False)]
LayerOpt = Annotated[str | None, typer.Option("--layer", help="Layer holding the law's curve.")]
HandleOpt = Annotated[str | None, typer.Option("--handle", help="Handle of the law's curve.")]
Y0Opt = Annotated[float | None, typer.Option("--y0", help="Drawing y of zero acceleration (overrides the axis found).")]
X0Opt = Annotated[float | None, typer.Option(
    "--x0", help="Drawing x of the cycle's start, theta = 0 (overrides the curve's start).")]
OriginOpt = Annotated[str | None, typer.Option("--origin", help="X,Y: --x0 and --y0 at once (drawing units).")]
CycleOpt = Annotated[float, typer.Option("--cycle", help="Working angle the curve spans (deg).")]
LiftOpt = Annotated[float | None, typer.Option("--lift", help="Scale the law so the rise is this (mm).")]
PhasesOpt = Annotated[str | None, typer.Option(
    "--phases", help='Override detected phases: "0:90:rise,90:180:dwell,180:270:return,270:360:dwell" (deg).')]
XDegOpt = Annotated[bool, typer.Option("--x-deg", help="The drawing's x is already the cam angle in deg.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print one JSON object on stdout, nothing else.")]


def load_law_from_options(path: Path, layer: str | None, handle: str | None, cycle: float, lift: float | None,
                          phases: str | None, x_deg: bool = False, y0: float | None = None, x0: float | None = None,
                          origin: str | None = None, **table_options):
    """Read the law as the common options say (see camcad.law.source.load_law).

    --cycle counts as stated only when it was given on the command line (its default, 360, is an
    assumption: a curve that is not a whole cycle is then refused, not stretched); --origin X,Y
    sets --x0 and --y0 at once. ``table_options`` (follower, smoothing, accel_smoothing) go to
    ``load_law`` for motion tables.
    """
    from camcad.law.source import load_law

    if origin is not None:
        x0, y0 = parse_origin(origin, x0, y0)
    stated = cycle != 360.0 or option_given("cycle")
    return load_law(path, layer=layer, handle=handle, cycle_deg=cycle if stated else None, lift=lift,
                    phases=phases, x_deg=x_deg, y0=y0, x0=x0, **table_options)


def parse_origin(text: str, x0: float | None, y0: float | None) -> tuple[float, float]:
    """'X,Y' → (x0, y0); refused when --x0 or --y0 is given too."""
    if x0 is not None or y0 is not None:
        raise CamcadError("--origin and --x0/--y0 both given", "--origin", "give --origin X,Y or --x0/--y0")
    parts = text.replace(";", ",").split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        return float(parts[0]), float(parts[1])
    except ValueError:
        raise CamcadError(f"{text[:40]!r} is not two numbers", "--origin",
                          "write --origin X,Y, e.g. --origin 10,104.5") from None


def option_given(name: str) -> bool:
    """True when the option ``name`` of the running command was given on the command line (or
    when no command is running: a library call states what it passes)."""
    try:  # typer >= 0.16 runs its own copy of click
        from typer._click.globals import get_current_context
    except ImportError:  # pragma: no cover - older typer uses click itself
        from click import get_current_context  # type: ignore[no-redef]  # the same function of older typer

    ctx = get_current_context(silent=True)
    if ctx is None or name not in ctx.params:
        return True
    source = ctx.get_parameter_source(name)
    return source is not None and source.name not in ("DEFAULT", "DEFAULT_MAP")


def parse_pair(text: str, option: str, example: str = "A:B") -> tuple[float, float]:
    """'A:B' → (A, B) as floats, or a CamcadError naming the option."""
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        return float(parts[0]), float(parts[1])
    except ValueError:
        raise CamcadError(f"{text!r} is not two numbers", option, f"write {option} {example}") from None


def console(stderr: bool = False):
    """A rich console; 120 columns when not a terminal, so piped tables stay readable."""
    import shutil

    from rich.console import Console

    stream = sys.stderr if stderr else sys.stdout
    width = shutil.get_terminal_size((120, 24)).columns if stream.isatty() else 120
    # markup=False: user text ("0:100:dwell", "[cyclogram]") is printed as written, never interpreted
    return Console(stderr=stderr, highlight=False, width=width, markup=False, emoji=False, soft_wrap=True)


# --- a law from a file, a scene or a standard shape (the commands that analyse a law) ----------

SourceArg = Annotated[Path | None, typer.Argument(
    help="A scene (.toml), or an acceleration law (DXF or .csv/.txt table); omit it with --standard.",
    show_default=False)]
SceneArg = Annotated[Path, typer.Argument(help="Scene file (TOML): one mechanism or a group with [cyclogram].",
                                          show_default=False)]
StandardOpt = Annotated[str | None, typer.Option(
    "--standard", help="A standard law instead of a file: cycloidal, harmonic, poly345, ... (needs --phases, --lift).")]
ReturnStandardOpt = Annotated[str | None, typer.Option("--return-standard",
                                                          help="Shape of the returns (default: --standard).")]
RpmOpt = Annotated[str | None, typer.Option(
    "--rpm", help="Speed N or range N1:N2[:STEP] (rpm); overrides the scene's machine rpm.")]
OutOpt = Annotated[Path | None, typer.Option("-o", "--output", help="Output folder (default ./camcad-out/<name>/).")]
NoPlotsOpt = Annotated[bool, typer.Option("--no-plots", help="Do not write PNG plots.")]
MechanismOpt = Annotated[str | None, typer.Option("--mechanism", help="The mechanism of a group scene.")]


class LawSource:
    """What an analysis command works on: the law, a name for its outputs, where it came from, and,
    for a scene, the scene and the mechanism (whose other sections the command may use)."""

    def __init__(self, law, name: str, where: str, notes=(), scene=None, mechanism=None, loaded=None):
        self.law = law
        self.name = name
        self.where = where
        self.notes = list(notes)
        self.scene = scene
        self.mechanism = mechanism
        self.loaded = loaded


def resolve_source(source: Path | None, standard: str | None, return_standard: str | None, phases: str | None,
                   lift: float | None, layer: str | None, handle: str | None, cycle: float, x_deg: bool,
                   mechanism: str | None, y0: float | None = None, x0: float | None = None,
                   origin: str | None = None) -> LawSource:
    """The law of a scene (.toml, one mechanism picked with --mechanism), a drawn law file, or a standard shape."""
    if source is not None and standard is not None:
        raise CamcadError("both a file and --standard given", "command line", "give one law source")
    if source is not None and source.suffix.lower() == ".toml":
        from camcad.scene.file import read_scene
        from camcad.scene.laws import mechanism_law

        scene = read_scene(source)
        if mechanism is None:
            if len(scene.mechanisms) > 1:
                names = ", ".join(m.name for m in scene.mechanisms)
                raise CamcadError(f"the scene holds {len(scene.mechanisms)} mechanisms ({names})", str(source),
                                  "pick one with --mechanism")
            mech = scene.mechanisms[0]
        else:
            mech = scene.mechanism(mechanism)
        built = mechanism_law(scene, mech)
        name = mech.name if len(scene.mechanisms) > 1 or mech.prefix else scene.name
        return LawSource(built.law, name, str(source), built.notes, scene, mech, built.loaded)
    if standard is not None:
        from camcad.scene.laws import build_law
        from camcad.scene.sections.law import LawSpec

        if phases is None or lift is None:
            raise CamcadError("a standard law needs its phases and lift", "--standard",
                              'add --phases "0:90:dwell,90:180:rise,180:270:dwell,270:360:return" --lift 25')
        from camcad.law.standard import SHAPES

        for option, shape in (("--standard", standard), ("--return-standard", return_standard)):
            if shape is not None and shape not in SHAPES:
                raise CamcadError(f"unknown law {shape!r}", option, f"use one of {', '.join(sorted(SHAPES))}")
        built = build_law(LawSpec(where="--standard", standard=standard, return_standard=return_standard,
                                  phases=phases, lift=lift, cycle=cycle))
        return LawSource(built.law, standard, "--standard", built.notes)
    if source is None:
        raise CamcadError("no law given", "command line", "give a scene, a law file, or --standard NAME")
    loaded = load_law_from_options(source, layer, handle, cycle, lift, phases, x_deg, y0, x0, origin)
    return LawSource(loaded.law, source.stem, str(source), [loaded.source, *loaded.notes], loaded=loaded)


def output_dir(output: Path | None, name: str) -> Path:
    """-o when given, else ./camcad-out/<name>/."""
    return output if output is not None else Path("camcad-out") / name
