"""Impact of a driven lever on a limit stop, and its first rebound (Podgorny et al. 2018).

The driven lever (pivot A, arms a and b, reduced mass m at the contact point C) is pressed against a
limit plate with a preload. The model, step by step:

1. Reduced stiffness of the lever, c = 3EJ/((a + b) b²) (N/m): the tip deflection of a beam on two
   supports a apart with an overhang b loaded at its end, δ = F b² (a + b)/(3EJ).
2. Natural frequencies f_free = √(c/m)/(2π) without the stop and f_stop = √(c_on/m)/(2π) on the stop
   (the source: 297 Hz and 768 Hz computed, 268 and 700 Hz measured). On the stop the lever gains a
   support where the stop touches it (the source's Fig. 6, "the driven link on a rigid stop"): a beam
   on three supports — the pivot A, the drive B (a from A) and the stop S (s beyond B) — with the reduced
   mass at C (b beyond B). Its stiffness at C follows from the overhanging beam's influence coefficients
   f(x, u) (deflection at x per unit load at u, both beyond B, x ≤ u: [a x u/3 + x²(3u − x)/6]/(EJ);
   f(b, b) = b²(a + b)/(3EJ) is the source's c = 3EJ/((a + b)b²)) and the redundant reaction at S
   (force method): 1/c_on = f_CC − f_CS²/(f_SS + 1/k_c), k_c the stop's own contact stiffness (∞: a
   rigid stop). ``LeverBeam`` does this; with the stop at C (s = b) it is c_on = c + k_c, the stop's
   contact stiffness in parallel with the lever — the model a scene gets from ``stop_stiffness_N_per_m``
   alone (an override of the beam scheme).
3. Impulse S = J_A (ω0 − ω1)(1 + k)/l with ω1 = 0: S = J_A ω0 (1 + k)/l = m v0 (1 + k), m = J_A/l²,
   v0 = ω0 l the approach velocity of C (k: restitution, 5/9 for steel).
4. The contact lasts about half a period of the system on the stop (the issue; the source's
   recommendation after Panovko): τ = 1/(2 f_stop); mean force F = S/τ.
5. The force is a triangle rising to F over τ and back to zero over τ (impulse F τ = S) and acts
   on the one-mass model of the lever reduced to C:
       q̈ + 2n q̇ + ωc² q = Q(t)/m,   q(0) = 0, q̇(0) = v0,   n = ζ ωc,   ωc = 2π f_stop,
   solved by the Duhamel integral in closed form (``triangular_pulse_response``). The lever stays
   pressed on the stop by the preload after the contact, so it vibrates with the stiffness on the
   stop; the model holds while the rebound stays below the preload (``Impact.leaves_stop`` says when
   it does not).
   Sign convention: q > 0 towards the stop (the direction of approach); the stop pushes back, so
   Q = −triangle. The first rebound amplitude is the largest excursion away from the stop (−q)
   within the pulse and one free period after it.
6. The approach velocity comes from the law: contact happens when the nominal displacement reaches
   lift − preload (upper stop, end of the rise) or preload (lower stop, end of the return);
   v0 = |v(θc)| ω × ratio (mm/s), ratio = displacement of C per unit of the law's displacement.

Everything in the response is linear in v0, and v0 ∝ speed: the force and the rebound are
proportional to the speed (the source's 4.137 → 6.2 N and 0.07 → 0.105 mm for 280 → 420 rpm are
both the ratio 1.5). Stretching the approach phase to a phase angle t keeps the contact at the same
point of the phase and scales v0 by t0/t, so the rebound is A(t) = A(t0) t0/t exactly; its tangent
at t0 is the source's linearised cyclogram constraint a = k t + b with k = −A0/t0, b = 2A0
(the source: a = −0.003 t + 0.208 mm, t in deg), and the least phase angle for an allowed amplitude
[a] is t = t0 A0/[a].

Units: SI inside (m, s, N, kg); lengths at the interface in mm, angles in deg, speeds in rpm.
Sources: Podgorny, Maksimchuk, Kirillov, Skeeba, Obrabotka Metallov 20(1) (2018) 44–54;
Ya. G. Panovko, Fundamentals of the Applied Theory of Vibration and Impact (1990);
A. A. Yablonsky, S. S. Noreiko, Course of the Theory of Vibrations (2007) — the Duhamel integral.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from camcad.dynamics.model import rpm_to_rad_s
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, Phase

STOP_SIDES = ("upper", "lower")


# --------------------------------------------------------------------------------------------
# Formulas
# --------------------------------------------------------------------------------------------

def lever_stiffness(youngs_modulus_mpa: float, second_moment_mm4: float, arm_a_mm: float, arm_b_mm: float) -> float:
    """Reduced stiffness of the lever at its tip, c = 3EJ/((a + b) b²), N/m.

    E in MPa (N/mm²), J the second moment of the lever's section in mm⁴, a and b the arm lengths
    in mm (a between the supports, b the overhang to the contact point). E·J/mm³ is N/mm, × 1000 → N/m.
    Source: Podgorny et al. (2018), their reduced stiffness c_пр: the tip deflection of an overhanging beam.

    Parameters
    ----------
    youngs_modulus_mpa : float
        E, MPa.
    second_moment_mm4 : float
        J, the section's second moment, in mm to the fourth power (mm⁴).
    arm_a_mm, arm_b_mm : float
        a and b, mm.

    Returns
    -------
    float
        c, N/m.

    Examples
    --------
    >>> from camcad.dynamics import lever_stiffness
    >>> lever_stiffness(2.1e5, 100.0, 50.0, 100.0)         # 3 x 2.1e5 x 100 / (150 x 100²) = 42 N/mm
    42000.0
    """
    return 3.0 * youngs_modulus_mpa * second_moment_mm4 / ((arm_a_mm + arm_b_mm) * arm_b_mm**2) * 1e3


def overhang_influence(arm_a_mm: float, x_mm: float, u_mm: float) -> float:
    """EJ × the deflection at x per unit load at u of a beam on two supports a apart with an overhang (mm³).

    x and u are measured beyond the second support B (on the overhang, ≥ 0); for x ≤ u
    f = a x u/3 + x²(3u − x)/6 (the rotation at B of the span under the moment u, plus the cantilever from
    B), symmetric in x and u (Maxwell). Divide by E·J (N·mm²) for mm/N. f(b, b) = b²(a + b)/3: the tip
    compliance behind the source's c = 3EJ/((a + b)b²).

    References
    ----------
    S. P. Timoshenko, J. M. Gere, Mechanics of Materials (1972), ch. 7 (deflections by superposition, the
    overhanging beam); W. C. Young, R. G. Budynas, Roark's Formulas for Stress and Strain, 7th ed. (2002),
    Table 8.1 (simply supported beam with an end moment, cantilever with a point load).

    Examples
    --------
    >>> overhang_influence(50.0, 100.0, 100.0) == 100.0**2 * 150.0 / 3
    True
    """
    x, u = (x_mm, u_mm) if x_mm <= u_mm else (u_mm, x_mm)
    return arm_a_mm * x * u / 3.0 + x * x * (3.0 * u - x) / 6.0


@dataclass(frozen=True)
class LeverBeam:
    """The driven lever as a beam, free and on its stop (the source's Figs. 5 and 6).

    The pivot A, the drive B at ``arm_a_mm`` from A, the reduced mass at C ``arm_b_mm`` beyond B, the stop
    touching the lever at S, ``stop_arm_mm`` from A (beyond B). Free: c = 3EJ/((a + b)b²). On the stop,
    S is a third support with the stop's own contact stiffness k_c in series (∞: rigid), and by the force
    method 1/c_on = f_CC − f_CS²/(f_SS + EJ/k_c) over EJ (``overhang_influence``). With S at C and a finite
    k_c this is c + k_c: the stop in parallel with the lever.

    Parameters
    ----------
    youngs_modulus_mpa : float
        E of the lever, MPa.
    second_moment_mm4 : float
        J of its section, mm^4 (mm⁴).
    arm_a_mm : float
        a: pivot to drive, mm.
    arm_b_mm : float
        b: drive to the reduced mass C, mm.
    stop_arm_mm : float
        Pivot to the stop's contact S, mm (> a; S = C when it equals a + b).
    contact_stiffness_n_per_m : float
        The stop's own contact stiffness k_c, N/m (``math.inf``: a rigid stop, the source's Fig. 6).

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54, Figs. 5–6 and c = 3EJ/((a + b)b²);
    S. P. Timoshenko, J. M. Gere, Mechanics of Materials (1972), ch. 7 and 10 (superposition; statically
    indeterminate beams by the force method).

    Examples
    --------
    A steel lever (E 2.1·10⁵ MPa, J 62.94 mm⁴, a 50, b 100 mm): free c = 3EJ/((a + b)b²) = 26.435 N/mm; a
    rigid stop 51.03 mm beyond the drive (101.03 mm from the pivot) makes it 6.69 times stiffer:

    >>> beam = LeverBeam(2.1e5, 62.94, 50.0, 100.0, 101.03)
    >>> round(beam.free_stiffness_n_per_m), round(beam.stop_stiffness_n_per_m / beam.free_stiffness_n_per_m, 2)
    (26435, 6.69)
    >>> parallel = LeverBeam(2.1e5, 62.94, 50.0, 100.0, 150.0, contact_stiffness_n_per_m=1.5e5)
    >>> round(parallel.stop_stiffness_n_per_m - parallel.free_stiffness_n_per_m)     # c + k_c
    150000
    """

    youngs_modulus_mpa: float
    second_moment_mm4: float
    arm_a_mm: float
    arm_b_mm: float
    stop_arm_mm: float
    contact_stiffness_n_per_m: float = math.inf

    @property
    def free_stiffness_n_per_m(self) -> float:
        """c = 3EJ/((a + b)b²), N/m (``lever_stiffness``)."""
        return lever_stiffness(self.youngs_modulus_mpa, self.second_moment_mm4, self.arm_a_mm, self.arm_b_mm)

    @property
    def stop_stiffness_n_per_m(self) -> float:
        """c_on: the stiffness at C with the lever on its stop, N/m (class docstring)."""
        ej = self.youngs_modulus_mpa * self.second_moment_mm4          # N·mm²
        a, b, s = self.arm_a_mm, self.arm_b_mm, self.stop_arm_mm - self.arm_a_mm
        f_cc, f_cs, f_ss = (overhang_influence(a, b, b), overhang_influence(a, b, s), overhang_influence(a, s, s))
        series = 0.0 if math.isinf(self.contact_stiffness_n_per_m) else ej / (self.contact_stiffness_n_per_m * 1e-3)
        compliance = (f_cc - f_cs * f_cs / (f_ss + series)) / ej       # mm/N
        if not compliance > 1e-12 * f_cc / ej:
            return math.inf
        return 1e3 / compliance

    def describe(self) -> dict:
        """The inputs and the two stiffnesses (mm, MPa, mm⁴, N/m) for a report."""
        return {"youngs_modulus_MPa": self.youngs_modulus_mpa, "second_moment_mm4": self.second_moment_mm4,
                "arm_a_mm": self.arm_a_mm, "arm_b_mm": self.arm_b_mm, "stop_arm_mm": self.stop_arm_mm,
                "contact_stiffness_N_per_m": (None if math.isinf(self.contact_stiffness_n_per_m)
                                              else self.contact_stiffness_n_per_m),
                "free_stiffness_N_per_m": self.free_stiffness_n_per_m,
                "stop_stiffness_N_per_m": self.stop_stiffness_n_per_m,
                "scheme": "the lever on three supports: pivot, drive and the stop (force method)"}


def reduced_mass(lever_inertia_kg_m2: float, lever_length_mm: float) -> float:
    """Mass at the lever's end equivalent to its moment of inertia about the pivot, m = J_A/l² (kg).

    Parameters
    ----------
    lever_inertia_kg_m2 : float
        J_A, kg·m².
    lever_length_mm : float
        l, mm.

    Returns
    -------
    float
        m, kg.

    Examples
    --------
    >>> from camcad.dynamics import reduced_mass
    >>> round(reduced_mass(1.708e-4, 150.0), 12)                   # 1.708e-4 / 0.15², the source's lever
    0.007591111111
    """
    length = lever_length_mm * 1e-3
    return lever_inertia_kg_m2 / length**2


def natural_frequency_hz(stiffness_n_per_m: float, mass_kg: float) -> float:
    """f = √(c/m)/(2π), Hz."""
    return math.sqrt(stiffness_n_per_m / mass_kg) / (2.0 * math.pi)


def impact_impulse(mass_kg: float, approach_velocity_m_s: float, restitution: float) -> float:
    """S = m v0 (1 + k) = J_A ω0 (1 + k)/l, N·s (the velocity goes from v0 to −k v0).

    Source: Podgorny et al. (2018), S_C = J_A (ω1 − ω0)(1 + k)/l with ω1 = 0 (after Panovko 1990); sign dropped.

    Parameters
    ----------
    mass_kg : float
        m, the reduced mass at the contact point, kg.
    approach_velocity_m_s : float
        v0, m/s.
    restitution : float
        k, the coefficient of restitution (dimensionless; 5/9 for steel on steel in the source).

    Returns
    -------
    float
        S, N·s.

    Examples
    --------
    >>> from camcad.dynamics import impact_impulse
    >>> round(impact_impulse(0.0076, 0.5, 5 / 9), 12)         # 0.0076 x 0.5 x 14/9
    0.005911111111
    """
    return mass_kg * approach_velocity_m_s * (1.0 + restitution)


def impact_force(impulse_ns: float, pulse_s: float) -> float:
    """Mean impact force F = S/τ, N (τ the interaction time, s). Source: Podgorny et al. (2018).

    Parameters
    ----------
    impulse_ns : float
        S, N·s.
    pulse_s : float
        τ, s.

    Returns
    -------
    float
        F, N.

    Examples
    --------
    >>> from camcad.dynamics import impact_force
    >>> impact_force(0.002, 0.0005)
    4.0
    """
    return impulse_ns / pulse_s


# --------------------------------------------------------------------------------------------
# Duhamel response to a triangular pulse, closed form
# --------------------------------------------------------------------------------------------

def _free(t, q0, v0, n, k1, omega):
    """Damped free vibration from q0, v0: (q, q̇)."""
    decay = np.exp(-n * t)
    c, s = np.cos(k1 * t), np.sin(k1 * t)
    q = decay * (q0 * c + (v0 + n * q0) / k1 * s)
    qd = decay * (v0 * c - (n * v0 + omega**2 * q0) / k1 * s)
    return q, qd


def _ramp(t, n, k1, omega, mass):
    """Response (q, q̇) to a unit ramp force Q = t (N/s) applied at t = 0 from rest; zero for t < 0.

    R(t) = [t − 2n/ω² + e^{−nt}((2n/ω²) cos k1t + ((2n²/ω² − 1)/k1) sin k1t)] / (m ω²):
    the particular solution (t − 2n/ω²)/(mω²) plus the free vibration that makes R(0) = R'(0) = 0.
    """
    t = np.asarray(t, dtype=float)
    tt = np.maximum(t, 0.0)
    w2 = omega**2
    c_coef = 2.0 * n / w2
    d_coef = (2.0 * n * n / w2 - 1.0) / k1
    decay = np.exp(-n * tt)
    c, s = np.cos(k1 * tt), np.sin(k1 * tt)
    q = (tt - c_coef + decay * (c_coef * c + d_coef * s)) / (mass * w2)
    qd = (1.0 + decay * ((-n * c_coef + k1 * d_coef) * c + (-n * d_coef - k1 * c_coef) * s)) / (mass * w2)
    inside = t >= 0.0
    return np.where(inside, q, 0.0), np.where(inside, qd, 0.0)


def triangular_pulse_response(t, *, omega: float, damping_ratio: float, mass: float, peak_force: float,
                              rise_time: float, q0: float = 0.0, v0: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form Duhamel solution of q̈ + 2n q̇ + ω² q = Q(t)/m from q(0) = q0, q̇(0) = v0.

    Q is a triangle: peak_force · t/τ for 0 ≤ t ≤ τ, peak_force · (2τ − t)/τ for τ ≤ t ≤ 2τ, then 0
    (τ = rise_time). n = ζω, k1 = √(ω² − n²) (underdamped, ζ < 1).

        q = q0 e^{−nt}(cos k1t + (n/k1) sin k1t) + (v0/k1) e^{−nt} sin k1t
            + (1/(m k1)) ∫₀ᵗ Q(t1) e^{−n(t−t1)} sin k1(t − t1) dt1          (Podgorny et al. 2018, eq. 2)

    The triangle is (F/τ)[r(t) − 2r(t − τ) + r(t − 2τ)] with r the unit ramp, so the integral is
    (F/τ)[R(t) − 2R(t − τ) + R(t − 2τ)] with R from ``_ramp``. After the pulse the motion is the free
    vibration from the state at 2τ (evaluated that way to avoid cancelling large ramp terms).
    Loses relative accuracy when ω τ ≪ 1 (terms of order 1/(ωτ)² cancel).

    Parameters
    ----------
    t : array_like
        Instants, s.
    omega : float
        ω, rad/s.
    damping_ratio : float
        ζ < 1 (dimensionless).
    mass : float
        m, kg.
    peak_force : float
        F, N.
    rise_time : float
        τ, s.
    q0, v0 : float
        The start, m (1000 mm) and m/s.

    Returns
    -------
    q, qdot : ndarray
        At ``t``: m (1000 mm) and m/s.

    Examples
    --------
    Undamped, no force: the free vibration q = (v0/ω) sin ωt.

    >>> import math
    >>> from camcad.dynamics import triangular_pulse_response
    >>> q, qdot = triangular_pulse_response([math.pi / 20], omega=10.0, damping_ratio=0.0, mass=1.0, peak_force=0.0,
    ...                                     rise_time=0.01, v0=1.0)
    >>> round(float(q[0]), 12), round(float(qdot[0]), 12)
    (0.1, 0.0)
    """
    if not 0.0 <= damping_ratio < 1.0:
        raise ValueError("damping ratio must be in [0, 1)")
    t = np.asarray(t, dtype=float)
    n = damping_ratio * omega
    k1 = omega * math.sqrt(1.0 - damping_ratio**2)
    scale = peak_force / rise_time

    def during(time):
        q, qd = _free(time, q0, v0, n, k1, omega)
        for shift, weight in ((0.0, 1.0), (rise_time, -2.0), (2.0 * rise_time, 1.0)):
            rq, rqd = _ramp(time - shift, n, k1, omega, mass)
            q = q + scale * weight * rq
            qd = qd + scale * weight * rqd
        return q, qd

    end = 2.0 * rise_time
    q_end, qd_end = during(np.array(end))
    q_in, qd_in = during(np.minimum(t, end))
    q_out, qd_out = _free(np.maximum(t - end, 0.0), float(q_end), float(qd_end), n, k1, omega)
    after = t > end
    return np.where(after, q_out, q_in), np.where(after, qd_out, qd_in)


