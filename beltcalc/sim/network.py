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

from beltcalc.errors import InputError, require_positive, require_range

Points = tuple[tuple[float, float], ...]


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


# --- piecewise-linear functions of time --------------------------------------------------------
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


def _piece(points: Points, t_mid: float) -> tuple[float, float]:
    """(a, c) with value = a + c t on the piece that holds ``t_mid`` (not a break point)."""
    ts = [p[0] for p in points]
    k = int(np.searchsorted(ts, t_mid, side="right")) - 1
    if k < 0:
        return points[0][1], 0.0
    if k >= len(points) - 1:
        return points[-1][1], 0.0
    (t0, v0), (t1, v1) = points[k], points[k + 1]
    c = (v1 - v0) / (t1 - t0)
    return v0 - c * t0, c


# --- elements ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Inertia:
    """A rotating mass: inertia J [kg m^2]; with ``translation`` a sliding mass [kg]."""

    name: str
    J: float
    translation: bool = False


@dataclass(frozen=True)
class Coupling:
    """Spring-damper C [N m/rad], d [N m s/rad] from node ``i`` to ``U`` x node ``j``."""

    name: str
    i: str
    j: str | None
    C: float
    d: float
    U: float = 1.0


@dataclass(frozen=True)
class Strand:
    """A tension-only strand (chain, belt span) from node ``i`` to node ``j`` (None: the frame).

    stiffness c [N/m], damping b [N s/m], radii r_i, r_j [m] where it leaves the nodes
    (1 for a translating node), pretension F_0 [N]. Elongation
    ``delta = r_i phi_i - r_j phi_j + F_0 / c``; force ``c delta + b delta'`` while taut.
    """

    name: str
    i: str
    j: str | None
    r_i: float
    r_j: float
    stiffness: float
    damping: float
    preload: float = 0.0


@dataclass(frozen=True)
class Load:
    """Load torque on ``node`` against the motion [N m]:
    ``mean + amplitude sin(omega t + phase) + table(t)``; with ``in_angle`` True the sine is
    ``amplitude sin(phi_node + phase)`` (locked to the shaft angle: nonlinear). ``table``:
    (t [s], torque [N m]) points, linear in between, a repeated time is a jump, held
    constant outside. The sine acts from ``start`` [s] on. A negative load drives the node."""

    node: str
    mean: float = 0.0
    amplitude: float = 0.0
    omega: float = 0.0
    phase: float = 0.0
    in_angle: bool = False
    table: Points = ()
    start: float = 0.0

    def torque(self, t, phi=0.0):
        """The load torque at time ``t`` (and shaft angle ``phi``) [N m]."""
        arg = phi if self.in_angle else self.omega * np.asarray(t)
        out = self.mean + self.amplitude * np.sin(arg + self.phase) * (np.asarray(t) >= self.start)
        if self.table:
            out = out + piecewise(self.table, t)
        return out


@dataclass(frozen=True)
class Prescribed:
    """A node whose motion is imposed (an ideal speed-controlled drive): it starts at
    ``speed`` [rad/s] and accelerates at ``accel``, a piecewise-linear table of
    (t [s], accel [rad/s^2]) points (empty: constant speed). Its coupling torques are what
    the drive must deliver (output ``T_drive_<node>``)."""

    node: str
    speed: float = 0.0
    accel: Points = ()


@dataclass(frozen=True)
class SpeedLoop:
    """A drive on ``node`` with feed-forward and a proportional speed loop:
    ``T = feedforward(t) + gain (reference(t) - omega)``, both tables piecewise linear
    (t [s], N m) and (t [s], rad/s); gain [N m s/rad]. Output ``T_drive_<node>``."""

    node: str
    gain: float
    reference: Points
    feedforward: Points = ()


