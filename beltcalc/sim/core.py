"""The one place that integrates. Methods by name from the registry (:mod:`beltcalc.sim.methods`):

- ``exact``: networks that are linear between switches, with constant, sinusoidal and
  piecewise-linear inputs. The state is augmented with the inputs' generators
  (g' = G g), balanced by a diagonal similarity of powers of two, and the augmented system
  z' = F z is propagated with its exact one-step matrix (scaling and squaring, or the
  Taylor series on steps short enough for it to be exact to rounding). No
  eigen-decomposition: on the sewing model its eigenvector matrix has a condition number
  near 1e13 and loses about 0.1 rad/s.

  * one linear system over the whole run: in blocks, the powers P_r = expm(F dt)^r,
    r < b, applied to every block start at once;
  * tension-only strands and time break points: piecewise, mode by mode, with internal
    steps from the dynamics, every switch located to machine precision on the exact
    solution and the outputs read off it afterwards (:mod:`beltcalc.sim.switching`).
- ``radau``, ``bdf``, ``lsoda``, ``rk45``, ``dop853``: scipy's ``solve_ivp`` with the
  analytic Jacobian where it takes one, restarted at every time break point and at every
  strand switch (terminal events with their direction set);
- ``odeint``: scipy's older LSODA wrapper with ``Dfun``, on the raw right-hand side (each
  strand taut or slack by its own state, no events): fast on smooth networks, and the
  trap the design warns of on switching ones, where the call budget stops it.
- ``auto``: ``exact`` where the network allows it; a nonlinear network without switches that
  is not stiff (an explicit method is stable in at most ``EXPLICIT_STEPS`` steps, its fastest
  pole from the Jacobian at rest: :func:`beltcalc.sim.methods.choose_method`) ``dop853``; else
  ``radau``; the result says why.

Every run carries an error estimate per speed signal, in the signal's own unit, from a
second computation that shares neither the rounding nor the partition of the first (see
:func:`simulate`), plus a conditioning term. An estimate above the tolerance
(``error_tol`` of the signal's scale) makes ``auto`` refine, then fall back to Radau with
events; if nothing reaches it the run fails with one line, unless ``accept_error``.
"""

from __future__ import annotations

import time

import numpy as np

from beltcalc.errors import InputError, SimulationError, require_positive
from beltcalc.sim.methods import METHODS, SolverConfig, choose_method
from beltcalc.sim.network import Network
from beltcalc.sim.propagate import one_piece, propagate, reference_rows
from beltcalc.sim.result import SimResult
from beltcalc.sim.switching import EPS, piecewise_exact, switched_history

__all__ = ["SolverConfig", "simulate", "choose_method", "conditioning", "estimate_error", "run_exact",
           "one_piece_accelerations"]

MAX_PHASE = 1e-3 / EPS  # rad: an input's phase w t_end beyond which a float holds it to worse than 1 mrad

FALLBACK_SECONDS = 30.0     # computing time auto's Radau fallback may take
RADAU_FALLBACK_WORK = 2e6   # strand events x states^2 above which auto's Radau fallback is not tried
REFINE_WORK = 1e10          # strand events x states^2 above which auto does not refine the exact run (4x its
                            # cost: 200 rollers, 14,300 events x 1,605 states, would take 10 minutes more)
ESTIMATE_STEP = 1.5         # the error estimate's piecewise second run: bottom steps 1.5 times as long
                            # (switching.terms_for: up to 62 Taylor terms): another partition, fewer steps


CONCURRENT_SIZE = 300       # states from which a watched run's second computation runs beside it (the sparse path)


class Figures:
    """What the error estimate reads of a watched second computation: its node speeds and the
    summaries of its watched figures (a forked process sends these, not the whole run)."""

    def __init__(self, result: SimResult, n: int):
        self.speeds = result.states[n:2 * n]
        self.extremes = dict.fromkeys(result.extremes)
        self.summaries = {key: result.summary(*key) for key in result.extremes}

    def summary(self, name: str, start: float):
        return self.summaries[(name, start)]


