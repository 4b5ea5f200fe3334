"""The polish of extremes, shared by both watches (:mod:`beltcalc.sim.watch.blocks`,
:mod:`beltcalc.sim.watch.pieces`): the largest value of many polynomials on intervals at once
(a step's exact Taylor polynomial), the store of a sparse run's candidate steps that wait for
it, and the largest value of a signal read exactly on grids (:func:`zoom_max`: a stiff mode's
ladder, a time piece's exact solution).

Each row of a coefficient array (lowest power first, ``|s| <= 1``) is read on a grid, then
polished by safeguarded Newton steps on ``p' = 0`` in the grid cells either side of its best
point; every step is an array operation over all the rows.
"""

from __future__ import annotations

import math

import numpy as np

CURVE_SAFETY = 2.0   # the largest |s''| seen on a cell and its neighbours, times this, bounds it there
GRID = 257           # points per refinement interval before the local optimum is polished
COARSE = 9           # points per step at which a sparse mode's candidate polynomials are read first
PENDING_FLOATS = 2e6   # a sparse mode's candidate steps held for their polish, per window and side
NEWTON = 12          # safeguarded Newton steps of the vectorised polish
NEWTON_DONE = 1e-9   # ... a row done once a step moves it by at most this (of the unit step)
SHIFT_EXACT = 8      # a cell's curvature bound: its midpoint's Taylor terms below this order exact
WIDTH = 2 * COARSE + 2  # a pending step's figures: bound, a, b, coarse values, the cells' rises


class PendingSteps:
    """A sparse mode's candidate steps of one window and side that wait for their polish: per
    step its signal, the bound of its polynomial's maximum (over its COARSE - 1 cells, a cell's
    larger end value plus the most it can rise there), its coefficients (zero-padded to the
    widest mode's terms), its coarse values, its cells' rises and its interval [a, b]. Rows whose bound falls below their signal's best
    are dropped (:meth:`prune`): they cannot hold the extreme."""

    def __init__(self):
        self.n, self.cap, self.T = 0, 0, 0
        self.who = np.zeros(0, dtype=np.int64)
        self.meta = np.zeros((0, WIDTH))     # bound, a, b, coarse values, the cells' rises
        self.C = np.zeros((0, 0))

    def add(self, who, bound, C, y, rise, a, b) -> None:
        """Hold the steps given: signals ``who``, bounds, coefficients C (steps, terms), coarse
        values y, the cells' rises (steps, COARSE - 1) and intervals [a, b]; the store grows
        (doubling) as needed."""
        k, T = who.size, max(self.T, C.shape[1])
        if self.n + k > self.cap or T > self.T:
            cap = max(2 * self.cap, self.n + k, 64)
            grown = np.zeros((cap, T))
            grown[:self.n, :self.T] = self.C[:self.n]
            self.C, self.T = grown, T
            self.who = np.concatenate([self.who[:self.n], np.zeros(cap - self.n, dtype=np.int64)])
            self.meta = np.vstack([self.meta[:self.n], np.zeros((cap - self.n, WIDTH))])
            self.cap = cap
        rows = slice(self.n, self.n + k)
        self.who[rows] = who
        self.C[rows, :C.shape[1]] = C
        self.C[rows, C.shape[1]:] = 0.0
        self.meta[rows, 0], self.meta[rows, 1], self.meta[rows, 2] = bound, a, b
        self.meta[rows, 3:3 + COARSE] = y
        self.meta[rows, 3 + COARSE:] = rise
        self.n += k

    def prune(self, best: np.ndarray) -> None:
        """Drop the rows whose bound is below their signal's best value."""
        keep = np.flatnonzero(self.meta[:self.n, 0] >= best[self.who[:self.n]])
        if keep.size < self.n:
            m = keep.size
            self.who[:m], self.C[:m], self.meta[:m] = self.who[keep], self.C[keep], self.meta[keep]
            self.n = m

    def full(self) -> bool:
        """Whether the rows held take more than PENDING_FLOATS."""
        return self.n * (self.T + WIDTH + 1) > PENDING_FLOATS

    def crowded(self) -> bool:
        """Whether the rows held take more than half of PENDING_FLOATS."""
        return 2 * self.n * (self.T + WIDTH + 1) > PENDING_FLOATS

    def rows(self):
        """(who, bound, C, y, rise, a, b) of the rows held (rise: per cell)."""
        n, m = self.n, self.meta
        return self.who[:n], m[:n, 0], self.C[:n], m[:n, 3:3 + COARSE], m[:n, 3 + COARSE:], m[:n, 1], m[:n, 2]

    def clear(self) -> None:
        """Drop every row."""
        self.n = 0

    def polish(self, best: np.ndarray) -> None:
        """Raise ``best`` by the maximum of every row that may still hold it
        (:func:`polish_steps`), and drop every row."""
        self.prune(best)
        if self.n:
            who, _, C, y, rise, a, b = self.rows()
            s_c = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, COARSE)[None, :]
            polish_steps(best, who, trim_terms(C), s_c, y, rise, a, b)
        self.clear()


