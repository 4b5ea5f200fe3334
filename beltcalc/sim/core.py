"""The one place that integrates. Methods by name from a registry:

- ``exact``: networks that are linear between switches, with constant, sinusoidal and
  piecewise-linear inputs. The state is augmented with the inputs' generators
  (g' = G g), and the augmented system z' = F z is propagated with the one-step matrix
  expm(F dt) (scipy's scaling and squaring). No eigen-decomposition: on the sewing model
  its eigenvector matrix has a condition number near 1e13 and loses about 0.1 rad/s.

  * one linear system over the whole run: in blocks, the powers P_r = expm(F dt)^r,
    r < b, applied to every block start at once;
  * tension-only strands and time break points: piecewise. Between switches the exact
    solution is propagated (powers by doubling); the switching functions (a strand's
    elongation and force, both linear in z) are checked on every step, with their rates,
    for a sign change or a hidden double crossing (a cubic Hermite test, and steps no
    longer than 1 / the fastest angular frequency of the mode); a switch is then located by
    bisection and Brent's method on the exact solution, expm(F tau) z. The run restarts
    on the switching surface in the new mode, which is chosen by the rates, so it does
    not fire again at once. The number of switches is bounded (``max_events``) and
    reported.
- ``radau``, ``bdf``, ``lsoda``, ``rk45``, ``dop853``: scipy's ``solve_ivp`` with the
  analytic Jacobian where it takes one, restarted at every time break point and at every
  strand switch (terminal events with their direction set);
- ``odeint``: scipy's older LSODA wrapper with ``Dfun``, on the raw right-hand side (each
  strand taut or slack by its own state, no events): fast on smooth networks, and the
  trap the design warns of on switching ones, where the call budget stops it.
- ``auto``: ``exact`` where the network allows it, else ``radau``; the result says why.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import odeint, solve_ivp  # the simulation commands import this module only
from scipy.linalg import expm

from beltcalc.errors import InputError, SimulationError, require_positive
from beltcalc.sim.network import Network
from beltcalc.sim.result import SimResult


@dataclass(frozen=True)
class SolverConfig:
    """method: auto | exact | radau | bdf | lsoda | odeint | rk45 | dop853;
    rtol/atol for the step-size-controlled methods; max_rhs_calls bounds a run;
    max_events bounds the strand switches (a strand chattering near zero tension);
    estimate_error: run the reference (half-step exact, or exact) and report the difference."""

    method: str = "auto"
    rtol: float = 1e-8
    atol: float = 1e-10
    max_rhs_calls: int = 5_000_000
    max_events: int = 20_000
    estimate_error: bool = True


class _Budget(Exception):
    pass


def _initial(network: Network, x0: np.ndarray | None) -> np.ndarray:
    x = network.initial_state() if x0 is None else np.asarray(x0, dtype=float)
    if x.shape != (network.size,):
        raise InputError(f"initial state has {x.size} values; the network has {network.size}", param="x0")
    return x


def _augment(network: Network, A: np.ndarray, B: np.ndarray) -> np.ndarray:
    m, p = A.shape[0], B.shape[1]
    F = np.zeros((m + p, m + p))
    F[:m, :m] = A
    F[:m, m:] = B
    F[m:, m:] = network.generator_matrix()
    return F


def augmented_matrix(network: Network, taut=None, t_mid: float = 0.0) -> np.ndarray:
    """F of z' = F z with z = [x, g]: the network (strand mode ``taut``, time piece holding
    ``t_mid``) and its input generators."""
    return _augment(network, *network.first_order(taut, t_mid))


def _orbit(step: np.ndarray, start: np.ndarray, count: int) -> np.ndarray:
    """[step^0 start, step^1 start, ..., step^(count-1) start] by doubling: log2(count)
    batched products instead of count sequential ones. ``start`` is a vector or a matrix."""
    out = np.empty((count, *start.shape))
    out[0] = start
    filled, power = 1, step
    while filled < count:
        n = min(filled, count - filled)
        out[filled:filled + n] = power @ out[:n] if start.ndim == 2 else out[:n] @ power.T
        filled += n
        power = power @ power
    return out


def _propagate(F: np.ndarray, z0: np.ndarray, dt: float, samples: int) -> np.ndarray:
    """z at t_k = k dt, k < samples, as columns. With S = expm(F dt) and b ~ sqrt(samples):
    the powers S^r (r < b) and the block starts S^(k b) z0 are built by doubling, then one
    BLAS product gives every sample: z[k b + r] = S^r (S^(k b) z0)."""
    m = F.shape[0]
    step = expm(F * dt)
    b = max(1, min(samples, int(math.ceil(math.sqrt(samples)))))
    powers = _orbit(step, np.eye(m), b)
    jump = step @ powers[b - 1]                      # S^b
    nblocks = -(-samples // b)
    starts = _orbit(jump, z0, nblocks)               # (nblocks, m)
    # z[k b + r, i] = sum_j starts[k, j] powers[r, i, j]: one product whose result is
    # already in sample order (no strided copy afterwards)
    q = powers.transpose(2, 0, 1).reshape(m, b * m)
    z = (starts @ q).reshape(nblocks * b, m)
    return z[:samples].T


# --- switching ------------------------------------------------------------------------------
class _Switches:
    """The strand mode, its switches and the event budget of one run."""

    def __init__(self, network: Network, z0: np.ndarray, cfg: SolverConfig, method: str, h: float):
        self.network, self.cfg, self.method = network, cfg, method
        delta, force = network.strand_rows()
        d, f = delta @ z0, force @ z0
        # at rest a strand without pretension sits on the surface; it is taut if it stretches
        self.taut = tuple(bool(a > 0 and b > 0) for a, b in zip(d, f))
        F = augmented_matrix(network, self.taut)
        self.taut = tuple(network.taut_after(k, z0, F @ z0, _ahead(F, z0, h), h) for k in range(len(d)))
        self.start = self.taut
        self.log: list[tuple[float, int, bool]] = []
        self.located = 0

    def switch(self, strand: int, t: float, z: np.ndarray, F: np.ndarray, h: float) -> None:
        """Decide strand ``strand``'s mode just after ``t`` and record a change."""
        self.located += 1
        if self.located > self.cfg.max_events:
            name = self.network.strands[strand].name
            raise SimulationError(
                f"method {self.method}: {self.cfg.max_events} strand events by t = {t:.6g} s (strand {name} "
                "chatters near zero tension); add pretension or damping, or raise --max-events")
        on = self.network.taut_after(strand, z, F @ z, _ahead(F, z, h), h)
        if on != self.taut[strand]:
            self.taut = tuple(on if k == strand else v for k, v in enumerate(self.taut))
            self.log.append((t, strand, on))

    def info(self, t_end: float) -> dict:
        """Switch count and each strand's time slack [s]."""
        slack = {}
        for k, s in enumerate(self.network.strands):
            on, since, total = self.start[k], 0.0, 0.0
            for t, strand, state in self.log:
                if strand == k:
                    if not on:
                        total += t - since
                    on, since = state, t
            if not on:
                total += t_end - since
            slack[s.name] = total
        return {"events": len(self.log), "located": self.located, "slack_time": slack}


