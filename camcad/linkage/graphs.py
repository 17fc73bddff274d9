"""Kinematic chains as graphs: links are vertices, revolute pairs are edges (Sunkuev 1984, ch. 1).

A planar chain of n links (the frame counted) joined by p revolute pairs has the mobility
(Chebyshev–Grübler)

    W = 3 (n − 1) − 2 p,   so   p = (3 (n − 1) − W) / 2.

Sunkuev 1984 (Sunkuev 1984, p. 9 of the abstract) prints p = (3n − W)/2: that holds when its n counts the
*moving* links only (n_moving = n − 1). Table 1 of Sunkuev 1984 counts all links (its four-link chain is
the four-bar), so camcad's n is the total number of links and the formula above is the one used.

An *ordinary* chain here is a graph that is

1. simple (two links share at most one pair),
2. connected,
3. of minimum degree 2 (every link is in at least two pairs),
4. free of rigid sub-chains: every set S of ≥ 2 links with e(S) pairs among them has
   3 (|S| − 1) − 2 e(S) ≥ 1 (a triangle, or anything stiffer, is excluded),

with mobility W. Fractionated chains (a cut vertex) are kept. An *adjustable* chain is an ordinary
chain with some pairs locked ("жёсткая регулируемая связь", Sunkuev 1984, p. 8); see ``camcad.linkage.atlas``.

Non-isomorphism is decided by ``canonical_form``: colour refinement followed by an exhaustive
individualisation search that keeps the lexicographically smallest relabelled adjacency matrix
(edge colours included). It is exact (a canonical form, not a hash) and needs no third-party code.
"""

from __future__ import annotations

from dataclasses import dataclass

from camcad.errors import CamcadError

#: edge colours in the canonical form
ORDINARY = 1
LOCKED = 2


def pairs_for(links: int, dof: int, where: str = "--links/--dof") -> int:
    """Number of revolute pairs p of a planar chain with ``links`` links and mobility ``dof``.

    p = (3 (n − 1) − W) / 2  (Chebyshev–Grübler, n counting the frame; Sunkuev 1984 p. 9 prints
    p = (3n − W)/2 with n the moving links only).

    Parameters
    ----------
    links : int
        Number of links n, the frame included.
    dof : int
        Mobility W (degrees of freedom) of the chain.
    where : str
        Where the numbers came from, for the error message.

    Returns
    -------
    int
        Number of pairs p.

    Raises
    ------
    CamcadError
        When 3 (n − 1) − W is odd or the chain cannot exist (n < 4 or W < 1 or p < n).

    Examples
    --------
    >>> pairs_for(4, 1), pairs_for(6, 1), pairs_for(10, 1), pairs_for(9, 2)
    (4, 7, 13, 11)
    """
    if links < 2 or dof < 1:
        raise CamcadError(f"a chain needs at least 2 links and 1 degree of freedom, got n={links}, W={dof}",
                          where, "give --links 4 or more and --dof 1 or more")
    twice = 3 * (links - 1) - dof
    if twice % 2:
        raise CamcadError(f"no planar chain with revolute pairs has n={links} links and W={dof}: "
                          f"3(n-1)-W = {twice} is odd, so the pair count (3(n-1)-W)/2 is not whole",
                          where,
                          f"n + W must be odd: try --links {links + 1} or --links {links - 1}, or --dof {dof + 1}")
    pairs = twice // 2
    if pairs < links:
        raise CamcadError(f"n={links} links with W={dof} would have p={pairs} pairs, fewer than the {links} "
                          "a closed chain with every link in two pairs needs", where,
                          f"use W <= {links - 3} for n={links} (W = n-3 is the single loop)")
    return pairs


def mobility(links: int, pairs: int) -> int:
    """Mobility W = 3 (n − 1) − 2 p of a planar chain with revolute pairs.

    Examples
    --------
    >>> mobility(4, 4), mobility(6, 7), mobility(5, 5)
    (1, 1, 2)
    """
    return 3 * (links - 1) - 2 * pairs


