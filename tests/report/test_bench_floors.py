"""`camcad bench`'s floors, peers and references: independent of camcad, and right.

The floors are second implementations of camcad's kernels (numpy only), the references the closed forms and
second methods the kernel table measures errors against. Each is checked here against a closed form or a
property, and each floor against camcad's own kernel (a second method for both). No timing is asserted.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from camcad import balance, dynamics, fourier
from camcad.bench import floors, kernels, peers, references

BENCH = Path(__file__).resolve().parents[2] / "camcad" / "bench"


@pytest.mark.parametrize("module", ["floors.py", "peers.py", "references.py", "peer_mechanism.py", "timing.py"])
def test_floors_peers_and_references_import_nothing_of_camcad(module):
    tree = ast.parse((BENCH / module).read_text(encoding="utf-8"))
    names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert not [n for n in names if n.split(".")[0] == "camcad"], module


@pytest.mark.reference("closed form", "pressure angle atan(v/(Rb + Rr + s)) on a 1,000,001-point grid "
                                      "(docs/INTERFACE.md)")
def test_the_roller_cam_reference_gives_the_peak_pressure_angle_of_the_closed_form():
    # the peer's cam: cycloidal rise of 20 mm over 90 deg after a 90 deg dwell, Rb 40, Rr 10, no offset;
    # the peak of atan(v / (50 + s)) by brute force on a fine grid of the rise, s and v written out here
    cam = references.RollerCam(kernels.PEER_CAM, 20.0, 40.0, 10.0)
    beta = math.pi / 2
    u = np.linspace(0.0, 1.0, 1_000_001)
    s = 20.0 * (u - np.sin(2 * np.pi * u) / (2 * np.pi))
    v = 20.0 / beta * (1.0 - np.cos(2 * np.pi * u))
    brute = float(np.max(np.arctan(v / (50.0 + s))))
    found = cam.extremes()
    assert found["max"] == pytest.approx(brute, abs=1e-11)
    assert found["min"] == pytest.approx(-brute, abs=1e-11)   # the return mirrors the rise
    assert math.degrees(found["max_at"]) == pytest.approx(90.0 + math.degrees(beta) * float(u[np.argmax(
        np.arctan(v / (50.0 + s)))]), abs=1e-3)


@pytest.mark.reference("second method", "the floor's numpy synthesis against the closed form and camcad")
@pytest.mark.parametrize("cam, lift, rb", [(kernels.DEFAULT_CAM, 25.0, 50.0), (kernels.PEER_CAM, 20.0, 40.0)])
def test_the_profile_floor_reproduces_the_closed_form_and_camcad(cam, lift, rb):
    from camcad.profile.followers import Follower
    from camcad.profile.synth import ProfileSettings, synthesize

    floor = floors.profile_floor(cam, lift, rb, 10.0, 1e-3)
    exact = references.RollerCam(cam, lift, rb, 10.0)
    ref = exact.extremes()
    assert floor["phi_max"] == pytest.approx(ref["max"], rel=1e-10)
    assert floor["phi_min"] == pytest.approx(ref["min"], rel=1e-10)
    assert floor["rho_pitch_min"] == pytest.approx(ref["rho_pitch_min"], rel=1e-9)
    # the written chords stay within the tolerance of the exact profile (Hausdorff, measured independently)
    assert references.polyline_deviation(floor["profile"], exact.profile) <= 1e-3
    result = synthesize(kernels.camcad_law(cam, lift), Follower("roller", rb, 10.0),
                        ProfileSettings(design=False, plots=False))
    assert result.pressure_angle.maximum.value == pytest.approx(floor["phi_max"], rel=1e-10)
    assert result.rho_pitch_min.value == pytest.approx(floor["rho_pitch_min"], rel=1e-9)


@pytest.mark.reference("second method", "Simpson's rule per drawn segment; camcad's min-change")
def test_the_min_change_floor_balances_the_drawn_law_as_camcad_does():
    law = kernels.drawn_law(2_000)
    motions = [p.end for p in law.phases if p.kind in ("rise", "return")]
    dwells = [(p.start, p.end) for p in law.phases if p.kind == "dwell"]
    rise = next((p.start, p.end) for p in law.phases if p.kind == "rise")
    found = floors.min_change_floor(law.x, law.a, motions, dwells, [rise], [(p.start, p.end) for p in law.phases])
    lift = float(np.ptp(law.kinematics(np.linspace(0, 2 * np.pi, 4001)).s))
    assert references.simpson_closure(law.x, found["a"], motions, lift) < 1e-12
    fixed = balance.correct(law, "min-change")
    assert np.max(np.abs(found["a"] - fixed.law.a)) <= 1e-9 * np.max(np.abs(law.a))
    assert found["rms_change"] == pytest.approx(fixed.rms_change, rel=1e-9)


@pytest.mark.reference("closed form", "periodic response by matrix exponentials per phase")
def test_the_sweep_floor_and_camcad_match_the_matrix_exponential_solution():
    law = floors.Law([(k, w, "cycloidal") for k, w in references.SDOF_PHASES], 25.0)
    n = 4096
    theta = 2 * np.pi * np.arange(n) / n
    s, _, a, _ = law(theta)
    speeds = [300.0, 377.0]
    found = floors.sweep_floor(s, a, 2 * np.pi, 40.0, 0.05, speeds)
    from camcad.law.standard import compose

    swept = dynamics.sweep(compose(list(references.SDOF_PHASES), 25.0, "cycloidal"),
                           dynamics.ElasticFollower(40.0, 0.05), speeds, samples=n, keep=speeds)
    for row, rpm in enumerate(speeds):
        accel, _, peak = references.sdof_exact(rpm, 40.0, 0.05, 25.0)
        assert np.max(np.abs(found["accel"][row, ::n // 256] - accel)) / peak < 1e-7
        assert np.max(np.abs(swept.responses[rpm].accel_elastic[::n // 256] - accel)) / peak < 1e-7


@pytest.mark.reference("closed form", "c_k of cycloidal motions (integration of the closed form)")
def test_the_fourier_floor_and_peer_match_the_closed_form_coefficients():
    phases = kernels.FOURIER_PHASES
    law = floors.Law([(k, w, "cycloidal") for k, w in phases], 25.0)
    n = 1 << 14
    s, _, a, _ = law(2 * np.pi * np.arange(n) / n)
    exact = 2 * np.abs(references.cycloidal_coefficients(phases, 25.0, 32))
    assert np.max(np.abs(floors.fourier_floor(s, a, 32)["amplitudes"] - exact)) < 1e-12
    assert np.max(np.abs(peers.fft_adaptive(lambda t: law(t)[0], 32, 1e-13)["amplitudes"] - exact)) < 1e-12
    from camcad.law.standard import compose

    spectrum = fourier.analyse(compose(list(phases), 25.0, "cycloidal"), 32)
    assert np.max(np.abs(spectrum.amplitudes - exact)) < 1e-12


@pytest.mark.reference("property", "the trapezoid residuals of the loop's own integration close within its tolerance")
def test_the_paper_loop_closes_by_its_own_trapezoid_rule():
    law = kernels.drawn_law(2_000)
    motions = [p.end for p in law.phases if p.kind in ("rise", "return")]
    rise = next((p.start, p.end) for p in law.phases if p.kind == "rise")
    back = next((p.start, p.end) for p in law.phases if p.kind == "return")
    knobs = [((rise[0] + rise[1]) / 2, rise[1]), ((back[0] + back[1]) / 2, back[1]), back, rise]
    found = peers.paper_loop(law.x, law.a, motions, rise, knobs, step_deg=0.1, tol=1e-6)
    assert found["integrations"] < 400
    # its own judge: the trapezoid at 0.1 deg; Simpson's exact closure is off by the trapezoid's error only
    lift = found["lift"]
    assert references.simpson_closure(law.x, found["a"], motions, lift) < 1e-2


@pytest.mark.reference("property", "a table read back equals the values written (17 significant digits)")
def test_the_table_floor_and_peer_read_back_what_was_written(tmp_path):
    theta = np.linspace(0.0, 360.0, 101)
    a = np.sin(np.radians(theta))
    path = tmp_path / "t.csv"
    path.write_text("theta_deg,a\n" + "".join(f"{t!r},{v!r}\n" for t, v in zip(theta.tolist(), a.tolist())))
    assert np.array_equal(floors.table_floor(path), np.column_stack((theta, a)))
    assert np.array_equal(peers.csv_reader(path), np.column_stack((theta, a)))
