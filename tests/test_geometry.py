"""Tests of beltcalc.formulas.geometry: open-belt length, centre-distance back-solve, wrap, spans, linear axis."""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from beltcalc.formulas import geometry as geo
from beltcalc.errors import InputError


def path_length_numeric(d1: float, d2: float, a: float, n: int = 200_000) -> float:
    """Length of the belt path built from its tangent points and measured as a polyline.

    Independent of eq. (17-1): the outer common tangents of two circles (centres (0, 0) and
    (a, 0), radii r1 <= r2) are found from the unit normal n with n . (c2 - c1) = r1 - r2...
    here solved as: the tangent direction makes angle phi with the axis, sin(phi) = (r2 - r1)/a;
    the tangent points are c_i + r_i n with n = (-sin(phi), cos(phi)) rotated for each side. The
    arcs are sampled and summed as chords.
    """
    r1, r2 = d1 / 2, d2 / 2
    phi = math.asin((r2 - r1) / a)
    # upper tangent: normal (−sin phi, cos phi); lower tangent mirrored
    n_up = np.array([-math.sin(phi), math.cos(phi)])
    n_lo = np.array([-math.sin(phi), -math.cos(phi)])
    c1, c2 = np.array([0.0, 0.0]), np.array([a, 0.0])
    # arc on the large pulley from the upper to the lower tangent point, the long way round the outside
    t_start = math.atan2(n_up[1], n_up[0])
    t_end = math.atan2(n_lo[1], n_lo[0])
    sweep2 = (t_start - t_end) % (2 * math.pi)          # clockwise via angle 0 (outside, +x side)
    th = t_start - np.linspace(0.0, sweep2, n)
    arc2 = c2 + r2 * np.column_stack([np.cos(th), np.sin(th)])
    sweep1 = 2 * math.pi - sweep2                         # the small pulley wraps the rest
    th1 = t_end - np.linspace(0.0, sweep1, n)
    arc1 = c1 + r1 * np.column_stack([np.cos(th1), np.sin(th1)])
    path = np.vstack([arc2, arc1, arc2[:1]])
    return float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))


@pytest.mark.parametrize("d1, d2, a", [(0.1, 0.1, 0.5), (0.1, 0.3, 0.5), (0.03183, 0.06366, 0.3), (0.05, 0.4, 0.26)])
def test_exact_length_matches_numeric_path(d1, d2, a):
    # polyline of 2 x 200000 chords: relative error ~ (sweep/n)^2 / 24 < 1e-11
    assert geo.belt_pitch_length(d1, d2, a) == pytest.approx(path_length_numeric(d1, d2, a), rel=1e-9)


def test_equal_pulleys_by_hand():
    # 2 a + pi d: 2 * 1.245 + pi * 0.127324 = 2.490 + 0.4 = 2.89 m (40 teeth AT10 = 400 mm of arc)
    d = 40 * 0.010 / math.pi
    assert geo.belt_pitch_length(d, d, 1.245) == pytest.approx(2.89, rel=1e-14)
    assert geo.wrap_angles(d, d, 1.245) == pytest.approx((math.pi, math.pi), rel=1e-15)
    assert geo.span_length(d, d, 1.245) == pytest.approx(1.245, rel=1e-15)


def test_wrap_and_span_by_hand():
    # d1 = 0.1, d2 = 0.3, a = 0.5: sin(beta) = 0.2, beta = 0.2013579 rad;
    # wrap 180 -/+ 23.0739 deg; span = sqrt(0.25 - 0.01) = 0.4898979
    a1, a2 = geo.wrap_angles(0.1, 0.3, 0.5)
    assert math.degrees(a1) == pytest.approx(180 - 2 * math.degrees(math.asin(0.2)), rel=1e-14)
    assert a1 + a2 == pytest.approx(2 * math.pi, rel=1e-15)
    assert geo.span_length(0.1, 0.3, 0.5) == pytest.approx(math.sqrt(0.24), rel=1e-14)


