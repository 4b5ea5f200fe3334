"""The element kinds of a drive train. Each kind stamps itself: it checks its own values,
adds its own rows to the network's matrices and inputs, and names its own outputs. A
:class:`~beltcalc.sim.network.Network` takes them all in one list and only loops over them
(a new kind is one class here, or anywhere); drive files name a kind through one class of
:mod:`beltcalc.sim.drivefile.kinds` and one line of the ``ELEMENTS`` registry
(:mod:`beltcalc.sim.drivefile.registry`). Rigid gears merge nodes into coordinates and
tension-only strands are switched by the core itself. SI floats only; no pint, no click.

The hooks an element may define (all optional, see :class:`Element`):

- ``check(net)``: refuse impossible values (:class:`~beltcalc.errors.InputError`);
- ``matrices(net)``: ``(g, C, d)`` triples: a spring C and damper d on the deflection
  ``g . q`` of the generalised coordinates (K += C g g^T, D += d g g^T, Lagrange with
  Rayleigh dissipation);
- ``states()``: extra first-order states it owns (name, SI unit), e.g. a motor's torque;
- ``inputs(piece)``: its terms of ``x' = A x + B g`` on one time piece (a
  :class:`~beltcalc.sim.network.Piece`);
- ``tables()``, ``breaks()``: its piecewise-linear inputs and switch-on times (they split
  the run into time pieces);
- ``frequencies()``: its sinusoid frequencies in time [rad/s] (input generators);
- ``nonlinear_kind``, ``nonlinear(net, t, X, out, constrained)``, ``jacobian(net, x, jac)``:
  what the linear form cannot take (loads locked to a shaft angle), which sends the run to
  an implicit solver with this analytic Jacobian;
- ``switched`` and the hooks of :class:`beltcalc.sim.elements.switched.Switched`: modes of
  its own (friction that sticks, a drive's torque limit), switched by the core;
- ``pieces``, ``piece_at(net, x)``, ``piece_events(net, piece)``: a nonlinear kind that is
  smooth between surfaces of its own (a polygon strand's seatings and slack switches): the
  scipy runs hold each such element on its piece (``net.pieces``) and stop at every surface
  (:mod:`beltcalc.sim.elements.polygon`); ``tension_only``: reported as a strand;
- ``outputs(net, t, X, accel)``: ``{signal: (array, SI unit)}`` from the states ``X`` and the
  coordinates' accelerations ``accel`` (rows ``n:2n`` of x', nothing else of it);
  ``outputs_of(net, elements, t, X, accel)`` (a classmethod) gives those of several elements
  of the kind at once.

Pint quantities are accepted wherever an element takes an SI float: they are converted to
the SI unit the kind's ``UNITS`` gives the field (``Inertia(name, J=Q_(3.5, "g*m^2"))``), and
a quantity of the wrong dimension is refused with a message naming the field.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    couplings' Lagrange form [M16 eq. 3-7] and the induction motor's dynamic characteristic
    [M16 eq. 2].
[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": the tension-only
    strand [RP eq. 8-11].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.si import convert_fields

Points = tuple[tuple[float, float], ...]

class Element:
    """Base of every element kind: converts pint quantities on construction (frozen
    dataclasses: ``object.__setattr__``) by the kind's ``UNITS`` (field -> SI unit; None:
    SI base units of the quantity's own dimension, for a torque or a force by the node it
    acts on), and gives every hook a do-nothing default."""

    UNITS: ClassVar[dict[str, str | None]] = {}
    #: True for a kind with modes of its own (:mod:`beltcalc.sim.elements.switched`)
    switched: ClassVar[bool] = False
    #: where the kind stamps among the others: the network sums the matrices and inputs kind by
    #: kind in this order (couplings, speed loops, loads, prescribed motions, motors, then any
    #: other kind), the elements of one kind as listed
    ORDER: ClassVar[int] = 60

    def __post_init__(self):
        convert_fields(self, self.UNITS)

    @property
    def nonlinear_kind(self) -> bool:
        """True when the element's terms are not linear in the state (then :meth:`nonlinear`
        and :meth:`jacobian` give them and the core uses an implicit solver)."""
        return False

    def nonlinear(self, net, t, X, out, constrained: bool) -> None:
        """Add the element's nonlinear terms of x' at states ``X`` (columns) to ``out``."""

    def jacobian(self, net, x, jac) -> None:
        """Add d(nonlinear terms)/dx at the state ``x`` to ``jac``."""

    def check(self, net) -> None:
        """Refuse impossible values."""

    def matrices(self, net) -> list:
        """(g, C, d): spring and damper on the deflection g . q."""
        return []

    def states(self) -> list[tuple[str, str]]:
        """Extra first-order states (name, SI unit)."""
        return []

    def inputs(self, piece) -> None:
        """Terms of x' = A x + B g on one time piece."""

    def tables(self) -> list[Points]:
        """Piecewise-linear input tables."""
        return []

    def breaks(self) -> list[float]:
        """Times where an input switches on (beside the tables' points)."""
        return []

    def frequencies(self) -> list[float]:
        """Angular frequencies of sinusoids in time [rad/s]."""
        return []

    def outputs(self, net, t, X, accel) -> dict:
        """{signal: (array over t, SI unit)} from the states ``X`` and the coordinates'
        accelerations ``accel``."""
        return {}

    @classmethod
    def outputs_of(cls, net, elements, t, X, accel) -> dict:
        """The outputs of several elements of this kind at once, in their order (a kind with
        many members overrides it with one array expression over all of them and every
        sample; by default each element gives its own)."""
        out = {}
        for el in elements:
            out.update(el.outputs(net, t, X, accel))
        return out


