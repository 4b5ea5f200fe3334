"""Messages that say it right (issue 30, item 5), each through the command a user types:
unit hints in the option's or the key's display unit and how to type a value with a space,
"did you mean" with the three closest names, percentages never past 999 %, R^2 as a plain
number, no float-range blame for a physical cause, phase rows at the phase's peak, and the
drive file that holds no drive."""

from __future__ import annotations

import difflib

import pytest
from click.testing import CliRunner

from beltcalc.catalogs import builtin_dir
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
