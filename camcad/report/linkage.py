"""Plots, drawings and output files of ``camcad linkage`` (atlas and fgen).

Figures are ``matplotlib.figure.Figure`` objects (Agg, no pyplot state); DXF drawings are
``camcad.io.dxf_write.Drawing`` objects; ``write_atlas_outputs`` and ``write_fgen_outputs`` write a
command's files atomically into its output folder. Same input, same bytes: no timestamps.

Atlas diagrams follow Sunkuev 1984's Fig. 2 convention: links are vertices, pairs are edges; the links of
an adjustable link are filled vertices and its locked pairs thick edges.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import pairwise
from pathlib import Path

import numpy as np

from camcad.io.atomic import write_atomic, write_text_atomic
from camcad.io.dxf_write import Drawing, DxfCircle, DxfLine, DxfPath, DxfText, write_dxf
from camcad.io.jsonout import write_json
from camcad.linkage.fgen import structural_error
from camcad.linkage.fourbar import joints, transmission_angle
from camcad.linkage.layout import layout
from camcad.linkage.synthesis import error_tolerance
from camcad.profile.followers import arm_angle_on_base_circle
from camcad.report.profile_files import build_drawing

PNG_METADATA = {"Software": None}
FORBIDDEN = "#f4c7c3"
FORBIDDEN_EDGE = "#c0392b"


def _write_dxf(path: Path, drawing: Drawing) -> Path:
    """``write_dxf`` with ezdxf's fixed metadata (no creation time, no random GUIDs): byte-identical files."""
    import ezdxf

    previous = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        return write_dxf(path, drawing)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = previous


def _save_png(fig, path: Path, dpi: int = 130) -> Path:
    return write_atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi, metadata=PNG_METADATA))


# --------------------------------------------------------------------------------------------
# Atlas
# --------------------------------------------------------------------------------------------

def _xy(point) -> tuple[float, float]:
    """A plane point (a pair of numbers) as two floats, mm."""
    return float(point[0]), float(point[1])


def _grid(count: int) -> tuple[int, int]:
    cols = max(1, min(count, math.ceil(math.sqrt(count * 1.4))))
    rows = math.ceil(count / cols)
    return rows, cols


def atlas_figure(chains, layouts, title: str, adjustable: bool):
    """All chains of an atlas in one figure: a cell per chain, numbered as in the JSON list; adjustable
    links as filled vertices and thick locked pairs (Sunkuev 1984, Fig. 2).

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> from camcad.linkage.layout import layout
    >>> r = atlas(4, 1, adjustable=2)
    >>> fig = atlas_figure(r.chains, [layout(c.n, c.edges) for c in r.chains], "n'=4, m=2", True)
    >>> len(fig.axes), len(fig.axes[0].collections)
    (1, 3)
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    rows, cols = _grid(len(chains))
    cell = 1.15 if len(chains) <= 60 else 0.85
    head = 0.95 if adjustable else 0.7
    fig = Figure(figsize=(max(6.5, cols * cell), rows * cell + head))
    ax = fig.add_axes((0.005, 0.005, 0.99, 1 - (head - 0.1) / (rows * cell + head)))
    ax.set_axis_off()
    ax.set_aspect("equal")
    thin: list[list[np.ndarray]] = []
    thick: list[list[np.ndarray]] = []
    points, fills = [], []
    for k, (chain, pos) in enumerate(zip(chains, layouts)):
        r, c = divmod(k, cols)
        origin = np.array([c * 3.0, -r * 3.0])
        p = pos * 1.05 + origin
        locked = set(chain.locked)
        for e in chain.edges:
            (thick if e in locked else thin).append([p[e[0]], p[e[1]]])
        filled = {v for e in chain.locked for v in e}
        for v in range(chain.n):
            points.append(p[v])
            fills.append("black" if v in filled else "white")
        ax.text(origin[0] - 1.35, origin[1] + 1.2, str(k + 1), fontsize=6 if len(chains) > 60 else 7,
                color="#555555", va="center")
    ax.add_collection(LineCollection(thin, colors="black", linewidths=0.8, zorder=1))
    if thick:
        ax.add_collection(LineCollection(thick, colors="black", linewidths=3.0, zorder=1))
    ax.set_xlim(-1.6, cols * 3.0 - 1.4)
    ax.set_ylim(-(rows - 1) * 3.0 - 1.6, 1.6)
    # vertex size: a radius of 0.16 data units in points (equal aspect: the tighter of the two scales)
    box = ax.get_position()
    x_range = cols * 3.0 - 1.4 + 1.6
    y_range = (rows - 1) * 3.0 + 3.2
    per_unit = min(box.width * fig.get_figwidth() * 72 / x_range, box.height * fig.get_figheight() * 72 / y_range)
    radius_pt = 0.16 * per_unit
    pts = np.array(points)
    ax.scatter(pts[:, 0], pts[:, 1], s=(2 * radius_pt) ** 2, c=fills, edgecolors="black", linewidths=0.8, zorder=2)
    legend = "links: vertices, pairs: edges"
    if adjustable:
        legend += "\nadjustable link: filled vertices and thick (locked) pairs (Sunkuev 1984, Fig. 2)"
    fig.suptitle(f"{title}\n{legend}", fontsize=9)
    return fig


def atlas_drawing(chains, layouts, title: str, adjustable: bool, cell_mm: float = 40.0) -> Drawing:
    """The atlas as a DXF drawing: one diagram per chain in a grid of ``cell_mm`` cells.

    Layers: ATLAS_PAIR (pairs, lines), ATLAS_LINK (links, circles), ATLAS_LOCKED_PAIR (locked pairs drawn
    thick: a closed outline 1.6 mm wide), ATLAS_ADJUSTABLE_LINK (links of an adjustable link drawn filled:
    concentric circles), ATLAS_TEXT (numbers and title).

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> from camcad.linkage.layout import layout
    >>> r = atlas(4, 1, adjustable=1)                 # the five-bar with one locked pair
    >>> d = atlas_drawing(r.chains, [layout(c.n, c.edges) for c in r.chains], "n'=4, m=1", True)
    >>> len(d.lines), len(d.paths), len(d.circles)    # 4 free pairs, 1 locked band, 3 + 2 x 4 circles
    (4, 1, 11)
    """
    _, cols = _grid(len(chains))
    radius = 0.06 * cell_mm
    scale = 0.36 * cell_mm
    lines, circles, paths, texts = [], [], [], []
    for k, (chain, pos) in enumerate(zip(chains, layouts)):
        r, c = divmod(k, cols)
        origin = np.array([c * cell_mm, -r * cell_mm])
        p = pos * scale + origin
        locked = set(chain.locked)
        filled = {v for e in chain.locked for v in e}
        for u, v in chain.edges:
            a, b = p[u], p[v]
            d = b - a
            length = float(np.hypot(*d))
            if length == 0:
                continue
            unit = d / length
            start, end = a + unit * radius, b - unit * radius
            if (u, v) in locked:
                normal = np.array([-unit[1], unit[0]]) * 0.8
                band = np.array([start + normal, end + normal, end - normal, start - normal])
                paths.append(DxfPath("ATLAS_LOCKED_PAIR", band, True))
            else:
                lines.append(DxfLine("ATLAS_PAIR", tuple(start), tuple(end)))
        for v in range(chain.n):
            centre = (float(p[v][0]), float(p[v][1]))
            if v in filled:
                for f in (1.0, 0.75, 0.5, 0.25):
                    circles.append(DxfCircle("ATLAS_ADJUSTABLE_LINK", centre, radius * f))
            else:
                circles.append(DxfCircle("ATLAS_LINK", centre, radius))
        texts.append(DxfText("ATLAS_TEXT", str(k + 1), (float(origin[0] - 0.48 * cell_mm),
                                                         float(origin[1] + 0.4 * cell_mm)), 2.5))
    texts.append(DxfText("ATLAS_TEXT", title, (-0.5 * cell_mm, 0.62 * cell_mm), 3.5))
    layers = ("ATLAS_PAIR", "ATLAS_LINK", "ATLAS_TEXT") + (("ATLAS_LOCKED_PAIR", "ATLAS_ADJUSTABLE_LINK")
                                                           if adjustable else ())
    return Drawing(paths=tuple(paths), circles=tuple(circles), lines=tuple(lines), texts=tuple(texts), layers=layers)


def atlas_csv(payload: dict) -> str:
    """One CSV row per chain: index, links, pairs (u-v), assortment, locked pairs, fractionated.

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> atlas_csv(atlas(4, 1).payload).splitlines()[1]
    '1,4,0-1 0-2 1-3 2-3,n2=4,,false'
    """
    lines = ["index,links,pairs,assortment,locked_pairs,fractionated"]
    for item in payload["chains"]:
        pairs = " ".join(f"{u}-{v}" for u, v in item["pairs"])
        locked = " ".join(f"{u}-{v}" for u, v in item.get("locked_pairs", []))
        assortment = " ".join(f"n{k}={v}" for k, v in item["assortment"].items())
        lines.append(f"{item['index']},{item['links']},{pairs},{assortment},{locked},{str(item['fractionated']).lower()}")
    return "\n".join(lines) + "\n"


def atlas_title(payload: dict) -> str:
    """The atlas's title: class, count and the reference count (Sunkuev 1984, Table 1 or published).

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> atlas_title(atlas(6, 1, adjustable=1).payload)
    "adjustable chains n'=6, W'=1, m=1: 7 (Sunkuev 1984, Table 1: 7)"
    """
    if payload["kind"] == "adjustable":
        head = (f"adjustable chains n'={payload['links']}, W'={payload['dof']}, m={payload['adjustable']}: "
                f"{payload['count']}")
        if "seed_count" in payload:
            head += f" (Sunkuev 1984, Table 1: {payload['seed_count']})"
        return head
    head = f"ordinary chains n={payload['links']}, W={payload['dof']}: {payload['count']}"
    if "published_count" in payload:
        head += f" (published: {payload['published_count']})"
    return head


def _scheme_cells(report, cell: float = 3.0):
    """(origin, scheme, chain) per chain on the atlas grid (the same cells as the graphs)."""
    rows, cols = _grid(len(report.chains))
    for k, (chain, sch) in enumerate(zip(report.chains, report.schemes)):
        r, c = divmod(k, cols)
        yield k, np.array([c * cell, -r * cell]), sch, chain
    del rows


def schemes_figure(report, title: str):
    """Every chain of the atlas as a kinematic scheme (stage 4): links as bars and plates through their joints,
    the frame hatched, the input marked with an arrow, an adjustable link filled with its locked pairs as squares.

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> from camcad.linkage.schemes import annotate_schemes
    >>> r = atlas(4, 1, adjustable=1)
    >>> annotate_schemes(r)
    >>> len(schemes_figure(r, "n'=4, m=1").axes)
    1
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    rows, cols = _grid(len(report.chains))
    cell = 1.3 if len(report.chains) <= 60 else 0.9
    fig = Figure(figsize=(max(6.5, cols * cell), rows * cell + 1.0))
    ax = fig.add_axes((0.005, 0.005, 0.99, 1 - 0.9 / (rows * cell + 1.0)))
    ax.set_axis_off()
    ax.set_aspect("equal")
    for k, origin, sch, chain in _scheme_cells(report):
        pts = sch.joints * 1.05 + origin
        adjustable = {v for g in sch.adjustable for v in g}
        locked = set(chain.locked)
        for link, poly in enumerate(sch.polygons):
            xy = pts[list(poly)]
            face = "#bdbdbd" if link in adjustable else ("#f3e3b5" if link == sch.frame else "white")
            hatch = "////" if link == sch.frame else None
            if len(poly) == 2:
                ax.plot(xy[:, 0], xy[:, 1], color="#8c8c8c" if link in adjustable else "black",
                        lw=4.0 if link in adjustable else 2.6 if link == sch.frame else 1.4, solid_capstyle="round",
                        zorder=2)
            else:
                ax.add_patch(Polygon(xy, closed=True, facecolor=face, edgecolor="black", lw=1.0, hatch=hatch,
                                     zorder=1))
            if link == sch.input:
                mid = xy.mean(axis=0)
                ax.annotate("", xy=mid + (0.25, 0.25), xytext=mid, arrowprops={"arrowstyle": "->", "lw": 0.9},
                            zorder=4)
        for j, e in enumerate(chain.edges):
            if e in locked:
                ax.plot(*pts[j], "s", ms=4.5, color="black", zorder=3)
            else:
                ax.plot(*pts[j], "o", ms=4.0, mfc="white", mec="black", mew=0.9, zorder=3)
        ax.text(origin[0] - 1.35, origin[1] + 1.2, str(k + 1), fontsize=6 if len(report.chains) > 60 else 7,
                color="#555555", va="center")
    ax.set_xlim(-1.6, cols * 3.0 - 1.4)
    ax.set_ylim(-(rows - 1) * 3.0 - 1.6, 1.6)
    fig.suptitle(f"{title}: kinematic schemes\nframe hatched, input arrowed, adjustable link grey with "
                 "locked pairs as squares", fontsize=9)
    return fig


