"""How a study runs: every chunk of a :class:`~beltcalc.sim.study.plan.Plan`
(:func:`~beltcalc.sim.study.runs.run_chunk`) in this process or on Dask (a local cluster of
processes, or an existing scheduler: :mod:`beltcalc.sim.study.cluster`; one cluster for
several studies: :func:`study_cluster`), each task retried on failure, the chunks handed on in
chunk order (:func:`execute`) with how long each part took (:class:`Execution`); a grid's rows
kept in memory (:func:`grid_rows`).
"""

from __future__ import annotations

import re
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Iterator

from beltcalc.errors import UsageError
from beltcalc.sim.study.plan import Plan
from beltcalc.sim.study.runs import Chunk, RunRow, failed_chunk, run_chunk

DASK_MIN_RUNS = 200      # below this a local cluster costs more than it saves
PROBE_S = 0.3            # the work of the first chunk, which times a run here (one group where the scene batches)
# what a local cluster costs a study, about: Dask's import, its start, the workers' import of the
# runs' code, its close (1.0 s for 2 workers on 2 cores, commands timed; 4.5 s for 16 workers in
# issue 34). On 2 cores a sewing study of 2,000 batched runs stays here, one of 3,000 goes to the
# workers; near there either choice costs under 0.4 s (the first chunk's first calls make a run
# look dearer, and the timed chunk delays the cluster's start).
START_S, START_S_PER_WORKER = 0.5, 0.25


def dask_available() -> bool:
    """True when dask.distributed can be imported (``pip install "beltcalc[dist]"``)."""
    import importlib.util

    return importlib.util.find_spec("distributed") is not None and importlib.util.find_spec("dask") is not None


@dataclass
class Execution:
    """How a study ran: ``how`` in words, on how many ``workers``, in how many ``chunks`` of
    ``chunk`` runs; the seconds it took to start the local cluster or reach the scheduler and
    have the workers import the runs' code (``start``, 0 in this process), to compute every
    chunk (``compute``: from the first chunk sent to the last one handed on), this process's
    CPU meanwhile (``client_cpu``: handing chunks out, merging what comes back, writing the
    rows; in this process, the runs too), and the chunks' own wall and CPU time where they
    ran (``chunk_wall``, ``chunk_cpu``); ``why`` it ran where it did, when that was measured
    (:func:`execute`)."""

    how: str
    workers: int = 1
    chunks: int = 0
    chunk: int = 0
    runs: int = 0
    start: float = 0.0
    compute: float = 0.0
    client_cpu: float = 0.0
    chunk_wall: float = 0.0
    chunk_cpu: float = 0.0
    why: str = ""

    @property
    def busy(self) -> float | None:
        """The workers' busy fraction: the chunks' wall time over ``workers`` x ``compute``."""
        return self.chunk_wall / (self.workers * self.compute) if self.compute > 0 else None

    def to_dict(self) -> dict:
        """JSON-ready, SI (``{"value", "unit"}``)."""
        q = lambda v, u: {"value": v, "unit": u}  # noqa: E731
        remote = self.how != "in-process"
        return {"how": self.how, "workers": self.workers, "chunks": self.chunks, "runs_per_chunk": self.chunk,
                "cluster_start": q(self.start, "s"), "compute_wall": q(self.compute, "s"),
                "client_cpu": q(self.client_cpu, "s"),
                "client_cpu_per_run": q(self.client_cpu / self.runs if self.runs else None, "s"),
                "worker_cpu": q(self.chunk_cpu, "s"),
                "client_cpu_share": q(self.client_cpu / self.chunk_cpu if remote and self.chunk_cpu > 0 else None,
                                      "1"),
                "worker_busy": q(self.busy, "1"), "why": self.why or None}

    def text(self) -> str:
        """One line for the report.

        >>> print(Execution("dask local cluster, 2 workers", 2, 50, 1000, 50_000, 0.8, 24.0, 0.3, 47.5, 47.0).text())
        2 workers, 50 chunks of up to 1,000 runs: cluster start 0.8 s, compute 24 s, workers busy 99%; this process 0.3 s of CPU (0.64% of the workers')
        """
        who = f"{self.workers} worker{'' if self.workers == 1 else 's'}" if self.how != "in-process" else "in this process"
        line = f"{who}, {self.chunks:,} chunk{'' if self.chunks == 1 else 's'} of up to {self.chunk:,} runs: "
        why = f" ({self.why})" if self.why else ""
        if self.how == "in-process":
            return line + f"compute {self.compute:.3g} s{why}"
        busy = "" if self.busy is None else f", workers busy {self.busy:.0%}"
        share = f" ({self.client_cpu / self.chunk_cpu:.2%} of the workers')" if self.chunk_cpu > 0 else ""
        return (line + f"cluster start {self.start:.2g} s, compute {self.compute:.3g} s{busy}; this process "
                f"{self.client_cpu:.2g} s of CPU{share}{why}")


