"""Timing-belt substitute model from catalog data: teeth, mass, stiffness, damping, tension.

All functions take and return SI floats. References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
[BRECO] BRECO/BRECOFLEX timing-belt design pages (belt-pilot.com, id=1702): teeth in mesh.
[Gates 508C] Gates 508C sonic tension meter manual: span frequency.
[MISUMI] MISUMI timing pulleys, AT5 pitch-diameter table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

from beltcalc.errors import InputError, require_positive


def teeth_on_span(center_distance: float, pitch: float) -> float:
    r"""Number of belt teeth on a span of length ``center_distance`` [-].

    .. math:: z = a / P + 1

    Parameters
    ----------
    center_distance : float
        Distance between the pulley axes a, [m]
    pitch : float
        Belt pitch P, [m]

    Notes
    -----
    [W21 eq. 14]. Not rounded: the paper uses a/P + 1 as printed (125.5 for the WDU axis).

    Examples
    --------
    >>> teeth_on_span(1.245, 0.010)
    125.5
    """
    require_positive("center_distance", center_distance, "m")
    require_positive("pitch", pitch, "m")
    if center_distance < pitch:
        raise InputError(
            f"{center_distance:g} m is shorter than one belt pitch ({pitch:g} m)",
            param="center_distance",
        )
    return center_distance / pitch + 1.0


def belt_mass_on_span(weight_per_length: float, center_distance: float) -> float:
    r"""Mass of the belt on one span [kg].

    .. math:: m_{belt} = w_{spec} \, a

    Notes
    -----
    [W21 eq. 15].

    Examples
    --------
    >>> round(belt_mass_on_span(0.114, 1.245), 5)
    0.14193
    """
    require_positive("belt_weight", weight_per_length, "kg/m")
    require_positive("center_distance", center_distance, "m")
    return weight_per_length * center_distance


SUBSTITUTE_MASS_MODELS = ("eq7", "rayleigh")


def substitute_mass(belt_mass: float, teeth: float, model: str = "eq7") -> float:
    r"""Substitute mass of the belt span acting at the carriage [kg].

    .. math::
        m_{TB} = \frac{m_{belt} \, z}{2 (z-1)^2} \quad \text{(eq7)}, \qquad
        m_{TB} = m_{belt} / 3 \quad \text{(rayleigh)}

    Parameters
    ----------
    belt_mass : float
        Belt mass on the span m_belt, [kg]
    teeth : float
        Teeth on the span z (> 1), [-]
    model : str
        ``"eq7"`` (default, [W21 eq. 7]) or ``"rayleigh"`` (uniform bar fixed at one
        end, kinetic energy of the linear static deflection shape).

    Notes
    -----
    ``eq7`` is the default because it is the paper's model and reproduces its worked
    example. It comes from lumping the span into z-1 masses whose displacements are
    summed, and it shrinks like m_belt / (2 z) as the span gets longer; the Rayleigh value
    m_belt / 3 is the continuum limit of the same chain and does not depend on the
    tooth count. For tension the difference is negligible (both are grams against a
    carriage of kilograms); for vibration, compare both with the simulator's full chain.

    Examples
    --------
    >>> round(substitute_mass(0.14193, 125.5) * 1e3, 4)
    0.5746
    >>> round(substitute_mass(0.14193, 125.5, "rayleigh") * 1e3, 2)
    47.31
    """
    require_positive("belt_mass", belt_mass, "kg")
    if teeth <= 1:
        raise InputError(f"{teeth:g} teeth on the span; it needs more than 1", param="center_distance")
    if model == "eq7":
        return belt_mass * teeth / (2.0 * (teeth - 1.0) * (teeth - 1.0))   # inf, not OverflowError, when huge
    if model == "rayleigh":
        return belt_mass / 3.0
    raise InputError(f"{model!r} is not a model; use one of {', '.join(SUBSTITUTE_MASS_MODELS)}",
                     param="substitute_mass_model")


def belt_stiffness(specific_stiffness: float, center_distance: float) -> float:
    r"""Substitute stiffness of one belt span [N/m].

    .. math:: \varepsilon = F_{Tadm}/C_{spec}, \quad x = \varepsilon a, \quad
              k_{TB} = F_{Tadm}/x = C_{spec}/a

    Parameters
    ----------
    specific_stiffness : float
        Catalog elasticity C_spec (force per unit strain of the belt width), [N]
    center_distance : float
        Span length a, [m]

    Notes
    -----
    [W21 eq. 16] and the text after it. Linear-elastic belt; the tooth and pulley
    compliance are not included.

    Examples
    --------
    >>> round(belt_stiffness(5.5e5, 1.245))
    441767
    """
    require_positive("c_spec", specific_stiffness, "N")
    require_positive("center_distance", center_distance, "m")
    return specific_stiffness / center_distance


def pulley_pitch_diameter(teeth: int, pitch: float) -> float:
    r"""Pitch diameter of a timing-belt pulley [m].

    .. math:: d_0 = z P / \pi

    Notes
    -----
    Timing-belt formula sheets; [MISUMI AT5 table] (20 teeth: 31.83 mm).

    Examples
    --------
    >>> round(pulley_pitch_diameter(20, 0.005) * 1e3, 2)
    31.83
    >>> round(pulley_pitch_diameter(40, 0.010) * 1e3, 1)
    127.3
    """
    if teeth < 1:
        raise InputError(f"{teeth} pulley teeth; it needs at least 1", param="pulley_teeth")
    require_positive("pitch", pitch, "m")
    return teeth * pitch / math.pi


def teeth_in_mesh(teeth_small: float, teeth_large: float, pitch: float,
                  center_distance: float, z_e_max: float | None = None) -> float:
    r"""Teeth of the small pulley in mesh with the belt [-].

    .. math:: z_e = \frac{z_1}{180^\circ} \arccos\!\left(\frac{P (z_2 - z_1)}{2 \pi a}\right)

    capped at the catalog's maximum ``z_e_max``.

    Notes
    -----
    [BRECO]; not rounded down. For equal pulleys (a linear
    axis) the belt wraps half the pulley: z_e = z_1 / 2.

    Examples
    --------
    >>> teeth_in_mesh(40, 40, 0.010, 1.245)
    20.0
    >>> teeth_in_mesh(40, 40, 0.010, 1.245, z_e_max=12)
    12
    """
    arg = pitch * (teeth_large - teeth_small) / (2.0 * math.pi * center_distance)
    if not -1.0 <= arg <= 1.0:
        raise InputError("the pulleys overlap at this center distance", param="center_distance")
    z_e = teeth_small / 180.0 * math.degrees(math.acos(arg))
    return min(z_e, z_e_max) if z_e_max else z_e


@dataclass(frozen=True)
class DampingFit:
    """Result of :func:`damping_from_tooth_load`: b_TB [N s/m], fit R^2 [-], speeds [m/s]."""

    damping: float
    r_squared: float
    v_min: float
    v_max: float
    points: int


def damping_from_tooth_load(table: Sequence[tuple[float, float]], pulley_diameter: float,
                            width: float, teeth_meshing: float) -> DampingFit:
    r"""Belt damping b_TB fitted to the catalog's specific tooth load F_tspec(n) [N s/m].

    .. math::
        v = \omega D / 2, \quad F_t(v) = F_{tspec}(n) \, W \, z_e, \quad
        F_b(v) = F_t(v) - F_t(0), \quad
        s = \frac{\sum v F_b}{\sum v^2}, \quad b_{TB} = |s|

    Parameters
    ----------
    table : sequence of (float, float)
        Pairs (pulley speed [rad/s], F_tspec [N/m]); the first pair must be at speed 0.
    pulley_diameter : float
        Pitch diameter D of the pulley, [m]
    width : float
        Belt width W, [m]
    teeth_meshing : float
        Teeth in mesh z_e, [-]

    Notes
    -----
    [W21 sec. 3.2] and [W21 Fig. 8]: the fall of the allowable tooth load with speed is
    read as a viscous loss, fitted by least squares with a line through the origin.
    R^2 is 1 - SS_res / SS_tot about the mean of F_b.

    Examples
    --------
    BRECO T20, 25 mm, D = 128 mm, 10 teeth in mesh (0, 1000 and 6500 rpm rows):

    >>> rpm = 2 * math.pi / 60
    >>> fit = damping_from_tooth_load([(0, 10150.), (1000 * rpm, 5720.), (6500 * rpm, 2420.)],
    ...                               0.128, 0.025, 10.0)
    >>> round(fit.damping, 1), round(fit.r_squared, 3)
    (47.2, 0.659)
    """
    require_positive("pulley_diameter", pulley_diameter, "m")
    require_positive("width", width, "m")
    require_positive("teeth_meshing", teeth_meshing, "")
    if len(table) < 2 or table[0][0] != 0.0:
        raise InputError("the F_tspec table needs a row at speed 0 and at least one more row",
                         param="belt")
    v = [omega * pulley_diameter / 2.0 for omega, _ in table]
    force = [load * width * teeth_meshing for _, load in table]
    f_b = [f - force[0] for f in force]
    slope = sum(vi * fi for vi, fi in zip(v, f_b)) / sum(vi * vi for vi in v)
    mean = sum(f_b) / len(f_b)
    ss_res = sum((fi - slope * vi) ** 2 for vi, fi in zip(v, f_b))
    ss_tot = sum((fi - mean) ** 2 for fi in f_b)
    r2 = 1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0
    return DampingFit(abs(slope), r2, min(v), max(v), len(v))


def tension_peak(substitute_mass: float, mass: float, accel: float, tension_accel: float,
                 tension_speed: float, damping: float) -> float:
    r"""Belt force the pretension must cover so the belt stays rigid [N].

    .. math::
        F_{t,peak} = (m_{TB} + m)\,\ddot x_t + b_{TB}\,\dot x_t + m\,a_{max}

    Parameters
    ----------
    substitute_mass : float
        m_TB, [kg]
    mass : float
        Moving mass m (carriage), [kg]
    accel : float
        Peak carriage acceleration a_max, [m/s^2]
    tension_accel : float
        Acceleration of the tensioning motion, [m/s^2]
    tension_speed : float
        Speed of the tensioning motion, [m/s]
    damping : float
        b_TB, [N s/m]

    Notes
    -----
    [W21 eq. 10] with the rigidity condition k_TB x = m a_max of [W21 eq. 11] for the
    spring term. Quasi-static: assumes the belt never goes slack and no creep.

    Examples
    --------
    The paper's WDU axis ([W21 sec. 3.2]): 505.1 N.

    >>> round(tension_peak(0.0005746, 50.0, 10.0, 0.1, 0.005, 20.0), 1)
    505.1
    """
    require_positive("mass", mass, "kg")
    require_positive("accel", accel, "m/s^2")
    for name, value, unit in (("substitute_mass", substitute_mass, "kg"),
                              ("tension_accel", tension_accel, "m/s^2"),
                              ("tension_speed", tension_speed, "m/s"),
                              ("damping", damping, "N*s/m")):
        if not (math.isfinite(value) and value >= 0):
            raise InputError(f"{value:g} {unit} is not allowed; it must be >= 0 {unit}", param=name)
    return (substitute_mass + mass) * tension_accel + damping * tension_speed + mass * accel


def pretension_displacement(force: float, stiffness: float) -> float:
    r"""Displacement to apply to the belt so it carries ``force`` [m].

    .. math:: x_{max} = F_{t,peak} / k_{TB}

    Notes
    -----
    [W21 eq. 12]. Linear belt, no creep. The paper prints 1.15 mm for its example,
    rounding 1.143 mm up.

    Examples
    --------
    >>> round(pretension_displacement(505.1, 441767.0) * 1e3, 3)
    1.143
    """
    require_positive("stiffness", stiffness, "N/m")
    return force / stiffness


def span_frequency(force: float, weight_per_length: float, span_length: float) -> float:
    r"""First transverse natural frequency of a belt span under tension [Hz].

    .. math:: f = \frac{1}{2 L} \sqrt{F / w_{spec}}

    Parameters
    ----------
    force : float
        Span tension F, [N]
    weight_per_length : float
        Belt mass per length w_spec, [kg/m]
    span_length : float
        Free span length L, [m]

    Notes
    -----
    Taut string; what a sonic tension meter reads ([Gates 508C]:
    T = 4 M W S^2 f^2 1e-9). Bending stiffness neglected; Gates advises spans longer
    than 20 pitches.

    Examples
    --------
    >>> round(span_frequency(505.1, 0.114, 1.245), 2)
    26.73
    """
    require_positive("span_length", span_length, "m")
    require_positive("belt_weight", weight_per_length, "kg/m")
    if force < 0:
        raise InputError(f"{force:g} N: a span cannot carry a compressive force", param="force")
    return math.sqrt(force / weight_per_length) / (2.0 * span_length)