def check_points(points: Points, what: str) -> None:
    """Refuse a table whose times fall (a repeated time is a jump and is allowed)."""
    times = [p[0] for p in points]
    if any(b < a for a, b in zip(times, times[1:])):
        raise InputError(f"the {what} table must have rising times (a time may repeat for a jump)",
                         param="network")
    if any(not (math.isfinite(a) and math.isfinite(b)) for a, b in points):
        raise InputError(f"the {what} table has a value that is not finite", param="network")


def piecewise(points: Points, t):
    """Value of a piecewise-linear table at ``t``: linear between points, the later value at a
    repeated time (a jump), held constant outside.

    >>> float(piecewise(((0.0, 0.0), (1.0, 2.0), (1.0, 5.0)), 0.5)), float(piecewise(((0.0, 0.0), (1.0, 2.0), (1.0, 5.0)), 1.0))
    (1.0, 5.0)
    """
    ts = np.array([p[0] for p in points])
    vs = np.array([p[1] for p in points])
    t = np.asarray(t, dtype=float)
    k = np.searchsorted(ts, t, side="right") - 1
    inside = (k >= 0) & (k < ts.size - 1)
    kk = np.clip(k, 0, ts.size - 2) if ts.size > 1 else np.zeros_like(k)
    if ts.size > 1:
        span = ts[kk + 1] - ts[kk]
        slope = np.where(span > 0, (vs[kk + 1] - vs[kk]) / np.where(span > 0, span, 1.0), 0.0)
        mid = vs[kk] + slope * (t - ts[kk])
    else:
        mid = np.full_like(t, vs[0])
    return np.where(inside, mid, np.where(k < 0, vs[0], vs[-1]))


def piece(points: Points, t_mid: float) -> tuple[float, float]:
    """(a, c) with value = a + c t on the piece that holds ``t_mid`` (not a break point).

    >>> piece(((0.0, 0.0), (2.0, 4.0)), 1.0)
    (0.0, 2.0)
    """
    if not points:
        return 0.0, 0.0
    ts = [p[0] for p in points]
    k = int(np.searchsorted(ts, t_mid, side="right")) - 1
    if k < 0:
        return points[0][1], 0.0
    if k >= len(points) - 1:
        return points[-1][1], 0.0
    (t0, v0), (t1, v1) = points[k], points[k + 1]
    c = (v1 - v0) / (t1 - t0)
    return v0 - c * t0, c


