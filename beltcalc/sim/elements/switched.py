"""Elements with modes of their own, exact between their switches: friction that sticks (a
clutch between two nodes, a brake or a bearing's friction to the frame) and the torque
limit of a speed loop. Each is piecewise linear: a slipping clutch's torque is a function
of time alone, a stuck one is a rigid joint, a saturated drive's torque is a constant. The
switching core propagates each mode exactly and locates every switch on the exact solution,
as it does a strand's (:mod:`beltcalc.sim.switching`); the network assembles a mode's
matrices (:mod:`beltcalc.sim.network.switched`).

A switched element declares its states (``STATES``) and, for each, the *conditions* that
hold while it is in it: rows over ``z = [x, g]`` that stay ``>= 0`` (:meth:`Switched.conditions`).
A condition that falls through zero is a switch; at a switch the next state is the one
whose conditions hold just after it, tried together with the other elements on a surface
(:meth:`beltcalc.sim.network.switched.SwitchedModes.decide_switched`). A stuck clutch is
the Filippov sliding mode of the friction law [F88 sec. 2.4]: the constraint torque that
keeps the relative speed zero, linear in state and inputs, with stuck kept while it stays
within the static limit, as in the friction element of the Modelica library [OEM99 sec. 4].

SI floats only.

References:

[OEM99] M. Otter, H. Elmqvist, S. E. Mattsson, "Hybrid modeling in Modelica based on the
    synchronous data flow principle", Proc. IEEE CACSD (1999) 151-157: the friction
    element's modes (forward and backward sliding, stuck) and the conditions between them.
[F88] A. F. Filippov, Differential Equations with Discontinuous Righthand Sides, Kluwer
    (1988): the motion on a discontinuity surface (sliding), the convex combination of the
    two sides that keeps the state on it.
[AM08] K. J. Astrom, R. M. Murray, Feedback Systems, Princeton University Press (2008): the
    PI controller and integrator windup, anti-windup by holding the integrator
    [AM08 sec. 10.4].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from beltcalc.errors import InputError, require_range
from beltcalc.sim.elements import Element, Points, check_points, piece, piecewise


class Switched(Element):
    """Base of an element with discrete states (``STATES``, their names; ints index them).

    Hooks (beside :class:`~beltcalc.sim.elements.Element`'s): :meth:`candidates` (the states
    it may take on a time piece, most preferred first), :meth:`stamp` (its terms of ``[A | B]``
    in a state, before any stuck joint is imposed), :meth:`joint` (the row g over the
    coordinates it holds at zero relative speed in a state, or None), :meth:`settle` (terms
    that read the mode's accelerations, after the joints), :meth:`conditions`,
    :meth:`state_of` (the state a bare state vector suggests, for a caller without the
    run's mode history), ``default`` (the state the frequency domain takes)."""

    STATES: ClassVar[tuple[str, ...]] = ()
    switched: ClassVar[bool] = True

    def candidates(self, t_mid: float) -> tuple[int, ...]:
        return tuple(range(len(self.STATES)))

    def stamp(self, p, state: int) -> None:
        """Its terms of ``[A | B]`` in ``state`` on the piece ``p``."""

    def joint(self, net, state: int) -> np.ndarray | None:
        return None

    def settle(self, p, state: int, AB: np.ndarray) -> None:
        """Terms written after the joints are imposed (``AB``: the mode's ``[A | B]``)."""

    def conditions(self, ctx, state: int) -> list[tuple[np.ndarray, bool]]:
        """(row over z, is a switch) pairs that stay >= 0 in ``state``; a row that is no
        switch only says whether the state may be entered (a stuck clutch's zero speed)."""
        return []

    def state_of(self, net, t, X) -> np.ndarray:
        return np.zeros(np.shape(t), dtype=np.int64)

    def slip_sign(self, state: int) -> int:
        """+1 slipping forward, -1 backward, 0 otherwise: a friction element's torque sign
        while it turns work into heat (the run's slip heat); 0 for other kinds."""
        return 0

    @property
    def default(self) -> int:
        return 0


# --- friction: clutch, brake, bearing -----------------------------------------------------------
@dataclass(frozen=True)
class Friction(Switched):
    """Dry friction between node ``i`` and ``U`` x node ``j`` (``j`` None: the frame): a clutch,
    a torque limiter, a brake, a bearing's friction [OEM99 sec. 4].

    ``capacity``: the slipping (kinetic) torque T_c(t) [N m, or N between translating nodes]
    as a piecewise-linear table of (t [s], torque) points (a clutch's mu F_n(t) r_eff z, a
    limiter's set torque); ``static``: the static limit over it, T_s = static T_c (>= 1);
    ``viscous`` [N m s/rad]: a damper on the same relative speed (a bearing's viscous part);
    ``one_way``: a freewheel, which carries torque only from i to j (it overruns when j turns
    faster).

    Relative angle ``phi_rel = phi_i - U phi_j``, relative speed ``w = phi_rel'``; the torque
    T the element carries acts on i as -T and on j as U T, like a coupling's:

    * slipping forward (w > 0): T = T_c(t); backward (w < 0): T = -T_c(t);
    * stuck (w = 0): T is the torque that keeps w at zero (the joint's constraint torque,
      linear in state and inputs), while -T_s <= T <= T_s (0 <= T <= T_s one way);
    * free: T = 0 (no normal force on the piece, or a freewheel overrunning, w < 0).

    Outputs ``T_<name>`` [N m], ``w_<name>`` (relative speed) and ``mode_<name>`` (the state's
    index in ``STATES``)."""

    name: str
    i: str
    j: str | None
    capacity: Points
    static: float = 1.0
    viscous: float = 0.0
    U: float = 1.0
    one_way: bool = False

    STATES: ClassVar[tuple[str, ...]] = ("free", "stuck", "forward", "backward")
    FREE, STUCK, FORWARD, BACKWARD = 0, 1, 2, 3
    UNITS: ClassVar[dict] = {"static": "", "viscous": None, "U": ""}

    def check(self, net) -> None:
        net.check_ends(self.name, self.i, self.j)
        for end in (self.i, self.j):
            if end is not None:
                net.require_inertia(end, f"friction {self.name}")
        if not self.capacity:
            raise InputError(f"friction {self.name} needs its torque: give a capacity table", param="network")
        check_points(self.capacity, f"capacity of {self.name}")
        if any(v < 0 for _, v in self.capacity):
            raise InputError(f"friction {self.name}: a torque capacity below 0 is not allowed", param="network")
        if not (math.isfinite(self.static) and self.static >= 1.0):
            raise InputError(f"{self.static:g} is not allowed; the static limit is a factor >= 1 on the slipping "
                             "torque", param=f"{self.name} static")
        require_range(f"{self.name} viscous", self.viscous, "N*m*s/rad", low=0.0)
        if not (math.isfinite(self.U) and self.U != 0):
            raise InputError(f"{self.U:g} is not allowed; the ratio must be finite and not 0", param=f"{self.name} U")
        if not self.row(net).any():
            raise InputError(f"friction {self.name} joins {self.i} to nodes geared rigidly to it: it can never "
                             "slip", param="network")
        ends = [e for e in (self.i, self.j) if e is not None]
        if all(net.coord(e)[0] in net.fixed for e in ends):
            raise InputError(f"friction {self.name} acts only on {' and '.join(ends)}, whose motion is prescribed: "
                             "it cannot change that motion; leave it out (the drive's torque is what moves the "
                             "node)", param="network")

    def row(self, net) -> np.ndarray:
        """g over the coordinates with phi_rel = g . q."""
        g = net.node_row(self.i).copy()
        if self.j is not None:
            g = g - self.U * net.node_row(self.j)
        return g

    def matrices(self, net) -> list:
        return [(self.row(net), 0.0, self.viscous)] if self.viscous else []

    def tables(self) -> list[Points]:
        return [self.capacity]

    def torque_piece(self, t_mid: float) -> tuple[float, float]:
        """(a, c): T_c = a + c t on the piece holding t_mid."""
        return piece(self.capacity, t_mid)

    def candidates(self, t_mid: float) -> tuple[int, ...]:
        a, c = self.torque_piece(t_mid)
        if a == 0.0 and c == 0.0:
            return (self.FREE,)
        return (self.STUCK, self.FORWARD, self.FREE) if self.one_way else (self.STUCK, self.FORWARD, self.BACKWARD)

    def stamp(self, p, state: int) -> None:
        if state not in (self.FORWARD, self.BACKWARD):
            return
        a, c = self.torque_piece(p.t_mid)
        sign = 1.0 if state == self.FORWARD else -1.0
        p.generalized(self.row(p.net), -sign * a, -sign * c)

    def joint(self, net, state: int) -> np.ndarray | None:
        return self.row(net) if state == self.STUCK else None

    def slip_sign(self, state: int) -> int:
        """+1 slipping forward, -1 backward, 0 otherwise (its torque's sign while slipping)."""
        return 1 if state == self.FORWARD else -1 if state == self.BACKWARD else 0

    def conditions(self, ctx, state: int) -> list[tuple[np.ndarray, bool]]:
        w = ctx.speed_row(self.row(ctx.net))
        if state == self.FORWARD:
            return [(w, True)]
        if state == self.BACKWARD:
            return [(-w, True)]
        if state == self.FREE:
            return [(-w, True)] if self.one_way else []
        a, c = self.torque_piece(ctx.t_mid)
        limit = ctx.time_row(self.static * a, self.static * c)
        T = ctx.joint_torque(self)
        low = T if self.one_way else T + limit
        return [(limit - T, True), (low, True), (w, False), (-w, False)]

    def state_of(self, net, t, X) -> np.ndarray:
        w = self.row(net) @ X[net.n:2 * net.n]
        out = np.where(w > 0, self.FORWARD, np.where(w < 0, self.BACKWARD if not self.one_way else self.FREE,
                                                    self.STUCK))
        return out.astype(np.int64)

    @property
    def default(self) -> int:
        return self.STUCK if any(v > 0 for _, v in self.capacity[-1:]) else self.FREE

    def outputs(self, net, t, X, accel) -> dict:
        state = net.switched_states(self, t, X)
        unit = "N" if net.node(self.i).translation else "N m"
        Tc = piecewise(self.capacity, t)
        T = np.where(state == self.FORWARD, Tc, np.where(state == self.BACKWARD, -Tc, 0.0))
        stuck = state == self.STUCK
        if np.any(stuck):
            T = np.where(stuck, net.joint_torques(self, t, X), T)
        w = self.row(net) @ X[net.n:2 * net.n]
        if self.viscous:
            T = T + self.viscous * w
        speed = "m/s" if net.node(self.i).translation else "rad/s"
        return {f"T_{self.name}": (np.broadcast_to(T, np.shape(t)).astype(float), unit),
                f"w_{self.name}": (w, speed),
                f"mode_{self.name}": (np.broadcast_to(state, np.shape(t)).astype(float), "1")}


# --- the speed loop: PI with a torque limit ------------------------------------------------------
@dataclass(frozen=True)
class SpeedLoop(Switched):
    """A drive on ``node`` with feed-forward and a PI speed loop:
    ``T = feedforward(t) + gain (reference(t) - omega) + ki I``, ``I' = reference(t) - omega``
    (the integral of the speed error, state ``I_<node>`` [rad], with ``ki`` > 0), both tables
    piecewise linear (t [s], N m) and (t [s], rad/s); gain [N m s/rad], ki [N m/rad].

    ``limit`` [N m]: the drive's torque (current) limit, |T| <= limit [AM08 sec. 10.4]. The
    command ``T_cmd`` beyond it saturates: T = +-limit, the integrator held (anti-windup by
    clamping: ``I' = 0``). Where holding would let the command fall back inside while the
    free integrator would push it out (``T_cmd' < 0`` held, ``> 0`` free, at T_cmd = limit), the
    command stays at its limit with the integrator rising just as fast as that needs
    (``ki I' = -(feedforward' + gain e')``: "held high"), the Filippov sliding motion between
    the two [F88 sec. 2.4]; it leaves when either side's rate allows. Without a limit the loop
    is linear (states free only). Output ``T_drive_<node>``."""

    node: str
    gain: float
    reference: Points
    feedforward: Points = ()
    ki: float = 0.0
    limit: float = math.inf

    STATES: ClassVar[tuple[str, ...]] = ("free", "high", "low", "held high", "held low")
    FREE, HIGH, LOW, HELD_HIGH, HELD_LOW = 0, 1, 2, 3, 4
    UNITS: ClassVar[dict] = {"gain": None, "ki": None, "limit": None}
    ORDER: ClassVar[int] = 20

    @property
    def switched(self) -> bool:                 # type: ignore[override]
        return math.isfinite(self.limit)

    @property
    def name(self) -> str:
        return f"drive_{self.node}"

    def check(self, net) -> None:
        net.check_ends("a speed loop", self.node, None)
        net.require_inertia(self.node, "a speed loop")
        require_range(f"{self.node} speed-loop gain", self.gain, "N*m*s/rad", low=0.0)
        require_range(f"{self.node} speed-loop ki", self.ki, "N*m/rad", low=0.0)
        if not self.limit > 0:
            raise InputError(f"{self.limit:g} is not allowed; a torque limit must be > 0",
                             param=f"{self.node} speed-loop limit")
        check_points(self.reference, f"speed reference of node {self.node}")
        check_points(self.feedforward, f"feed-forward of node {self.node}")

    def states(self) -> list[tuple[str, str]]:
        return [(f"I_{self.node}", "rad")] if self.ki else []

    def matrices(self, net) -> list:
        # -gain omega: a damper to the frame (a limited loop stamps it in its free state only)
        return [] if self.switched else [(net.node_row(self.node), 0.0, self.gain)]

    def tables(self) -> list[Points]:
        return [t for t in (self.reference, self.feedforward) if t]

    def candidates(self, t_mid: float) -> tuple[int, ...]:
        return tuple(range(5)) if self.ki else (self.FREE, self.HIGH, self.LOW)

    def inputs(self, p) -> None:
        if not self.switched:
            self._free(p, damper=False)

    def _free(self, p, damper: bool) -> None:
        a, c = piece(self.feedforward, p.t_mid)
        ra, rc = piece(self.reference, p.t_mid)
        p.torque(self.node, a + self.gain * ra, c + self.gain * rc)
        k, f = p.net.coord(self.node)
        n = p.net.n
        if damper:
            p.A[n + k, n + k] -= self.gain * f * f * p.Minv[k]
        if self.ki:
            s = p.state(self)
            p.A[n + k, s] += f * self.ki * p.Minv[k]        # ki I drives the node
            p.A[s, n + k] -= f                               # I' = reference - omega
            p.B[s, 0] += ra
            if rc:
                p.B[s, p.ramp] += rc

    def stamp(self, p, state: int) -> None:
        if state == self.FREE:
            self._free(p, damper=True)
        else:
            p.torque(self.node, self.limit if state in (self.HIGH, self.HELD_HIGH) else -self.limit)

    def settle(self, p, state: int, AB: np.ndarray) -> None:
        if state not in (self.HELD_HIGH, self.HELD_LOW):
            return
        # held: ki I' = -(feedforward' + gain (reference' - omega')), the command's rate zero
        k, f = p.net.coord(self.node)
        n, m, s = p.net.n, p.A.shape[0], p.state(self)
        c = piece(self.feedforward, p.t_mid)[1] + self.gain * piece(self.reference, p.t_mid)[1]
        row = self.gain * f * AB[n + k] / self.ki
        p.A[s] = row[:m]
        p.B[s] = row[m:]
        p.B[s, 0] -= c / self.ki

    def command(self, ctx) -> np.ndarray:
        """T_cmd = feedforward + gain (reference - omega) + ki I as a row over z."""
        a, c = piece(self.feedforward, ctx.t_mid)
        ra, rc = piece(self.reference, ctx.t_mid)
        k, f = ctx.net.coord(self.node)
        row = ctx.time_row(a + self.gain * ra, c + self.gain * rc)
        row[ctx.net.n + k] -= self.gain * f
        if self.ki:
            row[ctx.net.state_index[id(self)]] += self.ki
        return row

    def conditions(self, ctx, state: int) -> list[tuple[np.ndarray, bool]]:
        T = self.command(ctx)
        L = ctx.time_row(self.limit, 0.0)
        if state == self.FREE:
            return [(L - T, True), (T + L, True)]
        if state == self.HIGH:
            return [(T - L, True)]
        if state == self.LOW:
            return [(-L - T, True)]
        # held: the command's rate held (r_s) and free (r_f = r_s + ki e) bracket zero
        k, f = ctx.net.coord(self.node)
        c = piece(self.feedforward, ctx.t_mid)[1] + self.gain * piece(self.reference, ctx.t_mid)[1]
        r_held = ctx.time_row(c, 0.0) - self.gain * f * ctx.acc_row(k)
        ra, rc = piece(self.reference, ctx.t_mid)
        e = ctx.time_row(ra, rc)
        e[ctx.net.n + k] -= f
        r_free = r_held + self.ki * e
        if state == self.HELD_HIGH:
            return [(-r_held, True), (r_free, True), (T - L, False), (L - T, False)]
        return [(r_held, True), (-r_free, True), (T + L, False), (-L - T, False)]

    def state_of(self, net, t, X) -> np.ndarray:
        if not self.switched:
            return np.zeros(np.shape(t), dtype=np.int64)
        T = self._command_values(net, t, X)
        return np.where(T > self.limit, self.HIGH, np.where(T < -self.limit, self.LOW, self.FREE)).astype(np.int64)

    def _command_values(self, net, t, X) -> np.ndarray:
        c, f = net.coord(self.node)
        ff = piecewise(self.feedforward, t) if self.feedforward else 0.0
        T = ff + self.gain * (piecewise(self.reference, t) - f * X[net.n + c])
        if self.ki:
            T = T + self.ki * X[net.state_index[id(self)]]
        return np.broadcast_to(T, np.shape(t))

    def outputs(self, net, t, X, accel) -> dict:
        T = self._command_values(net, t, X)
        unit = "N" if net.node(self.node).translation else "N m"
        out = {}
        if self.switched:
            state = net.switched_states(self, t, X)
            high = (state == self.HIGH) | (state == self.HELD_HIGH)
            low = (state == self.LOW) | (state == self.HELD_LOW)
            T = np.where(high, self.limit, np.where(low, -self.limit, T))
            out[f"mode_{self.name}"] = (np.broadcast_to(state, np.shape(t)).astype(float), "1")
        out[f"T_drive_{self.node}"] = (np.array(np.broadcast_to(T, np.shape(t)), dtype=float), unit)
        return out
