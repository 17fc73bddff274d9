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
