"""The one output writer (beltcalc/cli/writer.py), through the commands (issue 27, R1, R9,
R13, R14): a link is written at its target, a FIFO and a device in place, a file keeps its
mode, owner and hard links; a read-only folder or a full disk leaves the old file and no
temporary; a command writes its files only once it has finished (an error or Ctrl-C
leaves none), and Ctrl-C is one ``Error: interrupted`` line, exit 130.
"""

from __future__ import annotations

import errno
import os
import signal
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

import beltcalc.cli.writer as writer
from beltcalc.cli.main import cli
from clichecks import ok, one_error_line

OLD = "old,content\n"


@pytest.fixture(autouse=True)
def _no_debug_from_environment(monkeypatch):
    monkeypatch.delenv("BELTCALC_DEBUG", raising=False)


def run(*args: str):
    return CliRunner().invoke(cli, list(args))


def temporaries(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if writer.TEMP_PATTERN.fullmatch(p.name))


def is_tension_csv(path: Path) -> bool:
    return path.read_text().startswith("quantity,value,unit\n") and "tension_peak," in path.read_text()


# --- what is at the path decides how it is written (R1) -----------------------------------

def test_a_symlink_is_written_at_its_target(tmp_path):
    # was: the link replaced by a regular file, its target left as it was
    target = tmp_path / "t.csv"
    target.write_text(OLD)
    link = tmp_path / "link.csv"
    link.symlink_to("t.csv")
    result = ok(run("tension", "--csv", str(link)))
    assert result.stderr == f"wrote {link}\n"
    assert link.is_symlink() and os.readlink(link) == "t.csv"
    assert is_tension_csv(target)
    assert temporaries(tmp_path) == []


def test_a_dangling_symlink_makes_its_target_with_a_plain_open_mode(tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to("sub/new.csv")
    (tmp_path / "sub").mkdir()
    previous = os.umask(0o027)
    try:
        ok(run("tension", "--csv", str(link)))
    finally:
        os.umask(previous)
    target = tmp_path / "sub" / "new.csv"
    assert link.is_symlink() and is_tension_csv(target)
    assert stat.S_IMODE(target.stat().st_mode) == 0o640          # 0666 & ~0027, not mkstemp's 0600
    assert temporaries(tmp_path / "sub") == []


def test_a_new_file_gets_the_mode_of_a_plain_open(tmp_path):
    previous = os.umask(0o002)
    try:
        ok(run("tension", "--csv", str(tmp_path / "new.csv")))
    finally:
        os.umask(previous)
    assert stat.S_IMODE((tmp_path / "new.csv").stat().st_mode) == 0o664


def test_a_dangling_symlink_into_a_missing_folder_is_exit_2(tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to("nowhere/new.csv")
    one_error_line(run("tension", "--csv", str(link)), 2, "--csv", "link.csv", "nowhere", "does not exist")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv"] and link.is_symlink()


def test_a_loop_of_links_is_exit_2(tmp_path):
    (tmp_path / "a.csv").symlink_to("b.csv")
    (tmp_path / "b.csv").symlink_to("a.csv")
    one_error_line(run("tension", "--csv", str(tmp_path / "a.csv")), 2, "--csv", "a.csv")
    assert all(p.is_symlink() for p in tmp_path.iterdir())


@pytest.mark.parametrize("via_link", [False, True])
def test_a_folder_is_exit_2_naming_the_option(tmp_path, via_link):
    folder = tmp_path / "folder"
    folder.mkdir()
    path = folder
    if via_link:
        path = tmp_path / "link.csv"
        path.symlink_to("folder")
    one_error_line(run("tension", "--csv", str(path)), 2, "--csv", "folder")
    assert list(folder.iterdir()) == []


def test_a_0600_file_keeps_its_mode(tmp_path):
    # was: replaced by a 0644 file (a private result readable by every user)
    path = tmp_path / "private.csv"
    path.write_text(OLD)
    path.chmod(0o600)
    ok(run("tension", "--csv", str(path)))
    assert stat.S_IMODE(path.stat().st_mode) == 0o600 and is_tension_csv(path)


def test_a_replaced_file_keeps_its_owner(tmp_path):
    if os.geteuid() != 0:
        pytest.skip("only root can give a file to another user")
    path = tmp_path / "theirs.csv"
    path.write_text(OLD)
    os.chown(path, 12345, 23456)
    ok(run("tension", "--csv", str(path)))
    st = path.stat()
    assert (st.st_uid, st.st_gid) == (12345, 23456) and is_tension_csv(path)


def test_a_file_with_hard_links_is_written_in_place(tmp_path):
    # was: the name written got a new file; the other name kept the old content
    path = tmp_path / "a.csv"
    path.write_text(OLD * 200)                     # longer than the new content: truncated
    other = tmp_path / "b.csv"
    os.link(path, other)
    inode = path.stat().st_ino
    ok(run("tension", "--csv", str(path)))
    assert path.stat().st_ino == inode == other.stat().st_ino and path.stat().st_nlink == 2
    assert is_tension_csv(other) and "old,content" not in other.read_text()
    assert temporaries(tmp_path) == []


def test_a_fifo_is_written_in_place(tmp_path):
    # was: the FIFO replaced by a regular file (its reader waited for ever)
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()), daemon=True)
    reader.start()
    ok(run("tension", "--csv", str(fifo)))
    reader.join(10)
    assert not reader.is_alive()
    assert got and got[0].startswith("quantity,value,unit\n") and "tension_peak," in got[0]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert temporaries(tmp_path) == []


