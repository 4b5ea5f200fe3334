"""A timing-belt linear axis as a dynamic model [W21]: the motor side (motor rotor,
gearbox, coupling, pulleys: one inertia at the motor shaft) joined to the carriage by the
belt, either as the substitute spring-damper-mass of [W21 eq. 5-9] (k_TB, b_TB, m_TB) or as
the paper's chain of z - 1 mass-spring-damper units in series [W21 eq. 1]. External
resistance F_R and guide friction act against the move; the motor either follows the
motion profile exactly (an ideal servo, ``prescribed``) or is driven by the rigid
feed-forward torque of ``motor-size`` plus a proportional speed loop (``speed-loop``).
SI floats only.

The scene ``simulate linear-axis`` (``catalogs/scenes/linear_axis.toml``, over the
motor-size scene ``wdu``) reports the belt force against the pretension, the carriage's
following error and residual vibration, and the motor torque against the rigid answer.

Belt force: F = k_TB (r phi / i - x) + b_TB (r omega / i - v), r = D / 2, positive when the
belt pulls the carriage forward. The carriage runs in +x.

The motor's peak and RMS torque and the belt force's extremes are computed off the exact
solution (:func:`beltcalc.sim.watch.pieces.exact_signals`), not from the output samples:
the prescribed acceleration is right-continuous, so a sample never sees the left limit at
the end of a phase, where the torque peaks; ``motor-size``'s rigid peak takes both limits, and so does this one.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the WDU axis, its belt models [W21 eq. 1-9] and the
    rigidity condition [W21 eq. 10-11].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Iterable

import numpy as np

from beltcalc.formulas.drive import BeltAxis
from beltcalc.design.dutycycle import CycleDuty
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.params import Param
from beltcalc.formulas.profiles import Phase, Trapezoid
from beltcalc.design.checks import RULES
from beltcalc.report import Row, Section
from beltcalc.sim.network import Network
from beltcalc.sim.scenes.axis_stops import (extremes, moves, phase_starts, reference_position, reference_tables,
                                            settling_checks, shaper_rows, static_sections, stop_figures, stop_rows)
from beltcalc.sim.scenes import axis_stops
from beltcalc.sim.scenes.base import Outcome, Scene, scene_values
from beltcalc.design.axis_inputs import PARAMS as AXIS_PARAMS

move_time = axis_stops.move_time     # the end of the first move, where the scene's users look for it

DRIVES = ("prescribed", "speed-loop")
BELT_MODELS = ("substitute", "chain")
SPANS = ("paper", "moving")
CYCLES = ("one-way", "out-and-back")
PARAMS = AXIS_PARAMS + [
    Param("thread", None, "Tensioner bolt thread (for the pretension, as `beltcalc tension`)."),
    Param("tension_accel", "m/s^2", "Acceleration of the tensioning motion."),
    Param("tension_speed", "m/s", "Speed of the tensioning motion."),
    Param("mu", "", "Thread friction coefficient."),
    Param("damping", "N*s/m", "Belt damping b_TB, instead of the catalog's.", required=False),
    Param("drive", None, "prescribed (ideal servo) or speed-loop (feed-forward + speed_gain)."),
    Param("speed_gain", "N*m*s/rad", "Proportional speed-loop gain."),
    Param("belt_model", None, "substitute (eq. 5-9) or chain (eq. 1, z - 1 units)."),
    Param("spans", None, "paper (one span k_TB = C_spec / a, held) or moving (both spans, their lengths "
          "following the carriage: k = C_spec / L1 + C_spec / L2).", required=False),
    Param("start", "m", "Span 1 (drive pulley to carriage) at the move's start (default: the stroke centred "
          "on the axis).", required=False),
    Param("cycle", None, "one-way (one move, then after_move) or out-and-back (the move, a dwell, the move "
          "back, a dwell: settling at both ends).", required=False),
    Param("shaper", None, "Input shaper for each move: zv, zvd or ei (none: the move as planned), designed "
          "for the axis's first mode where the move stops.", required=False),
    Param("shaper_frequency", "Hz", "The shaper's design frequency instead of the predicted mode's.",
          required=False),
    Param("shaper_zeta", "", "The shaper's design damping ratio instead of the predicted mode's.", required=False),
    Param("shaper_at", None, "both (default: the modes where each move starts and stops, the two shapers "
          "convolved: what the move excites at its start rings on, lightly damped, to its stop) or end (the mode "
          "where it stops only).", required=False),
    Param("static_force", "N", "A force on the carriage at standstill (a process force), for the static "
          "positioning error.", required=False),
    Param("after_move", "s", "Simulated time after the move."),
    Param("step", "s", "Output step."),
    Param("settle_band", "m", "Following-error band for the settling time."),
    Param("jerk", "rad/s^3|m/s^3", "Jerk limit: the move becomes motor-size's 7-phase S-curve "
          "(at the motor 1e5rad/s^3 or the carriage 200m/s^3; none: the trapezoid).", required=False),
    Param("move_time", "s", "The move by its time instead of speed and accel (as motor-size --move-time).",
          required=False),
    Param("accel_fraction", "", "With move_time: acceleration time / move time (at most 0.5; default 1/3).",
          required=False),
    Param("jerk_fraction", "", "With move_time: jerk time / acceleration time (0: trapezoid, at most 0.5).",
          required=False),
]


@dataclass(frozen=True)
class ShapedBack:
    """The move back's shaper (designed where it stops, at the stroke's start)."""

    shaper: object
    name: str = "move back"
    position: float | None = None

    @property
    def added(self) -> float:
        return self.shaper.duration


@dataclass(frozen=True)
class AxisModel:
    """What the dynamic model needs, SI: the rigid axis and its motion (from ``motor-size``),
    the motor, the belt's substitute parameters (from ``tension``), and the drive.
    ``profile`` is the move at the motor shaft with its dwell as the last phase; ``duty`` the
    rigid answer of motor-size for this motor (:class:`beltcalc.design.dutycycle.CycleDuty`)."""

    axis: BeltAxis
    profile: Trapezoid          # at the motor shaft, the dwell its last phase
    duty: CycleDuty             # the rigid answer of motor-size for this motor
    motor_inertia: float        # kg m^2
    motor_damping: float        # N m s/rad, b_M
    stiffness: float            # N/m, k_TB
    damping: float              # N s/m, b_TB
    belt_mass: float            # kg, the belt on the span (for the chain model)
    teeth: float                # teeth on the span z
    drive: str = "prescribed"
    speed_gain: float = 0.0     # N m s/rad
    belt_model: str = "substitute"
    spans: str = "paper"
    center_distance: float = 0.0   # m, a
    start: float = 0.0             # m, span 1 at the move's start (drive pulley to carriage)
    cycle: str = "one-way"
    shaped: tuple = ()             # each move's shaper (ShapedMove of motor-size, ShapedBack)

    @property
    def travel(self) -> float:
        """The carriage's travel of one move [m]."""
        t0, t1, _ = moves(self)[0]
        return sum(ph.angle for ph, start in zip(self.profile.phases, phase_starts(self)) if t0 <= start < t1) \
            * self.lever

    @property
    def return_start(self) -> float:
        """Span 2 (carriage round the idler back to the drive pulley) at the move's start [m]:
        L2 = 2 a - L1 + pi D / 2 (:func:`span_stiffness`)."""
        return 2 * self.center_distance - self.start + math.pi * self.axis.pulley_diameter / 2

    @property
    def lever(self) -> float:
        """Carriage travel per motor radian r / i [m/rad]."""
        return self.axis.carriage_per_motor()

    @property
    def rotating_inertia(self) -> float:
        """Everything that turns, at the motor shaft [kg m^2]: the reduced inertia without
        the carriage and the belt (those are the other end of the belt)."""
        parts = self.axis.inertia_parts()
        return self.motor_inertia + sum(v for k, v in parts.items() if k not in ("carriage", "belt"))

    @property
    def rotating_damping(self) -> float:
        """Viscous damping at the motor shaft without the guide's [N m s/rad]."""
        ax = self.axis
        return self.motor_damping + ax.bearing_damping * (1 + 1 / ax.belt_ratio ** 2) / ax.gear_ratio ** 2

    @property
    def chain_units(self) -> int:
        """Mass-spring-damper units of the chain of [W21 eq. 1]: the whole pitches on the span, z - 1
        rounded down (124 for the WDU axis, z = 125.5)."""
        return max(1, int(math.floor(self.teeth - 1 + 1e-9)))

    def check(self) -> None:
        """Refuse a drive or belt model that does not exist, and negative stiffness, damping or gain."""
        with scene_values(("drive", "belt_model", "damping", "speed_gain", "spans", "start", "cycle")):
            if self.spans not in SPANS:
                raise InputError(f"{self.spans!r} is not a span model; use one of {', '.join(SPANS)}", param="spans")
            if self.cycle not in CYCLES:
                raise InputError(f"{self.cycle!r} is not a cycle; use one of {', '.join(CYCLES)}", param="cycle")
            if self.spans == "moving":
                if self.belt_model != "substitute":
                    raise InputError("moving spans take the substitute belt (belt_model substitute)",
                                     param="spans")
                end = self.start + self.travel
                if not (0 < self.start < self.center_distance and 0 < end < self.center_distance):
                    raise InputError(f"the carriage would run from {self.start * 1e3:g} mm to {end * 1e3:g} mm of the "
                                     f"drive pulley: both must lie within the centre distance "
                                     f"{self.center_distance * 1e3:g} mm (lower start or stroke)", param="start")
            if self.drive not in DRIVES:
                raise InputError(f"{self.drive!r} is not a drive; use one of {', '.join(DRIVES)}", param="drive")
            if self.belt_model not in BELT_MODELS:
                raise InputError(f"{self.belt_model!r} is not a belt model; use one of {', '.join(BELT_MODELS)}",
                                 param="belt_model")
            require_positive("stiffness", self.stiffness, "N/m")
            require_range("damping", self.damping, "N*s/m", low=0.0)
            require_range("speed_gain", self.speed_gain, "N*m*s/rad", low=0.0)
            if self.drive == "speed-loop" and any(ph.jerk for ph in self.profile.phases):
                raise InputError("the speed loop takes a trapezoid only (its speed reference and feed-forward "
                                 "are piecewise-linear tables); leave out jerk and jerk_fraction, or use drive "
                                 "prescribed", param="drive")


