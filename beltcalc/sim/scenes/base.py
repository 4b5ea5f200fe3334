"""What a scene is, and running one.

A :class:`Scene` names its parameters (:class:`~beltcalc.params.Param`), where their
values come from (a scene file, by default ``catalogs/scenes/<file>.toml``), how they
build a :class:`~beltcalc.sim.network.Network` and how one run is reported (an
:class:`Outcome`: sections of :class:`~beltcalc.report.Row`). Anything that can say this
is a scene: the built-in ones (:data:`beltcalc.sim.scenes.SCENES`), or a drive file whose
parameters are its ``ELEMENT.KEY`` addresses.

:func:`run_scene` runs a scene from SI values and a :class:`~beltcalc.sim.core.SolverConfig`
(:func:`scene_network` builds its network alone; sweeps, tolerance studies and work-precision:
:mod:`beltcalc.sim.study`). An error about one of the scene's values comes out with
``scope="scene"`` and the parameter's name (:func:`scene_values`). A scene may declare its
batch row (:class:`BatchRow`): what a study computes for many of its runs at once.
Nothing here prints, parses options or writes files.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable, Iterator, Mapping, Sequence

from beltcalc.checks import RULES
from beltcalc.errors import BeltcalcError, FloatRangeError, InputError, float_range, require_positive
from beltcalc.params import Param, Resolved, resolve
from beltcalc.report import Column, Section

TIMING = [Param("t_end", "s", "simulated time"), Param("samples", "", "output samples"),
          Param("window", "s", "start of the steady window")]

Panel = tuple[str, tuple[tuple[str, str], ...]]   # (y label, ((signal, legend), ...)): one plot panel


@dataclass
class Outcome:
    """One run of a scene: the network, the result and what to report."""

    net: object                 # beltcalc.sim.network.Network
    result: object              # beltcalc.sim.result.SimResult
    sections: list[Section]
    notes: list[str] = field(default_factory=list)
    checks: list = field(default_factory=list)      # beltcalc.checks.Check
    window: float | None = None                      # start of the steady window [s] (None: the asked one)

    def __post_init__(self):
        # every run checks its own error estimate against the tolerance it was given; each
        # failing check is a warning (stderr, the JSON's one `warnings` key)
        r = self.result
        if getattr(r, "error_estimate", None) is not None and r.extra.get("error_tol"):
            self.checks.append(RULES["error_estimate"].check(r.error_relative, r.extra["error_tol"],
                                                             detail=f"relative to the scale of {r.error_signal}"))
        from beltcalc.checks import failures

        for c in failures(self.checks):
            if c.key == "error_estimate" and r.extra.get("error_accepted"):
                continue                 # the core's own warning says it ("accepted with a large error")
            if c.warning() not in r.warnings:
                r.warnings.append(c.warning())

    def require_running(self, accept: bool = False) -> None:
        """Refuse a run whose drive stalls (a failing check of :data:`STALL_CHECKS`): its
        means and amplitudes are of no steady state. With ``accept`` the run is kept with a
        warning, and every row of the report says it is of a stalled drive.

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


def check_timing(values: Mapping[str, object]) -> int:
    """Refuse a run that cannot be made: ``t_end``, ``samples``, ``window``. Returns the sample count.

    >>> check_timing({"t_end": 1.0, "samples": 10001.0, "window": 0.5})
    10001
    """
    require_positive("t_end", values["t_end"], "s")
    from beltcalc.params import MAX_SAMPLES

    samples = int(values["samples"]) if values["samples"] <= MAX_SAMPLES else MAX_SAMPLES + 1
    if samples > MAX_SAMPLES:
        raise InputError(f"{values['samples']:g} samples; at most {MAX_SAMPLES:,}", param="samples")
    if samples < 2 or samples != values["samples"]:
        raise InputError(f"{values['samples']:g} samples; it must be a whole number >= 2", param="samples")
    if not 0 <= values["window"] < values["t_end"]:
        raise InputError(f"{values['window']:g} s is not inside the run (0..{values['t_end']:g} s)", param="window")
    return samples


