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


@pytest.mark.parametrize("text, si_unit", [("0.27879741668086166 kg*m^2", "kg*m^2"), ("1500.0 N", "N"),
                                           ("-3e2 rad/s", "rad/s"), ("2N", "N"), (" 68.7 N*m*s/rad ", "N*m*s/rad")])
def test_a_number_in_exactly_the_si_unit_reads_as_pint_reads_it(monkeypatch, text, si_unit):
    # the shortcut that skips pint where the unit is the SI unit asked for, against pint itself
    from beltcalc import units

    fast = units.parse_quantity(text, si_unit)
    monkeypatch.setattr(units, "_in_si", lambda text, si_unit: None)           # no shortcut: pint's path
    assert fast == units.parse_quantity(text, si_unit)


@pytest.mark.parametrize("text, si_unit", [("1.5.3 N", "N"), ("1,5 N", "N"), ("inf N", "N"), ("5 m", "kg"),
                                           ("9" * 400 + " N", "N")])
def test_the_shortcut_leaves_bad_text_to_the_checks(text, si_unit):
    from beltcalc.units import QuantityError, parse_quantity

    with pytest.raises(QuantityError):
        parse_quantity(text, si_unit)
