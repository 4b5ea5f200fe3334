"""Drive files, issue 28 item 6, through ``beltcalc simulate drive FILE``: an induction motor's
pole pairs inferred from its rated speed and supply (or a given pair that disagrees refused),
every missing or unknown key of a file in one message, gear pairs that reverse, and texts
refused where numbers belong. (A load's frequency in Hz, the item's last symptom, was fixed in
5ba0404 and is held by tests/test_drivefile.py::test_a_load_frequency_in_hz_is_cycles_per_second.)

Rated slip range: NEMA design D (high slip) runs at 5-13 % at rated load, designs A-C and E
below 5 % (EASA Electrical Engineering Handbook, "General Speed-Torque Characteristics", after
NEMA MG 10 table 2-1); beltcalc allows up to 15 %.
"""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from beltcalc.data.catalogs import builtin_dir
from beltcalc.cli.main import cli
from clichecks import edited_copy, ok, one_error_line

DRIVES = builtin_dir() / "drives"

INDUCTION = """[drive]
t_end = "3 s"
window = "2.5 s"

[[node]]
name = "rotor"
inertia = "0.01 kg*m^2"

[[motor]]
name = "m"
kind = "induction"
node = "rotor"
rated_power = "1.1 kW"
rated_speed = "1400 rpm"
breakdown_factor = 2.3
breakdown_slip = 0.2
supply = "50 Hz"
{extra}"""


def run(*args):
    return CliRunner().invoke(cli, ["simulate", "drive", *args])


