"""Messages that say it right (issue 30, item 5), each through the command a user types:
unit hints in the option's or the key's display unit and how to type a value with a space,
"did you mean" with the three closest names, percentages never past 999 %, R^2 as a plain
number, no float-range blame for a physical cause, phase rows at the phase's peak, and the
drive file that holds no drive."""

from __future__ import annotations

import difflib
import json
import math
import re

import pytest
from click.testing import CliRunner

from beltcalc.data.catalogs import builtin_dir
from beltcalc.cli.main import cli
from clichecks import edited_copy, ok, one_error_line

MINIMAL = builtin_dir() / "drives" / "minimal.toml"


def run(*args):
    return CliRunner().invoke(cli, list(args))


# --- unit hints: the display unit, and a value typed with a space -------------------------------

def test_a_drive_file_length_without_unit_is_hinted_in_mm(tmp_path):
    path = edited_copy(MINIMAL, tmp_path, 'length = "500 mm"', "length = 600")
    line = one_error_line(run("simulate", "drive", str(path)), 1, "belt_span 'tight': length:")
    assert 'e.g. "600 mm"' in line
    assert '"600 m"' not in line


def test_a_set_length_without_unit_is_hinted_in_mm():
    one_error_line(run("simulate", "drive", str(MINIMAL), "--set", "tight.length=600"), 2,
                   "--set", "e.g. 'tight.length=600 mm'")


def test_power_with_a_space_says_to_quote_it_or_leave_the_space_out():
    # the shell hands click '3' and 'kW': the hint names the unit typed and both ways to write it
    one_error_line(run("chain", "--power", "3", "kW"), 2,
                   "--power", "'3 kW' with a space is two words to the shell",
                   "--power 3kW", '--power "3 kW"')


def test_a_bare_power_is_hinted_in_kw_with_both_ways_to_type_it():
    one_error_line(run("chain", "--power", "3"), 2, "--power", "e.g. '3 kW'", "--power 3kW", '--power "3 kW"')


def test_accel_with_a_space_names_the_unit_typed_not_another_dimension():
    line = one_error_line(run("motor-size", "--accel", "10", "m/s^2"), 2,
                          "--accel", '--accel "10 m/s^2"', "--accel 10m/s^2")
    assert "rad/s^2" not in line


def test_a_bare_accel_offers_both_of_its_dimensions():
    one_error_line(run("motor-size", "--accel", "10"), 2, "--accel", "'10 rad/s^2' or '10 m/s^2'")


def test_a_set_value_split_by_a_space_says_to_quote_it():
    one_error_line(run("simulate", "sewing", "--set", "C4=190", "N*m/rad"), 2,
                   "'C4=190 N*m/rad' with a space is two words to the shell", '--set "C4=190 N*m/rad"')


def test_neither_nor():
    one_error_line(run("motor-size", "--speed", "5kg"), 2,
                   "'5kg' is neither a rotational speed nor a speed")


# --- did you mean: the three closest names ------------------------------------------------------

def test_a_misspelt_sewing_set_name_offers_the_three_closest():
    from beltcalc.sim.scenes import SCENES

    names = [p.name for p in SCENES["sewing"].params]          # what --set takes
    line = one_error_line(run("simulate", "sewing", "--set", "C5=190N*m/rad"), 2, "--set", "'C5' is not a value here")
    by_lower = {n.lower(): n for n in names}
    want = difflib.get_close_matches("c5", list(by_lower), n=3, cutoff=0.0)    # the three nearest, case ignored
    assert f"did you mean {', '.join(by_lower[w] for w in want)}?" in line
    assert "c4" in want
    assert f"({len(names)} names)" in line
    assert ", ".join(names[:5]) not in line          # not every name any more


@pytest.mark.parametrize("args, code, fragments", [
    (["tension", "--belt", "AT11"], 2, ["--belt", "unknown belt 'AT11'; did you mean AT10, "]),
    (["motor-size", "--motor", "SGM7J-06"], 2, ["--motor", "did you mean SGM7J-06A, "]),
    (["simulate", "drive", "convyor"], 2, ["did you mean conveyor, ", "(one of conveyor, "]),
    (["simulate", "drive", "conveyor", "--set", "upper.pretensio=5N"], 2, ["did you mean upper.pretension, "]),
    (["motor-size", "--motors", "yaskawaa"], 2, ["--motors", "did you mean yaskawa?"]),
])
def test_every_unknown_name_offers_the_closest(args, code, fragments):
    line = one_error_line(run(*args), code, *fragments)
    hint = line.split("did you mean ", 1)[1].split("?", 1)[0]
    assert 1 <= len(hint.split(", ")) <= 3


