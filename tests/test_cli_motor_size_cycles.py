"""``beltcalc motor-size`` duty cycles (issue 14): S-curves, moves by time, cycle files, vertical
axes, torque-speed zones, gearbox catalogs and the braking resistor; every error line.

The WDU numbers of tests/test_cli_motor_size.py (module docstring) are the base:
J_red = 6.0710488e-4 kg m^2 with SGM7J-06A, b_M = 6.0797188e-4 N m s/rad, T_R = 3.1215536e-3 N m,
k = D/(2 i) = 3.1830989e-3 m/rad, omega = 314.15927 rad/s, eps = 3141.5927 rad/s^2.
"""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from beltcalc.data.catalogs import builtin_dir
from beltcalc.cli.main import cli
from clichecks import ok, one_error_line

PI = math.pi
D = 0.4 / PI
K = D / 40
J_PULLEY = PI * 2700 * 0.03 / 32 * (D ** 4 - 0.02 ** 4)
M_TB = 0.114 * 1.245 * 125.5 / (2 * 124.5 ** 2)
J_LOAD = 1e-5 + 2e-5 / 400 + 2 * J_PULLEY / 400 + (50 + M_TB) * D ** 2 / 4 / 400
J_RED = J_LOAD + 0.8e-4
OMEGA = 100 * PI
EPS = 10 / K
B_M = 0.1 * 1.91 / OMEGA
T_R = 0.002 * 50 * 9.80665 * K
CYCLE = builtin_dir() / "cycles" / "pick_place_vertical.toml"


@pytest.fixture(autouse=True)
def _no_debug_from_environment(monkeypatch):
    monkeypatch.delenv("BELTCALC_DEBUG", raising=False)


def run(*args: str):
    return CliRunner().invoke(cli, ["motor-size", *args])


def js(*args: str) -> dict:
    """The JSON of a run that exits 0; its warnings are on stderr too, one 'warning:' line each."""
    res = run(*args, "--json")
    assert res.exit_code == 0, res.output + res.stderr
    out = json.loads(res.stdout)
    assert res.stderr.splitlines() == [f"warning: {w}" for w in out["warnings"]]
    return out


def test_default_json_has_empty_warnings_and_the_assumed_zone():
    out = js()
    assert out["warnings"] == []
    assert out["zone"]["assumed"] is True
    assert any("no torque-speed curve" in a for a in out["assumptions"])
    # the default move tops out at the rated speed: the flat part, margin T_max - peak = 6.69 - 2.1013978
    assert out["zone_margin"]["value"] == pytest.approx(6.69 - 2.1013978, rel=1e-6)


def test_scurve_peak_by_hand():
    # jerk 200 m/s^3 at the carriage: T_j = a/j = 10/200 = 0.05 s; the largest torque is at the end of the
    # constant acceleration (J j = 38 N m/s >> b a: the torque falls in accel_out), where the speed is
    # v - a T_j / 2 = 314.15927 - 3141.5927 * 0.025 = 235.61945 rad/s:
    # J eps + b w + T_R = 1.9072762 + 0.1432500 + 0.0031216 = 2.0536478 N m
    out = js("--jerk", "200m/s^3")
    want = J_RED * EPS + B_M * (OMEGA - EPS * 0.025) + T_R
    assert want == pytest.approx(2.0536478, rel=1e-6)
    assert out["peak_torque"]["value"] == pytest.approx(want, rel=1e-12)
    assert out["motor_jerk"]["value"] == pytest.approx(200 / K, rel=1e-12)
    assert [p["phase"] for p in out["phases"]][:4] == ["accel_in", "accelerate", "accel_out", "cruise"]
    # the same jerk at the motor gives the same answer
    assert js("--jerk", f"{200 / K!r}rad/s^3")["peak_torque"]["value"] == pytest.approx(want, rel=1e-12)
    # cycle time: 1 m at 1 m/s + v/a + T_j = 1 + 0.1 + 0.05 = 1.15 s, plus the 0.5 s dwell
    assert out["cycle_time"]["value"] == pytest.approx(1.65, rel=1e-12)


