"""The roller table of Rusek & Popenda with and without the polygon (chordal) action (issue 33).

    python benchmarks/chain_dynamics.py        (about 8 minutes on 2 cores)

``beltcalc simulate roller-table --json`` as a user runs it (end to end, in this process), at
three supply frequencies: 50 Hz (the scene's default: the rollers' tooth-passing frequency
18.5 Hz lies 2.4 % above the well-damped mode at 18.03 Hz), the frequency that puts the tooth
frequency on the lightly damped mode nearest it (21.6 Hz), and 40 Hz, each with ``polygon=off``
(round sprockets, the exact solver) and ``polygon=on``. Per run: the method, its wall time and error estimate, roller 1's
mean speed and speed ripple (half peak-to-peak over the window), the tight strand's peak
force, the return strand's time slack, the tooth frequency and its nearest mode. Writes
``benchmarks/results/chain_dynamics.md``.
"""

from __future__ import annotations

import json
import os
import platform
import time
from pathlib import Path


def run(*sets: str) -> tuple[float, dict]:
    """(wall time [s], the JSON report) of ``beltcalc simulate roller-table --json --set ...``."""
    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    args = ["simulate", "roller-table", "--json"] + [a for s in sets for a in ("--set", s)]
    start = time.perf_counter()
    res = CliRunner().invoke(cli, args)
    wall = time.perf_counter() - start
    if res.exit_code != 0:
        raise SystemExit(f"{' '.join(args)}: exit {res.exit_code}: {res.stderr or res.output}")
    return wall, json.loads(res.stdout)


def on_mode_supply() -> tuple[float, float, float]:
    """(the supply frequency [Hz] that puts the rollers' tooth frequency on the lightly damped
    mode (damping ratio below 0.05) nearest the default's, that mode [Hz], its damping ratio): the rollers
    turn in proportion to the supply (the motor's slip held), so f = f_supply x f_mode / f_z,
    refined on the round-sprocket run (half a second each) until they agree to 1e-4."""
    from beltcalc.sim.frequency import poles
    from beltcalc.sim.scenes import SCENES

    scene = SCENES["roller-table"]
    modes = [p for p in poles(scene.build(dict(scene.values()))) if p.kind == "oscillatory" and p.damping_ratio < 0.05]
    _, report = run()
    target = min(modes, key=lambda p: abs(p.frequency - report["chain"]["tooth_frequency"]["value"]))
    supply = 50.0
    for _ in range(6):
        _, report = run(f"supply_frequency={supply!r}Hz")
        f_z = report["chain"]["tooth_frequency"]["value"]
        if abs(f_z / target.frequency - 1) < 1e-4:
            break
        supply *= target.frequency / f_z
    return supply, target.frequency, target.damping_ratio


def row(label: str, polygon: str, wall: float, r: dict) -> str:
    """One line of the table from the report ``r``."""
    roller, chain, strands = r["rollers"]["1"], r["chain"], r["strands"]
    return (f"| {label} | {polygon} | {r['method']} | {wall:.1f} | {r['error_relative']['value']:.1g} | "
            f"{roller['speed_mean']['value']:.5f} | {roller['speed_amplitude']['value']:.4g} | "
            f"{strands['drive-sprocket1']['force_max']['value']:.1f} | "
            f"{strands['sprocket3-drive']['slack_time']['value']:.3f} | {chain['tooth_frequency']['value']:.3f} | "
            f"{chain['nearest_mode']['value']:.3f} | {chain['separation']['value']:.3f} |")


def main() -> None:
    load = os.getloadavg()[0]
    supply, mode, zeta = on_mode_supply()
    cases = [("50 Hz (default)", "supply_frequency=50Hz"),
             (f"{supply:.3f} Hz (f_z on the {mode:.2f} Hz mode, damping ratio {zeta:.3f})",
              f"supply_frequency={supply!r}Hz"), ("40 Hz", "supply_frequency=40Hz")]
    lines = [
        "# The roller table with and without the polygon action",
        "",
        "`python benchmarks/chain_dynamics.py`: `beltcalc simulate roller-table --json --set polygon=off|on "
        "--set supply_frequency=F`, end to end in one process, "
        f"on {platform.processor() or platform.machine()} ({os.cpu_count()} cores), load {load:.1f} at the start.",
        "Roller 1: mean speed and ripple (half peak-to-peak) over the window t >= 5.5 s; the tight strand "
        "drive-sprocket1's peak force over the run; the return strand's time slack; the tooth-passing frequency "
        "z n of the window, its nearest natural frequency and their separation.",
        "",
        "| supply | polygon | method | wall [s] | error (rel.) | roller speed [rad/s] | ripple [rad/s] | "
        "peak force [N] | return slack [s] | f_z [Hz] | nearest mode [Hz] | separation |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, supply_set in cases:
        for polygon in ("off", "on"):
            wall, report = run(supply_set, f"polygon={polygon}")
            lines.append(row(label, polygon, wall, report))
            print(lines[-1], flush=True)
    out = Path(__file__).parent / "results" / "chain_dynamics.md"
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
