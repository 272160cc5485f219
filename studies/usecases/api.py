"""Every command as a Python function: what the command line runs (studies/app/commands.py parses
the flags, calls these and prints) and what `import bearingfem` offers (the facade re-exports
them). One route: the command and its function are the same call, so their numbers are equal.

Each function takes what its command takes: the assembly (an `Assembly` from `load_assembly`, or
the path of its TOML file), tables as a CSV path or in memory (column name -> values: a dict of
lists or arrays, or a pandas DataFrame; the same columns and checks as the file), and for the
commands that write a folder an optional `out` (None: the files go to a temporary folder that is
removed afterwards; the typed result holds the numbers). Results are typed (frozen dataclasses);
`.to_frame()` gives the table the command writes as CSV, units in the column names (docs/cli.md).

Bad input raises a ValueError subclass (ConfigError, TableError, EffectError, ModelError,
ToleranceError, DesignError, StiffnessRunError, BearingRunError, OutputError, ...) whose message
is the one line the command prints before exiting with code 2; nothing is written then.
"""
from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from studies.usecases.output_folder import check_output_file, output_folder


def _quiet(*_args) -> None:
    """The default progress: nothing (the command line passes its own)."""


def _is_path(x) -> bool:
    return isinstance(x, (str, os.PathLike))


def _assembly(assembly):
    """An `Assembly`, and the path it came from (None for one built in memory)."""
    from studies.model.config import load_assembly

    if _is_path(assembly):
        return load_assembly(Path(assembly)), Path(assembly)
    return assembly, None


def table(source, allowed: set[str] | None, where: str) -> dict[str, np.ndarray]:
    """A table argument as checked column arrays: a CSV path read by `read_table` (rows named by
    their line), or an in-memory table (dict or DataFrame; rows named `row N`, 1-based) through
    the same `check_columns`; `where` names an in-memory table in errors."""
    from studies.model.table import TableError, check_columns, read_table

    if _is_path(source):
        return read_table(Path(source), allowed=allowed)
    try:
        cols = {str(k): np.asarray(v, float).ravel() for k, v in dict(source).items()}
    except (TypeError, ValueError) as exc:
        raise TableError(f"{where}: not a table of numbers ({exc})") from None
    check_columns(where, cols, allowed)
    return cols


def _provenance(command: str, **inputs) -> dict:
    """`provenance` with the inputs given as files (an in-memory input is named, not hashed)."""
    from studies.model.provenance import provenance

    prov = provenance(command, {k: Path(v) for k, v in inputs.items() if _is_path(v)})
    prov["inputs"].update({k: {"path": "(in-memory table)", "sha256": _table_sha256(v)}
                           for k, v in inputs.items()
                           if v is not None and not _is_path(v) and k != "assembly"})
    return prov


def _table_sha256(cols) -> str:
    """SHA-256 of an in-memory table: its column names and float64 values in order."""
    import hashlib

    h = hashlib.sha256()
    for k, v in dict(cols).items():
        h.update(str(k).encode() + b"\0" + np.ascontiguousarray(np.asarray(v, float)).tobytes())
    return h.hexdigest()


@contextmanager
def _folder(out):
    """The command's output folder (`output_folder`: atomic, guarded), or with out=None a
    temporary one removed afterwards."""
    if out is not None:
        with output_folder(Path(out)) as tmp:
            yield tmp
        return
    with tempfile.TemporaryDirectory(prefix="bearingfem-") as tmp:
        yield Path(tmp)


def _check_workers(workers) -> None:
    from studies.model.table import TableError

    if workers is not None and workers < 1:
        raise TableError(f"workers {workers}: need at least 1")


# --- the commands --------------------------------------------------------------------------------

def diagnose(assembly, measured, out=None, progress=_quiet, noise: Mapping | None = None):
    """`bearingfem diagnose ASSEMBLY.toml MEASURED.csv --out DIR [--noise COLUMN=REL%[+ABS]]`:
    which named effect explains what the baseline model gets wrong on `measured` (condition
    columns, measured output columns and optional per-row `sigma_<column>`, docs/cli.md
    "diagnose"; at least 8 rows).  noise: a sensor's stated standard uncertainty per column,
    {"torque_Nmm": "1.5%+0.2"} (1.5 % of reading plus 0.2 N mm; a number or "0.5": absolute).
    Writes diagnosis.json and the report into `out`.  Returns `Diagnosis` (`verdict`, `cause`,
    `.result` the typed `studies.diagnosis.result.DiagnosisResult`, `.json` diagnosis.json as
    written)."""
    from studies.diagnosis.files import (OUTPUT_NAMES, diagnose_tables, measured_columns,
                                         measured_noise, split_measured)

    asm, _ = _assembly(assembly)
    cols = table(measured, measured_columns(OUTPUT_NAMES), "measured")
    where = measured if _is_path(measured) else "measured"
    conditions, meas = split_measured(cols, where)
    stated = measured_noise(cols, meas, noise, where)       # bad input: before any FE work
    with _folder(out) as tmp:
        result, doc = diagnose_tables(asm, conditions, meas, tmp, progress=progress,
                                      noise_model=stated)
    return Diagnosis(result, doc)


