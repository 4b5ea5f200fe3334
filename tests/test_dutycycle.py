"""Tests of beltcalc.design.dutycycle: exact duty cycles (issue 14).

Every hard number is checked against an independent computation: closed forms worked by
hand in the comments, or scipy.integrate.quad of the torque evaluated point by point from
the plain physics (speed and acceleration read off the phases, the gearbox efficiency
chosen by the sign of the power at that instant) - not from the piecewise polynomials
under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from beltcalc.formulas.drive import G0, BeltAxis, duty
from beltcalc.design.dutycycle import AxisDrive, Gearbox, Mounting, Segment, cycle_duty, single_move
from beltcalc.design.zones import assumed_zone, zone_check
from beltcalc.design.regeneration import capacitor_energy, regeneration
from beltcalc.errors import InputError
from beltcalc.formulas.profiles import move_by_time, scurve, trapezoid

R = 0.05                      # pulley radius D/2 [m]


def axis(**kw):
    base = dict(mass=10.0, substitute_mass=0.1, pulley_diameter=2 * R, pulley_inertia=2e-4, idler_inertia=2e-4,
                coupling_inertia=1e-5, gearbox_inertia=2e-5, gear_ratio=5.0, bearing_damping=1e-3,
                guide_damping=2.0, resistance=15.0, guide_friction=0.003)
    base.update(kw)
    return BeltAxis(**base)


# --- the independent reference ----------------------------------------------------------------

def reference(drive: AxisDrive, segments, j_m: float, b_m: float):
    """(list of (t0, t1, torque(t), speed(t), load torque(t))) of the cycle, the torque evaluated from the
    physics at each instant (no polynomials, no pre-cut pieces)."""
    ax, gb, mt = drive.axis, drive.gearbox, drive.mounting
    out, t0 = [], 0.0
    for seg in segments:
        m = ax.mass + seg.payload
        r_i = ax.pulley_diameter / 2 / gb.ratio
        jl = (ax.coupling_inertia + ax.pulley_inertia + (ax.idler_inertia + ax.load_inertia) / ax.belt_ratio ** 2
              + (m + ax.substitute_mass + mt.counterweight) * (ax.pulley_diameter / 2) ** 2) / gb.ratio ** 2
        bl = (ax.bearing_damping * (1 + ax.belt_ratio ** -2) + ax.guide_damping * (ax.pulley_diameter / 2) ** 2) \
            / gb.ratio ** 2
        fr = ax.resistance + (seg.force if seg.kind == "move" else 0.0) \
            + ax.guide_friction * m * G0 * math.cos(mt.incline)
        grav = (m - mt.counterweight) * G0 * math.sin(mt.incline) + (seg.force if seg.kind == "dwell" else 0.0)
        for ph in seg.phases:
            def kin(t, ph=ph, t0=t0, s=seg.direction):
                x = t - t0
                return s * (ph.speed0 + ph.accel * x + 0.5 * ph.jerk * x * x), s * (ph.accel + ph.jerk * x)

            def load(t, kin=kin, seg=seg, jl=jl, bl=bl, fr=fr, grav=grav, r_i=r_i):
                w, wd = kin(t)
                moving = seg.kind == "move"
                return jl * wd + bl * w + (math.copysign(fr * r_i, w) if moving else 0.0) + grav * r_i

            def torque(t, kin=kin, seg=seg, load=load):
                w, wd = kin(t)
                moving = seg.kind == "move"
                tl = load(t)
                if not moving:
                    return 0.0 if mt.brake else tl
                p = tl * w
                tg = tl / gb.efficiency if p > 0 else (tl * gb.eta_back if p < 0 else tl)
                return (j_m + gb.inertia) * wd + b_m * w + tg

            out.append((t0, t0 + ph.duration, torque, lambda t, kin=kin: kin(t)[0], load))
            t0 += ph.duration
    return out


def zeros(tq, a, b, n=2001):
    """Sign changes of the reference torque on (a, b): a scan, then Brent's method."""
    from scipy.optimize import brentq

    ts = np.linspace(a + 1e-13, b - 1e-13, n)
    vs = [tq(t) for t in ts]
    return [brentq(tq, ts[k], ts[k + 1], xtol=1e-16, rtol=1e-15) for k in range(n - 1) if vs[k] * vs[k + 1] < 0]