def trim_terms(C: np.ndarray) -> np.ndarray:
    """C without its trailing columns of exact zeros (a sparse orbit's Taylor terms end in
    them): the same polynomials, fewer terms to evaluate."""
    live = np.flatnonzero(C.any(axis=0))
    return C[:, :int(live[-1]) + 1 if live.size else 1]


def polish_steps(best, who, C, s_c, y, rise, a, b) -> None:
    """Raise ``best`` by each step polynomial's maximum: Newton in the two coarse cells
    around its best coarse point; in every other cell whose larger end value plus its
    ``rise`` (per cell, or one per step) still reaches what that found, the full search
    (:func:`polish_polynomials`) on the cell, at the density the whole step's GRID gives."""
    r = np.arange(C.shape[0])
    i = np.argmax(y, axis=1)
    lo, hi = s_c[r, np.maximum(i - 1, 0)], s_c[r, np.minimum(i + 1, COARSE - 1)]
    found = np.maximum(y[r, i], newton_max(C, s_c[r, i], lo, hi, 2 * NEWTON))
    cell = np.maximum(y[:, :-1], y[:, 1:]) + (rise if rise.ndim == 2 else rise[:, None])
    k = np.arange(COARSE - 1)[None, :]
    cell[(k == i[:, None] - 1) | (k == i[:, None])] = -np.inf
    row, at = np.nonzero(cell >= found[:, None])
    if row.size:
        grid = (GRID - 1) // (COARSE - 1) + 1
        np.maximum.at(found, row, polish_polynomials(C[row], s_c[row, at], s_c[row, at + 1], grid))
    np.maximum.at(best, who, found)



def zoom_max(read, a: float, b: float, points: int, levels: int) -> tuple[float, float]:
    """(the largest value of a signal on [a, b], where) off grids of its exact values:
    ``points`` evenly spaced on [a, b], then ``points`` across the two grid cells either side of
    the best one, ``levels`` grids in all (each spacing (points - 1) / 2 times finer than the
    last); the best value of every grid. ``read(t0, d, i)`` gives the signal at ``t0 + j d``,
    ``j < points``, where ``t0`` is point ``i`` of the grid read before (None on the first), so a
    reader that carries the exact state along its grid starts from the state it holds.

    From an interval of an eighth of a period, five grids of 65 points put the best point within
    (b - a) 1.5e-8 of the top, where the signal is below it by (2 pi 1e-8)^2 / 2 of its
    amplitude: rounding. The first grid must see the top's hump (as a bounded search's bracket).

    >>> round(zoom_max(lambda t0, d, i: -(t0 + d * np.arange(65) - 0.3) ** 2, 0.0, 1.0, 65, 5)[1], 7)
    0.3
    """
    best, where = -np.inf, a
    t0, width, i = a, b - a, None
    for _ in range(levels):
        d = width / (points - 1)
        y = read(t0, d, i)
        j = int(np.argmax(y))
        if y[j] >= best:
            best, where = float(y[j]), t0 + j * d
        lo, hi = max(j - 1, 0), min(j + 1, points - 1)
        t0, width, i = t0 + lo * d, (hi - lo) * d, lo
    return best, where


def seen_rise(curvature, spacing):
    """The candidate rule of both watches (:class:`beltcalc.sim.watch.blocks.Watch`,
    :func:`beltcalc.sim.watch.pieces.exact_signals`): between two points a spacing d apart, a
    signal rises above the larger of its two values by at most ``max |s''| d^2 / 8``, with
    max |s''| taken as CURVE_SAFETY times the largest ``curvature`` (|s''|) seen at the cell's
    points and its neighbours'. A cell whose larger value plus this reaches the best value seen
    is a candidate, polished on the exact solution; no other cell can hold the extreme."""
    return CURVE_SAFETY * curvature * (spacing * spacing / 8)


