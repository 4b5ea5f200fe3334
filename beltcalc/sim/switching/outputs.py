"""What a switching run writes: the samples read off the exact solution, the integrals the
window's means come from, and the free rigid rotations taken out of the angles.

:class:`Outputs` is the part of :class:`beltcalc.sim.switching.run.Run` that writes them;
:func:`rigid_modes` finds the rotations, :func:`slack_times` sums each strand's time slack
from the run's switches.
"""

from __future__ import annotations

import numpy as np

from beltcalc.sim.propagate import orbit
from beltcalc.sim.switching.mode import Mode


class StepIntegrals:
    """The state's integral from 0 at the step points of one block, ``I[r] = I0 + Q sum_(i<r)
    Z[i]`` (``Q`` the integral of one step's exponential,
    :meth:`beltcalc.sim.switching.mode.DenseMode.Q`; None where the rows summed are already
    the steps' integrals, the sparse path's), formed only at the rows asked for (``self[r]``):
    one row is its own sum (a block's first sample, a switch, its end: the usual reads), an
    index array the prefix sums of all rows (formed once), and the product with Q is paid for
    the rows read instead of for every step."""

    def __init__(self, I0: np.ndarray, rows: np.ndarray, Q: np.ndarray | None = None):
        self.I0, self.Q, self.rows = I0, Q, rows
        self.S = None

    def __getitem__(self, r) -> np.ndarray:
        if np.ndim(r) == 0:                   # one row (the usual read): its sum alone
            s = np.ones(r) @ self.rows[:r]   # a BLAS product: numpy's sum down a narrow array is 5x slower
        else:
            if self.S is None:
                self.S = np.empty((self.rows.shape[0] + 1, self.rows.shape[1]))
                self.S[0] = 0.0
                np.cumsum(self.rows, axis=0, out=self.S[1:])
            s = self.S[r]
        return self.I0 + (s if self.Q is None else s @ self.Q.T)


