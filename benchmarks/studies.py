"""Studies at scale (issue 17, item 7): the per-run cost of a sewing tolerance study against the
solver-only time of one exact run, its memory at 10^3..10^5 runs, 1 against 2 local Dask
workers, and the extrapolated time of 10^6 runs.

Run: python benchmarks/studies.py [--quick]

* **Per-run cost** (paired): chunks of the study ``simulate sewing --vary C4=normal(260 N*m/rad,
  5%) --vary M3_0=normal(0.1 N*m,10%) --vary J3=uniform(2.8e-4,3e-4 kg*m^2) --vary
  U12=normal(1.375,2%)`` (:func:`beltcalc.sim.study.runs.run_chunk`: every run's summary row, the
  exact method with its error estimate, 10,001 samples over 1 s), on the batched path
  (:mod:`beltcalc.sim.batch`) and one by one (``Plan.batch`` False), each round followed by 15
  solver-only runs of the nominal drive (``SimResult.wall_time`` of ``simulate(net, 1.0, 10001,
  SolverConfig('exact'))``, their median). The ratio of each round is taken against the
  solver-only median of the same round (the machine is shared: its load moves both alike);
  the table gives the medians over the rounds, wall (``perf_counter``) and CPU (``process_time``).
* **Memory**: the peak resident memory (``ru_maxrss``) of the ``beltcalc`` command running the
  study in one process, rows streamed to a CSV file, at 10^3, 10^4 and 10^5 runs; the time run
  at 10^3 and 10^4, the exact steady state (``--steady-state-only``, a cheaper run with the
  same streaming) at all three. Growth against 10^3.
* **Scaling** (issue 34): the two studies of the issue, each the ``beltcalc`` command a user
  types, with ``--json`` (its ``execution_profile``), in this process and on a local Dask
  cluster of every worker count asked (``--workers 1,2``: this machine's; ``1`` is this
  process), each the best of ``--repeats`` runs taken in turn (and every repeat's ratios to the
  in-process run just before it):

  - sewing, the batched path: ``simulate sewing --vary 'C4=normal(260N*m/rad,5%)' --vary
    'U12=normal(1.375,2%)' --runs 50000 --seed 1``;
  - the conveyor drive file, one run at a time: ``simulate drive conveyor --vary
    'upper.pretension=normal(400N,5%)' --runs 400 --seed 1``.

  With ``--conveyor-per-worker``, ``--conveyor-runs`` is the conveyor's runs a worker (W times
  that on W workers) and its speed-ups are per run: issue 34's 4,000 runs on 16 workers against
  one worker's 250 (``benchmarks/scaling_device.py`` runs that on a 16-core machine).

  Per row: the command's wall time end to end, the cluster's start, the compute wall time
  (first chunk sent to last chunk merged), the speed-up over this process with and without the
  start, the client's CPU per run and as a share of the workers' CPU, the workers' busy
  fraction, whether the JSON's statistics equal those of this process bit for bit, and per repeat
  the paired speed-up and the workers' CPU per run against this process's.
* **10^6 runs**: the per-run compute time of the sewing study's command in one process, and on
  the most workers measured (the scaling runs), and of one by one in this process (the per-run
  rounds), times 10^6.

BLAS single-threaded (OPENBLAS_NUM_THREADS=1, as the Dask workers run). The load average of the
machine (shared with other jobs) is printed with the results. Writes
``benchmarks/results/studies.md``.
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

VARY = ["C4=normal(260N*m/rad,5%)", "M3_0=normal(0.1N*m,10%)", "J3=uniform(2.8e-4kg*m^2,3e-4kg*m^2)",
        "U12=normal(1.375,2%)"]


def plan(runs: int, batch: bool = True, chunk: int = 250, seed: int = 1):
    from beltcalc.sim.core import SolverConfig
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.study.plan import Plan, parse_vary

    scene = SCENES["sewing"]
    dists = [parse_vary(scene.params, v) for v in VARY]
    return Plan(scene, scene.values(), SolverConfig(), tuple(n for n, _ in dists), dists=tuple(d for _, d in dists),
                runs=runs, seed=seed, chunk=chunk, batch=batch)


def solver_only(count: int = 15) -> tuple[float, float]:
    """(median ``SimResult.wall_time`` of one exact run of the nominal sewing drive, the CPU time
    of the same propagation, ``core._exact``, per call) [s]."""
    from beltcalc.sim.core import SolverConfig, run_exact, simulate
    from beltcalc.sim.scenes import SCENES
    from beltcalc.sim.scenes.sewing import build

    net = build(SCENES["sewing"].values())
    cfg = SolverConfig("exact")
    wall = float(np.median([simulate(net, 1.0, 10001, cfg).wall_time for _ in range(count)]))
    t, x0 = np.linspace(0.0, 1.0, 10001), net.initial_state()
    c0 = time.process_time()
    for _ in range(count):
        run_exact(net, t, x0, cfg)
    return wall, (time.process_time() - c0) / count


def chunk_cost(p, c: int) -> tuple[float, float, int]:
    """(wall, CPU) seconds per run of chunk ``c``, and how many rows came from the batch."""
    from beltcalc.sim.study.runs import run_chunk

    w0, c0 = time.perf_counter(), time.process_time()
    chunk = run_chunk(p, c)
    n = len(chunk.rows)
    return (time.perf_counter() - w0) / n, (time.process_time() - c0) / n, chunk.batched


def per_run(rounds: int) -> dict:
    batched, single = plan(250 * rounds), plan(60 * rounds, batch=False, chunk=60)
    chunk_cost(batched, 0)                        # warm-up: imports, caches
    out = {"batched": [], "single": [], "solver": [], "solver_cpu": [], "rows": 0}
    for r in range(rounds):
        s0 = solver_only()
        wb, cb, nb = chunk_cost(batched, r)
        ws, cs, _ = chunk_cost(single, r)
        s1 = solver_only()
        solver, cpu = 0.5 * (s0[0] + s1[0]), 0.5 * (s0[1] + s1[1])
        out["solver"].append(solver)
        out["solver_cpu"].append(cpu)
        out["batched"].append((wb, cb, wb / solver, cb / cpu))
        out["single"].append((ws, cs, ws / solver, cs / cpu))
        out["rows"] += nb
        print(f"round {r}: solver-only {solver * 1e3:.3f} ms (CPU {cpu * 1e3:.3f}); batched {wb * 1e3:.3f} ms/run "
              f"(CPU {cb / cpu:.2f}x), one by one {ws * 1e3:.3f} ms/run (CPU {cs / cpu:.2f}x)", flush=True)
    out["batched_runs"] = 250 * rounds
    return out


def max_rss(runs: int, steady: bool) -> tuple[int, float]:
    """(peak resident memory [bytes], wall [s]) of ``beltcalc simulate sewing`` running the study."""
    code = ("import resource, sys; from beltcalc.cli.main import main; sys.argv = ['beltcalc'] + sys.argv[1:]\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)")
    args = [a for v in VARY for a in ("--vary", v)]
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, "-c", code, "simulate", "sewing", *(["--steady-state-only"] if steady
                                                                                  else []),
                               *args, "--runs", str(runs), "--workers", "1", "--json", "--csv",
                               os.path.join(tmp, "r.csv")], capture_output=True, text=True, check=True)
        wall = time.perf_counter() - t0
    return int(done.stderr.splitlines()[-1]) * 1024, wall


SEWING = ["simulate", "sewing", "--vary", "C4=normal(260N*m/rad,5%)", "--vary", "U12=normal(1.375,2%)", "--seed", "1"]
CONVEYOR = ["simulate", "drive", "conveyor", "--vary", "upper.pretension=normal(400N,5%)", "--seed", "1"]


def study(args: list[str], runs: int, workers: int) -> dict:
    """One run of the command ``beltcalc ARGS --runs RUNS --workers W --json``: its wall time end
    to end, its JSON's execution profile and statistics."""
    import json

    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "beltcalc.cli.main", *args, "--runs", str(runs), "--workers",
                           str(workers), "--json"], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"beltcalc {' '.join(args)} --runs {runs} --workers {workers}: exit {done.returncode}\n{done.stderr}")
    wall = time.perf_counter() - t0
    out = json.loads(done.stdout)
    prof = out["execution_profile"]
    return {"runs": runs, "wall": wall, "start": prof["cluster_start"]["value"], "compute": prof["compute_wall"]["value"],
            "client_cpu": prof["client_cpu"]["value"], "worker_cpu": prof["worker_cpu"]["value"],
            "busy": prof["worker_busy"]["value"], "chunks": prof["chunks"], "chunk": prof["runs_per_chunk"],
            "how": out["execution"], "outputs": out["outputs"], "limits": out["limits"]}


