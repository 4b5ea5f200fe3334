"""Outputs and derivatives as array expressions (issue 17, "fast outputs"), the exact
propagation into one preallocated array, and the imports of the exact path.

The reference is the implementation these replaced, kept below as it was (``_old_*``):
``Network.derivative`` grouped the samples by (strand pattern, time piece) with
``np.unique`` and added each taut strand's stamps 512 samples at a time with
``np.add.at``; ``Network.outputs`` asked every element for its own outputs; the exact
propagation built every sample in a temporary of (samples, states) and transposed it.
The two sum the same terms in another order, so they agree to rounding, and "rounding" is a
bound, not a fixed 1e-12 (another BLAS kernel orders a product's sums otherwise: run the file
with ``OPENBLAS_CORETYPE=Haswell``, ``Nehalem``, ``Sandybridge``, ``Prescott``):

* an acceleration is a dot product of a row of ``[A B]`` with ``[x; g]``; with stiff couplings
  its terms (k times an angle of hundreds of radians) are 1e4 times the acceleration, so two
  orders of summation differ by up to ``2 m eps sum|a_i z_i|`` (the forward error bound of a
  sum of ``m`` terms, each side), which :func:`_rounding` computes from the terms' magnitudes
  (measured: 6e-11 of the acceleration's scale on the sewing scene, OpenBLAS Prescott kernels;
  the bound there is 4e-9, and a stiffness off by 1e-6 of itself moves it 100 times further:
  :func:`test_the_rounding_bound_is_tight_enough_to_catch_a_wrong_term`);
* every other signal is the same element's formula on the same states, held to the run's own
  error estimate relative to the signal's scale (``error_relative``: 1e-13 .. 2e-10 here), the
  method's stated error: below it the two are the same result, and a wrong formula is off by
  far more. A run whose free rigid rotations were re-based out of the angles
  (:meth:`beltcalc.sim.switching.Run.rebase`) computes its elastic outputs from the re-based
  states; the old outputs are computed from the same states (:func:`_run` catches them).
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim import core
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.drivefile import load_drive
from beltcalc.sim.elements import Coupling, Prescribed
from beltcalc.sim.network import (Gear, Inertia, Load, Network, Prescribed as Pres, SpeedLoop, Strand)
from beltcalc.sim.scenes import SCENES
from beltcalc.numerics.balance import balance
from beltcalc.numerics.expm import expm
from beltcalc.sim import propagate as prop

EPS = float(np.finfo(float).eps)
# the built-in drives the old implementation can run: not those with elements that have modes of
# their own (clutches, brakes, friction, torque limits, issue 31), which it predates: each sample's
# mode is the run's, not one its state tells (tests/test_switched.py holds those to Radau); nor
# those with a carriage belt whose spans follow the carriage (issue 32): nonlinear, no exact run
# (tests/test_belt_axis.py holds it to Radau)
DRIVES = sorted(p.stem for p in (Path(__file__).parent.parent / "catalogs" / "drives").glob("*.toml")
                if not any(k in p.read_text() for k in ("[[clutch]]", "[[brake]]", "[[friction]]", "torque_limit",
                                                        "[[carriage_belt]]")))


# --- the implementation before issue 17, kept as it was ------------------------------------------
def _old_derivative(net, t, x, constrained=True, magnitude=False, generators=None):
    """``magnitude`` (the tests' addition, not the old code's): the same sums over the terms'
    magnitudes, ``|A| |x| + |B| |g|`` and the strands' ``|stamp| |z|``, for :func:`_rounding`;
    ``generators`` then stands in for ``g``."""
    x = np.asarray(x, dtype=float)
    single = x.ndim == 1
    X = x[:, None] if single else x
    T = np.broadcast_to(np.asarray(t, dtype=float), (X.shape[1],))
    t_end = float(T.max())
    starts = net.segment_starts(t_end)
    seg = np.searchsorted(starts, T, side="right") - 1
    taut = net.taut_of(X, T) if net.strands else np.ones((0, X.shape[1]), bool)
    G = net.generators(T)
    size = (lambda M: np.abs(M)) if magnitude else (lambda M: M)
    if magnitude:
        assert net.linear                       # (the nonlinear terms have no such sum)
        X, G = np.abs(X), np.abs(G if generators is None else np.broadcast_to(generators, G.shape))
    out = np.empty_like(X)
    if net.strands and (constrained or not net.fixed):
        none = tuple(False for _ in net.strands)
        for sg in np.unique(seg):
            cols = seg == sg
            A, B = net.first_order(none, net.piece_time(int(sg), starts, t_end), constrained)
            out[:, cols] = size(A) @ X[:, cols] + size(B) @ G[:, cols]
        owner, rows, where, vals = net.strand_stamps()
        Z = np.vstack([X, G])
        for a in range(0, X.shape[1], 512):
            b = min(a + 512, X.shape[1])
            part = np.zeros((net.size, b - a))
            np.add.at(part, rows, size(vals)[:, None] * Z[where, a:b] * taut[owner, a:b])
            out[:, a:b] += part
    else:
        keys = np.concatenate([taut, seg[None, :]]).T
        uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
        for q, key in enumerate(uniq):
            cols = inverse.ravel() == q
            A, B = net.first_order(tuple(bool(v) for v in key[:-1]),
                                   net.piece_time(int(key[-1]), starts, t_end), constrained)
            out[:, cols] = size(A) @ X[:, cols] + size(B) @ G[:, cols]
    if not net.linear:
        out += net.nonlinear_terms(T, X, constrained)
    return out[:, 0] if single else out


def _rounding(net, t, x, constrained=True, generators_error=0.0):
    """How far two evaluations of the derivative at (t, x) may differ by rounding alone: each
    is a sum of at most ``m`` terms per row (states, generators, strand stamps), whose computed
    value is within ``m eps sum|terms|`` of the exact one whatever the order of summation
    (``|x'y - fl(x'y)| <= gamma_m |x|'|y|``, ``gamma_m = m u / (1 - m u)``, ``u = eps / 2``:
    Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., section 3.1), so twice that
    between the two; plus ``|B| generators_error`` where one side reads the generators off
    the propagation instead of evaluating them (test_propagated_generators_...)."""
    m = net.size + net.generators(0.0).size + (len(net.strand_stamps()[3]) if net.strands else 0)
    terms = _old_derivative(net, t, x, constrained, magnitude=True)
    bound = 2 * m * EPS * terms
    if generators_error:
        bound = bound + _old_derivative(net, t, np.zeros_like(x), constrained, magnitude=True,
                                        generators=generators_error)
    return bound


def _old_strand_forces(net, t, x):
    if not net.strands:
        return {}
    z = np.vstack([x, net.generators(t)])
    delta, force = net.strand_rows()
    f = force @ z
    on = (delta @ z > 0) & (f > 0)
    return {s.name: np.where(on[k], f[k], 0.0) for k, s in enumerate(net.strands)}


def _old_node_signals(net, x, dx):
    n, out = net.n, {}
    for k, nd in enumerate(net.nodes):
        if nd.name in net.index:
            continue
        row = net.T[k]
        lin = "m" if nd.translation else "rad"
        out[f"{'x' if nd.translation else 'phi'}_{nd.name}"] = (row @ x[:n], lin)
        out[f"{'v' if nd.translation else 'omega'}_{nd.name}"] = (row @ x[n:2 * n], f"{lin}/s")
        out[f"accel_{nd.name}"] = (row @ dx[n:2 * n], f"{lin}/s^2")
    return out


def _old_element_outputs(net, el, t, x, dx):
    if isinstance(el, Prescribed):      # it asked the network's derivative: the old one here
        c, f = net.coord(el.node)
        free = _old_derivative(net, t, x, constrained=False)
        unit = "N" if net.node(el.node).translation else "N m"
        return {f"T_drive_{el.node}": (net.mass[c] * (dx[net.n + c] - free[net.n + c]) / f, unit)}
    return el.outputs(net, t, x, dx[net.n:2 * net.n])


def _old_signals(net, t, x, rebased=None):
    """What core._outputs gave: states, accelerations, then Network.outputs. ``rebased`` (the
    tests' addition): the states the run took its elastic outputs from, the free rigid
    rotations taken out (core._outputs's argument of that name), for the elements' outputs."""
    n = net.n
    xe = x if rebased is None else rebased
    signals = {name: (row, unit) for (name, unit), row in zip(net.state_names(), x)}
    dx = _old_derivative(net, t, x)
    for k, (name, unit) in enumerate(net.accel_names()):
        signals[name] = (dx[n + k], unit)
    out = {}
    for el in net.couplings:
        out.update(el.outputs(net, t, xe, dx[n:2 * n]))
    for name, force in _old_strand_forces(net, t, xe).items():
        out[f"F_{name}"] = (force, "N")
    for el in net.elements:
        if isinstance(el, Coupling):
            continue
        for name, (value, unit) in _old_element_outputs(net, el, t, xe, dx).items():
            if name in out and name.startswith("load_"):
                value = out[name][0] + value
            out[name] = (np.array(value, dtype=float, copy=True), unit)
    out.update(_old_node_signals(net, x, dx))
    signals.update(out)
    return signals


def _old_propagate(F, z0, dt, samples, parts=1):
    m = F.shape[0]
    scale = balance(F)
    Ft = F / scale[:, None] * scale[None, :]
    step = np.linalg.matrix_power(expm(Ft * (dt / parts)), parts)   # the scheme is tested, not expm
    b = max(1, min(samples, int(math.ceil(math.sqrt(samples)))))
    powers = prop.matrix_orbit(step, b)
    jump = step @ powers[b - 1]
    nblocks = -(-samples // b)
    starts = prop.orbit(jump, z0 / scale, nblocks)
    q = powers.transpose(2, 0, 1).reshape(m, b * m)
    z = (starts @ q).reshape(nblocks * b, m)
    return z[:samples].T * scale[:, None]


# --- the networks: the three scenes and every built-in drive file -------------------------------
def _scene(name):
    scene = SCENES[name]
    values = dict(scene.values())
    if name == "roller-table":
        values["rollers"] = 3
    t_end, samples = scene.timing(dict(values))
    return scene.build(dict(values)), t_end, samples


def _drive(name):
    d = load_drive(name)
    return d.network, d.t_end, d.samples


def _mixed():
    """Strands beside a prescribed node (the unconstrained derivative of its drive torque),
    a speed loop, a rigid gear, a massless node condensed out, a tabulated and a phased,
    delayed sinusoidal load."""
    nodes = [Inertia("d", 2e-3), Inertia("a", 1e-3), Inertia("g", 4e-4), Inertia("m", 0.0), Inertia("b", 5e-3),
             Inertia("s", 1e-3)]
    couplings = [Coupling("da", "d", "a", 400.0, 0.2), Coupling("gm", "g", "m", 800.0, 0.4),
                 Coupling("mb", "m", "b", 800.0, 0.4)]
    loads = [Load("b", 0.3, 0.2, 40.0, phase=0.7, start=0.05), Load("b", 0.1, table=((0.0, 0.0), (0.1, 0.5))),
             Load("s", 0.05, 0.1, 40.0)]
    strands = [Strand("ab", "a", "s", 0.03, 0.03, 2e5, 30.0, preload=20.0),
               Strand("sa", "s", "a", 0.03, 0.03, 2e5, 30.0, preload=20.0)]
    return (Network(nodes,
                    [*couplings, *loads, Pres("d", 50.0, ((0.0, 100.0), (0.1, -50.0))), *strands, Gear("a", "g", 2.0),
                     SpeedLoop("b", 0.5, ((0.0, 0.0), (0.2, 10.0)))]), 0.3, 3001)


CASES = {**{f"scene {n}": (lambda n=n: _scene(n)) for n in SCENES},
         **{f"drive {n}": (lambda n=n: _drive(n)) for n in DRIVES},
         "mixed network": _mixed}


def _close(new: np.ndarray, old: np.ndarray, rtol: float) -> None:
    """Row by row: rtol, and rtol of the row's largest magnitude as its absolute tolerance."""
    new, old = np.atleast_2d(new), np.atleast_2d(old)
    assert new.shape == old.shape
    for k, (a, b) in enumerate(zip(new, old)):
        assert_allclose(a, b, rtol=rtol, atol=rtol * float(np.max(np.abs(b))), err_msg=f"row {k}")


def _within(new: np.ndarray, old: np.ndarray, bound: np.ndarray) -> None:
    """Row by row, to the row's largest rounding bound (:func:`_rounding`)."""
    new, old, bound = np.atleast_2d(new), np.atleast_2d(old), np.atleast_2d(bound)
    assert new.shape == old.shape == bound.shape
    for k, (a, b, e) in enumerate(zip(new, old, bound)):
        assert_allclose(a, b, rtol=0, atol=float(e.max()), err_msg=f"row {k}")


def _run(monkeypatch, net, t_end, samples, cfg):
    """simulate(), and the re-based states core._outputs took its elastic outputs from (None
    where the run did not re-base)."""
    seen = {}
    real = core._outputs

    def spy(*args, **kwargs):
        seen["rebased"] = kwargs.get("rebased", args[10] if len(args) > 10 else None)
        return real(*args, **kwargs)

    monkeypatch.setattr(core, "_outputs", spy)
    return simulate(net, t_end, samples, cfg), seen.get("rebased")


def _same(net, r, old: dict, rtol: float, loads_rtol: float | None = None, generators_error: float = 0.0) -> None:
    """Every signal to ``rtol`` of its scale (the method's stated error, relative); the
    accelerations to that or their rounding bound (:func:`_rounding`), whichever is larger;
    loads to ``loads_rtol``: an exact run of one linear piece reads a load's sine off its
    propagated generators (the very values that drove its states), which differ from
    ``sin w t`` by the propagation's rounding, ``generators_error`` (6e-12 after the sewing
    scene's 10^4 steps, :func:`test_propagated_generators_are_the_sines_to_rounding`)."""
    new = r.signals
    assert list(new) == list(old)          # the same signals in the same order (CSV columns)
    n = net.n
    accel = {name: k for k, (name, _) in enumerate(net.accel_names())}
    bound = _rounding(net, r.t, r.states, generators_error=generators_error)[n:2 * n]
    for name, (value, unit) in old.items():
        got = new[name]
        assert got.shape == np.shape(value), name
        scale = float(np.max(np.abs(value))) if np.size(value) else 0.0
        tol = loads_rtol if loads_rtol is not None and name.startswith("load_") else rtol
        atol = tol * scale
        if name in accel:
            atol = max(atol, float(bound[accel[name]].max()))
        assert_allclose(got, value, rtol=0, atol=atol, err_msg=name)


@pytest.mark.parametrize("case", list(CASES))
def test_outputs_equal_the_old_ones_to_rounding(case, monkeypatch):
    net, t_end, samples = CASES[case]()
    r, rebased = _run(monkeypatch, net, t_end, samples, SolverConfig("exact", accept_error=True))
    old = _old_signals(net, r.t, r.states, rebased)
    # the tolerance: the run's own error estimate (1e-13 .. 2e-10 of the scale on these runs)
    assert 0 < r.error_relative < 1e-9
    _same(net, r, old, r.error_relative, loads_rtol=samples * 1e-15, generators_error=samples * 1e-15)
    assert all(r.units[k] == u for k, (_, u) in old.items())


def test_propagated_generators_are_the_sines_to_rounding():
    # the one-piece exact run propagates g = [1, sin w t, cos w t] with the states; its rounding
    # grows with the number of steps (6e-12 here), far below the states' own error estimate
    net, t_end, samples = _scene("sewing")
    t = np.linspace(0.0, t_end, samples)
    x, _, _, info = core.run_exact(net, t, net.initial_state(), SolverConfig("exact"))
    g = info["generators"]
    assert g.shape == (net.generators(0.0).size, samples)
    assert_allclose(g, net.generators(t), rtol=0, atol=samples * 1e-15)


@pytest.mark.parametrize("case", list(CASES))
def test_derivative_equals_the_old_one_both_ways(case):
    net, t_end, samples = CASES[case]()
    r = simulate(net, t_end, samples, SolverConfig("exact", accept_error=True, estimate_error=False))
    for constrained in (True, False):
        _within(net.derivative(r.t, r.states, constrained), _old_derivative(net, r.t, r.states, constrained),
                _rounding(net, r.t, r.states, constrained))
    k = samples // 3                          # one state, one time
    _within(net.derivative(r.t[k], r.states[:, k])[:, None], _old_derivative(net, r.t[k], r.states[:, k])[:, None],
            _rounding(net, r.t[k], r.states[:, k])[:, None])


def test_the_rounding_bound_is_tight_enough_to_catch_a_wrong_term():
    # the bound must not swallow a real difference: the stiffest coupling's term off by 1e-6
    # of itself moves an acceleration of the sewing scene 100 times further than the bound
    net, t_end, samples = _scene("sewing")
    r = simulate(net, t_end, samples, SolverConfig("exact", estimate_error=False))
    A, _ = net.first_order()
    n = net.n
    bound = _rounding(net, r.t, r.states)[n:2 * n]
    k, j = np.unravel_index(int(np.argmax(np.abs(A[n:2 * n, :n]))), (n, n))
    wrong = A[n + k, j] * 1e-6 * r.states[j]
    assert float(np.abs(wrong).max()) > 100 * float(bound[k].max())


def test_odeint_run_outputs_equal_the_old_ones():
    # the scipy path evaluates the generators itself (no propagated ones). No error estimate
    # here: every signal to the run's own tolerance (rtol 1e-6) of its scale, the accelerations
    # also to their rounding bound. Measured: 4e-11 of the scale on the accelerations (OpenBLAS
    # Nehalem kernels), 4e-13 on a coupling's torque (k times a difference of two angles of
    # 200 rad): far below the tolerance; a wrong term in a formula is far above it
    net, t_end, samples = _scene("sewing")
    r = simulate(net, t_end, 2001, SolverConfig("odeint", rtol=1e-6, atol=1e-8, estimate_error=False))
    _same(net, r, _old_signals(net, r.t, r.states), 1e-6)


def test_a_run_of_one_linear_piece_takes_the_shortcut(monkeypatch):
    calls = []
    real = core.one_piece_accelerations
    monkeypatch.setattr(core, "one_piece_accelerations", lambda *a: calls.append(1) or real(*a))
    net, t_end, samples = _scene("sewing")
    r = simulate(net, t_end, samples, SolverConfig("exact"))
    assert calls == [1]
    _same(net, r, _old_signals(net, r.t, r.states), r.error_relative, loads_rtol=samples * 1e-15,
          generators_error=samples * 1e-15)
    # a network with time breaks or strands does not take it
    calls.clear()
    net, t_end, samples = _scene("roller-table")
    simulate(net, t_end, 601, SolverConfig("exact", accept_error=True, estimate_error=False))
    assert calls == []


@pytest.mark.parametrize("samples, parts", [(10001, 1), (10001, 3), (10000, 1), (2, 1), (17, 3), (9, 1)])
def test_propagation_into_one_array_equals_the_old_one(samples, parts):
    net, t_end, _ = _scene("sewing")
    F = prop.augmented_matrix(net)
    z0 = np.concatenate([net.initial_state(), net.generators(0.0)])
    dt = t_end / (samples - 1)
    old = _old_propagate(F, z0, dt, samples, parts)
    new = prop.propagate(F, z0, dt, samples, parts)
    assert new.shape == old.shape and new.flags.c_contiguous
    # the same scheme, its products grouped otherwise: to twice the propagation's stated rounding
    # floor, eps ||F~|| t_end of each row's scale (core.conditioning: 1.4e-10 here; the error
    # estimate adds the same floor to every exact run)
    floor = 2 * core.conditioning(net, t_end)
    _close(new, old, floor)
    some = prop.propagate(F, z0, dt, samples, parts, rows=np.arange(5, 10))
    _close(some, new[5:10], floor)


def test_the_error_estimates_reference_is_the_other_partition_at_its_samples():
    # a run of one linear piece compares its speeds with the other partition (expm(F~ dt/3)^3)
    # at every (b+1)-th sample and the last (propagate.reference_rows): those samples are what a
    # whole second propagation gives there, and the estimate is the largest difference over
    # them plus the conditioning floor
    net, t_end, samples = _scene("sewing")
    t = np.linspace(0.0, t_end, samples)
    x0 = net.initial_state()
    n = net.n
    full = core.run_exact(net, t, x0, SolverConfig("exact"), scale=0.7)[0]
    F, scale = prop.one_piece(net)
    idx, ref = prop.reference_rows(F, np.concatenate([x0, net.generators(0.0)]), t[1] - t[0], samples,
                                   range(n, 2 * n), scale)
    b = math.ceil(math.sqrt(samples))
    assert idx[-1] == samples - 1 and np.all(np.diff(idx)[:-1] == b + 1)
    assert len(set(idx[:-1] % b)) == len(idx) - 1                # every sample at another offset in its block
    # the same partition by two chains of products: to twice the rounding floor (as above)
    floor = 2 * core.conditioning(net, t_end)
    assert_allclose(ref, full[n:2 * n][:, idx], rtol=0, atol=floor * float(np.abs(full[n:2 * n]).max()))
    r = simulate(net, t_end, samples, SolverConfig("exact"))
    speeds = r.states[n:2 * n]
    units = [u for _, u in net.state_names()[n:2 * n]]
    scale_of = {u: max(float(np.abs(speeds[j]).max()) for j in range(n) if units[j] == u) for u in units}
    expected = max(float(np.abs(speeds[j][idx] - ref[j]).max()) / scale_of[units[j]] for j in range(n))
    # (the same operations on the same numbers in this process: equal but for the last digit)
    assert r.error_relative == pytest.approx(expected + core.conditioning(net, t_end), rel=1e-12)
    assert r.error_at in t[idx]


def _modules_after(code: str) -> set[str]:
    """The modules a fresh process has loaded after ``code`` (printed on stderr)."""
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint('MODULES', ' '.join(sorted(sys.modules)), "
                          "file=sys.stderr)"], capture_output=True, text=True, check=True)
    return set(out.stderr.split("MODULES", 1)[1].split())


def test_the_exact_path_does_not_import_scipy_integrate():
    loaded = _modules_after("from beltcalc.sim.scenes import SCENES\nfrom beltcalc.sim.core import simulate, "
                            "SolverConfig\ns = SCENES['sewing']; v = dict(s.values())\n"
                            "r = simulate(s.build(v), 1.0, 2001, SolverConfig('exact'))")
    assert not {m for m in loaded if m.startswith(("scipy.linalg", "scipy.integrate", "scipy.optimize"))}
    # (pint itself imports dask.base when dask is installed; nothing of ours imports more)
    assert not {"matplotlib", "pandas", "distributed", "dask.array", "dask.dataframe"} & loaded


def test_a_scipy_method_still_imports_it_where_it_runs():
    loaded = _modules_after("from beltcalc.sim.scenes import SCENES\nfrom beltcalc.sim.core import simulate, "
                            "SolverConfig\ns = SCENES['sewing']; v = dict(s.values())\n"
                            "r = simulate(s.build(v), 0.01, 101, SolverConfig('odeint', estimate_error=False))")
    assert "scipy.integrate" in loaded


def _cli_modules(*args: str) -> set[str]:
    return _modules_after("from beltcalc.cli.main import cli\n"
                          f"cli.main({list(args)!r}, prog_name='beltcalc', standalone_mode=False)")


def test_the_command_list_imports_no_command():
    # `beltcalc --help` lists the commands from SUMMARIES: no pint, numpy or scipy
    loaded = _cli_modules("--help")
    assert not {"pint", "numpy", "scipy", "dask", "matplotlib", "beltcalc.cli.options"} & loaded


def test_a_simulate_help_imports_no_solver_plot_or_dask_of_ours():
    loaded = _cli_modules("simulate", "sewing", "--help")
    assert not {m for m in loaded if m.startswith(("scipy.integrate", "matplotlib", "distributed", "dask.array",
                                                   "dask.dataframe", "pandas"))}
    assert "beltcalc.sim.core" not in loaded
    # what pint brings when dask is installed (pint.compat: dask.base) is the floor, not ours
    assert not {m for m in loaded if m.startswith("dask")} - _modules_after("import pint")


@pytest.mark.parametrize("width", [40, 60, 80, 100, 200])
def test_the_command_summaries_are_the_commands_own_help(width):
    import importlib

    import click
    from click.testing import CliRunner

    from beltcalc.cli.main import COMMANDS, SUMMARIES, cli

    assert set(SUMMARIES) == set(COMMANDS)
    limit = min(width, 100) - 6 - max(len(n) for n in COMMANDS)
    for name, target in COMMANDS.items():
        module, attr = target.split(":")
        cmd = getattr(importlib.import_module(module), attr)
        assert click.Command(name, help=SUMMARIES[name]).get_short_help_str(limit) == cmd.get_short_help_str(limit), \
            name
    shown = CliRunner().invoke(cli, ["--help"], terminal_width=width)
    assert shown.exit_code == 0 and "simulate" in shown.output
