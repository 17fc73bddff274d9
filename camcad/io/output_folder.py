"""Where a run writes: one guard for every output, names confined to the folder, inputs never replaced.

Rules (README "Safety"):

- **Names.** A name that comes from a file (a scene's ``name``, a mechanism's key) becomes a file or
  folder name by ``safe_name``: letters, digits, ``_``, ``.`` and ``-`` are kept, every other character
  becomes ``_``; leading dots are dropped; an empty name, ``.`` or ``..`` becomes ``_``; Windows'
  reserved device names (CON, PRN, AUX, NUL, COM1–9, LPT1–9) get a trailing ``_``; at most 100
  characters. So a name can never hold a path separator or climb out of the folder. ``safe_name`` is not
  injective (``lift 1`` and ``lift_1`` give ``lift_1``): ``distinct_names`` refuses names of one run
  that would share a file name, naming both (compared without case, so the outputs also stay apart on
  a file system that ignores case).
- **Confinement.** Every path handed out by ``OutputFolder.path`` is resolved (symlinks and ``..``
  followed) and must lie inside the resolved output folder. A path the user writes inside a file (an
  edit script's ``save``) is resolved against the output folder by ``confined_path``: absolute paths,
  ``~``, ``..`` and empty parts are refused.
- **One guard for all outputs** (``check_outputs``): every file a run will write is collected and the set
  is checked *before anything is written*: no output is an input of the run (resolved paths compared,
  and for files that exist their device and inode: a hard link or a symlink to the input is the input),
  no two outputs are the same file, no output is an existing folder or lies under another output. A
  refusal is one line naming both files and what each is (``-o``, ``--plot``, an operation's save, the
  law, the script). ``OutputFolder.plan`` runs it for the names a command writes into its folder; the
  commands that write single files (``check --plot``, ``fix -o``, ``edit``) call it directly.
- **One run at a time.** While a run writes, it holds an exclusive lock (``fcntl.flock``) on the
  folder itself (no lock file is left behind); a second run into the same folder waits for it (up to
  ``LOCK_TIMEOUT_S``) so the two runs' files never interleave. Each file is written atomically
  (``camcad.io.atomic``).
- **Workers die with their run.** A pool's worker (a sweep's chunks, a scene's plots) is forked from the run;
  ``init_worker`` (a pool's initializer) closes the worker's copy of the folder's lock, so the lock is held
  by the run alone, and makes the worker end with the run: on Linux the kernel kills it when its parent
  dies (``prctl(PR_SET_PDEATHSIG, SIGKILL)``), elsewhere a thread checks its parent once a second. After
  ``kill -9`` of a run no orphan keeps the folder (``--resume``) or the CPU.
- **Interrupted runs.** From the first path it hands out until the run ends normally, the folder holds
  ``INCOMPLETE_MARK`` (a short text saying which run is writing); a run killed on the way leaves it there,
  so a folder of mixed old and new files says so. The next run into the folder (holding the lock, so no
  other run is writing) removes the temporary files an interrupted atomic write left behind
  (``.NAME.XXXXXXXX.tmp``, up to two folder levels deep) and, when it completes, the mark.
"""

from __future__ import annotations

import os
import re
import signal
import sys
import threading
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from camcad.errors import CamcadError
from camcad.io.atomic import TEMP_FILE, write_text_atomic

#: the longest name safe_name returns
MAX_NAME = 100
#: the longest name (one part of a path) a file system holds, bytes
NAME_MAX = 255
#: how long a run waits for another run writing into the same folder (s)
LOCK_TIMEOUT_S = 120.0
#: the file that marks a folder whose run has not finished (removed when it does)
INCOMPLETE_MARK = "CAMCAD-INCOMPLETE.txt"
_RESERVED = {"CON", "PRN", "AUX", "NUL", *(f"COM{i}" for i in range(1, 10)), *(f"LPT{i}" for i in range(1, 10))}
#: the lock descriptors this process holds (a forked worker closes its copies: release_inherited_locks)
_HELD_LOCKS: set[int] = set()


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


