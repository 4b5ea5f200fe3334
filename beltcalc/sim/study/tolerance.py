"""Tolerance (Monte Carlo) studies: the limits on an output column (:class:`Limit`) and the
fold of every run into what the report needs, in constant memory.

An :class:`Accumulator` folds each chunk into sums of fixed size (exact mean, standard
deviation, min and max, standardised regression coefficients from co-moment matrices merged
by the pairwise update of [CGL79]) and a reservoir of :data:`RESERVOIR` rows (algorithm R
of [Vit85]) for percentiles and Spearman rank correlations; memory is constant in the
number of runs. A limit's failing fraction comes with its Wilson score interval [Wil27]
(:func:`wilson`).

References:

[CGL79] T. F. Chan, G. H. Golub, R. J. LeVeque, "Updating formulae and a pairwise algorithm
    for computing sample variances", Stanford report STAN-CS-79-773 (1979).
[Vit85] J. S. Vitter, "Random sampling with a reservoir", ACM Trans. Math. Software 11
    (1985) 37-57.
[Wil27] E. B. Wilson, "Probable inference, the law of succession, and statistical
    inference", J. Amer. Statist. Assoc. 22 (1927) 209-212.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from typing import Callable, Mapping, Sequence

import numpy as np

from beltcalc.errors import UsageError, did_you_mean
from beltcalc.params import bare_number
from beltcalc.sim.study.execution import execute
from beltcalc.sim.study.plan import Plan
from beltcalc.sim.study.runs import Chunk, RunRow

RESERVOIR = 10_000       # rows kept for percentiles and rank correlations
PERCENTILES = (1, 5, 50, 95, 99)
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
MAX_DISTINCT = 50        # distinct warnings / failure reasons kept (the rest counted)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


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
    """Wilson score interval [Wil27] of a fraction ``failed / n`` (95 % by default); (None, None) for n = 0.

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


# --- the fold: constant memory ----------------------------------------------------------------

class _Moments:
    """Count, means and co-moment matrix of vectors [inputs..., one output], merged batch by
    batch by the pairwise update of [CGL79]: exact and of fixed size."""

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
        """Algorithm R [Vit85] over the rows in run order (deterministic: its own seeded stream)."""
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
