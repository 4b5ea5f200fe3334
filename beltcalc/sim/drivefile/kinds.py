"""The element kinds of drive files: each declares its section, its keys (fields of the one
typed schema, :mod:`beltcalc.data.schema`: a :class:`~beltcalc.data.schema.Quantity` with its SI unit
and bounds, a :class:`~beltcalc.data.schema.Text`, ...; each with its help) and how an entry of it
builds (:meth:`Kind.build`: the elements it adds to the
:class:`~beltcalc.sim.network.Network`, and what the report follows). The motors are in
:mod:`beltcalc.sim.drivefile.motors`; the registry of them all, ``ELEMENTS``, in
:mod:`beltcalc.sim.drivefile.registry`.

A kind builds through the builder it is given (:class:`beltcalc.sim.drivefile.builder.Builder`):
``b.get(e, key, default)``, ``b.need(e, key)`` (SI values, checked, ``--set`` first),
``b.node_name``, ``b.between``, ``b.lookup`` (a catalog entry), ``b.fail(e, key, what)``, and
``b.add(element)``; its records (``notes``, ``torques``, ``limits``, ...) are the report's.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the belt's substitute spring and its damping.
[DH56] J. P. Den Hartog, Mechanical Vibrations, 4th ed., McGraw-Hill (1956): the dynamic
    vibration absorber, a mass on a spring and a damper fixed to the system it calms
    [DH56 sec. 3.2-3.3].
"""

from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path
from typing import ClassVar

from beltcalc.errors import BeltcalcError
from beltcalc.data.schema import Field, Flag, Names, Quantity, Table, Text, Whole
from beltcalc.sim.drivefile.keys import TORQUE, Entry, read_drive_toml


class Kind:
    """A section of drive files: ``section`` (``[[section]]``), its ``keys`` in the order the
    docs and ``--list-params`` show them, and :meth:`build`.

    ``node_key``: the key that names the node the entry acts on; a key of either dimension
    (``"N*m|N"``) takes the one of that node (rotating or translating).
    ``shares_node_name``: the entry may take the name of that node (a motor named after the
    node it drives)."""

    section: ClassVar[str]
    keys: ClassVar[dict[str, Field]]
    node_key: ClassVar[str] = ""
    shares_node_name: ClassVar[bool] = False

    @classmethod
    def problems(cls, e: Entry) -> list[tuple[str, str, str]]:
        """What is wrong with the entry beyond unknown and missing keys, as (where, key, what)."""
        return []

    @classmethod
    def missing(cls, e: Entry, given: set) -> list[tuple[str, str, str]]:
        """The keys the entry needs by what it is (a motor's kind) that ``given`` (its keys in
        the file and those set) lacks, as (where, key, what)."""
        return []

    @classmethod
    def build(cls, b, e: Entry) -> None:
        """Add the entry's elements to the builder ``b``."""
        raise NotImplementedError


class Head(Kind):
    """``[drive]``: the title and the timing (read by the builder's ``timing``)."""

    section = "drive"
    keys = {
        "title": Text(help="title of the report"),
        "t_end": Quantity("s", help="simulated time", required=True, low=">0"),
        "samples": Whole(help="output samples (>= 2)"),
        "window": Quantity("s", help="start of the steady window for means and amplitudes", low=">=0"),
    }


