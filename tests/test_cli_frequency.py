"""``beltcalc modes``, ``response``, ``campbell`` (beltcalc/cli/frequency.py): every command's
default run, --json structure and values against peers' figures (openTorsion's Friswell cases)
and analytic cases (a damped one-mass drive: peak 1/d at w_n, Q = 1/(2 zeta); crossings at
2 pi f / k), --csv and --plot files, --set, and each bad input's one line and exit code."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from beltcalc.sim import frequency_report as fq
from beltcalc.sim.drivefile import undamped_frequencies
from clichecks import ok, one_error_line, read_csv, table_rows

# a damped one-mass drive on a spring to the frame: J phi'' + d phi' + C phi = T
J, C, D = 0.3, 1200.0, 0.9
WN = math.sqrt(C / J)                       # 63.2456 rad/s
ZETA = D / (2 * math.sqrt(C * J))           # 0.023717

ONE_MASS = f"""
[drive]
title = "one mass on a spring"
t_end = "1 s"

[[node]]
name = "a"
inertia = "{J} kg*m^2"

[[coupling]]
name = "k"
between = ["a"]
stiffness = "{C} N*m/rad"
damping = "{D} N*m*s/rad"
"""


MASSLESS = """
[drive]
t_end = "1 s"

[[node]]
name = "a"
inertia = "0.1 kg*m^2"

[[node]]
name = "m"
inertia = "0 kg*m^2"

[[node]]
name = "b"
inertia = "0.2 kg*m^2"

[[coupling]]
name = "k1"
between = ["a", "m"]
stiffness = "100 N*m/rad"
damping = "0.1 N*m*s/rad"

