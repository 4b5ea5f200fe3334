"""Elements with modes of their own (issue 31): friction that sticks and a PI speed loop with
a torque limit, run by the exact core, against closed forms and against scipy's Radau with
events at rtol 1e-12 (the same equations restarted at every switch: an independent
integrator, with its own event location and its own mode decisions' timing)."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.network import Coupling, Friction, Inertia, Load, Network, Prescribed, SpeedLoop

RADAU = SolverConfig("radau", 1e-12, 1e-15)


def _log(result):
    return [(float(t), j, s) for t, j, s in result.extra["switched"]["log"]]


# --- clutch engagement: the closed form ------------------------------------------------------------
@pytest.mark.parametrize("J1, J2, T, dw", [(0.5, 1.5, 20.0, 100.0), (2e-3, 0.4, 3.0, 157.0)])
def test_clutch_engagement_sticks_at_the_closed_form_time(J1, J2, T, dw):
    """Two inertias, relative speed dw, a constant slipping torque T: the relative speed falls
    linearly, ``dw' = -T (1/J1 + 1/J2)``, so it sticks at ``t = J_eff dw / T`` with the common
    speed of the momentum, and the slip work equals the kinetic energy lost."""
    net = Network([Inertia("a", J1), Inertia("b", J2)], [Friction("cl", "a", "b", ((0.0, T),))])
    x0 = np.array([0.0, 0.0, dw, 0.0])
    r = simulate(net, 3.0 * J1 * J2 / (J1 + J2) * dw / T, 3001, SolverConfig(), x0=x0)
    J_eff = J1 * J2 / (J1 + J2)
    t_stick = J_eff * dw / T
    assert r.extra["switched"]["start"] == (Friction.FORWARD,)
    (t, _, state), = _log(r)
    assert state == Friction.STUCK
    assert t == pytest.approx(t_stick, rel=1e-12)
    common = J1 * dw / (J1 + J2)
    assert_allclose(r.signals["omega_a"][-1], common, rtol=1e-12)
    assert_allclose(r.signals["omega_b"][-1], common, rtol=1e-12)
    # the relative angle slipped is the area under the linear relative speed: the heat T dphi,
    # which is the kinetic energy lost
    slipped = (r.signals["phi_a"] - r.signals["phi_b"])[-1]
    assert T * slipped == pytest.approx(0.5 * J_eff * dw ** 2, rel=1e-12)
    assert r.extra["switched"]["heat"]["cl"] == pytest.approx(0.5 * J_eff * dw ** 2, rel=1e-12)
    assert r.extra["switched"]["time"]["cl"]["forward"] == pytest.approx(t_stick, rel=1e-12)
    # the torque: T while slipping, none once stuck (nothing loads the pair)
    assert_allclose(r.signals["T_cl"][r.t < t_stick], T, rtol=1e-15)
    assert_allclose(r.signals["T_cl"][r.t > t_stick], 0.0, atol=1e-12 * T)
    assert r.error_estimate <= 1e-9 * dw


# --- the stick-slip oscillator: the analytic limit cycle -----------------------------------------------
def _stick_slip(method=SolverConfig(), watch=None):
    m, k, v0, Fk, Fs = 2.0, 800.0, 0.05, 6.0, 10.0
    net = Network([Inertia("mass", m, translation=True), Inertia("belt", 1.0, translation=True)],
                  [Coupling("spring", "mass", None, k, 0.0), Prescribed("belt", speed=v0),
                   Friction("fr", "mass", "belt", ((0.0, Fk),), static=Fs / Fk)])
    x0 = net.initial_state()
    x0[net.n + net.index["mass"]] = v0
    return simulate(net, 3.0, 6001, method, x0=x0, watch=watch), (m, k, v0, Fk, Fs)


def test_stick_slip_oscillator_has_the_analytic_period_and_amplitude():
    """A mass on a belt at v0, held by a spring to the frame: stuck until the spring's force
    reaches the static limit Fs (x1 = Fs / k), then it slides at the kinetic force Fk about
    x_k = Fk / k with omega = sqrt(k / m) until its speed is the belt's again, after
    ``(pi + 2 phi0) / omega`` (tan phi0 = v0 / (omega (x1 - x_k))) at x2 = 2 x_k - x1, where it
    sticks (|k x2| <= Fs) and is carried back to x1 in ``2 (Fs - Fk) / (k v0)``. Peak
    ``x_k + sqrt((x1 - x_k)^2 + (v0 / omega)^2)``."""
    r, (m, k, v0, Fk, Fs) = _stick_slip(watch=(["x_mass"], [0.0]))
    w = math.sqrt(k / m)
    x1, xk = Fs / k, Fk / k
    phi0 = math.atan2(v0 / w, x1 - xk)
    slide, stick = (math.pi + 2 * phi0) / w, 2 * (Fs - Fk) / (k * v0)
    log = _log(r)
    assert log[0] == (pytest.approx(x1 / v0, rel=1e-13), 0, Friction.BACKWARD)
    states = [s for _, _, s in log]
    assert states == [Friction.BACKWARD, Friction.STUCK] * (len(log) // 2) + [Friction.BACKWARD] * (len(log) % 2)
    times = np.array([t for t, _, _ in log])
    assert_allclose(times[1::2] - times[0::2][:times[1::2].size], slide, rtol=1e-12)
    assert_allclose(times[2::2] - times[1::2][:times[2::2].size], stick, rtol=1e-12)
    # the peak of the slides, read off the exact solution where it peaks (v = 0), not the samples
    peak = xk + math.hypot(x1 - xk, v0 / w)
    assert r.summary("x_mass", 0.0).max == pytest.approx(peak, rel=1e-12)
    assert r.summary("x_mass", 0.0).min == pytest.approx(0.0, abs=1e-15)
    assert r.signals["x_mass"].max() == pytest.approx(peak, rel=2e-5)      # the samples: within (w dt)^2 / 8
    # and Radau with events on the same equations, to its tolerance
    ref, _ = _stick_slip(RADAU)
    assert_allclose([t for t, _, _ in _log(ref)], times, rtol=0, atol=1e-10)
    assert_allclose(r.signals["x_mass"], ref.signals["x_mass"], rtol=0, atol=1e-11 * x1 + r.error_estimate)


# --- a speed loop at its torque limit: the saturated ramp ------------------------------------------------
def _pi_free(J, kp, ki, TL, t0, e0, I0, t):
    """The error e = w_ref - w of ``J e' = -(kp e + ki I - TL)``, ``I' = e`` from (t0, e0, I0)."""
    disc = cmath.sqrt(kp * kp - 4 * J * ki)
    s1, s2 = (-kp + disc) / (2 * J), (-kp - disc) / (2 * J)
    Ip = TL / ki
    C1 = (e0 - s2 * (I0 - Ip)) / (s1 - s2)
    C2 = (I0 - Ip) - C1
    tau = t - t0
    return (C1 * s1 * np.exp(s1 * tau) + C2 * s2 * np.exp(s2 * tau)).real


@pytest.mark.parametrize("ki, held", [(2.0, False), (20.0, True)])
def test_saturated_speed_loop_ramps_then_follows_the_pi_closed_form(ki, held):
    """A step of speed demand w_ref on J against a constant load TL, PI gains kp, ki, torque
    limit L: the drive gives L (integrator clamped) and the speed ramps at (L - TL) / J until
    the command kp e falls to L at ``t1 = (w_ref - L / kp) J / (L - TL)``. Where the free
    integrator would push the command back over the limit (ki e > kp (L - TL) / J there) it is
    held at L, the integrator rising just enough, until ``e2 = kp (L - TL) / (J ki)``; then
    the loop is linear, ``J I'' + kp I' + ki I = TL``: closed forms for every sample."""
    J, kp, L, TL, wref = 0.02, 0.5, 3.0, 1.0, 100.0
    net = Network([Inertia("m", J)], [SpeedLoop("m", kp, ((0.0, wref),), ki=ki, limit=L), Load("m", TL)])
    r = simulate(net, 1.0, 4001, SolverConfig())
    ramp = (L - TL) / J
    t1 = (wref - L / kp) * J / (L - TL)
    log = _log(r)
    assert r.extra["switched"]["start"] == (SpeedLoop.HIGH,)
    if held:
        e2 = kp * ramp / ki
        t2 = (wref - e2) * J / (L - TL)
        assert [s for _, _, s in log] == [SpeedLoop.HELD_HIGH, SpeedLoop.FREE]
        assert_allclose([t for t, _, _ in log], [t1, t2], rtol=1e-12)
        free_from, e0, I0 = t2, e2, (L - kp * e2) / ki
    else:
        assert [s for _, _, s in log] == [SpeedLoop.FREE]
        assert log[0][0] == pytest.approx(t1, rel=1e-12)
        free_from, e0, I0 = t1, L / kp, 0.0
    t = r.t
    e = np.where(t < free_from, wref - ramp * t, _pi_free(J, kp, ki, TL, free_from, e0, I0, t))
    assert_allclose(r.signals["omega_m"], wref - e, rtol=0, atol=1e-12 * wref + r.error_estimate)
    assert_allclose(r.signals["T_drive_m"][t < t1], L, rtol=1e-15)
    assert np.max(r.signals["T_drive_m"]) == pytest.approx(L, rel=1e-12)
    ref = simulate(net, 1.0, 4001, RADAU)
    assert [s for _, _, s in _log(ref)] == [s for _, _, s in log]
    assert_allclose(ref.signals["omega_m"], r.signals["omega_m"], rtol=0, atol=1e-9 * wref)


