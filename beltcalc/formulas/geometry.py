"""Geometry of an open two-pulley belt drive and of a timing-belt linear axis. SI floats only.

References:

[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011): wrap angles theta_d = pi -/+ 2 asin((D - d) / (2 C)) and the exact
    open-belt length L = sqrt(4 C^2 - (D - d)^2) + (D theta_D + d theta_d) / 2
    [Shigley eq. 17-1].
[Tsubaki belts] Tsubakimoto Chain, technical data, synchronous belts, "Official list"
    [Tsubaki belts formula sheet]: the approximate belt length
    L = 2 C + 1.57 (D + d) + (D - d)^2 / (4 C), its inverse, and z_m = N Phi / 360 deg.
[BRECO] BRECO/BRECOFLEX timing-belt design pages (belt-pilot.com, id=1702): L = z_B P.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from beltcalc.errors import InputError, require_positive, require_range

MAX_ITERATIONS = 100   # Newton steps of the centre-distance back-solve (quadratic: < 10 used)


def _check(small: float, large: float, center_distance: float) -> None:
    require_positive("pulley_diameter", small, "m")
    require_positive("pulley_diameter", large, "m")
    require_positive("center_distance", center_distance, "m")
    if center_distance <= (small + large) / 2:
        raise InputError(f"{center_distance:g} m: the pulleys ({small:g} m and {large:g} m) touch or overlap; "
                         f"it must be > {(small + large) / 2:g} m", param="center_distance")


def open_belt_angle(small: float, large: float, center_distance: float) -> float:
    r"""Angle of the free spans against the line of centres [rad].

    .. math:: \beta = \arcsin\frac{d_2 - d_1}{2 a}

    d_1, d_2 pitch diameters [m] (either order: the sign follows d_2 - d_1), a centre
    distance [m]. [Shigley eq. 17-1]. Valid while the pulleys do not overlap.

    >>> open_belt_angle(0.1, 0.1, 0.5)
    0.0
    >>> round(math.degrees(open_belt_angle(0.1, 0.3, 0.5)), 4)
    11.537
    """
    _check(min(small, large), max(small, large), center_distance)
    return math.asin((large - small) / (2.0 * center_distance))


def wrap_angles(small: float, large: float, center_distance: float) -> tuple[float, float]:
    r"""Wrap angles of the belt on the small and the large pulley [rad].

    .. math:: \alpha_1 = \pi - 2\beta, \quad \alpha_2 = \pi + 2\beta

    [Shigley eq. 17-1] (theta_d, theta_D).

    >>> [round(math.degrees(x), 3) for x in wrap_angles(0.1, 0.3, 0.5)]
    [156.926, 203.074]
    """
    beta = open_belt_angle(small, large, center_distance)
    return math.pi - 2.0 * beta, math.pi + 2.0 * beta


def span_length(small: float, large: float, center_distance: float) -> float:
    r"""Free length of each span of an open belt, tangent point to tangent point [m].

    .. math:: s = a \cos\beta = \tfrac12 \sqrt{4 a^2 - (d_2 - d_1)^2}

    [Shigley eq. 17-1], first term.

    >>> round(span_length(0.1, 0.3, 0.5), 6)
    0.489898
    """
    return center_distance * math.cos(open_belt_angle(small, large, center_distance))


def belt_pitch_length(small: float, large: float, center_distance: float) -> float:
    r"""Exact pitch length of an open belt around two pulleys [m].

    .. math:: L = 2 a \cos\beta + \frac{\pi}{2}(d_1 + d_2) + \beta (d_2 - d_1)

    d_1, d_2 pitch diameters [m], a centre distance [m]. [Shigley eq. 17-1]: two
    tangent spans plus the arcs d_1 alpha_1 / 2 and d_2 alpha_2 / 2. Equal pulleys give
    2 a + pi d.

    >>> round(belt_pitch_length(0.1273, 0.1273, 1.245), 6)
    2.889925
    >>> round(belt_pitch_length(0.1, 0.3, 0.5), 6)
    1.648386
    """
    beta = open_belt_angle(small, large, center_distance)
    return (2.0 * center_distance * math.cos(beta) + math.pi * (small + large) / 2.0
            + beta * (large - small))


def center_distance_approx(small: float, large: float, length: float) -> float:
    r"""Centre distance from the belt length by the manufacturers' approximate formula [m].

    .. math:: B = L - \frac{\pi}{2}(d_1 + d_2), \quad
              a \approx \frac{B + \sqrt{B^2 - 2 (d_2 - d_1)^2}}{4}

    [Tsubaki belts formula sheet] (Tsubaki prints 1.57 for pi/2). It inverts L = 2a + pi (d1+d2)/2 +
    (d2-d1)^2/(4a), which drops terms of order beta^4; it is the start of the exact
    back-solve :func:`center_distance_for_length`.

    >>> round(center_distance_approx(0.1, 0.3, 1.648386), 5)
    0.50003
    """
    b = length - math.pi * (small + large) / 2.0
    disc = b * b - 2.0 * (large - small) ** 2
    if b <= 0 or disc < 0:
        raise InputError(f"a belt of {length:g} m is too short to wrap pulleys of {small:g} m and {large:g} m",
                         param="belt_length")
    return (b + math.sqrt(disc)) / 4.0


def center_distance_for_length(small: float, large: float, length: float) -> float:
    r"""Centre distance at which an open belt of pitch length ``length`` fits exactly [m].

    Solves :func:`belt_pitch_length` (a) = L for a. The derivative is dL/da = 2 cos(beta)
    (the beta terms cancel since 2 a sin(beta) = d_2 - d_1), so L(a) is strictly
    increasing on a > (d_1 + d_2)/2 and the root is unique. Newton's method from the
    approximate formula of :func:`center_distance_approx`, safeguarded by bisection on
    the bracket [(d_1 + d_2)/2, L/2], at most ``MAX_ITERATIONS`` steps; converged when the
    step is below 1e-15 of a. [Shigley eq. 17-1] for L(a).

    >>> L = belt_pitch_length(0.1, 0.3, 0.5)
    >>> abs(center_distance_for_length(0.1, 0.3, L) - 0.5) < 1e-14
    True
    """
    require_positive("pulley_diameter", small, "m")
    require_positive("pulley_diameter", large, "m")
    require_positive("belt_length", length, "m")
    d1, d2 = min(small, large), max(small, large)
    lo, hi = (d1 + d2) / 2.0 * (1.0 + 1e-12), length / 2.0
    if hi <= lo or belt_pitch_length(d1, d2, lo) >= length:
        shortest = belt_pitch_length(d1, d2, lo)
        raise InputError(f"{length:g} m is too short: the shortest belt around pulleys of {d1:g} m and "
                         f"{d2:g} m (touching) is {shortest:.6g} m", param="belt_length")
    try:
        a = min(max(center_distance_approx(d1, d2, length), lo), hi)
    except InputError:
        a = (lo + hi) / 2.0
    for _ in range(MAX_ITERATIONS):
        f = belt_pitch_length(d1, d2, a) - length
        if f == 0.0:
            return a
        if f > 0:
            hi = a
        else:
            lo = a
        new = a - f / (2.0 * math.cos(open_belt_angle(d1, d2, a)))
        if not lo < new < hi:
            new = (lo + hi) / 2.0
        if abs(new - a) <= 2e-16 * a:
            return new
        a = new
    raise InputError(f"the centre distance for a {length:g} m belt did not converge in {MAX_ITERATIONS} steps",
                     param="belt_length")


def belt_teeth(length: float, pitch: float) -> float:
    r"""Teeth on a belt of pitch length L: :math:`z_B = L / P` [-] (not rounded).

    [Tsubaki belts formula sheet], [BRECO formula sheet] (L = z_B P).

    >>> belt_teeth(2.88, 0.010)
    288.0
    """
    require_positive("belt_length", length, "m")
    require_positive("pitch", pitch, "m")
    return length / pitch


def nearest_stock_teeth(teeth: float, stock: tuple[int, ...] = ()) -> tuple[int | None, int | None]:
    """The stock tooth counts just below and just above ``teeth`` (equal if it is one).

    With no stock list (an open-length belt joined to length) every whole number of teeth
    is a stock length: floor and ceiling. ``None`` where the list has no length on that side.

    >>> nearest_stock_teeth(288.99)
    (288, 289)
    >>> nearest_stock_teeth(150.0, (100, 150, 200))
    (150, 150)
    >>> nearest_stock_teeth(250.0, (100, 150, 200))
    (200, None)
    """
    if not stock:
        low = math.floor(teeth + 1e-9)
        high = math.ceil(teeth - 1e-9)
        return low, high
    below = [t for t in stock if t <= teeth + 1e-9]
    above = [t for t in stock if t >= teeth - 1e-9]
    return (below[-1] if below else None), (above[0] if above else None)


@dataclass(frozen=True)
class LinearAxisGeometry:
    """Belt of a linear axis (open belt clamped to the carriage at both ends), SI [m]."""

    belt_length: float      # m, cut length including both clamp allowances
    pitch_length: float     # m, belt between the clamps (pitch line)
    return_span: float      # m, the free span that does not carry the carriage
    span_min: float         # m, shortest carriage-side span (at either end of the stroke)
    span_max: float         # m, the other carriage-side span at that end of the stroke
    free_travel: float      # m, a - carriage length: room for the stroke


def linear_axis_geometry(center_distance: float, pulley_diameter: float, carriage_length: float,
                         stroke: float, clamp_allowance: float) -> LinearAxisGeometry:
    r"""Belt length and span lengths of a linear axis at the ends of its stroke.

    The belt runs from one clamp on the carriage round both (equal) pulleys back to the
    other clamp:

    .. math::
        L_p = 2 a + \pi d - l_c, \quad L_{cut} = L_p + 2 l_{clamp}, \quad
        s_{min} = (a - l_c - s)/2, \quad s_{max} = s_{min} + s

    a centre distance, d pulley pitch diameter, l_c the carriage length between the clamp
    points, l_clamp the belt length held in each clamp, s the stroke, centred in the free
    travel a - l_c. [Shigley eq. 17-1] with beta = 0 (equal pulleys: spans a, arcs pi d / 2).

    >>> g = linear_axis_geometry(1.245, 0.1273, 0.2, 0.8, 0.05)
    >>> round(g.pitch_length, 5), round(g.belt_length, 5), round(g.span_min, 4), round(g.span_max, 4)
    (2.68992, 2.78992, 0.1225, 0.9225)
    """
    require_positive("center_distance", center_distance, "m")
    require_positive("pulley_diameter", pulley_diameter, "m")
    require_range("carriage_length", carriage_length, "m", 0.0, center_distance, high_open=True)
    require_range("clamp_allowance", clamp_allowance, "m", 0.0)
    free = center_distance - carriage_length
    require_range("stroke", stroke, "m", 0.0, free)
    pitch_length = 2.0 * center_distance + math.pi * pulley_diameter - carriage_length
    s_min = (free - stroke) / 2.0
    return LinearAxisGeometry(belt_length=pitch_length + 2.0 * clamp_allowance, pitch_length=pitch_length,
                              return_span=center_distance, span_min=s_min, span_max=s_min + stroke,
                              free_travel=free)
