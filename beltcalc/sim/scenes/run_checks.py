"""The checks a scene's run makes of its drive: the strength of its most loaded strand and
the fatigue of its most loaded chain strand (:func:`strand_check`), its periodic loads against its natural frequencies
(:func:`resonance_check`), an induction motor's torque against its breakdown torque
(:func:`motor_checks`) and whether the motor runs at all (:func:`stall_checks`,
:func:`stalls`, :func:`stall_line`). Each is a :class:`~beltcalc.design.checks.Check` of a rule of
:data:`beltcalc.design.checks.RULES`.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    induction motor's linearised characteristic [M16 eq. 2], which holds below the
    breakdown torque.
"""

from __future__ import annotations

import math
from typing import Mapping

from beltcalc.design.checks import RULES


#: The rule of a strand by the limit it is given (``limits[name] = (N, what)``): a chain's
#: breaking load F_B with the safety F_B / F >= 6 that ``chain`` applies; a belt's F_Tadm.
STRAND_RULES = {"breaking load": "chain_safety", "F_Tadm": "belt_tension_member"}


def strand_check(net, result, limits: Mapping[str, tuple[float, str]], chain_param: str | None = "chain") -> list:
    """The strength check of the most loaded strand over the whole run, with how many
    strands fail theirs: a chain strand's breaking-load safety F_B / F against the same rule
    (:data:`beltcalc.design.checks.RULES` ``chain_safety``) as ``chain`` (which takes F = K_s F_pull
    + q v^2: its service factor stands for the shocks a run computes), a belt strand's peak
    force against F_Tadm (``belt_tension_member``). ``limits[name] = (N, what)``, ``what``
    a key of :data:`STRAND_RULES`; the most loaded is the one of largest utilisation. A chain
    strand that fails it is told the breaking load it needs and the first one-strand chain of
    ``catalogs/chains.toml`` (smallest pitch) that has it, set by ``chain_param`` (a scene's
    parameter; None: none names it). The strands are :func:`~beltcalc.sim.scenes.fatigue.tension_strands`;
    then the fatigue check of the most loaded chain strand
    (:func:`~beltcalc.sim.scenes.fatigue.fatigue_check`, where the network carries chain
    strands' fatigue data).

    >>> from types import SimpleNamespace as NS
    >>> net = NS(strands=[NS(name="a")])
    >>> res = NS(summary=lambda name, start: NS(max=4196.0))
    >>> c, = strand_check(net, res, {"a": (22.2e3, "breaking load")})
    >>> round(c.value, 3), c.limit, c.verdict, c.level       # 22.2 kN / 4196 N; F_B / 6 on F_a
    (5.291, 6.0, 'FAIL', 3700.0)
    """
    from beltcalc.sim.scenes.fatigue import fatigue_check, tension_strands

    checks = []
    for s in tension_strands(net):
        if s.name not in limits:
            continue
        f, (limit, what) = result.summary(f"F_{s.name}", 0.0).max, limits[s.name]
        rule = RULES[STRAND_RULES[what]]
        if rule.limit is None:             # a force limit (F_Tadm)
            checks.append((rule.check(f, limit, key="strand_strength", name="strand force"), s.name, limit, what))
        else:                              # a safety on the breaking load
            safety = limit / f if f > 0 else math.inf
            checks.append((rule.check(safety, key="strand_strength", name="strand breaking-load safety"),
                           s.name, limit / rule.limit, what))
    fatigue = fatigue_check(net, result)
    if not checks:
        return fatigue
    over = sum(1 for c, *_ in checks if c.verdict == "FAIL")
    worst, name, level, what = max(checks, key=lambda c: c[0].utilisation)
    detail = f"the peak force F over the run of strand {name}, the most loaded against its {what}"
    if over > 1:
        detail += f"; {over} of {len(checks)} strands fail it"
    signals = tuple(f"F_{n}" for _, n, lev, w in checks if lev == level and w == what)
    rule = RULES[STRAND_RULES[what]]
    if rule.limit is None:
        return [rule.check(worst.value, worst.limit, key="strand_strength", name=worst.name, detail=detail,
                           signals=signals)] + fatigue
    if worst.verdict == "FAIL":
        detail += "; " + _stronger_chain(rule.limit * limits[name][0] / worst.value, chain_param)
    return [rule.check(worst.value, key="strand_strength", name=worst.name, detail=detail, signals=signals,
                       level=level)] + fatigue


