"""What a user's one command costs: start-up against the pint floor, and the exact
propagation's first (cold) call in a fresh process against a warm one.

Run: python benchmarks/startup.py [--runs N] [--processes K] [--only startup|cold]

Writes ``benchmarks/results/startup.md``:

- *Start-up*: every command with its defaults (each reproduces its source's worked
  example; ``simulate sewing`` runs the simulation) and two help pages, each run as its own
  process in turn with the floor ``python -c "import pint; pint.UnitRegistry(cache_folder=
  ':auto:')"`` (what any command that reads a quantity pays), A B A B ...; the CPU time
  (user + system, the operating system's accounting of the finished child, ``os.wait4``)
  of each, and the ratio pair by pair. Medians are quoted.
- *Cold and warm*: in ``K`` fresh processes (imports and the network's build done first,
  not timed), the first exact propagation of the sewing scene (``core._exact``: matrices,
  balancing, ``expm``, the samples); in another, its first ``expm`` alone; in a third, a
  first whole ``simulate()`` (propagation, outputs, error estimate); then, in the same
  process, the best of 20 warm calls. Medians over the processes; each time is this
  process's CPU time (``time.process_time``: page faults included, time spent waiting for a
  core while other processes ran excluded).

BLAS single-threaded, as the CLI runs it. Every process reads compiled bytecode, as an
installed package does (pip compiles it on install): where ``PYTHONDONTWRITEBYTECODE`` is set,
the children run without it and with ``PYTHONPYCACHEPREFIX`` in a temporary folder, filled by
the unpaired warm-up run; ``--no-bytecode`` measures with every module compiled from source
on every run instead.
"""

from __future__ import annotations

import argparse
import atexit
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

FLOOR = [sys.executable, "-c", "import pint; pint.UnitRegistry(cache_folder=':auto:')"]
# the floor with the garbage collector handled as the console script handles it (paused while
# importing, what is alive at the end frozen): how much of a ratio is that handling
FLOOR_GC = [sys.executable, "-c", "import gc; gc.disable(); import pint; pint.UnitRegistry(cache_folder=':auto:'); "
            "gc.freeze()"]
# commands above the target are broken down (floor, scipy imports, the calculation, the rest)
BREAKDOWN = [["simulate", "sewing"], ["simulate", "roller-table"], ["simulate", "drive", "conveyor"], ["response"]]
COMMANDS = [["--help"], ["simulate", "sewing", "--help"], ["simulate", "roller-table", "--help"], ["tension"],
            ["catalog", "list"], ["motor-size"], ["belt-drive"], ["chain"], ["simulate", "sewing"],
            ["simulate", "roller-table"], ["simulate", "linear-axis"], ["simulate", "drive", "conveyor"],
            ["simulate", "drive", "sewing"], ["simulate", "drive", "roller_table"],
            ["simulate", "drive", "linear_axis"], ["simulate", "drive", "friswell_5_disks"],
            ["simulate", "drive", "friswell_geared"], ["modes"], ["response"], ["campbell"]]