def triangular_pulse(t, peak_force: float, rise_time: float) -> np.ndarray:
    """The triangular force Q(t) of ``triangular_pulse_response`` (N).

    Parameters
    ----------
    t : array_like
        Instants, s.
    peak_force : float
        The peak, N.
    rise_time : float
        τ, s (the triangle rises over τ and falls over τ).

    Returns
    -------
    ndarray
        Q at ``t``, N.

    Examples
    --------
    >>> from camcad.dynamics import triangular_pulse
    >>> triangular_pulse([0.0, 0.5, 1.0, 1.5, 2.0, 3.0], 4.0, 1.0).tolist()
    [0.0, 2.0, 4.0, 2.0, 0.0, 0.0]
    """
    t = np.asarray(t, dtype=float)
    return peak_force * np.clip(np.minimum(t, 2.0 * rise_time - t) / rise_time, 0.0, None)


# --------------------------------------------------------------------------------------------
# The stop model
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StopModel:
    """A driven lever pressed on a limit stop: the one-mass model of its impact and first rebound.

    Reduced to the contact point C: the lever's stiffness c and the stop's contact stiffness c_s act in
    parallel on the stop, so f_free = √(c/m)/(2π) and f_stop = √((c + c_s)/m)/(2π); the contact lasts
    τ = 1/(2 f_stop); the impulse is S = m v0 (1 + k) and the mean force F = S/τ (module docstring of
    ``camcad.dynamics.impact``).

    Parameters
    ----------
    mass_kg : float
        Reduced mass at the contact point C, m = J_A/l², kg.
    stiffness_n_per_m : float
        The lever's reduced stiffness c at C, N/m (e.g. 3EJ/((a + b)b²),
        ``camcad.dynamics.impact.lever_stiffness``).
    stop_stiffness_n_per_m : float
        The contact stiffness c_s the stop adds in parallel, N/m.
    restitution : float
        Coefficient of restitution k, dimensionless (5/9 for steel in the source).
    damping_ratio : float
        ζ of the one-mass model, dimensionless.
    preload_mm : float
        The preload that holds the lever on the stop, as a deflection at C, mm.
    stop : str
        "upper" (reached at the end of a rise) or "lower" (at the end of a return).
    ratio : float
        Displacement of C per unit of the law's displacement (dimensionless; mm/rad for a law in rad).
    allowed_amplitude_mm : float, optional
        The rebound limit, mm (None: not checked).
    beam : LeverBeam, optional
        The lever as a beam on its stop, where the two stiffnesses came from (for the report); None when
        they were given.

    References
    ----------
    Yu. Podgorny, O. Maksimchuk, A. Kirillov, V. Skeeba, "Features of machine cyclogramming taking into
    account the interaction of links with stops", Obrabotka Metallov 20(1) (2018) 44–54.
    Ya. G. Panovko, Fundamentals of the Applied Theory of Vibration and Impact (1990).

    Examples
    --------
    m = 0.5 kg, c = 2·10⁵ N/m, c_s = 10⁶ N/m: by hand f_free = √(4·10⁵)/(2π) = 100.658 Hz and
    f_stop = √(2.4·10⁶)/(2π) = 246.562 Hz:

    >>> import camcad
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> round(stop.f_free_hz, 3), round(stop.f_stop_hz, 3), round(stop.pulse_s * 2 * stop.f_stop_hz, 12)
    (100.658, 246.562, 1.0)
    """

    mass_kg: float
    stiffness_n_per_m: float
    stop_stiffness_n_per_m: float
    restitution: float
    damping_ratio: float
    preload_mm: float
    stop: str = "upper"
    ratio: float = 1.0
    allowed_amplitude_mm: float | None = None
    beam: LeverBeam | None = None

    @property
    def omega_stop(self) -> float:
        """ωc = √((c + c_s)/m), rad/s: the system pressed on the stop."""
        return math.sqrt((self.stiffness_n_per_m + self.stop_stiffness_n_per_m) / self.mass_kg)

    @property
    def f_free_hz(self) -> float:
        return natural_frequency_hz(self.stiffness_n_per_m, self.mass_kg)

    @property
    def f_stop_hz(self) -> float:
        return natural_frequency_hz(self.stiffness_n_per_m + self.stop_stiffness_n_per_m, self.mass_kg)

    @property
    def pulse_s(self) -> float:
        """τ = half the period on the stop, 1/(2 f_stop) (s)."""
        return 0.5 / self.f_stop_hz