def execute(plan: Plan, on_chunk: Callable[[Chunk], None], workers: int | None = None,
            scheduler: str | None = None, notes: list[str] | None = None,
            progress: Callable[[int], None] | None = None, cluster=None) -> Execution:
    """Run every chunk of ``plan`` and hand each to ``on_chunk`` in chunk order; the chunks
    are sized for the workers that run them (:meth:`~beltcalc.sim.study.plan.Plan.sized`)
    unless the plan fixes them.

    ``cluster``: a cluster already started (:func:`study_cluster`: studies in a row pay its
    start once). Else ``scheduler`` (``tcp://HOST:PORT``): an existing Dask cluster. Else
    ``workers`` processes of a local Dask cluster when dask is installed, the study has more
    than :data:`DASK_MIN_RUNS` runs and ``workers`` > 1; otherwise in this process. With
    ``workers`` not given (None: up to the CPU count), the study's first chunk runs here and
    measures a run (:func:`_measured`): the rest goes to a local cluster only where it would
    take longer here than the cluster's start costs. Returns how it ran (:class:`Execution`: ``how`` is
    ``"in-process"``, ``"dask local cluster, N workers"`` or ``"dask scheduler ADDRESS"``);
    ``notes`` receives why it did not use Dask when asked; ``progress(n)`` is called as runs
    finish (after each run in this process, after each chunk on Dask).
    """
    import os

    if cluster is not None:
        return _run_on(cluster, plan, on_chunk, progress)
    check_scheduler(scheduler)
    auto = workers is None
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
    if auto and scheduler is None and not plan.chunk:
        return _measured(plan, on_chunk, workers, progress)
    with study_cluster(workers, scheduler) as started:
        return _run_on(started, plan, on_chunk, progress)


def _measured(plan: Plan, on_chunk, workers: int, progress=None) -> Execution:
    """The first chunk in this process (about :data:`PROBE_S` of work by the nominal run's
    time, or one batch group), then the rest here or on a local cluster of ``workers``: on the
    cluster where the rest would take longer here than its start (:data:`START_S` +
    :data:`START_S_PER_WORKER` a worker) repays, ``S W / (W - 1)``. The rows and the summary
    are those of any other chunking."""
    import math
    import time

    from dataclasses import replace

    unit, n = plan.unit, plan.n_runs
    first = unit if unit > 1 or not plan.run_cost else max(1, math.ceil(PROBE_S / plan.run_cost))
    first = min(n, first)
    here = plan.after(first, 1)
    w0, c0 = time.perf_counter(), time.process_time()
    chunk = run_chunk(here, 0, progress)
    wall, cpu, runs = chunk.wall, chunk.cpu, chunk.runs
    on_chunk(chunk)
    del chunk
    rest = (n - first) * wall / max(runs, 1)
    start = START_S + START_S_PER_WORKER * workers
    worth = start * workers / (workers - 1)
    if rest <= worth:
        why = (f"the first {first:,} runs timed a run: the other {n - first:,} take about {rest:.2g} s here, under "
               f"the {worth:.2g} s a cluster of {workers} workers must save to repay its start")
        tail = _in_process(here, on_chunk, progress, first=1)
        return replace(tail, chunks=here.n_chunks, runs=n, compute=time.perf_counter() - w0,
                       client_cpu=time.process_time() - c0, chunk_wall=tail.chunk_wall + wall,
                       chunk_cpu=tail.chunk_cpu + cpu, why=why)
    why = (f"the first {first:,} runs timed a run here: the other {n - first:,} would take about {rest:.2g} s in "
           f"this process, over the {worth:.2g} s a cluster of {workers} workers must save to repay its start")
    there = plan.after(first, workers)
    with study_cluster(workers) as started:
        tail = _run_on(started, there, on_chunk, progress, first=1)
    return replace(tail, chunks=there.n_chunks, runs=n, compute=tail.compute + wall, chunk_wall=tail.chunk_wall + wall,
                   chunk_cpu=tail.chunk_cpu + cpu, why=why)


