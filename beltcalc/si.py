"""Pint quantities where the library takes SI floats.

The library computes in plain SI floats. A notebook user may hand it pint quantities
instead (``Inertia("motor", J=Q_(3.5, "g*m^2"))``): :func:`as_si` converts one to the SI unit
a field documents, or refuses one of the wrong dimension with a message that names the
field. It recognises a quantity by its methods (``to``, ``magnitude``), so the physics
modules that call it never import pint.
"""

from __future__ import annotations

from dataclasses import fields
from functools import cache

from beltcalc.errors import InputError


_PLAIN = frozenset({float, int, bool, str, type(None), tuple})


def is_quantity(value) -> bool:
    """Whether ``value`` looks like a pint quantity."""
    return hasattr(value, "magnitude") and hasattr(value, "to_base_units") and hasattr(value, "to")


def as_si(value, unit: str | None, where: str):
    """``value`` in the SI unit ``unit`` (``""``: a plain number; None: SI base units of
    whatever dimension it has) if it is a quantity; anything else unchanged.

    >>> from beltcalc.units import ureg
    >>> as_si(ureg().Quantity(1500, "rpm"), "rad/s", "speed")
    157.07963267948966
    >>> as_si(ureg().Quantity(2, "m"), "kg", "mass")
    Traceback (most recent call last):
    ...
    beltcalc.errors.InputError: mass = 2 m: it must be in kg
    """
    if not is_quantity(value):
        return value
    try:
        q = value.to_base_units() if unit is None else value.to(unit or "dimensionless")
    except Exception:     # pint's DimensionalityError (pint is not imported here)
        wanted = f"in {unit}" if unit else "a plain number"
        raise InputError(f"{where} = {value:g~}: it must be {wanted}") from None
    return float(q.magnitude)


@cache
def _field_names(cls) -> tuple[str, ...]:
    """The dataclass fields of ``cls``, looked up once per class (``dataclasses.fields``
    builds its tuple on every call; an element is constructed thousands of times a study)."""
    return tuple(f.name for f in fields(cls))


def convert_fields(obj, units: dict[str, str | None]) -> None:
    """Convert every quantity-valued field of a (frozen) dataclass ``obj`` in place, by the
    SI unit ``units`` gives for it (a field not listed: base units)."""
    for name in _field_names(type(obj)):
        value = getattr(obj, name)
        if value.__class__ in _PLAIN:      # most fields: nothing to convert, no attribute look-ups
            continue
        if is_quantity(value):
            object.__setattr__(obj, name, as_si(value, units.get(name), f"{type(obj).__name__}.{name}"))