def schemes_drawing(report, title: str, cell_mm: float = 40.0) -> Drawing:
    """The kinematic schemes as DXF (mm, ``cell_mm`` per chain): SCHEME_LINK (bars and plate outlines),
    SCHEME_FRAME (the frame's outline and its ground hatch), SCHEME_INPUT (the input's arrow),
    SCHEME_ADJUSTABLE (adjustable links' outlines), SCHEME_JOINT (circles; locked pairs as squares on
    SCHEME_LOCKED), ATLAS_TEXT (numbers and the title).

    Examples
    --------
    >>> from camcad.linkage.atlas import atlas
    >>> from camcad.linkage.schemes import annotate_schemes
    >>> r = atlas(4, 1, adjustable=2)
    >>> annotate_schemes(r)
    >>> sorted({c.layer for c in schemes_drawing(r, "t").circles})
    ['SCHEME_JOINT']
    """
    scale = cell_mm / 3.0
    lines, circles, texts = [], [], []
    r = 0.09 * scale
    for k, origin, sch, chain in _scheme_cells(report):
        pts = (sch.joints * 1.05 + origin) * scale
        adjustable = {v for g in sch.adjustable for v in g}
        locked = set(chain.locked)
        for link, poly in enumerate(sch.polygons):
            layer = ("SCHEME_FRAME" if link == sch.frame else "SCHEME_ADJUSTABLE" if link in adjustable
                     else "SCHEME_LINK")
            ring = list(poly) + ([poly[0]] if len(poly) > 2 else [])
            for a, b in pairwise(ring):
                lines.append(DxfLine(layer, _xy(pts[a]), _xy(pts[b])))
            if link == sch.frame:
                base = pts[list(poly)].mean(axis=0)
                for j in range(4):
                    x0 = base[0] - 1.5 * r + j * r
                    lines.append(DxfLine("SCHEME_FRAME", (float(x0), float(base[1] - 2 * r)),
                                         (float(x0 - 0.7 * r), float(base[1] - 2.7 * r))))
            if link == sch.input:
                mid = pts[list(poly)].mean(axis=0)
                tip = mid + np.array([3 * r, 3 * r])
                lines.append(DxfLine("SCHEME_INPUT", _xy(mid), _xy(tip)))
                lines.append(DxfLine("SCHEME_INPUT", _xy(tip), (float(tip[0] - r), float(tip[1]))))
                lines.append(DxfLine("SCHEME_INPUT", _xy(tip), (float(tip[0]), float(tip[1] - r))))
        for j, e in enumerate(chain.edges):
            x, y = map(float, pts[j])
            if e in locked:
                square = [(x - r, y - r), (x + r, y - r), (x + r, y + r), (x - r, y + r), (x - r, y - r)]
                lines += [DxfLine("SCHEME_LOCKED", a, b) for a, b in pairwise(square)]
            else:
                circles.append(DxfCircle("SCHEME_JOINT", (x, y), r))
        texts.append(DxfText("ATLAS_TEXT", str(k + 1), (float((origin[0] - 1.35) * scale),
                                                       float((origin[1] + 1.2) * scale)), 0.12 * scale))
    texts.append(DxfText("ATLAS_TEXT", title, (-1.6 * scale, 2.0 * scale), 0.15 * scale))
    return Drawing(circles=tuple(circles), lines=tuple(lines), texts=tuple(texts),
                   layers=("SCHEME_LINK", "SCHEME_FRAME", "SCHEME_INPUT", "SCHEME_ADJUSTABLE", "SCHEME_JOINT",
                           "SCHEME_LOCKED", "ATLAS_TEXT"))