class Outputs:
    """The part of :class:`beltcalc.sim.switching.run.Run` that writes its outputs as it goes:
    ``out`` (the states at the output times ``t``), ``integrals`` and ``force_integrals``
    (from 0, where asked for), ``theta``, ``theta_out`` and ``rebases`` (the rigid rotations
    taken out). The arrays and the run's scaling ``S`` are the run's attributes, set up by
    its constructor."""

    def emit(self, mode: Mode, base: np.ndarray, t_base: np.ndarray, until: float, inclusive: bool = False,
             I_base: np.ndarray | None = None) -> None:
        """Write the output samples with t < until (<= with ``inclusive``), each read off the
        exact solution from the step start before it (rows of ``base`` at times ``t_base``,
        where the state's integral from 0 is ``I_base``)."""
        t = self.t
        stop = int(np.searchsorted(t, until, side="right" if inclusive else "left"))
        if stop <= self.next_out:
            return
        idx = np.arange(self.next_out, stop)
        k = np.clip(np.searchsorted(t_base, t[idx], side="right") - 1, 0, len(t_base) - 1)
        tau = np.clip(t[idx] - t_base[k], 0.0, mode.h)
        many = not mode.sparse and idx.size >= 16 and self.uniform
        V = None
        if mode.sparse:                  # the Taylor terms of the block's steps, where the orbit kept them
            kept = mode.kept(base[0])
            if kept is not None and k[-1] < kept.shape[0]:
                V = kept[k].transpose(1, 0, 2)
        if many and not self.integrate:
            # many samples in one piece: the first off its step, the rest by expm(F~ dt) powers
            # (one m^2 product per sample instead of a Taylor sum of TERMS)
            Z = orbit(mode.step(self.dt), mode.at(base[k[0]], tau[0]), idx.size)
        elif self.integrate:
            if many:
                # the same with the integrals: [z; I] stepped by [[S, 0], [Phi, I]]
                z0, I0 = mode.at(base[k[0]], tau[0], integrate=True)
                W = orbit(mode.step_integral(self.dt), np.concatenate([z0, I0 + I_base[k[0]]]), idx.size)
                Z, I = W[:, :z0.size], W[:, z0.size:]
            else:
                Z, I = mode.at(base[k], tau, integrate=True, V=V)
                I += I_base[k]
            cols = slice(self.next_out, stop)          # the samples written: idx, as a slice
            self.integrals[:, cols] = (I * self.S[None, :]).T[:self.m]
            on = np.asarray(mode.taut[:len(self.network.strands)], dtype=float)
            forces = self.strand_ops[1] @ (I - self.I_piece).T
            self.force_integrals[:, cols] = self.F_run[:, None] + on[:, None] * forces
        else:
            Z = mode.at(base[k], tau, V=V)
        self.out[:, self.next_out:stop] = (Z * self.S[None, :]).T[:self.m]
        if self.theta.size:
            self.theta_out[:, self.next_out:stop] = self.theta[:, None]
        self.next_out = stop

    def rebase(self, z: np.ndarray, t: float) -> np.ndarray:
        """z with each free rigid rotation taken out of its angles (its root angle exactly 0),
        the rotation added to ``theta``: the angles a stiff coupling's torque is the
        difference of stay as small as one block's rotation, so their rounding does not grow
        with the run (a 2e9 N m/rad coupling at 150 rad/s: eps |phi| C is 1e-4 N m after 2 s).
        Nothing read off the exact solution changes but the angles, which the run adds back."""
        if not self.theta.size:
            return z
        roots = self.rigid_root
        theta = z[roots] * self.S[roots]
        if not np.any(theta):
            return z
        z = z - theta @ self.rigid_z
        z[roots] = 0.0
        self.theta = self.theta + theta
        self.rebases.append((t, theta))
        return z

    def absolute(self) -> tuple[np.ndarray, np.ndarray | None]:
        """(states with the rigid rotations added back, the re-based states or None): the
        angles as they are, and the states every elastic output is computed from."""
        if not self.rebases:
            return self.out, None
        return self.out + self.rigid[:, :self.m].T @ self.theta_out, self.out

    def rigid_integrals(self) -> np.ndarray | None:
        """(components, samples): the integral from 0 of each rotation taken out,
        ``sum_k d_theta_k (t - t_k)+``; the states' integrals (``integrals``, re-based) plus
        ``R^T`` times it are the integrals of the states as they are. Kept apart, so a
        torque's mean is not the difference of two large angle integrals."""
        if not self.rebases or self.integrals is None:
            return None
        tk = np.array([r[0] for r in self.rebases])
        dk = np.array([r[1] for r in self.rebases])             # (rebases, components)
        t = self.t
        # sample by sample, in O(rebases + samples) (a switching run re-bases at every block:
        # 20,000 times at 100 rollers): I(t_i) - I(t_(i-1)) = A(t_(i-1)) (t_i - t_(i-1)) plus
        # d_k (t_i - t_k) of the rebases in (t_(i-1), t_i], A(t) the rotation taken out by t
        at = np.searchsorted(t, tk, side="left")               # the first sample at or after each
        inside = at < t.size
        at, tk, dk = at[inside], tk[inside], dk[inside]
        step = np.zeros((dk.shape[1], t.size))
        for c in range(dk.shape[1]):
            local = np.bincount(at, weights=dk[:, c] * (t[at] - tk), minlength=t.size)
            taken = np.cumsum(np.bincount(at, weights=dk[:, c], minlength=t.size))
            step[c, 1:] = taken[:-1] * np.diff(t)
            step[c] += local
        return np.cumsum(step, axis=1)


