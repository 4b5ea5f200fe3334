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

from beltcalc.catalogs import CatalogReader, builtin_dir
from beltcalc.dutycycle import Gearbox
from beltcalc.errors import UnknownNameError, did_you_mean
from beltcalc.units import quote

_KEYS = {"ratio": "", "J": "kg*m^2", "efficiency": "", "efficiency_back": "", "n_max_in": "rad/s",
         "T_rated_out": "N*m", "T_peak_out": "N*m"}


def load_gearboxes(extra: Iterable[str | Path] = ()) -> dict[str, Gearbox]:
    """The built-in gearboxes (``catalogs/gearboxes/``) and those of the files ``extra``, by
    lower-case name. A malformed file is a CatalogError naming the file and the key."""
    folder = builtin_dir() / "gearboxes"
    paths = sorted(folder.glob("*.toml")) if folder.is_dir() else []
    out: dict[str, Gearbox] = {}
    for path in [*paths, *map(Path, extra)]:
        reader = CatalogReader(Path(path), allowed=("source", "units", "gearboxes"))
        for i, e in enumerate(reader.entries("gearboxes")):
            where = f"gearboxes[{i}]"
            reader.check_keys(e, _KEYS, where)
            nums = reader.numbers(e, _KEYS, reader.entry_units(e, where), where,
                                  required=("ratio", "J", "efficiency"), zero_ok=("J",))
            for key in ("efficiency", "efficiency_back"):
                if nums.get(key, 0.5) > 1:
                    reader.fail(f"{where}.{key}", "must be <= 1")
            name = reader.text(e, "name", where)
            if name.lower() in out:
                reader.fail(f"{where}.name", f"duplicate gearbox name {name!r}")
            out[name.lower()] = Gearbox(
                ratio=nums["ratio"], inertia=nums["J"], efficiency=nums["efficiency"],
                efficiency_back=nums.get("efficiency_back"), max_input_speed=nums.get("n_max_in"),
                rated_torque=nums.get("T_rated_out"), peak_torque=nums.get("T_peak_out"), name=name,
                source=str(reader.entry_source(e, where)))
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
