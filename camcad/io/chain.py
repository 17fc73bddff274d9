"""Which drawn pieces form the law: pieces joined end to end, and the law's chain chosen among them.

The rules (docs/reading.md):

- **Joining.** Every curve piece of the drawing (LINE, ARC, ELLIPSE arc, LWPOLYLINE, POLYLINE,
  SPLINE) has two ends; ends closer than the join tolerance (default 1e-6 × the drawing's size,
  robust to a few stray entities) are one node, whatever the pieces' types, directions, order in
  the file or layers. Pieces of no length are dropped; pieces drawn twice over (the same ends and
  shape) count once. Nodes are found in O(n log n) (a k-d tree, and a greedy pass over the few
  ends that have a neighbour within the tolerance), so thousands of coincident pieces cost nothing.
- **Missed snaps.** Loose ends (reached by one piece end) of two pieces closer than ``SNAP_FRACTION``
  (1e-4) × the drawing's size, each the other's nearest loose end, are joined; a note names them when
  the law runs through them. A wider gap stays open (warned of, or the refusal says where).
- **The law is a function of x.** A law's chain runs left to right: each piece runs in x one way
  (a vertical piece is a jump). Among all such chains the law is the one spanning the largest
  x-range; of chains spanning the same range, the one whose y varies most (an axis does not vary,
  a zigzag through ordinate lines varies less than the curve), then the one with fewer pieces.
  Found by dynamic programming over the nodes sorted in x (a longest path in an acyclic graph),
  O(n log n).
- **Axes, grid and frame lines are left out.** A chain that is straight, or horizontal throughout
  (apart from vertical ends), is not a law; it and every straight piece at least as wide are left
  out and the choice is made again. A vertical line at an end of the chain that reaches beyond the
  rest of the curve's height is an axis, not a jump, and is left out too.
- **Layers.** The chain is looked for on each layer alone and on all layers together; a chain
  across layers is used only when it is wider than every single-layer chain (a FreeCAD export puts
  each object on a layer of its own). Two different chains of the same width are ambiguous.
- **Not a function of x.** When an open chain that goes back in x is wider than the law found,
  the drawing is refused with the place where it goes back.
- **What the drawing implies** (:func:`implied_pieces`). A closed outline that is a band of even width
  (an outlined stroke: OpenSCAD, Illustrator's Outline Stroke, Inkscape's Stroke to Path) stands for its
  centre line (:func:`band_centre_line`); two loose ends at one x and different heights, one ending a
  piece and one starting another, with no other loose end there, imply the vertical jump between
  plateaus drawn without risers. The law is chosen again with them and that law is taken when it is wider,
  or when the law as drawn runs along an outline's side (the law offset by the stroke's half-width).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, NoReturn

import numpy as np

from camcad.errors import CamcadError
from camcad.io.dxf_read import Curve, Piece, PieceSet, handles_text

#: default end-to-end join tolerance, as a fraction of the drawing's size
JOIN_FRACTION = 1e-6
#: loose ends of two pieces closer than this fraction of the drawing's size are a missed snap: joined, noted
SNAP_FRACTION = 1e-4
#: x steps below this fraction of the drawing's size count as vertical (and as not going back)
X_FRACTION = 1e-9
#: two chains whose x-ranges agree within this fraction are ambiguous
AMBIGUITY_FRACTION = 1e-6
#: rounds of leaving out straight lines before giving up
MAX_ROUNDS = 200
#: ... and at most this many pieces searched over all rounds together (each round searches every piece left:
#: 10,000 overlapping LINEs, each its own straight chain, took 200 rounds and 9.6 s of CPU; now 20 rounds)
MAX_ROUND_PIECES = 200_000
#: a piece that would extend the law's chain but ends this fraction of its width (or less) short of it
#: is a gap the author did not mean: warned of
NEAR_GAP_FRACTION = 0.02
GAP_WARNING = "warning: the law's chain ends at"
#: a wider chain going back in x by at most this fraction of its width is a law drawn a little wrong
MISDRAWN_BACK_FRACTION = 0.25


@dataclass(frozen=True)
class Graph:
    """The pieces of a drawing as edges between nodes (joined ends).

    Node ids index ``node_xy``; ``ends[i] = (node at the start of piece i, node at its end)``.
    For a usable piece, ``left[i]``/``right[i]`` are its left and right nodes (lower and upper for
    a vertical one) and ``forward[i]`` says the piece's own direction runs left to right (upwards).
    """

    pieces: tuple[Piece, ...]
    ends: np.ndarray
    node_xy: np.ndarray
    column: np.ndarray
    column_x: np.ndarray
    usable: np.ndarray
    vertical: np.ndarray
    left: np.ndarray
    right: np.ndarray
    forward: np.ndarray
    variation: np.ndarray
    straight: np.ndarray
    problems: tuple[str, ...]
    zero_length: np.ndarray
    duplicate_key: tuple
    widths: np.ndarray
    join_tol: float
    x_tol: float
    size: float
    snaps: tuple = ()
    snap_tol: float = 0.0


@dataclass(frozen=True)
class Path:
    """A chain: piece indices in order, each with the direction it is run in (True: its own)."""

    steps: tuple[tuple[int, bool], ...]
    span: float
    variation: float

    @property
    def pieces(self) -> tuple[int, ...]:
        return tuple(i for i, _ in self.steps)


@dataclass(frozen=True)
class LawChain:
    """The chosen law: its curve, what was noted, and the straight lines left out (axis candidates)."""

    curve: Curve
    notes: tuple[str, ...]
    left_out: tuple[int, ...]
    graph: Graph
    candidates: int
    used: tuple[int, ...] = ()
    #: how to close the nearest gap a piece stops short of the chain by ("" if none): the likelier cause
    #: when the law read is refused
    gap_fix: str = ""
    #: the chain's x-range, drawing units
    span: float = 0.0


# ---------------------------------------------------------------------------------------------
# The graph
# ---------------------------------------------------------------------------------------------

def drawing_size(points: np.ndarray) -> float:
    """Size of a drawing from its pieces' ends: the diagonal of the box holding 99 % of them in
    each direction (a few stray entities far away do not widen the tolerances).

    Examples
    --------
    >>> drawing_size(np.array([[0.0, 0.0], [3.0, 4.0]]))
    5.0
    """
    if len(points) == 0:
        return 0.0
    if len(points) < 200:
        low, high = points.min(axis=0), points.max(axis=0)
    else:
        low, high = np.percentile(points, 0.5, axis=0), np.percentile(points, 99.5, axis=0)
    return float(np.hypot(*(high - low)))


def cluster_points(points: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Group points closer than ``tol`` into nodes: (node id of each point, node coordinates).

    Exact duplicates are merged by sorting; among the rest, only points with a neighbour within
    ``tol`` are grouped, greedily in x order (each joins the first group whose first point is
    within ``tol``), so n coincident points cost O(n log n), not O(n²).

    Parameters
    ----------
    points : ndarray, shape (n, 2)
    tol : float
        Join distance, drawing units.

    Returns
    -------
    tuple of ndarray
        Node id per point (n,), node coordinates (m, 2) (the group's first point).

    Examples
    --------
    >>> ids, xy = cluster_points(np.array([[0, 0], [1, 0], [0, 1e-9], [0, 0]], dtype=float), 1e-6)
    >>> ids.tolist(), xy.tolist()
    ([0, 1, 0, 0], [[0.0, 0.0], [1.0, 0.0]])
    """
    if len(points) == 0:
        return np.zeros(0, dtype=int), np.zeros((0, 2))
    unique, inverse = np.unique(points, axis=0, return_inverse=True)
    inverse = np.asarray(inverse).reshape(-1)
    label = np.arange(len(unique))
    if len(unique) > 1 and tol > 0:
        first, second, _ = near_pairs(unique, tol)
        close = np.unique(first)
        if len(close):
            order = np.argsort(first, kind="stable")
            first, second = first[order], second[order]
            starts = np.searchsorted(first, close)
            stops = np.searchsorted(first, close, side="right")
            assigned = np.zeros(len(unique), dtype=bool)
            for i, lo, hi in zip(close.tolist(), starts.tolist(), stops.tolist()):  # in x, then y order
                if assigned[i]:
                    continue
                near = [j for j in [i, *second[lo:hi].tolist()] if not assigned[j]]
                label[near] = i
                assigned[near] = True
    roots, compact = np.unique(label, return_inverse=True)
    return np.asarray(compact).reshape(-1)[inverse], unique[roots]


