"""Exact extremes of chosen signals over windows, read off the exact solution.

The switching core (:mod:`beltcalc.sim.switching`) steps the exact solution on internal
bottom steps chosen from the dynamics alone, never from the output grid. A :class:`Watch`
sees the state at every step point and piece end, keeps for each signal and window
``[start, t_end]`` the point where the signal is largest (and smallest), and at the end of
the run maximises the signal's exact Taylor polynomial around that point: within one step
either side, inside the strand-mode piece and the window. The result does not depend on the
output samples; its accuracy is that of the polynomial (rounding), except where two peaks
of one signal lie within the polynomial's sampling error of each other (then it is the
lower one, off by less than that difference).

Signals are rows over the state ``z = [x, g]``: a state, a coupling torque, or a strand
force (its row while taut, zero while slack).
"""

from __future__ import annotations

import numpy as np

from beltcalc.sim.scalar import bounded_minimum, horner

GRID = 257          # points per refinement interval before the local optimum is polished


class Watch:
    """Extremes of ``names`` (rows ``rows`` over z, unbalanced; ``strand[k]`` the strand
    index of a strand force, else -1) over each window ``[start, t_end]``."""

    def __init__(self, names: list[str], rows: np.ndarray, strand: np.ndarray, windows: list[float]):
        self.names, self.rows, self.strand = list(names), np.asarray(rows, dtype=float), np.asarray(strand)
        self.windows = [float(w) for w in windows]
        self.result: dict[tuple[str, float], tuple[float, float]] = {}

    def bind(self, run) -> None:
        """Attach to a run: rows in its balanced coordinates, empty records."""
        self.run = run
        self.O = self.rows * run.S[None, :]
        nw, k, size = len(self.windows), len(self.names), run.S.size
        self.best = {side: np.full((nw, k), -np.inf) for side in (1, -1)}     # side * value, largest
        self.z = {side: np.zeros((nw, k, size)) for side in (1, -1)}
        self.t = {side: np.zeros((nw, k)) for side in (1, -1)}
        # the step point before the best one (the stiff ladder reads forward only: the peak
        # may lie in the step that ends at the best point)
        self.z_prev = {side: np.zeros((nw, k, size)) for side in (1, -1)}
        self.t_prev = {side: np.full((nw, k), np.nan) for side in (1, -1)}
        self._last: tuple[np.ndarray, float, int] | None = None
        self.key = {side: np.empty((nw, k), dtype=object) for side in (1, -1)}
        self.piece = {side: np.zeros((nw, k), dtype=np.int64) for side in (1, -1)}
        self.piece_start: list[float] = []

    def values(self, taut: tuple[bool, ...], Z: np.ndarray) -> np.ndarray:
        """(rows of Z, signals): the signals at the states Z in the strand pattern ``taut``."""
        v = Z @ self.O.T
        if self.strand.size and (self.strand >= 0).any():
            on = np.ones(len(self.names), dtype=bool)
            s = self.strand >= 0
            on[s] = np.asarray(taut, dtype=bool)[self.strand[s]]
            v[:, ~on] = 0.0
        return v

    def update(self, mode, Z: np.ndarray, times: np.ndarray, piece: int) -> None:
        """Step points Z (rows, balanced) at ``times`` of piece number ``piece`` in ``mode``."""
        while len(self.piece_start) <= piece:
            self.piece_start.append(float(times[0]))
        vals = self.values(mode.taut, Z)
        cols = np.arange(vals.shape[1])
        for w, start in enumerate(self.windows):
            inside = np.nonzero(times >= start)[0]
            if inside.size == 0:
                continue
            for side in (1, -1):
                v = side * vals[inside]
                at = np.argmax(v, axis=0)
                top = v[at, cols]
                better = top > self.best[side][w]
                if better.any():
                    rows = inside[at[better]]
                    self.best[side][w, better] = top[better]
                    self.z[side][w, better] = Z[rows]
                    self.t[side][w, better] = times[rows]
                    self.piece[side][w, better] = piece
                    for k, r in zip(np.nonzero(better)[0], rows):
                        if r > 0:
                            self.z_prev[side][w, k], self.t_prev[side][w, k] = Z[r - 1], times[r - 1]
                        elif self._last is not None and self._last[2] == piece:
                            self.z_prev[side][w, k], self.t_prev[side][w, k] = self._last[0], self._last[1]
                        else:
                            self.t_prev[side][w, k] = np.nan
                    for k in np.nonzero(better)[0]:
                        self.key[side][w, k] = mode.key     # (pattern, piece, time): the cache rebuilds it
        self._last = (Z[-1].copy(), float(times[-1]), piece)

    def finish(self) -> None:
        """Polish every recorded extreme on the exact polynomial around its point."""
        run = self.run
        ends = run.piece_ends + [run.t_end]
        for w, start in enumerate(self.windows):
            for side in (1, -1):
                for k, name in enumerate(self.names):
                    best = self.best[side][w, k]
                    if not np.isfinite(best):
                        continue
                    mode = run.cache.get(*self.key[side][w, k])
                    tz, p = self.t[side][w, k], self.piece[side][w, k]
                    lo_t = max(start, self.piece_start[p], tz - mode.h)
                    hi_t = min(run.t_end, ends[p], tz + mode.h)
                    value = best
                    if hi_t > lo_t and not (self.strand[k] >= 0 and not mode.taut[self.strand[k]]):
                        starts = [(self.z[side][w, k], tz)]
                        t_prev = self.t_prev[side][w, k]
                        if mode.K and np.isfinite(t_prev):     # the stiff ladder reads forward only
                            starts.insert(0, (self.z_prev[side][w, k], t_prev))
                        for z0, t0 in starts:
                            f = self._polynomial(mode, z0, k, side)
                            a, b = (lo_t - t0) / mode.h, (hi_t - t0) / mode.h
                            if mode.K:
                                a, b = max(a, 0.0), min(b, 1.0)
                            value = max(value, self._polish(f, a, b))
                    if self.strand[k] >= 0:        # a taut strand pulls: what rounds below zero at a switch is zero
                        value = max(value, 0.0) if side == 1 else min(value, 0.0)
                    key = (name, start)
                    lo_v, hi_v = self.result.get(key, (np.nan, np.nan))
                    if side == 1:
                        self.result[key] = (lo_v, value)
                    else:
                        self.result[key] = (-value, hi_v)

    @staticmethod
    def _polish(f, a: float, b: float) -> float:
        """The largest value of f on [a, b]: a grid, then a bounded search around its best
        point. ``f`` is a pair: the function on an array of points, and on one float."""
        if not b > a:
            return -np.inf
        on_grid, at = f
        s = np.linspace(a, b, GRID)
        y = on_grid(s)
        i = int(np.argmax(y))
        value = float(y[i])
        lo, hi = s[max(i - 1, 0)], s[min(i + 1, GRID - 1)]
        if hi > lo:
            _, fun, _ = bounded_minimum(lambda x: -at(x), lo, hi, xatol=1e-9 * (b - a))
            value = max(value, -fun)
        return value

    def _polynomial(self, mode, z: np.ndarray, k: int, side: int):
        """side * signal k at the point z + s h (s in units of the mode's step) as a function
        of s: (on an array of s, on one float s)."""
        row = self.O[k]
        if mode.K == 0:
            c = (side * (mode.taylor(z) @ row)).tolist()      # p(s) = sum_j c_j s^j, |s| <= 1 (||F~ L|| = THETA)
            return (lambda s: horner(c, s)), (lambda s: horner(c, float(s)))

        def g(s):                                       # stiff ladder: forward from z
            return side * (mode.at(np.repeat(z[None], s.size, axis=0), s * mode.h) @ row)
        return g, lambda s: float(g(np.array([s]))[0])
