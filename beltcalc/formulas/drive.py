"""Rigid model of a timing-belt linear axis seen from the motor shaft: reflected inertia,
losses, and the motor torque, power and energy of a motion profile.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: [W21 eq. 17-29]. [W21 eq. 18-28] print
    ``(m_TB + m) D`` and ``F_R D``; both are dimensionally wrong (kg m added to kg m^2,
    and a torque twice too large). The right forms, used here, are those of [C04].
[C04] R. Crowder, Electric Drives and Electromechanical Systems, Newnes (2006), p. 86,
    [C04 eq. 3.21-3.27]: I_L = M D^2 / 4, T_ext = D F / 2,
    I_tot = I_p1 + I_L + (I_RL + I_p2) / n^2.

A gearbox of ratio i (motor speed / drive-pulley speed) between motor and drive pulley is
an extension of ours; with i = 1 every formula reduces to [W21] and [C04]. SI floats only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import require_positive, require_range
from beltcalc.formulas.profiles import Trapezoid

G0 = 9.80665  # standard gravity [m/s^2]


def cylinder_inertia(outer_diameter: float, inner_diameter: float, width: float, density: float) -> float:
    r"""Moment of inertia of a hollow cylinder about its axis [kg m^2].

    .. math:: J = \frac{\pi \rho w}{32} (d_o^4 - d_i^4)

    Examples
    --------
    Aluminium AT10 40-tooth pulley body, d0 = 127.32 mm, bore 20 mm, 30 mm wide:

    >>> round(cylinder_inertia(0.12732, 0.020, 0.030, 2700.0) * 1e3, 3)
    2.088
    """
    require_positive("outer_diameter", outer_diameter, "m")
    require_positive("width", width, "m")
    require_positive("density", density, "kg/m^3")
    require_range("inner_diameter", inner_diameter, "m", 0.0, outer_diameter, high_open=True)
    return math.pi * density * width * (outer_diameter ** 4 - inner_diameter ** 4) / 32.0


def motor_damping(efficiency: float, rated_torque: float, rated_speed: float) -> float:
    r"""Equivalent viscous loss of a motor from its efficiency [N m s/rad].

    .. math:: b_M = (1 - \eta) \, T_n / \omega_n

    Notes
    -----
    DESIGN.md 2.5: the loss torque (1 - eta) T_n at rated speed, spread as viscous
    damping. [W21 sec. 3.2] takes b_M3 from "catalog data on drive efficiency".

    Examples
    --------
    >>> round(motor_damping(0.9, 1.27, 314.159), 6)
    0.000404
    """
    require_range("motor_efficiency", efficiency, "", 0.0, 1.0, low_open=True)
    require_positive("rated_torque", rated_torque, "N*m")
    require_positive("rated_speed", rated_speed, "rad/s")
    return (1.0 - efficiency) * rated_torque / rated_speed


@dataclass(frozen=True)
class BeltAxis:
    """A belt-driven linear axis without its motor, SI units.

    mass [kg] carriage m; substitute_mass [kg] belt m_TB; pulley_diameter [m] D of the
    drive pulley; pulley_inertia, idler_inertia [kg m^2] J_P1, J_P2; coupling_inertia
    [kg m^2] J_C on the drive-pulley shaft; gearbox_inertia [kg m^2] J_G at the motor
    shaft; load_inertia [kg m^2] J_RL on the idler shaft; belt_ratio n = D2 / D1;
    gear_ratio i = motor speed / drive-pulley speed; bearing_damping [N m s/rad] b_B of
    each pulley shaft; guide_damping [N s/m] b_LG; resistance [N] F_R against the motion;
    guide_friction [-] mu of the carriage guide (horizontal axis: normal force m g).
    """

    mass: float
    substitute_mass: float
    pulley_diameter: float
    pulley_inertia: float
    idler_inertia: float
    coupling_inertia: float = 0.0
    gearbox_inertia: float = 0.0
    load_inertia: float = 0.0
    belt_ratio: float = 1.0
    gear_ratio: float = 1.0
    bearing_damping: float = 0.0
    guide_damping: float = 0.0
    resistance: float = 0.0
    guide_friction: float = 0.0

    def __post_init__(self):
        for name, unit in (("mass", "kg"), ("pulley_diameter", "m"), ("belt_ratio", ""), ("gear_ratio", "")):
            require_positive(name, getattr(self, name), unit)
        for name, unit in (("substitute_mass", "kg"), ("pulley_inertia", "kg*m^2"), ("idler_inertia", "kg*m^2"),
                           ("coupling_inertia", "kg*m^2"), ("gearbox_inertia", "kg*m^2"),
                           ("load_inertia", "kg*m^2"), ("bearing_damping", "N*m*s/rad"),
                           ("guide_damping", "N*s/m"), ("resistance", "N")):
            require_range(name, getattr(self, name), unit, low=0.0)
        require_range("guide_friction", self.guide_friction, "", 0.0, 1.0, high_open=True)

    def inertia_parts(self) -> dict[str, float]:
        r"""Contributions to the inertia at the motor shaft, without the motor [kg m^2].

        .. math::
            J_{red} - J_M = J_G + \frac{1}{i^2}\left(J_C + J_{P1} + \frac{J_{P2} + J_{RL}}{n^2}
                            + (m + m_{TB}) \frac{D^2}{4}\right)

        [W21 eq. 18] corrected by [C04 eq. 3.21, 3.22, 3.27]. Keys: gearbox, coupling,
        pulleys, carriage, belt, rotating load.

        >>> ax = BeltAxis(mass=50.0, substitute_mass=0.0, pulley_diameter=0.1,
        ...               pulley_inertia=1e-3, idler_inertia=1e-3)
        >>> round(ax.inertia_parts()["carriage"], 6), round(ax.load_inertia_total, 6)
        (0.125, 0.127)
        """
        i2 = self.gear_ratio ** 2
        r2 = self.pulley_diameter ** 2 / 4.0
        n2 = self.belt_ratio ** 2
        return {
            "gearbox": self.gearbox_inertia,
            "coupling": self.coupling_inertia / i2,
            "pulleys": (self.pulley_inertia + self.idler_inertia / n2) / i2,
            "carriage": self.mass * r2 / i2,
            "belt": self.substitute_mass * r2 / i2,
            "rotating load": self.load_inertia / n2 / i2,
        }

    @property
    def load_inertia_total(self) -> float:
        """Everything but the motor rotor, at the motor shaft [kg m^2]."""
        return sum(self.inertia_parts().values())

    def damping(self, motor_damping: float = 0.0) -> float:
        r"""Viscous damping at the motor shaft [N m s/rad].

        .. math:: b_{red} = b_M + \frac{1}{i^2}\left(b_B (1 + 1/n^2) + b_{LG} \frac{D^2}{4}\right)

        [W21 eq. 23] (2 b_B for n = 1) with D^2/4 for its misprinted D/4.
        """
        r2 = self.pulley_diameter ** 2 / 4.0
        return motor_damping + (self.bearing_damping * (1 + 1 / self.belt_ratio ** 2)
                                + self.guide_damping * r2) / self.gear_ratio ** 2

    @property
    def resistance_torque(self) -> float:
        r"""Torque of the resistance and guide friction at the motor shaft while moving [N m].

        .. math:: T_R = (F_R + \mu m g) \frac{D}{2 i}

        [W21 eq. 27] with [C04 eq. 3.23-3.24]: F D / 2, not the printed F D.
        """
        return (self.resistance + self.guide_friction * self.mass * G0) * self.pulley_diameter / (2 * self.gear_ratio)

    def motor_angle(self, travel: float) -> float:
        """Motor angle [rad] for a carriage travel [m]."""
        return travel * 2.0 * self.gear_ratio / self.pulley_diameter

    def carriage_per_motor(self) -> float:
        """Carriage travel per motor radian [m/rad]: v = omega * this."""
        return self.pulley_diameter / (2.0 * self.gear_ratio)


@dataclass(frozen=True)
class PhaseTorque:
    """Torque at the start and end of a phase [N m] (linear in between)."""

    name: str
    duration: float
    torque0: float
    torque1: float
    speed0: float
    speed1: float


@dataclass(frozen=True)
class Duty:
    """Torque, power and energy of one motion cycle at the motor shaft, SI units."""

    inertia: float              # J_red [kg m^2]
    damping: float              # b_red [N m s/rad]
    resistance_torque: float    # T_R [N m]
    phases: tuple[PhaseTorque, ...]
    peak_torque: float          # max |T| [N m]
    rms_torque: float           # [N m] over the cycle
    peak_power: float           # max T omega [W]
    braking_torque: float       # most negative T (0 if none) [N m]
    braking_energy: float       # energy fed back while T omega < 0 (>= 0) [J]
    accel_time: float           # t_a [s]
    accel_energy: float         # [W21 eq. 29]: T_max omega_max t_a [J]
    accel_energy_exact: float   # integral of T omega over the acceleration phase [J]
    cycle_time: float           # [s]

    def torque_at(self, t: float) -> float:
        """Torque at time ``t`` of the cycle [N m]."""
        start = 0.0
        for p in self.phases:
            if t <= start + p.duration or p is self.phases[-1]:
                x = min(max((t - start) / p.duration, 0.0), 1.0) if p.duration else 0.0
                return p.torque0 + x * (p.torque1 - p.torque0)
            start += p.duration
        return 0.0


def _integral_quadratic(f0: float, fm: float, f1: float, duration: float) -> float:
    """Simpson's rule: exact for a quadratic through (0, f0), (tau/2, fm), (tau, f1)."""
    return duration * (f0 + 4.0 * fm + f1) / 6.0