def fixed_timing(values: Mapping[str, object], **options) -> tuple[float, int]:
    """(t_end, samples) of a scene whose :data:`TIMING` parameters give them."""
    return values["t_end"], check_timing(values)


@dataclass(frozen=True)
class BatchRow:
    """A scene's rows by batched exact propagation (:mod:`beltcalc.sim.batch`), for a study.

    ``rows(runs, cfg, **options)`` takes the runs of a chunk (each run's SI values, ``cfg``
    and ``options`` as :attr:`Scene.run` takes them) and gives each run's row: the values
    :meth:`Outcome.column_rows` would report, in their order, or None where the batch cannot
    vouch for the run (it then goes through the scene's single run). ``run`` is the run
    function whose rows these are: a scene whose ``run`` is another is not batched.
    """

    run: Callable[..., Outcome]
    rows: Callable[..., list]


@dataclass(frozen=True)
class Scene:
    """A scene: its parameters and what to do with their values.

    ``build(values, **options) -> Network``; ``run(values, cfg, **options) -> Outcome``;
    ``timing(values, **options) -> (t_end, samples)``. ``values`` are SI (as
    :meth:`values` resolves them); ``options`` are the scene's keyword inputs that are no
    value of the scene file (the linear axis's ``motor``). ``signal`` is the speed the
    work-precision table compares; ``sweep_example`` and ``sweep_columns`` show a sweep;
    ``plot`` lists the panels of a time plot. ``load(ref)`` reads the scene file
    (``title``, ``source.path``, ``values``: name -> (text, why)); by default
    :func:`beltcalc.scenefile.load_scene` for ``simulate <name>``. ``batch``: the rows a
    study may compute for many runs at once (:class:`BatchRow`; None: one run at a time).
    """

    name: str
    file: str                                   # the scene file run by default
    params: Sequence[Param]
    build: Callable[..., object]
    run: Callable[..., Outcome]
    signal: str
    sweep_example: str
    sweep_columns: tuple[str, ...]
    plot: tuple[Panel, ...] = ()
    timing: Callable[..., tuple[float, int]] = fixed_timing
    load: Callable[[str], object] | None = None
    batch: BatchRow | None = None

    @property
    def batched(self) -> Callable[..., list] | None:
        """The rows of :attr:`batch` where they are this scene's :attr:`run`'s, else None."""
        return self.batch.rows if self.batch is not None and self.batch.run is self.run else None

    @property
    def timed(self) -> bool:
        """True when the run's length and samples are parameters (:data:`TIMING`); else the
        scene finds them itself from its ``step``."""
        return any(p.name == "t_end" for p in self.params)

    def resolve(self, ref: str | None = None, given: Mapping[str, object] | None = None
                ) -> tuple[object, dict[str, Resolved]]:
        """(the scene file, each parameter's value with its origin): ``given`` (SI, None = not
        given) over the scene file ``ref`` (a built-in name or a path; default :attr:`file`)."""
        if self.load is not None:
            scene = self.load(ref or self.file)
        else:
            from beltcalc.scenefile import load_scene

            scene = load_scene(ref or self.file, command=f"simulate {self.name}")
        return scene, resolve(scene, self.params, given)

    def values(self, ref: str | None = None, **given) -> dict[str, object]:
        """The SI values of the scene file ``ref`` (default :attr:`file`), ``given`` ones replaced.

        >>> from beltcalc.sim.scenes import SCENES
        >>> SCENES["sewing"].values(C4=190.0)["C4"], SCENES["sewing"].values()["J1"]
        (190.0, 1.1e-05)
        """
        return {k: v.value for k, v in self.resolve(ref, given)[1].items()}

    def with_step(self, values: Mapping[str, object], step: float) -> dict[str, object]:
        """``values`` with the output step ``step`` [s]: the samples over ``t_end`` of a timed
        scene, else the scene's own ``step``."""
        from beltcalc.params import MAX_SAMPLES

        n = values["t_end"] / step + 1 if self.timed else values.get("t_end", 0.0) / step + 1
        if not n <= MAX_SAMPLES:
            raise InputError(f"{step:g} s gives {n:.3g} samples; at most {MAX_SAMPLES:,} (raise the step)",
                             param="step")
        if self.timed:
            return dict(values, samples=float(round(values["t_end"] / step) + 1))
        return dict(values, step=step)


