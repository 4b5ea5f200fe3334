"""``beltcalc simulate sewing``: the five-mass sewing-machine drive of Mamatova et al. (2016)
through the command line: output shape, physics checked by hand, methods against the exact
solution, sweeps, CSV/JSON/plot outputs, user scene files and every bad input.

Hand computation for the default scene (catalogs/scenes/sewing.toml), SI:
  motor: w0 = 2 pi f / p = 2 pi 50 / 1 = 314.15927 rad/s (synchronous speed)
         M_c = breakdown_factor * rated_torque = 2.5 * 1.2 = 3 N m, S_c = 0.2
  mean loads: M3_0 = 0.1 N m (main shaft), M5_0 = 0.012 N m (bottom shaft); U23 = U34 = U45 = 1
  steady state (every derivative averages to zero over a load period):
    node 5: J5 w5' = U45 T_45 - M5      ->  mean T_45 = M5_0 = 0.012 N m
    node 4: J4 w4' = U34 T_34 - T_45    ->  mean T_34 = 0.012 N m
    node 3: J3 w3' = U23 T_23 - T_34 - M3 -> mean T_23 = M3_0 + M5_0 = 0.112 N m
    node 2: J2 w2' = U12 T_12 - T_23    ->  mean T_12 = 0.112/1.375 = 0.081454545 N m
    node 1: J1 w1' = M_motor - T_12     ->  mean M_motor = (M3_0 + M5_0)/U12 = 0.081454545 N m
  motor (eq. 2, linear): M' = 0 on average -> 2 M_c (w0 - w1)/w0 = S_c M_m
    w1 = w0 (1 - S_c M_m/(2 M_c)) = 314.15927 (1 - 0.2 * 0.081454545/6)
       = 314.15927 (1 - 0.0027151515) = 314.15927 * 0.99728485 = 313.30628 rad/s
    w3 = w1/U12 = 313.30628/1.375 = 227.85911 rad/s   (= steady_speed(p), = the load frequency)
  load period T = 2 pi/227.85911 = 0.027574870 s; the default window 0.5..1 s holds 18.13 periods,
  so a window mean of a sinusoid of amplitude A is off by up to 2 A/(w L) = 2 A/(227.86 * 0.5):
  for T_45 (A = 0.0702 N m) that is 1.2e-3 N m, 10 % of 0.012 N m. A window of exactly 18 periods,
  starting at 1 - 18 * 0.027574870 = 0.50365234 s, removes it.
"""

from __future__ import annotations

import functools
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

from beltcalc.data.catalogs import builtin_dir
from beltcalc.cli.main import cli
from clichecks import edited_copy, ok, one_error_line, read_csv, table_rows
from beltcalc.errors import SimulationError
from beltcalc.sim import core, scipy_methods
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.scenes.sewing import build, steady_speed

PI = math.pi
SEWING_TOML = builtin_dir() / "scenes" / "sewing.toml"

# the scene's values in SI, typed from sewing.toml
PARAMS = dict(
    J1=0.11e-4, J2=0.10e-3, J3=0.29e-3, J4=0.38e-4, J5=0.49e-3,
    C1=260.0, C2=260.0, C3=260.0, C4=260.0, d1=5.4, d2=6.1, d3=5.2, d4=6.0,
    U12=1.375, U23=1.0, U34=1.0, U45=1.0,
    M3_amp=0.175, M3_0=0.1, M5_amp=0.14, M5_0=0.012,
    rated_torque=1.2, breakdown_factor=2.5, breakdown_slip=0.2, supply_frequency=50.0, pole_pairs=1.0,
    load_frequency=0.0, t_end=1.0, samples=10001.0, window=0.5,
    # the eccentric tension roller (issue 15): off by default, its assumed geometry stated in the scene
    roller_eccentricity=0.0, motor_pulley_radius=0.025, roller_radius=0.02, belt_center_distance=0.25,
    roller_pivot_x=0.125, roller_pivot_y=-0.04,
)

# --- the hand values of the module docstring ------------------------------------------------
W0 = 2 * PI * 50 / 1                           # 314.15927 rad/s
M_C = 2.5 * 1.2                                # 3 N m
S_C = 0.2
M_M = (0.1 + 0.012) / 1.375                    # 0.081454545 N m
W1 = W0 * (1 - S_C * M_M / (2 * M_C))          # 313.30628 rad/s
W3 = W1 / 1.375                                # 227.85911 rad/s
PERIOD = 2 * PI / W3                           # 0.027574870 s

# a short run for the checks that do not need the steady state (about 0.05 s each)
SHORT = ("--t-end", "0.3s", "--window", "0.2s", "--samples", "3001")
SHAFT_KEYS = {"speed_mean": "rad/s", "speed_amplitude": "rad/s", "accel_amplitude": "rad/s^2",
              "torque_mean": "N*m", "torque_amplitude": "N*m"}
MOTOR_KEYS = {"speed_mean": "rad/s", "torque_mean": "N*m", "torque_amplitude": "N*m"}


