"""Torque on the bolt of a screw (bolt) belt tensioner.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: [W21 eq. 13].
[VDI 2230] VDI 2230 Part 1 (2015), Systematic calculation of highly stressed bolted joints:
    tightening torque M_A = F (0.16 P + 0.58 d2 mu_G + mu_K D_Km / 2).
[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011): thread friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import InputError, require_positive, require_range


def lead_angle(pitch: float, pitch_diameter: float) -> float:
    r"""Lead angle of a single-start thread [rad].

    .. math:: \gamma = \arctan\frac{P}{\pi d_2}

    Notes
    -----
    [W21 eq. 13].

    Examples
    --------
    M10x1 (d2 = 9.35 mm): 1.95 deg.

    >>> round(math.degrees(lead_angle(0.001, 0.00935)), 2)
    1.95
    """
    require_positive("thread_pitch", pitch, "m")
    require_positive("pitch_diameter", pitch_diameter, "m")
    return math.atan(pitch / (math.pi * pitch_diameter))


def friction_angle(mu: float, flank_angle: float = math.radians(60.0)) -> float:
    r"""Apparent friction angle of a thread with flank angle alpha [rad].

    .. math:: \rho' = \arctan\frac{\mu}{\cos(\alpha / 2)}

    Parameters
    ----------
    mu : float
        Thread friction coefficient, in (0, 1) [-]
    flank_angle : float
        Thread flank angle alpha (60 deg for ISO metric threads), [rad]

    Notes
    -----
    [W21 eq. 13]. Typical mu 0.08-0.2 for steel threads [Shigley], 0.15 typical.

    Examples
    --------
    >>> round(math.degrees(friction_angle(0.2)), 2)
    13.0
    """
    require_range("mu", mu, "", 0.0, 1.0, low_open=True, high_open=True)
    return math.atan(mu / math.cos(flank_angle / 2.0))


@dataclass(frozen=True)
class BoltTorque:
    """Torque on the tensioner bolt, SI: angles [rad], torques [N m]."""

    lead_angle: float
    friction_angle: float
    thread_torque: float
    bearing_torque: float

    @property
    def torque(self) -> float:
        """Total torque on the bolt [N m]."""
        return self.thread_torque + self.bearing_torque


def bolt_torque(force: float, pitch: float, pitch_diameter: float, mu: float,
                flank_angle: float = math.radians(60.0), bearing_friction: float = 0.0,
                bearing_diameter: float = 0.0) -> BoltTorque:
    r"""Torque to turn a tensioner bolt against an axial ``force`` [N m].

    .. math::
        T = \tfrac12 F d_2 \tan(\gamma + \rho') + F \mu_K D_{Km} / 2

    Parameters
    ----------
    force : float
        Axial force on the bolt (the belt tension), [N]
    pitch, pitch_diameter : float
        Thread pitch P and pitch diameter d2, [m]
    mu : float
        Thread friction coefficient, in (0, 1) [-]
    flank_angle : float
        Thread flank angle, [rad]
    bearing_friction : float
        Friction coefficient mu_K under the bolt head or nut face, [0, 1); 0 omits the term
    bearing_diameter : float
        Effective friction diameter of the bearing face D_Km, [m]

    Notes
    -----
    Thread term: [W21 eq. 13]. Bearing-face term: [VDI 2230]; the paper leaves it
    out, which is right only for a bolt that bears on a thrust bearing.
    Valid while gamma + rho' < 90 deg (otherwise the thread cannot be turned).

    Examples
    --------
    The paper's example: F_t = 505.1 N, M10x1, mu = 0.2: 0.63 N m.

    >>> round(bolt_torque(505.1, 0.001, 0.00935, 0.2).torque, 3)
    0.631
    """
    if not (math.isfinite(force) and force >= 0):
        raise InputError(f"{force:g} N is not allowed; it must be >= 0 N", param="force")
    gamma = lead_angle(pitch, pitch_diameter)
    rho = friction_angle(mu, flank_angle)
    if gamma + rho >= math.pi / 2:
        raise InputError(
            f"{mu:g} gives lead angle {math.degrees(gamma):.2f} deg + friction angle "
            f"{math.degrees(rho):.2f} deg >= 90 deg: the thread cannot be turned; "
            "lower the friction or use a finer thread",
            param="mu",
        )
    thread = 0.5 * force * pitch_diameter * math.tan(gamma + rho)
    bearing = 0.0
    if bearing_friction:
        require_range("bearing_friction", bearing_friction, "", 0.0, 1.0, high_open=True)
        require_positive("bearing_diameter", bearing_diameter, "m")
        bearing = force * bearing_friction * bearing_diameter / 2.0
    return BoltTorque(gamma, rho, thread, bearing)
