"""What one run of a scene reports: the :class:`Outcome` (its sections, notes and checks, as
text rows, JSON and sweep columns) and the sections the scenes share, one per tension-only
strand (:func:`strand_sections`) and those of an exact periodic steady state
(:func:`steady_sections`, rows :class:`SteadyRow`). SI floats; nothing here prints or
writes files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Iterable, Mapping

import numpy as np

from beltcalc.design.checks import RULES
from beltcalc.errors import InputError
from beltcalc.report import Column, Section
from beltcalc.sim.scenes.fatigue import fatigue_sections, slack_time, tension_strands
from beltcalc.sim.scenes.run_checks import stall_line, stalls

__all__ = ["Outcome", "SteadyRow", "steady_sections", "strand_sections", "switched_sections", "tension_strands"]


@dataclass
class Outcome:
    """One run of a scene: the network, the result and what to report."""

    net: object                 # beltcalc.sim.network.Network
    result: object              # beltcalc.sim.result.SimResult
    sections: list[Section]
    notes: list[str] = field(default_factory=list)
    checks: list = field(default_factory=list)      # beltcalc.design.checks.Check
    window: float | None = None                      # start of the steady window [s] (None: the asked one)

    def __post_init__(self):
        # every run checks its own error estimate against the tolerance it was given; each
        # failing check is a warning (stderr, the JSON's one `warnings` key)
        r = self.result
        if getattr(r, "error_estimate", None) is not None and r.extra.get("error_tol"):
            self.checks.append(RULES["error_estimate"].check(r.error_relative, r.extra["error_tol"],
                                                             detail=f"relative to the scale of {r.error_signal}"))
        from beltcalc.design.checks import failures

        for c in failures(self.checks):
            if c.key == "error_estimate" and r.extra.get("error_accepted"):
                continue                 # the core's own warning says it ("accepted with a large error")
            if c.warning() not in r.warnings:
                r.warnings.append(c.warning())

    def require_running(self, accept: bool = False) -> None:
        """Refuse a run whose drive stalls (a failing check of
        :data:`~beltcalc.sim.scenes.run_checks.STALL_CHECKS`): its means and amplitudes are of
        no steady state. With ``accept`` the run is kept with a warning, and every row of the
        report says it is of a stalled drive.

        Raises :class:`~beltcalc.errors.InputError` (one line: how it stalls, what to try)."""
        if not stalls(self.checks):
            return
        line = stall_line(self.checks)
        if not accept:
            raise InputError(f"{line}. No steady state to report: lower the loads or choose a stronger motor "
                             "(`accept_error` prints the run, every row marked)")
        mark = "of a stalled drive: no steady state"
        self.sections = [replace(sec, rows=[replace(r, note=f"{r.note}; {mark}" if r.note else mark)
                                            for r in sec.rows]) for sec in self.sections]
        if line not in self.result.warnings:
            self.result.warnings.insert(0, line + "; printed with `accept_error`: every row is of a stalled drive")

    def to_dict(self, title: str, modes: bool = False) -> dict:
        """The run as one JSON-ready object: the scene's ``title``, how it was solved, every
        section's rows as ``{key: {"value": SI, "unit": SI unit}}`` placed by its path, the
        notes, and with ``modes`` every pole of the network
        (:meth:`beltcalc.sim.frequency_report.Modes.to_list`: ``kind``; an oscillatory
        mode's ``frequency`` and ``damping_ratio``, a real pole's ``time_constant``)."""
        r = self.result
        obj = {"scene": title, "method": r.method, "reason": r.reason,
               "wall_time": {"value": r.wall_time, "unit": "s"}, "steps": r.steps, "rhs_calls": r.rhs_calls,
               "error_estimate": {"value": r.error_estimate, "unit": r.error_unit},
               "error_relative": {"value": r.error_relative, "unit": "1"}, "error_signal": r.error_signal,
               "error_reference": r.error_reference, "warnings": list(r.warnings)}
        if r.extra.get("slack_time"):
            obj["events"] = r.extra["events"]
        for sec in self.sections:
            node = obj
            for key in sec.path:
                node = node.setdefault(key, {})
            node.update({row.key: {"value": row.value, "unit": row.unit} for row in sec.rows})
        if modes:
            from beltcalc.sim.frequency_report import modes as every_pole

            obj["modes"] = every_pole(self.net, shapes=False).to_list(shapes=False)
        if self.notes:
            obj["notes"] = self.notes
        obj["checks"] = [c.to_dict() for c in self.checks]
        obj["warnings"] = list(r.warnings)
        return obj

    def columns(self) -> list[tuple[str, float]]:
        """Every reported value as (``<item or section>_<key>_<unit>``, SI value): a sweep row."""
        return [(c.key, c.value) for c in self.column_rows()]

    def column_rows(self) -> list[Column]:
        """Every reported value as a :class:`~beltcalc.report.Column` (key, readable label,
        SI unit, display unit, value): what a sweep or study reports per run. A key is the
        section's (its ``key``, else the last part of its path), its row's and its SI unit
        (``main_speed_mean_rad_per_s``); the exact periodic steady state's keys begin
        ``steady_`` and their labels say ``steady`` (``steady_main_speed_mean_rad_per_s``,
        "main shaft (3) steady: speed, mean"), the window's say neither: a key and its label
        name the same quantity."""
        from beltcalc.sim.result import unit_tag

        cols = []
        for sec in self.sections:
            steady = sec.path[0] == "steady_state"
            where = sec.title.split(",")[0] + (" steady" if steady else "")
            name = ("steady_" if steady else "") + (sec.key or sec.path[-1])
            for row in sec.rows:
                unit = "" if row.unit in ("", "1") else "_" + unit_tag(row.unit)
                cols.append(Column(f"{name}_{row.key}{unit}", f"{where}: {row.label}", row.unit,
                                   row.display or row.unit, row.value))
        return cols



def strand_sections(net, result, limits: Mapping[str, tuple[float, str]], group: str,
                    label: str = "limit / max") -> list[Section]:
    """One row per tension-only strand (:func:`tension_strands`) over the whole run: force min
    and max (off the exact solution where the run kept them), the time it was slack
    (:func:`~beltcalc.sim.scenes.fatigue.slack_time`), and its force limit (a chain's
    breaking load, a belt's F_Tadm: ``limits[name] = (N, what)``) over its peak; then per
    chain strand its fatigue (:func:`~beltcalc.sim.scenes.fatigue.fatigue_sections`).
    The contacts of a backlash are strands to the core but not here: their backlash reports
    them (:func:`beltcalc.sim.scenes.drive.backlash_sections`)."""
    from beltcalc.report import Row

    out = []
    for strand in tension_strands(net):
        s = result.summary(f"F_{strand.name}", 0.0)
        rows = [Row("force_min", "force min", s.min, "N"), Row("force_max", "force max", s.max, "N"),
                Row("slack_time", "time slack", slack_time(net, result, strand.name), "s")]
        if strand.name in limits:
            limit, what = limits[strand.name]
            rows.append(Row("safety", label, limit / max(s.max, 1e-300), "1", digits=3, note=what))
        out.append(Section(("strands", strand.name), strand.name, rows, group=group, item=strand.name))
    return out + fatigue_sections(net, result)



def switched_sections(net, result, limits: Mapping[str, tuple[float, str]]) -> list[Section]:
    """The elements with modes of their own over the whole run: each friction element's
    (clutch, brake, bearing) time stuck, slipping and free, its mode changes, its heat (the
    slip work, exact on the exact path) and peak torque, then its rating over that peak
    (``limits[name] = (N m, what)``); each limited drive's time in range, at its limit and
    held there, and its mode changes."""
    from beltcalc.report import Row
    from beltcalc.sim.elements.switched import Friction

    history = result.extra.get("switched")
    if not history:
        return []
    out, rated = [], []
    for el in net.switched:
        spent, changes = history["time"][el.name], float(history["switches"][el.name])
        if isinstance(el, Friction):
            signal = f"T_{el.name}"
            peak = float(np.max(np.abs(result.signals[signal]))) if signal in result.signals else 0.0
            rows = [Row("time_stuck", "time stuck", float(spent["stuck"]), "s"),
                    Row("time_slipping", "time slipping", float(spent["forward"] + spent["backward"]), "s"),
                    Row("time_free", "time free", float(spent["free"]), "s"),
                    Row("switches", "mode changes", changes, "1", digits=6),
                    Row("heat", "slip heat", float(history.get("heat", {}).get(el.name, math.nan)), "J"),
                    Row("torque_peak", "torque, peak", peak, result.units.get(signal, "N m"))]
            out.append(Section(("switched", el.name), el.name, rows, group="clutches, brakes and friction, whole "
                               "run (slip heat: the work friction turned into heat)", item=el.name))
            if el.name in limits:
                limit, what = limits[el.name]
                rated.append(Section(("ratings", el.name), el.name, [
                    Row("torque_peak", "torque, peak", peak, result.units.get(signal, "N m")),
                    Row("rating", what, limit, result.units.get(signal, "N m")),
                    Row("safety", "rating / peak", limit / max(peak, 1e-300), "1", digits=3)],
                    group="clutch and brake ratings, whole run", item=el.name))
        else:
            rows = [Row("time_free", "time in range", float(spent["free"]), "s"),
                    Row("time_limit", "time at its limit",
                        float(sum(v for k, v in spent.items() if k in ("high", "low"))), "s"),
                    Row("time_held", "time held at it", float(sum(v for k, v in spent.items() if "held" in k)), "s"),
                    Row("switches", "mode changes", changes, "1", digits=6)]
            out.append(Section(("switched", el.name), el.name, rows, group="drive torque limits, whole run",
                               item=el.name))
    return out + rated


@dataclass(frozen=True)
class SteadyRow:
    """One row of a steady-state section: ``stat`` (``"mean"`` or ``"amplitude"``) of the
    steady-state output ``signal`` times ``scale`` (a belt span's force: its torque over its
    lever [1/m]), in ``unit`` (default: the signal's SI unit)."""

    key: str
    label: str
    signal: str
    stat: str = "mean"
    display: str = ""
    digits: int = 4
    scale: float = 1.0
    unit: str = ""


def steady_sections(ss, layout: Iterable[tuple]) -> list[Section]:
    """The sections of an exact periodic steady state ``ss``
    (:class:`beltcalc.sim.frequency.SteadyState`) under the JSON key ``steady_state``:
    ``layout`` is ``(name, title, rows, group, item)`` per section (``name`` a string or a
    path below ``steady_state``; ``rows`` :class:`SteadyRow`; ``group``, ``item`` as
    :class:`~beltcalc.report.Section`'s). The sewing scene and a drive file report their
    steady state through it.

    >>> from beltcalc.sim.frequency import SteadyState
    >>> ss = SteadyState({"omega_a": 10.0}, {"omega_a": 0.5}, {}, {"omega_a": "rad/s"}, [], True)
    >>> sec, = steady_sections(ss, [("a", "a, periodic steady state (exact)",
    ...                              [SteadyRow("speed_mean", "speed, mean", "omega_a"),
    ...                               SteadyRow("speed_amplitude", "speed, amplitude", "omega_a", "amplitude")],
    ...                              "", "")])
    >>> sec.path, [(r.key, r.value, r.unit) for r in sec.rows]
    (('steady_state', 'a'), [('speed_mean', 10.0, 'rad/s'), ('speed_amplitude', 0.5, 'rad/s')])
    """
    from beltcalc.report import Row

    out = []
    for name, title, rows, group, item in layout:
        path = ("steady_state",) + ((name,) if isinstance(name, str) else tuple(name))
        values = [(r, (ss.mean if r.stat == "mean" else ss.amplitude)[r.signal]) for r in rows]
        out.append(Section(path, title, [
            Row(r.key, r.label, v * (r.scale if r.stat == "mean" else abs(r.scale)), r.unit or ss.units[r.signal],
                r.display, r.digits) for r, v in values], group=group, item=item))
    return out

