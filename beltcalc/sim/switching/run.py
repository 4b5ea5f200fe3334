"""The run of the switching core: the exact solution propagated mode by mode between strand
switches and time break points (:func:`piecewise_exact`, :class:`Run`).

A run balances the all-taut matrix once (:meth:`Run._scaling`), picks the dense or the
sparse path (from SPARSE_SIZE states: :mod:`beltcalc.sim.switching.sparse`), and keeps the
modes it builds by (pattern, time piece). Each stretch of one mode is propagated in blocks
of steps (:meth:`Run.advance`: the first block half the previous stretch's, doubled while
nothing happens), scanned for the first crossing (:mod:`beltcalc.sim.switching.firing`; a
stiff mode's coarse steps halved down its ladder, :meth:`Run._descend`), the outputs
written on the way (:class:`beltcalc.sim.switching.outputs.Outputs`). At a crossing or a
new time piece the strands on a surface are decided (:meth:`Run.decide`) and the run goes
on in the new mode. DESIGN.md section 3.0 and docs/switching.md hold the design.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from beltcalc.errors import SimulationError
from beltcalc.numerics.balance import balance
from beltcalc.sim.propagate import augmented_matrix, orbit
from beltcalc.sim.switching.firing import EPS, ROUND, first_crossing, may_cross
from beltcalc.sim.switching.mode import DenseMode, Mode
from beltcalc.sim.switching.outputs import Outputs, StepIntegrals, rigid_modes, slack_times, switched_log
from beltcalc.sim.switching.parts import SparseParts
from beltcalc.sim.switching.sparse import SparseMode
from beltcalc.sim.switching.steps import power_radius

MAX_BLOCK = 2048     # steps propagated ahead at once (doubled from FIRST_BLOCK while nothing happens)
FIRST_BLOCK = 64     # steps of a run's first block; later, half the previous stretch's (Run.advance) ...
FIRST_FLOPS = 2e6    # ... and at most this many state-size^2 products (size 19: 5540 steps, 245: 33)
CACHE_BYTES = 400e6  # modes kept (least recently used first out)
RADIUS_MARGIN = 1.25  # the sparse path's power-step radius, raised by this (it may come from below)
SPARSE_SIZE = 300    # states (with generators) from which modes are sparse (see SparseParts) ...
SPARSE_FROM = 100    # ... and from which a dense run that builds many modes starts again sparse:
DENSE_WORK = 2e8     # once the dense modes built, times states^3, pass this (piecewise_exact)
SPARSE_BLOCK = 2e6   # polynomial coefficients held per block of sparse steps
KEEP_FLOATS = 8e6    # a watched sparse block's Taylor terms kept for the watch (64 MB) at most
REBASE_TURN = 2 * math.pi   # rad: a block's rotation before the angles are re-based (Run.rebase)
MAX_STEPS = 20_000_000   # internal steps a run may need (a mode far stiffer than the run is long)


class ModeCache:
    """Modes by (pattern, time piece), least recently used dropped beyond CACHE_BYTES: sparse
    ones (:class:`beltcalc.sim.switching.sparse.SparseMode`) where ``parts`` is given, else
    dense (:class:`beltcalc.sim.switching.mode.DenseMode`)."""

    def __init__(self, network, S, omega, rho, scale, parts=None):
        self.network, self.S, self.omega, self.rho, self.scale, self.parts = network, S, omega, rho, scale, parts
        self.modes: OrderedDict = OrderedDict()
        self.built = 0
        self.bytes = 0

    def get(self, taut, seg, t_mid) -> Mode:
        key = (taut, seg)
        mode = self.modes.get(key)
        if mode is None:
            if self.parts is not None:
                mode = SparseMode(self.parts, taut, t_mid, self.S, self.rho, self.scale)
            else:
                mode = DenseMode(self.network, taut, t_mid, self.S, self.omega, self.rho, self.scale)
            self.modes[key] = mode
            mode.key = (taut, seg, t_mid)
            self.built += 1
            self.bytes += mode.nbytes
            while len(self.modes) > 2 and self.bytes > CACHE_BYTES:
                self.bytes -= self.modes.popitem(last=False)[1].nbytes
        self.modes.move_to_end(key)
        return mode


class DenseTooCostly(Exception):
    """A dense run built more modes than DENSE_WORK allows: :func:`piecewise_exact` runs it
    again on the sparse path."""


class Run(Outputs):
    """The exact piecewise propagation of one network over the output times ``t``."""

    def __init__(self, network, t: np.ndarray, x0: np.ndarray, max_events: int, scale: float = 1.0,
                 method: str = "exact", integrate: bool = False, watch=None, sparse: bool | None = None,
                 give_up_dense: bool = False):

        self.network, self.t, self.max_events, self.method = network, t, max_events, method
        t_end = float(t[-1])
        self.t_end = t_end
        self.starts = network.segment_starts(t_end)
        self.ends = self.starts[1:] + [t_end]
        all_taut = network.full_pattern(tuple(True for _ in network.strands))
        # every switched element in its state 0 (free, no joint): a held node's row and column
        # vanish, and balancing would scale it by 1e-11 (its motion in other modes then huge)
        loose = all_taut[:len(network.strands)] + (0,) * len(network.switched)
        F0 = augmented_matrix(network, loose, network.piece_time(0, self.starts, t_end))
        self.S = self._scaling(F0)
        n = network.size
        parts = None
        if sparse is None:
            sparse = F0.shape[0] >= SPARSE_SIZE
        self.sparse = bool(sparse and network.strands and not network.switched)
        # a dense run of many strand patterns stops (DenseTooCostly) once its modes cost more
        # than the sparse path would (each dense mode: expm, its integral, its Taylor terms)
        self.dense_limit = DENSE_WORK / F0.shape[0] ** 3 if (give_up_dense and not self.sparse and network.strands
                                                            and F0.shape[0] >= SPARSE_FROM) else math.inf
        if self.sparse:
            # no stiff ladder on the sparse path; the spectral radius by power steps
            parts, omega = SparseParts(network, self.S), 0.0
            rho = RADIUS_MARGIN * power_radius(parts.scipy_matrix(all_taut, network.piece_time(0, self.starts, t_end)))
        else:
            # the fastest oscillation (stiff ladders) and the spectral radius (the step) of
            # the all-taut matrix: a slack strand takes a spring and a damper away
            # (the generators' block is autonomous: its eigenvalues are the inputs' own)
            # (with switched elements, of the loose and the default mode: a joint can raise both)
            lam = np.linalg.eigvals(F0[:n, :n]) if n else np.zeros(0)
            if network.switched and n:
                Fd = augmented_matrix(network, all_taut, network.piece_time(0, self.starts, t_end))
                lam = np.concatenate([lam, np.linalg.eigvals(Fd[:n, :n])])
            omega = float(np.max(np.abs(lam.imag))) if lam.size else 0.0
            lam = np.concatenate([lam, np.linalg.eigvals(F0[n:, n:])]) if F0.shape[0] > n else lam
            rho = float(np.max(np.abs(lam))) if lam.size else 0.0
        self.cache = ModeCache(network, self.S, omega, rho, scale, parts)
        self.m = n
        self.out = np.empty((n, t.size))
        # free rigid rotations: the angles are re-based as the run goes (see rigid_modes); with
        # every switched element in its state 0 (free: no joint, whose projection would hide the
        # angles its constraint torque depends on)
        pieces = [augmented_matrix(network, loose, network.piece_time(k, self.starts, t_end))
                  for k in range(len(self.starts))]
        self.rigid, self.rigid_root = rigid_modes(pieces, network.n)
        self.rigid_speed = network.n + self.rigid_root
        self.rigid_z = self.rigid / self.S[None, :] if self.rigid.size else self.rigid
        self.theta = np.zeros(self.rigid.shape[0])              # the rotation taken out so far
        self.theta_out = np.zeros((self.rigid.shape[0], t.size))
        self.rebases: list[tuple[float, np.ndarray]] = []
        self.next_out = 0
        self.dt = float(t[1] - t[0]) if t.size > 1 else 0.0
        # uniform to the rounding of the times themselves (np.linspace's steps differ by an
        # ulp of t: 1e-12 of the step at 10,001 samples over 1 s), so samples may be read by
        # powers of expm(F~ dt)
        self.uniform = t.size > 2 and bool(np.max(np.abs(np.diff(t) - self.dt)) <= 64 * EPS * max(abs(t[0]), abs(t[-1])))
        # (a run with friction integrates its states: a slipping clutch's heat needs them)
        self.integrate = integrate or watch is not None or bool(network.switched)
        self.integrals = np.empty((n, t.size)) if self.integrate else None
        ns = len(network.strands)
        self.force_integrals = np.empty((ns, t.size)) if self.integrate else None   # int of F dt
        self.F_run = np.zeros(ns)            # ... up to the current piece's start
        self.I_piece = None
        self.I_run = None                    # integral of z from 0 to the current point (balanced)
        self.watch = watch
        self.piece_ends: list[float] = []
        self.switches: list[tuple[float, int, bool]] = []
        self.located = 0
        self.steps = 0
        self.first_block = FIRST_BLOCK
        self._scratch = None
        delta, force = network.strand_rows()
        self.delta = delta * self.S[None, :]
        self.force = force * self.S[None, :]
        # decide()'s products with every strand's rows and their magnitudes (|rows|^T: the
        # levels are mag @ |rows|^T), sparse on the sparse path
        if parts is not None:
            D, Fo = parts.sparse.csr_matrix(self.delta), parts.sparse.csr_matrix(self.force)
            self.strand_ops = (D, Fo, lambda mag, A=abs(D): A @ mag, lambda mag, A=abs(Fo): A @ mag)
        else:
            self.strand_ops = (self.delta, self.force, lambda mag, A=np.abs(self.delta).T: mag @ A,
                                lambda mag, A=np.abs(self.force).T: mag @ A)
        z = np.concatenate([x0, network.generators(0.0)]) / self.S
        self.I_run = np.zeros_like(z)
        if watch is not None:
            watch.bind(self)
        self.settled = z
        self.start_taut = self.decide(z, all_taut, 0, list(range(len(network.strands))), start=True)
        self.z0 = self.settled if network.switched else z

    def _scaling(self, F0: np.ndarray) -> np.ndarray:
        """S balancing the all-taut matrix, with the constant input's column scaled down (a
        power of two) until it is no longer than the state columns in *any* strand pattern.
        Pretensions cancel on a node between two taut strands but not when one is slack:
        unscaled, that column sets ``||F~||`` (and the step) in every pattern with slack
        strands, 8x on a 60-roller chain, for an input that is constant."""

        S = balance(F0)
        if not self.network.strands:
            return S
        net, c = self.network, self.network.size
        owner, rows, cols, vals = net.strand_stamps()
        none = tuple(False for _ in net.strands)
        worst = 0.0
        for seg in range(len(self.starts)):
            base = augmented_matrix(net, none, net.piece_time(seg, self.starts, self.t_end))[:, c]
            col = np.abs(base) / S
            np.add.at(col, rows[cols == c], np.abs(vals[cols == c]) / S[rows[cols == c]])
            worst = max(worst, float(col.sum() * S[c]))
        Ft = np.abs(F0 / S[:, None] * S[None, :])
        target = float(np.delete(Ft.sum(axis=0), c).max()) if Ft.shape[0] > 1 else 0.0
        if worst > target > 0:
            S = S.copy()
            S[c] *= 2.0 ** -math.ceil(math.log2(worst / target))
        return S

    # --- decisions ----------------------------------------------------------------------------
    def decide(self, z: np.ndarray, taut: tuple, seg: int, strands, fired: int | None = None,
               start: bool = False) -> tuple:
        """The pattern just after a restart at z. A strand in ``strands`` off its surfaces is
        taut if its elongation and force are both positive. A strand on a surface is taut if
        both leave zero upwards in the taut mode (the other strands as decided); repeated
        until the pattern is consistent.

        "On a surface" means within the rounding level of a value read off the exact
        solution: ``ROUND`` times the sum of the magnitudes of its Taylor terms over one
        bottom step (``|rows| sum_j |V_j|``). A located switch sits there: its value is a root of
        the step's polynomial, so what is left of it (e.g. ``delta = -3e-20 m`` at a take-up
        without pretension) is rounding, and its sign says nothing; the rate decides.

        Then the elements with modes of their own (friction, torque limits): ``fired`` (its
        index among them) switched, or any on a surface, are decided with the strands'
        pattern as it is (:meth:`beltcalc.sim.network.Network.decide_switched`)."""
        net = self.network
        t_mid = net.piece_time(seg, self.starts, self.t_end)
        if net.strands:
            taut = self._decide_strands(z, taut, seg, strands, t_mid)
        if net.switched:
            h = self.cache.get(taut, seg, t_mid).L
            taut, settled = net.decide_switched(z * self.S, taut, t_mid, h, fired, guess=start)
            self.settled = settled / self.S
        return taut

    def _decide_strands(self, z: np.ndarray, taut: tuple, seg: int, strands, t_mid: float) -> tuple:
        here = self.cache.get(taut, seg, t_mid)
        V = here.taylor(z)
        terms = {taut: V}                    # z's Taylor terms per pattern tried
        D, Fo, level_d, level_f = self.strand_ops
        dv, fv = D @ z, Fo @ z
        mag = np.abs(V).sum(axis=0)          # the magnitudes that enter the Taylor sum
        on_d = np.abs(dv) <= ROUND * level_d(mag) + 1e-300
        on_f = np.abs(fv) <= ROUND * level_f(mag) + 1e-300
        pattern = list(taut)
        for k in strands:
            if not (on_d[k] or on_f[k]):
                pattern[k] = bool(dv[k] > 0 and fv[k] > 0)
        near = np.nonzero(on_d | on_f)[0].tolist()
        for _ in range(len(near) + 2):
            changed = False
            for k in near:
                trial = tuple(pattern[:k] + [True] + pattern[k + 1:])
                mode = self.cache.get(trial, seg, t_mid)
                Vt = terms.get(trial)
                if Vt is None:
                    Vt = terms[trial] = mode.taylor(z)
                up = self._leaves_up(self.delta, k, Vt, on_d[k]) and self._leaves_up(self.force, k, Vt, on_f[k])
                if pattern[k] != up:
                    pattern[k], changed = up, True
            if not changed:
                break
        return tuple(pattern)

    @staticmethod
    def _leaves_up(rows: np.ndarray, k: int, V: np.ndarray, on: bool) -> bool:
        """Whether rows[k] . z(s) is >= 0 just after s = 0 (V: z's Taylor terms). Off its
        surface the value decides; on it (``on``), the first rate coefficient beyond rounding
        does (none: at rest, which counts as taut). A large network's over the row's nonzeros
        only (a strand's row reads a few states of a chain's thousands)."""
        W, row = V, rows[k]
        if row.size >= SPARSE_SIZE:
            cols = np.flatnonzero(row)
            W, row = V[:, cols], row[cols]
        c = W @ row
        if not on:
            return bool(c[0] > 0)
        tol = ROUND * (np.abs(W) @ np.abs(row)) + 1e-300
        big = np.nonzero(np.abs(c[1:]) > tol[1:])[0]
        return True if big.size == 0 else bool(c[1 + big[0]] > 0)

    # --- scanning -----------------------------------------------------------------------------
    def _descend(self, mode: Mode, z: np.ndarray, level: int, first: bool, limit: float, checked: bool = False):
        """The first crossing in the step of length h / 2^level from z (only its first
        ``limit`` fraction): (tau, event) or None. ``first`` forces the leftmost path down
        to the bottom step (a restart's boundary layer)."""
        if level == mode.K:
            Z = np.vstack([z, mode.P(mode.K) @ z])
            hit = first_crossing(mode, Z, first, limit)
            self.steps += 1
            return None if hit is None else (hit[1] * mode.L, hit[2])
        w = mode.h / 2 ** level
        if not (first or checked) and not may_cross(mode, z[None], (mode.P(level) @ z)[None], w)[0]:
            return None
        half = w / 2
        left = self._descend(mode, z, level + 1, first, min(1.0, 2 * limit))
        if left is not None or limit <= 0.5:
            return left
        right = self._descend(mode, mode.P(level + 1) @ z, level + 1, False, 2 * limit - 1)
        return None if right is None else (half + right[0], right[1])

    # --- the run ------------------------------------------------------------------------------
    def advance(self, mode: Mode, z: np.ndarray, t0: float, t_stop: float):
        """Propagate from (t0, z) to the first crossing or to t_stop, writing the outputs on
        the way: (t, z, event) of the crossing, or (t_stop, z(t_stop), None). The next
        stretch's first block is half this one's steps, at most FIRST_FLOPS / size^2 steps
        (8 to MAX_BLOCK): switches that come every few steps are not overshot by much, long
        quiet stretches of a small network take few blocks, and a large network never
        propagates much past an early switch."""
        start = self.steps
        out = self._advance(mode, z, t0, t_stop)
        m = mode.size
        self.first_block = max(8, min(MAX_BLOCK, (self.steps - start) // 2, int(FIRST_FLOPS / (m * m))))
        return out

    def _advance(self, mode: Mode, z: np.ndarray, t0: float, t_stop: float):
        h = mode.h
        total = (t_stop - t0) / h
        n_full = int(math.floor(total * (1 + 4 * EPS)))
        rem = (t_stop - t0) - n_full * h
        if rem <= 4 * EPS * max(abs(t_stop), h):
            rem = 0.0
        i, block, first = 0, self.first_block, True
        most = max(8, int(SPARSE_BLOCK / (mode.terms * max(1, mode.n_events)))) if mode.sparse else MAX_BLOCK
        integ = self.integrate
        self.I_piece = self.I_run
        while i < n_full:
            cnt = min(block, n_full - i, most)
            if self.theta.size:          # a block turns the drive by at most REBASE_TURN before its re-base
                turn = float(np.max(np.abs(z[self.rigid_speed] * self.S[self.rigid_speed]))) * h
                if turn * cnt > REBASE_TURN:
                    cnt = max(min(8, cnt), int(REBASE_TURN / turn))
            times = t0 + (i + np.arange(cnt + 1)) * h
            J = None
            if mode.K == 0:
                Z, C, J = mode.orbit(z, cnt, stop_early=True, integrate=integ and mode.sparse,
                                     keep=self._keep(mode, cnt), first=first)
                cnt = Z.shape[0] - 1
                times = times[:cnt + 1]
                hit = getattr(mode, "hit", None)
                if hit is None:
                    hit = first_crossing(mode, Z, first, C=C, cleared=cnt - 1 if mode.sparse else 0)
                found = None if hit is None else (hit[0], hit[1] * h, hit[2])
                self.steps += cnt
            else:
                Z = orbit(mode.doubling(), z, cnt + 1)
                found = None
                flags = may_cross(mode, Z[:-1], Z[1:], h)
                if first:
                    flags[0] = True
                for j in np.nonzero(flags)[0]:
                    res = self._descend(mode, Z[j], 0, first and j == 0, 1.0, checked=True)
                    if res is not None:
                        found = (int(j), res[0], res[1])
                        break
                self.steps += cnt if found is None else int(found[0]) + 1
            Ib = None
            if integ:                                  # the integral at the step points, as asked for
                Ib = StepIntegrals(self.I_run, Z[:cnt], mode.Q(0)) if J is None else StepIntegrals(self.I_run, J)
            if found is not None:
                j, tau, e = found
                te = times[j] + tau
                self.emit(mode, Z[:j + 1], times[:j + 1], te, I_base=Ib)
                kept = mode.kept(Z[0]) if mode.sparse else None       # the step's Taylor terms
                V = kept[j] if kept is not None and j < kept.shape[0] else None
                if integ:
                    z_e, I_e = mode.at(Z[j], tau, integrate=True, V=V)
                    self.I_run = Ib[j] + I_e
                else:
                    z_e = mode.at(Z[j], tau, V=V)
                self._watch(mode, np.vstack([Z[:j + 1], z_e]), np.append(times[:j + 1], te))
                return te, z_e, e
            self.emit(mode, Z[:cnt], times[:cnt], times[cnt], I_base=Ib)
            self._watch(mode, Z, times)
            if integ:
                self.I_run = Ib[cnt]
            z, i, first = self.rebase(Z[cnt], float(times[cnt])), i + cnt, False
            block = min(2 * block, MAX_BLOCK)
        if rem > 0:
            t_last = t0 + n_full * h
            if mode.K == 0:
                Z, C, _ = mode.orbit(z, 1)
                hit = first_crossing(mode, Z, first, rem / h, C=C)
                found = None if hit is None else (hit[1] * h, hit[2])
            else:
                found = self._descend(mode, z, 0, first, rem / h)
            self.steps += 1
            tau, e = found if found is not None else (rem, None)
            te = t_last + tau
            self.emit(mode, z[None], np.array([t_last]), te if found is not None else t_stop,
                      I_base=self.I_run[None] if integ else None)
            if integ:
                z_e, I_e = mode.at(z, tau, integrate=True)
                self.I_run = self.I_run + I_e
            else:
                z_e = mode.at(z, tau)
            self._watch(mode, np.vstack([z, z_e]), np.array([t_last, te]))
            return (te, z_e, e) if found is not None else (t_stop, z_e, None)
        self._watch(mode, z[None], np.array([t_stop]))
        return t_stop, z, None

    def _keep(self, mode: Mode, count: int) -> np.ndarray | None:
        """A scratch array for a watched sparse block's Taylor terms (:meth:`SparseMode.orbit`),
        reused from block to block (the watch reads it before the next block), or None:
        unwatched, dense, or larger than KEEP_FLOATS."""
        if self.watch is None or not mode.sparse:
            return None
        shape = (count, mode.terms, mode.size)
        if math.prod(shape) > KEEP_FLOATS:
            return None
        if self._scratch is None or any(a < b for a, b in zip(self._scratch.shape, shape)):
            self._scratch = np.empty(tuple(max(a, b) for a, b in zip(shape, self._scratch.shape
                                                                     if self._scratch is not None else shape)))
        return self._scratch

    def _watch(self, mode: Mode, Z: np.ndarray, times: np.ndarray) -> None:
        if self.watch is not None:
            self.watch.update(mode, Z, times, len(self.piece_ends))

    def run(self) -> "Run":
        net = self.network
        z, taut = self.z0, self.start_taut
        t_cur, seg = 0.0, 0
        while seg < len(self.starts):
            t_stop = self.ends[seg]
            if t_stop <= t_cur:
                seg += 1
                continue
            mode = self.cache.get(taut, seg, net.piece_time(seg, self.starts, self.t_end))
            if self.cache.built > self.dense_limit:
                raise DenseTooCostly(self.cache.built)
            # counted in bottom steps: a stiff ladder takes fewer, but squares its way up from one
            # (2^K of them), and a ladder some 40 levels tall overflows (a 60 km shaft)
            need = self.steps + (t_stop - t_cur) / mode.L
            if need > MAX_STEPS:
                raise SimulationError(
                    f"method {self.method}: the run needs about {need:.3g} internal steps of {mode.L:.3g} s (its "
                    f"stiffest part), more than {MAX_STEPS:,}; a stiffness or a damping many decades above the "
                    "rest? Check the inputs, shorten the run, or make a very stiff coupling rigid")
            z_from, I_from, theta_from, rebased = z, self.I_run, self.theta, len(self.rebases)
            t_new, z, e = self.advance(mode, z, t_cur, t_stop)
            if net.switched:
                self._heat(taut, seg, (t_cur, z_from, I_from, theta_from), (t_new, z, self.I_run, self.theta),
                           self.rebases[rebased:])
            z = self.rebase(z, t_new)
            self.piece_ends.append(t_new)
            if self.integrate:
                done = self.strand_ops[1] @ (self.I_run - self.I_piece)
                self.F_run = self.F_run + np.asarray(mode.taut[:len(net.strands)], dtype=float) * done
            if e is None:
                t_cur, seg = t_stop, seg + 1
                if seg < len(self.starts):           # the inputs change piece: re-decide strands on a surface
                    new = self.decide(z, taut, seg, [])
                    self._log(t_cur, taut, new)
                    taut = new
                    if net.switched:
                        z = self.settled
                continue
            self.located += 1
            k, ns = int(mode.event_strand[e]), len(net.strands)
            if self.located > self.max_events:
                what = f"strand {net.strands[k].name}" if k < ns else net.switched[k - ns].name
                raise SimulationError(
                    f"method {self.method}: {self.max_events} {'strand events' if k < ns else 'switches'} by t = {t_new:.6g} s ({what} "
                    "switches that often); add pretension or damping, or raise `max_events`")
            new = self.decide(z, taut, seg, [k] if k < ns else [], fired=k - ns if k >= ns else None)
            self._log(t_new, taut, new)
            taut, t_cur = new, t_new
            if net.switched:
                z = self.settled
        mode = self.cache.get(taut, len(self.starts) - 1, net.piece_time(len(self.starts) - 1, self.starts, self.t_end))
        self.I_piece = self.I_run
        self.emit(mode, z[None], np.array([self.t_end]), self.t_end, inclusive=True,
                  I_base=self.I_run[None] if self.integrate else None)
        self.end_taut = taut
        if self.watch is not None:
            self.watch.finish()
        return self

    def _heat(self, taut, seg, start, end, rebases) -> None:
        """Add the work each slipping friction element turned into heat over a stretch, exactly:
        with T = s (a + c t) on the piece and phi = g . q its relative angle,
        ``int T phi' dt = s [(a + c t) phi] - s c int phi dt`` (the run's integral of the
        state gives the last term). ``start``, ``end``: (t, z, its integral, the rotation taken
        out so far); ``rebases``: those made within the stretch. The relative angle of two
        sides that turn freely in the loose mode has a part along the rigid rotations that the
        run re-bases: it is added back, ``(g . rigid) theta``, and its integral from the
        rotation's steps."""
        net = self.network
        t_mid = net.piece_time(seg, self.starts, self.t_end)
        n, ns = net.n, len(net.strands)
        (t0, z0, I0, theta0), (t1, z1, I1, theta1) = start, end
        if not hasattr(self, "heat"):
            self.heat = {el.name: 0.0 for el in net.switched}
        # int theta dt over the stretch: theta0 throughout, each rebase's step from its time on
        theta_int = theta0 * (t1 - t0)
        for when, step in rebases:
            theta_int = theta_int + step * (t1 - when)
        for el, state in zip(net.switched, taut[ns:]):
            sign = el.slip_sign(state)
            if not sign:
                continue
            a, c = el.torque_piece(t_mid)
            g = el.row(net)
            along = self.rigid[:, :n] @ g if self.theta.size else np.zeros(0)
            phi0 = g @ (z0[:n] * self.S[:n]) + along @ theta0
            phi1 = g @ (z1[:n] * self.S[:n]) + along @ theta1
            work = (a + c * t1) * phi1 - (a + c * t0) * phi0
            if c:
                work -= c * (g @ ((I1 - I0)[:n] * self.S[:n]) + along @ theta_int)
            self.heat[el.name] += sign * work

    def _log(self, t: float, before, after) -> None:
        for k, (a, b) in enumerate(zip(before, after)):
            if a != b:
                self.switches.append((t, k, b))

    def info(self) -> dict:
        """Switches, each strand's time slack [s], and the work done."""
        net = self.network
        ns = len(net.strands)
        slack = slack_times(net, self.start_taut, self.switches, self.t_end)
        names = [s.name for s in net.strands]
        info = {"events": len(self.switches), "located": self.located, "slack_time": slack,
                "switches": [(t, names[k], on) for t, k, on in self.switches if k < ns], "modes": self.cache.built}
        if net.switched:
            info["switched"] = switched_log(net, self.start_taut, self.switches, self.t_end)
            info["switched"]["heat"] = dict(getattr(self, "heat", {el.name: 0.0 for el in net.switched}))
        return info


def piecewise_exact(network, t: np.ndarray, x0: np.ndarray, max_events: int, scale: float = 1.0, watch=None):
    """Exact propagation between strand switches and time break points: (states, steps, info).
    With a ``watch`` (:class:`beltcalc.sim.watch.Watch`), its extremes are filled and
    ``info["integrals"]`` holds the states' integrals from 0 at every sample.

    A network of SPARSE_FROM to SPARSE_SIZE states starts dense; if its strand patterns need
    more dense modes than DENSE_WORK / states^3 (a long chain that keeps switching: 36 rollers
    of the roller table, 2,469 switches, took 224 s dense, 22 s sparse and 26 s so), it starts
    again on the sparse path (25 rollers, 510 switches: 25 s dense, 14 s so; 20 rollers, 58
    switches, 22 modes, stay dense at 3.5 s where sparse takes 11 s). The choice counts modes,
    never time: the same on every machine."""
    try:
        run = Run(network, t, x0, max_events, scale, watch=watch, give_up_dense=True).run()
        restarted = 0
    except DenseTooCostly as e:
        restarted = e.args[0]
        run = Run(network, t, x0, max_events, scale, watch=watch, sparse=True).run()
    info = run.info()
    info["path"] = "sparse" if run.sparse else "dense"
    if restarted:
        info["path"] += f" (after {restarted} dense modes)"
    out, rebased = run.absolute()
    if rebased is not None:
        info["rebased"] = rebased
    if watch is not None:
        info["integrals"] = run.integrals
        rigid = run.rigid_integrals()
        if rigid is not None:
            info["rigid_integrals"] = (run.rigid[:, :run.m], rigid)
        info["force_integrals"] = {s.name: run.force_integrals[k] for k, s in enumerate(network.strands)}
    return out, run.steps, info