def _second(network: Network, t, x0, cfg, watch) -> Figures:
    """The watched second computation of :func:`estimate_error`: the exact method with another
    internal step (:data:`ESTIMATE_STEP`)."""
    return Figures(_run(network, t, x0, cfg, "exact", "", scale=ESTIMATE_STEP, watch=watch), network.n)


def _beside(work):
    """``work()`` started in a forked process where it can run beside this one: a second CPU
    this process may use, the main thread of a process that is not itself a worker, and a
    platform that forks. Returns a call that waits for its value (its ``cancel`` stops the
    child). Where any of these is missing, or the child fails in any way (its exception does
    not travel), the call computes ``work()`` here: the same computation, the same value,
    later. (multiprocessing flushes stdout and stderr before it forks: nothing buffered is
    written twice.)"""
    import os
    import threading

    try:
        import multiprocessing as mp

        usable = (hasattr(os, "fork") and len(os.sched_getaffinity(0)) >= 2 and mp.parent_process() is None
                  and threading.current_thread() is threading.main_thread())
    except (AttributeError, ImportError, OSError):
        usable = False
    if not usable:
        return work
    ctx = mp.get_context("fork")
    receive, send = ctx.Pipe(duplex=False)

    def child():
        try:
            value = work()
        except BaseException:           # noqa: BLE001 - the parent computes it again and raises
            send.send(None)
            return
        send.send(value)

    proc = ctx.Process(target=child, daemon=True)
    proc.start()
    send.close()

    def wait():
        try:
            value = receive.recv()
        except (EOFError, OSError):
            value = None
        finally:
            receive.close()
            proc.join()
        return work() if value is None else value

    def cancel():
        proc.terminate()
        proc.join()
        receive.close()
    wait.cancel = cancel
    return wait


def _round_up(x: float) -> str:
    """``x`` rounded up to one significant digit, as text (2.1e-05 -> '3e-05')."""
    import math

    e = math.floor(math.log10(x))
    return f"{math.ceil(x / 10.0 ** e - 1e-9) * 10.0 ** e:.0e}".replace("e-0", "e-").replace("e+0", "e+")


def _initial(network: Network, x0: np.ndarray | None) -> np.ndarray:
    x = network.initial_state() if x0 is None else np.asarray(x0, dtype=float)
    if x.shape != (network.size,):
        raise InputError(f"initial state has {x.size} values; the network has {network.size}", param="x0")
    return x


def run_exact(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig, scale: float = 1.0, watch=None,
              rows=None):
    """The exact solution: one linear system over the run, or piecewise between strand switches
    and time break points (:mod:`beltcalc.sim.switching`). ``scale`` != 1 runs another internal
    partition (the error estimate's second computation). ``rows``: the state rows wanted; a
    smooth run computes only those and leaves the others zero (the piecewise path fills all)."""
    if not network.linear:
        why = "; ".join(sorted({getattr(el, "nonlinear_reason", "loads locked to a shaft angle")
                                for el in network.elements if el.nonlinear_kind})) or "nonlinear elements"
        raise InputError("the exact method needs a network that is linear between switches; this one has "
                         f"{why}: use `method` radau (or auto)", param="method")
    if not network.smooth or watch is not None:
        # piecewise (also for a smooth network whose window statistics are watched: the
        # extremes and integrals come off the exact solution, not the samples)
        out, steps, info = piecewise_exact(network, t, x0, cfg.max_events, scale, watch)
        return out, steps, 0, info
    dt = t[1] - t[0]
    F, balancing = one_piece(network)
    z0 = np.concatenate([x0, network.generators(0.0)])
    parts = 1 if scale == 1.0 else 3
    if rows is None:
        # every row of z into one array: the states, then the generators (the outputs read
        # their sines off it instead of evaluating sin w t again)
        z = propagate(F, z0, dt, t.size, parts, scale=balancing)
        return z[:network.size], t.size - 1, 0, {"generators": z[network.size:], "one_piece": True}
    wanted = np.arange(network.size)[rows]
    x = np.zeros((network.size, t.size))     # rows never written stay zero
    if wanted.size and np.all(np.diff(wanted) == 1):
        propagate(F, z0, dt, t.size, parts, wanted, out=x[wanted[0]:wanted[-1] + 1], scale=balancing)
    else:
        x[wanted] = propagate(F, z0, dt, t.size, parts, wanted, scale=balancing)
    return x, t.size - 1, 0, {}


