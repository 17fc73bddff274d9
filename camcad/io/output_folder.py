"""The folder a command writes into: names confined to it, inputs never replaced, one run at a time.

Rules (README "Safety"):

- **Names.** A name that comes from a file (a scene's ``name``, a mechanism's key) becomes a file or
  folder name by ``safe_name``: letters, digits, ``_``, ``.`` and ``-`` are kept, every other character
  becomes ``_``; leading dots are dropped; an empty name, ``.`` or ``..`` becomes ``_``; Windows'
  reserved device names (CON, PRN, AUX, NUL, COM1–9, LPT1–9) get a trailing ``_``; at most 100
  characters. So a name can never hold a path separator or climb out of the folder.
- **Confinement.** Every path handed out by ``OutputFolder.path`` is resolved (symlinks and ``..``
  followed) and must lie inside the resolved output folder.
- **Inputs.** No output may be an input of the same run: the resolved paths are compared, and for files
  that exist, their device and inode (a hard link or a symlink to the input is the input). Such a
  run is refused before anything is written, with one line naming both.
- **One run at a time.** While a run writes, it holds an exclusive lock (``fcntl.flock``) on the
  folder itself (no lock file is left behind); a second run into the same folder waits for it (up to
  ``LOCK_TIMEOUT_S``) so the two runs' files never interleave. Each file is written atomically
  (``camcad.io.atomic``).
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Iterable
from pathlib import Path

from camcad.errors import CamcadError

#: the longest name safe_name returns
MAX_NAME = 100
#: how long a run waits for another run writing into the same folder (s)
LOCK_TIMEOUT_S = 120.0
_RESERVED = {"CON", "PRN", "AUX", "NUL", *(f"COM{i}" for i in range(1, 10)), *(f"LPT{i}" for i in range(1, 10))}


def safe_name(text: str) -> str:
    """A file or folder name made from ``text`` by the rule in the module docstring.

    Examples
    --------
    >>> safe_name("../../etc/passwd"), safe_name("loom group 1"), safe_name("CON"), safe_name("..")
    ('etc_passwd', 'loom_group_1', 'CON_', '_')
    """
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", str(text))
    name = re.sub(r"_+", "_", name).lstrip("._").rstrip("_") or "_"
    name = name[:MAX_NAME]
    if name in (".", ".."):
        name = "_"
    if name.split(".")[0].upper() in _RESERVED:
        name += "_"
    return name


def _identity(path: Path) -> tuple[int, int] | None:
    try:
        stat = path.stat()
    except OSError:
        return None
    return stat.st_dev, stat.st_ino


class OutputFolder:
    """Where a run writes: hands out confined paths and holds the folder's lock while the run writes.

    Parameters
    ----------
    folder : Path
        The output folder (created if missing; an existing file there is refused).
    inputs : iterable of Path
        Every file the run reads: none of them may be replaced by an output.
    where : str
        How the user named the folder (``-o``), for error messages.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> root = pathlib.Path(tempfile.mkdtemp())
    >>> with OutputFolder(root / "out") as out:
    ...     out.path("group", "profile.dxf").relative_to(out.folder).as_posix()
    'group/profile.dxf'
    """

    def __init__(self, folder: str | Path, inputs: Iterable[str | Path] = (), where: str = "-o") -> None:
        self.where = where
        folder = Path(folder)
        if folder.exists() and not folder.is_dir():
            raise CamcadError("the output folder is an existing file", str(folder),
                              "give a folder with -o (it is created if missing)")
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except FileExistsError:
            raise CamcadError("a file stands on the way to the output folder", str(folder),
                              "give another folder with -o") from None
        except OSError as err:
            raise CamcadError(f"cannot create the output folder ({err.strerror})", str(folder),
                              "give a writable folder with -o") from None
        self.folder = folder
        self._root = folder.resolve()
        # a name with a NUL byte names no file (the law's own reader refuses it with a clear line)
        self._inputs = [(Path(p), Path(p).resolve(), _identity(Path(p))) for p in inputs if "\x00" not in str(p)]
        self._lock: int | None = None

    # -- the lock ------------------------------------------------------------------------------
    def __enter__(self) -> OutputFolder:
        self.lock()
        return self

    def __exit__(self, *exc: object) -> None:
        self.unlock()

    def lock(self, timeout_s: float = LOCK_TIMEOUT_S) -> None:
        """Take the folder's exclusive lock, waiting for another run that holds it."""
        import fcntl

        if self._lock is not None:
            return
        try:  # the folder itself is locked: no lock file is left behind
            handle = os.open(self._root, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_CLOEXEC", 0))
        except OSError as err:
            raise CamcadError(f"cannot open the output folder ({err.strerror})", str(self.folder),
                              "give a readable, writable folder with -o") from None
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except OSError:
                if time.monotonic() > deadline:
                    os.close(handle)
                    raise CamcadError(f"another camcad run has been writing into the folder for over "
                                      f"{timeout_s:g} s", str(self.folder),
                                      "wait for it to finish, or write into another folder with -o") from None
                time.sleep(0.05)
        self._lock = handle

    def unlock(self) -> None:
        if self._lock is not None:
            os.close(self._lock)  # closing releases the flock
            self._lock = None

    # -- paths ---------------------------------------------------------------------------------
    def path(self, *parts: str) -> Path:
        """The path of an output inside the folder: each part a name made safe by ``safe_name``.

        Raises CamcadError when the path would replace an input of the run or (through a symlink
        already in the folder) lead outside it.
        """
        names = [safe_name(part) for part in parts]
        path = self.folder.joinpath(*names)
        self.check(path)
        return path

    def check(self, path: Path) -> Path:
        """``path`` if it lies inside the folder and is not an input; else a CamcadError."""
        resolved = path.resolve()
        if resolved != self._root and self._root not in resolved.parents:
            raise CamcadError(f"the output {path.name} would be written outside the output folder "
                              f"(to {resolved})", str(path), "remove the symlink in the output folder")
        identity = _identity(path)
        for given, real, inode in self._inputs:
            if resolved == real or (identity is not None and identity == inode):
                raise CamcadError(f"the output {path} would replace the input {given}", self.where,
                                  "write into another folder with -o (camcad never overwrites its input)")
        return path


def refuse_input(output: str | Path, inputs: Iterable[str | Path], where: str = "-o") -> Path:
    """``output`` if it is not one of ``inputs`` (resolved path, or same file by inode); else CamcadError."""
    output = Path(output)
    resolved, identity = output.resolve(), _identity(output)
    for given in inputs:
        given = Path(given)
        if resolved == given.resolve() or (identity is not None and identity == _identity(given)):
            raise CamcadError(f"the output {output} would replace the input {given}", where,
                              "give another output name (camcad never overwrites its input)")
    return output
