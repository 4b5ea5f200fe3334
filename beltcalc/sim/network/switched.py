"""What the elements with modes of their own add to a network
(:mod:`beltcalc.sim.elements.switched`: friction that sticks, a drive's torque limit): a
mode's joints, the conditions that hold in it, the switches they make, and the choice of the
next mode at a switch. :class:`~beltcalc.sim.network.Network` has them as methods
(:class:`SwitchedModes`); the switching core and the scipy methods call them. SI floats.

**A mode** is the strands' pattern followed by every switched element's state (an int): the
tuple ``pattern = (taut_1, ..., taut_s, state_1, ..., state_w)``.

**A stuck joint keeps its degree of freedom** and is held by its constraint torque (a
Lagrange multiplier), not by merging its two nodes: every mode then has the same state
vector, so a switch needs no mapping of the state, the propagators of every mode act on the
same ``z``, and the constraint torque, which the conditions and the reports need, is a row
over ``z``. With the joints' rows ``G`` over the coordinates and the accelerations ``a`` of
the mode without them (a row block of ``[A | B]``), ``M q'' = f - G^T lambda`` and
``G q'' = 0`` give

    lambda = (G M_f^-1 G^T)^-1 G a,     q'' = a - M_f^-1 G^T lambda

(``M_f^-1``: the inverse masses, 0 on a prescribed coordinate, whose motion is imposed): the
Gauss principle of least constraint for a linear constraint on the speeds [U96]. Both are
linear in z, so the stuck mode is linear and propagated exactly like the others, its
relative speed held at its entry value (zero to rounding) by construction.

**The next mode** at a switch (or where the inputs change piece) is the one in which every
element's conditions hold just after it: each condition's value, and on its surface its
first Taylor coefficient beyond rounding in that mode, must be >= 0 (:meth:`decide_switched`).
The elements on a surface are tried together, their current states first, then their
preferred order (stuck before slipping), and the first mode that holds is kept; a clutch
that would chatter between slipping forward and back is stuck instead, since stuck is the
sliding motion that holds (Filippov [F88 sec. 2.4]).

References:

[U96] F. E. Udwadia, R. E. Kalaba, Analytical Dynamics: A New Approach, Cambridge University
    Press (1996): the constrained accelerations of a linear constraint on the speeds, from
    Gauss's principle [U96 ch. 2].
[F88] A. F. Filippov, Differential Equations with Discontinuous Righthand Sides, Kluwer
    (1988): the motion on a discontinuity surface.
"""

from __future__ import annotations

import itertools

import numpy as np

from beltcalc.errors import InputError, SimulationError
from beltcalc.sim.network.assembly import Event

EPS = np.finfo(float).eps
ROUND = 1024 * EPS   # the switching core's rounding level (beltcalc.sim.switching.firing.ROUND)
TERMS = 8            # Taylor terms of a decision's leaving test
MAX_TRIALS = 4096    # modes tried at one decision
DRIFT = 1e-9         # a stuck joint's relative speed below this of the largest speed is drift (settled)


class Context:
    """What an element's conditions read of one mode: rows over ``z = [x, g]``."""

    def __init__(self, net, t_mid: float, AB: np.ndarray, joints: dict):
        self.net, self.t_mid, self.AB, self.joints = net, t_mid, AB, joints
        self.width = AB.shape[1]

    def speed_row(self, g: np.ndarray) -> np.ndarray:
        """g . q' (g over the coordinates)."""
        row = np.zeros(self.width)
        row[self.net.n:2 * self.net.n] = g
        return row

    def time_row(self, a: float, c: float) -> np.ndarray:
        """a + c t (the generators 1 and t)."""
        row = np.zeros(self.width)
        row[self.net.size] = a
        if c:
            row[self.net.size + 1] = c
        return row

    def acc_row(self, k: int) -> np.ndarray:
        """Coordinate k's acceleration in this mode."""
        return self.AB[self.net.n + k].copy()

    def joint_torque(self, el) -> np.ndarray:
        """The constraint torque of a stuck element (its lambda)."""
        return self.joints[id(el)].copy()