def distinct_names(names: Iterable[str], what: str = "mechanisms", where: str = "") -> dict[str, str]:
    """{name: safe_name(name)} for names that each get their own file or folder; else a CamcadError
    naming the two that would share one (compared without case).

    Examples
    --------
    >>> distinct_names(["lift", "feed 1"])
    {'lift': 'lift', 'feed 1': 'feed_1'}
    >>> distinct_names(["lift 1", "lift_1"])
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: the mechanisms 'lift 1' and 'lift_1' would both write into lift_1; rename one ...
    """
    out: dict[str, str] = {}
    seen: dict[str, str] = {}
    for name in names:
        safe = safe_name(name)
        key = safe.casefold()
        if key in seen:
            raise CamcadError(f"the {what} {_quoted(seen[key])} and {_quoted(name)} would both write into {safe}",
                              where, "rename one (names are made file names by keeping letters, digits, _ . - "
                                     "and ignoring case)")
        seen[key] = name
        out[name] = safe
    return out


def _quoted(text: str, limit: int = 40) -> str:
    text = repr(str(text))
    return text if len(text) <= limit else text[: limit - 4] + "...'"


def _identity(path: Path) -> tuple[int, int] | None:
    try:
        stat = path.stat()
    except (OSError, ValueError):
        return None
    return stat.st_dev, stat.st_ino


def is_folder(path: str | Path) -> bool:
    """True when ``path`` is an existing folder; False for anything else, a name no file system can hold (a NUL
    byte, a part longer than ``NAME_MAX``) included."""
    try:
        return Path(path).is_dir()
    except (OSError, ValueError):
        return False


def _check_name(path: Path, what: str, where: str) -> None:
    """A CamcadError for a name no file system holds: a NUL byte, or a part longer than ``NAME_MAX`` bytes."""
    text = str(path)
    if "\x00" in text:
        raise CamcadError(f"the {what} {_quoted(text)} holds a NUL byte", where, "give another name")
    for part in Path(text).parts:
        size = len(os.fsencode(part)) if "\x00" not in part else 0
        if size > NAME_MAX:
            raise CamcadError(f"a name in the {what} is {size} bytes long ({_quoted(part, 30)}), more than a file "
                              f"system holds ({NAME_MAX})", where, "give a shorter name")


def _resolved(path: Path) -> Path:
    try:
        return path.resolve()
    except (OSError, RuntimeError):  # a symlink loop: the path as written
        return Path(os.path.abspath(path))


# ---------------------------------------------------------------------------------------------
# The guard: every output of a run against every input and every other output
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Item:
    """A file of a run, and what it is to the user (``-o``, ``--plot``, ``the law``, ``operation 3 (save)``)."""

    path: Path
    role: str = ""

    def text(self) -> str:
        return f"{self.path} ({self.role})" if self.role else str(self.path)


def _items(entries: Iterable, default_role: str) -> list[Item]:
    out = []
    for entry in entries:
        if isinstance(entry, Item):
            out.append(entry)
        elif isinstance(entry, tuple):
            out.append(Item(Path(entry[0]), str(entry[1])))
        else:
            out.append(Item(Path(entry), default_role))
    return out


