"""The drive-file kinds of friction that sticks: ``[[clutch]]`` (between two nodes: a
friction clutch, a torque limiter, a freewheel), ``[[brake]]`` (a clutch to the frame) and
``[[friction]]`` (a bearing's Coulomb and viscous friction on a node). Each builds one
:class:`~beltcalc.sim.elements.switched.Friction`, whose modes (stuck, slipping either way,
free) the core switches exactly [OEM99 sec. 4].

A clutch's slipping torque is ``mu F_n r_eff z`` (friction coefficient, normal force,
effective radius, friction surfaces) or a set ``torque`` (a torque limiter), switched on at
``engage`` and off at ``release``, each over ``ramp`` (linear): the capacity table the core
reads as a piecewise-linear input. The static limit is ``mu_static / mu`` (or
``static_torque / torque``) times it.

References:

[OEM99] M. Otter, H. Elmqvist, S. E. Mattsson, "Hybrid modeling in Modelica based on the
    synchronous data flow principle", Proc. IEEE CACSD (1999) 151-157: the friction
    element's modes.
"""

from __future__ import annotations

from beltcalc.data.schema import Flag, Names, Quantity, Text
from beltcalc.sim.drivefile.keys import TORQUE, Entry
from beltcalc.sim.drivefile.kinds import Kind

DAMPING = "N*m*s/rad|N*s/m"


def _schedule(b, e: Entry, torque: float) -> tuple[tuple[float, float], ...]:
    """The capacity table of a torque switched on at ``engage`` and off at ``release``, each
    over ``ramp``."""
    on, ramp, off = b.get(e, "engage", 0.0), b.get(e, "ramp", 0.0), b.get(e, "release")
    if off is not None and off < on + ramp:
        b.fail(e, "release", f"it must come after the engagement ends ({on + ramp:g} s)")
    points = [(0.0, torque)] if on == 0.0 and ramp == 0.0 else [(0.0, 0.0), (on, 0.0), (on + ramp, torque)]
    if off is not None:
        points += [(off, torque), (off + ramp, 0.0)]
    return tuple(points)


def _torques(b, e: Entry) -> tuple[float, float]:
    """(slipping torque, static over slipping) of a clutch or a brake."""
    torque, mu = b.get(e, "torque"), b.get(e, "mu")
    if (torque is None) == (mu is None):
        b.fail(e, "torque", "give the slipping torque, or mu with normal_force and radius (not both)")
    if torque is not None:
        static = b.get(e, "static_torque", torque)
        if static < torque:
            b.fail(e, "static_torque", f"it must be at least the slipping torque ({torque:g})")
        return torque, static / torque if torque > 0 else 1.0
    torque = mu * b.need(e, "normal_force") * b.need(e, "radius") * b.get(e, "surfaces", 1.0)
    mu_s = b.get(e, "mu_static", mu)
    if mu_s < mu:
        b.fail(e, "mu_static", f"it must be at least mu ({mu:g})")
    return torque, mu_s / mu if mu > 0 else 1.0


def _reported(b, e: Entry) -> None:
    """A clutch's or brake's torque in the report, against its rating where the file gives one."""
    b.torques.append((f"T_{e.name}", e.name))
    if b.get(e, "rating") is not None:
        b.limits[e.name] = (b.get(e, "rating"), "rating")


CLUTCH_KEYS = {
    "torque": Quantity(TORQUE, help="slipping torque (a torque limiter's set torque); or mu, normal_force, radius",
                       low=">=0"),
    "static_torque": Quantity(TORQUE, help="torque at which it breaks loose [default: torque]", low=">=0"),
    "mu": Quantity("", help="friction coefficient while slipping", low=">=0"),
    "mu_static": Quantity("", help="friction coefficient at rest [default: mu]", low=">=0"),
    "normal_force": Quantity("N", help="normal (clamping) force F_n when engaged", low=">=0"),
    "radius": Quantity("m", help="effective friction radius r_eff", low=">0"),
    "surfaces": Quantity("", help="friction surfaces z (torque mu F_n r_eff z) [default: 1]", low=">0"),
    "engage": Quantity("s", help="time the normal force comes on [default: 0]", low=">=0"),
    "ramp": Quantity("s", help="time it takes to come on (and off), linear [default: 0]", low=">=0"),
    "release": Quantity("s", help="time it starts to go off [default: never]", low=">=0"),
}


class ClutchKind(Kind):
    """``[[clutch]]``: a friction clutch, torque limiter or freewheel between two nodes: stuck
    while the torque it must carry stays within its static limit, slipping at its torque
    otherwise (:class:`~beltcalc.sim.elements.switched.Friction`). Outputs ``T_NAME`` (the
    torque it carries), ``w_NAME`` (slip speed) and ``mode_NAME``."""

    section = "clutch"
    node_key = "between"
    keys = {
        "name": Text(help="unique name", required=True),
        "between": Names(help="[driving node, driven node]", required=True),
        "ratio": Quantity("", help="U: the slip speed is omega_a - U omega_b", low=">0"),
        **CLUTCH_KEYS,
        "one_way": Flag(help="a freewheel: carries torque from the first node to the second only"),
        "rating": Quantity(TORQUE, help="the torque the catalog rates it for (a check on the peak)", low=">0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements.switched import Friction

        a, c = b.between(e, (2,))
        torque, static = _torques(b, e)
        b.add(Friction(e.name, a, c, _schedule(b, e, torque), static, 0.0, b.get(e, "ratio", 1.0),
                       bool(b.get(e, "one_way", False))))
        _reported(b, e)


class BrakeKind(Kind):
    """``[[brake]]``: a friction brake on a node (a clutch to the frame), applied at
    ``engage``: it slips the node down and holds it once stopped, while the torque needed
    stays within its static limit."""

    section = "brake"
    node_key = "node"
    keys = {
        "name": Text(help="unique name", required=True),
        "node": Text(help="node it brakes", required=True),
        **CLUTCH_KEYS,
        "rating": Quantity(TORQUE, help="the torque the catalog rates it for (a check on the peak)", low=">0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements.switched import Friction

        node = b.node_name(e, "node")
        torque, static = _torques(b, e)
        b.add(Friction(e.name, node, None, _schedule(b, e, torque), static))
        _reported(b, e)


class FrictionKind(Kind):
    """``[[friction]]``: a bearing's friction on a node, Coulomb plus viscous, that holds the
    node at rest until the torque on it exceeds ``static_torque`` (MSL's BearingFriction)."""

    section = "friction"
    node_key = "node"
    keys = {
        "name": Text(help="unique name", required=True),
        "node": Text(help="node it acts on", required=True),
        "torque": Quantity(TORQUE, help="Coulomb friction torque while turning", required=True, low=">=0"),
        "static_torque": Quantity(TORQUE, help="torque it holds at rest [default: torque]", low=">=0"),
        "viscous": Quantity(DAMPING, help="viscous friction (torque per speed) [default: 0]", low=">=0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements.switched import Friction

        node = b.node_name(e, "node")
        torque = b.need(e, "torque")
        static = b.get(e, "static_torque", torque)
        if static < torque:
            b.fail(e, "static_torque", f"it must be at least the Coulomb torque ({torque:g})")
        b.add(Friction(e.name, node, None, ((0.0, torque),), static / torque if torque > 0 else 1.0,
                       b.get(e, "viscous", 0.0)))
        b.torques.append((f"T_{e.name}", e.name))
