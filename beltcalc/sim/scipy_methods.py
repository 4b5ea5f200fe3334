"""scipy's solvers as methods of the core: ``solve_ivp`` (Radau, BDF, LSODA, RK45, DOP853) with
the analytic Jacobian where the method takes one, restarted at every time break point and
at every strand switch (terminal events with their direction set), and ``odeint`` (LSODA
through the older wrapper, with ``Dfun``) on the raw right-hand side.

Each run keeps a budget (right-hand-side calls, computing time, and a pace check: a run many
decades too stiff for its tolerance is refused in seconds, not after its whole budget), and
refuses inputs it cannot follow (an input with more periods in the run than its call budget
can sample). The registry of methods is :data:`beltcalc.sim.methods.METHODS`; scipy is
imported on a run's first call, never at import.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING

import numpy as np

from beltcalc.errors import SimulationError
from beltcalc.sim.propagate import augmented_matrix
from beltcalc.sim.switching import slack_times, switched_log

if TYPE_CHECKING:
    from beltcalc.sim.methods import SolverConfig
    from beltcalc.sim.network import Network


class Budget(Exception):
    pass


PACE_AFTER = 5.0    # seconds of computing after which a scipy run's pace is judged ...
PACE_FACTOR = 5.0   # ... and it stops where that pace would take this many times its max_seconds


def new_budget(cfg: SolverConfig, t_end: float = 0.0) -> list:
    """[calls so far, max_rhs_calls, the CPU time by which the run must end, its start,
    t_end, max_seconds, why it stopped ("calls", "time" or "pace")]. Computing time is this
    process's CPU time (:func:`time.process_time`), not the wall clock: a run on a machine
    busy with other work is judged by the work it did, so its budget and pace, and a test
    that relies on them, do not depend on the machine's load."""
    now = time.process_time()
    return [0, cfg.max_rhs_calls, now + cfg.max_seconds, now, float(t_end), cfg.max_seconds, ""]


def over(budget: list, t: float) -> bool:
    """Whether a scipy run at time ``t`` has spent its budget: its right-hand-side calls, its
    computing time, or (judged every 256 calls after PACE_AFTER s) a pace at which reaching
    t_end would take over PACE_FACTOR times its computing time: a run many decades too stiff
    for its tolerance is refused in seconds, not after its whole budget (issue 27 R15: the
    error estimate's Radau at 1/100 of the tolerances reached 0.0046 s of 0.05 s in 120 s)."""
    if budget[0] > budget[1]:
        budget[6] = "calls"
        return True
    if budget[0] & 255:
        return False
    now = time.process_time()
    if now > budget[2]:
        budget[6] = "time"
        return True
    spent = now - budget[3]
    if budget[4] > 0 and spent > PACE_AFTER and spent * budget[4] > PACE_FACTOR * budget[5] * max(t, 0.0):
        budget[6] = "pace"
        return True
    return False



# --- scipy's solvers ----------------------------------------------------------------------------
def generators(network: Network):
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
    gen = generators(network)

    def rhs(t, x):
        budget[0] += 1
        if over(budget, t):
            raise Budget(t)
        dx = A @ x + B @ gen(t)
        if nonlinear:
            dx += network.nonlinear_terms(t, x)
        return dx

    def jac(t, x):
        return A + network.nonlinear_jacobian(x) if nonlinear else A

    return rhs, jac


