"""The design space of a sweep: which scene keys vary, over which values, and design ids.

A sweep varies keys of a scene (TOML tables, ``camcad.scene.file``), each written as its path in the file:

- ``SECTION.KEY`` for a single-mechanism scene (``follower.base_radius``, ``contact.width``, ``law.standard``),
  ``mechanisms.NAME.SECTION.KEY`` for a mechanism of a group, ``machine.rpm`` (one speed per design) and
  ``cyclogram.KEY`` for the cyclogram's scalar keys (``cycle_deg``, ``start_deg``);
- ``law.phases.LABEL`` (``mechanisms.NAME.law.phases.LABEL`` in a group) for the phase angle of one motion of
  a standard law: LABEL is ``rise``, ``return``, ``rise_2``, ``return_2``, … (the labels of the report's
  ``phase_limits``); the motion keeps its start and shape, and the next dwell (else the previous one) takes up
  the change, as ``camcad.cyclogram.retime.stretch_phase`` does when a cyclogram retimes a law.

Each key takes one SPEC:

- a range ``A:B:STEP``: A, A + STEP, …, up to B (B included when it falls on the grid, to 1e-9 of a step);
  each value is computed as A + i·STEP and rounded to 12 significant digits (no accumulated round-off);
- a list ``a,b,c`` (numbers, names or true/false, as the key's type says);
- a distribution ``normal(mu,sigma)`` or ``uniform(a,b)`` for a Monte-Carlo with ``samples`` draws.

Range and list keys form a grid (their Cartesian product, the last key varying fastest); distribution keys
are drawn ``samples`` times for every grid point. Design ``id`` = grid index × samples + sample. Draw ``j`` of
distribution key ``k`` comes from its own random stream (``numpy.random.default_rng([seed, k, j])``): a
design's values depend only on (seed, its id), never on which worker or chunk computes it, and every grid
point sees the same draws (common random numbers, so grid points are compared on equal terms).
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camcad.cyclogram.retime import format_phases, stretch_phase
from camcad.errors import CamcadError, nearest_name
from camcad.law.phases import parse_phases
from camcad.law.standard import shape_named
from camcad.scene.fields import parse_speeds, read_table

#: significant digits of a range's values (A + i·STEP without the round-off of the binary step)
RANGE_DIGITS = 12
#: the most designs one sweep may hold (checked from the SPECs' counts before any value is made: a range's
#: values are computed when a design asks for them, never stored)
MAX_DESIGNS = 1_000_000
#: the values of a range checked by the scene's parser before the sweep runs (all of them up to this many;
#: past it, both ends and evenly spaced ones: the checks are ranges and types, so the ends decide)
CHECKED_VALUES = 1000
#: section name → (module, name of its field list) of the scene's parsers
SECTION_FIELDS = {
    "law": ("camcad.scene.sections.law", "law_fields"),
    "follower": ("camcad.scene.sections.follower", "FOLLOWER_FIELDS"),
    "filter": ("camcad.scene.sections.filter", "FILTER_FIELDS"),
    "dynamics": ("camcad.scene.sections.dynamics", "DYNAMICS_FIELDS"),
    "stops": ("camcad.scene.sections.stops", "STOPS_FIELDS"),
    "contact": ("camcad.scene.sections.contact", "CONTACT_FIELDS"),
    "cyclogram": ("camcad.scene.sections.cyclogram", "CYCLOGRAM_FIELDS"),
}
#: field kinds a sweep can vary (lists and tables cannot)
SCALAR_KINDS = ("float", "int", "str", "bool", "number_or_list")
#: keys a sweep does not vary (they choose files or a whole structure, not a figure)
NOT_VARIED = {"law.file": "a sweep does not vary the law's file", "law.phases": "vary one phase angle with "
              "law.phases.rise (or return, rise_2, ...)", "follower.auto_base_radius": "it is a switch, not a figure"}


def section_fields(section: str) -> list:
    """The ``camcad.scene.fields.Field`` list of a scene section (``law``, ``follower``, …)."""
    import importlib

    module, name = SECTION_FIELDS[section]
    found = getattr(importlib.import_module(module), name)
    return found() if callable(found) else found


# --------------------------------------------------------------------------------------------
# keys
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Key:
    """A scene key a sweep varies.

    path:    the key as written (``follower.base_radius``), also its column name in the results.
    tables:  where its table sits in the scene's TOML tables, e.g. ("mechanisms", "lift", "follower").
    name:    the key inside that table (``base_radius``), or the phase label for a phase angle.
    kind:    "float", "int", "str" or "bool".
    unit:    its unit (deg for a phase angle).
    phase:   True for a phase angle of ``law.phases``.
    field:   the scene parser's Field (None for machine.rpm and phase angles).
    """

    path: str
    tables: tuple[str, ...]
    name: str
    kind: str
    unit: str = ""
    phase: bool = False
    field: Any = None

    @property
    def numeric(self) -> bool:
        return self.kind in ("float", "int")


def valid_keys(tables: dict) -> list[str]:
    """Every key of the scene ``tables`` a sweep can vary (the sections the scene has)."""
    out = ["machine.rpm"]
    for prefix, sections in _mechanism_tables(tables):
        for section in sections:
            if section not in SECTION_FIELDS or not isinstance(sections[section], dict):
                continue
            for f in section_fields(section):
                if f.kind in SCALAR_KINDS and f"{section}.{f.name}" not in NOT_VARIED:
                    out.append(f"{prefix}{section}.{f.name}")
            if section == "law" and isinstance(sections["law"].get("phases"), str):
                out.extend(f"{prefix}law.phases.{label}" for label in _motion_labels(sections["law"]["phases"]))
    if isinstance(tables.get("cyclogram"), dict):
        out.extend(f"cyclogram.{f.name}" for f in section_fields("cyclogram") if f.kind in SCALAR_KINDS)
    return out


def _mechanism_tables(tables: dict) -> list[tuple[str, dict]]:
    """(prefix, sections) of each mechanism: ("", tables) for a single one, ("mechanisms.NAME.", …) in a group."""
    group = tables.get("mechanisms")
    if isinstance(group, dict):
        return [(f"mechanisms.{name}.", sections) for name, sections in group.items() if isinstance(sections, dict)]
    return [("", tables)]


def _motion_labels(phases_text: str) -> list[str]:
    kinds = [item.split(":")[-1].strip().lower() for item in phases_text.split(",") if item.strip()]
    counts: dict[str, int] = {}
    labels = []
    for kind in kinds:
        if kind in ("rise", "return"):
            counts[kind] = counts.get(kind, 0) + 1
            labels.append(kind if counts[kind] == 1 else f"{kind}_{counts[kind]}")
    return labels


def resolve_key(path: str, tables: dict, where: str = "--vary") -> Key:
    """The ``Key`` a ``--vary`` path names in the scene ``tables``; a one-line CamcadError naming the nearest
    valid key when the scene has no such key.

    Examples
    --------
    >>> from camcad.scene.default import default_tables
    >>> key = resolve_key("follower.base_radius", default_tables())
    >>> key.tables, key.name, key.kind, key.unit
    (('follower',), 'base_radius', 'float', 'mm')
    >>> resolve_key("law.phases.rise", default_tables()).phase
    True
    """
    path = path.strip()
    valid = valid_keys(tables)
    parts = path.split(".")
    for reserved, why in NOT_VARIED.items():
        if path == reserved or path.endswith("." + reserved):
            raise CamcadError(f"cannot vary {path}: {why}", where, "vary a figure of the scene, e.g. "
                              "follower.base_radius")
    if path == "machine.rpm":
        return Key(path, ("machine",), "rpm", "float", "rpm")
    if parts[0] == "cyclogram" and len(parts) == 2 and path in valid:
        f = _field(section_fields("cyclogram"), parts[1])
        return Key(path, ("cyclogram",), parts[1], _kind(f), f.unit, field=f)
    prefix: tuple[str, ...] = ()
    rest = parts
    if isinstance(tables.get("mechanisms"), dict) and len(parts) >= 3 and parts[0] == "mechanisms":
        prefix, rest = ("mechanisms", parts[1]), parts[2:]
    if path not in valid:
        section = rest[0] if rest else ""
        owner = tables
        for name in prefix:
            owner = owner.get(name, {}) if isinstance(owner, dict) else {}
        if section in SECTION_FIELDS and section != "cyclogram" and isinstance(owner, dict) \
                and section not in owner and len(rest) == 2:
            place = ".".join(prefix + (section,))
            raise CamcadError(f"the scene has no [{place}] section to vary {path} in", where,
                              f"add [{place}] to the scene, or vary a key it has: {_few(valid)}")
        if len(rest) == 3 and rest[:2] == ["law", "phases"] and not isinstance(owner.get("law", {}).get("phases"),
                                                                               str):
            raise CamcadError(f"cannot vary {path}: the law has no phases text", where,
                              "vary phase angles of a standard law (with phases = \"...\" in [law])")
        raise CamcadError(f"unknown key '{path}'", where, _nearest(path, valid))
    if len(rest) == 3:  # law.phases.LABEL
        law = _table_at(tables, prefix + ("law",))
        if law.get("file") is not None:
            raise CamcadError(f"cannot vary {path}: the phase angles of a drawn law are not varied", where,
                              "vary them on a standard law ([law] standard), or retime the drawing first")
        return Key(path, prefix + ("law",), rest[2], "float", "deg", phase=True)
    f = _field(section_fields(rest[0]), rest[1])
    return Key(path, prefix + (rest[0],), rest[1], _kind(f), f.unit, field=f)


def _few(valid: list[str], count: int = 6) -> str:
    shown = ", ".join(valid[:count])
    return shown + (", ..." if len(valid) > count else "")


def _nearest(path: str, valid: list[str]) -> str:
    text = nearest_name(path, valid)
    if text.startswith("did you mean"):
        return text.split("?")[0] + "?"
    return f"keys of this scene: {_few(valid)}"


def _field(fields: list, name: str):
    for f in fields:
        if f.name == name:
            return f
    raise KeyError(name)


def _kind(f) -> str:
    return "float" if f.kind == "number_or_list" else f.kind


def _table_at(tables: dict, path: tuple[str, ...]) -> dict:
    table = tables
    for name in path:
        table = table[name]
    return table


# --------------------------------------------------------------------------------------------
# specs
# --------------------------------------------------------------------------------------------

class RangeValues(Sequence):
    """The values A + i·STEP (i = 0 … count − 1) of a range, each rounded to ``RANGE_DIGITS`` significant digits,
    computed when asked for: a range of 10⁸ values takes no memory.

    Examples
    --------
    >>> values = RangeValues(30.0, 0.1, 11)
    >>> len(values), values[1], values[-1], values[-3:]
    (11, 30.1, 31.0, (30.8, 30.9, 31.0))
    """

    def __init__(self, start: float, step: float, count: int, integer: bool = False) -> None:
        self.start, self.step, self.length, self.integer = float(start), float(step), int(count), bool(integer)

    def __len__(self) -> int:
        return self.length

    def __getitem__(self, index):
        if isinstance(index, slice):
            return tuple(self[i] for i in range(*index.indices(self.length)))
        i = int(index)
        if i < 0:
            i += self.length
        if not 0 <= i < self.length:
            raise IndexError(index)
        value = _round(self.start + i * self.step)
        return int(value) if self.integer else value

    def __eq__(self, other) -> bool:
        if isinstance(other, RangeValues):
            return (self.start, self.step, self.length, self.integer) == (other.start, other.step, other.length,
                                                                        other.integer)
        return isinstance(other, (tuple, list)) and len(other) == self.length and tuple(self) == tuple(other)

    def __hash__(self) -> int:
        return hash((self.start, self.step, self.length, self.integer))

    def __repr__(self) -> str:
        return f"RangeValues({self.start!r}, {self.step!r}, {self.length!r})"


@dataclass(frozen=True)
class Spec:
    """The values of one varied key: a grid (``values``) or a distribution (``dist``, ``params``)."""

    key: Key
    text: str
    values: Sequence = ()
    dist: str | None = None
    params: tuple[float, ...] = ()

    @property
    def random(self) -> bool:
        return self.dist is not None

    def draw(self, seed: int, index: int, sample: int) -> float:
        """Draw ``sample`` of this key, the ``index``-th key of the sweep (its own random stream)."""
        rng = np.random.default_rng([int(seed), int(index), int(sample)])
        if self.dist == "normal":
            return float(rng.normal(self.params[0], self.params[1]))
        return float(rng.uniform(self.params[0], self.params[1]))


_DIST = re.compile(r"^\s*(normal|uniform)\s*\((.*)\)\s*$", re.IGNORECASE)


def parse_spec(key: Key, text: str, where: str = "--vary") -> Spec:
    """The values ``text`` gives ``key``: ``A:B:STEP``, ``a,b,c`` or ``normal(mu,sigma)`` / ``uniform(a,b)``.

    Each grid value is checked as the scene's parser checks the key (type, range, choices), so a value
    the scene would refuse is refused here, before any design runs.

    Examples
    --------
    >>> from camcad.scene.default import default_tables
    >>> key = resolve_key("follower.base_radius", default_tables())
    >>> parse_spec(key, "30:31:0.1").values[-3:]
    (30.8, 30.9, 31.0)
    >>> parse_spec(key, "normal(50, 0.01)").params
    (50.0, 0.01)
    """
    where = f"{where} {key.path}"
    text = text.strip()
    if not text:
        raise CamcadError("no values given", where, f"write {key.path}=A:B:STEP, a,b,c or normal(mu,sigma)")
    match = _DIST.match(text)
    if match:
        if not key.numeric or key.kind == "int":
            raise CamcadError(f"{key.path} is {_kind_text(key)}: it cannot follow a distribution", where,
                              "give a list of values instead")
        name = match.group(1).lower()
        params = _numbers(match.group(2), where, f"{name}(a,b)")
        if len(params) != 2:
            raise CamcadError(f"{name}() takes two numbers, got {len(params)}", where,
                              "write normal(mu,sigma) or uniform(a,b)")
        if name == "normal" and not params[1] > 0:
            raise CamcadError(f"normal() needs sigma > 0, got {params[1]:g}", where, "write normal(mu,sigma)")
        if name == "uniform" and not params[1] > params[0]:
            raise CamcadError(f"uniform(a,b) needs a < b, got {params[0]:g}, {params[1]:g}", where,
                              "write uniform(low,high)")
        return Spec(key, text, dist=name, params=tuple(params))
    if ":" in text:
        if not key.numeric:
            raise CamcadError(f"{key.path} is {_kind_text(key)}: it takes a list, not a range", where,
                              "write a,b,c")
        parts = _numbers(text.replace(":", ","), where, "A:B:STEP")
        if len(parts) != 3:
            raise CamcadError(f"range {_excerpt(text)!r} is not A:B:STEP", where, "write e.g. 30:80:0.5")
        start, stop, step = parts
        if not step > 0:
            raise CamcadError(f"range step must be positive, got {step:g}", where, "write A:B:STEP with STEP > 0")
        if stop < start:
            raise CamcadError(f"range {start:g}:{stop:g} runs backwards", where, "write the smaller end first")
        span = (stop - start) / step + 1e-9
        if not span < MAX_DESIGNS:
            raise CamcadError(f"range gives {span + 1:.3g} values, more designs than a sweep runs ({MAX_DESIGNS:,})",
                              where, "use a larger step, or split the sweep")
        count = math.floor(span) + 1
        if key.kind == "int" and any(v != int(v) for v in (start, step)):
            raise CamcadError(f"{key.path} is a whole number: the range gives fractions", where,
                              "give whole-number ends and step")
        values: Sequence = RangeValues(start, step, count, integer=key.kind == "int")
        for index in _checked_indices(count):
            _check_value(key, values[index], where)
        return Spec(key, text, values=values)
    else:
        items = [item.strip() for item in text.split(",")]
        if any(not item for item in items):
            raise CamcadError(f"empty item in the list {_excerpt(text)!r}", where, "write a,b,c")
        values = tuple(_typed(item, key, where) for item in items)
        if len(set(values)) != len(values):
            raise CamcadError("a value is listed twice", where, "list each value once")
    for value in values:
        _check_value(key, value, where)
    return Spec(key, text, values=values)


def _checked_indices(count: int) -> list[int]:
    """Which values of a range of ``count`` the scene's parser checks (``CHECKED_VALUES``)."""
    if count <= CHECKED_VALUES:
        return list(range(count))
    return sorted(set(np.linspace(0, count - 1, CHECKED_VALUES).round().astype(int).tolist()))


