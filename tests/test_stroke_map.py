"""The resonance map along a belt axis's stroke (beltcalc.sim.stroke_map, `beltcalc modes DRIVE
--along-stroke N`), against the closed forms of a carriage between its two belt spans.

The carriage belt's spans are L1 = L1_0 + x and L2 = L2_0 - x long, each with the stiffness
C_spec / L and damping b_spec / L [W21 eq. 5]; held at x the belt is the spring
k(x) = C_spec (1/L1 + 1/L2) with the damper b(x) = b_spec (1/L1 + 1/L2) on u = r phi - x. With the
pulley prescribed the carriage alone swings: a one-degree-of-freedom oscillator, whose pole
s^2 + (b/m) s + k/m = 0 has |s| = sqrt(k / m) whatever the damping, so

    f(x) = sqrt(k(x) / m) / (2 pi),    zeta(x) = b(x) / (2 sqrt(k(x) m)).

With the pulley free (inertia J, r metres of belt a radian) the pulley and the carriage swing
against each other on the belt: k r^2 (phi - x / r) is the two-mass spring, and undamped
f(x) = sqrt(k(x) (1/m + r^2/J)) / (2 pi). k(x) is least where L1 = L2, x* = (L2_0 - L1_0) / 2:
the lowest first frequency is there where the travel reaches it, else at the travel's end nearest.
"""

from __future__ import annotations

import csv
import json
import math
from functools import cache

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

from beltcalc.cli.main import cli
from beltcalc.errors import InputError, UnknownNameError
from beltcalc.sim.elements import Coupling, Inertia, Prescribed
from beltcalc.sim.elements.carriage_belt import CarriageBelt
from beltcalc.sim.network import Network
from beltcalc.sim.stroke_map import MAX_EVALUATIONS, XTOL, stroke_map

C_SPEC, B_SPEC, L1, L2, MASS, R, J = 4e5, 10.0, 0.1, 2.2, 8.0, 0.025, 2e-3


def carriage(stroke: float, damping: float = B_SPEC, held: bool = True) -> Network:
    """The carriage on its belt; the pulley prescribed (``held``) or free."""
    elements = [CarriageBelt("belt", "pulley", "carriage", R, C_SPEC, damping, L1, L2, stroke=stroke)]
    if held:
        elements.insert(0, Prescribed("pulley", 0.0))
    return Network([Inertia("pulley", J), Inertia("carriage", MASS, True)], elements)


def k_of(x):
    """k(x) = C_spec (1/L1 + 1/L2), the spans at x [W21 eq. 5]."""
    return C_SPEC * (1 / (L1 + np.asarray(x)) + 1 / (L2 - np.asarray(x)))


def f_held(x):
    """The carriage alone on its spans: sqrt(k / m) / 2 pi."""
    return np.sqrt(k_of(x) / MASS) / (2 * math.pi)


def f_free(x):
    """The pulley and the carriage against each other, undamped: sqrt(k (1/m + r^2/J)) / 2 pi."""
    return np.sqrt(k_of(x) * (1 / MASS + R ** 2 / J)) / (2 * math.pi)


# --- the library against the closed forms --------------------------------------------------------
@pytest.mark.parametrize("stroke", [0.6, -0.05, 1.5])
def test_every_position_has_the_two_spring_frequency_and_damping(stroke):
    m = stroke_map(carriage(stroke), 50)
    assert m.positions.size == 50 and m.modes == 1
    assert_allclose(m.positions, np.linspace(min(0, stroke), max(0, stroke), 50), rtol=0, atol=1e-15)
    assert_allclose(m.frequency[:, 0], f_held(m.positions), rtol=1e-9)
    b = B_SPEC * (1 / (L1 + m.positions) + 1 / (L2 - m.positions))
    assert_allclose(m.damping_ratio[:, 0], b / (2 * np.sqrt(k_of(m.positions) * MASS)), rtol=1e-9)
    assert_allclose(m.stiffness, k_of(m.positions), rtol=1e-12)
    assert_allclose(m.span1, L1 + m.positions, rtol=1e-15)
    assert_allclose(m.span2, L2 - m.positions, rtol=1e-15)
    # the shape: the carriage swings, the held pulley does not
    j = m.nodes.index("carriage")
    assert_allclose(m.amplitude[:, 0, j], 1.0, rtol=1e-12)
    assert_allclose(m.amplitude[:, 0, 1 - j], 0.0, atol=1e-12)
    assert m.ends == pytest.approx((f_held(m.travel[0]), f_held(m.travel[1])), rel=1e-9)


