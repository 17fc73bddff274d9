"""Positions for drawing a chain's graph (the atlas diagrams): few crossings, vertices apart.

Candidates: for each of the longest simple cycles (up to ``MAX_OUTER``) the cycle is put on a circle
and the other vertices at the barycentre of their neighbours (Tutte's embedding, planar for a
3-connected planar graph with a face as the outer cycle); each candidate is also relaxed by stress
majorisation (SMACOF on the graph distances), which separates the blocks of fractionated chains.
The candidate without near-coincident vertices (separation ≥ 0.2 of the drawing's half-width) or
nearly overlapping edges (angle ≥ 20° at every vertex), and with
the fewest edge crossings, then the widest vertex separation, wins. Deterministic.
"""

from __future__ import annotations

import math

import numpy as np

MAX_OUTER = 12


def simple_cycles(n: int, edges) -> list[tuple[int, ...]]:
    """All simple cycles (length ≥ 3) of a small graph, each once, smallest vertex first.

    Examples
    --------
    >>> simple_cycles(4, [(0, 1), (1, 2), (2, 3), (3, 0)])
    [(0, 1, 2, 3)]
    """
    adj: list[list[int]] = [[] for _ in range(n)]
    for u, v in edges:
        adj[u].append(v)
        adj[v].append(u)
    found = set()
    out = []

    def dfs(start, v, path, seen):
        for w in adj[v]:
            if w == start and len(path) >= 3:
                cyc = tuple(path)
                key = min(cyc[1], cyc[-1])
                canon = cyc if cyc[1] == key else (cyc[0],) + tuple(reversed(cyc[1:]))
                if canon not in found:
                    found.add(canon)
                    out.append(canon)
            elif w > start and w not in seen:
                seen.add(w)
                path.append(w)
                dfs(start, w, path, seen)
                path.pop()
                seen.discard(w)

    for s in range(n):
        dfs(s, s, [s], {s})
    return out


