"""Motor sizing of a timing-belt linear axis: from the designer's data to the motor to buy.

Composes :mod:`beltcalc.belt` (substitute belt mass), :mod:`beltcalc.drive` (reflected
inertia, losses, torque), :mod:`beltcalc.profiles` (motion) and :mod:`beltcalc.motors`
(choice). SI floats only.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Iterable

from beltcalc import belt as bm
from beltcalc.catalogs import BeltProfile, Motor
from beltcalc.drive import BeltAxis, Duty, cylinder_inertia, duty
from beltcalc.errors import InputError, require_positive
from beltcalc.motors import Choice, MotorCheck, check_motor, choose_motor
from beltcalc.profiles import Trapezoid, trapezoid


@dataclass(frozen=True)
class SizingInputs:
    """Everything ``beltcalc motor-size`` needs, SI. ``speed``/``accel`` carry their kind:
    ``speed_unit`` "rad/s" (motor) or "m/s" (carriage), ``accel_unit`` "rad/s^2" or
    "m/s^2". ``pulley_diameter`` / ``pulley_inertia`` / ``idler_inertia`` = None are
    computed from the pulley teeth and geometry."""

    mass: float
    width: float
    center_distance: float
    pulley_teeth: int
    pulley_width: float
    pulley_bore: float
    pulley_density: float
    coupling_inertia: float
    gearbox_inertia: float
    gear_ratio: float
    belt_ratio: float
    resistance: float
    guide_friction: float
    guide_damping: float
    bearing_damping: float
    motor_efficiency: float
    speed: float
    speed_unit: str
    accel: float
    accel_unit: str
    stroke: float
    dwell: float
    inertia_ratio_limit: float = 10.0
    peak_margin: float = 0.0
    substitute_mass_model: str = "eq7"
    pulley_diameter: float | None = None
    pulley_inertia: float | None = None
    idler_inertia: float | None = None
    load_inertia: float = 0.0


@dataclass(frozen=True)
class Sizing:
    """The axis, its motion at the motor shaft, and the motor choice."""

    axis: BeltAxis
    profile: Trapezoid
    choice: Choice
    shown: MotorCheck | None   # the motor whose duty is reported (selected or --motor)
    substitute_mass: float


def build_axis(inp: SizingInputs, belt: BeltProfile) -> tuple[BeltAxis, float]:
    """The rigid axis (without motor) and the belt's substitute mass m_TB [kg]."""
    if inp.pulley_teeth < 1:
        raise InputError(f"{inp.pulley_teeth} teeth; a pulley needs at least 1", param="pulley_teeth")
    d = inp.pulley_diameter if inp.pulley_diameter is not None else bm.pulley_pitch_diameter(inp.pulley_teeth, belt.pitch)
    require_positive("pulley_diameter", d, "m")
    row = belt.width_row(inp.width) if belt.widths else None
    if row is None or row.w_spec is None:
        raise InputError(f"{belt.name} {inp.width * 1e3:g} mm has no published belt weight; "
                         "the belt mass is needed", param="width")
    z = bm.teeth_on_span(inp.center_distance, belt.pitch)
    m_tb = bm.substitute_mass(bm.belt_mass_on_span(row.w_spec, inp.center_distance), z,
                              inp.substitute_mass_model)
    def body(diameter):  # the stated pulley geometry: a cylinder of the pitch diameter
        return cylinder_inertia(diameter, inp.pulley_bore, inp.pulley_width, inp.pulley_density)

    axis = BeltAxis(
        mass=inp.mass, substitute_mass=m_tb, pulley_diameter=d,
        pulley_inertia=inp.pulley_inertia if inp.pulley_inertia is not None else body(d),
        idler_inertia=inp.idler_inertia if inp.idler_inertia is not None else body(d * inp.belt_ratio),
        coupling_inertia=inp.coupling_inertia, gearbox_inertia=inp.gearbox_inertia,
        load_inertia=inp.load_inertia, belt_ratio=inp.belt_ratio, gear_ratio=inp.gear_ratio,
        bearing_damping=inp.bearing_damping, guide_damping=inp.guide_damping,
        resistance=inp.resistance, guide_friction=inp.guide_friction,
    )
    return axis, m_tb