def test_move_by_time():
    # 1 m in 1.5 s, thirds: v = 1/(1.5 - 0.5) = 1 m/s, a = 1/0.5 = 2 m/s^2 -> motor 628.31853 rad/s^2
    out = js("--move-time", "1.5s")
    assert out["motor_speed"]["value"] == pytest.approx(OMEGA, rel=1e-12)
    assert out["carriage_accel"]["value"] == pytest.approx(2.0, rel=1e-12)
    assert out["cycle_time"]["value"] == pytest.approx(2.0, rel=1e-12)


def test_a_cycle_file_of_one_move_equals_the_single_move(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text('[cycle]\ntitle = "one"\n[[segment]]\nkind = "move"\ndistance = "1000 mm"\n'
                    '[[segment]]\nkind = "dwell"\ntime = "0.5 s"\n')
    base, mine = js(), js("--cycle", str(path))
    for key in ("peak_torque", "rms_torque", "peak_power", "braking_energy", "reflected_inertia", "cycle_time",
                "accel_energy", "accel_energy_exact"):
        assert mine[key]["value"] == pytest.approx(base[key]["value"], rel=1e-13), key
    assert mine["selected_motor"] == base["selected_motor"] == "SGM7J-06A"


# the file pick_place_vertical.toml as repeated options (its [cycle] defaults as --speed/--accel/--jerk)
SEGMENTS = ("--speed", "1m/s", "--accel", "5m/s^2", "--jerk", "100m/s^3",
            "--segment", "move: name=down empty, distance=400mm, direction=-",
            "--segment", "dwell: name=grip, time=0.3s, force=-50N",
            "--segment", "move: name=up with part, distance=400mm, direction=+, payload=10kg",
            "--segment", "dwell: name=hand over, time=0.5s, payload=10kg")
BUS = ("--dc-bus-capacitance", "1000uF", "--dc-bus-voltage", "325V", "--chopper-voltage", "380V")


def test_segment_options_equal_the_cycle_file():
    # the same cycle given as options and as the file: one computation, so every output is the
    # same (bit for bit); only the inputs' echo, the cycle's title and what the scene gives differ
    # (the options give the speed and acceleration the file's [cycle] gives)
    base = js("--incline", "90deg", "--cycle", str(CYCLE), *BUS)
    mine = js("--incline", "90deg", *SEGMENTS, *BUS)
    assert {k for k in base if base[k] != mine.get(k)} == {"inputs", "scene"}
    assert set(base["scene"]["inherited"]) - set(mine["scene"]["inherited"]) == {"speed", "accel"}
    assert mine["peak_torque"]["value"] == pytest.approx(3.1528502, rel=1e-7)     # README's 3.153 N m
    assert mine["inputs"]["segment_texts"]["origin"] == "option"


def test_segment_options_print_the_cycle():
    res = run("--incline", "90deg", *SEGMENTS)
    assert res.exit_code == 0, res.output
    assert "cycle: 4 segments (--segment)" in res.stdout and "up with part" in res.stdout
    # going down, the motor holds the load back with a positive torque while the power flows back:
    # braking (the note once said 'none' because the torque was positive)
    line = next(x for x in res.stdout.splitlines() if "braking torque" in x)
    assert "while braking" in line and "2.49" in line


def test_one_segment_option_equals_the_single_move():
    base = js()
    mine = js("--segment", "move: distance=1000mm", "--segment", "dwell: time=0.5s")
    for key in ("peak_torque", "rms_torque", "peak_power", "braking_energy", "cycle_time", "accel_energy_exact"):
        assert mine[key]["value"] == pytest.approx(base[key]["value"], rel=1e-13), key


def test_vertical_cycle_file():
    out = js("--incline", "90deg", "--cycle", str(CYCLE))
    assert [s["name"] for s in out["segments"]] == ["down empty", "grip", "up with part", "hand over"]
    # holding with the part: (50 + 10) kg * 9.80665 * k = 588.399 * 3.1830989e-3 = 1.8729322 N m (+ b_M w = 0)
    hand_over = out["segments"][3]
    assert hand_over["rms_torque"]["value"] == pytest.approx(60 * 9.80665 * K, rel=1e-12)
    assert out["holding_torque"]["value"] == pytest.approx(60 * 9.80665 * K, rel=1e-12)
    # grip: 50 kg held, the part pushes up with 50 N: (50 * 9.80665 - 50) * k = 1.4016059 N m
    assert out["segments"][1]["peak_torque"]["value"] == pytest.approx((50 * 9.80665 - 50) * K, rel=1e-12)
    # going down empty the motor brakes the whole way: energy back, none in
    assert out["segments"][0]["energy_motoring"]["value"] == pytest.approx(0.0, abs=1e-12)
    assert out["segments"][0]["energy_braking"]["value"] > 100
    assert out["selected_motor"] == "SGM7J-06A"
    # the same incline in radians
    assert js("--incline", f"{PI / 2!r}rad", "--cycle", str(CYCLE))["rms_torque"]["value"] == \
        pytest.approx(out["rms_torque"]["value"], rel=1e-14)
    # a brake holds in the dwells: the RMS falls
    braked = js("--incline", "90deg", "--cycle", str(CYCLE), "--brake")
    assert braked["segments"][3]["rms_torque"]["value"] == 0.0
    assert braked["rms_torque"]["value"] == pytest.approx(math.sqrt(
        sum(s["rms_torque"]["value"] ** 2 * s["duration"]["value"] for s in out["segments"][::2])
        / out["cycle_time"]["value"]), rel=1e-12)


def test_dc_bus_and_resistor():
    # one braking event per cycle, 27.910199 J (the default move); C = 1000 uF, 325 -> 380 V:
    # E_C = 0.5 * 1e-3 * (380^2 - 325^2) = 0.5 * 1e-3 * 38775 = 19.3875 J; E_R = 27.910199 - 19.3875 = 8.522699 J
    out = js("--dc-bus-capacitance", "1000uF", "--dc-bus-voltage", "325V", "--chopper-voltage", "380V")
    assert out["dc_bus_energy"]["value"] == pytest.approx(19.3875, rel=1e-12)
    e_b = out["braking_energy"]["value"]
    assert out["resistor_energy"]["value"] == pytest.approx(e_b - 19.3875, rel=1e-12)
    assert out["resistor_power"]["value"] == pytest.approx((e_b - 19.3875) / 1.6, rel=1e-12)
    assert out["resistance_max"]["value"] == pytest.approx(380 ** 2 / out["resistor_peak_power"]["value"], rel=1e-12)
    assert len(out["warnings"]) == 1 and "braking resistor" in out["warnings"][0]
    res = run("--dc-bus-capacitance", "1000uF", "--dc-bus-voltage", "325V", "--chopper-voltage", "380V")
    assert res.exit_code == 0 and res.stderr.startswith("warning: braking returns")


def test_zone_fails_at_high_speed_with_a_catalog_curve(tmp_path):
    # a motor of our own with a published-style intermittent zone that falls to 1 N m at 6000 rpm;
    # at 5000 rpm the limit is 6 - 5 * 1000/2000 = 3.5 N m; 20 m/s^2 gives about 4.1 N m < T_max 6
    cat = tmp_path / "m.toml"
    cat.write_text('''[source]
document = "test motor"
[[motors]]
name = "TEST-1"
P = 600
T_n = 1.91
T_max = 6
J = 0.8
n_rated = 3000
n_max = 6000
zone_source = "made up for the test"
intermittent = [ { speed = 0, torque = 6 }, { speed = 4000, torque = 6 }, { speed = 6000, torque = 1 } ]
units = { P = "W", T_n = "N*m", T_max = "N*m", J = "kg*cm^2", n_rated = "rpm", n_max = "rpm", speed = "rpm", torque = "N*m" }
''')
    out = js("--catalog", str(cat), "--motor", "TEST-1", "--speed", "5000rpm", "--accel", "20m/s^2")
    test1 = next(m for m in out["motors"] if m["name"] == "TEST-1")
    assert test1["peak_ok"] and not test1["zone_ok"] and not test1["ok"]
    assert out["zone"]["assumed"] is False
    peak = out["peak_torque"]["value"]
    assert out["zone"]["limit"]["value"] == pytest.approx(6 - 5 * 1000 / 2000, rel=1e-12)  # 3.5 N m at 5000 rpm
    assert out["zone_margin"]["value"] == pytest.approx(3.5 - peak, rel=1e-9)
    assert any("outside the intermittent zone" in w for w in out["warnings"])


def test_gearbox_catalog(tmp_path):
    # a gearbox of ratio 20 with 0.1 kg cm^2 (the scene's), efficiency 0.9: the accelerating torque at the
    # end of the acceleration is J_M eps + b_M w + (J_L' eps + T_R) / 0.9, with J_L' = J_LOAD - 1e-5
    gb = tmp_path / "g.toml"
    gb.write_text('''[source]
document = "test gearbox"
[[gearboxes]]
name = "PL-20"
ratio = 20
J = 0.1
efficiency = 0.9
n_max_in = 4000
T_rated_out = 10
T_peak_out = 60
units = { J = "kg*cm^2", n_max_in = "rpm", T_rated_out = "N*m", T_peak_out = "N*m" }
''')
    out = js("--gearbox-catalog", str(gb), "--gearbox", "PL-20", "--motor", "SGM7J-06A")
    want = (0.8e-4 + 1e-5) * EPS + B_M * OMEGA + ((J_LOAD - 1e-5) * EPS + T_R) / 0.9
    assert out["peak_torque"]["value"] == pytest.approx(want, rel=1e-12)
    assert out["gearbox"]["name"] == "PL-20"
    checks = {c["name"]: c for c in out["gearbox"]["checks"]}
    # peak output torque: ((J_L' eps + T_R) * 20
    assert checks["gearbox peak output torque"]["value"]["value"] == pytest.approx(
        ((J_LOAD - 1e-5) * EPS + T_R) * 20, rel=1e-12)
    assert not checks["gearbox RMS output torque"]["ok"]        # 10 N m rated is too little here
    assert any("gearbox RMS output torque" in w for w in out["warnings"])


ERRORS = [
    pytest.param(["--move-time", "1s", "--speed", "2m/s"], 2, ["--speed", "--move-time"], id="time-and-speed"),
    pytest.param(["--move-time", "1s", "--jerk", "100m/s^3"], 2, ["--jerk"], id="time-and-jerk"),
    pytest.param(["--cycle", str(CYCLE), "--stroke", "1m"], 2, ["--stroke", "--cycle"], id="cycle-and-stroke"),
    pytest.param(["--dc-bus-capacitance", "1mF"], 2, ["--dc-bus-voltage"], id="bus-incomplete"),
    pytest.param(["--sweep", "accel=1rad/s^2:2rad/s^2:2", "--jerk", "1m/s^3"], 2, ["--sweep", "--jerk"],
                 id="sweep-and-jerk"),
    pytest.param(["--jerk", "5kg"], 2, ["--jerk", "'5kg'"], id="jerk-units"),
    pytest.param(["--jerk", "0m/s^3"], 1, ["--jerk", "> 0"], id="jerk-zero"),
    pytest.param(["--incline", "100deg"], 1, ["--incline"], id="incline-over-90"),
    pytest.param(["--gear-efficiency", "1.5"], 1, ["--gear-efficiency", "(0, 1]"], id="efficiency-over-1"),
    pytest.param(["--counterweight", "-1kg"], 1, ["--counterweight", ">= 0"], id="counterweight-negative"),
    pytest.param(["--move-time", "1s", "--accel-fraction", "0.7"], 1, ["--accel-fraction"], id="fraction"),
    pytest.param(["--gearbox", "NOPE"], 2, ["--gearbox", "'NOPE'"], id="unknown-gearbox"),
    pytest.param(["--dc-bus-capacitance", "1mF", "--dc-bus-voltage", "400V", "--chopper-voltage", "380V"], 1,
                 ["--chopper-voltage", "above the bus voltage"], id="chopper-below-bus"),
    pytest.param(["--segment", "move: distance=3"], 2, ["--segment", "'move: distance=3'", "distance", "unit"],
                 id="segment-no-unit"),
    pytest.param(["--segment", "jump: distance=3m"], 2, ["--segment", "kind", "move:", "dwell:"], id="segment-kind"),
    pytest.param(["--segment", "move: distance=3m, colour=red"], 2, ["--segment", "colour", "unknown key"],
                 id="segment-key"),
    pytest.param(["--segment", "move: distance=3m, distance=4m"], 2, ["--segment", "distance", "twice"],
                 id="segment-twice"),
    pytest.param(["--segment", "move: distance 3m"], 2, ["--segment", "KEY=VALUE"], id="segment-no-equals"),
    pytest.param(["--segment", "dwell: distance=3m"], 2, ["--segment", "not a key of a dwell"], id="segment-dwell"),
    pytest.param(["--segment", "dwell: force=3N"], 2, ["--segment", "time", "missing"], id="segment-dwell-time"),
    pytest.param(["--segment", "move: distance=1m", "--stroke", "1m"], 2, ["--stroke", "--segment"],
                 id="segment-and-stroke"),
    pytest.param(["--segment", "move: distance=1m", "--cycle", str(CYCLE)], 2, ["--segment", "--cycle", "not both"],
                 id="segment-and-cycle"),
    pytest.param(["--segment", "move: distance=-1m"], 1, ["--segment", "segment 1", "-1 m"], id="segment-negative"),
    pytest.param(["--segment", "dwell: time=1s"], 1, ["--segment", "no move"], id="segment-only-dwells"),
]


@pytest.mark.parametrize("args, code, fragments", ERRORS)
def test_errors_are_one_line(args, code, fragments, tmp_path):
    out = tmp_path / "out.csv"
    one_error_line(run(*args, "--csv", str(out)), code, *fragments)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text, fragments", [
    ('[[segment]]\nkind = "move"\n', ["segment[0].distance", "missing"]),
    ('[[segment]]\nkind = "jump"\n', ["segment[0].kind"]),
    ('[[segment]]\nkind = "dwell"\ntime = "1 m"\n', ["segment[0].time", "'1 m'"]),
    ('[[segment]]\nkind = "move"\ndistance = "1 m"\ndirection = "up"\n', ["segment[0].direction"]),
    ('[[segment]]\nkind = "move"\ndistance = "1 m"\ncolour = "red"\n', ["segment[0].colour", "unknown key"]),
    ('[cycle]\ntitle = "x"\n', ["segment", "one or more"]),
    ('[[segment]]\nkind = "move"\ndistance = "-1 m"\n', ["--cycle", "segment 1", "-1 m"]),
    ('[[segment]]\nkind = "dwell"\ntime = "1 s"\n', ["--cycle", "no move"]),
    ('[[segment]]\nkind = "dwell"\ntime = "1 s"\nforce = "1 N"\ndistance = "1 m"\n', ["segment[0].distance"]),
    ('not toml ===', ["not valid TOML"]),
])
def test_bad_cycle_files(tmp_path, text, fragments):
    path = tmp_path / "c.toml"
    path.write_text(text)
    one_error_line(run("--cycle", str(path)), 1, *fragments)


