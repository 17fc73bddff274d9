"""The vertex modes of the correction: which vertices may move and how (min-change, extrema, lobes,
key points, a segment), solved exactly as the least change that meets the conditions.

Every mode is a basis B of allowed changes δ = B p (one column per unknown p_j) and a measure of
the change (the function norm ∫δa² dθ, or the sum of squared vertex changes). Rules shared by all:

- vertices on the axis and inside dwells stay (a dwell stays a dwell), and so do held vertices;
- the two vertices of a jump (same angle) are one unknown: they move together, so a jump is never
  torn into a spike; a held vertex (``--move``, or on the axis) leaves its partner free alone;
- ``extrema``: each local extremum (with its plateau) moves, and the change tapers linearly to the
  neighbouring extrema and to the lobe's ends, so the lobe keeps its shape (no single-vertex spike);
- ``extrema-resample``: each lobe scales as a whole.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.arrays import unique
from camcad.balance.checking import lift_scale
from camcad.balance.conditions import (
    Condition,
    conditions,
    functional_rows,
    lift_conditions,
    mass_diagonals,
    mass_matrix,
    targets,
    valid_step,
)
from camcad.balance.iterate import iterate_moves
from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw, sample_piecewise_linear, uniform_grid
from camcad.law.phases import zero_threshold
from camcad.numerics import solve_tridiagonal

#: a condition is met by a solve when its residual is below this fraction of the rise
SOLVE_TOLERANCE = 1e-8
#: a vertex change at or below this fraction of max |a| is round-off, not a change (``correct`` counts it so too)
ROUND_OFF_CHANGE = 1e-12


def _free_vertices(law: PiecewiseLinearLaw, hold: np.ndarray) -> np.ndarray:
    """Vertices a correction may move: off the axis, outside dwells, not held."""
    eps = zero_threshold(law.a)
    free = (np.abs(law.a) > eps) & ~hold
    for phase in law.phases:
        if phase.kind == "dwell":
            free &= ~((law.x > phase.start) & (law.x < phase.end))
    return free


def jump_nodes(x: np.ndarray) -> np.ndarray:
    """Node number of each vertex: vertices at the same angle (a jump) share one node.

    Parameters
    ----------
    x : ndarray
        Knots (rad), non-decreasing.

    Returns
    -------
    ndarray of int
        Non-decreasing node numbers from 0 (no unit).

    Examples
    --------
    >>> jump_nodes(np.array([0.0, 1.0, 1.0, 2.0])).tolist()
    [0, 1, 1, 2]
    """
    x = np.asarray(x, dtype=float)
    if len(x) == 0:
        return np.zeros(0, dtype=int)
    return np.concatenate(([0], np.cumsum(x[1:] != x[:-1]))).astype(int)


def resample_law(law: PiecewiseLinearLaw, step_deg: float, hold: np.ndarray):
    """The law resampled at a uniform step; jumps keep both their vertices so they stay vertical."""
    valid_step(step_deg, law.cycle)
    grid = uniform_grid(0.0, law.cycle, np.radians(step_deg))
    jumps = law.x[:-1][np.diff(law.x) == 0]
    boundaries = np.array([p.start for p in law.phases] + [p.end for p in law.phases])
    held = law.x[hold]
    knots = unique(np.concatenate((grid, jumps, boundaries, held)))
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


# --- bases ----------------------------------------------------------------------------------------

@dataclass(frozen=True)
class NodeBasis:
    """One column per jump node of the movable vertices (a vertex's change is its node's unknown):
    δ = B p puts p[col[i]] on vertex idx[i]. Its Gram matrices are tridiagonal (numpy, no sparse matrix).

    idx: the movable vertices (increasing); col: each one's column (non-decreasing, 0 … k − 1);
    n: vertices in all; k: columns.
    """

    idx: np.ndarray
    col: np.ndarray
    n: int
    k: int

    @property
    def shape(self) -> tuple[int, int]:
        return (self.n, self.k)

    def __matmul__(self, p) -> np.ndarray:
        out = np.zeros(self.n)
        out[self.idx] = np.asarray(p, dtype=float).ravel()[self.col]
        return out

    def restrict(self, rows: np.ndarray) -> np.ndarray:
        """C B: each column the sum of the rows' entries at its vertices, shape (m, k)."""
        if self.k == 0:
            return np.zeros((rows.shape[0], 0))
        picked = rows[:, self.idx]
        if self.k == len(self.idx):        # no jump among them: one vertex per column
            return picked
        starts = np.flatnonzero(np.concatenate(([True], self.col[1:] != self.col[:-1])))
        return np.add.reduceat(picked, starts, axis=1)

    def gram(self, x: np.ndarray, use_mass: bool) -> tuple[np.ndarray, np.ndarray]:
        """(diagonal, off-diagonal G[c, c+1]) of G = BᵀMB (``use_mass``) or BᵀB."""
        if not use_mass:
            return np.bincount(self.col, minlength=self.k).astype(float), np.zeros(max(self.k - 1, 0))
        m_diag, m_off = mass_diagonals(x)
        diag = np.bincount(self.col, weights=m_diag[self.idx], minlength=self.k)
        off = np.zeros(max(self.k - 1, 0))
        # vertices i, i + 1 both movable and in consecutive columns couple through M[i, i+1]
        linked = (self.idx[1:] == self.idx[:-1] + 1) & (self.col[1:] == self.col[:-1] + 1)
        off[self.col[:-1][linked]] += m_off[self.idx[:-1][linked]]   # each column links to the next at most once
        # a jump's two vertices share a column: M between them is 0 (a zero-length segment)
        return diag, off


