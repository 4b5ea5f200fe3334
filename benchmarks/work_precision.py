"""Work-precision of every method of the simulation core on the sewing scene.

Run: python benchmarks/work_precision.py [--out benchmarks/results/work_precision_sewing.md]

Writes a Markdown table (method, tolerance, wall time, right-hand-side calls, steps, largest
error of the main-shaft speed against the exact solution) and, at the end, the time each
method needs to reach the exact method's error or the best error it can reach. BLAS runs
single-threaded, as in the CLI (small matrices: threads cost more than they save).
"""

import os

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
from pathlib import Path  # noqa: E402

from beltcalc.catalogs import load_scene  # noqa: E402
from beltcalc.cli.options import resolve_scene  # noqa: E402
from beltcalc.cli.simulate import SEWING  # noqa: E402
from beltcalc.sim.scenes.sewing import build  # noqa: E402
from beltcalc.sim.workprecision import fastest_at, work_precision  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "work_precision_sewing.md"))
    args = parser.parse_args()
    values = {k: v.value for k, v in resolve_scene(load_scene("sewing"), SEWING, {}).items()}
    net = build(values)
    samples, t_end = int(values["samples"]), values["t_end"]
    rows = work_precision(net, t_end, samples, "omega_3")
    lines = [f"# Work-precision, sewing scene ({samples} samples over {t_end:g} s)", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
             "BLAS single-threaded. Error: max |omega_3 - omega_3,exact| over the run [rad/s].", "",
             "| method | rtol | wall time [ms] | RHS calls | steps | max error [rad/s] | note |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r.method} | {'-' if r.rtol is None else f'{r.rtol:.0e}'} | "
                     f"{'-' if r.error is None else f'{r.wall_time * 1e3:.3g}'} | {r.rhs_calls} | {r.steps} | "
                     f"{'-' if r.error is None else f'{r.error:.2g}'} | {r.note} |")
    exact = rows[0]
    best = {m: min((r for r in rows if r.method == m and r.error is not None), key=lambda r: r.error, default=None)
            for m in dict.fromkeys(r.method for r in rows)}
    lines += ["", "Best error each method reached, and its time against exact:", "",
              "| method | best error [rad/s] | wall time [ms] | x exact's time |", "|---|---|---|---|"]
    for m, r in best.items():
        if r is not None:
            lines.append(f"| {m} | {r.error:.2g} | {r.wall_time * 1e3:.3g} | {r.wall_time / exact.wall_time:.0f} |")
    reach = fastest_at(rows, 1e-6)
    lines += ["", "Fastest run of each method with error <= 1e-6 rad/s:", "",
              "| method | rtol | wall time [ms] | x exact's time |", "|---|---|---|---|"]
    for m, r in sorted(reach.items(), key=lambda kv: kv[1].wall_time):
        lines.append(f"| {m} | {'-' if r.rtol is None else f'{r.rtol:.0e}'} | {r.wall_time * 1e3:.3g} | "
                     f"{r.wall_time / exact.wall_time:.0f} |")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
