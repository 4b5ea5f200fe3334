"""Independent references for tests/test_hard_cases_cli.py, written once and stored here.

Run from the repository root (each case says its cost; hours in all on two busy cores):

    python tests/reference/make_references.py [roller3 roller0 pulse stiff sewing_ecc]

Nothing of beltcalc is imported: the equations are written out below from the drive's
components and integrated by scipy's ``solve_ivp(method="Radau")`` (the constant Jacobian of
each strand pattern for the linear drives), and the tension-only strands are switched by
terminal events written here. Every case is run at two tolerances (rtol 1e-11 and 1e-10 for
the roller table); the stored value is the finer one and ``referr`` the difference of the two
(the reference's own error, an overestimate: the coarser run's error).

Drives are read from their drive files as *data* (inertias, stiffnesses, dampings, lengths,
teeth, loads): ``catalogs/drives/roller_table.toml`` (the scene ``beltcalc simulate
roller-table`` at its default three rollers; the test checks that the CLI echoes the same
scene values), ``tests/reference/stiff.toml``, ``catalogs/drives/sewing.toml``. They are
assembled here by Lagrange with Rayleigh dissipation (Rusek & Popenda eq. 8-11; Mamatova et
al. 2016 eq. 2-7):

* node k: inertia J_k (+ m L r_k^2 / 2 of every chain strand it holds, m = 0.91 kg/m for
  10B-1, SOURCED_DATA.md; sprocket pitch radius r = p / (2 sin(pi / z)), p = 15.875 mm,
  ISO 606 table 1);
* coupling (i, j, U): torque T = C (phi_i - U phi_j) + d (omega_i - U omega_j), -T on i,
  +U T on j (d = damping_time x C where the file gives a damping time);
* chain strand i -> j: c = EA / L, b = damping_time x c,
  delta = r_i phi_i - r_j phi_j + F0 / c, taut force F = c delta + b delta', -F r_i on i,
  +F r_j on j; taut while delta > 0 and F > 0;
* induction motor (Mamatova et al. 2016, eq. 2) on its node:
  M' = 2 M_c w_c / w_0 (w_s(t) - omega) - w_c S_c M, w_s rising linearly from 0 to
  w_0 = 2 pi f / p over the ramp, M_c = breakdown_factor x rated torque, w_c = 2 pi f;
* loads against the motion: mean + amplitude sin(w t) from ``start`` + the table (a jump).

Coordinates are relative: the motor's angle and the deflections theta of a spanning tree
of the elements, with their rates (phi = rho phi_motor + T theta, rho the rigid rotation),
so that a stiff element's twist is a state of its own with an absolute tolerance of its own
(rtol x 1 N m / C: 5e-20 rad for the 2e9 N m/rad coupling at rtol 1e-10) and no deflection
rate is the difference of two large speeds. Quadratures of theta and M give window means
exactly: the window start and end are step points.

Switching (docs/switching.md states the same rules): a taut strand fires when F falls
through 0 (-> slack); a slack strand fires when min(delta, F / c) rises through 0
(-> taut: at take-up delta = 0 the force jumps to b delta'). An event is located by
solve_ivp on the step's interpolant, then refined by one Newton step on the state
re-integrated from the segment's start (the interpolant of Radau IIA is of lower order
than its steps: no stored value is read off it). Every output time is a step point: the
integration stops there. Extremes are located on the interpolant between samples and then
evaluated by integrating to that time from the segment's start.

The sewing drive with the eccentric tension roller (docs/eccentric_roller.md: the belt path
of three circles, E1-E3; the spans' forces from the potential, E4-E7) is nonlinear: Radau
with scipy's finite-difference Jacobian, through every output time.

scipy's Radau can end a piece with a step of a few ulps that it then rejects below its
minimum ("required step size is less than spacing between numbers"); those last ulps are
taken by one Euler step (``Hybrid._solve``). The stiff drive uses rtol 1e-10 and 1e-9: at
1e-11 Radau stopped so before that step was added, and took minutes per 0.3 s (an earlier
reference of the same drive in absolute speeds at rtol 1e-12 agreed with the 1e-10 one to
1.4e-8 N m on the stiff coupling's torque).
"""

from __future__ import annotations

import json
import math
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CHAIN_PITCH, CHAIN_MASS = 0.015875, 0.91      # 10B-1: ISO 606 table 1; mass SOURCED_DATA.md


UNITS = {"": 1.0, "kg*m^2": 1.0, "N*m/rad": 1.0, "N*m*s/rad": 1.0, "m": 1.0, "N": 1.0, "s": 1.0,
         "N*m": 1.0, "rad/s": 1.0, "rad": 1.0, "Hz": 1.0, "W": 1.0, "kW": 1e3, "rpm": 2 * math.pi / 60}


def si(text) -> float:
    """The SI number of a drive file's quantity text (``"0.004 kg*m^2"``, ``"15 kW"``,
    ``"1470 rpm"``; Hz stays Hz and is turned into rad/s where used). Only the units these
    drives use are known; any other is an error."""
    number, _, unit = str(text).strip().partition(" ")
    return float(number) * UNITS[unit.strip()]


