"""``beltcalc simulate sewing``: time simulation of a drive train on the shared core."""

from __future__ import annotations

import json

import click

from beltcalc.cli.options import OutputPath, SceneParam, output_options, resolve_scene
from beltcalc.cli.output import (Row, console, format_number, print_table, progress, require_matplotlib,
                                 table_csv, write_atomic)

SEWING = [SceneParam(f"J{k}", "kg*m^2", f"inertia J{k}") for k in range(1, 6)]
SEWING += [SceneParam(f"C{k}", "N*m/rad", f"stiffness C{k}") for k in range(1, 5)]
SEWING += [SceneParam(f"d{k}", "N*m*s/rad", f"damping d{k}") for k in range(1, 5)]
SEWING += [SceneParam(name, "", f"ratio {name}") for name in ("U12", "U23", "U34", "U45")]
SEWING += [
    SceneParam("M3_amp", "N*m", "load amplitude on the main shaft"),
    SceneParam("M3_0", "N*m", "mean load on the main shaft"),
    SceneParam("M5_amp", "N*m", "load amplitude on the bottom shaft"),
    SceneParam("M5_0", "N*m", "mean load on the bottom shaft"),
    SceneParam("rated_torque", "N*m", "motor rated torque"),
    SceneParam("breakdown_factor", "", "breakdown torque / rated torque"),
    SceneParam("breakdown_slip", "", "breakdown slip"),
    SceneParam("supply_frequency", "Hz", "supply frequency"),
    SceneParam("pole_pairs", "", "motor pole pairs"),
    SceneParam("load_frequency", "rad/s", "load frequency (0: the steady main-shaft speed)"),
    SceneParam("t_end", "s", "simulated time"),
    SceneParam("samples", "", "output samples"),
    SceneParam("window", "s", "start of the steady window"),
]
METHOD_NAMES = ["auto", "exact", "radau", "bdf", "lsoda", "odeint", "rk45", "dop853"]
SHAFTS = {"main": ("3", "T_23"), "bottom": ("5", "T_45")}


def _parse_assignments(params: list[SceneParam], items: tuple[str, ...], option: str) -> dict:
    """``NAME=QUANTITY`` pairs -> {name: SI value}; unknown names and bad quantities are usage errors."""
    from beltcalc.units import QuantityError, parse_quantity

    by_name = {p.name: p for p in params}
    out = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or name not in by_name:
            raise click.BadParameter(f"{item!r}: use NAME=QUANTITY with NAME one of {', '.join(by_name)}",
                                     param_hint=option)
        try:
            out[name] = parse_quantity(text, by_name[name].unit)
        except QuantityError as exc:
            raise click.BadParameter(f"{item!r}: {exc}", param_hint=option) from None
    return out


def _sweep(params: list[SceneParam], text: str | None):
    if text is None:
        return None
    from beltcalc.sizing import linspace

    name, sep, rng = text.partition("=")
    parts = rng.split(":")
    if not sep or len(parts) != 3:
        raise click.BadParameter(f"{text!r}: use NAME=START:STOP:N, e.g. C4=50:310:14", param_hint="--sweep")
    unit = next((p.unit for p in params if p.name == name), "")
    bounds = []
    for part in parts[:2]:
        try:  # a bare number is in the parameter's SI unit (C4=50:310:14)
            part = f"{float(part)!r} {unit}"
        except ValueError:
            pass
        try:
            bounds.append(_parse_assignments(params, (f"{name}={part}",), "--sweep")[name])
        except click.BadParameter as exc:
            reason = exc.message.split(": ", 1)[-1]
            raise click.BadParameter(f"{text!r}: {reason}", param_hint="--sweep") from None
    start, stop = bounds
    try:
        n = int(parts[2])
    except ValueError:
        raise click.BadParameter(f"{text!r}: N must be a whole number", param_hint="--sweep") from None
    if not 1 <= n <= 10000:
        raise click.BadParameter(f"{text!r}: N must be 1..10000", param_hint="--sweep")
    return name, linspace(start, stop, n)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
def simulate():
    """Time simulation of drive trains (every scene runs on the one ODE core)."""


@simulate.command("sewing")
@click.option("--scene", default="sewing", show_default=True, help="Built-in scene or a scene .toml file.")
@click.option("--set", "assignments", multiple=True, metavar="NAME=QUANTITY",
              help="Change a scene parameter, e.g. --set C4=190N*m/rad (repeatable).")
