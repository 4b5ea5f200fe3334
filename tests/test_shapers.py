"""Tests of beltcalc.formulas.shapers: ZV, ZVD and EI input shapers (Singer & Seering 1990;
Singhose, Seering & Singer 1994), their residual vibration, and moves convolved with them.

References are independent of the code: the closed forms of the undamped sensitivity curves,
the shapers' formulas written out here, Singhose's published damped-EI curve fits, and a
second-order system x'' + 2 zeta w x' + w^2 x = a(t) driven by the move, integrated with
scipy's DOP853 at rtol 1e-12 (checked first against the exact response to steps of
acceleration).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from numpy.testing import assert_allclose

from beltcalc.errors import InputError
from beltcalc.formulas.profiles import Phase, SCurve, move_by_time, scurve, trapezoid
from beltcalc.formulas.shapers import (SHAPERS, ei, insensitivity, residual_vibration,
                                       shape_phases, shaped_profile, zv, zvd)


def k_factor(zeta):
    return math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2))


def textbook_v(amps, times, f, zeta):
    """[SS90] V written out: exp(-zeta w t_n) sqrt(C^2 + S^2), C, S sums with exp(+zeta w t_i)."""
    w = 2 * math.pi * np.asarray(f, dtype=float)[..., None]
    wd = w * math.sqrt(1 - zeta ** 2)
    a, t = np.asarray(amps), np.asarray(times)
    c = (a * np.exp(zeta * w * t) * np.cos(wd * t)).sum(-1)
    s = (a * np.exp(zeta * w * t) * np.sin(wd * t)).sum(-1)
    return np.exp(-zeta * w[..., 0] * t[-1]) * np.hypot(c, s)


# -- the shapers ------------------------------------------------------------------------------------

class TestShapers:
    @pytest.mark.parametrize("zeta", [0.0, 0.05, 0.3])
    def test_zv_and_zvd_are_the_published_sequences(self, zeta):
        # [SS90]: ZV A = [1, K]/(1+K), t = [0, Td/2]; ZVD A = [1, 2K, K^2]/(1+K)^2, t = [0, Td/2, Td]
        f, k = 12.0, k_factor(zeta)
        td = 1 / (f * math.sqrt(1 - zeta ** 2))
        s = zv(f, zeta)
        assert s.amplitudes == pytest.approx([1 / (1 + k), k / (1 + k)], rel=1e-14)
        assert s.times == pytest.approx([0.0, td / 2], rel=1e-14)
        d = zvd(f, zeta)
        assert d.amplitudes == pytest.approx(np.array([1, 2 * k, k * k]) / (1 + k) ** 2, rel=1e-14)
        assert d.times == pytest.approx([0.0, td / 2, td], rel=1e-14)
        assert (d.duration, d.frequency, d.zeta, d.name) == (pytest.approx(td, rel=1e-14), f, zeta, "zvd")

    @pytest.mark.parametrize("vtol", [0.01, 0.05, 0.2])
    def test_undamped_ei_is_the_closed_form(self, vtol):
        # [SSS94]: A = [(1+V)/4, (1-V)/2, (1+V)/4], t = [0, T/2, T]
        s = ei(5.0, 0.0, vtol)
        assert s.amplitudes == pytest.approx([(1 + vtol) / 4, (1 - vtol) / 2, (1 + vtol) / 4], rel=1e-14)
        assert s.times == pytest.approx([0.0, 0.1, 0.2], rel=1e-14)

    @pytest.mark.parametrize("zeta", [0.01, 0.05, 0.1, 0.2])
    @pytest.mark.parametrize("vtol", [0.02, 0.05, 0.1])
    def test_damped_ei_meets_its_defining_conditions(self, zeta, vtol):
        """V = Vtol at the design, its peak there (dV/df = 0), and V = 0 at one frequency below
        and one above (minima found by scipy's bounded search on the textbook V)."""
        from scipy.optimize import minimize_scalar
        f = 8.0
        s = ei(f, zeta, vtol)
        v = lambda x: float(textbook_v(s.amplitudes, s.times, x, zeta))   # noqa: E731
        assert v(f) == pytest.approx(vtol, rel=1e-10)
        h = 1e-5 * f
        assert (v(f + h) - v(f - h)) / (2 * h) == pytest.approx(0.0, abs=1e-8 / f)
        assert v(f + h) < vtol and v(f - h) < vtol or (v(f + h), v(f - h)) == pytest.approx((vtol, vtol), rel=1e-9)
        for bracket in ((0.6 * f, f), (f, 1.4 * f)):
            m = minimize_scalar(v, bounds=bracket, method="bounded", options={"xatol": 1e-13 * f})
            assert m.fun == pytest.approx(0.0, abs=1e-8)
        assert sum(s.amplitudes) == pytest.approx(1.0, rel=1e-14)
        assert min(s.amplitudes) > 0

    @pytest.mark.parametrize("zeta", [0.0, 0.02, 0.05, 0.1, 0.2])
    def test_damped_ei_against_singhoses_curve_fits(self, zeta):
        """Singhose's curve fits of the damped EI shaper at Vtol = 5 % (as printed in Klipper's
        klippy/extras/shaper_defs.py, get_ei_shaper, and Convolve's DIGEI5.m for t2): times in
        damped periods, last impulse at Td. Ours puts the hump's peak at the design frequency
        with the last time free: amplitudes agree to 1e-3, times to 1.5 % of Td."""
        v = 0.05
        a1 = (0.24968 + 0.24961 * v) + ((0.80008 + 1.23328 * v) + (0.49599 + 3.17316 * v) * zeta) * zeta
        a3 = (0.25149 + 0.21474 * v) + ((-0.83249 + 1.41498 * v) + (0.85181 - 4.90094 * v) * zeta) * zeta
        t2 = 0.4999 + (((0.46159 + 8.57843 * v) * v) + (((4.26169 - 108.644 * v) * v)
                                                        + ((1.75601 + 336.989 * v) * v) * zeta) * zeta) * zeta
        f = 10.0
        td = 1 / (f * math.sqrt(1 - zeta ** 2))
        s = ei(f, zeta, v)
        assert s.amplitudes == pytest.approx([a1, 1 - a1 - a3, a3], abs=1e-3)
        assert np.array(s.times) / td == pytest.approx([0.0, t2, 1.0], abs=0.015)

    @given(f=st.floats(0.1, 1e4), zeta=st.floats(0.0, 0.25), vtol=st.floats(0.01, 0.2),
           kind=st.sampled_from(sorted(SHAPERS)))
    @settings(max_examples=40, deadline=None)
    def test_amplitudes_sum_to_one_and_times_ascend(self, f, zeta, vtol, kind):
        s = SHAPERS[kind](f, zeta, vtol) if kind == "ei" else SHAPERS[kind](f, zeta)
        assert sum(s.amplitudes) == pytest.approx(1.0, rel=1e-13)
        assert min(s.amplitudes) > 0 and s.times[0] == 0.0
        assert np.all(np.diff(s.times) > 0)
        # the time it adds: half a damped period (ZV), one (ZVD), a little under one (EI, damped)
        periods = s.duration * f * math.sqrt(1 - zeta ** 2)
        if kind == "ei":
            assert periods == pytest.approx(1.0, abs=0.05)
        else:
            assert periods == pytest.approx(0.5 if kind == "zv" else 1.0, rel=1e-13)


# -- the sensitivity curves -------------------------------------------------------------------------

class TestResidualVibration:
    R = np.linspace(0.05, 2.95, 581)

    def test_undamped_closed_forms(self):
        f = 7.0
        # ZV: |cos(pi r / 2)|; ZVD: cos^2(pi r / 2); EI: |(1-V)/2 + (1+V)/2 cos(pi r)|
        assert_allclose(residual_vibration(zv(f), self.R * f), np.abs(np.cos(np.pi * self.R / 2)), atol=1e-13)
        assert_allclose(residual_vibration(zvd(f), self.R * f), np.cos(np.pi * self.R / 2) ** 2, atol=1e-13)
        v = 0.05
        assert_allclose(residual_vibration(ei(f, 0.0, v), self.R * f),
                        np.abs((1 - v) / 2 + (1 + v) / 2 * np.cos(np.pi * self.R)), atol=1e-13)

    @pytest.mark.parametrize("make", [zv, zvd, ei])
    def test_damped_against_the_textbook_formula(self, make):
        s = make(20.0, 0.05)
        for zeta in (0.0, 0.05, 0.12):      # the actual damping may differ from the design's
            assert_allclose(residual_vibration(s, self.R * 20.0, zeta),
                            textbook_v(s.amplitudes, s.times, self.R * 20.0, zeta), rtol=1e-11, atol=1e-14)
        assert residual_vibration(s, 20.0) == pytest.approx(0.05 if make is ei else 0.0, abs=1e-13)
        assert isinstance(residual_vibration(s, 20.0), float)

    def test_design_damping_is_the_default(self):
        s = zvd(3.0, 0.1)
        assert residual_vibration(s, 3.3) == pytest.approx(residual_vibration(s, 3.3, 0.1), rel=1e-15)


class TestInsensitivity:
    def test_undamped_zv_zvd_ei_widths_at_5_percent(self):
        """Closed forms from the curves above; they are the figures the input-shaping literature
        quotes for 5 % (ZV about 0.06, ZVD about 0.29, EI about 0.40 of the design frequency)."""
        zv_half = 2 / math.pi * math.asin(0.05)                  # |cos(pi r/2)| = 0.05
        zvd_half = 2 / math.pi * math.asin(math.sqrt(0.05))      # cos^2(pi r/2) = 0.05
        # EI: (1-V)/2 + (1+V)/2 cos(pi r) = 0.05 outside the zeros, V = 0.05
        ei_low = math.acos((2 * 0.05 - 0.95) / 1.05) / math.pi
        for s, low, high in ((zv(50.0), 1 - zv_half, 1 + zv_half), (zvd(50.0), 1 - zvd_half, 1 + zvd_half),
                             (ei(50.0), ei_low, 2 - ei_low)):
            assert insensitivity(s, 0.05) == pytest.approx((low, high), rel=1e-12)
        widths = [np.diff(insensitivity(s, 0.05))[0] for s in (zv(50.0), zvd(50.0), ei(50.0))]
        assert widths == pytest.approx([0.0637, 0.2871, 0.3995], abs=5e-5)

    def test_ei_defaults_to_its_vtol_and_holds_the_hump(self):
        s = ei(10.0, 0.05, 0.1)
        low, high = insensitivity(s)
        assert (low, high) == pytest.approx(insensitivity(s, 0.1), rel=1e-15)
        r = np.linspace(low, high, 2001)
        assert np.max(residual_vibration(s, r * 10.0)) == pytest.approx(0.1, rel=1e-9)   # the peak, at design
        assert residual_vibration(s, [low * 10.0, high * 10.0]) == pytest.approx([0.1, 0.1], rel=1e-9)

    def test_a_level_below_the_least_vibration_is_refused(self):
        s = zv(10.0, 0.05)
        with pytest.raises(InputError, match="level"):
            insensitivity(s, 0.01, zeta=0.5)      # mismatched damping: V never reaches 1 %


# -- bad input --------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, param", [
    (lambda: zv(0.0), "frequency"), (lambda: zvd(-1.0), "frequency"), (lambda: ei(math.nan), "frequency"),
    (lambda: zv(1.0, -0.1), "zeta"), (lambda: zvd(1.0, 1.0), "zeta"), (lambda: ei(1.0, 1.5), "zeta"),
    (lambda: ei(1.0, 0.0, 0.0), "vtol"), (lambda: ei(1.0, 0.05, 1.0), "vtol"), (lambda: ei(1.0, 0.0, -0.1), "vtol"),
    (lambda: residual_vibration(zv(1.0), [1.0, 0.0]), "frequency"), (lambda: residual_vibration(zv(1.0), 1.0, 1.0), "zeta"),
    (lambda: insensitivity(zv(1.0), 0.0), "level"), (lambda: ei(1.0, 0.5, 0.6), "zeta"),
])
def test_bad_input_names_the_parameter(call, param):
    with pytest.raises(InputError) as e:
        call()
    assert e.value.param == param


