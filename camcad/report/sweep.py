"""The outputs of a sweep a designer looks at: the feasible region, the Pareto front, the best design's scene.

- ``region_figure``: a 2-D slice of the design space (two varied keys), each grid cell coloured by the check
  that fails worst there (or "feasible"), the feasible boundary drawn as a line (the least feasible value of
  the vertical key at each value of the horizontal one), an optional reference curve over it;
- ``pareto_figure``: the feasible designs in the plane of the first two objectives (a third, when given, as
  colour), the non-dominated ones joined, the best one marked;
- the best design written as a scene file (``camcad.report.scene_toml``) that ``camcad profile`` runs as it
  stands.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.io.atomic import write_text_atomic
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.scene import run_scene
from camcad.report.scene_toml import scene_toml
from camcad.scene.pipeline import PipelineOptions
from camcad.sweep import analysis
from camcad.sweep.evaluate import prepared
from camcad.sweep.space import apply_values
from camcad.sweep.store import read_results

#: colours of the failing checks, in order of their counts (the feasible cells are pale green)
FAIL_COLOURS = ("#c62828", "#1565c0", "#ef6c00", "#6a1b9a", "#00838f", "#8d6e63", "#ad1457", "#9e9d24",
                "#455a64", "#f9a825")
FEASIBLE_COLOUR = "#c8e6c9"
ERROR_COLOUR = "#bdbdbd"


def axis_label(key: str, unit: str = "") -> str:
    """An axis label for a varied key: its section and name, its unit, the key itself.

    Examples
    --------
    >>> axis_label("follower.base_radius", "mm"), axis_label("law.phases.rise", "deg")
    ('follower base radius (mm)  [follower.base_radius]', 'rise phase angle (deg)  [law.phases.rise]')
    """
    parts = key.split(".")
    if len(parts) >= 3 and parts[-2] == "phases":
        name = f"{parts[-1]} phase angle"
    else:
        name = " ".join(parts[-2:]).replace("_", " ")
    unit = f" ({unit})" if unit else ""
    return f"{name}{unit}  [{key}]"


def region_figure(x: np.ndarray, y: np.ndarray, labels: np.ndarray, x_label: str, y_label: str,
                  title: str = "", reference: tuple[np.ndarray, np.ndarray, str] | None = None,
                  boundary: list[dict] | None = None, zoom: tuple[float, float, float, float] | None = None):
    """The feasible region of a 2-D slice.

    Parameters
    ----------
    x, y : ndarray
        The two keys' values of each design of the slice (a grid: every (x, y) pair once).
    labels : ndarray of str
        Per design: "feasible", or the name of the check that fails worst ("bad input" for a refused design).
    x_label, y_label : str
        Axis labels with units.
    title : str
        Title (what the slice holds fixed); wrapped to the figure's width.
    reference : (ndarray, ndarray, str), optional
        A curve (x, y, legend text) drawn over the region, e.g. the least base radius solved per rise angle.
    boundary : list of dict, optional
        ``camcad.sweep.analysis.feasible_boundary`` of the slice, drawn half-way between the largest infeasible
        and the least feasible value of each column (not drawn where it lies outside the grid).
    zoom : (x0, x1, y0, y1), optional
        Also show this window enlarged in an inset (the grid's cells, the boundary and the reference).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import textwrap

    from matplotlib.patches import Patch

    xs, ys = unique(x), unique(y)
    failing = [name for name, _ in sorted(_counts(labels).items(), key=lambda kv: -kv[1])
               if name not in ("feasible", "bad input", "internal error")]
    names = ["feasible", *failing] + [n for n in ("bad input", "internal error") if n in set(labels)]
    colours = [FEASIBLE_COLOUR, *[FAIL_COLOURS[i % len(FAIL_COLOURS)] for i in range(len(failing))]] + \
        [ERROR_COLOUR for n in names[1 + len(failing):]]
    code = {name: i for i, name in enumerate(names)}
    grid = np.full((len(ys), len(xs)), np.nan)
    grid[np.searchsorted(ys, y), np.searchsorted(xs, x)] = [code[str(v)] for v in labels]
    fig, ax = new_figure(9.5, 6.0)
    handles = [Patch(facecolor=colours[i], edgecolor="#555555", linewidth=0.5,
                     label=("feasible" if n == "feasible" else f"refused: {n}" if n in ("bad input", "internal error")
                            else f"fails: {n}")) for i, n in enumerate(names)
               if n in set(labels)]
    handles += _draw_region(ax, xs, ys, grid, colours, boundary, reference)
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_xlim(_edges(xs)[0], _edges(xs)[-1])
    ax.set_ylim(_edges(ys)[0], _edges(ys)[-1])
    if zoom is not None:   # each design a dot: the boundary lies between the last failing and the first feasible
        inset = ax.inset_axes([0.52, 0.5, 0.45, 0.46])
        inside = (x >= zoom[0]) & (x <= zoom[1]) & (y >= zoom[2]) & (y <= zoom[3])
        dots = [colours[code[str(v)]] for v in labels[inside]]
        inset.scatter(x[inside], y[inside], c=dots, s=22, edgecolors="#333333", linewidths=0.4, zorder=2)
        if reference is not None:
            inset.plot(reference[0], reference[1], color="#1a237e", linewidth=1.3, linestyle="--", zorder=3)
        inset.set_xlim(zoom[0], zoom[1])
        inset.set_ylim(zoom[2], zoom[3])
        inset.set_facecolor("white")
        inset.tick_params(labelsize=7)
        inset.grid(True, alpha=0.25)
        inset.set_title("enlarged: one dot per design", fontsize=8)
        ax.indicate_inset_zoom(inset, edgecolor="#333333")
    if title:
        ax.set_title("\n".join(textwrap.wrap(title, 90)), fontsize=10)
    fig.legend(handles=handles, loc="outside right upper", fontsize=8, frameon=False)
    return fig


def _draw_region(ax, xs, ys, grid, colours, boundary, reference) -> list:
    """The coloured cells, the boundary and the reference curve on ``ax``; returns the legend's line handles."""
    from matplotlib.colors import ListedColormap

    ax.pcolormesh(_edges(xs), _edges(ys), np.ma.masked_invalid(grid), cmap=ListedColormap(colours),
                  vmin=-0.5, vmax=len(colours) - 0.5, shading="flat")
    handles = []
    if boundary:
        dx = float(np.min(np.diff(xs))) if len(xs) > 1 else 1.0
        px: list[float] = []
        py: list[float] = []
        for b in sorted(boundary, key=lambda e: e["x"]):
            if b["least_feasible"] is None or b["greatest_infeasible"] is None:
                px.append(math.nan)   # the boundary of this column lies outside the grid: not drawn
                py.append(math.nan)
                continue
            level = (b["least_feasible"] + b["greatest_infeasible"]) / 2
            px += [b["x"] - dx / 2, b["x"] + dx / 2]
            py += [level, level]
        if any(math.isfinite(v) for v in px):
            (line,) = ax.plot(px, py, color="black", linewidth=1.4, label="feasible boundary (sweep grid)")
            handles.append(line)
    if reference is not None:
        rx, ry, text = reference
        ax.plot(rx, ry, color="white", linewidth=3.0, zorder=3)
        (line,) = ax.plot(rx, ry, color="#1a237e", linewidth=1.3, linestyle="--", label=text, zorder=4)
        handles.append(line)
    return handles


def _counts(labels: np.ndarray) -> dict[str, int]:
    out: dict[str, int] = {}
    for v in labels:
        out[str(v)] = out.get(str(v), 0) + 1
    return out


def _edges(values: np.ndarray) -> np.ndarray:
    """Cell edges around sorted grid values (half-way between neighbours)."""
    values = np.asarray(values, dtype=float)
    if len(values) == 1:
        half = 0.5 * (abs(values[0]) or 1.0) * 0.1
        return np.array([values[0] - half, values[0] + half])
    mids = (values[1:] + values[:-1]) / 2
    return np.concatenate([[values[0] - (mids[0] - values[0])], mids, [values[-1] + (values[-1] - mids[-1])]])


def pareto_figure(points: dict[str, np.ndarray], front: np.ndarray, best: int | None, objectives: list,
                  labels: dict[str, str], title: str = "", best_label: str = "best design (best.toml)",
                  what: str = "designs"):
    """Feasible designs in the plane of the first two objectives, the Pareto front joined, the best marked.

    Parameters
    ----------
    points : dict
        Columns of the (per grid point) designs: ``feasible`` and each objective's column.
    front : ndarray of int
        Row indices of the Pareto front (``camcad.sweep.analysis.pareto_front``).
    best : int or None
        Row index of the best design.
    objectives : list of Objective
        One to three objectives; the third, if any, colours the points.
    labels : dict
        {column: axis label with unit}.
    title : str
        Title.
    best_label : str
        Legend text of the best design.
    what : str
        What a point is ("designs", or "grid points" for a Monte-Carlo sweep).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure(8.5, 6.0)
    feasible = np.flatnonzero(points["feasible"])
    first = objectives[0].column
    second = objectives[1].column if len(objectives) > 1 else None
    xv = np.asarray(points[first], dtype=float)
    yv = np.asarray(points[second], dtype=float) if second else np.zeros_like(xv)
    if len(objectives) > 2:
        third = objectives[2].column
        art = ax.scatter(xv[feasible], yv[feasible], c=np.asarray(points[third], dtype=float)[feasible], s=10,
                         cmap="viridis", alpha=0.7, label=f"feasible {what}")
        bar = fig.colorbar(art, ax=ax)
        bar.set_label(f"{objectives[2].sense}imise {labels.get(third, third)}", fontsize=8)
    else:
        ax.scatter(xv[feasible], yv[feasible], s=8, color="#9e9e9e", alpha=0.6, label=f"feasible {what}")
    if len(front):
        order = front[np.argsort(xv[front], kind="stable")]
        ax.plot(xv[order], yv[order], color=COLOURS["fail"], marker="o", markersize=4, linewidth=1.2,
                label=f"Pareto front ({len(front)} {what if len(front) != 1 else what[:-1]})")
    if best is not None:
        ax.plot([xv[best]], [yv[best]], marker="*", markersize=16, color="#ffb300", markeredgecolor="black",
                linestyle="none", label=best_label)
    ax.set_xlabel(f"{objectives[0].sense}imise {labels.get(first, first)}")
    if second:
        ax.set_ylabel(f"{objectives[1].sense}imise {labels.get(second, second)}")
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    return fig


# --------------------------------------------------------------------------------------------
# a finished sweep's outputs
# --------------------------------------------------------------------------------------------

def sweep_outputs(folder, plan, tables: dict, base_dir, objectives: list, plot_axes: tuple[str, str] | None = None,
                  plots: bool = True, run_best: bool = True, out=None) -> dict:
    """Read the sweep's results in ``folder`` and write what a designer looks at; return the report's content.

    Writes (into ``folder``): ``region.png`` (feasible region of a 2-D slice), ``pareto.png`` and
    ``pareto.csv`` (the Pareto front of ``objectives`` over the feasible designs), ``best.toml`` (the best
    feasible design as a scene file, its law files named by absolute paths) and ``best/`` (``camcad profile``'s
    outputs for it: profile.dxf, law.csv, report.json, summary page).

    Parameters
    ----------
    folder : Path
        The sweep's output folder.
    plan : camcad.sweep.run.SweepPlan
        The sweep.
    tables : dict
        The scene's own tables (before the task renamed its law files).
    base_dir : Path or None
        Folder of the scene's relative law files.
    objectives : list of camcad.sweep.analysis.Objective
        What "best" means, in order of priority.
    plot_axes : (str, str), optional
        Keys on the horizontal and vertical axes of the region plot (default: the first two numeric grid keys).
    plots : bool
        Draw the PNG files.
    run_best : bool
        Run best.toml through ``camcad profile`` into ``best/``.
    out : OutputFolder, optional
        The locked output folder handing out the paths.

    Returns
    -------
    dict
        ``counts``, ``objectives``, ``best``, ``pareto``, ``region``, ``outputs`` (report.json's keys).
    """
    from pathlib import Path

    folder = Path(folder)
    path = (lambda *parts: out.path(*parts)) if out is not None else (lambda *parts: folder.joinpath(*parts))
    table = read_results(folder)
    cols = analysis.columns(table)
    counts = analysis.summary(cols)
    space = _space(plan)
    grid_keys = [s.key.path for s in space.grid_specs]
    units = dict(plan.units)
    for name in table.column_names:
        meta = table.schema.field(name).metadata or {}
        if b"unit" in meta:
            units.setdefault(name, meta[b"unit"].decode())
    objectives = [o for o in objectives if o.column in cols]
    points = analysis.per_grid_point(cols, space.samples, grid_keys, objectives)
    feasible_rows = np.flatnonzero(points["feasible"])
    labels = {c: _column_label(c, units, plan.keys) for c in [o.column for o in objectives]}
    outputs: list = []
    report: dict[str, Any] = {"counts": counts, "objectives": [o.text for o in objectives],
                              "per_grid_point": space.samples > 1}
    if space.samples > 1:
        report["counts"]["grid_points"] = len(points["design"])
        report["counts"]["grid_points_feasible_in_every_draw"] = int(points["feasible"].sum())
    # Pareto front and best design
    front = np.array([], dtype=np.int64)
    if objectives and len(feasible_rows):
        scores = np.column_stack([np.asarray(points[o.column], dtype=float)[feasible_rows] for o in objectives])
        front = feasible_rows[analysis.pareto_front(scores, [o.sense for o in objectives])]
    best = analysis.best_index(points, objectives)
    report["pareto"] = {"designs": len(front)}
    if len(front):
        csv_path = path("pareto.csv")
        _write_csv(csv_path, points, front, grid_keys, objectives)
        outputs.append(csv_path)
    if best is None:
        report["best"] = None
    else:
        values = {k: analysis.as_number(points[k][best]) for k in grid_keys}
        report["best"] = {"design": int(points["design"][best]), "values": values,
                          "objectives": {o.text: analysis.as_number(points[o.column][best]) for o in objectives},
                          "governing": str(points["governing"][best]),
                          "min_margin_ratio": analysis.as_number(points["min_margin_ratio"][best])}
        if space.samples > 1:
            report["best"]["yield"] = analysis.as_number(points["yield"][best])
        keys = {s.key.path: s.key for s in space.grid_specs}
        best_tables = _absolute_files(apply_values(tables, keys, values), base_dir)
        header = (f"The best feasible design of a camcad sweep (design {int(points['design'][best])}):\n"
                  + "\n".join(f"  {k} = {v}" for k, v in values.items())
                  + f"\nbest by: {', '.join(o.text for o in objectives)}")
        best_path = path("best.toml")

        write_text_atomic(best_path, scene_toml(best_tables, header))
        outputs.append(best_path)
        report["best"]["scene"] = str(best_path)
        if run_best:
            result = run_scene(best_path, PipelineOptions(output=path("best"), plots=("summary",) if plots else ()))
            report["best"]["profile"] = {"passed": bool(result.passed), "folder": str(path("best")),
                                         "tightest": _tightest(result.report)}
            outputs.append(path("best"))
    # the feasible region of a 2-D slice, and the Pareto front
    axes = analysis.region_axes(space, plot_axes)
    if axes is not None:
        fig, report["region"] = _region(points, axes, grid_keys, best, units, space, draw=plots)
        if fig is not None:
            outputs.append(save_figure(fig, path("region.png")))
    if plots and len(objectives) >= 2 and len(feasible_rows):
        title = f"{len(feasible_rows)} feasible of {len(points['design'])} " + \
            ("grid points (feasible in every draw)" if space.samples > 1 else "designs")
        fig = pareto_figure(points, front, best, objectives, labels, title,
                            what="grid points" if space.samples > 1 else "designs")
        outputs.append(save_figure(fig, path("pareto.png")))
    report["outputs"] = [str(p) for p in outputs]
    return report


def _space(plan):
    return prepared(plan.task).space


def _column_label(column: str, units: dict, keys: dict) -> str:
    """An axis label for a results column: a key with its unit, a check's figure with its unit."""
    if column in keys:
        return axis_label(column, units.get(column, ""))
    if column == "min_margin_ratio":
        return "least margin / limit over all checks"
    check, _, part = column.rpartition(".")
    unit = units.get(column, "") if part in ("value", "limit", "margin") else ""
    what = {"margin_ratio": "margin / limit", "value": "", "limit": "limit", "margin": "margin"}.get(part, part)
    return " ".join(x for x in (check, what) if x) + (f" ({unit})" if unit else "")


def _tightest(report: dict) -> list:
    if "mechanisms" in report:
        return [f"{name}/{m['tightest'][0]}" for name, m in report["mechanisms"].items() if m.get("tightest")]
    return list(report.get("tightest", []))[:1]


def _absolute_files(tables: dict, base_dir) -> dict:
    """The tables with every [law] file named by its absolute path (best.toml is written elsewhere)."""
    group = tables.get("mechanisms")
    sections = list(group.values()) if isinstance(group, dict) else [tables]
    for section in sections:
        law = section.get("law") if isinstance(section, dict) else None
        if isinstance(law, dict) and isinstance(law.get("file"), str) and base_dir is not None:
            from pathlib import Path

            law["file"] = str((Path(base_dir) / law["file"]).resolve())
    return tables


def _region(points, axes, grid_keys, best, units, space, draw: bool = True):
    x_key, y_key = axes
    fixed = {}
    mask = np.ones(len(points["design"]), dtype=bool)
    anchor = best if best is not None else 0
    for key in grid_keys:
        if key in axes:
            continue
        value = points[key][anchor]
        fixed[key] = analysis.as_number(value)
        mask &= points[key] == value
    x = np.asarray(points[x_key][mask], dtype=float)
    y = np.asarray(points[y_key][mask], dtype=float)
    feasible = points["feasible"][mask]
    labels = np.where(feasible, "feasible", points["governing"][mask]).astype(object)
    boundary = analysis.feasible_boundary(x, y, feasible)
    region = {"x": x_key, "y": y_key, "fixed": fixed, "boundary": boundary}
    if not draw:
        return None, region
    parts = [f"{k} = {v}" for k, v in fixed.items()]
    what = "grid points feasible in every draw" if space.samples > 1 else "designs"
    title = f"feasible region: {int(feasible.sum())} of {int(mask.sum())} {what}" + \
        (f"; slice at {', '.join(parts)}" if parts else "")
    fig = region_figure(x, y, labels, axis_label(x_key, units.get(x_key, "")), axis_label(y_key, units.get(y_key, "")),
                        title, boundary=boundary)
    return fig, region


def _write_csv(path, points, rows, grid_keys, objectives) -> None:
    import csv
    import io

    # each column once: an objective may be a varied key or min_margin_ratio itself (the default objective)
    columns = list(dict.fromkeys(["design", *grid_keys, *[o.column for o in objectives], "governing",
                                  "min_margin_ratio"]))
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for i in rows:
        writer.writerow([_csv_value(points[c][i]) for c in columns])
    write_text_atomic(path, buffer.getvalue())


def _csv_value(value):
    if isinstance(value, (float, np.floating)):
        return "" if not math.isfinite(float(value)) else repr(float(value))
    if isinstance(value, np.generic):
        return value.item()
    return value
