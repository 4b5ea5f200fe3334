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

from beltcalc.data.tomlsafe import quote

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


MAX_TEXT = 200        # characters of a quantity text; longer is refused before pint sees it
MAX_POWER = 12        # largest unit power (``m^2``, ``s^-3``); a larger one is no unit of ours


@lru_cache(maxsize=None)
def _dimensionality(si_unit: str):
    return ureg().parse_units(si_unit).dimensionality


# A number, then the unit. pint would evaluate any Python-like arithmetic in a text
# (``9**9**9 kg`` never returns), so the number is read here and pint reads only the unit.
_LEADING = re.compile(r"\s*([+-]?(?:(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
                      r"|(?:inf(?:inity)?|nan)(?![A-Za-z0-9_])))\s*", re.IGNORECASE)
_POWER = re.compile(r"\*\*|\^")
# a power is a small number not followed by more of a number (``g0**1e308`` is no power)
_EXPONENT = re.compile(r"\s*\(?\s*[+-]?\d{1,2}(?:\.\d{1,2})?(?![0-9.eE])\s*\)?")
_LONE_NUMBER = re.compile(r"(?<![A-Za-z0-9_.\u00b5\u03bc])\d")


#: The unit a value of an SI unit is written in where that is not the SI unit itself (a belt
#: span of 600 is 600 mm, not 600 m; a speed of 3000 is 3000 rpm): the unit of the examples in
#: the messages about a bare number or a wrong dimension, where the caller names no display unit.
EXAMPLE_UNITS = {"m": "mm", "rad/s": "rpm", "rad": "deg"}


def example_unit(si_unit: str, display: str | None = None) -> str:
    """The unit a message's example writes a value of ``si_unit`` in: ``display`` (the unit
    the option or key is shown in) if given, else :data:`EXAMPLE_UNITS`' or the SI unit.

    >>> example_unit("m"), example_unit("m", "in"), example_unit("N*m/rad")
    ('mm', 'in', 'N*m/rad')
    """
    return display or EXAMPLE_UNITS.get(si_unit, si_unit)


def _example(si_unit: str, display: str | None, number: str = "50") -> str:
    if si_unit in ("", "1"):
        return "a plain number, e.g. '0.2'"
    return f"a number and a unit, e.g. '{number} {example_unit(si_unit, display)}'"


def _unit_text(unit: str, text: str, example: str) -> str:
    """The unit part of a quantity text, checked to be a unit and nothing pint would compute:
    powers are small numbers (``m^2``, ``s**-2``), not powers of powers, and no number
    stands alone (a scale factor, ``kg*1e3``)."""
    where = unit.strip()
    if where.startswith(("*", "^")):
        raise QuantityError(f"{quote(text)}: powers and arithmetic on numbers are not read; give {example}")
    if where.count("(") > 4 or len(_POWER.findall(where)) > 8:
        raise QuantityError(f"cannot read {quote(text)} as a quantity; give {example}")
    rest, pos = [], 0
    for m in _POWER.finditer(where):
        if m.start() < pos:
            continue
        exp = _EXPONENT.match(where, m.end())
        after = where[exp.end():].lstrip() if exp else ""
        if exp is None or after.startswith(("*", "^")) and _POWER.match(after) \
                or abs(float(exp.group().strip(" ()"))) > MAX_POWER:
            raise QuantityError(f"{quote(text)}: a unit power is a small number (e.g. 'm^2', 's^-1'), "
                                f"not an expression; give {example}")
        rest.append(where[pos:m.start()])
        pos = exp.end()
    rest.append(where[pos:])
    body = "".join(rest)
    if _LONE_NUMBER.search(body[2:] if body.startswith("1/") else body):
        raise QuantityError(f"cannot read {quote(text)} as one number and a unit; give {example}")
    return where