def _kind_text(key: Key) -> str:
    return {"str": "a name", "bool": "true or false", "int": "a whole number"}.get(key.kind, "a number")


def _excerpt(text: str, limit: int = 40) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _round(value: float) -> float:
    return float(f"{value:.{RANGE_DIGITS}g}")


def _numbers(text: str, where: str, form: str) -> list[float]:
    out = []
    for item in text.split(","):
        try:
            value = float(item.strip())
        except ValueError:
            raise CamcadError(f"{_excerpt(item.strip())!r} is not a number", where, f"write {form}") from None
        if not math.isfinite(value):
            raise CamcadError(f"{item.strip()!r} is not finite", where, f"write {form} with finite numbers")
        out.append(value)
    return out


def _typed(item: str, key: Key, where: str):
    if key.kind == "float":
        return _numbers(item, where, "a,b,c (numbers)")[0]
    if key.kind == "int":
        try:
            return int(item)
        except ValueError:
            raise CamcadError(f"{_excerpt(item)!r} is not a whole number", where, "write a,b,c (whole numbers)") \
                from None
    if key.kind == "bool":
        if item.lower() not in ("true", "false"):
            raise CamcadError(f"{_excerpt(item)!r} is not true or false", where, "write true,false")
        return item.lower() == "true"
    return item


