"""Tests of beltcalc.formulas.drive: reflected inertia, losses and motor torque of a belt axis.

References: Wojtkowiak et al., Energies 14 (2021) 317, eq. 17-29 and Fig. 13-15 ("the
paper"); A. Crowder, Electric Drives and Electromechanical Systems, eq. 3.21-3.27.
The paper prints ``(m_TB + m) D / 4`` for the reflected mass and ``F_R D`` for the
resistance torque; Crowder's ``M D^2 / 4`` and ``D F / 2`` are right (DESIGN.md 2.5).
"""

import math

import numpy as np
import pint
import pytest
from numpy.testing import assert_allclose

from beltcalc.formulas.drive import G0, BeltAxis, cylinder_inertia, duty, motor_damping
from beltcalc.errors import InputError
from beltcalc.formulas.profiles import trapezoid
from beltcalc.design.sizing import energy_eq29_closed_form
from beltcalc.units import ureg

RPM = 2 * math.pi / 60


def crowder_axis(**kw) -> BeltAxis:
    """M = 8 kg carriage + 0.5 kg belt, D = 60 mm, I_p1 = 4e-5, I_p2 = 1e-4, I_RL = 2e-4 kg m^2, n = 2."""
    args = dict(mass=8.0, substitute_mass=0.5, pulley_diameter=0.06, pulley_inertia=4e-5,
                idler_inertia=1e-4, load_inertia=2e-4, belt_ratio=2.0)
    args.update(kw)
    return BeltAxis(**args)


# The same axis behind a 4:1 gearbox (J_G = 3e-5 at the motor, J_C = 1e-5 on the pulley shaft),
# with losses: b_B = 0.001 N m s/rad per pulley shaft, b_LG = 20 N s/m, F_R = 30 N, mu = 0.003.
GEARED = dict(gear_ratio=4.0, gearbox_inertia=3e-5, coupling_inertia=1e-5, bearing_damping=0.001,
              guide_damping=20.0, resistance=30.0, guide_friction=0.003)
B_MOTOR = 2e-4  # N m s/rad

# Hand values of the geared axis (used by several tests):
# J = 3e-5 + (1e-5 + 7.765e-3)/16 = 3e-5 + 4.859375e-4 = 5.159375e-4 kg m^2 (see test_gear_ratio)
J_GEARED = 5.159375e-4
# b = 2e-4 + (0.001 (1 + 1/4) + 20 * 0.06^2/4)/16 = 2e-4 + (0.00125 + 0.018)/16 = 2e-4 + 1.203125e-3
B_GEARED = 1.403125e-3
# T_R = (30 + 0.003 * 8 * 9.80665) * 0.06/(2*4) = (30 + 0.2353596) * 0.0075 = 30.2353596 * 0.0075
T_R_GEARED = 0.226765197


# --- reflected inertia, damping, resistance --------------------------------------------

def test_crowder_reflected_inertia_with_belt_ratio():
    ax = crowder_axis()
    # Crowder eq. 3.22: I_L = M D^2/4 = (8 + 0.5) * 0.06^2/4 = 8.5 * 0.0009 = 7.65e-3 kg m^2
    #   (carriage 8 * 0.0009 = 7.2e-3, belt 0.5 * 0.0009 = 4.5e-4)
    # eq. 3.27: (I_RL + I_p2)/n^2 = (2e-4 + 1e-4)/2^2 = 7.5e-5 kg m^2
    # I_tot = I_p1 + I_L + (I_RL + I_p2)/n^2 = 4e-5 + 7.65e-3 + 7.5e-5 = 7.765e-3 kg m^2
    parts = ax.inertia_parts()
    assert parts["carriage"] == pytest.approx(7.2e-3, rel=1e-12)
    assert parts["belt"] == pytest.approx(4.5e-4, rel=1e-12)
    assert parts["pulleys"] == pytest.approx(4e-5 + 1e-4 / 4, rel=1e-12)      # 6.5e-5
    assert parts["rotating load"] == pytest.approx(5e-5, rel=1e-12)          # 2e-4 / 4
    assert parts["gearbox"] == pytest.approx(0.0, abs=1e-15)
    assert parts["coupling"] == pytest.approx(0.0, abs=1e-15)
    assert ax.load_inertia_total == pytest.approx(7.765e-3, rel=1e-12)


