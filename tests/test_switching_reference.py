"""The tension-only strand core ("exact", no error estimate) against references that owe
nothing to beltcalc's integrators: closed forms solved by brentq, scipy's expm, and scipy's
solve_ivp with terminal events written here (never beltcalc's radau path).

Strand rules (beltcalc/sim/network.py, docs/switching.md): elongation
delta = r_i phi_i - r_j phi_j + F0/c; taut force F = c delta + b delta'; taut while delta > 0
and F > 0. Taut -> slack when F falls through 0; slack -> taut when delta rises through 0
(take-up, F jumps to b delta') or when the virtual force c delta + b delta' rises through 0
while delta > 0. A Load(mean=M) is a generalised force -M on its node.

Switch times come from r.extra["switches"]: (t, strand name, taut after) per mode change.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.optimize import brentq

from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.network import Inertia, Load, Network, Strand
from beltcalc.sim.scenes import roller_table

EXACT = SolverConfig("exact", estimate_error=False)
BOUNDED = SolverConfig("exact", estimate_error=False, max_events=1000)   # the bounce needs 25 (+ ~12 not switching)


def params(**over):
    """The default roller-table scene's parameters (SI), with ``over`` replacing some."""
    from beltcalc.sim.scenes import SCENES

    return SCENES["roller-table"].values(**over)


def switch_times(r):
    return np.array([t for t, _, _ in r.extra["switches"]], dtype=float)


# --- 1. bouncing contact into resting contact ----------------------------------------------------
# A mass m on a strand to the frame (r_i = 1, F0 = 0, so delta = x), pushed towards take-up by
# f (Load mean -f), from x = -d0 at rest. Flight (slack): x'' = a = f/m, parabolas. Contact
# (taut), from a take-up at x = 0 with speed v > 0:  m x'' + b x' + c x = f, closed form
#   x = x_s + e^{-s t}(P cos w_d t + Q sin w_d t),  x_s = f/c,  P = -x_s,  Q = (v + s P)/w_d,
# with s = zeta w_n, w_d = w_n sqrt(1 - zeta^2). The force F = f + e^{-s t} R cos(w_d t - psi)
# is monotone between consecutive zeros of F' (spaced pi/w_d), so the release (first F = 0) is
# bracketed by them and found by brentq to 1e-16 s; if the first minimum of F stays > 0 the
# mass is captured (resting contact: F -> f, x -> f/c). After a release at x_r > 0, v_r < 0
# the virtual force c x + b x' re-zeros at s* = -2 v_r/a - 2 b/c where x(s*) = (b/c)(v_r + 2ab/c)
# < 0 whenever |v_r| > 2ab/c (checked), so the next switch is the take-up x = 0 rising: the
# larger root of x_r + v_r s + a s^2/2 (no cancellation, -v_r > 0).
M1, C1, ZETA1, FORCE1, D0 = 1.0, 1e6, 0.1, 10.0, 0.05
B1 = 2 * ZETA1 * math.sqrt(C1 * M1)


def contact(m, c, b, f, v):
    """Release of a contact that starts at x = 0 with speed v: (duration, x, v at release),
    or None when the force never returns to zero (capture)."""
    wn = math.sqrt(c / m)
    zeta = b / (2 * math.sqrt(c * m))
    s, wd = zeta * wn, wn * math.sqrt(1 - zeta * zeta)
    xs = f / c
    P = -xs
    Q = (v + s * P) / wd

    def state(t):
        e, co, si = math.exp(-s * t), math.cos(wd * t), math.sin(wd * t)
        return xs + e * (P * co + Q * si), e * ((-s * P + wd * Q) * co + (-s * Q - wd * P) * si)

    def force(t):
        x, xd = state(t)
        return c * x + b * xd

    # F - f = e^{-s t}(U cos + V sin); F' = e^{-s t}((-s U + wd V) cos + (-s V - wd U) sin)
    U, V = c * P + b * (-s * P + wd * Q), c * Q + b * (-s * Q - wd * P)
    psi = math.atan2(-s * V - wd * U, -s * U + wd * V)   # F' ~ cos(wd t - psi)
    k = math.ceil((-psi - math.pi / 2) / math.pi)
    ext = [t for t in ((math.pi / 2 + j * math.pi + psi) / wd for j in range(k, k + 4)) if t > 0][:2]
    lo = 0.0
    for t_ext in ext:                 # F(0) = b v > 0; a maximum then a minimum, or a minimum first
        if force(t_ext) < 0:
            t = brentq(force, lo, t_ext, xtol=1e-16, rtol=1e-15, maxiter=500)
            return t, *state(t)
        lo = t_ext
    return None