# --------------------------------------------------------------------------------------------
# the drive: matrices from its components
# --------------------------------------------------------------------------------------------
class Drive:
    """A drive of inertias, couplings, tension-only strands, one induction motor and loads.

    Coordinates: the motor's angle phi_m and the deflections theta of a spanning tree of the
    elements (every coupling's phi_i - U phi_j, every tree strand's r_i phi_i - r_j phi_j),
    so that phi = rho phi_m + T theta (rho the rigid rotation, T from the tree) and a
    stiff element's deflection is a state of its own, with an absolute tolerance of its own
    (rtol x 1 N m / C); the speeds likewise (omega = rho omega_m + T theta': a deflection's
    rate is never the difference of two large speeds). State
    y = [phi_m, theta (n-1), omega_m, theta' (n-1), M, int theta (n-1), int M]."""

    def __init__(self, data: dict):
        nodes = data["node"]
        self.names = [nd["name"] for nd in nodes]
        n = self.n = len(nodes)
        ix = self.ix = {name: k for k, name in enumerate(self.names)}
        J = np.array([si(nd["inertia"]) for nd in nodes])
        radius = {}
        for nd in nodes:
            if "teeth" in nd:
                assert nd["chain"] == "10B-1"
                radius[nd["name"]] = CHAIN_PITCH / (2 * math.sin(math.pi / nd["teeth"]))
        # elements: (name, strand?, g, C or c, d or b, F0, (i, j, U) with phi_i = U phi_j at rest)
        self.elements = []
        for c in data.get("coupling", []):
            i, j = (ix[x] for x in c["between"])
            U = float(c.get("ratio", 1.0))
            C = si(c["stiffness"])
            d = si(c["damping"]) if "damping" in c else si(c.get("damping_time", "0 s")) * C
            g = np.zeros(n)
            g[i] += 1.0
            g[j] -= U
            self.elements.append((c["name"], False, g, C, d, 0.0, (i, j, U)))
        self.strands = []
        for s in data.get("chain_strand", []):
            a, b = s["from"], s["to"]
            L = si(s["length"])
            c = si(s["stiffness"]) / L
            g = np.zeros(n)
            g[ix[a]] += radius[a]
            g[ix[b]] -= radius[b]
            F0 = si(s.get("pretension", "0 N"))
            self.elements.append((s["name"], True, g, c, si(s.get("damping_time", "0 s")) * c, F0,
                                  (ix[a], ix[b], radius[b] / radius[a])))
            self.strands.append(s["name"])
            J[ix[a]] += CHAIN_MASS * L * radius[a] ** 2 / 2        # half the strand's mass to each end
            J[ix[b]] += CHAIN_MASS * L * radius[b] ** 2 / 2
        self.J = J
        (m,) = data["motor"]
        self.motor = ix[m["node"]]
        f = si(m["supply"])
        torque = si(m["rated_torque"]) if "rated_torque" in m else si(m["rated_power"]) / si(m["rated_speed"])
        self.Mc = float(m["breakdown_factor"]) * torque
        self.Sc = float(m["breakdown_slip"])
        self.wc = 2 * math.pi * f
        self.w0 = self.wc / int(m.get("pole_pairs", 1))
        self.ramp = si(m.get("ramp", "0 s"))
        self.gain = 2 * self.Mc * self.wc / self.w0
        self.loads = []
        for ld in data.get("load", []):
            table = [(si(t), si(v)) for t, v in ld.get("table", [])]
            freq = si(ld.get("frequency", "0 rad/s"))
            if str(ld.get("frequency", "")).endswith("Hz"):
                freq *= 2 * math.pi
            self.loads.append((ix[ld["node"]], si(ld.get("torque", "0 N*m")), si(ld.get("amplitude", "0 N*m")),
                               freq, si(ld.get("phase", "0 rad")), si(ld.get("start", "0 s")), table))
        # the rigid rotation and a spanning tree, from the motor
        rho = np.full(n, np.nan)
        rho[self.motor] = 1.0
        tree = []
        grown = True
        while grown:
            grown = False
            for e, (_, _, _, _, _, _, (i, j, U)) in enumerate(self.elements):
                if np.isnan(rho[j]) and not np.isnan(rho[i]):
                    rho[j] = rho[i] / U
                elif np.isnan(rho[i]) and not np.isnan(rho[j]):
                    rho[i] = rho[j] * U
                else:
                    continue
                tree.append(e)
                grown = True
        assert not np.isnan(rho).any() and len(tree) == n - 1
        self.rho, self.tree = rho, tree
        others = [k for k in range(n) if k != self.motor]
        Gt = np.array([self.elements[e][2] for e in tree])
        T = np.zeros((n, n - 1))
        T[others] = np.linalg.inv(Gt[:, others])
        self.T, self.Gt = T, Gt
        # each element's deflection as a row over theta (a tree element's: exactly its own theta)
        self.h = []
        for e, el in enumerate(self.elements):
            if e in tree:
                h = np.zeros(n - 1)
                h[tree.index(e)] = 1.0
            else:
                h = el[2] @ T
            assert abs(el[2] @ rho) <= 1e-15 * np.abs(el[2]).max()
            self.h.append(h)
        self.strand_ix = [e for e, el in enumerate(self.elements) if el[1]]
        # the strands' rows and constants as arrays (one product per call, not one per strand:
        # at 30 rollers each of 122 events computed every strand's force in a Python loop)
        self.Hs = np.array([self.h[e] for e in self.strand_ix]).reshape(len(self.strand_ix), n - 1)
        self.cs = np.array([self.elements[e][3] for e in self.strand_ix])
        self.bs = np.array([self.elements[e][4] for e in self.strand_ix])
        self.F0s = np.array([self.elements[e][5] for e in self.strand_ix])
        self.P = np.vstack([np.eye(n)[self.motor], self.Gt]) / J[None, :]     # rows: omega_m', theta''
        self._pre, self._last = {}, (None, None)
        self.size = 3 * n + 1
        # absolute tolerances per state, as multiples of rtol: 1 N m (1 N) of each tree element
        # and that times the fastest mode's angular frequency for each tree element's rate
        inv = np.array([1.0 / self.elements[e][3] for e in tree])
        fast = float(np.abs(np.linalg.eigvals(self.matrix(np.ones(len(self.strand_ix), bool)))).max())
        self.atol_scale = np.concatenate([[1.0], inv, [1.0], fast * inv, [1.0], inv, [1.0]])

    # --- slices of the state [phi_m, theta, omega_m, theta', M, int theta, int M]
    @property
    def i_th(self):
        return slice(1, self.n)

    @property
    def i_wm(self):
        return self.n

    @property
    def i_thd(self):
        return slice(self.n + 1, 2 * self.n)

    @property
    def i_M(self):
        return 2 * self.n

    @property
    def i_Q(self):
        return slice(2 * self.n + 1, 3 * self.n)

    @property
    def i_QM(self):
        return 3 * self.n

    def phi(self, y):
        """Absolute angles [rad]."""
        return self.rho * y[0] + self.T @ y[self.i_th]

    def omega(self, y):
        """Absolute speeds [rad/s]: rho omega_m + T theta'."""
        return self.rho * y[self.i_wm] + self.T @ y[self.i_thd]

    def breaks(self, t_end):
        out = {self.ramp} if self.ramp else set()
        for node, mean, amp, w, ph, start, table in self.loads:
            if amp and start:
                out.add(start)
            out.update(t for t, _ in table)
        return sorted(b for b in out if 0 < b < t_end)

    def sync(self, t):
        if not self.ramp:
            return self.w0
        return self.w0 * min(t / self.ramp, 1.0)

    def load(self, t):
        """Load torques on the nodes at t [N m] (against the motion). The caller passes a
        time inside the piece: a table's jump is never integrated over."""
        out = np.zeros(self.n)
        for node, mean, amp, w, ph, start, table in self.loads:
            v = mean
            if amp and t >= start:
                v += amp * math.sin(w * t + ph)
            if table:
                ts = [p[0] for p in table]
                vs = [p[1] for p in table]
                k = int(np.searchsorted(ts, t, side="right")) - 1
                if k < 0:
                    v += vs[0]
                elif k >= len(ts) - 1:
                    v += vs[-1]
                else:
                    v += vs[k] + (vs[k + 1] - vs[k]) * (t - ts[k]) / (ts[k + 1] - ts[k])
            out[node] += v
        return out

    def matrix(self, taut):
        """y' = A y + f(t) in a strand pattern (A: the constant Jacobian). With q = rho phi_m +
        T theta the coordinates' accelerations are q'' = f / J (f the nodes' torques), so
        omega_m' = f_m / J_m and theta'' = G_tree q''."""
        n, N = self.n, self.size
        A = np.zeros((N, N))
        th, thd = self.i_th, self.i_thd
        A[0, self.i_wm] = 1.0
        A[th, thd] = np.eye(n - 1)
        Kt = np.zeros((n, n - 1))          # torques on the nodes from theta and from theta'
        Dt = np.zeros((n, n - 1))
        k = 0
        for e, (_, strand, g, C, d, F0, _) in enumerate(self.elements):
            if strand:
                on = taut[k]
                k += 1
                if not on:
                    continue
            Kt -= C * np.outer(g, self.h[e])
            Dt -= d * np.outer(g, self.h[e])
        # q'' = (Kt theta + Dt theta' + e_m M + forcing) / J
        P = np.vstack([np.eye(n)[self.motor], self.Gt]) / self.J[None, :]      # rows: omega_m', theta''
        rows = np.r_[self.i_wm, np.arange(n + 1, 2 * n)]
        A[np.ix_(rows, np.arange(1, n))] = P @ Kt
        A[np.ix_(rows, np.arange(n + 1, 2 * n))] = P @ Dt
        A[rows, self.i_M] = P[:, self.motor]
        A[self.i_M, self.i_wm] = -self.gain
        A[self.i_M, self.i_M] = -self.wc * self.Sc
        A[self.i_Q, th] = np.eye(n - 1)
        A[self.i_QM, self.i_M] = 1.0
        return A

    def forcing(self, t, taut):
        n = self.n
        f = np.zeros(self.size)
        key = tuple(bool(x) for x in taut)
        if key not in self._pre:             # the taut strands' pretensions on the nodes
            q = np.zeros(n)
            for k, e in enumerate(self.strand_ix):
                if taut[k]:
                    q -= self.elements[e][2] * self.elements[e][5]
            self._pre[key] = q
        q = self._pre[key] - self.load(t)
        f[np.r_[self.i_wm, np.arange(n + 1, 2 * n)]] = self.P @ q
        f[self.i_M] = self.gain * self.sync(t)
        return f

    def forces(self, y):
        """Per strand: elongation delta [m], its rate [m/s], the taut-mode force c delta + b delta' [N]."""
        if not self.strand_ix:
            return np.zeros((3, 0))
        y = np.asarray(y, float)
        key = y.tobytes()
        if self._last[0] == key:             # solve_ivp asks every event at the same state
            return self._last[1]
        th, thd = y[self.i_th], y[self.i_thd]
        hth, rate = self.Hs @ th, self.Hs @ thd
        out = np.array([hth + self.F0s / self.cs, rate, self.cs * hth + self.F0s + self.bs * rate])
        self._last = (key, out)
        return out

    def force_rate(self, j, yd):
        """d/dt of strand j's taut force from y' (its theta' and theta'' rows)."""
        e = self.strand_ix[j]
        return self.elements[e][3] * (self.h[e] @ yd[self.i_th]) + self.elements[e][4] * (self.h[e] @ yd[self.i_thd])

    def couplings(self):
        """(name, row over theta (and theta'), C, d) of every coupling: T = C h.theta + d h.theta'."""
        return [(nm, self.h[e], C, d) for e, (nm, strand, g, C, d, _, _) in enumerate(self.elements) if not strand]

    @property
    def c(self):
        return np.array([self.elements[e][3] for e in self.strand_ix])


