r"""Batched exact propagation: the runs of a study chunk that share one structure, solved together.

A study (:mod:`beltcalc.sim.study`) runs one scene many times with some values changed. Where
every run of a chunk is one linear time-invariant network over the whole run (no strands, no
time break points, no nonlinear element) with the same states, generators and time grid,
each run ``r`` is ``z_r' = F_r z_r`` with ``z = [x, g]`` (the state and the input
generators [MVL03 sec. 10], :func:`beltcalc.sim.propagate.augmented_matrix`), and what its
summary row needs is a few signals ``y_ri(t_k) = c_ri^T z_r(t_k)`` that are linear in ``z``:
speeds, accelerations (``c^T F``), coupling torques, a motor's torque. They are computed for
the chunk at once:

- ``F~_r = D_r^{-1} F_r D_r`` balanced (powers of two, exact), ``S_r = expm(F~_r dt)`` by
  scaling and squaring [AH09] for the whole stack in one call (:func:`beltcalc.numerics.expm.expm`
  takes ``(runs, n, n)``);
- with ``b = ceil(sqrt(N))`` for ``N`` samples, the rows ``w_{r,i,j} = c~_ri^T S_r^j``
  (``j < b``) by doubling and the block starts ``S_r^{kb} z~_r(0)`` by doubling: then
  ``y_ri(t_{kb + j}) = (S_r^{kb} z~_r(0)) . w_{r,i,j}``, one batched matrix product per pass
  (the block scheme of :func:`beltcalc.sim.propagate.propagate`, reading off only the signals
  asked for instead of every state);
- reduced at once to what the row reports: min, max and trapezoid mean over each run's steady
  window, the peak of each speed over the run, and the error estimate of
  :func:`beltcalc.sim.core.estimate_error` (the speeds at every (b+1)-th sample and the last
  again with ``expm(F~ dt / 3)^3``, the other internal partition:
  :func:`beltcalc.sim.propagate.reference_rows`, plus the conditioning floor ``eps ||F~||_1 t_end``).

No time series is kept: a pass holds at most :data:`PASS_BYTES` of samples, so memory does not
grow with the chunk or the number of runs.

This module knows no scene. A scene that can be batched declares its batch row
(:class:`beltcalc.sim.scenes.base.BatchRow`, its :attr:`~beltcalc.sim.scenes.base.Scene.batch`):
the function that builds its runs' networks, asks these for the signals its row reports and
turns them into the row, in the order of its columns; today the sewing scene (its time run and
``steady_state_only``: :func:`beltcalc.sim.scenes.sewing.batched_rows`). Drive files run one by
one: their rows take extremes and means off the exact solution between the samples
(:mod:`beltcalc.sim.watch`), which the batch does not reproduce. Every run a batch row cannot
vouch for (an impossible value, an eccentric roller or angle-locked loads: nonlinear; another
structure than the chunk's; a check within :data:`MARGIN` of its limit or failing; an error
estimate above half the tolerance) goes through the scene's own single run
(:func:`beltcalc.sim.study.runs.run_one`), and so does one run of every chunk, whose row the
batch must reproduce (:func:`beltcalc.sim.study.runs.agrees`) or the whole chunk goes one by
one.

References:

[MVL03] C. Moler and C. Van Loan, "Nineteen dubious ways to compute the exponential of a
    matrix, twenty-five years later", SIAM Review 45 (2003) 3-49: the augmented system for
    polynomial and sinusoidal inputs.
[AH09] A. H. Al-Mohy and N. J. Higham, "A new scaling and squaring algorithm for the matrix
    exponential", SIAM J. Matrix Anal. Appl. 31 (2009) 970-989: :func:`beltcalc.numerics.expm.expm`.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from beltcalc.numerics.balance import balance
from beltcalc.sim.propagate import augmented_matrix, balanced_step, block_length, matrix_orbit, orbit, reference_rows

PASS_BYTES = 16 * 2 ** 20   # samples held by one pass of the batch (runs x samples x signals x 8 bytes)
MARGIN = 1e-6               # a check whose utilisation is above 1 - MARGIN goes through the single run


# --- the engine ----------------------------------------------------------------------------------

class Propagation:
    r"""The exact solution of a stack of runs ``z_r' = F_r z_r`` at ``samples`` points ``k dt``,
    as :func:`beltcalc.sim.propagate.propagate` computes it for one run, with the same operations
    in the same order (so the same numbers): ``F~ = D^{-1} F D`` balanced, ``S = expm(F~ dt /
    parts)^parts`` (:func:`beltcalc.numerics.expm.expm` on the whole stack), the powers ``S^j`` (``j <
    b = ceil(sqrt(samples))``) and the block starts ``S^{kb} z~(0)`` by doubling; then
    ``z_i(t_{kb+j}) = D_i (S^j)_i . S^{kb} z~(0)``. :meth:`rows` reads any rows over any
    range of blocks, so a run's summary needs only its window and the rows it reports.

    Notes
    -----
    Moler & Van Loan, SIAM Review 45 (2003) 3-49, sections 3 and 10 (scaling and squaring, the
    augmented system of the inputs); the block scheme is :func:`beltcalc.sim.propagate.propagate`'s.
    """

    def __init__(self, F: np.ndarray, z0: np.ndarray, dt: float, samples: int, parts: int = 1,
                 scale: np.ndarray | None = None, step: np.ndarray | None = None):
        self.scale = balance(F) if scale is None else scale
        s = self.scale
        if step is None:
            step = balanced_step(F, s, dt, parts)
        self.b = b = block_length(samples)
        self.powers = matrix_orbit(step, b)
        jump = step @ self.powers[:, b - 1]
        self.full, self.tail = divmod(samples, b)
        self.starts = orbit(jump, z0 / s, self.full + (self.tail > 0))
        self.samples = samples

    def rows(self, rows: Sequence[int], block0: int = 0, block1: int | None = None) -> np.ndarray:
        """z[rows] at the samples of blocks ``block0`` to ``block1`` (exclusive; None: to the last
        sample): (runs, len(rows), samples)."""
        rows = np.asarray(rows)
        R = self.starts.shape[0]
        b, full, tail = self.b, self.full, self.tail
        P = np.ascontiguousarray((self.powers[:, :, rows, :] * self.scale[:, None, rows, None]).transpose(0, 2, 3, 1))
        stop = full if block1 is None else min(block1, full)
        with_tail = block1 is None and tail
        out = np.empty((R, rows.size, (stop - block0) * b + (tail if with_tail else 0)))
        if stop > block0:
            blocks = out[:, :, :(stop - block0) * b].reshape(R, rows.size, stop - block0, b)
            np.matmul(self.starts[:, None, block0:stop], P, out=blocks)
        if with_tail:
            for r in range(R):
                out[r, :, (stop - block0) * b:] = self.starts[r, full] @ P[r, :, :, :tail]
        return out


def exact_windows(nets: Sequence, t: np.ndarray, first: Sequence[int], names: Sequence[str],
                  estimate: bool = True):
    """For each network (one linear piece over the run, all of one size and time grid ``t``),
    the signals ``names`` over its window (the samples from ``first[r]`` on), computed as a
    single run computes them (:func:`beltcalc.sim.core._outputs`; the same operations but for
    the order of a sum, so equal to rounding): a state; ``accel_<node>`` of a coordinate, its
    row of ``[A B] z`` (:func:`beltcalc.sim.core.one_piece_accelerations`, ``g`` as propagated);
    ``T_<coupling>``, ``C (g . phi) + d (g . omega)``
    (:meth:`beltcalc.sim.elements.Coupling.outputs_of`); and the run's error estimate as
    :func:`beltcalc.sim.core.estimate_error` forms it (the speeds against
    :func:`beltcalc.sim.propagate.reference_rows`, plus the conditioning floor), relative to the
    speeds' peaks over the window and the reference's samples before it: a lower bound of the
    single run's scale (its peaks over every sample), so the batch's estimate is at least the
    single run's, and no speed is formed before the window.

    Yields one pass of runs at a time: ``(runs, k, Y, err)``, ``Y[j, i]`` signal ``names[i]``
    of run ``runs[j]`` at the samples from ``k`` on (``k <= first[r]``), ``err[j]`` its
    relative error estimate (None without ``estimate``). A pass holds at most
    :data:`PASS_BYTES` of states. A name of another kind raises KeyError.
    """
    from beltcalc.sim.switching import EPS

    R = len(nets)
    if R == 0:
        return
    N = t.size
    dt = t[1] - t[0]
    net0 = nets[0]
    m, n = net0.size, net0.n
    states = net0.state_names()
    index = {name: k for k, (name, _) in enumerate(states)}
    kinds = []
    for name in names:
        if name in index:
            kinds.append(("state", index[name]))
        elif name.startswith("accel_") and name[6:] in net0.index:
            kinds.append(("accel", n + net0.index[name[6:]]))
        elif name.startswith("T_") and any(c.name == name[2:] for c in net0.couplings):
            kinds.append(("torque", name[2:]))
        else:
            raise KeyError(name)
    accel = [k for kind, k in kinds if kind == "accel"]
    torque = [c for kind, c in kinds if kind == "torque"]
    speeds = list(range(n, 2 * n))
    units = [states[k][1] for k in speeds]
    step = max(1, int(PASS_BYTES // (8 * N * (m + len(names) + (2 * n if estimate else 0)))))
    # the chunk's balancings, steps, initial states and error references: one stacked call each
    F_all = np.stack([augmented_matrix(net) for net in nets])
    scale_all = balance(F_all)
    step_all = balanced_step(F_all, scale_all, dt)
    z0_all = np.stack([np.concatenate([net.initial_state(), net.generators(0.0)]) for net in nets])
    if estimate:
        at, ref_all = reference_rows(F_all, z0_all, dt, N, speeds, scale=scale_all)
    for a in range(0, R, step):
        idx = list(range(a, min(R, a + step)))
        Rp = len(idx)
        F = F_all[a:a + Rp]
        z0 = z0_all[a:a + Rp]
        prop = Propagation(F, z0, dt, N, scale=scale_all[a:a + Rp], step=step_all[a:a + Rp])
        b = prop.b
        block0 = min(int(first[r]) for r in idx) // b
        k = block0 * b
        Z = prop.rows(range(z0.shape[1]), block0)            # every state and generator, from the window's block on
        X = Z[:, :m]
        Y = np.empty((Rp, len(names), N - k))
        for i, (kind, what) in enumerate(kinds):
            if kind == "state":
                Y[:, i] = X[:, what]
        if accel:
            # the rows of A x + B g (one_piece_accelerations), g as propagated: one product on z
            AB = np.stack([np.hstack(nets[r].first_order())[accel] for r in idx])
            dx = AB @ Z
            for i, (kind, what) in enumerate(kinds):
                if kind == "accel":
                    Y[:, i] = dx[:, accel.index(what)]
        if torque:
            cs = [[next(c for c in nets[r].couplings if c.name == name) for name in torque] for r in idx]
            G = np.stack([np.array([c.deflection(nets[r]) for c in row]) for r, row in zip(idx, cs)])
            C = np.array([[c.C for c in row] for row in cs])[:, :, None]
            D = np.array([[c.d for c in row] for row in cs])[:, :, None]
            T = G @ X[:, :n]                                    # Coupling.outputs_of, its operations
            T *= C
            rate = G @ X[:, n:2 * n]
            rate *= D
            T += rate
            for i, (kind, what) in enumerate(kinds):
                if kind == "torque":
                    Y[:, i] = T[:, torque.index(what)]
        err = None
        if estimate:
            ref = ref_all[a:a + Rp].copy()                      # the single run's reference
            win = X[:, n:2 * n]
            peak = np.maximum(win.max(axis=2), -win.min(axis=2))
            pre = at[at < k]
            if pre.size:
                # the run's speeds at the reference's samples before the window, each off its
                # block start: z(q b + r) = D S~^r z~(q b)
                q, r = np.divmod(pre, b)
                zs = (prop.powers[:, r][:, :, n:2 * n, :] @ prop.starts[:, q, :, None])[..., 0]
                zs = zs.transpose(0, 2, 1) * prop.scale[:, n:2 * n, None]
                peak = np.maximum(peak, np.abs(zs).max(axis=2))
                ref -= np.concatenate([zs, win[:, :, at[at >= k] - k]], axis=2)
            else:
                ref -= win[:, :, at - k]
            apart = np.maximum(ref.max(axis=2), -ref.min(axis=2))
            s = prop.scale
            floor = EPS * np.abs(F / s[:, :, None] * s[:, None, :]).sum(axis=1).max(axis=1) * float(t[-1])
            err = np.array([_relative(peak[j], apart[j], float(floor[j]), units) for j in range(Rp)])
        yield idx, k, Y, err


def _relative(peak: np.ndarray, apart: np.ndarray, floor: float, units: Sequence[str]) -> float:
    """The largest relative error estimate over the speeds, as
    :func:`beltcalc.sim.core.estimate_error` forms it: per speed ``apart + floor x scale`` over
    ``scale``, the scale the largest peak of the speeds of its unit (1 where that is 0)."""
    scales: dict[str, float] = {}
    for u, p in zip(units, peak):
        scales[u] = max(scales.get(u, 0.0), float(p))
    worst = 0.0
    for u, d in zip(units, apart):
        sc = scales[u] if scales[u] > 0 else 1.0
        worst = max(worst, (float(d) + floor * sc) / sc)
    return worst


def window_stats(t: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(mean, amplitude, min, max) of each row of ``Y`` (signals over the samples at ``t``, the
    whole window, uniformly spaced), as :meth:`beltcalc.sim.result.SimResult.summary` takes
    them from the samples: the mean by the trapezoid rule over the window's length, within the
    extremes; the amplitude half the peak-to-peak. On the uniform grid the trapezoid sum is
    ``(sum - (first + last) / 2) dt``: one pass over the samples instead of ``numpy.trapezoid``'s
    four, equal to it to rounding (the grid's spacing varies by an ulp).

    >>> [v.tolist() for v in window_stats(np.array([0.0, 1.0, 2.0]), np.array([[1.0, 3.0, 1.0]]))]
    [[2.0], [1.0], [1.0], [3.0]]
    """
    lo, hi = Y.min(axis=-1), Y.max(axis=-1)
    if Y.shape[-1] > 1:
        mean = (Y.sum(axis=-1) - 0.5 * (Y[..., 0] + Y[..., -1])) / (Y.shape[-1] - 1)
    else:
        mean = Y[..., 0].copy()
    return np.minimum(np.maximum(mean, lo), hi), 0.5 * (hi - lo), lo, hi