# -- a move convolved with a shaper ------------------------------------------------------------------

def accel_at(phases, t):
    """Acceleration of a move at times ``t`` (right-continuous; 0 before and after it)."""
    t = np.asarray(t, dtype=float)
    out = np.zeros_like(t)
    t0 = 0.0
    for ph in phases:
        inside = (t >= t0) & (t < t0 + ph.duration)
        out[inside] = ph.accel + ph.jerk * (t[inside] - t0)
        t0 += ph.duration
    return out


MOVES = {
    "trapezoid": trapezoid(100.0, 1000.0, 50.0).phases,
    "triangle": trapezoid(100.0, 1000.0, 4.0).phases,
    "scurve": scurve(100.0, 1000.0, 20000.0, 50.0).phases,
    "scurve short": scurve(100.0, 1000.0, 5000.0, 3.0).phases,
    "by time": move_by_time(40.0, 0.6, 0.4, 0.3).phases,
}


class TestShapePhases:
    @pytest.mark.parametrize("move", sorted(MOVES))
    @pytest.mark.parametrize("shaper", [zv(7.0), zvd(13.0, 0.05), ei(4.0, 0.1), ei(40.0, 0.02, 0.1)], ids=str)
    def test_angle_speed_continuity_and_the_brute_force_sum(self, move, shaper):
        phases = MOVES[move]
        out = shape_phases(phases, shaper)
        angle = sum(p.angle for p in phases)
        assert sum(p.angle for p in out) == pytest.approx(angle, rel=1e-12)
        assert sum(p.duration for p in out) == pytest.approx(sum(p.duration for p in phases) + shaper.duration,
                                                              rel=1e-13)
        assert out[0].speed0 == pytest.approx(0.0, abs=1e-12) and out[-1].speed1 == pytest.approx(0.0, abs=1e-9)
        peak = max(max(p.speed0, p.speed1) for p in phases)
        assert_allclose([p.speed1 for p in out[:-1]], [p.speed0 for p in out[1:]], rtol=0, atol=1e-12 * peak)
        assert min(p.duration for p in out) > 0
        assert [p.name for p in out] == [f"shaped {k}" for k in range(1, len(out) + 1)]
        # the acceleration at random times: sum_i A_i a(t - t_i), evaluated on the original move
        rng = np.random.default_rng(7)
        t = rng.uniform(0, sum(p.duration for p in out), 500)
        brute = sum(a * accel_at(phases, t - ti) for a, ti in zip(shaper.amplitudes, shaper.times))
        amax = max(abs(p.accel) + abs(p.jerk) * p.duration for p in phases)
        assert_allclose(accel_at(out, t), brute, rtol=0, atol=1e-9 * amax)
        # within the move's own bounds, and one sign of acceleration per phase
        assert max(max(p.speed0, p.speed1) for p in out) <= peak * (1 + 1e-12)
        assert all(p.accel * p.accel1 >= -1e-9 * amax ** 2 for p in out)

    def test_a_move_between_speeds_adds_the_held_speeds_angle(self):
        # from 10 rad/s up to 30 rad/s: theta_s = theta + sum A_i (w0 t_i + w1 (t_n - t_i))
        phases = (Phase("up", 0.2, 10.0, 100.0), Phase("hold", 0.1, 30.0, 0.0))
        s = zvd(5.0, 0.1)
        out = shape_phases(phases, s)
        theta = sum(p.angle for p in phases)
        extra = sum(a * (10.0 * t + 30.0 * (s.duration - t)) for a, t in zip(s.amplitudes, s.times))
        assert sum(p.angle for p in out) == pytest.approx(theta + extra, rel=1e-12)
        assert (out[0].speed0, out[-1].speed1) == pytest.approx((10.0, 30.0), rel=1e-12)

    @given(speed=st.floats(1.0, 500.0), accel=st.floats(10.0, 1e5), jerk_ratio=st.floats(0.5, 50.0),
           stroke=st.floats(0.01, 1000.0), f=st.floats(0.5, 200.0), zeta=st.floats(0.0, 0.2),
           kind=st.sampled_from(sorted(SHAPERS)))
    @settings(max_examples=60, deadline=None)
    def test_shaping_keeps_the_angle_and_the_final_speed(self, speed, accel, jerk_ratio, stroke, f, zeta, kind):
        move = scurve(speed, accel, jerk_ratio * accel * accel / speed, stroke)
        out = shape_phases(move.phases, SHAPERS[kind](f, zeta))
        assert sum(p.angle for p in out) == pytest.approx(stroke, rel=1e-12)
        assert out[-1].speed1 == pytest.approx(0.0, abs=1e-11 * move.peak_speed)

    def test_empty_and_zero_duration_phases(self):
        assert shape_phases((), zv(1.0)) == ()
        out = shape_phases((Phase("a", 0.5, 0.0, 2.0), Phase("nothing", 0.0, 1.0, 5.0), Phase("b", 0.5, 1.0, -2.0)),
                           zv(1.0))
        assert sum(p.angle for p in out) == pytest.approx(0.5, rel=1e-12)
        assert min(p.duration for p in out) > 0


