"""Work-precision: every method of the core on one network (:func:`work_precision`) or on a
scene's (:func:`scene_work_precision`), wall time against error.

The reference is the exact solution; the error is the largest absolute difference of one
speed over the whole run. The exact row's own error is its estimate: the difference to an
exact run on another internal partition and scaling of A h, plus the conditioning floor. Explicit methods are
bounded by a budget of right-hand-side calls: on a stiff network they are limited by
stability, not accuracy, and a row says when the budget stopped them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping

import numpy as np

from beltcalc.errors import InputError, SimulationError
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.methods import METHODS
from beltcalc.sim.network import Network
from beltcalc.sim.scenes.base import Scene, scene_network

TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
EXACT_REPEATS = 30       # the exact row's time: the best of this many runs (cheap next to one scipy run)


@dataclass(frozen=True)
class WorkRow:
    method: str
    rtol: float | None       # None for exact
    wall_time: float         # s, best of the repeats
    rhs_calls: int
    steps: int
    error: float | None      # max |omega - omega_exact| [rad/s]; None if the run failed
    note: str = ""


def work_precision(network: Network, t_end: float, samples: int, signal: str,
                   tolerances=TOLERANCES, explicit_tolerances=(1e-3, 1e-6), repeats: int = 3,
                   max_rhs_calls: int = 2_000_000, progress: Callable[[], None] | None = None) -> list[WorkRow]:
    """Run every method at every tolerance (atol = rtol / 100) and measure it against exact."""
    checked = simulate(network, t_end, samples, SolverConfig("exact", accept_error=True))
    ref = checked[signal]
    rows = []
    # a run of well under a millisecond: the best of many, or one interruption of the process
    # decides every "x exact's time" of the table
    best = min((simulate(network, t_end, samples, SolverConfig("exact", estimate_error=False))
                for _ in range(max(repeats, EXACT_REPEATS))), key=lambda r: r.wall_time)
    rows.append(WorkRow("exact", None, best.wall_time, 0, best.steps, checked.errors[signal],
                        "its estimate: vs another internal partition"))
    if progress:
        progress()
    for method in (m for m in METHODS if not METHODS[m].exact):
        tols = explicit_tolerances if METHODS[method].explicit else tolerances
        for tol in tols:
            cfg = SolverConfig(method, rtol=tol, atol=tol / 100, max_rhs_calls=max_rhs_calls, estimate_error=False)
            try:
                runs = [simulate(network, t_end, samples, cfg) for _ in range(1 if METHODS[method].explicit else repeats)]
                r = min(runs, key=lambda x: x.wall_time)
                rows.append(WorkRow(method, tol, r.wall_time, r.rhs_calls, r.steps,
                                    float(np.max(np.abs(r[signal] - ref)))))
            except (SimulationError, InputError) as exc:     # a method that refuses the drive: its line
                rows.append(WorkRow(method, tol, float("nan"), max_rhs_calls, 0, None, str(exc).split(";")[0]))
            if progress:
                progress()
    return rows


def count_runs(tolerances=TOLERANCES, explicit_tolerances=(1e-3, 1e-6)) -> int:
    """How many rows :func:`work_precision` makes (for a progress bar)."""
    return 1 + sum(len(explicit_tolerances if m.explicit else tolerances) for m in METHODS.values() if not m.exact)


def fastest_at(rows: list[WorkRow], error: float) -> dict[str, WorkRow]:
    """Per method, the fastest row whose error is at most ``error``."""
    out = {}
    for r in rows:
        if r.error is not None and r.error <= error and (r.method not in out or r.wall_time < out[r.method].wall_time):
            out[r.method] = r
    return out


@dataclass(frozen=True)
class WorkPrecision:
    """Every method against the exact solution on one scene (:func:`scene_work_precision`)."""

    rows: list                  # WorkRow
    t_end: float                # s
    samples: int
    signal: str


def scene_work_precision(scene: Scene, values: Mapping[str, object],
                         progress: Callable[[], None] | None = None, **options) -> WorkPrecision:
    """Run every method at every tolerance on the scene's network at SI ``values`` and measure
    each against the exact solution on ``scene.signal``; ``progress()`` after each run (of
    :func:`count_runs`)."""
    net, t_end, samples = scene_network(scene, values, **options)
    rows = work_precision(net, t_end, samples, scene.signal, progress=progress)
    return WorkPrecision(rows, t_end, samples, scene.signal)