# --------------------------------------------------------------------------------------------
# hybrid integration
# --------------------------------------------------------------------------------------------
class Hybrid:
    """Radau with terminal strand events; ``stops`` (output times, break points) are step
    points. ``segments``: (t_a, t_b, taut, y_a, interpolant) with y_a exact."""

    def __init__(self, drive: Drive, rtol: float, t_end: float, stops, taut0=None):
        self.d, self.rtol, self.t_end = drive, rtol, t_end
        self.atol = rtol * drive.atol_scale
        stops = np.unique(np.concatenate([np.asarray(stops, float), drive.breaks(t_end), [t_end]]))
        keep = np.concatenate([[True], np.diff(stops) > 1e-9])     # linspace's 1.5000000000000002 is 1.5
        self.stops = stops[keep]
        self.taut = np.ones(len(drive.strands), bool) if taut0 is None else np.array(taut0, bool)
        self.segments, self.switches = [], []
        self.mats = {}

    def A(self, taut):
        key = tuple(bool(x) for x in taut)
        if key not in self.mats:
            self.mats[key] = self.d.matrix(np.array(key))
        return self.mats[key]

    def _solve(self, t0, t1, y0, taut, events=(), dense=False):
        A = self.A(taut)
        d = self.d
        brk = d.breaks(self.t_end)
        def rhs(t, y):
            # the table's value of the piece (a jump at a stop takes the side of the segment)
            f = d.forcing(t if not brk else _inside(t, t0, t1), taut)
            return A @ y + f
        sol = solve_ivp(rhs, (t0, t1), y0, method="Radau", jac=A, rtol=self.rtol, atol=self.atol,
                        events=list(events), dense_output=dense)
        gap = t1 - sol.t[-1]
        if sol.status == -1 and 0 < gap <= 1e-9 * max(1.0, abs(t1)):
            # scipy's Radau clips its last step to the end and, when only a few ulps are left,
            # can reject that step down below its minimum ("required step size is less than
            # spacing between numbers": a Newton rate of 0/0); the last ulps by one Euler step
            sol.y = np.column_stack([sol.y, sol.y[:, -1] + gap * rhs(sol.t[-1], sol.y[:, -1])])
            sol.t = np.append(sol.t, t1)
            sol.status, sol.message = 0, "ended by an Euler step over the last ulps"
        return sol

    def _events(self, taut):
        d = self.d
        evs = []
        for k in range(len(d.strands)):
            if taut[k]:
                def ev(t, y, k=k):
                    return d.forces(y)[2][k]
                ev.direction = -1
            else:
                def ev(t, y, k=k):
                    delta, _, F = d.forces(y)
                    return min(delta[k], F[k] / d.c[k])
                ev.direction = 1
            ev.terminal = True
            evs.append(ev)
        return evs

    def run(self, y0, log_every=0.5):
        t, y = 0.0, np.asarray(y0, float)
        k_stop = 0
        same_time = 0
        t_log = 0.0
        wall = time.time()
        while t < self.t_end:
            while self.stops[k_stop] <= t:
                k_stop += 1
            t1 = self.stops[k_stop]
            taut = self.taut.copy()
            sol = self._solve(t, t1, y, taut, self._events(taut), dense=True)
            assert sol.status >= 0, (sol.message, t, t1, sol.t[-3:], self.taut)
            if sol.status == 1:
                hits = [(te[0], j) for j, te in enumerate(sol.t_events) if te.size]
                te, j = min(hits)
                ev = self._events(taut)[j]
                # refine: the state at te from the segment's exact start, one Newton step on g
                ye = self._solve(t, te, y, taut).y[:, -1] if te > t else y.copy()
                g = ev(te, ye)
                gd = self._event_rate(j, taut, te, ye)
                if gd != 0 and te > t:
                    te2 = min(max(te - g / gd, t), t1)
                    ye = self._solve(t, te2, y, taut).y[:, -1] if te2 > t else y.copy()
                    te = te2
                self.segments.append((t, te, taut, y.copy(), sol.sol))
                self.taut[j] = not taut[j]
                self.switches.append((te, self.d.strands[j], bool(self.taut[j])))
                same_time = same_time + 1 if te == t else 0
                assert same_time < 50, "switches without progress"
                t, y = te, ye
            else:
                self.segments.append((t, t1, taut, y.copy(), sol.sol))
                t, y = t1, sol.y[:, -1]
            if log_every and t >= t_log:
                print(f"  t = {t:.3f} s, {len(self.switches)} switches, {time.time() - wall:.0f} s", flush=True)
                t_log += log_every
        self.y_end = y
        return self

    def _event_rate(self, j, taut, t, y):
        """d/dt of event function j at (t, y) in the segment's pattern."""
        d = self.d
        yd = self.A(taut) @ y + d.forcing(t, taut)
        delta, rate, F = d.forces(y)
        Fd = d.force_rate(j, yd)
        if taut[j]:
            return Fd
        return rate[j] if delta[j] <= F[j] / d.c[j] else Fd / d.c[j]

    # --- reading the solution
    def state_at(self, t):
        """The exact state at t: integrated from the start of its segment."""
        self.dense(t)
        k = max(int(np.searchsorted(self._starts, t, side="right")) - 1, 0)
        ta, tb, taut, ya, _ = self.segments[k]
        assert ta <= t <= tb
        return ya.copy() if t == ta else self._solve(ta, t, ya, taut).y[:, -1]

    def states_at_stops(self, times):
        """Exact states at output times that are stops (segment ends)."""
        starts = np.array([sg[0] for sg in self.segments] + [self.segments[-1][1]])
        ys = [sg[3] for sg in self.segments] + [self.y_end]
        out = []
        for t in times:
            k = int(np.argmin(np.abs(starts - t)))
            assert abs(starts[k] - t) <= 1e-9, t
            while k > 0 and starts[k - 1] == starts[k]:     # switches at a stop: the state before them
                k -= 1
            out.append(ys[k])
        return np.array(out).T

    def dense(self, t):
        if not hasattr(self, "_starts") or len(self._starts) != len(self.segments):
            self._starts = np.array([sg[0] for sg in self.segments])
        k = max(int(np.searchsorted(self._starts, t, side="right")) - 1, 0)
        return self.segments[k][4](t)

    def extreme(self, signal, times, values, sign, lo=-np.inf, hi=np.inf):
        """The largest of sign x signal(t) over [lo, hi]. Every sampled local peak within reach
        of the best sample (the largest |second difference| of the samples) is searched between
        its neighbouring samples: 64 points on the interpolant, then each local peak of those
        refined by Brent's method on the interpolant and evaluated exactly there (two peaks
        can lie between two samples: the pulsating roller's speed has two 0.4 ms apart)."""
        m = (times >= lo) & (times <= hi)
        tt, vv = times[m], sign * values[m]
        best = int(np.argmax(vv))
        d2 = np.abs(np.diff(vv, 2)).max() if vv.size > 2 else 0.0
        # every sample within reach, not only the samples' local peaks: a peak between two samples
        # may sit beside a sampled local peak, outside the two intervals around it (the pulsating
        # roller's speed peaks at 3.50291 s between samples 3.502 and 3.503 s, while its samples
        # peak elsewhere: the first version of this search missed it by 3.4e-4 rad/s)
        cands = [k for k in range(vv.size) if vv[k] >= vv[best] - 2 * d2]
        out = vv[best]
        f = lambda s: sign * signal(self.dense(s))
        found = []                 # (value on the interpolant, time) of every refined local peak
        for k in cands:
            a, b = tt[max(k - 1, 0)], tt[min(k + 1, vv.size - 1)]
            if a == b:
                continue
            grid = np.linspace(a, b, 65)
            g = np.array([f(s) for s in grid])
            peaks = [j for j in range(65) if (j == 0 or g[j] >= g[j - 1]) and (j == 64 or g[j] >= g[j + 1])]
            for j in sorted(peaks, key=lambda j: -g[j])[:3]:
                lo_, hi_ = grid[max(j - 1, 0)], grid[min(j + 1, 64)]
                r = minimize_scalar(lambda s: -f(s), bounds=(lo_, hi_), method="bounded",
                                    options={"xatol": 1e-13 * max(1.0, b)})
                found += [(-float(r.fun), float(r.x)), (float(g[j]), float(grid[j]))]
        # the interpolant ranks the peaks (its error is far below the gaps between them); the
        # best few are evaluated on states re-integrated to their times (no value is read off it)
        for _, s in sorted(set(found), reverse=True)[:EXACT_PEAKS]:
            out = max(out, sign * signal(self.state_at(s)))
        return sign * out


