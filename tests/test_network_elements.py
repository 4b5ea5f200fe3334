"""Tests of the generalised network (beltcalc.sim.network, beltcalc.sim.elements): rigid
gears merged into one coordinate, massless nodes condensed, several motors, pint quantities,
a prescribed move from a motor-size profile. References: hand-typed matrices solved by
scipy.linalg.eigh, the static balance, and the profile's own distance."""

import math

import numpy as np
import pytest
import scipy.linalg as sla

from beltcalc.errors import InputError
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.drivefile import undamped_frequencies
from beltcalc.sim.network import Coupling, Gear, Inertia, InductionMotor, Load, Network, Prescribed, Strand


def _eigh_hz(M, K):
    w2 = sla.eigh(np.asarray(K, float), np.asarray(M, float), eigvals_only=True)
    return sorted(math.sqrt(v) / (2 * math.pi) for v in w2 if v > 1e-9 * max(w2))


def test_gear_merges_two_nodes_into_one_coordinate():
    # disk a -- spring C -- gear g1 =(ratio 3)= gear g2 -- spring C2 -- disk b
    # coordinates q = [phi_a, phi_g1, phi_b]; phi_g2 = phi_g1 / 3:
    # M = diag(Ja, J1 + J2/9, Jb), K by hand
    Ja, J1, J2, Jb, C, C2, i = 2.0, 0.1, 0.5, 4.0, 1000.0, 3000.0, 3.0
    net = Network([Inertia("a", Ja), Inertia("g1", J1), Inertia("g2", J2), Inertia("b", Jb)],
                  [Coupling("s1", "a", "g1", C, 0.0), Coupling("s2", "g2", "b", C2, 0.0), Gear("g1", "g2", i)])
    assert net.coords == ["a", "g1", "b"]
    M = np.diag([Ja, J1 + J2 / i ** 2, Jb])
    K = np.array([[C, -C, 0.0], [-C, C + C2 / i ** 2, -C2 / i], [0.0, -C2 / i, C2]])
    np.testing.assert_allclose(net.M, M, rtol=1e-15)
    np.testing.assert_allclose(net.K, K, rtol=1e-15)
    assert undamped_frequencies(net) == pytest.approx(_eigh_hz(M, K), rel=1e-12)


def test_gear_written_from_either_end_gives_the_same_network():
    nodes = [Inertia("x", 1.0), Inertia("y", 2.0), Inertia("z", 3.0)]
    cps = [Coupling("c", "x", "y", 50.0, 0.0)]
    one = Network(nodes, [*cps, Coupling("d", "z", None, 80.0, 0.0), Gear("y", "z", 2.0)])
    two = Network(nodes, [*cps, Coupling("d", "z", None, 80.0, 0.0), Gear("z", "y", 0.5)])
    assert undamped_frequencies(one) == pytest.approx(undamped_frequencies(two), rel=1e-13)


def test_gear_loop_with_inconsistent_ratios_is_refused():
    nodes = [Inertia(n, 1.0) for n in "abc"]
    with pytest.raises(InputError, match="rigid gears form a loop with inconsistent ratios"):
        Network(nodes, [Gear("a", "b", 2.0), Gear("b", "c", 2.0), Gear("a", "c", 3.0)])
    # a consistent loop is fine
    Network(nodes, [Gear("a", "b", 2.0), Gear("b", "c", 2.0), Gear("a", "c", 4.0)])


def test_geared_node_signals_follow_the_ratio():
    net = Network([Inertia("m", 0.01), Inertia("p", 0.002), Inertia("w", 0.3)],
                  [Coupling("shaft", "p", "w", 400.0, 0.2), Load("w", 2.0), Prescribed("m", 100.0),
                   Gear("m", "p", 4.0)])
    r = simulate(net, 0.5, 501, SolverConfig("exact"))
    np.testing.assert_allclose(r["omega_p"], r["omega_m"] / 4.0, rtol=1e-14)
    np.testing.assert_allclose(r["phi_p"], r["phi_m"] / 4.0, rtol=1e-14)
    # at constant speed the geared pair does not accelerate: the drive torque at the motor is
    # the shaft's torque reflected through the ratio, T_shaft / 4, at every sample
    np.testing.assert_allclose(r["T_drive_m"], r["T_shaft"] / 4.0, rtol=1e-9, atol=1e-12 * np.abs(r["T_shaft"]).max())


