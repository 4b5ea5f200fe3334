"""Tests of beltcalc.formulas.belt: the substitute model of Wojtkowiak et al., Energies 14 (2021) 317."""

import math

import pytest

from beltcalc.formulas import belt as bm
from beltcalc.errors import InputError

RPM = 2 * math.pi / 60


class TestWorkedExampleWDU:
    """Section 3.2 of the paper: AT10 25 mm, a = 1245 mm (Fig. 6: w_spec 0.114 kg/m, C_spec 5.5e5 N)."""

    def test_teeth_and_mass(self):
        # z = 1245/10 + 1 = 125.5 (eq. 14); m_belt = 0.114 * 1.245 = 0.14193 kg (eq. 15)
        assert bm.teeth_on_span(1.245, 0.010) == pytest.approx(125.5, rel=1e-12)
        assert bm.belt_mass_on_span(0.114, 1.245) == pytest.approx(0.14193, rel=1e-12)

    def test_substitute_mass_eq7(self):
        # m_TB = 0.14193 * 125.5 / (2 * 124.5^2) = 17.81222 / 31000.5 = 5.74578e-4 kg
        assert bm.substitute_mass(0.14193, 125.5) == pytest.approx(5.74578e-4, rel=1e-5)

    def test_substitute_mass_rayleigh(self):
        assert bm.substitute_mass(0.14193, 125.5, "rayleigh") == pytest.approx(0.04731, rel=1e-12)

    def test_stiffness(self):
        # k_TB = C_spec / a = 5.5e5 / 1.245 = 441767.07 N/m (eq. 16)
        assert bm.belt_stiffness(5.5e5, 1.245) == pytest.approx(441767.07, rel=1e-8)

    def test_tension_peak_and_displacement(self):
        m_tb = bm.substitute_mass(0.14193, 125.5)
        force = bm.tension_peak(m_tb, 50.0, 10.0, 0.1, 0.005, 20.0)
        # (50.000575)*0.1 + 20*0.005 + 50*10 = 505.1001 N: the paper prints 505.1 N
        assert force == pytest.approx(505.1, abs=0.05)
        # x_max = 505.1 / 441767 = 1.1434 mm; the paper rounds this up to 1.15 mm
        x = bm.pretension_displacement(force, bm.belt_stiffness(5.5e5, 1.245))
        assert x * 1e3 == pytest.approx(1.143, abs=0.005)


def test_punching_die_axis_by_hand():
    # PDD axis of the paper: AT10 32 mm (w 0.145 kg/m, C_spec 7e5 N), a = 795 mm, 90 kg, 10 m/s^2.
    # z = 80.5; m_belt = 0.145 * 0.795 = 0.115275 kg; m_TB = 0.115275 * 80.5 / (2 * 79.5^2)
    #   = 9.279638 / 12640.5 = 7.34119e-4 kg; k_TB = 7e5 / 0.795 = 880503.1 N/m;
    # F = 90.000734 * 0.1 + 20 * 0.005 + 90 * 10 = 909.10007 N; x = 909.10007 / 880503.1 = 1.032478 mm
    z = bm.teeth_on_span(0.795, 0.010)
    m_tb = bm.substitute_mass(bm.belt_mass_on_span(0.145, 0.795), z)
    k = bm.belt_stiffness(7e5, 0.795)
    force = bm.tension_peak(m_tb, 90.0, 10.0, 0.1, 0.005, 20.0)
    assert (z, m_tb, k) == pytest.approx((80.5, 7.34119e-4, 880503.1), rel=1e-6)
    assert force == pytest.approx(909.10007, rel=1e-8)
    assert bm.pretension_displacement(force, k) == pytest.approx(1.032478e-3, rel=1e-6)


def test_rayleigh_is_continuum_limit_and_eq7_is_not():
    # eq. 7 tends to m/(2 z) for long spans; Rayleigh stays m/3 whatever the tooth count.
    for z in (10.0, 100.0, 1000.0):
        assert bm.substitute_mass(1.0, z) == pytest.approx(z / (2 * (z - 1) ** 2), rel=1e-12)
        assert bm.substitute_mass(1.0, z, "rayleigh") == pytest.approx(1 / 3, rel=1e-12)


