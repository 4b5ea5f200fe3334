"""The one writer of every file a command writes (``--csv``, ``--plot``, ``--parquet``).

What is at the path decides how it is written (:func:`resolve_target`):

- nothing, or a regular file with one link: atomically. The bytes go to a temporary file
  in the same folder, are flushed to disk (``fsync``) and the temporary is renamed over
  the path (``os.replace``). A file it replaces keeps its mode and, where the user may
  set it (root, or the same owner), its owner and group; a new file gets the mode a plain
  ``open()`` gives (``0666`` less the umask).
- a symbolic link: its target, by the same rules (a dangling link makes its target, in a
  folder that must exist). The link stays a link.
- a regular file with hard links (``st_nlink > 1``): written in place, so that every name
  still shares it. Its space is reserved (``posix_fallocate``) before a byte of it
  changes, so a full disk leaves it as it was; a process killed while its bytes are copied
  can leave it part old, part new (the price of keeping the links).
- anything else that exists (a FIFO, a character or block device such as ``/dev/null``):
  opened and written in place, never removed or replaced (a FIFO waits for its reader).
- a folder: refused.

A command writes nothing until it has finished: inside :func:`output_session` (the
command group opens one around every command) the content goes to its temporary file while
the command runs, and only :meth:`Session.commit`, called once the command has printed its
answer, puts the files in place and says ``wrote PATH``. An error, ``--strict``, or an
interrupt (Ctrl-C) before that removes every temporary: no file is written, none replaced.
Outside a session (the library, a test) :func:`write_file` writes at once.

Temporary files are named ``.beltcalc-XXXXXXXX.tmp`` (8 random characters), in the
target's folder (for a file written in place: the system's temporary folder, ``$TMPDIR``). A
process killed outright (SIGKILL, a power cut) between creating one and the rename leaves
it behind; every later write into that folder removes those of its files of that exact
pattern that are older than :data:`STALE_TMP_AGE` (an hour), owned by the same user and
not locked: a running writer holds a lock (``flock``) on its own until it is done.
"""

from __future__ import annotations

import errno
import fcntl
import os
import re
import signal
import stat
import tempfile
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

from beltcalc.errors import OutputError

TEMP_PREFIX = ".beltcalc-"
TEMP_SUFFIX = ".tmp"
TEMP_PATTERN = re.compile(re.escape(TEMP_PREFIX) + r"[a-z0-9_]{8}" + re.escape(TEMP_SUFFIX))
STALE_TMP_AGE = 3600.0      # seconds after which an unlocked temporary of ours is a leftover
_CHUNK = 1 << 20

