"""Every command but `study` and `bench` as a use case: what the command line runs
(studies/app/commands.py parses the flags, calls these and prints) and what `import bearingfem`
offers (the facade wraps them and emits their warnings). One route: the command and its function
are the same call with the same defaults (`studies.usecases.defaults`), so their checks, warnings
and numbers are equal.

Each function takes what its command takes: the assembly (an `Assembly` from `load_assembly`, or
the path of its TOML file), tables as a CSV path (str or Path) or in memory (column name ->
values: a dict of lists or arrays, or a pandas DataFrame; the same columns and checks as the
file), and for the commands that write a folder an optional `out` (None: the files go to a
temporary folder that is removed afterwards; the typed result holds the numbers). Results are
typed (frozen dataclasses) and carry the lines the command prints as warnings (`warning_lines`);
`.to_frame()` gives the table the command writes as CSV, units in the column names (docs/cli.md).

Bad input raises a ValueError subclass (ConfigError, TableError, EffectError, ModelError,
ToleranceError, DesignError, StiffnessRunError, BearingRunError, OutputError, and
`infra.errors.BearingfemError` for the solver's failures, ...) whose message is the one line the
command prints before exiting with code 2; nothing is written then.
"""
from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Mapping

import numpy as np

from studies.usecases import defaults
from studies.usecases.output_folder import check_output_file, output_folder


def _quiet(*_args) -> None:
    """The default progress: nothing (the command line passes its own)."""


def _is_path(x) -> bool:
    return isinstance(x, (str, os.PathLike))


def _assembly(assembly):
    """An `Assembly`: `assembly` itself, or loaded from its path (keeping its file's `Origin`)."""
    from studies.model.config import load_assembly

    return load_assembly(Path(assembly)) if _is_path(assembly) else assembly


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


def _interval_record(lubrication) -> dict:
    """What the friction interval columns of `simulate` and `bearing` are (level, regime, law,
    factors, how obtained, measured leave-one-source-out coverage), for the sidecar JSON
    (`analytic.friction.interval.interval_record`)."""
    from analytic.friction.interval import interval_record, lubrication_interval
    return interval_record(lubrication_interval(lubrication))


def _provenance(command: str, asm=None, assembly=None, effects: dict | None = None,
                **tables) -> dict:
    """`provenance` of a command's inputs: the assembly `asm` as given (`assembly`: its path, or
    the loaded or in-memory `Assembly`; `provenance.assembly_record`), each table as its file or
    as an in-memory table (named, hashed by content), the effects switched on."""
    from studies.model.provenance import assembly_record, provenance

    inputs: dict = {}
    if asm is not None:
        inputs["assembly"] = assembly_record(asm, Path(assembly) if _is_path(assembly) else None)
    for k, v in tables.items():
        if v is not None:
            inputs[k] = (Path(v) if _is_path(v) else
                         {"path": "(in-memory table)", "sha256": _table_sha256(v)})
    return provenance(command, inputs, effects)


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


def _input_warnings(asm, conditions: dict | None) -> tuple[str, ...]:
    """The plausibility warnings of an assembly and a conditions table (None: none given) before
    any model output (`checks.plausibility_warnings`): what `tolerance`, `design` and
    `diagnose` print, as `simulate` and `report` do with their outputs' checks added."""
    from studies.model.checks import plausibility_warnings

    return tuple(plausibility_warnings(asm, conditions))


def _check_workers(workers) -> None:
    from studies.model.table import TableError

    if workers is not None and workers < 1:
        raise TableError(f"workers {workers}: need at least 1")


# --- the commands --------------------------------------------------------------------------------

def warning_lines(result) -> list[str]:
    """The warning lines a command prints for its result (each after `bearingfem COMMAND:
    warning: `), in the order it prints them: the result's `warnings` (plausibility warnings,
    then the summaries of violated limits), and for `stiffness` the ROSS table's. The Python
    API emits the same lines as `BearingfemWarning`s."""
    lines = list(getattr(result, "warnings", ()))
    ross = getattr(result, "ross", None)
    if ross is not None and ross.warning:
        lines.append(ross.warning)
    return lines


