"""Motor choice for a belt axis: every catalog motor checked on peak torque, RMS torque,
speed and load/motor inertia ratio, with its own rotor inertia and losses.

Criteria (DESIGN.md 2.5): peak torque <= T_max / (1 + margin), RMS torque <= T_n,
peak speed <= n_max, load/motor inertia ratio <= limit (10: Parker's guidance for
servos). Among the motors that pass, the smallest (lowest rated torque) that runs at
50-100 % of its rated torque is preferred, because motors are efficient there
([W21 sec. 1, 4], after McCoy & Douglass 1996); if none runs in that band the smallest
that passes is chosen and the report says so.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

from beltcalc.data.catalogs import Motor
from beltcalc.design.checks import RULES, Check, percent
from beltcalc.formulas.drive import BeltAxis, Duty, duty, motor_damping
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.formulas.profiles import Trapezoid

if TYPE_CHECKING:
    from beltcalc.design.dutycycle import CycleDuty, AxisDrive, Segment
    from beltcalc.design.zones import ZoneCheck

BAND = (0.5, 1.0)  # preferred RMS utilisation of the rated torque


@dataclass(frozen=True)
class MotorCheck:
    """One motor against the duty it would see (its own rotor inertia and losses)."""

    motor: Motor
    duty: Duty
    inertia_ratio: float
    peak_ok: bool
    rms_ok: bool
    speed_ok: bool
    inertia_ok: bool
    zone: "ZoneCheck | None" = None      # the intermittent torque-speed zone (cycle checks)
    zone_points: tuple[tuple[float, float], ...] = ()
    zone_assumed: bool = False           # True: the catalog has no curve; the assumed one is used
    continuous_limit: float | None = None  # the RMS limit used (T_n, or the continuous zone at the mean speed)

    @property
    def zone_ok(self) -> bool:
        return self.zone is None or self.zone.ok

    @property
    def ok(self) -> bool:
        return self.peak_ok and self.rms_ok and self.speed_ok and self.inertia_ok and self.zone_ok

    @property
    def utilisation(self) -> float:
        """RMS torque / rated torque [-]."""
        return self.duty.rms_torque / self.motor.T_n

    @property
    def in_band(self) -> bool:
        return BAND[0] <= self.utilisation <= BAND[1]


@dataclass(frozen=True)
class Choice:
    """The checks of every motor (smallest rated torque first) and the recommendation."""

    checks: tuple[MotorCheck, ...]
    selected: MotorCheck | None
    reason: str


def rating_checks(m: Motor, peak_torque: float, rms_torque: float, peak_speed: float | None,
                  peak_margin: float = 0.0, rms_limit: float | None = None) -> list[Check]:
    """A duty's peak torque [N m], RMS torque [N m] and peak speed [rad/s] (None: not
    checked) against the motor's data sheet: T_max, ``rms_limit`` (default T_n), n_max."""
    sheet = m.source.document
    rms_limit = m.T_n if rms_limit is None else rms_limit
    rms_from = "T_n" if rms_limit == m.T_n else "the continuous zone at the mean speed"
    out = [
        RULES["motor_peak_torque"].check(peak_torque * (1.0 + peak_margin), m.T_max, key="motor_peak",
                                         name=f"{m.name} peak torque", unit="N*m",
                                         quantity=f"T_peak x (1 + `peak_margin` {peak_margin:g})", detail=sheet),
        RULES["motor_rms_torque"].check(rms_torque, rms_limit, key="motor_rms", name=f"{m.name} RMS torque",
                                        unit="N*m", detail=f"over the cycle, against {rms_from} ({sheet})"),
    ]
    if peak_speed is not None:
        out.append(RULES["motor_speed"].check(peak_speed, m.n_max, name=f"{m.name} speed", detail=sheet))
    return out