class NodeKind(Kind):
    """``[[node]]``: a rotating inertia or a translating mass, with the pitch diameter where
    strands leave it."""

    section = "node"
    keys = {
        "name": Text(help="unique name", required=True),
        "inertia": Quantity("kg*m^2", help="rotating inertia (0: massless, condensed out)", low=">=0"),
        "mass": Quantity("kg", help="a translating mass instead of an inertia", low=">=0"),
        "teeth": Whole(help="teeth of the pulley or sprocket (pitch diameter from the belt or chain)"),
        "belt": Text(help="belt profile of the pulley (catalog name), for its pitch diameter"),
        "chain": Text(help="chain of the sprocket (catalog name), for its pitch diameter"),
        "pitch_diameter": Quantity("m", help="pitch diameter where strands leave the node", low=">0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        inertia, mass = b.get(e, "inertia"), b.get(e, "mass")
        if (inertia is None) == (mass is None):
            b.fail(e, "inertia", "give exactly one of inertia (rotating) or mass (translating)")
        value = inertia if mass is None else mass
        if not (value >= 0 and math.isfinite(value)):
            b.fail(e, "inertia" if mass is None else "mass", f"{value:g} is not allowed; it must be >= 0")
        b.add_node(e.name, value, translation=mass is not None)
        d = b.get(e, "pitch_diameter")
        teeth = b.get(e, "teeth")
        if teeth is not None:
            b.teeth[e.name] = int(teeth)
        if d is None and teeth is not None:
            belt, chain = e.raw.get("belt"), e.raw.get("chain")
            if (belt is None) == (chain is None):
                b.fail(e, "teeth", "give the belt or the chain that runs on it (for the pitch diameter)")
            if belt is not None:
                from beltcalc.formulas.belt import pulley_pitch_diameter

                d = pulley_pitch_diameter(teeth, b.lookup(e, "belt", "belt").pitch)
            else:
                from beltcalc.formulas.chain import sprocket_pitch_diameter

                d = sprocket_pitch_diameter(b.lookup(e, "chain", "chain").pitch, teeth)
        if d is not None:
            if not d > 0:
                b.fail(e, "pitch_diameter", f"{d:g} m; it must be > 0 m")
            b.radius[e.name] = d / 2


class CouplingKind(Kind):
    """``[[coupling]]``: a spring-damper with a ratio (:class:`~beltcalc.sim.elements.Coupling`),
    rigid (a :class:`~beltcalc.sim.elements.Gear`), or a belt with an eccentric tension roller
    (:class:`~beltcalc.sim.elements.eccentric.EccentricBelt`)."""

    section = "coupling"
    node_key = "between"
    keys = {
        "name": Text(help="unique name"),
        "between": Names(help="[node, node] (one node: to the frame)", required=True),
        "stiffness": Quantity("N*m/rad|N/m", help="spring C", required=True, low=">=0"),
        "damping": Quantity("N*m*s/rad|N*s/m", help="damper d", low=">=0"),
        "ratio": Quantity("", help="U: the torque is C (phi_a - U phi_b) + d (omega_a - U omega_b)", low=">0"),
        "rigid": Flag(help="join the two nodes rigidly (phi_b = phi_a / U); the error of doing so is printed"),
        "eccentricity": Quantity("m", help="an eccentric tension roller on the belt's slack span: the pivot's "
                                           "offset Delta from the roller's centre (docs/eccentric_roller.md); 0: none",
                                 low=">=0"),
        "roller_radius": Quantity("m", help="the tension roller's radius r3", low=">0", when="eccentricity"),
        "pulley_radius": Quantity("m", help="pitch radius r1 of the first node's pulley (r2 = ratio x r1) "
                                            "[default: the node's pitch diameter / 2]", low=">0"),
        "center_distance": Quantity("m", help="centre distance a of the two pulleys", low=">0", when="eccentricity"),
        "pivot_x": Quantity("m", help="the roller's pivot, along the line from the first pulley to the second",
                            when="eccentricity"),
        "pivot_y": Quantity("m", help="the roller's pivot, across that line (negative: under the slack span)",
                            when="eccentricity"),
        "roller_angle": Quantity("rad", help="the eccentric's angle theta_0 when the first node's angle is 0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements import Coupling, Gear

        ends = b.between(e, (1, 2))
        C, d = b.need(e, "stiffness"), b.get(e, "damping", 0.0)
        U = b.get(e, "ratio", 1.0)
        j = ends[1] if len(ends) == 2 else None
        if b.get(e, "rigid", False) and not b.flexible:
            if j is None:
                b.fail(e, "rigid", "a rigid coupling to the frame would hold the node still; "
                                   "use a prescribed motor of speed 0")
            b.add(Gear(ends[0], j, U, name=e.name))
            b.rigid.append(e.name)
            return
        if (b.get(e, "eccentricity", 0.0) or 0.0) > 0:    # else the roller's keys change nothing
            cls.eccentric(b, e, ends, j, C, d, U)
            return
        b.add(Coupling(e.name, ends[0], j, C, d, U))
        b.torques.append((f"T_{e.name}", e.name))

    @classmethod
    def eccentric(cls, b, e: Entry, ends, j, C, d, U) -> None:
        """A belt coupling with an eccentric tension roller (:class:`~beltcalc.sim.elements.eccentric.EccentricBelt`)."""
        from beltcalc.sim.elements.beltpath import Eccentric
        from beltcalc.sim.elements.eccentric import EccentricBelt

        if j is None:
            b.fail(e, "eccentricity", "a tension roller needs a belt between two nodes")
        if b.get(e, "rigid", False):
            b.fail(e, "rigid", "a coupling with an eccentric tension roller cannot be rigid")
        r1 = b.get(e, "pulley_radius", b.radius.get(ends[0]))
        if r1 is None:
            b.fail(e, "pulley_radius", f"give it, or a pitch diameter on node {ends[0]!r}")
        geo = Eccentric(r1=r1, r2=U * r1, a=b.need(e, "center_distance"), r3=b.need(e, "roller_radius"),
                        px=b.need(e, "pivot_x"), py=b.need(e, "pivot_y"), delta=b.need(e, "eccentricity"),
                        theta0=b.get(e, "roller_angle", 0.0))
        b.add(EccentricBelt(e.name, ends[0], j, C, d, geo))
        b.torques.append((f"T_{e.name}", e.name))


class ShaftKind(Kind):
    """``[[shaft]]``: a coupling whose stiffness comes from the shaft's geometry and material,
    its own inertia half to each end node."""

    section = "shaft"
    keys = {
        "name": Text(help="unique name"),
        "between": Names(help="[node, node]", required=True),
        "diameter": Quantity("m", help="outer diameter", required=True, low=">0"),
        "bore": Quantity("m", help="bore diameter (0: solid)", low=">=0"),
        "length": Quantity("m", help="length between the nodes", required=True, low=">0"),
        "material": Text(help="material of catalogs/materials.toml (G and density)"),
        "shear_modulus": Quantity("Pa", help="G, instead of a material's", low=">0"),
        "density": Quantity("kg/m^3", help="density, for the shaft's own inertia (half to each node)", low=">=0"),
        "damping": Quantity("N*m*s/rad", help="damper d", low=">=0"),
        "damping_time": Quantity("s", help="stiffness-proportional damping d = beta C", low=">=0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.formulas.chain import torsional_stiffness
        from beltcalc.sim.elements import Coupling

        a, c = b.between(e, (2,))
        D, bore, L = b.need(e, "diameter"), b.get(e, "bore", 0.0), b.need(e, "length")
        G, rho = b.get(e, "shear_modulus"), b.get(e, "density")
        material = b.get(e, "material")
        if material is not None:
            props = materials().get(material)
            if props is None:
                b.fail(e, "material", f"{material!r} is not in catalogs/materials.toml ({', '.join(materials())})")
            G = props["shear_modulus"] if G is None else G
            rho = props["density"] if rho is None else rho
        if G is None:
            b.fail(e, "shear_modulus", "give the material or the shear modulus")
        C = torsional_stiffness(D, bore, L, G)
        beta = b.get(e, "damping_time")
        d = b.get(e, "damping", 0.0) if beta is None else beta * C
        b.add(Coupling(e.name, a, c, C, d))
        b.torques.append((f"T_{e.name}", e.name))
        if rho:
            from beltcalc.formulas.drive import cylinder_inertia

            J = cylinder_inertia(D, bore, L, rho)
            for node in (a, c):
                b.inertia[node] += J / 2
            b.notes.append(f"shaft {e.name}: C = {C:.5g} N m/rad; its own inertia {J:.4g} kg m^2, half to "
                           f"{a} and half to {c}")


def materials() -> dict:
    """catalogs/materials.toml: {name: {"shear_modulus": Pa, "density": kg/m^3}} (shared:
    read only)."""
    from beltcalc.data.catalogs import builtin_dir

    return material_table(str(builtin_dir() / "materials.toml"))


@lru_cache(maxsize=2)
def material_table(path: str) -> dict:
    """The material table at ``path`` in SI floats, read and converted once per process."""
    from beltcalc.units import parse_quantity

    data = read_drive_toml(Path(path))
    out = {}
    for name, props in data.get("materials", {}).items():
        out[name] = {"shear_modulus": parse_quantity(props["shear_modulus"], "Pa"),
                     "density": parse_quantity(props["density"], "kg/m^3")}
    return out


class GearKind(Kind):
    """``[[gear]]``: a rigid gear pair (:class:`~beltcalc.sim.elements.Gear`): one coordinate."""

    section = "gear"
    keys = {
        "name": Text(help="unique name"),
        "between": Names(help="[node a, node b]", required=True),
        "ratio": Quantity("", help="speed of a / speed of b (phi_b = phi_a / ratio; negative: the pair reverses, "
                                   "as an external gear pair does)", required=True, low="!=0",
                          hint="negative: the pair turns the other way"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements import Gear

        a, c = b.between(e, (2,))
        b.add(Gear(a, c, b.need(e, "ratio"), name=e.name))


class BeltSpanKind(Kind):
    """``[[belt_span]]``: a tension-only span of a catalog belt (:class:`~beltcalc.sim.elements.Strand`),
    or a two-way spring (``tension_only = false``)."""

    section = "belt_span"
    keys = {
        "name": Text(help="unique name"),
        "from": Text(help="node it leaves (its pitch circle, or a translating node)", required=True),
        "to": Text(help="node it reaches", required=True),
        "belt": Text(help="belt profile (catalog name)", required=True),
        "width": Quantity("m", help="belt width (a catalog width)", required=True, low=">0"),
        "length": Quantity("m", help="free span length", required=True, low=">0"),
        "pretension": Quantity("N", help="pretension F_0", low=">=0"),
        "damping": Quantity("N*s/m", help="b; otherwise fitted to the catalog's F_tspec(n) as `beltcalc tension` does",
                            low=">=0"),
        "tension_only": Flag(help="true (default): the span goes slack; false: a two-way spring"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.formulas import belt as bm
        from beltcalc.sim.elements import Coupling, Strand

        (i, r_i), (j, r_j) = b.end_radius(e, "from"), b.end_radius(e, "to")
        belt = b.lookup(e, "belt", "belt")
        width, length = b.need(e, "width"), b.need(e, "length")
        try:
            row = belt.width_row(width)
        except BeltcalcError as exc:
            b.fail(e, "width", exc.message)
        if row.C_spec is None:
            b.fail(e, "belt", f"{belt.name} has no C_spec for {width * 1e3:g} mm in its catalog")
        k = bm.belt_stiffness(row.C_spec, length)
        damping = b.get(e, "damping")
        if damping is None:
            damping, why = cls.damping(b, e, belt, width, length, i if r_i != 1.0 else j)
            b.notes.append(f"belt span {e.name}: k = C_spec / L = {k:.5g} N/m, b = {damping:.4g} N s/m {why}")
        F0 = b.get(e, "pretension", 0.0)
        b.strand_mass(e, (i, r_i), (j, r_j), row.w_spec, length)
        if row.F_Tadm:
            b.limits[e.name] = (row.F_Tadm, "F_Tadm")
        if not b.get(e, "tension_only", True):
            # one two-way spring k = C_spec / L (the substitute model, [W21 eq. 5]):
            # C (phi_i - U phi_j) with C = k r_i^2, U = r_j / r_i: the torque r_i F
            b.add(Coupling(e.name, i, j, k * r_i ** 2, damping * r_i ** 2, r_j / r_i))
            b.spans[e.name] = r_i
            return
        b.add(Strand(e.name, i, j, r_i, r_j, k, damping, F0))

    @classmethod
    def damping(cls, b, e: Entry, belt, width: float, length: float, pulley: str) -> tuple[float, str]:
        """b_TB as `beltcalc tension` finds it: fitted to F_tspec(n) on the pulley the span
        leaves ([W21 sec. 3.2]), or the catalog's value."""
        from beltcalc.formulas import belt as bm

        if belt.F_tspec and pulley in b.radius:
            D = 2 * b.radius[pulley]
            z = max(1, round(math.pi * D / belt.pitch))
            z_e = bm.teeth_in_mesh(z, z, belt.pitch, length, belt.z_e_max)
            fit = bm.damping_from_tooth_load(belt.F_tspec, D, width, z_e)
            how = f"fitted to the catalog's F_tspec(n) on {pulley}, D = {D * 1e3:.4g} mm, z_e = {z_e:g}"
            b.fits[e.name] = (fit.r_squared, how)
            return fit.damping, f"({how}, R^2 = {fit.r_squared:.3f})"
        if belt.damping is not None:
            return belt.damping, f"(catalog value: {belt.damping_source or belt.source})"
        b.fail(e, "damping", f"{belt.name} has no F_tspec(n) table and no damping value; give damping")


class ChainStrandKind(Kind):
    """``[[chain_strand]]``: a tension-only strand of a catalog chain (:class:`~beltcalc.sim.elements.Strand`)."""

    section = "chain_strand"
    keys = {
        "name": Text(help="unique name"),
        "from": Text(help="node (sprocket) it leaves", required=True),
        "to": Text(help="node (sprocket) it reaches", required=True),
        "chain": Text(help="chain (catalogs/chains.toml name, e.g. 10B-1)", required=True),
        "length": Quantity("m", help="free strand length", required=True, low=">0"),
        "pretension": Quantity("N", help="pretension F_0", low=">=0"),
        "stiffness": Quantity("N", help="EA: the force per unit strain (chains publish none: the file must say)",
                              required=True, low=">0"),
        "mass": Quantity("kg/m", help="mass per length, instead of the catalog's", low=">=0"),
        "breaking_load": Quantity("N", help="breaking load, instead of the catalog's", low=">0"),
        "allowable_dynamic_load": Quantity("N", help="the maker's allowable dynamic (fatigue) load, instead of the "
                                                     "catalog's (a chain without one: its fatigue check unverified)",
                                           low=">0"),
        "damping": Quantity("N*s/m", help="b", low=">=0"),
        "damping_time": Quantity("s", help="stiffness-proportional damping b = beta c", low=">=0"),
        "polygon": Flag(help="true: the strand's length follows the sprockets' tooth polygons (the polygon action; "
                             "both nodes need teeth); false (default): round sprockets of the pitch diameter"),
        "phase_from": Quantity("rad", help="with polygon: the seated roller's angle past the strand's tangent point "
                                           "on the `from` sprocket at rest (default 0)"),
        "phase_to": Quantity("rad", help="with polygon: the same on the `to` sprocket (default: the span's fraction "
                                         "of a pitch, as that fraction of a tooth)"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.formulas.chain import strand_stiffness
        from beltcalc.formulas.fatigue import StrandFatigue
        from beltcalc.sim.elements import Strand

        (i, r_i), (j, r_j) = b.end_radius(e, "from"), b.end_radius(e, "to")
        chain = b.lookup(e, "chain", "chain")
        length = b.need(e, "length")
        c = strand_stiffness(b.need(e, "stiffness"), length)
        beta = b.get(e, "damping_time")
        damping = b.get(e, "damping", 0.0) if beta is None else beta * c
        b.lengths[e.name] = length
        if b.get(e, "polygon", False):
            b.add(cls.polygon(b, e, chain, (i, r_i), (j, r_j), length, c, damping))
        else:
            for key in ("phase_from", "phase_to"):
                if e.raw.get(key) is not None:
                    b.fail(e, key, "a phase needs polygon = true")
            b.add(Strand(e.name, i, j, r_i, r_j, c, damping, b.get(e, "pretension", 0.0)))
        b.limits[e.name] = (b.get(e, "breaking_load", chain.breaking_load), "breaking load")
        own = b.get(e, "allowable_dynamic_load")
        b.fatigue[e.name] = StrandFatigue(chain.name, own if own is not None else chain.allowable_dynamic_load,
                                          "the drive's `allowable_dynamic_load`" if own is not None else
                                          "catalogs/chains.toml" if chain.allowable_dynamic_load is not None else
                                          f"none published for {chain.name} in catalogs/chains.toml")
        b.strand_mass(e, (i, r_i), (j, r_j), b.get(e, "mass", chain.mass), length)

    @staticmethod
    def polygon(b, e: Entry, chain, end_i, end_j, length: float, c: float, damping: float):
        """The strand with the polygon action (:class:`~beltcalc.sim.elements.polygon.PolygonStrand`):
        each end's sprocket by its teeth on this strand's chain (its pitch radius must be that
        chain's on those teeth)."""
        from beltcalc.formulas.chain import sprocket_pitch_diameter
        from beltcalc.sim.elements.polygon import PolygonStrand

        teeth = []
        for key, (node, r) in (("from", end_i), ("to", end_j)):
            raw = b.node_entries[node].raw
            z = raw.get("teeth")
            if z is None or raw.get("mass") is not None:
                b.fail(e, "polygon", f"the polygon action needs the sprocket's teeth: give node {node!r} teeth "
                                     f"and chain")
            d = sprocket_pitch_diameter(chain.pitch, int(z))
            if abs(d / 2 - r) > 1e-9 * d:
                b.fail(e, "polygon", f"node {node!r} has a pitch diameter of {2 * r * 1e3:.6g} mm, not that of "
                                     f"{int(z)} teeth on {chain.name} ({d * 1e3:.6g} mm): give it chain = "
                                     f"\"{chain.name}\"")
            teeth.append(int(z))
        return PolygonStrand(e.name, end_i[0], end_j[0], chain.pitch, teeth[0], teeth[1], length, c, damping,
                             b.get(e, "pretension", 0.0), b.get(e, "phase_from"), b.get(e, "phase_to"))


class LoadKind(Kind):
    """``[[load]]``: a load torque (:class:`~beltcalc.sim.elements.Load`): constant, a sine in
    time or in the node's angle, a table."""

    section = "load"
    node_key = "node"
    keys = {
        "name": Text(help="unique name"),
        "node": Text(help="node it acts on", required=True),
        "torque": Quantity(TORQUE, help="constant part, against the motion"),
        "amplitude": Quantity(TORQUE, help="amplitude of the sine"),
        "frequency": Quantity("rad/s|Hz", help="frequency of the sine in time", low=">=0"),
        "order": Quantity("", help="instead of frequency: the sine locked to the node's angle, sin(order phi)",
                          low=">0"),
        "phase": Quantity("rad", help="phase of the sine"),
        "start": Quantity("s", help="the sine acts from here on (torque from 0; a later step: table)", low=">=0"),
        "table": Table(columns=(Quantity("s"), Quantity(TORQUE)), help="tabulated part [[t, torque], ...]"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements import Load

        node = b.node_name(e, "node")
        freq = b.get_unit(e, "frequency")
        omega = 0.0
        if freq[0] is not None:
            omega = freq[0] * (2 * math.pi if freq[1] == "Hz" else 1.0)
        order = b.get(e, "order")
        if order is not None and freq[0]:
            b.fail(e, "order", "give frequency (in time) or order (in the shaft angle), not both")
        b.add(Load(node, b.get(e, "torque", 0.0), b.get(e, "amplitude", 0.0), omega, b.get(e, "phase", 0.0),
                   in_angle=order is not None, table=tuple(b.get(e, "table", ())), start=b.get(e, "start", 0.0),
                   order=1.0 if order is None else order))


class DamperKind(Kind):
    """``[[damper]]``: a torsional vibration damper on a node [DH56 sec. 3.2-3.3]: a ring of
    inertia J_d joined to the node by a spring k_d and a damper c_d (a tuned absorber; k_d = 0:
    a viscous, Houdaille, damper). It is a node of its own, named after the entry
    (``omega_NAME``), and a coupling ``NAME_spring`` (``T_NAME_spring``): nothing the core
    does not already propagate exactly."""

    section = "damper"
    node_key = "node"
    keys = {
        "name": Text(help="unique name: the ring's node", required=True),
        "node": Text(help="node the damper is fixed to", required=True),
        "inertia": Quantity("kg*m^2", help="the ring's inertia J_d", required=True, low=">0"),
        "stiffness": Quantity("N*m/rad", help="spring k_d between node and ring (0: a viscous damper)", low=">=0"),
        "damping": Quantity("N*m*s/rad", help="damper c_d between node and ring", low=">=0"),
    }

    @classmethod
    def build(cls, b, e: Entry) -> None:
        from beltcalc.sim.elements import Coupling

        node = b.node_name(e, "node")          # (the reader refuses a name another entry has)
        k, c = b.get(e, "stiffness", 0.0), b.get(e, "damping", 0.0)
        if k == 0.0 and c == 0.0:
            b.fail(e, "damping", "give a stiffness or a damping (with neither, the ring turns free)")
        b.add_node(e.name, b.need(e, "inertia"))
        b.add(Coupling(f"{e.name}_spring", node, e.name, k, c, 1.0))
        b.torques.append((f"T_{e.name}_spring", f"{e.name}_spring"))
