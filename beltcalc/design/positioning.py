"""Static positioning error of a belt-driven linear axis: how far a carriage clamped to a
timing belt gives way under a force while the motor holds the drive pulley still.

The belt runs from the drive pulley to the carriage (span 1, length L_1), on from the
carriage round the free idler and back to the drive pulley (span 2, length L_2). With the
drive pulley held, the two spans pull on the carriage as two springs in parallel; the belt
on the drive pulley, held by the teeth in mesh, gives way by the teeth's deflection in
series with them; the tooth clearance (backlash) of the drive pulley adds its play.

- each span is a spring C_spec / L [W21 eq. 16] (elongation eps = F / C_spec, x = eps L);
  the belt's elongation under the force is the first error of a linear drive [BRECOflex23];
- the two spans act in parallel on the carriage and share the force as their stiffnesses
  (statics; the same two-path stiffness as :func:`beltcalc.sim.scenes.linear_axis.span_stiffness`);
- the teeth in mesh on the drive pulley carry the whole force and deflect in series with the
  spans: a stiffness per tooth c_t times the teeth in mesh z_e (ours: no maker's c_t was found);
- the drive pulley's backlash and the belt's length tolerance are further errors of a linear
  drive [BRECOflex23]; the maker sums the errors statistically, as a root sum of squares;
  the worst case is their plain sum;
- the pretension must keep the unloaded span taut: linear drives F_TV >= F_U [Elatech p. 55],
  a bound the exact share of this model never exceeds.

SI floats only. Positive forces pull the carriage away from the drive pulley (they stretch
span 1 and relieve span 2); negative forces push it towards the drive pulley.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: k_TB = C_spec / a [W21 eq. 16], x_max = F / k_TB
    [W21 eq. 12]; worked example F_t,peak = 505.1 N, x_max = 1.14 mm (AT10, 25 mm, a = 1245 mm).
[BRECOflex23] BRECOflex CO., "Timing Belt Repeatability for Linear Drives", blog, 21 April
    2023 (brecoflex.com/blog/timing-belt-repeatability-for-linear-drives): the error
    components of a linear drive (belt elongation under the static-friction, dynamic and
    applied forces; drive pulley backlash; length tolerance, generally 0.1 mm per m of
    travel), summed as a statistical estimate.
[Elatech] Elatech timing-belt catalogue (Goodyear Elatech PT belt division), as recorded in
    ../shared/data/SOURCED_DATA.md: linear drives F_TV >= F_U [Elatech p. 55].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range


@dataclass(frozen=True)
class PositionError:
    """The static error of the carriage at one position, SI units (see the field comments).

    ``total`` is the worst case (every error in the same direction); ``rss`` the maker's
    statistical sum [BRECOflex23]. ``mesh_stiffness`` is None where no tooth stiffness was given
    (then ``tooth`` is 0 and ``stiffness`` is the spans' alone).
    """

    force: float                # N, signed (> 0: away from the drive pulley)
    span1: float                # m, L_1: drive pulley to carriage
    span2: float                # m, L_2: carriage round the idler back to the drive pulley
    span_stiffness: float       # N/m, C_spec (1/L_1 + 1/L_2)
    mesh_stiffness: float | None  # N/m, z_e c_t
    stiffness: float            # N/m, spans and mesh in series
    stretch: float              # m, |F| / span_stiffness
    tooth: float                # m, |F| / mesh_stiffness
    backlash: float             # m, the drive pulley's play
    length_tolerance: float     # m, the belt's length (pitch) tolerance over the travel
    total: float                # m, stretch + tooth + backlash + length_tolerance
    rss: float                  # m, root sum of squares of the four
    tension_change1: float      # N, change of span 1's tension (> 0: tighter)
    tension_change2: float      # N, change of span 2's tension
    min_pretension: float       # N, least pretension that keeps both spans taut under this force


def span_lengths(center_distance: float, pulley_diameter: float, position: float) -> tuple[float, float]:
    r"""The two spans at the carriage, (L_1, L_2) [m], for equal drive and idler pulleys.

    .. math:: L_2 = 2 a - L_1 + \pi D / 2

    ``position`` is L_1, the free span from the drive pulley's tangent point to the carriage's
    clamp (0 < L_1 <= a); L_2 runs on to the idler, half round it and back along the return
    side to the drive pulley. The belt on the held drive pulley is not counted (the teeth hold
    it). The same geometry as :func:`beltcalc.sim.scenes.linear_axis.span_stiffness`.

    Examples
    --------
    >>> [round(x, 4) for x in span_lengths(1.245, 0.128, 0.5)]
    [0.5, 2.191]
    """
    require_positive("center_distance", center_distance, "m")
    require_positive("pulley_diameter", pulley_diameter, "m")
    require_range("position", position, "m", 0.0, center_distance, low_open=True)
    return position, 2.0 * center_distance - position + math.pi * pulley_diameter / 2.0


def span_pair_stiffness(specific_stiffness: float, span1: float, span2: float) -> float:
    r"""Stiffness of the carriage on the two belt spans in parallel [N/m].

    .. math:: k = \frac{C_{spec}}{L_1} + \frac{C_{spec}}{L_2} = C_{spec} \frac{L_1 + L_2}{L_1 L_2}

    Parameters
    ----------
    specific_stiffness : float
        The belt's specific stiffness C_spec (force per unit strain, for its width), [N]
    span1, span2 : float
        Lengths of the spans on either side of the carriage, [m]

    Notes
    -----
    Each span is C_spec / L [W21 eq. 16]; the two act in parallel on the carriage while the
    drive pulley is held. With one span fixed the other's stiffness C_spec / L is [W21 eq. 16]
    alone; equal spans L give 2 C_spec / L.

    Examples
    --------
    AT10, 25 mm (C_spec = 5.5e5 N), the carriage 0.5 m from the drive pulley of the WDU axis:

    >>> round(span_pair_stiffness(5.5e5, 0.5, 2.191) / 1e6, 4)
    1.351
    """
    require_positive("specific_stiffness", specific_stiffness, "N")
    require_positive("span1", span1, "m")
    require_positive("span2", span2, "m")
    return specific_stiffness / span1 + specific_stiffness / span2


def tension_changes(force: float, span1: float, span2: float) -> tuple[float, float]:
    r"""How a force on the carriage changes the two spans' tensions, (dT_1, dT_2) [N].

    .. math:: \Delta T_1 = F \frac{L_2}{L_1 + L_2}, \quad \Delta T_2 = -F \frac{L_1}{L_1 + L_2}

    The spans share the force as their stiffnesses C_spec / L [W21 eq. 16]: the shorter one
    takes the larger part. dT_1 - dT_2 = F is what the teeth of the held drive pulley carry.

    Examples
    --------
    >>> [round(t, 2) for t in tension_changes(500.0, 0.5, 2.191)]
    [407.1, -92.9]
    """
    require_range("force", force, "N")
    require_positive("span1", span1, "m")
    require_positive("span2", span2, "m")
    total = span1 + span2
    return force * span2 / total, -force * span1 / total


def min_pretension(force: float, span1: float, span2: float, reversing: bool = True) -> float:
    r"""Least pretension that keeps both spans taut under the force on the carriage [N].

    .. math:: F_{TV} \ge |F| \frac{\max(L_1, L_2)}{L_1 + L_2} \quad \text{(reversing)}

    Without ``reversing`` only the signed force counts: F L_1 / (L_1 + L_2) for F > 0 (span 2
    is relieved), -F L_2 / (L_1 + L_2) for F < 0 (span 1 is relieved).

    Notes
    -----
    From :func:`tension_changes`. The makers' rule for linear drives, F_TV >= F_U [Elatech p. 55],
    is the limit as the carriage reaches a pulley (one span of length 0); this model's share is
    never above it. Belt mass, sag and the pretension's own effect on the tooth mesh are left out.

    Examples
    --------
    >>> round(min_pretension(500.0, 0.5, 2.191), 2), round(min_pretension(500.0, 0.5, 2.191, reversing=False), 2)
    (407.1, 92.9)
    """
    d1, d2 = tension_changes(force, span1, span2)
    if reversing:
        return max(abs(d1), abs(d2))
    return max(-d1, -d2, 0.0)


def _mesh(tooth_stiffness: float | None, teeth_in_mesh: float | None) -> float | None:
    if tooth_stiffness is None and teeth_in_mesh is None:
        return None
    if tooth_stiffness is None or teeth_in_mesh is None:
        missing = "tooth_stiffness" if tooth_stiffness is None else "teeth_in_mesh"
        raise InputError(f"the tooth deflection needs both `tooth_stiffness` and `teeth_in_mesh`; give `{missing}` "
                         "too, or neither to leave the tooth term out", param=missing)
    require_positive("tooth_stiffness", tooth_stiffness, "N/m")
    require_positive("teeth_in_mesh", teeth_in_mesh, "")
    return tooth_stiffness * teeth_in_mesh


def static_error(force: float, specific_stiffness: float, span1: float, span2: float,
                 tooth_stiffness: float | None = None, teeth_in_mesh: float | None = None,
                 backlash: float = 0.0, length_tolerance: float = 0.0,
                 pretension: float | None = None) -> PositionError:
    r"""Static positioning error of the carriage under ``force`` with the drive pulley held.

    .. math::
        k_s = C_{spec} \left(\frac{1}{L_1} + \frac{1}{L_2}\right), \quad
        k_m = z_e c_t, \quad
        \delta = \frac{|F|}{k_s} + \frac{|F|}{k_m} + b + \delta_L

    Parameters
    ----------
    force : float
        Force on the carriage along the belt, [N]; > 0 away from the drive pulley
    specific_stiffness : float
        The belt's specific stiffness C_spec for its width, [N] (catalog ``C_spec``)
    span1, span2 : float
        The spans either side of the carriage (see :func:`span_lengths`), [m]
    tooth_stiffness : float, optional
        Stiffness of one belt tooth in mesh for the belt's width, c_t, [N/m]; with
        ``teeth_in_mesh`` z_e [-] on the drive pulley. Neither given: no tooth term.
    backlash : float
        Play between belt teeth and the drive pulley's grooves, b, [m] (the maker's table)
    length_tolerance : float
        The belt's length tolerance over the travel, delta_L, [m]
    pretension : float, optional
        Installed span tension F_TV, [N]; given, a force that would slacken a span is refused

    Returns
    -------
    PositionError
        The components, their worst-case sum and root sum of squares, the stiffnesses and
        the spans' tension changes.

    Notes
    -----
    Span stretch: [W21 eq. 16] per span, the spans in parallel; the elongation, backlash and
    length tolerance are the error components of [BRECOflex23], whose statistical estimate is
    ``rss``. The tooth term is a series spring of ours (no published tooth stiffness was
    found). Linear-elastic belt, no creep, no friction in the guide or idler, idler free,
    belt mass and sag left out; the pulley's backlash counts once (one reversal of the force).

    Examples
    --------
    AT10, 25 mm, 500 N, the carriage 0.5 m from the drive pulley of the WDU axis:

    >>> e = static_error(500.0, 5.5e5, 0.5, 2.191)
    >>> round(e.stretch * 1e3, 4), round(e.tension_change2, 1), round(e.min_pretension, 1)
    (0.3701, -92.9, 92.9)
    """
    require_range("force", force, "N")
    k_s = span_pair_stiffness(specific_stiffness, span1, span2)
    k_m = _mesh(tooth_stiffness, teeth_in_mesh)
    require_range("backlash", backlash, "m", low=0.0)
    require_range("length_tolerance", length_tolerance, "m", low=0.0)
    d1, d2 = tension_changes(force, span1, span2)
    if pretension is not None:
        require_range("pretension", pretension, "N", low=0.0)
        _check_taut(force, pretension, span1, span2, d1, d2)
    stretch = abs(force) / k_s
    tooth = abs(force) / k_m if k_m is not None else 0.0
    parts = (stretch, tooth, backlash, length_tolerance)
    stiffness = k_s if k_m is None else 1.0 / (1.0 / k_s + 1.0 / k_m)
    return PositionError(force=force, span1=span1, span2=span2, span_stiffness=k_s, mesh_stiffness=k_m,
                         stiffness=stiffness, stretch=stretch, tooth=tooth, backlash=backlash,
                         length_tolerance=length_tolerance, total=sum(parts),
                         rss=math.sqrt(sum(p * p for p in parts)), tension_change1=d1, tension_change2=d2,
                         min_pretension=max(-d1, -d2, 0.0))


def _check_taut(force: float, pretension: float, span1: float, span2: float, d1: float, d2: float) -> None:
    for which, change in ((1, d1), (2, d2)):
        if pretension + change < 0.0:
            need = -change
            raise InputError(
                f"{pretension:g} N is below the {need:.4g} N that keeps span {which} taut under `force` = "
                f"{force:g} N with the carriage at span1 = {span1:g} m, span2 = {span2:g} m "
                f"(span {which} takes {abs(change) / abs(force):.3f} of the force); raise `pretension` or lower `force`",
                param="pretension")


def worst_position(center_distance: float, pulley_diameter: float, start: float, end: float) -> float:
    r"""Where on the stroke [start, end] the span stretch is largest: L_1 [m], in closed form.

    .. math:: \frac{|F|}{k_s} = \frac{|F|}{C_{spec}} \frac{L_1 (L_t - L_1)}{L_t}, \quad
        L_t = L_1 + L_2 = 2 a + \pi D / 2, \quad L_1^* = \mathrm{clip}(L_t / 2, \mathrm{start}, \mathrm{end})

    The compliance is a parabola in L_1 with its top at L_t / 2 = a + pi D / 4, beyond the idler;
    on a stroke inside the axis (L_1 <= a) it rises all the way, so the worst place is the end
    farthest from the drive pulley, where span 1 is longest. The tooth, backlash and tolerance
    terms do not depend on the position.

    Examples
    --------
    >>> worst_position(1.245, 0.128, 0.1, 1.1)
    1.1
    """
    span_lengths(center_distance, pulley_diameter, start)     # checks a, D and 0 < start <= a
    span_lengths(center_distance, pulley_diameter, end)
    lo, hi = min(start, end), max(start, end)
    half = center_distance + math.pi * pulley_diameter / 4.0
    return min(max(half, lo), hi)


@dataclass(frozen=True)
class StrokeError:
    """The static error along the stroke: arrays over ``positions`` (L_1, m) and the worst.

    ``span_stiffness`` [N/m], ``stretch`` and ``total`` [m], ``min_pretension`` [N] (reversing
    force) per position; ``worst`` is :func:`static_error` at :func:`worst_position` of the
    stroke the positions span, ``least_pretension`` [N] the pretension that keeps both spans
    taut everywhere on it under the force either way.
    """

    positions: np.ndarray
    span_stiffness: np.ndarray
    stretch: np.ndarray
    total: np.ndarray
    min_pretension: np.ndarray
    worst: PositionError
    least_pretension: float


def along_stroke(force: float, specific_stiffness: float, center_distance: float, pulley_diameter: float,
                 positions, tooth_stiffness: float | None = None, teeth_in_mesh: float | None = None,
                 backlash: float = 0.0, length_tolerance: float = 0.0,
                 pretension: float | None = None) -> StrokeError:
    r"""The static error at each carriage position L_1 of ``positions`` [m] on an axis of
    centre distance a and equal pulleys of diameter D, and the worst one in closed form.

    .. math:: \delta(L_1) = \frac{|F|}{C_{spec}} \frac{L_1 L_2}{L_1 + L_2} + \frac{|F|}{z_e c_t} + b + \delta_L,
        \quad L_2 = 2 a - L_1 + \pi D / 2

    Notes
    -----
    Each position as :func:`static_error` ([W21 eq. 16] per span, [BRECOflex23] components);
    the worst by :func:`worst_position`. The least pretension on the stroke is the largest
    share either span takes of a reversing force (at most |F| [Elatech p. 55]). Given a
    ``pretension``, a position where it would let a span go slack is refused.

    Examples
    --------
    >>> s = along_stroke(500.0, 5.5e5, 1.245, 0.128, [0.1, 0.6, 1.1])
    >>> [round(float(x) * 1e3, 4) for x in s.stretch], round(s.worst.span1, 3)
    ([0.0875, 0.4238, 0.5912], 1.1)
    """
    require_range("force", force, "N")
    require_positive("specific_stiffness", specific_stiffness, "N")
    x = np.atleast_1d(np.asarray(positions, dtype=float))
    if x.ndim != 1 or x.size == 0:
        raise InputError("give one or more carriage positions (a 1-D list of L_1 values)", param="positions")
    for value in x:
        span_lengths(center_distance, pulley_diameter, float(value))
    l2 = 2.0 * center_distance - x + math.pi * pulley_diameter / 2.0
    k_s = specific_stiffness / x + specific_stiffness / l2
    k_m = _mesh(tooth_stiffness, teeth_in_mesh)
    require_range("backlash", backlash, "m", low=0.0)
    require_range("length_tolerance", length_tolerance, "m", low=0.0)
    stretch = abs(force) / k_s
    total = stretch + (abs(force) / k_m if k_m is not None else 0.0) + backlash + length_tolerance
    share = np.maximum(x, l2) / (x + l2)
    if pretension is not None:
        for value, other in zip(x, l2):       # refuses the first position that slackens a span
            static_error(force, specific_stiffness, float(value), float(other), tooth_stiffness, teeth_in_mesh,
                         backlash, length_tolerance, pretension)
    where = worst_position(center_distance, pulley_diameter, float(x.min()), float(x.max()))
    l1w, l2w = span_lengths(center_distance, pulley_diameter, where)
    worst = static_error(force, specific_stiffness, l1w, l2w, tooth_stiffness, teeth_in_mesh, backlash,
                         length_tolerance)
    # the largest share is at the stroke end nearest a pulley: L_1 small (span 1) or L_1 = a's far side
    ends = np.array([x.min(), x.max()])
    ends_l2 = 2.0 * center_distance - ends + math.pi * pulley_diameter / 2.0
    least = float(abs(force) * np.max(np.maximum(ends, ends_l2) / (ends + ends_l2)))
    return StrokeError(positions=x, span_stiffness=k_s, stretch=stretch, total=total,
                       min_pretension=abs(force) * share, worst=worst, least_pretension=least)
