"""Tests of beltcalc.formulas.profiles: trapezoidal and triangular moves (Wojtkowiak et al. 2021, Fig. 9-12).

All quantities at the motor shaft, SI: rad, rad/s, rad/s^2, s. The area under the speed
curve is the stroke; the phases follow one another without a jump in speed.
"""

import math

import numpy as np

import pytest
from hypothesis import given, strategies as st

from beltcalc.errors import InputError
from beltcalc.formulas.profiles import trapezoid


def durations(p):
    return [ph.duration for ph in p.phases]


class TestTrapezoid:
    """omega_max = 100 rad/s, eps = 1000 rad/s^2, theta = 50 rad, dwell 0.2 s."""

    P = trapezoid(100.0, 1000.0, 50.0, dwell=0.2)

    def test_phase_names_and_durations(self):
        # t_a = omega/eps = 100/1000 = 0.1 s; theta_a = omega^2/(2 eps) = 10000/2000 = 5 rad;
        # t_c = (theta - 2 theta_a)/omega = (50 - 10)/100 = 0.4 s; dwell 0.2 s
        assert [ph.name for ph in self.P.phases] == ["accelerate", "cruise", "decelerate", "dwell"]
        assert durations(self.P) == pytest.approx([0.1, 0.4, 0.1, 0.2], rel=1e-12)
        # cycle = 0.1 + 0.4 + 0.1 + 0.2 = 0.8 s
        assert self.P.cycle_time == pytest.approx(0.8, rel=1e-12)
        assert self.P.accel_time == pytest.approx(0.1, rel=1e-12)
        assert self.P.triangular is False

    def test_angles_add_up_to_the_stroke(self):
        # accelerate: 0.5 * 1000 * 0.1^2 = 5 rad; cruise: 100 * 0.4 = 40 rad;
        # decelerate: 100 * 0.1 - 0.5 * 1000 * 0.1^2 = 10 - 5 = 5 rad; dwell: 0 rad. Sum 50 rad.
        assert [ph.angle for ph in self.P.phases] == pytest.approx([5.0, 40.0, 5.0, 0.0], abs=1e-12)
        assert sum(ph.angle for ph in self.P.phases) == pytest.approx(50.0, rel=1e-12)

    def test_speeds_and_accelerations(self):
        # 0 -> 100 at +1000, 100 -> 100 at 0, 100 -> 0 at -1000, standstill
        got = [(ph.speed0, ph.speed1, ph.accel) for ph in self.P.phases]
        want = [(0.0, 100.0, 1000.0), (100.0, 100.0, 0.0), (100.0, 0.0, -1000.0), (0.0, 0.0, 0.0)]
        for g, w in zip(got, want):
            assert g == pytest.approx(w, abs=1e-9)
        assert self.P.peak_speed == pytest.approx(100.0, rel=1e-12)

    def test_speeds_are_continuous_between_phases(self):
        for a, b in zip(self.P.phases, self.P.phases[1:]):
            assert b.speed0 == pytest.approx(a.speed1, abs=1e-9)


class TestTriangle:
    """theta = 4 rad < omega^2/eps = 10000/1000 = 10 rad: the speed is never reached."""

    P = trapezoid(100.0, 1000.0, 4.0)

    def test_peak_speed_is_sqrt_eps_theta(self):
        # omega_p = sqrt(eps theta) = sqrt(1000 * 4) = sqrt(4000) = 63.245553 rad/s
        assert self.P.triangular is True
        assert self.P.peak_speed == pytest.approx(63.245553, rel=1e-8)
        assert self.P.peak_speed == pytest.approx(math.sqrt(1000.0 * 4.0), rel=1e-12)

    def test_two_phases_no_cruise(self):
        # t_a = omega_p/eps = 63.245553/1000 = 0.063245553 s, twice for the cycle
        assert [ph.name for ph in self.P.phases] == ["accelerate", "decelerate"]
        assert durations(self.P) == pytest.approx([0.063245553, 0.063245553], rel=1e-8)
        assert self.P.cycle_time == pytest.approx(0.126491106, rel=1e-8)

    def test_area_is_the_stroke(self):
        # each half: 0.5 * 1000 * 0.063245553^2 = 0.5 * 1000 * 0.004 = 2 rad; sum 4 rad
        assert [ph.angle for ph in self.P.phases] == pytest.approx([2.0, 2.0], rel=1e-12)
        assert self.P.phases[-1].speed1 == pytest.approx(0.0, abs=1e-9)

    def test_stroke_just_short_of_the_boundary(self):
        # theta = 9.9 rad < 10 rad: triangular with omega_p = sqrt(9900) = 99.498744 rad/s
        p = trapezoid(100.0, 1000.0, 9.9)
        assert p.triangular is True
        assert p.peak_speed == pytest.approx(99.498744, rel=1e-8)