def bounce_sequence(m=M1, c=C1, b=B1, f=FORCE1, d0=D0):
    """Every switch (t, taut after) of the bouncing mass, the contact durations and flights."""
    a = f / m
    t = math.sqrt(2 * d0 / a)          # first flight from rest
    v = a * t
    switches, contacts, flights, impacts = [(t, True)], [], [t], [v]
    while True:
        rel = contact(m, c, b, f, v)
        if rel is None:
            return {"switches": switches, "contacts": contacts, "flights": flights, "impacts": impacts}
        dt, xr, vr = rel
        assert xr > 0 and -vr > 2 * a * b / c      # releases stretched; take-up at x = 0 (see above)
        t += dt
        switches.append((t, False))
        contacts.append(dt)
        fl = (-vr + math.sqrt(vr * vr - 2 * a * xr)) / a
        t += fl
        v = vr + a * fl
        switches.append((t, True))
        flights.append(fl)
        impacts.append(v)


def bouncing_net():
    net = Network([Inertia("m", M1, translation=True)],
                  [Load("m", mean=-FORCE1), Strand("s", "m", None, 1.0, 1.0, C1, B1, 0.0)])
    return net, np.array([-D0, 0.0])


def test_bounce_reference_agrees_with_solve_ivp():
    # the closed-form sequence checked against scipy (DOP853, rtol 1e-13) with events written
    # here: 25 switches (12 bounces, then capture), agreeing to 4e-14 s when written
    seq = bounce_sequence()
    t, y, taut, got = 0.0, np.array([-D0, 0.0]), False, []
    while True:
        if taut:
            def rhs(s, y):
                return [y[1], (FORCE1 - C1 * y[0] - B1 * y[1]) / M1]

            def release(s, y):
                return C1 * y[0] + B1 * y[1]
            release.terminal, release.direction = True, -1
            events = [release]
        else:
            def rhs(s, y):
                return [y[1], FORCE1 / M1]

            def take_up(s, y):
                return y[0]

            def virtual(s, y):               # virtual force, counted only while stretched
                return C1 * y[0] + B1 * y[1] if y[0] > 0 else -1.0
            take_up.terminal = virtual.terminal = True
            take_up.direction = virtual.direction = 1
            events = [take_up, virtual]
        sol = solve_ivp(rhs, (t, 1.0), y, method="DOP853", rtol=1e-13, atol=1e-18, events=events,
                        first_step=1e-7)
        if sol.status != 1:
            break
        t, j = min((te[0], j) for j, te in enumerate(sol.t_events) if te.size)
        y, taut = sol.y_events[j][0], not taut
        got.append((t, taut))
    assert [on for _, on in got] == [on for _, on in seq["switches"]]
    assert_allclose([t for t, _ in got], [t for t, _ in seq["switches"]], rtol=0, atol=1e-11)
    assert 8 <= len(seq["contacts"]) <= 15