def motor_profile(inp: SizingInputs, axis: BeltAxis) -> Trapezoid:
    """The move at the motor shaft: speeds and accelerations given at the carriage are
    converted with v = omega D / (2 i)."""
    require_positive("speed", inp.speed, inp.speed_unit)
    require_positive("accel", inp.accel, inp.accel_unit)
    k = axis.carriage_per_motor()
    speed = inp.speed / k if inp.speed_unit == "m/s" else inp.speed
    accel = inp.accel / k if inp.accel_unit == "m/s^2" else inp.accel
    require_positive("stroke", inp.stroke, "m")
    return trapezoid(speed, accel, axis.motor_angle(inp.stroke), inp.dwell)


def size_axis(inp: SizingInputs, belt: BeltProfile, motors: list[Motor], motor: Motor | None = None) -> Sizing:
    """Reflected inertia, torque, energy and the motor choice of a belt axis.

    ``motor`` (optional) is a motor to report on whatever the recommendation.

    >>> from beltcalc.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = SizingInputs(mass=50.0, width=0.025, center_distance=1.245, pulley_teeth=40,
    ...     pulley_width=0.03, pulley_bore=0.02, pulley_density=2700.0, coupling_inertia=2e-5,
    ...     gearbox_inertia=1e-5, gear_ratio=20.0, belt_ratio=1.0, resistance=0.0,
    ...     guide_friction=0.002, guide_damping=0.0, bearing_damping=0.0, motor_efficiency=0.9,
    ...     speed=314.159, speed_unit="rad/s", accel=10.0, accel_unit="m/s^2", stroke=1.0, dwell=0.5)
    >>> s = size_axis(inp, cat.belt("AT10"), list(cat.motors.values()))
    >>> s.choice.selected.motor.name
    'SGM7J-06A'
    """
    axis, m_tb = build_axis(inp, belt)
    profile = motor_profile(inp, axis)
    choice = choose_motor(axis, profile, motors, inp.motor_efficiency, inp.inertia_ratio_limit, inp.peak_margin)
    shown = choice.selected
    if motor is not None:
        shown = next((c for c in choice.checks if c.motor is motor), None) or check_motor(
            axis, profile, motor, inp.motor_efficiency, inp.inertia_ratio_limit, inp.peak_margin)
    return Sizing(axis=axis, profile=profile, choice=choice, shown=shown, substitute_mass=m_tb)


def rigid_duty(inp: SizingInputs, axis: BeltAxis, motor: Motor | None) -> Duty:
    """The duty with one motor (or, with ``motor`` None, of the load alone: no rotor, no motor loss)."""
    profile = motor_profile(inp, axis)
    if motor is None:
        return duty(profile, axis.load_inertia_total, axis.damping(), axis.resistance_torque)
    return check_motor(axis, profile, motor, inp.motor_efficiency).duty


SWEEPABLE = {"accel": "accel", "speed": "speed"}


def sweep(inp: SizingInputs, belt: BeltProfile, motor: Motor | None, name: str,
          values: Iterable[float], unit: str, progress: Callable[[], None] | None = None) -> list[tuple[float, Duty, Trapezoid]]:
    """Duty of one motor over a range of ``accel`` or ``speed`` (the paper's Fig. 13-15).

    ``unit`` tells whether the values are at the motor ("rad/s", "rad/s^2") or the carriage.
    """
    if name not in SWEEPABLE:
        raise InputError(f"cannot sweep {name!r}; sweepable: {', '.join(SWEEPABLE)}", param="sweep")
    axis, _ = build_axis(inp, belt)
    rows = []
    for value in values:
        point = replace(inp, **{name: value, f"{name}_unit": unit})
        profile = motor_profile(point, axis)
        rows.append((value, rigid_duty(point, axis, motor), profile))
        if progress:
            progress()
    return rows


def linspace(start: float, stop: float, n: int) -> list[float]:
    """``n`` evenly spaced values from ``start`` to ``stop`` inclusive."""
    if n < 1:
        raise InputError(f"{n} points; a sweep needs at least 1", param="sweep")
    if n == 1:
        return [start]
    return [start + (stop - start) * k / (n - 1) for k in range(n)]


def energy_eq29_closed_form(inertia: float, damping: float, resistance_torque: float,
                            speed: float, accel: float) -> float:
    r"""Eq. 29 with these models, in closed form [J].

    .. math:: E(\varepsilon) = J \omega^2 + (b \omega + T_R) \omega^2 / \varepsilon

    It falls with the acceleration towards J omega^2 (the paper's Fig. 14).

    >>> energy_eq29_closed_form(0.01, 0.001, 0.5, 100.0, 1000.0)
    106.0
    """
    return inertia * speed ** 2 + (damping * speed + resistance_torque) * speed ** 2 / accel

