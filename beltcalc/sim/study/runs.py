"""The runs of a study, chunk by chunk: each run one :class:`RunRow` (every scalar it reports,
its failing checks, its warnings, or the reason it failed: a solver failure, an impossible
value drawn, e.g. a negative mass). A failing run is a row, never a stopped study.

A chunk (:func:`run_chunk`, the task a Dask worker runs) takes its rows from batched exact
propagation where the scene declares a batch row (:attr:`beltcalc.sim.scenes.base.Scene.batch`,
over :mod:`beltcalc.sim.batch`), checked against one single run per group of runs to
:data:`VERIFY_RTOL`; every other run is the scene's single run (:func:`run_one`). A tolerance
study's chunk folds its rows where it runs (:func:`beltcalc.sim.study.fold.fold_rows`) and sends
back that part, with its rows only as the study asks for them (CSV text, columns).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from beltcalc.sim.study.plan import Plan

VERIFY_RTOL = 1e-9          # the chunk's check run: the batch's row against the single run's


@dataclass
class RunRow:
    """One run: its inputs, every scalar it reports (key -> SI value), its failing checks
    (:class:`~beltcalc.design.checks.Check`), its warnings, and ``error``: why it failed (None: it
    ran), with the parameter the failure names (``param``)."""

    inputs: tuple[float, ...]
    values: dict[str, float | None]
    failed: tuple = ()
    warnings: tuple[str, ...] = ()
    error: str | None = None
    param: str | None = None       # the library parameter a failure names (BeltcalcError.param)


@dataclass
class Chunk:
    """What chunk ``index`` sends back: its rows (all of them, or none where the plan folds
    them and did not ask for them), the columns they report (key -> Column, no values),
    ``batched``: how many of its ``runs`` came from batched exact propagation
    (:func:`batch_rows`), the others from the scene's single run; where the plan folds
    (``Plan.fold``): its ``part`` (:class:`~beltcalc.sim.study.fold.Part`), the rows as CSV
    lines (``csv``) or columns (``table``) as asked; ``wall`` and ``cpu``: the seconds it took
    where it ran."""

    index: int
    rows: list[RunRow]
    columns: dict
    batched: int = 0
    runs: int = 0
    part: object = None
    csv: str | None = None
    table: dict | None = None
    wall: float = 0.0
    cpu: float = 0.0


def run_one(plan: Plan, x: Sequence[float]) -> tuple[RunRow, list]:
    """One run of ``plan.scene`` with ``plan.names`` set to ``x``: its row and its columns."""
    from beltcalc.errors import BeltcalcError
    from beltcalc.sim.scenes.base import run_scene

    x = tuple(float(v) for v in x)
    values = dict(plan.values)
    values.update(zip(plan.names, x))
    try:
        out = run_scene(plan.scene, values, plan.cfg, **plan.options)
        cols = out.column_rows()
    except BeltcalcError as exc:
        return RunRow(x, {}, error=str(exc), param=exc.param), []
    except (ArithmeticError, ValueError, np.linalg.LinAlgError, MemoryError) as exc:
        return RunRow(x, {}, error=f"{type(exc).__name__}: {exc}"), []
    except Exception as exc:                      # a defect: still a row, with its name
        return RunRow(x, {}, error=f"internal error: {type(exc).__name__}: {exc}"), []
    from beltcalc.design.checks import failures

    vals = {c.key: _finite(c.value) for c in cols}
    return RunRow(x, vals, tuple(failures(out.checks)), tuple(out.result.warnings)), cols


def _finite(value) -> float | None:
    return float(value) if isinstance(value, (int, float)) and math.isfinite(value) else None


def batch_rows(plan: Plan, X: np.ndarray) -> list[list[float] | None]:
    """Each run's row values (in its columns' order) where the scene declares a batch row
    (:attr:`beltcalc.sim.scenes.base.Scene.batched`) that can vouch for it, else None (the
    single run, one by one). The batch gets each run's SI values (``plan.values`` with
    ``plan.names`` set to the run's inputs), the solver config and the scene's options."""
    rows = plan.scene.batched
    if rows is None or len(X) == 0:
        return [None] * len(X)
    runs = []
    for x in np.asarray(X, dtype=float):
        v = dict(plan.values)
        v.update(zip(plan.names, (float(e) for e in x)))
        runs.append(v)
    return rows(runs, plan.cfg, **plan.options)


def agrees(batch: Sequence[float], values: Mapping[str, float | None], rtol: float = VERIFY_RTOL) -> bool:
    """True when the batch's row equals the single run's ``values`` (key -> SI) to ``rtol``,
    column by column in order (an absolute floor of ``rtol`` times the row's largest value,
    for a column that is zero)."""
    ref = list(values.values())
    if len(ref) != len(batch) or any(v is None for v in ref):
        return False
    a, b = np.asarray(batch, float), np.asarray(ref, float)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return False
    return bool(np.all(np.abs(a - b) <= rtol * np.maximum(np.abs(b), 1e-300) + 1e-14 * np.abs(b).max()))


def _batch(plan: Plan, X: np.ndarray) -> list:
    """Each run's row values from batched exact propagation, or None (:func:`batch_rows`;
    the batch is a faster way to the same rows: if it fails, every run goes one by one)."""
    if not plan.batch:
        return [None] * len(X)
    try:
        return batch_rows(plan, X)
    except Exception:                             # noqa: BLE001  (the single runs then say what is wrong)
        return [None] * len(X)


def run_chunk(plan: Plan, c: int, tick: Callable[[int], None] | None = None) -> Chunk:
    """Chunk ``c`` of ``plan`` (the task a Dask worker runs): one row per run, folded where
    the plan folds (:func:`finish`); ``tick(n)`` as runs finish.

    Where the scene batches, the runs go to its batch in groups of
    :data:`~beltcalc.sim.study.plan.BATCH_GROUP` aligned on the run index (a batched row is
    equal to the single run's to rounding, and which rounding depends on the runs batched with
    it: fixed groups keep every row the same whatever the chunks). In each group the runs the
    batch vouches for (:func:`batch_rows`) come from batched exact propagation; the first of
    them also runs alone, and unless the batch reproduces its row (:func:`agrees`) the whole
    group runs one by one. Every other run is the scene's single run."""
    import time

    from beltcalc.sim.study.plan import BATCH_GROUP

    w0, c0 = time.perf_counter(), time.process_time()
    lo, hi = plan.bounds(c)
    X, priority = plan.draws(lo, hi)
    rows: list = []
    columns: dict = {}
    used = 0
    a = lo
    while a < hi:
        b = min(hi, (a // BATCH_GROUP + 1) * BATCH_GROUP)
        group, n = _group(plan, X[a - lo:b - lo], columns, tick)
        rows += group
        used += n
        a = b
    chunk = finish(plan, Chunk(c, rows, columns, used), priority)
    chunk.wall, chunk.cpu = time.perf_counter() - w0, time.process_time() - c0
    return chunk


def _group(plan: Plan, X: np.ndarray, columns: dict, tick) -> tuple[list[RunRow], int]:
    """The rows of the runs ``X`` (one group of the batch: :func:`run_chunk`) and how many of
    them came from the batch; ``columns`` gains the columns the single runs report."""
    batched = _batch(plan, X)
    rows: list = [None] * len(X)

    def single(i):
        row, cols = run_one(plan, X[i])
        rows[i] = row
        for col in cols:
            if col.key not in columns:
                columns[col.key] = replace(col, value=None)
        if tick is not None:
            tick(1)
        return row

    check = next((i for i, b in enumerate(batched) if b is not None), None)
    keys = None
    if check is not None:
        row = single(check)
        if row.error is None and not row.failed and not row.warnings and agrees(batched[check], row.values):
            keys = list(row.values)
    used = 0
    for i, x in enumerate(X):
        if rows[i] is not None:
            continue
        if keys is not None and batched[i] is not None:
            rows[i] = RunRow(tuple(float(v) for v in x), {k: _finite(v) for k, v in zip(keys, batched[i])})
            used += 1
            if tick is not None:
                tick(1)
        else:
            single(i)
    return rows, used


def finish(plan: Plan, chunk: Chunk, priority) -> Chunk:
    """``chunk`` as it goes back: where ``plan.fold`` is set, its part and its rows as the fold
    asks (CSV lines, columns, the rows themselves, or none)."""
    chunk.runs = len(chunk.rows)
    spec = plan.fold
    if spec is None:
        return chunk
    from beltcalc.sim.study.fold import fold_rows

    lo, _ = plan.bounds(chunk.index)
    chunk.part = fold_rows(spec, lo, chunk.rows, priority)
    if "csv" in spec.send:
        import csv
        import io

        text = io.StringIO()
        csv.writer(text, lineterminator="\n").writerows(row_cells(r, spec.keys) for r in chunk.rows)
        chunk.csv = text.getvalue()
    if "table" in spec.send:
        chunk.table = row_table(chunk.rows, spec)
    if "rows" not in spec.send:
        chunk.rows = []
    return chunk


def failed_chunk(plan: Plan, c: int, reason: str) -> Chunk:
    """Chunk ``c`` whose task failed after its retries: every run a row with the reason."""
    X, priority = plan.draws(*plan.bounds(c))
    rows = [RunRow(tuple(float(v) for v in x), {}, error=f"task failed: {reason}") for x in X]
    return finish(plan, Chunk(c, rows, {}), priority)


def row_table(rows: Sequence[RunRow], spec) -> dict:
    """Rows as columns (key -> list): the inputs (``spec.inputs``' CSV keys are the caller's:
    here ``input_0 ..``), ``spec.keys``, ``failed_checks``, ``warnings`` (count), ``error``."""
    data = {f"input_{i}": [r.inputs[i] for r in rows] for i in range(len(spec.inputs))}
    data.update({k: [r.values.get(k) for r in rows] for k in spec.keys})
    data["failed_checks"] = [";".join(c.key for c in r.failed) for r in rows]
    data["warnings"] = [len(r.warnings) for r in rows]
    data["error"] = [r.error for r in rows]
    return data


def row_cells(row: RunRow, keys: Iterable[str]) -> list:
    """A row as CSV cells in the order: inputs, ``keys``, failed checks, warnings count, error."""
    return ([repr(float(x)) for x in row.inputs]
            + ["" if row.values.get(k) is None else repr(row.values[k]) for k in keys]
            + [";".join(c.key for c in row.failed), str(len(row.warnings)), row.error or ""])
