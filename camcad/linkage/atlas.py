"""Enumeration of ordinary and adjustable planar kinematic chains (Sunkuev 1984, ch. 1, Table 1).

Ordinary chains (rules in ``camcad.linkage.graphs``) are generated the way Sunkuev 1984 describes after
Woo (Sunkuev 1984, p. 9–10): choose a link assortment (n_i links of order i), build the *contracted graph*
on the links of order ≥ 3 (a multigraph with loops: each of its edges stands for a string of
binary links), distribute the n_2 binary links over its edges, expand, keep the graphs that are
chains, and remove isomorphic copies by the exact canonical form of ``graphs.canonical_form``.

Adjustable chains (Sunkuev 1984, p. 8–11): an adjustable chain with n' links, mobility W' and m locked pairs
("жёсткие регулируемые связи") is an ordinary chain with n = n' + m links and W = W' + m whose m
pairs are coloured as locked. The locked pairs and the links they touch form the adjustable links;
each must be an open chain (the locked pairs form a forest). The kinematic requirements are checked
on the *contracted* chain, in which each adjustable link is one vertex (Sunkuev 1984, p. 11: "подграф
регулируемого звена рассматривается как одна вершина"): it must be an ordinary chain with n' links
and mobility W' by the same four rules (in particular simple: an adjustable link may not be joined
to another link by two pairs, which would make that pair of links rigid). Colourings are counted
up to isomorphism of the coloured graph.

This rule gives 1, 3, 4, 7, 38 for the first five rows of Table 1 and 276 (not 285) for the row
n' = 8, m = 1; see ``docs/linkage.md`` and ``table1_rows``.
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from itertools import combinations, pairwise

from camcad.errors import CamcadError
from camcad.linkage.graphs import (
    LOCKED,
    ORDINARY,
    Chain,
    canonical_form,
    chain_problems,
    is_connected,
    pairs_for,
    relabel,
    rigid_subchain,
)

#: largest chains enumerated (links n = n' + m of the ordinary chain); 12-link 1-DOF chains (6856 of them)
#: take minutes and cannot be drawn legibly, so the CLI refuses beyond this
MAX_LINKS = 10

#: Table 1 of Sunkuev 1984 (p. 11): (n', W', m) -> number of adjustable chains
SEED_TABLE1 = {(4, 1, 1): 1, (4, 1, 2): 3, (4, 1, 3): 4, (6, 1, 1): 7, (6, 1, 2): 38, (8, 1, 1): 285}

#: published counts of ordinary chains (Tsai, Mechanism Design: Enumeration of Kinematic Structures
#: According to Function, CRC 2001, tables of planar chains with revolute pairs): (n, W) -> count
PUBLISHED_ORDINARY = {(4, 1): 1, (6, 1): 2, (8, 1): 16, (10, 1): 230, (5, 2): 1, (7, 2): 4, (9, 2): 40}

RULE_ORDINARY = ("graph with n vertices (links, frame counted) and p = (3(n-1)-W)/2 edges (revolute pairs); "
                 "simple, connected, every link in >= 2 pairs, no rigid sub-chain (every set S of >= 2 links "
                 "has 3(|S|-1) - 2e(S) >= 1); fractionated chains kept; counted up to isomorphism")
RULE_ADJUSTABLE = ("ordinary chain with n = n'+m links and W = W'+m, m of its pairs locked; the locked pairs form "
                   "a forest (each adjustable link is an open chain); contracting each adjustable link to one "
                   "vertex must give an ordinary chain with n' links and mobility W' (simple, every link in >= 2 "
                   "pairs, no rigid sub-chain); counted up to isomorphism of the edge-coloured graph")


def _check_size(links: int, where: str) -> None:
    if links > MAX_LINKS:
        raise CamcadError(f"chains of {links} links are beyond what camcad enumerates (up to {MAX_LINKS} links, "
                          "e.g. 230 ten-link 1-DOF chains in about a second)", where,
                          f"use --links {MAX_LINKS} or fewer (for adjustable chains n'+m <= {MAX_LINKS})")


def link_assortments(links: int, dof: int) -> list[dict[int, int]]:
    """Every link assortment {order i: n_i} of a chain with ``links`` links and mobility ``dof``.

    Σ n_i = n and Σ i·n_i = 2p with p = (3(n − 1) − W)/2, i ≥ 2 (Sunkuev 1984, p. 9, first stage of Woo's
    method). Orders are bounded by n − 1.

    Examples
    --------
    >>> link_assortments(6, 1)
    [{2: 4, 3: 2}, {2: 5, 4: 1}]
    >>> len(link_assortments(8, 1))
    5
    """
    pairs = pairs_for(links, dof)
    excess = 2 * pairs - 2 * links  # Σ (i − 2) n_i
    out = []

    def parts(remaining: int, largest: int, acc: list[int]) -> None:
        if remaining == 0:
            if len(acc) <= links:
                counts: dict[int, int] = {}
                for part in acc:
                    counts[part + 2] = counts.get(part + 2, 0) + 1
                n2 = links - len(acc)
                full = ({2: n2} if n2 else {}) | counts
                out.append(dict(sorted(full.items())))
            return
        for part in range(min(remaining, largest), 0, -1):
            if part + 2 <= links - 1:
                parts(remaining - part, part, acc + [part])

    parts(excess, excess, [])
    return sorted(out, key=lambda a: sorted(a.items()))


def _multigraphs(degrees: list[int]):
    """Labelled loop-and-multi-edge graphs with the given vertex degrees (a loop adds 2):
    yields lists of contracted edges (i, j), i <= j, repeated by multiplicity."""
    h = len(degrees)
    pairs = [(i, j) for i in range(h) for j in range(i, h)]
    last = {i: max(k for k, (a, b) in enumerate(pairs) if i in (a, b)) for i in range(h)}
    rem = list(degrees)
    chosen: list[tuple[int, int]] = []

    def rec(k: int):
        if k == len(pairs):
            if not any(rem):
                yield list(chosen)
            return
        i, j = pairs[k]
        top = rem[i] // 2 if i == j else min(rem[i], rem[j])
        for mult in range(top, -1, -1):
            if i == j:
                rem[i] -= 2 * mult
            else:
                rem[i] -= mult
                rem[j] -= mult
            ok = all(rem[v] == 0 for v in (i, j) if last[v] == k)
            if ok:
                chosen.extend([(i, j)] * mult)
                yield from rec(k + 1)
                del chosen[len(chosen) - mult:]
            if i == j:
                rem[i] += 2 * mult
            else:
                rem[i] += mult
                rem[j] += mult

    yield from rec(0)


def _distinct_multigraphs(degrees: list[int]):
    """The connected contracted multigraphs of ``_multigraphs``, one per isomorphism class (canonical form
    with edge colour = multiplicity, vertex colour = number of loops)."""
    h = len(degrees)
    seen = set()
    for contracted in _multigraphs(degrees):
        simple = sorted({e for e in contracted if e[0] != e[1]})
        if not is_connected(h, simple):
            continue
        loops = [sum(1 for e in contracted if e == (v, v)) for v in range(h)]
        mult = [contracted.count(e) for e in simple]
        cert = canonical_form(h, simple, mult, [(degrees[v], loops[v]) for v in range(h)])[0]
        if cert in seen:
            continue
        seen.add(cert)
        yield contracted


def _distributions(contracted: list[tuple[int, int]], binaries: int):
    """Numbers of binary links on each contracted edge: loops get >= 2; of several parallel edges
    (or loops at one vertex) at most one gets 0 and their counts are non-decreasing (they are
    interchangeable)."""
    count = len(contracted)
    mins = [2 if i == j else 0 for i, j in contracted]
    acc = [0] * count

    def rec(k: int, left: int):
        if k == count:
            if left == 0:
                yield list(acc)
            return
        low = mins[k]
        if k > 0 and contracted[k - 1] == contracted[k]:
            low = max(low, acc[k - 1], 1 if acc[k - 1] == 0 else 0)
        for value in range(low, left + 1):
            acc[k] = value
            yield from rec(k + 1, left - value)
        acc[k] = 0

    yield from rec(0, binaries)


def _expand(h: int, contracted: list[tuple[int, int]], counts: list[int]) -> tuple[int, list[tuple[int, int]]]:
    edges: list[tuple[int, int]] = []
    nxt = h
    for (i, j), k in zip(contracted, counts):
        path = [i] + list(range(nxt, nxt + k)) + [j]
        nxt += k
        edges.extend((min(a, b), max(a, b)) for a, b in pairwise(path))
    return nxt, edges


@dataclass
class OrdinaryAtlas:
    """The ordinary chains of one class (n, W), in canonical numbering, with the work it took."""

    links: int
    dof: int
    chains: list[Chain]
    candidates: int
    seconds: float
    by_assortment: dict[str, int] = field(default_factory=dict)


def ordinary_chains(links: int, dof: int) -> OrdinaryAtlas:
    """All non-isomorphic ordinary chains with ``links`` links and mobility ``dof`` (contracted graphs).

    Parameters
    ----------
    links : int
        Number of links n (the frame counted).
    dof : int
        Mobility W.

    Returns
    -------
    OrdinaryAtlas
        The chains (sorted by assortment, then canonical certificate), the number of expanded
        candidate graphs, the wall time (s) and the count per link assortment.

    Examples
    --------
    >>> [len(ordinary_chains(n, 1).chains) for n in (4, 6, 8)]
    [1, 2, 16]
    >>> [len(ordinary_chains(n, 2).chains) for n in (5, 7)]
    [1, 4]
    """
    _check_size(links, "--links")
    start = time.perf_counter()
    pairs = pairs_for(links, dof)
    found: dict[tuple, tuple[str, Chain]] = {}
    rejected: set = set()
    candidates = 0
    for assortment in link_assortments(links, dof):
        label = " ".join(f"n{i}={k}" for i, k in assortment.items())
        binaries = assortment.get(2, 0)
        degrees = [i for i, k in sorted(assortment.items(), reverse=True) if i > 2 for _ in range(k)]
        graphs: Iterable[tuple[int, list[tuple[int, int]]]]
        if not degrees:
            graphs = [(links, [(min(a, (a + 1) % links), max(a, (a + 1) % links)) for a in range(links)])]
        else:
            graphs = (_expand(len(degrees), contracted, counts)
                      for contracted in _distinct_multigraphs(degrees)
                      for counts in _distributions(contracted, binaries))
        for n, edges in graphs:
            candidates += 1
            if len(set(edges)) != len(edges) or len(edges) != pairs:
                continue
            cert, order = canonical_form(n, edges)
            if cert in found or cert in rejected:
                continue
            if chain_problems(n, edges, dof):
                rejected.add(cert)
                continue
            found[cert] = (label, relabel(Chain(n, tuple(sorted(edges))), order))
    chains_by = sorted(found.items(), key=lambda item: (item[1][0], item[0]))
    by_assortment: dict[str, int] = {}
    for _, (label, _) in chains_by:
        by_assortment[label] = by_assortment.get(label, 0) + 1
    return OrdinaryAtlas(links, dof, [chain for _, (_, chain) in chains_by], candidates,
                         time.perf_counter() - start, by_assortment)


def _contract(chain_n: int, edges, locked) -> tuple[int, list[tuple[int, int]], list[list[int]]] | None:
    """Contract each component of the locked pairs to one vertex. Returns (n', contracted edges,
    groups) or None when the locked pairs hold a cycle (an adjustable link must be an open chain).
    Contracted edges keep multiplicity and self-loops so that the caller can reject them."""
    parent = list(range(chain_n))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for u, v in locked:
        ru, rv = find(u), find(v)
        if ru == rv:
            return None
        parent[ru] = rv
    roots = sorted({find(v) for v in range(chain_n)})
    index = {r: k for k, r in enumerate(roots)}
    locked_set = set(locked)
    contracted = [(index[find(u)], index[find(v)]) for u, v in edges if (u, v) not in locked_set]
    groups: dict[int, list[int]] = {}
    for v in range(chain_n):
        groups.setdefault(index[find(v)], []).append(v)
    return len(roots), contracted, [groups[k] for k in range(len(roots))]


def adjustable_problems(chain: Chain, dof_prime: int) -> list[str]:
    """Why ``chain`` with its ``locked`` pairs is not an admissible adjustable chain of mobility W'.

    The requirements are checked on the contracted chain (each adjustable link one vertex, seed
    p. 11); see the module docstring for the rule.

    Examples
    --------
    >>> c6 = Chain(6, ((0, 1), (0, 5), (1, 2), (2, 3), (3, 4), (4, 5)), locked=((0, 1), (1, 2)))
    >>> adjustable_problems(c6, 1)
    []
    """
    contracted = _contract(chain.n, chain.edges, chain.locked)
    if contracted is None:
        return ["the locked pairs close a loop (an adjustable link must be an open chain)"]
    n_prime, edges, _ = contracted
    problems = []
    for u, v in edges:
        if u == v:
            problems.append("a free pair joins an adjustable link to itself")
            break
    normal = [(min(u, v), max(u, v)) for u, v in edges if u != v]
    if len(set(normal)) != len(normal):
        problems.append("an adjustable link is joined to another link by two pairs (rigid)")
    if problems:
        return problems
    return [f"contracted chain: {p}" for p in chain_problems(n_prime, normal, dof_prime)]


@dataclass
class AdjustableAtlas:
    """Adjustable chains of one class (n', W', m) and the counts under weaker rules."""

    links: int
    dof: int
    locked: int
    chains: list[Chain]
    base_chains: int
    colourings: int
    count_unconditional: int
    count_forest: int
    count_contracted_connected_min2: int
    count_contracted_simple: int
    seconds: float
    seed_count: int | None = None
    by_base: dict[int, int] = field(default_factory=dict)


def adjustable_chains(links: int, dof: int, locked: int) -> AdjustableAtlas:
    """All non-isomorphic adjustable chains with n' = ``links``, W' = ``dof`` and m = ``locked``.

    Rule (module docstring): colour m pairs of every ordinary chain with n' + m links and mobility
    W' + m; keep colourings whose locked pairs form a forest and whose contracted chain is an
    ordinary chain (n', W'); count up to isomorphism of the coloured graph (Sunkuev 1984, p. 8–11).

    Besides the count under that rule it returns, to show how much each condition removes, the
    number of colourings up to isomorphism with no condition (``count_unconditional``), with the
    forest condition only (``count_forest``), with the contracted chain connected and every link in
    ≥ 2 pairs only (``count_contracted_connected_min2``), and with it also simple
    (``count_contracted_simple``, no rigid-sub-chain check).

    Examples
    --------
    >>> [len(adjustable_chains(4, 1, m).chains) for m in (1, 2, 3)]
    [1, 3, 4]
    >>> len(adjustable_chains(6, 1, 1).chains)
    7
    """
    if locked < 1:
        raise CamcadError(f"--adjustable must be 1 or more, got {locked}", "--adjustable",
                          "give the number m of locked pairs, e.g. --adjustable 1")
    _check_size(links + locked, "--links/--adjustable")
    pairs_for(links, dof, "--links/--dof (of the adjustable chain)")
    start = time.perf_counter()
    base = ordinary_chains(links + locked, dof + locked).chains
    seen_all: set = set()
    seen_forest: set = set()
    seen_weak: set = set()
    seen_simple: set = set()
    kept: dict[tuple, tuple[int, Chain]] = {}
    colourings = 0
    for base_index, chain in enumerate(base):
        for subset in combinations(chain.edges, locked):
            colourings += 1
            candidate = Chain(chain.n, chain.edges, tuple(subset))
            colours = [LOCKED if e in subset else ORDINARY for e in chain.edges]
            cert, order = canonical_form(chain.n, chain.edges, colours)
            if cert in seen_all:
                continue
            seen_all.add(cert)
            contracted = _contract(chain.n, chain.edges, subset)
            if contracted is None:
                continue
            seen_forest.add(cert)
            n_prime, edges, _ = contracted
            degree = [0] * n_prime
            for u, v in edges:
                degree[u] += 1
                degree[v] += 1

            if min(degree) < 2 or not is_connected(n_prime, edges):
                continue
            seen_weak.add(cert)
            normal = [(min(u, v), max(u, v)) for u, v in edges]
            if any(u == v for u, v in normal) or len(set(normal)) != len(normal):
                continue
            seen_simple.add(cert)
            if rigid_subchain(n_prime, normal) is not None:
                continue
            kept[cert] = (base_index, relabel(candidate, order))
    ordered = sorted(kept.items(), key=lambda item: (item[1][0], item[0]))
    by_base: dict[int, int] = {}
    for _, (b, _) in ordered:
        by_base[b] = by_base.get(b, 0) + 1
    return AdjustableAtlas(links, dof, locked, [c for _, (_, c) in ordered], len(base), colourings,
                           len(seen_all), len(seen_forest), len(seen_weak), len(seen_simple),
                           time.perf_counter() - start, SEED_TABLE1.get((links, dof, locked)), by_base)


@dataclass
class AtlasReport:
    """The atlas of one class: the chains (canonical numbering) and the JSON payload."""

    chains: list[Chain]
    payload: dict
    adjustable: bool
    seconds: float = 0.0
    schemes: list = field(default_factory=list)   # camcad.linkage.schemes.Scheme per chain, once annotated


def _discrepancy(key: tuple[int, int, int], result: AdjustableAtlas) -> str | None:
    seed = SEED_TABLE1.get(key)
    if seed is None or seed == len(result.chains):
        return None
    return (f"Table 1 of Sunkuev 1984 gives {seed}; camcad's rule gives {len(result.chains)}. Without any kinematic "
            f"condition (every colouring up to isomorphism) the count is {result.count_unconditional}; with the "
            f"contracted chain only connected, simple and of minimum degree 2 (no rigid-sub-chain check) it is "
            f"{result.count_contracted_simple}. No single rule tried reproduces all six rows of Table 1 (the rule "
            "that gives 1, 3, 4, 7, 38 gives this number); Sunkuev 1984's rule for this row is not recoverable from "
            "the abstract (see docs/linkage.md)")


def atlas(links: int, dof: int, adjustable: int | None = None) -> AtlasReport:
    """The atlas report of ordinary chains (n = ``links``, W = ``dof``) or, with ``adjustable`` = m, of
    adjustable chains (n' = ``links``, W' = ``dof``, m locked pairs).

    Payload keys: ``count``, ``chains`` (each: links, pairs, assortment, locked_pairs, adjustable_links,
    fractionated), ``rule``, ``seed_count`` (when Table 1 of Sunkuev 1984 has the class), ``published_count``
    (ordinary chains with a published count), ``discrepancy`` (text, when Sunkuev 1984's count differs),
    ``counts`` (under weaker rules). ``AtlasReport.seconds`` is the enumeration time (not in the payload,
    so that the written files stay byte-identical).

    Examples
    --------
    >>> atlas(6, 1, adjustable=2).payload["count"], atlas(6, 1, adjustable=2).payload["seed_count"]
    (38, 38)
    """
    result: OrdinaryAtlas | AdjustableAtlas
    if adjustable is None:
        result = ordinary_chains(links, dof)
        chains = result.chains
        payload = {"kind": "ordinary", "links": links, "dof": dof, "pairs": pairs_for(links, dof),
                   "count": len(chains), "rule": RULE_ORDINARY, "candidates": result.candidates,
                   "by_assortment": result.by_assortment}
        if (links, dof) in PUBLISHED_ORDINARY:
            payload["published_count"] = PUBLISHED_ORDINARY[(links, dof)]
            payload["published_source"] = ("Tsai, Mechanism Design: Enumeration of Kinematic Structures According "
                                           "to Function (CRC 2001), planar chains with revolute pairs")
    else:
        result = adjustable_chains(links, dof, adjustable)
        chains = result.chains
        payload = {"kind": "adjustable", "links": links, "dof": dof, "adjustable": adjustable,
                   "base_links": links + adjustable, "base_dof": dof + adjustable,
                   "count": len(chains), "rule": RULE_ADJUSTABLE,
                   "counts": {"rule": len(chains), "unconditional": result.count_unconditional,
                              "locked_pairs_forest": result.count_forest,
                              "contracted_connected_min_degree_2": result.count_contracted_connected_min2,
                              "contracted_simple": result.count_contracted_simple},
                   "base_chains": result.base_chains, "colourings": result.colourings}
        if result.seed_count is not None:
            payload["seed_count"] = result.seed_count
            payload["seed_source"] = "Sunkuev 1984, Table 1 (abstract, ch. 1)"
            payload["discrepancy"] = _discrepancy((links, dof, adjustable), result)
    items = []
    for index, chain in enumerate(chains, start=1):
        item = {"index": index, **chain.to_json()}
        cut = any(not is_connected(chain.n - 1, [(u - (u > v0), w - (w > v0)) for u, w in chain.edges
                                                 if v0 not in (u, w)]) for v0 in range(chain.n))
        item["fractionated"] = cut
        items.append(item)
    payload["chains"] = items
    return AtlasReport(chains, payload, adjustable is not None, result.seconds)
