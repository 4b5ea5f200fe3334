"""The one pint registry of beltcalc, and parsing/formatting of quantities.

Units live only at the edges: command-line options and catalog files are converted to
SI floats here, and SI floats are converted back here for display. The physics modules
never import pint.

The registry is built once, on first use, with pint's definition cache
(``cache_folder=":auto:"``), which cuts its construction from ~0.2 s to ~0.02 s.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache

import pint

_REGISTRY: pint.UnitRegistry | None = None


def ureg() -> pint.UnitRegistry:
    """Return the application's unit registry, building it on first call."""
    global _REGISTRY
    if _REGISTRY is None:
        try:
            _REGISTRY = pint.UnitRegistry(cache_folder=":auto:")
        except OSError:  # read-only home: build without the cache
            _REGISTRY = pint.UnitRegistry()
        _REGISTRY.define("rev = revolution")  # as in the paper's 'rev/s'
    return _REGISTRY


class QuantityError(ValueError):
    """A text that is not a quantity of the wanted dimension (a usage error)."""


@lru_cache(maxsize=None)
def _dimensionality(si_unit: str):
    return ureg().parse_units(si_unit).dimensionality


def parse_quantity(text: str | float, si_unit: str) -> float:
    """Read ``text`` as a quantity of the dimension of ``si_unit`` and return it in ``si_unit``.

    A bare number is accepted only for dimensionless quantities (``si_unit`` "" or "1").

    >>> parse_quantity("90kg", "kg")
    90.0
    >>> round(parse_quantity("3000rpm", "rad/s"), 4)
    314.1593
    >>> parse_quantity("5 m", "kg")
    Traceback (most recent call last):
    ...
    beltcalc.units.QuantityError: '5 m' is a length, not a mass (e.g. '5 kg')
    """
    reg = ureg()
    dimensionless = si_unit in ("", "1")
    if isinstance(text, (int, float)):
        value = float(text)
        q = reg.Quantity(value, "" if dimensionless else si_unit)
    else:
        example = "a plain number, e.g. '0.2'" if dimensionless else f"a number and a unit, e.g. '50 {si_unit}'"
        _check_number_text(text, example)
        try:
            q = reg.Quantity(text.strip())
        except Exception as exc:  # pint raises many types for bad text
            raise QuantityError(f"cannot read {text!r} as a quantity; give {example}") from exc
        if not isinstance(q, pint.Quantity):  # e.g. a bare unit name parsed to a Unit
            q = reg.Quantity(1.0, str(q))
    if isinstance(q.magnitude, complex) or not hasattr(q.magnitude, "__float__"):
        raise QuantityError(f"{text!r} is not a number")
    if dimensionless:
        if not q.dimensionless:
            raise QuantityError(f"{text!r} must be a plain number, not a {dimension_name(q.dimensionality)}")
        value = float(q.m_as(""))
    else:
        if q.unitless:
            raise QuantityError(f"{text!r} needs a unit, e.g. '{text} {si_unit}'")
        if "rad" in si_unit and "hertz" in str(q.units):
            raise QuantityError(f"{text!r} is a frequency; for a rotational speed write revolutions "
                                f"('{q.magnitude:g} rev/s', '{q.magnitude * 60:g} rpm') or '... rad/s'")
        if q.dimensionality != _dimensionality(si_unit):
            raise QuantityError(
                f"{text!r} is a {dimension_name(q.dimensionality)}, "
                f"not a {dimension_name(_dimensionality(si_unit))} (e.g. '{q.magnitude:g} {si_unit}')"
            )
        value = float(q.m_as(si_unit))
    if not math.isfinite(value):
        raise QuantityError(f"{text!r} is not a finite number")
    return value


def parse_quantity_any(text: str | float, si_units: tuple[str, ...]) -> tuple[float, str]:
    """Read ``text`` as a quantity of any one of the dimensions of ``si_units``.

    Returns the value in the matching SI unit and that unit.

    >>> parse_quantity_any("2 m/s", ("rad/s", "m/s"))
    (2.0, 'm/s')
    >>> round(parse_quantity_any("3000rpm", ("rad/s", "m/s"))[0], 3)
    314.159
    """
    problems = []
    for unit in si_units:
        try:
            return parse_quantity(text, unit), unit
        except QuantityError as exc:
            problems.append(exc)
    if any("is a" in str(p) for p in problems):
        names = " or ".join(dimension_name(_dimensionality(u)) for u in si_units)
        raise QuantityError(f"{text!r} is neither a {names} (e.g. "
                            + " or ".join(f"'1 {u}'" for u in si_units) + ")")
    raise problems[0]


_NUMBER = re.compile(r"\s*[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")


def _check_number_text(text: str, example: str) -> None:
    """Refuse text that pint would read silently wrong: pint multiplies juxtaposed numbers,
    so ``1,5kg`` would be 15 kg and ``1.5.3kg`` 0.45 kg."""
    if "," in text:
        raise QuantityError(f"{text!r}: use a decimal point, not a comma; give {example}")
    m = _NUMBER.match(text)
    if m and text[m.end():m.end() + 1] in tuple("0123456789."):
        raise QuantityError(f"cannot read {text!r} as one number; give {example}")


_DIMENSION_NAMES = {
    "[mass]": "mass",
    "[length]": "length",
    "[time]": "time",
    "[length] / [time]": "speed",
    "[length] / [time] ** 2": "acceleration",
    "1 / [time]": "rotational speed or frequency",
    "1 / [time] ** 2": "angular acceleration",
    "[length] * [mass] / [time] ** 2": "force",
    "[length] ** 2 * [mass] / [time] ** 2": "torque or energy",
    "[mass] / [time] ** 2": "stiffness (force per length)",
    "[mass] / [time]": "damping (force per speed)",
    "[mass] / [length]": "mass per length",
    "[length] ** 2 * [mass]": "moment of inertia",
    "dimensionless": "plain number",
}


def dimension_name(dimensionality) -> str:
    """A readable name for a pint dimensionality (``'length'``, ``'force'``, ...)."""
    key = str(dimensionality)
    return _DIMENSION_NAMES.get(key, key)


@lru_cache(maxsize=None)
def conversion_factor(from_unit: str, to_unit: str) -> float:
    """The factor that converts a value in ``from_unit`` to ``to_unit``.

    >>> conversion_factor("mm", "m")
    0.001
    """
    return float(ureg().Quantity(1.0, from_unit).m_as(to_unit))


def convert(value: float, from_unit: str, to_unit: str) -> float:
    """Convert a float between two pint unit strings (``""`` or ``"1"`` is dimensionless).

    >>> convert(1.0, "rad", "deg")
    57.29577951308232
    """
    if from_unit == to_unit:
        return value
    return value * conversion_factor(from_unit or "", to_unit or "")
