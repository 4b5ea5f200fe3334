"""Rendering of results: rich tables on stdout, JSON, CSV (written by :mod:`beltcalc.cli.writer`).

A result is a list of :class:`~beltcalc.report.Row` (SI value, SI unit, display unit),
grouped in sections. The same rows give the table, the JSON object and the CSV file, so
the three never disagree.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import time
from contextlib import contextmanager
from functools import cache
from typing import Callable, Iterable, Iterator, Sequence

import click

from beltcalc.cli.writer import STALE_TMP_AGE, announce, write_file
from beltcalc.errors import OutputError
from beltcalc.report import Row, format_number  # noqa: F401  (format_number: the CLI's too)

write_atomic = write_file     # the name the commands use: every file goes through the one writer


def require_matplotlib() -> None:
    """Fail early, before any work, when --plot is asked for without matplotlib installed."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise OutputError("--plot needs matplotlib: pip install 'beltcalc[plot]'") from None


def plot_format(path) -> str:
    """The format a plot is written in to ``path``: the one its suffix names (``.png``,
    ``.pdf``, ``.svg``, in any case); a file written in place with no suffix (a device, a
    FIFO: ``/dev/stdout``; :func:`beltcalc.cli.writer.resolve_target`) gets PNG. Another
    suffix, or none on a file, is a ``ValueError`` saying what is allowed
    (:func:`beltcalc.plots.plot_format`).

    >>> plot_format("out.PDF"), plot_format("a/b.svg")
    ('pdf', 'svg')
    >>> plot_format("out.jpg")
    Traceback (most recent call last):
    ...
    ValueError: 'out.jpg': a plot is written as .png, .pdf or .svg (the suffix names the format), not '.jpg'
    """
    from pathlib import Path

    from beltcalc.cli.writer import resolve_target
    from beltcalc.plots import plot_format as named_format

    in_place = False
    if not Path(path).suffix:
        try:
            in_place = resolve_target(path).how == "in place"
        except (OutputError, OSError):
            pass
    try:
        return named_format(path, in_place)
    except OutputError as exc:
        raise ValueError(exc.message) from None


def write_figure(fig, path, dpi: int = 110) -> None:
    """Write the matplotlib figure ``fig`` to ``path`` in the format its suffix names
    (:func:`plot_format`), through the one writer (atomically, once the result is known
    good) (:func:`beltcalc.plots.save_figure`)."""
    from beltcalc.plots import save_figure

    save_figure(fig, path, dpi, fmt=plot_format(path), write=write_atomic)


def display_value(row: Row) -> str:
    """The row's value in its display unit, ``digits`` significant digits; a text (an input
    as it was written, with its unit) as it is."""
    from beltcalc.units import convert

    if isinstance(row.value, str):
        return row.value
    if row.value is None or (isinstance(row.value, float) and math.isnan(row.value)):
        return "-"
    if _factor(row):        # past 999 %: the factor, "x12.3" (docs/output.md)
        from beltcalc.design.checks import percent

        return percent(row.value)
    si = "" if row.unit == "1" else row.unit
    shown = row.display if row.display else si
    value = convert(row.value, si, shown) if shown != si else row.value
    return format_number(value, row.digits)


def _factor(row: Row) -> bool:
    """Whether ``row`` is a percentage past 999 %, shown as a factor ("x12.3") instead."""
    from beltcalc.design.checks import PERCENT_MAX

    value = row.value
    if row.display != "percent" or isinstance(value, (str, bool)) or value is None or not math.isfinite(value):
        return False
    shown = value * 100
    return not math.isfinite(shown) or abs(float(format_number(shown, row.digits))) > PERCENT_MAX


def display_unit(row: Row) -> str:
    unit = row.display or row.unit
    if unit == "percent":
        return "" if _factor(row) else "%"
    return "" if unit in ("1", "") else unit.replace("**", "^").replace("*", " ")


def console(width: int = 110):
    """A rich console on stdout at least ``width`` columns wide (pipes default to 80).

    Text is shown as written: no ``:name:`` emoji codes replaced (a name or a file name with
    colons stays as typed; and each table cell skips the look-up, which also spares loading
    rich's emoji table)."""
    out = _console_class()(soft_wrap=False, emoji=False)
    out.width = max(out.width, width)
    return out


@cache
def _console_class():
    """rich's Console, whose ``print`` of a table never cuts a number (:func:`fit_table`): a
    table too wide for the console is printed wider (a terminal then wraps its lines)."""
    from rich.console import Console
    from rich.table import Table

    class FittingConsole(Console):
        def print(self, *objects, **kwargs):
            need = max((fit_table(self, o) for o in objects if isinstance(o, Table)), default=0)
            if need <= self.width:
                return super().print(*objects, **kwargs)
            shown = self.width
            self.width = need
            try:
                return super().print(*objects, **kwargs)
            finally:
                self.width = shown

    return FittingConsole


