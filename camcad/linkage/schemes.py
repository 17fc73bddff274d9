"""Stage 4 of the structural synthesis: each chain of the atlas as a kinematic scheme (Sunkuev 1984, ch. 1, after
Woo: "На четвертом этапе по заданным графам определяются схемы соответствующих кинематических цепей").

A chain's graph has links as vertices and pairs as edges. Its scheme turns that round: every pair becomes a joint
drawn at the middle of its edge in the graph's layout (``camcad.linkage.layout``), and every link becomes the
polygon through its joints — a bar for a binary link, a triangle for a ternary one, a quadrilateral for a
quaternary one. Then:

- the **frame** is a link of the highest order outside the adjustable links (ties: the lowest canonical number);
  an adjustable chain whose every link of that order is in an adjustable link takes the highest order of the rest;
- the **input** is a binary link jointed to the frame (ties: the lowest number; none when the frame has no binary
  neighbour: the scheme says so);
- an **adjustable link** (the links joined by locked pairs, Sunkuev 1984, Fig. 1 b) is drawn filled, its locked pairs as
  squares (the joint is clamped while the machine runs and released to regulate), ordinary pairs as circles.

A short guide to choosing among the schemes (``GUIDE``) is printed with the atlas and stored per chain as
``scheme`` in the JSON: which link is the frame and which the input, whether the adjustable link is jointed to the
frame (regulated at the frame: reachable with the machine stopped, its setting does not move with the input) and
how many loops the chain has.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.linkage.graphs import Chain
from camcad.linkage.layout import layout

GUIDE = ("choose the scheme whose adjustable link is jointed to the frame (it is set at a fixed place while the "
         "machine is stopped, as Sunkuev 1984's regulation tasks assume) and whose input is a binary link on the frame "
         "(a crank or a rocker driven directly); among those, fewer links of higher order make simpler parts; a "
         "chain with a cut link (fractionated) is two mechanisms in series")


@dataclass(frozen=True)
class Scheme:
    """A chain drawn as a kinematic scheme: joint positions (one per pair, in ``chain.edges`` order), each link's
    polygon (joint indices around it), the frame and input links, the adjustable links, and the guide's facts."""

    joints: np.ndarray                # (pairs, 2)
    polygons: tuple[tuple[int, ...], ...]
    frame: int
    input: int | None
    adjustable: tuple[tuple[int, ...], ...]
    adjustable_on_frame: bool
    loops: int

    def to_json(self) -> dict:
        return {"frame_link": self.frame, "input_link": self.input,
                "joints": [[round(float(x), 6), round(float(y), 6)] for x, y in self.joints],
                "link_polygons": [list(p) for p in self.polygons],
                "adjustable_jointed_to_frame": self.adjustable_on_frame, "loops": self.loops}


def scheme(chain: Chain, positions: np.ndarray | None = None) -> Scheme:
    """The kinematic scheme of ``chain`` (module docstring); ``positions`` the graph layout (default
    ``camcad.linkage.layout.layout``).

    Examples
    --------
    The four-bar: four joints, four bars, the frame link 0 and a binary input jointed to it.

    >>> s = scheme(Chain(4, ((0, 1), (0, 3), (1, 2), (2, 3))))
    >>> len(s.joints), [len(p) for p in s.polygons], s.frame, s.input, s.loops
    (4, [2, 2, 2, 2], 0, 1, 1)
    """
    pos = layout(chain.n, chain.edges) if positions is None else np.asarray(positions, dtype=float)
    joints = np.array([(pos[u] + pos[v]) / 2 for u, v in chain.edges])
    polygons = []
    for link in range(chain.n):
        mine = [k for k, e in enumerate(chain.edges) if link in e]
        centre = joints[mine].mean(axis=0)
        mine.sort(key=lambda k: math.atan2(joints[k][1] - centre[1], joints[k][0] - centre[0]))
        polygons.append(tuple(mine))
    degrees = chain.degrees()
    adjustable = tuple(chain.adjustable_links())
    in_adjustable = {v for g in adjustable for v in g}
    free = [v for v in range(chain.n) if v not in in_adjustable] or list(range(chain.n))
    frame = max(free, key=lambda v: (degrees[v], -v))
    neighbours = sorted({w for e in chain.edges for w in e if frame in e and w != frame})
    binary = [w for w in neighbours if degrees[w] == 2 and w not in in_adjustable]
    on_frame = any(frame in e and (e[0] in in_adjustable or e[1] in in_adjustable) for e in chain.edges)
    loops = len(chain.edges) - chain.n + 1
    return Scheme(joints, tuple(polygons), frame, binary[0] if binary else None, adjustable, on_frame, loops)


def annotate_schemes(report) -> None:
    """Add every chain's scheme (``scheme`` key) and the guide to an ``camcad.linkage.atlas.AtlasReport``'s
    payload, and keep the schemes on the report (``report.schemes``) for the drawings."""
    schemes = [scheme(chain) for chain in report.chains]
    for item, s in zip(report.payload["chains"], schemes):
        item["scheme"] = s.to_json()
    report.payload["guide"] = GUIDE
    if report.adjustable:
        count = sum(1 for s in schemes if s.adjustable_on_frame)
        report.payload["adjustable_jointed_to_frame"] = count
    report.schemes = schemes
