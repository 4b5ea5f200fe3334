"""Tests of beltcalc.formulas.screw: eq. (13) of Wojtkowiak et al. 2021 and the VDI 2230 head term."""

import math

import pytest

from beltcalc.errors import InputError
from beltcalc.formulas.screw import bolt_torque, friction_angle, lead_angle


def test_paper_example_m10x1():
    # Section 3.2: M10x1, d2 = 9.35 mm, P = 1 mm, mu = 0.2, F = 505.1 N:
    # gamma = atan(1 / (pi 9.35)) = 1.95 deg; rho' = atan(0.2 / cos 30) = 13.0 deg; T = 0.63 N m
    bt = bolt_torque(505.1, 0.001, 0.00935, 0.2)
    assert math.degrees(bt.lead_angle) == pytest.approx(1.95, abs=0.01)
    assert math.degrees(bt.friction_angle) == pytest.approx(13.0, abs=0.01)
    assert bt.torque == pytest.approx(0.63, abs=0.005)
    assert bt.bearing_torque == 0.0


def test_m8_coarse_with_head_friction_by_hand():
    # M8 (P 1.25, d2 7.188 mm), mu 0.15, F = 1000 N:
    # gamma = atan(1.25 / (pi 7.188)) = 3.16834 deg; rho' = atan(0.15 / 0.866025) = 9.82643 deg;
    # T_thread = 0.5 * 1000 * 0.007188 * tan(12.99477 deg) = 3.594 * 0.230773 = 0.829395 N m;
    # VDI 2230 head term, mu_K 0.15, D_Km 12 mm: 1000 * 0.15 * 0.012 / 2 = 0.9 N m
    bt = bolt_torque(1000.0, 0.00125, 0.007188, 0.15, bearing_friction=0.15, bearing_diameter=0.012)
    assert math.degrees(bt.lead_angle) == pytest.approx(3.16834, abs=1e-5)
    assert math.degrees(bt.friction_angle) == pytest.approx(9.82643, abs=1e-5)
    assert bt.thread_torque == pytest.approx(0.829395, rel=1e-5)
    assert bt.bearing_torque == pytest.approx(0.9, rel=1e-12)
    assert bt.torque == pytest.approx(1.729395, rel=1e-5)


def test_vdi2230_approximation_agrees():
    # VDI 2230 thread term 0.16 P + 0.58 d2 mu is the small-angle form of eq. 13: within 2 %
    for mu in (0.08, 0.12, 0.2):
        exact = bolt_torque(1.0, 0.0015, 0.009026, mu).thread_torque
        assert exact == pytest.approx(0.16 * 0.0015 + 0.58 * 0.009026 * mu, rel=0.02)


def test_self_locking_limit():
    # gamma + rho' >= 90 deg: the thread cannot be turned
    with pytest.raises(InputError, match="90 deg") as exc:
        bolt_torque(100.0, 0.1, 0.009, 0.99)
    assert exc.value.param == "mu"


@pytest.mark.parametrize("mu", [0.0, 1.0, -0.1, 1.5, math.nan])
def test_friction_outside_open_unit_interval(mu):
    with pytest.raises(InputError, match=r"in \(0, 1\)"):
        friction_angle(mu)


def test_lead_angle_positive_inputs():
    with pytest.raises(InputError):
        lead_angle(0.0, 0.009)
