"""Roller chains: formulas of beltcalc.formulas.chain (issue 13 part), selection (beltcalc.design.chain_select),
the chain catalog, and `beltcalc chain`."""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings, strategies as st

from beltcalc.formulas import chain as cm
from beltcalc.design import chain_select as cs
from beltcalc.data.catalogs import load_catalog
from beltcalc.data.scenefile import load_scene
from beltcalc.cli.main import cli
from beltcalc.errors import InputError
from beltcalc.units import parse_quantity

CAT = load_catalog()
HP, RPM = cs.HORSEPOWER, cs.RPM


def run(*args):
    return CliRunner().invoke(cli, list(args))


# --- Shigley Example 17-5 --------------------------------------------------------------------

def test_shigley_example_17_5():
    # Shigley, Mechanical Engineering Design, Example 17-5: 90 hp at 300 rev/min, 17/34 teeth,
    # K_s = 1.3, n_d = 1.5, C/p = 25: H_tab = 1.5 * 1.3 * 90 / K2 = 175.5 / K2 hp;
    # 1 strand no. 200, 2 strands no. 160, 3 strands no. 140, 4 strands no. 140.
    r = cs.select_chain(cs.ChainInputs(speed=300 * RPM, power=90 * HP, service_factor=1.3, design_factor=1.5,
                                       center_pitches=25), CAT.chains.values())
    assert r.required == pytest.approx(175.5 * HP, rel=1e-14)
    assert {k: c.chain.name for k, c in r.best_per_strands.items()} == {1: "200-1", 2: "160-2", 3: "140-3",
                                                                       4: "140-4"}
    # the next smaller chain of each row does not carry it (the selection is tight, not loose)
    for strands, smaller in ((1, "180-1"), (2, "140-2"), (3, "120-3"), (4, "120-4")):
        cand = next(c for c in r.candidates if c.chain.name == smaller)
        assert not cand.carries and cand.utilisation > 1
    # chain length (Shigley's continuation): L/p = 2*25 + 51/2 + 17^2/(4 pi^2 25) = 75.79 -> 76 links
    assert r.geometry.links_exact == pytest.approx(50 + 25.5 + 289 / (100 * math.pi ** 2), rel=1e-14)
    assert r.geometry.links == 76
    assert r.chosen.chain.name == "140-3"


def test_link_plate_rating_by_hand():
    # eq. 17-32 for no. 140 (p = 1.75 in), N1 = 17, 300 rpm: 0.004 * 17^1.08 * 300^0.9 * 1.75^2.8775 = 72.39 hp
    h = 0.004 * 17 ** 1.08 * 300 ** 0.9 * 1.75 ** (3 - 0.07 * 1.75)
    assert cs.rated_power_link_plate(1.75 * 0.0254, 17, 300 * RPM) / HP == pytest.approx(h, rel=1e-14)
    # eq. 17-33 for no. 40 at 3000 rpm: 1000 * 17 * 17^1.5 * 0.5^0.8 / 3000^1.5 = 4.165 hp
    h2 = 1000 * 17 * 17 ** 1.5 * 0.5 ** 0.8 / 3000 ** 1.5
    assert cs.rated_power_roller_bushing(0.5 * 0.0254, 17, 3000 * RPM) / HP == pytest.approx(h2, rel=1e-14)
    # ISO 10823 tooth factor (19/z1)^1.08 is the same law: ratio of ratings at 19 and 17 teeth
    ratio = cs.rated_power_link_plate(0.0127, 19, 100.0) / cs.rated_power_link_plate(0.0127, 17, 100.0)
    assert ratio == pytest.approx((19 / 17) ** 1.08, rel=1e-14)


def test_roller_bushing_limit_governs_at_high_speed():
    chain = CAT.chain("40-1")
    assert cs.rated_power(chain, 17, 300 * RPM)[1] == "link plate"
    assert cs.rated_power(chain, 17, 6000 * RPM)[1] == "roller bushing"


# --- geometry ------------------------------------------------------------------------------

