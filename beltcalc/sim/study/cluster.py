"""The Dask cluster a study runs on (:func:`beltcalc.sim.study.execution.execute`), started,
run and stopped quietly.

Dask logs to stderr on its own: its workers' heartbeats that fail while a cluster shuts down
(``distributed.comm.core.CommClosedError ... Stream is closed``), its nannies' restarts.
While a study runs here, the loggers of ``distributed`` and ``tornado`` stand at CRITICAL
in this process (as they were, after) and in each worker process (:data:`WORKER_ENVIRON`),
and Dask's warnings are ignored; what matters reaches the study as a failed task, which
becomes rows with their reason (:func:`beltcalc.sim.study.runs.failed_chunk`), or as one error
line when the cluster does not start.

A worker process of a local cluster starts by Python's ``spawn``, which runs the parent's
main module again in it (as ``__mp_main__``): a script that starts a study at its top level,
without an ``if __name__ == "__main__":`` guard, would start it again in each worker
(``RuntimeError: ... before the current process has finished its bootstrapping phase``,
then ``Nanny failed to start``). The workers need nothing of the script (Dask pickles what
it defines by value, with cloudpickle), so for such a script its main module is not named
to them while the cluster runs (:func:`unguarded_script`); a guarded script's workers
import it as always (what its top level registers is there in them too).
"""

from __future__ import annotations

import ast
import logging
import os
import sys
import warnings
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Iterator

from beltcalc.errors import BeltcalcError, UsageError

QUIET_LOGGERS = ("distributed", "tornado", "bokeh")   # Dask's loggers and those of its servers
# each worker process sets up its logging from these when it imports distributed (dask reads
# DASK_* variables into its config: logging.distributed = critical)
WORKER_ENVIRON = {"DASK_LOGGING__DISTRIBUTED": "critical", "DASK_LOGGING__TORNADO": "critical"}
# Dask's own periodic work that a study does not use, slowed or off in a local cluster (its
# scheduler runs in this process, its workers get them as DASK_* variables): the event loop's
# blocked-loop check every 20 ms, the system monitor every 0.5 s, work stealing (the chunks are
# alike and handed out as workers free up), each worker's sampling profiler (every 10 ms), and
# the memory monitor of each worker and of its nanny (here, in this process) from every 0.1 s to
# every second (a worker past its memory limit is still paused, then restarted, within a second).
# Measured on 2 workers, idle: this process's CPU 42 -> 16 ms a second with the first four,
# 14 -> 6 ms with the memory monitor's; each worker's 6 -> 2.5 ms a second.
QUIET_CONFIG = {"distributed.admin.tick.interval": "1s", "distributed.admin.system-monitor.interval": "5s",
                "distributed.scheduler.work-stealing": False, "distributed.worker.profile.enabled": False,
                "distributed.worker.memory.monitor-interval": "1s"}
GUARD = ('in a script, start a study under \'if __name__ == "__main__":\', or run it in this process '
         '(`workers` 1)')


@contextmanager
def quiet_logs() -> Iterator[None]:
    """Dask's loggers (:data:`QUIET_LOGGERS` and every logger below them) at CRITICAL while
    the block runs, each back at its own level after; Dask's warnings ignored meanwhile."""
    import distributed  # noqa: F401  (its import sets its loggers' levels: before they are saved)

    manager = logging.Logger.manager
    names = [n for n, lg in list(manager.loggerDict.items())
             if isinstance(lg, logging.Logger) and n.split(".")[0] in QUIET_LOGGERS]
    saved = [(lg, lg.level) for lg in map(logging.getLogger, dict.fromkeys([*QUIET_LOGGERS, *names]))]
    for lg, _ in saved:
        lg.setLevel(logging.CRITICAL)
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", module=r"(distributed|tornado|dask)(\..*)?$")
            yield
    finally:
        for lg, level in saved:
            lg.setLevel(level)


@contextmanager
def scheduler_client(address: str) -> Iterator[object]:
    """A Dask client of the scheduler at ``address``; an unreachable one is one error line
    within seconds."""
    from distributed import Client

    from beltcalc.errors import InputError
    from beltcalc.units import quote

    try:
        client = Client(address, timeout="3s")
    except Exception as exc:                  # OSError, TimeoutError, a malformed address
        raise InputError(f"cannot reach the Dask scheduler at {quote(address)}: {exc}", param="scheduler") from None
    try:
        yield client
    finally:
        client.close()


