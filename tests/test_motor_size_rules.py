"""``beltcalc motor-size``, issue 28 item 5: the braking resistor rated by the method the docs
cite, one rule for a dwell of 0 s, a note where the jerk keeps a move below the acceleration
asked, and a new axis that names what it takes from the scene (and where each value is
measured), through the command a user types.

Hand values: the WDU scene's pulley is 40 AT10 teeth, D = 0.4 m / pi, behind a 20:1 gearbox,
so k = D / (2 i) = 0.01 / pi m per motor radian and 3000 rpm at the motor is 1 m/s at the
carriage.
"""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from beltcalc.data.catalogs import builtin_dir, load_catalog
from beltcalc.data.scenefile import load_scene
from beltcalc.cli.main import cli

CYCLE = builtin_dir() / "cycles" / "pick_place_vertical.toml"
BUS = ("--dc-bus-capacitance", "1000uF", "--dc-bus-voltage", "325V", "--chopper-voltage", "380V")
K = 0.4 / math.pi / 40            # D / (2 i) [m/rad]
G0 = 9.80665


def run(*args: str):
    return CliRunner().invoke(cli, ["motor-size", *args])


def js(*args: str) -> dict:
    res = run(*args, "--json")
    assert res.exit_code == 0, res.output + res.stderr
    return json.loads(res.stdout)


# --- the braking resistor ---------------------------------------------------------------------

