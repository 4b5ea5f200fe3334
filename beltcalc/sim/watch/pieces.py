r"""Exact extremes and integrals of the square of linear signals over the time pieces of a
network without strands (issue 14, item 7; the linear axis's motor torque and belt force).

Between its time breaks such a network is linear and time-invariant with its inputs in the
generators: ``z' = F z``, ``z = [x, g]``. A signal is a row over z that may change from piece
to piece (a prescribed node's drive torque: :func:`drive_torque_row`), so it may jump at a
break: each piece is read from its right limit at the start to its left limit at the end, and
an extreme says on which side it lies. The grid of each piece is walked with
:func:`beltcalc.sim.propagate.orbit`; the candidates are polished with
:func:`beltcalc.sim.watch.polish.zoom_max` on the exact solution, as the switching core's
:class:`beltcalc.sim.watch.blocks.Watch` polishes a stiff mode's ladder.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from beltcalc.errors import InputError
from beltcalc.sim.elements import Prescribed, SpeedLoop, piece
from beltcalc.numerics.expm import expm
from beltcalc.sim.propagate import augment, orbit
from beltcalc.sim.watch.polish import zoom_max

if TYPE_CHECKING:
    from beltcalc.sim.network import Network

POINTS_PER_PERIOD = 16     # grid points per period of the fastest oscillating mode
MIN_POINTS = 32            # grid points per piece at least
MAX_WORK = 1e11            # grid points x states^2 of a run at most (about 20 s)
CHUNK = 4096               # grid states held at a time
GAUSS_NODES = 8            # Gauss-Legendre nodes per grid interval (exact for degree 15)
ZOOM_POINTS = 65           # exact values per grid of a candidate's polish ...
ZOOM_LEVELS = 5            # ... and its grids, each 32 times finer
NEAR = 0.01                # grid maxima polished: within this much of the signal's range of the best


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
    (and 32 per piece; the orbit of ``expm(F h)``, :func:`beltcalc.sim.propagate.orbit`);
    every grid maximum whose parabola through three grid points comes within 1 % of the
    signal's range of the largest is polished on the exact solution (:func:`zoom_max`: 65
    exact values around it, five times, each 32 times finer). The piece's ends are its right
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
    cands = {name: {1: [], -1: []} for name in names}    # (estimate, piece, start time, z, h)
    spread = {name: (math.inf, -math.inf) for name in names}
    mats = []
    for a, b, t_mid, A, B, count in _pieces(net, t_end, cuts, rms_end):
        h = (b - a) / count
        F = augment(net, A, B)
        steps = [expm(F * h)]              # the orbit's doublings, kept across the chunks
        R = np.array([rows[name](t_mid) for name in names])
        mats.append((F, R))
        rms_piece = rms_end is not None and b <= rms_end * (1 + 1e-12)
        nodes = [R @ expm(F * (h * (1 + x) / 2)) for x in xg] if rms_piece else []
        # the grid 0..count in chunks (memory: CHUNK states at a time); each chunk carries the two
        # states before it, so every interior grid point is tested once with both neighbours
        carry_z, carry_v, start = np.empty((0, F.shape[0])), np.empty((0, len(names))), 0
        while start <= count:
            stop = min(start + CHUNK, count + 1)
            Z = orbit(steps, z if start == 0 else steps[0] @ carry_z[-1], stop - start)
            V = Z @ R.T
            if rms_piece:
                last = min(stop, count) - start        # intervals j -> j + 1 for j < count
                for x, w, node in zip(xg, wg, nodes):
                    vals = Z[:last] @ node.T
                    for k, name in enumerate(names):
                        square[name] += 0.5 * h * w * float(vals[:, k] @ vals[:, k])
            ZZ, VV = np.vstack([carry_z, Z]), np.vstack([carry_v, V])
            first = start - len(carry_z)               # grid index of ZZ[0]
            for k, name in enumerate(names):
                v = VV[:, k]
                spread[name] = (min(spread[name][0], float(V[:, k].min())), max(spread[name][1], float(V[:, k].max())))
                for side in (1, -1):
                    u = side * v
                    for j in (0, count):                                # the piece's two limits
                        if start <= j < stop and u[j - first] > best[name][side][0]:
                            best[name][side] = (float(u[j - first]), a + j * h, "right" if j == 0 else "left")
                    mid, lo, hi = u[1:-1], u[:-2], u[2:]
                    for i in np.nonzero((mid >= lo) & (mid >= hi))[0] + 1:
                        j = first + i
                        if u[i] > best[name][side][0]:
                            best[name][side] = (float(u[i]), a + j * h, "inside")
                        curve = 2 * u[i] - u[i - 1] - u[i + 1]        # the parabola through three points
                        est = u[i] + (u[i + 1] - u[i - 1]) ** 2 / (8 * curve) if curve > 0 else u[i]
                        cands[name][side].append((float(est), len(mats) - 1, a + (j - 1) * h, ZZ[i - 1].copy(), h))
            carry_z, carry_v = ZZ[-2:], VV[-2:]
            start = stop
        z = carry_z[-1]
    # polish the grid maxima that may be the largest: within NEAR of the signal's range of the
    # best parabola through three grid points (16 points per period: the parabola is within
    # 0.1 % of a sine's top)
    for k, name in enumerate(names):
        width = spread[name][1] - spread[name][0]
        for side in (1, -1):
            ranked = cands[name][side]
            if not ranked:
                continue
            top = max(max(c[0] for c in ranked), best[name][side][0])
            for est, ip, t0, z0, h in ranked:
                if est < top - NEAR * width:
                    continue
                F, R = mats[ip]
                val, tau = zoom_max(_reader(F, side * R[k], z0), 0.0, 2 * h, ZOOM_POINTS, ZOOM_LEVELS)
                if val > best[name][side][0]:
                    best[name][side] = (val, t0 + tau, "inside")
    out = {}
    for name in names:
        (hi, t_hi, s_hi), (lo, t_lo, s_lo) = best[name][1], best[name][-1]
        out[name] = ExactSignal(hi, t_hi, s_hi, -lo, t_lo, s_lo,
                                square[name] if rms_end is not None and rms_end <= t_end * (1 + 1e-12) else None)
    return out