def simulate(network: Network, t_end: float, samples: int, cfg: SolverConfig = SolverConfig(),
             x0: np.ndarray | None = None, watch: tuple | None = None) -> SimResult:
    """Integrate ``network`` from ``x0`` (rest by default) over [0, t_end] at ``samples`` points.

    ``watch`` = (signal names, window starts[, reported]): on the exact piecewise path, the result's
    :meth:`SimResult.summary` over ``[start, t_end]`` then takes those signals' extremes off
    the exact solution (:mod:`beltcalc.sim.watch`) and every linear signal's mean from the
    exact integral of the state, independent of ``samples``.

    The only function that integrates; every scene calls it. With ``cfg.estimate_error`` the
    result carries an error estimate per speed signal (see :func:`estimate_error`); where it
    exceeds ``cfg.error_tol`` of the signal's scale, ``auto`` refines the exact method's
    internal step, then falls back to Radau with events at a tolerance 100 times tighter
    than asked; if the estimate still exceeds it, :class:`SimulationError` (one line: what was
    reached, on which signal, what to try) unless ``cfg.accept_error``.
    """
    require_positive("t_end", t_end, "s")
    if samples < 2:
        raise InputError(f"{samples} samples; at least 2 are needed", param="samples")
    if not 0 < cfg.error_tol < 1:
        raise InputError(f"error tolerance {cfg.error_tol:g} is not allowed; it must be in (0, 1)", param="error_tol")
    for w in network.frequencies():
        if abs(w) * t_end > MAX_PHASE:
            raise InputError(f"an input at {abs(w):.4g} rad/s turns {abs(w) * t_end:.3g} rad over the run: beyond "
                             f"{MAX_PHASE:.2g} rad a float cannot hold its phase to a milliradian; lower its "
                             "frequency or `t_end`")
    method, reason = choose_method(network, cfg.method, t_end)
    if cfg.method == "auto" and method == "dop853" and cfg.rtol > cfg.error_tol * 1e-4:
        # an elastic force is a difference of positions times a stiffness: its relative error runs
        # about 100 times the speeds' (the carriage belt: 40x), so the explicit run starts 1e-4 below
        from dataclasses import replace

        cfg = replace(cfg, rtol=max(1e-13, cfg.error_tol * 1e-4), atol=min(cfg.atol, cfg.error_tol * 1e-6))
        reason += f", at rtol {cfg.rtol:g} (1e-4 of the error tolerance)"
    x0 = _initial(network, x0)
    t = np.linspace(0.0, t_end, samples)
    second = None
    if cfg.estimate_error and method == "exact" and watch:
        # the estimate's second watched computation, beside the run where the run is long (sparse)
        second = (_beside if network.size >= CONCURRENT_SIZE else lambda work: work)(
            lambda: _second(network, t, x0, cfg, watch))
    try:
        result = _run(network, t, x0, cfg, method, reason, watch=watch)
    except BaseException:
        getattr(second, "cancel", lambda: None)()      # a forked second computation is not waited for
        raise
    if not cfg.estimate_error:
        return result
    estimate_error(result, network, x0, cfg, watch=watch, second=second)
    tried = [f"{method} ({result.error_relative:.1g})"]
    work = int(result.extra.get("located", 0)) * network.size ** 2
    if result.error_relative > cfg.error_tol and cfg.method == "auto" and method == "exact" and work > REFINE_WORK:
        events = f"{int(result.extra.get('located', 0))} strand events x {network.size} states"
        tried += [f"not refined ({events}: 4x this run)", f"not radau ({events}: too long)"]
    elif result.error_relative > cfg.error_tol and cfg.method == "auto" and method == "exact":
        # refine: a quarter of the internal step, checked against the first run
        fine = _run(network, t, x0, cfg, "exact", reason + "; refined to a quarter of the internal step",
                    scale=0.25, watch=watch)
        estimate_error(fine, network, x0, cfg, reference=(result, "exact at 4x the internal step"), watch=watch)
        tried.append(f"exact refined ({fine.error_relative:.1g})")
        if fine.error_relative <= cfg.error_tol:
            return fine
        tight = SolverConfig("radau", max(1e-13, min(cfg.rtol, cfg.error_tol / 100)),  # scipy's floor is 2.2e-14
                             max(1e-16, min(cfg.atol, cfg.error_tol * 1e-4)),
                             cfg.max_rhs_calls, cfg.max_events, True, cfg.error_tol, cfg.accept_error,
                             min(cfg.max_seconds, FALLBACK_SECONDS))
        radau = None
        located = int(fine.extra.get("located", 0))
        if located * network.size ** 2 > RADAU_FALLBACK_WORK:
            # Radau restarts (a dense LU) at every switch: 30 rollers (127 switches, 245 states)
            # do not finish in 10 minutes (benchmarks/results/roller_scaling.md); not tried
            tried.append(f"not radau ({located} strand events x {network.size} states: too long)")
        else:
            try:
                radau = _run(network, t, x0, tight, "radau",
                             "auto: the exact method's estimate exceeded the tolerance; Radau with events")
            except SimulationError as exc:
                radau = None
                tried.append("radau (" + str(exc).split(" (", 1)[0].replace("method radau ", "") + ")")
        if radau is not None:
            estimate_error(radau, network, x0, tight, reference=(fine, "the refined exact run"))
            tried.append(f"radau ({radau.error_relative:.1g})")
            if radau.error_relative <= cfg.error_tol:
                return radau
        result = fine
    elif result.error_relative > cfg.error_tol and cfg.method == "auto" and method in ("dop853", "radau") \
            and cfg.rtol > 1e-12:
        # auto's run of a nonlinear drive: once more at 1/100 of the tolerances (its own estimate
        # at 1/10^4)
        from dataclasses import replace

        tight = replace(cfg, rtol=max(1e-13, cfg.rtol / 100), atol=max(1e-16, cfg.atol / 100))
        again = "dop853" if network.piecewise else method      # smooth pieces: Radau at 1/100 crawls
        fine = _run(network, t, x0, tight, again, reason + f"; {again} at rtol {tight.rtol:g}: the estimate at "
                    f"{cfg.rtol:g} exceeded the tolerance")
        estimate_error(fine, network, x0, tight)
        tried.append(f"{again} at rtol {tight.rtol:g} ({fine.error_relative:.1g})")
        result = fine
    if result.error_relative > cfg.error_tol:
        message = (f"error estimate {result.error_estimate:.3g} {result.error_unit} on {result.error_signal} "
                   f"(largest near t = {result.error_at:.6g} s) is {result.error_relative:.2g} of its scale "
                   f"{result.error_scale:.4g} {result.error_unit}, above the tolerance {cfg.error_tol:g}; "
                   f"tried {', '.join(tried)}")
        if not cfg.accept_error:
            looser = f"a looser `error_tol` (at least {_round_up(result.error_relative)})"
            if result.method == "exact" and any(x.startswith("not radau") for x in tried):
                # no other method finishes: two exact computations (each to rounding) disagree this much
                hint = (f"no other method finishes here, and two exact computations (each to rounding, on its "
                        f"own internal steps) differ by this much; try {looser}")
            else:
                tighter = "" if result.method == "exact" else f"a tighter `rtol` (here {cfg.rtol:g}), "
                hint = f"try {tighter}another `method`, {looser}"
            raise SimulationError(message + f"; {hint}, or `accept_error` to print it anyway", param="error_tol")
        result.extra["error_accepted"] = True
        result.warnings.append("accepted with a large error: " + message)
    return result


