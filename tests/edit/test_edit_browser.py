"""The browser editor end to end: WebAgg served on 127.0.0.1 by camcad, driven by Playwright in Debian's
headless Chromium. Drags a lobe (numbers update during the drag), applies min-change, saves, and checks the
saved drawing with `camcad check` and against the library's correction.

Required in CI (CAMCAD_REQUIRE_BROWSER=1: a missing browser fails); skipped locally without Chromium.
Set CAMCAD_SCREENSHOTS=DIR to keep a screenshot of the page (docs/img/edit-browser.png comes from it).
"""

from __future__ import annotations

import http.client
import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import SAMPLES

from camcad.balance import correct
from camcad.edit.session import EditSession
from camcad.law.source import load_law

REQUIRED = os.environ.get("CAMCAD_REQUIRE_BROWSER") == "1"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def chromium_path() -> str | None:
    for candidate in (os.environ.get("CAMCAD_CHROMIUM"), shutil.which("chromium-headless-shell"),
                      shutil.which("chromium"), shutil.which("chromium-browser")):
        if candidate and Path(candidate).exists():
            return candidate
    return None


def _missing(why: str):
    if REQUIRED:
        pytest.fail(f"CAMCAD_REQUIRE_BROWSER=1 but {why}")
    pytest.skip(why)


@pytest.fixture
def server(tmp_path):
    pytest.importorskip("tornado") if not REQUIRED else __import__("tornado")
    from camcad.edit.web import EditorServer

    source = tmp_path / "fig2.dxf"
    shutil.copy(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf", source)
    session = EditSession.from_file(source)
    srv = EditorServer(session, port=0, output=tmp_path / "edited.dxf").start_in_thread()
    yield srv
    srv.stop()


def test_server_listens_on_loopback_only_and_checks_the_host(server):
    assert server.address == "127.0.0.1" and server.url.startswith("http://127.0.0.1:")
    assert all(sock.getsockname()[0] == "127.0.0.1" for sock in server.sockets)
    ok = http.client.HTTPConnection("127.0.0.1", server.port, timeout=5)
    ok.request("GET", "/")
    assert ok.getresponse().status == 200
    rebound = http.client.HTTPConnection("127.0.0.1", server.port, timeout=5)
    rebound.request("GET", "/", headers={"Host": f"evil.example:{server.port}"})
    assert rebound.getresponse().status == 403


def test_browser_drag_lobe_min_change_save_and_check(server, tmp_path, cli):
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _missing("the playwright package is not installed")
    executable = chromium_path()
    if executable is None:
        _missing("no Chromium found (apt-get install chromium-headless-shell or chromium)")
    session = server.session
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=executable, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1560, "height": 1130})
            page.goto(server.url)
            page.wait_for_function("Number(document.body.dataset.camcadRevision) >= 1", timeout=15000)
            assert "DOES NOT CLOSE" in page.inner_text("#camcad-verdict")
            canvas = page.locator("canvas.mpl-canvas").first
            canvas.wait_for()
            box = canvas.bounding_box()
            height = server.call(lambda: server.figure.bbox.height)
            page.evaluate("window.camcadFigure.canvas_div.focus()")  # keys go to the figure
            page.keyboard.press("l")                              # lobe drag mode
            page.wait_for_function("window.camcadLast && window.camcadLast.readout.includes('drag: lobe')")
            peak = int(np.argmax(session.law.a))
            x, y = server.call(server.view.display_xy, peak)
            px, py = box["x"] + x, box["y"] + height - y
            page.mouse.move(px, py)
            page.mouse.down()
            revision = int(page.evaluate("document.body.dataset.camcadRevision"))
            page.mouse.move(px, py + 40, steps=5)
            # numbers arrive during the drag, before the release
            page.wait_for_function(f"Number(document.body.dataset.camcadRevision) > {revision} && "
                                   "window.camcadLast.dragging", timeout=10000)
            live = page.evaluate("window.camcadLast")
            assert live["areas"]["rise_accel"] < 5.0326 and session.applied == 0
            page.mouse.up()
            page.wait_for_function("Number(document.body.dataset.camcadOperations) == 1", timeout=10000)
            lobe_op = session.operations[0]
            assert lobe_op["op"] == "move_lobe" and lobe_op["y"] < float(session.initial_law.a[peak])
            page.keyboard.press("1")                              # preview min-change
            page.wait_for_function("window.camcadLast.preview === true", timeout=10000)
            assert "PREVIEW" in page.inner_text("#camcad-verdict")
            page.keyboard.press("Enter")                          # accept
            page.wait_for_function("Number(document.body.dataset.camcadOperations) == 2 && "
                                   "window.camcadLast.balanced", timeout=10000)
            page.keyboard.press("s")                              # save, as fix does
            page.wait_for_function("window.camcadLast.message.startsWith('saved')", timeout=10000)
            assert "PROFILE CLOSES" in page.inner_text("#camcad-verdict")
            shots = os.environ.get("CAMCAD_SCREENSHOTS")
            if shots:
                page.wait_for_timeout(1500)
                page.screenshot(path=str(Path(shots) / "edit-browser.png"))
        finally:
            browser.close()
    saved = tmp_path / "edited.dxf"
    check = cli("check", saved, "--json")
    assert check.code == 0 and check.json()["balanced"] is True
    # a second route: replay the lobe drag on a fresh session and correct with the library
    fresh = EditSession.from_file(tmp_path / "fig2.dxf")
    fresh.apply(lobe_op)
    expected = correct(fresh.law, "min-change").law
    again = load_law(saved)
    assert np.array_equal(again.law.x, expected.x)
    assert np.max(np.abs(again.law.a - expected.a)) <= 1e-9 * np.max(np.abs(expected.a))
    assert math.isclose(check.json()["rise"], -check.json()["return"], rel_tol=1e-9)