def drive_data(model: AxisModel, substitute_mass: float | None = None, stiffness: float | None = None) -> dict:
    """The drive (the structure of a drive file, SI floats): the motor side, the belt
    (substitute or chain), the carriage, the move. Its values come from `motor-size`'s
    sizing of the axis, so the scene writes the drive rather than reading one file;
    ``catalogs/drives/linear_axis.toml`` is this drive for the WDU scene.

    ``substitute_mass`` / ``stiffness`` override m_TB / k_TB (the model comparisons)."""
    model.check()
    ax, lever = model.axis, model.lever
    k = model.stiffness if stiffness is None else stiffness
    b = model.damping
    nodes = [dict(name="motor", inertia=model.rotating_inertia)]
    couplings = [dict(name="bearings", between=["motor"], stiffness=0.0, damping=model.rotating_damping)]
    belts: list[dict] = []
    if model.belt_model == "substitute":
        m_tb = ax.substitute_mass if substitute_mass is None else substitute_mass
        nodes.append(dict(name="carriage", mass=ax.mass + m_tb))
        if model.spans == "moving":
            # both spans, following the carriage: k = C_spec (1/L1 + 1/L2), C_spec = k_TB a, b_spec = b_TB a
            a = model.center_distance
            nodes[0]["pitch_diameter"] = 2 * lever
            belts.append(dict(name="belt", pulley="motor", carriage="carriage", specific_stiffness=k * a,
                              specific_damping=b * a, span=model.start, return_span=model.return_start,
                              stroke=model.travel))
        else:
            # C (phi - U x) with C = k lever^2, U = 1 / lever: the torque lever * F
            couplings.append(dict(name="belt", between=["motor", "carriage"], stiffness=k * lever ** 2,
                                  damping=b * lever ** 2, ratio=1.0 / lever))
    else:
        n = model.chain_units
        unit_mass = model.belt_mass / n
        kk, bb = n * k, n * b                 # [W21 eq. 8-9]: k' = (z - 1) k_TB, b' = (z - 1) b_TB
        names = [f"tooth{j}" for j in range(2, n + 1)] + ["carriage"]
        nodes += [dict(name=name, mass=unit_mass) for name in names[:-1]]
        nodes.append(dict(name="carriage", mass=ax.mass + unit_mass))
        couplings.append(dict(name="belt", between=["motor", names[0]], stiffness=kk * lever ** 2,
                              damping=bb * lever ** 2, ratio=1.0 / lever))
        couplings += [dict(name=f"belt_{a}", between=[a, c], stiffness=kk, damping=bb)
                      for a, c in zip(names, names[1:])]
    if ax.guide_damping:
        couplings.append(dict(name="guide", between=["carriage"], stiffness=0.0, damping=ax.guide_damping))
    resist = ax.resistance_torque / lever       # F_R + mu m g, against the move
    table = []
    for t0, t1, sign in moves(model):
        table += [[t0, 0.0], [t0, sign * resist], [t1, sign * resist], [t1, 0.0]]
    loads = [dict(name="resistance", node="carriage", table=table[1:])] if resist else []
    accel, speed, torque = reference_tables(model)
    if model.drive == "prescribed":
        motor = dict(name="servo", kind="prescribed", node="motor", speed=0.0, accel=[list(p) for p in accel])
    else:
        motor = dict(name="servo", kind="speed_loop", node="motor", gain=model.speed_gain,
                     reference=[list(p) for p in speed], feedforward=[list(p) for p in torque])
    return {"drive": {"title": "Timing-belt linear axis (Wojtkowiak et al. 2021, WDU axis)", "t_end": moves(model)[-1][1]},
            "node": nodes, "coupling": couplings, "motor": [motor], "load": loads,
            **({"carriage_belt": belts} if belts else {})}


