"""The one error type users see: what is wrong, where, and how to fix it."""

from __future__ import annotations

import difflib


class CamcadError(Exception):
    """A problem with the user's input or request; the CLI prints it on one line and exits 2.

    Every function of the public API raises this (and only this) for bad input; anything else that
    escapes is a bug (exit 3 at the command line). The message is one line: where, what, how to fix.

    Parameters
    ----------
    what : str
        What is wrong, e.g. "vertex 17 goes back in x" (no unit: text).
    where : str, optional
        The file, entity, vertex or option it concerns, e.g. "accel.dxf, LWPOLYLINE 2F".
    fix : str, optional
        How to fix it, e.g. "redraw the vertex or pick another curve with --handle".

    Examples
    --------
    >>> err = CamcadError("vertex 17 goes back in x", "accel.dxf, LWPOLYLINE 2F", "redraw the vertex")
    >>> str(err)
    'accel.dxf, LWPOLYLINE 2F: vertex 17 goes back in x; redraw the vertex'
    >>> err.what, err.where, err.fix
    ('vertex 17 goes back in x', 'accel.dxf, LWPOLYLINE 2F', 'redraw the vertex')
    """

    def __init__(self, what: str, where: str = "", fix: str = "") -> None:
        self.what = what
        self.where = where
        self.fix = fix
        super().__init__(self.message())

    def message(self) -> str:
        text = f"{self.where}: {self.what}" if self.where else self.what
        if self.fix:
            text += f"; {self.fix}"
        return " ".join(text.split())


def nearest_name(name: str, valid: list[str]) -> str:
    """'did you mean …' text for an unknown key, or the list of valid keys."""
    close = difflib.get_close_matches(name, valid, n=1, cutoff=0.5)
    if close:
        return f"did you mean '{close[0]}'? valid keys: {', '.join(valid)}"
    return f"valid keys: {', '.join(valid)}"


def excerpt(value: object, limit: int = 40) -> str:
    """A short, printable excerpt of ``value`` for an error message: its repr cut to ``limit`` characters,
    and for a long list or text its length. An error line never echoes a whole 100,000-number array.

    Examples
    --------
    >>> excerpt([1.5] * 100000)
    '[1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5,... (a list of 100000 items)'
    >>> excerpt("short")
    "'short'"
    """
    text = repr(value)
    if len(text) <= limit:
        return text
    size = f" (a {type(value).__name__} of {len(value)} items)" if isinstance(value, (list, tuple, dict)) else \
        (f" ({len(value)} characters)" if isinstance(value, (str, bytes)) else "")
    return text[:limit] + "..." + size
