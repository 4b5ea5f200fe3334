"""A drive train as a graph: inertias (or masses), spring-damper couplings with a ratio,
tension-only strands (chains, belt spans), an induction motor, speed-controlled drives and
load torques. The network assembles its matrices once (Lagrange with Rayleigh dissipation)
and gives the first-order system ``x' = A x + B g(t) + f(t, x)`` with names and units for
every state and output. SI floats only; no pint, no click.

State vector: ``x = [phi_1..phi_n, omega_1..omega_n, (M_motor)]``; a translating node
(``Inertia(..., translation=True)``) has a position [m] and a speed [m/s] instead.

Coupling k between nodes i and j with ratio U (``j`` None: to the frame):

    potential   V = C/2 (phi_i - U phi_j)^2,   dissipation  R = d/2 (omega_i - U omega_j)^2

so its torque on i is ``-C (phi_i - U phi_j) - d (omega_i - U omega_j)`` and on j ``U`` times
the opposite (Mamatova et al. 2016, eq. 3-7, assembled instead of typed).

A strand from node i to node j (Rusek & Popenda, eq. 8-11) has the elongation
``delta = r_i phi_i - r_j phi_j + F_0 / c`` (r: pitch radius [m], 1 for a translating node;
F_0 the pretension) and the force ``F = c delta + b delta'`` while it is taut, 0 while slack.
It is taut while ``delta > 0`` (the paper's eq. 9-11) *and* ``F > 0``: the paper lets the
damper push while the elongation is still positive; a chain cannot push, so we also
release a strand whose force reaches zero. Between switches the network is linear; the
switching surfaces ``delta = 0`` and ``F = 0`` are hyperplanes in the state, which the core
locates on the exact solution.

Inputs that are piecewise linear in time (tabulated loads, a prescribed acceleration, the
reference and feed-forward of a speed loop) keep the network linear between their break
points: the generators are ``g = [1, t, sin w1 t, cos w1 t, ...]`` and ``B`` depends on the
time segment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from beltcalc.errors import FloatRangeError, InputError, did_you_mean, require_positive
from beltcalc.sim.elements import (Coupling, Element, Gear, Inertia, InductionMotor, Load, Points, Prescribed,
                                   SpeedLoop, Strand, check_gear_ratio, check_points, piece, piecewise)

__all__ = ["Coupling", "Event", "Gear", "Inertia", "InductionMotor", "Load", "Network", "Piece", "Prescribed",
           "SpeedLoop", "Strand", "check_points", "piecewise", "series_stiffness"]


def series_stiffness(c1: float, c2: float) -> float:
    r"""Stiffness of two springs in series, eliminating the massless node between them [N m/rad].

    .. math:: c_{1-2} = \frac{c_1 c_2}{c_1 + c_2}

    Eq. (3) of Rusek & Popenda (clutch and shaft in series). Exact for springs without
    dampers; a damper on the massless node would leave a first-order element instead.

    >>> series_stiffness(300.0, 600.0)
    200.0
    """
    require_positive("c1", c1, "N*m/rad")
    require_positive("c2", c2, "N*m/rad")
    return c1 * c2 / (c1 + c2)


@dataclass(frozen=True)
class Event:
    """A switching surface of the current mode: ``row @ z`` (z = [x, g]) crossing zero in
    ``direction`` (+1 rising, -1 falling) may switch strand ``strand``."""

    strand: int
    kind: str       # "delta" (elongation) or "force"
    direction: int
    row: np.ndarray


def _add_outer(M: np.ndarray, g: np.ndarray, c: float) -> None:
    """M += c g g^T on the nonzero entries of g only (a coupling touches two coordinates)."""
    if c:
        idx = np.flatnonzero(g)
        v = g[idx]
        M[idx[:, None], idx] += c * (v[:, None] * v)       # np.ix_ and np.outer, without their overhead


class Piece:
    """What elements write into ``[A | B]`` of ``x' = A x + B g`` on one time piece (the one
    holding ``t_mid``): torques ``a + c t`` and sinusoids on a node (taken to its coordinate
    through the node's factor), and rows of their own states."""

    def __init__(self, net: "Network", A: np.ndarray, B: np.ndarray, t_mid: float):
        self.net, self.A, self.B, self.t_mid = net, A, B, t_mid
        self.Minv = 1.0 / net.mass
        self.ramp = 1 if net.ramp else None
        self._first = 1 + int(net.ramp)
        self._freqs = net.frequencies()

    def torque(self, node: str, a: float, c: float = 0.0) -> None:
        """A torque (force on a translating node) ``a + c t`` [N m] acting on ``node``."""
        k, f = self.net.coord(node)
        n = self.net.n
        self.B[n + k, 0] += f * a * self.Minv[k]
        if c:
            self.B[n + k, self.ramp] += f * c * self.Minv[k]

    def sine(self, node: str, omega: float, s: float, c: float) -> None:
        """A torque ``s sin(omega t) + c cos(omega t)`` [N m] on ``node``."""
        k, f = self.net.coord(node)
        q = self._first + 2 * next(i for i, w in enumerate(self._freqs) if math.isclose(w, omega))
        self.B[self.net.n + k, q] += f * s * self.Minv[k]
        self.B[self.net.n + k, q + 1] += f * c * self.Minv[k]

    def state(self, element) -> int:
        """Index of an element's own (first) state."""
        return self.net.state_index[id(element)]


def _require_finite(*arrays: np.ndarray, net: "Network | None" = None) -> None:
    """Refuse a first-order system with an entry beyond the float range: a stiffness,
    damping or load divided by a mass or inertia overflows (e.g. 1e308 N m/rad on 1e-5
    kg m^2) and no solver can do anything with it. With ``net`` (the arrays ``A``, ``B`` of
    :meth:`Network.first_order`) the message names the coordinate and the term."""
    with np.errstate(invalid="ignore"):
        if all(np.isfinite(a).all() for a in arrays):
            return
    what = "a stiffness, damping or load over a mass or inertia"
    if net is not None and len(arrays) == 2:
        A, B = arrays
        n = net.n
        bad = np.argwhere(~np.isfinite(A))
        if bad.size:
            row, col = (int(v) for v in bad[0])
            if n <= row < 2 * n:
                c = net.coords[row - n]
                unit = "m" if net.node(c).translation else "rad"
                term = ("stiffness" if col < n else "damping" if col < 2 * n else "a motor's or an element's term")
                what = f"the {term} on {c} over its {'mass' if unit == 'm' else 'inertia'}"
        elif (~np.isfinite(B)).any():
            row = int(np.argwhere(~np.isfinite(B))[0][0])
            if n <= row < 2 * n:
                what = f"a load on {net.coords[row - n]} over its inertia"
    raise FloatRangeError(f"the drive's equations of motion overflow a float: {what} is beyond 1e308 in SI "
                          "units; check the values and their units")


def _require_finite_elements(elements) -> None:
    """Refuse an element with a value beyond the float range (a stiffness G pi d^4 / 32 L of a
    shaft a millionth of a micrometre long): each float field of each element kind."""
    import dataclasses

    for el in elements:
        if not dataclasses.is_dataclass(el):
            continue
        for f in dataclasses.fields(el):
            v = getattr(el, f.name)
            if isinstance(v, float) and not math.isfinite(v):
                kind = type(el).__name__.lower()
                name = getattr(el, "name", "") or f"on {getattr(el, 'node', '')}"
                unit = getattr(el, "UNITS", {}).get(f.name) or "in SI units"
                what = {"C": "stiffness C", "d": "damping d", "J": "inertia J", "U": "ratio U",
                        "omega": "frequency omega"}.get(f.name, f.name)
                raise FloatRangeError(f"the {what} of {kind} {name} overflows a float "
                                      f"({'not a number' if math.isnan(v) else 'beyond 1e308 ' + unit})")


@dataclass
class Network:
    """Nodes and elements (couplings, rigid gears, strands, loads, drives), assembled into the
    matrices of the first-order system. ``motor`` is one :class:`InductionMotor` or a list;
    ``elements`` takes any other element kind (:class:`~beltcalc.sim.elements.Element`):
    the network only calls the hooks every kind has.

    Generalised coordinates: every rigid gear group (nodes joined by :class:`Gear`) is one
    coordinate, the angle of its first node; a node's angle is ``node_row(name) . q``.
    A group without inertia (massless nodes between springs) is condensed out exactly:
    its angle follows the springs' static balance, ``q_m = -K_mm^-1 K_mr q_r`` (Guyan's
    reduction, exact without inertia), provided its dampers are proportional to its springs
    (else a first-order element would be left). Loads, drives and strands must sit on nodes
    with inertia.
    """

    nodes: list[Inertia]
    couplings: list[Coupling]
    loads: list[Load] = field(default_factory=list)
    motor: InductionMotor | list | None = None
    prescribed: list[Prescribed] = field(default_factory=list)
    strands: list[Strand] = field(default_factory=list)
    speed_loops: list[SpeedLoop] = field(default_factory=list)
    gears: list[Gear] = field(default_factory=list)
    elements: list[Element] = field(default_factory=list)

    def __post_init__(self):
        _require_finite_elements([*self.nodes, *self.couplings, *self.loads, *self.prescribed, *self.strands,
                                  *self.speed_loops, *self.gears, *self.elements,
                                  *(self.motor if isinstance(self.motor, (list, tuple)) else [self.motor])])
        names = [n.name for n in self.nodes]
        if len(set(names)) != len(names):
            raise InputError(f"node names repeat: {names}", param="network")
        self._node = {n.name: n for n in self.nodes}
        self._row_of = {n.name: k for k, n in enumerate(self.nodes)}
        for nd in self.nodes:
            if nd.J != 0:
                require_positive(f"J_{nd.name}", nd.J, "kg*m^2")
        self.motors = [] if self.motor is None else (list(self.motor) if isinstance(self.motor, (list, tuple))
                                                     else [self.motor])
        for m in self.motors:
            if not isinstance(m, InductionMotor):
                raise InputError(f"motor must be an InductionMotor (or a list of them), not {type(m).__name__}",
                                 param="network")
        motor_names = [m.name for m in self.motors]
        if len(set(motor_names)) != len(motor_names):
            raise InputError(f"several motors named {motor_names}: give each motor a name of its own",
                             param="network")
        self._coordinates()
        # every element that stamps itself: the named kinds, then any other kind (``elements``)
        self.elements = [*self.couplings, *self.speed_loops, *self.loads, *self.prescribed, *self.motors,
                         *self.elements]
        self.fixed = {}
        for p in self.prescribed:
            p.check(self)
            c = self.coord(p.node)[0]
            if c in self.fixed:
                raise InputError(f"prescribed motion names node {p.node!r} (or one geared to it) twice",
                                 param="network")
            self.fixed[c] = p
        looped = set()
        for s in self.speed_loops:
            c = self.coord(s.node)[0] if s.node in self._node else None
            if c is None or c in self.fixed or c in looped:
                raise InputError(f"a speed loop must sit on a free node of its own, not {s.node!r}",
                                 param="network")
            looped.add(c)
        for el in self.elements + list(self.strands) + list(self.gears):
            el.check(self)
        self.state_index, extra = {}, []
        for el in self.elements:
            if el.states():
                self.state_index[id(el)] = 2 * self.n + len(extra)
                extra += el.states()
        self._extra_states = extra
        # what the elements make of the network, asked many times a run: once
        self._linear = not any(el.nonlinear_kind for el in self.elements)
        self._ramp = any(el.tables() or el.breaks() for el in self.elements)
        freqs: list[float] = []
        for el in self.elements:
            for w in el.frequencies():
                if not any(math.isclose(w, v) for v in freqs):
                    freqs.append(w)
        self._freqs = tuple(freqs)
        self._condense_check()
        self._K0, self._D0 = self._assemble()
        self._G = np.array([s.geometry(self) for s in self.strands]).reshape(len(self.strands), self.n)
        self._cache: dict = {}
        self._rows = None
        self._stamps = None
        self.taut = tuple(True for _ in self.strands)
        self.K, self.D = self.stiffness_damping(self.taut)

    # --- coordinates: rigid gears merged, massless groups condensed -----------------------------
    def _coordinates(self) -> None:
        """Node -> row over the coordinates (``self.T``, nodes x n), and the coordinates' masses."""
        index = {nd.name: k for k, nd in enumerate(self.nodes)}
        parent = list(range(len(self.nodes)))
        factor = [1.0] * len(self.nodes)          # phi_k = factor[k] * phi_parent[k]

        def find(k):
            f = 1.0
            while parent[k] != k:
                f *= factor[k]
                k = parent[k]
            return k, f

        for g in self.gears:
            for end in (g.a, g.b):
                if end not in index:
                    raise InputError(f"gear {g.name or g.a + '-' + g.b} names an unknown node {end!r}; "
                                     + did_you_mean(str(end), [nd.name for nd in self.nodes]), param="network")
            check_gear_ratio(g.name, g.ratio)
            (ra, fa), (rb, fb) = find(index[g.a]), find(index[g.b])
            # phi_a = fa R_a, phi_b = fb R_b, and phi_b = phi_a / ratio
            if ra == rb:
                if not math.isclose(fb, fa / g.ratio, rel_tol=1e-9):
                    raise InputError(f"rigid gears form a loop with inconsistent ratios at {g.name or g.b!r}: "
                                     f"{g.b} would turn at {fb:.6g} and at {fa / g.ratio:.6g} times "
                                     f"{self.nodes[ra].name}", param="network")
            elif ra < rb:      # the earlier-listed node stays the root
                parent[rb], factor[rb] = ra, fa / (g.ratio * fb)
            else:
                parent[ra], factor[ra] = rb, g.ratio * fb / fa
        roots, f_of = [], []
        for k in range(len(self.nodes)):
            r, f = find(k)
            roots.append(r)
            f_of.append(f)
        groups = sorted(set(roots))
        gmass = {r: 0.0 for r in groups}
        for k, nd in enumerate(self.nodes):
            square = f_of[k] * f_of[k]
            if not math.isfinite(square):
                raise FloatRangeError(f"the rigid gears make node {nd.name} turn {abs(f_of[k]):.3g} times as fast as "
                                      f"{self.nodes[roots[k]].name}: the square of that ratio, which takes its "
                                      "inertia and springs to one coordinate, overflows a float (beyond 1e308)")
            gmass[roots[k]] += square * nd.J
        heavy = [r for r in groups if gmass[r] > 0]
        light = [r for r in groups if gmass[r] == 0]
        self.coords = [self.nodes[r].name for r in heavy]
        self.index = {name: c for c, name in enumerate(self.coords)}
        self.mass = np.array([gmass[r] for r in heavy], dtype=float)
        n, L = len(heavy), len(light)
        F = np.zeros((len(self.nodes), n + L))    # node -> group coordinates (heavy first)
        col = {r: c for c, r in enumerate(heavy + light)}
        for k in range(len(self.nodes)):
            F[k, col[roots[k]]] = f_of[k]
        self._group_rows, self._light = F, L
        self._massless = {self.nodes[k].name for k in range(len(self.nodes)) if roots[k] in light}
        if L == 0:
            self.T = F
            return
        # static condensation of the massless groups through the couplings' springs
        K = np.zeros((n + L, n + L))
        D = np.zeros_like(K)
        for c in self.couplings:
            for end in (c.i, c.j):
                if end is not None and end not in index:
                    raise InputError(f"element {c.name} names an unknown node {end!r}; "
                                     + did_you_mean(str(end), [nd.name for nd in self.nodes]), param="network")
            g = F[index[c.i]] - (c.U * F[index[c.j]] if c.j is not None else 0.0)
            K += c.C * np.outer(g, g)
            D += c.d * np.outer(g, g)
        Kmm, Kmr = K[n:, n:], K[n:, :n]
        try:
            cond = np.linalg.cond(Kmm)
        except np.linalg.LinAlgError:
            cond = math.inf
        if not cond < 1e12:
            lonely = [self.nodes[r].name for r in light]
            raise InputError(f"node(s) {', '.join(lonely)} have no inertia and no spring path to one: give "
                             "each node an inertia, or connect it by a coupling to a node that has one",
                             param="network")
        R = np.vstack([np.eye(n), -np.linalg.solve(Kmm, Kmr)])     # group coordinates -> heavy ones
        self._condensed_D = (D, R)
        self.T = F @ R

    def _condense_check(self) -> None:
        """The condensation is exact only if no damper pulls on a massless group as it follows
        the springs' balance: D_m R = 0 (dampers proportional to the springs, or none)."""
        if not self._light:
            return
        D, R = self._condensed_D
        n = self.n
        scale = float(np.abs(D).max()) * float(np.abs(R).max()) if D.size else 0.0
        if scale and float(np.abs(D[n:] @ R).max()) > 1e-9 * scale:
            names = sorted(self._massless)
            raise InputError(f"node(s) {', '.join(names)} have no inertia and dampers not proportional to their "
                             "springs: condensing them would not be exact; give them an inertia, or make each "
                             "damping d = beta C with one beta", param="network")
        for el in self.elements:
            node = getattr(el, "node", None)
            if node in self._massless:
                raise InputError(f"{type(el).__name__} on {node!r}: a node without inertia cannot carry a load "
                                 "or a drive; give it the inertia of its parts", param="network")

    def check_ends(self, name: str, i: str | None, j: str | None) -> None:
        """Refuse an element that names a node that does not exist."""
        for end in (i, j):
            if end is not None and end not in self._node:
                raise InputError(f"element {name} names an unknown node {end!r}; "
                                 + did_you_mean(str(end), list(self._node)), param="network")

    def require_inertia(self, node: str, what: str) -> None:
        """Refuse a load or drive on a node without inertia (it is condensed out)."""
        if node in self._massless:
            raise InputError(f"{what} on {node!r}: a node without inertia cannot carry a load or a drive; "
                             "give it the inertia of its parts", param="network")

    def node(self, name: str) -> Inertia:
        """The node called ``name``."""
        return self._node[name]

    def node_row(self, name: str) -> np.ndarray:
        """The row over the coordinates that gives node ``name``'s angle (position)."""
        return self.T[self._row_of[name]]

    def coord(self, name: str) -> tuple[int, float]:
        """(coordinate, factor) of a node with inertia: phi_node = factor * q[coordinate]."""
        row = self.node_row(name)
        c = int(np.flatnonzero(row)[0])
        return c, float(row[c])

    # --- structure ------------------------------------------------------------------------
    @property
    def n(self) -> int:
        """Number of generalised coordinates (nodes with inertia, gear groups merged)."""
        return len(self.coords)

    @property
    def M(self) -> np.ndarray:
        """The (diagonal) mass matrix of the coordinates [kg m^2 or kg]."""
        return np.diag(self.mass)

    @property
    def size(self) -> int:
        """Number of states."""
        return 2 * self.n + len(self._extra_states)

    @property
    def linear(self) -> bool:
        """True when the network is linear between switches (strands) and time break points
        (tables): every load is constant, sinusoidal or tabulated in time, so an exact
        solution exists. An element whose terms are nonlinear (a load locked to a shaft angle:
        ``nonlinear_kind``) makes it nonlinear."""
        return self._linear

    @property
    def ramp(self) -> bool:
        """True when a piecewise-linear input needs the generator ``t``."""
        return self._ramp

    @property
    def smooth(self) -> bool:
        """No strands and no time break points: one linear system over the whole run."""
        return not self.strands and not self.ramp

    def breaks(self, t_end: float) -> list[float]:
        """The times in (0, t_end) where a piecewise-linear input changes its piece."""
        times = set()
        for table in self._tables():
            times.update(p[0] for p in table)
        for el in self.elements:
            times.update(el.breaks())
        return sorted(t for t in times if 0.0 < t < t_end)

    def initial_state(self) -> np.ndarray:
        """Rest, except the prescribed nodes at their initial speed."""
        x = np.zeros(self.size)
        for k, p in self.fixed.items():
            x[self.n + k] = p.speed / self.coord(p.node)[1]
        return x

    def state_names(self) -> list[tuple[str, str]]:
        """(name, SI unit) of every state: each coordinate's angle and speed (named after its
        first node), then the elements' own states."""
        heads = [self._node[c] for c in self.coords]
        out = [(f"x_{n.name}", "m") if n.translation else (f"phi_{n.name}", "rad") for n in heads]
        out += [(f"v_{n.name}", "m/s") if n.translation else (f"omega_{n.name}", "rad/s") for n in heads]
        return out + list(self._extra_states)

    def accel_names(self) -> list[tuple[str, str]]:
        """(name, SI unit) of every coordinate's acceleration."""
        return [(f"accel_{c}", "m/s^2" if self._node[c].translation else "rad/s^2") for c in self.coords]

    def _assemble(self):
        """K = G^T diag(C) G and D = G^T diag(d) G over every element's springs and dampers
        (rows g of G on the deflections g . q): two products, made exactly symmetric (the
        rounding of ``C_k g_ki g_kj`` depends on the order of its factors)."""
        n = self.n
        stamps = [s for el in self.elements for s in el.matrices(self)]
        if not stamps:
            return np.zeros((n, n)), np.zeros((n, n))
        G = np.array([g for g, _, _ in stamps], dtype=float).reshape(len(stamps), n)
        C = np.array([c for _, c, _ in stamps], dtype=float)
        d = np.array([d for _, _, d in stamps], dtype=float)
        K, D = (G.T * C) @ G, (G.T * d) @ G
        return 0.5 * (K + K.T), 0.5 * (D + D.T)

    def stiffness_damping(self, taut: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray]:
        """K and D with the strands that are ``taut``."""
        K, D = self._K0.copy(), self._D0.copy()
        for k, (s, on) in enumerate(zip(self.strands, taut)):
            if on:
                _add_outer(K, self._G[k], s.stiffness)
                _add_outer(D, self._G[k], s.damping)
        return K, D

    # --- first-order form -------------------------------------------------------------------
    def frequencies(self) -> list[float]:
        """The distinct angular frequencies of the time-sinusoidal inputs [rad/s]."""
        return list(self._freqs)

    def generators(self, t: np.ndarray | float) -> np.ndarray:
        """g(t) = [1, (t), sin w1 t, cos w1 t, ...], shape (len(g),) or (len(g), len(t)).
        For the very array ``t`` given to :meth:`seed_generators`: the rows given there
        (read-only)."""
        seeded = self.__dict__.get("_seeded")
        if seeded is not None and t is seeded[0]:
            return seeded[1]
        t = np.asarray(t, dtype=float)
        rows = [np.ones_like(t)]
        if self.ramp:
            rows.append(t.copy())
        for w in self.frequencies():
            rows += [np.sin(w * t), np.cos(w * t)]
        return np.array(rows)

    def seed_generators(self, t: np.ndarray, g: np.ndarray | None) -> None:
        """Let :meth:`generators` answer for the array ``t`` (the same object) with ``g``: the
        generators an exact run propagated with the states (its sines agree with ``sin w t``
        to rounding), so the outputs of a run do not evaluate them again. None forgets."""
        if g is None:
            self.__dict__.pop("_seeded", None)
            return
        g = g.view()
        g.flags.writeable = False
        self._seeded = (t, g)

    def generator_matrix(self) -> np.ndarray:
        """G of g' = G g."""
        p = 1 + int(self.ramp) + 2 * len(self.frequencies())
        G = np.zeros((p, p))
        if self.ramp:
            G[1, 0] = 1.0       # (t)' = 1
        first = 1 + int(self.ramp)
        for k, w in enumerate(self.frequencies()):
            s, c = first + 2 * k, first + 2 * k + 1
            G[s, c] = w         # (sin w t)' = w cos w t
            G[c, s] = -w        # (cos w t)' = -w sin w t
        return G

    def segment_starts(self, t_end: float = math.inf) -> list[float]:
        """Start times of the time segments on which every input is one linear piece."""
        return [0.0] + self.breaks(t_end)

    def segment(self, t: float, starts: list[float]) -> int:
        """Index of the segment that holds ``t`` (a break point belongs to the later one)."""
        return int(np.searchsorted(starts, t, side="right")) - 1

    @staticmethod
    def piece_time(seg: int, starts: list[float], t_end: float) -> float:
        """A time inside segment ``seg`` of a run ending at ``t_end`` (its middle): the key to
        its input pieces. The last segment ends at t_end, not at a break beyond the run."""
        end = starts[seg + 1] if seg + 1 < len(starts) else max(t_end, starts[seg])
        return starts[seg] + 0.5 * (end - starts[seg]) if end > starts[seg] else starts[seg]

    def first_order(self, taut: tuple[bool, ...] | None = None, t_mid: float = 0.0,
                    constrained: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """(A, B) of x' = A x + B g on the time piece that holds ``t_mid``, with the strands
        that are ``taut`` (default: all). ``constrained`` False leaves the prescribed nodes
        free (for their drive torque). The last 64 (strand mode, time piece) pairs are cached."""
        taut = self.taut if taut is None else tuple(taut)
        pieces = tuple(self._pieces(t_mid))
        key = (taut, pieces, constrained)
        hit = self._cache.get(key)
        if hit is None:
            hit = self._cache[key] = self._build(taut, t_mid, constrained)
            if len(self._cache) > 64:          # strand patterns are many on long chains: keep the recent
                self._cache.pop(next(iter(self._cache)))
        return hit

    def _tables(self) -> list[Points]:
        """Every piecewise-linear input table."""
        return [t for el in self.elements for t in el.tables()]

    def _pieces(self, t_mid):
        """The active piece of every table, and which inputs have switched on (a cache key)."""
        for table in self._tables():
            yield piece(table, t_mid)
        yield tuple(t_mid >= b for el in self.elements for b in el.breaks())

    def _build(self, taut, t_mid, constrained):
        n, m = self.n, self.size
        K, D = self.stiffness_damping(taut)
        Minv = 1.0 / self.mass
        A = np.zeros((m, m))
        A[:n, n:2 * n] = np.eye(n)
        A[n:2 * n, :n] = -Minv[:, None] * K
        A[n:2 * n, n:2 * n] = -Minv[:, None] * D
        B = np.zeros((m, 1 + int(self.ramp) + 2 * len(self.frequencies())))
        p = Piece(self, A, B, t_mid)
        for s, on, g in zip(self.strands, taut, self._G):
            if on and s.preload:                           # the pretension: -G^T F0
                for k in np.nonzero(g)[0]:
                    B[n + k, 0] += -g[k] * s.preload * Minv[k]
        for el in self.elements:
            el.inputs(p)
        if constrained:
            for k, pr in self.fixed.items():  # imposed motion: omega' = accel(t) / factor, an input
                f = self.coord(pr.node)[1]
                A[n + k, :] = 0.0
                B[n + k, :] = 0.0
                if pr.accel:
                    a, c = piece(pr.accel, t_mid)
                    B[n + k, 0] = a / f
                    if c:
                        B[n + k, p.ramp] = c / f
        _require_finite(A, B, net=self)
        return A, B

    def strand_stamps(self, fixed_rows: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What each strand adds to ``[A | B]`` when taut, as sparse entries ``(owner, row,
        col, value)`` over ``z = [x, g]`` (column ``size`` is the constant generator): its
        stiffness and damping on the two nodes' accelerations (``-M^-1 c g g^T`` and
        ``-M^-1 b g g^T``) and its pretension (``-M^-1 g F0``). Rows of prescribed nodes are
        left out, as :meth:`first_order` zeroes them (kept with ``fixed_rows``: the
        unconstrained system of a drive torque). With these, ``[A | B]`` of any strand
        pattern is the all-slack one plus the stamps of its taut strands: O(strands) work
        per pattern instead of a dense rebuild."""
        n, m = self.n, self.size
        Minv = 1.0 / self.mass
        owner, rows, cols, vals = [], [], [], []
        for k, (s, g) in enumerate(zip(self.strands, self._G)):
            nz = np.nonzero(g)[0]
            for a in nz:
                if a in self.fixed and not fixed_rows:
                    continue
                for b in nz:
                    owner += [k, k]
                    rows += [n + a, n + a]
                    cols += [b, n + b]
                    vals += [-Minv[a] * s.stiffness * g[a] * g[b], -Minv[a] * s.damping * g[a] * g[b]]
                if s.preload:
                    owner.append(k)
                    rows.append(n + a)
                    cols.append(m)
                    vals.append(-Minv[a] * g[a] * s.preload)
        vals = np.array(vals, dtype=float)
        _require_finite(vals)
        return (np.array(owner, dtype=np.int64), np.array(rows, dtype=np.int64),
                np.array(cols, dtype=np.int64), vals)

    def state_matrix(self, taut: tuple[bool, ...] | None = None) -> np.ndarray:
        """A of x' = A x + (inputs), with every strand taut unless ``taut`` says otherwise."""
        return self.first_order(taut)[0]

    def input_matrix(self, taut: tuple[bool, ...] | None = None, t_mid: float = 0.0) -> np.ndarray:
        """B of x' = A x + B g on the time piece holding ``t_mid``."""
        return self.first_order(taut, t_mid)[1]

    # --- strands ----------------------------------------------------------------------------
    def strand_rows(self) -> tuple[np.ndarray, np.ndarray]:
        """Rows over z = [x, g] giving every strand's elongation delta [m] and (taut) force F [N]
        (built once)."""
        if self._rows is None:
            n, m = self.n, self.size
            p = self.generators(0.0).size
            delta = np.zeros((len(self.strands), m + p))
            force = np.zeros_like(delta)
            for k, s in enumerate(self.strands):
                delta[k, :n] = self._G[k]
                delta[k, m] = s.preload / s.stiffness
                force[k, :n] = s.stiffness * self._G[k]
                force[k, n:2 * n] = s.damping * self._G[k]
                force[k, m] = s.preload
            self._rows = (delta, force)
        return self._rows

    def events(self, taut: tuple[bool, ...]) -> list[Event]:
        """The switching surfaces of a mode: a taut strand goes slack when its force or its
        elongation falls through zero; a slack one goes taut when its elongation rises
        through zero (its force is then b delta' > 0), or when its force rises through zero
        while it is still elongated."""
        delta, force = self.strand_rows()
        out = []
        for k, on in enumerate(taut):
            if on:
                out += [Event(k, "force", -1, force[k]), Event(k, "delta", -1, delta[k])]
            else:
                out += [Event(k, "delta", +1, delta[k]), Event(k, "force", +1, force[k])]
        return out

    def taut_after(self, k: int, z: np.ndarray, dz: np.ndarray, ahead: np.ndarray, h: float) -> bool:
        """Whether strand ``k`` is taut just after the state ``z``: elongation and force both
        positive. A value within 1e-6 of what its rate ``dz`` changes in the time ``h`` (a
        located switch sits that close to its surface) is judged by its rate, and a rate that
        small by the state ``ahead`` (a moment later, e.g. from rest)."""
        delta, force = self.strand_rows()

        def positive(row):
            v, rate = row @ z, row @ dz
            if abs(v) > 1e-6 * abs(rate) * h:
                return v > 0
            if abs(rate) * h > 1e-9 * abs(row @ ahead - v) and rate != 0:
                return rate > 0
            # no rate at all (at rest, a strand without pretension): taut unless the state a
            # moment later says it slackens; a chain just touching its sprockets is taut
            return row @ ahead >= v

        return positive(delta[k]) and positive(force[k])

    def taut_of(self, x: np.ndarray, t) -> np.ndarray:
        """Boolean (strands, samples): taut where elongation and force are both positive."""
        X = x if x.ndim == 2 else x[:, None]
        z = np.vstack([X, self.generators(np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],)))])
        delta, force = self.strand_rows()
        return (delta @ z > 0) & (force @ z > 0)

    def strand_forces(self, t, x: np.ndarray) -> dict[str, np.ndarray]:
        """Force in each strand [N]: c delta + b delta' while taut, else 0."""
        if not self.strands:
            return {}
        f = self._forces(np.vstack([x, self.generators(t)]))
        return {s.name: f[k] for k, s in enumerate(self.strands)}

    # --- right-hand side --------------------------------------------------------------------
    def derivative(self, t, x: np.ndarray, constrained: bool = True) -> np.ndarray:
        """x' at states ``x`` (columns) and times ``t``, each strand taut or slack by its own
        state (the raw, discontinuous right-hand side).

        Array expressions over all samples: per time piece (a few) the all-slack matrices,
        ``A x + B g``, plus the stamps of every taut strand (:meth:`strand_stamps`), summed
        row by row in the stamps' order over blocks of samples: no matrix per strand pattern
        (a long chain has nearly one pattern per sample)."""
        x = np.asarray(x, dtype=float)
        single = x.ndim == 1
        X = x[:, None] if single else x
        T = np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],))
        G = self.generators(t if np.shape(t) == T.shape else T)
        out = self._linear_part(T, X, G, constrained)
        if self.strands:
            self._add_strands(out, X, G, constrained)
        if not self.linear:
            out += self.nonlinear_terms(T, X, constrained)
        return out[:, 0] if single else out

    def _add_strands(self, out: np.ndarray, X: np.ndarray, G: np.ndarray, constrained: bool) -> None:
        """out += the stamps of the strands taut at each sample: every stamp entry
        ``value * z[col]`` where its strand is taut, added into its row in the stamps' order
        (the terms are large and cancel: a strand force is a small difference of stiffness
        times angle, so the order of the sum is kept). Array expressions over blocks of
        samples, one per rank of an entry within its row (a handful)."""
        key = ("stamps", constrained)
        hit = self._cache.get(key)
        if hit is None:
            owner, rows, cols, vals = self.strand_stamps(fixed_rows=not constrained)
            targets = np.flatnonzero(np.bincount(rows))          # the rows stamped, sorted (np.unique
            group = np.searchsorted(targets, rows)               # would import numpy.ma: 5 ms of start-up)
            rank = np.zeros(rows.size, dtype=np.int64)
            seen: dict[int, int] = {}
            for e, r in enumerate(group.tolist()):
                rank[e], seen[r] = seen.get(r, 0), seen.get(r, 0) + 1
            layers = [np.flatnonzero(rank == j) for j in range(int(rank.max()) + 1 if rank.size else 0)]
            hit = self._cache[key] = (targets, [(group[e], owner[e], cols[e], vals[e][:, None]) for e in layers])
        targets, layers = hit
        if not targets.size:
            return
        Z = np.vstack([X, G])
        taut = self._taut_rows(Z)
        N = X.shape[1]
        block = max(256, (1 << 18) // targets.size)
        for a in range(0, N, block):
            b = min(a + block, N)
            part = np.zeros((targets.size, b - a))
            for group, owner, cols, vals in layers:       # entries of distinct rows: no collision
                part[group] += vals * Z[cols, a:b] * taut[owner, a:b]
            out[targets, a:b] += part

    def _taut_rows(self, Z: np.ndarray) -> np.ndarray:
        """Boolean (strands, samples): elongation and force both positive at ``Z = [x, g]``."""
        delta, force = self.strand_rows()
        return (delta @ Z > 0) & (force @ Z > 0)

    def _linear_part(self, T: np.ndarray, X: np.ndarray, G: np.ndarray, constrained: bool) -> np.ndarray:
        """``A x + B g`` of the all-slack mode, time piece by time piece (one product on a run
        of one piece)."""
        none = tuple(False for _ in self.strands)
        t_end = float(T.max()) if T.size else 0.0
        starts = self.segment_starts(t_end)
        if len(starts) == 1:
            A, B = self.first_order(none, self.piece_time(0, starts, t_end), constrained)
            return A @ X + B @ G
        seg = np.searchsorted(starts, T, side="right") - 1
        out = np.empty_like(X)
        for sg in np.flatnonzero(np.bincount(seg)):        # the pieces present (np.unique imports numpy.ma)
            cols = seg == sg
            A, B = self.first_order(none, self.piece_time(int(sg), starts, t_end), constrained)
            out[:, cols] = A @ X[:, cols] + B @ G[:, cols]
        return out

    def _forces(self, Z: np.ndarray) -> np.ndarray:
        """Strand forces (strands x samples) at ``Z = [x, g]``: c delta + b delta' where the
        elongation and the force are both positive, else 0."""
        delta, force = self.strand_rows()
        f = force @ Z
        f[(delta @ Z <= 0) | (f <= 0)] = 0.0
        return f

    def nonlinear_terms(self, t, x: np.ndarray, constrained: bool = True) -> np.ndarray:
        """x' contribution of what the linear form cannot take: loads locked to a shaft angle."""
        out = np.zeros_like(x, dtype=float)
        for el in self.elements:
            el.nonlinear(self, t, x, out, constrained)
        return out

    def nonlinear_jacobian(self, x: np.ndarray) -> np.ndarray:
        """d(nonlinear_terms)/dx: only the angle-locked loads depend on the state."""
        jac = np.zeros((self.size, self.size))
        for el in self.elements:
            el.jacobian(self, x, jac)
        return jac

    # --- outputs ----------------------------------------------------------------------------
    def coupling_torques(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Torque transmitted by each coupling [N m]: C (phi_i - U phi_j) + d (omega_i - U omega_j)."""
        if not self.couplings:
            return {}
        torques = Coupling.outputs_of(self, self.couplings, None, x, None)
        return {c.name: torques[f"T_{c.name}"][0] for c in self.couplings}

    def node_signals(self, x: np.ndarray, accel: np.ndarray) -> dict[str, tuple[np.ndarray, str]]:
        """Angle, speed and acceleration of every node that is not a coordinate itself (geared
        to one, or condensed): ``node_row . q`` and its derivatives, one product for all."""
        n, out = self.n, {}
        idx = [k for k, nd in enumerate(self.nodes) if nd.name not in self.index]
        if not idx:
            return out
        R = self.T[idx]
        phi, omega, acc = R @ x[:n], R @ x[n:2 * n], R @ accel
        for q, k in enumerate(idx):
            nd = self.nodes[k]
            lin = "m" if nd.translation else "rad"
            out[f"{'x' if nd.translation else 'phi'}_{nd.name}"] = (phi[q], lin)
            out[f"{'v' if nd.translation else 'omega'}_{nd.name}"] = (omega[q], f"{lin}/s")
            out[f"accel_{nd.name}"] = (acc[q], f"{lin}/s^2")
        return out

    def linear_rows(self) -> dict[str, np.ndarray]:
        """Rows over the state x of the signals linear in it: every state, the angle and speed of
        every node that is not a coordinate (geared or condensed), every coupling torque.

        Here, on the network, so that the frequency domain (modes, response, campbell) reads
        them without importing the time-domain core."""
        m = self.size
        eye = np.eye(m)
        rows = {name: eye[k] for k, (name, _) in enumerate(self.state_names())}
        for name, (row, _) in self.node_signals(eye, np.zeros((self.n, m))).items():
            if not name.startswith("accel_"):
                rows[name] = np.asarray(row, dtype=float)
        for name, row in self.coupling_torques(eye).items():
            rows[f"T_{name}"] = np.asarray(row, dtype=float)
        return rows

    def outputs(self, t: np.ndarray, x: np.ndarray, accel: np.ndarray) -> dict[str, tuple[np.ndarray, str]]:
        """Every element's outputs {signal: (array over t, SI unit)}: coupling torques, strand
        forces, loads, drive torques, and the angles of the nodes that are not coordinates.
        Loads on one node are summed. Each run of elements of one kind gives its outputs at
        once (``outputs_of``: one array expression per kind over every sample)."""
        out = {}
        if self.couplings:
            out.update(Coupling.outputs_of(self, self.couplings, t, x, accel))
        for name, force in self.strand_forces(t, x).items():
            out[f"F_{name}"] = (force, "N")
        rest = [el for el in self.elements if not isinstance(el, Coupling)]
        a = 0
        while a < len(rest):
            kind = type(rest[a])
            b = a + 1
            while b < len(rest) and type(rest[b]) is kind:
                b += 1
            for name, (value, unit) in kind.outputs_of(self, rest[a:b], t, x, accel).items():
                if name in out and name.startswith("load_"):
                    value = out[name][0] + value
                out[name] = (np.array(value, dtype=float, copy=True), unit)
            a = b
        out.update(self.node_signals(x, accel))
        return out

    def energy(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Kinetic and potential energy [J] of states x (columns); couplings only (no strands)."""
        n = self.n
        phi, om = x[:n], x[n:2 * n]
        kinetic = 0.5 * np.einsum("i...,ij,j...->...", om, self.M, om)
        potential = 0.5 * np.einsum("i...,ij,j...->...", phi, self._K0, phi)
        return kinetic, potential

    def modes(self, taut: tuple[bool, ...] | None = None) -> list[tuple[float, float]]:
        """Natural frequencies [Hz] and damping ratios [-] of the linear network (motor included
        as its state; every strand taut unless ``taut`` says otherwise), from the eigenvalues
        of A, lowest frequency first; real poles are left out."""
        lam = np.linalg.eigvals(self.state_matrix(taut))
        # rigid-body modes: a double eigenvalue 0 that rounding splits to about +-sqrt(eps) |A|
        floor = 1e-7 * max(1.0, float(np.max(np.abs(lam))))
        out = []
        for s in lam:
            if s.imag > floor and abs(s) > floor:
                wn = abs(s)
                out.append((wn / (2 * math.pi), -s.real / wn))
        return sorted(out)