def check_outputs(outputs: Iterable, inputs: Iterable = (), where: str = "-o") -> list[Path]:
    """The shared guard: check every output of a run, as a set, before anything is written.

    Parameters
    ----------
    outputs : iterable of Path, (Path, role) or Item
        Every file the run will write.
    inputs : iterable of Path, (Path, role) or Item
        Every file the run reads.
    where : str
        The option that names the outputs, for the error.

    Returns
    -------
    list of Path
        The outputs, in order.

    Raises
    ------
    CamcadError
        An output that is an input (same resolved path, or for existing files the same device and inode),
        two outputs that are one file, an output under another output, an output that is an existing
        folder, or a name with a NUL byte: one line naming both files.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> law = pathlib.Path(tempfile.mkdtemp()) / "law.dxf"
    >>> _ = law.write_text("0\\nEOF\\n")
    >>> check_outputs([(law.with_suffix(".png"), "--plot")], [(law, "the law")])[0].name
    'law.png'
    >>> check_outputs([(law, "--plot")], [(law, "the law")])
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: -o: the output .../law.dxf (--plot) would replace the input .../law.dxf (the law); ...
    """
    outs = _items(outputs, "")
    ins = [(item, _resolved(item.path), _identity(item.path)) for item in _items(inputs, "")
           if "\x00" not in str(item.path)]
    files: dict[Path, Item] = {}
    folders: dict[Path, Item] = {}
    identities: dict[tuple[int, int], Item] = {}
    for out in outs:
        _check_name(out.path, "output", where)
        real = _resolved(out.path)
        identity = _identity(out.path)
        for given, resolved, inode in ins:
            if real == resolved or (identity is not None and identity == inode):
                raise CamcadError(f"the output {out.text()} would replace the input {given.text()}", where,
                                  "give another output name or folder (camcad never overwrites its input)")
        if is_folder(out.path):
            raise CamcadError(f"the output {out.text()} is an existing folder, not a file name", where,
                              "give a file name")
        other = files.get(real) or (identities.get(identity) if identity is not None else None)
        if other is not None:
            raise CamcadError(f"the outputs {other.text()} and {out.text()} are the same file", where,
                              "give each output its own name")
        if real in folders:
            raise CamcadError(f"the output {out.text()} is also the folder of the output {folders[real].text()}",
                              where, "give each output its own name")
        for parent in real.parents:
            if parent in files:
                raise CamcadError(f"the output {out.text()} would lie inside the output {files[parent].text()}",
                                  where, "give each output its own name")
            folders.setdefault(parent, out)
        files[real] = out
        if identity is not None:
            identities[identity] = out
    return [out.path for out in outs]


def confined_path(text: str, folder: Path, where: str, what: str = "path") -> Path:
    """``text`` (a relative path written in a file, e.g. an edit script's ``save``) as a path inside ``folder``.

    Absolute paths, ``~``, ``..``, empty parts, NUL and control characters are refused with one line; so
    is a path that leads out of ``folder`` through a symlink already there (``.`` parts are dropped).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> root = pathlib.Path(tempfile.mkdtemp())
    >>> confined_path("sub/law.dxf", root, "script").relative_to(root).as_posix()
    'sub/law.dxf'
    >>> confined_path("../../victim/notes.txt", root, "script, operation 3", "save path")
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: script, operation 3: the save path '../../victim/notes.txt' climbs out ...
    """
    fix = f"give a name relative to the output folder {folder}, e.g. \"law.fixed.dxf\" (use -o to choose the folder)"
    raw = str(text)
    if any(ord(ch) < 32 or ord(ch) == 127 for ch in raw):
        raise CamcadError(f"the {what} {_quoted(raw)} holds a control character", where, fix)
    if raw.startswith("~"):
        raise CamcadError(f"the {what} {_quoted(raw)} names a home folder (~)", where, fix)
    parts = raw.replace("\\", "/").split("/")
    if raw.startswith(("/", "\\")) or os.path.isabs(raw) or re.match(r"^[A-Za-z]:", raw):
        raise CamcadError(f"the {what} {_quoted(raw)} is absolute", where, fix)
    if ".." in parts:
        raise CamcadError(f"the {what} {_quoted(raw)} climbs out of the output folder (..)", where, fix)
    parts = [part for part in parts if part != "."]
    if not parts or any(part == "" for part in parts):
        raise CamcadError(f"the {what} {_quoted(raw)} has an empty part", where, fix)
    _check_name(Path(*parts), what, where)
    path = Path(folder).joinpath(*parts)
    root = _resolved(Path(folder))
    real = _resolved(path)
    if real != root and root not in real.parents:
        raise CamcadError(f"the {what} {_quoted(raw)} leads outside the output folder (to {real}) through a symlink",
                          where, fix)
    return path


# ---------------------------------------------------------------------------------------------
# The output folder
# ---------------------------------------------------------------------------------------------

