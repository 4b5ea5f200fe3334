"""The belt axis as it moves (issue 32): a carriage belt whose spans follow the carriage, checked
against the same equations written out here and solved by scipy's Radau at rtol 1e-11, and
against the linear spring it is when held."""

from __future__ import annotations

import csv
import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim.core import simulate
from beltcalc.sim.elements import Coupling, Inertia, Load, Prescribed
from beltcalc.sim.elements.carriage_belt import CarriageBelt, held_at
from beltcalc.sim.network import Network

DATA = Path(__file__).parent / "data"
MOVE = DATA / "belt_axis_move.toml"
# the values of tests/data/belt_axis_move.toml
C_SPEC, B_SPEC, L1, L2, MASS, R, SPEED = 4e5, 10.0, 0.1, 2.2, 8.0, 0.025, 10.0


def cli(*args: str):
    """The command a user types, in process: (exit code, stdout, stderr)."""
    from click.testing import CliRunner

    from beltcalc.cli.main import cli as main

    res = CliRunner().invoke(main, list(args))
    return res.exit_code, res.stdout, res.stderr


def reference_move(t: np.ndarray, pretension: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`solve_reference` on the samples ``t`` (computed once per grid and pretension)."""
    return _reference(tuple(np.round(t, 12)), pretension)


@functools.cache
def _reference(t: tuple, pretension: float | None):
    return solve_reference(np.array(t), pretension)


def solve_reference(t: np.ndarray, pretension: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The constant-speed move of ``belt_axis_move.toml`` written out: m x'' = F, the belt at the
    pulley at r w t, each span k = C/L, b = B/L on its length now; with a pretension each span
    tension-only. scipy Radau at rtol 1e-11 (the kinks of a slack span: events at each span's
    force zero, restarted there). Returns x, v, F."""
    from scipy.integrate import solve_ivp

    def spans(tt, y):
        x, v = y
        u, du = R * SPEED * tt - x, R * SPEED - v
        l1, l2 = L1 + x, L2 - x
        f0 = pretension or 0.0
        f1 = f0 - C_SPEC / l1 * u - B_SPEC / l1 * du
        f2 = f0 + C_SPEC / l2 * u + B_SPEC / l2 * du
        return f1, f2, f0 - C_SPEC / l1 * u, f0 + C_SPEC / l2 * u

    def force(tt, y):
        f1, f2, s1, s2 = spans(tt, y)
        if pretension is not None:
            f1 = f1 if (s1 > 0 and f1 > 0) else 0.0
            f2 = f2 if (s2 > 0 and f2 > 0) else 0.0
        return f2 - f1

    def rhs(tt, y):
        return [y[1], force(tt, y) / MASS]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], method="Radau", rtol=1e-11, atol=1e-14, t_eval=t,
                    max_step=1e-3 if pretension is not None else np.inf)
    assert sol.success
    x, v = sol.y
    F = np.array([force(tt, (a, b)) for tt, a, b in zip(t, x, v)])
    return x, v, F


def read_csv(path: Path) -> dict[str, np.ndarray]:
    rows = list(csv.DictReader(path.open()))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def move_network(pretension: float | None = None, moving: bool = True) -> Network:
    return Network([Inertia("pulley", 2e-3), Inertia("carriage", MASS, True)],
                   [Prescribed("pulley", SPEED),
                    CarriageBelt("belt", "pulley", "carriage", R, C_SPEC, B_SPEC, L1, L2, pretension, 0.6, moving)])


