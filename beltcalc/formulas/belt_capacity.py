"""The formulas of a timing-belt drive's capacity, from the makers' design pages: the
peripheral force, the specific tooth load at a speed, the tooth shear capacity, the shaft
load of two strands, and the installation tension rule. SI floats; the checks that use them
are :mod:`beltcalc.design.belt_drive`'s.

References:

[Elatech] Elatech timing-belt catalogue (Goodyear Elatech PT belt division), as recorded in
    ../shared/data/SOURCED_DATA.md: F_Tmax = F_TV + F_U <= F_Tadm; linear drives F_TV >= F_U
    [Elatech p. 55].
[BRECO] BRECO/BRECOFLEX timing-belt design pages (belt-pilot.com, id=1702): tooth capacity
    F_t = F_tspec(n) * b[cm] * z_e, teeth in mesh z_e capped at z_e max.
[Tsubaki belts] Tsubakimoto Chain, technical data, synchronous belts: correction factors
    Ko, Ki, Ks, Ka [Tsubaki belts table 1-4] and meshing factor (full capacity with 6 or more
    teeth in mesh) [Tsubaki belts table 6].
[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011): T1 - T2 = F_U, T1 + T2 = 2 F_i for a belt with equal spans; the
    resultant of two strand forces [Shigley sec. 17-1].
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

import math

from beltcalc.errors import InputError, require_positive, require_range

LAYOUTS = ("linear", "endless")


def peripheral_force(torque: float, pitch_diameter: float) -> float:
    r"""Peripheral (effective) force of a pulley [N].

    .. math:: F_U = 2 T / d_0

    T torque on the pulley [N m], d_0 its pitch diameter [m]. [Tsubaki belts formula sheet]
    ("Fa = 2T/Dp") and [BRECO formula sheet] (F_U = 2 10^3 M / d_0 in N, N m, mm).

    >>> round(peripheral_force(31.83, 0.12732), 6)
    500.0
    """
    require_positive("torque", torque, "N*m")
    require_positive("pulley_diameter", pitch_diameter, "m")
    return 2.0 * torque / pitch_diameter


def specific_tooth_load(table: tuple[tuple[float, float], ...], speed: float) -> float:
    r"""The catalog's specific tooth load F_tspec at pulley speed ``speed`` [N/m].

    Linear interpolation in the table of (speed [rad/s], F_tspec [N/m]) pairs [BRECO]; a
    speed beyond the last row is refused (the table is not extrapolated).

    Notes
    -----
    The catalogs hold every row the maker prints (40 to 48 rows, 20 to 500 rpm apart), so
    the result equals the printed value at a printed speed and lies between the two
    neighbouring printed values elsewhere. The printed curves fall and are convex, so a
    chord lies above the curve between rows: by at most 1.4 % on the built-in tables
    (BRECO T20, 100-200 rpm), bounded from the neighbouring rows' slopes; the bound and
    its derivation are in docs/catalogs.md. With only a few rows of a table the chords
    overshot by up to 19 % (issue 28).

    >>> rpm = math.pi / 30
    >>> round(specific_tooth_load(((0.0, 3640.0), (1000 * rpm, 2649.0)), 500 * rpm), 6)
    3144.5
    """
    if not table:
        raise InputError("the belt has no F_tspec(n) table", param="belt")
    require_range("speed", speed, "rad/s", 0.0)
    speeds = [s for s, _ in table]
    if speed > speeds[-1] * (1 + 1e-12):
        raise InputError(f"{speed * 30 / math.pi:.6g} rpm is beyond the catalog's F_tspec table "
                         f"(up to {speeds[-1] * 30 / math.pi:.6g} rpm); it is not extrapolated", param="speed")
    for (s0, f0), (s1, f1) in zip(table, table[1:]):
        if s0 <= speed <= s1:
            return f0 + (f1 - f0) * (speed - s0) / (s1 - s0)
    return table[-1][1]


def tooth_shear_capacity(specific_load: float, width: float, teeth_meshing: float) -> float:
    r"""Peripheral force the teeth in mesh can carry [N].

    .. math:: F_{U,adm} = F_{tspec}(n) \, b \, z_e

    F_tspec [N/m] per tooth and unit width (the catalogs print N/cm with b in cm), b belt
    width [m], z_e teeth in mesh. [BRECO]; [W21 sec. 3.2].

    >>> round(tooth_shear_capacity(3640.0, 0.025, 12), 6)
    1092.0
    """
    require_positive("width", width, "m")
    require_positive("teeth_meshing", teeth_meshing, "")
    return specific_load * width * teeth_meshing


def shaft_load(tight: float, slack: float, wrap: float) -> float:
    r"""Resultant of the two strand forces on a pulley (its shaft/bearing load) [N].

    .. math:: F_W = \sqrt{T_1^2 + T_2^2 - 2 T_1 T_2 \cos\alpha}

    T_1, T_2 strand forces [N], alpha the wrap angle [rad]: the strands pull along their
    tangents, which enclose pi - alpha. Vector sum ([Shigley Fig. 17-1] geometry).
    alpha = pi gives T_1 + T_2.

    >>> shaft_load(1000.0, 500.0, math.pi)
    1500.0
    >>> round(shaft_load(600.0, 400.0, math.pi / 2), 3)
    721.11
    """
    for name, v in (("tight", tight), ("slack", slack)):
        if not (math.isfinite(v) and v >= 0):
            raise InputError(f"strand force {v:g} N must be >= 0 N", param="pretension")
    return math.sqrt(max(tight * tight + slack * slack - 2.0 * tight * slack * math.cos(wrap), 0.0))


def installation_tension_rule(force: float, layout: str, service: float = 1.0) -> float:
    r"""The minimum installation tension (pretension) [N].

    .. math:: F_v \ge F_U \ \text{(linear)}, \qquad F_v \ge c_2 F_U / 2 \ \text{(endless)}

    Linear drives: [Elatech p. 55] (the idle side must not go slack whatever
    the carriage position). Endless two-pulley drives with equal spans: T_1 - T_2 = F,
    T_1 + T_2 = 2 F_v [Shigley sec. 17-1] give the slack side T_2 = F_v - F / 2; at the design
    load F = c_2 F_U (the peak the tooth-shear check is made for, service factor c_2 of
    [Tsubaki belts table 1-4]) it stays >= 0 when F_v >= c_2 F_U / 2. At the nominal F_U it is then
    (c_2 - 1) F_U / 2 > 0. (F_v = F_U / 2 would leave it at 0 N under the nominal load and
    negative, i.e. slack and jumping teeth, under c_2 F_U: issue 28.)

    >>> installation_tension_rule(500.0, "linear"), installation_tension_rule(500.0, "endless", 1.4)
    (500.0, 350.0)
    """
    if layout not in LAYOUTS:
        raise InputError(f"{layout!r} is not a layout; use one of {', '.join(LAYOUTS)}", param="layout")
    return force if layout == "linear" else service * force / 2.0
