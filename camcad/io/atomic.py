"""Atomic file output that cannot be redirected: a reader never sees a half-written file, a failed
write leaves nothing behind, and a symlink planted in the output folder is never followed.

How: the new content goes into a temporary file created exclusively in the target's own folder
(``tempfile.mkstemp``: ``O_CREAT | O_EXCL`` with an unpredictable name, mode 0600 widened to the
umask's default afterwards), is flushed and fsynced, then renamed over the target (``os.replace``,
atomic on POSIX file systems). The rename replaces a symlink at the target name by the new file; it
never writes through it. The temporary file is removed on any failure, including KeyboardInterrupt; those
left by a process that was killed (``kill -9`` gives no chance to clean up) are removed by the next process
that writes into the same folder (once per folder and process), when ``STRAY_AGE_S`` old (a younger one may
belong to a writer still at work).
"""

from __future__ import annotations

import os
import re
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from camcad.errors import CamcadError

#: a temporary file of ``write_atomic`` (mkstemp's prefix ".NAME." and 8 random characters, suffix ".tmp")
TEMP_FILE = re.compile(r"^\..+\.[A-Za-z0-9_]{8}\.tmp$")
#: a temporary file beside its target is stray (its writer died) when older than this (s)
STRAY_AGE_S = 600.0
#: the folders this process has cleaned of stray temporary files
_CLEANED: set[str] = set()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str | Path, write: Callable[[Path], object]) -> Path:
    """Call ``write(tmp)`` on a fresh temporary file beside ``path``, then rename it over ``path``.

    Parameters
    ----------
    path : str or Path
        The file to create or replace. Its folder is created if missing.
    write : callable
        Writes the content to the path it is given (it may reopen the file by name).

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> write_atomic(folder / "a.txt", lambda tmp: tmp.write_text("x")).read_text()
    'x'
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise CamcadError("a file stands where the output folder should be", str(path.parent),
                          "choose another output folder with -o") from None
    except OSError as err:
        raise CamcadError(f"cannot create the output folder ({err.strerror})", str(path.parent),
                          "choose another output folder with -o") from None
    if path.is_dir():
        raise CamcadError("the output is an existing folder, not a file name", str(path),
                          "give a file name with -o")
    if str(path.parent) not in _CLEANED:
        _CLEANED.add(str(path.parent))
        remove_stray_temps(path.parent)
    try:
        handle, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as err:
        raise CamcadError(f"cannot write into the output folder ({err.strerror})", str(path.parent),
                          "choose a writable folder with -o") from None
    tmp = Path(name)
    try:
        os.close(handle)
        write(tmp)
        with open(tmp, "rb+") as stream:
            os.fsync(stream.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as err:
        raise CamcadError(f"cannot write the file ({err.strerror})", str(path),
                          "check the folder's permissions and free space, or choose another output") from None
    finally:
        if tmp.exists() or tmp.is_symlink():
            tmp.unlink()
    return path


def remove_stray_temps(folder: str | Path, min_age_s: float = STRAY_AGE_S) -> int:
    """Remove the temporary files interrupted ``write_atomic`` calls left in ``folder``, those older than
    ``min_age_s``; returns how many.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / ".law.csv.abcd1234.tmp").write_text("half a file")
    >>> _ = (folder / "law.csv").write_text("kept")
    >>> remove_stray_temps(folder, min_age_s=0), sorted(p.name for p in folder.iterdir())
    (1, ['law.csv'])
    """
    removed = 0
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return 0
    now = time.time()
    for entry in entries:
        try:
            if TEMP_FILE.match(entry.name) and entry.is_file(follow_symlinks=False) \
                    and now - entry.stat(follow_symlinks=False).st_mtime >= min_age_s:
                os.unlink(entry.path)
                removed += 1
        except OSError:
            continue
    return removed


def write_text_atomic(path: str | Path, text: str) -> Path:
    """``write_atomic`` of UTF-8 text with ``\\n`` line ends."""
    return write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8", newline="\n"))
