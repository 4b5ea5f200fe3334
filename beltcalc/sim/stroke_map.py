r"""The resonance map of a belt axis along its stroke: the drive's oscillatory modes with the
carriage held at evenly spaced positions over its travel, and the lowest first frequency over
the stroke and where it lies.

A carriage belt (:class:`~beltcalc.sim.elements.carriage_belt.CarriageBelt`) changes its
stiffness as the carriage moves: its spans are L1 = L1_0 + x and L2 = L2_0 - x long, so the
carriage sees

.. math:: k(x) = C_{spec} \left(\frac{1}{L_{1,0} + x} + \frac{1}{L_{2,0} - x}\right)

([W21 eq. 5] per span, the two in parallel). Held at x (:func:`held_at`) the drive is linear;
its poles (:func:`beltcalc.sim.frequency.poles`) and mode shapes
(:func:`beltcalc.sim.frequency.mode_shapes`) are the axis's there. With the drive side held
(a prescribed pulley) the carriage alone swings, at f = sqrt(k(x) / m) / 2 pi, lowest where
k is: at L1 = L2 (x* = (L2_0 - L1_0) / 2) where the travel reaches it, else at the travel's
end nearest to it. SI floats only; nothing here prints, parses options or writes files.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the belt's stiffness k = C_spec / L [W21 eq. 5].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import InputError, UnknownNameError, did_you_mean
from beltcalc.sim import frequency as fr
from beltcalc.sim.elements.carriage_belt import CarriageBelt, carriage_belts, held_at

POSITIONS = (2, 2000)      # the positions a map may take: at least its two ends, at most this many
XTOL = 1e-9                # the lowest point's search stops at this width, relative to the travel
MAX_EVALUATIONS = 100      # ... or after this many evaluations of the first frequency
_INVPHI = (math.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class StrokeMap:
    """The modes of a drive along the stroke of its carriage belt ``belt``.

    ``positions`` [m] the carriage's positions from its start (``travel`` (low, high) [m],
    both ends included), ``span1``/``span2`` the belt's spans there [m] (``inf``: no return
    span) and ``stiffness`` its stiffness at the carriage [N/m]; per position (rows) and mode
    (columns, the k-th lowest oscillatory mode at that position: where two modes cross,
    column k passes from one to the other) ``frequency`` the undamped natural frequency
    |s| / 2 pi [Hz] and ``damping_ratio`` [-], NaN where a position has fewer oscillatory
    modes; with shapes ``amplitude`` and ``phase`` [rad] (position, mode, node: each node of
    ``nodes`` against the largest, as :func:`beltcalc.sim.frequency.mode_shapes`), else None.
    ``lowest`` [Hz] the lowest first frequency over the travel and ``lowest_at`` [m] where,
    refined between the grid's points (``evaluations`` of the first frequency);
    ``ends`` the first frequency at the travel's low and high end [Hz]."""

    belt: str
    nodes: tuple[str, ...]
    travel: tuple[float, float]
    positions: np.ndarray
    span1: np.ndarray
    span2: np.ndarray
    stiffness: np.ndarray
    frequency: np.ndarray
    damping_ratio: np.ndarray
    amplitude: np.ndarray | None
    phase: np.ndarray | None
    lowest: float
    lowest_at: float
    evaluations: int
    ends: tuple[float, float]

    @property
    def modes(self) -> int:
        """The most oscillatory modes at any position (the columns)."""
        return int(self.frequency.shape[1])

    @property
    def first(self) -> np.ndarray:
        """The first natural frequency at each position [Hz]."""
        return self.frequency[:, 0]


def find_belt(net, belt: str | None = None) -> CarriageBelt:
    """The carriage belt of network ``net`` named ``belt``, or its only one.

    Raises :class:`~beltcalc.errors.InputError` about ``positions`` where the network has
    none (a map along the stroke needs one), and about ``belt`` where it has several and none
    is named; :class:`~beltcalc.errors.UnknownNameError` for a name it does not have."""
    belts = carriage_belts(net)
    if not belts:
        raise InputError("the drive has no carriage belt (a [[carriage_belt]] whose spans follow a carriage): a map "
                         "along the stroke needs one", param="positions")
    if belt is None:
        if len(belts) > 1:
            raise InputError(f"the drive has {len(belts)} carriage belts ({', '.join(b.name for b in belts)}): name "
                             "the one to map", param="belt")
        return belts[0]
    for b in belts:
        if b.name == belt:
            return b
    raise UnknownNameError(f"{belt!r} is not a carriage belt of the drive; "
                           + did_you_mean(belt, (b.name for b in belts)), param="belt")


def first_frequency(net, belt: str, x: float) -> float:
    """The first natural frequency [Hz] of ``net`` with carriage belt ``belt`` held at ``x``
    [m] (NaN where no mode oscillates there)."""
    for p in fr.poles(held_at(net, {belt: x})):
        if p.kind == "oscillatory":
            return float(p.frequency)
    return math.nan


