"""The eccentric roller's belt against its pretension (issue 26, item 6).

The sewing drive with the eccentric tension roller (``beltcalc simulate sewing --set
roller_eccentricity=...``): each span's force against the pretension, tension-only spans
where a pretension is given (docs/eccentric_roller.md section 7), and the refusals with their
true causes (section 8).

The reference is independent of the library's right-hand side: the drive's equations are
written here from [M16 eq. 2-7] (five inertias, the couplings C2..C4, the loads M3 and M5, the
motor lag of eq. 2) with the belt of docs/eccentric_roller.md E1-E8 (the loop length from the
three circles' common tangents and arcs, its rate from E3, tension-only spans), and solved by
scipy's Radau at rtol 1e-11, stopped at every switch of a span (events on min(spring force,
force) of each span), where the library's Radau steps over the switches unaided. The inputs
are the scene file's values (``SCENES["sewing"].values``); nothing is compared with the code's
own earlier output.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from beltcalc.cli.main import cli
from beltcalc.sim.elements.beltpath import Eccentric
from beltcalc.sim.elements.eccentric import EccentricBelt, contact_limit
from beltcalc.sim.network import Inertia, Network
from beltcalc.sim.scenes import SCENES

from clichecks import ok, one_error_line, read_csv, warnings

RTOL_REF, ATOL_REF = 1e-11, 1e-12
# The reference's own error at these tolerances: against the same solution at rtol 1e-12,
# atol 1e-13 its speeds differ by 5.7e-9 rad/s (2 mm, 60 N, 0.05 s; its switch times by 1.1e-12 s)
# and 1.1e-9 rad/s (0.5 mm, 600 N, 0.1 s); the bound used is about twice the larger.
REF_ERROR = 1e-8      # rad/s
CSV_DIGITS = 1e-10    # %.10g in the CSV: relative rounding of a written value


# --- the independent model ------------------------------------------------------------------------
def _tangent(ci, ri, cj, rj):
    """Length and direction of the belt from circle i to circle j (E1; signed radii)."""
    dx, dy = cj[0] - ci[0], cj[1] - ci[1]
    D = math.hypot(dx, dy)
    ex, ey = dx / D, dy / D
    dr = rj - ri
    length = math.sqrt(D * D - dr * dr)
    return length, ((length * ex + dr * ey) / D, (length * ey - dr * ex) / D)


def _turn(u, v, rho):
    """The belt's turn on a circle from the arriving direction u to the leaving one v, in the
    circle's wrap direction (counter-clockwise for rho > 0) [rad, in [0, 2 pi)]."""
    angle = math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])
    return (angle if rho > 0 else -angle) % (2 * math.pi)


def belt_length(theta, g):
    """(L, dL/dtheta, the roller's wrap angle) of the loop motor pulley -> roller -> rim at the
    roller angle theta: spans plus arcs, the arcs from the turn of the belt's direction (not the
    contact points, as the library does); dL/dtheta from E3."""
    c = (g["px"] + g["D"] * math.cos(theta), g["py"] + g["D"] * math.sin(theta))
    circles = [((0.0, 0.0), g["r1"]), (c, -g["r3"]), ((g["a"], 0.0), g["r2"])]
    spans = [_tangent(*circles[k], *circles[(k + 1) % 3]) for k in range(3)]
    wraps = [_turn(spans[k - 1][1], spans[k][1], circles[k][1]) for k in range(3)]
    L = sum(s[0] for s in spans) + sum(abs(circles[k][1]) * wraps[k] for k in range(3))
    du = (spans[0][1][0] - spans[1][1][0], spans[0][1][1] - spans[1][1][1])      # u_in - u_out on the roller
    return L, g["D"] * (-du[0] * math.sin(theta) + du[1] * math.cos(theta)), wraps[1]


