"""``beltcalc.design.motor_report``: the motor-size report built in the library, called as a
Python user calls it (no command line). Reference values: the hand computation of the WDU
scene in tests/test_cli_motor_size.py (module docstring).
"""

from __future__ import annotations

import csv
import io
import math

import pytest

from beltcalc.design.motor_report import (PROFILE_HEADER, inherited_rows, profile_csv, profile_samples, report_dict,
                                          report_sections, sweep_table)
from beltcalc.errors import InputError


def sized(motor: str | None = None, **given):
    """The WDU scene sized (and its resolved values), as ``beltcalc motor-size`` sizes it."""
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.params import resolve
    from beltcalc.data.scenefile import load_scene
    from beltcalc.design.sizing import DutyOptions, size_cycle
    from beltcalc.design.axis_inputs import PARAMS, SizingInputs

    cat = load_catalog()
    values = resolve(load_scene("wdu", command="motor-size"), PARAMS, given)
    inp = SizingInputs.from_values({k: v.value for k, v in values.items()})
    return size_cycle(inp, cat.belt(values["belt"].value), list(cat.motors.values()),
                      cat.motor(motor) if motor else None, DutyOptions()), values


def rows(sections) -> dict:
    return {r.key: r for sec in sections for r in sec.rows}


def test_sections_of_the_wdu_axis_by_hand():
    s, _ = sized()
    sections = report_sections(s)
    assert [sec.path for sec in sections] == [("motion",), ("inertia",), ("torque",), ("zone",),
                                              ("regeneration",)]
    r = rows(sections)
    # J_red = 6.0710488e-4 kg m^2, peak 2.1013978 N m, RMS 0.6910177 N m, E29 66.017358 J, exact 32.008605 J
    assert r["reflected_inertia"].value == pytest.approx(6.0710488e-4, rel=1e-7)
    assert r["peak_torque"].value == pytest.approx(2.1013978, rel=1e-7)
    assert r["rms_torque"].value == pytest.approx(0.6910177, rel=1e-6)
    assert r["accel_energy"].value == pytest.approx(66.017358, rel=1e-7)
    assert r["accel_energy_exact"].value == pytest.approx(32.008605, rel=1e-7)
    assert r["inertia_ratio"].value == pytest.approx(6.5888109, rel=1e-7)


def test_no_motor_fits_names_the_input_in_the_library_and_the_option_on_the_command_line():
    # --gear-ratio 1: the inertia ratio fails for every motor (test_cli_motor_size.py); no motor to report
    s, _ = sized(gear_ratio=1.0)
    assert s.shown is None
    sections = report_sections(s)
    assert [sec.path for sec in sections] == [("motion",), ("inertia",)]
    note = rows(sections)["inertia_ratio"].note
    assert note.endswith("give motor NAME")       # the library's name of the input, as str(error) shows it
    cli_note = rows(report_sections(s, lambda n: "--" + n.replace("_", "-")))["inertia_ratio"].note
    assert cli_note.endswith("give --motor NAME")
    obj = report_dict(s, sections)
    assert obj["peak_torque"] == {"value": None, "unit": "N*m",
                                  "reason": "no motor fits, so there is no torque profile; give motor NAME"}
    assert obj["selected_motor"] is None and obj["reported_motor"] is None
    with pytest.raises(InputError, match="no torque profile"):
        profile_samples(s)


def test_json_object_keeps_a_value_beyond_a_float_as_null_with_the_reason():
    s, _ = sized()
    obj = report_dict(s, report_sections(s))
    assert obj["peak_torque"] == {"value": pytest.approx(2.1013978, rel=1e-7), "unit": "N m"}
    assert obj["reported_motor"] == "SGM7J-06A"
    # four phases, the smallest margin at the end of the acceleration (test_cli_motor_size_cycles.py)
    assert [p["phase"] for p in obj["phases"]] == ["accelerate", "cruise", "decelerate", "dwell"]
    assert obj["zone"]["margin"]["value"] == pytest.approx(6.69 - 2.1013978, rel=1e-6)
    from beltcalc.report import Row, Section

    bad = [Section(("x",), "x", [Row("x", "x", math.inf, "N")])]
    assert report_dict(s, bad)["x"] == {"value": None, "unit": "N", "reason": "beyond the range of a float: "
                                        "an input is out of a physical range"}


def test_profile_csv_is_the_samples_with_every_digit():
    s, _ = sized()
    samples = profile_samples(s)
    assert len(samples) == 4 * 21
    # end of the acceleration: t = 0.1 s, 2.1013978 N m at 314.15927 rad/s, 660.17358 W
    assert samples[20][0] == pytest.approx(0.1, rel=1e-12)
    assert samples[20][3] == pytest.approx(2.1013978, rel=1e-7)
    assert samples[20][4] == pytest.approx(660.17358, rel=1e-7)
    table = list(csv.reader(io.StringIO(profile_csv(s))))
    assert tuple(table[0]) == PROFILE_HEADER
    assert [tuple(float(x) for x in row) for row in table[1:]] == samples


def test_inherited_rows_label_each_value_by_the_callers_name():
    _, values = sized()
    inherited = {k: v for k, v in values.items() if k in ("mass", "speed")}
    out = inherited_rows(inherited, lambda n: f"<{n}>")
    assert [(r.key, r.label) for r in out] == [("scene_mass", "<mass>"), ("scene_speed", "<speed>")]
    assert out[1].note.startswith("motor side: motor shaft")      # the scene gives 3000 rpm


def test_sweep_table_checks_each_point_against_the_motor():
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.params import resolve
    from beltcalc.data.scenefile import load_scene
    from beltcalc.design.sizing import sweep
    from beltcalc.design.axis_inputs import PARAMS, SizingInputs

    cat = load_catalog()
    values = resolve(load_scene("wdu", command="motor-size"), PARAMS, {})
    inp = SizingInputs.from_values({k: v.value for k, v in values.items()})
    motor = cat.motor("SGM7J-06A")
    points = sweep(inp, cat.belt(values["belt"].value), motor, "accel", [100.0, 1e5], "rad/s^2")
    st = sweep_table("accel", "rad/s^2", points, motor, 0.0)
    assert st.key == "accel_rad_per_s2" and st.header[0] == st.key and len(st.header) == 9
    assert [r[0] for r in st.rows] == [100.0, 1e5]
    # 1e5 rad/s^2 needs J_red eps = 6.0710488e-4 * 1e5 = 60.7 N m and more: over T_max 6.69 N m; 100 rad/s^2 passes
    assert [v for v, _ in st.failed] == [1e5]
    assert any(w.startswith("SGM7J-06A peak torque FAILS") and "(at 1 of 2 points: accel = 100000 rad/s^2)" in w
               for w in st.warnings)
    assert all("--" not in w for w in st.warnings)
