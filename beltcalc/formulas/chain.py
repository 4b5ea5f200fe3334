"""Chain drives and rollers of a roller table: sprocket diameter, strand stiffness, the
torsion of shafts and roller tubes, and how an off-centre load shares between a roller's
two ends. SI floats only.

References:

[ISO 606] ISO 606:2004, Short-pitch transmission precision roller and bush chains,
    attachments and associated chain sprockets (the B series is DIN 8187): sprocket
    diametral dimensions, pitch circle d = p / sin(180 deg / z), root d_f = d - d1, tip
    diameter limits [ISO 606 clause 5.3].
[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011), roller chains [Shigley sec. 17-5]: chordal speed variation
    [Shigley eq. 17-31] and [Shigley Fig. 17-18], chain length [Shigley eq. 17-34], centre
    distance [Shigley eq. 17-35].
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317: the belt's stiffness law [W21 eq. 16].
[RP] A. Rusek, A. Popenda, "Mathematical model of drive system for metallurgical roller
    table unit with rotation of rollers transmitted by chain transmission": the placement
    factor w_p [RP eq. 16].
"""

from __future__ import annotations

import math

from beltcalc.errors import InputError, require_positive, require_range


def sprocket_pitch_diameter(pitch: float, teeth: int) -> float:
    r"""Pitch diameter of a chain sprocket [m].

    .. math:: d = \frac{p}{\sin(180^\circ / z)}

    p chain pitch [m], z teeth [-] ([ISO 606 clause 5.3]; ``../shared/data/SOURCED_DATA.md``).
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
    same law as the belt's k = C_spec / a [W21 eq. 16].

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
    width along the roller [m], L the roller length [m]; from [RP eq. 16]. A
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
    c / L and the drive end 1 - c / L. [RP eq. 16] defines w_p but not how it
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


# --- roller-chain drive geometry (issue 13) -----------------------------------------------


def sprocket_root_diameter(pitch: float, teeth: int, roller_diameter: float) -> float:
    r"""Root diameter of a sprocket [m]: :math:`d_f = d - d_1` [ISO 606 clause 5.3].

    d pitch-circle diameter [m], d_1 the chain's roller diameter [m].

    >>> round(sprocket_root_diameter(0.009525, 19, 0.00635) * 1e3, 2)
    51.52
    """
    require_positive("roller_diameter", roller_diameter, "m")
    return sprocket_pitch_diameter(pitch, teeth) - roller_diameter


def sprocket_tip_diameters(pitch: float, teeth: int, roller_diameter: float) -> tuple[float, float]:
    r"""Smallest and largest tip diameter ISO 606 allows for a sprocket [m].

    .. math:: d_{a,min} = d + p\,(1 - 1.6 / z) - d_1, \quad d_{a,max} = d + 1.25 p - d_1

    [ISO 606 clause 5.3] (tooth heights and tip diameters). The CROSS+MORSE 06B 19-tooth sprocket
    (d = 57.87 mm, outside 61.3 mm) lies inside this range.

    >>> [round(x * 1e3, 2) for x in sprocket_tip_diameters(0.009525, 19, 0.00635)]
    [60.24, 63.43]
    """
    require_positive("roller_diameter", roller_diameter, "m")
    d = sprocket_pitch_diameter(pitch, teeth)
    return d + pitch * (1.0 - 1.6 / teeth) - roller_diameter, d + 1.25 * pitch - roller_diameter


def polygon_speed_variation(teeth: int) -> float:
    r"""Chordal (polygon) speed variation of a chain on a sprocket [-].

    .. math:: \frac{v_{max} - v_{min}}{v_{max}} = 1 - \cos(180^\circ / z)

    The chain leaves at the radius d/2 when a roller sits on the line of centres and at
    (d/2) cos(180 deg / z) half a pitch later [Shigley Fig. 17-18], [Shigley eq. 17-31]. z >= 3.

    >>> round(polygon_speed_variation(17), 5)
    0.01704
    """
    if teeth < 3 or teeth != int(teeth):
        raise InputError(f"{teeth:g} teeth is not allowed; a sprocket needs a whole number >= 3", param="teeth")
    return 1.0 - math.cos(math.pi / teeth)


def chain_length_links(center_distance: float, pitch: float, teeth_small: int, teeth_large: int) -> float:
    r"""Chain length in pitches for a centre distance (not rounded) [-].

    .. math:: \frac{L}{p} = \frac{2C}{p} + \frac{N_1 + N_2}{2} + \frac{(N_2 - N_1)^2}{4\pi^2 C/p}

    [Shigley eq. 17-34]. The usual approximate formula (it drops terms of order beta^4, as
    the manufacturers' charts do).

    >>> round(chain_length_links(0.635, 0.0254, 17, 34), 4)
    75.7928
    """
    require_positive("center_distance", center_distance, "m")
    require_positive("pitch", pitch, "m")
    c = center_distance / pitch
    return 2.0 * c + (teeth_small + teeth_large) / 2.0 + (teeth_large - teeth_small) ** 2 / (4.0 * math.pi ** 2 * c)


def chain_links_even(links: float) -> int:
    """The next even number of links at or above ``links`` (no cranked offset link needed).

    >>> chain_links_even(75.7928), chain_links_even(76.0), chain_links_even(76.2)
    (76, 76, 78)
    """
    n = math.ceil(links - 1e-9)
    return n + (n % 2)


def chain_center_distance(links: float, pitch: float, teeth_small: int, teeth_large: int) -> float:
    r"""Centre distance for a chain of ``links`` pitches [m] (exact inverse of [Shigley eq. 17-34]).

    .. math:: A = \frac{N_1 + N_2}{2} - \frac{L}{p}, \quad
              C = \frac{p}{4}\left[-A + \sqrt{A^2 - 8\left(\frac{N_2 - N_1}{2\pi}\right)^2}\right]

    [Shigley eq. 17-35].

    >>> round(chain_center_distance(76, 0.0254, 17, 34) * 1e3, 3)
    637.647
    """
    require_positive("pitch", pitch, "m")
    a = (teeth_small + teeth_large) / 2.0 - links
    disc = a * a - 8.0 * ((teeth_large - teeth_small) / (2.0 * math.pi)) ** 2
    if a >= 0 or disc < 0:
        raise InputError(f"{links:g} links are too few for sprockets of {teeth_small} and {teeth_large} teeth",
                         param="links")
    return pitch / 4.0 * (-a + math.sqrt(disc))


def chain_speed(pitch: float, teeth: int, speed: float) -> float:
    r"""Mean chain speed [m/s]: :math:`v = z p \omega / (2\pi)` [Shigley eq. 17-30].

    >>> round(chain_speed(0.0254, 17, 300 * math.pi / 30), 4)
    2.159
    """
    require_positive("pitch", pitch, "m")
    return teeth * pitch * speed / (2.0 * math.pi)


def chain_wrap_angle(pitch: float, teeth_small: int, teeth_large: int, center_distance: float) -> float:
    r"""Chain wrap (arc of contact) on the small sprocket [rad].

    .. math:: \theta_1 = \pi - 2 \arcsin\frac{d_2 - d_1}{2 C}

    d_1, d_2 the pitch diameters p / sin(180 deg / z) [m], C the centre distance [m]: the
    open-belt geometry of [Shigley eq. 17-1] on the pitch circles. Equal sprockets: pi.

    >>> round(math.degrees(chain_wrap_angle(0.0254, 17, 34, 0.635)), 2)
    167.61
    """
    require_positive("center_distance", center_distance, "m")
    d1 = sprocket_pitch_diameter(pitch, teeth_small)
    d2 = sprocket_pitch_diameter(pitch, teeth_large)
    if center_distance <= (d1 + d2) / 2:
        raise InputError(f"{center_distance:g} m: the sprockets ({d1:.4g} m and {d2:.4g} m) overlap",
                         param="center_distance")
    return math.pi - 2.0 * math.asin((d2 - d1) / (2.0 * center_distance))


LBF = 4.4482216152605                 # N per pound-force


def galling_speed(pitch: float, teeth: int, tension: float) -> float:
    r"""Highest small-sprocket speed before the pins and bushings gall [rad/s].

    .. math:: n_1 \le 1000 \left[\frac{82.5}{7.95^p \, 1.0278^{N_1} \, 1.323^{F/1000}}\right]^{1/(1.59 \log_{10} p + 1.873)}
              \ \text{rev/min}

    p pitch [in], N_1 teeth of the small sprocket, F the chain tension [lbf] ([Shigley sec. 17-5]:
    "the maximum speed (rev/min) for a chain drive is limited by galling between the pin and
    the bushing"; the Type C' cells of [Shigley table 17-20] are this region: "submit design
    to manufacturer for evaluation"). It falls with pitch, teeth and tension.

    >>> round(galling_speed(0.5 * 0.0254, 17, 0.0) * 30 / math.pi)
    8061
    """
    require_positive("pitch", pitch, "m")
    require_range("tension", tension, "N", 0.0)
    p = pitch / 0.0254
    exponent = 1.59 * math.log10(p) + 1.873
    if exponent <= 0:
        raise InputError(f"{pitch:g} m: below 0.066 in the galling formula has no meaning", param="pitch")
    # in logarithms: a tension of 1e6 lbf makes 1.323^(F/1000) overflow, the limit just tends to 0
    log_base = math.log(82.5) - p * math.log(7.95) - teeth * math.log(1.0278) - tension / LBF / 1000.0 * math.log(1.323)
    return 1000.0 * math.exp(log_base / exponent) * math.pi / 30.0
