"""A drive file as a scene (``beltcalc simulate drive FILE``): its parameters are the file's
values (``ELEMENT.KEY``, and ``t_end``/``samples``/``window``), and its report follows the
file: every node's speed, every coupling's and shaft's torque, every backlash's torque and
contacts, every strand's extremes, slack time and safety, every motor's torque, over the
steady window (strands, and a backlash's peak and contacts: the whole run). Means and
extremes come off the exact solution where the run is exact (:mod:`beltcalc.sim.watch`).
Where the drive has an exact periodic steady state (linear, strands taut in it, constant and
sinusoidal inputs after the last input change, before the window) the same quantities in
it, exactly (``steady_state``); else a note says why. A check says whether the start-up
transient has decayed by the window's start (the slowest pole). SI floats only.

References:

[M16] D. A. Mamatova, S. Zhang, A. Djuraev, M. A. Mansurova, "Analysis of Belting Stiffness
    Transmission Impact on Rotating Mass Motion Law of Technological Machines" (2016): the
    induction motor's characteristic [M16 eq. 2], which a start from rest without a ramp leaves.
[MSL] Modelica Association, Modelica Standard Library 4.0.0 (2020),
    Modelica.Mechanics.Rotational.Components.ElastoBacklash2: the backlash a drive's
    ``[[backlash]]`` entries report.
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

from beltcalc.params import Param
from beltcalc.report import Row, Section
from beltcalc.sim.scenes.base import (Outcome, Scene, SteadyRow, check_timing, exact_steady_state,
                                      motor_checks, resonance_check, settling_check, steady_sections, strand_check,
                                      strand_sections, strands_at_end)
from beltcalc.sim.scenes.outcome import switched_sections


class _FileScene:
    """What :meth:`Scene.resolve` reads from a scene file: title, source path, values."""

    def __init__(self, drive_file):
        class _Source:
            path = drive_file.path

        self.title = drive_file.head.raw.get("title") or drive_file.path.stem
        self.source = _Source()
        self.values = {p.name: (p.text, "drive file") for p in drive_file.params() if p.text is not None}


def _param(p) -> Param:
    unit = {"text": None}.get(p.unit, p.unit)
    if p.name == "samples":
        unit = ""
    return Param(p.name, unit, p.help, required=p.name in ("t_end",))


def drive_scene(ref: str | Path, catalog=None) -> Scene:
    """The scene of a drive file (a path, or a built-in drive by name).

    >>> from beltcalc.sim.core import SolverConfig
    >>> from beltcalc.sim.scenes.base import run_scene
    >>> scene = drive_scene("friswell_5_disks")
    >>> out = run_scene(scene, scene.values(samples=201.0), SolverConfig())
    >>> [s.item for s in out.sections if s.path[0] == "nodes"]
    ['disk1', 'disk2', 'disk3', 'disk4', 'disk5']
    """
    from beltcalc.sim.drivefile import DriveFile, drive_path

    f = DriveFile(drive_path(ref))
    f.build(catalog=catalog)            # the file as written: its own errors name element and key
    params = [_param(p) for p in f.params()]
    speeds = [(f"omega_{e.name}" if "mass" not in e.raw else f"v_{e.name}", e.name)
              for e in f.entries if e.section == "node"]
    return Scene(name="drive", file=str(f.path), params=params,
                 build=partial(_build, f, catalog), run=partial(_run, f, catalog),
                 timing=partial(_timing, f, catalog),
                 signal=speeds[0][0], sweep_example=_sweep_example(params),
                 sweep_columns=(), plot=(("speed", tuple(speeds)),),
                 load=lambda _ref: _FileScene(f))


def _sweep_example(params: list[Param]) -> str:
    p = next((p for p in params if "." in p.name and p.unit not in (None, "int") and "|" not in p.unit), None)
    return f"{p.name}=START:STOP:N" if p else "t_end=1s:2s:3"


def _values(values: dict) -> dict:
    """Scene values as the drive file's builder takes them (the timing as given)."""
    out = dict(values)
    if "samples" in out and out["samples"] is not None:
        out["samples"] = int(out["samples"])
    return out


