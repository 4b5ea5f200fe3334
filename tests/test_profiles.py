"""Tests of beltcalc.profiles: trapezoidal and triangular moves (Wojtkowiak et al. 2021, Fig. 9-12).

All quantities at the motor shaft, SI: rad, rad/s, rad/s^2, s. The area under the speed
curve is the stroke; the phases follow one another without a jump in speed.
"""

import math

import pytest
from hypothesis import given, strategies as st

from beltcalc.errors import InputError
from beltcalc.profiles import trapezoid


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
    assert str(exc.value).startswith(f"--{param}: ")
    assert unit in str(exc.value)