def build_graph(pieces: tuple[Piece, ...], join_tol: float | None = None, snap: bool = True) -> Graph:
    """Join the pieces' ends into nodes and classify each piece (see the module docstring).

    Parameters
    ----------
    pieces : tuple of Piece
    join_tol : float, optional
        End-to-end join distance (drawing units); default 1e-6 × the drawing's size.
    snap : bool
        Join loose ends of different pieces closer than ``SNAP_FRACTION`` × the drawing's size (a
        missed snap; :func:`snap_dangling_ends`).

    Returns
    -------
    Graph
    """
    count = len(pieces)
    starts = np.array([p.points[0] for p in pieces], dtype=float).reshape(-1, 2)
    finals = np.array([p.points[-1] for p in pieces], dtype=float).reshape(-1, 2)
    all_ends = np.vstack((starts, finals))
    size = drawing_size(all_ends)
    if join_tol is None:
        join_tol = max(JOIN_FRACTION * size, 1e-12)
    x_tol = max(X_FRACTION * size, 1e-300)
    node_of, node_xy = cluster_points(all_ends, join_tol)
    snap_tol = SNAP_FRACTION * size
    snaps: tuple[Snap, ...] = ()
    if snap and snap_tol > join_tol:
        node_of, snaps = snap_dangling_ends(node_of, node_xy, count, snap_tol)
    ends = np.column_stack((node_of[:count], node_of[count:]))
    # columns: nodes grouped by x
    order = np.argsort(node_xy[:, 0], kind="stable")
    xs = node_xy[order, 0]
    new_column = np.concatenate(([True], np.diff(xs) > x_tol)) if len(xs) else np.zeros(0, dtype=bool)
    column_sorted = np.cumsum(new_column) - 1
    column = np.empty(len(node_xy), dtype=int)
    column[order] = column_sorted
    column_x = np.bincount(column_sorted, weights=xs) / np.bincount(column_sorted) if len(xs) else np.zeros(0)
    usable = np.zeros(count, dtype=bool)
    vertical = np.zeros(count, dtype=bool)
    left = np.zeros(count, dtype=int)
    right = np.zeros(count, dtype=int)
    forward = np.ones(count, dtype=bool)
    variation = np.zeros(count)
    straight = np.zeros(count, dtype=bool)
    zero_length = np.zeros(count, dtype=bool)
    problems: list[str] = [""] * count
    keys: list = [None] * count
    # two-point pieces (LINEs, mostly), all at once
    two = np.array([len(p.points) == 2 and not p.closed for p in pieces], dtype=bool)
    if two.any():
        idx = np.flatnonzero(two)
        a, b = ends[idx, 0], ends[idx, 1]
        variation[idx] = np.abs(finals[idx, 1] - starts[idx, 1])
        straight[idx] = True
        same = a == b
        zero_length[idx[same]] = True
        for i in idx[same]:
            problems[i] = "it has no length"
        vert = ~same & (column[a] == column[b])
        up = node_xy[b, 1] >= node_xy[a, 1]
        rightward = node_xy[b, 0] > node_xy[a, 0]
        own = np.where(vert, up, rightward)
        ok = ~same
        usable[idx[ok]] = True
        vertical[idx[vert]] = True
        forward[idx] = own
        left[idx] = np.where(own, a, b)
        right[idx] = np.where(own, b, a)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        quantum = max(8 * join_tol, 1e-300)
        flip = a > b
        first = np.where(flip[:, None], finals[idx], starts[idx])
        last = np.where(flip[:, None], starts[idx], finals[idx])
        coords = np.round(np.hstack((first, last)) / quantum) + 0.0
        for k, i in enumerate(idx):
            keys[i] = (int(lo[k]), int(hi[k]), 2, hash(coords[k].tobytes()))
    for i in np.flatnonzero(~two):
        piece = pieces[i]
        a, b = int(ends[i, 0]), int(ends[i, 1])
        pts = piece.points
        variation[i] = float(np.abs(np.diff(pts[:, 1])).sum())
        straight[i] = is_straight(pts)
        problem = ""
        if a == b and _extent(pts) <= join_tol:
            zero_length[i] = True
            problem = "it has no length"
        elif piece.closed or a == b:
            problem = "it is closed"
        elif column[a] == column[b]:
            if np.ptp(pts[:, 0]) > 2 * x_tol + abs(node_xy[a, 0] - node_xy[b, 0]):
                problem = "it is not a function of x (it bulges sideways and comes back)"
            else:
                up = node_xy[b, 1] >= node_xy[a, 1]
                steps = np.diff(pts[:, 1]) * (1 if up else -1)
                if np.any(steps < -join_tol):
                    problem = "it runs up and down at one x"
                else:
                    vertical[i] = True
                    left[i], right[i] = (a, b) if up else (b, a)
                    forward[i] = bool(up)
        else:
            direction = 1.0 if node_xy[b, 0] > node_xy[a, 0] else -1.0
            steps = np.diff(pts[:, 0]) * direction
            back = np.flatnonzero(steps < -x_tol)
            if len(back):
                k = int(back[0]) + 1
                problem = (f"it goes back in x at vertex {k} (x {pts[k, 0]:.6g} after {pts[k - 1, 0]:.6g}"
                           + (", drawn right to left)" if direction < 0 else ")"))
            else:
                left[i], right[i] = (a, b) if direction > 0 else (b, a)
                forward[i] = direction > 0
        usable[i] = not problem
        problems[i] = problem
        keys[i] = _duplicate_key(pts, a, b, join_tol)
    widths = np.array([abs(p.points[-1, 0] - p.points[0, 0]) if len(p.points) == 2 else float(np.ptp(p.points[:, 0]))
                       for p in pieces])
    return Graph(tuple(pieces), ends, node_xy, column, column_x, usable, vertical, left, right, forward,
                 variation, straight, tuple(problems), zero_length, tuple(keys), widths, float(join_tol),
                 float(x_tol), size, snaps, float(max(snap_tol, join_tol)))


@dataclass(frozen=True)
class Snap:
    """Two piece ends a missed snap left apart, joined: the node they became, the pieces, the gap."""

    node: int
    pieces: tuple[int, int]
    gap: float


def snap_dangling_ends(node_of: np.ndarray, node_xy: np.ndarray, count: int,
                       snap_tol: float) -> tuple[np.ndarray, tuple[Snap, ...]]:
    """Join the loose ends of different pieces that are each other's nearest loose end within ``snap_tol``.

    A loose end is a node that only one piece end reaches. Two loose ends of different pieces closer
    than ``snap_tol`` (a small fraction of the drawing's size: a missed snap), and each the other's
    nearest loose end, become one node (the first one's).

    Parameters
    ----------
    node_of : ndarray of int, shape (2 count,)
        Node of every piece end: starts first, then ends.
    node_xy : ndarray, shape (m, 2)
        Node coordinates.
    count : int
        Number of pieces.
    snap_tol : float
        Largest gap joined, drawing units.

    Returns
    -------
    (ndarray, tuple of Snap)
        The new node of every piece end, and the joins made.

    Examples
    --------
    Two LINEs 0..1 and 1.001..2 on the x axis, ends 0.001 apart:

    >>> node_of = np.array([0, 2, 1, 3])          # starts (0, 2), ends (1, 3)
    >>> node_xy = np.array([[0, 0], [1, 0], [1.001, 0], [2, 0]], dtype=float)
    >>> new, snaps = snap_dangling_ends(node_of, node_xy, 2, 0.01)
    >>> new.tolist(), [(s.node, s.pieces) for s in snaps]
    ([0, 1, 1, 3], [(1, (0, 1))])
    """
    degree = np.bincount(node_of, minlength=len(node_xy))
    piece_of_end = np.concatenate((np.arange(count), np.arange(count)))
    same = node_of[:count] == node_of[count:]
    loose = np.flatnonzero(degree == 1)
    loose = loose[~np.isin(loose, node_of[:count][same])]
    if len(loose) < 2:
        return node_of, ()
    owner = np.empty(len(node_xy), dtype=int)
    owner[node_of] = piece_of_end
    # each loose end's nearest other loose end within snap_tol (no partner: −1); only a pair of mutual nearest
    # ends within snap_tol is joined, so the nearest beyond snap_tol never matters
    first, second, gap = near_pairs(node_xy[loose], snap_tol)
    partner = np.full(len(loose), -1)
    distance = np.full(len(loose), np.inf)
    order = np.lexsort((second, gap, first))          # by end, then by distance (then index, for ties)
    head = np.flatnonzero(np.concatenate(([True], first[order][1:] != first[order][:-1]))) if len(order) else order
    partner[first[order][head]] = second[order][head]
    distance[first[order][head]] = gap[order][head]
    index = np.arange(len(loose))
    mutual = np.flatnonzero((partner >= 0) & (partner[np.maximum(partner, 0)] == index) & (index < partner))
    new = node_of.copy()
    snaps = []
    for k in mutual:
        a, b = int(loose[k]), int(loose[partner[k]])
        if owner[a] == owner[b]:
            continue   # the two ends of one piece: a nearly closed piece is not closed by a snap
        new[new == b] = a
        snaps.append(Snap(a, (int(owner[a]), int(owner[b])), float(distance[k])))
    return new, tuple(snaps)


