"""What a calculation reports: rows of named quantities in SI, grouped in sections.

A :class:`Row` is one output quantity (SI value, SI unit, the unit to display it in); a
:class:`Section` is rows reported together. The command line renders the same rows as a
table, a JSON object and a CSV file, so the three never disagree; a Python user reads
them directly.
"""

from __future__ import annotations

from dataclasses import dataclass


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
