"""The on-disk cache of bearingfem: meshes and FE set-ups, one folder per kind.

Every entry is a file named by a hash of everything it depends on. It is written atomically (to a
temporary file `<stem>.<pid><suffix>` beside it, read back and checked, then renamed), and checked
again whenever it is read: a damaged, truncated or foreign file is removed and rebuilt with one
warning line, never used. Temporary files of killed runs are removed (their PID is gone, or they
are older than STALE_AGE_S). The location is BEARINGFEM_CACHE (default ~/.cache/bearingfem); when
it cannot be written, a private temporary folder serves the run (one warning).
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable, TypeVar

T = TypeVar("T")

#: temporary cache files of killed runs older than this are removed whatever their PID (s)
STALE_AGE_S = 24 * 3600.0


def warn(msg: str) -> None:
    """One warning line on stderr (the run goes on)."""
    print(f"bearingfem: warning: {msg}", file=sys.stderr, flush=True)


def cache_dir(kind: str = "meshes", what: str = "mesh") -> Path:
    """The cache folder of one kind of entry (BEARINGFEM_CACHE or ~/.cache/bearingfem, then
    `kind`). When it cannot be created or written, a private temporary folder serves this run
    (one warning naming `what` is cached there)."""
    base = Path(os.environ.get("BEARINGFEM_CACHE", Path.home() / ".cache" / "bearingfem"))
    d = base / kind
    try:
        d.mkdir(parents=True, exist_ok=True)
        if not os.access(d, os.W_OK | os.X_OK):
            raise PermissionError(13, "not writable")
        return d
    except OSError as exc:
        known = _fallback.get(str(base))
        if known is None:
            known = _fallback[str(base)] = Path(tempfile.mkdtemp(prefix="bearingfem-cache-"))
            warn(f"{what} cache {d} is not usable ({exc.strerror or exc}); using {known} for "
                 "this run")
        (known / kind).mkdir(exist_ok=True)
        return known / kind


#: the temporary folder serving an unusable cache location, per location (one warning per run)
_fallback: dict[str, Path] = {}


def remove_stale(d: Path, stem: str, suffix: str) -> None:
    """Temporary files of killed runs in `d`: `<stem>_<key>.<pid><suffix>` whose process is gone,
    or older than STALE_AGE_S."""
    now = time.time()
    for f in d.glob(f"{stem}_*.*{suffix}"):
        try:
            pid = int(f.suffixes[-2][1:])
        except (ValueError, IndexError):
            continue
        try:
            alive = pid != os.getpid() and _pid_alive(pid)
            if not alive or now - f.stat().st_mtime > STALE_AGE_S:
                f.unlink()
        except OSError:
            pass


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def cached_file(path: Path, make: Callable[[Path], None], read: Callable[[Path], T], *,
                what: str, writer: str, error: type[Exception], refresh: bool = False) -> T:
    """The checked content of the cache entry `path`, built when missing or unusable.

    make(tmp): writes the entry to the temporary path `tmp`. read(p): reads and checks an entry,
    raising `error` (one-line message) when it is not a sound entry for this key. An unusable
    cached file is removed with one warning and rebuilt; a freshly written one that does not read
    back (a full disk) raises `error` and never enters the cache. `what` names the entry in
    messages ("mesh"), `writer` what wrote it ("gmsh")."""
    if (path.exists() or path.is_symlink()) and not refresh:
        try:
            return read(path)
        except error as exc:
            warn(f"cached {what} {path} is unusable ({exc}); rebuilding it")
            try:
                shutil.rmtree(path) if path.is_dir() and not path.is_symlink() else path.unlink()
            except OSError as exc2:
                raise error(f"cannot remove the unusable cached {what} {path} "
                            f"({exc2.strerror})") from None
    tmp = path.with_suffix(f".{os.getpid()}{path.suffix}")
    try:
        make(tmp)
        try:
            content = read(tmp)
        except error as exc:
            raise error(f"{writer} wrote an unusable {what} ({exc}); is the disk at "
                        f"{path.parent} full?") from None
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return content
