"""The catalog loader (:mod:`beltcalc.data.catalogs`) and the invariants of the built-in data."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from beltcalc.data.catalogs import BeltProfile, Catalog, Motor, Thread, builtin_dir, load_catalog
from beltcalc.errors import BeltcalcError, CatalogError, UnknownNameError

ROOT = Path(__file__).resolve().parents[1]
RPM = 2.0 * math.pi / 60.0


@pytest.fixture(scope="module")
def cat() -> Catalog:
    return load_catalog()


def belts(cat):
    return list(cat.belts.values())


# --- the built-in data -------------------------------------------------------------------

def test_builtin_catalog_is_complete(cat):
    assert {b.name for b in cat.belts.values()} == {
        "BRECO-AT10", "BRECO-T2.5", "BRECO-T20", "BRECO-AT5 GEN III",
        "Elatech-T2.5", "Elatech-T5", "Elatech-AT5", "Elatech-ATL5", "Elatech-AT20",
    }
    assert {"M6", "M8", "M10", "M12", "M16", "M8x1", "M10x1", "M10x1.25"} <= {t.name for t in cat.threads.values()}
    assert {"SGM7J-04A", "SGM7A-15A", "SGM7A-30A", "SGMAH-04A"} <= {m.name for m in cat.motors.values()}
    assert builtin_dir().is_dir()
    for entry in [*cat.belts.values(), *cat.threads.values(), *cat.motors.values()]:
        assert entry.source.document.strip(), entry.name
        assert Path(entry.source.path).is_file(), entry.name


def test_c_spec_over_f_tadm_matches_the_stated_ratio(cat):
    checked = 0
    for belt in belts(cat):
        if belt.C_spec_per_F_Tadm is None:
            continue
        for row in belt.widths:
            if row.C_spec is None or row.F_Tadm is None:
                continue
            assert row.C_spec / row.F_Tadm == pytest.approx(belt.C_spec_per_F_Tadm, rel=0.01), \
                (belt.name, row.width)
            checked += 1
    assert checked >= 30  # every width row of every profile that has the ratio


def test_belt_weight_rises_with_width(cat):
    for belt in belts(cat):
        weights = [row.w_spec for row in belt.widths if row.w_spec is not None]
        assert all(b > a for a, b in zip(weights, weights[1:])), (belt.name, weights)


def test_widths_sorted(cat):
    for belt in belts(cat):
        widths = [row.width for row in belt.widths]
        assert widths == sorted(widths), belt.name
        assert len(set(widths)) == len(widths), belt.name


def test_specific_tooth_load_falls_with_speed(cat):
    tables = 0
    for belt in belts(cat):
        if not belt.F_tspec:
            continue
        tables += 1
        speeds = [s for s, _ in belt.F_tspec]
        loads = [f for _, f in belt.F_tspec]
        assert speeds[0] == 0.0, belt.name
        assert all(b > a for a, b in zip(speeds, speeds[1:])), (belt.name, speeds)
        assert all(b < a for a, b in zip(loads, loads[1:])), (belt.name, loads)
    assert tables >= 6


def test_thread_pitch_diameter_is_iso_724(cat):
    for thread in cat.threads.values():
        assert thread.d2 == pytest.approx(thread.d - 0.649519 * thread.P, abs=1e-6), thread.name  # 0.001 mm
        assert thread.flank_angle == pytest.approx(math.radians(60.0)), thread.name


def test_motor_ratings_consistent(cat):
    for motor in cat.motors.values():
        assert motor.T_max > motor.T_n, motor.name
        assert motor.n_max >= motor.n_rated, motor.name
        assert motor.T_n * motor.n_rated == pytest.approx(motor.P, rel=0.03), motor.name


@pytest.mark.parametrize("name", ["SGM7A-15A", "SGM7A-30A"])
def test_noted_sgm7a_torques_are_2_6_percent_above_power(cat, name):
    motor = cat.motor(name)
    assert motor.T_n * motor.n_rated / motor.P == pytest.approx(1.026, abs=0.001)


def test_si_conversion_at10_and_sgm7j(cat):
    at10 = cat.belt("AT10")
    assert at10.pitch == pytest.approx(0.010)
    row = at10.width_row(0.025)
    assert row.width == pytest.approx(0.025)
    assert row.F_Tadm == pytest.approx(2200.0)
    assert row.C_spec == pytest.approx(5.5e5)
    assert row.w_spec == pytest.approx(0.114)
    assert at10.damping == pytest.approx(20.0)
    motor = cat.motor("SGM7J-04A")
    assert motor.J == pytest.approx(0.486e-4, rel=1e-9)
    assert motor.n_max == pytest.approx(628.3, abs=0.05)
    assert motor.n_max == pytest.approx(6000 * RPM, rel=1e-12)
    assert motor.n_rated == pytest.approx(3000 * RPM, rel=1e-12)
    assert motor.P == pytest.approx(400.0)
    m10 = cat.thread("M10x1")
    assert (m10.d, m10.P, m10.d2) == (pytest.approx(0.010), pytest.approx(0.001), pytest.approx(0.00935))
    t20 = cat.belt("T20")
    assert t20.F_tspec[14][0] == pytest.approx(1000 * RPM)   # the 15th printed row (tests/test_catalog_tables.py)
    assert t20.F_tspec[14][1] == pytest.approx(5720.0)  # 57.2 N/cm


def test_width_row_unknown_lists_the_catalog_widths(cat):
    with pytest.raises(UnknownNameError, match=r"20 mm .*16, 25, 32 mm") as info:
        cat.belt("AT10").width_row(0.020)
    assert info.value.param == "width"
    assert info.value.exit_code == 2


# --- lookups -----------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["AT10", "at10", "BRECO-AT10", "breco-at10", "  Breco-At10 "])
def test_belt_lookup_by_alias_and_full_name(cat, name):
    assert cat.belt(name).name == "BRECO-AT10"


def test_other_lookups_case_insensitive(cat):
    assert cat.belt("at5 gen iii").name == "BRECO-AT5 GEN III"
    assert cat.belt("elatech-at5").name == "Elatech-AT5"
    assert cat.belt("AT5").name == "Elatech-AT5"  # BRECO's is "AT5 GEN III"
    assert cat.thread("m10x1").name == "M10x1"
    assert cat.motor("sgm7j-04a").name == "SGM7J-04A"
    assert isinstance(cat.entry("M10x1"), Thread)
    assert isinstance(cat.entry("SGM7J-04A"), Motor)
    assert isinstance(cat.entry("t20"), BeltProfile)


def test_ambiguous_profile_names_both(cat):
    with pytest.raises(UnknownNameError, match="ambiguous") as info:
        cat.belt("T2.5")
    assert "BRECO-T2.5" in str(info.value) and "Elatech-T2.5" in str(info.value)
    assert str(info.value).startswith("belt: ")  # the library names its parameter; the CLI maps it to --belt


def test_unknown_names_suggest_close_ones(cat):
    with pytest.raises(UnknownNameError, match="AT10") as info:
        cat.belt("AT11")
    assert info.value.param == "belt"
    with pytest.raises(UnknownNameError, match="M10x1"):
        cat.thread("M10x2")
    with pytest.raises(UnknownNameError, match="SGM7J-04A"):
        cat.motor("SGM7J-04")
    with pytest.raises(UnknownNameError):
        cat.thread("AT10")  # belts are not threads


# --- the loader on user files ------------------------------------------------------------

def _readme_toml_example() -> str:
    """The catalog example of docs/catalogs.md: the ```toml block that has a [source] table."""
    text = (ROOT / "docs" / "catalogs.md").read_text()
    blocks = [m.group(1) for m in re.finditer(r"^```toml\n(.*?)^```$", text, flags=re.S | re.M)]
    catalog = [b for b in blocks if "[source]" in b]
    assert catalog, "docs/catalogs.md has no ```toml catalog block"
    return catalog[0]


