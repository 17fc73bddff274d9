"""The editor in a browser: the view's figure served through matplotlib's WebAgg protocol by a small
tornado application bound to 127.0.0.1 only, answering only the user who started it.

The page holds matplotlib's own canvas (``mpl.js``: mouse and key events go to the server, PNG frames
come back) and a live panel: during a drag the server sends only the numbers (a ``camcad`` message:
closures, areas, the readout), and the figure is redrawn in full on release.

Who may drive it:

- **A token.** The URL the command prints (and opens) carries a random token as its first path part
  (``http://127.0.0.1:PORT/TOKEN/``, 192 bits from ``secrets``); every HTTP request and the websocket must
  carry it (compared in constant time), anything else gets HTTP 403. Another process on the machine can
  reach the port but not the token.
- **The host and origin.** Requests whose Host header is not this server's loopback address are refused
  (a page on another site cannot drive the editor through DNS rebinding), and the websocket accepts only
  its own origin (tornado's default).
- **Checked messages.** Every websocket message is checked (``parse_message``: known types, fields
  of the right type and in range, a device pixel ratio of 0 refused) before matplotlib sees it; a refused
  message, or one whose handling fails anyway, is reported on the page and changes nothing; the figure is
  put back in a state it can draw and the session's edits are untouched, so they can still be saved.
  Nothing is printed on the terminal.
"""

from __future__ import annotations

import asyncio
import errno
import hmac
import json
import math
import re
import secrets
import threading
from io import BytesIO
from pathlib import Path
from typing import Any

from camcad.edit.view import FIGSIZE, EditorView, new_figure
from camcad.errors import CamcadError
from camcad.io.input_file import check_json_nesting

