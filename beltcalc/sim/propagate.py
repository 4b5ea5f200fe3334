"""Propagation of ``z' = F z`` exactly: the one home of the augmented matrix, the balanced
one-sample step, and the doubling orbits every exact path shares (a single run, a study's
stack of runs, the switching core's modes, the watch).

``z = [x, g]`` holds the network's state and its inputs' generators (``g' = G g``,
:meth:`beltcalc.sim.network.Network.generator_matrix`), so constant, sinusoidal and
piecewise-linear inputs ride in ``F`` [MVL03 sec. 10]. A step ``S = expm(F~ dt)`` on the
balanced ``F~ = D^-1 F D`` (``D`` powers of two: an exact similarity, LAPACK ``dgebal``)
is carried along a run by doubling: the orbit ``[z, S z, S^2 z, ...]`` of ``count`` rows in
``log2(count)`` batched products (:func:`orbit`), the powers ``[I, S, ..., S^(b-1)]`` the
same way (:func:`matrix_orbit`). Both broadcast over leading stack axes, so a study's chunk
of runs takes the same products, run by run, as one run.

Every function here is pure numpy on arrays; nothing imports the rest of ``beltcalc.sim``
but the linear algebra, so the core, the switching engine, the watch and the batch engine
all sit above it (no import cycle).

References
----------
[MVL03] C. Moler and C. Van Loan, "Nineteen dubious ways to compute the exponential of a
matrix, twenty-five years later", SIAM Review 45 (2003) 3-49, sections 3 and 10.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from beltcalc.numerics.balance import balance
from beltcalc.numerics.expm import expm

if TYPE_CHECKING:
    from beltcalc.sim.network import Network


def augment(network: Network, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    m, p = A.shape[0], B.shape[1]
    F = np.zeros((m + p, m + p))
    F[:m, :m] = A
    F[:m, m:] = B
    F[m:, m:] = network.generator_matrix()
    return F


def augmented_matrix(network: Network, taut=None, t_mid: float = 0.0) -> np.ndarray:
    """F of z' = F z with z = [x, g]: the network (strand mode ``taut``, time piece holding
    ``t_mid``) and its input generators."""
    return augment(network, *network.first_order(taut, t_mid))


def one_piece(network: Network) -> tuple[np.ndarray, np.ndarray]:
    """(F, scale): the augmented matrix of the network's one linear piece (every strand taut,
    the first time piece) and its balancing (:func:`beltcalc.numerics.balance.balance`), kept
    on the network: a run, its error estimate and its conditioning read them once."""
    hit = network.__dict__.get("_one_piece")
    if hit is None:
        F = augmented_matrix(network)
        hit = network.__dict__["_one_piece"] = (F, balance(F))
    return hit


def balanced_step(F: np.ndarray, scale: np.ndarray, dt: float, parts: int = 1) -> np.ndarray:
    """``expm(F~ dt / parts)^parts`` with ``F~ = D^-1 F D`` balanced (``D = diag(scale)``): the
    one-sample step of a one-piece run (``parts`` > 1: another partition of it), for one
    matrix (m, m) or a stack (R, m, m) with its scales (R, m)."""
    Ft = F / scale[..., :, None] * scale[..., None, :]
    return np.linalg.matrix_power(expm(Ft * (dt / parts)), parts)


def propagate(F: np.ndarray, z0: np.ndarray, dt: float, samples: int, parts: int = 1,
               rows=None, out: np.ndarray | None = None, scale: np.ndarray | None = None) -> np.ndarray:
    """z at t_k = k dt, k < samples, as columns (only ``rows`` of z, default all). F is
    balanced first (a diagonal similarity of powers of two: exact). With S = expm(F~ dt) (or
    expm(F~ dt / parts)^parts, another partition and scaling of A h for the error estimate)
    and b ~ sqrt(samples): the powers S^r (r < b) and the block starts S^(k b) z0 are built
    by doubling; then z[i, k b + r] = sum_j S^r[i, j] (S^(k b) z0)[j], written straight into
    the one result array, row i by row i (a product per row whose result is already that
    row's samples in time order), with the balancing scale folded into the powers. No
    temporary as large as the result: a cold process touches only the result's own pages.
    ``out``: the (rows, samples) array to fill (e.g. rows of a larger array); ``scale``: F's
    balancing where the caller has it."""
    m = F.shape[0]
    rows = np.arange(m) if rows is None else np.asarray(rows)
    scale = balance(F) if scale is None else scale
    step = balanced_step(F, scale, dt, parts)
    b = block_length(samples)
    powers = matrix_orbit(step, b)
    jump = step @ powers[b - 1]                      # S^b
    full, tail = divmod(samples, b)
    starts = orbit(jump, z0 / scale, full + (tail > 0))    # (blocks, m), balanced coordinates
    # per wanted row i: the (m, b) matrix P_i[j, r] = scale_i S^r[i, j] (exact: powers of two)
    P = np.ascontiguousarray((powers[:, rows, :] * scale[rows][None, :, None]).transpose(1, 2, 0))
    out = np.empty((rows.size, samples)) if out is None else out
    if full:
        # out[i, k b + r] = starts[k] . P_i[:, r]: one batched product into the result
        blocks = out[:, :full * b].reshape(rows.size, full, b)     # a view (the last axis split)
        np.matmul(starts[None, :full], P, out=blocks)
        if not np.shares_memory(blocks, out):
            out[:, :full * b] = blocks.reshape(rows.size, full * b)
    if tail:
        out[:, full * b:] = starts[full] @ P[:, :, :tail]
    return out


def orbit(step: np.ndarray | list, start: np.ndarray, count: int) -> np.ndarray:
    """``[start, S start, S^2 start, ...]`` (``count`` rows) by doubling: ``log2(count)``
    batched products instead of ``count`` sequential ones. ``start`` is one state ``(m,)``
    (result ``(count, m)``) or a stack ``(..., m)`` with ``step`` ``(..., m, m)`` (result
    ``(..., count, m)``: every stack entry its own orbit, the same products entry by entry).
    ``step`` may be the list ``[S, S^2, S^4, ...]`` a caller keeps across calls (extended here
    as far as needed), so a run's many blocks square the step once, not once per block (a
    size-62 square is as many flops as 60 rows of the orbit).

    >>> orbit(np.array([[2.0]]), np.array([1.0]), 5)[:, 0].tolist()
    [1.0, 2.0, 4.0, 8.0, 16.0]
    """
    start = np.asarray(start)
    out = np.empty((*start.shape[:-1], count, start.shape[-1]))
    out[..., 0, :] = start
    powers = step if isinstance(step, list) else [step]
    filled, k = 1, 0
    while filled < count:
        if k == len(powers):
            powers.append(powers[-1] @ powers[-1])
        n = min(filled, count - filled)
        np.matmul(out[..., :n, :], np.swapaxes(powers[k], -1, -2), out=out[..., filled:filled + n, :])
        filled += n
        k += 1
    return out


def matrix_orbit(step: np.ndarray, count: int) -> np.ndarray:
    """``[I, S, S^2, ..., S^(count-1)]`` by doubling, ``(count, m, m)`` from ``S`` ``(m, m)``,
    or ``(..., count, m, m)`` from a stack ``(..., m, m)`` (every entry its own powers).

    >>> matrix_orbit(np.array([[3.0]]), 4)[:, 0, 0].tolist()
    [1.0, 3.0, 9.0, 27.0]
    """
    m = step.shape[-1]
    out = np.empty((*step.shape[:-2], count, m, m))
    out[..., 0, :, :] = np.eye(m)
    filled, power = 1, step
    while filled < count:
        n = min(filled, count - filled)
        out[..., filled:filled + n, :, :] = power[..., None, :, :] @ out[..., :n, :, :]
        filled += n
        power = power @ power
    return out


def block_length(samples: int) -> int:
    """The block length ``b ~ sqrt(samples)`` of :func:`propagate`.

    >>> block_length(10001), block_length(1)
    (101, 1)
    """
    return max(1, min(samples, int(math.ceil(math.sqrt(samples)))))


def reference_rows(F: np.ndarray, z0: np.ndarray, dt: float, samples: int, rows,
                   scale: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The error estimate's second computation of a run that is one linear piece: ``rows`` of
    ``z`` at every s-th sample (``s = b + 1``, coprime to :func:`propagate`'s block length
    ``b``, so the samples fall at every offset within a block) and at the last, by another
    partition of the step and another chain of products: ``S' = expm(F~ dt / 3)^3``, the stride
    step ``S'^s`` by binary powering, its orbit by doubling, the last sample's remainder by
    binary powering. Returns ``(idx, ref)``: the sample indices and ``ref[..., i, j]``, row
    ``rows[i]`` at sample ``idx[j]``.

    Why a subset of the samples suffices: the run's own error is the rounding of ``S`` and of
    its powers carried along the orbit, a smooth function of the sample index (per block
    start and per offset within a block), which samples at every offset and every block
    follow; each sample's last dot product adds a rounding that the conditioning term of
    :func:`beltcalc.sim.core.estimate_error` bounds. ~sqrt(samples) samples instead of all: the estimate costs
    one ``expm`` and a few products instead of a second whole propagation.

    ``F`` (m, m) and ``z0`` (m,), or stacks (R, m, m) and (R, m) (one call for a study's
    chunk, :mod:`beltcalc.sim.batch`; ``ref`` then (R, len(rows), len(idx))). ``scale``: the
    balancing of ``F`` where the caller has it."""
    single = F.ndim == 2
    F3, z3 = (F[None], z0[None]) if single else (F, z0)
    scale = (balance(F3) if scale is None else scale).reshape(F3.shape[:2])
    step = balanced_step(F3, scale, dt, 3)
    stride = min(block_length(samples) + 1, samples - 1)
    idx = np.arange(0, samples, stride)
    z = orbit(np.linalg.matrix_power(step, stride), z3 / scale, idx.size)
    if idx[-1] != samples - 1:
        last = np.linalg.matrix_power(step, samples - 1 - int(idx[-1])) @ z[:, -1, :, None]
        z = np.concatenate([z, last.transpose(0, 2, 1)], axis=1)
        idx = np.append(idx, samples - 1)
    rows = np.asarray(rows)
    ref = (z[:, :, rows] * scale[:, None, rows]).transpose(0, 2, 1)
    return idx, (ref[0] if single else ref)
