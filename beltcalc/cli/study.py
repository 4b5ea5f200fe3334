"""The tolerance studies of ``beltcalc simulate ... --vary``: read the study's options, run
it (:mod:`beltcalc.sim.study.tolerance`), stream its rows to ``--csv``/``--parquet`` and render its
summary as tables, ``--json`` or ``--plot``. Shared by every simulate command through
:func:`beltcalc.cli.simulate.run_command`."""

from __future__ import annotations

import click

from beltcalc.errors import InputError, OutputError, UsageError


def study_inputs(spec, grid, vary, runs, seed, limits, parquet_path) -> list:
    """Check the study options together; returns ``[(name, Distribution)]`` of ``--vary``."""
    from math import prod

    if not vary:
        for given, option in ((runs, "--runs"), (seed, "--seed"), (limits, "--limit"), (parquet_path, "--parquet")):
            if given:
                raise UsageError(f"{option} goes with --vary (a tolerance study)", param="vary")
        if not grid:                    # a single run: the study module is not loaded (start-up)
            return []
    from beltcalc.sim.study.plan import MAX_GRID, parse_vary

    names = [n for n, _ in grid]
    if len(set(names)) < len(names):
        raise UsageError(f"{', '.join(n for n in names if names.count(n) > 1)} swept twice", param="sweep")
    if grid and prod(len(p) for _, p in grid) > MAX_GRID:
        raise UsageError(f"the grid has {prod(len(p) for _, p in grid):,} points; at most {MAX_GRID:,} "
                         "(its rows are kept for the table): fewer points, or a --vary study", param="sweep")
    dists = [parse_vary(spec.params, text) for text in vary]
    varied = [n for n, _ in dists]
    if len(set(varied)) < len(varied):
        raise UsageError(f"{', '.join(n for n in varied if varied.count(n) > 1)} varied twice", param="vary")
    if dists and grid:
        raise UsageError("--vary and --sweep do not go together: a tolerance study or a grid", param="vary")
    if parquet_path is not None:
        try:
            __import__("pyarrow")
        except ImportError:
            raise OutputError("--parquet needs pyarrow: pip install 'beltcalc[data]'") from None
    for text in limits:
        from beltcalc.sim.study.tolerance import split_limit

        split_limit(text)                  # the form now; the key and unit after the nominal run
    return dists


def dask_note(n_runs: int, workers, scheduler) -> None:
    """Say on stderr that a study that would run on Dask runs in this process (dask missing)."""
    import os

    from beltcalc.sim.study.execution import DASK_MIN_RUNS, dask_available

    if scheduler is None and (workers or os.cpu_count() or 1) > 1 and n_runs > DASK_MIN_RUNS \
            and not dask_available():
        click.echo(f'note: dask is not installed: the {n_runs:,} runs go in this process, one at a time '
                   '(pip install "beltcalc[dist]" for a local cluster of processes)', err=True)


def _key(name: str, unit: str) -> str:
    from beltcalc.sim.result import unit_tag

    return name if unit in ("1", "") else f"{name}_{unit_tag(unit)}"