CHILD = r'''
import json, sys, time
import numpy as np
from beltcalc.sim import core, propagate
from beltcalc.sim.core import SolverConfig, simulate
from beltcalc.sim.scenes import SCENES
scene = SCENES["sewing"]; values = dict(scene.values())
net = scene.build(values); t_end, samples = scene.timing(values)
t = np.linspace(0.0, t_end, samples); x0 = net.initial_state(); cfg = SolverConfig("exact")

def timed(f):     # CPU time of this process (not the time other processes held the core)
    start = time.process_time(); f(); return time.process_time() - start

out = {}
if sys.argv[1] == "propagation":
    out["exact"] = timed(lambda: core.run_exact(net, t, x0, cfg))
    out["exact_warm"] = min(timed(lambda: core.run_exact(net, t, x0, cfg)) for _ in range(20))
elif sys.argv[1] == "expm":
    from beltcalc.numerics.expm import expm
    F = propagate.augmented_matrix(net) * (t[1] - t[0])
    out["expm"] = timed(lambda: expm(F))
    out["expm_warm"] = min(timed(lambda: expm(F)) for _ in range(20))
elif sys.argv[1] == "touch":     # a new array of the result's size, written once (the system's pages)
    out["touch"] = timed(lambda: np.empty((14, samples)).fill(1.0))
    out["touch_warm"] = min(timed(lambda: np.empty((14, samples)).fill(1.0)) for _ in range(20))
elif sys.argv[1] == "solve":     # numpy's first LAPACK call (14 x 14, as in expm)
    A = propagate.augmented_matrix(net)
    out["solve"] = timed(lambda: np.linalg.solve(A + 1e3 * np.eye(14), A))
    out["solve_warm"] = min(timed(lambda: np.linalg.solve(A + 1e3 * np.eye(14), A)) for _ in range(20))
else:
    out["simulate"] = timed(lambda: simulate(net, t_end, samples, cfg))
    out["simulate_warm"] = min(timed(lambda: simulate(net, t_end, samples, cfg)) for _ in range(20))
print(json.dumps(out))
'''


def cpu_of(cmd: list[str]) -> float:
    """User + system CPU seconds of one run of ``cmd`` (output discarded); a command that
    fails is an error here, not a fast row."""
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL)
    err = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        raise SystemExit(f"{' '.join(cmd)} exited {code}: {err.decode(errors='replace').strip()}")
    return usage.ru_utime + usage.ru_stime


def startup(runs: int) -> list[str]:
    exe = shutil.which("beltcalc") or str(Path(sys.executable).with_name("beltcalc"))
    lines = ["## Start-up: CPU of each command against the pint floor", "",
             f"Floor: `{' '.join(FLOOR[:2])} \"{FLOOR[2]}\"`. {runs} rounds each, after one unpaired warm-up of each: "
             "the command, the floor and the floor with the console script's garbage-collector handling "
             f"(`{FLOOR_GC[2]}`) in turn; ratios pair by pair, medians quoted. CPU = user + system of the finished "
             "process.", "",
             "| command | CPU [ms], median | floor [ms], median | ratio, median of pairs | ratio min..max | "
             "ratio to the floor with the same collector handling |",
             "|---|---|---|---|---|---|"]
    for args in COMMANDS:
        cmd = [exe, *args]
        cpu_of(cmd), cpu_of(FLOOR), cpu_of(FLOOR_GC)
        a, b, c = [], [], []
        for _ in range(runs):
            a.append(cpu_of(cmd))
            b.append(cpu_of(FLOOR))
            c.append(cpu_of(FLOOR_GC))
        ratios = [x / y for x, y in zip(a, b)]
        same = [x / y for x, y in zip(a, c)]
        lines.append(f"| `beltcalc {' '.join(args)}` | {statistics.median(a) * 1e3:.0f} | "
                     f"{statistics.median(b) * 1e3:.0f} | {statistics.median(ratios):.2f} | "
                     f"{min(ratios):.2f}..{max(ratios):.2f} | {statistics.median(same):.2f} |")
        print(lines[-1], flush=True)
    return lines


PARTS = r"""
import contextlib, io, json, sys, time
cpu = time.process_time
t0 = cpu()
import pint
from beltcalc.units import ureg
ureg()
t1 = cpu()
if sys.argv[1] == "import":                 # what importing these modules costs after the floor
    for name in sys.argv[2:]:
        __import__(name)
    print(json.dumps({"floor": t1 - t0, "total": cpu() - t1}))
    raise SystemExit
inside = [0.0]
if sys.argv[1] == "simulate":               # (only there: the time-domain core is imported)
    from beltcalc.sim import core
    real = core.simulate
    def simulate(*a, **k):                  # the calculation: every simulate() the command calls
        start = cpu()
        try:
            return real(*a, **k)
        finally:
            inside[0] += cpu() - start
    core.simulate = simulate
from beltcalc.cli.main import cli
with contextlib.redirect_stdout(io.StringIO()):
    code = cli.main(sys.argv[1:], prog_name="beltcalc", standalone_mode=False)
assert code in (0, None), code
loaded = sorted(m for m in ("scipy.linalg", "scipy.sparse", "scipy.optimize") if m in sys.modules)
print(json.dumps({"floor": t1 - t0, "total": cpu() - t1, "simulate": inside[0], "scipy": loaded}))
"""