EXACT_PEAKS = 6     # the interpolant's best peaks of a signal evaluated exactly


def _inside(t, t0, t1):
    """A time of the open segment (t0, t1) for the inputs: a table jump at t0 or t1 takes the
    segment's own side."""
    eps = 1e-12 * max(1.0, abs(t1))
    return min(max(t, t0 + eps), t1 - eps) if t1 - t0 > 2 * eps else 0.5 * (t0 + t1)


# --------------------------------------------------------------------------------------------
# cases
# --------------------------------------------------------------------------------------------
def roller_drive(pretension=None, amplitude=0.0, frequency=0.0):
    data = tomllib.loads((ROOT / "catalogs/drives/roller_table.toml").read_text())
    for s in data["chain_strand"]:
        if pretension is not None:
            s["pretension"] = f"{pretension} N"
    for ld in data["load"]:
        share = si(ld["table"][-1][1]) / 40.0               # the load's share of the 40 N m roller load
        ld["amplitude"] = f"{share * amplitude} N*m"
        ld["frequency"] = f"{frequency} rad/s"
    return Drive(data)


def drive_case(name, drive, t_end, window, samples, rtols=(1e-11, 1e-10), extremes=None):
    """Window means (exact, from the quadratures), extremes (over the window and over the
    run) and sampled signals of a drive, at two tolerances. ``extremes``: the signals whose
    extremes are located (default every one; each costs re-integrations from its segment's
    start, 40 minutes for all 240 signals of 30 rollers)."""
    times = np.linspace(0.0, t_end, samples)
    out = {}
    n = drive.n
    sig = {}
    for k, node in enumerate(drive.names):
        sig[f"omega_{node}"] = (lambda y, k=k: drive.rho[k] * y[drive.i_wm] + drive.T[k] @ y[drive.i_thd])
    for nm, h_, C, d in drive.couplings():
        sig[f"T_{nm}"] = (lambda y, h_=h_, C=C, d=d: C * (h_ @ y[drive.i_th]) + d * (h_ @ y[drive.i_thd]))
    sig["M_motor"] = lambda y: y[drive.i_M]
    for rtol in rtols:
        print(f"{name}: rtol {rtol:g}", flush=True)
        wall = time.time()
        h = Hybrid(drive, rtol, t_end, np.concatenate([times, [window]]))
        h.run(np.zeros(drive.size))
        Y = h.states_at_stops(times)
        ya, yb = h.states_at_stops([window])[:, 0], h.y_end
        Tw = t_end - window
        res = {"wall_s": time.time() - wall, "switches": len(h.switches)}
        phi_a, phi_b = drive.phi(ya), drive.phi(yb)
        for k, node in enumerate(drive.names):
            res[f"mean_omega_{node}"] = (phi_b[k] - phi_a[k]) / Tw
        dQ, dth = yb[drive.i_Q] - ya[drive.i_Q], yb[drive.i_th] - ya[drive.i_th]
        for nm, h_, C, d in drive.couplings():
            res[f"mean_T_{nm}"] = (C * (h_ @ dQ) + d * (h_ @ dth)) / Tw
        res["mean_M_motor"] = (yb[drive.i_QM] - ya[drive.i_QM]) / Tw
        series = {key: np.array([f(Y[:, i]) for i in range(Y.shape[1])]) for key, f in sig.items()}
        # strand forces: the mode at each sample from the segments (a slack strand has none)
        modes = _modes_at(h, times)
        for j, s in enumerate(drive.strands):
            F = np.array([drive.forces(Y[:, i])[2][j] for i in range(Y.shape[1])])
            series[f"F_{s}"] = np.where(modes[:, j], F, 0.0)
        for key, v in series.items():
            if extremes is not None and key not in extremes:
                continue
            if key.startswith("F_"):
                j = drive.strands.index(key[2:])
                fmax = lambda y, j=j: drive.forces(y)[2][j]
                res[f"max_{key}"] = h.extreme(fmax, times, v, +1)
                res[f"min_{key}"] = float(v.min())        # 0 once slack; else refined below
                if v.min() > 0:
                    res[f"min_{key}"] = h.extreme(fmax, times, v, -1)
                continue
            f = sig[key]
            res[f"max_{key}"] = h.extreme(f, times, v, +1, lo=window)
            res[f"min_{key}"] = h.extreme(f, times, v, -1, lo=window)
            res[f"runmax_{key}"] = h.extreme(f, times, v, +1)
            res[f"runmin_{key}"] = h.extreme(f, times, v, -1)
        res["switch_times"] = [t for t, _, _ in h.switches]
        res["switch_names"] = [f"{s}:{int(on)}" for _, s, on in h.switches]
        out[rtol] = (res, series)
        print(f"{name}: rtol {rtol:g}: {len(h.switches)} switches, {time.time() - wall:.0f} s", flush=True)
    return times, out