def run_tolerance(spec, title, values, resolved, dists, runs, seed, limit_texts, cfg, options, as_json, csv_path,
                  parquet_path, plot_path, strict, workers, scheduler, to_option) -> None:
    """A tolerance study: the nominal run (its columns; an error there is the command's),
    then ``runs`` draws, rows streamed to the files, the summary rendered."""
    import time
    from dataclasses import replace

    from beltcalc.cli.output import dumps, emit_warnings, progress, require_matplotlib, write_atomic, write_figure, wrote
    from beltcalc.errors import render
    from beltcalc.sim.scenes.base import run_scene
    from beltcalc.sim.study.plan import Plan
    from beltcalc.sim.study.tolerance import parse_limit, tolerance_study

    if plot_path is not None:
        require_matplotlib()
    names = tuple(n for n, _ in dists)
    t0 = time.perf_counter()
    nominal = run_scene(spec, values, cfg, **options)
    run_cost = time.perf_counter() - t0          # sizes the chunks (beltcalc.sim.study.plan.chunk_size)
    columns = {c.key: replace(c, value=None) for c in nominal.column_rows()}
    nominal_values = {c.key: c.value for c in nominal.column_rows()}
    limits = [parse_limit(text, columns) for text in limit_texts]
    plan = Plan(spec, dict(values), cfg, names, dists=tuple(d for _, d in dists), runs=runs, seed=seed,
                options=dict(options), run_cost=run_cost)
    input_keys = [_key(n, d.unit) for n, d in dists]
    header = input_keys + list(columns) + ["failed_checks", "warnings", "error"]
    dask_note(runs, workers, scheduler)
    state: dict = {}

    def body(csv_tmp=None, pq_tmp=None):
        sinks, send = [], []
        csv_fh = None
        if csv_tmp is not None:           # the rows come as CSV lines, formatted where they ran
            import csv

            csv_fh = open(csv_tmp, "w", newline="", encoding="utf-8")
            csv.writer(csv_fh, lineterminator="\n").writerow(header)
            sinks.append(lambda chunk: csv_fh.write(chunk.csv))
            send.append("csv")
        pq = None
        if pq_tmp is not None:
            pq = _ParquetSink(pq_tmp, input_keys, list(columns))
            sinks.append(pq.write)
            send.append("table")
        try:
            with progress(runs, f"study of {', '.join(names)}", enabled=not as_json and runs > 1) as advance:
                summary, how = tolerance_study(plan, columns, limits, (lambda ch: [f(ch) for f in sinks]) if sinks
                                               else None, lambda n: [advance() for _ in range(n)], workers, scheduler,
                                               send=send)
        finally:
            if csv_fh is not None:
                csv_fh.close()
            if pq is not None:
                pq.close()
        if summary.runs and summary.errors >= summary.runs:      # no run succeeded: no study to report
            first = ""
            if summary.reasons:
                reason, (_, run) = summary.reasons[0]
                first = f"; the first (run {run}): {_reason(reason, render, to_option, names)}"
            raise InputError(f"none of the {summary.runs:,} runs succeeded{first}")
        warnings = _warnings(summary, render, to_option, names)
        emit_warnings(warnings, [c for _, c in summary.checks.values()], strict)
        if strict:
            bad = [lim for lim in summary.limits if lim["failed"]]
            if summary.errors or bad:
                what = ([f"{summary.errors} of {summary.runs} runs failed"] if summary.errors else []) + \
                       [f"{lim['limit'].text} fails in {lim['failed']} runs" for lim in bad]
                raise InputError(f"{'; '.join(what)}; see the warnings", param="strict")
        state.update(summary=summary, how=how, warnings=warnings)

    files = [(p, kind) for p, kind in ((csv_path, "csv"), (parquet_path, "parquet")) if p is not None]

    def nest(k, tmps):
        if k == len(files):
            body(**tmps)
            return
        path, kind = files[k]
        write_atomic(path, lambda tmp: nest(k + 1, dict(tmps, **{f"{kind[:3] if kind == 'csv' else 'pq'}_tmp": tmp})))

    nest(0, {})
    for path, _ in files:
        wrote(path)
    summary, how, warnings = state["summary"], state["how"], state["warnings"]
    obj = _to_dict(title, spec, resolved, dists, input_keys, columns, nominal_values, summary, runs, seed, how,
                   warnings)
    if plot_path is not None:
        from beltcalc.plots import study_figure

        write_figure(study_figure(summary, columns, limits, len(dists), spec.sweep_columns), plot_path)
        wrote(plot_path)
    if as_json:
        from beltcalc.cli.output import inputs_json

        inputs = inputs_json(spec.params, resolved)
        for n, d in dists:                 # a varied input: its distribution, not one value
            inputs[n] = {"text": d.text.partition("=")[2], "value": d.mean, "unit": d.unit, "origin": "vary"}
        click.echo(dumps(dict(obj, inputs=inputs)))
        return
    _print(obj, summary, columns, dists, how.text())


