"""The browser editor's messages from the page, checked before matplotlib sees them.

The page (matplotlib's ``mpl.js``) sends JSON objects over the websocket, each with a ``type`` and its
fields. Any process that reaches the socket could send anything, so every message is checked here: a
known type, each field of the right type and in range, nothing else passed on. A message that fails is
refused with a one-line reason (shown on the page; nothing is printed on the terminal) and changes
nothing: the session, its edits and the figure stay as they were.

Ranges: cursor positions within ``MAX_COORDINATE_PX`` of the canvas; a canvas of 1 to ``MAX_SIDE_PX`` CSS
pixels a side; a device pixel ratio from ``MIN_RATIO`` to ``MAX_RATIO`` (0 would give the figure a dpi
of 0 and break every later frame); and at most ``MAX_PIXELS`` physical pixels (side × side × ratio²) so a
forged size cannot make the server render gigabytes.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

from camcad.errors import CamcadError
from camcad.io.input_file import check_json_nesting

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
    camcad.edit.messages.BadMessage: set_device_pixel_ratio: device_pixel_ratio 0 is out of range (0.25 .. 8); ...
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


__all__ = ["MESSAGES", "BadMessage", "parse_message"]
