"""Running the editor: a script headless, a desktop window (TkAgg), or the browser (WebAgg).

``run_editor`` is what ``camcad edit`` calls: it makes the session, replays ``--script`` when given
(no window), otherwise opens the desktop window when there is a display and ``--web`` is not asked
for, else serves the editor on 127.0.0.1 and prints its URL. It returns the check keys of the final
law, the number of operations applied and the files written.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

from camcad.balance.drawn import drawn_polyline
from camcad.edit.session import (
    DEFAULT_TOL,
    EditSession,
    default_output,
    load_script,
    loaded_from_law,
    sampled_law,
)
from camcad.io.output_folder import check_outputs, confined_path, is_folder
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.segments import SegmentLaw
from camcad.law.source import LoadedLaw

if TYPE_CHECKING:
    from matplotlib.backend_bases import FigureManagerBase


@dataclass
class EditOutcome:
    """What an editing run did: ``payload`` (SPEC check keys of the final law, ``operations``,
    ``outputs``, ``max_change``/``rms_change`` against the input in input y units) and the verdict."""

    payload: dict
    balanced: bool


def has_display() -> bool:
    """A desktop session to open a window on (Windows and macOS always; elsewhere $DISPLAY or Wayland)."""
    if sys.platform in ("win32", "darwin"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def make_session(law, *, name: str, input_path: Path | None, tol: float = DEFAULT_TOL, notes=(),
                 step_deg: float = 0.5) -> EditSession:
    """A session on a law read from a file (``LoadedLaw``) or on a closed-form law (sampled every
    ``step_deg`` into a polyline — a law designed from segments drawn as ``camcad law`` draws it, meeting its
    phases' end values; it has no drawing, so it saves as a new polyline or a table)."""
    if isinstance(law, LoadedLaw):
        return EditSession(law, tol=tol, input_path=input_path, where=str(input_path or name))
    if isinstance(law, SegmentLaw):
        # a law designed from segments states its phases' end values: drawn so that it meets them
        law = drawn_polyline(law).law
    elif not isinstance(law, PiecewiseLinearLaw):
        law = sampled_law(law, step_deg)
    loaded = loaded_from_law(law, name, notes)
    return EditSession(loaded, tol=tol, input_path=None, where=name)


def run_editor(session: EditSession, *, script: Path | None = None, output: Path | None = None, web: bool = False,
               port: int = 0, open_browser: bool = True, announce: Callable[[str], None] = print,
               inputs=()) -> EditOutcome:
    """Replay ``script`` headless, or open the editor (desktop window or browser) until it is closed.

    Parameters
    ----------
    session : the law to edit.
    script : an edit script (JSON list of operations); replayed without a window. Its save paths are
        relative to the output folder (``output_folder(session, output)``) and confined to it; every
        output of the run (each save and ``output``) is checked against every input (the law, the script,
        ``inputs``) and against the others before the first operation runs.
    output : with a script, the final law is also saved here (default ``<input>.edited.dxf`` when the
        script saves nothing); an existing folder: the final law is saved in it under its default name.
        In the window, where ``s`` saves.
    web : serve the editor in a browser even when there is a display.
    port : the browser editor's port (0: a free one); the server binds 127.0.0.1 only.
    open_browser : open the URL in the system's browser.
    announce : where the URL and notes are printed.
    inputs : further files the session was read from (a scene and its law files), as paths or
        (path, role): never replaced.
    """
    session.inputs = [*session.inputs, *((Path(p), "an input") if not isinstance(p, tuple) else p for p in inputs)]
    if output is not None and is_folder(output):
        output = Path(output) / default_output(session).name
    if script is not None:
        ops = load_script(script)
        session.base_dir = output_folder(session, output)
        final = output if output is not None else (
            None if any(op["op"] == "save" for op in ops) else default_output(session))
        saves = [(confined_path(op["path"], session.base_dir, f"{script}, operation {i} (save)", "save path"),
                  f"operation {i} (save)") for i, op in enumerate(ops) if op["op"] == "save"]
        final_item = [(final, "-o" if output is not None else "the edited law")] if final is not None else []
        check_outputs(saves + final_item, [*session.inputs, (Path(script), "the script")], str(script))
        session.inputs.append((Path(script), "the script"))
        session.replay(ops, where=str(script))
        if final is not None:
            session.save(final, record=False)
    elif web or not has_display():
        if not web:
            announce("camcad edit: no display here, so the editor runs in a browser")
        _serve(session, output, port, open_browser, announce)
    else:
        try:
            _desktop(session, output)
        except _NoDesktop as why:
            announce(f"camcad edit: no desktop window ({why}); the editor runs in a browser")
            _serve(session, output, port, open_browser, announce)
    return summary(session)


def output_folder(session: EditSession, output: Path | None) -> Path:
    """The folder an edit script's saves go into: ``output``'s folder, else the folder of the default output
    (the input's folder, or the current one for a law without a file)."""
    target = Path(output) if output is not None else default_output(session)
    return target.parent


def summary(session: EditSession) -> EditOutcome:
    report = session.report
    max_change, rms_change = session.changes()
    payload = {"source": session.loaded.source, "notes": list(session.loaded.notes), **report.to_dict(),
               "operations": session.applied, "outputs": [str(p) for p in session.outputs],
               "max_change": max_change, "rms_change": rms_change, "vertices": len(session.law.x)}
    return EditOutcome(payload, report.balanced)


class _NoDesktop(Exception):
    pass


def _desktop(session: EditSession, output: Path | None) -> None:
    """The editor in a TkAgg window; returns when the window is closed."""
    try:
        import tkinter  # noqa: F401

        import matplotlib

        matplotlib.use("TkAgg", force=True)
        import matplotlib.pyplot as plt
    except Exception as err:  # noqa: BLE001 - any failure to get Tk means: use the browser
        raise _NoDesktop(f"{type(err).__name__}: {err}") from None
    from camcad.edit.view import FIGSIZE, EditorView

    try:
        figure = plt.figure(figsize=FIGSIZE, dpi=100)
    except Exception as err:  # noqa: BLE001 - e.g. TclError: no display name
        raise _NoDesktop(f"{type(err).__name__}: {err}") from None
    manager = cast("FigureManagerBase", figure.canvas.manager)  # a pyplot figure has a manager
    window = getattr(manager, "window", None)
    if window is not None:
        _fit_screen(figure, manager, window)
    title = f"camcad edit — {session.where}"
    manager.set_window_title(title)
    view = EditorView(session, figure, blit=True, output=output)
    figure._camcad_view = view  # type: ignore[attr-defined]  # keep the view alive as long as the window
    plt.show(block=True)
    plt.close(figure)


def _fit_screen(figure, manager, window) -> None:
    """Open the window at a size that fits the screen (``camcad.edit.view.window_size``: a 1366 x 768 laptop
    too), and bring it back to that size whenever it would reach past the screen (Tk scales the figure by the
    screen's pixel ratio once the window is shown). Smaller than the screen, the window is the user's to
    resize; the view lays itself out again at every size."""
    from camcad.edit.view import window_size

    screen = (window.winfo_screenwidth(), window.winfo_screenheight())
    width, height = window_size(screen)
    toolbar = getattr(manager, "toolbar", None)

    def fit(_event=None) -> None:
        bar = toolbar.winfo_reqheight() if toolbar is not None else 0
        if figure.bbox.width > screen[0] or figure.bbox.height + bar > screen[1]:
            dpi = float(figure.dpi)               # screen px per inch, Tk's pixel ratio included
            figure.set_size_inches(width / dpi, height / dpi, forward=True)
        if toolbar is not None and toolbar.winfo_reqwidth() > width:
            toolbar.configure(width=width)        # it asks for the width the figure was made with

    fit()
    figure.canvas.mpl_connect("resize_event", fit)
    window.minsize(640, 400)


def _serve(session: EditSession, output: Path | None, port: int, open_browser: bool,
           announce: Callable[[str], None]) -> None:
    from camcad.edit.web import EditorServer

    server = EditorServer(session, port=port, output=output)
    announce(f"camcad edit: the editor is at {server.url} (served on {server.address} only; Ctrl+C stops it)")
    if open_browser:
        import webbrowser

        try:
            webbrowser.open(server.url)
        except Exception as err:  # noqa: BLE001 - no browser: the URL is printed
            announce(f"camcad edit: could not open a browser ({err}); open the URL above")
    server.run()


__all__ = ["EditOutcome", "has_display", "make_session", "output_folder", "run_editor", "summary"]