@dataclass(frozen=True)
class Diagnosis:
    """A diagnosis: the typed `DiagnosisResult` (`result`) and diagnosis.json as written
    (`json`); `verdict` and `cause` as the command prints them."""
    result: object
    json: dict = field(repr=False)

    @property
    def verdict(self) -> str:
        return self.json["verdict"]

    @property
    def cause(self) -> str | None:
        return self.json.get("cause")


def tolerance(assembly, conditions=None, samples: int = 1000, seed: int = 0, out=None,
              workers: int | None = None, scheduler: str | None = None, progress=_quiet,
              bar=None):
    """`bearingfem tolerance ASSEMBLY.toml [CONDITIONS.csv] --samples N --out DIR [--seed S]`:
    worst case and Monte Carlo of the fit tolerances ([fits] classes or deviations).  conditions:
    a conditions table, or None for the assembly's operating range.  Returns
    `tolerance_report.ToleranceSummary` (probabilities; `.json` tolerance.json; `.to_frame()`
    samples.csv: one row per sample and condition)."""
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.usecases import tolerance_report

    if samples < 2:
        raise tolerance_report.ToleranceError(f"samples {samples}: need at least 2")
    _check_workers(workers)
    asm, path = _assembly(assembly)
    cond = None if conditions is None else table(conditions, set(CONDITION_COLUMNS), "conditions")
    prov = _provenance("tolerance", assembly=path, conditions=conditions)
    with _folder(out) as tmp:
        return tolerance_report.run(asm, cond, tmp, prov, samples=samples, seed=seed,
                                    progress=progress, workers=workers, scheduler=scheduler,
                                    bar=bar)


def design(assembly, range_C: tuple[float, float], out=None, band: tuple[float, float] = (0.8, 1.2),
           band_N: tuple[float, float] | None = None, clamps: bool = False,
           vary: Mapping[str, tuple] | None = None, workers: int | None = None,
           scheduler: str | None = None, progress=_quiet, bar=None):
    """`bearingfem design ASSEMBLY.toml --range T_MIN:T_MAX --out DIR [--band LOW:HIGH |
    --band-N LOW:HIGH] [--clamps] [--vary KEY=V1,V2,...]`: the stack whose preload varies least
    over range_C (C).  band: fractions of the assembled preload; band_N: the band in N instead;
    vary: {key of `design_search.SETTING_KEYS`: values}.  Returns `design_search.DesignResult`
    (`.to_frame()`: the confirmed designs, ranked, the columns of design.json's rows)."""
    from studies.usecases import design_search as ds

    T_min, T_max = (float(v) for v in range_C)
    if not T_min < T_max:
        raise ds.DesignError(f"range_C {T_min:g}:{T_max:g}: LOW must be below HIGH")
    if not (-150.0 <= T_min and T_max <= 300.0):
        raise ds.DesignError(f"range_C {T_min:g}:{T_max:g}: outside -150..300 C (range of the "
                             "material data)")
    if band_N is not None:
        lo, hi = (float(v) for v in band_N)
        if not lo < hi or lo < 0:
            raise ds.DesignError(f"band_N {lo:g}:{hi:g}: need 0 <= LOW < HIGH (N)")
        the_band = ds.Band(lo, hi, absolute=True)
    else:
        lo, hi = (float(v) for v in band)
        if not lo < hi:
            raise ds.DesignError(f"band {lo:g}:{hi:g}: LOW must be below HIGH")
        the_band = ds.Band(lo, hi)
    _check_workers(workers)
    asm, path = _assembly(assembly)
    vary = {k: tuple(v) for k, v in (vary or {}).items()}
    ds.settings_of(asm, vary)                   # bad values: one line before any work
    with _folder(out) as tmp:
        return ds.run(asm, T_min, T_max, tmp, _provenance("design", assembly=path),
                      band=the_band, clamps=clamps, progress=progress, workers=workers,
                      scheduler=scheduler, bar=bar, vary=vary)


