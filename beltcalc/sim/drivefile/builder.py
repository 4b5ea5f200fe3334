"""The builder of a drive file: it hands each entry to its kind (``ELEMENTS``) with the values
read once by their keys' fields (:mod:`beltcalc.data.schema`) to SI floats (``--set`` values
first, each checked against its key's bounds), and collects the nodes, the elements and what
the report follows (notes, torques, strand limits, belt fits, motor signals, the inputs
used).

References:

[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": a strand's
    mass lumped into the sprockets it joins.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache

from beltcalc.errors import BeltcalcError, InputError, did_you_mean
from beltcalc.data.schema import SI_TEXTS, TEXTS, Context, Quantity
from beltcalc.sim.drivefile.keys import Entry
from beltcalc.sim.drivefile.registry import ELEMENTS, kind_of

_MISSING = object()          # a key the file does not give


@lru_cache(maxsize=1)
def builtin_catalog():
    """The built-in catalogs, read once per process (a sweep builds its drive many times)."""
    from beltcalc.data.catalogs import load_catalog

    return load_catalog()


def few(names: list[str], shown: int = 6) -> str:
    """``a, b, c`` or ``a, b, ... and 12 more``.

    >>> few(list("abcdefgh"))
    'a, b, c, d, e, f and 2 more'
    """
    if len(names) <= shown:
        return ", ".join(names)
    return ", ".join(names[:shown]) + f" and {len(names) - shown} more"


class Builder:
    """Turns the entries of a :class:`~beltcalc.sim.drivefile.reader.DriveFile` into nodes and
    elements, converting each value once (SI floats). ``flexible`` keeps rigid couplings
    elastic (to say what making them rigid costs)."""

    def __init__(self, drive_file, values: dict, catalog, flexible: bool = False):
        self.f, self.values, self.flexible = drive_file, values, flexible
        self._catalog = catalog
        self.current = "drive"
        self.notes: list[str] = []
        self.torques: list[tuple[str, str]] = []
        self.spans: dict[str, float] = {}
        self.limits: dict[str, tuple[float, str]] = {}
        self.fatigue: dict = {}                  # chain strand -> beltcalc.formulas.fatigue.StrandFatigue
        self.fits: dict[str, tuple[float, str]] = {}   # belt span -> (R^2, the fit), as `tension` checks it
        self.motor_signals: list[tuple[str, str]] = []
        self.rigid: list[str] = []
        self.used: dict = {}
        self.weighed: list[str] = []            # strands whose mass went to their end nodes
        self.unweighed: list[str] = []          # strands whose catalog has no mass
        self.node_entries = {e.name: e for e in drive_file.entries if e.section == "node"}
        self.nodes: list[tuple[str, bool]] = []  # (name, translating) of every node, in order
        self.elements: list = []
        self.inertia: dict[str, float] = {}      # node -> its inertia, with the shares of shafts and strands
        self.radius: dict[str, float] = {}       # node -> pitch radius where strands leave it
        self.teeth: dict[str, int] = {}          # node -> teeth of its sprocket or toothed pulley
        self.lengths: dict[str, float] = {}      # chain strand -> its free length [m]

    @property
    def catalog(self):
        if self._catalog is None:
            self._catalog = builtin_catalog()
        return self._catalog

    # --- what the kinds call ----------------------------------------------------------------
    def add(self, element) -> None:
        """Add an element (:class:`~beltcalc.sim.elements.Element`) to the network."""
        self.elements.append(element)

    def add_node(self, name: str, value: float, translation: bool = False) -> None:
        """Add a node of inertia [kg m^2] (mass [kg] if ``translation``) ``value``; shafts and
        strands add their shares to it (``inertia``)."""
        self.nodes.append((name, translation))
        self.inertia[name] = value

    def fail(self, e: Entry, key: str, message: str):
        """Raise the one-line error of the file about ``key`` of entry ``e``."""
        self.f.fail(e.where, key, message)

    # --- values ---------------------------------------------------------------------------
    def get(self, e: Entry, key: str, default=None):
        """The SI value of ``key`` of entry ``e`` (an override first), or ``default``; a
        value out of its key's range is refused, naming the file's element and key (or the
        address, when the value was set). What the file itself gives (its field, in the unit
        of the node it acts on; its address and checked value) is worked out on the first
        build and kept on the drive file: a study builds the drive thousands of times with a
        few values changed."""
        hit = self.f.file_values.get((id(e), key))
        if hit is None:
            spec = self.f.field_of(e, key)
            value = _MISSING
            if key in e.raw:
                try:           # (a FieldError is a ValueError; its bounds are checked too)
                    value = spec.read(e.raw[key], self.context())
                except (ValueError, TypeError) as exc:
                    self.f.fail(e.where, key, str(exc))
            hit = self.f.file_values[(id(e), key)] = (spec, key if e.section == "drive" else f"{e.name}.{key}", value)
        spec, address, value = hit
        if address in self.values:
            value = self.values[address]
            value = value[0] if isinstance(value, tuple) else value
            self.used[address] = (value, "set")
            problem = spec.bound_problem(value, spec.unit) if isinstance(spec, Quantity) else ""
            if problem:
                raise InputError(problem, param=address, scope="scene")
            return value
        if value is _MISSING:
            return default
        if spec.scalar:
            self.used[address] = (value, "file")
        return value

    def get_unit(self, e: Entry, key: str):
        """(SI value, unit) of a key with alternative dimensions, or (None, None); the file's
        value checked against the key's bounds."""
        spec = kind_of(e.section).keys[key]
        address = f"{e.name}.{key}"
        if address in self.values:
            v = self.values[address]
            return v if isinstance(v, tuple) else (v, spec.unit.split("|")[0])
        if key not in e.raw:
            return None, None
        try:
            return replace(spec, keep_unit=True).read(e.raw[key], self.context())
        except (ValueError, TypeError) as exc:
            self.f.fail(e.where, key, str(exc))

    def context(self) -> Context:
        """What the file's values are read in: quantity texts, or SI numbers too in a drive
        built in code."""
        return Context(SI_TEXTS if self.f.generated else TEXTS)

    def need(self, e: Entry, key: str):
        """As :meth:`get`, and the key missing is an error."""
        value = self.get(e, key)
        if value is None:
            self.f.fail(e.where, key, f"missing ({kind_of(e.section).keys[key].help})")
        return value

    def node_name(self, e: Entry, key: str) -> str:
        """The node ``key`` of ``e`` names (it must exist)."""
        name = e.raw.get(key)
        if not isinstance(name, str):
            self.f.fail(e.where, key, "must name a node")
        if name not in self.node_entries:
            self.f.fail(e.where, key, f"{name!r} is not a node of this drive; "
                                      + did_you_mean(name, sorted(self.node_entries)))
        return name

    def between(self, e: Entry, count: tuple[int, ...]) -> list[str]:
        """The nodes ``between`` of ``e`` lists, as many as one of ``count``."""
        ends = e.raw.get("between")
        if not isinstance(ends, list) or len(ends) not in count or not all(isinstance(x, str) for x in ends):
            self.f.fail(e.where, "between", f"must list {' or '.join(map(str, count))} node names")
        for name in ends:
            if name not in self.node_entries:
                self.f.fail(e.where, "between", f"{name!r} is not a node of this drive; "
                                                + did_you_mean(name, sorted(self.node_entries)))
        return ends

    def lookup(self, e: Entry, key: str, kind: str):
        """The catalog entry (``kind``: ``belt``, ``chain``) that ``key`` of ``e`` names."""
        name = self.get(e, key)
        try:
            return getattr(self.catalog, kind)(name)
        except BeltcalcError as exc:
            self.f.fail(e.where, key, exc.message)

    def end_radius(self, e: Entry, key: str) -> tuple[str, float]:
        """(node, lever) of a strand's end: the node's pitch radius [m], 1 on a translating node."""
        node = self.node_name(e, key)
        if self.node_entries[node].raw.get("mass") is not None:
            return node, 1.0
        r = self.radius.get(node)
        if r is None:
            self.f.fail(e.where, key, f"node {node!r} has no pitch diameter: give it teeth and the belt/chain, "
                                      "or pitch_diameter")
        return node, r

    def strand_mass(self, e: Entry, end_i, end_j, per_length: float | None, length: float) -> None:
        """Half the strand's mass m L moves with each end: inertia m L r^2 / 2 on a pulley or
        sprocket of pitch radius r, mass m L / 2 on a translating node (the chain's mass
        lumped into the sprockets, as [RP] lumps it)."""
        if per_length is None:
            self.unweighed.append(e.name)
            return
        for node, r in (end_i, end_j):
            translating = self.node_entries[node].raw.get("mass") is not None
            share = per_length * length / 2 * (1.0 if translating else r ** 2)
            self.inertia[node] += share
        self.weighed.append(e.name)

    # --- the drive ------------------------------------------------------------------------
    def head_text(self, key: str):
        return self.get(self.f.head, key)

    def timing(self) -> tuple[float, int, float]:
        """(t_end [s], samples, window [s]) of ``[drive]``, checked."""
        h = self.f.head
        self.current = "drive"
        t_end = self.need(h, "t_end")
        samples = self.get(h, "samples", 2001)
        window = self.get(h, "window", 0.0)
        if not (t_end > 0 and math.isfinite(t_end)):
            self.f.fail("drive", "t_end", f"{t_end:g} s; it must be > 0 s")
        if samples != int(samples) or not 2 <= samples <= 10_000_000:
            self.f.fail("drive", "samples", f"{samples}; it must be a whole number 2..10,000,000")
        if not 0 <= window < t_end:
            self.f.fail("drive", "window", f"{window:g} s is not inside the run (0..{t_end:g} s)")
        return t_end, int(samples), window

    def build(self) -> tuple[list, list]:
        """(nodes, elements) of the drive: each entry built by its kind, in file order within
        the sections' order; the nodes with the shares of shafts and strands."""
        from beltcalc.sim.elements import Inertia

        for e in self.f.entries:
            self.current = e.where
            ELEMENTS[e.section].build(self, e)
        nodes = [Inertia(name, self.inertia[name], translation) for name, translation in self.nodes]
        if self.weighed:
            self.notes.append(f"strand masses: half of each strand's mass to each end node ({few(self.weighed)})")
        if self.unweighed:
            self.notes.append(f"strand masses not counted (the catalog has none; give mass): {few(self.unweighed)}")
        return nodes, self.elements