# a table cell that is a number as format_number and the commands write it: 3.006e-05, -0.5,
# 1,234, 40%, 12.3 %, x12.3, +0.53, or "-" (none)
_NUMBER_CELL = re.compile(r"[-+]?(?:\d[\d,]*(?:\.\d*)?|\.\d+)(?:e[-+]?\d+)?(?: ?%)?|x\d+(?:\.\d+)?|-",
                          re.IGNORECASE)


def _plain(cell) -> str:
    from rich.errors import MarkupError
    from rich.text import Text

    if isinstance(cell, Text):
        return cell.plain
    if isinstance(cell, str):
        try:
            return Text.from_markup(cell).plain
        except MarkupError:
            return cell
    return ""


def fit_table(out, table) -> int:
    """Make the rich ``table`` keep every number whole, and return the console width it needs.

    A column whose every cell is a number (:data:`_NUMBER_CELL`) is never wrapped; the
    others wrap at spaces and fold, never crop. rich narrows a table too wide for the console
    by taking width from its widest wrapping columns first (``Table._collapse_widths``); the
    width returned leaves each wrapping column at least its longest word, so a number inside
    a text (``1.2% .. 3.4%``) stays whole too.

    >>> from rich.table import Table
    >>> t = Table()
    >>> t.add_column("value"); t.add_column("note")
    >>> t.add_row("3.006e-05", "a long note " * 4)
    >>> out = console()
    >>> fit_table(out, t), t.columns[0].no_wrap, t.columns[1].no_wrap   # 9 + 2 + (4 + 2 + 1) + 3 borders
    (21, True, False)
    """
    options = out.options.update_width(1_000_000)
    fixed, wrapping = 0, []
    for column in table.columns:
        cells = [_plain(c).strip() for c in column.cells]
        if any(cells) and all(_NUMBER_CELL.fullmatch(c) for c in cells if c):
            column.no_wrap = True
        elif not column.no_wrap:
            column.overflow = "fold"
        # rich's own measure of a column (padding included): (longest word, whole line)
        low, high = table._measure_column(out, options, column)
        if column.no_wrap:
            fixed += high
        else:
            wrapping.append((low, high))
    level = max((low for low, _ in wrapping), default=0)
    # + 1 a wrapping column: rich splits a reduction between equal columns in whole cells
    return fixed + sum(min(high, level) + 1 for _, high in wrapping) + table._extra_width


def print_table(title: str, sections: Sequence[tuple[str, Sequence[Row]]],
                notes: Iterable[str] = ()) -> None:
    """A rich table on stdout: one block per section, quantity / value / unit / note."""
    from rich.table import Table

    table = Table(title=title, title_justify="left", show_lines=False)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_column("unit")
    table.add_column("note", overflow="fold")
    for i, (name, rows) in enumerate(sections):
        table.add_row(f"[bold]{name}[/bold]", "", "", "", end_section=False)
        for j, row in enumerate(rows):
            table.add_row("  " + row.label, display_value(row), display_unit(row), no_inf(row.note),
                          end_section=(j == len(rows) - 1 and i < len(sections) - 1))
    out = console()
    out.print(table)
    for note in notes:
        out.print(no_inf(note), highlight=False, markup=False)


def unit_text(unit: str) -> str:
    """A unit spelled the one way the JSON uses: products with ``*`` (``N*s/m``, ``kg*m^2``).

    >>> unit_text("N s/m"), unit_text("rad/s/(N m)"), unit_text("1")
    ('N*s/m', 'rad/s/(N*m)', '1')
    """
    return " ".join(unit.split()).replace(" ", "*")


_NOT_FINITE_WORD = re.compile(r"(?<![\w.'\"])([-+]?)(inf(?:inity)?|nan)(?![\w'\"])", re.IGNORECASE)


def no_inf(text: str) -> str:
    """``text`` (a message, a warning) with a figure that is not finite, as Python formats it,
    said in words: no ``inf`` or ``nan`` printed. What a user typed, quoted, stays as typed.

    >>> no_inf("an input at inf rad/s turns -inf rad; 'inf kg' is refused; nan N; info")
    "an input at over 1e308 rad/s turns below -1e308 rad; 'inf kg' is refused; not a number N; info"
    """
    def words(m) -> str:
        if m.group(2).lower() == "nan":
            return "not a number"
        return "below -1e308" if m.group(1) == "-" else "over 1e308"
    return _NOT_FINITE_WORD.sub(words, text)