def drive(v: dict, pretension):
    """The sewing drive of the scene values ``v`` [M16 eq. 2-7]: the motor's synchronous speed
    2 pi f / p, breakdown torque and slip; the load frequency, the steady main-shaft speed under
    the mean loads (the static motor characteristic with the loads reflected through U12)."""
    r1 = v["motor_pulley_radius"]
    g = dict(r1=r1, r2=v["U12"] * r1, a=v["belt_center_distance"], r3=v["roller_radius"], px=v["roller_pivot_x"],
             py=v["roller_pivot_y"], D=v["roller_eccentricity"])
    w0 = 2 * math.pi * v["supply_frequency"] / v["pole_pairs"]
    mc = v["breakdown_factor"] * v["rated_torque"]
    motor_load = (v["M3_0"] + v["M5_0"]) / v["U12"]
    w = w0 * (1 - v["breakdown_slip"] * motor_load / (2 * mc)) / v["U12"]
    return dict(g=g, J=[v[f"J{k}"] for k in range(1, 6)], C=[v[f"C{k}"] for k in range(1, 5)],
                d=[v[f"d{k}"] for k in range(1, 5)], U23=v["U23"], w0=w0, Mc=mc, Sc=v["breakdown_slip"],
                wc=2 * math.pi * v["supply_frequency"], w=w, M3=(v["M3_0"], v["M3_amp"]),
                M5=(v["M5_0"], v["M5_amp"]), F0=pretension, L0=belt_length(0.0, g)[0],
                k=v["C1"] / (2 * r1 ** 2), b=v["d1"] / (2 * r1 ** 2))


def span_forces(m, y):
    """((spring, force) of the tight span, of the slack span, delta_phi) at the state y, the
    spans taut (E8): F_t = F_0 + k x + b xdot, F_s = F_0 + k (delta - x) + b (deltadot - xdot)."""
    g, k, b = m["g"], m["k"], m["b"]
    L, L1, _ = belt_length(-g["r1"] * y[0] / g["r3"], g)          # theta = theta0 - r1 phi1 / r3, theta0 = 0
    delta, dphi = L - m["L0"], -g["r1"] / g["r3"] * L1
    x, xdot = g["r1"] * y[0] - g["r2"] * y[1], g["r1"] * y[5] - g["r2"] * y[6]
    f0 = m["F0"] or 0.0
    st, ss = f0 + k * x, f0 + k * (delta - x)
    return (st, st + b * xdot), (ss, ss + b * (dphi * y[5] - xdot)), dphi


def rhs(t, y, m, mode):
    """x' of the state (phi_1..5, omega_1..5, M) with the spans on (mode 1) or slack (0)."""
    g = m["g"]
    (_, ft), (_, fs), dphi = span_forces(m, y)
    ft, fs = ft * mode[0], fs * mode[1]
    J, C, d, U = m["J"], m["C"], m["d"], m["U23"]
    q2 = C[1] * (y[1] - U * y[2]) + d[1] * (y[6] - U * y[7])
    q3 = C[2] * (y[2] - y[3]) + d[2] * (y[7] - y[8])
    q4 = C[3] * (y[3] - y[4]) + d[3] * (y[8] - y[9])
    s = math.sin(m["w"] * t)
    acc = [(y[10] - g["r1"] * ft + (g["r1"] - dphi) * fs) / J[0],
           (g["r2"] * (ft - fs) - q2) / J[1],
           (U * q2 - q3 - m["M3"][0] - m["M3"][1] * s) / J[2],
           (q3 - q4) / J[3],
           (q4 - m["M5"][0] - m["M5"][1] * s) / J[4]]
    torque = 2 * m["Mc"] * m["wc"] / m["w0"] * (m["w0"] - y[5]) - m["wc"] * m["Sc"] * y[10]
    return [*y[5:10], *acc, torque]


def _on(m, y) -> tuple[bool, bool]:
    if m["F0"] is None:
        return True, True
    return tuple(bool(e > 0 and f > 0) for e, f in span_forces(m, y)[:2])