def _build(drive_file, catalog, values: dict, **options):
    return drive_file.build(_values(values), catalog).network


def _timing(drive_file, catalog, values: dict, **options) -> tuple[float, int]:
    drive = drive_file.build(_values(values), catalog)
    return drive.t_end, drive.samples


def _run(drive_file, catalog, values: dict, cfg, **options) -> Outcome:
    from beltcalc.sim.core import simulate

    drive = drive_file.build(_values(values), catalog)
    check_timing({"t_end": drive.t_end, "samples": float(drive.samples), "window": drive.window})
    net = drive.network
    w0 = drive.window
    watched = [_speed(net, n) for n in drive.nodes] + [s for s, _ in drive.torques]
    watched += [f"F_{s.name}" for s in net.tension_strands] + [s for s, _ in drive.motors]
    # what the report gives: nodes and couplings over the window, strands over the whole run,
    # motors both (their peak over the run): the estimate judges these figures
    reported = {name: (w0,) for name in watched}
    reported.update({f"F_{s.name}": (0.0,) for s in net.tension_strands})
    reported.update({f"F_{c.name}": (0.0, w0) for bl in _backlashes(net) for c in bl.contacts()})
    reported.update({s: (0.0, w0) for s, _ in drive.motors})
    result = simulate(net, drive.t_end, drive.samples, cfg, watch=(watched, (0.0, w0), reported))
    checks = strand_check(net, result, drive.limits, None) + damping_fit_check(drive) + resonance_check(net, result, w0)
    # a start from rest without a ramp is outside [M16 eq. 2]: its peak counts from the window
    for m in net.motors:
        checks += motor_checks(result, f"M_{m.name}", m.breakdown_torque, w0, 0.0 if m.sync_table else w0,
                               speed=_speed(net, m.node))
    notes = list(drive.notes)
    sections = report(drive, result)
    steady, why = steady_state(drive)
    if steady is None:
        notes.append(f"no exact steady state: {why}")
    else:
        sections += steady_report(drive, steady)
    # the transient's decay: the poles with the strands as in the steady state (taut), else as
    # at the end of the run; those of the linear part where the drive is nonlinear
    taut = None if steady is not None else strands_at_end(net, result)
    checks += settling_check(net, w0, drive.t_end, taut)
    return Outcome(net, result, sections, notes, checks)


def damping_fit_check(drive) -> list:
    """The damping fit of the belt spans whose b was fitted to the catalog's F_tspec(n) (no
    ``damping`` given), by the rule ``tension`` applies (:data:`beltcalc.design.checks.RULES`
    ``damping_fit``, R^2 >= 0.9): the worst span's R^2, with how many fall below it. No
    fitted span: no check.

    >>> from types import SimpleNamespace as NS
    >>> c, = damping_fit_check(NS(fits={"upper": (0.659, "fitted on p1"), "lower": (0.95, "fitted on p2")}))
    >>> c.value, c.verdict
    (0.659, 'FAIL')
    """
    from beltcalc.design.checks import RULES

    if not drive.fits:
        return []
    rule = RULES["damping_fit"]
    name, (r2, how) = min(drive.fits.items(), key=lambda kv: kv[1][0])
    below = sum(1 for value, _ in drive.fits.values() if rule.check(value).verdict == "FAIL")
    detail = f"belt span {name}, b_TB {how}"
    if below > 1:
        detail += f"; {below} of {len(drive.fits)} fitted spans are below it"
    return [rule.check(r2, detail=detail + f"; give `{name}.damping` from a measurement")]


def steady_state(drive):
    """``(ss, None)``: the exact periodic steady state of every quantity the report gives
    over its window (:func:`~beltcalc.sim.scenes.base.exact_steady_state`), or ``(None,
    why)``."""
    net = drive.network
    if _backlashes(net):
        names = ", ".join(bl.name for bl in _backlashes(net))
        return None, (f"backlash {names}: the steady state is solved with every contact closed, and the two "
                      "sides of a dead band cannot both be")
    outputs = [_speed(net, n) for n in drive.nodes] + [s for s, _ in drive.torques]
    outputs += [f"T_{name}" for name in drive.spans] + [f"F_{s.name}" for s in net.strands]
    outputs += [s for s, _ in drive.motors]
    return exact_steady_state(net, list(dict.fromkeys(outputs)), drive.window)


