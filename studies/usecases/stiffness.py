"""`bearingfem stiffness ASSEMBLY.toml CONDITIONS.csv -o OUT.csv [--per-bearing] [--ross OUT.csv]`:
the pair's tangent stiffness at its equilibrium per row of a conditions table (docs/cli.md
"stiffness"; shared/spec/cli.md).

Per row: the equilibrium by the model's one route (temperatures -> FE -> groove-centre shifts ->
pair, `equilibrium`), then `analytic.bearing.stiffness.pair_stiffness` at it: the 5 x 5 matrix of
the rigid rotor about the pair's centre (mid-point of the ball planes), columns STIFFNESS_COLUMNS
after the condition columns; --per-bearing adds each bearing's matrix about its own ball plane
(suffix _A, _B).  --ross writes the coefficients against speed in the table layout of
`ross.BearingElement` (ROSS, `ross-rotordynamics` on PyPI: `BearingElement.from_table` reads
these column names; SI units: frequency in rad/s, stiffness N/m, damping N s/m): one row per
distinct speed, sorted, the pair's lateral stiffness (kxx, kyy, kxy, kyx; ROSS's bearing element
has no tilt stiffness: the pair's k_tx, k_ty and the radial-tilt coupling stay in OUT.csv), no
damping (the bearing model is quasi-static: cxx = cyy = cxy = cyx = 0).  ROSS interpolates
between the speeds and extrapolates outside their range; the range is stated in the table's
provenance sidecar and on stdout, and fewer than ROSS_MIN_SPEEDS speeds give a warning.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.bearing.state import PairState
from analytic.bearing.stiffness import PairStiffness, pair_stiffness
from studies.model.inputs import PhysicsInputs
from studies.model.pipeline import ModelError, Pipeline, table_inputs
from studies.model.result import SimulationResult
from studies.model.table import TableError, TableWriter, read_conditions

#: output columns (shared/spec/cli.md "stiffness"): name -> (row, column of the 5 x 5 matrix in
#: `analytic.bearing.stiffness.DOFS` order (x, y, z, theta_x, theta_y), factor from N, mm, rad)
STIFFNESS_COLUMNS = {
    "k_xx_N_per_mm": (0, 0, 1.0), "k_yy_N_per_mm": (1, 1, 1.0), "k_zz_N_per_mm": (2, 2, 1.0),
    "k_xy_N_per_mm": (0, 1, 1.0), "k_yx_N_per_mm": (1, 0, 1.0),
    "k_tx_Nmm_per_mrad": (3, 3, 1e-3), "k_ty_Nmm_per_mrad": (4, 4, 1e-3),
    "k_x_ty_N_per_mrad": (0, 4, 1e-3),
}
#: ROSS's bearing table: column -> (row, column of the matrix); stiffness N/mm -> N/m
ROSS_STIFFNESS = {"kxx": (0, 0), "kyy": (1, 1), "kxy": (0, 1), "kyx": (1, 0)}
ROSS_DAMPING = ("cxx", "cyy", "cxy", "cyx")
#: fewer speeds than this in a ROSS table: a warning (ROSS fits a spline through >= 4 points and
#: extrapolates; the issue asks for at least 5)
ROSS_MIN_SPEEDS = 5
RPM_TO_RAD_S = 2.0 * np.pi / 60.0
#: rows evaluated together (every ball of every row is held at once: about 0.1 MB per row with
#: quasi-dynamic balls)
CHUNK_ROWS = 2048


class StiffnessRunError(ValueError):
    """Bad input for the command: one line, exit 2."""


@dataclass(frozen=True)
class Equilibrium:
    """The pair's equilibrium at the rows and what it was solved with."""
    result: SimulationResult     # the model's result at the rows (`Pipeline.run`)
    pair: PairState
    pair_args: dict              # keyword arguments of `analytic.bearing.solve_pair`