def finite(obj):
    """``obj`` with every NaN or infinity replaced by None (JSON has neither), recursively;
    every ``unit`` entry spelled by :func:`unit_text`; no ``inf`` in a warning's text."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        if isinstance(obj.get("unit"), str):
            obj = {**obj, "unit": unit_text(obj["unit"])}
        if isinstance(obj.get("warnings"), (list, tuple)):
            obj = {**obj, "warnings": [no_inf(w) if isinstance(w, str) else w for w in obj["warnings"]]}
        return {k: finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite(v) for v in obj]
    return obj


def dumps(obj) -> str:
    """Strict JSON text of ``obj``, indented; NaN and infinity become null."""
    return json.dumps(finite(obj), indent=2, allow_nan=False)


def rows_json(rows: Iterable[Row], **extra) -> str:
    """One JSON object: ``{key: {"value": SI float, "unit": SI unit}, **extra}``."""
    obj = {r.key: {"value": r.value, "unit": r.unit} for r in rows}
    obj.update(extra)
    return dumps(obj)


def inputs_json(params, resolved) -> dict:
    """Every input of the run with its value in SI, its unit, the text it was read from and
    its origin: ``"option"`` (given on the command line) or ``"scene: <why>"``. A name (a
    belt, a routing) has the same shape as in the design commands' inputs
    (:func:`beltcalc.cli.contract.entry`): its ``text``, ``"value": null``, ``"unit": ""``."""
    units = {p.name: p.unit for p in params}
    out = {}
    for name, r in resolved.items():
        unit = units.get(name)
        value = r.value
        if isinstance(value, tuple):            # a value of one of several dimensions: (float, unit)
            value, unit = value
        entry = {"text": r.text, "origin": "option" if r.given else r.origin}
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            entry = {"value": float(value), "unit": "1" if unit in (None, "", "int") else unit, **entry}
        else:       # a name (a belt, a routing), as the design commands echo one (cli/contract.py)
            entry = {"value": None, "unit": "", **entry}
        out[name] = entry
    return out


strict_option = click.option(
    "--strict", is_flag=True,
    help="Exit 1 (and write no file) when a design check fails or cannot be verified (beyond a table or chart, "
         "no data); without it each is a warning.")


def emit_warnings(warnings: Iterable[str], checks=(), strict: bool = False) -> None:
    """The one way a command reports warnings and failed checks.

    Each warning is one ``warning: ...`` line on stderr (the same text goes into the
    JSON's ``warnings`` key, which the caller builds). With ``strict`` a failing check, or
    one that could not be verified (:class:`~beltcalc.design.checks.Check` ``unverified``), ends
    the command with exit 1 before any file is written.
    """
    from beltcalc.design.checks import failures
    from beltcalc.errors import InputError

    for w in warnings:
        click.echo(f"warning: {no_inf(w)}", err=True)
    bad = failures(checks)
    if strict and bad:
        parts = []
        for verdict, what in (("FAIL", "fail"), ("unverified", "cannot be verified")):
            these = [c for c in bad if c.verdict == verdict]
            if these:
                names = ", ".join(dict.fromkeys(c.name for c in these))
                parts.append(f"{len(these)} checks {what} ({names})")
        raise InputError(f"{' and '.join(parts)}; see the warnings", param="strict")


def wrote(path) -> None:
    """Say on stderr that ``path`` was written (after --csv or --plot): once the command's
    files are in place (:mod:`beltcalc.cli.writer`)."""
    announce(path)


def csv_cell(value) -> str:
    """A value as a CSV field: a float as ``repr`` (every digit), none or one that is not
    finite as an empty field (what the table shows as "-" and the JSON as null).

    >>> csv_cell(0.1), csv_cell(None), csv_cell(float("inf")), csv_cell("inf"), csv_cell("AT10")
    ('0.1', '', '', '', 'AT10')
    """
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ""
    if isinstance(value, str):
        return "" if value.strip().lower() in _NOT_FINITE else value
    return str(value)


_NOT_FINITE = frozenset({"inf", "-inf", "+inf", "nan", "-nan", "infinity", "-infinity", "none"})


def rows_csv(rows: Iterable[Row]) -> str:
    """CSV text with the header ``quantity,value,unit`` (SI values)."""
    return table_csv(["quantity", "value", "unit"], ([r.key, r.value, r.unit] for r in rows))


def table_csv(header: Sequence[str], rows: Iterable[Sequence]) -> str:
    """CSV text: ``header``, then ``rows``, each cell by :func:`csv_cell` (no ``inf``, ``nan``
    or ``None`` in a file: an empty field)."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([csv_cell(x) for x in row] for row in rows)
    return buf.getvalue()


@contextmanager
def spinner(label: str, enabled: bool = True, after: float = 1.0) -> Iterator[None]:
    """A rich spinner with the elapsed time on stderr while one long piece of work runs
    (shown only on a terminal, and only once the work has taken ``after`` seconds)."""
    from rich.console import Console

    err = Console(stderr=True)
    if not enabled or not err.is_terminal:
        yield
        return
    import threading

    done = threading.Event()

    def show():
        if done.wait(after):
            return
        with err.status(f"{label} ...", spinner="dots") as status:
            start = time.monotonic() - after
            while not done.wait(0.2):
                status.update(f"{label} ... {time.monotonic() - start:.0f} s")

    thread = threading.Thread(target=show, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()


@contextmanager
def progress(total: int, label: str, enabled: bool = True) -> Iterator[Callable[[], None]]:
    """A rich progress bar on stderr for ``total`` steps; yields the function that advances it.

    Disabled (a no-op) when ``enabled`` is False, e.g. with ``--json``, or for short work.
    """
    from rich.console import Console

    err = Console(stderr=True)
    if not enabled or not err.is_terminal:  # a bar in a log file is noise
        yield lambda: None
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeRemainingColumn(), console=err, transient=True) as bar:
        task = bar.add_task(label, total=total)
        yield lambda: bar.advance(task)
