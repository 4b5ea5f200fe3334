"""Sweeps and grids over a scene's parameters: one run per point, each through
:func:`beltcalc.sim.scenes.base.run_scene` (in this process, or on Dask through
:func:`beltcalc.sim.study.execution.execute`), collected in a :class:`Sweep` (columns, rows,
failing checks, warnings; no time series unless asked).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

from beltcalc.report import Column
from beltcalc.sim.scenes.base import Scene, run_scene
from beltcalc.sim.study.execution import grid_rows
from beltcalc.sim.study.plan import Plan
from beltcalc.sim.study.runs import RunRow


@dataclass(frozen=True)
class Sweep:
    """The runs of a grid: one parameter, or several (the product, the last varying
    fastest). ``points[k]`` is the value (one parameter) or the tuple of values (several)
    of run ``k``, ``runs[k]`` its :class:`~beltcalc.sim.study.runs.RunRow` (its columns, failing
    checks, warnings, or the reason it failed); ``columns`` every column any run reported,
    in the order first met. No time series is kept (``outcomes`` only when asked:
    :func:`sweep_scene` with ``keep_outcomes``)."""

    names: tuple[str, ...]
    units: tuple[str, ...]         # each swept parameter's SI unit ("1" a plain number)
    points: list
    runs: list
    columns: dict
    outcomes: list = field(default_factory=list)
    how: str = "in-process"

    @property
    def name(self) -> str:
        """The swept parameter(s), ``A x B`` for several."""
        return " x ".join(self.names)

    @property
    def unit(self) -> str:
        return self.units[0] if len(self.units) == 1 else ""

    def _keys(self) -> list[Column]:
        from beltcalc.sim.result import unit_tag

        out = []
        for name, unit in zip(self.names, self.units):
            key = name if unit == "1" else f"{name}_{unit_tag(unit)}"
            out.append(Column(key, name, unit, unit))
        return out

    def header(self) -> list[str]:
        """The swept parameters, then every reported value (:meth:`~beltcalc.sim.scenes.outcome.Outcome.columns`)."""
        return [c.key for c in self.column_info()]

    def column_info(self) -> list[Column]:
        """The swept parameters, then every value any run reports (runs of another layout, e.g.
        more rollers, add their columns in the order first met), as columns without values."""
        cols = {c.key: c for c in self._keys()}
        for k, c in self.columns.items():
            cols.setdefault(k, c)
        return list(cols.values())

    def _point(self, k: int) -> tuple[float, ...]:
        p = self.points[k]
        return tuple(p) if isinstance(p, (tuple, list)) else (p,)

    def rows(self) -> list[list[float | None]]:
        """One row per point, in the order of :meth:`column_info`; None where a run does not
        report that column (or failed: :meth:`errors`)."""
        keys = [c.key for c in self.column_info()][len(self.names):]
        return [list(self._point(k)) + [r.values.get(key) for key in keys] for k, r in enumerate(self.runs)]

    def errors(self) -> list[tuple[int, str]]:
        """(index, reason) of every point whose run failed."""
        return [(k, r.error) for k, r in enumerate(self.runs) if r.error is not None]

    def _where(self, at: list[int]) -> str:
        def one(k):
            return ", ".join(f"{n} = {v:.6g}{'' if u in ('', '1') else ' ' + u}"
                             for n, v, u in zip(self.names, self._point(k), self.units))
        if len(self.names) == 1:
            unit = "" if self.units[0] in ("", "1") else f" {self.units[0]}"
            return f"{self.names[0]} = " + ", ".join(f"{self._point(k)[0]:.6g}" for k in at[:5]) + \
                (", ..." if len(at) > 5 else "") + unit
        return "; ".join(one(k) for k in at[:3]) + ("; ..." if len(at) > 3 else "")

    def warnings(self) -> list[str]:
        """Every distinct warning of the runs (and reason a run failed), once, with the points
        where it was given."""
        seen: dict[str, list[int]] = {}
        for k, r in enumerate(self.runs):
            for w in r.warnings:
                seen.setdefault(w, []).append(k)
            if r.error is not None:
                seen.setdefault(f"the run failed: {r.error}", []).append(k)
        out = []
        for w, at in seen.items():
            out.append(w if len(at) == len(self.runs) else
                       f"{w} (at {len(at)} of {len(self.runs)} points: {self._where(at)})")
        return out

    def failed_checks(self) -> list:
        """Every failing check of every run (:class:`~beltcalc.design.checks.Check`)."""
        return [c for r in self.runs for c in r.failed]

    def _point_json(self, k: int) -> dict:
        vals = self._point(k)
        if len(self.names) == 1:
            return {"value": vals[0], "unit": self.units[0]}
        return {n: {"value": v, "unit": u} for n, v, u in zip(self.names, vals, self.units)}

    def to_dict(self, title: str) -> dict:
        """The sweep as one JSON-ready object: each swept parameter with its unit and values,
        the columns (key, label, SI unit), one row per point, the failing checks per point
        (``point``: ``{"value", "unit"}`` for one swept parameter, ``{name: {"value",
        "unit"}}`` for several), the points whose run failed with the reason (``errors``,
        when any did) and the warnings."""
        failed = [{"point": self._point_json(k), "checks": [c.to_dict() for c in r.failed]}
                  for k, r in enumerate(self.runs) if r.failed]
        if len(self.names) == 1:
            params = [{"name": self.names[0], "unit": self.units[0], "values": [self._point(k)[0]
                                                                             for k in range(len(self.runs))]}]
        else:
            params = [{"name": n, "unit": u, "values": list(dict.fromkeys(self._point(k)[i]
                                                                          for k in range(len(self.runs))))}
                      for i, (n, u) in enumerate(zip(self.names, self.units))]
        obj = {"scene": title, "study": "sweep", "parameters": params,
               "columns": [{"key": c.key, "label": c.label, "unit": c.unit} for c in self.column_info()],
               "rows": self.rows(), "failed_checks": failed}
        if self.errors():
            obj["errors"] = [{"point": self._point_json(k), "error": e} for k, e in self.errors()]
        obj["warnings"] = self.warnings()
        return obj


def swept_unit(scene: Scene, name: str) -> str:
    """The SI unit of a swept or varied parameter (``"1"`` a plain or whole number)."""
    param = next((p for p in scene.params if p.name == name), None)
    return param.unit if param is not None and param.unit not in (None, "int", "") else "1"


def grid_scene(scene: Scene, values: Mapping[str, object], grid: Sequence[tuple[str, Sequence[float]]], cfg,
               progress: Callable[[int], None] | None = None, workers: int | None = 1, scheduler: str | None = None,
               notes: list[str] | None = None, **options) -> Sweep:
    """One run per point of the product of ``grid`` (``[(name, points), ...]``), the other
    values as given; ``progress(n)`` after each ``n`` runs. Runs go through
    :func:`beltcalc.sim.study.execution.execute` (``workers``, ``scheduler``: in this process or on
    Dask). A run that fails (a solver failure) is a row with its reason; a point that is no
    valid value of its parameter, or a grid whose every run fails, raises the first such
    run's error."""
    names = tuple(n for n, _ in grid)
    plan = Plan(scene, dict(values), cfg, names, grid=tuple(tuple(float(x) for x in p) for _, p in grid),
                options=dict(options))
    runs, columns, how = grid_rows(plan, progress, workers, scheduler, notes)
    # a point the user asked for that is no valid value (an error about a swept parameter),
    # or a grid none of whose runs ran: the error of the first such run, as a single run says it
    bad = next((r for r in runs if r.error is not None and r.param in names), None)
    if bad is None and runs and all(r.error is not None for r in runs):
        bad = runs[0]
    if bad is not None:
        run_scene(scene, dict(values, **dict(zip(names, bad.inputs))), cfg, **options)   # raises it
    if len(names) == 1:
        points = [r.inputs[0] for r in runs]
    else:
        points = [tuple(r.inputs) for r in runs]
    return Sweep(names, tuple(swept_unit(scene, n) for n in names), points, runs, columns, how=how)