def integral(ref, f, lo=-math.inf, hi=math.inf):
    """Integral of f over the cycle (between lo and hi), by quad between the torque's zeros."""
    from scipy.integrate import quad

    total = 0.0
    for a, b, tq, w, tl in ref:
        a, b = max(a, lo), min(b, hi)
        if b <= a:
            continue
        # the torque's zeros (power changes sign) and the load torque's (the efficiency switches: a kink)
        cuts = sorted([a, *zeros(tq, a, b), *zeros(tl, a, b), b])
        total += sum(quad(lambda t: f(tq, w, t), c, e, epsabs=0.0, epsrel=2e-14, limit=200)[0]
                     for c, e in zip(cuts, cuts[1:]))
    return total


# --- a cycle of one move is today's single move ---------------------------------------------------

def test_one_move_equals_todays_duty():
    ax = axis()
    prof = trapezoid(300.0, 4000.0, 200.0, dwell=0.3)
    j_m, b_m = 1e-4, 5e-4
    new = cycle_duty(AxisDrive(ax), single_move(prof), j_m, b_m)
    old = duty(prof, j_m + ax.load_inertia_total, ax.damping(b_m), ax.resistance_torque)
    for key in ("peak_torque", "rms_torque", "peak_power", "braking_torque", "braking_energy", "cycle_time"):
        assert getattr(new, key) == pytest.approx(getattr(old, key), rel=1e-13), key
    for a, b in zip(new.phases, old.phases):
        assert (a.torque0, a.torque1) == pytest.approx((b.torque0, b.torque1), rel=1e-13)