def _modes_at(h, times):
    """The strand pattern at each time (the segment that ends there: its left limit, where a
    switch falls exactly on a sample the taut value is its limit, zero force)."""
    modes = np.zeros((len(times), len(h.d.strands)), bool)
    k = 0
    for i, t in enumerate(times):
        while k < len(h.segments) - 1 and h.segments[k][1] < t:
            k += 1
        modes[i] = h.segments[k][2]
    return modes


def save_case(name, times, out, every, meta):
    (fine, coarse) = sorted(out)
    res, series = out[fine]
    res10, series10 = out[coarse]
    meta = dict(meta, rtol=fine, rtol_referr=coarse)
    keep = slice(None, None, every)
    arrays = {"t": times[keep]}
    for key, v in series.items():
        arrays[key] = v[keep]
        arrays[key + "_referr"] = np.abs(v[keep] - series10[key][keep])
    np.savez_compressed(HERE / f"{name}.npz", **arrays)
    scalars = {}
    for key, v in res.items():
        if isinstance(v, list) or key in ("wall_s", "switches"):
            continue
        scalars[key] = {"value": v, "referr": abs(v - res10[key])}
    doc = {"case": name, "meta": meta, "switches": res["switches"], "switches_coarse": res10["switches"],
           "wall_s": {"fine": res["wall_s"], "coarse": res10["wall_s"]},
           "values": scalars, "switch_times": res["switch_times"], "switch_names": res["switch_names"]}
    (HERE / f"{name}.json").write_text(json.dumps(doc, indent=1) + "\n")


