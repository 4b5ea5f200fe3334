"""``beltcalc catalog list`` and ``beltcalc catalog show NAME``."""

from __future__ import annotations

import math
from dataclasses import fields

import click

from beltcalc.cli.options import catalog_option, output_options
from beltcalc.cli.output import (Row, console, dumps, display_unit, display_value, print_table, rows_csv, table_csv,
                                 write_atomic, wrote)

# Per kind and field: (SI unit as printed in JSON/CSV, display unit of the table).
_UNITS = {
    "belt": {"pitch": ("m", "mm"), "C_spec_per_F_Tadm": ("1", ""), "damping": ("N s/m", ""),
             "z_e_max": ("1", ""), "z_min": ("1", ""), "z_min_contraflexure": ("1", ""),
             "d_min": ("m", "mm"), "d_min_contraflexure": ("m", "mm")},
    "belt width": {"width": ("m", "mm"), "F_Tadm": ("N", ""), "C_spec": ("N", ""),
                   "w_spec": ("kg/m", ""), "breaking": ("N", "")},
    "F_tspec": {"speed": ("rad/s", "rpm"), "load": ("N/m", "N/cm")},
    "thread": {"d": ("m", "mm"), "P": ("m", "mm"), "d2": ("m", "mm"), "flank_angle": ("rad", "deg")},
    "chain": {"pitch": ("m", "mm"), "roller_diameter": ("m", "mm"), "inner_width": ("m", "mm"),
              "pin_diameter": ("m", "mm"), "transverse_pitch": ("m", "mm"), "breaking_load": ("N", "kN"),
              "mass": ("kg/m", ""), "strands": ("1", ""), "roller_bushing_constant": ("1", "")},
    "motor": {"P": ("W", ""), "T_n": ("N m", ""), "T_max": ("N m", ""), "J": ("kg m^2", "kg*cm^2"),
              "n_rated": ("rad/s", "rpm"), "n_max": ("rad/s", "rpm"), "efficiency": ("1", "")},
}


def _kind(entry) -> str:
    from beltcalc.data.catalogs import BeltProfile, Chain, Thread

    if isinstance(entry, Chain):
        return "chain"
    return "belt" if isinstance(entry, BeltProfile) else "thread" if isinstance(entry, Thread) else "motor"


def entry_rows(entry) -> list[Row]:
    """Every numeric value of a catalog entry as rows (SI), tables flattened by index."""
    kind = _kind(entry)
    rows = []
    for f in fields(entry):
        value = getattr(entry, f.name)
        if f.name in _UNITS[kind] and value is not None:
            unit, shown = _UNITS[kind][f.name]
            rows.append(Row(f.name, f.name, float(value), unit, shown))
    if kind == "belt":
        for i, w in enumerate(entry.widths):
            for key, (unit, shown) in _UNITS["belt width"].items():
                if getattr(w, key) is not None:
                    rows.append(Row(f"widths[{i}].{key}", f"width {w.width * 1e3:g} mm: {key}",
                                    getattr(w, key), unit, shown))
        for i, (speed, load) in enumerate(entry.F_tspec):
            for key, value in (("speed", speed), ("load", load)):
                unit, shown = _UNITS["F_tspec"][key]
                rows.append(Row(f"F_tspec[{i}].{key}", f"F_tspec[{i}] {key}", value, unit, shown))
    return rows


def _summary(entry) -> str:
    kind = _kind(entry)
    if kind == "belt":
        widths = "/".join(f"{w.width * 1e3:g}" for w in entry.widths) or "no width table"
        table = ", F_tspec(n)" if entry.F_tspec else ""
        unit = " mm" if entry.widths else ""
        return f"pitch {entry.pitch * 1e3:g} mm, widths {widths}{unit}{table}"
    if kind == "thread":
        return f"{entry.series} P = {entry.P * 1e3:g} mm, d2 = {entry.d2 * 1e3:.3f} mm"
    if kind == "chain":
        iso = f" (ISO {entry.iso}-{entry.strands})" if entry.iso else ""
        mass = f", {entry.mass:.3g} kg/m" if entry.mass is not None else ""
        return (f"{entry.series} series{iso}, pitch {entry.pitch * 1e3:g} mm, "
                f"F_B {entry.breaking_load / 1e3:.4g} kN{mass}")
    return (f"T_n {entry.T_n:g} N m, T_max {entry.T_max:g} N m, J {entry.J * 1e4:g} kg cm^2, "
            f"n_max {entry.n_max * 30 / math.pi:.0f} rpm")


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
def catalog():
    """List and show the belts, threads, motors and chains of the catalogs."""