def check_scheduler(scheduler: str | None) -> None:
    """A scheduler's address, or a :class:`~beltcalc.errors.UsageError` naming it."""
    from beltcalc.units import quote

    if scheduler is not None and not re.fullmatch(r"(tcp|tls|ucx|ws|wss|inproc)://[^\s]{1,200}", scheduler):
        raise UsageError(f"{quote(scheduler)}: give the scheduler's address, e.g. tcp://HOST:8786", param="scheduler")


def _in_process(plan: Plan, on_chunk, progress=None, first: int = 0) -> Execution:
    import time

    plan = plan.sized(1)
    w0, c0 = time.perf_counter(), time.process_time()
    wall = cpu = 0.0
    for c in range(first, plan.n_chunks):
        chunk = run_chunk(plan, c, progress)
        wall, cpu = wall + chunk.wall, cpu + chunk.cpu
        on_chunk(chunk)
        del chunk                                # not held while the next one runs
    return Execution("in-process", 1, plan.n_chunks, plan.chunk, plan.n_runs, 0.0, time.perf_counter() - w0,
                     time.process_time() - c0, wall, cpu)


# dask's workers start with MALLOC_TRIM_THRESHOLD_=65536, which also fixes glibc's mmap
# threshold at 128 KiB: every array of a run (a batch pass, a time series) is then a fresh
# mmap whose pages fault in again, and a chunk costs 1.8x its CPU time in this process
# (benchmarks/studies.py). Arrays up to 32 MiB come from the heap instead, and the heap is
# trimmed above 128 MiB: a worker keeps at most that much freed memory.
WORKER_MALLOC = {"MALLOC_MMAP_THRESHOLD_": str(32 * 2 ** 20), "MALLOC_TRIM_THRESHOLD_": str(128 * 2 ** 20)}


@dataclass
class StartedCluster:
    """A Dask client ready for studies (:func:`study_cluster`): ``how`` it runs them, on how
    many ``workers``, and the seconds its start took."""

    client: object
    how: str
    workers: int
    start: float
    used: bool = False


@contextmanager
def study_cluster(workers: int | None = None, scheduler: str | None = None) -> Iterator[StartedCluster]:
    """A Dask cluster for one or more studies (:func:`execute`'s ``cluster``): a client of the
    scheduler at ``scheduler``, or a new local cluster of ``workers`` processes (default: the
    CPU count), closed after the block; Dask's own log lines kept off stderr meanwhile
    (:mod:`beltcalc.sim.study.cluster`)."""
    import os
    import time

    from beltcalc.sim.study.cluster import local_cluster, quiet_logs, scheduler_client

    check_scheduler(scheduler)
    t0 = time.perf_counter()
    with quiet_logs():
        if scheduler is not None:
            with scheduler_client(scheduler) as client:
                n = sum(client.nthreads().values()) or 1
                yield StartedCluster(client, f"dask scheduler {scheduler}", n, time.perf_counter() - t0)
            return
        workers = workers or os.cpu_count() or 1
        with local_cluster(workers, WORKER_MALLOC) as client:
            yield StartedCluster(client, f"dask local cluster, {workers} worker{'' if workers == 1 else 's'}", workers,
                                 time.perf_counter() - t0)