@pytest.mark.slow
def test_a_constant_speed_move_through_the_cli_matches_radau_on_the_same_equations(tmp_path):
    """``beltcalc simulate drive`` on the moving spans: position, speed and belt force against the
    equations solved by Radau at rtol 1e-11, within the run's own error estimate."""
    out = tmp_path / "run.csv"
    code, stdout, stderr = cli("simulate", "drive", str(MOVE), "--json", "--csv", str(out))
    assert code == 0, stderr
    report = json.loads(stdout)
    assert report["method"] == "dop853"
    got = read_csv(out)
    t = got["t_s"]
    x, v, F = reference_move(t)
    assert_allclose(got["x_carriage_m"], x, rtol=0, atol=1e-9)
    assert_allclose(got["v_carriage_m_per_s"], v, rtol=0, atol=1e-8)
    # the estimate names the worst signal, the belt force: it covers the true difference
    assert report["error_signal"] == "F_belt"
    assert np.abs(got["F_belt_N"] - F).max() <= report["error_estimate"]["value"] * (1 + 1e-9) + 1e-6
    assert report["error_relative"]["value"] == pytest.approx(0.0, abs=1e-6)
    # the spans' lengths follow the carriage
    assert_allclose(got["L1_belt_m"], L1 + x, rtol=0, atol=1e-9)
    assert_allclose(got["k_belt_N_per_m"], C_SPEC * (1 / (L1 + x) + 1 / (L2 - x)), rtol=1e-8)


@pytest.mark.slow
def test_the_error_estimate_covers_every_signal():
    """The run's estimate per signal (speed and belt force) against the written-out Radau."""
    net = move_network()
    res = simulate(net, 0.5, 1001)
    x, v, F = reference_move(res.t)
    for name, ref in (("v_carriage", v), ("F_belt", F)):
        true = float(np.abs(res[name] - ref).max())
        assert true <= res.errors[name] * 1.0 + 1e-15, name
        # and does not overstate it tenfold
        assert res.errors[name] <= 10 * true + 1e-12, name


@pytest.mark.slow
def test_tension_only_spans_go_slack_as_the_written_out_equations_do():
    """A pretension below the force the move needs: span 1 goes slack and takes up again; the
    clipped equations by Radau at rtol 1e-11 (steps of at most 1 ms)."""
    net = move_network(pretension=300.0)
    res = simulate(net, 0.5, 1001)
    x, v, F = reference_move(res.t, pretension=300.0)
    assert float(res["F_belt_1"].min()) == pytest.approx(0.0, abs=1e-12)      # it went slack
    assert_allclose(res["v_carriage"], v, rtol=0, atol=max(1e-6, 2 * res.errors["v_carriage"]))
    assert_allclose(res["F_belt"], F, rtol=0, atol=max(1e-3, 2 * res.errors["F_belt"]))


def test_the_jacobian_is_the_derivative_of_the_right_hand_side():
    for pretension in (None, 300.0):
        net = move_network(pretension)
        z = np.array([1.3, 0.3, 10.0, 0.2])
        z[1] = R * z[0] - 2e-4
        jac = net.nonlinear_jacobian(z)
        h = 1e-7
        numeric = np.array([(net.nonlinear_terms(0.0, z + h * e) - net.nonlinear_terms(0.0, z - h * e)) / (2 * h)
                            for e in np.eye(4)]).T
        assert_allclose(jac, numeric, rtol=1e-6, atol=1e-6 * np.abs(jac).max())


def test_held_at_its_start_the_belt_is_the_linear_spring_to_rounding():
    """Not moving, the carriage belt is the coupling C_spec (1/L1 + 1/L2) on u = r phi - x: the same
    matrices and, solved exactly, the same run to rounding; moving, its nonlinear remainder is 0 while
    the carriage is at its start."""
    k = C_SPEC * (1 / L1 + 1 / L2)
    b = B_SPEC * (1 / L1 + 1 / L2)
    nodes = [Inertia("pulley", 2e-3), Inertia("carriage", MASS, True)]
    held = Network(nodes, [Load("pulley", 1.5), CarriageBelt("belt", "pulley", "carriage", R, C_SPEC, B_SPEC, L1,
                                                             L2, moving=False)])
    spring = Network(nodes, [Load("pulley", 1.5), Coupling("belt", "pulley", "carriage", k * R ** 2, b * R ** 2,
                                                           1 / R)])
    assert held.linear
    assert_allclose(held.K, spring.K, rtol=1e-15)
    assert_allclose(held.D, spring.D, rtol=1e-15)
    a, c = simulate(held, 0.2, 401), simulate(spring, 0.2, 401)
    assert a.method == c.method == "exact"
    assert_allclose(a["v_carriage"], c["v_carriage"], rtol=0, atol=1e-12 * np.abs(c["v_carriage"]).max())
    assert_allclose(a["T_belt"], c["T_belt"], rtol=0, atol=1e-10 * np.abs(c["T_belt"]).max())
    moving = move_network()
    z = np.array([0.4, 0.0, 3.0, -0.2])
    assert_allclose(moving.nonlinear_terms(0.0, z), 0.0, atol=1e-12)