def test_the_resistor_is_rated_by_the_cited_method_and_the_average_is_a_row_of_its_own():
    res = run("--incline", "90deg", "--cycle", str(CYCLE), *BUS, "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    # E_C = C (U_max^2 - U_dc^2) / 2 = 0.5 * 1e-3 F * (380^2 - 325^2) V^2 = 19.3875 J per event
    e_c = 0.5 * 1e-3 * (380.0 ** 2 - 325.0 ** 2)
    assert out["dc_bus_energy"]["value"] == pytest.approx(e_c, rel=1e-12)
    e_k = sum(max(ev["energy"]["value"] - e_c, 0.0) for ev in out["braking_events"])
    assert out["resistor_energy"]["value"] == pytest.approx(e_k, rel=1e-12)
    t = out["cycle_time"]["value"]
    # Yaskawa Sigma-7 SERVOPACK manual, 12.8.6 "Calculating the Regenerative Energy", step 6:
    # W_K = E_K / (0.2 T), 0.2 being the resistor's utilized load ratio of 20 % (note 1)
    assert out["resistor_rating"]["value"] == pytest.approx(e_k / (0.2 * t), rel=1e-12)
    assert out["resistor_power"]["value"] == pytest.approx(e_k / t, rel=1e-12)     # the average, its own row
    # the warning asks for the rating, and names the average beside it
    assert f"rated at least {e_k / (0.2 * t):.3g} W" in res.stderr
    assert f"{e_k / t:.3g} W on average" in res.stderr
    table = run("--incline", "90deg", "--cycle", str(CYCLE), *BUS).stdout
    rating = next(line for line in table.splitlines() if "rated capacity W_K" in line)
    assert f"{e_k / (0.2 * t):.3g}" in rating and "E_K / (0.2 T)" in rating
    average = next(line for line in table.splitlines() if "braking resistor, average power" in line)
    assert f"{e_k / t:.3g}" in average and "not a rating" in average


# --- a dwell of 0 s ---------------------------------------------------------------------------

def test_a_dwell_of_zero_is_no_dwell_in_every_form(tmp_path):
    path = tmp_path / "zero.toml"
    path.write_text('[cycle]\ntitle = "zero dwell"\n[[segment]]\nkind = "move"\ndistance = "400 mm"\n'
                    '[[segment]]\nkind = "dwell"\ntime = "0 s"\n')
    base = js("--stroke", "400mm", "--dwell", "0s")
    # 0.4 m at 1 m/s with 10 m/s^2: 0.4 / 1 + 1 / 10 = 0.5 s, and no dwell after it
    assert base["cycle_time"]["value"] == pytest.approx(0.5, rel=1e-12)
    for out in (js("--segment", "move: distance=400mm", "--segment", "dwell: time=0s"), js("--cycle", str(path))):
        assert [g["kind"] for g in out["segments"]] == ["move"]
        for key in ("cycle_time", "peak_torque", "rms_torque", "braking_energy", "motoring_energy"):
            assert out[key]["value"] == pytest.approx(base[key]["value"], rel=1e-12), key


@pytest.mark.parametrize("args", [
    ("--dwell", "-1s"),
    ("--segment", "move: distance=400mm", "--segment", "dwell: time=-1s"),
], ids=["option", "segment"])
def test_a_negative_dwell_is_refused_by_the_same_rule(args):
    res = run(*args)
    assert res.exit_code == 1
    assert "-1 s is not allowed; it must be >= 0 s" in res.stderr


# --- the jerk that keeps a move below the acceleration asked ----------------------------------

def test_a_note_says_when_the_jerk_keeps_the_move_below_the_acceleration_asked():
    # v = 1 m/s and j = 20 m/s^3 at the carriage: v j = 20 < a^2 = 100, so the speed is reached
    # before the acceleration, a = sqrt(v j) = 4.4721 m/s^2 (Biagiotti & Melchiorri 2008, 3.4)
    out = js("--jerk", "20m/s^3")
    [move] = out["jerk_limited_moves"]
    assert move["carriage_accel_reached"]["value"] == pytest.approx(math.sqrt(20.0), rel=1e-9)
    assert move["carriage_accel_asked"]["value"] == pytest.approx(10.0, rel=1e-12)
    assert move["accel_reached"]["value"] == pytest.approx(math.sqrt(20.0) / K, rel=1e-9)
    assert out["carriage_accel"]["value"] == pytest.approx(math.sqrt(20.0), rel=1e-9)
    [note] = out["notes"]
    assert "jerk limit" in note and "4.472 m/s^2" in note and "below the 10 m/s^2" in note
    text = run("--jerk", "20m/s^3").stdout
    line = next(x for x in text.splitlines() if "carriage acceleration" in x)
    assert "the jerk limits it: 10 m/s^2 asked" in line
    assert "note: move: the jerk limit" in text
    # j = 200 m/s^3: v j = 200 >= a^2, the acceleration is reached: no note
    reached = js("--jerk", "200m/s^3")
    assert reached["jerk_limited_moves"] == [] and reached["notes"] == []
    assert reached["carriage_accel"]["value"] == pytest.approx(10.0, rel=1e-12)


# --- a new axis and the scene -----------------------------------------------------------------

NEW = ("--incline", "90deg", "--mass", "5kg", "--stroke", "400mm", "--move-time", "0.6s")


def test_a_new_axis_names_in_the_table_what_it_takes_from_the_scene():
    out = js(*NEW)
    scene = load_scene("wdu").values
    inherited = out["scene"]["inherited"]
    assert out["scene"]["name"] == "wdu" and out["scene"]["new_axis"] is True
    assert {"gear_ratio", "pulley_teeth", "dwell", "belt"} <= set(inherited)
    assert not {"mass", "stroke", "speed", "accel"} & set(inherited)     # given, or replaced by --move-time
    for name, entry in inherited.items():
        assert entry["text"] == scene[name][0], name
    res = run(*NEW)
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith("Motor sizing: your axis on the scene wdu")
    assert "from the scene wdu (not given" in res.stdout
    gear = next(x for x in res.stdout.splitlines() if "--gear-ratio" in x)
    assert scene["gear_ratio"][0] in gear and "motor speed / drive-pulley speed" in gear
    dwell = next(x for x in res.stdout.splitlines() if "--dwell" in x)
    assert scene["dwell"][0] in dwell


def test_the_scene_alone_is_not_a_new_axis():
    out = js()
    assert out["scene"]["new_axis"] is False
    assert "from the scene" not in run().stdout


def test_a_vertical_axis_comes_back_down_and_brakes_on_the_way():
    # the default cycle of an inclined axis: up, the dwell, down, the dwell
    out = js(*NEW)
    assert [g["name"] for g in out["segments"]] == ["up", "dwell at the top", "down", "dwell at the bottom"]
    assert any("comes back" in n for n in out["notes"])
    # the way down by hand: the 5 kg carriage gives back m g L, less the motor's own loss
    # b_M integral w^2 dt (no guide friction at 90 deg, no bearing or guide damping, an ideal
    # gearbox; the move starts and ends at rest, so the kinetic energy nets out)
    motor = load_catalog().motor(out["selected_motor"])
    eta = motor.efficiency if motor.efficiency is not None else 0.9
    b_m = (1 - eta) * motor.T_n / motor.n_rated
    w = 0.4 / K / (0.6 - 0.2)                        # thirds: T_a = 0.2 s, w = theta / (T - T_a)
    w2_dt = w * w * (2 * 0.2 / 3 + 0.2)              # two ramps of w^2 t/3 and the cruise
    down = next(g for g in out["segments"] if g["name"] == "down")
    net_back = down["energy_braking"]["value"] - down["energy_motoring"]["value"]
    assert net_back == pytest.approx(5 * G0 * 0.4 - b_m * w2_dt, rel=1e-9)
    assert out["braking_energy"]["value"] == pytest.approx(
        sum(g["energy_braking"]["value"] for g in out["segments"]), rel=1e-12)


def test_every_value_of_the_scene_says_where_it_is_measured():
    out = js()
    sides = ("motor side:", "carriage side:", "motor speed / drive-pulley speed", "the cycle:")
    for name, entry in out["scene"]["inherited"].items():
        assert entry["where"].startswith(sides), name
    # a speed or acceleration by its unit: the scene's 3000 rpm at the motor, 10 m/s^2 at the carriage
    assert out["scene"]["inherited"]["speed"]["where"].startswith("motor side")
    assert out["scene"]["inherited"]["accel"]["where"].startswith("carriage side")
    text = run("--mass", "20kg").stdout
    for option in ("--gearbox-inertia", "--coupling-inertia", "--speed", "--accel", "--pulley-teeth"):
        line = next(x for x in text.splitlines() if f" {option} " in x)
        assert "motor side" in line or "carriage side" in line, option
    assert "reflected inertia, at the motor shaft" in text and "torque at the motor shaft" in text


def test_no_scene_names_every_missing_value_at_once_and_with_all_given_is_the_scene():
    res = run("--scene", "none", "--mass", "50kg")
    assert res.exit_code == 2
    [line] = [x for x in res.stderr.splitlines() if x.startswith("Error")]
    missing = [n for n in load_scene("wdu").values if n != "mass"]
    for name in missing:
        assert "--" + name.replace("_", "-") in line, name
    assert f"({len(missing)} missing)" in line
    args = []
    for name, (text, _) in load_scene("wdu").values.items():
        args += ["--" + name.replace("_", "-"), text]
    mine, base = js("--scene", "none", *args), js()
    assert mine["scene"]["inherited"] == {}
    for key in ("peak_torque", "rms_torque", "reflected_inertia", "cycle_time"):
        assert mine[key]["value"] == pytest.approx(base[key]["value"], rel=1e-15), key