def steady_stats(nets: Sequence, names: Sequence[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(mean, amplitude), each (runs, len(names)), of the exact periodic steady state of each
    network (:func:`beltcalc.sim.frequency.steady_state`, the same operations: the means
    by :func:`beltcalc.sim.frequency.mean_states` for the stack, the complex solves ``(j w I -
    A) X = B_c - j B_s`` of every run in one batched call), and ``ok`` (runs,): False where a
    run's drive does not balance (its single run says so). The networks have the same size
    and one load frequency each (strands none, no ramp)."""
    from beltcalc.sim import frequency as fr

    R, q = len(nets), len(names)
    if not R:
        return np.zeros((0, q)), np.zeros((0, q)), np.ones(0, dtype=bool)
    AB = [net.first_order(None, 1.0) for net in nets]
    A = np.stack([A for A, _ in AB])
    mean_x, ok = fr.mean_states(A, np.stack([B[:, 0] for _, B in AB]), balance(A))
    net0 = nets[0]
    states, eye = [s for s, _ in net0.state_names()], np.eye(net0.size)
    # the output rows (runs, names, size) and powers of j w: a state's and an acceleration's
    # are the same for every run, a coupling's torque has each run's own C and d
    same = {y: _output_row(net0, y, states, eye) for y in names if not y.startswith("T_")}
    rows = np.stack([np.stack([same[y][0] if y in same else _output_row(net, y, states, eye)[0] for y in names])
                     for net in nets])
    power = np.array([same[y][1] if y in same else 0 for y in names])
    w = np.array([net.frequencies()[0] for net in nets])
    M = 1j * w[:, None, None] * eye[None] - A
    X = np.linalg.solve(M, np.stack([B[:, 2] - 1j * B[:, 1] for _, B in AB])[:, :, None])[:, :, 0]
    # each value by its own dot product, as the single run forms it: a torque's mean is the
    # small difference of large terms (the angles), so the order of the sum shows at 1e-11
    mean, amp = np.zeros((R, q)), np.zeros((R, q))
    for r in range(R):
        for i in range(q):
            if power[i] == 0:
                mean[r, i] = rows[r, i] @ mean_x[r]
            amp[r, i] = abs(complex(rows[r, i] @ X[r] * (1j * w[r]) ** power[i]))
    return mean, amp, ok


def _output_row(net, name: str, names: Sequence[str], eye: np.ndarray) -> tuple[np.ndarray, int]:
    """(row over the state, power of j w) of a state, ``T_<coupling>`` or ``accel_<node>`` of a
    coordinate: the rows :func:`beltcalc.sim.frequency.output_row` takes from
    :meth:`beltcalc.sim.network.Network.linear_rows` (unit rows; the coupling's torque of the identity).
    ``names``: the state names; ``eye``: the identity of the state's size."""
    if name in names:
        return eye[names.index(name)], 0
    if name.startswith("T_"):
        from beltcalc.sim.elements import Coupling

        c = [c for c in net.couplings if c.name == name[2:]]
        return np.asarray(Coupling.outputs_of(net, c, None, eye, None)[name][0], dtype=float), 0
    if name.startswith("accel_") and f"omega_{name[6:]}" in names:
        return eye[names.index(f"omega_{name[6:]}")], 1
    raise KeyError(name)


def eigenvalues(nets: Sequence) -> np.ndarray:
    """The eigenvalues of each network's state matrix (strands taut), one stacked call:
    (runs, states), as :func:`beltcalc.sim.frequency.poles` computes them for one."""
    return np.linalg.eigvals(np.stack([net.state_matrix() for net in nets]))


def resonance_separation(nets: Sequence, lam: np.ndarray | None = None) -> np.ndarray:
    """Per network the least relative separation ``|f_e - f_n| / f_n`` of a load's frequency
    (a sinusoid in time with an amplitude) from an undamped natural frequency of an
    oscillatory mode (:func:`beltcalc.sim.scenes.run_checks.resonance_check`, whose poles are
    :func:`beltcalc.sim.frequency.poles`: the eigenvalues of A, one batched call, or ``lam``
    where given: :func:`eigenvalues`); NaN where there is no such check, 0 where an element has
    an excitation of its own (not covered here).

    Notes
    -----
    Classification as :func:`beltcalc.sim.frequency._classify`: a pole is oscillatory when
    ``|Im s|`` and ``|s|`` exceed ``1e-7 max(1, max |s|)``; ``f_n = |s| / 2 pi``.
    """
    out = np.full(len(nets), np.nan)
    if not nets:
        return out
    if lam is None:
        lam = eigenvalues(nets)
    for r, net in enumerate(nets):
        if any(hasattr(el, "excitation") for el in net.elements):
            out[r] = 0.0
            continue
        exc = [abs(ld.omega) / (2 * math.pi) for ld in net.loads if ld.amplitude and not ld.in_angle and ld.omega]
        s = lam[r]
        floor = 1e-7 * max(1.0, float(np.max(np.abs(s)))) if s.size else 0.0
        fn = np.abs(s[(s.imag > floor) & (np.abs(s) > floor)]) / (2 * math.pi)
        if exc and fn.size:
            out[r] = min(float(np.min(np.abs(f - fn) / fn)) for f in exc)
    return out