def _stronger_chain(need: float, param: str | None) -> str:
    """What to do where a chain strand needs the breaking load ``need`` [N]: the first
    one-strand chain of the built-in catalog (smallest pitch, then breaking load) that has it.

    >>> _stronger_chain(25.18e3, "chain")
    'it needs a chain of F_B >= 25.18 kN at this peak force: `chain`=12B-1 (28.9 kN, the smallest one-strand chain of catalogs/chains.toml that has it), then run again (another pitch changes the sprockets and the force)'
    """
    from beltcalc.data.catalogs import load_catalog

    text = f"it needs a chain of F_B >= {need / 1e3:.4g} kN at this peak force"
    fits = sorted((c for c in load_catalog().chains.values() if c.strands == 1 and c.breaking_load >= need),
                  key=lambda c: (round(c.pitch, 9), c.breaking_load))    # 60-1 and 12B-1: 19.05 mm
    if not fits:
        return text + ": stronger than every one-strand chain of catalogs/chains.toml; more strands or a lower load"
    pick = f"`{param}`={fits[0].name}" if param else fits[0].name
    return (text + f": {pick} ({fits[0].breaking_load / 1e3:.4g} kN, the smallest one-strand chain of "
            "catalogs/chains.toml that has it), then run again (another pitch changes the sprockets and the force)")


def resonance_check(net, result, window: float) -> list:
    """Plausibility: the drive's own periodic loads against its natural frequencies.

    Each load with an amplitude excites ``omega / 2 pi`` (a sine in time) or ``order`` times
    its node's mean speed over the steady window over ``2 pi`` (locked to the shaft angle).
    The check is the least relative separation ``|f_e - f_n| / f_n`` over the undamped
    natural frequencies ``f_n`` of the oscillatory modes (strands taut, a backlash closed on
    one side: :func:`beltcalc.sim.elements.backlash.closed_pattern`,
    :func:`beltcalc.sim.frequency.poles`) against the rule ``resonance`` of
    :data:`beltcalc.design.checks.RULES` (an assumed margin of 10 %). No periodic
    load, or no oscillatory mode: no check.
    """
    excitations = []
    for ld in net.loads:
        if not ld.amplitude:
            continue
        if ld.in_angle:
            name = f"omega_{ld.node}"
            if name not in result.signals:
                continue
            excitations.append((abs(ld.order * result.summary(name, window).mean) / (2 * math.pi),
                                f"the load on {ld.node}"))
        elif ld.omega:
            excitations.append((abs(ld.omega) / (2 * math.pi), f"the load on {ld.node}"))
    for el in net.elements:              # element kinds with a periodic excitation of their own
        if hasattr(el, "excitation"):
            excitations += el.excitation(result, window)
    if not excitations:
        return []
    from beltcalc.sim.elements.backlash import closed_pattern
    from beltcalc.sim.frequency import poles

    modes = [p for p in poles(net, closed_pattern(net)) if p.kind == "oscillatory"]
    if not modes:
        return []
    sep, f_e, node, p = min(((abs(f - p.frequency) / p.frequency, f, node, p)
                             for f, node in excitations for p in modes), key=lambda x: x[0])
    return [RULES["resonance"].check(sep, detail=f"{node} excites {f_e:.4g} Hz, {sep:.1%} from a natural frequency "
                                                 f"of {p.frequency:.4g} Hz (damping ratio {p.damping_ratio:.3g})")]