@contextmanager
def local_cluster(workers: int, environ: dict[str, str]) -> Iterator[object]:
    """A client of a new local Dask cluster of ``workers`` processes, one thread each, whose
    processes start with the variables ``environ`` (and :data:`WORKER_ENVIRON`); closed, and
    this process's environment as it was, after the block. A cluster that does not start is
    one :class:`~beltcalc.errors.BeltcalcError` line; a study started while a worker process
    imports a script (one with no main guard, whose workers are not kept from it) a
    :class:`~beltcalc.errors.UsageError` saying what to do (:data:`GUARD`)."""
    import multiprocessing

    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise UsageError(f"a study was started while a worker process was starting: {GUARD}")
    import dask
    from distributed import Client, LocalCluster

    environ = {**environ, **WORKER_ENVIRON, **{"DASK_" + k.upper().replace(".", "__").replace("-", "_"): str(v)
                                               for k, v in QUIET_CONFIG.items()}}
    with ExitStack() as stack:
        stack.enter_context(_main_kept_from_workers(unguarded_script()))
        stack.enter_context(dask.config.set(QUIET_CONFIG))
        try:
            with dask.config.set({f"distributed.nanny.pre-spawn-environ.{k}": v for k, v in environ.items()}):
                # the nanny writes a worker's variables (these, and dask's own: OMP_NUM_THREADS=1,
                # ...) into this process's os.environ before it spawns the worker, and leaves them
                # there (distributed.nanny.WorkerProcess.start): as they were, after
                keys = [*dask.config.get("distributed.nanny.pre-spawn-environ"), "PYTHONHASHSEED"]
                stack.callback(_restore_environ, {k: os.environ.get(k) for k in keys})
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                                       silence_logs=logging.CRITICAL)
        except Exception as exc:           # a nanny that failed, no free port, ...
            raise BeltcalcError(f"the local Dask cluster of {workers} workers did not start "
                                f"({type(exc).__name__}: {exc}); {GUARD}") from None
        stack.callback(cluster.close)
        client = Client(cluster)
        stack.callback(client.close)
        yield client


def _restore_environ(before: dict[str, str | None]) -> None:
    for key, value in before.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


def unguarded_script() -> bool:
    """True when this call comes from the top level of the script Python runs (``python
    script.py``, ``python -m module``) outside its ``if __name__ == "__main__":`` block: each
    worker process that ``spawn`` starts would run that code again. False for an interactive
    session, ``python -c``, a notebook (no script file), a call from a guarded block or from
    another thread once the script's top level is done."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if not path:
        return False
    line, frame = None, sys._getframe(1)
    while frame is not None:                 # the script's own top-level frame, at the line running
        if frame.f_code.co_name == "<module>" and frame.f_globals is vars(main):
            line = frame.f_lineno
        frame = frame.f_back
    if line is None:
        return False
    try:
        tree = ast.parse(Path(path).read_bytes(), path)
    except (OSError, SyntaxError, ValueError):
        return True
    return not any(isinstance(node, ast.If) and _is_main_test(node.test) and node.lineno <= line <= node.end_lineno
                   for node in tree.body)


def _is_main_test(test) -> bool:
    """``__name__ == "__main__"`` (either way round)."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    return (any(isinstance(s, ast.Name) and s.id == "__name__" for s in sides)
            and any(isinstance(s, ast.Constant) and s.value == "__main__" for s in sides))


@contextmanager
def _main_kept_from_workers(keep: bool) -> Iterator[None]:
    """With ``keep``, the main module's file and spec hidden while the block runs: a process
    ``spawn`` starts meanwhile (``multiprocessing.spawn.get_preparation_data``) does not run
    it again."""
    main = sys.modules.get("__main__")
    if not keep or main is None:
        yield
        return
    names = vars(main)
    saved = {k: names[k] for k in ("__file__", "__spec__") if k in names}
    names.pop("__file__", None)
    names["__spec__"] = None
    try:
        yield
    finally:
        names.pop("__spec__", None)
        names.update(saved)
