"""Helpers shared by the CLI tests: a clean success, a failure that is one error line, an
edited copy of a scene file, a CSV time series and the rows of a printed table."""

import csv
import io
from pathlib import Path

import numpy as np


def ok(result):
    """A run that exited 0 with nothing on stderr but ``warning:`` lines (failed checks and
    what the run could not give; ``warnings(result)`` lists them) and ``wrote FILE`` lines."""
    detail = f"exit {result.exit_code}\nstdout:\n{result.stdout}\nstderr:\n{result.stderr}"
    assert result.exit_code == 0, detail
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert all(line.startswith(("warning: ", "wrote ")) for line in result.stderr.splitlines()), detail
    return result


def warnings(result) -> list[str]:
    """The ``warning:`` lines of a run's stderr, without the prefix."""
    return [line[len("warning: "):] for line in result.stderr.splitlines() if line.startswith("warning: ")]


def one_error_line(result, exit_code: int, *fragments: str, stdout_empty: bool = True) -> str:
    """A run that failed with ``exit_code`` and exactly one 'Error:' line holding ``fragments``."""
    detail = f"exit {result.exit_code}\nstdout:\n{result.stdout}\nstderr:\n{result.stderr}"
    assert result.exit_code == exit_code, detail
    assert isinstance(result.exception, SystemExit), repr(result.exception)
    lines = result.stderr.splitlines()
    assert len(lines) == 1, detail
    assert lines[0].startswith("Error: "), detail
    assert "Traceback" not in result.output, detail
    if stdout_empty:
        assert result.stdout == "", detail
    for fragment in fragments:
        assert fragment in lines[0], f"{fragment!r} not in {lines[0]!r}"
    return lines[0]


def edited_copy(source: Path, folder: Path, old: str, new: str) -> Path:
    """A copy of ``source`` in ``folder`` with ``old`` replaced by ``new`` (which must be there)."""
    text = source.read_text()
    assert old in text
    path = folder / f"my_{source.name}"
    path.write_text(text.replace(old, new))
    return path


def read_csv(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    rows = list(csv.reader(io.StringIO(path.read_text())))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return header, {name: data[:, k] for k, name in enumerate(header)}


def table_rows(text: str, after: str) -> list[list[str]]:
    """The body rows (cells) of the rich table whose title starts with ``after``."""
    lines = text[text.index(after):].splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("┡"))
    rows = []
    for line in lines[start + 1:]:
        if not line.startswith("│"):
            break
        rows.append([cell.strip() for cell in line.strip("│").split("│")])
    return rows


_SHARED: dict[tuple[str, ...], object] = {}

#: Where the runs of :func:`shared_run` are kept for every process of one test session
#: (pytest-xdist's workers; set by conftest.py), None: in this process only.
SHARED_DIR: Path | None = None


class StoredResult:
    """What a test reads of a click ``Result`` (exit code, output streams, the exception's kind),
    read back from another process's run."""

    def __init__(self, exit_code: int, stdout: str, stderr: str, output: str, exception: str | None):
        self.exit_code, self.stdout, self.stderr, self.output = exit_code, stdout, stderr, output
        self.exception = None if exception is None else (SystemExit(exit_code) if exception == "SystemExit"
                                                         else RuntimeError(exception))


def shared_run(*args: str):
    """``beltcalc ARGS`` run in-process once per test session and shared by the tests that read
    it (a run of many seconds, e.g. the 20-roller table, asked for by several test modules):
    once per session across pytest-xdist's workers too (the first to ask runs it under a file
    lock; the others read what it kept). Only for runs that read no files the tests write."""
    if args in _SHARED:
        return _SHARED[args]
    if SHARED_DIR is None:
        _SHARED[args] = _invoke(args)
        return _SHARED[args]
    import fcntl
    import hashlib
    import json

    SHARED_DIR.mkdir(parents=True, exist_ok=True)
    key = hashlib.sha256(json.dumps(args).encode()).hexdigest()[:24]
    path = SHARED_DIR / f"{key}.json"
    with open(SHARED_DIR / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not path.exists():
            res = _invoke(args)
            exc = None if res.exception is None else type(res.exception).__name__
            kept = {"args": list(args), "exit_code": res.exit_code, "stdout": res.stdout, "stderr": res.stderr,
                    "output": res.output, "exception": exc}
            path.with_suffix(".tmp").write_text(json.dumps(kept))
            path.with_suffix(".tmp").replace(path)
            _SHARED[args] = res
            return res
    kept = json.loads(path.read_text())
    assert kept["args"] == list(args)
    _SHARED[args] = StoredResult(kept["exit_code"], kept["stdout"], kept["stderr"], kept["output"], kept["exception"])
    return _SHARED[args]


def shared_path(name: str) -> Path:
    """A file a :func:`shared_run` writes (``--csv``) where every process of the session finds it:
    in ``SHARED_DIR``, else in a folder of this process."""
    import os
    import tempfile

    folder = SHARED_DIR if SHARED_DIR is not None else Path(tempfile.gettempdir()) / f"beltcalc-shared-{os.getpid()}"
    folder.mkdir(parents=True, exist_ok=True)
    return folder / name


def sewing_eccentric_run():
    """(the run, its CSV's path) of ``simulate sewing --set roller_eccentricity=2mm --json --csv``,
    once per session: a Radau run of 30-55 s that tests/test_eccentric.py and
    tests/test_hard_cases_cli.py both read."""
    path = shared_path("sewing_eccentric.csv")
    return shared_run("simulate", "sewing", "--set", "roller_eccentricity=2mm", "--json", "--csv", str(path)), path


def _invoke(args):
    from click.testing import CliRunner

    from beltcalc.cli.main import cli

    return CliRunner().invoke(cli, list(args))
