"""``beltcalc simulate sewing|roller-table|linear-axis``: time simulations of drive trains.

The scenes and their runs are library code (:mod:`beltcalc.sim.scenes`). A command here
parses its options, resolves the scene's values, calls the library once (a run, a sweep,
or every method side by side) and renders the outcome as a table, ``--json``, ``--csv``
or ``--plot``. A scene's value named in an error is the option that sets it (``--set
NAME``, or ``--t-end``/``--samples``/``--window``/``--dt``).

References (the scenes' papers, in the commands' help):

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016).
[W21] D. Wojtkowiak, K. Talaska, D. Wilczynski, J. Gorecki, K. Walesa, "Determining the
    Power Consumption of the Automatic Device for Belt Perforation Based on the Dynamic
    Model", Energies 14 (2021) 317.
"""

from __future__ import annotations

import click

from beltcalc.cli.main import OPTION_NAMES, SCENE_OPTION, option_name
from beltcalc.cli.options import DriveRef, OutputPath, Tolerance, catalog_option, output_options
from beltcalc.cli.output import (console, display_unit, display_value, format_number, inputs_json, print_table, progress, spinner, dumps, emit_warnings, wrote,
                                 require_matplotlib, table_csv, write_atomic, write_figure)
from beltcalc.errors import render
from beltcalc.report import Row, Section, unit_label
from beltcalc.sim.methods import NAMES
from beltcalc.sim.scenes.base import Scene

TIME_OPTIONS = {"t_end": "--t-end", "samples": "--samples", "window": "--window"}


def _seconds(text: str, option: str) -> float:
    from beltcalc.units import QuantityError, parse_quantity

    try:
        return parse_quantity(text, "s")
    except QuantityError as exc:
        raise click.BadParameter(str(exc), param_hint=option) from None