def stiffness(assembly, conditions, out=None, per_bearing: bool = False, ross=None,
              free_axial: bool = False, progress=_quiet):
    """`bearingfem stiffness ASSEMBLY.toml CONDITIONS.csv -o OUT.csv [--per-bearing]
    [--ross ROSS.csv] [--free-axial]`: the pair's 5 x 5 tangent stiffness at its equilibrium per
    row (25 columns), with free_axial also the force-controlled radial stiffness.  out and ross:
    file paths to write (None: not written); `ross=True` builds the ROSS table without writing
    it.  Returns `stiffness.StiffnessRun` (`.to_frame()` OUT.csv; `.ross.to_frame()` the
    ROSS table, `ross.BearingElement.from_table` reads its names; `.warnings` the lines the
    command prints, e.g. rows that lost the preload)."""
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.usecases import stiffness as st

    inputs = tuple(Path(p) for p in (assembly, conditions) if _is_path(p))
    if out is not None:                         # before any work: nothing the user has is lost
        check_output_file(Path(out), inputs)
    if _is_path(ross):
        check_output_file(Path(ross), inputs + ((Path(out),) if out is not None else ()))
    asm, path = _assembly(assembly)
    cond = table(conditions, set(CONDITION_COLUMNS), "conditions")
    where = str(conditions) if _is_path(conditions) else "conditions"
    res = st.compute(asm, cond, where, per_bearing, ross is not None and ross is not False,
                     progress, free_axial)
    if out is not None:
        ross_out = ross if _is_path(ross) else None
        st.write(res, Path(out), None if ross_out is None else Path(ross_out),
                 _provenance("stiffness", assembly=path, conditions=conditions))
    return res


def report(assembly, conditions=None, out=None, pdf: bool = False, progress=_quiet,
           command: list[str] | None = None):
    """`bearingfem report ASSEMBLY.toml [CONDITIONS.csv] --out DIR [--pdf]`: report.md and
    report.html (and report.pdf), margins first.  Returns `assembly_report.ReportRun` (the
    warnings; `.to_frame()` results.csv)."""
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.usecases import assembly_report

    asm, path = _assembly(assembly)
    cond = None if conditions is None else table(conditions, set(CONDITION_COLUMNS), "conditions")
    prov = _provenance("report", assembly=path, conditions=conditions)
    with _folder(out) as tmp:
        return assembly_report.run(asm, cond, tmp, prov, progress=progress, pdf=pdf,
                                   command=command)


def verify(out=None, assembly=None, progress=_quiet):
    """`bearingfem verify --out DIR [--assembly ASSEMBLY.toml]`: the verification cases (Lamé,
    mesh convergence of the assembly's stack, manufactured solutions) into verification.md and
    verification.json.  Returns `verify.VerifyRun`."""
    from studies.usecases import verify as vf

    asm = None if assembly is None else _assembly(assembly)[0]
    with _folder(out) as tmp:
        return vf.run(tmp, progress=progress, assembly=asm)


def bearing(bearing_file, loads, out=None, convention: str = "exact", control: str = "outer"):
    """`bearingfem bearing BEARING.toml LOADS.csv -o OUT.csv [--convention exact|iso16281]
    [--control outer|inner|jones]`: one bearing, 5 DOF of its inner ring, per row of `loads`.
    bearing_file: the bearing's TOML path (or a loaded `BearingConfig`).  Returns
    `bearing_single.BearingRun` (`.state` the typed state, `.to_frame()` OUT.csv)."""
    from studies.model.config import load_bearing
    from studies.model.provenance import provenance
    from studies.usecases import bearing_single as bs

    if out is not None:                         # before any work: nothing the user has is lost
        check_output_file(Path(out), tuple(Path(p) for p in (bearing_file, loads) if _is_path(p)))
    cfg = load_bearing(Path(bearing_file)) if _is_path(bearing_file) else bearing_file
    cols = table(loads, set(bs.LOAD_COLUMNS), "loads")
    res = bs.solve(cfg, cols, str(loads) if _is_path(loads) else "loads", convention, control,
                   str(bearing_file) if _is_path(bearing_file) else "bearing")
    if out is not None:
        prov = provenance("bearing", {k: Path(v) for k, v in
                                      (("bearing", bearing_file), ("loads", loads)) if _is_path(v)},
                          {"convention": {"name": convention},
                           "raceway_control": {"name": control}})
        bs.write(res, Path(out), prov)
    return res
