"""Exact extremes of chosen signals over windows, read off the exact solution.

The switching core (:mod:`beltcalc.sim.switching`) steps the exact solution on internal
bottom steps chosen from the dynamics alone, never from the output grid. A :class:`Watch`
sees the state at every step point and piece end, and each signal also half way through
every step, with its second derivative there and at the points (rows ``O F~^2``). A peak
between the points seen can rise above them by at most ``max |s''| d^2 / 8`` (d the spacing
of the points seen; CURVE_SAFETY on it): every step whose seen values plus that bound reach
the best value seen is a candidate. The result does not depend on the output samples.

* Dense modes keep up to C candidate steps per signal, side and window (the highest bounds;
  their points in one shared pool) and at the end of the run maximise each signal's exact
  Taylor polynomial around each: within one step either side, inside the strand-mode piece
  and the window. What was let go is kept as :attr:`Watch.uncertain` (its bound less the
  extreme found) and goes into the run's error estimate. A stiff mode is seen at every
  bottom step where the run's budget allows (:meth:`Watch.walks`); beyond it the candidates
  are its coarse step points, 2^K bottom steps apart (docs/switching.md).
* Sparse modes (large networks) read each block in one product of the signals' rows (values,
  midpoints, slopes and curvatures: F~ applied to the states, nothing formed per strand
  pattern); a step on which a signal is monotone (its end slopes and the curvature bound) is
  no candidate. Each candidate step's exact Taylor polynomial (the orbit's own terms) is read
  at COARSE points at once, and waits for its polish while it may still hold the extreme
  (:meth:`Watch._settle`, :mod:`beltcalc.sim.watch.polish`): nothing is let go.

Signals are rows over the state ``z = [x, g]``: a state, a coupling torque, or a strand
force (its row while taut, zero while slack).
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.numerics.expm import expm
from beltcalc.sim.watch.polish import (COARSE, CURVE_SAFETY, GRID, PendingSteps, cell_rises, horner_rows,
                                       polish_polynomials, seen_rise, trim_terms, zoom_max)
from beltcalc.sim.propagate import orbit

MAX_CANDIDATES = 16    # candidate steps polished per signal, side and window ...
CANDIDATE_BYTES = 64e6  # ... as far as their step points fit this much
KEPT_MODES = 8         # modes whose signal rows (half step, second derivative) are kept
FLAT = 1e-14          # ... and polished only where they may rise by more than this, relative
SETTLE_FLOATS = 4e6    # polynomial coefficients a sparse mode's candidate steps form at once
LADDER_POINTS = 4096   # a stiff mode's extreme: its bottom-step points walked where at most this many ...
LADDER_ZOOM = 4        # ... else grids of GRID points searched on its ladder (the last 2e-9 of the step apart)
WALK_POINTS = 2e6      # a stiff mode is watched at every bottom step where the run has at most this many ...
WALK_BYTES = 32e6      # ... and its 2^K powers of expm(F~ L) take at most this much
WALK_CHUNK = 2e6       # floats of bottom-step points formed at once


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
        # a large network's signal rows are sparse (a speed reads one state, a torque four)
        self.Op = self.O
        if run.sparse:
            from scipy import sparse

            self.Op = sparse.csr_matrix(self.O)
            self.Op.sort_indices()
            self._csr = (self.Op.indptr.astype(np.int64), self.Op.indices.astype(np.int64), self.Op.data)
        # the run takes free rigid rotations out of the angles as it goes (Run.rebase): a
        # signal that sees them (an angle) is not watched; the samples give its extremes
        rigid = getattr(run, "rigid", np.zeros((0, run.S.size)))
        self.moves = (np.abs(self.rows @ rigid.T) > 1e-9 * np.abs(self.rows).sum(axis=1)[:, None]).any(axis=1) \
            if rigid.size else np.zeros(len(self.names), dtype=bool)
        nw, k, size = len(self.windows), len(self.names), run.S.size
        # up to C candidate steps per signal, side and window (memory: CANDIDATE_BYTES)
        C = self.C = int(min(MAX_CANDIDATES, max(1, CANDIDATE_BYTES // max(1, nw * k * size * 8 * 4))))
        self.best = {side: np.full((nw, k), -np.inf) for side in (1, -1)}     # side * value, largest seen
        self.u = {side: np.full((nw, k, C), -np.inf) for side in (1, -1)}     # each candidate's bound
        self.dropped = {side: np.full((nw, k), -np.inf) for side in (1, -1)}  # the largest bound let go
        # each candidate's step point, and the step point before it (the stiff ladder reads
        # forward only: the peak may lie in the step that ends at the candidate's point), as rows
        # of one pool of points: the signals whose candidates enter at one step share its row
        # (a start-up raises the best value of every signal at every block's end)
        self.zi = {side: np.zeros((nw, k, C), dtype=np.int64) for side in (1, -1)}
        self.zi_prev = {side: np.zeros((nw, k, C), dtype=np.int64) for side in (1, -1)}
        self.t = {side: np.zeros((nw, k, C)) for side in (1, -1)}
        self.t_prev = {side: np.full((nw, k, C), np.nan) for side in (1, -1)}
        self.pool = np.zeros((min(64, 4 * nw * k * C), size))
        self.pooled = 0
        self._last: tuple[np.ndarray, float, int] | None = None
        self.key = {side: np.zeros((nw, k, C), dtype=np.int64) for side in (1, -1)}   # index into self.keys
        self.keys: list[tuple] = []          # mode keys (pattern, piece, time): the cache rebuilds the mode
        self._key_index: dict[tuple, int] = {}
        self.piece = {side: np.zeros((nw, k, C), dtype=np.int64) for side in (1, -1)}
        self.piece_start: list[float] = []
        self._half: dict[tuple, tuple] = {}
        self._second: dict[tuple, np.ndarray] = {}
        self.uncertain: dict[tuple[str, float], tuple[float, float]] = {}
        self._pending = {side: [PendingSteps() for _ in self.windows] for side in (1, -1)}

    def values(self, taut: tuple[bool, ...], Z: np.ndarray) -> np.ndarray:
        """(signals, rows of Z): the signals at the states Z in the strand pattern ``taut``
        (signal-major: the extremes are reductions along contiguous rows)."""
        v = self.Op @ Z.T
        if self.strand.size and (self.strand >= 0).any():
            v[self._slack(taut)] = 0.0
        return v

    def _slack(self, taut: tuple[bool, ...]) -> np.ndarray:
        """Which signals are the force of a strand slack in ``taut`` (zero there)."""
        on = np.ones(len(self.names), dtype=bool)
        s = self.strand >= 0
        on[s] = np.asarray(taut, dtype=bool)[self.strand[s]]
        return ~on

    def walks(self, mode) -> bool:
        """Whether a stiff mode is watched at its bottom steps (``expm(F~ L)`` powers from each
        coarse step point) rather than at its coarse step points, 2^K bottom steps apart,
        between which a signal that rings (a stiff coupling's torque) may peak unseen: where
        the run has at most WALK_POINTS bottom steps and the powers fit WALK_BYTES."""
        m = mode.size
        return bool(mode.K and not mode.sparse and self.run.t_end / mode.L <= WALK_POINTS
                    and 2 ** mode.K * m * m * 8 <= WALK_BYTES)

    def update(self, mode, Z: np.ndarray, times: np.ndarray, piece: int) -> None:
        """Step points Z (rows, balanced) at ``times`` (ascending) of piece number ``piece`` in
        ``mode``: each signal's largest and smallest value per window, with the step point
        before it. A stiff mode that :meth:`walks` is seen at every bottom step between."""
        if Z.shape[0] > 1 and self.walks(mode):
            for Zb, tb in self._bottom_points(mode, Z, times):
                self._update(mode, Zb, tb, piece)
            return
        self._update(mode, Z, times, piece)

    def _bottom_points(self, mode, Z: np.ndarray, times: np.ndarray):
        """The bottom-step points of the coarse steps Z[i] -> Z[i+1] (those before Z[i+1]; a
        short last step keeps its own), in chunks, then Z[-1]: ``P^j Z[i]``, j < 2^K, with
        ``P = expm(F~ L)`` and its powers kept on the mode."""
        n, m = 2 ** mode.K, Z.shape[1]
        powers = getattr(mode, "_walk_powers", None)
        if powers is None:
            powers = np.empty((n, m, m))
            powers[0] = np.eye(m)
            filled, step = 1, mode.P(mode.K)
            while filled < n:                       # by doubling: P^(k + filled) = P^filled P^k
                k = min(filled, n - filled)
                powers[filled:filled + k] = step @ powers[:k]
                filled += k
                step = step @ step
            # one matrix (m, n m): column block j is (P^j)^T, so Z @ it is every P^j z in one GEMM
            powers = mode._walk_powers = np.ascontiguousarray(powers.transpose(2, 0, 1).reshape(m, n * m))
        per = max(1, int(WALK_CHUNK / (n * m)))
        offsets = np.arange(n) * mode.L
        for a in range(0, Z.shape[0] - 1, per):
            b = min(a + per, Z.shape[0] - 1)
            Zb = (Z[a:b] @ powers).reshape(-1, m)          # rows: (i, j) -> P^j Z[i]
            tb = (times[a:b, None] + offsets[None, :]).reshape(-1)
            keep = tb < np.repeat(times[a + 1:b + 1], n)
            if not keep.all():
                Zb, tb = Zb[keep], tb[keep]
            # each chunk ends on the next one's first point: no step is left between chunks
            yield np.vstack([Zb, Z[b]]), np.append(tb, times[b])

    def _rows2(self, mode) -> np.ndarray:
        """The signals' second derivatives as rows over z: ``O F~^2`` (kept per dense mode)."""
        O2 = self._second.get(mode.key)
        if O2 is None:
            while len(self._second) >= KEPT_MODES:
                self._second.pop(next(iter(self._second)))
            O2 = self._second[mode.key] = (self.O @ mode.Ft) @ mode.Ft
        return O2

    def _sparse_reads(self, mode, Z: np.ndarray, times: np.ndarray, slack) -> tuple:
        """A sparse mode's block in one product of the signals' rows: values at the points and
        half way through each step (the orbit's midpoints where it kept them), first and |second|
        derivatives at the points, second half way (F~ applied to the states: nothing formed
        per strand pattern), each (signals, columns), a slack strand's force zero."""
        dt = times[1:] - times[:-1]
        npts, steps = Z.shape[0], Z.shape[0] - 1
        X = np.empty((npts + steps, Z.shape[1]))
        X[:npts] = Z
        zs = X[npts:]
        full = dt >= mode.L * (1 - 1e-9)
        terms = mode.kept(Z[0])          # the orbit's own midpoints and Taylor terms of this block
        if terms is not None and terms.shape[0] >= steps:
            zs[full] = mode.block[1][:steps][full]
        else:
            full[:] = False
        if not full.all():
            part = np.flatnonzero(~full)
            V = terms[part].transpose(1, 0, 2) if terms is not None and part[-1] < terms.shape[0] else None
            zs[part] = mode.at(Z[part], dt[part] / 2, V=V)
        D1 = mode.apply(X.T)
        D2 = mode.apply(D1)
        R = self.Op @ np.hstack([X.T, D1[:, :npts], D2])
        if slack is not None:
            R[slack] = 0.0
        a, b = npts + steps, 2 * npts + steps
        return R[:, :npts], R[:, npts:a], R[:, a:b], np.abs(R[:, b:b + npts]), R[:, b + npts:]

    def _halves(self, mode, Z: np.ndarray, times: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray]:
        """(signals, rows - 1) twice: a dense mode's signals and their second derivatives half
        way through each step Z[i] -> Z[i+1]; a full step (``spacing`` long) by ``O expm(F~
        spacing / 2)`` (one product of the signals' rows, kept per mode and spacing), a shorter
        one by the mode's own reading (a sparse mode's: :meth:`_sparse_reads`)."""
        dt = times[1:] - times[:-1]
        O2 = self._rows2(mode)
        key = (mode.key, spacing)
        hit = self._half.get(key)
        if hit is None:
            while len(self._half) >= KEPT_MODES:
                self._half.pop(next(iter(self._half)))
            E = expm(mode.Ft * (spacing / 2))
            hit = self._half[key] = (self.O @ E, O2 @ E)
        Oh, O2h = hit
        mids, curv = Oh @ Z[:-1].T, O2h @ Z[:-1].T
        short = np.flatnonzero(dt < spacing * (1 - 1e-9))     # (step times round to 1e-11 of a step)
        if short.size:
            zs = mode.at(Z[short], dt[short] / 2)
            mids[:, short], curv[:, short] = self.O @ zs.T, O2 @ zs.T
        return mids, curv

    def _update(self, mode, Z: np.ndarray, times: np.ndarray, piece: int) -> None:
        """Each signal's best value seen per window and side, and its candidate steps: every
        step whose values seen (its ends and its midpoint) plus the most a peak between them
        can rise, ``max |s''| (d^2 / 8)`` with d the spacing of the points seen and
        ``|s''|`` the largest second derivative seen on the step and its neighbours times
        CURVE_SAFETY, reach the best value seen: up to C of them, the highest bounds first;
        the largest bound of those let go is kept (:attr:`uncertain`)."""
        while len(self.piece_start) <= piece:
            self.piece_start.append(float(times[0]))
        key = self._key_index.get(mode.key)
        if key is None:
            key = self._key_index[mode.key] = len(self.keys)
            self.keys.append(mode.key)
        npts = Z.shape[0]
        slack = self._slack(mode.taut) if self.strand.size and (self.strand >= 0).any() else None
        if mode.sparse and npts > 1:
            vals, mids, slope, curv, curv_m = self._sparse_reads(mode, Z, times, slack)
        else:
            vals = self.values(mode.taut, Z)
        if npts > 1:
            if not mode.sparse:
                spacing = mode.L if mode.K == 0 or self.walks(mode) else mode.h
                mids, curv_m = self._halves(mode, Z, times, spacing)
                curv = np.abs(self._rows2(mode) @ Z.T)
                if slack is not None:
                    mids[slack] = 0.0
                    curv[slack], curv_m[slack] = 0.0, 0.0
            # per step: the largest value seen, and the bound of its rise between points seen
            top = {1: np.maximum(np.maximum(vals[:, :-1], vals[:, 1:]), mids),
                   -1: -np.minimum(np.minimum(vals[:, :-1], vals[:, 1:]), mids)}
            c2 = np.maximum(np.maximum(curv[:, :-1], curv[:, 1:]), np.abs(curv_m))
            c2[:, 1:] = np.maximum(c2[:, 1:], c2[:, :-1].copy())
            c2[:, :-1] = np.maximum(c2[:, :-1], c2[:, 1:].copy())
            d = 0.5 * (times[1:] - times[:-1])
            rise = monotone = seen_rise(c2, d[None, :])
            if mode.sparse:
                # a step on which the signal is monotone has its extremes at its ends, both seen:
                # no candidate. With |s''| <= CURVE_SAFETY c2 (the bound of the rise), s' keeps its
                # sign on the step where both ends' slopes have it and their sum exceeds that
                # bound times the step (the two lines s'(t0) - M tau and s'(t1) - M (dt - tau))
                a0, a1 = slope[:, :-1], slope[:, 1:]
                turn = CURVE_SAFETY * c2 * (2 * d)[None, :]
                steady = ((a0 > 0) & (a1 > 0) & (a0 + a1 > turn)) | ((a0 < 0) & (a1 < 0) & (a0 + a1 < -turn))
                monotone = np.where(steady, -np.inf, rise)
            seen_t = np.empty(2 * npts - 1)
            seen_t[0::2], seen_t[1::2] = times, 0.5 * (times[:-1] + times[1:])
            seen = np.empty((vals.shape[0], 2 * npts - 1))
            seen[:, 0::2], seen[:, 1::2] = vals, mids
            step_end = times[1:]
        else:
            top = {1: vals, -1: -vals}
            rise = monotone = np.zeros_like(vals)
            seen_t, seen = times, vals
            step_end = times
        nsteps = top[1].shape[1]
        for w, start in enumerate(self.windows):
            first = int(np.searchsorted(seen_t, start))
            if first >= seen_t.size:
                continue
            s0 = int(np.searchsorted(step_end, start))        # the steps that reach into the window
            for side in (1, -1):
                inside = side * seen[:, first:]
                best = np.maximum(self.best[side][w], inside.max(axis=1))
                self.best[side][w] = best
                if mode.sparse and npts == 1:
                    continue                  # a point alone: its value is all there is
                u = top[side][:, s0:] + monotone[:, s0:]
                if s0 < nsteps and npts > 1 and times[s0] < start:   # the window starts inside step s0:
                    u[:, 0] = top[side][:, s0] + rise[:, s0]          # its value there is not seen
                reach = u >= best[:, None]
                if side == -1:                      # a strand's least force seen at 0 is its least
                    reach[(self.strand >= 0) & (best >= 0.0)] = False     # (finish: it pulls)
                u = np.where(reach, u, -np.inf)
                if not np.isfinite(u).any():
                    continue
                if mode.sparse:
                    self._settle(mode, side, w, start, u, s0, Z, times, slack)
                else:
                    self._merge(side, w, u, s0, Z, times, piece, key, best)
        self._last = (Z[-1].copy(), float(times[-1]), piece)

    def _settle(self, mode, side: int, w: int, start: float, u: np.ndarray, s0: int, Z: np.ndarray,
                times: np.ndarray, slack: np.ndarray | None) -> None:
        """A sparse mode's candidate steps (``u`` finite: signals, steps from s0), each on its
        exact Taylor polynomial from the step's first point over the step (and the window):
        first read at COARSE points, values of the signal that raise the best; a step whose
        coarse best plus the most its polynomial can rise between them still reaches the best
        is kept pending (:class:`beltcalc.sim.watch.polish.PendingSteps`) and polished only if it still
        does when the pending rows fill up or the run ends (:meth:`finish`). Nothing is let go. A start-up
        raises a signal's best at every block, so most candidates are passed by a later one
        and never polished. The steps' Taylor terms are the orbit's own where it kept them
        (:meth:`beltcalc.sim.switching.Mode.orbit`), else formed once for every signal that asks
        (sparse products, as the orbit's step); only the asked signals' coefficients are
        formed, pair by pair (:meth:`_coefficients`), SETTLE_FLOATS at a time."""
        skip = self.moves if slack is None else (self.moves | slack)
        sig, col = np.nonzero(np.isfinite(u) & ~skip[:, None])
        if sig.size == 0:
            return
        steps = s0 + col
        order = np.argsort(steps, kind="stable")         # by step: a chunk's steps are few
        sig, steps = sig[order], steps[order]
        kept = mode.kept(Z[0])
        L = mode.L
        # what each pair costs: its coefficients, and a step's Taylor terms where the orbit
        # did not keep them (the pairs are in step order: a step's first pair pays)
        ptr = self._csr[0]
        cost = (ptr[sig + 1] - ptr[sig]) * mode.terms
        if kept is None or steps[-1] >= kept.shape[0]:
            cost[np.flatnonzero(np.diff(steps, prepend=-1))] += mode.terms * Z.shape[1]
        cum = np.cumsum(cost)
        cuts = np.searchsorted(cum, np.arange(SETTLE_FLOATS, cum[-1], SETTLE_FLOATS))
        bounds = np.unique(np.concatenate([[0], cuts, [sig.size]]))
        best = self.best[side][w]
        pending = self._pending[side][w]
        for lo_p, hi_p in zip(bounds[:-1], bounds[1:]):
            who, at = sig[lo_p:hi_p], steps[lo_p:hi_p]
            C = trim_terms(side * self._coefficients(mode, Z, kept, who, at))   # (pairs, terms), lowest first
            t0, t1 = times[at], times[at + 1]
            a = np.maximum(0.0, (start - t0) / L)
            b = (t1 - t0) / L
            # the polynomials at COARSE points (values: they raise the best); the steps whose
            # coarse best plus max|p''| d^2 / 8 (|p''| <= sum j (j - 1) |c_j|) reach it wait
            s_c = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, COARSE)[None, :]
            y = horner_rows(C, s_c)
            top = y.max(axis=1)
            top[~(b > a)] = -np.inf
            np.maximum.at(best, who, top)
            j = np.arange(C.shape[1])
            curve = np.abs(C) @ (j * (j - 1.0))
            rise = curve * ((b - a) / (COARSE - 1)) ** 2 / 8
            # a rise below rounding of its values: known to rounding at its coarse points
            go = np.flatnonzero((b > a) & (top + rise >= best[who]) & (rise > FLAT * np.abs(top)))
            if go.size:
                # the steps that pass this coarse bound: each cell's own (cell_rises)
                cells = cell_rises(C[go], s_c[go])
                reach = (np.maximum(y[go, :-1], y[go, 1:]) + cells).max(axis=1)
                keep = (reach >= best[who[go]]) & (cells.max(axis=1) > FLAT * np.abs(top[go]))
                go, cells, reach = go[keep], cells[keep], reach[keep]
            if go.size:
                pending.add(who[go], reach, C[go], y[go], cells, a[go], b[go])
        if pending.full():
            pending.prune(best)
            if pending.crowded():          # still half full of steps that may hold the extreme
                pending.polish(best)

    def _coefficients(self, mode, Z: np.ndarray, kept, who: np.ndarray, at: np.ndarray) -> np.ndarray:
        """(pairs, terms): signal ``who[p]``'s Taylor coefficients on the step from Z[at[p]]:
        its row's nonzeros times the step's Taylor terms, summed in the row's order (as the
        sparse product ``O V`` sums them). The terms from the orbit's (``kept``) where it has
        the step, else formed here for the steps asked for."""
        T = mode.terms
        if kept is not None and at.max() < kept.shape[0]:
            V, local = kept, at
        else:
            uniq, local = np.unique(at, return_inverse=True)
            V = mode.taylor(Z[uniq]).transpose(1, 0, 2)       # (steps, terms, states)
        ptr, idx, data = self._csr
        count = ptr[who + 1] - ptr[who]
        ends = np.cumsum(count)
        first = ends - count
        nz = np.arange(int(ends[-1]) if ends.size else 0) - np.repeat(first - ptr[who], count)
        G = V[np.repeat(local, count), :, idx[nz]]                 # (nonzeros, terms)
        G *= data[nz][:, None]
        C = np.zeros((who.size, T))
        some = count > 0
        C[some] = np.add.reduceat(G, first[some], axis=0) if G.shape[0] else 0.0
        return C

    def _merge(self, side: int, w: int, u: np.ndarray, s0: int, Z, times, piece: int, key: int,
               best: np.ndarray) -> None:
        """Keep the C highest bounds of the candidates so far and of this block's steps ``u``
        (signals, steps from s0; -inf: not a candidate), each with its step point. A new step
        takes the slot of a candidate it beats (ties keep the old one): only what enters is
        copied."""
        C = self.C
        take = min(C, u.shape[1])
        idx = np.argpartition(-u, take - 1, axis=1)[:, :take] if u.shape[1] > take else \
            np.broadcast_to(np.arange(u.shape[1]), (u.shape[0], u.shape[1]))
        cu = np.take_along_axis(u, idx, axis=1)                       # (signals, take)
        old = self.u[side][w]
        old[old < best[:, None]] = -np.inf                            # bounds below the best seen: gone
        rows = np.flatnonzero((cu > old.min(axis=1)[:, None]).any(axis=1))
        if rows.size == 0:
            if np.isfinite(cu).any():
                self.dropped[side][w] = np.maximum(self.dropped[side][w], cu.max(axis=1))
            return
        allu = np.concatenate([old[rows], cu[rows]], axis=1)         # (rows, C + take)
        order = np.argsort(-allu, axis=1, kind="stable")              # ties: the old first
        keep = np.zeros(allu.shape, dtype=bool)
        np.put_along_axis(keep, order[:, :C], True, axis=1)
        lost = np.where(keep, -np.inf, allu).max(axis=1)
        self.dropped[side][w, rows] = np.maximum(self.dropped[side][w, rows], lost)
        others = np.ones(u.shape[0], dtype=bool)
        others[rows] = False
        if others.any() and np.isfinite(cu[others]).any():
            self.dropped[side][w, others] = np.maximum(self.dropped[side][w, others], cu[others].max(axis=1))
        free = np.argsort(keep[:, :C], axis=1, kind="stable")         # the old slots let go, first
        enter = np.argsort(~keep[:, C:], axis=1, kind="stable")       # the new steps kept, first
        count = keep[:, C:].sum(axis=1)
        r, j = np.nonzero(np.arange(take)[None, :] < count[:, None])
        sig, slot = rows[r], free[r, j]
        new = enter[r, j]
        step = s0 + idx[sig, new]
        self.u[side][w, sig, slot] = cu[sig, new]
        self.t[side][w, sig, slot] = times[step]
        self.piece[side][w, sig, slot] = piece
        self.key[side][w, sig, slot] = key
        # the rows Z[step] and Z[step - 1] (Z[-1]: the last point of the block before), each once
        edge = step == 0
        last = edge.any() and self._last is not None and self._last[2] == piece
        need = np.unique(np.concatenate([step, step[~edge] - 1]))
        at = self._add(Z[need], self._last[0][None] if last else None)
        self.zi[side][w, sig, slot] = at[np.searchsorted(need, step)]
        self.zi_prev[side][w, sig[~edge], slot[~edge]] = at[np.searchsorted(need, step[~edge] - 1)]
        self.t_prev[side][w, sig[~edge], slot[~edge]] = times[step[~edge] - 1]
        if edge.any():
            if last:
                self.zi_prev[side][w, sig[edge], slot[edge]] = at[-1]
                self.t_prev[side][w, sig[edge], slot[edge]] = self._last[1]
            else:
                self.t_prev[side][w, sig[edge], slot[edge]] = np.nan

    def _add(self, rows: np.ndarray, extra: np.ndarray | None) -> np.ndarray:
        """Put ``rows`` (then ``extra``, if any) into the pool of candidates' points; their
        indices. A full pool first drops the points no candidate refers to any more, then grows:
        it holds at most about four times the points that live candidates refer to."""
        new = rows if extra is None else np.vstack([rows, extra])
        if self.pooled + new.shape[0] > self.pool.shape[0]:
            self._compact()          # then grow unless half of it is free (each compaction costs a pass)
            if 2 * (self.pooled + new.shape[0]) > self.pool.shape[0]:
                grown = np.zeros((max(2 * self.pool.shape[0], 2 * (self.pooled + new.shape[0])), self.pool.shape[1]))
                grown[:self.pooled] = self.pool[:self.pooled]
                self.pool = grown
        at = np.arange(self.pooled, self.pooled + new.shape[0])
        self.pool[at] = new
        self.pooled += new.shape[0]
        return at

    def _compact(self) -> None:
        """Keep only the pool's points that a live candidate (a finite bound) refers to."""
        used = np.zeros(self.pooled, dtype=bool)
        for side in (1, -1):
            live = np.isfinite(self.u[side])
            used[self.zi[side][live]] = True
            used[self.zi_prev[side][live & np.isfinite(self.t_prev[side])]] = True
        keep = np.flatnonzero(used)
        remap = np.zeros(self.pooled, dtype=np.int64)
        remap[keep] = np.arange(keep.size)
        self.pool[:keep.size] = self.pool[keep]
        self.pooled = keep.size
        for side in (1, -1):
            self.zi[side] = remap[self.zi[side]]
            self.zi_prev[side] = remap[self.zi_prev[side]]

    def finish(self) -> None:
        """Polish every candidate on the exact polynomial around its point: the polynomials of
        every signal, side, window and candidate at once (:func:`polish_polynomials`), a stiff
        mode's ladder one by one (:func:`zoom_max`). Where candidates were let go whose bound
        lies above the extreme found, :attr:`uncertain` holds by how much (else 0)."""
        run = self.run
        for w in range(len(self.windows)):
            for side in (1, -1):
                self._pending[side][w].polish(self.best[side][w])
        ends = run.piece_ends + [run.t_end]
        self._terms: dict[tuple, np.ndarray] = {}
        slots, values = [], []                      # (window, side, signal), the value so far
        jobs: list[tuple[int, list[float], float, float]] = []     # (slot, coefficients, a, b)
        for w, start in enumerate(self.windows):
            for side in (1, -1):
                for k in range(len(self.names)):
                    best = self.best[side][w, k]
                    if not np.isfinite(best):
                        continue
                    slot = len(slots)
                    slots.append((w, side, k))
                    values.append(best)
                    for c in np.flatnonzero(self.u[side][w, k] >= best):
                        self._candidate(run, ends, start, w, side, k, int(c), slot, values, jobs)
        values = np.array(values)
        if jobs:
            at = np.array([j[0] for j in jobs])
            C = np.zeros((len(jobs), max(len(j[1]) for j in jobs)))   # a run's modes share one term count
            for r, j in enumerate(jobs):
                C[r, :len(j[1])] = j[1]
            found = polish_polynomials(C, np.array([j[2] for j in jobs]), np.array([j[3] for j in jobs]))
            np.maximum.at(values, at, found)
        for (w, side, k), value in zip(slots, values.tolist()):
            if self.moves[k]:
                continue
            if self.strand[k] >= 0:        # a taut strand pulls: what rounds below zero at a switch is zero
                value = max(value, 0.0) if side == 1 else min(value, 0.0)
            key = (self.names[k], self.windows[w])
            lo_v, hi_v = self.result.get(key, (np.nan, np.nan))
            self.result[key] = (lo_v, value) if side == 1 else (-value, hi_v)
            dropped = float(self.dropped[side][w, k])
            if self.strand[k] >= 0 and side == -1:     # a strand's force is never below 0: no step let
                dropped = min(dropped, 0.0)            # go can hold a least force below it
            gap = max(0.0, dropped - value)
            lo_u, hi_u = self.uncertain.get(key, (0.0, 0.0))
            self.uncertain[key] = (lo_u, gap) if side == 1 else (gap, hi_u)
        self._terms = {}

    def _candidate(self, run, ends, start, w, side, k, c, slot, values, jobs) -> None:
        """The polish jobs of candidate c of (window w, side, signal k): its polynomial either
        side of its step point, inside its strand-mode piece and the window."""
        mode = run.cache.get(*self.keys[self.key[side][w, k, c]])
        tz, p = self.t[side][w, k, c], self.piece[side][w, k, c]
        zi = int(self.zi[side][w, k, c])
        walked = self.walks(mode)          # its records are bottom-step points
        reach = mode.L if walked else mode.h
        lo_t = max(start, self.piece_start[p], tz - reach)
        hi_t = min(run.t_end, ends[p], tz + reach)
        if not hi_t > lo_t or (self.strand[k] >= 0 and not mode.taut[self.strand[k]]):
            return
        starts = [(zi, tz)]
        t_prev = self.t_prev[side][w, k, c]
        if mode.K and np.isfinite(t_prev):     # the stiff ladder reads forward only
            starts.insert(0, (int(self.zi_prev[side][w, k, c]), t_prev))
        if walked:           # the polynomial either side of the best bottom-step point
            a, b = max(-1.0, (lo_t - tz) / mode.L), min(1.0, (hi_t - tz) / mode.L)
            jobs.append((slot, side * (self._taylor(mode, zi) @ self.O[k]), a, b))
            return
        if mode.K and 2 ** (mode.K + 1) <= LADDER_POINTS:
            # a stiff mode's step points are 2^K bottom steps apart: its bottom-step
            # points over [t0, tz + h] by the bottom step expm(F~ L), the best of
            # them, then its polynomial either side, as on a mode without a ladder
            z0, t0 = self.pool[starts[0][0]], starts[0][1]
            count = int(math.ceil((hi_t - t0) / mode.L * (1 + 1e-12)))
            Z = orbit(mode.doubling(mode.K), z0, count + 1)
            times = t0 + np.arange(count + 1) * mode.L
            vals = side * (Z @ self.O[k])
            inside = np.flatnonzero((times >= lo_t) & (times <= hi_t))
            if inside.size:
                j = int(inside[np.argmax(vals[inside])])
                values[slot] = max(values[slot], float(vals[j]))
                a, b = max(-1.0, (lo_t - times[j]) / mode.L), min(1.0, (hi_t - times[j]) / mode.L)
                jobs.append((slot, side * (mode.taylor(Z[j]) @ self.O[k]), a, b))
            return
        for i0, t0 in starts:
            a, b = (lo_t - t0) / mode.h, (hi_t - t0) / mode.h
            if mode.K == 0:      # p(s) = sum_j c_j s^j, |s| <= 1 (||F~ L|| = THETA)
                jobs.append((slot, side * (self._taylor(mode, i0) @ self.O[k]), a, b))
            elif min(b, 1.0) > max(a, 0.0):      # a ladder too tall to walk step by step: a search on it
                found, _ = zoom_max(self._ladder(mode, self.pool[i0], k, side), max(a, 0.0), min(b, 1.0), GRID,
                                    LADDER_ZOOM)
                values[slot] = max(values[slot], found)

    def _taylor(self, mode, i: int) -> np.ndarray:
        """The Taylor terms of ``mode`` at pool point i (kept while :meth:`finish` runs: the
        candidates of many signals share a point)."""
        key = (mode.key, i)
        V = self._terms.get(key)
        if V is None:
            V = self._terms[key] = mode.taylor(self.pool[i])
        return V

    def _ladder(self, mode, z: np.ndarray, k: int, side: int):
        """side * signal k on a grid of GRID points of a stiff mode from the point z (in units
        of its coarse step, read forward on its ladder): the reader of :func:`zoom_max`."""
        row = self.O[k]

        def read(s0: float, d: float, _i) -> np.ndarray:
            s = s0 + d * np.arange(GRID)
            return side * (mode.at(np.repeat(z[None], GRID, axis=0), s * mode.h) @ row)
        return read