def run_command(spec: Scene, scene: str, assignments, dt, method, rtol, atol, max_events, error_tol, accept_error, modes,
                sweep_text, plot_path, work_precision, as_json, csv_path, options: dict, preset: dict | None = None,
                t_end=None, samples=None, window=None, strict: bool = False, vary=(), runs=None, seed=None,
                limits=(), parquet_path=None, workers=None, scheduler=None) -> None:
    """The body every ``simulate`` command shares: ``preset`` are scene values its own
    options give (None: not given), ``options`` the scene's keyword inputs. ``sweep_text``
    (one or several ``--sweep``: a grid) or ``vary`` (a tolerance study) run a study."""
    from beltcalc.errors import require_positive
    from beltcalc.params import parse_assignments, sweep_points
    from beltcalc.sim.core import SolverConfig
    from beltcalc.sim.scenes.base import run_scene

    if click.get_current_context().meta.get(LIST_PARAMS):
        _list_params(spec, scene, as_json)
        return
    own = dict(TIME_OPTIONS if spec.timed else {}, **({"step": "--dt"} if dt is not None else {}))
    click.get_current_context().meta[SCENE_OPTION] = lambda name: own.get(name, f"--set {name}")
    click.get_current_context().meta.setdefault(OPTION_NAMES, {}).update({"step": "--dt"} if dt is not None else {})
    given = parse_assignments(spec.params, assignments)
    for name, text in (("t_end", t_end), ("window", window)):
        if text is not None:
            given[name] = _seconds(text, TIME_OPTIONS[name])
    if samples is not None:
        given["samples"] = float(samples)
    given.update({k: v for k, v in (preset or {}).items() if v is not None})
    if isinstance(sweep_text, str):
        sweep_text = (sweep_text,)
    grid = [sweep_points(spec.params, text, spec.sweep_example) for text in sweep_text or ()]
    own.update({name: f"--sweep {name}" for name, _ in grid})   # a swept value is named by --sweep
    from beltcalc.cli.study import study_inputs

    dists = study_inputs(spec, grid, vary, runs, seed, limits, parquet_path)
    own.update({name: f"--vary {name}" for name, _ in dists})
    if plot_path is not None:
        require_matplotlib()
    scene_def, resolved = spec.resolve(scene, given)
    values = {k: v.value for k, v in resolved.items()}
    if dt is not None:
        values = spec.with_step(values, require_positive("dt", _seconds(dt, "--dt"), "s"))
    if work_precision:
        _work_precision(spec, values, options, as_json, csv_path)
        return
    cfg = SolverConfig(method=method, rtol=rtol, atol=atol, max_events=max_events, error_tol=error_tol,
                       accept_error=accept_error)
    names = {p.name for p in spec.params}
    to_option = lambda n: own.get(n, f"--set {n}") if n in names else option_name(n)  # noqa: E731
    if dists:
        from beltcalc.cli.study import run_tolerance

        run_tolerance(spec, scene_def.title, values, resolved, dists, runs or 1000, seed or 0, limits, cfg, options,
                      as_json, csv_path, parquet_path, plot_path, strict, workers, scheduler, to_option)
        return
    if grid:
        from math import prod

        from beltcalc.cli.study import dask_note
        from beltcalc.sim.study.sweeps import grid_scene

        total = prod(len(p) for _, p in grid)
        dask_note(total, workers, scheduler)
        with progress(total, f"sweep {' x '.join(n for n, _ in grid)}", enabled=not as_json and total > 1) as advance:
            result = grid_scene(spec, values, grid, cfg, lambda n: [advance() for _ in range(n)],
                                workers=workers, scheduler=scheduler, **options)
        for r in result.runs:
            r.warnings = tuple(render(w, to_option) for w in r.warnings)
            r.error = None if r.error is None else render(r.error, to_option)
        _render_sweep(spec, result, scene_def.title, as_json, csv_path, plot_path, strict)
        return
    with spinner(f"simulating {spec.name}", enabled=not as_json):
        out = run_scene(spec, values, cfg, **options)
    out.require_running(accept_error)     # a drive that stalls: one line, exit 1 (marked with --accept-error)
    out.result.warnings[:] = [render(w, to_option) for w in out.result.warnings]
    out.notes[:] = [render(n, to_option) for n in out.notes]
    emit_warnings(out.result.warnings, out.checks, strict)   # with --strict, a failing check ends here
    if csv_path is not None:      # the time series; a run without one (steady state only): its rows
        write_atomic(csv_path, out.result.csv_text() if out.result.t.size else table_csv(
            ["section", "key", "value", "unit"],
            [["/".join(sec.path), row.key, repr(row.value), row.unit] for sec in out.sections for row in sec.rows]))
        wrote(csv_path)
    if plot_path is not None:
        if not out.result.t.size:
            raise click.UsageError("--plot draws a time series; this run has none (--steady-state-only)")
        from beltcalc.plots import scene_figure

        shaded = out.window if out.window is not None else values.get("window")
        write_figure(scene_figure(spec, out, shaded), plot_path)
        wrote(plot_path)
    if as_json:
        click.echo(dumps(dict(out.to_dict(scene_def.title, modes), inputs=inputs_json(spec.params, resolved))))
        return
    _print_sections(scene_def.title, out.sections + [Section(("solved",), "solved", _info_rows(out.result))],
                    [f"method: {out.result.reason}"] + out.notes)
    _print_checks(out.checks)
    if modes:
        _print_modes(out.net)


def _print_checks(checks) -> None:
    """The checks as one table, failing and unverified rows marked; a utilisation past 999 %
    as a factor ("x12.3"), none for a score (the damping fit's R^2: its value is the figure)."""
    from rich.table import Table

    from beltcalc.design.checks import percent

    if not checks:
        return
    t = Table(title="checks", title_justify="left")
    for col in ("check", "value", "limit", "unit", "utilisation", "verdict"):
        t.add_column(col, justify="left" if col in ("check", "unit", "verdict") else "right")
    for c in checks:
        u = c.utilisation
        style = "bold red" if c.verdict == "FAIL" else "bold yellow" if c.verdict == "unverified" else None
        t.add_row(c.name, "-" if c.value is None else format_number(c.value, 4),
                  "-" if c.limit is None else format_number(c.limit, 4), c.unit,
                  "-" if u is None or c.score else percent(u) if u < 1e300 else "unbounded", c.verdict, style=style)
    console().print(t)


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
        worst = "worst figure" if "trajectory_error" in result.extra else "worst speed"
        rows.append(Row("error_estimate", f"error estimate ({worst})", result.error_estimate, result.error_unit,
                        digits=2, note=f"{result.error_signal}, vs {result.error_reference}"))
        traj = result.extra.get("trajectory_error")
        if traj is not None:
            rows.append(Row("trajectory_difference", "trajectories differ by (worst speed)", traj["value"],
                            traj["unit"], digits=2, note=f"{traj['signal']}: the samples of two partitions"))
    return rows


