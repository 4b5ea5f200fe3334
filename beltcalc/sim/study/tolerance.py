"""Tolerance (Monte Carlo) studies: the limits on an output column (:func:`parse_limit`) and
the study itself (:func:`tolerance_study`): every run drawn, folded where it runs into what
the report needs (:mod:`beltcalc.sim.study.fold`), in constant memory.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from typing import Callable, Mapping, Sequence

from beltcalc.errors import UsageError, did_you_mean
from beltcalc.params import bare_number
from beltcalc.sim.study.execution import Execution, execute
from beltcalc.sim.study.fold import RESERVOIR, Fold, FoldSpec, Limit, StudySummary
from beltcalc.sim.study.plan import Plan
from beltcalc.sim.study.runs import Chunk


# --- limits ------------------------------------------------------------------------------------

def split_limit(text: str) -> tuple[str, str, str]:
    """``KEY>=VALUE`` or ``KEY<=VALUE`` -> (key, op, value text).

    >>> split_limit("strand_safety_1 >= 2")
    ('strand_safety_1', '>=', '2')
    """
    from beltcalc.units import quote

    m = re.fullmatch(r"\s*([^<>=\s]+)\s*(>=|<=)\s*(\S.*?)\s*", text)
    if m is None:
        raise UsageError(f"{quote(text)}: use KEY>=VALUE or KEY<=VALUE, KEY a column of the study", param="limit")
    return m.group(1), m.group(2), m.group(3)


def parse_limit(text: str, columns: Mapping[str, object]) -> Limit:
    """The limit ``text`` on one of ``columns`` (key -> :class:`~beltcalc.report.Column`), its
    value in the column's SI unit (units needed where the column has one)."""
    from beltcalc.units import QuantityError, parse_quantity, quote

    key, op, value = split_limit(text)
    if key not in columns:
        hint = did_you_mean(key, columns)
        raise UsageError(f"{quote(text)}: {quote(key)} is not a column of this study" + (f"; {hint}" if hint else ""),
                         param="limit")
    unit = columns[key].unit or "1"
    if unit in ("1", ""):
        try:
            bound = float(value)
        except ValueError:
            raise UsageError(f"{quote(text)}: {key} is a plain number; give one", param="limit") from None
    else:
        if bare_number(value):
            raise UsageError(f"{quote(text)}: {key} needs a unit, e.g. '{key}{op}{value} {unit}'", param="limit")
        try:
            bound = parse_quantity(value, unit.replace(" ", "*"))
        except QuantityError as exc:
            raise UsageError(f"{quote(text)}: {exc}", param="limit") from None
    if not math.isfinite(bound):
        raise UsageError(f"{quote(text)}: the limit must be a finite number", param="limit")
    return Limit(key, op, bound, unit, text)
def tolerance_study(plan: Plan, columns: Mapping[str, object], limits: Sequence[Limit] = (),
                    on_chunk: Callable[[Chunk], None] | None = None, progress: Callable[[int], None] | None = None,
                    workers: int | None = None, scheduler: str | None = None, reservoir: int = RESERVOIR,
                    notes: list[str] | None = None, send: Sequence[str] = (),
                    cluster=None) -> tuple[StudySummary, Execution]:
    """Run a tolerance plan over the output ``columns`` (key -> Column: the nominal run's).
    Each chunk folds its runs where it runs (:class:`~beltcalc.sim.study.fold.FoldSpec`) and
    goes to ``on_chunk`` (with its rows as ``send`` asks: ``"csv"``, ``"table"``, ``"rows"``),
    then into the client's :class:`~beltcalc.sim.study.fold.Fold`. ``cluster``: a cluster
    already started (:func:`beltcalc.sim.study.execution.study_cluster`). Returns (summary, how
    it ran)."""
    spec = FoldSpec(tuple(plan.names), tuple(columns), tuple(limits), reservoir, frozenset(send))
    fold = Fold(spec, columns)
    batched = [0]

    def take(chunk: Chunk):
        if on_chunk is not None:
            on_chunk(chunk)
        fold.add(chunk.part)
        batched[0] += chunk.batched

    how = execute(replace(plan, fold=spec), take, workers, scheduler, notes, progress, cluster)
    return replace(fold.summary(), batched=batched[0]), how