# --------------------------------------------------------------------------------------------
# Contact and approach velocity from the law
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Contact:
    """Where the follower meets the stop: the phase, the cam angle θc (rad) and v(θc) (law units per rad)."""

    phase: Phase
    theta: float
    velocity_analog: float


def find_contact(law: MotionLaw, stop: str, preload_mm: float, ratio: float = 1.0, where: str = "[stops]") -> Contact:
    """Contact with the stop: the nominal displacement reaches lift − preload (upper) or preload (lower).

    The preload is measured at the contact point C (mm); in the law's units it is preload/ratio.
    The approach phase is the rise ending at the highest displacement (upper stop) or the return
    ending at the lowest (lower stop). θc is found by brentq on s(θ) − target inside that phase.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm or rad).
    stop : str
        "upper" or "lower".
    preload_mm : float
        The preload at the contact point, mm.
    ratio : float
        Contact-point units per unit of the law (dimensionless for mm to mm).
    where : str
        Named in errors.

    Returns
    -------
    Contact
        ``phase`` the approach phase, ``theta`` θc (rad) and ``velocity_analog`` v(θc) (law units per rad).

    Raises
    ------
    CamcadError
        A preload the law never reaches.

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> import numpy as np
    >>> from camcad.dynamics import find_contact
    >>> contact = find_contact(law, "upper", 0.25)
    >>> contact.phase.kind, round(float(law.kinematics(np.array([contact.theta])).s[0]), 9)   # 20 - 0.25 mm
    ('rise', 19.75)
    """
    from scipy.optimize import brentq

    if stop not in STOP_SIDES:
        raise CamcadError(f"stop {stop!r} is not one of {', '.join(STOP_SIDES)}", where, "write stop = \"upper\"")
    kind = "rise" if stop == "upper" else "return"
    candidates = [p for p in law.phases if p.kind == kind]
    if not candidates:
        raise CamcadError(f"the law has no {kind} phase to approach the {stop} stop", where,
                          "give the law's phases (--phases) or choose the other stop")
    ends = np.array([law.kinematics(np.array([p.end])).s[0] for p in candidates])
    phase = candidates[int(np.argmax(ends) if stop == "upper" else np.argmin(ends))]
    s_start, s_end = law.kinematics(np.array([phase.start, phase.end])).s
    preload = preload_mm / ratio
    target = s_end - preload if stop == "upper" else s_end + preload
    if not (min(s_start, s_end) < target < max(s_start, s_end)):
        raise CamcadError(f"the preload {preload_mm:g} mm is not inside the {kind}'s travel "
                          f"{abs(s_end - s_start) * ratio:.4g} mm", where, "give a preload smaller than the stroke")
    theta = brentq(lambda th: float(law.kinematics(np.array([th])).s[0]) - target, phase.start, phase.end,
                   xtol=1e-14, rtol=4 * np.finfo(float).eps)
    velocity = float(law.kinematics(np.array([theta])).v[0])
    return Contact(phase, float(theta), velocity)


