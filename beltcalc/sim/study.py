"""Studies of a scene: grids over several parameters and tolerance (Monte Carlo) studies,
in-process or on Dask, each run reduced to its summary row.

A study is a list of runs of one scene (:class:`~beltcalc.sim.scenes.base.Scene`): the
scene's SI values with some of them replaced, either by the points of a grid (the product
of several ``NAME=START:STOP:N`` sweeps) or by values drawn from distributions
(:class:`Distribution`: normal, uniform, triangular). Each run gives one :class:`RunRow`:
every scalar the run reports (:meth:`~beltcalc.sim.scenes.base.Outcome.column_rows`), its
failing checks, its warnings, or the reason it failed (``error``: a solver failure, an
impossible value drawn, e.g. a negative mass). A failing run is a row, never a stopped
study.

Runs go in chunks of :data:`CHUNK` (:func:`run_chunk`). The values of chunk ``c`` are
drawn from ``numpy.random.SeedSequence(seed, spawn_key=(c,))`` (the ``c``-th child of
``SeedSequence(seed).spawn``), so the rows do not depend on how many workers run them, and
come back in chunk order. :func:`execute` runs the chunks in this process or on Dask (a
local cluster of processes, or an existing scheduler), each task retried on failure.

A tolerance study keeps no rows: :class:`Accumulator` folds each chunk into sums of fixed
size (exact mean, standard deviation, min and max, standardised regression coefficients
from co-moment matrices merged by Chan et al.'s pairwise update) and a reservoir of
:data:`RESERVOIR` rows (Vitter's algorithm R) for percentiles and Spearman rank
correlations; memory is constant in the number of runs. SI floats; no click, no pint
(texts are read through :mod:`beltcalc.params` and :mod:`beltcalc.units`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from beltcalc.errors import UsageError, did_you_mean
from beltcalc.params import Param, bare_number

CHUNK = 250              # runs per task
RESERVOIR = 10_000       # rows kept for percentiles and rank correlations
MAX_RUNS = 10_000_000
MAX_GRID = 1_000_000     # points of a grid (its rows are kept for the table)
DASK_MIN_RUNS = 200      # below this a local cluster costs more than it saves
PERCENTILES = (1, 5, 50, 95, 99)
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
MAX_DISTINCT = 50        # distinct warnings / failure reasons kept (the rest counted)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


# --- distributions ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Distribution:
    """A distribution of one parameter, SI: ``normal`` (mean, sd), ``uniform`` (lo, hi),
    ``triangular`` (lo, mode, hi). ``text`` is what the user wrote.

    >>> d = Distribution("triangular", (1.0, 2.0, 4.0), "N")
    >>> round(d.mean, 6), round(d.sd, 6)
    (2.333333, 0.62361)
    """

    kind: str
    args: tuple[float, ...]
    unit: str = "1"
    text: str = ""

    @property
    def mean(self) -> float:
        a = self.args
        return {"normal": a[0], "uniform": (a[0] + a[1]) / 2}.get(self.kind, sum(a) / 3)

    @property
    def sd(self) -> float:
        a = self.args
        if self.kind == "normal":
            return a[1]
        if self.kind == "uniform":
            return (a[1] - a[0]) / math.sqrt(12)
        lo, mode, hi = a
        return math.sqrt((lo * lo + mode * mode + hi * hi - lo * mode - lo * hi - mode * hi) / 18)

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` values drawn with ``rng`` (a spread of 0 gives the value itself, exactly)."""
        a = self.args
        if self.kind == "normal":
            return a[0] + a[1] * rng.standard_normal(n)
        u = rng.random(n)
        if self.kind == "uniform":
            return a[0] + (a[1] - a[0]) * u
        lo, mode, hi = a                         # inverse CDF of the triangular distribution
        if hi == lo:
            return np.full(n, lo)
        f = (mode - lo) / (hi - lo)
        return np.where(u < f, lo + np.sqrt(u * (hi - lo) * (mode - lo)),
                        hi - np.sqrt((1 - u) * (hi - lo) * (hi - mode)))

    def to_dict(self) -> dict:
        """JSON-ready: the kind, its arguments as ``{"value", "unit"}``, mean and sd."""
        names = {"normal": ("mean", "sd"), "uniform": ("low", "high"), "triangular": ("low", "mode", "high")}
        q = lambda v: {"value": v, "unit": self.unit}  # noqa: E731
        return {"kind": self.kind, "text": self.text, **{k: q(v) for k, v in zip(names[self.kind], self.args)},
                "mean": q(self.mean), "sd": q(self.sd)}