def test_gear_ratio_divides_everything_on_the_pulley_side_by_i_squared():
    ax = crowder_axis(gear_ratio=4.0, gearbox_inertia=3e-5, coupling_inertia=1e-5)
    # pulley side: J_C + I_tot = 1e-5 + 7.765e-3 = 7.775e-3 kg m^2, seen through i = 4: / 16
    #   = 4.859375e-4; the gearbox inertia is already at the motor: + 3e-5 -> 5.159375e-4 kg m^2
    parts = ax.inertia_parts()
    assert parts["gearbox"] == pytest.approx(3e-5, rel=1e-12)
    assert parts["coupling"] == pytest.approx(1e-5 / 16, rel=1e-12)           # 6.25e-7
    assert parts["carriage"] == pytest.approx(7.2e-3 / 16, rel=1e-12)         # 4.5e-4
    assert parts["belt"] == pytest.approx(4.5e-4 / 16, rel=1e-12)             # 2.8125e-5
    assert parts["pulleys"] == pytest.approx(6.5e-5 / 16, rel=1e-12)          # 4.0625e-6
    assert parts["rotating load"] == pytest.approx(5e-5 / 16, rel=1e-12)      # 3.125e-6
    assert ax.load_inertia_total == pytest.approx(J_GEARED, rel=1e-12)
    # carriage speed per motor radian: D/(2 i) = 0.06/8 = 0.0075 m/rad; 0.5 m -> 0.5/0.0075 = 66.667 rad
    assert ax.carriage_per_motor() == pytest.approx(0.0075, rel=1e-12)
    assert ax.motor_angle(0.5) == pytest.approx(66.666667, rel=1e-8)


def test_damping_with_belt_and_gear_ratio():
    ax = crowder_axis(**GEARED)
    assert ax.damping(B_MOTOR) == pytest.approx(B_GEARED, rel=1e-12)
    # paper eq. 23 (n = 1, i = 1): b_M + 2 b_B + b_LG D^2/4 = 2e-4 + 0.002 + 20 * 0.0009 = 0.0202
    ax1 = crowder_axis(belt_ratio=1.0, bearing_damping=0.001, guide_damping=20.0)
    assert ax1.damping(2e-4) == pytest.approx(0.0202, rel=1e-12)


def test_guide_friction_and_resistance_torque():
    # guide friction alone: mu m g D/(2 i) = 0.003 * 8 * 9.80665 * 0.06/8 = 0.2353596 * 0.0075
    #   = 1.765197e-3 N m (the belt's substitute mass carries no normal force)
    ax = crowder_axis(gear_ratio=4.0, guide_friction=0.003)
    assert ax.resistance_torque == pytest.approx(1.765197e-3, rel=1e-7)
    assert ax.resistance_torque == pytest.approx(0.003 * 8 * G0 * 0.06 / 8, rel=1e-12)
    # with F_R = 30 N: (30 + 0.2353596) * 0.0075 = 0.226765197 N m
    assert crowder_axis(**GEARED).resistance_torque == pytest.approx(T_R_GEARED, rel=1e-9)
    # direct drive, F_R only: D F/2 = 0.06 * 30/2 = 0.9 N m (Crowder eq. 3.23)
    assert crowder_axis(resistance=30.0).resistance_torque == pytest.approx(0.9, rel=1e-12)