CASES = {}


def case(f):
    CASES[f.__name__] = f
    return f


@case
def roller3():
    """Default roller table, 3 rollers, 300 N: 7 s, window 5.5 s, 7001 samples."""
    times, out = drive_case("roller3", roller_drive(), 7.0, 5.5, 7001)
    save_case("roller3", times, out, 10, {"rollers": 3, "pretension_N": 300.0, "t_end_s": 7.0,
                                                   "window_s": 5.5, "samples": 7001})


@case
def roller30():
    """30 rollers sharing the three rollers' load (4 N m each; roller30.toml, as the scene
    builds it): 2 s, the load at 0.6 s, window 1.2 s, 2001 samples."""
    drive = Drive(tomllib.loads((HERE / "roller30.toml").read_text()))
    # extremes only of what the scene reports (the rollers' drive-end speeds and torques, the
    # motor, every strand): the other 180 signals' would take 40 minutes more
    reported = ["omega_motor", "M_motor"] + [f"F_{s}" for s in drive.strands]
    reported += [f"{x}{k}" for k in range(1, 31) for x in ("omega_end", "T_shaft", "T_tube")]
    reported = [x + "a" if x.startswith("omega_end") else x for x in reported]
    times, out = drive_case("roller30", drive, 2.0, 1.2, 2001, extremes=set(reported))
    save_case("roller30", times, out, 4, {"rollers": 30, "roller_load_N_m": 4.0, "load_start_s": 0.6,
                                          "t_end_s": 2.0, "window_s": 1.2, "samples": 2001})


@case
def roller0():
    """Zero pretension, 3 rollers: 9 s, window 7.5 s (the load step's transient decays)."""
    times, out = drive_case("roller0", roller_drive(pretension=0.0), 9.0, 7.5, 9001)
    save_case("roller0", times, out, 10, {"rollers": 3, "pretension_N": 0.0, "t_end_s": 9.0,
                                                   "window_s": 7.5, "samples": 9001})


@case
def pulse():
    """A pulsating roller load (70 N m amplitude per roller, 50 rad/s, from 3 s), 300 N:
    3.6 s, window 3.3 s."""
    times, out = drive_case("pulse", roller_drive(amplitude=70.0, frequency=50.0), 3.6, 3.3, 3601)
    save_case("pulse", times, out, 4, {"rollers": 3, "pretension_N": 300.0, "load_amplitude_N_m": 70.0,
                                                "load_frequency_rad_per_s": 50.0, "t_end_s": 3.6,
                                                "window_s": 3.3, "samples": 3601})


@case
def stiff():
    """tests/reference/stiff.toml: a 2e9 N m/rad coupling beside a 2e3 one (stiffness ratio
    1e6): 2 s, window 1.5 s, 2001 samples. The stiff coupling's twist (5e-8 rad) is a state
    of its own with atol = rtol x 5e-10 rad."""
    drive = Drive(tomllib.loads((HERE / "stiff.toml").read_text()))
    # rtol 1e-10 and 1e-9 (the module's docstring says why not 1e-11)
    times, out = drive_case("stiff", drive, 2.0, 1.5, 2001, rtols=(1e-10, 1e-9))
    save_case("stiff", times, out, 1, {"file": "stiff.toml", "t_end_s": 2.0, "window_s": 1.5, "samples": 2001})


# --------------------------------------------------------------------------------------------
# the sewing drive with the eccentric tension roller (docs/eccentric_roller.md, derived there
# from the geometry; Mamatova et al. 2016, eq. 1-7, Fig. 2)
# --------------------------------------------------------------------------------------------
def tangent(ci, ri, cj, rj):
    """Common tangent from circle i to circle j (centres as (x, y) tuples), signed radii (each
    centre a signed radius to the left of the direction of travel): its length l and
    direction u = (l e - (rj - ri) e_perp) / D, e the unit vector from ci to cj."""
    dx, dy = cj[0] - ci[0], cj[1] - ci[1]
    D = math.hypot(dx, dy)
    ex, ey = dx / D, dy / D
    dr = rj - ri
    l = math.sqrt(D * D - dr * dr)
    return l, ((l * ex + dr * ey) / D, (l * ey - dr * ex) / D)


def turn(u_in, u_out, ccw: bool) -> float:
    """The wrap angle on a circle from the arriving direction to the leaving one, measured in
    the wrap's own sense (counter-clockwise for a pulley, clockwise for the roller) [rad]."""
    a = math.atan2(u_in[0] * u_out[1] - u_in[1] * u_out[0], u_in[0] * u_out[0] + u_in[1] * u_out[1])
    return (a if ccw else -a) % (2 * math.pi)