def build(model: AxisModel, substitute_mass: float | None = None, stiffness: float | None = None) -> Network:
    """The network of :func:`drive_data`, built by the drive-file builder."""
    from beltcalc.sim.drivefile import DriveFile

    return DriveFile.from_data(drive_data(model, substitute_mass, stiffness), "linear axis").network()


def belt_force(model: AxisModel, torque: np.ndarray) -> np.ndarray:
    """Belt force on the carriage [N] from the belt coupling's torque at the motor [N m]."""
    return np.asarray(torque) / model.lever


def first_frequency(net: Network) -> float | None:
    """Lowest natural frequency [Hz] of a network (its prescribed nodes held); None when
    every mode is overdamped."""
    modes = net.modes()
    return modes[0][0] if modes else None


def two_mass_frequency(rotating: float, lever: float, mass: float, stiffness: float) -> float:
    r"""First natural frequency of the motor side against the carriage through the belt [Hz].

    .. math:: \omega^2 = k \left(\frac{1}{m} + \frac{(r/i)^2}{J}\right)

    (the two-mass value w^2 = C (1/J1 + 1/J2) with the carriage reflected to the motor).

    >>> round(two_mass_frequency(1e-3, 0.005, 50.0, 1e5), 3)
    10.676
    """
    return math.sqrt(stiffness * (1.0 / mass + lever ** 2 / rotating)) / (2 * math.pi)


