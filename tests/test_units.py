"""Tests of beltcalc.units: one registry, parsing at the edges."""

import math

import pytest
from hypothesis import given, strategies as st

from beltcalc.units import QuantityError, convert, parse_quantity, ureg


def test_one_registry():
    assert ureg() is ureg()


@pytest.mark.parametrize("text, unit, expected", [
    ("90kg", "kg", 90.0),
    ("90 kg", "kg", 90.0),
    ("31.3in", "m", 0.79502),
    ("0.5g0", "m/s^2", 4.903325),
    ("3000rpm", "rad/s", 314.159265),
    ("20 N*s/m", "N*s/m", 20.0),
    ("5mm/s", "m/s", 0.005),
    ("0.2", "", 0.2),
])
def test_parse(text, unit, expected):
    assert parse_quantity(text, unit) == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("text, unit, match", [
    ("abc", "kg", "cannot read"),
    ("5m", "kg", "is a length, not a mass"),
    ("5", "kg", "needs a unit"),
    ("nan kg", "kg", "not a finite number"),
    ("inf m", "m", "not a finite number"),
    ("5 kg", "", "plain number"),
])
def test_parse_rejects(text, unit, match):
    with pytest.raises(QuantityError, match=match):
        parse_quantity(text, unit)


@given(st.floats(min_value=1e-6, max_value=1e6))
def test_round_trip(value):
    assert convert(convert(value, "m", "in"), "in", "m") == pytest.approx(value, rel=1e-12)
    assert parse_quantity(f"{value!r} mm", "m") == pytest.approx(value / 1000, rel=1e-12)
    assert math.isfinite(parse_quantity(f"{value!r} lbf", "N"))