def test_hand_values_of_the_docstring():
    # (8 significant digits: rounding is up to 1.6e-8 relative)
    assert W0 == pytest.approx(314.15927, rel=2e-8)
    assert M_M == pytest.approx(0.081454545, rel=2e-8)
    assert W1 == pytest.approx(313.30628, rel=2e-8)
    assert W3 == pytest.approx(227.85911, rel=2e-8)
    assert PERIOD == pytest.approx(0.027574870, rel=1e-7)
    assert 1 - 18 * PERIOD == pytest.approx(0.50365234, rel=1e-7)
    # the library's steady speed with the scene's values is the same formula
    assert steady_speed(PARAMS) == pytest.approx(W3, rel=1e-12)


def test_params_dict_matches_the_scene_file():
    from beltcalc.sim.scenes import SCENES

    _, resolved = SCENES["sewing"].resolve()
    assert set(resolved) == set(PARAMS)
    for key, value in PARAMS.items():
        assert resolved[key].value == pytest.approx(value, rel=1e-12, abs=1e-300), key


@pytest.fixture(autouse=True)
def _no_debug_from_environment(monkeypatch):
    monkeypatch.delenv("BELTCALC_DEBUG", raising=False)


def run(*args: str):
    return CliRunner().invoke(cli, ["simulate", "sewing", *args])


def js(*args: str) -> dict:
    return json.loads(ok(run(*args, "--json")).stdout)


def value(out: dict, shaft: str, key: str) -> float:
    return out["shafts"][shaft][key]["value"]


# --- default run and its JSON -------------------------------------------------------------------

def test_default_table_names_both_shafts_and_the_exact_method():
    out = ok(run()).stdout
    assert "Sewing-machine drive (Mamatova et al. 2016)" in out
    # the window moves to the latest start >= 0.5 s holding whole load periods: 18 of 0.0275749 s
    assert "main shaft (3), t >= 0.5037 s" in out
    assert "window t >= 0.503652 s: 18 whole load periods" in out
    assert "bottom shaft (5)" in out
    assert "motor (1)" in out
    method = [line for line in out.splitlines() if line.startswith("method:")]
    assert len(method) == 1 and "exact" in method[0], out
    assert "227.86" in out  # main-shaft speed, 5 digits (W3 = 227.85911 by hand)


def test_default_json_keys_and_si_units():
    out = js()
    assert {"method", "reason", "wall_time", "steps", "rhs_calls", "error_estimate", "error_reference",
            "shafts", "motor"} <= set(out)
    assert out["method"] == "exact"
    assert out["wall_time"]["unit"] == "s" and isinstance(out["wall_time"]["value"], float)
    assert out["steps"] == 10000  # 10001 samples: one exact step per output interval
    assert out["error_estimate"]["unit"] == "rad/s"
    assert out["error_reference"] == "exact with another internal step and scaling of A h"
    assert set(out["shafts"]) == {"main", "bottom"}
    for shaft in ("main", "bottom"):
        assert set(out["shafts"][shaft]) == set(SHAFT_KEYS), shaft
        for key, unit in SHAFT_KEYS.items():
            item = out["shafts"][shaft][key]
            assert set(item) == {"value", "unit"}, (shaft, key)
            assert item["unit"] == unit, (shaft, key)
            assert isinstance(item["value"], float), (shaft, key)
    assert set(out["motor"]) == set(MOTOR_KEYS)
    for key, unit in MOTOR_KEYS.items():
        assert out["motor"][key]["unit"] == unit, key
    # the motor's speed is in rad/s (the table shows rpm): w1 = 313.30628 rad/s, not 2992 rpm
    assert out["motor"]["speed_mean"]["value"] == pytest.approx(W1, rel=1e-3)


# --- physics through the CLI -----------------------------------------------------------------

def test_mean_speed_is_the_static_motor_balance():
    # w3 = 227.85911 rad/s, w1 = 313.30628 rad/s (module docstring)
    out = js()
    assert value(out, "main", "speed_mean") == pytest.approx(W3, rel=1e-3)
    assert value(out, "bottom", "speed_mean") == pytest.approx(W3, rel=1e-3)  # U34 = U45 = 1
    assert out["motor"]["speed_mean"]["value"] == pytest.approx(W1, rel=1e-3)
    # the shafts turn together: w1 = U12 w3 over the same window (to the window's ripple)
    assert out["motor"]["speed_mean"]["value"] == pytest.approx(1.375 * value(out, "main", "speed_mean"), rel=1e-5)
    # the run is accurate far beyond these tolerances
    assert out["error_estimate"]["value"] == pytest.approx(0.0, abs=1e-6)