def _run(network, t, x0, cfg, method, reason, scale: float = 1.0, watch: tuple | None = None) -> SimResult:
    start = time.perf_counter()
    spy = _watch(network, *watch[:2]) if watch and method == "exact" else None
    if METHODS[method].exact:
        x, steps, calls, extra = METHODS[method].run(network, t, x0, cfg, scale, spy)
    else:
        from beltcalc.sim.scipy_methods import require_resolvable_inputs

        require_resolvable_inputs(network, float(t[-1]), cfg, method)
        x, steps, calls, extra = METHODS[method].run(network, t, x0, cfg)
    wall = time.perf_counter() - start
    if not np.all(np.isfinite(x)):
        raise SimulationError(f"method {method} gave non-finite values; try another `method`")
    result = _outputs(network, t, x, method, reason, wall, steps, calls, extra, extra.pop("generators", None),
                      extra.pop("rebased", None))
    if spy is not None:
        result.extremes = spy.result
        result.extra["watch_uncertain"] = spy.uncertain
        result.integrals = extra.pop("integrals")
        result.rigid_integrals = extra.pop("rigid_integrals", None)
        result.linear_rows = network.linear_rows()
        result.signal_integrals = {f"F_{k}": v for k, v in extra.pop("force_integrals").items()}
    return result


