"""The summary page drawn for less: one figure reused across the mechanisms of a group must give exactly the
page a fresh figure gives (issue 32), and its labels stay where matplotlib's own placement puts them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import SAMPLES

from camcad.report.figure import save_figure
from camcad.report.profile import SummaryPage
from camcad.scene.pipeline import PipelineOptions, analyse_scene


@pytest.fixture(scope="module")
def loom():
    return analyse_scene(SAMPLES / "scenes" / "loom_group1.toml", PipelineOptions(plots=()))


def _pixels(path: Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


@pytest.mark.reference("second method", "a page drawn into a fresh figure, pixel for pixel")
def test_a_reused_page_is_the_page_a_fresh_figure_draws(loom, tmp_path):
    names = list(loom.runs)
    assert len(names) >= 3
    page = SummaryPage()
    for name in names:       # every page after the first is drawn over the one before it
        save_figure(page.draw(loom.runs[name].profile, loom.report["mechanisms"][name]), tmp_path / f"{name}.png")
    for name in names[1:]:
        fresh = SummaryPage().draw(loom.runs[name].profile, loom.report["mechanisms"][name])
        save_figure(fresh, tmp_path / f"{name}-fresh.png")
        assert np.array_equal(_pixels(tmp_path / f"{name}.png"), _pixels(tmp_path / f"{name}-fresh.png")), name


@pytest.mark.reference("second method", "matplotlib's own label placement (it measures the tick labels)")
def test_fixed_label_positions_are_where_matplotlib_puts_the_labels(loom, monkeypatch):
    import camcad.report.profile as plots

    def labels(fig):
        fig.canvas.draw()
        return [(ax.xaxis.label.get_window_extent(), ax.yaxis.label.get_window_extent())
                for ax in fig.axes if ax.axison]

    for name in loom.runs:
        run, report = loom.runs[name].profile, loom.report["mechanisms"][name]
        fixed = labels(SummaryPage().draw(run, report))
        with monkeypatch.context() as patch:
            patch.setattr(plots, "fix_label_positions", lambda fig: None)
            auto = labels(SummaryPage().draw(run, report))
        assert len(fixed) == len(auto) >= 5
        for (fx, fy), (mx, my) in zip(fixed, auto):
            if fx.width > 0:   # an x label: the same height within 3 px (1 pt is 1.5 px at 110 dpi)
                assert abs(fx.y1 - mx.y1) <= 3.0 and abs(fx.x0 - mx.x0) <= 0.5, name
            if fy.height > 0:  # a y label: beside the widest tick label within 6 px
                assert abs(fy.x0 - my.x0) <= 6.0 and abs(fy.y0 - my.y0) <= 0.5, name
