"""Belt tension design of a timing-belt linear axis: the belt's substitute model, the
pretension it needs, the tensioner bolt torque and the span frequency to check it with.

This composes :mod:`beltcalc.belt` and :mod:`beltcalc.screw` with catalog data
(Wojtkowiak et al., Energies 14 (2021) 317, section 3). SI floats only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from beltcalc import belt as bm
from beltcalc.catalogs import BeltProfile, BeltWidth, Thread
from beltcalc.errors import InputError, require_positive
from beltcalc.screw import BoltTorque, bolt_torque
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
    bearing_diameter [m] (VDI 2230 bearing-face term; 0 leaves it out).
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


def _damping(inp: TensionInputs, belt: BeltProfile, teeth: float) -> tuple[float, str, bm.DampingFit | None]:
    if inp.damping is not None:
        if not (math.isfinite(inp.damping) and inp.damping >= 0):
            raise InputError(f"{inp.damping:g} N*s/m is not allowed; it must be >= 0 N*s/m", param="damping")
        return inp.damping, "given (damping)", None
    if belt.F_tspec:
        z_pulley = max(1, round(math.pi * inp.pulley_diameter / belt.pitch))
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

    Eq. (7), (10)-(16) of Wojtkowiak et al. 2021 (see :mod:`beltcalc.belt`) and eq. (13)
    (see :mod:`beltcalc.screw`).

    >>> from beltcalc.catalogs import load_catalog
    >>> cat = load_catalog()
    >>> inp = TensionInputs(center_distance=1.245, width=0.025, mass=50.0, accel=10.0,
    ...                     tension_accel=0.1, tension_speed=0.005, mu=0.2,
    ...                     pulley_diameter=0.128)
    >>> r = design_tension(inp, cat.belt("AT10"), cat.thread("M10x1"))
    >>> round(r.tension_peak, 1), round(r.pretension_displacement * 1e3, 3), round(r.bolt.torque, 2)
    (505.1, 1.143, 0.63)
    """
    require_positive("width", inp.width, "m")
    overrides = (inp.f_tadm, inp.c_spec, inp.belt_weight)
    row = None if (belt.widths == () and None not in overrides) else belt.width_row(inp.width)
    f_tadm = _catalog_value(inp.f_tadm, row, "F_Tadm", "f_tadm", belt, "N")
    w_spec = _catalog_value(inp.belt_weight, row, "w_spec", "belt_weight", belt, "kg/m")

    teeth = bm.teeth_on_span(inp.center_distance, belt.pitch)
    m_belt = bm.belt_mass_on_span(w_spec, inp.center_distance)
    m_tb = bm.substitute_mass(m_belt, teeth, inp.substitute_mass_model)
    if inp.stiffness is not None:
        k_tb = require_positive("stiffness", inp.stiffness, "N/m")
    else:
        c_spec = _catalog_value(inp.c_spec, row, "C_spec", "c_spec", belt, "N")
        k_tb = bm.belt_stiffness(c_spec, inp.center_distance)
    b_tb, b_text, fit = _damping(inp, belt, teeth)

    force = bm.tension_peak(m_tb, inp.mass, inp.accel, inp.tension_accel, inp.tension_speed, b_tb)
    x_max = bm.pretension_displacement(force, k_tb)
    bolt = bolt_torque(force, thread.P, thread.d2, inp.mu, thread.flank_angle,
                       inp.bearing_friction, inp.bearing_diameter)
    span = inp.span_length if inp.span_length is not None else inp.center_distance
    freq = bm.span_frequency(force, w_spec, span)
    util = force / f_tadm

    warnings = []
    if util > 1.0:
        warnings.append(
            f"belt overloaded: F_t,peak = {force:.1f} N is {util:.0%} of F_Tadm = {f_tadm:g} N "
            f"for {belt.name} {inp.width * 1e3:g} mm; choose a wider belt (`select_width`) "
            "or lower `accel` or `mass`"
        )
    if span < 20 * belt.pitch:
        warnings.append(f"span {span * 1e3:g} mm is shorter than 20 pitches: a sonic tension "
                        "meter reads poorly there (Gates 508C manual)")
    return TensionReport(
        belt=belt.name, width=inp.width, thread=thread.name, teeth=teeth, belt_mass=m_belt,
        substitute_mass=m_tb, substitute_mass_model=inp.substitute_mass_model, stiffness=k_tb,
        damping=b_tb, damping_source=b_text, damping_fit=fit, tension_peak=force,
        pretension_displacement=x_max, allowable_tension=f_tadm, utilisation=util, bolt=bolt,
        span_length=span, span_frequency=freq, warnings=tuple(warnings),
    )


def select_width(inp: TensionInputs, belt: BeltProfile, thread: Thread,
                 safety_factor: float = 1.0) -> TensionReport:
    """The narrowest catalog width whose F_Tadm covers ``safety_factor`` * F_t,peak.

    The belt selection of Fig. 5 of Wojtkowiak et al. 2021, on the tension of eq. (10).
    Each width is designed in full, since m_TB and a fitted b_TB depend on it.

    >>> from beltcalc.catalogs import load_catalog
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