@catalog.command("list")
@catalog_option
@output_options
def list_entries(catalog_paths, as_json, csv_path):
    """List every belt, thread and motor with a one-line summary and its source."""
    from beltcalc.data.catalogs import load_catalog

    cat = load_catalog(catalog_paths)
    groups = {"belts": cat.belts, "threads": cat.threads, "motors": cat.motors, "chains": cat.chains}
    records = [(kind, e.name, _summary(e), str(e.source)) for kind, table in groups.items()
               for e in table.values()]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(["kind", "name", "summary", "source"], records))
        wrote(csv_path)
    if as_json:
        click.echo(dumps({kind: [{"name": e.name, "summary": _summary(e), "source": str(e.source),
                                  "file": e.source.path} for e in table.values()]
                          for kind, table in groups.items()}))
        return
    from rich.table import Table

    table = Table(title="beltcalc catalogs", title_justify="left")
    for col in ("kind", "name", "summary", "source"):
        table.add_column(col, overflow="fold")
    for kind, name, summary, source in records:
        table.add_row(kind[:-1], name, summary, source.split(";")[0])
    console(140).print(table)


@catalog.command("show")
@click.argument("name")
@catalog_option
@output_options
def show(name, catalog_paths, as_json, csv_path):
    """Show one entry (belt, thread or motor) with every value, its unit and its source."""
    from beltcalc.data.catalogs import load_catalog

    entry = load_catalog(catalog_paths).entry(name)
    rows = entry_rows(entry)
    if csv_path is not None:
        write_atomic(csv_path, rows_csv(rows))
        wrote(csv_path)
    src = entry.source
    if as_json:
        obj = {"name": entry.name, "kind": _kind(entry),
               "source": {"document": src.document, "location": src.location,
                          "edition": src.edition, "file": src.path}}
        obj.update({r.key: {"value": r.value, "unit": r.unit} for r in rows})
        for key in ("note", "damping_source", "series"):
            if getattr(entry, key, ""):
                obj[key] = getattr(entry, key)
        click.echo(dumps(obj))
        return
    notes = [f"source: {src}", f"file: {src.path}"]
    for key in ("note", "damping_source"):
        if getattr(entry, key, ""):
            notes.append(f"{key}: {getattr(entry, key)}")
    if _kind(entry) == "belt" and entry.widths:
        print_belt(entry, notes)
    else:
        print_table(f"{_kind(entry)} {entry.name}", [("values", rows)], notes=notes)


def print_belt(entry, notes) -> None:
    """A belt as two tables: scalars and widths, then the F_tspec(n) table."""
    from rich.markup import escape
    from rich.table import Table

    rows = entry_rows(entry)
    scalars = [r for r in rows if "[" not in r.key]
    print_table(f"belt {entry.name}", [("values", scalars)])
    keys = [k for k in _UNITS["belt width"] if any(getattr(w, k) is not None for w in entry.widths)]
    by_key = {r.key: r for r in rows}
    table = Table(title=f"{entry.name}: width table", title_justify="left")
    for k in keys:
        row = by_key.get(f"widths[0].{k}") or next(r for r in rows if r.key.endswith(f".{k}"))
        table.add_column(escape(f"{k} [{display_unit(row)}]"), justify="right")
    for i, _ in enumerate(entry.widths):
        table.add_row(*(display_value(by_key[f"widths[{i}].{k}"]) if f"widths[{i}].{k}" in by_key else "-"
                        for k in keys))
    out = console()
    out.print(table)
    if entry.F_tspec:
        ft = Table(title=f"{entry.name}: specific tooth load F_tspec(n)", title_justify="left")
        ft.add_column(escape("n [rpm]"), justify="right")
        ft.add_column(escape("F_tspec [N/cm]"), justify="right")
        for i, _ in enumerate(entry.F_tspec):
            ft.add_row(display_value(by_key[f"F_tspec[{i}].speed"]), display_value(by_key[f"F_tspec[{i}].load"]))
        out.print(ft)
    for note in notes:
        out.print(note, highlight=False, markup=False)
