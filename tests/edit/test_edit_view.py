"""The editor's view driven by real matplotlib mouse and key events on an off-screen Agg canvas:
drags (vertex, snap, lobe, phase boundary, range), insert/delete, shortcuts, preview/accept, saving,
and the layout (the readout outside the plot, the shortcut list not cut off)."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
from conftest import SAMPLES
from matplotlib.backend_bases import KeyEvent, MouseEvent
from matplotlib.backends.backend_agg import FigureCanvasAgg

from camcad.edit.session import EditSession, loaded_from_law
from camcad.edit.view import MIN_FIGURE_PX, SHORTCUTS, EditorView, help_columns, new_figure
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.phases import detect_phases
from camcad.law.source import load_law

T = 2 * math.pi


class QuietCanvas(FigureCanvasAgg):
    """The Agg canvas, but a full redraw requested by the view (draw_idle) only counts: the tests look at
    the session and the artists; blitting during drags still draws for real on the first background."""

    idle_draws = 0

    def draw_idle(self, *args, **kwargs):
        self.idle_draws += 1


def make_view(session: EditSession, tmp_path=None, canvas=QuietCanvas) -> EditorView:
    figure = new_figure()
    canvas(figure)
    out = tmp_path / "out.dxf" if tmp_path is not None else None
    view = EditorView(session, figure, output=out)
    figure.canvas.draw()
    return view


def fig2(tmp_path) -> EditSession:
    source = tmp_path / "fig2.dxf"
    shutil.copy(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf", source)
    return EditSession.from_file(source)


def mouse(view, name, x, y, button=1, modifiers=()):
    """A real MouseEvent (matplotlib keeps whole pixels of x and y)."""
    canvas = view.canvas
    kw = {"buttons": {button}} if name == "motion_notify_event" else {"button": button}
    canvas.callbacks.process(name, MouseEvent(name, canvas, x, y, modifiers=modifiers, **kw))


def drag(view, start, end, steps=6, modifiers=()):
    mouse(view, "button_press_event", *start, modifiers=modifiers)
    for t in np.linspace(0, 1, steps + 1)[1:]:
        mouse(view, "motion_notify_event", start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1]),
              modifiers=modifiers)
    mouse(view, "button_release_event", *end, modifiers=modifiers)


def key(view, name, x=5.0, y=5.0):
    canvas = view.canvas
    canvas.callbacks.process("key_press_event", KeyEvent("key_press_event", canvas, name, x, y))


def data_y(view, y_px):
    return view.ax_a.transData.inverted().transform((0, y_px))[1]


def two_lobes() -> PiecewiseLinearLaw:
    x = np.radians([0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330, 360.0])
    a = np.array([0, 5, 0, 8, 0, -6, 0, -7, 0, 3, 0, -3, 0.0])
    return PiecewiseLinearLaw(x, a, T, detect_phases(x, a, T))


def test_vertex_drag_is_one_operation_drawn_by_blitting(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path, canvas=FigureCanvasAgg)   # real full draws here
    assert view.blit and view._background is not None
    i = 120
    x, y = (round(v) for v in view.display_xy(i))
    target = data_y(view, y - 25)            # the axes stay frozen during the drag
    drag(view, (x, y), (x, y - 25))
    assert s.operations == [{"op": "move", "x_deg": pytest.approx(math.degrees(s.law.x[i])),
                             "y": pytest.approx(target, rel=1e-9)}]
    assert s.law.a[i] == pytest.approx(target, rel=1e-9)
    key(view, "z")
    assert s.law is s.initial_law
    key(view, "ctrl+y")
    assert s.law.a[i] == pytest.approx(target, rel=1e-9)


def test_drag_snaps_to_the_axis_and_to_equal_extrema():
    s = EditSession(loaded_from_law(two_lobes(), "two lobes"))
    view = make_view(s)
    x, y = view.display_xy(1)                 # the +5 peak
    zero = view.ax_a.transData.transform((0, 0))[1]
    drag(view, (x, y), (x, zero + 3))
    assert s.law.a[1] == 0.0                  # snapped onto the axis
    key(view, "z")
    peak8 = view.ax_a.transData.transform((0, 8.0))[1]
    drag(view, (x, y), (x, peak8 - 4))
    assert s.law.a[1] == 8.0                  # snapped to the other lobe's extremum
    key(view, "n")                            # snapping off
    key(view, "z")
    drag(view, (x, y), (x, peak8 - 4))
    assert s.law.a[1] != 8.0


def test_shift_drag_moves_in_angle_and_clamps_to_a_jump():
    s = EditSession(loaded_from_law(two_lobes(), "two lobes"))
    view = make_view(s)
    x, y = view.display_xy(3)                 # the +8 peak at 90 deg, between 60 and 120
    far = view.ax_a.transData.transform((150, 8.0))[0]
    drag(view, (x, y), (far, y), modifiers={"shift"})
    assert s.law.x[3] == s.law.x[4] == math.radians(120)   # stopped at its neighbour: a jump
    assert s.operations[-1]["to_x_deg"] == pytest.approx(120.0)


def test_lobe_and_extremum_drags():
    law = two_lobes()
    s = EditSession(loaded_from_law(law, "two lobes"))
    view = make_view(s)
    key(view, "l")
    x, y = view.display_xy(3)
    drag(view, (x, y), (x, y + 30))          # display y grows upwards
    op = s.operations[-1]
    assert op["op"] == "move_lobe"
    factor = s.law.a[3] / law.a[3]
    assert factor > 1 and np.array_equal(s.law.a[2:5], law.a[2:5] * factor)
    key(view, "e")
    x, y = view.display_xy(7)                 # the -7 trough, dragged down
    drag(view, (x, y), (x, y - 20))
    assert s.operations[-1]["op"] == "move_extrema" and s.law.a[7] < law.a[7]
    key(view, "l")
    x, y = view.display_xy(0)                 # on the axis: no lobe, a message, nothing changes
    before = s.applied
    mouse(view, "button_press_event", x, y)
    assert "no lobe" in view.message and view.message_error and s.applied == before


def test_insert_and_delete_from_mouse_and_keys():
    s = EditSession(loaded_from_law(two_lobes(), "two lobes"))
    view = make_view(s)
    px, py = view.ax_a.transData.transform((45.0, 2.0))
    mouse(view, "button_press_event", px, py, button=3)
    assert len(s.law.x) == 14 and s.operations[-1]["op"] == "insert"
    # matplotlib's events carry whole pixels: a pixel is about 0.4 deg and 0.05 in y here
    assert s.operations[-1]["x_deg"] == pytest.approx(45.0, abs=0.5)
    assert s.operations[-1]["y"] == pytest.approx(2.0, abs=0.1)
    px, py = view.ax_a.transData.transform((200.0, -1.0))
    key(view, "i", px, py)
    assert len(s.law.x) == 15
    x, y = view.display_xy(int(np.argmin(np.abs(s.law.x - math.radians(200)))))
    key(view, "d", x, y)
    assert len(s.law.x) == 14 and s.operations[-1] == {"op": "delete", "x_deg": pytest.approx(200.0, abs=0.5)}
    key(view, "j")                           # a jump at the selected vertex, then removed again
    assert s.operations[-1]["op"] == "jump"
    key(view, "j")
    assert s.operations[-1]["op"] == "unjump"


def test_preview_accept_and_reject(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path)
    law0 = s.law
    key(view, "1")                            # min-change
    assert s.preview is not None and s.law is law0
    assert view.ghost_a.get_visible() and "PREVIEW" in view.badge.get_text()
    assert "max change" in view.message
    key(view, "escape")
    assert s.preview is None and s.law is law0 and not view.ghost_a.get_visible()
    key(view, "1")
    key(view, "enter")
    assert s.report.balanced and s.operations == [{"op": "correct", "mode": "min-change"}]
    assert "CLOSES" in view.badge.get_text()


def test_range_selection_limits_the_mode_and_compare_table(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path)
    a_px = view.ax_a.transData.transform
    start, end = a_px((100.0, -9.5)), a_px((350.0, -9.5))    # empty space low in the graph
    drag(view, tuple(start), tuple(end))
    assert view.range == (pytest.approx(100.0, abs=0.5), pytest.approx(350.0, abs=0.5))
    key(view, "5")                                           # segment mode on the range
    assert s.preview is not None and s.preview.op["segment"] == pytest.approx([100, 350], abs=0.5)
    key(view, "enter")
    held = s.law.x < math.radians(99)
    assert np.array_equal(s.law.a[held], s.initial_law.a[held])
    key(view, "c")
    assert "compare all modes" in view.table.get_text() and "min-change" in view.table.get_text()
    key(view, "c")


def test_an_impossible_mode_shows_the_error_and_keeps_the_law(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path)
    a_px = view.ax_a.transData.transform
    drag(view, tuple(a_px((5.0, -9.5))), tuple(a_px((50.0, -9.5))))   # only the first dwell
    law0 = s.law
    key(view, "5")
    assert view.message_error and "unchanged" in view.message
    assert s.law is law0 and s.preview is None


def test_phase_boundary_drag_on_the_velocity_panel(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path)
    x, y = view.boundary_xy(1)                    # rise | dwell at 180 deg
    to = view.ax_v.transData.transform((190.0, 0))[0]
    drag(view, (x, y), (to, y))
    op = s.operations[-1]
    assert op["op"] == "move_phase" and op["to_deg"] == pytest.approx(190.0, abs=0.5)
    assert math.degrees(s.law.phases[1].end) == pytest.approx(op["to_deg"], abs=1e-9)
    assert len(s.operations) == 1                 # one drag, one operation


def test_nudges_typed_values_and_saving(tmp_path):
    s = fig2(tmp_path)
    view = make_view(s, tmp_path)
    view.selected = 120
    a0 = float(s.law.a[120])
    step = 0.01 * float(np.max(np.abs(s.law.a)))
    key(view, "up")
    assert s.law.a[120] == pytest.approx(a0 + step, rel=1e-12)
    key(view, "shift+down")
    assert s.law.a[120] == pytest.approx(a0 - 9 * step, rel=1e-12)
    for k in ("t", "2", ".", "5", "enter"):
        key(view, k)
    assert s.law.a[120] == 2.5
    key(view, "right")
    assert view.selected == 121
    key(view, "s")
    assert (tmp_path / "out.dxf").exists() and "saved" in view.message
    key(view, "x")
    assert (tmp_path / "fig2.edits.json").exists()
    key(view, "w")
    assert (tmp_path / "out.csv").exists()
    assert load_law(tmp_path / "out.dxf").law.a[120] == pytest.approx(2.5, rel=1e-9)


def test_nothing_to_undo_is_a_message_not_an_error():
    s = EditSession(loaded_from_law(two_lobes(), "two lobes"))
    view = make_view(s)
    key(view, "z")
    assert view.message_error and "nothing to undo" in view.message


@pytest.mark.parametrize("size_px", [None, MIN_FIGURE_PX, (1900, 1000), "resized", (1100, 550)])
def test_layout_readout_outside_the_plot_and_shortcuts_not_cut_off(size_px):
    from matplotlib.backend_bases import ResizeEvent

    s = EditSession(loaded_from_law(two_lobes(), "two lobes"))
    view = make_view(s, canvas=FigureCanvasAgg)
    if size_px is not None:     # a window of that size (px at 100 dpi), or one shrunk after it opened
        width, height = MIN_FIGURE_PX if size_px == "resized" else size_px
        view.figure.set_size_inches(width / 100, height / 100)
        ResizeEvent("resize_event", view.canvas)._process()     # as the window's canvas sends it
        view.canvas.draw()
    renderer = view.canvas.get_renderer()
    fig_box = view.figure.bbox
    axes_boxes = [ax.get_window_extent(renderer) for ax in (view.ax_a, view.ax_v, view.ax_s, view.ax_p)]
    texts = (view.readout, view.badge, view.table, view.msg_text, view.profile_text, view.title_text,
             view.status_text)
    text_boxes = [text.get_window_extent(renderer) for text in texts]
    for text, box in zip(texts, text_boxes):
        assert not any(box.overlaps(ax_box) for ax_box in axes_boxes), text.get_text()[:40]
        assert fig_box.x0 <= box.x0 and box.x1 <= fig_box.x1 and fig_box.y0 <= box.y0 and box.y1 <= fig_box.y1, \
            text.get_text()[:40]
    for i, first in enumerate(text_boxes[:5]):
        for second in text_boxes[i + 1:5]:
            assert not first.overlaps(second)
    for ax_box in axes_boxes:
        assert fig_box.x0 <= ax_box.x0 < ax_box.x1 <= fig_box.x1 and fig_box.y0 <= ax_box.y0 < ax_box.y1 <= fig_box.y1
    x0, y0, x1, y1 = view.help_block._rect                 # nothing reaches into the shortcut list
    top_of_list = fig_box.height * y1
    for box in text_boxes[:5] + axes_boxes:
        assert box.y0 >= top_of_list
    assert view.ax_a.get_window_extent(renderer).height >= 100
    if size_px == (1100, 550):   # smaller than a 1366 x 768 screen: the list gives way to the plots, h shows it
        assert not view.help_block.get_visible() and view.help_hint.get_visible()
        return
    assert view.table_rows >= 3 and view.ax_a.get_window_extent(renderer).height >= 150
    assert view.help_block.get_visible() and not view.help_hint.get_visible()
    help_figure = view.help_block.last_figure           # the shortcut list, drawn once into an image
    help_renderer = help_figure.canvas.get_renderer()
    help_box = help_figure.bbox
    texts = help_figure.texts
    boxes = [t.get_window_extent(help_renderer) for t in texts]
    assert len(boxes) == 2 * help_columns(view.figure.get_figwidth()) + 1
    for box in boxes:
        assert help_box.x0 <= box.x0 and box.x1 <= help_box.x1 and help_box.y0 <= box.y0 and box.y1 <= help_box.y1
    for i, first in enumerate(boxes):
        for second in boxes[i + 1:]:
            assert not first.overlaps(second)
    shown = "\n".join(t.get_text() for t in texts)
    assert all(k in shown and w in shown for k, w in SHORTCUTS)
    block = view.help_block
    x0, y0, x1, y1 = block._rect
    assert 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1
    assert view.readout.get_window_extent(renderer).y0 > fig_box.height * y1   # the readout is above the list
