"""What a sweep found: counts, governing limits, the feasible boundary, the Pareto front and the best design.

All functions take the results as columns (``columns(table)``: {name: numpy array}) so they work on a
pyarrow table of any size without pandas.

Monte-Carlo sweeps are judged per grid point (``per_grid_point``): a grid point is feasible when every draw
of it is (the design meets its limits over the sampled tolerances), its yield is the fraction of feasible
draws, and each objective takes its worst value over the draws (the largest of a minimised figure, the
smallest of a maximised one).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError, nearest_name
from camcad.sweep.evaluate import STATUS_BAD, STATUS_BUG, STATUS_OK

#: shown per kind of error in the report
ERROR_EXAMPLES = 5


def columns(table, names: list[str] | None = None) -> dict[str, np.ndarray]:
    """{column: numpy array} of a pyarrow table (nulls: NaN for numbers, "" for text, False for flags)."""
    out = {}
    for name in names or table.column_names:
        column = table.column(name)
        kind = str(column.type)
        if kind in ("double", "float"):
            out[name] = column.to_numpy(zero_copy_only=False).astype(float)
        elif kind == "bool":
            out[name] = np.array([bool(v) for v in column.to_pylist()], dtype=bool)
        elif kind.startswith("int"):
            out[name] = np.array([(-1 if v is None else v) for v in column.to_pylist()], dtype=np.int64)
        else:
            out[name] = np.array([("" if v is None else v) for v in column.to_pylist()], dtype=object)
    return out


def check_names(names: list[str]) -> list[str]:
    """The checks that have columns (``<check>.passed``), in column order."""
    return [n[: -len(".passed")] for n in names if n.endswith(".passed")]


# --------------------------------------------------------------------------------------------
# counts
# --------------------------------------------------------------------------------------------

def summary(cols: dict[str, np.ndarray]) -> dict:
    """Counts: designs, feasible, infeasible, bad input, internal errors; for the infeasible designs how many
    each check failed (``failed_by``, a design may fail several) and which check failed worst
    (``governing``); a few error messages with their counts.

    Examples
    --------
    >>> cols = {"design": np.arange(3), "status": np.array(["ok", "ok", "bad input"], dtype=object),
    ...         "feasible": np.array([True, False, False]), "error": np.array(["", "", "x"], dtype=object),
    ...         "governing": np.array(["a", "a", "bad input"], dtype=object),
    ...         "a.passed": np.array([True, False, False])}
    >>> s = summary(cols)
    >>> s["designs"], s["feasible"], s["infeasible"], s["bad_input"], s["failed_by"], s["governing"]
    (3, 1, 1, 1, {'a': 1}, {'a': 1})
    """
    status = cols["status"]
    ok = status == STATUS_OK
    feasible = cols["feasible"] & ok
    infeasible = ok & ~feasible
    failed_by = {}
    for check in check_names(list(cols)):
        count = int(np.sum(infeasible & ~cols[f"{check}.passed"]))
        if count:
            failed_by[check] = count
    governing = Counter(cols["governing"][infeasible].tolist())
    errors: dict[str, list] = {}
    for kind in (STATUS_BAD, STATUS_BUG):
        messages = Counter(cols["error"][status == kind].tolist())
        errors[kind] = [{"error": text, "designs": count} for text, count in messages.most_common(ERROR_EXAMPLES)]
    return {"designs": len(status), "feasible": int(feasible.sum()), "infeasible": int(infeasible.sum()),
            "bad_input": int(np.sum(status == STATUS_BAD)), "internal_errors": int(np.sum(status == STATUS_BUG)),
            "failed_by": dict(sorted(failed_by.items(), key=lambda kv: -kv[1])),
            "governing": dict(governing.most_common()), "errors": errors}


# --------------------------------------------------------------------------------------------
# objectives
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Objective:
    """``sense`` ("min" or "max") of the column ``column``."""

    sense: str
    column: str

    @property
    def text(self) -> str:
        return f"{self.sense}:{self.column}"


def parse_objective(text: str, names: list[str], where: str = "--objective") -> Objective:
    """``min:COLUMN`` or ``max:COLUMN`` → Objective; COLUMN is a varied key, ``min_margin_ratio`` or a check's
    figure (``pressure angle, rise.margin``; a check's name alone means its margin).

    Examples
    --------
    >>> parse_objective("max:pressure angle, rise", ["pressure angle, rise.margin"]).column
    'pressure angle, rise.margin'
    """
    sense, _, column = text.partition(":")
    sense, column = sense.strip().lower(), column.strip()
    if sense not in ("min", "max") or not column:
        raise CamcadError(f"{text[:60]!r} is not min:COLUMN or max:COLUMN", where,
                          'write e.g. --objective min:follower.base_radius --objective "max:min_margin_ratio"')
    numeric = [n for n in names if not n.endswith(".passed") and not n.startswith("_")
               and n not in ("status", "error", "governing", "feasible", "design", "sample")]
    if column in numeric:
        return Objective(sense, column)
    if f"{column}.margin" in numeric:
        return Objective(sense, f"{column}.margin")
    hint = nearest_name(column, numeric)
    hint = hint.split("?")[0] + "?" if hint.startswith("did you mean") else "columns: " + ", ".join(numeric[:8])
    raise CamcadError(f"no column {column[:60]!r} to optimise", where, hint)


def default_objectives(keys: dict[str, str]) -> list[Objective]:
    """The smallest value of the first numeric varied key (a base radius first, if one is varied) and the
    largest least margin ratio (the design farthest from every limit)."""
    numeric = [k for k, kind in keys.items() if kind in ("float", "int")]
    radii = [k for k in numeric if k.endswith("base_radius")]
    first = next(iter(radii or numeric), None)
    out = [Objective("min", first)] if first else []
    return out + [Objective("max", "min_margin_ratio")]


# --------------------------------------------------------------------------------------------
# Monte-Carlo: per grid point
# --------------------------------------------------------------------------------------------

def per_grid_point(cols: dict[str, np.ndarray], samples: int, grid_keys: list[str],
                   objectives: list[Objective]) -> dict[str, np.ndarray]:
    """The designs of each grid point taken together (module docstring); the identity for ``samples`` 1.

    Returns columns: ``design`` (the grid point's first design id), the grid keys, ``feasible`` (every draw),
    ``yield`` (fraction of feasible draws), ``governing`` (the check that failed worst most often, else the
    tightest), ``min_margin_ratio`` (worst), and each objective's column (worst over the draws).
    """
    out: dict[str, Any]
    if samples <= 1:
        out = {name: cols[name] for name in ["design", *grid_keys, "feasible", "governing", "min_margin_ratio"]}
        out["feasible"] = cols["feasible"] & (cols["status"] == STATUS_OK)
        out["yield"] = out["feasible"].astype(float)
        for objective in objectives:
            out[objective.column] = cols[objective.column]
        return out
    grid = cols["design"] // samples
    order = np.argsort(grid, kind="stable")
    points, starts = np.unique(grid[order], return_index=True)
    ends = np.append(starts[1:], len(order))
    feasible_draw = cols["feasible"] & (cols["status"] == STATUS_OK)
    out = {"design": points * samples}
    for key in grid_keys:
        out[key] = cols[key][order][starts]
    out["feasible"] = np.array([feasible_draw[order[a:b]].all() and b - a == samples for a, b in zip(starts, ends)])
    out["yield"] = np.array([feasible_draw[order[a:b]].mean() for a, b in zip(starts, ends)])
    governing = []
    for a, b in zip(starts, ends):
        rows = order[a:b]
        failing = [g for g, f in zip(cols["governing"][rows], feasible_draw[rows]) if not f]
        governing.append(Counter(failing).most_common(1)[0][0] if failing else
                         cols["governing"][rows[np.nanargmin(_finite(cols["min_margin_ratio"][rows]))]])
    out["governing"] = np.array(governing, dtype=object)
    out["min_margin_ratio"] = np.array([np.nanmin(_finite(cols["min_margin_ratio"][order[a:b]]))
                                        for a, b in zip(starts, ends)])
    for objective in objectives:
        if objective.column in out:
            continue
        values = cols[objective.column][order]
        pick = np.nanmax if objective.sense == "min" else np.nanmin
        out[objective.column] = np.array([pick(_finite(values[a:b])) for a, b in zip(starts, ends)])
    return out


def _finite(values: np.ndarray) -> np.ndarray:
    values = np.asarray(values, dtype=float)
    return values if np.isfinite(values).any() else np.array([np.nan])


# --------------------------------------------------------------------------------------------
# boundary, Pareto front, best design
# --------------------------------------------------------------------------------------------

def feasible_boundary(x: np.ndarray, y: np.ndarray, feasible: np.ndarray) -> list[dict]:
    """For each value of ``x``: the least ``y`` whose design is feasible, whether every larger ``y`` of the
    grid is feasible too (``monotone``), and the largest infeasible ``y`` below it.

    Examples
    --------
    >>> x = np.array([1, 1, 1, 2, 2, 2]); y = np.array([10, 11, 12, 10, 11, 12])
    >>> ok = np.array([False, True, True, False, False, True])
    >>> [(b["x"], b["least_feasible"], b["monotone"]) for b in feasible_boundary(x, y, ok)]
    [(1.0, 11.0, True), (2.0, 12.0, True)]
    """
    out = []
    for value in unique(x):
        at = x == value
        ys, ok = y[at], feasible[at]
        order = np.argsort(ys)
        ys, ok = ys[order], ok[order]
        if not ok.any():
            out.append({"x": float(value), "least_feasible": None, "greatest_infeasible": float(ys[-1]),
                        "monotone": True})
            continue
        first = int(np.argmax(ok))
        below = ys[:first]
        out.append({"x": float(value), "least_feasible": float(ys[first]),
                    "greatest_infeasible": float(below[-1]) if len(below) else None,
                    "monotone": bool(ok[first:].all())})
    return out


def pareto_front(values: np.ndarray, senses: list[str]) -> np.ndarray:
    """Indices of the non-dominated rows of ``values`` (n × k), each column minimised (``"min"``) or
    maximised (``"max"``); rows with a NaN are left out; of identical rows the first is kept.

    A row dominates another when it is no worse in every objective and better in one. Rows are taken in
    lexicographic order, so a row can only be dominated by rows before it; each is compared with the front so
    far (O(n · front size)).

    Examples
    --------
    >>> v = np.array([[1.0, 5.0], [2.0, 3.0], [3.0, 4.0], [4.0, 1.0], [2.0, 3.0]])
    >>> pareto_front(v, ["min", "min"]).tolist()
    [0, 1, 3]
    """
    values = np.asarray(values, dtype=float)
    if values.ndim != 2 or values.shape[1] != len(senses):
        raise ValueError("one sense per column")
    signs = np.array([1.0 if s == "min" else -1.0 for s in senses])
    costs = values * signs
    keep = np.flatnonzero(np.isfinite(costs).all(axis=1))
    costs = costs[keep]
    order = np.lexsort(costs.T[::-1])
    front: list[int] = []
    front_costs = np.empty((0, costs.shape[1]))
    for i in order:
        c = costs[i]
        if len(front) and np.any(np.all(front_costs <= c, axis=1)):
            continue  # dominated by (or equal to) a row already on the front
        front.append(int(keep[i]))
        front_costs = np.vstack([front_costs, c])
    return np.array(sorted(front), dtype=np.int64)


def best_index(points: dict[str, np.ndarray], objectives: list[Objective]) -> int | None:
    """The best feasible row: the first objective's best, ties broken by the next ones, then the lowest design
    id; None when no row is feasible."""
    feasible = np.flatnonzero(points["feasible"])
    if not len(feasible):
        return None
    keys = [points["design"][feasible]]
    for objective in reversed(objectives):
        values = np.asarray(points[objective.column][feasible], dtype=float)
        values = np.where(np.isfinite(values), values, np.inf if objective.sense == "min" else -np.inf)
        keys.append(values if objective.sense == "min" else -values)
    return int(feasible[np.lexsort(keys)[0]])


def region_axes(space, requested: tuple[str, str] | None = None) -> tuple[str, str] | None:
    """The keys on the horizontal and vertical axes of the region plot: ``requested`` (checked), else the first
    two numeric keys varied over a grid of several values; None when there are not two such keys."""
    numeric = [s.key.path for s in space.grid_specs if s.key.numeric and len(s.values) > 1]
    if requested is None:
        return (numeric[0], numeric[1]) if len(numeric) >= 2 else None
    for key in requested:
        if key not in numeric:
            raise CamcadError(f"{key[:60]!r} is not a numeric key the sweep varies over a grid", "--plot",
                              f"choose two of: {', '.join(numeric) or '(none: vary two numeric keys)'}")
    if requested[0] == requested[1]:
        raise CamcadError("the region plot needs two different keys", "--plot", "give --plot KEY_X,KEY_Y")
    return requested


def as_number(value: Any) -> Any:
    """A JSON-friendly scalar (numpy → Python; NaN → None)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
