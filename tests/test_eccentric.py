"""The eccentric-belt element (issue 15): without eccentricity it is the constant-ratio coupling;
its analytic Jacobian against finite differences; energy conserved without damping over 100
roller periods; Radau and BDF agree at tight tolerance; its ratio output is the geometry's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim.elements.beltpath import Eccentric, eccentric_ratio
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.elements.eccentric import EccentricBelt
from beltcalc.sim.network import Coupling, Inertia, Load, Network

GEO = Eccentric(r1=0.02, r2=0.0275, a=0.30, r3=0.015, px=0.15, py=-0.030, delta=0.002)
J1, J2, C1, D1 = 1.0e-4, 2.0e-4, 300.0, 0.0


def belt(delta=GEO.delta, d=D1, C=C1):
    geo = Eccentric(**{**GEO.__dict__, "delta": delta})
    return EccentricBelt("b", "m", "r", C, d, geo)


def network(delta=GEO.delta, d=D1, loads=(), J=(J1, J2)):
    return Network([Inertia("m", J[0]), Inertia("r", J[1])], [*loads, belt(delta, d)])


def test_without_eccentricity_it_is_the_constant_ratio_coupling():
    plain = network(delta=0.0, d=0.05, loads=[Load("r", 0.01, amplitude=0.02, omega=40.0)])
    ref = Network([Inertia("m", J1), Inertia("r", J2)],
                  [Coupling("b", "m", "r", C1, 0.05, U=1.375), Load("r", 0.01, amplitude=0.02, omega=40.0)])
    assert plain.linear
    assert_allclose(plain.first_order(None, 0.0)[0], ref.first_order(None, 0.0)[0], rtol=0, atol=0)
    a = simulate(plain, 0.5, 501)
    b = simulate(ref, 0.5, 501)
    assert_allclose(a.states, b.states, rtol=0, atol=0)
    assert_allclose(a["T_b"], b["T_b"], rtol=0, atol=1e-10 * np.abs(b["T_b"]).max())   # two groupings of one sum


def test_tiny_eccentricity_tends_to_the_constant_ratio_drive():
    loads = [Load("r", 0.01, amplitude=0.02, omega=40.0)]
    cfg = SolverConfig(method="radau", rtol=1e-11, atol=1e-13, estimate_error=False)
    ref = simulate(network(0.0, 0.05, loads), 0.3, 301)
    diffs = []
    for delta in (1e-7, 1e-8, 0.0):
        run = simulate(network(delta, 0.05, loads), 0.3, 301, cfg)
        diffs.append(np.abs(run["omega_r"] - ref["omega_r"]).max())
    # the difference falls in proportion to delta (1e-7 m: 1.7e-6 rad/s), and at delta = 0 Radau
    # meets the exact constant-ratio run to its tolerance
    assert diffs[1] == pytest.approx(diffs[0] / 10, rel=0.01)
    assert diffs[2] == pytest.approx(0.0, abs=1e-9 * np.abs(ref["omega_r"]).max())


def test_analytic_jacobian_matches_finite_differences():
    net = network(d=0.04)
    rng = np.random.default_rng(3)
    for _ in range(5):
        x = rng.normal(size=net.size) * np.array([2.0, 2.0, 30.0, 30.0])
        jac = net.nonlinear_jacobian(x)
        h = 1e-5     # central differences: truncation 1e-10, rounding 1e-11 of the entries here
        fd = np.empty_like(jac)
        for k in range(net.size):
            e = np.zeros(net.size)
            e[k] = h
            fd[:, k] = (net.nonlinear_terms(0.0, x + e) - net.nonlinear_terms(0.0, x - e)) / (2 * h)
        scale = np.abs(fd).max()
        assert_allclose(jac, fd, rtol=0, atol=1e-7 * scale)


def energy(net, el, X, J):
    phi_m, phi_r, w_m, w_r = X
    g = el.geometry
    delta = el.stretch(phi_m)[0]
    x = g.r1 * phi_m - g.r2 * phi_r
    return 0.5 * J[0] * w_m ** 2 + 0.5 * J[1] * w_r ** 2 + 0.5 * el.k * (x ** 2 + (delta - x) ** 2)


@pytest.mark.slow
def test_energy_is_conserved_without_damping_over_100_roller_periods():
    J = (1e-2, 2e-2)       # heavy shafts: the belt mode (about 28 Hz) well below the roller's 127 Hz
    net = network(d=0.0, J=J)
    el = net.elements[-1]
    w = 600.0                                         # rad/s at the motor pulley (5730 rpm)
    x0 = np.array([0.0, 0.0, w, w / 1.375])
    period = 2 * math.pi * GEO.r3 / (GEO.r1 * w)      # one roller turn
    cfg = SolverConfig(method="radau", rtol=1e-11, atol=1e-13, estimate_error=False)
    run = simulate(net, 100 * period, 2001, cfg, x0=x0)
    E = energy(net, el, run.states, J)
    assert E[0] == pytest.approx(0.5 * J[0] * w ** 2 + 0.5 * J[1] * (w / 1.375) ** 2, rel=1e-12)
    assert_allclose(E, E[0], rtol=1e-8)
    # the eccentric really acts: the ratio sweeps its whole ripple (the run passes every roller angle)
    ratios = [eccentric_ratio(GEO, t) for t in np.linspace(0.0, 2 * math.pi, 3601)]
    assert np.ptp(run["U_b"]) == pytest.approx(max(ratios) - min(ratios), rel=0.02)   # 20 samples a turn


def test_radau_and_bdf_agree():
    loads = [Load("r", 0.01, amplitude=0.02, omega=40.0)]
    net = network(d=0.05, loads=loads)
    x0 = np.array([0.0, 0.0, 60.0, 60.0 / 1.375])
    a = simulate(net, 0.2, 201, SolverConfig(method="radau", rtol=1e-11, atol=1e-13, estimate_error=False), x0=x0)
    b = simulate(net, 0.2, 201, SolverConfig(method="bdf", rtol=1e-11, atol=1e-13, estimate_error=False), x0=x0)
    assert_allclose(a["omega_r"], b["omega_r"], rtol=0, atol=1e-7 * np.abs(a["omega_r"]).max())


def test_ratio_output_is_the_geometry_ratio_and_auto_says_why():
    net = network(d=0.05)
    run = simulate(net, 0.05, 51, x0=np.array([0.0, 0.0, 60.0, 60.0 / 1.375]))
    # not stiff (its fastest pole is its belt mode): auto runs it on DOP853 and says why
    assert "eccentric tension roller" in run.reason and run.method == "dop853" and "not stiff" in run.reason
    theta = GEO.theta(run["phi_m"])
    assert_allclose(run["U_b"], [eccentric_ratio(GEO, t) for t in theta], rtol=1e-10)


ROLLER_FILE = """
[drive]
title = "two shafts and a belt with an eccentric tension roller"
t_end = "0.03 s"
samples = 31
window = "0.02 s"