def _node_columns(x: np.ndarray, movable: np.ndarray) -> tuple[NodeBasis, np.ndarray]:
    """One column per jump node among the ``movable`` vertices (coefficient 1 on each of them)."""
    idx = np.flatnonzero(movable)
    nodes = jump_nodes(x)[idx]
    col = np.concatenate(([0], np.cumsum(nodes[1:] != nodes[:-1]))).astype(int) if len(idx) else \
        np.zeros(0, dtype=int)
    k = int(col[-1]) + 1 if len(col) else 0
    return NodeBasis(idx, col, len(x), k), idx


def _extrema_columns(law: PiecewiseLinearLaw, free: np.ndarray):
    """One column per extremum group: 1 on the group, tapering linearly in θ to 0 at the lobe's ends
    (the vertices just outside the lobe) and across to the neighbouring extrema of the same lobe."""
    from scipy import sparse

    x, n = law.x, len(law.x)
    rows: list[int] = []
    cols: list[int] = []
    vals: list[float] = []
    col = 0
    for lobe in lobes(law.a, free):
        groups = _lobe_extrema(law.a, lobe)
        spans = [(x[g[0]], x[g[-1]]) for g in groups]
        left = x[lobe[0] - 1] if lobe[0] > 0 else None
        right = x[lobe[-1] + 1] if lobe[-1] < n - 1 else None
        for i in lobe:
            xi = x[i]
            for k, (lo, hi) in enumerate(spans):
                if lo <= xi <= hi:
                    rows.append(i)
                    cols.append(col + k)
                    vals.append(1.0)
                    break
            else:
                k = int(np.searchsorted([lo for lo, _ in spans], xi))  # first group to the right
                if k == 0:
                    t = 1.0 if left is None else (xi - left) / (spans[0][0] - left)
                    rows.append(i)
                    cols.append(col)
                    vals.append(t)
                elif k == len(spans):
                    t = 1.0 if right is None else (right - xi) / (right - spans[-1][1])
                    rows.append(i)
                    cols.append(col + k - 1)
                    vals.append(t)
                else:
                    t = (xi - spans[k - 1][1]) / (spans[k][0] - spans[k - 1][1])
                    rows.extend((i, i))
                    cols.extend((col + k - 1, col + k))
                    vals.extend((1.0 - t, t))
        col += len(groups)
    keep = np.asarray(vals) != 0.0
    basis = sparse.csc_matrix((np.asarray(vals)[keep], (np.asarray(rows, dtype=int)[keep],
                                                        np.asarray(cols, dtype=int)[keep])), shape=(n, col))
    return basis, unique(np.asarray(rows, dtype=int)[keep])