def test_exactly_at_the_boundary_is_a_trapezoid_without_cruise():
    # theta = omega^2/eps = 10 rad: the speed is reached at the midpoint; t_c = (10 - 10)/100 = 0
    p = trapezoid(100.0, 1000.0, 10.0)
    assert p.triangular is False
    assert [ph.name for ph in p.phases] == ["accelerate", "decelerate"]
    assert p.peak_speed == pytest.approx(100.0, rel=1e-12)
    assert p.cycle_time == pytest.approx(0.2, rel=1e-12)


def test_dwell():
    # dwell 0: no dwell phase; dwell 0.35 s: a standstill phase of 0.35 s, cycle 0.6 + 0.35 = 0.95 s
    p0 = trapezoid(100.0, 1000.0, 50.0)
    p1 = trapezoid(100.0, 1000.0, 50.0, dwell=0.35)
    assert [ph.name for ph in p0.phases] == ["accelerate", "cruise", "decelerate"]
    assert p0.cycle_time == pytest.approx(0.6, rel=1e-12)
    assert p1.phases[-1].name == "dwell"
    assert (p1.phases[-1].duration, p1.phases[-1].speed0, p1.phases[-1].accel) == pytest.approx(
        (0.35, 0.0, 0.0), abs=1e-12)
    assert p1.cycle_time == pytest.approx(0.95, rel=1e-12)


@given(speed=st.floats(0.1, 1e4), accel=st.floats(0.1, 1e6), stroke=st.floats(1e-3, 1e5),
       dwell=st.floats(0.0, 10.0))
def test_any_move_covers_the_stroke_and_stops(speed, accel, stroke, dwell):
    p = trapezoid(speed, accel, stroke, dwell)
    assert sum(ph.angle for ph in p.phases) == pytest.approx(stroke, rel=1e-9)
    assert p.phases[-1].speed1 == pytest.approx(0.0, abs=1e-9 * speed)
    # the peak never exceeds the speed asked for; below it only for a triangle
    assert p.peak_speed == pytest.approx(min(speed, math.sqrt(accel * stroke)), rel=1e-12)
    assert p.triangular == (stroke < speed ** 2 / accel)


@pytest.mark.parametrize("args, param, unit", [
    ((0.0, 1000.0, 50.0), "speed", "rad/s"),
    ((-100.0, 1000.0, 50.0), "speed", "rad/s"),
    ((100.0, 0.0, 50.0), "accel", "rad/s^2"),
    ((100.0, -1.0, 50.0), "accel", "rad/s^2"),
    ((100.0, 1000.0, 0.0), "stroke", "rad"),
    ((100.0, 1000.0, -5.0), "stroke", "rad"),
    ((100.0, 1000.0, 50.0, -0.1), "dwell", "s"),
    ((math.nan, 1000.0, 50.0), "speed", "rad/s"),
    ((100.0, math.inf, 50.0), "accel", "rad/s^2"),
    ((100.0, 1000.0, 50.0, math.inf), "dwell", "s"),
])
def test_bad_inputs_name_the_parameter(args, param, unit):
    with pytest.raises(InputError) as exc:
        trapezoid(*args)
    assert exc.value.param == param
    assert str(exc.value).startswith(f"{param}: ")
    assert unit in str(exc.value)


# --- S-curves and moves by time (issue 14) --------------------------------------------------------
# Biagiotti & Melchiorri, Trajectory Planning for Automatic Machines and Robots (2008), section 3.4.

from beltcalc.formulas.profiles import SCurve, move_by_time, scurve  # noqa: E402


def _kinematics(p, t):
    """(speed, acceleration) at time t from the phases' own data (omega0 + a0 s + j s^2/2)."""
    start = 0.0
    for ph in p.phases:
        if t <= start + ph.duration or ph is p.phases[-1]:
            s = t - start
            return ph.speed0 + ph.accel * s + 0.5 * ph.jerk * s * s, ph.accel + ph.jerk * s
        start += ph.duration