def test_shigley_open_belt_worked_example():
    # Shigley's Mechanical Engineering Design (Budynas & Nisbett), solutions manual, chapter 17,
    # Problem 17-4(b): d = 6 in, D = 18 in, C = 96 in; eq. (17-1): theta_d = 3.016 511 rad,
    # theta_D = 3.266 674 rad; eq. (17-2): L = 230.074 in (printed to 6-7 digits)
    inch = 0.0254
    d, D, C = 6 * inch, 18 * inch, 96 * inch
    assert geo.wrap_angles(d, D, C) == pytest.approx((3.016511, 3.266674), abs=5e-7)
    assert geo.belt_pitch_length(d, D, C) / inch == pytest.approx(230.074, abs=5e-4)
    # and back: the centre distance for that belt is the 96 in again
    assert geo.center_distance_for_length(d, D, geo.belt_pitch_length(d, D, C)) / inch == pytest.approx(96, rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(d1=st.floats(0.005, 0.5), ratio=st.floats(1.0, 8.0), gap=st.floats(1.001, 20.0))
def test_center_distance_round_trip(d1, ratio, gap):
    d2 = d1 * ratio
    a = gap * (d1 + d2) / 2
    length = geo.belt_pitch_length(d1, d2, a)
    back = geo.center_distance_for_length(d1, d2, length)
    assert back == pytest.approx(a, rel=1e-12)
    assert geo.belt_pitch_length(d1, d2, back) == pytest.approx(length, rel=1e-13)


def test_approximate_formula_is_close_for_small_angles_and_not_exact():
    # Tsubaki's L = 2C + 1.57(D + d) + (D - d)^2 / (4C) drops O(beta^4): at beta = 0.2 rad the
    # centre distance differs by a few 1e-5 relative; the exact back-solve is 1e-15.
    length = geo.belt_pitch_length(0.1, 0.3, 0.5)
    approx = geo.center_distance_approx(0.1, 0.3, length)
    assert approx == pytest.approx(0.5, rel=2e-4)
    assert abs(approx - 0.5) > 1e-6
    assert geo.center_distance_for_length(0.1, 0.3, length) == pytest.approx(0.5, rel=1e-14)


def test_too_short_belt_and_overlapping_pulleys_are_input_errors():
    with pytest.raises(InputError) as exc:
        geo.center_distance_for_length(0.1, 0.3, 0.5)
    assert exc.value.param == "belt_length"
    with pytest.raises(InputError) as exc:
        geo.belt_pitch_length(0.1, 0.3, 0.15)
    assert exc.value.param == "center_distance"


def test_nearest_stock_teeth():
    assert geo.nearest_stock_teeth(288.4) == (288, 289)
    assert geo.nearest_stock_teeth(289.0) == (289, 289)
    assert geo.nearest_stock_teeth(120.0, (100, 125, 150)) == (100, 125)
    assert geo.nearest_stock_teeth(90.0, (100, 125)) == (None, 100)


def test_linear_axis_by_hand():
    # a = 1245, d = 127.324 (40 x 10 mm / pi), carriage 200, stroke 800, clamps 50 mm each:
    # pitch length 2490 + 400 - 200 = 2690 mm; cut 2790 mm; free travel 1045 mm;
    # spans at a stroke end (1045 - 800) / 2 = 122.5 mm and 922.5 mm
    g = geo.linear_axis_geometry(1.245, 0.4 / math.pi, 0.2, 0.8, 0.05)
    assert (g.pitch_length, g.belt_length, g.free_travel) == pytest.approx((2.69, 2.79, 1.045), rel=1e-14)
    assert (g.span_min, g.span_max, g.return_span) == pytest.approx((0.1225, 0.9225, 1.245), rel=1e-12)
    # span lengths plus carriage give the centre distance at both ends of the stroke
    assert g.span_min + g.span_max + 0.2 == pytest.approx(1.245, rel=1e-14)
    with pytest.raises(InputError):
        geo.linear_axis_geometry(1.245, 0.127, 0.2, 1.1, 0.05)   # stroke longer than the free travel
