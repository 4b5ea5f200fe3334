"""The output contract of the design commands (tension, belt-drive, chain, motor-size):
checks in the JSON `checks` key, one `warning:` line on stderr per failure (the same text in
`warnings`), --strict exits 1 and writes nothing, inputs echoed with their origin, files
written only after the result is known good (with one `wrote` line each), and the options
a run does not use still checked (issue 12)."""

import json

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import ok, one_error_line, warnings

ORIGINS = ("default", "option")


def run(*args):
    return CliRunner().invoke(cli, list(args))


def js(*args):
    res = ok(run(*args, "--json"))
    out = json.loads(res.stdout)
    assert warnings(res) == out["warnings"]          # each warning once on stderr, once in the JSON
    return out


def checks(out) -> dict:
    return {c["key"]: c for c in out["checks"]}


def assert_inputs_contract(out):
    """Every echoed input is {text, value (float or None), unit, origin}."""
    assert out["inputs"], out.keys()
    for name, item in out["inputs"].items():
        assert set(item) == {"text", "value", "unit", "origin"}, name
        assert item["value"] is None or isinstance(item["value"], float), name
        assert item["origin"] in ORIGINS or item["origin"].startswith(("scene: ", "catalog: ")), (name, item)


def assert_values_contract(obj, path="$"):
    """No bare float anywhere in the JSON: every number sits in a {"value", "unit"} pair."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(v, float) and k != "value":
                raise AssertionError(f"bare float at {path}.{k}")
            assert_values_contract(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for k, v in enumerate(obj):
            assert not isinstance(v, float), f"bare float at {path}[{k}]"
            assert_values_contract(v, f"{path}[{k}]")


# --- tension -----------------------------------------------------------------------------

def test_tension_default_passes_every_check_and_warns_nothing():
    res = ok(run("tension", "--json"))
    assert res.stderr == ""
    out = json.loads(res.stdout)
    assert out["warnings"] == []
    verdicts = {k: c["verdict"] for k, c in checks(out).items()}
    assert verdicts == {"belt_tension": "pass", "damping_fit": "n/a", "belt_mass": "pass"}
    assert checks(out)["damping_fit"]["reason"] == "b_TB is the catalog's value, not fitted"
    assert_inputs_contract(out)
    assert out["inputs"]["belt"] == {"text": "BRECO-AT10", "value": None, "unit": "", "origin": "default"}
    assert out["inputs"]["mass"] == {"text": "50 kg", "value": pytest.approx(50.0), "unit": "kg", "origin": "default"}
    assert out["inputs"]["f_tadm"]["value"] == pytest.approx(2200.0)
    assert out["inputs"]["f_tadm"]["origin"].startswith("catalog: BRECO-AT10")
    assert_values_contract(out)


def test_tension_inputs_say_option_for_what_was_given():
    out = js("tension", "--mass", "60kg", "--damping", "25N*s/m")
    assert out["inputs"]["mass"] == {"text": "60 kg", "value": pytest.approx(60.0), "unit": "kg", "origin": "option"}
    assert out["inputs"]["damping"]["origin"] == "option"
    assert out["inputs"]["accel"]["origin"] == "default"
    assert checks(out)["damping_fit"]["reason"] == "b_TB is given (--damping)"


def test_tension_damping_fit_check_fires_on_t20():
    # BRECO T20: the line through the origin fits F_b(v) of the page's 40 rows with R^2 = 0.151
    # (test_tension.test_fitted_damping_t20; 0.659 when the catalog held 3 rows)
    out = js("tension", "--belt", "BRECO-T20", "--width", "32mm")
    fit = checks(out)["damping_fit"]
    assert fit["verdict"] == "FAIL"
    assert fit["value"]["value"] == pytest.approx(0.151, abs=0.001)
    assert fit["limit"]["value"] == pytest.approx(0.9)
    assert fit["kind"] == "min" and "F_tspec" in fit["rule"]
    assert [w for w in out["warnings"] if w.startswith("damping fit R^2 FAILS: 0.1509 ")]
    assert "--damping" in out["warnings"][0]               # the library name shown as the option


def test_tension_belt_mass_check_fires_on_a_huge_span():
    # a = 1e9 m of AT10 25 mm (w_spec 0.114 kg/m): 1.14e8 kg of belt against a 50 kg carriage
    out = js("tension", "--center-distance", "1e9m")
    mass = checks(out)["belt_mass"]
    assert mass["verdict"] == "FAIL"
    assert mass["value"]["value"] == pytest.approx(1.14e8, rel=1e-9)
    assert mass["limit"]["value"] == pytest.approx(50.0)
    assert len(out["warnings"]) == 1 and out["warnings"][0].startswith("belt mass on the span FAILS")


def test_tension_belt_mass_check_passes_at_the_limit_and_fails_just_over():
    # 0.114 kg/m x 438.6 m = 50.0 kg; a 49 kg carriage is lighter than that belt
    assert checks(js("tension", "--center-distance", "438m"))["belt_mass"]["verdict"] == "pass"
    assert checks(js("tension", "--center-distance", "438m", "--mass", "49kg"))["belt_mass"]["verdict"] == "FAIL"


def test_tension_overload_is_a_check_with_a_warning():
    out = js("tension", "--mass", "500kg", "--width", "16mm")
    c = checks(out)["belt_tension"]
    assert c["verdict"] == "FAIL"
    assert c["value"]["value"] == pytest.approx(5050.1, abs=0.05)
    assert c["limit"]["value"] == pytest.approx(1400.0)
    assert "overloaded" in out["warnings"][0]


def test_tension_strict_exits_1_and_writes_no_file(tmp_path):
    target = tmp_path / "out.csv"
    res = run("tension", "--center-distance", "1e9m", "--strict", "--csv", str(target))
    assert res.exit_code == 1
    assert res.stderr.splitlines()[-1].startswith("Error: --strict: 1 checks fail (belt mass on the span)")
    assert list(tmp_path.iterdir()) == []
    ok(run("tension", "--strict"))                     # the default passes


def test_tension_csv_is_written_after_the_warnings_and_said(tmp_path):
    target = tmp_path / "out.csv"
    res = run("tension", "--belt", "BRECO-T20", "--csv", str(target))
    assert res.exit_code == 0
    lines = res.stderr.splitlines()
    assert lines[0].startswith("warning: damping fit R^2 FAILS") and lines[-1] == f"wrote {target}"
    assert target.exists()


def test_tension_bolt_torque_says_what_it_leaves_out():
    out = js("tension")
    assert out["bolt_torque"]["value"] == pytest.approx(0.6307, abs=1e-4)
    assert "VDI 2230" in out["bolt_torque"]["note"] and "--bearing-friction" in out["bolt_torque"]["note"]
    assert out["bearing_torque"]["value"] is None and "--bearing-friction" in out["bearing_torque"]["reason"]
    # with it: 0.6307 + 505.1 N x 0.15 x 0.015 m / 2 = 1.199 N m (VDI 2230), nothing left out
    full = js("tension", "--bearing-friction", "0.15", "--bearing-diameter", "15mm")
    assert full["bolt_torque"]["value"] == pytest.approx(1.1989, abs=1e-4)
    assert "note" not in full["bolt_torque"]
    table = ok(run("tension")).stdout
    assert "WITHOUT bearing-face friction" in table and "add 0.568 N m" in table


@pytest.mark.parametrize("args, option", [
    (["--center-distance", "1e300m"], "--center-distance"),
    (["--stiffness", "5e-324N/m"], "--stiffness"),
    (["--pulley-diameter", "1e308m", "--belt", "BRECO-T20"], "--pulley-diameter"),
], ids=["huge-span", "tiny-stiffness", "huge-pulley"])
def test_tension_overflow_is_one_line_naming_the_option(args, option, tmp_path):
    target = tmp_path / "out.csv"
    line = one_error_line(run("tension", *args, "--json", "--csv", str(target)), 1, option)
    assert "internal error" not in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, option", [
    (["--pulley-diameter", "-1m"], "--pulley-diameter"),          # AT10 does not fit the damping
    (["--safety-factor", "-1"], "--safety-factor"),              # without --select-width
    (["--c-spec", "-0N", "--stiffness", "1e5N/m"], "--c-spec"),  # --stiffness replaces C_spec / a
    (["--span-length", "-1m"], "--span-length"),
], ids=["pulley", "safety-factor", "c-spec", "span-length"])
def test_tension_unused_options_are_checked(args, option):
    one_error_line(run("tension", *args), 1, option, "is not allowed")


def test_tension_missing_companion_option_is_a_usage_error():
    one_error_line(run("tension", "--bearing-friction", "0.1"), 2, "--bearing-friction needs --bearing-diameter")
    one_error_line(run("tension", "--bearing-diameter", "15mm"), 2, "--bearing-diameter needs --bearing-friction")


USER_AT10 = ('[source]\ndocument = "My own belt test"\n\n[[belts]]\nmanufacturer = "Acme"\nprofile = "AT10"\n'
             'pitch = 10\ndamping = 20\nunits = { pitch = "mm", width = "mm", F_Tadm = "N", C_spec = "N", '
             'w_spec = "kg/m", damping = "N*s/m" }\n'
             'widths = [ { width = 25, F_Tadm = 1000, C_spec = 2.5e5, w_spec = 0.1 } ]\n')


@pytest.mark.parametrize("command", ["tension", "belt-drive", "motor-size"])
def test_a_user_catalog_with_another_at10_leaves_the_defaults_alone(command, tmp_path):
    path = tmp_path / "my.toml"
    path.write_text(USER_AT10)
    ok(run(command, "--catalog", str(path)))
    one_error_line(run(command, "--catalog", str(path), "--belt", "AT10"), 2, "ambiguous", "Acme-AT10, BRECO-AT10")
    if command != "motor-size":
        assert js(command, "--catalog", str(path), "--belt", "Acme-AT10")["belt"] == "Acme-AT10"


# --- belt-drive --------------------------------------------------------------------------

SHEAR = ["belt-drive", "--belt", "Elatech-AT5", "--layout", "endless", "--teeth", "20", "--teeth-large", "40",
         "--center-distance", "300mm", "--torque", "10N*m", "--speed", "1500rpm"]


def test_belt_drive_default_passes_and_echoes_its_inputs():
    res = ok(run("belt-drive", "--json"))
    assert res.stderr == ""
    out = json.loads(res.stdout)
    assert out["warnings"] == [] and all(c["verdict"] != "FAIL" for c in out["checks"])
    assert set(out["checks"][0]) >= {"key", "name", "value", "limit", "margin", "utilisation", "verdict", "rule"}
    assert_inputs_contract(out)
    assert out["inputs"]["belt"]["text"] == "BRECO-AT10"
    assert out["inputs"]["service_factor"]["origin"].startswith("catalog: ")
    assert out["inputs"]["f_tadm"]["value"] == pytest.approx(2200.0)
    assert_values_contract(out)


def test_belt_drive_failing_check_is_a_warning_and_strict_fails(tmp_path):
    # Elatech AT5 at 10 N m on 20 teeth: F_U c2 = 879.6 N against a tooth capacity of 583.6 N
    # (24.16 N/cm printed at 1500 rpm x 2.5 cm x z_e 9.662)
    out = js(*SHEAR)
    shear = checks(out)["tooth_shear"]
    assert shear["verdict"] == "FAIL"
    assert shear["value"]["value"] == pytest.approx(879.6, abs=0.05)
    assert shear["limit"]["value"] == pytest.approx(583.6, abs=0.05)
    assert out["warnings"] == [w for w in out["warnings"] if "tooth shear FAILS" in w] != []
    target = tmp_path / "d.csv"
    res = run(*SHEAR, "--strict", "--csv", str(target))
    assert res.exit_code == 1 and "--strict" in res.stderr.splitlines()[-1]
    assert list(tmp_path.iterdir()) == []
    res = run(*SHEAR, "--csv", str(target))
    assert res.exit_code == 0 and res.stderr.splitlines()[-1] == f"wrote {target}" and target.exists()


T25 = ["--belt", "BRECO-T2.5", "--width", "10mm", "--layout", "endless", "--teeth", "12", "--teeth-large", "24",
       "--center-distance", "100mm", "--torque", "0.05N*m", "--speed", "1000rpm"]


@pytest.mark.parametrize("args, key, value, limit", [
    (["--mass", "200kg"], "tension_member", 4000.0, 2200.0),        # F_U + F_v = 2000 + 2000 N of F_Tadm 2200 N
    (["--pretension", "100N"], "pretension", 100.0, 500.0),         # the rule wants F_v >= F_U = 500 N
    (T25, "pulley_teeth", 12.0, 15.0),                             # BRECO T2.5: z_min = 15
    (T25, "teeth_in_mesh", 5.8176, 6.0),                           # 12/24 teeth at 100 mm: z_e = 5.82
], ids=["tension-member", "pretension", "pulley-teeth", "teeth-in-mesh"])
def test_belt_drive_each_check_fires(args, key, value, limit):
    out = js("belt-drive", *args)
    c = checks(out)[key]
    assert c["verdict"] == "FAIL"
    assert c["value"]["value"] == pytest.approx(value, abs=1e-4)
    assert c["limit"]["value"] == pytest.approx(limit)
    assert [w for w in out["warnings"] if w.startswith(c["name"] + " FAILS")]


# --- chain -------------------------------------------------------------------------------

def test_chain_default_passes_its_checks():
    # Shigley Example 17-5: 3 strands of no. 140 carry 130.9 kW of 135 kW rated (97 %)
    res = ok(run("chain", "--json"))
    out = json.loads(res.stdout)
    c = checks(out)
    # every check passes but the centre distance: the example's C/p = 25 is below the makers' 30 (issue 28)
    assert {k: v["verdict"] for k, v in c.items()} == {
        "rating": "pass", "safety": "pass", "galling": "pass", "teeth_small": "pass", "teeth_large": "pass",
        "ratio": "pass", "wrap": "pass", "center_pitches": "FAIL"}
    assert res.stderr.splitlines() == ["warning: " + out["warnings"][0]]
    assert out["warnings"][0].startswith("centre distance in pitches FAILS")
    assert c["rating"]["utilisation"]["value"] == pytest.approx(0.97, abs=0.005)
    assert_inputs_contract(out)
    assert out["inputs"]["power"] == {"text": "90 hp", "value": pytest.approx(67112.99, abs=0.01), "unit": "W",
                                      "origin": "default"}
    assert out["inputs"]["speed"]["origin"] == "default"
    assert_values_contract(out)


def test_chain_named_chain_that_does_not_carry_fails_both_checks(tmp_path):
    out = js("chain", "--chain", "10B-1")
    c = checks(out)
    assert c["rating"]["verdict"] == "FAIL" and c["safety"]["verdict"] == "FAIL"
    assert c["safety"]["value"]["value"] == pytest.approx(0.3433, abs=1e-4)
    assert len(out["warnings"]) == 3 and "does not carry the drive" in out["warnings"][0]
    assert out["inputs"]["chain_name"]["origin"] == "option"
    target = tmp_path / "c.csv"
    res = run("chain", "--chain", "10B-1", "--strict", "--csv", str(target))
    assert res.exit_code == 1 and "3 checks fail" in res.stderr.splitlines()[-1]
    assert list(tmp_path.iterdir()) == []


# --- motor-size --------------------------------------------------------------------------

MOTOR_CHECKS = ["motor_peak", "motor_rms", "motor_speed", "motor_inertia", "motor_zone"]


def test_motor_size_default_passes_the_selected_motors_checks():
    # Wojtkowiak et al. WDU axis: SGM7J-06A, peak 2.101 N m of T_max 6.69, RMS 0.691 of T_n 1.91, ratio 6.59
    res = ok(run("motor-size", "--json"))
    assert res.stderr == ""
    out = json.loads(res.stdout)
    c = checks(out)
    assert list(c) == MOTOR_CHECKS and {v["verdict"] for v in c.values()} == {"pass"}
    assert c["motor_peak"]["value"]["value"] == pytest.approx(2.1014, abs=1e-4)
    assert c["motor_rms"]["limit"] == {"value": pytest.approx(1.91), "unit": "N*m"}
    assert c["motor_inertia"]["value"]["value"] == pytest.approx(6.5888, abs=1e-4)
    assert_inputs_contract(out)
    assert out["inputs"]["belt"]["text"] == "BRECO-AT10" and out["inputs"]["belt"]["origin"].startswith("scene: ")
    assert out["inputs"]["mass"]["value"] == pytest.approx(50.0) and out["inputs"]["mass"]["unit"] == "kg"
    assert out["inputs"]["jerk_fraction"]["origin"] == "default"
    assert_values_contract(out)
    m = next(m for m in out["motors"] if m["name"] == "SGM7J-06A")
    assert m["peak_torque"] == {"value": pytest.approx(2.1014, abs=1e-4), "unit": "N*m"}
    assert m["utilisation"]["unit"] == "1" and m["inertia_ratio"]["unit"] == "1"


@pytest.mark.parametrize("args, failing", [
    (["--motor", "SGM7J-A5A"], ["motor_peak", "motor_rms", "motor_inertia", "motor_zone"]),
    (["--motor", "SGM7J-04A"], ["motor_inertia"]),                       # 10.85 > 10
    (["--motor", "SGMAH-04A", "--speed", "5500rpm"], ["motor_inertia", "motor_speed", "motor_zone"]),
    (["--motor", "SGM7J-06A", "--speed", "6000rpm"], ["motor_zone"]),    # 2.29 N m where the zone allows 1.91
], ids=["A5A", "04A-inertia", "SGMAH-speed", "06A-zone"])
def test_motor_size_reported_motor_checks_fire(args, failing):
    out = js("motor-size", *args)
    c = checks(out)
    assert sorted(k for k, v in c.items() if v["verdict"] == "FAIL") == sorted(failing)
    assert len(out["warnings"]) >= len(failing)
    for key in failing:
        assert c[key]["name"] + " FAILS" in " ".join(out["warnings"])


def test_motor_size_inertia_check_by_hand():
    # J_L / J_M of the WDU axis on SGM7J-04A (test_cli_motor_size.test_json_motor_table_by_hand)
    c = checks(js("motor-size", "--motor", "SGM7J-04A"))["motor_inertia"]
    assert c["value"]["value"] == pytest.approx(10.845779, rel=1e-6)
    assert c["limit"]["value"] == pytest.approx(10.0)
    assert c["utilisation"]["value"] == pytest.approx(1.0845779, rel=1e-6)


def test_motor_size_strict_and_files(tmp_path):
    csv = tmp_path / "p.csv"
    res = run("motor-size", "--motor", "SGM7J-04A", "--strict", "--csv", str(csv))
    assert res.exit_code == 1 and "--strict: 1 checks fail" in res.stderr.splitlines()[-1]
    assert list(tmp_path.iterdir()) == []
    res = run("motor-size", "--csv", str(csv))
    assert res.exit_code == 0 and res.stderr.splitlines() == [f"wrote {csv}"] and csv.exists()
    ok(run("motor-size", "--strict"))


def test_motor_size_writes_nothing_when_no_motor_fits(tmp_path):
    # fuzz: the direct drive fits no motor; the files used to be written before the exit 1
    csv, png = tmp_path / "out.csv", tmp_path / "out.png"
    res = run("motor-size", "--motor", "SGM7J-02A", "--gear-ratio", "1", "--csv", str(csv), "--plot", str(png))
    assert res.exit_code == 1
    assert res.stderr.splitlines()[-1].startswith("Error: no motor fits")
    assert list(tmp_path.iterdir()) == []


# --- hostile values: every quantity option of the four commands --------------------------

def _quantity_options():
    import click

    from beltcalc.cli.options import QuantityParam

    for name in ("tension", "belt-drive", "chain", "motor-size"):
        for p in cli.get_command(None, name).params:
            if isinstance(p, click.Option) and isinstance(p.type, QuantityParam):
                yield name, p.opts[0], p.type.si_unit.split("|")[0]


@pytest.mark.parametrize("value, as_json", [("1e308", False), ("5e-324", False), ("1e300", True)])
def test_hostile_values_give_a_result_or_one_line(value, as_json):
    """Found by fuzzing: overflow and underflow inside the physics were 'internal error's,
    and a table could not print an infinite value. Exit 0 (valid JSON) or one error line."""
    for command, option, unit in _quantity_options():
        args = [command, option, value + unit] + (["--json"] if as_json else [])
        res = run(*args)
        assert res.exit_code in (0, 1, 2), args
        if res.exit_code:
            line = one_error_line(res, res.exit_code, stdout_empty=False)
            assert "internal error" not in line, (args, line)
        elif as_json:
            json.loads(res.stdout)


@pytest.mark.parametrize("args, option, allowed", [
    (["chain", "--speed", "1e300rad/s"], "--speed", "physical range"),
    # the gear ratio is range-checked before the arithmetic (its square is the reflected inertia's)
    (["motor-size", "--gear-ratio", "1e300"], "--gear-ratio", "must lie within 1e-150..1e150"),
    (["motor-size", "--jerk", "1e308rad/s^3"], "--jerk", "physical range"),
], ids=["chain-speed", "gear-ratio", "jerk"])
def test_arithmetic_failure_names_the_option_given(args, option, allowed):
    line = one_error_line(run(*args), 1, option, allowed)
    assert "internal error" not in line


@pytest.mark.parametrize("args, option", [
    (["--accel-fraction", "0"], "--accel-fraction"),             # used only with --move-time
    (["--jerk-fraction", "-1"], "--jerk-fraction"),
    (["--accel-fraction", "0.7", "--sweep", "accel=100rad/s^2:200rad/s^2:2"], "--accel-fraction"),
], ids=["accel-fraction", "jerk-fraction", "in-a-sweep"])
def test_motor_size_unused_options_are_checked(args, option):
    one_error_line(run("motor-size", *args), 1, option, "is not allowed")


def test_installed_script_strict_in_a_real_process(tmp_path):
    """The console script itself: warnings on stderr, exit 1 under --strict, no file."""
    import shutil
    import subprocess

    exe = shutil.which("beltcalc")
    assert exe, "the beltcalc console script is not installed"
    target = tmp_path / "t.csv"
    proc = subprocess.run([exe, "tension", "--belt", "BRECO-T20", "--strict", "--csv", str(target)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert lines[0].startswith("warning: damping fit R^2 FAILS: 0.1509 ")
    assert lines[1] == "Error: --strict: 1 checks fail (damping fit R^2); see the warnings"
    assert list(tmp_path.iterdir()) == []


def test_motor_size_sweep_schema_and_its_checks(tmp_path):
    # SGM7J-06A (T_max 6.69 N m): peak torque J_red eps + 0.194 N m passes up to 10000 rad/s^2, fails at 15000 and 20000
    args = ["motor-size", "--sweep", "accel=5000rad/s^2:20000rad/s^2:4"]
    out = js(*args)
    assert out["parameters"] == [{"name": "accel", "unit": "rad/s^2", "values": [5000.0, 10000.0, 15000.0, 20000.0]}]
    assert [c["key"] for c in out["columns"]][:2] == ["accel_rad_per_s2", "motor_speed_rad_per_s"]
    assert all(set(c) == {"key", "label", "unit"} for c in out["columns"])
    assert [f["point"]["value"] for f in out["failed_checks"]] == [15000.0, 20000.0]
    assert {c["key"] for f in out["failed_checks"] for c in f["checks"]} == {"motor_peak"}
    peak = out["failed_checks"][0]["checks"][0]
    assert peak["value"]["value"] == pytest.approx(9.301, abs=1e-3) and peak["limit"]["value"] == pytest.approx(6.69)
    assert len(out["warnings"]) == 1 and out["warnings"][0].endswith("(at 2 of 4 points: accel = 15000, 20000 rad/s^2)")
    target = tmp_path / "s.csv"
    res = run(*args, "--strict", "--csv", str(target))
    assert res.exit_code == 1 and list(tmp_path.iterdir()) == []
    assert js("motor-size", "--sweep", "accel=100rad/s^2:1000rad/s^2:3")["failed_checks"] == []