# --- scipy's solvers with events (strand mode by its rates, restarted at each switch) -------------
class Switches:
    """The strand mode, its switches and the event budget of one run."""

    def __init__(self, network: Network, z0: np.ndarray, cfg: SolverConfig, method: str, h: float,
                 t_mid: float = 0.0):
        self.network, self.cfg, self.method = network, cfg, method
        delta, force = network.strand_rows()
        d, f = delta @ z0, force @ z0
        # at rest a strand without pretension sits on the surface; it is taut if it stretches
        self.taut = network.full_pattern(tuple(bool(a > 0 and b > 0) for a, b in zip(d, f)))
        F = augmented_matrix(network, self.taut, t_mid)
        self.taut = network.full_pattern(tuple(network.taut_after(k, z0, F @ z0, ahead(F, z0, h), h)
                                               for k in range(len(d))))
        self.taut, self.z = network.decide_switched(z0, self.taut, t_mid, h, slack=cfg.rtol, guess=True)
        self.start = self.taut
        self.log: list[tuple[float, int, bool]] = []
        self.located = 0

    def switch(self, strand: int, t: float, z: np.ndarray, F: np.ndarray, h: float, t_mid: float = 0.0) -> None:
        """Decide strand ``strand``'s mode (or a switched element's, numbered after the
        strands) just after ``t`` and record a change."""
        self.located += 1
        net, ns = self.network, len(self.network.strands)
        if self.located > self.cfg.max_events:
            what = f"strand {net.strands[strand].name}" if strand < ns else net.switched[strand - ns].name
            raise SimulationError(
                f"method {self.method}: {self.cfg.max_events} {'strand events' if strand < ns else 'switches'} by t = {t:.6g} s ({what} "
                "switches that often); add pretension or damping, or raise `max_events`")
        if strand >= ns:
            self.restart(t, z, h, t_mid, fired=strand - ns)
            return
        on = net.taut_after(strand, z, F @ z, ahead(F, z, h), h)
        if on != self.taut[strand]:
            self.taut = tuple(on if k == strand else v for k, v in enumerate(self.taut))
            self.log.append((t, strand, on))
        if net.switched:
            self.restart(t, z, h, t_mid)

    def restart(self, t: float, z: np.ndarray, h: float, t_mid: float, fired: int | None = None) -> None:
        """Decide the switched elements just after ``t`` (a switch, or a new time piece)."""
        new, self.z = self.network.decide_switched(z, self.taut, t_mid, h, fired, slack=self.cfg.rtol)
        for k, (a, b) in enumerate(zip(self.taut, new)):
            if a != b:
                self.log.append((t, k, b))
        self.taut = new

    def info(self, t_end: float) -> dict:
        """Switch count and each strand's time slack [s] (and the switched elements' history)."""
        info = {"events": len(self.log), "located": self.located,
                "slack_time": slack_times(self.network, self.start, self.log, t_end)}
        if self.network.switched:
            info["switched"] = switched_log(self.network, self.start, self.log, t_end)
        return info


def ahead(F: np.ndarray, z: np.ndarray, h: float) -> np.ndarray:
    """The state a moment (1e-6 h) later, by its Taylor series to second order."""
    eps = 1e-6 * h
    dz = F @ z
    return z + eps * dz + 0.5 * eps ** 2 * (F @ dz)



def counting(name: str, counter: list[int]):
    """scipy's solver class ``name``, counting its accepted steps in ``counter[0]``
    (solve_ivp reports right-hand-side calls, not steps; each ``step()`` call that does
    not fail is one accepted step)."""
    import scipy.integrate

    base = getattr(scipy.integrate, name)

    class Counting(base):
        def step(self):
            message = super().step()
            if self.status != "failed":
                counter[0] += 1
            return message

    Counting.__name__ = name
    return Counting