def test_csv_of_a_cycle_is_exact_at_the_phase_ends(tmp_path):
    path = tmp_path / "p.csv"
    ok(run("--jerk", "200m/s^3", "--csv", str(path)))
    rows = [line.split(",") for line in path.read_text().splitlines()[1:]]
    # 7 move phases + dwell, 21 points each; the last point of 'accelerate' is the peak (left limit)
    assert len(rows) == 8 * 21
    assert float(rows[2 * 21 - 1][3]) == pytest.approx(J_RED * EPS + B_M * (OMEGA - EPS * 0.025) + T_R, rel=1e-12)


def test_assumed_zone_end_and_where_the_margin_is_smallest():
    # 4500 rpm: the assumed zone of SGM7J-06A falls from 6.69 at 3000 rpm to T_n = 1.91 at 6000 rpm:
    # 6.69 - 4.78 * 1500/3000 = 4.3 N m; with --zone-end 0.5 to 3.345 at 6000: 6.69 - 3.345/2 = 5.0175 N m.
    # The smallest margin is at the end of the acceleration, at 4500 rpm (peak torque, highest speed).
    w = 4500 * PI / 30
    for extra, limit in (((), 4.3), (("--zone-end", "0.5"), 5.0175)):
        out = js("--speed", "4500rpm", "--motor", "SGM7J-06A", *extra)
        z = out["zone"]
        assert (z["speed"]["value"], z["limit"]["value"]) == pytest.approx((w, limit), rel=1e-12)
        assert (z["segment"], z["phase"]) == ("move", "accelerate")
        assert out["zone_margin"]["value"] == pytest.approx(limit - out["peak_torque"]["value"], rel=1e-12)


