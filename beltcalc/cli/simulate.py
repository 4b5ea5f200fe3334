"""``beltcalc simulate sewing|roller-table|linear-axis``: time simulations of drive trains.

Every scene runs on the one ODE core (:func:`beltcalc.sim.core.simulate`). The commands
share one runner: parse ``--set``/``--sweep``/timing options, resolve the scene, build the
network, run (or sweep, or compare every method), and render sections of rows as a table,
``--json`` or ``--csv``. A scene only says how to build its network and what to report.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from typing import Callable

import click

from beltcalc.cli.options import OutputPath, SceneParam, catalog_option, output_options, resolve_scene
from beltcalc.cli.output import (console, display_unit, display_value, format_number, print_table, progress,
                                 require_matplotlib, table_csv, write_atomic)
from beltcalc.report import Row, Section

METHOD_NAMES = ["auto", "exact", "radau", "bdf", "lsoda", "odeint", "rk45", "dop853"]
TIMING = [SceneParam("t_end", "s", "simulated time"), SceneParam("samples", "", "output samples"),
          SceneParam("window", "s", "start of the steady window")]


@dataclass
class Outcome:
    """One run of a scene: the network, the result and what to report."""

    net: object
    result: object
    sections: list[Section]
    notes: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Scene:
    """What a simulate command needs from its scene."""

    command: str
    params: list[SceneParam]
    run: Callable          # (values, cfg, flags, errors) -> Outcome
    build: Callable        # (values, flags) -> Network
    signal: str            # the speed compared in --work-precision
    sweep_example: str
    sweep_show: tuple[str, ...]          # sweep columns shown on the terminal
    plot: tuple = ()                     # panels: (ylabel, ((signal, label), ...))
    timing: bool = True                  # --t-end/--samples/--window apply


# --- the shared runner ------------------------------------------------------------------------
def _parse_assignments(params: list[SceneParam], items: tuple[str, ...], option: str) -> dict:
    """``NAME=QUANTITY`` pairs -> {name: SI value or text}; unknown names and bad quantities are usage errors."""
    from beltcalc.units import QuantityError, parse_quantity, parse_quantity_any

    by_name = {p.name: p for p in params}
    out = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or name not in by_name:
            raise click.BadParameter(f"{item!r}: use NAME=QUANTITY with NAME one of {', '.join(by_name)}",
                                     param_hint=option)
        unit = by_name[name].unit
        try:
            if unit is None:
                out[name] = text.strip()
            elif unit == "int":
                out[name] = int(text)
            elif "|" in unit:
                out[name] = parse_quantity_any(text, tuple(unit.split("|")))
            else:
                out[name] = parse_quantity(text, unit)
        except (QuantityError, ValueError) as exc:
            raise click.BadParameter(f"{item!r}: {exc}", param_hint=option) from None
    return out


def _sweep(params: list[SceneParam], text: str | None, example: str):
    if text is None:
        return None
    from beltcalc.sizing import linspace

    name, sep, rng = text.partition("=")
    parts = rng.split(":")
    if not sep or len(parts) != 3:
        raise click.BadParameter(f"{text!r}: use NAME=START:STOP:N, e.g. {example}", param_hint="--sweep")
    param = next((p for p in params if p.name == name), None)
    if param is not None and (param.unit is None or "|" in (param.unit or "")):
        raise click.BadParameter(f"{text!r}: {name} cannot be swept (it is not a single quantity)",
                                 param_hint="--sweep")
    unit = "" if param is None or param.unit == "int" else param.unit
    bounds = []
    for part in parts[:2]:
        try:  # a bare number is in the parameter's SI unit (C4=50:310:14)
            part = f"{float(part)!r} {unit}"
        except ValueError:
            pass
        try:
            value = _parse_assignments([replace(param, unit=unit)] if param else params, (f"{name}={part}",),
                                       "--sweep")[name]
        except click.BadParameter as exc:
            reason = exc.message.split(": ", 1)[-1]
            raise click.BadParameter(f"{text!r}: {reason}", param_hint="--sweep") from None
        bounds.append(value)
    try:
        n = int(parts[2])
    except ValueError:
        raise click.BadParameter(f"{text!r}: N must be a whole number", param_hint="--sweep") from None
    if not 1 <= n <= 10000:
        raise click.BadParameter(f"{text!r}: N must be 1..10000", param_hint="--sweep")
    return name, linspace(bounds[0], bounds[1], n)


def _values(spec: Scene, scene: str, given: dict) -> tuple[object, dict]:
    from beltcalc.catalogs import load_scene

    scene_def = load_scene(scene, command=f"simulate {spec.command}")
    resolved = resolve_scene(scene_def, spec.params, given)
    return scene_def, {k: v.value for k, v in resolved.items()}


def check_timing(values: dict) -> int:
    """Refuse a run that cannot be made: t_end, samples, window. Returns the sample count."""
    from beltcalc.errors import InputError, require_positive

    require_positive("t_end", values["t_end"], "s")
    samples = int(values["samples"])
    if samples < 2 or samples != values["samples"]:
        raise InputError(f"{values['samples']:g} samples; it must be a whole number >= 2", param="samples")
    if not 0 <= values["window"] < values["t_end"]:
        raise InputError(f"{values['window']:g} s is not inside the run (0..{values['t_end']:g} s)", param="window")
    return samples


def run_command(spec: Scene, scene, assignments, dt, method, rtol, atol, max_events, error_tol, accept_error, modes,
                sweep_text, plot_path, work_precision, as_json, csv_path, flags: dict, t_end=None, samples=None,
                window=None) -> None:
    """The body every ``simulate`` command shares."""
    from beltcalc.errors import InputError
    from beltcalc.sim.core import SolverConfig
    from beltcalc.units import QuantityError, parse_quantity

    given = _parse_assignments(spec.params, assignments, "--set")
    for name, text in (("t_end", t_end), ("window", window)):
        if text is not None:
            try:
                given[name] = parse_quantity(text, "s")
            except QuantityError as exc:
                raise click.BadParameter(str(exc), param_hint=f"--{name.replace('_', '-')}") from None
    if samples is not None:
        given["samples"] = float(samples)
    given.update({k: v for k, v in flags.items() if k in {p.name for p in spec.params} and v is not None})
    sweep = _sweep(spec.params, sweep_text, spec.sweep_example)
    if plot_path is not None:
        require_matplotlib()
    scene_def, values = _values(spec, scene, given)
    if dt is not None:
        try:
            step = parse_quantity(dt, "s")
        except QuantityError as exc:
            raise click.BadParameter(str(exc), param_hint="--dt") from None
        if step <= 0:
            raise InputError(f"{step:g} s is not allowed; it must be > 0 s", param="dt")
        if spec.timing:
            values["samples"] = float(round(values["t_end"] / step) + 1)
        else:
            values["step"] = step
    cfg = SolverConfig(method=method, rtol=rtol, atol=atol, max_events=max_events, error_tol=error_tol,
                       accept_error=accept_error)

    if work_precision:
        _work_precision(spec, values, flags, as_json, csv_path)
        return
    if sweep is not None:
        name, points = sweep
        outcomes = []
        with progress(len(points), f"sweep {name}", enabled=not as_json and len(points) > 1) as advance:
            for v in points:
                outcomes.append(spec.run(dict(values, **{name: v}), cfg, flags, True))
                advance()
        _render_sweep(spec, name, points, outcomes, as_json, csv_path, plot_path)
        return
    out = spec.run(values, cfg, flags, True)
    for warning in out.result.warnings:
        click.echo(f"warning: {warning}", err=True)
    if csv_path is not None:
        write_atomic(csv_path, out.result.csv_text())
    if plot_path is not None:
        _plot(spec, out.result, plot_path)
    solved = _info_rows(out.result)
    if as_json:
        r = out.result
        obj = {"scene": scene_def.title, "method": r.method, "reason": r.reason,
               "wall_time": {"value": r.wall_time, "unit": "s"}, "steps": r.steps, "rhs_calls": r.rhs_calls,
               "error_estimate": {"value": r.error_estimate, "unit": r.error_unit},
               "error_relative": {"value": r.error_relative, "unit": "1"}, "error_signal": r.error_signal,
               "error_reference": r.error_reference, "warnings": list(r.warnings)}
        if r.extra.get("slack_time"):
            obj["events"] = r.extra["events"]
        for sec in out.sections:
            node = obj
            for key in sec.path:
                node = node.setdefault(key, {})
            node.update({row.key: {"value": row.value, "unit": row.unit} for row in sec.rows})
        if modes:
            obj["modes"] = [{"frequency": {"value": f, "unit": "Hz"}, "damping_ratio": {"value": z, "unit": "1"}}
                            for f, z in out.net.modes()]
        if out.notes:
            obj["notes"] = out.notes
        click.echo(json.dumps(obj, indent=2))
        return
    _print_sections(scene_def.title, out.sections + [Section(("solved",), "solved", solved)],
                    [f"method: {out.result.reason}"] + out.notes)
    if modes:
        _print_modes(out.net)


def _print_sections(title: str, sections: list[Section], notes: list[str]) -> None:
    """Plain sections as one key-value table; a group of sections as one table, a row per item."""
    from rich.table import Table

    plain = [(s.title, s.rows) for s in sections if not s.group]
    print_table(title, plain, notes=notes)
    groups: dict[str, list[Section]] = {}
    for s in sections:
        if s.group:
            groups.setdefault(s.group, []).append(s)
    out = console()
    for group, secs in groups.items():
        t = Table(title=group, title_justify="left")
        t.add_column("")
        for row in secs[0].rows:
            unit = display_unit(row)
            t.add_column(f"{row.label} [{unit}]" if unit else row.label, justify="right")
        for s in secs:
            t.add_row(s.item, *(display_value(row) for row in s.rows))
        out.print(t)


def _info_rows(result) -> list[Row]:
    rows = [Row("wall_time", "wall time", result.wall_time, "s", "ms", digits=3),
            Row("steps", "steps", float(result.steps), "1"),
            Row("rhs_calls", "right-hand-side calls", float(result.rhs_calls), "1")]
    if result.extra.get("slack_time"):
        rows.append(Row("events", "strand switches", float(result.extra["events"]), "1"))
    if result.error_estimate is not None:
        rows.append(Row("error_estimate", "error estimate (worst speed)", result.error_estimate, result.error_unit,
                        digits=2, note=f"{result.error_signal}, vs {result.error_reference}"))
    return rows


def _print_modes(net) -> None:
    from rich.table import Table

    t = Table(title="modes of the linear network (motor state included, strands taut)", title_justify="left")
    t.add_column("mode", justify="right")
    t.add_column("frequency Hz", justify="right")
    t.add_column("damping ratio", justify="right")
    for k, (f, z) in enumerate(net.modes(), 1):
        t.add_row(str(k), format_number(f, 4), format_number(z, 3))
    console().print(t)


def _columns(out: Outcome) -> list[tuple[str, float]]:
    """A sweep row: every reported value, named <item or section>_<key>_<unit>."""
    from beltcalc.sim.result import _unit_tag

    cols = []
    for sec in out.sections:
        for row in sec.rows:
            unit = "" if row.unit in ("", "1") else "_" + _unit_tag(row.unit)
            cols.append((f"{sec.path[-1]}_{row.key}{unit}", row.value))
    return cols


def _render_sweep(spec: Scene, name, points, outcomes, as_json, csv_path, plot_path) -> None:
    header = [name] + [c for c, _ in _columns(outcomes[0])]
    table = [[v] + [x for _, x in _columns(o)] for v, o in zip(points, outcomes)]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, (["" if x is None else repr(x) for x in r] for r in table)))
    if plot_path is not None:
        _plot_sweep(spec, name, header, table, plot_path)
    if as_json:
        click.echo(json.dumps({"sweep": name, "columns": header, "rows": table}, indent=2))
        return
    from rich.table import Table

    shown = [c for c in spec.sweep_show if c in header]
    t = Table(title=f"sweep of {name}", title_justify="left")
    for col in [name] + shown:
        t.add_column(col, justify="right")
    for r in table:
        t.add_row(*(format_number(r[header.index(c)], 4) for c in [name] + shown))
    console().print(t)
    console().print("all columns: --json or --csv", markup=False)


def _work_precision(spec: Scene, values: dict, flags: dict, as_json: bool, csv_path) -> None:
    from beltcalc.sim.workprecision import count_runs, work_precision

    net = spec.build(values, flags)
    t_end, samples = spec_timing(spec, values, flags)
    with progress(count_runs(), "work-precision", enabled=not as_json) as advance:
        rows = work_precision(net, t_end, samples, spec.signal, progress=advance)
    header = ["method", "rtol", "wall_time_s", "rhs_calls", "steps", f"max_error_{spec.signal}", "note"]
    table = [[r.method, r.rtol, r.wall_time, r.rhs_calls, r.steps, r.error, r.note] for r in rows]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, table))
    if as_json:
        click.echo(json.dumps({"columns": header, "rows": table, "samples": samples, "t_end": t_end}, indent=2))
        return
    print_work_precision(rows, f"work-precision: {spec.command} scene, {samples} samples over {t_end:g} s, "
                               f"error of {spec.signal} against exact")


def spec_timing(spec: Scene, values: dict, flags: dict) -> tuple[float, int]:
    """(t_end, samples) of a scene's run."""
    if spec.timing:
        return values["t_end"], check_timing(values)
    return _axis_timing(values, _axis_prepare(values, flags)[0])


