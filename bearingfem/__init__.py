"""bearingfem from Python: the `bearingfem` command's use cases, three lines away.

    import bearingfem
    asm = bearingfem.load_assembly("my_pair.toml")
    out = bearingfem.simulate(asm, {"T_ambient_C": [-40, 20, 80]})     # or a CSV path

Each function is the use case its command calls (`studies.usecases.api`; the command line only
parses flags and prints), so the same checks run and the same call gives the same numbers, the
defaults included (`studies.usecases.defaults`): `simulate`, `diagnose`, `tolerance`, `design`,
`stiffness`, `report`, `verify`, `bearing`. `study` and `bench` have no function (a study is a
script of its own, `studies.validation`; a benchmark prints timings of a whole process).

- Inputs: what the command takes. The assembly as an `Assembly` (`load_assembly`, which keeps its
  file's path, SHA-256 and comments: a report of it lists them as its sources) or the path of its
  TOML file; tables as a CSV path (str or Path) or in memory (column name -> values: a dict of
  lists or arrays, or a pandas DataFrame), checked as the file is.
- Warnings: each line the command prints as `bearingfem COMMAND: warning: LINE` (Fahrenheit in a
  Celsius column, a contact angle in radians, no `T_ambient_C`, a viscosity law far outside its
  fit, an oil-bath f0, one summary per violated limit) is a Python warning of category
  `BearingfemWarning` with the text LINE, and stays on the result: `DataFrame.attrs["warnings"]`
  for `simulate`, the typed result's `warnings` otherwise.
- Errors: bad or unworkable input (a malformed table, a fit the contact solver cannot settle)
  raises a ValueError subclass, `BearingfemError` for the solver's failures, whose message is the
  one line the command prints before exiting with code 2; nothing is written then.
- Results: `simulate` returns a `pandas.DataFrame` (the condition columns first, then the output,
  flag and margin columns of docs/cli.md in the order of OUT.csv); the others a typed result with
  `.to_frame()` where the command writes a CSV. The FE set-up of an assembly is kept for the next
  call with an equal assembly (`Pipeline.shared`).
"""
from __future__ import annotations

import functools
from pathlib import Path
from typing import Mapping

from infra.errors import BearingfemError, BearingfemWarning, emit
from infra.version import __version__
from studies.usecases import api

__all__ = ["__version__", "BearingfemError", "BearingfemWarning", "load_assembly", "simulate",
           "diagnose", "tolerance", "design", "stiffness", "report", "verify", "bearing"]


def load_assembly(path: str | Path):
    """Read and check an assembly TOML file (`studies.model.config.Assembly`, carrying its file's
    `Origin`); a problem raises `studies.model.config.ConfigError` (a ValueError) with the
    one-line message the command line prints."""
    from studies.model.config import load_assembly as load

    return load(path)


def simulate(assembly, conditions, effects: Mapping | None = None, out=None,
             direct: bool = False, workers: int | None = None, scheduler: str | None = None):
    """Model outputs per row of `conditions`: `bearingfem simulate` (`studies.usecases.api.simulate`).

    assembly: an `Assembly` (`load_assembly`) or the path of its TOML file.
    conditions: a CSV path, or column name -> values (a dict of lists or arrays, or a pandas
        DataFrame) with the condition columns of docs/cli.md (`T_ambient_C` in C, `speed_rpm`,
        `preload_assembled_N`, `axial_load_N` and `radial_load_N` in N, `moment_Nmm` in N mm,
        part temperatures `T_<part>_C`, `time_s`), all of equal length.
    effects: {effect name: {parameter: value}} switched on, as `simulate --effect`.
    out: also write OUT.csv (and its provenance sidecar) there.
    Returns a `pandas.DataFrame`: the condition columns, then the output columns
    (`studies.model.columns.to_columns`), units in the names; `.attrs["warnings"]` the command's
    warning lines, each also emitted as a `BearingfemWarning`. Bad input raises ValueError
    subclasses (TableError, EffectError, ModelError, BearingfemError) with one-line messages
    naming the column or row.
    """
    res = api.simulate(assembly, conditions, effects, out, direct=direct, workers=workers,
                       scheduler=scheduler)
    frame = res.to_frame()
    frame.attrs["warnings"] = list(res.warnings)
    emit(res.warnings)
    return frame


def _warned(use_case):
    """The use case `use_case` whose result's warning lines (`api.warning_lines`) are emitted as
    `BearingfemWarning`s (the result keeps them)."""
    @functools.wraps(use_case)
    def function(*args, **kwargs):
        result = use_case(*args, **kwargs)
        emit(api.warning_lines(result))
        return result
    return function


diagnose = _warned(api.diagnose)
tolerance = _warned(api.tolerance)
design = _warned(api.design)
stiffness = _warned(api.stiffness)
report = _warned(api.report)
verify = _warned(api.verify)
bearing = _warned(api.bearing)
