"""The editor's view: a matplotlib Figure that shows an ``EditSession`` and turns the canvas's mouse and
key events into session operations.

The view works on any canvas: TkAgg (desktop window), WebAgg (browser, ``camcad.edit.web``) and the
off-screen Agg canvas (tests, benchmark). On a canvas that can blit, a drag redraws only the
artists that change (the law, the areas, v, s, the badge, the readout, the table) over a saved
background, with the axes frozen; on the browser canvas a drag sends only the numbers (``live``)
and the figure is redrawn in full on release.

What the window shows: the acceleration (input y units) with the areas above and below the axis
shaded and their values per phase, v and s below it, phases shaded and their boundaries marked, a
closure badge (v at the end of each rise and return, the displacement gap), a small pitch-curve
preview that shows the gap, a table of phases and of the vertices around the selected one (or the
"compare all modes" table), the readout line and the list of shortcuts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import cast

import numpy as np
from matplotlib.artist import Artist
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import FancyBboxPatch, Polygon, Rectangle
from matplotlib.transforms import blended_transform_factory

from camcad.arrays import union
from camcad.balance import MODES
from camcad.edit.session import (
    EditSession,
    default_output,
    default_script,
    extremum_group,
    jump_group,
    lobe_of,
)
from camcad.errors import CamcadError
from camcad.law.phases import zero_threshold

PHASE_COLOURS = {"rise": "#e8f1fb", "return": "#fdeee6", "dwell": "#f2f2f2"}
ABOVE, BELOW = "#2a9d8f", "#e76f51"
PREVIEW = "#1d4ed8"
PICK_PX = 8.0      # a press within this distance of a vertex grabs it
PHASE_PX = 6.0     # ... of a phase boundary grabs the boundary
SNAP_PX = 7.0      # a dragged value snaps to a target within this distance
CLICK_PX = 3.0     # a press and release closer than this is a click, not a range
DENSE = 3000       # above this many vertices v and s are drawn at the vertices only
MARKERS_MAX = 400  # vertex markers are drawn up to this many vertices
FIGSIZE = (15.0, 9.8)

#: (keys, what they do) as listed in the window
SHORTCUTS = [
    ("drag a point", "move a vertex; shift: also in angle"),
    ("v  l  e", "drag: vertex / lobe / extremum group"),
    ("drag a phase line", "move a phase boundary"),
    ("drag on empty graph", "select an angle range"),
    ("i  right-click", "insert a vertex at the mouse"),
    ("d  delete", "delete the vertex at the mouse"),
    ("j", "make / remove a jump"),
    ("n", "snapping on / off"),
    ("up  down", "nudge 1 % (shift: 10 %)"),
    ("left  right", "select previous / next vertex"),
    ("shift+left/right", "nudge the angle by 0.1°"),
    ("t", "type Y or X:Y, then enter"),
    ("1 .. 7", "preview a fix mode (on the range)"),
    ("enter  esc", "accept / reject the preview"),
    ("c", "compare all modes"),
    ("p", "find the phases again"),
    ("z  ctrl+z", "undo (a drag is one step)"),
    ("y  ctrl+y", "redo"),
    ("s  ctrl+s", "save the drawing (as fix does)"),
    ("w", "save a CSV table"),
    ("x", "save the edit script"),
    ("esc", "clear the range / the message"),
    ("h", "show / hide this list"),
]


@dataclass
class _Drag:
    kind: str                     # "vertex", "lobe", "extrema", "phase", "range"
    axes: object
    press_xy: tuple[float, float]
    index: int = -1
    end: str | None = None
    base_deg: float = 0.0         # angle of the grabbed vertex or boundary at the press (deg)
    free_x: bool = False
    snaps_y: tuple[float, ...] = ()
    snaps_x: tuple[float, ...] = ()
    start_deg: float = 0.0        # range: where it started
    lo: float = 0.0
    hi: float = 0.0
    moved: bool = False


class EditorView:
    """Draws ``session`` on ``figure`` and edits it from the canvas's events.

    Parameters
    ----------
    session : the model.
    figure : a Figure already attached to its canvas (Tk, WebAgg or Agg).
    blit : redraw drags by blitting when the canvas can.
    live : called with the numbers (a dict) after every change and during drags (the browser path).
    output : where ``s`` saves (default ``<input>.edited.dxf``, or ``.edited.csv`` for a table input).
    title : the title line.
    """

    def __init__(self, session: EditSession, figure: Figure, *, blit: bool = True,
                 live: Callable[[dict], None] | None = None, output: Path | None = None, title: str = "") -> None:
        self.session = session
        self.figure = figure
        self.canvas = figure.canvas
        self.blit = bool(blit and getattr(self.canvas, "supports_blit", False))
        self.live = live
        self.output = output or default_output(session)
        self.title = title or session.where
        self.mode = "vertex"
        self.snap = True
        self.selected = int(np.argmax(np.abs(session.law.a)))
        self.range: tuple[float, float] | None = None
        self.typing: str | None = None
        self.compare: list | None = None
        self.message = ""
        self.message_error = False
        self.cursor_text = ""
        self.status = ""
        self._drag: _Drag | None = None
        self._background = None
        self._phase_key: tuple | None = None
        self._phase_artists: list = []
        self._area_texts: list = []
        self._curve_cache: dict = {}
        self._build()
        self._connect()
        self.refresh()

    # --- building the figure ---------------------------------------------------------------------

    def _build(self) -> None:
        fig = self.figure
        fig.set_facecolor("white")
        left, width = 0.055, 0.60            # placed for the figure's size by ``_layout``
        self.ax_a = fig.add_axes((left, 0.57, width, 0.365))
        self.ax_v = fig.add_axes((left, 0.39, width, 0.16), sharex=self.ax_a)
        self.ax_s = fig.add_axes((left, 0.21, width, 0.16), sharex=self.ax_a)
        self.ax_p = fig.add_axes((0.695, 0.50, 0.13, 0.20))
        for ax in (self.ax_a, self.ax_v, self.ax_s):
            ax.grid(True, alpha=0.3)
            ax.axhline(0.0, color="0.35", lw=0.8, zorder=1)
            ax.set_autoscale_on(False)
        self.ax_a.tick_params(labelbottom=False)
        self.ax_v.tick_params(labelbottom=False)
        y_unit = "mm/rad²" if self.session.y_scale == 1.0 else f"input y units (× {self.session.y_scale:.4g} = mm/rad²)"
        self.ax_a.set_ylabel(f"a ({y_unit})", fontsize=9)
        self.ax_v.set_ylabel("v (mm/rad)", fontsize=9)
        self.ax_s.set_ylabel("s (mm)", fontsize=9)
        self.ax_s.set_xlabel("cam angle θ (deg)", fontsize=9)
        cycle = self.session.cycle_deg
        self.ax_a.set_xlim(-0.005 * cycle, 1.005 * cycle)
        self.ax_p.set_aspect("equal", adjustable="box")
        self.ax_p.set_xticks([])
        self.ax_p.set_yticks([])
        self.ax_p.set_title("pitch curve (knife-edge preview)", fontsize=8.5, loc="left")

        def line(ax, **kw):
            artist = Line2D([], [], animated=True, **kw)
            ax.add_line(artist)
            return artist

        a = self.ax_a
        self.pos_fill = Polygon(np.zeros((3, 2)), closed=True, facecolor=ABOVE, alpha=0.35, lw=0, animated=True,
                                zorder=2)
        a.add_patch(self.pos_fill)
        self.neg_fill = Polygon(np.zeros((3, 2)), closed=True, facecolor=BELOW, alpha=0.35, lw=0, animated=True,
                                zorder=2)
        a.add_patch(self.neg_fill)
        self.range_patch = Rectangle((0, 0), 0, 1, transform=blended_transform_factory(a.transData, a.transAxes),
                                     facecolor="#a78bfa", alpha=0.10, edgecolor="#7c3aed", lw=1.2,
                                     animated=True, visible=False, zorder=1.5)
        a.add_patch(self.range_patch)
        self.ghost_a = line(a, color="0.45", lw=1.2, ls="--", zorder=3, visible=False)
        self.a_line = line(a, color="k", lw=1.3, zorder=4)
        self.a_marks = line(a, color="k", lw=0, marker="o", ms=3.0, zorder=5)
        self.lobe_line = line(a, color="#f59e0b", lw=3.0, alpha=0.8, zorder=4.5, visible=False)
        self.sel_mark = line(a, color="#dc2626", lw=0, marker="o", ms=8, mfc="none", mew=2, zorder=6)
        self.ghost_v = line(self.ax_v, color="0.45", lw=1.1, ls="--", visible=False)
        self.v_line = line(self.ax_v, color="k", lw=1.2)
        self.v_marks = line(self.ax_v, lw=0, marker="o", ms=6, color=BELOW)
        self.ghost_s = line(self.ax_s, color="0.45", lw=1.1, ls="--", visible=False)
        self.s_line = line(self.ax_s, color="k", lw=1.2)
        self.s_gap = line(self.ax_s, lw=2.0, marker="s", ms=5, color=BELOW)
        self.p_base = self.ax_p.plot([], [], color="0.75", lw=0.8, ls=":")[0]
        self.drag_lines = [line(ax, color="#7c3aed", lw=1.6, visible=False) for ax in (self.ax_a, self.ax_v, self.ax_s)]
        self.p_line = line(self.ax_p, color="k", lw=1.0)
        self.p_gap = line(self.ax_p, color=BELOW, lw=2.5, marker="o", ms=3)
        mono = {"family": "monospace"}
        self.title_text = fig.text(0.055, 0.972, "", fontsize=10.5, weight="bold", va="center")
        self.status_text = fig.text(0.985, 0.972, "", fontsize=9, ha="right", va="center", color="0.3")
        self.badge = fig.text(0.695, 0.935, "", fontsize=8.6, va="top", ha="left",
                              bbox={"boxstyle": "round,pad=0.45", "facecolor": "#fde2e2", "edgecolor": BELOW},
                              fontdict=mono)
        self.profile_text = fig.text(0.835, 0.695, "", fontsize=8.2, va="top", fontdict=mono)
        self.table = fig.text(0.695, 0.465, "", fontsize=8.0, va="top", fontdict=mono)
        self.readout = fig.text(0.055, 0.148, "", fontsize=9.2, va="center", fontdict=mono)
        self.msg_text = fig.text(0.985, 0.148, "", fontsize=9.2, va="center", ha="right")
        self.rule = Line2D([0.04, 0.985], [0.133, 0.133], transform=fig.transFigure, color="0.8", lw=0.8)
        fig.add_artist(self.rule)
        # the shortcut list never changes: it is drawn once into an image (text is most of a full draw)
        self.help_block = _StaticBlock(fig, (0.03, 0.005, 0.995, 0.13), _draw_help)
        fig.add_artist(self.help_block)
        self.help_hint = fig.text(0.03, 0.01, "h: the list of shortcuts", fontsize=HELP_FONT, va="bottom",
                                  family="monospace", color="#1d4ed8", visible=False)
        self.help_wanted = True       # h hides and shows the list; a window too short for it hides it
        self.table_rows = 9
        self._layout()
        self._dynamic = [self.range_patch, self.pos_fill, self.neg_fill, self.ghost_a, self.a_line, self.a_marks,
                         self.lobe_line, self.sel_mark, self.ghost_v, self.v_line, self.v_marks, self.ghost_s,
                         self.s_line, self.s_gap, self.p_line, self.p_gap, *self.drag_lines]

    def _connect(self) -> None:
        canvas = self.canvas
        manager = getattr(canvas, "manager", None)
        handler = getattr(manager, "key_press_handler_id", None)
        if handler is not None:  # matplotlib's own shortcuts (save, quit, grid, ...) would fight ours
            canvas.mpl_disconnect(handler)
        self._cids = [canvas.mpl_connect("button_press_event", self.on_press),
                      canvas.mpl_connect("motion_notify_event", self.on_motion),
                      canvas.mpl_connect("button_release_event", self.on_release),
                      canvas.mpl_connect("key_press_event", self.on_key),
                      canvas.mpl_connect("draw_event", self._on_draw),
                      canvas.mpl_connect("resize_event", self._on_resize)]

    # --- drawing -----------------------------------------------------------------------------------

    def _on_draw(self, event) -> None:
        """After every full draw: keep the background (for blitting) and paint the changing artists."""
        renderer = getattr(event, "renderer", None)
        if renderer is None:
            return
        own = renderer is self.canvas.get_renderer() if hasattr(self.canvas, "get_renderer") else False
        if own and hasattr(self.canvas, "copy_from_bbox"):
            self._background = self.canvas.copy_from_bbox(self.figure.bbox)
        for artist in self._dynamic + self._area_texts:
            if artist.get_visible():
                artist.draw(renderer)

    def _on_resize(self, _event) -> None:
        self._background = None
        self._layout()
        self._update_texts(self._shown_law()[0])

    def _layout(self) -> None:
        """Place the plots, the texts and the shortcut list for the figure's size (it follows the window).

        Text keeps its size in points: the title line, the readout and the shortcut list take the heights
        their lines need, the right-hand column (closure badge, pitch preview, tables) its width, and the
        three plots share what is left. On a short window the pitch preview shrinks and the vertex table
        lists fewer rows, so that everything stays inside the window down to 1366 x 768 px
        (``MIN_FIGURE_PX``); a window too short even for that hides the shortcut list (h shows it)."""
        fig = self.figure
        w_pt, h_pt = 72.0 * fig.get_figwidth(), 72.0 * fig.get_figheight()
        full = self._place(w_pt, h_pt, self.help_wanted)
        if self.help_wanted and not full:
            self._place(w_pt, h_pt, False)

    def _place(self, w_pt: float, h_pt: float, with_help: bool) -> bool:
        """Lay the figure out (``_layout``) with or without the shortcut list; False when it does not fit."""
        fig = self.figure

        def fx(pt: float) -> float:
            return pt / w_pt

        def fy(pt: float) -> float:
            return pt / h_pt

        columns = help_columns(fig.get_figwidth())
        help_top = 4.0 + (help_height_pt(columns) if with_help else HELP_FONT * 1.4)
        self.help_block.set_visible(with_help)
        self.help_hint.set_visible(not with_help)
        self.help_hint.set_position((0.03, fy(4.0)))
        self.help_block.set_rect((0.03, fy(4.0), 0.995, fy(max(help_top, 5.0))))
        self.rule.set_ydata([fy(help_top + 3.0)] * 2)
        readout = help_top + 14.0
        for text in (self.readout, self.msg_text):
            text.set_y(fy(readout))
        title = h_pt - 15.0
        self.title_text.set_y(fy(title))
        self.status_text.set_y(fy(title))
        right = max(0.6, 1.0 - fx(RIGHT_COLUMN_PT))           # the right-hand column starts here
        left = fx(46.0)
        width = right - fx(36.0) - left
        bottom = readout + 40.0                                # the x tick labels and the axis label
        top = h_pt - 34.0
        gap = 12.0
        plots = max(top - bottom - 2.0 * gap, 60.0)
        a_h, v_h = 0.53 * plots, 0.235 * plots
        self.ax_s.set_position((left, fy(bottom), width, fy(v_h)))
        self.ax_v.set_position((left, fy(bottom + v_h + gap), width, fy(v_h)))
        self.ax_a.set_position((left, fy(top - a_h), width, fy(a_h)))
        # the right-hand column, from the top: badge, pitch preview (profile text beside it), tables
        badge_top = h_pt - 30.0
        self.badge.set_position((right, fy(badge_top)))
        badge_h = BADGE_LINES * 8.6 * 1.2 + 12.0
        lines_pt = 8.0 * 1.2                                   # one line of the table
        table_min = TABLE_FIXED_LINES * lines_pt               # the phases, no vertex row
        floor = help_top + 5.0                                 # the table may reach down to the list's rule
        room = badge_top - badge_h - floor - 26.0              # what the preview and the table share
        preview = min(PREVIEW_PT, max(room - table_min - 3 * lines_pt, 60.0))
        p_top = badge_top - badge_h - 14.0
        self.ax_p.set_position((right, fy(p_top - preview), fx(preview), fy(preview)))
        self.profile_text.set_position((right + fx(preview + 10.0), fy(p_top)))
        table_top = p_top - preview - 10.0
        self.table.set_position((right, fy(table_top)))
        fits = int((table_top - floor) / lines_pt) - TABLE_FIXED_LINES
        self.table_rows = int(min(9, max(0, fits)))
        return a_h >= 100.0 and fits >= 3

    def _shown_law(self):
        """The law drawn in full (the preview when one is held) and the ghost (the current law then)."""
        session = self.session
        if session.preview is not None:
            return session.preview.correction.law, session.law
        return session.law, None

    def refresh(self) -> None:
        """Update every artist from the session and redraw the whole figure (idle)."""
        law, ghost = self._shown_law()
        self._update_phases(law)
        self._update_curves(law, ghost)
        self._autoscale(law, ghost)
        self._update_texts(law)
        self._notify_live()
        self.canvas.draw_idle()

    def _update_phases(self, law) -> None:
        key = tuple((p.kind, p.start, p.end) for p in law.phases)
        if key == self._phase_key:
            return
        self._phase_key = key
        for artist in self._phase_artists:
            artist.remove()
        self._phase_artists = []
        for ax in (self.ax_a, self.ax_v, self.ax_s):
            for p in law.phases:
                span = ax.axvspan(math.degrees(p.start), math.degrees(p.end), color=PHASE_COLOURS[p.kind], zorder=0,
                                  lw=0)
                self._phase_artists.append(span)
            for b in self.session.boundaries_deg(law):
                self._phase_artists.append(ax.axvline(b, color="#6b7280", lw=1.0, ls=(0, (4, 3)), zorder=1))
        trans = blended_transform_factory(self.ax_a.transData, self.ax_a.transAxes)
        for p in law.phases:
            mid = math.degrees(p.start + p.end) / 2
            self._phase_artists.append(self.ax_a.text(mid, 0.985, p.kind, transform=trans, ha="center", va="top",
                                                      fontsize=8.5, color="0.35", clip_on=True))
        for text in self._area_texts:
            text.remove()
        self._area_texts = []
        for p in law.phases:
            if p.kind == "dwell":
                continue
            for _ in (0, 1):
                text = self.ax_a.text(0, 0, "", transform=trans, ha="center", fontsize=7.8, animated=True,
                                      bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.75,
                                            "lw": 0})
                self._area_texts.append(text)

    def _curves(self, law):
        cached = self._curve_cache.get(id(law))
        if cached is not None and cached[0] is law:
            return cached[1]
        if len(self._curve_cache) > 4:
            self._curve_cache.clear()
        curves = self._compute_curves(law)
        self._curve_cache[id(law)] = (law, curves)
        return curves

    def _compute_curves(self, law):
        session = self.session
        deg = np.degrees(law.x)
        y = law.a / session.y_scale
        if len(law.x) > DENSE:
            theta = law.x
        else:
            theta = union(law.x, np.linspace(0.0, law.cycle, 1441))
        kin = law.kinematics(theta)
        return deg, y, np.degrees(theta), kin.v, kin.s

    def _update_curves(self, law, ghost, texts: bool = True) -> None:
        deg, y, t_deg, v, s = self._curves(law)
        self.a_line.set_data(deg, y)
        self.a_marks.set_data(deg, y)
        self.a_marks.set_visible(len(deg) <= MARKERS_MAX)
        xs, pos, neg = _fill_outlines(deg, y)
        self.pos_fill.set_xy(np.column_stack((xs, pos)))
        self.neg_fill.set_xy(np.column_stack((xs, neg)))
        self.v_line.set_data(t_deg, v)
        self.s_line.set_data(t_deg, s)
        report = self.session.report_of(law)
        ends = [(r["end_deg"], r["v_end"]) for r in report.phases if r["kind"] != "dwell"]
        if ends:
            self.v_marks.set_data(*zip(*ends))
        else:
            self.v_marks.set_data([], [])
        worst = max((abs(v_end) for _, v_end in ends), default=0.0)
        self.v_marks.set_color(ABOVE if worst <= report.tolerance_abs else BELOW)
        cycle = self.session.cycle_deg
        self.s_gap.set_data([cycle, cycle], [s[0], s[0] + report.displacement_closure])
        self.s_gap.set_color(ABOVE if abs(report.displacement_closure) <= report.tolerance_abs else BELOW)
        for artist in (self.ghost_a, self.ghost_v, self.ghost_s):
            artist.set_visible(ghost is not None)
        if ghost is not None:
            g_deg, g_y, g_t, g_v, g_s = self._curves(ghost)
            self.ghost_a.set_data(g_deg, g_y)
            self.ghost_v.set_data(g_t, g_v)
            self.ghost_s.set_data(g_t, g_s)
        colour = PREVIEW if ghost is not None else "k"
        for artist in (self.a_line, self.v_line, self.s_line, self.a_marks):
            artist.set_color(colour)
        self._update_selection(law)
        self._update_range()
        if texts:
            self._update_area_texts(law, report, deg, y)
        self._update_profile(law, report, texts)

    def _update_selection(self, law) -> None:
        n = len(law.x)
        self.selected = min(max(self.selected, 0), n - 1)
        i = self.selected
        self.sel_mark.set_data([math.degrees(law.x[i])], [law.a[i] / self.session.y_scale])
        drag = self._drag
        if drag is not None and drag.kind in ("lobe", "extrema"):
            lobe = lobe_of(law.a, drag.index)
            if drag.kind == "extrema":
                lobe = extremum_group(law.a, lobe) if len(lobe) else lobe
            self.lobe_line.set_data(np.degrees(law.x[lobe]), law.a[lobe] / self.session.y_scale)
            self.lobe_line.set_marker("o" if drag.kind == "extrema" else "None")
            self.lobe_line.set_visible(True)
        else:
            self.lobe_line.set_visible(False)

    def _update_range(self) -> None:
        if self.range is None:
            self.range_patch.set_visible(False)
            return
        lo, hi = sorted(self.range)
        self.range_patch.set_bounds(lo, 0.0, hi - lo, 1.0)
        self.range_patch.set_visible(True)

    def _update_area_texts(self, law, report, deg, y) -> None:
        rows = [r for r in report.phases if r["kind"] != "dwell"]
        texts = iter(self._area_texts)
        for row in rows:
            inside = (deg >= row["start_deg"]) & (deg <= row["end_deg"])
            for sign, key in ((1, "area_positive"), (-1, "area_negative")):
                text = next(texts, None)
                if text is None:
                    return
                part = inside & (sign * y > 0)
                if not part.any():
                    text.set_visible(False)
                    continue
                centre = float(np.average(deg[part], weights=np.abs(y[part])))
                if row["kind"] == "rise":
                    name = "accel" if sign > 0 else "decel"
                else:
                    name = "decel" if sign > 0 else "accel"
                text.set_text(f"{row['kind']} {name}\n{row[key]:+.5g}")
                text.set_position((centre, 0.90 if sign > 0 else 0.035))
                text.set_va("top" if sign > 0 else "bottom")
                text.set_color("#1f6f65" if sign > 0 else "#b4472c")
                text.set_visible(True)
        for text in texts:
            text.set_visible(False)

    def _update_profile(self, law, report, texts: bool = True) -> None:
        try:
            preview = self.session.pitch_preview(361, law)
        except CamcadError:
            preview = None
        if preview is None:
            for artist in (self.p_line, self.p_base, self.p_gap):
                artist.set_data([], [])
            self.profile_text.set_text("no preview:\nthe cycle does\nnot divide 360°")
            return
        points, radius, gap = preview
        self.p_line.set_data(points[:, 0], points[:, 1])
        circle = np.linspace(0, 2 * math.pi, 121)
        self.p_base.set_data(radius * np.cos(circle), radius * np.sin(circle))
        closes = abs(report.displacement_closure) <= report.tolerance_abs
        if closes:
            self.p_gap.set_data([], [])
        else:
            self.p_gap.set_data([points[0, 0], points[-1, 0]], [points[0, 1], points[-1, 1]])
        if not texts:
            return
        self.profile_text.set_text(f"base circle\n  Rb {radius:.4g} mm\ngap at 0°\n  {gap:+.3g} mm\n"
                                   + ("closes" if closes else "DOES NOT\nCLOSE"))
        self.profile_text.set_color(ABOVE if closes else BELOW)

    def _autoscale(self, law, ghost) -> None:
        if self._drag is not None:
            return  # the axes stay frozen during a drag
        laws = [law] + ([ghost] if ghost is not None else [])
        for ax, line_get in ((self.ax_a, lambda c: c[1]), (self.ax_v, lambda c: c[3]), (self.ax_s, lambda c: c[4])):
            values = np.concatenate([line_get(self._curves(item)) for item in laws])
            lo, hi = float(np.min(values)), float(np.max(values))
            lo, hi = min(lo, 0.0), max(hi, 0.0)
            span = max(hi - lo, 1e-12)
            if ax is self.ax_a:
                ax.set_ylim(lo - 0.22 * span, hi + 0.30 * span)
            else:
                ax.set_ylim(lo - 0.12 * span, hi + 0.12 * span)
        if len(self.p_line.get_xdata()):
            self.ax_p.relim()
            self.ax_p.autoscale_view()
            x0, x1 = self.ax_p.get_xlim()
            y0, y1 = self.ax_p.get_ylim()
            half = 0.55 * max(x1 - x0, y1 - y0)
            cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
            self.ax_p.set_xlim(cx - half, cx + half)
            self.ax_p.set_ylim(cy - half, cy + half)

    def _update_texts(self, law) -> None:
        session = self.session
        report = session.report_of(law)
        self.title_text.set_text(f"camcad edit — {self.title}")
        self.status_text.set_text(f"{len(law.x)} vertices · {session.applied} "
                                  f"operation{'s' if session.applied != 1 else ''} · "
                                  f"undo {'yes' if session.can_undo else 'no'} · "
                                  f"redo {'yes' if session.can_redo else 'no'}"
                                  f" · saves to {self.output.name}")
        self.badge.set_text("\n".join(self.badge_lines(law, report)))
        preview = session.preview is not None
        closes = report.balanced
        face, edge = ("#dbeafe", PREVIEW) if preview else (("#dcfce7", ABOVE) if closes else ("#fde2e2", BELOW))
        bbox = cast(FancyBboxPatch, self.badge.get_bbox_patch())  # the badge is drawn with a bbox
        bbox.set_facecolor(face)
        bbox.set_edgecolor(edge)
        self.table.set_text("\n".join(self.table_lines(law, report)))
        self.readout.set_text(self.readout_line(law))
        self.msg_text.set_text(self.message)
        self.msg_text.set_color("#b91c1c" if self.message_error else "#1f2937")

    def badge_lines(self, law, report) -> list[str]:
        """The closure badge: verdict, v at the end of the rise and return, the displacement gap, areas."""
        session = self.session
        lines = []
        if session.preview is not None:
            p = session.preview
            lines.append(f"PREVIEW  {p.correction.mode}  (enter: accept, esc: reject)")
            lines.append(f"change  max {p.max_change:.4g}  RMS {p.rms_change:.4g}  (input y)")
            lines.append(("closes" if report.balanced else "STILL DOES NOT CLOSE") + " after it")
        else:
            lines.append("PROFILE CLOSES" if report.balanced else "PROFILE DOES NOT CLOSE")
        vc = report.velocity_closure
        lines.append(f"v end of rise   {vc['rise']:+.3e} mm/rad")
        lines.append(f"v end of return {vc['return']:+.3e} mm/rad")
        lines.append(f"gap s(end)-s(0) {report.displacement_closure:+.3e} mm")
        lines.append(f"tolerance       {report.tolerance_abs:.2e} ({report.tolerance:g} x rise)")
        areas = report.areas
        lines.append("areas ∫a dθ (mm/rad):")
        lines.append(f" rise   +{areas['rise_accel']:.5g} / {areas['rise_decel']:.5g}")
        lines.append(f" return {areas['return_accel']:.5g} / +{areas['return_decel']:.5g}")
        if session.preview is None:
            max_change, rms_change = session.changes(law)
            lines.append(f"edited: max Δa {max_change:.3g}, RMS {rms_change:.3g}")
        return lines

    def table_lines(self, law, report) -> list[str]:
        """Phases, then either the vertices around the selected one or the compare-all-modes table."""
        lines = ["phase      from (deg)  to (deg)   v at end"]
        for row in report.phases:
            v_end = f"{row['v_end']:+.2e}" if row["kind"] != "dwell" else ""
            lines.append(f"{row['kind']:<8s} {row['start_deg']:10.3f} {row['end_deg']:9.3f}  {v_end}")
        lines.append("")
        if self.compare is not None:
            where = "range {:.4g}..{:.4g} deg".format(*sorted(self.range)) if self.range else "whole law"
            lines.append(f"compare all modes ({where})")
            lines.append("   mode              max Δ     RMS Δ   closes")
            for k, row in enumerate(self.compare, start=1):
                if row.error:
                    lines.append(f"{k}  {row.mode:<16s}  {_clip(row.error, 27)}")
                else:
                    lines.append(f"{k}  {row.mode:<16s}{row.max_change:9.3g} {row.rms_change:9.3g}   "
                                 f"{'yes' if row.balanced else 'no'}")
            lines.append("press 1..7 to preview a mode")
            return lines
        if self.table_rows == 0:           # a short window: the phases only
            return lines
        lines.append("  vertex    θ (deg)     a (input y)")
        for i, deg, y, note in self.session.vertex_rows(self.selected, self.table_rows, law):
            mark = ">" if i == self.selected else " "
            lines.append(f"{mark}{i:6d} {deg:10.4f} {y:14.6g}  {note}")
        return lines

    def readout_line(self, law) -> str:
        mode = {"vertex": "vertex", "lobe": "lobe", "extrema": "extremum group"}[self.mode]
        if self.typing is not None:
            return f"type a value for vertex {self.selected} (Y or X:Y), enter to set: {self.typing}_"
        i = min(self.selected, len(law.x) - 1)
        sel = f"vertex {i}: θ {math.degrees(law.x[i]):.4f}°, a {law.a[i] / self.session.y_scale:.6g}"
        rng = "" if self.range is None else "  range {:.4g}..{:.4g}°".format(*sorted(self.range))
        return (f"drag: {mode}  snap: {'on' if self.snap else 'off'}  {sel}{rng}"
                + (f"  |  {self.cursor_text}" if self.cursor_text else ""))

    def numbers(self) -> dict:
        """What the browser shows live: the badge lines, the readout, the message and a few figures."""
        law, _ = self._shown_law()
        report = self.session.report_of(law)
        return {"badge": self.badge_lines(law, report), "readout": self.readout_line(law),
                "message": self.message, "error": self.message_error, "balanced": report.balanced,
                "preview": self.session.preview is not None,
                "velocity_closure": report.velocity_closure, "displacement_closure": report.displacement_closure,
                "areas": report.areas, "vertices": len(law.x), "operations": self.session.applied,
                "dragging": self._drag is not None and self._drag.moved, "status": self.status_line(law)}

    def _notify_live(self) -> None:
        if self.live is not None:
            self.live(self.numbers())

    # --- drags: blit or live numbers -----------------------------------------------------------------

    def _drag_redraw(self) -> None:
        """During a drag: the graph artists by blitting (the axes frozen), the numbers outside the plot (the
        window's status line, the browser's live panel); texts in the figure wait for the release."""
        law, ghost = self._shown_law()
        self.status = self.status_line(law)
        toolbar = getattr(self.canvas, "toolbar", None)
        if toolbar is not None and hasattr(toolbar, "set_message"):
            toolbar.set_message(self.status)
        if self.blit:
            self._update_curves(law, ghost, texts=False)
            if self._background is None:
                self.canvas.draw()
                return
            self.canvas.restore_region(self._background)
            for artist in self._dynamic:
                if artist.get_visible():
                    artist.axes.draw_artist(artist)
            for box in self._blit_boxes():
                self.canvas.blit(box)
        if self.live is not None:
            self._notify_live()

    def _blit_boxes(self) -> list:
        """What a drag changes: the three graphs (with their tick labels' margin) and the profile preview."""
        from matplotlib.transforms import Bbox

        graphs = Bbox.union([ax.bbox for ax in (self.ax_a, self.ax_v, self.ax_s)]).expanded(1.01, 1.01)
        return [graphs, self.ax_p.bbox.expanded(1.02, 1.02)]

    def status_line(self, law=None) -> str:
        """One line of live numbers: the verdict, the closures and the four areas."""
        law = law or self._shown_law()[0]
        report = self.session.report_of(law)
        vc, areas = report.velocity_closure, report.areas
        verdict = "closes" if report.balanced else "DOES NOT CLOSE"
        text = (f"{verdict}: gap {report.displacement_closure:+.3e} mm, v rise {vc['rise']:+.2e}, "
                f"v return {vc['return']:+.2e} mm/rad; areas {areas['rise_accel']:+.4g} {areas['rise_decel']:+.4g} "
                f"{areas['return_accel']:+.4g} {areas['return_decel']:+.4g} mm/rad")
        return text + (f" | {self.cursor_text}" if self.cursor_text else "")

    def _set_message(self, text: str, error: bool = False) -> None:
        self.message = text
        self.message_error = error

    # --- hit tests -------------------------------------------------------------------------------------

    def _pixels(self, ax, x, y) -> np.ndarray:
        return ax.transData.transform(np.column_stack((np.atleast_1d(x), np.atleast_1d(y))))

    def vertex_at(self, x_px: float, y_px: float) -> int | None:
        """The vertex within ``PICK_PX`` of the display point, nearest first."""
        law = self.session.law
        points = self._pixels(self.ax_a, np.degrees(law.x), law.a / self.session.y_scale)
        d2 = (points[:, 0] - x_px) ** 2 + (points[:, 1] - y_px) ** 2
        i = int(np.argmin(d2))
        return i if d2[i] <= PICK_PX ** 2 else None

    def boundary_at(self, ax, x_px: float) -> int | None:
        bounds = self.session.boundaries_deg()
        if not bounds:
            return None
        px = self._pixels(ax, bounds, np.zeros(len(bounds)))[:, 0]
        k = int(np.argmin(np.abs(px - x_px)))
        return k if abs(px[k] - x_px) <= PHASE_PX else None

    def display_xy(self, index: int) -> tuple[float, float]:
        """Display coordinates (pixels, origin bottom left) of vertex ``index`` (for tests and benchmarks)."""
        law = self.session.law
        return tuple(self._pixels(self.ax_a, math.degrees(law.x[index]), law.a[index] / self.session.y_scale)[0])

    def boundary_xy(self, k: int, ax=None) -> tuple[float, float]:
        ax = ax or self.ax_v
        b = self.session.boundaries_deg()[k]
        y = sum(ax.get_ylim()) / 2
        return tuple(self._pixels(ax, b, y)[0])

    def _data_xy(self, event, ax) -> tuple[float, float]:
        x, y = ax.transData.inverted().transform((event.x, event.y))
        return float(x), float(y)

    # --- mouse ---------------------------------------------------------------------------------------

    def _toolbar_busy(self) -> bool:
        toolbar = getattr(self.canvas, "toolbar", None)
        return bool(toolbar is not None and getattr(toolbar, "mode", ""))

    def on_press(self, event) -> None:
        if self._toolbar_busy() or self.typing is not None or event.inaxes is None:
            return
        ax = event.inaxes
        if ax not in (self.ax_a, self.ax_v, self.ax_s):
            return
        if event.button == 3 and ax is self.ax_a:
            self._insert_at(event.xdata, event.ydata)
            return
        if event.button != 1:
            return
        session = self.session
        index = self.vertex_at(event.x, event.y) if ax is self.ax_a else None
        if index is not None:
            self.selected = index
            kind = self.mode
            law = session.law
            if kind in ("lobe", "extrema") and len(lobe_of(law.a, index)) == 0:
                self._set_message("that vertex is on the axis: it has no lobe; drag mode v moves it", True)
                self.refresh()
                return
            shift = "shift" in getattr(event, "modifiers", ()) or event.key == "shift"
            drag = _Drag(kind, ax, (event.x, event.y), index=index, end=session.end_of(index),
                         base_deg=math.degrees(law.x[index]), free_x=shift and kind == "vertex")
            drag.snaps_y = self._snap_values(index, kind)
            if drag.free_x:
                lo, hi = session.x_limits(index)
                drag.snaps_x = tuple(v for v in (math.degrees(lo), math.degrees(hi)) if np.any(np.degrees(law.x) == v))
            session.begin_gesture()
            self._drag = drag
            self._set_message("")
            return
        k = self.boundary_at(ax, event.x)
        if k is not None:
            lo, hi = session.phase_limits(k)
            self._drag = _Drag("phase", ax, (event.x, event.y), index=k, base_deg=session.boundaries_deg()[k],
                               lo=lo, hi=hi)
            session.begin_gesture()
            self._set_message("")
            return
        if ax is self.ax_a:
            self._drag = _Drag("range", ax, (event.x, event.y), start_deg=float(event.xdata))

    def _snap_values(self, index: int, kind: str) -> tuple[float, ...]:
        """Ordinates (input y) the dragged vertex snaps to: the axis, the other lobes' extrema of its
        sign (scaled for a lobe drag, so the lobe's peak meets theirs), the other end of its jump."""
        law = self.session.law
        a = law.a
        lobe = lobe_of(a, index)
        peaks = []
        eps_lobes = _lobe_peaks(a)
        own_peak = None
        if len(lobe):
            own_peak = float(a[lobe][np.argmax(np.abs(a[lobe]))])
        for start, peak in eps_lobes:
            if len(lobe) and start == lobe[0]:
                continue
            if own_peak is not None and np.sign(peak) != np.sign(own_peak):
                continue
            peaks.append(peak)
        values = []
        if kind == "vertex":
            values.append(0.0)
            values.extend(peaks)
            first, last = _group(law.x, index)
            values.extend(float(a[j]) for j in range(first, last + 1) if j != index)
        elif kind == "lobe" and own_peak:
            values.extend(p * a[index] / own_peak for p in peaks)
        elif kind == "extrema":
            values.extend(peaks)
        return tuple(v / self.session.y_scale for v in values)

    def on_motion(self, event) -> None:
        drag = self._drag
        if drag is None:
            if event.inaxes is self.ax_a and event.xdata is not None:
                self.cursor_text = f"mouse θ {event.xdata:.3f}°, a {event.ydata:.5g}"
            return
        if abs(event.x - drag.press_xy[0]) < 1 and abs(event.y - drag.press_xy[1]) < 1 and not drag.moved:
            return
        drag.moved = True
        x, y = self._data_xy(event, drag.axes)
        session = self.session
        try:
            if drag.kind == "range":
                self.range = (drag.start_deg, min(max(x, 0.0), session.cycle_deg))
                self._update_range()
            elif drag.kind == "phase":
                to = min(max(x, drag.lo), drag.hi)
                session.apply({"op": "move_phase", "from_deg": drag.base_deg, "to_deg": to})
                for ax, line in zip((self.ax_a, self.ax_v, self.ax_s), self.drag_lines):
                    line.set_data([to, to], ax.get_ylim())
                    line.set_visible(True)
                self.cursor_text = f"boundary {drag.base_deg:.3f}° -> {to:.3f}°"
            else:
                self._drag_vertex(drag, x, y)
        except CamcadError as err:
            self._set_message(err.what, True)
        self._drag_redraw()

    def _drag_vertex(self, drag: _Drag, x: float, y: float) -> None:
        session = self.session
        snapped = ""
        if self.snap and drag.snaps_y:
            target_px = self._pixels(self.ax_a, 0.0, y)[0, 1]
            px = self._pixels(self.ax_a, np.zeros(len(drag.snaps_y)), np.array(drag.snaps_y))[:, 1]
            k = int(np.argmin(np.abs(px - target_px)))
            if abs(px[k] - target_px) <= SNAP_PX:
                y = float(drag.snaps_y[k])
                snapped = "axis" if y == 0.0 else "equal extremum / jump end"
        op = {"op": {"vertex": "move", "lobe": "move_lobe", "extrema": "move_extrema"}[drag.kind],
              "x_deg": drag.base_deg, "y": y}
        if drag.end is not None:
            op["end"] = drag.end
        if drag.free_x:
            lo, hi = session.x_limits(drag.index, session.gesture_base)
            to = min(max(x, math.degrees(lo)), math.degrees(hi))
            if self.snap and drag.snaps_x:
                px = self._pixels(self.ax_a, np.array(drag.snaps_x), np.zeros(len(drag.snaps_x)))[:, 0]
                target_px = self._pixels(self.ax_a, to, 0.0)[0, 0]
                k = int(np.argmin(np.abs(px - target_px)))
                if abs(px[k] - target_px) <= SNAP_PX:
                    to = float(drag.snaps_x[k])
                    snapped = (snapped + ", " if snapped else "") + "jump"
            op["to_x_deg"] = to
        session.apply(op)
        law = session.law
        i = self.selected
        self.cursor_text = (f"θ {math.degrees(law.x[i]):.4f}°, a {law.a[i] / session.y_scale:.6g}"
                            + (f"  [snap: {snapped}]" if snapped else ""))

    def on_release(self, event) -> None:
        drag = self._drag
        if drag is None:
            return
        self._drag = None
        session = self.session
        for line in self.drag_lines:
            line.set_visible(False)
        if drag.kind == "range":
            if not drag.moved or abs(event.x - drag.press_xy[0]) < CLICK_PX:
                self.range = None
                self._set_message("range cleared" if self.compare is None else "")
            else:
                lo, hi = sorted(cast(tuple[float, float], self.range))  # the drag has set it
                self._set_message(f"range {lo:.4g}..{hi:.4g} deg: press 1..7 to preview a mode on it")
                if self.compare is not None:
                    self.compare = session.compare_modes(self._segment())
        else:
            op = session.end_gesture()
            if op is not None:
                what = {"move": "vertex moved", "move_lobe": "lobe scaled", "move_extrema": "extremum group moved",
                        "move_phase": "phase boundary moved"}[op["op"]]
                self._set_message(f"{what} (one undo step)")
                if self.compare is not None:
                    self.compare = session.compare_modes(self._segment())
        self.cursor_text = ""
        self.refresh()

    # --- operations from keys ---------------------------------------------------------------------

    def _apply(self, op: dict, done: str) -> bool:
        try:
            self.session.apply(op)
        except CamcadError as err:
            self._set_message(err.what + (f"; {err.fix}" if err.fix else ""), True)
            return False
        self._set_message(done)
        if self.compare is not None:
            self.compare = self.session.compare_modes(self._segment())
        return True

    def _insert_at(self, x_deg: float | None, y: float | None) -> None:
        if x_deg is None or y is None:
            self._set_message("point at the acceleration graph to insert a vertex", True)
        elif self._apply({"op": "insert", "x_deg": float(x_deg), "y": float(y)},
                         f"vertex inserted at {x_deg:.4f} deg"):
            self.selected = int(np.searchsorted(self.session.law.x, math.radians(x_deg)))
        self.refresh()

    def _vertex_op(self, name: str, index: int, done: str, **fields) -> bool:
        law = self.session.law
        op = {"op": name, "x_deg": math.degrees(law.x[index]), **fields}
        end = self.session.end_of(index)
        if end is not None and name in ("move", "delete", "move_lobe", "move_extrema"):
            op["end"] = end
        return self._apply(op, done)

    def _segment(self) -> tuple[float, float] | None:
        if self.range is None:
            return None
        lo, hi = sorted(self.range)
        return (lo, hi) if hi > lo else None

    def on_key(self, event) -> None:
        key = event.key
        if key is None:
            return
        if self.typing is not None:
            self._typing_key(key)
            return
        session = self.session
        law = session.law
        if event.inaxes is self.ax_a and event.xdata is not None:
            self.cursor_text = f"mouse θ {event.xdata:.3f}°, a {event.ydata:.5g}"
        step = 0.01 * float(np.max(np.abs(law.a))) / session.y_scale
        i = min(self.selected, len(law.x) - 1)
        if key in ("v", "l", "e"):
            self.mode = {"v": "vertex", "l": "lobe", "e": "extrema"}[key]
            self._set_message(f"drag mode: {self.readout_line(law).split('  ')[0][6:]}")
        elif key == "h":
            self.help_wanted = not self.help_wanted
            self._layout()
            self._background = None
            self._set_message("the list of shortcuts " + ("shown" if self.help_block.get_visible() else
                                                          "hidden: h shows it" if not self.help_wanted else
                                                          "does not fit this window: make it taller"))
        elif key == "n":
            self.snap = not self.snap
            self._set_message(f"snapping {'on' if self.snap else 'off'}")
        elif key in ("up", "down", "shift+up", "shift+down"):
            factor = (10.0 if key.startswith("shift") else 1.0) * (1 if key.endswith("up") else -1)
            y = float(law.a[i]) / session.y_scale + factor * step
            self._vertex_op("move", i, f"vertex {i} nudged to {y:.6g}", y=y)
        elif key in ("left", "right"):
            self.selected = max(0, min(len(law.x) - 1, i + (1 if key == "right" else -1)))
            self._set_message("")
        elif key in ("shift+left", "shift+right"):
            to = math.degrees(law.x[i]) + (0.1 if key.endswith("right") else -0.1)
            to = min(max(to, 0.0), session.cycle_deg)
            self._vertex_op("move", i, f"vertex {i} nudged in angle", y=float(law.a[i]) / session.y_scale,
                            to_x_deg=to)
        elif key in ("i", "insert"):
            self._insert_at(event.xdata if event.inaxes is self.ax_a else None,
                            event.ydata if event.inaxes is self.ax_a else None)
            return
        elif key in ("d", "delete"):
            target = self.vertex_at(event.x, event.y) if event.inaxes is self.ax_a and event.x is not None else None
            target = i if target is None else target
            if self._vertex_op("delete", target, f"vertex {target} deleted"):
                self.selected = max(0, target - 1)
        elif key == "j":
            if session.end_of(i) is None:
                self._vertex_op("jump", i, f"jump made at vertex {i}: drag its right end")
                self.selected = i + 1 if self.message and not self.message_error else i
            else:
                self._vertex_op("unjump", i, "jump removed (its ends merged at their mean)")
        elif key == "t":
            self.typing = ""
        elif key in [str(k) for k in range(1, len(MODES) + 1)]:
            self._preview(MODES[int(key) - 1])
        elif key in ("enter", "a"):
            if session.preview is not None:
                mode = session.preview.correction.mode
                session.accept()
                self._set_message(f"{mode} accepted (one undo step)")
                if self.compare is not None:
                    self.compare = session.compare_modes(self._segment())
        elif key in ("escape", "backspace"):
            if session.preview is not None:
                session.reject()
                self._set_message("preview rejected: the law is unchanged")
            elif self.compare is not None:
                self.compare = None
                self._set_message("")
            elif self.range is not None:
                self.range = None
                self._set_message("range cleared")
            else:
                self._set_message("")
        elif key == "c":
            if self.compare is None:
                self.compare = session.compare_modes(self._segment())
                self._set_message("compare all modes: press 1..7 to preview one, c to close")
            else:
                self.compare = None
                self._set_message("")
        elif key == "p":
            self._apply({"op": "detect_phases"}, "phases found again from the edited law")
        elif key in ("z", "ctrl+z", "u"):
            self._undo_redo("undo")
        elif key in ("y", "ctrl+y", "ctrl+Z", "ctrl+shift+z", "U"):
            self._undo_redo("redo")
        elif key in ("s", "ctrl+s"):
            self._save(self.output)
        elif key == "w":
            self._save(self.output.with_suffix(".csv") if self.output.suffix.lower() != ".csv"
                       else self.output.with_name(self.output.stem + ".table.csv"))
        elif key == "x":
            self._save(default_script(self.session))
        else:
            return
        self.refresh()

    def _undo_redo(self, which: str) -> None:
        try:
            self.session.apply({"op": which})
            self._set_message(f"{which} done")
        except CamcadError as err:
            self._set_message(err.what, True)

    def _preview(self, mode: str) -> None:
        segment = self._segment()
        if mode == "segment" and segment is None:
            self._set_message("mode segment needs a range: drag on the acceleration graph first", True)
            return
        try:
            preview = self.session.preview_correction(mode, segment)
        except CamcadError as err:
            self._set_message(f"{mode}: {err.what}; the law is unchanged", True)
            return
        where = "whole law" if segment is None else f"range {segment[0]:.4g}..{segment[1]:.4g} deg"
        verdict = "closes" if preview.correction.after.balanced else "still does not close"
        self._set_message(f"preview {mode} on the {where}: max change {preview.max_change:.4g}, RMS "
                          f"{preview.rms_change:.4g}; {verdict}; enter accepts, esc rejects")

    def _save(self, path: Path) -> None:
        try:
            written = self.session.save(path)
        except CamcadError as err:
            self._set_message(err.message(), True)
            return
        self._set_message(f"saved {written}")

    def _typing_key(self, key: str) -> None:
        if key == "escape":
            self.typing = None
            self._set_message("typing cancelled")
        elif key == "enter":
            text, self.typing = cast(str, self.typing), None  # called while typing
            self._typed(text)
        elif key == "backspace":
            self.typing = cast(str, self.typing)[:-1]
        elif len(key) == 1 and key in "0123456789.-+eE:":
            self.typing = cast(str, self.typing) + key
        self.refresh()

    def _typed(self, text: str) -> None:
        session = self.session
        law = session.law
        i = min(self.selected, len(law.x) - 1)
        try:
            parts = [float(p) for p in text.split(":")]
            if len(parts) not in (1, 2) or not all(math.isfinite(p) for p in parts):
                raise ValueError
        except ValueError:
            self._set_message(f"{text!r} is not a number (Y) or an angle and a number (X:Y)", True)
            return
        if len(parts) == 1:
            self._vertex_op("move", i, f"vertex {i} set to {parts[0]:g}", y=parts[0])
        else:
            self._vertex_op("move", i, f"vertex {i} set to {parts[0]:g} deg, {parts[1]:g}", y=parts[1],
                            to_x_deg=parts[0])


# ---------------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------------

HELP_FONT = 7.2
#: width of the right-hand column (closure badge, pitch preview, tables), points
RIGHT_COLUMN_PT = 330.0
#: the pitch preview's side at most, points
PREVIEW_PT = 144.0
#: lines of the closure badge (a preview adds two)
BADGE_LINES = 10
#: lines of the table besides the vertex rows: its header, five phases, a blank line and the vertex header
TABLE_FIXED_LINES = 8
#: the smallest figure the layout is made for (px at 100 dpi): a 1366 x 768 screen less the toolbar and
#: a window manager's title bar and panel
MIN_FIGURE_PX = (1330, 620)
#: the shortcut columns: keys, then their descriptions this far to the right (inches)
HELP_KEYS_IN = 1.55


def help_columns(width_in: float) -> int:
    """Columns of the shortcut list on a figure ``width_in`` inches wide: a column is 3.9 in wide; four from
    16 in (fewer lines, so more height for the plots), three from 12 in, else two."""
    return 4 if width_in >= 16.0 else 3 if width_in >= 12.0 else 2


def help_height_pt(columns: int) -> float:
    """Height of the shortcut list in ``columns`` columns (points): its rows and the fix-modes line."""
    rows = math.ceil(len(SHORTCUTS) / columns)
    return (rows + 1.6) * HELP_FONT * 1.25 + 6.0


def _draw_help(fig: Figure) -> None:
    """The shortcut list in columns (``help_columns``) and the fix modes, on ``fig`` (the help block's own
    figure, as wide as the window)."""
    width = fig.get_figwidth()        # inches; the columns share the width, the descriptions follow the keys
    columns = help_columns(width / 0.965)
    per = math.ceil(len(SHORTCUTS) / columns)
    spacing = (width - 0.2) / columns
    top = 1.0 - 3.0 / 72.0 / fig.get_figheight()
    for c in range(columns):
        chunk = SHORTCUTS[c * per:(c + 1) * per]
        x = (0.2 + c * spacing) / width
        fig.text(x, top, "\n".join(k for k, _ in chunk), fontsize=HELP_FONT, va="top", family="monospace",
                 color="#1d4ed8")
        fig.text(x + HELP_KEYS_IN / width, top, "\n".join(w for _, w in chunk), fontsize=HELP_FONT, va="top",
                 family="monospace", color="0.2")
    modes = " · ".join(f"{k} {mode}" for k, mode in enumerate(MODES, start=1))
    fig.text(0.2 / width, 0.5 * HELP_FONT * 1.25 / 72.0 / fig.get_figheight() + 0.02,
             f"fix modes: {modes}   (a range limits them; mode segment needs one)",
             fontsize=HELP_FONT, va="center", family="monospace", color="0.2")


class _StaticBlock(Artist):
    """Texts that never change, rendered once (per size and dpi) into an image that every full draw pastes.

    ``rect`` is (x0, y0, x1, y1) in figure fractions; ``build(figure)`` draws the texts on a figure of
    that size (its own coordinates)."""

    def __init__(self, figure: Figure, rect: tuple[float, float, float, float], build) -> None:
        super().__init__()
        self._parent = figure
        self._rect = rect
        self._build = build
        self._cache: tuple[tuple[int, int, float], np.ndarray] | None = None
        self.last_figure: Figure | None = None

    def set_rect(self, rect: tuple[float, float, float, float]) -> None:
        """Move the block to ``rect`` (figure fractions); it is drawn again at its new size when it changes."""
        self._rect = rect

    def render(self, dpi: float) -> np.ndarray:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        fig = self._parent
        x0, y0, x1, y1 = self._rect
        w_in, h_in = fig.get_figwidth() * (x1 - x0), fig.get_figheight() * (y1 - y0)
        key = (round(w_in * dpi), round(h_in * dpi), dpi)
        if self._cache is None or self._cache[0] != key:
            block = Figure(figsize=(w_in, h_in), dpi=dpi)
            FigureCanvasAgg(block)
            block.patch.set_alpha(0.0)
            self._build(block)
            block.canvas.draw()
            self.last_figure = block
            self._cache = (key, np.asarray(cast(FigureCanvasAgg, block.canvas).buffer_rgba())[::-1].copy())
        return self._cache[1]

    def draw(self, renderer) -> None:
        if not self.get_visible():
            return
        image = self.render(renderer.dpi if hasattr(renderer, "dpi") else self._parent.dpi)
        box = self._parent.bbox
        gc = renderer.new_gc()
        renderer.draw_image(gc, round(box.x0 + box.width * self._rect[0]), round(box.y0 + box.height * self._rect[1]),
                            image)
        gc.restore()


def _group(x: np.ndarray, index: int) -> tuple[int, int]:
    return jump_group(x, index)


def _lobe_peaks(a: np.ndarray) -> list[tuple[int, float]]:
    """(first index, peak value) of every lobe of ``a``."""
    eps = zero_threshold(a)
    sign = np.where(np.abs(a) <= eps, 0, np.sign(a)).astype(int)
    change = np.flatnonzero(np.diff(sign) != 0) + 1
    starts = np.concatenate(([0], change))
    stops = np.concatenate((change, [len(a)]))
    peaks = []
    for start, stop in zip(starts, stops):
        if sign[start] != 0:
            part = a[start:stop]
            peaks.append((int(start), float(part[np.argmax(np.abs(part))])))
    return peaks


def _fill_outlines(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The polyline cut at its zero crossings, as closed outlines of its parts above and below the axis:
    (x, max(y, 0), min(y, 0)), each starting and ending on the axis."""
    cross = np.flatnonzero(y[:-1] * y[1:] < 0)
    if len(cross):
        xc = x[cross] + (x[cross + 1] - x[cross]) * y[cross] / (y[cross] - y[cross + 1])
        x = np.insert(x, cross + 1, xc)
        y = np.insert(y, cross + 1, 0.0)
    xs = np.concatenate(([x[0]], x, [x[-1]]))
    ys = np.concatenate(([0.0], y, [0.0]))
    return xs, np.maximum(ys, 0.0), np.minimum(ys, 0.0)


def _clip(text: str, width: int) -> str:
    return text if len(text) <= width else text[: width - 1] + "…"


def new_figure() -> Figure:
    """A Figure of the editor's size (not attached to any canvas)."""
    return Figure(figsize=FIGSIZE, dpi=100)


#: what a desktop takes around the figure, px: the toolbar, a window manager's title bar and its panel
WINDOW_CHROME_PX = (16, 120)


def window_size(screen_px: tuple[int, int]) -> tuple[int, int]:
    """The figure's size (px at 100 dpi) for a window on a screen of ``screen_px``: the editor's own size
    (``FIGSIZE``), or less so that the window, its toolbar and the desktop's title bar and panel fit the
    screen (a 1366 x 768 laptop: 1350 x 648).

    Examples
    --------
    >>> window_size((1366, 768)), window_size((2560, 1440))
    ((1350, 648), (1500, 980))
    """
    width = min(round(FIGSIZE[0] * 100), screen_px[0] - WINDOW_CHROME_PX[0])
    height = min(round(FIGSIZE[1] * 100), screen_px[1] - WINDOW_CHROME_PX[1])
    return max(width, 640), max(height, 400)