def _check_value(key: Key, value, where: str) -> None:
    """The scene parser's own check of one value of ``key`` (type, range, choices)."""
    if key.phase:
        if not value > 0:
            raise CamcadError(f"phase angle must be positive, got {value:g} deg", where, "give angles > 0")
        return
    if key.path.endswith("machine.rpm"):
        parse_speeds(value, where)
        return

    f = key.field
    if key.tables[-1] == "law" and key.name in ("standard", "return_standard"):
        try:
            shape_named(value)
        except KeyError as err:
            raise CamcadError(str(err.args[0]), where, "pick one of the names listed") from None
    read_table({f.name: value}, [f], where)


# --------------------------------------------------------------------------------------------
# the space
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DesignSpace:
    """The designs of a sweep: the grid of the range and list keys × ``samples`` draws of the distributions.

    Parameters
    ----------
    specs : tuple of Spec
        The varied keys in the order given (the last grid key varies fastest).
    samples : int
        Draws of the distribution keys per grid point (1 without distributions).
    seed : int
        Seed of the draws.
    """

    specs: tuple[Spec, ...]
    samples: int = 1
    seed: int = 0
    shape: tuple[int, ...] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "shape", tuple(len(s.values) for s in self.grid_specs))

    @property
    def grid_specs(self) -> tuple[Spec, ...]:
        return tuple(s for s in self.specs if not s.random)

    @property
    def grid_size(self) -> int:
        return int(math.prod(self.shape)) if self.shape else 1

    @property
    def size(self) -> int:
        """Number of designs."""
        return self.grid_size * self.samples

    def values(self, design: int) -> dict[str, Any]:
        """{key path: value} of design ``design`` (0 ≤ design < size).

        Examples
        --------
        >>> from camcad.scene.default import default_tables
        >>> t = default_tables()
        >>> space = DesignSpace((parse_spec(resolve_key("follower.base_radius", t), "30:32:1"),
        ...                      parse_spec(resolve_key("law.standard", t), "cycloidal,harmonic")))
        >>> space.size, space.values(3)
        (6, {'follower.base_radius': 31.0, 'law.standard': 'harmonic'})
        """
        if not 0 <= design < self.size:
            raise IndexError(design)
        grid, sample = divmod(int(design), self.samples)
        out: dict[str, Any] = {}
        index = np.unravel_index(grid, self.shape) if self.shape else ()
        grid_specs = iter(zip(self.grid_specs, index))
        for number, spec in enumerate(self.specs):
            if spec.random:
                out[spec.key.path] = spec.draw(self.seed, number, sample)
            else:
                s, i = next(grid_specs)
                out[spec.key.path] = s.values[int(i)]
        return out