def span_stiffness(specific_stiffness: float, center_distance: float, pulley_diameter: float,
                   position: float) -> float:
    r"""Belt stiffness at the carriage when both belt paths are counted [N/m].

    .. math:: k = \frac{C_{spec}}{L_1} + \frac{C_{spec}}{L_2}, \quad L_2 = 2 a - L_1 + \pi D / 2

    L_1 [m] the free span from the drive pulley to the carriage; L_2 the rest of the belt
    back to the drive pulley round the (free) idler. The paper uses C_spec / a for one span.

    >>> round(span_stiffness(1e6, 1.0, 0.1, 0.5) / 1e6, 4)
    2.6035
    """
    require_range("position", position, "m", 0.0, center_distance, low_open=True)
    l2 = 2 * center_distance - position + math.pi * pulley_diameter / 2
    return specific_stiffness / position + specific_stiffness / l2


def prepare(inp, belt, motors, motor, tension_inputs, thread, drive: str = "prescribed",
            speed_gain: float = 0.0, belt_model: str = "substitute", opts=None, spans: str = "paper",
            start: float | None = None, cycle: str = "one-way", shaper_zeta: float | None = None,
            shaper_at: str = "both"):
    """From the designer's data to the model: ``motor-size`` (the rigid axis, the move, the
    motor and its rigid duty) and ``tension`` (k_TB, b_TB and the pretension F_t,peak).

    ``inp``: :class:`beltcalc.design.axis_inputs.SizingInputs`; ``opts``:
    :class:`beltcalc.design.sizing.DutyOptions` of the move (S-curve ``jerk``, ``move_time``;
    None: the trapezoid; a cycle, an incline or a gearbox efficiency are not simulated);
    ``tension_inputs``: :class:`beltcalc.design.tension.TensionInputs` (its mass, width, centre
    distance and pulley diameter are taken from the axis); ``spans``, ``start`` (None: the stroke
    centred on the axis) and ``cycle`` as :class:`AxisModel`'s. A shaper in ``opts``
    (:class:`beltcalc.design.sizing.DutyOptions`) shapes each move for the model's own first
    mode where the move stops (:func:`axis_mode`; ``opts.shaper_frequency`` instead where
    given), with that mode's damping ratio or ``shaper_zeta``; ``shaper_at`` ``both``: for
    the modes where it starts and where it stops (the two shapers convolved). Returns (AxisModel,
    CycleSizing, TensionReport).
    """
    from beltcalc.design.sizing import DutyOptions

    opts = DutyOptions() if opts is None else opts
    if opts.cycle is not None or opts.incline or opts.counterweight or opts.gearbox is not None \
            or opts.gear_efficiency != 1.0 or opts.gear_efficiency_back not in (None, 1.0):
        raise InputError("the linear-axis simulation takes one horizontal move through an ideal gearbox "
                         "(no cycle, incline, counterweight or gearbox efficiency)", param="drive")
    shaping = opts.shaper
    model, sizing, report = _assemble(inp, belt, motors, motor, tension_inputs, thread,
                                      replace(opts, shaper=None, shaper_frequency=None),
                                      (drive, speed_gain, belt_model, spans, start, cycle))
    if shaping is None:
        return model, sizing, report
    # each move shaped for the mode where it stops: the move out at the end of the stroke, the
    # move back at its start (the model's own network, held there)
    modes = {x: axis_mode(model, x) for x in (model.travel, 0.0)}
    (f_out, z_out), (f_back, z_back) = modes[model.travel], modes[0.0]
    if opts.shaper_frequency is not None:
        f_out = f_back = opts.shaper_frequency
    from beltcalc.formulas.shapers import SHAPERS, convolve

    zeta = (lambda z: z) if shaper_zeta is None else (lambda z: shaper_zeta)
    out = SHAPERS[shaping](f_out, zeta(z_out))
    back = SHAPERS[shaping](f_back, zeta(z_back))
    if shaper_at == "both" and opts.shaper_frequency is None:
        # the move starts where the other stops: one shaper for each end's mode, convolved
        out, back = convolve(out, back), convolve(back, out)
    elif shaper_at not in ("end", "both"):
        raise InputError(f"{shaper_at!r}: use end (the mode where each move stops) or both (where it starts and "
                         "stops)", param="shaper_at")
    shaped_opts = replace(opts, shaper=out, shaper_frequency=None)
    back = back if cycle == "out-and-back" else None
    return _assemble(inp, belt, motors, motor, tension_inputs, thread, shaped_opts,
                     (drive, speed_gain, belt_model, spans, start, cycle), back, model)