class TestSCurve:
    """v = 100 rad/s, a = 1000 rad/s^2, j = 20000 rad/s^3, theta = 50 rad:
    v j = 2e6 >= a^2 = 1e6, so T_j = a/j = 0.05 s, T_a = T_j + v/a = 0.15 s (constant
    acceleration 0.15 - 2 * 0.05 = 0.05 s), T_v = theta/v - T_a = 0.5 - 0.15 = 0.35 s; move 0.65 s."""

    P = scurve(100.0, 1000.0, 20000.0, 50.0, dwell=0.1)

    def test_phases_by_hand(self):
        assert [ph.name for ph in self.P.phases] == ["accel_in", "accelerate", "accel_out", "cruise",
                                                     "decel_in", "decelerate", "decel_out", "dwell"]
        assert [ph.duration for ph in self.P.phases] == pytest.approx(
            [0.05, 0.05, 0.05, 0.35, 0.05, 0.05, 0.05, 0.1], rel=1e-12)
        assert self.P.cycle_time == pytest.approx(0.75, rel=1e-12)
        assert self.P.accel_time == pytest.approx(0.15, rel=1e-12)
        assert self.P.peak_speed == pytest.approx(100.0, rel=1e-12)
        assert self.P.peak_accel == pytest.approx(1000.0, rel=1e-12)
        assert not self.P.triangular
        # speed after the first jerk phase: j T_j^2 / 2 = 20000 * 0.0025 / 2 = 25 rad/s
        assert self.P.phases[1].speed0 == pytest.approx(25.0, rel=1e-12)

    def test_speed_and_acceleration_are_continuous(self):
        for a, b in zip(self.P.phases, self.P.phases[1:]):
            assert b.speed0 == pytest.approx(a.speed1, abs=1e-9)
            assert b.accel == pytest.approx(a.accel1, abs=1e-9)
        assert self.P.phases[-1].speed1 == pytest.approx(0.0, abs=1e-12)

    def test_area_against_quadrature(self):
        from scipy.integrate import quad

        bounds = np.cumsum([0.0] + [ph.duration for ph in self.P.phases])
        area = sum(quad(lambda t: _kinematics(self.P, t)[0], a, b, epsabs=0, epsrel=1e-13)[0]
                   for a, b in zip(bounds, bounds[1:]))
        assert area == pytest.approx(50.0, rel=1e-12)


def test_scurve_with_zero_jerk_time_is_the_trapezoid_exactly():
    for args in ((100.0, 1000.0, 50.0, 0.2), (100.0, 1000.0, 4.0, 0.0), (100.0, 1000.0, 10.0, 0.3)):
        t = trapezoid(*args)
        s = scurve(args[0], args[1], math.inf, args[2], args[3])
        assert isinstance(s, SCurve)
        assert s.phases == t.phases          # the same floats, not approximately
        assert (s.triangular, s.peak_speed, s.accel_time, s.cycle_time) == \
            (t.triangular, t.peak_speed, t.accel_time, t.cycle_time)


def test_scurve_tends_to_the_trapezoid_as_jerk_grows():
    # T_j = a/j -> 0: the cycle time T_a + T_v + T_a = (T_j + v/a) + (theta/v - T_j - v/a) + ... = theta/v + v/a + T_j
    for j in (1e5, 1e7, 1e9):
        s = scurve(100.0, 1000.0, j, 50.0)
        assert s.cycle_time == pytest.approx(50.0 / 100.0 + 100.0 / 1000.0 + 1000.0 / j, rel=1e-12)


def test_scurve_speed_not_reached_acceleration_reached():
    # theta = 5 rad: T_v = 5/100 - 0.15 < 0; 2 a^3/j^2 = 2e9/4e8 = 5 rad <= 5: the acceleration is
    # just reached. T_j = 0.05; T_a = 0.025 + sqrt(0.000625 + 0.005) = 0.025 + 0.075 = 0.1 s = 2 T_j;
    # v = a (T_a - T_j) = 1000 * 0.05 = 50 rad/s
    s = scurve(100.0, 1000.0, 20000.0, 5.0)
    assert s.triangular
    assert s.peak_speed == pytest.approx(50.0, rel=1e-12)
    assert s.cycle_time == pytest.approx(0.2, rel=1e-12)
    # theta = 20 rad: T_a = 0.025 + sqrt(0.000625 + 0.02) = 0.025 + 0.1436141 = 0.1686141 s,
    # v = 1000 * (0.1686141 - 0.05) = 118.6141 > ... capped? no: v < v_max is required -> here v_max = 200
    s2 = scurve(200.0, 1000.0, 20000.0, 20.0)
    assert s2.triangular
    assert s2.peak_speed == pytest.approx(1000.0 * (0.025 + math.sqrt(0.000625 + 0.02) - 0.05), rel=1e-12)
    assert sum(ph.angle for ph in s2.phases) == pytest.approx(20.0, rel=1e-12)


