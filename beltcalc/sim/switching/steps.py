"""The bottom step of the switching core and the Taylor series of the exact solution on it.

The bottom step ``L = min(THETA / ||F~||_1, RHO / rho)`` (:func:`step_length`; ``rho`` the
spectral radius, from the eigenvalues on the dense path, from power steps on the sparse one:
:func:`power_radius`) makes the Taylor series ``z(t + s L) = sum_j s^j V_j``,
``V_j = (F~ L)^j z / j!``, exact to rounding with :func:`terms_for` terms (s in [0, 1]).
:func:`taylor_terms` and :func:`taylor_matrices` form the terms, :func:`taylor_sum` sums them
at any s. Pure numpy on arrays: the modes (:mod:`beltcalc.sim.switching.mode`) hold the
matrices.
"""

from __future__ import annotations

import math

import numpy as np

THETA = 8.0          # ||F~ L||_1 on the bottom step at most ...
RHO = 4.0            # ... and rho(F~) L at most (rho: the spectral radius): the terms grow at most ~exp(RHO)
TERMS = 34           # terms at ||F~ L||_1 <= 4: 4^34 / 34! = 1e-18 < 2^-53, the Taylor series is exact to rounding


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


def power_radius(F, steps: int = 96) -> float:
    """An estimate of the spectral radius of F (sparse): the mean growth per step of ``F^k v``
    over the second half of ``steps`` power steps from a fixed random v (a complex pair or
    eigenvalues of one modulus make the growth oscillate; the mean over 48 steps settles it).
    Measured within 0.3 % of the exact radius on the 40- and 100-roller tables (1 ms); from
    below where the largest eigenvalues lie close together (hence the run's RADIUS_MARGIN).
    0 if F^k v vanishes (a nilpotent F)."""
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


def taylor_terms(Ft: np.ndarray, Z: np.ndarray, L: float, terms: int = TERMS) -> np.ndarray:
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


def taylor_matrices(Ft: np.ndarray, L: float, terms: int = TERMS) -> np.ndarray:
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


def taylor_sum(V: np.ndarray, s) -> np.ndarray:
    """sum_j s^j V[j]; s a scalar, or one value per row of V[j] (|s| <= 1). The powers of s
    in one array and one product over j: every term is at most the series' own, so the sum
    rounds within (terms) eps of the sum of their magnitudes, as Horner's does."""
    s = np.asarray(s, dtype=float)
    powers = np.arange(V.shape[0], dtype=float)
    if s.ndim:
        return np.einsum("jc,jcm->cm", np.power(s[None, :], powers[:, None]), V)
    return (np.power(float(s), powers) @ V.reshape(V.shape[0], -1)).reshape(V.shape[1:])