class _ParquetSink:
    """Rows to a Parquet file, one row group per chunk (constant memory)."""

    def __init__(self, path, input_keys, keys):
        import pyarrow as pa
        import pyarrow.parquet as pq

        self.pa, self.input_keys, self.keys = pa, input_keys, keys
        self.schema = pa.schema([(k, pa.float64()) for k in input_keys + keys]
                                + [("failed_checks", pa.string()), ("warnings", pa.int64()), ("error", pa.string())])
        self.writer = pq.ParquetWriter(str(path), self.schema)

    def write(self, chunk) -> None:
        data = dict(chunk.table)
        for i, k in enumerate(self.input_keys):
            data[k] = data.pop(f"input_{i}")
        self.writer.write_table(self.pa.table({k: data[k] for k in self.schema.names}, schema=self.schema))

    def close(self) -> None:
        self.writer.close()


def _warnings(summary, render, to_option, names) -> list[str]:
    """Each distinct warning once with how many runs gave it; each failure reason; each
    limit that some runs fail."""
    n = summary.runs
    out = []
    for w, k in summary.warnings.items():
        text = render(w, to_option)
        out.append(text if k == n else f"{text} (in {k:,} of {n:,} runs)")
    if summary.more_warnings:
        out.append(f"{summary.more_warnings:,} more warnings of other texts (not kept)")
    for reason, (k, first) in summary.reasons:
        out.append(f"{k:,} of {n:,} runs failed (first: run {first}): {_reason(reason, render, to_option, names)}")
    if summary.more_reasons:
        out.append(f"{summary.more_reasons:,} more runs failed for other reasons (not kept)")
    for lim in summary.limits:
        if lim["failed"]:
            lo, hi = lim["ci95"]
            out.append(f"limit {lim['limit'].text} fails in {lim['failed']:,} of {lim['evaluated']:,} runs "
                       f"({lim['fraction']:.3%}; 95% confidence {lo:.3%} to {hi:.3%})")
    if summary.extra_keys:
        out.append(f"some runs report values the nominal run does not ({', '.join(summary.extra_keys[:5])}); "
                   "they are left out of the summary")
    return out


def _reason(reason: str, render, to_option, names) -> str:
    name, sep, rest = reason.partition(": ")
    if sep and name in names:
        return f"--vary {name}: {render(rest, to_option)}"
    return render(reason, to_option)


def _q(value, unit):
    return {"value": value, "unit": unit or "1"}


def _to_dict(title, spec, resolved, dists, input_keys, columns, nominal, summary, runs, seed, how, warnings) -> dict:
    """The study as one JSON-ready object (SI; values as ``{"value", "unit"}``)."""
    from beltcalc.sim.study.fold import PERCENTILES, RESERVOIR

    outputs = {}
    for key, col in columns.items():
        e = summary.outputs.get(key, {"n": 0})
        u = col.unit or "1"
        entry = {"label": col.label, "unit": u, "n": e["n"], "nominal": _q(nominal.get(key), u)}
        for stat in ("mean", "sd", *(f"p{p}" for p in PERCENTILES), "min", "max"):
            entry[stat] = _q(e.get(stat), u)
        entry["influence"] = [{"input": i["input"], "src": _q(i["src"], "1"), "spearman": _q(i["spearman"], "1")}
                              for i in e.get("influence", [])]
        entry["r2"] = _q(e.get("r2"), "1")
        outputs[key] = entry
    limits = [{"key": lim["limit"].key, "op": lim["limit"].op, "limit": _q(lim["limit"].bound, lim["limit"].unit),
               "text": lim["limit"].text, "evaluated": lim["evaluated"], "failed": lim["failed"],
               "fraction": _q(lim["fraction"], "1"),
               "ci95": [_q(lim["ci95"][0], "1"), _q(lim["ci95"][1], "1")]} for lim in summary.limits]
    return {
        "scene": title, "study": "tolerance", "runs": summary.runs, "seed": seed, "execution": how.how,
        "execution_profile": how.to_dict(),
        "propagation": summary.propagation,
        "parameters": [{"name": n, "unit": d.unit, "key": k, "distribution": d.to_dict()}
                       for (n, d), k in zip(dists, input_keys)],
        "columns": [{"key": k, "label": n, "unit": d.unit} for (n, d), k in zip(dists, input_keys)]
        + [{"key": c.key, "label": c.label, "unit": c.unit or "1"} for c in columns.values()],
        "outputs": outputs,
        "reservoir": {"rows": summary.kept, "runs": summary.runs,
                      "note": "mean, sd, min, max and the regression coefficients (src) are exact over every run; "
                              "percentiles and rank correlations (spearman) "
                              + ("are over every run" if summary.kept >= summary.runs else
                                 f"come from {summary.kept:,} of the {summary.runs:,} runs drawn uniformly")
                              + f" (a reservoir of {RESERVOIR:,} rows)"},
        "limits": limits,
        "failures": {"runs": summary.errors,
                     "reasons": [{"reason": r, "runs": k, "first_run": first} for r, (k, first) in summary.reasons]},
        "failed_checks": [{"key": key, "name": c.name, "runs": k} for key, (k, c) in summary.checks.items()],
        "warnings": warnings,
    }


