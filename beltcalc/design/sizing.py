"""Motor sizing of a timing-belt linear axis: from the designer's data to the motor to buy.

Composes :mod:`beltcalc.formulas.belt` (substitute belt mass), :mod:`beltcalc.formulas.drive` (the axis),
:mod:`beltcalc.formulas.profiles` (motion), :mod:`beltcalc.design.dutycycle` (torque, energy, zones,
regeneration) and :mod:`beltcalc.design.motors` (choice). One implementation: :func:`size_cycle`;
:func:`size_axis` (the public API) calls it, and :func:`sweep` uses the same exact cycle
duty. SI floats only.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the energy of the acceleration phase [W21 eq. 29] and its
    sweeps [W21 Fig. 13-15].
[BM08] L. Biagiotti, C. Melchiorri, Trajectory Planning for Automatic Machines and Robots,
    Springer (2008): the S-curve (see :mod:`beltcalc.formulas.profiles`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Iterable

from beltcalc.formulas import belt as bm
from beltcalc.data.catalogs import BeltProfile, Motor
from beltcalc.design.checks import RULES, Check, failures
from beltcalc.formulas.drive import BeltAxis, cylinder_inertia
from beltcalc.design.dutycycle import CycleDuty, AxisDrive, Gearbox, Mounting, Segment
from beltcalc.design.regeneration import capacitor_energy, Regeneration, regeneration
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.design.motors import Choice, MotorCheck, check_cycle, choose_for_cycle, motor_checks
from beltcalc.formulas.profiles import MoveSpec, Trapezoid, move_by_time, scurve, trapezoid
from beltcalc.design.axis_inputs import SizingInputs

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


def size_axis(inp: SizingInputs, belt: BeltProfile, motors: list[Motor], motor: Motor | None = None,
              opts: "DutyOptions | None" = None) -> "CycleSizing":
    """Reflected inertia, torque, energy and the motor choice of a belt axis: the public
    entry (``beltcalc.size_axis``) of :func:`size_cycle`, which it calls. Without ``opts``
    the move is the inputs' single trapezoid and its dwell, horizontal, through an ideal
    gearbox (the paper's case); ``opts`` (:class:`DutyOptions`) adds S-curves, cycles,
    inclines, gearbox ratings and the DC bus.

    ``motor`` (optional) is a motor to report on whatever the recommendation.

    >>> from beltcalc.data.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = SizingInputs(mass=50.0, width=0.025, center_distance=1.245, pulley_teeth=40,
    ...     pulley_width=0.03, pulley_bore=0.02, pulley_density=2700.0, coupling_inertia=2e-5,
    ...     gearbox_inertia=1e-5, gear_ratio=20.0, belt_ratio=1.0, resistance=0.0,
    ...     guide_friction=0.002, guide_damping=0.0, bearing_damping=0.0, motor_efficiency=0.9,
    ...     speed=314.159, speed_unit="rad/s", accel=10.0, accel_unit="m/s^2", stroke=1.0, dwell=0.5)
    >>> s = size_axis(inp, cat.belt("AT10"), list(cat.motors.values()))
    >>> s.choice.selected.motor.name, round(s.shown.duty.peak_torque, 4)
    ('SGM7J-06A', 2.1014)
    """
    return size_cycle(inp, belt, motors, motor, DutyOptions() if opts is None else opts)


@dataclass(frozen=True)
class SweepPoint:
    """One point of a sweep: the swept ``value`` (in the sweep's unit), the move at the motor
    shaft, and its duty with one motor (or the load alone), SI: peak and RMS torque [N m],
    acceleration time t_a [s], E = T_max w_max t_a [W21 eq. 29] and the exact integral of T w
    over the acceleration [J]."""

    value: float
    profile: Trapezoid
    duty: CycleDuty
    accel_time: float
    accel_energy: float
    accel_energy_exact: float

    @property
    def peak_torque(self) -> float:
        return self.duty.peak_torque

    @property
    def rms_torque(self) -> float:
        return self.duty.rms_torque


SWEEPABLE = {"accel": "accel", "speed": "speed"}


def sweep(inp: SizingInputs, belt: BeltProfile, motor: Motor | None, name: str,
          values: Iterable[float], unit: str, progress: Callable[[], None] | None = None) -> list[SweepPoint]:
    """Duty of one motor over a range of ``accel`` or ``speed`` [W21 Fig. 13-15], by
    the same exact cycle duty as :func:`size_cycle` (the single move and its dwell); with
    ``motor`` None the load alone (no rotor, no motor loss).

    ``unit`` tells whether the values are at the motor ("rad/s", "rad/s^2") or the carriage.
    """
    from beltcalc.formulas.drive import motor_damping
    from beltcalc.design.dutycycle import cycle_duty, single_move

    if name not in SWEEPABLE:
        raise InputError(f"cannot sweep {name!r}; sweepable: {', '.join(SWEEPABLE)}", param="sweep")
    axis, _ = build_axis(inp, belt)
    drive = AxisDrive(axis)
    j_m = b_m = 0.0
    if motor is not None:
        eta = motor.efficiency if motor.efficiency is not None else inp.motor_efficiency
        j_m, b_m = motor.J, motor_damping(eta, motor.T_n, motor.n_rated)
    rows = []
    for value in values:
        point = replace(inp, **{name: value, f"{name}_unit": unit})
        profile = motor_profile(point, axis)
        segments = single_move(profile)
        d = cycle_duty(drive, segments, j_m, b_m)
        rows.append(SweepPoint(value, profile, d, *move_energy(segments, d)))
        if progress:
            progress()
    return rows


def energy_eq29_closed_form(inertia: float, damping: float, resistance_torque: float,
                            speed: float, accel: float) -> float:
    r"""[W21 eq. 29] with these models, in closed form [J].

    .. math:: E(\varepsilon) = J \omega^2 + (b \omega + T_R) \omega^2 / \varepsilon

    It falls with the acceleration towards J omega^2 [W21 Fig. 14].

    >>> energy_eq29_closed_form(0.01, 0.001, 0.5, 100.0, 1000.0)
    106.0
    """
    return inertia * speed ** 2 + (damping * speed + resistance_torque) * speed ** 2 / accel



# --- duty cycles (issue 14): S-curves, several segments, inclines, zones, regeneration -----------

@dataclass(frozen=True)
class DutyOptions:
    """What a duty cycle adds to :class:`SizingInputs`, SI. ``jerk`` (value, unit "rad/s^3"
    or "m/s^3") makes the single move an S-curve; ``move_time`` gives it by time instead of
    speed and acceleration; ``cycle`` replaces it by these segments (``speed``/``accel``/
    ``jerk`` of the inputs are their defaults). ``incline`` [rad], ``counterweight`` [kg],
    ``brake``; gearbox efficiency driving / back-driven and the catalog gearbox (its ratio and
    inertia replace the inputs'); DC bus: ``dc_bus_capacitance`` [F], ``dc_bus_voltage`` and
    ``chopper_voltage`` [V]; ``regen_efficiency``; ``zone_end``: the assumed zone's torque
    at n_max as a fraction of T_max (None: the rated torque)."""

    jerk: tuple[float, str] | None = None
    move_time: float | None = None
    accel_fraction: float = 1.0 / 3.0
    jerk_fraction: float = 0.0
    cycle: tuple[MoveSpec, ...] | None = None
    cycle_title: str = ""
    incline: float = 0.0
    counterweight: float = 0.0
    brake: bool = False
    gear_efficiency: float = 1.0
    gear_efficiency_back: float | None = None
    gearbox: Gearbox | None = None
    dc_bus_capacitance: float | None = None
    dc_bus_voltage: float | None = None
    chopper_voltage: float | None = None
    regen_efficiency: float = 1.0
    zone_end: float | None = None
    shaper: str | None = None
    shaper_frequency: float | None = None
    shaper_zeta: float = 0.0
    shaper_at: str = "both"

    def __post_init__(self):
        # checked also when no --move-time uses them (an option a run ignores is still checked)
        require_range("accel_fraction", self.accel_fraction, "", 0.0, 0.5, low_open=True)
        require_range("jerk_fraction", self.jerk_fraction, "", 0.0, 0.5)
        if isinstance(self.shaper, str):
            from beltcalc.formulas.shapers import SHAPERS

            if self.shaper not in SHAPERS:
                raise InputError(f"{self.shaper!r} is not a shaper; use one of {', '.join(SHAPERS)}", param="shaper")
            if self.shaper_frequency is not None:
                require_positive("shaper_frequency", self.shaper_frequency, "Hz")
            require_range("shaper_zeta", self.shaper_zeta, "", 0.0, 1.0, high_open=True)
            if self.shaper_at not in ("end", "both"):
                raise InputError(f"{self.shaper_at!r}: use end (the mode where each move stops) or both (where it "
                                 "starts and where it stops)", param="shaper_at")


@dataclass(frozen=True)
class GearboxCheck:
    name: str
    value: float
    limit: float
    unit: str

    @property
    def ok(self) -> bool:
        return self.value <= self.limit


@dataclass(frozen=True)
class ShapedMove:
    """A move of the cycle shaped for the axis's first mode where it stops: the move's name,
    the :class:`beltcalc.formulas.shapers.Shaper`, the carriage's position at the move's end
    (span 1, drive pulley to carriage [m]; None where the frequency was given) and the time
    the shaper adds to the move [s] (the dwell after it shortened by as much where it is at
    least as long)."""

    name: str
    shaper: object
    position: float | None
    added: float


def axis_frequency(c_spec: float, mass: float, center_distance: float, pulley_diameter: float,
                   position: float) -> float:
    r"""The belt axis's first natural frequency with the carriage at ``position`` (span 1 from
    the drive pulley [m]) and the drive side held [Hz]: the carriage ``mass`` [kg] between its
    two spans, each C_spec / L ([W21 eq. 5]),

    .. math:: f = rac{1}{2\pi}\sqrt{rac{C_{spec} (1/L_1 + 1/L_2)}{m}}, \quad L_2 = 2a - L_1 + \pi D / 2

    >>> round(axis_frequency(5.5e5, 50.0, 1.245, 0.128, 1.1225), 3)
    20.636
    """
    from beltcalc.design.positioning import span_lengths, span_pair_stiffness

    l1, l2 = span_lengths(center_distance, pulley_diameter, position)
    return math.sqrt(span_pair_stiffness(c_spec, l1, l2) / mass) / (2 * math.pi)


def shape_cycle(inp: SizingInputs, axis: BeltAxis, belt: BeltProfile, segments: tuple[Segment, ...],
                opts: DutyOptions) -> tuple[tuple[Segment, ...], tuple[ShapedMove, ...]]:
    """Each move of ``segments`` shaped by ``opts.shaper`` (:mod:`beltcalc.formulas.shapers`)
    for the axis's first mode where the move stops (``opts.shaper_at`` ``both``: and where it
    starts, the two shapers convolved) (:func:`axis_frequency`: the carriage
    starts with the stroke centred on the axis, span 1 = (a - stroke) / 2, and each move
    carries it its distance along its direction), or at ``opts.shaper_frequency``; the dwell
    after a move gives up the time its shaper adds where it is at least as long (the cycle
    time stays), else the cycle lengthens. ``opts.shaper`` may also be a
    :class:`~beltcalc.formulas.shapers.Shaper` itself, used on every move as it is. Returns the
    segments and what was shaped."""
    from beltcalc.formulas.shapers import SHAPERS, convolve, shaped_profile

    if opts.shaper is None:
        return segments, ()
    c_spec = None
    if opts.shaper_frequency is None and isinstance(opts.shaper, str):
        row = belt.width_row(inp.width)
        c_spec = row.C_spec
        if c_spec is None:
            raise InputError(f"{belt.name} has no C_spec for {inp.width * 1e3:g} mm in its catalog, so the axis's "
                             "frequency is unknown: give the shaper's frequency", param="shaper_frequency")
    a, lever = inp.center_distance, axis.carriage_per_motor()
    position = (a - inp.stroke) / 2
    out, shaped = list(segments), []
    for k, seg in enumerate(segments):
        if seg.kind != "move":
            continue
        before = position
        position += seg.direction * sum(ph.angle for ph in seg.profile.phases if ph.name != "dwell") * lever
        if not isinstance(opts.shaper, str):            # a shaper given as it is
            shaper, where = opts.shaper, None
        elif opts.shaper_frequency is not None:
            shaper, where = SHAPERS[opts.shaper](opts.shaper_frequency, opts.shaper_zeta), None
        else:
            def designed(x: float):
                if not 0 < x < a:
                    raise InputError(f"move {seg.name!r} reaches {x * 1e3:.6g} mm from the drive pulley, off the "
                                     f"axis (0 to {a * 1e3:g} mm, the stroke centred on it): give the shaper's "
                                     "frequency", param="shaper_frequency")
                f = axis_frequency(c_spec, axis.mass + axis.substitute_mass + seg.payload, a, axis.pulley_diameter, x)
                return SHAPERS[opts.shaper](f, opts.shaper_zeta)
            shaper, where = designed(position), position
            if opts.shaper_at == "both":
                # what the move excites where it starts rings on (lightly damped) to where it stops
                shaper = convolve(shaper, designed(before))
        move = tuple(ph for ph in seg.profile.phases if ph.name != "dwell")
        out[k] = replace(seg, profile=shaped_profile(replace(seg.profile, dwell=0.0, phases=move), shaper))
        nxt = out[k + 1] if k + 1 < len(out) else None
        if nxt is not None and nxt.kind == "dwell" and nxt.duration >= shaper.duration:
            out[k + 1] = replace(nxt, duration=nxt.duration - shaper.duration)
        shaped.append(ShapedMove(seg.name, shaper, where, shaper.duration))
    return tuple(g for g in out if g.kind == "move" or g.duration > 0), tuple(shaped)


@dataclass(frozen=True)
class CycleSizing:
    """A duty cycle sized: the axis, the drive, the segments at the motor shaft, the choice,
    the reported motor's regeneration, the gearbox checks, warnings and assumptions."""

    axis: BeltAxis
    drive: AxisDrive
    segments: tuple[Segment, ...]
    choice: Choice
    shown: MotorCheck | None
    substitute_mass: float
    regen: Regeneration | None
    gearbox_checks: tuple[GearboxCheck, ...]
    warnings: tuple[str, ...]
    assumptions: tuple[str, ...]
    checks: tuple[Check, ...] = ()      # the reported motor's and the gearbox's
    notes: tuple[str, ...] = ()         # what the cycle does that was not asked (jerk-limited moves, the way back)
    shaped: tuple[ShapedMove, ...] = ()  # each move's input shaper (DutyOptions.shaper)

    @property
    def first_move(self) -> Segment:
        return next(s for s in self.segments if s.kind == "move")

    @property
    def profile(self) -> Trapezoid:
        """The first move's profile at the motor shaft."""
        return self.first_move.profile


def _at_motor(value: tuple[float, str], k: float, motor_unit: str, param: str) -> float:
    v, unit = value
    require_positive(param, v, unit)
    return v if unit == motor_unit else v / k


def move_profile(spec: MoveSpec, axis: BeltAxis, defaults: SizingInputs, default_jerk=None) -> Trapezoid:
    """The profile of a move at the motor shaft (magnitudes; the direction is the segment's)."""
    k = axis.carriage_per_motor()
    require_positive("stroke", spec.distance, "m")
    angle = axis.motor_angle(spec.distance)
    if spec.time is not None:
        return move_by_time(angle, spec.time, spec.accel_fraction, spec.jerk_fraction)
    speed = _at_motor(spec.speed or (defaults.speed, defaults.speed_unit), k, "rad/s", "speed")
    accel = _at_motor(spec.accel or (defaults.accel, defaults.accel_unit), k, "rad/s^2", "accel")
    jerk = spec.jerk or default_jerk
    if jerk is None:
        return trapezoid(speed, accel, angle)
    return scurve(speed, accel, _at_motor(jerk, k, "rad/s^3", "jerk"), angle)


def cycle_segments(inp: SizingInputs, axis: BeltAxis, opts: DutyOptions) -> tuple[Segment, ...]:
    """The cycle at the motor shaft: the segments of ``opts.cycle``, or the single move of
    the inputs (stroke, speed/accel/jerk or move time) and its dwell; on an inclined axis
    (``opts.incline`` != 0) the move out and back (:func:`out_and_back`), since what goes up
    comes down and the way down is where the drive brakes.

    One rule for a dwell of 0 s, however it is given: no dwell (the move runs straight into
    the next); a negative one is refused."""
    if opts.cycle is None:
        spec = MoveSpec("move", "move", distance=inp.stroke, time=opts.move_time,
                        accel_fraction=opts.accel_fraction, jerk_fraction=opts.jerk_fraction)
        if opts.move_time is None and opts.jerk is None:
            prof = motor_profile(inp, axis)           # today's trapezoid, unchanged
        else:
            prof = move_profile(spec, axis, inp, opts.jerk)
        require_range("dwell", inp.dwell, "s", low=0.0)
        if opts.incline != 0:
            return out_and_back(prof, inp.dwell, opts.incline)
        segs = [Segment("move", "move", profile=prof)]
        if inp.dwell > 0:
            segs.append(Segment("dwell", "dwell", duration=inp.dwell))
        return tuple(segs)
    if not opts.cycle:
        raise InputError("the cycle has no segments", param="cycle")
    if len(opts.cycle) > 10000:
        raise InputError(f"{len(opts.cycle)} segments; at most 10000", param="cycle")
    out = []
    for n, spec in enumerate(opts.cycle, start=1):
        name = spec.name or f"{spec.kind} {n}"
        try:
            if spec.kind == "dwell":
                if spec.time is None:
                    raise InputError("a dwell needs a time", param="cycle")
                if require_range("dwell", spec.time, "s", low=0.0) == 0.0:
                    continue                  # 0 s: the move runs straight into the next, as --dwell 0s
                out.append(Segment(name, "dwell", duration=spec.time, payload=spec.payload, force=spec.force))
            else:
                prof = move_profile(spec, axis, inp, opts.jerk)
                out.append(Segment(name, "move", profile=prof, direction=spec.direction, payload=spec.payload,
                                   force=spec.force))
        except InputError as exc:
            raise InputError(f"segment {n} ({name}): {exc}", param="cycle") from None
    if not any(seg.kind == "move" for seg in out):
        raise InputError("the cycle has no move (only dwells): nothing to size a motor for", param="cycle")
    return tuple(out)


def out_and_back(profile: Trapezoid, dwell: float, incline: float) -> tuple[Segment, ...]:
    """The default cycle of an inclined axis: the move along +x (up the incline when
    ``incline`` > 0), the dwell, the same move back along -x, the dwell (a dwell of 0 s is
    left out). The way down returns the potential energy: without it the braking energy
    and the resistor would be those of half a cycle that never closes.

    >>> from beltcalc.formulas.profiles import trapezoid
    >>> [(g.name, g.direction) for g in out_and_back(trapezoid(100.0, 1000.0, 50.0), 0.5, 1.5708)]
    [('up', 1), ('dwell at the top', 1), ('down', -1), ('dwell at the bottom', 1)]
    """
    first, second = ("up", "down") if incline > 0 else ("down", "up")
    where = {"up": "at the top", "down": "at the bottom"}
    segs = []
    for name, direction in ((first, 1), (second, -1)):
        segs.append(Segment(name, "move", profile=profile, direction=direction))
        if dwell > 0:
            segs.append(Segment(f"dwell {where[name]}", "dwell", duration=dwell))
    return tuple(segs)


def jerk_limited(segments, k: float) -> list[str]:
    """Notes on the moves whose jerk limit keeps them below the acceleration asked (an
    S-curve whose acceleration phase never reaches ``accel``, [BM08 sec. 3.4]: when
    v j < a^2 the speed is reached first, a_lim = sqrt(v j); when the stroke is too short,
    theta < 2 a^3 / j^2, neither is reached). ``k`` [m/rad] converts the motor's acceleration
    to the carriage's.

    >>> from beltcalc.formulas.profiles import scurve
    >>> jerk_limited([Segment("move", "move", profile=scurve(100.0, 1000.0, 2000.0, 500.0))], 0.01)[0][:57]
    'move: the jerk limit (20 m/s^3 at the carriage, 2000 rad/'
    """
    notes = []
    for g in segments:
        p = g.profile
        if g.kind != "move" or not math.isfinite(getattr(p, "jerk", math.inf)):
            continue
        if p.peak_accel >= p.accel * (1 - 1e-12):
            continue
        why = ("the stroke is too short to reach either (theta < 2 a^3 / j^2)" if p.triangular
               else "the speed is reached first (v j < a^2: a = sqrt(v j))")
        notes.append(f"{g.name}: the jerk limit ({p.jerk * k:.4g} m/s^3 at the carriage, {p.jerk:.4g} rad/s^3 "
                     f"at the motor) keeps the acceleration at {p.peak_accel * k:.4g} m/s^2 ({p.peak_accel:.4g} "
                     f"rad/s^2 at the motor), below the {p.accel * k:.4g} m/s^2 ({p.accel:.4g} rad/s^2) asked: "
                     f"{why}")
    return notes


def size_cycle(inp: SizingInputs, belt: BeltProfile, motors: list[Motor], motor: Motor | None = None,
               opts: DutyOptions = DutyOptions()) -> CycleSizing:
    """Reflected inertia, the duty cycle's torque and energy, the motor choice against the
    torque-speed zones, the gearbox checks and the braking resistor.

    With the default ``opts`` it is today's single trapezoidal move, horizontally, through
    an ideal gearbox: the same numbers as :func:`size_axis` (to rounding).

    >>> from beltcalc.data.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = SizingInputs(mass=50.0, width=0.025, center_distance=1.245, pulley_teeth=40,
    ...     pulley_width=0.03, pulley_bore=0.02, pulley_density=2700.0, coupling_inertia=2e-5,
    ...     gearbox_inertia=1e-5, gear_ratio=20.0, belt_ratio=1.0, resistance=0.0,
    ...     guide_friction=0.002, guide_damping=0.0, bearing_damping=0.0, motor_efficiency=0.9,
    ...     speed=314.159, speed_unit="rad/s", accel=10.0, accel_unit="m/s^2", stroke=1.0, dwell=0.5)
    >>> s = size_cycle(inp, cat.belt("AT10"), list(cat.motors.values()))
    >>> s.choice.selected.motor.name, round(s.shown.duty.peak_torque, 4)
    ('SGM7J-06A', 2.1014)
    """
    gb_cat = opts.gearbox
    if gb_cat is not None:
        inp = replace(inp, gear_ratio=gb_cat.ratio, gearbox_inertia=gb_cat.inertia)
    axis, m_tb = build_axis(inp, belt)
    if gb_cat is not None:
        gearbox = replace(gb_cat, efficiency=gb_cat.efficiency if opts.gear_efficiency == 1.0 else opts.gear_efficiency,
                          efficiency_back=opts.gear_efficiency_back if opts.gear_efficiency_back is not None
                          else gb_cat.efficiency_back)
    else:
        gearbox = Gearbox(inp.gear_ratio, inp.gearbox_inertia, opts.gear_efficiency, opts.gear_efficiency_back)
    drive = AxisDrive(axis, Mounting(opts.incline, opts.counterweight, opts.brake), gearbox)
    segments, shaped = shape_cycle(inp, axis, belt, cycle_segments(inp, axis, opts), opts)
    choice = choose_for_cycle(drive, segments, motors, inp.motor_efficiency, inp.inertia_ratio_limit,
                              inp.peak_margin, opts.zone_end)
    shown = choice.selected
    if motor is not None:
        shown = next((c for c in choice.checks if c.motor is motor), None) or check_cycle(
            drive, segments, motor, inp.motor_efficiency, inp.inertia_ratio_limit, inp.peak_margin, opts.zone_end)
    warnings, assumptions = [], []
    regen = None
    bus = (opts.dc_bus_capacitance, opts.dc_bus_voltage, opts.chopper_voltage)
    if shown is not None:
        stored = capacitor_energy(*bus) if bus[0] is not None else None
        regen = regeneration(shown.duty, stored, opts.regen_efficiency, opts.chopper_voltage)
        if shown.zone_assumed:
            end = "the rated torque T_n" if opts.zone_end is None else f"{opts.zone_end:g} x T_max"
            assumptions.append(f"{shown.motor.name}: the catalog has no torque-speed curve; intermittent zone "
                               f"assumed flat at T_max up to the rated speed, then falling linearly to {end} "
                               "at the maximum speed")
        cont = getattr(shown.motor, "continuous", ())
        if not cont and shown.duty.mean_speed > shown.motor.n_rated:
            warnings.append(f"{shown.motor.name}: the mean speed {shown.duty.mean_speed * 30 / math.pi:.0f} rpm is "
                            "above the rated speed and the catalog has no continuous zone; the RMS check against "
                            "T_n is not safe there")
        if stored is not None and regen.resistor_energy > 0:
            warnings.append(f"braking returns up to {max(e for _, e, _ in regen.events):.3g} J per event, more than the "
                            f"DC-bus capacitors store ({stored:.3g} J): a braking resistor rated at least "
                            f"{regen.resistor_rating:.3g} W (W_K = E_K / (0.2 T), Yaskawa's 20 % load ratio; "
                            f"{regen.resistor_power:.3g} W on average) and {regen.resistor_peak_power:.3g} W peak "
                            "is needed")
        if shown.duty.holding_torque > 0 and opts.incline != 0 and not opts.brake:
            assumptions.append("at rest the motor holds the axis against gravity (no brake): the holding torque "
                               "counts in the RMS")
    gb_checks = []
    if shown is not None:
        d = shown.duty
        if gearbox.max_input_speed is not None:
            gb_checks.append(GearboxCheck("gearbox input speed", d.peak_speed, gearbox.max_input_speed, "rad/s"))
        if gearbox.peak_torque is not None:
            gb_checks.append(GearboxCheck("gearbox peak output torque", d.load_peak_torque * gearbox.ratio,
                                          gearbox.peak_torque, "N m"))
        if gearbox.rated_torque is not None:
            gb_checks.append(GearboxCheck("gearbox RMS output torque", d.load_rms_torque * gearbox.ratio,
                                          gearbox.rated_torque, "N m"))
    checks = []
    if shown is not None:
        checks = motor_checks(shown, inp.inertia_ratio_limit, inp.peak_margin)
        src = gearbox.source or "the gearbox catalog"
        rule = {"gearbox input speed": "gearbox_input_speed", "gearbox peak output torque": "gearbox_peak_torque",
                "gearbox RMS output torque": "gearbox_rms_torque"}
        checks += [RULES[rule[c.name]].check(c.value, c.limit, key=c.name.replace(" ", "_"),
                                             unit=c.unit.replace(" ", "*"), detail=src) for c in gb_checks]
    warnings[:0] = [c.warning() for c in failures(checks)]
    notes = jerk_limited(segments, axis.carriage_per_motor())
    if opts.cycle is None and opts.incline != 0:
        notes.append("the cycle is " + ", ".join(g.name for g in segments) + ": an inclined axis comes back, "
                     "and the braking on the way down counts in the braking energy and the resistor")
    return CycleSizing(axis=axis, drive=drive, segments=segments, choice=choice, shown=shown,
                       substitute_mass=m_tb, regen=regen, gearbox_checks=tuple(gb_checks),
                       warnings=tuple(warnings), assumptions=tuple(assumptions), checks=tuple(checks),
                       notes=tuple(notes), shaped=shaped)


def move_energy(segments, duty) -> tuple[float, float, float]:
    r"""(t_a, E_29, E_exact) of the first move of a cycle's ``duty`` [s, J, J].

    .. math:: E_{29} = T_{max}\,\omega_{max}\,t_a, \qquad E_{exact} = \int_{0}^{t_a} T \omega \, dt

    [W21 eq. 29] with T_max the cycle's peak torque, beside the exact
    integral of the power over the move's acceleration phases (a polynomial per piece).
    """
    from beltcalc.design.polynomials import poly_integral, poly_mul
    from beltcalc.formulas.profiles import ACCEL_PHASES

    seg_index = next(k for k, seg in enumerate(segments) if seg.kind == "move")
    prof = segments[seg_index].profile
    t_a = prof.accel_time
    exact = sum(poly_integral(poly_mul(p.torque, p.w), p.duration) for p in duty.pieces
                if p.segment == seg_index and p.phase in ACCEL_PHASES)
    return t_a, duty.peak_torque * prof.peak_speed * t_a, exact


def first_move_energy(s: CycleSizing) -> tuple[float, float, float]:
    """:func:`move_energy` of the reported motor's duty [s, J, J]."""
    return move_energy(s.segments, s.shown.duty)
