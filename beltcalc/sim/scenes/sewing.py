"""The sewing-machine drive of Mamatova et al. (2016) as a network: five inertias, four
spring-damper couplings with ratios, an induction motor on shaft 1, technological loads on
the main shaft (3) and the bottom shaft (5); and the scene ``simulate sewing``: its
parameters (``catalogs/scenes/sewing.toml``) and its report, the speed, acceleration and
transmitted torque of the main and bottom shafts over a steady window. SI floats only."""

from __future__ import annotations

import math
from functools import lru_cache

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.params import Param
from beltcalc.report import Row, Section
from beltcalc.sim.network import Network
from beltcalc.sim.scenes.base import TIMING, Outcome, Scene, check_timing, scene_values

NODES = ("1", "2", "3", "4", "5")
NAMES = {"1": "motor", "2": "driven-pulley rim", "3": "main shaft", "4": "toothed-pulley rim", "5": "bottom shaft"}
SHAFTS = {"main": ("3", "T_23"), "bottom": ("5", "T_45")}   # reported shaft: (node, torque it receives)

PARAMS = [Param(f"J{k}", "kg*m^2", f"inertia J{k}") for k in range(1, 6)]
PARAMS += [Param(f"C{k}", "N*m/rad", f"stiffness C{k}") for k in range(1, 5)]
PARAMS += [Param(f"d{k}", "N*m*s/rad", f"damping d{k}") for k in range(1, 5)]
PARAMS += [Param(name, "", f"ratio {name}") for name in ("U12", "U23", "U34", "U45")]
PARAMS += [
    Param("M3_amp", "N*m", "load amplitude on the main shaft"),
    Param("M3_0", "N*m", "mean load on the main shaft"),
    Param("M5_amp", "N*m", "load amplitude on the bottom shaft"),
    Param("M5_0", "N*m", "mean load on the bottom shaft"),
    Param("rated_torque", "N*m", "motor rated torque"),
    Param("breakdown_factor", "", "breakdown torque / rated torque"),
    Param("breakdown_slip", "", "breakdown slip"),
    Param("supply_frequency", "Hz", "supply frequency"),
    Param("pole_pairs", "", "motor pole pairs"),
    Param("load_frequency", "rad/s", "load frequency (0: the steady main-shaft speed)"),
] + TIMING


def check(p: dict) -> None:
    """Refuse parameter values that make no physical sense (errors name the parameter, ``scope="scene"``)."""
    with scene_values(p):
        for k in range(1, 6):
            require_positive(f"J{k}", p[f"J{k}"], "kg*m^2")
        for k in range(1, 5):
            require_range(f"C{k}", p[f"C{k}"], "N*m/rad", low=0.0)
            require_range(f"d{k}", p[f"d{k}"], "N*m*s/rad", low=0.0)
        for key in ("U12", "U23", "U34", "U45", "breakdown_factor"):
            require_positive(key, p[key], "")
        require_positive("rated_torque", p["rated_torque"], "N*m")
        require_positive("supply_frequency", p["supply_frequency"], "Hz")
        require_range("breakdown_slip", p["breakdown_slip"], "", 0.0, 1.0, low_open=True)
        require_range("load_frequency", p["load_frequency"], "rad/s", low=0.0)
        if p["pole_pairs"] < 1 or p["pole_pairs"] != int(p["pole_pairs"]):
            raise InputError(f"{p['pole_pairs']:g} is not allowed; it must be a whole number >= 1", param="pole_pairs")


def steady_speed(p: dict) -> float:
    r"""Steady speed of the main shaft [rad/s] under the mean loads.

    In steady rotation the couplings do not deflect relative to the ratios, so the motor
    carries the mean loads reflected through U12 (U23 = U34 = U45 = 1 assumed here, as
    printed): :math:`M_m = (M_{3,0} + M_{5,0}) / U_{12}`; the static characteristic of eq. 2
    gives :math:`\omega_1 = \omega_0 (1 - S_c M_m / (2 M_c))`, and :math:`\omega_3 = \omega_1 / U_{12}`.

    >>> p = dict(M3_0=0.1, M5_0=0.012, U12=1.375, U23=1.0, U34=1.0, U45=1.0, rated_torque=1.2,
    ...          breakdown_factor=2.5, breakdown_slip=0.2, supply_frequency=50.0, pole_pairs=1)
    >>> round(steady_speed(p), 3)
    227.859
    """
    ratio3 = p["U12"] * p["U23"]
    ratio5 = ratio3 * p["U34"] * p["U45"]
    torque = p["M3_0"] / ratio3 + p["M5_0"] / ratio5
    w0 = 2 * math.pi * p["supply_frequency"] / p["pole_pairs"]
    mc = p["breakdown_factor"] * p["rated_torque"]
    return w0 * (1 - p["breakdown_slip"] * torque / (2 * mc)) / ratio3