def _watch(network: Network, names, windows):
    """A :class:`beltcalc.sim.watch.Watch` of the named signals (states, coupling torques,
    strand forces) over the windows ``[start, t_end]``."""
    from beltcalc.sim.watch import Watch

    p = network.generators(0.0).size
    lin = network.linear_rows()
    _, force = network.strand_rows()
    strands = {f"F_{s.name}": k for k, s in enumerate(network.strands)}
    rows, strand, kept = [], [], []
    for name in names:
        if name in lin:
            rows.append(np.concatenate([lin[name], np.zeros(p)]))
            strand.append(-1)
        elif name in strands:
            rows.append(force[strands[name]])
            strand.append(strands[name])
        else:
            continue                 # not linear in the state (accelerations, drive torques): sampled
        kept.append(name)
    size = network.size + p
    return Watch(kept, np.array(rows).reshape(len(kept), size), np.array(strand, dtype=np.int64), list(windows))


def conditioning(network: Network, t_end: float) -> float:
    """The relative rounding floor of an exact run: machine epsilon times the stiffness ratio,
    taken as ||F~||_1 t_end (the balanced augmented matrix's norm over the run: how many of
    its fastest time constants the run spans)."""
    norm = network.__dict__.get("_balanced_norm")
    if norm is None:                           # a property of the network's matrices: once per network
        F, s = one_piece(network)
        norm = network.__dict__["_balanced_norm"] = float(np.abs(F / s[:, None] * s[None, :]).sum(axis=0).max())
    return EPS * norm * t_end


