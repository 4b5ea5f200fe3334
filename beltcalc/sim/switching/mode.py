"""A mode of the switching core: one strand pattern on one time piece of the inputs.

Between switches the network is ``z' = F z`` with ``z = [x, g]``; a mode holds the balanced
``F~ = S^-1 F S`` of its pattern, its bottom step (:mod:`beltcalc.sim.switching.steps`) and its
switching rows ``H`` (one per event: a strand's force or elongation, with the direction it
fires in). :class:`Mode` is what every mode offers the run (the rounding levels, the state a
time into a step, the terms a block kept); :class:`DenseMode` is a small network's:

* ``expm`` ladders ``P_k = expm(F~ h / 2^k)`` of a stiff mode (``h = 2^K L``, built bottom-up
  by squaring), the orbit of a block by doubling (:func:`beltcalc.sim.propagate.orbit`);
* the switching functions' polynomial on a bottom step from the rows ``R_j = H (F~ L)^j / j!``
  (:attr:`DenseMode.R`), and a cheap rigorous bound of their reach (:meth:`DenseMode.near`)
  that leaves most steps without forming the polynomial;
* the exponential's integral for the window's means (:meth:`DenseMode.Q`,
  :meth:`DenseMode.step_integral`).

A large network's modes are :class:`beltcalc.sim.switching.sparse.SparseMode`.

References:

[VL78] C. F. Van Loan, "Computing integrals involving the matrix exponential", IEEE Trans.
    Automat. Control 23 (1978) 395-404.
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.numerics.expm import expm
from beltcalc.sim.propagate import augmented_matrix, orbit
from beltcalc.sim.switching.firing import ROUND
from beltcalc.sim.switching.steps import step_length, taylor_matrices, taylor_sum, taylor_terms, terms_for

STIFF = 64.0         # ||F~|| / fastest oscillation above which coarse steps are used
TAYLOR_BYTES = 2e6  # a dense mode keeps its Taylor matrices (TERMS x size^2) up to this size (size <= 71)
NEAR_GROUP = 8       # rows of a block sharing one second-order reach bound (DenseMode.near) ...
NEAR_GROUP_SIZE = 100    # ... on modes of at most this many states (the bound's set-up is 8 size^3)


class Mode:
    """One strand pattern on one time piece: what the run and the watch read of every mode.

    Attributes: ``taut`` (the pattern), ``sparse``, ``size`` (states with generators), ``L``
    (the bottom step), ``K`` and ``h = 2^K L`` (the coarse step: K > 0 only for a stiff dense
    mode), ``terms`` (of the Taylor series on a bottom step), ``Ft`` (the balanced F~),
    ``events``, ``H`` and ``absH`` (the switching rows and their magnitudes), ``dirs`` (each
    event's firing direction), ``event_strand`` and ``n_events``; the methods ``taylor``,
    ``orbit``, ``coeffs``, ``apply`` and ``nbytes`` are the subclasses' own."""

    sparse = False

    def levels(self, Z: np.ndarray) -> np.ndarray:
        """(events, rows of Z): the rounding level of each switching function at each row,
        ``ROUND |H| |z|`` (a value within it of zero is on the surface)."""
        return ROUND * (self.absH @ np.abs(Z).T) + 1e-300

    def kept(self, z0: np.ndarray) -> np.ndarray | None:
        """The Taylor terms (steps, terms, states) the orbit kept of its last block
        (:meth:`orbit`'s ``keep``) if that block started at ``z0``, else None."""
        block = getattr(self, "block", None)
        if block is None or not np.array_equal(block[0], z0):
            return None
        return block[2]

    def at(self, z: np.ndarray, tau: np.ndarray | float, integrate: bool = False, V: np.ndarray | None = None):
        """The exact state a time tau in [0, h] after z (rows of z for an array of tau):
        the ladder (:meth:`DenseMode.P`, a stiff mode's) for the whole bottom steps of tau,
        the Taylor sum for the rest. With
        ``integrate``: (state, integral of the state from 0 to tau), the integral summed
        the same way (``Q`` per ladder step, ``L sum_j V_j s^(j+1) / (j+1)`` for the rest).
        ``V``: z's Taylor terms where the caller has them (a mode without a ladder)."""
        tau = np.asarray(tau, dtype=float)
        Z = np.array(z, dtype=float, copy=True)
        I = np.zeros_like(Z) if integrate else None
        if self.K:
            q = np.minimum(np.floor(tau / self.L), 2 ** self.K - 1).astype(np.int64)
            frac = tau / self.L - q
            for k in range(self.K, 0, -1):            # bit (K - k) of q: a step of 2^(K-k) L
                bit = (q >> (self.K - k)) & 1
                if tau.ndim == 0:
                    if bit:
                        if integrate:
                            I = I + self.Q(k) @ Z
                        Z = self.P(k) @ Z
                elif bit.any():
                    if integrate:
                        I[bit == 1] += Z[bit == 1] @ self.Q(k).T
                    Z[bit == 1] = Z[bit == 1] @ self.P(k).T
        else:
            frac = tau / self.L
        V = self.taylor(Z) if V is None or self.K else V
        if not integrate:
            return taylor_sum(V, frac)
        W = V * (self.L / np.arange(1, self.terms + 1)).reshape((self.terms,) + (1,) * (V.ndim - 1))
        return taylor_sum(V, frac), I + taylor_sum(W, frac) * (frac[:, None] if np.ndim(frac) else frac)



class DenseMode(Mode):
    """A small network's mode: dense matrices, ``expm`` ladders, the orbit by doubling, the
    polynomial rows ``R`` precomputed."""

    def __init__(self, network, taut: tuple[bool, ...], t_mid: float, S: np.ndarray, omega: float, rho: float,
                 scale: float):
        self.taut = taut
        self._P: dict[int, np.ndarray] = {}
        self._doubling: dict[int, list] = {}
        self._Q: dict[int, np.ndarray] = {}
        self._R = None
        self._coeff_rows = 0
        self._T = None
        self._B2 = None
        self.events = network.events(taut) + network.switched_events(taut, t_mid)
        self.dirs = np.array([e.direction for e in self.events], dtype=float)
        self.event_strand = np.array([e.strand for e in self.events], dtype=np.int64)
        self.n_events = len(self.events)
        F = augmented_matrix(network, taut, t_mid)
        self.Ft = F / S[:, None] * S[None, :]
        self.size = F.shape[0]
        norm = float(np.abs(self.Ft).sum(axis=0).max())
        self.L = scale * step_length(norm, rho)
        self.terms = terms_for(norm * self.L)
        self.K = 0
        if omega > 0 and norm > STIFF * omega:
            self.K = max(0, int(math.floor(math.log2(1.0 / (omega * self.L)))))
        self.h = self.L * 2 ** self.K
        self.H = np.array([e.row for e in self.events]).reshape(len(self.events), F.shape[0]) * S[None, :]
        self.absH = np.abs(self.H)

    def apply(self, X: np.ndarray) -> np.ndarray:
        """F~ X for states X (states, columns)."""
        return self.Ft @ X

    @property
    def nbytes(self) -> int:
        """Memory the mode holds once its ladder, rows and squares are built (a fixed figure:
        the squares at their most, 12 of the step for MAX_BLOCK and 15 each of the sample
        steps for 2^15 samples in one block, the integral's twice the size)."""
        m, terms = self.Ft.shape[0], self.terms
        taylor = terms * m * m if terms * m * m * 8 <= TAYLOR_BYTES else 0
        return 8 * (m * m * (3 + self.K + 12 + 15 + 4 * 15) + terms * self.H.size + taylor)

    def taylor(self, Z: np.ndarray) -> np.ndarray:
        """V[j] = (F~ L)^j Z / j! for j < terms; Z is one state (size,) or rows (count, size):
        one product with the stacked Taylor matrices (:func:`beltcalc.sim.switching.steps.taylor_matrices`,
        kept per mode where they take at most TAYLOR_BYTES), else term by term."""
        terms = self.terms
        m = self.Ft.shape[0]
        if self._T is None and terms * m * m * 8 <= TAYLOR_BYTES:
            self._T = taylor_matrices(self.Ft, self.L, terms)
        if self._T is None:
            return taylor_terms(self.Ft, Z, self.L, terms)
        if Z.ndim == 1:
            return (self._T @ Z).reshape(terms, m)
        return (Z @ self._T.T).reshape(Z.shape[0], terms, m).transpose(1, 0, 2)

    def orbit(self, z: np.ndarray, count: int, stop_early: bool = False, integrate: bool = False,
              keep: np.ndarray | None = None, first: bool = False):
        """(Z, None, None): the states at ``count`` bottom steps from z (rows Z, count + 1 of
        them) by doubling; the run scans them itself (:func:`beltcalc.sim.switching.firing.first_crossing`)
        and integrates them by :class:`beltcalc.sim.switching.outputs.StepIntegrals`. The
        other arguments are :meth:`beltcalc.sim.switching.sparse.SparseMode.orbit`'s."""
        return orbit(self.doubling(), z, count + 1), None, None

    def coeffs(self, Z: np.ndarray) -> np.ndarray:
        """C (terms, events, rows of Z): every switching function's polynomial on the bottom
        step from each row of Z."""
        if not self.n_events:
            return np.zeros((self.terms, 0, Z.shape[0]))
        E = self.n_events
        self._coeff_rows += Z.shape[0]
        if self._R is None and self._coeff_rows < E:
            # forming R (terms x events x size^2) costs as much as the Taylor terms of as many
            # rows as there are events: a short-lived mode of a large network never forms it
            return np.matmul(self.H, self.taylor(Z).transpose(0, 2, 1))
        return (self.R.reshape(self.terms * E, -1) @ Z.T).reshape(self.terms, E, Z.shape[0])

    def P(self, k: int) -> np.ndarray:
        """expm(F~ h / 2^k): the ladder, built bottom-up by squaring from the bottom step."""
        if k not in self._P:
            M = expm(self.Ft * self.L)
            self._P[self.K] = M
            for level in range(self.K - 1, -1, -1):
                M = M @ M
                self._P[level] = M
        return self._P[k]

    def doubling(self, k: int = 0) -> list:
        """[P_k, P_k^2, P_k^4, ...] as far as :func:`beltcalc.sim.propagate.orbit` has needed them: the squares a
        run's blocks share."""
        if k not in self._doubling:
            self._doubling[k] = [self.P(k)]
        return self._doubling[k]

    def step(self, dt: float) -> list:
        """[expm(F~ dt), its square, ...] (:func:`beltcalc.sim.propagate.orbit`'s powers, as far
        as needed), for reading many uniformly spaced samples off one piece."""
        if getattr(self, "_step", (None,))[0] != dt:
            self._step = (dt, [expm(self.Ft * dt)])
        return self._step[1]

    def step_integral(self, dt: float) -> list:
        """[G, G^2, ...] (:func:`beltcalc.sim.propagate.orbit`'s powers) of
        ``G = [[S, 0], [Phi, I]]``, ``S = expm(F~ dt)``, ``Phi = int_0^dt expm(F~ tau) d tau``:
        ``[z; I] -> [S z; I + Phi z]`` steps a state and its integral from 0 one sample on, for
        reading many uniformly spaced samples and the integrals the window's means come from
        off one piece. Both blocks from one exponential,
        ``expm([[F~ dt, I dt], [0, 0]]) = [[S, Phi], [0, I]]`` [VL78 Theorem 1] (the integral
        of the exponential)."""
        if getattr(self, "_step_integral", (None,))[0] != dt:
            m = self.Ft.shape[0]
            M = np.zeros((2 * m, 2 * m))
            M[:m, :m] = self.Ft * dt
            M[:m, m:] = np.eye(m) * dt
            E = expm(M)
            G = np.zeros((2 * m, 2 * m))
            G[:m, :m] = E[:m, :m]
            G[m:, :m] = E[:m, m:]
            G[m:, m:] = np.eye(m)
            self._step_integral = (dt, [G])
        return self._step_integral[1]

    def Q(self, k: int) -> np.ndarray:
        """The integral of the ladder step, ``int_0^(h / 2^k) expm(F~ tau) d tau``: the
        bottom one ``L phi_1(F~ L)`` by its Taylor series (Horner, exact to rounding like
        the state's), the longer ones by ``Q_(k-1) = Q_k + P_k Q_k``."""
        if k not in self._Q:
            A = self.Ft * self.L
            eye = np.eye(A.shape[0])
            M = eye.copy()
            for j in range(self.terms, 1, -1):
                M = eye + (A @ M) / j
            Q = self.L * M
            self._Q[self.K] = Q
            for level in range(self.K - 1, -1, -1):
                Q = Q + self.P(level + 1) @ Q
                self._Q[level] = Q
        return self._Q[k]

    def near(self, Z: np.ndarray) -> np.ndarray:
        """(events, rows of Z): whether each switching function may come within its rounding
        level (:meth:`levels`) of zero on the bottom step from each row, without the whole
        step staying within it (a graze). A rigorous cheap bound of the polynomial's
        reach ``sum_(j>=1) |c_j|``: the rate ``c_1 = H (F~ L) z`` exactly, the rest by
        ``|H| |F~ L|^(j-2) |(F~ L)^2 z| / j!``. Bounding from the second derivative keeps the
        cancellation of rigid rotation (angles of hundreds of radians) that an absolute bound
        on z or z' loses: measured within 1 % of the exact reach on the roller table, where
        bounding from z' is 500 times too wide.

        The rows of Z are consecutive bottom steps, ``z_(i+r) = P^r z_i`` (``P = expm(F~ L)``,
        which commutes with ``F~``), so ``|(F~ L)^2 z_(i+r)| <= M |(F~ L)^2 z_i|`` with ``M``
        the largest ``|P^r|`` over r < NEAR_GROUP, entry by entry: the second-order part is
        formed on every NEAR_GROUP-th row only (the first order and the value, the bound's
        tight parts, on every row), at most a few times wider on a part that is itself small.
        The rounding levels the same way, ``|H| |z_(i+r)| <= |H| M |z_i|``: the exact level is
        formed only on the rows that bound does not clear."""
        if self._B2 is None:
            A, H = np.abs(self.Ft * self.L), self.absH
            theta = float(A.sum(axis=0).max())           # |A|'s largest column sum, ||F~ L||_1
            J = min(self.terms, int(math.ceil(2 * theta)) + 6)
            B, M, fact = np.zeros_like(H), H, 2.0
            for j in range(2, J):
                B += M / fact
                M, fact = M @ A, fact * (j + 1)
            if J < self.terms:
                # the terms from J on, entry by entry: (x |A|^k)_i <= max(x) theta^k, so their
                # sum is at most max(M) / J! / (1 - theta / (J + 1)) (M = |H| |A|^(J-2))
                B += (M.max(axis=1) / fact / (1.0 - theta / (J + 1)))[:, None]
            m = A.shape[0]
            self._group = NEAR_GROUP if m <= NEAR_GROUP_SIZE else 1
            P, power, M = self.P(self.K), np.eye(m), np.eye(m)
            for _ in range(1, self._group):
                power = power @ P
                np.maximum(M, np.abs(power), out=M)
            self._B2 = np.ascontiguousarray(B @ M if self._group > 1 else B)
            self._HM = ROUND * (self.absH @ M if self._group > 1 else self.absH)
            A = self.Ft * self.L
            self._W = np.vstack([self.H @ A, self.H])    # one product for both
            self._A2 = A @ A
        # events along the first axis: the reductions over events run along whole rows
        E, k, n = self.H.shape[0], self._group, Z.shape[0]
        P = np.abs(self._W @ Z.T)                      # (E + E, rows): |H A z|, |H z|
        second = self._B2 @ np.abs(self._A2 @ Z[::k].T)         # (E, rows / k): M |A^2 z| through the series
        bound = P[:E]
        bound += np.repeat(second, k, axis=1)[:, :n]
        C0 = P[E:]
        high = np.repeat(self._HM @ np.abs(Z[::k]).T, k, axis=1)[:, :n]
        high += bound
        high += 1e-300
        rows = np.flatnonzero((C0 <= high).any(axis=0))
        out = np.zeros((E, n), dtype=bool)
        if rows.size:
            tol, b, c = self.levels(Z[rows]), bound[:, rows], C0[:, rows]
            out[:, rows] = (c <= b + tol) & (b + c > tol)
        return out

    @property
    def R(self) -> np.ndarray:
        """R[j] = H (F~ L)^j / j!: the polynomial coefficients of every switching function on
        a bottom step are R @ z."""
        if self._R is None:
            R = np.empty((self.terms, *self.H.shape))
            R[0] = self.H
            M = self.Ft * self.L
            for j in range(1, self.terms):
                R[j] = (R[j - 1] @ M) / j
            self._R = R
        return self._R