def simulate(assembly, conditions, effects: Mapping | None = None, out=None,
             direct: bool = False, workers: int | None = None, scheduler: str | None = None,
             progress=_quiet):
    """`bearingfem simulate ASSEMBLY.toml CONDITIONS.csv -o OUT.csv [--effect NAME:k=v]...
    [--direct] [--workers N | --scheduler ADDRESS]`: the model per row of `conditions` (the
    condition columns of docs/cli.md: `T_ambient_C` and part temperatures `T_<part>_C` in C,
    `speed_rpm`, `preload_assembled_N`, `axial_load_N`, `radial_load_N` in N, `moment_Nmm`,
    `time_s`; in transient mode also `T_sink_C`, `film_scale`, `heat_W`).
    effects: {effect name: {parameter: value}}, as `--effect`.  out: the CSV to write (None:
    nothing written, the table kept in memory).  With a CSV path and `out` the file is streamed
    chunk by chunk as by the command (memory independent of the rows); otherwise the table is
    evaluated in memory, the same chunks through the same `stream.simulate_chunks`.
    Returns `Simulation` (`.warnings` the lines the command prints; `.to_frame()` OUT.csv:
    the condition columns first, then the outputs, flags and margins)."""
    from studies.model import stream
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.model.pipeline import Pipeline
    from studies.model.table import write_table

    _check_workers(workers)
    if out is not None:                         # before any work: nothing the user has is lost
        check_output_file(Path(out), tuple(Path(p) for p in (assembly, conditions) if _is_path(p)))
    asm = _assembly(assembly)
    transient = asm.thermal.mode == "transient"
    if transient:         # part temperatures computed: rows in time order, one route
        from studies.model import transient_route as tr
    allowed = tr.condition_columns() if transient else set(CONDITION_COLUMNS)
    effects = {k: dict(v) for k, v in (effects or {}).items()}
    prov = {**_provenance("simulate", asm, assembly, effects, conditions=conditions),
            "friction_interval": _interval_record(asm.lubrication)}
    streamed = out is not None and _is_path(conditions)     # the command's way
    # all of the table is checked before any FE work (a bad row late in a file included)
    if streamed:
        n_rows = stream.check_conditions(Path(conditions), columns=allowed)
    else:
        cols = table(conditions, allowed, "conditions")
    settings = dict(direct=direct, progress=progress, workers=workers, scheduler=scheduler,
                    pipeline=(Pipeline.shared(asm, progress=progress)
                              if workers is None and scheduler is None else None))
    if streamed:
        run = (tr.simulate_transient_file if transient else stream.simulate_file)(
            asm, Path(conditions), Path(out), effects, provenance=prov, n_rows=n_rows, **settings)
        return Simulation(run, None, Path(out))
    if transient:
        where = str(conditions) if _is_path(conditions) else "conditions"
        run, columns = tr.simulate_transient_columns(asm, cols, where, effects, **settings)
    else:
        run, columns = stream.simulate_columns(asm, cols, effects, **settings)
    if out is not None:
        write_table(Path(out), columns, prov)
    return Simulation(run, columns, None if out is None else Path(out))


@dataclass(frozen=True)
class Simulation:
    """What `simulate` did. run: `stream.SimulateRun` (rows, violated checks, plausibility
    warnings); columns: the output table in memory (None when streamed into `out`); out: the
    file written, or None."""
    run: object
    columns: dict | None = field(repr=False)
    out: Path | None = None

    @property
    def n_rows(self) -> int:
        return self.run.n_rows

    @property
    def violations(self) -> list:
        return self.run.violations

    @property
    def warnings(self) -> tuple[str, ...]:
        """The lines the command prints as warnings: the plausibility warnings, then one
        summary per violated check (`SimulateRun.summaries`)."""
        return (*self.run.warnings, *self.run.summaries())

    def to_frame(self):
        """OUT.csv as a `pandas.DataFrame`: the condition columns, then the outputs (full
        precision; a streamed run's file is read back, its 10 significant digits)."""
        import pandas as pd

        return pd.DataFrame(self.columns) if self.columns is not None else pd.read_csv(self.out)


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

    asm = _assembly(assembly)
    cols = table(measured, measured_columns(OUTPUT_NAMES), "measured")
    where = measured if _is_path(measured) else "measured"
    conditions, meas = split_measured(cols, where)
    stated = measured_noise(cols, meas, noise, where)       # bad input: before any FE work
    warnings = _input_warnings(asm, conditions)
    with _folder(out) as tmp:
        result, doc = diagnose_tables(asm, conditions, meas, tmp, progress=progress,
                                      noise_model=stated)
    return Diagnosis(result, doc, warnings)


