"""The sparse path of the switching core: a large network's modes (from SPARSE_SIZE states,
:mod:`beltcalc.sim.switching.run`).

``F~`` of a strand pattern is assembled from the strands' stamps in O(nonzeros)
(:class:`beltcalc.sim.switching.parts.SparseParts`), and every bottom step is its Taylor
sum of sparse products, summed until the bound of the tail left is TAIL of ``||z||_1``:
nothing of size states^2 is formed, so a new strand pattern costs little. A block's orbit
stops at its first switch (:meth:`SparseMode.orbit`), its switching functions examined on
the step's own Taylor terms. The products go through scipy's own C kernels behind
``csr @ vector`` and ``csr @ dense`` where they answer as the public product does
(:func:`_sparse_kernels`), else through the public product.
"""

from __future__ import annotations

import numpy as np

from beltcalc.sim.switching.firing import ROUND, first_fire, may_fire, stays_down
from beltcalc.sim.switching.mode import Mode
from beltcalc.sim.switching.parts import SparseParts
from beltcalc.sim.switching.steps import step_length, terms_for

_kernels = ...   # scipy's C kernels behind ``csr @ vector`` and ``csr @ dense``: looked up on first use


def _sparse_kernels():
    """scipy's own C kernels behind ``csr @ vector`` (``y += A x``) and ``csr @ dense``
    (``Y += A X``, X row-major (columns of A, vectors)), without the ~4 us of Python dispatch
    per call (the sparse path makes millions), or None where scipy lacks them. Imported on
    first use: a dense run never needs scipy.sparse (about 12 ms of start-up)."""
    global _kernels
    if _kernels is ...:
        try:
            from scipy.sparse._sparsetools import csr_matvec, csr_matvecs
            _kernels = (csr_matvec, csr_matvecs) if _kernels_agree(csr_matvec, csr_matvecs) else None
        except ImportError:
            _kernels = None
    return _kernels


def _kernels_agree(matvec, matvecs) -> bool:
    """Whether scipy's private kernels still take the arguments they took when this was
    written (scipy 1.11-1.16) and accumulate what the public product gives, on a 3 x 2
    matrix with an empty row: a private signature may change in any release, and a kernel
    that reads its arguments otherwise is not used (the public ``@`` is)."""
    from scipy.sparse import csr_matrix

    A = csr_matrix(np.array([[1.0, 0.0], [0.0, 0.0], [2.0, -3.0]]))
    x, X = np.array([0.5, 2.0]), np.array([[0.5, 1.0], [2.0, -1.0]])
    y, Y = np.ones(3), np.ones((3, 2))
    try:
        matvec(*_csr(A), x, y)
        matvecs(*A.shape, 2, A.indptr, A.indices, A.data, X.ravel(), Y.ravel())
    except (TypeError, ValueError):
        return False
    return bool(np.array_equal(y, 1.0 + A @ x) and np.array_equal(Y, 1.0 + A @ X))


def _csr(A) -> tuple:
    """(rows, columns, indptr, indices, data) of a CSR matrix: a kernel's first arguments."""
    return (*A.shape, A.indptr, A.indices, A.data)


TAIL = 2.0 ** -64    # the sparse orbit's terms: until the bound of the tail left is this of ||z||_1 (5e-20)