def test_a_misspelt_motor_kind_in_a_drive_file(tmp_path):
    path = edited_copy(MINIMAL, tmp_path, 'kind = "induction"', 'kind = "inductoin"')
    one_error_line(run("simulate", "drive", str(path)), 1, "kind: 'inductoin' is not a kind; did you mean induction, ")


def test_a_misspelt_key_in_a_drive_file(tmp_path):
    path = edited_copy(MINIMAL, tmp_path, 'stiffness = "1500 N*m/rad"', 'stifness = "1500 N*m/rad"')
    one_error_line(run("simulate", "drive", str(path)), 1, "stifness: unknown key; did you mean stiffness, ")


# --- percentages: never past 999 %; R^2 is no percentage -----------------------------------------

def test_an_overloaded_belt_shows_its_utilisation_as_a_factor():
    # 5000 kg at 10 m/s^2 pulls about 5000 * 10 = 50,000 N through a belt allowed F_Tadm = 2200 N
    # (BRECO AT10, 25 mm): about 23 times, "x23", not "2296 %"
    result = ok(run("tension", "--mass", "5000kg"))
    obj = json.loads(ok(run("tension", "--mass", "5000kg", "--json")).stdout)
    u = obj["utilisation"]["value"]
    assert u == pytest.approx(obj["tension_peak"]["value"] / 2200.0, rel=1e-12)
    assert u == pytest.approx(5000 * 10.0 / 2200.0, rel=0.02)
    row = next(line for line in result.stdout.splitlines() if "utilisation F_t,peak / F_Tadm" in line)
    assert "%" not in row
    assert shown_factor(row) == pytest.approx(u, rel=5e-3)          # three significant digits
    assert shown_factor(result.stderr.split("utilisation ", 1)[1]) == pytest.approx(u, rel=5e-3)
    assert not re.search(r"\d{4,}\s*%", result.stdout + result.stderr)


def shown_factor(text: str) -> float:
    """The first factor "x12.3" in ``text``."""
    return float(re.search(r"\bx([0-9.]+(?:e[-+]?[0-9]+)?)", text).group(1))


def test_a_percentage_up_to_999_stays_a_percentage():
    # 1000 kg: F_t,peak / F_Tadm = 10,105 / 2200 = 4.59: "459 %"
    obj = json.loads(ok(run("tension", "--mass", "1000kg", "--json")).stdout)
    u = obj["utilisation"]["value"]
    assert 1 < u < 9.99
    out = ok(run("tension", "--mass", "1000kg")).stdout
    row = next(line for line in out.splitlines() if "utilisation F_t,peak / F_Tadm" in line)
    assert f"{u * 100:.0f}" in row and "%" in row


def test_the_motor_choice_column_never_prints_past_999_percent():
    out = ok_or_no_motor(run("motor-size", "--gear-ratio", "1"))
    obj = json.loads(run("motor-size", "--gear-ratio", "1", "--json").stdout)
    first = obj["motors"][0]
    u = first["utilisation"]["value"]
    assert u > 10          # the smallest motor runs far past its rated torque
    row = next(line for line in out.splitlines() if line.startswith(f"│ {first['name']} "))
    assert shown_factor(row) == pytest.approx(u, rel=5e-3)
    assert not re.search(r"\d{4,}%", out)


def ok_or_no_motor(result) -> str:
    """A motor-size run whose only error is that no motor fits (exit 1): its tables."""
    assert result.exit_code == 1, result.stderr
    assert result.stderr.splitlines()[-1].startswith("Error: no motor fits"), result.stderr
    return result.stdout


def test_percent_rule():
    from beltcalc.design.checks import percent

    assert [percent(0.2304), percent(9.99), percent(9.996), percent(12.34), percent(1000.0), percent(2.28e6)] == \
        ["23%", "999%", "x10", "x12.3", "x1000", "x2.28e+06"]


