"""Tests of the frequency domain (beltcalc.sim.frequency): poles and mode shapes against
Friswell's systems (openTorsion's cases) solved by scipy.linalg.eigh, frequency responses
against the analytic two-mass and one-mass systems and against python-control, the exact
periodic steady state of the sewing drive against long exact time simulations (whole
periods, extremes off the exact solution), Campbell crossings against 2 pi f / k."""

import math

import numpy as np
import pytest
import scipy.linalg as sla

from beltcalc.errors import InputError
from beltcalc.sim import frequency as fr
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.drivefile import load_drive
from beltcalc.sim.network import Coupling, Inertia, Load, Network, Strand


def _eigh(M, K):
    w2, V = sla.eigh(np.asarray(K, float), np.asarray(M, float))
    keep = w2 > 1e-9 * w2.max()
    return np.sqrt(w2[keep]) / (2 * math.pi), V[:, keep]


def _normalised(v):
    v = np.asarray(v, float)
    return v / v[np.argmax(np.abs(v))]


def test_friswell_five_disks_poles_and_mode_shapes():
    net = load_drive("friswell_5_disks").network
    J = [3.5e-3, 3.5e-3, 3.5e-3, 0.15, 0.05]
    K = np.zeros((5, 5))
    for n, c in enumerate((12e3, 12e3, 14e3, 10e3)):
        K[n:n + 2, n:n + 2] += c * np.array([[1, -1], [-1, 1]])
    f, V = _eigh(np.diag(J), K)
    poles = fr.poles(net)
    assert [p.kind for p in poles] == ["rigid", "rigid"] + ["oscillatory"] * 4
    assert [p.frequency for p in poles[2:]] == pytest.approx(f, rel=1e-9)
    assert [p.damping_ratio for p in poles[2:]] == pytest.approx([0.0] * 4, abs=1e-12)
    for shape, ref in zip(fr.mode_shapes(net), V.T):
        signed = [shape.amplitude[f"disk{k}"] * math.cos(math.radians(shape.phase[f"disk{k}"])) for k in range(1, 6)]
        np.testing.assert_allclose(signed, _normalised(ref), rtol=1e-9, atol=1e-12)
        energy = {f"k{k}": 0.5 * c * (ref[k - 1] - ref[k]) ** 2 for k, c in zip(range(1, 5), (12e3, 12e3, 14e3, 10e3))}
        total = sum(energy.values())
        assert shape.energy == pytest.approx({k: e / total for k, e in energy.items()}, rel=1e-9, abs=1e-12)
        assert shape.dominant == max(energy, key=energy.get)


def test_friswell_geared_mode_shapes_include_the_merged_gears():
    net = load_drive("friswell_geared").network
    shapes = fr.mode_shapes(net)
    assert [m.pole.frequency for m in shapes] == pytest.approx([10.30419, 20.47926, 24.42292], rel=1e-6)
    for m in shapes:
        # gear 3 turns at 1/1.6 of gear 1, gear 2 with gear 1, gear 4 with gear 3's ratio off gear 2
        assert m.amplitude["gear3"] == pytest.approx(m.amplitude["gear1"] / 1.6, rel=1e-12)
        assert m.amplitude["gear2"] == pytest.approx(m.amplitude["gear1"], rel=1e-12)
        assert m.amplitude["gear4"] == pytest.approx(m.amplitude["gear1"] / 1.6, rel=1e-12)


def test_one_mass_velocity_response_has_q_of_one_over_two_zeta_exactly():
    # mobility of J phi'' + d phi' + C phi = T: peak at w_n, half-power bandwidth d / J, so
    # Q = w_n J / d = 1 / (2 zeta) exactly
    J, C, d = 0.3, 1200.0, 0.9
    net = Network([Inertia("a", J)], [Coupling("k", "a", None, C, d)])
    wn = math.sqrt(C / J)
    r = fr.frequency_response(net, ["load:a"], ["omega_a"], np.linspace(0.5 * wn, 1.5 * wn, 301))
    (f, peak, q), = r.peaks[("omega_a", "load:a")]
    assert f * 2 * math.pi == pytest.approx(wn, rel=1e-9)
    assert peak == pytest.approx(1 / d, rel=1e-9)
    assert q == pytest.approx(wn * J / d, rel=1e-7)
    zeta = fr.poles(net)[0].damping_ratio
    assert q == pytest.approx(1 / (2 * zeta), rel=1e-7)


