"""bearingfem from Python: the same model as the `bearingfem` command, three lines away.

    import bearingfem
    asm = bearingfem.load_assembly("my_pair.toml")
    out = bearingfem.simulate(asm, {"T_ambient_C": [-40, 20, 80]})

`simulate` returns a `pandas.DataFrame`, one row per condition row and the output columns of
`bearingfem simulate` in its order (docs/cli.md: `torque_Nmm`, `preload_N`, `contact_angle_deg`,
..., then the `flag_*` and `margin_*` checks; units in every name). The typed result behind it
(`studies.model.result.SimulationResult`: FE state, `PairState`, torque components, checks) is
`studies.model.pipeline.simulate_table`. The FE set-up of an assembly is kept for the next call with
an equal assembly (`Pipeline.shared`). BLAS runs single-threaded inside the FE superposition by itself.

Every other command has its function too, the same call the command line makes
(`studies.usecases.api`): `diagnose`, `tolerance`, `design`, `stiffness`, `report`, `verify`,
`bearing`. Each takes what its command takes (paths, or tables in memory: a dict of arrays or a
DataFrame) and returns a typed result, with `.to_frame()` where the command writes a CSV.
"""
from __future__ import annotations

from pathlib import Path
from typing import Mapping

import numpy as np

from infra.version import __version__
from studies.usecases.api import bearing, design, diagnose, report, stiffness, tolerance, verify

__all__ = ["__version__", "load_assembly", "simulate", "diagnose", "tolerance", "design",
           "stiffness", "report", "verify", "bearing"]


def load_assembly(path: str | Path):
    """Read and check an assembly TOML file (`studies.model.config.Assembly`); a problem raises
    `studies.model.config.ConfigError` with the one-line message the command line prints."""
    from studies.model.config import load_assembly as load

    return load(path)


def simulate(assembly, conditions: Mapping, effects: Mapping | None = None):
    """Model outputs per row of `conditions`.

    assembly: an `Assembly` (`load_assembly`) or the path of its TOML file.
    conditions: column name -> values (a dict of lists or arrays, or a pandas DataFrame) with the
        condition columns of docs/cli.md (`T_ambient_C` in C, `speed_rpm`, `preload_assembled_N`,
        `axial_load_N` and `radial_load_N` in N, `moment_Nmm` in N mm, part temperatures
        `T_<part>_C`, `time_s`), all of equal length.
    effects: {effect name: {parameter: value}} switched on, as `simulate --effect`.
    Returns a `pandas.DataFrame` of the output columns (`studies.model.columns.to_columns`),
    units in the names. Bad input raises ValueError subclasses (TableError, EffectError,
    ModelError) with one-line messages naming the column or row.
    """
    import pandas as pd

    from studies.model.columns import to_columns
    from studies.model.inputs import CONDITION_COLUMNS
    from studies.model.pipeline import Pipeline, simulate_table
    from studies.model.table import TableError, check_columns

    if not hasattr(assembly, "bearing"):
        assembly = load_assembly(assembly)
    cols = {str(k): np.asarray(v, float).ravel() for k, v in dict(conditions).items()}
    if not cols:
        raise TableError("conditions: no columns")
    if assembly.thermal.mode == "transient":     # part temperatures computed, rows in time order
        from studies.model.transient_route import TRANSIENT_COLUMNS, run_transient

        if effects:
            raise TableError('effects: not available with [thermal] mode = "transient"')
        check_columns("conditions", cols, allowed=set(CONDITION_COLUMNS) | set(TRANSIENT_COLUMNS))
        return pd.DataFrame(run_transient(Pipeline.shared(assembly), cols).columns())
    check_columns("conditions", cols, allowed=set(CONDITION_COLUMNS))
    result = simulate_table(assembly, cols, dict(effects or {}), pipeline=Pipeline.shared(assembly))
    return pd.DataFrame(to_columns(result, friction_split=True))
