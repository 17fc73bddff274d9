"""The ``camcad`` command line: a thin typer layer over the library.

Each command lives in its own module of this package and registers itself on ``app``;
heavy libraries (numpy, scipy, ezdxf, matplotlib) are imported inside the commands so
that ``camcad --help`` starts fast.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys

import typer

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="camcad: cam mechanisms from drawn acceleration laws. Angles in deg, lengths in mm, "
         "speeds in rpm. Exit codes: 0 ok, 1 a check failed, 2 bad input.",
)

_NOT_COMMANDS = {"common"}


def _register_commands() -> None:
    for module in pkgutil.iter_modules(__path__):
        if module.name not in _NOT_COMMANDS and not module.name.startswith("_"):
            importlib.import_module(f"{__name__}.{module.name}")


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the app, turn every user-facing failure into one line and exit code 2."""
    from camcad.cli.common import run_app

    _register_commands()
    sys.exit(run_app(app, sys.argv[1:] if argv is None else argv))