def _print_modes(net) -> None:
    from beltcalc.cli.frequency import print_poles
    from beltcalc.sim.frequency_report import modes

    print_poles(modes(net, shapes=False), "modes of the linear network (motor states included, strands taut): "
                                          "every pole")
    console().print("mode shapes, response, Campbell diagram: beltcalc modes, response, campbell",
                    markup=False, highlight=False)


def _render_sweep(spec: Scene, sweep, title: str, as_json, csv_path, plot_path, strict: bool) -> None:
    """A sweep: warnings (each once, with where it was given), then the CSV, the plot, and
    the JSON or a table of the scene's chosen columns with labels and display units."""
    columns, table = sweep.column_info(), sweep.rows()
    errors = sweep.errors()
    if table and len(errors) >= len(table):          # no run succeeded: no sweep to report
        from beltcalc.errors import InputError

        k, reason = errors[0]
        raise InputError(f"none of the {len(table):,} runs succeeded; the first (run {k}): {reason}")
    emit_warnings(sweep.warnings(), sweep.failed_checks(), strict)
    if strict and errors:
        from beltcalc.errors import InputError

        raise InputError(f"{len(errors)} of {len(table)} runs failed; see the warnings", param="strict")
    if csv_path is not None:
        failed = dict(errors)
        header = [c.key for c in columns] + (["error"] if errors else [])
        write_atomic(csv_path, table_csv(header, (["" if x is None else repr(x) for x in r]
                                                  + ([failed.get(k, "")] if errors else [])
                                                  for k, r in enumerate(table))))
        wrote(csv_path)
    swept = len(sweep.names)
    shown = list(range(swept)) + [i for key in spec.sweep_columns for i, c in enumerate(columns)
                                  if c.key == key][:6]
    if len(shown) == swept:          # a drive file names no columns: the first few it reports
        shown += list(range(swept, min(len(columns), swept + 6)))
    if plot_path is not None:
        from beltcalc.plots import sweep_figure

        write_figure(sweep_figure([columns[i] for i in shown], [[r[i] for i in shown] for r in table], swept),
                     plot_path)
        wrote(plot_path)
    if as_json:
        click.echo(dumps(sweep.to_dict(title)))
        return
    from rich.markup import escape
    from rich.table import Table

    from beltcalc.units import convert

    t = Table(title=f"sweep of {sweep.name}", title_justify="left")
    for i in shown:
        c = columns[i]
        t.add_column(escape(f"{c.label.replace(': ', chr(10))}\n[{unit_label(c.display)}]"), justify="right")
    for r in table:
        t.add_row(*("-" if r[i] is None else format_number(convert(r[i], columns[i].unit, columns[i].display), 4)
                    for i in shown))
    if len(table) > 200:
        console().print(f"({len(table)} rows)", markup=False)
    console().print(t)
    console().print("every column: --json or --csv", markup=False)


def _work_precision(spec: Scene, values: dict, options: dict, as_json: bool, csv_path) -> None:
    from beltcalc.sim.study.workprecision import count_runs, scene_work_precision

    with progress(count_runs(), "work-precision", enabled=not as_json) as advance:
        wp = scene_work_precision(spec, values, advance, **options)
    header = ["method", "rtol", "wall_time_s", "rhs_calls", "steps", f"max_error_{wp.signal}", "note"]
    table = [[r.method, r.rtol, r.wall_time, r.rhs_calls, r.steps, r.error, r.note] for r in wp.rows]
    if csv_path is not None:
        write_atomic(csv_path, table_csv(header, table))
    if as_json:
        click.echo(dumps({"columns": header, "rows": table, "samples": wp.samples, "t_end": wp.t_end}))
        return
    _print_work_precision(wp.rows, f"work-precision: {spec.name} scene, {wp.samples} samples over {wp.t_end:g} s, "
                                   f"error of {wp.signal} against exact")


