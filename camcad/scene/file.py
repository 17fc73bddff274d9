"""Scene files (TOML): one mechanism, or a group of mechanisms with their cyclogram.

Layout (docs/SCENE.md): top-level ``name``, ``description``, ``[machine]``; for one mechanism the
sections ``[law]``, ``[follower]``, ``[filter]``, ``[dynamics]``, ``[stops]``, ``[contact]`` at the top
level; for a group the same sections under ``[mechanisms.NAME]`` and one top-level ``[cyclogram]``.
Each section is validated by the module that owns it (unknown keys, missing values, wrong types
and units get a one-line error naming the file and section).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from camcad.errors import CamcadError, excerpt, nearest_name
from camcad.io.input_file import check_nesting, read_input
from camcad.scene.fields import parse_speeds

MECHANISM_SECTIONS = ("law", "follower", "linkage", "filter", "dynamics", "stops", "contact", "load", "export",
                      "compare")
#: [drive] (camcad.scene.sections.drive) is the camshaft's: one per scene, at the top level of a group scene too
TOP_LEVEL = ("name", "description", "machine", "mechanisms", "cyclogram", "drive") + MECHANISM_SECTIONS
MACHINE_KEYS = ("rpm",)


@dataclass(frozen=True)
class Mechanism:
    """One mechanism of a scene: its name and its raw (not yet parsed) sections.

    ``read_scene`` makes them; each section is parsed by its own module when the pipeline uses it.

    Attributes
    ----------
    name : str
        The mechanism's name (the scene's own name for a single-mechanism scene).
    sections : dict
        Its raw TOML tables by section name ("law", "follower", "dynamics", ...), values in the units of
        ``docs/SCENE.md``.
    prefix : str
        How its sections are written in the file ("mechanisms.lift." in a group scene, "" otherwise), for
        messages.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [machine]
    ... rpm = [300.0, 400.0]
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... ''')
    >>> scene = camcad.read_scene(folder / "cam.toml")
    >>> mechanism = scene.mechanisms[0]
    >>> mechanism.name, sorted(mechanism.sections), mechanism.prefix
    ('cam', ['law'], '')
    """

    name: str
    sections: dict
    prefix: str          # how its sections are written in the file, e.g. "mechanisms.lift." or ""

    def where(self, scene_path: Path, section: str) -> str:
        return f"{scene_path} [{self.prefix}{section}]"

    def has(self, section: str) -> bool:
        return section in self.sections


@dataclass(frozen=True)
class Scene:
    """A scene as read: its mechanisms, the machine's speeds and the cyclogram, each section raw until parsed.

    ``read_scene`` makes it; the example is there.

    Attributes
    ----------
    path : Path
        The scene file (relative law files in it are found beside it).
    name, description : str
        The scene's name and its one-line description.
    speeds_rpm : tuple of float, optional
        The machine's speeds, rpm (None when the scene gives none).
    mechanisms : tuple of Mechanism
        Its mechanisms, in file order.
    cyclogram : dict, optional
        The raw [cyclogram] section, or None.
    raw : dict
        The whole TOML document as read.
    built_laws : dict
        The laws built so far, by mechanism name (``mechanism_law``'s cache).
    from_file : bool
        False for a scene a command built from its options (``path`` then only names it).
    """
    path: Path
    name: str
    description: str
    speeds_rpm: tuple[float, ...] | None
    mechanisms: tuple[Mechanism, ...]
    cyclogram: dict | None = None
    raw: dict = field(default_factory=dict, repr=False)
    built_laws: dict = field(default_factory=dict, repr=False, compare=False)  # mechanism_law's cache
    from_file: bool = True   # False: built by a command from its options (``path`` only names it)

    @property
    def base_dir(self) -> Path:
        return self.path.parent

    def input_files(self) -> list[Path]:
        """Every file the scene reads: the scene itself and the law files its [law] sections name."""
        found = [self.path] if self.from_file else []
        for mech in self.mechanisms:
            law = mech.sections.get("law")
            if isinstance(law, dict) and isinstance(law.get("file"), str):
                found.append(self.base_dir / law["file"])
            for section in ("linkage", "load"):  # a [linkage] table of Pi, a [load] table of forces
                table = mech.sections.get(section)
                if isinstance(table, dict) and isinstance(table.get("file"), str):
                    found.append(self.base_dir / table["file"])
        return found

    def mechanism(self, name: str) -> Mechanism:
        for mech in self.mechanisms:
            if mech.name == name:
                return mech
        raise CamcadError(f"no mechanism named {excerpt(name)}", str(self.path),
                          nearest_name(name, [m.name for m in self.mechanisms]).replace("valid keys", "mechanisms"))


#: the largest scene file read (bytes): a scene is a page of settings, and Python's TOML parser takes
#: about 0.5 s per MB, so a runaway file is refused before it is parsed
MAX_SCENE_BYTES = 1 << 20


def read_toml(path: Path) -> dict:
    """The TOML document; a missing file, not a regular file (a FIFO, a device), a file over
    ``MAX_SCENE_BYTES``, bad encoding, a syntax error or tables and arrays nested deeper than
    ``input_file.MAX_NESTING`` is a one-line CamcadError."""
    path = Path(path)
    if not path.exists():
        raise CamcadError("no such scene file", str(path), "check the path")
    try:
        size = path.stat().st_size
    except OSError:
        size = 0
    if size > MAX_SCENE_BYTES:
        raise CamcadError(f"a scene file of {size / 1e6:.1f} MB is too large (at most {MAX_SCENE_BYTES >> 20} MB)",
                          str(path), "put long tables in a law file (.csv) and name it with [law] file = \"...\"")
    raw = read_input(path, "a scene file (TOML)", MAX_SCENE_BYTES)
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except tomllib.TOMLDecodeError as err:
        raise CamcadError(f"not valid TOML ({' '.join(str(err).split())})", str(path),
                          "fix the syntax at that line") from None
    except UnicodeDecodeError:
        raise CamcadError("not a UTF-8 text file", str(path), "save the scene as UTF-8 text") from None
    except RecursionError:   # arrays or inline tables nested hundreds deep
        raise CamcadError("tables and arrays nest deeper than camcad reads", str(path), "flatten the file") from None
    check_nesting(data, str(path))
    return data


def read_scene(path: str | Path) -> Scene:
    """Read a scene file (TOML) and check its structure: sections, names, the machine's speeds.

    Each section's content (keys, types, units) is checked by its own parser when the pipeline uses
    it (``docs/SCENE.md`` lists every key with its unit: angles deg, lengths mm, speeds rpm, forces N,
    stresses MPa, masses kg, frequencies Hz).

    Parameters
    ----------
    path : str or Path
        The scene file (.toml); relative law files in it are found beside it.

    Returns
    -------
    Scene
        ``name``, ``description``, ``speeds_rpm`` (rpm, None when the scene gives no speed),
        ``mechanisms`` (each with its raw sections), ``cyclogram`` (the raw section or None).

    Raises
    ------
    CamcadError
        A file that cannot be read or is not TOML, an unknown section or key (with the nearest valid
        one), a value of the wrong type.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... [follower]
    ... type = "roller"
    ... base_radius = 40.0
    ... roller_radius = 10.0
    ... ''')
    >>> scene = camcad.read_scene(folder / "cam.toml")
    >>> scene.name, [mechanism.name for mechanism in scene.mechanisms], scene.speeds_rpm
    ('cam', ['cam'], None)
    """
    path = Path(path)
    return scene_from_dict(read_toml(path), path)


def scene_from_dict(raw: dict, path: str | Path, from_file: bool = True) -> Scene:
    """A scene from the tables of a TOML document (``raw``); ``path`` names it in messages and, when
    ``from_file``, is the file it was read from (relative law files are found beside it). A scene built
    by a command from its options has ``from_file=False`` and absolute law files."""
    path = Path(path)
    where = str(path)
    for key in raw:
        if key not in TOP_LEVEL:
            if key == "groups":   # a machine of groups (camcad.scene.machine)
                raise CamcadError("this is a machine scene ([groups.NAME])", where,
                                  "run it with camcad machine; camcad profile takes one mechanism or one group")
            raise CamcadError(f"unknown section or key '{key}'", where, nearest_name(key, list(TOP_LEVEL)))
    name = raw.get("name", path.stem)
    if not isinstance(name, str) or not name.strip():
        raise CamcadError(f"'name' must be text, got {excerpt(name)}", where, 'write name = "my_cam"')
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise CamcadError(f"'description' must be text, got {excerpt(description)}", where, 'write description = "..."')
    speeds = None
    machine = raw.get("machine")
    if machine is not None:
        if not isinstance(machine, dict):
            raise CamcadError("[machine] must be a table", where, "write [machine] with rpm = ...")
        for key in machine:
            if key not in MACHINE_KEYS:
                raise CamcadError(f"unknown key '{key}'", f"{where} [machine]", nearest_name(key, list(MACHINE_KEYS)))
        if "rpm" in machine:
            speeds = tuple(parse_speeds(machine["rpm"], f"{where} [machine] rpm"))
    mechanisms = _mechanisms(raw, path)
    cyclogram = raw.get("cyclogram")
    if cyclogram is not None and not isinstance(cyclogram, dict):
        raise CamcadError("[cyclogram] must be a table", where, "write [cyclogram] with [[cyclogram.operations]]")
    return Scene(path, name.strip(), description, speeds, mechanisms, cyclogram, raw, from_file=from_file)


def _mechanisms(raw: dict, path: Path) -> tuple[Mechanism, ...]:
    where = str(path)
    top = [key for key in MECHANISM_SECTIONS if key in raw]
    if "mechanisms" in raw:
        if top:
            raise CamcadError(f"[{top[0]}] at the top level of a group scene", where,
                              f"move it under [mechanisms.NAME.{top[0]}]")
        group = raw["mechanisms"]
        if not isinstance(group, dict) or not group:
            raise CamcadError("[mechanisms] must hold [mechanisms.NAME] tables", where,
                              "write each mechanism as [mechanisms.NAME] with its [law], [follower], ...")
        found = []
        for name, sections in group.items():
            if not isinstance(sections, dict):
                raise CamcadError(f"mechanisms.{name} must be a table", where,
                                  f"write [mechanisms.{name}.law], [mechanisms.{name}.follower], ...")
            for key in sections:
                if key not in MECHANISM_SECTIONS:
                    raise CamcadError(f"unknown section '{key}'", f"{where} [mechanisms.{name}]",
                                      nearest_name(key, list(MECHANISM_SECTIONS)).replace("keys", "sections"))
            found.append(Mechanism(str(name), dict(sections), f"mechanisms.{name}."))
        return tuple(found)
    if not top:
        if isinstance(raw.get("cyclogram"), dict):
            return ()  # a network on its own: a cyclogram of operations without mechanisms
        raise CamcadError("the scene describes no mechanism", where,
                          "add a [law] section (and [follower]), or [mechanisms.NAME] tables")
    name = raw.get("name", path.stem)
    return (Mechanism(str(name), {key: raw[key] for key in top}, ""),)
