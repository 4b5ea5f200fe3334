"""Roller-table scaling: the exact method against Radau as the number of rollers grows.

Run: python benchmarks/roller_scaling.py [--rollers 1,3,10,30,100,200] [--radau-limit 600]

For each roller count N the default scene runs with a per-roller load of 120 N m / N (the
three-roller default's 3 x 40 N m in total, which the motor carries), 7 s at 7001 samples
(the scene's default run):

* ``exact``, solve only (``estimate_error`` off) and end to end with its error estimate;
* Radau (rtol 1e-9, atol 1e-12, events at every strand switch), in its own process, given
  ``--radau-limit`` seconds (default 10 minutes) before it is stopped.

Each run is a separate process (its own start-up, no shared caches); the times are the
``simulate()`` call's wall time, with the scipy packages the methods import on first use
already loaded (their import is start-up, measured by ``benchmarks/startup.py``). Writes
``benchmarks/results/roller_scaling.md``: states, strand switches, times, the exact
method's own error estimate, and the largest difference
between exact and Radau over every node speed and sample. BLAS runs single-threaded, as in
the CLI.
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

T_END, SAMPLES, TOTAL_LOAD = 7.0, 7001, 120.0


def values(rollers: int) -> dict:
    """The scene's values as `beltcalc simulate roller-table --set rollers=N --set
    roller_load=...` gives them (T_END, SAMPLES and the scene's own window)."""
    from beltcalc.sim.scenes import SCENES

    return SCENES["roller-table"].values(rollers=float(rollers), roller_load=TOTAL_LOAD / rollers, t_end=T_END,
                                         samples=float(SAMPLES))


def one(rollers: int, method: str, out: str) -> None:
    """Run one case in this process; print its figures as JSON and save the node speeds.
    ``exact`` and ``exact+estimate`` time the call the CLI makes (the scene's run: the
    window's extremes and means watched on the exact solution, every output); Radau the
    bare ``simulate()`` (no watch: it samples)."""
    from beltcalc.sim.core import SolverConfig, simulate
    from beltcalc.sim.scenes import roller_table

    vals = values(rollers)
    net = roller_table.build(vals)
    if method == "exact":
        cfg = SolverConfig("exact", estimate_error=False, max_events=1_000_000)
    elif method == "exact+estimate":
        cfg = SolverConfig("exact", max_events=1_000_000, accept_error=True)
    else:
        # no budget of its own: the parent's --radau-limit stops it
        cfg = SolverConfig("radau", rtol=1e-9, atol=1e-12, estimate_error=False, max_events=1_000_000,
                           max_rhs_calls=10**9, max_seconds=1e9)
    # the scipy packages a method loads on first use (the exact path's brentq and sparse kernel,
    # Radau's scipy.integrate): imported before the clock starts, so the time is the solve's,
    # for every method alike (their import is start-up: benchmarks/startup.py)
    import scipy.integrate  # noqa: F401
    import scipy.optimize  # noqa: F401
    import scipy.sparse  # noqa: F401

    t0 = time.perf_counter()
    if method == "radau":
        r = simulate(net, T_END, SAMPLES, cfg)
    else:
        r = roller_table.run(vals, cfg).result
    wall = time.perf_counter() - t0
    n = net.n
    np.save(out, r.states[n:2 * n])
    print(json.dumps({"wall": wall, "states": net.size, "strands": len(net.strands),
                      "switches": r.extra.get("events"), "estimate": r.error_estimate,
                      "estimate_unit": r.error_unit, "relative": r.error_relative}))


def case(rollers: int, method: str, folder: str, limit: float) -> dict | None:
    out = os.path.join(folder, f"{method}_{rollers}.npy")
    try:
        p = subprocess.run([sys.executable, __file__, "--one", str(rollers), method, out], capture_output=True,
                           text=True, timeout=limit)
    except subprocess.TimeoutExpired:
        return None
    if p.returncode:
        raise RuntimeError(f"{method} at {rollers} rollers failed:\n{p.stderr}")
    res = json.loads(p.stdout.strip().splitlines()[-1])
    res["speeds"] = np.load(out)
    return res


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rollers", default="1,3,10,30,100,200")
    parser.add_argument("--radau-limit", type=float, default=600.0, help="seconds Radau may take per case")
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "roller_scaling.md"))
    parser.add_argument("--one", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        one(int(args.one[0]), args.one[1], args.one[2])
        return
    lines = [f"# Roller-table scaling ({SAMPLES} samples over {T_END:g} s, roller load {TOTAL_LOAD:g} N m / N)", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; BLAS "
             "single-threaded; every run its own process. Radau: rtol 1e-9, atol 1e-12, events at every strand "
             f"switch, stopped after {args.radau_limit:g} s. Difference: max |speed exact - speed Radau| over every "
             "node and sample [rad/s]. Estimate: the exact method's own error estimate (its largest relative to "
             "the signal's scale). Load: the machine's 1-minute load average when the exact runs began and "
             f"ended ({time.strftime('%Y-%m-%d')}).", "",
             "| rollers | states | switches | exact [s] | exact + estimate [s] | estimate | Radau [s] "
             "| Radau / exact | max difference [rad/s] | load |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as folder:
        for n in (int(x) for x in args.rollers.split(",")):
            load = [os.getloadavg()[0]]          # the shared machine's load: what the times ran beside
            ex = case(n, "exact", folder, 3600)
            est = case(n, "exact+estimate", folder, 3600)
            load.append(os.getloadavg()[0])
            rad = case(n, "radau", folder, args.radau_limit)
            diff = float(np.max(np.abs(ex["speeds"] - rad["speeds"]))) if rad else None
            row = (f"| {n} | {ex['states']} | {ex['switches']} | {ex['wall']:.3g} | {est['wall']:.3g} | "
                   f"{est['estimate']:.2g} {est['estimate_unit']} ({est['relative']:.1g}) | "
                   + (f"{rad['wall']:.3g} | {rad['wall'] / ex['wall']:.3g} | {diff:.2g} |" if rad else
                      f"> {args.radau_limit:g} (stopped) | - | - |")
                   + f" {load[0]:.1f}-{load[1]:.1f} |")
            lines.append(row)
            print(row, flush=True)
            # the table so far, after every row: a run stopped later keeps the rows it finished
            Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
