"""The ``beltcalc`` command group: lazy subcommands and the one error boundary.

Subcommands are imported only when run, so ``beltcalc tension`` never imports scipy or
matplotlib. Every :class:`~beltcalc.errors.BeltcalcError` becomes one line on stderr
and its exit code here (1: physically impossible input, catalog or solver failure;
2: usage: bad text, wrong unit, unknown name). ``--debug`` shows the traceback instead.
Python warnings are not shown (``--debug`` shows them): what a user must know is a check's
``warning:`` line. An interrupt (Ctrl-C) is ``Error: interrupted``, exit 130. The files a
command writes are put in place only once it has finished (:mod:`beltcalc.cli.writer`):
a failing or interrupted command leaves none.

The line names the option that sets the value the error is about: a library parameter
``center_distance`` is ``--center-distance``; a scene's value (``scope="scene"``) is named
by the command that resolved the scene (``ctx.meta[SCENE_OPTION]``: ``--set rollers``,
``--t-end``), by default as any other parameter.
"""

from __future__ import annotations

import gc
import importlib
import os
import sys
import warnings

# The networks here are small (tens of states): a multi-threaded BLAS spends longer
# starting threads than multiplying (the exact propagator runs 0.3 ms single-threaded and
# 9 ms with two OpenBLAS threads on the sewing model). Set before numpy is imported;
# a user's own setting wins.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import click

from beltcalc import __version__
from beltcalc.errors import BeltcalcError, UsageError, render

# name -> "module:attribute"; the module is imported only when the command runs.
COMMANDS = {
    "tension": "beltcalc.cli.tension:tension",
    "catalog": "beltcalc.cli.catalog:catalog",
    "motor-size": "beltcalc.cli.motor_size:motor_size",
    "simulate": "beltcalc.cli.simulate:simulate",
    "belt-drive": "beltcalc.cli.belt_drive:belt_drive",
    "chain": "beltcalc.cli.chain:chain",
    "modes": "beltcalc.cli.frequency:modes",
    "response": "beltcalc.cli.frequency:response",
    "campbell": "beltcalc.cli.frequency:campbell",
}

# name -> the start of its help (its first paragraph, or enough of it for the widest help
# line): `beltcalc --help` lists the commands without importing them (which would load pint,
# numpy and the catalogs). tests/test_fast_outputs.py checks each against the command's own.
SUMMARIES = {
    "tension": "Belt tension of a timing-belt linear axis, and the bolt torque that sets it.",
    "catalog": "List and show the belts, threads, motors and chains of the catalogs.",
    "motor-size": "Motor torque, energy and motor choice for a timing-belt linear axis.",
    "simulate": "Time simulation of drive trains (every scene runs on the one ODE core).",
    "belt-drive": "Geometry and the checks a designer signs off for a timing-belt drive.",
    "chain": "Roller-chain selection by the ACA power-rating formulas, with ISO 606 sprockets.",
    "modes": ("Every pole of a drive (a drive file, or a built-in drive by name: conveyor, sewing "
              "[default], roller_table, linear_axis, linear_axis_moving, friswell_5_disks, friswell_geared):"),
    "response": ("The frequency response H(jw) of a drive (default: the sewing drive) from each input to "
                 "each output: magnitude in the output's unit per the input's unit, and phase,"),
    "campbell": ("The Campbell diagram of a drive (default: the sewing drive): where the excitation orders "
                 "cross its modes as the reference node runs up, each crossing with its speed"),
}


SCENE_OPTION = "beltcalc.scene_option"   # ctx.meta key: scene parameter name -> its option text
ARGV = "beltcalc.argv"                   # ctx.meta key: the words of the command line, as typed
OPTION_NAMES = "beltcalc.option_names"   # ctx.meta key: {library parameter: its option} where they differ


def option_name(name: str) -> str:
    """The option of a library parameter: ``center_distance`` -> ``--center-distance``."""
    return "--" + name.replace("_", "-")


def error_line(exc: BeltcalcError, meta: dict) -> str:
    """The one line of a library error, its parameter (and every parameter its message
    names in backquotes) named as the option that sets it (``meta[OPTION_NAMES]`` where a
    command's option is not the parameter's name, ``f_min`` -> ``--from``)."""
    names = meta.get(OPTION_NAMES, {})

    def to_name(name: str) -> str:
        return names.get(name) or option_name(name)

    message = render(exc.message, to_name)
    if not exc.param:
        return message
    to_option = meta.get(SCENE_OPTION, to_name) if exc.scope == "scene" else to_name
    if isinstance(exc, UsageError):
        return f"Invalid value for {to_option(exc.param)}: {message}"
    return f"{to_option(exc.param)}: {message}"


