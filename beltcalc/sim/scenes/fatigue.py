"""The tension-only strands a scene reports (:func:`tension_strands`) and the fatigue of its
chain strands: per chain strand its peak force against the maker's allowable dynamic load,
the rainflow count of its force and the Miner damage per hour and life
(:func:`fatigue_sections`), and the check of the most loaded one (:func:`fatigue_check`,
rule ``chain_fatigue`` of :data:`beltcalc.design.checks.RULES`). SI floats; nothing here
prints or writes files.

The count runs over the samples of the strand's force over the whole run (the window its
rows report): a peak between two samples is cut to the larger of them, and the damage per
hour takes the run as repeating, start-up included.

References:

[ASTM E1049] ASTM E1049-85 (reapproved 2017), Standard Practices for Cycle Counting in
    Fatigue Analysis: rainflow counting [ASTM E1049 sec. 5.4.4].
[Miner45] M. A. Miner, "Cumulative damage in fatigue", J. Appl. Mech. 12 (1945) A159-A164:
    the damage sum [Miner45 eq. 1].
"""

from __future__ import annotations

import numpy as np

from beltcalc.design.checks import RULES
from beltcalc.report import Row, Section

HOUR = 3600.0


def tension_strands(net) -> list:
    """The tension-only strands a scene reports: the network's strands but a backlash's
    contacts (its backlash reports them), then every element that says it carries tension
    only (``tension_only = True``: a nonlinear chain strand, which the core does not list
    among ``net.strands``). Each has a ``name`` and the force signal ``F_<name>``."""
    from beltcalc.sim.elements.backlash import Contact

    every = getattr(net, "tension_strands", None)
    if every is None:           # a stand-in without the network's own list (doctests)
        every = list(net.strands) + [el for el in getattr(net, "elements", ()) if getattr(el, "tension_only", False)]
    return [s for s in every if not isinstance(s, Contact)]


def slack_time(net, result, name: str) -> float:
    """The time strand ``name`` was slack over the run [s]: the run's own figure where it
    kept one (``result.extra["slack_time"]``; a linear strand it does not list never went
    slack), else from the samples of ``F_<name>`` (the time its force is at or below zero, an
    interval with one such end counted half)."""
    slack = result.extra.get("slack_time") or {}
    if name in slack or any(s.name == name for s in net.strands):
        return float(slack.get(name, 0.0))
    f = result.signals.get(f"F_{name}")
    if f is None or f.size < 2:
        return 0.0
    zero = f <= 0.0
    dt = np.diff(result.t)
    return float(np.sum(dt[zero[:-1] & zero[1:]]) + 0.5 * np.sum(dt[zero[:-1] ^ zero[1:]]))


def strand_fatigue(net) -> dict:
    """The chain strands with their fatigue data (:class:`beltcalc.formulas.fatigue.StrandFatigue`),
    as the drive-file builder gave them to the network; none for a network built otherwise."""
    return dict(getattr(net, "fatigue", None) or {})