def estimate_error(result: SimResult, network: Network, x0: np.ndarray, cfg: SolverConfig,
                   reference: tuple[SimResult, str] | None = None, watch: tuple | None = None,
                   second=None) -> None:
    """Fill the result's error estimate: per speed signal, the largest difference to a second
    computation that shares neither rounding nor partition (exact: another internal step and
    another scaling of A h, at a subset of the samples where the run is one linear piece
    (:func:`reference_rows`); scipy's methods: the exact solution, or Radau at 1/100 of the
    tolerances where no exact solution exists), plus the conditioning floor
    :func:`conditioning` times the signal's scale.

    A run whose window figures come off the exact solution (``watch``, :func:`simulate`) is
    judged by them: the second computation is watched too, and the estimate is the largest
    difference of what the result reports (each watched signal's mean, least and largest
    value over each window), plus the conditioning floor and what the watch could not rule
    out (:attr:`beltcalc.sim.watch.Watch.uncertain`), each relative to its signal's scale.
    ``second``: a call that gives that second computation's :class:`Figures` (:func:`simulate`
    starts it beside the run, :func:`_beside`); default computed here.
    The trajectories' difference is kept beside it (``extra["trajectory_error"]``): near-grazing
    strand switches may shift a trajectory's phase between two partitions while its means and
    extremes agree (100 rollers)."""
    n, method, t = network.n, result.method, result.t
    speeds = result.states[n:2 * n]
    full = None                                 # the second computation's every state (scipy's methods)
    idx = None                                  # the samples compared (None: every one)
    widen = 1.0                                 # the difference times this is the estimate
    other = None                                # the second computation as a result (watched runs)
    if reference is not None:
        other, label = reference
        ref = other.states[n:2 * n]
        full = None if method == "exact" else other.states
    elif method == "exact" and watch and result.extremes:
        other = second() if second is not None else _second(network, t, x0, cfg, watch)
        ref = other.speeds
        label = "exact with another internal step and scaling of A h"
    elif method == "exact" and result.extra.get("one_piece"):
        F, balancing = one_piece(network)
        idx, ref = reference_rows(F, np.concatenate([x0, network.generators(0.0)]), float(t[1] - t[0]), t.size,
                                  range(n, 2 * n), balancing)
        label = "exact with another internal step and scaling of A h"
    elif method == "exact":
        ref = run_exact(network, t, x0, cfg, scale=ESTIMATE_STEP, rows=range(n, 2 * n))[0][n:2 * n]
        label = "exact with another internal step and scaling of A h"
    elif network.linear:
        full = run_exact(network, t, x0, cfg)[0]
        ref = full[n:2 * n]
        label = "exact solution"
    else:
        # the same explicit method (not stiff: it ran) or Radau, at 1/100 of the tolerances. A Radau
        # run of a network with smooth pieces (a polygon strand's seatings) is checked by DOP853 at
        # 1/10: it restarts at each piece without a Jacobian, where Radau at 1/100 refactors at every
        # kick and crawls (the roller table: 2.6 s of 7 in 300 s); DOP853 at 1/100 costs 3 times the
        # first run there, at 1/10 1.8 times
        second = method if method in ("dop853", "rk45") else ("dop853" if network.piecewise else "radau")
        share = 10 if second == "dop853" and method == "radau" else 100
        tight = SolverConfig(second, cfg.rtol / share, cfg.atol / share, cfg.max_rhs_calls, cfg.max_events, False)
        try:
            full = METHODS[second].run(network, t, x0, tight)[0]
            ref = full[n:2 * n]
        except SimulationError as e:
            raise SimulationError(f"the error estimate's second computation ({second} at 1/{share} of the "
                                  f"tolerances, rtol {tight.rtol:.2g}): {e}") from None
        label = f"{second} at 1/{share} of the tolerances"
        # the difference is the first run's error less the second's own: with the global error
        # about tol^(p/(p+1)) for order p (error per step controlled), the second's is
        # 100^(-p/(p+1)) of the first's (Radau p = 5: 2.2 %; DOP853 p = 8: 1.7 %): widen by it. A
        # Radau run checked by DOP853 at 1/10 is not checked by a better run (on the roller table with
        # the polygon action, against DOP853 at 1e-10: DOP853 at 1e-9 is off by 1.1e-6 rad/s, Radau at
        # 1e-8 by 2.6e-7): the difference is doubled, the bound where the two errors are alike
        order = {"radau": 5, "dop853": 8, "rk45": 4}[second]
        widen = 1.0 + share ** (-order / (order + 1)) if share == 100 else 2.0
    names = network.state_names()
    result.extra["error_tol"] = cfg.error_tol
    floor = conditioning(network, float(t[-1])) if network.linear else 0.0
    scales: dict[str, float] = {}
    peak = np.maximum(speeds.max(axis=1), -speeds.min(axis=1))    # max |speed| per row, no temporary
    diff = (speeds if idx is None else speeds[:, idx]) - ref
    apart = np.maximum(diff.max(axis=1), -diff.min(axis=1)) * widen
    for k in range(n, 2 * n):
        name, unit = names[k]
        scales[unit] = max(scales.get(unit, 0.0), float(peak[k - n]))
    errors, worst = {}, None
    for k in range(n, 2 * n):
        name, unit = names[k]
        scale = scales[unit] if scales[unit] > 0 else 1.0
        errors[name] = float(apart[k - n]) + floor * scale
        rel = errors[name] / scale
        if worst is None or rel > worst[0]:
            worst = (rel, k, name, unit, scale)
    if full is not None:
        worst = _elastic_errors(result, network, full, floor, errors, worst, widen)
    result.errors = errors
    rel, row, signal, unit, scale = worst[:5]
    result.error_relative, result.error_row, result.error_signal = float(rel), row, signal
    result.error_unit, result.error_scale = unit, float(scale)
    result.error_estimate = errors[result.error_signal]
    result.error_reference = label
    at = int(np.argmax(np.abs(diff[row - n])))
    result.error_at = worst[5] if len(worst) > 5 else float(t[at if idx is None else idx[at]])
    if other is not None and result.extremes and other.extremes:
        _figure_errors(result, other, floor, watch[2] if watch and len(watch) > 2 else None)