def _print_work_precision(rows, title: str) -> None:
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


LIST_PARAMS = "beltcalc.list_params"     # ctx.meta key: --list-params was given


# --list-params' "from" of a value neither the scene (or drive) file nor the command line gives:
# the scene does without it (its "what" says how), or the command's own default applies
NOT_SET = "not set"


def _list_params(spec: Scene, scene: str, as_json: bool = False) -> None:
    """Every --set name of the scene (or drive file) with its unit, its value in the scene
    file and why, and what it is: one table on stdout (with ``as_json`` one JSON object,
    ``{"parameters": {name: {"text", "value", "unit", "origin", "help"}}}``). A value the
    file does not set is "-", from "not set"."""
    from rich.markup import escape
    from rich.table import Table

    _, resolved = spec.resolve(scene)
    if as_json:
        echo = inputs_json(spec.params, resolved)
        helps = {p.name: p.help for p in spec.params}
        click.echo(dumps({"scene": scene, "parameters": {k: dict(v, help=helps.get(k, "")) for k, v in echo.items()},
                          "warnings": []}))
        return
    t = Table(title=escape(f"--set NAME=QUANTITY: the values of {scene}"), title_justify="left")
    for col in ("name", "unit", "value", "what", "from"):
        t.add_column(col, overflow="fold")
    for p in spec.params:
        r = resolved.get(p.name)
        unit = {"int": "whole number", None: "name", "": "number"}.get(p.unit, p.unit)
        t.add_row(p.name, escape(unit.replace("|", " or ")), escape(r.text if r is not None else "-"),
                  escape(p.help), escape(r.origin.removeprefix("scene: ") if r is not None else NOT_SET))
    console(width=140).print(t)


