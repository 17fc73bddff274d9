"""Several cams on one elastic main shaft (camcad.dynamics.shaft) and the machine scene's [shaft].

Independent references: the modal (closed-form) solution of the linear case written here — two cams whose
laws have a constant velocity analog, so that the coupled shaft and chains are a linear system with constant
coefficients, x(t) = Σ φ_i (φ_iᵀ M x0) cos ω_i t from the eigenvectors of K φ = ω² M φ (scipy.linalg.eigh);
the single-cam case against ``camcad.dynamics.multimass.simulate`` (a second implementation, its own equations);
a second integrator (Radau, implicit) against DOP853 on the nonlinear two-cam sample; the property that the
twist falls as 1/c with the shaft's stiffness.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import camcad
from camcad.dynamics.multimass import MultiMassModel, SpeedDrive, simulate
from camcad.dynamics.shaft import ElasticShaft, ShaftCam, simulate_shaft
from camcad.errors import CamcadError

ROOT = Path(__file__).resolve().parents[2]
MACHINE = ROOT / "samples" / "scenes" / "loom_machine.toml"


class Ramp:
    """A 'law' with a constant velocity analog, s = ρ θ (mm): a screw, not a cam; it makes the model linear."""

    def __init__(self, rho: float):
        self.rho = rho

    def kinematics(self, theta):
        theta = np.asarray(theta, dtype=float)
        return SimpleNamespace(s=self.rho * theta, v=np.full_like(theta, self.rho), a=np.zeros_like(theta))


@pytest.mark.reference("closed form", "modal superposition of the linear two-cam shaft (eigh of K, M)")
def test_two_cams_on_a_linear_shaft_equal_the_modal_solution():
    rho = (20.0, 35.0)                        # mm per rad
    j = (0.02, 0.05)                          # kg m²
    m = (1.5, 3.0)                            # kg
    fn = (60.0, 45.0)                         # Hz: c2 = m (2π fn)²
    c = (4.0e3, 2.5e3)                        # N m/rad
    cams = tuple(ShaftCam(f"c{k}", Ramp(rho[k]), j[k], camcad.ElasticFollower(fn[k], 0.0, m[k])) for k in range(2))
    shaft = ElasticShaft(cams, c, 0.0)
    omega = 2 * math.pi * 200 / 60
    # coordinates relative to the rigid motion: x = (φ1 − ωt, φ2 − ωt, q1 − ρ1ωt·s, q2 − ρ2ωt·s), s = 1e-3 m/mm
    r = [1e-3 * rho[0], 1e-3 * rho[1]]
    c2 = [m[k] * (2 * math.pi * fn[k]) ** 2 for k in range(2)]
    stiff = np.zeros((4, 4))
    stiff[0, 0] = c[0] + c[1] + c2[0] * r[0] ** 2
    stiff[1, 1] = c[1] + c2[1] * r[1] ** 2
    stiff[0, 1] = stiff[1, 0] = -c[1]
    for k in range(2):
        stiff[k, 2 + k] = stiff[2 + k, k] = -c2[k] * r[k]
        stiff[2 + k, 2 + k] = c2[k]
    mass = np.diag([j[0], j[1], m[0], m[1]])
    from scipy.linalg import eigh

    w2, modes = eigh(stiff, mass)            # modes are M-orthonormal
    x0 = np.array([2e-3, -1e-3, 1e-5, -2e-5])
    period = 2 * math.pi / omega
    initial = (x0[:2], np.full(2, omega), x0[2:], np.array(r) * omega)
    found = simulate_shaft(shaft, 200.0, revolutions=0.5, keep=0.5, samples=4000, rtol=1e-12, initial=initial)
    t = found.time
    expected = (modes * (modes.T @ mass @ x0)) @ np.cos(np.sqrt(w2)[:, None] * t[None, :])
    got = np.vstack([found.phi - omega * t, found.q - np.array(r)[:, None] * omega * t])
    assert np.max(np.abs(got - expected), axis=1) == pytest.approx(np.zeros(4), abs=1e-9 * np.max(np.abs(x0)) * 1e3)
    assert period > 0


@pytest.mark.reference("second method", "camcad.dynamics.multimass.simulate with a speed drive (one cam)")
def test_one_cam_equals_the_multimass_model_with_a_speed_drive():
    law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    follower = camcad.ElasticFollower(80.0, 0.05, 1.0)
    found = simulate_shaft(ElasticShaft((ShaftCam("a", law, 0.01, follower),), (2e4,), 0.02), 300.0,
                           revolutions=1.0, samples=512, rtol=1e-11)
    model = MultiMassModel(1.0, 0.01, 2e4, 1.0, follower.mass_kg * follower.omega_n**2, 0.05, 0.02)
    other = simulate(model, law, SpeedDrive(300.0), 0.2, samples=513, rtol=1e-11)
    assert found.time == pytest.approx(other.time, abs=1e-15)
    assert np.max(np.abs(found.phi[0] - other.phi1)) < 1e-8
    assert np.max(np.abs(found.q[0] - other.q)) < 1e-9


@pytest.fixture(scope="module")
def sample_machine():
    from camcad.scene.machine import analyse_machine
    from camcad.scene.pipeline import PipelineOptions

    return analyse_machine(MACHINE, PipelineOptions(plots=()))


@pytest.mark.reference("second method", "Radau (implicit) against DOP853 on the two-cam sample")
def test_sample_shaft_by_a_second_integrator(sample_machine):
    shaft = sample_machine.shaft
    radau = simulate_shaft(shaft.shaft, shaft.rpm, revolutions=4.0, samples=512, method="Radau", rtol=1e-8)
    dop = simulate_shaft(shaft.shaft, shaft.rpm, revolutions=4.0, samples=512, method="DOP853", rtol=1e-10)
    for k in range(2):
        twist = dop.twist_deg(k)
        assert np.max(np.abs(radau.twist_deg(k) - twist)) < 2e-4 * np.max(np.abs(twist))
        error = dop.dynamic_error(k)
        assert np.max(np.abs(radau.dynamic_error(k) - error)) < 2e-4 * np.max(np.abs(error))


@pytest.mark.reference("property", "a quasi-static shaft twists as 1/c: 10x stiffer, 10x less")
def test_twist_scales_with_the_shaft_compliance(sample_machine):
    # far above the excitation (shaft modes ≫ the law's harmonics) the twist is the static one, torque/c
    shaft = sample_machine.shaft.shaft
    stiff = replace(shaft, stiffness_n_m_per_rad=tuple(100.0 * c for c in shaft.stiffness_n_m_per_rad))
    stiffer = replace(shaft, stiffness_n_m_per_rad=tuple(1000.0 * c for c in shaft.stiffness_n_m_per_rad))
    base = simulate_shaft(shaft, 420.0, revolutions=4.0, samples=512)
    hard = simulate_shaft(stiff, 420.0, revolutions=4.0, samples=512)
    harder = simulate_shaft(stiffer, 420.0, revolutions=4.0, samples=512, rtol=1e-11)
    for k in range(2):
        ratio = np.max(np.abs(harder.twist_deg(k))) / np.max(np.abs(hard.twist_deg(k)))
        assert ratio == pytest.approx(0.1, rel=0.05)
        assert np.max(np.abs(hard.twist_distortion(k))) < 0.02 * np.max(np.abs(base.twist_distortion(k)))


@pytest.mark.reference("property", "each cam on the shaft gets the machine's retimed law (rise at event 10.2); twist "
                                   "and distortion reported per cam")
def test_sample_reports_each_followers_distortion(sample_machine):
    report = sample_machine.report["shaft"]
    assert [c["mechanism"] for c in report["cams"]] == ["group2:heald", "group2:batten"]
    for cam in report["cams"]:
        assert cam["twist_max_deg"] > 0 and cam["law_distortion_max_mm"] > 0
        assert cam["dynamic_error_max_mm"] >= cam["law_distortion_max_mm"] * 0.5
    assert len(report["torsional_frequencies_hz"]) == 2
    # the law a cam gets on the shaft is the one the machine retimed: its rise starts at the machine's 10.2
    law = sample_machine.shaft.shaft.cams[0].law
    rise = next(p for p in law.phases if p.kind == "rise")
    assert math.degrees(rise.start) == pytest.approx(sample_machine.result.result.event_times_deg["10.2"], abs=1e-7)


@pytest.mark.reference("property", "no [shaft]: no shaft model, the report says the shaft is taken as rigid")
def test_the_shaft_is_modelled_only_when_the_scene_gives_it(tmp_path):
    from camcad.scene.machine import analyse_machine
    from camcad.scene.pipeline import PipelineOptions

    text = MACHINE.read_text()
    start = text.index("\n[shaft]\n")
    end = text.index("# ------------------------------------------------------------------ the machine's network")
    path = tmp_path / "m.toml"
    (tmp_path / "loom_group1.toml").write_text((MACHINE.parent / "loom_group1.toml").read_text())
    path.write_text(text[:start] + text[end:])
    found = analyse_machine(path, PipelineOptions(plots=()))
    assert found.shaft is None and "shaft" not in found.report
    assert "rigid" in found.report["skipped"]["shaft"]


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("edit, pattern", [
    (lambda s: s.replace('cams = ["group2:heald", "group2:batten"]', 'cams = ["group2:heald", "group3:batten"]'),
     "is not \"GROUP:MECHANISM\" of a group"),
    (lambda s: s.replace('cams = ["group2:heald", "group2:batten"]', 'cams = ["group2:heald", "group2:batton"]'),
     "group 'group2' has no mechanism 'batton'"),
    (lambda s: s.replace("stiffness_N_m_per_rad = [1.2e5, 8.0e4]", "stiffness_N_m_per_rad = [1.2e5]"),
     "must hold 2 positive numbers"),
    (lambda s: s.replace('cams = ["group2:heald", "group2:batten"]', 'cams = ["group2:heald", "group1:shuttle_lift"]'),
     "cam group1:shuttle_lift has no \\[dynamics\\]"),
])
def test_shaft_errors(tmp_path, edit, pattern):
    from camcad.scene.machine import analyse_machine
    from camcad.scene.pipeline import PipelineOptions

    (tmp_path / "loom_group1.toml").write_text((MACHINE.parent / "loom_group1.toml").read_text())
    path = tmp_path / "m.toml"
    path.write_text(edit(MACHINE.read_text()))
    with pytest.raises(CamcadError, match=pattern):
        analyse_machine(path, PipelineOptions(plots=()))
