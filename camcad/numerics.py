"""Scalar root finding and bounded minimisation on plain Python floats (Brent's methods).

camcad needs a root or a minimum of a scalar function in a handful of places (phase boundaries of a
drawn law, the peak of the pressure angle between two samples, the least base radius). scipy.optimize
does this well but costs half a second to import, which a profile that needs no optimiser should not
pay. These are the classical algorithms, written from their published descriptions:

- ``brent_root``: R. P. Brent, *Algorithms for Minimization without Derivatives* (1973), ch. 4
  ("zero"): bisection safeguarding secant and inverse quadratic interpolation; the bracket always
  holds a sign change, and the result is within ``xtol + rtol·|x|`` of a root.
- ``bounded_minimum``: the same book, ch. 5 ("localmin"): golden-section search safeguarding
  successive parabolic interpolation on [a, b]; the result is within ``xatol + √ε·|x|`` of a local
  minimum.

tests/law/test_numerics.py checks both against closed forms and against scipy's independent implementations.
"""

from __future__ import annotations

import math
from collections.abc import Callable

EPS = 2.220446049250313e-16
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))
_SQRT_EPS = math.sqrt(EPS)


def brent_root(f: Callable[[float], float], a: float, b: float, *, xtol: float = 2e-12,
               rtol: float = 4 * EPS, maxiter: int = 200) -> float:
    """A root of ``f`` in [a, b], where f(a) and f(b) have opposite signs (or one is zero).

    Parameters
    ----------
    f : callable
        A continuous scalar function.
    a, b : float
        The bracket.
    xtol, rtol : float
        Absolute and relative tolerance on the root.
    maxiter : int
        Most iterations before a RuntimeError.

    Returns
    -------
    float
        x with |x − root| <= xtol + rtol·|x| for some root in the bracket.

    Examples
    --------
    >>> round(brent_root(lambda x: x * x - 2.0, 0.0, 2.0), 12)
    1.414213562373
    """
    fa, fb = float(f(a)), float(f(b))
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise ValueError(f"f(a) = {fa:g} and f(b) = {fb:g} have the same sign: no bracket")
    c, fc = a, fa
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = rtol * abs(b) + 0.5 * xtol
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:  # secant
                p = 2.0 * m * s
                q = 1.0 - s
            else:  # inverse quadratic interpolation
                q = fa / fc
                r = fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0.0 else -tol)
        fb = float(f(b))
    raise RuntimeError(f"brent_root did not converge in {maxiter} iterations")


def bounded_minimum(f: Callable[[float], float], a: float, b: float, *, xatol: float = 1e-13,
                    maxiter: int = 500) -> tuple[float, float]:
    """A local minimum of ``f`` on [a, b] (the ends themselves are not evaluated).

    Parameters
    ----------
    f : callable
        A scalar function, finite on (a, b).
    a, b : float
        The interval, a < b.
    xatol : float
        Absolute tolerance on the abscissa.
    maxiter : int
        Most iterations.

    Returns
    -------
    (x, f(x))

    Examples
    --------
    A minimum is found to about sqrt(machine epsilon) relative in x (f is flat there: an error δ in x
    changes f by δ², below the round-off of f when δ < 1e-8), and f to full precision:

    >>> x, fx = bounded_minimum(lambda t: (t - 0.3) ** 2 + 1.0, 0.0, 1.0)
    >>> round(x, 7), round(fx, 12)
    (0.3, 1.0)
    """
    if not b > a:
        raise ValueError("bounded_minimum needs a < b")
    x = w = v = a + _GOLDEN * (b - a)
    fx = fw = fv = float(f(x))
    d = e = 0.0
    for _ in range(maxiter):
        middle = 0.5 * (a + b)
        tol = _SQRT_EPS * abs(x) + xatol / 3.0
        tol2 = 2.0 * tol
        if abs(x - middle) <= tol2 - 0.5 * (b - a):
            break
        parabolic = False
        if abs(e) > tol:
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            else:
                q = -q
            r, e = e, d
            if abs(p) < abs(0.5 * q * r) and q * (a - x) < p < q * (b - x):
                d = p / q
                u = x + d
                if u - a < tol2 or b - u < tol2:
                    d = tol if x < middle else -tol
                parabolic = True
        if not parabolic:
            e = (b - x) if x < middle else (a - x)
            d = _GOLDEN * e
        u = x + (d if abs(d) >= tol else (tol if d > 0.0 else -tol))
        fu = float(f(u))
        if fu <= fx:
            if u < x:
                b = x
            else:
                a = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    return x, fx