@contextmanager
def scene_values(names: Iterable[str]) -> Iterator[None]:
    """Errors raised inside about one of ``names`` are about a scene's value: they leave
    with ``scope="scene"`` (the command line names them ``--set NAME``)."""
    names = set(names)
    try:
        yield
    except BeltcalcError as exc:
        if exc.param in names and exc.scope is None:
            exc.scope = "scene"
        raise


def run_scene(scene: Scene, values: Mapping[str, object], cfg, **options) -> Outcome:
    """One run of ``scene`` with SI ``values`` and the solver config ``cfg``.

    >>> from beltcalc.sim.core import SolverConfig
    >>> from beltcalc.sim.scenes import SCENES
    >>> sewing = SCENES["sewing"]
    >>> out = run_scene(sewing, sewing.values(t_end=0.3, window=0.2, samples=301.0), SolverConfig())
    >>> out.sections[0].title, out.result.method
    ('main shaft (3), t >= 0.2 s', 'exact')
    """
    with scene_values(p.name for p in scene.params):
        try:
            with float_range("the scene's model"):
                return scene.run(dict(values), cfg, **options)
        except FloatRangeError as exc:
            raise _blame(scene, values, exc, options) from None


def _blame(scene: Scene, values: Mapping[str, object], exc, options):
    """An overflow of ``scene`` with ``values``: about the value (differing from the scene
    file's) that makes its model overflow (:func:`beltcalc.errors.blame`: the model is
    built, and its first-order system, with each such value put back)."""
    from beltcalc.errors import blame

    try:
        defaults = scene.values()
    except BeltcalcError:
        return exc
    import inspect

    units = {p.name: p.unit for p in scene.params}
    changed = [k for k, v in values.items() if defaults.get(k) != v and isinstance(v, (int, float))]
    takes = inspect.signature(scene.build).parameters       # a run's options the build may not take
    if not any(p.kind == p.VAR_KEYWORD for p in takes.values()):
        options = {k: v for k, v in options.items() if k in takes}

    def probe(name):
        given = dict(values)
        if name is not None:          # put back: the file's value, or none where the file gives none
            given.pop(name)
            if defaults.get(name) is not None:
                given[name] = defaults[name]
        with float_range("the scene's model"):
            scene.build(given, **options).first_order()

    def show(name):
        unit = units.get(name) or ""
        unit = "" if unit in ("", "1", "int") or "|" in unit else f" {unit}"
        return f"{values[name]:g}{unit}"

    return blame(exc, changed, probe, show)


def scene_network(scene: Scene, values: Mapping[str, object], **options) -> tuple[object, float, int]:
    """(network, t_end, samples) of ``scene`` at SI ``values``, as its run would build them: an
    error about one of its values leaves with ``scope="scene"`` (:func:`scene_values`), an
    overflow names the value that causes it."""
    with scene_values(p.name for p in scene.params):
        try:
            with float_range("the scene's model"):
                net = scene.build(dict(values), **options)
                t_end, samples = scene.timing(dict(values), **options)
        except FloatRangeError as exc:
            raise _blame(scene, values, exc, options) from None
    return net, t_end, samples


def strand_sections(net, result, limits: Mapping[str, tuple[float, str]], group: str,
                    label: str = "limit / max") -> list[Section]:
    """One row per tension-only strand over the whole run: force min and max (off the exact
    solution where the run kept them), the time it was slack, and its force limit (a
    chain's breaking load, a belt's F_Tadm: ``limits[name] = (N, what)``) over its peak."""
    from beltcalc.report import Row

    slack = result.extra.get("slack_time", {})
    out = []
    for strand in net.strands:
        s = result.summary(f"F_{strand.name}", 0.0)
        rows = [Row("force_min", "force min", s.min, "N"), Row("force_max", "force max", s.max, "N"),
                Row("slack_time", "time slack", float(slack.get(strand.name, 0.0)), "s")]
        if strand.name in limits:
            limit, what = limits[strand.name]
            rows.append(Row("safety", label, limit / max(s.max, 1e-300), "1", digits=3, note=what))
        out.append(Section(("strands", strand.name), strand.name, rows, group=group, item=strand.name))
    return out