def test_size_axis_is_size_cycle_and_the_sweep_its_duty():
    # one implementation (issue 14, tidy): beltcalc.size_axis calls size_cycle; a sweep point is the
    # same cycle duty; both equal drive.duty's closed form of the single trapezoid (1e-13)
    import beltcalc
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.design.sizing import DutyOptions, size_cycle, sweep
    from beltcalc.design.axis_inputs import SizingInputs

    cat = load_catalog()
    inp = SizingInputs(mass=50.0, width=0.025, center_distance=1.245, pulley_teeth=40, pulley_width=0.03,
                       pulley_bore=0.02, pulley_density=2700.0, coupling_inertia=2e-5, gearbox_inertia=1e-5,
                       gear_ratio=20.0, belt_ratio=1.0, resistance=0.0, guide_friction=0.002, guide_damping=0.0,
                       bearing_damping=0.0, motor_efficiency=0.9, speed=314.159, speed_unit="rad/s", accel=10.0,
                       accel_unit="m/s^2", stroke=1.0, dwell=0.5)
    motors, belt = list(cat.motors.values()), cat.belt("AT10")
    a, b = beltcalc.size_axis(inp, belt, motors), size_cycle(inp, belt, motors, None, DutyOptions())
    assert a.shown.motor.name == b.shown.motor.name == "SGM7J-06A"
    assert (a.shown.duty.peak_torque, a.shown.duty.rms_torque) == (b.shown.duty.peak_torque, b.shown.duty.rms_torque)
    m = a.shown.motor
    b_m = (1 - 0.9) * m.T_n / m.n_rated
    old = duty(a.profile, m.J + a.axis.load_inertia_total, a.axis.damping(b_m), a.axis.resistance_torque)
    point = sweep(inp, belt, m, "accel", [10.0], "m/s^2")[0]
    for got in (a.shown.duty, point.duty):
        for key in ("peak_torque", "rms_torque", "peak_power", "braking_energy"):
            assert getattr(got, key) == pytest.approx(getattr(old, key), rel=1e-13), key
    assert (point.accel_time, point.accel_energy, point.accel_energy_exact) == pytest.approx(
        (old.accel_time, old.accel_energy, old.accel_energy_exact), rel=1e-13)
    # the options pass through: a gearbox of efficiency 0.9 divides the load side of the peak by 0.9
    # (the rotor and the gearbox's own 1e-5 kg m^2 stay on the motor side, Crowder eq. 3.9)
    gear = beltcalc.size_axis(inp, belt, motors, opts=DutyOptions(gear_efficiency=0.9))
    own = (m.J + 1e-5) * a.profile.accel + b_m * a.profile.peak_speed
    assert gear.shown.duty.peak_torque == pytest.approx(own + (old.peak_torque - own) / 0.9, rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(speed=st.floats(10.0, 600.0), accel=st.floats(100.0, 1e5), stroke=st.floats(0.1, 500.0),
       dwell=st.floats(0.0, 2.0), mass=st.floats(0.5, 200.0), b_m=st.floats(0.0, 1e-2))
def test_one_move_equals_todays_duty_for_any_move(speed, accel, stroke, dwell, mass, b_m):
    ax = axis(mass=mass)
    prof = trapezoid(speed, accel, stroke, dwell)
    new = cycle_duty(AxisDrive(ax), single_move(prof), 1e-4, b_m)
    old = duty(prof, 1e-4 + ax.load_inertia_total, ax.damping(b_m), ax.resistance_torque)
    for key in ("peak_torque", "rms_torque", "peak_power", "braking_energy"):
        assert getattr(new, key) == pytest.approx(getattr(old, key), rel=1e-12, abs=1e-12), key


# --- RMS and energies of every profile against quadrature to 1e-12 -------------------------------------

def cycle_mixed():
    """Two S-curve moves with other payloads and a process force, dwells with and without force,
    a 30 deg incline and a gearbox of 0.85 driving / 0.7 back-driven."""
    ax = axis()
    drive = AxisDrive(ax, Mounting(incline=math.radians(30.0)), Gearbox(5.0, 2e-5, 0.85, 0.7))
    segs = [
        Segment("up", "move", profile=scurve(300.0, 5000.0, 2e5, 150.0), direction=1, payload=4.0, force=20.0),
        Segment("press", "dwell", duration=0.2, payload=4.0, force=-60.0),
        Segment("down", "move", profile=scurve(250.0, 8000.0, 5e5, 150.0), direction=-1),
        Segment("wait", "dwell", duration=0.3),
        Segment("nudge", "move", profile=move_by_time(20.0, 0.2, 0.25, 0.3), direction=1, payload=1.0),
        Segment("back", "move", profile=trapezoid(200.0, 3000.0, 20.0), direction=-1, payload=1.0),
    ]
    return drive, segs


@pytest.mark.parametrize("brake", [False, True])
def test_rms_and_energies_against_quadrature(brake):
    drive, segs = cycle_mixed()
    drive = AxisDrive(drive.axis, Mounting(drive.mounting.incline, 0.0, brake), drive.gearbox)
    j_m, b_m = 1.5e-4, 8e-4
    d = cycle_duty(drive, segs, j_m, b_m)
    ref = reference(drive, segs, j_m, b_m)
    sq = integral(ref, lambda tq, w, t: tq(t) ** 2)
    pos = integral(ref, lambda tq, w, t: max(tq(t) * w(t), 0.0))
    neg = integral(ref, lambda tq, w, t: max(-tq(t) * w(t), 0.0))
    assert d.rms_torque == pytest.approx(math.sqrt(sq / d.cycle_time), rel=1e-12)
    assert d.energy_motoring == pytest.approx(pos, rel=1e-12)
    assert d.braking_energy == pytest.approx(neg, rel=1e-12)
    assert neg > 1.0 and pos > 1.0          # both happen in this cycle: the test is not vacuous
    # per segment: the sum of the segments' integral of T^2 is the cycle's
    assert sum(s.sq_integral for s in d.segments) == pytest.approx(sq, rel=1e-12)


def test_peak_torque_against_a_fine_evaluation():
    drive, segs = cycle_mixed()
    d = cycle_duty(drive, segs, 1.5e-4, 8e-4)
    ref = reference(drive, segs, 1.5e-4, 8e-4)
    best = 0.0
    for a, b, tq, _, _ in ref:
        # both limits at the phase ends (eps inside) and 20001 points between
        ts = np.concatenate([[a + 1e-13, b - 1e-13], np.linspace(a, b, 20001)[1:-1]])
        best = max(best, max(abs(tq(t)) for t in ts))
    assert d.peak_torque == pytest.approx(best, rel=1e-9)


def test_right_continuous_acceleration_peak_is_the_left_limit():
    # trapezoid: the torque at the end of the acceleration is J eps + b omega_max + T_R (the left limit),
    # not the cruise torque that a sample at t = t_a would see
    ax = axis(bearing_damping=0.0, guide_damping=0.0, resistance=0.0, guide_friction=0.0)
    prof = trapezoid(100.0, 1000.0, 50.0)
    d = cycle_duty(AxisDrive(ax), single_move(prof), 1e-4, 1e-3)
    j = 1e-4 + ax.load_inertia_total
    assert d.peak_torque == pytest.approx(j * 1000.0 + 1e-3 * 100.0, rel=1e-13)
    assert d.peak_time == pytest.approx(0.1, rel=1e-13)
    assert d.torque_at(0.1, "left") == pytest.approx(j * 1000.0 + 0.1, rel=1e-13)
    assert d.torque_at(0.1, "right") == pytest.approx(0.1, rel=1e-12)


# --- vertical axes -------------------------------------------------------------------------------

def test_vertical_axis_at_rest_holds_m_g_D_over_2_i():
    # 10 kg + 2 kg payload, D = 0.1 m, i = 5: (12 * 9.80665) * 0.05 / 5 = 1.176798 N m,
    # also with gearbox efficiency 0.8 (at rest no power flows) and whatever the friction
    ax = axis()
    seg = [Segment("hold", "dwell", duration=1.0, payload=2.0)]
    d = cycle_duty(AxisDrive(ax, Mounting(incline=math.pi / 2), Gearbox(5.0, 2e-5, 0.8)), seg, 1e-4, 1e-3)
    assert d.holding_torque == pytest.approx(12 * 9.80665 * 0.05 / 5, rel=1e-13)
    assert d.rms_torque == pytest.approx(1.176798, rel=1e-6)
    # upside down: -90 deg holds the same torque the other way
    d2 = cycle_duty(AxisDrive(ax, Mounting(incline=-math.pi / 2)), seg, 1e-4, 1e-3)
    assert d2.peak_torque == pytest.approx(1.176798, rel=1e-6)
    assert d2.phases[0].torque0 == pytest.approx(-1.176798, rel=1e-6)
    # a brake holds instead of the motor; a counterweight of the whole mass balances it
    assert cycle_duty(AxisDrive(ax, Mounting(math.pi / 2, brake=True)), seg).rms_torque == 0.0
    assert cycle_duty(AxisDrive(ax, Mounting(math.pi / 2, counterweight=12.0)), seg).holding_torque == \
        pytest.approx(0.0, abs=1e-15)


def test_incline_30_degrees_at_rest():
    # sin 30 = 1/2: 10 kg * 9.80665 / 2 * 0.05 / 5 = 0.4903325 N m
    d = cycle_duty(AxisDrive(axis(), Mounting(incline=math.radians(30.0))), [Segment("rest", "dwell", duration=0.5)])
    assert d.holding_torque == pytest.approx(0.4903325, rel=1e-12)


# --- braking energy and the resistor --------------------------------------------------------------------

def test_lowering_returns_the_potential_energy_times_the_back_efficiency():
    # a vertical axis lowers m = 10 kg by L = theta r / i; rest to rest, no friction or damping, the motor
    # keeps holding (T > 0) while omega < 0: the energy fed back is exactly eta_b m g L
    ax = axis(bearing_damping=0.0, guide_damping=0.0, resistance=0.0, guide_friction=0.0, substitute_mass=0.0)
    prof = scurve(100.0, 500.0, 2e4, 80.0)
    drive = AxisDrive(ax, Mounting(incline=math.pi / 2), Gearbox(5.0, 2e-5, 0.9, 0.75))
    d = cycle_duty(drive, [Segment("down", "move", profile=prof, direction=-1)], 1e-4, 0.0)
    lowered = 80.0 * R / 5.0                                  # 0.8 m
    assert all(p.torque0 > 0 and p.torque1 > 0 for p in d.phases)   # holding all the way
    assert d.braking_energy == pytest.approx(0.75 * 10 * 9.80665 * lowered, rel=1e-12)
    assert d.energy_motoring == pytest.approx(0.0, abs=1e-12)
    # the resistor: E_R = eta_e E_brake - E_C for the one event, continuous power E_R / t_cycle
    e_c = capacitor_energy(470e-6, 325.0, 380.0)               # 0.5 * 470e-6 * (380^2 - 325^2) = 9.1119 J
    assert e_c == pytest.approx(0.5 * 470e-6 * (380.0 ** 2 - 325.0 ** 2), rel=1e-14)
    reg = regeneration(d, e_c, efficiency=0.9, chopper_voltage=380.0)
    assert len(reg.events) == 1
    assert reg.resistor_energy == pytest.approx(0.9 * d.braking_energy - e_c, rel=1e-12)
    assert reg.resistor_power == pytest.approx(reg.resistor_energy / d.cycle_time, rel=1e-14)
    assert reg.resistor_peak_power == pytest.approx(0.9 * d.peak_braking_power, rel=1e-14)
    assert reg.resistance_max == pytest.approx(380.0 ** 2 / reg.resistor_peak_power, rel=1e-14)


def test_resistor_energy_is_the_negative_power_minus_losses_per_event():
    drive, segs = cycle_mixed()
    d = cycle_duty(drive, segs, 1.5e-4, 8e-4)
    ref = reference(drive, segs, 1.5e-4, 8e-4)
    assert len(d.events) >= 2
    for ev in d.events:
        e = integral(ref, lambda tq, w, t: max(-tq(t) * w(t), 0.0), ev.start, ev.end)
        assert ev.energy == pytest.approx(e, rel=1e-12)
    cap = 0.5 * min(ev.energy for ev in d.events)
    reg = regeneration(d, cap)
    assert reg.resistor_energy == pytest.approx(sum(max(ev.energy - cap, 0.0) for ev in d.events), rel=1e-13)
    # a capacitor larger than every event: nothing for the resistor
    assert regeneration(d, 1e6).resistor_energy == 0.0


# --- the torque-speed zone -----------------------------------------------------------------------

def test_assumed_zone_fails_a_motor_that_passes_the_flat_check_at_high_speed():
    # n_rated 100 rad/s, n_max 200 rad/s, T_max 1 N m, T_n 0.3 N m: assumed zone at 190 rad/s is
    # 1 - 0.7 * 90/100 = 0.37 N m. A move at 190 rad/s whose accelerating torque ends at
    # J eps + b w = 0.5e-3 * 1000 + 0.5e-3 * 190 = 0.5 + 0.095 = 0.595 N m <= T_max passes the flat check
    # and fails the zone by 0.37 - 0.595 = -0.225 N m at the end of the acceleration (t = 0.19 s).
    ax = BeltAxis(mass=1e-9, substitute_mass=0.0, pulley_diameter=0.1, pulley_inertia=0.0, idler_inertia=0.0)
    prof = trapezoid(190.0, 1000.0, 100.0)
    d = cycle_duty(AxisDrive(ax), single_move(prof), 0.5e-3, 0.5e-3)
    assert d.peak_torque == pytest.approx(0.595, rel=1e-6)
    z = zone_check(d, assumed_zone(1.0, 0.3, 100.0, 200.0))
    assert not z.ok
    assert z.margin == pytest.approx(0.37 - 0.595, rel=1e-6)
    assert (z.time, z.speed, z.limit) == pytest.approx((0.19, 190.0, 0.37), rel=1e-9)
    # the same move at 100 rad/s stays on the flat part: margin T_max - peak
    slow = cycle_duty(AxisDrive(ax), single_move(trapezoid(100.0, 1000.0, 100.0)), 0.5e-3, 0.5e-3)
    z2 = zone_check(slow, assumed_zone(1.0, 0.3, 100.0, 200.0))
    assert z2.ok and z2.margin == pytest.approx(1.0 - 0.55, rel=1e-7)   # the 1e-9 kg carriage: 2.5e-9 N m


def test_zone_minimum_inside_a_phase_against_a_fine_search():
    drive, segs = cycle_mixed()
    d = cycle_duty(drive, segs, 1.5e-4, 8e-4)
    pts = ((0.0, 3.0), (150.0, 3.0), (280.0, 2.0), (320.0, 0.5))
    z = zone_check(d, pts, peak_margin=0.1)
    ref = reference(drive, segs, 1.5e-4, 8e-4)
    best = math.inf
    for a, b, tq, w, _ in ref:
        for t in np.linspace(a + 1e-13, b - 1e-13, 20001):
            best = min(best, float(np.interp(abs(w(t)), *zip(*pts))) - 1.1 * abs(tq(t)))
    assert z.margin == pytest.approx(best, abs=1e-7)
    assert z.margin <= best + 1e-12


# --- bad input -----------------------------------------------------------------------------------

@pytest.mark.parametrize("make, param", [
    (lambda: Mounting(incline=2.0), "incline"),
    (lambda: Mounting(counterweight=-1.0), "counterweight"),
    (lambda: Gearbox(efficiency=0.0), "gear_efficiency"),
    (lambda: Gearbox(efficiency=0.9, efficiency_back=1.2), "gear_efficiency_back"),
    (lambda: Segment("x", "move", profile=None), "cycle"),
    (lambda: Segment("x", "dwell", duration=0.0), "dwell"),
    (lambda: Segment("x", "hover"), "cycle"),
    (lambda: Segment("x", "dwell", duration=1.0, direction=2), "cycle"),
    (lambda: capacitor_energy(1e-3, 380.0, 325.0), "chopper_voltage"),
    (lambda: cycle_duty(AxisDrive(axis()), []), "cycle"),
])
def test_bad_inputs_name_the_parameter(make, param):
    with pytest.raises(InputError) as exc:
        make()
    assert exc.value.param == param