@pytest.mark.parametrize("samples", [2001, 3])
def test_bouncing_mass_switches_and_capture(samples):
    # every switch of the closed-form sequence to 1e-9 s, whatever the output grid (samples=3:
    # the whole run is two 0.5 s output steps)
    seq = bounce_sequence()
    net, x0 = bouncing_net()
    r = simulate(net, 1.0, samples, BOUNDED, x0=x0)
    want = np.array([t for t, _ in seq["switches"]])
    assert r.extra["events"] == len(want) == 25
    assert [on for _, _, on in r.extra["switches"]] == [on for _, on in seq["switches"]]
    assert {name for _, name, _ in r.extra["switches"]} == {"s"}
    assert_allclose(switch_times(r), want, rtol=0, atol=1e-9)
    # resting contact: capture at ~0.68 s, then the contact decays at zeta w_n = 100 1/s, so by
    # 1 s the mass sits at f/c within e^-32 of the capture amplitude (~1e-5 m)
    assert r["x_m"][-1] == pytest.approx(FORCE1 / C1, rel=1e-9)
    assert r["v_m"][-1] == pytest.approx(0.0, abs=1e-12)
    assert r["F_s"][-1] == pytest.approx(FORCE1, rel=1e-9)
    assert r.extra["slack_time"]["s"] == pytest.approx(sum(seq["flights"]), abs=1e-8)
    # rigid-limit Zeno: with the restitution e0 of the contact without f (its release speed /
    # impact speed, independent of the speed: a homogeneous linear contact) flights would be
    # 2 v1 e0^k / a and accumulate at t_inf = t1 + 2 v1 e0 / (a (1 - e0)). The real capture
    # (last take-up) differs from it by the contact durations it leaves out (+) and by the
    # flights the finite force f shortens near capture and the bounces after capture that
    # never happen (-); the two nearly cancel: measured t_cap - t_inf = -2.7 ms against
    # summed contacts 38.6 ms. Asserted: |t_cap - t_inf| <= the summed simulated contacts.
    a = FORCE1 / M1
    e0 = -contact(M1, C1, B1, 0.0, 1.0)[2]
    times = switch_times(r)
    t1, v1 = times[0], a * times[0]
    t_inf = t1 + 2 * v1 * e0 / (a * (1 - e0))
    t_cap = times[-1]
    contacts = times[1::2] - times[0:-1:2]
    assert abs(t_cap - t_inf) <= contacts.sum()


# --- 2. grazing at zero force ----------------------------------------------------------------
# Mass m on a strand to the frame, pretension F0, load M + A sin(w t) (generalised force
# -(M + A sin w t)). Taut: m x'' + b x' + c x = -F0 - M - A sin(w t). Periodic solution
# x = X0 + P sin(w t) + Q cos(w t) with X0 = -(F0 + M)/c and
#   (c - m w^2) P - b w Q = -A,   b w P + (c - m w^2) Q = 0,
# and F = c x + b x' + F0 = -M + Fs sin(w t) + Fc cos(w t), Fs = c P - b w Q, Fc = c Q + b w P:
# the pretension drops out, min F = -M - |F~|. M = -|F~| (1 - eps) puts the minimum at
# -eps |F~|: eps = 0 grazes F = 0 exactly once a period. delta = (F - b delta')/c has mean
# -M/c and amplitude -M/|c + i b w| < -M/c, so delta > 0 throughout. Start on the periodic
# solution: x(0) = X0 + Q, v(0) = w P (no transient).
M2, C2, ZETA2, W2, A2, F02 = 1.0, 1e5, 0.05, 100.0, 100.0, 50.0
B2 = 2 * ZETA2 * math.sqrt(C2 * M2)
PERIODS = 100


def periodic(eps):
    k = C2 - M2 * W2 ** 2
    P, Q = np.linalg.solve([[k, -B2 * W2], [B2 * W2, k]], [-A2, 0.0])
    Fs, Fc = C2 * P - B2 * W2 * Q, C2 * Q + B2 * W2 * P
    M = -math.hypot(Fs, Fc) * (1 - eps)
    return M, -(F02 + M) / C2, P, Q, Fs, Fc


def grazing_net(M):
    return Network([Inertia("m", M2, translation=True)],
                   [Load("m", mean=M, amplitude=A2, omega=W2), Strand("s", "m", None, 1.0, 1.0, C2, B2, F02)])


def test_force_grazing_zero_makes_no_switch():
    M, X0, P, Q, Fs, Fc = periodic(0.0)
    t_end = PERIODS * 2 * math.pi / W2
    r = simulate(grazing_net(M), t_end, PERIODS * 50 + 1, EXACT, x0=np.array([X0 + Q, W2 * P]))
    assert r.extra["events"] == 0
    assert r.extra["slack_time"]["s"] == 0.0
    t = r.t
    x = X0 + P * np.sin(W2 * t) + Q * np.cos(W2 * t)
    F = -M + Fs * np.sin(W2 * t) + Fc * np.cos(W2 * t)
    assert_allclose(r["x_m"], x, rtol=0, atol=1e-9 * np.max(np.abs(x)))
    assert_allclose(r["v_m"], W2 * (P * np.cos(W2 * t) - Q * np.sin(W2 * t)), rtol=0,
                    atol=1e-9 * W2 * math.hypot(P, Q))
    assert_allclose(r["F_s"], F, rtol=0, atol=1e-9 * -M)


