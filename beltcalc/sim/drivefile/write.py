"""Writing a drive file: :func:`to_toml`, a drive described in code as drive-file text."""

from __future__ import annotations

from beltcalc.data.schema import Names, Quantity, Table, Text
from beltcalc.sim.drivefile.reader import DriveFile


def to_toml(data: dict, header: str = "") -> str:
    """A drive described in code (:meth:`DriveFile.from_data`, SI floats) as drive-file text:
    every quantity written with its SI unit (exact: ``repr`` of the float), ``header`` as
    comment lines on top. Reading the text back builds the same drive.

    >>> print(to_toml({"drive": {"t_end": 1.0}, "node": [{"name": "a", "inertia": 0.5}]}))
    [drive]
    t_end = "1.0 s"
    <BLANKLINE>
    [[node]]
    name = "a"
    inertia = "0.5 kg*m^2"
    <BLANKLINE>
    """
    import json

    f = DriveFile.from_data(data, "<data>")

    def value(raw, spec) -> str:
        if isinstance(raw, bool):
            return "true" if raw else "false"
        if isinstance(spec, (Text, Names)):
            return json.dumps(raw)
        if isinstance(spec, Table):
            x, y = spec.columns
            return "[" + ", ".join(f"[{value(t, x)}, {value(v, y)}]" for t, v in raw) + "]"
        if isinstance(raw, str) or not isinstance(spec, Quantity) or not spec.unit:
            return json.dumps(raw) if isinstance(raw, str) else repr(raw)
        return json.dumps(f"{float(raw)!r} {spec.unit.split('|')[0]}")

    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    if lines:
        lines.append("")
    lines.append("[drive]")
    lines += [f"{k} = {value(v, f.field_of(f.head, k))}" for k, v in f.head.raw.items()]
    for e in f.entries:
        lines += ["", f"[[{e.section}]]"]
        lines += [f"{k} = {value(v, f.field_of(e, k))}" for k, v in e.raw.items()]
    return "\n".join(lines) + "\n"
