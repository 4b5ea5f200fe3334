"""Tests of beltcalc.design.motors: every motor checked on peak, RMS, speed and inertia ratio, and the
recommendation (DESIGN.md 2.5: prefer the smallest motor running at 50-100 % of its rated torque).

One axis and one move for every case, chosen so that the duty is easy by hand:
carriage 10 kg, D = 100 mm, gearbox i = 10, F_R = 20 N, nothing else:
  load inertia  J_L = m D^2/4 / i^2 = 10 * 0.01/4/100 = 2.5e-4 kg m^2
  resistance    T_R = F_R D/(2 i) = 20 * 0.1/20 = 0.1 N m
Move: 100 rad/s, 1000 rad/s^2, 20 rad, dwell 0.2 s: t_a = 0.1 s, theta_a = 5 rad,
t_c = (20 - 10)/100 = 0.1 s, cycle 0.1 + 0.1 + 0.1 + 0.2 = 0.5 s.
With motor efficiency 1 (b_M = 0) and rotor J_M, X = (J_M + J_L) * 1000:
  accelerate X + 0.1, cruise 0.1, decelerate -X + 0.1, dwell 0 (all constant)
  peak = X + 0.1;  integral T^2 = 0.1 ((X + 0.1)^2 + 0.01 + (X - 0.1)^2) = 0.1 (2 X^2 + 0.03)
  RMS = sqrt(0.1 (2 X^2 + 0.03)/0.5) = sqrt(0.4 X^2 + 0.006)
"""

import math

import pytest

from beltcalc.data.catalogs import Motor, Source, load_catalog
from beltcalc.formulas.drive import BeltAxis
from beltcalc.errors import InputError
from beltcalc.design.motors import check_motor, choose_motor
from beltcalc.formulas.profiles import trapezoid

AXIS = BeltAxis(mass=10.0, substitute_mass=0.0, pulley_diameter=0.1, pulley_inertia=0.0,
                idler_inertia=0.0, gear_ratio=10.0, resistance=20.0)
MOVE = trapezoid(100.0, 1000.0, 20.0, dwell=0.2)
SRC = Source(document="test motors", path="test.toml")


def motor(name, t_n, t_max, j, n_max=200.0, efficiency=1.0, n_rated=100.0):
    return Motor(name=name, series="test", P=t_n * n_rated, T_n=t_n, T_max=t_max, J=j,
                 n_rated=n_rated, n_max=n_max, source=SRC, efficiency=efficiency)


# J_M = 0.5e-4: X = 0.3, peak 0.4 N m, RMS sqrt(0.4 * 0.09 + 0.006) = sqrt(0.042) = 0.2049390 N m,
#   load/motor inertia 2.5e-4/0.5e-4 = 5
# J_M = 0.2e-4: X = 0.27, peak 0.37 N m, RMS sqrt(0.4 * 0.0729 + 0.006) = sqrt(0.03516) = 0.1875100,
#   ratio 2.5e-4/0.2e-4 = 12.5 > 10
# J_M = 2.5e-4: X = 0.5, peak 0.6 N m, RMS sqrt(0.4 * 0.25 + 0.006) = sqrt(0.106) = 0.3255764, ratio 1
R1 = motor("R1", 0.20, 1.0, 0.5e-4)             # RMS 0.2049 > T_n 0.2: fails RMS only
P1 = motor("P1", 0.25, 0.35, 0.5e-4)            # peak 0.4 > T_max 0.35: fails peak only
S1 = motor("S1", 0.30, 1.0, 0.5e-4, n_max=90.0, n_rated=50.0)  # 100 rad/s > 90: fails speed only
I1 = motor("I1", 0.35, 1.0, 0.2e-4)             # ratio 12.5 > 10: fails inertia only
G45 = motor("G45", 0.45, 0.5, 0.5e-4)           # passes, RMS/T_n = 0.2049390/0.45 = 45.5 %
H50 = motor("H50", 0.50, 1.5, 2.5e-4)           # passes, RMS/T_n = 0.3255764/0.5 = 65.1 %
G60 = motor("G60", 0.60, 1.8, 0.5e-4)           # passes, RMS/T_n = 0.2049390/0.6 = 34.2 %
FAILING = [R1, P1, S1, I1]


def by_name(choice):
    return {c.motor.name: c for c in choice.checks}