# --------------------------------------------------------------------------------------------
# Impact at one speed, over speeds, against the phase angle
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Impact:
    """The impact at one speed (``camcad.impact_sweep`` gives one per speed; the example is there).

    Attributes
    ----------
    rpm : float
        The cam speed, rpm.
    contact_deg : float
        The cam angle of contact, deg.
    approach_velocity_mm_s : float
        v0, the velocity at which the follower meets the stop, mm/s.
    impulse_ns : float
        S = m v0 (1 + k), N·s.
    force_n : float
        The mean force F = S/τ, N.
    pulse_s : float
        τ, the interaction time, s.
    rebound_mm : float
        The first rebound's amplitude, mm.
    rebound_at_s : float
        When it peaks after contact, s.
    preload_mm : float
        The preload, mm (inf: none).
    time : ndarray
        The response's instants after contact when kept, s.
    q_mm : ndarray
        The response q at ``time``, mm.
    """

    rpm: float
    contact_deg: float
    approach_velocity_mm_s: float
    impulse_ns: float
    force_n: float
    pulse_s: float
    rebound_mm: float
    rebound_at_s: float
    preload_mm: float = math.inf
    time: np.ndarray = field(default_factory=lambda: np.empty(0))
    q_mm: np.ndarray = field(default_factory=lambda: np.empty(0))

    @property
    def leaves_stop(self) -> bool:
        """The rebound exceeds the preload: the lever lifts off and the linear model on the stop no longer holds."""
        return self.rebound_mm > self.preload_mm


