"""``beltcalc motor-size``: reflected inertia, torque, energy and motor choice of a belt axis.

References (in the options' help):

[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

import math

import click

from beltcalc.cli.options import OutputPath, catalog_option, output_options, quantity_option, scene_options
from beltcalc.cli.contract import checks_json, echo_inputs, entry, fmt, options_text, out_of_range, shown
from beltcalc.cli.output import (console, dumps, emit_warnings, print_table, progress,
                                 require_matplotlib, strict_option, table_csv, write_atomic, write_figure, wrote)
from beltcalc.cli.main import option_name
from beltcalc.design.checks import percent
from beltcalc.design.motor_report import (SWEEP_COLUMNS, inherited_rows, profile_csv, report_dict, report_sections,
                                          scene_dict, sweep_table)
from beltcalc.errors import InputError, UnknownNameError, did_you_mean
from beltcalc.report import Row, Section
from beltcalc.design.axis_inputs import PARAMS


def _sweep_spec(text: str | None):
    """``accel=100rad/s^2:1000rad/s^2:10`` -> (name, [values], unit)."""
    if text is None:
        return None
    from beltcalc.params import linspace
    from beltcalc.design.sizing import SWEEPABLE
    from beltcalc.units import QuantityError, parse_quantity_any

    units = {"accel": ("rad/s^2", "m/s^2"), "speed": ("rad/s", "m/s")}
    name, _, rng = text.partition("=")
    parts = rng.split(":")
    if name not in SWEEPABLE:
        raise click.BadParameter(f"{text!r}: {name!r} cannot be swept here; {did_you_mean(name, SWEEPABLE)} "
                                 "(e.g. accel=100rad/s^2:1000rad/s^2:10)", param_hint="--sweep")
    if len(parts) != 3:
        raise click.BadParameter(f"{text!r}: use NAME=START:STOP:N with NAME one of "
                                 f"{', '.join(SWEEPABLE)}, e.g. accel=100rad/s^2:1000rad/s^2:10",
                                 param_hint="--sweep")
    try:
        (start, u1), (stop, u2) = (parse_quantity_any(p, units[name]) for p in parts[:2])
        n = int(parts[2])
    except (QuantityError, ValueError) as exc:
        raise click.BadParameter(f"{text!r}: {exc}", param_hint="--sweep") from None
    if u1 != u2:
        raise click.BadParameter(f"{text!r}: START and STOP must both be at the motor or both at the carriage",
                                 param_hint="--sweep")
    if n < 1 or n > 100000:
        raise click.BadParameter(f"{text!r}: N must be 1..100000", param_hint="--sweep")
    return name, linspace(start, stop, n), u1


@click.command("motor-size", context_settings={"help_option_names": ["-h", "--help"]})
@click.option("--scene", default="wdu", show_default=True,
              help="Built-in scene (wdu, pdd) or a scene .toml file; every option below overrides it, and "
                   "the table lists what the axis takes from it. 'none': no scene, every value an option.")
@scene_options(PARAMS)
@click.option("--substitute-mass-model", type=click.Choice(["eq7", "rayleigh"]), default="eq7", show_default=True,
              help="m_TB by [W21 eq. 7], or the Rayleigh m_belt/3.")
@quantity_option("--jerk", si_unit="rad/s^3|m/s^3",
                 help="Jerk limit: the move becomes a 7-phase S-curve (at the motor 1e5rad/s^3 or the carriage 200m/s^3).")
@quantity_option("--move-time", si_unit="s",
                 help="Give the move by its time instead of --speed/--accel (see --accel-fraction, --jerk-fraction).")
@quantity_option("--accel-fraction", si_unit="", default="0.333333333333333",
                 help="With --move-time: acceleration time / move time (at most 0.5).")
@quantity_option("--jerk-fraction", si_unit="", default="0",
                 help="With --move-time: jerk time / acceleration time (0: trapezoid, at most 0.5).")
@click.option("--cycle", "cycle_path", type=click.Path(exists=True, dir_okay=False, readable=True), default=None,
              help="A duty-cycle file (TOML): moves and dwells with payload, force, direction (catalogs/cycles/).")
@click.option("--segment", "segment_texts", multiple=True, metavar="'KIND: KEY=VALUE, ...'",
              help="The cycle as repeated options instead of --cycle, in order, with the cycle file's keys: "
                   "'move: distance=400mm, direction=-, payload=10kg' or 'dwell: time=0.3s, force=-50N'; "
                   "moves without speed/accel/jerk take --speed/--accel/--jerk.")
@quantity_option("--incline", si_unit="rad", default="0deg",
                 help="Angle of the axis above the horizontal (90deg: vertical, + is up).")
@quantity_option("--counterweight", si_unit="kg", default="0kg", help="Counterweight balancing the carriage.")
@click.option("--brake", is_flag=True, help="A holding brake holds the axis in every dwell (no motor torque there).")
@quantity_option("--gear-efficiency", si_unit="", default=None,
                 help="Gearbox efficiency when the motor drives [default: 1, or the --gearbox's].")
@quantity_option("--gear-efficiency-back", si_unit="", default=None,
                 help="Gearbox efficiency when the load drives the motor [default: as driving].")
@click.option("--gearbox", "gearbox_name", default=None,
              help="A gearbox from a gearbox catalog: its ratio and inertia replace --gear-ratio/--gearbox-inertia.")
@click.option("--gearbox-catalog", "gearbox_files", multiple=True,
              type=click.Path(exists=True, dir_okay=False, readable=True),
              help="A gearbox catalog file (TOML, [[gearboxes]]); repeatable.")
@quantity_option("--dc-bus-capacitance", si_unit="F", help="Drive's DC-bus capacitance (with the two voltages).")
@quantity_option("--dc-bus-voltage", si_unit="V", help="DC-bus voltage at rest (about 1.41 x mains).")
@quantity_option("--chopper-voltage", si_unit="V", help="DC-bus voltage at which the braking resistor switches in.")
@quantity_option("--regen-efficiency", si_unit="", default="1",
                 help="Share of the braking energy that reaches the DC bus (1: all of it, the safe side).")
@quantity_option("--zone-end", si_unit="", default=None,
                 help="Assumed intermittent zone at n_max as a fraction of T_max [default: down to T_n].")
@click.option("--shaper", type=click.Choice(["zv", "zvd", "ei"]), default=None,
              help="Shape each move with an input shaper for the belt's first mode where the move stops (the "
                   "carriage between its two spans, k = C_spec (1/L1 + 1/L2), the drive held; the stroke centred "
                   "on the axis), or at --shaper-frequency.")
@quantity_option("--shaper-frequency", si_unit="Hz", default=None,
                 help="With --shaper: the design frequency instead of the predicted mode's.")
@quantity_option("--shaper-zeta", si_unit="", default="0",
                 help="With --shaper: the mode's damping ratio it is designed for.")
@click.option("--shaper-at", type=click.Choice(["both", "end"]), default="both", show_default=True,
              help="With --shaper: shape each move for the modes where it starts and stops (two shapers "
                   "convolved: the start's ringing survives a lightly damped move) or where it stops only.")
@quantity_option("--settle-band", si_unit="m", default=None,
                 help="Simulate the move out and back (the belt's spans following the carriage, an ideal servo) "
                      "and check that the carriage settles into this band (e.g. 0.05mm) within each dwell.")
@click.option("--motor", "motor_name", default=None, help="Report this motor (the choice is still made over all).")
@click.option("--motors", "motor_files", default=None,
              help="Choose only among the motors of this catalog file (e.g. yaskawa).")
@click.option("--sweep", "sweep_text", default=None, metavar="NAME=START:STOP:N",
              help="Sweep accel or speed, e.g. accel=100rad/s^2:1000rad/s^2:10 ([W21 Fig. 13-15]).")
@click.option("--plot", "plot_path", type=OutputPath(), default=None,
              help="Write a plot (PNG, PDF or SVG, as the suffix names): torque and speed over the cycle and the cycle's points over the motor's "
                   "torque-speed zones, or the sweep's curves (needs matplotlib).")
@catalog_option
@output_options
@strict_option
@click.pass_context
def motor_size(ctx, scene, substitute_mass_model, jerk, move_time, accel_fraction, jerk_fraction, cycle_path,
               segment_texts, incline,
               counterweight, brake, gear_efficiency, gear_efficiency_back, gearbox_name, gearbox_files,
               dc_bus_capacitance, dc_bus_voltage, chopper_voltage, regen_efficiency, zone_end, shaper,
               shaper_frequency, shaper_zeta, shaper_at, settle_band, motor_name,
               motor_files, sweep_text, plot_path, catalog_paths, as_json, csv_path, strict, **given):
    """Motor torque, energy and motor choice for a timing-belt linear axis.

    With no options: the work-drive-unit axis of Wojtkowiak et al., Energies 14 (2021) 317
    (scene `wdu`; `--scene pdd` is the punching-die axis with F_R = 50 N). The scene
    states every value it assumes; `--json` lists them with their reasons.

    Duty cycles: an S-curve (--jerk), a move by time (--move-time), several moves and
    dwells (--cycle FILE, or --segment repeated), inclined and vertical axes (--incline, --counterweight, --brake),
    the gearbox's efficiency and ratings, the motor's torque-speed zone, and the braking
    resistor (--dc-bus-capacitance with the two voltages).
    """
    from beltcalc.data.catalogs import load_catalog
    from beltcalc.params import resolve
    from beltcalc.data.scenefile import load_scene
    from beltcalc.design.sizing import DutyOptions, size_axis, size_cycle, sweep
    from beltcalc.design.axis_inputs import SizingInputs

    spec = _sweep_spec(sweep_text)
    if segment_texts and cycle_path is not None:
        raise click.BadParameter("give the cycle either as a file (--cycle) or as --segment options, not both",
                                 param_hint="--segment")
    cycle_option = "--cycle" if cycle_path is not None else ("--segment" if segment_texts else None)
    _check_combinations(given, jerk, move_time, cycle_option, spec, incline, counterweight, brake, gear_efficiency,
                        gear_efficiency_back, gearbox_name, (dc_bus_capacitance, dc_bus_voltage, chopper_voltage))
    if plot_path is not None:
        require_matplotlib()
    DutyOptions(accel_fraction=accel_fraction, jerk_fraction=jerk_fraction)   # their ranges, also in a sweep
    cat = load_catalog(catalog_paths)
    replaced = _replaced(cycle_option is not None, move_time is not None, gearbox_name is not None)
    scene_def = _no_scene(given, replaced) if scene == "none" else load_scene(scene, command="motor-size")
    values = resolve(scene_def, PARAMS, given)
    belt = cat.belt(values["belt"].value)
    motors = _motor_list(cat, motor_files)
    chosen = cat.motor(motor_name) if motor_name else None
    inp = SizingInputs.from_values({k: v.value for k, v in values.items()}, substitute_mass_model)

    if spec is not None:
        with out_of_range(ctx):
            sizing = size_axis(inp, belt, motors, chosen)
        name, points, unit = spec
        motor = sizing.shown.motor if sizing.shown else None
        with progress(len(points), f"sweep {name}", enabled=not as_json and len(points) >= 20) as advance:
            with out_of_range(ctx):
                rows = sweep(inp, belt, motor, name, points, unit, advance)
        _render_sweep(name, unit, rows, motor, inp.peak_margin, as_json, csv_path, plot_path, strict)
        return

    cycle = None
    if cycle_path is not None:
        from beltcalc.data.cyclefile import load_cycle

        cycle = load_cycle(cycle_path)
    elif segment_texts:
        from beltcalc.data.cyclefile import CycleFile, parse_segments

        cycle = CycleFile(title=f"{len(segment_texts)} segments (--segment)", path="",
                          segments=parse_segments(segment_texts))
    gb = None
    if gearbox_name is not None:
        from beltcalc.design.gearboxes import gearbox

        gb = gearbox(gearbox_name, gearbox_files)
    opts = DutyOptions(
        jerk=jerk, move_time=move_time, accel_fraction=accel_fraction, jerk_fraction=jerk_fraction,
        cycle=cycle.segments if cycle else None, cycle_title=cycle.title if cycle else "",
        incline=incline, counterweight=counterweight, brake=brake,
        gear_efficiency=1.0 if gear_efficiency is None else gear_efficiency,
        gear_efficiency_back=gear_efficiency_back, gearbox=gb, dc_bus_capacitance=dc_bus_capacitance,
        dc_bus_voltage=dc_bus_voltage, chopper_voltage=chopper_voltage, regen_efficiency=regen_efficiency,
        zone_end=zone_end, shaper=shaper, shaper_frequency=shaper_frequency,
        shaper_zeta=0.0 if shaper_zeta is None else shaper_zeta, shaper_at=shaper_at)
    try:
        with out_of_range(ctx):
            sizing = size_cycle(inp, belt, motors, chosen, opts)
    except InputError as exc:
        if segment_texts and exc.param == "cycle":     # the cycle came from --segment options
            exc.param = "segment"
        raise

    sections = report_sections(sizing, option_name)
    if settle_band is not None and sizing.shown is not None:
        sizing, settled = _settling(sizing, inp, belt, opts, settle_band, catalog_paths, as_json)
        sections.append(settled)
    warnings = options_text(sizing.warnings)
    fits = sizing.choice.selected is not None
    emit_warnings(warnings, sizing.checks, strict and fits)   # with --strict, a failing check ends here
    if fits:                      # files only for a result that is good: no file when no motor fits
        if csv_path is not None:
            write_atomic(csv_path, profile_csv(sizing))
            wrote(csv_path)
        if plot_path is not None:
            from beltcalc.plots import profile_figure

            write_figure(profile_figure(sizing), plot_path, dpi=120)
            wrote(plot_path)
    inherited = {k: v for k, v in values.items() if not v.given and k not in replaced}
    new_axis = any(v.given for v in values.values()) or incline != 0 or counterweight != 0
    if as_json:
        obj = report_dict(sizing, sections, option_name)
        obj.update(scene=scene_dict(scene_def, inherited, new_axis), inputs=_inputs(ctx, values),
                   checks=checks_json(sizing.checks), warnings=warnings)
        click.echo(dumps(obj))
    else:
        title = scene_def.title
        if new_axis and scene_def.name != "none":
            title = f"your axis on the scene {scene_def.name}"
        if new_axis and inherited:
            sections.append(Section(("scene",), f"from the scene {scene_def.name} (not given; override with "
                                    "the option)", inherited_rows(inherited, option_name)))
        _print(sizing, sections, values, title + (f"; cycle: {cycle.title}" if cycle else ""))
    if not fits:
        raise InputError(f"no motor fits: {sizing.choice.reason} (see the table); lower --accel or --speed, "
                         "change --gear-ratio, or add motors with --catalog", param=None)


def _settling(sizing, inp, belt, opts, band: float, catalog_paths, as_json: bool):
    """The sizing with the settling checks of its move out and back added, and their section
    (:func:`beltcalc.sim.scenes.linear_axis.settle_cycle`)."""
    from dataclasses import replace

    from beltcalc.sim.scenes.axis_settle import settle_cycle
    from beltcalc.sim.scenes.axis_stops import stop_rows

    if band <= 0:
        raise click.BadParameter(f"{band * 1e3:g} mm is not allowed; the band must be > 0", param_hint="--settle-band")
    with progress(1, "settling: simulating the move out and back", enabled=not as_json) as advance:
        stops, checks, run = settle_cycle(inp, belt, sizing.shown.motor, opts, band, catalog_paths)
        advance()
    rows = stop_rows(stops, band)
    rows.append(Row("settle_error_estimate", "error estimate of the run (worst speed)", run.error_estimate,
                    run.error_unit, note=f"{run.method}; vs {run.error_reference}"))
    section = Section(("settling",), "settling (dynamic: the belt's spans following the carriage, an ideal servo)",
                      rows)
    return replace(sizing, checks=sizing.checks + tuple(checks)), section


def _inputs(ctx, values) -> dict:
    """The scene's values (origin ``scene: <why>`` or ``option``) and the command's own options."""
    by_name = {p.name: p for p in PARAMS}
    out = {}
    for k, v in values.items():
        value, unit = v.value, by_name[k].unit
        if isinstance(value, tuple):
            value, unit = value
        else:
            unit = "" if unit is None else ("1" if unit in ("int", "") else unit)
        out[k] = entry(v.text, value, unit, "option" if v.given else v.origin)
    out.update(echo_inputs(ctx, skip=set(by_name)))
    return out


def _no_scene(given, replaced):
    """``--scene none``: a scene without values; every value the run uses must be an option,
    all the missing ones named in one message (those a cycle, a move time or a catalog
    gearbox replaces stand in as unused)."""
    from beltcalc.data.catalogs import Source
    from beltcalc.data.scenefile import SceneFile

    missing = [option_name(p.name) for p in PARAMS
               if p.required and given.get(p.name) is None and p.name not in replaced]
    if missing:
        raise click.BadParameter(f"'none' takes every value from the options; give also {', '.join(missing)} "
                                 f"({len(missing)} missing), or start from a scene file of your own "
                                 "(catalogs/scenes/wdu.toml is one)", param_hint="--scene")
    unused = {k: (_UNUSED[k], "not used: replaced by the cycle, the move time or the gearbox") for k in replaced}
    return SceneFile(name="none", title="your axis (no scene)", command="motor-size",
                 source=Source("the command line"), values=unused)


# values a cycle, a move time or a catalog gearbox replaces (not taken from a scene then), and
# what stands in for them without a scene
_REPLACED = {"cycle": ("stroke", "dwell"), "move_time": ("speed", "accel"),
             "gearbox": ("gear_ratio", "gearbox_inertia")}
_UNUSED = {"stroke": "1 m", "dwell": "0 s", "speed": "1 m/s", "accel": "1 m/s^2", "gear_ratio": "1",
           "gearbox_inertia": "0 kg*m^2"}


def _replaced(cycle: bool, move_time: bool, gearbox: bool) -> set[str]:
    """The names of :data:`PARAMS` the run does not use."""
    out = set()
    for flag, on in (("cycle", cycle), ("move_time", move_time), ("gearbox", gearbox)):
        if on:
            out.update(_REPLACED[flag])
    return out


def _check_combinations(given, jerk, move_time, cycle_option, sweep, incline, counterweight, brake, eff, eff_back,
                        gearbox_name, bus) -> None:
    """Option combinations that make no sense are usage errors (exit 2)."""
    def bad(option, why):
        raise click.BadParameter(why, param_hint=option)

    if move_time is not None:
        for name in ("speed", "accel"):
            if given.get(name) is not None:
                bad(f"--{name}", f"--move-time gives the move by its time; leave out --{name}")
        if jerk is not None:
            bad("--jerk", "--move-time gives the move by its time; use --jerk-fraction instead of --jerk")
    if cycle_option is not None:
        for name in ("stroke", "dwell"):
            if given.get(name) is not None:
                bad(f"--{name}", f"{cycle_option} gives every move and dwell; leave out --{name}")
        if move_time is not None:
            bad("--move-time", f"{cycle_option} gives every move; give time = ... per move in the cycle")
    if sweep is not None:
        extra = [n for n, v in (("--jerk", jerk), ("--move-time", move_time), (cycle_option, cycle_option),
                                ("--gearbox", gearbox_name), ("--gear-efficiency", eff),
                                ("--gear-efficiency-back", eff_back), ("--dc-bus-capacitance", bus[0]))
                 if v is not None] + (["--brake"] if brake else []) + (["--incline"] if incline else []) \
            + (["--counterweight"] if counterweight else [])
        if extra:
            bad("--sweep", f"sweeps are of the single horizontal trapezoid; leave out {extra[0]}")
    names = ("--dc-bus-capacitance", "--dc-bus-voltage", "--chopper-voltage")
    if any(v is not None for v in bus) and not all(v is not None for v in bus):
        missing = [n for n, v in zip(names, bus) if v is None]
        bad(missing[0], f"the DC bus needs all three of {', '.join(names)}")


# --- helpers ---------------------------------------------------------------------------------

def _motor_list(cat, files: str | None):
    from pathlib import Path

    from beltcalc.units import quote

    motors = list(cat.motors.values())
    if files is None:
        return motors
    stems = sorted({Path(m.source.path).stem for m in motors})
    picked = [m for m in motors if Path(m.source.path).stem.lower() == files.lower()]
    if not picked:
        raise UnknownNameError(f"unknown motor catalog {quote(files)}; {did_you_mean(files, stems)}",
                               param="motors")
    return picked


def _print(s, sections, values, title) -> None:
    from rich.table import Table

    print_table(f"Motor sizing: {title}", [(sec.title, shown(sec.rows)) for sec in sections])
    out = console(140)
    if s.shown is not None and (len(s.segments) > 2 or any(g.kind == "move" and g.profile.phases[0].jerk
                                                              for g in s.segments) or len(s.segments) == 1):
        seg = Table(title=f"segments ({s.shown.motor.name})", title_justify="left")
        for col in ("segment", "kind", "t s", "peak N m", "RMS N m", "peak rpm", "E in J", "E back J"):
            seg.add_column(col, justify="left" if col in ("segment", "kind") else "right")
        for g in s.shown.duty.segments:
            seg.add_row(g.name, g.kind, fmt(g.duration, 4), fmt(g.peak_torque, 3),
                        fmt(g.rms_torque, 3), fmt(g.peak_speed * 30 / math.pi, 4),
                        fmt(g.energy_motoring, 3), fmt(g.energy_braking, 3))
        out.print(seg)
    if s.shown is not None:
        ph = Table(title="time at each torque (phases; torque at the start -> end)", title_justify="left")
        for col in ("segment", "phase", "t s", "T start N m", "T end N m", "|T| max N m", "RMS N m"):
            ph.add_column(col, justify="left" if col in ("segment", "phase") else "right")
        for p in s.shown.duty.phases:
            ph.add_row(p.segment_name, p.name, fmt(p.duration, 4), fmt(p.torque0, 4),
                       fmt(p.torque1, 4), fmt(p.peak, 4), fmt(p.rms, 4))
        out.print(ph)
    table = Table(title="motor choice (smallest rated torque first)", title_justify="left")
    for col in ("motor", "T_n N m", "T_max N m", "J kg cm^2", "peak", "RMS", "speed", "zone", "J ratio",
                "RMS/T_n", ""):
        table.add_column(col, justify="right" if "N m" in col or "J" in col else "left")
    for c in s.choice.checks:
        mark = lambda ok: "ok" if ok else "[red]FAIL[/red]"
        pick = "[bold green]<- selected[/bold green]" if c is s.choice.selected else ""
        table.add_row(c.motor.name, f"{c.motor.T_n:g}", f"{c.motor.T_max:g}", f"{c.motor.J * 1e4:g}",
                      mark(c.peak_ok), mark(c.rms_ok), mark(c.speed_ok), mark(c.zone_ok),
                      f"{c.inertia_ratio:.3g} " + ("" if c.inertia_ok else "[red]FAIL[/red]"),
                      percent(c.utilisation), pick)
    out.print(table)
    picked = s.choice.selected.motor.name if s.choice.selected else "none"
    out.print(f"recommended: {picked}: {s.choice.reason}", highlight=False, markup=False)
    if len(s.segments) <= 2 and s.first_move.profile.triangular:
        out.print("the stroke is too short to reach the speed: triangular profile", markup=False)
    for a in s.assumptions:
        out.print(f"assumed: {a}", markup=False, highlight=False)
    for n in options_text(s.notes):
        out.print(f"note: {n}", markup=False, highlight=False)
    given = [f"{k}={v.text}" for k, v in values.items() if v.given]
    out.print("inputs: scene values (--json lists each with its reason)"
              + (f"; given: {', '.join(given)}" if given else ""), markup=False, highlight=False)


_SWEEP_DISPLAY = {"rad/s^2": "rad/s^2", "m/s^2": "m/s^2", "rad/s": "rpm", "m/s": "m/s"}


def _render_sweep(name, unit, points, motor, peak_margin, as_json, csv_path, plot_path, strict) -> None:
    """The sweep in the one sweep schema of every command (parameters, columns, rows,
    failed_checks, warnings); each point's duty checked against the motor's ratings
    (:func:`beltcalc.design.motor_report.sweep_table`)."""
    from beltcalc.design.checks import failures

    st = sweep_table(name, unit, points, motor, peak_margin)
    table, point_checks = st.rows, st.point_checks
    warnings = options_text(st.warnings)
    emit_warnings(warnings, [c for cs in point_checks for c in cs], strict)
    if csv_path is not None:
        write_atomic(csv_path, table_csv(st.header, ([repr(x) for x in r] for r in table)))
        wrote(csv_path)
    if plot_path is not None:
        from beltcalc.plots import motor_sweep_figure

        write_figure(motor_sweep_figure(name, unit, table, motor), plot_path, dpi=120)
        wrote(plot_path)
    label = motor.name if motor else "load only (no motor fits)"
    if as_json:
        click.echo(dumps({
            "command": "motor-size", "study": "sweep", "motor": motor.name if motor else None,
            "parameters": [{"name": name, "unit": unit, "values": [r[0] for r in table]}],
            "columns": [{"key": st.key, "label": name, "unit": unit}]
                       + [{"key": k, "label": lab, "unit": u} for k, lab, u in SWEEP_COLUMNS],
            "rows": table,
            "failed_checks": [{"point": {"value": v, "unit": unit}, "checks": checks_json(cs)}
                              for v, cs in st.failed],
            "warnings": warnings}))
        return
    from beltcalc.units import convert
    from rich.table import Table

    shown = _SWEEP_DISPLAY[unit]
    t = Table(title=f"sweep of {name} ({label}): the paper's Fig. 13-15", title_justify="left")
    for col in (f"{name} [{shown}]", "motor rpm", "peak torque N m", "t_a s", "E eq.29 J", "E exact J", "RMS N m",
                "profile", "checks"):
        t.add_column(col.replace("[", "\\["), justify="right")
    for r, cs in zip(table, point_checks):
        bad = failures(cs)
        t.add_row(fmt(convert(r[0], unit, shown)), fmt(r[1] * 30 / math.pi),
                  *(fmt(x, 4) for x in r[3:8]), "triangular" if r[8] else "trapezoid",
                  "FAIL: " + ", ".join(c.key.removeprefix("motor_") for c in bad) if bad else ("pass" if cs else "-"),
                  style="bold red" if bad else None)
    console().print(t)
