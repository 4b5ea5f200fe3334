"""Torque-speed zones: the smallest margin of a duty cycle's points (|omega|, |T|) below a
motor's torque-speed limit, exact on the cycle's piecewise polynomials; the zone assumed
from a motor's data sheet where none is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.design.dutycycle import CycleDuty
from beltcalc.design.polynomials import poly_add, poly_scale, poly_shift, poly_value, quad_min, roots_inside
from beltcalc.errors import require_range

@dataclass(frozen=True)
class ZoneCheck:
    """The smallest margin of the cycle's points (|omega|, |T|) below a torque-speed limit.

    ``margin`` [N m] = T_lim(|omega|) - (1 + peak_margin) |T| at its smallest, at cycle time
    ``time`` where the speed is ``speed`` and the torque ``torque`` against ``limit``."""

    margin: float
    time: float
    speed: float
    torque: float
    limit: float
    segment: int = -1
    phase: str = ""

    @property
    def ok(self) -> bool:
        return self.margin >= -1e-12 * max(abs(self.limit), 1.0)


def zone_limit(points: tuple[tuple[float, float], ...], speed: float) -> float:
    """The zone's torque at ``speed`` [N m], linear between its (speed, torque) points."""
    for (w0, t0), (w1, t1) in zip(points, points[1:]):
        if speed <= w1:
            return t0 + (t1 - t0) * (speed - w0) / (w1 - w0)
    return points[-1][1]


def zone_check(duty: CycleDuty, points: tuple[tuple[float, float], ...], peak_margin: float = 0.0) -> ZoneCheck:
    r"""Every point of the cycle against a torque-speed zone, exactly.

    .. math:: g(t) = T_{lim}(|\omega(t)|) - (1 + m) |T(t)| \ge 0

    ``points`` are (speed [rad/s], torque [N m]) from speed 0 up to the motor's maximum
    speed, the limit linear between them. Speeds above the last point are not checked
    here (the speed check covers them).

    Notes
    -----
    Between two points of the zone the limit is linear in the speed; the speed is a
    polynomial of degree <= 2 in time on each piece, and so is the torque: g is a
    quadratic on each piece cut where |omega| crosses a point's speed, and its minimum is
    at an end or at the vertex (exact). The servo makers' sizing tools check the same
    (e.g. Yaskawa SigmaSelect: every operating point inside the intermittent zone).
    """
    require_range("peak_margin", peak_margin, "", low=0.0)
    k = 1.0 + peak_margin
    speeds = [w for w, _ in points]
    best = None
    for p in duty.pieces:
        sign_w = 1.0 if poly_value(p.w, 0.5 * p.duration) >= 0 else -1.0
        aw = poly_scale(p.w, sign_w)
        cuts = [0.0]
        for w_k in speeds[1:]:
            cuts += roots_inside(poly_add(aw, (-w_k,)), p.duration)
        cuts = sorted(set(cuts)) + [p.duration]
        for a, b in zip(cuts, cuts[1:]):
            if b - a <= 0:
                continue
            mid_w = poly_value(aw, 0.5 * (a + b))
            if mid_w > speeds[-1] * (1 + 1e-12):
                continue
            idx = max(0, min(len(points) - 2, next((i for i in range(len(points) - 1)
                                                     if mid_w <= speeds[i + 1]), len(points) - 2)))
            (w0, t0), (w1, t1) = points[idx], points[idx + 1]
            slope = (t1 - t0) / (w1 - w0)
            lim = poly_add((t0 - slope * w0,), poly_scale(poly_shift(aw, a), slope))
            tq = poly_shift(p.torque, a)
            sgn = 1.0 if poly_value(tq, 0.5 * (b - a)) >= 0 else -1.0
            g = poly_add(lim, poly_scale(tq, -k * sgn))
            val, where = quad_min(g, b - a)
            if best is None or val < best[0]:
                wv = poly_value(aw, a + where)
                best = (val, p.start + a + where, wv, poly_value(p.torque, a + where), poly_value(lim, where),
                        p.segment, p.phase)
    if best is None:
        return ZoneCheck(math.inf, 0.0, 0.0, 0.0, points[0][1])
    return ZoneCheck(*best)


def assumed_zone(T_max: float, T_end: float, n_rated: float, n_max: float) -> tuple[tuple[float, float], ...]:
    """The intermittent zone assumed when the catalog publishes none: T_max flat from 0 to
    the rated speed, then falling linearly to ``T_end`` at the maximum speed.

    >>> assumed_zone(4.46, 1.27, 314.16, 628.32)
    ((0.0, 4.46), (314.16, 4.46), (628.32, 1.27))
    """
    require_range("zone_end_torque", T_end, "N*m", 0.0, T_max)
    if n_max > n_rated:
        return ((0.0, T_max), (n_rated, T_max), (n_max, T_end))
    return ((0.0, T_max), (n_max, T_max))
