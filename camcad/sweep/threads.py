"""Numerical threads of a sweep worker: one per process.

A sweep runs one design per core; a BLAS library that also starts a thread per core makes the workers'
threads spin against each other on a loaded machine (a 4×64 complex matrix product: 1.7 ms on one thread,
70–300 ms with two threads per worker on a busy 2-core machine). ``pin_numerical_threads`` sets the usual
environment variables (OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS) to 1 — read by a library that
starts after it, e.g. in a process spawned from this one — and tells the OpenBLAS libraries already loaded
in this process (numpy's and scipy's) to use one thread, through their own ``openblas_set_num_threads``.
"""

from __future__ import annotations

import ctypes
import os
import re

#: the environment variables the numerical libraries read for their thread count
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "VECLIB_MAXIMUM_THREADS",
                    "NUMEXPR_NUM_THREADS")
#: the setter of each OpenBLAS build (plain, 64-bit interface, scipy-openblas)
_SETTERS = ("openblas_set_num_threads", "openblas_set_num_threads64_", "scipy_openblas_set_num_threads64_",
            "scipy_openblas_set_num_threads")

_pinned: list[int] = []


def loaded_openblas() -> list[str]:
    """Paths of the OpenBLAS libraries mapped into this process (Linux: /proc/self/maps; elsewhere none)."""
    try:
        with open("/proc/self/maps", encoding="utf-8", errors="replace") as maps:
            text = maps.read()
    except OSError:
        return []
    return sorted(set(re.findall(r"(/\S*openblas\S*\.so[\w.\-]*)", text)))


def pin_numerical_threads(threads: int = 1) -> list[str]:
    """Numerical libraries to ``threads`` threads in this process (and in processes it starts); the OpenBLAS
    libraries it told, by path. Done once per process."""
    for name in THREAD_VARIABLES:
        os.environ[name] = str(threads)
    if _pinned == [os.getpid()]:
        return []
    told = []
    for path in loaded_openblas():
        try:
            library = ctypes.CDLL(path)
        except OSError:
            continue
        for setter in _SETTERS:
            function = getattr(library, setter, None)
            if function is not None:
                function(ctypes.c_int(threads))
                told.append(path)
                break
    _pinned[:] = [os.getpid()]
    return told
