"""The balance conditions of a drawn law as linear functionals of its ordinates (seed 003, eqs. 1–3).

v = 0 at the end of every rise and return, s(cycle) = s(0); each is a row of C with C a = residuals,
computed exactly from the piecewise-linear shape functions; M is the polyline's mass matrix.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.law.law import PiecewiseLinearLaw


MODES = ("min-change", "extrema", "extrema-resample", "keypoints", "segment", "phase", "phase-keypoints")
METHODS = ("exact", "iterate")
DEFAULT_TOL = 1e-5       # of the rise displacement
DEFAULT_STEP_DEG = 0.1   # the source's resampling step
DEFAULT_MAX_STRETCH = 0.05


# ---------------------------------------------------------------------------------------------
# Conditions
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Condition:
    """One balance condition: ``quantity`` ("v" or "s") must be zero at ``theta`` (rad)."""

    name: str
    quantity: str
    theta: float
    phase_index: int | None = None


def conditions(law: PiecewiseLinearLaw) -> tuple[Condition, ...]:
    """v = 0 at the end of every rise and return; s(cycle) = s(0) at the end of the cycle."""
    found = []
    for index, phase in enumerate(law.phases):
        if phase.kind in ("rise", "return"):
            found.append(Condition(f"velocity at the end of the {phase.kind} "
                                   f"({np.degrees(phase.end):.6g} deg)", "v", phase.end, index))
    found.append(Condition("displacement closure (rise = -return)", "s", law.cycle))
    return tuple(found)


def functional_rows(x: np.ndarray, conds: tuple[Condition, ...]) -> np.ndarray:
    """Matrix C: row i gives v(θ_i) or s(θ_i) as Σ_k C_ik a_k for the polyline on knots x, exactly.

    On a segment of length L starting at x_k with D = θc − x_k (for the part before θc):
        ∫ a dθ            → a_k L/2,            a_{k+1} L/2
        ∫ (θc − τ) a dτ   → a_k L(D/2 − L/6),   a_{k+1} L(D/2 − L/3)
    A segment cut by θc is treated as a shorter segment whose end value interpolates a_k, a_{k+1}.
    """
    n = len(x)
    rows = np.zeros((len(conds), n))
    lengths = np.diff(x)
    for row, cond in zip(rows, conds):
        tc = cond.theta
        full = np.flatnonzero(x[1:] <= tc)  # segments entirely before tc
        length = lengths[full]
        if cond.quantity == "v":
            np.add.at(row, full, length / 2.0)
            np.add.at(row, full + 1, length / 2.0)
        else:
            d = tc - x[full]
            np.add.at(row, full, length * (d / 2.0 - length / 6.0))
            np.add.at(row, full + 1, length * (d / 2.0 - length / 3.0))
        k = int(np.searchsorted(x, tc, side="right")) - 1
        if 0 <= k < n - 1 and x[k] < tc < x[k + 1]:
            seg = x[k + 1] - x[k]
            part = tc - x[k]
            t = part / seg
            if cond.quantity == "v":
                w_start, w_end = part / 2.0, part / 2.0
            else:
                w_start, w_end = part * (part / 2.0 - part / 6.0), part * (part / 2.0 - part / 3.0)
            row[k] += w_start + w_end * (1.0 - t)
            row[k + 1] += w_end * t
    return rows


def mass_matrix(x: np.ndarray):
    """Sparse M with ∫ (Σ δ_k φ_k)² dθ = δᵀ M δ for the hat functions φ_k of the knots x (rad)."""
    from scipy import sparse

    length = np.diff(x)
    n = len(x)
    diag = np.zeros(n)
    diag[:-1] += length / 3.0
    diag[1:] += length / 3.0
    off = length / 6.0
    return sparse.diags([off, diag, off], [-1, 0, 1], format="csc")