_FROZEN = [False]
WARM_PACKAGES = ("beltcalc", "scipy")     # what a study's runs import (the CLI's own modules aside)


def study_modules() -> list[str]:
    """The modules of :data:`WARM_PACKAGES` this process has imported (after its nominal run:
    what a run needs), its command line's aside."""
    import sys

    return sorted(m for m in list(sys.modules) if m.split(".")[0] in WARM_PACKAGES
                  and not m.startswith("beltcalc.cli"))


def warm_worker(names: list[str]) -> int:
    """Import ``names`` in a worker (those that import: a best effort), then freeze what is
    alive out of the garbage collector (as :func:`chunk_task` does after a first chunk); the
    number imported. Run on each worker as part of the cluster's start (:func:`_run_on`): the
    first chunk of each worker then does not import the code of the runs (about 0.25 s)."""
    import gc
    import importlib

    done = 0
    for name in names:
        try:
            importlib.import_module(name)
            done += 1
        except Exception:                    # noqa: BLE001  (a module made at run time: a chunk imports what it needs)
            pass
    gc.collect()
    gc.freeze()
    return done


def chunk_task(plan: Plan, c: int) -> Chunk:
    """:func:`~beltcalc.sim.study.runs.run_chunk` as a Dask worker runs it. After a worker's
    first chunk, what its imports and that chunk left alive (Dask, numpy, scipy, beltcalc's
    modules and caches) is frozen out of the garbage collector (``gc.freeze``), as the command
    line does in its own process (:func:`beltcalc.cli.main.main`): the collections the runs
    trigger then walk only the runs' objects."""
    import gc

    chunk = run_chunk(plan, c)
    if not _FROZEN[0]:
        _FROZEN[0] = True
        gc.collect()
        gc.freeze()
    return chunk


def _run_on(cluster: StartedCluster, plan: Plan, on_chunk, progress, retries: int = 2, first: int = 0) -> Execution:
    """Every chunk of ``plan`` as a task of ``cluster``, at most about two per worker in
    flight, handed to ``on_chunk`` in chunk order; a task that fails after its retries is
    its chunk's rows with the reason; chunks from ``first`` on (those before it ran
    elsewhere). The cluster's start counts for its first study only,
    and with it the workers' import of the runs' code (:func:`warm_worker`, about 0.25 s)."""
    import time
    import uuid

    from distributed import as_completed

    client = cluster.client
    plan = plan.sized(cluster.workers)
    warm = 0.0
    if not cluster.used:
        t0 = time.perf_counter()
        try:
            client.run(warm_worker, study_modules())     # part of the start: the workers import the runs' code
        except Exception:                      # noqa: BLE001  (a worker lost: its chunks say so, retried or as rows)
            pass
        warm = time.perf_counter() - t0
    w0, c0 = time.perf_counter(), time.process_time()
    shared = client.scatter(plan, broadcast=True)
    n = plan.n_chunks
    cap = 2 * cluster.workers + 2
    token = uuid.uuid4().hex
    nxt, done, pending, which = first, first, {}, {}
    wall = cpu = 0.0
    ac = as_completed()
    while done < n:
        while nxt < n and (nxt - done) < cap:
            fut = client.submit(chunk_task, shared, nxt, retries=retries, pure=False,
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
        wall, cpu = wall + pending[c].wall, cpu + pending[c].cpu
        if progress is not None:
            progress(pending[c].runs)
        while done in pending:
            on_chunk(pending.pop(done))
            done += 1
    start, cluster.used = (0.0 if cluster.used else cluster.start) + warm, True
    return Execution(cluster.how, cluster.workers, n, plan.chunk, plan.n_runs, start, time.perf_counter() - w0,
                     time.process_time() - c0, wall, cpu)


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
    return rows, columns, how.how
