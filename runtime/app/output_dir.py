"""The output folder of one ``simulate`` run: checked first, locked, written atomically.

Why: a run can take hours, and its results are what the user keeps.  So, before the run, the
folder is checked (not a file, not someone's non-empty folder without ``--force``, writable);
two runs into one folder at once would silently mix or replace each other's files, so the
second refuses, naming the first (a lock file beside the folder holding the owner's pid, locked
with ``flock``: a lock left by a run that died is free again and is taken over); and the files
are written into a staging folder beside the target and moved into place only when all are
complete, with SIGINT and SIGTERM held back for those few renames.  An interrupted run (Ctrl-C,
SIGTERM, a crash) therefore leaves the previous results as they were and never a truncated file.

    with OutputDir(Path("out/demo"), force=True) as output:
        write_files(output.staging)
        output.commit(["trajectory.npz", "summary.json"])
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import os
import shutil
import signal
import socket
import time
from collections.abc import Iterable, Iterator
from pathlib import Path

__all__ = ["FolderLock", "OutputDir", "OutputError"]


class OutputError(Exception):
    """The output folder cannot be used (one line, naming the path)."""


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM that arrive in the block are delivered when it ends.

    Python-level handlers, not a signal mask: a mask holds signals for one thread only, and a
    process-directed signal (Ctrl-C) would go to another thread (BLAS, numba) instead.  Outside
    the main thread, where handlers cannot be set, nothing is held."""
    pending: list[int] = []

    def hold(signum: int, _frame: object) -> None:
        if signum not in pending:
            pending.append(signum)

    held = (signal.SIGINT, signal.SIGTERM)
    try:
        previous = [signal.signal(s, hold) for s in held]
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        for s, handler in zip(held, previous, strict=True):
            signal.signal(s, handler)
        for s in pending:
            signal.raise_signal(s)


class OutputDir:
    """The target folder ``target`` of one run; ``owned`` are the file names a run writes
    (files of an earlier run among them that this run does not write are removed at commit;
    any other file in the folder is left alone)."""

    def __init__(self, target: Path, *, force: bool, owned: Iterable[str] = ()) -> None:
        self.target = Path(target)
        self.force = force
        self.owned = set(owned)
        name = self.target.name or "out"
        self.lock = FolderLock(self.target, "simulate run")
        self.lock_path = self.lock.path
        self.staging = self.target.parent / f".{name}.partial-{os.getpid()}"
        self.stale_lock: str | None = None  # who held the lock we took over, if anyone

    # -- before the run ---------------------------------------------------------------------

    def __enter__(self) -> OutputDir:
        self._check_target()
        try:
            self.target.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(
                f"cannot create the folder {str(self.target.parent)!r} for the output "
                f"{str(self.target)!r}: {_reason(exc)}"
            ) from None
        self.lock.acquire()
        self.stale_lock = self.lock.stale
        try:
            self._remove_stale_staging()
            self._check_writable()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _check_target(self) -> None:
        out = self.target
        if out.exists() and not out.is_dir():
            raise OutputError(f"output {str(out)!r} exists and is not a directory")
        for ancestor in out.parents:
            if ancestor.exists():
                if not ancestor.is_dir():
                    raise OutputError(
                        f"cannot create the output {str(out)!r}: {str(ancestor)!r} is a file, "
                        "not a directory"
                    )
                break
        if out.is_dir() and not self.force:
            try:
                busy = any(out.iterdir())
            except OSError as exc:
                raise OutputError(f"cannot read the output {str(out)!r}: {_reason(exc)}") from None
            if busy:
                raise OutputError(
                    f"output directory {str(out)!r} is not empty; use --force to overwrite "
                    "its files"
                )

    def _remove_stale_staging(self) -> None:
        """Staging folders of runs that died (we hold the lock: no live run owns one)."""
        pattern = f".{self.target.name or 'out'}.partial-*"
        for path in self.target.parent.glob(pattern):
            if path != self.staging and path.is_dir():
                shutil.rmtree(path, ignore_errors=True)

    def _check_writable(self) -> None:
        """Create the staging folder now and, if the target exists, a file in it: a folder that
        cannot be written is found before the run, not after it."""
        try:
            self.staging.mkdir()
        except OSError as exc:
            raise OutputError(
                f"cannot write beside the output {str(self.target)!r} "
                f"(creating {str(self.staging)!r}): {_reason(exc)}"
            ) from None
        if self.target.is_dir():
            probe = self.target / f".{self.staging.name}.write-test"
            try:
                probe.write_bytes(b"")
                probe.unlink()
            except OSError as exc:
                raise OutputError(
                    f"cannot write into the output directory {str(self.target)!r}: {_reason(exc)}"
                ) from None

    # -- after the run ----------------------------------------------------------------------

    def commit(self, written: Iterable[str]) -> None:
        """Move the files ``written`` (complete, in ``staging``) into the target; our files of an
        earlier run that this run did not write are removed.  Signals wait until it is done."""
        written = list(written)
        with _signals_held():
            if not self.target.exists():
                os.rename(self.staging, self.target)  # the whole folder at once
                return
            for name in written:
                os.replace(self.staging / name, self.target / name)
            for name in self.owned - set(written):
                (self.target / name).unlink(missing_ok=True)
            shutil.rmtree(self.staging, ignore_errors=True)

    def close(self) -> None:
        """Remove the staging folder (an interrupted run's files) and release the lock."""
        shutil.rmtree(self.staging, ignore_errors=True)
        self.lock.release()


