"""What a calculation reports: rows of named quantities in SI, grouped in sections.

A :class:`Row` is one output quantity (SI value, SI unit, the unit to display it in); a
:class:`Section` is rows reported together. The command line renders the same rows as a
table, a JSON object and a CSV file, so the three never disagree; a Python user reads
them directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# A JSON value that is not a finite number: null, and why.
BEYOND = "beyond the range of a float: an input is out of a physical range"


def format_number(value: float, digits: int = 4) -> str:
    """``digits`` significant digits, plain decimals from 1e-4 to 1e7, integers as integers
    ('-' for a value that is not a finite number): how tables print numbers.

    >>> format_number(13.004, 3), format_number(350000.0), format_number(0.073), format_number(16.0)
    ('13.0', '350000', '0.07300', '16')
    >>> format_number(None), format_number(2e-9)
    ('-', '2.0000e-09')
    """
    if value is None or not math.isfinite(value):
        return "-"
    if value == int(value) and abs(value) < 1e7:
        return str(int(value))
    mag = math.floor(math.log10(abs(value)))
    if -4 <= mag < 7:
        return f"{value:.{max(digits - 1 - mag, 0)}f}"
    return f"{value:.{digits}g}"


def unit_label(unit: str) -> str:
    """A unit as a table or axis shows it: ``N m``, ``rad/s``, ``-`` for a plain number.

    >>> unit_label("N*m"), unit_label("rad/s^2"), unit_label("1")
    ('N m', 'rad/s^2', '-')
    """
    unit = "" if unit in ("1", "") else unit.replace("**", "^").replace("*", " ")
    return unit or "-"


def denoise(x: float) -> float:
    """Rounding noise off a displayed figure (an undamped mode's 1e-17 damping ratio, a node
    at rest's phase): ``x`` to 9 decimals, never -0.0.

    >>> denoise(1e-17), denoise(-1e-12), denoise(0.0312345678912)
    (0.0, 0.0, 0.031234568)
    """
    return round(x, 9) + 0.0


def rpm(speed: float) -> float:
    """A speed [rad/s] in revolutions per minute."""
    return speed * 60.0 / (2 * math.pi)


def quantity(value, unit: str) -> dict:
    """``{"value", "unit"}`` of a JSON object; a value that is not a finite number is null with
    the reason."""
    if isinstance(value, float) and not math.isfinite(value):
        return {"value": None, "unit": unit, "reason": BEYOND}
    return {"value": value, "unit": unit}


@dataclass(frozen=True)
class Row:
    """One output quantity. ``unit`` is the SI unit of ``value`` as printed in JSON/CSV
    ("1" for a plain number); ``display`` is the unit of the table (a pint unit string)."""

    key: str
    label: str
    value: float
    unit: str
    display: str = ""
    digits: int = 4
    note: str = ""


@dataclass(frozen=True)
class Section:
    """Rows reported together: ``path`` places them in the JSON (("shafts", "main")),
    ``group`` prints sections of one group as one table with a row per ``item``; ``key``
    names the rows in a sweep's or study's column keys (default: the last part of ``path``;
    :meth:`beltcalc.sim.scenes.base.Outcome.column_rows`)."""

    path: tuple[str, ...]
    title: str
    rows: list[Row]
    group: str = ""
    item: str = ""
    key: str = ""


@dataclass(frozen=True)
class Column:
    """One column of a sweep or study: ``key`` (a CSV/JSON name), a readable ``label``, the
    SI ``unit`` of its values, the ``display`` unit of a table or plot, and (for one run)
    its ``value``."""

    key: str
    label: str
    unit: str
    display: str
    value: float | None = None
