"""Tests of beltcalc.design.tension (composition with catalog data) and the `beltcalc tension` CLI."""

import json
import math

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings, strategies as st

from beltcalc.data.catalogs import load_catalog
from beltcalc.cli.main import cli
from beltcalc.errors import InputError, UnknownNameError
from beltcalc.design.tension import TensionInputs, design_tension, select_width

CAT = load_catalog()
WDU = TensionInputs(center_distance=1.245, width=0.025, mass=50.0, accel=10.0, tension_accel=0.1,
                    tension_speed=0.005, mu=0.2, pulley_diameter=0.128)


def run(*args):
    return CliRunner().invoke(cli, list(args))


def test_worked_example_library():
    # Wojtkowiak et al. 2021, section 3.2: 505.1 N, 1.15 mm (exactly 1.143 mm), 0.63 N m, 1.95/13.0 deg
    r = design_tension(WDU, CAT.belt("AT10"), CAT.thread("M10x1"))
    assert r.tension_peak == pytest.approx(505.1, abs=0.05)
    assert r.pretension_displacement * 1e3 == pytest.approx(1.143, abs=0.005)
    assert r.bolt.torque == pytest.approx(0.63, abs=0.005)
    assert math.degrees(r.bolt.lead_angle) == pytest.approx(1.95, abs=0.01)
    assert math.degrees(r.bolt.friction_angle) == pytest.approx(13.0, abs=0.01)
    assert r.damping == pytest.approx(20.0, rel=1e-12)
    assert "catalog value" in r.damping_source
    assert r.utilisation == pytest.approx(505.1 / 2200, rel=1e-4)
    assert r.warnings == ()


