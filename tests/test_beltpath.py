"""The belt path around circles and the eccentric tension roller (issue 15, geometry): the loop
length against the exact open-belt formula and against a direct construction (points on the
tangents and arcs, summed as chords), its gradient against finite differences, and the
roller's ratio U12 against a finite difference of the kinematic constraint."""

from __future__ import annotations

import math

import numpy as np
import pytest

from beltcalc.errors import InputError
from beltcalc.formulas.geometry import belt_pitch_length
from beltcalc.sim.elements.beltpath import Circle, Eccentric, eccentric_ratio, loop

# a sewing-machine-sized drive: motor pulley r1, rim r2 = 1.375 r1 (the paper's U12), the roller
# under the slack span, its pivot 2 mm eccentric
GEO = Eccentric(r1=0.02, r2=0.0275, a=0.30, r3=0.015, px=0.15, py=-0.030, delta=0.002)


def polygon_length(lp, points: int = 4000) -> float:
    """The loop as a polygon: points along every span and arc (in its wrap direction), chords
    summed; converges to the length as O(1/points^2)."""
    pts = []
    for k, c in enumerate(lp.circles):
        sp = lp.spans[k]
        pts += [sp.start + (sp.end - sp.start) * s for s in np.linspace(0.0, 1.0, 3)[:-1]]
        nxt = lp.circles[(k + 1) % len(lp.circles)]
        arrive = sp.end - nxt.center
        a0 = math.atan2(arrive[1], arrive[0])
        sign = 1.0 if nxt.rho > 0 else -1.0
        wrap = lp.wraps[(k + 1) % len(lp.circles)]
        for s in np.linspace(0.0, 1.0, points)[:-1]:
            ang = a0 + sign * wrap * s
            pts.append(nxt.center + abs(nxt.rho) * np.array([math.cos(ang), math.sin(ang)]))
    pts.append(pts[0])
    pts = np.array(pts)
    return float(np.sum(np.hypot(*np.diff(pts, axis=0).T)))


@pytest.mark.parametrize("d1, d2, a", [(0.1273, 0.1273, 1.245), (0.1, 0.3, 0.5), (0.04, 0.055, 0.3)])
def test_two_pulleys_give_the_exact_open_belt_length(d1, d2, a):
    lp = loop([Circle(0.0, 0.0, d1 / 2), Circle(a, 0.0, d2 / 2)])
    assert lp.length == pytest.approx(belt_pitch_length(d1, d2, a), rel=1e-14)
    assert sum(lp.wraps) == pytest.approx(2 * math.pi, rel=1e-14)


@pytest.mark.parametrize("theta", [0.0, 1.0, 2.5, 4.0, 5.5])
def test_loop_length_by_polygon_and_arcs(theta):
    lp = GEO.path(theta)
    assert polygon_length(lp) == pytest.approx(lp.length, rel=1e-7)
    # the roller is wrapped on the belt's back: its wrap is below half a turn, the pulleys' above
    assert 0 < lp.wraps[1] < math.pi and lp.wraps[0] > math.pi / 2


def test_length_gradient_is_u_in_minus_u_out():
    lp = GEO.path(0.7)
    h = 1e-7
    for k, c in enumerate(lp.circles):
        for axis in range(2):
            moved = list(lp.circles)
            shift = np.zeros(2)
            shift[axis] = h
            plus = Circle(c.x + shift[0], c.y + shift[1], c.rho)
            minus = Circle(c.x - shift[0], c.y - shift[1], c.rho)
            moved[k] = plus
            lp_p = loop(moved)
            moved[k] = minus
            lp_m = loop(moved)
            assert (lp_p.length - lp_m.length) / (2 * h) == pytest.approx(lp.gradient(k)[axis], abs=1e-7)


def test_length_rate_against_finite_differences_and_the_wrap_bound():
    for theta in np.linspace(0.0, 2 * math.pi, 9):
        h = 1e-6
        fd = (GEO.length(theta + h) - GEO.length(theta - h)) / (2 * h)
        assert GEO.length_rate(theta) == pytest.approx(fd, abs=1e-9)
    # |dL/dtheta| <= delta |u_in - u_out| = 2 delta sin(beta / 2), beta the roller's wrap
    beta = GEO.path(0.0).wraps[1]
    rates = [abs(GEO.length_rate(t)) for t in np.linspace(0.0, 2 * math.pi, 721)]
    assert max(rates) == pytest.approx(2 * GEO.delta * math.sin(beta / 2), rel=0.05)


def test_ratio_without_eccentricity_is_the_pulley_ratio():
    plain = Eccentric(**{**GEO.__dict__, "delta": 0.0})
    for theta in (0.0, 1.0, 3.0):
        assert eccentric_ratio(plain, theta) == pytest.approx(1.375, rel=1e-15)


def test_ratio_is_the_kinematic_constraint():
    # the transmitted force k (2 x - delta) held constant along a motion: x = r1 phi1 - r2 phi2,
    # delta = L(theta(phi1)) - L(theta0); a small step in phi1 and the phi2 that keeps it gives
    # phidot1 / phidot2
    phi1, h = 0.3, 1e-6
    theta = GEO.theta(phi1)

    def phi2_for(p1):
        delta = GEO.length(GEO.theta(p1)) - GEO.length(GEO.theta0)
        return (GEO.r1 * p1 - delta / 2) / GEO.r2      # 2 x - delta = 0

    ratio = 2 * h / (phi2_for(phi1 + h) - phi2_for(phi1 - h))
    assert eccentric_ratio(GEO, theta) == pytest.approx(ratio, rel=1e-8)
    # the ripple about r2/r1: to first order in delta, (r2/r1) (1 -+ delta sin(beta/2) / r3)
    values = [eccentric_ratio(GEO, t) for t in np.linspace(0.0, 2 * math.pi, 721)]
    beta = GEO.path(0.0).wraps[1]
    ripple = GEO.delta * math.sin(beta / 2) / GEO.r3
    assert max(values) / 1.375 - 1 == pytest.approx(ripple, rel=0.15)
    assert 1 - min(values) / 1.375 == pytest.approx(ripple, rel=0.15)


def test_overlapping_circles_have_no_span():
    with pytest.raises(InputError, match="no belt span"):
        loop([Circle(0.0, 0.0, 0.1), Circle(0.05, 0.0, -0.1)])
