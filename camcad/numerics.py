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


#: B_2k / (2k)! for k = 1..7 (Bernoulli numbers B_2 = 1/6, B_4 = −1/30, B_6 = 1/42, B_8 = −1/30,
#: B_10 = 5/66, B_12 = −691/2730, B_14 = 7/6)
_BERNOULLI_OVER_FACTORIAL = tuple(b / math.factorial(2 * k) for k, b in enumerate(
    (1 / 6, -1 / 30, 1 / 42, -1 / 30, 5 / 66, -691 / 2730, 7 / 6), start=1))


def hurwitz_zeta(s: float, a: float, terms: int = 10) -> float:
    """The Hurwitz zeta function ζ(s, a) = Σ_{n≥0} (a + n)^{−s} for s > 1, a > 0, by Euler–Maclaurin.

    The first ``terms`` terms are summed directly; the rest, Σ_{n≥M} f(n) with f(x) = (a + x)^{−s} and
    M = ``terms``, is ∫_M^∞ f + f(M)/2 + Σ_{k=1}^{7} B_2k/(2k)! · s(s+1)…(s+2k−2) (a+M)^{1−s−2k}, whose
    remainder is below the last correction kept: with a + M ≥ 10 and s ≤ 40 that is under 1e-16 of the sum.
    (scipy.special.zeta computes the same; importing it costs a quarter of a second.)

    Parameters
    ----------
    s : float
        Exponent, > 1.
    a : float
        Shift, > 0.
    terms : int
        Terms summed before the Euler–Maclaurin tail.

    Returns
    -------
    float
        ζ(s, a).

    References
    ----------
    NIST Digital Library of Mathematical Functions, §25.11 (Hurwitz zeta) and §2.10 (Euler–Maclaurin).

    Examples
    --------
    >>> abs(hurwitz_zeta(2.0, 1.0) - math.pi**2 / 6) < 1e-15
    True
    >>> abs(hurwitz_zeta(4.0, 1.0) - math.pi**4 / 90) < 1e-15
    True
    """
    if not (s > 1.0 and a > 0.0):
        raise ValueError(f"hurwitz_zeta needs s > 1 and a > 0, got s = {s!r}, a = {a!r}")
    head = math.fsum((a + n) ** -s for n in range(terms))
    x = a + terms
    tail = x ** (1.0 - s) / (s - 1.0) + 0.5 * x**-s
    rising = s                      # s(s+1)…(s+2k−2)
    power = x ** (-s - 1.0)         # (a+M)^{1−s−2k}
    for k, coefficient in enumerate(_BERNOULLI_OVER_FACTORIAL, start=1):
        tail += coefficient * rising * power
        rising *= (s + 2 * k - 1) * (s + 2 * k)
        power /= x * x
    return head + tail


def solve_tridiagonal(lower, diag, upper, rhs):
    """x with T x = rhs for the tridiagonal T (``diag`` on the diagonal, ``lower[i]`` = T[i+1, i],
    ``upper[i]`` = T[i, i+1]), by odd-even cyclic reduction: log₂ n vectorised levels (numpy, no scipy).

    Stable without pivoting for a diagonally dominant or symmetric positive definite T (the case of the
    polyline mass matrices it serves); ``rhs`` may have several columns (shape (n,) or (n, m)).

    Parameters
    ----------
    lower, upper : ndarray, shape (n − 1,)
        Sub- and super-diagonal.
    diag : ndarray, shape (n,)
        Diagonal.
    rhs : ndarray, shape (n,) or (n, m)
        Right-hand side(s).

    Returns
    -------
    ndarray
        x, shaped like ``rhs``.

    References
    ----------
    R. W. Hockney, "A fast direct solution of Poisson's equation using Fourier analysis", J. ACM 12
    (1965) 95–113 (cyclic reduction); G. H. Golub and C. F. Van Loan, Matrix Computations, 4th ed.
    (2013), §4.3 (tridiagonal systems).

    Examples
    --------
    >>> import numpy as np
    >>> x = solve_tridiagonal(np.array([1.0, 1.0]), np.array([4.0, 4.0, 4.0]), np.array([1.0, 1.0]),
    ...                       np.array([5.0, 6.0, 5.0]))
    >>> [round(float(v), 12) for v in x]
    [1.0, 1.0, 1.0]
    """
    import numpy as np

    diag = np.asarray(diag, dtype=float)
    n = len(diag)
    d = np.asarray(rhs, dtype=float)
    single = d.ndim == 1
    a = np.zeros(n)
    c = np.zeros(n)
    a[1:] = lower
    c[:-1] = upper
    # right-hand sides as rows: the reduction works along the unknowns, the last axis
    x = _reduce(a, diag, c, np.ascontiguousarray(d.reshape(n, -1).T)).T
    return x[:, 0] if single else x


#: below this many unknowns cyclic reduction hands over to a dense solve
_DENSE_BELOW = 64


def _reduce(a, b, c, d):
    """Cyclic reduction of a[i] x[i−1] + b[i] x[i] + c[i] x[i+1] = d[:, i] (a[0] = 0, c[−1] = 0; d of
    shape (m, n), one right-hand side per row): the even-numbered equations take their odd neighbours
    out, the even unknowns are solved the same way, the odd ones follow from their own equations."""
    import numpy as np

    n = len(b)
    if n <= _DENSE_BELOW:      # a small system: one dense solve beats the remaining levels' overhead
        dense = np.diag(b)
        dense[np.arange(1, n), np.arange(n - 1)] = a[1:]
        dense[np.arange(n - 1), np.arange(1, n)] = c[:-1]
        return np.linalg.solve(dense, d.T).T
    if n % 2 == 0:          # one more equation x = 0, decoupled (a = c = 0), makes the count odd
        a, b, c = np.append(a, 0.0), np.append(b, 1.0), np.append(c, 0.0)
        d = np.concatenate((d, np.zeros((d.shape[0], 1))), axis=1)
    ao, bo, co, do = a[1::2], b[1::2], c[1::2], d[:, 1::2]
    alpha = a[2::2] / bo          # even i ≥ 2 and its left odd neighbour (with the sign taken below)
    gamma = c[0:-1:2] / bo        # even i ≤ n − 3 and its right odd neighbour
    b2 = b[0::2].copy()
    b2[1:] -= alpha * co
    b2[:-1] -= gamma * ao
    a2 = np.zeros_like(b2)
    c2 = np.zeros_like(b2)
    a2[1:] = -alpha * ao
    c2[:-1] = -gamma * co
    d2 = d[:, 0::2].copy()
    d2[:, 1:] -= alpha * do
    d2[:, :-1] -= gamma * do
    xe = _reduce(a2, b2, c2, d2)
    x = np.empty_like(d)
    x[:, 0::2] = xe
    x[:, 1::2] = (do - ao * xe[:, :-1] - co * xe[:, 1:]) / bo
    return x[:, :n]