def breakdown(processes: int) -> list[str]:
    """Where the CPU of a command above the target goes, in one process (no exit, collector on)."""
    def child(*args):
        done = subprocess.run([sys.executable, "-c", PARTS, *args], capture_output=True, text=True, check=True)
        return json.loads(done.stdout)

    def med(rows, key):
        return statistics.median(r[key] for r in rows) * 1e3

    lines = ["## Where it goes: the commands with a calculation", "",
             f"In-process CPU (`time.process_time`), medians over {processes} fresh processes, the collector left on "
             "and the process not ended (so these sums are below the start-up table's): the floor (pint's "
             "registry), the command after it, and of that the `simulate()` calls (the calculation: propagation, "
             "outputs, error estimate) and, measured in other fresh processes after the floor, the import of the "
             "scipy packages the command loads.", "",
             "| command | floor [ms] | command after the floor [ms] | of which simulate() [ms] | scipy packages it "
             "imports | their import [ms] |", "|---|---|---|---|---|---|"]
    for args in BREAKDOWN:
        rows = [child(*args) for _ in range(processes)]
        loaded = rows[0]["scipy"]
        imports = med([child("import", *loaded) for _ in range(processes)], "total") if loaded else 0.0
        lines.append(f"| `beltcalc {' '.join(args)}` | {med(rows, 'floor'):.0f} | {med(rows, 'total'):.0f} | "
                     f"{med(rows, 'simulate'):.0f} | {', '.join(loaded) or '-'} | {imports:.0f} |")
        print(lines[-1], flush=True)
    return lines


def cold(processes: int) -> list[str]:
    runs = {"propagation": [], "expm": [], "solve": [], "touch": [], "simulate": []}
    for _ in range(processes):
        for kind in runs:
            done = subprocess.run([sys.executable, "-c", CHILD, kind], capture_output=True, text=True, check=True)
            runs[kind].append(json.loads(done.stdout))

    def med(kind, key):
        return statistics.median(r[key] for r in runs[kind]) * 1e3

    lines = ["## Cold and warm: the sewing scene's exact run (10,001 samples, 11 states)", "",
             f"Medians over {processes} fresh processes; warm: the best of 20 further calls in the same process; CPU "
             "time of the process (`time.process_time`).", "",
             "| what | cold: first call in a fresh process [ms CPU] | warm [ms CPU] | cold / warm |",
             "|---|---|---|---|"]
    for label, kind, key in [("exact propagation (`core._exact`: matrices, balancing, expm, every sample)",
                              "propagation", "exact"),
                             ("one `expm` (`beltcalc.numerics.expm`) of the 14 x 14 augmented matrix", "expm", "expm"),
                             ("of which: numpy's first LAPACK call (a 14 x 14 solve)", "solve", "solve"),
                             ("a new 14 x 10,001 array written once (the result's size; warm: memory freed and "
                              "reused; cold: pages the system must map, about 1.5 us each here)", "touch", "touch"),
                             ("whole `simulate()` (propagation, outputs, error estimate)", "simulate", "simulate")]:
        c, w = med(kind, key), med(kind, key + "_warm")
        lines.append(f"| {label} | {c:.3f} | {w:.3f} | {c / w:.1f} |")
    print("\n".join(lines), flush=True)
    return lines


