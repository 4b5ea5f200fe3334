"""The exact periodic steady state of a drive file and the settling check of its window
(beltcalc.sim.scenes.drive, base.exact_steady_state / settling_check; issue 26, item 4).

A user's two-motor drive reported window means 21 % high because the window still held the
start-up transient, without a word. Here a two-motor drive whose every figure has a closed
form: the steady state (means and the 2 Hz ripple) against it to 1e-9, the slowest pole's
time constant against the roots of its characteristic polynomial, the window that starts
too early warned of (and its means off the steady state), the window that starts late
agreeing with the steady state to the run's error estimate plus what is left of the
transient; and drives that have no exact steady state (a strand that goes slack, a load
locked to a shaft angle) say why in a note and exit 0."""

from __future__ import annotations

import json
import math
import re

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import ok, warnings

# --- the two-motor drive: rigid (two rigid gears), so that every figure has a closed form -----
# Two induction motors (eq. 2 of Mamatova et al. 2016, [M16 eq. 2]) on m1 and m2, each geared
# 5:1 to the drum; a damper to the frame on the drum (the bearing); the drum's load 60 N m,
# 100 N m from 0.7 s (a table step), a 10 N m ripple at 2 Hz from 1 s (`start`). The last input
# change is at 1 s.
J1, J2, J3 = 0.1, 0.1, 36.0           # kg m^2
U = 5.0                               # motor speed / drum speed
D_BEARING = 0.5                       # N m s/rad on the drum
RATED = (20.0, 16.0)                  # N m
BREAKDOWN_FACTOR, SLIP = 2.5, 0.2
SUPPLY, POLE_PAIRS = 50.0, 2
T_LOAD, T_RIPPLE, F_RIPPLE = 100.0, 10.0, 2.0       # N m, N m, Hz
LAST_CHANGE = 1.0                     # s: the ripple starts


def two_motor_file(path, t_end: str, samples: int, window: str):
    path.write_text(f"""
[drive]
title = "Two motors on one drum"
t_end = "{t_end}"
samples = {samples}
window = "{window}"

[[node]]
name = "m1"
inertia = "{J1} kg*m^2"

[[node]]
name = "m2"
inertia = "{J2} kg*m^2"

[[node]]
name = "drum"
inertia = "{J3} kg*m^2"

[[gear]]
name = "g1"
between = ["m1", "drum"]
ratio = {U}

[[gear]]
name = "g2"
between = ["m2", "drum"]
ratio = {U}

[[coupling]]
name = "bearing"
between = ["drum"]
stiffness = "0 N*m/rad"
damping = "{D_BEARING} N*m*s/rad"

[[motor]]
name = "big"
kind = "induction"
node = "m1"
rated_torque = "{RATED[0]} N*m"
breakdown_factor = {BREAKDOWN_FACTOR}
breakdown_slip = {SLIP}
supply = "{SUPPLY} Hz"
pole_pairs = {POLE_PAIRS}

[[motor]]
name = "small"
kind = "induction"
node = "m2"
rated_torque = "{RATED[1]} N*m"
breakdown_factor = {BREAKDOWN_FACTOR}
breakdown_slip = {SLIP}
supply = "{SUPPLY} Hz"
pole_pairs = {POLE_PAIRS}

[[load]]
name = "process"
node = "drum"
torque = "60 N*m"
table = [["0.7 s", "0 N*m"], ["0.7 s", "{T_LOAD - 60} N*m"]]
amplitude = "{T_RIPPLE} N*m"
frequency = "{2 * math.pi * F_RIPPLE!r} rad/s"
start = "{LAST_CHANGE} s"
""")
    return path