[[coupling]]
name = "k2"
between = ["m", "b"]
stiffness = "200 N*m/rad"
damping = "0.2 N*m*s/rad"
"""


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def js(*args) -> dict:
    return json.loads(ok(run(*args, "--json")).stdout)


@pytest.fixture
def one_mass(tmp_path) -> Path:
    path = tmp_path / "one_mass.toml"
    path.write_text(ONE_MASS)
    return path


def csv_rows(path: Path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_text())))


def is_png(path: Path) -> bool:
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# --- modes ----------------------------------------------------------------------------------------

def test_modes_default_is_the_sewing_drive_with_every_pole():
    out = ok(run("modes")).stdout
    rows = table_rows(out, "Sewing-machine drive (Mamatova et al. 2016): every pole")
    assert [r[1] for r in rows] == ["rigid body", "mode 1"] + ["real"] * 8
    assert rows[1][2:5] == ["17.36", "16.55", "0.302"]
    # issue 11: 8 real poles with time constants from 1.7 us to 23 ms
    assert (rows[2][5], rows[-1][5]) == ("23.34 ms", "1.653 us")
    assert "undamped natural frequencies (no damping, motors free): 118.2, 281.1, 604.7, 857.9 Hz" in out
    assert ("mode 1: 17.36 Hz, damping ratio 0.302; strain energy: 23 (36.0 %), 12 (30.1 %), 34 (20.5 %), "
            "45 (13.5 %)") in out
    shape = table_rows(out, "mode 1: 17.36 Hz")
    assert [r[0] for r in shape] == ["1", "2", "3", "4", "5"]
    assert shape[0][1:] == ["1", "0"]                       # the largest amplitude is the reference


def test_modes_json_of_the_sewing_drive():
    obj = js("modes", "sewing")
    assert obj["drive"] == "Sewing-machine drive (Mamatova et al. 2016)"
    modes = obj["modes"]
    assert [m["kind"] for m in modes] == ["rigid", "oscillatory"] + ["real"] * 8
    m = modes[1]
    assert m["mode"] == 1
    assert m["frequency"] == {"value": pytest.approx(17.3634, rel=1e-5), "unit": "Hz"}
    assert m["damping_ratio"] == {"value": pytest.approx(0.3017, rel=1e-3), "unit": "1"}
    assert m["damped_frequency"]["value"] == pytest.approx(17.3634 * math.sqrt(1 - 0.30171 ** 2), rel=1e-4)
    # s = -zeta w_n + j w_n sqrt(1 - zeta^2)
    wn = 2 * math.pi * m["frequency"]["value"]
    assert m["s_real"]["value"] == pytest.approx(-m["damping_ratio"]["value"] * wn, rel=1e-12)
    assert m["s_imag"]["value"] == pytest.approx(2 * math.pi * m["damped_frequency"]["value"], rel=1e-12)
    shape = m["shape"]
    assert shape["nodes"]["1"] == {"amplitude": {"value": pytest.approx(1.0, rel=1e-12), "unit": "1"},
                                   "phase": {"value": pytest.approx(0.0, abs=1e-9), "unit": "rad"}}
    assert max(n["amplitude"]["value"] for n in shape["nodes"].values()) == pytest.approx(1.0, rel=1e-12)
    shares = {e: s["value"] for e, s in shape["strain_energy"].items()}
    assert sorted(shares) == ["12", "23", "34", "45"]
    assert sum(shares.values()) == pytest.approx(1.0, rel=1e-12)
    assert shape["largest_strain_energy"] == {"element": "23", "share": {"value": pytest.approx(0.36, abs=5e-4),
                                                                        "unit": "1"}}
    tau = [p["time_constant"] for p in modes if p["kind"] == "real"]
    assert {t["unit"] for t in tau} == {"s"}
    assert [tau[0]["value"], tau[-1]["value"]] == pytest.approx([23.343e-3, 1.6532e-6], rel=1e-4)
    for p in modes:                                     # a real pole: s = -1 / tau
        if p["kind"] == "real":
            assert p["s_real"]["value"] == pytest.approx(-1 / p["time_constant"]["value"], rel=1e-12)
    net = fq.load("sewing").network
    assert obj["undamped_frequencies"] == {"value": pytest.approx(undamped_frequencies(net), rel=1e-12), "unit": "Hz"}


def test_modes_of_friswells_geared_system():
    # openTorsion's test case for Friswell et al. example 9.6.3 prints 10.304, 20.479, 24.423 Hz
    obj = js("modes", "friswell_geared")
    assert [m["kind"] for m in obj["modes"]] == ["rigid", "rigid"] + ["oscillatory"] * 3
    osc = obj["modes"][2:]
    assert [m["frequency"]["value"] for m in osc] == pytest.approx([10.304, 20.479, 24.423], abs=5e-4)
    assert obj["undamped_frequencies"]["value"] == pytest.approx([10.304, 20.479, 24.423], abs=5e-4)
    for m in osc:
        assert m["damping_ratio"]["value"] == pytest.approx(0.0, abs=1e-12)
        nodes = {n: v["amplitude"]["value"] for n, v in m["shape"]["nodes"].items()}
        assert nodes["gear3"] == pytest.approx(nodes["gear1"] / 1.6, rel=1e-9)     # the 1.6:1 gear pair
    # mode 2: the two branch disks against each other, the rest still
    assert osc[1]["shape"]["largest_strain_energy"]["element"] in ("branch1", "branch2")
    assert osc[1]["shape"]["nodes"]["disk0"]["amplitude"]["value"] == pytest.approx(0.0, abs=1e-9)


def test_modes_of_friswells_five_disks():
    # openTorsion's test case for Friswell et al. example 9.7.1: 81.21, 141.21, 378.95, 536.36 Hz
    obj = js("modes", "friswell_5_disks")
    f = [m["frequency"]["value"] for m in obj["modes"] if m["kind"] == "oscillatory"]
    assert f == pytest.approx([81.21, 141.21, 378.95, 536.36], abs=5e-3)


def test_modes_of_a_one_mass_drive_are_analytic(one_mass):
    (m,) = js("modes", one_mass)["modes"]
    assert m["frequency"]["value"] == pytest.approx(WN / (2 * math.pi), rel=1e-12)
    assert m["damping_ratio"]["value"] == pytest.approx(ZETA, rel=1e-12)
    assert m["damped_frequency"]["value"] == pytest.approx(WN * math.sqrt(1 - ZETA ** 2) / (2 * math.pi), rel=1e-12)
    assert m["shape"]["largest_strain_energy"]["element"] == "k"


def test_modes_set_changes_the_drive():
    base = js("modes")["modes"][1]["frequency"]["value"]
    stiff = js("modes", "--set", "23.stiffness=2600N*m/rad")["modes"][1]["frequency"]["value"]
    expected = fq.modes(fq.load("sewing", {"23.stiffness": 2600.0}).network).oscillatory()[0].frequency
    assert stiff == pytest.approx(expected, rel=1e-12)
    assert stiff != pytest.approx(base, rel=1e-6)


def test_modes_csv_and_plot(tmp_path):
    path, png = tmp_path / "modes.csv", tmp_path / "modes.png"
    out = ok(run("modes", "--csv", path, "--plot", png)).stdout
    assert "every pole" in out
    rows = csv_rows(path)
    assert [r["kind"] for r in rows] == ["rigid", "oscillatory"] + ["real"] * 8
    obj = js("modes")
    assert float(rows[1]["frequency_Hz"]) == pytest.approx(obj["modes"][1]["frequency"]["value"], rel=1e-15)
    assert rows[1]["largest_strain_energy"] == "23"
    assert float(rows[1]["amplitude_5"]) == pytest.approx(
        obj["modes"][1]["shape"]["nodes"]["5"]["amplitude"]["value"], rel=1e-15)
    assert float(rows[2]["time_constant_s"]) == pytest.approx(23.343e-3, rel=1e-4)
    assert rows[0]["frequency_Hz"] == "" and rows[2]["frequency_Hz"] == ""
    assert is_png(png)


# --- response -------------------------------------------------------------------------------------

def test_response_default_run():
    out = ok(run("response")).stdout
    assert "frequency response H(jw) (strands taut), 1.736 to 173.6 Hz, 2000 points, log" in out
    peaks = table_rows(out, "resonance peaks of |H|")
    # the default: a load on the last node (5), the speed of every node
    assert [(r[0], r[1]) for r in peaks] == [(f"omega_{k}", "load:5") for k in range(1, 6)]
    assert {r[4] for r in peaks} == {"rad/s/(N m)"}
    assert peaks[2][2:4] == ["16.93", "19.08"]
    assert "magnitude and phase at some of the frequencies" in out


def test_response_json_of_a_one_mass_drive_is_analytic(one_mass):
    # mobility of J phi'' + d phi' + C phi = T: |H| = w / |C - J w^2 + j d w|, peak 1/d at w_n,
    # half-power bandwidth d/J, so Q = w_n J / d = 1/(2 zeta) exactly
    obj = js("response", one_mass, "--from", "5Hz", "--to", "15Hz", "--points", "301")
    assert obj["excitations"] == ["load:a"] and obj["outputs"] == ["omega_a"]
    f = obj["frequency"]
    assert f["unit"] == "Hz" and len(f["value"]) == 301
    assert f["value"][0] == pytest.approx(5.0, rel=1e-15) and f["value"][-1] == pytest.approx(15.0, rel=1e-15)
    (r,) = obj["responses"]
    assert (r["output"], r["input"], r["magnitude"]["unit"], r["phase"]["unit"]) == (
        "omega_a", "load:a", "rad/s/(N*m)", "rad")          # SI (issue 27; the table shows degrees)
    for k in (0, 150, 300):
        w = 2 * math.pi * f["value"][k]
        assert r["magnitude"]["value"][k] == pytest.approx(w / abs(C - J * w * w + 1j * D * w), rel=1e-12)
        assert r["phase"]["value"][k] == pytest.approx(
            math.atan2(C - J * w * w, D * w), abs=1e-11)       # arg(j w / (C - J w^2 + j d w)) [rad]
    (peak,) = r["peaks"]
    assert peak["frequency"] == {"value": pytest.approx(WN / (2 * math.pi), rel=1e-9), "unit": "Hz"}
    assert peak["magnitude"] == {"value": pytest.approx(1 / D, rel=1e-9), "unit": "rad/s/(N*m)"}
    assert peak["q"] == {"value": pytest.approx(1 / (2 * ZETA), rel=1e-7), "unit": "1"}


def test_response_named_inputs_outputs_and_units():
    obj = js("response", "--input", "load:3", "--input", "supply:motor", "--output", "T_23", "--output", "accel_5",
             "--from", "10rad/s", "--to", "100Hz", "--points", "50", "--spacing", "linear")
    f = obj["frequency"]["value"]
    assert f[0] == pytest.approx(10 / (2 * math.pi), rel=1e-15)         # rad/s read as angular frequency
    assert f[1] - f[0] == pytest.approx((100 - f[0]) / 49, rel=1e-9)     # linear spacing
    units = {(r["output"], r["input"]): r["magnitude"]["unit"] for r in obj["responses"]}
    assert units == {("T_23", "load:3"): "(N*m)/(N*m)", ("T_23", "supply:motor"): "(N*m)/(rad/s)",
                     ("accel_5", "load:3"): "rad/s^2/(N*m)", ("accel_5", "supply:motor"): "rad/s^2/(rad/s)"}


def test_one_point_is_the_response_at_from(one_mass):
    obj = js("response", one_mass, "--from", "10Hz", "--points", "1")
    (r,) = obj["responses"]
    w = 2 * math.pi * 10.0
    assert obj["frequency"]["value"] == [10.0]
    assert r["magnitude"]["value"] == [pytest.approx(w / abs(C - J * w * w + 1j * D * w), rel=1e-12)]
    assert r["peaks"] == []


def test_response_csv_one_row_per_frequency_and_bode_plot(tmp_path):
    path, png = tmp_path / "h.csv", tmp_path / "bode.png"
    ok(run("response", "--output", "omega_3", "--output", "T_45", "--points", "200", "--csv", path, "--plot", png))
    header, cols = read_csv(path)
    assert header == ["f_Hz", "omega_rad_per_s", "mag_omega_3_from_load_5_rad_per_s_per_N_m",
                      "phase_omega_3_from_load_5_deg", "mag_T_45_from_load_5_N_m_per_N_m", "phase_T_45_from_load_5_deg"]
    assert cols["f_Hz"].size == 200
    assert cols["omega_rad_per_s"] == pytest.approx(2 * math.pi * cols["f_Hz"], rel=1e-15)
    obj = js("response", "--output", "omega_3", "--output", "T_45", "--points", "200")
    assert list(cols["mag_T_45_from_load_5_N_m_per_N_m"]) == pytest.approx(obj["responses"][1]["magnitude"]["value"],
                                                                           rel=1e-15)
    assert is_png(png)


# --- campbell -------------------------------------------------------------------------------------

def test_a_load_on_a_node_without_inertia_is_refused_by_its_input(tmp_path):
    # the middle node of two springs has no inertia: it is condensed out and takes no load;
    # its speed is an output (here the node of the one mode: phi_m = (k1 phi_a + k2 phi_b) / (k1 + k2) = 0)
    path = tmp_path / "massless.toml"
    path.write_text(MASSLESS)
    one_error_line(run("response", path, "--input", "load:m"), 1, "--input: a load input on 'm': a node without "
                                                                    "inertia cannot carry a load")
    obj = js("response", path, "--output", "omega_m", "--output", "omega_b", "--points", "400")
    assert [r["input"] for r in obj["responses"]] == ["load:b", "load:b"]
    assert obj["responses"][0]["peaks"] == []
    # the two-mass mode through the condensed spring: C = 100 x 200 / 300, J = 0.1 x 0.2 / 0.3
    f = math.sqrt((200 / 3) / (0.02 / 0.3)) / (2 * math.pi)
    assert js("modes", path)["modes"][2]["frequency"]["value"] == pytest.approx(f, rel=1e-12)
    (peak,) = obj["responses"][1]["peaks"]
    assert peak["frequency"]["value"] == pytest.approx(f, rel=2e-3)       # damping ratio 0.016 shifts it


def test_campbell_default_run():
    out = ok(run("campbell")).stdout
    # orders 1, 2, 3 and the loads' own: at the motor's synchronous speed the loads run at the
    # main shaft's steady speed 227.86 rad/s, order 227.86 / 314.16 = 0.7253 of the motor
    assert "Campbell diagram, speed of node 1 from 0 to 377.0 rad/s (3600 rpm), orders 1, 2, 3, 0.7253" in out
    rows = table_rows(out, "crossings of order lines and modes")
    assert [(r[3], r[4]) for r in rows] == [("3", "1"), ("2", "1"), ("1", "1"), ("0.7253", "1")]
    assert rows[2][:3] == ["109.1", "1042", "0.347"]
    assert "node 1 turns at 314.2 rad/s (3000 rpm)" in out


def test_campbell_json_crossings_at_two_pi_f_over_k():
    obj = js("campbell", "--orders", "1,2,4", "--reference", "5")
    assert obj["reference"] == "5" and obj["orders"] == [1.0, 2.0, 4.0] and obj["motor"] == "motor"
    # the motor's node turns at its synchronous speed 2 pi 50 Hz / 1 pole pair; the belt U12 = 1.375
    operating = 2 * math.pi * 50 / 1.375
    assert obj["operating_speed"] == {"value": pytest.approx(operating, rel=1e-12), "unit": "rad/s"}
    assert obj["speed_max"]["value"] == pytest.approx(1.2 * operating, rel=1e-12)
    (mode,) = obj["modes"]
    f = mode["frequency"]["value"]
    assert f == pytest.approx(17.3634, rel=1e-5)
    assert [c["order"] for c in obj["crossings"]] == [4.0, 2.0, 1.0]
    for c in obj["crossings"]:
        assert c["speed"]["unit"] == "rad/s" and c["mode"] == 1
        assert c["speed"]["value"] == pytest.approx(2 * math.pi * f / c["order"], rel=1e-12)
        assert c["damping_ratio"]["value"] == pytest.approx(mode["damping_ratio"]["value"], rel=1e-12)
        assert c["speed_per_operating_speed"]["value"] == pytest.approx(c["speed"]["value"] / operating, rel=1e-12)


def test_campbell_of_a_drive_without_a_motor(one_mass):
    obj = js("campbell", one_mass, "--speed-max", "1200rpm", "--speed-min", "100rpm")
    assert obj["reference"] == "a" and obj["operating_speed"] is None and obj["motor"] is None
    # 10.07 Hz: order 1 at 604 rpm, 2 at 302 rpm, 3 at 201 rpm, all inside 100..1200 rpm
    speeds = [c["speed"]["value"] for c in obj["crossings"]]
    assert speeds == pytest.approx([WN / 3, WN / 2, WN], rel=1e-12)
    obj = js("campbell", one_mass, "--speed-max", "500rpm", "--speed-min", "250rpm")
    assert [c["order"] for c in obj["crossings"]] == [2.0]


def test_campbell_csv_and_plot(tmp_path):
    path, png = tmp_path / "campbell.csv", tmp_path / "campbell.png"
    ok(run("campbell", "conveyor", "--orders", "1,2,4", "--csv", path, "--plot", png))
    header, cols = read_csv(path)
    assert header == ["speed_rad_per_s", "speed_rpm", "order", "mode", "frequency_Hz", "damping_ratio",
                      "speed_per_operating_speed"]
    assert cols["speed_rpm"] == pytest.approx(cols["speed_rad_per_s"] * 60 / (2 * math.pi), rel=1e-15)
    assert cols["speed_rad_per_s"] == pytest.approx(2 * math.pi * cols["frequency_Hz"] / cols["order"], rel=1e-12)
    assert cols["order"].size == len(js("campbell", "conveyor", "--orders", "1,2,4")["crossings"]) == 8
    assert is_png(png)


def test_the_console_script_runs_campbell():
    exe = Path(sys.executable).with_name("beltcalc")
    result = subprocess.run([str(exe), "campbell", "--json"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["reference"] == "1"


# --- simulate --modes shows the same poles --------------------------------------------------------

def test_simulate_modes_json_is_every_pole():
    obj = json.loads(ok(run("simulate", "drive", "sewing", "--modes", "--json", "--samples", "101",
                            "--t-end", "0.1s", "--window", "0s")).stdout)
    poles = js("modes")["modes"]
    assert [m["kind"] for m in obj["modes"]] == [m["kind"] for m in poles]
    assert all("shape" not in m for m in obj["modes"])
    assert obj["modes"][1]["frequency"]["value"] == pytest.approx(poles[1]["frequency"]["value"], rel=1e-12)
    assert obj["modes"][2]["time_constant"]["value"] == pytest.approx(poles[2]["time_constant"]["value"], rel=1e-12)


# --- bad input: one line, exit 2 for usage and units, 1 for the physically impossible -------------

@pytest.mark.parametrize("args, code, fragments", [
    (["modes", "no_such_drive"], 2, ["'no_such_drive' is neither a file nor a built-in drive"]),
    (["modes", "--set", "23.stiffnes=5N*m/rad"], 2, ["Invalid value for --set", "23.stiffnes"]),
    (["modes", "--set", "23.stiffness=5m"], 2, ["Invalid value for --set", "is a length"]),
    (["modes", "--set", "23.stiffness=-5N*m/rad"], 1, ["--set 23.stiffness:", "-5"]),
    (["modes", "--plot", "/no/such/folder/m.png"], 2, ["--plot", "does not exist"]),
    (["response", "--input", "load:9"], 2, ["--input", "'load:9' is not an input of this drive", "load:5"]),
    (["response", "--output", "omega_9"], 2, ["--output", "'omega_9' is not an output of this drive", "omega_5"]),
    (["response", "--from", "1m"], 2, ["--from", "length"]),
    (["response", "--from", "1"], 2, ["--from", "needs a unit"]),
    (["response", "--points", "0"], 2, ["--points", "0"]),
    (["response", "--points", "100001"], 2, ["--points", "100001"]),
    (["response", "--from", "-1Hz"], 1, ["--from: -1 Hz; a frequency must be >= 0 Hz"]),
    (["response", "--from", "100Hz", "--to", "10Hz"], 2, ["Invalid value for --to: 10 Hz; it must be above --from"]),
    (["response", "--from", "500Hz"], 2, ["the default --to, 173.6 Hz", "give --to"]),
    (["response", "--from", "0Hz"], 2, ["--from", "log-spaced"]),
    (["response", "--from", "0Hz", "--spacing", "linear"], 1, ["--from", "rigid-body mode"]),
    (["response", "--points", "1", "--from", "5Hz", "--to", "10Hz"], 2, ["--to", "one point"]),
    (["response", "friswell_5_disks"], 1, ["undamped modes at 81.208, 141.21, 378.95, 536.36 Hz"]),
    (["campbell", "--orders", "1,x"], 2, ["--orders", "1,x"]),
    (["campbell", "--orders", "0,1"], 1, ["--orders: order 0; orders must be > 0"]),
    (["campbell", "--speed-max", "50Hz"], 2, ["--speed-max", "is a frequency"]),
    (["campbell", "--speed-max", "-5rad/s"], 1, ["--speed-max", "must be > 0"]),
    (["campbell", "--speed-min", "500rad/s", "--speed-max", "100rad/s"], 1, ["--speed-min", "below --speed-max"]),
    (["campbell", "--reference", "9"], 2, ["--reference", "'9' is not a node of this drive; did you mean 5, 4, 3? (one of 1, 2, 3, 4, 5)"]),
    (["campbell", "friswell_geared"], 2, ["no induction motor", "give --speed-max"]),
    (["campbell", "linear_axis", "--reference", "carriage", "--speed-max", "1rad/s"], 2,
     ["--reference", "'carriage' translates"]),
])
def test_bad_input_is_one_line(tmp_path, args, code, fragments):
    written = tmp_path / "out.csv"
    result = run(*args, "--csv", written)
    one_error_line(result, code, *fragments)
    assert not written.exists()
    assert list(tmp_path.iterdir()) == []               # no temporary file left either