_ARITY = {"normal": 2, "uniform": 2, "triangular": 3}


def parse_vary(params: Sequence[Param], text: str) -> tuple[str, Distribution]:
    """``NAME=normal(MEAN,SD or P%)``, ``NAME=uniform(LOW,HIGH)``,
    ``NAME=triangular(LOW,MODE,HIGH)`` -> (name, :class:`Distribution` in SI).

    Values are read as ``--set NAME=...`` reads them (a dimensioned parameter needs units).
    Anything else is a :class:`~beltcalc.errors.UsageError` (``param="vary"``).

    >>> p = [Param("C4", "N*m/rad", "stiffness")]
    >>> parse_vary(p, "C4=normal(260N*m/rad,5%)")[1].args
    (260.0, 13.0)
    >>> parse_vary(p, "C4=uniform(0.2kN*m/rad, 300 N*m/rad)")[1].args
    (200.0, 300.0)
    >>> parse_vary(p, "C4=normal(260,5%)")
    Traceback (most recent call last):
    ...
    beltcalc.errors.UsageError: vary: 'C4=normal(260,5%)': C4 needs units, e.g. 'C4=normal(260 N*m/rad,5%)'
    """
    from beltcalc.params import parse_assignments
    from beltcalc.units import quote

    name, sep, rest = text.partition("=")
    name = name.strip()
    m = re.fullmatch(r"\s*([a-z]+)\s*\((.*)\)\s*", rest)
    if not sep or m is None or m.group(1) not in _ARITY:
        raise UsageError(f"{quote(text)}: use NAME=normal(MEAN,SD or P%), NAME=uniform(LOW,HIGH) or "
                         "NAME=triangular(LOW,MODE,HIGH)", param="vary")
    kind, args = m.group(1), [a.strip() for a in m.group(2).split(",")]
    if len(args) != _ARITY[kind]:
        raise UsageError(f"{quote(text)}: {kind} takes {_ARITY[kind]} values, got {len(args)}", param="vary")
    param = next((p for p in params if p.name == name), None)
    if param is None:
        parse_assignments(params, [f"{name}=0"])      # the unknown name, with the closest ones
    if param.unit is None or param.unit == "int" or "|" in param.unit:
        raise UsageError(f"{quote(text)}: {name} cannot be varied (it is not a single continuous quantity)",
                         param="vary")
    percent = kind == "normal" and args[1].endswith("%")
    values = []
    for k, a in enumerate(args):
        if percent and k == 1:
            try:
                values.append(float(a[:-1]) / 100.0 * abs(values[0]))
            except ValueError:
                raise UsageError(f"{quote(text)}: {quote(a)} is not a percentage", param="vary") from None
            continue
        if param.unit not in ("", "1") and bare_number(a):
            example = ",".join(f"{x} {param.unit}" if bare_number(x) and not (percent and j == 1) else x
                               for j, x in enumerate(args))
            raise UsageError(f"{quote(text)}: {name} needs units, e.g. '{name}={kind}({example})'", param="vary")
        try:
            values.append(float(parse_assignments([param], [f"{name}={a}"])[name]))
        except UsageError as exc:
            raise UsageError(f"{quote(text)}: {exc.message.split(': ', 1)[-1]}", param="vary") from None
    if kind == "normal" and values[1] < 0:
        raise UsageError(f"{quote(text)}: the standard deviation must be >= 0", param="vary")
    if kind == "uniform" and values[0] > values[1]:
        raise UsageError(f"{quote(text)}: LOW must be <= HIGH", param="vary")
    if kind == "triangular" and not values[0] <= values[1] <= values[2]:
        raise UsageError(f"{quote(text)}: it needs LOW <= MODE <= HIGH", param="vary")
    unit = param.unit if param.unit not in ("", None) else "1"
    return name, Distribution(kind, tuple(values), unit, text)