def response_after_impact(stop: StopModel, approach_velocity_m_s: float, time) -> tuple[np.ndarray, np.ndarray]:
    """The motion after contact: v0 towards the stop, the stop's triangular pulse pushing back.

    Parameters
    ----------
    stop : StopModel
        The lever and its stop (kg, N/m).
    approach_velocity_m_s : float
        v0, m/s.
    time : array_like
        The instants after contact, s.

    Returns
    -------
    q, qdot : ndarray
        The displacement (m, 1000 mm) and its rate (m/s) at ``time``.

    Examples
    --------
    >>> import camcad
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> from camcad.dynamics import response_after_impact
    >>> q, qdot = response_after_impact(stop, 0.1, [0.0])
    >>> float(q[0]), float(qdot[0])
    (0.0, 0.1)
    """
    force = impact_force(impact_impulse(stop.mass_kg, approach_velocity_m_s, stop.restitution), stop.pulse_s)
    return triangular_pulse_response(time, omega=stop.omega_stop, damping_ratio=stop.damping_ratio,
                                     mass=stop.mass_kg, peak_force=-force, rise_time=stop.pulse_s,
                                     q0=0.0, v0=approach_velocity_m_s)


def first_rebound(stop: StopModel, approach_velocity_m_s: float, samples: int = 4001) -> tuple[float, float]:
    """Largest excursion away from the stop, max(−q), within the pulse and one period after it; and its time.

    Found on ``samples`` points, then refined where q̇ changes sign (brentq on the closed-form q̇).

    Parameters
    ----------
    stop : StopModel
        The lever and its stop (kg, N/m).
    approach_velocity_m_s : float
        v0, m/s.
    samples : int
        Points of the first search (a count).

    Returns
    -------
    tuple of float
        The rebound, m (1000 mm), and when it peaks after contact, s.

    Examples
    --------
    >>> import camcad
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> from camcad.dynamics import first_rebound
    >>> rebound, at = first_rebound(stop, 0.1)
    >>> rebound > 0 and 0 < at < 1 / stop.f_free_hz
    True
    """
    from scipy.optimize import brentq

    end = 2.0 * stop.pulse_s + 2.0 * math.pi / stop.omega_stop
    time = np.linspace(0.0, end, samples)
    q, _ = response_after_impact(stop, approach_velocity_m_s, time)
    i = int(np.argmin(q))
    best_t, best_q = float(time[i]), float(q[i])
    if 0 < i < samples - 1:
        def rate(t):
            return float(response_after_impact(stop, approach_velocity_m_s, np.array([t]))[1][0])
        lo, hi = time[i - 1], time[i + 1]
        if rate(lo) < 0.0 < rate(hi):
            best_t = brentq(rate, lo, hi, xtol=1e-15)
            best_q = float(response_after_impact(stop, approach_velocity_m_s, np.array([best_t]))[0][0])
    return max(0.0, -best_q), best_t


