"""The parts of the output contract the design commands (tension, belt-drive, chain,
motor-size) share: the inputs echoed with their origin, the checks as table rows, and the
warnings with library names turned into options.

Every input is ``{"text", "value" (SI float or None), "unit", "origin"}``; the origin is
``"default"``, ``"option"``, ``"scene: <why>"`` or ``"catalog: <where>"``.
"""

from __future__ import annotations

import math
from contextlib import contextmanager

import click
from click.core import ParameterSource

from beltcalc.cli.main import option_name
from beltcalc.design.checks import figure
from beltcalc.errors import render
from beltcalc.report import BEYOND, Row, format_number, quantity  # noqa: F401  (quantity: the CLI's too)

# Options that are how to report, not what to compute.
NOT_INPUTS = frozenset({"as_json", "csv_path", "plot_path", "strict", "catalog_paths"})


def origin(ctx: click.Context, name: str) -> str:
    """``"default"`` when click filled in ``name``, else ``"option"``."""
    source = ctx.get_parameter_source(name)
    return "default" if source in (None, ParameterSource.DEFAULT, ParameterSource.DEFAULT_MAP) else "option"


def entry(text: str, value, unit: str, where: str) -> dict:
    """One echoed input; a value that is not a finite number is None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        value = None
    return {"text": text, "value": None if value is None else float(value), "unit": unit, "origin": where}


def echo_inputs(ctx: click.Context, skip=()) -> dict:
    """Every option of the running command that has a value, with its origin.

    A quantity is its SI float and SI unit; a whole number has unit ``"1"``; a name, a
    choice or a flag is text only (value None, unit ``""``). An option without a value
    (not given, no default) is left out: the command adds what it took instead (e.g. a
    catalog value) with :func:`entry`.
    """
    from beltcalc.cli.options import QuantityParam

    out = {}
    for p in ctx.command.params:
        name = p.name
        if name in NOT_INPUTS or name in skip or not isinstance(p, click.Option):
            continue
        value = ctx.params.get(name)
        if value is None or (p.multiple and not value):
            continue
        where = origin(ctx, name)
        if isinstance(p.type, QuantityParam):
            v, unit = value if isinstance(value, tuple) else (value, p.type.si_unit)
            text = p.default if where == "default" and isinstance(p.default, str) else f"{v:g} {unit}".strip()
            out[name] = entry(text, v, unit or "1", where)
        elif isinstance(value, bool):
            out[name] = entry("yes" if value else "no", None, "", where)
        elif isinstance(value, int):
            out[name] = entry(str(value), value, "1", where)
        else:
            out[name] = entry(str(value), None, "", where)
    return out


def options_text(texts) -> list[str]:
    """Warnings (or notes) with the library's backquoted names as the options that set them."""
    return [render(t, option_name) for t in texts]


def checks_json(checks) -> list[dict]:
    """``Check.to_dict()`` of each check, its rule and reason naming options."""
    out = []
    for c in checks:
        d = c.to_dict()
        d["rule"] = render(d["rule"], option_name)
        if "reason" in d:
            d["reason"] = render(d["reason"], option_name)
        out.append(d)
    return out


def check_rows(checks) -> list[Row]:
    """The checks as table rows: utilisation in % (past 999 % as a factor, "x12.3"), the
    verdict and the rule in the note (a failing row says FAIL first, an n/a or unverified
    row why). A check on a score (the damping fit's R^2, :attr:`~beltcalc.design.checks.Check.score`)
    shows the value itself as a plain number: limit / R^2 is no fraction of a capacity. A
    utilisation with no finite figure (a minimum check on a value at or below 0) is "-" with
    that said, not blamed on the float range."""
    rows = []
    for c in checks:
        u = c.utilisation
        if c.verdict == "unverified":
            note = f"UNVERIFIED: {render(c.unverified, option_name)}"
        elif c.verdict == "n/a":
            note = f"n/a: {render(c.reason, option_name)}"
        else:
            op = "<=" if c.kind == "max" else ">="
            unit = "" if c.unit == "1" else " " + c.unit.replace("*", " ")
            note = (f"pass: {figure(c.value)} {op} {figure(c.limit)}{unit}" if c.verdict == "pass"
                    else f"FAIL: {figure(c.value)}{unit}, must be {op} {figure(c.limit)}{unit}")
            if u is not None and math.isinf(u) and not c.score:
                note += ("; no utilisation: the value is at or below 0" if c.kind == "min"
                         else "; no utilisation: the limit is not above 0")
                u = None
        if c.score:
            rows.append(Row(f"check_{c.key}", c.name, c.value, "1", digits=3, note=note))
        else:
            rows.append(Row(f"check_{c.key}", c.name, u, "1", "percent", digits=3, note=note))
    return rows


@contextmanager
def out_of_range(ctx: click.Context):
    """Turn an arithmetic failure of the library (overflow, division by a value that
    underflowed to zero, a matrix of infinities) into one line naming the options given.

    The library checks each input's range; what it cannot foresee is a combination of
    finite inputs whose arithmetic leaves the floats (``--speed 1e300rad/s``). The
    options the user gave are the ones to blame: one is named as the error's option,
    several are listed. Python's RuntimeWarnings inside (numpy's on the way there) are
    not printed.
    """
    from beltcalc.cli.options import QuantityParam
    from beltcalc.errors import BeltcalcError, InputError

    import warnings

    try:
        with warnings.catch_warnings():      # numpy's "invalid value" on the way to the failure: not for users
            warnings.simplefilter("ignore", RuntimeWarning)
            yield
    except BeltcalcError:
        raise
    except (ArithmeticError, ValueError) as exc:
        if not (isinstance(exc, ArithmeticError) or type(exc).__name__ == "LinAlgError"):
            raise
        given = [p.name for p in ctx.command.params
                 if isinstance(p.type, QuantityParam) and ctx.params.get(p.name) is not None
                 and origin(ctx, p.name) == "option"]
        what = f"the arithmetic leaves the range of a float ({type(exc).__name__})"
        if len(given) == 1:
            raise InputError(f"{what}; give a value in a physical range", param=given[0]) from None
        names = ", ".join(f"`{n}`" for n in given) or "the scene's values"
        raise InputError(f"{what} with these inputs; one of {names} is out of a physical range") from None


def shown(rows) -> list[Row]:
    """``rows`` with every value that is not a finite number (also once converted to its
    display unit: 1e308 m is infinite in mm) shown as '-' and said why in its note."""
    from dataclasses import replace

    from beltcalc.cli.output import display_value

    out = []
    for r in rows:
        if isinstance(r.value, float):
            try:
                bad = not math.isfinite(r.value) or display_value(r) in ("inf", "-inf", "nan")
            except (OverflowError, ValueError):
                bad = True
            if bad:
                r = replace(r, value=None, note=f"{r.note}; {BEYOND}" if r.note else BEYOND)
        out.append(r)
    return out


def fmt(value, digits: int = 4) -> str:
    """:func:`beltcalc.report.format_number` ('-' for a value that is not a finite number)."""
    return format_number(value, digits)