NOTES = """## Notes

- What a command pays beyond the floor: click and rich (the table), its own modules, the
  catalog files (TOML, units converted once), and its calculation. No default command
  imports a scipy module: the exact method's `expm` and balancing are
  `beltcalc.numerics.expm` and `.balance` (numpy; `scipy.linalg` had cost about 80 ms after the floor, about
  40 of them scipy's array-API layer importing numpy's `f2py`, `testing`, `ma`, `random` and
  `polynomial`), strand switches are located and the watch's extremes polished by
  `beltcalc.numerics.scalar`'s ports of scipy's `brentq` and bounded `minimize_scalar`
  (`scipy.optimize` had cost about 110 ms), `scipy.sparse` is imported only where the
  switching core's sparse path runs (large strand networks), `scipy.integrate` only for
  scipy's methods.
- The console script pauses the garbage collector while the command's modules are imported
  and freezes what is alive when it ends (`beltcalc/cli/main.py`): about a fifth of every
  command's CPU had been collections walking long-lived objects, mostly at shutdown. The
  floor process does not do this; the last column of the start-up table divides by a floor
  that does, so it shows the rest of the work like for like.
- The floor runs with BLAS single-threaded, as every command runs (`beltcalc/cli/main.py` sets
  `OPENBLAS_NUM_THREADS=1` before numpy loads). Typed as is, with OpenBLAS's default threads,
  the floor costs about 18 % more CPU on this machine (its threads' start-up and teardown),
  and every ratio is lower by as much.
- Bytecode: an installed package reads its compiled modules. With beltcalc compiled from
  source on every run instead (`--no-bytecode`: an editable checkout under
  `PYTHONDONTWRITEBYTECODE`), each ratio is 0.05 to 0.2 higher.
- At the target (1.3x): `simulate roller-table` and its drive file `roller_table` (the same
  scene; the drive file's range over the pairs is wide on this machine), then `simulate drive
  conveyor`. The roller table's calculation is about 65 ms of CPU cold (*Where it goes*; it
  was 140 ms, 1.56x): two exact runs of 6 s, 47,165 bottom steps of 133 us and the error
  estimate's 32,127 steps 1.5 times as long, every step's switching functions checked, 6,001
  samples with their exact integrals and 17 watched signals. What made it cheaper: the bottom
  step is `min(8 / ||F~||, 4 / rho)` instead of `4 / ||F~||` (the chain strands set the norm,
  6.0e4 1/s, while the spectral radius is 1.9e4: twice the step, half the steps), the reach
  bound's second-order part and rounding levels formed once per 8 steps, a run's blocks
  sharing their squared step matrices, glibc's malloc keeping freed memory for the next
  block's temporaries (the console script sets its thresholds: a page fault per page of
  every temporary had cost 1.5 us), and the drive data the scene hands the drive-file
  builder read without pint where its unit is already SI (9 ms: `docs/switching.md`).
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7, help="pairs per command (start-up)")
    parser.add_argument("--processes", type=int, default=7, help="fresh processes (cold and warm)")
    parser.add_argument("--only", choices=["startup", "cold", "breakdown"])
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "startup.md"))
    parser.add_argument("--no-bytecode", action="store_true", help="compile every module from source on every run")
    args = parser.parse_args()
    if args.no_bytecode:
        os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
        os.environ.pop("PYTHONPYCACHEPREFIX", None)
    elif os.environ.pop("PYTHONDONTWRITEBYTECODE", None):
        os.environ["PYTHONPYCACHEPREFIX"] = tempfile.mkdtemp(prefix="beltcalc-startup-pyc-")
        atexit.register(shutil.rmtree, os.environ["PYTHONPYCACHEPREFIX"], True)
    lines = ["# Start-up and the cold call", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; BLAS "
             f"single-threaded; load average {os.getloadavg()[0]:.1f} at the start (other processes on the machine "
             f"slow every row); {'every module compiled from source on every run' if args.no_bytecode else 'compiled bytecode read, as installed'}. "
             f"Run: `python benchmarks/startup.py{' --only ' + args.only if args.only else ''}"
             f"{' --no-bytecode' if args.no_bytecode else ''}`.", ""]
    if args.only in (None, "cold"):
        lines += cold(args.processes) + [""]
    if args.only in (None, "startup"):
        lines += startup(args.runs) + [""]
    if args.only in (None, "breakdown"):
        lines += breakdown(args.processes) + [""]
    if args.only is None:
        lines += [NOTES]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines))


if __name__ == "__main__":
    main()
