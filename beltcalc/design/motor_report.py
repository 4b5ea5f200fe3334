"""What a motor sizing reports: the rows of a sized duty cycle grouped in sections, its JSON
object, the torque profile sampled (and as CSV text), the torque-speed panel's data, and the
table of a sweep with each point's rating checks.

Everything here reads a :class:`beltcalc.design.sizing.CycleSizing` (or the points of
:func:`beltcalc.design.sizing.sweep`) and returns SI floats in :class:`~beltcalc.report.Row` and
:class:`~beltcalc.report.Section`, plain dicts and text; nothing prints, parses options or
writes files. A text that points at an input names it in backquotes, as the library's
errors do (```motor```); ``name`` (as in :func:`beltcalc.errors.render`) says how a caller
prints such a name: the command line passes the option that sets it.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from typing import Callable, Sequence

from beltcalc.design.checks import Check, failures, percent
from beltcalc.errors import render
from beltcalc.report import Row, Section, format_number, quantity


def _same(name: str) -> str:
    return name


# The load / motor inertia ratio with no motor to report: no rotor inertia to divide by (a
# physical absence, not a float's range).
NO_MOTOR_RATIO = "no motor fits, so there is no rotor inertia to divide by; give `motor` NAME"

# A torque profile needs a motor: its rotor and its losses are part of the torque.
NO_PROFILE = "no motor fits, so there is no torque profile; give `motor` NAME"

def _rpm(w: float) -> str:
    return f"{w * 30 / math.pi:.0f} rpm"


def _jerk_limited(g) -> bool:
    """Whether the jerk keeps move ``g`` below its acceleration limit (see
    :func:`beltcalc.design.sizing.jerk_limited`)."""
    p = g.profile
    return (g.kind == "move" and math.isfinite(getattr(p, "jerk", math.inf))
            and p.peak_accel < p.accel * (1 - 1e-12))


def report_sections(s, name: Callable[[str], str] = _same) -> list[Section]:
    """The rows of the sized cycle ``s`` in sections: motion, reflected inertia and, with a
    motor to report, the torque at the motor shaft, the torque-speed zone, the regeneration
    and the gearbox's checks (each where it has rows). With one move, the torque of each
    phase; with several, the first move's acceleration and energy.

    >>> from beltcalc.data.catalogs import load_catalog
    >>> from beltcalc.params import resolve
    >>> from beltcalc.data.scenefile import load_scene
    >>> from beltcalc.design.axis_inputs import PARAMS, SizingInputs
    >>> from beltcalc.design.sizing import DutyOptions, size_cycle
    >>> cat = load_catalog()
    >>> values = resolve(load_scene("wdu", command="motor-size"), PARAMS, {})
    >>> inp = SizingInputs.from_values({k: v.value for k, v in values.items()})
    >>> s = size_cycle(inp, cat.belt(values["belt"].value), list(cat.motors.values()), None, DutyOptions())
    >>> [sec.path[0] for sec in report_sections(s)]
    ['motion', 'inertia', 'torque', 'zone', 'regeneration']
    """
    from beltcalc.design.sizing import first_move_energy

    ax, shown = s.axis, s.shown
    move = s.first_move
    prof = move.profile
    single = s.drive and len([g for g in s.segments if g.kind == "move"]) == 1
    motor_j = shown.motor.J if shown else 0.0
    parts = ax.inertia_parts()
    load_j = s.drive.load_inertia(s.segments)
    k = ax.carriage_per_motor()
    cycle_time = sum(g.time for g in s.segments)
    peak_speed = max(p.peak_speed for p in (g.profile for g in s.segments if g.kind == "move"))
    accel = getattr(prof, "peak_accel", 0.0) or prof.accel
    limited = _jerk_limited(move)
    motion = [
        Row("pulley_diameter", "pulley pitch diameter D", ax.pulley_diameter, "m", "mm",
            note="drive pulley, carriage side"),
        Row("gear_ratio", "gear ratio i", ax.gear_ratio, "1",
            note="motor speed / drive-pulley speed" + (f"; {s.drive.gearbox.name}" if s.drive.gearbox.name else "")),
        Row("motor_speed", "peak motor speed", peak_speed, "rad/s", "rpm",
            note="triangular: speed not reached" if single and prof.triangular else ""),
        Row("carriage_speed", "peak carriage speed", peak_speed * k, "m/s"),
        Row("motor_accel", "motor acceleration" + ("" if single else " (first move)"), accel, "rad/s^2",
            note=f"the jerk limits it: {format_number(prof.accel, 4)} rad/s^2 asked" if limited else ""),
        Row("carriage_accel", "carriage acceleration" + ("" if single else " (first move)"), accel * k, "m/s^2",
            note=f"the jerk limits it: {format_number(prof.accel * k, 4)} m/s^2 asked" if limited else ""),
    ]
    if math.isfinite(getattr(prof, "jerk", math.inf)):
        motion.append(Row("motor_jerk", "motor jerk limit" + ("" if single else " (first move)"), prof.jerk,
                          "rad/s^3", note="S-curve"))
    motion.append(Row("cycle_time", "cycle time", cycle_time, "s"))
    for n, m in enumerate(s.shaped, start=1):
        tag = "" if len(s.shaped) == 1 else f"_{n}"
        where = ("given" if m.position is None else
                 f"the belt's first mode with the carriage {m.position * 1e3:.5g} mm from the drive pulley "
                 "(both spans, the drive held)")
        motion += [Row(f"shaper_frequency{tag}", f"{m.shaper.name.upper()} input shaper of {m.name}, designed at",
                       m.shaper.frequency, "Hz", note=where + f"; damping ratio {m.shaper.zeta:.3g}"),
                   Row(f"shaper_time{tag}", "  time it adds to the move", m.added, "s",
                       note="the dwell after it shortened by as much, where it is as long")]
    mt = s.drive.mounting
    if mt.incline != 0:
        motion.append(Row("incline", "incline", mt.incline, "rad", "deg",
                          note="of the carriage's travel (+x) above horizontal"
                               + ("; brake holds in dwells" if mt.brake else "")))
    if mt.counterweight:
        motion.append(Row("counterweight", "counterweight", mt.counterweight, "kg", note="carriage side"))
    inertia = [Row("inertia_motor", f"motor rotor ({shown.motor.name if shown else 'none'})", motor_j,
                   "kg m^2", "kg*cm^2")]
    inertia += [Row("inertia_" + n.replace(" ", "_"), n, v, "kg m^2", "kg*cm^2") for n, v in parts.items()]
    inertia += [
        Row("reflected_inertia", "reflected inertia J_red", load_j + motor_j, "kg m^2", "kg*cm^2",
            note="at the motor shaft" + ("; largest payload" if not single else "")
                 + ("; counterweight" if mt.counterweight else "")),
        Row("inertia_ratio", "load / motor inertia", shown.inertia_ratio if shown else None, "1", digits=3,
            note="" if shown else render(NO_MOTOR_RATIO, name)),
    ]
    sections = [Section(("motion",), "motion", motion),
                Section(("inertia",), "reflected inertia, at the motor shaft", inertia)]
    if shown is None:
        return sections
    d = shown.duty
    torque = []
    if single:
        # each phase at its peak, signed (the largest |T| over the phase), then its start -> end
        torque += [Row(f"torque_{p.name}", f"{p.name} ({p.duration:.3g} s)", p.extreme, "N m", digits=3,
                       note=f"peak; {format_number(p.torque0, 3)} -> {format_number(p.torque1, 3)} N m")
                   for p in d.phases]
    t_a, e29, exact = first_move_energy(s)
    m = shown.motor
    torque += [
        Row("peak_torque", "peak torque", d.peak_torque, "N m", digits=3, note=f"T_max {m.T_max:g} N m"),
        Row("rms_torque", "RMS torque", d.rms_torque, "N m", digits=3,
            note=f"limit {format_number(shown.continuous_limit, 3)} N m: {percent(shown.utilisation)} of T_n"),
        Row("mean_speed", "mean speed", d.mean_speed, "rad/s", "rpm", note=f"rated {_rpm(m.n_rated)}"),
        Row("peak_power", "peak power", d.peak_power, "W", digits=3),
        Row("holding_torque", "holding torque at rest", d.holding_torque, "N m", digits=3),
        Row("braking_torque", "braking torque", d.braking_torque, "N m", digits=3,
            note="while braking (power flows back)" if d.braking_energy > 0 else "no braking"),
        Row("braking_energy", "braking energy per cycle", d.braking_energy, "J", digits=3),
        Row("motoring_energy", "motoring energy per cycle", d.energy_motoring, "J", digits=3),
        Row("accel_time", "acceleration time t_a", t_a, "s", digits=3, note="" if single else "first move"),
        Row("accel_energy", "energy E = T_max w_max t_a", e29, "J", digits=3, note="eq. 29"),
        Row("accel_energy_exact", "energy, integral T w dt", exact, "J", digits=3,
            note="acceleration phase, exact" if single else "first move's acceleration, exact"),
    ]
    sections.append(Section(("torque",), f"torque at the motor shaft ({m.name})", torque))
    z = shown.zone
    if z and z.segment >= 0:
        sections.append(Section(("zone",), "torque-speed zone", [
            Row("zone_margin", "smallest margin to the peak zone", z.margin, "N m", digits=3,
                note=f"{s.segments[z.segment].name}/{z.phase}, t = {z.time:.4g} s, {_rpm(z.speed)}: "
                     f"|T| {format_number(abs(z.torque), 3)} vs {format_number(z.limit, 3)} N m"
                     + (" (assumed zone)" if shown.zone_assumed else ""))]))
    regen = _regen_rows(s.regen)
    if regen:
        sections.append(Section(("regeneration",), "regeneration", regen))
    gear = [Row(c.name.replace(" ", "_"), c.name, c.value, c.unit if c.unit != "rad/s" else "rad/s",
                "rpm" if c.unit == "rad/s" else "", digits=4,
                note=f"limit {format_number(c.limit * (30 / math.pi if c.unit == 'rad/s' else 1), 4)}"
                     f"{' rpm' if c.unit == 'rad/s' else ' ' + c.unit}: {'ok' if c.ok else 'FAIL'}")
            for c in s.gearbox_checks]
    if gear:
        sections.append(Section(("gearbox",), "gearbox", gear))
    return sections


def _regen_rows(r) -> list[Row]:
    """The rows of :class:`beltcalc.design.regeneration.Regeneration` ``r``: the braking resistor's
    energy, rating and powers; what the DC-bus capacitors store when they are given; the
    largest resistance when the resistor takes energy (no rows when ``r`` is None)."""
    if r is None:
        return []
    rows = []
    if r.stored is not None:
        rows.append(Row("dc_bus_energy", "DC-bus capacitors store", r.stored, "J", digits=3, note="per event"))
    rows += [
        Row("resistor_energy", "braking resistor energy per cycle E_K", r.resistor_energy, "J", digits=3),
        Row("resistor_rating", "braking resistor, rated capacity W_K", r.resistor_rating, "W", digits=3,
            note="E_K / (0.2 T): Yaskawa's 20 % load ratio; the rating to buy"),
        Row("resistor_power", "braking resistor, average power", r.resistor_power, "W", digits=3,
            note="E_K / T over the cycle; not a rating"),
        Row("resistor_peak_power", "braking resistor, peak", r.resistor_peak_power, "W", digits=3),
    ]
    if r.resistance_max is not None:
        rows.append(Row("resistance_max", "resistance at most", r.resistance_max, "ohm", digits=3,
                        note="U_chopper^2 / P_peak"))
    return rows


def report_dict(s, sections: Sequence[Section], name: Callable[[str], str] = _same) -> dict:
    """The sized cycle ``s`` as one JSON-ready object: every row of ``sections`` as
    ``{key: {"value": SI, "unit": SI unit}}`` (a value that is not a finite number null with
    the reason; the torque rows null with the reason when no motor fits), the selected and
    the reported motor, every motor's checks, and of the reported motor the segments, the
    phases, the braking events and the zone; the gearbox, the assumptions, the notes and the
    jerk-limited moves."""
    obj = {r.key: quantity(r.value, r.unit) for sec in sections for r in sec.rows}
    for key, unit in (("peak_torque", "N*m"), ("rms_torque", "N*m"), ("accel_time", "s"), ("accel_energy", "J"),
                      ("accel_energy_exact", "J"), ("peak_power", "W")):
        obj.setdefault(key, {"value": None, "unit": unit, "reason": render(NO_PROFILE, name)})
    if s.shown is None:
        obj["inertia_ratio"] = {"value": None, "unit": "1", "reason": render(NO_MOTOR_RATIO, name)}
    obj["selected_motor"] = s.choice.selected.motor.name if s.choice.selected else None
    obj["reported_motor"] = s.shown.motor.name if s.shown else None
    obj["reason"] = s.choice.reason
    obj["triangular"] = s.first_move.profile.triangular
    obj["motors"] = [{
        "name": c.motor.name, "peak_torque": quantity(c.duty.peak_torque, "N*m"), "rms_torque": quantity(c.duty.rms_torque, "N*m"),
        "inertia_ratio": quantity(c.inertia_ratio, "1"), "utilisation": quantity(c.utilisation, "1"), "peak_ok": c.peak_ok,
        "rms_ok": c.rms_ok, "speed_ok": c.speed_ok, "inertia_ok": c.inertia_ok, "zone_ok": c.zone_ok,
        "zone_margin": quantity(c.zone.margin if c.zone else None, "N*m"), "zone_assumed": c.zone_assumed,
        "rms_limit": quantity(c.continuous_limit, "N*m"), "ok": c.ok,
    } for c in s.choice.checks]
    if s.shown is not None:
        d = s.shown.duty
        obj["segments"] = [{
            "name": g.name, "kind": g.kind, "start": quantity(g.start, "s"), "duration": quantity(g.duration, "s"),
            "peak_torque": quantity(g.peak_torque, "N m"), "rms_torque": quantity(g.rms_torque, "N m"),
            "peak_speed": quantity(g.peak_speed, "rad/s"), "energy_motoring": quantity(g.energy_motoring, "J"),
            "energy_braking": quantity(g.energy_braking, "J"),
        } for g in d.segments]
        obj["phases"] = [{
            "segment": p.segment_name, "phase": p.name, "start": quantity(p.start, "s"), "duration": quantity(p.duration, "s"),
            "speed0": quantity(p.speed0, "rad/s"), "speed1": quantity(p.speed1, "rad/s"), "torque0": quantity(p.torque0, "N m"),
            "torque1": quantity(p.torque1, "N m"), "peak_torque": quantity(p.peak, "N m"),
            "extreme_torque": quantity(p.extreme, "N m"), "rms_torque": quantity(p.rms, "N m"),
        } for p in d.phases]
        obj["braking_events"] = [{"start": quantity(e.start, "s"), "end": quantity(e.end, "s"), "energy": quantity(e.energy, "J"),
                                  "peak_power": quantity(e.peak_power, "W")} for e in d.events]
        z = s.shown.zone
        obj["zone"] = {
            "assumed": s.shown.zone_assumed, "source": getattr(s.shown.motor, "zone_source", ""),
            "points": [{"speed": quantity(w, "rad/s"), "torque": quantity(t, "N m")} for w, t in s.shown.zone_points],
            "margin": quantity(z.margin, "N m"), "time": quantity(z.time, "s"), "speed": quantity(z.speed, "rad/s"),
            "torque": quantity(z.torque, "N m"), "limit": quantity(z.limit, "N m"),
            "segment": s.segments[z.segment].name if z.segment >= 0 else None, "phase": z.phase or None,
        }
    obj["gearbox"] = {"name": s.drive.gearbox.name or None, "source": s.drive.gearbox.source or None,
                      "efficiency": quantity(s.drive.gearbox.efficiency, "1"),
                      "efficiency_back": quantity(s.drive.gearbox.eta_back, "1"),
                      "checks": [{"name": c.name, "value": quantity(c.value, c.unit),
                                  "limit": quantity(c.limit, c.unit), "ok": c.ok} for c in s.gearbox_checks]}
    obj["assumptions"] = [render(a, name) for a in s.assumptions]
    obj["notes"] = [render(n, name) for n in s.notes]
    obj["jerk_limited_moves"] = [{
        "segment": g.name, "accel_asked": quantity(g.profile.accel, "rad/s^2"),
        "accel_reached": quantity(g.profile.peak_accel, "rad/s^2"),
        "carriage_accel_asked": quantity(g.profile.accel * s.axis.carriage_per_motor(), "m/s^2"),
        "carriage_accel_reached": quantity(g.profile.peak_accel * s.axis.carriage_per_motor(), "m/s^2"),
    } for g in s.segments if _jerk_limited(g)]
    return obj


def inherited_rows(inherited, name: Callable[[str], str] = _same) -> list[Row]:
    """One row per value a run took from its scene (``inherited``: name -> resolved value,
    :func:`beltcalc.params.resolve`): its text as the scene gives it, labelled by ``name``,
    where it is measured (motor or carriage side) and the scene's reason, shortened to its
    source."""
    from beltcalc.design.axis_inputs import where

    rows = []
    for key, v in inherited.items():
        why = v.origin.removeprefix("scene: ")
        source = why.split(":")[0].split(",")[0].strip() if ":" in why else ""
        rows.append(Row(f"scene_{key}", name(key), v.text, "", note=f"{where(key, v.value)}"
                        + (f"; {source}" if source else "")))
    return rows


def scene_dict(scene_def, inherited, new_axis: bool) -> dict:
    """The scene of a run for its JSON: name, title, whether the run's axis is a new one
    (``new_axis``: a value given, or an incline or counterweight) and each value taken from
    the scene (``inherited``) with its text and where it is measured."""
    from beltcalc.design.axis_inputs import where

    return {"name": scene_def.name, "title": scene_def.title, "new_axis": new_axis,
            "inherited": {k: {"text": v.text, "where": where(k, v.value)} for k, v in inherited.items()}}


PROFILE_HEADER = ("t_s", "speed_rad_per_s", "accel_rad_per_s2", "torque_N_m", "power_W")


def profile_samples(s, per_phase: int = 21) -> list[tuple[float, float, float, float, float]]:
    """(t, omega, omegadot, torque, power) of the reported motor through the cycle, SI,
    ``per_phase`` points per phase, its ends as the right limit at the start and the left
    limit at the end (exact values).

    Raises :class:`~beltcalc.errors.InputError` when ``s`` has no motor to report."""
    from beltcalc.design.polynomials import poly_value
    from beltcalc.errors import InputError

    if s.shown is None:
        raise InputError(NO_PROFILE)
    d, out = s.shown.duty, []
    by_phase: dict[tuple[int, float], list] = {}
    for p in d.pieces:
        by_phase.setdefault(p.segment, []).append(p)
    for ph in d.phases:
        pieces = [p for p in by_phase[ph.segment] if ph.start - 1e-12 <= p.start < ph.start + ph.duration - 1e-15]
        for j in range(per_phase):
            t = ph.start + ph.duration * j / (per_phase - 1)
            piece = pieces[-1] if j == per_phase - 1 else next(
                (p for p in pieces if p.start <= t < p.start + p.duration), pieces[-1])
            tau = min(max(t - piece.start, 0.0), piece.duration)
            w = poly_value(piece.w, tau)
            wd = piece.w[1] + 2 * piece.w[2] * tau
            tq = poly_value(piece.torque, tau)
            out.append((t, w, wd, tq, tq * w))
    return out


def profile_csv(s) -> str:
    """:func:`profile_samples` as CSV text under :data:`PROFILE_HEADER`, every digit of each
    float; one that is not a finite number an empty field."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(PROFILE_HEADER)
    writer.writerows([repr(v) if math.isfinite(v) else "" for v in row] for row in profile_samples(s))
    return buf.getvalue()