def test_mean_torques_are_the_mean_loads_default_window():
    out = js()
    # T_23 carries both loads: M3_0 + M5_0 = 0.112 N m; the motor (M3_0 + M5_0)/U12 = 0.081454545 N m
    assert value(out, "main", "torque_mean") == pytest.approx(0.112, rel=0.02)
    assert out["motor"]["torque_mean"]["value"] == pytest.approx(0.112 / 1.375, rel=0.02)
    # T_45 = M5_0 = 0.012 N m, to the window bound 2 A/(w L) of the docstring (about 1.2e-3 N m)
    amp = value(out, "bottom", "torque_amplitude")
    assert amp == pytest.approx(0.0702, rel=0.01)
    assert value(out, "bottom", "torque_mean") == pytest.approx(0.012, abs=2 * amp / (W3 * 0.5))


def test_mean_torques_are_the_mean_loads_over_whole_periods():
    # window of exactly 18 load periods: 1 - 18 * 0.027574870 = 0.50365234 s; what is left is the
    # 0.1 ms sampling of the window's ends (about A/4964 = 1.4e-5 N m, 1.2e-3 of 0.012 N m)
    out = js("--window", f"{1 - 18 * PERIOD!r}s")
    assert value(out, "bottom", "torque_mean") == pytest.approx(0.012, rel=3e-3)
    assert value(out, "main", "torque_mean") == pytest.approx(0.112, rel=5e-4)
    assert out["motor"]["torque_mean"]["value"] == pytest.approx(0.112 / 1.375, rel=5e-4)
    assert value(out, "main", "speed_mean") == pytest.approx(W3, rel=1e-5)


def test_csv_series_obey_newton_on_the_bottom_shaft(tmp_path):
    # J5 accel_5 = U45 T_45 - load_5 at every sample; accel_3 = d omega_3/dt (central differences,
    # error (w h)^2/6 = (227.86 * 1e-4)^2/6 = 8.7e-5 of the amplitude 425 rad/s^2 -> 0.04 rad/s^2)
    path = tmp_path / "run.csv"
    ok(run("--csv", str(path)))
    _, s = read_csv(path)
    steady = s["t_s"] >= 0.5
    assert_allclose(0.49e-3 * s["accel_5_rad_per_s2"], s["T_45_N_m"] - s["load_5_N_m"], rtol=1e-6, atol=1e-8)
    grad = np.gradient(s["omega_3_rad_per_s"], s["t_s"])
    assert_allclose(grad[steady][1:-1], s["accel_3_rad_per_s2"][steady][1:-1], atol=0.2)
    # the load is M5_0 + M5_amp sin(w3 t) with w3 the steady speed
    assert_allclose(s["load_5_N_m"], 0.012 + 0.14 * np.sin(W3 * s["t_s"]), atol=1e-9)


# --- --set ------------------------------------------------------------------------------------

def test_set_changes_the_result():
    base = js(*SHORT)
    soft = js(*SHORT, "--set", "C4=190N*m/rad")
    # C4 hardly matters (README: the dampers dominate), but it does change the bottom shaft
    assert value(soft, "bottom", "torque_amplitude") != pytest.approx(value(base, "bottom", "torque_amplitude"),
                                                                      rel=1e-5)
    assert value(soft, "bottom", "speed_amplitude") != pytest.approx(value(base, "bottom", "speed_amplitude"),
                                                                     rel=1e-6)
    # and the units are converted: 190 N m/rad = 0.19 kN m/rad
    kilo = js(*SHORT, "--set", "C4=0.19kN*m/rad")
    for key in SHAFT_KEYS:
        assert value(kilo, "bottom", key) == pytest.approx(value(soft, "bottom", key), rel=1e-12), key


def test_set_mean_load_moves_speed_and_torques():
    # M5_0 = 0.024 N m: M_m = 0.124/1.375 = 0.090181818 N m,
    # w1 = 314.15927 (1 - 0.2 * 0.090181818/6) = 314.15927 * 0.99699394 = 313.21488 rad/s,
    # w3 = 313.21488/1.375 = 227.79264 rad/s (also the new load frequency); period 0.027582916 s,
    # 18 periods from 1 - 0.49649249 = 0.50350751 s
    w3 = W0 * (1 - S_C * (0.124 / 1.375) / (2 * M_C)) / 1.375
    assert w3 == pytest.approx(227.79264, rel=2e-8)
    assert 1 - 18 * 2 * PI / w3 == pytest.approx(0.50350751, rel=2e-8)
    out = js("--set", "M5_0=0.024N*m", "--window", f"{1 - 18 * 2 * PI / w3!r}s")
    assert value(out, "main", "speed_mean") == pytest.approx(w3, rel=1e-5)
    assert value(out, "bottom", "torque_mean") == pytest.approx(0.024, rel=3e-3)
    assert value(out, "main", "torque_mean") == pytest.approx(0.124, rel=5e-4)
    assert out["motor"]["torque_mean"]["value"] == pytest.approx(0.124 / 1.375, rel=5e-4)