# --- limits ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Limit:
    """A limit on one output column: ``value op bound`` passes (``op`` ``>=`` or ``<=``)."""

    key: str
    op: str
    bound: float
    unit: str
    text: str

    def fails(self, y: np.ndarray) -> np.ndarray:
        return y < self.bound if self.op == ">=" else y > self.bound


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


def wilson(failed: int, n: int, z: float = Z95) -> tuple[float | None, float | None]:
    """Wilson score interval of a fraction ``failed / n`` (95 % by default); (None, None) for n = 0.

    >>> [round(x, 4) for x in wilson(0, 100)]
    [0.0, 0.037]
    >>> [round(x, 4) for x in wilson(10, 100)]
    [0.0552, 0.1744]
    """
    if n <= 0:
        return None, None
    p = failed / n
    d = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / d
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (0.0 if failed == 0 else max(0.0, centre - half)), (1.0 if failed == n else min(1.0, centre + half))


# --- the plan and one chunk ---------------------------------------------------------------------

@dataclass(frozen=True)
class Plan:
    """What to run: ``scene`` at SI ``values``, with the inputs ``names`` replaced per run by
    a grid's points (``grid``: one list of points per name, the product in row-major order)
    or by draws from ``dists`` (``runs`` of them, ``seed``)."""

    scene: object
    values: Mapping[str, object]
    cfg: object
    names: tuple[str, ...]
    grid: tuple[tuple[float, ...], ...] | None = None
    dists: tuple[Distribution, ...] | None = None
    runs: int = 0
    seed: int = 0
    chunk: int = CHUNK
    options: Mapping[str, object] = field(default_factory=dict)
    batch: bool = True             # batched exact propagation where the scene has one (beltcalc.sim.batch)

    @property
    def n_runs(self) -> int:
        return math.prod(len(g) for g in self.grid) if self.grid is not None else self.runs

    @property
    def n_chunks(self) -> int:
        return -(-self.n_runs // self.chunk)

    def inputs(self, c: int) -> np.ndarray:
        """The input values of chunk ``c``: one row per run, one column per name."""
        lo, hi = c * self.chunk, min((c + 1) * self.chunk, self.n_runs)
        if self.grid is not None:
            idx = np.unravel_index(np.arange(lo, hi), [len(g) for g in self.grid])
            return np.column_stack([np.asarray(g, float)[i] for g, i in zip(self.grid, idx)]) \
                if self.grid else np.zeros((hi - lo, 0))
        rng = np.random.default_rng(np.random.SeedSequence(self.seed, spawn_key=(c,)))
        return np.column_stack([d.sample(rng, hi - lo) for d in self.dists]) if self.dists \
            else np.zeros((hi - lo, 0))


@dataclass
class RunRow:
    """One run: its inputs, every scalar it reports (key -> SI value), its failing checks
    (:class:`~beltcalc.checks.Check`), its warnings, and ``error``: why it failed (None: it
    ran), with the parameter the failure names (``param``)."""

    inputs: tuple[float, ...]
    values: dict[str, float | None]
    failed: tuple = ()
    warnings: tuple[str, ...] = ()
    error: str | None = None
    param: str | None = None       # the library parameter a failure names (BeltcalcError.param)


@dataclass
class Chunk:
    """The rows of chunk ``index`` and the columns they report (key -> Column, no values);
    ``batched``: how many of the rows came from batched exact propagation
    (:mod:`beltcalc.sim.batch`), the others from the scene's single run."""

    index: int
    rows: list[RunRow]
    columns: dict
    batched: int = 0


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
    from beltcalc.checks import failures

    vals = {c.key: _finite(c.value) for c in cols}
    return RunRow(x, vals, tuple(failures(out.checks)), tuple(out.result.warnings)), cols


def _finite(value) -> float | None:
    return float(value) if isinstance(value, (int, float)) and math.isfinite(value) else None


def _batch(plan: Plan, X: np.ndarray) -> list:
    """Each run's row values from batched exact propagation, or None (:func:`beltcalc.sim.batch.batch_rows`;
    the batch is a faster way to the same rows: if it fails, every run goes one by one)."""
    if not plan.batch:
        return [None] * len(X)
    from beltcalc.sim.batch import batch_rows

    try:
        return batch_rows(plan, X)
    except Exception:                             # noqa: BLE001  (the single runs then say what is wrong)
        return [None] * len(X)


def run_chunk(plan: Plan, c: int, tick: Callable[[int], None] | None = None) -> Chunk:
    """Chunk ``c`` of ``plan``: one row per run (the task a Dask worker runs); ``tick(n)``
    as runs finish.

    The runs the scene's batch vouches for (:mod:`beltcalc.sim.batch`) come from batched
    exact propagation; the first of them also runs alone, and unless the batch reproduces its
    row (:func:`beltcalc.sim.batch.agrees`) the whole chunk runs one by one. Every other run
    is the scene's single run."""
    from beltcalc.sim.batch import agrees

    X = plan.inputs(c)
    batched = _batch(plan, X)
    rows: list = [None] * len(X)
    columns: dict = {}

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
    return Chunk(c, rows, columns, used)


def failed_chunk(plan: Plan, c: int, reason: str) -> Chunk:
    """Chunk ``c`` whose task failed after its retries: every run a row with the reason."""
    return Chunk(c, [RunRow(tuple(float(v) for v in x), {}, error=f"task failed: {reason}") for x in plan.inputs(c)], {})


# --- execution ----------------------------------------------------------------------------------

def dask_available() -> bool:
    """True when dask.distributed can be imported (``pip install "beltcalc[dist]"``)."""
    import importlib.util

    return importlib.util.find_spec("distributed") is not None and importlib.util.find_spec("dask") is not None


def execute(plan: Plan, on_chunk: Callable[[Chunk], None], workers: int | None = None,
            scheduler: str | None = None, notes: list[str] | None = None,
            progress: Callable[[int], None] | None = None) -> str:
    """Run every chunk of ``plan`` and hand each to ``on_chunk`` in chunk order.

    ``scheduler`` (``tcp://HOST:PORT``): an existing Dask cluster. Else ``workers`` processes
    of a local Dask cluster (default: the CPU count) when dask is installed, the study has
    more than :data:`DASK_MIN_RUNS` runs and ``workers`` > 1; otherwise in this process.
    Returns how it ran (``"in-process"``, ``"dask local cluster, N workers"``,
    ``"dask scheduler ADDRESS"``); ``notes`` receives why it did not use Dask when asked;
    ``progress(n)`` is called as runs finish (after each run in this process, after each
    chunk on Dask).
    """
    import os

    from beltcalc.units import quote

    if scheduler is not None and not re.fullmatch(r"(tcp|tls|ucx|ws|wss|inproc)://[^\s]{1,200}", scheduler):
        raise UsageError(f"{quote(scheduler)}: give the scheduler's address, e.g. tcp://HOST:8786", param="scheduler")
    workers = workers or os.cpu_count() or 1
    if scheduler is None and (workers <= 1 or plan.n_runs <= DASK_MIN_RUNS):
        return _in_process(plan, on_chunk, progress)
    if not dask_available():
        if scheduler is not None:
            raise UsageError('a Dask scheduler needs dask: pip install "beltcalc[dist]"', param="scheduler")
        if notes is not None:
            notes.append(f'dask is not installed: the {plan.n_runs} runs go in this process, one at a time '
                         '(pip install "beltcalc[dist]" for a local cluster of processes)')
        return _in_process(plan, on_chunk, progress)
    return _on_dask(plan, on_chunk, workers, scheduler, progress)


def _in_process(plan: Plan, on_chunk, progress=None) -> str:
    for c in range(plan.n_chunks):
        on_chunk(run_chunk(plan, c, progress))
    return "in-process"


# dask's workers start with MALLOC_TRIM_THRESHOLD_=65536, which also fixes glibc's mmap
# threshold at 128 KiB: every array of a run (a batch pass, a time series) is then a fresh
# mmap whose pages fault in again, and a chunk costs 1.8x its CPU time in this process
# (benchmarks/studies.py). Arrays up to 32 MiB come from the heap instead, and the heap is
# trimmed above 128 MiB: a worker keeps at most that much freed memory.
WORKER_MALLOC = {"MALLOC_MMAP_THRESHOLD_": str(32 * 2 ** 20), "MALLOC_TRIM_THRESHOLD_": str(128 * 2 ** 20)}


def _on_dask(plan: Plan, on_chunk, workers: int, scheduler: str | None, progress=None, retries: int = 2) -> str:
    """The chunks on an existing scheduler, or on a local cluster of ``workers`` processes;
    Dask's own log lines kept off stderr meanwhile (:mod:`beltcalc.sim.cluster`)."""
    from beltcalc.sim.cluster import local_cluster, quiet_logs, scheduler_client

    with quiet_logs():
        if scheduler is not None:
            with scheduler_client(scheduler) as client:
                _run_on(client, plan, on_chunk, 1, progress, retries)
            return f"dask scheduler {scheduler}"
        with local_cluster(workers, WORKER_MALLOC) as client:
            _run_on(client, plan, on_chunk, workers, progress, retries)
        return f"dask local cluster, {workers} worker{'' if workers == 1 else 's'}"


def _run_on(client, plan: Plan, on_chunk, workers: int, progress, retries: int) -> None:
    """Every chunk of ``plan`` as a task of ``client``, at most about two per worker in
    flight, handed to ``on_chunk`` in chunk order; a task that fails after its retries is
    its chunk's rows with the reason."""
    import uuid

    from distributed import as_completed

    shared = client.scatter(plan, broadcast=True)
    n = plan.n_chunks
    cap = 2 * max(len(client.scheduler_info().get("workers", {})), workers) + 2
    token = uuid.uuid4().hex
    nxt, done, pending, which = 0, 0, {}, {}
    ac = as_completed()
    while done < n:
        while nxt < n and (nxt - done) < cap:
            fut = client.submit(run_chunk, shared, nxt, retries=retries, pure=False,
                                key=f"beltcalc-chunk-{nxt}-{token}")
            which[fut.key] = nxt
            ac.add(fut)
            nxt += 1
        fut = next(ac)
        c = which.pop(fut.key)
        try:
            pending[c] = fut.result()
        except Exception as exc:              # the task failed after its retries: rows with the reason
            pending[c] = failed_chunk(plan, c, f"{type(exc).__name__}: {exc}")
        fut.release()
        if progress is not None:
            progress(len(pending[c].rows))
        while done in pending:
            on_chunk(pending.pop(done))
            done += 1


# --- grids: rows in memory ----------------------------------------------------------------------

def grid_rows(plan: Plan, progress: Callable[[int], None] | None = None, workers: int | None = None,
              scheduler: str | None = None, notes: list[str] | None = None) -> tuple[list[RunRow], dict, str]:
    """Every run of a grid plan, in order: (rows, columns in the order first met, how it ran)."""
    rows: list[RunRow] = []
    columns: dict = {}

    def take(chunk: Chunk):
        rows.extend(chunk.rows)
        for k, col in chunk.columns.items():
            columns.setdefault(k, col)

    how = execute(plan, take, workers, scheduler, notes, progress)
    return rows, columns, how


# --- tolerance studies: constant memory ---------------------------------------------------------

class _Moments:
    """Count, means and co-moment matrix of vectors [inputs..., one output], merged batch by
    batch (Chan, Golub & LeVeque 1979): exact and of fixed size."""

    __slots__ = ("n", "mean", "M")

    def __init__(self, k: int):
        self.n, self.mean, self.M = 0, np.zeros(k), np.zeros((k, k))

    def add(self, Z: np.ndarray) -> None:
        nb = Z.shape[0]
        if nb == 0:
            return
        mb = Z.mean(axis=0)
        D = Z - mb
        Mb = D.T @ D
        n = self.n + nb
        delta = mb - self.mean
        self.M += Mb + np.outer(delta, delta) * (self.n * nb / n)
        self.mean += delta * (nb / n)
        self.n = n


class Accumulator:
    """Folds the rows of a tolerance study, chunk by chunk, into what its report needs.

    ``inputs``: the varied names; ``columns``: key -> Column of the outputs (the nominal run's);
    ``limits``: :class:`Limit` on some of them. Memory is fixed: per output a co-moment matrix
    of (inputs + 1)^2, min and max; a reservoir of ``reservoir`` rows; counts of failures,
    failing checks and warnings (at most :data:`MAX_DISTINCT` distinct texts each).
    """

    def __init__(self, inputs: Sequence[str], columns: Mapping[str, object], limits: Sequence[Limit] = (),
                 reservoir: int = RESERVOIR, seed: int = 0):
        self.inputs, self.keys = list(inputs), list(columns)
        self.columns = dict(columns)
        self.limits = list(limits)
        k, m = len(self.inputs), len(self.keys)
        self.moments = [_Moments(k + 1) for _ in self.keys]
        self.lo, self.hi = np.full(m, np.inf), np.full(m, -np.inf)
        self.cap = reservoir
        self.res = np.full((reservoir, k + m), np.nan)
        self.rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2 ** 31,)))
        self.runs = self.errors = 0
        self.reasons: dict[str, list] = {}          # reason -> [count, first run]
        self.more_reasons = 0
        self.checks: dict[str, list] = {}           # check key -> [count, first failing Check]
        self.warnings: dict[str, int] = {}
        self.more_warnings = 0
        self.limit_counts = [[0, 0] for _ in self.limits]     # [evaluated, failed]
        self.extra_keys: set[str] = set()

    def add(self, rows: Sequence[RunRow]) -> None:
        """Fold one chunk's rows (in run order)."""
        k, m = len(self.inputs), len(self.keys)
        X = np.array([r.inputs for r in rows], float).reshape(len(rows), k)
        Y = np.array([[np.nan if r.values.get(key) is None else r.values[key] for key in self.keys] for r in rows],
                     float).reshape(len(rows), m)
        for i, r in enumerate(rows):
            run = self.runs + i
            if r.error is not None:
                self.errors += 1
                kind = _NUMBER.sub("#", r.error)           # one reason whatever the value drawn
                if kind in self.reasons:
                    self.reasons[kind][0] += 1
                elif len(self.reasons) < MAX_DISTINCT:
                    self.reasons[kind] = [1, run, r.error]
                else:
                    self.more_reasons += 1
                continue
            for c in r.failed:
                entry = self.checks.setdefault(c.key, [0, c])
                entry[0] += 1
            for w in r.warnings:
                if w in self.warnings:
                    self.warnings[w] += 1
                elif len(self.warnings) < MAX_DISTINCT:
                    self.warnings[w] = 1
                else:
                    self.more_warnings += 1
            if len(r.values) > m or any(key not in self.columns for key in r.values):
                self.extra_keys.update(key for key in r.values if key not in self.columns)
        for j in range(m):
            y = Y[:, j]
            ok = np.isfinite(y)
            if ok.any():
                self.moments[j].add(np.column_stack([X[ok], y[ok]]))
                self.lo[j] = min(self.lo[j], y[ok].min())
                self.hi[j] = max(self.hi[j], y[ok].max())
        for L, counts in zip(self.limits, self.limit_counts):
            y = Y[:, self.keys.index(L.key)]
            ok = np.isfinite(y)
            counts[0] += int(ok.sum())
            counts[1] += int(L.fails(y[ok]).sum())
        self._reservoir(np.column_stack([X, Y]))
        self.runs += len(rows)

    def _reservoir(self, Z: np.ndarray) -> None:
        """Algorithm R over the rows in run order (deterministic: its own seeded stream)."""
        t0, n = self.runs, Z.shape[0]
        fill = max(0, min(n, self.cap - t0))
        if fill:
            self.res[t0:t0 + fill] = Z[:fill]
        if fill < n:
            t = np.arange(t0 + fill, t0 + n)
            j = self.rng.integers(0, t + 1)
            keep = j < self.cap
            slots, src = j[keep], np.nonzero(keep)[0] + fill
            if slots.size:                       # a slot drawn twice keeps its last row
                last = {s: r for s, r in zip(slots.tolist(), src.tolist())}
                self.res[list(last)] = Z[list(last.values())]

    def summary(self) -> "StudySummary":
        """The report: per output its statistics and the inputs that move it most."""
        from scipy.stats import rankdata

        k = len(self.inputs)
        kept = min(self.runs, self.cap)
        R = self.res[:kept]
        outputs = {}
        for j, key in enumerate(self.keys):
            mo = self.moments[j]
            entry = {"n": mo.n}
            if mo.n == 0:
                outputs[key] = entry
                continue
            cov = mo.M / max(mo.n - 1, 1)
            sd = math.sqrt(max(cov[k, k], 0.0))
            entry.update(mean=float(mo.mean[k]), sd=sd if mo.n > 1 else None, min=float(self.lo[j]),
                         max=float(self.hi[j]))
            y = R[:, k + j]
            ok = np.isfinite(y)
            if ok.any():
                pct = np.percentile(y[ok], PERCENTILES)
                entry.update({f"p{p}": float(v) for p, v in zip(PERCENTILES, pct)})
            src, r2 = _src(cov, k)
            rho = [None] * k
            if ok.sum() > 2 and np.ptp(y[ok]) > 0:
                ry = rankdata(y[ok])
                for i in range(k):
                    x = R[ok, i]
                    if np.ptp(x) > 0:
                        rho[i] = float(np.corrcoef(rankdata(x), ry)[0, 1])
            entry["influence"] = sorted(
                ({"input": name, "src": s, "spearman": r} for name, s, r in zip(self.inputs, src, rho)),
                key=lambda e: -abs(e["src"] if e["src"] is not None else (e["spearman"] or 0.0)))
            entry["r2"] = r2
            outputs[key] = entry
        limits = []
        for L, (n, f) in zip(self.limits, self.limit_counts):
            lo, hi = wilson(f, n)
            limits.append({"limit": L, "evaluated": n, "failed": f, "fraction": f / n if n else None,
                           "ci95": (lo, hi)})
        return StudySummary(self.runs, self.errors, kept, outputs, limits,
                            sorted(((text, [k, first]) for k, first, text in self.reasons.values()),
                                   key=lambda kv: -kv[1][0]), self.more_reasons,
                            {key: (n, c) for key, (n, c) in self.checks.items()}, dict(self.warnings),
                            self.more_warnings, sorted(self.extra_keys), R.copy())