def _extra_unit_hint(message: str, argv: list[str]) -> str:
    """Where click found an extra word on the command line that is a unit after an option's
    value (``--set C4=190 N*m/rad``, ``--t-end 2 s``): the shell split a value typed with a
    space; say to quote it."""
    from beltcalc.units import is_unit

    if not message.startswith("Got unexpected extra argument"):
        return ""
    for i, word in enumerate(argv):
        if i >= 2 and argv[i - 2].startswith("-") and not argv[i - 1].startswith("-") and is_unit(word) \
                and f"({word}" in message:
            opt, value = argv[i - 2].partition("=")[0], argv[i - 1]
            return (f": '{value} {word}' with a space is two words to the shell; "
                    f"quote it: {opt} \"{value} {word}\"")
    return ""


MAX_MESSAGE = 2000   # characters of an error line


def one_line(message: str) -> str:
    """``message`` as one line of printable text: a newline or a right-to-left override a
    user put in a name or a file name is shown escaped, and a line longer than
    :data:`MAX_MESSAGE` is cut.

    >>> print(one_line("unknown belt 'AT\\u202e10'\\nx"))
    unknown belt 'AT\\u202e10'\\nx
    """
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)
    return text if len(text) <= MAX_MESSAGE else f"{text[:MAX_MESSAGE]}... ({len(text)} characters)"


MMAP_THRESHOLD = 32 << 20    # glibc: allocations below this come from the heap ...
TRIM_THRESHOLD = 256 << 20   # ... which keeps up to this much freed memory at its top


def _keep_freed_memory() -> None:
    """Let glibc's malloc keep freed memory for the next allocation instead of handing every
    large temporary back to the system and faulting its pages in again when the next one is
    made. numpy's temporaries in a run are block-sized (a few hundred KB, thousands of them),
    above glibc's default 128 KB mmap threshold: each cost about 1.5 us a page on this kind
    of machine (``np.abs(Z @ W)`` on a 2048-row block: 227 us, 72 us with this). A setting of
    the console script's process, never of the library's; a user's own ``MALLOC_*`` setting
    wins; not glibc (or no ``mallopt``): nothing to do. Called once a command is loaded
    (numpy has imported ctypes by then)."""
    global _keep_freed_memory_done
    if _keep_freed_memory_done or any(k.startswith("MALLOC_") for k in os.environ):
        return
    _keep_freed_memory_done = True
    try:
        import ctypes

        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):
        return
    mallopt(-3, MMAP_THRESHOLD)      # M_MMAP_THRESHOLD
    mallopt(-1, TRIM_THRESHOLD)      # M_TRIM_THRESHOLD


_keep_freed_memory_done = False


INTERRUPTED = "interrupted"
INTERRUPTED_EXIT = 130      # 128 + SIGINT, as a shell reports a command Ctrl-C ended


class _Failure(click.ClickException):
    def __init__(self, message: str, exit_code: int):
        super().__init__(message)
        self.exit_code = exit_code