def forces(m, Y) -> np.ndarray:
    """The spans' forces (2 x samples): tension-only with a pretension."""
    out = np.empty((2, Y.shape[1]))
    for j in range(Y.shape[1]):
        (et, ft), (es, fs), _ = span_forces(m, Y[:, j])
        if m["F0"] is None:
            out[:, j] = ft, fs
        else:
            out[:, j] = ft if et > 0 and ft > 0 else 0.0, fs if es > 0 and fs > 0 else 0.0
    return out


_REFS: dict = {}


def reference(eccentricity: float, pretension, t_end: float, samples: int, rtol=RTOL_REF, atol=ATOL_REF):
    """(t, states 11 x samples, switches [(t, span, on)], model): from rest, Radau stopped at
    every switch of a span and restarted in the other mode."""
    key = (eccentricity, pretension, t_end, samples, rtol, atol)
    if key in _REFS:
        return _REFS[key]
    v = SCENES["sewing"].values(roller_eccentricity=eccentricity)
    m = drive(v, pretension)
    t_eval = np.linspace(0.0, t_end, samples)
    y, t0 = np.zeros(11), 0.0
    mode = _on(m, y)
    parts, switches = [(np.array([0.0]), np.zeros((11, 1)))], []
    while True:
        events = []
        if pretension is not None:
            for s in range(2):
                def event(t, yy, *_, s=s):
                    return min(span_forces(m, yy)[s])
                event.terminal, event.direction = True, (-1 if mode[s] else 1)
                events.append(event)
        sol = solve_ivp(rhs, (t0, t_end), y, method="Radau", t_eval=t_eval[(t_eval > t0) & (t_eval <= t_end)],
                        rtol=rtol, atol=atol, args=(m, mode), events=events or None)
        assert sol.status >= 0, sol.message
        if len(sol.t):
            parts.append((sol.t, sol.y))
        if sol.status == 0:
            break
        t0, s = min((float(e[0]), k) for k, e in enumerate(sol.t_events) if e.size)
        y = sol.y_events[s][0]
        mode = tuple(not on if k == s else on for k, on in enumerate(mode))
        switches.append((t0, s, mode[s]))
    t = np.concatenate([p[0] for p in parts])
    Y = np.concatenate([p[1] for p in parts], axis=1)
    assert_allclose(t, t_eval, rtol=0, atol=1e-15)
    _REFS[key] = (t, Y, switches, m)
    return _REFS[key]


def run_cli(tmp_path, *settings: str, t_end: str, window: str, samples: int):
    """``beltcalc simulate sewing --set ... --json --csv``: (JSON, CSV columns, warnings)."""
    csv_path = tmp_path / "run.csv"
    args = ["simulate", "sewing"]
    for s in settings:
        args += ["--set", s]
    args += ["--t-end", t_end, "--window", window, "--samples", str(samples), "--json", "--csv", str(csv_path)]
    result = ok(CliRunner().invoke(cli, args))
    out = json.loads(result.stdout)
    assert out["warnings"] == warnings(result)
    return out, read_csv(csv_path)[1], out["warnings"]


def check_speeds(out, cols, Y):
    """Every shaft's speed against the reference, to 10 times the run's error estimate (its
    worst figure's relative error times the speeds' scale; DESIGN.md 3.0: it never understates
    the true error by more than 10x) plus the reference's own error and the CSV's rounding;
    returns the largest difference."""
    estimate = speed_estimate(out, Y)
    assert 0 < out["error_relative"]["value"] <= 1e-6          # the run met its tolerance
    worst = 0.0
    for k in range(1, 6):
        lib, ref = cols[f"omega_{k}_rad_per_s"], Y[4 + k]
        tol = 10 * estimate + REF_ERROR + CSV_DIGITS * np.abs(ref).max()
        assert_allclose(lib, ref, rtol=0, atol=tol, err_msg=f"omega_{k}")
        worst = max(worst, float(np.abs(lib - ref).max()))
    return worst