def test_torque_of_a_constant_acceleration_phase():
    ax = crowder_axis(**GEARED)
    J, b, tr = ax.load_inertia_total, ax.damping(B_MOTOR), ax.resistance_torque
    # 200 rad/s at 4000 rad/s^2 over 0.5 m = 66.667 rad: omega^2/eps = 10 rad < 66.667, a trapezoid,
    # t_a = 200/4000 = 0.05 s, t_c = (66.667 - 10)/200 = 0.283333 s
    d = duty(trapezoid(200.0, 4000.0, ax.motor_angle(0.5)), J, b, tr)
    acc, cru, dec = d.phases
    # accelerate: T = J eps + b omega + F D/2: start 5.159375e-4 * 4000 + 0 + 0.226765197
    #   = 2.06375 + 0.226765197 = 2.290515197; end + b omega = 1.403125e-3 * 200 = 0.280625 -> 2.571140197
    assert (acc.torque0, acc.torque1) == pytest.approx((2.290515197, 2.571140197), rel=1e-9)
    # cruise: 0.280625 + 0.226765197 = 0.507390197
    assert (cru.torque0, cru.torque1) == pytest.approx((0.507390197, 0.507390197), rel=1e-9)
    # decelerate: -2.06375 + 0.507390197 = -1.556359803 -> -2.06375 + 0.226765197 = -1.836984803
    assert (dec.torque0, dec.torque1) == pytest.approx((-1.556359803, -1.836984803), rel=1e-9)
    assert acc.duration == pytest.approx(0.05, rel=1e-12)
    assert cru.duration == pytest.approx(0.283333333, rel=1e-8)
    assert d.peak_torque == pytest.approx(2.571140197, rel=1e-9)
    assert d.braking_torque == pytest.approx(-1.836984803, rel=1e-9)
    # peak power at the end of the acceleration: 2.571140197 * 200 = 514.2280394 W
    assert d.peak_power == pytest.approx(514.2280394, rel=1e-9)


# --- the paper's errata, shown with pint ----------------------------------------------

Q = ureg().Quantity
J_Q = Q(5e-4, "kg*m^2")
M_Q = Q(8.0, "kg")
MTB_Q = Q(0.5, "kg")
D_Q = Q(0.06, "m")
EPS_Q = Q(1000.0, "rad/s^2")
F_Q = Q(30.0, "N")


def test_printed_eq18_inertia_is_dimensionally_wrong():
    # eq. 18: J + 1/4 (m_TB + m) D  ->  kg m^2 + kg m: cannot be added
    with pytest.raises(pint.DimensionalityError):
        J_Q + (MTB_Q + M_Q) * D_Q / 4
    with pytest.raises(pint.DimensionalityError):
        J_Q + (MTB_Q + M_Q) * D_Q


def test_printed_eq28_inertia_term_is_dimensionally_wrong():
    # eq. 28: (J + 1/4 (m_TB + m) D) eps + ... + F_R D: the bracket already fails
    with pytest.raises(pint.DimensionalityError):
        (J_Q + (MTB_Q + M_Q) * D_Q / 4) * EPS_Q + F_Q * D_Q


def test_printed_eq23_damping_is_dimensionally_wrong():
    # eq. 23: b_M + 2 b_B + 1/4 b_LG D -> N m s/rad + N s: cannot be added (D^2/4 is right)
    b_m, b_lg = Q(2e-4, "N*m*s/rad"), Q(20.0, "N*s/m")
    with pytest.raises(pint.DimensionalityError):
        b_m + b_lg * D_Q / 4
    right = (b_m + b_lg * D_Q ** 2 / 4).to("N*m*s/rad")
    # 2e-4 + 20 * 0.0009 = 0.0182 N m s/rad
    assert right.magnitude == pytest.approx(0.0182, rel=1e-12)
    assert crowder_axis(belt_ratio=1.0, guide_damping=20.0).damping(2e-4) == pytest.approx(
        right.magnitude, rel=1e-12)


def test_printed_F_R_D_is_a_torque_but_twice_crowders():
    # F_R D has the dimension of a torque, so pint cannot catch it ...
    printed = F_Q * D_Q
    assert printed.dimensionality == Q(1.0, "N*m").dimensionality
    # ... but the virtual work F_R dx = F_R (D/2) dphi gives D F/2 (Crowder 3.23):
    # printed 30 * 0.06 = 1.8 N m, right 0.06 * 30/2 = 0.9 N m
    right = D_Q * F_Q / 2
    assert printed.to("N*m").magnitude == pytest.approx(1.8, rel=1e-12)
    assert right.to("N*m").magnitude == pytest.approx(0.9, rel=1e-12)
    assert (printed / right).to("").magnitude == pytest.approx(2.0, rel=1e-12)
    assert crowder_axis(resistance=30.0).resistance_torque == pytest.approx(0.9, rel=1e-12)


