"""Named parameters of a scene: their units, their values from a scene file, and the
``NAME=QUANTITY`` and ``NAME=START:STOP:N`` texts that change them.

A :class:`Param` says what a value is (an SI quantity, a whole number, a text, or one of
several dimensions). :func:`resolve` takes each value from what the caller gives, else from
the scene file (``catalogs/scenes/*.toml``, read by :func:`beltcalc.data.scenefile.load_scene`),
converted to SI once, and says where it came from. :func:`parse_assignments` and
:func:`sweep_points` read the texts a user types; what they cannot read is a
:class:`~beltcalc.errors.UsageError` naming the input (``set``, ``sweep``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Iterable, Mapping, Sequence


MAX_SAMPLES = 10_000_000
# Values that size an allocation, bounded as the options that set them are, whether given
# as an option, by --set/--sweep or in a scene file: name -> (lowest, highest, the bound's name).
LIMITS = {"samples": (2, MAX_SAMPLES, "--samples")}


@dataclass(frozen=True)
class Param:
    """A parameter of a scene. ``unit``: SI unit (``""`` a plain number, ``"a|b"`` either
    dimension, the value then ``(float, unit)``), ``"int"`` a whole number, or ``None`` a
    name (text). ``required``: the scene (or the caller) must give it."""

    name: str
    unit: str | None
    help: str
    required: bool = True

    def parse(self, text: str) -> object:
        """The value of ``text`` in this parameter's unit (SI float, ``(float, unit)``, int or text).

        Raises :class:`~beltcalc.units.QuantityError` or ``ValueError`` when it cannot be read.

        >>> Param("C4", "N*m/rad", "stiffness").parse("0.19 kN*m/rad")
        190.0
        """
        from beltcalc.units import MAX_TEXT, QuantityError, parse_quantity, parse_quantity_any, quote

        if len(text) > MAX_TEXT:
            raise QuantityError(f"{quote(text)} is too long (at most {MAX_TEXT} characters)")
        if self.unit is None:
            return text.strip()
        if self.unit == "int":
            if not re.fullmatch(r"\s*[+-]?[0-9]+\s*", text):
                raise QuantityError(f"{quote(text)} is not a whole number, e.g. '{self.name}=20'")
            value = int(text)
        elif "|" in self.unit:
            value = parse_quantity_any(text, tuple(self.unit.split("|")))
        else:
            value = parse_quantity(text, self.unit)
        cap = LIMITS.get(self.name)
        if cap is not None and not cap[0] <= (value[0] if isinstance(value, tuple) else value) <= cap[1]:
            raise QuantityError(f"{quote(text)} is outside {cap[0]:,}..{cap[1]:,} (the limit of {cap[2]})")
        return value

    def text(self, value: object) -> str:
        """``value`` as text with its unit (what a report of the inputs shows).

        >>> Param("mass", "kg", "moving mass").text(60.0), Param("speed", "rad/s|m/s", "").text((2.0, "m/s"))
        ('60 kg', '2 m/s')
        """
        if isinstance(value, tuple):
            return f"{value[0]:g} {value[1]}"
        if isinstance(value, float):
            return f"{value:g} {self.unit}".strip()
        return str(value)


@dataclass(frozen=True)
class Resolved:
    """A parameter's value (SI float, ``(float, unit)``, int or text), its text and origin:
    ``"given"`` (by the caller) or ``"scene: <why>"`` (the scene file's reason)."""

    value: object
    text: str
    origin: str

    @property
    def given(self) -> bool:
        """True when the caller gave the value (not the scene file)."""
        return self.origin == "given"


def resolve(scene, params: Sequence[Param], given: Mapping[str, object] | None = None) -> dict[str, Resolved]:
    """Each parameter from ``given`` (SI values; None = not given), else from the scene file.

    ``scene`` is a :class:`beltcalc.data.catalogs.Scene`. A scene value that cannot be read, a
    key that is no parameter, or a required value that is missing, is a
    :class:`~beltcalc.errors.CatalogError` naming the scene file and the key (a missing
    one also names the parameter, ``scope="scene"``: it may be given instead).
    """
    from beltcalc.errors import CatalogError, did_you_mean
    from beltcalc.units import QuantityError

    given = given or {}
    known = {p.name for p in params}
    for key in scene.values:
        if key not in known:
            raise CatalogError(f"{scene.source.path}: parameters.{key}: not a parameter of this scene; "
                               + did_you_mean(key, [p.name for p in params]))
    out = {}
    for p in params:
        if given.get(p.name) is not None:
            out[p.name] = Resolved(given[p.name], p.text(given[p.name]), "given")
            continue
        if p.name not in scene.values:
            if p.required:
                raise CatalogError(f"{scene.source.path}: parameters.{p.name}: missing", param=p.name,
                                   scope="scene")
            continue
        text, why = scene.values[p.name]
        try:
            value = p.parse(text)
        except (QuantityError, ValueError) as exc:
            raise CatalogError(f"{scene.source.path}: parameters.{p.name}: {exc}") from None
        out[p.name] = Resolved(value, text, f"scene: {why}")
    return out


def parse_assignments(params: Sequence[Param], items: Iterable[str]) -> dict[str, object]:
    """``NAME=QUANTITY`` texts -> {name: value in the parameter's unit}.

    An unknown name or a value that cannot be read is a :class:`~beltcalc.errors.UsageError`
    (``param="set"``) quoting the text.

    >>> parse_assignments([Param("C4", "N*m/rad", "stiffness")], ["C4=190 N*m/rad"])
    {'C4': 190.0}
    >>> parse_assignments([Param("C4", "N*m/rad", "stiffness")], ["C4=190"])
    Traceback (most recent call last):
    ...
    beltcalc.errors.UsageError: set: 'C4=190': C4 needs a unit, e.g. 'C4=190 N*m/rad'
    """
    from beltcalc.errors import UsageError
    from beltcalc.units import QuantityError, example_unit, quote

    by_name = {p.name: p for p in params}
    out = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep:
            raise UsageError(f"{quote(item)}: use NAME=QUANTITY; {_names_hint(name, list(by_name))}", param="set")
        if name not in by_name:
            raise UsageError(f"{quote(item)}: {quote(name)} is not a value here; {_names_hint(name, list(by_name))}",
                             param="set")
        param = by_name[name]
        try:
            out[name] = param.parse(text)
        except (QuantityError, ValueError) as exc:
            message = str(exc)
            if bare_number(text) and param.unit not in (None, "", "int"):
                examples = " or ".join(f"'{name}={text.strip()} {example_unit(u)}'" for u in param.unit.split("|"))
                message = f"{name} needs a unit, e.g. {examples}"
            raise UsageError(f"{quote(item)}: {message}", param="set") from None
    return out


def bare_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def linspace(start: float, stop: float, n: int) -> list[float]:
    """``n`` evenly spaced values from ``start`` to ``stop`` inclusive.

    >>> linspace(0.0, 1.0, 3)
    [0.0, 0.5, 1.0]
    """
    from beltcalc.errors import InputError

    if n < 1:
        raise InputError(f"{n} points; a sweep needs at least 1", param="sweep")
    if n == 1:
        return [start]
    return [start + (stop - start) * k / (n - 1) for k in range(n)]


def _names_hint(name: str, names: list[str]) -> str:
    """The three names closest to ``name`` and how many there are, or all of them where they
    are few (:func:`~beltcalc.errors.did_you_mean`).

    >>> _names_hint("uper.pretension", [f"e{k}.x" for k in range(70)] + ["upper.pretension"])
    'did you mean upper.pretension, e9.x, e8.x? (71 names)'
    """
    from beltcalc.errors import did_you_mean

    return did_you_mean(name, names)


def sweep_points(params: Sequence[Param], text: str, example: str = "") -> tuple[str, list[float]]:
    """``NAME=START:STOP:N`` -> (name, N evenly spaced values from START to STOP).

    START and STOP are read as ``--set NAME=...`` reads a value: with units for a quantity
    (``C4=50N*m/rad:310N*m/rad:14``), a bare number for a plain number or a whole number.
    A text, a parameter of several dimensions, a malformed range, N outside 1..10000 or a
    whole-number parameter whose points are not whole is a
    :class:`~beltcalc.errors.UsageError` (``param="sweep"``) quoting ``text``; ``example``
    is shown with the expected form.

    >>> sweep_points([Param("C4", "N*m/rad", "stiffness")], "C4=50N*m/rad:310N*m/rad:3")
    ('C4', [50.0, 180.0, 310.0])
    >>> sweep_points([Param("C4", "N*m/rad", "stiffness")], "C4=50:310:3")
    Traceback (most recent call last):
    ...
    beltcalc.errors.UsageError: sweep: 'C4=50:310:3': C4 needs units on START and STOP, e.g. 'C4=50N*m/rad:310N*m/rad:3'
    """
    from beltcalc.errors import UsageError
    from beltcalc.units import example_unit, quote

    name, sep, rng = text.partition("=")
    parts = rng.split(":")
    if not sep or len(parts) != 3:
        raise UsageError(f"{quote(text)}: use NAME=START:STOP:N, e.g. {example}", param="sweep")
    param = next((p for p in params if p.name == name), None)
    if param is not None and (param.unit is None or "|" in param.unit):
        raise UsageError(f"{quote(text)}: {name} cannot be swept (it is not a single quantity)", param="sweep")
    try:
        n = int(parts[2])
    except ValueError:
        raise UsageError(f"{quote(text)}: N must be a whole number", param="sweep") from None
    if not 1 <= n <= 10000:
        raise UsageError(f"{quote(text)}: N must be 1..10000", param="sweep")
    if param is not None and param.unit not in ("", "int") and any(bare_number(p) for p in parts[:2]):
        unit = example_unit(param.unit)
        raise UsageError(f"{quote(text)}: {name} needs units on START and STOP, e.g. "
                         f"'{name}={parts[0].strip()}{unit}:{parts[1].strip()}{unit}:{parts[2].strip()}'",
                         param="sweep")
    bounds = []
    for part in parts[:2]:
        if param is not None and param.unit == "int" and bare_number(part) and float(part) == int(float(part)):
            part = str(int(float(part)))      # rollers=1:20:20 as well as 1.0:20.0
        try:
            bounds.append(parse_assignments([param] if param else params, [f"{name}={part}"])[name])
        except UsageError as exc:
            raise UsageError(f"{quote(text)}: {exc.message.split(': ', 1)[-1]}", param="sweep") from None
    points = linspace(float(bounds[0]), float(bounds[1]), n)
    if param is not None and param.unit == "int" and any(p != round(p) for p in points):
        whole = abs(int(bounds[1]) - int(bounds[0])) + 1
        raise UsageError(f"{quote(text)}: {name} is a whole number; {n} points from {bounds[0]} to {bounds[1]} "
                         f"are not whole (take N = {whole}, or N - 1 dividing {abs(int(bounds[1]) - int(bounds[0]))})",
                         param="sweep")
    return name, points
