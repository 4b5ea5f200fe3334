"""How a study runs: every chunk of a :class:`~beltcalc.sim.study.plan.Plan`
(:func:`~beltcalc.sim.study.runs.run_chunk`) in this process or on Dask (a local cluster of
processes, or an existing scheduler: :mod:`beltcalc.sim.study.cluster`), each task retried on
failure, the chunks handed on in chunk order (:func:`execute`); a grid's rows kept in memory
(:func:`grid_rows`).
"""

from __future__ import annotations

import re
from typing import Callable

from beltcalc.errors import UsageError
from beltcalc.sim.study.plan import Plan
from beltcalc.sim.study.runs import Chunk, RunRow, failed_chunk, run_chunk

DASK_MIN_RUNS = 200      # below this a local cluster costs more than it saves


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
    return on_dask(plan, on_chunk, workers, scheduler, progress)


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


def on_dask(plan: Plan, on_chunk, workers: int, scheduler: str | None, progress=None, retries: int = 2) -> str:
    """The chunks on an existing scheduler, or on a local cluster of ``workers`` processes;
    Dask's own log lines kept off stderr meanwhile (:mod:`beltcalc.sim.study.cluster`)."""
    from beltcalc.sim.study.cluster import local_cluster, quiet_logs, scheduler_client

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
