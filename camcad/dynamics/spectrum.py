"""The sampled spectrum of a law's displacement for the frequency-domain response, and the closure check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, Phase

#: a law whose displacement or velocity does not return to its start within this fraction of the
#: lift (per rad for the velocity) has a break: its periodic response is meaningless. The same
#: tolerance as ``camcad check``, so every law that passes the check can be analysed.
CLOSURE_TOLERANCE = BALANCE_TOLERANCE
DEFAULT_SAMPLES = 16384
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: frequency path: a harmonic whose |D_k| = |ωn² − Ω_k² + 2iζωnΩ_k| is at most this fraction of ωn² is in
#: resonance. The exact response there is unbounded (ζ = 0) and the computed one is ruled by the round-off
#: of Ω_k (relative error ≈ 4e-16/|D_k/ωn²|, 4e-6 at this bound), so it is refused instead.
RESONANCE_DETUNING = 1e-10
#: time path: an eigenvalue λ of the monodromy matrix with |1 − λ| ≤ this × rtol is resonance. The shooting
#: solve divides by 1 − λ, and the marched monodromy carries an error of the order of rtol, so the response
#: would be ruled by integration error (measured: relative error ≈ 0.02–0.1 rtol/|1 − λ|, ≤ 1e-3 here).
RESONANCE_GAP_PER_RTOL = 100.0



# --------------------------------------------------------------------------------------------
# The law's spectrum
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LawSpectrum:
    """A law sampled at uniform points over its cycle, and the rfft of its displacement.

    ``law_spectrum`` returns it; the example is there.

    Attributes
    ----------
    cycle : float
        The law's cycle, rad.
    theta : ndarray
        The samples, rad, in [0, cycle) without the end.
    s : ndarray
        The displacement there, mm.
    a : ndarray
        The acceleration analog there, mm/rad² (exact at the samples).
    coefficients : ndarray
        S_k (mm), k = 0 … N/2, with s(θ) = Σ_k S_k e^{ikνθ} over k = −N/2 … N/2, S_{−k} = conj(S_k),
        ν = 2π/cycle (harmonic orders per rad).
    lift : float
        The law's lift, mm.
    phases : tuple of Phase
        The law's phases (rad).
    """

    cycle: float
    theta: np.ndarray
    s: np.ndarray
    a: np.ndarray
    coefficients: np.ndarray
    lift: float
    phases: tuple[Phase, ...] = ()

    @property
    def samples(self) -> int:
        return len(self.theta)

    @property
    def orders(self) -> np.ndarray:
        """Angular frequency of each harmonic per rad of cam angle, kν (1/rad)."""
        return 2.0 * np.pi / self.cycle * np.arange(len(self.coefficients))


def check_closure(law: MotionLaw, where: str = "law", tolerance: float = CLOSURE_TOLERANCE) -> float:
    """Lift of the law (mm); a CamcadError when s or v at the end of the cycle differ from the start.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    where : str
        Named in errors.
    tolerance : float
        A fraction of the lift (dimensionless): s may differ by that × lift (mm), v by that × lift per rad.

    Returns
    -------
    float
        The lift max(s) − min(s), mm.

    Raises
    ------
    CamcadError
        A law that does not close.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> from camcad.dynamics import check_closure
    >>> round(check_closure(law), 9)
    20.0
    """
    theta = np.linspace(0.0, law.cycle, 4097)
    kin = law.kinematics(theta)
    lift = float(kin.s.max() - kin.s.min())
    if not lift > 0:
        raise CamcadError("the law does not move (zero lift)", where, "give a law with a rise")
    gap_s = float(kin.s[-1] - kin.s[0])
    gap_v = float(kin.v[-1] - kin.v[0])
    if abs(gap_s) > tolerance * lift or abs(gap_v) > tolerance * lift:
        raise CamcadError(f"the law does not close over the cycle (s gap {gap_s:.3g} mm, v gap {gap_v:.3g} mm/rad), "
                          "so its cam has a break and no periodic motion", where,
                          "balance it first with camcad fix")
    return lift


def law_spectrum(law: MotionLaw, samples: int = DEFAULT_SAMPLES, where: str = "law") -> LawSpectrum:
    """Sample the law at ``samples`` points per cycle and take the rfft of its displacement.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm); it must close (``check_closure``).
    samples : int
        Points per cycle (a count).
    where : str
        Named in errors.

    Returns
    -------
    LawSpectrum
        The samples (rad, mm, mm/rad²) and the coefficients S_k (mm).

    Examples
    --------
    The harmonic law s = 10 − 10 cos θ: S_0 = 10 mm and S_1 = −5 mm (the cosine split over ±1):

    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.dynamics import law_spectrum
    >>> spectrum = law_spectrum(law, samples=64)
    >>> [round(complex(c).real, 9) for c in spectrum.coefficients[:3]]
    [10.0, -5.0, 0.0]
    """
    if samples < 8 or samples % 2:
        raise ValueError("samples must be an even number >= 8")
    lift = check_closure(law, where)
    theta = law.cycle * np.arange(samples) / samples
    kin = law.kinematics(theta)
    coefficients = np.fft.rfft(kin.s) / samples
    return LawSpectrum(law.cycle, theta, kin.s, kin.a, coefficients, lift, tuple(law.phases))




