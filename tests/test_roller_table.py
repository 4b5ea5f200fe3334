"""The roller-table drive of Rusek & Popenda (seeds/002): the chain formulas of
beltcalc/formulas/chain.py, and the scene beltcalc/sim/scenes/roller_table.py on the shared core.

Hand computation for the default scene (catalogs/scenes/roller_table.toml), SI:
  sprockets: 10B-1 chain p = 15.875 mm, z = 19: d = p / sin(180 deg / 19) = 15.875 / 0.16459459
             = 96.4491 mm, r = 48.22455 mm (ISO 606 / DIN 8187)
  ratio: i = 5 * 5 * 19 / 19 = 25 (two gear stages, sprockets 19:19)
  motor: w0 = 2 pi 50 / 2 = 157.07963 rad/s, M_c = 2.3 * 7.3 = 16.79 N m, S_c = 0.2
  steady state, n = 3 rollers of M = 40 N m: M_m = n M / i = 120 / 25 = 4.8 N m,
    w_m = w0 (1 - S_c M_m / (2 M_c)) = 157.07963 (1 - 0.2 * 4.8 / 33.58) = 152.58897 rad/s,
    rollers w_m / i = 6.1035588 rad/s (Mamatova et al. eq. 2, linearised Kloss)
  chain, serpentine: the drive strand carries the whole table, n M / r = 120 / 0.04822455 = 2488.36 N;
    each roller takes M / r = 829.453 N out of the chain; an idler passes the force on.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.formulas.chain import load_split, placement_factor, sprocket_pitch_diameter, strand_stiffness, torsional_stiffness
from beltcalc.errors import InputError, SimulationError
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.network import Coupling, Load, Network
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.scenes import roller_table as rt

# the scene's values in SI, as the command resolves them
PARAMS = SCENES["roller-table"].values()
EXACT = SolverConfig("exact", estimate_error=False)
R_SPROCKET = 0.015875 / math.sin(math.pi / 19) / 2      # 48.22455 mm (module docstring)


def scene(**changes) -> dict:
    return dict(PARAMS, **changes)


def speeds(net: Network, result) -> np.ndarray:
    return np.array([result[f"omega_{node.name}"] for node in net.nodes])


def test_hand_values_of_the_docstring():
    p = scene()
    assert R_SPROCKET == pytest.approx(0.04822455, rel=1e-7)
    assert rt.total_ratio(p) == pytest.approx(25.0, rel=1e-15)
    assert rt.synchronous_speed(p) == pytest.approx(157.07963, rel=1e-7)
    # w0 (1 - S_c M_m / (2 M_c)) / i with M_m = 4.8 N m
    assert rt.steady_speed(p) == pytest.approx(6.1035588, rel=1e-7)
    assert rt.steady_speed(scene(rollers=1.0)) == pytest.approx(155.58275 / 25, rel=1e-7)


# --- chain.py ----------------------------------------------------------------------------------

def test_sprocket_pitch_diameter_10b1_19_teeth():
    # d = p / sin(180 deg / z) = 15.875 mm / sin(9.4737 deg) = 96.449 mm (ISO 606; the scene file)
    assert sprocket_pitch_diameter(0.015875, 19) == pytest.approx(0.096449, rel=1e-5)
    assert sprocket_pitch_diameter(0.015875, 19) * 1e3 == pytest.approx(96.45, abs=0.005)
    # 15 teeth (the idlers): 15.875 / sin(12 deg) = 76.354 mm (toml: "d = 76.35 mm")
    assert sprocket_pitch_diameter(0.015875, 15) == pytest.approx(0.076354, rel=1e-4)
    # many teeth: the pitch circle tends to z p / pi
    assert sprocket_pitch_diameter(0.015875, 1000) == pytest.approx(1000 * 0.015875 / math.pi, rel=1e-5)


@pytest.mark.parametrize("pitch, teeth", [(0.015875, 2), (0.015875, 19.5), (0.0, 19), (-0.015875, 19)])
def test_sprocket_refuses_nonsense(pitch, teeth):
    with pytest.raises(InputError):
        sprocket_pitch_diameter(pitch, teeth)


def test_strand_stiffness_is_ea_over_length():
    # c = EA / L: 1.5 MN / 0.6 m = 2.5 MN/m (the scene's roller-to-roller strand)
    assert strand_stiffness(1.5e6, 0.6) == pytest.approx(2.5e6, rel=1e-15)
    assert strand_stiffness(1.5e6, 1.2) == pytest.approx(1.25e6, rel=1e-15)
    with pytest.raises(InputError):
        strand_stiffness(1.5e6, 0.0)


def test_torsional_stiffness_of_shaft_and_tube():
    # c = G pi (D^4 - d^4) / (32 L)
    # journal 60 mm solid, 150 mm, G = 81 GPa: I_p = pi 0.06^4 / 32 = 1.2723450e-6 m^4,
    #   c = 81e9 * 1.2723450e-6 / 0.15 = 687066.3 N m/rad
    assert torsional_stiffness(0.06, 0.0, 0.15, 81e9) == pytest.approx(687066.3, rel=1e-7)
    # tube 219.1 x 8 mm, 1.2 m: D^4 - d^4 = 0.2191^4 - 0.2031^4 = 2.3044618e-3 - 1.7015303e-3
    #   = 6.029315e-4 m^4, I_p = 5.919266e-5 m^4, c = 81e9 * 5.919266e-5 / 1.2 = 3.995504e6 N m/rad
    assert torsional_stiffness(0.2191, 0.2031, 1.2, 81e9) == pytest.approx(3.995504e6, rel=1e-6)
    # a tube is the solid bar minus its bore; stiffness goes as 1/L
    whole, bore = torsional_stiffness(0.2191, 0.0, 1.2, 81e9), torsional_stiffness(0.2031, 0.0, 1.2, 81e9)
    assert torsional_stiffness(0.2191, 0.2031, 1.2, 81e9) == pytest.approx(whole - bore, rel=1e-12)
    assert torsional_stiffness(0.06, 0.0, 0.3, 81e9) == pytest.approx(687066.3 / 2, rel=1e-7)


@pytest.mark.parametrize("args", [(0.06, 0.06, 0.15, 81e9), (0.06, -0.01, 0.15, 81e9), (0.06, 0.0, 0.0, 81e9),
                                  (0.0, 0.0, 0.15, 81e9), (0.06, 0.0, 0.15, 0.0)])
def test_torsional_stiffness_refuses_nonsense(args):
    with pytest.raises(InputError):
        torsional_stiffness(*args)


@pytest.mark.parametrize("offset, width, length, expected", [
    (0.2, 0.8, 1.2, 1.0),     # centred: a_x = (L - a) / 2 (the scene's default)
    (0.0, 0.8, 1.2, 0.0),     # against the drive end
    (0.4, 0.8, 1.2, 2.0),     # against the far end
    (0.1, 0.8, 1.2, 0.5),     # 2 * 0.1 / 0.4
    (0.3, 0.6, 1.2, 1.0),     # 2 * 0.3 / 0.6
    (0.0, 1.2, 1.2, 1.0),     # as long as the roller: centred by force
])
def test_placement_factor_values(offset, width, length, expected):
    # w_p = 2 a_x / (L - a), Rusek & Popenda eq. 16
    assert placement_factor(offset, width, length) == pytest.approx(expected, rel=1e-14, abs=1e-15)


@pytest.mark.parametrize("offset, width, length", [
    pytest.param(-0.1, 0.8, 1.2, id="negative-offset"),
    pytest.param(0.5, 0.8, 1.2, id="offset-beyond-L-minus-a"),
    pytest.param(0.0, 1.5, 1.2, id="wider-than-roller"),
    pytest.param(0.0, -0.8, 1.2, id="negative-width"),
    pytest.param(0.0, 0.0, 1.2, id="zero-width"),
    pytest.param(0.0, 0.8, -1.2, id="negative-length"),
    pytest.param(0.0, 0.8, 0.0, id="zero-length"),
    # a = L leaves no room: any a_x > 0 = L - a puts the element past the roller's end
    pytest.param(0.3, 1.2, 1.2, id="offset-with-full-width"),
])
def test_placement_factor_refuses_nonsense(offset, width, length):
    with pytest.raises(InputError):
        placement_factor(offset, width, length)


@pytest.mark.parametrize("factor", [0.0, 0.3, 1.0, 1.7, 2.0])
def test_load_split_shares(factor):
    near, far = load_split(factor, 0.8, 1.2)
    assert near + far == pytest.approx(1.0, rel=1e-15)
    assert 0.0 < far < 1.0 and 0.0 < near < 1.0
    # lever rule: centre c = (w_p (L - a) + a) / 2, far share c / L
    assert far == pytest.approx((factor * 0.4 + 0.8) / 2.4, rel=1e-14)
    # mirror symmetry: w_p -> 2 - w_p puts the element at the other end, the shares swap
    mirrored = load_split(2.0 - factor, 0.8, 1.2)
    assert mirrored == pytest.approx((far, near), rel=1e-14)


def test_load_split_centred_and_at_the_ends():
    assert load_split(1.0, 0.8, 1.2) == pytest.approx((0.5, 0.5), rel=1e-15)
    # against the drive end: centre at a / 2 = 0.4 m of 1.2 m, far end 1/3
    assert load_split(0.0, 0.8, 1.2) == pytest.approx((2 / 3, 1 / 3), rel=1e-14)
    # a narrow element at the far end: centre at L - a / 2 = 1.15 m, far share 1.15 / 1.2
    assert load_split(2.0, 0.1, 1.2) == pytest.approx((0.05 / 1.2, 1.15 / 1.2), rel=1e-13)
    for factor in (-0.1, 2.1):
        with pytest.raises(InputError):
            load_split(factor, 0.8, 1.2)


# --- the scene: routing, inertias ----------------------------------------------------------------

def test_serpentine_and_loops_routing():
    ser = rt.strands(scene())
    assert [s[0] for s in ser] == ["drive-sprocket1", "sprocket1-idler1", "idler1-sprocket2", "sprocket2-idler2",
                                   "idler2-sprocket3", "sprocket3-drive"]
    # 0.5 m to roller 1, half a roller pitch to and from each idler, the return the whole table
    assert_allclose([s[3] for s in ser], [0.5, 0.3, 0.3, 0.3, 0.3, 1.7], rtol=1e-14)
    loops = rt.strands(scene(routing="loops"))
    assert [(s[1], s[2]) for s in loops] == [("drive", "sprocket1"), ("sprocket1", "drive"),
                                             ("sprocket1", "sprocket2"), ("sprocket2", "sprocket1"),
                                             ("sprocket2", "sprocket3"), ("sprocket3", "sprocket2")]
    no_idlers = rt.strands(scene(idler_inertia=0.0))
    assert [s[0] for s in no_idlers] == ["drive-sprocket1", "sprocket1-sprocket2", "sprocket2-sprocket3",
                                         "sprocket3-drive"]


def test_roller_and_sprocket_inertia():
    # J = pi rho w (D^4 - d^4) / 32: tube 219.1 x 8 mm, 1.2 m, 7850 kg/m^3:
    #   pi 7850 1.2 6.029315e-4 / 32 = 0.557571 kg m^2
    assert rt.roller_inertia(scene()) == pytest.approx(math.pi * 7850 * 1.2 * 6.029315e-4 / 32, rel=1e-6)
    # sprocket: a steel disc of the pitch diameter 96.449 mm, 20 mm thick
    assert rt.sprocket_inertia(scene(), 19) == pytest.approx(math.pi * 7850 * 0.02 * 0.096449 ** 4 / 32, rel=1e-4)


# --- the scene on the core ---------------------------------------------------------------------

def test_taut_strands_are_couplings_with_a_constant_pretension_torque():
    # With every strand taut, the strand a -> b (delta = r_a phi_a - r_b phi_b + F0 / c) is the
    # coupling C = c r_a^2, d = b r_a^2, U = r_b / r_a plus the constant torques -r_a F0 on a and
    # +r_b F0 on b (Load is a torque against the motion). 5 kN of pretension keeps every strand
    # taut through start-up and load; the two networks must give the same motion.
    p = scene(pretension=5000.0, load_start=1.0)
    net = rt.build(p)
    res = simulate(net, 2.5, 2501, EXACT)
    assert all(v == 0.0 for v in res.extra["slack_time"].values()), res.extra["slack_time"]
    assert res.extra["events"] == 0
    for s in net.strands:
        assert res[f"F_{s.name}"].min() > 0.0, s.name
    couplings = list(net.couplings)
    loads = list(net.loads)
    for s in net.strands:
        couplings.append(Coupling(s.name, s.i, s.j, s.stiffness * s.r_i ** 2, s.damping * s.r_i ** 2, s.r_j / s.r_i))
        loads += [Load(s.i, mean=s.r_i * s.preload), Load(s.j, mean=-s.r_j * s.preload)]
    linear = Network(net.nodes, [*couplings, *loads, *net.motors])
    ref = simulate(linear, 2.5, 2501, EXACT)
    scale = float(np.max(np.abs(speeds(linear, ref))))
    assert scale > 100.0  # the motor is near 150 rad/s: the comparison is not of zeros
    assert_allclose(speeds(net, res), speeds(linear, ref), rtol=0, atol=1e-9 * scale)
    # the strand force is the coupling's torque over r_a, plus the pretension
    for s in net.strands:
        assert_allclose(res[f"F_{s.name}"], ref[f"T_{s.name}"] / s.r_i + s.preload, rtol=1e-7,
                        atol=1e-9 * s.preload)


def test_steady_torque_balance_serpentine():
    # element against the drive end (a_x = 0): w_p = 0, far-end share (0 + 0.8) / 2.4 = 1/3
    p = scene(element_offset=0.0)
    net = rt.build(p)
    res = simulate(net, 6.0, 6001, EXACT)
    w0 = 4.5        # the load lands at 3 s; 1.5 s to settle (the scene's window)
    n, load = 3, 40.0
    # module docstring: M_m = 3 * 40 / 25 = 4.8 N m, rollers at 6.1035588 rad/s
    assert res.summary("M_motor", w0).mean == pytest.approx(n * load / rt.total_ratio(p), rel=1e-3)
    assert res.summary("M_motor", w0).mean == pytest.approx(4.8, rel=1e-3)
    near, far = load_split(0.0, 0.8, 1.2)
    assert far == pytest.approx(1 / 3, rel=1e-14)
    for k in range(1, n + 1):
        for end in "ab":
            assert res.summary(f"omega_end{k}{end}", w0).mean == pytest.approx(rt.steady_speed(p), rel=1e-4), (k, end)
        # the journal carries the whole roller load, the tube the far end's share
        assert res.summary(f"T_shaft{k}", w0).mean == pytest.approx(load, rel=1e-3), k
        assert res.summary(f"T_tube{k}", w0).mean == pytest.approx(far * load, rel=1e-3), k
    # the chain: the drive strand pulls the table, each roller takes M / r, idlers pass it on,
    # the return strand has gone slack (its 300 N pretension is less than the tight side's rise)
    force = {s.name: res.summary(f"F_{s.name}", w0).mean for s in net.strands}
    assert force["drive-sprocket1"] == pytest.approx(3 * load / R_SPROCKET, rel=1e-3)      # 2488.36 N
    assert force["sprocket1-idler1"] == pytest.approx(2 * load / R_SPROCKET, rel=1e-3)     # 1658.91 N
    assert force["idler1-sprocket2"] == pytest.approx(force["sprocket1-idler1"], rel=1e-5)
    assert force["idler2-sprocket3"] == pytest.approx(load / R_SPROCKET, rel=1e-3)         # 829.45 N
    assert force["sprocket3-drive"] == 0.0     # exactly: a slack strand carries nothing
    assert res.extra["slack_time"]["sprocket3-drive"] > 2.5
    assert res.extra["slack_time"]["drive-sprocket1"] == 0.0


def test_steady_torque_balance_loops():
    # roller to roller loops: the same motor balance, each pair's tight strand carries what lies
    # beyond it. The loops ring longer than the serpentine after the load lands (about 1.5 s to
    # 1e-4): the window starts 1.5 s after the landing and spans 1 s.
    p = scene(routing="loops", load_start=2.5)
    net = rt.build(p)
    res = simulate(net, 5.0, 5001, EXACT)
    w0 = 4.0
    assert res.summary("M_motor", w0).mean == pytest.approx(4.8, rel=1e-3)
    for k in (1, 2, 3):
        assert res.summary(f"omega_end{k}a", w0).mean == pytest.approx(rt.steady_speed(p), rel=1e-4), k
        assert res.summary(f"T_shaft{k}", w0).mean == pytest.approx(40.0, rel=1e-3), k
        assert res.summary(f"T_tube{k}", w0).mean == pytest.approx(20.0, rel=1e-3), k
    # tight minus slack strand of the loop into roller k: the load of rollers k..3 over r
    for k, a, b in ((3, "drive", "sprocket1"), (2, "sprocket1", "sprocket2"), (1, "sprocket2", "sprocket3")):
        pull = res.summary(f"F_{a}-{b}", w0).mean - res.summary(f"F_{b}-{a}", w0).mean
        assert pull == pytest.approx(k * 40.0 / R_SPROCKET, rel=1e-3), (a, b)
    # the return strand of every loop went slack when the load landed and stayed so
    for a, b in (("sprocket1", "drive"), ("sprocket2", "sprocket1"), ("sprocket3", "sprocket2")):
        assert res.extra["slack_time"][f"{a}-{b}"] > 2.0, (a, b)
        assert res[f"F_{a}-{b}"][res.window(w0)].max() == 0.0, (a, b)


def overrunning(net: Network) -> Network:
    """The same network with every roller load reversed: the load drives the rollers."""
    loads = [dataclasses.replace(ld, mean=-ld.mean, amplitude=-ld.amplitude,
                                 table=tuple((t, -v) for t, v in ld.table)) for ld in net.loads]
    return Network(net.nodes, [*net.couplings, *loads, *net.motors, *net.strands])


def test_overrunning_load_slackens_the_drive_strand_whatever_the_solver():
    # roller_load = -40 N m from 1.5 s: the rollers run ahead of the chain. The drive strand
    # (drive -> roller 1) goes slack and stays slack; the return strand (roller 3 -> drive) holds
    # the table back. Exact and radau must find the same switch and the same motion.
    p = scene(load_start=1.5)
    net = overrunning(rt.build(p))
    dt = 1e-3
    ex = simulate(net, 3.0, 3001, EXACT)
    ra = simulate(net, 3.0, 3001, SolverConfig("radau", rtol=1e-9, atol=1e-12, estimate_error=False))
    slack = ex.extra["slack_time"]
    # slack from soon after the landing to the end (1.5 s at most)
    assert 1.0 < slack["drive-sprocket1"] < 1.5
    for name in ("sprocket1-idler1", "idler1-sprocket2", "sprocket2-idler2", "idler2-sprocket3",
                 "sprocket3-drive"):
        assert slack[name] == 0.0, name
    late = ex.window(2.0)
    assert ex["F_drive-sprocket1"][late].max() == 0.0
    assert ex["F_sprocket3-drive"][late].min() > 1000.0
    # the same switches
    assert ra.extra["events"] == ex.extra["events"]
    assert ex.extra["events"] >= 1
    for name, value in slack.items():
        assert ra.extra["slack_time"][name] == pytest.approx(value, abs=3 * dt), name
    # the same motion, to 1e-6 of the speed scale (rtol 1e-9 on ~150 rad/s leaves ~1e-7 rad/s)
    scale = float(np.max(np.abs(speeds(net, ex))))
    assert_allclose(speeds(net, ra), speeds(net, ex), rtol=0, atol=1e-6 * scale)


def test_overrunning_load_steady_balance():
    # M_m = -4.8 N m (the motor brakes, above synchronous speed):
    #   w_m = 157.07963 (1 + 0.2 * 4.8 / 33.58) = 161.57030 rad/s, rollers 6.4628118 rad/s;
    # the return strand carries the whole table: 120 N m / r = 2488.36 N; roller 3 hands it
    # 829.45 N of its own and passes on 2 x 829.45 N from rollers 1 and 2.
    # With the drive strand slack the table rings on the long return strand (1.7 m, chain damping
    # 2e-4 s): 2.5 s after the landing the 2 s window mean is within 3e-4 of the balance.
    p = scene(load_start=1.5)
    net = overrunning(rt.build(p))
    res = simulate(net, 6.0, 3001, EXACT)
    w0 = 4.0
    assert rt.steady_speed(dict(p, roller_load=-40.0)) == pytest.approx(6.4628118, rel=1e-7)
    assert res.summary("M_motor", w0).mean == pytest.approx(-4.8, rel=1e-3)
    assert res.summary("omega_end1a", w0).mean == pytest.approx(6.4628118, rel=2e-4)
    assert res.summary("F_sprocket3-drive", w0).mean == pytest.approx(3 * 40.0 / R_SPROCKET, rel=1e-3)
    assert res.summary("F_sprocket2-idler2", w0).mean == pytest.approx(2 * 40.0 / R_SPROCKET, rel=1e-3)
    assert res.summary("F_sprocket1-idler1", w0).mean == pytest.approx(40.0 / R_SPROCKET, rel=1e-3)
    assert res.summary("T_shaft2", w0).mean == pytest.approx(-40.0, rel=1e-3)


def test_scene_accepts_a_negative_roller_load():
    # the overrunning case through the scene itself: roller_load < 0 is a load that drives the rollers
    # (Load: "A negative load drives the node"); it must build the reversed network
    p = scene(load_start=1.5)
    reversed_ = rt.build(scene(load_start=1.5, roller_load=-40.0))
    expected = overrunning(rt.build(p))
    assert reversed_.loads == expected.loads


def test_one_roller_reaches_the_static_balance():
    p = scene(rollers=1.0, load_start=2.5)
    net = rt.build(p)
    res = simulate(net, 4.0, 4001, EXACT)
    assert np.all(np.isfinite(res.states))
    # M_m = 40 / 25 = 1.6 N m, rollers at w0 (1 - 0.2 * 1.6 / 33.58) / 25 = 6.2233098 rad/s
    assert res.summary("M_motor", 3.5).mean == pytest.approx(1.6, rel=1e-3)
    assert res.summary("omega_end1a", 3.5).mean == pytest.approx(6.2233098, rel=1e-4)
    assert res.summary("T_shaft1", 3.5).mean == pytest.approx(40.0, rel=1e-3)


def test_twenty_rollers_build_and_run():
    p = scene(rollers=20.0, load_start=1.0)
    net = rt.build(p)
    # 20 sprockets, 20 x 2 roller ends, 19 idlers, the drive, gear and motor
    assert net.n == 3 + 20 * 3 + 19
    assert len(net.strands) == 20 + 19 + 1
    assert [s.name for s in net.strands][-1] == "sprocket20-drive"
    # start-up only (the load lands after the run): 0.2 s of the inverter ramp
    res = simulate(net, 0.2, 21, EXACT)
    assert np.all(np.isfinite(res.states))
    drive = res["omega_drive"][-1]
    # the gear and clutch follow the motor (their twist is small against 25:1)
    assert drive == pytest.approx(res["omega_motor"][-1] / 25, rel=2e-2)
    # the chain winds up from the drive: every roller turns forward, none faster than the drive,
    # the first close behind it (the chain stretches strand by strand as the table speeds up)
    rollers = np.array([res[f"omega_end{k}b"][-1] for k in range(1, 21)])
    assert np.all(rollers > 0.0) and np.all(rollers < drive)
    assert rollers[0] == pytest.approx(drive, rel=0.1)
    # accelerating the table: the drive strand pulls above its pretension, the return strand
    # falls below it, and the force falls along the chain as each roller takes its share
    first, last = res["F_drive-sprocket1"][-1], res["F_sprocket20-drive"][-1]
    assert first > p["pretension"] > last
    assert res["F_sprocket10-idler10"][-1] < first


def test_chain_without_pretension_turns_the_rollers():
    # pretension 0: the strands hang exactly at zero elongation at rest; as the motor turns the
    # drive sprocket the drive strand stretches and must take up the rollers (the chain has no backlash)
    p = scene(pretension=0.0, load_start=3.0)     # no roller load in this run
    net = rt.build(p)
    res = simulate(net, 1.0, 1001, EXACT)
    # at 1 s of the 2 s ramp the drive sprocket turns near 3.1 rad/s; the rollers must follow
    assert res["omega_drive"][-1] == pytest.approx(3.12, rel=0.02)
    assert res["omega_end3b"][-1] == pytest.approx(res["omega_drive"][-1], rel=0.02), \
        "the rollers stand still while the drive sprocket turns: the chain never took up"
    assert res.extra["slack_time"]["drive-sprocket1"] < 0.5


def test_pulsating_load_starts_when_the_element_lands():
    # the element brings its load, mean and pulsation, when it lands (load_start): before that the
    # rollers carry nothing (roller_table.toml: "the element lands on the rollers at 3 s")
    p = scene(load_start=3.0, load_amplitude=10.0, load_frequency=20.0)
    net = rt.build(p)
    before = np.linspace(0.05, 2.95, 59)
    for ld in net.loads:
        assert_allclose(ld.torque(before), 0.0, atol=1e-12, err_msg=f"load on {ld.node} acts before it lands")
    # after the landing: mean + amplitude sin(w t), split between the ends (centred: 50/50)
    after = np.linspace(3.05, 5.0, 40)
    total = sum(ld.torque(after) for ld in net.loads if ld.node.startswith("end1"))
    assert_allclose(total, 40.0 + 10.0 * np.sin(20.0 * after), rtol=1e-12)


def test_chattering_is_bounded_and_named():
    # one roller under a +-40 N m pulsation at 30 rad/s on its 40 N m mean, from the start: the
    # chain loop's strands go slack and taut again and again (24 switches in 2.5 s, 15 s to run);
    # max_events = 5 stops the run early and names the strand and the option
    p = scene(rollers=1.0, load_start=0.0, load_amplitude=40.0, load_frequency=30.0)
    net = rt.build(p)
    with pytest.raises(SimulationError) as info:
        simulate(net, 2.5, 2501, SolverConfig("exact", max_events=5, estimate_error=False))
    text = str(info.value)
    assert "5 strand events" in text and "raise max_events" in text and "exact" in text
    named = [s.name for s in net.strands if f"strand {s.name} " in text]
    assert len(named) == 1, text
    reached = float(text.split("t = ")[1].split(" s")[0])
    assert 0.0 < reached < 2.5


def test_a_load_after_the_end_of_the_run_does_not_act():
    # causality: an element landing at 2.6 s cannot move a run that stops at 2.5 s; it must give
    # the same motion as an element that never lands within reach (at 10 s)
    late = rt.build(scene(load_start=2.6))
    never = rt.build(scene(load_start=10.0))
    a = simulate(late, 2.5, 501, EXACT)
    b = simulate(never, 2.5, 501, EXACT)
    # the outputs say no load acted
    assert_allclose(a["load_end1a"], 0.0, atol=1e-12)
    # no load: at the end of the ramp the journals carry only the rollers' acceleration torque
    assert b.summary("T_shaft1", 2.3).mean == pytest.approx(0.0, abs=1.0)
    assert_allclose(speeds(late, a), speeds(never, b), rtol=0, atol=1e-9 * 157.0,
                    err_msg="the load landing at 2.6 s acted inside a run that ends at 2.5 s")


def test_twenty_rollers_keep_every_strand_after_the_start_up():
    # regression: after the inverter ramp (2 s) the chain's strands slacken and take up again
    # one after another; a switch located a hair before its surface was once judged "no
    # switch", the strand was then never re-examined, and rollers 5-20 ran backwards with
    # strand forces of 78 MN. Every roller must turn forward together, and no strand may
    # carry more than the start-up can give it (the motor's breakdown torque through the
    # gear, at the driving sprocket, is about 16.8 * 25 / 0.048 = 8.7 kN)
    p = scene(rollers=20.0, t_end=2.8, samples=2801.0, window=2.5)
    net = rt.build(p)
    r = simulate(net, p["t_end"], int(p["samples"]), SolverConfig("exact", estimate_error=False))
    ends = np.array([r[f"omega_end{k}a"][-1] for k in range(1, 21)])
    assert_allclose(ends, ends.mean(), rtol=0.02)
    assert ends.min() > 0.9 * rt.synchronous_speed(p) / rt.total_ratio(p)
    breakdown = p["breakdown_factor"] * p["rated_torque"] * rt.total_ratio(p) / (
        sprocket_pitch_diameter(p["chain_pitch"], int(p["drive_teeth"])) / 2)
    assert max(r[f"F_{s.name}"].max() for s in net.strands) < breakdown


# --- issue 16: slack chains you can trust ---------------------------------------------------------
def _scene(**over):
    values = dict(PARAMS)
    values.update(over)
    return values


def test_zero_pretension_settles_at_the_static_balance():
    # no pretension: every strand starts on its surface, the start-up switches strands 258
    # times; once settled every roller turns at the static balance of the motor through the
    # ratios (rt.steady_speed). The old core left rollers 2 and 3 at -154 rad/s here.
    p = _scene(pretension=0.0)
    res = simulate(rt.build(p), 20.0, 4001, SolverConfig("exact", estimate_error=False))
    late = res.window(15.0)
    for k in (1, 2, 3):
        assert res[f"omega_end{k}a"][late].mean() == pytest.approx(rt.steady_speed(p), rel=1e-8), k
    assert res.extra["events"] > 100


def test_zero_pretension_agrees_with_radau():
    # independent reference: scipy's Radau with events at rtol 1e-9 on the default horizon.
    # The start-up chatter is sensitive (the two solvers differ by 0.07 rad/s pointwise while
    # strands take up at tiny speeds), the window means agree to 2e-7.
    p = _scene(pretension=0.0)
    net = rt.build(p)
    ex = simulate(net, 6.0, 6001, SolverConfig("exact", estimate_error=False))
    ra = simulate(net, 6.0, 6001, SolverConfig("radau", rtol=1e-9, atol=1e-12, estimate_error=False))
    w = ex.window(4.5)
    for k in (1, 2, 3):
        name = f"omega_end{k}a"
        assert ex[name][w].mean() == pytest.approx(ra[name][w].mean(), rel=1e-6), k
    assert ex["F_drive-sprocket1"].max() == pytest.approx(ra["F_drive-sprocket1"].max(), rel=2e-3)


def test_pulsating_load_trajectory_does_not_depend_on_the_output_grid():
    # a pulsating roller load slackens strands hundreds of times; the internal steps come
    # from the dynamics, so 5001 and 20001 samples give the same switches and the same states
    # at the common output times (the old core moved roller 1 by 0.09 rad/s between grids)
    p = _scene(load_amplitude=60.0, load_frequency=40.0)
    net = rt.build(p)
    coarse = simulate(net, 5.0, 5001, SolverConfig("exact", estimate_error=False))
    fine = simulate(net, 5.0, 20001, SolverConfig("exact", estimate_error=False))
    assert coarse.extra["events"] == fine.extra["events"] > 300
    assert_allclose([t for t, _, _ in coarse.extra["switches"]], [t for t, _, _ in fine.extra["switches"]],
                    rtol=0, atol=1e-12)
    for name in ("omega_end1a", "omega_motor", "F_drive-sprocket1"):
        scale = np.max(np.abs(fine[name]))
        assert_allclose(coarse[name], fine[name][::4], rtol=0, atol=1e-9 * scale, err_msg=name)


# --- issue 13: the chain's data from catalogs/chains.toml ---------------------------------------

def test_chain_data_comes_from_the_catalog():
    # the scene file names the chain (10B-1); pitch, mass and breaking load are the catalog's and
    # equal, bit for bit, to what the scene file typed before (15.875 mm, 0.91 kg/m, 22.2 kN)
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.units import parse_quantity

    chain = load_catalog().chain("10B-1")
    _, resolved = SCENES["roller-table"].resolve()
    assert resolved["chain"].value == "10B-1"
    for key, attr, typed, unit in (("chain_pitch", "pitch", "15.875 mm", "m"),
                                   ("chain_mass", "mass", "0.91 kg/m", "kg/m"),
                                   ("chain_breaking_load", "breaking_load", "22.2 kN", "N")):
        assert resolved[key].value == pytest.approx(getattr(chain, attr), rel=0, abs=0)
        assert resolved[key].value == pytest.approx(parse_quantity(typed, unit), rel=0, abs=0)
        assert resolved[key].origin == "catalog: 10B-1 (chains.toml)"
    # the drive names the chain: sprockets by teeth on it, strands with the catalog's mass and load
    data = rt.drive_data(PARAMS)
    assert {s["chain"] for s in data["chain_strand"]} == {"10B-1"}
    assert not any("mass" in s or "breaking_load" in s for s in data["chain_strand"])
    sprockets = {n["name"]: n for n in data["node"] if "teeth" in n}
    assert set(sprockets) == {"drive", "sprocket1", "sprocket2", "sprocket3", "idler1", "idler2"}
    assert all(n["chain"] == "10B-1" for n in sprockets.values())
    net = rt.build(PARAMS)
    drive = next(s for s in net.strands if s.name == "drive-sprocket1")
    assert drive.r_i == pytest.approx(R_SPROCKET, rel=1e-15)


def test_another_chain_changes_pitch_mass_and_breaking_load():
    # --set chain=12B-1: p = 19.05 mm, 1.18 kg/m, 28.9 kN from the catalog; a value given wins
    values = SCENES["roller-table"].values(chain="12B-1")
    assert (values["chain_pitch"], values["chain_mass"], values["chain_breaking_load"]) == pytest.approx(
        (0.01905, 1.18, 28900.0), rel=1e-14)
    net = rt.build(values)
    assert next(s for s in net.strands if s.name == "drive-sprocket1").r_i == pytest.approx(
        0.01905 / math.sin(math.pi / 19) / 2, rel=1e-14)
    given = SCENES["roller-table"].values(chain="12B-1", chain_breaking_load=30000.0)
    assert given["chain_breaking_load"] == pytest.approx(30000.0, rel=1e-15)
    data = rt.drive_data(dict(PARAMS, chain_pitch=0.016, chain_mass=1.0))   # not the catalog's: written out
    assert data["chain_strand"][0]["mass"] == pytest.approx(1.0, rel=1e-15)
    assert data["node"][2]["pitch_diameter"] == pytest.approx(0.016 / math.sin(math.pi / 19), rel=1e-15)


def test_a_chain_without_mass_or_unknown_is_one_error():
    with pytest.raises(InputError, match="06B-1 has no mass in chains.toml; give it") as exc:
        SCENES["roller-table"].values(chain="06B-1")
    assert (exc.value.param, exc.value.scope) == ("chain_mass", "scene")
    assert SCENES["roller-table"].values(chain="06B-1", chain_mass=0.41)["chain_pitch"] == pytest.approx(
        0.009525, rel=1e-14)
    from beltcalc.errors import UnknownNameError

    with pytest.raises(UnknownNameError) as exc:
        SCENES["roller-table"].values(chain="10X-1")
    assert (exc.value.param, exc.value.scope) == ("chain", "scene")