# --- the plot's torque-speed panel ----------------------------------------------------------------

def sized(*catalogs: str, motor: str | None = None):
    """The CycleSizing motor-size reports for the WDU scene with these catalog files (and --motor)."""
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.data.scenefile import load_scene
    from beltcalc.params import resolve
    from beltcalc.design.sizing import DutyOptions, size_cycle
    from beltcalc.design.axis_inputs import PARAMS, SizingInputs

    cat = load_catalog(catalogs)
    values = resolve(load_scene("wdu", command="motor-size"), PARAMS, {})
    inp = SizingInputs.from_values({k: v.value for k, v in values.items()})
    return size_cycle(inp, cat.belt(values["belt"].value), list(cat.motors.values()),
                      cat.motor(motor) if motor else None, DutyOptions())


def test_zone_panel_draws_the_assumed_zone_and_the_cycle():
    from beltcalc.design.motor_report import zone_plot_data

    data = zone_plot_data(sized())
    # SGM7J-06A: T_max 6.69 N m flat to the rated 3000 rpm, then down to T_n 1.91 N m at 6000 rpm
    assert data["intermittent_assumed"] and not data["continuous_from_catalog"]
    assert data["intermittent"] == [pytest.approx(p, rel=1e-12) for p in [(0.0, 6.69), (3000.0, 6.69), (6000.0, 1.91)]]
    assert data["continuous"] == [pytest.approx(p, rel=1e-12) for p in [(0.0, 1.91), (3000.0, 1.91)]]
    # the cycle's points reach the peak torque (the left limit at t_a) at 3000 rpm; the RMS point
    # sits at the mean speed: the stroke 314.16 rad over the cycle 1.6 s = 1875 rpm
    w, t = zip(*data["points"])
    assert max(t) == pytest.approx(2.1013978, rel=1e-7) and max(w) == pytest.approx(3000.0, rel=1e-12)
    assert data["rms"] == pytest.approx((1875.0, 0.6910177), rel=1e-6)
    assert data["worst"] == pytest.approx((3000.0, 2.1013978), rel=1e-7)


