"""Screenshots of `camcad edit` for docs/edit.md: the desktop window (TkAgg, under a display such as
Xvfb) and the browser page (WebAgg in Debian's headless Chromium through Playwright).

Run from the repository root:
    Xvfb :99 -screen 0 1600x1100x24 &
    DISPLAY=:99 python docs/make_edit_screenshots.py            # both
    DISPLAY=:99 python docs/make_edit_screenshots.py desktop    # only the window
The desktop shot needs ImageMagick's `import`; the browser shot needs playwright and chromium.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
OUT = ROOT / "docs" / "img"
SAMPLE = ROOT / "samples" / "dxf" / "fig2_rise_area_too_large.dxf"


def _events(view, canvas):
    """The story of the screenshot: a lobe dragged down, a range selected, min-change previewed."""
    from matplotlib.backend_bases import KeyEvent, MouseEvent

    def key(name):
        canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, name, 5, 5))

    def mouse(name, x, y, **kw):
        canvas.callbacks.process(name, MouseEvent(name, canvas, x, y, **kw))

    key("l")
    peak = int(np.argmax(view.session.law.a))
    x, y = view.display_xy(peak)
    mouse("button_press_event", x, y, button=1)
    for k in range(1, 9):
        mouse("motion_notify_event", x, y - 4 * k, buttons={1})
    mouse("button_release_event", x, y - 32, button=1)
    a = view.ax_a.transData.transform
    x0, y0 = a((70.0, -9.0))
    x1, _ = a((355.0, -9.0))
    mouse("button_press_event", x0, y0, button=1)
    for t in np.linspace(0, 1, 6)[1:]:
        mouse("motion_notify_event", x0 + t * (x1 - x0), y0, buttons={1})
    mouse("button_release_event", x1, y0, button=1)
    key("1")


def desktop(path: Path) -> None:
    import matplotlib

    matplotlib.use("TkAgg", force=True)
    import matplotlib.pyplot as plt

    from camcad.edit.session import EditSession
    from camcad.edit.view import FIGSIZE, EditorView

    with tempfile.TemporaryDirectory() as tmp:
        source = Path(tmp) / SAMPLE.name
        shutil.copy(SAMPLE, source)
        session = EditSession.from_file(source)
        figure = plt.figure(figsize=FIGSIZE, dpi=100)
        figure.canvas.manager.set_window_title(f"camcad edit — {SAMPLE.name}")
        view = EditorView(session, figure, blit=True, title=f"samples/dxf/{SAMPLE.name}")
        plt.show(block=False)
        for _ in range(20):
            figure.canvas.flush_events()
            time.sleep(0.05)
        _events(view, figure.canvas)
        figure.canvas.draw()
        view.canvas.toolbar.set_message(view.status_line())
        for _ in range(30):
            figure.canvas.flush_events()
            time.sleep(0.05)
        window = figure.canvas.get_tk_widget().winfo_toplevel().winfo_id()
        subprocess.run(["import", "-window", hex(window), "-frame", str(path)], check=True)
        plt.close(figure)
    print(f"written {path}")


def browser(path: Path) -> None:
    from playwright.sync_api import sync_playwright

    from camcad.edit.session import EditSession
    from camcad.edit.web import EditorServer

    executable = shutil.which("chromium-headless-shell") or shutil.which("chromium")
    args = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"]
    with tempfile.TemporaryDirectory() as tmp:
        source = Path(tmp) / SAMPLE.name
        shutil.copy(SAMPLE, source)
        session = EditSession.from_file(source)
        server = EditorServer(session, port=0, title=f"samples/dxf/{SAMPLE.name}").start_in_thread()
        try:
            with sync_playwright() as p:
                chrome = p.chromium.launch(executable_path=executable, args=args)
                page = chrome.new_page(viewport={"width": 1540, "height": 1110})
                page.goto(server.url)
                page.wait_for_function("Number(document.body.dataset.camcadRevision) >= 1", timeout=20000)
                page.evaluate("window.camcadFigure.canvas_div.focus()")
                box = page.locator("canvas.mpl-canvas").first.bounding_box()
                height = server.call(lambda: server.figure.bbox.height)
                page.keyboard.press("l")
                page.wait_for_timeout(1500)
                x, y = server.call(server.view.display_xy, int(np.argmax(session.law.a)))
                page.mouse.move(box["x"] + x, box["y"] + height - y)
                page.mouse.down()
                page.mouse.move(box["x"] + x, box["y"] + height - y + 32, steps=8)
                page.mouse.up()
                page.wait_for_timeout(1500)
                page.keyboard.press("c")             # compare all modes
                page.wait_for_timeout(2500)
                page.screenshot(path=str(path), full_page=True)
                chrome.close()
        finally:
            server.stop()
    print(f"written {path}")


if __name__ == "__main__":
    which = sys.argv[1:] or ["desktop", "browser"]
    OUT.mkdir(parents=True, exist_ok=True)
    if "desktop" in which:
        if not os.environ.get("DISPLAY"):
            sys.exit("the desktop screenshot needs a display (run Xvfb :99 and DISPLAY=:99)")
        desktop(OUT / "edit-desktop.png")
    if "browser" in which:
        browser(OUT / "edit-browser.png")