def _basis(law: PiecewiseLinearLaw, mode: str, free: np.ndarray, segment_deg, where: str):
    """Columns B of allowed changes δ = B p, whether to measure p with the mass matrix, the touched vertices."""
    from scipy import sparse

    n = len(law.x)
    if mode in ("min-change", "keypoints"):
        basis, idx = _node_columns(law.x, free)
        return basis, mode == "min-change", idx
    if mode == "segment":
        lo, hi = np.radians(min(segment_deg)), np.radians(max(segment_deg))
        movable = free & (law.x >= lo) & (law.x <= hi)
        if not movable.any():
            raise CamcadError(f"the segment {segment_deg[0]:g}:{segment_deg[1]:g} deg holds no vertex off the axis",
                              where or "--segment", "widen the segment or use --mode min-change")
        basis, idx = _node_columns(law.x, movable)
        return basis, True, idx
    if mode == "extrema":
        basis, idx = _extrema_columns(law, free)
        return basis, True, idx
    groups = lobe_groups(law.a, free)
    rows: list[int] = []
    cols: list[int] = []
    vals: list[float] = []
    for col, group in enumerate(groups):
        rows.extend(group)
        cols.extend([col] * len(group))
        vals.extend(list(law.a[group]))  # a lobe scales: every point moves in proportion
    return sparse.csc_matrix((vals, (rows, cols)), shape=(n, len(groups))), True, \
        unique(np.concatenate(groups)) if groups else np.array([], dtype=int)


