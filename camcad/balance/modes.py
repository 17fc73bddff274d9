"""The vertex modes of the correction: which vertices may move and how (min-change, extrema, lobes,
key points, a segment), solved exactly as the least change that meets the conditions.
"""

from __future__ import annotations


import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw, sample_piecewise_linear, uniform_grid
from camcad.law.phases import zero_threshold
from camcad.balance.checking import _scale
from camcad.balance.conditions import conditions, functional_rows, mass_matrix
from camcad.balance.iterate import _iterate


def _free_vertices(law: PiecewiseLinearLaw, hold: np.ndarray) -> np.ndarray:
    """Vertices a correction may move: off the axis, outside dwells, not held."""
    eps = zero_threshold(law.a)
    free = (np.abs(law.a) > eps) & ~hold
    for phase in law.phases:
        if phase.kind == "dwell":
            free &= ~((law.x > phase.start) & (law.x < phase.end))
    return free


def _resample(law: PiecewiseLinearLaw, step_deg: float, hold: np.ndarray):
    """The law resampled at a uniform step; jumps keep both their vertices so they stay vertical."""
    if not (np.isfinite(step_deg) and step_deg > 0):
        raise CamcadError(f"step {step_deg!r} deg must be positive", "--step", "give e.g. --step 0.1")
    grid = uniform_grid(0.0, law.cycle, np.radians(step_deg))
    jumps = law.x[:-1][np.diff(law.x) == 0]
    boundaries = np.array([p.start for p in law.phases] + [p.end for p in law.phases])
    held = law.x[hold]
    knots = np.unique(np.concatenate((grid, jumps, boundaries, held)))
    x_parts, a_parts = [], []
    for t in knots:
        at = np.flatnonzero(law.x == t)
        if len(at) > 1:  # a jump: left and right values
            x_parts.extend([t, t])
            a_parts.extend([law.a[at[0]], law.a[at[-1]]])
        else:
            x_parts.append(t)
            a_parts.append(sample_piecewise_linear(law.x, law.a, np.array([t]))[0])
    x_new = np.array(x_parts)
    new_hold = np.isin(x_new, held)
    return PiecewiseLinearLaw(x_new, np.array(a_parts), law.cycle, law.phases), new_hold


# --- vertex modes -------------------------------------------------------------------------------

def _basis(law: PiecewiseLinearLaw, mode: str, free: np.ndarray, segment_deg, where: str):
    """Columns B of allowed changes δ = B p, and whether to measure p with the mass matrix."""
    from scipy import sparse

    n = len(law.x)
    if mode in ("min-change", "keypoints"):
        idx = np.flatnonzero(free)
        return sparse.csc_matrix((np.ones(len(idx)), (idx, np.arange(len(idx)))), shape=(n, len(idx))), \
            mode == "min-change", idx
    if mode == "segment":
        lo, hi = np.radians(min(segment_deg)), np.radians(max(segment_deg))
        idx = np.flatnonzero(free & (law.x >= lo) & (law.x <= hi))
        if len(idx) == 0:
            raise CamcadError(f"the segment {segment_deg[0]:g}:{segment_deg[1]:g} deg holds no vertex off the axis",
                              where or "--segment", "widen the segment or use --mode min-change")
        return sparse.csc_matrix((np.ones(len(idx)), (idx, np.arange(len(idx)))), shape=(n, len(idx))), True, idx
    groups = extremum_groups(law.a, free) if mode == "extrema" else lobe_groups(law.a, free)
    rows, cols, vals = [], [], []
    for col, group in enumerate(groups):
        rows.extend(group)
        cols.extend([col] * len(group))
        # extrema move by a common amount; a lobe scales, so every point moves in proportion
        vals.extend([1.0] * len(group) if mode == "extrema" else list(law.a[group]))
    return sparse.csc_matrix((vals, (rows, cols)), shape=(n, len(groups))), True, \
        np.unique(np.concatenate(groups)) if groups else np.array([], dtype=int)