class EccentricLoop:
    """Motor pulley (radius r1) at the origin, the rim (r2) at (a, 0), the tension roller (r3)
    on the back of the slack (bottom) span, its centre P + Delta (cos theta, sin theta). The
    belt runs counter-clockwise: motor pulley -> roller -> rim -> motor pulley."""

    def __init__(self, r1, r2, a, r3, px, py, delta):
        self.r1, self.r2, self.a, self.r3 = r1, r2, a, r3
        self.px, self.py, self.delta = px, py, delta

    def centre(self, theta):
        return self.px + self.delta * math.cos(theta), self.py + self.delta * math.sin(theta)

    def spans(self, theta):
        c1, c2, c3 = (0.0, 0.0), (self.a, 0.0), self.centre(theta)
        return tangent(c1, self.r1, c3, -self.r3), tangent(c3, -self.r3, c2, self.r2), tangent(c2, self.r2, c1, self.r1)

    def length(self, theta) -> float:
        """Belt path length: three spans and three arcs [m]."""
        s13, s32, s21 = self.spans(theta)
        arcs = (self.r1 * turn(s21[1], s13[1], True) + self.r3 * turn(s13[1], s32[1], False)
                + self.r2 * turn(s32[1], s21[1], True))
        return s13[0] + s32[0] + s21[0] + arcs

    def slope(self, theta) -> float:
        """dL/dtheta = (u_in - u_out) . dC/dtheta: moving a circle's centre moves the length by
        u_in - u_out, the arcs taking up the tangent points' motion [m/rad]."""
        s13, s32, _ = self.spans(theta)
        (ax, ay), (bx, by) = s13[1], s32[1]
        return self.delta * (-(ax - bx) * math.sin(theta) + (ay - by) * math.cos(theta))


class SewingEccentric:
    """The five-inertia sewing drive (catalogs/drives/sewing.toml) with the eccentric roller on
    belt 12: two elastic spans of stiffness k = C1 / (2 r1^2), damping b = d1 / (2 r1^2),
    x = r1 phi1 - r2 phi2, delta = L(theta) - L(theta0), theta = theta0 - r1 phi1 / r3,
    V = k/2 [x^2 + (delta - x)^2], R = b/2 [x'^2 + (delta' - x')^2] (docs/eccentric_roller.md
    E4-E7). Coordinates: phi1 and the twists e12 = phi1 - U phi2, e23, e34, e45 with their
    rates; M the motor torque; quadratures of e23, e45 and M."""

    def __init__(self, p: dict):
        self.p = p
        self.U = p["U12"]
        self.geo = EccentricLoop(p["r1"], p["U12"] * p["r1"], p["a"], p["r3"], p["px"], p["py"], p["delta"])
        self.L0 = self.geo.length(0.0)
        self.k = p["C1"] / (2 * p["r1"] ** 2)
        self.b = p["d1"] / (2 * p["r1"] ** 2)
        self.w0 = 2 * math.pi * p["f"] / p["pole_pairs"]
        self.wc = 2 * math.pi * p["f"]
        self.gain = 2 * p["Mc"] * self.wc / self.w0
        self.size = 14

    def unpack(self, y):
        phi1, e12, e23, e34, e45, w1, r12, r23, r34, r45, M = y[:11].tolist()
        w2 = (w1 - r12) / self.U
        w3 = w2 - r23
        w4 = w3 - r34
        w5 = w4 - r45
        return phi1, (e12, e23, e34, e45), (w1, w2, w3, w4, w5), (r12, r23, r34, r45), M

    def accel(self, t, y):
        p = self.p
        phi1, (e12, e23, e34, e45), w, (r12, r23, r34, r45), M = self.unpack(y)
        r1, r2, r3 = p["r1"], self.U * p["r1"], p["r3"]
        theta = -r1 * phi1 / r3
        delta = self.geo.length(theta) - self.L0
        dphi = -(r1 / r3) * self.geo.slope(theta)
        x, xd = r1 * e12, r1 * r12
        dd = dphi * w[0]
        k, b = self.k, self.b
        Q1 = -k * r1 * (2 * x - delta) - k * (delta - x) * dphi - b * r1 * (2 * xd - dd) - b * (dd - xd) * dphi
        Q2 = k * r2 * (2 * x - delta) + b * r2 * (2 * xd - dd)
        T23 = p["C2"] * e23 + p["d2"] * r23
        T34 = p["C3"] * e34 + p["d3"] * r34
        T45 = p["C4"] * e45 + p["d4"] * r45
        M3 = p["M3_0"] + p["M3_amp"] * math.sin(p["w_load"] * t)
        M5 = p["M5_0"] + p["M5_amp"] * math.sin(p["w_load"] * t)
        a = ((M + Q1) / p["J1"], (Q2 - T23) / p["J2"], (T23 - T34 - M3) / p["J3"], (T34 - T45) / p["J4"],
             (T45 - M5) / p["J5"])
        return a, (T23, T45), Q2

    def rhs(self, t, y):
        phi1, e, w, r, M = self.unpack(y)
        a, (T23, T45), _ = self.accel(t, y)
        dM = self.gain * (self.w0 - w[0]) - self.wc * self.p["Sc"] * M
        return np.array([w[0], *r, a[0], a[0] - self.U * a[1], a[1] - a[2], a[2] - a[3], a[3] - a[4], dM,
                         y[2], y[4], M])

    def signals(self, t, y):
        phi1, e, w, r, M = self.unpack(y)
        a, (T23, T45), _ = self.accel(t, y)
        return {"omega_1": w[0], "omega_3": w[2], "omega_5": w[4], "accel_3": a[2], "accel_5": a[4],
                "T_23": T23, "T_45": T45, "M_motor": M}