def speed_estimate(out, Y) -> float:
    """The run's claimed error of a speed [rad/s]: its worst figure's relative error (a speed's or
    a torque's, each on its unit's scale) times the speeds' scale."""
    return out["error_relative"]["value"] * max(np.abs(Y[4 + k]).max() for k in range(1, 6))


def force_tolerance(out, m, t_end: float, Y) -> float:
    """A span force's error bound from the speeds' [N]: the damper's b r |d omega| plus the
    spring's k r |d phi|, |d phi| <= |d omega| t_end (r: the larger pulley radius)."""
    bound = 10 * speed_estimate(out, Y) + REF_ERROR
    return 2 * m["g"]["r2"] * bound * (m["b"] + m["k"] * t_end)


# --- (a) a taut run -------------------------------------------------------------------------------
@pytest.mark.slow
def test_a_taut_run_agrees_with_the_independent_radau_reference(tmp_path):
    # 0.5 mm of eccentricity and 600 N of pretension: the start from rest (its drop is the
    # largest) leaves the slack span 344 N, so no span switches and the tension-only model is the
    # taut one, its pretension term F_0 delta_phi included
    t, Y, switches, m = reference(0.0005, 600.0, 0.1, 1001)
    assert switches == []
    ref_forces = forces(m, Y)
    assert ref_forces.min() > 300.0
    out, cols, warned = run_cli(tmp_path, "roller_eccentricity=0.5mm", "belt_pretension=600N", t_end="0.1s",
                                window="0.05s", samples=1001)
    assert not [w for w in warned if w.startswith("belt 12")]
    assert out["method"] == "radau"
    worst = check_speeds(out, cols, Y)
    tol = force_tolerance(out, m, 0.1, Y)
    for k, side in enumerate(("tight", "slack")):
        assert_allclose(cols[f"F_12_{side}_N"], ref_forces[k], rtol=CSV_DIGITS, atol=tol)
        assert out["roller"][f"{side}_force_min_run"]["value"] == pytest.approx(ref_forces[k].min(), abs=tol)
    assert out["roller"]["pretension"]["value"] == 600.0
    check, = (c for c in out["checks"] if c["key"] == "belt_spans_taut")
    assert check["verdict"] == "pass"
    # the estimate covers the speeds' true error (it is the shaft torque T_23's, a stiffness times
    # a difference of angles, relatively 7x larger: tests/test_hard_cases_cli.py holds that one
    # against Radau; measured here 1.02e-6 against 7.6e-6 rad/s)
    assert worst <= speed_estimate(out, Y)


# --- (b) a run whose spans go slack ---------------------------------------------------------------
@pytest.mark.slow
def test_a_slackening_span_warns_and_is_tension_only(tmp_path):
    # 2 mm with 60 N: the slack span's force would swing by about 260 N, so it goes slack at the
    # start and again once a roller turn; the reference finds the switches by events
    t, Y, switches, m = reference(0.002, 60.0, 0.05, 501)
    assert len(switches) >= 4 and {(s, on) for _, s, on in switches} >= {(1, False), (1, True)}
    ref_forces = forces(m, Y)
    out, cols, warned = run_cli(tmp_path, "roller_eccentricity=2mm", "belt_pretension=60N", t_end="0.05s",
                                window="0.02s", samples=501)
    period = 2 * math.pi / m["w"]                        # the window: whole load periods up to t_end
    start = cols["t_s"] >= 0.05 - math.floor((0.05 - 0.02) / period) * period - 1e-12
    shares = {side: float(np.mean(ref_forces[k][start] <= 0)) for k, side in enumerate(("tight", "slack"))}
    assert min(shares.values()) > 0.2              # here both spans go slack in the window (the start's swing)
    side = max(shares, key=shares.get)
    other = "slack" if side == "tight" else "tight"
    line, = (w for w in warned if w.startswith("belt 12"))
    for fragment in (f"its {side} span loses its tension", "from the pretension 60 N to 0 N", f"the {other} span ",
                     "modelled tension-only", "from an eccentricity of about", "here 2 mm", "--set belt_pretension"):
        assert fragment in line, (fragment, line)
    assert out["roller"]["slack_force_min"]["value"] == pytest.approx(0.0, abs=1e-12)
    assert out["roller"]["slack_force_min_run"]["value"] == pytest.approx(0.0, abs=1e-12)
    for k in shares:          # a sample near a switch may fall either side within the run's error
        assert out["roller"][f"{k}_slack_share"]["value"] == pytest.approx(shares[k], abs=2.5 / start.sum())
    check, = (c for c in out["checks"] if c["key"] == "belt_spans_taut")
    assert check["verdict"] == "FAIL" and check["value"]["value"] == pytest.approx(0.0, abs=1e-12)
    assert sum("belt 12" in w for w in warned) == 1                  # one line, the check's
    worst = check_speeds(out, cols, Y)
    # forces: 0 where the reference's span is slack, the reference's force elsewhere (a sample
    # near a switch may fall either side within the run's error: a force of at most the bound)
    tol = force_tolerance(out, m, 0.05, Y)
    for k, side in enumerate(("tight", "slack")):
        assert_allclose(cols[f"F_12_{side}_N"], ref_forces[k], rtol=CSV_DIGITS, atol=tol)
    assert np.all(cols["F_12_slack_N"][ref_forces[1] == 0] == 0.0)
    assert worst <= speed_estimate(out, Y)     # measured 4.3e-6 against 3.8e-4 rad/s (T_23's estimate)


