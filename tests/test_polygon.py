"""The polygon (chordal) action of a chain strand (issue 33): the strand's length against the
seating geometry found by brute force over every pair of rollers, closed forms of the chordal
action, the limit of many teeth (today's strand, at order 1 / z^2), and runs through the
command a user types against the same equations written out here and solved by scipy's Radau
(rtol 1e-11) stopped at every seating and slack switch."""

from __future__ import annotations

import csv
import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim.elements.polygon import PolygonStrand, span_phase

DATA = Path(__file__).parent / "data"
DRIVE = DATA / "chain_polygon.toml"
P10B = 0.015875          # 10B-1 pitch [m]


def cli(*args: str):
    """The command a user types, in process: (exit code, stdout, stderr)."""
    from click.testing import CliRunner

    from beltcalc.cli.main import cli as main

    res = CliRunner().invoke(main, list(args))
    return res.exit_code, res.stdout, res.stderr


# --- the geometry, written out: every roller of both sprockets ----------------------------------
class Polygons:
    """Two sprockets' pitch polygons as the docs define them, computed without the element:
    the open drive's layout, every roller's position, the common tangent found by brute force."""

    def __init__(self, p, z_i, z_j, L, psi_i, psi_j):
        self.p, self.z_i, self.z_j, self.psi_i, self.psi_j = p, z_i, z_j, psi_i, psi_j
        self.R_i, self.R_j = p / (2 * math.sin(math.pi / z_i)), p / (2 * math.sin(math.pi / z_j))
        self.D = math.hypot(L, self.R_i - self.R_j)
        self.beta0 = math.acos((self.R_i - self.R_j) / self.D)
        self.rest = 0.0
        self.rest = self.length(0.0, 0.0)

    def rollers(self, phi, z, R, psi, centre):
        """(index k, x, y) of every roller on the sprocket, once each: the turn centred on the
        top (k counts the rollers that have come round since rest, so the free links do too)."""
        k0 = round(-(phi + psi) * z / (2 * math.pi))
        k = np.arange(k0 - z // 2, k0 - z // 2 + z)
        a = self.beta0 + psi + phi + 2 * math.pi * k / z
        return k, centre + R * np.cos(a), R * np.sin(a)

    def tangent(self, phi_i, phi_j):
        """The pair of rollers whose line leaves every roller of both sprockets on one side
        (under it, away from its normal): brute force over all pairs; (k_i, k_j, length)."""
        ki, xi, yi = self.rollers(phi_i, self.z_i, self.R_i, self.psi_i, 0.0)
        kj, xj, yj = self.rollers(phi_j, self.z_j, self.R_j, self.psi_j, self.D)
        # candidates: the rollers near the top of each (a quarter turn either side)
        top_i = np.argsort(-(xi * math.cos(self.beta0) + yi * math.sin(self.beta0)))[:max(4, self.z_i // 4)]
        top_j = np.argsort(-((xj - self.D) * math.cos(self.beta0) + yj * math.sin(self.beta0)))[:max(4, self.z_j // 4)]
        X, Y = np.concatenate([xi, xj]), np.concatenate([yi, yj])
        best = None
        for a in top_i:
            for b in top_j:
                dx, dy = xj[b] - xi[a], yj[b] - yi[a]
                ell = math.hypot(dx, dy)
                nx, ny = -dy / ell, dx / ell
                over = (X - xi[a]) * nx + (Y - yi[a]) * ny
                worst = over.max()
                if best is None or worst < best[0]:
                    best = (worst, ki[a], kj[b], ell)
        assert best[0] <= 1e-12, "no supporting line"
        return best[1:]

    def length(self, phi_i, phi_j):
        """e = |V_j - V_i| + p (k_j - k_i) - e_0: the free links counted by the seated rollers."""
        ki, kj, ell = self.tangent(phi_i, phi_j)
        return ell + self.p * (kj - ki) - self.D - self.rest


@pytest.mark.parametrize("z_i, z_j, L", [(19, 15, 0.6), (19, 19, 0.5), (9, 40, 0.3), (60, 12, 1.2)])
def test_length_against_the_seating_found_by_brute_force(z_i, z_j, L):
    s = PolygonStrand("s", "a", "b", P10B, z_i, z_j, L, 1e6)
    ref = Polygons(P10B, z_i, z_j, L, s.phase_i, s.phase_j)
    rng = np.random.default_rng(z_i * 100 + z_j)
    angles = list(rng.uniform(-20, 20, size=(150, 2)))
    # seatings: the angles of i where a roller reaches the tangent, and a hair either side
    for k in range(-3, 4):
        tie = (k + 0.5) * 2 * math.pi / z_i - s.phase_i
        angles += [(tie + d, 0.0) for d in (-1e-9, 0.0, 1e-9)]
    for phi_i, phi_j in angles:
        want = ref.length(phi_i, phi_j)
        got = s.elongation_at(float(phi_i), float(phi_j))[0]
        assert got == pytest.approx(want, abs=1e-12)
    a = np.array(angles)
    vector = s.elongation(a[:, 0], a[:, 1])[0]
    scalar = [s.elongation_at(float(x), float(y))[0] for x, y in a]
    assert_allclose(vector, scalar, rtol=0, atol=1e-15)


def test_derivatives_against_central_differences():
    s = PolygonStrand("s", "a", "b", P10B, 19, 15, 0.6, 1e6)
    h = 1e-6
    for phi_i, phi_j in [(0.1, 0.2), (0.37, -0.5), (11.3, 12.1)]:
        e, e_i, e_j, e_ii, e_ij, e_jj = s.elongation_at(phi_i, phi_j)
        seats = s.seats_at(phi_i, phi_j)

        def part(k, a, b):
            return s.elongation_at(a, b, seats)[k]
        assert e_i == pytest.approx((part(0, phi_i + h, phi_j) - part(0, phi_i - h, phi_j)) / (2 * h), abs=1e-9)
        assert e_j == pytest.approx((part(0, phi_i, phi_j + h) - part(0, phi_i, phi_j - h)) / (2 * h), abs=1e-9)
        assert e_ii == pytest.approx((part(1, phi_i + h, phi_j) - part(1, phi_i - h, phi_j)) / (2 * h), abs=1e-8)
        assert e_ij == pytest.approx((part(1, phi_i, phi_j + h) - part(1, phi_i, phi_j - h)) / (2 * h), abs=1e-8)
        assert e_jj == pytest.approx((part(2, phi_i, phi_j + h) - part(2, phi_i, phi_j - h)) / (2 * h), abs=1e-8)


def test_closed_forms_of_the_chordal_action():
    """Equal sprockets in phase (a span of whole pitches) turning together: the strand moves
    parallel to itself, so its length never changes, and the chain leaves at the seated
    roller's speed omega R cos(theta), theta its angle from the strand's normal, between
    omega R cos(180 deg / z) and omega R [ISO 10823 sec. 5]. One tooth of either sprocket
    moves exactly one pitch of chain."""
    z = 19
    R = P10B / (2 * math.sin(math.pi / z))
    s = PolygonStrand("s", "a", "b", P10B, z, z, 40 * P10B, 1e6)
    assert s.phase_j == pytest.approx(0.0, abs=1e-12)
    phi = np.linspace(-3.0, 3.0, 2001)
    e, e_i, e_j, *_ = s.elongation(phi, phi)
    assert_allclose(e, 0.0, rtol=0, atol=1e-12)
    theta = (phi + math.pi / z) % (2 * math.pi / z) - math.pi / z
    assert_allclose(e_i, R * np.cos(theta), rtol=0, atol=1e-12)
    assert_allclose(-e_j, R * np.cos(theta), rtol=0, atol=1e-12)
    edge = math.pi / z                          # a seating: the slowest chain
    assert s.elongation_at(edge, edge)[1] == pytest.approx(R * math.cos(math.pi / z), abs=1e-12)
    assert e_i.max() == pytest.approx(R, abs=1e-9)
    # one tooth is one pitch, at any angle of either sprocket
    t = 2 * math.pi / z
    for a, b in [(0.1, -0.4), (1.234, 5.0), (-7.7, 0.02)]:
        assert s.elongation_at(a + t, b)[0] - s.elongation_at(a, b)[0] == pytest.approx(P10B, abs=1e-12)
        assert s.elongation_at(a, b + t)[0] - s.elongation_at(a, b)[0] == pytest.approx(-P10B, abs=1e-12)


def test_the_span_phase_of_a_fraction_of_a_pitch():
    assert span_phase(40 * P10B, P10B, 19) == pytest.approx(0.0, abs=1e-12)
    assert span_phase(40.25 * P10B, P10B, 20) == pytest.approx(2 * math.pi * 0.25 / 20, rel=1e-9)


def test_many_teeth_converge_to_todays_strand_at_order_two():
    """R held, z doubling: e -> R phi_i - R phi_j (the round sprocket), the difference falling
    4 times per doubling (order 2 in 1 / z: the mean radius R sinc(pi / z) and the pulse
    R (1 - cos(pi / z)) are both O(1 / z^2))."""
    R = 0.0482
    angles = [(0.3, 0.1), (1.3, -0.4), (7.0, 6.5)]
    errs = []
    for z in (40, 80, 160, 320, 640):
        s = PolygonStrand("s", "a", "b", 2 * R * math.sin(math.pi / z), z, z, 0.6, 1e6, phase_j=0.0)
        errs.append(max(abs(s.elongation_at(a, b)[0] - R * (a - b)) for a, b in angles))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert_allclose(orders, 2.0, atol=0.15)


def seated(g, pi, pj, seats):
    """A strand of :class:`Polygons` on the rollers ``seats`` = (k_i, k_j) at the angles ``pi``,
    ``pj``: (e, de/dphi_i, de/dphi_j, the line's normal, V_i, V_j, their polar angles), the
    seated rollers held (the smooth branch past a seating too)."""
    k_i, k_j = seats
    a_i = g.beta0 + g.psi_i + pi + 2 * math.pi * k_i / g.z_i
    a_j = g.beta0 + g.psi_j + pj + 2 * math.pi * k_j / g.z_j
    vi = (g.R_i * math.cos(a_i), g.R_i * math.sin(a_i))
    vj = (g.D + g.R_j * math.cos(a_j), g.R_j * math.sin(a_j))
    dx, dy = vj[0] - vi[0], vj[1] - vi[1]
    ell = math.hypot(dx, dy)
    ux, uy = dx / ell, dy / ell
    e = ell + g.p * (k_j - k_i) - g.D - g.rest
    return e, -(ux * -vi[1] + uy * vi[0]), ux * -vj[1] + uy * (vj[0] - g.D), (-uy, ux), vi, vj, a_i, a_j


# --- a run of the drive file against the equations written out --------------------------------
# tests/data/chain_polygon.toml: the driver prescribed, the driven sprocket free
J_DRIVEN, LOAD, F0, EA, BETA, L = 4e-3, 12.0, 160.0, 1.5e6, 2e-4, 0.5
Z_DRIVER, Z_DRIVEN = 19, 15


def driver_angle(t):
    """The prescribed driver: 150 rad/s^2 for 0.1 s, then 15 rad/s (floats)."""
    return (75.0 * t * t, 150.0 * t) if t < 0.1 else (0.75 + 15.0 * (t - 0.1), 15.0)


@functools.cache
def _reference(t: tuple):
    return solve_reference(np.array(t))


def solve_reference(t):
    """The driven sprocket's speed and both strands' forces on the samples ``t``: J phi'' =
    -F_t de_t/dphi - F_s de_s/dphi - load, each strand c (e + F0/c) + b e' while stretched
    and pulling, e by :class:`Polygons` (its rollers and their tangent, not the element's
    search), scipy Radau at rtol 1e-11 stopped at every seating (a roller of either sprocket
    reaches the strand's line) and every slack switch, the seated rollers and the slack state
    frozen between stops."""
    from scipy.integrate import solve_ivp

    c, b = EA / L, BETA * EA / L
    tight = Polygons(P10B, Z_DRIVER, Z_DRIVEN, L, 0.0, span_phase(L, P10B, Z_DRIVEN))
    slack = Polygons(P10B, Z_DRIVEN, Z_DRIVER, L, 0.0, span_phase(L, P10B, Z_DRIVER))

    def state(tt, y, seats, taut):
        phi_d, w_d = driver_angle(tt)
        phi, w = y
        out = []
        for g, (pi, wi), (pj, wj), sts, on in ((tight, (phi_d, w_d), (phi, w), seats[0], taut[0]),
                                               (slack, (phi, w), (phi_d, w_d), seats[1], taut[1])):
            e, e_i, e_j, *_ = seated(g, pi, pj, sts)
            stretch = c * e + F0
            force = stretch + b * (e_i * wi + e_j * wj)
            out.append((force * on, e_i, e_j, stretch, force))
        return out

    def rhs(tt, y, seats, taut):
        (ft, _, dt_j, *_), (fs, ds_i, *_) = state(tt, y, seats, taut)
        return [y[1], (-ft * dt_j - fs * ds_i - LOAD) / J_DRIVEN]

    def heights(g, phi_i, phi_j, sts):
        """How far each seated roller's neighbours lie under the strand's line (>= 0 while it holds)."""
        _, _, _, n, vi, vj, a_i, a_j = seated(g, phi_i, phi_j, sts)
        out = []
        for v, a, z, R, centre in ((vi, a_i, g.z_i, g.R_i, 0.0), (vj, a_j, g.z_j, g.R_j, g.D)):
            for step in (-1, 1):
                w = (centre + R * math.cos(a + 2 * math.pi * step / z), R * math.sin(a + 2 * math.pi * step / z))
                out.append(n[0] * (v[0] - w[0]) + n[1] * (v[1] - w[1]))
        return out

    def decide(tt, y):
        phi_d, w_d = driver_angle(tt)
        seats = tuple(tuple(int(k) for k in g.tangent(*pair)[:2])
                      for g, pair in ((tight, (phi_d, y[0])), (slack, (y[0], phi_d))))
        taut = tuple(bool(st > 0 and f > 0) for _, _, _, st, f in state(tt, y, seats, (1, 1)))
        return seats, taut

    def events(seats, taut, skip=(), start=0.0):
        """The stops of a piece; one that just fired without a change starts past its surface."""
        fns = []
        for which, g in ((0, tight), (1, slack)):
            for m in range(4):
                def seat(tt, y, *_, which=which, g=g, m=m, again=len(fns) in skip):
                    phi_d = driver_angle(tt)[0]
                    pi, pj = (phi_d, y[0]) if which == 0 else (y[0], phi_d)
                    v = heights(g, pi, pj, seats[which])[m]
                    return -max(abs(v), 1e-300) if again and tt == start else v
                seat.terminal, seat.direction = True, -1
                fns.append(seat)
            for m in (3, 4):
                def switch(tt, y, *_, which=which, m=m, again=len(fns) in skip, sign=(-1 if taut[which] else 1)):
                    v = state(tt, y, seats, taut)[which][m]
                    return sign * max(abs(v), 1e-300) if again and tt == start else v
                switch.terminal, switch.direction = True, (-1 if taut[which] else 1)
                fns.append(switch)
        return fns

    y, t0 = np.array([0.0, 0.0]), 0.0
    out = {"w": [], "Ft": [], "Fs": []}
    seats, taut = decide(0.0, y)
    done = 0
    stops = 0
    skip = ()
    flips = []          # the slack strand's switches
    start_taut = taut[1]
    while t0 < t[-1]:
        grid = t[(t > t0) & (t <= t[-1])]
        sol = solve_ivp(rhs, (t0, t[-1]), y, method="Radau", rtol=1e-11, atol=1e-13, t_eval=grid,
                        events=events(seats, taut, skip, t0), args=(seats, taut), dense_output=False)
        for tt, yy in zip(sol.t, np.reshape(sol.y, (2, -1)).T):
            f = state(tt, yy, seats, taut)
            out["w"].append(yy[1])
            out["Ft"].append(f[0][0])
            out["Fs"].append(f[1][0])
        done += len(sol.t)
        if sol.status != 1:
            break
        t_e, j = min((te[0], j) for j, te in enumerate(sol.t_events) if te.size)
        y = sol.y_events[j][0]
        ahead = y + 1e-9 * np.array(rhs(t_e, y, seats, taut))
        before = (seats, taut)
        seats, taut = decide(t_e + 1e-9, ahead)
        skip = (skip if t_e == t0 else ()) + ((j,) if (seats, taut) == before else ())
        if taut[1] != before[1][1]:
            flips.append(t_e)
        t0 = t_e
        stops += 1
        assert stops < 5000
    assert done == t.size - 1
    edges = [0.0] + flips + [float(t[-1])]
    slack_time = sum(b - a for k, (a, b) in enumerate(zip(edges, edges[1:])) if (k % 2 == 0) != start_taut)
    out = {k: np.concatenate([[v0], np.array(v)]) for (k, v), v0 in zip(out.items(), (0.0, F0, F0))}
    return out, stops, slack_time


@pytest.mark.slow
def test_a_chain_drive_with_the_polygon_action_against_radau_with_events(tmp_path):
    """``beltcalc simulate drive tests/data/chain_polygon.toml --json --csv``: the driven
    sprocket's speed and both strands' forces, against the equations written out and solved
    by Radau at rtol 1e-11 stopped at every seating and slack switch, within the run's own
    error estimate; the slack strand goes slack and taut again."""
    out = tmp_path / "run.csv"
    code, stdout, _ = cli("simulate", "drive", str(DRIVE), "--json", "--csv", str(out))
    assert code == 0
    report = json.loads(stdout)
    rows = list(csv.DictReader(out.open()))
    t = np.array([float(r["t_s"]) for r in rows])
    got = {k: np.array([float(r[k]) for r in rows]) for k in ("omega_driven_rad_per_s", "F_tight_N", "F_slack_N")}
    ref, stops, slack_time = _reference(tuple(t))
    assert stops > 30                          # seatings of both sprockets and slack switches
    est = report["error_estimate"]["value"]
    assert report["error_estimate"]["unit"] == "N"
    for key, want in (("F_tight_N", ref["Ft"]), ("F_slack_N", ref["Fs"])):
        assert_allclose(got[key], want, rtol=0, atol=est * 1.05 + 1e-9)
    # the speed, judged by its own share of the estimate: a force error over c r^2 / (J w)
    assert_allclose(got["omega_driven_rad_per_s"], ref["w"], rtol=0, atol=1e-6)
    assert slack_time > 0.1
    assert report["strands"]["slack"]["slack_time"]["value"] == pytest.approx(slack_time, abs=1e-9)
    assert report["strands"]["tight"]["slack_time"]["value"] == 0.0


# --- the roller table with the polygon action ----------------------------------------------------
ROLLER_SETS = ("polygon=on", "rollers=1", "ramp_time=0.15s", "load_start=0.2s", "t_end=0.35s", "window=0.25s",
               "samples=351")


def network_reference(net, t, rtol=1e-11):
    """A network whose chain strands carry the polygon action, solved with its strands written
    out here: the network's linear part (its matrices per input piece, verified elsewhere) less
    the springs the strands stamp on their mean radii p z / (2 pi), plus each strand's force
    c (e + F0 / c) + b e' while stretched and pulling on its seated rollers (:class:`Polygons`),
    -F de/dphi on its two sprockets. scipy Radau at ``rtol``, stopped at every input break, every
    seating (a neighbour of a seated roller reaches the strand's line) and every slack switch.
    Returns the states on ``t`` and each strand's force and slack time."""
    from scipy.integrate import solve_ivp

    n = net.n
    strands = []
    for s in net.tension_strands:
        g = Polygons(s.pitch, s.z_i, s.z_j, s.length, s.phase_i, s.phase_j)
        ri, rj = net.node_row(s.i), net.node_row(s.j)
        mean = s.pitch * s.z_i / (2 * math.pi) * ri - s.pitch * s.z_j / (2 * math.pi) * rj
        strands.append((s.name, g, ri, rj, mean, s.stiffness, s.damping, s.preload))
    free = np.ones(n)
    free[list(net.fixed)] = 0.0
    gain = free / net.mass

    def ends(x, ri, rj):
        return float(ri @ x[:n]), float(rj @ x[:n]), float(ri @ x[n:2 * n]), float(rj @ x[n:2 * n])

    def forces(x, mode):
        out = []
        for (name, g, ri, rj, mean, c, b, f0), (seats, on) in zip(strands, mode):
            pi, pj, wi, wj = ends(x, ri, rj)
            e, e_i, e_j, *_ = seated(g, pi, pj, seats)
            stretch = c * e + f0
            force = stretch + b * (e_i * wi + e_j * wj)
            out.append((force if on else 0.0, e_i, e_j, stretch, force))
        return out

    def rhs(tt, x, A, B, mode):
        dx = A @ x + B @ net.generators(tt)
        acc = np.zeros(n)
        for (name, g, ri, rj, mean, c, b, f0), (f, e_i, e_j, _, _) in zip(strands, forces(x, mode)):
            acc += c * (mean @ x[:n]) * mean + b * (mean @ x[n:2 * n]) * mean     # the stamped spring back
            acc -= f * (e_i * ri + e_j * rj)
        dx[n:2 * n] += gain * acc
        return dx

    def decide(x):
        mode = []
        for name, g, ri, rj, mean, c, b, f0 in strands:
            pi, pj, wi, wj = ends(x, ri, rj)
            seats = tuple(int(k) for k in g.tangent(pi, pj)[:2])
            e, e_i, e_j, *_ = seated(g, pi, pj, seats)
            stretch = c * e + f0
            mode.append((seats, bool(stretch > 0 and stretch + b * (e_i * wi + e_j * wj) > 0)))
        return tuple(mode)

    def events(mode, skip, start):
        fns = []
        for k, ((name, g, ri, rj, *_), (seats, on)) in enumerate(zip(strands, mode)):
            for m in range(4):
                def seat(tt, x, *_, g=g, ri=ri, rj=rj, seats=seats, m=m, again=len(fns) in skip):
                    pi, pj, _, _ = ends(x, ri, rj)
                    e, _, _, nrm, vi, vj, a_i, a_j = seated(g, pi, pj, seats)
                    v, a, z, R, c0 = ((vi, a_i, g.z_i, g.R_i, 0.0), (vj, a_j, g.z_j, g.R_j, g.D))[m // 2]
                    step = 2 * math.pi * (1 if m % 2 else -1) / z
                    h = nrm[0] * (v[0] - c0 - R * math.cos(a + step)) + nrm[1] * (v[1] - R * math.sin(a + step))
                    return -max(abs(h), 1e-300) if again and tt == start else h
                seat.terminal, seat.direction = True, -1
                fns.append(seat)
            for m in (3, 4):
                def switch(tt, x, *_, k=k, m=m, again=len(fns) in skip, sign=-1 if on else 1):
                    v = forces(x, mode)[k][m]
                    return sign * max(abs(v), 1e-300) if again and tt == start else v
                switch.terminal, switch.direction = True, -1 if on else 1
                fns.append(switch)
        return fns

    starts = net.segment_starts(t[-1]) + [math.inf]
    x, t0 = net.initial_state(), 0.0
    mode = decide(x)
    slack = {name: (0.0, None if on else 0.0) for (name, *_), (_, on) in zip(strands, mode)}
    states = [x]
    skip, stops = (), 0
    while t0 < t[-1]:
        seg = int(np.searchsorted(starts, t0, side="right")) - 1
        t1 = min(starts[seg + 1], t[-1])
        A, B = net.first_order(None, 0.5 * (starts[seg] + t1))
        grid = t[(t > t0) & (t <= t1)]
        sol = solve_ivp(rhs, (t0, t1), x, method="Radau", rtol=rtol, atol=rtol * 1e-2, t_eval=grid,
                        events=events(mode, skip, t0), args=(A, B, mode))
        assert sol.status >= 0, sol.message
        states += list(np.reshape(sol.y, (x.size, -1)).T)
        if sol.status == 1:
            t_e, j = min((te[0], j) for j, te in enumerate(sol.t_events) if te.size)
            x = sol.y_events[j][0]
            new = decide(x + 1e-9 * rhs(t_e, x, A, B, mode))
            for (name, *_), (_, was), (_, now) in zip(strands, mode, new):
                spent, since = slack[name]
                if was and not now:
                    slack[name] = (spent, t_e)
                elif now and not was:
                    slack[name] = (spent + t_e - since, None)
            skip = (skip if t_e == t0 else ()) + ((j,) if new == mode else ())
            mode, t0 = new, t_e
            stops += 1
            assert stops < 20000
        else:
            x, t0, skip = sol.y[:, -1], t1, ()
    X = np.array(states).T
    assert X.shape[1] == t.size
    F = {name: np.array([forces(X[:, k], decide(X[:, k]))[m][0] for k in range(t.size)])
         for m, (name, *_) in enumerate(strands)}
    times = {name: spent + (t[-1] - since if since is not None else 0.0) for name, (spent, since) in slack.items()}
    return X, F, times, stops


@pytest.mark.slow
def test_the_roller_table_with_the_polygon_action_against_radau_with_events(tmp_path):
    """``beltcalc simulate roller-table --set polygon=on`` (one roller, a short start and load):
    the roller's speed and the strands' forces against :func:`network_reference` at rtol 1e-11,
    within the run's own estimate; the return strand goes slack."""
    from beltcalc.sim.drivefile import DriveFile
    from beltcalc.sim.scenes.roller_table import SCENE, drive_data

    out = tmp_path / "run.csv"
    args = [a for kv in ROLLER_SETS for a in ("--set", kv)]
    code, stdout, stderr = cli("simulate", "roller-table", *args, "--json", "--csv", str(out))
    assert code == 0, stderr
    report = json.loads(stdout)
    rows = list(csv.DictReader(out.open()))
    t = np.array([float(r["t_s"]) for r in rows])
    values = SCENE.values(polygon="on", rollers=1.0, ramp_time=0.15, load_start=0.2, t_end=0.35, window=0.25,
                          samples=351.0)
    net = DriveFile.from_data(drive_data(values), "roller table").network()
    X, F, slack, stops = network_reference(net, t)
    assert stops > 20
    n = net.n
    est = report["error_estimate"]
    rel = report["error_relative"]["value"]             # the run's estimate, relative to its signal's scale
    assert rel <= 1e-6
    for name, f in F.items():
        got = np.array([float(r[f"F_{name}_N"]) for r in rows])
        assert_allclose(got, f, rtol=0, atol=rel * np.abs(f).max())
    speed = np.array([float(r["omega_end1a_rad_per_s"]) for r in rows])
    assert_allclose(speed, net.node_row("end1a") @ X[n:2 * n], rtol=0, atol=1e-7)
    assert slack["sprocket1-drive"] > 0.01
    for name, spent in slack.items():
        assert report["strands"][name]["slack_time"]["value"] == pytest.approx(spent, abs=1e-9)
    assert est["value"] > 0


def test_runs_with_many_teeth_converge_to_todays_strand():
    """A driver at 10 rad/s pulling a loaded sprocket through two pretensioned strands, R held:
    with z = 100 ... 800 teeth the run converges to today's round-sprocket run (the exact
    solution), its mean strand force at order 2 in 1 / z (the mean radius R sinc(pi / z)) and
    its largest force difference at least at order 1.5 (the pulse R (1 - cos(pi / z)) at the
    rising tooth frequency)."""
    from beltcalc.sim.core import SolverConfig, simulate
    from beltcalc.sim.elements import Inertia, Load, Prescribed, Strand
    from beltcalc.sim.network import Network

    R, c, F0 = 0.05, 3e6, 300.0
    b = 2e-4 * c

    def net(z):
        els = [Prescribed("driver", 10.0), Load("driven", 5.0)]
        if z is None:
            els += [Strand("tight", "driver", "driven", R, R, c, b, F0), Strand("slack", "driven", "driver", R, R, c, b, F0)]
        else:
            p = 2 * R * math.sin(math.pi / z)
            els += [PolygonStrand("tight", "driver", "driven", p, z, z, 0.5, c, b, F0, 0.0, 0.0),
                    PolygonStrand("slack", "driven", "driver", p, z, z, 0.5, c, b, F0, 0.0, 0.0)]
        return Network([Inertia("driver", 2e-3), Inertia("driven", 4e-3)], els)

    today = simulate(net(None), 0.05, 501, SolverConfig())
    assert today.method == "exact"
    teeth = np.array([100, 200, 400, 800])
    peak, mean = [], []
    for z in teeth:
        r = simulate(net(int(z)), 0.05, 501, SolverConfig(estimate_error=False))
        peak.append(np.abs(r["F_tight"] - today["F_tight"]).max())
        mean.append(abs(r.summary("F_tight", 0.02).mean - today.summary("F_tight", 0.02).mean))
    order_mean = -np.polyfit(np.log(teeth), np.log(mean), 1)[0]
    order_peak = -np.polyfit(np.log(teeth), np.log(peak), 1)[0]
    assert order_mean == pytest.approx(2.0, abs=0.2)
    assert order_peak == pytest.approx(2.0, abs=0.5)


# --- docs/chain_dynamics.md: its roller table is the stored benchmark -----------------------------
ROOT = Path(__file__).resolve().parents[1]
STORED = ROOT / "benchmarks" / "results" / "chain_dynamics.md"
HEADER = "| supply | polygon |"


def table_rows(text: str) -> list[str]:
    """The body rows of the roller table (:func:`test_readme_figures.markdown_rows`)."""
    from test_readme_figures import markdown_rows

    return markdown_rows(text, HEADER)


def test_the_docs_roller_table_is_the_stored_one():
    page = (ROOT / "docs" / "chain_dynamics.md").read_text(encoding="utf-8")
    stored = table_rows(STORED.read_text(encoding="utf-8"))
    assert len(stored) == 6 and table_rows(page) == stored
    cells = {(r.split("|")[1].strip().split()[0], r.split("|")[2].strip()): [c.strip() for c in r.strip("|").split("|")]
             for r in stored}
    on, off = cells[("50", "on")], cells[("50", "off")]
    # the figures the page's text quotes for the default speed, from the stored rows
    mode = cells[("58.462", "on")]
    for quote, figure, cell in [("(half peak-to-peak, roller 1): 0.146 rad/s", 0.146, on[6]),
                                ("against 0.0002 rad/s with round sprockets", 0.0002, off[6]),
                                ("of the tight strand: 4358 N", 4358, on[7]), ("against 4196 N", 4196, off[7]),
                                ("doubles: 0.310 rad/s", 0.310, mode[6]),
                                ("(4029 N here against 4142 N", 4029, mode[7])]:
        assert " ".join(quote.split()) in " ".join(page.split())
        digits = len(str(figure).split(".")[1]) if "." in str(figure) else 0
        assert float(cell) == pytest.approx(figure, abs=0.51 * 10 ** -digits)


@pytest.mark.parametrize("supply", ["50", "40"])
def test_the_stored_round_sprocket_rows_come_out_of_the_code(supply):
    """The rows without the polygon action (exact, half a second each) re-run: mean speed,
    ripple, peak force, slack time, tooth frequency and nearest mode as stored."""
    stored = {r.split("|")[1].strip().split()[0]: [c.strip() for c in r.strip("|").split("|")]
              for r in table_rows(STORED.read_text(encoding="utf-8")) if r.split("|")[2].strip() == "off"}
    row = stored[supply]
    code, stdout, _ = cli("simulate", "roller-table", "--json", "--set", f"supply_frequency={supply}Hz")
    assert code == 0
    r = json.loads(stdout)
    got = [r["rollers"]["1"]["speed_mean"]["value"], r["rollers"]["1"]["speed_amplitude"]["value"],
           r["strands"]["drive-sprocket1"]["force_max"]["value"], r["strands"]["sprocket3-drive"]["slack_time"]["value"],
           r["chain"]["tooth_frequency"]["value"], r["chain"]["nearest_mode"]["value"]]
    for value, cell in zip(got, row[5:11]):
        digits = len(cell.split(".")[1]) if "." in cell else 0
        assert value == pytest.approx(float(cell), abs=0.51 * 10 ** -digits + 1e-3 * abs(float(cell)))


@pytest.mark.parametrize("change, message", [
    ({"driver": ("teeth = 19\nchain = \"10B-1\"", "pitch_diameter = \"96 mm\"")},
     "the polygon action needs the sprocket's teeth: give node 'driver' teeth and chain"),
    ({"driver": ("chain = \"10B-1\"", "chain = \"08B-1\"")},
     "not that of 19 teeth on 10B-1"),
    ({"polygon": ("\npolygon = true", "\npolygon = false\nphase_to = \"10 deg\"")},
     "phase_to: a phase needs polygon = true"),
])
def test_bad_polygon_strands_are_one_line_errors(tmp_path, change, message):
    text = DRIVE.read_text(encoding="utf-8")
    for old, new in change.values():
        text = text.replace(old, new, 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text, encoding="utf-8")
    code, stdout, stderr = cli("simulate", "drive", str(bad))
    assert code == 1
    assert message in stderr and "Traceback" not in stderr and len(stderr.strip().splitlines()) == 1
    assert stdout == ""


# --- the polygon excitation in the frequency domain ------------------------------------------------
def test_the_pulse_harmonics_against_a_least_squares_fit():
    """The length pulse's and lever arms' harmonics (an FFT of one tooth period) against a least-
    squares fit of 150 harmonics to the pulse sampled elsewhere (random times over three periods):
    equal to 1e-7 of the pulse for the first five (the pulse is C^1 with a kink in its rate at each
    seating: its harmonics fall as 1 / k^3, so the fit's truncation leaves about 150^-3), to 2e-5 of
    the lever arms' swing (continuous with a kink: 1 / k^2)."""
    from beltcalc.sim.polygon_response import harmonics_of

    s = PolygonStrand("s", "a", "b", P10B, 19, 15, 0.6, 2.5e6)
    speed = 6.0
    omega, E, Li, Lj = harmonics_of(s, speed, 5)
    assert omega == pytest.approx(19 * speed)
    r_i, r_j = s.mean_radii
    t = np.random.default_rng(7).uniform(0, 3 * 2 * math.pi / omega, 4000)
    e, e_i, e_j, *_ = s.elongation(speed * t, speed * r_i / r_j * t)
    k = np.arange(1, 151)
    basis = np.hstack([np.ones((t.size, 1)), np.cos(np.outer(t, k * omega)), np.sin(np.outer(t, k * omega))])
    # the lever arms are continuous with a kink at each seating: their harmonics fall as 1 / k^2
    for signal, want, tol in ((e - (r_i * speed * t - r_j * speed * r_i / r_j * t), E, 1e-7), (e_i - r_i, Li, 2e-5),
                              (e_j + r_j, Lj, 2e-5)):
        c = np.linalg.lstsq(basis, signal, rcond=None)[0]
        fitted = c[1:6] - 1j * c[151:156]                # a cos + b sin = Re((a - j b) e^{jwt})
        assert_allclose(fitted, want, rtol=0, atol=tol * np.abs(signal).max())


@pytest.mark.slow
def test_the_polygon_response_against_a_time_run_to_steady_state():
    """``response --polygon``'s harmonics of a driven sprocket's speed and of the strand force,
    against the linear drive integrated in time (scipy Radau, rtol 1e-10) under the same
    harmonics of the forcing -(c e_p + b e_p') g - F (e_,i - r_i) g_i - F (e_,j + r_j) g_j
    (:func:`~beltcalc.sim.polygon_response.harmonics_of`, checked above), its last five tooth
    periods Fourier-analysed: the frequency-domain solve against the time domain."""
    from types import SimpleNamespace

    from scipy.integrate import solve_ivp

    from beltcalc.sim.elements import Coupling, Inertia, Load, Strand
    from beltcalc.sim.network import Network
    from beltcalc.sim.polygon_response import harmonics_of, polygon_response

    R19, R15 = P10B / (2 * math.sin(math.pi / 19)), P10B / (2 * math.sin(math.pi / 15))
    c, b, F0, Fm = 3e6, 600.0, 400.0, 1200.0
    net = Network([Inertia("driver", 2e-3), Inertia("driven", 4e-3)],
                  [Coupling("bearing", "driven", None, 0.0, 0.5), Coupling("motor", "driver", None, 0.0, 0.5),
                   Strand("tight", "driver", "driven", R19, R15, c, b, F0),
                   Strand("slack", "driven", "driver", R15, R19, c, b, F0), Load("driven", 0.0)])
    drive = SimpleNamespace(network=net, teeth={"driver": 19, "driven": 15}, lengths={"tight": 0.5, "slack": 0.5})
    speed, H = 9.0, 3
    r = polygon_response(drive, "tight", speed, H, ["omega_driven", "F_tight"], mean_force=Fm)
    s = PolygonStrand("tight", "driver", "driven", 2 * R19 * math.sin(math.pi / 19), 19, 15, 0.5, c, b, F0)
    Omega, E, Li, Lj = harmonics_of(s, speed, H)
    r_i, r_j = s.mean_radii
    A, _ = net.first_order(None, 0.0)
    n = net.n
    g_i, g_j = net.node_row("driver"), net.node_row("driven")
    g = r_i * g_i - r_j * g_j
    U = [(-(c + 1j * k * Omega * b) * E[k - 1] * g - Fm * (Li[k - 1] * g_i + Lj[k - 1] * g_j)) / net.mass
         for k in range(1, H + 1)]

    def rhs(t, x):
        dx = A @ x
        dx[n:2 * n] += sum((u * np.exp(1j * k * Omega * t)).real for k, u in enumerate(U, 1))
        return dx

    period = 2 * math.pi / Omega
    periods = 20                                     # the bearings' pole (1/e in 8 ms) gone 90 times over
    t_eval = np.linspace((periods - 5) * period, periods * period, 5 * 64 + 1)
    sol = solve_ivp(rhs, (0.0, periods * period), np.zeros(net.size), method="Radau", rtol=1e-10, atol=1e-14,
                    t_eval=t_eval, jac=lambda t, x: A)
    x = sol.y[:, :-1]
    outputs = {"omega_driven": g_j @ x[n:2 * n],
               "F_tight": c * (g @ x[:n]) + b * (g @ x[n:2 * n])}      # the strand's own motion ...
    for name, y in outputs.items():
        spec = 2 * np.fft.rfft(y) / y.size
        for k in range(1, H + 1):
            got = spec[5 * k]
            if name == "F_tight":
                got = got + (c + 1j * k * Omega * b) * E[k - 1]      # ... plus the pulse's own stretch
            assert abs(got - r.outputs[name][k - 1]) <= 1e-6 * abs(r.outputs[name][0]), (name, k)


def test_campbell_draws_the_tooth_orders_by_default():
    """``beltcalc campbell roller_table``: the 19-tooth sprockets' order 19 / 25 of the motor
    (two gear stages of 5) and the 15-tooth idlers' (their speed ratio on the pitch radii), each
    named, and the crossings of the sprockets' order where 2 pi f_mode / k says."""
    code, stdout, _ = cli("campbell", "roller_table", "--json")
    assert code == 0
    d = json.loads(stdout)
    sources = {round(o["order"], 6): o["source"] for o in d["order_sources"]}
    assert sources[0.76] == "teeth: drive, sprocket1, sprocket2, sprocket3 (19)"
    idler = 15 * math.sin(math.pi / 15) / math.sin(math.pi / 19) / 25
    assert sources[round(idler, 6)] == "teeth: idler1, idler2 (15)"
    modes = {m["mode"]: m["frequency"]["value"] for m in d["modes"]}
    tooth = [x for x in d["crossings"] if x["order"] == pytest.approx(0.76, rel=1e-9)]
    assert tooth
    for x in tooth:
        assert x["speed"]["value"] == pytest.approx(2 * math.pi * modes[x["mode"]] / 0.76, rel=1e-9)
    code, stdout, _ = cli("campbell", "roller_table", "--orders", "1", "--json")
    assert json.loads(stdout)["orders"] == [1.0]


def test_response_polygon_through_the_command(tmp_path):
    """``beltcalc response roller_table --polygon drive-sprocket1 --speed 6.1rad/s --json --csv``:
    the tooth frequency 19 x 6.1 / 2 pi, one row per harmonic, the bound the sum of the
    harmonics; bad options are one-line errors."""
    out = tmp_path / "h.csv"
    code, stdout, _ = cli("response", "roller_table", "--polygon", "drive-sprocket1", "--speed", "6.1rad/s",
                          "--harmonics", "4", "--json", "--csv", str(out))
    assert code == 0
    p = json.loads(stdout)["polygon"]
    assert p["tooth_frequency"]["value"] == pytest.approx(19 * 6.1 / (2 * math.pi), rel=1e-12)
    assert [h["harmonic"] for h in p["harmonics"]] == [1, 2, 3, 4]
    amp = [h["outputs"]["F_drive-sprocket1"]["amplitude"]["value"] for h in p["harmonics"]]
    assert p["bound"]["F_drive-sprocket1"]["value"] == pytest.approx(sum(amp), rel=1e-12)
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 4 and float(rows[0]["pulse_m"]) == pytest.approx(p["harmonics"][0]["pulse"]["value"])
    for args, exit_code, text in [(["--polygon", "nope", "--speed", "1rad/s"], 2, "'nope' is not a strand"),
                                  (["--polygon", "drive-sprocket1"], 2, "--polygon and --speed go together"),
                                  (["--polygon", "drive-sprocket1", "--speed", "0rad/s"], 1, "--speed"),
                                  (["--polygon", "drive-sprocket1", "--speed", "1rad/s", "--harmonics", "51"], 2,
                                   "--harmonics")]:
        code, stdout, stderr = cli("response", "roller_table", *args)
        assert code == exit_code and text in stderr and "Traceback" not in stderr, (args, stderr)