def axis_mode(model: AxisModel, x: float) -> tuple[float, float]:
    """(frequency [Hz], damping ratio) of the axis's first mode with the carriage ``x`` [m]
    from the move's start (moving spans: held there; the paper's one span: wherever it is)."""
    from beltcalc.sim.elements.carriage_belt import held_at

    net = build(model)
    if model.spans == "moving":
        net = held_at(net, {"belt": x})
    modes = net.modes()
    if not modes:
        raise InputError("the axis has no oscillatory mode to shape the move for (overdamped)", param="shaper")
    return modes[0]


def _assemble(inp, belt, motors, motor, tension_inputs, thread, opts, layout, back_shaper=None, unshaped=None):
    """The :class:`AxisModel` of :func:`prepare` from the sizing of ``opts``; ``layout`` =
    (drive, speed_gain, belt_model, spans, start, cycle); ``back_shaper``: the move back's
    shaper, applied to the move ``unshaped`` (the model without shaping) makes."""
    from beltcalc.formulas.drive import motor_damping
    from beltcalc.formulas.shapers import shape_phases
    from beltcalc.design.sizing import size_cycle
    from beltcalc.design.tension import design_tension

    drive, speed_gain, belt_model, spans, start, cycle = layout
    sizing = size_cycle(inp, belt, motors, motor, opts)
    if sizing.shown is None:
        raise InputError(f"no motor fits ({sizing.choice.reason}); name one to simulate anyway", param="motor")
    check = sizing.shown
    move = sizing.first_move.profile
    dwell = sum(g.time for g in sizing.segments if g.kind == "dwell")
    out = tuple(ph for ph in move.phases if ph.name != "dwell")
    stop = (Phase("dwell", dwell, 0.0, 0.0),) if dwell > 0 else ()
    phases = out + stop
    if cycle == "out-and-back":
        # the move back: the move out negated (shaped for where it stops), then the dwell again
        ahead, rest = out, dwell
        if back_shaper is not None:
            plain = tuple(ph for ph in unshaped.profile.phases                # the unshaped move out
                          if not ph.name.endswith("dwell") and not ph.name.startswith("back "))
            ahead = shape_phases(plain, back_shaper)
            rest = unshaped.profile.dwell
            rest = rest - back_shaper.duration if rest >= back_shaper.duration else rest
        phases += tuple(Phase("back " + ph.name, ph.duration, -ph.speed0, -ph.accel, -ph.jerk) for ph in ahead) \
            + ((Phase("back dwell", rest, 0.0, 0.0),) if rest > 0 else ())
    profile = replace(move, dwell=dwell, phases=phases)
    # a_max of the rigidity condition [W21 eq. 11]: the largest acceleration the move reaches
    accel = max(max(abs(ph.accel), abs(ph.accel1)) for ph in phases) * sizing.axis.carriage_per_motor()
    tin = replace(tension_inputs, center_distance=inp.center_distance, width=inp.width, mass=inp.mass,
                  accel=accel, pulley_diameter=sizing.axis.pulley_diameter,
                  substitute_mass_model=inp.substitute_mass_model)
    report = design_tension(tin, belt, thread)
    eta = check.motor.efficiency if check.motor.efficiency is not None else inp.motor_efficiency
    model = AxisModel(
        axis=sizing.axis, profile=profile, duty=check.duty, motor_inertia=check.motor.J,
        motor_damping=motor_damping(eta, check.motor.T_n, check.motor.n_rated),
        stiffness=report.stiffness, damping=report.damping, belt_mass=report.belt_mass, teeth=report.teeth,
        drive=drive, speed_gain=speed_gain, belt_model=belt_model, spans=spans, center_distance=inp.center_distance,
        start=(inp.center_distance - inp.stroke) / 2 if start is None else start, cycle=cycle,
        shaped=sizing.shaped + ((ShapedBack(back_shaper),) if back_shaper is not None else ()),
    )
    model.check()
    return model, sizing, report