def cell_rises(C: np.ndarray, s_c: np.ndarray) -> np.ndarray:
    """(rows, cells): the most each polynomial row of C (lowest power first) can rise above
    the larger of its values at the ends of each cell between the points ``s_c`` (rows,
    cells + 1): ``max |p''| d^2 / 8`` on a cell of width d. The bound of |p''| comes from the
    polynomial about the cell's midpoint m, ``p(m + u) = sum q_i u^i``:
    ``|p''| <= sum i (i - 1) |q_i| (d / 2)^(i - 2)``, with ``q_i = p^(i)(m) / i!`` exact for
    i < SHIFT_EXACT and bounded above it by ``sum_j binom(j, i) |c_j| M^(j - i)`` (M the
    largest of 1 and |s|): those terms carry (d / 2)^6 and less. It is close to the largest
    |p''| on the cell (a step's polynomial, where the bound from the coefficients about the
    step's start, ``sum j (j - 1) |c_j|``, is some 80 times too large for the longer steps of
    the error estimate's second run). Rounding: T eps of that coefficient bound, added."""
    P, T = C.shape
    if T < 3:
        return np.zeros((P, s_c.shape[1] - 1))
    m = 0.5 * (s_c[:, :-1] + s_c[:, 1:])                       # (rows, cells)
    half = 0.5 * (s_c[:, 1:] - s_c[:, :-1])
    j = np.arange(T)
    binom = np.array([[math.comb(int(n), int(i)) for i in j] for n in j], dtype=float)   # [j, i]
    top = min(SHIFT_EXACT, T)
    q = [np.abs(horner_rows(C[:, i:] * binom[i:, i], m)) for i in range(2, top)]
    M = np.maximum(1.0, np.abs(s_c).max(axis=1))
    Q = ((np.abs(C) * M[:, None] ** j) @ binom) / M[:, None] ** j     # bounds of |q_i|, every i
    curve = np.zeros(m.shape)
    for i in range(T - 1, 1, -1):                              # Horner in d / 2
        curve = curve * half + i * (i - 1.0) * (q[i - 2] if i < top else Q[:, i, None])
    far = (np.abs(C) * M[:, None] ** j) @ (j * (j - 1.0))
    curve += T * np.finfo(float).eps * far[:, None]
    return curve * (2.0 * half) ** 2 / 8


def horner_rows(C: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Row r of C (coefficients, lowest first) at the points x[r] (x: (rows,) or (rows, points))."""
    c = np.ascontiguousarray(C.T)              # a column per term: each step reads one row
    if x.ndim > 1:
        c = c[:, :, None]
    y = np.zeros(x.shape)
    for j in range(C.shape[1] - 1, -1, -1):
        y *= x
        y += c[j]
    return y


def polish_polynomials(C: np.ndarray, a: np.ndarray, b: np.ndarray, grid: int = GRID) -> np.ndarray:
    """The largest value of each polynomial ``sum_j C[r, j] s^j`` on [a[r], b[r]] (|s| <= 1),
    all at once: a grid of ``grid`` points, then safeguarded Newton steps on ``p' = 0`` inside
    the grid cells either side of the grid's best point (a bisection step wherever Newton
    would leave the bracket or p is not concave there). Never below the grid's best value;
    -inf where the interval is empty. Newton converges quadratically from a cell of
    (b - a) / 256: the value is the polynomial's maximum to rounding, as a bounded Brent
    search to 1e-9 of the interval gives it (``tests/test_watch.py``)."""
    P, T = C.shape
    out = np.full(P, -np.inf)
    ok = b > a
    if not ok.any():
        return out
    C, a, b = C[ok], a[ok], b[ok]
    rows = np.arange(C.shape[0])
    s = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, grid)[None, :]
    y = horner_rows(C, s)
    i = np.argmax(y, axis=1)
    best = y[rows, i]
    lo, hi, x = s[rows, np.maximum(i - 1, 0)], s[rows, np.minimum(i + 1, grid - 1)], s[rows, i]
    out[ok] = np.maximum(best, newton_max(C, x, lo, hi, NEWTON))
    return out


def newton_max(C: np.ndarray, x: np.ndarray, lo: np.ndarray, hi: np.ndarray, steps: int) -> np.ndarray:
    """The largest value of each polynomial row of C on its bracket [lo, hi] around x, by
    safeguarded Newton steps on ``p' = 0`` (a bisection step wherever Newton would leave the
    bracket or p is not concave there), at most ``steps`` of them: the best of p at the last x
    and the bracket's ends. A row is done once a Newton step moves it by at most NEWTON_DONE
    (of the unit step): quadratic convergence has then put x within rounding of the root of
    p', where p is flat to rounding (|p''| NEWTON_DONE^2 is below eps |p|)."""
    T = C.shape[1]
    D1 = C[:, 1:] * np.arange(1, T)
    D2 = D1[:, 1:] * np.arange(1, T - 1)
    x, lo, hi = x.astype(float, copy=True), lo.astype(float, copy=True), hi.astype(float, copy=True)
    live = np.arange(C.shape[0])
    for _ in range(steps):
        if not live.size:
            break
        xs, D1l, D2l = x[live], D1[live], D2[live]
        d1, d2 = horner_rows(D1l, xs), horner_rows(D2l, xs)
        lo_l = np.where(d1 > 0, xs, lo[live])                 # the maximum lies where p' changes sign
        hi_l = np.where(d1 < 0, xs, hi[live])
        with np.errstate(divide="ignore", invalid="ignore"):
            move = d1 / d2
        step = xs - move
        good = (d2 < 0) & (step > lo_l) & (step < hi_l)
        x[live] = np.where(good, step, 0.5 * (lo_l + hi_l))
        lo[live], hi[live] = lo_l, hi_l
        live = live[~(good & (np.abs(move) <= NEWTON_DONE))]
    return np.maximum(horner_rows(C, x), np.maximum(horner_rows(C, lo), horner_rows(C, hi)))