def build_space(tables: dict, vary: list[str], samples: int | None = None, seed: int = 0) -> DesignSpace:
    """The design space of ``--vary KEY=SPEC`` texts on the scene ``tables``.

    Raises a one-line CamcadError for an unknown key, a key given twice, a bad SPEC, a distribution without
    ``samples`` or ``samples`` without a distribution.
    """
    if not vary:
        raise CamcadError("nothing to vary", "--vary", "give --vary KEY=SPEC, e.g. --vary follower.base_radius=30:80:1")
    specs = []
    seen = set()
    for text in vary:
        if "=" not in text:
            raise CamcadError(f"{_excerpt(text)!r} is not KEY=SPEC", "--vary",
                              "write e.g. --vary follower.base_radius=30:80:0.5")
        path, spec_text = text.split("=", 1)
        key = resolve_key(path, tables)
        if key.path in seen:
            raise CamcadError(f"{key.path} is varied twice", "--vary", "give each key once")
        seen.add(key.path)
        specs.append(parse_spec(key, spec_text))
    random = any(s.random for s in specs)
    if random and samples is None:
        raise CamcadError("a distribution needs the number of draws", "--vary", "add --samples N (and --seed S)")
    if not random and samples not in (None, 1):
        raise CamcadError("--samples without a distribution", "--samples",
                          "vary a key with normal(mu,sigma) or uniform(a,b), or drop --samples")
    if samples is not None and samples < 1:
        raise CamcadError(f"--samples must be at least 1, got {samples}", "--samples", "give --samples N with N >= 1")
    size = math.prod(len(s.values) for s in specs if not s.random) * (samples or 1)
    if size > MAX_DESIGNS:
        raise CamcadError(f"the sweep holds {size:.3g} designs, more than a sweep runs ({MAX_DESIGNS:,})", "--vary",
                          "use coarser ranges or fewer draws, or split the sweep")
    space = DesignSpace(tuple(specs), samples or 1, int(seed))
    return space