@pytest.mark.parametrize("args, code, fragments", [
    pytest.param(["--set", "C4=190"], 2, ["--set", "'C4=190'", "unit"], id="no-unit"),
    pytest.param(["--set", "FOO=1"], 2, ["--set", "'FOO=1'", "'FOO' is not a value here; did you mean ", "(37 names)"],
                 id="unknown-name"),
    pytest.param(["--set", "C4"], 2, ["--set", "NAME=QUANTITY"], id="no-equals"),
    pytest.param(["--set", "C4=5kg"], 2, ["--set", "'C4=5kg'"], id="wrong-dimension"),
    pytest.param(["--set", "J1=-1kg*m^2"], 1, ["-1 kg*m^2", "> 0 kg*m^2"], id="negative-inertia"),
    pytest.param(["--set", "d2=-1N*m*s/rad"], 1, ["-1 N*m*s/rad", ">= 0"], id="negative-damping"),
    pytest.param(["--set", "breakdown_slip=0"], 1, ["--set breakdown_slip", "(0, 1]"], id="zero-slip"),
    pytest.param(["--set", "samples=2.5"], 1, ["--samples", "2.5", "whole number"], id="fractional-samples"),
])
def test_bad_set_is_one_error_line(args, code, fragments, tmp_path):
    out = tmp_path / "out.csv"
    one_error_line(run(*args, "--csv", str(out)), code, *fragments)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("assignment, name", [("J1=-1kg*m^2", "J1"), ("C4=-1N*m/rad", "C4"),
                                              ("supply_frequency=0Hz", "supply_frequency")])
def test_bad_set_names_the_parameter_given(assignment, name):
    line = one_error_line(run("--set", assignment), 1)
    assert name in line


@pytest.mark.parametrize("assignment, name", [("U12=0", "U12"), ("pole_pairs=0", "pole_pairs"),
                                              ("rated_torque=0N*m", "rated_torque"),
                                              ("breakdown_factor=0", "breakdown_factor")])
def test_zero_parameter_is_an_input_error(assignment, name):
    line = one_error_line(run("--set", assignment), 1)
    assert "internal error" not in line
    assert name in line or name.replace("_", "-") in line


# --- methods ---------------------------------------------------------------------------------

@pytest.mark.parametrize("method_args", [
    pytest.param(("--method", "radau", "--rtol", "1e-6", "--atol", "1e-8"), id="radau"),
    pytest.param(("--method", "odeint", "--rtol", "1e-10"), id="odeint"),   # at 1e-8 its torques miss by 1.4e-6
])
def test_methods_agree_with_exact(method_args):
    exact = js(*SHORT)
    other = js(*SHORT, *method_args)
    assert exact["method"] == "exact"
    assert other["method"] == method_args[1]
    assert other["reason"] == "requested"
    assert other["error_reference"] == "exact solution"
    assert other["rhs_calls"] > 0 and exact["rhs_calls"] == 0
    for shaft in ("main", "bottom"):
        for key in ("speed_mean", "speed_amplitude"):
            assert value(other, shaft, key) == pytest.approx(value(exact, shaft, key), rel=1e-3), (shaft, key)


def test_error_estimate_is_the_largest_difference_to_exact(tmp_path):
    # against "exact solution" the estimate is, per speed and per coupling torque, max |x - x_exact|
    # over the samples; the run's figure is the worst relative to its unit's scale (a torque is a
    # stiffness times a difference of angles: its relative error is above the speeds'). The CSV
    # keeps 10 significant digits: 313.3 rad/s to 1e-7 rad/s and 14 N m to 1e-9 N m, far below
    # the ~5e-5 rad/s and ~2e-6 N m differences.
    a, b = tmp_path / "exact.csv", tmp_path / "radau.csv"
    ok(run(*SHORT, "--csv", str(a)))
    out = json.loads(ok(run(*SHORT, "--method", "radau", "--rtol", "1e-6", "--atol", "1e-8", "--json",
                            "--csv", str(b))).stdout)
    _, ex = read_csv(a)
    _, ra = read_csv(b)
    groups = {"rad/s": [f"omega_{k}_rad_per_s" for k in range(1, 6)],
              "N*m": [c for c in ex if c.startswith("T_") and c.endswith("_N_m")]}
    assert len(groups["N*m"]) == 4
    diff = {c: np.max(np.abs(ra[c] - ex[c])) for cols in groups.values() for c in cols}
    scale = {u: max(np.max(np.abs(ra[c])) for c in cols) for u, cols in groups.items()}
    worst = max(diff[c] / scale[u] for u, cols in groups.items() for c in cols)
    assert out["error_relative"]["value"] == pytest.approx(worst, rel=1e-2)
    named = out["error_signal"] + ("_rad_per_s" if out["error_signal"].startswith("omega_") else "_N_m")
    assert out["error_estimate"]["value"] == pytest.approx(diff[named], rel=1e-2)


