"""Drag latency of `camcad edit`: time per drag event at 300 and 10,000 vertices.

- desktop: a real matplotlib MouseEvent through the view (the session's edit, its exact integral and
  balance check, the artists updated and blitted over the saved background, the numbers to the status
  line), on the off-screen Agg canvas and, when a display is available (DISPLAY set), in the TkAgg
  window itself including Tk painting the frame.
- browser (server): a WebAgg mouse message as the websocket delivers it, to the numbers leaving the
  server (the ``camcad`` message the page shows during the drag; the figure is redrawn on release).
- browser (end to end): Playwright moves the mouse in Debian's headless Chromium and waits for the page's
  numbers to change (skipped without Chromium and Playwright).

Run: python benchmarks/bench_edit.py [--quick]   (quick: 15 events, the smaller law only)
"""

from __future__ import annotations

import os
import shutil
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from camcad.edit.session import EditSession, loaded_from_law
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.phases import detect_phases
from camcad.law.standard import compose

SIZES = (300, 10_000)


def drawn_law(vertices: int) -> PiecewiseLinearLaw:
    """A cycloidal dwell-rise-dwell-return law (25 mm) drawn with ``vertices`` vertices, its rise 4 % high."""
    law = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0)
    theta = np.linspace(0.0, 2 * np.pi, vertices)
    a = law.kinematics(theta).a
    a = np.where((theta > np.radians(60)) & (theta < np.radians(120)), 1.04 * a, a)
    return PiecewiseLinearLaw(theta, a, 2 * np.pi, detect_phases(theta, a, 2 * np.pi))


def _session(vertices: int) -> EditSession:
    return EditSession(loaded_from_law(drawn_law(vertices), f"drawn law, {vertices} vertices"))