# --- three clutches engaging in sequence: against Radau with events ---------------------------------------
def _train(config, ramp=0.05, stagger=0.15):
    nodes = [Inertia(f"s{k}", J) for k, J in enumerate((0.05, 0.02, 0.08, 0.3))]
    clutches = [Friction(f"c{k}", f"s{k}", f"s{k + 1}",
                         ((0.1 + stagger * k, 0.0), (0.1 + stagger * k + ramp, 6.0 - k)), static=1.2)
                for k in range(3)]
    drive = [Load("s0", -2.0, amplitude=3.0, omega=40.0), Load("s3", 0.5, amplitude=0.8, omega=25.0),
             Coupling("bearing", "s2", None, 0.0, 0.01)]
    net = Network(nodes, clutches + drive)
    x0 = net.initial_state()
    x0[net.n] = 80.0
    return net, simulate(net, 1.5, 3001, config, x0=x0)


@pytest.mark.parametrize("stagger", [0.15, 0.0])
def test_three_clutches_in_sequence_match_radau_with_events(stagger):
    """Four inertias, three clutches whose normal force ramps on in sequence (stagger 0: all
    at once, several elements switching together), a sine torque on each end: every switch
    and every speed against Radau with events at rtol 1e-12, to the run's estimate."""
    net, r = _train(SolverConfig(), stagger=stagger)
    _, ref = _train(RADAU, stagger=stagger)
    log, ref_log = _log(r), _log(ref)
    assert len(log) >= 4
    assert [(j, s) for _, j, s in log] == [(j, s) for _, j, s in ref_log]
    assert_allclose([t for t, _, _ in log], [t for t, _, _ in ref_log], rtol=0, atol=1e-9)
    scale = 80.0
    for k in range(4):
        assert_allclose(r.signals[f"omega_s{k}"], ref.signals[f"omega_s{k}"], rtol=0,
                        atol=1e-9 * scale + r.error_estimate)
    # the estimate covers the difference from Radau (whose own error is below 1e-9 of the scale)
    worst = max(np.max(np.abs(r.signals[f"omega_s{k}"] - ref.signals[f"omega_s{k}"])) for k in range(4))
    assert worst <= r.error_estimate + 1e-9 * scale
    # each clutch's torque within its limits at every sample
    for k in range(3):
        cap = np.interp(r.t, [0.1 + stagger * k, 0.1 + stagger * k + 0.05], [0.0, 6.0 - k])
        assert np.all(np.abs(r.signals[f"T_c{k}"]) <= 1.2 * cap * (1 + 1e-12) + 1e-12)


