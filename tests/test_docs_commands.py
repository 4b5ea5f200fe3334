"""Every `beltcalc ...` command in a fenced code block of README.md and docs/**/*.md runs, in-process
through click's CliRunner, and gives its documented exit code.

A block's commands are its lines that start with ``beltcalc`` (or ``$ beltcalc`` in a block that
shows a command with its output: then only those), a trailing ``\\`` joining the next line. The
exit code is 0 unless the line's comment says otherwise (``# exit 1``). Files a command writes
(``--csv``, ``--plot``, ``--parquet``) go to the test's own folder; relative input paths are read
from the repository's root.

Not run here, each for its reason in ``NOT_RUN``: commands with a placeholder or a file of the
reader's own, and runs of minutes. A command ``tests/test_readme_figures.py`` runs already (its
``COMMANDS``) is checked through the same shared run (``clichecks.shared_run``, once per session)
with ``--json``, so the suite does not pay for it twice. Commands over 10 s are marked slow.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest
from click.testing import CliRunner

from beltcalc.cli.main import cli
from clichecks import shared_run

ROOT = Path(__file__).resolve().parents[1]
OUTPUT_OPTIONS = ("--csv", "--plot", "--parquet")
EXIT = re.compile(r"#.*\bexit (\d+)")


@dataclass(frozen=True)
class Example:
    page: str
    line: int
    text: str                   # as written, continuation lines joined

    @property
    def tokens(self) -> list[str]:
        return shlex.split(self.text, comments=True)

    @property
    def args(self) -> tuple[str, ...]:
        return tuple(self.tokens[1:])

    @property
    def exit_code(self) -> int:
        m = EXIT.search(self.text)
        return int(m[1]) if m else 0

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}: {' '.join(self.args)[:70]}"


def fenced_blocks(text: str) -> list[tuple[int, str, list[str]]]:
    """(first line number, info string, lines) of every fenced block."""
    blocks, current, info, start = [], None, "", 0
    for number, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            if current is None:
                current, info, start = [], line.strip()[3:].strip(), number + 1
            else:
                blocks.append((start, info, current))
                current = None
        elif current is not None:
            current.append(line)
    assert current is None, "unclosed fenced block"
    return blocks


def commands(page: str) -> list[Example]:
    out = []
    for start, info, lines in fenced_blocks((ROOT / page).read_text(encoding="utf-8")):
        if info not in ("", "sh", "bash", "console", "shell"):
            continue                                    # toml, python: not commands
        prompt = any(line.startswith("$ ") for line in lines)
        k = 0
        while k < len(lines):
            line, number = lines[k], start + k
            while line.rstrip().endswith("\\") and k + 1 < len(lines):
                k += 1
                line = line.rstrip()[:-1] + " " + lines[k].strip()
            k += 1
            if prompt:
                if line.startswith("$ beltcalc "):
                    out.append(Example(page, number, line[2:]))
            elif line.startswith("beltcalc "):
                out.append(Example(page, number, line))
    return out


PAGES = ["README.md"] + sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md"))
EXAMPLES = [e for page in PAGES for e in commands(page)]

# commands not run here, by their arguments as written, with the reason
LONG = "a run of minutes (its benchmark: docs/performance.md)"
NOT_RUN: dict[str, str] = {
    "simulate sewing --work-precision": LONG,
    "simulate sewing --vary C4=normal(260N*m/rad,5%) --vary U12=normal(1.375,2%) --runs 10000 --seed 1 "
    "--limit main_torque_amplitude_N_m<=0.2N*m --csv rows.csv":
        "10,000 runs (the README's 100-run study of the same inputs runs here; benchmarks/studies.py times it)",
    "simulate sewing --set roller_eccentricity=2mm":
        "a run of 30-55 s that tests/test_hard_cases_cli.py runs as written (with --json and --csv) against "
        "an independent Radau reference",
    "simulate sewing --vary C4=normal(260N*m/rad,5%) --runs 5000 --seed 1 --scheduler tcp://SCHEDULER:8786":
        "a cluster of the reader's own (tests/test_study_cli.py starts dask scheduler and dask worker on the "
        "loopback and runs a study there)",
    "simulate roller-table --set polygon=on":
        "a run of about 2 minutes; tests/test_polygon.py runs the scene with the polygon action (one roller, a short "
        "start) against Radau with events, and benchmarks/chain_dynamics.py times the default",
    "simulate roller-table --method radau --rtol 1e-9":
        "a Radau run of about a minute over the default 7 s (its solver is scipy's; the exact run is compared with "
        "a Radau reference at rtol 1e-11 in tests/test_hard_cases_cli.py, and Radau is timed in docs/performance.md)",
}
# commands over 10 s (on the 2-core machine, beside other work): run, marked slow
SLOW: set[str] = {
    "simulate sewing --angle-loads",                                    # 24 s: Radau, nonlinear
    "simulate roller-table --set rollers=20 --set roller_load=6N*m",    # 14 s (slow in the figure test too)
    "simulate roller-table --sweep pretension=0N:600N:7 --csv sweep.csv",   # 12 s
    "simulate linear-axis --belt-model chain",                          # 12 s: 124 units
    "simulate sewing --steady-state-only --sweep C4=50N*m/rad:310N*m/rad:1000",  # 11 s: 1000 points
}


def reason_not_to_run(e: Example) -> str | None:
    key = " ".join(e.args)
    if key in NOT_RUN:
        return NOT_RUN[key]
    if "..." in e.tokens:
        return "a placeholder (...) for the reader's own options"
    outputs = {e.args[k + 1] for k, a in enumerate(e.args[:-1]) if a in OUTPUT_OPTIONS}
    for a in e.args:
        for value in ([a] if "=" not in a else [a.split("=", 1)[1]]):
            if (value.endswith((".toml", ".json")) and value not in outputs
                    and not (ROOT / value).exists() and Path(value).stem not in drive_names()):
                return f"{value}: a file of the reader's own"
    return None


def drive_names() -> list[str]:
    from beltcalc.sim.drivefile import drive_names as names

    return names()


def figure_commands() -> set[tuple[str, ...]]:
    """The commands tests/test_readme_figures.py runs (with --json, through shared_run)."""
    import test_readme_figures

    return set(test_readme_figures.COMMANDS.values())


def rewritten(args: tuple[str, ...], folder: Path) -> list[str]:
    """``args`` with every output path moved into ``folder``."""
    out = list(args)
    for k, a in enumerate(out[:-1]):
        if a in OUTPUT_OPTIONS:
            out[k + 1] = str(folder / Path(out[k + 1]).name)
    return out


def params() -> list:
    return [pytest.param(e, id=e.id, marks=[pytest.mark.slow] if " ".join(e.args) in SLOW else [])
            for e in EXAMPLES]


@pytest.mark.parametrize("example", params())
def test_documented_command_runs(example, tmp_path, monkeypatch):
    reason = reason_not_to_run(example)
    if reason:
        pytest.skip(reason)
    monkeypatch.chdir(ROOT)
    if example.args in figure_commands():
        result = shared_run(*example.args, "--json")
        assert result.exit_code == example.exit_code, f"beltcalc {example.text}\n{result.output[-2000:]}"
        return
    result = CliRunner().invoke(cli, rewritten(example.args, tmp_path))
    assert result.exit_code == example.exit_code, (
        f"{example.page}:{example.line}: beltcalc {' '.join(example.args)} exited {result.exit_code}, "
        f"documented {example.exit_code}\n{result.output[-2000:]}")
    if example.exit_code == 0:
        assert "Traceback" not in result.output


def test_the_parser_reads_blocks_continuations_prompts_and_exit_codes(tmp_path):
    text = ("text\n```\nbeltcalc tension   # a comment\nbeltcalc chain \\\n    --series B\n```\n"
            "```toml\nbeltcalc = 1\n```\n```\n$ beltcalc modes\nbeltcalc output line\n"
            "$ beltcalc motor-size --gear-ratio 1   # exit 1\n```\n")
    (tmp_path / "page.md").write_text(text)
    global ROOT
    saved, ROOT = ROOT, tmp_path
    try:
        found = commands("page.md")
    finally:
        ROOT = saved
    assert [(e.args, e.exit_code) for e in found] == [
        (("tension",), 0), (("chain", "--series", "B"), 0), (("modes",), 0), (("motor-size", "--gear-ratio", "1"), 1)]


def test_every_page_with_commands_is_read():
    """The README and the command pages hold commands; every one is either run or skipped for a
    stated reason, and NOT_RUN and SLOW name only commands that stand in a page."""
    by_page = {e.page for e in EXAMPLES}
    for page in ("README.md", "docs/tension.md", "docs/motor_sizing.md", "docs/design_checks.md",
                 "docs/drive_files.md", "docs/frequency_domain.md", "docs/scenes.md", "docs/studies.md",
                 "docs/catalogs.md"):
        assert page in by_page, page
    written = {" ".join(e.args) for e in EXAMPLES}
    assert set(NOT_RUN) <= written and SLOW <= written, (set(NOT_RUN) | SLOW) - written