def _read(text: str, si_unit: str, display: str | None):
    """``text`` as (magnitude, pint unit, the number as written) without evaluating it."""
    reg = ureg()
    example = _example(si_unit, display)
    if len(text) > MAX_TEXT:
        raise QuantityError(f"{quote(text)} is too long for a quantity (at most {MAX_TEXT} characters); "
                            f"give {example}")
    _check_number_text(text, example)
    m = _LEADING.match(text)
    number = m.group(1) if m else ""
    unit = text[m.end():] if m else text
    if number and unit.lstrip().startswith("/"):   # '1/s', '5/min'
        unit = "1" + unit.lstrip()
    unit = _unit_text(unit, text, example) if unit.strip() else ""
    if not number and not unit:
        raise QuantityError(f"cannot read {quote(text)} as a quantity; give {example}")
    try:
        units = reg.parse_units(unit) if unit else reg.parse_units("")
    except Exception as exc:  # pint raises many types for bad text
        raise QuantityError(f"cannot read {quote(text)} as a quantity; give {example}") from exc
    if not number:     # 'kg' is not 1 kg: a unit alone is a value forgotten
        raise QuantityError(f"{quote(text)} has no number; give a number and its unit, e.g. '10 {unit}'")
    magnitude = float(number)
    if math.isinf(magnitude) and "inf" not in number.lower():
        raise QuantityError(f"{quote(text)}: the number is too large (at most about 1e308); give {example}")
    return magnitude, units, number


def _in_si(text: str, si_unit: str) -> float | None:
    """The value of a finite number followed by exactly the SI unit asked for (what the
    built-in scenes hand the drive-file builder), without pint: a unit's first reading costs
    pint up to 1 ms, 9 ms for the roller table's drive. None for anything else, which
    :func:`parse_quantity` then reads and checks in full."""
    if len(text) > MAX_TEXT or "," in text:
        return None
    m = _LEADING.match(text)
    if not m or text[m.end():].rstrip() != si_unit:
        return None
    value = float(m.group(1))
    return value if math.isfinite(value) else None


def parse_quantity(text: str | float, si_unit: str, display: str | None = None) -> float:
    """Read ``text`` as a quantity of the dimension of ``si_unit`` and return it in ``si_unit``.

    A bare number is accepted only for dimensionless quantities (``si_unit`` "" or "1").
    ``display`` is the unit the caller shows the value in (``mm`` for a width): the
    examples in messages use it (by default :func:`example_unit`'s). The text is one number
    and a unit: pint reads only the unit, so an expression (``9**9**9 kg``) is refused, not
    computed; at most :data:`MAX_TEXT` characters.

    >>> parse_quantity("90kg", "kg")
    90.0
    >>> round(parse_quantity("3000rpm", "rad/s"), 4)
    314.1593
    >>> parse_quantity("5 m", "kg")
    Traceback (most recent call last):
    ...
    beltcalc.units.QuantityError: '5 m' is a length, not a mass; give e.g. '5 kg'
    >>> parse_quantity("25", "m", display="mm")
    Traceback (most recent call last):
    ...
    beltcalc.units.QuantityError: '25' needs a unit, e.g. '25 mm'
    """
    dimensionless = si_unit in ("", "1")
    value = _in_si(text, si_unit) if isinstance(text, str) and not dimensionless else None
    if value is not None:
        return value
    reg = ureg()
    shown = example_unit(si_unit, display)
    if isinstance(text, (int, float)):
        value = float(text)
        q = reg.Quantity(value, "" if dimensionless else si_unit)
        number = repr(value)
    else:
        magnitude, units, number = _read(text, si_unit, display)
        q = reg.Quantity(magnitude, units)
    if dimensionless:
        if q.dimensionality:       # not q.dimensionless: that computes the factor (1 Ym^12*Ym^12 overflows)
            raise QuantityError(f"{quote(text)} must be a plain number, not {dimension_name(q.dimensionality)}")
        try:
            value = float(q.m_as(""))
        except OverflowError:      # a unit whose factor is beyond a float
            value = math.inf
    else:
        try:
            unitless = q.unitless
        except OverflowError:      # the root units' factor is beyond a float: it has units
            unitless = False
        if unitless:
            raise QuantityError(f"{quote(text)} needs a unit, e.g. '{number or text} {shown}'")
        if "rad" in si_unit and "hertz" in str(q.units):
            raise QuantityError(f"{quote(text)} is a frequency; for a rotational speed write revolutions "
                                f"('{q.magnitude:g} rev/s', '{q.magnitude * 60:g} rpm') or '... rad/s'")
        if q.dimensionality != _dimensionality(si_unit):
            raise QuantityError(
                f"{quote(text)} is {dimension_name(q.dimensionality)}, "
                f"not {dimension_name(si_unit)}; give e.g. '{q.magnitude:g} {shown}'"
            )
        try:
            value = float(q.m_as(si_unit))
        except OverflowError:
            value = math.inf
    if not math.isfinite(value):
        if number and not math.isfinite(float(number)):
            raise QuantityError(f"{quote(text)} is not a finite number")
        raise QuantityError(f"{quote(text)} is too large: above 1e308 {si_unit}".rstrip())
    return value


