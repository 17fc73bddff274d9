"""What an analysis command writes and prints: one run of one library function, its outputs, its JSON.

Every analysis command (``spectrum``, ``dynamics``, ``impact``, ``contact``, ``cyclogram``) is
``<name>_command(...) -> CommandRun``: resolve the source, open the ``OutputFolder`` (the command's inputs can
never be replaced), run the scene-layer function that returns the ``AnalysisReport``, write the files and
``<name>.json``. The CLI prints ``run.text()`` or ``run.payload`` and exits with ``run.exit_code``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from camcad.io.jsonout import write_json
from camcad.io.output_folder import OutputFolder, safe_name
from camcad.report.figure import save_figure


def default_folder(name: str) -> Path:
    """./camcad-out/<name made safe>/ (docs/INTERFACE.md)."""
    return Path("camcad-out") / safe_name(name)


@dataclass
class CommandRun:
    """One run of an analysis command: the report, the files written (the JSON last) and the payload
    (``report.to_dict()`` with ``outputs``); ``lines`` renders the text output."""

    report: Any
    outputs: list = field(default_factory=list)
    payload: dict = field(default_factory=dict)
    lines: Callable[[CommandRun], list] | None = None

    @property
    def exit_code(self) -> int:
        return self.report.exit_code

    def text(self) -> list[str]:
        return self.lines(self) if self.lines is not None else []


def open_folder(output: Path | None, name: str, inputs) -> OutputFolder:
    """The OutputFolder of a command: -o, else ./camcad-out/<name>/; checked before anything is computed."""
    return OutputFolder(output if output is not None else default_folder(name), inputs)


def write_figures(out: OutputFolder, figures, json_name: str, others=()) -> list[Path]:
    """Save ``figures`` ((name or name parts, Figure) pairs) into ``out``, after checking them, ``others``
    (names written later) and ``json_name`` as one set (``OutputFolder.plan``): nothing is written when one
    of them would replace an input or another output."""
    parts = [(name,) if isinstance(name, str) else tuple(name) for name, _ in figures]
    out.plan([*parts, *((name,) for name in others), (json_name,)])
    return [save_figure(fig, out.path(*name)) for name, (_, fig) in zip(parts, figures)]


def finish(report, out: OutputFolder, written: list[Path], json_name: str,
           lines: Callable[[CommandRun], list] | None) -> CommandRun:
    """Write ``<json_name>`` (the report with its outputs) into ``out`` and return the CommandRun."""
    json_path = out.path(json_name)
    outputs = [*written, json_path]
    payload = {**report.to_dict(), "outputs": [str(p) for p in outputs]}
    write_json(json_path, payload)
    return CommandRun(report, outputs, payload, lines)
