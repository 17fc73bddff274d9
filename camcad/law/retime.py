"""Changing a law's phase angles while keeping its lift and its shape.

A cyclogram shortens or stretches an operation; the law of that operation must follow. A motion
phase of width β stretched to β′ keeps its shape in the normalised angle u = (θ − θ0)/β and its
lift h, so its acceleration analog scales by (β/β′)² (a = h f''(u)/β², Norton 2009 §3): the
velocity scales by β/β′ and the displacement is unchanged. A balanced law therefore stays
balanced. Dwells simply take the new widths.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Phase, PiecewiseLinearLaw, sample_piecewise_linear
from camcad.law.segments import SegmentLaw, solve_segments
from camcad.law.standard import CompositeLaw, Segment


def retime(law, phases: tuple[Phase, ...], where: str = ""):
    """The law with new phase boundaries: the same kinds in the same order, covering the same cycle.

    A dwell of the law may be missing from ``phases`` (a neighbouring motion took all of it); it
    becomes a dwell of zero width and disappears from the result's phases. A segment law
    (``camcad.law.segments``) is solved again at the new angles, every segment keeping its stated end values.
    """
    old = tuple(law.phases)
    bounds = _aligned_bounds(old, tuple(phases), where)
    if abs(bounds[0][0] - old[0].start) > 1e-12 or abs(bounds[-1][1] - old[-1].end) > 1e-9:
        raise CamcadError("the new phases do not cover the law's cycle", where, "keep the first start and last end")
    if isinstance(law, CompositeLaw):
        segments = tuple(Segment(seg.kind, start, end, seg.lift, seg.shape)
                         for seg, (start, end) in zip(law.segments, bounds) if end > start)
        return CompositeLaw(segments, law.cycle)
    if isinstance(law, PiecewiseLinearLaw):
        return _retime_polyline(law, bounds)
    if isinstance(law, SegmentLaw):
        # every segment keeps its stated end values and is solved again at its new angles; a dwell the
        # neighbouring motion took all of disappears
        specs = tuple(replace(spec, to_deg=float(np.degrees(end)))
                      for spec, (start, end) in zip(law.specs, bounds) if end > start)
        return solve_segments(specs, float(np.degrees(law.cycle)), where or law.where)
    raise CamcadError(f"cannot change the phase angles of a {type(law).__name__}", where,
                      "give the law as a standard law or a drawn polyline")


def _aligned_bounds(old: tuple[Phase, ...], new: tuple[Phase, ...], where: str) -> list[tuple[float, float]]:
    """(start, end) for every phase of ``old`` from ``new``; a dwell missing from ``new`` gets zero width."""
    bounds = []
    j = 0
    position = new[0].start if new else 0.0
    for phase in old:
        if j < len(new) and new[j].kind == phase.kind:
            bounds.append((new[j].start, new[j].end))
            position = new[j].end
            j += 1
        elif phase.kind == "dwell":
            bounds.append((position, position))
        else:
            raise CamcadError("the new phases do not have the kinds of the law's phases in the same order", where,
                              f"the law's phases are {', '.join(p.kind for p in old)}")
    if j != len(new):
        raise CamcadError("the new phases do not have the kinds of the law's phases in the same order", where,
                          f"the law's phases are {', '.join(p.kind for p in old)}")
    return bounds


def _retime_polyline(law: PiecewiseLinearLaw, bounds: list[tuple[float, float]]) -> PiecewiseLinearLaw:
    """Warp the knots phase by phase and scale each motion phase's ordinates by (β/β′)².

    Every phase boundary becomes a double knot, its left copy belonging to the phase before and
    its right copy to the phase after, so two neighbouring phases can scale differently.
    """
    old = law.phases
    x, a = law.x, law.a
    for boundary in [p.start for p in old[1:]]:
        at = np.flatnonzero(x == boundary)
        if len(at) >= 2:
            continue
        value = a[at[0]] if len(at) else sample_piecewise_linear(x, a, np.array([boundary]))[0]
        cut = int(np.searchsorted(x, boundary, side="left"))
        x = np.insert(np.delete(x, at), cut, [boundary, boundary])
        a = np.insert(np.delete(a, at), cut, [value, value])
    owner = np.searchsorted([p.end for p in old], x, side="left")  # phase holding x (the left one at a boundary)
    starts = np.array([p.start for p in old])
    for index in range(1, len(x)):
        if x[index] == x[index - 1] and x[index] in starts:
            owner[index] = int(np.flatnonzero(starts == x[index])[0])  # the right copy opens the next phase
    owner = np.minimum(owner, len(old) - 1)
    factor = np.array([1.0 if p.kind == "dwell" else (p.width / (end - start)) ** 2
                       for p, (start, end) in zip(old, bounds)])
    old_breaks = np.array([p.start for p in old] + [old[-1].end])
    new_breaks = np.array([start for start, _ in bounds] + [bounds[-1][1]])
    # a stated end velocity scales with the phase (v = h f'(u)/β); a stated position stays
    phases = tuple(Phase(p.kind, start, end, p.s_end, p.v_end * p.width / (end - start))
                   for p, (start, end) in zip(old, bounds) if end > start)
    return PiecewiseLinearLaw(np.interp(x, old_breaks, new_breaks), a * factor[owner], law.cycle, phases,
                              law.v0, law.s0)