def write_atlas_outputs(out_dir: Path, report, plots: bool = True) -> list[Path]:
    """Write atlas.json, atlas.csv, atlas.dxf and (unless ``plots`` is False) atlas.png into ``out_dir``
    (atomically, byte-identical for the same input); returns the paths.

    Examples
    --------
    >>> import tempfile
    >>> from camcad.linkage.atlas import atlas
    >>> sorted(p.name for p in write_atlas_outputs(Path(tempfile.mkdtemp()), atlas(4, 1), plots=False))
    ['atlas.csv', 'atlas.dxf', 'atlas.json']
    """
    out_dir = Path(out_dir)
    payload = report.payload
    layouts = [layout(chain.n, chain.edges) for chain in report.chains]
    title = atlas_title(payload)
    written = [write_text_atomic(out_dir / "atlas.csv", atlas_csv(payload)),
               _write_dxf(out_dir / "atlas.dxf", atlas_drawing(report.chains, layouts, title, report.adjustable))]
    if report.schemes:
        written.append(_write_dxf(out_dir / "schemes.dxf", schemes_drawing(report, title)))
    if plots:
        fig = atlas_figure(report.chains, layouts, title, report.adjustable)
        written.append(_save_png(fig, out_dir / "atlas.png", dpi=110 if len(report.chains) > 100 else 140))
        if report.schemes:
            written.append(_save_png(schemes_figure(report, title), out_dir / "schemes.png",
                                     dpi=110 if len(report.chains) > 100 else 140))
    payload["outputs"] = [str(p) for p in written] + [str(out_dir / "atlas.json")]
    written.append(write_json(out_dir / "atlas.json", payload))
    return written


# --------------------------------------------------------------------------------------------
# Function generator
# --------------------------------------------------------------------------------------------

def error_figure(result):
    """Structural error (deg) against the input angle with the nodes marked, and the transmission angle
    with its limit (forbidden bands shaded).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0))
    >>> [ax.get_ylabel() for ax in error_figure(r).axes[:2]]
    ['output angle error Δψ (deg)', 'μ (deg)']
    """
    from matplotlib.figure import Figure

    ev, t = result.evaluation, result.target
    phi = np.degrees(ev.phi)
    err = np.degrees(ev.error)
    fig = Figure(figsize=(8.5, 6.2), layout="constrained")
    ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    ax.axhline(0, color="grey", lw=0.6)
    ax.plot(phi, err, color="#1f4e9c", lw=1.4, label="structural error")
    nodes_deg = np.degrees(result.nodes_phi)
    # each node where the error is (the Q method's centre pivot, least squares and minimax do not interpolate)
    node_err = np.degrees(structural_error(result.mechanism, t, result.nodes_phi)) if len(nodes_deg) else nodes_deg
    if result.method == "remez":
        ax.plot(nodes_deg, node_err, "s", color="#c0392b", ms=5, label=f"{len(nodes_deg)} reference points")
    elif len(nodes_deg) <= 12:
        ax.plot(nodes_deg, node_err, "o", color="#c0392b", ms=5, label=f"{len(nodes_deg)} interpolation nodes")
    elif len(nodes_deg):
        ax.plot(nodes_deg, node_err, "|", color="#c0392b", ms=8, label=f"{len(nodes_deg)} fitting points")
    tolerance = error_tolerance(result.options, t)
    if tolerance <= 4 * max(float(np.max(np.abs(err))), 1e-300):
        ax.axhline(tolerance, color=FORBIDDEN_EDGE, lw=0.8, ls="--", label=f"tolerance ±{tolerance:.3g} deg")
        ax.axhline(-tolerance, color=FORBIDDEN_EDGE, lw=0.8, ls="--")
    k = int(np.argmax(np.abs(err)))
    ax.plot(phi[k], err[k], "D", color="black", ms=5, label="largest |error|")
    ax.set_ylabel("output angle error Δψ (deg)")
    ax.set_title(f"{result.method}: {t.label} on [{t.x0:g}, {t.x1:g}], input {t.input_range_deg:g} deg, "
                 f"output {t.output_range_deg:g} deg\nmax |error| {abs(err[k]):.4g} deg at φ = {phi[k]:.1f} deg, "
                 f"RMS {ev.rms_error_deg:.3g} deg", fontsize=10)
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    top = ax.secondary_xaxis("top", functions=(lambda p: t.x0 + (t.x1 - t.x0) * p / t.input_range_deg,
                                               lambda x: (x - t.x0) / (t.x1 - t.x0) * t.input_range_deg))
    top.set_xlabel("x", fontsize=8)
    fg = result.mechanism

    mu = np.degrees(transmission_angle(fg.a, fg.b, fg.c, fg.d, fg.phi0 + ev.phi))
    limit = result.options.limits.mu_min_deg
    ax2.axhspan(0, limit, color=FORBIDDEN, lw=0, label=f"below μ_min = {limit:g} deg")
    ax2.axhspan(180 - limit, 180, color=FORBIDDEN, lw=0)
    ax2.plot(phi, mu, color="#2d7f3b", lw=1.3, label="transmission angle μ")
    ax2.set_ylim(0, 180)
    ax2.set_yticks([0, 30, 60, 90, 120, 150, 180])
    ax2.set_ylabel("μ (deg)")
    ax2.set_xlabel("input angle φ from the first position (deg)")
    ax2.grid(True, lw=0.4, alpha=0.6)
    ax2.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax2.set_title(f"worst min(μ, 180−μ) = {ev.mu_min_deg:.2f} deg (limit {limit:g}, margin "
                  f"{ev.mu_min_deg - limit:+.2f})", fontsize=9)
    return fig


def sixbar_error_figure(result, payload: dict):
    """A six-bar function generator (``camcad.linkage.sixbar``): structural error (deg) against the input
    angle with the nodes where the error is, and the transmission angle of each loop with the limit.

    Examples
    --------
    >>> from camcad.linkage.sixbar import SixbarOptions, report, synthesize_sixbar
    >>> from camcad.linkage.target import make_target
    >>> r = synthesize_sixbar(make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)"), SixbarOptions(scan=500, keep=1))
    >>> [ax.get_ylabel() for ax in sixbar_error_figure(r, report(r)).axes[:2]]
    ['output angle error Δψ (deg)', 'μ (deg)']
    """
    from matplotlib.figure import Figure

    t = result.target
    phi = np.degrees(result.phi)
    err = np.degrees(result.error)
    fig = Figure(figsize=(8.5, 6.2), layout="constrained")
    ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    ax.axhline(0, color="grey", lw=0.6)
    ax.plot(phi, err, color="#1f4e9c", lw=1.4, label="structural error")
    ax.plot(payload["nodes_deg"], payload["node_errors_deg"], "o", color="#c0392b", ms=5,
            label=f"{len(payload['nodes_deg'])} nodes (F at the centre: not exact)")
    tolerance = payload["max_error_tolerance_deg"]
    if tolerance <= 4 * max(float(np.max(np.abs(err))), 1e-300):
        ax.axhline(tolerance, color=FORBIDDEN_EDGE, lw=0.8, ls="--", label=f"tolerance ±{tolerance:.3g} deg")
        ax.axhline(-tolerance, color=FORBIDDEN_EDGE, lw=0.8, ls="--")
    k = int(np.argmax(np.abs(err)))
    ax.plot(phi[k], err[k], "D", color="black", ms=5, label="largest |error|")
    ax.set_ylabel("output angle error Δψ (deg)")
    ax.set_title(f"six-bar, Q method: {t.label} on [{t.x0:g}, {t.x1:g}], input {t.input_range_deg:g} deg, "
                 f"output {t.output_range_deg:g} deg\nmax |error| {abs(err[k]):.4g} deg at φ = {phi[k]:.1f} deg, "
                 f"RMS {result.rms_error_deg:.3g} deg", fontsize=10)
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    lk = result.linkage
    mus = lk.transmission(np.abs(result.phi))
    limit = result.options.limits.mu_min_deg
    ax2.axhspan(0, limit, color=FORBIDDEN, lw=0, label=f"below μ_min = {limit:g} deg")
    ax2.axhspan(180 - limit, 180, color=FORBIDDEN, lw=0)
    for mu, colour, name in zip(mus, ("#2d7f3b", "#7b3294"), ("loop 1 (OABC)", "loop 2 (CDEF)")):
        ax2.plot(phi, np.degrees(mu), color=colour, lw=1.3, label=f"μ {name}")
    ax2.set_ylim(0, 180)
    ax2.set_yticks([0, 30, 60, 90, 120, 150, 180])
    ax2.set_ylabel("μ (deg)")
    ax2.set_xlabel("input angle φ from the first position (deg)")
    ax2.grid(True, lw=0.4, alpha=0.6)
    ax2.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    m1, m2 = result.mu_deg
    ax2.set_title(f"worst min(μ, 180−μ): loop 1 {m1:.2f} deg, loop 2 {m2:.2f} deg (limit {limit:g})", fontsize=9)
    return fig