#: The rule of a strand by the limit it is given (``limits[name] = (N, what)``): a chain's
#: breaking load F_B with the safety F_B / F >= 6 that ``chain`` applies; a belt's F_Tadm.
STRAND_RULES = {"breaking load": "chain_safety", "F_Tadm": "belt_tension_member"}


def strand_check(net, result, limits: Mapping[str, tuple[float, str]], chain_param: str | None = "chain") -> list:
    """The strength check of the most loaded strand over the whole run, with how many
    strands fail theirs: a chain strand's breaking-load safety F_B / F against the same rule
    (:data:`beltcalc.checks.RULES` ``chain_safety``) as ``chain`` (which takes F = K_s F_pull
    + q v^2: its service factor stands for the shocks a run computes), a belt strand's peak
    force against F_Tadm (``belt_tension_member``). ``limits[name] = (N, what)``, ``what``
    a key of :data:`STRAND_RULES`; the most loaded is the one of largest utilisation. A chain
    strand that fails it is told the breaking load it needs and the first one-strand chain of
    ``catalogs/chains.toml`` (smallest pitch) that has it, set by ``chain_param`` (a scene's
    parameter; None: none names it).

    >>> from types import SimpleNamespace as NS
    >>> net = NS(strands=[NS(name="a")])
    >>> res = NS(summary=lambda name, start: NS(max=4196.0))
    >>> c, = strand_check(net, res, {"a": (22.2e3, "breaking load")})
    >>> round(c.value, 3), c.limit, c.verdict, c.level       # 22.2 kN / 4196 N; F_B / 6 on F_a
    (5.291, 6.0, 'FAIL', 3700.0)
    """
    checks = []
    for s in net.strands:
        if s.name not in limits:
            continue
        f, (limit, what) = result.summary(f"F_{s.name}", 0.0).max, limits[s.name]
        rule = RULES[STRAND_RULES[what]]
        if rule.limit is None:             # a force limit (F_Tadm)
            checks.append((rule.check(f, limit, key="strand_strength", name="strand force"), s.name, limit, what))
        else:                              # a safety on the breaking load
            safety = limit / f if f > 0 else math.inf
            checks.append((rule.check(safety, key="strand_strength", name="strand breaking-load safety"),
                           s.name, limit / rule.limit, what))
    if not checks:
        return []
    over = sum(1 for c, *_ in checks if c.verdict == "FAIL")
    worst, name, level, what = max(checks, key=lambda c: c[0].utilisation)
    detail = f"the peak force F over the run of strand {name}, the most loaded against its {what}"
    if over > 1:
        detail += f"; {over} of {len(checks)} strands fail it"
    signals = tuple(f"F_{n}" for _, n, lev, w in checks if lev == level and w == what)
    rule = RULES[STRAND_RULES[what]]
    if rule.limit is None:
        return [rule.check(worst.value, worst.limit, key="strand_strength", name=worst.name, detail=detail,
                           signals=signals)]
    if worst.verdict == "FAIL":
        detail += "; " + _stronger_chain(rule.limit * limits[name][0] / worst.value, chain_param)
    return [rule.check(worst.value, key="strand_strength", name=worst.name, detail=detail, signals=signals,
                       level=level)]


def _stronger_chain(need: float, param: str | None) -> str:
    """What to do where a chain strand needs the breaking load ``need`` [N]: the first
    one-strand chain of the built-in catalog (smallest pitch, then breaking load) that has it.

    >>> _stronger_chain(25.18e3, "chain")
    'it needs a chain of F_B >= 25.18 kN at this peak force: `chain`=12B-1 (28.9 kN, the smallest one-strand chain of catalogs/chains.toml that has it), then run again (another pitch changes the sprockets and the force)'
    """
    from beltcalc.catalogs import load_catalog

    text = f"it needs a chain of F_B >= {need / 1e3:.4g} kN at this peak force"
    fits = sorted((c for c in load_catalog().chains.values() if c.strands == 1 and c.breaking_load >= need),
                  key=lambda c: (round(c.pitch, 9), c.breaking_load))    # 60-1 and 12B-1: 19.05 mm
    if not fits:
        return text + ": stronger than every one-strand chain of catalogs/chains.toml; more strands or a lower load"
    pick = f"`{param}`={fits[0].name}" if param else fits[0].name
    return (text + f": {pick} ({fits[0].breaking_load / 1e3:.4g} kN, the smallest one-strand chain of "
            "catalogs/chains.toml that has it), then run again (another pitch changes the sprockets and the force)")




