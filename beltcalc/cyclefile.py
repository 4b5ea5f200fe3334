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

from beltcalc.catalogs import read_toml
from beltcalc.errors import CatalogError, did_you_mean
from beltcalc.sizing import MoveSpec
from beltcalc.units import QuantityError, parse_quantity, parse_quantity_any

MAX_SEGMENTS = 10000
_SEGMENT_KEYS = {"kind", "name", "distance", "direction", "time", "speed", "accel", "jerk", "accel_fraction",
                 "jerk_fraction", "payload", "force"}
_CYCLE_KEYS = {"title", "speed", "accel", "jerk", "note"}
_ALTERNATIVES = {"speed": ("rad/s", "m/s"), "accel": ("rad/s^2", "m/s^2"), "jerk": ("rad/s^3", "m/s^3")}


@dataclass(frozen=True)
class CycleFile:
    title: str
    path: str
    segments: tuple[MoveSpec, ...]


def load_cycle(path: str | Path) -> CycleFile:
    """Read a cycle file into :class:`~beltcalc.sizing.MoveSpec` segments (SI).

    >>> from beltcalc.catalogs import builtin_dir
    >>> c = load_cycle(builtin_dir() / "cycles" / "pick_place_vertical.toml")
    >>> [s.kind for s in c.segments][:3], c.segments[0].direction
    (['move', 'dwell', 'move'], -1)
    """
    path = Path(path)
    data = read_toml(path, "cycle file")    # bounded size and depth: 5,000 levels is one line

    def fail(key: str, message: str):
        raise CatalogError(f"{path}: {key}: {message}")

    extra = set(data) - {"cycle", "segment", "source"}
    if extra:
        key = sorted(extra)[0]
        fail(key, f"unknown top-level key; {did_you_mean(key, ('cycle', 'segment', 'source'))}")
    head = data.get("cycle", {})
    if not isinstance(head, dict):
        fail("cycle", "must be a table")
    extra = set(head) - _CYCLE_KEYS
    if extra:
        fail(f"cycle.{sorted(extra)[0]}", f"unknown key; {did_you_mean(sorted(extra)[0], sorted(_CYCLE_KEYS))}")
    segs = data.get("segment")
    if not isinstance(segs, list) or not segs or not all(isinstance(s, dict) for s in segs):
        fail("segment", "a cycle needs one or more [[segment]] tables")
    if len(segs) > MAX_SEGMENTS:
        fail("segment", f"{len(segs)} segments; at most {MAX_SEGMENTS}")

    def quantity(entry: dict, key: str, where: str, unit: str):
        return _quantity(entry, key, unit, lambda k, m: fail(f"{where}.{k}", m))

    defaults = {k: quantity(head, k, "cycle", "") for k in ("speed", "accel", "jerk") if k in head}
    out = []
    for n, e in enumerate(segs):
        where = f"segment[{n}]"
        out.append(_segment(e, lambda key, message, where=where: fail(f"{where}.{key}", message),
                            lambda entry, key, unit, where=where: quantity(entry, key, where, unit), defaults))
    title = head.get("title", path.stem)
    return CycleFile(title=str(title), path=str(path), segments=tuple(out))


def _quantity(entry: dict, key: str, unit: str, fail):
    """``entry[key]`` in SI (``(value, unit)`` for speed, accel and jerk); ``fail(key, message)``."""
    text = entry[key]
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        fail(key, f"{text!r} is not a quantity")
    try:
        if key in _ALTERNATIVES:
            return parse_quantity_any(text, _ALTERNATIVES[key])
        return parse_quantity(text, unit)
    except QuantityError as exc:
        fail(key, str(exc))


def _segment(e: dict, fail, quantity, defaults: dict) -> MoveSpec:
    """One segment (a file's ``[[segment]]`` table or the keys of :func:`parse_segments`) as a
    :class:`~beltcalc.sizing.MoveSpec`; ``fail(key, message)`` raises, ``quantity(entry, key,
    unit)`` reads a value; ``defaults``: speed, accel, jerk of the moves that give none."""
    extra = set(e) - _SEGMENT_KEYS
    if extra:
        fail(sorted(extra)[0], f"unknown key; {did_you_mean(sorted(extra)[0], sorted(_SEGMENT_KEYS), listed=99)}")
    kind = e.get("kind")
    if kind not in ("move", "dwell"):
        fail("kind", f"{kind!r}; use \"move\" or \"dwell\"")
    name = e.get("name", "")
    if not isinstance(name, str):
        fail("name", "must be a text")
    direction = e.get("direction", "+")
    if direction not in ("+", "-"):
        fail("direction", f"{direction!r}; use \"+\" or \"-\"")
    values = {}
    for key, unit in (("distance", "m"), ("time", "s"), ("payload", "kg"), ("force", "N"),
                      ("accel_fraction", ""), ("jerk_fraction", ""), ("speed", ""), ("accel", ""),
                      ("jerk", "")):
        if key in e:
            values[key] = quantity(e, key, unit)
    if kind == "dwell":
        bad = set(values) - {"time", "payload", "force"}
        if bad:
            fail(sorted(bad)[0], "not a key of a dwell (a dwell has time, payload, force)")
        if "time" not in values:
            fail("time", "missing: a dwell needs its time")
    else:
        if "distance" not in values:
            fail("distance", "missing: a move needs its distance")
        if "time" in values and ({"speed", "accel", "jerk"} & set(values)):
            fail("time", "give a move either time or speed/accel/jerk, not both")
        if "time" not in values:
            for key in ("speed", "accel"):
                values.setdefault(key, defaults.get(key))
            values.setdefault("jerk", defaults.get("jerk"))
    return MoveSpec(kind=kind, name=name, direction=1 if direction == "+" else -1, **values)


def parse_segments(texts, what: str = "segment") -> tuple[MoveSpec, ...]:
    """Segments from texts ``KIND: KEY=VALUE, KEY=VALUE, ...`` (one per segment, in order), with
    the keys of a cycle file's ``[[segment]]`` (KIND ``move`` or ``dwell``): the same
    :class:`~beltcalc.sizing.MoveSpec` as :func:`load_cycle` gives for the same segments.
    A move without speed, accel or jerk takes the caller's defaults (MoveSpec's None).

    A text that cannot be read is a :class:`~beltcalc.errors.UsageError` (``param=what``)
    quoting it.

    >>> [(s.kind, s.distance, s.direction, s.payload) for s in parse_segments(
    ...     ["move: distance=400mm, direction=-", "dwell: time=0.3s", "move: distance=0.4m, payload=10kg"])]
    [('move', 0.4, -1, 0.0), ('dwell', 0.0, 1, 0.0), ('move', 0.4, 1, 10.0)]
    """
    from beltcalc.errors import UsageError
    from beltcalc.units import quote

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
        out.append(_segment(entry, fail, lambda e, key, unit, fail=fail: _quantity(e, key, unit, fail), {}))
    return tuple(out)
