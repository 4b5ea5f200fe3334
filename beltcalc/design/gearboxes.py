"""Gearbox catalog files (``catalogs/gearboxes/*.toml`` and the user's ``--gearbox-catalog``):
ratio, inertia at the input, efficiency (driving and back-driven), maximum input speed,
rated and peak output torque, each entry with its source.

The format is that of the other catalog files (``[source]``, ``units``, one
``[[gearboxes]]`` table per gearbox)::

    [source]
    document = "Acme planetary gearboxes, catalogue 2026"
    location = "page 14, table 'PL60'"

    [[gearboxes]]
    name = "PL60-10"
    ratio = 10
    J = 0.061                    # at the input
    efficiency = 0.96            # motor drives
    efficiency_back = 0.94       # optional: the load drives (default: as driving)
    n_max_in = 6000              # optional: maximum input speed
    T_rated_out = 20             # optional: rated (continuous) output torque, checked on the RMS
    T_peak_out = 32              # optional: peak output torque (acceleration torque)
    units = { J = "kg*cm^2", n_max_in = "rpm", T_rated_out = "N*m", T_peak_out = "N*m" }

No gearbox data is built in: no public data sheet with every value was at hand when this
was written, and a catalog value is never a guess. Give your gearbox's data sheet as a file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from beltcalc.data.catalogs import ENTRY_TEXTS, SOURCE, builtin_dir, file_source
from beltcalc.design.dutycycle import Gearbox
from beltcalc.errors import UnknownNameError, did_you_mean
from beltcalc.data.schema import Entries, Quantity, Record, Section, Text, TomlFile
from beltcalc.units import quote

GEARBOX = Record({
    "name": Text(name=True, required=True, help="e.g. PL60-10"), "series": Text(name=True, help="the series"),
    "ratio": Quantity("", help="ratio, input speed / output speed", required=True, low=">0"),
    "J": Quantity("kg*m^2", help="inertia at the input", required=True, low=">=0"),
    "efficiency": Quantity("", help="efficiency, the motor driving", required=True, low=">0", high=1.0),
    "efficiency_back": Quantity("", help="efficiency, the load driving", low=">0", high=1.0),
    "n_max_in": Quantity("rad/s", help="maximum input speed", low=">0"),
    "T_rated_out": Quantity("N*m", help="rated (continuous) output torque", low=">0"),
    "T_peak_out": Quantity("N*m", help="peak output torque", low=">0"), **ENTRY_TEXTS,
}, units=True)
GEARBOX_FILE = Record({"source": Section(record=SOURCE, required=True, help="[source] with a document"),
                       "gearboxes": Entries(record=GEARBOX)}, units=True)


def load_gearboxes(extra: Iterable[str | Path] = ()) -> dict[str, Gearbox]:
    """The built-in gearboxes (``catalogs/gearboxes/``) and those of the files ``extra``, by
    lower-case name. A malformed file is a CatalogError naming the file and the key."""
    folder = builtin_dir() / "gearboxes"
    paths = sorted(folder.glob("*.toml")) if folder.is_dir() else []
    out: dict[str, Gearbox] = {}
    for path in [*paths, *map(Path, extra)]:
        file = TomlFile(Path(path), GEARBOX_FILE)
        source = file_source(file)
        for i, e in enumerate(file.values.get("gearboxes", [])):
            name = e["name"]
            if name.lower() in out:
                file.fail(f"gearboxes[{i}].name", f"duplicate gearbox name {name!r}")
            out[name.lower()] = Gearbox(
                ratio=e["ratio"], inertia=e["J"], efficiency=e["efficiency"],
                efficiency_back=e.get("efficiency_back"), max_input_speed=e.get("n_max_in"),
                rated_torque=e.get("T_rated_out"), peak_torque=e.get("T_peak_out"), name=name,
                source=str(source.within(e.get("source"))))
    return out


def gearbox(name: str, extra: Iterable[str | Path] = ()) -> Gearbox:
    """A gearbox by name from :func:`load_gearboxes`, or :class:`UnknownNameError`."""
    table = load_gearboxes(extra)
    if name.strip().lower() in table:
        return table[name.strip().lower()]
    known = sorted(g.name for g in table.values())
    if not known:
        raise UnknownNameError(f"unknown gearbox {quote(name)}; the gearbox catalogs have none "
                               "(give `gearbox_catalog`)", param="gearbox")
    raise UnknownNameError(f"unknown gearbox {quote(name)}; {did_you_mean(name, known)}", param="gearbox")