class OutputFolder:
    """Where a run writes: hands out confined paths and holds the folder's lock while the run writes.

    Parameters
    ----------
    folder : Path
        The output folder (created if missing; an existing file there is refused).
    inputs : iterable of Path or (Path, role)
        Every file the run reads: none of them may be replaced by an output.
    where : str
        How the user named the folder (``-o``), for error messages.
    mark : bool
        Mark the folder as incomplete while the run writes (module docstring).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> root = pathlib.Path(tempfile.mkdtemp())
    >>> with OutputFolder(root / "out") as out:
    ...     _ = out.plan([("group", "profile.dxf"), ("report.json",)])
    ...     out.path("group", "profile.dxf").relative_to(out.folder).as_posix()
    'group/profile.dxf'
    """

    def __init__(self, folder: str | Path, inputs: Iterable = (), where: str = "-o", mark: bool = True) -> None:
        self.where = where
        folder = Path(folder)
        _check_name(folder, "output folder", where)
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
        self.inputs = [item for item in _items(inputs, "") if "\x00" not in str(item.path)]
        self._inputs = [(item, _resolved(item.path), _identity(item.path)) for item in self.inputs]
        self._lock: int | None = None
        self._mark = mark
        self._marked = False
        self.cleaned = 0

    # -- the lock ------------------------------------------------------------------------------
    def __enter__(self) -> OutputFolder:
        self.lock()
        return self

    def __exit__(self, kind, *exc: object) -> None:
        try:
            if kind is None and self._marked:
                with _suppress_os_error():
                    (self._root / INCOMPLETE_MARK).unlink()
                self._marked = False
        finally:
            self.unlock()

    def lock(self, timeout_s: float = LOCK_TIMEOUT_S) -> None:
        """Take the folder's exclusive lock, waiting for another run that holds it; then remove what an
        interrupted run left behind (its temporary files)."""
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
        _HELD_LOCKS.add(handle)
        self.cleaned = self._remove_temps()

    def unlock(self) -> None:
        if self._lock is not None:
            _HELD_LOCKS.discard(self._lock)
            os.close(self._lock)  # closing releases the flock
            self._lock = None

    @property
    def incomplete(self) -> bool:
        """True when the folder carries the mark of a run that has not finished (this one, or a killed one)."""
        return (self._root / INCOMPLETE_MARK).exists()

    def _remove_temps(self, depth: int = 2) -> int:
        """Temporary files of interrupted atomic writes in the folder and its subfolders (``depth`` levels)."""
        removed = 0
        level = [self._root]
        for _ in range(depth + 1):
            following = []
            for folder in level:
                try:
                    entries = list(os.scandir(folder))
                except OSError:
                    continue
                for entry in entries:
                    try:
                        if entry.is_dir(follow_symlinks=False):
                            following.append(Path(entry.path))
                        elif entry.is_file(follow_symlinks=False) and TEMP_FILE.match(entry.name):
                            os.unlink(entry.path)
                            removed += 1
                    except OSError:
                        continue
            level = following
        return removed

    def _set_mark(self) -> None:
        if self._marked or not self._mark:
            return
        self._marked = True
        text = (f"A camcad run (process {os.getpid()}, started {time.strftime('%Y-%m-%d %H:%M:%S')}: "
                f"{' '.join(sys.argv[:1] + [a[:80] for a in sys.argv[1:12]])[:600]}) is writing into this folder, "
                "or stopped before it finished: its files may be a mix of that run and an earlier one. "
                "Run the command again to complete them; camcad removes this file when a run completes.\n")
        try:
            write_text_atomic(self._root / INCOMPLETE_MARK, text)
        except CamcadError:
            self._marked = False

    # -- paths ---------------------------------------------------------------------------------
    def path(self, *parts: str) -> Path:
        """The path of an output inside the folder: each part a name made safe by ``safe_name``.

        Raises CamcadError when the path would replace an input of the run or (through a symlink
        already in the folder) lead outside it. The first path handed out marks the folder as incomplete
        until the run ends normally.
        """
        names = [safe_name(part) for part in parts]
        path = self.folder.joinpath(*names)
        self.check(path)
        self._set_mark()
        return path

    def plan(self, names: Iterable, roles: Sequence[str] | None = None, folders: Iterable[str] = ()) -> list[Path]:
        """Check every output the run will write into the folder, as a set, before any is written.

        Parameters
        ----------
        names : iterable of str or tuple of str
            Each output's name, or its parts (``("lift", "profile.dxf")``), made safe as ``path`` does.
        roles : sequence of str, optional
            What each output is, for the error (default: its name).
        folders : iterable of str
            Subfolders whose whole content the run writes (a sweep's ``results``): no input may lie in one.

        Returns
        -------
        list of Path
            The outputs' paths.
        """
        for name in folders:
            sub = self.folder / safe_name(name)
            self.check(sub)
            real = _resolved(sub)
            for given, resolved, _ in self._inputs:
                if real == resolved or real in resolved.parents:
                    raise CamcadError(f"the input {given.text()} lies in {sub}, a folder the run writes", self.where,
                                      "move the input, or write into another folder with -o")
        paths = []
        for name in names:
            parts = (name,) if isinstance(name, str) else tuple(name)
            path = self.folder.joinpath(*(safe_name(part) for part in parts))
            self._confine(path)
            paths.append(path)
        items = [Item(path, roles[i] if roles is not None else "") for i, path in enumerate(paths)]
        check_outputs(items, self.inputs, self.where)
        return paths

    def _confine(self, path: Path) -> Path:
        resolved = _resolved(path)
        if resolved != self._root and self._root not in resolved.parents:
            raise CamcadError(f"the output {path.name} would be written outside the output folder "
                              f"(to {resolved})", str(path), "remove the symlink in the output folder")
        return resolved

    def check(self, path: Path) -> Path:
        """``path`` if it lies inside the folder and is not an input; else a CamcadError."""
        resolved = self._confine(path)
        identity = _identity(path)
        for given, real, inode in self._inputs:
            if resolved == real or (identity is not None and identity == inode):
                raise CamcadError(f"the output {path} would replace the input {given.text()}", self.where,
                                  "write into another folder with -o (camcad never overwrites its input)")
        return path