@click.option("--t-end", type=str, default=None, help="Simulated time [default: the scene's].")
@click.option("--samples", type=click.IntRange(2, 10_000_000), default=None, help="Output samples.")
@click.option("--dt", type=str, default=None, help="Output step instead of --samples, e.g. 0.1ms.")
@click.option("--window", type=str, default=None, help="Start of the steady window [default: the scene's].")
@click.option("--method", type=click.Choice(METHOD_NAMES), default="auto", show_default=True)
@click.option("--rtol", type=click.FloatRange(1e-14, 1, min_open=True), default=1e-8, show_default=True)
@click.option("--atol", type=click.FloatRange(1e-16, 1, min_open=True), default=1e-10, show_default=True)
@click.option("--angle-loads", is_flag=True, help="Loads follow the shaft angle, sin(phi), not sin(w t): nonlinear.")
@click.option("--modes", is_flag=True, help="Also print the natural frequencies and damping ratios.")
@click.option("--sweep", "sweep_text", default=None, metavar="NAME=START:STOP:N",
              help="Sweep a parameter, e.g. C4=50:310:14 (the paper's Fig. 5).")
@click.option("--plot", "plot_path", type=OutputPath(), default=None, help="Write a PNG (needs matplotlib).")
@click.option("--work-precision", is_flag=True,
              help="Run every method at tolerances 1e-3..1e-10 and tabulate wall time against error (about 1 min).")
@output_options
def sewing(scene, assignments, t_end, samples, dt, window, method, rtol, atol, angle_loads, modes,
           sweep_text, plot_path, work_precision, as_json, csv_path):
    """The sewing-machine drive of Mamatova et al. (2016): speed, acceleration and torque of the
    main and bottom shafts over a steady window, and how it was solved."""
    from beltcalc.catalogs import load_scene
    from beltcalc.errors import InputError
    from beltcalc.sim.core import SolverConfig
    from beltcalc.units import QuantityError, parse_quantity

    given = _parse_assignments(SEWING, assignments, "--set")
    for name, text in (("t_end", t_end), ("window", window)):
        if text is not None:
            try:
                given[name] = parse_quantity(text, "s")
            except QuantityError as exc:
                raise click.BadParameter(str(exc), param_hint=f"--{name.replace('_', '-')}") from None
    if samples is not None:
        given["samples"] = float(samples)
    spec = _sweep(SEWING, sweep_text)
    if plot_path is not None:
        require_matplotlib()
    scene_def = load_scene(scene, command="simulate sewing")
    values = {k: v.value for k, v in resolve_scene(scene_def, SEWING, given).items()}
    if dt is not None:
        try:
            step = parse_quantity(dt, "s")
        except QuantityError as exc:
            raise click.BadParameter(str(exc), param_hint="--dt") from None
        if step <= 0:
            raise InputError(f"{step:g} s is not allowed; it must be > 0 s", param="dt")
        values["samples"] = float(round(values["t_end"] / step) + 1)
    cfg = SolverConfig(method=method, rtol=rtol, atol=atol)

    if work_precision:
        _run_work_precision(values, angle_loads, as_json, csv_path)
        return
    if spec is not None:
        name, points = spec
        rows = []
        with progress(len(points), f"sweep {name}", enabled=not as_json and len(points) > 1) as advance:
            for v in points:
                rows.append(_run_sewing(dict(values, **{name: v}), cfg, angle_loads, errors=False))
                advance()
        _render_sweep(name, points, rows, as_json, csv_path, plot_path)
        return
    net, result, summary = _run_sewing(values, cfg, angle_loads)
    if csv_path is not None:
        write_atomic(csv_path, result.csv_text())
    if plot_path is not None:
        _plot(result, values["window"], plot_path)
    info = _info_rows(result)
    shaft_rows = _shaft_rows(summary)
    if as_json:
        obj = {"method": result.method, "reason": result.reason,
               "wall_time": {"value": result.wall_time, "unit": "s"}, "steps": result.steps,
               "rhs_calls": result.rhs_calls,
               "error_estimate": {"value": result.error_estimate, "unit": "rad/s"},
               "error_reference": result.error_reference,
               "shafts": {s: {r.key: {"value": r.value, "unit": r.unit} for r in rows}
                          for s, rows in shaft_rows.items()},
               "motor": {r.key: {"value": r.value, "unit": r.unit} for r in shaft_rows["motor"]}}
        obj["shafts"].pop("motor")
        if modes:
            obj["modes"] = [{"frequency": {"value": f, "unit": "Hz"}, "damping_ratio": {"value": z, "unit": "1"}}
                            for f, z in net.modes()]
        click.echo(json.dumps(obj, indent=2))
        return
    sections = [(f"main shaft (3), t >= {values['window']:g} s", shaft_rows["main"]),
                ("bottom shaft (5)", shaft_rows["bottom"]), ("motor (1)", shaft_rows["motor"]),
                ("solved", info)]
    print_table(scene_def.title, sections, notes=[f"method: {result.reason}"])
    if modes:
        _print_modes(net)