@dataclass(frozen=True)
class Diagnosis:
    """A diagnosis: the typed `DiagnosisResult` (`result`) and diagnosis.json as written
    (`json`); `verdict` and `cause` as the command prints them; `warnings` the plausibility
    warnings of the inputs."""
    result: object
    json: dict = field(repr=False)
    warnings: tuple[str, ...] = ()

    @property
    def verdict(self) -> str:
        return self.json["verdict"]

    @property
    def cause(self) -> str | None:
        return self.json.get("cause")


def tolerance(assembly, conditions=None, samples: int = defaults.TOLERANCE_SAMPLES,
              seed: int = defaults.TOLERANCE_SEED, out=None,
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
    asm = _assembly(assembly)
    cond = None if conditions is None else table(conditions, set(CONDITION_COLUMNS), "conditions")
    prov = _provenance("tolerance", asm, assembly, conditions=conditions)
    warnings = _input_warnings(asm, cond)
    with _folder(out) as tmp:
        res = tolerance_report.run(asm, cond, tmp, prov, samples=samples, seed=seed,
                                   progress=progress, workers=workers, scheduler=scheduler,
                                   bar=bar)
    return replace(res, warnings=warnings)


def design(assembly, range_C: tuple[float, float], out=None,
           band: tuple[float, float] = defaults.DESIGN_BAND,
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
    asm = _assembly(assembly)
    vary = {k: tuple(v) for k, v in (vary or {}).items()}
    ds.settings_of(asm, vary)                   # bad values: one line before any work
    warnings = _input_warnings(asm, None)
    with _folder(out) as tmp:
        res = ds.run(asm, T_min, T_max, tmp, _provenance("design", asm, assembly),
                     band=the_band, clamps=clamps, progress=progress, workers=workers,
                     scheduler=scheduler, bar=bar, vary=vary)
    return replace(res, warnings=warnings)


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
    asm = _assembly(assembly)
    cond = table(conditions, set(CONDITION_COLUMNS), "conditions")
    where = str(conditions) if _is_path(conditions) else "conditions"
    res = st.compute(asm, cond, where, per_bearing, ross is not None and ross is not False,
                     progress, free_axial)
    if out is not None:
        ross_out = ross if _is_path(ross) else None
        st.write(res, Path(out), None if ross_out is None else Path(ross_out),
                 _provenance("stiffness", asm, assembly, conditions=conditions))
    return res


def report(assembly, conditions=None, out=None, pdf: bool = False, progress=_quiet,
           command: list[str] | None = None, sensitivity: bool = False):
    """`bearingfem report ASSEMBLY.toml [CONDITIONS.csv] --out DIR [--pdf] [--sensitivity]`:
    report.md and report.html (and report.pdf), margins first (with `sensitivity`: also
    sensitivity.csv).  Returns `assembly_report.ReportRun` (the
    warnings; `.to_frame()` results.csv)."""
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.usecases import assembly_report

    asm = _assembly(assembly)
    cond = None if conditions is None else table(conditions, set(CONDITION_COLUMNS), "conditions")
    prov = _provenance("report", asm, assembly, conditions=conditions)
    with _folder(out) as tmp:
        return assembly_report.run(asm, cond, tmp, prov, progress=progress, pdf=pdf,
                                   command=command, sensitivity=sensitivity)


def verify(out=None, assembly=None, progress=_quiet):
    """`bearingfem verify --out DIR [--assembly ASSEMBLY.toml]`: the verification cases (Lamé,
    mesh convergence of the assembly's stack, manufactured solutions) into verification.md and
    verification.json.  Returns `verify.VerifyRun`."""
    from studies.usecases import verify as vf

    asm = None if assembly is None else _assembly(assembly)
    with _folder(out) as tmp:
        return vf.run(tmp, progress=progress, assembly=asm)


def bearing(bearing_file, loads, out=None, convention: str = defaults.BEARING_CONVENTION,
            control: str = defaults.BEARING_CONTROL):
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
        if cfg.lubrication is not None:
            prov = {**prov, "friction_interval": _interval_record(cfg.lubrication)}
        bs.write(res, Path(out), prov)
    return res