def _bitmasks(n: int, edges) -> list[int]:
    adj = [0] * n
    for u, v in edges:
        adj[u] |= 1 << v
        adj[v] |= 1 << u
    return adj


_MASKS: dict[int, tuple] = {}


def _all_masks(n: int):
    import numpy as np

    if n not in _MASKS:
        masks = np.arange(1 << n, dtype=np.int64)
        sizes = np.zeros(masks.size, dtype=np.int16)
        for bit in range(n):
            sizes += ((masks >> bit) & 1).astype(np.int16)
        _MASKS[n] = (masks, sizes)
    return _MASKS[n][0]


def _popcounts(n: int):
    _all_masks(n)
    return _MASKS[n][1]


def is_connected(n: int, edges) -> bool:
    """True when the graph on vertices 0..n−1 with ``edges`` is connected.

    Examples
    --------
    >>> is_connected(4, [(0, 1), (1, 2), (2, 3), (3, 0)]), is_connected(4, [(0, 1), (2, 3)])
    (True, False)
    """
    if n == 0:
        return True
    adj = _bitmasks(n, edges)
    seen, frontier = 1, 1
    while frontier:
        grow = 0
        rest = frontier
        while rest:
            low = rest & -rest
            grow |= adj[low.bit_length() - 1]
            rest ^= low
        frontier = grow & ~seen
        seen |= grow
    return seen == (1 << n) - 1


def rigid_subchain(n: int, edges) -> tuple[int, ...] | None:
    """The smallest set of links that forms a rigid (or overconstrained) sub-chain, or None.

    A set S of |S| ≥ 2 links with e(S) pairs among them is rigid when 3 (|S| − 1) − 2 e(S) ≤ 0
    (its own mobility is not positive). All 2^n subsets are checked exactly (n ≤ 16).

    Examples
    --------
    >>> rigid_subchain(5, [(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (4, 0)])  # a triangle 0-1-2
    (0, 1, 2)
    >>> rigid_subchain(4, [(0, 1), (1, 2), (2, 3), (3, 0)]) is None
    True
    """
    if n > 16:
        raise CamcadError(f"rigid sub-chain check supports up to 16 links, got {n}", "camcad.linkage.graphs",
                          "use fewer links")
    import numpy as np

    masks = _all_masks(n)
    internal = np.zeros(masks.size, dtype=np.int16)
    for u, v in edges:
        internal += ((masks >> u) & (masks >> v) & 1).astype(np.int16)
    sizes = _popcounts(n)
    rigid = (sizes >= 2) & (3 * (sizes - 1) - 2 * internal <= 0)
    if not rigid.any():
        return None
    candidates = np.flatnonzero(rigid)
    best = int(candidates[np.argmin(sizes[candidates])])
    return tuple(i for i in range(n) if best >> i & 1)


def chain_problems(n: int, edges, dof: int | None = None) -> list[str]:
    """Why the graph is not an ordinary kinematic chain (empty list: it is one).

    Checks the four rules of the module docstring and, when ``dof`` is given, the mobility.

    Examples
    --------
    >>> chain_problems(4, [(0, 1), (1, 2), (2, 3), (3, 0)], dof=1)
    []
    >>> chain_problems(4, [(0, 1), (1, 2), (2, 0), (2, 3)])[0]
    'link 3 is in 1 pair(s), fewer than 2'
    """
    problems = []
    seen = set()
    for u, v in edges:
        if u == v:
            problems.append(f"pair ({u},{v}) joins a link to itself")
        key = (min(u, v), max(u, v))
        if key in seen:
            problems.append(f"links {u} and {v} share two pairs")
        seen.add(key)
    degree = [0] * n
    for u, v in edges:
        degree[u] += 1
        degree[v] += 1
    for v, d in enumerate(degree):
        if d < 2:
            problems.append(f"link {v} is in {d} pair(s), fewer than 2")
    if not is_connected(n, edges):
        problems.append("the chain is not connected")
    if dof is not None and mobility(n, len(edges)) != dof:
        problems.append(f"mobility 3(n-1)-2p = {mobility(n, len(edges))}, not {dof}")
    if not problems:
        rigid = rigid_subchain(n, edges)
        if rigid is not None:
            problems.append(f"links {', '.join(map(str, rigid))} form a rigid sub-chain")
    return problems