def test_dev_null_stays_a_device(tmp_path):
    # was: as root, --csv /dev/null replaced the system's /dev/null by a regular file
    before = os.stat(os.devnull)
    assert stat.S_ISCHR(before.st_mode)
    result = ok(run("tension", "--csv", os.devnull))
    assert result.stderr == f"wrote {os.devnull}\n"
    after = os.stat(os.devnull)
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev
    assert stat.S_IMODE(after.st_mode) == stat.S_IMODE(before.st_mode)


# --- failures leave the old file and no temporary ------------------------------------------

def test_a_read_only_folder_is_a_clean_error(tmp_path):
    folder = tmp_path / "locked"
    folder.mkdir()
    (folder / "out.csv").write_text(OLD)
    folder.chmod(0o500)
    try:
        if os.geteuid() == 0:                       # root writes anyway: the library's error, below
            pytest.skip("root writes into a read-only folder")
        one_error_line(run("tension", "--csv", str(folder / "out.csv")), 2, "--csv", "locked", "not writable")
        assert sorted(p.name for p in folder.iterdir()) == ["out.csv"]
        assert (folder / "out.csv").read_text() == OLD
    finally:
        folder.chmod(0o700)


def test_a_folder_refusing_the_temporary_is_a_clean_error(tmp_path, monkeypatch):
    # the writer's own refusal (what a read-only folder gives root-less users once the
    # option's check has passed, e.g. a folder made read-only while the command ran)
    def refuse(*args, **kw):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES))
    monkeypatch.setattr(writer.tempfile, "mkstemp", refuse)
    (tmp_path / "out.csv").write_text(OLD)
    one_error_line(run("tension", "--csv", str(tmp_path / "out.csv")), 1, "cannot write", "out.csv",
                   "Permission denied")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]
    assert (tmp_path / "out.csv").read_text() == OLD