def release_inherited_locks() -> None:
    """In a forked worker: close this process's copies of the output folders' locks, so that the lock is
    held by the run that took it alone and dies with it (a worker orphaned by a killed run cannot keep
    ``--resume`` out of the folder)."""
    for handle in list(_HELD_LOCKS):
        with _suppress_os_error():
            os.close(handle)
        _HELD_LOCKS.discard(handle)


#: prctl option: the signal this process gets when its parent dies (linux/prctl.h)
PR_SET_PDEATHSIG = 1
#: how often a worker without prctl checks that its parent is alive (s)
PARENT_POLL_S = 1.0


def die_with_parent(parent: int) -> str:
    """Arrange for this process to end when process ``parent`` (its parent) ends; returns how ("prctl" or
    "watchdog"). A process whose parent is already gone ends at once."""
    how = "watchdog"
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
                how = "prctl"
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:   # the parent died before the line above took effect
        os._exit(1)
    if how == "watchdog":
        def watch() -> None:
            while True:
                time.sleep(PARENT_POLL_S)
                if os.getppid() != parent:
                    os._exit(1)

        threading.Thread(target=watch, name="camcad-parent-watch", daemon=True).start()
    return how


def init_worker(parent: int) -> None:
    """A pool worker's initializer: release the run's folder locks and die with the run (module docstring)."""
    release_inherited_locks()
    die_with_parent(parent)


class _suppress_os_error:
    def __enter__(self):
        return self

    def __exit__(self, kind, *exc) -> bool:
        return kind is not None and issubclass(kind, OSError)


def refuse_input(output: str | Path, inputs: Iterable[str | Path], where: str = "-o") -> Path:
    """``output`` if it is not one of ``inputs`` (resolved path, or same file by inode); else CamcadError."""
    check_outputs([Path(output)], inputs, where)
    return Path(output)
