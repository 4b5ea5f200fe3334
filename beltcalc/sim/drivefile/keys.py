"""What drive files are made of: the :class:`Entry` of a file's element, the
:class:`DriveParam` that ``--set`` addresses, and reading a file's TOML
(:func:`read_drive_toml`). The keys are fields of the one typed schema
(:mod:`beltcalc.data.schema`: :class:`~beltcalc.data.schema.Quantity`, :class:`~beltcalc.data.schema.Whole`,
:class:`~beltcalc.data.schema.Flag`, :class:`~beltcalc.data.schema.Text`, :class:`~beltcalc.data.schema.Names`,
:class:`~beltcalc.data.schema.Table`), declared by the element kinds
(:mod:`beltcalc.sim.drivefile.kinds`, :mod:`beltcalc.sim.drivefile.motors`), which read a
drive file's texts into SI numbers."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from beltcalc.errors import CatalogError
from beltcalc.data.tomlsafe import read_toml, shown_path


class DriveFileError(CatalogError):
    """A drive file that cannot be read or built: the message names the file, the element
    and the key (exit 1)."""


#: the unit of a torque that acts on a rotating node, or a force on a translating one
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
    timing name), its unit (a quantity's SI unit, ``""`` a plain number, ``"a|b"`` either
    dimension; ``"int"`` a whole number, ``"text"`` a text), the file's text (None: not
    given) and help."""

    name: str
    unit: str
    text: str | None
    help: str


def read_drive_toml(path: Path) -> dict:
    """The drive file ``path`` read by :func:`beltcalc.data.tomlsafe.read_toml` (bounded size and
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
