"""Option types and options shared by every command (defined once, used everywhere)."""

from __future__ import annotations

import math
import os
from pathlib import Path

import click

from beltcalc.cli.main import option_name
from beltcalc.units import QuantityError, parse_quantity, parse_quantity_any, quote


class QuantityParam(click.ParamType):
    """A quantity with units (``90kg``, ``31.3in``, ``0.5g0``) converted to an SI float.

    ``si_unit`` names the SI unit the value is returned in, and so the dimension the
    text must have; ``""`` is a plain number. With several units separated by ``|``
    (``"rad/s|m/s"``) any of those dimensions is accepted and the value comes back as
    ``(float, unit)``. Text, unit and finiteness are checked here (a usage error,
    exit 2); physical ranges are checked by the library (exit 1). ``display`` is the unit
    the command shows the value in (``mm`` for a width): a message's example uses it
    (``--width 25``: "e.g. '25 mm'").
    """

    name = "quantity"

    def __init__(self, si_unit: str, display: str | None = None):
        self.si_unit = si_unit
        self.display = display
        self.alternatives = tuple(si_unit.split("|")) if "|" in si_unit else ()

    def get_metavar(self, param, ctx=None) -> str:  # click >= 8.2 passes ctx
        return "NUMBER" if self.si_unit == "" else "QUANTITY"

    def convert(self, value, param, ctx):
        if isinstance(value, (float, tuple)):
            return value
        try:
            if self.alternatives:
                return parse_quantity_any(value, self.alternatives)
            return parse_quantity(value, self.si_unit, self.display)
        except QuantityError as exc:
            message = str(exc)
            if "needs a unit" in message and param is not None and param.opts:
                message = self.how_to_type(value, message, param.opts[0], ctx)
            self.fail(message, param, ctx)

    def how_to_type(self, value: str, message: str, opt: str, ctx) -> str:
        """``message`` about the bare number ``value`` with how to type the unit with it: where
        the word after it on the command line is a unit of this option, the shell split
        ``--power 3 kW`` in two (say so); else how to write a value with its unit, with or
        without a space."""
        from beltcalc.cli.main import ARGV
        from beltcalc.units import example_unit, unit_problem

        unit = self.display or example_unit((self.alternatives or (self.si_unit,))[0])
        after = _word_after(ctx.meta.get(ARGV, []) if ctx is not None else [], opt, value)
        if after and not after.startswith("-") and any(
                unit_problem(after, u) == "" for u in (self.alternatives or (self.si_unit,))):
            number = value.strip()
            return (f"{quote(value)} needs a unit: '{number} {after}' with a space is two words to the shell; "
                    f"write {opt} {number}{after} or quote it: {opt} \"{number} {after}\"")
        return (f"{message} (no space: {opt} {value.strip()}{unit.replace(' ', '*')}; "
                f"or quote it: {opt} \"{value.strip()} {unit}\")")


def _word_after(argv: list[str], opt: str, value: str) -> str | None:
    """The word after ``opt value`` (or ``opt=value``) on the command line ``argv``; None
    where there is none."""
    for i, word in enumerate(argv):
        if word == opt and i + 2 < len(argv) and argv[i + 1] == value:
            return argv[i + 2]
        if word == f"{opt}={value}" and i + 1 < len(argv):
            return argv[i + 1]
    return None


class Tolerance(click.FloatRange):
    """A float in a range that is also a number: ``click.FloatRange`` lets ``nan`` through
    (every comparison with it is false), and a solver with an ``nan`` tolerance never ends.
    The one type of every tolerance option (``--rtol``, ``--atol``, ``--error-tol``): a bad
    one is a usage error (exit 2) alike."""

    def convert(self, value, param, ctx):
        value = super().convert(value, param, ctx)
        if math.isnan(value):
            self.fail(f"{value!r} is not a number; give one in {self._describe_range()}", param, ctx)
        return value