def _refine(cells: list[list[int]], n: int, nbrs: list[list[tuple[int, int]]]) -> list[list[int]]:
    """Colour refinement of an ordered partition: split every cell by the multiset of
    (neighbour's cell, edge colour); sub-cells are ordered by that signature (isomorphism-invariant)."""
    while True:
        cell_of = [0] * n
        for index, cell in enumerate(cells):
            for v in cell:
                cell_of[v] = index
        out: list[list[int]] = []
        changed = False
        for cell in cells:
            if len(cell) == 1:
                out.append(cell)
                continue
            signature = {v: tuple(sorted((cell_of[u], colour) for u, colour in nbrs[v])) for v in cell}
            keys = sorted(set(signature.values()))
            if len(keys) == 1:
                out.append(cell)
                continue
            changed = True
            for key in keys:
                out.append([v for v in cell if signature[v] == key])
        cells = out
        if not changed:
            return cells


def canonical_form(n: int, edges, colours=None, vertex_colours=None) -> tuple[tuple, tuple[int, ...]]:
    """A canonical form of an edge-coloured (and optionally vertex-coloured) simple graph.

    Two graphs are isomorphic (by a map that keeps edge and vertex colours) exactly when their
    certificates are equal. Method: colour refinement, then individualisation of each vertex of the
    first non-singleton cell in turn, recursively; every leaf (a discrete partition) gives an order
    of the vertices, and the certificate is the smallest relabelled upper-triangular adjacency
    (colours as entries) over all leaves. The search is exhaustive, hence exact; its cost grows with
    the automorphism group, which is small for kinematic chains.

    Parameters
    ----------
    n : int
        Number of vertices.
    edges : sequence of (int, int)
        The edges.
    colours : sequence of int, optional
        Colour of each edge (default 1 = ordinary pair; ``LOCKED`` = 2 for a locked pair).
    vertex_colours : sequence of int, optional
        A colour per vertex (default all equal).

    Returns
    -------
    (certificate, order)
        ``certificate`` is a hashable tuple; ``order[k]`` is the vertex put in position k.

    Examples
    --------
    >>> a = canonical_form(4, [(0, 1), (1, 2), (2, 3), (3, 0)])[0]
    >>> b = canonical_form(4, [(0, 2), (2, 1), (1, 3), (3, 0)])[0]
    >>> a == b
    True
    """
    edges = list(edges)
    colours = [ORDINARY] * len(edges) if colours is None else list(colours)
    nbrs: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    matrix = [[0] * n for _ in range(n)]
    for (u, v), colour in zip(edges, colours):
        nbrs[u].append((v, colour))
        nbrs[v].append((u, colour))
        matrix[u][v] = matrix[v][u] = colour
    if vertex_colours is None:
        cells = [list(range(n))]
    else:
        keys = sorted(set(vertex_colours))
        cells = [[v for v in range(n) if vertex_colours[v] == key] for key in keys]
    head = tuple(tuple(sorted(vertex_colours)) if vertex_colours is not None else ())
    best: list = [None, None]

    def leaf(order: list[int]) -> None:
        cert = tuple(matrix[order[i]][order[j]] for i in range(n) for j in range(i + 1, n))
        if best[0] is None or cert < best[0]:
            best[0], best[1] = cert, tuple(order)

    def search(partition: list[list[int]]) -> None:
        partition = _refine(partition, n, nbrs)
        for index, cell in enumerate(partition):  # noqa: B007 - index and cell are used after the break
            if len(cell) > 1:
                break
        else:
            leaf([cell[0] for cell in partition])
            return
        for v in cell:
            rest = [u for u in cell if u != v]
            search(partition[:index] + [[v], rest] + partition[index + 1:])

    search(cells)
    return (n, head, best[0]), best[1]


