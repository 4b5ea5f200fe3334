r"""Exact extremes and integrals of the square of linear signals over the time pieces of a
network without strands (issue 14, item 7; the linear axis's motor torque and belt force).

Between its time breaks such a network is linear and time-invariant with its inputs in the
generators: ``z' = F z``, ``z = [x, g]``. A signal is a row over z that may change from piece
to piece (a prescribed node's drive torque: :func:`drive_torque_row`), so it may jump at a
break: each piece is read from its right limit at the start to its left limit at the end, and
an extreme says on which side it lies. The grid of each piece is walked with
:func:`beltcalc.sim.propagate.orbit`; its candidate cells are chosen by the rule the switching
core's :class:`beltcalc.sim.watch.blocks.Watch` uses (:func:`beltcalc.sim.watch.polish.seen_rise`)
and polished with :func:`beltcalc.sim.watch.polish.zoom_max` on the exact solution, as that
watch polishes a stiff mode's ladder.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from beltcalc.errors import InputError
from beltcalc.sim.elements import Prescribed, piece
from beltcalc.sim.elements.switched import SpeedLoop
from beltcalc.numerics.expm import expm
from beltcalc.sim.propagate import augment, orbit
from beltcalc.sim.watch.polish import seen_rise, zoom_max

if TYPE_CHECKING:
    from beltcalc.sim.network import Network

POINTS_PER_PERIOD = 16     # grid points per period of the fastest oscillating mode
MIN_POINTS = 32            # grid points per piece at least
MAX_WORK = 1e11            # grid points x states^2 of a run at most (about 20 s)
CHUNK = 4096               # grid states held at a time
GAUSS_NODES = 8            # Gauss-Legendre nodes per grid interval (exact for degree 15)
ZOOM_POINTS = 65           # exact values per grid of a candidate's polish ...
ZOOM_LEVELS = 5            # ... and its grids, each 32 times finer


@dataclass(frozen=True)
class ExactSignal:
    """A signal's extremes over the run and the integral of its square, off the exact
    solution: ``max``/``min`` with their times (``max_side``: ``left`` when the extreme is the
    left limit at the end of a piece, where a right-continuous input has already jumped in the
    samples), ``square_integral`` over [0, ``rms_end``] (None: the run ends before)."""

    max: float
    max_time: float
    max_side: str
    min: float
    min_time: float
    min_side: str
    square_integral: float | None

    @property
    def peak(self) -> float:
        """The largest |signal|."""
        return max(self.max, -self.min)

    @property
    def peak_time(self) -> float:
        return self.max_time if self.max >= -self.min else self.min_time

    @property
    def peak_side(self) -> str:
        return self.max_side if self.max >= -self.min else self.min_side

    def rms(self, duration: float) -> float | None:
        """RMS over [0, ``duration``] (the ``rms_end`` of the computation) [signal unit]."""
        if self.square_integral is None:
            return None
        return math.sqrt(self.square_integral / duration)


def drive_torque_row(net: Network, node: str, t_mid: float) -> np.ndarray:
    r"""The drive torque of ``node`` as a row over z = [x, g] on the time piece holding ``t_mid``.

    .. math:: T = \frac{m_c}{f} \left( [A_c \; B_c] - [A_f \; B_f] \right)_{n + c} z

    for a prescribed node (the torque that turns the free motion into the imposed one: the
    ``T_drive`` output of :class:`beltcalc.sim.elements.Prescribed`), and
    :math:`T = ff(t) + K (\omega_{ref}(t) - f x_{n+c})` for a speed loop (its ``T_drive``).
    (A, B) of the constrained and free network: :meth:`Network.first_order`.
    """
    n, size = net.n, net.size
    c, f = net.coord(node)
    el = next(e for e in net.elements if isinstance(e, (Prescribed, SpeedLoop)) and e.node == node)
    if isinstance(el, Prescribed):
        A, B = net.first_order(None, t_mid)
        Af, Bf = net.first_order(None, t_mid, constrained=False)
        return net.mass[c] / f * np.concatenate([A[n + c] - Af[n + c], B[n + c] - Bf[n + c]])
    row = np.zeros(size + net.generator_matrix().shape[0])
    row[n + c] = -el.gain * f
    a, k = piece(el.feedforward, t_mid)
    ra, rk = piece(el.reference, t_mid)
    row[size] = a + el.gain * ra
    if el.ki:
        row[net.state_index[id(el)]] = el.ki
    if k or rk:
        row[size + 1] = k + el.gain * rk      # the generator t (tables make the network ramp)
    return row


def coupling_row(net: Network, name: str, scale: float = 1.0) -> np.ndarray:
    """Coupling ``name``'s torque as a row over z = [x, g] (times ``scale``): it is linear in x."""
    p = net.generator_matrix().shape[0]
    row = net.coupling_torques(np.eye(net.size))[name] * scale
    return np.concatenate([row, np.zeros(p)])