def common_options(spec: Scene | None):
    """The options every simulate command has (``--t-end``, ``--samples``, ``--window`` for a
    timed scene; ``spec`` None: a drive file, named by its argument, not ``--scene``)."""
    def decorate(func):
        opts = [
            click.option("--set", "assignments", multiple=True, metavar="NAME=QUANTITY",
                         help="Change a value, e.g. --set NAME=QUANTITY (repeatable)"
                              + ("; a drive file's values are ELEMENT.KEY" if spec is None else "")
                              + "; --list-params lists every NAME with its unit and value."),
            click.option("--list-params", is_flag=True, expose_value=False,
                         callback=lambda ctx, _p, v: ctx.meta.__setitem__(LIST_PARAMS, True) if v else None,
                         help="List every --set NAME with its unit, its value and where it comes from, and stop."),
        ]
        if spec is not None:
            opts.insert(0, click.option("--scene", default=spec.file, show_default=True,
                                        help="Built-in scene or a scene .toml file."))
        if spec is None or spec.timed:
            opts += [click.option("--t-end", type=str, default=None, help="Simulated time [default: the scene's]."),
                     click.option("--samples", type=click.IntRange(2, 10_000_000), default=None, help="Output samples."),
                     click.option("--window", type=str, default=None,
                                  help="Start of the steady window [default: the scene's].")]
        opts += [
            click.option("--dt", type=str, default=None, help="Output step instead of --samples, e.g. 0.1ms."),
            click.option("--method", type=click.Choice(NAMES), default="auto", show_default=True),
            click.option("--rtol", type=Tolerance(1e-14, 1, min_open=True), default=1e-8, show_default=True),
            click.option("--atol", type=Tolerance(1e-16, 1, min_open=True), default=1e-10, show_default=True),
            click.option("--max-events", type=click.IntRange(1, 10_000_000), default=20_000, show_default=True,
                         help="Bound on strand switches (a chain chattering near zero tension)."),
            click.option("--error-tol", type=Tolerance(0, 1, min_open=True, max_open=True), default=1e-6,
                         show_default=True,
                         help="Largest error estimate accepted, relative to the signal's scale; above it auto "
                              "refines, then falls back to Radau, else the run fails."),
            click.option("--accept-error", is_flag=True,
                         help="Print a result whose error estimate exceeds --error-tol (marked) instead of failing."),
            click.option("--strict", is_flag=True,
                         help="Exit 1 (and write no file) when a check fails: strand strength, motor breakdown, "
                              "the error estimate, the steady window, ..."),
            click.option("--modes", is_flag=True,
                         help="Also print every pole of the linear network: oscillatory modes (frequency, damping "
                              "ratio), real poles (time constant), rigid-body modes."),
            click.option("--sweep", "sweep_text", multiple=True, metavar="NAME=START:STOP:N",
                         help="Sweep a value (a scene parameter, a drive file's ELEMENT.KEY); repeat it for a grid "
                              "(the product)."),
            click.option("--vary", "vary", multiple=True, metavar="NAME=DIST(...)",
                         help="A tolerance study: draw NAME from normal(MEAN,SD or P%), uniform(LOW,HIGH) or "
                              "triangular(LOW,MODE,HIGH), values with units as --set (repeatable)."),
            click.option("--runs", type=click.IntRange(1, 10_000_000), default=None,
                         help="Runs of a --vary study [default: 1000]."),
            click.option("--seed", type=click.IntRange(0), default=None, help="Seed of a --vary study [default: 0]."),
            click.option("--limit", "limits", multiple=True, metavar="KEY>=VALUE",
                         help="A --vary study counts the runs that fail it (KEY a column, VALUE with its unit; "
                              ">= or <=), with a 95% confidence interval (repeatable)."),
            click.option("--parquet", "parquet_path", type=OutputPath(), default=None,
                         help="Write a --vary study's rows as Parquet (needs pyarrow)."),
            click.option("--workers", type=click.IntRange(1, 1024), default=None,
                         help="Processes of the local Dask cluster of a study over 200 runs; 1: in this "
                              "process [default: the CPU count, where the study's first runs, timed here, show "
                              "that the rest would take longer than the cluster's start]."),
            click.option("--scheduler", default=None, envvar="DASK_SCHEDULER_ADDRESS", metavar="tcp://HOST:PORT",
                         help="Run a study on an existing Dask cluster [default: $DASK_SCHEDULER_ADDRESS]."),
            click.option("--plot", "plot_path", type=OutputPath(), default=None,
                         help="Write a plot: PNG, PDF or SVG, by the file's suffix (needs matplotlib)."),
            click.option("--work-precision", is_flag=True,
                         help="Run every method at tolerances 1e-3..1e-10 and tabulate wall time against error."),
            output_options,
        ]
        for opt in reversed(opts):
            func = opt(func)
        return func
    return decorate



class _SimulateGroup(click.Group):
    """The simulate commands, each built when it runs: a scene's command needs the scene
    (its parameters give the options), and ``simulate sewing`` imports no other scene."""

    def list_commands(self, ctx):
        return sorted(set(self.commands) | set(_BUILDERS))

    def get_command(self, ctx, name):
        if name not in self.commands and name in _BUILDERS:
            self.add_command(_BUILDERS[name](), name)
        return self.commands.get(name)


@click.group(cls=_SimulateGroup, context_settings={"help_option_names": ["-h", "--help"]})
def simulate():
    """Time simulation of drive trains (every scene runs on the one ODE core)."""