def move_options(values: dict):
    """The :class:`beltcalc.design.sizing.DutyOptions` of the scene's move parameters (``jerk``,
    ``move_time``, ``accel_fraction``, ``jerk_fraction``); none given: the trapezoid."""
    from beltcalc.design.sizing import DutyOptions

    given = {k: values[k] for k in ("jerk", "move_time", "accel_fraction", "jerk_fraction", "shaper",
                                    "shaper_frequency") if values.get(k) is not None}
    if given.get("shaper") == "none":
        del given["shaper"]
    with scene_values(tuple(given)):
        if "move_time" in given and "jerk" in given:
            raise InputError("move_time gives the move by its time; use jerk_fraction instead of jerk",
                             param="jerk")
        return DutyOptions(**given)


def prepare_scene(values: dict, substitute_mass_model: str = "eq7", motor: str | None = None,
                  catalog: Iterable[str] = ()):
    """:func:`prepare` from the scene's SI ``values`` (:data:`PARAMS`): the belt, thread and
    ``motor`` (default: motor-size's choice) from the built-in catalogs plus the files
    ``catalog``; m_TB by ``substitute_mass_model`` (``eq7`` or ``rayleigh``); the move by
    :func:`move_options`. Returns (AxisModel, CycleSizing, TensionReport)."""
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.design.axis_inputs import SizingInputs
    from beltcalc.design.tension import TensionInputs

    cat = load_catalog(catalog)
    inp = SizingInputs.from_values(values, substitute_mass_model)
    tin = TensionInputs(center_distance=inp.center_distance, width=inp.width, mass=inp.mass, accel=1.0,
                        tension_accel=values["tension_accel"], tension_speed=values["tension_speed"],
                        mu=values["mu"], pulley_diameter=1.0, damping=values.get("damping"))
    opts = move_options(values)
    with scene_values(("drive", "jerk", "move_time", "accel_fraction", "jerk_fraction", "spans", "start", "cycle",
                       "shaper", "shaper_frequency", "shaper_zeta", "shaper_at")):
        return prepare(inp, cat.belt(values["belt"]), list(cat.motors.values()), cat.motor(motor) if motor else None,
                       tin, cat.thread(values["thread"]), values["drive"], values["speed_gain"], values["belt_model"],
                       opts, values.get("spans") or "paper", values.get("start"), values.get("cycle") or "one-way",
                       values.get("shaper_zeta"), values.get("shaper_at") or "both")