class SparseMode(Mode):
    """A large network's mode: ``F~`` assembled from the strands' stamps in O(nonzeros),
    every bottom step taken by its Taylor sum of sparse products; no ladder (K = 0), nothing
    of size states^2."""

    sparse = True

    def __init__(self, parts: SparseParts, taut: tuple[bool, ...], t_mid: float, S: np.ndarray, rho: float,
                 scale: float):
        self.taut = taut
        self._Ft = self._events = None
        # the events in the parts' fixed order, two per strand (:meth:`SparseParts.events`):
        # the rows are every mode's (H shared), only their directions follow the pattern
        self._parts = parts
        self.dirs, self.event_strand = parts.directions(taut), parts.event_strand
        self.n_events = self.dirs.size
        self._csr_F, norm = parts.matrix(taut, t_mid)
        self.size = S.size
        self.L = scale * step_length(norm, rho)
        self.terms = terms_for(norm * self.L)
        # the orbit's test for the tail left after term j: ||V_j||_1 times this, at most
        # TAIL times ||z||_1 (||V_(k+1)|| <= theta / (k + 1) ||V_k|| with theta = ||F~ L||_1)
        theta = norm * self.L
        j = np.arange(self.terms, dtype=float)
        with np.errstate(divide="ignore"):
            self._tail = np.where(j + 2 > theta, theta / (j + 1) / (1 - theta / (j + 2)), np.inf)
        self.K, self.h = 0, self.L
        self.H, self.absH = parts.H, parts.absH
        # (F~ L / j) for the Taylor recursion: one sparsity pattern, the data scaled per j
        indptr, indices, data = self._csr_F
        scaled = data[None, :] * (self.L / np.arange(1, self.terms))[:, None]
        self._Ms = [(self.size, self.size, indptr, indices, d) for d in scaled]
        self._H, self._absH = _csr(self.H), _csr(self.absH)

    @property
    def Ft(self):
        """The balanced F~ as a scipy CSR matrix, formed when first asked for (a chain builds a
        mode at nearly every switch; its steps use the arrays)."""
        if self._Ft is None:
            indptr, indices, data = self._csr_F
            self._Ft = self._parts.sparse.csr_matrix((data, indices, indptr), shape=(self.size, self.size))
        return self._Ft

    @property
    def events(self) -> list:
        """The switching surfaces, as event objects, formed when asked for."""
        if self._events is None:
            self._events = self._parts.events(self.taut)
        return self._events

    def apply(self, X: np.ndarray) -> np.ndarray:
        """F~ X for states X (states, columns): by scipy's kernel on the mode's arrays."""
        kernels = _sparse_kernels()
        if kernels is None:
            return self.Ft @ X
        Y = np.zeros((self.size, X.shape[1]))
        indptr, indices, data = self._csr_F
        kernels[1](self.size, self.size, X.shape[1], indptr, indices, data, np.ascontiguousarray(X).ravel(), Y.ravel())
        return Y

    def M(self, j: int):
        """``F~ L / j`` as a scipy sparse matrix (the sparse path where scipy's kernels are
        not to be had)."""
        return self.Ft * (self.L / j)

    @property
    def nbytes(self) -> int:
        """Memory the mode holds: its scaled copies of F~ (one per Taylor term)."""
        return 8 * self.terms * self._csr_F[2].size

    def taylor(self, Z: np.ndarray) -> np.ndarray:
        """V[j] = (F~ L)^j Z / j! for j < terms; Z is one state (size,) or rows (count, size),
        summed by sparse products until the tail's bound is TAIL of ``|z|_1`` (the later terms
        0), as :meth:`orbit`'s steps."""
        terms = self.terms
        kernels = _sparse_kernels()
        if kernels is None:
            V = np.empty((terms, *Z.shape))
            V[0] = Z
            for j in range(1, terms):
                V[j] = self.M(j) @ V[j - 1] if Z.ndim == 1 else (self.M(j) @ V[j - 1].T).T
            return V
        # the terms up to where the tail's bound is TAIL of |z|_1 (every z's), as the orbit's
        # steps: the rest stay 0
        if Z.ndim == 1:
            V = np.zeros((terms, Z.size))
            V[0] = Z
            limit = TAIL * np.abs(Z).sum()
            first = getattr(self, "_used", 9) - 1
            for j in range(1, terms):
                kernels[0](*self._Ms[j - 1], V[j - 1], V[j])
                if j >= first and np.abs(V[j]).sum() * self._tail[j] <= limit:
                    break
            return V
        X = np.zeros((terms, Z.shape[1], Z.shape[0]))      # rows as columns: what csr @ dense reads
        X[0] = Z.T
        limit = TAIL * np.abs(Z).sum(axis=1)
        first = getattr(self, "_used", 9) - 1
        for j in range(1, terms):
            kernels[1](*self._Ms[j - 1][:2], Z.shape[0], *self._Ms[j - 1][2:], X[j - 1].ravel(), X[j].ravel())
            if j >= first and np.all(np.abs(X[j]).sum(axis=0) * self._tail[j] <= limit):
                break
        return X.transpose(0, 2, 1)

    def orbit(self, z: np.ndarray, count: int, stop_early: bool = False, integrate: bool = False,
              keep: np.ndarray | None = None, first: bool = False):
        """The states at ``count`` bottom steps from z (rows Z, count + 1 of them) and the
        switching functions' polynomial coefficients on each step, C (terms, events, count).
        ``stop_early``: end the block at the first step where a switching function crosses
        (nothing is propagated past a switch only to be thrown away): where one comes within
        its polynomial's reach of zero and may fire (:func:`beltcalc.sim.switching.firing.may_fire`,
        :func:`beltcalc.sim.switching.firing.stays_down`), the step is examined as
        :func:`beltcalc.sim.switching.firing.first_crossing` examines it (:func:`first_fire`;
        ``first``: z is a restart point), and the crossing found kept in ``self.hit`` as
        (step, s, event), else None; the block's last step is left to the scan.
        ``integrate``: also J, the integral of z over each step (rows; None otherwise: a dense
        run integrates by :class:`beltcalc.sim.switching.outputs.StepIntegrals`).
        ``keep``: a scratch array of at least (count, terms, states) into which each
        step's Taylor terms are written; ``self.block`` then holds (the block's first state,
        each step's midpoint, the terms kept), which the watch reads instead of Taylor sums
        of its own (the terms are those :meth:`taylor` forms, bit for bit: the same sparse
        sums in the same order)."""
        T, size = self.terms, z.size
        Z = np.empty((count + 1, size))
        Z[0] = z
        self.block = self.hit = None
        mids = np.empty((count if keep is not None else 0, size))     # each step's midpoint (the watch's)
        C = np.empty((count, self.n_events, T))          # filled where asked for: a hit, the last step
        J = np.empty((count, size)) if integrate else None
        W = np.empty((3, T))                             # one product a step: next state, midpoint, integral
        W[0], W[1], W[2] = 1.0, 0.5 ** np.arange(T), self.L / np.arange(1, T + 1)
        out = np.empty((3, size))
        Vs = keep[:count, :T] if keep is not None else np.empty((1, T, size))
        kernels = _sparse_kernels()
        E = self.n_events
        level, c0, c1, rest = np.empty(E), np.empty(E), np.empty(E), np.empty(E)
        tail = self._tail
        used = getattr(self, "_used", min(T, 16))     # terms the last step needed: the next is tested from there
        # the terms up to the first j whose tail bound is below TAIL ||z||_1 (the rest stay 0):
        # the series' own decay, exp(rho L) rather than exp(||F~ L||), decides how many
        limit = TAIL * np.abs(z).sum()
        rows = list(Vs[0])
        chain = list(zip(self._Ms, rows, rows[1:]))
        for i in range(count):           # sequential: each step's Taylor sum of sparse products
            V = Vs[0]
            if keep is not None and i:           # this step's own rows of the kept terms
                V = Vs[i]
                rows = list(V)
                chain = list(zip(self._Ms, rows, rows[1:]))
            V[0] = Z[i]
            n = T
            if kernels is not None:
                V[1:].fill(0.0)
                matvec = kernels[0]
                for j, (args, x, y) in enumerate(chain, 1):
                    matvec(*args, x, y)
                    if j >= used - 1 and np.abs(y).sum() * tail[j] <= limit:
                        n = j + 1
                        break
            else:
                for j in range(1, T):
                    V[j] = self.M(j) @ V[j - 1]
            used = n
            Vn = V[:n]
            np.matmul(W[:, :n], Vn, out=out)
            Z[i + 1] = out[0]
            if keep is not None:
                mids[i] = out[1]
            if integrate:
                J[i] = out[2]
            if not (stop_early and i + 1 < count):      # the block's last step: the scan's, in full
                C[i, :, :n] = self._coefficients(Vn)
                C[i, :, n:] = 0.0
                continue
            # a step where some function may cross: its value H z, its rate H V_1 and the rest
            # bounded by |H| sum_(j>=2) |V_j| (a switching function's polynomial's reach), then
            # the exact coefficients of those that come within it of zero, and the test
            # first_crossing makes: near, its Bernstein hull, its values, then first_fire
            if kernels is not None:
                for buf, vec, mat in ((c0, Z[i], self._H), (c1, V[1], self._H),
                                      (rest, np.abs(V[2:n]).sum(axis=0), self._absH),
                                      (level, np.abs(Z[i]), self._absH)):
                    buf[:] = 0.0
                    kernels[0](*mat, vec, buf)
            else:
                c0[:], c1[:] = self.H @ Z[i], self.H @ V[1]
                rest[:], level[:] = self.absH @ np.abs(V[2:n]).sum(axis=0), self.absH @ np.abs(Z[i])
            tol = ROUND * level + 1e-300
            bound = np.abs(c1) + rest
            near = np.flatnonzero((np.abs(c0) <= bound + tol) & (bound + np.abs(c0) > tol))
            if not near.size:
                continue
            c = np.zeros((near.size, T))
            c[:, :n] = self._coefficients(Vn, near)
            reach = np.abs(c[:, 1:]).sum(axis=1)
            keep_e = (np.abs(c[:, 0]) <= reach + tol[near]) & (reach + np.abs(c[:, 0]) > tol[near])
            near, c = near[keep_e], c[keep_e]
            if not near.size:
                continue
            pc = c[:, :n] * self.dirs[near, None]
            fire = may_fire(pc.T[:, :, None], tol[near, None])[:, 0]
            fire[fire] = ~stays_down(pc[fire], tol[near][fire])
            best = None
            for k in np.flatnonzero(fire):
                e = int(near[k])
                s = first_fire(c[k], self.dirs[e], float(tol[e]), not (first and i == 0))
                if s is not None and (best is None or s < best[0]):
                    best = (s, e)
            if best is not None:
                self.hit = (i, *best)
                count = i + 1
                break
        self._used = used
        if keep is not None:
            self.block = (Z[0].copy(), mids[:count], Vs[:count])
        return Z[:count + 1], C[:count].transpose(2, 1, 0), (J[:count] if integrate else None)

    def _coefficients(self, V: np.ndarray, events: np.ndarray | None = None) -> np.ndarray:
        """(events, terms of V): the switching functions' polynomial coefficients ``H V^T`` on
        a step from its Taylor terms V, every event's (a sparse product) or ``events``' (their
        rows' nonzeros gathered: the same sums in the same order)."""
        kernels = _sparse_kernels()
        n = V.shape[0]
        if events is None:
            if kernels is None:
                return np.asarray(self.H @ V.T)
            Vt = np.ascontiguousarray(V.T)
            c = np.zeros((self.n_events, n))
            kernels[1](*self._H[:2], n, *self._H[2:], Vt.ravel(), c.ravel())
            return c
        ptr, idx, data = self._H[2:]
        count = ptr[events + 1] - ptr[events]
        first = np.cumsum(count) - count
        at = np.arange(int(count.sum())) - np.repeat(first - ptr[events], count)
        G = V[:, idx[at]] * data[at]                     # (terms, nonzeros)
        c = np.zeros((events.size, n))
        some = count > 0
        if some.any():
            c[some] = np.add.reduceat(G, first[some], axis=1).T
        return c

    def coeffs(self, Z: np.ndarray) -> np.ndarray:
        """C (terms, events, rows of Z): every switching function's polynomial on the bottom
        step from each row of Z."""
        if not self.n_events:
            return np.zeros((self.terms, 0, Z.shape[0]))
        V = self.taylor(Z)                                       # (terms, count, size)
        return np.stack([(self.H @ V[j].T) for j in range(self.terms)])