def duty(profile: Trapezoid, inertia: float, damping: float, resistance_torque: float) -> Duty:
    r"""Motor torque over a profile and its peak, RMS, power and energies.

    .. math::
        T(t) = J_{red}\,\dot\omega + b_{red}\,\omega + T_R \,\mathrm{sgn}\,\omega,
        \qquad T_{rms} = \sqrt{\frac{1}{t_{cyc}}\int T^2 dt},
        \qquad E_{29} = T_{max}\,\omega_{max}\,t_a

    Parameters
    ----------
    profile : Trapezoid
        Motion at the motor shaft
    inertia : float
        J_red, [kg m^2]
    damping : float
        b_red, [N m s/rad]
    resistance_torque : float
        T_R, [N m], acting against the motion while the axis moves

    Notes
    -----
    [W21 eq. 26, 28] with the errata fixed, [W21 eq. 29] for the energy. Within a phase
    T is linear and T omega quadratic in time, so the integrals are exact (Simpson's
    rule, and the closed form tau (T0^2 + T0 T1 + T1^2) / 3 for T^2). With these
    models E_29(eps) = J omega^2 + (b omega + T_R) omega^2 / eps exactly, while the exact
    energy is J omega^2 / 2 + b omega^2 t_a / 3 + T_R omega t_a / 2.

    Examples
    --------
    >>> from beltcalc.formulas.profiles import trapezoid
    >>> d = duty(trapezoid(100.0, 1000.0, 50.0, 0.2), 0.01, 0.001, 0.5)
    >>> round(d.peak_torque, 3), round(d.accel_energy, 3), round(d.accel_energy_exact, 4)
    (10.6, 106.0, 52.8333)
    """
    require_positive("inertia", inertia, "kg*m^2")
    require_range("damping", damping, "N*m*s/rad", low=0.0)
    phases, sq, peak_power, braking_e = [], 0.0, 0.0, 0.0
    for ph in profile.phases:
        moving = 1.0 if (ph.speed0 > 0 or ph.speed1 > 0) else 0.0
        t0 = inertia * ph.accel + damping * ph.speed0 + resistance_torque * moving
        t1 = inertia * ph.accel + damping * ph.speed1 + resistance_torque * moving
        tau = ph.duration
        phases.append(PhaseTorque(ph.name, tau, t0, t1, ph.speed0, ph.speed1))
        sq += tau * (t0 * t0 + t0 * t1 + t1 * t1) / 3.0
        # power T omega: quadratic in t; its maximum at an end or at the vertex
        candidates = [t0 * ph.speed0, t1 * ph.speed1]
        a2 = (t1 - t0) * (ph.speed1 - ph.speed0)  # coefficient of x^2, x = t / tau
        if a2 < 0:
            x = -((t1 - t0) * ph.speed0 + t0 * (ph.speed1 - ph.speed0)) / (2 * a2)
            if 0 < x < 1:
                candidates.append((t0 + x * (t1 - t0)) * (ph.speed0 + x * (ph.speed1 - ph.speed0)))
        peak_power = max(peak_power, *candidates)
        # energy fed back: integral of T omega where T < 0 (omega >= 0 in a forward move)
        if moving and min(t0, t1) < 0:
            x0, x1 = (0.0, 1.0) if max(t0, t1) <= 0 else ((t0 / (t0 - t1), 1.0) if t0 > 0 else (0.0, t0 / (t0 - t1)))
            ta, tb = t0 + x0 * (t1 - t0), t0 + x1 * (t1 - t0)
            wa, wb = ph.speed0 + x0 * (ph.speed1 - ph.speed0), ph.speed0 + x1 * (ph.speed1 - ph.speed0)
            braking_e -= _integral_quadratic(ta * wa, (ta + tb) * (wa + wb) / 4, tb * wb, tau * (x1 - x0))
    acc = phases[0]
    exact = _integral_quadratic(acc.torque0 * acc.speed0, (acc.torque0 + acc.torque1) * (acc.speed0 + acc.speed1) / 4,
                                acc.torque1 * acc.speed1, acc.duration)
    t_max = max(max(abs(p.torque0), abs(p.torque1)) for p in phases)
    braking = min(0.0, *(min(p.torque0, p.torque1) for p in phases))
    return Duty(
        inertia=inertia, damping=damping, resistance_torque=resistance_torque, phases=tuple(phases),
        peak_torque=t_max, rms_torque=math.sqrt(sq / profile.cycle_time), peak_power=peak_power,
        braking_torque=braking, braking_energy=braking_e, accel_time=profile.accel_time,
        accel_energy=t_max * profile.peak_speed * profile.accel_time, accel_energy_exact=exact,
        cycle_time=profile.cycle_time,
    )
