"""Tests of the simulation core (beltcalc.sim): analytic cases against the exact propagator
and the scipy solvers."""

import math

import numpy as np
import pytest

from beltcalc.errors import InputError, SimulationError
from beltcalc.sim import scipy_methods
from beltcalc.sim.core import SolverConfig, conditioning, simulate
from beltcalc.sim.network import Coupling, Inertia, InductionMotor, Load, Network


def two_mass(C=100.0, d=0.0, J1=0.01, J2=0.03, loads=()):
    return Network([Inertia("1", J1), Inertia("2", J2)], [Coupling("c", "1", "2", C, d), *loads])


def test_matrices_lagrange_with_ratio():
    # coupling C (phi_1 - U phi_2): K = C [[1, -U], [-U, U^2]]
    net = Network([Inertia("1", 1.0), Inertia("2", 2.0)], [Coupling("c", "1", "2", 10.0, 0.5, 2.0)])
    np.testing.assert_allclose(net.K, [[10.0, -20.0], [-20.0, 40.0]], rtol=1e-15)
    np.testing.assert_allclose(net.D, [[0.5, -1.0], [-1.0, 2.0]], rtol=1e-15)
    np.testing.assert_allclose(net.M, [[1.0, 0.0], [0.0, 2.0]], rtol=1e-15)


def test_two_mass_natural_frequency():
    # w^2 = C (1/J1 + 1/J2) = 100 (100 + 33.333) = 13333.3 -> w = 115.47 rad/s = 18.378 Hz
    (f, zeta), = two_mass().modes()
    assert f == pytest.approx(math.sqrt(100 * (1 / 0.01 + 1 / 0.03)) / (2 * math.pi), rel=1e-12)
    assert zeta == pytest.approx(0.0, abs=1e-12)


def test_undamped_energy_over_10000_periods():
    # initial twist 0.01 rad, no damping, no load: energy C/2 0.01^2 = 5e-3 J must stay
    net = two_mass()
    w = math.sqrt(100 * (1 / 0.01 + 1 / 0.03))
    t_end = 10000 * 2 * math.pi / w
    x0 = np.array([0.01, 0.0, 0.0, 0.0])
    r = simulate(net, t_end, 200001, SolverConfig("exact", estimate_error=False), x0)
    x = np.array([r["phi_1"], r["phi_2"], r["omega_1"], r["omega_2"]])
    kin, pot = net.energy(x)
    np.testing.assert_allclose(kin + pot, 5e-3, rtol=1e-9)


def test_one_dof_harmonic_amplitude():
    # J phi'' + d phi' + C phi = -A sin(w t): steady amplitude A / |C - J w^2 + j d w|
    J, C, d, A, w = 0.02, 50.0, 0.3, 0.5, 40.0
    net = Network([Inertia("1", J)], [Coupling("ground", "1", None, C, d), Load("1", 0.0, A, w)])
    r = simulate(net, 20.0, 40001, SolverConfig("exact"))
    expected = A / abs(C - J * w * w + 1j * d * w)
    assert r.summary("phi_1", 15.0).amplitude == pytest.approx(expected, rel=1e-4)


def test_step_response_static_deflection():
    # constant load M on 1-DOF: phi -> -M / C
    net = Network([Inertia("1", 0.02)], [Coupling("g", "1", None, 50.0, 2.0), Load("1", 1.5)])
    r = simulate(net, 5.0, 2001, SolverConfig("exact"))
    assert r["phi_1"][-1] == pytest.approx(-1.5 / 50.0, rel=1e-9)


def sewing_like():
    J = [0.11e-4, 0.10e-3, 0.29e-3, 0.38e-4, 0.49e-3]
    d = [5.4, 6.1, 5.2, 6.0]
    U = [1.375, 1, 1, 1]
    nodes = [Inertia(str(k + 1), j) for k, j in enumerate(J)]
    cps = [Coupling(f"c{k + 1}", str(k + 1), str(k + 2), 260.0, d[k], U[k]) for k in range(4)]
    motor = InductionMotor("1", 3.0, 0.2, 2 * math.pi * 50, 2 * math.pi * 50)
    w = 300 / 1.375
    return Network(nodes, [*cps, Load("3", 0.1, 0.175, w), Load("5", 0.012, 0.14, w), motor])


def test_sewing_is_stiff():
    lam = np.linalg.eigvals(sewing_like().state_matrix())
    assert min(lam.real) == pytest.approx(-6.05e5, rel=0.01)


