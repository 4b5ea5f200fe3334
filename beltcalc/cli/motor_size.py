"""``beltcalc motor-size``: reflected inertia, torque, energy and motor choice of a belt axis."""

from __future__ import annotations

import json
import math

import click

from beltcalc.cli.options import (OutputPath, SceneParam, catalog_option, output_options, resolve_scene,
                                  scene_options)
from beltcalc.cli.output import (Row, console, format_number, print_table, progress, require_matplotlib,
                                 table_csv, write_atomic)
from beltcalc.errors import InputError, UnknownNameError

PARAMS = [
    SceneParam("belt", None, "Belt profile (gives the substitute belt mass m_TB)."),
    SceneParam("width", "m", "Belt width (a catalog width)."),
    SceneParam("center_distance", "m", "Pulley center distance."),
    SceneParam("mass", "kg", "Moving mass (carriage)."),
    SceneParam("pulley_teeth", "int", "Teeth of the drive and idler pulleys (d0 = z P / pi)."),
    SceneParam("pulley_diameter", "m", "Pulley pitch diameter D, instead of the teeth.", required=False),
    SceneParam("pulley_width", "m", "Pulley body width (for its inertia)."),
    SceneParam("pulley_bore", "m", "Pulley bore (for its inertia)."),
    SceneParam("pulley_density", "kg/m^3", "Pulley material density (for its inertia)."),
    SceneParam("pulley_inertia", "kg*m^2", "Drive pulley inertia J_P1, instead of the computed one.", required=False),
    SceneParam("idler_inertia", "kg*m^2", "Idler pulley inertia J_P2, instead of the computed one.", required=False),
    SceneParam("coupling_inertia", "kg*m^2", "Coupling inertia J_C (drive-pulley shaft)."),
    SceneParam("gearbox_inertia", "kg*m^2", "Gearbox inertia at the motor shaft J_G."),
    SceneParam("load_inertia", "kg*m^2", "Rotating load on the idler shaft J_RL.", required=False),
    SceneParam("gear_ratio", "", "Gearbox ratio i = motor speed / pulley speed (1: direct drive)."),
    SceneParam("belt_ratio", "", "Belt transmission ratio n = D2 / D1."),
    SceneParam("resistance", "N", "External resistance force F_R against the motion."),
    SceneParam("guide_friction", "", "Guide friction coefficient (ball 0.002-0.003, roller 0.001-0.002)."),
    SceneParam("guide_damping", "N*s/m", "Guide viscous damping b_LG."),
    SceneParam("bearing_damping", "N*m*s/rad", "Viscous damping b_B of each pulley shaft."),
    SceneParam("motor_efficiency", "", "Motor efficiency (gives b_M = (1 - eta) T_n / omega_n)."),
    SceneParam("speed", "rad/s|m/s", "Maximum speed: at the motor (3000rpm) or the carriage (2m/s)."),
    SceneParam("accel", "rad/s^2|m/s^2", "Acceleration: at the motor (500rad/s^2) or the carriage (10m/s^2)."),
    SceneParam("stroke", "m", "Carriage travel of one move."),
    SceneParam("dwell", "s", "Standstill after each move."),
    SceneParam("inertia_ratio_limit", "", "Largest load/motor inertia ratio allowed."),
    SceneParam("peak_margin", "", "Margin on the peak torque: peak * (1 + margin) <= T_max."),
]


def _sweep_spec(text: str | None):
    """``accel=100rad/s^2:1000rad/s^2:10`` -> (name, [values], unit)."""
    if text is None:
        return None
    from beltcalc.sizing import SWEEPABLE, linspace
    from beltcalc.units import QuantityError, parse_quantity_any

    units = {"accel": ("rad/s^2", "m/s^2"), "speed": ("rad/s", "m/s")}
    name, _, rng = text.partition("=")
    parts = rng.split(":")
    if name not in SWEEPABLE or len(parts) != 3:
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
              help="Built-in scene (wdu, pdd) or a scene .toml file; every option below overrides it.")
@scene_options(PARAMS)
@click.option("--substitute-mass-model", type=click.Choice(["eq7", "rayleigh"]), default="eq7", show_default=True,
              help="m_TB by the paper's eq. 7, or the Rayleigh m_belt/3.")
@click.option("--motor", "motor_name", default=None, help="Report this motor (the choice is still made over all).")
@click.option("--motors", "motor_files", default=None,
              help="Choose only among the motors of this catalog file (e.g. yaskawa).")
@click.option("--sweep", "sweep_text", default=None, metavar="NAME=START:STOP:N",
              help="Sweep accel or speed, e.g. accel=100rad/s^2:1000rad/s^2:10 (the paper's Fig. 13-15).")