def test_rk45_short_run():
    # explicit RK45 is held to microsecond steps by the -6e5 1/s eigenvalues: keep the run short
    result = run("--method", "rk45", "--t-end", "0.05s", "--window", "0.025s", "--samples", "51", "--rtol", "1e-3",
                 "--accept-error", "--json")
    assert result.exit_code == 0
    assert result.stderr.startswith("warning: accepted with a large error: error estimate ")
    out = json.loads(result.stdout)
    assert out["method"] == "rk45"
    assert out["error_reference"] == "exact solution"
    assert out["rhs_calls"] > 1000  # stability, not accuracy, sets the step
    # rtol 1e-3 misses the 1e-6 default tolerance: printed only with --accept-error, and marked
    assert out["error_relative"]["value"] > 1e-6
    assert out["warnings"] and out["warnings"][0].startswith("accepted with a large error: error estimate")


def test_rk45_loose_tolerance_fails_without_accept_error():
    result = run("--method", "rk45", "--t-end", "0.05s", "--window", "0.025s", "--samples", "51", "--rtol", "1e-3")
    one_error_line(result, 1, "--error-tol: error estimate ", "above the tolerance 1e-06", "--accept-error")


def test_angle_loads_use_radau():
    # loose tolerances and few samples keep Radau (and its 1/100-tolerance reference) near 1.5 s
    out = js("--angle-loads", "--t-end", "0.5s", "--window", "0.3s", "--samples", "501",
             "--rtol", "1e-6", "--atol", "1e-8")
    assert out["method"] == "radau"
    assert "nonlinear" in out["reason"]
    assert out["error_reference"] == "radau at 1/100 of the tolerances"
    # sin(phi) averages to zero over a revolution as sin(w t) does over a period: the same motor balance,
    # w3 = 227.85911 rad/s, and T_23 still carries M3_0 + M5_0 = 0.112 N m (window of 7.3 revolutions)
    assert value(out, "main", "speed_mean") == pytest.approx(W3, rel=1e-3)
    assert value(out, "main", "torque_mean") == pytest.approx(0.112, rel=0.02)


def test_angle_loads_with_exact_is_an_error(tmp_path):
    out = tmp_path / "out.csv"
    line = one_error_line(run("--angle-loads", "--method", "exact", *SHORT, "--csv", str(out)), 1, "--method")
    assert "radau" in line
    assert list(tmp_path.iterdir()) == []


# --- solver failure ----------------------------------------------------------------------------
# The CLI has no option for the right-hand-side budget (SolverConfig.max_rhs_calls, 5 million):
# rk45 would need several seconds of simulated time, about 80 s of wall time, to reach it.

def test_rk45_budget_failure_at_library_level():
    net = build(PARAMS)
    with pytest.raises(SimulationError) as info:
        simulate(net, 0.05, 51, SolverConfig("rk45", max_rhs_calls=2000))
    text = str(info.value)
    assert "rk45" in text and "t =" in text and "try" in text
    assert "2000 right-hand-side calls" in text
    reached = float(text.split("t = ")[1].split(" s")[0])
    assert 0.0 < reached < 0.05


def test_budget_failure_through_the_cli(monkeypatch, tmp_path):
    # the real budget check, reached through the command: every SolverConfig the command builds gets
    # max_rhs_calls = 2000
    monkeypatch.setattr(core, "SolverConfig", functools.partial(core.SolverConfig, max_rhs_calls=2000))
    out = tmp_path / "out.csv"
    line = one_error_line(run("--method", "rk45", "--t-end", "0.05s", "--window", "0.025s", "--samples", "51",
                              "--csv", str(out)), 1, "rk45", "t =", "try --method exact, radau")
    assert "2000 right-hand-side calls" in line
    assert list(tmp_path.iterdir()) == []


def test_simulation_error_inside_the_command_is_one_line(monkeypatch, tmp_path):
    def boom(network, t, x0, cfg):
        raise SimulationError("method rk45 stopped at t = 0.01 s after 5000000 right-hand-side calls; "
                              "try --method radau")

    monkeypatch.setattr(scipy_methods, "rk45", boom)
    out = tmp_path / "out.csv"
    line = one_error_line(run("--method", "rk45", *SHORT, "--csv", str(out)), 1)
    assert line == ("Error: method rk45 stopped at t = 0.01 s after 5000000 right-hand-side calls; "
                    "try --method radau")
    assert list(tmp_path.iterdir()) == []


# --- sweep -------------------------------------------------------------------------------------

def test_sweep_table_has_one_row_per_point():
    out = ok(run(*SHORT, "--sweep", "C4=50N*m/rad:310N*m/rad:3")).stdout
    assert "sweep of C4" in out
    rows = table_rows(out, "sweep of C4")
    assert len(rows) == 3
    assert [float(r[0]) for r in rows] == pytest.approx([50.0, 180.0, 310.0], rel=1e-12)