class DriveRef(click.ParamType):
    """A drive: a drive file's path or a built-in drive's name, kept as text (the library
    resolves it). What can be neither is a usage error (exit 2) here: an empty text (which
    a path would read as the current folder) and a folder."""

    name = "drive"

    def convert(self, value, param, ctx):
        from beltcalc.units import quote

        if not isinstance(value, str):
            return value
        if value.strip() == "":
            self.fail(f"{quote(value)} is no drive; give a drive file (e.g. 'my_drive.toml') or a built-in "
                      "drive's name (e.g. 'sewing')", param, ctx)
        try:
            folder = os.path.isdir(value)
        except (OSError, ValueError):      # a NUL, a name too long: the library says what it is
            folder = False
        if folder:
            self.fail(f"{quote(value, 200)} is a folder, not a drive file", param, ctx)
        return value


class FrequencyParam(QuantityParam):
    """A frequency in Hz: hertz as written (``10Hz``, ``1kHz``), an angular frequency or a
    speed divided by 2 pi (``62.8rad/s``, ``600rpm``: 10 Hz)."""

    def __init__(self):
        super().__init__("Hz")

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            return value
        hz = super().convert(value, param, ctx)      # text, number and dimension checked here
        try:
            return parse_quantity(value, "rad/s") / (2 * math.pi)
        except QuantityError:                        # the only refusal left: the text is in hertz
            return hz


class BandParam(click.ParamType):
    """A frequency band ``LOW:HIGH`` -> (low, high) in Hz: each end a frequency as
    :class:`FrequencyParam` reads it; a bare number at the low end takes the high end's unit
    (``0:12Hz``, ``2Hz:12Hz``, ``0:600rpm``). 0 <= low < high, both finite."""

    name = "band"

    def get_metavar(self, param, ctx=None) -> str:  # click >= 8.2 passes ctx
        return "LOW:HIGH"

    def convert(self, value, param, ctx):
        import re

        if isinstance(value, tuple):
            return value
        low, sep, high = str(value).partition(":")
        low, high = low.strip(), high.strip()
        if not sep or not low or not high or ":" in high:
            self.fail(f"{quote(value)}: give LOW:HIGH, e.g. 0:12Hz", param, ctx)
        bare = r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?"
        if re.fullmatch(bare, high):
            self.fail(f"{quote(value)} needs a unit, e.g. {low}:{high}Hz", param, ctx)
        number = re.match(bare, high)
        if re.fullmatch(bare, low) and number:
            low = low + high[number.end():]                  # 0:12Hz -> 0Hz, 12Hz
        lo, hi = (FrequencyParam().convert(v, param, ctx) for v in (low, high))
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi):
            self.fail(f"{quote(value)}: the band must have 0 Hz <= LOW < HIGH, got {lo:g} Hz to {hi:g} Hz",
                      param, ctx)
        return (lo, hi)


