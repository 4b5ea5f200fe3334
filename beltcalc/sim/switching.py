"""Tension-only strands on the exact solution: mode changes located to machine precision,
grazing and take-up done right, the internal step chosen from the dynamics alone.

Between mode changes the network is linear with generator inputs, ``z' = F z`` with
``z = [x, g]`` (:func:`beltcalc.sim.propagate.augmented_matrix`). A *mode* is one strand pattern
(which strands are taut) on one time piece of the inputs. This module propagates the exact
solution mode by mode:

* **Scaling.** ``F`` is balanced once per network by a diagonal similarity of powers of two
  (exact in floating point), ``F~ = S^-1 F S``: positions in rad and speeds in rad/s differ
  by the fastest angular frequency, and without balancing ``||F h||`` is 10^4 times
  larger than the dynamics need.
* **Steps from the dynamics.** The bottom step ``L = min(THETA / ||F~||_1, RHO / rho)``
  (rho: the spectral radius) makes the Taylor series of the exact solution over one step,
  ``z(t + s L) = sum_j s^j V_j`` with ``V_j = (F~ L)^j z / j!``, exact to rounding with
  :func:`terms_for` ``(||F~ L||)`` terms, at most 49 (s in [0, 1]). THETA bounds the
  truncation (the terms needed); RHO bounds how far the terms grow before they shrink
  (about ``exp(rho L)``), which is what the rounding of a value read off the series grows
  with: where the fastest motion is well below ``||F~||`` (a chain whose strand stiffness
  sets the norm) the step is THETA's, twice what ``||F~ L|| = 4`` gave; where a stiff
  coupling's own frequency is near ``||F~||`` it is RHO's, as before. Every switching
  function ``r . z`` is then a polynomial in s on the step; its coefficients come from the
  rows ``R_j = r (F~ L)^j / j!``, precomputed per mode. The output grid plays no part:
  samples are read off the exact solution afterwards, from the step that holds them.
* **Stiff modes** (``||F~||`` far above the fastest oscillation, e.g. a coupling 10^6 times
  stiffer than the rest): the coarse step is ``h = 2^K L`` (at most one radian of the
  fastest oscillation), propagated by ``P_0 = expm(F~ h)``, built bottom-up by squaring from
  the bottom step (so the ladder ``P_k = expm(F~ h / 2^k)`` comes for free). A coarse step is
  examined by the values and rates of the switching functions at its ends (a cubic Hermite
  test for a dip through zero inside it); a flagged step is halved down the ladder to the
  bottom level, where the polynomial is exact. After every restart the first coarse step
  is entered geometrically (L, L, 2L, 4L ... h/2) so a fast transient cannot hide a
  crossing.
* **Location.** The first crossing is the first root of the exact polynomial on the step,
  found by Brent's method on the polynomial (to 1e-15 of the step); the state there is the
  Taylor sum at that s. No ``expm`` per evaluation, no dependence on the output step.
* **Crossings, grazing, take-up.** A crossing counts when the function moves to its firing
  side by more than the rounding level ``tol`` (an excursion whose peak stays within
  ``tol`` is a graze: no switch). At a restart every strand that sits on a surface is
  decided by how its elongation and force leave zero in the taut mode (the first Taylor
  coefficient beyond rounding): taut if both become positive. Unloading (``F -> 0`` with
  ``delta > 0``) has the same accelerations in both modes, so it is a transversal or a
  grazing crossing, never a chatter. Take-up (``delta`` rising through 0) makes the
  damper's force jump to ``b delta'`` (a Kelvin-Voigt contact). See DESIGN.md section 3.0.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from beltcalc.errors import SimulationError
from beltcalc.sim.firing import EPS, first_fire, stays_down
from beltcalc.sim.linalg import balance, expm
from beltcalc.sim.propagate import augmented_matrix, orbit
from beltcalc.sim.sparse_parts import SparseParts

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

THETA = 8.0          # ||F~ L||_1 on the bottom step at most ...
RHO = 4.0            # ... and rho(F~) L at most (rho: the spectral radius): the terms grow at most ~exp(RHO)
TERMS = 34           # terms at ||F~ L||_1 <= 4: 4^34 / 34! = 1e-18 < 2^-53, the Taylor series is exact to rounding
TAIL = 2.0 ** -64    # the sparse orbit's terms: until the bound of the tail left is this of ||z||_1 (5e-20)
ROUND = 1024 * EPS   # rounding level of a switching function, relative to sum |r_i z_i|
STIFF = 64.0         # ||F~|| / fastest oscillation above which coarse steps are used
TAYLOR_BYTES = 2e6  # a dense mode keeps its Taylor matrices (TERMS x size^2) up to this size (size <= 71)
MAX_BLOCK = 2048     # steps propagated ahead at once (doubled from FIRST_BLOCK while nothing happens)
FIRST_BLOCK = 64     # steps of a run's first block; later, half the previous stretch's (Run.advance) ...
FIRST_FLOPS = 2e6    # ... and at most this many state-size^2 products (size 19: 5540 steps, 245: 33)
CACHE_BYTES = 400e6  # modes kept (least recently used first out)
RADIUS_MARGIN = 1.25  # the sparse path's power-step radius, raised by this (it may come from below)
NEAR_GROUP = 8       # rows of a block sharing one second-order reach bound (Mode.near) ...
NEAR_GROUP_SIZE = 100    # ... on modes of at most this many states (the bound's set-up is 8 size^3)
SPARSE_SIZE = 300    # states (with generators) from which modes are sparse (see SparseParts)
SPARSE_BLOCK = 2e6   # polynomial coefficients held per block of sparse steps
KEEP_FLOATS = 8e6    # a watched sparse block's Taylor terms kept for the watch (64 MB) at most
REBASE_TURN = 2 * math.pi   # rad: a block's rotation before the angles are re-based (Run.rebase)
MAX_STEPS = 20_000_000   # internal steps a run may need (a mode far stiffer than the run is long)


def terms_for(theta: float) -> int:
    """Taylor terms of a bottom step with ``||F~ L||_1 = theta``: TERMS up to 4; beyond it the
    fewest T whose remainder bound ``theta^T / T!`` is at most ``4^TERMS / TERMS!`` (1e-18):
    49 at THETA, 62 at 1.5 THETA (the error estimate's second run,
    :data:`beltcalc.sim.core.ESTIMATE_STEP`: fewer steps, the same truncation, more rounding,
    which tends to make the estimate larger, not smaller)."""
    if theta <= 4.0:
        return TERMS
    bound = 4.0 ** TERMS / math.factorial(TERMS)
    T, term = 1, theta
    while term > bound or T < TERMS:
        T += 1
        term *= theta / T
    return T


def _power_radius(F, steps: int = 96) -> float:
    """An estimate of the spectral radius of F (sparse): the mean growth per step of ``F^k v``
    over the second half of ``steps`` power steps from a fixed random v (a complex pair or
    eigenvalues of one modulus make the growth oscillate; the mean over 48 steps settles it).
    Measured within 0.3 % of the exact radius on the 40- and 100-roller tables (1 ms); from
    below where the largest eigenvalues lie close together (hence RADIUS_MARGIN). 0 if F^k
    v vanishes (a nilpotent F)."""
    v = np.random.default_rng(0).standard_normal(F.shape[0])
    logs = []
    for _ in range(steps):
        v = F @ v
        size = float(np.linalg.norm(v))
        if not size > 0 or not math.isfinite(size):
            return 0.0
        logs.append(math.log(size))
        v /= size
    return math.exp(sum(logs[steps // 2:]) / (steps - steps // 2))


def step_length(norm: float, rho: float) -> float:
    """The standard bottom step ``min(THETA / ||F~||_1, RHO / rho)`` (``rho`` the spectral
    radius, 0 where unknown: then ``RHO / ||F~||_1``, which rho never exceeds)."""
    norm = max(norm, 1e-300)
    return min(THETA / norm, RHO / (rho if rho > 0 else norm))


def _taylor(Ft: np.ndarray, Z: np.ndarray, L: float, terms: int = TERMS) -> np.ndarray:
    """V[j] = (F~ L)^j Z / j! for j < terms; Z is one state (size,) or rows (count, size)."""
    V = np.empty((terms, *Z.shape))
    V[0] = Z
    M = Ft.T * L
    matmul, divide = np.matmul, np.divide
    for j in range(1, terms):                # in place: (V[j-1] @ M) / j, without temporaries
        v = V[j]
        matmul(V[j - 1], M, out=v)
        divide(v, j, out=v)
    return V


def _taylor_matrices(Ft: np.ndarray, L: float, terms: int = TERMS) -> np.ndarray:
    """T[j] = (F~ L)^j / j! for j < terms, stacked (terms * size, size): every Taylor term of
    a state in one product, ``V = T z`` (the rows ``R`` of the switching functions are
    ``H T[j]`` the same way). Each entry of ``T[j] z`` rounds within eps of
    ``(|F~ L|^j / j!) |z|``, the bound of the term-by-term recursion."""
    m = Ft.shape[0]
    T = np.empty((terms, m, m))
    T[0] = np.eye(m)
    M = Ft * L
    for j in range(1, terms):
        np.matmul(M, T[j - 1], out=T[j])
        T[j] /= j
    return T.reshape(terms * m, m)


def _horner(V: np.ndarray, s) -> np.ndarray:
    """sum_j s^j V[j]; s a scalar, or one value per row of V[j] (|s| <= 1). The powers of s
    in one array and one product over j: every term is at most the series' own, so the sum
    rounds within (terms) eps of the sum of their magnitudes, as Horner's does."""
    s = np.asarray(s, dtype=float)
    powers = np.arange(V.shape[0], dtype=float)
    if s.ndim:
        return np.einsum("jc,jcm->cm", np.power(s[None, :], powers[:, None]), V)
    return (np.power(float(s), powers) @ V.reshape(V.shape[0], -1)).reshape(V.shape[1:])