def test_sweep_json_rows_equal_single_runs():
    out = js(*SHORT, "--sweep", "C4=50N*m/rad:310N*m/rad:3")
    assert out["study"] == "sweep"
    assert out["parameters"] == [{"name": "C4", "unit": "N*m/rad", "values": pytest.approx([50.0, 180.0, 310.0])}]
    assert out["columns"][0] == {"key": "C4_N_m_per_rad", "label": "C4", "unit": "N*m/rad"}
    label = {c["key"]: (c["label"], c["unit"]) for c in out["columns"]}
    assert label["bottom_torque_amplitude_N_m"] == ("bottom shaft (5): transmitted torque, amplitude", "N*m")
    cols = [c["key"] for c in out["columns"]]
    assert "main_speed_amplitude_rad_per_s" in cols
    assert len(out["rows"]) == 3
    assert all(len(r) == len(cols) for r in out["rows"])
    rows = [dict(zip(cols, r)) for r in out["rows"]]
    assert_allclose([r["C4_N_m_per_rad"] for r in rows], [50.0, 180.0, 310.0], rtol=1e-12)
    # the middle point is the run with --set C4=180N*m/rad
    single = js(*SHORT, "--set", "C4=180N*m/rad")
    for shaft in ("main", "bottom"):
        for key, col in (("speed_amplitude", "speed_amplitude_rad_per_s"),
                         ("accel_amplitude", "accel_amplitude_rad_per_s2"),
                         ("torque_amplitude", "torque_amplitude_N_m"), ("torque_mean", "torque_mean_N_m")):
            assert rows[1][f"{shaft}_{col}"] == pytest.approx(value(single, shaft, key), rel=1e-10), (shaft, key)
    assert rows[1]["main_speed_mean_rad_per_s"] == pytest.approx(value(single, "main", "speed_mean"), rel=1e-12)


def test_sweep_csv_is_the_sweep_table(tmp_path):
    path = tmp_path / "sweep.csv"
    ok(run(*SHORT, "--sweep", "C4=50N*m/rad:310N*m/rad:3", "--csv", str(path)))
    header, s = read_csv(path)
    assert header[0] == "C4_N_m_per_rad" and "bottom_speed_amplitude_rad_per_s" in header
    assert_allclose(s["C4_N_m_per_rad"], [50.0, 180.0, 310.0], rtol=1e-12)
    assert [p.name for p in tmp_path.iterdir()] == ["sweep.csv"]


@pytest.mark.parametrize("text, fragments", [
    pytest.param("C4=50:310", ["NAME=START:STOP:N"], id="no-count"),
    pytest.param("FOO=1:2:3", ["'FOO' is not a value here; did you mean ", "(37 names)"], id="unknown-name"),
    pytest.param("C4=a:b:3", ["'C4=a"], id="not-numbers"),
    pytest.param("C4=50:310:x", ["whole number"], id="count-not-a-number"),
    pytest.param("C4=50:310:0", ["1..10000"], id="zero-points"),
])
def test_bad_sweep_is_a_usage_error(text, fragments, tmp_path):
    out = tmp_path / "out.csv"
    one_error_line(run("--sweep", text, "--csv", str(out)), 2, "--sweep", *fragments)
    assert list(tmp_path.iterdir()) == []


def test_bad_sweep_name_quotes_the_users_text():
    one_error_line(run("--sweep", "FOO=1:2:3"), 2, "--sweep", "FOO=1:2:3")


# --- CSV -----------------------------------------------------------------------------------------

def test_csv_time_series(tmp_path):
    path = tmp_path / "run.csv"
    out = json.loads(ok(run(*SHORT, "--csv", str(path), "--json")).stdout)
    text = path.read_text()
    header = text.splitlines()[0]
    assert header.startswith("t_s,phi_1_rad,")
    for name in ("omega_3_rad_per_s", "omega_5_rad_per_s", "accel_3_rad_per_s2", "T_23_N_m", "T_45_N_m",
                 "M_motor_N_m", "load_3_N_m"):
        assert name in header.split(","), name
    assert len(text.splitlines()) == 3001 + 1
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]  # no temporary file left
    _, s = read_csv(path)
    assert s["t_s"][0] == pytest.approx(0.0, abs=1e-15)
    assert s["t_s"][-1] == pytest.approx(0.3, rel=1e-12)
    # the JSON summary is the CSV's window: the latest start >= 0.2 s holding whole load periods
    from beltcalc.sim.scenes.sewing import whole_period_window

    start, periods = whole_period_window(0.3, 0.2, W3)
    assert periods == 3
    w = s["t_s"] >= start - 1e-12
    mean = np.trapezoid(s["omega_3_rad_per_s"][w], s["t_s"][w]) / (s["t_s"][w][-1] - s["t_s"][w][0])
    assert out["shafts"]["main"]["speed_mean"]["value"] == pytest.approx(mean, rel=1e-9)   # the trapezoid rule
    t45 = s["T_45_N_m"][w]
    assert value(out, "bottom", "torque_amplitude") == pytest.approx((t45.max() - t45.min()) / 2, rel=1e-8)


