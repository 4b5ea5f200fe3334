"""Catalog files (belts, threads, motors, chains) loaded and validated into frozen SI dataclasses.

A catalog file is TOML. It has a ``[source]`` table (``document``, optionally
``location`` and ``edition``), an optional ``units`` table naming the unit of every
numeric key, and arrays of entries ``[[belts]]``, ``[[threads]]``, ``[[motors]]``,
``[[chains]]`` (any of them), or named ``[service_factors.NAME]`` tables. An entry may
carry its own ``units`` (merged over the file's) and its own ``source`` string. The keys
of each are declared once, as :mod:`beltcalc.data.schema` records (:data:`CATALOG_FILE`), which
convert every number to SI once, here; no other module reads a catalog file or knows a
catalog number.

This module is also the one place that resolves where the built-in catalogs live: the
``catalogs/`` folder of a source checkout, or ``beltcalc/catalogs`` inside an installed
wheel (hatchling ``force-include``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from beltcalc.errors import CatalogError, UnknownNameError, did_you_mean
from beltcalc.data.schema import Entries, Flag, List, Named, Names, Quantity, Record, Section, Text, TomlFile, Whole
from beltcalc.data.tomlsafe import MAX_NAME, quote, shown_path


def builtin_dir() -> Path:
    """Folder of the built-in catalogs (inside the wheel, or the checkout's top level)."""
    here = Path(__file__).resolve().parents[1]        # beltcalc/ (this module is in beltcalc/data/)
    for candidate in (here / "catalogs", here.parent / "catalogs"):
        if candidate.is_dir():
            return candidate
    raise CatalogError(f"built-in catalogs not found next to {here} (broken installation?)")


@dataclass(frozen=True)
class Source:
    """Where a catalog entry's numbers come from."""

    document: str
    location: str = ""
    edition: str = ""
    path: str = ""

    def __str__(self) -> str:
        parts = [self.document, self.location, self.edition]
        return "; ".join(p for p in parts if p)

    def within(self, own: str | None) -> Source:
        """The source of an entry that names its own ``own`` (None: this one), inside this file's."""
        return self if own is None else Source(document=own, location=self.document, path=self.path)


@dataclass(frozen=True)
class BeltWidth:
    """One row of a belt's width table, SI: width [m], forces [N], weight [kg/m].

    ``None`` marks a value the source does not publish.
    """

    width: float
    F_Tadm: float | None = None
    C_spec: float | None = None
    w_spec: float | None = None
    breaking: float | None = None


@dataclass(frozen=True)
class BeltProfile:
    """A timing-belt profile of one manufacturer, SI units.

    ``F_tspec`` is the specific tooth load table: pairs (pulley speed [rad/s],
    allowable load per tooth and belt width [N/m]), every row the maker prints.
    ``z_min`` is the maker's fewest pulley teeth for a drive without contraflexure,
    ``z_min_contraflexure`` with a backward-bent idler; ``d_min`` and
    ``d_min_contraflexure`` the smallest tension-roller diameters [m] of the same table.
    ``None`` where the source gives no value.
    """

    manufacturer: str
    profile: str
    pitch: float
    source: Source
    widths: tuple[BeltWidth, ...] = ()
    F_tspec: tuple[tuple[float, float], ...] = ()
    z_e_max: int | None = None
    z_min: int | None = None
    z_min_contraflexure: int | None = None
    d_min: float | None = None
    d_min_contraflexure: float | None = None
    C_spec_per_F_Tadm: float | None = None
    damping: float | None = None
    damping_source: str = ""
    note: str = ""
    stock_teeth: tuple[int, ...] = ()
    open_length: bool = False

    @property
    def name(self) -> str:
        return f"{self.manufacturer}-{self.profile}"

    def width_row(self, width: float) -> BeltWidth:
        """The width-table row of ``width`` [m] (to 1 um), or :class:`UnknownNameError`."""
        if not self.widths:
            raise UnknownNameError(
                f"{self.name} has no width table in its catalog ({self.source.path}); "
                "give `f_tadm`, `c_spec` and `belt_weight` for the width you use",
                param="width",
            )
        for row in self.widths:
            if abs(row.width - width) < 1e-6:
                return row
        listed = ", ".join(f"{r.width * 1e3:g}" for r in self.widths)
        raise UnknownNameError(
            f"{width * 1e3:g} mm is not a catalog width of {self.name}; the catalog has {listed} mm",
            param="width",
        )


@dataclass(frozen=True)
class Thread:
    """A metric thread, SI: nominal diameter d, pitch P, pitch diameter d2 [m], flank angle [rad]."""

    name: str
    series: str
    d: float
    P: float
    d2: float
    flank_angle: float
    source: Source


@dataclass(frozen=True)
class Motor:
    """A servo motor's data sheet, SI: P [W], T_n, T_max [N m], J [kg m^2], speeds [rad/s]."""

    name: str
    series: str
    P: float
    T_n: float
    T_max: float
    J: float
    n_rated: float
    n_max: float
    source: Source
    # torque-speed zones as published: (speed [rad/s], torque [N m]) from 0 to n_max; () = none
    intermittent: tuple[tuple[float, float], ...] = ()
    continuous: tuple[tuple[float, float], ...] = ()
    zone_source: str = ""
    efficiency: float | None = None


@dataclass(frozen=True)
class Chain:
    """A roller chain of one strand count, SI: lengths [m], breaking and allowable dynamic
    (fatigue) load [N], mass [kg/m]; ``allowable_dynamic_load`` None where no maker's figure.

    ``name`` is ``<size>-<strands>`` (``10B-1``, ``40-2``); ``iso`` the ISO 606 name of an
    ANSI size (``08A``). ``mass`` is ``None`` where the catalog's sources do not print it.
    ``roller_bushing_constant`` is K_r of the ACA roller-bushing rating formula.
    """

    name: str
    size: str
    series: str
    strands: int
    pitch: float
    roller_diameter: float
    inner_width: float
    pin_diameter: float
    breaking_load: float
    source: Source
    mass: float | None = None
    transverse_pitch: float | None = None
    roller_bushing_constant: float | None = None
    iso: str = ""
    lubrication: tuple[float, float] | None = None   # highest chain speed of Type A, of Type B [m/s]
    allowable_dynamic_load: float | None = None      # the maker's fatigue (maximum allowable) load [N]

    @property
    def aliases(self) -> tuple[str, ...]:
        return (f"{self.iso}-{self.strands}",) if self.iso else ()


@dataclass(frozen=True)
class ServiceFactors:
    """A service-factor table (``[service_factors.NAME]``), numbers as the source prints them.

    ``base[load kind][peak class][hours class]``; ``start_stop[peak class][starts class]``;
    the ``*_bounds`` are the class limits (see ``catalogs/belts/service_factors.toml``).
    """

    name: str
    source: Source
    load_kinds: tuple[str, ...]
    peak_ratio_bounds: tuple[float, ...]
    hours_bounds: tuple[float, ...]
    base: tuple[tuple[tuple[float, ...], ...], ...]
    starts_bounds: tuple[float, ...]
    start_stop: tuple[tuple[float, ...], ...]
    idler: dict
    speed_up_bounds: tuple[float, ...]
    speed_up: tuple[float, ...]


# --- the schema of a catalog file: numbers in the units of the `units` tables ---------------
def _number(unit: str, help: str, required: bool = False, low: str = ">0", **kw) -> Quantity:
    """A catalog number in ``unit`` (SI; its unit in the ``units`` table), > 0 unless ``low``."""
    return Quantity(unit, help=help, required=required, low=low, **kw)


MAX_FLANK_ANGLE = math.radians(120.0)

SOURCE = Record({
    "document": Text(required=True, help="every file names the document its numbers come from"),
    "location": Text(numbers=True, help="where in it: page, table, address"),
    "edition": Text(numbers=True, help="its edition or date"),
})
ENTRY_TEXTS = {"source": Text(filled=True, help="this entry's own source, within the file's"),
               "note": Text(help="a remark")}
BELT_WIDTH = Record({
    "width": _number("m", "belt width", required=True), "F_Tadm": _number("N", "admissible tension force"),
    "C_spec": _number("N", "specific stiffness"), "w_spec": _number("kg/m", "weight per length"),
    "breaking": _number("N", "breaking force"),
})
F_TSPEC_ROW = Record({
    "speed": _number("rad/s", "speed of the driving pulley", required=True, low=">=0"),
    "load": _number("N/m", "tooth load per tooth in mesh and belt width", required=True, unit_key="F_tspec"),
})
ZONE_POINT = Record({
    "speed": _number("rad/s", "motor speed", required=True, low=">=0"),
    "torque": _number("N*m", "torque at that speed", required=True, low=">=0"),
})
TEETH = Whole(help="a tooth count", low=">0")
BELT = Record({
    "manufacturer": Text(name=True, required=True, help="the maker, e.g. BRECO"),
    "profile": Text(name=True, required=True, help="the profile, e.g. AT10"),
    "pitch": _number("m", "tooth pitch", required=True),
    "C_spec_per_F_Tadm": _number("", "C_spec / F_Tadm, the same for every width"),
    "damping": _number("N*s/m", "belt damping b_TB where there is no F_tspec table"),
    "d_min": _number("m", "smallest tension-roller diameter"),
    "d_min_contraflexure": _number("m", "smallest tension-roller diameter with contraflexure"),
    "widths": Entries(record=BELT_WIDTH, help="the width table, widths ascending"),
    "F_tspec": Entries(record=F_TSPEC_ROW, help="specific tooth load against speed, from speed 0"),
    "z_e_max": Whole(help="most teeth in mesh", low=">0"), "z_min": Whole(help="fewest pulley teeth", low=">0"),
    "z_min_contraflexure": Whole(help="fewest pulley teeth with contraflexure", low=">0"),
    "stock_teeth": List(item=TEETH, rising=True, help="the stock belts' tooth counts, ascending"),
    "open_length": Flag(help="an open-length belt, cut to length"),
    "damping_source": Text(help="where the damping comes from"), **ENTRY_TEXTS,
}, units=True)
THREAD = Record({
    "name": Text(name=True, required=True, help="e.g. M10x1"), "series": Text(name=True, default="", help="e.g. fine"),
    "d": _number("m", "nominal diameter", required=True), "P": _number("m", "pitch", required=True),
    "d2": _number("m", "pitch diameter", required=True),
    "flank_angle": _number("rad", "flank angle (metric 60 deg)", required=True), **ENTRY_TEXTS,
}, units=True)
MOTOR = Record({
    "name": Text(name=True, required=True, help="e.g. SGM7J-04A"),
    "series": Text(name=True, default="", help="e.g. Sigma-7"),
    "P": _number("W", "rated power", required=True), "T_n": _number("N*m", "rated torque", required=True),
    "T_max": _number("N*m", "peak torque", required=True), "J": _number("kg*m^2", "rotor inertia", required=True),
    "n_rated": _number("rad/s", "rated speed", required=True),
    "n_max": _number("rad/s", "maximum speed", required=True),
    "efficiency": _number("", "efficiency", high=1.0),
    "intermittent": Entries(record=ZONE_POINT, help="the intermittent torque-speed zone, speeds from 0 to n_max"),
    "continuous": Entries(record=ZONE_POINT, help="the continuous torque-speed zone, speeds from 0 to n_max"),
    "zone_source": Text(help="where the torque-speed zones come from"), **ENTRY_TEXTS,
}, units=True)
CHAIN = Record({
    "name": Text(name=True, required=True, help="the size, e.g. 10B"),
    "series": Text(name=True, default="", help="A or B"),
    "iso": Text(name=True, help="the ISO 606 name of an ANSI size, e.g. 08A"),
    "pitch": _number("m", "pitch", required=True), "roller_diameter": _number("m", "roller diameter", required=True),
    "inner_width": _number("m", "inner width", required=True),
    "pin_diameter": _number("m", "pin diameter", required=True),
    "transverse_pitch": _number("m", "transverse pitch of a multi-strand chain"),
    "roller_bushing_constant": _number("", "K_r of the ACA roller-bushing rating"),
    "breaking_load": List(item=_number("N", "breaking load"), least=1, rising=True, required=True,
                          help="breaking loads by strand count 1, 2, ..., rising"),
    "allowable_dynamic_load": List(item=_number("N", "allowable dynamic (fatigue) load"), least=1, rising=True,
                                   help="the maker's fatigue loads by strand count 1, 2, ... (fewer: left out)"),
    "mass": Named(item=_number("kg/m", "mass per length"), help="{ strands = mass }"),
    "lubrication": Section(record=Record({
        "A": _number("m/s", "highest chain speed of lubrication Type A", required=True, unit_key="lubrication"),
        "B": _number("m/s", "highest chain speed of lubrication Type B", required=True, unit_key="lubrication"),
    }), help="{ A = speed, B = speed }"), **ENTRY_TEXTS,
}, units=True)
_FACTOR = _number("", "a factor", low=">=0")
_LIMITS = List(item=_FACTOR, required=True, help="class limits")
SERVICE_FACTORS = Record({
    "load_kinds": Names(required=True, help="the kinds of load"), "load_examples": List(item=Text()),
    "peak_ratio_bounds": _LIMITS, "hours_bounds": _LIMITS, "starts_bounds": _LIMITS, "speed_up_bounds": _LIMITS,
    "base": List(item=List(item=List(item=_FACTOR)), required=True, help="[load kind][peak class][hours class]"),
    "start_stop": List(item=List(item=_FACTOR), required=True, help="[peak class][starts class]"),
    "speed_up": List(item=_FACTOR, required=True, help="by speed-up class"),
    "idler": Named(item=_number("", "added factor", low=""), required=True, help="{ position = added factor }"),
})
CATALOG_FILE = Record({
    "source": Section(record=SOURCE, required=True, help="[source] with a document"),
    "belts": Entries(record=BELT), "threads": Entries(record=THREAD), "motors": Entries(record=MOTOR),
    "chains": Entries(record=CHAIN), "service_factors": Named(item=Section(record=SERVICE_FACTORS)),
}, units=True)


def file_source(file: TomlFile) -> Source:
    """The ``[source]`` of a file read by a record with :data:`SOURCE` as ``source``."""
    return Source(**file.values["source"], path=str(file.path))


def _rising(values) -> bool:
    return all(a < b for a, b in zip(values, values[1:]))


def _shape_problem(value: tuple, shape: tuple[int, ...], at: str) -> tuple[str, str]:
    """(where, why) ``value``'s nested lengths differ from ``shape``, or ("", "")."""
    if len(value) != shape[0]:
        return at, f"{len(value)} values; the table's shape is {shape}"
    for i, inner in enumerate(value if len(shape) > 1 else ()):
        where, why = _shape_problem(inner, shape[1:], f"{at}[{i}]")
        if why:
            return where, why
    return "", ""


class CatalogFile:
    """One catalog file read by :data:`CATALOG_FILE`: its entries as SI dataclasses, checked
    against each other (widths and speeds ascending, d2 < d, ...). Every error names the
    file and the key."""

    def __init__(self, path: Path):
        self.file = TomlFile(path, CATALOG_FILE)
        self.source = file_source(self.file)
        self.fail = self.file.fail
        values = self.file.values
        self.belts = [self.belt(e, f"belts[{i}]") for i, e in enumerate(values.get("belts", []))]
        self.threads = [self.thread(e, f"threads[{i}]") for i, e in enumerate(values.get("threads", []))]
        self.motors = [self.motor(e, f"motors[{i}]") for i, e in enumerate(values.get("motors", []))]
        self.chains = [c for i, e in enumerate(values.get("chains", [])) for c in self.chain(e, f"chains[{i}]")]
        self.service_factors = [self.factors(name, t, f"service_factors.{name}")
                                for name, t in values.get("service_factors", {}).items()]

    def belt(self, e: dict, where: str) -> BeltProfile:
        widths = tuple(BeltWidth(**row) for row in e.pop("widths", ()))
        if not _rising([r.width for r in widths]):
            self.fail(f"{where}.widths", "widths must be sorted ascending, without repeats")
        table = tuple((row["speed"], row["load"]) for row in e.pop("F_tspec", ()))
        speeds = [s for s, _ in table]
        if not _rising(speeds):
            self.fail(f"{where}.F_tspec", "speeds must be sorted ascending, without repeats")
        if table and (len(table) < 2 or speeds[0] != 0.0):
            self.fail(f"{where}.F_tspec", f"{len(table)} row{'s' * (len(table) != 1)} from {speeds[0]:g} rad/s; the "
                                          "table needs a row at speed 0 and at least one more (it is interpolated)")
        return BeltProfile(source=self.source.within(e.pop("source", None)), widths=widths, F_tspec=table, **e)

    def thread(self, e: dict, where: str) -> Thread:
        if e["d2"] >= e["d"]:
            self.fail(f"{where}.d2", "pitch diameter must be smaller than the nominal diameter")
        if e["flank_angle"] >= MAX_FLANK_ANGLE:
            self.fail(f"{where}.flank_angle", f"{math.degrees(e['flank_angle']):g} deg is not allowed; it must "
                                              f"be in (0, {math.degrees(MAX_FLANK_ANGLE):g}) deg "
                                              "(metric threads 60 deg, trapezoidal 30 deg)")
        e.pop("note", None)
        return Thread(source=self.source.within(e.pop("source", None)), **e)

    def motor(self, e: dict, where: str) -> Motor:
        if e["T_max"] < e["T_n"]:
            self.fail(f"{where}.T_max", "peak torque is below the rated torque")
        if e["n_max"] < e["n_rated"]:
            self.fail(f"{where}.n_max", "maximum speed is below the rated speed")
        for key in ("intermittent", "continuous"):
            points = tuple((p["speed"], p["torque"]) for p in e.pop(key, ()))
            speeds = [w for w, _ in points]
            if points and (len(points) < 2 or speeds[0] != 0 or not _rising(speeds)):
                self.fail(f"{where}.{key}", "needs 2 or more points, speeds ascending from 0")
            if points and speeds[-1] < e["n_max"] * (1 - 1e-9):
                self.fail(f"{where}.{key}", "must reach the maximum speed n_max")
            if points and "zone_source" not in e:
                self.fail(f"{where}.zone_source", "a torque-speed zone must say where it comes from")
            e[key] = points
        e.pop("note", None)
        return Motor(source=self.source.within(e.pop("source", None)), **e)

    def chain(self, e: dict, where: str) -> list[Chain]:
        """One chain entry: a :class:`Chain` per strand count of its breaking loads."""
        loads, masses, fatigue = e.pop("breaking_load"), e.pop("mass", {}), e.pop("allowable_dynamic_load", [])
        if len(fatigue) > len(loads):
            self.fail(f"{where}.allowable_dynamic_load", f"{len(fatigue)} values for {len(loads)} strand counts")
        for k in masses:
            if not (k.isdigit() and 1 <= int(k) <= len(loads)):
                self.fail(f"{where}.mass.{k}", f"not a strand count; the keys are strand counts 1..{len(loads)} "
                                                "(one per breaking load)")
        masses = {int(k): m for k, m in masses.items()}
        lub = e.pop("lubrication", None)
        if lub is not None and not lub["A"] < lub["B"]:
            self.fail(f"{where}.lubrication", "Type A's highest speed must be below Type B's")
        size, source = e.pop("name"), self.source.within(e.pop("source", None))
        e.pop("note", None)
        return [Chain(name=f"{size}-{k}", size=size, strands=k, breaking_load=load, mass=masses.get(k),
                      lubrication=lub and (lub["A"], lub["B"]), source=source,
                      allowable_dynamic_load=fatigue[k - 1] if k <= len(fatigue) else None, **e)
                for k, load in enumerate(loads, start=1)]

    def factors(self, name: str, t: dict, where: str) -> ServiceFactors:
        """A service-factor table, its grids of the shapes its class limits give."""
        n_peak, n_hours = len(t["peak_ratio_bounds"]) + 1, len(t["hours_bounds"]) + 1
        for key, shape in (("base", (len(t["load_kinds"]), n_peak, n_hours)),
                           ("start_stop", (n_peak, len(t["starts_bounds"]) + 1)),
                           ("speed_up", (len(t["speed_up_bounds"]) + 1,))):
            at, why = _shape_problem(t[key], shape, f"{where}.{key}")
            if why:
                self.fail(at, why)
        t.pop("load_examples", None)
        return ServiceFactors(name=name, source=self.source, **{k: tuple(v) if isinstance(v, list) else v
                                                                 for k, v in t.items()})


@dataclass
class Catalog:
    """Every belt, thread and motor of the loaded catalog files, by name."""

    belts: dict[str, BeltProfile] = field(default_factory=dict)
    threads: dict[str, Thread] = field(default_factory=dict)
    motors: dict[str, Motor] = field(default_factory=dict)
    chains: dict[str, Chain] = field(default_factory=dict)
    service_factors: dict[str, ServiceFactors] = field(default_factory=dict)
    files: list[str] = field(default_factory=list)

    def add_file(self, path: Path) -> None:
        reader = CatalogFile(path)
        for kind, items in (("belts", reader.belts), ("threads", reader.threads),
                            ("motors", reader.motors), ("chains", reader.chains)):
            for item in items:
                key = item.name.lower()
                for other in (self.belts, self.threads, self.motors, self.chains):
                    if key in other:
                        raise CatalogError(f"{shown_path(path)}: {kind}: duplicate name {item.name!r} "
                                           f"(already in {other[key].source.path})")
                getattr(self, kind)[key] = item
        for table in reader.service_factors:
            if table.name in self.service_factors:
                raise CatalogError(f"{shown_path(path)}: service_factors: duplicate name {quote(table.name)}")
            self.service_factors[table.name] = table
        self.files.append(str(path))

    def belt(self, name: str) -> BeltProfile:
        """A belt by its full name (``BRECO-AT10``) or by its profile alone when unique."""
        return self._lookup("belt", self.belts, name, "belt", aliases=True)

    def thread(self, name: str) -> Thread:
        return self._lookup("thread", self.threads, name, "thread")

    def motor(self, name: str) -> Motor:
        return self._lookup("motor", self.motors, name, "motor")

    def chain(self, name: str) -> Chain:
        """A chain by name (``10B-1``, ``40-2``) or by its ISO 606 A-series name (``08A-2``)."""
        key = name.strip().lower()
        for chain in self.chains.values():
            if key in (a.lower() for a in chain.aliases):
                return chain
        return self._lookup("chain", self.chains, name, "chain")

    def service_factor_table(self, name: str) -> ServiceFactors:
        if name not in self.service_factors:
            raise CatalogError(f"no service-factor table {quote(name)} in the catalogs "
                               f"(have: {', '.join(sorted(self.service_factors)) or 'none'})")
        return self.service_factors[name]

    def entry(self, name: str) -> BeltProfile | Thread | Motor | Chain:
        """Any entry by name (belts by profile too), for ``beltcalc catalog show``."""
        key = name.strip().lower()
        for chain in self.chains.values():
            if key in (a.lower() for a in chain.aliases):
                return chain
        merged = {**self.belts, **self.threads, **self.motors, **self.chains}
        return self._lookup("catalog entry", merged, name, None, aliases=True)

    def _lookup(self, what: str, table: dict, name: str, param: str | None, aliases: bool = False):
        key = name.strip().lower()
        if key in table:
            return table[key]
        if aliases:
            hits = [b for b in table.values() if isinstance(b, BeltProfile) and b.profile.lower() == key]
            if len(hits) == 1:
                return hits[0]
            if len(hits) > 1:
                names = ", ".join(sorted(h.name for h in hits))
                raise UnknownNameError(f"{quote(name)} is ambiguous; say which one: {names}", param=param)
        names = [v.name for v in table.values()]
        if aliases:
            names += [v.profile for v in table.values() if isinstance(v, BeltProfile)]
        hint = did_you_mean(name, names, listed=0) if len(name) <= MAX_NAME else ""
        hint = f"; {hint}" if hint else ""
        raise UnknownNameError(
            f"unknown {what} {quote(name)}{hint} (`beltcalc catalog list` lists them)", param=param
        )


def load_catalog(extra: Iterable[str | Path] = ()) -> Catalog:
    """Load the built-in catalogs plus the user's files ``extra`` (same format).

    Scenes (``catalogs/scenes/``), drive files (``catalogs/drives/``), duty cycles
    (``catalogs/cycles/``), gearboxes (``catalogs/gearboxes/``, read by :mod:`beltcalc.design.gearboxes`)
    and shaft materials (``catalogs/materials.toml``, read by :mod:`beltcalc.sim.drivefile`) are
    not catalog files and are skipped. The built-in part comes from the cache
    (:func:`_builtin_catalog`) when its files are unchanged.

    >>> cat = load_catalog()
    >>> cat.belt("AT10").width_row(0.025).F_Tadm
    2200.0
    """
    catalog = _builtin_catalog()
    for path in extra:
        catalog.add_file(Path(path))
    return catalog


def _builtin_files() -> list[Path]:
    root = builtin_dir()
    return [path for path in sorted(root.rglob("*.toml"))
            if not {"scenes", "drives", "cycles", "gearboxes", "materials.toml"} & set(path.relative_to(root).parts)]


CACHE_ENV = "BELTCALC_CACHE"     # a folder for the parsed built-in catalogs; "off": none


def _cache_file(files: list[Path]) -> Path | None:
    """Where the parsed built-in catalogs are kept: the user's cache folder (``$XDG_CACHE_HOME``
    or ``~/.cache``, then ``beltcalc``; ``$BELTCALC_CACHE`` instead, ``off`` for none), in a
    file named by the SHA-256 of every catalog file's bytes, of the code that reads them
    (this module, :mod:`beltcalc.data.schema`, :mod:`beltcalc.data.tomlsafe`, :mod:`beltcalc.units`) and
    of the folder they are in (entries name their file): any edit or another checkout is a
    new name, never a stale read."""
    import hashlib

    folder = os.environ.get(CACHE_ENV)
    if folder == "off":
        return None
    if not folder:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder = os.path.join(base, "beltcalc")
    where = hashlib.sha256(str(builtin_dir().resolve()).encode()).hexdigest()[:12]   # entries name their file
    digest = hashlib.sha256()
    code = [Path(__file__).with_name(name) for name in ("catalogs.py", "schema.py", "tomlsafe.py")]
    code.append(Path(__file__).parents[1] / "units.py")
    for path in [*files, *code]:
        digest.update(str(path.name).encode() + b"\0")
        try:
            digest.update(path.read_bytes())
        except OSError:
            return None
    return Path(folder) / f"catalog-{where}-{digest.hexdigest()[:32]}.pickle"


def _builtin_catalog() -> Catalog:
    """The built-in catalogs: unpickled from :func:`_cache_file` (0.3 ms) where it exists,
    else read from their TOML files (about 11 ms: parsing and unit conversion) and then
    written there atomically, replacing the file an earlier version of the same folder left
    (one file per checkout). A cache that cannot be read or written is ignored (the files
    are read); a fresh :class:`Catalog` every call (callers add files to it)."""
    import pickle

    files = _builtin_files()
    cache = _cache_file(files)
    if cache is not None:
        try:
            with open(cache, "rb") as fh:
                hit = pickle.load(fh)
            if isinstance(hit, Catalog):
                return hit
        except Exception:        # missing, partial, from another Python: read the files instead
            pass
    catalog = Catalog()
    for path in files:
        catalog.add_file(path)
    if cache is not None:
        try:
            cache.parent.mkdir(parents=True, exist_ok=True)
            tmp = cache.with_name(f"{cache.name}.{os.getpid()}.tmp")
            try:
                tmp.write_bytes(pickle.dumps(catalog, protocol=pickle.HIGHEST_PROTOCOL))
                os.replace(tmp, cache)
            finally:
                if tmp.exists():
                    tmp.unlink()
            prefix = cache.name.rsplit("-", 1)[0] + "-"       # this folder's older versions: one file each
            for old in cache.parent.glob(prefix + "*.pickle"):
                if old != cache:
                    old.unlink(missing_ok=True)
        except OSError:
            pass
    return catalog
