"""Three-precision-point synthesis of a four-bar function generator by Freudenstein's equation.

With the offsets φ0, ψ0 chosen, the three nodes k give three equations linear in K1, K2, K3:

    K1 cos β_k − K2 cos θ_k + K3 = cos(θ_k − β_k),   θ_k = φ0 + φ_k,  β_k = ψ0 + ψ_target(φ_k)

(Freudenstein, Trans. ASME 77 (1955) 853–861). With d = 1: a = 1/K1, c = 1/K2 and
b² = a² + c² + d² − 2 a c K3. A negative a (or c) is the same linkage with that link turned by
180°: a → −a, φ0 → φ0 + π (c → −c, ψ0 → ψ0 + π). No mechanism when b² ≤ 0, and none usable when
the three nodes fall on different assembly branches.

When φ0 and ψ0 are not given, camcad scans them on a 5° grid and keeps the admissible mechanism
(limits met, one branch) of least maximum error on 21 points; every closed-form solve counts its 3
positions and every error check its 21 (camcad's choice; the closed form itself has no rule for
the offsets).
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.fgen import FunctionGenerator, Limits, Work, structural_error
from camcad.linkage.fourbar import branch_of, output_angle
from camcad.linkage.target import Target

SCAN_STEP_DEG = 5.0
SCAN_POINTS = 21


def three_point(target: Target, nodes_phi, phi0: float, psi0: float, work: Work | None = None
                ) -> FunctionGenerator | None:
    """The four-bar (d = 1) through the three nodes with offsets φ0, ψ0 (rad), or None.

    Returns None when the system is singular, b² ≤ 0, or the nodes lie on different branches.

    Examples
    --------
    A target made by a known four-bar (a=0.4, b=1.1, c=0.8, d=1) is reproduced exactly:

    >>> from camcad.linkage.target import make_target
    >>> from camcad.linkage.fourbar import output_angle
    >>> t0, beta0 = 1.2, output_angle(0.4, 1.1, 0.8, 1.0, 1.2, 1)
    >>> f = lambda x: output_angle(0.4, 1.1, 0.8, 1.0, t0 + x, 1) - beta0
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> fg = three_point(t, [0.1, 0.5, 0.9], t0, beta0)
    >>> [round(v, 9) for v in fg.links()]
    [0.4, 1.1, 0.8, 1.0]
    """
    phi = np.asarray(nodes_phi, dtype=float)
    if work is not None:
        work.positions += len(phi)
    theta = phi0 + phi
    beta = psi0 + target.psi(phi)
    matrix = np.column_stack([np.cos(beta), -np.cos(theta), np.ones(3)])
    if abs(np.linalg.det(matrix)) < 1e-12:
        return None
    k1, k2, k3 = np.linalg.solve(matrix, np.cos(theta - beta))
    if k1 == 0 or k2 == 0:
        return None
    a, c, d = 1.0 / k1, 1.0 / k2, 1.0
    b2 = a * a + c * c + d * d - 2.0 * a * c * k3
    if b2 <= 0:
        return None
    if a < 0:
        a, phi0 = -a, phi0 + math.pi
    if c < 0:
        c, psi0 = -c, psi0 + math.pi
    b = math.sqrt(b2)
    theta = phi0 + phi
    beta = psi0 + target.psi(phi)
    sigma = branch_of(a, d, float(theta[0]), (d + c * math.cos(beta[0]), c * math.sin(beta[0])))
    got = output_angle(a, b, c, d, theta, sigma)
    if not np.all(np.isfinite(got)) or np.max(np.abs(np.angle(np.exp(1j * (got - beta))))) > 1e-6:
        return None
    return FunctionGenerator(float(a), b, float(c), d, float(np.remainder(phi0, 2 * math.pi)),
                             float(np.remainder(psi0, 2 * math.pi)), sigma)


def precision_synthesis(target: Target, nodes_phi, limits: Limits, work: Work, phi0_deg: float | None = None,
                        psi0_deg: float | None = None) -> FunctionGenerator:
    """Three-point synthesis with given offsets (deg), or with the offsets scanned (module docstring).

    Raises
    ------
    CamcadError
        When no admissible mechanism exists for the given (or any scanned) offsets.

    Examples
    --------
    >>> from camcad.linkage.fgen import nodes
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> w = Work()
    >>> fg = precision_synthesis(t, nodes(3, t.dphi), Limits(), w, 45.0, 135.0)
    >>> w.positions, float(np.max(np.abs(structural_error(fg, t, nodes(3, t.dphi))))) < 1e-12
    (3, True)
    """
    if (phi0_deg is None) != (psi0_deg is None):
        raise CamcadError("give both offsets or neither", "--phi0/--psi0",
                          "add the missing one, or drop both to let camcad scan them")
    check = np.linspace(0.0, target.dphi, SCAN_POINTS)
    if phi0_deg is not None:
        fg = three_point(target, nodes_phi, math.radians(phi0_deg), math.radians(cast(float, psi0_deg)), work)
        if fg is None:
            raise CamcadError(f"no four-bar passes the three nodes with phi0 = {phi0_deg:g} deg and psi0 = "
                              f"{psi0_deg:g} deg (b^2 <= 0, singular, or the nodes on different branches)",
                              "--phi0/--psi0", "try other offsets, or drop them to let camcad scan")
        return fg
    best, best_err = None, math.inf
    grid = np.radians(np.arange(0.0, 360.0, SCAN_STEP_DEG))
    for phi0 in grid:
        for psi0 in grid:
            fg = three_point(target, nodes_phi, float(phi0), float(psi0), work)
            if fg is None or limits.ratio_margin(fg) < 0 or limits.mu_margin(fg, target, work) < 0:
                continue
            err = structural_error(fg, target, check, work)
            worst = float(np.max(np.abs(err))) if np.all(np.isfinite(err)) else math.inf
            if worst < best_err:
                best, best_err = fg, worst
    if best is None:
        raise CamcadError("no three-point four-bar meets the limits for any offsets on the 5 deg grid",
                          "--method precision", "loosen --mu-min or --ratio-max, or use --method q")
    return best