def resonance_check(net, result, window: float) -> list:
    """Plausibility: the drive's own periodic loads against its natural frequencies.

    Each load with an amplitude excites ``omega / 2 pi`` (a sine in time) or ``order`` times
    its node's mean speed over the steady window over ``2 pi`` (locked to the shaft angle).
    The check is the least relative separation ``|f_e - f_n| / f_n`` over the undamped
    natural frequencies ``f_n`` of the oscillatory modes (strands taut,
    :func:`beltcalc.sim.frequency.poles`) against the rule ``resonance`` of
    :data:`beltcalc.checks.RULES` (an assumed margin of 10 %). No periodic
    load, or no oscillatory mode: no check.
    """
    excitations = []
    for ld in net.loads:
        if not ld.amplitude:
            continue
        if ld.in_angle:
            name = f"omega_{ld.node}"
            if name not in result.signals:
                continue
            excitations.append((abs(ld.order * result.summary(name, window).mean) / (2 * math.pi),
                                f"the load on {ld.node}"))
        elif ld.omega:
            excitations.append((abs(ld.omega) / (2 * math.pi), f"the load on {ld.node}"))
    for el in net.elements:              # element kinds with a periodic excitation of their own
        if hasattr(el, "excitation"):
            excitations += el.excitation(result, window)
    if not excitations:
        return []
    from beltcalc.sim.frequency import poles

    modes = [p for p in poles(net) if p.kind == "oscillatory"]
    if not modes:
        return []
    sep, f_e, node, p = min(((abs(f - p.frequency) / p.frequency, f, node, p)
                             for f, node in excitations for p in modes), key=lambda x: x[0])
    return [RULES["resonance"].check(sep, detail=f"{node} excites {f_e:.4g} Hz, {sep:.1%} from a natural frequency "
                                                 f"of {p.frequency:.4g} Hz (damping ratio {p.damping_ratio:.3g})")]


def motor_checks(result, signal: str, breakdown: float, window: float, peak_from: float = 0.0,
                 speed: str | None = None) -> list:
    """An induction motor's torque against its breakdown torque M_c: the mean over the steady
    window (beyond it the motor stalls) and the peak from ``peak_from`` [s] on (beyond it the
    linearised characteristic of Mamatova et al. eq. 2 does not hold); with ``speed`` (the
    motor node's speed signal) whether the motor turns forwards over the window
    (:func:`stall_checks`)."""
    mean, part = result.summary(signal, window).mean, result.summary(signal, peak_from)
    peak = max(abs(part.min), abs(part.max))
    span = "over the run" if peak_from <= 0 else f"t >= {peak_from:.4g} s"
    turning, rising = None, False
    if speed is not None:
        turning = result.summary(speed, window).mean
        w = result.signals[speed][result.t >= window - 1e-12 * max(1.0, window)]
        # a motor still gaining speed through the window is starting up, not stalled: its
        # torque goes into the train's acceleration (a short window early in the run)
        rising = bool(turning > 0 and w.size > 1 and w[-1] - w[0] > ACCELERATING * turning)
    return stall_checks(mean, turning, breakdown, f"t >= {window:.4g} s", (signal,), rising) + [
        RULES["breakdown_peak"].check(peak, breakdown, key="motor_peak_torque", detail=span, signals=(signal,))]


#: The checks whose failure means the drive stalls (:func:`stall_checks`): a run that fails
#: one has no steady state to report.
STALL_CHECKS = ("motor_mean_torque", "motor_direction")


#: A motor turning forwards whose speed rises by more than this part of its mean over the
#: window is starting up.
ACCELERATING = 0.01