def _elastic_errors(result: SimResult, network: Network, full: np.ndarray, floor: float, errors: dict,
                    worst: tuple, widen: float = 1.0) -> tuple:
    """A scipy run's torques and forces judged as its speeds are: every coupling torque and
    strand force of the result against the same output of the second computation's states
    ``full`` (their differences times ``widen``), relative to the largest |value| of its unit; a
    nonlinear element's torques and forces too (``T_``/``F_`` outputs). A torque is a difference of two
    angles times a stiffness, so its relative error can be far above the speeds' (the sewing
    drive's T_23 with the eccentric roller: 4x); the error of what the run prints is the larger.
    Returns the worst (relative, row, name, unit, scale[, time]) so far."""
    t = result.t

    def elastic(X):
        out = {**{f"T_{k}": v for k, v in network.coupling_torques(X).items()},
               **{f"F_{k}": v for k, v in network.strand_forces(t, X).items()}}
        for el in network.elements:         # a nonlinear element's torques and forces (a carriage belt's)
            if el.nonlinear_kind:
                out.update({k: v for k, (v, unit) in el.outputs(network, t, X, None).items()
                            if k[:2] in ("T_", "F_") and unit in ("N", "N m")})
        return out

    mine, theirs = elastic(result.states), elastic(full)
    scales: dict[str, float] = {}
    for name, y in mine.items():
        unit = result.units.get(name, "N*m" if name.startswith("T_") else "N")
        scales[unit] = max(scales.get(unit, 0.0), float(np.max(np.abs(y))) if y.size else 0.0)
    for name, y in mine.items():
        unit = result.units.get(name, "N*m" if name.startswith("T_") else "N")
        scale = scales[unit] if scales[unit] > 0 else 1.0
        d = np.abs(y - theirs[name]) * widen
        errors[name] = float(d.max()) + floor * scale
        if errors[name] / scale > worst[0]:
            worst = (errors[name] / scale, worst[1], name, unit, scale, float(t[int(np.argmax(d))]))
    return worst


