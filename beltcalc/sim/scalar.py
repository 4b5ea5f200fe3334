"""The old path of the scalar searches and Horner's polynomial, kept for one release.

:func:`brentq`, :func:`golden_minimum`, :func:`bounded_minimum` and :func:`horner` moved to
:mod:`beltcalc.numerics.scalar`; import them from there. This module only re-exports them,
so that code that still imports ``beltcalc.sim.scalar`` gets the same functions.
"""

from beltcalc.numerics.scalar import bounded_minimum, brentq, golden_minimum, horner

__all__ = ["bounded_minimum", "brentq", "golden_minimum", "horner"]