@dataclass(frozen=True)
class InductionMotor:
    r"""First-order dynamic characteristic of an induction motor on ``node``.

    .. math:: \dot M = \frac{2 M_c \omega_c}{\omega_0} (\omega_0 - \dot\varphi) - \omega_c S_c M

    breakdown_torque M_c [N m], breakdown_slip S_c [-], sync_speed omega_0 [rad/s],
    supply omega_c = 2 pi f [rad/s]. Eq. (2) of Mamatova et al. 2016 (after Pinchuk 1957):
    a lag of time constant 1/(omega_c S_c) on the linearised Kloss characteristic
    M = 2 M_c s / S_c, s = (omega_0 - omega)/omega_0.

    ``sync_table`` (t [s], rad/s): an inverter start. The synchronous speed follows the
    table while the characteristic keeps its slope 2 M_c / (S_c omega_0) (V/f control holds
    the slip speed at breakdown), so the motor stays on the linear part of its curve; a
    direct-on-line start from rest is far outside it (the line gives 2 M_c / S_c at s = 1).
    """

    node: str
    breakdown_torque: float
    breakdown_slip: float
    sync_speed: float
    supply: float
    sync_table: Points = ()

    def static_torque(self, speed: float) -> float:
        """The steady torque at ``speed`` [N m]: 2 M_c (omega_0 - omega) / (omega_0 S_c)."""
        return 2 * self.breakdown_torque * (self.sync_speed - speed) / (self.sync_speed * self.breakdown_slip)


@dataclass(frozen=True)
class Event:
    """A switching surface of the current mode: ``row @ z`` (z = [x, g]) crossing zero in
    ``direction`` (+1 rising, -1 falling) may switch strand ``strand``."""

    strand: int
    kind: str       # "delta" (elongation) or "force"
    direction: int
    row: np.ndarray