# --- nodes -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Inertia(Element):
    """A rotating mass: inertia J [kg m^2]; with ``translation`` a sliding mass [kg]. J = 0:
    a massless node between springs, condensed out exactly (see :class:`Network`)."""

    name: str
    J: float
    translation: bool = False

    UNITS: ClassVar[dict] = {"J": None}


@dataclass(frozen=True)
class Gear(Element):
    """A rigid gear stage: node ``b`` turns at ``1 / ratio`` of node ``a`` (phi_b = phi_a /
    ratio [-], or [rad/m] from a rotating to a translating node; negative: ``b`` turns the
    other way, as the wheel of an external gear pair does). The two nodes become one
    coordinate; no stiff spring is needed. The constraint's virtual work gives the torque
    balance T_b = ratio T_a on the pair, sign included (b's inertia reflects to a as J_b /
    ratio^2, whatever the sign)."""

    a: str
    b: str
    ratio: float
    name: str = ""

    UNITS: ClassVar[dict] = {"ratio": None}

    def check(self, net) -> None:
        check_gear_ratio(self.name, self.ratio)


def check_gear_ratio(name: str, ratio: float) -> float:
    """A rigid gear's ratio: finite and not 0 (negative reverses); an :class:`InputError`
    naming ``<name> ratio`` otherwise.

    >>> check_gear_ratio("g", -2.0)
    -2.0
    """
    if not (math.isfinite(ratio) and ratio != 0):
        raise InputError(f"{ratio:g} is not allowed; a gear ratio must be finite and not 0 (negative: the "
                         "pair reverses)", param=f"{name or 'gear'} ratio")
    return ratio


# --- couplings -------------------------------------------------------------------------------
@dataclass(frozen=True)
class Coupling(Element):
    """Spring-damper C [N m/rad], d [N m s/rad] from node ``i`` to ``U`` x node ``j`` (``j``
    None: to the frame). Potential V = C/2 (phi_i - U phi_j)^2, dissipation R = d/2 (omega_i -
    U omega_j)^2; its torque on i is ``-C (phi_i - U phi_j) - d (omega_i - U omega_j)`` and on
    j ``U`` times the opposite [M16 eq. 3-7], assembled instead of typed.
    Output ``T_<name>``: C (phi_i - U phi_j) + d (omega_i - U omega_j) [N m, or N between
    translating nodes]."""

    name: str
    i: str
    j: str | None
    C: float
    d: float
    U: float = 1.0

    UNITS: ClassVar[dict] = {"C": None, "d": None, "U": ""}
    ORDER: ClassVar[int] = 10

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        require_range(self.name, self.C, "N*m/rad", low=0.0)
        require_range(self.name, self.d, "N*m*s/rad", low=0.0)
        require_positive(f"U_{self.name}", self.U, "")

    def deflection(self, net) -> np.ndarray:
        """The row g over the coordinates with deflection phi_i - U phi_j = g . q."""
        g = net.node_row(self.i).copy()
        if self.j is not None:
            g -= self.U * net.node_row(self.j)
        return g

    def matrices(self, net) -> list:
        return [(self.deflection(net), self.C, self.d)]

    def outputs(self, net, t, X, accel) -> dict:
        g = self.deflection(net)
        n = net.n
        unit = "N" if net.node(self.i).translation else "N m"
        return {f"T_{self.name}": (self.C * (g @ X[:n]) + self.d * (g @ X[n:2 * n]), unit)}

    @classmethod
    def outputs_of(cls, net, elements, t, X, accel) -> dict:
        """Every coupling's torque from two products: the deflections ``g . phi`` and their
        rates ``g . omega`` of all couplings (rows g over the coordinates), then
        ``C (g . phi) + d (g . omega)``. (Not ``(C g) . phi``: the angles grow over a run and
        the deflection is their small difference, taken first.)"""
        n = net.n
        rows = np.array([c.deflection(net) for c in elements]).reshape(len(elements), n)
        X = np.asarray(X)
        shape = (len(elements),) + (1,) * (X.ndim - 1)
        C = np.array([c.C for c in elements]).reshape(shape)
        d = np.array([c.d for c in elements]).reshape(shape)
        T = rows @ X[:n]
        T *= C
        rate = rows @ X[n:2 * n]
        rate *= d
        T += rate
        return {f"T_{c.name}": (T[k], "N" if net.node(c.i).translation else "N m") for k, c in enumerate(elements)}