# --------------------------------------------------------------------------------------------
# a design's scene
# --------------------------------------------------------------------------------------------

def apply_values(tables: dict, keys: dict[str, Key], values: dict[str, Any]) -> dict:
    """A copy of the scene ``tables`` with the design's ``values`` ({key path: value}) written in.

    Phase angles are applied last, in the order given, each on the phases the previous one left
    (``camcad.cyclogram.retime.stretch_phase``: the motion keeps its start, a neighbouring dwell takes up the
    change); a phase that cannot be made that wide raises CamcadError.

    Examples
    --------
    >>> from camcad.scene.default import default_tables
    >>> t = default_tables()
    >>> key = resolve_key("law.phases.rise", t)
    >>> apply_values(t, {key.path: key}, {key.path: 90.0})["law"]["phases"]
    '0:90:rise,90:180:dwell,180:300:return,300:360:dwell'
    """
    out = copy.deepcopy(tables)
    phases = []
    for path, value in values.items():
        key = keys[path]
        if key.phase:
            phases.append((key, value))
            continue
        table = out
        for name in key.tables:
            table = table.setdefault(name, {})
        table[key.name] = value
    for key, width in phases:
        law = _table_at(out, key.tables)
        law["phases"] = stretched_phases(law["phases"], key.name, float(width), float(law.get("cycle", 360.0)),
                                         key.path)
    return out