def test_dt_sets_the_number_of_samples(tmp_path):
    # 0.1 s / 0.5 ms = 200 steps -> 201 samples -> 202 lines with the header
    path = tmp_path / "run.csv"
    ok(run("--dt", "0.5ms", "--t-end", "0.1s", "--window", "0.05s", "--csv", str(path)))
    lines = path.read_text().splitlines()
    assert len(lines) == 201 + 1
    _, s = read_csv(path)
    assert_allclose(np.diff(s["t_s"]), 5e-4, rtol=1e-6)


# --- modes ---------------------------------------------------------------------------------------

def test_modes_table_and_json():
    # every pole (issue 11): the motor's angle (rigid body), one oscillatory mode and 8 real
    # poles with time constants from 23.3 ms down to 1.65 us
    expected = build(PARAMS).modes()
    assert len(expected) == 1
    out = ok(run(*SHORT, "--modes")).stdout
    rows = table_rows(out, "modes of the linear network")
    assert [r[1] for r in rows] == ["rigid body", "mode 1"] + ["real"] * 8
    assert float(rows[1][2]) == pytest.approx(expected[0][0], rel=1e-3)  # printed to 4 digits
    assert (rows[2][5], rows[-1][5]) == ("23.34 ms", "1.653 us")
    modes = js(*SHORT, "--modes")["modes"]
    assert [m["kind"] for m in modes] == ["rigid", "oscillatory"] + ["real"] * 8
    oscillatory = [m for m in modes if m["kind"] == "oscillatory"]
    for m, (f, z) in zip(oscillatory, expected):
        assert m["frequency"]["unit"] == "Hz" and m["damping_ratio"]["unit"] == "1"
        assert m["frequency"]["value"] == pytest.approx(f, rel=1e-9)
        assert m["damping_ratio"]["value"] == pytest.approx(z, rel=1e-9)
    # README: one oscillatory mode, 17.4 Hz with damping ratio 0.30
    assert oscillatory[0]["frequency"]["value"] == pytest.approx(17.4, rel=5e-3)
    assert oscillatory[0]["damping_ratio"]["value"] == pytest.approx(0.30, rel=0.02)
    tau = [m["time_constant"] for m in modes if m["kind"] == "real"]
    assert {t["unit"] for t in tau} == {"s"}
    assert [tau[0]["value"], tau[-1]["value"]] == pytest.approx([23.343e-3, 1.6532e-6], rel=1e-4)


def test_no_modes_key_without_the_flag():
    assert "modes" not in js(*SHORT)


# --- time options ------------------------------------------------------------------------------

@pytest.mark.parametrize("args, code, fragments", [
    pytest.param(["--window", "2s"], 1, ["--window", "2 s"], id="window-after-end"),
    pytest.param(["--window", "-0.1s"], 1, ["--window"], id="window-negative"),
    pytest.param(["--t-end", "5m"], 2, ["--t-end", "'5m'"], id="t-end-length"),
    pytest.param(["--dt", "5kg"], 2, ["--dt", "'5kg'"], id="dt-mass"),
    pytest.param(["--window", "abc"], 2, ["--window"], id="window-not-a-quantity"),
    pytest.param(["--samples", "1"], 2, ["--samples"], id="one-sample"),
    pytest.param(["--method", "euler"], 2, ["--method", "'euler'"], id="unknown-method"),
])
def test_bad_time_options(args, code, fragments, tmp_path):
    out = tmp_path / "out.csv"
    one_error_line(run(*args, "--csv", str(out)), code, *fragments)
    assert list(tmp_path.iterdir()) == []


def test_negative_t_end_names_t_end():
    one_error_line(run("--t-end", "-1s"), 1, "--t-end")


def test_zero_dt_names_dt():
    one_error_line(run("--dt", "0s", "--t-end", "0.1s", "--window", "0.05s"), 1, "--dt")


# --- scene files ---------------------------------------------------------------------------------

def write_scene(tmp_path: Path, old: str, new: str) -> Path:
    return edited_copy(SEWING_TOML, tmp_path, old, new)


def test_user_scene_with_a_heavier_bottom_shaft(tmp_path):
    path = write_scene(tmp_path, 'J5 = { value = "0.49e-3 kg*m^2"', 'J5 = { value = "0.98e-3 kg*m^2"')
    base = js()
    heavy = js("--scene", str(path))
    # rigid train at the main shaft: J1 U12^2 + J2 + J3 + J4 + J5 = 2.08e-5 + 1e-4 + 2.9e-4 + 3.8e-5 + 4.9e-4
    # = 9.388e-4 kg m^2 -> 1.4288e-3 with J5 doubled: the ripple falls by about a third or more
    b0, b1 = value(base, "bottom", "speed_amplitude"), value(heavy, "bottom", "speed_amplitude")
    assert b1 != pytest.approx(b0, rel=0.2)
    assert b1 < b0
    # the same as --set on the built-in scene
    same = js("--set", "J5=0.98e-3kg*m^2")
    for key in SHAFT_KEYS:
        assert value(heavy, "bottom", key) == pytest.approx(value(same, "bottom", key), rel=1e-12), key
    # the mean speed does not depend on inertia
    assert value(heavy, "main", "speed_mean") == pytest.approx(W3, rel=1e-3)