class SwitchedModes:
    """The switched elements' methods of :class:`~beltcalc.sim.network.Network`: they read its
    ``switched`` elements, ``strands``, ``mass``, ``fixed``, ``n``, ``size`` and its
    ``first_order`` cache."""

    def full_pattern(self, pattern) -> tuple:
        """A strand pattern completed with the switched elements' default states (what the
        frequency domain takes), or a whole mode as it is."""
        pattern = tuple(pattern)
        ns = len(self.strands)
        if len(pattern) >= ns + len(self.switched):
            return pattern
        return pattern[:ns] + tuple(el.default for el in self.switched)[len(pattern) - ns:]

    def check_parallel_joints(self) -> None:
        """Refuse two elements that can stick on the same motion (a brake and a bearing's
        friction on one drum): their torques' split while both hold is not determined by the
        motion, so neither is which one breaks loose first. One element with the summed
        torques is the same drive."""
        rows = [(el, el.row(self)) for el in self.switched if hasattr(el, "row")]
        for a, (el, g) in enumerate(rows):
            for other, h in rows[a + 1:]:
                if abs(abs(g @ h) - np.linalg.norm(g) * np.linalg.norm(h)) <= 1e-12 * np.linalg.norm(g) * np.linalg.norm(h):
                    raise InputError(f"{el.name} and {other.name} both hold the same motion: give one element with "
                                     "their torques summed (e.g. the brake's torque plus the bearing's)",
                                     param="network")

    def impose_joints(self, A: np.ndarray, B: np.ndarray, pattern, constrained: bool, t_mid: float) -> dict:
        """Hold the stuck joints of ``pattern`` in ``[A | B]`` (in place): the accelerations'
        rows less ``M_f^-1 G^T lambda``. Returns {id(element): its lambda row over z}. The
        unconstrained system (a prescribed node left free, for its drive torque) takes the
        constrained system's lambdas and lets them act on every coordinate."""
        ns, n = len(self.strands), self.n
        stuck = [(el, el.joint(self, st)) for el, st in zip(self.switched, pattern[ns:])]
        stuck = [(el, g) for el, g in stuck if g is not None]
        if not stuck:
            return {}
        G = np.array([g for _, g in stuck])
        m = A.shape[0]
        if not constrained:
            joints = self.joint_rows(pattern, t_mid)
            lam = np.array([joints[id(el)] for el, _ in stuck])
            inv = 1.0 / self.mass
        else:
            inv = 1.0 / self.mass
            inv[list(self.fixed)] = 0.0
            acc = np.hstack([A[n:2 * n], B[n:2 * n]])
            W = G @ (inv[:, None] * G.T)
            rhs = G @ acc
            # joints that hold the same motion twice (a brake and a bearing on one stopped
            # drum, joints in a loop) share their torque: the least-norm lambdas
            lam = np.linalg.solve(W, rhs) if W.shape[0] == 1 else np.linalg.lstsq(W, rhs, rcond=1e-10)[0]
            # a torque that cancels to rounding inside the solve is zero (a drum shaft's torque
            # on a clutch whose driven hub a brake holds: 1e-13 of it)
            size = np.abs(np.linalg.pinv(W, rcond=1e-10)) @ (np.abs(G) @ np.abs(acc))
            lam[np.abs(lam) <= 64 * EPS * size] = 0.0
        push = (inv[:, None] * G.T) @ lam
        bound = (inv[:, None] * np.abs(G.T)) @ np.abs(lam)      # the terms' magnitudes
        for M, part, size in ((A, push[:, :m], bound[:, :m]), (B, push[:, m:], bound[:, m:])):
            # what cancels to rounding (a held node's acceleration: 1e-10 of a stiffness over an
            # inertia) is zero: left, it is a slow spurious motion that a tolerance-driven
            # solver chases with tiny steps
            scale = np.abs(M[n:2 * n]) + size
            M[n:2 * n] -= part
            M[n:2 * n][np.abs(M[n:2 * n]) <= 64 * EPS * scale] = 0.0
        return {id(el): lam[k] for k, (el, _) in enumerate(stuck)}

    def joint_rows(self, pattern, t_mid: float) -> dict:
        """{id(element): lambda row over z} of the stuck joints of ``pattern``."""
        if not self.switched:
            return {}
        pattern = self.full_pattern(pattern)
        key = (pattern, tuple(self._pieces(t_mid)))
        if key not in self._joints:
            self._build(pattern, t_mid, True)        # it keeps them
        return self._joints[key]

    def conditions(self, pattern, t_mid: float) -> list[list[tuple[np.ndarray, bool]]]:
        """Per switched element, its conditions (row over z, is a switch) in ``pattern``."""
        if not self.switched:
            return []
        pattern = self.full_pattern(pattern)
        key = ("conditions", pattern, tuple(self._pieces(t_mid)))
        hit = self._cache.get(key)
        if hit is None:
            A, B = self.first_order(pattern, t_mid)
            ctx = Context(self, t_mid, np.hstack([A, B]), self.joint_rows(pattern, t_mid))
            ns = len(self.strands)
            hit = self._cache[key] = [el.conditions(ctx, st) for el, st in zip(self.switched, pattern[ns:])]
        return hit

    def switched_events(self, pattern, t_mid: float) -> list[Event]:
        """The switches of a mode: every condition that is one, falling through zero."""
        ns = len(self.strands)
        return [Event(ns + j, "condition", -1, row)
                for j, conds in enumerate(self.conditions(pattern, t_mid)) for row, event in conds if event]

    def settle_joints(self, z: np.ndarray, pattern, guess: bool = False) -> np.ndarray:
        """z with the relative speed of every stuck joint of ``pattern`` exactly zero: the
        speeds' least change in kinetic energy that does it (momentum kept), removing the
        rounding a long stretch of sticking leaves (1e-12 of the speeds the drive had, which
        can be far more than those it has once it comes to rest). ``guess``: the pattern is a
        first guess (the start), whose "stuck" clutch may slip at 100 rad/s: only joints whose
        relative speed is below DRIFT of the speeds are settled, the rest is for the decision."""
        ns, n = len(self.strands), self.n
        G = [el.joint(self, st) for el, st in zip(self.switched, pattern[ns:])]
        top = float(np.max(np.abs(z[n:2 * n]))) if n else 0.0
        G = np.array([g for g in G if g is not None and (not guess or
                                                          abs(g @ z[n:2 * n]) <= DRIFT * top * np.abs(g).sum())])
        if not G.size:
            return z
        inv = 1.0 / self.mass
        inv[list(self.fixed)] = 0.0
        W = G @ (inv[:, None] * G.T)
        drift = G @ z[n:2 * n]
        share = np.linalg.solve(W, drift) if W.shape[0] == 1 else np.linalg.lstsq(W, drift, rcond=1e-10)[0]
        z = z.copy()
        z[n:2 * n] -= inv * (G.T @ share)
        return z

    def decide_switched(self, z: np.ndarray, pattern, t_mid: float, h: float,
                        fired: int | None = None, slack: float = 0.0, guess: bool = False) -> tuple[tuple, np.ndarray]:
        """(mode, z): the switched elements' states just after a restart at ``z`` (over
        [x, g]) in the strand pattern of ``pattern`` (the current states where every condition
        is off its surface, else the first mode tried whose conditions hold: see the module),
        and z with its stuck joints settled (:meth:`settle_joints`). ``h``: a step of the mode
        (the Taylor terms' scale); ``fired``: the element whose condition fired (decided in
        any case); ``slack``: the relative error of z where it is not exact (a scipy method's
        rtol): a condition within it of its surface is on it; ``guess``: ``pattern`` is a first
        guess (the run's start), not the mode the run was in."""
        pattern = self.full_pattern(pattern)
        if not self.switched:
            return pattern, z
        z = self.settle_joints(z, pattern, guess)
        ns = len(self.strands)
        current = list(pattern[ns:])
        options = [el.candidates(t_mid) for el in self.switched]
        conds = self.conditions(pattern, t_mid)
        mag = self._levels(z, self._magnitudes(pattern, t_mid, z, h))
        open_ = []
        for j in range(len(self.switched)):
            if j == fired or current[j] not in options[j] or any(
                    row @ z <= max(ROUND, slack) * (np.abs(row) @ mag) + 1e-300 for row, _ in conds[j]):
                open_.append(j)
        if not open_:
            return pattern, z
        tries = [[current[j]] + [s for s in options[j] if s != current[j]] if current[j] in options[j]
                 else list(options[j]) for j in open_]
        by_value = None
        for count, combo in enumerate(itertools.product(*tries)):
            if count >= MAX_TRIALS:
                break
            trial = list(pattern)
            for j, s in zip(open_, combo):
                trial[ns + j] = s
            trial = tuple(trial)
            if self._holds(z, trial, t_mid, h, slack, fired=fired):
                return trial, self.settle_joints(z, trial)
            if slack and by_value is None and self._holds(z, trial, t_mid, h, slack, rates=False, fired=fired):
                by_value = trial
        if by_value is not None:
            # a state known to a solver's tolerance only (scipy's): the rates just after it say
            # nothing that tolerance does not swamp; the first mode its values admit
            return by_value, self.settle_joints(z, by_value)
        names = ", ".join(self.switched[j].name for j in open_)
        raise SimulationError(f"no mode of {names} holds just after this switch (tried {min(count + 1, MAX_TRIALS)}); "
                              "the friction or limit values may contradict each other")

    def _terms(self, pattern, t_mid: float, z: np.ndarray, h: float, bound: bool = False):
        """z's Taylor terms (F h)^j z / j! in ``pattern``, j < TERMS; with ``bound`` also the
        same series of magnitudes, (|F| h)^j |z| / j!, that bounds each term's rounding (a
        stuck mode's rows are differences of large terms: their rates' rounding is that of
        the terms, not of the small result)."""
        A, B = self.first_order(pattern, t_mid)
        m = A.shape[0]
        F = np.zeros((z.size, z.size))
        F[:m, :m], F[:m, m:] = A, B
        F[m:, m:] = self.generator_matrix()
        V = np.empty((TERMS, z.size))
        V[0] = z
        for j in range(1, TERMS):
            V[j] = (F @ V[j - 1]) * (h / j)
        if not bound:
            return V
        U, aF = np.empty_like(V), np.abs(F)
        U[0] = np.abs(z)
        for j in range(1, TERMS):
            U[j] = (aF @ U[j - 1]) * (h / j)
        return V, U

    def _levels(self, z: np.ndarray, mag: np.ndarray) -> np.ndarray:
        """The magnitudes a condition's rounding is judged by: its terms' (``mag``), and every
        speed at least the largest speed's (settling a stuck joint moves the speeds by the
        rounding of the largest, a node just come to rest included)."""
        n = self.n
        out = mag.copy()
        if n:
            np.maximum(out[n:2 * n], np.max(np.abs(z[n:2 * n])), out=out[n:2 * n])
        return out

    def _magnitudes(self, pattern, t_mid, z, h) -> np.ndarray:
        return np.abs(self._terms(pattern, t_mid, z, h)).sum(axis=0)

    def _holds(self, z: np.ndarray, pattern, t_mid: float, h: float, slack: float = 0.0, rates: bool = True,
               fired: int | None = None) -> bool:
        """Whether every switched element's conditions hold just after z in ``pattern``."""
        V, U = self._terms(pattern, t_mid, z, h, bound=True)
        mag = self._levels(z, np.abs(V).sum(axis=0))
        n = self.n
        top = float(np.max(np.abs(z[n:2 * n]))) if n else 0.0
        for j, conds in enumerate(self.conditions(pattern, t_mid)):
            for row, event in conds:
                value = row @ z
                tol = max(ROUND, slack) * (np.abs(row) @ mag) + 1e-300
                if not event:      # a stuck joint's zero speed: drift that settling removes is zero
                    tol = max(tol, DRIFT * top * float(np.abs(row[n:2 * n]).sum()))
                if value < -tol:
                    return False
                if value <= tol and event and rates:          # (a row that is no switch: its value alone)
                    c = V[1:] @ row
                    level = ROUND * (U[1:] @ np.abs(row)) + 1e-300
                    big = np.flatnonzero(np.abs(c) > level)
                    if big.size and c[big[0]] < 0:
                        return False
        return True

    # --- the frequency domain: one mode as a linear network --------------------------------
    def frozen(self, pattern):
        """The linear network of one mode, for the frequency domain (modes, response,
        campbell): a stuck clutch a rigid gear between its nodes (its degree of freedom
        merged: no spurious rigid-body pole), a stuck brake or bearing a node held still, a
        slipping or free one only its viscous part (its torque is an input, not a stiffness),
        a drive at its limit a constant torque, a free one its linear loop."""
        import dataclasses

        from beltcalc.sim.elements import Coupling, Gear, Load, Prescribed
        from beltcalc.sim.elements.switched import Friction

        pattern = self.full_pattern(pattern)
        ns = len(self.strands)
        held = {p.node for p in self.prescribed}
        elements = list(self.gears) + list(self.strands)
        by_el = dict(zip(map(id, self.switched), pattern[ns:]))
        for el in self.elements:
            state = by_el.get(id(el))
            if state is None:
                elements.append(el)
            elif isinstance(el, Friction):
                if state == el.STUCK and el.j is not None:
                    elements.append(Gear(el.i, el.j, el.U, name=el.name))
                elif state == el.STUCK and el.i not in held:
                    elements.append(Prescribed(el.i))
                    held.add(el.i)
                if el.viscous and not (state == el.STUCK):
                    elements.append(Coupling(el.name, el.i, el.j, 0.0, el.viscous, el.U))
            elif state == el.FREE:
                elements.append(dataclasses.replace(el, limit=float("inf")))
            else:
                limit = el.limit if state in (el.HIGH, el.HELD_HIGH) else -el.limit
                elements.append(Load(el.node, -limit))
        return type(self)(list(self.nodes), elements)

    def describe(self, pattern) -> str:
        """The switched elements' states of ``pattern`` in words (``limiter stuck, ...``)."""
        pattern = self.full_pattern(pattern)
        ns = len(self.strands)
        return ", ".join(f"{el.name} {el.STATES[s]}" for el, s in zip(self.switched, pattern[ns:]))

    # --- per sample (outputs) ---------------------------------------------------------------
    def seed_switched(self, t: np.ndarray | None, states: np.ndarray | None) -> None:
        """Let :meth:`switched_states` answer for the array ``t`` (the same object) with the
        run's states (switched elements, samples); None forgets."""
        if t is None or states is None:
            self.__dict__.pop("_seeded_switched", None)
        else:
            self._seeded_switched = (t, states)

    def switched_states(self, el, t, X) -> np.ndarray:
        """Element ``el``'s state at each sample: the run's where seeded, else what the state
        suggests (:meth:`beltcalc.sim.elements.switched.Switched.state_of`)."""
        seeded = self.__dict__.get("_seeded_switched")
        if seeded is not None and t is seeded[0]:
            return seeded[1][next(j for j, e in enumerate(self.switched) if e is el)]
        return el.state_of(self, t, X)

    def sample_groups(self, t, X, Z) -> list[tuple[tuple, np.ndarray]]:
        """The samples grouped by mode: [(pattern, columns)], strands by their own state."""
        T = np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],))
        taut = self._taut_rows(Z) if self.strands else np.zeros((0, X.shape[1]), dtype=bool)
        states = np.array([self.switched_states(el, t, X) for el in self.switched]).reshape(len(self.switched), -1)
        states = np.broadcast_to(states, (len(self.switched), X.shape[1]))
        starts = self.segment_starts(float(T.max()) if T.size else 0.0)
        seg = np.searchsorted(starts, T, side="right") - 1
        keys = np.vstack([taut.astype(np.int64), states, seg[None]])
        out = []
        order = np.lexsort(keys[::-1]) if keys.shape[1] else np.zeros(0, dtype=np.int64)
        bounds = np.flatnonzero(np.any(np.diff(keys[:, order], axis=1) != 0, axis=0)) + 1
        for cols in np.split(order, bounds):
            if cols.size:
                k = keys[:, cols[0]]
                pattern = tuple(bool(v) for v in k[:len(self.strands)]) + tuple(int(v) for v in
                                                                                k[len(self.strands):-1])
                out.append((pattern, self.piece_time(int(k[-1]), starts, float(T.max())), cols))
        return out

    def joint_torques(self, el, t, X) -> np.ndarray:
        """Element ``el``'s constraint torque at each sample where it is stuck (else 0)."""
        Xa = np.asarray(X, dtype=float)
        T = np.broadcast_to(np.asarray(t, dtype=float), (Xa.shape[1],))
        Z = np.vstack([Xa, self.generators(t if np.shape(t) == T.shape else T)])
        out = np.zeros(Xa.shape[1])
        for pattern, t_mid, cols in self.sample_groups(t, Xa, Z):
            row = self.joint_rows(pattern, t_mid).get(id(el))
            if row is not None:
                out[cols] = row @ Z[:, cols]
        return out