def impact_at(law: MotionLaw, stop: StopModel, rpm: float, *, contact: Contact | None = None,
              keep_response: bool = False, samples: int = 4001) -> Impact:
    """The impact on the stop at ``rpm``: approach velocity, impulse, force, first rebound (module docstring).

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm or rad).
    stop : StopModel
        The lever and its stop (kg, N/m, mm).
    rpm : float
        The cam speed, rpm.
    contact : Contact, optional
        Where the follower meets the stop (``find_contact``; found when None).
    keep_response : bool
        Keep q(t) in the result (for plots).
    samples : int
        Points of the rebound's search (a count).

    Returns
    -------
    Impact
        v0 (mm/s), S (N·s), F (N), τ (s), the first rebound (mm) and when it peaks (s).

    Examples
    --------
    The impulse is m v0 (1 + k), and v0 = |v(θc)| ω:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> import numpy as np
    >>> from camcad.dynamics import find_contact, impact_at, rpm_to_rad_s
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> hit = impact_at(law, stop, 300.0)
    >>> contact = find_contact(law, "upper", 0.25)
    >>> v0 = abs(contact.velocity_analog) * rpm_to_rad_s(300.0)          # mm/s
    >>> round(hit.approach_velocity_mm_s / v0, 12), round(hit.impulse_ns / (0.5 * v0 * 1e-3 * (1 + 5 / 9)), 12)
    (1.0, 1.0)
    """
    contact = contact or find_contact(law, stop.stop, stop.preload_mm, stop.ratio)
    v0 = abs(contact.velocity_analog) * rpm_to_rad_s(rpm) * stop.ratio * 1e-3   # m/s
    impulse = impact_impulse(stop.mass_kg, v0, stop.restitution)
    force = impact_force(impulse, stop.pulse_s)
    rebound, at = first_rebound(stop, v0, samples)
    time = q = np.empty(0)
    if keep_response:
        time = np.linspace(0.0, 2.0 * stop.pulse_s + 3.0 * 2.0 * math.pi / stop.omega_stop, samples)
        q = response_after_impact(stop, v0, time)[0] * 1e3
    return Impact(float(rpm), float(np.degrees(contact.theta)), v0 * 1e3, impulse, force, stop.pulse_s,
                  rebound * 1e3, at, stop.preload_mm, time, q)


