"""The checks a designer signs off for a timing-belt drive: geometry, tooth shear, tension
member, pulley size, shaft load, installation tension and its span frequency, on the formulas
of :mod:`beltcalc.formulas.belt_capacity`. SI floats.

References:

[BRECO] BRECO/BRECOFLEX timing-belt design pages (belt-pilot.com, id=1702): tooth capacity
    F_t = F_tspec(n) * b[cm] * z_e, teeth in mesh z_e capped at z_e max.
[Tsubaki belts] Tsubakimoto Chain, technical data, synchronous belts: correction factors
    Ko, Ki, Ks, Ka [Tsubaki belts table 1-4] and meshing factor (full capacity with 6 or more
    teeth in mesh) [Tsubaki belts table 6].
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the paper's tension [W21 eq. 10-12]; the peak motor
    torque of a duty cycle [W21 eq. 26-28] as ``beltcalc motor-size`` computes it
    (:mod:`beltcalc.design.sizing`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from beltcalc.formulas import belt as bm
from beltcalc.formulas import geometry as geo
from beltcalc.data.catalogs import BeltProfile, ServiceFactors
from beltcalc.design.checks import RULES, Check, failures, percent
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.formulas.belt_capacity import (LAYOUTS, installation_tension_rule, peripheral_force, shaft_load,
                                              specific_tooth_load, tooth_shear_capacity)
from beltcalc.design.motor_peak import MotorPeak

# Fewer than 3 teeth make no pitch polygon: bad input, not a design to check (the makers'
# z_min, 10 and more where the catalogs give one, is the check: ``pulley_teeth``).
MIN_PULLEY_TEETH = 3


def minimum_pulley_teeth_source(belt: BeltProfile) -> str:
    """Where the pulley-teeth limit ``belt.z_min`` comes from, for the check's rule.

    The maker's table gives z_min for a drive without contraflexure and a larger one with
    a backward-bent idler (contraflexure); no idler is modelled here, so the check uses the
    value without contraflexure and says so.
    """
    if not belt.z_min:
        return f"the belt maker's z_min; none in the catalog for {belt.name}"
    bent = (f"; with a contraflexure idler the maker asks z_min = {belt.z_min_contraflexure}, not modelled"
            if belt.z_min_contraflexure else "; a contraflexure idler is not modelled")
    return f"z_min = {belt.z_min} without contraflexure, {belt.source.document}{bent}"


def _class(value: float, bounds: tuple[float, ...], closed_low: bool) -> int:
    """Index of the class of ``value``: bounds b_0 < b_1 < ...; ``closed_low`` puts a value
    equal to a bound into the upper class."""
    for i, b in enumerate(bounds):
        if value < b or (value == b and not closed_low):
            return i
    return len(bounds)


@dataclass(frozen=True)
class ServiceFactor:
    """Service factor c2 and its parts [-] (see :func:`service_factor`)."""

    value: float
    base: float           # Ko (or Ka when larger)
    base_from: str        # "Ko" or "Ka"
    idler: float          # Ki
    speed_up: float       # Ks
    text: str


def service_factor(table: ServiceFactors, load: str, hours: float, peak_ratio: float,
                   starts_per_day: float, idler: str = "none", speed_up_ratio: float = 1.0) -> ServiceFactor:
    r"""Service factor of a synchronous belt drive [Tsubaki belts table 1-4].

    .. math:: c_2 = \max(K_o, K_a) + K_i + K_s

    K_o [Tsubaki belts table 1] by load kind, peak/rated output ratio and hours per day; K_a
    [Tsubaki belts table 4] by the peak ratio and starts-stops per day; K_i idler
    [Tsubaki belts table 2]; K_s [Tsubaki belts table 3] speed-increase ratio. Class limits
    as printed: hours < 3 | 3-10 | > 10; peak ratio <= 200 % | 201-249 % | >= 250 %; starts
    <= 10 | 11-100 | 101-999 | >= 1000; speed-up [1, 1.25) | [1.25, 1.75) | ... Taking the
    larger of K_o and K_a and adding K_i, K_s is our reading of how the tables combine
    (docs/design_checks.md).

    >>> from beltcalc.data.catalogs import load_catalog
    >>> t = load_catalog().service_factor_table("synchronous_belt")
    >>> service_factor(t, "moderate", 8, 2.0, 10).value
    1.4
    >>> service_factor(t, "smooth", 2, 3.0, 2000, "tight_outside", 2.0).value
    2.3
    """
    if load not in table.load_kinds:
        raise InputError(f"{load!r} is not a load kind; use one of {', '.join(table.load_kinds)}", param="load")
    require_range("hours", hours, "h", 0.0, 24.0)
    require_range("peak_ratio", peak_ratio, "", 1.0)
    require_range("starts_per_day", starts_per_day, "", 0.0)
    require_range("speed_up_ratio", speed_up_ratio, "", 1.0)
    if idler not in table.idler:
        raise InputError(f"{idler!r} is not an idler position; use one of {', '.join(table.idler)}", param="idler")
    peak = _class(peak_ratio, table.peak_ratio_bounds, closed_low=False)        # <= 2.0 | (2, 2.5) | >= 2.5
    if peak_ratio == table.peak_ratio_bounds[-1]:
        peak = len(table.peak_ratio_bounds)
    hrs = _class(hours, table.hours_bounds, closed_low=True)                   # < 3 | 3..10 | > 10
    if hours == table.hours_bounds[-1]:
        hrs = len(table.hours_bounds) - 1
    starts = _class(starts_per_day, table.starts_bounds, closed_low=False)     # <= 10 | ... | >= 1000
    k_o = table.base[table.load_kinds.index(load)][peak][hrs]
    k_a = table.start_stop[peak][starts]
    k_i = table.idler[idler]
    k_s = table.speed_up[_class(speed_up_ratio, table.speed_up_bounds, closed_low=True)]
    base, base_from = (k_o, "Ko") if k_o >= k_a else (k_a, "Ka")
    value = round(base + k_i + k_s, 12)
    text = (f"{base_from} = {base:g} ({load} load, {hours:g} h/day, peak {percent(peak_ratio)} of rated, "
            f"{starts_per_day:g} starts/day) + Ki {k_i:g} ({idler}) + Ks {k_s:g} (speed-up {speed_up_ratio:g}); "
            f"{table.source.document}")
    return ServiceFactor(value, base, base_from, k_i, k_s, text)


@dataclass(frozen=True)
class BeltDriveInputs:
    """The drive as the designer knows it, SI. ``teeth_large=None``: equal pulleys.

    The peripheral force F_U is ``force`` if given, else 2 ``torque`` / d_1, else
    2 i T_M / d_1 of a ``motor_size`` run (:class:`MotorPeak`), else
    ``mass`` * ``accel`` + ``friction_force`` (a linear axis). ``pulley_speed`` [rad/s] or
    ``belt_speed`` [m/s] sets the running speed for the F_tspec table. ``pretension`` None:
    the manufacturers' rule. ``service_factor`` None: from the table with ``load`` ...
    """

    layout: str
    teeth: int
    center_distance: float
    width: float
    teeth_large: int | None = None
    force: float | None = None
    torque: float | None = None
    motor_size: MotorPeak | None = None
    mass: float | None = None
    accel: float | None = None
    friction_force: float = 0.0
    pulley_speed: float | None = None
    belt_speed: float | None = None
    pretension: float | None = None
    service_factor: float | None = None
    load: str = "moderate"
    hours: float = 8.0
    peak_ratio: float = 2.0
    starts_per_day: float = 10.0
    idler: str = "none"
    speed_up_ratio: float = 1.0
    stroke: float | None = None
    carriage_length: float = 0.0
    clamp_allowance: float = 0.0
    tension_accel: float = 0.1
    tension_speed: float = 0.005
    f_tspec: float | None = None        # N/m, overrides the catalog table at the running speed


@dataclass(frozen=True)
class WidthTrial:
    width: float
    worst: str
    utilisation: float
    passed: bool


@dataclass(frozen=True)
class WidthSelection:
    rule: str
    tried: tuple[WidthTrial, ...]
    chosen: float


@dataclass(frozen=True)
class BeltDriveReport:
    """Everything :func:`check_belt_drive` computed, SI (see the field comments)."""

    belt: str
    layout: str
    width: float                      # m
    teeth: tuple[int, int]
    diameters: tuple[float, float]    # m, pitch diameters
    wrap: tuple[float, float]         # rad
    span: float                       # m, free span (endless) / return span (linear)
    belt_length: float                # m, pitch length (endless) / cut length (linear)
    belt_teeth: float                 # 1
    stock: tuple[int | None, int | None]
    stock_center_distance: tuple[float | None, float | None]   # m
    linear: geo.LinearAxisGeometry | None
    teeth_in_mesh: float
    teeth_in_mesh_uncapped: float
    force: float                      # N, F_U
    force_source: str
    motor_size: MotorPeak | None      # the motor-size run F_U came from
    service: ServiceFactor
    speed: float | None               # rad/s, small pulley
    belt_speed: float | None          # m/s
    specific_load: float | None       # N/m
    tooth_capacity: float | None      # N
    pretension: float                 # N, F_v used
    pretension_rule: float            # N
    pretension_source: str
    paper_tension: float | None       # N, [W21 eq. 10-12]
    tight: float                      # N
    slack: float                      # N
    shaft_loads: tuple[float, float]  # N, at the small and the large pulley
    f_tadm: float | None
    span_frequency_rule: float | None  # Hz
    span_frequency_paper: float | None  # Hz
    checks: tuple[Check, ...]
    selection: WidthSelection | None = None
    warnings: tuple[str, ...] = field(default=())
    notes: tuple[str, ...] = field(default=())      # what the run decided for the user (a stock length skipped)
    slack_design: float | None = None                # N, endless: slack side at the design load c2 F_U (< 0: slack)


def _force(inp: BeltDriveInputs, d1: float) -> tuple[float, str, list[str]]:
    if inp.force is not None:
        return require_positive("force", inp.force, "N"), "given (force)", []
    if inp.torque is not None:
        return peripheral_force(inp.torque, d1), f"2 T / d1 with T = {inp.torque:g} N m", []
    m = inp.motor_size
    if m is not None:
        require_positive("gear_ratio", m.gear_ratio, "")
        warnings = []
        if not math.isclose(m.pulley_diameter, d1, rel_tol=1e-9):
            warnings.append(f"the motor-size run's driving pulley is d = {m.pulley_diameter * 1e3:.5g} mm, this "
                            f"drive's d1 = {d1 * 1e3:.5g} mm: F_U = 2 i T_M / d1 is for a pulley the torque was not "
                            "sized for (give `teeth` of that pulley, or size the motor for this one)")
        return (peripheral_force(m.pulley_torque, d1),
                f"2 i T_M / d1 with motor-size's peak T_M = {m.torque:.6g} N m and i = {m.gear_ratio:g} "
                f"({m.source}): pulley torque {m.pulley_torque:.6g} N m; conservative, it includes the torque "
                "that accelerates the motor, gearbox and pulleys themselves and takes the gearbox as lossless",
                warnings)
    if inp.mass is not None and inp.accel is not None:
        require_positive("mass", inp.mass, "kg")
        require_positive("accel", inp.accel, "m/s^2")
        require_range("friction_force", inp.friction_force, "N", 0.0)
        return (inp.mass * inp.accel + inp.friction_force,
                f"m a_max + F_R = {inp.mass:g} kg x {inp.accel:g} m/s^2 + {inp.friction_force:g} N", [])
    raise InputError("give the peripheral force: `force`, `torque`, `motor_size`, or `mass` with `accel`",
                     param="force")


def _paper_tension(inp: BeltDriveInputs, belt: BeltProfile, d1: float) -> float | None:
    """F_t,peak of [W21 eq. 10-12] for a linear axis with a mass; None otherwise."""
    if inp.layout != "linear" or inp.mass is None or inp.accel is None:
        return None
    from beltcalc.design.tension import TensionInputs, belt_damping

    row = belt.width_row(inp.width)
    if row.w_spec is None:
        return None
    t_inp = TensionInputs(center_distance=inp.center_distance, width=inp.width, mass=inp.mass, accel=inp.accel,
                          tension_accel=inp.tension_accel, tension_speed=inp.tension_speed, mu=0.2,
                          pulley_diameter=d1)
    teeth = bm.teeth_on_span(inp.center_distance, belt.pitch)
    m_tb = bm.substitute_mass(bm.belt_mass_on_span(row.w_spec, inp.center_distance), teeth)
    damping, _, _ = belt_damping(t_inp, belt, teeth)
    return bm.tension_peak(m_tb, inp.mass, inp.accel, inp.tension_accel, inp.tension_speed, damping)


def check_belt_drive(inp: BeltDriveInputs, belt: BeltProfile, factors: ServiceFactors) -> BeltDriveReport:
    """Geometry and capacity checks of one belt width (see the module references).

    >>> from beltcalc.data.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = BeltDriveInputs(layout="linear", teeth=40, center_distance=1.245, width=0.025,
    ...                       mass=50.0, accel=10.0)
    >>> r = check_belt_drive(inp, cat.belt("AT10"), cat.service_factor_table("synchronous_belt"))
    >>> r.force, r.pretension, round(r.paper_tension, 1), [c.verdict for c in r.checks][:2]
    (500.0, 500.0, 505.1, ['n/a', 'pass'])
    """
    if inp.layout not in LAYOUTS:
        raise InputError(f"{inp.layout!r} is not a layout; use one of {', '.join(LAYOUTS)}", param="layout")
    require_positive("width", inp.width, "m")
    z1 = inp.teeth
    z2 = inp.teeth_large if inp.teeth_large is not None else z1
    for name, z in (("teeth", z1), ("teeth_large", z2)):
        if z != int(z) or z < MIN_PULLEY_TEETH:
            raise InputError(f"{z:g} is not allowed; a pulley needs a whole number of teeth >= {MIN_PULLEY_TEETH}",
                             param=name)
    if z2 < z1:
        raise InputError(f"{z2} teeth: the large pulley must have at least the {z1} teeth of `teeth`",
                         param="teeth_large")
    if inp.layout == "linear" and z2 != z1:
        raise InputError("a linear axis here has equal pulleys; leave `teeth_large` out", param="teeth_large")
    d1, d2 = bm.pulley_pitch_diameter(z1, belt.pitch), bm.pulley_pitch_diameter(z2, belt.pitch)
    a = inp.center_distance
    wrap = geo.wrap_angles(d1, d2, a)
    row = belt.width_row(inp.width)

    linear = None
    if inp.layout == "linear":
        stroke = inp.stroke if inp.stroke is not None else max(a - inp.carriage_length, 0.0)
        linear = geo.linear_axis_geometry(a, d1, inp.carriage_length, stroke, inp.clamp_allowance)
        length, span = linear.belt_length, linear.return_span
        z_belt = geo.belt_teeth(linear.pitch_length, belt.pitch)
        stock, stock_a, notes = (None, None), (None, None), []
    else:
        length, span = geo.belt_pitch_length(d1, d2, a), geo.span_length(d1, d2, a)
        z_belt = geo.belt_teeth(length, belt.pitch)
        stock, stock_a, notes = _stock_lengths(geo.nearest_stock_teeth(z_belt, belt.stock_teeth), d1, d2, belt.pitch)

    z_e_raw = z1 * wrap[0] / (2.0 * math.pi)
    z_e = float(min(z_e_raw, belt.z_e_max)) if belt.z_e_max else z_e_raw   # the maker's z_e max [BRECO]

    force, force_source, force_warnings = _force(inp, d1)
    if inp.service_factor is not None:
        c2 = require_range("service_factor", inp.service_factor, "", 1.0)
        service = ServiceFactor(c2, c2, "given", 0.0, 0.0, "given (service_factor)")
    else:
        service = service_factor(factors, inp.load, inp.hours, inp.peak_ratio, inp.starts_per_day,
                                 inp.idler, inp.speed_up_ratio)

    speed = belt_speed = None
    if inp.pulley_speed is not None:
        speed = require_range("speed", inp.pulley_speed, "rad/s", 0.0)
        belt_speed = speed * d1 / 2.0
    elif inp.belt_speed is not None:
        belt_speed = require_range("speed", inp.belt_speed, "m/s", 0.0)
        speed = 2.0 * belt_speed / d1

    rule = installation_tension_rule(force, inp.layout, service.value)
    if inp.pretension is not None:
        f_v = require_range("pretension", inp.pretension, "N", 0.0)
        pre_src = "given (pretension)"
    else:
        f_v = rule
        pre_src = ("manufacturers' rule F_v = F_U (linear drive, Elatech p. 55)" if inp.layout == "linear"
                   else f"F_v = c2 F_U / 2 with c2 = {service.value:g} (endless: the slack side stays taut, "
                        "T_2 >= 0, up to the design load c2 F_U; Shigley eq. 17-1)")
    slack_design = None
    if inp.layout == "linear":
        tight, slack = f_v + force, f_v          # worst carriage position: the tight side takes all of F_U
    else:
        tight, slack = f_v + force / 2.0, max(f_v - force / 2.0, 0.0)
        slack_design = f_v - service.value * force / 2.0
    loads = (shaft_load(tight, slack, wrap[0]), shaft_load(tight, slack, wrap[1]))
    paper = _paper_tension(inp, belt, d1)

    w_spec = row.w_spec
    freq_rule = bm.span_frequency(f_v, w_spec, span) if w_spec else None
    freq_paper = bm.span_frequency(paper, w_spec, span) if (w_spec and paper is not None) else None

    # --- checks ----------------------------------------------------------------------
    specific = capacity = None
    reason = beyond = ""
    if inp.f_tspec is not None:
        specific = require_positive("f_tspec", inp.f_tspec, "N/m")
    elif not belt.F_tspec:
        reason = f"{belt.name} has no F_tspec(n) table in its catalog; give `f_tspec`"
    elif speed is None:
        reason = "no running speed; give `speed`"
    elif speed > belt.F_tspec[-1][0] * (1.0 + 1e-12):
        beyond = (f"{speed * 30 / math.pi:.6g} rpm is beyond the maker's F_tspec table of {belt.name} (up to "
                  f"{belt.F_tspec[-1][0] * 30 / math.pi:.6g} rpm): the tooth capacity there is not known and the "
                  "table is not extrapolated; give `f_tspec` from the maker for this speed")
    else:
        try:
            specific = specific_tooth_load(belt.F_tspec, speed)
        except InputError as exc:
            reason = exc.message
    if specific is not None:
        capacity = tooth_shear_capacity(specific, inp.width, z_e)
    checks = [
        RULES["belt_tooth_shear"].check(force * service.value, capacity, key="tooth_shear", reason=reason,
                                        unverified=beyond),
        RULES["belt_tension_member"].check(
            force + f_v, row.F_Tadm, key="tension_member", quantity="F_U + F_v",
            reason="" if row.F_Tadm else f"{belt.name} {inp.width * 1e3:g} mm has no published F_Tadm"),
        RULES["pretension_linear" if inp.layout == "linear" else "pretension_endless"].check(
            f_v, rule, key="pretension"),
        RULES["pulley_teeth"].check(float(z1), float(belt.z_min) if belt.z_min else None,
                                    detail=minimum_pulley_teeth_source(belt),
                                    reason="" if belt.z_min else f"the catalog gives no z_min for {belt.name}"),
        RULES["teeth_in_mesh"].check(z_e),
    ]
    warnings = force_warnings + [c.warning() for c in failures(checks)]
    return BeltDriveReport(
        belt=belt.name, layout=inp.layout, width=inp.width, teeth=(z1, z2), diameters=(d1, d2), wrap=wrap,
        span=span, belt_length=length, belt_teeth=z_belt, stock=stock, stock_center_distance=stock_a,
        linear=linear, teeth_in_mesh=z_e, teeth_in_mesh_uncapped=z_e_raw, force=force, force_source=force_source,
        motor_size=inp.motor_size if inp.force is None and inp.torque is None else None, service=service,
        speed=speed, belt_speed=belt_speed, specific_load=specific, tooth_capacity=capacity,
        pretension=f_v, pretension_rule=rule, pretension_source=pre_src, paper_tension=paper, tight=tight,
        slack=slack, shaft_loads=loads, f_tadm=row.F_Tadm, span_frequency_rule=freq_rule,
        span_frequency_paper=freq_paper, checks=tuple(checks), warnings=tuple(warnings), notes=tuple(notes),
        slack_design=slack_design,
    )


def _stock_lengths(stock: tuple[int | None, int | None], d1: float, d2: float,
                   pitch: float) -> tuple[tuple[int | None, int | None], tuple[float | None, float | None], list[str]]:
    """The stock belts either side of the drive's length that fit its pulleys, each with its
    back-solved centre distance; one that cannot fit (shorter than the belt round the two
    pulleys touching) is left out, with a note: it is no error of the drive (issue 28)."""
    teeth, centres, notes = [], [], []
    touching = (d1 + d2) / 2.0
    shortest = geo.belt_pitch_length(d1, d2, touching * (1.0 + 1e-12))
    for side, t in zip(("shorter", "longer"), stock):
        a = None
        if t and t * pitch <= shortest:
            notes.append(f"the {side} stock belt ({t} teeth, {t * pitch * 1e3:.6g} mm) cannot fit these pulleys: "
                         f"the belt round them touching (a = {touching * 1e3:.6g} mm) is {shortest * 1e3:.6g} mm; "
                         "left out")
            t = None
        elif t:
            a = geo.center_distance_for_length(d1, d2, t * pitch)
        teeth.append(t)
        centres.append(a)
    return (teeth[0], teeth[1]), (centres[0], centres[1]), notes


SELECTION_RULE = ("narrowest catalog width whose checks all pass (tooth shear with the service factor, "
                  "tension member F_U + F_v <= F_Tadm, installation tension, pulley and mesh teeth); "
                  "a check that is n/a or unverified does not block a width (an unverified one is reported)")


def select_belt_width(inp: BeltDriveInputs, belt: BeltProfile, factors: ServiceFactors) -> BeltDriveReport:
    """Check every catalog width, narrowest first; return the first that passes, with the
    widths tried and the rule (``report.selection``)."""
    if not belt.widths:
        raise InputError(f"{belt.name} has no width table to select from", param="belt")
    tried = []
    for row in belt.widths:
        report = check_belt_drive(replace(inp, width=row.width), belt, factors)
        rated = [c for c in report.checks if c.utilisation is not None]
        worst = max(rated, key=lambda c: c.utilisation)
        passed = all(c.verdict != "FAIL" for c in report.checks)
        tried.append(WidthTrial(row.width, worst.key, worst.utilisation, passed))
        if passed:
            return replace(report, selection=WidthSelection(SELECTION_RULE, tuple(tried), row.width))
    listed = ", ".join(f"{t.width * 1e3:g} mm ({t.worst} {percent(t.utilisation)})" for t in tried)
    raise InputError(f"no width of {belt.name} passes; tried {listed}; choose a larger profile or lower the load",
                     param="select_width")