def print_work_precision(rows, title: str) -> None:
    """The work-precision table (one row per method and tolerance)."""
    from rich.table import Table

    t = Table(title=title, title_justify="left")
    for col in ("method", "rtol", "wall time ms", "RHS calls", "steps", "max error", "note"):
        t.add_column(col, justify="left" if col in ("method", "note") else "right")
    for r in rows:
        t.add_row(r.method, "-" if r.rtol is None else f"{r.rtol:.0e}",
                  "-" if r.error is None else format_number(r.wall_time * 1e3, 3),
                  str(r.rhs_calls), str(r.steps), "-" if r.error is None else f"{r.error:.2g}", r.note)
    console().print(t)


def _plot(spec: Scene, result, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(spec.plot), 1, sharex=True, figsize=(8, 2.7 * len(spec.plot)), squeeze=False)
    for ax, (ylabel, lines) in zip(axes[:, 0], spec.plot):
        for signal, label in lines:
            if signal in result.signals:
                ax.plot(result.t, result[signal], label=label)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=8)
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def _plot_sweep(spec: Scene, name, header, table, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = [c for c in spec.sweep_show if c in header]
    fig, axes = plt.subplots(len(shown), 1, sharex=True, figsize=(7, 2.4 * len(shown)), squeeze=False)
    x = [r[0] for r in table]
    for ax, col in zip(axes[:, 0], shown):
        ax.plot(x, [r[header.index(col)] for r in table], "o-")
        ax.set_ylabel(col, fontsize=7)
    axes[-1, 0].set_xlabel(name)
    fig.tight_layout()
    write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def common_options(default_scene: str, timing: bool = True):
    """The options every simulate command has."""
    def decorate(func):
        opts = [
            click.option("--scene", default=default_scene, show_default=True,
                         help="Built-in scene or a scene .toml file."),
            click.option("--set", "assignments", multiple=True, metavar="NAME=QUANTITY",
                         help="Change a scene parameter, e.g. --set NAME=QUANTITY (repeatable)."),
        ]
        if timing:
            opts += [click.option("--t-end", type=str, default=None, help="Simulated time [default: the scene's]."),
                     click.option("--samples", type=click.IntRange(2, 10_000_000), default=None, help="Output samples."),
                     click.option("--window", type=str, default=None,
                                  help="Start of the steady window [default: the scene's].")]
        opts += [
            click.option("--dt", type=str, default=None, help="Output step instead of --samples, e.g. 0.1ms."),
            click.option("--method", type=click.Choice(METHOD_NAMES), default="auto", show_default=True),
            click.option("--rtol", type=click.FloatRange(1e-14, 1, min_open=True), default=1e-8, show_default=True),
            click.option("--atol", type=click.FloatRange(1e-16, 1, min_open=True), default=1e-10, show_default=True),
            click.option("--max-events", type=click.IntRange(1, 10_000_000), default=20_000, show_default=True,
                         help="Bound on strand switches (a chain chattering near zero tension)."),
            click.option("--error-tol", type=click.FloatRange(0, 1, min_open=True, max_open=True), default=1e-6,
                         show_default=True,
                         help="Largest error estimate accepted, relative to the signal's scale; above it auto "
                              "refines, then falls back to Radau, else the run fails."),
            click.option("--accept-error", is_flag=True,
                         help="Print a result whose error estimate exceeds --error-tol (marked) instead of failing."),
            click.option("--modes", is_flag=True, help="Also print the natural frequencies and damping ratios."),
            click.option("--sweep", "sweep_text", default=None, metavar="NAME=START:STOP:N",
                         help="Sweep a scene parameter."),
            click.option("--plot", "plot_path", type=OutputPath(), default=None, help="Write a PNG (needs matplotlib)."),
            click.option("--work-precision", is_flag=True,
                         help="Run every method at tolerances 1e-3..1e-10 and tabulate wall time against error."),
            output_options,
        ]
        for opt in reversed(opts):
            func = opt(func)
        return func
    return decorate


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
def simulate():
    """Time simulation of drive trains (every scene runs on the one ODE core)."""


# --- sewing -----------------------------------------------------------------------------------
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
] + TIMING
SHAFTS = {"main": ("3", "T_23"), "bottom": ("5", "T_45")}