@dataclass(frozen=True)
class ImpactSweep:
    """Impacts over speeds, and the phase-angle relation at the fastest speed (the worst case).

    ``camcad.impact_sweep`` returns it; the example is there.

    Attributes
    ----------
    impacts : tuple of Impact
        One per speed (``speeds_rpm``, ``rebound_mm``, ``force_n`` gather their figures: rpm, mm, N).
    contact : Contact
        Where the follower meets the stop (θ in rad).
    phase_deg : float
        The approach phase's angle, deg.
    relation : ReboundRelation
        The rebound against that angle at the fastest speed (mm, deg).
    """

    impacts: tuple[Impact, ...]
    contact: Contact
    phase_deg: float
    relation: ReboundRelation

    @property
    def speeds_rpm(self) -> np.ndarray:
        return np.array([i.rpm for i in self.impacts])

    @property
    def rebound_mm(self) -> np.ndarray:
        return np.array([i.rebound_mm for i in self.impacts])

    @property
    def force_n(self) -> np.ndarray:
        return np.array([i.force_n for i in self.impacts])


@dataclass(frozen=True)
class ReboundRelation:
    """Rebound amplitude against the approach phase angle at one speed: A(t) = A0 t0/t (mm, t in deg).

    ``tangent`` gives the linearised relation a = slope·t + intercept at t0 (slope = −A0/t0,
    intercept = 2A0), the form of Podgorny et al.'s (2018) cyclogram constraint a = −0.003 t + 0.208.

    Parameters
    ----------
    amplitude_mm : float
        A0, the rebound at the nominal angle, mm.
    phase_deg : float
        t0, the nominal approach phase angle, deg.
    rpm : float
        The speed it holds at, rpm.

    Examples
    --------
    >>> from camcad.dynamics import ReboundRelation
    >>> relation = ReboundRelation(amplitude_mm=0.105, phase_deg=35.0, rpm=420.0)
    >>> [round(v, 12) for v in relation.tangent], round(relation.least_phase(0.1), 9)   # 0.105 x 35 / 0.1
    ([-0.003, 0.21], 36.75)
    """

    amplitude_mm: float
    phase_deg: float
    rpm: float

    def __call__(self, t_deg):
        return self.amplitude_mm * self.phase_deg / np.asarray(t_deg, dtype=float)

    @property
    def tangent(self) -> tuple[float, float]:
        return -self.amplitude_mm / self.phase_deg, 2.0 * self.amplitude_mm

    def fit(self, low_deg: float, high_deg: float, points: int = 201) -> tuple[float, float]:
        """Least-squares line (slope mm/deg, intercept mm) of A(t) over [low, high] deg."""
        t = np.linspace(low_deg, high_deg, points)
        slope, intercept = np.polyfit(t, self(t), 1)
        return float(slope), float(intercept)

    def least_phase(self, allowed_mm: float) -> float:
        """Least phase angle (deg) with A(t) ≤ allowed: t = t0 A0/allowed (exact for this relation)."""
        return self.amplitude_mm * self.phase_deg / allowed_mm


