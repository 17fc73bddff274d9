"""A law drawn as an outlined stroke: the closed outline of a band of half-width w around the law, read
as its centre line.

OpenSCAD cannot draw a line, only areas: a law modelled there (``offset``, or the hull of circles along
it) is exported as the closed outline of a band around the law, one closed LWPOLYLINE (or one LINE per
edge in older releases). Illustrator's "Outline Stroke" and Inkscape's "Stroke to Path" do the same to a
drawn stroke. Either side of the band is the law offset by w, so neither is the law; the centre line is.

The rule (docs/reading.md):

- **A band.** Cut the outline by vertical lines through all its vertices: between two consecutive ones,
  every vertical line must cross the outline exactly twice (an upper and a lower side, each straight
  there). The centre line is the mid-point of the two crossings: exact on every straight stretch of the
  law, whatever its slope (both offsets of a line of slope m lie w·√(1+m²) above and below it), and off
  by O(w²·curvature) on curves. At a vertical jump it is a step of half the jump over 2w, which keeps
  the area of the jump.
- **Thin and even.** The band's half-width measured square to the centre line must be the same (within
  20 %) over at least 70 % of the x-range, nowhere less than half of it (but within 2w of the ends), and
  small: at most ``MAX_WIDTH_FRACTION`` of its length in x. A law and its axis meeting at both ends close
  a region that is no band (it is thin where the law dwells on the axis).
  A closed cam profile, a frame or a filled shape is not a band; a thin rectangle is the band of a
  straight line (OpenSCAD draws an axis so).
- **Ends.** A butt cap is one edge of length 2w at the outline's extreme, square to the law: the law
  ends at its middle (a square cap looks the same and is read so: the law then reads w longer at that
  end). Otherwise the cap is round, a half circle round the law's end: the law ends w inside it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: the band's half-width is at most this fraction of its length in x (a thin band, not a filled shape)
MAX_WIDTH_FRACTION = 0.05
#: the half-width measured square to the centre line agrees with the band's within this fraction ...
EVEN_FRACTION = 0.2
#: ... over at least this fraction of the x-range
EVEN_SHARE = 0.7
#: and the band is nowhere (but within 2w of its ends) thinner than this fraction of its width
THIN_FRACTION = 0.5


@dataclass(frozen=True)
class Band:
    """The centre line of an outlined stroke and what it was read with.

    Attributes
    ----------
    centre : ndarray, shape (n, 2)
        The centre line, left to right (drawing units); equal x at consecutive points is a jump.
    half_width : float
        The band's half-width w (drawing units).
    caps : tuple of str
        "butt" or "round" at the left and the right end.
    """

    centre: np.ndarray
    half_width: float
    caps: tuple[str, str]


def band_centre_line(ring: np.ndarray, x_tol: float) -> Band | None:
    """The centre line of a closed outline that is a band around a function of x, or None.

    Parameters
    ----------
    ring : ndarray, shape (n, 2)
        The outline's vertices in order (drawing units); closing back to the first is implied.
    x_tol : float
        x values closer than this are one (drawing units).

    Returns
    -------
    Band or None
        None when the outline is not a thin band of even width around a function of x (see the module
        docstring).

    Examples
    --------
    A band of half-width 0.5 around the line y = x/10 from x = 0 to 100, butt caps:

    >>> ring = np.array([[0, 0.5], [100, 10.5], [100, 9.5], [0, -0.5]])
    >>> band = band_centre_line(ring, 1e-9)
    >>> band.centre.tolist(), round(band.half_width, 6), band.caps
    ([[0.0, 0.0], [100.0, 10.0]], 0.497519, ('butt', 'butt'))
    """
    pts = np.asarray(ring, dtype=float)
    if len(pts) >= 2 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    if len(pts) < 4:
        return None
    start, end = pts, np.roll(pts, -1, axis=0)
    order = np.argsort(pts[:, 0], kind="stable")
    xs_sorted = pts[order, 0]
    new = np.concatenate(([True], np.diff(xs_sorted) > x_tol))
    columns = np.cumsum(new) - 1
    xs = np.bincount(columns, weights=xs_sorted) / np.bincount(columns)
    column_of = np.empty(len(pts), dtype=int)
    column_of[order] = columns
    if len(xs) < 2:
        return None
    c0, c1 = column_of, np.roll(column_of, -1)
    lo, hi = np.minimum(c0, c1), np.maximum(c0, c1)
    slanted = hi > lo
    # every non-vertical edge covers the slabs lo..hi-1; a band has exactly two edges over each slab
    edge = np.flatnonzero(slanted)
    counts = hi[edge] - lo[edge]
    slab = np.repeat(lo[edge], counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
    owner = np.repeat(edge, counts)
    per_slab = np.bincount(slab, minlength=len(xs) - 1)
    if np.any(per_slab != 2):
        return None
    sort = np.argsort(slab, kind="stable")
    owner = owner[sort].reshape(-1, 2)
    left_x, right_x = xs[:-1], xs[1:]

    def y_at(e: np.ndarray, x: np.ndarray) -> np.ndarray:
        p, q = start[e], end[e]
        t = (x - p[:, 0]) / (q[:, 0] - p[:, 0])
        return p[:, 1] + t * (q[:, 1] - p[:, 1])

    ya = np.column_stack((y_at(owner[:, 0], left_x), y_at(owner[:, 1], left_x)))
    yb = np.column_stack((y_at(owner[:, 0], right_x), y_at(owner[:, 1], right_x)))
    mid_a, mid_b = ya.mean(axis=1), yb.mean(axis=1)
    thick_a, thick_b = np.abs(ya[:, 0] - ya[:, 1]), np.abs(yb[:, 0] - yb[:, 1])
    width = right_x - left_x
    slope = (mid_b - mid_a) / width
    # the half-width square to the centre line, at the middle of each slab
    half = (thick_a + thick_b) / 4.0 / np.sqrt(1.0 + slope ** 2)
    w = _weighted_median(half, width)
    span, height = float(xs[-1] - xs[0]), float(np.ptp(pts[:, 1]))
    if not w > 0 or w > MAX_WIDTH_FRACTION * span:
        return None
    even = np.abs(half - w) <= EVEN_FRACTION * w
    if width[even].sum() < EVEN_SHARE * span:
        return None
    # a stroke is never thin in its middle: a region between a law and its axis (which meet in the dwells) is
    # no band, however even it is elsewhere
    core = (left_x >= xs[0] + 2 * w) & (right_x <= xs[-1] - 2 * w)
    if np.any(np.minimum(thick_a, thick_b)[core] < THIN_FRACTION * 2 * w):
        return None
    centre = np.empty((2 * len(width), 2))
    centre[0::2, 0], centre[1::2, 0] = left_x, right_x
    centre[0::2, 1], centre[1::2, 1] = mid_a, mid_b
    # consecutive slabs meet at one x: one point where they agree, a jump where they do not
    keep = np.ones(len(centre), dtype=bool)
    keep[2::2] = np.abs(centre[2::2, 1] - centre[1:-1:2, 1]) > 1e-12 * max(height, 1e-300)
    centre = centre[keep]
    left_cap = _butt_cap(pts, int(np.argmin(pts[:, 0])), w)
    right_cap = _butt_cap(pts, int(np.argmax(pts[:, 0])), w)
    caps = ("butt" if left_cap is not None else "round", "butt" if right_cap is not None else "round")
    # a butt cap is one edge of length 2w square to the law: the law ends at its middle; a round cap is a
    # half circle of radius w round the law's end
    if left_cap is not None:
        mid, reach = left_cap
        centre = np.vstack((mid, centre[centre[:, 0] > max(reach, mid[0])]))
    else:
        centre = _trim(centre, float(xs[0]) + w, left=True)
    if right_cap is not None:
        mid, reach = right_cap
        centre = np.vstack((centre[centre[:, 0] < min(reach, mid[0])], mid))
    else:
        centre = _trim(centre, float(xs[-1]) - w, left=False)
    if len(centre) < 2 or np.ptp(centre[:, 0]) <= 0:
        return None
    return Band(centre, float(w), caps)


#: a butt cap's edge is 2w long within this fraction
CAP_FRACTION = 0.1


def _butt_cap(pts: np.ndarray, extreme: int, w: float) -> tuple[np.ndarray, float] | None:
    """The butt cap at the outline's extreme vertex: (its middle, the x where it ends inward), or None
    (no edge of length 2w there: a round cap)."""
    n = len(pts)
    for other in ((extreme - 1) % n, (extreme + 1) % n):
        edge = pts[other] - pts[extreme]
        if abs(float(np.hypot(*edge)) - 2 * w) <= CAP_FRACTION * 2 * w:
            mid = (pts[extreme] + pts[other]) / 2.0
            inward = pts[other, 0] if pts[other, 0] != pts[extreme, 0] else mid[0]
            return mid, float(inward)
    return None


def _weighted_median(values: np.ndarray, weights: np.ndarray) -> float:
    order = np.argsort(values)
    cumulative = np.cumsum(weights[order])
    return float(values[order][np.searchsorted(cumulative, cumulative[-1] / 2.0)])


def _trim(centre: np.ndarray, x: float, left: bool) -> np.ndarray:
    """The centre line cut at x (the round cap's centre): the part right of x (``left``) or left of it."""
    xs = centre[:, 0]
    if left:
        k = int(np.searchsorted(xs, x, side="right"))
        if k == 0 or k >= len(xs):
            return centre
        y = np.interp(x, xs[k - 1:k + 1], centre[k - 1:k + 1, 1])
        return np.vstack(([x, y], centre[k:]))
    k = int(np.searchsorted(xs, x, side="left"))
    if k == 0 or k >= len(xs):
        return centre
    y = np.interp(x, xs[k - 1:k + 1], centre[k - 1:k + 1, 1])
    return np.vstack((centre[:k], [x, y]))


__all__ = ["Band", "band_centre_line"]
