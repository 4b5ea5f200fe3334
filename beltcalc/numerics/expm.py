# Ported from SciPy 1.17 (scipy/linalg/_matfuncs.py, _matfuncs_expm.pyx.in) under its license:
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

r"""Matrix exponential in numpy alone, for the time-domain core.

``scipy.linalg`` costs about 80 ms of a command's start-up, and the exact core uses two
things from it: ``expm`` and LAPACK's ``dgebal`` (balancing, :mod:`beltcalc.numerics.balance`).
This module has ``expm``, on numpy and the standard library only, taking one matrix
``(n, n)`` or a stack ``(..., n, n)`` in vectorised operations (one matmul or solve call per
stage for the stack).

:func:`expm` is a port of ``scipy.linalg.expm`` (scipy 1.17, ``_matfuncs.py`` and
``_matfuncs_expm.pyx.in``): the scaling and squaring algorithm of Al-Mohy and Higham [AH09]
with the same degree/scaling choice (:mod:`beltcalc.numerics.expm_degree`), the same Pade
evaluation and the same recomputed diagonal for triangular matrices. It agrees with scipy to
rounding as the exponential's conditioning amplifies it (relative 1-norm difference below
1e-13 max(1, ||A||_1) in ``tests/test_linalg.py``), not bit for bit (numpy's matmul/solve,
not scipy's BLAS calls).

References
----------
[AH09] A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
    exponential", SIAM J. Matrix Anal. Appl. 31 (2009) 970-989, doi:10.1137/09074721X.
[Hig05] N. J. Higham, "The scaling and squaring method for the matrix exponential revisited",
    SIAM J. Matrix Anal. Appl. 26 (2005) 1179-1193: the evaluation of r_13 in three products.
[Hig08] N. J. Higham, Functions of Matrices: Theory and Computation, SIAM (2008): the
    evaluation of the Pade approximant and the divided difference of exp.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from beltcalc.numerics.expm_degree import (
    DEGREES, LOG2_COEFF, THETA, AbsPowers, degree_and_scaling, ell)
from beltcalc.numerics.matrices import as_real_square


def _private_solve():
    """The gufunc under ``np.linalg.solve``, without its 3 us of error-state set-up, where it
    is still where it was (numpy 1.26-2.3) and solves as the public function does (checked on
    a 2 x 2 system with two right-hand sides: a private name may change in any release);
    else the public ``np.linalg.solve``."""
    try:
        from numpy.linalg._umath_linalg import solve
        a, b = np.array([[4.0, 1.0], [2.0, 3.0]]), np.array([[1.0, 2.0], [0.0, 1.0]])
        if np.array_equal(solve(a, b), np.linalg.solve(a, b)):
            return solve
    except (ImportError, TypeError, ValueError):
        pass
    return np.linalg.solve


_solve = _private_solve()

__all__ = ["expm"]

# Pade coefficients b_0..b_m of r_m = q_m(A)^-1 p_m(A), [AH09 eq. 2.1, 2.11] and [Hig05]
_B = {
    3: (120.0, 60.0, 12.0, 1.0),
    5: (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0),
    7: (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0),
    9: (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0,
        110880.0, 3960.0, 90.0, 1.0),
    13: (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
         129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0,
         40840800.0, 960960.0, 16380.0, 182.0, 1.0),
}
_PRESCALE_ABOVE = 2.0 ** 64   # ||A|| above which A is first scaled by 2^-k (scipy overflows)


@lru_cache(maxsize=64)
def _eye(n: int) -> np.ndarray:
    return np.eye(n)


@lru_cache(maxsize=64)
def _masks(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Boolean masks of the strictly lower and strictly upper triangles of an n x n matrix."""
    lower = np.tri(n, n, -1, dtype=bool)
    return lower, lower.T.copy()


def _diag_view(X: np.ndarray) -> np.ndarray:
    """Writable view of the diagonals of a C-contiguous stack X (K, n, n) as (K, n)."""
    K, n, _ = X.shape
    return X.reshape(K, n * n)[:, :: n + 1]