def test_a_poor_damping_fit_shows_r2_as_a_plain_number():
    # BRECO T20: the line through the origin fitted to its F_tspec(n) table gives R^2 = 0.151
    obj = json.loads(ok(run("tension", "--belt", "BRECO-T20", "--json")).stdout)
    r2 = obj["damping_fit_r_squared"]["value"]
    check = next(c for c in obj["checks"] if c["key"] == "damping_fit")
    assert check["value"]["value"] == pytest.approx(r2, rel=1e-12)
    assert check["utilisation"]["value"] == pytest.approx(0.9 / r2, rel=1e-12)     # the JSON keeps it
    result = ok(run("tension", "--belt", "BRECO-T20"))
    checks = result.stdout[result.stdout.index("checks (utilisation)"):]
    row = next(line for line in checks.splitlines() if "damping fit R^2" in line)
    cells = [c.strip() for c in row.split("│")]
    assert cells[2] == f"{r2:.3f}" and cells[3] == ""          # the value, no unit, no %
    assert f"{0.9 / r2 * 100:.0f}" not in row
    warning = next(w for w in result.stderr.splitlines() if "damping fit R^2 FAILS" in w)
    assert "utilisation" not in warning and "%" not in warning


def test_a_negative_r2_is_no_float_range():
    # Elatech T5 on an 80-tooth pulley: R^2 = -0.129 (the fit is worse than the mean)
    result = ok(run("tension", "--belt", "Elatech-T5"))
    assert "range of a float" not in result.stdout + result.stderr
    row = next(line for line in result.stdout[result.stdout.index("checks (utilisation)"):].splitlines()
               if "damping fit R^2" in line)
    assert "-0.129" in row


def test_the_simulated_damping_fit_check_has_no_utilisation(tmp_path):
    path = tmp_path / "t20.toml"
    path.write_text(MINIMAL.read_text().replace("BRECO-AT10", "BRECO-T20"))
    out = ok(run("simulate", "drive", str(path))).stdout
    row = next(line for line in out.splitlines() if "damping fit R^2" in line)
    cells = [c.strip() for c in row.split("│")]
    assert cells[2] == "0.1509" and cells[5] == "-" and cells[6] == "FAIL"


# --- a physical cause, not the range of a float ---------------------------------------------------

def test_no_motor_means_no_inertia_ratio_not_a_float_overflow():
    # direct drive (i = 1): the carriage reflects 50 kg (D/2)^2 = 50 * 0.0636620^2 = 0.2026 kg m^2,
    # thousands of times every rotor: no motor passes, so there is no rotor inertia to divide by
    result = run("motor-size", "--gear-ratio", "1")
    out = ok_or_no_motor(result)
    assert "range of a float" not in out + result.stderr
    lines = out.splitlines()
    k = next(i for i, line in enumerate(lines) if "load / motor inertia" in line)
    assert "no motor fits, so there is no rotor" in lines[k] and lines[k].split("│")[2].strip() == "-"
    obj = json.loads(run("motor-size", "--gear-ratio", "1", "--json").stdout)
    assert obj["inertia_ratio"]["value"] is None
    assert "no rotor inertia" in obj["inertia_ratio"]["reason"]
    assert obj["reflected_inertia"]["value"] == pytest.approx(50 * (0.4 / math.pi / 2) ** 2, rel=0.03)


# --- phase rows at the phase's peak ---------------------------------------------------------------

def test_the_decelerate_row_is_the_phase_peak():
    # WDU scene by hand (tests/test_cli_motor_size.py): J_red = 6.0710488e-4 kg m^2, eps = 3141.5927
    # rad/s^2, b_M omega = 0.1*1.91 = 0.191 N m at 3000 rpm, T_R = 3.1215536e-3 N m. Decelerating, T is
    # linear in t: -J eps + b_M omega(t) + T_R from -1.7131547 (omega = 3000 rpm) to -1.9041547 N m
    # (omega = 0); a line's extreme is an end, here the end.
    j_eps = 6.0710488e-4 * 3141.5927
    start, end = -j_eps + 0.191 + 3.1215536e-3, -j_eps + 3.1215536e-3
    obj = json.loads(ok(run("motor-size", "--json")).stdout)
    assert obj["torque_decelerate"]["value"] == pytest.approx(end, rel=1e-6)
    decel = next(p for p in obj["phases"] if p["phase"] == "decelerate")
    assert decel["torque0"]["value"] == pytest.approx(start, rel=1e-6)
    assert decel["extreme_torque"]["value"] == pytest.approx(end, rel=1e-6)
    out = ok(run("motor-size")).stdout
    row = next(line for line in out.splitlines() if "decelerate (0.1 s)" in line)
    assert row.split("│")[2].strip() == f"{end:.2f}" == "-1.90"