def sewing_params(delta: float) -> dict:
    data = tomllib.loads((ROOT / "catalogs/drives/sewing.toml").read_text())
    node = {nd["name"]: si(nd["inertia"]) for nd in data["node"]}
    c = {x["name"]: x for x in data["coupling"]}
    m = data["motor"][0]
    loads = {ld["name"]: ld for ld in data["load"]}
    assert "ramp" not in m
    p = {f"J{k}": node[str(k)] for k in range(1, 6)}
    for k, nm in enumerate(("12", "23", "34", "45"), start=1):
        p[f"C{k}"], p[f"d{k}"] = si(c[nm]["stiffness"]), si(c[nm]["damping"])
    mm = lambda text: float(text.split()[0]) * {"mm": 1e-3}[text.split()[1]]
    p.update(U12=float(c["12"]["ratio"]), r1=mm(c["12"]["pulley_radius"]), r3=mm(c["12"]["roller_radius"]),
             a=mm(c["12"]["center_distance"]), px=mm(c["12"]["pivot_x"]), py=mm(c["12"]["pivot_y"]), delta=delta,
             Mc=float(m["breakdown_factor"]) * si(m["rated_torque"]), Sc=float(m["breakdown_slip"]),
             f=si(m["supply"]), pole_pairs=int(m["pole_pairs"]),
             M3_0=si(loads["M3"]["torque"]), M3_amp=si(loads["M3"]["amplitude"]),
             M5_0=si(loads["M5"]["torque"]), M5_amp=si(loads["M5"]["amplitude"]),
             w_load=si(loads["M3"]["frequency"]))
    assert all(float(c[nm].get("ratio", 1)) == 1.0 for nm in ("23", "34", "45"))
    return p


def smooth_run(system, t_end, times, rtol):
    """Radau through every output time (each a step point): the exact states there."""
    atol = rtol * np.array([1.0, 1e-6, 1e-4, 1e-4, 1e-4, 1.0, 1e-3, 1e-2, 1e-2, 1e-2, 1e-2, 1e-4, 1e-4, 1e-2])
    y = np.zeros(system.size)
    out = [y.copy()]
    wall = time.time()
    for k, (a, b) in enumerate(zip(times, times[1:])):
        sol = solve_ivp(system.rhs, (a, b), y, method="Radau", rtol=rtol, atol=atol)
        assert sol.status == 0, (sol.message, a, b)
        y = sol.y[:, -1]
        out.append(y.copy())
        if k % 1000 == 0:
            print(f"  t = {b:.4f} s, {time.time() - wall:.0f} s", flush=True)
    return np.array(out).T


@case
def sewing_ecc():
    """The sewing scene with a 2 mm eccentric roller (``--set roller_eccentricity=2mm``):
    1 s, 10001 samples; the window samples of the reported signals are stored (the scene
    reports, for this nonlinear drive, trapezoid means and sampled extremes over
    t >= 0.50366 s, its whole load periods)."""
    p = sewing_params(2e-3)
    g = EccentricLoop(p["r1"], p["U12"] * p["r1"], p["a"], p["r3"], p["px"], p["py"], p["delta"])
    for th in np.linspace(0, 2 * math.pi, 7):                 # the slope against a difference of the length
        h = 1e-5
        fd = (g.length(th + h) - g.length(th - h)) / (2 * h)
        assert abs(fd - g.slope(th)) < 1e-9, (th, fd, g.slope(th))
    # the tangents' and wraps' conventions on the two pulleys alone: the open belt's length
    # 2 a cos(b) + pi (r1 + r2) + 2 b (r2 - r1), sin(b) = (r2 - r1) / a
    r1, r2, a = g.r1, g.r2, g.a
    s12, s21 = tangent((0.0, 0.0), r1, (a, 0.0), r2), tangent((a, 0.0), r2, (0.0, 0.0), r1)
    two = s12[0] + s21[0] + r1 * turn(s21[1], s12[1], True) + r2 * turn(s12[1], s21[1], True)
    b = math.asin((r2 - r1) / a)
    assert abs(two - (2 * a * math.cos(b) + math.pi * (r1 + r2) + 2 * b * (r2 - r1))) < 1e-15
    times = np.linspace(0.0, 1.0, 10001)
    system = SewingEccentric(p)
    out = {}
    for rtol in (1e-10, 1e-9):
        print(f"sewing_ecc: rtol {rtol:g}", flush=True)
        wall = time.time()
        Y = smooth_run(system, 1.0, times, rtol)
        sig = [system.signals(t, Y[:, i]) for i, t in enumerate(times)]
        out[rtol] = {k: np.array([s[k] for s in sig]) for k in sig[0]}
        out[rtol]["wall_s"] = time.time() - wall
    period = 2 * math.pi / p["w_load"]                 # the scene's window: whole load periods
    start = 1.0 - math.floor(0.5 / period + 1e-9) * period
    win = times >= start - 1e-12
    tw = times[win]
    fine, coarse = out[1e-10], out[1e-9]
    figs = {}
    for k in ("omega_1", "omega_3", "omega_5", "accel_3", "accel_5", "T_23", "T_45", "M_motor"):
        x = fine[k][win]
        figs[k] = {"mean": float(np.trapezoid(x, tw) / (tw[-1] - tw[0])), "min": float(x.min()),
                   "max": float(x.max()), "referr": float(np.abs(x - coarse[k][win]).max()),
                   "runmax": float(np.abs(fine[k]).max())}
    half = times >= 0.5 - 1e-12
    np.savez_compressed(HERE / "sewing_ecc.npz", t=times[half][::10], **{k: fine[k][half][::10] for k in figs})
    (HERE / "sewing_ecc.json").write_text(json.dumps({
        "case": "sewing_ecc", "meta": {"roller_eccentricity_m": 2e-3, "t_end_s": 1.0, "samples": 10001,
                                       "rtol": 1e-10, "rtol_referr": 1e-9, "params": p, "window_start_s": start},
        "wall_s": {"fine": fine["wall_s"], "coarse": coarse["wall_s"]}, "window": figs,
        "note": ("window figures as the scene computes them for a nonlinear run: the trapezoid mean and the least "
                 "and largest sample over the samples t >= window_start_s of the 10001-sample grid; the npz keeps "
                 "every 10th sample from 0.5 s")}, indent=1) + "\n")


if __name__ == "__main__":
    names = sys.argv[1:] or list(CASES)
    for nm in names:
        t0 = time.time()
        CASES[nm]()
        print(f"{nm}: done in {time.time() - t0:.0f} s", flush=True)
