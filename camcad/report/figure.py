"""The figure conventions of every camcad plot: made without pyplot, saved by the caller.

- A plot function takes the analysis' result and returns a ``matplotlib.figure.Figure`` (made with
  ``new_figure``); it writes nothing. Saving is the caller's business: ``save_figure`` (atomic, PNG, the
  project's DPI) or the user's own ``fig.savefig``.
- No pyplot: figures are plain ``Figure`` objects with an Agg canvas, so nothing global is touched, no
  figure is leaked, and plots can be drawn in parallel processes.
- Cheap to draw: a fixed DPI (``DPI``), the constrained layout engine (one layout pass at draw time, no
  tight bounding-box recomputation on save), unhinted glyphs and fast PNG compression (``HINTING``,
  ``PNG_COMPRESSION``).
- Every plot shows its limits and margins where they apply, says which phase angles it shows, and uses
  the law's own units (mm or rad/deg of swing).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from camcad.io.atomic import write_atomic

#: resolution of the written PNG files (dots per inch)
DPI = 110
#: FreeType hinting of the glyphs of every saved figure: none (hinting is 15 % of the time of a page full of
#: text; at this DPI the letters are as legible without it)
HINTING = "none"
#: zlib level of the PNG files: 1 writes a summary page in 63 ms instead of 100 ms (level 6) for 8 % more bytes
PNG_COMPRESSION = 1
#: height of every title above its axes (axes fraction): a title given its height is placed there, where
#: matplotlib would otherwise measure every tick label of its axes on every draw to lift it clear of them
#: (camcad's axes have no tick labels on top)
TITLE_Y = 1.0
#: the colours used for the same thing in every plot
COLOURS = {"rise": "#d9ead3", "return": "#f4cccc", "dwell": "#eeeeee", "limit": "#c00000", "ok": "#2e7d32",
           "fail": "#c00000", "law": "#1f4e79", "elastic": "#e07b00", "original": "#999999"}


def new_figure(width_in: float = 10.0, height_in: float = 5.0, *, rows: int = 1, cols: int = 1,
               layout: Literal["constrained", "compressed", "tight"] | None = "constrained",
               **subplot_kw: Any):
    """A Figure with an Agg canvas and its axes (an array when ``rows`` or ``cols`` > 1).

    Parameters
    ----------
    width_in, height_in : float
        Size in inches.
    rows, cols : int
        Grid of axes; ``rows = 0`` for none (the caller lays out its own).
    layout : str or None
        matplotlib layout engine ("constrained", or None for fixed margins).
    **subplot_kw
        Passed to ``Figure.subplots`` (e.g. ``sharex=True``, ``gridspec_kw``).

    Returns
    -------
    (Figure, Axes or ndarray of Axes, or None when ``rows = 0``)

    Examples
    --------
    >>> fig, ax = new_figure(4, 3)
    >>> type(fig).__name__, fig.get_dpi() == DPI
    ('Figure', True)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI, layout=layout)
    FigureCanvasAgg(fig)
    axes = fig.subplots(rows, cols, squeeze=True, **subplot_kw) if rows else None
    return fig, axes


def fix_label_positions(fig) -> None:
    """Place the x and y labels of every axes of ``fig`` at fixed distances outside its tick labels, instead
    of matplotlib's placing them by measuring every tick label on every draw (~15 % of the time of a page of
    several axes). Call it when the axes' limits are final. A y label keeps the distance of the axes' widest
    tick label, estimated from its characters' advance (0.64 em: DejaVu Sans digits), so it sits where
    matplotlib would put it.
    """
    import matplotlib
    from matplotlib.font_manager import FontProperties
    from matplotlib.transforms import ScaledTranslation

    gap = 3.5 + 3.5 + 4.0                   # tick length, label pad and a gap, pt
    for ax in fig.axes:
        if not ax.axison:
            continue
        for axis in (ax.xaxis, ax.yaxis):
            if not axis.label.get_text():
                continue
            labelsize = (matplotlib.rcParams["xtick.labelsize"] if axis is ax.xaxis
                         else matplotlib.rcParams["ytick.labelsize"])
            size = FontProperties(size=labelsize).get_size_in_points()
            far = axis.get_label_position() in ("top", "right")
            if axis is ax.xaxis:
                offset = gap + size                               # one line of tick labels (1 em)
                at, shift = (0.5, 1.0 if far else 0.0), (0.0, offset if far else -offset)
                axis.label.set_verticalalignment("bottom" if far else "top")
            else:
                low, high = sorted(axis.get_view_interval())
                slack = 1e-9 * max(abs(low), abs(high), 1e-300)
                values = [v for v in axis.get_major_locator()() if low - slack <= v <= high + slack]
                labels = axis.get_major_formatter().format_ticks(values)
                offset = gap + max((0.64 * len(text) for text in labels), default=1.0) * size
                at, shift = (1.0 if far else 0.0, 0.5), (offset if far else -offset, 0.0)
                axis.label.set_verticalalignment("top" if far else "bottom")
            axis.set_label_coords(*at, transform=ax.transAxes + ScaledTranslation(
                shift[0] / 72.0, shift[1] / 72.0, fig.dpi_scale_trans))


def save_figure(fig, path: str | Path, dpi: int = DPI) -> Path:
    """Write ``fig`` as a PNG to ``path`` atomically; returns ``path``.

    The PNG carries no time stamp or software version, so identical figures give identical files.
    """
    import matplotlib

    metadata = {"Software": None}

    def save(tmp: Path) -> None:
        with matplotlib.rc_context({"text.hinting": HINTING}):
            fig.savefig(tmp, format="png", dpi=dpi, metadata=metadata, pil_kwargs={"compress_level": PNG_COMPRESSION})

    return write_atomic(path, save)


def pyplot():
    """matplotlib.pyplot with the Agg backend (for plot functions not yet converted to ``new_figure``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
