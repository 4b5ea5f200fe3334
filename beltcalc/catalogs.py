"""Catalog files (belts, threads, motors, chains) loaded and validated into frozen SI dataclasses.

A catalog file is TOML. It has a ``[source]`` table (``document``, optionally
``location`` and ``edition``), an optional ``units`` table naming the unit of every
numeric key, and arrays of entries ``[[belts]]``, ``[[threads]]``, ``[[motors]]``,
``[[chains]]`` (any of them), or named ``[service_factors.NAME]`` tables. An entry may carry its own ``units`` (merged over the file's) and its own
``source`` string. Every number is converted to SI once, here; no other module reads a
catalog file or knows a catalog number.

This module is also the one place that resolves where the built-in catalogs live: the
``catalogs/`` folder of a source checkout, or ``beltcalc/catalogs`` inside an installed
wheel (hatchling ``force-include``).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Iterable

from beltcalc.errors import CatalogError, UnknownNameError, did_you_mean
from beltcalc.units import conversion_factor, quote, unit_problem


def builtin_dir() -> Path:
    """Folder of the built-in catalogs (inside the wheel, or the checkout's top level)."""
    here = Path(__file__).resolve().parent
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
    """A roller chain of one strand count, SI: lengths [m], breaking load [N], mass [kg/m].

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


# Per kind: key -> SI unit ("" for plain numbers); keys marked required must be present.
_BELT_KEYS = {"pitch": "m", "C_spec_per_F_Tadm": "", "damping": "N*s/m", "d_min": "m", "d_min_contraflexure": "m"}
_BELT_ROW_KEYS = {"width": "m", "F_Tadm": "N", "C_spec": "N", "w_spec": "kg/m", "breaking": "N"}
_FTSPEC_KEYS = {"speed": "rad/s", "load": "N/m"}
_THREAD_KEYS = {"d": "m", "P": "m", "d2": "m", "flank_angle": "rad"}
_MOTOR_KEYS = {"P": "W", "T_n": "N*m", "T_max": "N*m", "J": "kg*m^2",
               "n_rated": "rad/s", "n_max": "rad/s", "efficiency": ""}
_CHAIN_KEYS = {"pitch": "m", "roller_diameter": "m", "inner_width": "m", "pin_diameter": "m",
               "transverse_pitch": "m", "roller_bushing_constant": ""}
_TEXT_KEYS = {"manufacturer", "profile", "name", "series", "source", "note", "damping_source", "units"}


@lru_cache(maxsize=None)
def _unit_problem(unit: str, si_unit: str) -> str:
    """Why ``unit`` is not a unit of the dimension of ``si_unit`` ("" if it is one)."""
    return unit_problem(unit, si_unit)


MAX_DEPTH = 32                  # tables and arrays in tables and arrays: the catalogs need 4
MAX_FILE_BYTES = 20_000_000     # a catalog, scene or drive file; the largest built-in is ~30 kB
MAX_NAME = 100                  # characters of a name (manufacturer, profile, motor, ...)
MAX_TEXT = 10_000               # characters of any other text (a note, a source)
MAX_FLANK_ANGLE = math.radians(120.0)
_NAME_KEYS = {"manufacturer", "profile", "name", "series", "iso"}


def shown_key(key: str, limit: int = 40) -> str:
    r"""A key path as a message shows it: every part cut to ``limit`` characters and every
    character that is not printable (a newline, a right-to-left override) escaped.

    >>> shown_key("belts[0]." + "x" * 100_000), shown_key("a\u202eb.c")
    ('belts[0].xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx... (100000 characters)', 'a\\u202eb.c')
    """
    parts = []
    for part in str(key).split("."):
        cut = part[:limit] + f"... ({len(part)} characters)" if len(part) > limit else part
        parts.append("".join(c if c.isprintable() else repr(c)[1:-1] for c in cut))
    return ".".join(parts)


def text_problem(text: str, name: bool = False) -> str:
    r"""Why ``text`` cannot stand in a catalog ("" if it can): a control or formatting
    character (a newline in a name, a right-to-left override anywhere, which would make a
    table or a message say something else than the file), or a text too long.

    >>> text_problem("BRECO"), text_problem("AT\u202e01", name=True)
    ('', "'AT\\u202e01' holds the character U+202E; names are printable text on one line")
    """
    import unicodedata

    limit = MAX_NAME if name else MAX_TEXT
    if len(text) > limit:
        return f"{quote(text)} is too long (at most {limit} characters)"
    allowed = "" if name else "\n\t"
    for c in text:
        if c not in allowed and unicodedata.category(c) in ("Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"):
            what = "names are printable text on one line" if name else "texts are printable (newlines and tabs allowed)"
            return f"{quote(text)} holds the character U+{ord(c):04X}; {what}"
    if name and text != text.strip():
        return f"{quote(text)} starts or ends with a space"
    return ""


def shown_path(path, limit: int = 200) -> str:
    """A file path as a message shows it: characters that are not printable escaped, cut
    to ``limit`` characters (the line stays one line).

    >>> print(shown_path("my\\ncatalog.toml"))
    my\\ncatalog.toml
    """
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(path))
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def read_toml(path: Path, what: str = "catalog file") -> dict:
    """The TOML file ``path`` as a dict, or a :class:`CatalogError` naming the file: missing,
    unreadable, not UTF-8, not TOML, too large (:data:`MAX_FILE_BYTES`) or nested deeper
    than :data:`MAX_DEPTH` (a 5,000-level array would exhaust Python's recursion)."""
    shown = shown_path(path)
    try:
        size = os.stat(path).st_size
        if size > MAX_FILE_BYTES:
            raise CatalogError(f"{shown}: {size} bytes; a {what} has at most {MAX_FILE_BYTES} bytes")
        with open(path, "rb") as fh:
            raw = fh.read()
        # a byte-order mark (Windows editors save one) is no part of the TOML
        data = tomllib.loads(raw.decode("utf-8-sig"))
    except FileNotFoundError:
        raise CatalogError(f"{what} {shown} does not exist") from None
    except tomllib.TOMLDecodeError as exc:
        raise CatalogError(f"{shown}: not valid TOML ({exc})") from None
    except UnicodeDecodeError as exc:
        raise CatalogError(f"{shown}: not UTF-8 text (byte {exc.start}); save it as UTF-8") from None
    except (RecursionError, MemoryError):
        raise CatalogError(f"{shown}: nested too deeply (more than {MAX_DEPTH} levels of tables and arrays)") \
            from None
    except OSError as exc:
        raise CatalogError(f"{shown}: cannot be read ({exc.strerror})") from None
    _check_depth(shown, data)
    return data


def _check_depth(shown: str, data: dict) -> None:
    """Refuse tables and arrays nested deeper than :data:`MAX_DEPTH` (iteratively), and keys
    with control characters or longer than :data:`MAX_NAME` characters, naming the key."""
    stack = [(data, 1, "")]
    while stack:
        node, depth, where = stack.pop()
        if depth > MAX_DEPTH:
            raise CatalogError(f"{shown}: {shown_key(where)}: nested too deeply (more than {MAX_DEPTH} levels "
                               "of tables and arrays)")
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for key, value in items:
            if isinstance(key, str):
                problem = text_problem(key, name=True)
                if problem:
                    raise CatalogError(f"{shown}: {shown_key(f'{where}.{key}'.lstrip('.'))}: key {problem}")
                inner = f"{where}.{key}".lstrip(".")
            else:
                inner = f"{where}[{key}]"
            if isinstance(value, (dict, list)):
                stack.append((value, depth + 1, inner))


class CatalogReader:
    """Reads one catalog file; every error names the file and the key."""

    def __init__(self, path: Path, allowed=("source", "units", "belts", "threads", "motors", "chains",
                                            "service_factors")):
        self.path = path
        self.data = read_toml(path)
        src = self.data.get("source")
        if not isinstance(src, dict) or not isinstance(src.get("document"), str):
            self.fail("source.document", "every catalog file needs [source] with a 'document' string")
        self.source = Source(
            document=src["document"], location=str(src.get("location", "")),
            edition=str(src.get("edition", "")), path=str(path),
        )
        self.units = self.data.get("units", {})
        unknown = set(self.data) - set(allowed)
        if unknown:
            key = sorted(unknown)[0]
            self.fail(key, f"unknown top-level key; {did_you_mean(key, allowed, listed=len(allowed))}")

    def fail(self, key: str, message: str):
        raise CatalogError(f"{shown_path(self.path)}: {shown_key(key)}: {message}")

    def entries(self, kind: str) -> list[dict]:
        return self.rows(self.data, kind, kind)

    def rows(self, entry: dict, key: str, where: str) -> list[dict]:
        """``entry[key]`` as a list of tables (empty if absent), or a CatalogError."""
        items = entry.get(key, [])
        if not isinstance(items, list) or not all(isinstance(e, dict) for e in items):
            self.fail(where, "must be an array of tables")
        return items

    def text(self, entry: dict, key: str, where: str, default: str | None = None) -> str:
        value = entry.get(key, default)
        if not isinstance(value, str) or (default is None and not value.strip()):
            self.fail(f"{where}.{key}", "missing or not a text")
        problem = text_problem(value, name=key in _NAME_KEYS)
        if problem:
            self.fail(f"{where}.{key}", problem)
        return value

    def numbers(self, entry: dict, keys: dict[str, str], units: dict, where: str,
                required: Iterable[str] = (), zero_ok: Iterable[str] = ()) -> dict[str, float]:
        """Convert the numeric ``keys`` present in ``entry`` to SI; check they are > 0
        (or >= 0 for the keys in ``zero_ok``)."""
        out = {}
        for key, si_unit in keys.items():
            if key not in entry:
                if key in required:
                    self.fail(f"{where}.{key}", "missing")
                continue
            value = entry[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                self.fail(f"{where}.{key}", f"{quote(value)} is not a number")
            if si_unit:
                unit = units.get(key)
                if not isinstance(unit, str):
                    name = "F_tspec" if key == "load" else key
                    self.fail(f"{where.split('.')[0]}.units.{name}", "no unit given for this key")
                problem = _unit_problem(unit, si_unit)
                if problem:
                    self.fail(f"{where}.units.{key}", problem)
                value = value * conversion_factor(unit, si_unit)
            low_ok = value >= 0 if key in zero_ok else value > 0
            if not (math.isfinite(value) and low_ok):
                bound = ">= 0" if key in zero_ok else "> 0"
                self.fail(f"{where}.{key}", f"{quote(entry[key])} must be a finite number {bound}")
            out[key] = float(value)
        return out

    def check_keys(self, entry: dict, allowed: Iterable[str], where: str, text_keys=_TEXT_KEYS):
        extra = set(entry) - set(allowed) - set(text_keys)
        if extra:
            key = sorted(extra)[0]
            keys = [*allowed, *text_keys]
            self.fail(f"{where}.{key}", f"unknown key; {did_you_mean(key, keys, listed=len(keys))}")

    def entry_source(self, entry: dict, where: str) -> Source:
        if "source" not in entry:
            return self.source
        own = self.text(entry, "source", where)
        return Source(document=own, location=self.source.document, path=str(self.path))

    def entry_units(self, entry: dict, where: str) -> dict:
        units = entry.get("units", {})
        if not isinstance(units, dict) or not isinstance(self.units, dict):
            self.fail(f"{where}.units", "must be a table of unit strings")
        return {**self.units, **units}

    # --- kinds -----------------------------------------------------------------
    def belts(self) -> list[BeltProfile]:
        out = []
        for i, e in enumerate(self.entries("belts")):
            where = f"belts[{i}]"
            self.check_keys(e, [*_BELT_KEYS, "widths", "F_tspec", "z_e_max", "z_min", "z_min_contraflexure",
                                "stock_teeth", "open_length"], where)
            units = self.entry_units(e, where)
            nums = self.numbers(e, _BELT_KEYS, units, where, required=["pitch"])
            rows = []
            for j, row in enumerate(self.rows(e, "widths", f"{where}.widths")):
                rw = f"{where}.widths[{j}]"
                self.check_keys(row, _BELT_ROW_KEYS, rw, text_keys=())
                rows.append(BeltWidth(**self.numbers(row, _BELT_ROW_KEYS, units, rw, required=["width"])))
            widths = [r.width for r in rows]
            if any(b <= a for a, b in zip(widths, widths[1:])):
                self.fail(f"{where}.widths", "widths must be sorted ascending, without repeats")
            table = []
            for j, row in enumerate(self.rows(e, "F_tspec", f"{where}.F_tspec")):
                rw = f"{where}.F_tspec[{j}]"
                self.check_keys(row, _FTSPEC_KEYS, rw, text_keys=())
                vals = self.numbers(row, _FTSPEC_KEYS, {**units, "load": units.get("F_tspec")}, rw,
                                    required=_FTSPEC_KEYS, zero_ok=["speed"])
                table.append((vals["speed"], vals["load"]))
            speeds = [s for s, _ in table]
            if any(b <= a for a, b in zip(speeds, speeds[1:])):
                self.fail(f"{where}.F_tspec", "speeds must be sorted ascending, without repeats")
            if table and (len(table) < 2 or speeds[0] != 0.0):
                self.fail(f"{where}.F_tspec", f"{len(table)} row{'s' * (len(table) != 1)} from {speeds[0]:g} rad/s; the "
                                              "table needs a row at speed 0 and at least one more (it is interpolated)")
            ints = {}
            for key in ("z_e_max", "z_min", "z_min_contraflexure"):
                if key in e:
                    if not isinstance(e[key], int) or isinstance(e[key], bool) or e[key] <= 0:
                        self.fail(f"{where}.{key}", f"{e[key]!r} must be a whole number > 0")
                    ints[key] = e[key]
            stock = e.get("stock_teeth", [])
            if not isinstance(stock, list) or not all(isinstance(t, int) and not isinstance(t, bool)
                                                      and t > 0 for t in stock) \
                    or any(b <= a for a, b in zip(stock, stock[1:])):
                self.fail(f"{where}.stock_teeth", "must be a list of whole tooth counts > 0, ascending")
            open_length = e.get("open_length", False)
            if not isinstance(open_length, bool):
                self.fail(f"{where}.open_length", "must be true or false")
            out.append(BeltProfile(
                stock_teeth=tuple(stock), open_length=open_length,
                manufacturer=self.text(e, "manufacturer", where),
                profile=self.text(e, "profile", where),
                source=self.entry_source(e, where), widths=tuple(rows), F_tspec=tuple(table),
                note=self.text(e, "note", where, ""),
                damping_source=self.text(e, "damping_source", where, ""),
                **nums, **ints,
            ))
        return out

    def threads(self) -> list[Thread]:
        out = []
        for i, e in enumerate(self.entries("threads")):
            where = f"threads[{i}]"
            self.check_keys(e, _THREAD_KEYS, where)
            nums = self.numbers(e, _THREAD_KEYS, self.entry_units(e, where), where, required=_THREAD_KEYS)
            if nums["d2"] >= nums["d"]:
                self.fail(f"{where}.d2", "pitch diameter must be smaller than the nominal diameter")
            if nums["flank_angle"] >= MAX_FLANK_ANGLE:
                self.fail(f"{where}.flank_angle", f"{math.degrees(nums['flank_angle']):g} deg is not allowed; it must "
                                                  f"be in (0, {math.degrees(MAX_FLANK_ANGLE):g}) deg "
                                                  "(metric threads 60 deg, trapezoidal 30 deg)")
            out.append(Thread(name=self.text(e, "name", where), series=self.text(e, "series", where, ""),
                              source=self.entry_source(e, where), **nums))
        return out

    def motors(self) -> list[Motor]:
        out = []
        for i, e in enumerate(self.entries("motors")):
            where = f"motors[{i}]"
            self.check_keys(e, [*_MOTOR_KEYS, "intermittent", "continuous", "zone_source"], where)
            nums = self.numbers(e, _MOTOR_KEYS, self.entry_units(e, where), where,
                                required=[k for k in _MOTOR_KEYS if k != "efficiency"])
            if nums["T_max"] < nums["T_n"]:
                self.fail(f"{where}.T_max", "peak torque is below the rated torque")
            if nums["n_max"] < nums["n_rated"]:
                self.fail(f"{where}.n_max", "maximum speed is below the rated speed")
            if nums.get("efficiency", 0.5) > 1:
                self.fail(f"{where}.efficiency", "must be <= 1")
            zones = {key: self.zone(e, key, where, nums) for key in ("intermittent", "continuous")}
            out.append(Motor(name=self.text(e, "name", where), series=self.text(e, "series", where, ""),
                             source=self.entry_source(e, where), zone_source=self.text(e, "zone_source", where, ""),
                             **zones, **nums))
        return out

    def zone(self, e: dict, key: str, where: str, motor: dict) -> tuple[tuple[float, float], ...]:
        """A motor's torque-speed zone: ``[{ speed = .., torque = .. }, ...]`` from speed 0 to
        n_max, speeds ascending (units ``speed``, ``torque`` in the units table)."""
        units = {**self.entry_units(e, where)}
        points = []
        for j, row in enumerate(self.rows(e, key, f"{where}.{key}")):
            rw = f"{where}.{key}[{j}]"
            self.check_keys(row, ("speed", "torque"), rw, text_keys=())
            vals = self.numbers(row, {"speed": "rad/s", "torque": "N*m"}, units, rw, required=("speed", "torque"),
                                zero_ok=("speed", "torque"))
            points.append((vals["speed"], vals["torque"]))
        if not points:
            return ()
        speeds = [w for w, _ in points]
        if len(points) < 2 or speeds[0] != 0 or any(b <= a for a, b in zip(speeds, speeds[1:])):
            self.fail(f"{where}.{key}", "needs 2 or more points, speeds ascending from 0")
        if speeds[-1] < motor["n_max"] * (1 - 1e-9):
            self.fail(f"{where}.{key}", "must reach the maximum speed n_max")
        if "zone_source" not in e:
            self.fail(f"{where}.zone_source", "a torque-speed zone must say where it comes from")
        return tuple(points)


    def chains(self) -> list[Chain]:
        out = []
        for i, e in enumerate(self.entries("chains")):
            where = f"chains[{i}]"
            self.check_keys(e, [*_CHAIN_KEYS, "breaking_load", "mass", "iso", "lubrication"], where)
            units = self.entry_units(e, where)
            nums = self.numbers(e, _CHAIN_KEYS, units, where,
                                required=["pitch", "roller_diameter", "inner_width", "pin_diameter"])
            loads = e.get("breaking_load")
            if not isinstance(loads, list) or not loads:
                self.fail(f"{where}.breaking_load", "must be a list of breaking loads by strand count (1, 2, ...)")
            f_b = [self.numbers({"breaking_load": v}, {"breaking_load": "N"}, units, f"{where}.breaking_load[{k}]")
                   ["breaking_load"] for k, v in enumerate(loads)]
            if any(b <= a for a, b in zip(f_b, f_b[1:])):
                self.fail(f"{where}.breaking_load", "must rise with the strand count")
            masses = e.get("mass", {})
            if not isinstance(masses, dict) or not all(k.isdigit() and 1 <= int(k) <= len(f_b) for k in masses):
                self.fail(f"{where}.mass", "must be a table { strands = mass } with strands 1..len(breaking_load)")
            mass = {int(k): self.numbers({"mass": v}, {"mass": "kg/m"}, units, f"{where}.mass.{k}")["mass"]
                    for k, v in masses.items()}
            lub = e.get("lubrication")          # { A = v_A, B = v_B }: highest chain speed of each type
            if lub is not None:
                if not isinstance(lub, dict) or set(lub) != {"A", "B"}:
                    self.fail(f"{where}.lubrication", "must be a table { A = speed, B = speed }")
                lub = tuple(self.numbers({"lubrication": lub[k]}, {"lubrication": "m/s"}, units,
                                         f"{where}.lubrication.{k}")["lubrication"] for k in ("A", "B"))
                if not lub[0] < lub[1]:
                    self.fail(f"{where}.lubrication", "Type A's highest speed must be below Type B's")
            size = self.text(e, "name", where)
            iso = self.text(e, "iso", where, "")
            for k, load in enumerate(f_b, start=1):
                out.append(Chain(name=f"{size}-{k}", size=size, series=self.text(e, "series", where, ""),
                                 strands=k, breaking_load=load, mass=mass.get(k), iso=iso, lubrication=lub,
                                 source=self.entry_source(e, where), **nums))
        return out

    def service_factors(self) -> list[ServiceFactors]:
        tables = self.data.get("service_factors", {})
        if not isinstance(tables, dict):
            self.fail("service_factors", "must be named tables [service_factors.NAME]")
        out = []
        for name, t in tables.items():
            where = f"service_factors.{name}"
            keys = ("load_kinds", "peak_ratio_bounds", "hours_bounds", "base", "starts_bounds", "start_stop",
                    "idler", "speed_up_bounds", "speed_up")
            missing = [k for k in keys if k not in t]
            if missing:
                self.fail(f"{where}.{missing[0]}", "missing")
            extra = set(t) - set(keys) - {"load_examples"}
            if extra:
                key = sorted(extra)[0]
                self.fail(f"{where}.{key}", f"unknown key; {did_you_mean(key, [*keys, 'load_examples'], listed=99)}")

            def grid(value, shape, key):
                ok = isinstance(value, list) and len(value) == shape[0]
                if ok and len(shape) > 1:
                    return tuple(grid(v, shape[1:], key) for v in value)
                if not ok or (len(shape) == 1 and not all(
                        isinstance(x, (int, float)) and not isinstance(x, bool) and x >= 0 for x in value)):
                    self.fail(f"{where}.{key}", f"must be a table of numbers >= 0 of shape {shape}")
                return tuple(float(x) for x in value)

            kinds = t["load_kinds"]
            if not isinstance(kinds, list) or not all(isinstance(k, str) for k in kinds):
                self.fail(f"{where}.load_kinds", "must be a list of names")
            bounds = {k: grid(t[k], (len(t[k]) if isinstance(t[k], list) else -1,), k)
                      for k in ("peak_ratio_bounds", "hours_bounds", "starts_bounds", "speed_up_bounds")}
            n_peak, n_hours = len(bounds["peak_ratio_bounds"]) + 1, len(bounds["hours_bounds"]) + 1
            idler = t["idler"]
            if not isinstance(idler, dict) or not all(isinstance(v, (int, float)) for v in idler.values()):
                self.fail(f"{where}.idler", "must be a table { position = added factor }")
            out.append(ServiceFactors(
                name=name, source=self.source, load_kinds=tuple(kinds),
                base=grid(t["base"], (len(kinds), n_peak, n_hours), "base"),
                start_stop=grid(t["start_stop"], (n_peak, len(bounds["starts_bounds"]) + 1), "start_stop"),
                speed_up=grid(t["speed_up"], (len(bounds["speed_up_bounds"]) + 1,), "speed_up"),
                idler={k: float(v) for k, v in idler.items()}, **bounds))
        return out


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
        reader = CatalogReader(path)
        for kind, items in (("belts", reader.belts()), ("threads", reader.threads()),
                            ("motors", reader.motors()), ("chains", reader.chains())):
            for item in items:
                key = item.name.lower()
                for other in (self.belts, self.threads, self.motors, self.chains):
                    if key in other:
                        raise CatalogError(f"{shown_path(path)}: {kind}: duplicate name {item.name!r} "
                                           f"(already in {other[key].source.path})")
                getattr(self, kind)[key] = item
        for table in reader.service_factors():
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
    (``catalogs/cycles/``), gearboxes (``catalogs/gearboxes/``, read by :mod:`beltcalc.gearboxes`)
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
    file named by the SHA-256 of every catalog file's bytes and of the code that reads them
    (this module and :mod:`beltcalc.units`) and of the folder they are in (entries name their
    file): any edit or another checkout is a new name, never a stale read."""
    import hashlib

    folder = os.environ.get(CACHE_ENV)
    if folder == "off":
        return None
    if not folder:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder = os.path.join(base, "beltcalc")
    where = hashlib.sha256(str(builtin_dir().resolve()).encode()).hexdigest()[:12]   # entries name their file
    digest = hashlib.sha256()
    for path in [*files, Path(__file__), Path(__file__).with_name("units.py")]:
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


@dataclass(frozen=True)
class SceneFile:
    """A ready parameter set (``catalogs/scenes/*.toml``): values as text with units, each
    with the reason it has that value. The command that uses it converts the values."""

    name: str
    title: str
    command: str
    source: Source
    values: dict[str, tuple[str, str]]  # name -> (value text, why)


def scene_names(command: str | None = None) -> list[str]:
    """Names of the built-in scenes (for ``command`` only, if given)."""
    folder = builtin_dir() / "scenes"
    names = []
    for path in sorted(folder.glob("*.toml")):
        if command is None or load_scene(str(path)).command == command:
            names.append(path.stem)
    return names


def load_scene(ref: str, command: str | None = None) -> SceneFile:
    """A built-in scene by name (``wdu``) or a scene file by path.

    Every parameter is a table ``name = { value = "50 kg", why = "..." }``. A scene may
    name a ``base`` scene in its ``[scene]`` table: it inherits the base's parameters and
    overrides those it gives itself.

    >>> load_scene("wdu").values["mass"][0]
    '50 kg'
    """
    path = Path(ref)

    def exists(p: Path) -> bool:
        try:
            return p.exists()
        except (OSError, ValueError):      # a name too long, a NUL character
            return False
    if not (path.suffix == ".toml" or exists(path)):
        path = builtin_dir() / "scenes" / f"{ref}.toml"
        if not exists(path):
            known = scene_names(command)
            hint = did_you_mean(ref, known, listed=0) if len(ref) <= MAX_NAME else ""
            hint = f"; {hint}" if hint else ""
            raise UnknownNameError(f"unknown scene {quote(ref)}{hint} (built-in: {', '.join(known)}; "
                                   "or give a .toml path)", param="scene")
    reader = CatalogReader(path, allowed=("source", "scene", "parameters"))
    data = reader.data
    head = data.get("scene")
    if not isinstance(head, dict) or not isinstance(head.get("command"), str):
        reader.fail("scene.command", "a scene needs [scene] with 'title' and 'command'")
    if command is not None and head["command"] != command:
        reader.fail("scene.command", f"this scene is for `beltcalc {head['command']}`, not `{command}`")
    values = {}
    params = data.get("parameters")
    if not isinstance(params, dict):
        reader.fail("parameters", "a scene needs a [parameters] table")
    for key, item in params.items():
        if not isinstance(item, dict) or not isinstance(item.get("value"), (str, int, float)) \
                or isinstance(item.get("value"), bool):
            reader.fail(f"parameters.{key}", "must be { value = \"<quantity or name>\", why = \"...\" }")
        why = item.get("why", "")
        if not isinstance(why, str) or not why.strip():
            reader.fail(f"parameters.{key}.why", "every scene value must say why it has that value")
        values[key] = (str(item["value"]), why)
    base = head.get("base")
    if base is not None:
        if not isinstance(base, str) or base == path.stem:
            reader.fail("scene.base", "must name another scene")
        values = {**load_scene(base).values, **values}
    return SceneFile(name=path.stem, title=str(head.get("title", path.stem)), command=head["command"],
                 source=reader.source, values=values)
