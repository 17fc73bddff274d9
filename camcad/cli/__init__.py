"""The ``camcad`` command line: a thin typer layer over the library.

Each command lives in a module of this package and registers itself on ``app``. Commands load lazily:
``camcad --help`` and ``camcad --version`` import only typer, and ``camcad COMMAND`` imports only the
module of that command (``COMMANDS``), which in turn imports the library it needs inside the command
function — so a command's start-up costs what that command uses (tests/project/test_startup.py).
"""

from __future__ import annotations

import gc
import importlib
import importlib.util
import sys

import typer
from typer.core import TyperGroup

from camcad.version import __version__

#: command name -> (module that defines it, one-line help shown by ``camcad --help``); a test checks that
#: each line opens as the command's own help does
COMMANDS: dict[str, tuple[str, str]] = {
    "check": ("camcad.cli.check",
              "Check the area balance of an acceleration law (exit 0 balanced, 1 not, 2 bad input)."),
    "fix": ("camcad.cli.check", "Correct an unbalanced law with the smallest change and write a corrected copy."),
    "profile": ("camcad.cli.profile", "Synthesise a cam profile; write profile.dxf, law.csv, report.json and plots."),
    "law": ("camcad.cli.law",
            "Design a motion from segments or standard shapes; write law.dxf, law.csv, law.png, law.json."),
    "spectrum": ("camcad.cli.spectrum", "Harmonics of a law, the resonance band over a speed range, filtering."),
    "dynamics": ("camcad.cli.dynamics", "Elastic follower over a speed range: rigid vs elastic acceleration."),
    "impact": ("camcad.cli.dynamics", "Impact on a limit stop: force and first rebound against speed."),
    "contact": ("camcad.cli.contact", "Hertz contact stress along the profile, safety factor, phase limits."),
    "compare": ("camcad.cli.compare", "Two laws on one mechanism, side by side: A, B and A/B."),
    "synth": ("camcad.cli.synth", "Synthesise a law of a given tachogram from the harmonic database."),
    "cyclogram": ("camcad.cli.contact", "Optimise a group's cyclogram: least makespan under the phase limits."),
    "machine": ("camcad.cli.machine", "Optimise a machine of groups: least cycle or the longest limiting operation."),
    "drive": ("camcad.cli.drive", "Camshaft torque and power, flywheel and motor sizing."),
    "linkage": ("camcad.cli.linkage",
                "Linkages (Sunkuev 1984): atlas of adjustable chains, function generators, guiding mechanisms, "
                "adjustable mechanisms."),
    "edit": ("camcad.cli.edit", "Edit a drawn law by hand: drag points and lobes, watch the areas balance, save."),
    "sweep": ("camcad.cli.sweep", "Explore a design space: a scene's keys over ranges and draws, on a pool or Dask."),
    "bench": ("camcad.cli.bench", "Time and error of every kernel (median of repeats), as a table and a plot."),
}


class LazyGroup(TyperGroup):
    """A click group that imports a command's module only when that command runs (or its help is asked)."""

    def list_commands(self, ctx) -> list[str]:
        return [name for name in COMMANDS if _available(name)]

    def get_command(self, ctx, cmd_name: str):
        if cmd_name not in COMMANDS or not _available(cmd_name):
            return None
        importlib.import_module(COMMANDS[cmd_name][0])
        built = typer.main.get_group(app)
        return built.commands.get(cmd_name)

    def format_commands(self, ctx, formatter) -> None:
        rows = [(name, COMMANDS[name][1]) for name in self.list_commands(ctx)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


def _available(name: str) -> bool:
    return importlib.util.find_spec(COMMANDS[name][0]) is not None


#: plain (click) help: no rich markup, so "[cyclogram]" or "0:100:dwell" in a help text print as written,
#: and ``camcad --help`` does not import rich
app = typer.Typer(
    cls=LazyGroup,
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
    help=("camcad: cam mechanisms from drawn acceleration laws. Angles in deg, lengths in mm, speeds in rpm. "
          "Exit codes: 0 ok, 1 a check failed, 2 bad input or usage, 3 internal error (a bug: please report it). "
          "Add --debug to any command for the traceback of an internal error."),
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"camcad {__version__}")
        raise typer.Exit(0)


@app.callback()
def _options(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
    debug: bool = typer.Option(False, "--debug", help="Show the traceback of an internal error (any command)."),
) -> None:
    """camcad: cam mechanisms from drawn acceleration laws."""


def register_all() -> None:
    """Import every command module (tests and documentation that need the whole command tree)."""
    for name in COMMANDS:
        if _available(name):
            importlib.import_module(COMMANDS[name][0])


#: thresholds of Python's cyclic garbage collector in a command's process: a command allocates millions of
#: short-lived objects (matplotlib's artists above all) among the million objects its libraries hold, and
#: with Python's defaults (700, 10, 10) the collector's full passes over them took 0.25 s of the 3.8 s of CPU
#: of `camcad profile loom_group1.toml` (0.18 of 1.2 s for `camcad profile`); with these, 0.05 s. Reference
#: counting frees everything that is not a cycle at once, and a full pass still comes every 10 million
#: allocations, so a long run (a sweep, the editor's server) keeps its memory bounded.
GC_THRESHOLDS = (10_000, 50, 20)


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the app; bad input → one line and exit 2, a bug → one line and exit 3."""
    from camcad.cli.common import run_app

    gc.set_threshold(*GC_THRESHOLDS)

    sys.exit(run_app(app, sys.argv[1:] if argv is None else argv))