@pytest.mark.parametrize("method, tol", [("radau", 1e-5), ("bdf", 1e-3), ("lsoda", 1e-3), ("odeint", 1e-3)])
def test_implicit_methods_agree_with_exact(method, tol):
    net = sewing_like()
    exact = simulate(net, 0.5, 5001, SolverConfig("exact", estimate_error=False))
    other = simulate(net, 0.5, 5001, SolverConfig(method, rtol=1e-8, atol=1e-10, accept_error=True))
    np.testing.assert_allclose(other["omega_3"], exact["omega_3"], atol=tol)
    # the estimate per speed: the difference to the exact solution plus the rounding floor
    scale = max(np.max(np.abs(exact[f"omega_{k}"])) for k in "12345")
    floor = conditioning(net, 0.5) * scale
    assert other.error_reference == "exact solution"
    for k in "12345":
        diff = np.max(np.abs(other[f"omega_{k}"] - exact[f"omega_{k}"]))
        assert other.errors[f"omega_{k}"] == pytest.approx(diff + floor, rel=1e-6)
    # the coupling torques are judged alike, on the scale of the torques (a torque is a stiffness
    # times a difference of angles: its relative error can be far above the speeds')
    torques = [name for name in other.errors if name.startswith("T_")]
    assert len(torques) == len(net.couplings)
    t_scale = max(np.max(np.abs(other[name])) for name in torques)
    for name in torques:
        diff = np.max(np.abs(other[name] - exact[name]))
        assert other.errors[name] == pytest.approx(diff + conditioning(net, 0.5) * t_scale, rel=1e-6)
    worst = max(max(other.errors[f"omega_{k}"] for k in "12345") / scale,
                max(other.errors[name] for name in torques) / t_scale)
    assert other.error_relative == pytest.approx(worst, rel=1e-12)
    assert other.error_estimate == pytest.approx(other.errors[other.error_signal], rel=1e-12)
    assert other.error_unit == ("rad/s" if other.error_signal.startswith("omega_") else "N m")


def test_exact_error_estimate_is_small():
    r = simulate(sewing_like(), 0.5, 5001, SolverConfig("exact"))
    assert r.error_reference == "exact with another internal step and scaling of A h"
    assert r.error_estimate == pytest.approx(0.0, abs=1e-6)
    assert r.error_relative == pytest.approx(0.0, abs=1e-8)


def test_auto_switches_to_radau_for_angle_loads():
    net = Network([Inertia("1", 0.01)], [Coupling("g", "1", None, 10.0, 0.5), Load("1", 0.0, 0.2, in_angle=True)])
    r = simulate(net, 0.2, 201, SolverConfig("auto"))
    assert r.method == "radau"
    assert "nonlinear" in r.reason
    with pytest.raises(InputError, match="exact"):
        simulate(net, 0.2, 201, SolverConfig("exact"))


def test_rk45_budget_is_a_clear_failure():
    with pytest.raises(SimulationError, match=r"rk45 stopped at t = .* s after 2000 right-hand-side calls"):
        simulate(sewing_like(), 0.5, 501, SolverConfig("rk45", max_rhs_calls=2000, estimate_error=False))


def test_work_precision_rows_and_errors():
    from beltcalc.sim.study.workprecision import count_runs, fastest_at, work_precision

    net = two_mass(C=100.0, d=0.05, loads=[Load("2", 0.1, 0.05, 20.0)])
    rows = work_precision(net, 0.5, 501, "omega_2", tolerances=(1e-4, 1e-9), explicit_tolerances=(1e-6,),
                          repeats=1)
    assert len(rows) == count_runs((1e-4, 1e-9), (1e-6,)) == 1 + 4 * 2 + 2
    assert rows[0].method == "exact" and rows[0].error == pytest.approx(0.0, abs=1e-9)
    by = {(r.method, r.rtol): r for r in rows}
    # tighter tolerance, smaller error, for every implicit method
    for m in ("radau", "bdf", "lsoda", "odeint"):
        assert by[(m, 1e-9)].error < by[(m, 1e-4)].error
    assert set(fastest_at(rows, 1e-3)) >= {"exact", "radau", "odeint"}


def test_work_precision_reports_a_budget_stop():
    from beltcalc.sim.study.workprecision import work_precision

    rows = work_precision(sewing_like(), 0.2, 201, "omega_3", tolerances=(1e-4,), explicit_tolerances=(1e-3,),
                          repeats=1, max_rhs_calls=3000)
    stopped = [r for r in rows if r.method in ("rk45", "dop853")]
    assert all(r.error is None and "stopped at t =" in r.note for r in stopped)


