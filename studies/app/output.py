"""What the command line shares: the user-error type, progress lines and atomic output folders.

Bad input exits 2 with one line on stderr naming the file, row or column and the problem; results
are written to a temporary folder and renamed, so no partial output is left behind.
"""
from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from pathlib import Path

from infra.files import atomic_folder


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


MARKER = ".bearingfem-output"


@contextmanager
def atomic_dir(out: Path):
    """Yield a temporary folder beside `out`; move it to `out` only when the block succeeds
    (`infra.files.atomic_folder`, which also sweeps the temporaries of killed runs).

    An existing `out` is replaced only if it is empty or holds exactly what bearingfem wrote there
    (the marker file lists it); a folder with anything else in it (the user's own files, or files
    added since) is refused with their names, so nothing the user keeps there is lost. On failure
    or interruption the previous content stays untouched and the temporary folder is removed."""
    out = Path(out).resolve()
    if out.exists():
        if not out.is_dir() or out.is_symlink():
            raise UserError(f"{out}: exists and is not a folder")
        foreign = _foreign_files(out)
        if foreign:
            more = f" and {len(foreign) - 3} more" if len(foreign) > 3 else ""
            raise UserError(f"{out}: holds files bearingfem did not write ({', '.join(foreign[:3])}"
                            f"{more}); choose a new or empty folder (nothing was changed)")
    started = False
    try:
        with atomic_folder(out) as tmp:
            started = True
            yield tmp
            written = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*") if p.is_file())
            (tmp / MARKER).write_text("written by bearingfem; the next run replaces these files:\n"
                                      + "".join(f"{w}\n" for w in written))
    except OSError as exc:
        if not started:
            raise UserError(f"{out}: cannot create the output folder ({exc.strerror})") from None
        raise UserError(f"{out}: cannot write the results ({exc.strerror or exc}); nothing was "
                        "changed") from None


def _foreign_files(out: Path) -> list[str]:
    """Files under `out` that the marker does not list (all of them when there is no marker)."""
    marker = out / MARKER
    listed = set()
    if marker.is_file():
        listed = {line.strip() for line in marker.read_text().splitlines()[1:] if line.strip()}
    return sorted(str(p.relative_to(out)) for p in out.rglob("*")
                  if (p.is_file() or p.is_symlink()) and p != marker
                  and str(p.relative_to(out)) not in listed)