def test_readme_catalog_example_loads(tmp_path):
    path = tmp_path / "acme.toml"
    path.write_text(_readme_toml_example())
    cat = load_catalog([path])
    assert str(path) in cat.files
    belt = cat.belt("Acme-AT10")
    assert belt.pitch == pytest.approx(0.010)
    assert belt.z_e_max == 12
    assert belt.damping == pytest.approx(25.0)
    assert belt.width_row(0.025).F_Tadm == pytest.approx(2200.0)
    assert belt.F_tspec[0] == (pytest.approx(0.0), pytest.approx(4850.0))
    assert belt.F_tspec[1] == (pytest.approx(1000 * RPM), pytest.approx(3540.0))
    assert belt.source.document == "Acme belt catalogue 2026"
    thread = cat.thread("M12x1.5")
    assert thread.d2 == pytest.approx(0.011026)
    assert thread.d2 == pytest.approx(thread.d - 0.649519 * thread.P, abs=1e-6)
    motor = cat.motor("MyMotor-400")
    assert motor.J == pytest.approx(0.486e-4)
    assert motor.n_rated == pytest.approx(3000 * RPM)
    # the built-in AT10 is still there, but "AT10" alone is now ambiguous
    assert cat.belt("BRECO-AT10").pitch == pytest.approx(0.010)
    with pytest.raises(UnknownNameError, match="ambiguous"):
        cat.belt("AT10")