[[node]]
name = "motor"
inertia = "1e-4 kg*m^2"
pitch_diameter = "40 mm"

[[node]]
name = "rim"
inertia = "2e-4 kg*m^2"

[[coupling]]
name = "belt"
between = ["motor", "rim"]
stiffness = "300 N*m/rad"
damping = "0.05 N*m*s/rad"
ratio = 1.375
eccentricity = "2 mm"
roller_radius = "15 mm"
center_distance = "300 mm"
pivot_x = "150 mm"
pivot_y = "-30 mm"

[[load]]
node = "rim"
torque = "0.01 N*m"
amplitude = "0.02 N*m"
frequency = "40 rad/s"

[[motor]]
name = "m"
node = "motor"
kind = "prescribed"
speed = "60 rad/s"
"""


def test_a_drive_file_coupling_with_an_eccentric_roller(tmp_path):
    import json

    from click.testing import CliRunner

    from beltcalc.cli.main import cli
    from beltcalc.sim.drivefile import DriveFile

    path = tmp_path / "roller.toml"
    path.write_text(ROLLER_FILE, encoding="utf-8")
    net = DriveFile(path).network()
    belt_el = next(el for el in net.elements if isinstance(el, EccentricBelt))
    assert belt_el.geometry == GEO and not net.linear
    result = CliRunner().invoke(cli, ["simulate", "drive", str(path), "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    assert "eccentric tension roller" in out["reason"]
    flat = CliRunner().invoke(cli, ["simulate", "drive", str(path), "--set", "belt.eccentricity=0mm", "--json"])
    assert flat.exit_code == 0, flat.output
    assert json.loads(flat.stdout)["method"] == "exact"


@pytest.mark.slow
def test_sewing_scene_with_the_eccentric_roller():
    # the scene's assumed roller (r1 = 25 mm, r3 = 20 mm, a = 250 mm, pivot (125, -40) mm) with
    # Delta = 2 mm: U12's extremes are the geometry's, the amplitudes are set against the
    # constant-ratio drive run alike, and there is no exact steady state
    import json

    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    from clichecks import sewing_eccentric_run

    result, _ = sewing_eccentric_run()                  # docs/scenes.md's run, shared with the hard cases
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    geo = Eccentric(r1=0.025, r2=0.025 * 1.375, a=0.25, r3=0.02, px=0.125, py=-0.04, delta=0.002)
    ratios = [eccentric_ratio(geo, t) for t in np.linspace(0.0, 2 * math.pi, 3601)]
    roller = out["roller"]
    assert roller["ratio_min"]["value"] == pytest.approx(min(ratios), rel=2e-4)
    assert roller["ratio_max"]["value"] == pytest.approx(max(ratios), rel=2e-4)
    assert roller["ripple_frequency"]["value"] == pytest.approx(
        0.025 / 0.02 * out["motor"]["speed_mean"]["value"] / (2 * math.pi), rel=1e-12)
    plain = json.loads(CliRunner().invoke(cli, ["simulate", "sewing", "--json"]).stdout)
    assert roller["main_torque_amplitude_constant"]["value"] == pytest.approx(
        plain["shafts"]["main"]["torque_amplitude"]["value"], rel=1e-6)
    assert roller["main_torque_amplitude_ratio"]["value"] == pytest.approx(
        roller["main_torque_amplitude"]["value"] / roller["main_torque_amplitude_constant"]["value"], rel=1e-12)
    assert "eccentric tension roller" in out["reason"] and "steady_state" not in out
    # the figures docs/scenes.md quotes
    from pathlib import Path

    readme = " ".join((Path(__file__).parents[1] / "docs" / "scenes.md").read_text(encoding="utf-8").split())
    quoted = {"between 1.3640 and 1.3861": (roller["ratio_min"]["value"], roller["ratio_max"]["value"]),
              "at 62.22 Hz": roller["ripple_frequency"]["value"],
              "speed amplitude is 1.11 times": roller["main_speed_amplitude_ratio"]["value"],
              "torque amplitude 3.28 times": roller["main_torque_amplitude_ratio"]["value"],
              "torque amplitude is 1.81 times": roller["bottom_torque_amplitude_ratio"]["value"]}
    for text, value in quoted.items():
        assert text in readme, text
        numbers = __import__("re").findall(r"\d+\.\d+", text)
        values = value if isinstance(value, tuple) else (value,)
        for shown, v in zip(numbers, values):          # to half a unit of the last printed digit
            assert v == pytest.approx(float(shown), abs=0.5 * 10 ** -len(shown.split(".")[1])), text
    refused = CliRunner().invoke(cli, ["simulate", "sewing", "--set", "roller_eccentricity=2mm",
                                       "--steady-state-only"])
    assert refused.exit_code == 1 and "no exact steady state" in refused.stderr


def test_the_roller_ripple_is_an_excitation_of_the_resonance_check():
    from beltcalc.sim.result import SimResult
    from beltcalc.sim.scenes.base import resonance_check

    t = np.linspace(0.0, 1.0, 101)
    result = SimResult(t=t, signals={"omega_m": np.full(t.size, 60.0)}, units={"omega_m": "rad/s"},
                       method="exact", reason="", wall_time=0.0, steps=0, rhs_calls=0)
    el = belt()
    assert el.excitation(result, 0.5) == [(pytest.approx(0.02 / 0.015 * 60.0 / (2 * math.pi)), "the tension roller of b")]
    # the two shafts on the belt alone: one mode; the roller at 60 rad/s excites 12.7 Hz
    net = network(d=0.05)
    check, = resonance_check(net, result, 0.5)
    assert "the tension roller of b excites 12.73 Hz" in check.rule
