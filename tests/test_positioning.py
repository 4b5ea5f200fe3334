"""Static positioning error of a belt-driven linear axis (beltcalc.design.positioning).

References: the span stiffness C_spec / L and the WDU worked example of Wojtkowiak et al. 2021
[W21 eq. 12, 16]; the error components of BRECOflex's "Timing Belt Repeatability for Linear
Drives" (2023); the linear-drive pretension rule F_TV >= F_U of the Elatech catalogue p. 55.
No maker's printed example of the positioning error itself was found (see docs/positioning.md):
the published numbers checked here are W21's, the rest are closed forms written out by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from beltcalc.design import positioning as pos
from beltcalc.errors import InputError

# Wojtkowiak et al. 2021, section 3.2 (the WDU axis): AT10 belt 25 mm wide, C_spec from the
# BRECO AT10 table the paper prints (Fig. 6), centre distance 1245 mm, pulley D = 128 mm (Fig. 7).
C_SPEC = 5.5e5          # N
A = 1.245               # m
D = 0.128               # m
F_PEAK = 505.1          # N, the paper's F_t,peak
X_PRINTED = 1.14e-3     # m, the paper's x_max (it rounds up to 1.15 mm for the tensioner)


def test_published_example_one_span_stretch_is_w21s_pretension_displacement():
    # W21 eq. 16: k_TB = C_spec / a = 5.5e5 / 1.245 = 441767 N/m; eq. 12: x = F / k_TB
    # = 505.1 * 1.245 / 5.5e5 = 628.85 / 5.5e5 = 1.1434e-3 m, printed 1.14 mm.
    hand = 505.1 * 1.245 / 5.5e5
    assert hand == pytest.approx(1.14336e-3, rel=1e-5)
    # one span: the other span so long that it adds nothing (1e12 m: 1e-12 relative)
    e = pos.static_error(F_PEAK, C_SPEC, A, 1e12)
    assert e.stretch == pytest.approx(hand, rel=1e-9)
    assert e.span_stiffness == pytest.approx(C_SPEC / A, rel=1e-9)
    assert e.stretch == pytest.approx(X_PRINTED, abs=0.005e-3)      # to the paper's printed rounding


def test_wdu_axis_two_spans_by_hand():
    # the WDU carriage 0.5 m from the drive pulley, holding F = m a_max = 50 kg * 10 m/s^2 = 500 N
    # L2 = 2 a - L1 + pi D / 2 = 2.490 - 0.5 + 0.201062 = 2.191062 m
    # k  = C (1/L1 + 1/L2) = 5.5e5 * (2 + 0.456400) = 1.351020e6 N/m
    # x  = 500 / 1.351020e6 = 0.370088 mm
    # span 1 takes F L2 / (L1 + L2) = 500 * 2.191062 / 2.691062 = 407.100 N, span 2 gives up 92.900 N
    l1, l2 = pos.span_lengths(A, D, 0.5)
    assert (l1, l2) == pytest.approx((0.5, 2.191062), abs=1e-6)
    e = pos.static_error(500.0, C_SPEC, l1, l2)
    assert e.span_stiffness == pytest.approx(1.351020e6, rel=1e-6)
    assert e.stretch == pytest.approx(0.370088e-3, rel=1e-5)
    assert (e.tension_change1, e.tension_change2) == pytest.approx((407.100, -92.900), abs=1e-3)
    assert e.min_pretension == pytest.approx(92.900, abs=1e-3)
    assert pos.min_pretension(500.0, l1, l2) == pytest.approx(407.100, abs=1e-3)   # either way


def test_two_spring_closed_form_over_positions():
    # x(L1) = F L1 L2 / (C (L1 + L2)), the two spans in parallel
    x = np.linspace(0.01, A, 57)
    l2 = 2 * A - x + math.pi * D / 2
    s = pos.along_stroke(-300.0, C_SPEC, A, D, x)
    np.testing.assert_allclose(s.stretch, 300.0 * x * l2 / (C_SPEC * (x + l2)), rtol=1e-12)
    np.testing.assert_allclose(s.span_stiffness, C_SPEC / x + C_SPEC / l2, rtol=1e-12)
    np.testing.assert_allclose(s.min_pretension, 300.0 * np.maximum(x, l2) / (x + l2), rtol=1e-12)
    one = [pos.static_error(-300.0, C_SPEC, float(a), float(b)).stretch for a, b in zip(x, l2)]
    np.testing.assert_allclose(s.stretch, one, rtol=1e-12)


def test_the_stiffness_is_the_simulators_two_path_stiffness():
    from beltcalc.sim.scenes.linear_axis import span_stiffness

    for where in (0.05, 0.4, 1.0, A):
        l1, l2 = pos.span_lengths(A, D, where)
        assert pos.span_pair_stiffness(C_SPEC, l1, l2) == pytest.approx(span_stiffness(C_SPEC, A, D, where), rel=1e-12)


def test_equal_spans():
    # L1 = L2 = L: k = 2 C / L, x = F L / (2 C), each span takes half the force
    e = pos.static_error(400.0, 1e5, 0.8, 0.8)
    assert e.span_stiffness == pytest.approx(2 * 1e5 / 0.8, rel=1e-12)
    assert e.stretch == pytest.approx(400.0 * 0.8 / 2e5, rel=1e-12)
    assert (e.tension_change1, e.tension_change2) == pytest.approx((200.0, -200.0), rel=1e-12)
    assert pos.min_pretension(-400.0, 0.8, 0.8) == pytest.approx(200.0, rel=1e-12)


def test_carriage_at_a_pulley_needs_the_makers_pretension_rule():
    # L1 -> 0: span 1 takes the whole force, so a reversing force needs F_TV = F_U [Elatech p. 55]
    assert pos.min_pretension(500.0, 1e-9, 2.5) == pytest.approx(500.0, rel=1e-8)
    # elsewhere the share is max(L1, L2) / (L1 + L2), from 1/2 (equal spans) up to the rule's 1
    l1 = np.linspace(0.01, 1.99, 21)
    shares = [pos.min_pretension(1.0, a, 2.0 - a) for a in l1]
    np.testing.assert_allclose(shares, np.maximum(l1, 2.0 - l1) / 2.0, rtol=1e-12)
    assert pos.min_pretension(1.0, 1.0, 1.0) == pytest.approx(0.5, rel=1e-12)


def test_zero_force_is_no_error():
    e = pos.static_error(0.0, C_SPEC, 0.3, 2.0)
    assert (e.stretch, e.total, e.min_pretension) == pytest.approx((0.0, 0.0, 0.0), abs=0)


def test_tooth_backlash_and_tolerance_terms():
    # hypothetical data (no maker's tooth stiffness was found): c_t = 2e6 N/m per tooth, z_e = 12,
    # backlash 0.05 mm, length tolerance 0.1 mm/m over 0.5 m of travel [BRECOflex 2023]: 0.05 mm
    l1, l2 = 0.5, 2.0
    k_s = C_SPEC * (1 / l1 + 1 / l2)                       # 1.375e6 N/m
    e = pos.static_error(500.0, C_SPEC, l1, l2, tooth_stiffness=2e6, teeth_in_mesh=12,
                         backlash=0.05e-3, length_tolerance=1e-4 * 0.5)
    stretch, tooth = 500.0 / k_s, 500.0 / 24e6             # 0.363636 mm, 0.020833 mm
    assert (e.stretch, e.tooth) == pytest.approx((stretch, tooth), rel=1e-12)
    assert e.mesh_stiffness == pytest.approx(24e6, rel=1e-12)
    assert e.stiffness == pytest.approx(1 / (1 / k_s + 1 / 24e6), rel=1e-12)   # in series
    assert 500.0 / e.stiffness == pytest.approx(stretch + tooth, rel=1e-12)
    assert e.total == pytest.approx(stretch + tooth + 0.1e-3, rel=1e-12)
    assert e.rss == pytest.approx(math.sqrt(stretch ** 2 + tooth ** 2 + 2 * 0.05e-3 ** 2), rel=1e-12)


def test_worst_position_in_closed_form_against_a_dense_stroke():
    # compliance L1 (Lt - L1) / (C Lt) peaks at Lt / 2 = a + pi D / 4, beyond the idler: on any
    # stroke inside the axis the worst place is the end farthest from the drive pulley
    assert pos.worst_position(A, D, 0.1, 1.1) == pytest.approx(1.1, abs=0)
    assert pos.worst_position(A, D, 1.1, 0.1) == pytest.approx(1.1, abs=0)
    dense = pos.along_stroke(500.0, C_SPEC, A, D, np.linspace(0.1, 1.1, 2001), backlash=0.02e-3)
    assert dense.worst.total == pytest.approx(float(dense.total.max()), rel=1e-12)
    assert dense.worst.span1 == pytest.approx(float(dense.positions[np.argmax(dense.total)]), abs=1e-12)
    # the pretension for a reversing force is largest at the end nearest a pulley (here L1 = 0.1 m)
    assert dense.least_pretension == pytest.approx(float(dense.min_pretension.max()), rel=1e-12)


@pytest.mark.parametrize("call, param", [
    (lambda: pos.static_error(500.0, C_SPEC, 0.0, 2.0), "span1"),
    (lambda: pos.static_error(500.0, C_SPEC, 0.5, -1.0), "span2"),
    (lambda: pos.static_error(500.0, 0.0, 0.5, 2.0), "specific_stiffness"),
    (lambda: pos.static_error(math.nan, C_SPEC, 0.5, 2.0), "force"),
    (lambda: pos.static_error(500.0, C_SPEC, 0.5, 2.0, backlash=-1e-5), "backlash"),
    (lambda: pos.static_error(500.0, C_SPEC, 0.5, 2.0, tooth_stiffness=1e6), "teeth_in_mesh"),
    (lambda: pos.static_error(500.0, C_SPEC, 0.5, 2.0, teeth_in_mesh=6), "tooth_stiffness"),
    (lambda: pos.static_error(500.0, C_SPEC, 0.5, 2.0, tooth_stiffness=0.0, teeth_in_mesh=6), "tooth_stiffness"),
    (lambda: pos.span_lengths(A, D, 0.0), "position"),
    (lambda: pos.span_lengths(A, D, 1.3), "position"),
    (lambda: pos.span_lengths(-1.0, D, 0.5), "center_distance"),
    (lambda: pos.along_stroke(500.0, C_SPEC, A, 0.0, [0.5]), "pulley_diameter"),
    (lambda: pos.along_stroke(500.0, C_SPEC, A, D, []), "positions"),
])
def test_bad_input_names_the_parameter(call, param):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.param == param


def test_a_force_that_slackens_a_span_is_refused():
    # carriage at L1 = 0.5, L2 = 2.0: pushing it 500 N towards the drive pulley relieves span 1
    # by 500 * 2.0 / 2.5 = 400 N; 300 N of pretension is not enough, 400 N is
    with pytest.raises(InputError) as err:
        pos.static_error(-500.0, C_SPEC, 0.5, 2.0, pretension=300.0)
    assert err.value.param == "pretension"
    assert "span 1" in str(err.value) and "400 N" in str(err.value) and "force" in str(err.value)
    e = pos.static_error(-500.0, C_SPEC, 0.5, 2.0, pretension=400.0)
    assert e.tension_change1 == pytest.approx(-400.0, rel=1e-12)
    # pulling it away relieves span 2 by only 500 * 0.5 / 2.5 = 100 N
    assert pos.static_error(500.0, C_SPEC, 0.5, 2.0, pretension=300.0).tension_change2 == pytest.approx(-100.0)
    # along the stroke: near the drive pulley span 1 takes almost all of a push
    with pytest.raises(InputError) as err:
        pos.along_stroke(-500.0, C_SPEC, A, D, [1.0, 0.6, 0.05], pretension=450.0)
    assert err.value.param == "pretension" and "span1 = 0.05 m" in str(err.value)
