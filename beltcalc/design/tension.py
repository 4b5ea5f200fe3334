"""Belt tension design of a timing-belt linear axis: the belt's substitute model, the
pretension it needs, the tensioner bolt torque and the span frequency to check it with.

This composes :mod:`beltcalc.formulas.belt` and :mod:`beltcalc.formulas.screw` with catalog data
[W21 sec. 3]. SI floats only.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
[VDI 2230] VDI 2230 Part 1 (2015), Systematic calculation of highly stressed bolted joints:
    the bearing-face term of the tightening torque (see :mod:`beltcalc.formulas.screw`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from beltcalc.formulas import belt as bm
from beltcalc.data.catalogs import BeltProfile, BeltWidth, Thread
from beltcalc.design.checks import RULES, Check, failures
from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.formulas.screw import BoltTorque, bolt_torque
from beltcalc.si import convert_fields


@dataclass(frozen=True)
class TensionInputs:
    """What the designer knows, SI units. ``None`` means: take it from the catalog.

    Attributes: center_distance [m], width [m], mass [kg], accel [m/s^2] (peak carriage
    acceleration), tension_accel [m/s^2] and tension_speed [m/s] (of the tensioning
    motion), mu [-] (thread friction), damping [N s/m], pulley_diameter [m] (for the
    damping fit), span_length [m] (for the span frequency; default the center
    distance), stiffness [N/m] (overrides C_spec / a), f_tadm [N], c_spec [N],
    belt_weight [kg/m] (override the catalog row), bearing_friction [-] and
    bearing_diameter [m] ([VDI 2230] bearing-face term; 0 leaves it out).
    """

    center_distance: float
    width: float
    mass: float
    accel: float
    tension_accel: float
    tension_speed: float
    mu: float
    pulley_diameter: float
    damping: float | None = None
    span_length: float | None = None
    substitute_mass_model: str = "eq7"
    stiffness: float | None = None
    f_tadm: float | None = None
    c_spec: float | None = None
    belt_weight: float | None = None
    bearing_friction: float = 0.0
    bearing_diameter: float = 0.0

    def __post_init__(self):
        convert_fields(self, _INPUT_UNITS)


_INPUT_UNITS = {"center_distance": "m", "width": "m", "mass": "kg", "accel": "m/s^2", "tension_accel": "m/s^2",
                "tension_speed": "m/s", "mu": "", "pulley_diameter": "m", "damping": "N*s/m", "span_length": "m",
                "stiffness": "N/m", "f_tadm": "N", "c_spec": "N", "belt_weight": "kg/m", "bearing_friction": "",
                "bearing_diameter": "m"}


@dataclass(frozen=True)
class TensionReport:
    """Everything :func:`design_tension` computed, SI units (see the field comments)."""

    belt: str
    width: float                  # m
    thread: str
    teeth: float                  # 1, teeth on the span
    belt_mass: float              # kg, belt on the span
    substitute_mass: float        # kg, m_TB
    substitute_mass_model: str
    stiffness: float              # N/m, k_TB
    damping: float                # N s/m, b_TB
    damping_source: str
    damping_fit: bm.DampingFit | None
    tension_peak: float           # N
    pretension_displacement: float  # m
    allowable_tension: float      # N, F_Tadm
    utilisation: float            # 1
    bolt: BoltTorque
    span_length: float            # m
    span_frequency: float         # Hz
    warnings: tuple[str, ...] = field(default=())
    checks: tuple[Check, ...] = field(default=())
    belt_weight: float | None = None  # kg/m, w_spec used
    c_spec: float | None = None       # N, C_spec used (None when `stiffness` is given)
    # set by select_width: the rule, and (width [m], safety x F_t,peak / F_Tadm, passed) per width tried
    selection_rule: str = ""
    widths_tried: tuple[tuple[float, float, bool], ...] = field(default=())


def _catalog_value(given: float | None, row: BeltWidth | None, key: str, option: str,
                   belt: BeltProfile, unit: str) -> float:
    if given is not None:
        return require_positive(option, given, unit)
    value = getattr(row, key) if row is not None else None
    if value is None:
        raise InputError(
            f"{belt.name} at this width has no published {key} in {belt.source.path}; "
            f"give it with `{option}`",
            param=option,
        )
    return value


def validate_inputs(inp: TensionInputs) -> None:
    """Every input in its range, also the ones this run does not use (a negative pulley
    diameter is refused even when the damping is not fitted)."""
    for name, unit in (("center_distance", "m"), ("width", "m"), ("mass", "kg"), ("accel", "m/s^2"),
                       ("pulley_diameter", "m")):
        require_positive(name, getattr(inp, name), unit)
    for name, unit in (("tension_accel", "m/s^2"), ("tension_speed", "m/s")):
        require_range(name, getattr(inp, name), unit, low=0.0)
    require_range("mu", inp.mu, "", 0.0, 1.0, low_open=True, high_open=True)
    for name, unit in (("span_length", "m"), ("stiffness", "N/m"), ("f_tadm", "N"), ("c_spec", "N"),
                       ("belt_weight", "kg/m")):
        if getattr(inp, name) is not None:
            require_positive(name, getattr(inp, name), unit)
    if inp.damping is not None:
        require_range("damping", inp.damping, "N*s/m", low=0.0)
    require_range("bearing_friction", inp.bearing_friction, "", 0.0, 1.0, high_open=True)
    require_range("bearing_diameter", inp.bearing_diameter, "m", low=0.0)
    if inp.bearing_friction > 0 and inp.bearing_diameter == 0:
        raise InputError("the bearing-face friction needs the friction diameter under the bolt head: "
                         "give `bearing_diameter`", param="bearing_friction")


def _finite(value: float, what: str, param: str, unit: str) -> float:
    """``value`` if it is finite; else the input ``param`` is out of the range the
    arithmetic can hold: an :class:`InputError` naming it."""
    if math.isfinite(value):
        return value
    shown = "not a number" if math.isnan(value) else f"{'over' if value > 0 else 'below'} {'' if value > 0 else '-'}1e308 {unit}"
    raise InputError(f"{what} is {shown}, beyond what a float holds; give a value in a physical range",
                     param=param)


def belt_damping(inp: TensionInputs, belt: BeltProfile, teeth: float) -> tuple[float, str, bm.DampingFit | None]:
    if inp.damping is not None:
        if not (math.isfinite(inp.damping) and inp.damping >= 0):
            raise InputError(f"{inp.damping:g} N*s/m is not allowed; it must be >= 0 N*s/m", param="damping")
        return inp.damping, "given (damping)", None
    if belt.F_tspec:
        z_pulley = max(1, round(_finite(math.pi * inp.pulley_diameter / belt.pitch, "the pulley's tooth count",
                                        "pulley_diameter", "")))
        z_e = bm.teeth_in_mesh(z_pulley, z_pulley, belt.pitch, inp.center_distance, belt.z_e_max)
        fit = bm.damping_from_tooth_load(belt.F_tspec, inp.pulley_diameter, inp.width, z_e)
        cap = "" if belt.z_e_max else ", no z_e max in the catalog"
        text = (f"fitted to the catalog's F_tspec(n): D = {inp.pulley_diameter * 1e3:g} mm, "
                f"{z_pulley} pulley teeth, z_e = {z_e:g}{cap}, v = {fit.v_min:g}..{fit.v_max:.3g} m/s, "
                f"R^2 = {fit.r_squared:.3f}")
        return fit.damping, text, fit
    if belt.damping is not None:
        return belt.damping, f"catalog value: {belt.damping_source or belt.source}", None
    raise InputError(
        f"{belt.name} has no F_tspec(n) table and no damping value in its catalog; give `damping`",
        param="damping",
    )


def design_tension(inp: TensionInputs, belt: BeltProfile, thread: Thread) -> TensionReport:
    """Substitute model, pretension, bolt torque and span frequency of one belt width.

    [W21 eq. 7, 10-16] (see :mod:`beltcalc.formulas.belt`) and [W21 eq. 13] (see
    :mod:`beltcalc.formulas.screw`).

    >>> from beltcalc.data.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = TensionInputs(center_distance=1.245, width=0.025, mass=50.0, accel=10.0,
    ...                     tension_accel=0.1, tension_speed=0.005, mu=0.2,
    ...                     pulley_diameter=0.128)
    >>> r = design_tension(inp, cat.belt("AT10"), cat.thread("M10x1"))
    >>> round(r.tension_peak, 1), round(r.pretension_displacement * 1e3, 3), round(r.bolt.torque, 2)
    (505.1, 1.143, 0.63)
    """
    validate_inputs(inp)
    overrides = (inp.f_tadm, inp.c_spec, inp.belt_weight)
    row = None if (belt.widths == () and None not in overrides) else belt.width_row(inp.width)
    f_tadm = _catalog_value(inp.f_tadm, row, "F_Tadm", "f_tadm", belt, "N")
    w_spec = _catalog_value(inp.belt_weight, row, "w_spec", "belt_weight", belt, "kg/m")

    a = inp.center_distance
    teeth = bm.teeth_on_span(a, belt.pitch)
    m_belt = _finite(bm.belt_mass_on_span(w_spec, a), "the belt mass on the span w_spec a", "center_distance", "kg")
    m_tb = _finite(bm.substitute_mass(m_belt, teeth, inp.substitute_mass_model), "the substitute mass m_TB",
                   "center_distance", "kg")
    c_spec = None
    if inp.stiffness is not None:
        k_tb = inp.stiffness
    else:
        c_spec = _catalog_value(inp.c_spec, row, "C_spec", "c_spec", belt, "N")
        k_tb = bm.belt_stiffness(c_spec, a)
        if k_tb == 0:
            raise InputError(f"{a:g} m makes k_TB = C_spec / a zero; give a value in a physical range",
                             param="center_distance")
    b_tb, b_text, fit = belt_damping(inp, belt, teeth)

    force = _finite(bm.tension_peak(m_tb, inp.mass, inp.accel, inp.tension_accel, inp.tension_speed, b_tb),
                    "F_t,peak (lower `accel`, `tension_accel` or `tension_speed`)", "mass", "N")
    x_max = _finite(bm.pretension_displacement(force, k_tb), "the pretension displacement x_max = F_t,peak / k_TB",
                    "stiffness" if inp.stiffness is not None else "center_distance", "m")
    bolt = bolt_torque(force, thread.P, thread.d2, inp.mu, thread.flank_angle,
                       inp.bearing_friction, inp.bearing_diameter)
    _finite(bolt.torque, "the bolt torque", "bearing_diameter" if inp.bearing_friction else "mass", "N*m")
    span = inp.span_length if inp.span_length is not None else a
    freq = bm.span_frequency(force, w_spec, span)
    util = force / f_tadm

    checks = tension_checks(belt, inp, force, f_tadm, m_belt, fit)
    warnings = [c.warning() for c in failures(checks)]
    if span < 20 * belt.pitch:
        warnings.append(f"span {span * 1e3:g} mm is shorter than 20 pitches: a sonic tension "
                        "meter reads poorly there (Gates 508C manual)")
    return TensionReport(
        belt=belt.name, width=inp.width, thread=thread.name, teeth=teeth, belt_mass=m_belt,
        substitute_mass=m_tb, substitute_mass_model=inp.substitute_mass_model, stiffness=k_tb,
        damping=b_tb, damping_source=b_text, damping_fit=fit, tension_peak=force,
        pretension_displacement=x_max, allowable_tension=f_tadm, utilisation=util, bolt=bolt,
        span_length=span, span_frequency=freq, warnings=tuple(warnings), checks=tuple(checks),
        belt_weight=w_spec, c_spec=c_spec,
    )


def tension_checks(belt: BeltProfile, inp: TensionInputs, force: float, f_tadm: float, m_belt: float,
                   fit: bm.DampingFit | None) -> list[Check]:
    """The checks of a tension design: the belt's allowable tension, the damping fit's
    quality and the belt's mass against the carriage's (a plausibility check).

    >>> from beltcalc.data.catalogs import load_catalog
    >>> inp = TensionInputs(center_distance=1.245, width=0.025, mass=50.0, accel=10.0,
    ...                     tension_accel=0.1, tension_speed=0.005, mu=0.2, pulley_diameter=0.128)
    >>> [(c.key, c.verdict) for c in tension_checks(load_catalog().belt("AT10"), inp, 505.1, 2200.0, 0.142, None)]
    [('belt_tension', 'pass'), ('damping_fit', 'n/a'), ('belt_mass', 'pass')]
    """
    where = f"{belt.name} {inp.width * 1e3:g} mm"
    tadm_from = "given (`f_tadm`)" if inp.f_tadm is not None else f"the catalog ({belt.source.document})"
    checks = [RULES["belt_tension_member"].check(
        force, f_tadm, key="belt_tension", name=f"belt tension ({where})", quantity="F_t,peak",
        detail=f"F_Tadm from {tadm_from}; above it the belt is overloaded: choose a wider belt (`select_width`) "
               "or lower `accel` or `mass`")]
    fit_detail = "give `damping` from a measurement"
    if fit is not None:
        checks.append(RULES["damping_fit"].check(fit.r_squared, detail=fit_detail))
    else:
        why = "b_TB is given (`damping`)" if inp.damping is not None else "b_TB is the catalog's value, not fitted"
        checks.append(RULES["damping_fit"].check(None, detail=fit_detail, reason=why))
    checks.append(RULES["belt_mass"].check(
        m_belt, inp.mass, name="belt mass on the span",
        detail="m_belt on the span, against the moving mass `mass`: a belt heavier than what it moves is outside "
               "that model (check `center_distance`)"))
    return checks


def select_width(inp: TensionInputs, belt: BeltProfile, thread: Thread,
                 safety_factor: float = 1.0) -> TensionReport:
    """The narrowest catalog width whose F_Tadm covers ``safety_factor`` * F_t,peak.

    The belt selection of [W21 Fig. 5], on the tension of [W21 eq. 10].
    Each width is designed in full, since m_TB and a fitted b_TB depend on it.

    >>> from beltcalc.data.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = TensionInputs(center_distance=1.245, width=0.0, mass=50.0, accel=10.0,
    ...                     tension_accel=0.1, tension_speed=0.005, mu=0.2,
    ...                     pulley_diameter=0.128)
    >>> select_width(inp, cat.belt("AT10"), cat.thread("M10x1"), 3.0).width
    0.025
    """
    require_positive("safety_factor", safety_factor, "")
    rows = [r for r in belt.widths if r.F_Tadm is not None or inp.f_tadm is not None]
    if not rows:
        raise InputError(f"{belt.name} has no width table with F_Tadm to select from", param="belt")
    report = None
    tried = []
    rule = (f"narrowest catalog width with F_Tadm >= safety factor x F_t,peak (safety factor "
            f"{safety_factor:g}; eq. 10-12 of Wojtkowiak et al. 2021, widths tried narrowest first)")
    for row in rows:
        report = design_tension(replace(inp, width=row.width), belt, thread)
        need = safety_factor * report.tension_peak / report.allowable_tension
        tried.append((row.width, need, need <= 1.0))
        if report.allowable_tension >= safety_factor * report.tension_peak:
            return replace(report, selection_rule=rule, widths_tried=tuple(tried))
    widest = rows[-1].width
    raise InputError(
        f"no width of {belt.name} carries {safety_factor:g} x F_t,peak = "
        f"{safety_factor * report.tension_peak:.1f} N (widest {widest * 1e3:g} mm has F_Tadm "
        f"{report.allowable_tension:g} N); choose a larger profile or lower the load",
        param="safety_factor",
    )