@click.option("--plot", "plot_path", type=OutputPath(), default=None,
              help="Write a PNG: torque and speed over the cycle, or the sweep's curves (needs matplotlib).")
@catalog_option
@output_options
def motor_size(scene, substitute_mass_model, motor_name, motor_files, sweep_text, plot_path,
               catalog_paths, as_json, csv_path, **given):
    """Motor torque, energy and motor choice for a timing-belt linear axis.

    With no options: the work-drive-unit axis of Wojtkowiak et al., Energies 14 (2021) 317
    (scene `wdu`; `--scene pdd` is the punching-die axis with F_R = 50 N). The scene
    states every value it assumes; `--json` lists them with their reasons.
    """
    from beltcalc.catalogs import load_catalog, load_scene
    from beltcalc.sizing import SizingInputs, size_axis, sweep

    spec = _sweep_spec(sweep_text)
    if plot_path is not None:
        require_matplotlib()
    cat = load_catalog(catalog_paths)
    scene_def = load_scene(scene, command="motor-size")
    values = resolve_scene(scene_def, PARAMS, given)
    belt = cat.belt(values["belt"].value)
    motors = _motor_list(cat, motor_files)
    chosen = cat.motor(motor_name) if motor_name else None
    fields = {k: v.value for k, v in values.items() if k != "belt"}
    speed, speed_unit = fields.pop("speed")
    accel, accel_unit = fields.pop("accel")
    inp = SizingInputs(**fields, speed=speed, speed_unit=speed_unit, accel=accel, accel_unit=accel_unit,
                       substitute_mass_model=substitute_mass_model)
    sizing = size_axis(inp, belt, motors, chosen)

    if spec is not None:
        name, points, unit = spec
        motor = sizing.shown.motor if sizing.shown else None
        with progress(len(points), f"sweep {name}", enabled=not as_json and len(points) >= 20) as advance:
            rows = sweep(inp, belt, motor, name, points, unit, advance)
        _render_sweep(name, unit, rows, motor, as_json, csv_path, plot_path)
        return

    sections, rows = _sections(sizing)
    if csv_path is not None:
        write_atomic(csv_path, _profile_csv(sizing))
    if plot_path is not None:
        _plot_profile(sizing, plot_path)
    if as_json:
        click.echo(_json(sizing, rows, values))
    else:
        _print(sizing, sections, values, scene_def.title)
    if sizing.choice.selected is None:
        raise InputError(f"no motor fits: {sizing.choice.reason} (see the table); lower --accel or --speed, "
                         "change --gear-ratio, or add motors with --catalog", param=None)


# --- helpers ---------------------------------------------------------------------------------

def _motor_list(cat, files: str | None):
    from pathlib import Path

    motors = list(cat.motors.values())
    if files is None:
        return motors
    stems = sorted({Path(m.source.path).stem for m in motors})
    picked = [m for m in motors if Path(m.source.path).stem.lower() == files.lower()]
    if not picked:
        raise UnknownNameError(f"unknown motor catalog {files!r}; the motor catalogs are {', '.join(stems)}",
                               param="motors")
    return picked


