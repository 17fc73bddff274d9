"""Hertz contact, normal force, separation and the contact-stress phase-angle limit.

References used here (never a re-run of the code under test):
- Hertz line contact in Shigley's parametrisation (diameters d1, d2):
  b = sqrt(2F/(πl) · [(1−ν1²)/E1 + (1−ν2²)/E2] / (1/d1 + 1/d2)),  p_max = 2F/(π b l)
  (J. E. Shigley, Mechanical Engineering Design, "contact stresses: cylindrical contact");
  the same physics as Johnson's E*, R′ form used by camcad.contact, written differently.
- Conforming (concave) contact: R′ = Rr |ρ| / (|ρ| − Rr).
- Flat-faced translating follower: profile radius of curvature ρ = Rb + s + a (Norton).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from camcad import contact
from camcad.contact import ContactParams
from camcad.cyclogram.limits import least_phase_angle
from camcad.errors import CamcadError
from camcad.law.standard import Cycloidal
from camcad.scene.sections.contact import parse_contact

STEEL_E, STEEL_NU = 2.1e5, 0.3


def shigley_cylinders(force, length, d1, d2, e1, nu1, e2, nu2):
    """(b, p_max) of two cylinders (diameters d1, d2; concave: negative) after Shigley."""
    compliance = (1 - nu1**2) / e1 + (1 - nu2**2) / e2
    b = math.sqrt(2 * force / (math.pi * length) * compliance / (1 / d1 + 1 / d2))
    return b, 2 * force / (math.pi * b * length)


@pytest.mark.reference("closed form", "Hertz line contact by hand: E* = 115384.6 MPa, R' = 10.909 mm, sigma_H = 580.2 "
                                      "MPa (Johnson 1985)")
def test_convex_point_equals_closed_form():
    # cam ρ = 40 mm convex, roller Rr = 15 mm, steel on steel, F = 1000 N over L = 10 mm.
    # Hand value: E* = 2.1e5/(2·0.91) = 115384.6 MPa, R' = 40·15/55 = 10.909 mm,
    # σ_H = sqrt(1000·115384.6/(π·10·10.909)) = 580.2 MPa.
    b_ref, p_ref = shigley_cylinders(1000.0, 10.0, 80.0, 30.0, STEEL_E, STEEL_NU, 2.0e5, 0.29)
    e_star = contact.effective_modulus(STEEL_E, STEEL_NU, 2.0e5, 0.29)
    r_eff = contact.effective_radius(40.0, 15.0)
    assert float(contact.hertz_peak_pressure(1000.0, 10.0, r_eff, e_star)) == pytest.approx(p_ref, rel=1e-12)
    assert float(contact.hertz_half_width(1000.0, 10.0, r_eff, e_star)) == pytest.approx(b_ref, rel=1e-12)
    steel = contact.hertz_line_contact(1000.0, 10.0, 40.0, 15.0, STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    assert steel == pytest.approx(580.2, abs=0.05)


@pytest.mark.reference("closed form", "conforming contact R' = 15 x 60/(60 - 15) = 20 mm, Hertz by hand")
def test_concave_point_equals_conforming_closed_form():
    # concave flank ρ = −60 mm against Rr = 15 mm: R' = 15·60/(60 − 15) = 20 mm (conforming contact)
    r_eff = float(contact.effective_radius(-60.0, 15.0))
    assert r_eff == pytest.approx(20.0, rel=1e-14)
    e_star = contact.effective_modulus(STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    b_ref, p_ref = shigley_cylinders(800.0, 12.0, -120.0, 30.0, STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    assert float(contact.hertz_peak_pressure(800.0, 12.0, r_eff, e_star)) == pytest.approx(p_ref, rel=1e-12)
    assert float(contact.hertz_half_width(800.0, 12.0, r_eff, e_star)) == pytest.approx(b_ref, rel=1e-12)
    # a concave point carries the same load at a lower stress than a convex one of the same |ρ|
    assert contact.hertz_line_contact(800, 12, -60, 15, STEEL_E, STEEL_NU, STEEL_E, STEEL_NU) < \
        contact.hertz_line_contact(800, 12, 60, 15, STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    # a concave flank tighter than the roller does not fit
    assert not bool(contact.fits(-12.0, 15.0)) and bool(contact.fits(-15.0, 15.0))


@pytest.mark.reference("closed form", "flat face: 1/R' = 1/rho (Shigley, cylinder on a plane)")
def test_flat_follower_equals_cylinder_on_plane():
    # flat face: 1/R' = 1/ρ + 0; Shigley with d2 → ∞ (1/d2 = 0)
    e_star = contact.effective_modulus(STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    r_eff = float(contact.effective_radius(35.0, np.inf))
    assert r_eff == 35.0
    compliance = 2 * (1 - STEEL_NU**2) / STEEL_E
    b_ref = math.sqrt(2 * 500.0 / (math.pi * 8.0) * compliance / (1 / 70.0))
    p_ref = 2 * 500.0 / (math.pi * b_ref * 8.0)
    assert float(contact.hertz_peak_pressure(500.0, 8.0, r_eff, e_star)) == pytest.approx(p_ref, rel=1e-12)


@pytest.mark.reference("second method", "quadrature of the elliptical Hertz pressure across the strip gives F/L")
@pytest.mark.parametrize("rho, r_f", [(40.0, 15.0), (-60.0, 15.0), (35.0, np.inf)])
def test_pressure_integrates_back_to_the_load(rho, r_f):
    # ∫_{-b}^{b} p(x) dx · L = F for the elliptical Hertz distribution (quadrature, not p0 π b L / 2)
    force, width = 1234.5, 9.0
    e_star = contact.effective_modulus(STEEL_E, STEEL_NU, 1.9e5, 0.28)
    r_eff = float(contact.effective_radius(rho, r_f))
    b = float(contact.hertz_half_width(force, width, r_eff, e_star))
    total, _ = quad(lambda x: float(contact.hertz_pressure(x, force, width, r_eff, e_star)), -b, b,
                    epsabs=0.0, epsrel=1e-12, limit=200)
    assert total * width == pytest.approx(force, rel=1e-9)
    # the distribution is zero outside the strip and peaks at σ_H on the centre line
    assert float(contact.hertz_pressure(1.0001 * b, force, width, r_eff, e_star)) == 0.0
    assert float(contact.hertz_pressure(0.0, force, width, r_eff, e_star)) == pytest.approx(
        float(contact.hertz_peak_pressure(force, width, r_eff, e_star)), rel=1e-15)


def params(**overrides) -> ContactParams:
    base = dict(cam_modulus=STEEL_E, cam_poisson=STEEL_NU, follower_modulus=STEEL_E, follower_poisson=STEEL_NU,
                width=10.0, mass=0.8, allowable_stress=900.0, spring_rate=12.0, preload=150.0, load=40.0)
    base.update(overrides)
    return ContactParams(**base)


def flat_follower_rise(beta_deg: float, lift: float = 20.0, rb: float = 40.0, points: int = 2001):
    """Arrays of a cycloidal rise of ``lift`` over β for a translating flat-faced follower."""
    beta = math.radians(beta_deg)
    u = np.linspace(0.0, 1.0, points)
    shape = Cycloidal()
    s = lift * shape.evaluate(u, 0)
    v = lift * shape.evaluate(u, 1) / beta
    a = lift * shape.evaluate(u, 2) / beta**2
    rho = rb + s + a          # flat-faced translating follower (Norton)
    return u * beta, s, v, a, np.zeros_like(u), rho


@pytest.mark.reference("closed form", "sigma_H of a flat face along the profile, computed here from the Hertz formula")
def test_profile_stress_of_flat_follower_equals_closed_form():
    theta, s, v, a, phi, rho = flat_follower_rise(100.0)
    p = params()
    result = contact.contact_stress(theta, s, v, a, phi, rho, np.inf, 300.0, p)
    omega = 2 * math.pi * 300.0 / 60
    force = 0.8 * a * omega**2 / 1000 + 12.0 * s + 150.0 + 40.0   # N, pressure angle 0
    e_star = 1 / (2 * (1 - 0.09) / STEEL_E)
    expected = np.sqrt(force * e_star / (math.pi * 10.0 * rho))
    np.testing.assert_allclose(result.sigma, expected, rtol=1e-12)
    assert result.sigma_max == pytest.approx(expected.max(), rel=1e-12)
    assert result.at == theta[int(np.argmax(expected))]
    assert result.safety_factor == pytest.approx(900.0 / expected.max(), rel=1e-12)
    assert not result.separation


@pytest.mark.reference("closed form", "Hertz stress at hand-made convex, concave and straight points at 20 deg "
                                      "pressure angle")
def test_roller_profile_with_convex_concave_and_straight_points():
    # hand-made arrays: convex, concave and straight profile points, pressure angle 20 deg
    theta = np.radians([0.0, 10.0, 20.0])
    rho = np.array([50.0, -80.0, np.inf])
    s = np.array([0.0, 5.0, 10.0])
    a = np.array([30.0, -20.0, 0.0])
    v = np.array([10.0, 10.0, 10.0])
    phi = np.radians([20.0, 20.0, 20.0])
    p = params(load=0.0)
    result = contact.contact_stress(theta, s, v, a, phi, rho, 16.0, 200.0, p)
    omega = 2 * math.pi * 200 / 60
    force = (0.8 * a * omega**2 / 1000 + 12.0 * s + 150.0) / math.cos(math.radians(20))
    r_prime = np.array([50 * 16 / 66, 80 * 16 / 64, 16.0])
    e_star = 1 / (2 * (1 - 0.09) / STEEL_E)
    np.testing.assert_allclose(result.sigma, np.sqrt(force * e_star / (math.pi * 10 * r_prime)), rtol=1e-12)
    with pytest.raises(CamcadError, match="roller does not fit"):
        contact.contact_stress(theta, s, v, a, phi, np.array([50.0, -12.0, 90.0]), 16.0, 200.0, p)


@pytest.mark.reference("property", "force balance on the follower along its path for both directions of motion and "
                                   "both signs of phi")
def test_guide_friction_satisfies_the_force_balance():
    # vector balance on the follower (x across the guide, y along the path): the cam's normal force
    # F_n (sin φ, cos φ), the guide's side reaction −F_n sin φ and its friction −μ |F_n sin φ| sgn(ṡ)
    # along y, the load −F: sum_y = 0 for both directions of motion and both signs of φ.
    rng = np.random.default_rng(3)
    phi = rng.uniform(-0.6, 0.6, 200)
    velocity = rng.choice([-1.0, 1.0], 200) * rng.uniform(0.1, 50, 200)
    force = rng.uniform(10, 2000, 200)
    mu = 0.15
    f_n = contact.normal_force(force, phi, velocity, mu)
    residual = f_n * np.cos(phi) - mu * np.abs(f_n * np.sin(phi)) * np.sign(velocity) - force
    np.testing.assert_allclose(residual, 0.0, atol=1e-9)
    with pytest.raises(CamcadError, match="jams"):
        contact.normal_force([100.0], [math.radians(80)], [1.0], 0.2)   # tan 80° > 1/0.2


@pytest.mark.reference("closed form", "n_sep = 60/(2 pi) sqrt(1000 F0 beta^2/(m 2 pi h)) for a constant-force spring "
                                      "on a cycloidal rise")
def test_separation_speed_closed_form_and_consistency():
    # a constant-force spring (k = 0, preload F0) on a cycloidal rise: the follower leaves the cam
    # where the deceleration m|a|ω² first reaches F0: |a|max = 2πh/β² (at u = 3/4, on the grid),
    # so n_sep = 60/(2π) · sqrt(1000 F0 β² / (m 2π h)).
    theta, s, v, a, phi, rho = flat_follower_rise(90.0, lift=20.0, points=2001)
    p = params(spring_rate=0.0, preload=100.0, load=0.0)
    beta = math.radians(90.0)
    expected = 60 / (2 * math.pi) * math.sqrt(1000 * 100.0 * beta**2 / (0.8 * 2 * math.pi * 20.0))
    n_sep = contact.separation_speed_rpm(theta, s, a, p)
    assert n_sep == pytest.approx(expected, rel=1e-12)
    # with a real spring the separation speed found in closed form agrees with the force check
    p = params()
    n_sep = contact.separation_speed_rpm(theta, s, a, p)
    below = contact.contact_stress(theta, s, v, a, phi, rho, np.inf, n_sep * (1 - 1e-6), p)
    above = contact.contact_stress(theta, s, v, a, phi, rho, np.inf, n_sep * (1 + 1e-6), p)
    assert not below.separation and above.separation
    sweep = contact.stress_versus_speed(theta, s, v, a, phi, rho, np.inf, [0.5 * n_sep, 1.5 * n_sep], p)
    assert sweep.separation.tolist() == [False, True] and sweep.separation_rpm == n_sep
    # a form-closed cam carries negative forces on its other flank: no separation, σ from |F_n|
    form = contact.contact_stress(theta, s, v, a, phi, rho, np.inf, 1.5 * n_sep,
                                  params(closure="form"))
    assert not form.separation and form.min_force < 0


@pytest.mark.reference("second method", "sigma_max(t) on a grid (monotone) and brentq: the limit reproduces [sigma_H] "
                                        "to 1e-6")
def test_phase_angle_limit_meets_the_allowable_stress():
    # σ_max(t): largest σ_H over a cycloidal rise of 20 mm stretched to t deg (flat face, Rb 40 mm,
    # 400 rpm). Below about 85 deg the flat face undercuts (ρ ≤ 0, inadmissible: inf); above, σ_max
    # falls as t grows (checked on a grid here, test only). The least admissible t is found by
    # brentq and must reproduce [σ_H] to 1e-6 relative.
    p = params(allowable_stress=250.0)

    def sigma_max(t_deg: float) -> float:
        theta, s, v, a, phi, rho = flat_follower_rise(t_deg)
        if np.any(rho <= 0):
            return math.inf     # undercut: inadmissible
        return contact.contact_stress(theta, s, v, a, phi, rho, np.inf, 400.0, p).sigma_max

    grid = np.linspace(90, 180, 10)
    values = [sigma_max(t) for t in grid]
    assert np.all(np.diff(values) < 0) and values[0] > 250.0 > values[-1]
    limit = least_phase_angle(sigma_max, 250.0, 30.0, 180.0, source="contact")
    assert limit.binding and 90.0 < limit.angle_deg < 180.0
    assert sigma_max(limit.angle_deg) == pytest.approx(250.0, rel=1e-6)
    assert sigma_max(limit.angle_deg * (1 - 1e-5)) > 250.0     # the least such angle
    assert limit.evaluations < 60                              # root finding, not a scan
    # bracket checks: a limit met at the lower end is not binding; one not met at the upper end is an error
    easy = least_phase_angle(sigma_max, 1000.0, 120.0, 180.0, source="contact")
    assert not easy.binding and easy.angle_deg == 120.0
    with pytest.raises(CamcadError, match="even the longest phase angle 180 deg"):
        least_phase_angle(sigma_max, 100.0, 90.0, 180.0, source="contact", what="operation 1->2")


@pytest.mark.reference("property", "[contact] parsed as written, its assumptions noted; bad keys refused with the "
                                   "reason")
def test_parse_contact_reads_and_rejects():
    table = {"cam_modulus": 2.1e5, "cam_poisson": 0.3, "follower_modulus": 2.1e5, "follower_poisson": 0.3,
             "width": 12.0, "mass": 0.5, "allowable_stress": 1000.0, "spring_rate": 8.0, "preload": 60.0}
    parsed = parse_contact(table, "s.toml [contact]")
    assert parsed.closure == "force" and parsed.load == 0.0
    assert any("load = 0 N" in note for note in parsed.assumed)
    with pytest.raises(CamcadError, match="did you mean 'allowable_stress'"):
        parse_contact({**table, "allowable_stres": 9.0}, "s.toml [contact]")
    missing = dict(table)
    del missing["width"]
    with pytest.raises(CamcadError, match="missing value 'width' \\(mm\\)"):
        parse_contact(missing, "s.toml [contact]")
    with pytest.raises(CamcadError, match="must be a number"):
        parse_contact({**table, "mass": "0.5 kg"}, "s.toml [contact]")
    no_spring = {k: v for k, v in table.items() if k not in ("spring_rate", "preload")}
    with pytest.raises(CamcadError, match="force-closed"):
        parse_contact(no_spring, "s.toml [contact]")
    assert parse_contact({**no_spring, "closure": "form"}, "x").spring_rate == 0.0
    ranged = parse_contact({**table, "load": 50.0, "load_range_deg": [90, 180]}, "x")
    np.testing.assert_array_equal(ranged.load_over(np.radians([45.0, 90.0, 135.0, 200.0])), [0, 50, 50, 0])
    with pytest.raises(CamcadError, match="load_range_deg"):
        parse_contact({**table, "load_range_deg": [90]}, "x")


@pytest.mark.reference("closed form", "groove walls: inner R' = 50 x 10/60, outer (conforming) R' = 70 x 10/60")
def test_groove_outer_wall_carries_negative_forces():
    # form-closed groove cam: where the cam must pull the follower back (F < 0) the roller presses on
    # the groove's outer wall, which it touches from inside (conforming): pass ρ_back = −(ρ_p + Rr).
    # Pitch radius ρ_p = 60 mm, Rr = 10 mm: inner wall ρ = 50 (R' = 50·10/60), outer wall seen from the
    # roller ρ = −70 (R' = 70·10/60).
    theta = np.radians([0.0, 1.0])
    s = np.zeros(2)
    v = np.ones(2)
    a = np.array([500.0, -500.0])
    phi = np.zeros(2)
    p = params(closure="form", spring_rate=0.0, preload=0.0, load=0.0, mass=1.0)
    result = contact.contact_stress(theta, s, v, a, phi, np.full(2, 50.0), 10.0, 300.0, p,
                                    rho_back_mm=np.full(2, -70.0))
    force = abs(1.0 * 500.0 * (2 * math.pi * 300 / 60) ** 2 / 1000)
    e_star = 1 / (2 * (1 - 0.09) / STEEL_E)
    r_prime = np.array([50 * 10 / 60, 70 * 10 / 60])
    np.testing.assert_allclose(result.sigma, np.sqrt(force * e_star / (math.pi * 10 * r_prime)), rtol=1e-12)


# ------------------------------------------------------------------ the command on the sample scene

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "scenes" / "loom_group1.toml"


@pytest.mark.reference("closed form", "Norton's pitch-curve radius and phi = atan(v/(Rp + s)) for the sample's "
                                      "cycloidal rise, Hertz on top")
def test_cli_contact_on_the_sample_matches_textbook_geometry(tmp_path, cli):
    import tomllib

    from camcad.scene.file import read_scene
    from camcad.scene.laws import mechanism_law, phases_deg
    from camcad.scene.mechanism import phase_grid, phase_stress_function

    done = cli("contact", SAMPLE, "--json", "-o", tmp_path, "--rpm", "300:420:60", "--phase-angles", "law")
    assert done.code == 0, done.err
    payload = done.json()
    for key in ("sigma_max_MPa", "at_deg", "safety_factor", "separation", "phase_limit_deg"):
        assert key in payload["contact"]
    names = ("weft_returner", "shuttle_lift", "shuttle_spring_opener", "returner_spring_opener")
    expected = {"contact.json"} | {f"contact_{n}.png" for n in names} | {f"contact_speed_{n}.png" for n in names}
    assert {p.rsplit("/", 1)[-1] for p in payload["outputs"]} == expected
    for path in payload["outputs"]:
        assert (tmp_path / path.rsplit("/", 1)[-1]).stat().st_size > 0
    mechanisms = payload["contact"]["mechanisms"]
    worst = max(mechanisms, key=lambda n: mechanisms[n]["sigma_max_MPa"])
    assert payload["contact"]["mechanism"] == worst
    assert payload["contact"]["sigma_max_MPa"] == mechanisms[worst]["sigma_max_MPa"]
    report = mechanisms["weft_returner"]

    # independent route: translating roller, e = 0 (Norton): pitch radius
    # ρ_p = ((Rp+s)² + v²)^{3/2} / ((Rp+s)² + 2v² − a(Rp+s)), profile ρ = ρ_p − Rr, φ = atan(v/(Rp+s));
    # cycloidal rise of 30 mm over 40..110 deg and return over 170..240 deg, Rb 60, Rr 12.
    scene = tomllib.loads(SAMPLE.read_text())["mechanisms"]["weft_returner"]
    parsed = read_scene(SAMPLE)
    returner_law = mechanism_law(parsed, parsed.mechanism("weft_returner")).law
    theta = phase_grid(phases_deg(returner_law), 2000)
    from camcad.law.standard import compose
    kin = compose([("dwell", 40), ("rise", 70), ("dwell", 60), ("return", 70), ("dwell", 120)], 30.0,
                  "cycloidal").kinematics(theta)
    rp = 72.0
    y = rp + kin.s
    rho_p = (y**2 + kin.v**2) ** 1.5 / (y**2 + 2 * kin.v**2 - kin.a * y)
    phi = np.arctan(kin.v / y)
    e_star = 1 / (2 * (1 - 0.09) / STEEL_E)
    worst = 0.0
    for rpm in (300.0, 360.0, 420.0):
        omega = 2 * math.pi * rpm / 60
        force = (0.9 * kin.a * omega**2 / 1000 + 6.0 * kin.s + 120.0 + 15.0) / np.cos(phi)
        r_prime = 1 / (1 / (rho_p - 12.0) + 1 / 12.0)
        worst = max(worst, float(np.max(np.sqrt(force * e_star / (math.pi * 12.0 * r_prime)))))
    assert report["sigma_max_MPa"] == pytest.approx(worst, rel=1e-9)
    assert report["safety_factor"] == pytest.approx(1100.0 / worst, rel=1e-9)
    assert report["separation"] is False

    # the weft returner's rise cannot be shortened to [σ_H]: below its limit the profile undercuts
    sigma_max = phase_stress_function(returner_law, scene["follower"], parse_contact(scene["contact"], "x"),
                                      [300.0, 360.0, 420.0], 1, "x", 2000)
    rise_limit = report["phase_limit_deg"]["rise"]
    assert sigma_max(rise_limit) < 1100.0 and sigma_max(rise_limit - 1e-8) == math.inf
    assert any("inadmissible" in note for note in report["notes"])
    # the returner spring opener's least rise angle is set by the stress: σ_max(t_min) = [σ_H] to 1e-6
    opener = tomllib.loads(SAMPLE.read_text())["mechanisms"]["returner_spring_opener"]
    opener_law = mechanism_law(parsed, parsed.mechanism("returner_spring_opener")).law
    sigma_max = phase_stress_function(opener_law, opener["follower"], parse_contact(opener["contact"], "x"),
                                      [300.0, 360.0, 420.0], 1, "x", 2000)
    rise_limit = mechanisms["returner_spring_opener"]["phase_limit_deg"]["rise"]
    assert sigma_max(rise_limit) == pytest.approx(1100.0, rel=1e-6)
    assert 1100.0 < sigma_max(rise_limit * (1 - 1e-5)) < math.inf


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_cli_contact_bad_input(tmp_path, cli):
    text = SAMPLE.read_text()
    for edit, pattern in ((("allowable_stress = 1100.0", "allowable_stres = 1100.0"),
                           "did you mean 'allowable_stress'"),
                          (("mass = 0.9", "mass = \"heavy\""), "'mass' (kg) must be a number"),
                          (('rpm = [280.0, 420.0]', 'rpm = "fast"'), "rpm 'fast' is not N")):
        scene = tmp_path / "bad.toml"
        scene.write_text(text.replace(*edit, 1))
        done = cli("contact", scene, "--json", "-o", tmp_path, "--mechanism", "weft_returner")
        assert done.code == 2 and done.out == ""
        assert done.err.startswith("camcad: error:") and pattern in done.err, done.err
        assert len(done.err.strip().splitlines()) == 1
    done = cli("contact", SAMPLE, "--mechanism", "weft_retuner")
    assert done.code == 2 and "did you mean 'weft_returner'" in done.err