def _coefficients() -> dict[int, np.ndarray]:
    """Rows [W, V] (m <= 9) or [W2, W3, W4, W1] (m = 13) as combinations of [I, A^2, A^4,
    A^6, A^8]: U = A W, r_m = (V - U)^-1 (V + U) [AH09 eq. 2.11]; m = 13: U = A (A^6 W2 + W1),
    V = A^6 W4 + W3, the evaluation [Hig08 eq. 10.35]."""
    C = {}
    for m in (3, 5, 7, 9):
        b = _B[m]
        c = np.zeros((2, 5))
        for j in range(0, m + 1, 2):
            c[1, j // 2] = b[j]
        for j in range(1, m + 1, 2):
            c[0, (j - 1) // 2] = b[j]
        C[m] = c
    b = _B[13]
    C[13] = np.array([[0.0, b[9], b[11], b[13]], [b[0], b[2], b[4], b[6]],
                      [0.0, b[8], b[10], b[12]], [b[1], b[3], b[5], b[7]]])
    return C


_COEF = _coefficients()
_POW13 = np.array([0.0, 2.0, 4.0, 6.0])


def _pade(m: int, A: np.ndarray, powers: np.ndarray, s: np.ndarray | None) -> np.ndarray:
    """r_m(2^-s A) = I + 2 (V - U)^-1 U for a stack A (K, n, n), ``powers`` (K, 5, n, n) =
    [I, A^2, A^4, A^6, A^8] unscaled: the scaling by 2^-s (exact) is folded into the
    coefficients. scipy's ``pade_UV_calc`` does the same sums with axpy calls."""
    K, n, _ = A.shape
    if m < 13:
        p = (m + 1) // 2                  # [I, A^2, .., A^(m-1)]: A^8 may be unset
        W, V = np.matmul(_COEF[m][:, :p], powers[:, :p].reshape(K, p, n * n)).reshape(
            K, 2, n, n).transpose(1, 0, 2, 3)
        U = A @ W
    else:
        f = np.ldexp(1.0, -s)                                         # 2^-s per entry
        C = _COEF[13] * (f[:, None, None] ** _POW13)                  # (K, 4, 4)
        W2, W3, W4, W1 = np.matmul(C, powers[:, :4].reshape(K, 4, n * n)).reshape(K, 4, n, n).transpose(1, 0, 2, 3)
        A6 = powers[:, 3] * (f ** 6)[:, None, None]
        U = (A * f[:, None, None]) @ (A6 @ W2 + W1)
        V = A6 @ W4 + W3
    R = _solve(V - U, U)
    R *= 2.0
    _diag_view(R)[...] += 1.0
    return R


@lru_cache(maxsize=256)
def _coef13(s: int) -> tuple[np.ndarray, float, float]:
    """The m = 13 combination rows for 2^-s A (exact powers of two folded in), 2^-s, 2^-6s."""
    f = math.ldexp(1.0, -s)
    return _COEF[13] * (f ** _POW13), f, f ** 6


def _expm_one(a: np.ndarray) -> np.ndarray | None:
    """expm of one full (not triangular) matrix (n, n), n >= 2, with the algorithm's decisions
    in Python floats (the stack path's array bookkeeping costs more than the arithmetic at
    n ~ 14). Same operations as the stack path; None where that path must take over."""
    n = a.shape[0]
    P = np.abs(a).T                                   # |A|^T, see degree_and_scaling
    normA = float(P.sum(axis=1).max())
    if normA > _PRESCALE_ABOVE:
        return None
    log_norm = math.log2(normA)
    buf = np.empty((5, n, n))
    buf[0] = _eye(n)
    np.matmul(a, a, out=buf[1])
    np.matmul(buf[1], buf[1], out=buf[2])
    np.matmul(buf[2], buf[1], out=buf[3])
    n4, n6 = np.abs(buf[2:4]).sum(axis=1).max(axis=1).tolist()
    d6 = n6 ** (1.0 / 6.0)
    eta1 = max(n4 ** 0.25, d6)
    spins = None

    def ell_zero(i: int, shift: float = 0.0) -> bool:
        nonlocal spins
        if 2 * DEGREES[i] * (log_norm - shift) <= LOG2_COEFF[i]:
            return True
        if spins is None:
            spins = AbsPowers(P[None], np.array([normA]))
        k = 2 * DEGREES[i] + 1
        return bool(ell(spins.log_ratio(k) - (k - 1) * shift, i)[0] == 0)

    m, s = 13, 0
    if eta1 < THETA[0] and ell_zero(0):
        m = 3
    elif eta1 < THETA[1] and ell_zero(1):
        m = 5
    else:
        A8_10 = np.matmul(buf[2:4], buf[2])
        buf[4] = A8_10[0]
        n8, n10 = np.abs(A8_10).sum(axis=1).max(axis=1).tolist()
        d8 = n8 ** 0.125
        eta2 = max(d6, d8)
        if eta2 < THETA[2] and ell_zero(2):
            m = 7
        elif eta2 < THETA[3] and ell_zero(3):
            m = 9
        else:
            eta4 = min(eta2, max(d8, n10 ** 0.1))
            s = max(math.ceil(math.log2(eta4 / THETA[4])), 0) if eta4 > 0 else 0
            if not ell_zero(4, float(s)):
                s += int(ell(spins.log_ratio(27) - 26.0 * s, 4)[0])
    if m < 13:
        p = (m + 1) // 2                  # [I, A^2, .., A^(m-1)]: A^8 may be unset
        W, V = np.matmul(_COEF[m][:, :p], buf[:p].reshape(p, n * n)).reshape(2, n, n)
        U = a @ W
    else:
        C, f, f6 = _coef13(s)
        W2, W3, W4, W1 = np.matmul(C, buf[:4].reshape(4, n * n)).reshape(4, n, n)
        A6 = buf[3] * f6
        U = (a * f) @ (A6 @ W2 + W1)
        V = A6 @ W4 + W3
    R = _solve(V - U, U)
    R *= 2.0
    R.flat[:: n + 1] += 1.0
    for _ in range(s):
        R = R @ R
    return R


def _exp_sinch(x: np.ndarray) -> np.ndarray:
    """(e^x_{i+1} - e^x_i) / (x_{i+1} - x_i) along the last axis (e^x_i where they are equal):
    scipy's ``_exp_sinch``, [Hig08 eq. 10.42]."""
    ex = np.exp(x)
    num = np.diff(ex, axis=-1)
    den = np.diff(x, axis=-1)
    same = den == 0.0
    return np.where(same, ex[..., :-1], num / np.where(same, 1.0, den))


def expm(A) -> np.ndarray:
    r"""Matrix exponential e^A of a real matrix (n, n) or of each matrix of a stack (..., n, n).

    .. math:: e^A \approx r_m(2^{-s} A)^{2^s}, \qquad
              r_m(X) = q_m(X)^{-1} p_m(X) \;\text{(diagonal Pade approximant of degree m)}

    Parameters
    ----------
    A : array_like of float, shape (n, n) or (..., n, n)
        The matrix or matrices; finite, real (float32 and integers are taken as float64)

    Returns
    -------
    ndarray of float64, shape of A
        e^A of each matrix

    Raises
    ------
    ValueError
        A is not square, or has a non-finite entry
    TypeError
        A is complex

    Notes
    -----
    The scaling and squaring algorithm [AH09 alg. 5.1] as ``scipy.linalg.expm`` (1.17)
    implements it, ported statement for statement:

    - degree m in {3, 5, 7, 9, 13} and scaling s from the 1-norms of powers
      (:func:`beltcalc.numerics.expm_degree.degree_and_scaling`),
      eta = max(||A^p||^{1/p}, ||A^{p+1}||^{1/(p+1)}) (d_p and alpha_p of [AH09 thm. 4.2]),
      against theta_m of [AH09 table 3.1], with the ell(A, m) guard against overscaling (the
      norms of |A|^{2m+1}, lines 3-14 of the algorithm; here computed without overflow,
      see :class:`beltcalc.numerics.expm_degree.AbsPowers`);
    - r_m(2^-s A) = I + 2 (V - U)^-1 U with U, V the odd and even parts of p_m
      [AH09 eq. 2.11], m = 13 in the three-product scheme of [Hig05];
    - s squarings; for a triangular matrix the diagonal and the first off-diagonal of each
      square are recomputed exactly [AH09 code fragment 2.1] (with ``_exp_sinch``), and a
      diagonal matrix gets exp of its diagonal.

    A stack is evaluated entry by entry in the algorithm's sense: each entry has its own m
    and s (not the worst one of the stack, which would overscale the small entries and lose
    accuracy); the entries are grouped by m, each group's Pade approximant is one set of
    batched matmuls and one batched solve, and the squarings run for the largest s with only
    the entries that still need one. The n = 0 and n = 1 cases are answered directly.

    One departure from scipy: a matrix with ||A||_1 > 2^64 is first scaled by a power
    of two (exact) to norm ~2^16 and that power added to s; scipy overflows in the powers of A
    there (e.g. it returns zeros or NaN for the rotation generator with w >= 1e20), here the
    same choice of s results wherever the norms of the powers drive it.

    Examples
    --------
    >>> import numpy as np
    >>> w = 2.0
    >>> np.allclose(expm(np.array([[0.0, -w], [w, 0.0]])),
    ...             [[np.cos(w), -np.sin(w)], [np.sin(w), np.cos(w)]], rtol=0, atol=1e-15)
    True
    """
    a = as_real_square(A, "expm")
    shape = a.shape
    n = shape[-1]
    if n == 0 or a.size == 0:
        return np.empty(shape)
    if n == 1:
        return np.exp(a)
    lower, upper = _masks(n)
    if a.size == n * n and a[..., lower].any() and a[..., upper].any():    # one full matrix (or a stack of one)
        R = _expm_one(a.reshape(n, n))
        if R is not None:
            return R.reshape(shape)
    X = a.reshape(-1, n, n)
    K = X.shape[0]
    has_low = X[:, lower].any(axis=1)
    has_up = X[:, upper].any(axis=1)
    out = np.empty_like(X)

    diag = ~(has_low | has_up)
    if diag.any():                                     # scipy: bandwidth (0, 0)
        idx = np.flatnonzero(diag)
        out[idx] = 0.0
        _diag_view(out)[idx] = np.exp(_diag_view(X)[idx])
        if diag.all():
            return out.reshape(shape)
        work = np.flatnonzero(~diag)
        X = X[work]
        tri_low = ~has_up[work]                        # lower triangular (upper bandwidth 0)
        tri_up = ~has_low[work]
    else:
        work = None
        tri_low = ~has_up
        tri_up = ~has_low

    X0 = X
    # pre-scaling for huge norms (see Notes): exact, by powers of two
    normA = np.abs(X).sum(axis=2).max(axis=1)
    s0 = np.zeros(X.shape[0], dtype=np.int64)
    big = normA > _PRESCALE_ABOVE
    if big.any():
        s0[big] = np.frexp(normA[big])[1] - 16
        X = np.ldexp(X, -s0[:, None, None])

    K = X.shape[0]
    buf = np.empty((K, 5, n, n))
    buf[:, 0] = _eye(n)
    m, s, _ = degree_and_scaling(X, buf)
    s_pade = s
    s = s + s0
    R = np.empty_like(X)
    for deg in DEGREES:
        sel = m == deg
        if not sel.any():
            continue
        if sel.all():
            R = _pade(deg, X, buf, s_pade)
        else:
            idx = np.flatnonzero(sel)
            R[idx] = _pade(deg, X[idx], buf[idx], s_pade[idx])

    tri = tri_low | tri_up
    smax = int(s.max())
    if tri.any():
        # [AH09 code fragment 2.1]: the diagonal of r_m(2^-s T) set to exp(2^-s diag T)
        ti = np.flatnonzero(tri & (s > 0))
        dT = _diag_view(X0)[ti] * np.ldexp(1.0, -s[ti])[:, None]
        _diag_view(R)[ti] = np.exp(dT)
    for j in range(smax):                              # squarings
        need = s > j
        if need.all():
            R = R @ R
        else:
            idx = np.flatnonzero(need)
            R[idx] = R[idx] @ R[idx]
        if tri.any():
            ti = np.flatnonzero(tri & need)
            if ti.size:
                _fix_triangular(R, X0, ti, s[ti] - 1 - j, tri_low[ti])
    if tri.any():
        for ti, keep in ((np.flatnonzero(tri_up), np.triu), (np.flatnonzero(tri_low), np.tril)):
            if ti.size:
                R[ti] = keep(R[ti])
    if work is None:
        return R.reshape(shape)
    out[work] = R
    return out.reshape(shape)


def _fix_triangular(R: np.ndarray, T: np.ndarray, ti: np.ndarray, i: np.ndarray,
                    low: np.ndarray) -> None:
    """[AH09 code fragment 2.1], one squaring: R_k = e^{2^-i_k T_k} has its diagonal and first
    super- (sub-, for lower triangular T) diagonal recomputed from those of T_k (scipy)."""
    n = T.shape[-1]
    f = np.ldexp(1.0, -i)[:, None]
    dT = _diag_view(T)[ti] * f
    _diag_view(R)[ti] = np.exp(dT)
    flat_T = T.reshape(T.shape[0], n * n)
    flat_R = R.reshape(R.shape[0], n * n)
    up = np.flatnonzero(~low)
    lo = np.flatnonzero(low)
    if up.size:
        sd = flat_T[ti[up], 1::n + 1] * f[up]
        flat_R[ti[up], 1::n + 1] = _exp_sinch(dT[up]) * sd
    if lo.size:
        sd = flat_T[ti[lo], n::n + 1] * f[lo]
        flat_R[ti[lo], n::n + 1] = _exp_sinch(dT[lo]) * sd
