"""The sewing-machine drive of [M16] as a network: five inertias, four spring-damper
couplings with ratios, an induction motor on shaft 1, technological loads on the main shaft
(3) and the bottom shaft (5); and the scene ``simulate sewing``: its parameters
(``catalogs/scenes/sewing.toml``) and its report, the speed, acceleration and transmitted
torque of the main and bottom shafts over a steady window. SI floats only.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    drive, its parameters and the induction motor's characteristic [M16 eq. 2].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Sequence

import numpy as np

from beltcalc.errors import InputError, require_positive, require_range
from beltcalc.params import Param
from beltcalc.design.checks import RULES, Check
from beltcalc.report import Row, Section
from beltcalc.sim.network import Network
from beltcalc.sim.scenes.base import TIMING, BatchRow, Scene, check_timing, scene_values
from beltcalc.sim.scenes.outcome import Outcome, SteadyRow, steady_sections
from beltcalc.sim.scenes.run_checks import motor_checks, resonance_check, stall_checks
from beltcalc.sim.scenes.steady import SETTLING_STATES, exact_steady_state, settling_check, settling_residual

NODES = ("1", "2", "3", "4", "5")
NAMES = {"1": "motor", "2": "driven-pulley rim", "3": "main shaft", "4": "toothed-pulley rim", "5": "bottom shaft"}
SHAFTS = {"main": ("3", "T_23"), "bottom": ("5", "T_45")}   # reported shaft: (node, torque it receives)

PARAMS = [Param(f"J{k}", "kg*m^2", f"inertia J{k}") for k in range(1, 6)]
PARAMS += [Param(f"C{k}", "N*m/rad", f"stiffness C{k}") for k in range(1, 5)]
PARAMS += [Param(f"d{k}", "N*m*s/rad", f"damping d{k}") for k in range(1, 5)]
PARAMS += [Param(name, "", f"ratio {name}") for name in ("U12", "U23", "U34", "U45")]
PARAMS += [
    Param("M3_amp", "N*m", "load amplitude on the main shaft"),
    Param("M3_0", "N*m", "mean load on the main shaft"),
    Param("M5_amp", "N*m", "load amplitude on the bottom shaft"),
    Param("M5_0", "N*m", "mean load on the bottom shaft"),
    Param("rated_torque", "N*m", "motor rated torque"),
    Param("breakdown_factor", "", "breakdown torque / rated torque"),
    Param("breakdown_slip", "", "breakdown slip"),
    Param("supply_frequency", "Hz", "supply frequency"),
    Param("pole_pairs", "", "motor pole pairs"),
    Param("load_frequency", "rad/s", "load frequency (0: the steady main-shaft speed)"),
    Param("roller_eccentricity", "m", "the eccentric tension roller's eccentricity Delta (0: constant U12)"),
    Param("motor_pulley_radius", "m", "motor pulley pitch radius r1 (the rim is U12 r1)"),
    Param("roller_radius", "m", "tension roller radius r3"),
    Param("belt_center_distance", "m", "centre distance of the motor belt"),
    Param("roller_pivot_x", "m", "the roller's pivot along the belt, from the motor pulley"),
    Param("roller_pivot_y", "m", "the roller's pivot across the belt (negative: below)"),
    Param("belt_pretension", "N", "pretension of the motor belt's spans with the roller (not given: two-way spans "
                                  "without one, the paper's belt; given: tension-only spans)", required=False),
] + TIMING

#: the roller's values by the scene's names (:func:`beltcalc.sim.elements.eccentric.refuse`)
ROLLER = {"r1": "motor_pulley_radius", "r3": "roller_radius", "a": "belt_center_distance", "px": "roller_pivot_x",
          "py": "roller_pivot_y", "delta": "roller_eccentricity"}


def check(p: dict) -> None:
    """Refuse parameter values that make no physical sense (errors name the parameter, ``scope="scene"``)."""
    with scene_values(p):
        for k in range(1, 6):
            require_positive(f"J{k}", p[f"J{k}"], "kg*m^2")
        for k in range(1, 5):
            require_range(f"C{k}", p[f"C{k}"], "N*m/rad", low=0.0)
            require_range(f"d{k}", p[f"d{k}"], "N*m*s/rad", low=0.0)
        for key in ("U12", "U23", "U34", "U45", "breakdown_factor"):
            require_positive(key, p[key], "")
        require_positive("rated_torque", p["rated_torque"], "N*m")
        require_positive("supply_frequency", p["supply_frequency"], "Hz")
        require_range("breakdown_slip", p["breakdown_slip"], "", 0.0, 1.0, low_open=True)
        require_range("load_frequency", p["load_frequency"], "rad/s", low=0.0)
        if p["pole_pairs"] < 1 or p["pole_pairs"] != int(p["pole_pairs"]):
            raise InputError(f"{p['pole_pairs']:g} is not allowed; it must be a whole number >= 1", param="pole_pairs")
        if p.get("belt_pretension") is not None:
            require_range("belt_pretension", p["belt_pretension"], "N", low=0.0)
        if p.get("roller_eccentricity", 0.0) > 0:      # else the roller's values change nothing
            from beltcalc.sim.elements.eccentric import refuse

            refuse(roller_geometry(p), ROLLER)


def roller_geometry(p: dict):
    """The eccentric roller's :class:`~beltcalc.sim.elements.beltpath.Eccentric` of the scene's values."""
    from beltcalc.sim.elements.beltpath import Eccentric

    r1 = p["motor_pulley_radius"]
    return Eccentric(r1=r1, r2=p["U12"] * r1, a=p["belt_center_distance"], r3=p["roller_radius"],
                     px=p["roller_pivot_x"], py=p["roller_pivot_y"], delta=p["roller_eccentricity"])


def steady_speed(p: dict) -> float:
    r"""Steady speed of the main shaft [rad/s] under the mean loads.

    In steady rotation the couplings do not deflect relative to the ratios, so the motor
    carries the mean loads reflected through U12 (U23 = U34 = U45 = 1 assumed here, as
    printed): :math:`M_m = (M_{3,0} + M_{5,0}) / U_{12}`; the static characteristic [M16 eq. 2]
    gives :math:`\omega_1 = \omega_0 (1 - S_c M_m / (2 M_c))`, and :math:`\omega_3 = \omega_1 / U_{12}`.

    >>> p = dict(M3_0=0.1, M5_0=0.012, U12=1.375, U23=1.0, U34=1.0, U45=1.0, rated_torque=1.2,
    ...          breakdown_factor=2.5, breakdown_slip=0.2, supply_frequency=50.0, pole_pairs=1)
    >>> round(steady_speed(p), 3)
    227.859
    """
    ratio3 = p["U12"] * p["U23"]
    ratio5 = ratio3 * p["U34"] * p["U45"]
    torque = p["M3_0"] / ratio3 + p["M5_0"] / ratio5
    w0 = 2 * math.pi * p["supply_frequency"] / p["pole_pairs"]
    mc = p["breakdown_factor"] * p["rated_torque"]
    return w0 * (1 - p["breakdown_slip"] * torque / (2 * mc)) / ratio3


#: the scene's parameters as values of its drive file (catalogs/drives/sewing.toml)
ALIASES = {**{f"J{k}": f"{k}.inertia" for k in NODES},
           **{f"C{k}": f"{k}{k + 1}.stiffness" for k in range(1, 5)},
           **{f"d{k}": f"{k}{k + 1}.damping" for k in range(1, 5)},
           **{f"U{k}{k + 1}": f"{k}{k + 1}.ratio" for k in range(1, 5)},
           "M3_0": "M3.torque", "M3_amp": "M3.amplitude", "M5_0": "M5.torque", "M5_amp": "M5.amplitude",
           "rated_torque": "motor.rated_torque", "breakdown_factor": "motor.breakdown_factor",
           "breakdown_slip": "motor.breakdown_slip", "supply_frequency": "motor.supply",
           "pole_pairs": "motor.pole_pairs", "roller_eccentricity": "12.eccentricity",
           "motor_pulley_radius": "12.pulley_radius", "roller_radius": "12.roller_radius",
           "belt_center_distance": "12.center_distance", "roller_pivot_x": "12.pivot_x",
           "roller_pivot_y": "12.pivot_y"}


def build(p: dict, angle_loads: bool = False) -> Network:
    """The network of the scene's parameters ``p`` (SI floats, keys as in sewing.toml): the
    drive file ``catalogs/drives/sewing.toml`` with the scene's values (:data:`ALIASES`),
    the loads at ``load_frequency`` (0: the steady main-shaft speed, :func:`steady_speed`).

    With ``angle_loads`` the loads follow the shaft angle, sin(phi), instead of sin(w t):
    the network is then nonlinear. With the eccentric roller and ``belt_pretension`` the
    belt's spans are tension-only (:class:`~beltcalc.sim.elements.eccentric.EccentricBelt`).
    """
    check(p)
    values = {alias: p[name] for name, alias in ALIASES.items()}
    values["motor.pole_pairs"] = int(p["pole_pairs"])
    w = 0.0 if angle_loads else (p["load_frequency"] or steady_speed(p))
    for load in ("M3", "M5"):
        values[f"{load}.frequency"] = w
        if angle_loads:
            values[f"{load}.order"] = 1.0
    net = _drive_file().network(values)
    if p.get("belt_pretension") is not None:
        # the drive file has no key for it: the scene gives it to the eccentric belt (none
        # without eccentricity: the constant-ratio coupling has no spans)
        from beltcalc.sim.elements.eccentric import EccentricBelt

        net.elements = [el.with_pretension(p["belt_pretension"]) if isinstance(el, EccentricBelt) else el
                        for el in net.elements]
    return net


@lru_cache(maxsize=1)
def _drive_file():
    """catalogs/drives/sewing.toml, read once (a sweep builds the drive at every point)."""
    from beltcalc.sim.drivefile import DriveFile, drive_path

    return DriveFile(drive_path("sewing"))


def whole_period_window(t_end: float, window: float, omega: float) -> tuple[float, int]:
    """(start, periods): the latest start >= ``window`` from which [start, t_end] holds whole
    load periods 2 pi / omega; (window, 0) when not one period fits.

    >>> start, k = whole_period_window(1.0, 0.5, 227.85910934810255)
    >>> round(start, 8), k
    (0.50365234, 18)
    """
    if omega <= 0:
        return window, 0
    period = 2 * math.pi / omega
    k = int(math.floor((t_end - window) / period + 1e-9))
    return (t_end - k * period, k) if k >= 1 else (window, 0)


def run(values: dict, cfg, angle_loads: bool = False, steady_state_only: bool = False) -> Outcome:
    """One run: per shaft (main, bottom) the mean and amplitude of speed, acceleration and
    transmitted torque, and the motor's speed and torque, twice:

    - from the time simulation's samples over the steady window, moved to the latest start
      at or after ``window`` that holds whole load periods;
    - in the exact periodic steady state (:func:`beltcalc.sim.frequency.steady_state`),
      where the loads are sinusoids in time (not with ``angle_loads``).

    ``steady_state_only`` skips the time simulation (a sweep then costs under a millisecond a point)."""
    import time

    from beltcalc.sim.core import simulate
    from beltcalc.sim.result import SimResult

    samples = check_timing(values)
    net = build(values, angle_loads)
    notes = []
    steady = None
    eccentric = values.get("roller_eccentricity", 0.0) > 0
    if angle_loads or eccentric:
        why = ("the loads follow the shaft angle" if angle_loads else "the eccentric tension roller varies U12") + \
            " (nonlinear)"
    else:
        t0 = time.perf_counter()
        steady, why = exact_steady_state(net, STEADY_SIGNALS)
        steady_wall = time.perf_counter() - t0
    if steady is None and steady_state_only:
        raise InputError(f"{why}: there is no exact steady state; leave out `steady_state_only`",
                         param="steady_state_only")
    if steady_state_only:
        result = SimResult(t=np.zeros(0), signals={}, units={}, method="steady state",
                           reason="exact periodic steady state: the drive is linear with sinusoidal loads, so "
                                  "every signal is mean + Re(H(jw) e^{jwt}) (no time simulation)",
                           wall_time=steady_wall, steps=0, rhs_calls=0)
        breakdown = values["breakdown_factor"] * values["rated_torque"]
        checks = stall_checks(steady.mean["M_motor"], steady.mean["omega_1"], breakdown, "periodic steady state")
        return Outcome(net, result, _steady_sections(steady), notes, checks)
    if eccentric and cfg.method == "exact":
        reasons = "; ".join(sorted({el.nonlinear_reason for el in net.elements if el.nonlinear_kind}))
        raise InputError("the exact method needs a network that is linear between switches; this one is not: "
                         f"{reasons}: use `method` radau (or auto)", param="method")
    omega = abs(net.frequencies()[0]) if net.frequencies() else 0.0     # a stalled drive's loads turn backwards
    start, periods = whole_period_window(values["t_end"], values["window"], omega)
    result = simulate(net, values["t_end"], samples, cfg)
    if periods:
        notes.append(f"window t >= {start:.6g} s: {periods} whole load periods of {2 * math.pi / omega:.6g} s "
                     f"(asked from {values['window']:g} s)")
    elif omega:
        result.warnings.append(f"the window {values['window']:g}..{values['t_end']:g} s is shorter than one load "
                               f"period ({2 * math.pi / omega:.4g} s): its means and amplitudes are of a part of "
                               "a cycle" + ("; the steady-state rows are exact" if steady is not None else ""))
    sections = []
    for name, (node, torque) in SHAFTS.items():
        speed, accel, tq = (result.summary(s, start) for s in (f"omega_{node}", f"accel_{node}", torque))
        sections.append(Section(("shafts", name), f"{name} shaft ({node}), t >= {start:.4g} s" if name == "main"
                                else f"{name} shaft ({node})", [
            Row("speed_mean", "speed, mean", speed.mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed, amplitude", speed.amplitude, "rad/s"),
            Row("accel_amplitude", "acceleration, amplitude", accel.amplitude, "rad/s^2"),
            Row("torque_mean", "transmitted torque, mean", tq.mean, "N m"),
            Row("torque_amplitude", "transmitted torque, amplitude", tq.amplitude, "N m"),
        ]))
    speed, torque = result.summary("omega_1", start), result.summary("M_motor", start)
    sections.append(Section(("motor",), "motor (1)", [
        Row("speed_mean", "speed, mean", speed.mean, "rad/s", "rpm", digits=5),
        Row("torque_mean", "torque, mean", torque.mean, "N m"),
        Row("torque_amplitude", "torque, amplitude", torque.amplitude, "N m"),
    ]))
    if steady is None:
        notes.append(f"no exact steady state: {why}")
    else:
        sections += _steady_sections(steady)
    span_checks = []
    if eccentric:
        span_rows, span_checks = _span_forces(net, values, result, start)
        sections += _roller_sections(values, cfg, result, start, angle_loads, span_rows)
    breakdown = values["breakdown_factor"] * values["rated_torque"]
    # the paper's start from rest, direct on line, runs the linearised characteristic far beyond
    # breakdown (the model's own limit, not the drive's): the peak is checked in the window
    checks = motor_checks(result, "M_motor", breakdown, start, peak_from=start, speed="omega_1")
    checks += resonance_check(net, result, start)
    checks += span_checks
    checks += settling_check(net, start, values["t_end"])
    if omega:
        checks.append(RULES["window_periods"].check(float(periods)))
    return Outcome(net, result, sections, notes, checks, window=start)


def _roller_sections(values: dict, cfg, result, start: float, angle_loads: bool,
                     span_rows: list[Row]) -> list[Section]:
    """The eccentric tension roller: the ratio U12 over the window (min, max, its ripple
    frequency, once per roller turn: r1/r3 times the motor's speed), each shaft's speed
    and torque amplitude with the roller against the same drive with a constant U12 (run
    alike, without eccentricity), then ``span_rows`` (:func:`_span_forces`)."""
    from beltcalc.sim.core import simulate

    ratio = result.summary("U_12", start)
    r1, r3 = values["motor_pulley_radius"], values["roller_radius"]
    ripple = r1 / r3 * result.summary("omega_1", start).mean / (2 * math.pi)
    plain = simulate(build(dict(values, roller_eccentricity=0.0), angle_loads), values["t_end"],
                     int(values["samples"]), cfg)
    rows = [Row("ratio_min", "U12, min", ratio.min, "1", digits=5),
            Row("ratio_max", "U12, max", ratio.max, "1", digits=5),
            Row("ripple_frequency", "U12 ripple frequency (once per roller turn)", ripple, "Hz")]
    for name, (node, torque) in SHAFTS.items():
        for sig, what, unit in ((f"omega_{node}", "speed", "rad/s"), (torque, "torque", "N m")):
            with_roller, constant = result.summary(sig, start).amplitude, plain.summary(sig, start).amplitude
            rows += [Row(f"{name}_{what}_amplitude", f"{name} shaft {what} amplitude, with the roller",
                         with_roller, unit),
                     Row(f"{name}_{what}_amplitude_constant", "  with constant U12", constant, unit),
                     Row(f"{name}_{what}_amplitude_ratio", "  with / without", with_roller / constant, "1",
                         digits=3)]
    rows += span_rows
    return [Section(("roller",), f"eccentric tension roller (Delta = {values['roller_eccentricity'] * 1e3:g} mm), "
                                 f"t >= {start:.4g} s", rows)]


@dataclass(frozen=True)
class _SpanCheck(Check):
    """The belt spans' check, whose warning is one line of its own (the span, its least force,
    the pretension, the eccentricity at which it slackens)."""

    line: str = ""

    def warning(self) -> str:
        return self.line


def _span_forces(net, values: dict, result, start: float) -> tuple[list[Row], list[Check]]:
    """Each span of the roller's belt against its pretension: its least force over the steady
    window (the check: a span pulls only while its force is > 0) and over the whole run (the
    start from rest included), the share of the window it is slack; and, where a span
    slackens, the eccentricity from which it does (quasi-static,
    :meth:`~beltcalc.sim.elements.eccentric.EccentricBelt.slackening_eccentricity`).

    Without ``belt_pretension`` the spans are two-way springs without one (the paper's belt):
    their force changes stand for their forces, and any fall below zero is a span that would
    need a pretension to stay taut."""
    from beltcalc.sim.elements.eccentric import EccentricBelt

    belt = next(el for el in net.elements if isinstance(el, EccentricBelt))
    f0, name = belt.pretension, belt.name
    prefix = "F" if f0 is not None else "dF"
    rows, least, share = [], {}, {}
    if f0 is not None:
        rows.append(Row("pretension", "belt pretension (each span)", f0, "N"))
    for side in ("tight", "slack"):
        force = result[f"{prefix}_{name}_{side}"]
        window = force[result.t >= start]
        least[side], share[side] = float(window.min()), float(np.mean(window <= 0))
        what = "force" if f0 is not None else "force change from the pretension"
        rows += [Row(f"{side}_force_min", f"{side} span {what}, min", least[side], "N"),
                 Row(f"{side}_force_min_run", "  over the whole run (from rest)", float(force.min()), "N")]
        if f0 is not None:
            rows.append(Row(f"{side}_slack_share", "  share of the window slack", share[side], "1", digits=3))
    # the span the line is about: the lower one; of two slack ones, the one slack longer
    side = max(("slack", "tight"), key=lambda k: -least[k] if f0 is None else (least[k] <= 0, share[k], -least[k]))
    other = "slack" if side == "tight" else "tight"
    rule = (f"the least force of the two spans over the window t >= {start:.4g} s: a span pulls only while its force "
            "is > 0 (the start from rest is left out, as for the motor's peak)")
    if f0 is None:
        rule = "no pretension given: the spans are two-way; " + rule + "; their force change stands for it"
    spans = {"key": "belt_spans_taut", "name": f"belt {name} span force, min", "detail": rule,
             "signals": (f"{prefix}_{name}_tight", f"{prefix}_{name}_slack")}
    if least[side] > 0:
        return rows, [RULES["span_taut"].check(least[side], **spans)]
    window = f"the window t >= {start:.4g} s"
    if f0 is None:
        line = (f"belt {name}: no pretension given (`belt_pretension`): its spans are two-way springs, and the {side} "
                f"span's force falls {-least[side]:.4g} N below its pretension over {window} (the {other} span's "
                f"{-least[other]:.4g} N): with a pretension under that it goes slack at this eccentricity, which this "
                "run does not model; give `belt_pretension` to model the spans tension-only")
    else:
        speed = result.summary(f"omega_{belt.i}", start).mean
        pull = result.summary(f"T_{name}", start).mean / belt.geometry.r1     # F_t - F_s, transmitted
        level = f0 - pull / 2 if side == "slack" else f0 + pull / 2
        at = belt.slackening_eccentricity(level, speed)
        from_ = ("at any eccentricity (the pretension is under half the transmitted force)" if at == 0 else
                 "only through the drive's dynamics (quasi-statically it stays taut up to where the belt leaves the "
                 "roller)" if at is None else f"from an eccentricity of about {at * 1e3:.3g} mm (quasi-static)")
        also = f", the {other} span {share[other]:.0%}" if least[other] <= 0 else ""
        line = (f"belt {name}: its {side} span loses its tension: its force falls from the pretension {f0:.4g} N to "
                f"{least[side]:.4g} N ({share[side]:.0%} of {window} slack{also}), modelled tension-only; at this "
                f"pretension it slackens {from_}, here {values['roller_eccentricity'] * 1e3:g} mm; raise "
                "`belt_pretension` or lower `roller_eccentricity`")
    return rows, [RULES["span_taut"].check(least[side], **spans, cls=_SpanCheck, line=line)]


STEADY_SIGNALS = ["omega_3", "accel_3", "T_23", "omega_5", "accel_5", "T_45", "omega_1", "M_motor"]


def _steady_sections(ss) -> list[Section]:
    """The exact periodic steady state, shaft by shaft and the motor
    (:func:`~beltcalc.sim.scenes.outcome.steady_sections`)."""
    layout = [(f"{name}_shaft", f"{name} shaft ({node}), periodic steady state (exact)", [
        SteadyRow("speed_mean", "speed, mean", f"omega_{node}", digits=5),
        SteadyRow("speed_amplitude", "speed, amplitude", f"omega_{node}", "amplitude"),
        SteadyRow("accel_amplitude", "acceleration, amplitude", f"accel_{node}", "amplitude"),
        SteadyRow("torque_mean", "transmitted torque, mean", torque),
        SteadyRow("torque_amplitude", "transmitted torque, amplitude", torque, "amplitude"),
    ], "", "") for name, (node, torque) in SHAFTS.items()]
    layout.append(("motor_steady", "motor (1), periodic steady state (exact)", [
        SteadyRow("speed_mean", "speed, mean", "omega_1", display="rpm", digits=5),
        SteadyRow("torque_mean", "torque, mean", "M_motor"),
        SteadyRow("torque_amplitude", "torque, amplitude", "M_motor", "amplitude"),
    ], "", ""))
    # the columns of a sweep or study: steady_main_*, steady_bottom_*, steady_motor_* beside the
    # window's main_*, bottom_*, motor_* (the JSON keeps main_shaft, bottom_shaft, motor_steady)
    return [replace(sec, key=key) for sec, key in zip(steady_sections(ss, layout), [*SHAFTS, "motor"])]


def batched_rows(chunk: Sequence[dict], cfg, angle_loads: bool = False,
                 steady_state_only: bool = False) -> list[list[float] | None]:
    """The rows of :func:`run` (per shaft the window's speed mean and amplitude, acceleration
    amplitude, torque mean and amplitude; the motor's speed mean, torque mean and amplitude;
    the same in the exact periodic steady state) for the runs of a study's ``chunk`` (each
    run's SI values) by batched exact propagation (:mod:`beltcalc.sim.batch`), where the batch
    can vouch for the run; None for the others (their single run). The scene's batch row
    (:class:`~beltcalc.sim.scenes.base.BatchRow`)."""
    from beltcalc.sim.batch import MARGIN, eigenvalues, exact_windows, resonance_separation, steady_stats, window_stats
    from beltcalc.sim.frequency import poles_of

    if angle_loads or not steady_state_only and cfg.method not in ("auto", "exact"):
        return [None] * len(chunk)
    out: list = [None] * len(chunk)
    nets, vals, keys = {}, {}, {}
    for r, v in enumerate(chunk):
        try:
            samples = check_timing(v)
            if v.get("roller_eccentricity", 0.0) > 0:
                continue                               # the eccentric roller: nonlinear
            net = build(v)
        except Exception:                              # the single run says why, as a row
            continue
        freqs = net.frequencies()
        if not (net.linear and net.smooth) or len(freqs) != 1 or freqs[0] <= 0:
            continue
        nets[r], vals[r] = net, v
        keys[r] = (net.size, tuple(net.state_names()), len(net.generators(0.0)), samples,
                   float(v["t_end"]), steady_state_only)
    if not nets:
        return out
    common = max(set(keys.values()), key=lambda k: sum(1 for v in keys.values() if v == k))
    runs = [r for r in nets if keys[r] == common]
    ss_mean, ss_amp, ss_ok = steady_stats([nets[r] for r in runs], STEADY_SIGNALS)
    runs = [r for r, good in zip(runs, ss_ok) if good]        # a drive that does not balance: its single run
    ss_mean, ss_amp = ss_mean[ss_ok], ss_amp[ss_ok]
    steady = {r: [] for r in runs}
    for j, r in enumerate(runs):
        for name, (node, torque) in SHAFTS.items():
            i = {s: STEADY_SIGNALS.index(s) for s in (f"omega_{node}", f"accel_{node}", torque)}
            steady[r] += [ss_mean[j, i[f"omega_{node}"]], ss_amp[j, i[f"omega_{node}"]],
                          ss_amp[j, i[f"accel_{node}"]], ss_mean[j, i[torque]], ss_amp[j, i[torque]]]
        steady[r] += [ss_mean[j, STEADY_SIGNALS.index("omega_1")], ss_mean[j, STEADY_SIGNALS.index("M_motor")],
                      ss_amp[j, STEADY_SIGNALS.index("M_motor")]]
    if steady_state_only:
        for j, r in enumerate(runs):
            # the single run's stall checks (motor mean torque under breakdown, turning forwards):
            # a run near or past either goes through it
            breakdown = vals[r]["breakdown_factor"] * vals[r]["rated_torque"]
            torque, speed = ss_mean[j, STEADY_SIGNALS.index("M_motor")], ss_mean[j, STEADY_SIGNALS.index("omega_1")]
            if abs(torque) / breakdown > 1 - MARGIN or not speed > 0:
                continue
            out[r] = steady[r]
        return out

    _, _, _, samples, t_end, _ = common
    t = np.linspace(0.0, t_end, samples)
    first, window = [], {}
    for r in runs:
        v = vals[r]
        window[r] = whole_period_window(v["t_end"], v["window"], nets[r].frequencies()[0])
        first.append(int(np.searchsorted(t, window[r][0] - 1e-12, side="left")))
    wanted = [s for node, torque in SHAFTS.values() for s in (f"omega_{node}", f"accel_{node}", torque)]
    wanted += ["omega_1", "M_motor"]
    est = cfg.estimate_error
    for idx, k, Y, err in exact_windows([nets[r] for r in runs], t, first, wanted, est):
        lam = eigenvalues([nets[runs[jj]] for jj in idx])           # the poles of each run, one call
        seps = resonance_separation([nets[runs[jj]] for jj in idx], lam)
        for j, jj in enumerate(idx):
            r = runs[jj]
            v, periods = vals[r], window[r][1]
            if periods < 1:
                continue                               # a window shorter than a period: a warning
            if est and err[j] > 0.5 * cfg.error_tol:
                continue                               # auto would refine; the single run decides
            mean, amp, lo, hi = window_stats(t[first[jj]:], Y[j, :, first[jj] - k:])
            row = []
            for s in (0, 3):                           # main, bottom: speed, accel, torque
                row += [mean[s], amp[s], amp[s + 1], mean[s + 2], amp[s + 2]]
            row += [mean[6], mean[7], amp[7]]
            breakdown = v["breakdown_factor"] * v["rated_torque"]
            utils = [abs(mean[7]) / breakdown, max(abs(lo[7]), abs(hi[7])) / breakdown]
            if not mean[6] > 0:                        # the motor turns backwards: the single run's stall check
                continue
            if est:
                utils.append(err[j] / cfg.error_tol)
            if np.isfinite(seps[j]):                   # resonance_check: separation >= the rule's margin
                utils.append(RULES["resonance"].limit / seps[j] if seps[j] > 0 else math.inf)
            # settling_check: the transient left at the window start (the single run's check)
            if nets[r].size <= SETTLING_STATES:
                settled = settling_residual(nets[r], window[r][0], float(v["t_end"]), poles_of(lam[j]))
                if settled is not None:
                    utils.append(settled[0] / RULES["window_settled"].limit)
            if max(utils) > 1 - MARGIN:
                continue
            out[r] = [float(x) for x in row] + steady[r]
    return out


SCENE = Scene(
    "sewing", "sewing", PARAMS, build, run, "omega_3", "C4=50N*m/rad:310N*m/rad:14",
    # shown in a sweep's table: the exact steady state's, else (loads in the shaft angle) the window's
    ("steady_main_speed_amplitude_rad_per_s", "steady_main_accel_amplitude_rad_per_s2",
     "steady_main_torque_amplitude_N_m", "steady_bottom_speed_amplitude_rad_per_s",
     "steady_bottom_accel_amplitude_rad_per_s2", "steady_bottom_torque_amplitude_N_m",
     "main_speed_amplitude_rad_per_s", "main_accel_amplitude_rad_per_s2", "main_torque_amplitude_N_m",
     "bottom_speed_amplitude_rad_per_s", "bottom_accel_amplitude_rad_per_s2", "bottom_torque_amplitude_N_m"),
    (("speed [rad/s]", (("omega_3", "main shaft"), ("omega_5", "bottom shaft"))),
     ("acceleration [rad/s^2]", (("accel_3", "main shaft"), ("accel_5", "bottom shaft"))),
     ("transmitted torque [N m]", (("T_23", "main shaft"), ("T_45", "bottom shaft")))),
    batch=BatchRow(run, batched_rows),
)