def test_corrected_forms_add_and_match_beltaxis():
    # J_red = J + (m_TB + m) D^2/4 = 5e-4 + 8.5 * 0.0009 = 5e-4 + 7.65e-3 = 8.15e-3 kg m^2
    j_red = (J_Q + (MTB_Q + M_Q) * D_Q ** 2 / 4).to("kg*m^2")
    assert j_red.magnitude == pytest.approx(8.15e-3, rel=1e-12)
    # T = J_red eps + F D/2 = 8.15e-3 * 1000 + 0.9 = 8.15 + 0.9 = 9.05 N m (rad is dimensionless)
    torque = (j_red * EPS_Q + F_Q * D_Q / 2).to("N*m")
    assert torque.magnitude == pytest.approx(9.05, rel=1e-12)
    # BeltAxis with the same numbers (J_P1 = 5e-4 as the only rotating part, n = i = 1)
    ax = BeltAxis(mass=8.0, substitute_mass=0.5, pulley_diameter=0.06, pulley_inertia=5e-4,
                  idler_inertia=0.0, resistance=30.0)
    assert ax.load_inertia_total == pytest.approx(j_red.magnitude, rel=1e-12)
    d = duty(trapezoid(10.0, 1000.0, 1.0), ax.load_inertia_total, ax.damping(), ax.resistance_torque)
    assert d.phases[0].torque0 == pytest.approx(torque.magnitude, rel=1e-12)


# --- Fig. 13: peak torque is linear in the acceleration -----------------------------------

def test_fig13_peak_torque_linear_in_acceleration():
    ax = crowder_axis(**GEARED)
    theta = ax.motor_angle(0.5)  # 66.667 rad
    eps = np.array([1000.0, 2000.0, 3000.0, 4000.0, 5000.0])
    profiles = [trapezoid(200.0, e, theta) for e in eps]
    # omega^2/eps = 40, 20, 13.3, 10, 8 rad, all < 66.667: every move reaches 200 rad/s
    assert not any(p.triangular for p in profiles)
    peaks = np.array([duty(p, J_GEARED, B_GEARED, T_R_GEARED).peak_torque for p in profiles])
    # T_max = J eps + b omega + T_R = 5.159375e-4 eps + 0.280625 + 0.226765197:
    # 1.023327697, 1.539265197, 2.055202697, 2.571140197, 3.087077697 N m
    assert_allclose(peaks, [1.023327697, 1.539265197, 2.055202697, 2.571140197, 3.087077697], rtol=1e-9)
    assert_allclose(np.diff(peaks, 2), 0.0, atol=1e-12)
    assert_allclose(np.diff(peaks) / np.diff(eps), J_GEARED, rtol=1e-9)
    # intercept: the static torque b omega + T_R = 0.507390197 N m
    slope, intercept = np.polyfit(eps, peaks, 1)
    assert (slope, intercept) == pytest.approx((J_GEARED, 0.507390197), rel=1e-8)


def test_fig11_peak_torque_does_not_depend_on_speed_without_damping():
    # the paper: "the value of the peak torque is always the same regardless of the speed";
    # exactly so for b = 0: T_max = J eps + T_R = 5.159375e-4 * 4000 + 0.226765197 = 2.290515197
    peaks = [duty(trapezoid(w, 4000.0, 66.667), J_GEARED, 0.0, T_R_GEARED).peak_torque
             for w in (50.0, 100.0, 150.0, 200.0)]
    assert_allclose(peaks, 2.290515197, rtol=1e-9)


# --- Fig. 14/15: energy of the acceleration phase ----------------------------------------

OMEGA = 200.0


def _energies(eps_values, omega=OMEGA):
    out = []
    for e in eps_values:
        d = duty(trapezoid(omega, e, 1e4), J_GEARED, B_GEARED, T_R_GEARED)
        out.append((d.accel_energy, d.accel_energy_exact, d.accel_time))
    return np.array(out)


