"""The fast paths of issue 35 against the routes they replace or a closed form: each must give the same figures.

Tridiagonal solve (cyclic reduction) against a dense solve; the Hurwitz zeta (Euler–Maclaurin) against closed
forms and scipy; piece joining by cells against a brute-force neighbour search; one-pass phase areas against the
per-phase integrals; the table reader's numpy.loadtxt path against the careful reader; the dynamics sweep's
broadcast over speeds against the scalar path, speed by speed. No timing is asserted.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from camcad.numerics import hurwitz_zeta, solve_tridiagonal


@pytest.mark.reference("second method", "numpy.linalg.solve of the dense matrix")
@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 63, 64, 65, 127, 200, 1001, 4097])
def test_cyclic_reduction_solves_as_a_dense_solve(n):
    rng = np.random.default_rng(n)
    lower, upper = rng.uniform(-1, 1, n - 1), rng.uniform(-1, 1, n - 1)
    diag = 2.5 + rng.uniform(0, 1, n)          # diagonally dominant, as a polyline's mass matrix is
    rhs = rng.standard_normal((n, 3))
    dense = np.diag(diag) + np.diag(lower, -1) + np.diag(upper, 1)
    expected = np.linalg.solve(dense, rhs)
    assert np.max(np.abs(solve_tridiagonal(lower, diag, upper, rhs) - expected)) < 1e-12
    assert np.max(np.abs(solve_tridiagonal(lower, diag, upper, rhs[:, 0]) - expected[:, 0])) < 1e-12


@pytest.mark.reference("closed form", "zeta(2) = pi^2/6, zeta(4) = pi^4/90, zeta(s, a) - zeta(s, a + 1) = a^-s")
def test_hurwitz_zeta_closed_forms_and_scipy():
    assert hurwitz_zeta(2.0, 1.0) == pytest.approx(math.pi**2 / 6, rel=1e-15)
    assert hurwitz_zeta(4.0, 1.0) == pytest.approx(math.pi**4 / 90, rel=1e-15)
    for s, a in itertools.product((2.0, 6.0, 14.0), (1.5, 33.0, 1025.0)):
        assert hurwitz_zeta(s, a) - hurwitz_zeta(s, a + 1.0) == pytest.approx(a**-s, rel=1e-12)
    from scipy.special import zeta

    for s, a in itertools.product((2, 4, 8, 16), (1, 2, 65, 4097)):
        assert hurwitz_zeta(s, a) == pytest.approx(float(zeta(s, a)), rel=1e-14)


@pytest.mark.reference("second method", "all pairs by brute force")
def test_near_pairs_finds_every_pair_within_the_radius():
    from camcad.io.chain import near_pairs

    rng = np.random.default_rng(3)
    points = np.concatenate((rng.uniform(0, 10, (300, 2)), np.array([[5.0, 5.0], [5.0, 5.0 + 1e-9]]),
                             np.array([[0.0, 0.0], [0.3, 0.0]])))
    for radius in (1e-6, 0.3, 0.7):
        i, j, d = near_pairs(points, radius)
        found = set(zip(i.tolist(), j.tolist()))
        gaps = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
        brute = {(a, b) for a, b in zip(*np.nonzero(gaps <= radius)) if a != b}
        assert found == brute
        assert np.allclose(d, gaps[i, j], rtol=0, atol=1e-15)


@pytest.mark.reference("second method", "phase_integrals, one phase at a time")
def test_phase_areas_in_one_pass_equal_the_per_phase_integrals():
    from camcad.law.phases import phase_integrals, phases_integrals

    rng = np.random.default_rng(5)
    x = np.sort(np.concatenate((rng.uniform(0, 2 * np.pi, 500), [0.0, 1.0, 1.0, 3.0, 3.0, 2 * np.pi])))
    a = rng.standard_normal(len(x))
    bounds = [(0.0, 1.0), (1.0, 3.0), (0.5, 2.2), (3.0, 2 * np.pi), (1.7, 1.7), (0.0, 2 * np.pi)]
    for (lo, hi), got in zip(bounds, phases_integrals(x, a, bounds)):
        expected = phase_integrals(x, a, lo, hi)
        assert got == pytest.approx(expected, rel=1e-12, abs=1e-13)


@pytest.mark.reference("second method", "the careful reader (the fast path switched off)")
@pytest.mark.parametrize("text", [
    "theta_deg,a\n0,1\n90,2.5\n360,1\n",
    "# camcad law table\n\ntheta_deg,s_mm\r\n0,0\r\n180,25\r\n360,0\r\n",
    "0 1.5\n90 -2e-3\n360 1.5\n",
    "theta;a\n0;1\n5;2\n",
    "90,1\n0,2\n45,3\n",
])
def test_the_plain_table_path_reads_as_the_careful_reader(text, tmp_path, monkeypatch):
    from camcad.io import table_read

    path = tmp_path / "law.csv"
    path.write_text(text)
    assert table_read.read_plain_table(text, str(path)) is not None         # the fast path takes it
    fast = table_read.read_table(path)
    monkeypatch.setattr(table_read, "read_plain_table", lambda text, where: None)
    careful = table_read.read_table(path)
    for field in ("theta_deg", "values", "line_numbers"):
        assert np.array_equal(getattr(fast, field), getattr(careful, field)), field
    assert (fast.kind, fast.column, fast.header, fast.notes, fast.delimiter) == \
        (careful.kind, careful.column, careful.header, careful.notes, careful.delimiter)


@pytest.mark.reference("second method", "the careful table reader (line by line) reads what the fast path "
                                        "refuses")
@pytest.mark.parametrize("text", ["0,1\n\n90,2\n", '"0","1"\n', "0;1,5\n90;2\n", "theta,a\n0,1,5\n90,2,5\n",
                                  "0,1\n90,2 # note\n", "0,1\n90,nan\n"])
def test_anything_but_a_plain_table_goes_to_the_careful_reader(text):
    from camcad.io.table_read import read_plain_table

    assert read_plain_table(text, "t.csv") is None


@pytest.mark.reference("second method", "steady_state_frequency, speed by speed")
def test_the_broadcast_sweep_gives_each_speed_what_the_scalar_path_gives_it():
    from camcad import dynamics
    from camcad.law.standard import compose

    law = compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 25.0, "cycloidal")
    speeds = np.linspace(280.0, 420.0, 37)
    for follower in (dynamics.ElasticFollower(40.0, 0.05), dynamics.ElasticFollower(6.0, 0.0)):
        swept = dynamics.sweep(law, follower, speeds, samples=1024, keep=speeds[:3])
        spectrum = dynamics.law_spectrum(law, 1024)
        for i, rpm in enumerate(speeds):
            alone = dynamics.steady_state_frequency(spectrum, follower, rpm)
            assert swept.peak_accel_ratio[i] == alone.peak_accel_ratio
            assert swept.dynamic_error_max[i] == alone.dynamic_error_max
        first = swept.responses[float(speeds[0])]
        assert np.array_equal(first.accel_elastic, dynamics.steady_state_frequency(spectrum, follower,
                                                                                  speeds[0]).accel_elastic)
    # exact resonance with a zero harmonic (fn 6 Hz, zeta 0, 60 rpm: harmonic 6): the scalar path decides
    resonant = dynamics.sweep(law, dynamics.ElasticFollower(6.0, 0.0), [60.0, 61.0], samples=1024)
    assert 60.0 in resonant.notes and "zeta -> 0 limit" in resonant.notes[60.0][0]


@pytest.mark.reference("property", "threadpoolctl reports one thread per library in a sweep worker")
def test_a_sweep_worker_runs_numerical_libraries_on_one_thread(monkeypatch):
    import os

    from camcad.sweep import threads

    for name in threads.THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setattr(threads, "_pinned", [])
    told = threads.pin_numerical_threads()
    assert all(os.environ[name] == "1" for name in threads.THREAD_VARIABLES)
    assert told == [p for p in threads.loaded_openblas() if p in told]   # each one a loaded OpenBLAS
