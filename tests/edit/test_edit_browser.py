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


def _status(server, path: str, headers: dict | None = None) -> int:
    connection = http.client.HTTPConnection("127.0.0.1", server.port, timeout=5)
    connection.request("GET", path, headers=headers or {})
    response = connection.getresponse()
    body = response.read()
    assert b"Traceback" not in body
    return response.status


def test_server_listens_on_loopback_only_and_checks_the_host(server):
    assert server.address == "127.0.0.1" and server.url.startswith("http://127.0.0.1:")
    assert all(sock.getsockname()[0] == "127.0.0.1" for sock in server.sockets)
    page = f"/{server.token}/"
    assert server.url.endswith(page) and len(server.token) >= 32
    assert _status(server, page) == 200
    assert _status(server, page, {"Host": f"evil.example:{server.port}"}) == 403


def _handshake(server, path: str) -> int:
    """The status of a websocket handshake on ``path`` (101 when the socket opens)."""
    import base64
    import socket

    with socket.create_connection(("127.0.0.1", server.port), timeout=5) as sock:
        key = base64.b64encode(os.urandom(16)).decode()
        sock.sendall((f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\nUpgrade: websocket\r\n"
                      f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n"
                      f"Origin: http://127.0.0.1:{server.port}\r\n\r\n").encode())
        reply = sock.recv(4096).decode("latin-1")
    return int(reply.split()[1])


def test_requests_without_the_token_are_refused(server):
    # issue 34 F4: any process on the machine could drive the editor; now only the URL's holder can
    token = server.token
    wrong = ("x" if token[0] != "x" else "y") + token[1:]
    for path in ("/", "/mpl.js", "/_static/js/mpl_tornado.js", "/download.png", "/favicon.ico", "/ws",
                 f"/{wrong}/", f"/{wrong}/mpl.js", f"/{token[:-1]}/", f"/{token}x/", f"/../{token}/",
                 f"/{wrong}/_static/js/mpl_tornado.js", f"/{wrong}/download.png"):
        assert _status(server, path) == 403, path
    assert _status(server, f"/{token}/mpl.js") == 200
    assert _status(server, f"/{token}/_static/js/mpl_tornado.js") == 200
    assert _status(server, f"/{token}/download.exe") == 404
    assert _handshake(server, "/ws") == 403
    assert _handshake(server, f"/{wrong}/ws") == 403
    assert _handshake(server, f"/{token}/ws") == 101


def test_a_failing_message_is_recovered_from_and_the_edits_kept(server, tmp_path, capfd):
    # whatever goes wrong inside matplotlib's handling, the page is told, the figure can draw, edits stay
    session = server.session
    server.call(session.apply, {"op": "correct", "mode": "min-change"})
    before = session.law

    def broken(_content):
        raise ZeroDivisionError("float division by zero")

    server.manager.handle_json = broken
    server.call(server.handle_message, None, '{"type": "draw"}')
    assert server.recovered == 1 and "recovered, your edits are kept" in server.view.message
    del server.manager.handle_json                           # matplotlib's own again
    server.call(server.handle_message, None, '{"type": "set_device_pixel_ratio", "device_pixel_ratio": 0}')
    assert server.refused == 1 and "out of range" in server.view.message
    assert server.canvas.device_pixel_ratio == 1 and server.figure.dpi > 0
    server.call(server.figure.canvas.draw)                   # the figure still draws
    assert session.law is before and session.applied == 1
    saved = server.call(session.save, tmp_path / "kept.dxf")
    assert load_law(saved).law.x.size == before.x.size
    assert "Traceback" not in capfd.readouterr().err


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


FORGED = [
    '{"type": "set_device_pixel_ratio", "device_pixel_ratio": 0}',     # issue 34 F4: broke the page for good
    '{"type": "set_dpi_ratio", "dpi_ratio": -1}',
    'not json at all',
    '[' * 40 + ']' * 40,
    '{"type": "exec", "code": "import os"}',
    '{"type": "button_press", "x": "a", "y": 10, "button": 0, "buttons": 1, "modifiers": []}',
    '{"type": "motion_notify", "x": 1e300, "y": 10, "button": 0, "buttons": 1, "modifiers": []}',
    '{"type": "resize", "width": 1e9, "height": 1e9}',
    '{"type": "key_press", "key": "zzz"}',
    '{"type": "toolbar_button", "name": "__init__"}',
    '{"type": "scroll", "x": 10, "y": 10, "modifiers": ["hyper"], "step": 1}',
    '"a string"',
]


def test_browser_forged_and_malformed_messages_leave_the_editor_working(server, tmp_path, cli, capsys):
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
            page.evaluate("window.camcadFigure.canvas_div.focus()")
            page.keyboard.press("1")                                  # preview min-change
            page.wait_for_function("window.camcadLast.preview === true", timeout=10000)
            page.keyboard.press("Enter")                              # accept: one edit
            page.wait_for_function("Number(document.body.dataset.camcadOperations) == 1 && "
                                   "window.camcadLast.balanced", timeout=10000)
            edited = session.law
            for message in FORGED:                                    # through the page's own socket
                page.evaluate("m => window.camcadFigure.ws.send(m)", message)
            page.wait_for_function("window.camcadLast.message.startsWith('message refused') && "
                                   "window.camcadLast.error", timeout=10000)
            assert server.call(lambda: server.refused) == len(FORGED)
            assert "error" in page.get_attribute("#camcad-message", "class")
            assert session.law is edited and session.applied == 1      # nothing changed by them
            assert server.call(lambda: server.canvas.device_pixel_ratio) > 0
            revision = int(page.evaluate("document.body.dataset.camcadRevision"))
            frame = page.evaluate("window.camcadFigure.imageObj.src")
            page.keyboard.press("s")                                  # the edit is still saveable
            page.wait_for_function("window.camcadLast.message.startsWith('saved')", timeout=10000)
            assert int(page.evaluate("document.body.dataset.camcadRevision")) > revision
            page.wait_for_function(f"window.camcadFigure.imageObj.src !== {frame!r}", timeout=10000)  # new frames
        finally:
            browser.close()
    assert "Traceback" not in capsys.readouterr().err                 # nothing on the terminal
    check = cli("check", tmp_path / "edited.dxf", "--json")
    assert check.code == 0 and check.json()["balanced"] is True
    assert np.array_equal(load_law(tmp_path / "edited.dxf").law.x, edited.x)