@dataclass(frozen=True)
class Strand(Element):
    """A tension-only strand (chain, belt span) from node ``i`` to node ``j`` (None: the frame).

    stiffness c [N/m], damping b [N s/m], radii r_i, r_j [m] where it leaves the nodes
    (1 for a translating node), pretension F_0 [N]. Elongation
    ``delta = r_i phi_i - r_j phi_j + F_0 / c``; force ``c delta + b delta'`` while taut
    [RP eq. 8-11]. The switching core handles it (see :class:`Network`).
    """

    name: str
    i: str
    j: str | None
    r_i: float
    r_j: float
    stiffness: float
    damping: float
    preload: float = 0.0

    UNITS: ClassVar[dict] = {"r_i": "m", "r_j": "m", "stiffness": "N/m", "damping": "N*s/m", "preload": "N"}

    @property
    def default_taut(self) -> bool:
        """Taut in the network's default pattern (its modes and natural frequencies)."""
        return True

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        for end in (self.i, self.j):
            if end is not None and net.node(end).J == 0:
                raise InputError(f"strand {self.name} ends on {end}, a node without inertia: a strand needs "
                                 "an inertia at each end (give the node its sprocket's or pulley's inertia)",
                                 param="network")
        require_positive(f"{self.name} stiffness", self.stiffness, "N/m")
        require_range(f"{self.name} damping", self.damping, "N*s/m", low=0.0)
        require_range(f"{self.name} preload", self.preload, "N", low=0.0)
        require_positive(f"{self.name} r_i", self.r_i, "m")
        if self.j is not None:
            require_positive(f"{self.name} r_j", self.r_j, "m")

    def geometry(self, net) -> np.ndarray:
        """The row G over the coordinates with delta = G . q + F_0 / c."""
        g = self.r_i * net.node_row(self.i)
        if self.j is not None:
            g = g - self.r_j * net.node_row(self.j)
        return g


