"""What the command line shares: the user-error type, progress lines and atomic output folders.

Bad input exits 2 with one line on stderr naming the file, row or column and the problem; results
are written to a temporary folder and renamed, so no partial output is left behind.
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path


class UserError(Exception):
    """Bad input: printed as one line, exit code 2."""


def progress(msg: str) -> None:
    """Progress of long work, to stderr when a person watches it (a terminal, or BEARINGFEM_VERBOSE
    set); scripts and schedulers reading stderr see only warnings and the one-line errors."""
    if sys.stderr.isatty() or os.environ.get("BEARINGFEM_VERBOSE"):
        print(msg, file=sys.stderr, flush=True)


MARKER = ".bearingfem-output"


@contextmanager
def atomic_dir(out: Path):
    """Yield a temporary folder beside `out`; move it to `out` only when the block succeeds.

    An existing `out` is replaced only if it is empty or was written by bearingfem (it holds the
    marker file); any other existing folder is refused, so nothing the user keeps there is lost.
    On failure the previous content stays untouched and the temporary folder is removed."""
    out = Path(out).resolve()
    if out.exists():
        if not out.is_dir():
            raise UserError(f"{out}: exists and is not a folder")
        if any(out.iterdir()) and not (out / MARKER).exists():
            raise UserError(f"{out}: folder exists and was not written by bearingfem; choose a new "
                            "or empty folder (nothing was changed)")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    except OSError as exc:
        raise UserError(f"{out}: cannot create the output folder ({exc.strerror})") from None
    tmp.chmod(0o755)
    (tmp / MARKER).write_text("written by bearingfem; this folder is replaced by the next run\n")
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if out.exists():
        old = out.with_name(f".{out.name}.old")
        shutil.rmtree(old, ignore_errors=True)
        out.rename(old)
        tmp.rename(out)
        shutil.rmtree(old, ignore_errors=True)
    else:
        tmp.rename(out)