def steady_report(drive, ss) -> list:
    """The sections of the exact periodic steady state ``ss``, as the window's are laid out
    (nodes, couplings and shafts, two-way spans, strands, motors: mean and amplitude),
    under ``steady_state`` (:func:`~beltcalc.sim.scenes.base.steady_sections`)."""
    net = drive.network
    exact = "periodic steady state (exact)"
    layout = [(("nodes", node), node, [
        SteadyRow("speed_mean", "speed mean", _speed(net, node), digits=5),
        SteadyRow("speed_amplitude", "ampl.", _speed(net, node), "amplitude"),
    ], f"nodes, {exact}", node) for node in drive.nodes]
    for signal, name in drive.torques:
        force = ss.units[signal] != "N m"
        layout.append((("couplings", name), name, [
            SteadyRow("torque_mean", "force mean" if force else "torque mean", signal),
            SteadyRow("torque_amplitude", "ampl.", signal, "amplitude"),
        ], f"couplings and shafts, {exact}", name))
    for name, lever in drive.spans.items():
        layout.append((("spans", name), name, [
            SteadyRow("force_mean", "force mean", f"T_{name}", scale=1 / lever, unit="N"),
            SteadyRow("force_amplitude", "ampl.", f"T_{name}", "amplitude", scale=1 / lever, unit="N"),
        ], f"belt spans (two-way), {exact}", name))
    for strand in net.strands:
        layout.append((("strands", strand.name), strand.name, [
            SteadyRow("force_mean", "force mean", f"F_{strand.name}"),
            SteadyRow("force_amplitude", "ampl.", f"F_{strand.name}", "amplitude"),
        ], f"strands, {exact} (taut throughout: mean - ampl. > 0)", strand.name))
    for signal, node in drive.motors:
        layout.append((("motors", signal), f"motor on {node} ({signal}), {exact}", [
            SteadyRow("torque_mean", "torque, mean", signal),
            SteadyRow("torque_amplitude", "torque, amplitude", signal, "amplitude"),
            SteadyRow("speed_mean", "speed, mean", _speed(net, node), digits=5),
        ], "", ""))
    return steady_sections(ss, layout)


def _speed(net, node: str) -> str:
    return f"v_{node}" if net.node(node).translation else f"omega_{node}"


def report(drive, result) -> list[Section]:
    """The sections of a drive's run: nodes, couplings and shafts, two-way spans, strands,
    motors (see the module docstring)."""
    net, w0 = drive.network, drive.window
    out = []
    where = f"t >= {w0:g} s"
    for node in drive.nodes:
        name = _speed(net, node)
        s = result.summary(name, w0)
        unit = result.units[name]
        out.append(Section(("nodes", node), node, [
            Row("speed_mean", "speed mean", s.mean, unit, digits=5),
            Row("speed_amplitude", "ampl.", s.amplitude, unit),
            Row("speed_min", "min", s.min, unit, digits=5),
            Row("speed_max", "max", s.max, unit, digits=5),
        ], group=f"nodes, {where}", item=node))
    for signal, name in drive.torques:
        s = result.summary(signal, w0)
        unit = result.units[signal]
        rows = [Row("torque_mean", "torque mean" if unit == "N m" else "force mean", s.mean, unit),
                Row("torque_amplitude", "ampl.", s.amplitude, unit),
                Row("torque_min", "min", s.min, unit), Row("torque_max", "max", s.max, unit)]
        out.append(Section(("couplings", name), name, rows, group=f"couplings and shafts, {where}", item=name))
    out += backlash_sections(net, result, w0)
    for name, lever in drive.spans.items():
        s = result.summary(f"T_{name}", w0)
        out.append(Section(("spans", name), name, [
            Row("force_mean", "force mean", s.mean / lever, "N"),
            Row("force_amplitude", "ampl.", s.amplitude / lever, "N"),
            Row("force_min", "min", s.min / lever, "N"), Row("force_max", "max", s.max / lever, "N"),
        ] + _safety(drive, name, max(abs(s.min), abs(s.max)) / lever),
            group=f"belt spans (two-way), {where}; limit: F_Tadm", item=name))
    out += strand_sections(net, result, drive.limits, "strands, whole run (tension only; slack = no force; "
                           "limit: a belt's F_Tadm, a chain's breaking load)")
    out += switched_sections(net, result, drive.limits)
    for signal, node in drive.motors:
        s, whole = result.summary(signal, w0), result.summary(signal, 0.0)
        speed = result.summary(_speed(net, node), w0)
        unit = result.units[signal]
        out.append(Section(("motors", signal), f"motor on {node} ({signal}), {where}", [
            Row("torque_mean", "torque, mean", s.mean, unit),
            Row("torque_amplitude", "torque, amplitude", s.amplitude, unit),
            Row("torque_peak", "torque, peak over the run", max(abs(whole.min), abs(whole.max)), unit),
            Row("speed_mean", "speed, mean", speed.mean, result.units[_speed(net, node)], digits=5),
        ]))
    return out