def test_a_freewheel_carries_torque_one_way_only():
    """A one-way clutch from a driven shaft to a flywheel: it drives the flywheel while the
    shaft is faster (stuck, carrying torque), and lets the flywheel overrun when the drive
    stops (free, no torque): the flywheel then keeps its speed exactly."""
    net = Network([Inertia("shaft", 0.01), Inertia("fly", 0.5)],
                  [Load("shaft", 0.0, table=((0.0, -5.0), (1.0, -5.0), (1.0, 2.0))),
                   Friction("fw", "shaft", "fly", ((0.0, 50.0),), one_way=True)])
    r = simulate(net, 2.0, 2001, SolverConfig())
    states = [s for _, _, s in _log(r)]
    assert Friction.FREE in states
    after = r.t > 1.01
    w_end = 5.0 * 1.0 / 0.51                       # both driven together to t = 1 s
    assert_allclose(r.signals["omega_fly"][after], w_end, rtol=1e-12)
    assert_allclose(r.signals["T_fw"][after], 0.0, atol=1e-12)
    assert np.all(r.signals["T_fw"] >= -1e-12)


# --- through the command a user types ----------------------------------------------------------------
def _cli(*args):
    import json

    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    res = CliRunner().invoke(cli, ["simulate", "drive", *args])
    return res, (json.loads(res.stdout) if res.exit_code == 0 and "--json" in args else None)