@pytest.mark.parametrize("z", [3, 6, 9, 17, 19, 25, 57, 120])
def test_polygon_speed_variation_is_the_chordal_closed_form(z):
    # the chain leaves at r cos(theta), theta in [-pi/z, pi/z] as the sprocket turns one pitch
    theta = np.linspace(-math.pi / z, math.pi / z, 20001)
    v = np.cos(theta)
    assert cm.polygon_speed_variation(z) == pytest.approx((v.max() - v.min()) / v.max(), rel=1e-9)
    assert cm.polygon_speed_variation(z) == pytest.approx(1 - math.cos(math.pi / z), rel=1e-15)


@settings(max_examples=200, deadline=None)
@given(z1=st.integers(9, 40), extra=st.integers(0, 80), c_pitches=st.floats(20.0, 80.0))
def test_chain_length_even_and_round_trip(z1, extra, c_pitches):
    z2 = z1 + extra
    p = 0.015875
    exact = cm.chain_length_links(c_pitches * p, p, z1, z2)
    assert cm.chain_center_distance(exact, p, z1, z2) == pytest.approx(c_pitches * p, rel=1e-12)
    links = cm.chain_links_even(exact)
    # at or above exact, where exact within 1e-9 of a whole number is that number (50.00000000000001
    # links from rounding is 50: chain_links_even's own tolerance)
    assert links % 2 == 0 and exact - 1e-9 <= links < exact + 2
    c = cm.chain_center_distance(links, p, z1, z2)
    assert c >= c_pitches * p * (1 - 1e-12)
    assert cm.chain_length_links(c, p, z1, z2) == pytest.approx(links, rel=1e-12)


def test_sprocket_diameters_against_a_catalog():
    # CROSS+MORSE taper-bore sprockets for 06B (ISO 606): 19 teeth, pitch circle 57.87 mm,
    # outside diameter 61.3 mm, inside the ISO 606 tip range [d + p(1 - 1.6/z) - d1, d + 1.25 p - d1]
    chain = CAT.chain("06B-1")
    # the list's pitch circles for 17 ... 114 teeth, printed to 0.01 mm (38 teeth: 115.344 computed,
    # printed 115.35; every other row rounds to the printed value)
    printed = {17: 51.83, 19: 57.87, 25: 76.00, 30: 91.12, 38: 115.35, 45: 136.55, 57: 172.91, 76: 230.49,
               95: 288.08, 114: 345.68}
    for z, d in printed.items():
        assert cm.sprocket_pitch_diameter(chain.pitch, z) * 1e3 == pytest.approx(d, abs=0.0075), z
    lo, hi = cm.sprocket_tip_diameters(chain.pitch, 19, chain.roller_diameter)
    assert lo < 0.0613 < hi
    assert cm.sprocket_root_diameter(chain.pitch, 19, chain.roller_diameter) == pytest.approx(
        cm.sprocket_pitch_diameter(chain.pitch, 19) - 0.00635, rel=1e-14)


# --- the catalog ---------------------------------------------------------------------------

def test_10b1_is_the_roller_table_scene_chain():
    # the scene names the chain and no longer types its data: pitch, mass and breaking load come
    # from this entry, equal to the values the scene file typed before (SOURCED_DATA.md, DIN 8187)
    from beltcalc.sim.scenes import SCENES

    scene = load_scene("roller_table").values
    assert scene["chain"][0] == "10B-1"
    assert not {"chain_pitch", "chain_mass", "chain_breaking_load"} & set(scene)
    chain = CAT.chain("10B-1")
    _, values = SCENES["roller-table"].resolve()
    for key, attr, typed in (("chain_pitch", "pitch", "15.875 mm"), ("chain_mass", "mass", "0.91 kg/m"),
                             ("chain_breaking_load", "breaking_load", "22.2 kN")):
        assert values[key].value == pytest.approx(getattr(chain, attr), rel=1e-15)
        assert values[key].value == pytest.approx(parse_quantity(typed, values[key].text.split()[-1]), rel=1e-15)
        assert values[key].origin == "catalog: 10B-1 (chains.toml)"


# --- lubrication (McGuire Bearing, "Better chain performance", table "Feet per minute") ------

