"""The old path of the matrix exponential and the balancing, kept for one release.

:func:`expm` and :func:`balance` moved to :mod:`beltcalc.numerics`; import them from there.
This module only re-exports them, so that code that still imports
``beltcalc.sim.linalg`` gets the same functions.
"""

from beltcalc.numerics.balance import balance
from beltcalc.numerics.expm import expm

__all__ = ["balance", "expm"]