def equilibrium(pipe: Pipeline, inputs: PhysicsInputs, first_row: int = 0) -> Equilibrium:
    """The one call into the model's route (FE at the rows' and assembly states -> groove-centre
    shifts -> pair equilibrium), and the solver arguments it used (the FE answers are the
    pipeline's remembered ones, so the same arrays).  first_row: the 0-based table row the
    inputs start at (rows named in errors)."""
    result = pipe.run(inputs, first_row=first_row)
    args = pipe.pair_arguments(inputs, result.fe, result.fe_ref)
    return Equilibrium(result, result.pair, args)


def stiffness_at(pipe: Pipeline, inputs: PhysicsInputs, first_row: int = 0) -> PairStiffness:
    """`PairStiffness` of the pair at its equilibrium for the rows' inputs (`equilibrium`)."""
    eq = equilibrium(pipe, inputs, first_row)
    return pair_stiffness(pipe.geom, pipe.asm.arrangement, eq.pair, **eq.pair_args)


def stiffness_columns(k: PairStiffness, per_bearing: bool = False) -> dict[str, np.ndarray]:
    """The output columns of `k` (STIFFNESS_COLUMNS; with per_bearing the same of each bearing
    about its ball plane, suffixes _A and _B)."""
    out = {name: f * k.pair_N_mm_rad[:, i, j] for name, (i, j, f) in STIFFNESS_COLUMNS.items()}
    if per_bearing:
        for b, J in enumerate("AB"):
            out.update({f"{name}_{J}": f * k.bearing_N_mm_rad[b, :, i, j]
                        for name, (i, j, f) in STIFFNESS_COLUMNS.items()})
    return out


@dataclass(frozen=True)
class RossTable:
    """ROSS's bearing coefficient table: columns in SI, and the speed range it covers."""
    columns: dict[str, np.ndarray]
    speeds_rpm: np.ndarray

    @property
    def warning(self) -> str | None:
        n = self.speeds_rpm.size
        if n >= ROSS_MIN_SPEEDS:
            return None
        return (f"the ROSS table has {n} speed(s); ROSS interpolates the coefficients over speed "
                f"and extrapolates outside {self.range_text}: give at least {ROSS_MIN_SPEEDS} "
                "speeds (rows with distinct speed_rpm)")

    @property
    def range_text(self) -> str:
        return f"{self.speeds_rpm.min():g}..{self.speeds_rpm.max():g} rpm"

    def to_frame(self):
        """The table as a `pandas.DataFrame` (`ross.BearingElement.from_table` reads its names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def ross_table(k: PairStiffness, speed_rpm: np.ndarray, where: str = "conditions") -> RossTable:
    """One row per speed, sorted (a ROSS table is a function of speed): rows with equal speeds
    are refused (StiffnessRunError naming them: the table would be ambiguous)."""
    speed = np.asarray(speed_rpm, float)
    order = np.argsort(speed, kind="stable")
    s = speed[order]
    dup = np.flatnonzero(np.diff(s) == 0.0)
    if dup.size:
        i, j = sorted((int(order[dup[0]]), int(order[dup[0] + 1])))
        raise StiffnessRunError(
            f"{where}: rows {i + 1} and {j + 1} have the same speed_rpm {s[dup[0]]:g}; --ross "
            "writes one row per speed (one temperature and load state per speed)")
    K = k.pair_N_mm_rad[order]
    cols = {"frequency": s * RPM_TO_RAD_S}
    cols.update({name: 1e3 * K[:, i, j] for name, (i, j) in ROSS_STIFFNESS.items()})
    cols.update({name: np.zeros(s.size) for name in ROSS_DAMPING})
    return RossTable(cols, s)


@dataclass(frozen=True)
class StiffnessRun:
    """What `stiffness` computed: the output table (condition columns, then the stiffness
    columns) and the ROSS table when asked for."""
    n_rows: int
    ross: RossTable | None
    columns: dict | None = None

    def to_frame(self):
        """OUT.csv's columns as a `pandas.DataFrame` (units in the names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def _line(rows: dict, i: int) -> str:
    """Row i of a chunk as the user knows it: the file's line, or the table's 1-based row."""
    return f"line {rows['_line'][i]}" if "_line" in rows else f"row {int(rows['_row'][i]) + 1}"