class OutputPath(click.ParamType):
    """A file to write, checked before any work: its name not too long for the file system;
    not a folder; a link followed to its target; a new file or one replaced in a folder that
    exists and is writable, a file written in place (a FIFO, a device, a file with hard
    links) writable itself (:func:`beltcalc.cli.writer.resolve_target`). A plot's file (an
    option whose name holds ``plot``) ends in ``.png``, ``.pdf`` or ``.svg``, the format it is
    written in (:func:`beltcalc.cli.output.plot_format`)."""

    name = "path"

    def convert(self, value, param, ctx) -> Path:
        from beltcalc.cli.writer import resolve_target
        from beltcalc.errors import OutputError
        from beltcalc.units import quote

        if isinstance(value, Path):
            return value
        if value == "":
            example = "out.png" if param is not None and "plot" in (param.name or "") else "out.csv"
            self.fail(f"'' is no file name; give one, e.g. '{example}'", param, ctx)
        if "\0" in value:
            self.fail(f"{quote(value, 200)} holds a NUL character; give a file name", param, ctx)
        path = Path(value).expanduser()
        try:
            limit = os.pathconf(path.parent if str(path.parent) else ".", "PC_NAME_MAX")
        except (OSError, ValueError):
            limit = 255
        if len(os.fsencode(path.name)) > limit:
            self.fail(f"{quote(value)}: the file name is {len(os.fsencode(path.name))} bytes long; "
                      f"at most {limit} here", param, ctx)
        try:
            resolved = path.resolve(strict=False)
        except RuntimeError:                 # a loop of links (Python 3.11)
            self.fail(f"{quote(value, 200)}: a loop of symbolic links", param, ctx)
        if len(os.fsencode(str(resolved))) >= 4096:
            self.fail(f"{quote(value, 200)}: the path is too long (at most 4095 bytes)", param, ctx)
        folder = path.parent if str(path.parent) else Path(".")
        try:
            if os.path.isdir(path):
                self.fail(f"{quote(value, 200)} is a folder, not a file", param, ctx)
            if not folder.is_dir():
                self.fail(f"{quote(value, 200)}: the folder {quote(str(folder), 200)} does not exist", param, ctx)
            try:
                target = resolve_target(path)
            except OutputError as exc:
                self.fail(f"{quote(value, 200)}: {exc.message.partition(': ')[2]}", param, ctx)
            folder = target.path.parent
            if target.how == "in place":
                if not os.access(target.path, os.W_OK):
                    self.fail(f"{quote(value, 200)} exists and is not writable", param, ctx)
            elif not os.access(folder, os.W_OK | os.X_OK):
                self.fail(f"{quote(value, 200)}: the folder {quote(str(folder), 200)} is not writable", param, ctx)
            elif target.st is not None and not os.access(target.path, os.W_OK):
                self.fail(f"{quote(value, 200)} exists and is not writable", param, ctx)
        except OSError as exc:   # a folder name too long, a loop of links, ...
            self.fail(f"{quote(value, 200)}: {exc.strerror or exc}", param, ctx)
        if param is not None and "plot" in (param.name or ""):
            from beltcalc.cli.output import plot_format

            try:
                plot_format(path)          # the suffix names the format: .png, .pdf or .svg
            except ValueError as exc:
                self.fail(str(exc), param, ctx)
        return path


def quantity_option(*decls: str, si_unit: str, default=None, help: str, display: str | None = None, **kw):
    """A ``--name QUANTITY`` option; ``default`` is text with its unit, shown in --help;
    ``display`` the unit the command shows it in (the examples of its messages use it)."""
    return click.option(*decls, type=QuantityParam(si_unit, display), default=default,
                        show_default=default is not None, help=help, **kw)


json_option = click.option("--json", "as_json", is_flag=True,
                           help="Print one JSON object (SI values with their unit) and nothing else.")
csv_option = click.option("--csv", "csv_path", type=OutputPath(), default=None,
                          help="Also write the table to this CSV file (atomically).")
catalog_option = click.option(
    "--catalog", "catalog_paths", multiple=True,
    type=click.Path(exists=True, dir_okay=False, readable=True),
    help="A catalog file of your own (same TOML format), added to the built-in ones; repeatable.",
)


def output_options(func):
    """``--json`` and ``--csv``: every command has both."""
    return json_option(csv_option(func))


# --- scene parameters: one option per parameter, the scene file supplies the defaults ------

def scene_options(params):
    """Add one ``--name`` option per :class:`~beltcalc.params.Param`, default None (= take it
    from the scene)."""
    def decorate(func):
        for p in reversed(params):
            if p.unit == "int":
                kind = click.IntRange(min=0)
            elif p.unit is None:
                kind = str
            else:
                kind = QuantityParam(p.unit, "mm" if p.unit == "m" else None)   # lengths show in mm
            suffix = " [default: from the scene]" if p.required else ""
            func = click.option(option_name(p.name), p.name, type=kind, default=None, help=p.help + suffix)(func)
        return func
    return decorate