def closed_form() -> dict:
    r"""The two-motor drive by hand, reflected to the motor shaft (speed omega; drum Omega =
    omega / U). Each motor's static characteristic (eq. 2 at rest, linear):
    M_k = a_k (w0 - omega), a_k = 2 M_ck / (w0 S_c), M_ck = breakdown factor x rated torque,
    w0 = 2 pi f / pole pairs. Inertia J = J1 + J2 + J3 / U^2; the bearing d Omega on the drum is
    d / U^2 omega at the motors, the load T / U.

    Mean: a (w0 - omega) = T / U + d / U^2 omega (a = a_1 + a_2), so
    omega = (a w0 - T / U) / (a + d / U^2); M_k = a_k (w0 - omega).

    Ripple at w = 2 pi f_r: each motor lags, M_k' = p (a_k (w0 - omega) - M_k), p = 2 pi f S_c,
    so M_k = -a_k p / (p + j w) omega; J j w omega = sum M_k - T_r / U - d / U^2 omega gives
    |omega| = (T_r / U) / |J j w + d / U^2 + a p / (p + j w)|.

    Poles: the angle (rigid, 0); M_1 / a_1 - M_2 / a_2 decays at -p; and
    (J s + d / U^2)(s + p) + a p = 0, whose root nearer 0 is the slowest."""
    w0 = 2 * math.pi * SUPPLY / POLE_PAIRS
    p = 2 * math.pi * SUPPLY * SLIP
    a_k = [2 * BREAKDOWN_FACTOR * r / (w0 * SLIP) for r in RATED]
    a = sum(a_k)
    J = J1 + J2 + J3 / U ** 2
    d = D_BEARING / U ** 2
    omega = (a * w0 - T_LOAD / U) / (a + d)
    w = 2 * math.pi * F_RIPPLE
    lag = p / (p + 1j * w)
    ripple = (T_RIPPLE / U) / abs(J * 1j * w + d + a * lag)
    b, c = J * p + d, p * (d + a)
    s_slow = (-b + math.sqrt(b * b - 4 * J * c)) / (2 * J)     # both roots real here
    return {
        "omega_m1": omega, "omega_drum": omega / U,
        "M_big": a_k[0] * (w0 - omega), "M_small": a_k[1] * (w0 - omega),
        "T_bearing": D_BEARING * omega / U,
        "amp_omega_m1": ripple, "amp_omega_drum": ripple / U,
        "amp_M_big": a_k[0] * abs(lag) * ripple, "amp_M_small": a_k[1] * abs(lag) * ripple,
        "amp_T_bearing": D_BEARING * ripple / U,
        "tau": -1.0 / s_slow, "inrush": max(a_k) * w0,
    }


def run(*args):
    return CliRunner().invoke(cli, ["simulate", "drive", *args])


def val(obj, *path):
    for key in path:
        obj = obj[key]
    return obj["value"]


STEADY = [  # (JSON path under steady_state, closed-form key) of means and amplitudes
    (("nodes", "m1", "speed_mean"), "omega_m1"), (("nodes", "m2", "speed_mean"), "omega_m1"),
    (("nodes", "drum", "speed_mean"), "omega_drum"), (("nodes", "m1", "speed_amplitude"), "amp_omega_m1"),
    (("nodes", "drum", "speed_amplitude"), "amp_omega_drum"),
    (("couplings", "bearing", "torque_mean"), "T_bearing"),
    (("couplings", "bearing", "torque_amplitude"), "amp_T_bearing"),
    (("motors", "M_big", "torque_mean"), "M_big"), (("motors", "M_small", "torque_mean"), "M_small"),
    (("motors", "M_big", "torque_amplitude"), "amp_M_big"), (("motors", "M_small", "torque_amplitude"), "amp_M_small"),
    (("motors", "M_big", "speed_mean"), "omega_m1"),
]


def test_closed_form_balances():
    # the reference itself: the motors carry the load and the bearing (T / U + d Omega / U)
    ref = closed_form()
    assert ref["M_big"] + ref["M_small"] == pytest.approx(T_LOAD / U + D_BEARING * ref["omega_drum"] / U, rel=1e-14)
    assert ref["M_big"] / ref["M_small"] == pytest.approx(RATED[0] / RATED[1], rel=1e-14)
    assert 0.26 < ref["tau"] < 0.28          # a slow mechanical pole, as the user's 267 ms