def timing(values: dict, model: AxisModel) -> tuple[float, int]:
    """(t_end, samples) of a run: the move (out and back: to the end of the move back), then
    ``after_move``, sampled every ``step``."""
    require_positive("after_move", values["after_move"], "s")
    require_positive("step", values["step"], "s")
    t_end = moves(model)[-1][1] + values["after_move"]
    samples = int(round(t_end / values["step"])) + 1
    if samples > 10_000_000:
        raise InputError(f"{samples} samples; at most 10,000,000: raise the step", param="step")
    return t_end, samples


def scene_timing(values: dict, **options) -> tuple[float, int]:
    """:func:`timing` of the model the scene's values prepare (``options`` as :func:`prepare_scene`)."""
    return timing(values, prepare_scene(values, **options)[0])


def span_rows(model: AxisModel, values: dict) -> list[Row]:
    """First natural frequency with both belt paths counted, k = C_spec / L1 + C_spec / L2,
    the carriage at the start, middle and end of its move (moving spans: the model held
    there, :func:`axis_mode`; the paper's one span: the same network with that stiffness)."""
    a = model.center_distance
    if model.belt_model != "substitute" or not (0 < model.start + model.travel < a):
        return []
    c_spec = model.stiffness * a                       # k_TB = C_spec / a
    rows = []
    for key, label, x in (("start", "start", 0.0), ("mid", "middle", model.travel / 2), ("end", "end", model.travel)):
        k = span_stiffness(c_spec, a, model.axis.pulley_diameter, model.start + x)
        if model.spans == "moving":
            f = axis_mode(model, x)[0]
        else:
            f = first_frequency(build(replace(model, stiffness=k)))
        if f is None:
            continue
        rows.append(Row(f"first_frequency_spans_{key}", f"  with both spans, carriage at the {label}", f, "Hz",
                        note=f"k = {k / model.stiffness:.2f} k_TB"))
    return rows


def build_scene(values: dict, **options) -> Network:
    """The network of the scene's values (``options`` as :func:`prepare_scene`)."""
    return build(prepare_scene(values, **options)[0])


