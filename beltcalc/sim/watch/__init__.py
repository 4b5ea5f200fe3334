"""Exact extremes of signals read off the exact solution, not off the output samples.

* :mod:`beltcalc.sim.watch.blocks`: :class:`~beltcalc.sim.watch.blocks.Watch`, fed block by
  block by the switching core (:mod:`beltcalc.sim.switching`): extremes over windows of any
  run of the exact method, strands and all (the roller table, drive files).
* :mod:`beltcalc.sim.watch.pieces`: :func:`~beltcalc.sim.watch.pieces.exact_signals`, over the
  time pieces of a network without strands: extremes with their times and sides (the left
  limit at a piece's end, where an input jumps) and integrals of the square, for signals whose
  rows change from piece to piece (a prescribed node's drive torque: the linear axis).
* :mod:`beltcalc.sim.watch.polish`: what both share: the largest value of polynomials on
  intervals (Newton, every row at once) and of an exactly evaluated signal on an interval
  (:func:`~beltcalc.sim.watch.polish.zoom_max`: grids, each 32 or 128 times finer).

Both walk their grids with :func:`beltcalc.sim.propagate.orbit`.
"""

from beltcalc.sim.watch.blocks import Watch

__all__ = ["Watch"]