def grazing_reference(M, x0, t_end):
    """Own hybrid solve: DOP853 at rtol 1e-12, terminal events with their direction, restarted
    at each event. Taut: F falls through 0. Slack: delta rises through 0, or the virtual force
    rises through 0 while delta > 0."""
    def taut_rhs(t, y):
        return [y[1], (-F02 - M - A2 * math.sin(W2 * t) - C2 * y[0] - B2 * y[1]) / M2]

    def slack_rhs(t, y):
        return [y[1], (-M - A2 * math.sin(W2 * t)) / M2]

    def force(t, y):
        return C2 * y[0] + B2 * y[1] + F02

    def delta(t, y):
        return y[0] + F02 / C2

    def virtual(t, y):
        return force(t, y) if delta(t, y) > 0 else -1.0

    t, y, taut, out = 0.0, np.array(x0, dtype=float), True, []
    while True:
        force.direction = -1 if taut else 1
        delta.direction = virtual.direction = 1
        events = [force] if taut else [delta, virtual]
        for ev in events:
            ev.terminal = True
        sol = solve_ivp(taut_rhs if taut else slack_rhs, (t, t_end), y, method="DOP853", rtol=1e-12,
                        atol=1e-16, events=events)
        if sol.status != 1:
            return out
        t, j = min((te[0], j) for j, te in enumerate(sol.t_events) if te.size)
        y, taut = sol.y_events[j][0], not taut
        out.append((t, taut))


def test_force_dipping_below_zero_slackens_twice_a_period():
    # the minimum at -1e-3 of the force amplitude: a short slack episode (~1.7% of a period)
    # every period, two switches each; times as the own event-located reference to 1e-7 s
    # (agreed to 5e-14 s when written)
    M, X0, P, Q, Fs, Fc = periodic(1e-3)
    x0 = np.array([X0 + Q, W2 * P])
    t_end = PERIODS * 2 * math.pi / W2          # F(0) = 111 N: the run starts and ends taut
    r = simulate(grazing_net(M), t_end, PERIODS * 50 + 1, EXACT, x0=x0)
    ref = grazing_reference(M, x0, t_end)
    assert r.extra["events"] == len(ref) == 2 * PERIODS
    assert [on for _, _, on in r.extra["switches"]] == [on for _, on in ref] == [False, True] * PERIODS
    assert_allclose(switch_times(r), [t for t, _ in ref], rtol=0, atol=1e-7)


# --- 3. zero pretension on the roller table ------------------------------------------------------
def test_zero_pretension_roller_table_reaches_the_static_balance():
    # steady_speed: the motor carries n M / i_tot on its linearised characteristic (hand
    # computation in tests/test_roller_table.py). A horizon of 6 s with the window from 4.5 s
    # cannot show it to 1e-6: the load step at t = 3 s leaves a transient that decays at
    # 3.23 1/s (slowest mode of the final strand pattern, return strand slack; eigenvalue
    # -3.227 +- 44.2 i), so the 4.5..6 s means sit 1.8e-5..3.8e-5 above steady_speed (1.6e-5..
    # 3.2e-5 with the default 300 N pretension, where nothing is slack: the transient, not the
    # core). e^(-3.227 * 3) = 6e-5 of that by 7.5..9 s: about 2e-9, measured 0.9e-9..1.6e-9.
    p = params(pretension=0.0)
    net = roller_table.build(p)
    r = simulate(net, 9.0, 9001, EXACT)
    late = r.window(7.5)
    for k in (1, 2, 3):
        assert r[f"omega_end{k}a"][late].mean() == pytest.approx(roller_table.steady_speed(p), rel=1e-8), k


# --- 4. pulsating roller load ------------------------------------------------------------------
PULSE = {"load_amplitude": 70.0, "load_frequency": 50.0}    # 460 switches over 5 s (load from 3 s)


