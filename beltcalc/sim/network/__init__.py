"""A drive train as a graph: inertias (or masses), spring-damper couplings with a ratio,
tension-only strands (chains, belt spans), an induction motor, speed-controlled drives and
load torques. The network assembles its matrices once (Lagrange with Rayleigh dissipation)
and gives the first-order system ``x' = A x + B g(t) + f(t, x)`` with names and units for
every state and output. SI floats only; no pint, no click.

The package: :mod:`~beltcalc.sim.network.model` (the :class:`Network`),
:mod:`~beltcalc.sim.network.coordinates` (rigid gears merged, massless nodes condensed),
:mod:`~beltcalc.sim.network.strands` (the strands' rows, events and stamps) and
:mod:`~beltcalc.sim.network.assembly` (the :class:`Piece` elements stamp into).

State vector: ``x = [phi_1..phi_n, omega_1..omega_n, (M_motor)]``; a translating node
(``Inertia(..., translation=True)``) has a position [m] and a speed [m/s] instead.

Coupling k between nodes i and j with ratio U (``j`` None: to the frame):

    potential   V = C/2 (phi_i - U phi_j)^2,   dissipation  R = d/2 (omega_i - U omega_j)^2

so its torque on i is ``-C (phi_i - U phi_j) - d (omega_i - U omega_j)`` and on j ``U`` times
the opposite [M16 eq. 3-7], assembled instead of typed.

A strand from node i to node j [RP eq. 8-11] has the elongation
``delta = r_i phi_i - r_j phi_j + F_0 / c`` (r: pitch radius [m], 1 for a translating node;
F_0 the pretension) and the force ``F = c delta + b delta'`` while it is taut, 0 while slack.
It is taut while ``delta > 0`` [RP eq. 9-11] *and* ``F > 0``: the paper lets the
damper push while the elongation is still positive; a chain cannot push, so we also
release a strand whose force reaches zero. Between switches the network is linear; the
switching surfaces ``delta = 0`` and ``F = 0`` are hyperplanes in the state, which the core
locates on the exact solution.

Inputs that are piecewise linear in time (tabulated loads, a prescribed acceleration, the
reference and feed-forward of a speed loop) keep the network linear between their break
points: the generators are ``g = [1, t, sin w1 t, cos w1 t, ...]`` and ``B`` depends on the
time segment.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    couplings' Lagrange form [M16 eq. 3-7].
[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": the tension-only
    strands [RP eq. 8-11].
"""


from beltcalc.sim.elements import (Coupling, Gear, Inertia, InductionMotor, Load, Prescribed, Strand, check_points,
                                   piecewise)
from beltcalc.sim.elements.switched import Friction, SpeedLoop
from beltcalc.sim.network.assembly import Event, Piece, series_stiffness
from beltcalc.sim.network.model import Network

__all__ = ["Coupling", "Event", "Friction", "Gear", "Inertia", "InductionMotor", "Load", "Network", "Piece", "Prescribed",
           "SpeedLoop", "Strand", "check_points", "piecewise", "series_stiffness"]
