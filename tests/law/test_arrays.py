"""camcad.arrays against numpy's own set routines (an independent implementation)."""

import numpy as np
import pytest

from camcad.arrays import union, unique

CASES = [
    [],
    [1.0],
    [3.0, 1.0, 3.0, 2.0, 1.0],
    [0.0, -0.0, 1e-300, -1e-300, 5e-324],
    [np.nan, 1.0, np.nan, 0.5, np.inf, -np.inf, 1.0],
    [[2.0, 1.0], [1.0, 2.0]],
    [5, 3, 5, 1],
]


@pytest.mark.reference("second method", "numpy.unique (an independent implementation) on hand-picked hard cases")
@pytest.mark.parametrize("values", CASES)
def test_unique_equals_numpys(values):
    ours, theirs = unique(values), np.unique(np.asarray(values))
    assert ours.dtype == theirs.dtype
    np.testing.assert_array_equal(ours, theirs)


@pytest.mark.reference("second method", "numpy.union1d on random grids")
def test_union_equals_numpys_on_random_grids():
    rng = np.random.default_rng(3)
    for _ in range(50):
        a = np.round(rng.uniform(0, 10, rng.integers(0, 40)), 1)
        b = np.round(rng.uniform(0, 10, rng.integers(0, 40)), 1)
        np.testing.assert_array_equal(union(a, b), np.union1d(a, b))


@pytest.mark.reference("property", "importing camcad.arrays leaves numpy.ma unimported (start-up)")
def test_unique_does_not_import_numpys_masked_arrays():
    import subprocess
    import sys

    code = ("import sys, numpy; from camcad.arrays import unique, union; unique([2.0, 1.0, 2.0]); "
            "union([1.0], [0.0]); print('numpy.ma' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