def sweep_scene(scene: Scene, values: Mapping[str, object], name: str, points: Sequence[float], cfg,
                progress: Callable[[], None] | None = None, keep_outcomes: bool = False, **options) -> Sweep:
    """One run per value of ``name`` in ``points``, the other values as given; ``progress()``
    is called after each run. ``keep_outcomes`` keeps every run's
    :class:`~beltcalc.sim.scenes.outcome.Outcome` (its time series: 2.5 MiB a run of the sewing
    scene) in ``Sweep.outcomes``; a run that then fails raises."""
    if not keep_outcomes:
        step = None if progress is None else (lambda n: [progress() for _ in range(n)])
        return grid_scene(scene, values, [(name, points)], cfg, step, **options)
    from beltcalc.design.checks import failures

    outcomes, runs, columns = [], [], {}
    for v in points:
        o = run_scene(scene, dict(values, **{name: v}), cfg, **options)
        outcomes.append(o)
        cols = o.column_rows()
        runs.append(RunRow((float(v),), {c.key: c.value if c.value is None or math.isfinite(c.value) else None
                                          for c in cols}, tuple(failures(o.checks)),
                           tuple(o.result.warnings)))
        for c in cols:
            columns.setdefault(c.key, replace(c, value=None))
        if progress is not None:
            progress()
    return Sweep((name,), (swept_unit(scene, name),), [float(v) for v in points], runs, columns, outcomes)