def test_fig14_eq29_matches_the_closed_form():
    eps = np.array([50.0, 100.0, 200.0, 500.0, 1000.0, 4000.0, 1e5])
    e29 = _energies(eps)[:, 0]
    closed = [energy_eq29_closed_form(J_GEARED, B_GEARED, T_R_GEARED, OMEGA, e) for e in eps]
    assert_allclose(e29, closed, rtol=1e-12)
    # by hand at eps = 4000: J w^2 = 5.159375e-4 * 40000 = 20.6375 J;
    # (b w + T_R) w^2/eps = 0.507390197 * 40000/4000 = 5.07390197 J -> 25.71140197 J
    assert e29[5] == pytest.approx(25.71140197, rel=1e-9)


def test_fig14_energy_falls_with_acceleration_towards_J_omega_squared():
    eps = np.array([50.0, 100.0, 200.0, 500.0, 1000.0, 4000.0, 1e5, 1e7])
    e29 = _energies(eps)[:, 0]
    assert np.all(np.diff(e29) < 0)
    # E - J w^2 = (b w + T_R) w^2/eps: eps (E - J w^2) = 0.507390197 * 40000 = 20295.60788 J rad/s^2
    j_w2 = J_GEARED * OMEGA ** 2  # 20.6375 J
    assert_allclose(eps * (e29 - j_w2), 20295.60788, rtol=1e-6)
    # so at 1e7 rad/s^2 E is J w^2 + 0.00203 J
    assert e29[-1] == pytest.approx(20.6375 + 20295.60788 / 1e7, rel=1e-12)


def test_exact_energy_integral():
    eps = np.array([100.0, 1000.0, 4000.0, 1e5])
    got = _energies(eps)
    t_a = OMEGA / eps
    # integral_0^t_a (J eps + b eps t + T_R) eps t dt = J w^2/2 + b w^2 t_a/3 + T_R w t_a/2
    want = J_GEARED * OMEGA ** 2 / 2 + B_GEARED * OMEGA ** 2 * t_a / 3 + T_R_GEARED * OMEGA * t_a / 2
    assert_allclose(got[:, 2], t_a, rtol=1e-12)
    assert_allclose(got[:, 1], want, rtol=1e-12)
    # by hand at eps = 4000 (t_a = 0.05 s): 10.31875 + 1.403125e-3 * 40000 * 0.05/3 + 0.226765197 * 200 * 0.025
    #   = 10.31875 + 0.935416667 + 1.133825985 = 12.38799265 J
    assert got[2, 1] == pytest.approx(12.38799265, rel=1e-9)


def test_eq29_is_twice_the_kinetic_energy_for_a_pure_inertia():
    # b = T_R = 0: E29 = T_max w t_a = J eps * w * w/eps = J w^2; exact = J w^2/2 (kinetic energy)
    d = duty(trapezoid(100.0, 500.0, 1e3), 0.01, 0.0, 0.0)
    assert d.accel_energy == pytest.approx(100.0, rel=1e-12)        # 0.01 * 100^2
    assert d.accel_energy_exact == pytest.approx(50.0, rel=1e-12)   # 0.01 * 100^2/2


def test_fig15_energy_grows_nonlinearly_with_speed():
    # constant eps = 1000: E(w) = J w^2 + (b w + T_R) w^2/eps
    # w = 100: 5.159375 + (0.1403125 + 0.226765197) * 10 = 5.159375 + 3.67077697 = 8.83015197 J
    # w = 200: 20.6375 + 0.507390197 * 40 = 20.6375 + 20.29560788 = 40.93310788 J
    ws = [100.0, 200.0]
    got = [duty(trapezoid(w, 1000.0, 1e4), J_GEARED, B_GEARED, T_R_GEARED).accel_energy for w in ws]
    assert got == pytest.approx([8.83015197, 40.93310788], rel=1e-9)


# --- RMS torque, braking, power --------------------------------------------------------

# A small trapezoid: 10 rad/s, 100 rad/s^2, 2 rad, dwell 0.1 s; J = 0.01, b = 0.02, T_R = 0.3.
# t_a = 0.1 s, theta_a = 100/200 = 0.5 rad, t_c = (2 - 1)/10 = 0.1 s, cycle 0.1*3 + 0.1 = 0.4 s.
SMALL = trapezoid(10.0, 100.0, 2.0, dwell=0.1)