def _ahead(F: np.ndarray, z: np.ndarray, h: float) -> np.ndarray:
    """The state a moment (1e-6 h) later, by its Taylor series to second order."""
    eps = 1e-6 * h
    dz = F @ z
    return z + eps * dz + 0.5 * eps ** 2 * (F @ dz)


def _tol(scale: float) -> float:
    return 1e-9 * scale + 1e-300


def _hermite_signs(G0, G1, D0, D1, h):
    """Sign changes of the cubic Hermite interpolant of each switching function over an
    interval (values G, rates D at both ends), counted on 9 inner points."""
    th = np.linspace(0.0, 1.0, 11)[1:-1].reshape((-1,) + (1,) * np.ndim(G0))
    p = ((2 * th**3 - 3 * th**2 + 1) * G0 + (th**3 - 2 * th**2 + th) * h * D0
         + (-2 * th**3 + 3 * th**2) * G1 + (th**3 - th**2) * h * D1)
    seq = np.concatenate([G0[None], p, G1[None]])
    return np.sum(np.diff(np.sign(seq), axis=0) != 0, axis=0)


LEVELS = 12   # halvings of a step before a switch is placed on the cubic through its ends


class _Piece:
    """The augmented system of one strand mode on one time piece, its switching rows, and the
    one-step matrices P_k = expm(F h / 2^k) of its step h (built once, when first needed)."""

    def __init__(self, network: Network, taut, t_mid: float, dt: float):
        self.F = augmented_matrix(network, taut, t_mid)
        events = network.events(taut)
        self.events = events
        self.H = np.array([e.row for e in events]).reshape(len(events), self.F.shape[0])
        self.HF = self.H @ self.F
        self.dirs = np.array([e.direction for e in events])
        fastest = 0.0
        if events:
            lam = np.linalg.eigvals(self.F[:network.size, :network.size])
            fastest = float(np.max(np.abs(lam.imag))) if lam.size else 0.0
        self.sub = max(1, int(math.ceil(dt * fastest)))   # steps per output step: <= 1 rad each
        self.h = dt / self.sub
        self._P: dict[int, np.ndarray] = {}

    def P(self, k: int) -> np.ndarray:
        M = self._P.get(k)
        if M is None:
            M = self._P[k] = expm(self.F * (self.h / 2 ** k))
        return M

    def _start(self, G0, tol, skip):
        """Put the switching functions that just fired (``skip``) past their surface: a
        restart on the surface must not fire them again."""
        for e in skip:
            if abs(G0[e]) <= 2 * tol[e]:
                G0[e] = self.dirs[e] * 2 * tol[e]
        return G0

    def _flags(self, G0, G1, D0, D1, L, tol):
        """Per switching function over a step of length L: a crossing in its direction
        (from the surface too), and a possible hidden double crossing (cubic Hermite test)."""
        up = self.dirs > 0
        crossed = np.where(up, (G0 < -tol) & (G1 >= -tol) | (np.abs(G0) <= tol) & (G1 > tol),
                           (G0 > tol) & (G1 <= tol) | (np.abs(G0) <= tol) & (G1 < -tol))
        # the cubic departs from the chord by at most 4/27 (|L D0 - dG| + |L D1 - dG|): only
        # steps that close to zero need the test
        dG = G1 - G0
        reach = 4 / 27 * (np.abs(L * D0 - dG) + np.abs(L * D1 - dG))
        near = (np.minimum(np.abs(G0), np.abs(G1)) <= reach) & ((np.abs(G0) > tol) | (np.abs(G1) > tol)) & ~crossed
        hidden = np.zeros_like(crossed)
        if np.any(near):
            idx = np.nonzero(near)
            hidden[idx] = _hermite_signs(G0[idx], G1[idx], D0[idx], D1[idx], L) > 0
        return crossed, hidden

    def scan(self, Z: np.ndarray, skip=()):
        """Index i of the first step Z[i] -> Z[i+1] (each of length h) in which a switch may
        happen, or None."""
        if not self.events:
            return None
        G = Z @ self.H.T
        D = Z @ self.HF.T
        tol = _tol(np.max(np.abs(G), axis=0))
        G0 = G[:-1].copy()
        G0[0] = self._start(G0[0], tol, skip)
        crossed, hidden = self._flags(G0, G[1:], D[:-1], D[1:], self.h, tol)
        hit = np.nonzero(np.any(crossed | hidden, axis=1))[0]
        return int(hit[0]) if hit.size else None

    def search(self, z: np.ndarray, k: int, skip=()):
        """The earliest switch in the step of length h / 2^k from z: (tau, event, z(tau)) or None."""
        L = self.h / 2 ** k
        zb = self.P(k) @ z
        found = self._check(z, zb, L, skip)
        if found is None or k >= LEVELS:
            return found if found is None else self._root(z, L, *found)
        left = self.search(z, k + 1, skip)
        if left is not None:
            return left
        right = self.search(self.P(k + 1) @ z, k + 1)
        return None if right is None else (L / 2 + right[0], right[1], right[2])

    def search_span(self, z: np.ndarray, L: float, skip=()):
        """The same over a short remainder L < h / 2^LEVELS (one expm); also returns z(L)."""
        zb = expm(self.F * L) @ z
        found = self._check(z, zb, L, skip)
        return (None if found is None else self._root(z, L, *found)), zb

    def _check(self, z, zb, L, skip):
        if not self.events:
            return None
        G0, G1 = self.H @ z, self.H @ zb
        D0, D1 = self.HF @ z, self.HF @ zb
        tol = _tol(np.maximum(np.abs(G0), np.abs(G1)) + np.abs(D0) * L)
        G0 = self._start(G0, tol, skip)
        crossed, hidden = self._flags(G0, G1, D0, D1, L, tol)
        if not np.any(crossed | hidden):
            return None
        return G0, G1, D0, D1, tol, crossed | hidden

    def _root(self, z, L, G0, G1, D0, D1, tol, candidates):
        """The first crossing on the cubic Hermite through the step's ends (exact to the
        step's fourth power, h / 2^LEVELS long), and the exact state there."""
        th = np.linspace(0.0, 1.0, 257)[:, None]

        def cubic(x, e):
            return ((2 * x**3 - 3 * x**2 + 1) * G0[e] + (x**3 - 2 * x**2 + x) * L * D0[e]
                    + (-2 * x**3 + 3 * x**2) * G1[e] + (x**3 - x**2) * L * D1[e])

        best = None
        for e in np.nonzero(candidates)[0]:
            d = self.dirs[e]
            if abs(G0[e]) <= tol[e] and d * G1[e] > tol[e]:
                theta = 0.0                       # leaving the surface at once
            else:
                p = cubic(th[:, 0], e)
                before = d * p <= 0                 # on the side the crossing starts from
                if not before.any():
                    continue
                first = int(np.argmax(before))
                after = np.nonzero(~before[first:])[0]
                if after.size == 0:
                    continue
                j = first + int(after[0])
                lo, hi = th[j - 1, 0], th[j, 0]
                for _ in range(60):               # bisection on the cubic: scalar work
                    mid = 0.5 * (lo + hi)
                    if d * cubic(mid, e) > 0:
                        hi = mid
                    else:
                        lo = mid
                theta = hi
            if best is None or theta < best[0]:
                best = (theta, int(e))
        if best is None:
            return None
        tau, e = best[0] * L, best[1]
        if tau == 0.0:
            return tau, e, z
        # the cubic's root may sit a hair before the exact one: step on until the exact state
        # is past the surface, so the new mode is judged on a clear side
        d, row = self.dirs[e], self.H[e]
        for k in range(25):
            zt = expm(self.F * tau) @ z
            if d * (row @ zt) > 0 or tau >= L:
                break
            tau = min(L, tau + (L - tau) * 2.0 ** (k - 24))
        return tau, e, zt