class TestShapedProfile:
    def test_a_long_dwell_absorbs_the_shaper(self):
        p = trapezoid(100.0, 1000.0, 50.0, dwell=0.2)
        s = zvd(10.0)                                  # 0.1 s
        q = shaped_profile(p, s)
        assert isinstance(q, SCurve) and q.jerk == math.inf
        assert q.cycle_time == pytest.approx(p.cycle_time, rel=1e-13)
        assert q.dwell == pytest.approx(0.1, rel=1e-12) and q.phases[-1] == Phase("dwell", q.dwell, 0.0, 0.0)
        assert sum(ph.angle for ph in q.phases) == pytest.approx(50.0, rel=1e-12)
        assert q.peak_speed == pytest.approx(100.0, rel=1e-12)
        # the 0.1 s of acceleration and the ZVD's copies at 0, 0.05, 0.1 s: two overlap at most, 1/4 + 1/2
        assert q.peak_accel == pytest.approx(750.0, rel=1e-12)
        # the time to the peak speed: 0.1 s of ramp spread over 0.1 s more
        assert q.accel_time == pytest.approx(0.2, rel=1e-12)
        assert (q.speed, q.accel, q.stroke) == (p.speed, p.accel, p.stroke)

    def test_a_short_dwell_is_kept_and_the_cycle_lengthens(self):
        p = scurve(100.0, 1000.0, 20000.0, 50.0, dwell=0.05)
        s = ei(10.0, 0.05)
        q = shaped_profile(p, s)
        assert q.cycle_time == pytest.approx(p.cycle_time + s.duration, rel=1e-13)
        assert q.dwell == pytest.approx(0.05, rel=1e-15) and q.phases[-1].name == "dwell"
        assert q.jerk == p.jerk and q.peak_accel <= p.peak_accel * (1 + 1e-12)

    def test_a_dwell_exactly_as_long_disappears(self):
        q = shaped_profile(trapezoid(100.0, 1000.0, 50.0, dwell=0.05), zv(10.0))
        assert q.phases[-1].name != "dwell" and q.dwell == 0.0
        assert q.cycle_time == pytest.approx(0.65, rel=1e-13)