def test_a_clutch_in_a_drive_file_engages_a_flywheel_to_the_closed_form():
    """``[[clutch]]`` mu F_n r z = 0.3 x 500 N x 0.08 m x 2 = 24 N m, its force ramped on over
    0.05 s from 0.1 s, onto a 0.2 kg m^2 flywheel from a line at 100 rad/s: the flywheel
    gains 3 rad/s over the ramp, then 120 rad/s^2 until it sticks at 0.1 + 0.05 + 97 / 120 s;
    the line's drive torque is the clutch's."""
    from pathlib import Path

    path = str(Path(__file__).parent / "data" / "clutch_flywheel.toml")
    res, out = _cli(path, "--json")
    assert res.exit_code == 0, res.output
    assert out["couplings"]["cl"]["torque_max"]["value"] == pytest.approx(24.0, rel=1e-12)
    assert out["nodes"]["fly"]["speed_max"]["value"] == pytest.approx(100.0, rel=1e-12)
    assert out["error_relative"]["value"] <= 1e-9
    # the slip heat, read off the exact solution through the ramp: the line's work (100 rad/s x
    # the flywheel's final momentum 20 N m s) less the flywheel's energy (1000 J)
    assert out["switched"]["cl"]["heat"]["value"] == pytest.approx(1000.0, rel=1e-12)
    assert out["switched"]["cl"]["time_free"]["value"] == pytest.approx(0.1, rel=1e-12)
    assert out["switched"]["cl"]["time_slipping"]["value"] == pytest.approx(0.05 + 97.0 / 120.0, rel=1e-12)
    # the mean speed of the flywheel over the run, from the closed form of its motion
    t1, t2, t3 = 0.1, 0.15, 0.15 + 97.0 / 120.0
    ramp = 24.0 / 0.05 / 0.2 * (t2 - t1) ** 3 / 6          # the ramp's own area: a t^2 / 2 rise
    mean = (ramp + 3.0 * (t3 - t2) + 0.5 * 120.0 * (t3 - t2) ** 2 + 100.0 * (1.0 - t3)) / 1.0
    assert out["nodes"]["fly"]["speed_mean"]["value"] == pytest.approx(mean, rel=1e-9)


