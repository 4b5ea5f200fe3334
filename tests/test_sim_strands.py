"""Tension-only strands, piecewise-linear inputs and speed loops on the shared core
(beltcalc.sim.network / beltcalc.sim.core): analytic cases, solver independence, and the
traps of event handling named in DESIGN.md section 3."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.errors import InputError, SimulationError
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.network import (Coupling, Inertia, InductionMotor, Load, Network, Prescribed, SpeedLoop, Strand,
                                  piecewise)

EXACT = SolverConfig("exact", estimate_error=False)


def bounce(d0=0.01, v0=0.5, mass=2.0, c=2e4, b=0.0, preload=0.0):
    """A sliding mass on a tension-only strand anchored to the frame, slack by d0, moving at v0
    towards it: free flight for d0 / v0, half an oscillation of w = sqrt(c / m) on the strand,
    then free flight back at -v0 (no damping: the strand returns all the energy)."""
    net = Network([Inertia("m", mass, translation=True)], [Strand("s", "m", None, 1.0, 1.0, c, b, preload)])
    x0 = np.array([-d0, v0])
    return net, x0


def test_bounce_on_a_strand_is_exact():
    net, x0 = bounce()
    w = math.sqrt(2e4 / 2.0)
    t_hit, t_off = 0.01 / 0.5, 0.01 / 0.5 + math.pi / w
    r = simulate(net, 0.2, 2001, SolverConfig("exact"), x0=x0)
    assert r.extra["events"] == 2
    assert r.extra["slack_time"]["s"] == pytest.approx(0.2 - math.pi / w, rel=1e-12)
    assert r["v_m"][-1] == pytest.approx(-0.5, rel=1e-11)       # elastic: all the energy comes back
    # free flight after the strand lets go: x = -v0 (t - t_off)
    late = r.t > t_off + 1e-3
    assert_allclose(r["x_m"][late], -0.5 * (r.t[late] - t_off), atol=1e-12)
    # peak force v0 sqrt(c m) at the middle of the contact (sampled at 0.1 ms: cos error < 1e-4)
    assert r["F_s"].max() == pytest.approx(0.5 * math.sqrt(2e4 * 2.0), rel=1e-3)
    assert r["F_s"][r.t < t_hit].max() == 0.0
    assert r.error_estimate == pytest.approx(0.0, abs=1e-11)


def test_a_contact_inside_one_output_step_is_found():
    # the whole contact (22 ms) lies inside one 0.5 s output step: the exact method still finds
    # both switches and the mass leaves at -v0; a scan of samples alone would miss it
    net, x0 = bounce()
    r = simulate(net, 1.0, 3, EXACT, x0=x0)
    assert r.extra["events"] == 2
    assert r["v_m"][-1] == pytest.approx(-0.5, rel=1e-11)
    w = math.sqrt(2e4 / 2.0)
    assert r["x_m"][-1] == pytest.approx(-0.5 * (1.0 - 0.02 - math.pi / w), rel=1e-11)


@pytest.mark.parametrize("method", ["radau", "bdf", "lsoda", "dop853"])
def test_solvers_with_events_agree_with_exact_on_the_bounce(method):
    net, x0 = bounce(b=20.0)          # damped: the mass leaves slower, the force stays >= 0
    ref = simulate(net, 0.2, 401, EXACT, x0=x0)
    r = simulate(net, 0.2, 401, SolverConfig(method, rtol=1e-10, atol=1e-13, estimate_error=False), x0=x0)
    assert r.extra["events"] == ref.extra["events"] == 2
    assert r.extra["slack_time"]["s"] == pytest.approx(ref.extra["slack_time"]["s"], abs=1e-7)
    assert_allclose(r["v_m"], ref["v_m"], atol=1e-6)
    assert ref["F_s"].min() == 0.0


def test_damped_strand_lets_go_when_its_force_reaches_zero():
    # with a damper the force c delta + b delta' reaches zero while the strand is still stretched:
    # the strand lets go there (a chain cannot push), not at delta = 0 as the paper's eq. 9-11
    net, x0 = bounce(b=60.0)
    r = simulate(net, 0.2, 20001, EXACT, x0=x0)
    taut = r["F_s"] > 0
    last = np.nonzero(taut)[0][-1]
    delta = r["x_m"][last] + 0.0                      # r_i = 1, no pretension
    assert delta > 1e-5                               # still stretched when it lets go
    assert r["F_s"].min() == 0.0


def reversing():
    """Node a driven by 6 sin(20 t) N m pulls node b through a pretensioned strand (50 N at
    r = 50 mm); when the torque reverses the strand unloads and goes slack."""
    nodes = [Inertia("a", 0.01), Inertia("b", 0.02)]
    cps = [Coupling("ga", "a", None, 0.0, 0.05), Coupling("gb", "b", None, 0.0, 0.02)]
    strand = [Strand("s", "a", "b", 0.05, 0.05, 2e5, 50.0, preload=50.0)]
    return Network(nodes, [*cps, Load("a", 0.0, -6.0, 20.0), *strand])


@pytest.mark.parametrize("method", ["radau", "bdf", "lsoda"])
def test_a_reversing_load_makes_the_strand_slack_whatever_the_solver(method):
    net = reversing()
    ref = simulate(net, 2.0, 2001, SolverConfig("exact"))
    assert ref.extra["events"] == 3 and ref.extra["slack_time"]["s"] > 1.0
    assert ref.error_estimate == pytest.approx(0.0, abs=1e-9)
    r = simulate(net, 2.0, 2001, SolverConfig(method, rtol=1e-9, atol=1e-12, estimate_error=False))
    assert r.extra["events"] == 3
    assert r.extra["slack_time"]["s"] == pytest.approx(ref.extra["slack_time"]["s"], abs=1e-6)
    assert_allclose(r["omega_b"], ref["omega_b"], atol=1e-5)


def test_raw_right_hand_side_without_events_still_agrees_loosely():
    # odeint integrates across the switches without stopping (the trap): here it gets through,
    # at the accuracy its step control allows at the kinks
    net = reversing()
    ref = simulate(net, 2.0, 2001, EXACT)
    r = simulate(net, 2.0, 2001, SolverConfig("odeint", rtol=1e-9, atol=1e-12, estimate_error=False))
    assert_allclose(r["omega_b"], ref["omega_b"], atol=1e-4)
    assert r.extra["slack_time"]["s"] == pytest.approx(ref.extra["slack_time"]["s"], abs=2e-3)


def test_taut_strands_are_ordinary_springs():
    # a chain loop a -> b -> a (radii 50 and 80 mm) pretensioned to 400 N never goes slack
    # under these loads; each strand is then a spring C = c r_i^2, U = r_j / r_i plus its
    # pretension torques (r_i F0 against node i, r_j F0 driving node j), which cancel round
    # the loop
    strands = [Strand("ab", "a", "b", 0.05, 0.08, 2e5, 40.0, preload=400.0),
               Strand("ba", "b", "a", 0.08, 0.05, 2e5, 40.0, preload=400.0)]
    nodes = [Inertia("a", 0.01), Inertia("b", 0.02)]
    cps = [Coupling("gb", "b", None, 0.0, 0.1)]
    loads = [Load("a", 0.0, -1.0, 30.0), Load("b", 0.5)]
    a = simulate(Network(nodes, [*cps, *loads, *strands]), 1.0, 1001, EXACT)
    springs, pre = [], []
    for s in strands:
        springs.append(Coupling(s.name, s.i, s.j, s.stiffness * s.r_i ** 2, s.damping * s.r_i ** 2, s.r_j / s.r_i))
        pre += [Load(s.i, s.r_i * s.preload), Load(s.j, -s.r_j * s.preload)]
    b = simulate(Network(nodes, [*cps, *springs, *loads, *pre]), 1.0, 1001, EXACT)
    assert a.extra["events"] == 0 and min(a["F_ab"].min(), a["F_ba"].min()) > 0
    assert_allclose(a["omega_b"], b["omega_b"], atol=1e-10)
    assert_allclose(a["F_ab"], b["T_ab"] / 0.05 + 400.0, rtol=1e-9)


def test_a_strand_without_pretension_takes_up_from_rest():
    # at rest on its surface (no elongation, no rate) the strand is judged a moment later:
    # node a, driven, pulls b from the first instant; undamped, the force swings 0..2 T / r
    nodes = [Inertia("a", 0.01), Inertia("b", 0.01)]
    net = Network(nodes, [Load("a", -0.5), Strand("chain", "a", "b", 0.05, 0.05, 1e6, 0.0)])
    r = simulate(net, 0.5, 501, SolverConfig("exact"))
    # taut throughout: undamped, the force comes back to zero at every swing, and whether
    # rounding lets it dip below zero for an instant there is the BLAS kernel's (none under
    # OpenBLAS Haswell, 1.2e-8 s under Nehalem, Sandybridge and Prescott). A real slack spell
    # lasts a good part of the 9 ms swing; 1 us is 1e-4 of one
    assert r.extra["slack_time"]["chain"] == pytest.approx(0.0, abs=1e-6)
    # angular momentum: equal radii and inertias, so the mean speed is T t / (Ja + Jb) exactly
    assert_allclose(0.5 * (r["omega_a"] + r["omega_b"]), 0.5 * r.t / 0.02, atol=1e-9)
    assert r["F_chain"].max() == pytest.approx(2 * 0.5 / 2 / 0.05, rel=1e-3)


def test_chattering_is_bounded_and_named():
    with pytest.raises(SimulationError, match=r"2 strand events.*strand s.*raise max_events"):
        simulate(reversing(), 2.0, 2001, SolverConfig("exact", max_events=2, estimate_error=False))
    with pytest.raises(SimulationError, match=r"2 strand events.*strand s.*raise max_events"):
        simulate(reversing(), 2.0, 2001, SolverConfig("radau", max_events=2, estimate_error=False))


def test_a_step_load_at_an_off_grid_time_is_exact():
    # J w' = -d w - T 1(t > ts): w = -(T/d) (1 - exp(-d (t - ts) / J)) after ts = 0.1234 s
    J, d, T, ts = 0.02, 0.5, 2.0, 0.1234
    net = Network([Inertia("1", J)], [Coupling("g", "1", None, 0.0, d), Load("1", table=((ts, 0.0), (ts, T)))])
    r = simulate(net, 1.0, 101, SolverConfig("auto"))
    assert r.method == "exact"
    expected = np.where(r.t > ts, -(T / d) * (1 - np.exp(-d * (r.t - ts) / J)), 0.0)
    assert_allclose(r["omega_1"], expected, atol=1e-13)


def test_prescribed_trapezoid_and_its_drive_torque():
    # accelerate at 100 rad/s^2 for 0.1 s, cruise, brake: the drive torque of a bare 0.03 kg m^2
    # inertia is J a, and the speed follows the ramp exactly
    acc = ((0.0, 100.0), (0.1, 100.0), (0.1, 0.0), (0.3, 0.0), (0.3, -100.0), (0.4, -100.0), (0.4, 0.0))
    net = Network([Inertia("d", 0.03)], [Prescribed("d", 0.0, acc)])
    r = simulate(net, 0.5, 501, EXACT)
    assert_allclose(r["omega_d"], np.clip(np.minimum(100 * r.t, 10.0 - 100 * (r.t - 0.3)), 0.0, 10.0), atol=1e-12)
    inner = (np.abs(r.t - 0.1) > 2e-3) & (np.abs(r.t - 0.3) > 2e-3) & (np.abs(r.t - 0.4) > 2e-3)
    assert_allclose(r["T_drive_d"][inner], 0.03 * piecewise(acc, r.t[inner]), atol=1e-10)
    assert r["phi_d"][-1] == pytest.approx(0.5 + 2.0 + 0.5, rel=1e-12)     # ramp + cruise + brake


def test_speed_loop_first_order_response():
    # J w' = K (w_r - w): w = w_r (1 - exp(-K t / J)); the drive torque K (w_r - w)
    J, K, wr = 0.01, 0.2, 50.0
    net = Network([Inertia("m", J)], [SpeedLoop("m", K, ((0.0, wr),))])
    r = simulate(net, 0.5, 501, EXACT)
    assert_allclose(r["omega_m"], wr * (1 - np.exp(-K * r.t / J)), atol=1e-11)
    assert_allclose(r["T_drive_m"], K * (wr - r["omega_m"]), atol=1e-12)


def test_inverter_ramp_reaches_the_static_characteristic():
    # synchronous speed ramped 0 -> 157 rad/s in 1 s; afterwards the motor carries 2 N m at the
    # slip of the linearised characteristic: w = w0 (1 - S_c T / (2 M_c))
    w0, mc, sc = 157.08, 20.0, 0.2
    motor = InductionMotor("m", mc, sc, w0, 314.16, sync_table=((0.0, 0.0), (1.0, w0)))
    net = Network([Inertia("m", 0.01)], [Load("m", 2.0), motor])
    r = simulate(net, 3.0, 3001, SolverConfig("auto"))
    assert r.method == "exact"
    assert r["omega_m"][-1] == pytest.approx(w0 * (1 - sc * 2.0 / (2 * mc)), rel=1e-9)
    radau = simulate(net, 3.0, 3001, SolverConfig("radau", rtol=1e-10, atol=1e-12, estimate_error=False))
    assert_allclose(radau["omega_m"], r["omega_m"], atol=1e-5)


def test_bad_elements_are_refused():
    nodes = [Inertia("a", 0.01)]
    with pytest.raises(InputError, match="stiffness"):
        Network(nodes, [Strand("s", "a", None, 0.05, 1.0, 0.0, 0.0)])
    with pytest.raises(InputError, match="preload"):
        Network(nodes, [Strand("s", "a", None, 0.05, 1.0, 1e5, 0.0, -1.0)])
    with pytest.raises(InputError, match="unknown node"):
        Network(nodes, [Strand("s", "a", "zz", 0.05, 0.05, 1e5, 0.0)])
    with pytest.raises(InputError, match="rising times"):
        Network(nodes, [Prescribed("a", 0.0, ((1.0, 0.0), (0.5, 1.0)))])
    with pytest.raises(InputError, match="speed loop"):
        Network(nodes, [Prescribed("a"), SpeedLoop("a", 1.0, ((0.0, 1.0),))])
