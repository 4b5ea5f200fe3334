"""The fold of a tolerance study's runs into what its report needs, done where the runs are: a
chunk folds its own rows into a :class:`Part` (:func:`fold_rows`, on the Dask worker that ran
them), the client merges the parts in run order (:class:`Fold`) into a
:class:`StudySummary`. Memory is constant in the number of runs, and the summary is the same,
bit for bit, however the runs are cut into chunks and wherever the chunks run:

- **Moments** (count, means and co-moment matrix of [inputs..., one output], per output: the
  mean, sd and standardised regression coefficients) are merged by the pairwise update of
  [CGL79] over one fixed binary tree whose leaves are the runs: node ``(l, i)`` holds runs
  ``i 2^l .. (i + 1) 2^l - 1``. A chunk forms the nodes that lie wholly in its runs and sends
  the largest of them (at most two per level); the client completes the tree from them
  (:meth:`Fold.add`), and at the end folds the last incomplete nodes from the right. Every node
  is the same function of the same runs, wherever it was formed: no sum depends on the chunks.
- **Min, max, counts** (limits, failures, failing checks, warnings) are exact; the first run of
  each failure reason is a run index; warnings and reasons keep their first
  :data:`MAX_DISTINCT` texts in run order, as one pass over the rows would.
- **The reservoir** of :data:`RESERVOIR` rows, for percentiles and Spearman rank correlations,
  is the rows of the smallest priorities, each run's priority a 64-bit word of its own random
  stream (:meth:`beltcalc.sim.study.plan.Plan.draws`): a uniform sample without replacement
  (bottom-k sampling, [Coh97]) that a chunk cuts to its own smallest ``RESERVOIR`` and the
  client merges, ordered by run. Up to ``RESERVOIR`` runs it holds every row, and percentiles
  are exact; beyond, they are those of the sample.

A limit's failing fraction comes with its Wilson score interval [Wil27] (:func:`wilson`).

References:

[CGL79] T. F. Chan, G. H. Golub, R. J. LeVeque, "Updating formulae and a pairwise algorithm
    for computing sample variances", Stanford report STAN-CS-79-773 (1979).
[Coh97] E. Cohen, "Size-estimation framework with applications to transitive closure and
    reachability", J. Comput. System Sci. 55 (1997) 441-453.
[Wil27] E. B. Wilson, "Probable inference, the law of succession, and statistical
    inference", J. Amer. Statist. Assoc. 22 (1927) 209-212.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

RESERVOIR = 10_000       # rows kept for percentiles and rank correlations
PERCENTILES = (1, 5, 50, 95, 99)
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
MAX_DISTINCT = 50        # distinct warnings / failure reasons kept (the rest counted)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


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


@dataclass(frozen=True)
class FoldSpec:
    """What the chunks of a tolerance study fold and send back: the varied ``inputs``, the
    output ``keys`` (the nominal run's columns), the ``limits``, the reservoir's size, and
    which rows travel: ``send`` holds ``"csv"`` (the rows as CSV text, formatted by the chunk),
    ``"table"`` (as columns, for Parquet) or ``"rows"`` (:class:`~beltcalc.sim.study.runs.RunRow`)."""

    inputs: tuple[str, ...]
    keys: tuple[str, ...]
    limits: tuple[Limit, ...] = ()
    reservoir: int = RESERVOIR
    send: frozenset = frozenset()


# --- the moments' tree ----------------------------------------------------------------------------

@dataclass
class Node:
    """Node ``(level, index)`` of the moments' tree: per output the count ``n`` (m,), means
    ``mean`` (m, k + 1) and co-moment matrix ``M`` (m, k + 1, k + 1) of [inputs..., output]
    over runs ``index 2^level .. (index + 1) 2^level - 1`` whose output is finite."""

    level: int
    index: int
    n: np.ndarray
    mean: np.ndarray
    M: np.ndarray


def _merge(a, b):
    """(n, mean, M) of two sets from theirs [CGL79]; arrays of any leading shape (either set
    may be empty: n = 0; M None: single runs, whose co-moments are 0)."""
    na, ma, Ma = a
    nb, mb, Mb = b
    n = na + nb
    f = np.divide(nb, n, out=np.zeros_like(n), where=n > 0)
    g = np.divide(na * nb, n, out=np.zeros_like(n), where=n > 0)
    delta = mb - ma
    mean = ma + delta * f[..., None]
    M = delta[..., :, None] * delta[..., None, :] * g[..., None, None]
    if Ma is not None:
        M = Ma + Mb + M
    return n, mean, M


def tree_nodes(r0: int, Z: np.ndarray, ok: np.ndarray) -> list[Node]:
    """The largest tree nodes that lie wholly in runs ``r0 .. r0 + len(Z) - 1``, in run order.
    ``Z`` (runs, m, k + 1): per run and output its [inputs..., output]; ``ok`` (runs, m): the
    output is finite (a run where it is not counts for nothing in that output)."""
    w = ok.astype(float)
    cur = (w, np.where(ok[..., None], Z, 0.0), None)          # runs: co-moments 0 (None, not stored)
    zero = np.zeros(Z.shape[1:] + Z.shape[-1:])
    a, b, level = r0, r0 + len(Z), 0
    left: list[Node] = []
    right: list[Node] = []

    def node(i):                                 # copies: a view would keep the level's whole array alive
        return cur[0][i].copy(), cur[1][i].copy(), zero.copy() if cur[2] is None else cur[2][i].copy()

    def cut(sl):
        return tuple(None if x is None else x[sl] for x in cur)

    while b > a:
        if a % 2:                                # its sibling lies before these runs
            left.append(Node(level, a, *node(0)))
            cur, a = cut(slice(1, None)), a + 1
        if b > a and (b - a) % 2:                # ... after them
            right.append(Node(level, b - 1, *node(-1)))
            cur, b = cut(slice(None, -1)), b - 1
        if b == a:
            break
        cur = _merge(cut(slice(0, None, 2)), cut(slice(1, None, 2)))
        a, b, level = a // 2, b // 2, level + 1
    return left + right[::-1]


# --- a chunk's part -------------------------------------------------------------------------------

@dataclass
class Part:
    """What one chunk of runs ``r0 .. r0 + runs - 1`` folds to (:func:`fold_rows`)."""

    r0: int
    runs: int
    nodes: list
    lo: np.ndarray
    hi: np.ndarray
    limit_counts: np.ndarray                    # (limits, 2): evaluated, failed
    sample: np.ndarray                          # reservoir candidates: rows of [inputs..., outputs...]
    priority: np.ndarray                        # their priorities (uint64)
    run: np.ndarray                             # their run indices
    errors: int = 0
    reasons: dict = field(default_factory=dict)     # kind -> [runs, first run, text], in run order
    checks: dict = field(default_factory=dict)      # key -> [runs, a failing Check]
    warnings: dict = field(default_factory=dict)    # text -> runs, in run order
    extra_keys: set = field(default_factory=set)


def fold_rows(spec: FoldSpec, r0: int, rows: Sequence, priority: np.ndarray) -> Part:
    """The :class:`Part` of the rows of runs ``r0 ..`` (:class:`~beltcalc.sim.study.runs.RunRow`,
    in run order), ``priority`` each run's reservoir priority."""
    n, k, m = len(rows), len(spec.inputs), len(spec.keys)
    X = np.array([r.inputs for r in rows], float).reshape(n, k)
    Y = np.array([[np.nan if r.values.get(key) is None else r.values[key] for key in spec.keys] for r in rows],
                 float).reshape(n, m)
    part = Part(r0, n, [], np.full(m, np.inf), np.full(m, -np.inf), np.zeros((len(spec.limits), 2), dtype=np.int64),
                np.zeros((0, k + m)), np.zeros(0, np.uint64), np.zeros(0, np.int64))
    keys = set(spec.keys)
    for i, r in enumerate(rows):
        if r.error is not None:
            part.errors += 1
            kind = _NUMBER.sub("#", r.error)           # one reason whatever the value drawn
            entry = part.reasons.setdefault(kind, [0, r0 + i, r.error])
            entry[0] += 1
            continue
        for c in r.failed:
            part.checks.setdefault(c.key, [0, c])[0] += 1
        for w in r.warnings:
            part.warnings[w] = part.warnings.get(w, 0) + 1
        if len(r.values) > m or any(key not in keys for key in r.values):
            part.extra_keys.update(key for key in r.values if key not in keys)
    ok = np.isfinite(Y)
    if n:
        Z = np.concatenate([np.broadcast_to(X[:, None, :], (n, m, k)), Y[:, :, None]], axis=2)
        part.nodes = tree_nodes(r0, Z, ok)
        part.lo = np.where(ok.any(axis=0), np.where(ok, Y, np.inf).min(axis=0), np.inf)
        part.hi = np.where(ok.any(axis=0), np.where(ok, Y, -np.inf).max(axis=0), -np.inf)
    for j, L in enumerate(spec.limits):
        y = Y[:, spec.keys.index(L.key)]
        good = np.isfinite(y)
        part.limit_counts[j] = (int(good.sum()), int(L.fails(y[good]).sum()))
    keep = _smallest(np.asarray(priority, np.uint64), np.arange(r0, r0 + n), spec.reservoir)
    part.sample, part.priority, part.run = np.column_stack([X, Y])[keep], np.asarray(priority, np.uint64)[keep], \
        np.arange(r0, r0 + n)[keep]
    return part


def _smallest(priority: np.ndarray, run: np.ndarray, cap: int) -> np.ndarray:
    """Indices of the ``cap`` smallest (priority, run), in no particular order."""
    if len(priority) <= cap:
        return np.arange(len(priority))
    return np.lexsort((run, priority))[:cap]


# --- the client's fold ----------------------------------------------------------------------------

class Fold:
    """Merges the :class:`Part` of every chunk, in run order, into a :class:`StudySummary`
    (module docstring: the result does not depend on the chunks). Memory is fixed: the tree's
    open nodes (at most two per level), a reservoir of ``spec.reservoir`` rows, the counts (at
    most :data:`MAX_DISTINCT` distinct texts each)."""

    def __init__(self, spec: FoldSpec, columns=None):
        self.spec = spec
        self.columns = dict(columns) if columns is not None else {key: None for key in spec.keys}
        k, m = len(spec.inputs), len(spec.keys)
        self.stack: list[Node] = []
        self.lo, self.hi = np.full(m, np.inf), np.full(m, -np.inf)
        self.limit_counts = np.zeros((len(spec.limits), 2), dtype=np.int64)
        self.sample, self.priority, self.run = np.zeros((0, k + m)), np.zeros(0, np.uint64), np.zeros(0, np.int64)
        self.runs = self.errors = 0
        self.reasons: dict[str, list] = {}
        self.more_reasons = 0
        self.checks: dict[str, list] = {}
        self.warnings: dict[str, int] = {}
        self.more_warnings = 0
        self.extra_keys: set[str] = set()

    def add(self, part: Part) -> None:
        """Merge the part of the next runs (parts in run order)."""
        if part.r0 != self.runs:
            raise ValueError(f"the part of runs from {part.r0} came after {self.runs} runs")
        for node in part.nodes:
            self.stack.append(node)
            while len(self.stack) > 1:
                a, b = self.stack[-2], self.stack[-1]
                if not (a.level == b.level and a.index % 2 == 0 and b.index == a.index + 1):
                    break
                n, mean, M = _merge((a.n, a.mean, a.M), (b.n, b.mean, b.M))
                self.stack[-2:] = [Node(a.level + 1, a.index // 2, n, mean, M)]
        self.lo, self.hi = np.minimum(self.lo, part.lo), np.maximum(self.hi, part.hi)
        self.limit_counts += part.limit_counts
        self.errors += part.errors
        for kind, (count, first, text) in part.reasons.items():
            if kind in self.reasons:
                self.reasons[kind][0] += count
            elif len(self.reasons) < MAX_DISTINCT:
                self.reasons[kind] = [count, first, text]
            else:
                self.more_reasons += count
        for key, (count, check) in part.checks.items():
            self.checks.setdefault(key, [0, check])[0] += count
        for text, count in part.warnings.items():
            if text in self.warnings:
                self.warnings[text] += count
            elif len(self.warnings) < MAX_DISTINCT:
                self.warnings[text] = count
            else:
                self.more_warnings += count
        self.extra_keys |= part.extra_keys
        self._reservoir(part)
        self.runs += part.runs

    def _reservoir(self, part: Part) -> None:
        cap = self.spec.reservoir
        pr, run, rows = part.priority, part.run, part.sample
        if len(self.priority) >= cap:            # only rows of priority below the largest kept can enter
            top = self.priority.max()
            keep = pr <= top
            pr, run, rows = pr[keep], run[keep], rows[keep]
        if not len(pr):
            return
        pr, run = np.concatenate([self.priority, pr]), np.concatenate([self.run, run])
        rows = np.concatenate([self.sample, rows])
        keep = _smallest(pr, run, cap)
        self.priority, self.run, self.sample = pr[keep], run[keep], rows[keep]

    def moments(self) -> Node | None:
        """The root of the tree: the open nodes folded from the right (a shape that depends on
        the number of runs only)."""
        if not self.stack:
            return None
        acc = self.stack[-1]
        for node in reversed(self.stack[:-1]):
            n, mean, M = _merge((node.n, node.mean, node.M), (acc.n, acc.mean, acc.M))
            acc = Node(node.level + 1, -1, n, mean, M)
        return acc

    def summary(self) -> "StudySummary":
        """The report: per output its statistics and the inputs that move it most."""
        k = len(self.spec.inputs)
        order = np.argsort(self.run, kind="stable")
        R = self.sample[order]
        root = self.moments()
        outputs = {}
        for j, key in enumerate(self.spec.keys):
            count = 0 if root is None else int(root.n[j])
            entry = {"n": count}
            if count == 0:
                outputs[key] = entry
                continue
            cov = root.M[j] / max(count - 1, 1)
            sd = math.sqrt(max(cov[k, k], 0.0))
            entry.update(mean=float(root.mean[j, k]), sd=sd if count > 1 else None, min=float(self.lo[j]),
                         max=float(self.hi[j]))
            y = R[:, k + j]
            ok = np.isfinite(y)
            if ok.any():
                pct = np.percentile(y[ok], PERCENTILES)
                entry.update({f"p{p}": float(v) for p, v in zip(PERCENTILES, pct)})
            src, r2 = _src(cov, k)
            rho = [None] * k
            if ok.sum() > 2 and np.ptp(y[ok]) > 0:
                ry = ranks(y[ok])
                for i in range(k):
                    x = R[ok, i]
                    if np.ptp(x) > 0:
                        rho[i] = float(np.corrcoef(ranks(x), ry)[0, 1])
            entry["influence"] = sorted(
                ({"input": name, "src": s, "spearman": r} for name, s, r in zip(self.spec.inputs, src, rho)),
                key=lambda e: -abs(e["src"] if e["src"] is not None else (e["spearman"] or 0.0)))
            entry["r2"] = r2
            outputs[key] = entry
        limits = []
        for L, (n, f) in zip(self.spec.limits, self.limit_counts.tolist()):
            lo, hi = wilson(f, n)
            limits.append({"limit": L, "evaluated": n, "failed": f, "fraction": f / n if n else None,
                           "ci95": (lo, hi)})
        return StudySummary(self.runs, self.errors, len(R), outputs, limits,
                            sorted(((text, [count, first]) for count, first, text in self.reasons.values()),
                                   key=lambda kv: -kv[1][0]), self.more_reasons,
                            {key: (n, c) for key, (n, c) in self.checks.items()}, dict(self.warnings),
                            self.more_warnings, sorted(self.extra_keys), R)


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


def ranks(x: np.ndarray) -> np.ndarray:
    """Average ranks from 1 (tied values share the mean of their places), as
    ``scipy.stats.rankdata`` gives them, without importing ``scipy.stats`` (about a quarter
    of a second of a study's command).

    >>> ranks(np.array([3.0, 1.0, 3.0, 2.0])).tolist()
    [3.5, 1.0, 3.5, 2.0]
    """
    _, where, counts = np.unique(np.asarray(x, float), return_inverse=True, return_counts=True)
    last = np.cumsum(counts)
    return (last - (counts - 1) / 2.0)[np.ravel(where)]


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


@dataclass
class StudySummary:
    """What a tolerance study reports (all SI): ``runs`` (``errors`` of them failed),
    ``kept`` rows in the reservoir, per output key its statistics, the limits' failure
    fractions with Wilson 95 % intervals, the failure reasons ((the first run's text, [runs,
    first run]) for each reason, texts that differ only in their numbers counted as one),
    the failing checks (key -> (runs, a failing Check)), the warnings (text -> runs), and
    keys some run reported that the nominal run did not (left out of the statistics), and
    the reservoir's rows (``sample``, in run order)."""

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
    batched exact propagation for 990 of 1,000 runs (beltcalc.sim.batch); the other 10 one by one (the scene's single run: one check run per group of 250, and runs the batch does not cover)
    >>> print(propagation(0, 5))
    one by one (the scene's single run)
    """
    if batched == 0:
        return "one by one (the scene's single run)"
    text = f"batched exact propagation for {batched:,} of {runs:,} runs (beltcalc.sim.batch)"
    if batched < runs:
        text += (f"; the other {runs - batched:,} one by one (the scene's single run: one check run per group of "
                 "250, and runs the batch does not cover)")
    return text
