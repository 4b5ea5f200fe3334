"""A drive train as a graph: inertias, spring-damper couplings with a ratio, an induction
motor, and load torques. The network assembles its matrices once (Lagrange with Rayleigh
dissipation) and gives the first-order system ``x' = A x + B u(t) + f(t, x)`` with names
and units for every state and output. SI floats only; no pint, no click.

State vector: ``x = [phi_1..phi_n, omega_1..omega_n, (M_motor)]``.

Coupling k between nodes i and j with ratio U (``j`` None: to the frame):

    potential   V = C/2 (phi_i - U phi_j)^2,   dissipation  R = d/2 (omega_i - U omega_j)^2

so its torque on i is ``-C (phi_i - U phi_j) - d (omega_i - U omega_j)`` and on j ``U`` times
the opposite (Mamatova et al. 2016, eq. 3-7, assembled instead of typed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range


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
class Inertia:
    """A rotating mass: inertia J [kg m^2] (or a translating mass [kg])."""

    name: str
    J: float


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
class Load:
    """Load torque on ``node`` against the motion [N m]:
    ``mean + amplitude sin(omega t + phase)``; with ``in_angle`` True
    ``mean + amplitude sin(phi_node + phase)`` (locked to the shaft angle: nonlinear);
    with a ``table`` of (t [s], torque [N m]) pairs, ``mean`` + the table interpolated
    linearly in time (held constant outside it). A negative load drives the node."""

    node: str
    mean: float = 0.0
    amplitude: float = 0.0
    omega: float = 0.0
    phase: float = 0.0
    in_angle: bool = False
    table: tuple[tuple[float, float], ...] = ()

    def torque(self, t, phi=0.0):
        """The load torque at time ``t`` (and shaft angle ``phi``) [N m]."""
        if self.table:
            ts, vs = zip(*self.table)
            return self.mean + np.interp(t, ts, vs)
        arg = phi if self.in_angle else self.omega * np.asarray(t)
        return self.mean + self.amplitude * np.sin(arg + self.phase)


@dataclass(frozen=True)
class Prescribed:
    """A node whose motion is imposed (an ideal speed-controlled drive): it starts at
    ``speed`` [rad/s] and accelerates at ``accel(t)`` [rad/s^2] (None: constant speed).
    Its coupling torques are what the drive must deliver (output ``T_drive_<node>``)."""

    node: str
    speed: float = 0.0
    accel: object = None  # callable t -> rad/s^2, or None


@dataclass(frozen=True)
class InductionMotor:
    r"""First-order dynamic characteristic of an induction motor on ``node``.

    .. math:: \dot M = \frac{2 M_c \omega_c}{\omega_0} (\omega_0 - \dot\varphi) - \omega_c S_c M

    breakdown_torque M_c [N m], breakdown_slip S_c [-], sync_speed omega_0 [rad/s],
    supply omega_c = 2 pi f [rad/s]. Eq. (2) of Mamatova et al. 2016 (after Pinchuk 1957):
    a lag of time constant 1/(omega_c S_c) on the linearised Kloss characteristic
    M = 2 M_c s / S_c, s = (omega_0 - omega)/omega_0.
    """

    node: str
    breakdown_torque: float
    breakdown_slip: float
    sync_speed: float
    supply: float

    def static_torque(self, speed: float) -> float:
        """The steady torque at ``speed`` [N m]: 2 M_c (omega_0 - omega) / (omega_0 S_c)."""
        return 2 * self.breakdown_torque * (self.sync_speed - speed) / (self.sync_speed * self.breakdown_slip)


@dataclass
class Network:
    """Nodes, couplings, loads and an optional motor, assembled into matrices."""

    nodes: list[Inertia]
    couplings: list[Coupling]
    loads: list[Load] = field(default_factory=list)
    motor: InductionMotor | None = None
    prescribed: list[Prescribed] = field(default_factory=list)

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
            for end in (c.i, c.j):
                if end is not None and end not in self.index:
                    raise InputError(f"coupling {c.name} names an unknown node {end!r}", param="network")
            require_range(c.name, c.C, "N*m/rad", low=0.0)
            require_range(c.name, c.d, "N*m*s/rad", low=0.0)
            require_positive(f"U_{c.name}", c.U, "")
        for ld in self.loads:
            if ld.node not in self.index:
                raise InputError(f"a load names an unknown node {ld.node!r}", param="network")
            times = [p[0] for p in ld.table]
            if any(b <= a for a, b in zip(times, times[1:])):
                raise InputError(f"the load table on node {ld.node} must have rising times", param="network")
        self.fixed = {self.index[p.node]: p for p in self.prescribed}
        if any(p.node not in self.index for p in self.prescribed) or len(self.fixed) != len(self.prescribed):
            raise InputError("prescribed motion names an unknown node, or one node twice", param="network")
        if self.motor is not None:
            m = self.motor
            if m.node not in self.index or self.index[m.node] in self.fixed:
                raise InputError(f"the motor must sit on a free node, not {m.node!r}", param="network")
            for name in ("breakdown_torque", "breakdown_slip", "sync_speed", "supply"):
                require_positive(name, getattr(m, name), "")
        self.M, self.D, self.K = self._assemble()

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
        """True when the network is linear time-invariant and every input is a constant or a
        sinusoid in time (constant-speed prescribed motion included): an exact solution exists."""
        return not (any(ld.in_angle or ld.table for ld in self.loads)
                    or any(p.accel is not None for p in self.prescribed))

    def initial_state(self) -> np.ndarray:
        """Rest, except the prescribed nodes at their initial speed."""
        x = np.zeros(self.size)
        for k, p in self.fixed.items():
            x[self.n + k] = p.speed
        return x

    def state_names(self) -> list[tuple[str, str]]:
        """(name, SI unit) of every state."""
        out = [(f"phi_{n.name}", "rad") for n in self.nodes]
        out += [(f"omega_{n.name}", "rad/s") for n in self.nodes]
        if self.motor:
            out.append(("M_motor", "N m"))
        return out

    def _assemble(self):
        n = self.n
        M = np.diag([node.J for node in self.nodes]).astype(float)
        D = np.zeros((n, n))
        K = np.zeros((n, n))
        for c in self.couplings:
            i = self.index[c.i]
            # generalised-coordinate vector of the coupling's deflection: e_i - U e_j
            g = np.zeros(n)
            g[i] = 1.0
            if c.j is not None:
                g[self.index[c.j]] -= c.U
            K += c.C * np.outer(g, g)
            D += c.d * np.outer(g, g)
        return M, D, K

    # --- first-order form -------------------------------------------------------------------
    def state_matrix(self) -> np.ndarray:
        """A of x' = A x + (inputs): mechanics, and the motor's torque state if any."""
        n, m = self.n, self.size
        Minv = 1.0 / np.diag(self.M)
        A = np.zeros((m, m))
        A[:n, n:2 * n] = np.eye(n)
        A[n:2 * n, :n] = -Minv[:, None] * self.K
        A[n:2 * n, n:2 * n] = -Minv[:, None] * self.D
        for k in self.fixed:  # imposed motion: omega' = accel(t), an input
            A[n + k, :] = 0.0
        if self.motor:
            mo = self.motor
            k = self.index[mo.node]
            A[n + k, 2 * n] = Minv[k]                      # motor torque drives its node
            A[2 * n, n + k] = -2 * mo.breakdown_torque * mo.supply / mo.sync_speed
            A[2 * n, 2 * n] = -mo.supply * mo.breakdown_slip
        return A

    def frequencies(self) -> list[float]:
        """The distinct angular frequencies of the time-sinusoidal loads [rad/s]."""
        out = []
        for ld in self.loads:
            if not ld.in_angle and ld.amplitude and ld.omega and not any(math.isclose(ld.omega, w) for w in out):
                out.append(ld.omega)
        return out

    def input_matrix(self) -> np.ndarray:
        """B of x' = A x + B g, with g = [1, sin w1 t, cos w1 t, sin w2 t, ...] (time loads only)."""
        n = self.n
        freqs = self.frequencies()
        B = np.zeros((self.size, 1 + 2 * len(freqs)))
        if self.motor:
            mo = self.motor
            B[2 * n, 0] = 2 * mo.breakdown_torque * mo.supply      # 2 M_c w_c / w_0 * w_0
        for ld in self.loads:
            if ld.in_angle or ld.table or self.index[ld.node] in self.fixed:
                continue
            row = n + self.index[ld.node]
            inv = 1.0 / self.nodes[self.index[ld.node]].J
            B[row, 0] -= ld.mean * inv
            if ld.amplitude and ld.omega:
                k = next(q for q, w in enumerate(freqs) if math.isclose(w, ld.omega))
                B[row, 1 + 2 * k] -= ld.amplitude * math.cos(ld.phase) * inv
                B[row, 2 + 2 * k] -= ld.amplitude * math.sin(ld.phase) * inv
            elif ld.amplitude:  # omega = 0: a constant amplitude * sin(phase)
                B[row, 0] -= ld.amplitude * math.sin(ld.phase) * inv
        return B

    def generators(self, t: np.ndarray | float) -> np.ndarray:
        """g(t) = [1, sin w1 t, cos w1 t, ...], shape (len(g),) or (len(g), len(t))."""
        t = np.asarray(t, dtype=float)
        rows = [np.ones_like(t)]
        for w in self.frequencies():
            rows += [np.sin(w * t), np.cos(w * t)]
        return np.array(rows)

    def nonlinear_terms(self, t: float, x: np.ndarray) -> np.ndarray:
        """x' contribution of what the exact method cannot take: loads locked to a shaft
        angle, tabulated loads, and prescribed accelerations."""
        out = np.zeros_like(x)
        for ld in self.loads:
            k = self.index[ld.node]
            if (ld.in_angle or ld.table) and k not in self.fixed:
                out[self.n + k] -= ld.torque(t, x[k]) / self.nodes[k].J
        for k, p in self.fixed.items():
            if p.accel is not None:
                out[self.n + k] = p.accel(t)
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

    def drive_torques(self, t: np.ndarray, x: np.ndarray, accel: np.ndarray) -> dict[str, np.ndarray]:
        """Torque each prescribed drive delivers [N m]: J a + (K phi + D omega) of its row + its loads."""
        n, out = self.n, {}
        loads = self.load_torques(t, x)
        for k, p in self.fixed.items():
            out[p.node] = (self.nodes[k].J * accel[n + k] + self.K[k] @ x[:n] + self.D[k] @ x[n:2 * n]
                           + loads.get(p.node, 0.0))
        return out

    def energy(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Kinetic and potential energy [J] of states x (columns)."""
        n = self.n
        phi, om = x[:n], x[n:2 * n]
        kinetic = 0.5 * np.einsum("i...,ij,j...->...", om, self.M, om)
        potential = 0.5 * np.einsum("i...,ij,j...->...", phi, self.K, phi)
        return kinetic, potential

    def modes(self) -> list[tuple[float, float]]:
        """Natural frequencies [Hz] and damping ratios [-] of the linear network (motor included
        as its state), from the eigenvalues of A, lowest frequency first; real poles are left out."""
        lam = np.linalg.eigvals(self.state_matrix())
        # rigid-body modes: a double eigenvalue 0 that rounding splits to about +-sqrt(eps) |A|
        floor = 1e-7 * max(1.0, float(np.max(np.abs(lam))))
        out = []
        for s in lam:
            if s.imag > floor and abs(s) > floor:
                wn = abs(s)
                out.append((wn / (2 * math.pi), -s.real / wn))
        return sorted(out)