def test_two_mass_response_at_resonance_and_antiresonance():
    # T on mass 1: phi_1 = T (J2 s^2 + d s + C) / (s^2 (J1 J2 s^2 + (J1 + J2)(d s + C)))
    J1, J2, C, d = 0.02, 0.05, 800.0, 0.04
    net = Network([Inertia("1", J1), Inertia("2", J2)], [Coupling("c", "1", "2", C, d)])
    wr = math.sqrt(C * (1 / J1 + 1 / J2))
    wa = math.sqrt(C / J2)
    w = np.array([0.5 * wa, wa, 0.9 * wr, wr, 1.3 * wr])
    r = fr.frequency_response(net, ["load:1"], ["omega_1", "accel_1", "T_c"], w)
    s = 1j * w
    phi1 = (J2 * s ** 2 + d * s + C) / (s ** 2 * (J1 * J2 * s ** 2 + (J1 + J2) * (d * s + C)))
    phi2 = (d * s + C) / (s ** 2 * (J1 * J2 * s ** 2 + (J1 + J2) * (d * s + C)))
    np.testing.assert_allclose(r.H[:, 0, 0], s * phi1, rtol=1e-11)
    np.testing.assert_allclose(r.H[:, 1, 0], s ** 2 * phi1, rtol=1e-11)
    np.testing.assert_allclose(r.H[:, 2, 0], (C + d * s) * (phi1 - phi2), rtol=1e-10)
    # the antiresonance of the driven mass is deep and the resonance high: (J2 wa^2 = C)
    assert abs(r.H[1, 0, 0]) == pytest.approx(abs(s[1] * d * s[1] * phi2[1] / (d * s[1] + C)) * 0 + abs(s[1] * phi1[1]),
                                              rel=1e-11)
    assert abs(r.H[1, 0, 0]) / abs(r.H[3, 0, 0]) == pytest.approx(abs(phi1[1] * s[1]) / abs(phi1[3] * s[3]), rel=1e-11)


def test_frequency_response_matches_python_control():
    control = pytest.importorskip("control")
    net = load_drive("sewing").network
    A = net.state_matrix()
    B = np.column_stack([fr.input_column(net, "load:3"), fr.input_column(net, "supply:motor")])
    C = np.array([fr.output_row(net, "omega_3")[0], fr.output_row(net, "T_45")[0]])
    w = np.logspace(0, 4, 60)
    ref = control.ss(A, B, C, np.zeros((2, 2))).frequency_response(w).complex     # (outputs, inputs, w)
    r = fr.frequency_response(net, ["load:3", "supply:motor"], ["omega_3", "T_45"], w)
    np.testing.assert_allclose(np.moveaxis(r.H, 0, -1), ref, rtol=1e-9, atol=1e-14 * np.abs(ref).max())


def test_hessenberg_path_matches_batched_solves():
    rng = np.random.default_rng(1)
    n = fr.HESSENBERG_SIZE + 10
    A = rng.normal(size=(n, n)) - 3 * n ** 0.5 * np.eye(n)
    B = rng.normal(size=(n, 2))
    w = np.array([0.0, 0.7, 13.0])
    X = fr.solve_jw(A, B, w)
    for k, wk in enumerate(w):
        np.testing.assert_allclose(X[k], np.linalg.solve(1j * wk * np.eye(n) - A, B), rtol=1e-10, atol=1e-13)


def _whole_periods(net, periods: int, window: int, per_period: int = 100):
    """An exact run of ``periods`` load periods, sampled ``per_period`` times a period, with
    the window on the last ``window`` periods (its first sample exactly on a period)."""
    T = 2 * math.pi / net.frequencies()[0]
    names = ["omega_3", "omega_5", "T_23", "T_45", "M_motor"]
    start = (periods - window) * T
    r = simulate(net, periods * T, periods * per_period + 1, SolverConfig("exact"), watch=(names, (start,)))
    return r, names, start


