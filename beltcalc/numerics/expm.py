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
#
# balance() is ported from LAPACK 3.12 (dgebal.f) under its license:
#
# Copyright (c) 1992-2013 The University of Tennessee and The University
#                         of Tennessee Research Foundation.  All rights
#                         reserved.
# Copyright (c) 2000-2013 The University of California Berkeley. All
#                         rights reserved.
# Copyright (c) 2006-2013 The University of Colorado Denver.  All rights
#                         reserved.
#
# Redistribution and use in source and binary forms, with or without
# modification, are permitted provided that the following conditions are
# met:
#
# - Redistributions of source code must retain the above copyright
#   notice, this list of conditions and the following disclaimer.
#
# - Redistributions in binary form must reproduce the above copyright
#   notice, this list of conditions and the following disclaimer listed
#   in this license in the documentation and/or other materials
#   provided with the distribution.
#
# - Neither the name of the copyright holders nor the names of its
#   contributors may be used to endorse or promote products derived from
#   this software without specific prior written permission.
#
# The copyright holders provide no reassurances that the source code
# provided does not infringe any patent, copyright, or any other
# intellectual property rights of third parties.  The copyright holders
# disclaim any liability to any recipient for claims brought against
# recipient by a third party for infringement of that party's
# intellectual property rights.
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