def pivot_figure(result):
    """The Q method's signature picture: the circles of possible output pivots (one per node ≥ 2), the K
    pivots of the node subsets, their bounding rectangle and its diagonal Q (zoomed on the right).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> fig = pivot_figure(synthesize(t, FgenOptions(method="q")))
    >>> fig.axes[1].get_title()
    'zoom: Q = diagonal = 9.526e-04 crank lengths (2 subsets)'
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Rectangle

    q = result.q
    st = q.state
    fig = Figure(figsize=(11, 5.2), layout="constrained")
    ax, zoom = fig.subplots(1, 2)
    pts = np.array([[c.real, c.imag] for c in st.pivots])
    colours = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]
    phi = np.asarray(result.q_nodes_phi)
    a_pts = np.exp(1j * (phi - phi[0]))
    b_1 = a_pts[0] + st.b * np.exp(1j * st.alpha)
    for k, (centre, radius) in enumerate(st.circles, start=2):
        for axis in (ax, zoom):
            axis.add_patch(Circle((centre.real, centre.imag), radius, fill=False, lw=0.9,
                                  color=colours[(k - 2) % len(colours)], label=f"pivots keeping node {k}"
                                  if axis is ax else None))
    centre_pt = complex((max(c.real for c in st.pivots) + min(c.real for c in st.pivots)) / 2,
                        (max(c.imag for c in st.pivots) + min(c.imag for c in st.pivots)) / 2)
    ax.plot([0, centre_pt.real], [0, centre_pt.imag], color="black", lw=2.5, alpha=0.35, label="frame OC")
    ax.plot([0, a_pts[0].real], [0, a_pts[0].imag], color="black", lw=2, label="crank OA1, coupler A1B1")
    ax.plot([a_pts[0].real, b_1.real], [a_pts[0].imag, b_1.imag], color="black", lw=1.2)
    ax.plot([centre_pt.real, b_1.real], [centre_pt.imag, b_1.imag], color="black", lw=1.2, ls="--",
            label="rocker CB1")
    ax.plot(a_pts.real, a_pts.imag, "k.", ms=4)
    for k, a_k in enumerate(a_pts[1:], start=2):
        ax.annotate(f"A{k}", (a_k.real, a_k.imag), textcoords="offset points", xytext=(4, 2), fontsize=7)
    ax.annotate("O", (0, 0), textcoords="offset points", xytext=(-10, -10), fontsize=9)
    ax.annotate("A1", (a_pts[0].real, a_pts[0].imag), textcoords="offset points", xytext=(4, -10), fontsize=9)
    ax.annotate("B1", (b_1.real, b_1.imag), textcoords="offset points", xytext=(4, 4), fontsize=9)
    centre = np.array([(pts[:, 0].max() + pts[:, 0].min()) / 2, (pts[:, 1].max() + pts[:, 1].min()) / 2])
    ax.plot(*pts.T, "o", color="#c0392b", ms=5, label="pivots C of the subsets")
    xs_all = np.r_[pts[:, 0], 0.0, b_1.real, a_pts.real]
    ys_all = np.r_[pts[:, 1], 0.0, b_1.imag, a_pts.imag]
    span = max(np.ptp(xs_all), np.ptp(ys_all), 2.0)
    mid = np.array([(xs_all.max() + xs_all.min()) / 2, (ys_all.max() + ys_all.min()) / 2])
    ax.set_xlim(mid[0] - 0.75 * span, mid[0] + 0.75 * span)
    ax.set_ylim(mid[1] - 0.75 * span, mid[1] + 0.75 * span)
    ax.set_aspect("equal")
    ax.set_title("circles of output pivots C (crank OA = 1 at node 1)", fontsize=10)
    ax.set_xlabel("x (crank lengths)")
    ax.set_ylabel("y (crank lengths)")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.12), ncol=2)
    # the zoom never goes below 1e-6 of the pivot's distance: below that the K pivots coincide for any drawing
    # (and matplotlib cannot place ticks on a span near the floating-point resolution)
    half = max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]), 1e-6 * max(1.0, float(np.hypot(*pts.mean(axis=0))))) * 1.6
    zoom.add_patch(Rectangle((pts[:, 0].min(), pts[:, 1].min()), np.ptp(pts[:, 0]), np.ptp(pts[:, 1]),
                             fill=False, ls="--", color="black", lw=0.9))
    zoom.plot([pts[:, 0].min(), pts[:, 0].max()], [pts[:, 1].min(), pts[:, 1].max()], color="#c0392b", lw=1.4)
    labels = ["C" + "".join(str(i) for i in s) for s in result.q_subsets]
    if max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1])) < 0.05 * half:     # the pivots coincide at this scale
        zoom.plot(*pts[0], "o", color="#c0392b", ms=6)
        zoom.annotate(" = ".join(labels), tuple(pts[0]), textcoords="offset points", xytext=(6, 6), fontsize=9)
    else:
        for (x, y), label in zip(pts, labels):
            zoom.plot(x, y, "o", color="#c0392b", ms=6)
            zoom.annotate(label, (x, y), textcoords="offset points", xytext=(5, 5), fontsize=9)
    zoom.plot(*centre, "+", color="black", ms=12, mew=1.5)
    zoom.annotate("pivot taken" if q.pick == "centre" else "rectangle centre", tuple(centre),
                  textcoords="offset points", xytext=(6, -14), fontsize=8)
    zoom.set_xlim(centre[0] - half, centre[0] + half)
    zoom.set_ylim(centre[1] - half, centre[1] + half)
    zoom.set_aspect("equal")
    zoom.ticklabel_format(useOffset=True, style="sci", scilimits=(-3, 3))
    zoom.grid(True, lw=0.4, alpha=0.5)
    zoom.set_title(f"zoom: Q = diagonal = {st.q:.3e} crank lengths ({len(st.pivots)} subsets)", fontsize=10)
    zoom.set_xlabel("x (crank lengths)")
    fig.suptitle(f"Q method (Sunkuev 1984): free parameters b/a = {st.b:.5g}, α = "
                 f"{math.degrees(st.alpha) % 360:.3f} deg", fontsize=10)
    return fig


def _positions(fg, theta):
    return joints(fg.a, fg.b, fg.c, fg.d, theta, fg.branch)


def positions_figure(result):
    """The linkage in its two extreme positions of the working range (and faint intermediate ones), in mm.

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0))
    >>> positions_figure(r).axes[0].get_xlabel()
    'x (mm)'
    """
    from matplotlib.figure import Figure

    fg, t = result.mechanism, result.target
    fig = Figure(figsize=(8.5, 6.0), layout="constrained")
    ax = fig.subplots()
    thetas = fg.phi0 + np.linspace(0.0, t.dphi, 9)
    for k, theta in enumerate(thetas):
        j = _positions(fg, theta)
        if not np.all(np.isfinite(j["B"])):
            continue
        xs = [j["O"][0], j["A"][0], j["B"][0], j["C"][0]]
        ys = [j["O"][1], j["A"][1], j["B"][1], j["C"][1]]
        end = k in (0, len(thetas) - 1)
        ax.plot(xs, ys, "-o", color=("#1f4e9c" if k == 0 else "#c0392b") if end else "#bbbbbb",
                lw=2.0 if end else 0.7, ms=5 if end else 2, zorder=3 if end else 1,
                label=("first position (φ = 0)" if k == 0 else f"last position (φ = {t.input_range_deg:g} deg)")
                if end else None)
    path = np.linspace(0.0, t.dphi, 200) + fg.phi0
    j = _positions(fg, path)
    ax.plot(j["A"][:, 0], j["A"][:, 1], color="#1f4e9c", lw=0.6, ls=":")
    ax.plot(j["B"][:, 0], j["B"][:, 1], color="#c0392b", lw=0.6, ls=":")
    ax.plot([0, fg.d], [0, 0], color="black", lw=2.5, solid_capstyle="butt")
    for name, point in (("O", (0.0, 0.0)), ("C", (fg.d, 0.0))):
        ax.plot(*point, "^", color="black", ms=11, zorder=4)
        ax.annotate(name, point, textcoords="offset points", xytext=(-4, -18), fontsize=10)
    j0 = _positions(fg, fg.phi0)
    for name in ("A", "B"):
        ax.annotate(name + "₀", tuple(j0[name]), textcoords="offset points", xytext=(6, 6), fontsize=10,
                    color="#1f4e9c")
    ax.set_aspect("equal")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title(f"OA = {fg.a:.2f}, AB = {fg.b:.2f}, CB = {fg.c:.2f}, OC = {fg.d:.2f} mm; "
                 f"{result.evaluation.grashof}, branch {fg.branch:+d}", fontsize=10)
    return fig


def fgen_drawing(result) -> Drawing:
    """The kinematic diagram as DXF: FRAME (frame line and ground marks), LINKS (first position),
    EXTREME_POSITIONS (last position), JOINTS (pair circles), PATHS (paths of A and B), TEXT; mm.

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0))
    >>> d = fgen_drawing(r)
    >>> sorted({x.layer for x in d.lines}), len(d.circles), len(d.paths)
    (['EXTREME_POSITIONS', 'FRAME', 'LINKS'], 8, 2)
    """
    fg, t = result.mechanism, result.target
    scale = max(fg.a, fg.b, fg.c, fg.d)
    r = 0.025 * scale
    lines, circles, paths, texts = [], [], [], []
    h = 0.03 * scale

    def trimmed(layer, p, q):
        """The line p–q shortened by the joint radius at both ends (links meet the joint circles)."""
        d = np.subtract(q, p)
        length = float(np.hypot(*d))
        if length <= 2 * r:
            return None
        u = d / length
        return DxfLine(layer, tuple(map(float, np.add(p, r * u))), tuple(map(float, np.subtract(q, r * u))))

    lines.append(trimmed("FRAME", (0.0, 0.0), (fg.d, 0.0)))
    for x0 in (0.0, fg.d):
        lines.append(DxfLine("FRAME", (x0 - 2 * r, -1.6 * r), (x0 + 2 * r, -1.6 * r)))
        lines.append(DxfLine("FRAME", (x0, -r), (x0, -1.6 * r)))
        for k in range(5):
            xa = x0 - 2 * r + k * r
            lines.append(DxfLine("FRAME", (xa, -1.6 * r), (xa - 0.7 * r, -2.3 * r)))
    for layer, theta in (("LINKS", fg.phi0), ("EXTREME_POSITIONS", fg.phi0 + t.dphi)):
        j = _positions(fg, theta)
        pts = [(float(j[name][0]), float(j[name][1])) for name in ("O", "A", "B", "C")]
        for p, q in pairwise(pts):
            lines.append(trimmed(layer, p, q))
        for p in pts:
            circles.append(DxfCircle("JOINTS", p, r))
        suffix = "1" if layer == "LINKS" else "2"
        for name, p in zip(("A", "B"), pts[1:3]):
            texts.append(DxfText("TEXT", name + suffix, (p[0] + 1.5 * r, p[1] + 1.5 * r), h))
    path = fg.phi0 + np.linspace(0.0, t.dphi, 90)
    j = _positions(fg, path)
    for name in ("A", "B"):
        paths.append(DxfPath("PATHS", np.asarray(j[name], dtype=float), False))
    texts.append(DxfText("TEXT", "O", (-3 * r, 1.5 * r), h))
    texts.append(DxfText("TEXT", "C", (fg.d + 1.5 * r, 1.5 * r), h))
    offsets = (f"phi0 {math.degrees(fg.phi0) % 360:.3f} deg  psi0 {math.degrees(fg.psi0) % 360:.3f} deg  "
               f"input {t.input_range_deg:g} deg  output {t.output_range_deg:g} deg")
    accuracy = (f"max error {result.evaluation.max_error_deg:.4g} deg  min transmission angle "
                f"{result.evaluation.mu_min_deg:.2f} deg")
    info = [f"four-bar function generator: {t.label}, x {t.x0:g}..{t.x1:g}, method {result.method}",
            f"OA {fg.a:.3f}  AB {fg.b:.3f}  CB {fg.c:.3f}  OC {fg.d:.3f} mm", offsets, accuracy]
    low = min(0.0, float(np.nanmin(np.r_[j["A"][:, 1], j["B"][:, 1]]))) - 6 * r
    for k, line in enumerate(info):
        texts.append(DxfText("TEXT", line, (0.0, low - k * 1.8 * h), h))
    return Drawing(paths=tuple(paths), circles=tuple(circles), lines=tuple(x for x in lines if x is not None),
                   texts=tuple(texts), layers=("FRAME", "LINKS", "EXTREME_POSITIONS", "JOINTS", "PATHS", "TEXT"))


def error_csv(result) -> str:
    """The structural error as CSV: φ (deg), x, ψ_target and ψ of the mechanism (deg), error (deg).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0))
    >>> error_csv(r).splitlines()[1]
    'phi_deg,x,psi_target_deg,psi_deg,error_deg'
    """
    ev, t = result.evaluation, result.target
    phi = ev.phi[::10] if len(ev.phi) > 1000 else ev.phi
    err = ev.error[::10] if len(ev.phi) > 1000 else ev.error
    lines = ["# phi_deg: input angle from the first position; psi_deg: output angle from the first position",
             "phi_deg,x,psi_target_deg,psi_deg,error_deg"]
    for p, e in zip(phi, err):
        target = math.degrees(float(t.psi(p)))
        lines.append(f"{math.degrees(p):.10g},{float(t.x_of(p)):.10g},{target:.10g},{target + math.degrees(e):.10g},"
                     f"{math.degrees(e):.10g}")
    return "\n".join(lines) + "\n"


def write_fgen_outputs(out_dir: Path, result, payload: dict, plots: bool = True, prefix: str = "") -> list[Path]:
    """Write fgen.json, error.csv, linkage.dxf and the PNG plots (error, positions and, for the Q method,
    pivots) into ``out_dir``; ``prefix`` names the files of one method when several are written.

    Examples
    --------
    >>> import tempfile
    >>> from camcad.linkage.synthesis import report
    >>> import numpy as np
    >>> from camcad.linkage.synthesis import FgenOptions, synthesize
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize(t, FgenOptions(method="precision", phi0_deg=45.0, psi0_deg=135.0))
    >>> files = write_fgen_outputs(Path(tempfile.mkdtemp()), r, report(r), plots=False)
    >>> sorted(p.name for p in files)
    ['error.csv', 'fgen.json', 'linkage.dxf']
    """
    out_dir = Path(out_dir)
    written = [write_text_atomic(out_dir / f"{prefix}error.csv", error_csv(result)),
               _write_dxf(out_dir / f"{prefix}linkage.dxf", fgen_drawing(result))]
    if plots:
        written.append(_save_png(error_figure(result), out_dir / f"{prefix}error.png"))
        written.append(_save_png(positions_figure(result), out_dir / f"{prefix}positions.png"))
        if result.q is not None and result.method == "q":
            written.append(_save_png(pivot_figure(result), out_dir / f"{prefix}pivots.png"))
    payload["outputs"] = [str(p) for p in written] + [str(out_dir / f"{prefix}fgen.json")]
    written.append(write_json(out_dir / f"{prefix}fgen.json", payload))
    return written


# --------------------------------------------------------------------------------------------
# Linkage after the cam (part II): analysis, adjustable mechanisms, family, tuning
# --------------------------------------------------------------------------------------------

LOOP_NAMES = (("O", "A", "B", "C"), ("C", "D", "E", "F"))
SETTING_COLOURS = ("#7b3294", "#008837", "#e66101", "#5e3c99", "#1b9e77", "#d95f02", "#666666")


def _segments(joints: dict, loops: int, index=None) -> list[tuple[complex, complex]]:
    """The links of a chain as (start, end) pairs of complex points (mm) from ``Linkage.joints``."""
    def at(name):
        value = np.asarray(joints[name])
        return complex(value if index is None else value[index])

    pairs = [("O", "A"), ("A", "B"), ("B", "C")]
    if loops > 1:
        pairs += [("C", "D"), ("D", "E"), ("E", "F"), ("B", "D")]
    return [(at(p), at(q)) for p, q in pairs]


def _ground(lines: list, point: complex, r: float) -> None:
    x0, y0 = point.real, point.imag
    lines.append(DxfLine("FRAME", (x0 - 2 * r, y0 - 1.6 * r), (x0 + 2 * r, y0 - 1.6 * r)))
    lines.append(DxfLine("FRAME", (x0, y0 - r), (x0, y0 - 1.6 * r)))
    for k in range(5):
        xa = x0 - 2 * r + k * r
        lines.append(DxfLine("FRAME", (xa, y0 - 1.6 * r), (xa - 0.7 * r, y0 - 2.3 * r)))


def kinematic_drawing(linkage, psi_max: float, settings=(), arc=None, profile=None, follower=None,
                      title: tuple[str, ...] = ()) -> Drawing:
    """The linkage's kinematic diagram as DXF (mm, the cam's frame): FRAME (pivots, ground marks), LINKS (the
    chain with the follower on its base circle, ψ = 0), EXTREME_POSITIONS (at ψ_max), SETTINGS (every
    setting in both extreme positions), ADJUSTMENT (the adjustable element's arc, its centre and the lock
    radii), JOINTS (pair circles), PATHS (joint paths and the coupler point's path over the swing), TEXT;
    with ``profile`` (a ``ProfileResult``) the cam on its own layers (PROFILE, PITCH, BASE_CIRCLE, CENTER,
    ROLLER) at the same origin, and FOLLOWER (the arm from the pivot to the roller in both extremes).

    Parameters
    ----------
    linkage : camcad.linkage.analysis.Linkage
    psi_max : float
        The follower's swing, rad.
    settings : sequence of (label, Linkage)
        The chain at each setting.
    arc : tuple or None
        (centre complex mm, radius mm, lock angles rad) of the adjustable element's arc.
    profile : ProfileResult or None
    follower : camcad.profile.followers.Follower or None
        The oscillating follower (arm drawn in both extremes).
    title : tuple of str
        Text lines under the drawing.

    Examples
    --------
    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.4)
    >>> d = kinematic_drawing(lk, 0.4, arc=(100 + 10j, 10.0, [3.0, 3.5]))
    >>> sorted({x.layer for x in d.lines}) == ['ADJUSTMENT', 'EXTREME_POSITIONS', 'FRAME', 'LINKS']
    True
    """
    loops = len(linkage.loops)
    scale = max(max(lp.a, lp.b, lp.c, lp.d) for lp in linkage.loops)
    r = 0.02 * scale
    h = 0.025 * scale
    lines: list = []
    circles: list = []
    paths: list = []
    texts: list = []

    def add_chain(layer, lk, psi, names=True, suffix=""):
        j = lk.joints(np.array([psi]))
        for p, q in _segments(j, len(lk.loops), 0):
            d = q - p
            if abs(d) > 2 * r:
                u = d / abs(d)
                lines.append(DxfLine(layer, ((p + r * u).real, (p + r * u).imag), ((q - r * u).real, (q - r * u).imag)))
        for name in ("A", "B") + (("D", "E") if len(lk.loops) > 1 else ()):
            z = complex(np.asarray(j[name])[0])
            circles.append(DxfCircle("JOINTS" if layer != "SETTINGS" else "SETTINGS", (z.real, z.imag), r))
            if names:
                texts.append(DxfText("TEXT", name + suffix, (z.real + 1.5 * r, z.imag + 1.5 * r), h))
        return j

    j0 = add_chain("LINKS", linkage, 0.0, suffix="1")
    add_chain("EXTREME_POSITIONS", linkage, psi_max, suffix="2")
    pivots = ["O", "C"] + (["F"] if loops > 1 else [])
    for name in pivots:
        z = complex(np.asarray(j0[name])[0])
        circles.append(DxfCircle("JOINTS", (z.real, z.imag), r))
        _ground(lines, z, r)
        texts.append(DxfText("TEXT", name, (z.real - 3.5 * r, z.imag + 1.5 * r), h))
    for _label, lk in settings:
        for psi in (0.0, psi_max):
            add_chain("SETTINGS", lk, psi, names=False)
    grid = np.linspace(0.0, psi_max, 61)
    j = linkage.joints(grid)
    for name in ("A", "B") + (("D", "E") if loops > 1 else ()) + (("P",) if "P" in j else ()):
        pts = np.column_stack([np.real(j[name]), np.imag(j[name])])
        if np.all(np.isfinite(pts)):
            paths.append(DxfPath("PATHS", pts, False))
    if arc is not None:
        centre, radius_mm, angles = arc
        angles = np.asarray(angles, dtype=float)
        lo, hi = float(angles.min()), float(angles.max())
        span = np.linspace(lo - 0.1 * (hi - lo) - 0.05, hi + 0.1 * (hi - lo) + 0.05, 60)
        paths.append(DxfPath("ADJUSTMENT", np.column_stack([centre.real + radius_mm * np.cos(span),
                                                            centre.imag + radius_mm * np.sin(span)]), False))
        circles.append(DxfCircle("ADJUSTMENT", (centre.real, centre.imag), 0.6 * r))
        for k, ang in enumerate(angles):
            # a short radial tick at each lock position (the radii to M would cross the whole sheet)
            u = complex(math.cos(ang), math.sin(ang))
            end = centre + radius_mm * u
            lines.append(DxfLine("ADJUSTMENT", ((end - 1.5 * r * u).real, (end - 1.5 * r * u).imag),
                                 ((end + 1.5 * r * u).real, (end + 1.5 * r * u).imag)))
            if k in (0, len(angles) - 1):
                texts.append(DxfText("TEXT", f"x{k + 1}", (end.real + 2 * r, end.imag - 2 * r), 0.7 * h))
        middle = centre + radius_mm * complex(math.cos((lo + hi) / 2), math.sin((lo + hi) / 2))
        lines.append(DxfLine("ADJUSTMENT", (centre.real, centre.imag), (middle.real, middle.imag)))
        texts.append(DxfText("TEXT", "M", (centre.real + r, centre.imag + r), h))
    layers = ["FRAME", "LINKS", "EXTREME_POSITIONS", "SETTINGS", "ADJUSTMENT", "JOINTS", "PATHS", "TEXT"]
    extra_paths: list = []
    extra_circles: list = []
    extra_lines: list = []
    extra_splines: list = []
    if profile is not None:
        cam = build_drawing(profile)
        extra_paths, extra_circles, extra_lines = list(cam.paths), list(cam.circles), list(cam.lines)
        extra_splines = list(cam.splines)
        layers += [x for x in ("PROFILE", "PITCH", "BASE_CIRCLE", "CENTER", "ROLLER") if x not in layers]
    if follower is not None and follower.kind == "oscillating":
        g0 = arm_angle_on_base_circle(follower)
        for psi in (0.0, psi_max):
            g = g0 + psi
            end = complex(follower.pivot - follower.arm * math.cos(g), follower.arm * math.sin(g))
            lines.append(DxfLine("FOLLOWER", (follower.pivot, 0.0), (end.real, end.imag)))
            circles.append(DxfCircle("FOLLOWER", (end.real, end.imag), follower.roller_radius))
        layers.append("FOLLOWER")
    ys = [c.centre[1] for c in circles] + [y for p in paths for y in p.points[:, 1]]
    xs = [c.centre[0] for c in circles]
    if profile is not None:
        ys += [y for p in extra_paths for y in p.points[:, 1]]
    low = min(ys) - 6 * r
    left = min(xs) if xs else 0.0
    for k, line in enumerate(title):
        texts.append(DxfText("TEXT", line, (left, low - k * 1.8 * h), h))
    return Drawing(paths=tuple(paths + extra_paths), splines=tuple(extra_splines),
                   circles=tuple(circles + extra_circles), lines=tuple(lines + extra_lines), texts=tuple(texts),
                   layers=tuple(layers))


def diagram_figure(linkage, psi_max: float, settings=(), arc=None, title: str = "",
                   ends: tuple[str, str] | None = None):
    """The kinematic diagram as a figure: the chain in both extreme positions (blue ψ = 0, red ψ_max), faint
    intermediate positions, joint and coupler-point paths, the settings (thin, coloured) and the arc;
    ``ends`` names the two extreme positions in the legend (default: the follower's).

    Examples
    --------
    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.4)
    >>> diagram_figure(lk, 0.4).axes[0].get_xlabel()
    'x (mm)'
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 6.0), layout="constrained")
    ax = fig.subplots()
    loops = len(linkage.loops)

    def draw(lk, psi, **kw):
        j = lk.joints(np.array([psi]))
        label = kw.pop("label", None)
        for k, (p, q) in enumerate(_segments(j, len(lk.loops), 0)):
            ax.plot([p.real, q.real], [p.imag, q.imag], label=label if k == 0 else None, **kw)

    for psi in np.linspace(0.0, psi_max, 7)[1:-1]:
        draw(linkage, psi, color="#cccccc", lw=0.7)
    for k, (label, lk) in enumerate(settings):
        colour = SETTING_COLOURS[k % len(SETTING_COLOURS)]
        draw(lk, 0.0, color=colour, lw=0.9, ls="--", label=f"setting {label}")  # label carries its unit
        draw(lk, psi_max, color=colour, lw=0.9, ls="--")
    if ends is None:
        ends = ("follower on the base circle (ψ = 0)", f"follower at its swing ({math.degrees(psi_max):.4g} deg)")
    draw(linkage, 0.0, color="#1f4e9c", lw=2.0, marker="o", ms=4, label=ends[0])
    draw(linkage, psi_max, color="#c0392b", lw=2.0, marker="o", ms=4, label=ends[1])
    grid = np.linspace(0.0, psi_max, 121)
    j = linkage.joints(grid)
    for name in ("A", "B") + (("D", "E") if loops > 1 else ()):
        ax.plot(np.real(j[name]), np.imag(j[name]), color="#555555", lw=0.6, ls=":")
    if "P" in j:
        ax.plot(np.real(j["P"]), np.imag(j["P"]), color="#2d7f3b", lw=1.2, label="coupler point path")
    j0 = linkage.joints(np.array([0.0]))
    for name in ("O", "C") + (("F",) if loops > 1 else ()):
        z = complex(np.asarray(j0[name])[0])
        ax.plot(z.real, z.imag, "^", color="black", ms=10)
        ax.annotate(name, (z.real, z.imag), textcoords="offset points", xytext=(-4, -16))
    for name in ("A", "B") + (("D", "E") if loops > 1 else ()):
        z = complex(np.asarray(j0[name])[0])
        ax.annotate(name + "₁", (z.real, z.imag), textcoords="offset points", xytext=(5, 5), color="#1f4e9c")
    if arc is not None:
        centre, radius_mm, angles = arc
        angles = np.asarray(angles, dtype=float)
        lo, hi = float(angles.min()), float(angles.max())
        span = np.linspace(lo - 0.1 * (hi - lo) - 0.05, hi + 0.1 * (hi - lo) + 0.05, 100)
        ax.plot(centre.real + radius_mm * np.cos(span), centre.imag + radius_mm * np.sin(span), color="#e66101",
                lw=1.6, label="adjustment arc")
        ax.plot(centre.real, centre.imag, "+", color="#e66101", ms=12)
        ax.annotate("M", (centre.real, centre.imag), textcoords="offset points", xytext=(5, -12), color="#e66101")
    ax.set_aspect("equal")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def analysis_figure(analysis, mu_limit_deg: float | None = None):
    """Π (deg) and its exact derivatives Π', Π'', Π''' against the follower's swing, and the transmission
    angle of each loop with the limit's forbidden bands; limit positions and dead points marked.

    Examples
    --------
    >>> from camcad.linkage.analysis import Linkage, Loop, analyse
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.4)
    >>> len(analysis_figure(analyse(lk, 0.4), 40.0).axes)
    5
    """
    from matplotlib.figure import Figure

    psi = np.degrees(analysis.psi)
    fig = Figure(figsize=(9.0, 9.0), layout="constrained")
    axes = fig.subplots(5, 1, sharex=True)
    rows = (("Π (deg)", np.degrees(analysis.pi)), ("Π' (rad/rad)", analysis.d1), ("Π'' (1/rad)", analysis.d2),
            ("Π''' (1/rad²)", analysis.d3))
    for ax, (label, values) in zip(axes, rows):
        ax.plot(psi, values, color="#1f4e9c", lw=1.3)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.6)
        for x in analysis.limit_positions:
            ax.axvline(math.degrees(x), color="#c0392b", lw=0.8, ls="--")
        for x in analysis.dead_points:
            ax.axvline(math.degrees(x), color="black", lw=1.0, ls="-.")
    ax = axes[-1]
    if mu_limit_deg is not None:
        ax.axhspan(0, mu_limit_deg, color=FORBIDDEN, lw=0, label=f"below μ_min = {mu_limit_deg:g} deg")
        ax.axhspan(180 - mu_limit_deg, 180, color=FORBIDDEN, lw=0)
    for k, mu in enumerate(analysis.mu):
        ax.plot(psi, np.degrees(mu), lw=1.3, label=f"loop {k + 1}: worst {math.degrees(analysis.mu_min[k]):.2f} deg")
    ax.set_ylim(0, 180)
    ax.set_yticks([0, 45, 90, 135, 180])
    ax.set_ylabel("μ (deg)")
    ax.set_xlabel("follower swing ψ (deg)")
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.legend(fontsize=8, loc="best")
    state = ("branch continuous" if analysis.branch_continuous else "BRANCH NOT CONTINUOUS") + \
            (", monotone" if analysis.monotone else ", NOT monotone (limit position inside the swing)")
    axes[0].set_title(f"{analysis.linkage.kind}: stroke {math.degrees(analysis.stroke):.5g} deg over a swing of "
                      f"{math.degrees(analysis.psi_max):.5g} deg; {state}\nexact loop-closure derivatives; "
                      "dashed: limit positions (Π' = 0), dash-dot: dead points", fontsize=9)
    return fig