def _run_work_precision(values: dict, angle_loads: bool, as_json: bool, csv_path) -> None:
    from beltcalc.sim.scenes.sewing import build
    from beltcalc.sim.workprecision import count_runs, work_precision

    net = build(values, angle_loads)
    with progress(count_runs(), "work-precision", enabled=not as_json) as advance:
        rows = work_precision(net, values["t_end"], int(values["samples"]), "omega_3", progress=advance)
    header = ["method", "rtol", "wall_time_s", "rhs_calls", "steps", "max_error_omega3_rad_per_s", "note"]
    table = [[r.method, r.rtol, r.wall_time, r.rhs_calls, r.steps, r.error, r.note] for r in rows]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, table))
    if as_json:
        click.echo(json.dumps({"columns": header, "rows": table,
                               "samples": int(values["samples"]), "t_end": values["t_end"]}, indent=2))
        return
    print_work_precision(rows, f"work-precision: sewing scene, {int(values['samples'])} samples over "
                               f"{values['t_end']:g} s, error of the main-shaft speed against exact")


def print_work_precision(rows, title: str) -> None:
    """The work-precision table (one row per method and tolerance)."""
    from rich.table import Table

    t = Table(title=title, title_justify="left")
    for col in ("method", "rtol", "wall time ms", "RHS calls", "steps", "max error rad/s", "note"):
        t.add_column(col, justify="left" if col in ("method", "note") else "right")
    for r in rows:
        t.add_row(r.method, "-" if r.rtol is None else f"{r.rtol:.0e}",
                  "-" if r.error is None else format_number(r.wall_time * 1e3, 3),
                  str(r.rhs_calls), str(r.steps), "-" if r.error is None else f"{r.error:.2g}", r.note)
    console().print(t)


def _run_sewing(values: dict, cfg, angle_loads: bool, errors: bool = True):
    from dataclasses import replace

    from beltcalc.errors import InputError
    from beltcalc.sim.core import simulate
    from beltcalc.sim.scenes.sewing import build

    from beltcalc.errors import require_positive

    require_positive("t_end", values["t_end"], "s")
    samples = int(values["samples"])
    if samples < 2 or samples != values["samples"]:
        raise InputError(f"{values['samples']:g} samples; it must be a whole number >= 2", param="samples")
    if not 0 <= values["window"] < values["t_end"]:
        raise InputError(f"{values['window']:g} s is not inside the run (0..{values['t_end']:g} s)", param="window")
    net = build(values, angle_loads)
    result = simulate(net, values["t_end"], samples, cfg if errors else replace(cfg, estimate_error=False))
    w0 = values["window"]
    summary = {name: {"speed": result.summary(f"omega_{node}", w0), "accel": result.summary(f"accel_{node}", w0),
                      "torque": result.summary(torque, w0)} for name, (node, torque) in SHAFTS.items()}
    summary["motor"] = {"speed": result.summary("omega_1", w0), "torque": result.summary("M_motor", w0)}
    return net, result, summary


