"""The editor in a browser: the view's figure served through matplotlib's WebAgg protocol by a small
tornado application bound to 127.0.0.1 only.

The page holds matplotlib's own canvas (``mpl.js``: mouse and key events go to the server, PNG frames
come back) and a live panel: during a drag the server sends only the numbers (a ``camcad`` message:
closures, areas, the readout), and the figure is redrawn in full on release. Requests whose Host header
is not this server's loopback address are refused (a page on another site cannot drive the editor
through DNS rebinding), and the websocket accepts only its own origin (tornado's default).
"""

from __future__ import annotations

import asyncio
import errno
import json
import threading
from io import BytesIO
from pathlib import Path

from camcad.edit.view import FIGSIZE
from camcad.errors import CamcadError

ADDRESS = "127.0.0.1"

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<link rel="stylesheet" href="/_static/css/page.css" type="text/css">
<link rel="stylesheet" href="/_static/css/boilerplate.css" type="text/css">
<link rel="stylesheet" href="/_static/css/fbm.css" type="text/css">
<link rel="stylesheet" href="/_static/css/mpl.css" type="text/css">
<script src="/_static/js/mpl_tornado.js"></script>
<script src="/mpl.js"></script>
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
   var uri = (window.location.protocol === "https:" ? "wss://" : "ws://") + window.location.host + "/ws";
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

        from camcad.edit.view import EditorView, new_figure

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
        self.url = f"http://{ADDRESS}:{self.port}/"
        self.title = title or f"camcad edit — {session.where}"
        self.figure = new_figure()
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

        class Page(_Guard, tornado.web.RequestHandler):
            def get(self):
                self.set_header("Content-Type", "text/html; charset=utf-8")
                self.write(_PAGE.format(title=_html(server.title)))

        class MplJs(_Guard, tornado.web.RequestHandler):
            def get(self):
                self.set_header("Content-Type", "application/javascript")
                self.write(FigureManagerWebAgg.get_javascript())

        class Static(_Guard, tornado.web.StaticFileHandler):
            pass

        class Download(_Guard, tornado.web.RequestHandler):
            def get(self, fmt):
                import mimetypes

                buffer = BytesIO()
                server.figure.savefig(buffer, format=fmt)
                self.set_header("Content-Type", mimetypes.types_map.get("." + fmt, "binary"))
                self.write(buffer.getvalue())

        class Socket(_Guard, tornado.websocket.WebSocketHandler):
            supports_binary = True

            def open(self):
                server.manager.add_web_socket(self)
                if hasattr(self, "set_nodelay"):
                    self.set_nodelay(True)
                server.view._notify_live()

            def on_close(self):
                server.manager.remove_web_socket(self)

            def on_message(self, message):
                content = json.loads(message)
                if content["type"] == "supports_binary":
                    self.supports_binary = content["value"]
                else:
                    server.manager.handle_json(content)

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
            def get(self):
                self.set_header("Content-Type", "image/png")
                self.write(Path(mpl.get_data_path(), "images", "matplotlib.png").read_bytes())

        static = FigureManagerWebAgg.get_static_file_path()
        return tornado.web.Application([
            (r"/favicon.ico", Icon),
            (r"/", Page),
            (r"/mpl.js", MplJs),
            (r"/_static/(.*)", Static, {"path": static}),
            (r"/_images/(.*)", Static, {"path": str(Path(mpl.get_data_path(), "images"))}),
            (r"/download\.([a-z0-9.]+)", Download),
            (r"/ws", Socket),
        ], log_function=_quiet)

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
