"""Motion profiles of a positioning move: trapezoid (triangle when the stroke is short) and
the jerk-limited S-curve of 7 phases, given by limits (speed, acceleration, jerk) or by time.

A profile is a list of phases of constant jerk (zero for a trapezoid, so constant
acceleration); every quantity is on the motor shaft, SI: angle [rad], speed [rad/s],
acceleration [rad/s^2], jerk [rad/s^3], time [s]. Speed is a polynomial of degree <= 2 in
each phase, so integrals of the torque and power are exact (no sampling): RMS torque and
energies carry no discretisation error.

References
----------
[BM08] L. Biagiotti, C. Melchiorri, Trajectory Planning for Automatic Machines and Robots,
    Springer (2008): the trajectory with double S velocity profile [BM08 sec. 3.4],
    [BM08 eq. 3.19-3.33], here for a rest-to-rest move (v0 = v1 = 0) with equal
    acceleration and deceleration limits.
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the trapezoid [W21 Fig. 9-12].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import require_positive, require_range


@dataclass(frozen=True)
class Phase:
    """A phase of constant jerk ``jerk`` from speed ``speed0`` and acceleration ``accel``
    for ``duration``: omega(t) = speed0 + accel t + jerk t^2 / 2. ``jerk`` is 0 for the
    phases of a trapezoid (constant acceleration)."""

    name: str
    duration: float
    speed0: float
    accel: float
    jerk: float = 0.0

    @property
    def speed1(self) -> float:
        d = self.duration
        return self.speed0 + self.accel * d + 0.5 * self.jerk * d * d

    @property
    def accel1(self) -> float:
        """Acceleration at the end of the phase (its left limit) [rad/s^2]."""
        return self.accel + self.jerk * self.duration

    @property
    def angle(self) -> float:
        d = self.duration
        return self.speed0 * d + 0.5 * self.accel * d * d + self.jerk * d ** 3 / 6.0


@dataclass(frozen=True)
class Trapezoid:
    """Accelerate at ``accel`` to ``speed``, cruise, decelerate at ``accel``, dwell.

    ``triangular`` is True when the stroke is too short to reach ``speed``; the move then
    peaks at ``peak_speed`` = sqrt(accel * stroke) and has no cruise.
    """

    speed: float
    accel: float
    stroke: float
    dwell: float
    phases: tuple[Phase, ...]
    triangular: bool

    @property
    def peak_speed(self) -> float:
        return self.phases[0].speed1

    @property
    def accel_time(self) -> float:
        return self.phases[0].duration

    @property
    def cycle_time(self) -> float:
        return sum(p.duration for p in self.phases)


def trapezoid(speed: float, accel: float, stroke: float, dwell: float = 0.0) -> Trapezoid:
    r"""Trapezoidal (or triangular) move over ``stroke`` radians.

    .. math::
        t_a = \omega_{max}/\varepsilon, \quad
        \theta_a = \omega_{max}^2 / (2\varepsilon), \quad
        t_c = (\theta - 2\theta_a)/\omega_{max}

    If :math:`\theta < \omega_{max}^2/\varepsilon` the move is triangular:
    :math:`\omega_p = \sqrt{\varepsilon \theta}`, :math:`t_a = \omega_p / \varepsilon`.

    Parameters
    ----------
    speed : float
        Maximum speed omega_max, [rad/s]
    accel : float
        Acceleration = deceleration epsilon, [rad/s^2]
    stroke : float
        Angle of the move theta, [rad]
    dwell : float
        Standstill after the move, [s]

    Notes
    -----
    The motion law of [W21 Fig. 9-12] (accelerate, cruise, decelerate).

    Examples
    --------
    >>> p = trapezoid(100.0, 1000.0, 50.0, dwell=0.2)
    >>> [round(ph.duration, 4) for ph in p.phases], p.triangular
    ([0.1, 0.4, 0.1, 0.2], False)
    >>> q = trapezoid(100.0, 1000.0, 4.0)
    >>> round(q.peak_speed, 3), q.triangular
    (63.246, True)
    """
    require_positive("speed", speed, "rad/s")
    require_positive("accel", accel, "rad/s^2")
    require_positive("stroke", stroke, "rad")
    require_range("dwell", dwell, "s", low=0.0)
    if stroke >= speed ** 2 / accel:
        t_a = speed / accel
        t_c = (stroke - speed ** 2 / accel) / speed
        peak, triangular = speed, False
    else:
        peak = math.sqrt(accel * stroke)
        t_a, t_c, triangular = peak / accel, 0.0, True
    phases = [Phase("accelerate", t_a, 0.0, accel)]
    if t_c > 0:
        phases.append(Phase("cruise", t_c, peak, 0.0))
    phases.append(Phase("decelerate", t_a, peak, -accel))
    if dwell > 0:
        phases.append(Phase("dwell", dwell, 0.0, 0.0))
    return Trapezoid(speed, accel, stroke, dwell, tuple(phases), triangular)


ACCEL_PHASES = ("accel_in", "accelerate", "accel_out")


@dataclass(frozen=True)
class SCurve(Trapezoid):
    """A jerk-limited (double-S) move: up to 7 phases, then the dwell.

    ``jerk`` is the jerk limit [rad/s^3] (``inf``: the trapezoid); ``peak_accel`` the
    acceleration reached [rad/s^2] (below ``accel`` when the jerk limits it);
    ``triangular`` is True when the move never reaches ``speed`` (no cruise).
    """

    jerk: float = math.inf
    peak_accel: float = 0.0

    @property
    def peak_speed(self) -> float:
        return max(max(ph.speed0, ph.speed1) for ph in self.phases)

    @property
    def accel_time(self) -> float:
        """Time from standstill to the peak speed [s]: the leading phases of ACCEL_PHASES, or,
        for a move of other phases (a shaped move, :mod:`beltcalc.formulas.shapers`), the
        time to the end of the first phase that reaches the peak speed."""
        t = 0.0
        if self.phases and self.phases[0].name not in ACCEL_PHASES:
            peak = self.peak_speed
            for ph in self.phases:
                t += ph.duration
                if ph.speed1 >= peak * (1.0 - 1e-12):
                    break
            return t
        for ph in self.phases:
            if ph.name not in ACCEL_PHASES:
                break
            t += ph.duration
        return t


SCURVE_PHASES = ("accel_in", "accelerate", "accel_out", "cruise", "decel_in", "decelerate", "decel_out")


def _double_s(speed: float, accel: float, jerk: float, t_j: float, t_a: float, t_c: float,
              stroke: float, dwell: float, triangular: bool, limits: tuple[float, float, float]) -> SCurve:
    """The phases of a symmetric rest-to-rest double-S move with jerk time ``t_j``,
    acceleration time ``t_a`` (jerk phases included), cruise ``t_c`` at ``speed`` and the
    acceleration ``accel`` reached. Phases of zero duration are left out."""
    half = 0.5 * accel * t_j  # speed gained in one jerk phase: j t_j^2 / 2 = a t_j / 2
    t_const = max(t_a - 2.0 * t_j, 0.0)
    spec = [
        ("accel_in", t_j, 0.0, 0.0, jerk),
        ("accelerate", t_const, half, accel, 0.0),
        ("accel_out", t_j, speed - half, accel, -jerk),
        ("cruise", t_c, speed, 0.0, 0.0),
        ("decel_in", t_j, speed, 0.0, -jerk),
        ("decelerate", t_const, speed - half, -accel, 0.0),
        ("decel_out", t_j, half, -accel, jerk),
    ]
    phases = [Phase(n, d, w0, a0, j) for n, d, w0, a0, j in spec if d > 0]
    if dwell > 0:
        phases.append(Phase("dwell", dwell, 0.0, 0.0))
    v_lim, a_lim, j_lim = limits
    return SCurve(v_lim, a_lim, stroke, dwell, tuple(phases), triangular, jerk=j_lim, peak_accel=accel)


def scurve(speed: float, accel: float, jerk: float, stroke: float, dwell: float = 0.0) -> SCurve:
    r"""Jerk-limited (double-S, 7-phase) rest-to-rest move over ``stroke`` radians.

    With :math:`T_j` the jerk time, :math:`T_a` the acceleration time (jerk phases
    included) and :math:`T_v` the cruise ([BM08 eq. 3.19-3.33] with v0 = v1 = 0):

    .. math::
        T_j = a_{max}/j_{max},\quad T_a = T_j + v_{max}/a_{max}
        \quad (v_{max} j_{max} \ge a_{max}^2; \text{ else } T_j = \sqrt{v_{max}/j_{max}},
        T_a = 2 T_j)

        T_v = \theta / v_{max} - T_a \quad (\ge 0)

    If :math:`T_v < 0` the speed is not reached: with :math:`T_j = a_{max}/j_{max}`,
    :math:`T_a = T_j/2 + \sqrt{T_j^2/4 + \theta/a_{max}}` and
    :math:`v = a_{max}(T_a - T_j)` when :math:`\theta \ge 2 a_{max}^3/j_{max}^2`;
    otherwise the acceleration is not reached either:
    :math:`T_j = (\theta / (2 j_{max}))^{1/3}`, :math:`T_a = 2 T_j`,
    :math:`v = j_{max} T_j^2`.

    Parameters
    ----------
    speed, accel, jerk : float
        Limits v_max [rad/s], a_max [rad/s^2], j_max [rad/s^3]; ``jerk = inf`` gives the
        trapezoid of :func:`trapezoid` exactly (same phases, same floats)
    stroke : float
        Angle theta of the move [rad]
    dwell : float
        Standstill after the move [s]

    Notes
    -----
    [BM08 sec. 3.4] (double S velocity profile), case v0 = v1 = 0, a_max = d_max. The area
    under the speed is the stroke in every case.

    Examples
    --------
    >>> p = scurve(100.0, 1000.0, 20000.0, 50.0)
    >>> [ph.name for ph in p.phases][:4], [round(ph.duration, 4) for ph in p.phases][:4]
    (['accel_in', 'accelerate', 'accel_out', 'cruise'], [0.05, 0.05, 0.05, 0.35])
    >>> round(sum(ph.angle for ph in p.phases), 12), p.triangular
    (50.0, False)
    """
    require_positive("speed", speed, "rad/s")
    require_positive("accel", accel, "rad/s^2")
    if not (jerk > 0) or math.isnan(jerk):
        require_positive("jerk", jerk, "rad/s^3")
    require_positive("stroke", stroke, "rad")
    require_range("dwell", dwell, "s", low=0.0)
    if math.isinf(jerk):
        t = trapezoid(speed, accel, stroke, dwell)
        return SCurve(speed, accel, stroke, dwell, t.phases, t.triangular, jerk=math.inf, peak_accel=accel)
    limits = (speed, accel, jerk)
    if speed * jerk >= accel * accel:
        t_j, a_reached = accel / jerk, accel
        t_a = t_j + speed / accel
    else:
        t_j = math.sqrt(speed / jerk)
        a_reached, t_a = jerk * t_j, 2.0 * t_j
    t_c = stroke / speed - t_a
    if t_c >= 0:
        return _double_s(speed, a_reached, jerk, t_j, t_a, t_c, stroke, dwell, False, limits)
    if stroke >= 2.0 * accel ** 3 / jerk ** 2:   # the acceleration limit is still reached
        t_j = accel / jerk
        t_a = 0.5 * t_j + math.sqrt(0.25 * t_j * t_j + stroke / accel)
        return _double_s(accel * (t_a - t_j), accel, jerk, t_j, t_a, 0.0, stroke, dwell, True, limits)
    t_j = (stroke / (2.0 * jerk)) ** (1.0 / 3.0)
    return _double_s(jerk * t_j * t_j, jerk * t_j, jerk, t_j, 2.0 * t_j, 0.0, stroke, dwell, True, limits)


def move_by_time(stroke: float, move_time: float, accel_fraction: float = 1.0 / 3.0,
                 jerk_fraction: float = 0.0, dwell: float = 0.0) -> SCurve:
    r"""A move over ``stroke`` radians in ``move_time`` seconds (the speed and limits follow).

    ``accel_fraction`` = T_a / T (acceleration time over move time, at most 1/2: 1/3
    gives the "1/3-1/3-1/3" trapezoid); ``jerk_fraction`` = T_j / T_a (0: trapezoid, at
    most 1/2: 1/2 gives a move without constant-acceleration phase).

    .. math::
        T_a = f_a T, \quad T_j = f_j T_a, \quad v = \theta / (T - T_a), \quad
        a = v / (T_a - T_j), \quad j = a / T_j

    Notes
    -----
    The area under a symmetric double-S speed curve is v (T - T_a) ([BM08 eq. 3.25] with
    v0 = v1 = 0 and T = T_a + T_v + T_d, T_d = T_a).

    Examples
    --------
    >>> p = move_by_time(40.0, 0.6)
    >>> round(p.peak_speed, 9), round(p.peak_accel, 6), [round(ph.duration, 4) for ph in p.phases]
    (100.0, 500.0, [0.2, 0.2, 0.2])
    """
    require_positive("stroke", stroke, "rad")
    require_positive("move_time", move_time, "s")
    require_range("accel_fraction", accel_fraction, "", 0.0, 0.5, low_open=True)
    require_range("jerk_fraction", jerk_fraction, "", 0.0, 0.5)
    require_range("dwell", dwell, "s", low=0.0)
    t_a = accel_fraction * move_time
    t_j = jerk_fraction * t_a
    speed = stroke / (move_time - t_a)
    accel = speed / (t_a - t_j)
    jerk = accel / t_j if t_j > 0 else math.inf
    t_c = move_time - 2.0 * t_a
    return _double_s(speed, accel, jerk, t_j, t_a, t_c, stroke, dwell, t_c <= 0, (speed, accel, jerk))


@dataclass(frozen=True)
class MoveSpec:
    """One segment of a cycle as the designer gives it, SI. ``kind`` "move" or "dwell".

    A move: ``distance`` [m] of carriage travel, ``direction`` +1/-1, and either the
    limits ``speed``/``accel``/``jerk`` as ``(value, unit)`` with unit "rad/s" (motor) or
    "m/s" (carriage) etc. (None: the cycle's defaults; ``jerk`` None: a trapezoid), or
    ``time`` [s] with ``accel_fraction`` T_a/T and ``jerk_fraction`` T_j/T_a. A dwell:
    ``time`` [s]. ``payload`` [kg] and ``force`` [N] as :class:`beltcalc.design.dutycycle.Segment`.
    """

    kind: str
    name: str = ""
    distance: float = 0.0
    direction: int = 1
    time: float | None = None
    speed: tuple[float, str] | None = None
    accel: tuple[float, str] | None = None
    jerk: tuple[float, str] | None = None
    accel_fraction: float = 1.0 / 3.0
    jerk_fraction: float = 0.0
    payload: float = 0.0
    force: float = 0.0
