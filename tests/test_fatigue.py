"""beltcalc.formulas.fatigue: rainflow counting against ASTM E1049's worked example, its
invariants (hypothesis), Miner's sum against a hand calculation; the chain strands' fatigue
rows and check through the product path."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from beltcalc.errors import InputError
from beltcalc.formulas.fatigue import (SNCurve, chain_sn_curve, damage_rate, life, miner_damage, rainflow,
                                       turning_points)


def test_astm_e1049_rainflow_example_exact():
    # ASTM E1049-85 (2017) Fig. 6 / sec. 5.4.4: the load history -2, 1, -3, 5, -1, 3, -4, 4, -2,
    # counted by hand with the three-point rule:
    #   -2 1 -3: Y = |1 - -2| = 3 holds the start: half cycle 3 (mean -0.5), drop -2
    #   1 -3 5:  Y = 4 holds the start: half cycle 4 (mean -1), drop 1
    #   -3 5 -1 3 -4: X = 7 >= Y = |3 - -1| = 4: full cycle 4 (mean 1), drop -1, 3
    #   -3 5 -4: X = 9 >= Y = 8, Y holds the start: half cycle 8 (mean 1), drop -3
    #   residue 5 -4 4 -2: half cycles 9 (mean 0.5), 8 (mean 0), 6 (mean 1)
    # ASTM's table: range 9: 0.5, 8: 1.0, 6: 0.5, 4: 1.5, 3: 0.5.
    c = rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2])
    assert c.ranges.tolist() == [3.0, 4.0, 4.0, 8.0, 9.0, 8.0, 6.0]
    assert c.means.tolist() == [-0.5, -1.0, 1.0, 1.0, 0.5, 0.0, 1.0]
    assert c.counts.tolist() == [0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 0.5]
    table = {}
    for r, n in zip(c.ranges, c.counts):
        table[r] = table.get(r, 0.0) + n
    assert table == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_turning_points_plateaus_and_flanks():
    assert turning_points([0, 0, 1, 2, 2, 2, 1, 0, 0, 3]).tolist() == [0.0, 2.0, 0.0, 3.0]
    assert turning_points([]).size == 0
    assert turning_points([4.0]).tolist() == [4.0]
    with pytest.raises(InputError):
        turning_points([0.0, math.nan, 1.0])


def test_constant_and_monotone_signals():
    assert rainflow([5.0] * 10).total == 0.0
    c = rainflow(np.linspace(0.0, 3.0, 50))          # one rise: one half cycle of its range
    assert c.ranges.tolist() == [3.0] and c.counts.tolist() == [0.5]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(-50, 50), min_size=2, max_size=60))
def test_reversals_all_counted(values):
    # every reversal (a range between successive turning points) belongs to one half cycle:
    # the count in half cycles is the number of reversals
    points = turning_points(np.array(values, dtype=float))
    c = rainflow(values)
    assert 2 * c.total == pytest.approx(max(points.size - 1, 0), abs=0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(-50, 50), min_size=2, max_size=40), st.integers(1, 5), st.randoms())
def test_invariant_to_intermediate_samples(values, k, rnd):
    # samples inserted on the flanks between two samples (and repeated samples) are no
    # turning points: the count is the same
    dense = []
    for a, b in zip(values, values[1:]):
        dense.append(float(a))
        dense += sorted((a + (b - a) * rnd.random() for _ in range(k)), reverse=b < a)
    dense.append(float(values[-1]))
    dense = [x for x in dense for _ in range(rnd.randint(1, 2))]
    c0, c1 = rainflow(values), rainflow(dense)
    assert c1.ranges.tolist() == pytest.approx(c0.ranges.tolist(), rel=1e-12, abs=1e-12)
    assert c1.means.tolist() == pytest.approx(c0.means.tolist(), rel=1e-12, abs=1e-12)
    assert c1.counts.tolist() == c0.counts.tolist()


@settings(max_examples=50, deadline=None)
@given(st.integers(1, 200), st.floats(0.1, 1e4), st.floats(-1e4, 1e4), st.integers(2, 64))
def test_sine_periods_cycles(periods, amplitude, mean, per_quarter):
    # a sine of N periods from a peak (A cos) sampled with its peaks and valleys: N cycles of
    # range 2A about its mean (ASTM counts equal ranges as 2N half cycles: none closes a loop)
    t = np.linspace(0.0, periods, periods * 4 * per_quarter + 1)
    c = rainflow(mean + amplitude * np.cos(2 * np.pi * t))
    assert c.total == pytest.approx(periods, abs=1e-12)
    assert c.ranges == pytest.approx(np.full(c.ranges.size, 2 * amplitude), rel=1e-9)
    assert c.means == pytest.approx(np.full(c.means.size, mean), abs=1e-9 * amplitude + 1e-9 * abs(mean))
    # from the mean (A sin): the rise to the first peak and the fall to the mean at the end are
    # half cycles of A; the 2N - 1 reversals between peaks half cycles of 2A
    s = rainflow(mean + amplitude * np.sin(2 * np.pi * t))
    big = s.ranges >= 2 * amplitude * (1 - 1e-9)
    assert np.sum(s.counts[big]) == pytest.approx(periods - 0.5, abs=1e-12)
    assert s.total == pytest.approx(periods + 0.5, abs=1e-12)


def test_miner_hand_calculation():
    # hand: N(200) = 1e6 (100/200)^5 = 31250, N(150) = 1e6 (100/150)^5 = 131687.24;
    # D = 500/31250 + 2000/131687.24 = 0.016 + 0.0151875 = 0.0311875; 80 N below the cutoff
    curve = SNCurve(100.0, 1e6, 5.0)
    d = miner_damage([200.0, 150.0, 80.0], [0.0, 10.0, 0.0], [500.0, 2000.0, 1e9], curve)
    assert d == pytest.approx(0.016 + 2000 / (1e6 * (100 / 150) ** 5), rel=1e-12)
    assert d == pytest.approx(0.0311875, rel=1e-12)
    # elementary: 80 N with slope 5; Haibach: slope 9 below the knee
    e = miner_damage([80.0], [0.0], [1e6], SNCurve(100.0, 1e6, 5.0, "elementary"))
    h = miner_damage([80.0], [0.0], [1e6], SNCurve(100.0, 1e6, 5.0, "haibach"))
    assert e == pytest.approx(0.8 ** 5, rel=1e-12) and h == pytest.approx(0.8 ** 9, rel=1e-12)
    rate = damage_rate(d, 1800.0)
    assert life(rate) == pytest.approx(1800.0 / 0.0311875, rel=1e-12)
    assert life(0.0) == math.inf


def test_rainflow_and_miner_together():
    # the ASTM history in kN on a 5 kN / 1e6 / k = 3 curve (elementary): by hand
    # 0.5 (3^3 + 4^3 + 8^3 + 9^3 + 8^3 + 6^3) + 4^3 = 1030 + 64 = 1094 (kN^3); D = 1094 / (125 e6)
    c = rainflow(np.array([-2, 1, -3, 5, -1, 3, -4, 4, -2]) * 1e3)
    d = miner_damage(c.ranges, c.means, c.counts, SNCurve(5e3, 1e6, 3.0, "elementary"))
    assert d == pytest.approx(1094.0 / 125e6, rel=1e-12)


def test_curve_inputs_refused():
    with pytest.raises(InputError):
        SNCurve(0.0, 1e6, 5.0)
    with pytest.raises(InputError):
        SNCurve(1.0, 1e6, 5.0, "none")
    with pytest.raises(InputError):
        miner_damage([1.0, 2.0], [0.0], [1.0, 1.0], SNCurve(1.0, 1e6, 5.0))
    with pytest.raises(InputError):
        chain_sn_curve(0.0)


def test_chain_curve():
    # Tsubaki: P_min = P_max / 11, so the knee's range is 10/11 of the allowable load, at 1e7
    c = chain_sn_curve(3603.0)
    assert c.range_ref == pytest.approx(3603.0 * 10 / 11, rel=1e-15)
    assert (c.cycles_ref, c.slope, c.endurance, c.origin) == (1e7, 5.0, "cutoff", "assumed")


def test_catalog_allowable_loads():
    from beltcalc.data.catalogs import load_catalog

    chains = load_catalog().chains
    # U.S. Tsubaki Roller Chain General Catalog pp. 16-19: 40RB 810 lb, 80-2RB 5,620 lb
    assert chains["40-1"].allowable_dynamic_load == pytest.approx(810 * 4.4482216152605, rel=1e-9)
    assert chains["80-2"].allowable_dynamic_load == pytest.approx(5620 * 4.4482216152605, rel=1e-9)
    assert chains["140-4"].allowable_dynamic_load == pytest.approx(29830 * 4.4482216152605, rel=1e-9)
    assert chains["10b-1"].allowable_dynamic_load is None          # none found for the B series
    assert chains["160-1"].allowable_dynamic_load is None
    for c in chains.values():      # a fatigue limit lies well below the breaking load (15-26 % here)
        if c.allowable_dynamic_load is not None:
            assert 0.1 < c.allowable_dynamic_load / c.breaking_load < 0.3


def _roller_table(*args):
    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    return CliRunner().invoke(cli, ["simulate", "roller-table", "--json", *args])


def test_roller_table_fatigue_rows_and_check():
    import json

    res = _roller_table("--set", "chain=50-1")
    assert res.exit_code == 0, res.output
    obj = json.loads(res.stdout)
    rows = obj["chain_fatigue"]["drive-sprocket1"]
    allow = 1430 * 4.4482216152605
    assert rows["dynamic_load"] == {"value": pytest.approx(allow, rel=1e-9), "unit": "N"}
    peak = obj["strands"]["drive-sprocket1"]["force_max"]["value"]
    assert rows["dynamic_utilisation"]["value"] == pytest.approx(peak / allow, rel=1e-12)
    assert rows["damage_rate"]["unit"] == "1/s" and rows["damage_rate"]["value"] >= 0.0
    assert rows["cycles"]["value"] > 0 and rows["range_max"]["value"] <= peak
    check, = [c for c in obj["checks"] if c["key"] == "strand_fatigue"]
    assert check["verdict"] == "pass" and check["value"]["value"] == pytest.approx(peak, rel=1e-12)


def test_roller_table_fatigue_unverified_without_data():
    import json

    res = _roller_table()                           # 10B-1: no allowable load in the catalog
    obj = json.loads(res.stdout)
    check, = [c for c in obj["checks"] if c["key"] == "strand_fatigue"]
    assert check["verdict"] == "unverified" and "10B-1" in check["reason"]
    assert obj["chain_fatigue"]["drive-sprocket1"]["damage_rate"]["value"] is None
