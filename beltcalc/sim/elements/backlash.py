r"""A coupling with a dead band (gear backlash, play in a key or a jaw coupling), built from
two one-sided contacts that the switching core handles exactly, as it handles tension-only
strands.

Between nodes ``a`` and ``b`` (``b`` None: a stop fixed to the frame) with ratio U, the
relative angle is ``phi_rel = phi_a - U phi_b``; the total play is ``b`` (the dead band
``-b/2 <= phi_rel <= b/2``). The transmitted torque [MSL ElastoBacklash2]:

.. math::

    T = \begin{cases}
        \max(0,\ c (\varphi_{rel} - b/2) + d \dot\varphi_{rel}) & \varphi_{rel} > b/2 \\
        0 & |\varphi_{rel}| \le b/2 \\
        \min(0,\ c (\varphi_{rel} + b/2) + d \dot\varphi_{rel}) & \varphi_{rel} < -b/2
    \end{cases}

A contact pushes only: a damped contact separates when its torque falls to zero, before
``phi_rel`` is back at the edge of the band, and takes up again when its virtual torque
``c (phi_rel - b/2) + d phi_rel'`` rises through zero while still pressed in. At take-up the
torque jumps to ``d phi_rel'`` (a Kelvin-Voigt contact), as MSL's ElastoBacklash2 does;
MSL's ElastoBacklash instead limits the damping torque to the spring torque, ``c delta +
min(c delta, d delta')``, so that its torque starts from zero: not modelled here.

Each side is a :class:`Contact`, a :class:`~beltcalc.sim.elements.Strand` whose elongation is
``delta = side (phi_a - U phi_b) - b/2`` (``side`` +1 or -1) and whose "pretension" is
``-c b/2``: a gap where a strand has a preload. The network switches them as it switches
strands (take-up, release, grazing, Zeno accumulation located on the exact solution, see
:mod:`beltcalc.sim.switching`). :class:`Backlash` names the pair and gives the transmitted
torque ``T_<name>`` (+ side minus - side); its contacts are named ``<name>+`` and
``<name>-`` (their forces ``F_<name>+``, ``F_<name>-`` >= 0, in N m between rotating nodes).

With ``b = 0`` the element is a spring-damper that cannot pull: ``max(0, ...)`` on the +
side, ``min(0, ...)`` on the - side, i.e. the coupling ``c phi_rel + d phi_rel'`` except
where the damper would make the torque change sign against ``phi_rel`` (MSL's elements turn
into the plain coupling below b = 1e-10 rad instead).

References:

[MSL] Modelica Association, Modelica Standard Library 4.0.0 (2020),
    Modelica.Mechanics.Rotational.Components.ElastoBacklash2 and ElastoBacklash: backlash in
    series with a linear spring and damper, no pulling torque.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.sim.elements import Element, Strand


@dataclass(frozen=True)
class Contact(Strand):
    """One side of a dead band [MSL ElastoBacklash2]: a tension-only
    :class:`~beltcalc.sim.elements.Strand` with elongation ``delta = side (phi_i - U phi_j) - gap``
    and force ``c delta + d delta'`` while ``delta > 0`` and the force is > 0.

    Its strand lever arms are ``r_i = side``, ``r_j = side U`` and its pretension
    ``F_0 = -c gap`` (so ``delta = G . q + F_0 / c``): derived, not given. ``stiffness`` c
    [N m/rad, or N/m between translating nodes], ``damping`` d, ``U`` [-], ``gap`` [rad or m]
    (>= 0), ``side`` +1 (pushes when ``phi_i - U phi_j`` exceeds the gap) or -1.

    >>> c = Contact("bl+", "a", "b", 1e4, 2.0, U=1.0, gap=0.01, side=1)
    >>> c.r_i, c.r_j, c.preload
    (1.0, 1.0, -100.0)
    """

    r_i: float = field(init=False, default=1.0)
    r_j: float = field(init=False, default=1.0)
    preload: float = field(init=False, default=0.0)
    U: float = 1.0
    gap: float = 0.0
    side: int = 1

    UNITS: ClassVar[dict] = {"stiffness": None, "damping": None, "U": "", "gap": None}

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "r_i", float(self.side))
        object.__setattr__(self, "r_j", float(self.side) * self.U)
        object.__setattr__(self, "preload", -self.stiffness * self.gap)


    @property
    def default_taut(self) -> bool:
        """A dead band's default: closed on its + side, open on its - side."""
        return self.side > 0

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        for end in (self.i, self.j):
            if end is not None and net.node(end).J == 0:
                raise InputError(f"contact {self.name} ends on {end}, a node without inertia: a backlash needs an "
                                 "inertia at each end", param="network")
        if self.side not in (1, -1):
            raise InputError(f"contact {self.name}: side {self.side!r} is not +1 or -1", param="network")
        require_positive(f"{self.name} stiffness", self.stiffness, "N*m/rad")
        require_range(f"{self.name} damping", self.damping, "N*m*s/rad", low=0.0)
        require_range(f"{self.name} gap", self.gap, "rad", low=0.0)
        require_positive(f"U_{self.name}", self.U, "")
        if not np.any(self.geometry(net)):
            raise InputError(f"contact {self.name}: phi_{self.i} - U phi_{self.j} does not change (the nodes are "
                             "geared together at this ratio)", param="network")