def test_a_clutch_without_its_torque_is_refused_in_one_line(tmp_path):
    from pathlib import Path

    text = (Path(__file__).parent / "data" / "clutch_flywheel.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("mu = 0.3\n", ""))
    res, _ = _cli(str(bad))
    assert res.exit_code in (1, 2)
    assert "torque" in res.output and len(res.output.strip().splitlines()) == 1


def _net_modes(log, count):
    """Each element's state after every instant of the log (toggles of zero duration, where
    two conditions meet at one time and the second decision undoes the first, collapsed)."""
    out, times = [], sorted({round(float(t), 9) for t, _, _ in log})
    for when in times:
        state = {j: s for t, j, s in log if round(float(t), 9) <= when}
        out.append((when, tuple(state.get(j) for j in range(count))))
    return [(w, s) for k, (w, s) in enumerate(out) if k == 0 or s != out[k - 1][1]]


@pytest.mark.parametrize("values", [{}, {"limiter.torque": 70.0}, {"belt.torque": 2.0}],
                         ids=["as built", "static limit = slipping", "a drum that rocks to rest"])
def test_the_built_in_limiter_example_matches_radau_with_events(values):
    """The built-in drive ``conveyor_limiter`` (a servo at its torque limit, a torque limiter
    through a jam, a brake, belt friction that sticks): every mode change and every speed
    against Radau with events at rtol 1e-6, to Radau's tolerance (rtol 1e-8 does not pass
    3.5 s in minutes: the jaw's torque is a difference of 458 rad angles, whose rounding
    Radau's error control chases; the exact run takes under a second)."""
    from beltcalc.sim.drivefile import DriveFile, drive_path

    net = DriveFile(drive_path("conveyor_limiter")).build(values).network
    r = simulate(net, 5.0, 5001, SolverConfig())
    ref = simulate(net, 5.0, 5001, SolverConfig("radau", 1e-6, 1e-8, estimate_error=False))
    count = len(net.switched)
    mine, theirs = _net_modes(_log(r), count), _net_modes(_log(ref), count)
    assert [s for _, s in mine] == [s for _, s in theirs]
    assert_allclose([t for t, _ in mine], [t for t, _ in theirs], rtol=0, atol=1e-5)
    scale = max(np.max(np.abs(r.signals[f"omega_{k}"])) for k in ("rotor", "hub", "drum"))
    for k in ("rotor", "gear_in", "hub", "drum"):
        assert_allclose(r.signals[f"omega_{k}"], ref.signals[f"omega_{k}"], rtol=0, atol=1e-5 * scale)
    assert r.error_relative <= 1e-8
    time = r.extra["switched"]["time"]
    assert time["limiter"]["forward"] + time["limiter"]["backward"] >= 0.5       # it slips through the jam
    assert time["drive_rotor"]["high"] > 0                                       # the servo hits its limit
    assert_allclose(r.signals["omega_drum"][r.t > 3.6], 0.0, atol=1e-9)         # braked to rest


# --- the frequency domain in one mode ------------------------------------------------------------------
def test_a_stuck_clutch_is_a_rigid_gear_for_the_modes_and_a_slipping_one_only_its_damper():
    """Three inertias on two springs with a clutch (ratio 2) in the middle: stuck, the drive's
    modes are those of the same drive with a rigid gear there (the clutch's degree of freedom
    merged); slipping, those of the two halves apart (its torque is an input), each against
    the closed form of a two-mass oscillator sqrt(k (J1 + J2) / (J1 J2))."""
    from beltcalc.sim.drivefile import undamped_frequencies
    from beltcalc.sim.network import Gear

    nodes = [Inertia("a", 0.02), Inertia("b", 0.05), Inertia("c", 0.01), Inertia("d", 0.3)]
    springs = [Coupling("k1", "a", "b", 800.0, 0.0), Coupling("k2", "c", "d", 1500.0, 0.0)]
    net = Network(nodes, springs + [Friction("cl", "b", "c", ((0.0, 40.0),), U=2.0)])
    stuck = net.frozen(net.full_pattern(()))
    geared = Network(nodes, springs + [Gear("b", "c", 2.0)])
    assert_allclose(undamped_frequencies(stuck), undamped_frequencies(geared), rtol=1e-12)
    slipping = net.frozen((Friction.FORWARD,))
    two = sorted([math.sqrt(800.0 * 0.07 / (0.02 * 0.05)), math.sqrt(1500.0 * 0.31 / (0.01 * 0.3))])
    assert_allclose(sorted(undamped_frequencies(slipping)), np.array(two) / (2 * math.pi), rtol=1e-12)
    assert net.describe((Friction.FORWARD,)) == "cl forward"


def test_the_modes_command_says_which_mode_and_takes_a_named_one():
    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    import json

    res = CliRunner().invoke(cli, ["modes", "conveyor_limiter", "--json"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    states, origin = out["mode"].split(" (")
    assert set(states.split(", ")) == {"drive_rotor free", "limiter stuck", "brake stuck", "belt stuck"}
    assert origin == "at the end of the run, t = 5 s)"
    res = CliRunner().invoke(cli, ["modes", "conveyor_limiter", "--mode", "limiter=forward", "--mode", "brake=free",
                                   "--mode", "belt=forward", "--mode", "drive_rotor=free", "--json"])
    out = json.loads(res.stdout)
    assert out["mode"].endswith("(named)")
    assert len([m for m in out["modes"] if m["kind"] == "oscillatory"]) == 3
    res = CliRunner().invoke(cli, ["modes", "conveyor_limiter", "--mode", "limiter=slack"])
    assert res.exit_code == 2 and "--mode" in res.output and "stuck, forward, backward" in res.output


@pytest.mark.slow
def test_hundreds_of_stick_slip_switches_match_radau_with_events_through_the_cli():
    """A spindle whose bearing friction sticks and slips both ways every period of a sine
    drive (tests/data/stick_slip_sine.toml; 159 switches in 5 s): the command's report (mode
    changes, time stuck) against Radau with events at rtol 1e-9 over the first 2 s, every
    switch time and speed to Radau's tolerance (measured at rtol 1e-10 over 5 s: switch times
    5e-14 s, speeds 1e-11 rad/s)."""
    from pathlib import Path

    from beltcalc.sim.drivefile import load_drive

    path = Path(__file__).parent / "data" / "stick_slip_sine.toml"
    res, out = _cli(str(path), "--t-end", "2s", "--window", "1s", "--json")
    assert res.exit_code == 0, res.output
    net = load_drive(str(path)).network
    mine = simulate(net, 2.0, 2001, SolverConfig())
    ref = simulate(net, 2.0, 2001, SolverConfig("radau", 1e-9, 1e-12, estimate_error=False))
    log, ref_log = _log(mine), _log(ref)
    assert len(log) >= 50
    assert [s for _, _, s in log] == [s for _, _, s in ref_log]
    assert_allclose([t for t, _, _ in log], [t for t, _, _ in ref_log], rtol=0, atol=1e-8)
    assert_allclose(mine.signals["omega_spindle"], ref.signals["omega_spindle"], rtol=0, atol=1e-7)
    report = out["switched"]["bearing"]
    assert report["switches"]["value"] == len(log)
    assert report["time_stuck"]["value"] == pytest.approx(ref.extra["switched"]["time"]["bearing"]["stuck"],
                                                          rel=0, abs=1e-7)
    assert out["error_relative"]["value"] <= 1e-9


def test_friction_on_a_prescribed_node_alone_is_refused_in_one_line(tmp_path):
    from pathlib import Path

    text = (Path(__file__).parent / "data" / "clutch_flywheel.toml").read_text()
    bad = tmp_path / "brake_on_line.toml"
    bad.write_text(text.replace("[[clutch]]", '[[brake]]\nname = "hold"\nnode = "input"\ntorque = "5 N*m"\n\n[[clutch]]'))
    res, _ = _cli(str(bad))
    assert res.exit_code == 1
    assert "hold" in res.output and "prescribed" in res.output and len(res.output.strip().splitlines()) == 1