def test_massless_node_between_damped_springs_with_proportional_damping_is_exact():
    # springs with d = beta C on both sides of a massless node: the node follows the static
    # balance exactly; compare with a tiny (1e-12) inertia at the node under a step load
    beta = 1e-3
    cps = [Coupling("a", "1", "m", 300.0, beta * 300.0), Coupling("b", "m", "2", 600.0, beta * 600.0)]
    free = Network([Inertia("1", 0.01), Inertia("m", 0.0), Inertia("2", 0.02)], [*cps, Load("2", 1.0)])
    tiny = Network([Inertia("1", 0.01), Inertia("m", 1e-12), Inertia("2", 0.02)], [*cps, Load("2", 1.0)])
    a = simulate(free, 0.3, 301, SolverConfig("exact"))
    b = simulate(tiny, 0.3, 301, SolverConfig("radau", rtol=1e-11, atol=1e-14, estimate_error=False))
    np.testing.assert_allclose(a["omega_2"], b["omega_2"], atol=1e-6 * np.abs(b["omega_2"]).max())
    np.testing.assert_allclose(a["phi_m"], b["phi_m"], atol=1e-6 * np.abs(b["phi_m"]).max())


def test_node_without_a_path_to_an_inertia_is_refused():
    with pytest.raises(InputError, match=r"node\(s\) lost have no inertia and no spring path to one"):
        Network([Inertia("a", 1.0), Inertia("lost", 0.0)], [])


def test_load_on_a_massless_node_is_refused():
    cps = [Coupling("a", "1", "m", 300.0, 0.0), Coupling("b", "m", "2", 600.0, 0.0)]
    with pytest.raises(InputError, match="a node without inertia cannot carry a load"):
        Network([Inertia("1", 0.01), Inertia("m", 0.0), Inertia("2", 0.02)], [*cps, Load("m", 1.0)])


def test_two_induction_motors_share_the_load_by_their_characteristics():
    # two motors on one stiff shaft line against a load: in steady state both run at the
    # common speed w and deliver 2 Mc_k (w0_k - w) / (w0_k Sc_k), summing to the load
    m1 = InductionMotor("a", 10.0, 0.2, 157.08, 314.16, name="m1")
    m2 = InductionMotor("b", 20.0, 0.25, 157.08, 314.16, name="m2")
    load = 6.0
    net = Network([Inertia("a", 0.01), Inertia("b", 0.02), Inertia("c", 0.05)],
                  [Coupling("ab", "a", "b", 2e4, 5.0), Coupling("bc", "b", "c", 2e4, 5.0), Load("c", load), m1, m2])
    assert [s for s, _ in net.state_names()[-2:]] == ["M_m1", "M_m2"]
    r = simulate(net, 3.0, 3001, SolverConfig("exact"))
    g1 = 2 * m1.breakdown_torque / (m1.sync_speed * m1.breakdown_slip)
    g2 = 2 * m2.breakdown_torque / (m2.sync_speed * m2.breakdown_slip)
    w = (g1 * m1.sync_speed + g2 * m2.sync_speed - load) / (g1 + g2)
    assert r["omega_c"][-1] == pytest.approx(w, rel=1e-9)
    assert r["M_m1"][-1] == pytest.approx(m1.static_torque(w), rel=1e-8)
    assert r["M_m2"][-1] == pytest.approx(m2.static_torque(w), rel=1e-8)


def test_two_motors_need_two_names():
    m = InductionMotor("a", 10.0, 0.2, 157.0, 314.0)
    with pytest.raises(InputError, match="give each motor a name of its own"):
        Network([Inertia("a", 0.01), Inertia("b", 0.01)],
                [Coupling("c", "a", "b", 1e3, 0.0), m, InductionMotor("b", 10.0, 0.2, 157.0, 314.0)])


def test_pint_quantities_are_converted_or_refused_by_name():
    from beltcalc.units import ureg

    Q = ureg().Quantity
    node = Inertia("a", Q(3.5, "g*m^2"))
    assert node.J == pytest.approx(3.5e-3, rel=1e-15)
    c = Coupling("c", "a", None, Q(2.0, "kN*m/rad"), Q(1.0, "N*m*s/rad"))
    assert (c.C, c.d) == pytest.approx((2000.0, 1.0), rel=1e-15)
    load = Load("a", amplitude=Q(1.0, "N*m"), omega=Q(60.0, "rpm"))
    assert load.omega == pytest.approx(2 * math.pi, rel=1e-15)
    with pytest.raises(InputError, match=r"^Load.omega = 5 m: it must be in rad/s$"):
        Load("a", omega=Q(5.0, "m"))
    with pytest.raises(InputError, match=r"^Coupling.U = 2 m: it must be a plain number$"):
        Coupling("c", "a", None, 1.0, 0.0, Q(2.0, "m"))