def test_a_free_pulley_gives_the_two_mass_frequency():
    m = stroke_map(carriage(0.6, damping=0.0, held=False), 25)
    assert_allclose(m.frequency[:, 0], f_free(m.positions), rtol=1e-9)
    assert_allclose(m.damping_ratio[:, 0], 0.0, atol=1e-12)
    # the pulley turns against the carriage: phase 180 deg, amplitude r m / J in metres per radian
    # over the largest (the pulley's angle): (x / phi) = -(J / (m r)) -> carriage / pulley = J / (m r)
    j = m.nodes.index("carriage")
    ratio = J / (MASS * R)                 # x / phi of the mode, in m/rad (0.01)
    assert_allclose(m.amplitude[:, 0, j], ratio, rtol=1e-9)
    assert_allclose(np.abs(m.phase[:, 0, j]), math.pi, rtol=1e-12)


@pytest.mark.parametrize("stroke, where", [(0.6, 0.6), (-0.05, 0.0)])
def test_the_lowest_point_at_an_end_of_a_monotone_stroke(stroke, where):
    """k1 + k2 falls towards x* = 1.05 m: a stroke short of it has its lowest point at the end
    nearest to x*, that grid point exactly."""
    for held, f in ((True, f_held), (False, f_free)):
        m = stroke_map(carriage(stroke, damping=B_SPEC if held else 0.0, held=held), 50)
        assert m.lowest_at == pytest.approx(where, rel=1e-12, abs=1e-15)
        assert m.lowest == pytest.approx(float(f(where)), rel=1e-9)
        assert m.evaluations <= MAX_EVALUATIONS


@pytest.mark.parametrize("positions", [2, 3, 50, 2000])
def test_the_lowest_point_inside_the_stroke_is_where_the_spans_are_equal(positions):
    """Stroke 1.5 m over x* = (L2_0 - L1_0) / 2 = 1.05 m (L1 = L2 = 1.15 m): the search between
    the grid's points finds f(x*) = sqrt(2 C_spec / 1.15 m / m) / 2 pi to rounding. Where it
    lies is known less well: f is flat there, f(x) = f* (1 + c ((x - x*) / L)^2), so the
    rounding of the eigenvalues (1e-15) leaves x* known to about sqrt(1e-15) ~ 3e-8 of the
    travel whatever the search's width (1e-9 of the travel; measured 1.1e-8 m off): to 1e-7 of the
    travel here."""
    x_star = (L2 - L1) / 2
    m = stroke_map(carriage(1.5), positions)
    assert m.lowest == pytest.approx(float(f_held(x_star)), rel=1e-9)
    assert m.lowest == pytest.approx(math.sqrt(2 * C_SPEC / 1.15 / MASS) / (2 * math.pi), rel=1e-12)
    assert m.lowest_at == pytest.approx(x_star, rel=0, abs=1e-7 * 1.5)
    assert m.evaluations <= MAX_EVALUATIONS
    # the search's own stopping width: the bracket (two grid cells, or the whole travel for two or
    # three positions) shrunk by 0.618 an evaluation, after the first two, to 1e-9 of the travel
    # (give or take one where the width's rounding meets the tolerance)
    bracket = min(2 / (positions - 1), 1.0)
    expected = math.ceil(math.log(XTOL / bracket) / math.log((math.sqrt(5) - 1) / 2)) + 2
    assert m.evaluations == pytest.approx(expected, abs=1)


def test_without_shapes_the_frequencies_are_the_same():
    a, b = stroke_map(carriage(1.5), 20), stroke_map(carriage(1.5), 20, shapes=False)
    assert b.amplitude is None and b.phase is None
    assert_allclose(b.frequency, a.frequency, rtol=1e-12)
    assert_allclose(b.damping_ratio, a.damping_ratio, rtol=1e-9)


