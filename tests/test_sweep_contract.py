"""The sweep's output contract (issue 12): one schema with the swept parameter's unit, columns
with labels and units, rows aligned by key when a run's layout changes, each warning once with
the points where it was given, --strict over every point; inputs echoed with their origin;
"wrote FILE" on stderr; a run that ends before the load lands says so."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import ok, read_csv, warnings

ROLLERS = ("simulate", "roller-table", "--t-end", "1.2s", "--window", "1s", "--samples", "301",
           "--set", "load_start=0.8s")


def run(*args: str):
    return CliRunner().invoke(cli, list(args))


def test_a_sweep_that_changes_the_layout_keeps_rows_aligned_by_key():
    # 2 and 3 rollers: the 3-roller run has columns the 2-roller run lacks (None there), and
    # every value sits under its own key (the single runs give the same numbers)
    out = json.loads(ok(run(*ROLLERS, "--sweep", "rollers=2:3:2", "--json")).stdout)
    keys = [c["key"] for c in out["columns"]]
    assert out["parameters"] == [{"name": "rollers", "unit": "1", "values": [2.0, 3.0]}]
    assert keys[0] == "rollers" and len(keys) == len(set(keys))
    rows = [dict(zip(keys, r)) for r in out["rows"]]
    assert rows[0]["3_speed_mean_rad_per_s"] is None
    for k, n in enumerate((2, 3)):
        single = json.loads(ok(run(*ROLLERS, "--set", f"rollers={n}", "--json")).stdout)
        assert rows[k]["motor_torque_peak_N_m"] == pytest.approx(single["motor"]["torque_peak"]["value"], rel=1e-12)
        assert rows[k][f"{n}_speed_mean_rad_per_s"] == pytest.approx(
            single["rollers"][str(n)]["speed_mean"]["value"], rel=1e-12)


def test_sweep_warnings_once_with_their_points_and_strict_over_every_point(tmp_path):
    # load_start 0.5 s lands before roller 1 settles (no start-up time); 1.0 s after it
    args = ("simulate", "roller-table", "--set", "rollers=2", "--t-end", "3s", "--window", "2.7s",
            "--samples", "301", "--sweep", "load_start=0.05s:2.5s:2")
    result = ok(run(*args, "--json"))
    out = json.loads(result.stdout)
    said = warnings(result)
    assert out["warnings"] == said
    settle = [w for w in said if "did not settle" in w]
    assert len(settle) == 1 and "(at 1 of 2 points: load_start = 0.05 s)" in settle[0]
    assert "load_start" in settle[0] and "`" not in settle[0]
    keys = [c["key"] for c in out["columns"]]
    startup = [r[keys.index("motor_startup_time_s")] for r in out["rows"]]
    single = json.loads(ok(run(*args[:-2], "--set", "load_start=2.5s", "--json")).stdout)
    assert startup[0] is None and startup[1] == pytest.approx(single["motor"]["startup_time"]["value"], rel=1e-12)
    assert startup[1] == pytest.approx(1.99, abs=0.01)   # the default run's 1.988 s, on this coarser grid
    # a failing check at any point fails the sweep with --strict, and no file is written
    failing = run(*args, "--set", "chain_breaking_load=100N", "--strict", "--csv", str(tmp_path / "s.csv"))
    assert failing.exit_code == 1
    assert failing.stderr.splitlines()[-1].startswith("Error: ") and "--strict" in failing.stderr
    assert list(tmp_path.iterdir()) == []


def test_json_echoes_every_input_with_its_origin():
    out = json.loads(ok(run("simulate", "sewing", "--set", "C4=0.2kN*m/rad", "--t-end", "0.3s", "--window",
                            "0.2s", "--json")).stdout)
    inputs = out["inputs"]
    assert inputs["C4"] == {"value": pytest.approx(200.0), "unit": "N*m/rad", "text": "200 N*m/rad",
                            "origin": "option"}
    assert inputs["J3"]["value"] == pytest.approx(0.29e-3) and inputs["J3"]["unit"] == "kg*m^2"
    assert inputs["J3"]["origin"].startswith("scene: paper")
    assert inputs["t_end"]["origin"] == "option" and inputs["t_end"]["value"] == pytest.approx(0.3)


def test_written_files_are_named_on_stderr(tmp_path):
    csv_path, png = tmp_path / "run.csv", tmp_path / "run.png"
    result = ok(run("simulate", "sewing", "--t-end", "0.3s", "--window", "0.2s", "--csv", str(csv_path),
                    "--plot", str(png)))
    assert [line for line in result.stderr.splitlines() if line.startswith("wrote ")] == [
        f"wrote {csv_path}", f"wrote {png}"]
    sweep_csv = tmp_path / "sweep.csv"
    result = ok(run("simulate", "sewing", "--steady-state-only", "--sweep", "C4=50N*m/rad:310N*m/rad:3",
                    "--csv", str(sweep_csv)))
    assert result.stderr.splitlines() == [f"wrote {sweep_csv}"]
    header, table = read_csv(sweep_csv)
    assert header[0] == "C4_N_m_per_rad"
    assert list(table["C4_N_m_per_rad"]) == pytest.approx([50.0, 180.0, 310.0])


def test_sweep_table_headers_are_labels_with_display_units():
    out = ok(run("simulate", "sewing", "--steady-state-only", "--sweep", "C4=50N*m/rad:310N*m/rad:2")).stdout
    assert "[N m/rad]" in out and "[rad/s]" in out and "[rad/s^2]" in out
    assert "amplitude" in out and "steady_main_sp" not in out


def test_a_run_that_ends_before_the_load_lands_says_so():
    result = ok(run("simulate", "roller-table", "--set", "rollers=2", "--t-end", "0.5s", "--window", "0.1s",
                    "--samples", "201", "--json"))
    out = json.loads(result.stdout)
    said = warnings(result)
    assert any("before the load lands" in w and "--t-end" in w for w in said)
    assert out["motor"]["startup_time"]["value"] is None
    assert any("did not settle" in w for w in said)


def test_a_load_at_a_natural_frequency_fails_the_resonance_check():
    # the sewing drive's lowest mode is 17.36 Hz; a load at 110 rad/s (17.51 Hz) sits 0.8 % from it,
    # the default load (36.3 Hz) 109 % away
    out = json.loads(ok(run("simulate", "sewing", "--set", "load_frequency=110rad/s", "--t-end", "0.3s",
                            "--window", "0.2s", "--json")).stdout)
    check = next(c for c in out["checks"] if c["key"] == "resonance")
    assert check["verdict"] == "FAIL"
    assert check["value"]["value"] == pytest.approx(abs(110 / (2 * 3.141592653589793) - 17.36) / 17.36, abs=5e-4)
    assert any(w.startswith("load vs resonance FAILS") for w in out["warnings"])
    default = json.loads(ok(run("simulate", "sewing", "--t-end", "0.3s", "--window", "0.2s", "--json")).stdout)
    check = next(c for c in default["checks"] if c["key"] == "resonance")
    assert check["verdict"] == "pass" and check["value"]["value"] == pytest.approx(1.089, abs=1e-3)


def test_plot_draws_the_limits_of_the_checks(tmp_path, monkeypatch):
    # the limit lines come from the checks that bound a plotted signal: breakdown torque on the
    # motor-torque panel, on the strand-force panel the force the chain's safety rule allows,
    # F_B / 6 (Diamond Chain, issue 28); the steady window shaded
    import beltcalc.plots

    drawn = {}
    real_save = beltcalc.plots.save_figure

    def keep(fig, *args, **kw):
        drawn["axes"] = [(ax.get_ylabel(), [ln.get_label() for ln in ax.get_lines()],
                          [ln.get_ydata()[0] for ln in ax.get_lines() if "limit" in ln.get_label()])
                         for ax in fig.axes]
        real_save(fig, *args, **kw)

    monkeypatch.setattr(beltcalc.plots, "save_figure", keep)
    png = tmp_path / "rt.png"
    ok(run(*ROLLERS, "--set", "rollers=2", "--plot", str(png)))
    panels = {label: (lines, levels) for label, lines, levels in drawn["axes"]}
    lines, levels = panels["motor torque [N m]"]
    assert any("motor mean torque / motor peak torque limit" in ln for ln in lines)
    assert levels == pytest.approx([2.3 * 7.3])        # breakdown: 2.3 x the rated 7.3 N m (scene file)
    lines, levels = panels["strand force [N]"]
    assert "strand breaking-load safety limit" in lines and levels == pytest.approx([22200.0 / 6])


def test_a_belt_heavier_than_its_carriage_fails_the_plausibility_check():
    out = json.loads(run("simulate", "linear-axis", "--set", "mass=0.1kg", "--json").stdout)
    check = next(c for c in out["checks"] if c["key"] == "belt_mass")
    assert check["verdict"] == "FAIL"
    assert check["value"]["value"] == pytest.approx(0.14193, rel=1e-4)     # 1245 mm of 25 mm AT10
    assert check["limit"]["value"] == pytest.approx(0.1)
    assert any(w.startswith("belt mass FAILS") for w in out["warnings"])
    default = json.loads(run("simulate", "linear-axis", "--json").stdout)
    assert next(c for c in default["checks"] if c["key"] == "belt_mass")["verdict"] == "pass"


def test_an_absurdly_stiff_model_fails_fast_with_the_step_count():
    # a 60 km shaft is 1e13 times stiffer than the rest: the exact method would need 3e13 internal
    # steps; it says so at once instead of running for days
    result = run("simulate", "roller-table", "--set", "shaft_diameter=60km")
    assert result.exit_code == 1
    line = result.stderr.strip()
    assert line.startswith("Error: method exact: the run needs about ") and "internal steps" in line
    assert "more than 20,000,000" in line and len(result.stderr.splitlines()) == 1


@pytest.mark.parametrize("command", ["modes", "response", "campbell"])
def test_frequency_commands_follow_the_contract(command, tmp_path):
    out = json.loads(ok(run(command, "sewing", "--set", "23.stiffness=0.2kN*m/rad", "--json")).stdout)
    assert out["warnings"] == []
    assert out["inputs"]["23.stiffness"] == {"value": pytest.approx(200.0), "unit": "N*m/rad",
                                             "text": "200 N*m/rad", "origin": "option"}
    assert out["inputs"]["3.inertia"]["origin"].startswith("scene")
    path = tmp_path / f"{command}.csv"
    assert ok(run(command, "sewing", "--csv", str(path))).stderr.splitlines() == [f"wrote {path}"]


def test_list_params_names_every_set_value_with_unit_and_origin():
    out = ok(run("simulate", "sewing", "--list-params")).stdout
    assert "C4" in out and "N*m/rad" in out and "paper" in out
    lines = [ln for ln in out.splitlines() if ln.startswith("│ C4 ")]
    assert len(lines) == 1 and "260 N*m/rad" in lines[0]
    drive = ok(run("simulate", "drive", "conveyor", "--list-params")).stdout
    assert "rotor.inertia" in drive and "kg*m^2" in drive
    # it lists and stops: no run, nothing else printed
    assert "method:" not in out and "checks" not in out


def test_list_params_with_json_prints_json():
    out = json.loads(ok(run("simulate", "sewing", "--list-params", "--json")).stdout)
    c4 = out["parameters"]["C4"]
    assert c4["value"] == pytest.approx(260.0) and c4["unit"] == "N*m/rad" and c4["origin"].startswith("scene: paper")
    assert c4["help"] == "stiffness C4" and out["warnings"] == []
