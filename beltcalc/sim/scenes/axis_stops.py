"""The linear axis's moves and what the carriage does after each (:mod:`beltcalc.sim.scenes.linear_axis`):
the profile's timeline (its moves and the position it commands), the following error,
residual vibration and settling time at each stop and their checks, the static positioning
error, each move's input shaper, and the motor torque's and belt force's extremes. SI floats.

References:

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
import numpy as np

from beltcalc.design.checks import RULES
from beltcalc.report import Row, Section

def reference_tables(model) -> tuple[tuple, tuple, tuple]:
    """(acceleration, speed, feed-forward torque) of the move at the motor shaft as
    piecewise-linear tables (t, value): the profile's phases (the acceleration linear in a
    jerk phase, from its right limit at the start to its left limit at the end) and the
    rigid duty's torque piece by piece (linear on each piece of a trapezoid; the speed and
    torque tables are exact for trapezoids only, which is all the speed loop takes)."""
    from beltcalc.design.polynomials import poly_value

    accel, speed = [], []
    t = 0.0
    for ph in model.profile.phases:
        accel += [(t, ph.accel), (t + ph.duration, ph.accel1)]
        speed += [(t, ph.speed0), (t + ph.duration, ph.speed1)]
        t += ph.duration
    accel.append((t, 0.0))
    torque = []
    for start, _, sign in moves(model):
        # the way back is the way out negated: the rigid torque of a horizontal axis is odd in the
        # motion (inertia, viscous and Coulomb friction all reverse with it)
        for p in model.duty.pieces:
            torque += [(start + p.start, sign * poly_value(p.torque, 0.0)),
                       (start + p.start + p.duration, sign * poly_value(p.torque, p.duration))]
    torque.append((t, 0.0))
    return tuple(accel), tuple(speed), tuple(torque)


def phase_starts(model) -> list[float]:
    """The start time of each phase of the profile [s]."""
    out, t = [], 0.0
    for ph in model.profile.phases:
        out.append(t)
        t += ph.duration
    return out


def moves(model) -> list[tuple[float, float, float]]:
    """(start, end, direction +-1) of each move of the profile [s]: the runs of phases between
    its dwells (one move; out and back: two)."""
    out: list[tuple[float, float, float]] = []
    run = None
    for ph, start in zip(model.profile.phases, phase_starts(model)):
        if ph.name.endswith("dwell"):
            run = None
            continue
        if run is None:
            run = [start, start + ph.duration, -1.0 if ph.name.startswith("back ") else 1.0]
            out.append(run)
        else:
            run[1] = start + ph.duration
    return [tuple(m) for m in out]


def move_time(model) -> float:
    """End of the (first) move [s]."""
    return moves(model)[0][1]


def reference_position(model, t: np.ndarray) -> np.ndarray:
    """The carriage position the profile commands [m], exact per phase."""
    t = np.asarray(t, dtype=float)
    out = np.zeros_like(t)
    start, angle = 0.0, 0.0
    for ph in model.profile.phases:
        tau = np.clip(t - start, 0.0, ph.duration)
        inside = t >= start
        out = np.where(inside, angle + ph.speed0 * tau + 0.5 * ph.accel * tau ** 2 + ph.jerk * tau ** 3 / 6, out)
        start += ph.duration
        angle += ph.angle
    return out * model.lever


@dataclass(frozen=True)
class Stop:
    """The carriage at the end of one move: ``where`` (words), the move's end ``t_end`` and the
    end of the stop ``until`` [s] (the next move's start, or the run's end), the largest
    following error during the move and the residual vibration's amplitude (half its
    peak-to-peak) over the stop [m], the time from the move's end until the following error
    stays within the band of its rest value to ``until`` (``settle`` [s], None: it does not),
    and that rest value ``rest`` [m] (the motor's own position error, where the belt carries
    no force: 0 under an ideal servo)."""

    where: str
    t_end: float
    until: float
    following_max: float
    residual: float
    settle: float | None
    rest: float


def stop_figures(model, result, band: float) -> list[Stop]:
    """Each move's following error and its stop's residual vibration and settling time (off
    the output samples: the settling time to the output step)."""
    error = result.signals["following_error"]
    # the motor's own position error: the carriage rests there when the belt carries no force
    motor_error = result["phi_motor"] * model.lever - reference_position(model, result.t)
    runs = moves(model)
    t_last = float(result.t[-1])
    out = []
    for k, (t0, t1, sign) in enumerate(runs):
        until = runs[k + 1][0] if k + 1 < len(runs) else t_last
        during, after = result.window(t0, t1), result.window(t1, until)
        rest = float(motor_error[after][-1])
        settle = result.settle_time("following_error", rest, band, t1, until)
        where = "at the end of the stroke" if sign > 0 else "back at the start"
        out.append(Stop(where, t1, until, float(np.abs(error[during]).max()),
                        0.5 * float(error[after].max() - error[after].min()),
                        None if settle is None else settle - t1, rest))
    return out


def stop_rows(stops: list[Stop], band: float) -> list[Row]:
    """The carriage's rows: per move, the following error, the residual vibration and the
    settling time into ``band`` [m] (the first move's rows keep their one-move keys)."""
    rows = []
    for k, st in enumerate(stops):
        tag, label = ("", "the move") if k == 0 else ("_back", "the move back")
        rows += [
            Row(f"following_error_max{tag}", f"following error, max during {label}", st.following_max, "m", "mm"),
            Row(f"residual_amplitude{tag}", f"residual vibration after {label}, amplitude", st.residual, "m", "mm",
                note=f"carriage {st.where}, to t = {st.until:.6g} s"),
            Row(f"settling_time{tag}", f"settling time after {label} (band {band * 1e3:g} mm)", st.settle, "s",
                note="not within the stop" if st.settle is None else ""),
        ]
    return rows


def static_sections(model, force: float | None, pretension: float) -> list[Section]:
    """The static positioning error under ``force`` [N] on the carriage at standstill
    (:mod:`beltcalc.design.positioning`: the two spans in parallel, each C_spec / L): at the
    stroke's start and end and the worst place along it, and the pretension that keeps both
    spans taut under the force either way, against ``pretension`` [N]."""
    from beltcalc.design.positioning import along_stroke

    if not force:
        return []
    a, d = model.center_distance, model.axis.pulley_diameter
    c_spec = model.stiffness * a                       # k_TB = C_spec / a
    ends = sorted((model.start, model.start + model.travel))
    s = along_stroke(force, c_spec, a, d, np.linspace(ends[0], ends[1], 201))
    at = {"start": model.start, "end": model.start + model.travel}
    rows = []
    for key, x in at.items():
        k = int(np.argmin(np.abs(s.positions - x)))
        rows.append(Row(f"static_error_{key}", f"carriage deflection at the stroke's {key}", float(s.stretch[k]), "m",
                        "mm", note=f"span 1 {x * 1e3:.5g} mm; k = {float(s.span_stiffness[k]):.4g} N/m"))
    rows += [
        Row("static_error_worst", "  worst along the stroke", s.worst.stretch, "m", "mm",
            note=f"span 1 {s.worst.span1 * 1e3:.5g} mm (closed form)"),
        Row("static_pretension_needed", "pretension to keep both spans taut under +-F", s.least_pretension, "N",
            note=f"the belt's F_t,peak {pretension:.4g} N"),
    ]
    title = f"static positioning error under {force:g} N (belt stretch, both spans; docs/positioning.md)"
    return [Section(("static",), title, rows)]


def settling_checks(stops: list[Stop], band: float, last: bool = True) -> list:
    """The settling check of each stop that a move follows (``last``: the run's final stop
    too, whose end is the run's): the settling time into ``band`` [m] against the stop's
    length (not settled: beyond any figure)."""
    out = []
    for k, st in enumerate(stops):
        if k == len(stops) - 1 and not last:
            continue
        tag = "" if k == 0 else "_back"
        out.append(RULES["settling"].check(
            math.inf if st.settle is None else st.settle, st.until - st.t_end, key=f"settling{tag}",
            detail=f"the carriage {st.where}, into +-{band * 1e3:g} mm of its rest"
                   + (": not settled within the stop" if st.settle is None else ""), signals=("following_error",)))
    return out


def shaper_rows(model) -> list[Row]:
    """Each move's input shaper: its kind, design frequency and damping ratio, and the time it
    adds to the move."""
    rows = []
    for k, m in enumerate(model.shaped):
        tag, label = ("", "the move") if k == 0 else ("_back", "the move back")
        sh = m.shaper
        where = "at the end of the stroke" if k == 0 else "back at the start"
        rows += [Row(f"shaper_frequency{tag}", f"{sh.name.upper()} shaper of {label}, design frequency", sh.frequency,
                     "Hz", note=f"the first mode {where}, damping ratio {sh.zeta:.3g}"
                     + (" (convolved with the shaper for where it starts)" if "*" in sh.name else "")),
                 Row(f"shaper_time{tag}", f"  time it adds to {label}", sh.duration, "s")]
    return rows


def extremes(net, model, result, t_end: float, cycle_time: float):
    """(motor torque, belt force, how) as :class:`~beltcalc.sim.watch.pieces.ExactSignal`:
    off the exact solution on a linear network (both limits at every phase end); off the
    output samples on a nonlinear one (moving spans), ``how`` saying so and how far a sample
    may be from the extreme (a step times the largest rate seen)."""
    from beltcalc.sim.watch.pieces import ExactSignal, coupling_row, drive_torque_row, exact_signals

    rms_end = cycle_time if t_end >= cycle_time - 1e-12 else None
    if net.linear:
        exact = exact_signals(net, {"torque": lambda tm: drive_torque_row(net, "motor", tm),
                                    "force": lambda tm: coupling_row(net, "belt", 1.0 / model.lever)},
                              t_end, cuts=tuple(t for m in moves(model) for t in m[:2] if t > 0),
                              rms_end=rms_end)
        return exact["torque"], exact["force"], ""
    t = result.t
    step = float(t[1] - t[0])
    out = []
    for name in ("T_drive_motor", "F_belt"):
        y = np.asarray(result.signals[name], dtype=float)
        hi, lo = int(np.argmax(y)), int(np.argmin(y))
        square = None
        if rms_end is not None:
            inside = t <= rms_end + 1e-12
            square = float(np.trapezoid(y[inside] ** 2, t[inside]))
        out.append(ExactSignal(float(y[hi]), float(t[hi]), "", float(y[lo]), float(t[lo]), "", square))
    rate = float(np.abs(np.diff(result.signals["T_drive_motor"])).max())
    return out[0], out[1], (f"; from the output samples (moving spans: solved implicitly), to within "
                            f"{rate:.2g} N m of one step ({step * 1e3:.3g} ms)")
