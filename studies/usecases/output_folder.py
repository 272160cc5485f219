"""The outputs of a command, from the command line and from Python alike: the checks of an output
file (`check_output_file`: -o of `simulate`, `stiffness`, `bearing`) and the output folder
(`report`, `tolerance`, `design`, `diagnose`, `verify`, `study`), written into a temporary folder
beside it and moved into place only when the work succeeds (`infra.files.atomic_folder`, which also sweeps the
temporaries of killed runs).

An existing folder is replaced only if it is empty or holds exactly what bearingfem wrote there
(the marker file lists it); a folder with anything else in it (the user's own files, or files
added since) is refused with their names, so nothing the user keeps there is lost."""
from __future__ import annotations

import os
import stat
from contextlib import contextmanager
from pathlib import Path

from infra.files import atomic_folder

MARKER = ".bearingfem-output"


class OutputError(ValueError):
    """An output folder that cannot or may not be written: one line naming it."""


@contextmanager
def output_folder(out: Path):
    """Yield a temporary folder beside `out`; move it to `out` only when the block succeeds.
    On failure or interruption the previous content stays untouched and the temporary folder is
    removed.  Refusals and write errors are one-line `OutputError`s."""
    out = Path(out).resolve()
    if out.exists():
        if not out.is_dir() or out.is_symlink():
            raise OutputError(f"{out}: exists and is not a folder")
        foreign = _foreign_files(out)
        if foreign:
            more = f" and {len(foreign) - 3} more" if len(foreign) > 3 else ""
            raise OutputError(f"{out}: holds files bearingfem did not write ({', '.join(foreign[:3])}"
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
            raise OutputError(f"{out}: cannot create the output folder ({exc.strerror})") from None
        raise OutputError(f"{out}: cannot write the results ({exc.strerror or exc}); nothing was "
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


def check_output_file(path: Path, inputs: tuple[Path, ...] = ()) -> None:
    """Refuse, before any work is done, an output path (or its provenance sidecar) that would
    lose or alter something the user has: one of the inputs, a symlink, an existing non-regular
    file (FIFO, device, folder), or a place that cannot be written."""
    from studies.model.table import sidecar_path

    _check_one_output(Path(path), inputs)
    _check_one_output(sidecar_path(path), inputs)


def _check_one_output(path: Path, inputs: tuple[Path, ...]) -> None:
    if path.is_symlink():
        raise OutputError(f"{path}: is a symbolic link; -o writes a regular file and does not "
                        "replace links (give the target's path)")
    if path.exists():
        if path.is_dir():
            raise OutputError(f"{path}: is a folder; -o needs a file name")
        if not stat.S_ISREG(path.stat().st_mode):
            raise OutputError(f"{path}: exists and is not a regular file (FIFO, device or socket); "
                            "choose another output name")
        for given in inputs:
            try:
                same = Path(given).exists() and os.path.samefile(path, given)
            except OSError:
                same = False
            if same:
                raise OutputError(f"{path}: is the input file {given}; choose another output name "
                                "(nothing was changed)")
    parent = path.resolve().parent
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK):
        raise OutputError(f"{path}: cannot write there ({probe} is not a writable folder)")
