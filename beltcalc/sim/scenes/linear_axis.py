"""A timing-belt linear axis as a dynamic model (Wojtkowiak et al. 2021): the motor side
(motor rotor, gearbox, coupling, pulleys: one inertia at the motor shaft) joined to the
carriage by the belt, either as the substitute spring-damper-mass of eq. 5-9 (k_TB, b_TB,
m_TB) or as the paper's eq. 1 chain of z - 1 mass-spring-damper units in series. External
resistance F_R and guide friction act against the move; the motor either follows the
motion profile exactly (an ideal servo, ``prescribed``) or is driven by the rigid
feed-forward torque of ``motor-size`` plus a proportional speed loop (``speed-loop``).
SI floats only.

Belt force: F = k_TB (r phi / i - x) + b_TB (r omega / i - v), r = D / 2, positive when the
belt pulls the carriage forward. The carriage runs in +x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.drive import BeltAxis, Duty
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.profiles import Trapezoid
from beltcalc.sim.network import Coupling, Inertia, Load, Network, Prescribed, SpeedLoop

DRIVES = ("prescribed", "speed-loop")
BELT_MODELS = ("substitute", "chain")


@dataclass(frozen=True)
class AxisModel:
    """What the dynamic model needs, SI: the rigid axis and its motion (from ``motor-size``),
    the motor, the belt's substitute parameters (from ``tension``), and the drive."""

    axis: BeltAxis
    profile: Trapezoid          # at the motor shaft
    duty: Duty                  # the rigid answer of motor-size for this motor
    motor_inertia: float        # kg m^2
    motor_damping: float        # N m s/rad, b_M
    stiffness: float            # N/m, k_TB
    damping: float              # N s/m, b_TB
    belt_mass: float            # kg, the belt on the span (for the chain model)
    teeth: float                # teeth on the span z
    drive: str = "prescribed"
    speed_gain: float = 0.0     # N m s/rad
    belt_model: str = "substitute"

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
        """Mass-spring-damper units of the eq. 1 chain: the whole pitches on the span, z - 1
        rounded down (124 for the WDU axis, z = 125.5)."""
        return max(1, int(math.floor(self.teeth - 1 + 1e-9)))

    def check(self) -> None:
        if self.drive not in DRIVES:
            raise InputError(f"{self.drive!r} is not a drive; use one of {', '.join(DRIVES)}", param="--set drive")
        if self.belt_model not in BELT_MODELS:
            raise InputError(f"{self.belt_model!r} is not a belt model; use one of {', '.join(BELT_MODELS)}",
                             param="--set belt_model")
        require_positive("--set stiffness", self.stiffness, "N/m")
        require_range("--set damping", self.damping, "N*s/m", low=0.0)
        require_range("--set speed_gain", self.speed_gain, "N*m*s/rad", low=0.0)


def reference_tables(model: AxisModel) -> tuple[tuple, tuple, tuple]:
    """(acceleration, speed, feed-forward torque) of the move at the motor shaft as
    piecewise-linear tables (t, value): the profile's phases and the rigid duty's torque."""
    accel, speed, torque = [], [], []
    t = 0.0
    for ph, dt in zip(model.profile.phases, model.duty.phases):
        accel += [(t, ph.accel), (t + ph.duration, ph.accel)]
        speed += [(t, ph.speed0), (t + ph.duration, ph.speed1)]
        torque += [(t, dt.torque0), (t + dt.duration, dt.torque1)]
        t += ph.duration
    accel.append((t, 0.0))
    torque.append((t, 0.0))
    return tuple(accel), tuple(speed), tuple(torque)


def move_time(model: AxisModel) -> float:
    """End of the move (before the dwell) [s]."""
    return sum(ph.duration for ph in model.profile.phases if ph.name != "dwell")


def reference_position(model: AxisModel, t: np.ndarray) -> np.ndarray:
    """The carriage position the profile commands [m], exact per phase."""
    t = np.asarray(t, dtype=float)
    out = np.zeros_like(t)
    start, angle = 0.0, 0.0
    for ph in model.profile.phases:
        tau = np.clip(t - start, 0.0, ph.duration)
        inside = t >= start
        out = np.where(inside, angle + ph.speed0 * tau + 0.5 * ph.accel * tau ** 2, out)
        start += ph.duration
        angle += ph.angle
    return out * model.lever


