"""Errors of beltcalc and the checks that raise them.

Every error a user can cause is a :class:`BeltcalcError`. The command line turns it
into one line on stderr and an exit code at one place (``cli/main.py``):

- :class:`InputError`: the inputs are readable but physically impossible (exit 1);
- :class:`UnknownNameError`: a name that is not in the catalogs (exit 2, a usage error);
- :class:`UsageError`: text the library cannot read as asked (``NAME=QUANTITY``, a sweep
  range, an unknown parameter name): exit 2;
- :class:`CatalogError`: a missing or malformed catalog file (exit 1);
- :class:`OutputError`: an output file that cannot be written (exit 1);
- :class:`SimulationError`: a solver failure (exit 1).

An error may name the library parameter it is about (``param``), and its message may
point at other parameters written in backquotes (```max_events```). The library never
names a command-line option: ``str(error)`` shows the library's names (``mass: ...``,
"raise max_events"), and the command line maps every name to the option that sets it at
its one error boundary (:func:`render`; ``--mass: ...``, "raise --max-events"). The
library's parameter names are the option names with ``_`` for ``-``; a value of a scene
(``scope="scene"``: a scene file's parameter, or a drive element's ``ELEMENT.KEY``) is
mapped to ``--set NAME``.
"""

from __future__ import annotations

import math
import re
from contextlib import contextmanager
from typing import Callable, Iterable, Iterator

_REF = re.compile(r"`([A-Za-z_][A-Za-z0-9_.]*)`")


def render(message: str, name=lambda n: n) -> str:
    """``message`` with each backquoted parameter name replaced by ``name(it)``.

    >>> render("raise `max_events`"), render("raise `max_events`", lambda n: "--" + n.replace("_", "-"))
    ('raise max_events', 'raise --max-events')
    """
    return _REF.sub(lambda m: name(m.group(1)), message)


class BeltcalcError(Exception):
    """Base of every error a user can cause. ``exit_code`` is what the CLI returns."""

    exit_code = 1

    def __init__(self, message: str, param: str | None = None, scope: str | None = None):
        super().__init__(message)
        self.message = message
        self.param = param
        self.scope = scope      # None: a parameter of a library function; "scene": a scene's value

    def __str__(self) -> str:
        return f"{self.param}: {render(self.message)}" if self.param else render(self.message)


class InputError(BeltcalcError, ValueError):
    """Physically impossible input (negative mass, span shorter than a pitch, ...)."""


class FloatRangeError(InputError):
    """A value the inputs lead to (a stiffness over an inertia, a gear ratio squared, a
    diameter to the fourth power) lies beyond the float range (1.8e308): no model can be
    built on it. The message says what overflowed; :func:`blame` names the value a user
    gave that did it."""


class UnknownNameError(BeltcalcError, KeyError):
    """A belt, width, thread or motor that is not in the catalogs (a usage error)."""

    exit_code = 2

    def __str__(self) -> str:  # KeyError would quote the message
        return BeltcalcError.__str__(self)


class UsageError(BeltcalcError, ValueError):
    """Text that cannot be read as asked: ``NAME=QUANTITY`` without a known name or with a
    wrong unit, a malformed sweep range (a usage error). ``param`` names the input
    (``set``, ``sweep``)."""

    exit_code = 2


class CatalogError(BeltcalcError):
    """A catalog file is missing or malformed; the message names the file and key."""


class OutputError(BeltcalcError):
    """An output file could not be written (nothing is left half-written)."""


class SimulationError(BeltcalcError):
    """A solver failed; the message says at which time, with which method, what to try."""


def require_positive(param: str, value: float, unit: str) -> float:
    """Return ``value`` if it is a finite number > 0, else raise :class:`InputError`.

    >>> require_positive("mass", 50.0, "kg")
    50.0
    >>> require_positive("mass", -5.0, "kg")
    Traceback (most recent call last):
    ...
    beltcalc.errors.InputError: mass: -5 kg is not allowed; it must be > 0 kg
    """
    return require_range(param, value, unit, low=0.0, low_open=True)