def _sections(s) -> tuple[list, list[Row]]:
    ax, prof, shown = s.axis, s.profile, s.shown
    motor_j = shown.motor.J if shown else 0.0
    parts = ax.inertia_parts()
    total = ax.load_inertia_total + motor_j
    k = ax.carriage_per_motor()
    motion = [
        Row("pulley_diameter", "pulley pitch diameter D", ax.pulley_diameter, "m", "mm"),
        Row("gear_ratio", "gear ratio i", ax.gear_ratio, "1"),
        Row("motor_speed", "peak motor speed", prof.peak_speed, "rad/s", "rpm",
            note="triangular: speed not reached" if prof.triangular else ""),
        Row("carriage_speed", "peak carriage speed", prof.peak_speed * k, "m/s"),
        Row("motor_accel", "motor acceleration", prof.accel, "rad/s^2"),
        Row("carriage_accel", "carriage acceleration", prof.accel * k, "m/s^2"),
        Row("cycle_time", "cycle time", prof.cycle_time, "s"),
    ]
    inertia = [Row("inertia_motor", f"motor rotor ({shown.motor.name if shown else 'none'})", motor_j,
                   "kg m^2", "kg*cm^2")]
    inertia += [Row("inertia_" + n.replace(" ", "_"), n, v, "kg m^2", "kg*cm^2") for n, v in parts.items()]
    inertia += [
        Row("reflected_inertia", "reflected inertia J_red", total, "kg m^2", "kg*cm^2", note="at the motor shaft"),
        Row("inertia_ratio", "load / motor inertia", shown.inertia_ratio if shown else math.nan, "1", digits=3),
    ]
    rows = motion + inertia
    if shown is None:
        return [("motion", motion), ("reflected inertia", inertia)], rows
    d = shown.duty
    torque = [Row(f"torque_{p.name}", f"{p.name} ({p.duration:.3g} s)", p.torque1 if p.name == "accelerate" else p.torque0,
                  "N m", digits=3, note=f"{format_number(p.torque0, 3)} -> {format_number(p.torque1, 3)} N m")
              for p in d.phases]
    torque += [
        Row("peak_torque", "peak torque", d.peak_torque, "N m", digits=3, note=f"T_max {shown.motor.T_max:g} N m"),
        Row("rms_torque", "RMS torque", d.rms_torque, "N m", digits=3,
            note=f"T_n {shown.motor.T_n:g} N m: {shown.utilisation:.0%}"),
        Row("peak_power", "peak power", d.peak_power, "W", digits=3),
        Row("braking_torque", "braking torque", d.braking_torque, "N m", digits=3,
            note="regenerative" if d.braking_torque < 0 else "none"),
        Row("braking_energy", "braking energy per cycle", d.braking_energy, "J", digits=3),
        Row("accel_time", "acceleration time t_a", d.accel_time, "s", digits=3),
        Row("accel_energy", "energy E = T_max w_max t_a", d.accel_energy, "J", digits=3, note="eq. 29"),
        Row("accel_energy_exact", "energy, integral T w dt", d.accel_energy_exact, "J", digits=3,
            note="acceleration phase, exact"),
    ]
    return [("motion", motion), ("reflected inertia", inertia), (f"torque ({shown.motor.name})", torque)], rows + torque


def _print(s, sections, values, title) -> None:
    from rich.table import Table

    print_table(f"Motor sizing: {title}", sections)
    table = Table(title="motor choice (smallest rated torque first)", title_justify="left")
    for col in ("motor", "T_n N m", "T_max N m", "J kg cm^2", "peak", "RMS", "speed", "J ratio", "RMS/T_n", ""):
        table.add_column(col, justify="right" if "N m" in col or "J" in col else "left")
    for c in s.choice.checks:
        mark = lambda ok: "ok" if ok else "[red]FAIL[/red]"
        pick = "[bold green]<- selected[/bold green]" if c is s.choice.selected else ""
        table.add_row(c.motor.name, f"{c.motor.T_n:g}", f"{c.motor.T_max:g}", f"{c.motor.J * 1e4:g}",
                      mark(c.peak_ok), mark(c.rms_ok), mark(c.speed_ok),
                      f"{c.inertia_ratio:.3g} " + ("" if c.inertia_ok else "[red]FAIL[/red]"),
                      f"{c.utilisation:.0%}", pick)
    out = console()
    out.print(table)
    picked = s.choice.selected.motor.name if s.choice.selected else "none"
    out.print(f"recommended: {picked}: {s.choice.reason}", highlight=False, markup=False)
    if s.profile.triangular:
        out.print("the stroke is too short to reach the speed: triangular profile", markup=False)
    given = [f"{k}={v.text}" for k, v in values.items() if v.origin.startswith("option")]
    out.print("inputs: scene values (--json lists each with its reason)"
              + (f"; given: {', '.join(given)}" if given else ""), markup=False, highlight=False)


def _json(s, rows, values) -> str:
    obj = {r.key: {"value": (None if isinstance(r.value, float) and math.isnan(r.value) else r.value),
                   "unit": r.unit} for r in rows}
    for key in ("peak_torque", "rms_torque", "accel_time", "accel_energy", "accel_energy_exact", "peak_power"):
        obj.setdefault(key, {"value": None, "unit": ""})
    obj["selected_motor"] = s.choice.selected.motor.name if s.choice.selected else None
    obj["reported_motor"] = s.shown.motor.name if s.shown else None
    obj["reason"] = s.choice.reason
    obj["triangular"] = s.profile.triangular
    obj["motors"] = [{
        "name": c.motor.name, "peak_torque": c.duty.peak_torque, "rms_torque": c.duty.rms_torque,
        "inertia_ratio": c.inertia_ratio, "utilisation": c.utilisation, "peak_ok": c.peak_ok,
        "rms_ok": c.rms_ok, "speed_ok": c.speed_ok, "inertia_ok": c.inertia_ok, "ok": c.ok,
    } for c in s.choice.checks]
    obj["inputs"] = {k: {"text": v.text, "origin": v.origin} for k, v in values.items()}
    return json.dumps(obj, indent=2)