@pytest.mark.slow
def test_radau_at_rtol_1e_11_converges_through_the_switches():
    # the library's Radau with its analytic Jacobian and no events, through the same run's
    # unloadings (a kink) and take-ups (a jump of the damper's force): measured 1.4e-8 rad/s from
    # the evented reference at 0.05 s (speeds up to 140 rad/s)
    from beltcalc.sim.core import SolverConfig, simulate
    from beltcalc.sim.scenes.sewing import build

    t, Y, switches, m = reference(0.002, 60.0, 0.05, 501)
    net = build(SCENES["sewing"].values(roller_eccentricity=0.002, belt_pretension=60.0))
    run = simulate(net, 0.05, 501, SolverConfig(method="radau", rtol=1e-11, atol=1e-13, estimate_error=False))
    for k in range(1, 6):
        assert_allclose(run[f"omega_{k}"], Y[4 + k], rtol=0, atol=1e-7, err_msg=f"omega_{k}")
    assert run["F_12_slack"].min() == 0.0 and run["F_12_tight"].min() >= 0.0


# --- the pieces of the warning --------------------------------------------------------------------
def test_jacobian_with_tension_only_spans_matches_finite_differences():
    geo = Eccentric(r1=0.02, r2=0.0275, a=0.30, r3=0.015, px=0.15, py=-0.030, delta=0.002)
    belt = EccentricBelt("b", "m", "r", 300.0, 0.04, geo, pretension=40.0)
    net = Network([Inertia("m", 1e-4), Inertia("r", 2e-4)], [belt])
    rng = np.random.default_rng(3)
    seen = set()
    h = 1e-7
    for _ in range(40):
        x = rng.normal(size=net.size) * np.array([0.01, 0.01, 3.0, 3.0])
        mode = tuple(bool(v) for v in belt.spans(net, x)[4:6])
        shifted = [x + sign * h * np.eye(net.size)[k] for k in range(net.size) for sign in (-1, 1)]
        if any(tuple(bool(v) for v in belt.spans(net, y)[4:6]) != mode for y in shifted):
            continue                  # a switch within the difference's reach: no derivative to compare
        seen.add(mode)
        jac = net.nonlinear_jacobian(x)
        fd = np.empty_like(jac)
        for k in range(net.size):
            fd[:, k] = (net.nonlinear_terms(0.0, shifted[2 * k + 1]) - net.nonlinear_terms(0.0, shifted[2 * k])) / (2 * h)
        # central differences at h = 1e-7: rounding about 1e-9 of the largest entry, truncation less
        assert_allclose(jac, fd, rtol=0, atol=1e-6 * np.abs(fd).max())
    assert seen >= {(True, True), (True, False), (False, True)}