def zone_plot_data(s) -> dict:
    """What the torque-speed panel draws, in rpm and N m: the cycle's points (|omega|, |T|)
    (21 per phase, both limits at the phase ends), the intermittent zone (the catalog's, or
    the assumed one), the continuous zone (the catalog's, else T_n flat to the rated speed:
    the RMS limit), the RMS torque at the mean speed and the point of the smallest margin."""
    c, m = s.shown, s.shown.motor
    rpm = 30 / math.pi
    samples = profile_samples(s)
    cont = tuple(getattr(m, "continuous", ()))
    z = c.zone
    return {
        "points": [(abs(w) * rpm, abs(tq)) for _, w, _, tq, _ in samples],
        "intermittent": [(w * rpm, tq) for w, tq in c.zone_points],
        "intermittent_assumed": c.zone_assumed,
        "continuous": [(w * rpm, tq) for w, tq in cont] if cont else [(0.0, m.T_n), (m.n_rated * rpm, m.T_n)],
        "continuous_from_catalog": bool(cont),
        "rms": (c.duty.mean_speed * rpm, c.duty.rms_torque),
        "worst": (z.speed * rpm, abs(z.torque)) if z is not None else None,
    }


# The columns of a sweep after the swept value: key, label, SI unit.
SWEEP_COLUMNS = (("motor_speed_rad_per_s", "peak motor speed", "rad/s"),
                 ("motor_accel_rad_per_s2", "motor acceleration", "rad/s^2"),
                 ("peak_torque_N_m", "peak torque", "N*m"), ("accel_time_s", "acceleration time t_a", "s"),
                 ("accel_energy_J", "energy E = T_max w_max t_a (eq. 29)", "J"),
                 ("accel_energy_exact_J", "energy, integral T w dt", "J"), ("rms_torque_N_m", "RMS torque", "N*m"),
                 ("triangular", "triangular profile", ""))


