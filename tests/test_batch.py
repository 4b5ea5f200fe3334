"""Batched exact propagation for studies (issue 17, item 3; beltcalc.sim.batch, and the batch
row a scene declares, read by beltcalc.sim.study.runs): the rows of a chunk computed as a stack
equal the scene's single runs, and every run the batch cannot vouch for goes through the single
run."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from beltcalc.sim import batch
from beltcalc.sim.core import SolverConfig, conditioning, simulate
from beltcalc.sim.propagate import augmented_matrix, propagate
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.scenes.base import BatchRow, run_scene
from beltcalc.sim.scenes.sewing import batched_rows, build
from beltcalc.sim.study import runs as study_runs
from beltcalc.sim.study.plan import Plan, parse_vary
from beltcalc.sim.study.runs import run_chunk, run_one

SEWING = SCENES["sewing"]
CFG = SolverConfig()
#: the batch repeats the single run's operations: its rows agree to rounding (bit for bit on this machine)
RTOL = 1e-9
#: varied inputs that move the load frequency (U12, M3_0: the steady speed), so each run has its own window
VARY = ["C4=normal(260N*m/rad,5%)", "M3_0=normal(0.1N*m,10%)", "J3=uniform(2.8e-4kg*m^2,3e-4kg*m^2)",
        "U12=normal(1.375,2%)"]


def plan(varies=VARY, runs=24, seed=1, chunk=24, **options):
    dists = [parse_vary(SEWING.params, v) for v in varies]
    return Plan(SEWING, SEWING.values(), CFG, tuple(n for n, _ in dists), dists=tuple(d for _, d in dists),
                runs=runs, seed=seed, chunk=chunk, options=options)


def single_rows(p, c=0):
    return [run_one(p, x)[0] for x in p.inputs(c)]


@pytest.mark.parametrize("options", [{}, {"steady_state_only": True}], ids=["time run", "steady state"])
def test_the_batch_gives_the_single_runs_rows(options):
    p = plan(**options)
    X = p.inputs(0)
    got = study_runs.batch_rows(p, X)
    ref = single_rows(p)
    assert all(g is not None for g in got)
    assert len({round(x[3], 12) for x in X}) == len(X)          # U12 differs run by run: so do the windows
    for g, r in zip(got, ref):
        assert r.error is None and not r.failed and not r.warnings
        assert_allclose(g, list(r.values.values()), rtol=RTOL, atol=0)


def test_a_chunk_reports_how_many_rows_came_from_the_batch_and_equals_the_single_runs():
    p = plan(runs=30, chunk=30)
    chunk = run_chunk(p, 0)
    assert chunk.batched == 29                                   # one check run per chunk goes alone
    ref = single_rows(p)
    assert [r.inputs for r in chunk.rows] == [r.inputs for r in ref]
    for got, want in zip(chunk.rows, ref):
        assert list(got.values) == list(want.values)
        assert_allclose(list(got.values.values()), list(want.values.values()), rtol=RTOL, atol=0)
    assert list(chunk.columns) == list(ref[0].values)
    off = run_chunk(Plan(**{**p.__dict__, "batch": False}), 0)
    assert off.batched == 0 and [r.values for r in off.rows] == [r.values for r in ref]


def test_the_error_estimate_is_the_single_runs():
    v = SEWING.values()
    nets = [build(dict(v, C4=c, U12=u)) for c, u in ((150.0, 1.3), (260.0, 1.375), (310.0, 1.45))]
    t = np.linspace(0.0, v["t_end"], int(v["samples"]))
    (_, _, _, err), = list(batch.exact_windows(nets, t, [5000] * 3, ["omega_3"]))
    want = [simulate(net, v["t_end"], int(v["samples"]), CFG).error_relative for net in nets]
    # the same differences and floor; the scale from the window and the reference's samples
    # before it (a lower bound of the single run's peaks over every sample): at least the
    # single run's estimate, and within a few parts in 1e4 of it here
    assert_allclose(np.maximum(err, want), err, rtol=1e-12, atol=0)
    assert_allclose(err, want, rtol=2e-3, atol=0)


def test_propagation_is_the_cores():
    v = SEWING.values()
    nets = [build(dict(v, C4=c)) for c in (120.0, 260.0)]
    F = np.stack([augmented_matrix(net) for net in nets])
    z0 = np.stack([np.concatenate([net.initial_state(), net.generators(0.0)]) for net in nets])
    for parts in (1, 3):
        prop = batch.Propagation(F, z0, 1e-4, 1001, parts)
        got = prop.rows(range(11), 3)                           # from block 3 on (b = 32)
        for j in range(2):
            want = propagate(F[j], z0[j], 1e-4, 1001, parts, np.arange(11))
            # the same scheme on a stack of matrices, which a BLAS kernel may sum in another
            # order: to twice the propagation's stated rounding floor, eps ||F~|| t_end of the
            # scale (core.conditioning: 1.4e-11 over these 0.1 s)
            floor = 2 * conditioning(nets[j], 0.1)
            assert_allclose(got[j], want[:, 3 * prop.b:], rtol=floor, atol=floor * np.abs(want).max())


def test_runs_the_batch_cannot_vouch_for_go_one_by_one():
    # a breakdown torque below the load (the motor checks fail), an impossible inertia: each the
    # single run's row, with its failing checks or its error
    p = plan(["rated_torque=uniform(0.01N*m,0.2N*m)", "J1=normal(1.1e-5kg*m^2,150%)"], runs=40, chunk=40, seed=4)
    X = p.inputs(0)
    got = study_runs.batch_rows(p, X)
    ref = single_rows(p)
    vouched = [g is not None for g in got]
    assert any(vouched) and not all(vouched)
    assert any(r.failed for r in ref) and any(r.error for r in ref)
    for g, r, x in zip(got, ref, X):
        if r.error is not None or r.failed or r.warnings:
            assert g is None
        if g is not None:
            assert_allclose(g, list(r.values.values()), rtol=RTOL, atol=0)
    chunk = run_chunk(p, 0)
    assert chunk.batched == sum(vouched) - 1
    for got_row, want in zip(chunk.rows, ref):
        assert (got_row.error, [c.key for c in got_row.failed], got_row.warnings) == \
            (want.error, [c.key for c in want.failed], want.warnings)


def test_an_eccentric_roller_is_nonlinear_and_not_batched():
    p = plan(["roller_eccentricity=uniform(0.1mm,0.6mm)", "C4=normal(260N*m/rad,5%)"], runs=4, chunk=4)
    assert study_runs.batch_rows(p, p.inputs(0)) == [None] * 4


def test_a_batch_that_disagrees_with_its_check_run_sends_the_chunk_one_by_one(monkeypatch):
    p = plan(runs=10, chunk=10)
    real = study_runs.batch_rows
    monkeypatch.setattr(study_runs, "batch_rows", lambda plan, X: [[v * (1 + 1e-6) for v in row] if row else row
                                                              for row in real(plan, X)])
    chunk = run_chunk(p, 0)
    assert chunk.batched == 0
    assert [r.values for r in chunk.rows] == [r.values for r in single_rows(p)]


def test_a_drive_file_and_other_solvers_go_one_by_one():
    from beltcalc.sim.scenes.drive import drive_scene

    scene = drive_scene("friswell_5_disks")       # a drive file: its rows take extremes off the exact solution
    name, dist = parse_vary(scene.params, "disk2.inertia=uniform(0.003kg*m^2,0.004kg*m^2)")
    p = Plan(scene, scene.values(samples=201.0), CFG, (name,), dists=(dist,), runs=3, chunk=3)
    assert study_runs.batch_rows(p, p.inputs(0)) == [None] * 3
    chunk = run_chunk(p, 0)
    assert chunk.batched == 0 and all(r.error is None for r in chunk.rows)
    radau = plan(runs=3, chunk=3)
    radau = Plan(**{**radau.__dict__, "cfg": SolverConfig("radau")})
    assert study_runs.batch_rows(radau, radau.inputs(0)) == [None] * 3


def test_a_replaced_scene_run_is_never_batched():
    from dataclasses import replace

    p = plan(runs=3, chunk=3)
    other = Plan(**{**p.__dict__, "scene": replace(SEWING, run=lambda values, cfg, **kw: run_scene(
        SEWING, values, cfg, **kw))})
    assert study_runs.batch_rows(other, other.inputs(0)) == [None] * 3


def test_the_study_reads_the_batch_row_the_scene_declares():
    # batch.py knows no scene: a chunk's rows come from the scene's own BatchRow, which gets
    # each run's SI values (the scene's, the varied inputs set), the solver config, the options
    from dataclasses import replace

    seen = []

    def rows(chunk, cfg, **options):
        seen.append((list(chunk), cfg, options))
        return batched_rows(chunk, cfg, **options)

    p = plan(runs=6, chunk=6, steady_state_only=True)
    mine = Plan(**{**p.__dict__, "scene": replace(SEWING, batch=BatchRow(SEWING.run, rows))})
    chunk = run_chunk(mine, 0)
    assert chunk.batched == 5 and len(seen) == 1
    runs, cfg, options = seen[0]
    assert (cfg, options) == (CFG, {"steady_state_only": True})
    assert [[v[n] for n in p.names] for v in runs] == p.inputs(0).tolist()
    assert all({k: v[k] for k in p.values if k not in p.names} == {k: p.values[k] for k in p.values
                                                                  if k not in p.names} for v in runs)
    assert [r.values for r in chunk.rows] == [r.values for r in run_chunk(p, 0).rows]
    none = Plan(**{**p.__dict__, "scene": replace(SEWING, batch=None)})
    assert run_chunk(none, 0).batched == 0


def test_window_statistics_are_the_results_summary():
    v = SEWING.values()
    net = build(v)
    result = simulate(net, v["t_end"], int(v["samples"]), CFG)
    start = 0.5
    k = int(np.searchsorted(result.t, start - 1e-12))
    names = ["omega_3", "accel_5", "T_45", "M_motor"]
    mean, amp, lo, hi = batch.window_stats(result.t[k:], np.stack([result[s][k:] for s in names]))
    for i, s in enumerate(names):
        want = result.summary(s, start)
        # extremes exactly; the mean to rounding of the sum (one pass against numpy.trapezoid's
        # pairs): 1e-14 of the signal's magnitude (an acceleration of amplitude 426 around -2.9)
        size = float(np.abs(result[s][k:]).max())
        assert (amp[i], lo[i], hi[i]) == (want.amplitude, want.min, want.max)
        assert mean[i] == pytest.approx(want.mean, rel=0, abs=1e-14 * size)