def test_a_window_that_starts_too_early_is_warned_of_and_the_steady_state_is_exact(tmp_path):
    ref = closed_form()
    path = two_motor_file(tmp_path / "two_motors.toml", "2 s", 2001, "1.5 s")
    res = ok(run(str(path), "--json"))
    obj = json.loads(res.stdout)
    # the steady-state block: the closed form to 1e-9 (the solves are exact to rounding; the
    # motor's state matrix is conditioned ~1e4)
    for where, key in STEADY:
        assert val(obj["steady_state"], *where) == pytest.approx(ref[key], rel=1e-9), where
    # the warning, once on stderr and in the JSON, names the pole by its time constant and the
    # window that settles: 1 s + ln(1000) tau
    said = [w for w in warnings(res) if w.startswith("transient at the window start FAILS")]
    assert len(said) == 1 and said == [w for w in obj["warnings"] if w.startswith("transient at the window")]
    tau = float(re.search(r"time constant ([0-9.]+) s", said[0])[1])
    assert tau == pytest.approx(ref["tau"], rel=5e-4)                  # printed to 4 digits
    start = float(re.search(r"--window >= ([0-9.]+) s", said[0])[1])
    assert start == pytest.approx(LAST_CHANGE + math.log(1000) * ref["tau"], rel=5e-4)
    assert "the last input change at 1 s" in said[0]
    check = next(c for c in obj["checks"] if c["key"] == "window_settled")
    # what is left of the transient at 1.5 s: e^(-0.5 s / tau), from the exact pole
    assert check["value"]["value"] == pytest.approx(math.exp(-(1.5 - LAST_CHANGE) / ref["tau"]), rel=1e-9)
    assert check["verdict"] == "FAIL"
    # that is why: the window [1.5, 2] s (one whole ripple period) still climbs from the start
    # from rest. Its step response has no zero and two real poles (monotone), so the window's
    # speed is below the steady speed and the motors' torques above; the speed's deficit at
    # 1.5 s is at least e^(-1.5 s / tau) of the steady speed's 152 rad/s (0.56 rad/s), the
    # window means are off by more than 1e-3 -- far above the run's error estimate.
    assert obj["error_relative"]["value"] < 1e-6
    assert val(obj, "nodes", "m1", "speed_mean") < ref["omega_m1"] * (1 - 1e-3)
    for motor in ("M_big", "M_small"):
        assert val(obj, "motors", motor, "torque_mean") > ref[motor] * (1 + 1e-3)


def test_a_window_that_starts_late_agrees_with_the_steady_state(tmp_path):
    ref = closed_form()
    path = two_motor_file(tmp_path / "two_motors.toml", "10 s", 10001, "7 s")
    res = ok(run(str(path), "--json"))
    obj = json.loads(res.stdout)
    assert warnings(res) == [] and obj["warnings"] == []
    check = next(c for c in obj["checks"] if c["key"] == "window_settled")
    assert check["verdict"] == "pass"
    assert check["value"]["value"] == pytest.approx(math.exp(-(7.0 - LAST_CHANGE) / ref["tau"]), rel=1e-9)
    for where, key in STEADY:
        assert val(obj["steady_state"], *where) == pytest.approx(ref[key], rel=1e-9), where
    # the window [7, 10] s holds 6 whole ripple periods, so its means are the steady means up to
    # the run's error (error_relative, of the signals' scale) and what is left of the transient:
    # at most the largest transient (the motors' inrush a_k w0 on a direct-on-line start, 65x
    # their steady torque) times e^(-6 s / tau) (2e-10) -- 1.3e-8 of a steady value; the
    # amplitudes (half the peak-to-peak of the exact solution) alike
    leftover = ref["inrush"] / ref["M_small"] * math.exp(-(7.0 - LAST_CHANGE) / ref["tau"])
    tol = obj["error_relative"]["value"] + leftover
    assert tol < 1e-6
    for where, key in STEADY:
        section, item, row = where
        window = val(obj, section, item, row)
        scale = ref[key.replace("amp_", "")] if key.startswith("amp_") else ref[key]
        assert window == pytest.approx(ref[key], abs=tol * abs(scale)), where


def test_the_python_api_gives_the_same_steady_state(tmp_path):
    from beltcalc.sim.drivefile import load_drive
    from beltcalc.sim.scenes.drive import steady_state

    ref = closed_form()
    drive = load_drive(two_motor_file(tmp_path / "two_motors.toml", "2 s", 2001, "1.5 s"))
    ss, why = steady_state(drive)
    assert why is None and ss.exact and ss.frequencies == pytest.approx([2 * math.pi * F_RIPPLE], rel=1e-15)
    assert ss.mean["M_big"] == pytest.approx(ref["M_big"], rel=1e-9)
    assert ss.mean["omega_drum"] == pytest.approx(ref["omega_drum"], rel=1e-9)
    assert abs(ss.components["omega_m1"][2 * math.pi * F_RIPPLE]) == pytest.approx(ref["amp_omega_m1"], rel=1e-9)
    # a window that starts before the last input change: the steady state of the later inputs
    # is not what it shows, so none is claimed
    early = load_drive(drive.path, window=0.9)
    ss, why = steady_state(early)
    assert ss is None and why.startswith("an input changes at 1 s, after the window starts (0.9 s)")