def lobes(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """Runs of consecutive free vertices with the same sign of a.

    Parameters
    ----------
    a : ndarray
        Ordinates, mm/rad².
    free : ndarray of bool
        Vertices that may move (no unit).

    Returns
    -------
    list of ndarray of int
        Vertex indices of each run, in order (no unit).

    Examples
    --------
    >>> [r.tolist() for r in lobes(np.array([0.0, 1.0, 2.0, -1.0, 0.0]), np.array([0, 1, 1, 1, 0], bool))]
    [[1, 2], [3]]
    """
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
    """The groups of mode extrema-resample: one per lobe (see ``lobes``).

    Parameters
    ----------
    a : ndarray
        Ordinates, mm/rad².
    free : ndarray of bool
        Vertices that may move (no unit).

    Returns
    -------
    list of ndarray of int
        Vertex indices of each lobe, in order (no unit).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.balance import lobe_groups
    >>> [g.tolist() for g in lobe_groups(np.array([0.0, 1.0, 2.0, -1.0, 0.0]), np.array([0, 1, 1, 1, 0], bool))]
    [[1, 2], [3]]
    """
    return lobes(a, free)


def extremum_groups(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """The local maxima of positive lobes and minima of negative lobes; equal neighbours form one group.

    Parameters
    ----------
    a : ndarray
        Ordinates, mm/rad².
    free : ndarray of bool
        Vertices that may move (no unit).

    Returns
    -------
    list of ndarray of int
        Vertex indices of each extremum, a plateau of equal values one group (no unit).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.balance import extremum_groups
    >>> a = np.array([0.0, 1.0, 1.0, 0.5, 0.0, -2.0, 0.0])
    >>> [g.tolist() for g in extremum_groups(a, np.ones(7, bool))]
    [[1, 2], [5]]
    """
    groups = []
    for lobe in lobes(a, free):
        groups.extend(_lobe_extrema(a, lobe))
    return groups


def _lobe_extrema(a: np.ndarray, lobe: np.ndarray) -> list[np.ndarray]:
    values = np.abs(a[lobe])
    scale = values.max()
    # plateaus of equal values (within round-off) are one point for this purpose
    runs = []
    start = 0
    for i in range(1, len(lobe) + 1):
        if i == len(lobe) or abs(values[i] - values[start]) > 1e-9 * scale:
            runs.append((start, i))
            start = i
    groups = []
    for r, (r0, r1) in enumerate(runs):
        here = values[r0]
        left = values[runs[r - 1][0]] if r > 0 else -np.inf
        right = values[runs[r + 1][0]] if r + 1 < len(runs) else -np.inf
        if here >= left and here >= right:
            groups.append(lobe[r0:r1])
    return groups


# --- solving ---------------------------------------------------------------------------------------

def vertex_mode(law, mode, method, tol, step_deg, segment_deg, hold, max_iterations, where,
                 lift_targets=None):
    """Balance ``law`` by moving the vertices ``mode`` allows; with ``lift_targets`` (mm, one per rise)
    the displacement over each rise is held at that value too."""
    free = _free_vertices(law, hold)
    basis, use_mass, touched = _basis(law, mode, free, segment_deg, where)
    conds = conditions(law)
    if lift_targets is not None:
        conds = conds + lift_conditions(law, lift_targets)
    if basis.shape[1] == 0:
        raise CamcadError(f"mode {mode} finds no point it may move", where,
                          "use --mode min-change")
    if method == "exact":
        delta = least_change(law, conds, basis, use_mass, mode, where)
        # a change at round-off level (the solver's last bits where the exact change is 0) is no change:
        # the vertex is written as drawn
        delta[np.abs(delta) <= ROUND_OFF_CHANGE * float(np.max(np.abs(law.a), initial=0.0))] = 0.0
        return law.with_ordinates(law.a + delta), 1
    return iterate_moves(law, mode, conds, basis, touched, tol, step_deg, max_iterations, where)


def least_change(law: PiecewiseLinearLaw, conds: tuple[Condition, ...], basis, use_mass: bool,
                 mode: str = "min-change", where: str = "") -> np.ndarray:
    """The change δ = B p of least pᵀGp that meets every condition: C(a + δ) = targets.

    G = BᵀMB (the function norm ∫δa² dθ, M the polyline's mass matrix) or BᵀB (the sum of squared
    vertex changes). Solved through the Schur complement: p = G⁻¹Aᵀy with (A G⁻¹ Aᵀ) y = r, A = C B,
    r = targets − C a. Singular cases are solved, not refused: a column that does not change the
    function (a vertex whose segments both have zero length) stays put, and dependent conditions
    are met in the least-squares sense (the pseudo-inverse of the small Schur matrix). Conditions
    that cannot all be met raise a CamcadError that names the one that cannot be met.

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law (θ in rad, a in mm/rad²).
    conds : tuple of Condition
        The conditions to meet (targets in mm/rad and mm).
    basis : NodeBasis or scipy.sparse matrix (n_vertices, k)
        B: the shapes the change is made of (dimensionless); node columns (min-change, keypoints, segment) are
        solved as a tridiagonal system by cyclic reduction, any other basis by a sparse LU.
    use_mass : bool
        Measure the change as a function (True) or vertex by vertex (False).
    mode, where : str
        For messages.

    Returns
    -------
    ndarray
        δ, one value per vertex (mm/rad²).

    Examples
    --------
    Every vertex free (B = I), the function norm: the least change that balances the example law.

    >>> import numpy as np
    >>> from camcad.law.law import PiecewiseLinearLaw
    >>> from camcad.law.phases import detect_phases
    >>> x = np.radians([0.0, 45, 90, 135, 180, 225, 270, 315, 360])
    >>> a = np.array([0.0, 1, 0, -1, 0, -1, 0, 1.2, 0])          # the return's last lobe 20 % high, mm/rad²
    >>> law = PiecewiseLinearLaw(x, a, 2 * np.pi, detect_phases(x, a, 2 * np.pi))
    >>> import scipy.sparse
    >>> from camcad.balance import conditions, functional_rows, least_change
    >>> delta = least_change(law, conditions(law), scipy.sparse.identity(len(law.x), format="csc"), True)
    >>> residual = functional_rows(law.x, conditions(law)) @ (law.a + delta)
    >>> bool(np.max(np.abs(residual)) < 1e-12)
    True
    """
    rows = functional_rows(law.x, conds)
    goal = targets(conds)
    residual = goal - rows @ law.a
    if isinstance(basis, NodeBasis):
        p = _node_change(law, basis, rows, residual, use_mass)
    else:
        p = _sparse_change(law, basis, rows, residual, use_mass)
    delta = np.asarray(basis @ p).ravel()
    remaining = rows @ (law.a + delta) - goal
    limit = SOLVE_TOLERANCE * lift_scale(law)
    if not np.all(np.isfinite(delta)) or np.any(np.abs(remaining) > limit):
        A = basis.restrict(rows) if isinstance(basis, NodeBasis) else np.asarray((basis.T @ rows.T).T)
        _explain_unreachable(A, residual, conds, mode, where, limit, law, basis)
    return delta


def _schur(A_live: np.ndarray, residual: np.ndarray, solve) -> np.ndarray:
    """p (live columns) = G⁻¹Aᵀy with (A G⁻¹ Aᵀ) y = r; ``solve(R)`` gives G⁻¹R. The rows of A are scaled
    to a largest entry of 1 first, and the small Schur system is solved in the least-squares sense."""
    norms = np.abs(A_live).max(axis=1)
    scale_rows = np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 0.0)
    A_eq = A_live * scale_rows[:, None]
    g_inv_at = solve(np.ascontiguousarray(A_eq.T))
    y = np.linalg.lstsq(A_eq @ g_inv_at, residual * scale_rows, rcond=1e-12)[0]
    return g_inv_at @ y


def _node_change(law: PiecewiseLinearLaw, basis: NodeBasis, rows: np.ndarray, residual: np.ndarray,
                 use_mass: bool) -> np.ndarray:
    """The least change on node columns: G is tridiagonal, solved by cyclic reduction (numpy)."""
    A = basis.restrict(rows)
    diag, off = basis.gram(law.x, use_mass)
    live = diag > 1e-13 * diag.max() if len(diag) and diag.max() > 0 else np.zeros(len(diag), dtype=bool)
    p = np.zeros(basis.k)
    if not live.any():
        return p
    keep: slice | np.ndarray
    if live.all():
        keep, off_live, diag_live = slice(None), off, diag
    else:
        alive = np.flatnonzero(live)
        keep = alive
        # a dead column (both its segments of zero length) has no coupling: the live ones stay tridiagonal
        adjacent = alive[1:] == alive[:-1] + 1
        off_live = np.where(adjacent, off[alive[:-1]] if len(alive) > 1 else off[:0], 0.0)
        diag_live = diag[alive]

    def solve(right: np.ndarray) -> np.ndarray:
        found = solve_tridiagonal(off_live, diag_live, off_live, right)
        if not np.all(np.isfinite(found)):   # numerically singular: the least change along a tiny ridge
            ridge = 1e-12 * float(diag_live.mean())
            found = solve_tridiagonal(off_live, diag_live + ridge, off_live, right)
        return found

    p[keep] = _schur(A[:, keep], residual, solve)
    return p


def _sparse_change(law: PiecewiseLinearLaw, basis, rows: np.ndarray, residual: np.ndarray,
                   use_mass: bool) -> np.ndarray:
    """The least change on a general basis (a scipy sparse matrix): G = BᵀMB or BᵀB by a sparse LU."""
    from scipy import sparse
    from scipy.sparse.linalg import splu

    A = np.asarray((basis.T @ rows.T).T)  # C B, m × k
    gram = (basis.T @ mass_matrix(law.x) @ basis).tocsc() if use_mass else (basis.T @ basis).tocsc()
    diag = gram.diagonal()
    live = diag > 1e-13 * diag.max() if len(diag) and diag.max() > 0 else np.zeros(len(diag), dtype=bool)
    p = np.zeros(basis.shape[1])
    if live.any():
        g_live = gram[live][:, live].tocsc()

        def solve(right: np.ndarray) -> np.ndarray:
            try:
                return splu(g_live).solve(right)
            except RuntimeError:  # numerically singular: the least change along a tiny ridge
                ridge = 1e-12 * float(g_live.diagonal().mean())
                return splu((g_live + ridge * sparse.identity(g_live.shape[0], format="csc")).tocsc()).solve(right)

        p[live] = _schur(A[:, live], residual, solve)
    return p


def zero_law_message(mode: str, vertices: int, count: int) -> str:
    """What to say when the only balanced law a mode can reach has no motion left."""
    return (f"mode {mode} can balance this law only by removing all its motion (every acceleration zero): the "
            f"{vertices}-vertex law has too few points to move for its {count} balance conditions")


def _explain_unreachable(A, residual, conds, mode, where, limit, law, basis):
    """Raise the CamcadError that says which condition cannot be met, and what can meet it."""
    norms = np.abs(A).max(axis=1)
    biggest = max(float(norms.max()), 1e-300) if len(norms) else 1e-300
    other_modes = "use --mode min-change or keypoints (they move every point off the axis)"
    if mode == "segment":
        other_modes = "widen --segment to cover every phase that is out of balance, or use --mode min-change"
    elif mode == "min-change":
        other_modes = "check the phases (--phases) and the vertices the law may move"
    dead = [c for c, s, r in zip(conds, norms, residual) if s <= 1e-12 * biggest and abs(r) > limit]
    if dead:
        fix = "add --free-lift to let the rise change" if dead[0].is_lift else other_modes
        raise CamcadError(f"mode {mode} cannot change the {dead[0].name}: none of the points it may move acts on it",
                          where, fix)
    # which condition contradicts the others? try without each one, the lift conditions first
    order = [i for i, c in enumerate(conds) if c.is_lift] + [i for i, c in enumerate(conds) if not c.is_lift]
    for i in order:
        keep = [j for j in range(len(conds)) if j != i]
        sub, r = A[keep], residual[keep]
        solution = np.linalg.lstsq(sub, r, rcond=1e-12)[0]
        if np.all(np.abs(sub @ solution - r) <= limit):
            if conds[i].is_lift:
                balance_only = [j for j in keep if not conds[j].is_lift]
                p = np.linalg.lstsq(A[balance_only], residual[balance_only], rcond=1e-12)[0]
                moved = law.a + np.asarray(basis @ p).ravel()
                if np.all(np.abs(moved) <= 1e-9 * np.max(np.abs(law.a))):   # no motion left without the lift
                    raise CamcadError(zero_law_message(mode, len(law.x), len(balance_only)), where,
                                      "draw each lobe with more vertices")
                raise CamcadError(f"mode {mode} cannot keep the {conds[i].name} and balance the law with the points "
                                  "it may move", where, "add --free-lift to let the rise change, or use --mode "
                                  "min-change" if mode != "min-change" else "add --free-lift to let the rise change")
            raise CamcadError(f"mode {mode} cannot meet the {conds[i].name} together with the other conditions",
                              where, other_modes)
    raise CamcadError(f"mode {mode} has {np.linalg.matrix_rank(A)} independent ways to change the law "
                      f"for {len(conds)} conditions", where, other_modes)
