"""beltcalc: belt and chain drive trains, from catalog data to numbers you can build from.

The library works in SI floats; see :mod:`beltcalc.units` for parsing quantities,
:mod:`beltcalc.catalogs` for the data, :mod:`beltcalc.tension` for the tension design.
"""

__version__ = "0.1.0"