def test_massless_node_is_condensed_to_the_series_spring():
    # springs 300 and 600 N m/rad in series through a node without inertia = 200 N m/rad (eq. 3 of
    # Rusek & Popenda): the 2-mass frequency sqrt(200 (1/J1 + 1/J2)); the middle node's angle is
    # the static balance, phi_m = (300 phi_1 + 600 phi_2) / 900
    nodes = [Inertia("1", 0.01), Inertia("m", 0.0), Inertia("2", 0.02)]
    cps = [Coupling("a", "1", "m", 300.0, 0.0), Coupling("b", "m", "2", 600.0, 0.0)]
    net = Network(nodes, cps)
    (f, _), = net.modes()
    assert f == pytest.approx(math.sqrt(200 * (1 / 0.01 + 1 / 0.02)) / (2 * math.pi), rel=1e-12)
    assert net.node_row("m") == pytest.approx([1 / 3, 2 / 3], rel=1e-14)


def test_massless_node_with_unproportional_damping_is_refused_with_the_way_out():
    nodes = [Inertia("1", 0.01), Inertia("m", 0.0), Inertia("2", 0.02)]
    cps = [Coupling("a", "1", "m", 300.0, 1.0), Coupling("b", "m", "2", 600.0, 0.0)]
    with pytest.raises(InputError, match=r"node\(s\) m have no inertia and dampers not proportional.*give them an "
                                         r"inertia"):
        Network(nodes, cps)


def test_series_elimination_matches_a_tiny_middle_inertia():
    # springs 300 and 600 in series = 200 N m/rad: the 2-mass frequency sqrt(200 (1/J1 + 1/J2));
    # a middle node of 1e-9 kg m^2 instead of none gives the same lowest mode to 1e-5
    from beltcalc.sim.network import series_stiffness

    c = series_stiffness(300.0, 600.0)
    (f_series, _), = Network([Inertia("1", 0.01), Inertia("2", 0.02)], [Coupling("s", "1", "2", c, 0.0)]).modes()
    tiny = Network([Inertia("1", 0.01), Inertia("m", 1e-9), Inertia("2", 0.02)],
                   [Coupling("a", "1", "m", 300.0, 0.0), Coupling("b", "m", "2", 600.0, 0.0)])
    assert f_series == pytest.approx(math.sqrt(200 * (1 / 0.01 + 1 / 0.02)) / (2 * math.pi), rel=1e-12)
    assert tiny.modes()[0][0] == pytest.approx(f_series, rel=1e-5)


def test_stiffness_ratio_1e6():
    # a soft coupling (100) and a stiff one (1e8) in one train: the exact solution and Radau agree,
    # and the slow mode is the soft spring against the sum of the stiffly joined inertias
    # (the stiff mode: sqrt(1e8 (1/0.02 + 1/0.03)) = 9.1e4 rad/s, damping ratio 0.43)
    nodes = [Inertia("1", 0.01), Inertia("2", 0.02), Inertia("3", 0.03)]
    cps = [Coupling("soft", "1", "2", 100.0, 0.01), Coupling("stiff", "2", "3", 1e8, 3e4)]
    net = Network(nodes, [*cps, Load("3", 0.2, 0.1, 30.0)])
    f_slow = net.modes()[0][0]
    assert f_slow == pytest.approx(math.sqrt(100 * (1 / 0.01 + 1 / 0.05)) / (2 * math.pi), rel=1e-5)
    ex = simulate(net, 1.0, 2001, SolverConfig("exact", estimate_error=False))
    ra = simulate(net, 1.0, 2001, SolverConfig("radau", rtol=1e-8, atol=1e-11))
    np.testing.assert_allclose(ra["omega_3"], ex["omega_3"], atol=1e-6)
    np.testing.assert_allclose(ex["omega_2"], ex["omega_3"], atol=1e-3)  # stiffly joined


def test_prescribed_constant_speed_is_exact_and_gives_the_drive_torque():
    # drive node "d" at 100 rad/s, spring-damper to a 0.02 kg m^2 shaft carrying 2 N m:
    # steady state: both turn at 100 rad/s, twist phi_d - phi_1 = 2 / 50 = 0.04 rad, drive torque 2 N m
    from beltcalc.sim.network import Prescribed

    net = Network([Inertia("d", 1.0), Inertia("1", 0.02)],
                  [Coupling("c", "d", "1", 50.0, 1.0), Load("1", 2.0), Prescribed("d", speed=100.0)])
    assert net.linear
    r = simulate(net, 3.0, 3001, SolverConfig("auto"))
    assert r.method == "exact"
    assert r["omega_d"] == pytest.approx(np.full(3001, 100.0), rel=1e-12)
    assert r["phi_d"][-1] - r["phi_1"][-1] == pytest.approx(0.04, rel=1e-6)
    assert r["T_drive_d"][-1] == pytest.approx(2.0, rel=1e-6)
    assert r["omega_1"][-1] == pytest.approx(100.0, rel=1e-9)