r"""Matrix exponential and balancing in numpy alone, for the time-domain core.

``scipy.linalg`` costs about 80 ms of a command's start-up, and the exact core uses two
things from it: ``expm`` and LAPACK's ``dgebal`` (balancing). This module has ``expm``, on
numpy and the standard library only, taking one matrix ``(n, n)`` or a stack
``(..., n, n)`` in vectorised operations (one matmul or solve call per stage for the stack).

- :func:`expm` is a port of ``scipy.linalg.expm`` (scipy 1.17, ``_matfuncs.py`` and
  ``_matfuncs_expm.pyx.in``): the scaling and squaring algorithm of Al-Mohy and Higham [1]_
  with the same degree/scaling choice, the same Pade evaluation and the same recomputed
  diagonal for triangular matrices. It agrees with scipy to rounding as the exponential's
  conditioning amplifies it (relative 1-norm difference below 1e-13 max(1, ||A||_1) in
  ``tests/test_linalg.py``), not bit for bit (numpy's matmul/solve, not scipy's BLAS calls).
- :func:`balance` is LAPACK's ``dgebal`` with ``job = 'S'`` (scaling, no permutation) [2]_,
  statement by statement on one matrix at a time: Osborne's iteration [3]_ in 2-norms, a
  row and its column scaled by a power of two where that lowers their norms' sum by 5 %.
  Sequential by nature (each scaling changes the next row's norms); a simultaneous sweep
  over all rows oscillates.

References
----------
.. [1] A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
   exponential", SIAM J. Matrix Anal. Appl. 31 (2009) 970-989, doi:10.1137/09074721X.
.. [2] LAPACK 3.12, ``dgebal.f`` (the 2-norm version since LAPACK 3.5.0; R. James, J. Langou,
   B. Lowery, "On matrix balancing and eigenvector computation", arXiv:1401.5766, 2014).
.. [3] E. E. Osborne, "On pre-conditioning of matrices", J. ACM 7 (1960) 338-345; B. N.
   Parlett and C. Reinsch, "Balancing a matrix for calculation of eigenvalues and
   eigenvectors", Numer. Math. 13 (1969) 293-304.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

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

__all__ = ["balance", "expm"]

# --- expm: constants of [1] as scipy holds them -----------------------------------------------

_DEGREES = (3, 5, 7, 9, 13)
# theta_m of [1], Table 3.1 (the largest ||2^-s A|| for which r_m has backward error <= u)
_THETA = (1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
          2.097847961257068e0, 4.25e0)
# u / |c_{2m+1}| of the ell(A, m) test of [1] (Algorithm 5.1, lines 3-12): u = 2^-53 times
# the reciprocal of the leading coefficient of the Pade error series, as scipy writes them
_LOG2_COEFF = tuple(math.log2(2.0 ** -53 * c) for c in (
    100800.0, 10059033600.0, 4487938430976000.0, 5914384781877411840000.0,
    113250775606021113483283660800000000.0))
# Pade coefficients b_0..b_m of r_m = q_m(A)^-1 p_m(A), [1] eq. (2.1)/(2.11) (Higham 2005)
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


def _norm1(X: np.ndarray) -> np.ndarray:
    """1-norms (largest absolute column sum) of a stack (K, n, n)."""
    return np.abs(X).sum(axis=1).max(axis=1)


class _AbsPowers:
    r"""log2(|| |A|^k ||_1 / ||A||_1) for the ell(A, m) tests of [1], k = 2m + 1.

    Given P = |A|^T, || |A|^k ||_1 = || P^k 1 ||_inf (|A| >= 0). scipy gets it by k products
    from v = 1 (``kth_power_norm``); here Q = P / ||A||_1 (so nothing overflows:
    || Q^k 1 ||_inf <= 1) and its powers Q^2, Q^4, Q^8 carry v from k = 1 to 3, 7, 11, 15,
    19, 27, so log2 of the ratio is (k - 1) log2 ||A||_1 + log2 ||Q^k 1|| - log2 ||Q 1||. Same
    quantity; the rounding differs, which could only move the integer ell(A, m) where its
    argument is an integer."""

    def __init__(self, P: np.ndarray, normA: np.ndarray):
        self.log_norm = np.log2(normA)
        self.Q = P / normA[:, None, None]
        v = self.Q.sum(axis=2)
        self.v = {1: v[:, :, None]}
        self.log_v1 = np.log2(v.max(axis=1))
        self.Q2 = self.Q4 = self.Q8 = None

    def log_ratio(self, k: int) -> np.ndarray:
        if k not in self.v:
            if self.Q4 is None:
                self.Q2 = self.Q @ self.Q
                self.Q4 = self.Q2 @ self.Q2
                self.v[3] = self.Q2 @ self.v[1]
            last = max(self.v)
            while last < k:
                if k - last >= 8 and k != last + 4:
                    if self.Q8 is None:
                        self.Q8 = self.Q4 @ self.Q4
                    self.v[last + 8] = self.Q8 @ self.v[last]
                    last += 8
                else:
                    self.v[last + 4] = self.Q4 @ self.v[last]
                    last += 4
        with np.errstate(divide="ignore"):
            top = np.log2(self.v[k][:, :, 0].max(axis=1))
        return (k - 1) * self.log_norm + top - self.log_v1


def _ell(log_ratio: np.ndarray, i: int) -> np.ndarray:
    """ell(A, m) of [1] (Algorithm 5.1): max(ceil(log2(alpha / (u / |c_{2m+1}|)) / (2m)), 0)."""
    m = _DEGREES[i]
    return np.maximum(np.ceil((log_ratio - _LOG2_COEFF[i]) / (2 * m)), 0.0)


def _ell_zero_bound(log_norm: np.ndarray, i: int) -> np.ndarray:
    """Where ell(A, m) = 0 follows from || |A|^k ||_1 / ||A||_1 <= ||A||_1^(k-1)
    alone (k = 2m + 1): the products for the exact test are then skipped, same answer."""
    return 2 * _DEGREES[i] * log_norm <= _LOG2_COEFF[i]


def _pick(X: np.ndarray, buf: np.ndarray):
    """Degree m and scaling s per stack entry: scipy's ``pick_pade_structure``.

    ``buf`` (K, 5, n, n) receives [I, A^2, A^4, A^6, A^8] (A^8 only once the m = 7 test is
    reached). Returns (m (K,) int, s (K,) int, A8_done)."""
    K = X.shape[0]
    P = np.abs(X).transpose(0, 2, 1)                  # |A|^T: 1^T |A|^k as |A|^T-powers of 1
    normA = P.sum(axis=2).max(axis=1)                 # scipy's first spin: || A ||_1
    with np.errstate(divide="ignore"):
        log_norm = np.log2(normA)
    np.matmul(X, X, out=buf[:, 1])
    np.matmul(buf[:, 1], buf[:, 1], out=buf[:, 2])
    np.matmul(buf[:, 2], buf[:, 1], out=buf[:, 3])
    d46 = np.abs(buf[:, 2:4]).sum(axis=2).max(axis=2) ** _ROOTS46
    eta1 = d46.max(axis=1)                            # [1] Algorithm 5.1, line 2
    d6 = d46[:, 1]
    m = np.full(K, 13, dtype=np.int64)
    s = np.zeros(K, dtype=np.int64)
    open_ = np.ones(K, dtype=bool)
    spins = None

    def settle(i: int, eta: np.ndarray) -> None:
        nonlocal spins
        cand = open_ & (eta < _THETA[i])
        if not cand.any():
            return
        zero = _ell_zero_bound(log_norm, i)
        if not (zero | ~cand).all():
            if spins is None:
                spins = _AbsPowers(P, normA)
            zero = zero | (_ell(spins.log_ratio(2 * _DEGREES[i] + 1), i) == 0)
        ok = cand & zero
        m[ok] = _DEGREES[i]
        open_[ok] = False

    if (eta1 < _THETA[1]).any():
        settle(0, eta1)                               # lines 3-4: m = 3
        settle(1, eta1)                               # lines 5-6: m = 5
        if not open_.any():
            return m, s, False
    A8_10 = np.matmul(buf[:, 2:4], buf[:, 2:3])       # A^8 = A^4 A^4, A^10 = A^6 A^4
    buf[:, 4] = A8_10[:, 0]
    d8_10 = np.abs(A8_10).sum(axis=2).max(axis=2) ** _ROOTS810
    d8 = d8_10[:, 0]
    eta2 = np.maximum(d6, d8)                         # line 7
    if (open_ & (eta2 < _THETA[3])).any():
        settle(2, eta2)                               # lines 8-9: m = 7
        settle(3, eta2)                               # lines 10-11: m = 9
        if not open_.any():
            return m, s, True
    eta4 = np.minimum(eta2, d8_10.max(axis=1))        # lines 12-13
    with np.errstate(divide="ignore"):
        s13 = np.maximum(np.ceil(np.log2(eta4 / _THETA[4])), 0.0)
    # line 14: s = s + ell(2^-s A, 13), with alpha(2^-s A) = 2^(-26 s) alpha(A)
    zero = _ell_zero_bound(log_norm - s13, 4)
    if not (zero | ~open_).all():
        if spins is None:
            spins = _AbsPowers(P, normA)
        s13 = s13 + np.where(zero, 0.0, _ell(spins.log_ratio(27) - 26.0 * s13, 4))
    s[open_] = s13[open_].astype(np.int64)
    return m, s, True


_ROOTS46 = np.array([1.0 / 4.0, 1.0 / 6.0])
_ROOTS810 = np.array([1.0 / 8.0, 1.0 / 10.0])


def _coefficients() -> dict[int, np.ndarray]:
    """Rows [W, V] (m <= 9) or [W2, W3, W4, W1] (m = 13) as combinations of [I, A^2, A^4,
    A^6, A^8]: U = A W, r_m = (V - U)^-1 (V + U) ([1] (2.11); m = 13: U = A (A^6 W2 + W1),
    V = A^6 W4 + W3, the evaluation (10.35) of Higham, Functions of Matrices, 2008)."""
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
    P = np.abs(a).T                                   # |A|^T, see _pick
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
        if 2 * _DEGREES[i] * (log_norm - shift) <= _LOG2_COEFF[i]:
            return True
        if spins is None:
            spins = _AbsPowers(P[None], np.array([normA]))
        k = 2 * _DEGREES[i] + 1
        return bool(_ell(spins.log_ratio(k) - (k - 1) * shift, i)[0] == 0)

    m, s = 13, 0
    if eta1 < _THETA[0] and ell_zero(0):
        m = 3
    elif eta1 < _THETA[1] and ell_zero(1):
        m = 5
    else:
        A8_10 = np.matmul(buf[2:4], buf[2])
        buf[4] = A8_10[0]
        n8, n10 = np.abs(A8_10).sum(axis=1).max(axis=1).tolist()
        d8 = n8 ** 0.125
        eta2 = max(d6, d8)
        if eta2 < _THETA[2] and ell_zero(2):
            m = 7
        elif eta2 < _THETA[3] and ell_zero(3):
            m = 9
        else:
            eta4 = min(eta2, max(d8, n10 ** 0.1))
            s = max(math.ceil(math.log2(eta4 / _THETA[4])), 0) if eta4 > 0 else 0
            if not ell_zero(4, float(s)):
                s += int(_ell(spins.log_ratio(27) - 26.0 * s, 4)[0])
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
    scipy's ``_exp_sinch``, Higham, *Functions of Matrices*, 2008, eq. (10.42)."""
    ex = np.exp(x)
    num = np.diff(ex, axis=-1)
    den = np.diff(x, axis=-1)
    same = den == 0.0
    return np.where(same, ex[..., :-1], num / np.where(same, 1.0, den))