def working_figure(theta, kin, unit: str, title: str = ""):
    """The working member's y, y', y'', y''' against the cam angle (chain rule through Π).

    Examples
    --------
    >>> from camcad.law.law import Kinematics
    >>> t = np.linspace(0, 2 * np.pi, 5)
    >>> working_figure(t, Kinematics(t, t, t, t, t), "rad").axes[3].get_xlabel()
    'cam angle θ (deg)'
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 8.0), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    deg = np.degrees(theta)
    shown = "deg" if unit == "rad" else "mm"
    factor = math.degrees(1.0) if unit == "rad" else 1.0
    for ax, (label, values) in zip(axes, ((f"y ({shown})", kin.s * factor), (f"y' ({shown}/rad)", kin.v * factor),
                                          (f"y'' ({shown}/rad²)", kin.a * factor),
                                          (f"y''' ({shown}/rad³)", kin.j * factor))):
        ax.plot(deg, values, color="#1f4e9c", lw=1.2)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.6)
    axes[-1].set_xlabel("cam angle θ (deg)")
    axes[-1].set_xticks(np.arange(0, 361, 30))
    axes[0].set_title(title or "the working member through the linkage: y = Π(ψ(θ)), y'' = Π''ψ'² + Π'ψ''",
                      fontsize=9)
    return fig


def settings_figure(rows: list[dict], setting_label: str, title: str = ""):
    """ψ₁, ψ₂, the swing (deg) and the worst transmission angle against the setting.

    Examples
    --------
    >>> rows = [{"setting": 1.0, "psi1_deg": 0.0, "psi2_deg": 10.0, "swing_deg": 10.0, "mu_min_deg": 50.0},
    ...         {"setting": 2.0, "psi1_deg": 0.0, "psi2_deg": 12.0, "swing_deg": 12.0, "mu_min_deg": 48.0}]
    >>> len(settings_figure(rows, "lock angle (deg)").axes)
    2
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.5, 6.0), layout="constrained")
    ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    x = [r["setting"] for r in rows if "psi1_deg" in r]
    for key, label, colour in (("psi1_deg", "ψ₁ (first extreme)", "#1f4e9c"), ("psi2_deg", "ψ₂ (second extreme)",
                                                                           "#c0392b"),
                               ("swing_deg", "swing ψ₁₂", "#2d7f3b")):
        ax.plot(x, [r[key] for r in rows if "psi1_deg" in r], "-o", ms=4, color=colour, label=label)
    ax.set_ylabel("working member (deg)")
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.legend(fontsize=8)
    ax2.plot(x, [r["mu_min_deg"] for r in rows if "psi1_deg" in r], "-o", ms=4, color="#7b3294")
    ax2.set_ylabel("worst μ (deg)")
    ax2.set_xlabel(setting_label)
    ax2.grid(True, lw=0.4, alpha=0.6)
    if title:
        ax.set_title(title, fontsize=9)
    return fig