class _StepIntegrals:
    """The state's integral from 0 at the step points of one block, ``I[r] = I0 + Q sum_(i<r)
    Z[i]`` (``Q`` the integral of one step's exponential, :meth:`Mode.Q`; None where the rows
    summed are already the steps' integrals, the sparse path's), formed only at the rows
    asked for (``self[r]``): one row is its own sum (a block's first sample, a switch, its
    end: the usual reads), an index array the prefix sums of all rows (formed once), and the
    product with Q is paid for the rows read instead of for every step."""

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


class Mode:
    """One strand pattern on one time piece: the balanced matrix, its steps and switching rows.

    Dense (small networks): ``expm`` ladders, the orbit by doubling, the polynomial rows
    ``R`` precomputed. Sparse (``parts`` given, large networks): ``F~`` assembled from the
    strands' stamps in O(nonzeros), every bottom step taken by its Taylor sum of sparse
    products; nothing of size states^2 is formed, so a new strand pattern costs little."""

    def __init__(self, network, taut: tuple[bool, ...], t_mid: float, S: np.ndarray, omega: float, rho: float,
                 scale: float, parts: "SparseParts | None" = None):
        self.taut = taut
        self.sparse = parts is not None
        self._Ft = self._events = None
        self._P: dict[int, np.ndarray] = {}
        self._doubling: dict[int, list] = {}
        self._Q: dict[int, np.ndarray] = {}
        self._R = None
        self._coeff_rows = 0
        self._T = None
        self._B2 = None
        if self.sparse:
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
            return

        self._events = network.events(taut)
        self.dirs = np.array([e.direction for e in self.events], dtype=float)
        self.event_strand = np.array([e.strand for e in self.events], dtype=np.int64)
        self.n_events = len(self.events)
        F = augmented_matrix(network, taut, t_mid)
        self._Ft = F / S[:, None] * S[None, :]
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

    @property
    def Ft(self):
        """The balanced F~: dense, or a sparse mode's as a scipy CSR matrix, formed when first
        asked for (a chain builds a mode at nearly every switch; its steps use the arrays)."""
        if self._Ft is None:
            indptr, indices, data = self._csr_F
            self._Ft = self._parts.sparse.csr_matrix((data, indices, indptr), shape=(self.size, self.size))
        return self._Ft

    @property
    def events(self) -> list:
        """The switching surfaces, as event objects (a sparse mode's formed when asked for)."""
        if self._events is None:
            self._events = self._parts.events(self.taut)
        return self._events

    def apply(self, X: np.ndarray) -> np.ndarray:
        """F~ X for states X (states, columns): a sparse mode by scipy's kernel on its arrays."""
        kernels = _sparse_kernels() if self.sparse else None
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
        """Memory the mode holds once its ladder, rows and squares are built (a fixed figure:
        the squares at their most, 12 of the step for MAX_BLOCK and 15 each of the sample
        steps for 2^15 samples in one block, the integral's twice the size)."""
        if self.sparse:
            return 8 * self.terms * self._csr_F[2].size
        m, terms = self.Ft.shape[0], self.terms
        taylor = terms * m * m if terms * m * m * 8 <= TAYLOR_BYTES else 0
        return 8 * (m * m * (3 + self.K + 12 + 15 + 4 * 15) + terms * self.H.size + taylor)

    def taylor(self, Z: np.ndarray) -> np.ndarray:
        """V[j] = (F~ L)^j Z / j! for j < terms; Z is one state (size,) or rows (count, size).
        Dense: one product with the stacked Taylor matrices (:func:`_taylor_matrices`, kept
        per mode where they take at most TAYLOR_BYTES), else term by term."""
        terms = self.terms
        if not self.sparse:
            m = self.Ft.shape[0]
            if self._T is None and terms * m * m * 8 <= TAYLOR_BYTES:
                self._T = _taylor_matrices(self.Ft, self.L, terms)
            if self._T is None:
                return _taylor(self.Ft, Z, self.L, terms)
            if Z.ndim == 1:
                return (self._T @ Z).reshape(terms, m)
            return (Z @ self._T.T).reshape(Z.shape[0], terms, m).transpose(1, 0, 2)
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
        ``stop_early`` (sparse): end the block at the first step where a switching function
        crosses (nothing is propagated past a switch only to be thrown away): where one comes
        within its polynomial's reach of zero and may fire (:func:`_may_fire`,
        :func:`stays_down`), the step is examined as :meth:`Run._scan_exact` examines it
        (:func:`first_fire`; ``first``: z is a restart point), and the crossing found kept in
        ``self.hit`` as (step, s, event), else None; the block's last step is left to the scan.
        ``integrate`` (sparse): also J, the integral of z over each step (rows; None otherwise:
        a dense run integrates by :class:`_StepIntegrals`).
        ``keep`` (sparse): a scratch array of at least (count, terms, states) into which each
        step's Taylor terms are written; ``self.block`` then holds (the block's first state,
        each step's midpoint, the terms kept), which the watch reads instead of Taylor sums
        of its own (the terms are those :meth:`taylor` forms, bit for bit: the same sparse
        sums in the same order)."""
        if not self.sparse:
            return orbit(self.doubling(), z, count + 1), None, None
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
            # Run._scan_exact makes: near, its Bernstein hull, its values, then first_fire
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
            fire = _may_fire(pc.T[:, :, None], tol[near, None])[:, 0]
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
        if self.sparse:
            V = self.taylor(Z)                                       # (terms, count, size)
            return np.stack([(self.H @ V[j].T) for j in range(self.terms)])
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
        """[expm(F~ dt), its square, ...] (dense; :func:`beltcalc.sim.propagate.orbit`'s powers, as far as needed),
        for reading many uniformly spaced samples off one piece."""
        if getattr(self, "_step", (None,))[0] != dt:
            self._step = (dt, [expm(self.Ft * dt)])
        return self._step[1]

    def step_integral(self, dt: float) -> list:
        """[G, G^2, ...] (:func:`beltcalc.sim.propagate.orbit`'s powers) of ``G = [[S, 0], [Phi, I]]``, ``S = expm(F~
        dt)``, ``Phi = int_0^dt expm(F~ tau) d tau`` (dense): ``[z; I] -> [S z; I + Phi z]`` steps a state and its integral from 0
        one sample on, for reading many uniformly spaced samples and the integrals the
        window's means come from off one piece. Both blocks from one exponential,
        ``expm([[F~ dt, I dt], [0, 0]]) = [[S, Phi], [0, I]]`` (Van Loan, IEEE Trans. Autom.
        Control 23 (1978) 395-404, Theorem 1: the integral of the exponential)."""
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
        """The integral of the ladder step, ``int_0^(h / 2^k) expm(F~ tau) d tau`` (dense): the
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

    def levels(self, Z: np.ndarray) -> np.ndarray:
        """(events, rows of Z): the rounding level of each switching function at each row,
        ``ROUND |H| |z|`` (a value within it of zero is on the surface)."""
        return ROUND * (self.absH @ np.abs(Z).T) + 1e-300

    def near(self, Z: np.ndarray) -> np.ndarray:
        """(events, rows of Z): whether each switching function may come within its rounding
        level (:meth:`levels`) of zero on the bottom step from each row, without the whole
        step staying within it (a graze) (dense). A rigorous cheap bound of the polynomial's
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

    def kept(self, z0: np.ndarray) -> np.ndarray | None:
        """The Taylor terms (steps, terms, states) the orbit kept of its last block
        (:meth:`orbit`'s ``keep``) if that block started at ``z0``, else None."""
        block = getattr(self, "block", None)
        if block is None or not np.array_equal(block[0], z0):
            return None
        return block[2]

    def at(self, z: np.ndarray, tau: np.ndarray | float, integrate: bool = False, V: np.ndarray | None = None):
        """The exact state a time tau in [0, h] after z (rows of z for an array of tau):
        the ladder for the whole bottom steps of tau, the Taylor sum for the rest. With
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
            return _horner(V, frac)
        W = V * (self.L / np.arange(1, self.terms + 1)).reshape((self.terms,) + (1,) * (V.ndim - 1))
        return _horner(V, frac), I + _horner(W, frac) * (frac[:, None] if np.ndim(frac) else frac)


class _Cache:
    """Modes by (pattern, time piece), least recently used dropped beyond CACHE_BYTES."""

    def __init__(self, network, S, omega, rho, scale, parts=None):
        self.network, self.S, self.omega, self.rho, self.scale, self.parts = network, S, omega, rho, scale, parts
        self.modes: OrderedDict = OrderedDict()
        self.built = 0
        self.bytes = 0

    def get(self, taut, seg, t_mid) -> Mode:
        key = (taut, seg)
        mode = self.modes.get(key)
        if mode is None:
            mode = self.modes[key] = Mode(self.network, taut, t_mid, self.S, self.omega, self.rho, self.scale, self.parts)
            mode.key = (taut, seg, t_mid)
            self.built += 1
            self.bytes += mode.nbytes
            while len(self.modes) > 2 and self.bytes > CACHE_BYTES:
                self.bytes -= self.modes.popitem(last=False)[1].nbytes
        self.modes.move_to_end(key)
        return mode


# --- the polynomial on one bottom step ---------------------------------------------------------
_BERNSTEIN: dict[int, np.ndarray] = {}


def _bernstein(terms: int) -> np.ndarray:
    """The matrix taking a polynomial's coefficients on [0, 1] (``terms`` of them, lowest
    first) to its Bernstein coefficients, ``b_i = sum_(j<=i) C(i, j) / C(n, j) c_j`` (n the
    degree; Farouki & Rajan, Comput. Aided Geom. Des. 5 (1988) 1-26, eq. 11): positive
    weights, so each b_i rounds within a few eps of ``sum |c_j|``."""
    W = _BERNSTEIN.get(terms)
    if W is None:
        n = terms - 1
        W = np.zeros((terms, terms))
        for i in range(terms):
            for j in range(i + 1):
                W[i, j] = math.comb(i, j) / math.comb(n, j)
        W = _BERNSTEIN[terms] = W
    return W


def _may_fire(pc: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """(events, columns): whether each firing-side polynomial ``pc[:, e, q]`` (terms first,
    ``d p`` of :func:`beltcalc.sim.firing.first_fire`) can fire on [0, 1] at all, by the convex
    hull of its Bernstein coefficients (every value of p on [0, 1] lies between their least and
    largest): not if it never rises above 0, nor if it starts on the firing side beyond ``tol``
    and never comes back to 0. Every step this rules out is one ``first_fire`` would have
    refused after sampling and refining it (a strand at rest on its surface, its values
    exactly 0 at the step's start: hundreds of refinements each)."""
    T, E, Q = pc.shape
    B = (_bernstein(T) @ pc.reshape(T, E * Q)).reshape(T, E, Q)
    stays_up = (pc[0] > tol) & (B.min(axis=0) > 0)
    return (B.max(axis=0) > 0) & ~stays_up


class Run:
    """The exact piecewise propagation of one network over the output times ``t``."""

    def __init__(self, network, t: np.ndarray, x0: np.ndarray, max_events: int, scale: float = 1.0,
                 method: str = "exact", integrate: bool = False, watch=None):

        self.network, self.t, self.max_events, self.method = network, t, max_events, method
        t_end = float(t[-1])
        self.t_end = t_end
        self.starts = network.segment_starts(t_end)
        self.ends = self.starts[1:] + [t_end]
        all_taut = tuple(True for _ in network.strands)
        F0 = augmented_matrix(network, all_taut, network.piece_time(0, self.starts, t_end))
        self.S = self._scaling(F0)
        n = network.size
        parts = None
        if F0.shape[0] >= SPARSE_SIZE and network.strands:
            # no stiff ladder on the sparse path; the spectral radius by power steps
            parts, omega = SparseParts(network, self.S), 0.0
            rho = RADIUS_MARGIN * _power_radius(parts.scipy_matrix(all_taut, network.piece_time(0, self.starts, t_end)))
        else:
            # the fastest oscillation (stiff ladders) and the spectral radius (the step) of
            # the all-taut matrix: a slack strand takes a spring and a damper away
            # (the generators' block is autonomous: its eigenvalues are the inputs' own)
            lam = np.linalg.eigvals(F0[:n, :n]) if n else np.zeros(0)
            omega = float(np.max(np.abs(lam.imag))) if lam.size else 0.0
            lam = np.concatenate([lam, np.linalg.eigvals(F0[n:, n:])]) if F0.shape[0] > n else lam
            rho = float(np.max(np.abs(lam))) if lam.size else 0.0
        self.cache = _Cache(network, self.S, omega, rho, scale, parts)
        self.m = n
        self.out = np.empty((n, t.size))
        # free rigid rotations: the angles are re-based as the run goes (see rigid_modes)
        pieces = [augmented_matrix(network, all_taut, network.piece_time(k, self.starts, t_end))
                  for k in range(1, len(self.starts))]
        self.rigid, self.rigid_root = rigid_modes([F0] + pieces, network.n)
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
        self.integrate = integrate or watch is not None
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
            self._strand_ops = (D, Fo, lambda mag, A=abs(D): A @ mag, lambda mag, A=abs(Fo): A @ mag)
        else:
            self._strand_ops = (self.delta, self.force, lambda mag, A=np.abs(self.delta).T: mag @ A,
                                lambda mag, A=np.abs(self.force).T: mag @ A)
        z = np.concatenate([x0, network.generators(0.0)]) / self.S
        self.I_run = np.zeros_like(z)
        if watch is not None:
            watch.bind(self)
        self.start_taut = self.decide(z, all_taut, 0, list(range(len(network.strands))))
        self.z0 = z

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

    # --- outputs ------------------------------------------------------------------------------
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
            on = np.asarray(mode.taut, dtype=float)
            forces = self._strand_ops[1] @ (I - self.I_piece).T
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

    # --- decisions ----------------------------------------------------------------------------
    def decide(self, z: np.ndarray, taut: tuple[bool, ...], seg: int, strands) -> tuple[bool, ...]:
        """The pattern just after a restart at z. A strand in ``strands`` off its surfaces is
        taut if its elongation and force are both positive. A strand on a surface is taut if
        both leave zero upwards in the taut mode (the other strands as decided); repeated
        until the pattern is consistent.

        "On a surface" means within the rounding level of a value read off the exact
        solution: ``ROUND`` times the sum of the magnitudes of its Taylor terms over one
        bottom step (``|rows| sum_j |V_j|``). A located switch sits there: its value is a root of
        the step's polynomial, so what is left of it (e.g. ``delta = -3e-20 m`` at a take-up
        without pretension) is rounding, and its sign says nothing; the rate decides."""
        if not len(self.network.strands):
            return taut
        t_mid = self.network.piece_time(seg, self.starts, self.t_end)
        here = self.cache.get(taut, seg, t_mid)
        V = here.taylor(z)
        terms = {taut: V}                    # z's Taylor terms per pattern tried
        D, Fo, level_d, level_f = self._strand_ops
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
    def _scan_exact(self, mode: Mode, Z: np.ndarray, first: bool, limit: float = 1.0, C: np.ndarray | None = None,
                    cleared: int = 0):
        """The first crossing on the bottom steps Z[i] -> Z[i+1] (rows): (i, s, event) or None.
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
            cand[e, q] = _may_fire((C[:, e, q] * mode.dirs[e])[:, None, :], tol[e, q][None, :])[0]
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

    def _hermite(self, mode: Mode, Z0: np.ndarray, Z1: np.ndarray, w: float) -> np.ndarray:
        """Per step Z0[i] -> Z1[i] (rows, w long): whether a switching function may cross zero
        inside it: a sign change, or the cubic Hermite through values and rates reaching zero."""
        G0, G1 = Z0 @ mode.H.T, Z1 @ mode.H.T
        D0, D1 = (Z0 @ mode.Ft.T) @ mode.H.T * w, (Z1 @ mode.Ft.T) @ mode.H.T * w
        tol = ROUND * (np.abs(Z0) @ mode.absH.T) + 1e-300
        change = ((G0 > tol) != (G1 > tol)) | ((G0 < -tol) != (G1 < -tol))
        dG = G1 - G0
        reach = 4 / 27 * (np.abs(D0 - dG) + np.abs(D1 - dG))
        near = np.minimum(np.abs(G0), np.abs(G1)) <= reach + tol
        return np.any(change | near, axis=-1)

    def _descend(self, mode: Mode, z: np.ndarray, level: int, first: bool, limit: float, checked: bool = False):
        """The first crossing in the step of length h / 2^level from z (only its first
        ``limit`` fraction): (tau, event) or None. ``first`` forces the leftmost path down
        to the bottom step (a restart's boundary layer)."""
        if level == mode.K:
            Z = np.vstack([z, mode.P(mode.K) @ z])
            hit = self._scan_exact(mode, Z, first, limit)
            self.steps += 1
            return None if hit is None else (hit[1] * mode.L, hit[2])
        w = mode.h / 2 ** level
        if not (first or checked) and not self._hermite(mode, z[None], (mode.P(level) @ z)[None], w)[0]:
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
                    hit = self._scan_exact(mode, Z, first, C=C, cleared=cnt - 1 if mode.sparse else 0)
                found = None if hit is None else (hit[0], hit[1] * h, hit[2])
                self.steps += cnt
            else:
                Z = orbit(mode.doubling(), z, cnt + 1)
                found = None
                flags = self._hermite(mode, Z[:-1], Z[1:], h)
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
                Ib = _StepIntegrals(self.I_run, Z[:cnt], mode.Q(0)) if J is None else _StepIntegrals(self.I_run, J)
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
                hit = self._scan_exact(mode, Z, first, rem / h, C=C)
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
        """A scratch array for a watched sparse block's Taylor terms (:meth:`Mode.orbit`),
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
            # counted in bottom steps: a stiff ladder takes fewer, but squares its way up from one
            # (2^K of them), and a ladder some 40 levels tall overflows (a 60 km shaft)
            need = self.steps + (t_stop - t_cur) / mode.L
            if need > MAX_STEPS:
                raise SimulationError(
                    f"method {self.method}: the run needs about {need:.3g} internal steps of {mode.L:.3g} s (its "
                    f"stiffest part), more than {MAX_STEPS:,}; a stiffness or a damping many decades above the "
                    "rest? Check the inputs, shorten the run, or make a very stiff coupling rigid")
            t_new, z, e = self.advance(mode, z, t_cur, t_stop)
            z = self.rebase(z, t_new)
            self.piece_ends.append(t_new)
            if self.integrate:
                done = self._strand_ops[1] @ (self.I_run - self.I_piece)
                self.F_run = self.F_run + np.asarray(mode.taut, dtype=float) * done
            if e is None:
                t_cur, seg = t_stop, seg + 1
                if seg < len(self.starts):           # the inputs change piece: re-decide strands on a surface
                    new = self.decide(z, taut, seg, [])
                    self._log(t_cur, taut, new)
                    taut = new
                continue
            self.located += 1
            if self.located > self.max_events:
                name = net.strands[mode.event_strand[e]].name
                raise SimulationError(
                    f"method {self.method}: {self.max_events} strand events by t = {t_new:.6g} s (strand {name} "
                    "switches that often); add pretension or damping, or raise `max_events`")
            new = self.decide(z, taut, seg, [int(mode.event_strand[e])])
            self._log(t_new, taut, new)
            taut, t_cur = new, t_new
        mode = self.cache.get(taut, len(self.starts) - 1, net.piece_time(len(self.starts) - 1, self.starts, self.t_end))
        self.I_piece = self.I_run
        self.emit(mode, z[None], np.array([self.t_end]), self.t_end, inclusive=True,
                  I_base=self.I_run[None] if self.integrate else None)
        self.end_taut = taut
        if self.watch is not None:
            self.watch.finish()
        return self

    def _log(self, t: float, before, after) -> None:
        for k, (a, b) in enumerate(zip(before, after)):
            if a != b:
                self.switches.append((t, k, b))

    def info(self) -> dict:
        """Switches, each strand's time slack [s], and the work done."""
        slack = slack_times(self.network, self.start_taut, self.switches, self.t_end)
        names = [s.name for s in self.network.strands]
        return {"events": len(self.switches), "located": self.located, "slack_time": slack,
                "switches": [(t, names[k], on) for t, k, on in self.switches], "modes": self.cache.built}


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


def piecewise_exact(network, t: np.ndarray, x0: np.ndarray, max_events: int, scale: float = 1.0, watch=None):
    """Exact propagation between strand switches and time break points: (states, steps, info).
    With a ``watch`` (:class:`beltcalc.sim.watch.Watch`), its extremes are filled and
    ``info["integrals"]`` holds the states' integrals from 0 at every sample."""
    run = Run(network, t, x0, max_events, scale, watch=watch).run()
    info = run.info()
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