def crossings(pos: np.ndarray, edges) -> int:
    """Number of crossing pairs of edges (edges sharing a vertex never count).

    Examples
    --------
    >>> crossings(np.array([[0, 0], [1, 1], [0, 1], [1, 0]], dtype=float), [(0, 1), (2, 3)])
    1
    """
    e = np.asarray(list(edges), dtype=int)
    if len(e) < 2:
        return 0
    i, j = np.triu_indices(len(e), 1)
    a, b, c, d = e[i, 0], e[i, 1], e[j, 0], e[j, 1]
    disjoint = (a != c) & (a != d) & (b != c) & (b != d)
    p1, p2, p3, p4 = pos[a], pos[b], pos[c], pos[d]

    def orient(u, v, w):
        return (v[:, 0] - u[:, 0]) * (w[:, 1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (w[:, 0] - u[:, 0])

    cross = (orient(p3, p4, p1) * orient(p3, p4, p2) < -1e-12) & (orient(p1, p2, p3) * orient(p1, p2, p4) < -1e-12)
    return int(np.sum(cross & disjoint))


def _separation(pos: np.ndarray, edges) -> float:
    """Smallest vertex-vertex and vertex-to-other-edge distance."""
    n = len(pos)
    diff = pos[:, None, :] - pos[None, :, :]
    d = np.hypot(diff[..., 0], diff[..., 1]) + np.eye(n) * 1e9
    best = float(d.min())
    e = np.asarray(list(edges), dtype=int)
    a, b = pos[e[:, 0]], pos[e[:, 1]]                      # (E, 2)
    ab = b - a
    length2 = np.maximum((ab * ab).sum(axis=1), 1e-18)
    t = np.clip(((pos[None, :, :] - a[:, None, :]) * ab[:, None, :]).sum(axis=2) / length2[:, None], 0.0, 1.0)
    foot = a[:, None, :] + t[..., None] * ab[:, None, :]
    dist = np.hypot(*(pos[None, :, :] - foot).transpose(2, 0, 1))
    own = (np.arange(n)[None, :] == e[:, [0]]) | (np.arange(n)[None, :] == e[:, [1]])
    dist = np.where(own, np.inf, dist)
    return min(best, float(dist.min()))


def _smallest_angle(pos: np.ndarray, edges) -> float:
    """Smallest angle (rad) between two edges at a common vertex."""
    best = math.pi
    spokes: dict[int, list[float]] = {}
    for u, v in edges:
        for a, b in ((u, v), (v, u)):
            d = pos[b] - pos[a]
            spokes.setdefault(a, []).append(math.atan2(d[1], d[0]))
    for angles in spokes.values():
        angles.sort()
        for x, y in zip(angles, angles[1:] + [angles[0] + 2 * math.pi]):
            best = min(best, y - x)
    return best


def _tutte(n: int, edges, outer: tuple[int, ...]) -> np.ndarray:
    pos = np.zeros((n, 2))
    k = len(outer)
    for i, v in enumerate(outer):
        angle = math.pi / 2 + 2 * math.pi * i / k
        pos[v] = (math.cos(angle), math.sin(angle))
    inner = [v for v in range(n) if v not in outer]
    if inner:
        index = {v: i for i, v in enumerate(inner)}
        lap = np.zeros((len(inner), len(inner)))
        rhs = np.zeros((len(inner), 2))
        for u, v in edges:
            for x, y in ((u, v), (v, u)):
                if x in index:
                    lap[index[x], index[x]] += 1
                    if y in index:
                        lap[index[x], index[y]] -= 1
                    else:
                        rhs[index[x]] += pos[y]
        try:
            sol = np.linalg.solve(lap, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(lap, rhs, rcond=None)[0]
        for v, i in index.items():
            pos[v] = sol[i]
    return pos


def _distances(n: int, edges) -> np.ndarray:
    dist = np.full((n, n), np.inf)
    np.fill_diagonal(dist, 0)
    for u, v in edges:
        dist[u, v] = dist[v, u] = 1
    for k in range(n):
        dist = np.minimum(dist, dist[:, [k]] + dist[[k], :])
    return dist


def _smacof(pos: np.ndarray, dist: np.ndarray, iterations: int = 80) -> np.ndarray:
    x = pos.copy()
    weight = np.where(dist > 0, 1.0 / np.maximum(dist, 1e-9) ** 2, 0.0)
    vmat = -weight
    np.fill_diagonal(vmat, weight.sum(axis=1))
    vinv = np.linalg.pinv(vmat)
    for _ in range(iterations):
        diff = x[:, None, :] - x[None, :, :]
        d = np.hypot(diff[..., 0], diff[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(d > 1e-12, weight * dist / d, 0.0)
        bmat = -ratio
        np.fill_diagonal(bmat, 0.0)
        np.fill_diagonal(bmat, -bmat.sum(axis=1))
        x = vinv @ (bmat @ x)
    return x


def _relax_inner(pos: np.ndarray, dist: np.ndarray, pinned: set[int], iterations: int = 120) -> np.ndarray:
    """Localised stress majorisation of the vertices not in ``pinned`` (the outer cycle stays put), all
    free vertices at once: x_i ← Σ_j w_ij (x_j + d_ij (x_i − x_j)/|x_i − x_j|) / Σ_j w_ij, w_ij = d_ij⁻²,
    with graph distances d in units of an outer edge; coincident start points are split by a small
    deterministic nudge."""
    n = len(pos)
    free = np.array([i for i in range(n) if i not in pinned], dtype=int)
    if free.size == 0:
        return pos
    index = np.arange(n)
    x = pos + (0.05 * np.column_stack([np.cos(2.4 * index), np.sin(2.4 * index)])
               * (~np.isin(index, list(pinned)))[:, None])
    scale = 2 * math.sin(math.pi / max(len(pinned), 3))
    target = dist * scale
    weight = np.where(dist > 0, 1.0 / np.maximum(target, 1e-9) ** 2, 0.0)
    w = weight[free]                                       # (F, n)
    tf = target[free]
    for _ in range(iterations):
        diff = x[free][:, None, :] - x[None, :, :]         # (F, n, 2)
        d = np.hypot(diff[..., 0], diff[..., 1])
        unit = diff / np.maximum(d, 1e-9)[..., None]
        x[free] = (w[..., None] * (x[None, :, :] + tf[..., None] * unit)).sum(axis=1) / w.sum(axis=1)[:, None]
    return x


def _normalise(pos: np.ndarray) -> np.ndarray:
    pos = pos - pos.mean(axis=0)
    scale = np.max(np.abs(pos))
    return pos / scale if scale > 0 else pos


def layout(n: int, edges) -> np.ndarray:
    """(n, 2) positions in [−1, 1]² for the graph (module docstring).

    Examples
    --------
    >>> pos = layout(4, [(0, 1), (1, 2), (2, 3), (3, 0)])
    >>> crossings(pos, [(0, 1), (1, 2), (2, 3), (3, 0)])
    0
    """
    edges = [tuple(e) for e in edges]
    cycles = sorted(simple_cycles(n, edges), key=lambda c: (-len(c), c))[:MAX_OUTER]
    dist = _distances(n, edges)

    def score(pos):
        gap = _separation(pos, edges)
        return (gap < 0.2 or _smallest_angle(pos, edges) < math.radians(20), crossings(pos, edges), -round(gap, 3))

    outers = cycles or [tuple(range(n))]
    tutte = [_normalise(_tutte(n, edges, outer)) for outer in outers]
    scored = sorted(((score(p), k, p) for k, p in enumerate(tutte)), key=lambda item: (item[0], item[1]))
    best_key, _, best = scored[0]
    if not np.all(np.isfinite(dist)):
        return best
    # relax the inner vertices of the best few, the outer cycle fixed (spreads twins and near-collinear paths)
    for _key, k, _pos in scored[:6]:
        relaxed = _normalise(_relax_inner(_tutte(n, edges, outers[k]), dist, set(outers[k])))
        relaxed_key = score(relaxed)
        if relaxed_key < best_key:
            best, best_key = relaxed, relaxed_key
    if not best_key[0] and best_key[1] == 0:
        return best
    # relax the best few by stress majorisation (separates the blocks of fractionated chains)
    for _key, _k, pos in scored[:4]:
        k_index = np.arange(n)
        nudge = 0.05 * np.column_stack([np.cos(2.4 * k_index), np.sin(2.4 * k_index)])  # split coincident points
        relaxed = _normalise(_smacof(pos + nudge, dist))
        relaxed_key = score(relaxed)
        if relaxed_key < best_key:
            best, best_key = relaxed, relaxed_key
    return best