def test_top_level_units_and_entry_override(tmp_path):
    path = tmp_path / "units.toml"
    path.write_text("""
units = { d = "in", P = "mm", d2 = "mm", flank_angle = "deg" }
[source]
document = "test"
[[threads]]
name = "T-inch"
d = 0.5
P = 2
d2 = 11.4
flank_angle = 60
[[threads]]
name = "T-mm"
d = 12
P = 2
d2 = 10.7
flank_angle = 60
units = { d = "mm" }
""")
    cat = load_catalog([path])
    assert cat.thread("T-inch").d == pytest.approx(0.0127)
    assert cat.thread("T-mm").d == pytest.approx(0.012)
    assert cat.thread("T-mm").d2 == pytest.approx(0.0107)


SOURCE = '[source]\ndocument = "Test catalogue"\n'
BELT_UNITS = 'units = { pitch = "mm", width = "mm", F_Tadm = "N", C_spec = "N", w_spec = "kg/m" }\n'
GOOD_ROWS = "widths = [ { width = 16, F_Tadm = 1400 }, { width = 25, F_Tadm = 2200 } ]\n"


def belt(manufacturer="Acme", profile="XL9", body=BELT_UNITS + GOOD_ROWS) -> str:
    return f'[[belts]]\nmanufacturer = "{manufacturer}"\nprofile = "{profile}"\npitch = 10\n{body}'


def motor(name: str, T_n: float, T_max: float) -> str:
    return (f'[[motors]]\nname = "{name}"\nP = 400\nT_n = {T_n}\nT_max = {T_max}\nJ = 0.5\n'
            'n_rated = 3000\nn_max = 6000\n'
            'units = { P = "W", T_n = "N*m", T_max = "N*m", J = "kg*cm^2", n_rated = "rpm", n_max = "rpm" }\n')

def chain(extra: str = "", loads: str = "[10, 20]") -> str:
    return ('[[chains]]\nname = "Q1"\npitch = 12.7\nroller_diameter = 8.5\ninner_width = 7.7\npin_diameter = 4.4\n'
            f'breaking_load = {loads}\n{extra}units = {{ pitch = "mm", roller_diameter = "mm", inner_width = "mm", '
            'pin_diameter = "mm", breaking_load = "kN", mass = "kg/m", lubrication = "m/s" }\n')