def _figure_errors(result: SimResult, other: SimResult | Figures, floor: float, reported: dict | None = None) -> None:
    """Judge a watched run by the figures it reports: per watched signal and window, the
    differences of mean, least and largest value to the second computation ``other``, plus
    the conditioning floor and the watch's uncertainty, relative to the largest |value| of
    the signals of its unit. ``reported`` ({signal: window starts}): the figures the caller
    reports, where it reports fewer than it watches (a shaft's torque over the window, not
    over the start-up); default every one watched. The worst becomes the result's estimate (``error_signal`` names
    the figure); the trajectories' worst relative difference goes to
    ``extra["trajectory_error"]``."""
    result.extra["trajectory_error"] = {"value": result.error_estimate, "unit": result.error_unit,
                                        "relative": result.error_relative, "signal": result.error_signal}
    scales: dict[str, float] = {}
    names = sorted({name for name, _ in result.extremes})
    for name in names:
        unit = result.units.get(name, "")
        y = result.signals[name]
        scales[unit] = max(scales.get(unit, 0.0), float(np.max(np.abs(y))) if y.size else 0.0)
    uncertain = result.extra.get("watch_uncertain", {})
    worst = None
    for (name, start) in sorted(result.extremes):
        if reported is not None and start not in reported.get(name, ()):
            continue
        unit = result.units.get(name, "")
        scale = scales[unit] if scales[unit] > 0 else 1.0
        a, b = result.summary(name, start), other.summary(name, start)
        lo_u, hi_u = uncertain.get((name, start), (0.0, 0.0))
        for what, x, y, u in (("mean", a.mean, b.mean, 0.0), ("min", a.min, b.min, lo_u), ("max", a.max, b.max, hi_u)):
            err = abs(x - y) + u + floor * scale
            label = f"{what} of {name} over t >= {start:g} s"
            result.errors[label] = err
            if worst is None or err / scale > worst[0]:
                worst = (err / scale, label, unit, scale, err)
    if worst is None:
        return
    rel, label, unit, scale, err = worst
    result.error_relative, result.error_signal, result.error_unit = float(rel), label, unit
    result.error_scale, result.error_estimate = float(scale), float(err)


def _outputs(network: Network, t, x, method, reason, wall, steps, calls, extra, g=None,
             rebased=None) -> SimResult:
    """States, accelerations and every element's outputs (:meth:`Network.outputs`), each an
    array expression over all samples. A run that is one linear piece (no strands, no time
    break points) takes its accelerations from one product, :func:`one_piece_accelerations`.
    ``g``: the generators at ``t`` where the run propagated them with the states (else they
    are evaluated here, once for every output). ``rebased``: the states with the free rigid
    rotations taken out (:meth:`beltcalc.sim.switching.Run.rebase`): every elastic output
    (a torque, a force: differences of angles) is computed from them, the angles from x."""
    n = network.n
    signals, units = {}, {}
    for (name, unit), row in zip(network.state_names(), x):
        signals[name], units[name] = row, unit
    network.seed_generators(t, network.generators(t) if g is None else g)
    if network.switched and "switched" in extra:
        network.seed_switched(t, switched_history(t, extra["switched"]))
    try:
        if network.smooth and network.linear:
            accel = one_piece_accelerations(network, t, x)
        else:
            accel = network.derivative(t, x)[n:2 * n]
        for k, (name, unit) in enumerate(network.accel_names()):
            signals[name], units[name] = accel[k], unit
        for name, (value, unit) in network.outputs(t, x if rebased is None else rebased, accel).items():
            signals[name], units[name] = value, unit
        if rebased is not None:                # the angles of geared nodes as they are
            for name, (value, unit) in network.node_signals(x, accel).items():
                signals[name], units[name] = value, unit
    finally:
        network.seed_generators(t, None)
        network.seed_switched(None, None)
    return SimResult(t=t, signals=signals, units=units, method=method, reason=reason, wall_time=wall,
                     steps=steps, rhs_calls=calls, states=x, extra=extra)


def one_piece_accelerations(network: Network, t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The coordinates' accelerations, rows ``n:2n`` of x' = A x + B g(t), over every sample
    of a run that is one linear piece (a smooth linear network): one product for every row,
    one more for the rows an input drives; no grouping of the samples by strand pattern or
    time piece, and none of x' 's other rows."""
    A, B = network.first_order()
    n = network.n
    accel = A[n:2 * n] @ x
    rows = np.flatnonzero(B[n:2 * n].any(axis=1))     # the rows an input drives (few)
    if rows.size:
        accel[rows] += B[n + rows] @ network.generators(t)
    return accel
