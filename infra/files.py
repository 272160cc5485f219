"""Atomic output: files and folders written under a temporary name beside their target and renamed
onto it only when complete; and the one sweeper of the temporaries that killed runs leave behind.

Every temporary is hidden and named `.<target name>.<pid>.<host><random>[<suffix>]` (`temporary_path`):
the PID of the process writing it, 8 hex digits of this machine's name and 8 random ones. The
sweeper (`sweep_stale`) removes a temporary whose process is gone or a zombie (killed and not yet
reaped by its parent; checked only for temporaries of this machine: a shared folder may hold another machine's live ones) and any temporary older than
STALE_AGE_S (PIDs are reused). A run interrupted by an exception or a signal that unwinds (Ctrl-C,
SIGTERM in the command line) removes its own temporaries; one killed outright (SIGKILL, power
loss) leaves them to the next run's sweep.

Permissions: a new file is created with mode 0666 and a new folder with 0777, less the umask, by
the kernel (`os.open` / `os.mkdir` with a mode): the umask is never read and set back, which races
with other threads (the workers of a Dask cluster, `--scheduler`, run threads). A file that replaces an existing one keeps that
file's mode.
"""
from __future__ import annotations

import os
import re
import secrets
import shutil
import socket
import time
import zlib
from contextlib import contextmanager
from pathlib import Path

#: temporaries older than this are removed whatever their PID (s): a day
STALE_AGE_S = 24 * 3600.0

#: 8 hex digits naming this machine in temporary names (the PID rule holds only on it)
HOST_TAG = f"{zlib.crc32(socket.gethostname().encode()):08x}"

_TEMP = re.compile(r"\.(?P<pid>\d+)\.(?P<host>[0-9a-f]{8})[0-9a-f]{8}(?:\.[A-Za-z0-9]+)?$")


def temporary_path(path: Path, keep_suffix: bool = False) -> Path:
    """A fresh hidden temporary name beside `path` (see the module docstring); with `keep_suffix`
    it ends in `path`'s suffix (writers that choose the format by it: gmsh, numpy)."""
    path = Path(path)
    name = f".{path.name}.{os.getpid()}.{HOST_TAG}{secrets.token_hex(4)}"
    return path.with_name(name + (path.suffix if keep_suffix else ""))


def sweep_stale(folder: Path, prefix: str) -> list[Path]:
    """Remove the temporaries `<prefix>*` in `folder` of runs that are gone: named by
    `temporary_path` with the PID of a process that no longer runs on this machine, or older than
    STALE_AGE_S (any name with the prefix). Returns what was removed; errors are ignored (another
    run may sweep at the same time)."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    removed, now = [], time.time()
    for p in folder.glob(f"{glob_escape(prefix)}*"):
        m = _TEMP.search(p.name)
        try:
            dead = (m is not None and m["host"] == HOST_TAG and int(m["pid"]) != os.getpid()
                    and not _pid_alive(int(m["pid"])))
            if dead or now - p.lstat().st_mtime > STALE_AGE_S:
                _remove(p)
                removed.append(p)
        except OSError:
            pass
    return removed


def glob_escape(text: str) -> str:
    """`text` with the glob metacharacters * ? [ taken literally."""
    return re.sub(r"([*?\[])", r"[\1]", text)


def _pid_alive(pid: int) -> bool:
    """The process runs: it exists and is not a zombie (a process killed outright stays in the
    process table, state Z, until its parent reaps it: a launcher still running, a notebook that
    started it; it will never write again, so its temporaries are stale)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:       # another user's process
        return True
    return not _zombie(pid)


def _zombie(pid: int) -> bool:
    """Linux: /proc/<pid>/stat's state field (after the command name in parentheses, which may
    hold spaces) is Z (zombie) or X (dead) (proc(5)). Elsewhere, or unreadable: False."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            stat = fh.read()
    except OSError:
        return False
    fields = stat[stat.rfind(b")") + 1:].split()
    return bool(fields) and fields[0] in (b"Z", b"X")


def _remove(p: Path) -> None:
    if p.is_dir() and not p.is_symlink():
        shutil.rmtree(p)
    else:
        p.unlink(missing_ok=True)


def _new_folders(path: Path) -> list[Path]:
    """The folders above `path` that do not exist yet, outermost first."""
    return [p for p in reversed(Path(path).parents) if not p.exists()]


def _remove_folders(created: list[Path]) -> None:
    for p in reversed(created):
        try:
            p.rmdir()
        except OSError:
            pass


class AtomicFile:
    """A file written to a temporary beside `path` and renamed onto it by `commit`; `discard`
    (or an exception in a `with` block) removes the temporary and the folders created for it.
    `open()` returns the writable handle (text with newline="" unless `binary`). The temporary of
    a file that replaces another gets that file's mode, a new one 0666 less the umask."""

    def __init__(self, path: Path, binary: bool = False):
        self.path, self.binary = Path(path), binary
        self.tmp: Path | None = None
        self.handle = None
        self._created: list[Path] = []

    def open(self):
        path = self.path
        self._created = _new_folders(path)
        sweep_stale(path.parent, f".{path.name}.")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            mode = (os.stat(path).st_mode & 0o7777) if path.exists() else None
            while True:
                tmp = temporary_path(path)
                try:
                    self.tmp = tmp
                    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
                    break
                except FileExistsError:
                    self.tmp = None
            if mode is not None:
                os.fchmod(fd, mode)
            self.handle = (os.fdopen(fd, "wb") if self.binary
                           else os.fdopen(fd, "w", newline="", encoding="utf-8"))
        except BaseException:
            if self.handle is None and self.tmp is not None and "fd" in locals():
                os.close(fd)
            self.discard()
            raise
        return self.handle

    def commit(self) -> None:
        """Close the temporary and rename it onto `path` (on an error: `discard`, then raise)."""
        try:
            self.handle.close()
            os.replace(self.tmp, self.path)
            self.tmp = None
        except BaseException:
            self.discard()
            raise

    def discard(self) -> None:
        """Remove the temporary and the folders created for it (idempotent)."""
        if self.handle is not None:
            try:
                self.handle.close()
            except OSError:
                pass
        if self.tmp is not None:
            try:
                os.unlink(self.tmp)
            except OSError:
                pass
            self.tmp = None
        _remove_folders(self._created)

    def __enter__(self):
        return self.open()

    def __exit__(self, exc_type, exc, tb) -> bool:
        if exc_type is None:
            self.commit()
        else:
            self.discard()
        return False


def write_atomic(path: Path, data: str | bytes) -> None:
    """Write `data` (text as UTF-8) to `path` atomically (`AtomicFile`)."""
    with AtomicFile(path, binary=isinstance(data, bytes)) as fh:
        fh.write(data)


@contextmanager
def atomic_folder(out: Path):
    """Yield a new temporary folder beside `out` (mode 0777 less the umask); when the block ends
    without an exception it replaces `out` (an existing `out` is moved aside to a temporary name
    first and removed after), else it is removed and `out` stays as it was. Deciding whether `out`
    may be replaced is the caller's job (`studies.usecases.output_folder.output_folder`)."""
    out = Path(out)
    sweep_stale(out.parent, f".{out.name}.")
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = None
    try:
        while tmp is None:
            tmp = temporary_path(out)
            try:
                os.mkdir(tmp, 0o777)
            except FileExistsError:
                tmp = None
        yield tmp
        if out.exists():
            old = temporary_path(out)
            out.rename(old)
            tmp.rename(out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(out)
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