def rate(r: dict, key: str) -> float:
    """Seconds a run of the figure ``key`` (``compute``, ``wall``, ``worker_cpu``) of result ``r``."""
    return r[key] / r["runs"]


def scaling(label: str, args: list[str], runs: int, counts: list[int], repeats: int, per_worker: bool = False) -> dict:
    """The study on each worker count (1: this process), each the best (by end-to-end wall) of
    ``repeats`` runs taken in turn; with each, every repeat's ratios to the in-process run of the
    same repeat (``paired``: compute time, end to end, the workers' CPU per run; all per run).
    ``per_worker``: ``runs`` runs a worker (W workers run W x ``runs``), as issue 34 measured
    the conveyor (400 runs on one worker, 4,000 on 16): the speed-ups are then per run."""
    best: dict[int, dict] = {}
    for _ in range(repeats):
        here = None
        for w in counts:
            r = study(args, runs * w if per_worker else runs, w)
            print(f"{label}, {w} worker(s): {r['wall']:.2f} s end to end, compute {r['compute']:.2f} s, start "
                  f"{r['start']:.2f} s, client CPU {r['client_cpu']:.2f} s of {r['worker_cpu']:.2f} s, busy "
                  f"{r['busy']:.2f} ({r['how']}, {r['chunks']} chunks of {r['chunk']})", flush=True)
            here = r if w == 1 else here
            pair = None if here is None else tuple(rate(here, k) / rate(r, k) for k in ("compute", "wall")) + (
                rate(r, "worker_cpu") / rate(here, "worker_cpu"),)
            paired = best[w]["paired"] if w in best else []
            if w not in best or r["wall"] < best[w]["wall"]:
                best[w] = r
            best[w]["paired"] = paired + ([pair] if pair else [])
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer rounds and runs (a check of the script)")
    ap.add_argument("--sewing-runs", type=int, default=50_000, help="runs of the sewing study (batched)")
    ap.add_argument("--conveyor-runs", type=int, default=400, help="runs of the conveyor study (one by one)")
    ap.add_argument("--workers", default=",".join(str(w) for w in (1, 2, 4, 8, 16) if w <= (os.cpu_count() or 1)),
                    help="worker counts, comma-separated (1: in this process) [default: 1, 2, 4, ... up to the CPUs]")
    ap.add_argument("--repeats", type=int, default=2, help="runs of each study on each count (the best is kept)")
    ap.add_argument("--conveyor-per-worker", action="store_true",
                    help="--conveyor-runs runs a worker: W x that many on W workers (speed-ups per run; issue 34's "
                         "4,000 runs on 16 workers: --conveyor-runs 250)")
    ap.add_argument("--only-scaling", action="store_true", help="the scaling tables only (e.g. on a larger machine)")
    args = ap.parse_args()
    load0 = os.getloadavg()
    t_start = time.perf_counter()
    counts = [int(w) for w in args.workers.split(",")]
    sewing_runs, conveyor_runs = (5_000, 60) if args.quick else (args.sewing_runs, args.conveyor_runs)
    scale = {"sewing": (sewing_runs, scaling("sewing", SEWING, sewing_runs, counts, args.repeats)),
             "conveyor": (conveyor_runs, scaling("conveyor", CONVEYOR, conveyor_runs, counts, args.repeats,
                                                 args.conveyor_per_worker))}
    if args.only_scaling:
        print("\n".join(scaling_lines(scale)))
        return
    rounds = 2 if args.quick else 5
    cost = per_run(rounds)
    sizes = (1_000, 3_000) if args.quick else (1_000, 10_000, 100_000)
    memory = {}
    for steady in (False, True):
        for runs in sizes:
            if not steady and runs > 10_000:
                continue
            memory[(steady, runs)] = max_rss(runs, steady)
            print(f"memory {'steady' if steady else 'time run'} {runs}: {memory[(steady, runs)][0] / 2 ** 20:.1f} MiB "
                  f"in {memory[(steady, runs)][1]:.1f} s", flush=True)
    load1 = os.getloadavg()
    total = time.perf_counter() - t_start
    write(cost, memory, scale, sizes, load0, load1, total)


