"""``beltcalc simulate roller-table``: the chain-driven roller table of Rusek & Popenda through the
command line: tables, JSON keys and units, the CSV time series, sweeps, methods and bad input.

Hand values for the default scene (catalogs/scenes/roller_table.toml; derivation in
tests/test_roller_table.py): ratio i = 5 * 5 * 19 / 19 = 25; mean motor torque
M_m = 3 rollers * 40 N m / 25 = 4.8 N m; motor speed w0 (1 - S_c M_m / (2 M_c))
= 157.07963 (1 - 0.2 * 4.8 / 33.58) = 152.58897 rad/s; rollers 6.1035588 rad/s; each journal
carries the roller's 40 N m, each tube the far end's half (centred element), 20 N m.

Short runs stop at 2.5 s with the element landing at 2 s (the end of the inverter ramp): a run
that ends before the ramp does is not used here (see test_roller_table.py,
test_a_load_after_the_end_of_the_run_does_not_act).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

from beltcalc.cli.main import cli
from clichecks import ok, one_error_line, read_csv, table_rows

M_M = 3 * 40.0 / 25                                   # 4.8 N m
W_ROLLERS = 157.0796327 * (1 - 0.2 * M_M / (2 * 2.3 * 7.3)) / 25   # 6.1035588 rad/s
STRANDS = ["drive-sprocket1", "sprocket1-idler1", "idler1-sprocket2", "sprocket2-idler2", "idler2-sprocket3",
           "sprocket3-drive"]
ROLLER_KEYS = {"speed_mean": "rad/s", "speed_amplitude": "rad/s", "torque_drive_end_mean": "N*m",
               "torque_drive_end_amplitude": "N*m", "torque_far_end_mean": "N*m", "torque_far_end_amplitude": "N*m"}
STRAND_KEYS = {"force_min": "N", "force_max": "N", "slack_time": "s", "safety": "1"}
MOTOR_KEYS = {"speed_mean": "rad/s", "torque_mean": "N*m", "torque_amplitude": "N*m", "torque_peak": "N*m",
              "startup_time": "s", "steady_speed_rollers": "rad/s"}
SHORT = ("--t-end", "2.5s", "--window", "2.2s", "--samples", "501", "--set", "load_start=2s")


@pytest.fixture(autouse=True)
def _no_debug_from_environment(monkeypatch):
    monkeypatch.delenv("BELTCALC_DEBUG", raising=False)


def run(*args: str):
    return CliRunner().invoke(cli, ["simulate", "roller-table", *args])


def js(*args: str) -> dict:
    return json.loads(ok(run(*args, "--json")).stdout)


@pytest.fixture(scope="module")
def default_json() -> dict:
    return json.loads(ok(CliRunner().invoke(cli, ["simulate", "roller-table", "--json"])).stdout)


# --- the default run ---------------------------------------------------------------------------

def test_default_run_prints_motor_rollers_and_strands():
    out = ok(run()).stdout
    assert "Roller table with chain transmission (Rusek & Popenda)" in out
    assert "motor, t >= 5.5 s" in out
    method = [line for line in out.splitlines() if line.startswith("method:")]
    assert len(method) == 1 and "exact" in method[0], out
    rollers = table_rows(out, "rollers, t >= 5.5 s")
    assert [r[0] for r in rollers] == ["1", "2", "3"]
    # speed mean to 5 digits (6.1036 rad/s by hand), journal 40 N m, tube 20 N m
    for r in rollers:
        assert float(r[1]) == pytest.approx(W_ROLLERS, rel=1e-4), r
        assert float(r[3]) == pytest.approx(40.0, rel=1e-3), r
        assert float(r[5]) == pytest.approx(20.0, rel=1e-3), r
    strands = table_rows(out, "chain strands, whole run")
    assert [r[0] for r in strands] == STRANDS
    # the motor's mean torque, printed to 4 digits
    assert "4.800" in out


def test_default_json_keys_and_units(default_json):
    out = default_json
    assert {"method", "reason", "wall_time", "steps", "rhs_calls", "error_estimate", "error_reference", "events",
            "rollers", "strands", "motor"} <= set(out)
    assert out["method"] == "exact"
    assert out["wall_time"]["unit"] == "s" and out["wall_time"]["value"] > 0
    # the estimate is that of the worst reported figure (issue 26): a speed, a torque or a force
    assert out["error_estimate"]["unit"] in ("rad/s", "N*m", "N")
    assert out["error_signal"].split(" of ")[0] in ("mean", "min", "max")
    assert isinstance(out["events"], int) and out["events"] >= 1   # the return strand goes slack
    assert set(out["rollers"]) == {"1", "2", "3"}
    for k, roller in out["rollers"].items():
        assert {key: item["unit"] for key, item in roller.items()} == ROLLER_KEYS, k
        assert all(isinstance(item["value"], float) for item in roller.values()), k
    assert list(out["strands"]) == STRANDS
    for name, strand in out["strands"].items():
        assert {key: item["unit"] for key, item in strand.items()} == STRAND_KEYS, name
    assert {key: item["unit"] for key, item in out["motor"].items()} == MOTOR_KEYS


def test_default_json_values_are_the_static_balance(default_json):
    out = default_json
    motor = {k: v["value"] for k, v in out["motor"].items()}
    assert motor["torque_mean"] == pytest.approx(M_M, rel=1e-3)                       # 3 * 40 / 25
    assert motor["speed_mean"] == pytest.approx(25 * W_ROLLERS, rel=1e-4)             # 152.589 rad/s
    assert motor["steady_speed_rollers"] == pytest.approx(W_ROLLERS, rel=1e-7)
    assert motor["steady_speed_rollers"] == pytest.approx(6.1035588, rel=1e-7)
    assert motor["torque_peak"] >= motor["torque_mean"] + motor["torque_amplitude"]
    # the ramp takes 2 s, the element lands at 3 s: roller 1 settles in between
    assert 1.5 < motor["startup_time"] < 3.0
    for k, roller in out["rollers"].items():
        assert roller["speed_mean"]["value"] == pytest.approx(W_ROLLERS, rel=1e-4), k
        assert roller["torque_drive_end_mean"]["value"] == pytest.approx(40.0, rel=1e-3), k
        assert roller["torque_far_end_mean"]["value"] == pytest.approx(20.0, rel=1e-3), k
    drive = out["strands"]["drive-sprocket1"]
    # 10B-1 breaking load 22.2 kN over the largest force; the force starts at the 300 N pretension
    assert drive["safety"]["value"] == pytest.approx(22200.0 / drive["force_max"]["value"], rel=1e-12)
    assert 0.0 < drive["force_min"]["value"] <= 300.0
    assert drive["slack_time"]["value"] == 0.0
    # the return strand goes slack when the load lands (3 s) and stays slack to the end (7 s)
    assert out["strands"]["sprocket3-drive"]["slack_time"]["value"] == pytest.approx(4.0, abs=0.1)
    assert out["error_estimate"]["value"] == pytest.approx(0.0, abs=1e-6)


# --- CSV -----------------------------------------------------------------------------------------

def test_csv_time_series(tmp_path):
    path = tmp_path / "run.csv"
    out = json.loads(ok(run(*SHORT, "--csv", str(path), "--json")).stdout)
    header = path.read_text().splitlines()[0].split(",")
    assert header[0] == "t_s"
    assert path.read_text().startswith("t_s,")
    for name in STRANDS:
        assert f"F_{name}_N" in header, name
    for name in ("omega_end1a_rad_per_s", "M_motor_N_m", "T_shaft1_N_m", "T_tube3_N_m", "load_end2b_N_m"):
        assert name in header, name
    assert len(path.read_text().splitlines()) == 501 + 1
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]     # no temporary file left
    _, s = read_csv(path)
    assert s["t_s"][-1] == pytest.approx(2.5, rel=1e-12)
    dt = 2.5 / 500
    for name in STRANDS:
        force = s[f"F_{name}_N"]
        assert force.min() >= 0.0, name                              # tension only
        # the JSON's whole-run maximum is the exact one (off the exact solution, not the samples):
        # at least the CSV's largest sample, at most that plus the largest change between samples
        top = out["strands"][name]["force_max"]["value"]
        assert force.max() * (1 - 1e-9) <= top <= force.max() + np.max(np.abs(np.diff(force))), name
        # the time slack is the zero-force samples' share, to the samples' resolution
        assert out["strands"][name]["slack_time"]["value"] == pytest.approx(np.sum(force[1:] == 0.0) * dt,
                                                                            abs=2 * dt), name
    # the load lands at 2 s: 40 N m split 20/20 between the roller's ends
    assert_allclose(s["load_end2b_N_m"][s["t_s"] < 2.0 - 1e-9], 0.0, atol=1e-12)
    assert_allclose(s["load_end2b_N_m"][s["t_s"] >= 2.0], 20.0, rtol=1e-12)


def test_csv_is_not_written_on_a_bad_run(tmp_path):
    path = tmp_path / "run.csv"
    one_error_line(run(*SHORT, "--set", "rollers=0", "--csv", str(path)), 1, "--set rollers")
    assert list(tmp_path.iterdir()) == []


# --- bad input -----------------------------------------------------------------------------------

@pytest.mark.parametrize("assignment, code, fragments", [
    pytest.param("rollers=0", 1, ["--set rollers", "0 rollers", "1..200"], id="zero-rollers"),
    pytest.param("rollers=2.5", 1, ["--set rollers", "whole number"], id="fractional-rollers"),
    pytest.param("routing=zigzag", 1, ["--set routing", "'zigzag'", "serpentine", "loops"], id="unknown-routing"),
    # the element (800 mm) fits on the 1200 mm roller with a_x in [0, 0.4] m
    pytest.param("element_offset=2m", 1, ["--set element_offset", "2 m", "0.4"], id="element-off-the-roller"),
    pytest.param("pretension=-5N", 1, ["--set pretension", "-5 N"], id="negative-pretension"),
    pytest.param("nope=1", 2, ["--set", "'nope=1'", "'nope' is not a value here; did you mean ", " names)"],
                 id="unknown-name"),
    pytest.param("pretension=5kg", 2, ["--set", "'pretension=5kg'"], id="wrong-dimension"),
])
def test_bad_set_is_one_error_line(assignment, code, fragments, tmp_path):
    path = tmp_path / "run.csv"
    one_error_line(run("--set", assignment, "--csv", str(path)), code, *fragments)
    assert list(tmp_path.iterdir()) == []


def test_element_against_the_far_end_runs():
    # a_x = L - a = 1.2 m - 0.8 m = 0.4 m puts the element against the far end (w_p = 2, eq. 16):
    # allowed, the far end then carries (2 * 0.4 + 0.8) / 2.4 = 2/3 of the load
    out = js(*SHORT, "--set", "element_offset=400mm")
    assert set(out["rollers"]) == {"1", "2", "3"}


def test_chattering_chain_stops_at_max_events(tmp_path):
    # one roller under a +-40 N m pulsation at 30 rad/s from the start: the loop's strands switch
    # again and again (24 times in 2.5 s); --max-events 5 stops the run with one line
    path = tmp_path / "run.csv"
    line = one_error_line(run("--t-end", "2.5s", "--window", "2s", "--samples", "2501", "--set", "rollers=1",
                              "--set", "load_start=0s", "--set", "load_amplitude=40N*m",
                              "--set", "load_frequency=30rad/s", "--max-events", "5", "--csv", str(path)), 1,
                          "5 strand events", "--max-events", "exact")
    assert "strand drive-sprocket1 " in line or "strand sprocket1-drive " in line
    assert list(tmp_path.iterdir()) == []


# --- other shapes --------------------------------------------------------------------------------

def test_rollers_and_routing_shape_the_report():
    one = js(*SHORT, "--set", "rollers=1")
    assert set(one["rollers"]) == {"1"}
    assert list(one["strands"]) == ["drive-sprocket1", "sprocket1-drive"]
    # M_m = 40 / 25 = 1.6 N m: the steady balance the command reports for one roller
    assert one["motor"]["steady_speed_rollers"]["value"] == pytest.approx(
        157.0796327 * (1 - 0.2 * 1.6 / 33.58) / 25, rel=1e-7)
    loops = js(*SHORT, "--set", "routing=loops")
    assert list(loops["strands"]) == ["drive-sprocket1", "sprocket1-drive", "sprocket1-sprocket2",
                                      "sprocket2-sprocket1", "sprocket2-sprocket3", "sprocket3-sprocket2"]


# --- sweep ---------------------------------------------------------------------------------------

def test_sweep_pretension_json():
    out = js(*SHORT, "--sweep", "pretension=100N:500N:3")
    assert out["parameters"][0]["name"] == "pretension" and out["parameters"][0]["unit"] == "N"
    cols = [c["key"] for c in out["columns"]]
    assert cols[0] == "pretension_N"
    assert len(cols) == len(set(cols))
    for col in ("motor_torque_mean_N_m", "motor_speed_mean_rad_per_s", "1_speed_mean_rad_per_s",
                "3_torque_far_end_mean_N_m", "drive-sprocket1_force_max_N", "sprocket3-drive_slack_time_s",
                "drive-sprocket1_safety"):
        assert col in cols, col
    assert len(out["rows"]) == 3
    assert all(len(r) == len(cols) for r in out["rows"])
    rows = [dict(zip(cols, r)) for r in out["rows"]]
    assert_allclose([r["pretension_N"] for r in rows], [100.0, 300.0, 500.0], rtol=1e-12)
    # every strand starts at its pretension and the drive strand only tightens from there
    assert_allclose([r["drive-sprocket1_force_min_N"] for r in rows], [100.0, 300.0, 500.0], rtol=1e-9)
    # the middle point is the run with --set pretension=300N: the same inputs through the same
    # code, equal to rounding, not bit for bit (the same products on arrays at other addresses
    # may take other BLAS paths: a sewing sweep's point differs from its single run by 7e-12
    # under OpenBLAS Haswell, tests/test_scenes_api.py); to 1e-9, the method's error (the run's
    # estimate is 1e-10 of its scale); the neighbouring points differ by 1e-3 and more
    single = js(*SHORT, "--set", "pretension=300N")
    assert rows[1]["motor_torque_mean_N_m"] == pytest.approx(single["motor"]["torque_mean"]["value"], rel=1e-9)
    assert rows[1]["drive-sprocket1_force_max_N"] == pytest.approx(
        single["strands"]["drive-sprocket1"]["force_max"]["value"], rel=1e-9)
    assert rows[1]["2_speed_mean_rad_per_s"] == pytest.approx(single["rollers"]["2"]["speed_mean"]["value"],
                                                              rel=1e-9)


# --- methods -------------------------------------------------------------------------------------

def test_radau_agrees_with_exact():
    exact = js(*SHORT)
    radau = js(*SHORT, "--method", "radau")
    assert exact["method"] == "exact" and radau["method"] == "radau"
    assert radau["reason"] == "requested"
    assert radau["error_reference"] == "exact solution"
    assert radau["rhs_calls"] > 0 and exact["rhs_calls"] == 0
    assert radau["events"] == exact["events"]
    # exact: the window mean is the exact integral; radau: the trapezoid over its 501 samples
    # (dt = 5 ms, 0.5 rad of the rollers' 100 rad/s oscillation: measured 2.7e-5 apart)
    assert radau["motor"]["speed_mean"]["value"] == pytest.approx(exact["motor"]["speed_mean"]["value"], rel=1e-4)
    for k in ("1", "3"):
        assert radau["rollers"][k]["speed_mean"]["value"] == pytest.approx(
            exact["rollers"][k]["speed_mean"]["value"], rel=1e-4), k
    # radau's own report of its distance to exact, at rtol 1e-8 on ~150 rad/s
    assert radau["error_estimate"]["value"] == pytest.approx(0.0, abs=1e-3)


def test_chain_from_the_catalog_on_the_command_line():
    # issue 13: --set chain=NAME takes pitch, mass and breaking load from catalogs/chains.toml
    listed = json.loads(ok(run("--list-params", "--json")).stdout)["parameters"]
    assert listed["chain"]["text"] == "10B-1"
    assert listed["chain_pitch"] == {"value": pytest.approx(0.015875, rel=1e-15), "unit": "m", "text": "0.015875 m",
                                     "origin": "catalog: 10B-1 (chains.toml)", "help": "chain pitch"}
    res = run("--set", "chain=06B-1")
    assert res.exit_code == 1
    assert res.output.strip() == "Error: --set chain_mass: 06B-1 has no mass in chains.toml; give it"
    res = run("--set", "chain=10X-1")
    assert res.exit_code == 2 and res.output.startswith("Error: --set chain: unknown chain '10X-1'")
    assert len(res.output.strip().splitlines()) == 1