def _sewing_command() -> click.Command:
    from beltcalc.sim.scenes import SCENES

    @click.command("sewing")
    @common_options(SCENES["sewing"])
    @click.option("--angle-loads", is_flag=True, help="Loads follow the shaft angle, sin(phi), not sin(w t): nonlinear.")
    @click.option("--steady-state-only", is_flag=True,
                  help="Only the exact periodic steady state, no time simulation (under 1 ms a point in a sweep).")
    def sewing(angle_loads, steady_state_only, **kw):
        """The sewing-machine drive of Mamatova et al. (2016): speed, acceleration and torque of the
        main and bottom shafts over a steady window of whole load periods, and in the exact
        periodic steady state; how it was solved. Sweep e.g. --sweep C4=50N*m/rad:310N*m/rad:14 (the paper's
        [M16 Fig. 5]), with --steady-state-only for the exact steady state alone."""
        run_command(SCENES["sewing"], options={"angle_loads": angle_loads, "steady_state_only": steady_state_only},
                    **kw)

    return sewing


def _roller_table_command() -> click.Command:
    from beltcalc.sim.scenes import SCENES

    @click.command("roller-table")
    @common_options(SCENES["roller-table"])
    def roller_table(**kw):
        """The roller-table drive with chain transmission of Rusek & Popenda: induction motor,
        coupling, two-stage gear, clutch, tension-only chain strands and rollers loaded at both
        ends. Per roller speed and end torques, per strand force and time slack, motor torque and
        start-up time. Sweep e.g. --sweep rollers=1:20:20 or --sweep pretension=0N:600N:7."""
        run_command(SCENES["roller-table"], options={}, **kw)

    return roller_table


def _linear_axis_command() -> click.Command:
    from beltcalc.sim.scenes import SCENES

    @click.command("linear-axis")
    @common_options(SCENES["linear-axis"])
    @click.option("--belt-model", type=click.Choice(["substitute", "chain"]), default=None,
                  help="substitute: [W21 eq. 5-9], one spring-damper-mass; chain: [W21 eq. 1], z - 1 units "
                       "[default: the scene's].")
    @click.option("--drive", type=click.Choice(["prescribed", "speed-loop"]), default=None,
                  help="prescribed: the motor follows the move; speed-loop: feed-forward + speed gain [default: the "
                       "scene's].")
    @click.option("--substitute-mass-model", type=click.Choice(["eq7", "rayleigh"]), default="eq7", show_default=True,
                  help="m_TB by [W21 eq. 7] or Rayleigh's m/3.")
    @click.option("--motor", "motor_name", default=None, help="Motor to simulate [default: motor-size's choice].")
    @catalog_option
    def linear_axis(belt_model, drive, substitute_mass_model, motor_name, catalog_paths, **kw):
        """A timing-belt linear axis as a dynamic model (Wojtkowiak et al. 2021, WDU axis): the belt
        as the substitute spring-damper-mass of `beltcalc tension` (or the chain of [W21 eq. 1]),
        the motor on the move of `beltcalc motor-size`. Belt force against the pretension,
        following error, residual vibration, motor torque against the rigid answer."""
        run_command(SCENES["linear-axis"], preset={"belt_model": belt_model, "drive": drive},
                    options={"substitute_mass_model": substitute_mass_model, "motor": motor_name,
                             "catalog": catalog_paths}, **kw)

    return linear_axis


@simulate.command("drive")
@click.argument("file", metavar="FILE", type=DriveRef())
@common_options(None)
@catalog_option
def drive(file, catalog_paths, **kw):
    """Your own drive train from a drive file (TOML; docs/drive_files.md), or a built-in one
    by name (conveyor, sewing, roller_table, linear_axis, linear_axis_moving, friswell_5_disks, friswell_geared;
    catalogs/drives/): every node's speed, every
    coupling's and shaft's torque, every strand's extremes, slack time and safety, every
    motor's torque. Any value is --set ELEMENT.KEY=QUANTITY, e.g. --set upper.pretension=300N,
    or swept: --sweep upper.pretension=200N:600N:5."""
    from beltcalc.sim.scenes.drive import drive_scene

    catalog = None
    if catalog_paths:
        from beltcalc.data.catalogs import load_catalog

        catalog = load_catalog(catalog_paths)
    spec = drive_scene(file, catalog)
    run_command(spec, scene=spec.file, options={}, **kw)


# the built-in scenes' commands: name -> the function that builds it (on first use)
_BUILDERS = {"sewing": _sewing_command, "roller-table": _roller_table_command, "linear-axis": _linear_axis_command}