def ivp(name: str, uses_jac: bool):
    def run(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
        budget = new_budget(cfg, t[-1])
        steps = [0]
        solver = counting(name, steps)
        x = np.asarray(x0, dtype=float)
        starts = network.segment_starts(t[-1])
        sw = Switches(network, np.concatenate([x, network.generators(0.0)]), cfg, name.lower(), t[1] - t[0],
                      network.piece_time(0, starts, t[-1]))
        if network.switched:
            x = sw.z[:network.size]          # the stuck joints' speeds settled
        network.pieces = {el.name: el.piece_at(network, x) for el in network.piecewise}
        try:
            return _ivp_loop(network, t, x, cfg, name, uses_jac, budget, steps, solver, sw)
        finally:
            network.pieces = {}
    return run


def _piece_events(network, skip: tuple, t_cur: float) -> tuple[list, list]:
    """The event functions that end the elements' smooth pieces (a polygon strand's seating or
    slack switch), first in the event list, and their owners."""
    events, owners = [], []
    for el in network.piecewise:
        for fn, direction in el.piece_events(network, network.pieces[el.name]):
            j = len(events)

            def ev(tt, xx, fn=fn, again=j in skip, start=t_cur, sign=direction):
                value = fn(xx)
                return sign * max(abs(value), 1e-300) if again and tt == start else value
            ev.terminal, ev.direction = True, direction
            events.append(ev)
            owners.append(el)
    return events, owners


def _ivp_loop(network, t, x, cfg, name, uses_jac, budget, steps, solver, sw):
    """The integration of :func:`ivp`'s run from the state ``x``: solve_ivp from time break
    to time break, restarted at every event (a strand's or switched element's switch, the end
    of an element's smooth piece)."""
    from scipy.integrate import solve_ivp    # here, not at the top: the exact path needs none of it

    N, m, t_end = t.size, network.size, t[-1]
    eps = 1e-9 * (t[1] - t[0])
    starts = network.segment_starts(t_end)
    ends = starts[1:] + [math.inf]
    out = np.empty((m, N))
    out[:, 0] = x
    k, t_cur, skip = 0, 0.0, ()
    stats = {"nfev": 0, "njev": 0, "nlu": 0}
    ended = 0       # the elements' smooth pieces ended
    slack = {el.name: [0.0, None if el.taut_in(network.pieces[el.name]) else 0.0] for el in network.piecewise}
    while k < N - 1:
        seg = network.segment(t_cur + eps, starts)
        t_stop = min(ends[seg], t_end)
        mid = network.piece_time(seg, starts, t_end)
        rhs, jac = _system(network, sw.taut, mid, budget)
        gen = generators(network)
        events, owners = _piece_events(network, skip, t_cur)
        first = len(events)
        switching = network.events(sw.taut) + network.switched_events(sw.taut, mid)
        for j, ev in enumerate(switching, start=first):
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
            sol = solve_ivp(rhs, (t_cur, t_stop), x, method=solver, t_eval=t_eval, rtol=cfg.rtol,
                            atol=cfg.atol, events=events or None, **kwargs)
        except Budget as stop:
            raise SimulationError(budget_message(name, stop.args[0], cfg, budget, network)) from None
        except ValueError as exc:
            # scipy's event location (brentq on the step's interpolant) meets a function that
            # changed sign between the step's points but not on the interpolant
            raise SimulationError(f"method {name.lower()}: scipy's event location failed after t = "
                                  f"{t_cur:.6g} s ({exc}); try another `rtol`, or method exact") from None
        for key in stats:
            stats[key] += int(getattr(sol, key))
        if sol.status < 0:
            reached = sol.t[-1] if sol.t.size else t_cur
            raise SimulationError(f"method {name.lower()} failed at t = {reached:.6g} s: {sol.message}; "
                                  "try `method` radau or bdf, or looser `rtol`/`atol`")
        grid = [j for j, tt in enumerate(sol.t) if k + 1 + j <= last and abs(tt - t[k + 1 + j]) <= eps]
        for j in grid:
            out[:, k + 1 + j] = sol.y[:, j]
        k += len(grid)
        if sol.status == 1:
            fired = [(te[0], j) for j, te in enumerate(sol.t_events) if te.size]
            t_e, j = min(fired)
            x = sol.y_events[j][0]
            if j < first:       # an element's piece ends: decide its next just after t_e
                el = owners[j]
                was = network.pieces[el.name]
                network.pieces[el.name] = el.piece_at(network, x + 1e-6 * (t[1] - t[0]) * rhs(t_e, x))
                skip = (skip if t_e == t_cur else ()) + ((j,) if network.pieces[el.name] == was else ())
                ended += 1
                _slack_change(slack[el.name], el.taut_in(network.pieces[el.name]), t_e)
                t_cur = t_e
                continue
            z = np.concatenate([x, network.generators(t_e)])
            ev = switching[j - first]
            before = sw.taut
            sw.switch(ev.strand, t_e, z, augmented_matrix(network, sw.taut, mid), t[1] - t[0], mid)
            if network.switched:
                x = sw.z[:m]
            skip = (skip if t_e == t_cur else ()) + ((j,) if sw.taut == before else ())
            t_cur = t_e
        else:
            t_cur, x, skip = t_stop, sol.y[:, -1], ()
            if network.switched and t_cur < t_end:     # the inputs change piece: re-decide
                seg = network.segment(t_cur + eps, starts)
                sw.restart(t_cur, np.concatenate([x, network.generators(t_cur)]), t[1] - t[0],
                           network.piece_time(seg, starts, t_end))
                x = sw.z[:m]
    info = {"jacobians": stats["njev"], "lu": stats["nlu"], **sw.info(t_end)}
    if network.piecewise:
        info["pieces_ended"] = ended
        for name, (spent, since) in slack.items():      # each piecewise element's time slack, from its pieces
            info["slack_time"][name] = spent + (t_end - since if since is not None else 0.0)
    return out, steps[0], stats["nfev"], info


def _slack_change(acc: list, taut: bool, t: float) -> None:
    """Account a piece change at ``t`` in ``acc`` = [time slack so far, slack since (None: taut)]."""
    if taut and acc[1] is not None:
        acc[0] += t - acc[1]
        acc[1] = None
    elif not taut and acc[1] is None:
        acc[1] = t


def odeint_run(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    from scipy.integrate import odeint    # here, not at the top: the exact path needs none of it

    if network.switched:
        from beltcalc.errors import InputError
        names = ", ".join(el.name for el in network.switched)
        raise InputError(f"method odeint integrates the raw right-hand side, which cannot hold {names} stuck or "
                         "saturated; use `method` exact, radau or bdf (restarted at each switch)", param="method")

    budget = new_budget(cfg, t[-1])
    starts = network.segment_starts(t[-1])
    delta, force = network.strand_rows()
    gen = generators(network)
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
        if over(budget, tt):
            raise Budget(tt)
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
    except Budget as stop:
        raise SimulationError(budget_message("odeint", stop.args[0], cfg, budget, network)) from None
    if info["message"] != "Integration successful.":
        reached = float(info["tcur"][-1]) if len(info["tcur"]) else t[0]
        reached = reached if 1e-100 <= reached <= t[-1] else t[0]   # unset before the first output: garbage
        raise SimulationError(f"method odeint failed at t = {reached:.6g} s: {info['message']}; "
                              "try `method` radau, or looser `rtol`/`atol`")
    extra = {"jacobians": int(info["nje"][-1])}
    if network.strands:   # no events: the slack time from the samples
        taut = network.taut_of(y.T, t)
        dt = t[1] - t[0]
        extra["slack_time"] = {s.name: float(np.sum(~taut[k][1:]) * dt) for k, s in enumerate(network.strands)}
        extra["events"] = int(np.sum(np.diff(taut.astype(int), axis=1) != 0))
    return y.T, int(info["nst"][-1]), int(info["nfe"][-1]), extra


STEPS_PER_PERIOD = 4   # fewer steps than this per period of an input no step-size control accepts


def require_resolvable_inputs(network: Network, t_end: float, cfg: SolverConfig, method: str) -> None:
    """Refuse at once a time-stepping run whose fastest sinusoidal input cannot be followed
    within the budget: it needs at least STEPS_PER_PERIOD right-hand-side calls per period
    (e.g. a load at 1e82 rpm: 1e79 periods in a short run, where Radau would spend its whole
    ``max_rhs_calls`` and ``max_seconds`` budget before failing). The exact method takes
    these inputs exactly, whatever their frequency."""
    freqs = network.frequencies()
    if not freqs:
        return
    w = max(abs(f) for f in freqs)
    periods = w * t_end / (2 * math.pi)
    if periods * STEPS_PER_PERIOD > cfg.max_rhs_calls:
        instead = "`method` exact (it takes sinusoidal inputs exactly)" if network.linear else \
            "a lower frequency or a shorter `t_end`"
        raise SimulationError(
            f"method {method}: an input at {w:.4g} rad/s oscillates {periods:.3g} times in the run; following it "
            f"needs more than the {cfg.max_rhs_calls} right-hand-side calls allowed (at least {STEPS_PER_PERIOD} a "
            f"period); try {instead}")


def budget_message(method: str, reached: float, cfg: SolverConfig, budget: list,
                    network: Network | None = None) -> str:
    exact = network is None or network.linear     # suggest exact only where it runs: linear between switches
    from beltcalc.sim.methods import METHODS

    if METHODS[method.lower()].explicit:
        why = "the system is stiff for an explicit method, or switches too often?"
        instead = "`method` exact, radau or bdf" if exact else "`method` radau or bdf"
    else:
        why = ("the solution is hard at this tolerance, switches too often, or the model is many decades stiffer in "
               "one part?")
        instead = "`method` exact, or a looser `rtol`/`atol`" if exact else "a looser `rtol`/`atol`"
    if budget[6] == "pace":
        spent = time.process_time() - budget[3]
        return (f"method {method.lower()} stopped at t = {reached:.6g} s of {budget[4]:g} s after {spent:.3g} s of "
                f"computing ({budget[0]} right-hand-side calls): at that pace the run would take about "
                f"{spent * budget[4] / max(reached, 1e-300):.3g} s, beyond {cfg.max_seconds:g} s ({why}); try {instead}")
    spent = (f"{cfg.max_rhs_calls} right-hand-side calls" if budget[0] > budget[1] else
             f"{cfg.max_seconds:g} s of computing ({budget[0]} right-hand-side calls)")
    return f"method {method.lower()} stopped at t = {reached:.6g} s after {spent} ({why}); try {instead}"


radau = ivp("Radau", True)
bdf = ivp("BDF", True)
lsoda = ivp("LSODA", True)
rk45 = ivp("RK45", False)
dop853 = ivp("DOP853", False)