def run(values: dict, cfg, substitute_mass_model: str = "eq7", motor: str | None = None,
        catalog: Iterable[str] = ()) -> Outcome:
    """One run (``options`` as :func:`prepare_scene`): the belt force against the pretension
    and the first natural frequencies, the carriage's following error, residual vibration and
    settling time after each move, the motor's peak and RMS torque against motor-size's rigid
    answer."""
    from beltcalc.sim.core import simulate

    model, sizing, report = prepare_scene(values, substitute_mass_model, motor, catalog)
    net = build(model)
    t_end, samples = timing(values, model)
    result = simulate(net, t_end, samples, cfg)
    force = belt_force(model, result["T_belt"])
    result.signals["F_belt"], result.units["F_belt"] = force, "N"
    error = result["x_carriage"] - reference_position(model, result.t)
    result.signals["following_error"], result.units["following_error"] = error, "m"
    stops = stop_figures(model, result, values["settle_band"])
    pretension = report.tension_peak
    duty = model.duty
    cycle_time = model.profile.cycle_time
    torque, belt, how = extremes(net, model, result, t_end, cycle_time)
    rms = torque.rms(cycle_time)
    worst = belt.peak
    peak_note = (f"at t = {torque.peak_time:.6g} s" + (" (left limit: the end of a phase)"
                                                      if torque.peak_side == "left" else "") + how)
    f1 = first_frequency(net)
    sections = [
        Section(("belt",), "belt", [
            Row("force_max", "belt force, max", belt.max, "N"),
            Row("force_min", "belt force, min", belt.min, "N"),
            Row("pretension", "pretension F_t,peak (beltcalc tension)", pretension, "N"),
            Row("pretension_margin", "pretension - max |force|", pretension - worst, "N",
                note="< 0: the slack span goes slack (the paper's eq. 10-11 criterion)"),
            Row("stiffness", "k_TB = C_spec / a", model.stiffness, "N/m"),
            Row("damping", "b_TB", model.damping, "N*s/m"),
            Row("first_frequency", "first natural frequency", f1, "Hz",
                note="both spans, the carriage at the start" if model.spans == "moving" else "one span, k_TB"),
        ] + span_rows(model, values)),
        Section(("carriage",), "carriage", stop_rows(stops, values["settle_band"]) + shaper_rows(model)),
        *static_sections(model, values.get("static_force"), report.tension_peak),
        Section(("motor",), f"motor {sizing.shown.motor.name}", [
            Row("torque_peak", "torque, peak (dynamic)", torque.peak, "N m", note=peak_note),
            Row("torque_peak_rigid", "torque, peak (motor-size, rigid)", duty.peak_torque, "N m",
                note=f"at t = {duty.peak_time:.6g} s"),
            Row("torque_rms", "torque, RMS over the cycle (dynamic)", rms, "N m"),
            Row("torque_rms_rigid", "torque, RMS (motor-size, rigid)", duty.rms_torque, "N m"),
            Row("speed_max", "speed, max", float(np.abs(result["omega_motor"]).max()), "rad/s", "rpm"),
        ]),
    ]
    notes = [f"drive: {model.drive}; belt: {model.belt_model}"
             + (f" (eq. 1, {model.chain_units} units)" if model.belt_model == "chain" else
                f" (m_TB = {model.axis.substitute_mass * 1e3:.4g} g by {substitute_mass_model})")]
    if rms is None:
        result.warnings.append("the run ends before the cycle (move + dwell): no RMS; raise `after_move`")
    for k, stop in enumerate(stops):
        if stop.settle is None and k == len(stops) - 1:
            result.warnings.append(f"the carriage has not settled {stop.where} by {stop.until:.6g} s: raise "
                                   "`after_move`")
    m = sizing.shown.motor
    checks = [
        RULES["belt_slack"].check(worst, pretension, detail="the largest |belt force| over the run",
                                  signals=("F_belt",)),
        RULES["motor_peak_torque"].check(torque.peak, m.T_max, detail=f"dynamic, against {m.name}'s T_max",
                                         signals=("T_drive_motor",)),
        RULES["motor_rms_torque"].check(rms, m.T_n, detail=f"dynamic, over the cycle, against {m.name}'s T_n",
                                        reason="" if rms is not None else "the run ends before the cycle",
                                        signals=("T_drive_motor",)),
        RULES["motor_speed"].check(float(np.abs(result["omega_motor"]).max()), m.n_max,
                                   detail=f"against {m.name}'s n_max"),
        *settling_checks(stops, values["settle_band"], last=False),
        RULES["belt_mass"].check(model.belt_mass, model.axis.mass,
                                 detail="the belt on the span against the carriage mass it moves; a belt heavier "
                                        "than its carriage is outside the substitute model's premise (m_TB small "
                                        "beside m_WDU): check the centre distance, width and mass"),
    ]
    return Outcome(net, result, sections, notes, checks)


SCENE = Scene(
    "linear-axis", "linear_axis", PARAMS, build_scene, run, "v_carriage", "speed_gain=0.05N*m*s/rad:0.5N*m*s/rad:10",
    ("belt_force_max_N", "belt_pretension_margin_N", "carriage_following_error_max_m",
     "carriage_residual_amplitude_m", "motor_torque_peak_N_m"),
    (("belt force [N]", (("F_belt", "belt"),)),
     ("following error [mm]", (("following_error", "carriage"),)),
     ("motor torque [N m]", (("T_drive_motor", "motor"),))),
    timing=scene_timing,
)
