"""Hertz contact stress between a cam and its follower, along the profile and against speed.

Conventions
-----------
* Effective modulus (Johnson's E*):  1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2   (MPa).
  Some texts use E' = 2E*; every formula here is written with E*.
* Effective radius R′:  1/R′ = 1/ρ + 1/r_f, where ρ is the cam profile's radius of curvature at the
  contact point (mm; convex > 0, concave < 0, a straight flank ρ = ±inf) and r_f the follower's:
  the roller radius Rr, or r_f = inf for a flat face (1/r_f = 0). A concave flank conforms to the
  roller and raises R′; when |ρ| ≤ Rr on a concave part the roller does not fit (1/R′ ≤ 0).
* Contact width L (mm): the length of the line contact (the narrower of cam and roller).
* Forces: the normal force acts along the common normal; F_n > 0 presses follower and cam together.

Sources: K. L. Johnson, Contact Mechanics (Cambridge, 1985), ch. 4 (Hertz theory, two-dimensional
contact of cylinders); R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), dynamic
force analysis of force-closed followers and cam contact stress; Podgorny et al., Obrabotka Metallov
20(1) (2018) 44–54 (σ_max(t) ≤ [σ_H] as a cyclogram constraint, Podgorny et al. 2018).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from camcad.errors import CamcadError

# --------------------------------------------------------------------------------------------
# Hertz line contact: pure formulas
# --------------------------------------------------------------------------------------------


def effective_modulus(e1_mpa: float, nu1: float, e2_mpa: float, nu2: float) -> float:
    """Effective (contact) modulus E* of two elastic bodies, MPa.

    1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2,  E1, E2 in MPa, ν1, ν2 dimensionless.

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4 (the E* of the Hertz theory).
    """
    return 1.0 / ((1.0 - nu1**2) / e1_mpa + (1.0 - nu2**2) / e2_mpa)


def effective_radius(rho_cam_mm, follower_radius_mm) -> np.ndarray:
    """Effective radius R′ of the contact of a cam profile point with the follower, mm.

    1/R′ = 1/ρ + 1/r_f. ρ: the cam profile's radius of curvature (mm; convex > 0, concave < 0,
    ±inf for a straight flank). r_f: roller radius (mm), ``np.inf`` for a flat-faced follower.
    Returns +inf where the two surfaces are both flat (1/R′ = 0) and a negative or infinite value
    where a concave flank is tighter than the roller (|ρ| ≤ r_f: the roller does not fit); callers
    check that with ``fits``.

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4 (relative curvature of two cylinders).
    """
    rho = np.asarray(rho_cam_mm, dtype=float)
    with np.errstate(divide="ignore"):
        curvature = 1.0 / rho + 1.0 / np.asarray(follower_radius_mm, dtype=float)
        return 1.0 / curvature


def hertz_half_width(force_n, width_mm: float, r_eff_mm, e_star_mpa: float) -> np.ndarray:
    """Half-width b of the Hertz contact strip of two parallel cylinders, mm.

    b = sqrt(4 F R′ / (π L E*)),  F normal force N (≥ 0), L contact width mm, R′ effective radius mm,
    E* effective modulus MPa. A non-positive force gives b = 0 (no contact).

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4, two-dimensional Hertz contact
    (a² = 4PR/(πE*) with P = F/L the load per unit length).
    """
    force = np.maximum(np.asarray(force_n, dtype=float), 0.0)
    return np.sqrt(4.0 * force * np.asarray(r_eff_mm, dtype=float) / (np.pi * width_mm * e_star_mpa))


def hertz_peak_pressure(force_n, width_mm: float, r_eff_mm, e_star_mpa: float) -> np.ndarray:
    """Peak Hertz pressure σ_H = p0 of two parallel cylinders in line contact, MPa.

    σ_H = sqrt(F E* / (π L R′)) = 2F / (π b L),  F N (≥ 0; a non-positive force gives 0),
    L mm, R′ mm (1/R′ = 1/r1 + 1/r2, a concave surface has r < 0), E* MPa.

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4 (p0 = 2P/(πa), P = F/L).
    """
    force = np.maximum(np.asarray(force_n, dtype=float), 0.0)
    with np.errstate(divide="ignore"):
        return np.sqrt(force * e_star_mpa / (np.pi * width_mm * np.asarray(r_eff_mm, dtype=float)))


def hertz_pressure(x_mm, force_n: float, width_mm: float, r_eff_mm: float, e_star_mpa: float
                   ) -> np.ndarray:
    """Hertz pressure distribution across the contact strip, MPa (elliptical).

    p(x) = p0 sqrt(1 − x²/b²) for |x| < b, 0 outside; x (mm) measured across the strip from its
    centre line; ∫ p dx · L = F (the distribution carries the load: p0 π b L / 2 = F).

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4.
    """
    x = np.asarray(x_mm, dtype=float)
    b = float(hertz_half_width(force_n, width_mm, r_eff_mm, e_star_mpa))
    p0 = float(hertz_peak_pressure(force_n, width_mm, r_eff_mm, e_star_mpa))
    if b == 0.0:
        return np.zeros_like(x)
    inside = np.clip(1.0 - (x / b) ** 2, 0.0, None)
    return p0 * np.sqrt(inside)


def hertz_line_contact(force_n: float, width_mm: float, r1_mm: float, r2_mm: float,
                       e1_mpa: float, nu1: float, e2_mpa: float, nu2: float) -> float:
    """Peak Hertz pressure of two parallel cylinders in line contact, MPa.

    sigma_H = sqrt(F E* / (pi L R')),  1/R' = 1/r1 + 1/r2 (a concave surface has r < 0, a plane
    r = inf), 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2. F N, L mm, r mm, E MPa.

    Source: K. L. Johnson, Contact Mechanics (1985), ch. 4.
    """
    e_star = effective_modulus(e1_mpa, nu1, e2_mpa, nu2)
    r_eff = effective_radius(r1_mm, r2_mm)
    return float(hertz_peak_pressure(force_n, width_mm, r_eff, e_star))


def fits(rho_cam_mm, follower_radius_mm) -> np.ndarray:
    """True where the follower can touch the profile: 1/ρ + 1/r_f ≥ 0 (a concave flank not tighter
    than the roller). Units mm; sign convention as ``effective_radius``."""
    rho = np.asarray(rho_cam_mm, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / rho + 1.0 / np.asarray(follower_radius_mm, dtype=float) >= 0.0


# --------------------------------------------------------------------------------------------
# Forces on the follower
# --------------------------------------------------------------------------------------------

def angular_speed(rpm) -> np.ndarray:
    """ω = 2πn/60, rad/s, from n in rpm."""
    return 2.0 * np.pi * np.asarray(rpm, dtype=float) / 60.0


def axial_force(s_mm, a_mm_per_rad2, rpm, mass_kg: float, spring_rate_n_per_mm: float,
                preload_n: float, load_n=0.0) -> np.ndarray:
    """Force the cam must supply along the follower's path, N (positive: follower pressed on the cam).

    F = m·a·ω²/1000 + k·s + F0 + Q,
    m kg; a mm/rad² (the law's acceleration analog, rigid or elastic), ω = 2πn/60 rad/s, so
    a·ω²/1000 is the acceleration in m/s²; k N/mm; s mm (follower displacement from its lowest
    position, where the spring force is the preload F0, N); Q N the external or technological
    load resisting the stroke (pushing the follower towards the cam), a number or an array over θ.
    ``rpm`` may be an array of shape (speeds, 1) to broadcast a speed sweep over θ.

    Source: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), dynamic force
    of a force-closed follower (F_c = m ẍ + k (x + preload) + F_ext).
    """
    omega = angular_speed(rpm)
    return (mass_kg * np.asarray(a_mm_per_rad2, dtype=float) * omega**2 / 1000.0
            + spring_rate_n_per_mm * np.asarray(s_mm, dtype=float) + preload_n
            + np.asarray(load_n, dtype=float))


def normal_force(force_axial_n, pressure_angle_rad, velocity_mm_per_rad, friction: float = 0.0
                 ) -> np.ndarray:
    """Normal contact force from the force along the follower's path, N.

    F_n = F / (cos φ − μ |sin φ| sgn(v) sgn(F)),
    F the axial force (N, ``axial_force``), φ the pressure angle (rad, angle between the contact
    normal and the follower's path), v = ds/dθ (mm/rad, its sign is the direction of motion for a
    cam turning at ω > 0), μ the friction coefficient in the follower's guide. Model: the guide
    takes the normal force's side component F_n |sin φ| and its friction μ F_n |sin φ| opposes the
    follower's sliding, so the cam must push harder on the stroke against the force (sgn(v) sgn(F)
    = +1) and less when the force drives the follower; the moment of the guide reactions (guide
    length, overhang) is neglected. In a dwell (v = 0) the friction is taken as zero. F < 0 keeps
    its sign: for a form-closed (groove) cam the other flank carries it, for a force-closed one it
    means the follower leaves the cam.

    Raises CamcadError where the denominator is ≤ 0: the follower jams in its guide
    (tan|φ| ≥ 1/μ).

    Source: the force triangle of a translating follower with guide friction, e.g. R. L. Norton,
    Design of Machinery (force analysis of cam-follower systems); with μ = 0, F_n = F / cos φ.
    """
    force = np.asarray(force_axial_n, dtype=float)
    phi = np.asarray(pressure_angle_rad, dtype=float)
    direction = np.sign(np.asarray(velocity_mm_per_rad, dtype=float)) * np.sign(force)
    denominator = np.cos(phi) - friction * np.abs(np.sin(phi)) * direction
    if np.any(denominator <= 0.0):
        worst = float(np.degrees(np.max(np.abs(phi))))
        limit = 90.0 if friction == 0.0 else float(np.degrees(np.arctan(1.0 / friction)))
        raise CamcadError(
            f"the follower jams in its guide: pressure angle up to {worst:.2f} deg with friction "
            f"{friction:g} (jamming from {limit:.2f} deg)",
            "contact", "lower the pressure angle (larger base radius) or the guide friction")
    return force / denominator


@dataclass(frozen=True)
class ContactParams:
    """Materials, loads and the allowable stress of one cam–follower pair (for ``contact_stress``).

    Parameters
    ----------
    cam_modulus : float
        Young's modulus E1 of the cam, MPa.
    cam_poisson : float
        Poisson's ratio ν1 of the cam, dimensionless.
    follower_modulus : float
        Young's modulus E2 of the roller or flat face, MPa.
    follower_poisson : float
        Poisson's ratio ν2 of the follower, dimensionless.
    width : float
        Contact width L (the length of the line contact, the narrower of cam and roller), mm.
    mass : float
        Mass reduced to the contact point along the follower's path, kg.
    allowable_stress : float
        Allowable Hertz stress [σ_H], MPa.
    closure : str
        "force" (a spring keeps the follower on the cam; F ≤ 0 is a separation) or "form" (a groove or
        conjugate cam carries both signs of the force).
    spring_rate : float
        Spring rate k of a force-closed follower, N/mm.
    preload : float
        Spring force F0 at the follower's lowest position, N.
    load : float
        External (technological) load Q resisting the stroke, N.
    load_range_deg : (float, float), optional
        Cam angles (start, end), deg, where ``load`` acts; None: the whole cycle.
    friction : float
        Friction coefficient μ in the follower's guide, dimensionless.
    roller_radius : float, optional
        Roller radius, mm, when the follower does not give it (scene files).
    assumed : tuple of str
        The quantities not given and taken as zero, for the report (no unit: names).

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge (1985), ch. 4.
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009) (dynamic force analysis).

    Examples
    --------
    Steel on steel: E* = E/(2(1 − ν²)) = 115385 MPa (Johnson's effective modulus):

    >>> import camcad
    >>> steel = camcad.ContactParams(cam_modulus=2.1e5, cam_poisson=0.3, follower_modulus=2.1e5,
    ...                              follower_poisson=0.3, width=10.0, mass=0.5, allowable_stress=1000.0,
    ...                              spring_rate=20.0, preload=200.0)
    >>> round(steel.e_star)
    115385
    """

    cam_modulus: float
    cam_poisson: float
    follower_modulus: float
    follower_poisson: float
    width: float
    mass: float
    allowable_stress: float
    closure: str = "force"
    spring_rate: float = 0.0
    preload: float = 0.0
    load: float = 0.0
    load_range_deg: tuple[float, float] | None = None
    friction: float = 0.0
    roller_radius: float | None = None
    assumed: tuple[str, ...] = ()

    @property
    def e_star(self) -> float:
        """Effective modulus E*, MPa (see ``effective_modulus``)."""
        return effective_modulus(self.cam_modulus, self.cam_poisson,
                                 self.follower_modulus, self.follower_poisson)

    def load_over(self, theta_rad) -> np.ndarray:
        """The external load (N) at each cam angle θ (rad): ``load`` inside ``load_range_deg``, else 0."""
        theta = np.asarray(theta_rad, dtype=float)
        if self.load_range_deg is None:
            return np.full_like(theta, self.load)
        start, end = np.radians(self.load_range_deg)
        angle = np.mod(theta - start, 2.0 * np.pi)
        return np.where(angle <= np.mod(end - start, 2.0 * np.pi), self.load, 0.0)

# --------------------------------------------------------------------------------------------
# Stress along the profile
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ContactResult:
    """Contact stress along the profile at one speed.

    Arrays over the sampled cam angles ``theta`` (rad): ``normal_force`` N (signed; < 0: the
    follower would leave a force-closed cam), ``sigma`` MPa (σ_H from |F_n| for a form-closed cam,
    from max(F_n, 0) for a force-closed one), ``half_width`` mm, ``r_eff`` mm.
    Figures: ``sigma_max`` MPa at ``at`` (rad), ``safety_factor`` = [σ_H]/σ_max (stress ratio;
    since σ_H ∝ √F, the load may grow by its square before σ_H reaches [σ_H]),
    ``separation`` (force-closed follower: F_n ≤ 0 somewhere), ``min_force`` N at ``min_force_at``.
    """

    theta: np.ndarray
    normal_force: np.ndarray
    sigma: np.ndarray
    half_width: np.ndarray
    r_eff: np.ndarray
    rpm: float
    allowable: float
    closure: str
    sigma_max: float
    at: float
    min_force: float
    min_force_at: float
    separation: bool
    assumed: tuple[str, ...] = field(default=())

    @property
    def safety_factor(self) -> float:
        return self.allowable / self.sigma_max if self.sigma_max > 0 else float("inf")

    @property
    def passed(self) -> bool:
        return self.sigma_max <= self.allowable and not self.separation

    def report(self) -> dict:
        """The docs/INTERFACE.md ``contact`` keys (without ``phase_limit_deg``, which needs the law) and more."""
        return {
            "passed": self.passed,
            "sigma_max_MPa": self.sigma_max,
            "at_deg": float(np.degrees(self.at)),
            "safety_factor": self.safety_factor,
            "separation": self.separation,
            "allowable_MPa": self.allowable,
            "rpm": self.rpm,
            "closure": self.closure,
            "normal_force_max_N": float(np.max(np.abs(self.normal_force))),
            "normal_force_min_N": self.min_force,
            "normal_force_min_at_deg": float(np.degrees(self.min_force_at)),
            "half_width_max_mm": float(np.max(self.half_width)),
            "assumed": list(self.assumed),
        }


def contact_stress(theta_rad, s_mm, v_mm_per_rad, a_mm_per_rad2, pressure_angle_rad, rho_profile_mm,
                   follower_radius_mm: float, rpm: float, params: ContactParams,
                   rho_back_mm=None, linkage_load=None) -> ContactResult:
    """Hertz contact stress along the profile of a cam and its follower at one speed.

    Inputs are arrays over the same cam angles θ (**rad**; the profile's ``table`` gives them), so that
    the stress can follow the rigid law or the elastic model's acceleration. The chain:
    F = m a ω²/1000 + k s + F0 + Q (``axial_force``) → F_n = F/(cos φ − μ|sin φ| sgn(vF))
    (``normal_force``) → 1/R′ = 1/ρ + 1/r_f (``effective_radius``) → σ_H = √(|F_n| E*/(π L R′)).
    For an oscillating follower pass the roller centre's path (arm × swing, mm), the mass reduced to
    the roller centre and the spring reduced there; the formulas are the same along that path.
    The maximum is the largest sampled value: its accuracy is the caller's sampling of θ.

    Parameters
    ----------
    theta_rad : array_like
        Cam angles θ, rad.
    s_mm : array_like
        Follower displacement s, mm (from its lowest position, where the spring force is the preload).
    v_mm_per_rad : array_like
        Velocity analog v = ds/dθ, mm/rad (its sign is the direction of motion).
    a_mm_per_rad2 : array_like
        Acceleration analog a = d²s/dθ², mm/rad² (rigid law, or the elastic model's).
    pressure_angle_rad : array_like
        Pressure angle φ, rad.
    rho_profile_mm : array_like
        Radius of curvature ρ of the cam profile at the contact point, mm (convex > 0, concave < 0,
        ±inf straight).
    follower_radius_mm : float
        The roller radius Rr, mm, or ``numpy.inf`` for a flat face.
    rpm : float
        Cam speed n, rpm.
    params : ContactParams
        Materials (MPa), width (mm), mass (kg), spring (N/mm, N), load (N), allowable stress (MPa).
    rho_back_mm : array_like, optional
        Form-closed cam: the radius of the surface that carries a negative force (a groove's outer
        wall, seen from the roller: −(ρ_pitch + Rr)), mm, same sign convention; without it
        ``rho_profile_mm`` is used for both signs.
    linkage_load : camcad.linkage.transfer.LinkageLoad, optional
        The working member behind a linkage, reduced to the roller's path on the same θ: F = A ω² + B (N),
        with A = J Π'(Π'ψ'' + Π''ψ'²)/L and B = Π'Q/L, added to the axial force; None (default): no linkage.

    Returns
    -------
    ContactResult
        Arrays over θ: ``normal_force`` (N, signed), ``sigma`` (MPa), ``half_width`` (mm), ``r_eff``
        (mm); figures ``sigma_max`` (MPa) at ``at`` (rad), ``safety_factor`` [σ_H]/σ_max
        (dimensionless), ``separation``, ``min_force`` (N); ``report()`` gives the docs/INTERFACE.md keys.

    Raises
    ------
    CamcadError
        A concave flank tighter than the roller (|ρ| < Rr), or a follower that jams in its guide.

    References
    ----------
    K. L. Johnson, Contact Mechanics, Cambridge (1985), ch. 4 (Hertz line contact: p0 = 2P/(πa)).
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009) (forces on a force-closed
    follower).

    Examples
    --------
    A 1000 N preload, no motion, a roller of 10 mm on a convex flank of 20 mm, steel on steel, 10 mm wide.
    By hand: R′ = 20·10/30 = 6.667 mm, E* = 115385 MPa, σ_H = √(1000·115385/(π·10·6.667)) = 742.2 MPa:

    >>> import numpy as np
    >>> import camcad
    >>> steel = camcad.ContactParams(cam_modulus=2.1e5, cam_poisson=0.3, follower_modulus=2.1e5,
    ...                              follower_poisson=0.3, width=10.0, mass=0.0, allowable_stress=1000.0,
    ...                              preload=1000.0)
    >>> zero = np.zeros(3)
    >>> still = camcad.contact_stress(zero, zero, zero, zero, zero, np.full(3, 20.0), 10.0, 300.0, steel)
    >>> round(still.sigma_max, 1), round(still.safety_factor, 4), still.passed
    (742.2, 1.3473, True)

    At a pressure angle of 30° the normal force is F/cos 30°, so σ_H grows by (cos 30°)^(−1/2):

    >>> tilted = camcad.contact_stress(zero, zero, zero + 1.0, zero, np.radians(zero + 30.0),
    ...                                np.full(3, 20.0), 10.0, 300.0, steel)
    >>> round(tilted.sigma_max / still.sigma_max, 9), round(float(np.cos(np.radians(30.0))) ** -0.5, 9)
    (1.074569932, 1.074569932)
    """
    theta = np.asarray(theta_rad, dtype=float)
    load = params.load_over(theta)
    if linkage_load is not None:  # the working member through Pi' (camcad.linkage.transfer)
        load = load + linkage_load.at(rpm)
    force_axial = axial_force(s_mm, a_mm_per_rad2, rpm, params.mass, params.spring_rate,
                              params.preload, load)
    force_n = normal_force(force_axial, pressure_angle_rad, v_mm_per_rad, params.friction)
    rho = np.asarray(rho_profile_mm, dtype=float)
    if params.closure == "form" and rho_back_mm is not None:
        rho = np.where(force_n < 0.0, np.asarray(rho_back_mm, dtype=float), rho)
    inside = fits(rho, follower_radius_mm)
    if not np.all(inside):
        index = int(np.argmin(np.where(inside, np.inf, np.abs(rho))))
        at = f"at {np.degrees(theta[index]):.2f} deg"
        if np.isinf(follower_radius_mm):
            raise CamcadError(f"the flat face meets a concave profile point (radius {rho[index]:.3f} mm) {at}",
                              "contact", "use a larger base radius or a roller follower")
        raise CamcadError(
            f"the concave profile radius {abs(rho[index]):.3f} mm {at} is smaller than the roller "
            f"radius {follower_radius_mm:g} mm: the roller does not fit (undercut)",
            "contact", "use a smaller roller or a larger base radius")
    pressing = np.abs(force_n) if params.closure == "form" else np.maximum(force_n, 0.0)
    r_eff = effective_radius(rho, follower_radius_mm)
    e_star = params.e_star
    # a flat face on a straight flank (R' = inf) spreads the load over the face: σ_H → 0 there,
    # and the strip's half-width is reported as inf (not a Hertz contact)
    sigma = hertz_peak_pressure(pressing, params.width, r_eff, e_star)
    finite = np.isfinite(r_eff)
    half_width = np.where(finite, hertz_half_width(pressing, params.width,
                                                   np.where(finite, r_eff, 0.0), e_star), np.inf)
    peak = int(np.argmax(sigma))
    weakest = int(np.argmin(force_n))
    separation = params.closure == "force" and bool(force_n[weakest] <= 0.0)
    return ContactResult(theta=theta, normal_force=force_n, sigma=sigma, half_width=half_width,
                         r_eff=r_eff, rpm=float(rpm), allowable=params.allowable_stress,
                         closure=params.closure, sigma_max=float(sigma[peak]), at=float(theta[peak]),
                         min_force=float(force_n[weakest]), min_force_at=float(theta[weakest]),
                         separation=separation, assumed=params.assumed)


@dataclass(frozen=True)
class SpeedSweep:
    """σ_max, its place, the safety factor and separation at each speed (arrays over ``rpm``)."""

    rpm: np.ndarray
    sigma_max: np.ndarray    # MPa
    at: np.ndarray           # rad
    safety_factor: np.ndarray
    separation: np.ndarray   # bool
    separation_rpm: float    # lowest speed at which a force-closed follower leaves the cam (inf: never)
    allowable: float

    @property
    def worst(self) -> int:
        """Index of the speed with the largest σ_max."""
        return int(np.argmax(self.sigma_max))

    def report(self) -> dict:
        return {"rpm": self.rpm.tolist(), "sigma_max_MPa": self.sigma_max.tolist(),
                "at_deg": np.degrees(self.at).tolist(), "safety_factor": self.safety_factor.tolist(),
                "separation": self.separation.tolist(),
                "separation_rpm": None if np.isinf(self.separation_rpm) else self.separation_rpm}


def stress_versus_speed(theta_rad, s_mm, v_mm_per_rad, a_mm_per_rad2, pressure_angle_rad,
                        rho_profile_mm, follower_radius_mm: float, rpm_values,
                        params: ContactParams, rho_back_mm=None, linkage_load=None) -> SpeedSweep:
    """``contact_stress`` at every speed of ``rpm_values`` (the source plots the safety factor
    against shaft speed), plus the lowest separation speed (``separation_speed_rpm``).
    Units as ``contact_stress``; the rigid law's analogs are used at every speed."""
    rpm_values = np.atleast_1d(np.asarray(rpm_values, dtype=float))
    results = [contact_stress(theta_rad, s_mm, v_mm_per_rad, a_mm_per_rad2, pressure_angle_rad,
                              rho_profile_mm, follower_radius_mm, rpm, params, rho_back_mm, linkage_load)
               for rpm in rpm_values]
    sigma_max = np.array([r.sigma_max for r in results])
    return SpeedSweep(
        rpm=rpm_values, sigma_max=sigma_max, at=np.array([r.at for r in results]),
        safety_factor=np.array([r.safety_factor for r in results]),
        separation=np.array([r.separation for r in results]),
        separation_rpm=separation_speed_rpm(theta_rad, s_mm, a_mm_per_rad2, params, linkage_load),
        allowable=params.allowable_stress)


def separation_speed_rpm(theta_rad, s_mm, a_mm_per_rad2, params: ContactParams, linkage_load=None) -> float:
    """Lowest shaft speed at which a force-closed follower leaves the cam, rpm (inf: never).

    The normal force has the sign of F = F_s(θ) + m a ω²/1000 with F_s = k s + F0 + Q (friction
    and the pressure angle scale it by a positive factor). Where a < 0 it vanishes at
    ω² = 1000 F_s / (m |a|), so n_sep = (60/2π) min over {a < 0} of sqrt(1000 F_s/(m|a|)); where
    F_s ≤ 0 the follower leaves even at rest (0 rpm). Units: s mm, a mm/rad², m kg, k N/mm, F N.
    Exact on the sampled θ; a form-closed cam never separates (inf).

    With a ``linkage_load`` (A ω² + B, N) F_s gains B and the ω² coefficient m a/1000 gains A.

    Source: Norton (2009), force-closed follower: the spring must exceed the negative inertia force.
    """
    if params.closure != "force":
        return float("inf")
    theta = np.asarray(theta_rad, dtype=float)
    a = np.asarray(a_mm_per_rad2, dtype=float)
    static = (params.spring_rate * np.asarray(s_mm, dtype=float) + params.preload
              + params.load_over(theta))
    if linkage_load is not None:  # the working member through Pi' (camcad.linkage.transfer)
        static = static + linkage_load.static
        if np.any(static <= 0.0):
            return 0.0
        per = params.mass * a / 1000.0 + linkage_load.per_omega2
        if not np.any(per < 0.0):
            return float("inf")
        return float(np.sqrt(np.min(static[per < 0.0] / -per[per < 0.0])) * 60.0 / (2.0 * np.pi))
    if np.any(static <= 0.0):
        return 0.0
    pulling = a < 0.0
    if params.mass == 0.0 or not np.any(pulling):
        return float("inf")
    omega2 = 1000.0 * static[pulling] / (params.mass * -a[pulling])
    return float(np.sqrt(np.min(omega2)) * 60.0 / (2.0 * np.pi))