def stall_checks(torque: float, speed: float | None, breakdown: float, where: str, signals: tuple = (),
                 rising: bool = False) -> list:
    """Does an induction motor run? Its mean torque ``torque`` [N m] against its breakdown
    torque M_c (beyond it a real motor's torque falls and it stalls: the linearised
    characteristic of Mamatova et al. eq. 2 would go on rising), and its mean speed
    ``speed`` [rad/s] (None: not checked) in the direction of its synchronous speed (always
    forwards, > 0): loads that turn the motor backwards against the torque it drives
    with have stalled the train. ``where``: the window, for the rule. ``rising``: the motor
    gains speed through the window (a start-up): its mean torque check is n/a, not a verdict.

    >>> [c.verdict for c in stall_checks(2.0, 150.0, 3.0, "t >= 0.5 s")]
    ['pass', 'pass']
    >>> [c.verdict for c in stall_checks(36.4, -66.6, 3.0, "t >= 0.5 s")]
    ['FAIL', 'FAIL']
    """
    out = [RULES["breakdown_mean"].check(
        None if rising else abs(torque), breakdown, key="motor_mean_torque", detail=where, signals=signals,
        reason="the motor still gains speed through the window (a start-up): its mean torque goes into "
               "accelerating the train, no verdict on a stall" if rising else "")]
    if speed is not None:
        out.append(RULES["motor_direction"].check(speed, detail=f"{where}, in the direction of its synchronous "
                                                                 "speed"))
    return out


def stalls(checks) -> list:
    """The failing checks of ``checks`` that mean the drive stalls (:data:`STALL_CHECKS`)."""
    from beltcalc.checks import failures

    return [c for c in failures(checks) if c.key in STALL_CHECKS]


def stall_line(checks) -> str:
    """One line saying how the drive stalls, from its failing :data:`STALL_CHECKS`.

    >>> stall_line(stall_checks(36.4, -66.6, 3.0, "t >= 0.5 s"))
    'the drive stalls: motor mean torque 36.4 N m beyond the breakdown torque 3 N m (t >= 0.5 s); motor speed, mean -66.6 rad/s: the loads turn it backwards'
    """
    parts = []
    for c in stalls(checks):
        if c.key == "motor_direction":
            parts.append(f"{c.name} {c.value:.4g} {c.unit}: the loads turn it backwards")
        else:
            parts.append(f"{c.name} {c.value:.4g} {c.unit} beyond the breakdown torque {c.limit:.4g} {c.unit} "
                         f"({c.rule.split('; ')[-1]})")
    return "the drive stalls: " + "; ".join(parts)


# --- the exact periodic steady state, and whether the window has settled ----------------------------
#: What may be left of a start-up transient at the start of the steady window, relative to
#: the transient at its start: the slowest pole has decayed to this ln(1 / SETTLED) time
#: constants after the last input change (the registry's rule ``window_settled``, 0.1 %).
SETTLED = RULES["window_settled"].limit

#: States above which the settling check is not made: the poles of so large a drive (a
#: 100-roller table) cost seconds (a dense eigenvalue problem), more than some runs.
SETTLING_STATES = 800


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


def _decaying(p) -> bool:
    """A pole whose free motion decays (damping ratio above
    :data:`beltcalc.sim.frequency_report.UNDAMPED`, or a real pole's positive time constant)."""
    from beltcalc.sim.frequency_report import UNDAMPED

    if p.kind == "oscillatory":
        return p.damping_ratio > UNDAMPED
    return p.kind == "real" and p.time_constant > 0


def _pole_name(net, poles: list, p, taut=None) -> str:
    """A pole as a report names it: an oscillatory one by its mode number (as ``beltcalc
    modes`` numbers them), frequency, damping ratio and the element with the most strain
    energy (where the drive is small enough for its mode shapes); a real one by its time
    constant."""
    if p.kind != "oscillatory":
        return f"a real pole (time constant {p.time_constant:.4g} s)"
    k = [q for q in poles if q.kind == "oscillatory"].index(p) + 1
    where = ""
    if net.size <= SETTLING_STATES // 2:
        from beltcalc.sim.frequency import mode_shapes

        shapes = mode_shapes(net, taut)
        if k <= len(shapes) and shapes[k - 1].dominant:
            where = f", most strain energy in {shapes[k - 1].dominant}"
    return (f"mode {k} ({p.frequency:.4g} Hz, damping ratio {p.damping_ratio:.3g}, time constant "
            f"{-1.0 / p.s.real:.4g} s{where})")


