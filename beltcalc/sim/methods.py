"""The registry of the core's methods: one :class:`Method` record per name. The core
dispatches on it, the CLI's ``--method`` choices and the work-precision tables read it, and
a new method is one record here. Nothing is imported at module level but the standard
library: a record names its runner as ``"module:function"``, imported on its first run (the
exact path never loads scipy). :func:`choose_method` picks one for a network.

References:

[HW96] E. Hairer, G. Wanner, Solving Ordinary Differential Equations II: Stiff and
    Differential-Algebraic Problems, 2nd ed., Springer (1996): the stability domains of the
    explicit Dormand-Prince methods [HW96 sec. IV.2].

>>> [m.name for m in METHODS.values() if m.explicit]
['rk45', 'dop853']
>>> NAMES[:3]
('auto', 'exact', 'radau')
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass


@dataclass(frozen=True)
class SolverConfig:
    """method: auto | exact | radau | bdf | lsoda | odeint | rk45 | dop853;
    rtol/atol for the step-size-controlled methods; max_rhs_calls bounds a run;
    max_events bounds the strand switches (a strand chattering near zero tension);
    estimate_error: run a second, independent computation and report the difference;
    max_seconds bounds the computing time of a scipy run (besides max_rhs_calls: a model
    many decades stiffer in one part crawls at a few thousand calls a second);
    error_tol: the largest error estimate accepted, relative to the signal's scale (the
    largest speed of its unit over the run); accept_error: return a result whose estimate
    exceeds it (marked) instead of failing."""

    method: str = "auto"
    rtol: float = 1e-8
    atol: float = 1e-10
    max_rhs_calls: int = 5_000_000
    max_events: int = 20_000
    estimate_error: bool = True
    error_tol: float = 1e-6
    accept_error: bool = False
    max_seconds: float = 120.0     # computing time a scipy run may take (an ill-conditioned model crawls)


@dataclass(frozen=True)
class Method:
    """One method of :func:`beltcalc.sim.core.simulate`.

    ``runner(network, t, x0, cfg)`` returns ``(x, steps, rhs_calls, extra)``; the exact
    method's also takes ``scale`` (another internal partition, for the error estimate) and
    ``watch``. ``exact``: propagated exactly between switches (needs a network linear between
    them); ``explicit``: an explicit Runge-Kutta pair (stiff systems exhaust its budget);
    ``jacobian``: takes the analytic Jacobian."""

    name: str
    runner: str
    summary: str
    exact: bool = False
    explicit: bool = False
    jacobian: bool = False

    def run(self, *args, **kwargs):
        module, _, function = self.runner.partition(":")
        return getattr(importlib.import_module(module), function)(*args, **kwargs)


METHODS: dict[str, Method] = {m.name: m for m in (
    Method("exact", "beltcalc.sim.core:run_exact", "exact propagation between switches (linear networks)",
           exact=True),
    Method("radau", "beltcalc.sim.scipy_methods:radau", "scipy Radau IIA, implicit, order 5", jacobian=True),
    Method("bdf", "beltcalc.sim.scipy_methods:bdf", "scipy BDF, implicit, orders 1-5", jacobian=True),
    Method("lsoda", "beltcalc.sim.scipy_methods:lsoda", "scipy LSODA (solve_ivp), stiff/non-stiff switching",
           jacobian=True),
    Method("odeint", "beltcalc.sim.scipy_methods:odeint_run", "scipy odeint (LSODA, Dfun), no events",
           jacobian=True),
    Method("rk45", "beltcalc.sim.scipy_methods:rk45", "scipy RK45, explicit", explicit=True),
    Method("dop853", "beltcalc.sim.scipy_methods:dop853", "scipy DOP853, explicit, order 8", explicit=True),
)}

#: every name ``method`` takes: ``auto`` (exact where the network allows it, else radau) and the registry's
NAMES: tuple[str, ...] = ("auto", *METHODS)


EXPLICIT_STEPS = 2e4        # stable explicit steps up to which auto runs a nonlinear network on DOP853


def explicit_steps(network, t_end: float) -> tuple[float, float]:
    """(the fewest steps an explicit method (DOP853) takes over ``t_end`` [s] for stability,
    the steps it takes anyway to follow the fastest lightly damped oscillation): the linear
    part's spectral radius rho (its fastest pole, the nonlinear terms' Jacobian at rest
    included) times ``t_end`` over the stability bound of DOP853, about 3.3 on the negative
    real axis [HW96 sec. IV.2]; the largest |pole| of damping ratio below 0.7 times
    ``t_end`` over 0.3 (the step of an accurate explicit run, about 0.3 of 1/w). Where the
    first is not the larger, the drive is not stiff for an explicit method: its stability costs
    nothing the oscillation did not."""
    import numpy as np

    A, _ = network.first_order(None, 0.0)
    if not network.linear:
        A = A + network.nonlinear_jacobian(network.initial_state())
    lam = np.linalg.eigvals(A) if A.size else np.zeros(0)
    radius = float(np.max(np.abs(lam))) if lam.size else 0.0
    floor = 1e-7 * max(radius, 1.0)
    swing = [abs(s) for s in lam if s.imag > floor and -s.real < 0.7 * abs(s)]
    return radius * t_end / 3.3, max(swing, default=0.0) * t_end / 0.3


def choose_method(network, requested: str, t_end: float | None = None) -> tuple[str, str]:
    """The method to run and why. A nonlinear network without switches that is not stiff
    over ``t_end`` (an explicit method is stable in no more steps than following its fastest
    lightly damped oscillation takes, and in at most :data:`EXPLICIT_STEPS`:
    :func:`explicit_steps`) runs on DOP853, else on Radau."""
    if requested == "auto":
        if network.linear and network.smooth:
            return "exact", "auto: the network is linear with inputs in time, so its exact solution is used"
        if network.linear:
            return "exact", ("auto: the network is linear between strand switches and time break points, so it "
                             "is propagated exactly and each switch is located on the exact solution")
        why = sorted({getattr(el, "nonlinear_reason", "loads locked to a shaft angle")
                      for el in network.elements if el.nonlinear_kind})
        if t_end is not None and not network.strands and not network.switched:
            stable, follow = explicit_steps(network, t_end)
            if stable <= min(follow, EXPLICIT_STEPS):
                return "dop853", (f"auto: {'; '.join(why)}: the network is nonlinear and not stiff (an explicit "
                                  f"method is stable in {stable:.3g} steps, fewer than following its fastest "
                                  f"oscillation takes), so DOP853 (explicit, order 8)")
        return "radau", (f"auto: {'; '.join(why)}: the network is nonlinear; implicit Radau with the analytic "
                         "Jacobian")
    if requested not in METHODS:
        from beltcalc.errors import InputError

        raise InputError(f"{requested!r} is not a method; use one of {', '.join(NAMES)}", param="method")
    return requested, "requested"