def scaling_lines(scale: dict) -> list[str]:
    """The scaling tables (markdown), one per study."""
    titles = {"sewing": "sewing, batched path (`beltcalc " + " ".join(SEWING[:2]) + " --vary 'C4=normal(260N*m/rad,5%)' "
                        "--vary 'U12=normal(1.375,2%)' --runs {runs} --seed 1 --workers W --json`)",
              "conveyor": "conveyor drive file, one run at a time (`beltcalc simulate drive conveyor --vary "
                          "'upper.pretension=normal(400N,5%)' --runs {runs} --seed 1 --workers W --json`)"}
    lines = []
    for key, (runs, rows) in scale.items():
        one = rows[min(rows)]
        per_worker = any(r["runs"] != runs for r in rows.values())
        shown = f"{runs:,} x W" if per_worker else f"{runs:,}"
        lines += [f"### {titles[key].format(runs=shown)}", "",
                  "| workers | end to end [s] | cluster start [s] | compute [s] | speed-up, start included | "
                  "speed-up, start excluded | chunks x runs (the largest) | client CPU per run [ms] | client CPU / workers' CPU | "
                  "workers busy | statistics as in this process | each repeat, paired: speed-up without the start "
                  "(end to end) | each repeat, paired: the workers' CPU per run / this process's |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for w, r in sorted(rows.items()):
            same = r["outputs"] == one["outputs"] and r["limits"] == one["limits"]
            same = "- (other runs)" if r["runs"] != one["runs"] else "bit for bit" if same else "NO"
            where = "1 (this process)" if w == 1 else str(w) if "dask" in r["how"] else f"{w} (ran {r['how']})"
            share = "-" if w == 1 else f"{r['client_cpu'] / r['worker_cpu']:.2%}"
            pairs = r.get("paired") or []
            each = "-" if w == 1 else ", ".join(f"{c:.2f}x ({e:.2f}x)" for c, e, _ in pairs)
            cpu = "-" if w == 1 else ", ".join(f"{k:.3f}" for _, _, k in pairs)
            lines.append(f"| {where} | {r['wall']:.2f} | {r['start']:.2f} | "
                         f"{r['compute']:.2f} | {rate(one, 'wall') / rate(r, 'wall'):.2f}x | "
                         f"{rate(one, 'compute') / rate(r, 'compute'):.2f}x | "
                         f"{r['chunks']} x {r['chunk']:,} | {rate(r, 'client_cpu') * 1e3:.4f} | {share} | "
                         f"{r['busy']:.0%} | {same} | {each} | {cpu} |")
        if per_worker:
            each = ", ".join(f"{r['runs']:,} on {w}" for w, r in sorted(rows.items()))
            lines.append(f"\n{runs:,} runs a worker ({each}): every speed-up is per run.")
        lines.append("")
    return lines


def write(cost, memory, scale, sizes, load0, load1, total) -> None:
    med = lambda rows, k: float(np.median([r[k] for r in rows]))  # noqa: E731
    solver = float(np.median(cost["solver"]))
    solver_cpu = float(np.median(cost["solver_cpu"]))
    b_wall, b_cpu, b_ratio, b_cratio = (med(cost["batched"], k) for k in range(4))
    s_wall, s_cpu, s_ratio, s_cratio = (med(cost["single"], k) for k in range(4))
    lines = [
        "# Studies at scale: per-run cost, memory, workers (issues 17 and 34)",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; BLAS "
        f"single-threaded; `python benchmarks/studies.py` ({total:.0f} s). Load average (1, 5, 15 min) "
        f"{', '.join(f'{x:.2f}' for x in load0)} at the start, {', '.join(f'{x:.2f}' for x in load1)} at the end: "
        "the 2 cores are shared with other jobs, so wall times carry their load; the ratios are paired (each "
        "round against the solver-only time measured around it).",
        "",
        "The study: `beltcalc simulate sewing --vary " + " --vary ".join(f"'{v}'" for v in VARY) +
        " --runs N --seed 1`, each run its summary row (the exact method with its error estimate, 10,001 samples "
        "over 1 s, the steady window's statistics, the exact periodic steady state, the checks).",
        "",
        "## Per-run cost against the solver-only time of one exact run",
        "",
        f"Solver-only: `SimResult.wall_time` of `simulate(net, 1.0, 10001, SolverConfig('exact'))`, median "
        f"{solver * 1e3:.3f} ms; its CPU time (the same propagation, `core._exact`) {solver_cpu * 1e3:.3f} ms. "
        f"Medians over {len(cost['solver'])} rounds (a chunk of 250 runs batched, 60 one by one, per round). "
        "Wall against wall, CPU against CPU: under the load a chunk of a second loses the core to other jobs "
        "far more often than a run of half a millisecond, so the CPU ratio is the fairer one here.",
        "",
        "| path | wall per run [ms] | CPU per run [ms] | wall / solver-only wall | CPU / solver-only CPU |",
        "|---|---|---|---|---|",
        f"| batched exact propagation (`beltcalc.sim.batch`) | {b_wall * 1e3:.3f} | {b_cpu * 1e3:.3f} | "
        f"{b_ratio:.2f}x | {b_cratio:.2f}x |",
        f"| one by one (the scene's single run) | {s_wall * 1e3:.3f} | {s_cpu * 1e3:.3f} | {s_ratio:.2f}x | "
        f"{s_cratio:.2f}x |",
        "",
        f"Target <= 3x: {'met' if b_cratio <= 3 else 'not met'} (CPU {b_cratio:.2f}x, wall {b_ratio:.2f}x). "
        "The batched path is "
        f"{s_wall / b_wall:.1f}x faster than one by one; {cost['rows']:,} of {cost['batched_runs']:,} rows came "
        "from the batch (one check run per chunk goes alone).",
        "",
        "## Memory (peak resident memory of the command, rows streamed to CSV)",
        "",
        "| study | runs | peak RSS [MiB] | growth from 10^3 [MiB] | wall [s] |",
        "|---|---|---|---|---|",
    ]
    for steady in (False, True):
        base = memory.get((steady, sizes[0]))
        for runs in sizes:
            if (steady, runs) not in memory:
                continue
            rss, wall = memory[(steady, runs)]
            lines.append(f"| {'steady state' if steady else 'time run'} | {runs:,} | {rss / 2 ** 20:.1f} | "
                         f"{(rss - base[0]) / 2 ** 20:+.1f} | {wall:.1f} |")
    runs, rows = scale["sewing"]
    most = max(rows)
    per_run_most = rate(rows[most], "compute")
    # both batched rows from the scaling runs (minutes apart from the per-run rounds: the machine's
    # speed moves between them), one by one from the rounds
    per_run_here = rate(rows[min(rows)], "compute")
    lines += [
        "",
        "Target flat: the growth stays within a few MiB (a chunk's rows, the 10,000-row reservoir) whatever "
        "the number of runs.",
        "",
        f"## Scaling: this process against local Dask clusters of {', '.join(str(w) for w in sorted(rows) if w > 1)} "
        "workers (issue 34)",
        "",
        "Each study is the command a user types, timed end to end as a process (imports, the nominal run, the "
        "cluster's start and stop included); the rest is its JSON's `execution_profile`: the cluster's start, the "
        "compute wall time (first chunk sent to the last merged), this process's CPU meanwhile (handing chunks out, "
        "Dask's scheduler, which a local cluster runs in this process, and merging each chunk's part of the fold), "
        "and the workers' busy fraction (the chunks' wall time over workers x compute). \"Statistics as in this "
        "process\": the JSON's `outputs` and `limits` equal those of `--workers 1`, bit for bit. Best of "
        "the repeats by end-to-end wall time; the last two columns give every repeat against the in-process run "
        "just before it (the machine's load moves from one minute to the next).",
        "",
        *scaling_lines(scale),
        "## 10^6 runs, extrapolated",
        "",
        "| execution | per run [ms] | 10^6 runs |",
        "|---|---|---|",
        f"| batched, in this process | {per_run_here * 1e3:.3f} | {per_run_here * 1e6 / 60:.1f} min |",
        f"| batched, {most} local workers | {per_run_most * 1e3:.3f} | {per_run_most * 1e6 / 60:.1f} min |",
        f"| one by one, in this process | {s_wall * 1e3:.3f} | {s_wall * 1e6 / 60:.1f} min |",
        "",
    ]
    out = Path(__file__).parent / "results" / "studies.md"
    out.write_text("\n".join(lines))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