@pytest.mark.parametrize("positions", [1, 0, -3, 2001, 2.5, True, "50"])
def test_positions_out_of_bounds_are_refused(positions):
    with pytest.raises(InputError) as e:
        stroke_map(carriage(0.6), positions)
    assert e.value.param == "positions"


def test_a_drive_without_a_carriage_belt_is_refused():
    net = Network([Inertia("a", 1.0), Inertia("b", 2.0)], [Coupling("c", "a", "b", 100.0, 0.1)])
    with pytest.raises(InputError) as e:
        stroke_map(net)
    assert e.value.param == "positions" and "no carriage belt" in e.value.message
    with pytest.raises(UnknownNameError):
        stroke_map(carriage(0.6), belt="chain")
    assert stroke_map(carriage(0.6), 2, belt="belt").belt == "belt"


# --- the command ----------------------------------------------------------------------------------
def run(*args: str):
    res = CliRunner().invoke(cli, list(args))
    return res.exit_code, res.stdout, res.stderr


@cache
def wdu(positions: int = 50) -> dict:
    code, out, err = run("modes", "linear_axis_moving", "--along-stroke", str(positions), "--json")
    assert code == 0, err
    return json.loads(out)


def test_the_json_names_every_value_with_its_unit():
    obj = wdu()
    n = 50
    for key, unit in (("positions", "m"), ("span1", "m"), ("span2", "m"), ("belt_stiffness", "N/m")):
        assert obj[key]["unit"] == unit and len(obj[key]["value"]) == n
    mode = obj["modes"][0]
    assert mode["mode"] == 1
    assert mode["frequency"]["unit"] == "Hz" and len(mode["frequency"]["value"]) == n
    assert mode["damping_ratio"]["unit"] == "1" and len(mode["damping_ratio"]["value"]) == n
    for node in ("motor", "carriage"):
        shape = mode["shape"]["nodes"][node]
        assert shape["amplitude"]["unit"] == "1" and shape["phase"]["unit"] == "rad"
        assert len(shape["amplitude"]["value"]) == n
    assert obj["lowest"]["frequency"]["unit"] == "Hz" and obj["lowest"]["position"]["unit"] == "m"
    assert obj["ends"]["low"]["frequency"]["unit"] == "Hz" and obj["ends"]["high"]["position"]["unit"] == "m"
    assert obj["travel"]["low"]["unit"] == obj["travel"]["high"]["unit"] == "m"
    assert obj["band"] is None and obj["warnings"] == [] and obj["belt"] == "belt"
    assert "inputs" in obj


def test_the_wdu_axis_is_lowest_at_the_far_end_as_the_closed_form_says():
    """`beltcalc modes linear_axis_moving --along-stroke 50 --json`: the motor node is prescribed
    (the servo's move), so the carriage sees only its belt: f = sqrt(k / m) / 2 pi with k =
    C_spec (1/L1 + 1/L2), C_spec = k_TB a, the spans from the scene's start and stroke, m the
    carriage node's mass (the carriage and the substitute belt mass m_TB)."""
    from beltcalc.sim.scenes import linear_axis as la

    model = la.prepare_scene(la.SCENE.values(spans="moving"))[0]
    c_spec, mass = model.stiffness * model.center_distance, model.axis.mass + model.axis.substitute_mass
    stroke = model.travel

    def f(x):
        k = c_spec * (1 / (model.start + x) + 1 / (model.return_start - x))
        return math.sqrt(k / mass) / (2 * math.pi)

    obj = wdu()
    assert obj["travel"]["high"]["value"] == pytest.approx(stroke, rel=1e-12)
    assert obj["lowest"]["position"]["value"] == pytest.approx(stroke, rel=1e-12)
    assert obj["lowest"]["frequency"]["value"] == pytest.approx(f(stroke), rel=1e-9)
    assert obj["ends"]["low"]["frequency"]["value"] == pytest.approx(f(0.0), rel=1e-9)
    assert obj["ends"]["high"]["frequency"]["value"] == pytest.approx(f(stroke), rel=1e-9)
    xs = obj["positions"]["value"]
    assert_allclose(obj["modes"][0]["frequency"]["value"], [f(x) for x in xs], rtol=1e-9)
    # the figures docs/frequency_domain.md quotes
    assert f(0.0) == pytest.approx(48.82, abs=0.005) and f(stroke) == pytest.approx(20.64, abs=0.005)