def _profile_samples(s, per_phase: int = 21):
    """(t, omega, omegadot, torque, power) through the cycle, both ends of every phase."""
    d, t0, out = s.shown.duty, 0.0, []
    for ph, pt in zip(s.profile.phases, d.phases):
        for j in range(per_phase):
            x = j / (per_phase - 1)
            w = ph.speed0 + ph.accel * ph.duration * x
            tq = pt.torque0 + x * (pt.torque1 - pt.torque0)
            out.append((t0 + x * ph.duration, w, ph.accel, tq, tq * w))
        t0 += ph.duration
    return out


def _profile_csv(s) -> str:
    if s.shown is None:
        raise InputError("no motor fits, so there is no torque profile to write; give --motor NAME", param="csv")
    return table_csv(["t_s", "speed_rad_per_s", "accel_rad_per_s2", "torque_N_m", "power_W"],
                     ([repr(v) for v in row] for row in _profile_samples(s)))


def _plot_profile(s, path) -> None:
    if s.shown is None:
        raise InputError("no motor fits, so there is no torque profile to plot; give --motor NAME", param="plot")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = list(zip(*_profile_samples(s)))
    m = s.shown.motor
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    a1.plot(data[0], data[3], label="motor torque")
    for level, style, name in ((m.T_n, "--", "rated"), (m.T_max, ":", "peak")):
        a1.axhline(level, ls=style, color="k", lw=0.8, label=f"{m.name} {name} {level:g} N m")
        a1.axhline(-level, ls=style, color="k", lw=0.8)
    a1.set_ylabel("torque [N m]")
    a1.legend(fontsize=8)
    a2.plot(data[0], [w * 30 / math.pi for w in data[1]])
    a2.set_ylabel("motor speed [rpm]")
    a2.set_xlabel("time [s]")
    fig.suptitle(f"motor-size: {m.name}, RMS {s.shown.duty.rms_torque:.3g} N m")
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)


_SWEEP_DISPLAY = {"rad/s^2": "rad/s^2", "m/s^2": "m/s^2", "rad/s": "rpm", "m/s": "m/s"}


def _render_sweep(name, unit, rows, motor, as_json, csv_path, plot_path) -> None:
    header = [f"{name}_{unit.replace('/', '_per_').replace('^', '')}", "motor_speed_rad_per_s",
              "motor_accel_rad_per_s2", "peak_torque_N_m", "accel_time_s", "accel_energy_J",
              "accel_energy_exact_J", "rms_torque_N_m", "triangular"]
    table = [(v, p.peak_speed, p.accel, d.peak_torque, d.accel_time, d.accel_energy, d.accel_energy_exact,
              d.rms_torque, p.triangular) for v, d, p in rows]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, ([repr(x) for x in r] for r in table)))
    if plot_path is not None:
        _plot_sweep(name, unit, table, motor, plot_path)
    label = motor.name if motor else "load only (no motor fits)"
    if as_json:
        click.echo(json.dumps({"sweep": name, "unit": unit, "motor": motor.name if motor else None,
                               "columns": header, "rows": table}, indent=2))
        return
    from beltcalc.units import convert
    from rich.table import Table

    shown = _SWEEP_DISPLAY[unit]
    t = Table(title=f"sweep of {name} ({label}): the paper's Fig. 13-15", title_justify="left")
    for col in (f"{name} [{shown}]", "motor rpm", "peak torque N m", "t_a s", "E eq.29 J", "E exact J", "RMS N m",
                "profile"):
        t.add_column(col.replace("[", "\\["), justify="right")
    for r in table:
        t.add_row(format_number(convert(r[0], unit, shown)), format_number(r[1] * 30 / math.pi),
                  *(format_number(x, 4) for x in r[3:8]), "triangular" if r[8] else "trapezoid")
    console().print(t)


def _plot_sweep(name, unit, table, motor, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [r[0] for r in table]
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    a1.plot(x, [r[3] for r in table], "o-", label="peak torque")
    if motor:
        a1.axhline(motor.T_max, ls=":", color="k", label=f"{motor.name} T_max")
    a1.set_ylabel("torque [N m]")
    a1.legend(fontsize=8)
    a2.plot(x, [r[5] for r in table], "o-", label="E = T_max w t_a (eq. 29)")
    a2.plot(x, [r[6] for r in table], "s-", label="integral T w dt")
    a2.set_ylabel("acceleration energy [J]")
    a2.set_xlabel(f"{name} [{unit}]")
    a2.legend(fontsize=8)
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)