def test_angle_locked_load_of_order_two_has_its_jacobian():
    net = Network([Inertia("a", 0.5)],
                  [Coupling("g", "a", None, 10.0, 0.1), Load("a", amplitude=0.7, in_angle=True, order=2.0, phase=0.3)])
    x = np.array([0.4, 1.0])
    jac = net.nonlinear_jacobian(x)
    h = 1e-7
    fd = (net.nonlinear_terms(0.0, x + [h, 0.0]) - net.nonlinear_terms(0.0, x - [h, 0.0])) / (2 * h)
    assert jac[1, 0] == pytest.approx(fd[1], rel=1e-7)
    assert jac[1, 0] == pytest.approx(-0.7 * 2.0 * math.cos(2.0 * 0.4 + 0.3) / 0.5, rel=1e-14)


def test_a_new_element_kind_plugs_in_through_elements_alone():
    # a constant-torque brake on a node, as a kind of its own: its hooks are all the network
    # calls; a 1-DOF inertia decelerates at T / J from its initial speed (x0)
    from dataclasses import dataclass

    from beltcalc.sim.elements import Element

    @dataclass(frozen=True)
    class Brake(Element):
        node: str
        torque: float

        def inputs(self, piece):
            piece.torque(self.node, -self.torque)

        def outputs(self, net, t, X, dX):
            return {f"T_brake_{self.node}": (np.full(np.shape(t), self.torque), "N m")}

    net = Network([Inertia("w", 0.5)], [Brake("w", 2.0)])
    r = simulate(net, 1.0, 11, SolverConfig("exact"), x0=np.array([0.0, 10.0]))
    np.testing.assert_allclose(r["omega_w"], 10.0 - 2.0 / 0.5 * r.t, rtol=1e-13)
    np.testing.assert_allclose(r["T_brake_w"], 2.0, rtol=0)


def test_one_list_of_elements_is_stamped_kind_by_kind():
    # Network(nodes, elements): the order across kinds does not matter (the network stamps
    # couplings, speed loops, loads, prescribed motions, motors, then other kinds, each as
    # listed), so two listings give the very same matrices; gears and strands are sorted out
    nodes = [Inertia("m", 0.01), Inertia("p", 0.002), Inertia("w", 0.3), Inertia("s", 0.05)]
    c1, c2 = Coupling("c1", "m", "p", 1e3, 0.1), Coupling("c2", "w", None, 50.0, 0.2)
    loads = [Load("w", 2.0, 0.5, 30.0), Load("w", -0.5, table=((0.0, 0.0), (1.0, 1.0)))]
    motor = InductionMotor("m", 10.0, 0.2, 157.0, 314.0)
    gear, strand = Gear("p", "w", 4.0), Strand("chain", "w", "s", 0.05, 0.05, 1e6, 10.0, 100.0)
    a = Network(nodes, [c1, c2, *loads, motor, gear, strand])
    b = Network(nodes, [strand, loads[0], motor, c1, gear, loads[1], c2])
    assert [type(el).__name__ for el in b.elements] == ["Coupling", "Coupling", "Load", "Load", "InductionMotor"]
    assert (b.couplings, b.loads, b.motors, b.gears, b.strands) == ([c1, c2], loads, [motor], [gear], [strand])
    for taut in ((True,), (False,)):
        for t_mid in (0.5, 2.0):
            for x, y in zip(a.first_order(taut, t_mid), b.first_order(taut, t_mid)):
                np.testing.assert_array_equal(x, y)
    assert a.state_names() == b.state_names()


def test_a_node_or_a_stranger_among_the_elements_is_refused():
    nodes = [Inertia("a", 1.0)]
    with pytest.raises(InputError, match="Inertia 'b' among the elements is a node: nodes go in the first list"):
        Network(nodes, [Inertia("b", 1.0)])
    with pytest.raises(InputError, match="str '' among the elements is not an element"):
        Network(nodes, ["coupling"])
