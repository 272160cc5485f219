"""What the command line shares: the user-error type, progress lines and atomic output folders.

Bad input exits 2 with one line on stderr naming the file, row or column and the problem; results
are written to a temporary folder and renamed, so no partial output is left behind.
"""
from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from pathlib import Path

from studies.usecases.output_folder import OutputError, output_folder


class UserError(Exception):
    """Bad input: printed as one line, exit code 2."""


def progress(msg: str) -> None:
    """Progress of long work, to stderr when a person watches it (a terminal, or BEARINGFEM_VERBOSE
    set); scripts and schedulers reading stderr see only warnings and the one-line errors."""
    if watched():
        print(msg, file=sys.stderr, flush=True)


def watched() -> bool:
    """A person watches stderr (a terminal), or BEARINGFEM_VERBOSE asks for progress anyway."""
    return sys.stderr.isatty() or bool(os.environ.get("BEARINGFEM_VERBOSE"))


def progress_bar(desc: str, unit: str = "block"):
    """A `callback(done, total)` for long loops (`studies.model.parallel.map_blocks`): a tqdm
    bar on stderr while a person watches, nothing otherwise; closed when done == total."""
    state = {}

    def update(done: int, total: int) -> None:
        if not watched():
            return
        if "bar" not in state:
            from tqdm import tqdm  # noqa: PLC0415 -- deferred: only when a person watches

            state["bar"] = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False)
        bar = state["bar"]
        bar.update(done - bar.n)
        if done >= total:
            bar.close()
    return update


@contextmanager
def atomic_dir(out: Path):
    """`studies.usecases.output_folder.output_folder` (the one output-folder guard, shared with
    the Python API), its refusals raised as UserError (one line, exit 2)."""
    try:
        with output_folder(out) as tmp:
            yield tmp
    except OutputError as exc:
        raise UserError(str(exc)) from None