def test_the_csv_has_one_row_per_position(tmp_path):
    path = tmp_path / "map.csv"
    code, _, err = run("modes", "linear_axis_moving", "--along-stroke", "7", "--csv", str(path))
    assert code == 0, err
    rows = list(csv.DictReader(path.open()))
    assert len(rows) == 7
    assert list(rows[0]) == ["position_m", "span1_m", "span2_m", "belt_stiffness_N_per_m", "f1_Hz",
                             "damping_ratio1"]
    obj = wdu(7)
    assert_allclose([float(r["position_m"]) for r in rows], obj["positions"]["value"], rtol=1e-15)
    assert_allclose([float(r["f1_Hz"]) for r in rows], obj["modes"][0]["frequency"]["value"], rtol=1e-15)


def test_the_plot_is_written_with_a_band(tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "map.png"
    code, out, err = run("modes", "linear_axis_moving", "--along-stroke", "9", "--band", "0:12Hz", "--plot",
                         str(path))
    assert code == 0, err
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "lowest first frequency: 20.64 Hz at x = 1000 mm (the high end)" in out
    assert "excitation band 0 to 12 Hz" in out


def test_a_band_over_the_first_mode_warns():
    code, out, err = run("modes", "linear_axis_moving", "--along-stroke", "5", "--band", "0:30Hz", "--json")
    assert code == 0, err
    obj = json.loads(out)
    assert obj["band"]["high"] == {"value": 30.0, "unit": "Hz"} and obj["band"]["modes_inside"] == [1]
    assert len(obj["warnings"]) == 1 and "mode 1 lies inside the excitation band" in obj["warnings"][0]
    assert "warning: mode 1 lies inside" in err
    # rad/s is an angular frequency: 75.4 rad/s is 12 Hz
    obj = json.loads(run("modes", "linear_axis_moving", "--along-stroke", "2", "--band", "0:75.398223686rad/s",
                         "--json")[1])
    assert obj["band"]["high"]["value"] == pytest.approx(12.0, rel=1e-9) and obj["warnings"] == []


@pytest.mark.parametrize("args, option", [
    (["linear_axis_moving", "--along-stroke", "1"], "--along-stroke"),
    (["linear_axis_moving", "--along-stroke", "2001"], "--along-stroke"),
    (["linear_axis_moving", "--along-stroke", "ten"], "--along-stroke"),
    (["sewing", "--along-stroke", "5"], "--along-stroke"),
    (["linear_axis", "--along-stroke", "5"], "--along-stroke"),
    (["linear_axis_moving", "--band", "0:12Hz"], "--band"),
    (["linear_axis_moving", "--along-stroke", "5", "--band", "12Hz"], "--band"),
    (["linear_axis_moving", "--along-stroke", "5", "--band", "12:2Hz"], "--band"),
    (["linear_axis_moving", "--along-stroke", "5", "--band", "0:12"], "--band"),
    (["linear_axis_moving", "--along-stroke", "5", "--band", "0:12kg"], "--band"),
])
def test_bad_values_exit_2_in_one_line_naming_the_option(args, option):
    code, out, err = run("modes", *args)
    assert code == 2, (out, err)
    assert len(err.strip().splitlines()) == 1, err
    assert option in err and "Traceback" not in err


def test_without_the_option_modes_is_unchanged():
    """The drive's poles at the carriage's start: the held belt's k(0) on the carriage."""
    code, out, err = run("modes", "linear_axis_moving", "--json")
    assert code == 0, err
    obj = json.loads(out)
    assert "positions" not in obj and "lowest" not in obj
    first = next(p for p in obj["modes"] if p["kind"] == "oscillatory")
    assert first["frequency"]["value"] == pytest.approx(wdu()["ends"]["low"]["frequency"]["value"], rel=1e-12)