def _reader(F: np.ndarray, row: np.ndarray, z0: np.ndarray):
    """The signal ``row . e^{F tau} z0`` on the grids of :func:`zoom_max`: each grid the orbit
    of ``expm(F d)`` from the state at its first point, kept from the grid before."""
    held = [z0[None]]

    def read(t0: float, d: float, i) -> np.ndarray:
        Z = orbit(expm(F * d), held[0][0 if i is None else i], ZOOM_POINTS)
        held[0] = Z
        return Z @ row
    return read


def _pieces(net: Network, t_end: float, cuts, rms_end: float | None) -> list[tuple]:
    """(a, b, t_mid, A, B, grid points) of each piece between the network's breaks and ``cuts``;
    refuses a run whose grids are too much work (MAX_WORK)."""
    bounds = sorted({0.0, float(t_end), *net.breaks(t_end),
                     *(float(c) for c in (*cuts, *(() if rms_end is None else (rms_end,))) if 0.0 < c < t_end)})
    pieces = []
    for a, b in zip(bounds, bounds[1:]):
        t_mid = 0.5 * (a + b)
        A, B = net.first_order(None, t_mid)
        freq = np.abs(np.linalg.eigvals(A).imag).max(initial=0.0)
        count = max(MIN_POINTS, math.ceil((b - a) * freq * POINTS_PER_PERIOD / (2 * math.pi)))
        pieces.append((a, b, t_mid, A, B, count))
    total = sum(pc[-1] for pc in pieces)
    states = net.size + net.generator_matrix().shape[0]
    if total * states ** 2 > MAX_WORK:
        fastest = max(np.abs(np.linalg.eigvals(pc[3]).imag).max(initial=0.0) for pc in pieces) / (2 * math.pi)
        raise InputError(f"the exact peaks need {total:,} grid points of {states} states over the run (the "
                         f"fastest oscillating mode is at {fastest:.4g} Hz): too much work; shorten the run")
    return pieces