def settling_check(net, window: float, t_end: float, taut=None, poles: list | None = None) -> list:
    r"""Has the start-up transient decayed by the start of the steady window?

    The free motion of the linear drive (strands ``taut``, default all) after the last input
    change ``t_b`` (a ramp's end, a load switched on; 0: the start from rest) decays as
    :math:`e^{\mathrm{Re}(s) t}` per pole s; the slowest decaying pole (largest time
    constant :math:`\tau = -1 / \mathrm{Re}\, s`; rigid-body and undamped poles never decay
    and do not count) leaves

    .. math:: r = e^{-(t_w - t_b) / \tau}

    of its start at the window's start :math:`t_w` (:math:`r = 1` where an input changes
    inside the window). The check is ``r <=`` :data:`SETTLED`, i.e.
    :math:`t_w - t_b \ge \ln(1000)\,\tau`; its rule names the pole and the ``window`` (and
    ``t_end``, for a window of the same length) that would pass. A drive above
    :data:`SETTLING_STATES` states is not checked (n/a, with the reason); one without a
    decaying pole has no check. ``poles``: the drive's (:func:`beltcalc.sim.frequency.poles`
    with ``taut``), where the caller has them.

    >>> from beltcalc.sim.network import Coupling, Inertia, Network
    >>> net = Network([Inertia("a", 1.0)], [Coupling("d", "a", None, 0.0, 4.0)])   # tau = J / d = 0.25 s
    >>> c, = settling_check(net, 1.0, 2.0)
    >>> round(c.value, 6), c.verdict         # e^-4
    (0.018316, 'FAIL')
    """
    if net.size > SETTLING_STATES:
        why = f"not checked: the drive has {net.size} states (more than {SETTLING_STATES}); its poles would cost more"
        return [RULES["window_settled"].check(None, reason=why + " than the run")]
    if poles is None:
        from beltcalc.sim.frequency import poles as every_pole

        poles = every_pole(net, taut)
    decaying = [p for p in poles if _decaying(p)]
    if not decaying:
        return []
    slow = max(decaying, key=lambda p: -1.0 / p.s.real)
    tau = -1.0 / slow.s.real
    need = math.log(1.0 / SETTLED) * tau
    changes = input_changes(net, t_end)
    last = max(changes) if changes else 0.0
    since = "the start from rest at 0 s" if not changes else f"the last input change at {last:.4g} s"
    length = t_end - window
    fix = (f"run with `window` >= {last + need:.4g} s and `t_end` >= {last + need + length:.4g} s (the same "
           f"{length:.4g} s window)")
    if window < last:
        residual = 1.0
        rule = f"an input changes at {last:.4g} s, inside the window (from {window:.4g} s); "
    else:
        residual = math.exp(-(window - last) / tau)
        rule = ""
    rule += (f"the slowest pole, {_pole_name(net, poles, slow, taut)}, decays to {SETTLED:g} of its start "
             f"{need:.4g} s (ln {1 / SETTLED:g} time constants) after {since}: {fix}")
    if taut is not None and not all(taut):
        slack = [s.name for s, on in zip(net.strands, taut) if not on]
        rule += f"; strands slack as at the end of the run: {', '.join(slack)}"
    return [RULES["window_settled"].check(residual, detail=rule)]


def input_changes(net, t_end: float = math.inf) -> list[float]:
    """The break points in (0, ``t_end``) where an input really changes: the time piece after
    it has another (A, B) than the one before (a table point on a straight line, or a table
    that repeats its value, changes nothing).

    >>> from beltcalc.sim.network import Inertia, Load, Network
    >>> net = Network([Inertia("a", 1.0)], [Load("a", table=((0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 2.0)))])
    >>> net.breaks(math.inf), input_changes(net)       # on a line through 1 s, held from 2 s
    ([1.0, 2.0, 3.0], [2.0])
    """
    import numpy as np

    starts = [0.0] + net.breaks(t_end)
    mids = [0.5 * (a + b) for a, b in zip(starts, starts[1:])] + [starts[-1] + 1.0]
    out = []
    for k in range(1, len(starts)):
        (A0, B0), (A1, B1) = net.first_order(None, mids[k - 1]), net.first_order(None, mids[k])
        if not (np.array_equal(A0, A1) and np.array_equal(B0, B1)):
            out.append(starts[k])
    return out