def test_quasi_static_swing_and_the_slackening_eccentricity():
    # (k delta + b delta_phi omega) / 2 over a roller turn, from the independent path above
    v = SCENES["sewing"].values(roller_eccentricity=0.002)
    from beltcalc.sim.scenes.sewing import build

    belt = next(el for el in build(v).elements if isinstance(el, EccentricBelt))
    m = drive(v, None)
    speed = 298.0

    def swing(delta):
        g = dict(m["g"], D=delta)
        L0 = belt_length(0.0, g)[0]
        values = []
        for theta in np.linspace(0.0, 2 * math.pi, 720, endpoint=False):
            L, L1, _ = belt_length(theta, g)
            values.append((m["k"] * (L - L0) - m["b"] * g["r1"] / g["r3"] * L1 * speed) / 2)
        return min(values), max(values)

    assert belt.swing(speed) == pytest.approx(swing(0.002), rel=1e-3)       # 180 against 720 angles
    at = belt.slackening_eccentricity(60.0, speed)
    assert 0.3e-3 < at < 0.6e-3
    assert swing(at)[0] == pytest.approx(-60.0, rel=5e-3)
    assert belt.slackening_eccentricity(0.0, speed) == 0.0
    assert belt.slackening_eccentricity(1e5, speed) is None       # taut up to where the belt leaves the roller


def test_the_contact_limit_is_where_the_wrap_on_the_roller_vanishes():
    v = SCENES["sewing"].values()
    g = dict(drive(v, None)["g"])
    limit = contact_limit(Eccentric(r1=g["r1"], r2=g["r2"], a=g["a"], r3=g["r3"], px=g["px"], py=g["py"], delta=0.0))
    assert limit == pytest.approx(9.716e-3, abs=1e-6)          # the scene's pivot (125, -40) mm
    thetas = np.linspace(0.0, 2 * math.pi, 20001)

    def wraps(delta):
        return np.array([belt_length(t, dict(g, D=delta))[2] for t in thetas])

    # just below the limit the belt wraps the roller at every angle, by a vanishing angle once a
    # turn (measured 1.6e-5 rad at 1e-4 below); just past it the wrap angle passes through zero
    # and turns negative (the tangent construction gives nearly 2 pi): the belt leaves the roller
    below, past = wraps(limit * (1 - 1e-4)), wraps(limit * (1 + 1e-4))
    assert 0 < below.min() < 1e-4 and below.max() < 1.0
    assert past.max() > math.pi


def test_without_a_pretension_it_warns_and_a_short_window_promises_no_steady_rows():
    result = ok(CliRunner().invoke(cli, ["simulate", "sewing", "--set", "roller_eccentricity=2mm", "--t-end", "0.03s",
                                         "--window", "0.02s", "--samples", "301", "--json"]))
    out = json.loads(result.stdout)
    line, = (w for w in out["warnings"] if w.startswith("belt 12"))
    for fragment in ("no pretension given (--set belt_pretension)", "two-way springs", "N below its pretension",
                     "give --set belt_pretension to model the spans tension-only"):
        assert fragment in line, (fragment, line)
    short, = (w for w in out["warnings"] if "shorter than one load period" in w)
    assert "steady-state rows" not in short and "steady_state" not in out
    assert out["roller"]["slack_force_min"]["value"] < 0 and "pretension" not in out["roller"]