def test_scurve_neither_speed_nor_acceleration_reached():
    # theta = 1 rad < 2 a^3/j^2 = 5 rad: T_j = (theta/(2 j))^(1/3) = (1/40000)^(1/3) = 0.02924018 s,
    # a_reached = j T_j = 584.8035 rad/s^2, v = j T_j^2 = 17.09976 rad/s, four jerk phases only
    s = scurve(100.0, 1000.0, 20000.0, 1.0)
    tj = (1.0 / 40000.0) ** (1.0 / 3.0)
    assert [ph.name for ph in s.phases] == ["accel_in", "accel_out", "decel_in", "decel_out"]
    assert s.peak_accel == pytest.approx(584.8035, rel=1e-6)
    assert s.peak_speed == pytest.approx(20000.0 * tj * tj, rel=1e-12)
    assert sum(ph.angle for ph in s.phases) == pytest.approx(1.0, rel=1e-12)


@given(speed=st.floats(0.1, 1e4), accel=st.floats(0.1, 1e6), jerk=st.floats(1.0, 1e9), stroke=st.floats(1e-3, 1e5))
def test_any_scurve_covers_the_stroke_within_its_limits(speed, accel, jerk, stroke):
    s = scurve(speed, accel, jerk, stroke)
    assert sum(ph.angle for ph in s.phases) == pytest.approx(stroke, rel=1e-9)
    assert s.phases[-1].speed1 == pytest.approx(0.0, abs=1e-9 * speed)
    assert s.peak_speed <= speed * (1 + 1e-12)
    assert max(max(abs(ph.accel), abs(ph.accel1)) for ph in s.phases) <= accel * (1 + 1e-9)
    assert all(abs(ph.jerk) == pytest.approx(jerk, rel=1e-12) or ph.jerk == 0 for ph in s.phases)
    for a, b in zip(s.phases, s.phases[1:]):
        assert b.speed0 == pytest.approx(a.speed1, abs=1e-9 * speed)


def test_move_by_time():
    # theta = 40 rad in T = 0.6 s, T_a = T/3 = 0.2 s, T_j = T_a/2 = 0.1 s:
    # v = theta/(T - T_a) = 40/0.4 = 100 rad/s; a = v/(T_a - T_j) = 100/0.1 = 1000 rad/s^2; j = a/T_j = 1e4
    p = move_by_time(40.0, 0.6, 1.0 / 3.0, 0.5)
    assert p.peak_speed == pytest.approx(100.0, rel=1e-12)
    assert p.peak_accel == pytest.approx(1000.0, rel=1e-12)
    assert p.jerk == pytest.approx(1e4, rel=1e-12)
    assert p.cycle_time == pytest.approx(0.6, rel=1e-12)
    assert sum(ph.angle for ph in p.phases) == pytest.approx(40.0, rel=1e-12)
    # the same move from its limits
    q = scurve(100.0, 1000.0, 1e4, 40.0)
    assert [ph.duration for ph in q.phases] == pytest.approx([ph.duration for ph in p.phases], rel=1e-12)
    # jerk fraction 0: the trapezoid v = 100, a = 100/0.2 = 500
    t = move_by_time(40.0, 0.6)
    assert [ph.duration for ph in t.phases] == pytest.approx([0.2, 0.2, 0.2], rel=1e-12)
    assert t.peak_accel == pytest.approx(500.0, rel=1e-12)


@pytest.mark.parametrize("call, param", [
    (lambda: scurve(100.0, 1000.0, 0.0, 5.0), "jerk"),
    (lambda: scurve(100.0, 1000.0, -1.0, 5.0), "jerk"),
    (lambda: scurve(100.0, 1000.0, math.nan, 5.0), "jerk"),
    (lambda: move_by_time(1.0, 0.0), "move_time"),
    (lambda: move_by_time(1.0, 1.0, 0.6), "accel_fraction"),
    (lambda: move_by_time(1.0, 1.0, 0.3, 0.7), "jerk_fraction"),
])
def test_bad_scurve_inputs(call, param):
    with pytest.raises(InputError) as exc:
        call()
    assert exc.value.param == param
