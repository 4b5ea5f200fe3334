"""One typed schema for beltcalc's TOML files: catalog files (belts, threads, motors, chains,
service factors, gearboxes), cycle files, scene files, and the keys of drive files.

A file kind declares its tables as :class:`Record` s of typed fields: :class:`Quantity` (an SI
unit, bounds), :class:`Whole`, :class:`Flag`, :class:`Text`, :class:`Choice`,
:class:`Names`, :class:`List`, :class:`Table` (columns with units), :class:`Section` (a
table), :class:`Entries` (an array of tables) and :class:`Named` (a table of named values).
Every field has a help text, whether it is required, and a default. The type is the
field's class: a unit is only ever a unit (``"a|b"``: either dimension).

How a file writes a quantity is its :class:`Notation`: a number whose unit stands in the
file's or the entry's ``units`` table (:data:`CATALOG`), a text with its unit and plain
numbers bare (:data:`TEXTS`, drive files; :data:`SI_TEXTS`, a drive built in code whose
bare numbers are SI), or either of a text and a number (:data:`QUANTITIES`, cycle files).

A value a field refuses is a :class:`FieldError` naming where it is (``belts[0].widths[1]
.F_Tadm``); :class:`TomlFile` turns it into the one message of every file::

    FILE: ELEMENT.KEY: what is wrong with the value, and what is allowed

a :class:`~beltcalc.errors.CatalogError` (exit 1). Text given on the command line
(``motor-size --segment``) reads through the same fields and says the same, as a usage
error (exit 2).

A file's bytes are read by :func:`beltcalc.data.tomlsafe.read_toml` (bounded size and depth,
keys that are names). Importing this module is cheap: TOML and pint come on first use.

>>> SPAN = Record({"length": Quantity("m", help="free span length", required=True, low=">0"),
...                "teeth": Whole(help="teeth", low=">0")})
>>> SPAN.read({"length": "250 mm"}, Context(TEXTS), "belt_span[0]")
{'length': 0.25}
>>> SPAN.read({"length": "-1 m"}, Context(TEXTS), "belt_span[0]")
Traceback (most recent call last):
...
beltcalc.data.schema.FieldError: -1 m is not allowed; it must be > 0 m
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import ClassVar, Mapping

from beltcalc.errors import CatalogError, did_you_mean
from beltcalc.data.tomlsafe import join, quote, read_toml, shown, shown_key, shown_path, text_problem


# --- errors and notations ----------------------------------------------------------------------
class FieldError(ValueError):
    """A value a field refuses: ``message`` says what is wrong and what is allowed, ``at``
    where the value is inside its file (``belts[0].widths[1].F_Tadm``; ``""``: the value
    itself). ``str()`` is the message alone (a drive file adds its own element and key)."""

    def __init__(self, message: str, at: str = ""):
        super().__init__(message)
        self.message = message
        self.at = at


@dataclass(frozen=True, eq=False)
class Notation:
    """How a file writes a quantity.

    ``units_table``: a TOML number, its unit in the ``units`` table of its entry or of the
    file (catalogs). Otherwise a text with its unit (``"250 mm"``), where ``bare_si``
    takes a bare number of a dimension as SI (else it is refused: the file writes the unit)
    and ``plain_text`` lets a plain number be a text too (``"0.3"``). ``docs``: the page
    that describes the notation, named where a value is refused for it."""

    units_table: bool = False
    bare_si: bool = False
    plain_text: bool = False
    docs: str = ""


CATALOG = Notation(units_table=True)
TEXTS = Notation(docs="docs/drive_files.md")
SI_TEXTS = Notation(bare_si=True, docs="docs/drive_files.md")
QUANTITIES = Notation(bare_si=True, plain_text=True)


@dataclass(frozen=True, eq=False)
class Context:
    """What a value is read in: the file's :class:`Notation`, and (catalogs) the units table
    in force, which stands in the table at ``units_at``."""

    notation: Notation
    units: Mapping = field(default_factory=dict)
    units_at: str = ""


@lru_cache(maxsize=None)
def _unit_problem(unit: str, si_unit: str) -> str:
    from beltcalc.units import unit_problem

    return unit_problem(unit, si_unit)


@lru_cache(maxsize=4096)
def _quantity(raw: str, unit: str):
    """The text ``raw`` read as a quantity of ``unit`` (:func:`~beltcalc.units.parse_quantity`; of
    one of ``a|b``: (value, unit), :func:`~beltcalc.units.parse_quantity_any`). Each text
    is read by pint once per process: a drive file is built many times (a sweep's points).
    A refusal is not kept: it is raised again, the same, on every call."""
    from beltcalc.units import parse_quantity, parse_quantity_any

    if "|" in unit:
        return parse_quantity_any(raw, tuple(unit.split("|")))
    return parse_quantity(raw, unit)


def _is_number(raw) -> bool:
    return isinstance(raw, (int, float)) and not isinstance(raw, bool)


# --- fields --------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True, eq=False)
class Field:
    """A key of a table: its ``help`` (what the value is), whether it is ``required``, its
    ``default`` (None: absent), and ``when`` (required when that other key is given).
    :meth:`read` turns a raw TOML value into the value a program uses, or raises
    :class:`FieldError`. ``scalar``: one value (``--set KEY=...`` can give it)."""

    help: str = ""
    required: bool = False
    default: object = None
    when: str = ""

    scalar: ClassVar[bool] = True

    def read(self, raw, ctx: Context, at: str = "", key: str = ""):
        """``raw`` (the value at ``at``, under the key ``key``) as its program value."""
        raise NotImplementedError

    def refuse(self, kind: str, raw, at: str):
        """Raise that ``raw`` is not ``kind`` (``"a list"``), saying what the value is for."""
        about = f" ({self.help})" if self.help else ""
        raise FieldError(f"must be {kind}{about}, not {shown(raw)}", at)


_BOUNDS = {">0": lambda v: v > 0, ">=0": lambda v: v >= 0, "!=0": lambda v: v != 0}


@dataclass(frozen=True, eq=False)
class Quantity(Field):
    """A number with an SI ``unit`` (``""``: a plain number; ``"a|b"``: of either dimension,
    read as ``(value, unit)`` when ``keep_unit``), within ``low`` (``">0"``, ``">=0"``,
    ``"!=0"`` or ``""``) and ``high`` (at most). ``unit_key``: the key of the catalog's
    ``units`` table that gives its unit (default: its own key); ``hint``: said after a
    value out of bounds."""

    unit: str = ""
    low: str = ""
    high: float | None = None
    unit_key: str = ""
    keep_unit: bool = False
    hint: str = ""

    def read(self, raw, ctx: Context, at: str = "", key: str = ""):
        if ctx.notation.units_table:
            return self._from_table(raw, ctx, at, key)
        value = self._from_text(raw, ctx.notation, at)
        number, unit = value if isinstance(value, tuple) else (value, self.unit.split("|")[0])
        problem = self.bound_problem(number, unit)
        if problem:
            raise FieldError(problem, at)
        return value if self.keep_unit else number

    def bound_problem(self, value, unit: str = "", written: str = "") -> str:
        """Why ``value`` (SI, shown in ``unit``; the file wrote ``written``) is outside the
        bounds, or ``""``."""
        if not _is_number(value) or (not self.low or _BOUNDS[self.low](value)) \
                and (self.high is None or value <= self.high):
            return ""
        u = "" if unit in ("", "1") else " " + unit.split("|")[0]
        written = written or f"{value:g}{u}"
        hint = f" ({self.hint})" if self.hint else ""
        if self.low and not _BOUNDS[self.low](value):
            if self.low == "!=0":
                return f"{written} is not allowed; it must not be 0{u}{hint}"
            return f"{written} is not allowed; it must be {self.low[:-1]} 0{u}{hint}"
        si = "" if self.unit in ("", "1") else " " + self.unit.split("|")[0]
        return f"{written} is not allowed; it must be <= {self.high:g}{si}{hint}"

    def _from_table(self, raw, ctx: Context, at: str, key: str) -> float:
        """A catalog number: ``raw`` in the unit its ``units`` table names, in SI."""
        if not _is_number(raw):
            raise FieldError(f"{shown(raw)} is not a number", at)
        value, unit = raw, ""
        if self.unit:
            name = self.unit_key or key
            unit = ctx.units.get(name)
            where = f"{join(ctx.units_at, 'units')}.{name}"
            if not isinstance(unit, str):
                raise FieldError("no unit given for this key", where)
            problem = _unit_problem(unit, self.unit)
            if problem:
                raise FieldError(problem, where)
            from beltcalc.units import conversion_factor

            value = value * conversion_factor(unit, self.unit)
        written = f"{raw:g} {unit}".rstrip()
        if not math.isfinite(value):
            raise FieldError(f"{quote(raw)} is not a finite number" if not math.isfinite(raw) else
                             f"{written} is too large: above 1e308 {self.unit}".rstrip(), at)
        problem = self.bound_problem(value, unit, written)
        if problem:
            raise FieldError(problem, at)
        return float(value)

    def _from_text(self, raw, notation: Notation, at: str):
        """A quantity text (or a bare number, as ``notation`` allows) in SI: a float, or
        ``(value, unit)`` for a quantity of either of two dimensions."""
        from beltcalc.units import QuantityError, example_unit

        unit = self.unit
        plain = unit in ("", "1")
        if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
            raise FieldError(f"must be a quantity text such as '5 {example_unit(unit.split('|')[0])}', "
                             f"not {shown(raw)}" if not plain else f"must be a number, not {shown(raw)}", at)
        if isinstance(raw, str) and plain and not notation.plain_text:
            docs = f", {notation.docs}" if notation.docs else ""
            raise FieldError(f"must be a plain number, not the text {raw!r}: write it without quotes "
                             f"(ratios, factors and slips are numbers{docs})", at)
        if not isinstance(raw, str) and not plain:
            if notation.bare_si:
                value = float(raw)
                if not math.isfinite(value):
                    raise FieldError(f"{quote(raw)} is not a finite number", at)
                return (value, unit.split("|")[0]) if "|" in unit else value
            example = raw if isinstance(raw, int) or math.isfinite(raw) else 1.0    # "inf s" is refused too
            texts = " or ".join(f'"{example:g} {example_unit(u)}"' for u in unit.split("|"))
            raise FieldError(f"{raw!r} needs its unit: write it as a text, e.g. {texts}", at)
        try:
            if isinstance(raw, str):
                return _quantity(raw, unit)
            from beltcalc.units import parse_quantity

            return parse_quantity(raw, "")
        except QuantityError as exc:
            raise FieldError(str(exc), at) from None


@dataclass(frozen=True, eq=False)
class Whole(Field):
    """A whole number (a TOML integer), within ``low`` as :class:`Quantity`'s."""

    low: str = ""

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> int:
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise FieldError(f"must be a whole number, not {shown(raw)}", at)
        if self.low and not _BOUNDS[self.low](raw):
            raise FieldError(Quantity(low=self.low).bound_problem(raw), at)
        return raw


@dataclass(frozen=True, eq=False)
class Flag(Field):
    """``true`` or ``false``."""

    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> bool:
        if not isinstance(raw, bool):
            raise FieldError(f"must be true or false, not {shown(raw)}", at)
        return raw


@dataclass(frozen=True, eq=False)
class Text(Field):
    """A text: printable (newlines and tabs allowed); a ``name`` is one printable line
    (:func:`~beltcalc.data.tomlsafe.text_problem`). A required text, and one that is ``filled``,
    is not empty. ``numbers``: a number is taken as its text (``5.0`` -> ``"5.0"``)."""

    name: bool = False
    numbers: bool = False
    filled: bool = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> str:
        if self.numbers and _is_number(raw):
            raw = str(raw)
        if not isinstance(raw, str):
            raise FieldError(f"must be a text, not {shown(raw)}", at)
        if (self.required or self.filled) and not raw.strip():
            raise FieldError(f"must not be empty ({self.help})" if self.help else "must not be empty", at)
        problem = text_problem(raw, name=self.name)
        if problem:
            raise FieldError(problem, at)
        return raw


@dataclass(frozen=True, eq=False)
class Choice(Field):
    """One of the texts ``choices``."""

    choices: tuple[str, ...] = ()

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> str:
        if not isinstance(raw, str) or raw not in self.choices:
            raise FieldError(f"{shown(raw)} is not allowed; use " + " or ".join(f'"{c}"' for c in self.choices), at)
        return raw


@dataclass(frozen=True, eq=False)
class Names(Field):
    """A list of names (each as :class:`Text` ``name=True`` reads it), as many as one of
    ``count`` (empty: any number)."""

    count: tuple[int, ...] = ()
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> list[str]:
        if not isinstance(raw, list) or self.count and len(raw) not in self.count:
            self.refuse(f"a list of {' or '.join(map(str, self.count))} names" if self.count else "a list of names",
                        raw, at)
        name = Text(name=True, required=True)
        return [name.read(v, ctx, f"{at}[{i}]", key) for i, v in enumerate(raw)]


@dataclass(frozen=True, eq=False)
class List(Field):
    """A list of values that ``item`` reads (its unit under this list's key), at least
    ``least`` of them, strictly ascending where ``rising``."""

    item: Field = field(default_factory=Field)
    least: int = 0
    rising: bool = False
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> tuple:
        if not isinstance(raw, list) or len(raw) < self.least:
            self.refuse(f"a list of {self.least} or more" if self.least else "a list", raw, at)
        out = tuple(self.item.read(v, ctx, f"{at}[{i}]", key) for i, v in enumerate(raw))
        for i in range(1, len(out)):
            if self.rising and not out[i - 1] < out[i]:
                raise FieldError(f"must rise, without repeats: {raw[i]!r} after {raw[i - 1]!r}", f"{at}[{i}]")
        return out


@dataclass(frozen=True, eq=False)
class Table(Field):
    """A table of rows ``[x, y]`` (a list of pairs), each column a :class:`Quantity`; the
    first column rising (a value may repeat, for a jump). ``names``: the columns in words."""

    columns: tuple[Quantity, Quantity] = (Quantity("s"), Quantity(""))
    names: tuple[str, str] = ("time", "value")
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> tuple[tuple, ...]:
        from beltcalc.units import example_unit

        if not isinstance(raw, list) or not raw or not all(isinstance(p, list) and len(p) == 2 for p in raw):
            units = [example_unit(c.unit.split("|")[0]) if c.unit not in ("", "1") else "" for c in self.columns]
            rows = [", ".join(f'"{n} {u}"' if u else n for n, u in zip(pair, units))
                    for pair in (("0", "0"), ("1", "5"))]
            raise FieldError(f"must be a list of [{self.names[0]}, {self.names[1]}] pairs, e.g. "
                             f"[[{rows[0]}], [{rows[1]}]]", at)
        out = tuple(tuple(c.read(v, ctx, f"{at}[{i}][{j}]", key) for j, (c, v) in enumerate(zip(self.columns, row)))
                    for i, row in enumerate(raw))
        firsts = [row[0] for row in out]
        if any(b < a for a, b in zip(firsts, firsts[1:])):
            raise FieldError(f"the {self.names[0]}s must rise (a {self.names[0]} may repeat for a jump)", at)
        return out


@dataclass(frozen=True, eq=False)
class Record:
    """The keys of a TOML table: ``fields`` by key; any other key is refused. ``units``: the
    table may hold a ``units`` table (catalogs), whose units it and the tables inside it
    read over those of the tables around it."""

    fields: Mapping[str, Field]
    units: bool = False

    def read(self, raw, ctx: Context, at: str = "") -> dict:
        """``raw`` (the table at ``at``) as {key: value}: each given key read by its field,
        each missing one its default (None: left out); a missing required key, an unknown
        key, a key given without the key it needs (``when``) raises :class:`FieldError`."""
        allowed = [*self.fields, "units"] if self.units else list(self.fields)
        extra = sorted(set(raw) - set(allowed))
        if extra:
            raise FieldError(f"unknown key; {did_you_mean(extra[0], allowed, listed=99)}", join(at, extra[0]))
        if self.units:
            own = raw.get("units", {})
            if not isinstance(own, dict):
                raise FieldError("must be a table of unit texts", join(at, "units"))
            ctx = Context(ctx.notation, {**ctx.units, **own}, at)
        out = {}
        for key, spec in self.fields.items():
            if key in raw:
                out[key] = spec.read(raw[key], ctx, join(at, key), key)
            elif spec.required or spec.when and spec.when in raw:
                why = "; ".join(filter(None, (spec.help, "" if spec.required else f"needed with {spec.when}")))
                raise FieldError(f"missing ({why})" if why else "missing", join(at, key))
            elif spec.default is not None:
                out[key] = spec.default
        return out


@dataclass(frozen=True, eq=False)
class Section(Field):
    """A table, its keys those of ``record``."""

    record: Record = field(default_factory=lambda: Record({}))
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> dict:
        if not isinstance(raw, dict):
            self.refuse("a table", raw, at)
        return self.record.read(raw, ctx, at)


@dataclass(frozen=True, eq=False)
class Entries(Field):
    """An array of tables (``[[belts]]``), each read by ``record``: at least ``least``, at
    most ``most``."""

    record: Record = field(default_factory=lambda: Record({}))
    least: int = 0
    most: int | None = None
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> list[dict]:
        if not isinstance(raw, list) or not all(isinstance(e, dict) for e in raw) or len(raw) < self.least:
            self.refuse(f"an array of {self.least} or more tables" if self.least else "an array of tables", raw, at)
        if self.most is not None and len(raw) > self.most:
            raise FieldError(f"{len(raw)} [[{key or at}]] tables; at most {self.most}", at)
        return [self.record.read(e, ctx, f"{at}[{i}]") for i, e in enumerate(raw)]


@dataclass(frozen=True, eq=False)
class Named(Field):
    """A table of named values (``[service_factors.NAME]``, ``mass = { 1 = .., 3 = .. }``),
    each read by ``item`` (its unit under this table's key)."""

    item: Field = field(default_factory=Field)
    scalar: ClassVar[bool] = False

    def read(self, raw, ctx: Context, at: str = "", key: str = "") -> dict:
        if not isinstance(raw, dict):
            self.refuse("a table of named values", raw, at)
        return {name: self.item.read(v, ctx, join(at, name), key) for name, v in raw.items()}


# --- a file ---------------------------------------------------------------------------------------
class TomlFile:
    """One TOML file (:func:`read_toml`), read by a :class:`Record` of its top-level keys in
    its :class:`Notation`: ``values`` are the converted values. Every error is one
    :class:`~beltcalc.errors.CatalogError` naming the file, the element and the key."""

    def __init__(self, path, record: Record, notation: Notation = CATALOG, what: str = "catalog file"):
        self.path = path
        self.data = read_toml(path, what)
        try:
            self.values = record.read(self.data, Context(notation))
        except FieldError as exc:
            self.fail(exc.at, exc.message)

    def fail(self, at: str, message: str):
        """Raise the file's error about the key at ``at``."""
        raise CatalogError(f"{shown_path(self.path)}: {shown_key(at)}: {message}")