def _sewing_build(values: dict, flags: dict):
    from beltcalc.sim.scenes.sewing import build

    return build(values, flags.get("angle_loads", False))


def _sewing_run(values: dict, cfg, flags: dict, errors: bool) -> Outcome:
    from beltcalc.sim.core import simulate as run

    samples = check_timing(values)
    net = _sewing_build(values, flags)
    result = run(net, values["t_end"], samples, cfg if errors else replace(cfg, estimate_error=False))
    w0 = values["window"]
    sections = []
    for name, (node, torque) in SHAFTS.items():
        speed, accel, tq = (result.summary(s, w0) for s in (f"omega_{node}", f"accel_{node}", torque))
        sections.append(Section(("shafts", name), f"{name} shaft ({node}), t >= {w0:g} s" if name == "main"
                                else f"{name} shaft ({node})", [
            Row("speed_mean", "speed, mean", speed.mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed, amplitude", speed.amplitude, "rad/s"),
            Row("accel_amplitude", "acceleration, amplitude", accel.amplitude, "rad/s^2"),
            Row("torque_mean", "transmitted torque, mean", tq.mean, "N m"),
            Row("torque_amplitude", "transmitted torque, amplitude", tq.amplitude, "N m"),
        ]))
    speed, torque = result.summary("omega_1", w0), result.summary("M_motor", w0)
    sections.append(Section(("motor",), "motor (1)", [
        Row("speed_mean", "speed, mean", speed.mean, "rad/s", "rpm", digits=5),
        Row("torque_mean", "torque, mean", torque.mean, "N m"),
        Row("torque_amplitude", "torque, amplitude", torque.amplitude, "N m"),
    ]))
    return Outcome(net, result, sections)


SEWING_SCENE = Scene(
    "sewing", SEWING, _sewing_run, _sewing_build, "omega_3", "C4=50:310:14",
    ("main_speed_amplitude_rad_per_s", "main_accel_amplitude_rad_per_s2", "main_torque_amplitude_N_m",
     "bottom_speed_amplitude_rad_per_s", "bottom_accel_amplitude_rad_per_s2", "bottom_torque_amplitude_N_m"),
    (("speed [rad/s]", (("omega_3", "main shaft"), ("omega_5", "bottom shaft"))),
     ("acceleration [rad/s^2]", (("accel_3", "main shaft"), ("accel_5", "bottom shaft"))),
     ("transmitted torque [N m]", (("T_23", "main shaft"), ("T_45", "bottom shaft")))),
)


@simulate.command("sewing")
@common_options("sewing")
@click.option("--angle-loads", is_flag=True, help="Loads follow the shaft angle, sin(phi), not sin(w t): nonlinear.")
def sewing(angle_loads, **kw):
    """The sewing-machine drive of Mamatova et al. (2016): speed, acceleration and torque of the
    main and bottom shafts over a steady window, and how it was solved. Sweep e.g.
    --sweep C4=50:310:14 (the paper's Fig. 5)."""
    run_command(SEWING_SCENE, flags={"angle_loads": angle_loads}, **kw)


# --- roller table -----------------------------------------------------------------------------
def _roller_params() -> list[SceneParam]:
    from beltcalc.sim.scenes import roller_table as rt

    texts = {"routing": None}
    plain = ("rollers", "drive_teeth", "roller_teeth", "idler_teeth", "pole_pairs", "breakdown_slip",
             "settle_tolerance")
    units = {**rt.POSITIVE, **rt.NONNEGATIVE, **rt.ANY_SIGN, **{k: "" for k in plain}, **texts}
    return [SceneParam(k, u, k.replace("_", " ")) for k, u in units.items()] + TIMING


def _roller_build(values: dict, flags: dict):
    from beltcalc.sim.scenes.roller_table import build

    return build(values)


def _roller_run(values: dict, cfg, flags: dict, errors: bool) -> Outcome:
    from beltcalc.sim.core import simulate as run
    from beltcalc.sim.scenes import roller_table as rt

    samples = check_timing(values)
    net = rt.build(values)
    w0, n = values["window"], int(values["rollers"])
    watched = [f"{kind}{k}" for k in range(1, n + 1) for kind in ("omega_end", "T_shaft", "T_tube")]
    watched = [w + "a" if w.startswith("omega_end") else w for w in watched]
    watched += ["omega_motor", "M_motor"] + [f"F_{s.name}" for s in net.strands]
    result = run(net, values["t_end"], samples, cfg if errors else replace(cfg, estimate_error=False),
                 watch=(watched, (0.0, w0)))
    sections = []
    for k in range(1, n + 1):
        speed = result.summary(f"omega_end{k}a", w0)
        ta, tb = result.summary(f"T_shaft{k}", w0), result.summary(f"T_tube{k}", w0)
        sections.append(Section(("rollers", str(k)), f"roller {k}", [
            Row("speed_mean", "speed mean", speed.mean, "rad/s", digits=5),
            Row("speed_amplitude", "speed ampl.", speed.amplitude, "rad/s"),
            Row("torque_drive_end_mean", "torque drive end mean", ta.mean, "N m"),
            Row("torque_drive_end_amplitude", "ampl.", ta.amplitude, "N m"),
            Row("torque_far_end_mean", "torque far end mean", tb.mean, "N m"),
            Row("torque_far_end_amplitude", "ampl.", tb.amplitude, "N m"),
        ], group=f"rollers, t >= {w0:g} s (torque into the drive end through the journal, and along the tube "
                 "to the far end)", item=str(k)))
    slack = result.extra.get("slack_time", {})
    for s in net.strands:
        force = result.summary(f"F_{s.name}", 0.0)
        sections.append(Section(("strands", s.name), s.name, [
            Row("force_min", "force min", force.min, "N"),
            Row("force_max", "force max", force.max, "N"),
            Row("slack_time", "time slack", float(slack.get(s.name, 0.0)), "s"),
            Row("safety", "breaking load / max", values["chain_breaking_load"] / max(force.max, 1e-300), "1",
                digits=3),
        ], group="chain strands, whole run (tension only; slack = no force)", item=s.name))
    speed, torque = result.summary("omega_motor", w0), result.summary("M_motor", w0)
    whole = result.summary("M_motor", 0.0)
    peak = max(abs(whole.min), abs(whole.max))
    start = values["load_start"] if values["load_start"] > 0 else values["t_end"]
    target = result.summary("omega_end1a", 0.9 * start, start).mean
    settle = result.settle_time("omega_end1a", target, values["settle_tolerance"] * abs(target), 0.0, start)
    sections.append(Section(("motor",), f"motor, t >= {w0:g} s", [
        Row("speed_mean", "speed, mean", speed.mean, "rad/s", "rpm", digits=5),
        Row("torque_mean", "torque, mean", torque.mean, "N m"),
        Row("torque_amplitude", "torque, amplitude", torque.amplitude, "N m"),
        Row("torque_peak", "torque, peak over the run", peak, "N m"),
        Row("startup_time", "start-up time", settle, "s",
            note=f"roller 1 within {values['settle_tolerance']:.0%} of its speed before the load"),
        Row("steady_speed_rollers", "roller speed, static balance", rt.steady_speed(values), "rad/s", digits=5),
    ]))
    notes = []
    if settle is None:
        notes.append("the rollers did not settle before the load lands: raise load_start or t_end")
    breakdown = values["breakdown_factor"] * values["rated_torque"]
    if abs(torque.mean) > breakdown:
        notes.append(f"the motor's mean torque {torque.mean:.3g} N m exceeds its breakdown torque {breakdown:.3g} N m: "
                     "the linearised characteristic does not hold there, and a real motor would stall; "
                     "choose a larger motor or gear ratio")
    return Outcome(net, result, sections, notes)


ROLLER_SCENE = Scene(
    "roller-table", [], _roller_run, _roller_build, "omega_end1a", "pretension=0N:600N:7",
    ("motor_torque_peak_N_m", "motor_speed_mean_rad_per_s", "drive-sprocket1_force_max_N",
     "sprocket3-drive_slack_time_s", "motor_startup_time_s"),
    (("speed [rad/s]", (("omega_end1a", "roller 1"), ("omega_end2a", "roller 2"), ("omega_end3a", "roller 3"))),
     ("motor torque [N m]", (("M_motor", "motor"),)),
     ("strand force [N]", (("F_drive-sprocket1", "drive to roller 1"), ("F_sprocket3-drive", "return")))),
)


@simulate.command("roller-table")
@common_options("roller_table")
def roller_table(**kw):
    """The roller-table drive with chain transmission of Rusek & Popenda: induction motor,
    coupling, two-stage gear, clutch, tension-only chain strands and rollers loaded at both
    ends. Per roller speed and end torques, per strand force and time slack, motor torque and
    start-up time. Sweep e.g. --sweep rollers=1:20:20 or --sweep pretension=0N:600N:7."""
    run_command(replace(ROLLER_SCENE, params=_roller_params()), flags={}, **kw)


# --- linear axis ------------------------------------------------------------------------------
def _axis_params() -> list[SceneParam]:
    from beltcalc.cli.motor_size import PARAMS

    return PARAMS + [
        SceneParam("thread", None, "Tensioner bolt thread (for the pretension, as `beltcalc tension`)."),
        SceneParam("tension_accel", "m/s^2", "Acceleration of the tensioning motion."),
        SceneParam("tension_speed", "m/s", "Speed of the tensioning motion."),
        SceneParam("mu", "", "Thread friction coefficient."),
        SceneParam("damping", "N*s/m", "Belt damping b_TB, instead of the catalog's.", required=False),
        SceneParam("drive", None, "prescribed (ideal servo) or speed-loop (feed-forward + speed_gain)."),
        SceneParam("speed_gain", "N*m*s/rad", "Proportional speed-loop gain."),
        SceneParam("belt_model", None, "substitute (eq. 5-9) or chain (eq. 1, z - 1 units)."),
        SceneParam("after_move", "s", "Simulated time after the move."),
        SceneParam("step", "s", "Output step."),
        SceneParam("settle_band", "m", "Following-error band for the settling time."),
    ]


def _axis_prepare(values: dict, flags: dict):
    from beltcalc.catalogs import load_catalog
    from beltcalc.sim.scenes.linear_axis import prepare
    from beltcalc.sizing import SizingInputs
    from beltcalc.tension import TensionInputs

    cat = load_catalog(flags.get("catalog_paths") or ())
    belt = cat.belt(values["belt"])
    motor = cat.motor(flags["motor_name"]) if flags.get("motor_name") else None
    fields = {name: values[name] for name in _motor_size_names() if name in values and name != "belt"}
    speed, speed_unit = fields.pop("speed")
    accel, accel_unit = fields.pop("accel")
    inp = SizingInputs(**fields, speed=speed, speed_unit=speed_unit, accel=accel, accel_unit=accel_unit,
                       substitute_mass_model=flags.get("substitute_mass_model") or "eq7")
    tin = TensionInputs(center_distance=inp.center_distance, width=inp.width, mass=inp.mass, accel=1.0,
                        tension_accel=values["tension_accel"], tension_speed=values["tension_speed"],
                        mu=values["mu"], pulley_diameter=1.0, damping=values.get("damping"))
    return prepare(inp, belt, list(cat.motors.values()), motor, tin, cat.thread(values["thread"]),
                   values["drive"], values["speed_gain"], values["belt_model"])


def _motor_size_names() -> list[str]:
    from beltcalc.cli.motor_size import PARAMS

    return [p.name for p in PARAMS]


def _axis_timing(values: dict, model) -> tuple[float, int]:
    from beltcalc.errors import InputError, require_positive
    from beltcalc.sim.scenes.linear_axis import move_time

    require_positive("--set after_move", values["after_move"], "s")
    require_positive("--set step", values["step"], "s")
    t_end = move_time(model) + values["after_move"]
    samples = int(round(t_end / values["step"])) + 1
    if samples > 10_000_000:
        raise InputError(f"{samples} samples; at most 10,000,000: raise --dt", param="dt")
    return t_end, samples


def _span_rows(model, values: dict) -> list[Row]:
    """First natural frequency with both belt paths counted, k = C_spec / L1 + C_spec / L2,
    the carriage at the start, middle and end of a stroke centred on the span."""
    from dataclasses import replace as with_

    from beltcalc.sim.scenes import linear_axis as la

    a, stroke = values["center_distance"], values["stroke"]
    if model.belt_model != "substitute" or stroke >= a:
        return []
    c_spec = model.stiffness * a                       # k_TB = C_spec / a
    rows = []
    for key, label, where in (("start", "start", (a - stroke) / 2), ("mid", "middle", a / 2),
                              ("end", "end", (a + stroke) / 2)):
        k = la.span_stiffness(c_spec, a, model.axis.pulley_diameter, where)
        f = la.first_frequency(la.build(with_(model, stiffness=k)))
        if f is None:
            continue
        rows.append(Row(f"first_frequency_spans_{key}", f"  with both spans, carriage at the {label}", f, "Hz",
                        note=f"k = {k / model.stiffness:.2f} k_TB"))
    return rows


def _axis_build(values: dict, flags: dict):
    from beltcalc.sim.scenes.linear_axis import build

    return build(_axis_prepare(values, flags)[0])


def _axis_run(values: dict, cfg, flags: dict, errors: bool) -> Outcome:
    import numpy as np

    from beltcalc.sim.core import simulate as run
    from beltcalc.sim.scenes import linear_axis as la

    model, sizing, report = _axis_prepare(values, flags)
    net = la.build(model)
    t_end, samples = _axis_timing(values, model)
    result = run(net, t_end, samples, cfg if errors else replace(cfg, estimate_error=False))
    t_move = la.move_time(model)
    force = la.belt_force(model, result["T_belt"])
    result.signals["F_belt"], result.units["F_belt"] = force, "N"
    error = result["x_carriage"] - la.reference_position(model, result.t)
    result.signals["following_error"], result.units["following_error"] = error, "m"
    torque = result["T_drive_motor"]
    during = result.window(0.0, t_move)
    after = result.window(t_move)
    final = float(error[-max(2, samples // 20):].mean())
    settle = result.settle_time("following_error", final, values["settle_band"], t_move)
    residual = 0.5 * float(error[after].max() - error[after].min())
    pretension = report.tension_peak
    worst = float(np.abs(force).max())
    duty = model.duty
    cycle_time = sizing.profile.cycle_time
    cycle = result.window(0.0, cycle_time)
    rms = (float(np.sqrt(np.trapezoid(torque[cycle] ** 2, result.t[cycle]) / cycle_time))
           if t_end >= cycle_time - 1e-12 else None)
    f1 = la.first_frequency(net)
    sections = [
        Section(("belt",), "belt", [
            Row("force_max", "belt force, max", float(force.max()), "N"),
            Row("force_min", "belt force, min", float(force.min()), "N"),
            Row("pretension", "pretension F_t,peak (beltcalc tension)", pretension, "N"),
            Row("pretension_margin", "pretension - max |force|", pretension - worst, "N",
                note="< 0: the slack span goes slack (the paper's eq. 10-11 criterion)"),
            Row("stiffness", "k_TB = C_spec / a", model.stiffness, "N/m"),
            Row("damping", "b_TB", model.damping, "N*s/m"),
            Row("first_frequency", "first natural frequency", f1, "Hz"),
        ] + _span_rows(model, values)),
        Section(("carriage",), "carriage", [
            Row("following_error_max", "following error, max during the move",
                float(np.abs(error[during]).max()), "m", "mm"),
            Row("residual_amplitude", "residual vibration after the move, amplitude", residual, "m", "mm"),
            Row("settling_time", f"settling time after the move (band {values['settle_band'] * 1e3:g} mm)",
                settle - t_move if settle is not None else None, "s"),
        ]),
        Section(("motor",), f"motor {sizing.shown.motor.name}", [
            Row("torque_peak", "torque, peak (dynamic)", float(np.abs(torque).max()), "N m"),
            Row("torque_peak_rigid", "torque, peak (motor-size, rigid)", duty.peak_torque, "N m"),
            Row("torque_rms", "torque, RMS over the cycle (dynamic)", rms, "N m"),
            Row("torque_rms_rigid", "torque, RMS (motor-size, rigid)", duty.rms_torque, "N m"),
            Row("speed_max", "speed, max", float(np.abs(result["omega_motor"]).max()), "rad/s", "rpm"),
        ]),
    ]
    mass_model = flags.get("substitute_mass_model") or "eq7"
    if rms is None:
        notes_rms = ["the run ends before the cycle (move + dwell): no RMS; raise --set after_move"]
    else:
        notes_rms = []
    notes = [f"drive: {model.drive}; belt: {model.belt_model}"
             + (f" (eq. 1, {model.chain_units} units)" if model.belt_model == "chain" else
                f" (m_TB = {model.axis.substitute_mass * 1e3:.4g} g by {mass_model})")]
    notes += notes_rms
    if settle is None:
        notes.append("the carriage has not settled by the end of the run: raise --set after_move=...")
    if pretension < worst:
        notes.append(f"the belt force reaches {worst:.0f} N, above the pretension {pretension:.0f} N: "
                     "the slack span goes slack")
    return Outcome(net, result, sections, notes)


AXIS_SCENE = Scene(
    "linear-axis", [], _axis_run, _axis_build, "v_carriage", "speed_gain=0.05:0.5:10",
    ("belt_force_max_N", "belt_pretension_margin_N", "carriage_following_error_max_m",
     "carriage_residual_amplitude_m", "motor_torque_peak_N_m"),
    (("belt force [N]", (("F_belt", "belt"),)),
     ("following error [m]", (("following_error", "carriage"),)),
     ("motor torque [N m]", (("T_drive_motor", "motor"),))),
    timing=False,
)


@simulate.command("linear-axis")
@common_options("linear_axis", timing=False)
@click.option("--belt-model", type=click.Choice(["substitute", "chain"]), default=None,
              help="substitute: eq. 5-9, one spring-damper-mass; chain: eq. 1, z - 1 units [default: the scene's].")
@click.option("--drive", type=click.Choice(["prescribed", "speed-loop"]), default=None,
              help="prescribed: the motor follows the move; speed-loop: feed-forward + speed gain [default: the scene's].")
@click.option("--substitute-mass-model", type=click.Choice(["eq7", "rayleigh"]), default="eq7", show_default=True,
              help="m_TB by eq. 7 or Rayleigh's m/3.")
@click.option("--motor", "motor_name", default=None, help="Motor to simulate [default: motor-size's choice].")
@catalog_option
def linear_axis(belt_model, drive, substitute_mass_model, motor_name, catalog_paths, **kw):
    """A timing-belt linear axis as a dynamic model (Wojtkowiak et al. 2021, WDU axis): the belt
    as the substitute spring-damper-mass of `beltcalc tension` (or the paper's eq. 1 chain),
    the motor on the move of `beltcalc motor-size`. Belt force against the pretension,
    following error, residual vibration, motor torque against the rigid answer."""
    flags = {"belt_model": belt_model, "drive": drive, "substitute_mass_model": substitute_mass_model,
             "motor_name": motor_name, "catalog_paths": catalog_paths}
    run_command(replace(AXIS_SCENE, params=_axis_params()), flags=flags, **kw)