# -- the physics: a mode driven by the shaped move -------------------------------------------------

def residual_amplitude(phases, f, zeta, t_obs):
    """Amplitude at ``t_obs`` (after the move) of x'' + 2 zeta w x' + w^2 x = a(t), from rest:
    DOP853 at rtol 1e-12 phase by phase; sqrt(x^2 + ((x' + zeta w x)/w_d)^2) is the envelope."""
    from scipy.integrate import solve_ivp
    w = 2 * math.pi * f
    wd = w * math.sqrt(1 - zeta ** 2)
    y, t0 = np.zeros(2), 0.0
    for ph in list(phases) + [Phase("after", t_obs - sum(p.duration for p in phases), 0.0, 0.0)]:
        def rhs(t, y, ph=ph):
            return [y[1], ph.accel + ph.jerk * t - 2 * zeta * w * y[1] - w * w * y[0]]
        sol = solve_ivp(rhs, (0.0, ph.duration), y, method="DOP853", rtol=1e-12, atol=1e-16)
        y, t0 = sol.y[:, -1], t0 + ph.duration
    return math.hypot(y[0], (y[1] + zeta * w * y[0]) / wd)


def step_amplitude(phases, f, zeta, t_obs):
    """The same amplitude, exact, for a move of constant-acceleration phases: a step of
    acceleration da at t_k leaves the phasor da e^{(zeta w + i w_d) t_k}; amplitude
    e^{-zeta w t} |sum| / (w^2 sqrt(1 - zeta^2))."""
    w = 2 * math.pi * f
    s = complex(zeta * w, w * math.sqrt(1 - zeta ** 2))
    t_k, a_prev, total = 0.0, 0.0, 0j
    for ph in list(phases) + [Phase("after", 0.0, 0.0, 0.0)]:
        total += (ph.accel - a_prev) * np.exp(s * t_k)
        a_prev, t_k = ph.accel, t_k + ph.duration
    return math.exp(-zeta * w * t_obs) * abs(total) / (w * w * math.sqrt(1 - zeta ** 2))


