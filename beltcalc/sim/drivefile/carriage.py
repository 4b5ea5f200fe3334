"""The ``[[carriage_belt]]`` kind of drive files: a timing belt from a pulley to a carriage on a
linear axis, its spans' lengths following the carriage
(:class:`~beltcalc.sim.elements.carriage_belt.CarriageBelt`): span 1 from the pulley to the
carriage ``span + x``, the return span round the idler back ``return_span - x``, each with the
stiffness C_spec / L [W21 eq. 5] and damping b_spec / L. ``beltcalc modes DRIVE
--along-stroke N`` maps the axis's modes over the ``stroke``.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the belt's stiffness k = C_spec / L [W21 eq. 5].
"""

from __future__ import annotations

from beltcalc.data.schema import Flag, Quantity, Text
from beltcalc.errors import BeltcalcError
from beltcalc.sim.drivefile.keys import Entry
from beltcalc.sim.drivefile.kinds import BeltSpanKind, Kind


class CarriageBeltKind(Kind):
    """``[[carriage_belt]]``: a belt from a pulley to a carriage whose spans follow it."""

    section = "carriage_belt"
    keys = {
        "name": Text(help="unique name"),
        "pulley": Text(help="the drive pulley's node (its pitch circle: metres of belt a radian)", required=True),
        "carriage": Text(help="the carriage's node (a translating node, position x from its start)",
                         required=True),
        "belt": Text(help="belt profile (catalog name), for C_spec and the mass per length"),
        "width": Quantity("m", help="belt width (a catalog width), with belt", low=">0"),
        "specific_stiffness": Quantity("N", help="C_spec instead of the catalog's: k = C_spec / L per span",
                                       low=">0"),
        "span": Quantity("m", help="span 1, pulley to carriage, with the carriage at its start (x = 0)",
                         required=True, low=">0"),
        "return_span": Quantity("m", help="span 2, carriage round the idler back to the pulley, at x = 0 (none: "
                                          "span 1 only)", low=">0"),
        "stroke": Quantity("m", help="the carriage's travel from its start (negative: towards the pulley); "
                                     "the resonance map's range"),
        "pretension": Quantity("N", help="F_0: each span tension-only (none: two-way spans, forces as changes)",
                               low=">=0"),
        "specific_damping": Quantity("N*s", help="b_spec: b = b_spec / L per span; otherwise b_TB x span, b_TB "
                                                 "fitted as a belt_span's", low=">=0"),
        "moving": Flag(help="true (default): the spans follow the carriage; false: held at their lengths at x = 0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements.carriage_belt import CarriageBelt

        pulley, r = b.end_radius(e, "pulley")
        if r == 1.0 and b.node_entries[pulley].raw.get("mass") is not None:
            b.fail(e, "pulley", f"{pulley!r} is a translating node; the pulley turns (give it an inertia)")
        carriage = b.node_name(e, "carriage")
        if b.node_entries[carriage].raw.get("mass") is None:
            b.fail(e, "carriage", f"{carriage!r} turns; the carriage is a translating node (give it a mass)")
        span, back = b.need(e, "span"), b.get(e, "return_span")
        c_spec, damping = b.get(e, "specific_stiffness"), b.get(e, "specific_damping")
        w_spec = None
        if e.raw.get("belt") is not None:
            belt = b.lookup(e, "belt", "belt")
            width = b.need(e, "width")
            try:
                row = belt.width_row(width)
            except BeltcalcError as exc:
                b.fail(e, "width", exc.message)
            w_spec = row.w_spec
            if c_spec is None:
                if row.C_spec is None:
                    b.fail(e, "belt", f"{belt.name} has no C_spec for {width * 1e3:g} mm in its catalog")
                c_spec = row.C_spec
            if damping is None:
                b_tb, why = BeltSpanKind.damping(b, e, belt, width, span, pulley)
                damping = b_tb * span
                b.notes.append(f"carriage belt {e.name}: b_spec = b_TB x span = {damping:.4g} N s, b_TB {why}")
            if row.F_Tadm:
                b.limits[e.name] = (row.F_Tadm, "F_Tadm")
        if c_spec is None:
            b.fail(e, "specific_stiffness", "missing: give it, or the belt and width (the catalog's C_spec)")
        length = span + (back or 0.0)
        b.strand_mass(e, (pulley, r), (carriage, 1.0), w_spec, length)
        b.add(CarriageBelt(e.name, pulley, carriage, r, c_spec, damping or 0.0, span, back,
                           b.get(e, "pretension"), b.get(e, "stroke"), b.get(e, "moving", True)))