def test_rms_torque_by_hand():
    d = duty(SMALL, 0.01, 0.02, 0.3)
    # accelerate: 0.01*100 + 0.3 = 1.3 -> 1.3 + 0.02*10 = 1.5; cruise 0.2 + 0.3 = 0.5;
    # decelerate: -1 + 0.2 + 0.3 = -0.5 -> -1 + 0.3 = -0.7; dwell: 0 (not moving)
    want = [(1.3, 1.5), (0.5, 0.5), (-0.5, -0.7), (0.0, 0.0)]
    for ph, w in zip(d.phases, want):
        assert (ph.torque0, ph.torque1) == pytest.approx(w, abs=1e-12)
    # integral T^2 of a linear piece = tau (T0^2 + T0 T1 + T1^2)/3:
    #   accelerate 0.1 (1.69 + 1.95 + 2.25)/3 = 0.1 * 5.89/3 = 0.19633333
    #   cruise     0.1 * 0.25                   = 0.025
    #   decelerate 0.1 (0.25 + 0.35 + 0.49)/3 = 0.1 * 1.09/3 = 0.03633333
    #   dwell 0; sum (0.589 + 0.075 + 0.109)/3 = 0.773/3 = 0.25766667; / 0.4 s = 0.64416667;
    #   sqrt(0.64416667) = 0.80259994 N m
    assert d.cycle_time == pytest.approx(0.4, rel=1e-12)
    assert d.rms_torque == pytest.approx(0.80259994, rel=1e-8)
    assert d.rms_torque == pytest.approx(math.sqrt(0.773 / 3 / 0.4), rel=1e-12)
    # dense numerical check of the same integral, phase by phase (T is continuous within a phase)
    sq = sum(np.trapezoid(tq ** 2, t) for t, _, tq in _phase_samples(SMALL, 0.01, 0.02, 0.3))
    assert math.sqrt(sq / 0.4) == pytest.approx(d.rms_torque, rel=1e-9)


def test_torque_at():
    d = duty(SMALL, 0.01, 0.02, 0.3)
    # mid-acceleration (t = 0.05): 1.3 + 0.5 * 0.2 = 1.4; cruise 0.5; mid-deceleration
    # (t = 0.25): -0.6; dwell (t = 0.35): 0
    got = [d.torque_at(t) for t in (0.0, 0.05, 0.15, 0.25, 0.35, 0.4)]
    assert got == pytest.approx([1.3, 1.4, 0.5, -0.6, 0.0, 0.0], abs=1e-12)


def _phase_samples(profile, J, b, tr, n=100001):
    """Independent torque and speed samples of each phase: T = J a + b w + T_R (moving)."""
    for ph in profile.phases:
        t = np.linspace(0.0, ph.duration, n)
        w = ph.speed0 + ph.accel * t
        moving = 1.0 if max(ph.speed0, ph.speed1) > 0 else 0.0
        yield t, w, J * ph.accel + b * w + tr * moving


def _numerical_braking_energy(profile, J, b, tr):
    total = 0.0
    for t, w, tq in _phase_samples(profile, J, b, tr):
        total -= np.trapezoid(np.minimum(tq * w, 0.0), t)
    return total


def test_braking_negative_throughout_the_deceleration():
    d = duty(SMALL, 0.01, 0.02, 0.3)
    # decelerate: T = -0.5 - 2 t, w = 10 - 100 t (t in 0..0.1): T w = -5 + 30 t + 200 t^2;
    # integral = -0.5 + 15 * 0.01 + 200/3 * 0.001 = -0.5 + 0.15 + 0.0666667 = -0.2833333 J
    assert d.braking_torque == pytest.approx(-0.7, rel=1e-12)
    assert d.braking_energy == pytest.approx(17 / 60, rel=1e-12)  # 0.28333333 J
    assert d.braking_energy == pytest.approx(_numerical_braking_energy(SMALL, 0.01, 0.02, 0.3), rel=1e-9)