def test_pulley_pitch_diameter_misumi():
    # MISUMI AT5 table: 15T 23.87 mm, 16T 25.46 mm, 20T 31.83 mm, 30T 47.75 mm
    got = [bm.pulley_pitch_diameter(z, 0.005) * 1e3 for z in (15, 16, 20, 30)]
    assert got == pytest.approx([23.87, 25.46, 31.83, 47.75], abs=0.005)


def test_teeth_in_mesh():
    # equal pulleys: half wrap, z_e = z1/2; 20 and 40 teeth on P=5 mm at a = 200 mm:
    # acos(5*20/(2 pi 200)) = acos(0.0795775) = 85.4357 deg -> z_e = 20/180*85.4357 = 9.49286
    assert bm.teeth_in_mesh(30, 30, 0.005, 0.3) == pytest.approx(15.0, rel=1e-12)
    assert bm.teeth_in_mesh(20, 40, 0.005, 0.2) == pytest.approx(9.49286, rel=1e-5)
    assert bm.teeth_in_mesh(40, 40, 0.01, 1.0, z_e_max=12) == 12
    with pytest.raises(InputError):
        bm.teeth_in_mesh(10, 400, 0.01, 0.1)


def test_damping_fit_by_hand():
    # BRECO T20, 25 mm, D = 128 mm, z_e = 10: v = omega * D/2 = 0, 6.7021, 43.5634 m/s;
    # F_t = F_tspec * 2.5 cm * 10 = 2537.5, 1430, 605 N -> F_b = 0, -1107.5, -1932.5 N;
    # s = (6.70206*-1107.5 + 43.5634*-1932.5) / (6.70206^2 + 43.5634^2) = -91608.8 / 1942.69 = -47.156
    fit = bm.damping_from_tooth_load([(0.0, 10150.0), (1000 * RPM, 5720.0), (6500 * RPM, 2420.0)],
                                     0.128, 0.025, 10.0)
    assert fit.damping == pytest.approx(47.156, abs=0.001)
    assert (fit.v_min, fit.v_max, fit.points) == pytest.approx((0.0, 43.5634, 3), abs=1e-4)
    # SS_res = 791.4^2 + 121.8^2 = 641,1xx; SS_tot = 1,880,6xx -> R^2 = 0.659
    assert fit.r_squared == pytest.approx(0.659, abs=0.001)


def test_damping_fit_exact_line():
    # a load that falls exactly linearly with v is fitted with R^2 = 1 and its own slope
    d, w, z = 0.1, 0.02, 8.0
    table = [(om, 5000.0 - 3.0 * om * d / 2 / (w * z)) for om in (0.0, 50.0, 100.0, 300.0)]
    fit = bm.damping_from_tooth_load(table, d, w, z)
    assert fit.damping == pytest.approx(3.0, rel=1e-12)
    assert fit.r_squared == pytest.approx(1.0, rel=1e-12)


def test_span_frequency_gates_formula():
    # Gates 508C: T = 4 M W S^2 f^2 1e-9 with M [g/(m mm)], W [mm], S [mm]; for AT10 25 mm
    # M = 114 g/m / 25 mm = 4.56, S = 1245 -> f = sqrt(505.1 / (4*4.56*25*1245^2*1e-9)) = 26.732 Hz
    assert bm.span_frequency(505.1, 0.114, 1.245) == pytest.approx(26.732, abs=0.001)


@pytest.mark.parametrize("call, param", [
    (lambda: bm.teeth_on_span(0.005, 0.010), "center_distance"),
    (lambda: bm.teeth_on_span(-1.0, 0.010), "center_distance"),
    (lambda: bm.belt_mass_on_span(0.0, 1.0), "belt_weight"),
    (lambda: bm.belt_stiffness(5e5, 0.0), "center_distance"),
    (lambda: bm.pretension_displacement(100.0, 0.0), "stiffness"),
    (lambda: bm.tension_peak(0.0, -1.0, 10.0, 0.1, 0.005, 20.0), "mass"),
    (lambda: bm.tension_peak(0.0, 1.0, 10.0, 0.1, 0.005, math.nan), "damping"),
    (lambda: bm.substitute_mass(1.0, 10.0, "bogus"), "substitute_mass_model"),
    (lambda: bm.span_frequency(100.0, 0.1, 0.0), "span_length"),
])
def test_impossible_inputs_name_the_parameter(call, param):
    with pytest.raises(InputError) as exc:
        call()
    assert exc.value.param == param