def impact_sweep(law: MotionLaw, stop: StopModel, speeds_rpm, *, keep=(), progress=None,
                 samples: int = 4001) -> ImpactSweep:
    """The impact on the stop at every speed, and the rebound-against-phase relation at the fastest one.

    At each speed: the contact angle θc where the law reaches the stop (lift − preload for the upper
    stop), the approach velocity v0 = |v(θc)| ω × ratio, the impulse S = m v0 (1 + k), the mean force
    F = S/τ, and the first rebound amplitude from the closed-form Duhamel response to the triangular
    force pulse. Everything is linear in v0, so force and rebound are proportional to the speed.

    Parameters
    ----------
    law : MotionLaw
        The law: θ in rad, s in mm (or rad of swing; see ``StopModel.ratio``).
    stop : StopModel
        The lever and its stop (kg, N/m, mm).
    speeds_rpm : float or sequence of float
        The cam speeds, rpm.
    keep : sequence of float
        Speeds (rpm) whose response q(t) is kept in the result (for plots).
    progress : callable, optional
        Called as progress(done, total) after each speed (counts).
    samples : int
        Time samples of the rebound search per impact (a count).

    Returns
    -------
    ImpactSweep
        ``impacts`` (one ``Impact`` per speed: ``approach_velocity_mm_s`` mm/s, ``impulse_ns`` N·s,
        ``force_n`` N, ``pulse_s`` s, ``rebound_mm`` mm, ``contact_deg`` deg), ``speeds_rpm``,
        ``force_n`` and ``rebound_mm`` arrays, ``phase_deg`` (deg) and ``relation`` A(t) = A0 t0/t
        (mm against the approach phase angle t in deg).

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54: impulse, force and the first
    rebound by the Duhamel integral; their force 4.137 → 6.2 N and rebound 0.07 → 0.105 mm from 280 to
    420 rpm are both the speed ratio 1.5.

    Examples
    --------
    The source's speeds: force and rebound grow by 420/280 = 1.5, and the impulse is m v0 (1 + k):

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> stop = camcad.StopModel(mass_kg=0.5, stiffness_n_per_m=2e5, stop_stiffness_n_per_m=1e6,
    ...                         restitution=5 / 9, damping_ratio=0.05, preload_mm=0.25)
    >>> sweep = camcad.impact_sweep(law, stop, [280.0, 420.0])
    >>> round(float(sweep.force_n[1] / sweep.force_n[0]), 9), round(float(sweep.rebound_mm[1] / sweep.rebound_mm[0]), 9)
    (1.5, 1.5)
    >>> first = sweep.impacts[0]
    >>> by_hand = stop.mass_kg * first.approach_velocity_mm_s * 1e-3 * (1 + stop.restitution)
    >>> round(first.impulse_ns / by_hand, 12), round(first.force_n * first.pulse_s / first.impulse_ns, 12)
    (1.0, 1.0)
    """
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    contact = find_contact(law, stop.stop, stop.preload_mm, stop.ratio)
    keep = {float(k) for k in keep}
    impacts = []
    for i, rpm in enumerate(speeds):
        impacts.append(impact_at(law, stop, rpm, contact=contact, keep_response=float(rpm) in keep,
                                 samples=samples))
        if progress:
            progress(i + 1, len(speeds))
    worst = max(impacts, key=lambda item: item.rpm)
    phase_deg = float(np.degrees(contact.phase.width))
    return ImpactSweep(tuple(impacts), contact, phase_deg, ReboundRelation(worst.rebound_mm, phase_deg, worst.rpm))


