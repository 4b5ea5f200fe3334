"""Roller-chain selection: power rating, the chains of the catalog that carry a drive, and
the geometry and safety of each. SI floats only.

References:

[Shigley] R. G. Budynas, J. K. Nisbett, Shigley's Mechanical Engineering Design, 9th ed.,
    McGraw-Hill (2011). The American Chain Association rating formulas: link-plate limit
    [Shigley eq. 17-32] and roller-bushing limit [Shigley eq. 17-33], with the
    multiple-strand factors K2 of [Shigley table 17-23]; the same formulas and constants in
    Machinery's Handbook, "Horsepower capacity of roller chains". [Shigley Example 17-5]:
    90 hp at 300 rev/min, 17/34 teeth, K_s = 1.3, n_d = 1.5, C/p = 25 -> 1 strand no. 200,
    2 strands no. 160, 3 and 4 strands no. 140. [Shigley sec. 17-5]: "for smooth operation
    at moderate and high speeds ... a driving sprocket with at least 17 teeth"; "driven
    sprockets are not made in standard sizes over 120 teeth"; the most successful drives
    have ratios up to 6:1; the galling speed limit (:func:`beltcalc.formulas.chain.galling_speed`),
    the Type C' region of [Shigley table 17-20] ("submit design to manufacturer for
    evaluation").
[ISO 10823] ISO 10823:2004, Guidance on the selection of roller chain drives: corrected
    power = power x service factor x tooth factor (19 / z_1)^1.08, i.e. the same z_1^1.08
    law as [Shigley eq. 17-32].
[ISO 606] ISO 606:2004, Short-pitch transmission precision roller and bush chains,
    attachments and associated chain sprockets: the sprockets (:mod:`beltcalc.formulas.chain`).
[Diamond guide] Diamond Chain, technical engineering guide: the load in service should
    never exceed 1/6 of the minimum ultimate tensile strength.
[McGuire] McGuire Bearing Company, "Better chain performance": the highest chain speed of
    Type A (manual) and Type B (oil bath) lubrication by chain number, 40 to 160 (in
    ``catalogs/chains.toml``, key ``lubrication``); above Type B, Type C (oil stream).
[Diamond FAQ] Diamond Chain, FAQ (diamondchain.com/faq): "What is the recommended minimum
    chain wrap in a roller chain drive?": 120 deg on the smallest sprocket; "What is the
    smallest suggested sprocket size to minimize the effects of chordal action?": 12 teeth
    for a slow drive (drip lubrication), 17 medium (oil bath), 25 high speed (pumped); "How
    is the drive ratio of a roller chain drive calculated and what is the maximum
    recommended single reduction?" (as reproduced at experts123.com): 7:1; above it a
    double reduction.
[HKK] HKK Chain, engineering information, "Installation": the optimum centre distance is
    30 to 50 times the chain pitch; 80 pitches is the longest the common design rules allow
    (e.g. PTC Asia, "The center distance and chain length": a = (30-50) p, a_max <= 80 p).
[Tsubaki chains] U.S. Tsubaki, Roller Chain General Catalog: the maximum allowable load
    with a one-pitch offset link is 65 % of the chain's (RS40/RS50 page, [Tsubaki chains note 2])
    (Tsubaki, "The Complete Guide to Chain", table 2.1: an offset link is 35 % lower in
    fatigue strength).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable

from beltcalc.formulas import chain as cm
from beltcalc.data.catalogs import Chain
from beltcalc.design.checks import RULES, Check, failures
from beltcalc.errors import InputError, require_positive, require_range

HORSEPOWER = 745.69987158227022        # W, mechanical horsepower (550 ft lbf/s)
INCH = 0.0254                          # m
RPM = math.pi / 30.0                   # rad/s per rev/min
# Multiple-strand factors K2 [Shigley table 17-23]
STRAND_FACTORS = {1: 1.0, 2: 1.7, 3: 2.5, 4: 3.3, 5: 3.9, 6: 4.6, 8: 6.0}
LUBRICATION = {"A": "manual or drip", "B": "oil bath or slinger disc", "C": "oil stream (pump)"}   # [McGuire]
# Plausibility of the drive (issue 28): the makers' rules, each a rule of RULES with its source; the
# small sprocket's limit is data of the drive (its lubrication type), the others are fixed.
# small sprocket, by the drive's lubrication type [Diamond FAQ]; 17 where the type is not known [Shigley sec. 17-5]
MIN_TEETH_BY_LUBRICATION = {"A": 12, "B": 17, "C": 25}
MIN_TEETH = 17
# rating of a chain with a one-pitch offset link (odd link count) [Tsubaki chains note 2]
OFFSET_LINK_FACTOR = 0.65


def lubrication_type(chain_speed: float, limits: tuple[float, float] | None) -> str | None:
    r"""Lubrication type a roller chain needs at ``chain_speed`` [m/s]: ``"A"``, ``"B"`` or ``"C"``.

    .. math:: \text{A if } v \le v_A, \quad \text{B if } v_A < v \le v_B, \quad \text{C if } v > v_B

    ``limits`` = (v_A, v_B) [m/s], the highest chain speed of Type A (manual or drip) and
    Type B (oil bath or slinger disc) of the chain's pitch, the catalog's ``lubrication``
    ([McGuire] table); above v_B a pumped oil stream (Type C). None when the
    catalog has no limits for the chain. A speed within 1e-12 of a limit counts as on it (the
    table's ft/min and a speed computed in other units differ in the last bits).

    >>> fpm = 0.3048 / 60                 # m/s per ft/min; no. 140: Type A to 115, B to 1100 ft/min
    >>> [lubrication_type(v * fpm, (115 * fpm, 1100 * fpm)) for v in (100, 115, 743.75, 1100, 1101)]
    ['A', 'A', 'B', 'B', 'C']
    """
    if limits is None:
        return None
    require_range("chain_speed", chain_speed, "m/s", 0.0)
    v_a, v_b = limits
    on = 1.0 + 1e-12
    return "A" if chain_speed <= v_a * on else "B" if chain_speed <= v_b * on else "C"


def rated_power_link_plate(pitch: float, teeth: int, speed: float) -> float:
    r"""Single-strand power rating limited by link-plate fatigue [W].

    .. math:: H_1 = 0.004\, N_1^{1.08}\, n_1^{0.9}\, p^{3 - 0.07 p} \ \text{hp}

    p pitch [in], n_1 small-sprocket speed [rev/min], N_1 its teeth [Shigley eq. 17-32].
    Rates ANSI chains 40-240 (no. 41: 0.0022, not in the catalog). The tooth factor of
    [ISO 10823] follows the same z_1^1.08 law.

    >>> round(rated_power_link_plate(1.75 * INCH, 17, 300 * RPM) / HORSEPOWER, 2)
    72.39
    """
    require_positive("pitch", pitch, "m")
    require_positive("speed", speed, "rad/s")
    p = pitch / INCH
    return 0.004 * teeth ** 1.08 * (speed / RPM) ** 0.9 * p ** (3.0 - 0.07 * p) * HORSEPOWER


def rated_power_roller_bushing(pitch: float, teeth: int, speed: float, k_r: float = 17.0) -> float:
    r"""Single-strand power rating limited by roller-bushing impact fatigue [W].

    .. math:: H_2 = \frac{1000\, K_r\, N_1^{1.5}\, p^{0.8}}{n_1^{1.5}} \ \text{hp}

    K_r = 17 for chains 40-240 (29 for 25 and 35), p [in], n_1 [rev/min]: the rating of
    [Shigley eq. 17-33]. Falls with speed: it governs at high speed.

    >>> round(rated_power_roller_bushing(0.5 * INCH, 17, 3000 * RPM) / HORSEPOWER, 3)
    4.165
    """
    require_positive("pitch", pitch, "m")
    require_positive("speed", speed, "rad/s")
    p = pitch / INCH
    return 1000.0 * k_r * teeth ** 1.5 * p ** 0.8 / (speed / RPM) ** 1.5 * HORSEPOWER


def rated_power(chain: Chain, teeth: int, speed: float) -> tuple[float, str]:
    """Rating of ``chain`` (all its strands) on a ``teeth`` sprocket at ``speed`` [W], and
    which limit governs: K2 min(H1, H2) by [Shigley eq. 17-32, 17-33] and K2 of [Shigley table 17-23]."""
    if chain.strands not in STRAND_FACTORS:
        raise InputError(f"{chain.name}: no multiple-strand factor for {chain.strands} strands", param="chain")
    h1 = rated_power_link_plate(chain.pitch, teeth, speed)
    h2 = rated_power_roller_bushing(chain.pitch, teeth, speed, chain.roller_bushing_constant or 17.0)
    k2 = STRAND_FACTORS[chain.strands]
    return (k2 * h1, "link plate") if h1 <= h2 else (k2 * h2, "roller bushing")


@dataclass(frozen=True)
class ChainInputs:
    """A chain drive, SI. Power [W] or torque [N m] on the small sprocket at ``speed``
    [rad/s]; ``center_distance`` [m], or ``center_pitches`` (C/p) when it is None."""

    speed: float
    teeth_small: int = 17
    teeth_large: int = 34
    power: float | None = None
    torque: float | None = None
    service_factor: float = 1.0
    design_factor: float = 1.0
    center_distance: float | None = None
    center_pitches: float = 30.0
    links: int | None = None            # a chain length asked for (the centre distance follows); odd: an offset link


@dataclass(frozen=True)
class ChainCandidate:
    """One chain checked against the drive (SI)."""

    chain: Chain
    rated_power: float                 # W
    governing: str                     # "link plate" | "roller bushing"
    utilisation: float                 # required / rated
    chain_speed: float                 # m/s
    pull: float                        # N, F = P / v
    centrifugal: float | None          # N, q v^2
    safety_factor: float               # F_B / (K_s F + F_c); F_c left out where the mass is unknown
    carries: bool
    galling_speed: float | None = None  # rad/s, [Shigley sec. 17-5] at the tension per strand
    derating: float = 1.0              # OFFSET_LINK_FACTOR with an odd link count [Tsubaki chains]


@dataclass(frozen=True)
class ChainGeometry:
    """Sprockets and chain length of the chosen chain (SI)."""

    pitch_diameters: tuple[float, float]
    tip_diameters: tuple[tuple[float, float], tuple[float, float]]
    root_diameters: tuple[float, float]
    links_exact: float
    links: int
    center_distance: float             # m, back-solved for the link count
    polygon_variation: tuple[float, float]
    center_distance_asked: float | None = None   # m, the centre distance given (None: the link count was given)
    wrap_small: float = math.pi        # rad, chain wrap on the small sprocket at ``center_distance``


@dataclass(frozen=True)
class ChainReport:
    power: float                        # W, nominal
    required: float                     # W, n_d K_s H_nom
    torque: float                       # N m on the small sprocket
    speed: float                        # rad/s
    teeth: tuple[int, int]
    service_factor: float
    design_factor: float
    candidates: tuple[ChainCandidate, ...]      # every chain checked
    best_per_strands: dict                      # strands -> ChainCandidate (smallest pitch that carries)
    chosen: ChainCandidate
    geometry: ChainGeometry
    rule: str
    lubrication: str | None = None              # "A" | "B" | "C" of the chosen chain; None: no data
    warnings: tuple[str, ...] = field(default=())
    notes: tuple[str, ...] = field(default=())
    checks: tuple[Check, ...] = field(default=())


SELECTION_RULE = ("rated power K2 min(H1, H2) >= n_d K_s P (ACA formulas, Shigley eq. 17-32/33) and breaking-load "
                  "safety F_B / (K_s F + q v^2) >= 6 (Diamond Chain); of those, the smallest pitch, then the fewest "
                  "strands")


def chain_geometry(chain: Chain, inp: ChainInputs) -> ChainGeometry:
    """Sprocket diameters [ISO 606 clause 5.3], chain length in even links (or the ``links``
    asked for) and the centre distance back-solved for it [Shigley eq. 17-34, 17-35], polygon speed
    variation, chain wrap on the small sprocket."""
    z1, z2 = inp.teeth_small, inp.teeth_large
    d = (cm.sprocket_pitch_diameter(chain.pitch, z1), cm.sprocket_pitch_diameter(chain.pitch, z2))
    if inp.links is not None:
        if inp.links != int(inp.links) or inp.links < 1:
            raise InputError(f"{inp.links:g} is not allowed; a chain has a whole number of links >= 1", param="links")
        c_asked, links = None, int(inp.links)
        exact = float(links)
    else:
        c_asked = inp.center_distance if inp.center_distance is not None else inp.center_pitches * chain.pitch
        if c_asked <= (d[0] + d[1]) / 2:
            raise InputError(f"{c_asked:g} m: the sprockets of {chain.name} ({d[0]:.4g} m and {d[1]:.4g} m) overlap",
                             param="center_distance")
        exact = cm.chain_length_links(c_asked, chain.pitch, z1, z2)
        links = cm.chain_links_even(exact)
    center = cm.chain_center_distance(links, chain.pitch, z1, z2)
    if center <= (d[0] + d[1]) / 2:
        raise InputError(f"{links} links: the sprockets of {chain.name} ({d[0]:.4g} m and {d[1]:.4g} m) would overlap",
                         param="links")
    return ChainGeometry(
        pitch_diameters=d,
        tip_diameters=(cm.sprocket_tip_diameters(chain.pitch, z1, chain.roller_diameter),
                       cm.sprocket_tip_diameters(chain.pitch, z2, chain.roller_diameter)),
        root_diameters=(cm.sprocket_root_diameter(chain.pitch, z1, chain.roller_diameter),
                        cm.sprocket_root_diameter(chain.pitch, z2, chain.roller_diameter)),
        links_exact=exact, links=links, center_distance=center,
        polygon_variation=(cm.polygon_speed_variation(z1), cm.polygon_speed_variation(z2)),
        center_distance_asked=c_asked, wrap_small=cm.chain_wrap_angle(chain.pitch, z1, z2, center),
    )


def check_chain(chain: Chain, inp: ChainInputs, power: float, required: float) -> ChainCandidate:
    """Rating (x :data:`OFFSET_LINK_FACTOR` with an odd ``links``), pull, centrifugal pull,
    breaking-load safety [Diamond guide] and galling speed of one chain."""
    rated, governing = rated_power(chain, inp.teeth_small, inp.speed)
    derating = OFFSET_LINK_FACTOR if inp.links is not None and int(inp.links) % 2 else 1.0   # [Tsubaki chains]
    rated *= derating
    v = cm.chain_speed(chain.pitch, inp.teeth_small, inp.speed)
    pull = power / v
    f_c = chain.mass * v * v if chain.mass is not None else None
    tension = inp.service_factor * pull + (f_c or 0.0)
    safety = chain.breaking_load / tension   # no mass: without q v^2
    carries = rated >= required and RULES["chain_safety"].check(safety).verdict == "pass"     # [Diamond guide]
    galling = cm.galling_speed(chain.pitch, inp.teeth_small, tension / chain.strands) if tension < 1e300 else 0.0
    return ChainCandidate(chain, rated, governing, required / rated, v, pull, f_c, safety, carries, galling, derating)


def select_chain(inp: ChainInputs, chains: Iterable[Chain], name: str | None = None) -> ChainReport:
    """Every catalog chain checked; the smallest that carries the drive chosen (or ``name``).

    The example is [Shigley Example 17-5]:

    >>> from beltcalc.data.catalogs import load_catalog
    >>> r = select_chain(ChainInputs(speed=300 * RPM, power=90 * HORSEPOWER, service_factor=1.3,
    ...                              design_factor=1.5, center_pitches=25), load_catalog().chains.values())
    >>> {k: c.chain.name for k, c in sorted(r.best_per_strands.items())}
    {1: '200-1', 2: '160-2', 3: '140-3', 4: '140-4'}
    >>> r.chosen.chain.name, r.geometry.links
    ('140-3', 76)
    """
    require_positive("speed", inp.speed, "rad/s")
    for key, z in (("teeth", inp.teeth_small), ("teeth_large", inp.teeth_large)):
        if z != int(z) or z < 3:
            raise InputError(f"{z:g} is not allowed; a sprocket needs a whole number of teeth >= 3", param=key)
    if inp.teeth_large < inp.teeth_small:
        raise InputError(f"{inp.teeth_large} teeth: the large sprocket must have at least the {inp.teeth_small} "
                         "teeth of `teeth`", param="teeth_large")
    require_range("service_factor", inp.service_factor, "", 1.0)
    require_range("design_factor", inp.design_factor, "", 1.0)
    require_positive("center_pitches", inp.center_pitches, "")
    if inp.power is not None:
        power = require_positive("power", inp.power, "W")
    elif inp.torque is not None:
        power = require_positive("torque", inp.torque, "N*m") * inp.speed
    else:
        raise InputError("give the power (`power`) or the torque (`torque`) on the small sprocket", param="power")
    required = inp.design_factor * inp.service_factor * power
    if not math.isfinite(required):     # a torque of 1e308 N m: no figure of the drive is a number
        given = "`torque` x `speed`" if inp.power is None else "`power`"
        raise InputError(f"the drive's power ({given}, x n_d K_s for the rating) is beyond a float (over 1e308 W); "
                         "give a value in a physical range", param="torque" if inp.power is None else "power")
    candidates = tuple(check_chain(c, inp, power, required) for c in chains)
    if not candidates:
        raise InputError("no chain to choose from (check `series` and `strands`)", param="series")
    best: dict[int, ChainCandidate] = {}
    for cand in sorted(candidates, key=lambda c: c.chain.pitch):
        if cand.carries and cand.chain.strands not in best:
            best[cand.chain.strands] = cand
    if name is not None:
        matches = [c for c in candidates if c.chain.name.lower() == name.lower()
                   or name.lower() in (a.lower() for a in c.chain.aliases)]
        if not matches:
            raise InputError(f"{name!r} is not among the chains checked", param="chain")
        chosen = matches[0]
    else:
        if not best:
            top = max(candidates, key=lambda c: c.rated_power)
            given = "`torque` x `speed`" if inp.torque is not None else "`power`"
            raise InputError(f"no chain in the catalog carries {required / 1e3:.4g} kW ({given}) at "
                             f"{inp.speed / RPM:.6g} rpm (`speed`) on {inp.teeth_small} teeth (the "
                             f"strongest, {top.chain.name}, is rated {top.rated_power / 1e3:.4g} kW); use more teeth, "
                             "a faster shaft or more strands")
        chosen = min(best.values(), key=lambda c: (c.chain.pitch, c.chain.strands))
    geometry = chain_geometry(chosen.chain, inp)
    lube = lubrication_type(chosen.chain_speed, chosen.chain.lubrication)
    checks = chain_checks(chosen, required, inp, geometry, lube)
    warnings = [c.warning() for c in failures(checks)]
    notes = [length_note(chosen.chain, geometry, chosen.derating)]
    if chosen.centrifugal is None:
        notes.append(f"{chosen.chain.name}: the catalog has no mass for it: the centrifugal pull q v^2 is not "
                     "computed and the safety factor leaves it out")
    if lube is None:
        notes.append(f"{chosen.chain.name}: the catalog has no lubrication limits for its pitch (McGuire Bearing's "
                     "table covers chains 40 to 160): no lubrication type")
    else:
        notes.append(f"lubrication: Type {lube}, {LUBRICATION[lube]}, at v = {chosen.chain_speed:.4g} m/s "
                     f"(Type A up to {chosen.chain.lubrication[0]:.4g} m/s, Type B up to "
                     f"{chosen.chain.lubrication[1]:.4g} m/s; McGuire Bearing, 'Better chain performance')")
    return ChainReport(notes=tuple(notes),
        power=power, required=required, torque=power / inp.speed, speed=inp.speed,
        teeth=(inp.teeth_small, inp.teeth_large), service_factor=inp.service_factor,
        design_factor=inp.design_factor, candidates=candidates, best_per_strands=best, chosen=chosen,
        geometry=geometry, rule=SELECTION_RULE, lubrication=lube, warnings=tuple(warnings),
        checks=tuple(checks),
    )


def length_note(chain: Chain, g: ChainGeometry, derating: float) -> str:
    """What the chain length did to the centre distance: rounded to whole (even) links, or
    the link count asked for, with the offset link of an odd count."""
    p = chain.pitch
    if g.center_distance_asked is None:
        odd = (f"; an odd count: one offset link, the rating x {derating:g} (U.S. Tsubaki: 65 % of the maximum "
               "allowable load with a one-pitch offset link)" if g.links % 2 else "")
        return (f"chain length: {g.links} links (`links`), centre distance C = {g.center_distance * 1e3:.6g} mm "
                f"({g.center_distance / p:.4g} pitches){odd}")
    if abs(g.links_exact - g.links) <= 1e-9:
        return (f"chain length: {g.links} links fit the centre distance {g.center_distance_asked * 1e3:.6g} mm "
                "exactly")
    return (f"chain length: the centre distance {g.center_distance_asked * 1e3:.6g} mm "
            f"({g.center_distance_asked / p:.4g} pitches) needs {g.links_exact:.4f} pitches of chain, rounded up to "
            f"{g.links} links (an even count: no offset link), which moves C to {g.center_distance * 1e3:.6g} mm; "
            "`links` asks for another count (an odd one takes an offset link, the rating x "
            f"{OFFSET_LINK_FACTOR:g})")


def chain_checks(c: ChainCandidate, required: float, inp: ChainInputs | None = None,
                 g: ChainGeometry | None = None, lube: str | None = None) -> list[Check]:
    """The chosen (or named) chain's checks: its rating against the required rating and its
    breaking-load safety (the two rules of :data:`SELECTION_RULE`); with the drive (``inp``)
    and its geometry ``g`` also the speed the ratings hold to (galling [Shigley sec. 17-5]),
    the lubrication data, and the makers' plausibility rules: small-sprocket teeth by the
    lubrication type ``lube`` ([Shigley sec. 17-5], [Diamond FAQ]), large-sprocket teeth
    [Shigley sec. 17-5], ratio [Diamond FAQ], chain wrap [Diamond FAQ], centre distance in
    pitches [HKK].

    A chain that does not carry the drive (``--chain`` names it) fails one or both of the
    first two. Above the galling speed the rating is unverified, not a pass: the ACA charts
    do not vouch for it there (the C' region of [Shigley table 17-20]: ask the maker).
    """
    name = c.chain.name
    fc = "" if c.centrifugal is not None else "; no chain mass in the catalog: q v^2 left out"
    galls = rating_beyond = ""
    rpm = 30.0 / math.pi
    if inp is not None and c.galling_speed is not None and inp.speed > c.galling_speed * (1.0 + 1e-12):
        galls = (f"{inp.speed * rpm:.6g} rpm is above {name}'s galling speed, {c.galling_speed * rpm:.5g} rpm on "
                 f"{inp.teeth_small} teeth at this tension: pins and bushings gall (Shigley 17-5); submit the drive "
                 "to the chain maker")
        rating_beyond = (f"the ACA rating charts do not vouch for a rating above the galling speed "
                         f"({c.galling_speed * rpm:.5g} rpm; Shigley Table 17-20's Type C' region)")
    derated = f"; x {c.derating:g} for the offset link of an odd link count (U.S. Tsubaki)" if c.derating != 1 else ""
    checks = [
        RULES["chain_rating"].check(required, c.rated_power, key="rating", name=f"{name} power rating",
                                    detail=f"the {c.governing} limit{derated}; over it the chain does not carry the "
                                           "drive", unverified=rating_beyond if required <= c.rated_power else ""),
        RULES["chain_safety"].check(c.safety_factor, key="safety", name=f"{name} breaking-load safety",
                                    detail=f"F = K_s F_pull + q v^2, the service factor K_s for the shocks{fc}"),
    ]
    if inp is None or g is None:
        return checks
    z1, z2 = inp.teeth_small, inp.teeth_large
    checks.append(RULES["chain_galling"].check(
        inp.speed, c.galling_speed, key="galling", name=f"{name} speed vs galling", unverified=galls,
        detail="F = (K_s F_pull + q v^2) per strand"))
    if lube is None:
        checks.append(RULES["chain_lubrication"].check(
            c.chain_speed, None, key="lubrication", name=f"{name} lubrication",
            unverified=f"the catalog has no lubrication limits for {name}: at {c.chain_speed:.4g} m/s the "
                       "lubrication it needs is not known; ask the chain maker"))
    min_teeth = MIN_TEETH_BY_LUBRICATION[lube] if lube is not None else MIN_TEETH
    c_p = g.center_distance / c.chain.pitch
    short = c_p < (RULES["chain_center_min"].limit + RULES["chain_center_max"].limit) / 2
    checks += [
        RULES["sprocket_teeth"].check(float(z1), float(min_teeth), key="teeth_small",
                                      detail=f"z_1 >= {min_teeth}: Type {lube} lubrication" if lube is not None
                                      else f"z_1 >= {MIN_TEETH}: the lubrication type is not known"),
        RULES["sprocket_teeth_large"].check(float(z2), key="teeth_large"),
        RULES["chain_ratio"].check(z2 / z1, key="ratio", detail="above it two reductions"),
        RULES["chain_wrap"].check(g.wrap_small, key="wrap", detail="120 deg"),
        RULES["chain_center_min" if short else "chain_center_max"].check(c_p, key="center_pitches"),
    ]
    return checks
