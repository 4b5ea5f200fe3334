# Ported from LAPACK 3.12 (SRC/dgebal.f) under its license:
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

r"""Balancing in numpy alone: LAPACK's ``dgebal``, for the time-domain core.

``scipy.linalg`` costs about 80 ms of a command's start-up; the exact core's balancing needs
none of it. :func:`balance` is LAPACK's ``dgebal`` (LAPACK 3.12, ``dgebal.f``, in 2-norms
since LAPACK 3.5.0 as [JLL14] proposed) with ``job = 'S'`` (scaling, no permutation),
statement by statement on one matrix at a time: Osborne's iteration [Osb60] in powers of two
as Parlett and Reinsch arranged it [PR69], a row and its column scaled by a power of two
where that lowers their norms' sum by 5 %. Sequential by nature (each scaling changes the
next row's norms); a simultaneous sweep over all rows oscillates. A stack of
:data:`STACK_FROM` matrices or more is swept row ``i`` of every matrix at once, with the same
decisions.

References
----------
[JLL14] R. James, J. Langou, B. R. Lowery, "On matrix balancing and eigenvector computation",
    arXiv:1401.5766 (2014).
[Osb60] E. E. Osborne, "On pre-conditioning of matrices", J. ACM 7 (1960) 338-345.
[PR69] B. N. Parlett, C. Reinsch, "Balancing a matrix for calculation of eigenvalues and
    eigenvectors", Numer. Math. 13 (1969) 293-304.
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.numerics.matrices import as_real_square

__all__ = ["balance"]

_SFMIN1 = np.finfo(float).tiny / np.finfo(float).eps * 2.0   # dlamch('S') / dlamch('P') (P = eps * base)
_SFMAX1 = 1.0 / _SFMIN1
_SFMIN2 = _SFMIN1 * 2.0
_SFMAX2 = 1.0 / _SFMIN2
STACK_FROM = 8        # stacks of this many matrices or more: every matrix's row i at once
MAX_SWEEPS = 200      # a bound on the sweeps (dgebal loops until nothing changes; each change
                      # lowers a row's and column's norm sum by 5 %, so it ends long before)


def balance(F) -> np.ndarray:
    r"""The diagonal scaling ``d`` (exact powers of two) with ``D^-1 F D`` balanced, ``D =
    diag(d)``: LAPACK ``dgebal`` with ``job = 'S'`` (what
    ``scipy.linalg.matrix_balance(F, permute=False, separate=True)`` returns as its scale),
    for one matrix (n, n) or each matrix of a stack (..., n, n) (shape (..., n)).

    Osborne's iteration [Osb60], [JLL14] as dgebal runs it: sweep the rows in order; for
    row ``i``, with ``c`` and ``r`` the 2-norms of column ``i`` and row ``i``, find the power
    of two ``f`` bringing ``c f`` and ``r / f`` within a factor 2 of each other; apply it
    (row ``i`` over ``f``, column ``i`` times ``f``: exact in floating point) only where
    ``c f + r / f < 0.95 (c + r)``; repeat until a sweep changes nothing (at most
    :data:`MAX_SWEEPS`). The guards against overflow and underflow of the scale are dgebal's
    (``sfmin1 = tiny / u``), those on the columns' and rows' largest entries left out (they
    only bind beyond 1e300).

    >>> F = np.array([[1.0, 1e4], [1e-4, 1.0]])
    >>> d = balance(F)
    >>> d.tolist(), (F / d[:, None] * d[None, :]).tolist()
    ([512.0, 0.0625], [[1.0, 1.220703125], [0.8192, 1.0]])
    """
    A = as_real_square(F, "balance")
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