#: the scene's parameters as values of its drive file (catalogs/drives/sewing.toml)
ALIASES = {**{f"J{k}": f"{k}.inertia" for k in NODES},
           **{f"C{k}": f"{k}{k + 1}.stiffness" for k in range(1, 5)},
           **{f"d{k}": f"{k}{k + 1}.damping" for k in range(1, 5)},
           **{f"U{k}{k + 1}": f"{k}{k + 1}.ratio" for k in range(1, 5)},
           "M3_0": "M3.torque", "M3_amp": "M3.amplitude", "M5_0": "M5.torque", "M5_amp": "M5.amplitude",
           "rated_torque": "motor.rated_torque", "breakdown_factor": "motor.breakdown_factor",
           "breakdown_slip": "motor.breakdown_slip", "supply_frequency": "motor.supply",
           "pole_pairs": "motor.pole_pairs"}


def build(p: dict, angle_loads: bool = False) -> Network:
    """The network of the scene's parameters ``p`` (SI floats, keys as in sewing.toml): the
    drive file ``catalogs/drives/sewing.toml`` with the scene's values (:data:`ALIASES`),
    the loads at ``load_frequency`` (0: the steady main-shaft speed, :func:`steady_speed`).

    With ``angle_loads`` the loads follow the shaft angle, sin(phi), instead of sin(w t):
    the network is then nonlinear.
    """
    check(p)
    values = {alias: p[name] for name, alias in ALIASES.items()}
    values["motor.pole_pairs"] = int(p["pole_pairs"])
    w = 0.0 if angle_loads else (p["load_frequency"] or steady_speed(p))
    for load in ("M3", "M5"):
        values[f"{load}.frequency"] = w
        if angle_loads:
            values[f"{load}.order"] = 1.0
    return _drive_file().network(values)


@lru_cache(maxsize=1)
def _drive_file():
    """catalogs/drives/sewing.toml, read once (a sweep builds the drive at every point)."""
    from beltcalc.sim.drivefile import DriveFile, drive_path

    return DriveFile(drive_path("sewing"))


def run(values: dict, cfg, angle_loads: bool = False) -> Outcome:
    """One run: per shaft (main, bottom) the mean and amplitude of speed, acceleration and
    transmitted torque over t >= ``window``, and the motor's speed and torque."""
    from beltcalc.sim.core import simulate

    samples = check_timing(values)
    net = build(values, angle_loads)
    result = simulate(net, values["t_end"], samples, cfg)
    w0 = values["window"]
    sections = []
    for name, (node, torque) in SHAFTS.items():
        speed, accel, tq = (result.summary(s, w0) for s in (f"omega_{node}", f"accel_{node}", torque))
        sections.append(Section(("shafts", name), f"{name} shaft ({node}), t >= {w0:g} s" if name == "main"
                                else f"{name} shaft ({node})", [
            Row("speed_mean", "speed, mean", speed.mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed, amplitude", speed.amplitude, "rad/s"),
            Row("accel_amplitude", "acceleration, amplitude", accel.amplitude, "rad/s^2"),
            Row("torque_mean", "transmitted torque, mean", tq.mean, "N m"),
            Row("torque_amplitude", "transmitted torque, amplitude", tq.amplitude, "N m"),
        ]))
    speed, torque = result.summary("omega_1", w0), result.summary("M_motor", w0)
    sections.append(Section(("motor",), "motor (1)", [
        Row("speed_mean", "speed, mean", speed.mean, "rad/s", "rpm", digits=5),
        Row("torque_mean", "torque, mean", torque.mean, "N m"),
        Row("torque_amplitude", "torque, amplitude", torque.amplitude, "N m"),
    ]))
    return Outcome(net, result, sections)


SCENE = Scene(
    "sewing", "sewing", PARAMS, build, run, "omega_3", "C4=50:310:14",
    ("main_speed_amplitude_rad_per_s", "main_accel_amplitude_rad_per_s2", "main_torque_amplitude_N_m",
     "bottom_speed_amplitude_rad_per_s", "bottom_accel_amplitude_rad_per_s2", "bottom_torque_amplitude_N_m"),
    (("speed [rad/s]", (("omega_3", "main shaft"), ("omega_5", "bottom shaft"))),
     ("acceleration [rad/s^2]", (("accel_3", "main shaft"), ("accel_5", "bottom shaft"))),
     ("transmitted torque [N m]", (("T_23", "main shaft"), ("T_45", "bottom shaft")))),
)
