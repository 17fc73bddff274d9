"""The desktop editor fits a laptop's screen (issue 32): `camcad edit` opened on a 1366 x 768 X display (Xvfb)
shows its whole window on the screen, every toolbar button, and every part of the figure inside it; shrunk by
the user, it lays itself out again. A screenshot of the screen is kept (CAMCAD_SCREENSHOTS=DIR keeps a copy).

Needs Xvfb, ImageMagick's ``import`` and Tk; skipped without them unless CAMCAD_REQUIRE_DISPLAY=1.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import SAMPLES

REQUIRED = os.environ.get("CAMCAD_REQUIRE_DISPLAY") == "1"
SCREEN = (1366, 768)

#: runs `camcad edit` in the display given by $DISPLAY; when the window is up, prints what it shows (PROBE
#: lines of JSON), takes a screenshot, shrinks the window as a user would, prints again, and closes it
PROBE = r"""
import json, subprocess, sys
import matplotlib
matplotlib.use("TkAgg", force=True)
import matplotlib.pyplot as plt

def extents(fig):
    view = fig._camcad_view
    renderer = fig.canvas.get_renderer()
    def box(artist):
        b = artist.get_window_extent(renderer)
        return [b.x0, b.y0, b.x1, b.y1]
    axes = [box(ax) for ax in (view.ax_a, view.ax_v, view.ax_s, view.ax_p)]
    texts = [box(t) for t in (view.title_text, view.status_text, view.badge, view.profile_text, view.table,
                              view.readout, view.msg_text) if t.get_text()]
    x0, y0, x1, y1 = view.help_block._rect
    help_box = [x0 * fig.bbox.width, y0 * fig.bbox.height, x1 * fig.bbox.width, y1 * fig.bbox.height]
    inner = view.help_block.last_figure
    help_texts = [list(t.get_window_extent(inner.canvas.get_renderer()).extents) for t in inner.texts]
    return {"axes": axes, "texts": texts, "help": help_box, "help_size": [inner.bbox.width, inner.bbox.height],
            "help_texts": help_texts}

def probe(fig, manager, window, tag):
    window.update_idletasks()
    fig.canvas.draw()
    widget = fig.canvas.get_tk_widget()
    out = {"tag": tag, "screen": [window.winfo_screenwidth(), window.winfo_screenheight()],
           "window": [window.winfo_rootx(), window.winfo_rooty(), window.winfo_width(), window.winfo_height()],
           "canvas": [widget.winfo_rootx(), widget.winfo_rooty(), widget.winfo_width(), widget.winfo_height()],
           "figure": [fig.bbox.width, fig.bbox.height],
           "controls": [[w.winfo_class(), w.winfo_rootx(), w.winfo_rooty(), w.winfo_width(), w.winfo_height(),
                         bool(w.winfo_ismapped())] for w in manager.toolbar.winfo_children()
                        if w.winfo_class() in ("Button", "Checkbutton")],
           **extents(fig)}
    print("PROBE" + json.dumps(out), flush=True)

shown = plt.show
def show(*args, **kwargs):
    fig = plt.gcf()
    manager = fig.canvas.manager
    window = manager.window
    def first():
        probe(fig, manager, window, "opened")
        subprocess.run(["import", "-window", "root", sys.argv[2]], check=True)
        window.geometry("1100x600")                    # the user makes it smaller
        window.after(2500, second)
    def second():
        probe(fig, manager, window, "shrunk")
        plt.close(fig)
    window.after(4000, first)
    shown(*args, **kwargs)
plt.show = show
from camcad.cli import main
try:
    main(["edit", sys.argv[1]])
except SystemExit:
    pass
"""


def _needs(program: str) -> str:
    found = shutil.which(program)
    if found is None:
        if REQUIRED:
            pytest.fail(f"CAMCAD_REQUIRE_DISPLAY=1 but {program} is not installed")
        pytest.skip(f"{program} is not installed")
    return found


@pytest.fixture
def display():
    """An Xvfb display of a 1366 x 768 laptop screen; yields its $DISPLAY."""
    xvfb = _needs("Xvfb")
    _needs("import")
    try:
        import tkinter  # noqa: F401
    except ImportError:
        if REQUIRED:
            pytest.fail("CAMCAD_REQUIRE_DISPLAY=1 but Python has no tkinter")
        pytest.skip("Python has no tkinter")
    read, write = os.pipe()
    server = subprocess.Popen([xvfb, "-displayfd", str(write), "-screen", "0", f"{SCREEN[0]}x{SCREEN[1]}x24",
                               "-nolisten", "tcp"], pass_fds=(write,), stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as stream:
        number = stream.readline().strip()
    try:
        assert number.isdigit(), "Xvfb did not start"
        yield f":{number}"
    finally:
        server.terminate()
        server.wait(timeout=10)


def _inside(box, outer, slack: float = 0.5) -> bool:
    return (outer[0] - slack <= box[0] and box[2] <= outer[2] + slack and outer[1] - slack <= box[1]
            and box[3] <= outer[3] + slack)


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def test_the_desktop_editor_fits_a_1366_by_768_screen(display, tmp_path):
    source = tmp_path / "fig2.dxf"
    shutil.copy(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf", source)
    shot = tmp_path / "edit-1366x768.png"
    done = subprocess.run([sys.executable, "-c", PROBE, str(source), str(shot)], capture_output=True, text=True,
                          timeout=180, env={**os.environ, "DISPLAY": display})
    probes = [json.loads(line[5:]) for line in done.stdout.splitlines() if line.startswith("PROBE")]
    assert [p["tag"] for p in probes] == ["opened", "shrunk"], done.stderr[-2000:]
    opened, shrunk = probes
    assert opened["screen"] == list(SCREEN)
    x, y, width, height = opened["window"]
    # the whole window on the screen, with room left for a window manager's title bar and panel
    assert x >= 0 and y >= 0 and x + width <= SCREEN[0] and y + height <= SCREEN[1] - 60, opened["window"]
    assert width >= 1300 and height >= 600          # and it uses the screen: not a postage stamp
    for probe in probes:
        wx, wy, ww, wh = probe["window"]
        assert len(probe["controls"]) >= 7                      # home, back, forward, pan, zoom, subplots, save
        for name, cx, cy, cw, ch, mapped in probe["controls"]:
            assert mapped and wx <= cx and cx + cw <= wx + ww and wy <= cy and cy + ch <= wy + wh, (probe["tag"], name)
        fig = [0.0, 0.0, *probe["figure"]]
        assert probe["canvas"][2] == round(probe["figure"][0]) and probe["canvas"][3] == round(probe["figure"][1])
        for box in probe["axes"] + probe["texts"] + [probe["help"]]:
            assert _inside(box, fig), (probe["tag"], box)
        for text in probe["texts"]:
            assert not any(_overlap(text, ax) for ax in probe["axes"]), (probe["tag"], text)
        helpers = [0.0, 0.0, *probe["help_size"]]
        for box in probe["help_texts"]:
            assert _inside(box, helpers), (probe["tag"], box)
    assert shrunk["window"][2] == 1100 and shrunk["figure"][0] < opened["figure"][0]
    assert shot.stat().st_size > 10_000
    keep = os.environ.get("CAMCAD_SCREENSHOTS")
    if keep:
        shutil.copy(shot, Path(keep) / shot.name)