@dataclass(frozen=True)
class Backlash(Element):
    """A coupling with total play ``backlash`` b [rad, or m between translating nodes] between
    nodes ``a`` and ``b`` (None: to the frame): contact stiffness ``stiffness`` c [N m/rad],
    damping ``damping`` d [N m s/rad], ratio ``U`` [-] (``phi_rel = phi_a - U phi_b``, as a
    :class:`~beltcalc.sim.elements.Coupling`'s) [MSL ElastoBacklash2].

    The element itself stamps nothing: its two :class:`Contact` s (:meth:`contacts`) carry
    the torque, and the network needs all three (:meth:`elements`). Output ``T_<name>``: the
    transmitted torque ``F_<name>+ - F_<name>-`` [N m, or N], positive where ``phi_rel``
    exceeds b/2, as a coupling's is; it also gives the contacts' forces ``F_<name>+``,
    ``F_<name>-`` in that unit.

    >>> from beltcalc.sim.network import Inertia, Network
    >>> bl = Backlash("bl", "m", "l", 0.02, 1e4, 1.0)
    >>> net = Network([Inertia("m", 0.01), Inertia("l", 0.05)], bl.elements())
    >>> [s.name for s in net.strands], [s.preload for s in net.strands]
    (['bl+', 'bl-'], [-100.0, -100.0])
    """

    name: str
    a: str
    b: str | None
    backlash: float
    stiffness: float
    damping: float = 0.0
    U: float = 1.0

    UNITS: ClassVar[dict] = {"backlash": None, "stiffness": None, "damping": None, "U": ""}

    def contacts(self) -> tuple[Contact, Contact]:
        """The + side and the - side, ``<name>+`` and ``<name>-``, each with gap b/2."""
        return tuple(Contact(f"{self.name}{'+' if side > 0 else '-'}", self.a, self.b, self.stiffness, self.damping,
                             U=self.U, gap=self.backlash / 2, side=side) for side in (1, -1))

    def elements(self) -> list:
        """What a :class:`~beltcalc.sim.network.Network` takes: the backlash and its contacts."""
        return [self, *self.contacts()]

    def check(self, net) -> None:
        net.check_ends(self.name, self.a, self.b)
        require_range(f"{self.name} backlash", self.backlash, "rad", low=0.0)
        require_positive(f"{self.name} stiffness", self.stiffness, "N*m/rad")
        require_range(f"{self.name} damping", self.damping, "N*m*s/rad", low=0.0)
        require_positive(f"U_{self.name}", self.U, "")
        given = {s.name: s for s in net.strands}
        for c in self.contacts():
            if given.get(c.name) != c:
                raise InputError(f"backlash {self.name}: its contact {c.name} is not in the network as "
                                 f"Backlash.contacts() gives it; pass backlash.elements() to the Network",
                                 param="network")

    def outputs(self, net, t, X, accel) -> dict:
        """``T_<name>`` and the contacts' forces ``F_<name>+``, ``F_<name>-`` in the nodes'
        unit (the network labels every strand force N; a contact between rotating nodes
        carries N m): each ``c delta + d delta'`` where its elongation and force are both
        positive, else 0, from the contacts' rows over ``z = [x, g]``."""
        where = {s.name: k for k, s in enumerate(net.strands)}
        rows = [where[f"{self.name}+"], where[f"{self.name}-"]]
        delta, force = net.strand_rows()
        X = np.asarray(X, dtype=float)
        Z = np.vstack([X, net.generators(np.broadcast_to(np.asarray(t, dtype=float), X.shape[1:]))])
        f = force[rows] @ Z
        f[(delta[rows] @ Z <= 0) | (f <= 0)] = 0.0
        unit = "N" if net.node(self.a).translation else "N m"
        return {f"T_{self.name}": (f[0] - f[1], unit), f"F_{self.name}+": (f[0], unit),
                f"F_{self.name}-": (f[1], unit)}



def closed_pattern(net) -> tuple[bool, ...]:
    """The strand pattern of a drive in contact: every strand taut, every backlash closed on
    its + side and open on its - side (a network's default pattern, every strand taut, closes
    both sides of a dead band: twice its stiffness). For its modes and natural frequencies.

    >>> from beltcalc.sim.network import Inertia, Network
    >>> bl = Backlash("bl", "m", "l", 0.02, 1e4)
    >>> closed_pattern(Network([Inertia("m", 0.01), Inertia("l", 0.05)], bl.elements()))
    (True, False)
    """
    return tuple(s.default_taut for s in net.strands)