FPM = 0.3048 / 60          # m/s per ft/min
MCGUIRE = {"40": (300, 2300), "50": (250, 2000), "60": (220, 1800), "80": (170, 1500), "100": (150, 1300),
           "120": (130, 1200), "140": (115, 1100), "160": (100, 1000)}


def test_lubrication_limits_are_the_source_table():
    # the catalog's limits are the source's, for every strand count; a B-series chain takes the
    # row of the ANSI chain of its pitch; 06B (35) and 180-240 are not in the table
    for name, (a, b) in MCGUIRE.items():
        for chain in (c for c in CAT.chains.values() if c.size == name):
            assert chain.lubrication == pytest.approx((a * FPM, b * FPM), rel=1e-14), chain.name
            twin = [c for c in CAT.chains.values() if c.series == "B" and c.strands == chain.strands
                    and c.pitch == pytest.approx(chain.pitch, rel=1e-12)]
            for c in twin:
                assert c.lubrication == pytest.approx(chain.lubrication, rel=1e-14), c.name
    for name in ("06B-1", "180-1", "200-2", "240-3"):
        assert CAT.chain(name).lubrication is None


@pytest.mark.parametrize("size", sorted(MCGUIRE))
def test_lubrication_type_at_the_source_boundaries(size):
    # "up to" the stated speed is that type: A at v_A, B just above it and at v_B, C just above v_B
    a, b = MCGUIRE[size]
    limits = CAT.chain(f"{size}-1").lubrication
    got = [cs.lubrication_type(v * FPM, limits) for v in (0.0, a, a * (1 + 1e-9), b, b * (1 + 1e-9), 10 * b)]
    assert got == ["A", "A", "B", "B", "C", "C"]


def test_lubrication_of_the_example_and_of_10b1():
    # Shigley Example 17-5: no. 140 at 17 x 1.75 in x 300 rpm = 743.75 ft/min: between 115 and
    # 1100 ft/min, Type B (oil bath or slinger disc)
    r = cs.select_chain(cs.ChainInputs(speed=300 * RPM, power=90 * HP, service_factor=1.3, design_factor=1.5,
                                       center_pitches=25), CAT.chains.values())
    assert r.chosen.chain_speed == pytest.approx(743.75 * FPM, rel=1e-14)
    assert r.lubrication == "B"
    # 10B-1 (no. 50 pitch, 250 / 2000 ft/min) on 19 teeth: v = 19 x 15.875 mm x n, Type A up to
    # 76.2 m/min / 0.301625 m = 252.6 rpm, Type B up to 609.6 / 0.301625 = 2021.1 rpm
    for rpm, want in ((100, "A"), (252, "A"), (253, "B"), (2021, "B"), (2022, "C")):
        r = cs.select_chain(cs.ChainInputs(speed=rpm * RPM, power=100.0, teeth_small=19, teeth_large=19),
                            [CAT.chain("10B-1")], name="10B-1")
        v = 19 * 0.015875 * rpm / 60
        assert r.chosen.chain_speed == pytest.approx(v, rel=1e-14)
        assert r.lubrication == want, (rpm, v / FPM)
    r = cs.select_chain(cs.ChainInputs(speed=300 * RPM, power=1000.0), [CAT.chain("180-1")], name="180-1")
    assert r.lubrication is None
    assert any("no lubrication limits" in n for n in r.notes)


def test_cli_reports_the_lubrication():
    out = json.loads(run("chain", "--json").stdout)
    assert (out["lubrication"], out["lubrication_method"]) == ("B", "oil bath or slinger disc")
    assert out["lubrication_limit_a"] == {"value": pytest.approx(115 * FPM, rel=1e-14), "unit": "m/s"}
    assert out["lubrication_limit_b"] == {"value": pytest.approx(1100 * FPM, rel=1e-14), "unit": "m/s"}
    text = run("chain").stdout
    assert "Type B lubrication (oil bath, disc) up to" in text and "lubrication: Type B" in text
    fast = json.loads(run("chain", "--chain", "10B-1", "--power", "2kW", "--speed", "3000rpm", "--teeth", "19",
                          "--json").stdout)
    assert (fast["lubrication"], fast["lubrication_method"]) == ("C", "oil stream (pump)")