def _piecewise_exact(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    """Exact propagation between time break points and strand switches (see the module note)."""
    N, dt, t_end, m = t.size, t[1] - t[0], t[-1], network.size
    starts = network.segment_starts(t_end)
    ends = starts[1:] + [math.inf]
    z = np.concatenate([x0, network.generators(0.0)])
    sw = _Switches(network, z, cfg, "exact", dt)
    out = np.empty((m, N))
    out[:, 0] = x0
    k, t_cur, on_grid, steps = 0, 0.0, True, 0
    pieces: dict = {}
    skip: tuple = ()          # switching functions that fired at the current point
    eps = 1e-9 * dt

    def switch(piece, found):
        nonlocal z, t_cur, on_grid, skip, k
        tau, e, z = found
        t_cur += tau
        on_grid = False
        before = sw.taut
        sw.switch(piece.events[e].strand, t_cur, z, piece.F, piece.h)
        # a function that fired without a switch must not fire again from the same point
        skip = (skip if tau == 0 else ()) + ((e,) if sw.taut == before else ())
        if k + 1 < N and abs(t_cur - t[k + 1]) <= eps:     # a switch on an output time
            k += 1
            out[:, k] = z[:m]
            t_cur, on_grid = t[k], True

    while k < N - 1:
        seg = network.segment(t_cur + eps, starts)
        t_stop = min(ends[seg], t_end)
        key = (sw.taut, seg)
        piece = pieces.get(key)
        if piece is None:
            piece = pieces[key] = _Piece(network, sw.taut, network.piece_time(seg, starts, t_end), dt)
        q, h = piece.sub, piece.h
        last = min(N - 1, k + max(1, 65536 // q), int(np.searchsorted(t, t_stop + eps, side="right")) - 1)
        if on_grid and last > k:
            # whole output steps inside this time piece, q steps each, all at once
            Z = _orbit(piece.P(0), z, (last - k) * q + 1)
            hit = piece.scan(Z, skip)
            upto = (last - k) * q if hit is None else hit
            for i in range(q, upto + 1, q):
                out[:, k + i // q] = Z[i, :m]
            steps += upto
            k += upto // q
            t_cur = t[k] + (upto % q) * h
            on_grid = upto % q == 0
            z = Z[upto]
            if upto > 0:
                skip = ()
            if hit is None:
                continue
            found = piece.search(z, 0, skip)
            if found is None:                       # a false alarm: take the step as it is
                z, skip = Z[upto + 1], ()
                steps += 1
                t_cur += h
                if (upto + 1) % q == 0:
                    k += 1
                    out[:, k] = z[:m]
                    t_cur, on_grid = t[k], True
                continue
            switch(piece, found)
            continue
        # off the grid (after a switch or a break point): to the next output time or break,
        # in steps h, h/2, h/4, ... and a last remainder
        target = min(t[k + 1], t_stop)
        found = None
        level = 0
        while found is None:
            span = target - t_cur
            if span <= eps:
                break
            while level <= LEVELS and h / 2 ** level > span + eps:
                level += 1
            if level > LEVELS:
                found, zb = piece.search_span(z, span, skip)
                if found is None:
                    z, t_cur = zb, target
                break
            found = piece.search(z, level, skip)
            if found is None:
                z = piece.P(level) @ z
                t_cur += h / 2 ** level
                skip = ()
            steps += 1
        if found is not None:
            switch(piece, found)
            continue
        t_cur = target
        if target == t[k + 1]:
            k += 1
            out[:, k] = z[:m]
            on_grid = True
        else:
            on_grid = False
    return out, steps, 0, sw.info(t_end)


def _exact(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    if not network.linear:
        raise InputError("the exact method needs a network that is linear between switches; this one has "
                         "loads locked to a shaft angle: use --method radau (or auto)", param="method")
    if not network.smooth:
        return _piecewise_exact(network, t, x0, cfg)
    dt = t[1] - t[0]
    F = augmented_matrix(network)
    z0 = np.concatenate([x0, network.generators(0.0)])
    z = _propagate(F, z0, dt, t.size)
    return z[:network.size], t.size - 1, 0, {}


# --- scipy's solvers ----------------------------------------------------------------------------
def _generators(network: Network):
    """A fast g(t) for one time value (the solvers call it at every step)."""
    freqs, ramp = network.frequencies(), network.ramp

    def gen(t):
        out = [1.0, t] if ramp else [1.0]
        for w in freqs:
            out += [math.sin(w * t), math.cos(w * t)]
        return np.array(out)
    return gen


def _system(network: Network, taut, t_mid: float, budget: list[int]):
    """rhs and Jacobian of one strand mode on one time piece."""
    A, B = network.first_order(taut, t_mid)
    nonlinear = not network.linear
    gen = _generators(network)

    def rhs(t, x):
        budget[0] += 1
        if budget[0] > budget[1]:
            raise _Budget(t)
        dx = A @ x + B @ gen(t)
        if nonlinear:
            dx += network.nonlinear_terms(t, x)
        return dx

    def jac(t, x):
        return A + network.nonlinear_jacobian(x) if nonlinear else A

    return rhs, jac


def _ivp(name: str, uses_jac: bool):
    def run(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
        budget = [0, cfg.max_rhs_calls]
        N, m, t_end = t.size, network.size, t[-1]
        eps = 1e-9 * (t[1] - t[0])
        starts = network.segment_starts(t_end)
        ends = starts[1:] + [math.inf]
        x = np.asarray(x0, dtype=float)
        sw = _Switches(network, np.concatenate([x, network.generators(0.0)]), cfg, name.lower(), t[1] - t[0])
        out = np.empty((m, N))
        out[:, 0] = x
        k, t_cur, skip = 0, 0.0, ()
        stats = {"nfev": 0, "njev": 0, "nlu": 0}
        while k < N - 1:
            seg = network.segment(t_cur + eps, starts)
            t_stop = min(ends[seg], t_end)
            mid = network.piece_time(seg, starts, t_end)
            rhs, jac = _system(network, sw.taut, mid, budget)
            events = []
            gen = _generators(network)
            switching = network.events(sw.taut)
            for j, ev in enumerate(switching):
                def fn(tt, xx, row=ev.row, start=t_cur, again=j in skip, sign=ev.direction):
                    value = row[:m] @ xx + row[m:] @ gen(tt)
                    # a function that just fired without a switch restarts past its surface
                    return sign * max(abs(value), 1e-300) if again and tt == start else value
                fn.terminal, fn.direction = True, ev.direction
                events.append(fn)
            last = int(np.searchsorted(t, t_stop + eps, side="right")) - 1
            t_eval = [min(tt, t_stop) for tt in t[k + 1:last + 1]]   # a sample within eps past the break
            if not t_eval or abs(t_eval[-1] - t_stop) > eps:
                t_eval.append(t_stop)
            kwargs = {"jac": jac} if uses_jac else {}
            try:
                sol = solve_ivp(rhs, (t_cur, t_stop), x, method=name, t_eval=t_eval, rtol=cfg.rtol,
                                atol=cfg.atol, events=events or None, **kwargs)
            except _Budget as stop:
                raise SimulationError(_budget_message(name, stop.args[0], cfg)) from None
            for key in stats:
                stats[key] += int(getattr(sol, key))
            if sol.status < 0:
                reached = sol.t[-1] if sol.t.size else t_cur
                raise SimulationError(f"method {name.lower()} failed at t = {reached:.6g} s: {sol.message}; "
                                      "try --method radau or bdf, or looser --rtol/--atol")
            grid = [j for j, tt in enumerate(sol.t) if k + 1 + j <= last and abs(tt - t[k + 1 + j]) <= eps]
            for j in grid:
                out[:, k + 1 + j] = sol.y[:, j]
            k += len(grid)
            if sol.status == 1:
                fired = [(te[0], j) for j, te in enumerate(sol.t_events) if te.size]
                t_e, j = min(fired)
                x = sol.y_events[j][0]
                z = np.concatenate([x, network.generators(t_e)])
                ev = switching[j]
                before = sw.taut
                sw.switch(ev.strand, t_e, z, augmented_matrix(network, sw.taut, mid), t[1] - t[0])
                skip = (skip if t_e == t_cur else ()) + ((j,) if sw.taut == before else ())
                t_cur = t_e
            else:
                t_cur, x, skip = t_stop, sol.y[:, -1], ()
        return out, stats["nfev"], stats["nfev"], {"jacobians": stats["njev"], "lu": stats["nlu"], **sw.info(t_end)}
    return run


def _odeint(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    budget = [0, cfg.max_rhs_calls]
    starts = network.segment_starts(t[-1])
    delta, force = network.strand_rows()
    gen = _generators(network)
    fixed = network.first_order() if network.smooth else None

    def mode(tt, x):
        if fixed is not None:
            return fixed, None
        seg = network.segment(tt, starts)
        mid = network.piece_time(seg, starts, t[-1])
        if not network.strands:
            return network.first_order(None, mid), None
        z = np.concatenate([x, gen(tt)])
        taut = tuple(bool(v) for v in (delta @ z > 0) & (force @ z > 0))
        return network.first_order(taut, mid), taut

    def rhs(tt, x):    # the raw right-hand side: each strand taut or slack by its own state
        budget[0] += 1
        if budget[0] > budget[1]:
            raise _Budget(tt)
        (A, B), _ = mode(tt, x)
        dx = A @ x + B @ gen(tt)
        if not network.linear:
            dx += network.nonlinear_terms(tt, x)
        return dx

    def jac(tt, x):
        (A, _), _ = mode(tt, x)
        return A + network.nonlinear_jacobian(x) if not network.linear else A

    crit = np.array(network.breaks(t[-1]) + [t[-1]])
    try:
        y, info = odeint(rhs, x0, t, Dfun=jac, rtol=cfg.rtol, atol=cfg.atol, full_output=True,
                         tfirst=True, tcrit=crit, mxstep=max(500, cfg.max_rhs_calls // max(t.size, 1)))
    except _Budget as stop:
        raise SimulationError(_budget_message("odeint", stop.args[0], cfg)) from None
    if info["message"] != "Integration successful.":
        reached = float(info["tcur"][-1]) if len(info["tcur"]) else t[0]
        reached = reached if 0 <= reached <= t[-1] else t[0]
        raise SimulationError(f"method odeint failed at t = {reached:.6g} s: {info['message']}; "
                              "try --method radau, or looser --rtol/--atol")
    extra = {"jacobians": int(info["nje"][-1])}
    if network.strands:   # no events: the slack time from the samples
        taut = network.taut_of(y.T, t)
        dt = t[1] - t[0]
        extra["slack_time"] = {s.name: float(np.sum(~taut[k][1:]) * dt) for k, s in enumerate(network.strands)}
        extra["events"] = int(np.sum(np.diff(taut.astype(int), axis=1) != 0))
    return y.T, int(info["nst"][-1]), int(info["nfe"][-1]), extra


def _budget_message(method: str, reached: float, cfg: SolverConfig) -> str:
    return (f"method {method.lower()} stopped at t = {reached:.6g} s after {cfg.max_rhs_calls} right-hand-side "
            "calls (the system is stiff for an explicit method, or switches too often?); try --method exact, "
            "radau or bdf")


METHODS = {
    "exact": _exact,
    "radau": _ivp("Radau", True),
    "bdf": _ivp("BDF", True),
    "lsoda": _ivp("LSODA", True),
    "odeint": _odeint,
    "rk45": _ivp("RK45", False),
    "dop853": _ivp("DOP853", False),
}


def choose_method(network: Network, requested: str) -> tuple[str, str]:
    """The method to run and why."""
    if requested == "auto":
        if network.linear and network.smooth:
            return "exact", "auto: the network is linear with inputs in time, so its exact solution is used"
        if network.linear:
            return "exact", ("auto: the network is linear between strand switches and time break points, so it "
                             "is propagated exactly and each switch is located on the exact solution")
        return "radau", ("auto: loads locked to a shaft angle make the network nonlinear; implicit Radau with the "
                         "analytic Jacobian")
    if requested not in METHODS:
        raise InputError(f"{requested!r} is not a method; use one of auto, {', '.join(METHODS)}", param="method")
    return requested, "requested"


def simulate(network: Network, t_end: float, samples: int, cfg: SolverConfig = SolverConfig(),
             x0: np.ndarray | None = None) -> SimResult:
    """Integrate ``network`` from ``x0`` (rest by default) over [0, t_end] at ``samples`` points.

    The only function that integrates; every scene calls it.
    """
    require_positive("t_end", t_end, "s")
    if samples < 2:
        raise InputError(f"{samples} samples; at least 2 are needed", param="samples")
    method, reason = choose_method(network, cfg.method)
    x0 = _initial(network, x0)
    t = np.linspace(0.0, t_end, samples)
    start = time.perf_counter()
    x, steps, calls, extra = METHODS[method](network, t, x0, cfg)
    wall = time.perf_counter() - start
    if not np.all(np.isfinite(x)):
        raise SimulationError(f"method {method} gave non-finite values; try another --method")
    result = _outputs(network, t, x, method, reason, wall, steps, calls, extra)
    if cfg.estimate_error:
        _estimate_error(result, network, t_end, samples, cfg, x0, method)
    return result


def _estimate_error(result: SimResult, network: Network, t_end, samples, cfg, x0, method) -> None:
    n = network.n
    speeds = result.states[n:2 * n]
    if method == "exact":
        fine = METHODS["exact"](network, np.linspace(0.0, t_end, 2 * samples - 1), x0, cfg)[0]
        ref, label = fine[n:2 * n, ::2], "exact run at half the step"
    elif network.linear:
        ref = METHODS["exact"](network, result.t, x0, cfg)[0][n:2 * n]
        label = "exact solution"
    else:
        tight = SolverConfig("radau", cfg.rtol / 100, cfg.atol / 100, cfg.max_rhs_calls, cfg.max_events, False)
        ref = METHODS["radau"](network, result.t, x0, tight)[0][n:2 * n]
        label = "radau at 1/100 of the tolerances"
    result.error_estimate = float(np.max(np.abs(speeds - ref)))
    result.error_reference = label


def _outputs(network: Network, t, x, method, reason, wall, steps, calls, extra) -> SimResult:
    n = network.n
    signals, units = {}, {}
    for (name, unit), row in zip(network.state_names(), x):
        signals[name], units[name] = row, unit
    dx = network.derivative(t, x)
    for k, (name, unit) in enumerate(network.accel_names()):
        signals[name], units[name] = dx[n + k], unit
    def unit(node):   # the generalised force on a node: a force on a translating one
        return "N" if network.nodes[network.index[node]].translation else "N m"

    for c, (name, torque) in zip(network.couplings, network.coupling_torques(x).items()):
        signals[f"T_{name}"], units[f"T_{name}"] = torque, unit(c.i)
    for name, force in network.strand_forces(t, x).items():
        signals[f"F_{name}"], units[f"F_{name}"] = force, "N"
    for node, torque in network.load_torques(t, x).items():
        signals[f"load_{node}"], units[f"load_{node}"] = np.broadcast_to(torque, t.shape).copy(), unit(node)
    for node, torque in network.drive_torques(t, x, dx).items():
        signals[f"T_drive_{node}"], units[f"T_drive_{node}"] = np.broadcast_to(torque, t.shape).copy(), unit(node)
    return SimResult(t=t, signals=signals, units=units, method=method, reason=reason, wall_time=wall,
                     steps=steps, rhs_calls=calls, states=x, extra=extra)