def agg_figure():
    """The desktop view's figure on an off-screen Agg canvas (what the window draws into)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from camcad.edit.view import new_figure

    figure = new_figure()
    FigureCanvasAgg(figure)
    return figure, lambda: None


def tk_figure():
    """The desktop window itself (TkAgg), when a display is available; else None."""
    if not os.environ.get("DISPLAY"):
        return None
    try:
        import matplotlib

        matplotlib.use("TkAgg", force=True)
        import matplotlib.pyplot as plt

        from camcad.edit.view import FIGSIZE

        figure = plt.figure(figsize=FIGSIZE, dpi=100)
    except Exception:  # noqa: BLE001 - no usable Tk: not measured
        return None
    plt.show(block=False)
    figure.canvas.flush_events()
    return figure, figure.canvas.flush_events


def desktop_drag(vertices: int, mode: str, events: int, make_figure=agg_figure) -> float | None:
    """Median seconds per motion event of a drag on the desktop view (blitting); with the Tk window, the
    time includes handing the frame to Tk and letting it paint (flush_events)."""
    from matplotlib.backend_bases import KeyEvent, MouseEvent

    from camcad.edit.view import EditorView

    made = make_figure()
    if made is None:
        return None
    figure, flush = made
    canvas = figure.canvas
    session = _session(vertices)
    view = EditorView(session, figure, blit=True)
    canvas.draw()
    flush()
    canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, mode, 5, 5))
    canvas.draw()
    flush()
    peak = int(np.argmax(session.law.a))
    x, y = view.display_xy(peak)
    canvas.callbacks.process("button_press_event", MouseEvent("button_press_event", canvas, x, y, 1))
    times = []
    for k in range(events):
        event = MouseEvent("motion_notify_event", canvas, x, y - 1 - (k % 40), buttons={1})
        start = time.perf_counter()
        canvas.callbacks.process("motion_notify_event", event)
        flush()
        times.append(time.perf_counter() - start)
    canvas.callbacks.process("button_release_event", MouseEvent("button_release_event", canvas, x, y - 20, 1))
    assert session.applied == 1
    if make_figure is not agg_figure:
        import matplotlib.pyplot as plt

        plt.close(figure)
    return statistics.median(times)


def web_server_drag(vertices: int, mode: str, events: int) -> float:
    """Median seconds from a WebAgg mouse message to the numbers leaving the server."""
    from camcad.edit.web import EditorServer

    session = _session(vertices)
    server = EditorServer(session, port=0)
    sent: list[float] = []

    class Socket:  # what the websocket handler does with the server's messages, timed
        supports_binary = True

        def send_json(self, content):
            if content.get("type") == "camcad":
                sent.append(time.perf_counter())

        def send_binary(self, blob):
            pass

    manager = server.manager
    manager.add_web_socket(Socket())
    height = server.figure.bbox.height
    manager.handle_json({"type": "key_press", "key": f"k{mode}"})
    peak = int(np.argmax(session.law.a))
    x, y = server.view.display_xy(peak)

    def mouse(kind, dy, buttons):
        manager.handle_json({"type": kind, "x": x, "y": height - y + dy, "button": 0, "buttons": buttons,
                             "modifiers": [], "guiEvent": {}})

    mouse("button_press", 0, 1)
    times = []
    for k in range(events):
        sent.clear()
        start = time.perf_counter()
        mouse("motion_notify", 1 + (k % 40), 1)
        times.append(sent[-1] - start)
    mouse("button_release", 20, 0)
    for sock in server.sockets:
        sock.close()
    assert session.applied == 1
    return statistics.median(times)


def chromium() -> str | None:
    for candidate in (os.environ.get("CAMCAD_CHROMIUM"), shutil.which("chromium-headless-shell"),
                      shutil.which("chromium")):
        if candidate:
            return candidate
    return None


def browser_drag(vertices: int, events: int) -> float | None:
    """Median seconds from Playwright's mouse move in Chromium to the page showing the new numbers."""
    executable = chromium()
    try:
        from playwright.sync_api import sync_playwright

        from camcad.edit.web import EditorServer
    except ImportError:
        return None
    if executable is None:
        return None
    session = _session(vertices)
    server = EditorServer(session, port=0).start_in_thread()
    args = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"]
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=executable, args=args)
            page = browser.new_page(viewport={"width": 1560, "height": 1130})
            page.goto(server.url)
            page.wait_for_function("Number(document.body.dataset.camcadRevision) >= 1", timeout=20000)
            page.evaluate("window.camcadFigure.canvas_div.focus()")
            page.keyboard.press("l")
            page.wait_for_function("window.camcadLast.readout.includes('drag: lobe')", timeout=20000)
            page.wait_for_timeout(1500)  # let the redraw after the key settle
            box = page.locator("canvas.mpl-canvas").first.bounding_box()
            height = server.call(lambda: server.figure.bbox.height)
            x, y = server.call(server.view.display_xy, int(np.argmax(session.law.a)))
            px, py = box["x"] + x, box["y"] + height - y
            page.mouse.move(px, py)
            page.mouse.down()
            times = []
            for k in range(events):
                revision = int(page.evaluate("document.body.dataset.camcadRevision"))
                start = time.perf_counter()
                page.mouse.move(px, py + 1 + (k % 40))
                page.wait_for_function(f"Number(document.body.dataset.camcadRevision) > {revision}", timeout=20000,
                                       polling=1)
                times.append(time.perf_counter() - start)
            page.mouse.up()
            browser.close()
    finally:
        server.stop()
    return statistics.median(times)


def run(quick: bool = False) -> list[dict]:
    events = 15 if quick else 60
    sizes = SIZES[:1] if quick else SIZES
    rows = []
    for method, make in (("desktop (Agg canvas, blit)", agg_figure), ("desktop (TkAgg window, blit)", tk_figure)):
        for n in sizes:
            for mode, name in (("v", "vertex"), ("l", "lobe")):
                latency = desktop_drag(n, mode, events, make)
                if latency is not None:
                    rows.append({"kernel": "edit: drag event", "method": method,
                                 "setting": f"{name} drag, {n} vertices", "time_s": latency,
                                 "error": None, "error_unit": "-"})
    for n in sizes:
        rows.append({"kernel": "edit: drag event", "method": "browser (server: mouse message -> numbers)",
                     "setting": f"lobe drag, {n} vertices", "time_s": web_server_drag(n, "l", events),
                     "error": None, "error_unit": "-"})
    for n in sizes:
        latency = browser_drag(n, max(5, events // 3))
        if latency is not None:
            rows.append({"kernel": "edit: drag event", "method": "browser (Chromium: mouse -> numbers on page)",
                         "setting": f"lobe drag, {n} vertices", "time_s": latency, "error": None, "error_unit": "-"})
    return rows


def main() -> None:
    quick = "--quick" in sys.argv
    for row in run(quick):
        print(f"{row['method']:48s} {row['setting']:28s} {row['time_s'] * 1e3:8.2f} ms")


if __name__ == "__main__":
    main()
