"""Hostile input found by fuzzing (issue 12, "Found by fuzzing" and "Consistent input rules"),
each reproduced as one command: exit 2 for text that is no quantity or option value, exit 1
for a bad catalog file; one ``Error:`` line on stderr naming the option (or file and key),
the value and what is allowed; no traceback, no hang, no file left behind.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from beltcalc.units import QuantityError, dimension_name, parse_quantity, ureg
from clichecks import one_error_line


@pytest.fixture(autouse=True)
def _no_debug_from_environment(monkeypatch):
    monkeypatch.delenv("BELTCALC_DEBUG", raising=False)


@pytest.fixture
def out(tmp_path: Path) -> Path:
    """An empty folder for --csv; a failing run must leave it empty."""
    folder = tmp_path / "out"
    folder.mkdir()
    return folder


def run(*args: str):
    return CliRunner().invoke(cli, list(args))


def fails(out: Path, exit_code: int, *args_and_fragments) -> str:
    """Run ``args`` with ``--csv out/out.csv``; one error line with the fragments, no file."""
    args, fragments = args_and_fragments
    result = run(*args, "--csv", str(out / "out.csv"))
    line = one_error_line(result, exit_code, *fragments)
    assert sorted(p.name for p in out.iterdir()) == []
    return line


# --- 1. the unit parser computes nothing ---------------------------------------------------

@pytest.mark.parametrize("text", ["9**9**9 kg", "9^9^9 kg", "2*3 kg", "5 kg*9**9**9", "5 m**(9**9) kg"])
def test_arithmetic_in_a_quantity_is_refused_at_once(text, out):
    # (a hang is caught by the subprocess test below, with its timeout)
    line = fails(out, 2, ["tension", "--mass", text], ["--mass", "e.g. '50 kg'"])
    assert "give a number and a unit" in line


def test_arithmetic_does_not_hang_the_console_script(tmp_path):
    # in a subprocess with a timeout: a regression would hang pytest itself otherwise
    proc = subprocess.run([sys.executable, "-m", "beltcalc.cli.main", "tension", "--mass", "9**9**9 kg"],
                          capture_output=True, text=True, timeout=60, cwd=tmp_path,
                          env={**os.environ, "BELTCALC_DEBUG": ""})
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("Error: ")
    assert "--mass" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.parametrize("text, unit, expected", [
    ("1 kg*m^2", "kg*m^2", 1.0),
    ("2 kg m**2", "kg*m^2", 2.0),
    ("3 m/s^2", "m/s^2", 3.0),
    ("5 1/s", "1/s", 5.0),
    ("5/s", "1/s", 5.0),
    ("2.6e5 N/m", "N/m", 2.6e5),
    ("260 N*m/rad", "N*m/rad", 260.0),
    ("1e-3 kg*m^2", "kg*m^2", 1e-3),
    ("4 s^-2", "1/s^2", 4.0),
    ("0.5g0", "m/s^2", 4.903325),
])
def test_unit_powers_and_scientific_notation_still_read(text, unit, expected):
    assert parse_quantity(text, unit) == pytest.approx(expected, rel=1e-12)


def test_arithmetic_in_a_catalog_unit_is_refused_on_load(tmp_path, out):
    path = tmp_path / "mine.toml"
    path.write_text('[source]\ndocument = "test"\n[[belts]]\nmanufacturer = "Acme"\nprofile = "X9"\n'
                    'pitch = 10\nunits = { pitch = "9**9**9 mm" }\n')
    fails(out, 1, ["catalog", "list", "--catalog", str(path)], [str(path), "belts[0].units.pitch"])


def test_a_long_text_is_refused_and_quoted_short(out):
    text = "1" * 150 + " " + "k" * 100 + "g"
    line = fails(out, 2, ["tension", "--mass", text], ["--mass", "at most 200 characters", "(252 characters)"])
    assert len(line) == pytest.approx(200, abs=80)


# --- 2. a 400-digit number ----------------------------------------------------------------

def test_a_400_digit_number_is_one_line_exit_2(out):
    fails(out, 2, ["tension", "--mass", "9" * 400 + " kg"], ["--mass", "'9999", "give a number and a unit"])


def test_a_number_beyond_float_is_one_line_exit_2(out):
    fails(out, 2, ["tension", "--mass", "9" * 190 + "e200 kg"], ["--mass", "too large", "1e308"])


# --- 3. a file name too long ----------------------------------------------------------------

@pytest.mark.parametrize("option, command, suffix", [("--csv", ["tension"], ".csv"),
                                                     ("--plot", ["simulate", "sewing"], ".png")])
def test_a_file_name_too_long_is_exit_2_naming_the_option(option, command, suffix, out):
    name = "a" * 300 + suffix
    result = run(*command, option, str(out / name))
    one_error_line(result, 2, option, "file name is 304 bytes long", "at most")
    assert sorted(p.name for p in out.iterdir()) == []


def test_a_folder_name_too_long_is_exit_2(out):
    result = run("tension", "--csv", str(out / ("b" * 300) / "x.csv"))
    one_error_line(result, 2, "--csv", "too long")
    assert sorted(p.name for p in out.iterdir()) == []


# --- 5. unit errors in words, examples in the display unit ----------------------------------

@pytest.mark.parametrize("unit", ["m", "kg", "s", "N", "W", "V", "F", "Pa", "rad", "Hz", "N*m", "N*m/rad",
                                  "N*m*s/rad", "N*s/m", "N/m", "kg*m^2", "kg/m", "kg/m^3", "m/s", "m/s^2",
                                  "m/s^3", "rad/s", "rad/s^2", "rad/s^3"])
def test_every_option_dimension_has_words(unit):
    for name in (dimension_name(unit), dimension_name(ureg().parse_units(unit).dimensionality)):
        assert "[" not in name and "**" not in name, name
        assert name.split()[0] in ("a", "an"), name


def test_an_unnamed_dimension_is_words_with_si_units():
    assert dimension_name(ureg().parse_units("lbf*ft^2").dimensionality) == "a quantity in kg*m^3/s^2"


@pytest.mark.parametrize("args, fragments", [
    (["tension", "--width", "25"], ["--width", "e.g. '25 mm'"]),
    (["tension", "--center-distance", "1245"], ["--center-distance", "e.g. '1245 mm'"]),
    (["belt-drive", "--width", "25"], ["--width", "e.g. '25 mm'"]),
    (["chain", "--speed", "300"], ["--speed", "e.g. '300 rpm'"]),
    (["motor-size", "--stroke", "500"], ["--stroke", "e.g. '500 mm'"]),
    (["tension", "--mass", "5 N*m"], ["--mass", "is a torque or energy, not a mass", "e.g. '5 kg'"]),
    (["simulate", "sewing", "--set", "C4=5 kg"], ["C4", "a mass, not a torque per angle", "'5 N*m/rad'"]),
    (["simulate", "sewing", "--set", "J3=5 kg"], ["J3", "not an inertia (mass times length squared)"]),
])
def test_unit_errors_are_words_with_the_display_unit(args, fragments, out):
    line = fails(out, 2, args, fragments)
    assert "[mass]" not in line and "[length]" not in line and "**" not in line


def test_a_unit_error_in_a_library_call_names_the_dimension():
    with pytest.raises(QuantityError, match=r"'3 m' is a length, not a damping \(force per speed\)"):
        parse_quantity("3 m", "N*s/m")


# --- 4. catalog files: nesting, and every entry checked on load -----------------------------

BELT = ('[source]\ndocument = "test"\n[[belts]]\nmanufacturer = "Acme"\nprofile = "{profile}"\npitch = 10\n'
        'units = {{ pitch = "mm", speed = "rpm", F_tspec = "N/cm" }}\n{extra}\n')
THREAD = ('[source]\ndocument = "test"\n[[threads]]\nname = "M99"\n'
          'units = { d = "mm", P = "mm", d2 = "mm", flank_angle = "deg" }\nd = 10\nP = 1\nd2 = 9.3\n'
          'flank_angle = 180\n')


@pytest.mark.parametrize("body", ["a = " + "[" * 5000 + "]" * 5000,
                                  "a = " + "{ b = " * 5000 + "1" + " }" * 5000,
                                  "a = " + "[" * 40 + "]" * 40])
def test_a_deeply_nested_catalog_is_one_line_naming_the_file(body, tmp_path, out):
    path = tmp_path / "deep.toml"
    path.write_text('[source]\ndocument = "test"\n' + body + "\n")
    fails(out, 1, ["catalog", "list", "--catalog", str(path)], [str(path), "nested too deeply", "32 levels"])


@pytest.mark.parametrize("text, key, words", [
    (BELT.format(profile="X9", extra="F_tspec = [ { speed = 0, load = 10 } ]"), "belts[0].F_tspec",
     ["1 row from 0 rad/s", "at speed 0 and at least one more"]),
    (BELT.format(profile="X9", extra="F_tspec = [ { speed = 100, load = 10 }, { speed = 200, load = 9 } ]"),
     "belts[0].F_tspec", ["at speed 0"]),
    (THREAD, "threads[0].flank_angle", ["180 deg is not allowed", "(0, 120) deg"]),
    (BELT.format(profile="X\\n9", extra=""), "belts[0].profile", ["'X\\n9'", "U+000A", "one line"]),
    (BELT.format(profile="X\u202e9", extra=""), "belts[0].profile", ["'X\\u202e9'", "U+202E"]),
    (BELT.format(profile="X\\u0007", extra=""), "belts[0].profile", ["U+0007"]),
    (BELT.format(profile="X9", extra='note = "see \u202eleft"'), "belts[0].note", ["U+202E"]),
    (BELT.format(profile="X9", extra="k" * 100_000 + " = 1"), "belts[0]." + "k" * 40 + "...",
     ["(100000 characters)", "at most 100 characters"]),
])
def test_a_bad_catalog_entry_is_refused_on_load(text, key, words, tmp_path, out):
    path = tmp_path / "mine.toml"
    path.write_text(text, encoding="utf-8")
    line = fails(out, 1, ["catalog", "list", "--catalog", str(path)], [str(path), key, *words])
    # a bounded line: what it says besides the file's path (whose length is the test folder's)
    assert "\u202e" not in line and len(line) - len(str(path)) == pytest.approx(120, abs=100)
    # refused by the command that would have used it too, not blamed on one of its options
    result = run("tension", "--catalog", str(path))
    assert one_error_line(result, 1, str(path), key) == line


# --- 6. --set and --sweep: one rule for units, one cap for samples, the right option named ---

SEWING = ["simulate", "sewing", "--t-end", "0.3s", "--window", "0.2s", "--samples", "301"]


@pytest.mark.parametrize("args, fragments", [
    (["--set", "C4=190"], ["--set", "'C4=190'", "C4 needs a unit, e.g. 'C4=190 N*m/rad'"]),
    (["--sweep", "C4=50:310:14"], ["--sweep", "'C4=50:310:14'", "e.g. 'C4=50N*m/rad:310N*m/rad:14'"]),
    (["--sweep", "C4=50N*m/rad:310:14"], ["--sweep", "C4 needs units on START and STOP"]),
])
def test_set_and_sweep_refuse_a_bare_number_alike(args, fragments, out):
    fails(out, 2, [*SEWING, *args], fragments)


def test_set_and_sweep_read_units_alike():
    from beltcalc.params import parse_assignments, sweep_points
    from beltcalc.sim.scenes import SCENES

    params = SCENES["sewing"].params
    assert parse_assignments(params, ["C4=0.19 kN*m/rad"])["C4"] == pytest.approx(190.0, rel=1e-12)
    name, points = sweep_points(params, "C4=50N*m/rad:0.31kN*m/rad:3")
    assert name == "C4" and points == pytest.approx([50.0, 180.0, 310.0], rel=1e-12)


def test_a_sweep_of_a_whole_number_names_sweep(out):
    fails(out, 1, ["simulate", "roller-table", "--sweep", "rollers=1:2:10000"],
          ["--sweep rollers", "1.0001", "whole number"])


@pytest.mark.parametrize("args, code, fragments", [
    (["--set", "samples=1e12"], 2, ["--set", "'samples=1e12'", "2..10,000,000", "--samples"]),
    (["--sweep", "samples=100:1e12:2"], 2, ["--sweep", "2..10,000,000", "--samples"]),
    (["--samples", "1000000000000"], 2, ["--samples", "10000000"]),
])
def test_samples_have_one_cap_however_given(args, code, fragments, out):
    fails(out, code, ["simulate", "sewing", *args], fragments)


# --- 7. tolerances are numbers --------------------------------------------------------------

@pytest.mark.parametrize("option", ["--rtol", "--atol"])
@pytest.mark.parametrize("value", ["nan", "NaN", "-nan"])
def test_a_nan_tolerance_is_refused(option, value, out):
    fails(out, 2, [*SEWING, "--method", "rk45", option, value], [option, "nan is not a number", "<x<=1"])


# --- 8. temporaries of a killed write are cleaned by the next write -------------------------

def test_a_later_write_removes_stale_temporaries_of_the_writer(out):
    # issue 27 R13: a temporary a SIGKILL left is removed by the next write into its folder
    # once an hour old; one a writer still holds (locked), a younger one, another program's
    # file of a like name and a file of another pattern stay
    import fcntl

    from beltcalc.cli.output import STALE_TMP_AGE, write_atomic

    old = time.time() - STALE_TMP_AGE - 60
    stale = out / ".beltcalc-k3j9x_2a.tmp"          # left by a SIGKILL before the rename
    fresh = out / ".beltcalc-abcdefgh.tmp"          # a concurrent writer's, still young
    held = out / ".beltcalc-held_0001.tmp"          # old, but a running writer holds its lock
    other = out / ".out.csv.k3j9x_2a.tmp.csv"       # not this writer's pattern
    like = out / ".beltcalc-k3j9x_2a.tmp.bak"       # not exactly its pattern
    for p in (stale, fresh, held, other, like):
        p.write_text("half")
    for p in (stale, held, other, like):
        os.utime(p, (old, old))
    fd = os.open(held, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        write_atomic(out / "out.csv", "a,b\n")
    finally:
        os.close(fd)
    assert sorted(p.name for p in out.iterdir()) == sorted(["out.csv", fresh.name, held.name, other.name, like.name])
    assert (out / "out.csv").read_text() == "a,b\n"


# --- 9. Python warnings never reach stderr ---------------------------------------------------

def _warn_then(monkeypatch, fail: bool):
    import warnings

    import beltcalc.data.catalogs
    from beltcalc.errors import CatalogError

    real = beltcalc.data.catalogs.load_catalog

    def noisy(extra=()):
        warnings.warn("Mean of empty slice", RuntimeWarning)
        if fail:
            raise CatalogError("mine.toml: belts[0]: broken")
        return real(extra)
    monkeypatch.setattr(beltcalc.data.catalogs, "load_catalog", noisy)


def test_a_python_warning_is_not_on_stderr_of_a_failing_run(monkeypatch, out):
    _warn_then(monkeypatch, fail=True)
    line = fails(out, 1, ["catalog", "list"], ["mine.toml: belts[0]: broken"])
    assert "RuntimeWarning" not in line


def test_a_python_warning_is_not_on_stderr_of_a_good_run(monkeypatch):
    _warn_then(monkeypatch, fail=False)
    result = run("catalog", "list", "--json")
    assert result.exit_code == 0 and result.stderr == ""
    with pytest.warns(RuntimeWarning, match="Mean of empty slice"):   # --debug shows it again
        debug = run("--debug", "catalog", "list", "--json")
    assert debug.exit_code == 0


# --- names and file names a user types: quoted short, on one line --------------------------

@pytest.mark.parametrize("args, code, fragments", [
    (["tension", "--belt", "x" * 100_000], 2, ["--belt", "'" + "x" * 40 + "'... (100000 characters)"]),
    (["tension", "--belt", "AT\u202e10"], 2, ["--belt", "'AT\\u202e10'"]),
    (["tension", "--catalog", "a\nb.toml"], 2, ["--catalog", "a\\nb.toml", "does not exist"]),
    (["motor-size", "--scene", "s" * 300], 2, ["--scene", "(300 characters)"]),
])
def test_a_typed_name_is_echoed_short_on_one_line(args, code, fragments, out):
    line = fails(out, code, args, fragments)
    assert len(line) == pytest.approx(150, abs=150) and "\u202e" not in line


def test_an_allocation_too_large_is_one_line_exit_1(monkeypatch, out):
    # whatever check misses a size (here a stand-in for --dt 1e-12s), the boundary says what
    # happened and what to lower, not "internal error"
    import beltcalc.data.catalogs

    def huge(extra=()):
        raise MemoryError("Unable to allocate 7.28 TiB for an array")
    monkeypatch.setattr(beltcalc.data.catalogs, "load_catalog", huge)
    fails(out, 1, ["catalog", "list"], ["not enough memory", "7.28 TiB", "fewer --samples"])


# --- issue 27: a unit without a number, messages that name what was given, no inf ----------

@pytest.mark.parametrize("args, fragments", [
    # R6: each was read as 1 of the unit, exit 0
    (["tension", "--mass", "kg"], ["--mass", "'kg' has no number", "give a number and its unit, e.g. '10 kg'"]),
    (["chain", "--speed", "rpm"], ["--speed", "'rpm' has no number", "e.g. '10 rpm'"]),
    (["simulate", "sewing", "--set", "C4=N*m/rad"], ["--set", "'N*m/rad' has no number", "e.g. '10 N*m/rad'"]),
    (["simulate", "sewing", "--sweep", "C4=N*m/rad:N*m/rad:2"], ["--sweep", "has no number"]),
    (["simulate", "sewing", "--steady-state-only", "--vary", "C4=normal(N*m/rad,5%)", "--runs", "3"],
     ["--vary", "'N*m/rad' has no number"]),
    (["motor-size", "--sweep", "accel=rad/s^2:rad/s^2:2"], ["--sweep", "'rad/s^2' has no number"]),
])
def test_a_unit_without_a_number_is_refused_at_every_entry(args, fragments, out):
    line = fails(out, 2, args, fragments)
    assert "--power" not in line


def test_a_unit_without_a_number_in_a_drive_file_names_the_key(tmp_path, out):
    from beltcalc.data.catalogs import builtin_dir

    text = (builtin_dir() / "drives" / "friswell_5_disks.toml").read_text()
    assert 'inertia = "3.5e-3 kg*m^2"' in text
    path = tmp_path / "drive.toml"
    path.write_text(text.replace('inertia = "3.5e-3 kg*m^2"', 'inertia = "kg*m^2"', 1))
    fails(out, 1, ["modes", str(path)], ["drive.toml", "disk1", "inertia", "'kg*m^2' has no number"])


def test_unit_reader_refuses_a_unit_alone():
    with pytest.raises(QuantityError, match="'kg' has no number; give a number and its unit, e.g. '10 kg'"):
        parse_quantity("kg", "kg")
    with pytest.raises(QuantityError, match="'rpm' has no number"):
        parse_quantity("rpm", "rad/s")
    assert parse_quantity("5/s", "1/s") == pytest.approx(5.0, rel=1e-15)


@pytest.mark.parametrize("drive", ["", " ", "."])
def test_an_empty_drive_or_a_folder_is_a_usage_error(drive, out):
    # R10: `beltcalc modes ''` was "Error: .: cannot be read (Is a directory)", exit 1
    fails(out, 2, ["modes", drive], ["DRIVE", "drive" if drive.strip() == "" else "folder"])


def test_a_folder_as_drive_file_is_a_usage_error(tmp_path, out):
    fails(out, 2, ["simulate", "drive", str(tmp_path)], ["FILE", "is a folder, not a drive file"])


def test_the_error_tolerance_is_a_tolerance(out):
    # R12: `--error-tol nan` was exit 1 ("error tolerance nan is not allowed"), --rtol nan exit 2
    fails(out, 2, [*SEWING, "--error-tol", "nan"], ["--error-tol", "nan is not a number", "0<x<1"])
    fails(out, 2, [*SEWING, "--error-tol", "2"], ["--error-tol", "0<x<1"])


@pytest.mark.parametrize("args, given", [(["--speed", "1rpm"], "(--power) at 1 rpm (--speed)"),
                                         (["--speed", "1rpm", "--torque", "1e6N*m"], "(--torque x --speed)")])
def test_no_chain_names_what_was_given(args, given, out):
    # R11: `chain --speed ...` blamed --power (the default the user never gave)
    line = fails(out, 1, ["chain", *args], ["no chain in the catalog carries", given])
    assert not line.startswith("Error: --power:")


def test_no_inf_in_a_warning():
    # R4: "utilisation inf%"
    result = run("tension", "--mass", "1e-320kg")
    assert result.exit_code == 0, result.output
    assert "inf" not in result.output.replace("info", "")
    assert "belt mass on the span FAILS" in result.stderr and "beyond any finite figure" in result.stderr


def test_a_torque_beyond_a_float_is_one_line_naming_it(out):
    # R4: `chain --chain 10B-1 --torque 1e308N*m` printed "carry inf kW", "inf W must be <= 2688 W", exit 0
    fails(out, 1, ["chain", "--chain", "10B-1", "--torque", "1e308N*m"], ["--torque", "beyond a float"])


def test_a_figure_beyond_a_float_is_an_empty_csv_field(out):
    # R5: the CSV held 'inf' where the table shows '-' and the JSON null
    result = run("tension", "--span-length", "1e-320m", "--csv", str(out / "o.csv"))
    assert result.exit_code == 0, result.output
    rows = dict(line.split(",", 1) for line in (out / "o.csv").read_text().splitlines())
    assert rows["span_frequency"] == ",Hz"
    assert rows["bearing_torque"] == ",N m"                       # none: empty too (was 'None')
    assert "inf" not in (out / "o.csv").read_text() and "None" not in (out / "o.csv").read_text()
    shown = run("tension", "--span-length", "1e-320m", "--json")
    assert json.loads(shown.stdout)["span_frequency"]["value"] is None


def test_a_study_in_which_no_run_succeeds_exits_1(out):
    # R8: every run failed, exit 0 (the same values as --sweep exit 1)
    args = ["simulate", "sewing", "--steady-state-only", "--vary", "C4=uniform(-300N*m/rad,-100N*m/rad)",
            "--runs", "20"]
    fails(out, 1, args, ["none of the 20 runs succeeded", "the first (run 0)", "--vary C4", ">= 0 N*m/rad"])


def test_a_drive_file_with_a_byte_order_mark_reads(tmp_path):
    from beltcalc.data.catalogs import builtin_dir

    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + (builtin_dir() / "drives" / "friswell_5_disks.toml").read_bytes())
    plain = run("modes", "friswell_5_disks", "--json")
    with_bom = run("modes", str(path), "--json")
    assert with_bom.exit_code == 0 and plain.exit_code == 0, with_bom.output
    a, b = json.loads(plain.stdout), json.loads(with_bom.stdout)
    # the same drive, the same answer: Friswell et al. example 9.7.1, 81.21 ... 536.36 Hz
    assert b["undamped_frequencies"]["value"] == pytest.approx(a["undamped_frequencies"]["value"], rel=1e-12)
    assert b["undamped_frequencies"]["value"] == pytest.approx([81.21, 141.21, 378.95, 536.36], abs=0.01)


def test_an_error_line_never_prints_inf(out):
    # R4, R11: `simulate sewing --set U12=1e-200` said "an input at inf rad/s turns inf rad";
    # what a user typed, quoted, stays as typed
    line = fails(out, 1, ["simulate", "sewing", "--set", "U12=1e-200"],
                 ["--set U12: at 1e-200,", "frequency omega of load on 3 overflows a float (beyond 1e308 rad/s)"])
    assert "inf" not in line and "--drive" not in line
    fails(out, 2, ["tension", "--mass", "inf kg"], ["'inf kg'", "not a finite number"])


@pytest.mark.parametrize("args, fragments", [
    (["modes", "conveyor", "--set", "reducer.ratio=1e-299"],
     ["Error: --set reducer.ratio: at 1e-299,", "1e+299 times as fast", "overflows a float"]),
    (["modes", "conveyor", "--set", "output_shaft.diameter=1e100m"],
     ["Error: --set output_shaft.diameter: at 1e+100 m,", "shaft 'output_shaft'", "overflows a float"]),
    (["simulate", "roller-table", "--set", "stage1_ratio=1e200"],
     ["Error: --set stage1_ratio: at 1e+200,", "overflows a float"]),
    (["simulate", "linear-axis", "--set", "pulley_diameter=1e300m"],
     ["Error: --set pulley_diameter: at 1e+300 m,", "overflows a float"]),
    (["modes", "conveyor", "--set", "output_shaft.length=1e-310m"],
     ["Error: --set output_shaft.length: at 1e-310 m,", "stiffness C of coupling output_shaft", "overflows a float"]),
    (["simulate", "drive", "conveyor", "--set", "output_shaft.length=1e-310m"],
     ["Error: --set output_shaft.length: at 1e-310 m,", "overflows a float"]),
    (["modes", "sewing", "--set", "12.stiffness=1e300N*m/rad", "--set", "1.inertia=1e-300kg*m^2"],
     ["Error: --set 12.stiffness: at 1e+300 N*m/rad,", "the stiffness on 1 over its inertia"]),
])
def test_an_overflow_names_the_value_set(args, fragments, out):
    # R2: `internal error: OverflowError` from a float power (R11: the length named the built-in file)
    line = fails(out, 1, args, fragments)
    assert "internal error" not in line and "conveyor.toml" not in line and "inf" not in line


def test_an_overflow_of_a_drive_files_own_value_names_the_file(tmp_path, out):
    from beltcalc.data.catalogs import builtin_dir

    text = (builtin_dir() / "drives" / "conveyor.toml").read_text()
    path = tmp_path / "big.toml"
    path.write_text(text.replace('ratio = 10', 'ratio = 1e-299', 1))
    assert 'ratio = 1e-299' in path.read_text()
    fails(out, 1, ["modes", str(path)], ["big.toml", "overflows a float"])


def test_an_infinite_window_suggests_a_finite_one(tmp_path, out):
    # "window = inf" suggested writing "inf s", which is refused too
    path = tmp_path / "w.toml"
    path.write_text('[drive]\nt_end = "1 s"\nwindow = inf\n[[node]]\nname = "a"\ninertia = "1 kg*m^2"\n')
    line = fails(out, 1, ["modes", str(path)], ["window", "needs its unit", 'e.g. "1 s"'])
    assert "inf s" not in line


def test_an_unreachable_scheduler_fails_in_seconds(out, monkeypatch):
    # it took 20 s (distributed's connect timeout was 20 s); port 1 refuses at once. The client
    # is asked for a 3 s connect timeout (no clock read here: the call's arguments)
    distributed = pytest.importorskip("distributed")
    asked = []
    real = distributed.Client

    def client(*args, **kw):
        asked.append(kw.get("timeout"))
        return real(*args, **kw)

    monkeypatch.setattr(distributed, "Client", client)
    fails(out, 1, ["simulate", "sewing", "--steady-state-only", "--sweep", "C4=100N*m/rad:200N*m/rad:2",
                   "--scheduler", "tcp://127.0.0.1:1"],
          ["--scheduler", "cannot reach the Dask scheduler", "after 3 s"])
    assert asked == ["3s"]


def test_json_phases_are_in_rad():
    # the JSON gave phases in degrees; SI is rad (the tables keep degrees)
    import math

    response = run("response", "--json")
    assert response.exit_code == 0, response.output
    for r in json.loads(response.stdout)["responses"]:
        assert r["phase"]["unit"] == "rad"
        assert all(-math.pi - 1e-12 <= p <= math.pi + 1e-12 for p in r["phase"]["value"] if p is not None)
    modes = run("modes", "friswell_5_disks", "--json")
    assert modes.exit_code == 0, modes.output
    shapes = [m["shape"] for m in json.loads(modes.stdout)["modes"] if m["kind"] == "oscillatory"]
    phases = [n["phase"] for s in shapes for n in s["nodes"].values()]
    assert phases and all(p["unit"] == "rad" for p in phases)
    # Friswell's five disks, mode 1: disks 1-4 against disk 5 (180 deg in the table), pi rad here
    assert [abs(n["phase"]["value"]) for n in shapes[0]["nodes"].values()] == pytest.approx(
        [math.pi] * 4 + [0.0], abs=1e-9)


def test_text_inputs_of_a_simulation_have_the_input_shape():
    # simulate's JSON `inputs` gave a name (belt, routing) without `value`/`unit`; the design
    # commands echo one as {"text", "value": null, "unit": "", "origin"}
    result = run("simulate", "drive", "conveyor", "--json")
    assert result.exit_code == 0, result.output
    inputs = json.loads(result.stdout)["inputs"]
    assert inputs["upper.belt"]["value"] is None and inputs["upper.belt"]["unit"] == ""
    assert inputs["upper.belt"]["text"] == "BRECO-AT10"
    for name, item in inputs.items():
        assert set(item) == {"text", "value", "unit", "origin"}, (name, item)