# (file text, the key the message must name)
MALFORMED = [
    pytest.param(SOURCE + belt(body="pitch_again = = 3\n"), "line 7", id="invalid-toml"),
    pytest.param(SOURCE + belt(body='units = { width = "mm", F_Tadm = "N" }\n' + GOOD_ROWS),
                 "belts[0].units.pitch", id="missing-unit"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25, F_Tadm = -2200 } ]\n"),
                 "belts[0].widths[0].F_Tadm", id="negative-value"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25, F_Tadm = 0 } ]\n"),
                 "belts[0].widths[0].F_Tadm", id="zero-value"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25, F_Tadm = nan } ]\n"),
                 "belts[0].widths[0].F_Tadm", id="nan-value"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + 'widths = [ { width = 25, F_Tadm = "2200" } ]\n'),
                 "belts[0].widths[0].F_Tadm", id="text-value"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25 }, { width = 16 } ]\n"),
                 "belts[0].widths", id="widths-unsorted"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25 }, { width = 25 } ]\n"),
                 "belts[0].widths", id="widths-repeated"),
    pytest.param(SOURCE + belt(manufacturer="BRECO", profile="AT10"), "BRECO-AT10", id="duplicate-builtin"),
    pytest.param(SOURCE + belt(manufacturer="breco", profile="at10"), "breco-at10", id="duplicate-builtin-case"),
    pytest.param(SOURCE + belt() + belt(), "Acme-XL9", id="duplicate-in-file"),
    pytest.param(SOURCE + belt(body='colour = "red"\n' + BELT_UNITS), "belts[0].colour", id="unknown-key"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + "widths = [ { width = 25, F_tadm = 2200 } ]\n"),
                 "belts[0].widths[0].F_tadm", id="unknown-row-key"),
    pytest.param(SOURCE + "[[pulleys]]\nname = 'x'\n", "pulleys", id="unknown-top-level-key"),
    pytest.param('[source]\nlocation = "p. 3"\n' + belt(), "source.document", id="no-source-document"),
    pytest.param(SOURCE + belt(body='units = { pitch = "kg" }\n'), "belts[0].units.pitch", id="unit-wrong-dimension"),
    pytest.param(SOURCE + belt(body='units = { pitch = "furlongz" }\n'), "belts[0].units.pitch", id="unit-unknown"),
    pytest.param(SOURCE + belt(body='z_e_max = 1.5\nunits = { pitch = "mm" }\n'), "belts[0].z_e_max",
                 id="z_e_max-not-whole"),
    pytest.param(SOURCE + belt(body='units = { pitch = "mm", F_tspec = "N/cm", speed = "rpm" }\n'
                                    'F_tspec = [ { speed = 1000, load = 30 }, { speed = 0, load = 40 } ]\n'),
                 "belts[0].F_tspec", id="speeds-unsorted"),
    pytest.param(SOURCE + '[[threads]]\nname = "Mx"\nd = 10\nP = 1\nd2 = 10.5\nflank_angle = 60\n'
                          'units = { d = "mm", P = "mm", d2 = "mm", flank_angle = "deg" }\n',
                 "threads[0].d2", id="thread-d2-over-d"),
    pytest.param(SOURCE + motor(name="Mo-1", T_n=2.0, T_max=1.0), "motors[0].T_max",
                 id="motor-peak-below-rated"),
    # read by the schema (beltcalc/data/schema.py): each kind's own keys, the place of a list's item
    pytest.param(SOURCE + '[[threads]]\nname = "Mx"\nmanufacturer = "Acme"\nd = 10\nP = 1\nd2 = 9\nflank_angle = 60\n'
                          'units = { d = "mm", P = "mm", d2 = "mm", flank_angle = "deg" }\n',
                 "threads[0].manufacturer: unknown key", id="key-of-another-kind"),
    pytest.param(SOURCE + belt(body='source = ""\n' + BELT_UNITS + GOOD_ROWS), "belts[0].source: must not be empty",
                 id="empty-entry-source"),
    pytest.param(SOURCE + belt(body=BELT_UNITS + 'stock_teeth = [60, 50]\n' + GOOD_ROWS),
                 "belts[0].stock_teeth[1]: must rise", id="stock-teeth-unsorted"),
    pytest.param(SOURCE + chain('mass = { 3 = 1.0 }\nlubrication = { A = 1 }\n'),
                 "chains[0].lubrication.B: missing", id="chain-lubrication-without-B"),
    pytest.param(SOURCE + chain('mass = { 3 = 1.0 }\n'),
                 "chains[0].mass.3: not a strand count; the keys are strand counts 1..2", id="chain-mass-strands"),
    pytest.param(SOURCE + chain(loads="[10, -20]"),
                 "chains[0].breaking_load[1]: -20 kN is not allowed; it must be > 0 kN", id="chain-load-negative"),
]