def test_catalog_invariants():
    chains = list(CAT.chains.values())
    assert {"06B-1", "08B-1", "10B-1", "12B-1", "16B-1", "20B-1", "24B-1", "40-1", "50-1", "60-1", "80-1"} <= \
        {c.name for c in chains}
    for series in ("A", "B"):
        for strands in (1, 2, 3):
            same = sorted((c for c in chains if c.series == series and c.strands == strands), key=lambda c: c.pitch)
            loads = [c.breaking_load for c in same]
            assert all(b > a for a, b in zip(loads, loads[1:])), (series, strands)
    for c in chains:
        assert c.roller_diameter < c.pitch and c.pin_diameter < c.roller_diameter, c.name
        assert c.source.document.strip()
    # ANSI 40 = ISO 08A: 3125 lb = 13.90 kN; 1/2 in pitch
    assert CAT.chain("08A-1").breaking_load == pytest.approx(3125 * 4.4482216152605, rel=1e-12)
    assert CAT.chain("40-2").breaking_load == pytest.approx(2 * CAT.chain("40-1").breaking_load, rel=1e-14)
    assert CAT.chain("40-1").pitch == pytest.approx(0.0127, rel=1e-14)


# --- CLI -----------------------------------------------------------------------------------

def test_cli_default_reproduces_the_example():
    res = run("chain", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["chain"] == "140-3"
    assert out["best_per_strands"] == {"1": "200-1", "2": "160-2", "3": "140-3", "4": "140-4"}
    assert out["links"]["value"] == 76
    assert out["power"]["value"] == pytest.approx(90 * HP, rel=1e-12)
    # the example's C/p = 25 (76 links: 25.10 pitches) is below the makers' 30-50 pitches: the one warning
    assert len(out["warnings"]) == 1 and out["warnings"][0].startswith("centre distance in pitches FAILS: 25.1 ")


def test_cli_named_chain_that_does_not_carry_warns():
    res = run("chain", "--chain", "10B-1")
    assert res.exit_code == 0
    assert "does not carry" in res.stderr


def test_cli_units_do_not_change_the_result():
    a = json.loads(run("chain", "--json", "--power", "5kW", "--speed", "1000rpm", "--teeth", "19",
                       "--teeth-large", "38", "--center-distance", "500mm", "--series", "B").stdout)
    b = json.loads(run("chain", "--json", "--power", f"{5000 / HP!r}hp", "--speed", f"{1000 * RPM!r}rad/s",
                       "--teeth", "19", "--teeth-large", "38", "--center-distance", f"{500 / 25.4!r}in",
                       "--series", "B").stdout)
    assert a["chain"] == b["chain"]
    for key in ("rated_power", "center_distance", "pull", "safety_factor"):
        assert b[key]["value"] == pytest.approx(a[key]["value"], rel=1e-9)


def test_cli_csv(tmp_path):
    path = tmp_path / "c.csv"
    assert run("chain", "--csv", str(path)).exit_code == 0
    rows = {ln.split(",")[0]: ln.split(",") for ln in path.read_text().splitlines()[1:]}
    assert rows["links"][1] == "76.0" and rows["center_distance"][2] == "m"


@pytest.mark.parametrize("args, code, text", [
    (["--teeth", "2"], 2, "--teeth"),
    (["--power", "5m"], 2, "--power"),
    (["--power", "-5kW"], 1, "--power"),
    (["--chain", "11B-1"], 2, "--chain"),
    (["--power", "5MW"], 1, "--power"),                   # nothing in the catalog carries it
    (["--teeth", "30", "--teeth-large", "20"], 1, "--teeth-large"),
    (["--service-factor", "0.5"], 1, "--service-factor"),
])
def test_cli_bad_input_is_one_line(args, code, text):
    res = run("chain", *args)
    assert res.exit_code == code, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: ") and text in lines[0]


def test_library_refuses_missing_power():
    with pytest.raises(InputError) as exc:
        cs.select_chain(cs.ChainInputs(speed=10.0), CAT.chains.values())
    assert exc.value.param == "power"