@dataclass
class Network:
    """Nodes, couplings, strands, loads and drives, assembled into matrices."""

    nodes: list[Inertia]
    couplings: list[Coupling]
    loads: list[Load] = field(default_factory=list)
    motor: InductionMotor | None = None
    prescribed: list[Prescribed] = field(default_factory=list)
    strands: list[Strand] = field(default_factory=list)
    speed_loops: list[SpeedLoop] = field(default_factory=list)

    def __post_init__(self):
        names = [n.name for n in self.nodes]
        if len(set(names)) != len(names):
            raise InputError(f"node names repeat: {names}", param="network")
        self.index = {name: k for k, name in enumerate(names)}
        for n in self.nodes:
            if n.J == 0:
                raise InputError(
                    f"node {n.name} has no inertia: a massless node makes the equations algebraic and "
                    "cannot be simulated as it is; join its two springs into one, C = C1 C2 / (C1 + C2) "
                    "(series stiffness; see series_stiffness), or give it the inertia of its parts",
                    param=f"J_{n.name}")
            require_positive(f"J_{n.name}", n.J, "kg*m^2")
        for c in self.couplings:
            self._check_ends(c.name, c.i, c.j)
            require_range(c.name, c.C, "N*m/rad", low=0.0)
            require_range(c.name, c.d, "N*m*s/rad", low=0.0)
            require_positive(f"U_{c.name}", c.U, "")
        for s in self.strands:
            self._check_ends(s.name, s.i, s.j)
            require_positive(f"{s.name} stiffness", s.stiffness, "N/m")
            require_range(f"{s.name} damping", s.damping, "N*s/m", low=0.0)
            require_range(f"{s.name} preload", s.preload, "N", low=0.0)
            require_positive(f"{s.name} r_i", s.r_i, "m")
            if s.j is not None:
                require_positive(f"{s.name} r_j", s.r_j, "m")
        for ld in self.loads:
            if ld.node not in self.index:
                raise InputError(f"a load names an unknown node {ld.node!r}", param="network")
            check_points(ld.table, f"load on node {ld.node}")
        self.fixed = {self.index[p.node]: p for p in self.prescribed}
        if any(p.node not in self.index for p in self.prescribed) or len(self.fixed) != len(self.prescribed):
            raise InputError("prescribed motion names an unknown node, or one node twice", param="network")
        for p in self.prescribed:
            check_points(p.accel, f"acceleration of node {p.node}")
        self.looped = {}
        for s in self.speed_loops:
            k = self.index.get(s.node)
            if k is None or k in self.fixed or k in self.looped:
                raise InputError(f"a speed loop must sit on a free node of its own, not {s.node!r}",
                                 param="network")
            require_range(f"{s.node} speed-loop gain", s.gain, "N*m*s/rad", low=0.0)
            check_points(s.reference, f"speed reference of node {s.node}")
            check_points(s.feedforward, f"feed-forward of node {s.node}")
            self.looped[k] = s
        if self.motor is not None:
            m = self.motor
            if m.node not in self.index or self.index[m.node] in self.fixed:
                raise InputError(f"the motor must sit on a free node, not {m.node!r}", param="network")
            for name in ("breakdown_torque", "breakdown_slip", "sync_speed", "supply"):
                require_positive(name, getattr(m, name), "")
            check_points(m.sync_table, "synchronous speed")
        n = self.n
        self.M = np.diag([node.J for node in self.nodes]).astype(float)
        self._K0, self._D0 = self._assemble_couplings()
        # strand geometry: delta = G[s] . phi + F0/c
        self._G = np.zeros((len(self.strands), n))
        for k, s in enumerate(self.strands):
            self._G[k, self.index[s.i]] += s.r_i
            if s.j is not None:
                self._G[k, self.index[s.j]] -= s.r_j
        self._cache: dict = {}
        self._rows = None
        self._stamps = None
        self.taut = tuple(True for _ in self.strands)
        self.K, self.D = self.stiffness_damping(self.taut)

    def _check_ends(self, name, i, j):
        for end in (i, j):
            if end is not None and end not in self.index:
                raise InputError(f"element {name} names an unknown node {end!r}", param="network")

    # --- structure ------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.nodes)

    @property
    def size(self) -> int:
        """Number of states."""
        return 2 * self.n + (1 if self.motor else 0)

    @property
    def linear(self) -> bool:
        """True when the network is linear between switches (strands) and time break points
        (tables): every load is constant, sinusoidal or tabulated in time, so an exact
        solution exists. Loads locked to a shaft angle make it nonlinear."""
        return not any(ld.in_angle for ld in self.loads)

    @property
    def ramp(self) -> bool:
        """True when a piecewise-linear input needs the generator ``t``."""
        return (any(ld.table or (ld.start and ld.amplitude) for ld in self.loads) or any(p.accel for p in self.prescribed)
                or bool(self.speed_loops) or bool(self.motor and self.motor.sync_table))

    @property
    def smooth(self) -> bool:
        """No strands and no time break points: one linear system over the whole run."""
        return not self.strands and not self.ramp

    def breaks(self, t_end: float) -> list[float]:
        """The times in (0, t_end) where a piecewise-linear input changes its piece."""
        times = set()
        for table in self._tables():
            times.update(p[0] for p in table)
        times.update(ld.start for ld in self.loads if ld.amplitude)
        return sorted(t for t in times if 0.0 < t < t_end)

    def initial_state(self) -> np.ndarray:
        """Rest, except the prescribed nodes at their initial speed."""
        x = np.zeros(self.size)
        for k, p in self.fixed.items():
            x[self.n + k] = p.speed
        return x

    def state_names(self) -> list[tuple[str, str]]:
        """(name, SI unit) of every state."""
        out = [(f"x_{n.name}", "m") if n.translation else (f"phi_{n.name}", "rad") for n in self.nodes]
        out += [(f"v_{n.name}", "m/s") if n.translation else (f"omega_{n.name}", "rad/s") for n in self.nodes]
        if self.motor:
            out.append(("M_motor", "N m"))
        return out

    def accel_names(self) -> list[tuple[str, str]]:
        """(name, SI unit) of every node's acceleration."""
        return [(f"accel_{n.name}", "m/s^2" if n.translation else "rad/s^2") for n in self.nodes]

    def _assemble_couplings(self):
        n = self.n
        K = np.zeros((n, n))
        D = np.zeros((n, n))
        for c in self.couplings:
            # generalised-coordinate vector of the coupling's deflection: e_i - U e_j
            g = np.zeros(n)
            g[self.index[c.i]] = 1.0
            if c.j is not None:
                g[self.index[c.j]] -= c.U
            K += c.C * np.outer(g, g)
            D += c.d * np.outer(g, g)
        for k, s in self.looped.items():
            D[k, k] += s.gain
        return K, D

    def stiffness_damping(self, taut: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray]:
        """K and D with the strands that are ``taut``."""
        K, D = self._K0.copy(), self._D0.copy()
        for k, (s, on) in enumerate(zip(self.strands, taut)):
            if on:
                K += s.stiffness * np.outer(self._G[k], self._G[k])
                D += s.damping * np.outer(self._G[k], self._G[k])
        return K, D

    # --- first-order form -------------------------------------------------------------------
    def frequencies(self) -> list[float]:
        """The distinct angular frequencies of the time-sinusoidal loads [rad/s]."""
        out = []
        for ld in self.loads:
            if not ld.in_angle and ld.amplitude and ld.omega and not any(math.isclose(ld.omega, w) for w in out):
                out.append(ld.omega)
        return out

    def generators(self, t: np.ndarray | float) -> np.ndarray:
        """g(t) = [1, (t), sin w1 t, cos w1 t, ...], shape (len(g),) or (len(g), len(t))."""
        t = np.asarray(t, dtype=float)
        rows = [np.ones_like(t)]
        if self.ramp:
            rows.append(t.copy())
        for w in self.frequencies():
            rows += [np.sin(w * t), np.cos(w * t)]
        return np.array(rows)

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
        tables = [ld.table for ld in self.loads] + [p.accel for p in self.prescribed]
        tables += [s.reference for s in self.speed_loops] + [s.feedforward for s in self.speed_loops]
        return tables + [self.motor.sync_table] if self.motor else tables

    def _pieces(self, t_mid):
        """The active piece of every table (a cache key)."""
        for table in self._tables():
            yield _piece(table, t_mid) if table else (0.0, 0.0)
        yield tuple(t_mid >= ld.start for ld in self.loads)

    def _build(self, taut, t_mid, constrained):
        n, m = self.n, self.size
        K, D = self.stiffness_damping(taut)
        Minv = 1.0 / np.diag(self.M)
        A = np.zeros((m, m))
        A[:n, n:2 * n] = np.eye(n)
        A[n:2 * n, :n] = -Minv[:, None] * K
        A[n:2 * n, n:2 * n] = -Minv[:, None] * D
        B = np.zeros((m, 1 + int(self.ramp) + 2 * len(self.frequencies())))
        ramp = 1 if self.ramp else None
        freqs = self.frequencies()
        first = 1 + int(self.ramp)

        def torque(k, a, c=0.0):          # a + c t [N m] acting on node k
            B[n + k, 0] += a * Minv[k]
            if c:
                B[n + k, ramp] += c * Minv[k]

        if self.motor:
            mo = self.motor
            k = self.index[mo.node]
            A[n + k, 2 * n] = Minv[k]                      # motor torque drives its node
            A[2 * n, n + k] = -2 * mo.breakdown_torque * mo.supply / mo.sync_speed
            A[2 * n, 2 * n] = -mo.supply * mo.breakdown_slip
            gain = 2 * mo.breakdown_torque * mo.supply / mo.sync_speed
            if mo.sync_table:                              # 2 M_c w_c / w_0 * w_0(t)
                a, c = _piece(mo.sync_table, t_mid)
                B[2 * n, 0] = gain * a
                B[2 * n, ramp] = gain * c
            else:
                B[2 * n, 0] = gain * mo.sync_speed
        for s, on, g in zip(self.strands, taut, self._G):
            if on and s.preload:                           # the pretension: -G^T F0
                for k in np.nonzero(g)[0]:
                    torque(k, -g[k] * s.preload)
        for ld in self.loads:
            k = self.index[ld.node]
            torque(k, -ld.mean)
            if ld.table:
                a, c = _piece(ld.table, t_mid)
                torque(k, -a, -c)
            if ld.in_angle or not ld.amplitude or t_mid < ld.start:
                continue
            if ld.omega:
                q = first + 2 * next(i for i, w in enumerate(freqs) if math.isclose(w, ld.omega))
                B[n + k, q] -= ld.amplitude * math.cos(ld.phase) * Minv[k]
                B[n + k, q + 1] -= ld.amplitude * math.sin(ld.phase) * Minv[k]
            else:  # omega = 0: a constant amplitude * sin(phase)
                torque(k, -ld.amplitude * math.sin(ld.phase))
        for k, s in self.looped.items():                    # feed-forward + gain * reference
            a, c = _piece(s.feedforward, t_mid) if s.feedforward else (0.0, 0.0)
            ra, rc = _piece(s.reference, t_mid)
            torque(k, a + s.gain * ra, c + s.gain * rc)
        if constrained:
            for k, p in self.fixed.items():  # imposed motion: omega' = accel(t), an input
                A[n + k, :] = 0.0
                B[n + k, :] = 0.0
                if p.accel:
                    a, c = _piece(p.accel, t_mid)
                    B[n + k, 0] = a
                    if c:
                        B[n + k, ramp] = c
        return A, B

    def strand_stamps(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What each strand adds to ``[A | B]`` when taut, as sparse entries ``(owner, row,
        col, value)`` over ``z = [x, g]`` (column ``size`` is the constant generator): its
        stiffness and damping on the two nodes' accelerations (``-M^-1 c g g^T`` and
        ``-M^-1 b g g^T``) and its pretension (``-M^-1 g F0``). Rows of prescribed nodes are
        left out, as :meth:`first_order` zeroes them. With these, ``[A | B]`` of any strand
        pattern is the all-slack one plus the stamps of its taut strands: O(strands) work
        per pattern instead of a dense rebuild."""
        n, m = self.n, self.size
        Minv = 1.0 / np.diag(self.M)
        owner, rows, cols, vals = [], [], [], []
        for k, (s, g) in enumerate(zip(self.strands, self._G)):
            nz = np.nonzero(g)[0]
            for a in nz:
                if a in self.fixed:
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
        return (np.array(owner, dtype=np.int64), np.array(rows, dtype=np.int64),
                np.array(cols, dtype=np.int64), np.array(vals, dtype=float))

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
        z = np.vstack([x, self.generators(t)])
        delta, force = self.strand_rows()
        f = force @ z
        on = (delta @ z > 0) & (f > 0)
        return {s.name: np.where(on[k], f[k], 0.0) for k, s in enumerate(self.strands)}

    # --- right-hand side --------------------------------------------------------------------
    def derivative(self, t, x: np.ndarray, constrained: bool = True) -> np.ndarray:
        """x' at states ``x`` (columns) and times ``t``, each strand taut or slack by its own
        state (the raw, discontinuous right-hand side)."""
        x = np.asarray(x, dtype=float)
        single = x.ndim == 1
        X = x[:, None] if single else x
        T = np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],))
        t_end = float(T.max())
        starts = self.segment_starts(t_end)
        seg = np.searchsorted(starts, T, side="right") - 1
        taut = self.taut_of(X, T) if self.strands else np.ones((0, X.shape[1]), bool)
        G = self.generators(T)
        out = np.empty_like(X)
        if self.strands and (constrained or not self.fixed):
            # strand-affine: the all-slack matrices per time piece, plus every taut strand's
            # stamp (strand_stamps) sample by sample; no dense matrix per strand pattern (a
            # long chain has nearly one pattern per sample)
            none = tuple(False for _ in self.strands)
            for sg in np.unique(seg):
                cols = seg == sg
                A, B = self.first_order(none, self.piece_time(int(sg), starts, t_end), constrained)
                out[:, cols] = A @ X[:, cols] + B @ G[:, cols]
            if self._stamps is None:
                self._stamps = self.strand_stamps()
            owner, rows, where, vals = self._stamps
            Z = np.vstack([X, G])
            for a in range(0, X.shape[1], 512):
                b = min(a + 512, X.shape[1])
                part = np.zeros((self.size, b - a))
                np.add.at(part, rows, vals[:, None] * Z[where, a:b] * taut[owner, a:b])
                out[:, a:b] += part
        else:
            keys = np.concatenate([taut, seg[None, :]]).T
            uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
            for q, key in enumerate(uniq):
                cols = inverse.ravel() == q
                A, B = self.first_order(tuple(bool(v) for v in key[:-1]),
                                        self.piece_time(int(key[-1]), starts, t_end), constrained)
                out[:, cols] = A @ X[:, cols] + B @ G[:, cols]
        if not self.linear:
            out += self.nonlinear_terms(T, X, constrained)
        return out[:, 0] if single else out

    def nonlinear_terms(self, t, x: np.ndarray, constrained: bool = True) -> np.ndarray:
        """x' contribution of what the linear form cannot take: loads locked to a shaft angle."""
        out = np.zeros_like(x, dtype=float)
        for ld in self.loads:
            k = self.index[ld.node]
            if ld.in_angle and not (constrained and k in self.fixed):
                out[self.n + k] -= ld.amplitude * np.sin(x[k] + ld.phase) * (np.asarray(t) >= ld.start) / self.nodes[k].J
        return out

    def nonlinear_jacobian(self, x: np.ndarray) -> np.ndarray:
        """d(nonlinear_terms)/dx: only the angle-locked loads depend on the state."""
        jac = np.zeros((self.size, self.size))
        for ld in self.loads:
            if ld.in_angle and self.index[ld.node] not in self.fixed:
                k = self.index[ld.node]
                jac[self.n + k, k] -= ld.amplitude * np.cos(x[k] + ld.phase) / self.nodes[k].J
        return jac

    # --- outputs ----------------------------------------------------------------------------
    def coupling_torques(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """Torque transmitted by each coupling [N m]: C (phi_i - U phi_j) + d (omega_i - U omega_j)."""
        n, out = self.n, {}
        for c in self.couplings:
            i = self.index[c.i]
            defl, rate = x[i], x[n + i]
            if c.j is not None:
                j = self.index[c.j]
                defl, rate = defl - c.U * x[j], rate - c.U * x[n + j]
            out[c.name] = c.C * defl + c.d * rate
        return out

    def load_torques(self, t: np.ndarray, x: np.ndarray) -> dict[str, np.ndarray]:
        """Load torque on each loaded node [N m] (summed per node)."""
        out: dict[str, np.ndarray] = {}
        for ld in self.loads:
            out[ld.node] = out.get(ld.node, 0.0) + ld.torque(t, x[self.index[ld.node]])
        return out

    def drive_torques(self, t: np.ndarray, x: np.ndarray, dx: np.ndarray) -> dict[str, np.ndarray]:
        """Torque each prescribed drive or speed loop delivers [N m].

        A prescribed node: J (its imposed acceleration - the acceleration the other forces
        alone would give it). A speed loop: feed-forward + gain (reference - omega)."""
        n, out = self.n, {}
        if self.fixed:
            free = self.derivative(t, x, constrained=False)
            for k, p in self.fixed.items():
                out[p.node] = self.nodes[k].J * (dx[n + k] - free[n + k])
        for k, s in self.looped.items():
            ff = piecewise(s.feedforward, t) if s.feedforward else 0.0
            out[s.node] = ff + s.gain * (piecewise(s.reference, t) - x[n + k])
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