def fatigue_sections(net, result) -> list[Section]:
    """One section per chain strand (``chain_fatigue.<name>``): the maker's allowable dynamic
    load, the peak force over it, the load cycles the rainflow count finds
    [ASTM E1049 sec. 5.4.4] and the largest range, the Miner damage per hour [Miner45 eq. 1] on the
    chain's S-N curve (:func:`beltcalc.formulas.fatigue.chain_sn_curve`: the allowable load
    published, the slope assumed) and the life to D = 1. A chain without an allowable load
    has its count only (damage and life null, the note says why)."""
    from beltcalc.formulas.fatigue import chain_sn_curve, damage_rate, life, miner_damage, rainflow

    data = strand_fatigue(net)
    out = []
    duration = float(result.t[-1] - result.t[0]) if result.t.size > 1 else 0.0
    for strand in tension_strands(net):
        fat = data.get(strand.name)
        if fat is None or f"F_{strand.name}" not in result.signals:
            continue
        peak = result.summary(f"F_{strand.name}", 0.0).max
        cycles = rainflow(result.signals[f"F_{strand.name}"])
        largest = float(cycles.ranges.max()) if cycles.ranges.size else 0.0
        counted = f"rainflow over the {result.t.size} samples of t = 0..{result.t[-1]:g} s"
        rows = [Row("dynamic_load", "allowable dynamic load", fat.allowable, "N", note=fat.origin)]
        if fat.allowable is None:
            rows += [Row("dynamic_utilisation", "max / allowable dynamic load", None, "1", digits=3,
                         note="no allowable dynamic load"),
                     Row("cycles", "load cycles counted", cycles.total, "1", note=counted),
                     Row("range_max", "largest force range", largest, "N"),
                     Row("damage_rate", "Miner damage per hour", None, "1/s", "1/h", note="no S-N curve"),
                     Row("life", "life to D = 1", None, "s", "h", note="no S-N curve")]
        else:
            curve = chain_sn_curve(fat.allowable)
            rate = damage_rate(miner_damage(cycles.ranges, cycles.means, cycles.counts, curve), duration) \
                if duration > 0 else 0.0
            lasts = life(rate)
            how = (f"S-N curve {curve.origin}: range {curve.range_ref:.4g} N at {curve.cycles_ref:.3g} cycles, "
                   f"slope {curve.slope:g}, none below; the run repeating")
            rows += [Row("dynamic_utilisation", "max / allowable dynamic load", peak / fat.allowable, "1", digits=3),
                     Row("cycles", "load cycles counted", cycles.total, "1", note=counted),
                     Row("range_max", "largest force range", largest, "N"),
                     Row("damage_rate", "Miner damage per hour", rate, "1/s", "1/h", note=how),
                     Row("life", "life to D = 1", lasts if np.isfinite(lasts) else None, "s", "h",
                         note="" if np.isfinite(lasts) else "no damage: every range below the curve's knee")]
        out.append(Section(("chain_fatigue", strand.name), strand.name, rows, item=strand.name, key=strand.name,
                           group="chain strands, fatigue, whole run (allowable dynamic load: the maker's fatigue "
                                 "limit; damage per hour: Miner on an assumed S-N slope, per the samples)"))
    return out


def fatigue_check(net, result) -> list:
    """The fatigue check of the most loaded chain strand (rule ``chain_fatigue``): its peak
    force over the run against the maker's allowable dynamic load (the largest utilisation
    among the strands that have one). Unverified where a chain strand has none (the
    breaking-load check does not cover fatigue), unless a strand with one already fails;
    no chain strand: no check."""
    data = strand_fatigue(net)
    rule = RULES["chain_fatigue"]
    known, unknown = [], []
    for strand in tension_strands(net):
        fat = data.get(strand.name)
        if fat is None or f"F_{strand.name}" not in result.signals:
            continue
        peak = result.summary(f"F_{strand.name}", 0.0).max
        (known if fat.allowable is not None else unknown).append((peak, strand.name, fat))
    if not known and not unknown:
        return []
    missing = ""
    if unknown:
        chains = sorted({f.chain for _, _, f in unknown})
        missing = (f"no maker's allowable dynamic load for {', '.join(chains)} (catalogs/chains.toml): "
                   f"{len(unknown)} of {len(known) + len(unknown)} chain strands unchecked for fatigue; give the "
                   "strand's allowable_dynamic_load (a drive file's [[chain_strand]] key) from the chain's maker")
    if known:
        peak, name, fat = max(known, key=lambda k: k[0] / k[2].allowable)
        detail = f"the peak force of strand {name} ({fat.chain}, {fat.origin}) over the run"
        check = rule.check(peak, fat.allowable, key="strand_fatigue", detail=detail, signals=(f"F_{name}",))
        if missing and check.verdict != "FAIL":
            check = rule.check(peak, fat.allowable, key="strand_fatigue", detail=detail, signals=(f"F_{name}",),
                               unverified=missing)
        return [check]
    peak, name, fat = max(unknown, key=lambda k: k[0])
    return [rule.check(peak, None, key="strand_fatigue", signals=(f"F_{name}",), unverified=missing,
                       detail=f"the peak force of strand {name} ({fat.chain}) over the run")]