# --- loads and drives --------------------------------------------------------------------------
@dataclass(frozen=True)
class Load(Element):
    """Load torque on ``node`` against the motion [N m]:
    ``mean + amplitude sin(omega t + phase) + table(t)``; with ``in_angle`` True the sine is
    ``amplitude sin(order phi_node + phase)`` (locked to the shaft angle: nonlinear). ``table``: (t [s], torque [N m]) points, linear in
    between, a repeated time is a jump, held constant outside. The sine acts from ``start``
    [s] on. A negative load drives the node. Output ``load_<node>`` (summed per node)."""

    node: str
    mean: float = 0.0
    amplitude: float = 0.0
    omega: float = 0.0
    phase: float = 0.0
    in_angle: bool = False
    table: Points = ()
    start: float = 0.0
    order: float = 1.0

    UNITS: ClassVar[dict] = {"mean": None, "amplitude": None, "omega": "rad/s", "phase": "rad", "start": "s",
                             "order": ""}
    ORDER: ClassVar[int] = 30

    @property
    def nonlinear_kind(self) -> bool:
        return self.in_angle

    def check(self, net) -> None:
        net.check_ends("a load", self.node, None)
        net.require_inertia(self.node, "a load")
        check_points(self.table, f"load on node {self.node}")

    def torque(self, t, phi=0.0):
        """The load torque at time ``t`` (and node angle ``phi``) [N m]."""
        arg = self.order * phi if self.in_angle else self.omega * np.asarray(t)
        out = self.mean + self.amplitude * np.sin(arg + self.phase) * (np.asarray(t) >= self.start)
        if self.table:
            out = out + piecewise(self.table, t)
        return out

    def tables(self) -> list[Points]:
        return [self.table] if self.table else []

    def breaks(self) -> list[float]:
        return [self.start] if self.amplitude and self.start else []

    def frequencies(self) -> list[float]:
        return [self.omega] if (not self.in_angle and self.amplitude and self.omega) else []

    def inputs(self, p) -> None:
        p.torque(self.node, -self.mean)
        if self.table:
            a, c = piece(self.table, p.t_mid)
            p.torque(self.node, -a, -c)
        if self.in_angle or not self.amplitude or p.t_mid < self.start:
            return
        if self.omega:
            p.sine(self.node, self.omega, -self.amplitude * math.cos(self.phase), -self.amplitude * math.sin(self.phase))
        else:  # omega = 0: a constant amplitude * sin(phase)
            p.torque(self.node, -self.amplitude * math.sin(self.phase))

    def nonlinear(self, net, t, X, out, constrained: bool) -> None:
        if not self.in_angle:
            return
        c, f = net.coord(self.node)
        if c in net.fixed and constrained:
            return
        arg = self.order * f * X[c] + self.phase
        out[net.n + c] -= f * self.amplitude * np.sin(arg) * (np.asarray(t) >= self.start) / net.mass[c]

    def jacobian(self, net, x, jac) -> None:
        c, f = net.coord(self.node)
        if self.in_angle and c not in net.fixed:
            k = self.order * f
            jac[net.n + c, c] -= f * k * self.amplitude * np.cos(k * x[c] + self.phase) / net.mass[c]

    def outputs(self, net, t, X, accel) -> dict:
        c, f = net.coord(self.node)
        unit = "N" if net.node(self.node).translation else "N m"
        return {f"load_{self.node}": (np.broadcast_to(self.torque(t, f * X[c]), np.shape(t)), unit)}

    @classmethod
    def outputs_of(cls, net, elements, t, X, accel) -> dict:
        """Loads summed per node; a sinusoid in time from the network's generator rows
        ``sin w t``, ``cos w t`` (computed once for all loads, or propagated with the states
        by an exact run): ``sin(w t + phase) = cos(phase) sin w t + sin(phase) cos w t``."""
        out = {}
        shape = np.shape(t)
        g = None
        for el in elements:
            if el.in_angle or el.table or not (el.amplitude and el.omega) or not shape:
                (name, value), = el.outputs(net, t, X, accel).items()
            else:
                if g is None:
                    g = net.generators(t)
                    freqs = net.frequencies()
                    first = 1 + int(net.ramp)
                q = first + 2 * next(i for i, w in enumerate(freqs) if math.isclose(w, el.omega))
                wave = g[q] if el.phase == 0 else math.cos(el.phase) * g[q] + math.sin(el.phase) * g[q + 1]
                if el.start > 0:
                    wave = wave * (np.asarray(t) >= el.start)
                name = f"load_{el.node}"
                value = (el.mean + el.amplitude * wave, "N" if net.node(el.node).translation else "N m")
            if name in out:
                value = (out[name][0] + value[0], value[1])
            out[name] = value
        return out