def family_figure(result, members):
    """Stage 1 and 2 of the family synthesis: every member's pivots and their rectangle, the circle through
    the members' pivots (the adjustable link), and each member's structural error.

    Examples
    --------
    >>> import types
    >>> r = types.SimpleNamespace(pivots=[1 + 0j, 1j, -1 + 0j], centre=0j, radius=1.0,
    ...     settings=np.array([0.0, 1.5, 3.1]), q=0.0, max_error=[0.0, 0.0, 0.0], crank=1.0)
    >>> len(family_figure(r, [None] * 3).axes)
    2
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 5.0), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, width_ratios=(3, 2))
    t = np.linspace(0, 2 * np.pi, 400)
    ax.plot(result.centre.real + result.radius * np.cos(t), result.centre.imag + result.radius * np.sin(t),
            color="#e66101", lw=1.2, label="circle through the pivots (adjustable link)")
    ax.plot(result.centre.real, result.centre.imag, "+", color="#e66101", ms=12)
    for k, (p, x) in enumerate(zip(result.pivots, result.settings)):
        colour = SETTING_COLOURS[k % len(SETTING_COLOURS)]
        ax.plot(p.real, p.imag, "o", color=colour, label=f"member {k + 1}: C at x = {math.degrees(x):.4f} deg")
        ax.plot([result.centre.real, p.real], [result.centre.imag, p.imag], color=colour, lw=0.8)
    ax.set_aspect("equal")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"stage 1: Q = {result.q:.3g} crank lengths; stage 2: F = ({result.centre.real:.4f}, "
                 f"{result.centre.imag:.4f}) mm, R = {result.radius:.4f} mm", fontsize=9)
    errors = np.degrees(np.asarray(result.max_error, dtype=float))
    ax2.bar(np.arange(1, len(errors) + 1), np.maximum(errors, 1e-16), color="#1f4e9c")
    ax2.set_yscale("log")
    ax2.set_xlabel("member")
    ax2.set_ylabel("largest structural error (deg)")
    ax2.grid(True, lw=0.4, alpha=0.5, axis="y")
    return fig


def tune_figure(result, unit: str):
    """F(x₁) = f₁(x₁) − f₂(x₁) (deg) over the searched interval with every root marked (Sunkuev 1984, ch. 6, eq. 2).

    Examples
    --------
    >>> import types
    >>> r = types.SimpleNamespace(x1_grid=np.linspace(0, 1, 5), f_grid=np.linspace(-1, 1, 5), roots=[],
    ...     psi1=0.0, psi2=0.2)
    >>> tune_figure(r, "rad").axes[0].get_ylabel()
    'F(x1) = f1 - f2 (deg)'
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.5, 4.5), layout="constrained")
    ax = fig.subplots()
    x = np.degrees(result.x1_grid) if unit == "rad" else result.x1_grid
    ax.axhline(0, color="grey", lw=0.6)
    ax.plot(x, np.degrees(result.f_grid), color="#1f4e9c", lw=1.2, label="F(x1)")
    for k, root in enumerate(result.roots):
        xr = math.degrees(root.x1) if unit == "rad" else root.x1
        ax.plot(xr, 0.0, "o", color="#c0392b", ms=7, label=f"root {k + 1}: x1 = {xr:.6g}, x2 = "
                                                            f"{math.degrees(root.x2):.6g} deg")
    ax.set_xlabel("x1: lock angle (deg)" if unit == "rad" else "x1: slot position (mm)")
    ax.set_ylabel("F(x1) = f1 - f2 (deg)")
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.legend(fontsize=8)
    ax.set_title(f"settings for psi1 = {math.degrees(result.psi1):.6g} deg, psi2 = {math.degrees(result.psi2):.6g} "
                 "deg: every sign change of F bracketed and refined", fontsize=9)
    return fig