def unit_problem(unit: str, si_unit: str) -> str:
    """Why the text ``unit`` (a catalog's ``units`` entry) is not a unit of the dimension of
    ``si_unit``; ``""`` if it is one. Read as :func:`parse_quantity` reads a unit: nothing
    is computed.

    >>> unit_problem("mm", "m"), unit_problem("9**9**9 mm", "m")
    ('', "'9**9**9 mm' is not a unit; give a unit, e.g. 'm'")
    """
    example = f"a unit, e.g. '{si_unit}'"
    if not isinstance(unit, str):
        return f"{quote(unit)} is not a unit text; give {example}"
    if len(unit) > MAX_TEXT:
        return f"{quote(unit)} is too long for a unit (at most {MAX_TEXT} characters)"
    text = unit.strip()
    if not text or _LEADING.match(text) and not text.startswith("1/"):
        return f"{quote(unit)} is not a unit; give {example}"
    try:
        units = ureg().parse_units(_unit_text(text, unit, example))
    except QuantityError as exc:
        return str(exc)
    except Exception:  # pint raises many types for bad text
        return f"cannot read {quote(unit)} as a unit; give {example}"
    if units.dimensionality != _dimensionality(si_unit):
        return f"{quote(unit)} is {dimension_name(units.dimensionality)}, not {dimension_name(si_unit)}; " \
               f"give {example}"
    try:
        factor = float(ureg().Quantity(1.0, units).m_as(si_unit or ""))
    except (OverflowError, ZeroDivisionError):
        factor = math.inf
    if not math.isfinite(factor) or factor == 0:      # Ym^12*Ym^12: a factor beyond a float
        return f"{quote(unit)}: its factor to {si_unit or 'a plain number'} is beyond a float; give {example}"
    return ""


def is_unit(text: str) -> bool:
    """Whether ``text`` is a unit alone (``kW``, ``N*m/rad``), read as :func:`parse_quantity`
    reads one: no number, nothing computed.

    >>> is_unit("kW"), is_unit("N*m/rad"), is_unit("3"), is_unit("--t-end"), is_unit("sewing")
    (True, True, False, False, False)
    """
    if not isinstance(text, str) or not text.strip() or len(text) > MAX_TEXT or _LEADING.match(text):
        return False
    try:
        ureg().parse_units(_unit_text(text, text, "a unit"))
    except Exception:  # pint raises many types for bad text; QuantityError for an expression
        return False
    return True


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
    if all(" needs a unit" in str(p) for p in problems):      # a bare number: either unit will do
        number = text if isinstance(text, str) else f"{text:g}"
        raise QuantityError(f"{quote(text)} needs a unit, e.g. "
                            + " or ".join(f"'{number.strip()} {example_unit(u)}'" for u in si_units))
    if any(" is a" in str(p) or " is an" in str(p) for p in problems):
        names = " nor ".join(dimension_name(u) for u in si_units)
        raise QuantityError(f"{quote(text)} is neither {names}; give e.g. "
                            + " or ".join(f"'1 {example_unit(u)}'" for u in si_units))
    raise problems[0]


_NUMBER = re.compile(r"\s*[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")


def _check_number_text(text: str, example: str) -> None:
    """Refuse text that pint would read silently wrong: pint multiplies juxtaposed numbers,
    so ``1,5kg`` would be 15 kg and ``1.5.3kg`` 0.45 kg."""
    if "," in text:
        raise QuantityError(f"{quote(text)}: use a decimal point, not a comma; give {example}")
    m = _NUMBER.match(text)
    if m and text[m.end():m.end() + 1] in tuple("0123456789."):
        raise QuantityError(f"cannot read {quote(text)} as one number; give {example}")