def golden_section(f, a: float, b: float, tol: float, budget: int = MAX_EVALUATIONS) -> tuple[float, float, int]:
    """A minimum of ``f`` on [a, b] by golden-section search: (x, f(x), evaluations), the
    bracket shrunk by 0.618 an evaluation until it is ``tol`` wide or ``budget`` evaluations
    are spent (NaN counts as +inf). Near a smooth minimum f varies as (x - x*)^2, so rounding
    eps in f leaves x* known to about sqrt(eps) of the bracket's scale, whatever ``tol``;
    f(x) itself is within rounding of the minimum.

    >>> x, fx, n = golden_section(lambda x: (x - 0.3) ** 2, 0.0, 1.0, 1e-6)
    >>> round(x, 4), n
    (0.3, 31)
    """
    def g(x):
        v = f(x)
        return math.inf if math.isnan(v) else v

    c, d = b - _INVPHI * (b - a), a + _INVPHI * (b - a)
    fc, fd = g(c), g(d)
    n = 2
    while b - a > tol and n < budget:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - _INVPHI * (b - a)
            fc = g(c)
        else:
            a, c, fc = c, d, fd
            d = a + _INVPHI * (b - a)
            fd = g(d)
        n += 1
    return (c, fc, n) if fc <= fd else (d, fd, n)


def _modes_at(net, shapes: bool):
    """(frequencies, damping ratios, amplitudes, phases [rad]) of the oscillatory modes of the
    held network ``net``, mode 1 first (no shapes: amplitudes and phases empty)."""
    if shapes:
        ms = fr.mode_shapes(net)
        names = [nd.name for nd in net.nodes]
        return ([m.pole.frequency for m in ms], [m.pole.damping_ratio for m in ms],
                [[m.amplitude[n] for n in names] for m in ms],
                [[math.radians(m.phase[n]) for n in names] for m in ms])
    osc = [p for p in fr.poles(net) if p.kind == "oscillatory"]
    return [p.frequency for p in osc], [p.damping_ratio for p in osc], [], []


def stroke_map(net, positions: int = 50, belt: str | None = None, shapes: bool = True) -> StrokeMap:
    """The :class:`StrokeMap` of network ``net`` along the travel of its carriage belt (the
    only one, or the one named ``belt``; :meth:`CarriageBelt.travel`: 0 to its stroke) at
    ``positions`` evenly spaced carriage positions (2..2000, both ends included), the network
    held at each (:func:`~beltcalc.sim.elements.carriage_belt.held_at`): every oscillatory
    mode's natural frequency, damping ratio and (``shapes``) shape there.

    The lowest first frequency: the grid's lowest point, refined by a golden-section search
    (:func:`golden_section`) between its two neighbours on the continuous function
    x -> f1(x), to :data:`XTOL` of the travel or :data:`MAX_EVALUATIONS` evaluations; the
    lower of the grid's and the search's point is kept, so a minimum at an end of the travel
    is that end exactly.

    >>> from beltcalc.sim.elements import Inertia, Prescribed
    >>> from beltcalc.sim.network import Network
    >>> net = Network([Inertia("pulley", 1e-3), Inertia("carriage", 8.0, True)],
    ...               [Prescribed("pulley", 0.0),
    ...                CarriageBelt("belt", "pulley", "carriage", 0.025, 4e5, 0.0, 0.1, 2.2, stroke=1.5)])
    >>> m = stroke_map(net, 16)
    >>> round(m.lowest, 6), round(m.lowest_at, 5)    # L1 = L2 = 1.15 m: sqrt(2 C / 1.15 / 8) / 2 pi
    (46.932232, 1.05)
    >>> [round(f, 4) for f in m.ends]
    [115.0688, 50.9988]
    """
    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) or \
            not POSITIONS[0] <= positions <= POSITIONS[1]:
        raise InputError(f"{positions!r} positions; give {POSITIONS[0]}..{POSITIONS[1]} (both ends of the travel "
                         "count)", param="positions")
    el = find_belt(net, belt)
    low, high = (float(v) for v in el.travel())
    xs = np.linspace(low, high, int(positions))
    rows = [_modes_at(held_at(net, {el.name: float(x)}), shapes) for x in xs]
    m = max(len(r[0]) for r in rows)
    if m == 0:
        raise InputError(f"no mode of the drive oscillates anywhere along the travel of {el.name} "
                         f"({low * 1e3:g} to {high * 1e3:g} mm): every pole is real or rigid", param="positions")
    nodes = tuple(nd.name for nd in net.nodes)
    freq = np.full((xs.size, m), np.nan)
    zeta = np.full((xs.size, m), np.nan)
    amp = np.full((xs.size, m, len(nodes)), np.nan) if shapes else None
    phase = np.full((xs.size, m, len(nodes)), np.nan) if shapes else None
    for k, (f, z, a, ph) in enumerate(rows):
        freq[k, :len(f)], zeta[k, :len(z)] = f, z
        if shapes and f:
            amp[k, :len(f)], phase[k, :len(f)] = a, ph
    first = freq[:, 0]
    i = int(np.nanargmin(first)) if np.any(np.isfinite(first)) else 0
    best_x, best_f, evaluations = float(xs[i]), float(first[i]), 0
    if high > low:
        a, b = float(xs[max(i - 1, 0)]), float(xs[min(i + 1, xs.size - 1)])
        x, fx, evaluations = golden_section(lambda x: first_frequency(net, el.name, x), a, b, XTOL * (high - low))
        if fx < best_f or math.isnan(best_f):
            best_x, best_f = float(x), float(fx)
    l1, l2 = el.lengths(xs)
    k, _ = el.stiffness_at(xs)
    return StrokeMap(el.name, nodes, (low, high), xs, np.asarray(l1, dtype=float),
                     np.broadcast_to(np.asarray(l2, dtype=float), xs.shape).copy(),
                     np.broadcast_to(np.asarray(k, dtype=float), xs.shape).copy(), freq, zeta, amp, phase,
                     best_f, best_x, evaluations, (float(first[0]), float(first[-1])))