def _src(cov: np.ndarray, k: int) -> tuple[list[float | None], float | None]:
    """Standardised regression coefficients of the last variable of ``cov`` on the first ``k``
    (least squares on the co-moments; inputs that did not vary: None), and the fit's R^2."""
    out: list[float | None] = [None] * k
    sy2 = cov[k, k]
    live = [i for i in range(k) if cov[i, i] > 0]
    if not live or sy2 <= 0:
        return out, None
    Cxx = cov[np.ix_(live, live)]
    cxy = cov[live, k]
    b, *_ = np.linalg.lstsq(Cxx, cxy, rcond=None)
    sy = math.sqrt(sy2)
    for i, bi in zip(live, b):
        out[i] = float(bi * math.sqrt(cov[i, i]) / sy)
    r2 = float(cxy @ b / sy2)
    return out, min(max(r2, 0.0), 1.0)


@dataclass
class StudySummary:
    """What a tolerance study reports (all SI): ``runs`` (``errors`` of them failed),
    ``kept`` rows in the reservoir, per output key its statistics, the limits' failure
    fractions with Wilson 95 % intervals, the failure reasons ((the first run's text, [runs,
    first run]) for each reason, texts that differ only in their numbers counted as one),
    the failing checks (key -> (runs, a failing Check)), the warnings (text -> runs), and
    keys some run reported that the nominal run did not (left out of the statistics), and
    the reservoir's rows (``sample``)."""

    runs: int
    errors: int
    kept: int
    outputs: dict
    limits: list
    reasons: list
    more_reasons: int
    checks: dict
    warnings: dict
    more_warnings: int
    extra_keys: list
    sample: np.ndarray | None = None     # the reservoir: rows of [inputs..., outputs...]
    batched: int = 0                     # rows from batched exact propagation (beltcalc.sim.batch)

    @property
    def propagation(self) -> str:
        """Which path computed the rows: batched exact propagation, the single run, or both."""
        return propagation(self.batched, self.runs)


