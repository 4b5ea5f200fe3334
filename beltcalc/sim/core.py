"""The one place that integrates. Methods by name from a registry:

- ``exact``: linear time-invariant networks with constant and sinusoidal inputs. The state
  is augmented with the inputs' generators (g' = G g), and the augmented system z' = F z
  is propagated with the one-step matrix expm(F dt) (scipy's scaling and squaring), in
  blocks: the powers P_r = expm(F dt)^r, r < b, are applied to every block start at once.
  No eigen-decomposition: on the sewing model its eigenvector matrix has a condition
  number near 1e13 and loses about 0.1 rad/s.
- ``radau``, ``bdf``, ``lsoda``: scipy's ``solve_ivp`` with the analytic Jacobian (a
  callable, which LSODA needs); ``odeint``: scipy's older LSODA wrapper with ``Dfun``, the
  same algorithm with less overhead per step; ``rk45``, ``dop853`` for comparison.
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
    estimate_error: run the reference (half-step exact, or exact) and report the difference."""

    method: str = "auto"
    rtol: float = 1e-8
    atol: float = 1e-10
    max_rhs_calls: int = 5_000_000
    estimate_error: bool = True


class _Budget(Exception):
    pass


def _initial(network: Network, x0: np.ndarray | None) -> np.ndarray:
    x = network.initial_state() if x0 is None else np.asarray(x0, dtype=float)
    if x.shape != (network.size,):
        raise InputError(f"initial state has {x.size} values; the network has {network.size}", param="x0")
    return x


def augmented_matrix(network: Network) -> np.ndarray:
    """F of z' = F z with z = [x, g]: the network and its input generators."""
    A, B = network.state_matrix(), network.input_matrix()
    m, p = A.shape[0], B.shape[1]
    F = np.zeros((m + p, m + p))
    F[:m, :m] = A
    F[:m, m:] = B
    for k, w in enumerate(network.frequencies()):
        s, c = m + 1 + 2 * k, m + 2 + 2 * k
        F[s, c] = w      # (sin w t)' = w cos w t
        F[c, s] = -w     # (cos w t)' = -w sin w t
    return F


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


def _exact(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    if not network.linear:
        raise InputError("the exact method needs a linear network with constant or sinusoidal inputs; this "
                         "one has loads locked to a shaft angle, tabulated loads or a prescribed acceleration: "
                         "use --method radau (or auto)", param="method")
    dt = t[1] - t[0]
    F = augmented_matrix(network)
    z0 = np.concatenate([x0, network.generators(0.0)])
    z = _propagate(F, z0, dt, t.size)
    return z[:network.size], t.size - 1, 0, {}


def _rhs_and_jac(network: Network, budget: list[int]):
    A, B = network.state_matrix(), network.input_matrix()
    nonlinear = not network.linear
    freqs = network.frequencies()

    def g(t):
        out = [1.0]
        for w in freqs:
            out += [math.sin(w * t), math.cos(w * t)]
        return np.array(out)

    def rhs(t, x):
        budget[0] += 1
        if budget[0] > budget[1]:
            raise _Budget(t)
        dx = A @ x + B @ g(t)
        if nonlinear:
            dx += network.nonlinear_terms(t, x)
        return dx

    def jac(t, x):
        return A + network.nonlinear_jacobian(x) if nonlinear else A

    return rhs, jac


def _ivp(name: str, uses_jac: bool):
    def run(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
        budget = [0, cfg.max_rhs_calls]
        rhs, jac = _rhs_and_jac(network, budget)
        kwargs = {"jac": jac} if uses_jac else {}
        try:
            sol = solve_ivp(rhs, (t[0], t[-1]), x0, method=name, t_eval=t, rtol=cfg.rtol, atol=cfg.atol, **kwargs)
        except _Budget as stop:
            raise SimulationError(_budget_message(name, stop.args[0], cfg)) from None
        if sol.status != 0:
            reached = sol.t[-1] if sol.t.size else t[0]
            raise SimulationError(f"method {name.lower()} failed at t = {reached:.6g} s: {sol.message}; "
                                  "try --method radau or bdf, or looser --rtol/--atol")
        return sol.y, int(sol.nfev), int(sol.nfev), {"jacobians": int(sol.njev), "lu": int(sol.nlu)}
    return run


def _odeint(network: Network, t: np.ndarray, x0: np.ndarray, cfg: SolverConfig):
    budget = [0, cfg.max_rhs_calls]
    rhs, jac = _rhs_and_jac(network, budget)
    try:
        y, info = odeint(rhs, x0, t, Dfun=jac, rtol=cfg.rtol, atol=cfg.atol, full_output=True,
                         tfirst=True, mxstep=max(500, cfg.max_rhs_calls // max(t.size, 1)))
    except _Budget as stop:
        raise SimulationError(_budget_message("odeint", stop.args[0], cfg)) from None
    if info["message"] != "Integration successful.":
        reached = float(info["tcur"][-1]) if len(info["tcur"]) else t[0]
        raise SimulationError(f"method odeint failed at t = {reached:.6g} s: {info['message']}; "
                              "try --method radau, or looser --rtol/--atol")
    return y.T, int(info["nst"][-1]), int(info["nfe"][-1]), {"jacobians": int(info["nje"][-1])}


def _budget_message(method: str, reached: float, cfg: SolverConfig) -> str:
    return (f"method {method.lower()} stopped at t = {reached:.6g} s after {cfg.max_rhs_calls} right-hand-side "
            "calls (the system is stiff for an explicit method?); try --method radau, bdf or exact")


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
        if network.linear:
            return "exact", "auto: the network is linear with inputs in time, so its exact solution is used"
        return "radau", ("auto: angle-locked or tabulated loads or a prescribed acceleration make the network "
                         "nonlinear or time-varying; implicit Radau with the analytic Jacobian")
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
        tight = SolverConfig("radau", cfg.rtol / 100, cfg.atol / 100, cfg.max_rhs_calls, False)
        ref = METHODS["radau"](network, result.t, x0, tight)[0][n:2 * n]
        label = "radau at 1/100 of the tolerances"
    result.error_estimate = float(np.max(np.abs(speeds - ref)))
    result.error_reference = label


def _outputs(network: Network, t, x, method, reason, wall, steps, calls, extra) -> SimResult:
    n = network.n
    signals, units = {}, {}
    for (name, unit), row in zip(network.state_names(), x):
        signals[name], units[name] = row, unit
    dx = network.state_matrix() @ x + network.input_matrix() @ network.generators(t)
    if not network.linear:
        dx += np.column_stack([network.nonlinear_terms(t[k], x[:, k]) for k in range(t.size)])
    for k, node in enumerate(network.nodes):
        signals[f"accel_{node.name}"], units[f"accel_{node.name}"] = dx[n + k], "rad/s^2"
    for name, torque in network.coupling_torques(x).items():
        signals[f"T_{name}"], units[f"T_{name}"] = torque, "N m"
    for node, torque in network.load_torques(t, x).items():
        signals[f"load_{node}"], units[f"load_{node}"] = np.broadcast_to(torque, t.shape).copy(), "N m"
    for node, torque in network.drive_torques(t, x, dx).items():
        signals[f"T_drive_{node}"], units[f"T_drive_{node}"] = np.broadcast_to(torque, t.shape).copy(), "N m"
    return SimResult(t=t, signals=signals, units=units, method=method, reason=reason, wall_time=wall,
                     steps=steps, rhs_calls=calls, states=x, extra=extra)