def motor_checks(result, signal: str, breakdown: float, window: float, peak_from: float = 0.0,
                 speed: str | None = None) -> list:
    """An induction motor's torque against its breakdown torque M_c: the mean over the steady
    window (beyond it the motor stalls) and the peak from ``peak_from`` [s] on (beyond it the
    linearised characteristic [M16 eq. 2] does not hold); with ``speed`` (the
    motor node's speed signal) whether the motor turns forwards over the window
    (:func:`stall_checks`)."""
    mean, part = result.summary(signal, window).mean, result.summary(signal, peak_from)
    peak = max(abs(part.min), abs(part.max))
    span = "over the run" if peak_from <= 0 else f"t >= {peak_from:.4g} s"
    turning, rising = None, False
    if speed is not None:
        turning = result.summary(speed, window).mean
        w = result.signals[speed][result.t >= window - 1e-12 * max(1.0, window)]
        # a motor still gaining speed through the window is starting up, not stalled: its
        # torque goes into the train's acceleration (a short window early in the run)
        rising = bool(turning > 0 and w.size > 1 and w[-1] - w[0] > ACCELERATING * turning)
    return stall_checks(mean, turning, breakdown, f"t >= {window:.4g} s", (signal,), rising) + [
        RULES["breakdown_peak"].check(peak, breakdown, key="motor_peak_torque", detail=span, signals=(signal,))]


#: The checks whose failure means the drive stalls (:func:`stall_checks`): a run that fails
#: one has no steady state to report.
STALL_CHECKS = ("motor_mean_torque", "motor_direction")


#: A motor turning forwards whose speed rises by more than this part of its mean over the
#: window is starting up.
ACCELERATING = 0.01


def stall_checks(torque: float, speed: float | None, breakdown: float, where: str, signals: tuple = (),
                 rising: bool = False) -> list:
    """Does an induction motor run? Its mean torque ``torque`` [N m] against its breakdown
    torque M_c (beyond it a real motor's torque falls and it stalls: the linearised
    characteristic [M16 eq. 2] would go on rising), and its mean speed
    ``speed`` [rad/s] (None: not checked) in the direction of its synchronous speed (always
    forwards, > 0): loads that turn the motor backwards against the torque it drives
    with have stalled the train. ``where``: the window, for the rule. ``rising``: the motor
    gains speed through the window (a start-up): its mean torque check is n/a, not a verdict.

    >>> [c.verdict for c in stall_checks(2.0, 150.0, 3.0, "t >= 0.5 s")]
    ['pass', 'pass']
    >>> [c.verdict for c in stall_checks(36.4, -66.6, 3.0, "t >= 0.5 s")]
    ['FAIL', 'FAIL']
    """
    out = [RULES["breakdown_mean"].check(
        None if rising else abs(torque), breakdown, key="motor_mean_torque", detail=where, signals=signals,
        reason="the motor still gains speed through the window (a start-up): its mean torque goes into "
               "accelerating the train, no verdict on a stall" if rising else "")]
    if speed is not None:
        out.append(RULES["motor_direction"].check(speed, detail=f"{where}, in the direction of its synchronous "
                                                                 "speed"))
    return out


def stalls(checks) -> list:
    """The failing checks of ``checks`` that mean the drive stalls (:data:`STALL_CHECKS`)."""
    from beltcalc.design.checks import failures

    return [c for c in failures(checks) if c.key in STALL_CHECKS]


def stall_line(checks) -> str:
    """One line saying how the drive stalls, from its failing :data:`STALL_CHECKS`.

    >>> stall_line(stall_checks(36.4, -66.6, 3.0, "t >= 0.5 s"))
    'the drive stalls: motor mean torque 36.4 N m beyond the breakdown torque 3 N m (t >= 0.5 s); motor speed, mean -66.6 rad/s: the loads turn it backwards'
    """
    parts = []
    for c in stalls(checks):
        if c.key == "motor_direction":
            parts.append(f"{c.name} {c.value:.4g} {c.unit}: the loads turn it backwards")
        else:
            parts.append(f"{c.name} {c.value:.4g} {c.unit} beyond the breakdown torque {c.limit:.4g} {c.unit} "
                         f"({c.rule.split('; ')[-1]})")
    return "the drive stalls: " + "; ".join(parts)

