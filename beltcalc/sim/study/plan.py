"""What a study runs: the runs of one scene with some of its values replaced, by the points
of a grid or by values drawn from distributions (:class:`Distribution`, read by
:func:`parse_vary`), in chunks (:class:`Plan`).

The values of chunk ``c`` are drawn from ``numpy.random.SeedSequence(seed, spawn_key=(c,))``
(the ``c``-th child of ``SeedSequence(seed).spawn``), so the rows do not depend on how many
workers run them. SI floats; no click, no pint (texts are read through
:mod:`beltcalc.params` and :mod:`beltcalc.units`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from beltcalc.errors import UsageError
from beltcalc.params import Param, bare_number

CHUNK = 250              # runs per task
MAX_GRID = 1_000_000     # points of a grid (its rows are kept for the table)


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
    chunk: int = CHUNK
    options: Mapping[str, object] = field(default_factory=dict)
    batch: bool = True             # batched exact propagation where the scene declares it (Scene.batch)

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