def rows_csv(rows: list[dict], comment: str = "") -> str:
    """Rows of dicts as CSV (the union of their keys, first-seen order); None as empty.

    Examples
    --------
    >>> rows_csv([{"a": 1, "b": 2.5}, {"a": 2, "b": None}]).splitlines()
    ['a,b', '1,2.5', '2,']
    """
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys and not isinstance(r[k], (dict, list))]
    lines = ([f"# {comment}"] if comment else []) + [",".join(keys)]
    for r in rows:
        cells = []
        for k in keys:
            v = r.get(k)
            cells.append("" if v is None else (f"{v:.12g}" if isinstance(v, float) else str(v)))
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def analysis_csv(analysis) -> str:
    """ψ (deg), Π (deg), Π', Π'', Π''' and each loop's μ (deg) over the swing, and the coupler point (mm).

    Examples
    --------
    >>> from camcad.linkage.analysis import Linkage, Loop, analyse
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 0.0), 40.0, 120.0, 90.0),), theta0=1.4)
    >>> analysis_csv(analyse(lk, 0.4, 5)).splitlines()[1]
    'psi_deg,pi_deg,pi_1,pi_2,pi_3,mu1_deg'
    """
    head = ["psi_deg", "pi_deg", "pi_1", "pi_2", "pi_3"] + [f"mu{k + 1}_deg" for k in range(len(analysis.mu))]
    point = analysis.joints.get("P")
    if point is not None:
        head += ["coupler_x_mm", "coupler_y_mm"]
    lines = [("# Pi: the working member's turn from its position at psi = 0 (deg); pi_1..pi_3: exact dPi/dpsi.. "
              "(rad per rad of follower swing)"), ",".join(head)]
    for i in range(len(analysis.psi)):
        cells = [math.degrees(analysis.psi[i]), math.degrees(analysis.pi[i]), analysis.d1[i], analysis.d2[i],
                 analysis.d3[i]] + [math.degrees(mu[i]) for mu in analysis.mu]
        if point is not None:
            cells += [point[i].real, point[i].imag]
        lines.append(",".join(f"{float(c):.12g}" for c in cells))
    return "\n".join(lines) + "\n"