@dataclass(frozen=True)
class Prescribed(Element):
    """A node whose motion is imposed (an ideal speed-controlled drive): it starts at
    ``speed`` [rad/s] and accelerates at ``accel``, a piecewise-linear table of
    (t [s], accel [rad/s^2]) points (empty: constant speed). Its coupling torques are what
    the drive must deliver (output ``T_drive_<node>``)."""

    node: str
    speed: float = 0.0
    accel: Points = ()

    UNITS: ClassVar[dict] = {"speed": None}
    ORDER: ClassVar[int] = 40

    def check(self, net) -> None:
        net.check_ends("prescribed motion", self.node, None)
        net.require_inertia(self.node, "prescribed motion")
        check_points(self.accel, f"acceleration of node {self.node}")

    def tables(self) -> list[Points]:
        return [self.accel] if self.accel else []

    def outputs(self, net, t, X, accel) -> dict:
        c, f = net.coord(self.node)
        free = net.derivative(t, X, constrained=False)
        unit = "N" if net.node(self.node).translation else "N m"
        return {f"T_drive_{self.node}": (net.mass[c] * (accel[c] - free[net.n + c]) / f, unit)}


@dataclass(frozen=True)
class InductionMotor(Element):
    r"""First-order dynamic characteristic of an induction motor on ``node``.

    .. math:: \dot M = \frac{2 M_c \omega_c}{\omega_0} (\omega_0 - \dot\varphi) - \omega_c S_c M

    breakdown_torque M_c [N m], breakdown_slip S_c [-], sync_speed omega_0 [rad/s],
    supply omega_c = 2 pi f [rad/s]. The characteristic of [M16 eq. 2] (after Pinchuk 1957):
    a lag of time constant 1/(omega_c S_c) on the linearised Kloss characteristic
    M = 2 M_c s / S_c, s = (omega_0 - omega)/omega_0.

    ``sync_table`` (t [s], rad/s): an inverter start. The synchronous speed follows the
    table while the characteristic keeps its slope 2 M_c / (S_c omega_0) (V/f control holds
    the slip speed at breakdown), so the motor stays on the linear part of its curve; a
    direct-on-line start from rest is far outside it (the line gives 2 M_c / S_c at s = 1).
    Its torque is the state ``M_<name>`` [N m]; several motors need several names.
    """

    node: str
    breakdown_torque: float
    breakdown_slip: float
    sync_speed: float
    supply: float
    sync_table: Points = ()
    name: str = "motor"

    UNITS: ClassVar[dict] = {"breakdown_torque": "N*m", "breakdown_slip": "", "sync_speed": "rad/s",
                             "supply": "rad/s"}
    ORDER: ClassVar[int] = 50

    def check(self, net) -> None:
        net.check_ends(f"motor {self.name}", self.node, None)
        net.require_inertia(self.node, f"motor {self.name}")
        if net.coord(self.node)[0] in net.fixed:
            raise InputError(f"the motor must sit on a free node, not {self.node!r}", param="network")
        for name in ("breakdown_torque", "breakdown_slip", "sync_speed", "supply"):
            require_positive(name, getattr(self, name), "")
        check_points(self.sync_table, "synchronous speed")

    def static_torque(self, speed: float) -> float:
        """The steady torque at ``speed`` [N m]: 2 M_c (omega_0 - omega) / (omega_0 S_c)."""
        return 2 * self.breakdown_torque * (self.sync_speed - speed) / (self.sync_speed * self.breakdown_slip)

    def states(self) -> list[tuple[str, str]]:
        return [(f"M_{self.name}", "N m")]

    def tables(self) -> list[Points]:
        return [self.sync_table] if self.sync_table else []

    def inputs(self, p) -> None:
        c, f = p.net.coord(self.node)
        s = p.state(self)
        n = p.net.n
        gain = 2 * self.breakdown_torque * self.supply / self.sync_speed
        p.A[n + c, s] = f * p.Minv[c]                    # the motor torque drives its node
        p.A[s, n + c] = -gain * f                         # its node's speed, f omega_c
        p.A[s, s] = -self.supply * self.breakdown_slip
        if self.sync_table:                               # 2 M_c w_c / w_0 * w_0(t)
            a, cc = piece(self.sync_table, p.t_mid)
            p.B[s, 0] = gain * a
            p.B[s, p.ramp] = gain * cc
        else:
            p.B[s, 0] = gain * self.sync_speed