def build(model: AxisModel, substitute_mass: float | None = None, stiffness: float | None = None) -> Network:
    """The network: the motor side, the belt (substitute or chain), the carriage.

    ``substitute_mass`` / ``stiffness`` override m_TB / k_TB (the model comparisons)."""
    model.check()
    ax, lever = model.axis, model.lever
    k = model.stiffness if stiffness is None else stiffness
    b = model.damping
    nodes = [Inertia("motor", model.rotating_inertia)]
    couplings = [Coupling("bearings", "motor", None, 0.0, model.rotating_damping)]
    if model.belt_model == "substitute":
        m_tb = ax.substitute_mass if substitute_mass is None else substitute_mass
        nodes.append(Inertia("carriage", ax.mass + m_tb, translation=True))
        # C (phi - U x) with C = k lever^2, U = 1 / lever: the torque lever * F
        couplings.append(Coupling("belt", "motor", "carriage", k * lever ** 2, b * lever ** 2, 1.0 / lever))
    else:
        n = model.chain_units
        unit_mass = model.belt_mass / n
        kk, bb = n * k, n * b                 # eq. 8-9: k' = (z - 1) k_TB, b' = (z - 1) b_TB
        names = [f"tooth{j}" for j in range(2, n + 1)] + ["carriage"]
        for name in names[:-1]:
            nodes.append(Inertia(name, unit_mass, translation=True))
        nodes.append(Inertia("carriage", ax.mass + unit_mass, translation=True))
        couplings.append(Coupling("belt", "motor", names[0], kk * lever ** 2, bb * lever ** 2, 1.0 / lever))
        for a, c in zip(names, names[1:]):
            couplings.append(Coupling(f"belt_{a}", a, c, kk, bb))
    if ax.guide_damping:
        couplings.append(Coupling("guide", "carriage", None, 0.0, ax.guide_damping))
    t_move = move_time(model)
    resist = ax.resistance_torque / lever       # F_R + mu m g, against the move
    loads = [Load("carriage", table=((0.0, resist), (t_move, resist), (t_move, 0.0)))] if resist else []
    accel, speed, torque = reference_tables(model)
    if model.drive == "prescribed":
        return Network(nodes, couplings, loads, prescribed=[Prescribed("motor", 0.0, accel)])
    loop = SpeedLoop("motor", model.speed_gain, speed, torque)
    return Network(nodes, couplings, loads, speed_loops=[loop])


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
            speed_gain: float = 0.0, belt_model: str = "substitute"):
    """From the designer's data to the model: ``motor-size`` (the rigid axis, the move, the
    motor and its rigid duty) and ``tension`` (k_TB, b_TB and the pretension F_t,peak).

    ``inp``: :class:`beltcalc.sizing.SizingInputs`; ``tension_inputs``:
    :class:`beltcalc.tension.TensionInputs` (its mass, width, centre distance and pulley
    diameter are taken from the axis). Returns (AxisModel, Sizing, TensionReport).
    """
    from dataclasses import replace

    from beltcalc.drive import motor_damping
    from beltcalc.sizing import size_axis
    from beltcalc.tension import design_tension

    sizing = size_axis(inp, belt, motors, motor)
    if sizing.shown is None:
        raise InputError(f"no motor fits ({sizing.choice.reason}); name one with --motor to simulate anyway",
                         param="motor")
    check = sizing.shown
    accel = sizing.profile.accel * sizing.axis.carriage_per_motor()
    tin = replace(tension_inputs, center_distance=inp.center_distance, width=inp.width, mass=inp.mass,
                  accel=accel, pulley_diameter=sizing.axis.pulley_diameter,
                  substitute_mass_model=inp.substitute_mass_model)
    report = design_tension(tin, belt, thread)
    eta = check.motor.efficiency if check.motor.efficiency is not None else inp.motor_efficiency
    model = AxisModel(
        axis=sizing.axis, profile=sizing.profile, duty=check.duty, motor_inertia=check.motor.J,
        motor_damping=motor_damping(eta, check.motor.T_n, check.motor.n_rated),
        stiffness=report.stiffness, damping=report.damping, belt_mass=report.belt_mass, teeth=report.teeth,
        drive=drive, speed_gain=speed_gain, belt_model=belt_model,
    )
    model.check()
    return model, sizing, report