def test_prescribed_acceleration_drive_torque():
    # the drive (its own rotor 1 kg m^2) accelerates at 50 rad/s^2 through a stiff, well-damped
    # coupling: after the transient the driven 0.02 kg m^2 follows, and the drive delivers
    # (1 + 0.02) * 50 = 51 N m
    from beltcalc.sim.network import Prescribed

    net = Network([Inertia("d", 1.0), Inertia("1", 0.02)],
                  [Coupling("c", "d", "1", 1e4, 20.0), Prescribed("d", speed=0.0, accel=((0.0, 50.0),))])
    r = simulate(net, 1.0, 1001, SolverConfig("auto", rtol=1e-9, atol=1e-12))
    assert r.method == "exact"  # a piecewise-linear acceleration keeps the network linear
    ra = simulate(net, 1.0, 1001, SolverConfig("radau", rtol=1e-9, atol=1e-12))
    np.testing.assert_allclose(ra["omega_1"], r["omega_1"], atol=1e-6)
    assert r["omega_d"][-1] == pytest.approx(50.0, rel=1e-8)
    assert r["T_drive_d"][-1] == pytest.approx(1.02 * 50.0, rel=1e-6)
    assert r["accel_1"][-1] == pytest.approx(50.0, rel=1e-4)


def test_tabulated_load_equals_the_same_constant_and_ramp():
    # a table that holds 1.5 N m equals the constant load (exact); a ramp table is interpolated
    nodes, ground = [Inertia("1", 0.02)], Coupling("g", "1", None, 50.0, 2.0)
    const = simulate(Network(nodes, [ground, Load("1", 1.5)]), 2.0, 2001, SolverConfig("exact", estimate_error=False))
    table = simulate(Network(nodes, [ground, Load("1", table=((0.0, 1.5), (2.0, 1.5)))]), 2.0, 2001,
                     SolverConfig("auto", rtol=1e-10, atol=1e-12))
    assert table.method == "exact"
    np.testing.assert_allclose(table["phi_1"], const["phi_1"], atol=1e-12)
    radau = simulate(Network(nodes, [ground, Load("1", table=((0.0, 1.5), (2.0, 1.5)))]), 2.0, 2001,
                     SolverConfig("radau", rtol=1e-10, atol=1e-12))
    np.testing.assert_allclose(radau["phi_1"], const["phi_1"], atol=1e-9)
    ramp = Network(nodes, [ground, Load("1", 0.5, table=((0.0, 0.0), (1.0, 2.0)))])
    r = simulate(ramp, 2.0, 2001, SolverConfig("auto", estimate_error=False))
    np.testing.assert_allclose(r["load_1"][[0, 500, 1000, 2000]], [0.5, 1.5, 2.5, 2.5], rtol=1e-12)
    # the ramp's response, exact (a break point at 1 s) against Radau
    rr = simulate(ramp, 2.0, 2001, SolverConfig("radau", rtol=1e-10, atol=1e-13, estimate_error=False))
    np.testing.assert_allclose(rr["phi_1"], r["phi_1"], atol=1e-9)
    with pytest.raises(InputError, match="rising times"):
        Network(nodes, [ground, Load("1", table=((1.0, 0.0), (0.5, 1.0)))])



@pytest.mark.parametrize("name", ["RK45", "Radau", "BDF", "DOP853", "LSODA"])
def test_steps_of_scipy_methods_are_accepted_steps(name):
    # solve_ivp reports right-hand-side calls; the counting solver class counts accepted steps,
    # which are the intervals of solve_ivp's own output grid when no t_eval is given
    from scipy.integrate import solve_ivp

    def rhs(t, y):
        return np.array([y[1], -100.0 * y[0] - 0.3 * y[1]])

    plain = solve_ivp(rhs, (0.0, 2.0), [1.0, 0.0], method=name, rtol=1e-8, atol=1e-10)
    counter = [0]
    counted = solve_ivp(rhs, (0.0, 2.0), [1.0, 0.0], method=scipy_methods.counting(name, counter), rtol=1e-8, atol=1e-10)
    assert counter[0] == plain.t.size - 1
    assert counted.nfev == plain.nfev


def test_a_scipy_run_is_bounded_in_computing_time():
    # a model many decades stiffer in one part crawls under Radau: the run stops at max_seconds
    # with one line saying so, instead of running for minutes
    net = Network([Inertia("a", 1e-4), Inertia("b", 1e-4)],
                  [Coupling("c", "a", "b", 2.6e12, 0.0), Load("b", 0.0, amplitude=0.1, omega=200.0)])
    cfg = SolverConfig(method="radau", max_seconds=0.2, estimate_error=False, rtol=1e-12, atol=1e-16)
    with pytest.raises(SimulationError, match=r"radau stopped at t = .* s after 0.2 s of computing \(\d+ "
                                              r"right-hand-side calls\).*many decades stiffer"):
        simulate(net, 1.0, 11, cfg)