def _backlashes(net) -> list:
    """The :class:`~beltcalc.sim.elements.backlash.Backlash` elements of ``net``."""
    from beltcalc.sim.elements.backlash import Backlash

    return [el for el in net.elements if isinstance(el, Backlash)]


def backlash_sections(net, result, window: float) -> list[Section]:
    """One section per backlash [MSL ElastoBacklash2]: its torque ``T = F+ - F-`` over the
    window (mean, amplitude, min, max), its peak ``|T|`` over the run, the time each side was
    in contact and how many contacts each made (a switch to contact after the start; exact
    runs only, which log their switches).

    Where the run watched the contacts' forces (:func:`beltcalc.sim.core.simulate`'s
    ``watch``) these come off the exact solution: the two sides never push at once (with b
    > 0 they are apart; with b = 0 one side's virtual torque is the other's negative), so
    ``max T`` is the largest + force, or if the + side never closed in the window minus the
    least - force, ``min T`` likewise, and the mean is the difference of the forces' exact
    means.
    """
    slack = result.extra.get("slack_time", {})
    switches = result.extra.get("switches")
    t_end = float(result.t[-1])
    out = []
    for bl in _backlashes(net):
        unit = result.units[f"T_{bl.name}"]
        plus, minus = (f"{bl.name}{side}" for side in "+-")
        p, m = result.summary(f"F_{plus}", window), result.summary(f"F_{minus}", window)
        hi = p.max if p.max > 0 else -m.min
        lo = -m.max if m.max > 0 else p.min
        peak = max(result.summary(f"F_{plus}", 0.0).max, result.summary(f"F_{minus}", 0.0).max)
        rows = [Row("torque_mean", "torque mean" if unit == "N m" else "force mean", p.mean - m.mean, unit),
                Row("torque_amplitude", "ampl.", 0.5 * (hi - lo), unit),
                Row("torque_min", "min", lo, unit), Row("torque_max", "max", hi, unit),
                Row("torque_peak", "peak, run", peak, unit),
                Row("contact_plus", "+ side closed, run", t_end - float(slack.get(plus, t_end)), "s"),
                Row("contact_minus", "- side closed, run", t_end - float(slack.get(minus, t_end)), "s")]
        if switches is not None:
            for name, key, label in ((plus, "contacts_plus", "+ contacts"), (minus, "contacts_minus", "- contacts")):
                made = sum(1 for _, strand, on in switches if strand == name and on)
                rows.append(Row(key, label, float(made), "1", digits=9))
        out.append(Section(("backlash", bl.name), bl.name, rows, item=bl.name,
                           group=f"backlash, t >= {window:g} s (peak, time closed and contacts: whole run)"))
    return out


def _safety(drive, name: str, force_max: float) -> list[Row]:
    """The strand's force limit (a chain's breaking load, a belt's F_Tadm) over its peak force."""
    if name not in drive.limits:
        return []
    limit, what = drive.limits[name]
    return [Row("safety", "limit / max", limit / max(force_max, 1e-300), "1", digits=3, note=what)]
