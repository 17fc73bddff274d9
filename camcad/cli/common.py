"""What every command shares: error handling, JSON output, common options."""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path
from typing import Annotated, Any, Callable, Optional

import typer

from ..errors import CamcadError

# Typer annotations for the options that mean the same everywhere (SPEC.md).
JSON_OPTION = typer.Option(False, "--json", help="Print one JSON object on stdout, nothing else.")
NO_PLOTS_OPTION = typer.Option(False, "--no-plots", help="Do not write PNG plots.")


def run_app(app: typer.Typer, argv: list[str]) -> int:
    """Run ``app`` on ``argv``; return the exit code. Bad input → one line on stderr and 2."""
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
        print(f"camcad: error: {err.message()}", file=sys.stderr)
        return 2
    except typer.Abort:
        print("camcad: error: aborted", file=sys.stderr)
        return 2
    except typer.TyperException as err:  # usage errors from the argument parser
        if debug:
            raise
        print(f"camcad: error: {' '.join(err.format_message().split())}; see camcad --help",
              file=sys.stderr)
        return getattr(err, "exit_code", 2) or 2
    except KeyboardInterrupt:
        print("camcad: error: interrupted", file=sys.stderr)
        return 2
    except MemoryError:
        print("camcad: error: out of memory; use a coarser tolerance or a smaller input",
              file=sys.stderr)
        return 2
    except Exception as err:  # noqa: BLE001 - a user never sees a traceback without --debug
        if debug:
            raise
        print(f"camcad: error: internal error ({type(err).__name__}: {' '.join(str(err).split())}); "
              "rerun with --debug and report it", file=sys.stderr)
        return 2
    return result if isinstance(result, int) else 0


def to_jsonable(value: Any) -> Any:
    """numpy scalars and arrays, paths and tuples → plain JSON types; NaN/inf → null."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "tolist"):  # numpy array or scalar
        return to_jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def print_json(payload: dict) -> None:
    print(json.dumps(to_jsonable(payload), indent=2))


def emit(payload: dict, as_json: bool, render: Callable[[dict], None]) -> None:
    """Print ``payload`` as JSON, or hand it to ``render`` for the human-readable form."""
    if as_json:
        print_json(payload)
    else:
        render(payload)


# --- the law-choosing options (SPEC.md: the same meaning in every command) --------------------

LawArg = Annotated[Path, typer.Argument(help="Acceleration law: a DXF drawing or a .csv/.txt table (θ deg, a).",
                                        show_default=False)]
LayerOpt = Annotated[Optional[str], typer.Option("--layer", help="Layer holding the law's curve.")]
HandleOpt = Annotated[Optional[str], typer.Option("--handle", help="Handle of the law's curve.")]
CycleOpt = Annotated[float, typer.Option("--cycle", help="Working angle the curve spans (deg).")]
LiftOpt = Annotated[Optional[float], typer.Option("--lift", help="Scale the law so the rise is this (mm).")]
PhasesOpt = Annotated[Optional[str], typer.Option(
    "--phases", help='Override detected phases: "0:90:rise,90:180:dwell,180:270:return,270:360:dwell" (deg).')]
XDegOpt = Annotated[bool, typer.Option("--x-deg", help="The drawing's x is already the cam angle in deg.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print one JSON object on stdout, nothing else.")]


def load_law_from_options(path: Path, layer: str | None, handle: str | None, cycle: float, lift: float | None,
                          phases: str | None, x_deg: bool = False):
    """Read the law as the common options say (see camcad.law.source.load_law)."""
    from ..law.source import load_law

    return load_law(path, layer=layer, handle=handle, cycle_deg=cycle, lift=lift, phases=phases, x_deg=x_deg)


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
    return Console(stderr=stderr, highlight=False, width=width)