def near_pairs(points: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every ordered pair (i, j), i ≠ j, of ``points`` (n, 2) at most ``radius`` apart, and their distance.

    The points are binned in square cells of side ``radius`` (or larger, at most 2²⁰ cells a side) and
    sorted by cell; a pair within ``radius``
    lies in the same or a neighbouring cell, so each point is compared with the points of 9 cells only
    (O(n log n) for points that are not crowded into a few cells; numpy only, no k-d tree).

    Examples
    --------
    >>> i, j, d = near_pairs(np.array([[0.0, 0.0], [0.5, 0.0], [3.0, 0.0]]), 1.0)
    >>> sorted(zip(i.tolist(), j.tolist())), d.tolist()
    ([(0, 1), (1, 0)], [0.5, 0.5])
    """
    points = np.asarray(points, dtype=float)
    n = len(points)
    empty = np.zeros(0, dtype=int)
    if n < 2 or not radius > 0:
        return empty, empty, np.zeros(0)
    low = points.min(axis=0)
    extent = float(np.max(points.max(axis=0) - low))
    size = max(radius, extent / 2**20)            # cells no smaller than the radius, at most 2²⁰ a side
    cells = np.floor((points - low) / size)
    cx, cy = cells[:, 0].astype(np.int64), cells[:, 1].astype(np.int64)
    width = int(cy.max()) + 3
    key = (cx + 1) * width + (cy + 1)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    found_i, found_j = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            target = (cx + 1 + dx) * width + (cy + 1 + dy)
            lo = np.searchsorted(sorted_key, target, side="left")
            count = np.searchsorted(sorted_key, target, side="right") - lo
            total = int(count.sum())
            if total == 0:
                continue
            rows = np.repeat(np.arange(n), count)
            offset = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
            cols = order[np.repeat(lo, count) + offset]
            other = rows != cols
            found_i.append(rows[other])
            found_j.append(cols[other])
    if not found_i:
        return empty, empty, np.zeros(0)
    i, j = np.concatenate(found_i), np.concatenate(found_j)
    gap = np.hypot(points[i, 0] - points[j, 0], points[i, 1] - points[j, 1])
    keep = gap <= radius
    return i[keep], j[keep], gap[keep]


def _extent(points: np.ndarray) -> float:
    return float(np.hypot(*np.ptp(points, axis=0))) if len(points) else 0.0


def _duplicate_key(points: np.ndarray, a: int, b: int, tol: float) -> tuple:
    """Pieces with equal keys are the same curve drawn twice: the same ends and the same points
    (each rounded to 8 × the join tolerance), whatever their direction."""
    pts = points if a <= b else points[::-1]
    quantum = max(8 * tol, 1e-300)
    if len(pts) > 4096:  # a long polyline: its shape is known well enough from 4096 of its points
        pts = pts[np.linspace(0, len(pts) - 1, 4096).astype(int)]
    rounded = np.round(pts / quantum) + 0.0  # -0.0 and 0.0 alike
    return (min(a, b), max(a, b), len(points), hash(rounded.tobytes()))


def is_straight(points: np.ndarray) -> bool:
    """All points on the chord from the first to the last (within 1e-9 of its length).

    Examples
    --------
    >>> is_straight(np.array([[0, 0], [1, 1], [2, 2.0]]))
    True
    >>> is_straight(np.array([[0, 0], [1, 1], [2, 0.0]]))
    False
    """
    if len(points) < 3:
        return True
    d = points - points[0]
    chord = points[-1] - points[0]
    norm = float(np.hypot(*chord))
    if norm == 0:
        return False
    deviation = np.abs(d[:, 0] * chord[1] - d[:, 1] * chord[0]) / norm
    return bool(deviation.max() <= 1e-9 * max(norm, float(np.ptp(points[:, 1]))))


def _representatives(graph: Graph, mask: np.ndarray) -> np.ndarray:
    """``mask`` with every piece drawn twice over kept once (the first allowed copy)."""
    keep = mask.copy()
    seen: set = set()
    for i in np.flatnonzero(mask):
        key = graph.duplicate_key[i]
        if key in seen:
            keep[i] = False
        else:
            seen.add(key)
    return keep


# ---------------------------------------------------------------------------------------------
# The longest chain that is a function of x
# ---------------------------------------------------------------------------------------------

def _dp(graph: Graph, edges: np.ndarray, reverse: bool = False):
    """Best chain ending at each node (starting there, when ``reverse``), by dynamic programming.

    A state's key is (−start column, variation, −pieces) in forward order (start column mirrored
    when ``reverse``): the widest start, then the most variation, then the fewest pieces.
    Returns (final, inn, states): final[node] = (key, pointer); inn[node] the state reached by a
    non-vertical piece (or a fresh start); states holds the "up"/"down" states for the pointers.
    """
    sign = -1 if reverse else 1
    incoming: dict[int, list[int]] = {}
    vertical_in_column: dict[int, list[int]] = {}
    nodes_in_column: dict[int, set[int]] = {}
    for e in edges:
        a, b = int(graph.left[e]), int(graph.right[e])
        if graph.vertical[e]:
            vertical_in_column.setdefault(int(graph.column[a]), []).append(int(e))
        else:
            incoming.setdefault(a if reverse else b, []).append(int(e))
        for node in (a, b):
            nodes_in_column.setdefault(int(graph.column[node]), set()).add(node)
    final: dict[int, tuple] = {}
    inn: dict[int, tuple] = {}
    up_state: dict[int, tuple] = {}
    down_state: dict[int, tuple] = {}
    variation = graph.variation
    for col in sorted(nodes_in_column, reverse=reverse):
        nodes = nodes_in_column[col]
        for n in nodes:
            best: tuple[tuple[float, float, int], tuple[str, int, int] | None] = ((-sign * col, 0.0, 0), None)
            for e in incoming.get(n, ()):
                m = int(graph.right[e]) if reverse else int(graph.left[e])
                key = final[m][0]
                candidate = (key[0], key[1] + variation[e], key[2] - 1)
                if candidate > best[0]:
                    best = (candidate, ("final", e, m))
            inn[n] = best
        verticals = vertical_in_column.get(col)
        if not verticals:
            for n in nodes:
                final[n] = inn[n]
            continue
        below: dict[int, list[int]] = {}
        above: dict[int, list[int]] = {}
        for e in verticals:
            below.setdefault(int(graph.right[e]), []).append(e)   # e reaches its upper node from below
            above.setdefault(int(graph.left[e]), []).append(e)    # e reaches its lower node from above
        by_y = sorted(nodes, key=lambda node: graph.node_xy[node, 1])
        for n in by_y:
            best = inn[n]
            for e in below.get(n, ()):
                m = int(graph.left[e])
                key = up_state[m][0]
                candidate = (key[0], key[1] + variation[e], key[2] - 1)
                if candidate > best[0]:
                    best = (candidate, ("up", e, m))
            up_state[n] = best
        for n in reversed(by_y):
            best = inn[n]
            for e in above.get(n, ()):
                m = int(graph.right[e])
                key = down_state[m][0]
                candidate = (key[0], key[1] + variation[e], key[2] - 1)
                if candidate > best[0]:
                    best = (candidate, ("down", e, m))
            down_state[n] = best
        for n in nodes:
            final[n] = max(inn[n], up_state[n], down_state[n], key=lambda s: s[0])
    return final, inn, {"final": final, "up": up_state, "down": down_state}


def _unwind(state: tuple, states: dict, graph: Graph, reverse: bool) -> list[tuple[int, bool]]:
    """The chain of a DP state, in x order (right to left when ``reverse``), as (piece, own direction)."""
    steps: list[tuple[int, bool]] = []
    pointer = state[1]
    guard = 0
    while pointer is not None:
        kind, e, m = pointer
        if kind == "final":
            run_forward = not reverse  # the piece is run from its left node to its right node
        else:
            run_forward = kind == "up"   # a vertical piece run upwards goes from left (lower) to right
        own = bool(graph.forward[e]) == run_forward
        steps.append((int(e), own))
        pointer = states[kind][m][1]
        guard += 1
        if guard > len(graph.pieces) + 1:
            raise RuntimeError("chain reconstruction did not terminate")
    steps.reverse()
    return steps


def _key_span(graph: Graph, node: int, key: tuple, reverse: bool) -> float:
    start_col = -key[0] if not reverse else key[0]
    return abs(float(graph.column_x[graph.column[node]] - graph.column_x[start_col]))


def best_path(graph: Graph, mask: np.ndarray, through: int | None = None) -> Path | None:
    """The widest chain that is a function of x among the pieces in ``mask`` (optionally through
    piece ``through``); None when there is none.

    Parameters
    ----------
    graph : Graph
    mask : ndarray of bool
        The pieces that may be used.
    through : int, optional
        A piece the chain must contain.

    Returns
    -------
    Path or None
    """
    if through is not None and not (graph.usable[through] and mask[through]):
        return None
    chosen = _representatives(graph, mask & graph.usable)
    if through is not None and not chosen[through]:
        twins = [i for i in np.flatnonzero(chosen) if graph.duplicate_key[i] == graph.duplicate_key[through]]
        chosen[twins] = False
        chosen[through] = True
    edges = np.flatnonzero(chosen)
    if len(edges) == 0:
        return None
    final, inn, states = _dp(graph, edges)
    best: tuple[Any, ...] | None = None
    if through is None:
        for node, state in final.items():
            if state[1] is None:
                continue
            key = (_key_span(graph, node, state[0], False), state[0][1], state[0][2])
            if best is None or key > best[0]:
                best = (key, state)
        if best is None:
            return None
        steps = _unwind(best[1], states, graph, False)
        return Path(tuple(steps), best[0][0], best[0][1])
    back_final, back_inn, back_states = _dp(graph, edges, reverse=True)
    e = through
    options = []
    if graph.vertical[e]:
        lower, upper = int(graph.left[e]), int(graph.right[e])
        options = [(inn[lower], back_inn[upper], True), (inn[upper], back_inn[lower], False)]
    else:
        options = [(final[int(graph.left[e])], back_final[int(graph.right[e])], True)]
    for before, after, run_forward in options:
        start_col, end_col = -before[0][0], after[0][0]
        span = abs(float(graph.column_x[end_col] - graph.column_x[start_col]))
        key = (span, before[0][1] + after[0][1] + graph.variation[e], before[0][2] + after[0][2] - 1)
        if best is None or key > best[0]:
            best = (key, before, after, run_forward)
    assert best is not None  # options is never empty
    key, before, after, run_forward = best
    head = _unwind(before, states, graph, False)
    tail = [(i, not own) for i, own in _unwind(after, back_states, graph, True)]  # run the other way
    own = bool(graph.forward[e]) == run_forward
    steps = head + [(e, own)] + list(reversed(tail))
    return Path(tuple(steps), key[0], key[1])


def path_points(graph: Graph, path: Path) -> np.ndarray:
    """The chain's points in chain order (shared ends once)."""
    parts = []
    for k, (i, own) in enumerate(path.steps):
        pts = graph.pieces[i].points if own else graph.pieces[i].points[::-1]
        parts.append(pts if k == 0 else pts[1:])
    return np.concatenate(parts) if parts else np.zeros((0, 2))