def test_duty_of_each_motor_by_hand():
    checks = by_name(choose_motor(AXIS, MOVE, FAILING + [G45, H50, G60], 0.9))
    for name in ("R1", "P1", "S1", "G45", "G60"):
        assert checks[name].duty.peak_torque == pytest.approx(0.4, rel=1e-12)
        assert checks[name].duty.rms_torque == pytest.approx(math.sqrt(0.042), rel=1e-12)  # 0.2049390
        assert checks[name].inertia_ratio == pytest.approx(5.0, rel=1e-12)
    assert checks["I1"].duty.peak_torque == pytest.approx(0.37, rel=1e-12)
    assert checks["I1"].duty.rms_torque == pytest.approx(0.1875100, rel=1e-6)
    assert checks["I1"].inertia_ratio == pytest.approx(12.5, rel=1e-12)
    assert checks["H50"].duty.peak_torque == pytest.approx(0.6, rel=1e-12)
    assert checks["H50"].duty.rms_torque == pytest.approx(0.3255764, rel=1e-6)
    assert checks["H50"].inertia_ratio == pytest.approx(1.0, rel=1e-12)


def test_each_check_fails_on_its_own():
    checks = by_name(choose_motor(AXIS, MOVE, FAILING + [G45], 0.9))
    flags = {n: (c.peak_ok, c.rms_ok, c.speed_ok, c.inertia_ok, c.ok) for n, c in checks.items()}
    assert flags == {
        "R1": (True, False, True, True, False),
        "P1": (False, True, True, True, False),
        "S1": (True, True, False, True, False),
        "I1": (True, True, True, False, False),
        "G45": (True, True, True, True, True),
    }
    # checks come smallest rated torque first
    assert [c.motor.name for c in choose_motor(AXIS, MOVE, [G45, I1, R1, S1, P1], 0.9).checks] == \
        ["R1", "P1", "S1", "I1", "G45"]


def test_prefers_the_smallest_motor_in_the_50_100_percent_band():
    # passing: G45 (45.5 %, out of band), H50 (65.1 %, in band), G60 (34.2 %): H50 is chosen
    # although G45 is smaller
    c = choose_motor(AXIS, MOVE, FAILING + [G45, H50, G60], 0.9)
    assert c.selected.motor.name == "H50"
    assert c.selected.utilisation == pytest.approx(0.3255764 / 0.5, rel=1e-6)  # 0.6511528
    assert c.selected.in_band
    assert "65%" in c.reason and "50-100 %" in c.reason
    assert "none" not in c.reason


def test_smallest_passing_motor_when_none_is_in_band():
    # passing: G45 (45.5 %), G60 (34.2 %): none in band, the smallest (G45) is chosen and the reason says so
    c = choose_motor(AXIS, MOVE, FAILING + [G60, G45], 0.9)
    assert c.selected.motor.name == "G45"
    assert c.selected.utilisation == pytest.approx(0.2049390 / 0.45, rel=1e-6)  # 0.4554200
    assert not c.selected.in_band
    assert "none runs at 50-100 %" in c.reason
    assert "46%" in c.reason


def test_no_motor_fits():
    c = choose_motor(AXIS, MOVE, FAILING, 0.9)
    assert c.selected is None
    assert len(c.checks) == 4
    assert "no motor" in c.reason


def test_peak_margin():
    # G45: peak 0.4 N m against T_max 0.5 N m: margin 0.2 -> 0.48 <= 0.5 passes;
    # margin 0.3 -> 0.52 > 0.5 fails, and G60 (0.52 <= 1.8, 34 %) is chosen instead
    c20 = choose_motor(AXIS, MOVE, FAILING + [G45, G60], 0.9, peak_margin=0.2)
    assert c20.selected.motor.name == "G45"
    c30 = choose_motor(AXIS, MOVE, FAILING + [G45, G60], 0.9, peak_margin=0.3)
    assert not by_name(c30)["G45"].peak_ok
    assert c30.selected.motor.name == "G60"
    assert "34%" in c30.reason
    # the duty itself does not change with the margin
    assert by_name(c30)["G45"].duty.peak_torque == pytest.approx(0.4, rel=1e-12)


def test_inertia_ratio_limit():
    # I1 has ratio 12.5: with a limit of 15 it passes; its RMS 0.1875100/0.35 = 53.6 % is in band,
    # so it is chosen over G45 (45.5 %) and H50 (65.1 %, larger)
    c = choose_motor(AXIS, MOVE, FAILING + [G45, H50], 0.9, ratio_limit=15.0)
    assert c.selected.motor.name == "I1"
    assert c.selected.utilisation == pytest.approx(0.1875100 / 0.35, rel=1e-6)  # 0.5357428


def test_speed_over_every_motor_is_an_input_error():
    # 100 rad/s = 954.9 rpm; the fastest of these runs 90 rad/s = 859.4 rpm
    slow = [motor("A", 0.5, 1.5, 1e-4, n_max=90.0, n_rated=50.0),
            motor("B", 1.0, 3.0, 2e-4, n_max=80.0, n_rated=50.0)]
    with pytest.raises(InputError) as exc:
        choose_motor(AXIS, MOVE, slow, 0.9)
    assert exc.value.param == "speed"
    assert "955 rpm" in str(exc.value) and "859 rpm" in str(exc.value)