# --- (c) refusals with their causes ----------------------------------------------------------------
@pytest.mark.parametrize("settings, fragments", [
    (["roller_eccentricity=25mm"], ["--set roller_eccentricity:", "25 mm is not allowed", "< 20 mm, the roller radius",
                                    "pivot lies inside its roller"]),
    (["roller_eccentricity=20mm"], ["--set roller_eccentricity:", "20 mm is not allowed", "< 20 mm"]),
    (["roller_eccentricity=12mm"], ["--set roller_eccentricity:", "12 mm is not allowed", "< 9.716 mm",
                                    "the belt leaves it", "wrap angle on the roller falls to zero"]),
    (["roller_eccentricity=2mm", "roller_pivot_x=10mm"], ["--set roller_pivot_x:", "(10, -40) mm",
                                                          "puts the roller on the motor pulley"]),
    (["roller_eccentricity=2mm", "roller_pivot_x=240mm"], ["--set roller_pivot_x:", "on the driven rim"]),
    (["roller_eccentricity=2mm", "roller_pivot_y=-70mm"], ["--set roller_pivot_y:", "(125, -70) mm",
                                                           "leaves the roller clear of the belt"]),
    (["roller_eccentricity=2mm", "roller_pivot_y=10mm"], ["--set roller_pivot_y:", "through the tight span"]),
    (["roller_eccentricity=2mm", "belt_center_distance=50mm"], ["--set belt_center_distance:", "the pulleys overlap",
                                                                "> r1 + r2 = 59.38 mm"]),
    (["roller_eccentricity=2mm", "belt_pretension=-3N"], ["--set belt_pretension:", "-3 N is not allowed",
                                                          ">= 0 N"]),
])
def test_each_refusal_names_its_true_cause(settings, fragments):
    args = ["simulate", "sewing"]
    for s in settings:
        args += ["--set", s]
    line = one_error_line(CliRunner().invoke(cli, args + ["--t-end", "0.01s", "--window", "0.005s"]), 1, *fragments)
    assert "nearly touches" not in line


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
eccentricity = "10 mm"
roller_radius = "15 mm"
center_distance = "300 mm"
pivot_x = "150 mm"
pivot_y = "-30 mm"

[[motor]]
name = "m"
node = "motor"
kind = "prescribed"
speed = "60 rad/s"
"""


def test_a_drive_file_roller_that_loses_the_belt_is_refused_with_that_cause(tmp_path):
    path = tmp_path / "roller.toml"
    path.write_text(ROLLER_FILE, encoding="utf-8")
    one_error_line(CliRunner().invoke(cli, ["simulate", "drive", str(path)]), 1, "coupling 'belt'",
                   "the eccentricity 10 mm is not allowed", "the belt leaves it")


# --- (d) the exact method ---------------------------------------------------------------------------
def test_exact_on_an_eccentric_run_names_the_roller():
    line = one_error_line(CliRunner().invoke(cli, ["simulate", "sewing", "--set", "roller_eccentricity=2mm",
                                                   "--method", "exact"]), 1,
                          "--method:", "an eccentric tension roller makes the belt ratio vary", "--method radau")
    assert "loads locked" not in line


def test_the_budget_message_suggests_exact_only_where_it_runs():
    from beltcalc.errors import SimulationError
    from beltcalc.sim.core import SolverConfig, simulate
    from beltcalc.sim.network import Coupling

    geo = Eccentric(r1=0.02, r2=0.0275, a=0.30, r3=0.015, px=0.15, py=-0.030, delta=0.002)
    x0 = np.array([0.0, 0.0, 60.0, 60.0 / 1.375])
    nodes = [Inertia("m", 1e-4), Inertia("r", 2e-4)]
    cfg = SolverConfig(method="radau", max_rhs_calls=5, estimate_error=False)
    with pytest.raises(SimulationError) as eccentric:
        simulate(Network(nodes, [EccentricBelt("b", "m", "r", 300.0, 0.05, geo)]), 0.2, 201, cfg, x0=x0)
    assert "stopped at" in str(eccentric.value) and "exact" not in str(eccentric.value)
    with pytest.raises(SimulationError) as linear:
        simulate(Network(nodes, [Coupling("b", "m", "r", 300.0, 0.05, U=1.375)]), 0.2, 201, cfg, x0=x0)
    assert "try method exact" in str(linear.value)
