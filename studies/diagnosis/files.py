"""`bearingfem diagnose`: the real model behind the diagnosis engine.

The measured CSV holds condition columns (spec) and output columns the model predicts; every
output column present in both is compared. The baseline is allowed one nuisance calibration a
user would accept: a scale on the friction coefficient (`mu_scale`, 0.3..3), because the film or
traction coefficient of a real bearing is never known to better than that. Every listed effect is
a candidate (those whose required conditions are missing are reported as not applicable).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from studies.model.config import load_assembly
from studies.diagnosis.engine import diagnose_full
from studies.diagnosis.ladder import FormRoute
from studies.diagnosis.noisemodel import SIGMA_PREFIX, check_sigma_columns, stated_noise
from studies.diagnosis.ladder import candidates as ladder_candidates
from studies.diagnosis.report import write_report
from studies.diagnosis.result import DiagnosisResult, to_json
from studies.model.effects import (EFFECTS, ORDER, apply_effects, assembly_bounds,
                                   resolve_friction_coefficient)
from studies.model.inputs import CONDITION_COLUMNS, baseline_inputs
from studies.model.parallel import available_workers
from studies.model.pipeline import Pipeline
from studies.model.checks import CHECK_COLUMNS
from studies.model.columns import FRICTION_SPLIT_HEAT, FRICTION_SPLIT_TORQUE, INTERVAL_COLUMNS
from studies.model.table import TableError, read_table, write_table

#: output columns `diagnose` can compare (what `simulate` writes and a rig can measure)
COMPARABLE = ("torque_Nmm", "preload_N", "contact_angle_deg", "interference_inner_um",
              "interference_outer_um", "fit_pressure_inner_MPa", "fit_pressure_outer_MPa",
              "max_contact_pressure_MPa", "axial_stiffness_N_per_um")
NUISANCE = {"mu_scale": (0.3, 3.0, 1.0, 0.05)}
NUISANCE_TEXT = "mu_scale: scale on the friction coefficient (0.3..3)"
#: every column `simulate` may write besides the comparable ones (accepted, not compared)
OUTPUT_NAMES = {
    "torque_hysteresis_Nmm", "torque_differential_Nmm", "torque_spin_Nmm", "torque_inner_contacts_Nmm",
    "torque_outer_contacts_Nmm", "torque_A_Nmm", "torque_B_Nmm", "torque_load_Nmm",
    "torque_viscous_Nmm", "viscosity_mm2_s", "heat_W", "fit_pressure_inner_A_MPa",
    "fit_pressure_inner_B_MPa", "fit_pressure_outer_A_MPa", "fit_pressure_outer_B_MPa",
    "fit_pressure_inner_lame_MPa", "fit_pressure_inner_lame_plane_strain_MPa",
    "fit_pressure_outer_lame_MPa", "fit_pressure_outer_lame_plane_strain_MPa",
    "raceway_u_r_inner_A_um", "raceway_u_r_inner_A_lame_um", "groove_shift_dr_A_um",
    "groove_shift_dz_A_um", "groove_shift_dr_B_um", "groove_shift_dz_B_um", "axial_force_A_N",
    "axial_force_B_N", "contact_angle_A_deg", "contact_angle_B_deg", "ball_load_A_N",
    "ball_load_B_N", "preload_lost", "friction_coefficient", "static_safety",
    "land_margin_inner_deg", "land_margin_outer_deg", "radial_displacement_um", "tilt_mrad",
    "radial_force_A_N", "radial_force_B_N", "max_contact_pressure_A_MPa",
    "max_contact_pressure_B_MPa", "contact_angle_outer_A_deg", "contact_angle_outer_B_deg",
    "ball_load_outer_A_N", "ball_load_outer_B_N", "centrifugal_force_N",
    "gyroscopic_moment_Nmm"} | CHECK_COLUMNS | {*FRICTION_SPLIT_TORQUE, *FRICTION_SPLIT_HEAT,
                                    *INTERVAL_COLUMNS}


class ModelPredictor:
    """predict(effects, nuisance) on fixed conditions, with the pipeline built once."""

    def __init__(self, pipeline: Pipeline, conditions: dict[str, np.ndarray], columns):
        self.pl, self.columns = pipeline, tuple(columns)
        self.conditions = conditions
        a = pipeline.asm
        n = len(next(iter(conditions.values())))
        self.base = baseline_inputs(conditions, n, a.T_ref_C, a.preload.assembled_N,
                                    a.lubrication.speed_rpm)
        self.calls = 0
        self.forms = FormRoute(pipeline)        # the model-form ladder's rungs (ladder.py)

    def inputs(self, effects, nuisance, base=None):
        a = self.pl.asm
        listed, forms = self.forms.split(effects)
        inp = self.forms.apply_inputs(apply_effects(base or self.base, listed, a.T_ref_C), forms)
        scale = float((nuisance or {}).get("mu_scale", 1.0))
        mu0 = a.lubrication.friction_coefficient
        mu = resolve_friction_coefficient(inp, mu0) * scale
        return inp.copy(friction_coefficient=mu - mu0)

    def __call__(self, effects, nuisance):
        self.calls += 1
        return self.forms.columns(self.inputs(effects, nuisance), self.forms.split(effects)[1],
                                  self.columns)

    def at(self, effects, nuisance, conditions):
        a = self.pl.asm
        n = len(next(iter(conditions.values())))
        base = baseline_inputs(conditions, n, a.T_ref_C, a.preload.assembled_N, a.lubrication.speed_rpm)
        return self.forms.columns(self.inputs(effects, nuisance, base),
                                  self.forms.split(effects)[1], self.columns)


def read_measured(path: Path, known_outputs: set[str] | None = None) -> tuple[dict, dict]:
    """Conditions and measured outputs from one CSV; one-line errors. Columns the model writes but
    `diagnose` does not compare (e.g. a `simulate` file's extra outputs) are allowed and ignored."""
    return split_measured(read_table(path, allowed=measured_columns(known_outputs)), path)


def measured_columns(known_outputs: set[str] | None = None) -> set[str]:
    """The columns a measured table may hold: conditions, comparable outputs, their per-row
    standard uncertainties `sigma_<column>` (`noisemodel`), `known_outputs`."""
    return (set(CONDITION_COLUMNS) | set(COMPARABLE) | {SIGMA_PREFIX + c for c in COMPARABLE}
            | set(known_outputs or ()))


def measured_noise(cols: dict, measured: dict, noise, where) -> dict:
    """The stated noise of a checked measured table's compared columns ({column:
    `noisemodel.StatedNoise`}): the `sigma_<column>` columns of `cols` (`check_sigma_columns`)
    and `noise` ({column: "REL%[+ABS]" or ABS}, `diagnose --noise`); one-line NoiseSpecError
    (a TableError) naming the flag or the table, its line and column."""
    sig = check_sigma_columns(cols, measured, where)
    return stated_noise(noise, tuple(measured), sig, where)


def split_measured(cols: dict, where) -> tuple[dict, dict]:
    """A checked measured table (`read_table`, or an in-memory table through `check_columns`;
    `where` names it in errors) -> (conditions, measured outputs)."""
    measured = {c: cols[c] for c in COMPARABLE if c in cols}
    if not measured:
        raise TableError(f"{where}: no output column to compare (need one of {', '.join(COMPARABLE)})")
    conditions = {c: cols[c] for c in CONDITION_COLUMNS if c in cols}
    if not conditions:
        raise TableError(f"{where}: no condition column (need e.g. T_ambient_C or time_s)")
    n = len(next(iter(measured.values())))
    if n < 8:
        raise TableError(f"{where}: {n} rows: too few to diagnose (need at least 8)")
    return conditions, measured


def candidate_effects(asm) -> list:
    """Every listed effect as this assembly sees it: bounds narrowed to what it allows
    (`assembly_bounds`), its configured speed and lubrication (`Effect.for_assembly`)."""
    limits = assembly_bounds(asm)
    return [EFFECTS[name].with_bounds(**limits.get(name, {})).for_assembly(asm) for name in ORDER]


def diagnose_files(assembly_path: Path, measured_path: Path, out_dir: Path, progress=print,
                   pipeline: Pipeline | None = None, workers: int | None = None,
                   noise=None) -> dict:
    """`bearingfem diagnose`: diagnosis.json and the report in `out_dir`; returns the JSON.
    noise: {column: "REL%[+ABS]"} (`--noise`)."""
    asm = load_assembly(assembly_path)
    cols = read_table(measured_path, allowed=measured_columns(OUTPUT_NAMES))
    conditions, measured = split_measured(cols, measured_path)     # before the FE is built
    stated = measured_noise(cols, measured, noise, measured_path)
    return diagnose_tables(asm, conditions, measured, out_dir, progress, pipeline, workers,
                           noise_model=stated)[1]


def diagnose_tables(asm, conditions: dict, measured: dict, out_dir: Path, progress=print,
                    pipeline: Pipeline | None = None, workers: int | None = None,
                    noise_model: dict | None = None) -> tuple[DiagnosisResult, dict]:
    """The diagnosis of checked tables (`split_measured`): diagnosis.json and the report in
    `out_dir`; returns the typed result and the JSON written. workers: processes for the
    candidates' work (`diagnose_full`) and the report's plots (default every CPU this process
    may use); the result does not depend on it. noise_model: the stated noise of some columns
    (`measured_noise`)."""
    pl = pipeline or Pipeline.shared(asm, progress=progress)
    predict = ModelPredictor(pl, conditions, measured.keys())
    candidates = candidate_effects(asm) + ladder_candidates(asm)    # the model-form ladder last
    progress(f"diagnosing {len(next(iter(measured.values())))} rows, columns "
             f"{', '.join(measured)}, {len(candidates)} candidate effects ...")
    workers = available_workers() if workers is None else workers
    result = diagnose_full(predict, measured, conditions, candidates, NUISANCE,
                           T_ref_C=asm.T_ref_C, predict_at=predict.at, workers=workers,
                           noise_model=noise_model)
    doc = write_diagnosis_json(result, out_dir / "diagnosis.json")
    write_table(out_dir / "diagnosis.csv", diagnosis_columns(result, measured))
    write_report(result, conditions, measured, out_dir, workers=workers)
    return result, doc


def diagnosis_columns(result: DiagnosisResult, measured) -> dict[str, np.ndarray]:
    """The columns of diagnosis.csv, one row per measured row (docs/cli.md): `row` (1-based, as
    in the file), `heldout_block` (1-based), then per compared column the measured value
    `<column>`, the calibrated baseline `baseline_<column>`, the extended model
    `predicted_<column>` (the baseline's when nothing is claimed) and its predictive interval
    `predicted_lo_<column>` / `predicted_hi_<column>` (`studies.diagnosis.interval`, level
    `interval.level` in diagnosis.json: the claimed model's for `explained` /
    `explained_partly`, else the configured model's with the discrepancy the data show;
    empty where the column is not measured)."""
    n = result.n_rows
    out = {"row": np.arange(1, n + 1, dtype=float)}
    if result.row_blocks is not None:
        out["heldout_block"] = np.asarray(result.row_blocks, float) + 1.0
    for c in result.columns:
        out[c] = np.asarray(measured[c], float)
        out[f"baseline_{c}"] = np.asarray(result.baseline_pred[c], float)
        out[f"predicted_{c}"] = np.asarray(result.extended_pred[c], float)
        if result.interval is not None:
            out[f"predicted_lo_{c}"] = result.interval.columns[c].lo
            out[f"predicted_hi_{c}"] = result.interval.columns[c].hi
    return out


def write_diagnosis_json(result: DiagnosisResult, path: Path) -> dict:
    """diagnosis.json from the typed result (`studies.diagnosis.result.to_json`, the keys of
    docs/cli.md), with the nuisance calibration `diagnose` allows and the model calls (the
    workers' included); returns what it wrote."""
    doc = to_json(result)
    doc["nuisance_calibration"] = NUISANCE_TEXT
    doc["model_calls"] = doc["n_predict_calls"]
    path.write_text(json.dumps(doc, indent=2))
    return doc