def motor_checks(c: MotorCheck, ratio_limit: float = 10.0, peak_margin: float = 0.0) -> list[Check]:
    """The checks behind ``c``'s pass/fail flags (peak, RMS, speed, inertia ratio and,
    for a cycle, the torque-speed zone) as ``Check`` objects, SI units.

    Their verdicts are ``c.peak_ok``, ``c.rms_ok``, ... (to 1e-12).
    """
    m, d = c.motor, c.duty
    sheet = m.source.document
    rms_limit = c.continuous_limit if c.continuous_limit is not None else m.T_n
    out = rating_checks(m, d.peak_torque, d.rms_torque, getattr(d, "peak_speed", None), peak_margin, rms_limit)
    out.append(RULES["motor_inertia_ratio"].check(c.inertia_ratio, ratio_limit, key="motor_inertia",
                                                  name=f"{m.name} load/motor inertia ratio",
                                                  detail=f"load inertia at the motor / rotor inertia, "
                                                         f"`inertia_ratio_limit` = {ratio_limit:g}"))
    z = c.zone
    if z is not None:
        where = f"worst at t = {z.time:.4g} s, {z.speed * 30 / math.pi:.0f} rpm"
        zone = "assumed zone" if c.zone_assumed else sheet
        out.append(RULES["motor_zone"].check(z.limit - z.margin, z.limit, name=f"{m.name} torque-speed zone",
                                             unit="N*m", detail=f"at every point of the cycle ({zone}); outside the "
                                                                f"intermittent zone the motor cannot deliver it; {where}"))
    return out


def check_motor(axis: BeltAxis, profile: Trapezoid, motor: Motor, efficiency: float,
                ratio_limit: float = 10.0, peak_margin: float = 0.0) -> MotorCheck:
    """Duty of ``axis`` on ``profile`` driven by ``motor``, and the four pass/fail checks.

    The flat checks of DESIGN.md 2.5 on one trapezoid (:func:`beltcalc.formulas.drive.duty`'s closed
    form), kept as the reference the cycle checks reduce to; ``motor-size`` and
    :func:`beltcalc.design.sizing.size_axis` use :func:`check_cycle`, which adds the torque-speed zone.

    ``efficiency`` is used when the catalog has none for the motor; it gives the
    motor's viscous loss b_M = (1 - eta) T_n / omega_n.
    """
    eta = motor.efficiency if motor.efficiency is not None else efficiency
    b_m = motor_damping(eta, motor.T_n, motor.n_rated)
    load = axis.load_inertia_total
    d = duty(profile, motor.J + load, axis.damping(b_m), axis.resistance_torque)
    ratio = load / motor.J
    return MotorCheck(
        motor=motor, duty=d, inertia_ratio=ratio,
        peak_ok=d.peak_torque * (1.0 + peak_margin) <= motor.T_max,
        rms_ok=d.rms_torque <= motor.T_n,
        speed_ok=profile.peak_speed <= motor.n_max,
        inertia_ok=ratio <= ratio_limit,
    )


def choose_motor(axis: BeltAxis, profile: Trapezoid, motors: list[Motor], efficiency: float,
                 ratio_limit: float = 10.0, peak_margin: float = 0.0) -> Choice:
    """Check every motor and recommend one (or none, with the reason).

    Raises :class:`InputError` (param ``speed``) when the move is faster than every
    motor's maximum speed: no motor of the catalog can run it.

    >>> from beltcalc.data.catalogs import load_catalog
    >>> from beltcalc.formulas.profiles import trapezoid
    >>> axis = BeltAxis(mass=5.0, substitute_mass=0.0, pulley_diameter=0.05,
    ...                 pulley_inertia=2e-5, idler_inertia=2e-5)
    >>> c = choose_motor(axis, trapezoid(157.0, 2000.0, 200.0, 0.3),
    ...                  list(load_catalog().motors.values()), 0.9)
    >>> c.selected.motor.name, round(c.selected.inertia_ratio, 2)
    ('SGM7A-25A', 9.92)
    """
    require_positive("inertia_ratio_limit", ratio_limit, "")
    require_range("peak_margin", peak_margin, "", low=0.0)
    if not motors:
        raise InputError("no motors to choose from", param="motors")
    fastest = max(m.n_max for m in motors)
    if profile.peak_speed > fastest:
        raise InputError(
            f"{profile.peak_speed * 30 / math.pi:.0f} rpm at the motor is over every motor's "
            f"maximum speed (the fastest runs {fastest * 30 / math.pi:.0f} rpm); lower `speed` "
            "or the gear ratio",
            param="speed",
        )
    checks = [check_motor(axis, profile, m, efficiency, ratio_limit, peak_margin) for m in motors]
    return recommend(checks)


def recommend(checks: Sequence[MotorCheck]) -> Choice:
    """The recommendation among checked motors (the rules of the module docstring)."""
    checks = sorted(checks, key=lambda c: (c.motor.T_n, c.motor.J, c.motor.name))
    passing = [c for c in checks if c.ok]
    if not passing:
        n = "five" if any(c.zone is not None for c in checks) else "four"
        return Choice(tuple(checks), None, f"no motor of the catalog passes all {n} checks")
    in_band = [c for c in passing if c.in_band]
    if in_band:
        return Choice(tuple(checks), in_band[0],
                      f"smallest motor that passes and runs at {percent(in_band[0].utilisation)} "
                      "of its rated torque (50-100 %)")
    best = passing[0]
    return Choice(tuple(checks), best,
                  f"smallest motor that passes; none runs at 50-100 % of its rated torque "
                  f"(this one: {percent(best.utilisation)})")


