"""Reading an input file safely: only regular files, a stated size limit, any text encoding.

A law file is read whole before it is parsed. What is refused at once, with one clear line:
a path that does not exist, a directory, a FIFO, a socket or a device (``/dev/zero`` would be read
until memory runs out, a FIFO blocks forever), a file larger than :data:`MAX_INPUT_BYTES`, and a
file the system refuses to read (``/proc/self/mem``). Text is decoded from UTF-8 (with or without
a byte-order mark), UTF-16 (with a byte-order mark, or recognised by its zero bytes) or, failing
those, byte for byte (Latin-1 code points, so no byte is lost).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from camcad.errors import CamcadError

#: the largest input file camcad reads (bytes): 200 MB, far beyond any drawn law
MAX_INPUT_BYTES = 200 * 1024 * 1024
#: the deepest nesting of lists and tables camcad reads in a JSON or TOML file (a scene is 4 deep, an edit
#: script 3); checked before the parser recurses
MAX_NESTING = 32

_BOM_UTF8 = b"\xef\xbb\xbf"
_BOM_UTF16 = (b"\xff\xfe", b"\xfe\xff")


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def read_input(path: str | Path, what: str = "a DXF drawing or a .csv/.txt table",
               limit: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of an input file, after checking that it is a regular file of a sane size.

    Parameters
    ----------
    path : str or Path
        The file to read.
    what : str
        What the file should be, for the error's how-to-fix part.
    limit : int
        Largest size read, bytes (default :data:`MAX_INPUT_BYTES`, 200 MB).

    Returns
    -------
    bytes
        The whole content.

    Raises
    ------
    CamcadError
        Missing file, not a regular file (directory, FIFO, socket, device), larger than
        ``limit``, or unreadable; the message is one line naming the path.

    Examples
    --------
    >>> import tempfile, os
    >>> folder = tempfile.mkdtemp()
    >>> read_input(folder)
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: ...: is a directory, not a file; give a DXF drawing or a .csv/.txt table
    """
    path = Path(path)
    where = str(path)
    try:
        info = os.stat(path)  # follows symlinks; never opens the file (a FIFO would block)
    except FileNotFoundError:
        raise CamcadError("file not found", where, "check the path") from None
    except OSError as err:
        raise CamcadError(f"cannot read the file ({err.strerror or type(err).__name__})", where,
                          "check the path and its permissions") from None
    if not stat.S_ISREG(info.st_mode):
        raise CamcadError(f"is {_kind(info.st_mode)}, not a file", where, f"give {what}")
    if info.st_size > limit:
        raise CamcadError(f"the file is {info.st_size / 2**20:.0f} MB, more than camcad reads "
                          f"({limit / 2**20:.0f} MB)", where, f"give {what} of at most {limit / 2**20:.0f} MB")
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)  # a file may grow, or lie about its size (/proc)
    except OSError as err:
        raise CamcadError(f"cannot read the file ({err.strerror or type(err).__name__})", where,
                          f"give {what} saved on disk") from None
    if len(data) > limit:
        raise CamcadError(f"the file is larger than camcad reads ({limit / 2**20:.0f} MB)", where,
                          f"give {what} of at most {limit / 2**20:.0f} MB")
    return data


