# Ported from SciPy 1.17 (scipy/linalg/_matfuncs_expm.pyx.in, pick_pade_structure) under its license:
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

r"""Degree and scaling of the matrix exponential's Pade approximant [AH09 alg. 5.1].

:func:`degree_and_scaling` picks, for each matrix ``A`` of a stack, the degree ``m`` of the
diagonal Pade approximant ``r_m`` and the scaling ``s`` for ``e^A ~ r_m(2^-s A)^(2^s)``:
scipy's ``pick_pade_structure`` (scipy 1.17, ``_matfuncs_expm.pyx.in``), the same decisions
from the same norms. :mod:`beltcalc.numerics.expm` evaluates ``r_m`` and squares; it takes
the constants and the ``ell(A, m)`` test from here for its one-matrix path too.

References
----------
[AH09] A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
    exponential", SIAM J. Matrix Anal. Appl. 31 (2009) 970-989, doi:10.1137/09074721X.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["DEGREES", "THETA", "LOG2_COEFF", "AbsPowers", "ell", "ell_zero_bound", "degree_and_scaling"]

# --- the constants of [AH09] as scipy holds them ---------------------------------------------

DEGREES = (3, 5, 7, 9, 13)
# theta_m of [AH09 table 3.1] (the largest ||2^-s A|| for which r_m has backward error <= u)
THETA = (1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
         2.097847961257068e0, 4.25e0)
# u / |c_{2m+1}| of the ell(A, m) test, [AH09 alg. 5.1] lines 3-12: u = 2^-53 times
# the reciprocal of the leading coefficient of the Pade error series, as scipy writes them
LOG2_COEFF = tuple(math.log2(2.0 ** -53 * c) for c in (
    100800.0, 10059033600.0, 4487938430976000.0, 5914384781877411840000.0,
    113250775606021113483283660800000000.0))
# d_p = ||A^p||_1^(1/p) of [AH09 thm. 4.2], p = 4, 6 and 8, 10
_ROOTS46 = np.array([1.0 / 4.0, 1.0 / 6.0])
_ROOTS810 = np.array([1.0 / 8.0, 1.0 / 10.0])


class AbsPowers:
    r"""log2(|| |A|^k ||_1 / ||A||_1) for the ell(A, m) tests [AH09 alg. 5.1], k = 2m + 1.

    Given P = |A|^T, || |A|^k ||_1 = || P^k 1 ||_inf (|A| >= 0). scipy gets it by k products
    from v = 1 (``kth_power_norm``); here Q = P / ||A||_1 (so nothing overflows:
    || Q^k 1 ||_inf <= 1) and its powers Q^2, Q^4, Q^8 carry v from k = 1 to 3, 7, 11, 15,
    19, 27, so log2 of the ratio is (k - 1) log2 ||A||_1 + log2 ||Q^k 1|| - log2 ||Q 1||. Same
    quantity; the rounding differs, which could only move the integer ell(A, m) where its
    argument is an integer.

    Parameters
    ----------
    P : ndarray, shape (K, n, n)
        |A|^T of each matrix of the stack
    normA : ndarray, shape (K,)
        ||A||_1 of each, > 0
    """

    def __init__(self, P: np.ndarray, normA: np.ndarray):
        self.log_norm = np.log2(normA)
        self.Q = P / normA[:, None, None]
        v = self.Q.sum(axis=2)
        self.v = {1: v[:, :, None]}
        self.log_v1 = np.log2(v.max(axis=1))
        self.Q2 = self.Q4 = self.Q8 = None

    def log_ratio(self, k: int) -> np.ndarray:
        """log2(|| |A|^k ||_1 / ||A||_1) of each matrix (K,), for k = 2m + 1 (7, 11, 15, 19, 27)."""
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


def ell(log_ratio: np.ndarray, i: int) -> np.ndarray:
    """ell(A, m) of [AH09 alg. 5.1]: max(ceil(log2(alpha / (u / |c_{2m+1}|)) / (2m)), 0).

    Parameters
    ----------
    log_ratio : ndarray
        log2(|| |A|^(2m+1) ||_1 / ||A||_1) of each matrix (:meth:`AbsPowers.log_ratio`)
    i : int
        Index of the degree m = ``DEGREES[i]``

    Returns
    -------
    ndarray of float
        ell(A, m) of each matrix, an integer >= 0: the squarings the degree's bound asks for
    """
    m = DEGREES[i]
    return np.maximum(np.ceil((log_ratio - LOG2_COEFF[i]) / (2 * m)), 0.0)


def ell_zero_bound(log_norm: np.ndarray, i: int) -> np.ndarray:
    """Where ell(A, m) = 0 (m = ``DEGREES[i]``) follows from || |A|^k ||_1 / ||A||_1 <=
    ||A||_1^(k-1) alone (k = 2m + 1), given ``log_norm`` = log2 ||A||_1: the products for the
    exact test are then skipped, same answer."""
    return 2 * DEGREES[i] * log_norm <= LOG2_COEFF[i]


def degree_and_scaling(X: np.ndarray, buf: np.ndarray):
    """Degree m and scaling s per stack entry: scipy's ``pick_pade_structure`` [AH09 alg. 5.1].

    Parameters
    ----------
    X : ndarray, shape (K, n, n)
        The stack, finite, each ||A||_1 <= 2^64 (:func:`beltcalc.numerics.expm.expm` scales
        larger ones first)
    buf : ndarray, shape (K, 5, n, n)
        ``buf[:, 0]`` the identity; receives A^2, A^4, A^6 in ``buf[:, 1:4]`` and A^8 in
        ``buf[:, 4]`` once the m = 7 test is reached

    Returns
    -------
    m, s : ndarray of int64, shape (K,)
        Degree of the Pade approximant and number of squarings of each matrix
    A8_done : bool
        Whether ``buf[:, 4]`` holds A^8
    """
    K = X.shape[0]
    P = np.abs(X).transpose(0, 2, 1)                  # |A|^T: 1^T |A|^k as |A|^T-powers of 1
    normA = P.sum(axis=2).max(axis=1)                 # scipy's first spin: || A ||_1
    with np.errstate(divide="ignore"):
        log_norm = np.log2(normA)
    np.matmul(X, X, out=buf[:, 1])
    np.matmul(buf[:, 1], buf[:, 1], out=buf[:, 2])
    np.matmul(buf[:, 2], buf[:, 1], out=buf[:, 3])
    d46 = np.abs(buf[:, 2:4]).sum(axis=2).max(axis=2) ** _ROOTS46
    eta1 = d46.max(axis=1)                            # [AH09 alg. 5.1] line 2
    d6 = d46[:, 1]
    m = np.full(K, 13, dtype=np.int64)
    s = np.zeros(K, dtype=np.int64)
    open_ = np.ones(K, dtype=bool)
    spins = None

    def settle(i: int, eta: np.ndarray) -> None:
        nonlocal spins
        cand = open_ & (eta < THETA[i])
        if not cand.any():
            return
        zero = ell_zero_bound(log_norm, i)
        if not (zero | ~cand).all():
            if spins is None:
                spins = AbsPowers(P, normA)
            zero = zero | (ell(spins.log_ratio(2 * DEGREES[i] + 1), i) == 0)
        ok = cand & zero
        m[ok] = DEGREES[i]
        open_[ok] = False

    if (eta1 < THETA[1]).any():
        settle(0, eta1)                               # lines 3-4: m = 3
        settle(1, eta1)                               # lines 5-6: m = 5
        if not open_.any():
            return m, s, False
    A8_10 = np.matmul(buf[:, 2:4], buf[:, 2:3])       # A^8 = A^4 A^4, A^10 = A^6 A^4
    buf[:, 4] = A8_10[:, 0]
    d8_10 = np.abs(A8_10).sum(axis=2).max(axis=2) ** _ROOTS810
    d8 = d8_10[:, 0]
    eta2 = np.maximum(d6, d8)                         # line 7
    if (open_ & (eta2 < THETA[3])).any():
        settle(2, eta2)                               # lines 8-9: m = 7
        settle(3, eta2)                               # lines 10-11: m = 9
        if not open_.any():
            return m, s, True
    eta4 = np.minimum(eta2, d8_10.max(axis=1))        # lines 12-13
    with np.errstate(divide="ignore"):
        s13 = np.maximum(np.ceil(np.log2(eta4 / THETA[4])), 0.0)
    # line 14: s = s + ell(2^-s A, 13), with alpha(2^-s A) = 2^(-26 s) alpha(A)
    zero = ell_zero_bound(log_norm - s13, 4)
    if not (zero | ~open_).all():
        if spins is None:
            spins = AbsPowers(P, normA)
        s13 = s13 + np.where(zero, 0.0, ell(spins.log_ratio(27) - 26.0 * s13, 4))
    s[open_] = s13[open_].astype(np.int64)
    return m, s, True