def stretched_phases(text: str, label: str, width_deg: float, cycle_deg: float = 360.0, where: str = "phases") -> str:
    """The phases text with motion ``label`` (``rise``, ``return``, ``rise_2``, …) made ``width_deg`` wide."""
    phases = [(math.degrees(p.start), math.degrees(p.end), p.kind) for p in parse_phases(text, cycle_deg, where)]
    labels = {lab: i for i, lab in _labelled(phases)}
    if label not in labels:
        raise CamcadError(f"the law has no motion {label!r}", where, f"use one of {', '.join(labels)}")
    try:
        stretched = stretch_phase(phases, labels[label], width_deg, cycle_deg)
    except CamcadError as err:
        raise CamcadError(f"{label} cannot be made {width_deg:g} deg wide: no neighbouring dwell is wide enough",
                          where, "narrow the range, or give the law a longer dwell next to it") from err
    return format_phases([(_round(a), _round(b), k) for a, b, k in stretched])


def _labelled(phases) -> list[tuple[int, str]]:
    counts: dict[str, int] = {}
    out = []
    for index, (_, _, kind) in enumerate(phases):
        if kind == "dwell":
            continue
        counts[kind] = counts.get(kind, 0) + 1
        out.append((index, kind if counts[kind] == 1 else f"{kind}_{counts[kind]}"))
    return out
