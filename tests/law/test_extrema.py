"""camcad.extrema.zoom_max against closed forms and against Brent's bounded search (camcad.numerics)."""

import math

import numpy as np
import pytest

from camcad.extrema import zoom_max
from camcad.numerics import bounded_minimum


@pytest.mark.reference("closed form", "cos(x - x0): peak 1 at x0, between grid points")
@pytest.mark.parametrize("shift", [0.0, 0.123456789, 0.5, 0.99])
def test_smooth_peaks_to_round_off(shift):
    # f = cos(x − x0): peak 1 at x0 + 2πk, between grid points of a 1° grid
    x0 = 1.0 + shift * math.radians(1.0)
    grid = np.radians(np.arange(0.0, 360.0 + 1e-9, 1.0))
    peak, at = zoom_max(lambda u: np.atleast_2d(np.cos(u - x0)), grid, 1)
    assert peak[0] == pytest.approx(1.0, abs=2e-16)
    assert at[0] == pytest.approx(x0, abs=1e-7)      # the value is flat there: δx ≈ 1e-7 changes it by 5e-15


@pytest.mark.reference("second method", "Brent's bounded search (camcad.numerics) on each row, and the rows one at a "
                                        "time")
def test_many_rows_at_once_equal_one_row_at_a_time_and_brent():
    # rows of a cycloidal-like family with peaks at different places; each against Brent's bounded search
    rng = np.random.default_rng(5)
    a, b = rng.uniform(0.5, 2.0, 12), rng.uniform(0.2, 2.8, 12)

    def values(u):
        u = np.broadcast_to(u, (12, np.shape(u)[-1]))
        return a[:, None] * np.sin(u) * np.exp(-((u - b[:, None]) ** 2))

    grid = np.linspace(0.0, math.pi, 91)
    peak, at = zoom_max(values, grid, 12)
    for row in range(12):
        one, where = zoom_max(lambda u, row=row: values(u)[row:row + 1], grid, 1)
        assert one[0] == peak[row] and where[0] == at[row]
        k = int(np.argmax(values(grid)[row]))
        x, fx = bounded_minimum(lambda t, row=row: -float(values(np.array([t]))[row, 0]),
                                grid[max(k - 1, 0)], grid[min(k + 1, 90)], xatol=1e-13)
        assert peak[row] == pytest.approx(-fx, rel=1e-13, abs=1e-15)
        assert at[row] == pytest.approx(x, abs=1e-7)


@pytest.mark.reference("closed form", "-|x - 0.301| peaks at 0.301, within the last zoom spacing h/512; NaN and -inf "
                                      "are absent")
def test_a_kink_and_absent_values():
    # −|x − 0.301| peaks at a kink between samples: the peak is within the last zoom level's spacing, h/512
    grid = np.linspace(0.0, 1.0, 11)
    spacing = 0.1 / 512
    peak, at = zoom_max(lambda u: np.atleast_2d(-np.abs(u - 0.301)), grid, 1)
    assert -spacing <= peak[0] <= 0.0
    assert at[0] == pytest.approx(0.301, abs=spacing)
    # NaN and −inf are absent; a row with nothing finite gives −inf
    values = np.array([[np.nan, 1.0, -np.inf], [np.nan, np.nan, np.nan]])
    peak, _ = zoom_max(lambda u: values if np.ndim(u) == 1 else np.full((2, np.shape(u)[-1]), np.nan),
                       np.array([0.0, 0.5, 1.0]), 2)
    assert peak[0] == 1.0 and peak[1] == -np.inf


@pytest.mark.reference("closed form", "f = x on [0, 0.3): supremum 0.3 not taken, every value returned is one f took")
def test_a_jump_is_approached_from_below_never_overshot():
    # f = x on [0, 0.3), x − 1 after: its supremum 0.3 is not taken; a parabola through samples that straddle
    # the jump would rise above it, so every value returned must be one f took
    def f(u):
        return np.atleast_2d(np.where(u < 0.3, u, u - 1.0))

    grid = np.linspace(0.0, 1.0, 11)
    peak, at = zoom_max(f, grid, 1)
    assert 0.3 - 0.1 / 512 <= peak[0] < 0.3     # within the last spacing h/512
    assert float(f(np.array([at[0]]))[0, 0]) == peak[0]
