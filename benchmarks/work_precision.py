"""Work-precision of every method of the simulation core on the built-in scenes.

Run: python benchmarks/work_precision.py [--scene sewing|roller-table|linear-axis|all]
     python benchmarks/work_precision.py --drive conveyor_limiter   (a drive file: friction,
     clutches, brakes, torque limits: scipy's methods restarted at every switch, one run each)

Writes, per scene, ``benchmarks/results/work_precision_<scene>.md``: a Markdown table
(method, tolerance, wall time, right-hand-side calls, steps, largest error of one speed
against the exact solution) and, at the end, the best error each method reaches and the
time each needs for an error <= 1e-6. BLAS runs single-threaded, as in the CLI (small
matrices: threads cost more than they save).

Two times per run: *solver only* (``SimResult.wall_time``: the integration or propagation
alone) and *end to end* (the whole ``simulate()`` call in this process: matrices, solve,
every output signal, and for the exact row its error estimate, which runs the propagation
a second time; scipy's rows run without an estimate, as the table measures their error
against the exact solution outside their time). Both are the best of the repeats. The last
table puts them side by side, with the exact run once more including the network's build
from the scene's values. All are warm (this process has run the method before); a fresh
process pays more for its first call: ``benchmarks/startup.py``.
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from beltcalc.sim.core import SolverConfig, simulate  # noqa: E402
from beltcalc.sim.scenes import SCENES  # noqa: E402
from beltcalc.sim.study import workprecision  # noqa: E402
from beltcalc.sim.study.workprecision import fastest_at, scene_work_precision  # noqa: E402

END_TO_END: dict[tuple[str, float | None], float] = {}   # (method, rtol) -> best whole simulate() call [s]


def _timed_simulate(network, t_end, samples, cfg=SolverConfig(), **kw):
    """simulate(), its whole call timed (the work-precision runs go through it)."""
    start = time.perf_counter()
    result = simulate(network, t_end, samples, cfg, **kw)
    spent = time.perf_counter() - start
    if cfg.method != "exact" or not cfg.estimate_error:
        key = (cfg.method, None if cfg.method == "exact" else cfg.rtol)
        END_TO_END[key] = min(END_TO_END.get(key, spent), spent)
    return result


workprecision.simulate = _timed_simulate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="all", choices=[*SCENES, "all"])
    parser.add_argument("--drive", default=None, help="a drive file or built-in drive instead of the scenes")
    parser.add_argument("--signal", default="omega_drum", help="the speed measured (with --drive)")
    parser.add_argument("--out", default=str(Path(__file__).parent / "results"), help="folder for the results")
    args = parser.parse_args()
    if args.drive:
        run_drive(args.drive, args.signal, Path(args.out))
        return
    for name in SCENES if args.scene == "all" else [args.scene]:
        run(name, Path(args.out))


def run_drive(ref: str, signal: str, folder: Path) -> None:
    """Every method on a drive file's network, one run per tolerance (scipy's methods with
    events at every switch of a clutch, brake or limit can take minutes: at most 1,000,000
    right-hand-side calls each), against the exact solution; solver-only and end-to-end times."""
    from beltcalc.sim.drivefile import load_drive
    from beltcalc.sim.study.workprecision import work_precision

    drive = load_drive(ref)
    net, t_end, samples = drive.network, drive.t_end, drive.samples
    END_TO_END.clear()
    load = os.getloadavg()[0]
    rows = work_precision(net, t_end, samples, signal, tolerances=(1e-4, 1e-6, 1e-8), repeats=1,
                          max_rhs_calls=1_000_000)
    start = time.perf_counter()
    full = simulate(net, t_end, samples, SolverConfig("exact"))
    call = time.perf_counter() - start
    lines = [f"# Work-precision, drive {ref} ({samples} samples over {t_end:g} s)", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; BLAS "
             f"single-threaded; load average {load:.1f} at the start. Run: `python benchmarks/work_precision.py "
             f"--drive {ref}`. Error: max |{signal} - exact| over the run [rad/s]. scipy's methods restart at "
             "every switch (events on the same conditions the exact core locates), one run each, at most "
             "1,000,000 right-hand-side calls.", "",
             "| method | rtol | solver only [ms] | end to end [ms] | RHS calls | steps | max error | note |",
             "|---|---|---|---|---|---|---|---|",
             f"| exact (with its estimate) | - | {full.wall_time * 1e3:.3g} | {call * 1e3:.3g} | 0 | {full.steps} | "
             f"{full.error_estimate:.2g} (estimate) | {len(full.extra['switched']['log'])} switches |"]
    for r in rows[1:]:
        whole = END_TO_END.get((r.method, r.rtol))
        lines.append(f"| {r.method} | {r.rtol:.0e} | {'-' if r.error is None else f'{r.wall_time * 1e3:.3g}'} | "
                     f"{'-' if whole is None or r.error is None else f'{whole * 1e3:.3g}'} | {r.rhs_calls} | {r.steps} | "
                     f"{'-' if r.error is None else f'{r.error:.2g}'} | {r.note} |")
    out = folder / f"work_precision_drive_{Path(ref).stem}.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def exact_end_to_end(name: str, repeats: int = 50) -> tuple[float, float, float]:
    """Best of ``repeats`` whole calls of the exact method with its error estimate (the
    default call), without and with the network's build from the scene's values; and the
    solver-only time of those calls [s]."""
    scene = SCENES[name]
    values = scene.values()
    net = scene.build(dict(values))
    t_end, samples = scene.timing(dict(values))
    call = build = solver = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        r = simulate(net, t_end, samples, SolverConfig("exact"))
        call = min(call, time.perf_counter() - start)
        solver = min(solver, r.wall_time)
        start = time.perf_counter()
        simulate(scene.build(dict(values)), t_end, samples, SolverConfig("exact"))
        build = min(build, time.perf_counter() - start)
    return call, build, solver


def run(name: str, folder: Path) -> None:
    scene = SCENES[name]
    END_TO_END.clear()
    wp = scene_work_precision(scene, scene.values())
    rows, t_end, samples, signal = wp.rows, wp.t_end, wp.samples, wp.signal
    lines = [f"# Work-precision, {name} scene ({samples} samples over {t_end:g} s)", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
             f"BLAS single-threaded; load average {os.getloadavg()[0]:.1f} when the scene started (other processes "
             f"on the machine slow every row). Run: `python benchmarks/work_precision.py --scene {name}`. "
             f"Error: max |{signal} - exact| over the run (SI units). Steps: accepted steps (scipy's methods) "
             f"or internal exact steps; RHS calls: right-hand-side evaluations.", "",
             "| method | rtol | wall time [ms] | RHS calls | steps | max error | note |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r.method} | {'-' if r.rtol is None else f'{r.rtol:.0e}'} | "
                     f"{'-' if r.error is None else f'{r.wall_time * 1e3:.3g}'} | {r.rhs_calls} | {r.steps} | "
                     f"{'-' if r.error is None else f'{r.error:.2g}'} | {r.note} |")
    exact = rows[0]
    best = {m: min((r for r in rows if r.method == m and r.error is not None), key=lambda r: r.error, default=None)
            for m in dict.fromkeys(r.method for r in rows)}
    lines += ["", "Best error each method reached, and its time against exact:", "",
              "| method | best error | wall time [ms] | x exact's time |", "|---|---|---|---|"]
    for m, r in best.items():
        if r is not None:
            lines.append(f"| {m} | {r.error:.2g} | {r.wall_time * 1e3:.3g} | {r.wall_time / exact.wall_time:.0f} |")
    reach = fastest_at(rows, 1e-6)
    lines += ["", "Fastest run of each method with error <= 1e-6:", "",
              "| method | rtol | wall time [ms] | x exact's time |", "|---|---|---|---|"]
    for m, r in sorted(reach.items(), key=lambda kv: kv[1].wall_time):
        lines.append(f"| {m} | {'-' if r.rtol is None else f'{r.rtol:.0e}'} | {r.wall_time * 1e3:.3g} | "
                     f"{r.wall_time / exact.wall_time:.0f} |")
    call, build, solver = exact_end_to_end(name)
    lines += ["", "Solver only and end to end (the whole `simulate()` call: matrices, solve, every output signal; "
              "the exact method with its error estimate, a second computation on another partition (every sample "
              "again where the run switches, every (b+1)-th sample and the last where it is one linear piece); "
              "scipy's methods without one), each the best of its repeats in this one warm process:", "",
              "| method | rtol | solver only [ms] | end to end [ms] | end to end, x exact's |", "|---|---|---|---|---|",
              f"| exact, with its error estimate | - | {solver * 1e3:.3g} | {call * 1e3:.3g} | 1 |",
              f"| exact, with its estimate and the network's build | - | {solver * 1e3:.3g} | {build * 1e3:.3g} | "
              f"{build / call:.2g} |"]
    for r in rows[1:]:
        whole = END_TO_END.get((r.method, r.rtol))
        if r.error is None or whole is None:
            continue
        lines.append(f"| {r.method} | {r.rtol:.0e} | {r.wall_time * 1e3:.3g} | {whole * 1e3:.3g} | "
                     f"{whole / call:.0f} |")
    out = folder / f"work_precision_{name.replace('-', '_')}.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