def test_braking_torque_changes_sign_mid_deceleration():
    # J eps = 0.01 * 100 = 1, b w = 0.1 * 10 = 1, T_R = 0.5:
    # decelerate T0 = -1 + 1 + 0.5 = 0.5 -> T1 = -1 + 0 + 0.5 = -0.5, zero at t = 0.05 s
    prof = trapezoid(10.0, 100.0, 2.0)
    d = duty(prof, 0.01, 0.1, 0.5)
    assert (d.phases[2].torque0, d.phases[2].torque1) == pytest.approx((0.5, -0.5), abs=1e-12)
    assert d.braking_torque == pytest.approx(-0.5, rel=1e-12)
    # T = -10 (t - 0.05), w = -100 (t - 0.1): T w = 1000 (t - 0.05)(t - 0.1);
    # integral over 0.05..0.1 (u = t - 0.05, h = 0.05): 1000 (h^3/3 - 0.05 h^2/2)
    #   = 1000 (4.1666667e-5 - 6.25e-5) = -0.0208333 J: 0.0208333 J fed back (= 1/48)
    assert d.braking_energy == pytest.approx(1 / 48, rel=1e-12)
    assert d.braking_energy == pytest.approx(_numerical_braking_energy(prof, 0.01, 0.1, 0.5), rel=1e-9)


def test_braking_with_a_load_pulling_along():
    # T_R < 0 (a load pulling in the direction of motion; duty() accepts it, BeltAxis keeps F_R >= 0)
    prof = trapezoid(10.0, 100.0, 2.0)  # t_a = t_c = 0.1 s
    # T_R = -0.8, b = 0.15: accelerate 1 - 0.8 = 0.2 -> 1 + 1.5 - 0.8 = 1.7 (no braking);
    # cruise 1.5 - 0.8 = 0.7; decelerate T = -0.3 - 15 t, w = 10 - 100 t:
    # T w = -3 - 120 t + 1500 t^2, integral 0..0.1 = -0.3 - 0.6 + 0.5 = -0.4 J -> 0.4 J fed back
    d = duty(prof, 0.01, 0.15, -0.8)
    assert d.braking_energy == pytest.approx(0.4, rel=1e-12)
    assert d.braking_energy == pytest.approx(_numerical_braking_energy(prof, 0.01, 0.15, -0.8), rel=1e-9)
    # T_R = -2: accelerate T = -1 + 15 t (negative until t = 1/15 s, changes sign mid-phase), w = 100 t:
    #   integral 0..1/15 of (-100 t + 1500 t^2) = -50/225 + 500/3375 = -0.2222222 + 0.1481481 = -2/27 J
    # cruise T = 1.5 - 2 = -0.5: -0.5 * 10 * 0.1 = -0.5 J
    # decelerate T = -1.5 - 15 t, w = 10 - 100 t: T w = -15 + 1500 t^2: -1.5 + 0.5 = -1.0 J
    # fed back: 2/27 + 0.5 + 1.0 = 1.5740741 J
    d2 = duty(prof, 0.01, 0.15, -2.0)
    assert d2.braking_energy == pytest.approx(2 / 27 + 1.5, rel=1e-12)
    assert d2.braking_energy == pytest.approx(_numerical_braking_energy(prof, 0.01, 0.15, -2.0), rel=1e-9)
    assert d2.braking_torque == pytest.approx(-3.0, rel=1e-12)  # -1 - 2 at the end of the deceleration


def _numerical_peak_power(profile, J, b, tr):
    return max(float(np.max(tq * w)) for _, w, tq in _phase_samples(profile, J, b, tr))


@pytest.mark.parametrize("J, b, tr, want", [
    # small trapezoid: end of the acceleration, 1.5 N m * 10 rad/s = 15 W
    (0.01, 0.02, 0.3, 15.0),
    # b = 0.1, T_R = 0.5: 1 + 1 + 0.5 = 2.5 N m * 10 rad/s = 25 W
    (0.01, 0.1, 0.5, 25.0),
    # heavy damping b = 5: cruise (5 * 10) * 10 = 500 W < end of the acceleration (1 + 50) * 10 = 510 W
    (0.01, 5.0, 0.0, 510.0),
])
def test_peak_power_against_a_dense_maximum(J, b, tr, want):
    prof = trapezoid(10.0, 100.0, 2.0, dwell=0.1)
    d = duty(prof, J, b, tr)
    assert d.peak_power == pytest.approx(want, rel=1e-12)
    assert d.peak_power == pytest.approx(_numerical_peak_power(prof, J, b, tr), rel=1e-9)


