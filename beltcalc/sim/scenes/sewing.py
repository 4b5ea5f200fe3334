"""The sewing-machine drive of Mamatova et al. (2016) as a network: five inertias, four
spring-damper couplings with ratios, an induction motor on shaft 1, technological loads on
the main shaft (3) and the bottom shaft (5). SI floats only."""

from __future__ import annotations

import math

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.sim.network import Coupling, Inertia, InductionMotor, Load, Network

NODES = ("1", "2", "3", "4", "5")
NAMES = {"1": "motor", "2": "driven-pulley rim", "3": "main shaft", "4": "toothed-pulley rim", "5": "bottom shaft"}


def check(p: dict) -> None:
    """Refuse parameter values that make no physical sense, naming them as ``--set NAME``."""
    def name(key):
        return f"--set {key}"

    for k in range(1, 6):
        require_positive(name(f"J{k}"), p[f"J{k}"], "kg*m^2")
    for k in range(1, 5):
        require_range(name(f"C{k}"), p[f"C{k}"], "N*m/rad", low=0.0)
        require_range(name(f"d{k}"), p[f"d{k}"], "N*m*s/rad", low=0.0)
    for key in ("U12", "U23", "U34", "U45", "breakdown_factor"):
        require_positive(name(key), p[key], "")
    require_positive(name("rated_torque"), p["rated_torque"], "N*m")
    require_positive(name("supply_frequency"), p["supply_frequency"], "Hz")
    require_range(name("breakdown_slip"), p["breakdown_slip"], "", 0.0, 1.0, low_open=True)
    require_range(name("load_frequency"), p["load_frequency"], "rad/s", low=0.0)
    if p["pole_pairs"] < 1 or p["pole_pairs"] != int(p["pole_pairs"]):
        raise InputError(f"{p['pole_pairs']:g} is not allowed; it must be a whole number >= 1",
                         param=name("pole_pairs"))


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


def build(p: dict, angle_loads: bool = False) -> Network:
    """The network of the scene's parameters ``p`` (SI floats, keys as in sewing.toml).

    With ``angle_loads`` the loads follow the shaft angle, sin(phi), instead of sin(w t):
    the network is then nonlinear.
    """
    check(p)
    nodes = [Inertia(k, p[f"J{k}"]) for k in NODES]
    ratios = [p["U12"], p["U23"], p["U34"], p["U45"]]
    couplings = [Coupling(f"{k}{k + 1}", str(k), str(k + 1), p[f"C{k}"], p[f"d{k}"], ratios[k - 1])
                 for k in range(1, 5)]
    w = p["load_frequency"] or steady_speed(p)
    loads = [
        Load("3", p["M3_0"], p["M3_amp"], 0.0 if angle_loads else w, in_angle=angle_loads),
        Load("5", p["M5_0"], p["M5_amp"], 0.0 if angle_loads else w, in_angle=angle_loads),
    ]
    motor = InductionMotor("1", p["breakdown_factor"] * p["rated_torque"], p["breakdown_slip"],
                           2 * math.pi * p["supply_frequency"] / p["pole_pairs"],
                           2 * math.pi * p["supply_frequency"])
    return Network(nodes, couplings, loads, motor)