def test_zone_panel_draws_a_catalog_zone(tmp_path):
    from beltcalc.design.motor_report import zone_plot_data
    from beltcalc.plots import profile_figure, save_figure

    cat = tmp_path / "m.toml"
    cat.write_text('''[source]
document = "test motor"
[[motors]]
name = "TEST-2"
P = 600
T_n = 1.91
T_max = 6
J = 0.8
n_rated = 3000
n_max = 6000
zone_source = "made up for the test"
intermittent = [ { speed = 0, torque = 6 }, { speed = 4000, torque = 6 }, { speed = 6000, torque = 1 } ]
continuous = [ { speed = 0, torque = 2.2 }, { speed = 3000, torque = 1.91 }, { speed = 6000, torque = 0.8 } ]
units = { P = "W", T_n = "N*m", T_max = "N*m", J = "kg*cm^2", n_rated = "rpm", n_max = "rpm", speed = "rpm", torque = "N*m" }
''')
    s = sized(str(cat), motor="TEST-2")
    assert s.shown.motor.name == "TEST-2"
    data = zone_plot_data(s)
    assert not data["intermittent_assumed"] and data["continuous_from_catalog"]
    assert data["continuous"] == [pytest.approx(p, rel=1e-12) for p in [(0.0, 2.2), (3000.0, 1.91), (6000.0, 0.8)]]
    pytest.importorskip("matplotlib")
    path = tmp_path / "zone.png"
    save_figure(profile_figure(s), path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_of_a_cycle_and_matplotlib_only_when_plotting(tmp_path):
    import subprocess
    import sys

    code = "import sys, beltcalc.cli.motor_size; print('matplotlib' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip() == "False"
    pytest.importorskip("matplotlib")
    path = tmp_path / "cycle.png"
    res = run("--incline", "90deg", "--cycle", str(CYCLE), "--plot", str(path))
    assert res.exit_code == 0, res.output
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["cycle.png"]       # written atomically: no temporary left