@dataclass(frozen=True)
class Chain:
    """A kinematic chain: ``n`` links 0..n−1, ``edges`` (pairs, u < v, sorted) and the ``locked`` ones.

    The vertex numbering is canonical when the chain comes from ``camcad.linkage.atlas``.
    """

    n: int
    edges: tuple[tuple[int, int], ...]
    locked: tuple[tuple[int, int], ...] = ()

    @property
    def pairs(self) -> int:
        return len(self.edges)

    @property
    def dof(self) -> int:
        """Mobility of the chain with every pair free: 3 (n − 1) − 2 p."""
        return mobility(self.n, len(self.edges))

    def degrees(self) -> list[int]:
        degree = [0] * self.n
        for u, v in self.edges:
            degree[u] += 1
            degree[v] += 1
        return degree

    def assortment(self) -> dict[int, int]:
        """Link assortment {order i: number of links n_i} (order = pairs the link is in)."""
        out: dict[int, int] = {}
        for d in self.degrees():
            out[d] = out.get(d, 0) + 1
        return dict(sorted(out.items()))

    def certificate(self) -> tuple:
        colours = [LOCKED if e in set(self.locked) else ORDINARY for e in self.edges]
        return canonical_form(self.n, self.edges, colours)[0]

    def adjustable_links(self) -> list[tuple[int, ...]]:
        """The adjustable links: the vertex sets of the connected components of the locked pairs."""
        parent = list(range(self.n))

        def find(x: int) -> int:
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        for u, v in self.locked:
            parent[find(u)] = find(v)
        touched = sorted({x for e in self.locked for x in e})
        groups: dict[int, list[int]] = {}
        for v in touched:
            groups.setdefault(find(v), []).append(v)
        return sorted(tuple(g) for g in groups.values())

    def to_json(self) -> dict:
        out = {"links": self.n, "pairs": [list(e) for e in self.edges],
               "assortment": {str(k): v for k, v in self.assortment().items()}}
        if self.locked:
            out["locked_pairs"] = [list(e) for e in self.locked]
            out["adjustable_links"] = [list(g) for g in self.adjustable_links()]
        return out


def relabel(chain: Chain, order: tuple[int, ...]) -> Chain:
    """``chain`` with vertex ``order[k]`` renamed k; edges re-sorted.

    Examples
    --------
    >>> relabel(Chain(3, ((0, 1), (1, 2))), (2, 1, 0)).edges
    ((0, 1), (1, 2))
    """
    position = {v: k for k, v in enumerate(order)}

    def edge(e):
        a, b = position[e[0]], position[e[1]]
        return (a, b) if a < b else (b, a)

    return Chain(chain.n, tuple(sorted(edge(e) for e in chain.edges)), tuple(sorted(edge(e) for e in chain.locked)))


def canonical_chain(chain: Chain) -> tuple[tuple, Chain]:
    """(certificate, the chain relabelled in canonical order): isomorphic chains come out identical.

    Examples
    --------
    >>> a = canonical_chain(Chain(4, ((0, 1), (0, 3), (1, 2), (2, 3)), locked=((0, 1),)))[1]
    >>> b = canonical_chain(Chain(4, ((0, 2), (0, 3), (1, 2), (1, 3)), locked=((1, 3),)))[1]
    >>> a == b
    True
    """
    locked = set(chain.locked)
    colours = [LOCKED if e in locked else ORDINARY for e in chain.edges]
    cert, order = canonical_form(chain.n, chain.edges, colours)
    return cert, relabel(chain, order)