class FolderLock:
    """The lock of an output folder: a file ``.<name>.lock`` beside it, locked with ``flock``
    and holding the owner's pid, host and start time, so a second writer (``user``: what the
    message calls it, e.g. "simulate run") is refused naming the first; a lock left by a
    process that died is free again and is taken over (``stale`` then describes it)."""

    def __init__(self, target: Path, user: str) -> None:
        self.target, self.user = Path(target), user
        self.path = self.target.parent / f".{self.target.name or 'out'}.lock"
        self.stale: str | None = None
        self._fd: int | None = None

    def acquire(self) -> None:
        """Take the folder's lock, or raise naming the run that holds it."""
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as exc:
                raise OutputError(
                    f"cannot create the lock file {str(self.path)!r} for the output "
                    f"{str(self.target)!r}: {_reason(exc)}"
                ) from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as exc:
                holder = _read(fd)
                os.close(fd)
                if exc.errno not in (errno.EAGAIN, errno.EACCES):
                    raise OutputError(f"cannot lock {str(self.path)!r}: {_reason(exc)}") from None
                raise OutputError(
                    f"output {str(self.target)!r} is in use by another {self.user} "
                    f"({_describe(holder)}); wait for it or choose another --out "
                    f"(lock file {str(self.path)!r})"
                ) from None
            # The holder before us may have removed the file after we opened it: then our lock
            # is on a file nobody else sees; start again.
            try:
                same = os.stat(self.path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if not same:
                os.close(fd)
                continue
            previous = _read(fd)
            self.stale = _describe(previous) if previous else None
            os.ftruncate(fd, 0)
            record = {"pid": os.getpid(), "host": socket.gethostname(), "started": time.time()}
            os.pwrite(fd, (json.dumps(record) + "\n").encode(), 0)
            self._fd = fd
            return

    def release(self) -> None:
        """Unlock and remove the lock file (if we hold it)."""
        if self._fd is not None:
            with contextlib.suppress(OSError):
                self.path.unlink()
            os.close(self._fd)
            self._fd = None


def _read(fd: int) -> dict:
    try:
        data = os.pread(fd, 4096, 0).decode("utf-8", "replace").strip()
        return json.loads(data) if data else {}
    except (OSError, ValueError):
        return {"unreadable": True}


def _describe(holder: dict) -> str:
    """'pid 1234 on host, started 2026-11-23 16:20:01'."""
    if not isinstance(holder, dict) or "pid" not in holder:
        return "pid unknown"
    text = f"pid {holder['pid']}"
    if holder.get("host") and holder["host"] != socket.gethostname():
        text += f" on {holder['host']}"
    started = holder.get("started")
    if isinstance(started, int | float):
        text += ", started " + time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(started))
    return text