def _core(graph: Graph, path: Path) -> Path:
    """The chain without vertical pieces at its ends."""
    steps = list(path.steps)
    while steps and graph.vertical[steps[0][0]]:
        steps.pop(0)
    while steps and graph.vertical[steps[-1][0]]:
        steps.pop()
    return Path(tuple(steps), path.span, path.variation)


def _not_a_law(graph: Graph, path: Path) -> bool:
    """The chain is straight, or flat, once the vertical stretches at its ends are taken off (an axis, a
    grid line, a frame or a U-shaped border)."""
    pts = path_points(graph, path)
    x = pts[:, 0]
    off_start = np.abs(x - x[0]) > graph.x_tol
    off_end = np.abs(x - x[-1]) > graph.x_tol
    if not off_start.any():
        return True
    first = int(np.argmax(off_start))                       # the first point off the starting vertical
    last = len(x) - 1 - int(np.argmax(off_end[::-1]))       # the last point off the ending vertical
    inner = pts[first - 1: last + 2]
    if len(inner) < 2 or np.ptp(inner[:, 0]) <= graph.x_tol:
        return True
    return bool(np.ptp(inner[:, 1]) == 0 or is_straight(inner))


def widest_law_path(graph: Graph, mask: np.ndarray, through: int | None = None) -> tuple[Path | None, set[int]]:
    """:func:`best_path`, leaving out straight chains (axes, grid and frame lines) until a law is found.

    Returns the chain (or None) and the pieces left out as straight lines.
    """
    excluded: set[int] = set()
    allowed = mask.copy()
    straight_pieces = np.flatnonzero(mask & graph.straight & graph.usable)
    widths = graph.widths[straight_pieces]
    rounds = max(20, min(MAX_ROUNDS, MAX_ROUND_PIECES // max(1, int(np.count_nonzero(allowed)))))
    for _ in range(rounds):
        path = best_path(graph, allowed, through)
        if path is None:
            return None, excluded
        if not _not_a_law(graph, path):
            return _trim_axis_ends(graph, path, excluded), excluded
        wide = straight_pieces[widths >= path.span - 2 * graph.x_tol]
        drop = set(_core(graph, path).pieces or path.pieces) | set(wide.tolist())
        excluded |= drop
        allowed[list(drop)] = False
        if through is not None and through in excluded:
            return None, excluded
    return None, excluded


def _trim_axis_ends(graph: Graph, path: Path, excluded: set[int]) -> Path:
    """Leave out a vertical line at an end of the chain that reaches beyond the rest's height (an axis)."""
    steps = list(path.steps)
    core = _core(graph, path)
    if not core.steps:
        return path
    pts = path_points(graph, core)
    low, high = float(pts[:, 1].min()), float(pts[:, 1].max())
    reach = graph.join_tol
    for end in (0, -1):
        while steps and graph.vertical[steps[end][0]]:
            piece = graph.pieces[steps[end][0]].points
            if piece[:, 1].max() > high + reach or piece[:, 1].min() < low - reach:
                excluded.add(steps[end][0])
                steps.pop(end)
            else:
                break
    return Path(tuple(steps), path.span, path.variation)


# ---------------------------------------------------------------------------------------------
# Chains that go back in x (for the explanation)
# ---------------------------------------------------------------------------------------------

def open_chains(graph: Graph, mask: np.ndarray) -> list[list[tuple[int, bool]]]:
    """Maximal chains through nodes where exactly two of the pieces in ``mask`` meet, ignoring x
    order (closed pieces and pieces of no length left out)."""
    edges = [int(i) for i in np.flatnonzero(_representatives(graph, mask))
             if not graph.zero_length[i] and graph.problems[i] != "it is closed"]
    incident: dict[int, list[tuple[int, int]]] = {}
    for e in edges:
        for side in (0, 1):
            incident.setdefault(int(graph.ends[e, side]), []).append((e, side))
    used: set[int] = set()
    chains = []

    def follow(e: int, side: int) -> list[tuple[int, bool]]:
        chain = []
        while e not in used:
            used.add(e)
            chain.append((e, side == 0))
            node = int(graph.ends[e, 1 - side])
            nxt = [(f, s) for f, s in incident[node] if f != e]
            if len(incident[node]) != 2 or not nxt:
                break
            e, side = nxt[0]
        return chain

    starts = [(e, side) for e in edges for side in (0, 1) if len(incident[int(graph.ends[e, side])]) != 2]
    for e, side in starts + [(e, 0) for e in edges]:
        if e not in used:
            chains.append(follow(e, side))
    return chains


def _chain_problem(graph: Graph, chain: list[tuple[int, bool]]) -> tuple[float, str, str]:
    """(x-range, where, problem) of an open chain: where it first goes back in x."""
    pts_list, owner = [], []
    for k, (i, own) in enumerate(chain):
        pts = graph.pieces[i].points if own else graph.pieces[i].points[::-1]
        pts_list.append(pts if k == 0 else pts[1:])
        owner.extend([i] * (len(pts) if k == 0 else len(pts) - 1))
    pts = np.concatenate(pts_list)
    if graph.ends[chain[0][0], 0 if chain[0][1] else 1] == graph.ends[chain[-1][0], 1 if chain[-1][1] else 0] \
            and len(chain) > 1:
        return float(np.ptp(pts[:, 0])), "", "it is closed"
    x = pts[:, 0]
    direction = 1.0 if x[-1] >= x[0] else -1.0
    back = np.flatnonzero(np.diff(x) * direction < -graph.x_tol)
    if not len(back):
        return float(np.ptp(x)), "", ""
    k = int(back[0]) + 1
    piece = graph.pieces[owner[k]]
    if len(chain) == 1:
        label = piece.label
        problem = graph.problems[owner[k]] or f"it goes back in x at vertex {k} (x {x[k]:.6g} after {x[k - 1]:.6g})"
    else:
        label = f"the chain of {len(chain)} pieces ({handles_text([graph.pieces[i].handle for i, _ in chain], 4)}) " \
                f"on layer {piece.layer}"
        problem = f"it goes back in x in {piece.kind} {piece.handle} (x {x[k]:.6g} after {x[k - 1]:.6g})"
    return float(np.ptp(x)), label, problem


# ---------------------------------------------------------------------------------------------
# Choosing the law
# ---------------------------------------------------------------------------------------------

def find_law(piece_set: PieceSet, where: str, layer: str | None = None, handle: str | None = None,
             join_tol: float | None = None) -> LawChain:
    """The chain of pieces that holds the law (see the module docstring for the rules).

    Parameters
    ----------
    piece_set : PieceSet
        The drawing's pieces (:func:`camcad.io.dxf_read.collect_pieces`).
    where : str
        The file, for messages.
    layer : str, optional
        Only pieces on this layer (case-insensitive).
    handle : str, optional
        The chain must contain the entity with this handle.
    join_tol : float, optional
        End-to-end join distance, drawing units (default 1e-6 × the drawing's size).

    Returns
    -------
    LawChain

    Raises
    ------
    CamcadError
        No curve, no law-like chain (with the reason for the widest candidate), a wider chain that
        goes back in x (with where), or two chains of the same width (pick one with --handle/--layer).
    """
    pieces = piece_set.pieces
    if not pieces:
        skipped = [n for n in piece_set.notes if " skipped: " in n]
        why = f" ({skipped[0]})" if skipped else ""
        raise CamcadError(f"no curve found{why}", where,
                          f"the drawing holds {_counts_text(piece_set)}; draw the law as a polyline, "
                          "a chain of lines or a spline")
    graph = build_graph(pieces, join_tol)
    try:
        found: LawChain | None = _choose(graph, where, layer, handle)
        error: CamcadError | None = None
    except CamcadError as err:
        found, error = None, err
    # what a designer means but the drawing does not say: an outlined stroke's centre line, the vertical
    # jumps between plateaus drawn without risers; used when they give a wider law than the drawing as drawn
    implied = implied_pieces(graph)
    if implied is not None:
        other_graph = build_graph(implied.pieces, graph.join_tol)
        try:
            other: LawChain | None = _choose(other_graph, where, layer, handle)
        except CamcadError as err:
            other = None
            if found is None and implied.jumps and error is not None and "no curve here can be a law" in error.what:
                error = err   # the plateaus joined say better what is wrong than "a straight line"
        # a chain along an outline's side is the law offset by the stroke's half-width: never the law
        on_outline = found is not None and bool(implied.outlines & set(found.used))
        if other is not None and (found is None or on_outline or other.span > found.span * (1 + AMBIGUITY_FRACTION)
                                  + 2 * graph.x_tol):
            _refuse_unjoined_end(other, implied, graph, where)
            used = set(other.used)
            notes = [note for index, note in implied.notes if index in used and not implied.pieces[index].virtual]
            jumps = [note for index, note in implied.notes if index in used and implied.pieces[index].virtual]
            if jumps:
                notes.append(f"plateaus drawn without risers joined by {len(jumps)} vertical jump"
                             f"{'s' if len(jumps) > 1 else ''} the drawing implies: " + "; ".join(jumps))
            return replace(other, notes=tuple(notes) + other.notes)
    if found is None:
        assert error is not None
        if implied is not None and implied.unjoined and "no curve here can be a law" in error.what:
            _x, text = implied.unjoined[0]
            raise CamcadError(f"plateaus drawn without risers cannot be joined: {text}", where,
                              "draw the vertical jump of the law there")
        raise error
    return found


def _refuse_unjoined_end(chain: LawChain, implied: Implied, graph: Graph, where: str) -> None:
    """A chain joined by implied jumps that stops where loose ends meet that no jump joins is only part of
    the plateaus drawn: refused, naming the place."""
    x_lo, x_hi = float(chain.curve.points[:, 0].min()), float(chain.curve.points[:, 0].max())
    for x, text in implied.unjoined:
        if min(abs(x - x_lo), abs(x - x_hi)) <= graph.snap_tol:
            raise CamcadError(f"plateaus drawn without risers cannot be joined: {text}; the law read would stop there",
                              where, "draw the vertical jump of the law there")


def _choose(graph: Graph, where: str, layer: str | None, handle: str | None) -> LawChain:
    """:func:`find_law` on a graph of the drawing's pieces (as drawn, or with the pieces it implies)."""
    pieces = graph.pieces
    layers_of = np.array([p.layer.upper() for p in pieces])
    hidden = np.array([p.hidden for p in pieces])
    notes: list[str] = []
    through_set: list[int] = []
    if handle is not None:
        wanted = handle.strip().upper()
        through_set = [i for i, p in enumerate(pieces)
                       if p.handle.upper() == wanted or any(h.upper() == wanted for h, _ in p.sources)]
        if not through_set:
            raise CamcadError(f"no curve with handle {handle[:20]}", where,
                              f"curve handles here: {_handles_list(pieces)}")
        base = ~hidden | np.isin(layers_of, [pieces[i].layer.upper() for i in through_set])
    elif layer is not None:
        base = layers_of == layer.strip().upper()
        if not base.any():
            names = sorted({p.layer for p in pieces})
            raise CamcadError(f"no curve on layer {layer[:40]}", where,
                              f"layers with curves: {', '.join(names[:12]) or 'none'}")
    else:
        base = ~hidden if (~hidden).any() else np.ones(len(pieces), dtype=bool)
    groups = sorted(set(layers_of[base].tolist()))
    results = []  # (path, excluded, group name)
    for name in groups:
        mask = base & (layers_of == name)
        results.extend(_group_paths(graph, mask, through_set, name))
    single = [r for r in results if r[0] is not None]
    best_single = max(single, key=lambda r: (r[0].span, r[0].variation)) if single else None
    chosen = best_single
    across = False
    if len(groups) > 1:
        combined = [r for r in _group_paths(graph, base, through_set, "*") if r[0] is not None]
        if combined:
            best_all = max(combined, key=lambda r: (r[0].span, r[0].variation))
            margin = max(2 * graph.x_tol, AMBIGUITY_FRACTION * (best_single[0].span if best_single else 0.0))
            if best_single is None or best_all[0].span > best_single[0].span + margin:
                chosen, across = best_all, True
    if chosen is None:
        _refuse_without_law(graph, base, where, through_set)
    path, excluded, _ = chosen
    _refuse_wider_backward_chain(graph, base, path, excluded, where)
    if not across and handle is None:
        _refuse_ambiguous(graph, base, path, excluded, single, chosen, where, layer)
    curve = make_curve(graph, path)
    left_out = sorted(excluded - set(path.pieces))
    others = len([r for r in single if r is not chosen])
    how = "chosen by --handle" if handle is not None else \
        ("the widest chain; joined across layers" if across else "the widest chain that is a function of x")
    if others and handle is None:
        how += f" (of {others + 1} candidates on {len({r[2] for r in single})} layers)"
    notes.append(f"law: {curve.label}, {how}")
    if len(path.steps) > 1:
        notes.append(f"{len(path.steps)} pieces joined end to end (tolerance {graph.join_tol:.3g} drawing units)")
    if not curve.editable and curve.flatten_tol > 0:
        notes.append(f"{curve.kind} flattened to {len(curve.points)} points "
                     f"(tolerance {curve.flatten_tol:.3g} drawing units)")
    dropped = _dropped_notes(graph, base)
    notes.extend(dropped)
    notes.extend(_snap_notes(graph, path))
    gaps = _near_gaps(graph, base, path, excluded)
    notes.extend(note for note, _ in gaps)
    return LawChain(curve, tuple(notes), tuple(left_out), graph, len(single) or 1, path.pieces,
                    gaps[0][1] if gaps else "", path.span)


def _snap_notes(graph: Graph, path: Path) -> list[str]:
    """A note naming every missed snap the law's chain was joined across."""
    used = set(path.pieces)
    notes = []
    for snap in graph.snaps:
        a, b = snap.pieces
        if a in used and b in used:
            x, y = (float(v) if abs(v) > 1e-9 * graph.size else 0.0 for v in graph.node_xy[snap.node])
            pa, pb = graph.pieces[a], graph.pieces[b]
            notes.append(f"{pa.kind} {pa.handle} and {pb.kind} {pb.handle} end {snap.gap:.3g} drawing units apart at "
                         f"x = {x:.6g}, y = {y:.6g}: joined as a missed snap (loose ends closer than "
                         f"{SNAP_FRACTION:g} of the drawing's size, {graph.snap_tol:.3g}, are joined)")
    return notes


def _group_paths(graph: Graph, mask: np.ndarray, through_set: list[int], name: str):
    if through_set:
        out = []
        for t in through_set:
            if mask[t]:
                path, excluded = widest_law_path(graph, mask, t)
                out.append((path, excluded, name))
        return out or [(None, set(), name)]
    path, excluded = widest_law_path(graph, mask)
    return [(path, excluded, name)]


def _refuse_without_law(graph: Graph, mask: np.ndarray, where: str, through_set: list[int]) -> NoReturn:
    candidates: list[Any] = [i for i in np.flatnonzero(mask)] if not through_set else through_set
    if not candidates:
        candidates = list(range(len(graph.pieces)))
    # the widest open piece or chain explains best why there is no law
    explained = []
    for chain in open_chains(graph, np.isin(np.arange(len(graph.pieces)), candidates)):
        width, label, problem = _chain_problem(graph, chain)
        if problem and not all(graph.straight[i] for i, _ in chain):
            explained.append((width, label, problem))
    for i in candidates:
        if graph.problems[i] and not graph.zero_length[i]:
            explained.append((float(graph.widths[i]), graph.pieces[i].label, graph.problems[i]))
    open_first = sorted(explained, key=lambda t: (t[2] != "it is closed", t[0]), reverse=True)
    if open_first:
        width, label, problem = open_first[0]
        scope = "the curve chosen by --handle" if through_set else "the largest"
        raise CamcadError(f"no curve here can be a law; {scope}, {label}: {problem}", where, _problem_fix(problem))
    widest = max(candidates, key=lambda i: (graph.pieces[i].kind != "LINE", graph.widths[i]))
    piece = graph.pieces[widest]
    distinct = len(np.unique(piece.points, axis=0))
    if piece.kind in ("LWPOLYLINE", "POLYLINE", "SPLINE") and distinct < 3:
        problem = f"it has {distinct} distinct vertices; a law needs at least 3" if distinct < len(piece.points) \
            else f"it has {distinct} vertices; a law needs at least 3"
    elif graph.straight[widest]:
        problem = "it is a straight line (an axis or a grid line, not a law)"
    else:
        problem = "it is flat or straight throughout (an axis, a grid or a frame line, not a law)"
    fix = _problem_fix(problem)
    flat = [i for i in candidates if graph.usable[i] and not graph.zero_length[i] and not graph.vertical[i]]
    horizontal = [i for i in flat if graph.straight[i] and np.ptp(graph.pieces[i].points[:, 1]) <= graph.join_tol]
    degree = np.bincount(graph.ends.ravel(), minlength=len(graph.node_xy))
    loose = [i for i in horizontal if degree[graph.ends[i, 0]] == 1 and degree[graph.ends[i, 1]] == 1]
    levels = {round(float(graph.pieces[i].points[0, 1]) / max(graph.join_tol, 1e-300)) for i in loose}
    # nothing but horizontal (and vertical) lines, some of them loose at both ends at several heights: plateaus
    if len(levels) >= 2 and len(horizontal) == len(flat):
        raise CamcadError(f"no curve here can be a law: only straight lines, horizontal ones at {len(levels)} heights "
                          f"(the largest {graph.pieces[widest].label})", where,
                          "if they are a law's plateaus, make each end at the x where the next starts, or draw the "
                          "jumps between them")
    raise CamcadError(f"no curve here can be a law; the largest, {graph.pieces[widest].label}: {problem}", where, fix)


def _refuse_wider_backward_chain(graph: Graph, mask: np.ndarray, path: Path, excluded: set[int], where: str) -> None:
    allowed = mask.copy()
    allowed[list(excluded)] = False
    wide_straight = graph.straight & (graph.widths >= path.span - 2 * graph.x_tol)
    allowed &= ~wide_straight | np.isin(np.arange(len(graph.pieces)), path.pieces)
    for chain in open_chains(graph, allowed):
        width, label, problem = _chain_problem(graph, chain)
        if problem and problem != "it is closed" and width > path.span * (1 + AMBIGUITY_FRACTION) + 2 * graph.x_tol:
            if all(graph.straight[i] for i, _ in chain) and len(chain) == 1:
                continue
            if _backward_travel(graph, chain) > MISDRAWN_BACK_FRACTION * width:
                continue  # a frame, a border or a sketch that turns round: not a law drawn a little wrong
            first = graph.pieces[path.steps[0][0]]
            raise CamcadError(f"the widest curve, {label}, cannot be a law: {problem}", where,
                              f"{_problem_fix(problem)}, or pick another curve with --handle {first.handle}")


def _backward_travel(graph: Graph, chain: list[tuple[int, bool]]) -> float:
    """How far an open chain runs against its overall direction in x, in all (drawing units)."""
    parts = [graph.pieces[i].points if own else graph.pieces[i].points[::-1] for i, own in chain]
    x = np.concatenate([p[:, 0] for p in parts])
    steps = np.diff(x) * (1.0 if x[-1] >= x[0] else -1.0)
    return float(-steps[steps < 0].sum())


def _refuse_ambiguous(graph, base, path, excluded, single, chosen, where, layer) -> None:
    rivals = []
    span = path.span

    def shape(p: Path) -> set:
        return {graph.duplicate_key[i] for i in p.pieces}

    for other in single:
        if other is chosen or other[0] is None:
            continue
        if abs(other[0].span - span) <= AMBIGUITY_FRACTION * span + 2 * graph.x_tol and \
                shape(other[0]) != shape(path):
            rivals.append(other[0])
    mask = base.copy()
    mask[list(set(path.pieces) | excluded)] = False
    used_shapes = shape(path)
    mask &= np.array([key not in used_shapes for key in graph.duplicate_key])   # copies of the law's pieces
    mask &= np.array([p.layer.upper() for p in graph.pieces]) == graph.pieces[path.steps[0][0]].layer.upper()
    if mask.any():
        second, _ = widest_law_path(graph, mask)
        if second is not None and abs(second.span - span) <= AMBIGUITY_FRACTION * span + 2 * graph.x_tol:
            rivals.append(second)
    if rivals:
        names = ", ".join(graph.pieces[p.steps[0][0]].handle for p in [path] + rivals)
        scope = f"layer {layer}" if layer else "the drawing"
        ranges = [(float(pts[:, 0].min()), float(pts[:, 0].max()))
                  for pts in (path_points(graph, p) for p in [path] + rivals)]
        overlap = min(hi for _, hi in ranges) - max(lo for lo, _ in ranges)
        if overlap > 2 * graph.x_tol:
            raise CamcadError(f"{scope} holds {len(rivals) + 1} curves spanning the same x-range (handles {names})",
                              where, "pick one with --handle" + ("" if layer else " or --layer"))
        # side by side, not one over the other: most likely one law drawn in parts that do not meet
        gaps = _near_gaps(graph, base, path, excluded)
        spans = ", ".join(f"{lo:.6g}..{hi:.6g}" for lo, hi in ranges)
        raise CamcadError(f"{scope} holds {len(rivals) + 1} curves of the same width side by side (x {spans}; "
                          f"handles {names}) that do not join", where,
                          gaps[0][1] if gaps else "join them into one curve, or pick one with --handle")


def _dropped_notes(graph: Graph, mask: np.ndarray) -> list[str]:
    notes = []
    zero = int((graph.zero_length & mask).sum())
    if zero:
        notes.append(f"{zero} piece{'s' if zero > 1 else ''} of no length ignored")
    kept = _representatives(graph, mask & ~graph.zero_length)
    twice = np.flatnonzero(mask & ~graph.zero_length & ~kept)
    if len(twice):
        notes.append(f"{len(twice)} piece{'s' if len(twice) > 1 else ''} drawn twice over counted once "
                     f"({handles_text([graph.pieces[i].handle for i in twice], 4)})")
    return notes


def _near_gaps(graph: Graph, mask: np.ndarray, path: Path, excluded: set[int]) -> list[tuple[str, str]]:
    """(warning, how to fix) for each end of the chain that a piece would carry further in x but stops short
    of by more than the join tolerance (and at most ``NEAR_GAP_FRACTION`` of the chain's width): most likely
    a gap the author did not mean, so the law read is only part of the drawn one."""
    pts = path_points(graph, path)
    if len(pts) < 2:
        return []
    left, right = (pts[0], pts[-1]) if pts[-1][0] >= pts[0][0] else (pts[-1], pts[0])
    limit = NEAR_GAP_FRACTION * max(path.span, graph.x_tol)
    used = set(path.pieces) | excluded
    candidates = np.array([i for i in np.flatnonzero(mask & graph.usable & ~graph.zero_length) if i not in used],
                          dtype=int)
    if len(candidates) == 0:
        return []
    ends = np.array([(graph.pieces[i].points[0], graph.pieces[i].points[-1]) for i in candidates])  # (n, 2, 2)
    notes = []
    for end, outward in ((left, -1.0), (right, 1.0)):
        gaps = np.hypot(ends[..., 0] - end[0], ends[..., 1] - end[1]).min(axis=1)
        close = np.flatnonzero((gaps > graph.join_tol) & (gaps <= limit))
        # only a piece that would carry the chain past this end (not a tick mark pointing inward)
        near = [k for k in close[np.argsort(gaps[close])]
                if (outward * (graph.pieces[candidates[k]].points[:, 0] - end[0]) > graph.x_tol).any()]
        if near:
            piece, gap = graph.pieces[candidates[near[0]]], float(gaps[near[0]])
            notes.append((f"{GAP_WARNING} x = {end[0]:.6g}, {gap:.3g} drawing units short of "
                          f"{piece.kind} {piece.handle} (join tolerance {graph.join_tol:.3g}); if that piece is part "
                          "of the law, close the gap in the drawing",
                          f"the chain read stops at x = {end[0]:.6g}, {gap:.3g} drawing units short of "
                          f"{piece.kind} {piece.handle}: close that gap in the drawing"))
    return notes


def _problem_fix(problem: str) -> str:
    if "goes back" in problem or "function of x" in problem or "up and down" in problem:
        return "move that vertex so x never decreases along the curve (a vertical segment is a jump)"
    if "vertices" in problem:
        return "draw the law with at least 3 vertices"
    if "closed" in problem:
        return "draw the law as an open curve from the start to the end of the cycle"
    return "pick the law with --handle or --layer"


def _handles_list(pieces) -> str:
    text = ", ".join(f"{p.handle} ({p.kind}, layer {p.layer})" for p in pieces[:8])
    return text + (" ..." if len(pieces) > 8 else "") if text else "none"


def _counts_text(piece_set: PieceSet) -> str:
    """What the drawing holds instead of curves, layout by layout (never "no entities" when it holds some)."""
    def listed(counts) -> str:
        return ", ".join(f"{n} {kind}" for kind, n in sorted(counts.items()))

    where = f"the layout {piece_set.layout!r}" if piece_set.layout else "the model space"
    others = set(piece_set.elsewhere) - {piece_set.layout or "Model"}
    parts = [listed(piece_set.entity_counts) + (f" in {where}" if others else "")] if piece_set.entity_counts else []
    for name, counts in piece_set.elsewhere.items():
        if name == (piece_set.layout or "Model"):
            continue
        parts.append(f"{listed(counts)} in {'the model space' if name == 'Model' else f'the layout {name!r}'}")
    return "; ".join(parts) if parts else "no entities in the model space or any layout"


# ---------------------------------------------------------------------------------------------
# What the drawing implies: an outlined stroke's centre line, jumps between plateaus without risers
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Implied:
    """The drawing's pieces with what it implies: every outlined stroke replaced by its centre line, and
    the vertical jumps between plateaus drawn without risers added (virtual pieces).

    ``notes`` holds (index into ``pieces``, note) for each centre line and each jump, said when the law
    uses that piece.
    """

    pieces: tuple[Piece, ...]
    notes: tuple[tuple[int, str], ...]
    jumps: int
    #: (x, description) of every x where loose ends arrive and leave but not one of each: no jump implied
    unjoined: tuple[tuple[float, str], ...] = ()
    #: indices (into the drawing's pieces) of the outlines read as centre lines
    outlines: frozenset = frozenset()


def implied_pieces(graph: Graph) -> Implied | None:
    """The drawing's pieces with the outlined strokes' centre lines and the implied jumps (see
    :class:`Implied`), or None when it implies neither.

    An outline is a closed piece, or a closed chain of pieces meeting two at a node, that
    :func:`band_centre_line` reads as a band. A jump joins two loose ends (reached
    by one piece each) at one x (within the snap distance) and different heights, one the right end
    of a piece and the other the left end of another, when no other loose end is at that x.
    """
    pieces = list(graph.pieces)
    keep = np.ones(len(pieces), dtype=bool)
    centres: list[tuple[Piece, str]] = []
    outlined: set[int] = set()
    for ring in _rings(graph):
        members = [pieces[i] for i, _ in ring]
        points = path_points(graph, Path(tuple(ring), 0.0, 0.0))
        if len(points) > 3 and np.hypot(*(points[-1] - points[0])) <= graph.snap_tol:
            points = points[:-1]   # the ring's closing point: its first, or a missed snap away from it
        band = band_centre_line(points, graph.x_tol)
        if band is None:
            continue
        keep[[i for i, _ in ring]] = False
        outlined.update(i for i, _ in ring)
        first = members[0]
        kind = first.kind if len({p.kind for p in members}) == 1 else "chain"
        name = f"{kind} {first.handle}" if len(members) == 1 else \
            f"{kind} {handles_text([p.handle for p in members], 4)}"
        centre = Piece(band.centre, f"centre line of {kind}", first.handle, first.layer, first.index, exact=False,
                       flatten_tol=max(p.flatten_tol for p in members), hidden=all(p.hidden for p in members),
                       breakpoints=band.centre, sources=tuple(e for p in members for e in p.entities))
        caps = band.caps[0] if band.caps[0] == band.caps[1] else "/".join(band.caps)
        centres.append((centre, f"{name} is the outline of a stroke of half-width {band.half_width:.4g} drawing "
                                f"units ({caps} caps), not a curve: read as its centre line (exact on straight "
                                "stretches, within w²·curvature on curves)"))
    jumps, unjoined = _implied_jumps(graph)
    if not centres and not jumps:
        return None
    out = [p for p, k in zip(pieces, keep) if k]
    notes: list[tuple[int, str]] = []
    for centre, note in centres:
        notes.append((len(out), note))
        out.append(centre)
    for jump, note in jumps:
        notes.append((len(out), note))
        out.append(jump)
    return Implied(tuple(out), tuple(notes), len(jumps), tuple(unjoined), frozenset(outlined))


def _rings(graph: Graph) -> list[list[tuple[int, bool]]]:
    """Closed pieces, and closed chains of pieces meeting two at a node, each as (piece, own direction)."""
    rings: list[list[tuple[int, bool]]] = []
    for i, piece in enumerate(graph.pieces):
        if not graph.zero_length[i] and graph.problems[i] == "it is closed" and len(piece.points) >= 3:
            rings.append([(i, True)])
    mask = ~graph.zero_length & np.array([not p.virtual for p in graph.pieces], dtype=bool)
    for chain in open_chains(graph, mask):
        if len(chain) < 2:
            continue
        first, last = chain[0], chain[-1]
        start = graph.ends[first[0], 0 if first[1] else 1]
        end = graph.ends[last[0], 1 if last[1] else 0]
        if start == end:
            rings.append(chain)
    return rings


def _implied_jumps(graph: Graph) -> tuple[list[tuple[Piece, str]], list[tuple[float, str]]]:
    """The vertical jumps between loose ends at one x (see :func:`implied_pieces`), and the x where
    loose ends arrive and leave but not one of each (no jump can be told)."""
    count = len(graph.pieces)
    live = np.flatnonzero(graph.usable & ~graph.zero_length & ~np.array([p.hidden for p in graph.pieces], bool))
    if len(live) < 2:
        return [], []
    live = live[_representatives(graph, np.isin(np.arange(count), live))[live]]
    nodes = np.concatenate((graph.ends[live, 0], graph.ends[live, 1]))
    owners = np.concatenate((live, live))
    degree = np.bincount(nodes, minlength=len(graph.node_xy))
    loose = [(int(n), int(p)) for n, p in zip(nodes, owners) if degree[n] == 1]
    sides = []
    for node, owner in loose:
        x = graph.node_xy[node, 0]
        others = graph.pieces[owner].points[:, 0]
        if np.all(others <= x + graph.x_tol) and np.any(others < x - graph.x_tol):
            sides.append((x, node, owner, "arrives"))
        elif np.all(others >= x - graph.x_tol) and np.any(others > x + graph.x_tol):
            sides.append((x, node, owner, "leaves"))
        else:
            sides.append((x, node, owner, ""))
    sides.sort()
    groups: list[list] = []
    for item in sides:
        if groups and item[0] - groups[-1][-1][0] <= graph.snap_tol:
            groups[-1].append(item)
        else:
            groups.append([item])
    jumps = []
    unjoined = []
    for group in groups:
        kinds = [g[3] for g in group]
        if "arrives" in kinds and "leaves" in kinds and len(group) > 2:
            ends = ", ".join(f"{graph.pieces[g[2]].kind} {graph.pieces[g[2]].handle} {g[3]} at y = "
                             f"{graph.node_xy[g[1], 1]:.6g}" for g in group[:5])
            unjoined.append((float(group[0][0]), f"{len(group)} loose ends meet at x = {group[0][0]:.6g} ({ends})"))
        if len(group) != 2 or set(kinds) != {"arrives", "leaves"}:
            continue
        arrive = next(g for g in group if g[3] == "arrives")
        leave = next(g for g in group if g[3] == "leaves")
        a, b = graph.node_xy[arrive[1]], graph.node_xy[leave[1]]
        if abs(b[1] - a[1]) <= graph.join_tol:
            continue
        p, q = graph.pieces[arrive[2]], graph.pieces[leave[2]]
        points = np.array([a, b], dtype=float)
        jump = Piece(points, "jump", "", p.layer, -1, exact=False, breakpoints=points, virtual=True)
        jumps.append((jump, f"{p.kind} {p.handle} ends at y = {a[1]:.6g} and {q.kind} {q.handle} starts at y = "
                            f"{b[1]:.6g} at x = {a[0]:.6g} with nothing between"))
    return jumps, unjoined


# ---------------------------------------------------------------------------------------------
# Outlined strokes: a closed outline of a band around the law, read as its centre line
# ---------------------------------------------------------------------------------------------
# A law drawn as an outlined stroke: the closed outline of a band of half-width w around the law, read
# as its centre line.
#
# OpenSCAD cannot draw a line, only areas: a law modelled there (``offset``, or the hull of circles along
# it) is exported as the closed outline of a band around the law, one closed LWPOLYLINE (or one LINE per
# edge in older releases). Illustrator's "Outline Stroke" and Inkscape's "Stroke to Path" do the same to a
# drawn stroke. Either side of the band is the law offset by w, so neither is the law; the centre line is.
#
# The rule (docs/reading.md):
#
# - **A band.** Cut the outline by vertical lines through all its vertices: between two consecutive ones,
#   every vertical line must cross the outline exactly twice (an upper and a lower side, each straight
#   there). The centre line is the mid-point of the two crossings: exact on every straight stretch of the
#   law, whatever its slope (both offsets of a line of slope m lie w·√(1+m²) above and below it), and off
#   by O(w²·curvature) on curves. At a vertical jump it is a step of half the jump over 2w, which keeps
#   the area of the jump.
# - **Thin and even.** The band's half-width measured square to the centre line must be the same (within
#   20 %) over at least 70 % of the x-range, nowhere less than half of it (but within 2w of the ends), and
#   small: at most ``MAX_WIDTH_FRACTION`` of its length in x. A law and its axis meeting at both ends close
#   a region that is no band (it is thin where the law dwells on the axis).
#   A closed cam profile, a frame or a filled shape is not a band; a thin rectangle is the band of a
#   straight line (OpenSCAD draws an axis so).
# - **Ends.** A butt cap is one edge of length 2w at the outline's extreme, square to the law: the law
#   ends at its middle (a square cap looks the same and is read so: the law then reads w longer at that
#   end). Otherwise the cap is round, a half circle round the law's end: the law ends w inside it.

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
    pairs = owner[sort].reshape(-1, 2)
    left_x, right_x = xs[:-1], xs[1:]

    def y_at(e: np.ndarray, x: np.ndarray) -> np.ndarray:
        p, q = start[e], end[e]
        t = (x - p[:, 0]) / (q[:, 0] - p[:, 0])
        return p[:, 1] + t * (q[:, 1] - p[:, 1])

    ya = np.column_stack((y_at(pairs[:, 0], left_x), y_at(pairs[:, 1], left_x)))
    yb = np.column_stack((y_at(pairs[:, 0], right_x), y_at(pairs[:, 1], right_x)))
    mid_a, mid_b = ya.mean(axis=1), yb.mean(axis=1)
    thick_a, thick_b = np.abs(ya[:, 0] - ya[:, 1]), np.abs(yb[:, 0] - yb[:, 1])
    width = right_x - left_x
    slope = (mid_b - mid_a) / width
    # the half-width square to the centre line, at the middle of each slab
    half = (thick_a + thick_b) / 4.0 / np.hypot(1.0, slope)
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


# ---------------------------------------------------------------------------------------------
# The curve handed over
# ---------------------------------------------------------------------------------------------

def make_curve(graph: Graph, path: Path) -> Curve:
    """The :class:`~camcad.io.dxf_read.Curve` of a chain (the contract is in Curve's docstring)."""
    steps = list(path.steps)
    pieces = [graph.pieces[i] for i, _ in steps]
    entities = [entity for p in pieces for entity in p.entities]
    handles = tuple(handle for handle, _ in entities)
    indices = tuple(index for _, index in entities)
    layers = tuple(dict.fromkeys(p.layer for p in pieces))
    hidden = any(p.hidden for p in pieces)
    tol = max((p.flatten_tol for p in pieces), default=0.0)
    if len(pieces) == 1:
        piece = pieces[0]
        editable = piece.exact and piece.kind in ("LWPOLYLINE", "POLYLINE") and not piece.sources
        return Curve(piece.points, piece.kind, piece.handle, piece.layer, editable=editable, closed=False,
                     flatten_tol=0.0 if piece.exact else tol, handles=handles, hidden=hidden, pieces=(piece,),
                     reversed_pieces=(False,), entity_indices=indices, breakpoints=piece.breakpoints, layers=layers)
    points = path_points(graph, path)
    kinds = {p.kind for p in pieces}
    exact = all(p.exact for p in pieces)
    if kinds == {"LINE"}:
        kind = "LINE chain"
    elif kinds <= {"LINE", "ARC"}:
        kind = "LINE/ARC chain"
    else:
        kind = "chain"
    refs: list[list[tuple[str, str | int]]] = []
    if exact:
        for k, ((_i, own), piece) in enumerate(zip(steps, pieces)):
            n = len(piece.points)
            order = range(n) if own else range(n - 1, -1, -1)
            names = ["start", "end"] if piece.kind == "LINE" else list(range(n))
            own_refs = [(piece.handle, names[v] if piece.kind != "LINE" else names[0 if v == 0 else 1]) for v in order]
            if k == 0:
                refs.extend([[r] for r in own_refs])
            else:
                refs[-1].append(own_refs[0])
                refs.extend([[r] for r in own_refs[1:]])
    breakpoints = []
    for k, (i, own) in enumerate(steps):
        bp = graph.pieces[i].breakpoints
        if bp is None or len(bp) == 0:
            bp = graph.pieces[i].points[[0, -1]]
        bp = bp if own else bp[::-1]
        breakpoints.append(bp if k == 0 else bp[1:])
    return Curve(points, kind, handles[0] if handles else pieces[0].handle, pieces[0].layer,
                 editable=exact and kind == "LINE chain", closed=False,
                 flatten_tol=0.0 if exact else tol, handles=handles,
                 vertex_refs=tuple(tuple(r) for r in refs), hidden=hidden, pieces=tuple(pieces),
                 reversed_pieces=tuple(not own for _, own in steps), entity_indices=indices,
                 breakpoints=np.concatenate(breakpoints), layers=layers)


__all__ = [
    "Band",
    "Graph",
    "Implied",
    "LawChain",
    "Path",
    "Snap",
    "band_centre_line",
    "best_path",
    "build_graph",
    "cluster_points",
    "drawing_size",
    "find_law",
    "implied_pieces",
    "is_straight",
    "make_curve",
    "open_chains",
    "path_points",
    "snap_dangling_ends",
    "widest_law_path",
]