def test_worked_example_cli_json():
    res = run("tension", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    expected = {
        "tension_peak": (505.1, "N", 0.05), "pretension_displacement": (1.143e-3, "m", 5e-6),
        "bolt_torque": (0.63, "N*m", 0.005), "lead_angle": (math.radians(1.95), "rad", math.radians(0.01)),
        "friction_angle": (math.radians(13.0), "rad", math.radians(0.01)),
        "teeth": (125.5, "1", 1e-9), "belt_mass": (0.14193, "kg", 1e-8),
        "substitute_mass": (5.74578e-4, "kg", 1e-9), "stiffness": (441767.07, "N/m", 0.01),
        "damping": (20.0, "N*s/m", 1e-12), "utilisation": (0.229591, "1", 1e-6),
        "span_frequency": (26.732, "Hz", 0.001),
    }
    for key, (value, unit, tol) in expected.items():
        assert out[key]["unit"] == unit, key
        assert out[key]["value"] == pytest.approx(value, abs=tol), key


def test_table_output_shows_the_example():
    res = run("tension")
    assert res.exit_code == 0
    for text in ("505.1", "1.143", "0.631", "1.95", "13.0", "BRECO-AT10"):
        assert text in res.stdout


def test_csv_rows(tmp_path):
    path = tmp_path / "t.csv"
    res = run("tension", "--csv", str(path))
    assert res.exit_code == 0
    lines = path.read_text().splitlines()
    assert lines[0] == "quantity,value,unit"
    rows = {ln.split(",")[0]: ln.split(",") for ln in lines[1:]}
    assert float(rows["tension_peak"][1]) == pytest.approx(505.1, abs=0.05)
    assert rows["tension_peak"][2] == "N"
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left


def test_fitted_damping_t20():
    # BRECO T20 25 mm, D = 128 mm: 20 pulley teeth -> z_e = 10 (under the page's z_e max 12). The
    # catalog holds the page's 40 rows (issue 28; with its old 3 rows the fit was 47.156 N s/m,
    # R^2 0.659, test_belt.test_damping_fit_by_hand). Reference: numpy's least squares through the
    # origin on the printed rows of tests/test_catalog_tables.py: 66.876 N s/m, R^2 = 0.151.
    import numpy as np

    from test_catalog_tables import PRINTED

    rpm, n_per_cm = np.array(PRINTED["BRECO-T20"][0]).T
    v = rpm * math.pi / 30 * 0.128 / 2
    f_b = (n_per_cm - n_per_cm[0]) * 100 * 0.025 * 10
    (slope,), *_ = np.linalg.lstsq(v[:, None], f_b, rcond=None)
    r_squared = 1 - np.sum((f_b - slope * v) ** 2) / np.sum((f_b - f_b.mean()) ** 2)
    assert (abs(slope), r_squared) == pytest.approx((66.876, 0.151), abs=0.001)
    inp = TensionInputs(**{**WDU.__dict__, "width": 0.025})
    r = design_tension(inp, CAT.belt("T20"), CAT.thread("M10x1"))
    assert r.damping == pytest.approx(abs(slope), rel=1e-12)
    assert r.damping_fit.r_squared == pytest.approx(r_squared, rel=1e-12)
    assert r.damping_fit.points == 40
    assert "fitted" in r.damping_source


def test_rayleigh_option_changes_only_the_mass_terms():
    base = design_tension(WDU, CAT.belt("AT10"), CAT.thread("M10x1"))
    ray = design_tension(TensionInputs(**{**WDU.__dict__, "substitute_mass_model": "rayleigh"}),
                         CAT.belt("AT10"), CAT.thread("M10x1"))
    assert ray.substitute_mass == pytest.approx(0.14193 / 3, rel=1e-12)
    # F differs by (m_rayleigh - m_eq7) * 0.1 m/s^2
    assert ray.tension_peak - base.tension_peak == pytest.approx((0.04731 - 5.74578e-4) * 0.1, rel=1e-4)


def test_select_width():
    # F_t,peak ~ 505 N: safety 1 -> 16 mm (1400 N); safety 3 -> 1515 N > 1400 -> 25 mm (2200 N);
    # safety 5 -> 2525 N > 2200 -> 32 mm (2800 N); safety 6 -> 3030 N: none
    at10, m10 = CAT.belt("AT10"), CAT.thread("M10x1")
    assert select_width(WDU, at10, m10, 1.0).width == pytest.approx(0.016)
    assert select_width(WDU, at10, m10, 3.0).width == pytest.approx(0.025)
    assert select_width(WDU, at10, m10, 5.0).width == pytest.approx(0.032)
    with pytest.raises(InputError, match="no width"):
        select_width(WDU, at10, m10, 6.0)


def test_width_not_in_catalog():
    with pytest.raises(UnknownNameError, match="16, 25, 32"):
        design_tension(TensionInputs(**{**WDU.__dict__, "width": 0.020}), CAT.belt("AT10"), CAT.thread("M10x1"))


def test_belt_without_width_table_needs_overrides():
    at5 = CAT.belt("BRECO-AT5 GEN III")
    with pytest.raises(UnknownNameError, match="give f_tadm, c_spec and belt_weight"):
        design_tension(WDU, at5, CAT.thread("M10x1"))
    # with the three values given it works; damping fitted to its F_tspec table
    inp = TensionInputs(**{**WDU.__dict__, "f_tadm": 1750.0, "c_spec": 437500.0, "belt_weight": 0.09})
    r = design_tension(inp, at5, CAT.thread("M10x1"))
    assert r.stiffness == pytest.approx(437500 / 1.245, rel=1e-12)
    assert r.damping > 0


def test_missing_published_weight_is_an_error_not_a_guess():
    # a width row without a published w_spec (as Elatech AT20's 32-100 mm rows were until its page
    # was read, issue 28; the page prints all six weights): the neighbouring rows are not interpolated
    from dataclasses import replace

    at20 = CAT.belt("AT20")
    no_weight = replace(at20, widths=tuple(replace(w, w_spec=None) if w.width == pytest.approx(0.050) else w
                                           for w in at20.widths))
    inp = TensionInputs(**{**WDU.__dict__, "width": 0.050})
    with pytest.raises(InputError, match="give it with belt_weight"):
        design_tension(inp, no_weight, CAT.thread("M10x1"))
    assert design_tension(inp, at20, CAT.thread("M10x1")).belt_weight == pytest.approx(0.48)   # printed p. 18


def test_bearing_friction_adds_vdi_term():
    res = run("tension", "--json", "--bearing-friction", "0.15", "--bearing-diameter", "15mm")
    out = json.loads(res.stdout)
    # 505.1 N * 0.15 * 0.015 m / 2 = 0.56824 N m on top of 0.6307 N m
    assert out["bolt_torque"]["value"] - out["thread_torque"]["value"] == pytest.approx(0.568238, rel=1e-4)


# --- the same inputs in other units give the same outputs ----------------------------------

KEYS = ("tension_peak", "pretension_displacement", "bolt_torque", "span_frequency", "substitute_mass")


def _json(*args):
    res = run("tension", "--json", *args)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mass=st.floats(1.0, 500.0), accel=st.floats(0.5, 50.0), a_mm=st.floats(200.0, 3000.0),
       speed_mm_s=st.floats(0.1, 50.0))
def test_units_do_not_change_results(mass, accel, a_mm, speed_mm_s):
    si = _json("--mass", f"{mass!r} kg", "--accel", f"{accel!r} m/s^2", "--center-distance",
               f"{a_mm!r} mm", "--tension-speed", f"{speed_mm_s!r} mm/s", "--width", "32mm")
    other = _json("--mass", f"{mass / 0.45359237!r} lb", "--accel", f"{accel / 9.80665!r} g0",
                  "--center-distance", f"{a_mm / 25.4!r}in", "--tension-speed",
                  f"{speed_mm_s * 60 / 1000!r} m/min", "--width", "3.2cm")
    for key in KEYS:
        assert other[key]["value"] == pytest.approx(si[key]["value"], rel=1e-9), key