ADDRESS = "127.0.0.1"
#: image formats the page may download
DOWNLOAD_FORMATS = ("png", "svg", "pdf")

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<link rel="icon" href="favicon.ico">
<link rel="stylesheet" href="_static/css/page.css" type="text/css">
<link rel="stylesheet" href="_static/css/boilerplate.css" type="text/css">
<link rel="stylesheet" href="_static/css/fbm.css" type="text/css">
<link rel="stylesheet" href="_static/css/mpl.css" type="text/css">
<script src="_static/js/mpl_tornado.js"></script>
<script src="mpl.js"></script>
<title>{title}</title>
<style>
 body {{ font-family: sans-serif; margin: 8px 12px; background: #fafafa; }}
 #camcad-bar {{ display: flex; gap: 16px; align-items: flex-start; margin-bottom: 6px; }}
 #camcad-verdict {{ font-weight: bold; padding: 4px 10px; border-radius: 4px; min-width: 13em; text-align: center; }}
 #camcad-verdict.closes {{ background: #dcfce7; color: #14532d; border: 1px solid #2a9d8f; }}
 #camcad-verdict.open {{ background: #fde2e2; color: #7f1d1d; border: 1px solid #e76f51; }}
 #camcad-verdict.preview {{ background: #dbeafe; color: #1e3a8a; border: 1px solid #1d4ed8; }}
 #camcad-live {{ font-family: monospace; font-size: 12px; margin: 0; white-space: pre; }}
 #camcad-message {{ font-size: 13px; color: #1f2937; white-space: pre-line; }}
 #camcad-message.error {{ color: #b91c1c; }}
</style>
</head>
<body data-camcad-revision="0">
<div id="camcad-bar">
 <div id="camcad-verdict" class="open">loading…</div>
 <pre id="camcad-live"></pre>
 <div id="camcad-message"></div>
</div>
<div id="figure"></div>
<script>
 function ready(fn) {{
   if (document.readyState != "loading") {{ fn(); }} else {{ document.addEventListener("DOMContentLoaded", fn); }}
 }}
 ready(function () {{
   var websocket_type = mpl.get_websocket_type();
   var uri = (window.location.protocol === "https:" ? "wss://" : "ws://") + window.location.host +
             window.location.pathname.replace(/[^/]*$/, "") + "ws";
   var websocket = new websocket_type(uri);
   var fig = new mpl.figure(1, websocket, mpl_ondownload, document.getElementById("figure"));
   fig.handle_camcad = function (fig, msg) {{
     var verdict = document.getElementById("camcad-verdict");
     verdict.textContent = msg.preview ? "PREVIEW" : (msg.balanced ? "PROFILE CLOSES" : "DOES NOT CLOSE");
     verdict.className = msg.preview ? "preview" : (msg.balanced ? "closes" : "open");
     document.getElementById("camcad-live").textContent = msg.badge.slice(1, 5).join("\\n") + "\\n" + msg.readout;
     var message = document.getElementById("camcad-message");
     message.textContent = msg.status + (msg.message ? "\\n" + msg.message : "");
     message.className = msg.error ? "error" : "";
     document.body.dataset.camcadRevision = msg.revision;
     document.body.dataset.camcadOperations = msg.operations;
     window.camcadLast = msg;
   }};
   window.camcadFigure = fig;
   // fit the figure to the window (a 1366 x 768 laptop too): never larger than the editor's own size,
   // smaller when the window is; the view lays itself out again at the new size (camcad.edit.view)
   var design = {{width: @DESIGN_WIDTH@, height: @DESIGN_HEIGHT@}}, pending = null;
   function fit() {{
     var toolbar = fig.root.querySelector(".mpl-toolbar");
     var above = fig.canvas_div.getBoundingClientRect().top + window.scrollY;   // the bar and the title
     var spare = above + (toolbar ? toolbar.offsetHeight : 48) + 16;
     var width = Math.max(640, Math.min(design.width, window.innerWidth - 28));
     var height = Math.max(400, Math.min(design.height, window.innerHeight - spare));
     var now = fig.canvas_div.getBoundingClientRect();
     if (Math.abs(now.width - width) > 2 || Math.abs(now.height - height) > 2) {{
       fig.canvas_div.style.width = width + "px";     // matplotlib's page then asks the server for that size
       fig.canvas_div.style.height = height + "px";
     }}
     document.body.dataset.camcadFit = width + "x" + height;
   }}
   websocket.addEventListener("open", function () {{ window.setTimeout(fit, 50); }});
   window.addEventListener("resize", function () {{
     window.clearTimeout(pending);
     pending = window.setTimeout(fit, 150);
   }});
 }});
</script>
</body>
</html>
"""
#: the editor's own size (px at 100 dpi), the largest the page makes the figure
_PAGE = _PAGE.replace("@DESIGN_WIDTH@", str(round(FIGSIZE[0] * 100))).replace("@DESIGN_HEIGHT@",
                                                                             str(round(FIGSIZE[1] * 100)))


# ---------------------------------------------------------------------------------------------
# Messages from the page
# ---------------------------------------------------------------------------------------------

# The browser editor's messages from the page, checked before matplotlib sees them.
#
# The page (matplotlib's ``mpl.js``) sends JSON objects over the websocket, each with a ``type`` and its
# fields. Any process that reaches the socket could send anything, so every message is checked here: a
# known type, each field of the right type and in range, nothing else passed on. A message that fails is
# refused with a one-line reason (shown on the page; nothing is printed on the terminal) and changes
# nothing: the session, its edits and the figure stay as they were.
#
# Ranges: cursor positions within ``MAX_COORDINATE_PX`` of the canvas; a canvas of 1 to ``MAX_SIDE_PX`` CSS
# pixels a side; a device pixel ratio from ``MIN_RATIO`` to ``MAX_RATIO`` (0 would give the figure a dpi
# of 0 and break every later frame); and at most ``MAX_PIXELS`` physical pixels (side × side × ratio²) so a
# forged size cannot make the server render gigabytes.

#: the largest message accepted (bytes); the page's largest is a few hundred
MAX_MESSAGE_BYTES = 16 * 1024
#: nesting of a message (an object holding a list of modifiers, guiEvent one level more)
MAX_MESSAGE_NESTING = 4
#: a cursor farther than this from the canvas (pixels) is not a cursor
MAX_COORDINATE_PX = 1e5
#: a canvas side (CSS pixels), the device pixel ratio, and the physical pixels of a frame
MAX_SIDE_PX = 8192
MIN_RATIO, MAX_RATIO = 0.25, 8.0
MAX_PIXELS = 50_000_000
#: what the page may say: type → {field: (kind, required)}
MOUSE = {"x": ("coordinate", True), "y": ("coordinate", True), "button": ("button", False),
         "buttons": ("buttons", False), "modifiers": ("modifiers", False), "step": ("step", False),
         "guiEvent": ("ignored", False)}
MESSAGES: dict[str, dict[str, tuple[str, bool]]] = {
    "supports_binary": {"value": ("bool", True)},
    "ack": {}, "draw": {}, "refresh": {}, "send_image_mode": {},
    "resize": {"width": ("side", True), "height": ("side", True)},
    "set_device_pixel_ratio": {"device_pixel_ratio": ("ratio", True)},
    "set_dpi_ratio": {"dpi_ratio": ("ratio", True)},
    "button_press": MOUSE, "button_release": MOUSE, "dblclick": MOUSE, "motion_notify": MOUSE,
    "figure_enter": MOUSE, "figure_leave": MOUSE, "scroll": {**MOUSE, "step": ("step", True)},
    "key_press": {"key": ("key", True), "guiEvent": ("ignored", False)},
    "key_release": {"key": ("key", True), "guiEvent": ("ignored", False)},
    "toolbar_button": {"name": ("tool", True)},
}
MODIFIERS = frozenset({"ctrl", "alt", "shift", "meta", "super"})
TOOLS = frozenset({"home", "back", "forward", "pan", "zoom", "download"})
#: a key as mpl.js writes it: an optional modifier, "k", then the browser's key name
_KEY = re.compile(r"^(?:(?:ctrl|alt|shift)\+)?k[^\x00-\x1f\x7f]{1,32}$")


class BadMessage(CamcadError):
    """A message from the page that is refused (one line)."""


def parse_message(text: str | bytes, ratio: float = 1.0, size_css: tuple[float, float] = (1500.0, 980.0)) -> dict:
    """The checked message, with only its known fields (``guiEvent`` dropped), or ``BadMessage``.

    Parameters
    ----------
    text : str or bytes
        The websocket message.
    ratio : float
        The device pixel ratio now in effect (a resize is checked against it).
    size_css : (float, float)
        The canvas size now in effect, CSS pixels (a new ratio is checked against it).

    Examples
    --------
    >>> parse_message('{"type": "set_device_pixel_ratio", "device_pixel_ratio": 2, "figure_id": 1}')
    {'type': 'set_device_pixel_ratio', 'device_pixel_ratio': 2.0}
    >>> parse_message('{"type": "set_device_pixel_ratio", "device_pixel_ratio": 0}')
    Traceback (most recent call last):
    ...
    camcad.edit.web.BadMessage: set_device_pixel_ratio: device_pixel_ratio 0 is out of range (0.25 .. 8); ...
    """
    if isinstance(text, bytes):
        if len(text) > MAX_MESSAGE_BYTES:
            raise BadMessage(f"a message of {len(text)} bytes", "websocket", "the page sends short JSON messages")
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError:
            raise BadMessage("a message that is not UTF-8 text", "websocket", "the page sends JSON text") from None
    if len(text) > MAX_MESSAGE_BYTES:
        raise BadMessage(f"a message of {len(text)} characters", "websocket", "the page sends short JSON messages")
    try:
        check_json_nesting(text, "websocket", MAX_MESSAGE_NESTING)
        content = json.loads(text)
    except CamcadError as err:
        raise BadMessage(err.what, "websocket", "the page sends flat JSON objects") from None
    except ValueError as err:
        raise BadMessage(f"not JSON ({str(err)[:60]})", "websocket", "the page sends JSON objects") from None
    if not isinstance(content, dict):
        raise BadMessage(f"a JSON {type(content).__name__}, not an object", "websocket", "send {\"type\": ...}")
    kind = content.get("type")
    if not isinstance(kind, str) or kind not in MESSAGES:
        shown = kind if isinstance(kind, str) else type(kind).__name__
        raise BadMessage(f"unknown message type {shown[:40]!r}", "websocket",
                         "the editor answers matplotlib's messages only")
    out: dict[str, Any] = {"type": kind}
    for name, (field, required) in MESSAGES[kind].items():
        if name not in content or content[name] is None:
            if required:
                raise BadMessage(f"field {name!r} is missing", kind, f"give {name}")
            continue
        if field != "ignored":
            out[name] = _field(kind, name, field, content[name])
    if kind == "resize" and out["width"] * out["height"] * ratio ** 2 > MAX_PIXELS:
        raise BadMessage(f"a canvas of {out['width']:g} x {out['height']:g} at ratio {ratio:g} is more than "
                         f"{MAX_PIXELS:,} pixels", kind, "resize the window smaller")
    for name in ("device_pixel_ratio", "dpi_ratio"):
        if name in out and size_css[0] * size_css[1] * out[name] ** 2 > MAX_PIXELS:
            raise BadMessage(f"ratio {out[name]:g} makes the canvas more than {MAX_PIXELS:,} pixels", kind,
                             "use a smaller ratio or window")
    if kind in ("button_press", "button_release", "dblclick", "scroll", "motion_notify", "figure_enter",
                "figure_leave"):
        out.setdefault("button", 0)
        out.setdefault("buttons", 0)
        out.setdefault("modifiers", [])
        out["guiEvent"] = None
    if kind in ("key_press", "key_release"):
        out["guiEvent"] = None
    return out


def _number(kind: str, name: str, value, low: float, high: float, unit: str = "") -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise BadMessage(f"{name} must be a finite number, not {str(value)[:30]!r}", kind, f"give {name} as a number")
    if not low <= value <= high:
        raise BadMessage(f"{name} {value:g}{unit} is out of range ({low:g} .. {high:g})", kind,
                         f"give {name} in {low:g} .. {high:g}")
    return float(value)


def _field(kind: str, name: str, field: str, value):
    if field == "bool":
        if not isinstance(value, bool):
            raise BadMessage(f"{name} must be true or false, not {str(value)[:30]!r}", kind, f"give {name} as a bool")
        return value
    if field == "coordinate":
        return _number(kind, name, value, -MAX_COORDINATE_PX, MAX_COORDINATE_PX)
    if field == "side":
        return _number(kind, name, value, 1, MAX_SIDE_PX)
    if field == "ratio":
        return _number(kind, name, value, MIN_RATIO, MAX_RATIO)
    if field == "step":
        return _number(kind, name, value, -1000, 1000)
    if field in ("button", "buttons"):
        high = 15 if field == "button" else 255
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= high:
            raise BadMessage(f"{name} must be a whole number 0 .. {high}, not {str(value)[:30]!r}", kind,
                             f"give {name} as the browser sends it")
        return value
    if field == "modifiers":
        if not isinstance(value, list) or len(value) > len(MODIFIERS) or \
                any(not isinstance(m, str) or m not in MODIFIERS for m in value):
            raise BadMessage(f"{name} must be a list of {', '.join(sorted(MODIFIERS))}", kind,
                             "give the modifier keys held")
        return list(value)
    if field == "key":
        if not isinstance(value, str) or not _KEY.match(value):
            raise BadMessage(f"key {str(value)[:30]!r} is not a key as the page writes it", kind,
                             "send e.g. \"kz\" or \"ctrl+kz\"")
        return value
    if field == "tool":
        if not isinstance(value, str) or value not in TOOLS:
            raise BadMessage(f"unknown toolbar button {str(value)[:30]!r}", kind,
                             f"use one of {', '.join(sorted(TOOLS))}")
        return value
    raise AssertionError(field)  # pragma: no cover - every kind of MESSAGES is handled above


def require_tornado() -> None:
    """Raise the one-line error that says what to install when tornado is missing."""
    try:
        import tornado  # noqa: F401
    except ImportError:
        raise CamcadError("the browser editor needs tornado, which is not installed", "camcad edit --web",
                          "install camcad[edit] (pip install 'camcad[edit]') or run it on a desktop") from None


class EditorServer:
    """The editor's figure and view served on http://127.0.0.1:PORT/ (WebAgg over a websocket).

    Parameters
    ----------
    session : the ``EditSession`` to edit.
    port : TCP port; 0 picks a free one.
    output : where the view's ``s`` saves.
    title : the page's and the figure's title.
    """

    def __init__(self, session, *, port: int = 0, output: Path | None = None, title: str = "") -> None:
        require_tornado()
        import tornado.netutil
        from matplotlib.backends.backend_webagg_core import (
            FigureCanvasWebAggCore,
            FigureManagerWebAgg,
            NavigationToolbar2WebAgg,
        )

        class _Manager(FigureManagerWebAgg):
            _toolbar2_class = NavigationToolbar2WebAgg  # type: ignore[assignment]  # matplotlib types it as None

        if not (isinstance(port, int) and 0 <= port <= 65535):
            raise CamcadError(f"port {port!r} is not a TCP port", "--port", "give 0..65535 (0 picks a free one)")
        try:
            self.sockets = tornado.netutil.bind_sockets(port, address=ADDRESS)
        except OSError as err:
            if err.errno == errno.EADDRINUSE:
                raise CamcadError(f"port {port} is in use", "--port", "pick another port, or omit --port") from None
            raise CamcadError(f"cannot listen on {ADDRESS}:{port} ({err.strerror})", "--port",
                              "pick another port") from None
        self.port = int(self.sockets[0].getsockname()[1])
        self.address = ADDRESS
        #: the secret part of the URL: every request must carry it
        self.token = secrets.token_urlsafe(24)
        self.url = f"http://{ADDRESS}:{self.port}/{self.token}/"
        #: messages refused, and messages whose handling failed and were recovered from (for the page and tests)
        self.refused = 0
        self.recovered = 0
        self.title = title or f"camcad edit — {session.where}"
        self.figure = new_figure()
        self._figsize = FIGSIZE
        self.canvas = FigureCanvasWebAggCore(self.figure)
        self.manager = _Manager(self.canvas, 1)
        self.manager.set_window_title(self.title)
        self.revision = 0
        self.view = EditorView(session, self.figure, blit=False, live=self._send_live, output=output,
                               title=title or session.where)
        self.session = session
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._thread: threading.Thread | None = None
        self._ready = threading.Event()

    # --- live numbers ---------------------------------------------------------------------------

    def _send_live(self, numbers: dict) -> None:
        self.revision += 1
        payload = json.loads(json.dumps({**numbers, "revision": self.revision}, default=float))
        self.manager._send_event("camcad", **payload)

    # --- the tornado application ---------------------------------------------------------------

    def application(self):
        import matplotlib as mpl
        import tornado.web
        import tornado.websocket
        from matplotlib.backends.backend_webagg_core import FigureManagerWebAgg

        server = self
        allowed = {f"{ADDRESS}:{self.port}", f"localhost:{self.port}"}

        class _Guard:
            def prepare(self):
                if self.request.host not in allowed:
                    raise tornado.web.HTTPError(403, "this editor answers on %s only", server.url)
                given = self.path_args[0] if self.path_args else ""
                if not server.token_ok(given):
                    raise tornado.web.HTTPError(403, "the URL lacks this editor's token")

            def write_error(self, status_code, **kwargs):   # a short page, never a traceback
                self.set_header("Content-Type", "text/plain; charset=utf-8")
                self.finish(f"{status_code}: this editor answers only at the URL camcad edit printed\n")

        class Forbidden(_Guard, tornado.web.RequestHandler):
            def prepare(self):
                raise tornado.web.HTTPError(403)

            def get(self, *_args):
                raise tornado.web.HTTPError(403)

        class Page(_Guard, tornado.web.RequestHandler):
            def get(self, _token):
                self.set_header("Content-Type", "text/html; charset=utf-8")
                self.set_header("Cache-Control", "no-store")
                self.set_header("Referrer-Policy", "no-referrer")
                self.write(_PAGE.format(title=_html(server.title)))

        class MplJs(_Guard, tornado.web.RequestHandler):
            def get(self, _token):
                self.set_header("Content-Type", "application/javascript")
                self.write(FigureManagerWebAgg.get_javascript())

        class Static(_Guard, tornado.web.StaticFileHandler):
            def get(self, _token, path, include_body=True):
                return super().get(path, include_body)

        class Download(_Guard, tornado.web.RequestHandler):
            def get(self, _token, fmt):
                import mimetypes

                if fmt not in DOWNLOAD_FORMATS:
                    raise tornado.web.HTTPError(404)
                buffer = BytesIO()
                server.figure.savefig(buffer, format=fmt)
                self.set_header("Content-Type", mimetypes.types_map.get("." + fmt, "binary"))
                self.write(buffer.getvalue())

        class Socket(_Guard, tornado.websocket.WebSocketHandler):
            supports_binary = True

            def open(self, _token):
                server.manager.add_web_socket(self)
                if hasattr(self, "set_nodelay"):
                    self.set_nodelay(True)
                server.view._notify_live()

            def on_close(self):
                if self in server.manager.web_sockets:
                    server.manager.remove_web_socket(self)

            def on_message(self, message):
                server.handle_message(self, message)

            def send_json(self, content):
                self._write(json.dumps(content))

            def send_binary(self, blob):
                if self.supports_binary:
                    self._write(blob, binary=True)
                else:
                    import base64

                    self._write("data:image/png;base64," + base64.b64encode(blob).decode("ascii"))

            def _write(self, message, binary=False):
                """Send, ignoring a page that has gone (closed tab) instead of logging a traceback."""
                try:
                    future = self.write_message(message, binary=binary)
                except tornado.websocket.WebSocketClosedError:
                    return
                future.add_done_callback(lambda done: done.exception())

        class Icon(_Guard, tornado.web.RequestHandler):
            def get(self, _token):
                self.set_header("Content-Type", "image/png")
                self.write(Path(mpl.get_data_path(), "images", "matplotlib.png").read_bytes())

        static = FigureManagerWebAgg.get_static_file_path()
        token = r"/([A-Za-z0-9_-]{1,64})"
        return tornado.web.Application([
            (token + r"/favicon\.ico", Icon),
            (token + r"/", Page),
            (token + r"/mpl\.js", MplJs),
            (token + r"/_static/(.*)", Static, {"path": static}),
            (token + r"/_images/(.*)", Static, {"path": str(Path(mpl.get_data_path(), "images"))}),
            (token + r"/(?:\d+/)?download\.([a-z0-9.]+)", Download),
            (token + r"/ws", Socket),
            (r"/.*", Forbidden),
        ], log_function=_quiet, websocket_max_message_size=MAX_MESSAGE_BYTES)

    def token_ok(self, given: str) -> bool:
        """True when ``given`` is this server's token (compared in constant time)."""
        return hmac.compare_digest(str(given).encode("utf-8", "replace"), self.token.encode("ascii"))

    # --- messages from the page -------------------------------------------------------------------

    def handle_message(self, socket, message) -> None:
        """Check a message (``parse_message``) and hand it to matplotlib; a refused message, or one whose
        handling fails, is reported on the page and leaves the session as it was (``recover``)."""
        canvas = self.canvas
        ratio = float(getattr(canvas, "device_pixel_ratio", 1.0) or 1.0)
        width, height = self.figure.get_size_inches() * self.figure.dpi / ratio
        try:
            content = parse_message(message, ratio, (float(width), float(height)))
        except BadMessage as err:
            self.refused += 1
            self._tell(f"message refused: {err.message()}")
            return
        if content["type"] == "supports_binary":
            socket.supports_binary = content["value"]
            return
        try:
            self.manager.handle_json(content)
        except Exception as err:  # noqa: BLE001 - whatever went wrong, the editor goes on and says so
            self.recover(f"{content['type']} message failed ({type(err).__name__}: {' '.join(str(err).split())[:80]})")

    def recover(self, what: str) -> None:
        """Put the figure back in a state it can draw (ratio 1 and the editor's size when they are not sane),
        end a half-done drag without an edit, redraw, and say so on the page; the session's edits are kept."""
        self.recovered += 1
        canvas, figure = self.canvas, self.figure
        try:
            ratio = float(getattr(canvas, "device_pixel_ratio", 1.0))
            if not (math.isfinite(ratio) and ratio > 0):
                canvas._handle_set_device_pixel_ratio(1.0)
            width, height = figure.get_size_inches()
            if not (math.isfinite(width * height) and width > 0 and height > 0 and figure.dpi > 0):
                figure.set_dpi(100)
                figure.set_size_inches(*self._figsize, forward=False)
            if self.view._drag is not None:
                self.view._drag = None
                self.session.cancel_gesture()
            canvas._force_full = True
            self.view.refresh()
        except Exception:  # noqa: BLE001 - the message below still reaches the page
            pass
        self._tell(f"{what}; the editor recovered, your edits are kept")

    def _tell(self, text: str) -> None:
        self.view._set_message(text, error=True)
        try:
            self.view._notify_live()
        except Exception:  # noqa: BLE001 - a page that is gone
            pass

    # --- running --------------------------------------------------------------------------------

    async def _serve(self) -> None:
        from tornado.httpserver import HTTPServer

        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        http = HTTPServer(self.application())
        http.add_sockets(self.sockets)
        self._ready.set()
        try:
            await self._stop.wait()
        finally:
            http.stop()
            await http.close_all_connections()

    def run(self) -> None:
        """Serve until ``stop`` or Ctrl+C (which ends the editor normally)."""
        try:
            asyncio.run(self._serve())
        except KeyboardInterrupt:
            pass

    def start_in_thread(self) -> EditorServer:
        """Serve from a background thread (tests, benchmarks); returns when the server accepts connections."""
        self._thread = threading.Thread(target=self.run, name="camcad-edit-web", daemon=True)
        self._thread.start()
        if not self._ready.wait(10):
            raise RuntimeError("the editor's web server did not start")
        return self

    def call(self, function, *args):
        """Run ``function(*args)`` on the server's loop and return its result (thread-safe; for tests)."""
        if self._loop is None:
            return function(*args)
        future = asyncio.run_coroutine_threadsafe(_call(function, *args), self._loop)
        return future.result(10)

    def stop(self) -> None:
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        if self._thread is not None:
            self._thread.join(10)


def _quiet(handler) -> None:
    """Access log: only server errors (the terminal shows the URL, not every request)."""
    if handler.get_status() >= 500:
        import logging

        logging.getLogger("camcad.edit.web").error("%s %s -> %s", handler.request.method, handler.request.uri,
                                                   handler.get_status())


async def _call(function, *args):
    return function(*args)


def _html(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