def test_catalog_efficiency_beats_the_default():
    # motor efficiency 0.8, T_n 0.5 N m at 100 rad/s: b_M = 0.2 * 0.5/100 = 1e-3 N m s/rad;
    # cruise torque b_M w + T_R = 1e-3 * 100 + 0.1 = 0.2 N m (the default 0.9 would give 0.15)
    own = motor("E", 0.5, 1.5, 0.5e-4, efficiency=0.8)
    assert check_motor(AXIS, MOVE, own, 0.9).duty.phases[1].torque0 == pytest.approx(0.2, rel=1e-12)
    # no catalog efficiency: the default 0.9 -> b_M = 0.1 * 0.5/100 = 5e-4; 0.05 + 0.1 = 0.15 N m
    none = motor("N", 0.5, 1.5, 0.5e-4, efficiency=None)
    assert check_motor(AXIS, MOVE, none, 0.9).duty.phases[1].torque0 == pytest.approx(0.15, rel=1e-12)


@pytest.mark.parametrize("kw, param", [
    (dict(ratio_limit=0.0), "inertia_ratio_limit"),
    (dict(peak_margin=-0.1), "peak_margin"),
])
def test_bad_limits(kw, param):
    with pytest.raises(InputError) as exc:
        choose_motor(AXIS, MOVE, [G45], 0.9, **kw)
    assert exc.value.param == param


def test_no_motors_at_all():
    with pytest.raises(InputError) as exc:
        choose_motor(AXIS, MOVE, [], 0.9)
    assert exc.value.param == "motors"


class TestYaskawa:
    """The same axis and move against the Yaskawa catalog, efficiency 1 (the catalog gives none).

    load/motor inertia 2.5e-4/J_M:
      SGM7J-A5A 3.95e-6 -> 63.3, SGM7J-01A 6.59e-6 -> 37.9, SGM7J-C2A 9.15e-6 -> 27.3,
      SGMAH-04A 1.73e-5 -> 14.5: fail at 10;
      SGM7J-02A 2.63e-5 -> 9.51: passes; every other motor has J >= 4.86e-5 (ratio <= 5.1).
    SGM7J-02A: X = 0.2763, peak 0.3763 N m <= 2.23, RMS sqrt(0.4 * 0.07634169 + 0.006)
      = sqrt(0.03653668) = 0.1911457 N m <= 0.637, RMS/T_n = 30.0 %.
    In band would need RMS >= 0.5 T_n >= 0.635 N m for the bigger motors (T_n >= 1.27), but the
    largest RMS is SGM7A-30A's: X = 0.95, sqrt(0.4 * 0.9025 + 0.006) = 0.6058 N m: none is.
    """

    MOTORS = list(load_catalog().motors.values())

    def test_smallest_passing_motor(self):
        c = choose_motor(AXIS, MOVE, self.MOTORS, 1.0)
        checks = by_name(c)
        for name, ratio in (("SGM7J-A5A", 63.291139), ("SGM7J-01A", 37.936267),
                            ("SGM7J-C2A", 27.322404), ("SGMAH-04A", 14.450867)):
            assert checks[name].inertia_ratio == pytest.approx(ratio, rel=1e-7)
            assert not checks[name].inertia_ok
        sel = c.selected
        assert sel.motor.name == "SGM7J-02A"
        assert sel.inertia_ratio == pytest.approx(9.5057034, rel=1e-7)
        assert sel.duty.peak_torque == pytest.approx(0.3763, rel=1e-9)
        assert sel.duty.rms_torque == pytest.approx(0.1911457, rel=1e-6)
        assert sel.utilisation == pytest.approx(0.1911457 / 0.637, rel=1e-6)  # 0.3000717
        assert "none runs at 50-100 %" in c.reason and "30%" in c.reason
        assert not any(ch.in_band for ch in c.checks if ch.ok)

    def test_a_looser_inertia_limit_brings_a_motor_into_the_band(self):
        # limit 40: SGM7J-01A (ratio 37.9) passes: X = 0.25659, RMS sqrt(0.4 * 0.06583843 + 0.006)
        # = sqrt(0.03233537) = 0.1798204 N m, /0.318 = 56.5 % (in band); it is the smallest
        # (A5A: RMS 0.178315 > T_n 0.159 fails)
        c = choose_motor(AXIS, MOVE, self.MOTORS, 1.0, ratio_limit=40.0)
        assert not by_name(c)["SGM7J-A5A"].rms_ok
        assert c.selected.motor.name == "SGM7J-01A"
        assert c.selected.duty.rms_torque == pytest.approx(0.1798204, rel=1e-6)
        assert c.selected.utilisation == pytest.approx(0.5654730, rel=1e-6)
        assert "57%" in c.reason and "50-100 %" in c.reason