def test_peak_power_of_a_triangle():
    # theta = 0.25 rad < 10^2/100 = 1: w_p = sqrt(100 * 0.25) = 5 rad/s, t_a = 0.05 s
    # end of the acceleration: (0.01 * 100 + 0.02 * 5 + 0.3) * 5 = 1.4 * 5 = 7 W
    prof = trapezoid(10.0, 100.0, 0.25)
    d = duty(prof, 0.01, 0.02, 0.3)
    assert prof.triangular
    assert d.peak_power == pytest.approx(7.0, rel=1e-12)
    assert d.peak_power == pytest.approx(_numerical_peak_power(prof, 0.01, 0.02, 0.3), rel=1e-9)


# --- helpers ----------------------------------------------------------------------------

def test_cylinder_inertia_by_hand():
    # steel hollow cylinder d_o = 100 mm, d_i = 20 mm, w = 50 mm, rho = 7850:
    # pi rho w/32 (d_o^4 - d_i^4) = pi * 7850 * 0.05/32 * (1e-4 - 1.6e-7)
    #   = 1233.0750/32 * 9.984e-5 = 38.533594 * 9.984e-5 = 3.8471940e-3 kg m^2
    # cross-check m (d_o^2 + d_i^2)/8 with m = 7850 pi (0.01 - 0.0004)/4 * 0.05 = 2.9593803 kg:
    #   2.9593803 * 0.0104/8 = 3.8471944e-3 kg m^2
    assert cylinder_inertia(0.1, 0.02, 0.05, 7850.0) == pytest.approx(3.847194e-3, rel=1e-6)
    # solid: m d^2/8 = (7850 pi 0.01/4 * 0.05) * 0.01/8 = 3.0826878 * 0.00125 = 3.8533597e-3
    assert cylinder_inertia(0.1, 0.0, 0.05, 7850.0) == pytest.approx(3.8533597e-3, rel=1e-7)


def test_motor_damping_by_hand():
    # (1 - eta) T_n/omega_n = 0.1 * 1.27/(3000 * 2 pi/60) = 0.127/314.159265 = 4.0425355e-4 N m s/rad
    assert motor_damping(0.9, 1.27, 3000 * RPM) == pytest.approx(4.0425355e-4, rel=1e-7)
    # eta = 1: no loss
    assert motor_damping(1.0, 1.27, 3000 * RPM) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("call, param", [
    (lambda: cylinder_inertia(0.1, 0.1, 0.05, 7850.0), "inner_diameter"),
    (lambda: cylinder_inertia(0.1, -0.01, 0.05, 7850.0), "inner_diameter"),
    (lambda: cylinder_inertia(0.0, 0.0, 0.05, 7850.0), "outer_diameter"),
    (lambda: cylinder_inertia(0.1, 0.02, 0.0, 7850.0), "width"),
    (lambda: cylinder_inertia(0.1, 0.02, 0.05, -1.0), "density"),
    (lambda: motor_damping(0.0, 1.27, 314.0), "motor_efficiency"),
    (lambda: motor_damping(1.1, 1.27, 314.0), "motor_efficiency"),
    (lambda: motor_damping(0.9, 0.0, 314.0), "rated_torque"),
    (lambda: motor_damping(0.9, 1.27, 0.0), "rated_speed"),
    (lambda: crowder_axis(mass=-1.0), "mass"),
    (lambda: crowder_axis(pulley_diameter=0.0), "pulley_diameter"),
    (lambda: crowder_axis(gear_ratio=0.0), "gear_ratio"),
    (lambda: crowder_axis(belt_ratio=-2.0), "belt_ratio"),
    (lambda: crowder_axis(coupling_inertia=-1e-5), "coupling_inertia"),
    (lambda: crowder_axis(resistance=-1.0), "resistance"),
    (lambda: crowder_axis(guide_friction=1.0), "guide_friction"),
    (lambda: duty(SMALL, 0.0, 0.0, 0.0), "inertia"),
    (lambda: duty(SMALL, 0.01, -0.1, 0.0), "damping"),
])
def test_impossible_inputs_name_the_parameter(call, param):
    with pytest.raises(InputError) as exc:
        call()
    assert exc.value.param == param