def _disk_full_after_half(fh, text):
    fh.write(text[:len(text) // 2])
    fh.flush()
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_full_disk_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    monkeypatch.setattr(writer, "_write_text", _disk_full_after_half)
    path = tmp_path / "out.csv"
    path.write_text(OLD)
    one_error_line(run("tension", "--csv", str(path)), 1, "cannot write", "out.csv", "No space left on device")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"] and path.read_text() == OLD


def test_a_full_disk_leaves_a_hard_linked_file_as_it_was(tmp_path, monkeypatch):
    # written in place: its space is reserved before a byte of it changes
    def full(fd, offset, length):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(writer.os, "posix_fallocate", full)
    path = tmp_path / "a.csv"
    path.write_text(OLD)
    os.link(path, tmp_path / "b.csv")
    one_error_line(run("tension", "--csv", str(path)), 1, "cannot write", "a.csv", "No space left on device",
                   stdout_empty=False)
    assert path.read_text() == OLD and (tmp_path / "b.csv").read_text() == OLD
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.csv"]


def test_a_full_disk_during_a_figure_leaves_nothing(tmp_path, monkeypatch):
    # a writer function (savefig) failing half-way: the CSV written before it is not kept either
    pytest.importorskip("matplotlib")
    real = writer._stage

    def stage(path, content):
        if str(path).endswith(".png"):
            def half(tmp):
                Path(tmp).write_bytes(b"\x89PNG half")
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            content = half
        return real(path, content)
    monkeypatch.setattr(writer, "_stage", stage)
    args = ["motor-size", "--sweep", "accel=100rad/s^2:1000rad/s^2:3", "--csv", str(tmp_path / "m.csv"),
            "--plot", str(tmp_path / "m.png")]
    one_error_line(run(*args), 1, "cannot write", "m.png", "No space left on device")
    assert list(tmp_path.iterdir()) == []


# --- files only once the command has finished (R14), Ctrl-C (R9) --------------------------

def test_an_interrupt_while_the_table_prints_leaves_no_file(tmp_path, monkeypatch):
    # R14: Ctrl-C while motor-size printed its sweep table: exit 1, out.csv and out.png stayed
    pytest.importorskip("matplotlib")
    import beltcalc.cli.motor_size as motor_size

    class Interrupted:
        width = 110

        def print(self, *args, **kw):
            raise KeyboardInterrupt
    monkeypatch.setattr(motor_size, "console", lambda *a, **kw: Interrupted())
    (tmp_path / "m.csv").write_text(OLD)
    args = ["motor-size", "--sweep", "accel=100rad/s^2:1000rad/s^2:3", "--csv", str(tmp_path / "m.csv"),
            "--plot", str(tmp_path / "m.png")]
    result = run(*args)
    assert result.exit_code == 130 and result.stderr == "Error: interrupted\n", result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.csv"] and (tmp_path / "m.csv").read_text() == OLD


def test_a_failing_check_under_strict_writes_nothing(tmp_path):
    result = run("tension", "--mass", "1e-3kg", "--strict", "--csv", str(tmp_path / "out.csv"))
    assert result.exit_code == 1 and result.stderr.splitlines()[-1].startswith("Error: --strict")
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_is_one_line_exit_130_and_no_file(tmp_path):
    # R9: was a blank line and "Aborted.", exit 1; R14: and the study's files stayed
    env = dict(os.environ, BELTCALC_DEBUG="")
    env.pop("BELTCALC_DEBUG")
    args = [sys.executable, "-m", "beltcalc.cli.main", "simulate", "sewing", "--steady-state-only",
            "--vary", "C4=uniform(100N*m/rad,300N*m/rad)", "--runs", "10000000", "--workers", "1",
            "--csv", "out.csv", "--json"]
    # Ctrl-C as a terminal delivers it: SIGINT at its default (a suite started in the background
    # by a non-interactive shell inherits SIGINT ignored, and Python then leaves it ignored)
    proc = subprocess.Popen(args, cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 180          # bounds on waiting (a busy machine), not timings
    while not any(writer.TEMP_PATTERN.fullmatch(p.name) for p in tmp_path.iterdir()):   # the study has begun
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.05)
    time.sleep(0.3)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=180)
    assert proc.returncode == 130, (stdout, stderr)
    assert stderr == "Error: interrupted\n" and stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_dev_stdout_to_a_pipe_is_written_in_place(tmp_path):
    # /dev/stdout -> /proc/self/fd/1 -> 'pipe:[...]', a link no path names: written through the
    # link (was: replaced, as root, by a regular file; with the link followed: "no such file")
    proc = subprocess.run([sys.executable, "-m", "beltcalc.cli.main", "tension", "--json", "--csv", "/dev/stdout"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "wrote /dev/stdout\n"
    json_text, _, csv_text = proc.stdout.partition("quantity,value,unit\n")
    assert json_text.rstrip().endswith("}") and "tension_peak," in csv_text
    assert os.path.islink("/dev/stdout") and list(tmp_path.iterdir()) == []
