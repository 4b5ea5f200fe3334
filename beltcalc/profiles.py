"""Motion profiles of a positioning move: trapezoid (triangle when the stroke is short).

A profile is a list of phases of constant acceleration; every quantity is on the motor
shaft, SI: angle [rad], speed [rad/s], acceleration [rad/s^2], time [s]. Integrals of
polynomials of the phases are exact (no sampling), so RMS torque and energies carry no
discretisation error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import require_positive, require_range


@dataclass(frozen=True)
class Phase:
    """A phase of constant acceleration ``accel`` from speed ``speed0`` for ``duration``."""

    name: str
    duration: float
    speed0: float
    accel: float

    @property
    def speed1(self) -> float:
        return self.speed0 + self.accel * self.duration

    @property
    def angle(self) -> float:
        return self.speed0 * self.duration + 0.5 * self.accel * self.duration ** 2


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
    The motion law of Wojtkowiak et al. 2021, Fig. 9-12 (accelerate, cruise, decelerate).

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