def require_range(
    param: str,
    value: float,
    unit: str,
    low: float = -math.inf,
    high: float = math.inf,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Return ``value`` if it is finite and inside the interval, else raise :class:`InputError`.

    ``low_open``/``high_open`` exclude the bound itself. The message names the allowed
    range in the same unit.

    >>> require_range("mu", 0.2, "", 0.0, 1.0, low_open=True, high_open=True)
    0.2
    >>> require_range("mu", 1.5, "", 0.0, 1.0, low_open=True, high_open=True)
    Traceback (most recent call last):
    ...
    beltcalc.errors.InputError: mu: 1.5 is not allowed; it must be in (0, 1)
    """
    if hasattr(value, "magnitude") and hasattr(value, "to"):   # a pint quantity: say what to pass
        raise InputError(f"{value:g~} is a quantity; this function takes SI floats: pass "
                         f"x.to({unit or 'dimensionless'!r}).magnitude, or use the API that takes quantities",
                         param=param)
    bad_low = value <= low if low_open else value < low
    bad_high = value >= high if high_open else value > high
    if math.isfinite(value) and not bad_low and not bad_high:
        return value
    u = f" {unit}" if unit else ""
    if math.isinf(high):
        allowed = f"{'>' if low_open else '>='} {low:g}{u}"
    elif math.isinf(low):
        allowed = f"{'<' if high_open else '<='} {high:g}{u}"
    else:
        allowed = f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}{u}"
    raise InputError(f"{value:g}{u} is not allowed; it must be {allowed}", param=param)


MAX_CLOSE_TEXT = 200         # a longer name gets no closest names (difflib on it would only be slow)


def closest(name: str, names: Iterable[str], n: int = 3) -> list[str]:
    """The ``n`` names of ``names`` nearest to ``name``, nearest first: difflib's similarity
    ratio (``difflib.get_close_matches``), case ignored. Always ``n`` of them where there are
    that many: the three closest are offered even when none is close.

    >>> closest("C5", ["J1", "C1", "C4", "d1", "U12", "t_end"])
    ['C4', 'C1', 'U12']
    >>> closest("sgm7j-06", ["SGM7J-06A", "SGM7J-08A", "SGMAH-04A", "SGM7J-04A"])
    ['SGM7J-06A', 'SGM7J-08A', 'SGM7J-04A']
    """
    import difflib

    if not isinstance(name, str) or len(name) > MAX_CLOSE_TEXT:
        return []
    folded: dict[str, str] = {}
    for known in names:
        folded.setdefault(str(known).lower(), str(known))
    return [folded[m] for m in difflib.get_close_matches(name.lower(), list(folded), n=n, cutoff=0.0)]


def did_you_mean(name: str, names: Iterable[str], listed: int = 12) -> str:
    """The one hint of every unknown-name message: ``"did you mean a, b, c?"`` with the three
    closest of ``names`` (:func:`closest`), then, unless ``listed`` is 0 or those are all,
    every name in brackets where there are at most ``listed``, else how many there are.
    ``""`` when there are none.

    >>> did_you_mean("C5", ["J1", "C1", "C4", "d1", "U12"])
    'did you mean C4, C1, U12? (one of J1, C1, C4, d1, U12)'
    >>> did_you_mean("uper.pretension", [f"e{k}.x" for k in range(70)] + ["upper.pretension"])
    'did you mean upper.pretension, e9.x, e8.x? (71 names)'
    >>> did_you_mean("AT11", ["BRECO-AT10", "AT10", "AT5", "T20"], listed=0)
    'did you mean AT10, AT5, BRECO-AT10?'
    """
    names = list(dict.fromkeys(str(n) for n in names))
    if not names:
        return ""
    near = closest(name, names)
    hint = f"did you mean {', '.join(near)}?" if near else ""
    if listed and len(names) > len(near):      # the three are not all there is
        listing = f"one of {', '.join(names)}" if len(names) <= listed else f"{len(names)} names"
        hint = f"{hint} ({listing})" if hint else f"({listing})"
    return hint


FLOAT_MAX = "1e308"          # how a message says the float range


def _innermost(tb) -> str:
    """The innermost beltcalc function of a traceback (``torsional_stiffness``), or ''."""
    name = ""
    while tb is not None:
        if tb.tb_frame.f_globals.get("__name__", "").startswith("beltcalc"):
            name = tb.tb_frame.f_code.co_name
        tb = tb.tb_next
    return name


@contextmanager
def float_range(what: str | Callable[[], str]) -> Iterator[None]:
    """Inside: a float power or exponential beyond the float range (Python's
    ``OverflowError``) is a :class:`FloatRangeError` saying that ``what`` overflows, and in
    which function (``what`` may be a function of nothing giving the text).

    >>> with float_range("the drive's model"):
    ...     1e200 ** 2
    Traceback (most recent call last):
    ...
    beltcalc.errors.FloatRangeError: the drive's model overflows a float (beyond 1e308 in SI units)
    """
    try:
        yield
    except OverflowError as exc:
        where = _innermost(exc.__traceback__)
        where = f" in {where}()" if where and where not in ("float_range", "<module>") else ""
        what = what() if callable(what) else what
        raise FloatRangeError(f"{what} overflows a float{where} (beyond {FLOAT_MAX} in SI units)") from None


def blame(exc: FloatRangeError, changed: Iterable[str], probe: Callable[[str | None], None],
          show: Callable[[str], str]) -> FloatRangeError:
    """``exc`` about the one value a user changed that makes the model overflow.

    ``probe(name)`` builds the model with ``name`` put back to its file's value (``None``:
    with every value as given) and raises :class:`FloatRangeError` while it still overflows.
    The first of ``changed`` whose value put back lets it build is the culprit: the error
    comes back naming it (``param``, ``scope="scene"``: the command line says ``--set
    NAME``) with its value (``show(name)``). Where the model with every value as given does
    not overflow when only built (the overflow came later), or no single value is to blame,
    ``exc`` comes back as it is.

    >>> def probe(name):
    ...     if name != "ratio":
    ...         raise FloatRangeError("the mass matrix overflows a float")
    >>> str(blame(FloatRangeError("the mass matrix overflows a float"), ["mass", "ratio"], probe, lambda n: "1e+200"))
    'ratio: at 1e+200, the mass matrix overflows a float'
    """
    changed = list(changed)
    if exc.param is not None or not changed:
        return exc
    try:
        probe(None)
    except FloatRangeError:
        pass
    except Exception:       # another problem first: not this one to name
        return exc
    else:
        return exc
    for name in changed:
        try:
            probe(name)
        except FloatRangeError:
            continue
        except Exception:   # it builds past the overflow (and fails on something else): still the culprit
            pass
        return FloatRangeError(f"at {show(name)}, {exc.message}", param=name, scope="scene")
    return exc
