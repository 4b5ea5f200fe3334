"""Fuzz every command with the strategies of ``tests/test_fuzz.py``, many more times.

    python benchmarks/fuzz.py --examples 10000 [--seed 1] [--only tension] [--timeout 150]

Splits the invocations evenly over the commands, runs each in-process in its own empty
folder, and counts per command: exit 0/1/2, each failed invariant (hang, exit code,
traceback, internal error, stderr not one ``Error:`` line, invalid JSON, file left after
a failure, temporary file left, stalled drive reported as running), with the command line of each failure. Writes the counts
with the date, the command, the machine's load and wall time to
``benchmarks/results/fuzz.md`` (``--out``).
"""

from __future__ import annotations

import argparse
import collections
import os
import platform
import shutil
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from hypothesis import HealthCheck, Phase, given, seed, settings  # noqa: E402

import test_fuzz  # noqa: E402


def fuzz_command(command: str, examples: int, seed_value: int, folder: Path, timeout: float, log) -> dict:
    counts = collections.Counter()
    failures: list[tuple[str, str, str]] = []
    seconds: list[float] = []
    slowest = [0.0, ""]
    counter = iter(range(10 ** 9))

    @seed(seed_value)
    @settings(max_examples=examples, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(case=test_fuzz.STRATEGIES[command])
    def one(case):
        run_folder = folder / f"run{next(counter)}"
        out = test_fuzz.run(case, run_folder, timeout)
        shutil.rmtree(run_folder, ignore_errors=True)
        counts["invocations"] += 1
        counts[f"exit {out.exit_code}" if out.exit_code is not None else "no exit (hang)"] += 1
        seconds.append(out.seconds)
        if out.seconds > slowest[0]:
            slowest[:] = [out.seconds, case.command]
        for problem in out.problems:
            counts[problem] += 1
            failures.append((problem, case.command, (out.stderr.strip().splitlines() or [""])[-1][:300]))
            log(f"  FAIL {problem}: {case.command}\n       {failures[-1][2]}")

    one()
    return {"counts": counts, "failures": failures, "seconds": seconds, "slowest": slowest}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--examples", type=int, default=10_000, help="invocations in all (split over commands)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", action="append", help="only this command (repeatable), e.g. 'simulate drive'")
    parser.add_argument("--timeout", type=float, default=test_fuzz.TIMEOUT, help="seconds before a run is a hang")
    parser.add_argument("--out", type=Path, default=HERE / "results" / "fuzz.md")
    args = parser.parse_args(argv)

    commands = args.only or list(test_fuzz.STRATEGIES)
    unknown = set(commands) - set(test_fuzz.STRATEGIES)
    if unknown:
        parser.error(f"unknown command {sorted(unknown)}; one of {list(test_fuzz.STRATEGIES)}")
    per = max(1, args.examples // len(commands))
    load_before = os.getloadavg()
    started = datetime.now(timezone.utc)
    t0 = time.perf_counter()
    results = {}
    with tempfile.TemporaryDirectory(prefix="beltcalc-fuzz-") as tmp:
        for command in commands:
            print(f"{command}: {per} examples", flush=True)
            c0 = time.perf_counter()
            results[command] = fuzz_command(command, per, args.seed, Path(tmp) / command.replace(" ", "_"),
                                            args.timeout, lambda s: print(s, flush=True))
            results[command]["wall"] = time.perf_counter() - c0
            print(f"  {dict(results[command]['counts'])} in {results[command]['wall']:.0f} s", flush=True)
    wall = time.perf_counter() - t0
    load_after = os.getloadavg()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(report(results, args, started, wall, load_before, load_after))
    print(f"wrote {args.out}")
    return 1 if any(r["failures"] for r in results.values()) else 0


PROBLEMS = ["hang", "exit code", "exception", "traceback", "internal error", "stderr not one Error: line",
            "stderr on success not warning:/wrote lines", "invalid JSON", "file left after failure",
            "temporary file left", "stalled drive reported as running"]


def _problem_count(counts, prefix: str) -> int:
    return sum(v for k, v in counts.items() if k.startswith(prefix))


def report(results: dict, args, started, wall: float, load_before, load_after) -> str:
    total = collections.Counter()
    for r in results.values():
        total.update(r["counts"])
    lines = [
        "# Fuzzing every command (tests/test_fuzz.py strategies)",
        "",
        f"- date: {started:%Y-%m-%d %H:%M} UTC",
        f"- command: `python benchmarks/fuzz.py --examples {args.examples} --seed {args.seed}"
        + "".join(f" --only '{c}'" for c in (args.only or [])) + (f" --timeout {args.timeout:g}"
                                                                  if args.timeout != test_fuzz.TIMEOUT else "") + "`",
        f"- machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"load average (1/5/15 min) {'/'.join(f'{x:.2f}' for x in load_before)} before, "
        f"{'/'.join(f'{x:.2f}' for x in load_after)} after (shared machine)",
        f"- wall time: {wall:.0f} s for {total['invocations']} invocations",
        "- a run failing an invariant is listed below with its command line (run it in an empty folder; "
        "the input files it names are described after `#`)",
        "",
        "| command | invocations | exit 0 | exit 1 | exit 2 | failed invariants | median s | max s |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for command, r in results.items():
        c = r["counts"]
        secs = sorted(r["seconds"]) or [0.0]
        lines.append(f"| {command} | {c['invocations']} | {c['exit 0']} | {c['exit 1']} | {c['exit 2']} | "
                     f"{len(r['failures'])} | {secs[len(secs) // 2]:.3f} | {secs[-1]:.2f} |")
    failures = sum(len(r["failures"]) for r in results.values())
    lines.append(f"| **all** | {total['invocations']} | {total['exit 0']} | {total['exit 1']} | {total['exit 2']} | "
                 f"{failures} | | |")
    lines += ["", "## Failed invariants", "", "| invariant | count |", "|---|---:|"]
    for problem in PROBLEMS:
        lines.append(f"| {problem} | {_problem_count(total, problem)} |")
    lines += ["", "## Slowest invocation of each command", ""]
    for command, r in results.items():
        lines.append(f"- {command}: {r['slowest'][0]:.2f} s: `{r['slowest'][1]}`")
    lines += [""]
    if failures:
        lines += ["## Failures (command line, last stderr line)", ""]
        for command, r in results.items():
            for problem, line, err in r["failures"]:
                lines.append(f"- {problem}: `{line}`  \n  -> `{err}`")
    else:
        lines.append("No invocation failed an invariant.")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())
