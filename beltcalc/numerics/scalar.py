# Ported from SciPy 1.17 (scipy/optimize/Zeros/brentq.c, _optimize.py) under its license:
#
# Copyright (c) 2001-2002 Enthought, Inc. 2003, SciPy Developers.
# All rights reserved.
#
# Redistribution and use in source and binary forms, with or without
# modification, are permitted provided that the following conditions
# are met:
#
# 1. Redistributions of source code must retain the above copyright
#    notice, this list of conditions and the following disclaimer.
#
# 2. Redistributions in binary form must reproduce the above
#    copyright notice, this list of conditions and the following
#    disclaimer in the documentation and/or other materials provided
#    with the distribution.
#
# 3. Neither the name of the copyright holder nor the names of its
#    contributors may be used to endorse or promote products derived
#    from this software without specific prior written permission.
#
# THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS
# "AS IS" AND ANY EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT
# LIMITED TO, THE IMPLIED WARRANTIES OF MERCHANTABILITY AND FITNESS FOR
# A PARTICULAR PURPOSE ARE DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT
# OWNER OR CONTRIBUTORS BE LIABLE FOR ANY DIRECT, INDIRECT, INCIDENTAL,
# SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES (INCLUDING, BUT NOT
# LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR SERVICES; LOSS OF USE,
# DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER CAUSED AND ON ANY
# THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY, OR TORT
# (INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE
# OF THIS SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE.

r"""Scalar search: a root by Brent's method, a minimum by golden section.

Both are line-for-line ports of scipy's (``scipy.optimize.brentq``, from its C source
``Zeros/brentq.c``; ``minimize_scalar(method="golden")`` with a three-point bracket), the same floating-point
operations in the same order, so they return the same numbers bit for bit
(``tests/test_scalar.py`` checks it against scipy). They are here because importing
``scipy.optimize`` costs about a third of a command's start-up, and these few lines are all
the frequency response and the switching core use of it.

References
----------
1. R. P. Brent, *Algorithms for Minimization without Derivatives*, Prentice-Hall, 1973,
   ch. 4 (the root).
2. W. H. Press et al., *Numerical Recipes*, 3rd ed., 2007, sec. 9.3 (Brent's root) and
   10.2 (golden section search).
"""

from __future__ import annotations

import math
import sys
from typing import Callable

XTOL = 2e-12                              # scipy's default absolute tolerance of brentq
RTOL = 4 * sys.float_info.epsilon         # and the smallest relative one it accepts
MAXITER = 100
_GR = 0.61803399                          # the golden ratio's conjugate, as scipy rounds it
_GC = 1.0 - _GR
_GOLDEN_MEAN = 0.5 * (3.0 - math.sqrt(5.0))


def horner(c: list[float], x):
    r"""The polynomial ``sum_j c[j] x^j`` (c lowest first, a list of floats) at x, a float or
    an array of points.

    numpy's ``polynomial.polynomial.polyval`` operation for operation (so the same numbers
    bit for bit), without its per-call cost on a float, and in place on an array.

    Examples
    --------
    >>> horner([1.0, -3.0, 2.0], 2.0)
    3.0
    """
    if isinstance(x, float):
        y = c[-1]
        for j in range(len(c) - 2, -1, -1):
            y = c[j] + y * x
        return y
    y = x * 0                  # polyval's start, c[-1] + x * 0, in place
    y += c[-1]
    for j in range(len(c) - 2, -1, -1):
        y *= x
        y += c[j]
    return y


def _signbit(x: float) -> bool:
    return math.copysign(1.0, x) < 0