@dataclass(frozen=True)
class SweepTable:
    """A sweep of ``name`` in ``unit``: a row per point (the swept value, then the values of
    :data:`SWEEP_COLUMNS`), each point's rating checks against the motor (none for the load
    alone), the points with failing checks and one warning per failing check (over all
    points, the first five values named)."""

    name: str
    unit: str
    rows: list[tuple]
    point_checks: list[list[Check]]
    failed: list[tuple[float, list[Check]]]
    warnings: list[str]

    @property
    def key(self) -> str:
        """The swept value's column key: ``accel_rad_per_s2``."""
        return f"{self.name}_{self.unit.replace('/', '_per_').replace('^', '')}"

    @property
    def header(self) -> list[str]:
        return [self.key] + [k for k, _, _ in SWEEP_COLUMNS]


def sweep_table(name: str, unit: str, points, motor, peak_margin: float) -> SweepTable:
    """The :class:`SweepTable` of the points of :func:`beltcalc.design.sizing.sweep` of ``name`` in
    ``unit``, each point's duty checked against ``motor``'s ratings
    (:func:`beltcalc.design.motors.rating_checks`; ``motor`` None: no checks)."""
    from beltcalc.design.motors import rating_checks

    rows = [(r.value, r.profile.peak_speed, r.profile.accel, r.peak_torque, r.accel_time, r.accel_energy,
             r.accel_energy_exact, r.rms_torque, r.profile.triangular) for r in points]
    point_checks = [rating_checks(motor, r.peak_torque, r.rms_torque, r.profile.peak_speed, peak_margin)
                    if motor else [] for r in points]
    failed = [(r.value, failures(cs)) for r, cs in zip(points, point_checks) if failures(cs)]
    warnings = []
    for k in dict.fromkeys(c.key for _, cs in failed for c in cs):
        at = [(v, c) for v, cs in failed for c in cs if c.key == k]
        where = ", ".join(f"{v:.6g}" for v, _ in at[:5]) + (", ..." if len(at) > 5 else "")
        warnings.append(f"{at[0][1].warning()} (at {len(at)} of {len(points)} points: {name} = {where} {unit})")
    return SweepTable(name, unit, rows, point_checks, failed, warnings)
