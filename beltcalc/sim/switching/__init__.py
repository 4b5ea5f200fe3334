"""Tension-only strands on the exact solution: mode changes located to machine precision,
grazing and take-up done right, the internal step chosen from the dynamics alone.

Between mode changes the network is linear with generator inputs, ``z' = F z`` with
``z = [x, g]`` (:func:`beltcalc.sim.propagate.augmented_matrix`). A *mode* is one strand pattern
(which strands are taut) on one time piece of the inputs. This package propagates the
exact solution mode by mode:

* **Scaling.** ``F`` is balanced once per network by a diagonal similarity of powers of two
  (exact in floating point), ``F~ = S^-1 F S``: positions in rad and speeds in rad/s differ
  by the fastest angular frequency, and without balancing ``||F h||`` is 10^4 times
  larger than the dynamics need.
* **Steps from the dynamics.** The bottom step ``L = min(THETA / ||F~||_1, RHO / rho)``
  (rho: the spectral radius) makes the Taylor series of the exact solution over one step,
  ``z(t + s L) = sum_j s^j V_j`` with ``V_j = (F~ L)^j z / j!``, exact to rounding with
  :func:`terms_for` ``(||F~ L||)`` terms, at most 49 (s in [0, 1]). THETA bounds the
  truncation (the terms needed); RHO bounds how far the terms grow before they shrink
  (about ``exp(rho L)``), which is what the rounding of a value read off the series grows
  with: where the fastest motion is well below ``||F~||`` (a chain whose strand stiffness
  sets the norm) the step is THETA's, twice what ``||F~ L|| = 4`` gave; where a stiff
  coupling's own frequency is near ``||F~||`` it is RHO's, as before. Every switching
  function ``r . z`` is then a polynomial in s on the step; its coefficients come from the
  rows ``R_j = r (F~ L)^j / j!``, precomputed per mode. The output grid plays no part:
  samples are read off the exact solution afterwards, from the step that holds them.
* **Stiff modes** (``||F~||`` far above the fastest oscillation, e.g. a coupling 10^6 times
  stiffer than the rest): the coarse step is ``h = 2^K L`` (at most one radian of the
  fastest oscillation), propagated by ``P_0 = expm(F~ h)``, built bottom-up by squaring from
  the bottom step (so the ladder ``P_k = expm(F~ h / 2^k)`` comes for free). A coarse step is
  examined by the values and rates of the switching functions at its ends (a cubic Hermite
  test for a dip through zero inside it); a flagged step is halved down the ladder to the
  bottom level, where the polynomial is exact. After every restart the first coarse step
  is entered geometrically (L, L, 2L, 4L ... h/2) so a fast transient cannot hide a
  crossing.
* **Location.** The first crossing is the first root of the exact polynomial on the step,
  found by Brent's method on the polynomial (to 1e-15 of the step); the state there is the
  Taylor sum at that s. No ``expm`` per evaluation, no dependence on the output step.
* **Crossings, grazing, take-up.** A crossing counts when the function moves to its firing
  side by more than the rounding level ``tol`` (an excursion whose peak stays within
  ``tol`` is a graze: no switch). At a restart every strand that sits on a surface is
  decided by how its elongation and force leave zero in the taut mode (the first Taylor
  coefficient beyond rounding): taut if both become positive. Unloading (``F -> 0`` with
  ``delta > 0``) has the same accelerations in both modes, so it is a transversal or a
  grazing crossing, never a chatter. Take-up (``delta`` rising through 0) makes the
  damper's force jump to ``b delta'`` (a Kelvin-Voigt contact). See DESIGN.md section 3.0.

The modules, each on one responsibility (they import one another, never this interface):

* :mod:`~beltcalc.sim.switching.steps`: the bottom step from the dynamics and the Taylor
  series on it;
* :mod:`~beltcalc.sim.switching.firing`: where a switching function fires (the Bernstein
  hull, the grid test, the crossing itself) and the first crossing on a block of steps;
* :mod:`~beltcalc.sim.switching.mode`: a mode and a small network's dense modes (ladders,
  the orbit by doubling, the reach bound, the exponential's integral);
* :mod:`~beltcalc.sim.switching.parts` and :mod:`~beltcalc.sim.switching.sparse`: a large
  network's modes, assembled from the strands' stamps and stepped by sparse products;
* :mod:`~beltcalc.sim.switching.outputs`: the samples, the integrals, the rigid rotations;
* :mod:`~beltcalc.sim.switching.run`: the run (:func:`piecewise_exact`, :class:`Run`): blocks,
  scans, decisions at a restart.

The names below are the package's interface. Each constant is read where it is defined: a
test that changes one sets it on its own module (``beltcalc.sim.switching.run.SPARSE_SIZE``,
``beltcalc.sim.switching.sparse.TAIL``), not on the package.
"""

from beltcalc.sim.switching.firing import EPS, ROUND, first_fire, may_fire, stays_down
from beltcalc.sim.switching.mode import NEAR_GROUP, DenseMode, Mode
from beltcalc.sim.switching.outputs import rigid_modes, slack_times, switched_history, switched_log
from beltcalc.sim.switching.parts import SparseParts
from beltcalc.sim.switching.run import SPARSE_SIZE, Run, piecewise_exact
from beltcalc.sim.switching.sparse import SparseMode
from beltcalc.sim.switching.steps import RHO, TERMS, THETA, power_radius, step_length, terms_for

__all__ = ["DenseMode", "EPS", "Mode", "NEAR_GROUP", "RHO", "ROUND", "Run", "SPARSE_SIZE", "SparseMode",
           "SparseParts", "TERMS", "THETA", "first_fire", "may_fire", "piecewise_exact", "power_radius",
           "rigid_modes", "slack_times", "stays_down", "step_length", "switched_history", "switched_log", "terms_for"]