def test_user_scene_unknown_parameter(tmp_path):
    path = write_scene(tmp_path, "[parameters]\n", '[parameters]\nfoo = { value = "1", why = "test" }\n')
    line = one_error_line(run("--scene", str(path)), 1, str(path), "parameters.foo")
    assert "not a parameter" in line


def test_user_scene_bad_value(tmp_path):
    path = write_scene(tmp_path, 'C4 = { value = "260 N*m/rad"', 'C4 = { value = "260 kg"')
    one_error_line(run("--scene", str(path)), 1, str(path), "parameters.C4")


def test_unknown_scene_is_a_usage_error(tmp_path):
    out = tmp_path / "out.csv"
    one_error_line(run("--scene", "nosuch", "--csv", str(out)), 2, "--scene", "'nosuch'", "sewing")
    assert list(tmp_path.iterdir()) == []


# --- plot ----------------------------------------------------------------------------------------

def test_plot_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "run.png"
    ok(run(*SHORT, "--plot", str(path)))
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    sweep = tmp_path / "sweep.png"
    ok(run(*SHORT, "--sweep", "C4=50N*m/rad:310N*m/rad:3", "--plot", str(sweep)))
    assert sweep.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.png", "sweep.png"]


def test_plot_without_matplotlib_says_what_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    path = tmp_path / "run.png"
    one_error_line(run(*SHORT, "--plot", str(path), "--csv", str(tmp_path / "run.csv")), 1,
                   "--plot", "beltcalc[plot]")
    assert list(tmp_path.iterdir()) == []


def test_steady_state_flag_skips_the_time_simulation(tmp_path):
    # the exact periodic steady state alone: W3 by hand, the static balance of the torques,
    # and a sweep's table of the exact amplitudes
    out = js("--steady-state-only")
    steady = out["steady_state"]
    assert steady["main_shaft"]["speed_mean"]["value"] == pytest.approx(W3, rel=1e-8)
    assert steady["main_shaft"]["torque_mean"]["value"] == pytest.approx(0.112, rel=1e-8)
    assert steady["bottom_shaft"]["torque_mean"]["value"] == pytest.approx(0.012, rel=1e-8)
    assert out["method"] == "steady state" and "shafts" not in out
    path = tmp_path / "steady.csv"
    ok(run("--steady-state-only", "--csv", str(path)))
    assert path.read_text().splitlines()[0] == "section,key,value,unit"
    sweep = json.loads(ok(run("--steady-state-only", "--sweep", "C4=50N*m/rad:310N*m/rad:3", "--json")).stdout)
    col = [c["key"] for c in sweep["columns"]].index("steady_bottom_speed_amplitude_rad_per_s")
    assert [r[col] for r in sweep["rows"]] == pytest.approx([1.8719, 1.8723, 1.8726], abs=2e-4)
    one_error_line(run("--steady-state-only", "--plot", str(tmp_path / "x.png")), 2, "--plot", "--steady-state-only")
    one_error_line(run("--steady-state-only", "--angle-loads"), 1, "no exact steady state")


@pytest.mark.parametrize("setting", ["C1=1e308 N*m/rad", "J1=1e-320 kg*m^2"])
def test_equations_beyond_the_float_range_are_refused(setting, tmp_path):
    # a stiffness over an inertia beyond 1e308 (found by the fuzz test): one line, exit 1, no file
    out = tmp_path / "out.csv"
    line = one_error_line(run(*SHORT, "--set", setting, "--csv", str(out)), 1, "overflow", "check the values")
    assert "internal error" not in line
    assert list(tmp_path.iterdir()) == []


def test_an_input_too_fast_to_step_is_refused_at_once(tmp_path):
    # found by the fuzz benchmark: Radau spent its whole budget (minutes) on a load at 1e82 rpm.
    # 1e9 rad/s over 0.3 s is 4.8e7 periods: more than 4 calls each exceeds the 5e6 allowed
    out = tmp_path / "out.csv"
    line = one_error_line(run(*SHORT, "--method", "radau", "--set", "load_frequency=1e9rad/s", "--csv", str(out)),
                          1, "method radau", "oscillates 4.77e+07 times", "try --method exact")
    assert "5000000 right-hand-side calls" in line
    assert list(tmp_path.iterdir()) == []
    # the exact method takes the same input exactly (the steady state's window may not hold a period)
    assert run(*SHORT, "--set", "load_frequency=1e9rad/s").exit_code == 0


def test_an_input_phase_beyond_a_float_is_refused():
    line = one_error_line(run(*SHORT, "--set", "load_frequency=1e15rad/s"), 1, "3e+14 rad over the run",
                          "lower its frequency or --t-end")
    assert "internal error" not in line