@pytest.mark.slow
def test_pulsating_load_does_not_depend_on_the_output_grid():
    # 5001, 10001 and 20001 samples over 5 s: the same switches, the same states at the common
    # output times (every 2nd / 4th sample of the finest), so the same window statistics there
    # (measured differences 1e-13 of the scale). Statistics over each run's own grid are not
    # compared: a mean over N samples with both ends is O(1/N) off the integral (5001 vs 20001:
    # 1.2e-3 on omega_end1a), and extremes depend on where the samples fall (force peaks 2.5e-3)
    p = params(**PULSE)
    net = roller_table.build(p)
    runs = {n: simulate(net, 5.0, n, EXACT) for n in (5001, 10001, 20001)}
    fine = runs[20001]
    assert fine.extra["events"] > 200
    names = ["omega_end1a"] + [f"F_{s.name}" for s in net.strands]
    for n, step in ((5001, 4), (10001, 2)):
        r = runs[n]
        assert r.extra["events"] == fine.extra["events"]
        assert [(s, on) for _, s, on in r.extra["switches"]] == [(s, on) for _, s, on in fine.extra["switches"]]
        assert_allclose(switch_times(r), switch_times(fine), rtol=0, atol=1e-9)
        assert_allclose(r.t, fine.t[::step], rtol=0, atol=1e-12)
        late = r.window(4.5)
        for name in names:
            scale = np.max(np.abs(fine[name]))
            assert_allclose(r[name], fine[name][::step], rtol=0, atol=1e-9 * scale, err_msg=name)
            a, b = r[name][late], fine[name][::step][late]
            assert a.max() == pytest.approx(b.max(), rel=1e-6, abs=1e-6 * scale), name
            assert a.min() == pytest.approx(b.min(), rel=1e-6, abs=1e-6 * scale), name
            assert a.mean() == pytest.approx(b.mean(), rel=1e-6, abs=1e-6 * scale), name


def augmented(net, taut, t_mid):
    A, B = net.first_order(tuple(taut), t_mid)
    m, q = A.shape[0], B.shape[1]
    F = np.zeros((m + q, m + q))
    F[:m, :m], F[:m, m:], F[m:, m:] = A, B, net.generator_matrix()
    return F


def taut_state(net, t1):
    """State at t1 from rest with every strand taut, by scipy's expm on each input piece
    (exact for a linear piece), and the smallest strand force seen on a 0.1 ms grid."""
    _, force = net.strand_rows()
    bounds = [0.0] + net.breaks(t1) + [t1]
    z = np.concatenate([net.initial_state(), net.generators(0.0)])
    fmin = math.inf
    for a, b in zip(bounds, bounds[1:]):
        F = augmented(net, [True] * len(net.strands), 0.5 * (a + b))
        n = max(1, int(round((b - a) / 1e-4)))
        S, w = expm(F * (b - a) / n), z
        for _ in range(n):
            w = S @ w
            fmin = min(fmin, float(np.min(force @ w)))
        z = expm(F * (b - a)) @ z
    return z[:net.size], fmin


