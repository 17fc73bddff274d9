"""``camcad synth``: laws of a given tachogram from the harmonic database (issue 26, item 2).

References: the exact patterns of the cycloidal shape against their quadrature, the modified trapezoid's
pattern against scipy's adaptive quadrature of f'(u) e^{-izu} (an independent route), a drawn cycloidal law's
pattern against the closed form, and the synthesised law against the closed-form composite law sampled here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import SAMPLES
from scipy.integrate import quad

import camcad
from camcad.fourier.synth import full_database, numeric_pattern, tachogram_phases
from camcad.law.standard import SHAPES


@pytest.mark.reference("second method", "the cycloidal pattern in closed form (MotionPattern) against quadrature")
def test_quadrature_patterns_equal_the_exact_ones():
    z = np.array([0.0, 0.3, 5.0, 40.0, 400.0])
    for name in ("cycloidal", "harmonic", "poly345", "poly4567"):
        exact = full_database()[name]
        numeric = numeric_pattern(SHAPES[name])
        assert np.max(np.abs(numeric.transform(z) - exact.transform(z))) <= 1e-12
        assert numeric.moments == pytest.approx(exact.moments, abs=1e-14)


@pytest.mark.reference("second method", "scipy.integrate.quad of f'(u) cos/sin(zu) of the modified trapezoid")
def test_every_standard_shape_is_in_the_database():
    database = full_database()
    assert set(SHAPES) <= set(database)
    shape = SHAPES["modified_trapezoid"]
    for z in (0.7, 9.0, 30.0):
        real = quad(lambda u, z=z: shape.evaluate(np.array([u]), 1)[0] * math.cos(z * u), 0, 1, epsabs=1e-14,
                    points=list(shape.breakpoints()), limit=200)[0]
        imag = quad(lambda u, z=z: shape.evaluate(np.array([u]), 1)[0] * math.sin(z * u), 0, 1, epsabs=1e-14,
                    points=list(shape.breakpoints()), limit=200)[0]
        assert abs(database["modified_trapezoid"].transform(z)[0] - (real - 1j * imag)) <= 1e-12


@pytest.mark.reference("closed form", "the composite law of standard shapes (camcad.compose is exact), sampled "
                                      "here on 2^15 points")
@pytest.mark.parametrize("kind,shape,tol", [("DRTD", "harmonic", 1e-4), ("DRDTD", "modified_sine", 1e-4),
                                            ("RT", "cycloidal", 1e-5)])
def test_synth_meets_the_rms_error_with_the_least_harmonics(cli, tmp_path, kind, shape, tol):
    lift = 10.0
    angles = {"DRTD": ("--rise", "64", "--return", "64", "--start", "100"),
              "DRDTD": ("--rise", "90", "--return", "100", "--start", "40", "--far-dwell", "60"),
              "RT": ("--rise", "180", "--return", "180")}[kind]
    run = cli("synth", "--lift", lift, "--tachogram", kind, *angles, "--shape", shape, "--tol", tol * lift,
              "--dwell-tol", 1.0, "-o", tmp_path / "out", "--no-plots", "--json")
    assert run.code == 0, run.err
    data = run.json()["synth"]
    n = data["harmonics"]
    widths = {"DRTD": [("dwell", 100), ("rise", 64), ("return", 64), ("dwell", 132)],
              "DRDTD": [("dwell", 40), ("rise", 90), ("dwell", 60), ("return", 100), ("dwell", 70)],
              "RT": [("rise", 180), ("return", 180)]}[kind]
    exact = camcad.compose(widths, lift, shape)
    theta = np.arange(1 << 15) * (2 * math.pi / (1 << 15))
    s = exact.kinematics(theta).s
    spectrum = camcad.fourier.analyse(exact, n + 1)

    def rms(count):
        return float(np.sqrt(np.mean((spectrum.truncated(count).kinematics(theta).s - s) ** 2)))

    assert rms(n) <= tol * lift < rms(n - 1)
    assert [r["amplitude_mm"] for r in data["series"]] == pytest.approx(list(spectrum.amplitudes[:n]), rel=1e-8)


@pytest.mark.reference("property", "the written law checks (exit 0) and carries the phases it was synthesised with")
def test_the_synthesised_law_reads_back_with_its_phases(cli, tmp_path):
    run = cli("synth", "--lift", 0.421, "--unit", "rad", "--tachogram", "DRTD", "--rise", 64, "--return", 64,
              "--start", 100, "--shape", "harmonic", "--tol", 4e-5, "-o", tmp_path / "out", "--json")
    assert run.code == 0, run.err
    for name in ("synth.dxf", "synth.csv"):
        checked = cli("check", tmp_path / "out" / name, "--json")
        assert checked.code == 0, checked.out[-300:]
        phases = ",".join(f"{p['start_deg']:g}:{p['end_deg']:g}:{p['kind']}" for p in checked.json()["phases"])
        assert phases == "0:100:dwell,100:164:rise,164:228:return,228:360:dwell"
    assert (tmp_path / "out" / "patterns.csv").read_text().startswith("shape,z,magnitude,phase_deg")
    assert (tmp_path / "out" / "synth.png").exists()


@pytest.mark.reference("closed form", "a drawn cycloidal law's rise has the cycloidal pattern (to the drawing's "
                                      "chord error)")
def test_a_drawn_law_joins_the_database(cli, tmp_path):
    law = camcad.load_law(SAMPLES / "dxf" / "balanced_drdr_cycloidal.dxf")
    from camcad.fourier.synth import drawn_shapes, shape_pattern

    shapes = drawn_shapes(law.law, "drawn")
    pattern = shape_pattern(shapes["drawn_rise"])
    z = np.array([0.5, 3.0, 12.0])
    exact = full_database()["cycloidal"].transform(z)
    assert np.max(np.abs(pattern.transform(z) - exact)) <= 2e-3
    run = cli("synth", "--lift", 20, "--tachogram", "DRTD", "--rise", 90, "--return", 90, "--start", 60,
              "--shape", "drawn", "--shape-from", SAMPLES / "dxf" / "balanced_drdr_cycloidal.dxf", "--tol", 0.02,
              "--dwell-tol", 0.1, "-o", tmp_path / "out", "--json", "--no-plots")
    assert run.code == 0, run.err
    data = run.json()["synth"]
    assert data["shapes"] == {"rise": "balanced_drdr_cycloidal_rise", "return": "balanced_drdr_cycloidal_return"}
    assert data["patterns"]["balanced_drdr_cycloidal_rise"] == "quadrature"


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("args,expected", [
    (("--lift", "1", "--tachogram", "RT", "--rise", "100", "--return", "100"), "fills the cycle"),
    (("--lift", "1", "--tachogram", "XYZ", "--rise", "100", "--return", "100"), "unknown tachogram"),
    (("--lift", "1"), "no phases given"),
    (("--tachogram", "DRTD", "--rise", "100", "--return", "100"), "lift"),
    (("--lift", "1", "--tachogram", "DRTD", "--rise", "100", "--return", "100", "--shape", "drawn"),
     "--shape drawn needs"),
])
def test_what_synth_cannot_do_says_why(cli, tmp_path, args, expected):
    result = cli("synth", *args, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2 and expected in result.err and len(result.err.strip().splitlines()) == 1


@pytest.mark.reference("property", "a tachogram's phases add up to 360 deg")
def test_tachogram_phases_add_up_to_the_cycle():
    for kind in ("DRTD", "DRDTD", "RDTD"):
        phases = tachogram_phases(kind, 80.0, 90.0, start_deg=20.0, far_dwell_deg=30.0)
        assert sum(w for _, w in phases) == pytest.approx(360.0)