def exact_signals(net: Network, rows: dict, t_end: float, cuts=(), rms_end: float | None = None
                  ) -> dict[str, ExactSignal]:
    r"""Extremes and integrals of the square of linear signals over [0, ``t_end``], off the
    exact solution of a network without strands (linear between its time breaks).

    ``rows``: {name: row(t_mid) -> the signal as a row r over z = [x, g] on the time piece
    that holds t_mid}. On each piece [a, b] between the network's breaks and ``cuts``
    (with ``rms_end`` one of them):

    .. math:: z(a + \tau) = e^{F \tau} z(a), \quad F = \begin{bmatrix} A & B \\ 0 & G \end{bmatrix},
              \quad s(\tau) = r \, z(a + \tau)

    read on a grid of at least 16 points per period of the fastest oscillating mode of A
    (and 32 per piece; the orbit of ``expm(F h)``, :func:`beltcalc.sim.propagate.orbit`),
    with its second derivative ``r F^2 z`` there; every grid cell whose larger value plus the
    most the signal can rise between them (:func:`seen_rise`: the largest |s''| seen at the
    cell's points and its neighbours', twice, times h^2 / 8) reaches the best value seen is
    polished on the exact solution (:func:`zoom_max`: 65 exact values on the cell, five times,
    each 32 times finer), the highest bound first, until the rest fall below the best. The piece's ends are its right
    limit at a and its left limit at b, so a jump of a right-continuous input (the prescribed
    acceleration) is seen from both sides. The integral of :math:`s^2` is Gauss-Legendre
    with 8 nodes per grid interval (exact for polynomials of degree 15; the signal is
    analytic on the piece and resolved by the grid).

    Notes
    -----
    The grid only finds the neighbourhood of each extremum; the value comes from the exact
    solution where the polish ends (to rounding), so it does not depend on the output samples.
    Over-damped modes faster than the grid add no interior extremum that the grid could
    miss by more than their (decayed) size. Van Loan's block exponential for the integral
    is not used: with the chain model's fast over-damped modes e^{-F^T h} overflows.
    """
    if net.strands:
        raise InputError("exact signal extremes need a network without strands", param="network")
    names = list(rows)
    z = np.concatenate([net.initial_state(), net.generators(0.0)])
    best = {name: {1: (-math.inf, 0.0, ""), -1: (-math.inf, 0.0, "")} for name in names}
    square = {name: 0.0 for name in names}
    xg, wg = np.polynomial.legendre.leggauss(GAUSS_NODES)
    cands = {name: {1: [], -1: []} for name in names}    # (bound, piece, start time, z, h) of each cell
    mats = []
    for a, b, t_mid, A, B, count in _pieces(net, t_end, cuts, rms_end):
        h = (b - a) / count
        F = augment(net, A, B)
        steps = [expm(F * h)]              # the orbit's doublings, kept across the chunks
        R = np.array([rows[name](t_mid) for name in names])
        R2 = R @ F @ F                     # the signals' second derivatives
        mats.append((F, R))
        rms_piece = rms_end is not None and b <= rms_end * (1 + 1e-12)
        nodes = [R @ expm(F * (h * (1 + x) / 2)) for x in xg] if rms_piece else []
        # the grid 0..count in chunks (memory: CHUNK states at a time); each chunk carries the two
        # points before it, so every cell is tested once with the curvature of both neighbours
        carry_z, carry_v, carry_c, start = (np.empty((0, F.shape[0])), np.empty((0, len(names))),
                                            np.empty((0, len(names))), 0)
        while start <= count:
            stop = min(start + CHUNK, count + 1)
            Z = orbit(steps, z if start == 0 else steps[0] @ carry_z[-1], stop - start)
            V, C2 = Z @ R.T, np.abs(Z @ R2.T)
            if rms_piece:
                last = min(stop, count) - start        # intervals j -> j + 1 for j < count
                for x, w, node in zip(xg, wg, nodes):
                    vals = Z[:last] @ node.T
                    for k, name in enumerate(names):
                        square[name] += 0.5 * h * w * float(vals[:, k] @ vals[:, k])
            ZZ, VV, CC = np.vstack([carry_z, Z]), np.vstack([carry_v, V]), np.vstack([carry_c, C2])
            first = start - len(carry_z)               # grid index of ZZ[0]
            own = len(carry_z) - 1 if len(carry_z) else 0    # ZZ's first cell not tested before
            # per cell (ZZ[j], ZZ[j + 1]): the largest |s''| at its points and its neighbours'
            c = np.maximum(CC[:-1], CC[1:])
            c[1:] = np.maximum(c[1:], c[:-1].copy())
            c[:-1] = np.maximum(c[:-1], c[1:].copy())
            rise = seen_rise(c, h)
            for k, name in enumerate(names):
                for side in (1, -1):
                    u = side * VV[:, k]
                    i = own + int(np.argmax(u[own:]))                   # the grid's best value
                    if u[i] > best[name][side][0]:
                        j = first + i
                        best[name][side] = (float(u[i]), a + j * h, "right" if j == 0 else
                                            "left" if j == count else "inside")
                    bound = np.maximum(u[:-1], u[1:]) + rise[:, k]
                    for j in np.nonzero(bound[own:] >= best[name][side][0])[0] + own:
                        cands[name][side].append((float(bound[j]), len(mats) - 1, a + (first + j) * h, ZZ[j].copy(), h))
            carry_z, carry_v, carry_c = ZZ[-2:], VV[-2:], CC[-2:]
            start = stop
        z = carry_z[-1]
    # polish the candidate cells, the highest bound first, until the rest cannot reach the best
    for k, name in enumerate(names):
        for side in (1, -1):
            for bound, ip, t0, z0, h in sorted(cands[name][side], key=lambda c: -c[0]):
                if bound < best[name][side][0]:
                    break
                F, R = mats[ip]
                val, tau = zoom_max(_reader(F, side * R[k], z0), 0.0, h, ZOOM_POINTS, ZOOM_LEVELS)
                # a cell's ends are grid points, already seen with their sides (a piece's limits)
                if 0.0 < tau < h and val > best[name][side][0]:
                    best[name][side] = (val, t0 + tau, "inside")
    out = {}
    for name in names:
        (hi, t_hi, s_hi), (lo, t_lo, s_lo) = best[name][1], best[name][-1]
        out[name] = ExactSignal(hi, t_hi, s_hi, -lo, t_lo, s_lo,
                                square[name] if rms_end is not None and rms_end <= t_end * (1 + 1e-12) else None)
    return out
