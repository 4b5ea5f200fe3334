"""Studies (issue 17, items 2 and 4): grids and tolerance studies of a scene, in-process or on
Dask; each run one summary row, memory constant in the number of runs (beltcalc.sim.study)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from beltcalc.errors import UsageError
from beltcalc.sim.core import SolverConfig
from beltcalc.sim.scenes import SCENES
from beltcalc.sim.scenes.base import run_scene
from beltcalc.sim.study.execution import execute
from beltcalc.sim.study.plan import Distribution, Plan, parse_vary
from beltcalc.sim.study.runs import RunRow, run_chunk
from beltcalc.sim.study.sweeps import grid_scene
from beltcalc.sim.study.fold import Fold, FoldSpec, fold_rows, wilson
from beltcalc.sim.study.tolerance import parse_limit, tolerance_study

SEWING = SCENES["sewing"]
CFG = SolverConfig()
STEADY = {"steady_state_only": True}


def plan(varies, runs, seed=1, **kw):
    dists = [parse_vary(SEWING.params, v) for v in varies]
    return Plan(SEWING, SEWING.values(), CFG, tuple(n for n, _ in dists), dists=tuple(d for _, d in dists),
                runs=runs, seed=seed, options=dict(STEADY), **kw)


def columns_of(values=None):
    out = run_scene(SEWING, values or SEWING.values(), CFG, **STEADY)
    return {c.key: c for c in out.column_rows()}


def rows_of(p, workers=1, **kw):
    rows = []
    execute(p, lambda chunk: rows.extend(chunk.rows), workers=workers, **kw)
    return rows


# --- distributions and their texts ---------------------------------------------------------------

def test_distributions_read_values_as_set_does():
    name, d = parse_vary(SEWING.params, "C4=normal(260N*m/rad,5%)")
    assert name == "C4" and d.args == pytest.approx((260.0, 13.0)) and d.unit == "N*m/rad"
    _, d = parse_vary(SEWING.params, "C4=normal(0.26kN*m/rad, 10 N*m/rad)")
    assert d.args == pytest.approx((260.0, 10.0))
    _, d = parse_vary(SEWING.params, "U12=triangular(1.3,1.375,1.4)")        # a plain number: no unit
    assert d.args == (1.3, 1.375, 1.4) and d.unit == "1"
    for text, fragment in (("C4=normal(260,5%)", "needs units"), ("C4=gauss(1,2)", "normal(MEAN"),
                           ("C4=uniform(3N*m/rad,2N*m/rad)", "LOW must be <= HIGH"),
                           ("C4=triangular(1N*m/rad,3N*m/rad,2N*m/rad)", "LOW <= MODE <= HIGH"),
                           ("C4=normal(260N*m/rad,-1N*m/rad)", ">= 0"), ("C4=uniform(1N*m/rad)", "takes 2"),
                           ("C9=normal(1N*m/rad,1%)", "C9"), ("C4=normal(260N,5%)", "C4")):
        with pytest.raises(UsageError) as info:
            parse_vary(SEWING.params, text)
        assert info.value.param in ("vary", "set") and fragment in info.value.message, info.value.message


def test_samples_have_the_stated_moments():
    # uniform(2, 4): mean 3, sd 2/sqrt(12); triangular(0, 1, 4): mean 5/3, sd sqrt(13/18)
    rng = np.random.default_rng(0)
    for d, mean, sd in ((Distribution("uniform", (2.0, 4.0)), 3.0, 2 / math.sqrt(12)),
                        (Distribution("triangular", (0.0, 1.0, 4.0)), 5 / 3, math.sqrt(13 / 18)),
                        (Distribution("normal", (5.0, 0.5)), 5.0, 0.5)):
        x = d.sample(rng, 200_000)
        assert d.mean == pytest.approx(mean) and d.sd == pytest.approx(sd)
        assert x.mean() == pytest.approx(mean, rel=5e-3) and x.std() == pytest.approx(sd, rel=5e-3)
    t = Distribution("triangular", (0.0, 1.0, 4.0)).sample(rng, 100_000)
    assert t.min() >= 0.0 and t.max() <= 4.0 and np.mean(t < 1.0) == pytest.approx(0.25, abs=5e-3)


def test_wilson_interval():
    # Wilson (1927); Newcombe, Stat. Med. 17 (1998) 857, table I: 81/263 -> 0.2553..0.3662
    lo, hi = wilson(81, 263)
    assert (lo, hi) == pytest.approx((0.2553, 0.3662), abs=1e-4)
    assert wilson(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert wilson(0, 0) == (None, None)


def test_limits_name_a_column_and_need_its_unit():
    cols = columns_of()
    lim = parse_limit("steady_main_speed_mean_rad_per_s>=2000rpm", cols)
    assert lim.bound == pytest.approx(2000 * 2 * math.pi / 60) and lim.op == ">="
    assert list(lim.fails(np.array([200.0, 210.0, 220.0]))) == [True, False, False]
    for text, fragment in (("steady_main_speed_mean_rad_per_s>=200", "needs a unit"),
                           ("steady_main_speed_mean>=200rad/s", "did you mean steady_main_speed_mean_rad_per_s,"),
                           ("steady_main_speed_mean_rad_per_s=200rad/s", "KEY>=VALUE"),
                           ("steady_main_speed_mean_rad_per_s>=2N", "")):
        with pytest.raises(UsageError) as info:
            parse_limit(text, cols)
        assert info.value.param == "limit" and fragment in info.value.message


# --- the statistics, against numpy on every row -------------------------------------------------

def fold_in_chunks(spec, rows, priority, cuts):
    """The summary of ``rows`` folded in chunks that end at ``cuts``."""
    fold = Fold(spec)
    lo = 0
    for hi in [*cuts, len(rows)]:
        fold.add(fold_rows(spec, lo, rows[lo:hi], priority[lo:hi]))
        lo = hi
    return fold.summary()


def test_the_fold_is_exact_against_every_row_and_the_same_for_any_chunks():
    # y1 = 2 x1 - x2 + noise, y2 missing in some runs; chunks of uneven size; the reservoir holds
    # every row (runs < its size), so the percentiles are numpy's over all rows
    rng = np.random.default_rng(3)
    X = rng.normal(size=(1000, 2)) * [1.0, 3.0] + [5.0, -2.0]
    y1 = 2 * X[:, 0] - X[:, 1] + 0.1 * rng.normal(size=1000)
    y2 = X[:, 0] ** 3
    y2[::7] = np.nan
    rows = [RunRow(tuple(X[i]), {"y1": y1[i], "y2": None if np.isnan(y2[i]) else y2[i]}) for i in range(1000)]
    priority = rng.integers(0, 2 ** 63, 1000).astype(np.uint64)
    spec = FoldSpec(("x1", "x2"), ("y1", "y2"), reservoir=5000)
    s = fold_in_chunks(spec, rows, priority, (1, 250, 600))
    e = s.outputs["y1"]
    assert e["mean"] == pytest.approx(y1.mean(), rel=1e-12) and e["sd"] == pytest.approx(y1.std(ddof=1), rel=1e-10)
    assert (e["min"], e["max"]) == (y1.min(), y1.max())
    assert [e[f"p{p}"] for p in (1, 5, 50, 95, 99)] == pytest.approx(np.percentile(y1, [1, 5, 50, 95, 99]))
    # standardised regression coefficients: b_i sd(x_i) / sd(y) of the least-squares fit
    A = np.column_stack([np.ones(1000), X])
    b = np.linalg.lstsq(A, y1, rcond=None)[0][1:]
    src = {i["input"]: i["src"] for i in e["influence"]}
    assert src["x1"] == pytest.approx(b[0] * X[:, 0].std(ddof=1) / y1.std(ddof=1), rel=1e-9)
    assert src["x2"] == pytest.approx(b[1] * X[:, 1].std(ddof=1) / y1.std(ddof=1), rel=1e-9)
    assert e["influence"][0]["input"] == "x2"          # |-3 / 3.6| > |2 / 3.6|
    from scipy.stats import spearmanr

    ok = ~np.isnan(y2)
    assert s.outputs["y2"]["n"] == ok.sum()
    assert s.outputs["y2"]["mean"] == pytest.approx(y2[ok].mean(), rel=1e-12)
    rho = {i["input"]: i["spearman"] for i in s.outputs["y2"]["influence"]}
    assert rho["x1"] == pytest.approx(spearmanr(X[ok, 0], y2[ok])[0], rel=1e-12)
    # the tree of the moments is fixed by the runs: any chunks (one, ones of one run, odd
    # sizes, a power of two) give the same numbers, bit for bit
    for cuts in ((), tuple(range(1, 1000)), (3, 10, 511, 512, 777), (256, 512, 768)):
        assert fold_in_chunks(spec, rows, priority, cuts).outputs == s.outputs, cuts


def test_spearman_ranks_are_scipys_average_ranks_exactly():
    # the fold ranks without importing scipy.stats (a quarter of a second of every study's
    # command): the same floats as rankdata's default, ties included
    from scipy.stats import rankdata

    from beltcalc.sim.study.fold import ranks

    rng = np.random.default_rng(3)
    for n in (1, 2, 3, 50, 4000):
        for x in (rng.normal(size=n), rng.integers(0, 4, n).astype(float), np.round(rng.normal(size=n), 1)):
            assert np.array_equal(ranks(x), rankdata(x)), n


def test_the_reservoir_is_the_rows_of_the_smallest_priorities_whatever_the_chunks():
    # bottom-k sampling: the kept rows are those of the 500 smallest priorities (numpy's sort of
    # every priority is the reference), ordered by run, for any chunking
    rng = np.random.default_rng(4)
    rows = [RunRow((float(i),), {"y": float(i)}) for i in range(10_000)]
    priority = rng.integers(0, 2 ** 64 - 1, 10_000, dtype=np.uint64)
    spec = FoldSpec(("x",), ("y",), reservoir=500)
    s = fold_in_chunks(spec, rows, priority, range(250, 10_000, 250))
    assert s.kept == 500 and s.runs == 10_000 and s.sample.shape == (500, 2)
    want = np.sort(np.argsort(priority, kind="stable")[:500]).astype(float)
    assert_equal = np.testing.assert_array_equal
    assert_equal(s.sample[:, 0], want)
    assert_equal(fold_in_chunks(spec, rows, priority, (1, 2, 3, 4999, 5000, 9998)).sample, s.sample)
    assert s.sample[:, 0].mean() == pytest.approx(5000, rel=0.06)          # spread over the whole run order
    assert s.outputs["y"]["mean"] == pytest.approx(4999.5) and s.outputs["y"]["max"] == 9999.0   # exact, not sampled


def test_counts_keep_the_first_texts_in_run_order_whatever_the_chunks():
    from beltcalc.sim.study import fold as fold_module

    rows = [RunRow((float(i),), {"y": float(i)}, warnings=(f"w{i % 70}", "always")) if i % 3 else
            RunRow((float(i),), {}, error=f"J1: {-i} kg*m^2 must be > 0") for i in range(300)]
    spec = FoldSpec(("x",), ("y",))
    one = fold_in_chunks(spec, rows, np.arange(300, dtype=np.uint64), ())
    many = fold_in_chunks(spec, rows, np.arange(300, dtype=np.uint64), (1, 2, 50, 51, 200))
    assert one.warnings == many.warnings and one.more_warnings == many.more_warnings
    assert len(one.warnings) == fold_module.MAX_DISTINCT and one.warnings["always"] == 200
    first = list(dict.fromkeys(w for r in rows if r.error is None for w in r.warnings))[:fold_module.MAX_DISTINCT]
    assert list(one.warnings) == first
    assert one.more_warnings == 400 - sum(one.warnings.values())
    assert one.reasons == many.reasons == [("J1: 0 kg*m^2 must be > 0", [100, 0])]


# --- the tests -----------------------------------------------------------------------------

@pytest.mark.parametrize("options", [STEADY, {}], ids=["steady state", "time run"])
def test_a_study_without_spread_reproduces_the_single_run_exactly(options):
    # "exactly": to rounding. The batched path repeats the single run's operations, but on a
    # stack of matrices, which another BLAS kernel sums in another order (2.3e-11 of an
    # acceleration amplitude under OpenBLAS Haswell; bit for bit under others): every column
    # to 1e-9, the method's error (the single run's estimate is 1.6e-10 of its scale, and a
    # small column such as a torque mean sits several times below its signal's swing).
    # 7 runs: one check run, 6 batched
    p = plan(["C4=normal(260N*m/rad,0%)", "M3_0=uniform(0.12N*m,0.12N*m)", "J3=triangular(3e-4kg*m^2,3e-4kg*m^2,"
              "3e-4kg*m^2)"], runs=7)
    p = Plan(**{**p.__dict__, "options": dict(options)})
    single = run_scene(SEWING, dict(SEWING.values(), C4=260.0, M3_0=0.12, J3=3e-4), CFG, **options)
    want = {c.key: c.value for c in single.column_rows()}
    chunks = []
    execute(p, chunks.append, workers=1)
    rows = [r for ch in chunks for r in ch.rows]
    assert len(rows) == 7 and sum(ch.batched for ch in chunks) == 6
    for r in rows:
        assert r.inputs == (260.0, 0.12, 3e-4) and r.error is None and not r.failed and not r.warnings
        assert list(r.values) == list(want)
        assert r.values == pytest.approx(want, rel=1e-9, abs=0)


def test_a_linear_output_matches_the_analytic_propagation_at_1e4_runs():
    # The exact steady speed of the main shaft is linear in the mean loads (sewing.steady_speed):
    # omega3 = w0 (1 - S_c (M3_0 + M5_0) / U12 / (2 M_c)) / U12, so with independent inputs
    # mean = omega3(E M3_0, E M5_0), sd = w0 S_c / (2 M_c U12^2) sqrt(sd3^2 + sd5^2).
    from beltcalc.sim.scenes.sewing import steady_speed

    v = SEWING.values()
    d3, d5 = Distribution("normal", (0.1, 0.01), "N*m"), Distribution("uniform", (0.006, 0.018), "N*m")
    p = Plan(SEWING, v, CFG, ("M3_0", "M5_0"), dists=(d3, d5), runs=10_000, seed=1, options=STEADY)
    cols = columns_of()
    summary, how = tolerance_study(p, cols, workers=1)
    assert how.how == "in-process" and summary.runs == 10_000 and summary.errors == 0
    w0 = 2 * math.pi * v["supply_frequency"] / v["pole_pairs"]
    slope = w0 * v["breakdown_slip"] / (2 * v["breakdown_factor"] * v["rated_torque"] * v["U12"] ** 2)
    e = summary.outputs["steady_main_speed_mean_rad_per_s"]
    assert e["mean"] == pytest.approx(steady_speed(dict(v, M3_0=0.1, M5_0=0.012)), rel=1e-4)
    assert e["sd"] == pytest.approx(slope * math.hypot(d3.sd, d5.sd), rel=0.01)
    assert e["p50"] == pytest.approx(e["mean"], rel=1e-4)
    src = {i["input"]: i["src"] for i in e["influence"]}          # linear: the SRCs are the exact shares
    assert src["M3_0"] == pytest.approx(-d3.sd / math.hypot(d3.sd, d5.sd), rel=0.01)
    assert src["M5_0"] == pytest.approx(-d5.sd / math.hypot(d3.sd, d5.sd), rel=0.02)
    assert e["r2"] == pytest.approx(1.0, abs=1e-9)


def test_impossible_draws_are_rows_with_their_reason_and_the_study_finishes():
    # J1 = 1.1e-5 +- 200 %: about 31 % of the draws are negative inertias
    p = plan(["J1=normal(1.1e-5kg*m^2,200%)", "C4=uniform(200N*m/rad,300N*m/rad)"], runs=600, seed=2)
    rows = rows_of(p)
    assert len(rows) == 600
    bad = [r for r in rows if r.error is not None]
    assert [r.inputs[0] <= 0 for r in rows] == [r.error is not None for r in rows]
    assert 0.25 < len(bad) / 600 < 0.38
    assert all(r.error.startswith("J1: ") and "must be > 0" in r.error and r.values == {} for r in bad)
    summary, _ = tolerance_study(p, columns_of(), workers=1)
    assert summary.errors == len(bad) and summary.reasons[0][1][0] <= len(bad)
    assert summary.outputs["steady_main_speed_mean_rad_per_s"]["n"] == 600 - len(bad)


def test_each_run_draws_from_its_own_place_in_the_stream_whatever_the_chunks():
    # run i reads Philox words 4 w i .. (w = 1 counter step for 2 inputs and a priority): the
    # reference reads the whole stream from its start, with no advance, and inverts the
    # distributions by hand (the normal's quantile from the error function's, in mpmath)
    import mpmath

    p = plan(["C4=normal(260N*m/rad,5%)", "M3_0=uniform(0.09N*m,0.11N*m)"], runs=30, seed=5, chunk=8)
    one = rows_of(p)
    words = np.random.Philox(np.random.SeedSequence(5)).random_raw(30 * 4).reshape(30, 4)
    u = ((words[:, :2] >> np.uint64(11)).astype(float) + 0.5) / 2.0 ** 53
    c4 = [260.0 + 13.0 * float(mpmath.sqrt(2) * mpmath.erfinv(2 * mpmath.mpf(x) - 1)) for x in u[:, 0]]
    assert [r.inputs[0] for r in one] == pytest.approx(c4, rel=1e-14)
    assert [r.inputs[1] for r in one] == pytest.approx(0.09 + 0.02 * u[:, 1], rel=1e-15)
    assert np.array_equal(p.draws(0, 30)[1], words[:, 2])                   # the reservoir's priorities
    # any chunks, in any order: the same rows
    for chunk in (1, 7, 30):
        q = Plan(**{**p.__dict__, "chunk": chunk})
        backwards = [r for c in reversed(range(q.n_chunks)) for r in run_chunk(q, c).rows[::-1]][::-1]
        assert [r.inputs for r in backwards] == [r.inputs for r in one]
    assert [r.inputs for r in rows_of(plan(["C4=normal(260N*m/rad,5%)", "M3_0=uniform(0.09N*m,0.11N*m)"],
                                           runs=30, seed=6, chunk=8))] != [r.inputs for r in one]


def test_batched_rows_are_the_same_whatever_the_chunks():
    # a batched row equals the single run's to rounding, and which rounding depends on the runs
    # batched with it: they go in groups of 250 aligned on the run index, so chunks of 250, 500
    # or 750 runs (as 4, 2 or 1 workers cut them) give the same rows, bit for bit (the time run)
    p = plan(["C4=normal(260N*m/rad,5%)", "U12=normal(1.375,2%)"], runs=750, seed=2)
    p = Plan(**{**p.__dict__, "options": {}})
    rows = {size: rows_of(Plan(**{**p.__dict__, "chunk": size})) for size in (250, 750)}
    assert [(r.inputs, r.values) for r in rows[250]] == [(r.inputs, r.values) for r in rows[750]]
    uneven = rows_of(Plan(**{**p.__dict__, "chunk": 500, "starts": (0, 500)}))     # as chunk_starts cuts them
    assert [(r.inputs, r.values) for r in uneven] == [(r.inputs, r.values) for r in rows[750]]
    assert sum(1 for r in rows[750] if r.values) == 750


def test_a_chunk_whose_task_failed_is_its_rows_with_the_reason_in_the_fold():
    # a task that fails after its retries (a worker lost) comes back as its runs' rows with the
    # reason, folded here like any other chunk: the study goes on, and the report counts them
    from dataclasses import replace

    from beltcalc.sim.study.runs import failed_chunk

    p = plan(["C4=normal(260N*m/rad,5%)"], runs=30, seed=3, chunk=10)
    spec = FoldSpec(("C4",), ("steady_main_speed_mean_rad_per_s",), send=frozenset({"csv"}))
    q = replace(p, fold=spec)
    fold = Fold(spec)
    chunks = [run_chunk(q, 0), failed_chunk(q, 1, "KilledWorker: worker lost"), run_chunk(q, 2)]
    for chunk in chunks:
        fold.add(chunk.part)
    s = fold.summary()
    assert s.runs == 30 and s.errors == 10 and s.outputs["steady_main_speed_mean_rad_per_s"]["n"] == 20
    assert s.reasons == [("task failed: KilledWorker: worker lost", [10, 10])]
    lines = chunks[1].csv.splitlines()
    assert len(lines) == 10 and all(line.endswith(",task failed: KilledWorker: worker lost") for line in lines)
    assert [float(line.split(",")[0]) for line in lines] == [x[0] for x in p.draws(10, 20)[0]]


def test_chunks_are_sized_so_that_every_worker_gets_several():
    from beltcalc.sim.study.plan import chunk_size

    for runs, workers, cost in ((1600, 16, 0.109), (4000, 16, 0.109), (50_000, 16, 0.003), (50_000, 2, 0.003),
                                (201, 16, 0.003), (4000, 2, 0.109)):
        size = chunk_size(runs, workers, cost)
        chunks = -(-runs // size)
        assert chunks >= workers, (runs, workers)                   # every worker gets one
        # four per worker, unless that makes chunks of under a second (then at least a second's,
        # but never so few chunks that a worker gets none) or of over 1,000 runs
        assert size <= 1000 and (chunks >= 4 * workers or size * cost >= 1.0 or size == 1000
                                 or size == -(-runs // workers)), (runs, workers)


@pytest.mark.parametrize("runs, workers, cost, unit", [(1600, 16, 0.109, 1), (4000, 16, 0.109, 1),
                                                      (50_000, 16, 0.003, 250), (50_000, 2, 0.003, 250),
                                                      (400, 2, 0.15, 1), (201, 16, 0.003, 1), (7, 2, None, 1)])
def test_the_last_chunks_are_short_so_that_no_worker_waits_long_for_the_others(runs, workers, cost, unit):
    # chunk_starts [HSF92]: the chunks cover every run once, each start a multiple of the batch's
    # group, sizes never growing, none under the tail's floor but the last. Then a simulation of
    # the workers taking the next chunk as they free up (list scheduling), each run's cost
    # lognormal with a 10 % spread and each worker's first chunk 0.2-0.4 s slower (as measured),
    # over 20 draws: the last worker finishes within the floor's work and the warm-ups' spread
    # of the ideal share, and on average never later than with chunks all of one size; on 16
    # workers those leave at least twice the wait (a whole chunk when 4 per worker do not
    # divide evenly: 50,000 runs in 67 chunks of 750)
    import heapq

    from beltcalc.sim.study.plan import DISPATCH_S, TAIL_MIN_S, chunk_size, chunk_starts

    size = chunk_size(runs, workers, cost, unit)
    starts = chunk_starts(runs, workers, size, cost, unit)
    sizes = np.diff([*starts, runs])
    assert starts[0] == 0 and np.all(sizes > 0) and np.all(np.asarray(starts) % unit == 0)
    assert np.all(np.diff(sizes[:-1]) <= 0) and sizes.max() <= size
    if cost is None:
        return
    floor = min(size, max(unit, math.ceil(max(TAIL_MIN_S, 2 * workers * DISPATCH_S) / cost / unit) * unit))
    assert sizes[:-1].min() >= floor

    def wait(sizes, costs, warm):                 # the last worker's finish after the ideal share
        free, lo = [(warm[w], w) for w in range(workers)], 0
        for n in sizes:
            t, w = heapq.heappop(free)
            heapq.heappush(free, (t + costs[lo:lo + n].sum(), w))
            lo += n
        return max(t for t, _ in free) - (costs.sum() + warm.sum()) / workers

    uniform = [size] * (runs // size) + [runs % size] * (runs % size > 0)
    ours, theirs = [], []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        costs, warm = cost * rng.lognormal(0.0, 0.1, runs), rng.uniform(0.2, 0.4, workers)
        ours.append(wait(sizes, costs, warm))
        theirs.append(wait(uniform, costs, warm))
    assert max(ours) <= floor * cost + 0.2
    assert np.mean(ours) <= np.mean(theirs) + 1e-9
    if workers == 16 and runs > 1000:
        assert np.mean(ours) <= 0.5 * np.mean(theirs)


def test_a_grid_is_the_product_of_its_sweeps_and_each_point_its_single_run():
    v = SEWING.values()
    sweep = grid_scene(SEWING, v, [("C4", [100.0, 200.0, 300.0]), ("M3_0", [0.1, 0.12])], CFG, **STEADY)
    assert sweep.points == [(c, m) for c in (100.0, 200.0, 300.0) for m in (0.1, 0.12)]
    assert sweep.header()[:3] == ["C4_N_m_per_rad", "M3_0_N_m", "steady_main_speed_mean_rad_per_s"]
    single = run_scene(SEWING, dict(v, C4=300.0, M3_0=0.1), CFG, **STEADY)
    assert sweep.rows()[4][2:] == [c.value for c in single.column_rows()]
    out = sweep.to_dict("sewing")
    assert [p["name"] for p in out["parameters"]] == ["C4", "M3_0"]
    assert out["parameters"][1] == {"name": "M3_0", "unit": "N*m", "values": [0.1, 0.12]}


def memory_peak(runs: int) -> float:
    """Peak traced bytes of a sewing steady-state study of ``runs`` runs."""
    import tracemalloc

    p = plan(["C4=normal(260N*m/rad,5%)", "M3_0=normal(0.1N*m,10%)", "J3=uniform(2.8e-4kg*m^2,3e-4kg*m^2)"],
             runs=runs, chunk=250)
    cols = columns_of()
    tracemalloc.start()
    tolerance_study(p, cols, workers=1, reservoir=100)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


#: Bound on the memory a tolerance study allocates (tracemalloc peak) whatever its number of runs:
#: the reservoir, one chunk of rows, the moments' open nodes (chunks of 250 runs at both sizes: a
#: chunk's rows, at most 1,000 of them, are what the chunk size bounds). The reservoir fills as
#: runs come, up to its size (10,000 rows x 19 values = 1.5 MB by default): here 100 rows, full at
#: both sizes, so that what is left to grow is what must not.
MEMORY_BOUND = 8 * 2 ** 20


def test_memory_is_flat_in_the_number_of_runs():
    # tracemalloc multiplies the cost of a run about tenfold: 250 and 1,000 runs here; 3 x 10^4 below
    memory_peak(50)                 # what the first study imports and caches is no study's memory
    small = memory_peak(250)
    large = memory_peak(1000)
    assert large < MEMORY_BOUND and large < small + 2 ** 20


def max_rss(runs: int) -> int:
    """Peak resident memory [bytes] of the command running a sewing steady-state study of
    ``runs`` runs in one process, rows streamed to a CSV file."""
    import os
    import subprocess
    import sys
    import tempfile

    code = ("import resource, sys; from beltcalc.cli.main import main; sys.argv = ['beltcalc'] + sys.argv[1:]\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)")
    with tempfile.TemporaryDirectory() as tmp:
        done = subprocess.run([sys.executable, "-c", code, "simulate", "sewing", "--steady-state-only",
                               "--vary", "C4=normal(260N*m/rad,5%)", "--vary", "M3_0=normal(0.1N*m,10%)",
                               "--runs", str(runs), "--workers", "1", "--json", "--csv", os.path.join(tmp, "r.csv")],
                              capture_output=True, text=True, check=True)
    return int(done.stderr.splitlines()[-1]) * 1024


#: Bound on the growth of the resident memory from 10^3 to 3 x 10^4 runs (the process itself, with
#: numpy, scipy, pint and the scene, is about 120 MB either way).
RSS_GROWTH_BOUND = 16 * 2 ** 20


@pytest.mark.slow
def test_memory_stays_below_its_bound_at_3e4_runs():
    # 3 x 10^4 runs of the sewing steady state (batched: about 0.5 ms of CPU a run, most of it
    # building each run's network): the process's peak memory at 3 x 10^4 runs against 10^3
    # (tracemalloc in-process would take ten times as long). A row kept per run (a RunRow with its
    # inputs and 16 values: over 1 kB) would grow it by more than 29 MB, twice the bound.
    small, large = max_rss(1000), max_rss(30_000)
    assert large - small < RSS_GROWTH_BOUND, (small, large)


# --- Dask ----------------------------------------------------------------------------------------

def test_a_local_dask_cluster_gives_the_rows_and_the_summary_of_the_in_process_run():
    # one cluster for two studies (its start counted for the first only); on it 8 chunks of 30
    # runs, in this process one chunk holds them all: the rows, the CSV lines the chunks format
    # and every statistic are the same, bit for bit (beltcalc.sim.study.fold). One by one here
    # (the batch's rows: test_batched_rows_are_the_same_whatever_the_chunks)
    pytest.importorskip("distributed")
    from beltcalc.sim.study.execution import study_cluster, study_modules, warm_worker

    p = plan(["C4=normal(260N*m/rad,5%)", "J1=normal(1.1e-5kg*m^2,150%)"], runs=240, seed=9, batch=False)
    local = rows_of(p, workers=1)
    there_plan = Plan(**{**p.__dict__, "chunk": 30})
    cols = columns_of()
    amplitude = cols["steady_main_speed_amplitude_rad_per_s"].value          # the nominal run's: about half fail
    limits = [parse_limit(f"steady_main_speed_amplitude_rad_per_s<={amplitude!r}rad/s", cols)]
    csv_here, csv_there = [], []
    here, how_here = tolerance_study(p, cols, limits, lambda ch: csv_here.append(ch.csv), workers=1, send=("csv",))
    rows = []
    names = study_modules()               # what the workers import as the cluster starts: the runs' code
    assert "beltcalc.sim.core" in names and not any(n.startswith("beltcalc.cli") for n in names)
    with study_cluster(2) as cluster:
        assert list(cluster.client.run(warm_worker, ["json", "beltcalc.no_such_module"]).values()) == [1, 1]
        how = execute(there_plan, lambda chunk: rows.extend(chunk.rows), cluster=cluster)
        there, how_there = tolerance_study(there_plan, cols, limits, lambda ch: csv_there.append(ch.csv), send=("csv",),
                                           cluster=cluster)
    assert how.how == how_there.how == "dask local cluster, 2 workers" and how.start > 0 and how_there.start == 0
    assert how_here.chunks == 1 and how_there.chunks >= 8 and how_there.chunk_cpu > 0
    assert len(rows) == 240 and any(r.error for r in rows)
    assert [(r.inputs, r.values, r.error) for r in rows] == [(r.inputs, r.values, r.error) for r in local]
    assert "".join(csv_there) == "".join(csv_here) and len("".join(csv_here).splitlines()) == 240
    assert there.outputs == here.outputs and there.runs == here.runs == 240
    assert [(lim["evaluated"], lim["failed"]) for lim in there.limits] == \
        [(lim["evaluated"], lim["failed"]) for lim in here.limits]
    assert 0 < here.limits[0]["failed"] < here.limits[0]["evaluated"] < 240
    assert there.reasons == here.reasons and there.errors == here.errors > 0
    assert np.array_equal(there.sample, here.sample, equal_nan=True)


def test_without_dask_a_large_study_runs_in_process_with_a_note(monkeypatch):
    import beltcalc.sim.study.execution as execution

    monkeypatch.setattr(execution, "dask_available", lambda: False)
    p = plan(["C4=normal(260N*m/rad,5%)"], runs=201)
    notes = []
    assert execute(p, lambda chunk: None, workers=2, notes=notes).how == "in-process"
    assert "dask is not installed" in notes[0] and 'pip install "beltcalc[dist]"' in notes[0]
    with pytest.raises(UsageError):
        execute(p, lambda chunk: None, scheduler="tcp://127.0.0.1:1")