@pytest.mark.parametrize("load_frequency, periods, window", [
    (0.0, 60, 30),                                   # the default: the steady main-shaft speed, 227.86 rad/s
    (4.0, 4, 2),                                     # 4 rad/s (the example)
    (2 * math.pi * 17.3634, 40, 20),                 # at the drive's resonance
])
def test_sewing_steady_state_equals_a_long_simulation_over_whole_periods(load_frequency, periods, window):
    # extremes and window means come off the exact solution (watched), so they do not
    # depend on the samples; the slowest pole (23 ms) has decayed by e^-40 before the window
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes import sewing

    net = sewing.build(SCENES["sewing"].values(load_frequency=load_frequency))
    r, names, start = _whole_periods(net, periods, window)
    ss = fr.steady_state(net, names)
    assert ss.exact and len(ss.frequencies) == 1
    for name in names:
        s = r.summary(name, start)
        assert s.amplitude == pytest.approx(ss.amplitude[name], rel=1e-8), name
        assert s.mean == pytest.approx(ss.mean[name], rel=1e-8, abs=1e-8 * ss.amplitude[name]), name


def test_steady_state_refuses_where_there_is_none():
    free = Network([Inertia("a", 1.0), Inertia("b", 1.0)], [Coupling("c", "a", "b", 10.0, 0.1), Load("b", 1.0)])
    with pytest.raises(InputError, match="do not balance: the drive accelerates"):
        fr.steady_state(free, ["omega_a"])
    slack = Network([Inertia("a", 1.0), Inertia("b", 1.0)],
                    [Coupling("g", "a", None, 100.0, 1.0), Load("b", 0.0, 50.0, 3.0),
                     Strand("s", "a", "b", 1.0, 1.0, 1e4, 10.0, 5.0)])
    with pytest.raises(InputError, match="strand s would go slack in the steady state"):
        fr.steady_state(slack, ["omega_a"])
    angle = Network([Inertia("a", 1.0)], [Coupling("g", "a", None, 100.0, 1.0), Load("a", 0.0, 1.0, in_angle=True)])
    with pytest.raises(InputError, match="nonlinear"):
        fr.steady_state(angle, ["omega_a"])


def test_campbell_crossings_of_a_two_mass_system():
    # w^2 = C (1/J1 + 1/J2): f = 25 Hz; order k crosses at shaft speed 2 pi 25 / k
    J1, J2 = 0.01, 0.04
    C = (2 * math.pi * 25) ** 2 / (1 / J1 + 1 / J2)
    net = Network([Inertia("m", J1), Inertia("l", J2)], [Coupling("c", "m", "l", C, 0.02)])
    crossings = fr.campbell(net, [1, 2, 3, 4], speed_max=2 * math.pi * 25 / 1.5)
    assert [c.order for c in crossings] == [4, 3, 2]
    f = fr.poles(net)[-1].frequency
    assert [c.speed for c in crossings] == pytest.approx([2 * math.pi * f / k for k in (4, 3, 2)], rel=1e-14)
    assert f == pytest.approx(25.0 * math.sqrt(1 - crossings[0].damping_ratio ** 2) / math.sqrt(1 - crossings[0].damping_ratio ** 2),
                              rel=1e-6)


def test_sewing_steady_state_only_run_reports_the_same_steady_state_without_simulating():
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes.base import run_scene

    scene = SCENES["sewing"]
    full = run_scene(scene, scene.values(), SolverConfig())
    fast = run_scene(scene, scene.values(), SolverConfig(), steady_state_only=True)
    assert fast.result.method == "steady state" and fast.result.t.size == 0
    steady = {(s.path, r.key): r.value for s in full.sections if s.path[0] == "steady_state" for r in s.rows}
    assert {(s.path, r.key): r.value for s in fast.sections for r in s.rows} == steady
    # and the paper's Fig. 5 quantity, the bottom shaft's speed amplitude, is the window
    # reading's to the start-up transient's leftover
    window = next(r.value for s in full.sections if s.path == ("shafts", "bottom") for r in s.rows
                  if r.key == "speed_amplitude")
    assert steady[(("steady_state", "bottom_shaft"), "speed_amplitude")] == pytest.approx(window, rel=1e-5)
    with pytest.raises(InputError, match="no exact steady state"):
        run_scene(scene, scene.values(), SolverConfig(), angle_loads=True, steady_state_only=True)


def test_an_undamped_resonance_has_no_bandwidth_not_an_error():
    net = Network([Inertia("a", 1.0)], [Coupling("k", "a", None, 100.0, 0.0)])
    r = fr.frequency_response(net, ["load:a"], ["phi_a"], np.linspace(1, 20, 400))
    (f, mag, q), = r.peaks[("phi_a", "load:a")]
    assert f * 2 * math.pi == pytest.approx(10.0, rel=1e-6)
    assert q == math.inf