def _shaft_rows(summary) -> dict[str, list[Row]]:
    out = {}
    for name in SHAFTS:
        s = summary[name]
        out[name] = [
            Row("speed_mean", "speed, mean", s["speed"].mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed, amplitude", s["speed"].amplitude, "rad/s"),
            Row("accel_amplitude", "acceleration, amplitude", s["accel"].amplitude, "rad/s^2"),
            Row("torque_mean", "transmitted torque, mean", s["torque"].mean, "N m"),
            Row("torque_amplitude", "transmitted torque, amplitude", s["torque"].amplitude, "N m"),
        ]
    m = summary["motor"]
    out["motor"] = [Row("speed_mean", "speed, mean", m["speed"].mean, "rad/s", "rpm", digits=5),
                    Row("torque_mean", "torque, mean", m["torque"].mean, "N m"),
                    Row("torque_amplitude", "torque, amplitude", m["torque"].amplitude, "N m")]
    return out


def _info_rows(result) -> list[Row]:
    rows = [Row("wall_time", "wall time", result.wall_time, "s", "ms", digits=3),
            Row("steps", "steps", float(result.steps), "1"),
            Row("rhs_calls", "right-hand-side calls", float(result.rhs_calls), "1")]
    if result.error_estimate is not None:
        rows.append(Row("error_estimate", "error estimate (speeds)", result.error_estimate, "rad/s", digits=2,
                        note=f"vs {result.error_reference}"))
    return rows


def _print_modes(net) -> None:
    from rich.table import Table

    t = Table(title="modes of the linear network (motor state included)", title_justify="left")
    t.add_column("mode", justify="right")
    t.add_column("frequency Hz", justify="right")
    t.add_column("damping ratio", justify="right")
    for k, (f, z) in enumerate(net.modes(), 1):
        t.add_row(str(k), format_number(f, 4), format_number(z, 3))
    console().print(t)


def _render_sweep(name, points, rows, as_json, csv_path, plot_path) -> None:
    header = [name, "main_speed_amplitude_rad_per_s", "main_accel_amplitude_rad_per_s2", "main_torque_amplitude_N_m",
              "main_torque_mean_N_m", "bottom_speed_amplitude_rad_per_s", "bottom_accel_amplitude_rad_per_s2",
              "bottom_torque_amplitude_N_m", "bottom_torque_mean_N_m", "speed_mean_main_rad_per_s"]
    table = []
    for v, (_, _, s) in zip(points, rows):
        m, b = s["main"], s["bottom"]
        table.append([v, m["speed"].amplitude, m["accel"].amplitude, m["torque"].amplitude, m["torque"].mean,
                      b["speed"].amplitude, b["accel"].amplitude, b["torque"].amplitude, b["torque"].mean,
                      m["speed"].mean])
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, ([repr(x) for x in r] for r in table)))
    if plot_path is not None:
        _plot_sweep(name, header, table, plot_path)
    if as_json:
        click.echo(json.dumps({"sweep": name, "columns": header, "rows": table}, indent=2))
        return
    from rich.table import Table

    t = Table(title=f"sweep of {name} (the paper's Fig. 5): amplitudes over the steady window", title_justify="left")
    for col in (name, "main dw", "main deps", "main dM", "bottom dw", "bottom deps", "bottom dM", "M3 mean", "M5 mean"):
        t.add_column(col, justify="right")
    for r in table:
        t.add_row(*(format_number(x, 4) for x in (r[0], r[1], r[2], r[3], r[5], r[6], r[7], r[4], r[8])))
    out = console()
    out.print(t)
    out.print("dw [rad/s], deps [rad/s^2], dM [N m]: amplitudes (half peak-to-peak); means of the transmitted torques [N m]",
              markup=False)


def _plot(result, window, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    for node, torque, label in (("3", "T_23", "main shaft"), ("5", "T_45", "bottom shaft")):
        axes[0].plot(result.t, result[f"omega_{node}"], label=label)
        axes[1].plot(result.t, result[f"accel_{node}"], label=label)
        axes[2].plot(result.t, result[torque], label=label)
    for ax, ylabel in zip(axes, ("speed [rad/s]", "acceleration [rad/s^2]", "transmitted torque [N m]")):
        ax.set_ylabel(ylabel)
        ax.axvline(window, color="k", lw=0.6, ls=":")
        ax.legend(fontsize=8)
    axes[2].set_xlabel("time [s]")
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def _plot_sweep(name, header, table, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [r[0] for r in table]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 8))
    for k, ylabel in ((0, "speed amplitude [rad/s]"), (1, "accel. amplitude [rad/s^2]"), (2, "torque amplitude [N m]")):
        axes[k].plot(x, [r[1 + k] for r in table], "o-", label="main shaft")
        axes[k].plot(x, [r[5 + k] for r in table], "s-", label="bottom shaft")
        axes[k].set_ylabel(ylabel)
        axes[k].legend(fontsize=8)
    axes[2].set_xlabel(name)
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)