def test_held_at_a_position_the_network_has_the_two_spring_frequency():
    """A carriage between its two spans, the pulley held: f = sqrt((k1 + k2) / m) / (2 pi)."""
    net = move_network()
    for x in (-0.05, 0.0, 0.3, 0.6, 1.5):
        f = held_at(net, {"belt": x}).modes()[0][0]
        k = C_SPEC / (L1 + x) + C_SPEC / (L2 - x)
        assert f == pytest.approx(math.sqrt(k / MASS) / (2 * math.pi) * math.sqrt(1 - 0.0), rel=1e-3)


def test_a_carriage_that_reaches_a_pulley_fails_in_one_line(tmp_path):
    text = MOVE.read_text().replace('t_end = "0.5 s"', 't_end = "20 s"').replace('samples = 1001', 'samples = 201')
    path = tmp_path / "far.toml"
    path.write_text(text)
    code, _, stderr = cli("simulate", "drive", str(path))
    assert code == 1
    assert "reaches a pulley" in stderr
    assert "Traceback" not in stderr


@pytest.mark.parametrize("change, key", [
    ('span = "0.1 m"', 'span = "-0.1 m"'),
    ('stroke = "0.6 m"', 'stroke = "3 m"'),
    ('carriage = "carriage"', 'carriage = "pulley"'),
])
def test_bad_carriage_belts_are_refused_naming_the_key(tmp_path, change, key):
    path = tmp_path / "bad.toml"
    path.write_text(MOVE.read_text().replace(change, key))
    code, _, stderr = cli("simulate", "drive", str(path))
    assert code in (1, 2), stderr
    assert len(stderr.strip().splitlines()) == 1, stderr
    assert "Traceback" not in stderr


# --- moves shaped to the axis (the linear-axis scene, through the command) -------------------------------
def _scene(*sets: str) -> dict:
    args = ["simulate", "linear-axis", "--json"]
    for s in sets:
        args += ["--set", s]
    code, stdout, stderr = cli(*args)
    assert code == 0, stderr
    return json.loads(stdout)


UNDAMPED = ("damping=0N*s/m", "guide_friction=0", "shaper_at=end")


def test_a_zv_shaper_leaves_no_residual_vibration_at_its_design_frequency():
    """The WDU axis with its one belt span (the paper's model, linear: solved exactly), no damping
    and no friction: one undamped mode. The ZV-shaped move leaves none to rounding; EI leaves its
    tolerance, 5 %, of the unshaped move's."""
    plain = _scene(*UNDAMPED, "shaper=none")
    zv = _scene(*UNDAMPED, "shaper=zv")
    ei = _scene(*UNDAMPED, "shaper=ei")
    assert plain["method"] == zv["method"] == "exact"
    unshaped = plain["carriage"]["residual_amplitude"]["value"]
    assert unshaped == pytest.approx(5.685e-4, rel=1e-3)
    assert zv["carriage"]["residual_amplitude"]["value"] == pytest.approx(0.0, abs=1e-11 * unshaped + 1e-15)
    assert ei["carriage"]["residual_amplitude"]["value"] == pytest.approx(0.05 * unshaped, rel=1e-6)
    # the mode it was designed for: sqrt(k_TB / m) / 2 pi of the scene
    f = zv["carriage"]["shaper_frequency"]["value"]
    assert zv["carriage"]["shaper_time"]["value"] == pytest.approx(1 / (2 * f), rel=1e-12)