def write(tmp_path, text: str, name: str = "my_drive.toml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# --- pole pairs -------------------------------------------------------------------------------

def test_pole_pairs_are_inferred_from_the_rated_speed_and_the_supply(tmp_path):
    res = ok(run(write(tmp_path, INDUCTION.format(extra="")), "--json"))
    obj = json.loads(res.stdout)
    # 1400 rpm at 50 Hz: 3000 rpm (1 pair) and 1500 rpm (2 pairs) are above it, 1000 rpm (3) is not:
    # 2 pairs, rated slip 1 - 1400/1500 = 6.67 %. Unloaded, the rotor runs at the synchronous speed
    # 2 pi 50 / 2 = 157.08 rad/s (it ran at 2 pi 50 = 314.16 rad/s with pole_pairs taken as 1)
    assert obj["steady_state"]["nodes"]["rotor"]["speed_mean"]["value"] == pytest.approx(2 * math.pi * 50 / 2,
                                                                                         rel=1e-9)
    [note] = [n for n in obj["notes"] if "pole_pairs" in n]
    assert "pole_pairs = 2, inferred" in note and "rated slip 6.67%" in note


def test_an_inferred_pair_gives_the_file_s_own_given_pair(tmp_path):
    # the conveyor's motor: 1440 rpm at 50 Hz, pole_pairs = 2 in the file; without it, the same drive
    path = DRIVES / "conveyor.toml"
    base = json.loads(ok(run(str(path), "--json", "--samples", "201")).stdout)
    mine = json.loads(ok(run(str(edited_copy(path, tmp_path, "pole_pairs = 2\n", "")), "--json",
                             "--samples", "201")).stdout)
    for node, stats in base["nodes"].items():
        assert mine["nodes"][node]["speed_mean"]["value"] == pytest.approx(stats["speed_mean"]["value"], rel=1e-12)


@pytest.mark.parametrize("pairs, slip", [(1, "53.3%"), (3, "-40.0%")], ids=["too-much-slip", "above-synchronous"])
def test_a_given_pair_that_disagrees_with_the_rated_speed_is_refused(tmp_path, pairs, slip):
    # 1 pair: 3000 rpm synchronous, slip 1 - 1400/3000 = 53.3 %; 3 pairs: 1000 rpm, slip -40 %
    res = run(write(tmp_path, INDUCTION.format(extra=f"pole_pairs = {pairs}\n")))
    one_error_line(res, 1, "motor 'm': pole_pairs:", f"rated slip of {slip}", "rated_speed", "supply")


def test_a_rated_speed_that_fits_no_pole_count_is_refused(tmp_path):
    # 2000 rpm at 50 Hz: only 1 pair (3000 rpm) is above it, slip 33 %, far above any induction motor's
    res = run(write(tmp_path, INDUCTION.format(extra="").replace('"1400 rpm"', '"2000 rpm"')))
    one_error_line(res, 1, "motor 'm': rated_speed: 2000 rpm fits no pole count", "rated slip 33.3%", "supply")


# --- every missing or unknown key at once -----------------------------------------------------

def test_every_missing_key_of_a_motor_is_named_in_one_message(tmp_path):
    text = INDUCTION.format(extra="")
    for line in ('breakdown_factor = 2.3\n', 'breakdown_slip = 0.2\n', 'supply = "50 Hz"\n'):
        text = text.replace(line, "")
    line = one_error_line(run(write(tmp_path, text)), 1, "3 problems")
    for key in ("supply", "breakdown_factor", "breakdown_slip"):
        assert f"motor 'm': {key}: missing" in line, key


def test_unknown_and_missing_keys_of_several_elements_in_one_message(tmp_path):
    text = INDUCTION.format(extra='colour = "red"\n').replace('supply = "50 Hz"\n', "")
    text += '\n[[coupling]]\nname = "c"\nbetween = ["rotor"]\nstifness = "10 N*m/rad"\n'
    line = one_error_line(run(write(tmp_path, text)), 1, "4 problems")
    for fragment in ("motor 'm': colour: unknown key", "coupling 'c': stifness: unknown key",
                     "coupling 'c': stiffness: missing", "motor 'm': supply: missing"):
        assert fragment in line, fragment


def test_one_problem_is_said_as_before(tmp_path):
    text = INDUCTION.format(extra="").replace('supply = "50 Hz"\n', "")
    line = one_error_line(run(write(tmp_path, text)), 1)
    assert line == f"Error: {tmp_path / 'my_drive.toml'}: motor 'm': supply: missing (induction: supply frequency)"


# --- a gear pair that reverses ----------------------------------------------------------------

GEARED = """[drive]
t_end = "1 s"

[[node]]
name = "a"
inertia = "0.01 kg*m^2"

[[node]]
name = "b"
inertia = "0.04 kg*m^2"

[[gear]]
name = "pair"
between = ["a", "b"]
ratio = {ratio}

[[motor]]
name = "drive"
kind = "torque"
node = "a"
torque = [["0 s", "1 N*m"], ["1 s", "1 N*m"]]

[[load]]
name = "brake"
node = "b"
torque = "0.5 N*m"
"""


@pytest.mark.parametrize("ratio", [-2.0, 2.0])
def test_a_gear_pair_reverses_with_a_negative_ratio(tmp_path, ratio):
    obj = json.loads(ok(run(write(tmp_path, GEARED.format(ratio=ratio)), "--json", "--window", "0s")).stdout)
    # by hand: phi_b = phi_a / r, one coordinate phi_a with J = J_a + J_b / r^2 = 0.01 + 0.04 / 4 = 0.02
    # kg m^2; the 0.5 N m load on b acts on a as -0.5 / r (virtual work: T_b dphi_b = (T_b / r) dphi_a),
    # so J w_a' = 1 - 0.5 / r: 1.25 N m for r = -2 (b's load helps: b turns backwards into it), 0.75
    # for r = +2; from rest over 1 s: w_a = (1 - 0.5 / r) / 0.02, w_b = w_a / r
    w_a = (1.0 - 0.5 / ratio) / 0.02
    a, b = obj["nodes"]["a"], obj["nodes"]["b"]
    assert a["speed_max"]["value"] == pytest.approx(w_a, rel=1e-9)
    end_b = b["speed_min"] if ratio < 0 else b["speed_max"]
    assert end_b["value"] == pytest.approx(w_a / ratio, rel=1e-9)
    assert math.copysign(1.0, end_b["value"]) == math.copysign(1.0, ratio)


def test_a_gear_ratio_of_zero_is_refused(tmp_path):
    one_error_line(run(write(tmp_path, GEARED.format(ratio=0))), 1, "gear 'pair': ratio: 0 is not allowed",
                   "must not be 0")


# --- numbers, not texts -----------------------------------------------------------------------

@pytest.mark.parametrize("text, where", [
    (GEARED.format(ratio='"7.5"'), "gear 'pair': ratio"),
    (INDUCTION.format(extra="").replace("breakdown_factor = 2.3", 'breakdown_factor = "2.3"'),
     "motor 'm': breakdown_factor"),
], ids=["gear-ratio", "breakdown-factor"])
def test_a_text_where_a_number_belongs_is_refused(tmp_path, text, where):
    # docs/drive_files.md: "Plain numbers only for ratios, factors, counts"
    one_error_line(run(write(tmp_path, text)), 1, f"{where}: must be a plain number, not the text '")