def propagation(batched: int, runs: int) -> str:
    """The study's method text: how many of ``runs`` rows came from batched exact propagation.

    >>> print(propagation(990, 1000))
    batched exact propagation for 990 of 1,000 runs (beltcalc.sim.batch); the other 10 one by one (the scene's single run: one check run per chunk, and runs the batch does not cover)
    >>> print(propagation(0, 5))
    one by one (the scene's single run)
    """
    if batched == 0:
        return "one by one (the scene's single run)"
    text = f"batched exact propagation for {batched:,} of {runs:,} runs (beltcalc.sim.batch)"
    if batched < runs:
        text += (f"; the other {runs - batched:,} one by one (the scene's single run: one check run per chunk, "
                 "and runs the batch does not cover)")
    return text


def tolerance_study(plan: Plan, columns: Mapping[str, object], limits: Sequence[Limit] = (),
                    on_rows: Callable[[Chunk], None] | None = None, progress: Callable[[int], None] | None = None,
                    workers: int | None = None, scheduler: str | None = None, reservoir: int = RESERVOIR,
                    notes: list[str] | None = None) -> tuple[StudySummary, str]:
    """Run a tolerance plan; each chunk goes to ``on_rows`` (to stream it to a file) and into
    an :class:`Accumulator` over ``columns`` (the nominal run's). Returns (summary, how it ran)."""
    acc = Accumulator(plan.names, columns, limits, reservoir, plan.seed)
    batched = [0]

    def take(chunk: Chunk):
        if on_rows is not None:
            on_rows(chunk)
        acc.add(chunk.rows)
        batched[0] += chunk.batched

    how = execute(plan, take, workers, scheduler, notes, progress)
    return replace(acc.summary(), batched=batched[0]), how


def row_cells(row: RunRow, keys: Iterable[str]) -> list:
    """A row as CSV cells in the order: inputs, ``keys``, failed checks, warnings count, error."""
    return ([repr(float(x)) for x in row.inputs]
            + ["" if row.values.get(k) is None else repr(row.values[k]) for k in keys]
            + [";".join(c.key for c in row.failed), str(len(row.warnings)), row.error or ""])
