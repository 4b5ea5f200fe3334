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

What a run reports lives beside this module, and the scenes import it from here too:
:mod:`~beltcalc.sim.scenes.outcome` (:class:`Outcome`, the strand and steady-state
sections), :mod:`~beltcalc.sim.scenes.run_checks` (the strand, resonance, motor and stall
checks) and :mod:`~beltcalc.sim.scenes.steady` (the exact periodic steady state, and whether
the window has settled).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable, Iterable, Iterator, Mapping, Sequence

from beltcalc.errors import BeltcalcError, FloatRangeError, InputError, float_range, require_positive
from beltcalc.params import Param, Resolved, resolve
from beltcalc.sim.scenes.outcome import Outcome
# what a run reports, importable from here as the scenes (drive files, the roller table) import it
from beltcalc.sim.scenes.outcome import SteadyRow, steady_sections, strand_sections  # noqa: F401
from beltcalc.sim.scenes.run_checks import motor_checks, resonance_check, strand_check  # noqa: F401
from beltcalc.sim.scenes.steady import exact_steady_state, settling_check, strands_at_end  # noqa: F401

TIMING = [Param("t_end", "s", "simulated time"), Param("samples", "", "output samples"),
          Param("window", "s", "start of the steady window")]

Panel = tuple[str, tuple[tuple[str, str], ...]]   # (y label, ((signal, legend), ...)): one plot panel


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
    :func:`beltcalc.data.scenefile.load_scene` for ``simulate <name>``. ``batch``: the rows a
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
            from beltcalc.data.scenefile import load_scene

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

