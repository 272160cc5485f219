"""`bearingfem stiffness ASSEMBLY.toml CONDITIONS.csv -o OUT.csv [--per-bearing] [--free-axial]
[--ross OUT.csv]`: the pair's tangent stiffness at its equilibrium per row of a conditions table
(docs/cli.md "Bearing stiffness").

Per row: the equilibrium by the model's one route (temperatures -> FE -> groove-centre shifts ->
pair, `equilibrium`), then `analytic.bearing.stiffness.pair_stiffness` at it: the 5 x 5 matrix of
the rigid rotor about the pair's centre (mid-point of the ball planes), all 25 entries as
STIFFNESS_COLUMNS after the condition columns (each entry at the other four DOFs held);
--free-axial adds the force-controlled radial stiffness (axial load and moment held,
`analytic.bearing.stiffness.force_controlled`); then the pair's preload (`preload_N`,
`preload_lost`, as `simulate` names them; a row that lost it gets one warning line);
--per-bearing adds each bearing's matrix about its own ball plane (suffix _A, _B).  --ross writes
the coefficients against speed in the table layout of `ross.BearingElement` (ROSS,
`ross-rotordynamics` on PyPI: `BearingElement.from_table` reads these column names; SI units:
frequency in rad/s, stiffness N/m, damping N s/m): one row per distinct speed, sorted, the pair's
lateral stiffness (kxx, kyy, kxy, kyx; ROSS's bearing element has no tilt stiffness: the pair's
k_tx, k_ty and the radial-tilt coupling stay in OUT.csv), no damping (the bearing model is
quasi-static: cxx = cyy = cxy = cyx = 0), and no row that lost its preload (refused).  ROSS
interpolates between the speeds and extrapolates outside their range; the range is stated in the
table's provenance sidecar and on stdout, and fewer than ROSS_MIN_SPEEDS speeds give a warning.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.bearing.state import PairState
from analytic.bearing.stiffness import PairStiffness, force_controlled, pair_stiffness
from studies.model.inputs import PhysicsInputs
from studies.model.pipeline import ModelError, Pipeline, table_inputs
from studies.model.result import SimulationResult
from studies.model.table import TableError, TableWriter, read_conditions

#: the DOFs' short names in the column names, `analytic.bearing.stiffness.DOFS` order
AXES = ("x", "y", "z", "tx", "ty")
#: unit of entry (i, j) by the kinds of DOF i (load) and j (motion), and its factor from the
#: matrix's N, mm, rad: a force per translation N/mm, a force per tilt N/mrad, a moment per
#: translation N mm/mm, a moment per tilt N mm/mrad (docs/cli.md "Bearing stiffness")
_UNITS = {(False, False): ("N_per_mm", 1.0), (False, True): ("N_per_mrad", 1e-3),
          (True, False): ("Nmm_per_mm", 1.0), (True, True): ("Nmm_per_mrad", 1e-3)}
#: the eight names the command wrote before the full matrix (kept as they were)
_FIRST_EIGHT = {
    "k_xx_N_per_mm": (0, 0), "k_yy_N_per_mm": (1, 1), "k_zz_N_per_mm": (2, 2),
    "k_xy_N_per_mm": (0, 1), "k_yx_N_per_mm": (1, 0),
    "k_tx_Nmm_per_mrad": (3, 3), "k_ty_Nmm_per_mrad": (4, 4), "k_x_ty_N_per_mrad": (0, 4),
}


def _stiffness_columns() -> dict[str, tuple[int, int, float]]:
    """Every entry of the 5 x 5 (docs/cli.md "Bearing stiffness"): name -> (row, column of the
    matrix, factor from N, mm, rad).  The first eight names first, then the other seventeen as
    `k_<a>_<b>_<unit>` (a the load, b the motion) row by row."""
    out = {}
    for name, (i, j) in _FIRST_EIGHT.items():
        out[name] = (i, j, _UNITS[(i >= 3, j >= 3)][1])
    held = set(_FIRST_EIGHT.values())
    for i in range(5):
        for j in range(5):
            if (i, j) not in held:
                unit, f = _UNITS[(i >= 3, j >= 3)]
                out[f"k_{AXES[i]}_{AXES[j]}_{unit}"] = (i, j, f)
    return out


#: output columns: name -> (row, column of the 5 x 5 matrix in `analytic.bearing.stiffness.DOFS`
#: order (x, y, z, theta_x, theta_y), factor from N, mm, rad): all 25 entries
STIFFNESS_COLUMNS = _stiffness_columns()
#: --free-axial: the pair's radial stiffness with the axial load and the moment held
CONDENSED_COLUMN = "k_xx_condensed_N_per_mm"
#: the pair's preload beside the stiffness (the names of `simulate`)
PRELOAD_COLUMNS = ("preload_N", "preload_lost")
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
    return solve_rows(pipe, inputs, first_row)[1]


def solve_rows(pipe: Pipeline, inputs: PhysicsInputs,
               first_row: int = 0) -> tuple[Equilibrium, PairStiffness]:
    """The rows' equilibrium (`equilibrium`) and the pair's stiffness at it."""
    eq = equilibrium(pipe, inputs, first_row)
    return eq, pair_stiffness(pipe.geom, pipe.asm.arrangement, eq.pair, **eq.pair_args)


def stiffness_columns(k: PairStiffness, free_axial: bool = False) -> dict[str, np.ndarray]:
    """The pair's output columns of `k` (STIFFNESS_COLUMNS; with free_axial also its
    force-controlled radial stiffness CONDENSED_COLUMN,
    `analytic.bearing.stiffness.force_controlled`)."""
    out = {name: f * k.pair_N_mm_rad[:, i, j] for name, (i, j, f) in STIFFNESS_COLUMNS.items()}
    if free_axial:
        out[CONDENSED_COLUMN] = force_controlled(k.pair_N_mm_rad, 0)
    return out


def bearing_columns(k: PairStiffness) -> dict[str, np.ndarray]:
    """--per-bearing: the 25 entries of each bearing about its ball plane, suffixes _A, _B."""
    return {f"{name}_{J}": f * k.bearing_N_mm_rad[b, :, i, j]
            for b, J in enumerate("AB") for name, (i, j, f) in STIFFNESS_COLUMNS.items()}


def lost_preload_warning(lost: np.ndarray, lines: np.ndarray, where: str) -> str | None:
    """One line when rows have lost the preload (`PairState.preload_lost`: a bearing's axial
    load reached 0), else None."""
    bad = np.flatnonzero(lost)
    if not bad.size:
        return None
    shown = ", ".join(str(int(v)) for v in lines[bad[:5]]) + (", ..." if bad.size > 5 else "")
    return (f"{where}: the pair's preload is lost in {bad.size} of {lost.size} row(s) (line(s) "
            f"{shown}; preload_N 0, a bearing unloaded): the k columns there are the stiffness "
            "of the balls the external loads still press, not of a preloaded pair (all 0 "
            "without loads: the rotor is loose)")
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
    columns), the ROSS table when asked for, and the warning lines."""
    n_rows: int
    ross: RossTable | None
    warnings: tuple[str, ...] = ()
    columns: dict | None = None

    def to_frame(self):
        """OUT.csv's columns as a `pandas.DataFrame` (units in the names)."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def compute(asm, cond: dict, where: str = "conditions", per_bearing: bool = False,
            ross: bool = False, progress=None, free_axial: bool = False) -> StiffnessRun:
    """Solve every row of the conditions `cond` (checked columns: `read_conditions`, or the API's
    in-memory table, whose rows are numbered 1.. where a file's are named by their line; `where`
    names it in errors) and build the output columns (and the ROSS table with `ross`): a row
    that did not converge, or with `ross` a row that lost its preload, is one StiffnessRunError
    or ModelError line naming it (docs/cli.md "Bearing stiffness" argues why); rows that lost
    the preload without `ross`: kept, with preload_N beside the stiffness and one warning line."""
    n = len(next(v for c, v in cond.items() if not c.startswith("_")))
    lines = cond["_line"] if "_line" in cond else np.arange(1, n + 1)
    label = "line" if "_line" in cond else "row"
    pipe = Pipeline.shared(asm, progress=progress)
    cols = {c: v for c, v in cond.items() if not c.startswith("_")}
    parts, speeds, preload, lost = [], [], [], []
    for i0 in range(0, n, CHUNK_ROWS):          # bounded working memory (every ball, every row)
        rows = {c: v[i0:i0 + CHUNK_ROWS] for c, v in cond.items()}
        inputs = table_inputs(asm, rows)
        eq, k = solve_rows(pipe, inputs, i0)
        bad = np.flatnonzero(~k.converged)
        if bad.size:
            raise ModelError(f"{where}: {label} {lines[i0 + bad[0]]}: the balls' state "
                             f"at the equilibrium did not converge")
        parts.append(k)
        speeds.append(np.broadcast_to(inputs.speed_rpm, (min(n - i0, CHUNK_ROWS),)))
        preload.append(eq.pair.preload_N)
        lost.append(eq.pair.preload_lost)
        if progress and n > CHUNK_ROWS:
            progress(f"stiffness: {min(n, i0 + CHUNK_ROWS)} of {n} rows")
    k = PairStiffness(*(np.concatenate([getattr(p, f) for p in parts], axis=ax) for f, ax in
                        (("pair_N_mm_rad", 0), ("bearing_N_mm_rad", 1), ("loads_N_mm", 1),
                         ("converged", 0))))
    lost = np.concatenate(lost)
    speed = np.concatenate(speeds)
    if ross and lost.any():
        i = int(np.flatnonzero(lost)[0])
        raise StiffnessRunError(
            f"{where}: {label} {lines[i]} (speed_rpm {speed[i]:g}): the pair's "
            f"preload is lost ({int(lost.sum())} of {n} rows): --ross exports no such speed (a "
            "pair without preload has a stiffness set by the external loads, 0 without them, "
            "not a function of speed; left out, ROSS would interpolate over it); drop those "
            "rows or run without --ross (OUT.csv has preload_N)")
    cols.update(stiffness_columns(k, free_axial))
    cols.update({PRELOAD_COLUMNS[0]: np.concatenate(preload),
                 PRELOAD_COLUMNS[1]: lost.astype(float)})
    if per_bearing:
        cols.update(bearing_columns(k))
    warnings = tuple(w for w in (lost_preload_warning(lost, lines, where),) if w)
    table = ross_table(k, speed, where) if ross else None
    return StiffnessRun(n, table, warnings, cols)


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
                             "extrapolates outside the interpolated range; every speed has "
                             "its preload (a row that lost it is refused)")})
                with TableWriter(ross_out, side) as wr:
                    wr.write(ross.columns)
    except TableError as exc:
        raise StiffnessRunError(str(exc)) from None


def run(assembly_path: Path, conditions_path: Path, out: Path, per_bearing: bool = False,
        ross_out: Path | None = None, provenance: dict | None = None,
        progress=None, free_axial: bool = False) -> StiffnessRun:
    """The command: read, solve every row (`compute`), then write OUT.csv (and the ROSS table)
    atomically (`write`); nothing is written when any row fails."""
    from studies.model.config import load_assembly

    asm = load_assembly(assembly_path)
    cond = read_conditions(conditions_path)
    res = compute(asm, cond, str(conditions_path), per_bearing, ross_out is not None, progress,
                  free_axial)
    write(res, out, ross_out, provenance)
    return res