# Words for the dimensions of the SI units the options and catalogs use (rad is a plain
# number to pint: N*m and N*m/rad share a dimension, so the unit names the kind).
_UNIT_NAMES = {
    "m": "a length", "kg": "a mass", "s": "a time", "N": "a force", "W": "a power",
    "V": "a voltage", "F": "a capacitance", "Pa": "a pressure (stress, modulus)", "A": "a current",
    "rad": "an angle", "Hz": "a frequency",
    "N*m": "a torque",
    "N*m/rad": "a torque per angle (rotational stiffness)",
    "N*m*s/rad": "a rotational damping (torque per angular speed)",
    "N*s/m": "a damping (force per speed)",
    "N/m": "a stiffness or a force per length",
    "kg*m^2": "an inertia (mass times length squared)",
    "kg/m": "a mass per length", "kg/m^3": "a density",
    "m/s": "a speed", "m/s^2": "an acceleration", "m/s^3": "a jerk",
    "rad/s": "a rotational speed", "rad/s^2": "an angular acceleration", "rad/s^3": "an angular jerk",
}

# Words for a dimension as pint gives it ({base dimension: power}), for what a user wrote.
_DIMENSION_NAMES = {
    (("[mass]", 1),): "a mass",
    (("[length]", 1),): "a length",
    (("[time]", 1),): "a time",
    (("[length]", 2),): "an area",
    (("[length]", 3),): "a volume",
    (("[length]", 1), ("[time]", -1)): "a speed",
    (("[length]", 1), ("[time]", -2)): "an acceleration",
    (("[length]", 1), ("[time]", -3)): "a jerk",
    (("[time]", -1),): "a rotational speed or frequency",
    (("[time]", -2),): "an angular acceleration",
    (("[time]", -3),): "an angular jerk",
    (("[length]", 1), ("[mass]", 1), ("[time]", -2)): "a force",
    (("[length]", 2), ("[mass]", 1), ("[time]", -2)): "a torque or energy",
    (("[length]", 2), ("[mass]", 1), ("[time]", -3)): "a power",
    (("[length]", 2), ("[mass]", 1), ("[time]", -1)): "a rotational damping (torque per angular speed)",
    (("[mass]", 1), ("[time]", -2)): "a stiffness (force per length)",
    (("[mass]", 1), ("[time]", -1)): "a damping (force per speed)",
    (("[length]", -1), ("[mass]", 1)): "a mass per length",
    (("[length]", -3), ("[mass]", 1)): "a density",
    (("[length]", -1), ("[mass]", 1), ("[time]", -2)): "a pressure (stress, modulus)",
    (("[length]", 2), ("[mass]", 1)): "an inertia (mass times length squared)",
    (("[current]", 1),): "a current",
    (("[current]", -1), ("[length]", 2), ("[mass]", 1), ("[time]", -3)): "a voltage",
    (("[current]", 2), ("[length]", -2), ("[mass]", -1), ("[time]", 4)): "a capacitance",
    (("[temperature]", 1),): "a temperature",
    (): "a plain number",
}

_BASE_SYMBOLS = {"[mass]": "kg", "[length]": "m", "[time]": "s", "[current]": "A",
                 "[temperature]": "K", "[substance]": "mol", "[luminosity]": "cd"}


def dimension_name(what) -> str:
    """Words, with their article, for a dimension: ``what`` is an SI unit text as the options
    name it (``"N*m/rad"``) or a pint dimensionality (what a user wrote). Never pint's
    dimension algebra: an unnamed dimension is "a quantity in" its SI base units.

    >>> dimension_name("N*m/rad"), dimension_name(ureg().parse_units("lbf*ft^2").dimensionality)
    ('a torque per angle (rotational stiffness)', 'a quantity in kg*m^3/s^2')
    """
    if isinstance(what, str):
        if what in _UNIT_NAMES:
            return _UNIT_NAMES[what]
        what = _dimensionality(what)
    key = tuple(sorted((str(k), v) for k, v in dict(what).items()))
    if key in _DIMENSION_NAMES:
        return _DIMENSION_NAMES[key]
    return f"a quantity in {_base_units(key)}"


def _base_units(key) -> str:
    """``(("[length]", 2), ("[mass]", 1), ("[time]", -2))`` -> ``kg*m^2/s^2``."""
    def power(name, p):
        symbol = _BASE_SYMBOLS.get(name, name.strip("[]"))
        p = abs(p)
        return symbol if p == 1 else f"{symbol}^{p:g}"
    order = list(_BASE_SYMBOLS)
    key = sorted(key, key=lambda kv: order.index(kv[0]) if kv[0] in order else len(order))
    up = "*".join(power(n, p) for n, p in key if p > 0) or "1"
    down = [power(n, p) for n, p in key if p < 0]
    if not down:
        return up
    return f"{up}/{down[0]}" if len(down) == 1 else f"{up}/({'*'.join(down)})"


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
