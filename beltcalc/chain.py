"""Chain drives and rollers of a roller table: sprocket diameter, strand stiffness, the
torsion of shafts and roller tubes, and how an off-centre load shares between a roller's
two ends. SI floats only."""

from __future__ import annotations

import math

from beltcalc.errors import InputError, require_positive, require_range


def sprocket_pitch_diameter(pitch: float, teeth: int) -> float:
    r"""Pitch diameter of a chain sprocket [m].

    .. math:: d = \frac{p}{\sin(180^\circ / z)}

    p chain pitch [m], z teeth [-] (ISO 606 / DIN 8187; ``../shared/data/SOURCED_DATA.md``).
    Valid for z >= 3.

    >>> round(sprocket_pitch_diameter(0.015875, 19) * 1e3, 2)
    96.45
    """
    require_positive("pitch", pitch, "m")
    if teeth < 3 or teeth != int(teeth):
        raise InputError(f"{teeth:g} teeth is not allowed; a sprocket needs a whole number >= 3", param="teeth")
    return pitch / math.sin(math.pi / teeth)


def strand_stiffness(specific_stiffness: float, length: float) -> float:
    r"""Longitudinal stiffness of a chain strand [N/m]: :math:`c = c_{spec} / L`.

    c_spec [N] is the force per unit strain (the strand's EA), L [m] its free length. The
    same law as the belt's k = C_spec / a (Wojtkowiak et al. 2021, eq. 16).

    >>> strand_stiffness(1.5e6, 0.6)
    2500000.0
    """
    require_positive("chain_stiffness", specific_stiffness, "N")
    require_positive("length", length, "m")
    return specific_stiffness / length


def torsional_stiffness(outer_diameter: float, inner_diameter: float, length: float, shear_modulus: float) -> float:
    r"""Torsional stiffness of a round shaft or tube [N m/rad].

    .. math:: c = \frac{G I_p}{L}, \quad I_p = \frac{\pi (D^4 - d^4)}{32}

    D, d outer and bore diameter [m] (d = 0: solid), L length [m], G shear modulus [Pa].

    >>> round(torsional_stiffness(0.06, 0.0, 0.15, 81e9))
    687066
    """
    require_positive("outer_diameter", outer_diameter, "m")
    require_range("inner_diameter", inner_diameter, "m", 0.0, outer_diameter, high_open=True)
    require_positive("length", length, "m")
    require_positive("shear_modulus", shear_modulus, "Pa")
    return shear_modulus * math.pi * (outer_diameter ** 4 - inner_diameter ** 4) / 32.0 / length


def placement_factor(offset: float, width: float, length: float) -> float:
    r"""Placement (symmetry) factor of a transported element on a roller [-].

    .. math:: w_p = \frac{2 a_x}{L - a}

    a_x distance from the element's edge to the roller's drive end [m], a the element's
    width along the roller [m], L the roller length [m] (Rusek & Popenda, eq. 16). A
    centred element has w_p = 1; w_p = 0 and 2 put it against either end.

    >>> placement_factor(0.2, 0.8, 1.2)
    1.0
    """
    require_positive("roller_length", length, "m")
    require_range("element_width", width, "m", 0.0, length, low_open=True)
    free = length - width
    slack = 1e-9 * length                      # 1.2 - 0.8 is 0.3999... in binary
    require_range("element_offset", offset, "m", 0.0, free + slack)
    if free <= slack:
        return 1.0                             # as wide as the roller: centred by force
    return min(2.0, 2.0 * offset / free)


def load_split(factor: float, width: float, length: float) -> tuple[float, float]:
    r"""Shares of a roller's load carried at its drive end and at its far end [-].

    The element presses uniformly on [a_x, a_x + a]; its centre lies at
    c = a_x + a/2 = (w_p (L - a) + a) / 2, and the lever rule gives the far end
    c / L and the drive end 1 - c / L. Eq. 16 of Rusek & Popenda defines w_p but not how it
    enters the equations; this is our statics.

    >>> load_split(1.0, 0.8, 1.2)
    (0.5, 0.5)
    >>> tuple(round(s, 4) for s in load_split(0.0, 0.8, 1.2))
    (0.6667, 0.3333)
    """
    require_range("placement factor", factor, "", 0.0, 2.0)
    require_range("element_width", width, "m", 0.0, length, low_open=True)
    far = (factor * (length - width) + width) / (2.0 * length)
    return 1.0 - far, far