def write_linkage_outputs(out_dir: Path, name: str, payload: dict, texts: dict | None = None,
                          figures: dict | None = None, drawing: Drawing | None = None,
                          written_before: Sequence[Path] = ()) -> list[Path]:
    """Write ``name``.json (``payload`` with ``outputs``), the CSV ``texts`` ({file name: text}), the PNG
    ``figures`` ({file name: Figure factory}) and ``name``.dxf into ``out_dir``, atomically; files already
    written for the command (``written_before``, e.g. its animation) are listed first.

    Examples
    --------
    >>> import tempfile
    >>> files = write_linkage_outputs(Path(tempfile.mkdtemp()), "analysis", {"a": 1}, {"x.csv": "a\\n1\\n"})
    >>> sorted(p.name for p in files)
    ['analysis.json', 'x.csv']
    """
    out_dir = Path(out_dir)
    written = list(written_before)
    written += [write_text_atomic(out_dir / file, text) for file, text in (texts or {}).items()]
    if drawing is not None:
        written.append(_write_dxf(out_dir / f"{name}.dxf", drawing))
    for file, make in (figures or {}).items():
        written.append(_save_png(make(), out_dir / file))
    payload["outputs"] = [str(p) for p in written] + [str(out_dir / f"{name}.json")]
    written.append(write_json(out_dir / f"{name}.json", payload))
    return written