def compute(asm, cond: dict, where: str = "conditions", per_bearing: bool = False,
            ross: bool = False, progress=None) -> StiffnessRun:
    """Solve every row of the conditions `cond` (checked columns: `read_conditions`, or the API's
    in-memory table; `where` names it in errors) and build the output columns (and the ROSS
    table with `ross`)."""
    n = len(next(v for c, v in cond.items() if not c.startswith("_")))
    pipe = Pipeline.shared(asm, progress=progress)
    cols = {c: v for c, v in cond.items() if not c.startswith("_")}
    if "_line" not in cond:
        cond = dict(cond, _row=np.arange(n))
    parts, speeds = [], []
    for i0 in range(0, n, CHUNK_ROWS):          # bounded working memory (every ball, every row)
        rows = {c: v[i0:i0 + CHUNK_ROWS] for c, v in cond.items()}
        inputs = table_inputs(asm, rows)
        k = stiffness_at(pipe, inputs, i0)
        bad = np.flatnonzero(~k.converged)
        if bad.size:
            raise ModelError(f"{where}: {_line(rows, bad[0])}: the balls' state "
                             f"at the equilibrium did not converge")
        parts.append(k)
        speeds.append(np.broadcast_to(inputs.speed_rpm, (min(n - i0, CHUNK_ROWS),)))
        if progress and n > CHUNK_ROWS:
            progress(f"stiffness: {min(n, i0 + CHUNK_ROWS)} of {n} rows")
    k = PairStiffness(*(np.concatenate([getattr(p, f) for p in parts], axis=ax) for f, ax in
                        (("pair_N_mm_rad", 0), ("bearing_N_mm_rad", 1), ("loads_N_mm", 1),
                         ("converged", 0))))
    cols.update(stiffness_columns(k, per_bearing))
    table = ross_table(k, np.concatenate(speeds), where) if ross else None
    return StiffnessRun(n, table, cols)


def write(res: StiffnessRun, out: Path, ross_out: Path | None = None,
          provenance: dict | None = None) -> None:
    """OUT.csv (and the ROSS table) atomically, each with its provenance sidecar."""
    try:
        with TableWriter(out, provenance) as w:
            w.write(res.columns)
            if ross_out is not None and res.ross is not None:
                ross = res.ross
                side = dict(provenance or {}, ross={
                    "speeds_rpm": ross.speeds_rpm.tolist(),
                    "interpolated_range_rpm": [float(ross.speeds_rpm.min()),
                                               float(ross.speeds_rpm.max())],
                    "note": ("ROSS BearingElement coefficients of the pair at its centre (SI: "
                             "frequency rad/s, k N/m, c N s/m; no damping modelled); ROSS "
                             "extrapolates outside the interpolated range")})
                with TableWriter(ross_out, side) as wr:
                    wr.write(ross.columns)
    except TableError as exc:
        raise StiffnessRunError(str(exc)) from None


def run(assembly_path: Path, conditions_path: Path, out: Path, per_bearing: bool = False,
        ross_out: Path | None = None, provenance: dict | None = None,
        progress=None) -> StiffnessRun:
    """The command: read, solve every row, then write OUT.csv (and the ROSS table) atomically;
    nothing is written when any row fails."""
    from studies.model.config import load_assembly

    asm = load_assembly(assembly_path)
    cond = read_conditions(conditions_path)
    res = compute(asm, cond, str(conditions_path), per_bearing, ross_out is not None, progress)
    write(res, out, ross_out, provenance)
    return res