class TestModeResponse:
    MOVE = trapezoid(100.0, 1000.0, 50.0).phases      # 0.6 s

    @pytest.mark.parametrize("zeta", [0.0, 0.05])
    def test_the_integrator_matches_the_exact_step_response(self, zeta):
        for f in (7.3, 12.0):
            assert residual_amplitude(self.MOVE, f, zeta, 1.0) == pytest.approx(
                step_amplitude(self.MOVE, f, zeta, 1.0), rel=1e-8)

    @pytest.mark.parametrize("zeta", [0.0, 0.05])
    @pytest.mark.parametrize("move", ["trapezoid", "scurve", "by time"])
    def test_zv_leaves_no_vibration_at_its_design(self, zeta, move):
        f = 7.3       # the unshaped move leaves vibration at 7.3 Hz (0.6 s is no multiple of its period)
        phases = MOVES[move]
        s = zv(f, zeta)
        t_obs = sum(p.duration for p in phases) + s.duration + 0.05
        unshaped = residual_amplitude(phases, f, zeta, t_obs - s.duration)
        assert unshaped > 1e-4
        assert residual_amplitude(shape_phases(phases, s), f, zeta, t_obs) == pytest.approx(0.0, abs=1e-9 * unshaped)

    @pytest.mark.parametrize("make", [zv, zvd, ei])
    @pytest.mark.parametrize("ratio", [0.85, 1.0, 1.1])
    def test_the_shaped_move_leaves_v_times_the_unshaped_vibration(self, make, ratio):
        """At the mode's actual frequency f = ratio f_design, the shaped move's vibration (at
        t + t_n) over the unshaped one's (at t) is V of residual_vibration."""
        zeta = 0.05
        s = make(7.3, zeta)
        f = ratio * 7.3
        t = sum(p.duration for p in self.MOVE) + 0.02
        unshaped = step_amplitude(self.MOVE, f, zeta, t)
        shaped = residual_amplitude(shape_phases(self.MOVE, s), f, zeta, t + s.duration)
        assert shaped / unshaped == pytest.approx(residual_vibration(s, f), rel=1e-7, abs=1e-9)


