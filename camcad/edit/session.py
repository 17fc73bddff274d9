"""The editor's model: a drawn acceleration law, the operations on it, undo/redo, corrections, saving.

No matplotlib here: the view (``camcad.edit.view``) only turns mouse and key events into the
operations below, and a script (``--script EDITS.json``) applies the same operations headless.

Units at the interface (operations, script, tables): the cam angle in **degrees of the cycle**
(0 … ``--cycle``), the acceleration in the **input's y units** (what the drawing or table holds;
``loaded.y_scale`` turns them into the law's mm/rad², as ``camcad fix --move`` does). Inside, the
law is the library's ``PiecewiseLinearLaw`` (θ in rad, a in mm/rad²).

Operations (each a JSON object with ``"op"`` and its fields; ``OPERATIONS`` lists the fields):

- ``move``: the vertex nearest ``x_deg`` gets the ordinate ``y``; with ``to_x_deg`` it also moves in
  angle (a jump's two ends move together), clamped between its neighbours: it may join a single
  neighbour to make a jump, never a jump that already has two ends nor one at the cycle's ends.
  ``end`` ("left"/"right") picks one end of a jump (default the left one, the value arriving from
  the left).
- ``move_lobe``: the lobe (the run of consecutive vertices with the sign of the vertex nearest
  ``x_deg``) is scaled so that vertex reaches ``y`` — the source's option (b) for dense curves,
  where one vertex barely changes the balance. A lobe is not dragged through the axis: a ``y`` of
  the other sign flattens it onto the axis.
- ``move_extrema``: the extremum group of that lobe (its vertices of largest |a|, equal within
  1e-9) is set to ``y`` (the source's option b: equal extrema move together).
- ``insert`` (``x_deg`` strictly inside the cycle, not on an existing vertex), ``delete`` (not the
  first or last vertex, never below 3 vertices), ``jump`` (the vertex gets a twin at the same angle
  with ordinate ``y``, default its own), ``unjump`` (a jump's ends merge into one vertex at their
  mean ordinate).
- ``move_phase``: the phase boundary nearest ``from_deg`` (within 1°) moves to ``to_deg``; the two
  phases on either side are stretched linearly in angle with the ordinates kept (the source's
  option f). ``detect_phases``: the phases are found again from the edited law.
- ``correct``: a correction mode of ``camcad fix`` (``balance.MODES``) on the law, optionally
  limited to ``segment`` [A, B] (deg): mode ``segment`` takes it as its range, every other mode
  holds the vertices outside it. Optional ``method``, ``step_deg``, ``max_stretch`` as in ``fix``.
- ``undo``, ``redo`` (an undo with nothing to undo is an error in a script, a message in the window),
  ``save`` (``path``: ``.dxf`` a corrected copy of the drawing exactly as ``fix`` writes it, a table
  suffix such as ``.csv`` a table, ``.json`` the edit script; the path is relative to the output folder
  (``-o``'s folder, else the input's) and confined to it: absolute paths, ``~`` and ``..`` are refused;
  no save may replace an input — the law, the script, a scene's files — or another output of the run).

Undo works per gesture: a drag is one step (``begin_gesture``/``end_gesture``), however many
mouse events it took. Every state is an immutable law, so undo restores the exact arrays.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.balance import MODES, BalanceReport, Correction, check, correct, difference_norms
from camcad.balance.conditions import DEFAULT_TOL, valid_tol
from camcad.errors import CamcadError
from camcad.io.atomic import write_text_atomic
from camcad.io.input_file import check_json_nesting, decode_text, read_input
from camcad.io.law_record import LawRecord
from camcad.io.law_write import write_corrected
from camcad.io.output_folder import check_outputs, confined_path
from camcad.io.table_read import TABLE_SUFFIXES
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.phases import detect_phases, zero_threshold
from camcad.law.source import LoadedLaw, VertexMap, load_law
from camcad.profile import CamGeometry, Follower

#: how many undo steps are kept (each a law; laws that differ only in ordinates share their angles)
MAX_UNDO = 200
#: a phase keeps at least this width when its boundary is dragged (deg)
MIN_PHASE_DEG = 0.01
#: a vertex dragged in angle stops this far (deg) from a neighbour it may not join in a jump
X_GAP_DEG = 1e-6
#: ``move_phase`` finds the boundary within this distance of ``from_deg`` (deg)
PHASE_PICK_DEG = 1.0
#: the largest edit script read (bytes) and the most operations it may hold (a hand-made script has tens)
MAX_SCRIPT_BYTES = 10 * 1024 * 1024
MAX_OPERATIONS = 2_000

NUMBER, TEXT, PAIR, END = "number", "text", "pair", "end"

#: every operation: its fields, (kind, required)
OPERATIONS: dict[str, dict[str, tuple[str, bool]]] = {
    "move": {"x_deg": (NUMBER, True), "y": (NUMBER, True), "to_x_deg": (NUMBER, False), "end": (END, False)},
    "move_lobe": {"x_deg": (NUMBER, True), "y": (NUMBER, True), "end": (END, False)},
    "move_extrema": {"x_deg": (NUMBER, True), "y": (NUMBER, True), "end": (END, False)},
    "insert": {"x_deg": (NUMBER, True), "y": (NUMBER, True)},
    "delete": {"x_deg": (NUMBER, True), "end": (END, False)},
    "jump": {"x_deg": (NUMBER, True), "y": (NUMBER, False)},
    "unjump": {"x_deg": (NUMBER, True)},
    "move_phase": {"from_deg": (NUMBER, True), "to_deg": (NUMBER, True)},
    "detect_phases": {},
    "correct": {"mode": (TEXT, True), "segment": (PAIR, False), "method": (TEXT, False),
                "step_deg": (NUMBER, False), "max_stretch": (NUMBER, False)},
    "undo": {},
    "redo": {},
    "save": {"path": (TEXT, True)},
}
#: operations that change the law (and so take an undo step)
EDITS = frozenset(OPERATIONS) - {"undo", "redo", "save"}


# ---------------------------------------------------------------------------------------------
# Script format
# ---------------------------------------------------------------------------------------------

def normalize_operation(op: Any, index: int | None = None, where: str = "edit") -> dict:
    """Check one operation against ``OPERATIONS`` and return it with plain Python values.

    Parameters
    ----------
    op : dict
        The operation, a mapping with ``"op"`` and its fields (angles ``*_deg`` in deg, ``y`` in the
        drawing's y units).
    index : int, optional
        Its position in the script (named in errors).
    where : str
        The script (or the window) named in errors.

    Returns
    -------
    dict
        ``{"op": name, field: value, ...}``: numbers as float (deg for angles, no unit conversion),
        ``segment`` as a list of two floats.

    Raises
    ------
    CamcadError
        A missing, unknown or mistyped key, or an unknown operation, naming the index and the key.

    Examples
    --------
    >>> from camcad.edit import normalize_operation
    >>> normalize_operation({"op": "correct", "mode": "segment", "segment": [60, 180]})
    {'op': 'correct', 'mode': 'segment', 'segment': [60.0, 180.0]}
    """
    at = f"{where}, operation {index}" if index is not None else where
    if not isinstance(op, dict):
        raise CamcadError(f"an operation must be a JSON object, not {type(op).__name__}", at,
                          'write e.g. {"op": "move", "x_deg": 75, "y": 1.2}')
    name = op.get("op")
    if not isinstance(name, str):
        raise CamcadError('key "op" is missing or not a string', at, f"give one of {', '.join(OPERATIONS)}")
    if name not in OPERATIONS:
        raise CamcadError(f"unknown operation {name!r}", at, f"use one of {', '.join(OPERATIONS)}")
    spec = OPERATIONS[name]
    at = f"{at} ({name})"
    unknown = [key for key in op if key != "op" and key not in spec]
    if unknown:
        fields = ", ".join(spec) or "none"
        raise CamcadError(f"key {unknown[0]!r} is not a field of {name}", at, f"fields of {name}: {fields}")
    result: dict[str, Any] = {"op": name}
    for key, (kind, required) in spec.items():
        if key not in op or op[key] is None:
            if required:
                raise CamcadError(f"key {key!r} is missing", at, f"give {key} ({_kind_text(kind)})")
            continue
        value = op[key]
        if kind == NUMBER:
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise CamcadError(f"key {key!r} must be a finite number, not {value!r}", at,
                                  f"give {key} as a number")
            result[key] = float(value)
        elif kind == TEXT:
            if not isinstance(value, str) or not value:
                raise CamcadError(f"key {key!r} must be a non-empty string, not {value!r}", at, f"give {key} as text")
            result[key] = value
        elif kind == END:
            if value not in ("left", "right"):
                raise CamcadError(f"key {key!r} must be \"left\" or \"right\", not {value!r}", at,
                                  "pick the end of the jump: left (the value before it) or right")
            result[key] = value
        else:  # PAIR
            ok = (isinstance(value, (list, tuple)) and len(value) == 2
                  and all(not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v)
                          for v in value))
            if not ok:
                raise CamcadError(f"key {key!r} must be a list of two numbers [A, B] (deg), not {value!r}", at,
                                  f'write "{key}": [60, 180]')
            result[key] = [float(value[0]), float(value[1])]
    if name == "correct" and result["mode"] not in MODES:
        raise CamcadError(f"unknown mode {result['mode']!r}", at, f"use one of {', '.join(MODES)}")
    return result


def _kind_text(kind: str) -> str:
    return {NUMBER: "a number", TEXT: "text", PAIR: "[A, B] in deg", END: '"left" or "right"'}[kind]


def validate_script(ops: Any, where: str) -> list[dict]:
    """A whole script: a JSON list of at most ``MAX_OPERATIONS`` operations, each ``normalize_operation``'s.

    Parameters
    ----------
    ops : list of dict
        The operations as read from JSON.
    where : str
        The script, named in errors.

    Returns
    -------
    list of dict
        The operations, each as ``normalize_operation`` returns it (no unit conversion).

    Raises
    ------
    CamcadError
        Not a list, longer than ``MAX_OPERATIONS``, or an operation ``normalize_operation`` refuses (naming its index).

    Examples
    --------
    >>> from camcad.edit import validate_script
    >>> validate_script([{"op": "delete", "x_deg": 45}, {"op": "redo"}], "edits.json")
    [{'op': 'delete', 'x_deg': 45.0}, {'op': 'redo'}]
    """
    if not isinstance(ops, list):
        raise CamcadError(f"the script is a JSON {type(ops).__name__}, not a list of operations", where,
                          'write [{"op": "move", "x_deg": 75, "y": 1.2}, {"op": "save", "path": "out.dxf"}]')
    if len(ops) > MAX_OPERATIONS:
        raise CamcadError(f"the script holds {len(ops)} operations, more than camcad replays ({MAX_OPERATIONS})",
                          where, "split it into several scripts")
    return [normalize_operation(op, i, where) for i, op in enumerate(ops)]


def load_script(path: str | Path) -> list[dict]:
    """Read and check an edit script (a JSON list of operations, as ``camcad edit --script`` replays it).

    The script is a regular file of at most ``MAX_SCRIPT_BYTES``, nested at most ``input_file.MAX_NESTING``
    deep, at most ``MAX_OPERATIONS`` long.

    Parameters
    ----------
    path : str or Path
        The script file (JSON).

    Returns
    -------
    list of dict
        The operations checked by ``normalize_operation`` (angles in deg, ordinates in the drawing's y units).

    Raises
    ------
    CamcadError
        A file that cannot be read or is not JSON, or an operation that ``normalize_operation`` refuses.

    Examples
    --------
    >>> import json, tempfile, pathlib
    >>> from camcad.edit import load_script
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "edits.json"
    >>> _ = path.write_text(json.dumps([{"op": "move", "x_deg": 90, "y": 2}, {"op": "undo"}]))
    >>> load_script(path)
    [{'op': 'move', 'x_deg': 90.0, 'y': 2.0}, {'op': 'undo'}]
    """
    path = Path(path)
    where = str(path)
    raw = read_input(path, "an edit script (a JSON list of operations)", MAX_SCRIPT_BYTES)
    text, _encoding = decode_text(raw)
    check_json_nesting(text, where)
    try:
        ops = json.loads(text)
    except json.JSONDecodeError as err:
        raise CamcadError(f"not valid JSON: {err.msg} at line {err.lineno}, column {err.colno}", where,
                          "fix the JSON (a list of objects)") from None
    return validate_script(ops, where)


# ---------------------------------------------------------------------------------------------
# Laws without a drawing (standard laws)
# ---------------------------------------------------------------------------------------------

def sampled_law(law, step_deg: float = 0.5) -> PiecewiseLinearLaw:
    """A closed-form law (``camcad.compose``) as a drawn polyline, to edit it.

    a is sampled every ``step_deg`` and at every phase boundary; where a jumps (left and right values differ by
    more than 1e-9 of the peak) the boundary gets two vertices, so the jump stays vertical.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, a in mm/rad²).
    step_deg : float
        The sampling step, deg.

    Returns
    -------
    PiecewiseLinearLaw
        The polyline: knots in rad, a in mm/rad², the law's phases.

    Examples
    --------
    The simple harmonic rise jumps in acceleration at its ends: two vertices there.

    >>> import camcad
    >>> from camcad.edit import sampled_law
    >>> law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 10.0, "harmonic")
    >>> drawn = sampled_law(law, step_deg=1.0)
    >>> len(drawn.x), int((drawn.x[1:] == drawn.x[:-1]).sum())   # 361 samples, jumps at 90, 180, 270 deg
    (364, 3)
    """
    if not (math.isfinite(step_deg) and 0 < step_deg <= 10):
        raise CamcadError(f"step {step_deg!r} deg is out of range", "--step", "give a step between 0 and 10 deg")
    cycle = float(law.cycle)
    count = max(round(math.degrees(cycle) / step_deg), 8)
    grid = np.linspace(0.0, cycle, count + 1)
    bounds = sorted({float(p.start) for p in law.phases} | {float(p.end) for p in law.phases})
    knots = unique(np.concatenate((grid, bounds)))
    a = law.kinematics(knots).a
    a[-1] = law.kinematics(np.array([cycle - 1e-12 * cycle])).a[0]
    peak = max(float(np.max(np.abs(a))), 1e-300)
    xs, ys = [], []
    for t, value in zip(knots, a):
        if 0.0 < t < cycle and any(abs(t - b) <= 1e-12 for b in bounds):
            delta = 1e-10 * cycle
            left, right = law.kinematics(np.array([t - delta, t + delta])).a
            if abs(left - right) > 1e-9 * peak:
                xs.extend([t, t])
                ys.extend([left, right])
                continue
        xs.append(t)
        ys.append(value)
    return PiecewiseLinearLaw(np.array(xs), np.array(ys), cycle, tuple(law.phases))


def loaded_from_law(law: PiecewiseLinearLaw, name: str, notes: Iterable[str] = ()) -> LoadedLaw:
    """A ``LoadedLaw`` for a law that was not read from a file (angles in deg, y in mm/rad²)."""
    n = len(law.x)
    identity = np.arange(n)
    return LoadedLaw(law=law, path=Path(name), source=f"{name}, {n} vertices", notes=tuple(notes), y_scale=1.0,
                     x_min=0.0, x_max=math.degrees(law.cycle), phases_given=True,
                     vertex_map=VertexMap(identity, identity.copy(), np.zeros(n)))


# ---------------------------------------------------------------------------------------------
# Small pure helpers on a law
# ---------------------------------------------------------------------------------------------

def jump_group(x: np.ndarray, index: int) -> tuple[int, int]:
    """(first, last) index of the vertices sharing the angle of vertex ``index`` (a jump has two)."""
    first = index
    while first > 0 and x[first - 1] == x[index]:
        first -= 1
    last = index
    while last + 1 < len(x) and x[last + 1] == x[index]:
        last += 1
    return first, last


def lobe_of(a: np.ndarray, index: int) -> np.ndarray:
    """Indices of the lobe holding vertex ``index``: the run of consecutive vertices whose acceleration
    has its sign (|a| at or below ``zero_threshold`` counts as zero and ends a lobe)."""
    eps = zero_threshold(a)
    sign = np.where(np.abs(a) <= eps, 0, np.sign(a)).astype(int)
    own = sign[index]
    if own == 0:
        return np.array([], dtype=int)
    other = np.flatnonzero(sign != own)
    left = other[other < index]
    right = other[other > index]
    start = int(left[-1]) + 1 if len(left) else 0
    stop = int(right[0]) if len(right) else len(a)
    return np.arange(start, stop)


def extremum_group(a: np.ndarray, lobe: np.ndarray) -> np.ndarray:
    """The vertices of ``lobe`` with the largest |a| (equal within 1e-9 of it)."""
    if len(lobe) == 0:
        return lobe
    values = np.abs(a[lobe])
    peak = float(values.max())
    return lobe[values >= peak * (1.0 - 1e-9)]


def law_problems(law: PiecewiseLinearLaw) -> list[str]:
    """What is wrong with a law as an editor state (empty when it is sound): the invariants every
    operation keeps. Used by the tests and as a guard after each operation."""
    x, a = law.x, law.a
    problems = []
    if len(x) < 3:
        problems.append(f"{len(x)} vertices")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(a))):
        problems.append("non-finite values")
    if np.any(np.diff(x) < 0):
        problems.append("x goes back")
    if x[0] != 0.0 or x[-1] != law.cycle:
        problems.append("does not span the cycle")
    if len(x) >= 2 and (x[1] == x[0] or x[-2] == x[-1]):
        problems.append("a jump at the cycle's ends")
    if len(x) >= 3 and np.any((x[2:] == x[1:-1]) & (x[1:-1] == x[:-2])):
        problems.append("three vertices at one angle")
    phases = law.phases
    tol = 1e-9 * law.cycle
    if phases:
        if abs(phases[0].start) > tol or abs(phases[-1].end - law.cycle) > tol:
            problems.append("phases do not span the cycle")
        if any(abs(p.end - q.start) > tol for p, q in itertools.pairwise(phases)):
            problems.append("phases have gaps")
    return problems


# ---------------------------------------------------------------------------------------------
# The session
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class EditState:
    """One state of the edited law. ``restructured``: vertices were inserted, deleted, split or merged
    (or the law resampled) since loading, so a saved drawing gets a new polyline instead of moving
    the drawn vertices in place."""

    law: PiecewiseLinearLaw
    restructured: bool = False


@dataclass
class Preview:
    """A correction shown before it is accepted: the result, and the operation that makes it."""

    correction: Correction
    op: dict
    max_change: float   # input y units
    rms_change: float   # input y units


@dataclass
class ModeRow:
    """One row of "compare all modes": what a mode would do to the current law (input y units)."""

    mode: str
    balanced: bool | None
    max_change: float | None
    rms_change: float | None
    error: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)

    def to_dict(self) -> dict:
        return {"mode": self.mode, "balanced": self.balanced, "max_change": self.max_change,
                "rms_change": self.rms_change, "error": self.error, "notes": list(self.notes)}


class EditSession:
    r"""A law being edited: operations, undo/redo, the balance report, corrections, saving.

    Parameters
    ----------
    loaded : LoadedLaw
        The law as read (``camcad.load_law``): its curve, drawing and scales are what a saved drawing is
        built from.
    tol : float
        Closure tolerance, a fraction of the rise (as ``camcad check --tol``).
    input_path : Path, optional
        The input file, never overwritten (None for a law that has no file).
    where : str
        How errors name the input.

    Examples
    --------
    Raise the return's last lobe of a law drawn 20 % high back to its size, then undo:

    >>> import tempfile, pathlib
    >>> import camcad
    >>> from camcad.edit import EditSession
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1.2), (360, 0)]
    >>> _ = (folder / "law.csv").write_text("".join(f"{t},{a}\n" for t, a in rows))
    >>> session = EditSession(camcad.load_law(folder / "law.csv"))
    >>> session.report.balanced
    False
    >>> session.apply({"op": "move", "x_deg": 315, "y": 1.0})
    >>> session.report.balanced, session.can_undo
    (True, True)
    >>> session.undo(); session.report.balanced
    False
    """

    def __init__(self, loaded: LoadedLaw, *, tol: float = DEFAULT_TOL, input_path: Path | None = None,
                 where: str = "") -> None:
        self.loaded = loaded
        self.tol = valid_tol(tol)
        self.input_path = Path(input_path) if input_path is not None else None
        self.where = where or str(loaded.path)
        problems = law_problems(loaded.law)
        if problems:
            raise CamcadError(f"the law cannot be edited: {', '.join(problems)}", self.where,
                              "redraw the law (at least 3 vertices, no jump at the cycle's ends)")
        self._initial = EditState(loaded.law)
        self._state = self._initial
        self._undo: list[EditState] = []
        self._redo: list[EditState] = []
        self._log: list[dict] = []
        self._reports: dict[int, tuple[PiecewiseLinearLaw, BalanceReport]] = {}
        self._gesture: EditState | None = None
        self._gesture_op: dict | None = None
        self.preview: Preview | None = None
        self.outputs: list[Path] = []
        #: the folder an operation's relative save path is resolved against (and confined to)
        self.base_dir = Path.cwd()
        #: the files the session read, as (path, role): no save may replace one
        self.inputs: list[tuple[Path, str]] = [(self.input_path, "the law")] if self.input_path is not None else []

    # --- construction ------------------------------------------------------------------------

    @classmethod
    def from_file(cls, path: str | Path, *, tol: float = DEFAULT_TOL, **options) -> EditSession:
        """Read ``path`` with ``load_law(path, **options)`` and start a session on it."""
        loaded = load_law(path, **options)
        return cls(loaded, tol=tol, input_path=Path(path))

    # --- what the session holds -------------------------------------------------------------

    @property
    def law(self) -> PiecewiseLinearLaw:
        """The current law (θ rad, a mm/rad²)."""
        return self._state.law

    @property
    def state(self) -> EditState:
        return self._state

    @property
    def initial_law(self) -> PiecewiseLinearLaw:
        return self._initial.law

    @property
    def report(self) -> BalanceReport:
        """The balance report of the current law (``balance.check`` at ``tol``), cached per state."""
        return self.report_of(self.law)

    def report_of(self, law: PiecewiseLinearLaw) -> BalanceReport:
        """``balance.check(law, tol)``, cached for the last few laws."""
        cached = self._reports.get(id(law))
        if cached is not None and cached[0] is law:
            return cached[1]
        report = check(law, self.tol)
        if len(self._reports) > 8:
            self._reports.clear()
        self._reports[id(law)] = (law, report)
        return report

    @property
    def operations(self) -> list[dict]:
        """Every operation applied so far, in order (copies)."""
        return [dict(op) for op in self._log]

    @property
    def applied(self) -> int:
        return len(self._log)

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    @property
    def cycle_deg(self) -> float:
        return math.degrees(self.law.cycle)

    @property
    def y_scale(self) -> float:
        """law units (mm/rad²) per input y unit."""
        return float(self.loaded.y_scale)

    def to_law(self, y: float) -> float:
        """Input y units in law units (mm/rad²)."""
        return float(y) * self.y_scale

    def theta_deg(self, law: PiecewiseLinearLaw | None = None) -> np.ndarray:
        return np.degrees((law or self.law).x)

    def changes(self, law: PiecewiseLinearLaw | None = None) -> tuple[float, float]:
        """(max |Δa|, RMS Δa) of ``law`` (default the current one) against the law as loaded, input y units."""
        max_change, rms_change = difference_norms(self.initial_law, law or self.law)
        return max_change / self.y_scale, rms_change / self.y_scale

    # --- finding things ------------------------------------------------------------------------

    def vertex_near(self, x_deg: float, end: str | None = None, law: PiecewiseLinearLaw | None = None,
                    key: str = "x_deg", at: str | None = None) -> int:
        """Index of the vertex nearest the cam angle ``x_deg`` (deg); of a jump, its ``end`` ("left", the
        default, or "right")."""
        law = law or self.law
        self._inside_cycle(x_deg, key, law, at)
        theta = math.radians(x_deg)
        i = int(np.argmin(np.abs(law.x - theta)))
        first, last = jump_group(law.x, i)
        return last if end == "right" else first

    def end_of(self, index: int, law: PiecewiseLinearLaw | None = None) -> str | None:
        """"left"/"right" when vertex ``index`` is an end of a jump, else None."""
        x = (law or self.law).x
        first, last = jump_group(x, index)
        if first == last:
            return None
        return "left" if index == first else "right"

    def boundaries_deg(self, law: PiecewiseLinearLaw | None = None) -> list[float]:
        """The interior phase boundaries (deg)."""
        law = law or self.law
        return [math.degrees(p.end) for p in law.phases[:-1]]

    def _inside_cycle(self, value: float, key: str, law: PiecewiseLinearLaw, at: str | None = None) -> None:
        cycle_deg = math.degrees(law.cycle)
        if not (math.isfinite(value) and -1e-9 <= value <= cycle_deg + 1e-9):
            raise CamcadError(f"{key} {value:g} deg is outside the cycle 0..{cycle_deg:g} deg", at or self.where,
                              f"give an angle in 0..{cycle_deg:g}")

    # --- applying operations ------------------------------------------------------------------

    def apply(self, op: dict, *, index: int | None = None, where: str | None = None) -> None:
        """Apply one operation (see the module docstring). Inside a gesture, an edit is computed from
        the state at the gesture's start and replaces the gesture's previous result.

        Raises
        ------
        CamcadError
            Bad fields, an impossible edit or correction (the law is then unchanged).
        """
        where = where or self.where
        op = normalize_operation(op, index, where)
        name = op["op"]
        at = f"{where}, operation {index} ({name})" if index is not None else f"{where} ({name})"
        if name == "undo":
            self.undo(at)
        elif name == "redo":
            self.redo(at)
        elif name == "save":
            self.save(self._resolve(op["path"], at), at=at, record=False)
        else:
            base = self._gesture if self._gesture is not None else self._state
            new = self._edit(base, op, at)
            problems = law_problems(new.law)
            if problems:  # an operation must never leave a broken law; refuse it
                raise CamcadError(f"{name} would leave the law broken ({', '.join(problems)})", at,
                                  "undo the previous step or choose another edit")
            if self._gesture is not None:
                self._state = new
                self._gesture_op = op
                return
            self._commit(new)
        self._log.append(op)

    def replay(self, ops: list[dict], where: str = "script") -> int:
        """Apply a checked script; returns how many operations were applied."""
        for i, op in enumerate(ops):
            self.apply(op, index=i, where=where)
        return len(ops)

    def export_script(self) -> list[dict]:
        """The script of what was done: every edit, undo and redo in order (saves are left out: give
        ``-o`` or add a ``save`` when replaying)."""
        return [dict(op) for op in self._log if op["op"] != "save"]

    def _resolve(self, path: str, where: str = "") -> Path:
        """An operation's save path inside ``base_dir`` (``output_folder.confined_path``)."""
        return confined_path(path, self.base_dir, where or self.where, "save path")

    def _commit(self, new: EditState) -> None:
        if new is self._state:
            return
        self._undo.append(self._state)
        if len(self._undo) > MAX_UNDO:
            del self._undo[0]
        self._redo.clear()
        self._state = new
        self.preview = None

    # --- gestures: a drag is one undo step -----------------------------------------------------

    def begin_gesture(self) -> None:
        """Start a gesture (a drag): the edits until ``end_gesture`` make one undo step and one
        operation in the script, each computed from the state at this point."""
        if self._gesture is None:
            self.preview = None
            self._gesture = self._state
            self._gesture_op = None

    def end_gesture(self) -> dict | None:
        """Finish the gesture; returns its operation (None when nothing changed)."""
        if self._gesture is None:
            return None
        base, op = self._gesture, self._gesture_op
        self._gesture, self._gesture_op = None, None
        if op is None or self._state is base:
            self._state = base
            return None
        self._undo.append(base)
        if len(self._undo) > MAX_UNDO:
            del self._undo[0]
        self._redo.clear()
        self._log.append(op)
        return op

    def cancel_gesture(self) -> None:
        """Drop the gesture: the law is as before it."""
        if self._gesture is not None:
            self._state = self._gesture
            self._gesture, self._gesture_op = None, None

    @property
    def gesture_base(self) -> PiecewiseLinearLaw | None:
        return self._gesture.law if self._gesture is not None else None

    # --- undo / redo ---------------------------------------------------------------------------

    def undo(self, at: str | None = None) -> None:
        """Go back one step (a gesture, an operation, an accepted correction).

        Raises
        ------
        CamcadError
            Nothing to undo (the window shows it as a message).
        """
        self.cancel_gesture()
        self.preview = None
        if not self._undo:
            raise CamcadError("nothing to undo", at or self.where, "remove the undo, or edit something first")
        self._redo.append(self._state)
        self._state = self._undo.pop()

    def redo(self, at: str | None = None) -> None:
        """Go forward one undone step (CamcadError when there is none)."""
        self.cancel_gesture()
        self.preview = None
        if not self._redo:
            raise CamcadError("nothing to redo", at or self.where, "redo only after an undo")
        self._undo.append(self._state)
        self._state = self._redo.pop()

    # --- the edits -----------------------------------------------------------------------------

    def _edit(self, state: EditState, op: dict, at: str) -> EditState:
        law = state.law
        name = op["op"]
        if name == "correct":
            result = self._correction(law, op, at)
            return EditState(result.law, state.restructured or result.resampled)
        if name == "move_phase":
            return EditState(self._move_phase(law, op["from_deg"], op["to_deg"], at), state.restructured)
        if name == "detect_phases":
            phases = detect_phases(law.x, law.a, law.cycle, at)
            return EditState(law.with_phases(phases), state.restructured)
        if name == "insert":
            return EditState(self._insert(law, op["x_deg"], self.to_law(op["y"]), at), True)
        i = self.vertex_near(op["x_deg"], op.get("end"), law, at=at)
        if name == "move":
            return EditState(self._move(law, i, self.to_law(op["y"]), op.get("to_x_deg"), at), state.restructured)
        if name in ("move_lobe", "move_extrema"):
            if "end" not in op:  # of a jump from the axis, the end off the axis holds the lobe
                first, last = jump_group(law.x, i)
                i = next((j for j in range(first, last + 1) if len(lobe_of(law.a, j))), i)
            return EditState(self._move_lobe(law, i, self.to_law(op["y"]), name == "move_extrema", at),
                             state.restructured)
        if name == "delete":
            return EditState(self._delete(law, i, at), True)
        if name == "jump":
            y = self.to_law(op["y"]) if "y" in op else None
            return EditState(self._make_jump(law, i, y, at), True)
        if name == "unjump":
            return EditState(self._remove_jump(law, i, at), True)
        raise AssertionError(name)  # pragma: no cover - every operation is handled above

    def _move(self, law: PiecewiseLinearLaw, i: int, a_new: float, to_x_deg: float | None,
              at: str) -> PiecewiseLinearLaw:
        a = law.a.copy()
        a[i] = a_new
        if to_x_deg is None:
            return law.with_ordinates(a)
        self._inside_cycle(to_x_deg, "to_x_deg", law, at)
        lo, hi = self.x_limits(i, law)
        x = law.x.copy()
        first, last = jump_group(x, i)
        x[first:last + 1] = min(max(math.radians(to_x_deg), lo), hi)
        return PiecewiseLinearLaw(x, a, law.cycle, law.phases)

    def x_limits(self, i: int, law: PiecewiseLinearLaw | None = None) -> tuple[float, float]:
        """(lo, hi) in rad where vertex ``i`` (with its jump twin) may be moved in angle: between its
        neighbours; onto a neighbour only when that makes a two-ended jump inside the cycle."""
        law = law or self.law
        x = law.x
        n = len(x)
        first, last = jump_group(x, i)
        if first == 0 or last == n - 1:
            return float(x[i]), float(x[i])   # the cycle's ends do not move in angle
        gap = math.radians(X_GAP_DEG)
        size = last - first + 1
        left_first, _ = jump_group(x, first - 1)
        _, right_last = jump_group(x, last + 1)
        can_join_left = size == 1 and left_first == first - 1 and first - 1 > 0
        can_join_right = size == 1 and right_last == last + 1 and last + 1 < n - 1
        lo = float(x[first - 1]) + (0.0 if can_join_left else gap)
        hi = float(x[last + 1]) - (0.0 if can_join_right else gap)
        if hi < lo:  # neighbours closer than the gap: the vertex stays
            return float(x[i]), float(x[i])
        return lo, hi

    def _move_lobe(self, law: PiecewiseLinearLaw, i: int, a_new: float, extrema_only: bool,
                   at: str) -> PiecewiseLinearLaw:
        lobe = lobe_of(law.a, i)
        if len(lobe) == 0:
            raise CamcadError(f"the vertex at {math.degrees(law.x[i]):.6g} deg is on the axis: it belongs to no lobe",
                              at, "pick a vertex off the axis")
        a = law.a.copy()
        if extrema_only:
            group = extremum_group(law.a, lobe)
            value = a_new if a_new * law.a[group[0]] > 0 else 0.0
            a[group] = value
        else:
            factor = a_new / law.a[i]
            a[lobe] = law.a[lobe] * max(factor, 0.0)
        return law.with_ordinates(a)

    def _insert(self, law: PiecewiseLinearLaw, x_deg: float, a_new: float, at: str) -> PiecewiseLinearLaw:
        cycle_deg = math.degrees(law.cycle)
        theta = math.radians(x_deg)
        if not 0.0 < theta < law.cycle:
            raise CamcadError(f"insert at {x_deg:g} deg: a new vertex must lie strictly inside the cycle "
                              f"0..{cycle_deg:g} deg", at, "give an angle between the first and the last vertex")
        if np.any(law.x == theta):
            raise CamcadError(f"a vertex is already at {x_deg:g} deg", at,
                              "move that vertex, or make a jump there with the jump operation")
        k = int(np.searchsorted(law.x, theta))
        x = np.insert(law.x, k, theta)
        a = np.insert(law.a, k, a_new)
        return PiecewiseLinearLaw(x, a, law.cycle, law.phases)

    def _delete(self, law: PiecewiseLinearLaw, i: int, at: str) -> PiecewiseLinearLaw:
        n = len(law.x)
        if i == 0 or i == n - 1:
            raise CamcadError("the first and the last vertex hold the ends of the cycle", at,
                              "move them instead of deleting them")
        if n <= 3:
            raise CamcadError(f"the law has {n} vertices; it needs at least 3", at, "insert a vertex first")
        return PiecewiseLinearLaw(np.delete(law.x, i), np.delete(law.a, i), law.cycle, law.phases)

    def _make_jump(self, law: PiecewiseLinearLaw, i: int, a_new: float | None, at: str) -> PiecewiseLinearLaw:
        n = len(law.x)
        first, last = jump_group(law.x, i)
        if first != last:
            raise CamcadError(f"the vertex at {math.degrees(law.x[i]):.6g} deg is already a jump", at,
                              "move one of its ends, or remove it with unjump")
        if i == 0 or i == n - 1:
            raise CamcadError("a jump cannot sit at the ends of the cycle", at, "make the jump at an inner vertex")
        value = law.a[i] if a_new is None else a_new
        x = np.insert(law.x, i + 1, law.x[i])
        a = np.insert(law.a, i + 1, value)
        return PiecewiseLinearLaw(x, a, law.cycle, law.phases)

    def _remove_jump(self, law: PiecewiseLinearLaw, i: int, at: str) -> PiecewiseLinearLaw:
        first, last = jump_group(law.x, i)
        if first == last:
            raise CamcadError(f"there is no jump at {math.degrees(law.x[i]):.6g} deg", at,
                              "pick a vertical segment of the law")
        mean = 0.5 * (law.a[first] + law.a[last])
        x = np.delete(law.x, range(first + 1, last + 1))
        a = np.delete(law.a, range(first + 1, last + 1))
        a[first] = mean
        return PiecewiseLinearLaw(x, a, law.cycle, law.phases)

    def phase_limits(self, k: int, law: PiecewiseLinearLaw | None = None) -> tuple[float, float]:
        """(lo, hi) in deg where the boundary between phases k and k+1 may go."""
        law = law or self.law
        phases = law.phases
        return (math.degrees(phases[k].start) + MIN_PHASE_DEG, math.degrees(phases[k + 1].end) - MIN_PHASE_DEG)

    def boundary_near(self, from_deg: float, law: PiecewiseLinearLaw | None = None,
                      at: str = "") -> int:
        """k of the boundary (end of phase k) nearest ``from_deg``, within ``PHASE_PICK_DEG``."""
        law = law or self.law
        bounds = self.boundaries_deg(law)
        if not bounds:
            raise CamcadError("the law has a single phase: there is no boundary to move", at or self.where,
                              "give --phases with several phases")
        k = int(np.argmin([abs(b - from_deg) for b in bounds]))
        if abs(bounds[k] - from_deg) > PHASE_PICK_DEG:
            listed = ", ".join(f"{b:.6g}" for b in bounds)
            raise CamcadError(f"no phase boundary near {from_deg:g} deg", at or self.where,
                              f"the boundaries are at {listed} deg")
        return k

    def _move_phase(self, law: PiecewiseLinearLaw, from_deg: float, to_deg: float, at: str) -> PiecewiseLinearLaw:
        k = self.boundary_near(from_deg, law, at)
        lo, hi = self.phase_limits(k, law)
        if not lo <= to_deg <= hi:
            raise CamcadError(f"phase boundary to {to_deg:g} deg: it must stay between {lo:.6g} and {hi:.6g} deg "
                              f"(inside the {law.phases[k].kind} and the {law.phases[k + 1].kind} around it)",
                              at, "move it less far")
        phases = list(law.phases)
        start, old, end = phases[k].start, phases[k].end, phases[k + 1].end
        new = math.radians(to_deg)
        x = law.x.copy()
        left = (x >= start) & (x <= old)
        right = (x > old) & (x <= end)
        x[left] = start + (x[left] - start) * ((new - start) / (old - start))
        x[right] = new + (x[right] - old) * ((end - new) / (end - old))
        x[law.x == old] = new
        x[law.x == start] = start
        x[law.x == end] = end
        collapsed = (np.diff(x) == 0) & (np.diff(law.x) > 0)
        if np.any(collapsed):
            raise CamcadError(f"moving the boundary to {to_deg:g} deg squeezes two vertices onto one angle", at,
                              "move it less far")
        phases[k] = Phase(phases[k].kind, start, new)
        phases[k + 1] = Phase(phases[k + 1].kind, new, end)
        return PiecewiseLinearLaw(x, law.a, law.cycle, tuple(phases))

    # --- corrections ---------------------------------------------------------------------------

    def _correction(self, law: PiecewiseLinearLaw, op: dict, at: str) -> Correction:
        mode = op["mode"]
        kwargs: dict[str, Any] = {}
        for key, name in (("method", "method"), ("step_deg", "step_deg"), ("max_stretch", "max_stretch")):
            if key in op:
                kwargs[name] = op[key]
        segment = op.get("segment")
        if segment is not None:
            lo, hi = sorted(segment)
            self._inside_cycle(lo, "segment", law, at)
            self._inside_cycle(hi, "segment", law, at)
            if mode == "segment":
                kwargs["segment_deg"] = (lo, hi)
            else:
                inside = (law.x >= math.radians(lo)) & (law.x <= math.radians(hi))
                kwargs["fixed"] = ~inside
        return correct(law, mode, tol=self.tol, where=at, **kwargs)

    def preview_correction(self, mode: str, segment: tuple[float, float] | None = None, **options) -> Preview:
        """Compute a correction of the current law and hold it for ``accept``/``reject``.

        Raises
        ------
        CamcadError
            The mode cannot balance this law (nothing is held; the law is unchanged).
        """
        op: dict[str, Any] = {"op": "correct", "mode": mode, **options}
        if segment is not None:
            op["segment"] = [float(segment[0]), float(segment[1])]
        op = normalize_operation(op, None, self.where)
        self.preview = None
        result = self._correction(self.law, op, f"{self.where} (correct)")
        max_change, rms_change = difference_norms(self.law, result.law)
        self.preview = Preview(result, op, max_change / self.y_scale, rms_change / self.y_scale)
        return self.preview

    def accept(self) -> None:
        """Make the held correction the current law (one undo step, one ``correct`` operation)."""
        if self.preview is None:
            raise CamcadError("no correction to accept", self.where, "preview a correction first")
        preview = self.preview
        self._commit(EditState(preview.correction.law, self._state.restructured or preview.correction.resampled))
        self._log.append(preview.op)
        self.preview = None

    def reject(self) -> None:
        """Drop the held correction."""
        self.preview = None

    def compare_modes(self, segment: tuple[float, float] | None = None) -> list[ModeRow]:
        """What every correction mode of ``fix`` would do to the current law (the law is not changed)."""
        rows = []
        for mode in MODES:
            if mode == "segment" and segment is None:
                rows.append(ModeRow(mode, None, None, None, "needs a range (select one)"))
                continue
            op: dict[str, Any] = {"op": "correct", "mode": mode}
            if segment is not None:
                op["segment"] = [float(segment[0]), float(segment[1])]
            try:
                result = self._correction(self.law, normalize_operation(op, None, self.where), self.where)
            except CamcadError as err:
                rows.append(ModeRow(mode, None, None, None, err.what))
                continue
            max_change, rms_change = difference_norms(self.law, result.law)
            rows.append(ModeRow(mode, result.after.balanced, max_change / self.y_scale, rms_change / self.y_scale,
                                notes=result.notes))
        return rows

    # --- saving --------------------------------------------------------------------------------

    def save(self, path: str | Path, *, at: str | None = None, record: bool = True) -> Path:
        """Write the current law: ``.dxf`` a corrected copy of the drawing exactly as ``camcad fix``
        writes it (``io.law_write.write_corrected``), a table suffix (``.csv``, ``.txt``, …) a table,
        ``.json`` the edit script. Never overwrites the input (paths compared after resolving links).

        Returns
        -------
        Path
            The written file.
        """
        path = Path(path)
        at = at or f"{self.where} (save)"
        suffix = path.suffix.lower()
        if suffix not in (".dxf", ".json") + TABLE_SUFFIXES:
            raise CamcadError(f"cannot save as {suffix or 'a file without a suffix'}", str(path),
                              f"use .dxf (the drawing), .csv (a table) or .json (the edit script); {at}")
        check_outputs([(path, "save")], self.inputs, at)
        if suffix == ".json":
            written = write_text_atomic(path, json.dumps(self.export_script(), indent=1) + "\n")
        else:
            law_record = LawRecord.for_law(self.law, "camcad edit", unit=self.loaded.unit or "mm")
            written, _notes = write_corrected(self.loaded, self.law, path, resampled=self._state.restructured,
                                              record=law_record)
        self.outputs.append(Path(written))
        if record:
            self._log.append({"op": "save", "path": str(path)})
        return Path(written)

    # --- tables for the view -------------------------------------------------------------------

    def vertex_rows(self, center: int, count: int = 9, law: PiecewiseLinearLaw | None = None) -> list[tuple]:
        """``count`` rows (index, θ deg, a in input y units, note) around vertex ``center``."""
        law = law or self.law
        n = len(law.x)
        center = min(max(center, 0), n - 1)
        start = min(max(center - count // 2, 0), max(n - count, 0))
        rows = []
        for i in range(start, min(start + count, n)):
            end = self.end_of(i, law)
            note = f"jump {end}" if end else ("axis" if law.a[i] == 0 else "")
            rows.append((i, math.degrees(law.x[i]), float(law.a[i]) / self.y_scale, note))
        return rows

    def pitch_preview(self, samples: int = 721, law: PiecewiseLinearLaw | None = None):
        """The pitch curve of a knife-edge translating follower on this law, for a small preview:
        (points (samples×2, mm), base radius mm, closure gap mm) or None when the cycle does not
        divide 360°. The base radius is chosen as twice the largest |s| so the curve stays round."""
        law = law or self.law
        lobes = 2 * math.pi / law.cycle
        if abs(lobes - round(lobes)) > 1e-9:
            return None
        theta_one = np.linspace(0.0, law.cycle, 513)
        s = law.kinematics(theta_one).s
        radius = max(2.0 * float(np.max(np.abs(s))), 1e-9)
        geometry = CamGeometry(law, Follower("knife", base_radius=radius, pressure_angle_limit_rise_deg=None,
                                             pressure_angle_limit_return_deg=None))
        theta = np.linspace(0.0, 2 * math.pi, samples)
        points = geometry.pitch(theta).points
        gap = float(s[-1] - s[0])
        return points, radius, gap


def default_output(session: EditSession) -> Path:
    """Where the window's save goes without ``-o``: ``<input>.edited.dxf`` beside a drawing,
    ``<input>.edited<suffix>`` beside a table, ``<name>.edited.dxf`` for a law without a file."""
    if session.input_path is None:
        return Path(session.loaded.path.name + ".edited.dxf")
    path = session.input_path
    suffix = ".dxf" if session.loaded.curve is not None else path.suffix
    return path.with_name(path.stem + ".edited" + suffix)


def default_script(session: EditSession) -> Path:
    """Where the window saves the edit script: ``<input>.edits.json``."""
    path = session.input_path or Path(session.loaded.path.name)
    return path.with_name(path.stem + ".edits.json")