def test_a_phase_peak_inside_the_phase():
    # One phase of constant jerk: omega = 10 + 10 t - 10 t^2 rad/s on [0, 1] s (accel 10 -> -10 rad/s^2),
    # J = 0.05 (rotor) + 20 kg (0.1 m / 2)^2 = 0.1 kg m^2, b = 1 N m s/rad, nothing else:
    # T(t) = J (10 - 20 t) + b (10 + 10 t - 10 t^2); T' = -2 + 10 - 20 t = 0 at t = 0.4 s,
    # T(0.4) = 0.1 * 2 + (10 + 4 - 1.6) = 12.6 N m, above the ends T(0) = 11 and T(1) = 9.
    from beltcalc.design.dutycycle import AxisDrive, Segment, cycle_duty
    from beltcalc.formulas.drive import BeltAxis
    from beltcalc.formulas.profiles import Phase, Trapezoid

    axis = BeltAxis(mass=20.0, substitute_mass=0.0, pulley_diameter=0.1, pulley_inertia=0.0, idler_inertia=0.0,
                    gear_ratio=1.0)
    phase = Phase("accel_out", 1.0, 10.0, 10.0, -20.0)
    move = Segment("move", "move", profile=Trapezoid(20.0, 10.0, phase.angle, 0.0, (phase,), False))
    row, = cycle_duty(AxisDrive(axis), [move], motor_inertia=0.05, motor_damping=1.0).phases
    assert (row.torque0, row.torque1) == (pytest.approx(11.0, rel=1e-12), pytest.approx(9.0, rel=1e-12))
    assert row.extreme == pytest.approx(12.6, rel=1e-12)
    assert row.peak == pytest.approx(12.6, rel=1e-12)


# --- a drive file with no drive; --list-params says where a value comes from ----------------------

@pytest.mark.parametrize("text", ["", "# my drive\n\n"])
def test_an_empty_drive_file_points_to_the_minimal_drive(tmp_path, text):
    path = tmp_path / "mine.toml"
    path.write_text(text)
    line = one_error_line(run("simulate", "drive", str(path)), 1, "the file holds no drive",
                          "catalogs/drives/minimal.toml", "docs/drive_files.md")
    assert "t_end: missing" not in line
    assert (builtin_dir() / "drives" / "minimal.toml").is_file()


def test_list_params_says_not_set_for_a_value_no_file_gives():
    out = ok(run("simulate", "sewing", "--list-params")).stdout
    assert "the caller" not in out
    row = next(line for line in out.splitlines() if line.startswith("│ belt_pretension "))
    cells = [c.strip() for c in row.split("│")]
    assert cells[3] == "-" and cells[5] == "not set"
    c4 = next(line for line in out.splitlines() if line.startswith("│ C4 "))
    assert "paper, section IV" in c4          # a value the scene file gives says why


def test_the_simulate_checks_table_never_prints_past_999_percent():
    # window at 0 s: the transient at the window start is all of it (r = 1 against 0.001): x1000
    args = ("simulate", "drive", "minimal", "--set", "window=0s")
    obj = json.loads(ok(run(*args, "--json")).stdout)
    check = next(c for c in obj["checks"] if c["key"] == "window_settled")
    u = check["utilisation"]["value"]
    assert u == pytest.approx(check["value"]["value"] / 1e-3, rel=1e-12) and u > 10
    result = ok(run(*args))
    row = next(line for line in result.stdout.splitlines() if line.startswith("│ transient at the window start"))
    assert shown_factor(row) == pytest.approx(u, rel=5e-3) and "%" not in row