def lobes(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """Runs of consecutive free vertices with the same sign of a."""
    result = []
    current: list[int] = []
    sign = 0
    for i in range(len(a)):
        s = int(np.sign(a[i])) if free[i] else 0
        if s != 0 and s == sign:
            current.append(i)
        else:
            if current:
                result.append(np.array(current))
            current = [i] if s != 0 else []
            sign = s
    if current:
        result.append(np.array(current))
    return result


def lobe_groups(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    return lobes(a, free)


def extremum_groups(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """The local maxima of positive lobes and minima of negative lobes; equal neighbours form one group."""
    groups = []
    for lobe in lobes(a, free):
        values = np.abs(a[lobe])
        scale = values.max()
        # plateaus of equal values (within round-off) are one point for this purpose
        runs = []
        start = 0
        for i in range(1, len(lobe) + 1):
            if i == len(lobe) or abs(values[i] - values[start]) > 1e-9 * scale:
                runs.append((start, i))
                start = i
        for r, (r0, r1) in enumerate(runs):
            here = values[r0]
            left = values[runs[r - 1][0]] if r > 0 else -np.inf
            right = values[runs[r + 1][0]] if r + 1 < len(runs) else -np.inf
            if here >= left and here >= right:
                groups.append(lobe[r0:r1])
    return groups


def _vertex_mode(law, mode, method, tol, step_deg, segment_deg, hold, max_iterations, where):
    free = _free_vertices(law, hold)
    basis, use_mass, touched = _basis(law, mode, free, segment_deg, where)
    conds = conditions(law)
    rows = functional_rows(law.x, conds)
    if basis.shape[1] == 0:
        raise CamcadError(f"mode {mode} finds no point it may move", where,
                          "use --mode min-change")
    if method == "exact":
        delta = _least_change(law, rows, basis, use_mass, conds, mode, where)
        return law.with_ordinates(law.a + delta), 1
    return _iterate(law, mode, conds, basis, touched, tol, step_deg, max_iterations, where)


def _least_change(law, rows, basis, use_mass, conds, mode, where) -> np.ndarray:
    """δ = B p with the least pᵀGp such that C(a + δ) = 0; G = BᵀMB (function norm) or I."""
    from scipy.sparse.linalg import splu

    residual = rows @ law.a
    A = np.asarray((basis.T @ rows.T).T)  # C B, m × k
    if use_mass:
        gram = (basis.T @ mass_matrix(law.x) @ basis).tocsc()
        solve = splu(gram).solve
        g_inv_at = solve(np.ascontiguousarray(A.T))
    else:
        g_inv_at = A.T.copy()
    schur = A @ g_inv_at
    scale = _scale(law)
    p = -g_inv_at @ np.linalg.lstsq(schur, residual, rcond=1e-12)[0]
    delta = np.asarray(basis @ p).ravel()
    remaining = rows @ (law.a + delta)
    if np.any(np.abs(remaining) > 1e-8 * scale):
        _explain_unreachable(A, residual, conds, mode, where)
    return delta


def _explain_unreachable(A, residual, conds, mode, where):
    scale_rows = np.abs(A).max(axis=1)
    dead = [c.name for c, s, r in zip(conds, scale_rows, residual) if s <= 1e-12 * max(scale_rows.max(), 1e-300)
            and abs(r) > 0]
    if dead:
        what = f"mode {mode} cannot change the {dead[0]}: none of the points it may move acts on it"
    else:
        what = (f"mode {mode} has {np.linalg.matrix_rank(A)} independent ways to change the law "
                f"for {len(conds)} balance conditions")
    fix = "use --mode min-change or keypoints (they move every point off the axis)"
    if mode == "segment":
        fix = "widen --segment to cover every phase that is out of balance, or use --mode min-change"
    raise CamcadError(what, where, fix)