def rigid_modes(Fs: list[np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
    """The free rigid rotations of a network: (R, roots), R[c] a state vector (angles only)
    with ``F R[c] = 0`` for every matrix F in ``Fs`` (the all-taut augmented matrices of the
    time pieces; a slack strand only takes a spring away, so R[c] holds in every strand
    pattern) and ``R[c, roots[c]] = 1``, one per connected group of the first ``n``
    (angle) coordinates that nothing holds to the frame. Empty where there is none (a
    spring to the frame, a prescribed angle).

    >>> F = np.zeros((4, 4)); F[0, 2] = F[1, 3] = 1.0
    >>> F[2, :2] = [-2.0, 2.0]; F[3, :2] = [1.0, -1.0]      # one spring between two inertias
    >>> rigid_modes([F], 2)[0]
    array([[1., 1., 0., 0.]])
    """
    F0 = Fs[0]
    m = F0.shape[0]
    link = np.zeros((n, n), dtype=bool)            # coordinates coupled through any row
    for F in Fs:
        nz = F[:, :n] != 0
        for row in np.flatnonzero(nz.sum(axis=1) > 1):
            cols = np.flatnonzero(nz[row])
            link[np.ix_(cols, cols)] = True
    seen = np.zeros(n, dtype=bool)
    out, roots = [], []
    for root in range(n):
        if seen[root]:
            continue
        group, todo = [root], [root]
        seen[root] = True
        while todo:                                # at most n visits: each coordinate once
            k = todo.pop()
            for j in np.flatnonzero(link[k] & ~seen):
                seen[j] = True
                group.append(int(j))
                todo.append(int(j))
        group.sort()
        r = np.zeros(len(group))
        r[group.index(root)] = 1.0
        rest = [i for i, g in enumerate(group) if g != root]
        if rest:
            # the group's accelerations from its angles, less the root's own row (a free group's
            # rows are dependent): a square system, then checked on every row of every matrix
            acc = [n + g for g in group if g != root]
            A = F0[np.ix_(acc, group)]
            try:
                r[rest] = np.linalg.solve(A[:, rest], -A[:, group.index(root)])
            except np.linalg.LinAlgError:
                continue
        size, worst = 0.0, 0.0
        with np.errstate(all="ignore"):
            for F in Fs:
                K = F[:, group]
                size = max(size, float(np.abs(K).sum(axis=0).max()) * float(np.abs(r).max()))
                worst = max(worst, float(np.abs(K @ r).max()))
        if not np.all(np.isfinite(r)) or not worst <= 1e-10 * size:
            continue                               # held to the frame: no free rotation
        v = np.zeros(m)
        v[group] = r
        out.append(v)
        roots.append(root)
    return np.array(out).reshape(len(out), m), np.array(roots, dtype=np.int64)


def slack_times(network, start: tuple[bool, ...], log: list[tuple[float, int, bool]], t_end: float) -> dict:
    """Each strand's time slack [s] from its first mode and its switches (t, strand, taut after)."""
    slack = {}
    for k, s in enumerate(network.strands):
        on, since, total = start[k], 0.0, 0.0
        for t, strand, state in log:
            if strand == k:
                if not on:
                    total += t - since
                on, since = state, t
        if not on:
            total += t_end - since
        slack[s.name] = total
    return slack



def switched_log(network, start: tuple, log: list[tuple[float, int, object]], t_end: float) -> dict:
    """The switched elements' history from a run's first mode and its switches (t, index in
    the mode, state after): ``{"start": their first states, "log": [(t, element, state)],
    "time": {name: {state name: seconds in it}}, "switches": {name: count}}`` (element: its
    index among ``network.switched``)."""
    ns = len(network.strands)
    first = tuple(int(s) for s in start[ns:])
    entries = [(t, k - ns, int(state)) for t, k, state in log if k >= ns]
    time, count = {}, {}
    for j, el in enumerate(network.switched):
        spent = {name: 0.0 for name in el.STATES}
        state, since, n = first[j], 0.0, 0
        for t, k, new in entries:
            if k == j:
                spent[el.STATES[state]] += t - since
                state, since, n = new, t, n + 1
        spent[el.STATES[state]] += t_end - since
        time[el.name], count[el.name] = spent, n
    return {"start": first, "log": entries, "time": time, "switches": count}


def switched_history(t: np.ndarray, history: dict) -> np.ndarray:
    """(switched elements, samples): each element's state at each sample time, from
    :func:`switched_log` (a sample at a switch's time takes the state after it)."""
    start = history["start"]
    out = np.empty((len(start), np.size(t)), dtype=np.int64)
    for j, s in enumerate(start):
        times = np.array([when for when, k, _ in history["log"] if k == j], dtype=float)
        states = np.array([s] + [state for _, k, state in history["log"] if k == j], dtype=np.int64)
        out[j] = states[np.searchsorted(times, np.asarray(t, dtype=float), side="right")]
    return out