def strands_at_end(net, result) -> tuple[bool, ...] | None:
    """Which strands are taut at the end of the run (force > 0); None: no strands."""
    if not net.strands:
        return None
    return tuple(bool(result[f"F_{s.name}"][-1] > 0) for s in net.strands)


def exact_steady_state(net, outputs: Sequence[str], window: float | None = None, poles: list | None = None):
    """``(ss, None)``: the exact periodic steady state of ``outputs``
    (:func:`beltcalc.sim.frequency.steady_state`: strands taut, the inputs after the last
    break point), or ``(None, why)``: one line saying why there is none, for a note.

    There is none where the drive is nonlinear; a node's motion is prescribed (its speed is
    what the move left it); an input changes after ``window`` [s] starts (the steady state
    of the later inputs is not what the window shows); a mode is undamped or unstable (its
    free motion never decays); or where :func:`~beltcalc.sim.frequency.steady_state`
    refuses (a drive that accelerates or turns freely, a strand that would go slack:
    ``mean - amplitude <= 0``). A speed loop's drive torque ``T_drive_<node>`` is
    ``feedforward + gain (reference - speed)`` with the tables' last values. ``poles``: the
    drive's with every strand taut, where the caller has them.
    """
    from beltcalc.sim import frequency as fr
    from beltcalc.sim.elements import SpeedLoop

    if not net.linear:
        why = "; ".join(sorted({getattr(el, "nonlinear_reason", "loads locked to a shaft angle")
                                for el in net.elements if el.nonlinear_kind}))
        return None, f"the drive is nonlinear ({why})"
    if net.fixed:
        nodes = ", ".join(p.node for p in net.fixed.values())
        return None, (f"the motion of {nodes} is prescribed: its steady speed is what the move left it, not a "
                      "balance of torques")
    changes = input_changes(net)
    if window is not None and changes and max(changes) > window:
        return None, (f"an input changes at {max(changes):.4g} s, after the window starts ({window:.4g} s): the "
                      "steady state of the later inputs is not what the window shows")
    if poles is None:
        poles = fr.poles(net)
    lasting = [p for p in poles if p.kind != "rigid" and not _decaying(p)]
    if lasting:
        p = lasting[0]
        what = (f"a mode at {p.frequency:.4g} Hz is undamped (damping ratio {p.damping_ratio:.2g})"
                if p.kind == "oscillatory" and abs(p.damping_ratio) <= 1e-9 else
                f"a pole is unstable (s = {p.s.real:.4g}{p.s.imag:+.4g}j 1/s)")
        return None, f"{what}: its free motion never decays"
    loops = {f"T_drive_{s.node}": s for s in net.speed_loops}
    speeds = {y: f"v_{loops[y].node}" if net.node(loops[y].node).translation else f"omega_{loops[y].node}"
              for y in outputs if y in loops}
    asked = list(dict.fromkeys([y for y in outputs if y not in loops] + list(speeds.values())))
    try:
        ss = fr.steady_state(net, asked)
    except InputError as exc:          # its own words, less the advice a time run has taken
        return None, exc.message.removesuffix("; simulate it in time")
    for y, speed in speeds.items():
        loop: SpeedLoop = loops[y]
        ff = loop.feedforward[-1][1] if loop.feedforward else 0.0
        ss.mean[y] = ff + loop.gain * (loop.reference[-1][1] - ss.mean[speed])
        ss.components[y] = {w: -loop.gain * c for w, c in ss.components[speed].items()}
        ss.amplitude[y] = float(sum(abs(c) for c in ss.components[y].values()))
        ss.units[y] = "N" if net.node(loop.node).translation else "N m"
    return ss, None
