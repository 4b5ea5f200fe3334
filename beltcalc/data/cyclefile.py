"""Duty-cycle files (TOML) for ``beltcalc motor-size --cycle``: loaded and converted to SI once.

A cycle file has a ``[cycle]`` table (``title``; optional defaults ``speed``, ``accel``,
``jerk`` for every move) and one ``[[segment]]`` table per move or dwell, in order::

    [cycle]
    title = "Pick and place on a vertical axis"
    speed = "1 m/s"            # at the carriage (m/s) or the motor (rpm, rad/s)
    accel = "5 m/s^2"
    jerk = "100 m/s^3"         # optional: S-curves; leave out for trapezoids

    [[segment]]
    kind = "move"              # move | dwell
    name = "down, empty"
    distance = "300 mm"
    direction = "-"            # + or - along the axis (+ is up on a vertical axis)
    payload = "0 kg"           # carried in this segment, on top of the carriage mass
    force = "0 N"              # move: process force against the motion

    [[segment]]
    kind = "dwell"
    time = "0.2 s"
    force = "30 N"             # dwell: force on the carriage towards -, held by the drive

A move may give ``time`` (with ``accel_fraction`` T_a/T, default 1/3, and
``jerk_fraction`` T_j/T_a, default 0) instead of speed and acceleration. The same segments
may be given as texts ``KIND: KEY=VALUE, ...`` (:func:`parse_segments`, ``motor-size
--segment``). Every value is a
quantity with its unit (plain numbers for the fractions). A malformed file is one
:class:`~beltcalc.errors.CatalogError` naming the file and the key.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from beltcalc.data.catalogs import SOURCE
from beltcalc.data.schema import (QUANTITIES, Choice, Context, Entries, FieldError, Quantity, Record, Section, Text,
                             TomlFile)
from beltcalc.formulas.profiles import MoveSpec

MAX_SEGMENTS = 10000
LIMITS = {   # a move's limits, at the motor (rotation) or at the carriage: read as (value, unit)
    "speed": Quantity("rad/s|m/s", keep_unit=True, help="speed limit: at the motor (rpm, rad/s) or the carriage (m/s)"),
    "accel": Quantity("rad/s^2|m/s^2", keep_unit=True, help="acceleration limit, at the motor or the carriage"),
    "jerk": Quantity("rad/s^3|m/s^3", keep_unit=True, help="jerk limit (an S-curve), at the motor or the carriage"),
}
SEGMENT = Record({
    "kind": Choice(choices=("move", "dwell"), required=True, help='"move" or "dwell"'),
    "name": Text(help="what the segment does"),
    "direction": Choice(choices=("+", "-"), help="+ or - along the axis (+ is up on a vertical axis)"),
    "distance": Quantity("m", help="a move's carriage travel"),
    "time": Quantity("s", help="a dwell's time, or a move's instead of its limits"),
    "payload": Quantity("kg", help="carried on top of the carriage mass"),
    "force": Quantity("N", help="a move's process force against the motion; a dwell's force towards -"),
    "accel_fraction": Quantity("", help="T_a / T of a move by time"),
    "jerk_fraction": Quantity("", help="T_j / T_a of a move by time"),
    **LIMITS,
})
CYCLE = Record({"title": Text(numbers=True, help="the cycle's title"), **LIMITS, "note": Text(help="a remark")})
CYCLE_FILE = Record({
    "cycle": Section(record=CYCLE, help="the title, and the limits of every move that gives none"),
    "segment": Entries(record=SEGMENT, required=True, least=1, most=MAX_SEGMENTS,
                       help="a cycle needs one or more [[segment]] tables"),
    "source": Section(record=SOURCE, help="where the cycle comes from"),
})


@dataclass(frozen=True)
class CycleFile:
    title: str
    path: str
    segments: tuple[MoveSpec, ...]


def load_cycle(path: str | Path) -> CycleFile:
    """Read a cycle file into :class:`~beltcalc.formulas.profiles.MoveSpec` segments (SI).

    >>> from beltcalc.data.catalogs import builtin_dir
    >>> c = load_cycle(builtin_dir() / "cycles" / "pick_place_vertical.toml")
    >>> [s.kind for s in c.segments][:3], c.segments[0].direction
    (['move', 'dwell', 'move'], -1)
    """
    path = Path(path)
    file = TomlFile(path, CYCLE_FILE, QUANTITIES, "cycle file")   # bounded size and depth: 5,000 levels is one line
    head = file.values.get("cycle", {})
    defaults = {k: v for k, v in head.items() if k in LIMITS}
    out = []
    for n, values in enumerate(file.values["segment"]):
        try:
            out.append(move_spec(values, defaults))
        except FieldError as exc:
            file.fail(f"segment[{n}].{exc.at}", exc.message)
    return CycleFile(title=head.get("title", path.stem), path=str(path), segments=tuple(out))


def move_spec(values: dict, defaults: dict) -> MoveSpec:
    """A segment's values (as :data:`SEGMENT` reads them) as a :class:`~beltcalc.formulas.profiles.MoveSpec`,
    or a :class:`~beltcalc.data.schema.FieldError` at the key a move or a dwell may not have or
    needs; ``defaults``: speed, accel, jerk of the moves that give none."""
    values = dict(values)
    kind, name, direction = values.pop("kind"), values.pop("name", ""), values.pop("direction", "+")
    if kind == "dwell":
        bad = set(values) - {"time", "payload", "force"}
        if bad:
            raise FieldError("not a key of a dwell (a dwell has time, payload, force)", sorted(bad)[0])
        if "time" not in values:
            raise FieldError("missing: a dwell needs its time", "time")
    else:
        if "distance" not in values:
            raise FieldError("missing: a move needs its distance", "distance")
        if "time" in values and ({"speed", "accel", "jerk"} & set(values)):
            raise FieldError("give a move either time or speed/accel/jerk, not both", "time")
        if "time" not in values:
            for key in LIMITS:
                values.setdefault(key, defaults.get(key))
    return MoveSpec(kind=kind, name=name, direction=1 if direction == "+" else -1, **values)


def parse_segments(texts, what: str = "segment") -> tuple[MoveSpec, ...]:
    """Segments from texts ``KIND: KEY=VALUE, KEY=VALUE, ...`` (one per segment, in order), with
    the keys of a cycle file's ``[[segment]]`` (KIND ``move`` or ``dwell``): the same
    :class:`~beltcalc.formulas.profiles.MoveSpec` as :func:`load_cycle` gives for the same segments.
    A move without speed, accel or jerk takes the caller's defaults (MoveSpec's None).

    A text that cannot be read is a :class:`~beltcalc.errors.UsageError` (``param=what``)
    quoting it.

    >>> [(s.kind, s.distance, s.direction, s.payload) for s in parse_segments(
    ...     ["move: distance=400mm, direction=-", "dwell: time=0.3s", "move: distance=0.4m, payload=10kg"])]
    [('move', 0.4, -1, 0.0), ('dwell', 0.0, 1, 0.0), ('move', 0.4, 1, 10.0)]
    """
    from beltcalc.errors import UsageError
    from beltcalc.data.tomlsafe import quote

    texts = list(texts)
    if len(texts) > MAX_SEGMENTS:
        raise UsageError(f"{len(texts)} segments; at most {MAX_SEGMENTS}", param=what)
    out = []
    for text in texts:
        def fail(key: str, message: str, text=text):
            raise UsageError(f"{quote(text)}: {key}: {message}", param=what)

        kind, sep, rest = text.partition(":")
        entry: dict = {"kind": kind.strip()}
        if not sep or entry["kind"] not in ("move", "dwell"):
            fail("kind", "use 'move: KEY=VALUE, ...' or 'dwell: time=..., ...'")
        for item in filter(None, (p.strip() for p in rest.split(","))):
            key, eq, value = item.partition("=")
            key = key.strip()
            if not eq or not key:
                fail(item, "use KEY=VALUE")
            if key in entry:
                fail(key, "given twice")
            entry[key] = value.strip()
        try:
            out.append(move_spec(SEGMENT.read(entry, Context(QUANTITIES)), {}))
        except FieldError as exc:
            fail(exc.at, exc.message)
    return tuple(out)