@pytest.mark.parametrize("text, key", MALFORMED)
def test_malformed_file_is_catalog_error_naming_file_and_key(text, key, tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(text)
    with pytest.raises(CatalogError) as info:
        load_catalog([path])
    message = str(info.value)
    assert str(path) in message
    assert key in message
    assert "\n" not in message
    assert info.value.exit_code == 1


def test_missing_file_is_catalog_error(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(CatalogError, match="does not exist") as info:
        load_catalog([path])
    assert str(path) in str(info.value)


def test_good_file_loads_after_a_bad_one_is_refused(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(SOURCE + belt(body='colour = "red"\n' + BELT_UNITS))
    with pytest.raises(CatalogError):
        load_catalog([bad])
    good = tmp_path / "good.toml"
    good.write_text(SOURCE + belt())
    assert load_catalog([good]).belt("XL9").width_row(0.016).F_Tadm == pytest.approx(1400.0)


# --- bugs --------------------------------------------------------------------------------

def test_not_utf8_is_catalog_error(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(SOURCE.encode() + b"# Gr\xf6\xdfe\n" + belt().encode())
    with pytest.raises(CatalogError) as info:
        load_catalog([path])
    assert str(path) in str(info.value)


def test_widths_not_an_array_is_catalog_error(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(SOURCE + belt(body=BELT_UNITS + "widths = 5\n"))
    with pytest.raises(CatalogError) as info:
        load_catalog([path])
    assert str(path) in str(info.value) and "belts[0].widths" in str(info.value)


def test_units_inside_a_width_row_are_not_silently_ignored(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(SOURCE + belt(body=BELT_UNITS + 'widths = [ { width = 25, F_Tadm = 2, '
                                                     'units = { F_Tadm = "kN" } } ]\n'))
    try:
        cat = load_catalog([path])
    except CatalogError as exc:  # refusing the key is as good as honouring it
        assert "belts[0].widths[0].units" in str(exc)
        return
    assert cat.belt("XL9").width_row(0.025).F_Tadm == pytest.approx(2000.0)


def test_name_repeated_across_kinds_is_refused(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(SOURCE + motor(name="M10x1", T_n=1.27, T_max=4.46))
    try:
        cat = load_catalog([path])
    except CatalogError as exc:
        assert "M10x1" in str(exc) and str(path) in str(exc)
        return
    assert isinstance(cat.entry("M10x1"), Thread)


def test_belt_entry_source_is_used(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(SOURCE + belt(body='source = "Acme page 3"\n' + BELT_UNITS + GOOD_ROWS))
    profile = load_catalog([path]).belt("XL9")
    assert profile.source.document == "Acme page 3"


def test_errors_are_beltcalc_errors():
    assert issubclass(CatalogError, BeltcalcError)
    assert issubclass(UnknownNameError, KeyError)


@pytest.mark.parametrize("old, new, key", [
    ("[[1.2, 1.3, 1.4], ", "[[1.2, 1.3], ", "service_factors.mine.base[0][0]: 2 values; the table's shape is (3,)"),
    ("speed_up = [0.0, ", "speed_up = [", "service_factors.mine.speed_up: 4 values; the table's shape is (5,)"),
    ("speed_up = [0.0, ", "speed_up = [-1, ", "service_factors.mine.speed_up[0]: -1 is not allowed; it must be >= 0"),
    ('load_kinds = [', 'load_kinds = [3, ', "service_factors.mine.load_kinds[0]: must be a text, not 3"),
])
def test_malformed_service_factor_table_names_the_cell(old, new, key, tmp_path):
    text = (builtin_dir() / "belts" / "service_factors.toml").read_text().replace("synchronous_belt", "mine")
    assert old in text
    path = tmp_path / "factors.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(CatalogError) as info:
        load_catalog([path])
    assert str(info.value) == f"{path}: {key}"
