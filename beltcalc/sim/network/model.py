"""The :class:`Network`: nodes and elements assembled into the first-order system
``x' = A x + B g(t) + f(t, x)``, with names and units for every state and output (the
package's docstring, :mod:`beltcalc.sim.network`, gives the model). SI floats only.

References:

[Guy65] R. J. Guyan, "Reduction of stiffness and mass matrices", AIAA Journal 3 (1965) 380.
"""

from __future__ import annotations

import math

import numpy as np

from beltcalc.errors import InputError, did_you_mean, require_positive
from beltcalc.sim.elements import (Coupling, Element, Gear, Inertia, InductionMotor, Load, Points, Prescribed,
                                   Strand, piece)
from beltcalc.sim.elements.switched import SpeedLoop
from beltcalc.sim.network.assembly import Piece, add_outer, require_finite, require_finite_elements
from beltcalc.sim.network.coordinates import check_condensation, coordinates
from beltcalc.sim.network.strands import StrandModes
from beltcalc.sim.network.switched import SwitchedModes


class Network(StrandModes, SwitchedModes):
    """Nodes and elements, assembled into the matrices of the first-order system.

    ``nodes``: the :class:`Inertia` of every node; ``elements``: one list of every other
    element, of any kind (:class:`~beltcalc.sim.elements.Element`). The network sorts them by
    what they do: rigid :class:`Gear` pairs merge nodes into coordinates, tension-only
    :class:`Strand` s are switched by the core (``strands``), and every other element stamps
    itself (``elements``, kind by kind in the order of their ``ORDER``, as listed within a
    kind): the network only calls the hooks every kind has. ``couplings``, ``loads``,
    ``motors``, ``prescribed`` and ``speed_loops`` list the stamping elements of those kinds.

    Generalised coordinates: every rigid gear group (nodes joined by :class:`Gear`) is one
    coordinate, the angle of its first node; a node's angle is ``node_row(name) . q``.
    A group without inertia (massless nodes between springs) is condensed out exactly:
    its angle follows the springs' static balance, ``q_m = -K_mm^-1 K_mr q_r`` (Guyan's
    reduction [Guy65], exact without inertia), provided its dampers are proportional to its
    springs (else a first-order element would be left). Loads, drives and strands must sit on nodes
    with inertia.

    >>> net = Network([Inertia("a", 1.0), Inertia("b", 2.0)], [Load("b", 1.0), Coupling("c", "a", "b", 8.0, 0.0)])
    >>> [type(el).__name__ for el in net.elements], net.coords
    (['Coupling', 'Load'], ['a', 'b'])
    """

    def __init__(self, nodes: list[Inertia], elements: list[Element] = ()):
        self.nodes = list(nodes)
        given = list(elements)
        for el in given:
            if not isinstance(el, Element) or isinstance(el, Inertia):
                what = "a node: nodes go in the first list" if isinstance(el, Inertia) else "not an element"
                raise InputError(f"{type(el).__name__} {getattr(el, 'name', '')!r} among the elements is {what}",
                                 param="network")
        require_finite_elements([*self.nodes, *given])
        self.gears = [el for el in given if isinstance(el, Gear)]
        self.strands = [el for el in given if isinstance(el, Strand)]
        # every element that stamps itself, kind by kind (stable: as given within a kind)
        self.elements = sorted((el for el in given if not isinstance(el, (Gear, Strand))), key=lambda el: el.ORDER)
        #: the elements with modes of their own (friction, torque limits): the mode's tail
        self.switched = [el for el in self.elements if el.switched]
        names = [n.name for n in self.nodes]
        if len(set(names)) != len(names):
            raise InputError(f"node names repeat: {names}", param="network")
        self._node = {n.name: n for n in self.nodes}
        self._row_of = {n.name: k for k, n in enumerate(self.nodes)}
        for nd in self.nodes:
            if nd.J != 0:
                require_positive(f"J_{nd.name}", nd.J, "kg*m^2")
        motor_names = [m.name for m in self.motors]
        if len(set(motor_names)) != len(motor_names):
            raise InputError(f"several motors named {motor_names}: give each motor a name of its own",
                             param="network")
        self._coords = coordinates(self.nodes, self.gears, self.couplings)
        self.coords, self.mass, self.T = self._coords.coords, self._coords.mass, self._coords.T
        self.index = {name: c for c, name in enumerate(self.coords)}
        self._massless = self._coords.massless
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
        check_condensation(self._coords, self.elements)
        self._K0, self._D0 = self._assemble()
        self._G = np.array([s.geometry(self) for s in self.strands]).reshape(len(self.strands), self.n)
        self._cache: dict = {}
        #: the smooth piece each element with pieces (``pieces`` True: a polygon strand's seated
        #: rollers and slack state) is held on while a solver with events integrates it; empty:
        #: each finds its own at every state
        self.pieces: dict = {}
        self.piecewise = [el for el in self.elements if getattr(el, "pieces", False)]
        self._rows = None
        self._stamps = None
        self._joints: dict = {}
        self.taut = self.full_pattern(tuple(s.default_taut for s in self.strands))
        self.check_parallel_joints()
        self.K, self.D = self.stiffness_damping(self.taut)

    # --- the stamping elements by kind -------------------------------------------------------
    @property
    def couplings(self) -> list[Coupling]:
        """The spring-damper couplings, in stamp order."""
        return [el for el in self.elements if isinstance(el, Coupling)]

    @property
    def loads(self) -> list[Load]:
        """The loads, in stamp order."""
        return [el for el in self.elements if isinstance(el, Load)]

    @property
    def motors(self) -> list[InductionMotor]:
        """The induction motors, in stamp order."""
        return [el for el in self.elements if isinstance(el, InductionMotor)]

    @property
    def prescribed(self) -> list[Prescribed]:
        """The prescribed motions, in stamp order."""
        return [el for el in self.elements if isinstance(el, Prescribed)]

    @property
    def speed_loops(self) -> list[SpeedLoop]:
        """The speed loops, in stamp order."""
        return [el for el in self.elements if isinstance(el, SpeedLoop)]

    # --- nodes and coordinates ----------------------------------------------------------------
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
    def tension_strands(self) -> list:
        """Every strand a report shows with its force ``F_<name>``: the switched strands, then
        the elements that are tension-only strands of their own (``tension_only``: a polygon
        strand)."""
        return list(self.strands) + [el for el in self.elements if getattr(el, "tension_only", False)]

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
                add_outer(K, self._G[k], s.stiffness)
                add_outer(D, self._G[k], s.damping)
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
        taut = self.taut if taut is None else self.full_pattern(taut)
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
        ns = len(self.strands)
        for el, state in zip(self.switched, taut[ns:]):
            el.stamp(p, state)
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
        if self.switched:
            joints = self.impose_joints(A, B, taut, constrained, t_mid)
            if constrained:
                self._joints[(taut, tuple(self._pieces(t_mid)))] = joints
                if len(self._joints) > 256:
                    self._joints.pop(next(iter(self._joints)))
            AB = np.hstack([A, B])
            for el, state in zip(self.switched, taut[ns:]):
                el.settle(p, state, AB)
        require_finite(A, B, net=self)
        return A, B

    def state_matrix(self, taut: tuple[bool, ...] | None = None) -> np.ndarray:
        """A of x' = A x + (inputs), with every strand taut unless ``taut`` says otherwise."""
        return self.first_order(taut)[0]

    def input_matrix(self, taut: tuple[bool, ...] | None = None, t_mid: float = 0.0) -> np.ndarray:
        """B of x' = A x + B g on the time piece holding ``t_mid``."""
        return self.first_order(taut, t_mid)[1]

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
        if self.switched:
            # each sample in its own mode (the run's where seeded): a few modes per run
            out = np.empty_like(X)
            for pattern, t_mid, cols in self.sample_groups(t, X, np.vstack([X, G])):
                A, B = self.first_order(pattern, t_mid, constrained)
                out[:, cols] = A @ X[:, cols] + B @ G[:, cols]
            if not self.linear:
                out += self.nonlinear_terms(T, X, constrained)
            return out[:, 0] if single else out
        out = self._linear_part(T, X, G, constrained)
        if self.strands:
            self._add_strands(out, X, G, constrained)
        if not self.linear:
            out += self.nonlinear_terms(T, X, constrained)
        return out[:, 0] if single else out

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