@pytest.mark.parametrize("ratio", [0.9, 1.07])
def test_off_its_frequency_the_zv_shaper_follows_its_sensitivity_curve(ratio):
    """Designed at f / r for a mode at f: the residual is |cos(pi r / 2)| of the unshaped move's
    (the ZV curve of an undamped mode [SS90])."""
    plain = _scene(*UNDAMPED, "shaper=none")
    f = _scene(*UNDAMPED, "shaper=zv")["carriage"]["shaper_frequency"]["value"]
    off = _scene(*UNDAMPED, "shaper=zv", f"shaper_frequency={f / ratio!r}Hz")
    expected = abs(math.cos(math.pi * ratio / 2)) * plain["carriage"]["residual_amplitude"]["value"]
    assert off["carriage"]["residual_amplitude"]["value"] == pytest.approx(expected, rel=1e-6)


def test_moving_spans_out_and_back_shaped_at_both_ends_settle():
    """The WDU axis with its spans following the carriage, out and back: unshaped it rings through
    both dwells; shaped for the modes where each move starts and stops (ZVD, convolved) it settles
    into 0.05 mm within them, and the report says what the shapers were designed for."""
    plain = _scene("spans=moving", "cycle=out-and-back", "shaper=none")
    shaped = _scene("spans=moving", "cycle=out-and-back", "shaper=zvd")
    c0, c1 = plain["carriage"], shaped["carriage"]
    assert c0["settling_time"]["value"] is None             # not within the 0.5 s dwell
    assert c0["settling_time_back"]["value"] == pytest.approx(0.62, abs=0.05)   # 0.6 s into the last 1 s
    assert c1["settling_time"]["value"] == pytest.approx(0.0, abs=0.01)
    assert c1["settling_time_back"]["value"] == pytest.approx(0.0, abs=0.01)
    assert c1["residual_amplitude"]["value"] == pytest.approx(0.0, abs=0.1 * c0["residual_amplitude"]["value"])
    # designed where each move stops: the two-span closed form, the drive held, at each end
    from beltcalc.design.sizing import axis_frequency
    from beltcalc.sim.scenes import linear_axis as la

    model = la.prepare_scene(la.SCENE.values(spans="moving"))[0]
    mass = la.build(model).node("carriage").J
    c_spec, a, d = model.stiffness * model.center_distance, model.center_distance, model.axis.pulley_diameter
    assert c1["shaper_frequency"]["value"] == pytest.approx(
        axis_frequency(c_spec, mass, a, d, model.start + model.travel), rel=1e-9)
    assert c1["shaper_frequency_back"]["value"] == pytest.approx(axis_frequency(c_spec, mass, a, d, model.start),
                                                                 rel=1e-9)
    checks = {c["key"]: c["verdict"] for c in shaped["checks"]}
    assert checks["settling"] == "pass"
    assert {c["key"]: c["verdict"] for c in plain["checks"]}["settling"] == "FAIL"


def test_motor_size_shapes_its_move_and_checks_the_settling():
    code, stdout, stderr = cli("motor-size", "--shaper", "zv", "--settle-band", "0.05mm", "--json")
    assert code == 0, stderr
    d = json.loads(stdout)
    assert d["shaper_frequency"]["unit"] == "Hz"
    # ZV convolved for both ends: half a period of each mode
    from beltcalc.design.sizing import axis_frequency

    f_end = d["shaper_frequency"]["value"]
    assert f_end == pytest.approx(axis_frequency(5.5e5, 50.0 + 0.0005746, 1.245, 0.12732395447351627, 1.1225),
                                  rel=1e-3)
    checks = {c["key"]: c for c in d["checks"]}
    assert checks["settling"]["verdict"] == "pass"
    assert checks["settling_back"]["verdict"] == "pass"
