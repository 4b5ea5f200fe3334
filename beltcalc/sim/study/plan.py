"""What a study runs: the runs of one scene with some of its values replaced, by the points
of a grid or by values drawn from distributions (:class:`Distribution`, read by
:func:`parse_vary`), in chunks (:class:`Plan`) sized to the work and the workers
(:func:`chunk_size`), smaller towards the end (:func:`chunk_starts`).

Every run draws its own values (:meth:`Plan.draws`): run ``i`` reads the words of the
counter-based generator Philox-4x64 [SMDS11] (key from ``numpy.random.SeedSequence(seed)``)
at counter ``i * w`` onwards (``w`` counter steps of 4 words each, one word per varied input
and one for the run's reservoir priority), and turns each into a value by the inverse of its
distribution function. A run's values therefore depend on the seed and its index only: the same
rows whatever the chunks and however many workers run them. SI floats; no click, no pint
(texts are read through :mod:`beltcalc.params` and :mod:`beltcalc.units`).

References:

[HSF92] S. F. Hummel, E. Schonberg, L. E. Flynn, "Factoring: a method for scheduling parallel
    loops", Commun. ACM 35(8) (1992) 90-101.

[SMDS11] J. K. Salmon, M. A. Moraes, R. O. Dror, D. E. Shaw, "Parallel random numbers: as easy
    as 1, 2, 3", Proc. SC11 (2011), article 16.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from beltcalc.errors import UsageError
from beltcalc.params import Param, bare_number

MAX_GRID = 1_000_000     # points of a grid (its rows are kept for the table)
TASKS_PER_WORKER = 4     # chunks per worker: the last ones to finish leave the others idle for at most 1/4 of a share
MIN_TASK_S = 1.0         # a chunk of less work than this costs more in dispatch and its check run than it balances
MAX_CHUNK = 1000         # runs per chunk: what a chunk holds and sends back (its rows, its reservoir) stays small
TAIL_MIN_S = 0.1         # the last chunks (chunk_starts) hold at least this much work, and
DISPATCH_S = 0.01        # at least twice what this process spends on one chunk (Dask's dispatch, the merge) per worker
BATCH_GROUP = 250        # runs batched together (beltcalc.sim.study.runs.run_chunk): a chunk of a scene that batches holds whole groups


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
        """``n`` values drawn with ``rng`` (:meth:`quantile` of uniform draws)."""
        return self.quantile((rng.integers(0, 2 ** 53, n) + 0.5) * 2.0 ** -53)

    def quantile(self, u: np.ndarray) -> np.ndarray:
        """The inverse of the distribution function at ``u`` in (0, 1): the values whose
        probabilities are ``u`` (a spread of 0 gives the value itself, exactly).

        >>> Distribution("normal", (10.0, 2.0)).quantile(np.array([0.5, 0.8413447460685429]))
        array([10., 12.])
        """
        a = self.args
        u = np.asarray(u, dtype=float)
        if self.kind == "normal":
            from scipy.special import ndtri

            return a[0] + a[1] * ndtri(u)
        if self.kind == "uniform":
            return a[0] + (a[1] - a[0]) * u
        lo, mode, hi = a                         # inverse CDF of the triangular distribution
        if hi == lo:
            return np.full(u.shape, lo)
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


# --- the plan ----------------------------------------------------------------------------------

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
    chunk: int = 0                 # runs per chunk (the largest); 0: sized where it runs (chunk_size)
    starts: tuple[int, ...] | None = None   # each chunk's first run where they are not all `chunk` long (chunk_starts)
    options: Mapping[str, object] = field(default_factory=dict)
    batch: bool = True             # batched exact propagation where the scene declares it (Scene.batch)
    fold: object = None            # a tolerance study's fold (beltcalc.sim.study.fold.FoldSpec): done by the chunk
    run_cost: float | None = None  # seconds of one single run, measured (chunk_size)

    @property
    def n_runs(self) -> int:
        return math.prod(len(g) for g in self.grid) if self.grid is not None else self.runs

    @property
    def n_chunks(self) -> int:
        return len(self.starts) if self.starts is not None else -(-self.n_runs // self.chunk)

    def bounds(self, c: int) -> tuple[int, int]:
        """The runs of chunk ``c``: ``range(*plan.bounds(c))``."""
        if self.starts is not None:
            return self.starts[c], self.starts[c + 1] if c + 1 < len(self.starts) else self.n_runs
        return c * self.chunk, min((c + 1) * self.chunk, self.n_runs)

    def inputs(self, c: int) -> np.ndarray:
        """The input values of chunk ``c``: one row per run, one column per name."""
        return self.draws(*self.bounds(c))[0]

    def draws(self, lo: int, hi: int) -> tuple[np.ndarray, np.ndarray]:
        """The input values of runs ``lo .. hi - 1`` (one row per run, one column per name) and
        each run's reservoir priority (uint64: :mod:`beltcalc.sim.study.fold`); a grid's runs are
        its points in row-major order, their priorities 0.

        A drawn run ``i`` reads Philox words ``4 w i`` onwards (module docstring): its values do
        not depend on which runs are drawn with it.

        >>> d = Distribution("uniform", (0.0, 1.0))
        >>> p = Plan(None, {}, None, ("x",), dists=(d,), runs=10, seed=3)
        >>> bool(np.all(p.draws(0, 10)[0][4:7] == p.draws(4, 7)[0]))
        True
        """
        n = hi - lo
        if self.grid is not None:
            idx = np.unravel_index(np.arange(lo, hi), [len(g) for g in self.grid])
            X = np.column_stack([np.asarray(g, float)[i] for g, i in zip(self.grid, idx)]) \
                if self.grid else np.zeros((n, 0))
            return X, np.zeros(n, dtype=np.uint64)
        k = len(self.dists or ())
        width = -(-(k + 1) // 4)                 # Philox counter steps per run, 4 words each
        gen = np.random.Philox(np.random.SeedSequence(self.seed))
        gen.advance(lo * width)
        words = gen.random_raw(n * width * 4).reshape(n, width * 4)
        u = ((words[:, :k] >> np.uint64(11)).astype(float) + 0.5) * 2.0 ** -53     # in (0, 1), 53 bits
        X = np.column_stack([d.quantile(u[:, j]) for j, d in enumerate(self.dists)]) if k else np.zeros((n, 0))
        return X, words[:, k].copy()

    def sized(self, workers: int) -> "Plan":
        """This plan in chunks for ``workers`` (as it is where its size is set): of
        :func:`chunk_size` runs in this process, and on several workers smaller towards the
        end (:func:`chunk_starts`)."""
        from dataclasses import replace

        if self.chunk:
            return self
        size = chunk_size(self.n_runs, workers, self.run_cost, self.unit)
        starts = chunk_starts(self.n_runs, workers, size, self.run_cost, self.unit) if workers > 1 else None
        return replace(self, chunk=size, starts=starts)

    def after(self, first: int, workers: int) -> "Plan":
        """This plan with runs ``0 .. first - 1`` as its chunk 0 and the rest in chunks for
        ``workers`` (as :meth:`sized` cuts them; ``first`` a multiple of :attr:`unit`).

        >>> p = Plan(None, {}, None, ("x",), dists=(Distribution("uniform", (0.0, 1.0)),), runs=1000, run_cost=0.15)
        >>> p.after(2, 2).starts[:4], p.after(2, 2).bounds(24), p.after(2, 1).starts
        ((0, 2, 127, 252), (999, 1000), (0, 2))
        """
        from dataclasses import replace

        rest = self.n_runs - first
        size = chunk_size(rest, workers, self.run_cost, self.unit)
        cuts = chunk_starts(rest, workers, size, self.run_cost, self.unit) if workers > 1 \
            else tuple(range(0, rest, size))
        return replace(self, chunk=max(size, first), starts=(0, *(first + c for c in cuts)))

    @property
    def unit(self) -> int:
        """Runs that go together: the batch's group (:data:`BATCH_GROUP`) where the scene
        batches, else 1; a chunk starts at a multiple of it."""
        return BATCH_GROUP if self.batch and getattr(self.scene, "batched", None) is not None else 1


def chunk_size(runs: int, workers: int, run_cost: float | None = None, unit: int = 1) -> int:
    """Runs per chunk for ``runs`` runs on ``workers`` workers, one run costing ``run_cost``
    seconds (None: unknown; the nominal run's time, which its first-call costs inflate, is an
    upper bound): :data:`TASKS_PER_WORKER` chunks per worker, each of at least
    :data:`MIN_TASK_S` of work and at most :data:`MAX_CHUNK` runs, but never so large that a
    worker gets none; a multiple of ``unit`` runs (the batch's groups: :data:`BATCH_GROUP`).
    In this process (one worker) a chunk is as large as allowed: there the chunks balance
    nothing. Each chunk costs this process about 6 ms (Dask's dispatch, the merge of its part):
    fewer, larger chunks where the work allows.

    >>> chunk_size(1600, 16, 0.109), chunk_size(50_000, 16, 0.003), chunk_size(201, 16, 0.003)
    (25, 782, 13)
    >>> chunk_size(50_000, 1, 0.003), chunk_size(7, 1), chunk_size(4000, 2, 0.109)
    (1000, 7, 500)
    >>> chunk_size(50_000, 16, 0.003, 250), chunk_size(50_000, 2, 0.003, 250), chunk_size(1600, 16, 0.003, 250)
    (750, 1000, 250)
    """
    workers = max(1, int(workers))
    size = -(-runs // (TASKS_PER_WORKER * workers)) if workers > 1 else runs
    if run_cost is not None and run_cost > 0:
        size = max(size, math.ceil(MIN_TASK_S / run_cost))
    size = min(size, MAX_CHUNK, -(-runs // workers))
    return max(unit, size // unit * unit)


def chunk_starts(runs: int, workers: int, size: int, run_cost: float | None = None,
                 unit: int = 1) -> tuple[int, ...]:
    """Where each chunk starts: chunks of ``size`` runs while the runs left are many, then each
    chunk a ``1 / (2 workers)`` share of the runs left [HSF92], so that the last chunks to
    finish are short and no worker waits long for the others; no chunk under ``size`` or
    under :data:`TAIL_MIN_S` of work, whichever is less, nor so short that this process,
    handing chunks out one at a time, cannot keep every worker fed (``2 workers``
    :data:`DISPATCH_S` of work); ``run_cost`` seconds a run (unknown: the floor is one
    ``unit``); every start a multiple of ``unit`` (the batch's groups).

    With chunks all of ``size`` runs, the workers still busy at the end hold a whole chunk
    each: on 16 workers, 4 chunks each, that is up to a quarter of a worker's share, while
    the others wait. Here the wait is at most the last chunk's work.

    >>> s = chunk_starts(400, 2, 50, 0.15)
    >>> len(s), [b - a for a, b in zip(s, s[1:] + (400,))][-8:]
    (20, [5, 4, 3, 2, 2, 1, 1, 1])
    >>> s = chunk_starts(50_000, 2, 1000, 0.003, 250)
    >>> len(s), [b - a for a, b in zip(s, s[1:] + (50_000,))][-9:]
    (56, [750, 500, 250, 250, 250, 250, 250, 250, 250])
    """
    workers, size, unit = max(1, int(workers)), max(1, int(size)), max(1, int(unit))
    floor_s = max(TAIL_MIN_S, 2 * workers * DISPATCH_S)
    least = unit if run_cost is None or run_cost <= 0 else math.ceil(floor_s / run_cost / unit) * unit
    least = max(unit, min(size, least))
    starts, lo = [], 0
    while lo < runs:                   # each pass takes at least one unit of runs: at most `runs` passes
        starts.append(lo)
        share = -(-(runs - lo) // (2 * workers)) // unit * unit
        lo += min(size, max(least, share))
    return tuple(starts)
