"""The check layer: one :class:`Check` per design rule (value, limit, margin, verdict).

A check is ``value <= limit`` (``kind="max"``) or ``value >= limit`` (``kind="min"``).
Its utilisation is value/limit (max) or limit/value (min): 1 is exactly at the limit,
above 1 fails. A check that cannot be made (a table the catalog lacks, an input not
given) has verdict ``"n/a"`` and says why in ``reason``; it never fails silently.

A check whose figures the sources do not vouch for (a running speed beyond the maker's
table or rating chart, a chain with no lubrication data) has verdict ``"unverified"`` and
says why in ``unverified``. It is not a pass: like a FAIL it is a warning (stderr and the
JSON's ``warnings``) and it fails ``--strict`` (:func:`failures` returns both).

Every check is made from a :class:`Rule` of :data:`RULES` (``RULES["chain_safety"].check(...)``):
one definition of each limit, its kind, unit and source, whichever command meets the
quantity (``chain`` and a simulated chain strand, ``tension`` and a drive file's fitted
belt damping). docs/design_checks.md lists them (tested against the registry).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping


@dataclass(frozen=True)
class Check:
    """One design check, SI values. ``rule`` says what is compared and where it comes from."""

    key: str
    name: str
    value: float | None
    limit: float | None
    unit: str
    kind: str = "max"          # "max": value <= limit; "min": value >= limit
    rule: str = ""
    reason: str = ""           # why it is n/a
    signals: tuple[str, ...] = ()   # time signals whose magnitude the limit bounds (a plot draws it there)
    level: float | None = None      # where it differs from ``limit``: the bound on ``signals``, in their unit
                                    # (a safety factor's allowable force)
    unverified: str = ""            # why the sources do not vouch for the figures: the verdict is "unverified"
    score: bool = False             # the value is a score (a fit's R^2), not a load: shown as itself, never
                                    # as a utilisation (0.9 / R^2 is no fraction of a capacity)

    @property
    def utilisation(self) -> float | None:
        """value / limit (max) or limit / value (min); None when n/a.

        >>> Check("t", "tooth shear", 50.0, 100.0, "N").utilisation
        0.5
        >>> Check("z", "teeth", 20.0, 15.0, "1", kind="min").utilisation
        0.75
        """
        if self.value is None or self.limit is None:
            return None
        if self.kind == "max":
            return self.value / self.limit if self.limit > 0 else float("inf")
        return self.limit / self.value if self.value > 0 else float("inf")

    @property
    def margin(self) -> float | None:
        """limit - value (max) or value - limit (min), in ``unit``; None when n/a."""
        if self.value is None or self.limit is None:
            return None
        return self.limit - self.value if self.kind == "max" else self.value - self.limit

    @property
    def verdict(self) -> str:
        """``"pass"``, ``"FAIL"``, ``"n/a"``, or ``"unverified"`` where ``unverified`` says why
        the figures are not vouched for (whatever they are: the caller decides when).

        >>> Check("t", "tooth shear", 150.0, 100.0, "N").verdict
        'FAIL'
        >>> Check("t", "tooth shear", 50.0, None, "N", unverified="beyond the table").verdict
        'unverified'
        """
        if self.unverified:
            return "unverified"
        u = self.utilisation
        if u is None:
            return "n/a"
        return "pass" if u <= 1.0 + 1e-12 else "FAIL"

    def warning(self) -> str:
        """The one-line warning of a failed or unverified check (no figure beyond a float
        printed as ``inf``).

        >>> Check("m", "belt mass", 0.14, 1e-320, "kg").warning()
        'belt mass FAILS: 0.14 kg must be <= 1e-320 kg (utilisation beyond any finite figure; )'
        >>> Check("t", "tooth shear", 264.0, None, "N", rule="F_U c2 <= F_tspec b z_e",
        ...       unverified="12000 rpm is beyond the table").warning()
        'tooth shear UNVERIFIED: 12000 rpm is beyond the table; not a pass (F_U c2 <= F_tspec b z_e)'
        """
        if self.unverified:
            return f"{self.name} UNVERIFIED: {self.unverified}; not a pass ({self.rule})"
        op = "<=" if self.kind == "max" else ">="
        unit = "" if self.unit in ("", "1") else f" {self.unit}"
        u = self.utilisation
        used = (f"utilisation {percent(u)}" if u is not None and math.isfinite(u)
                else "utilisation beyond any finite figure")
        return (f"{self.name} FAILS: {figure(self.value)}{unit} must be {op} {figure(self.limit)}{unit} "
                f"({'' if self.score else used + '; '}{self.rule})")

    def to_dict(self) -> dict:
        """JSON-ready: values ``{"value", "unit"}``, utilisation and margin, verdict, rule
        (never NaN: None with the reason); ``reason``: why it is n/a or unverified."""
        return {"key": self.key, "name": self.name,
                "value": {"value": self.value, "unit": self.unit}, "limit": {"value": self.limit, "unit": self.unit},
                "kind": self.kind, "margin": {"value": self.margin, "unit": self.unit},
                "utilisation": {"value": self.utilisation, "unit": "1"}, "verdict": self.verdict,
                "rule": self.rule, **({"reason": self.unverified or self.reason} if self.unverified or self.reason else {})}


def figure(value: float | None, spec: str = ".4g") -> str:
    """``value`` for a sentence: formatted by ``spec``; one beyond a float (or none) in words.

    >>> figure(2688.04), figure(float("inf")), figure(float("nan"))
    ('2688', 'a figure beyond a float', 'no figure')
    """
    if value is None or math.isnan(value):
        return "no figure"
    if math.isinf(value):
        return "a figure beyond a float" if value > 0 else "a figure below any float"
    return format(value, spec)


PERCENT_MAX = 999      # a percentage is printed up to this; beyond it a factor ("x12.3")


def percent(fraction: float | None, decimals: int = 0) -> str:
    """``fraction`` (0.23: 23 %) for a sentence or a table: a percentage with ``decimals``
    decimals up to :data:`PERCENT_MAX` %, beyond it the factor with three significant digits
    ("x12.3": 12.3 times), so that no percentage runs to "228000000%"; one beyond a float
    (or none) in words (:func:`figure`).

    >>> percent(0.2304), percent(0.2304, 1), percent(9.99), percent(12.34), percent(1000.4), percent(2.28e6)
    ('23%', '23.0%', '999%', 'x12.3', 'x1000', 'x2.28e+06')
    >>> percent(float("inf")), percent(None)
    ('a figure beyond a float', 'no figure')
    """
    if fraction is None or not math.isfinite(fraction):
        return figure(fraction)
    shown = f"{fraction * 100:.{decimals}f}"
    if abs(float(shown)) <= PERCENT_MAX:
        return f"{shown}%"
    return f"x{float(f'{fraction:.3g}'):g}"       # three digits, no exponent below 1e6: x1000, not x1e+03


def failures(checks) -> list[Check]:
    """The checks that do not pass: those that FAIL and those that are unverified (each a
    warning, each failing ``--strict``). An n/a check is neither."""
    return [c for c in checks if c.verdict in ("FAIL", "unverified")]


# --- the registry of rules ---------------------------------------------------------------------

@dataclass(frozen=True)
class Rule:
    """One design rule: what is compared (``quantity``), against what (``limit``, or where the
    limit is data of the case, ``limit_name``), which way (``kind``), in which ``unit``, and
    where the rule comes from (``source``: document, page or table; "assumed" or "our rule"
    where it is ours). ``met_by``: the commands whose checks use it.

    :meth:`check` makes the :class:`Check` of a value: every command meeting the quantity
    gets the same limit, kind and rule text; ``detail`` says what the value is in this case.

    >>> r = RULES["chain_safety"]
    >>> c = r.check(5.29, key="safety", name="10B-1 breaking-load safety", detail="F = K_s F_pull + q v^2")
    >>> c.limit, c.kind, c.verdict, c.rule.split(" (")[0]
    (6.0, 'min', 'FAIL', 'F_B / F >= 6')
    >>> RULES["belt_tension_member"].check(450.0, 2200.0).verdict
    'pass'
    """

    key: str
    label: str
    limit: float | None          # None: the limit is data of the case (``limit_name``), given to :meth:`check`
    unit: str
    kind: str                    # "max": value <= limit; "min": value >= limit
    quantity: str                # the compared quantity in symbols
    source: str
    limit_name: str = ""         # what the limit is where it is data (the catalog's F_Tadm)
    met_by: tuple[str, ...] = ()
    score: bool = False          # the quantity is a score (R^2), not a load: its checks show the value itself

    @property
    def formula(self) -> str:
        """The rule in symbols: ``"F_B / F >= 6"``, ``"F <= F_Tadm"``."""
        return self.written()

    def written(self, quantity: str | None = None) -> str:
        """The rule in symbols with ``quantity`` as a command writes it (only where the limit
        is data: a fixed limit's rule reads the same in every command)."""
        op = "<=" if self.kind == "max" else ">="
        if self.limit is None:
            return f"{quantity or self.quantity} {op} {self.limit_name}"
        if quantity is not None:
            raise ValueError(f"rule {self.key!r} has the fixed limit {self.limit:g}: its quantity is "
                             f"{self.quantity!r} in every command (say what it is in `detail`)")
        unit = "" if self.unit in ("", "1") else f" {self.unit}"
        return f"{self.quantity} {op} {self.limit:g}{unit}"

    def text(self, detail: str = "", quantity: str | None = None) -> str:
        """The rule as a check states it: formula, source, then ``detail`` (this case).

        >>> RULES["belt_tension_member"].text("the catalog's F_Tadm", quantity="F_U + F_v")[:22]
        'F_U + F_v <= F_Tadm (t'
        """
        return f"{self.written(quantity)} ({self.source})" + (f"; {detail}" if detail else "")

    def check(self, value: float | None, limit: float | None = None, *, key: str | None = None,
              name: str | None = None, detail: str = "", reason: str = "", signals: tuple[str, ...] = (),
              level: float | None = None, unit: str | None = None, quantity: str | None = None,
              cls: type | None = None, **extra) -> Check:
        """The :class:`Check` of ``value`` [``unit``] by this rule. ``limit``: only for a rule
        whose limit is data (None there with a ``reason``: n/a); a fixed limit cannot be given.
        ``key``/``name``: the check's own (default: the rule's); ``unit``: another spelling
        of the rule's unit (``"N*m"`` for ``"N m"``); ``quantity``: the compared quantity as
        the command writes it (:meth:`written`); ``cls``: a :class:`Check` subclass (its
        ``extra`` fields)."""
        if self.limit is not None:
            if limit is not None:
                raise ValueError(f"rule {self.key!r} has the fixed limit {self.limit:g}; it takes no other")
            limit = self.limit
        if unit is not None and unit.replace("*", " ") != self.unit.replace("*", " "):
            raise ValueError(f"rule {self.key!r} is in {self.unit!r}, not {unit!r}")
        return (cls or Check)(key or self.key, name or self.label, value, limit, unit or self.unit, kind=self.kind,
                              rule=self.text(detail, quantity), reason=reason, signals=tuple(signals), level=level,
                              score=self.score, **extra)


_SHEET = "the motor's data sheet (catalogs/motors)"
_GEARBOX = "the gearbox's rating (catalogs/gearboxes: its maker's page)"
_BREAKDOWN = ("Mamatova et al. 2016 eq. 2: an induction motor's linearised characteristic, up to its breakdown "
              "torque M_c")

#: Every design rule a command checks, by key (:class:`Rule`); docs/design_checks.md's table.
RULES: Mapping[str, Rule] = {r.key: r for r in (
    # roller chains
    Rule("chain_rating", "chain power rating", None, "W", "max", "n_d K_s P",
         "ACA rating formulas, Shigley 9th ed. eq. 17-32/17-33, K2 Table 17-23",
         limit_name="K2 min(H1, H2)", met_by=("chain",)),
    Rule("chain_safety", "breaking-load safety", 6.0, "1", "min", "F_B / F",
         "Diamond Chain, technical engineering guide: the load in service at most 1/6 of the minimum ultimate "
         "tensile strength F_B (ISO 606 / ASME B29.1 minimum)",
         met_by=("chain", "simulate roller-table", "simulate drive")),
    Rule("chain_fatigue", "chain strand vs fatigue", None, "N", "max", "F_max",
         "U.S. Tsubaki Roller Chain General Catalog: the maximum allowable load, 'derived from the lowest fatigue "
         "limit: when a load lower than this value is repetitively applied to the roller chain, fatigue failure will "
         "never occur' (catalogs/chains.toml); a chain without one is unverified",
         limit_name="the maker's allowable dynamic load", met_by=("simulate roller-table", "simulate drive")),
    Rule("chain_galling", "chain speed vs galling", None, "rad/s", "max", "n_1",
         "Shigley 9th ed. 17-5: the speed is limited by galling between pin and bushing, n_1 <= 1000 [82.5 / "
         "(7.95^p 1.0278^N_1 1.323^(F/1000))]^(1/(1.59 log p + 1.873)) rpm, p in, F lbf; beyond it the check and "
         "the rating are unverified (Table 17-20's Type C' region: submit the design to the maker)",
         limit_name="the galling speed", met_by=("chain",)),
    Rule("chain_lubrication", "chain lubrication", None, "m/s", "max", "v",
         "McGuire Bearing, 'Better chain performance': Type A / B / C by chain speed for chains 40-160; a chain "
         "without a row is unverified", limit_name="the lubrication table's speeds (a row for the chain)",
         met_by=("chain",)),
    Rule("sprocket_teeth", "small sprocket teeth", None, "1", "min", "z_1",
         "Diamond Chain FAQ, smallest sprocket for chordal action: 12 / 17 / 25 teeth with drip / oil bath / pumped "
         "lubrication; Shigley 9th ed. 17-5: at least 17 for moderate and high speeds (the type not known)",
         limit_name="12 / 17 / 25 by lubrication type A / B / C (17 where not known)", met_by=("chain",)),
    Rule("sprocket_teeth_large", "large sprocket teeth", 120.0, "1", "max", "z_2",
         "Shigley 9th ed. 17-5: no standard sprockets over 120 teeth (a worn chain rides high)", met_by=("chain",)),
    Rule("chain_ratio", "speed ratio", 7.0, "1", "max", "z_2 / z_1",
         "the chain makers' FAQ on the largest single reduction, 7:1 (Diamond Chain's wording, as reproduced at "
         "experts123.com); Shigley 17-5: the most successful drives up to 6:1", met_by=("chain",)),
    Rule("chain_wrap", "chain wrap, small sprocket", 2.0 * math.pi / 3.0, "rad", "min", "theta_1",
         "Diamond Chain FAQ, minimum chain wrap: 120 deg on the smallest sprocket (90 deg only with close tension "
         "control)", met_by=("chain",)),
    Rule("chain_center_min", "centre distance in pitches", 30.0, "1", "min", "C / p",
         "HKK Chain, engineering information 'Installation': 30 to 50 pitches optimum", met_by=("chain",)),
    Rule("chain_center_max", "centre distance in pitches", 80.0, "1", "max", "C / p",
         "the longest centre distance the common rules allow, 80 pitches (e.g. PTC Asia, 'The center distance and "
         "chain length': a = (30-50) p, a_max <= 80 p)", met_by=("chain",)),
    # timing belts
    Rule("belt_tooth_shear", "tooth shear", None, "N", "max", "F_U c2",
         "BRECO F_tspec(n) tables; Wojtkowiak et al. 2021 sec. 3.2; c2: Tsubaki Tables 1-4",
         limit_name="F_tspec(n) b z_e", met_by=("belt-drive",)),
    Rule("belt_tension_member", "tension member", None, "N", "max", "F",
         "the belt maker's allowable tension F_Tadm per width (Elatech catalogue p. 55; catalogs/belts)",
         limit_name="F_Tadm", met_by=("belt-drive", "tension", "simulate drive")),
    Rule("pretension_linear", "installation tension", None, "N", "min", "F_v", "Elatech catalogue p. 55",
         limit_name="F_U", met_by=("belt-drive",)),
    Rule("pretension_endless", "installation tension", None, "N", "min", "F_v",
         "slack side T_2 = F_v - c2 F_U / 2 >= 0 at the design load c2 F_U: Shigley eq. 17-1 with the Tsubaki "
         "service factor c2", limit_name="c2 F_U / 2", met_by=("belt-drive",)),
    Rule("pulley_teeth", "pulley teeth", None, "1", "min", "z_1",
         "the belt maker's z_min (catalogs/belts: the maker's page)", limit_name="z_min", met_by=("belt-drive",)),
    Rule("teeth_in_mesh", "teeth in mesh", 6.0, "1", "min", "z_e",
         "Tsubaki Table 6: meshing factor 1.0 from 6 teeth in mesh", met_by=("belt-drive",)),
    Rule("damping_fit", "damping fit R^2", 0.9, "1", "min", "R^2",
         "our limit, on the line through the origin fitted to the catalog's F_tspec(n) (DESIGN.md 2.1; "
         "Wojtkowiak et al. 2021 give none): below it b_TB = |slope| describes the table poorly",
         met_by=("tension", "simulate drive"), score=True),
    Rule("belt_mass", "belt mass", None, "kg", "max", "m_belt",
         "plausibility, our rule: Wojtkowiak et al. 2021 eq. 7-11 treat the belt as a spring with a small added "
         "mass on the carriage", limit_name="the mass it moves", met_by=("tension", "simulate linear-axis")),
    Rule("belt_slack", "belt force", None, "N", "max", "|F_belt|",
         "Wojtkowiak et al. 2021 eq. 10-11: above the pretension the slack span goes slack",
         limit_name="F_t,peak (the pretension)", met_by=("simulate linear-axis",)),
    Rule("settling", "settling in the stop", None, "s", "max", "t_settle",
         "our rule: the carriage settles into the band before the next move starts",
         limit_name="the stop (the dwell)", met_by=("simulate linear-axis", "motor-size")),
    Rule("span_taut", "belt span force, min", 0.0, "N", "min", "F_min",
         "our rule: a tension-only span pulls only while its force is > 0", met_by=("simulate sewing",)),
    # motors
    Rule("motor_peak_torque", "motor peak torque", None, "N m", "max", "T_peak", _SHEET, limit_name="T_max",
         met_by=("motor-size", "simulate linear-axis")),
    Rule("motor_rms_torque", "motor RMS torque", None, "N m", "max", "T_rms", _SHEET,
         limit_name="T_n (or the continuous zone at the mean speed)", met_by=("motor-size", "simulate linear-axis")),
    Rule("motor_speed", "motor speed", None, "rad/s", "max", "n_peak", _SHEET, limit_name="n_max",
         met_by=("motor-size", "simulate linear-axis")),
    Rule("motor_inertia_ratio", "load/motor inertia ratio", None, "1", "max", "J_load / J_M",
         "Parker's guidance for servos", limit_name="`inertia_ratio_limit` (default 10)", met_by=("motor-size",)),
    Rule("motor_zone", "torque-speed zone", None, "N m", "max", "(1 + `peak_margin`) |T|",
         _SHEET + " (or an assumed zone)", limit_name="the intermittent zone's torque at that speed",
         met_by=("motor-size",)),
    Rule("gearbox_input_speed", "gearbox input speed", None, "rad/s", "max", "n_in", _GEARBOX,
         limit_name="n_max,in", met_by=("motor-size",)),
    Rule("gearbox_peak_torque", "gearbox peak output torque", None, "N m", "max", "i T_peak,load", _GEARBOX,
         limit_name="T_peak,out", met_by=("motor-size",)),
    Rule("gearbox_rms_torque", "gearbox RMS output torque", None, "N m", "max", "i T_rms,load", _GEARBOX,
         limit_name="T_rated,out", met_by=("motor-size",)),
    Rule("breakdown_peak", "motor peak torque", None, "N m", "max", "|M|", _BREAKDOWN, limit_name="M_c",
         met_by=("simulate sewing", "simulate roller-table", "simulate drive")),
    Rule("breakdown_mean", "motor mean torque", None, "N m", "max", "|M_mean|",
         _BREAKDOWN + "; beyond it the motor stalls", limit_name="M_c",
         met_by=("simulate sewing", "simulate roller-table", "simulate drive")),
    Rule("motor_direction", "motor speed, mean", 0.0, "rad/s", "min", "omega_mean",
         "our rule: at or below 0 the loads turn the stalled train backwards against the motor",
         met_by=("simulate sewing", "simulate roller-table", "simulate drive")),
    # simulation
    Rule("error_estimate", "error estimate", None, "1", "max", "error / scale",
         "DESIGN.md 3.1: the run's error estimate against the tolerance it was given",
         limit_name="the accepted tolerance", met_by=("simulate",)),
    Rule("resonance", "load vs resonance", 0.1, "1", "min", "|f_e - f_n| / f_n",
         "an assumed design margin: closer, the response is resonant", met_by=("simulate", "study")),
    Rule("window_settled", "transient at the window start", 1e-3, "1", "max", "r",
         "an assumed limit: the slowest pole has decayed ln(1000) time constants", met_by=("simulate", "study")),
    Rule("window_periods", "steady window", 1.0, "1", "min", "whole load periods",
         "our rule: the window's means and amplitudes are of whole cycles", met_by=("simulate sewing",)),
)}


def rules_table() -> str:
    """docs/design_checks.md's table of :data:`RULES` (markdown), one row per rule."""
    lines = ["| rule | check | rule in symbols | limit | unit | source | met by |", "|---|---|---|---|---|---|---|"]
    for r in RULES.values():
        cells = (f"`{r.key}`", r.label, r.formula, f"{r.limit:g}" if r.limit is not None else r.limit_name,
                 r.unit or "-", r.source, ", ".join(r.met_by))
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines)
