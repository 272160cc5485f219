"""The on-disk cache of bearingfem: meshes and FE set-ups, one folder per kind.

Every entry is a file named by a hash of everything it depends on. It is written atomically (to a
hidden temporary beside it, `infra.files.temporary_path`, read back and checked, then renamed), and
checked again whenever it is read: a damaged, truncated or foreign file is removed and rebuilt with
one warning line, never used. The temporaries of killed runs are removed when a run first uses the
folder (`infra.files.sweep_stale`: their PID is gone, or they are older than a day). The location
is BEARINGFEM_CACHE (default ~/.cache/bearingfem); when it cannot be written, a private temporary
folder serves the run (one warning).
"""
from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Callable, TypeVar

from infra.files import sweep_stale, temporary_path

T = TypeVar("T")


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
        sweep_stale(d, ".")                    # the temporaries of killed runs
        _sweep_legacy(d)
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


#: temporaries of bearingfem 0.2.0 and before: `<stem>_<key>.<pid><suffix>`
_LEGACY = re.compile(r"^[a-z]+_[0-9a-f]+\.(\d+)\.(msh|npz)$")


def _sweep_legacy(d: Path) -> None:
    """Remove the temporaries that killed runs of earlier versions left (named as _LEGACY; their
    PID no longer runs)."""
    for f in d.iterdir():
        m = _LEGACY.match(f.name)
        if m and int(m[1]) != os.getpid():
            try:
                os.kill(int(m[1]), 0)
            except ProcessLookupError:
                f.unlink(missing_ok=True)
            except OSError:
                pass


def npz_arrays(path: Path, error: type[Exception]) -> dict:
    """Every array of the numpy archive `path` by name (no pickles); `error` with a one-line
    message where the file cannot be read as one (damaged or foreign: zipfile, OSError,
    ValueError ...), for a cache entry's `read`."""
    import numpy as np

    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except Exception as exc:
        raise error(f"unreadable: {type(exc).__name__}") from None


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
    tmp = temporary_path(path, keep_suffix=True)   # the writer may choose the format by it
    try:
        make(tmp)
        try:
            content = read(tmp)
        except error as exc:
            raise error(f"{writer} wrote an unusable {what} ({exc}); is the disk at "
                        f"{path.parent} full?") from None
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return content
