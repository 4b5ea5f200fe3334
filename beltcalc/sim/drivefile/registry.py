"""The one registry of drive-file element kinds: ``ELEMENTS`` (section -> kind class), from
which the reader, the builder, ``--set``, the writer and the docs' key tables take every
section and key. Adding a kind to drive files is one class (a
:class:`~beltcalc.sim.drivefile.kinds.Kind`: its section, keys and build) and one line here;
a kind of motor is one class and one line of
:attr:`~beltcalc.sim.drivefile.motors.MotorKind.kinds`.

The order of ``ELEMENTS`` is the order a drive is built in: nodes first (the others read
their pitch radii and add to their inertias), then each section's entries as the file lists
them.

>>> SECTIONS
('drive', 'node', 'coupling', 'shaft', 'gear', 'belt_span', 'chain_strand', 'motor', 'load', 'damper', 'clutch', 'brake', 'friction', 'backlash', 'carriage_belt')
>>> KINDS
('induction', 'prescribed', 'speed_loop', 'torque')
"""

from __future__ import annotations

from beltcalc.data.schema import Field
from beltcalc.sim.drivefile.backlash import BacklashKind
from beltcalc.sim.drivefile.carriage import CarriageBeltKind
from beltcalc.sim.drivefile.kinds import (BeltSpanKind, ChainStrandKind, CouplingKind, DamperKind, GearKind, Head, Kind,
                                          LoadKind, NodeKind, ShaftKind)
from beltcalc.sim.drivefile.motors import MotorKind
from beltcalc.sim.drivefile.switched import BrakeKind, ClutchKind, FrictionKind

#: section -> the kind of its entries, in the order a drive is built
ELEMENTS: dict[str, type[Kind]] = {kind.section: kind for kind in (
    NodeKind,
    CouplingKind,
    ShaftKind,
    GearKind,
    BeltSpanKind,
    ChainStrandKind,
    MotorKind,
    LoadKind,
    DamperKind,
    ClutchKind,
    BrakeKind,
    FrictionKind,
    BacklashKind,
    CarriageBeltKind,
)}

# Views of the registry for readers of the format (the reader and the builder ask ELEMENTS
# itself, through kind_of and sections, so a kind added to it at run time is read too):
#: every section of a drive file: ``[drive]``, then the elements' ``[[section]]``
SECTIONS: tuple[str, ...] = (Head.section, *ELEMENTS)
#: section -> its keys
KEYS: dict[str, dict[str, Field]] = {Head.section: Head.keys, **{s: kind.keys for s, kind in ELEMENTS.items()}}
#: the kinds of motor
KINDS: tuple[str, ...] = tuple(MotorKind.kinds)
#: kind of motor -> its keys (beside name, kind, node)
KIND_KEYS: dict[str, set[str]] = {name: set(kind.keys) for name, kind in MotorKind.kinds.items()}


def sections() -> tuple[str, ...]:
    """Every section a drive file may have, as ``ELEMENTS`` holds them now."""
    return (Head.section, *ELEMENTS)


def kind_of(section: str) -> type[Kind]:
    """The kind of ``section`` (``"drive"``: the head)."""
    return Head if section == Head.section else ELEMENTS[section]
