"""A switching function's polynomial on one bottom step: whether it can fire, and where.

On a bottom step of the exact solution (:mod:`beltcalc.sim.switching`) every switching
function ``r . z`` is a polynomial in the step's fraction s (its Taylor coefficients, lowest
first). Firing means rising through 0 to its firing side (``d p``, d its direction) and going
on beyond the rounding level ``tol`` there (an excursion within ``tol`` is a graze).
:func:`stays_down` rules a step out cheaply (values and rates on a grid with the bound of
p''), after the switching core's Bernstein hull; :func:`first_fire` finds the crossing.
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.sim.scalar import brentq, horner     # brentq: scipy's, bit for bit, without scipy.optimize

EPS = np.finfo(float).eps

_POWERS: dict[int, np.ndarray] = {}
STAYS_GRID = 17      # points at which stays_down reads each polynomial on [0, 1]


def stays_down(pc: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """(rows,): whether each firing-side polynomial ``pc[r]`` (coefficients, lowest first)
    cannot fire on [0, 1] (:func:`first_fire` needs a rise through 0 that goes on beyond
    ``tol``): read at STAYS_GRID points with ``|p''| <= M = sum j (j - 1) |c_j|`` between them,
    either it stays below ``-tol`` (its values plus ``M h^2 / 8``), or it starts at most ``tol``
    up and falls all the way (its rates at both ends of every cell negative, and their mean
    below ``-M h / 2``: a strand leaving the surface it was just decided on)."""
    n = pc.shape[1]
    hit = _POWERS.get(n)
    if hit is None:
        s = np.linspace(0.0, 1.0, STAYS_GRID)[None, :]
        j = np.arange(n)[:, None]
        hit = _POWERS[n] = (s ** j, np.where(j > 0, j * s ** np.maximum(j - 1, 0), 0.0))
    S, D = hit
    j = np.arange(n)
    h = 1.0 / (STAYS_GRID - 1)
    M = np.abs(pc) @ (j * (j - 1.0))
    below = (pc @ S).max(axis=1) + M * h * h / 8 < -tol
    rate = pc @ D
    mean = (rate[:, :-1] + rate[:, 1:]) / 2
    falls = (pc[:, 0] <= tol) & (rate < 0).all(axis=1) & (mean + (M * h / 2)[:, None] < 0).all(axis=1)
    return below | falls


def first_fire(c: np.ndarray, d: float, tol: float, from_start: bool, limit: float = 1.0) -> float | None:
    """The first s in [0, limit] where d * p(s) (p: coefficients ``c``, lowest first) crosses
    from <= 0 to > 0 and goes on beyond ``tol`` (an excursion that stays within ``tol`` is a
    graze). ``from_start`` False ignores an excursion already under way at s = 0 (a restart
    just decided it); True counts one that starts at s = 0 from within ``tol``."""
    pc = d * c
    top = np.flatnonzero(pc)                             # the sparse orbit's terms end in exact zeros:
    pc = pc[:max(int(top[-1]) + 1 if top.size else 1, 3)]   # p and its rates are the same without them
    dpc = np.arange(1, pc.size) * pc[1:]                 # p' and p'' (numpy's polyder, operation for operation)
    M2 = float(np.sum(np.abs(np.arange(1, dpc.size) * dpc[1:])))     # max |p''| on [0, 1]
    pl, dpl = pc.tolist(), dpc.tolist()

    def p(x: float) -> float:
        return horner(pl, float(x))

    def dp(x: float) -> float:
        return horner(dpl, float(x))

    grid = np.linspace(0.0, limit, 33)
    vals = horner(pl, grid).tolist()
    grid = grid.tolist()
    # refine gaps where the sampled values cannot rule out a hidden dip through zero
    i, guard = 0, 0
    while i < len(grid) - 1 and guard < 4000:
        a, b, va, vb = grid[i], grid[i + 1], vals[i], vals[i + 1]
        w = b - a
        bend = M2 * w * w / 8
        hidden = (va > 0) == (vb > 0) and min(abs(va), abs(vb)) <= bend and bend > tol
        if hidden or ((va > 0) != (vb > 0) and abs(dp(0.5 * (a + b))) <= M2 * w / 2 and bend > tol):
            mid = 0.5 * (a + b)
            grid.insert(i + 1, mid)
            vals.insert(i + 1, float(p(mid)))
            guard += 1
            continue
        i += 1
    vals = np.array(vals)
    grid = np.array(grid)
    k = 0
    if abs(vals[0]) <= tol:                  # on the surface at s = 0
        big = np.nonzero(np.abs(vals) > tol)[0]
        if big.size == 0:
            return None                      # stays within rounding of the surface: a graze
        k0 = int(big[0])
        if vals[k0] > 0:
            if from_start:                   # leaves the surface to the firing side: the last root before
                nonpos = np.nonzero(vals[:k0] <= 0)[0]
                if nonpos.size == 0:
                    return 0.0
                j = int(nonpos[-1]) + 1
                return float(brentq(p, grid[j - 1], grid[j], xtol=1e-16, rtol=4 * EPS, maxiter=200))
            back = np.nonzero(vals[k0:] <= 0)[0]     # a restart decided this departure: skip it
            if back.size == 0:
                return None
            k = k0 + int(back[0])
        else:
            k = k0
    elif vals[0] > 0:                        # already on the firing side: wait until it comes back
        back = np.nonzero(vals <= 0)[0]
        if back.size == 0:
            return None
        k = int(back[0])
    while k < len(vals) - 1:
        ups = np.nonzero(vals[k + 1:] > 0)[0]
        if ups.size == 0:
            return None
        j = k + 1 + int(ups[0])             # vals[j-1] <= 0 < vals[j]
        downs = np.nonzero(vals[j:] <= 0)[0]
        end = j + int(downs[0]) if downs.size else len(vals)
        peak = float(np.max(vals[j:end]))
        growing = end == len(vals) and float(dp(grid[-1])) > 0
        if peak > tol or growing:
            lo, hi = grid[j - 1], grid[j]
            if p(lo) == 0.0:
                return float(lo)
            return float(brentq(p, lo, hi, xtol=1e-16, rtol=4 * EPS, maxiter=200))
        k = end
    return None