# --- duty cycles: torque-speed zones ----------------------------------------------------------

def intermittent_zone(motor: Motor, end_fraction: float | None = None) -> tuple[tuple[tuple[float, float], ...], bool]:
    """The motor's intermittent (peak) torque-speed zone and whether it is assumed.

    The catalog's ``intermittent`` points when it has them; otherwise the assumption of
    :func:`beltcalc.design.zones.assumed_zone`: T_max flat up to the rated speed, then
    linear down to ``end_fraction`` x T_max at the maximum speed (``None``: down to the
    rated torque T_n). Servo data sheets (e.g. Yaskawa Sigma-7, "Torque-Motor Speed
    Characteristics") show the intermittent zone flat at T_max up to a corner speed at or
    above the rated speed, then falling with the supply voltage's limit towards n_max;
    the straight line from (n_rated, T_max) to (n_max, T_n) is a stated assumption, not
    data, and the output says so.
    """
    own = getattr(motor, "intermittent", ())
    if own:
        return tuple(own), False
    from beltcalc.design.zones import assumed_zone

    end = motor.T_n if end_fraction is None else end_fraction * motor.T_max
    return assumed_zone(motor.T_max, end, motor.n_rated, motor.n_max), True


def check_cycle(drive: "AxisDrive", segments: "Sequence[Segment]", motor: Motor, efficiency: float,
                ratio_limit: float = 10.0, peak_margin: float = 0.0,
                end_fraction: float | None = None) -> MotorCheck:
    """A duty cycle driven by ``motor``: peak, RMS (or the continuous zone at the mean
    speed), speed, inertia ratio and every point against the intermittent zone.

    The inertia ratio is the load's (the largest payload of the cycle, through the
    gearbox, with the gearbox's own inertia) over the rotor's.
    """
    from beltcalc.design.dutycycle import cycle_duty
    from beltcalc.design.zones import zone_check, zone_limit

    eta = motor.efficiency if motor.efficiency is not None else efficiency
    b_m = motor_damping(eta, motor.T_n, motor.n_rated)
    d: CycleDuty = cycle_duty(drive, segments, motor.J, b_m)
    points, assumed = intermittent_zone(motor, end_fraction)
    cont = getattr(motor, "continuous", ())
    limit = zone_limit(tuple(cont), d.mean_speed) if cont else motor.T_n
    ratio = drive.load_inertia(segments) / motor.J
    return MotorCheck(
        motor=motor, duty=d, inertia_ratio=ratio,
        peak_ok=d.peak_torque * (1.0 + peak_margin) <= motor.T_max,
        rms_ok=d.rms_torque <= limit,
        speed_ok=d.peak_speed <= motor.n_max,
        inertia_ok=ratio <= ratio_limit,
        zone=zone_check(d, points, peak_margin), zone_points=points, zone_assumed=assumed,
        continuous_limit=limit,
    )


def choose_for_cycle(drive: "AxisDrive", segments: "Sequence[Segment]", motors: list[Motor], efficiency: float,
                     ratio_limit: float = 10.0, peak_margin: float = 0.0,
                     end_fraction: float | None = None) -> Choice:
    """:func:`choose_motor` for a duty cycle: the same rules, and the zone check too.

    Raises :class:`InputError` (param ``speed``) when the cycle is faster than every
    motor's maximum speed.
    """
    require_positive("inertia_ratio_limit", ratio_limit, "")
    require_range("peak_margin", peak_margin, "", low=0.0)
    if end_fraction is not None:
        require_range("zone_end", end_fraction, "", 0.0, 1.0)
    if not motors:
        raise InputError("no motors to choose from", param="motors")
    checks = [check_cycle(drive, segments, m, efficiency, ratio_limit, peak_margin, end_fraction) for m in motors]
    fastest = max(m.n_max for m in motors)
    top = checks[0].duty.peak_speed
    if top > fastest:
        raise InputError(
            f"{top * 30 / math.pi:.0f} rpm at the motor is over every motor's maximum speed (the fastest "
            f"runs {fastest * 30 / math.pi:.0f} rpm); lower `speed` or the gear ratio", param="speed")
    return recommend(checks)