# -- docs/input_shaping.md -------------------------------------------------------------------------

def test_the_docs_table_is_the_codes_output():
    """The sensitivity table of docs/input_shaping.md, row by row, from the code (V in % to the
    page's 0.1, the width to 0.001, the added time in periods to 0.001)."""
    from pathlib import Path
    text = (Path(__file__).resolve().parents[1] / "docs" / "input_shaping.md").read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith(("| ZV |", "| ZVD |", "| EI |"))]
    assert len(rows) == 6
    ratios = [0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.2]
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        name, zeta = cells[0].lower(), float(cells[1])
        s = SHAPERS[name](1.0, zeta)
        page = [float(c) for c in cells[2:]]
        low, high = insensitivity(s, 0.05)
        ours = list(100 * residual_vibration(s, ratios)) + [high - low, s.duration]
        assert page == pytest.approx(ours, abs=0.05 + 1e-9) and page[7:] == pytest.approx(ours[7:], abs=5e-4 + 1e-12)


def test_the_docs_example_runs():
    from pathlib import Path
    text = (Path(__file__).resolve().parents[1] / "docs" / "input_shaping.md").read_text(encoding="utf-8")
    block = text.split("```python\n")[1].split("```")[0]
    exec(compile(block, "docs/input_shaping.md", "exec"), {})