def test_a_strand_that_goes_slack_has_no_steady_state(tmp_path):
    # a chain loop with 100 N pretension each strand pulls 50 N m / r = 1037 N on a 19-tooth
    # 10B-1 sprocket (r = 15.875 mm / (2 sin(pi / 19)) = 48.2 mm): taut, the return strand
    # would carry 100 - 519 N < 0, so the drive is not linear in its steady state
    path = tmp_path / "chain.toml"
    path.write_text("""
[drive]
t_end = "1 s"
samples = 1001
window = "0.8 s"

[[node]]
name = "motor"
inertia = "0.01 kg*m^2"
teeth = 19
chain = "10B-1"

[[node]]
name = "drum"
inertia = "0.2 kg*m^2"
teeth = 19
chain = "10B-1"

[[chain_strand]]
name = "tight"
from = "motor"
to = "drum"
chain = "10B-1"
length = "600 mm"
pretension = "100 N"
stiffness = "1.5e6 N"
damping_time = "2e-4 s"

[[chain_strand]]
name = "return"
from = "drum"
to = "motor"
chain = "10B-1"
length = "600 mm"
pretension = "100 N"
stiffness = "1.5e6 N"
damping_time = "2e-4 s"

[[motor]]
name = "motor"
kind = "induction"
node = "motor"
rated_torque = "30 N*m"
breakdown_factor = 2.5
breakdown_slip = 0.2
supply = "50 Hz"
pole_pairs = 2

[[load]]
node = "drum"
torque = "50 N*m"
""")
    res = ok(run(str(path), "--json"))
    obj = json.loads(res.stdout)
    assert "steady_state" not in obj
    why = [n for n in obj["notes"] if n.startswith("no exact steady state")]
    assert len(why) == 1 and "strand return would go slack in the steady state" in why[0]
    # the settling check then takes the poles with the strands as at the end of the run
    check = next(c for c in obj["checks"] if c["key"] == "window_settled")
    assert "strands slack as at the end of the run: return" in check["rule"]


def test_a_load_locked_to_the_shaft_angle_has_no_steady_state(tmp_path):
    path = tmp_path / "cam.toml"
    path.write_text("""
[drive]
t_end = "0.3 s"
samples = 301
window = "0.2 s"

[[node]]
name = "shaft"
inertia = "0.05 kg*m^2"

[[motor]]
kind = "induction"
node = "shaft"
rated_torque = "10 N*m"
breakdown_factor = 2.5
breakdown_slip = 0.2
supply = "50 Hz"
pole_pairs = 2

[[load]]
node = "shaft"
torque = "5 N*m"
amplitude = "1 N*m"
order = 2
""")
    res = ok(run(str(path), "--json"))
    obj = json.loads(res.stdout)
    assert "steady_state" not in obj
    assert "no exact steady state: the drive is nonlinear (loads locked to a shaft angle)" in obj["notes"]
    text = ok(run(str(path))).stdout
    assert "no exact steady state: the drive is nonlinear" in text and "periodic steady state" not in text


def test_the_steady_state_columns_of_a_sweep_do_not_collide_with_the_window_columns(tmp_path):
    path = two_motor_file(tmp_path / "two_motors.toml", "2 s", 201, "1.5 s")
    obj = json.loads(ok(run(str(path), "--json", "--sweep", "bearing.damping=0.5N*m*s/rad:1N*m*s/rad:2")).stdout)
    keys = [c["key"] for c in obj["columns"]]
    assert len(keys) == len(set(keys))
    assert "M_big_torque_mean_N_m" in keys and "steady_M_big_torque_mean_N_m" in keys
    k = keys.index("steady_M_big_torque_mean_N_m")
    assert obj["rows"][0][k] == pytest.approx(closed_form()["M_big"], rel=1e-9)