def brentq(f: Callable[[float], float], a: float, b: float, xtol: float = XTOL, rtol: float = RTOL,
           maxiter: int = MAXITER) -> float:
    r"""A root of ``f`` in [a, b], where f(a) and f(b) have opposite signs (Brent's method:
    inverse quadratic steps, bisection where they would not shrink the bracket fast enough).

    The root x0 returned satisfies ``|x - x0| <= xtol + rtol |x0|`` for the exact root x.

    Parameters
    ----------
    f : callable
        Continuous function of one float
    a, b : float
        Ends of the bracket, f(a) f(b) <= 0
    xtol, rtol : float
        Absolute and relative tolerance, xtol > 0 and rtol >= 4 eps
    maxiter : int
        Iterations before giving up

    Returns
    -------
    float
        The root

    Raises
    ------
    ValueError
        f(a) and f(b) of the same sign, f returns NaN, or a tolerance out of range
    RuntimeError
        No convergence in ``maxiter`` iterations

    Notes
    -----
    scipy's ``brentq`` (``scipy/optimize/Zeros/brentq.c``, C. Harris), statement by statement.

    Examples
    --------
    >>> x = brentq(lambda x: x * x - 2.0, 0.0, 2.0)      # within xtol = 2e-12 of sqrt(2)
    >>> abs(x - 2 ** 0.5) < 2e-12, x
    (True, 1.4142135623731364)
    """
    if xtol <= 0:
        raise ValueError(f"xtol too small ({xtol:g} <= 0)")
    if rtol < RTOL:
        raise ValueError(f"rtol too small ({rtol:g} < {RTOL:g})")

    def fx(x: float) -> float:
        y = float(f(x))
        if math.isnan(y):
            raise ValueError(f"The function value at x={x} is NaN; solver cannot continue.")
        return y

    xpre, xcur = float(a), float(b)
    xblk = fblk = spre = scur = 0.0
    fpre, fcur = fx(xpre), fx(xcur)
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if _signbit(fpre) == _signbit(fcur):
        raise ValueError("f(a) and f(b) must have different signs")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and _signbit(fpre) != _signbit(fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:                      # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:                                 # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            bound = 3 * abs(sbis) - delta
            if 2 * abs(stry) < (abs(spre) if abs(spre) < bound else bound):
                spre, scur = scur, stry           # a good short step
            else:
                spre = scur = sbis                # bisect
        else:
            spre = scur = sbis                    # bisect
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = fx(xcur)
    raise RuntimeError(f"Failed to converge after {maxiter} iterations, value is {xcur}.")


def golden_minimum(f: Callable[[float], float], xa: float, xb: float, xc: float, xtol: float = 1.4901161193847656e-08,
                   maxiter: int = 5000) -> tuple[float, float]:
    r"""(x, f(x)) at a minimum of ``f`` inside the bracket xa < xb < xc with f(xb) below
    f(xa) and f(xc), by golden section until the bracket is narrower than
    ``xtol (|x1| + |x2|)``.

    Parameters
    ----------
    f : callable
        Function of one float
    xa, xb, xc : float
        The bracket (xa and xc may come in either order)
    xtol : float
        Relative width of the final bracket
    maxiter : int
        Iterations at most

    Returns
    -------
    tuple of float
        The abscissa and the value at the minimum found

    Raises
    ------
    ValueError
        Not a bracket: xb not between xa and xc, or f(xb) not below both ends

    Notes
    -----
    scipy's ``minimize_scalar(f, bracket=(xa, xb, xc), method="golden")``, statement by
    statement (its result's ``x`` and ``fun``).

    Examples
    --------
    >>> x, fx = golden_minimum(lambda x: (x - 1.0) ** 2, 0.0, 0.5, 3.0, xtol=1e-12)
    >>> round(x, 9), fx < 1e-20
    (1.0, True)
    """
    if xa > xc:
        xc, xa = xa, xc
    if not (xa < xb and xb < xc):
        raise ValueError("Bracketing values (xa, xb, xc) do not fulfill this requirement: (xa < xb) and (xb < xc)")
    fa, fb, fc = f(xa), f(xb), f(xc)
    if not (fb < fa and fb < fc):
        raise ValueError("Bracketing values (xa, xb, xc) do not fulfill this requirement: (f(xb) < f(xa)) and "
                         "(f(xb) < f(xc))")
    x3, x0 = xc, xa
    if abs(xc - xb) > abs(xb - xa):
        x1 = xb
        x2 = xb + _GC * (xc - xb)
    else:
        x2 = xb
        x1 = xb - _GC * (xb - xa)
    f1, f2 = f(x1), f(x2)
    for _ in range(maxiter):
        if abs(x3 - x0) <= xtol * (abs(x1) + abs(x2)):
            break
        if f2 < f1:
            x0, x1 = x1, x2
            x2 = _GR * x1 + _GC * x3
            f1, f2 = f2, f(x2)
        else:
            x3, x2 = x2, x1
            x1 = _GR * x2 + _GC * x0
            f2, f1 = f1, f(x1)
    return (x1, f1) if f1 < f2 else (x2, f2)