def _fmt(value, col) -> str:
    from beltcalc.cli.output import format_number
    from beltcalc.units import convert

    if value is None:
        return "-"
    unit = col.unit or "1"
    shown = col.display or unit
    v = value if shown == unit or unit == "1" else convert(value, unit, shown)
    return format_number(v, 4)


def _print(obj, summary, columns, dists, execution: str) -> None:
    from rich.markup import escape
    from rich.table import Table

    from beltcalc.cli.output import console, format_number
    from beltcalc.report import unit_label
    from beltcalc.sim.study.fold import PERCENTILES

    out = console(200)
    t = Table(title=f"tolerance study of {obj['scene']}: {summary.runs:,} runs, seed {obj['seed']} ({obj['execution']})",
              title_justify="left")
    for col in ("input", "distribution", "mean", "sd", "unit"):
        t.add_column(col, justify="right" if col in ("mean", "sd") else "left")
    for n, d in dists:
        t.add_row(n, escape(d.text.partition("=")[2]), format_number(d.mean, 4), format_number(d.sd, 4),
                  unit_label(d.unit))
    out.print(t)
    t = Table(title="outputs", title_justify="left")
    t.add_column("output [unit]")           # a text wraps; a number never (cli.output.fit_table)
    for h in ("mean", "sd", *(f"{p}%" for p in PERCENTILES), "min", "max"):
        t.add_column(h, justify="right", no_wrap=True)
    t.add_column("moved most by: src / spearman")
    for key, col in columns.items():
        e = summary.outputs.get(key, {})
        infl = [i for i in e.get("influence", []) if i["src"] is not None or i["spearman"] is not None][:1]
        moved = ", ".join(f"{i['input']} {_num(i['src'])} / {_num(i['spearman'])}" for i in infl)
        t.add_row(escape(f"{col.label} [{unit_label(col.display or col.unit)}]"),
                  *(_fmt(e.get(s), col) for s in ("mean", "sd", *(f"p{p}" for p in PERCENTILES), "min", "max")),
                  escape(moved or "-"))
    out.print(t)
    if summary.limits:
        t = Table(title="limits", title_justify="left")
        for h in ("limit", "failed", "of runs", "fraction", "95% confidence"):
            t.add_column(h, justify="left" if h == "limit" else "right")
        for lim in summary.limits:
            lo, hi = lim["ci95"]
            t.add_row(escape(lim["limit"].text), f"{lim['failed']:,}", f"{lim['evaluated']:,}",
                      "-" if lim["fraction"] is None else f"{lim['fraction']:.3%}",
                      "-" if lo is None else f"{lo:.3%} .. {hi:.3%}")
        out.print(t)
    notes = [f"rows: {obj['propagation']}",
             f"failed runs: {summary.errors:,} of {summary.runs:,} (each a row with its reason; see the warnings)"
             if summary.errors else f"failed runs: none of {summary.runs:,}", obj["reservoir"]["note"],
             "src: standardised regression coefficient of a linear fit over every run; spearman: rank correlation",
             f"execution: {execution}", "every row: --csv or --parquet; every statistic: --json"]
    for note in notes:
        out.print(note, markup=False, highlight=False)


def _num(x) -> str:
    return "-" if x is None else f"{x:+.2f}"