class BeltcalcGroup(click.Group):
    """A group that loads its commands lazily and prints every error as one line."""

    def list_commands(self, ctx):
        return sorted(COMMANDS)

    def format_commands(self, ctx, formatter):
        """The command list from :data:`SUMMARIES`, cut as click cuts a command's help:
        nothing is imported (a command missing there is imported for its help)."""
        names = self.list_commands(ctx)
        limit = formatter.width - 6 - max(len(name) for name in names)
        rows = [(name, (click.Command(name, help=SUMMARIES[name]) if name in SUMMARIES else
                        self.get_command(ctx, name)).get_short_help_str(limit)) for name in names]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def get_command(self, ctx, name):
        target = COMMANDS.get(name)
        if target is None:
            return None
        module, attr = target.split(":")
        command = getattr(importlib.import_module(module), attr)
        _resume_gc()
        _keep_freed_memory()
        return command

    def parse_args(self, ctx, args):
        # the words as typed: an option's value that a space split in two ('--power 3 kW') is
        # told apart from a number with no unit (beltcalc.cli.options.QuantityParam)
        ctx.meta[ARGV] = list(args)
        return super().parse_args(ctx, args)

    def make_context(self, info_name, args, parent=None, **extra):
        try:
            return super().make_context(info_name, args, parent, **extra)
        except KeyboardInterrupt:
            raise _Failure(INTERRUPTED, INTERRUPTED_EXIT) from None

    def invoke(self, ctx):
        from beltcalc.cli.writer import output_session

        try:
            # files are staged while the command runs and put in place only once it has
            # finished: an error or an interrupt leaves none (beltcalc.cli.writer)
            with output_session() as files:
                rv = super().invoke(ctx)
                files.commit()
            return rv
        except KeyboardInterrupt:   # Ctrl-C: one line, the shell's code for SIGINT, no file
            if ctx.meta.get("beltcalc.debug"):
                raise
            raise _Failure(INTERRUPTED, INTERRUPTED_EXIT) from None
        except BeltcalcError as exc:
            if ctx.meta.get("beltcalc.debug"):
                raise
            raise _Failure(error_line(exc, ctx.meta), exc.exit_code) from None
        except (click.exceptions.ClickException, click.exceptions.Exit, click.exceptions.Abort):
            raise
        except MemoryError as exc:  # a size no check bounded: say so, not "internal error"
            if ctx.meta.get("beltcalc.debug"):
                raise
            raise _Failure(f"not enough memory for this run ({exc or 'MemoryError'}); ask for less: fewer "
                           "--samples (or a larger --dt), a shorter sweep", 1) from None
        except Exception as exc:  # a bug: say so in one line, keep the traceback for --debug
            if ctx.meta.get("beltcalc.debug"):
                raise
            raise _Failure(f"internal error: {type(exc).__name__}: {exc} "
                           "(run `beltcalc --debug ...` for the traceback)", 1) from None

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        # Python warnings (numpy's RuntimeWarning, scipy's ODEintWarning) never reach stderr:
        # stderr holds `warning:` lines of the checks and, on failure, exactly one Error: line.
        # --debug shows them again (the group's callback, inside this context).
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            code = self._main(args, prog_name, complete_var, **extra)
        if standalone_mode:
            sys.exit(code)
        return code

    def _main(self, args, prog_name, complete_var, **extra) -> int:
        try:
            rv = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
            code = rv if isinstance(rv, int) else 0
        except click.ClickException as exc:
            message = exc.format_message()
            if isinstance(exc, _Failure):      # the library's line: no figure printed as inf
                from beltcalc.cli.output import no_inf

                message = no_inf(message)
            elif isinstance(exc, click.UsageError) and exc.ctx is not None:
                message += _extra_unit_hint(message, exc.ctx.meta.get(ARGV, []))
            click.echo(f"Error: {one_line(message)}", err=True)
            code = exc.exit_code
        except click.exceptions.Abort:     # an interrupt click saw first
            click.echo(f"Error: {INTERRUPTED}", err=True)
            code = INTERRUPTED_EXIT
        return code


@click.group(cls=BeltcalcGroup, context_settings={"help_option_names": ["-h", "--help"],
                                                   "max_content_width": 100})
@click.version_option(__version__, prog_name="beltcalc")
@click.option("--debug", is_flag=True, envvar="BELTCALC_DEBUG",
              help="Show the full traceback of an error.")
@click.pass_context
def cli(ctx: click.Context, debug: bool) -> None:
    """Belt and chain drive trains: belt model, tension, bolt torque, motor sizing, simulation.

    Every quantity takes units (`--mass 90kg`, `--center-distance 31.3in`, `--accel 0.5g0`);
    with no options each command reproduces its source paper's worked example.
    """
    ctx.meta["beltcalc.debug"] = debug
    if debug:
        warnings.simplefilter("default")


_GC_PAUSED = False


def _resume_gc() -> None:
    """Start the cyclic garbage collector that :func:`main` paused, its objects so far frozen
    (``gc.freeze``: modules, functions and classes live to the end; collections never walk
    them again)."""
    global _GC_PAUSED
    if _GC_PAUSED:
        _GC_PAUSED = False
        gc.freeze()
        gc.enable()


def main() -> None:
    """Console-script entry point.

    A command is one short process, and about a fifth of its CPU went to the garbage
    collector walking objects that live to its end: the tens of thousands that importing
    pint, numpy and the command creates, walked again by each collection the imports
    trigger, and all of them once more as the interpreter shuts down. So the collector is
    paused until the command's module is imported (:func:`_resume_gc`: frozen, then
    collections resume for the run itself, a long study included), and what is alive when
    the command ends is frozen, not collected, before the process exits. What the command
    prints and writes is unchanged (streams are flushed and files closed as before)."""
    global _GC_PAUSED
    if gc.isenabled():
        gc.disable()
        _GC_PAUSED = True
    try:
        cli(prog_name="beltcalc")
    finally:
        _resume_gc()
        gc.freeze()


if __name__ == "__main__":  # pragma: no cover
    main()