def _check(A, name: str) -> np.ndarray:
    a = np.asarray(A)
    if np.iscomplexobj(a):
        raise TypeError(f"{name}: a real matrix is needed, got dtype {a.dtype}")
    a = np.array(a, dtype=np.float64, order="C", copy=None)
    if a.ndim < 2 or a.shape[-1] != a.shape[-2]:
        raise ValueError(f"{name}: a square matrix (n, n) or a stack (..., n, n) is needed, "
                         f"got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: the matrix has a non-finite entry")
    return a


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
    Algorithm 5.1 of Al-Mohy and Higham [1]_ as ``scipy.linalg.expm`` (1.17) implements it,
    ported statement for statement:

    - degree m in {3, 5, 7, 9, 13} and scaling s from the 1-norms of powers,
      eta = max(||A^p||^{1/p}, ||A^{p+1}||^{1/(p+1)}) ([1] Theorem 4.2, d_p and alpha_p),
      against theta_m ([1] Table 3.1), with the ell(A, m) guard against overscaling (the
      norms of |A|^{2m+1}, lines 3-14 of the algorithm; here computed without overflow,
      see ``_AbsPowers``);
    - r_m(2^-s A) = I + 2 (V - U)^-1 U with U, V the odd and even parts of p_m ([1] (2.11),
      m = 13 in the three-product scheme of Higham 2005);
    - s squarings; for a triangular matrix the diagonal and the first off-diagonal of each
      square are recomputed exactly ([1] Code Fragment 2.1, with ``_exp_sinch``), and a
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
    a = _check(A, "expm")
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
    m, s, _ = _pick(X, buf)
    s_pade = s
    s = s + s0
    R = np.empty_like(X)
    for deg in _DEGREES:
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
        # [1] Code Fragment 2.1: the diagonal of r_m(2^-s T) set to exp(2^-s diag T)
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
    """[1] Code Fragment 2.1, one squaring: R_k = e^{2^-i_k T_k} has its diagonal and first
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



# --- balance: LAPACK dgebal, job 'S' -------------------------------------------------------------

_SFMIN1 = np.finfo(float).tiny / np.finfo(float).eps * 2.0   # dlamch('S') / dlamch('P') (P = eps * base)
_SFMAX1 = 1.0 / _SFMIN1
_SFMIN2 = _SFMIN1 * 2.0
_SFMAX2 = 1.0 / _SFMIN2
STACK_FROM = 8        # stacks of this many matrices or more: every matrix's row i at once
MAX_SWEEPS = 200      # a bound on the sweeps (dgebal loops until nothing changes; each change
                      # lowers a row's and column's norm sum by 5 %, so it ends long before)


def balance(F) -> np.ndarray:
    r"""The diagonal scaling ``d`` (exact powers of two) with ``D^-1 F D`` balanced, ``D =
    diag(d)``: LAPACK ``dgebal`` with ``job = 'S'`` [2]_ (what
    ``scipy.linalg.matrix_balance(F, permute=False, separate=True)`` returns as its scale),
    for one matrix (n, n) or each matrix of a stack (..., n, n) (shape (..., n)).

    Osborne's iteration [3]_ as dgebal runs it: sweep the rows in order; for row ``i``, with
    ``c`` and ``r`` the 2-norms of column ``i`` and row ``i``, find the power of two ``f``
    bringing ``c f`` and ``r / f`` within a factor 2 of each other; apply it (row ``i`` over
    ``f``, column ``i`` times ``f``: exact in floating point) only where ``c f + r / f <
    0.95 (c + r)``; repeat until a sweep changes nothing (at most :data:`MAX_SWEEPS`). The
    guards against overflow and underflow of the scale are dgebal's (``sfmin1 = tiny / u``),
    those on the columns' and rows' largest entries left out (they only bind beyond 1e300).

    >>> F = np.array([[1.0, 1e4], [1e-4, 1.0]])
    >>> d = balance(F)
    >>> d.tolist(), (F / d[:, None] * d[None, :]).tolist()
    ([512.0, 0.0625], [[1.0, 1.220703125], [0.8192, 1.0]])
    """
    A = _check(F, "balance")
    n = A.shape[-1]
    if A.size == 0:
        return np.ones(A.shape[:-1])
    flat = A.reshape(-1, n, n)
    mag = np.abs(flat).reshape(flat.shape[0], -1)
    tiny = np.where(mag > 0.0, mag, np.inf).min(axis=1)
    wide = (mag.max(axis=1) > 2.0 ** 480) | (tiny < 2.0 ** -480)   # squares would over- or underflow
    plain = np.flatnonzero(~wide)
    out = np.ones((flat.shape[0], n))
    if plain.size >= STACK_FROM:
        out[plain] = _balance_stack(flat[plain])
    else:
        for k in plain:
            out[k] = _balance_one(flat[k].copy())
    for k in np.flatnonzero(wide):
        out[k] = _balance_one(flat[k].copy(), safe=True)
    return out.reshape(A.shape[:-1])


def _balance_one(B: np.ndarray, safe: bool = False) -> np.ndarray:
    """dgebal's loop on one matrix ``B`` (scaled in place). ``safe``: 2-norms that neither
    over- nor underflow (``math.hypot``, as dgebal's ``dnrm2`` scales), for entries beyond
    2^+-480; else ``sqrt(x . x)``."""
    n = B.shape[0]
    scale = [1.0] * n
    sqrt, hypot = math.sqrt, math.hypot
    for _ in range(MAX_SWEEPS):
        changed = False
        for i in range(n):
            col, row = B[:, i], B[i]
            if safe:
                c, r = hypot(*col.tolist()), hypot(*row.tolist())
            else:
                c, r = sqrt(float(col @ col)), sqrt(float(row @ row))
            if c == 0.0 or r == 0.0:
                continue
            g, f, s = r / 2.0, 1.0, c + r
            while c < g and max(f, c) < _SFMAX2 and min(r, g) > _SFMIN2:
                f, c, r, g = f * 2.0, c * 2.0, r / 2.0, g / 2.0
            g = c / 2.0
            while g >= r and r < _SFMAX2 and min(f, c, g) > _SFMIN2:
                f, c, g, r = f / 2.0, c / 2.0, g / 2.0, r * 2.0
            if c + r >= 0.95 * s:
                continue
            if f < 1.0 and scale[i] < 1.0 and f * scale[i] <= _SFMIN1:
                continue
            if f > 1.0 and scale[i] > 1.0 and scale[i] >= _SFMAX1 / f:
                continue
            scale[i] *= f
            changed = True
            row *= 1.0 / f
            col *= f
        if not changed:
            break
    return np.array(scale)


def _balance_stack(A: np.ndarray) -> np.ndarray:
    """:func:`_balance_one` of every matrix of a stack (R, n, n) at once: row ``i`` of every
    matrix, then row ``i + 1``, ..., with the same decisions. The two doubling loops are
    closed forms on the exponents (exact: every value is scaled by powers of two): with
    ``c = mc 2^ec``, ``r = mr 2^er`` (``frexp``) and ``e = er - ec``, loop 1 doubles ``k``
    times, the least ``k >= 0`` with ``c 2^(2k+1) >= r``: ``k = max(0, (e + [mc < mr]) // 2)``;
    where it did not run, loop 2 halves ``j`` times, the least ``j >= 0`` with ``c < r
    2^(2j+1)``: ``j = max(0, ([mc >= mr] - e) // 2)``. A matrix whose values would come
    within 2^124 of dgebal's overflow and underflow guards is balanced again alone by
    :func:`_balance_one`. A matrix is done when a sweep changes nothing in it; sweeps go on
    for the others (at most :data:`MAX_SWEEPS`)."""
    B = A.copy()
    R, n, _ = B.shape
    scale = np.ones((R, n))
    active = np.arange(R)
    extreme = np.zeros(R, dtype=bool)
    lo, hi = 2.0 ** -900, 2.0 ** 900
    for _ in range(MAX_SWEEPS):
        changed = np.zeros(active.size, dtype=bool)
        sub = B[active]
        for i in range(n):
            col, row = sub[:, :, i], sub[:, i, :]
            c = np.sqrt(np.einsum("rj,rj->r", col, col))
            r = np.sqrt(np.einsum("rj,rj->r", row, row))
            live = (c != 0.0) & (r != 0.0)
            mc, ec = np.frexp(np.where(live, c, 1.0))
            mr, er = np.frexp(np.where(live, r, 1.0))
            e = er.astype(np.int64) - ec
            up = np.maximum(0, (e + (mc < mr)) // 2)
            k = np.where(up > 0, up, -np.maximum(0, ((mc >= mr) - e) // 2))
            f = np.ldexp(1.0, k)
            cn, rn = c * f, r / f
            keep = live & (cn + rn < 0.95 * (c + r))
            if not keep.any():
                continue
            fs = scale[active, i] * f
            wild = keep & ((np.minimum(np.minimum(c, rn / 2.0), np.minimum(f, fs)) < lo)
                           | (np.maximum(np.maximum(cn, r), np.maximum(f, fs)) > hi))
            extreme[active[wild]] = True
            keep &= ~wild
            w = np.flatnonzero(keep)
            scale[active[w], i] = fs[w]
            sub[w, i, :] *= (1.0 / f[w])[:, None]
            sub[w, :, i] *= f[w][:, None]
            changed[w] = True
        B[active] = sub
        active = active[changed & ~extreme[active]]
        if active.size == 0:
            break
    for k in np.flatnonzero(extreme):
        scale[k] = _balance_one(A[k].copy(), safe=True)
    return scale