def hybrid_reference(net, t0, x0, t_end, t_eval, method, rtol):
    """Own hybrid integration from (t0, x0): solve_ivp per strand mode and input piece
    (modes from net.first_order, switching rows from net.strand_rows over z = [x, g]),
    terminal events with their direction, restarted at every event and break point. A virtual
    force rising through 0 while delta <= 0 fires without a switch; that function is then not
    fired again at the restart point."""
    delta, force = net.strand_rows()
    m, ns, gen = net.size, len(net.strands), net.generators
    bounds = sorted({t0, t_end, *[b for b in net.breaks(t_end) if b > t0]})
    x = np.asarray(x0, dtype=float)
    z = np.concatenate([x, gen(t0)])
    taut = [bool(delta[k] @ z > 0 and force[k] @ z > 0) for k in range(ns)]
    out = np.full((m, len(t_eval)), np.nan)
    out[:, 0] = x
    t, seg, skip, switches = t0, 0, None, []
    while t < t_end:
        while bounds[seg + 1] <= t:
            seg += 1
        t_stop = bounds[seg + 1]
        A, B = net.first_order(tuple(taut), 0.5 * (bounds[seg] + t_stop))
        funcs = []
        for k in range(ns):
            kinds = [("force", force[k], -1)] if taut[k] else [("delta", delta[k], 1), ("force", force[k], 1)]
            for kind, row, d in kinds:
                def ev(s, y, row=row, d=d, start=t, again=skip == (k, kind)):
                    v = row[:m] @ y + row[m:] @ gen(s)
                    return d * max(abs(v), 1e-300) if again and s == start else v
                ev.terminal, ev.direction = True, d
                funcs.append((k, kind, ev))
        kw = {"jac": lambda s, y: A} if method == "Radau" else {}
        sol = solve_ivp(lambda s, y: A @ y + B @ gen(s), (t, t_stop), x, method=method, rtol=rtol,
                        atol=rtol * 1e-2, events=[f for _, _, f in funcs],
                        t_eval=[tt for tt in t_eval if t < tt <= t_stop], **kw)
        assert sol.status >= 0, sol.message
        out[:, np.searchsorted(t_eval, sol.t)] = sol.y
        if sol.status == 1:
            t_e, j = min((te[0], j) for j, te in enumerate(sol.t_events) if te.size)
            k, kind, _ = funcs[j]
            x = sol.y_events[j][0]
            zz = np.concatenate([x, gen(t_e)])
            new = False if taut[k] else (kind == "delta" or bool(delta[k] @ zz > 0))
            skip = None if new != taut[k] else (k, kind)
            if new != taut[k]:
                taut[k] = new
                switches.append((t_e, net.strands[k].name, new))
            t = t_e
        else:
            x, t, skip = sol.y[:, -1], t_stop, None
    return out, switches


@pytest.mark.parametrize("method, after", [("DOP853", 0.3)])
def test_pulsating_load_agrees_with_an_own_event_located_reference(method, after):
    # (Radau, the implicit reference, over the same pulsating load: 125 switches in 0.6 s, stored
    # at rtol 1e-11 by tests/reference/make_references.py and compared through the command in
    # tests/test_hard_cases_cli.py::test_pulsating_load_slackening_strands_against_radau; here
    # it took a minute for 11 switches)
    # up to the load start (3 s) every strand stays taut (default 300 N pretension; smallest
    # force 227 N on a 0.1 ms grid, and the exact run's first switch comes later): that piece
    # is linear and scipy's expm gives its end state. From there our own solve_ivp with events
    # at rtol 1e-11 (DOP853: 43 switches in 0.3 s, ~3 s; Radau, slow: 11 switches in 0.15 s,
    # ~20 s; Radau at rtol 1e-11 over 0.5 s takes minutes). Measured when written: switch times
    # 7e-11 s, speeds 2e-10 and forces 3e-10 of their scale.
    p = params(**PULSE)
    net = roller_table.build(p)
    t0, t_end = p["load_start"], p["load_start"] + after
    r = simulate(net, t_end, int(round(t_end * 1000)) + 1, EXACT)
    x0, fmin = taut_state(net, t0)
    assert fmin > 100.0
    assert switch_times(r)[0] > t0
    i0 = int(np.searchsorted(r.t, t0 - 1e-12))
    # each state to 1e-9 of its own scale over the run (the motor torque is 6e-4 N m here,
    # 17 N m in the start-up: an absolute 1e-9 would ask 1e-10 of its scale)
    for got, want, scale in zip(r.states[:, i0], x0, np.abs(r.states).max(axis=1)):
        assert got == pytest.approx(want, rel=1e-9, abs=1e-9 * scale)
    out, ref = hybrid_reference(net, r.t[i0], x0, t_end, r.t[i0:], method, 1e-11)
    assert len(ref) >= 10
    assert [(s, on) for _, s, on in r.extra["switches"]] == [(s, on) for _, s, on in ref]
    assert_allclose(switch_times(r), [t for t, _, _ in ref], rtol=0, atol=1e-8)
    names = [name for name, _ in net.state_names()]
    for name in ("omega_end1a", "omega_drive", "omega_motor"):
        k = names.index(name)
        assert_allclose(r[name][i0:], out[k], rtol=0, atol=1e-8 * np.max(np.abs(r[name])), err_msg=name)
    forces = net.strand_forces(r.t[i0:], out)
    for s in net.strands:
        got = r[f"F_{s.name}"][i0:]
        assert_allclose(got, forces[s.name], rtol=0, atol=1e-8 * np.max(np.abs(got)), err_msg=s.name)
