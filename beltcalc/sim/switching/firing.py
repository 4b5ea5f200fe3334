"""Where a switching function fires: the event location of the switching core.

On a bottom step of the exact solution (:mod:`beltcalc.sim.switching`) every switching
function ``r . z`` is a polynomial in the step's fraction s (its Taylor coefficients, lowest
first). Firing means rising through 0 to its firing side (``d p``, d its direction) and going
on beyond the rounding level ``tol`` there (an excursion within ``tol`` is a graze; ``tol``
is ROUND times the magnitudes the value is summed from). The tests, cheapest first:

* :func:`may_cross` (a stiff mode's coarse steps): a sign change at the step's ends, or the
  cubic Hermite through their values and rates reaching zero;
* the reach of the polynomial (``sum_(j>=1) |c_j|``) against its value, in
  :func:`first_crossing` (and bounded without the polynomial by the modes);
* :func:`may_fire`: the convex hull of its Bernstein coefficients [FR88 eq. 11];
* :func:`stays_down`: values and rates on a grid with the bound of p'';
* :func:`first_fire`: the crossing itself, by sampling, refinement and Brent's method.

:func:`first_crossing` runs them on a block of steps and returns the first crossing.

References:

[FR88] R. T. Farouki and V. T. Rajan, "Algorithms for polynomials in Bernstein form",
    Comput. Aided Geom. Des. 5 (1988) 1-26.
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.numerics.scalar import brentq, horner     # brentq: scipy's, bit for bit, without scipy.optimize

EPS = np.finfo(float).eps
ROUND = 1024 * EPS   # rounding level of a switching function, relative to sum |r_i z_i|

_POWERS: dict[int, np.ndarray] = {}
_BERNSTEIN: dict[int, np.ndarray] = {}
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


def _bernstein(terms: int) -> np.ndarray:
    """The matrix taking a polynomial's coefficients on [0, 1] (``terms`` of them, lowest
    first) to its Bernstein coefficients, ``b_i = sum_(j<=i) C(i, j) / C(n, j) c_j`` (n the
    degree) [FR88 eq. 11]: positive weights, so each b_i rounds within a few eps of
    ``sum |c_j|``."""
    W = _BERNSTEIN.get(terms)
    if W is None:
        n = terms - 1
        W = np.zeros((terms, terms))
        for i in range(terms):
            for j in range(i + 1):
                W[i, j] = math.comb(i, j) / math.comb(n, j)
        W = _BERNSTEIN[terms] = W
    return W


def may_fire(pc: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """(events, columns): whether each firing-side polynomial ``pc[:, e, q]`` (terms first,
    ``d p`` of :func:`first_fire`) can fire on [0, 1] at all, by the convex hull of its
    Bernstein coefficients (every value of p on [0, 1] lies between their least and largest)
    [FR88]: not if it never rises above 0, nor if it starts on the firing side beyond ``tol``
    and never comes back to 0. Every step this rules out is one ``first_fire`` would have
    refused after sampling and refining it (a strand at rest on its surface, its values
    exactly 0 at the step's start: hundreds of refinements each)."""
    T, E, Q = pc.shape
    B = (_bernstein(T) @ pc.reshape(T, E * Q)).reshape(T, E, Q)
    stays_up = (pc[0] > tol) & (B.min(axis=0) > 0)
    return (B.max(axis=0) > 0) & ~stays_up


def first_crossing(mode, Z: np.ndarray, first: bool, limit: float = 1.0, C: np.ndarray | None = None,
                   cleared: int = 0):
    """The first crossing on the bottom steps Z[i] -> Z[i+1] (rows) of ``mode``
    (:class:`beltcalc.sim.switching.mode.Mode`): (i, s, event) or None.
    ``first``: Z[0] is a restart point. ``limit``: fraction of the last step to examine.
    ``C``: the steps' polynomial coefficients when the orbit already has them; ``cleared``:
    the first steps the orbit already found no switching function near zero on (its
    ``stop_early`` test is the candidate test below)."""
    if not mode.n_events:
        return None
    count = Z.shape[0] - 1
    if C is None:                 # dense: bound first, the full polynomial only where needed
        steps = np.nonzero(mode.near(Z[:count]).any(axis=0))[0]
        if steps.size == 0:
            return None
        C = mode.coeffs(Z[steps])
    else:
        steps = np.arange(cleared, count)
        C = C[:, :, cleared:count]
    tol = mode.levels(Z[steps])                                          # (E, steps)
    reach = np.abs(C[1:]).sum(axis=0)
    cand = (np.abs(C[0]) <= reach + tol) & (reach + np.abs(C[0]) > tol)
    e, q = np.nonzero(cand)
    if e.size:                  # the hull of each candidate's own polynomial (few of E x steps)
        cand[e, q] = may_fire((C[:, e, q] * mode.dirs[e])[:, None, :], tol[e, q][None, :])[0]
    for q in np.nonzero(cand.any(axis=0))[0]:      # q: column of C, steps[q]: the step
        i, best = int(steps[q]), None
        for e in np.nonzero(cand[:, q])[0]:
            lim = limit if i == count - 1 else 1.0
            s = first_fire(C[:, e, q], mode.dirs[e], float(tol[e, q]), not (first and i == 0), lim)
            if s is not None and (best is None or s < best[0]):
                best = (s, int(e))
        if best is not None:
            return i, best[0], best[1]
    return None


def may_cross(mode, Z0: np.ndarray, Z1: np.ndarray, w: float) -> np.ndarray:
    """Per step Z0[i] -> Z1[i] (rows, w long) of a stiff mode's ladder: whether a switching
    function may cross zero inside it: a sign change, or the cubic Hermite through values and
    rates reaching zero."""
    G0, G1 = Z0 @ mode.H.T, Z1 @ mode.H.T
    D0, D1 = (Z0 @ mode.Ft.T) @ mode.H.T * w, (Z1 @ mode.Ft.T) @ mode.H.T * w
    tol = ROUND * (np.abs(Z0) @ mode.absH.T) + 1e-300
    change = ((G0 > tol) != (G1 > tol)) | ((G0 < -tol) != (G1 < -tol))
    dG = G1 - G0
    reach = 4 / 27 * (np.abs(D0 - dG) + np.abs(D1 - dG))
    near = np.minimum(np.abs(G0), np.abs(G1)) <= reach + tol
    return np.any(change | near, axis=-1)
