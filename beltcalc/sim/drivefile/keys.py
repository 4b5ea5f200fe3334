"""The keys of drive files: :class:`Key` (a key's SI unit, help, whether it is required and
its range), the :class:`Entry` of a file's element, the :class:`DriveParam` that ``--set``
addresses, and the conversion of a raw TOML value to SI (:func:`convert`), the one place a
drive file's text becomes numbers. The keys themselves are declared by the element kinds
(:mod:`beltcalc.sim.drivefile.kinds`, :mod:`beltcalc.sim.drivefile.motors`)."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from beltcalc.catalogs import read_toml, shown_path
from beltcalc.errors import CatalogError


class DriveFileError(CatalogError):
    """A drive file that cannot be read or built: the message names the file, the element
    and the key (exit 1)."""


@dataclass(frozen=True)
class Key:
    """A key a section accepts. ``unit``: SI unit (``""`` a plain number, ``"a|b"`` either
    dimension), ``"int"``, ``"bool"``, ``"text"``, ``"names"`` (node names), or ``"table:X,Y"``
    (a list of [X, Y] quantity pairs)."""

    unit: str
    help: str
    required: bool = False
    low: str = ""          # "": any value; ">0" positive; ">=0" not negative; "!=0" not zero
    when: str = ""         # needed when this other key is given (the docs' "required" column)

    @property
    def scalar(self) -> bool:
        """Whether ``--set ELEMENT.KEY=...`` can give it."""
        return self.unit not in ("names", "bool") and not self.unit.startswith("table:")


TORQUE = "N*m|N"


@dataclass(frozen=True)
class Entry:
    """One element of the file: its section, name, index in the section and raw values."""

    section: str
    name: str
    index: int
    raw: dict

    @property
    def where(self) -> str:
        return f"{self.section} {self.name!r}"


@dataclass(frozen=True)
class DriveParam:
    """A value of the file that ``--set``/``--sweep`` can address: ``ELEMENT.KEY`` (or a
    timing name), its SI unit (as :class:`Key`), the file's text (None: not given) and help."""

    name: str
    unit: str
    text: str | None
    help: str


def read_drive_toml(path: Path) -> dict:
    """The drive file ``path`` read by :func:`beltcalc.catalogs.read_toml` (bounded size and
    depth: a file nested 5,000 levels deep is one line, not a RecursionError), every
    failure a :class:`DriveFileError` naming the file."""
    try:
        return read_toml(path, "drive file")
    except CatalogError as exc:
        if not os.path.lexists(path):
            raise DriveFileError(f"{shown_path(path)}: no such drive file") from None
        raise DriveFileError(exc.message) from None


def text_of(value) -> str | None:
    """A raw value as the text ``--list-params`` shows (None: not given)."""
    if value is None:
        return None
    return str(value)


def out_of_range(value, spec: Key, unit: str) -> str:
    """Why ``value`` is outside its key's range, or ``""``."""
    if not spec.low or not isinstance(value, (int, float)) or isinstance(value, bool):
        return ""
    bad = {">0": value <= 0, ">=0": value < 0, "!=0": value == 0}[spec.low]
    if not bad:
        return ""
    u = "" if unit in ("", "int") else " " + unit.split("|")[0]
    if spec.low == "!=0":
        return f"{value:g}{u} is not allowed; it must not be 0{u} (negative: the pair turns the other way)"
    return f"{value:g}{u} is not allowed; it must be {spec.low[0:-1]} 0{u}"


def convert(raw, spec: Key, keep_unit: bool = False, si_numbers: bool = False):
    """A raw TOML value as its SI value (ValueError with the reason otherwise). A bare number
    is a plain number; for a quantity of a dimension it is refused (a file writes the unit),
    unless ``si_numbers`` (a drive built in code, in SI)."""
    from beltcalc.units import QuantityError, example_unit, parse_quantity, parse_quantity_any

    unit = spec.unit
    if unit == "text":
        if not isinstance(raw, str):
            raise ValueError(f"must be a text, not {raw!r}")
        return raw
    if unit == "bool":
        if not isinstance(raw, bool):
            raise ValueError(f"must be true or false, not {raw!r}")
        return raw
    if unit == "int":
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise ValueError(f"must be a whole number, not {raw!r}")
        return raw
    if unit.startswith("table:"):
        x_unit, y_unit = unit[6:].split(",")
        if not isinstance(raw, list) or not raw or not all(isinstance(p, list) and len(p) == 2 for p in raw):
            raise ValueError("must be a list of [time, value] pairs, e.g. [[\"0 s\", \"0 N*m\"], [\"1 s\", \"5 N*m\"]]")
        out = []
        for t, v in raw:
            out.append((convert(t, Key(x_unit, ""), si_numbers=si_numbers),
                        convert(v, Key(y_unit, ""), si_numbers=si_numbers)))
        times = [t for t, _ in out]
        if any(b < a for a, b in zip(times, times[1:])):
            raise ValueError("the times must rise (a time may repeat for a jump)")
        return tuple(out)
    if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
        raise ValueError(f"must be a quantity text such as '5 {example_unit(unit.split('|')[0])}', not {raw!r}")
    if isinstance(raw, str) and unit in ("", "1"):
        raise ValueError(f"must be a plain number, not the text {raw!r}: write it without quotes "
                         "(ratios, factors and slips are numbers, docs/drive_files.md)")
    if not isinstance(raw, str) and unit not in ("", "1"):
        if si_numbers:
            value = float(raw)
            return (value, unit.split("|")[0]) if keep_unit and "|" in unit else value
        example = raw if isinstance(raw, int) or math.isfinite(raw) else 1.0    # "inf s" is refused too
        texts = " or ".join(f'"{example:g} {example_unit(u)}"' for u in unit.split("|"))
        raise ValueError(f"{raw!r} needs its unit: write it as a text, e.g. {texts}")
    try:
        if isinstance(raw, str):
            got = quantity(raw, unit)
        else:
            got = parse_quantity_any(raw, tuple(unit.split("|"))) if "|" in unit else parse_quantity(raw, unit)
        if "|" in unit:
            value, u = got
            return (value, u) if keep_unit else value
        return got
    except QuantityError as exc:
        raise ValueError(str(exc)) from None


@lru_cache(maxsize=4096)
def quantity(raw: str, unit: str):
    """The text ``raw`` read as a quantity of ``unit`` (:func:`~beltcalc.units.parse_quantity`; of
    one of ``a|b``: (value, unit), :func:`~beltcalc.units.parse_quantity_any`). Each text
    is read by pint once per process: a build reads every value of the file, and a run
    builds its drive several times (the rigid notes, the error estimate, a sweep's points).
    A refusal is not kept: it is raised again, the same, on every call."""
    from beltcalc.units import parse_quantity, parse_quantity_any

    if "|" in unit:
        return parse_quantity_any(raw, tuple(unit.split("|")))
    return parse_quantity(raw, unit)
