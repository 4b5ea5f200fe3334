"""The ``[[backlash]]`` kind of drive files: a coupling with a dead band [MSL ElastoBacklash2]
(:class:`~beltcalc.sim.elements.backlash.Backlash`): no torque while the relative angle
``phi_a - U phi_b`` is inside the play ``-b/2 .. b/2``, a contact spring and damper beyond
it that only push. Its two contacts are switched exactly by the core, as tension-only
strands are; the drive report gives the torque ``T_<name>``, its peak, the time in contact
on each side and the number of contacts made (:func:`beltcalc.sim.scenes.drive.backlash_sections`).

References:

[MSL] Modelica Association, Modelica Standard Library 4.0.0 (2020),
    Modelica.Mechanics.Rotational.Components.ElastoBacklash2: backlash in series with a
    linear spring and damper, no pulling torque.
"""

from __future__ import annotations

from beltcalc.data.schema import Names, Quantity, Text
from beltcalc.sim.drivefile.keys import Entry
from beltcalc.sim.drivefile.kinds import Kind


class BacklashKind(Kind):
    """``[[backlash]]``: play ``backlash`` between two nodes (one: a stop on the frame), contact
    stiffness and damping, a ratio as a coupling's [MSL ElastoBacklash2]."""

    section = "backlash"
    node_key = "between"
    keys = {
        "name": Text(help="unique name (its two sides are this name with + and -)"),
        "between": Names(help="[node, node] (one node: a stop on the frame)", required=True),
        "backlash": Quantity("rad|m", help="total play b: no torque while -b/2 <= phi_a - U phi_b <= b/2",
                             required=True, low=">=0"),
        "stiffness": Quantity("N*m/rad|N/m", help="contact spring c", required=True, low=">0"),
        "damping": Quantity("N*m*s/rad|N*s/m", help="contact damper d (the torque jumps to d omega_rel at a "
                                                    "contact; a contact cannot pull)", low=">=0"),
        "ratio": Quantity("", help="U: beyond the play the torque is c (phi_a - U phi_b -+ b/2) + d (omega_a - "
                                   "U omega_b)", low=">0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements.backlash import Backlash

        ends = b.between(e, (1, 2))
        j = ends[1] if len(ends) == 2 else None
        bl = Backlash(e.name, ends[0], j, b.need(e, "backlash"), b.need(e, "stiffness"), b.get(e, "damping", 0.0),
                      b.get(e, "ratio", 1.0))
        for element in bl.elements():
            b.add(element)