def shown(path) -> str:
    """``path`` as a message shows it: on one line, control characters escaped."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(path))


def _failed(path, exc: OSError) -> OutputError:
    return OutputError(f"cannot write {shown(path)}: {exc.strerror or exc}")


@dataclass(frozen=True)
class Target:
    """Where the bytes for a path go: ``path`` (a link resolved), and ``how``: ``"new"``,
    ``"replace"`` (atomic rename over a regular file) or ``"in place"`` (a file with hard
    links, a FIFO, a device); ``st`` its status (None for a new file)."""

    path: Path
    how: str
    st: os.stat_result | None = None


def resolve_target(path) -> Target:
    """How :func:`write_file` writes ``path`` (see the module's docstring), or an
    :class:`~beltcalc.errors.OutputError`: a folder, a loop of links, a folder missing."""
    path = Path(path)
    real = path
    try:
        try:
            st = os.lstat(path)
        except FileNotFoundError:
            st = None
        if st is not None and stat.S_ISLNK(st.st_mode):
            real = Path(os.path.realpath(path))
            try:
                st = os.lstat(real)
            except FileNotFoundError:
                st = None
            if st is not None and stat.S_ISLNK(st.st_mode):
                raise OutputError(f"cannot write {shown(path)}: a loop of symbolic links")
            if st is None:
                try:
                    st = os.stat(path)
                except FileNotFoundError:
                    st = None
                if st is not None and not stat.S_ISDIR(st.st_mode):
                    # a link the kernel follows but no path names (/dev/stdout -> /proc/self/fd/1
                    # -> 'pipe:[...]'): opened through the link itself
                    return Target(path, "in place", st)
        if st is None:
            folder = real.parent
            if not folder.is_dir():
                where = f"its link points to {shown(real)}, in " if real != path else ""
                raise OutputError(f"cannot write {shown(path)}: {where}the folder {shown(folder)}, which does not "
                                  "exist")
            return Target(real, "new")
    except OSError as exc:
        raise _failed(path, exc) from None
    if stat.S_ISDIR(st.st_mode):
        raise OutputError(f"cannot write {shown(path)}: it is a folder, not a file")
    if stat.S_ISREG(st.st_mode) and st.st_nlink <= 1:
        return Target(real, "replace", st)
    return Target(real, "in place", st)


def umask() -> int:
    """The process's umask (read without changing it where Linux shows it)."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def remove_stale_temporaries(folder, age: float = STALE_TMP_AGE, limit: int = 100) -> int:
    """Remove this writer's temporaries in ``folder`` left by a killed run: names of
    :data:`TEMP_PATTERN` exactly, regular files of this user, older than ``age`` seconds
    and not locked by a writer still at work; at most ``limit`` of them, ignoring any it
    cannot remove. Returns how many it removed."""
    removed = 0
    now = time.time()
    try:
        entries = os.scandir(folder)
    except OSError:
        return 0
    with entries:
        for entry in entries:
            if removed >= limit:
                break
            if not TEMP_PATTERN.fullmatch(entry.name):
                continue
            try:
                st = entry.stat(follow_symlinks=False)
                if not stat.S_ISREG(st.st_mode) or st.st_uid != os.geteuid() or now - st.st_mtime <= age:
                    continue
                fd = os.open(entry.path, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)     # a writer at work holds it
                    os.unlink(entry.path)
                    removed += 1
                finally:
                    os.close(fd)
            except OSError:
                pass
    return removed


def _write_text(fh, text: str) -> None:
    """Write ``text`` to the open temporary file (one place, so a test can fail it)."""
    fh.write(text)


@dataclass
class _Staged:
    """A file whose content is complete in its temporary ``tmp`` (locked through ``fd``)."""

    path: Path
    tmp: Path
    fd: int

    def discard(self) -> None:
        try:
            os.unlink(self.tmp)
        except OSError:
            pass
        try:
            os.close(self.fd)
        except OSError:
            pass

    def publish(self) -> None:
        """Put the content at ``path`` by the rule for what is there now."""
        try:
            target = resolve_target(self.path)
            if target.how in ("new", "replace") and self.tmp.parent == target.path.parent:
                self._rename(target)
            else:
                self._copy(target)
        except OSError as exc:
            raise _failed(self.path, exc) from None
        finally:
            self.discard()

    def _rename(self, target: Target) -> None:
        os.fsync(self.fd)
        if target.st is None:
            os.fchmod(self.fd, 0o666 & ~umask())
        else:
            st = target.st
            mine = os.fstat(self.fd)
            if (mine.st_uid, mine.st_gid) != (st.st_uid, st.st_gid):
                try:
                    os.fchown(self.fd, st.st_uid, st.st_gid)
                except PermissionError:        # another user's file: the owner is ours now
                    try:
                        os.fchown(self.fd, -1, st.st_gid)
                    except PermissionError:
                        pass
            os.fchmod(self.fd, stat.S_IMODE(st.st_mode))
        os.replace(self.tmp, target.path)
        try:
            folder = os.open(target.path.parent, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        except OSError:
            return
        try:
            os.fsync(folder)
        except OSError:
            pass
        finally:
            os.close(folder)

    def _copy(self, target: Target) -> None:
        """Write in place: a file with hard links, a FIFO, a device (or a new file whose
        temporary is elsewhere)."""
        size = os.fstat(self.fd).st_size
        flags = os.O_WRONLY | os.O_NOCTTY | os.O_CLOEXEC
        if target.st is None:
            flags |= os.O_CREAT | os.O_EXCL
        out = os.open(target.path, flags, 0o666)
        try:
            regular = stat.S_ISREG(os.fstat(out).st_mode)
            if regular and size:
                try:
                    os.posix_fallocate(out, 0, size)     # a full disk fails here, before a byte changes
                except OSError as exc:
                    if exc.errno not in (errno.EOPNOTSUPP, errno.EINVAL, errno.ENOSYS):
                        raise
            os.lseek(self.fd, 0, os.SEEK_SET)
            while True:
                chunk = os.read(self.fd, _CHUNK)
                if not chunk:
                    break
                view = memoryview(chunk)
                while view:
                    view = view[os.write(out, view):]
            if regular:
                os.ftruncate(out, size)
                os.fsync(out)
        finally:
            os.close(out)


def _stage(path, content) -> _Staged:
    """``content`` written to a new temporary for ``path`` (locked, flushed), or an
    :class:`~beltcalc.errors.OutputError` with nothing left behind."""
    path = Path(path)
    target = resolve_target(path)
    folder = target.path.parent if target.how != "in place" else Path(tempfile.gettempdir())
    remove_stale_temporaries(folder)
    try:
        fd, name = tempfile.mkstemp(prefix=TEMP_PREFIX, suffix=TEMP_SUFFIX, dir=folder)
    except OSError as exc:
        raise _failed(path, exc) from None
    staged = _Staged(path, Path(name), fd)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        if isinstance(content, str):
            with os.fdopen(os.dup(fd), "w", newline="", encoding="utf-8") as fh:
                _write_text(fh, content)
        else:
            content(staged.tmp)
    except BaseException as exc:
        staged.discard()
        if isinstance(exc, OSError):
            raise _failed(path, exc) from None
        raise
    return staged


@dataclass
class Session:
    """The files of one command: staged while it runs, put in place by :meth:`commit`."""

    staged: list[_Staged] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)

    def commit(self) -> None:
        """Put every staged file in place, then say ``wrote PATH`` for each on stderr.
        An interrupt that arrives meanwhile is ignored (the command has finished); a file
        that cannot be put in place is an error, and the files after it are not written."""
        import click

        with _interrupts_deferred():
            try:
                while self.staged:
                    self.staged.pop(0).publish()
            finally:
                self.discard()
        for line in self.messages:
            click.echo(line, err=True)
        self.messages.clear()

    def discard(self) -> None:
        while self.staged:
            self.staged.pop().discard()


_SESSIONS: list[Session] = []


@contextmanager
def output_session() -> Iterator[Session]:
    """Hold every file written inside until :meth:`Session.commit`; on leaving (an error,
    an interrupt, no commit) remove what was not committed."""
    session = Session()
    _SESSIONS.append(session)
    try:
        yield session
    finally:
        _SESSIONS.remove(session)
        session.discard()


@contextmanager
def _interrupts_deferred():
    """SIGINT ignored in the main thread while the files are put in place: the command has
    finished, and an interrupt now would leave some written and some not."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    try:
        previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    except ValueError:      # not the main interpreter
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def write_file(path, content) -> None:
    """Write ``content`` (text, or a function that writes the file at the path it is given,
    e.g. a figure's ``savefig``) to ``path`` by the rules of this module: at once, or, in an
    :func:`output_session`, when the session commits. On any failure (a read-only folder, a
    full disk) nothing is left half-written and no temporary stays:
    :class:`~beltcalc.errors.OutputError` naming the path."""
    staged = _stage(path, content)
    if _SESSIONS:
        _SESSIONS[-1].staged.append(staged)
    else:
        staged.publish()


def announce(path) -> None:
    """``wrote PATH`` on stderr: at once, or after the session's files are in place."""
    line = "wrote " + shown(path)
    if _SESSIONS:
        _SESSIONS[-1].messages.append(line)
    else:
        import click

        click.echo(line, err=True)