def test_sewing_reports_its_steady_state_through_the_shared_rows():
    # the sewing scene's block keeps its shape (main_shaft, bottom_shaft, motor_steady) and its
    # drive file reports the same steady state: mean load torques through U12 = 1.375,
    # (0.1 + 0.012) / 1.375 N m at the motor
    scene = json.loads(ok(CliRunner().invoke(cli, ["simulate", "sewing", "--json"])).stdout)
    drive = json.loads(ok(run("sewing", "--json")).stdout)
    assert list(scene["steady_state"]) == ["main_shaft", "bottom_shaft", "motor_steady"]
    assert val(scene["steady_state"], "motor_steady", "torque_mean") == pytest.approx(0.112 / 1.375, rel=1e-9)
    assert val(drive["steady_state"], "motors", "M_motor", "torque_mean") == pytest.approx(
        val(scene["steady_state"], "motor_steady", "torque_mean"), rel=1e-12)
    assert val(drive["steady_state"], "nodes", "3", "speed_amplitude") == pytest.approx(
        val(scene["steady_state"], "main_shaft", "speed_amplitude"), rel=1e-12)
    # its window starts 16 time constants of its slowest pole (30 ms) after the start
    for obj in (scene, drive):
        check = next(c for c in obj["checks"] if c["key"] == "window_settled")
        assert check["verdict"] == "pass" and check["value"]["value"] < 1e-6


def test_a_speed_loop_on_a_two_way_belt_to_a_carriage(tmp_path):
    # A speed loop (feed-forward 1 N m + 0.5 N m s/rad (20 rad/s - omega)) drives a pulley of
    # r = 63.66 mm / 2, a two-way belt span pulls a 20 kg carriage against 30 N and a guide's
    # 50 N s/m. Steady: the belt carries r (d v + F) with v = r omega, so
    # ff + g (w_ref - omega) = r (d r omega + F): omega = (ff + g w_ref - r F) / (g + d r^2);
    # the belt force F + d r omega, the drive torque r (F + d r omega).
    path = tmp_path / "loop.toml"
    path.write_text("""
[drive]
t_end = "5 s"
samples = 5001
window = "4 s"

[[node]]
name = "motor"
inertia = "0.02 kg*m^2"
pitch_diameter = "63.66 mm"

[[node]]
name = "carriage"
mass = "20 kg"

[[belt_span]]
name = "belt"
from = "motor"
to = "carriage"
belt = "BRECO-AT10"
width = "25 mm"
length = "1 m"
damping = "2000 N*s/m"
tension_only = false

[[coupling]]
name = "guide"
between = ["carriage"]
stiffness = "0 N/m"
damping = "50 N*s/m"

[[motor]]
kind = "speed_loop"
node = "motor"
gain = "0.5 N*m*s/rad"
reference = [["0 s", "0 rad/s"], ["1 s", "20 rad/s"]]
feedforward = [["0 s", "1 N*m"]]

[[load]]
node = "carriage"
torque = "30 N"
amplitude = "5 N"
frequency = "6.283185307179586 rad/s"
start = "2 s"
""")
    r, g, d, F = 0.06366 / 2, 0.5, 50.0, 30.0
    omega = (1.0 + g * 20.0 - r * F) / (g + d * r * r)
    res = ok(run(str(path), "--json"))
    obj = json.loads(res.stdout)
    steady = obj["steady_state"]
    assert val(steady, "nodes", "motor", "speed_mean") == pytest.approx(omega, rel=1e-9)
    assert val(steady, "nodes", "carriage", "speed_mean") == pytest.approx(r * omega, rel=1e-9)
    assert val(steady, "spans", "belt", "force_mean") == pytest.approx(F + d * r * omega, rel=1e-9)
    assert val(steady, "motors", "T_drive_motor", "torque_mean") == pytest.approx(r * (F + d * r * omega), rel=1e-9)
    # the window [4, 5] s (one ripple period, 27 time constants of the slowest pole after the
    # ripple starts) agrees with it to the run's error; the drive torque's extremes are the
    # largest of its 1 ms samples (it is not a watched signal), below the 1 Hz sine's true
    # extremes by at most 1 - cos(w dt / 2) = 4.9e-6 of its amplitude
    assert [c["verdict"] for c in obj["checks"] if c["key"] == "window_settled"] == ["pass"]
    tol = obj["error_relative"]["value"] + 1e-9
    sampled = 1 - math.cos(2 * math.pi * 1e-3 / 2)
    for where, rel in ((("motors", "T_drive_motor", "torque_mean"), tol),
                       (("motors", "T_drive_motor", "torque_amplitude"), tol + sampled),
                       (("nodes", "motor", "speed_mean"), tol), (("nodes", "motor", "speed_amplitude"), tol),
                       (("couplings", "guide", "torque_amplitude"), tol)):
        assert val(obj, *where) == pytest.approx(val(steady, *where), rel=rel), where