def decode_text(raw: bytes) -> tuple[str, str]:
    """Text of a file whose encoding is not declared, and how it was decoded.

    UTF-8 (a byte-order mark is dropped), UTF-16 with a byte-order mark, UTF-16 without one when
    every other byte of the start is zero; otherwise UTF-8 where valid and, where not, each byte as
    the Latin-1 character of the same code (nothing is lost, coordinates are ASCII anyway).

    Parameters
    ----------
    raw : bytes
        The file's content.

    Returns
    -------
    tuple of (str, str)
        The text, and the encoding name: "utf-8", "utf-8-sig", "utf-16", "utf-16-le", "utf-16-be"
        or "latin-1".

    Examples
    --------
    >>> decode_text(b"\\xef\\xbb\\xbf0\\nSECTION")
    ('0\\nSECTION', 'utf-8-sig')
    >>> decode_text("0\\nSECTION".encode("utf-16"))
    ('0\\nSECTION', 'utf-16')
    >>> decode_text("0\\nEOF".encode("utf-16-le"))
    ('0\\nEOF', 'utf-16-le')
    """
    if raw.startswith(_BOM_UTF8):
        return raw[3:].decode("utf-8", errors="replace"), "utf-8-sig"
    if raw[:2] in _BOM_UTF16:
        return raw.decode("utf-16", errors="replace"), "utf-16"
    encoding = utf16_without_bom(raw)
    if encoding:
        return raw.decode(encoding, errors="replace"), encoding
    try:
        return raw.decode("utf-8"), "utf-8"
    except UnicodeDecodeError:
        return raw.decode("latin-1"), "latin-1"


def utf16_without_bom(raw: bytes) -> str | None:
    """"utf-16-le" or "utf-16-be" when the start of ``raw`` looks like UTF-16 text without a
    byte-order mark (ASCII characters with a zero high byte), else None."""
    head = raw[:512]
    if len(head) < 4:
        return None
    head = head[: len(head) // 2 * 2]
    even, odd = head[0::2], head[1::2]
    if odd.count(0) >= 0.9 * len(odd) and even.count(0) <= 0.1 * len(even):
        return "utf-16-le"
    if even.count(0) >= 0.9 * len(even) and odd.count(0) <= 0.1 * len(odd):
        return "utf-16-be"
    return None


def is_regular_file(path: str | Path) -> bool:
    """True when ``path`` names a regular file (checked without opening it)."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def check_json_nesting(text: str, where: str, limit: int = MAX_NESTING) -> None:
    """A CamcadError when the JSON ``text`` nests lists and objects deeper than ``limit`` (scanned before it is
    parsed: Python's parser recurses once per level).

    Examples
    --------
    >>> check_json_nesting('[{"op": "move", "x": [1, 2]}]', "s.json")
    >>> check_json_nesting("[" * 100 + "]" * 100, "s.json")
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: s.json: lists and objects nest 33 deep at character 33, ...
    """
    depth = 0
    in_string = False
    escaped = False
    for index, ch in enumerate(text):
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            if depth > limit:
                raise CamcadError(f"lists and objects nest {depth} deep at character {index + 1}, deeper than "
                                  f"camcad reads ({limit})", where, "flatten the file")
        elif ch in "]}":
            depth -= 1


def check_nesting(data, where: str, limit: int = MAX_NESTING) -> None:
    """A CamcadError when the parsed ``data`` (dicts and lists) nests deeper than ``limit``; walked without
    recursion, so a TOML file of dotted keys a thousand deep is refused, not a crash.

    Examples
    --------
    >>> check_nesting({"a": {"b": [1, 2]}}, "s.toml")
    >>> deep = {}
    >>> node = deep
    >>> for _ in range(40):
    ...     node["k"] = {}
    ...     node = node["k"]
    >>> check_nesting(deep, "s.toml")
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: s.toml: tables and arrays nest 33 deep, deeper than camcad reads (32); flatten the file
    """
    stack = [(data, 0)]
    while stack:
        node, depth = stack.pop()
        if isinstance(node, dict):
            children = list(node.values())
        elif isinstance(node, list):
            children = node
        else:
            continue
        if depth + 1 > limit:
            raise CamcadError(f"tables and arrays nest {depth + 1} deep, deeper than camcad reads ({limit})", where,
                              "flatten the file")
        stack.extend((child, depth + 1) for child in children if isinstance(child, (dict, list)))


__all__ = ["MAX_INPUT_BYTES", "MAX_NESTING", "check_json_nesting", "check_nesting", "decode_text", "is_regular_file",
           "read_input", "utf16_without_bom"]
