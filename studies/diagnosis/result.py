"""The typed result of one diagnosis (`DiagnosisResult`) and its JSON form.

The engine returns a `DiagnosisResult`; the report reads it by attribute. `to_json` turns it into
the content of `diagnosis.json` (keys of docs/cli.md first, then the diagnostics) and is the only
place that knows the file's keys; `studies.diagnosis.files.write_diagnosis_json` writes it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from studies.diagnosis.candidate import Candidate
from studies.diagnosis.noisemodel import CONSISTENCY_ALPHA
from studies.diagnosis.core import JointFit, Residuals, jsonable
from studies.diagnosis.generalised import FormEntry
from studies.diagnosis.goodness import AtBound, GoodnessOfFit, Left
from studies.diagnosis.heldout import WorseColumn
from studies.diagnosis.interval import Intervals
from studies.diagnosis.openworld import OpenWorld
from studies.diagnosis.problem import Noise
from studies.diagnosis.selection import AcceptedCause

#: how the held-out gain is measured (the `heldout.method` text of the file)
HELDOUT_METHOD = ("contiguous blocks; parameters refitted on the other blocks (one Gauss-Newton "
                  "step from the full fit; a profiled threshold re-selected over its grid, then "
                  "all parameters refitted by nonlinear least squares); paired block bootstrap "
                  "of the RMSE difference over the blocks that can test the effect")


@dataclass
class ModelRmse:
    """In-sample and held-out RMSE per compared column (column units) of one model."""
    rmse: dict[str, float]
    heldout_rmse: dict[str, float]


@dataclass(frozen=True)
class ColumnEvidence:
    """The verdict's evidence in one compared column: the baseline's misfit (in-sample RMS in
    noise units), the extended model's held-out RMSE ratio (extended / baseline) and held-out
    gain (baseline minus extended held-out RMSE, noise units), its in-sample chi-square drop
    (standardised residuals) and that drop's share over the columns."""
    baseline_misfit_sigma: float
    heldout_rmse_ratio: float
    heldout_gain_sigma: float
    chi2_drop: float
    chi2_drop_share: float


@dataclass
class NuisanceFit:
    """The nuisance calibration: bounds, fitted with the baseline and with the extended model."""
    names: list[str]
    bounds: dict[str, tuple[float, float]]
    baseline: dict[str, float]
    extended: dict[str, float]


@dataclass
class BestPartial:
    """An unexplained verdict's best candidate (it passes but leaves structure)."""
    effect: str
    parameters: dict[str, float]
    residuals: Residuals


@dataclass
class Cost:
    """Model calls and wall seconds (total and in model calls), per phase."""
    n_predict_calls: int
    calls_by_phase: dict[str, int]
    seconds_total: float
    seconds_predict: float
    seconds_by_phase: dict[str, dict[str, float]]


@dataclass
class DiagnosisResult:
    """One diagnosis (verdicts and keys: docs/cli.md; method: `studies.diagnosis.engine`)."""
    verdict: str        # no_discrepancy | explained | explained_partly | ambiguous | unexplained
    cause: str | None
    parameters: dict[str, float]    # the cause's fitted parameters (effect units)
    parameter_uncertainty: dict     # standard uncertainty, None, or {"interval": [a, b]}
    indistinguishable: list[str]
    separating_test: str | None
    baseline: ModelRmse
    extended: ModelRmse
    heldout_rmse_ratio: dict[str, float]    # extended / baseline held-out RMSE per column
    heldout_rmse_ratio_first: float         # the same of the first column (the old scalar)
    decisive_column: str                    # the largest baseline misfit in noise units
    evidence: dict[str, ColumnEvidence]     # per column
    candidates: list[Candidate]     # fitted first (passing, then by delta BIC), then the rest
    extended_form: FormEntry | None     # the generalised form that explains the data
    generalised_forms: list[FormEntry]
    reasons: list[str]
    columns: list[str]
    noise: Noise
    nuisance: NuisanceFit
    residuals_baseline: Residuals   # `Problem.describe` of the baseline residuals
    residuals_extended: Residuals | None
    baseline_structure: bool
    best_partial: BestPartial | None
    lookalike: dict[str, dict[str, float]]
    joint_fits: dict[str, JointFit]
    separating_tests: list[dict]
    heldout_blocks: int
    heldout_untestable: list[dict]
    thresholds: dict[str, float]
    notes: list[str]
    spikes: dict[str, list[int]]
    n_rows: int
    cost: Cost
    open_world: OpenWorld | None
    # forward selection and goodness of fit (`studies.diagnosis.selection`, `goodness`)
    causes: list[AcceptedCause] = field(default_factory=list)
    left: list[Left] = field(default_factory=list)
    at_bound: list[AtBound] = field(default_factory=list)
    #: candidates the claim rules stopped because they make a column worse
    worse_columns: list[WorseColumn] = field(default_factory=list)
    #: the claimed model's predictive intervals (None unless explained / explained_partly)
    interval: Intervals | None = None
    goodness: GoodnessOfFit | None = None
    noise_final: Noise | None = None    # the noise model of the selection's last pass
    #: per compared column, the smallest change the data could show and the change the
    #: configured model leaves (`studies.diagnosis.detection`, noise units)
    detection: dict = field(default_factory=dict)
    # the predictions (column arrays) behind the report's plots; not part of the file
    baseline_pred: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    extended_pred: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    candidate_preds: dict[str, dict[str, np.ndarray]] = field(default_factory=dict, repr=False)
    #: held-out block of each row (0-based; diagnosis.csv)
    row_blocks: np.ndarray | None = field(default=None, repr=False)

    @property
    def not_identifiable(self) -> dict[str, str]:
        """Candidates these data cannot test, with the reason."""
        return {c.effect: c.reason for c in self.candidates
                if c.status in ("not_identifiable", "not_applicable")}

    def noise_sigma(self, column: str) -> float:
        return self.noise.sigma[column]


def to_json(r: DiagnosisResult) -> dict:
    """The content of diagnosis.json (JSON values only): docs/cli.md's keys first."""
    out = {
        "verdict": r.verdict,
        "cause": r.cause,
        "parameters": r.parameters,
        "indistinguishable": list(r.indistinguishable),
        "separating_test": r.separating_test,
        "baseline": {"rmse": r.baseline.rmse, "heldout_rmse": r.baseline.heldout_rmse},
        "extended": {"rmse": r.extended.rmse, "heldout_rmse": r.extended.heldout_rmse},
        "gain": {"heldout_rmse_ratio": dict(r.heldout_rmse_ratio),
                 "decisive_column": r.decisive_column,
                 "heldout_rmse_ratio_first": float(r.heldout_rmse_ratio_first)},
        "candidates": [c.to_json() for c in r.candidates],
        "left": r.left,
        "at_bound": r.at_bound,
        "worse_columns": [{"effect": w.effect, "column": w.column, "gain": w.gain,
                           "difference_sigma": -w.difference.rmse_gain,
                           "interval_sigma": [-w.difference.ci[1], -w.difference.ci[0]],
                           "text": w.text} for w in r.worse_columns],
        "interval": None if r.interval is None else r.interval.to_json(),
        "causes": r.causes,
        "detection": {c: d.to_json() for c, d in r.detection.items()},
        # ---- extras
        "evidence": r.evidence,
        "goodness_of_fit": r.goodness,
        "noise_final": (None if r.noise_final is None else
                        {"sigma": dict(r.noise_final.sigma), "ar1": dict(r.noise_final.rho),
                         "source": {c: r.noise_final.describe(c) for c in r.columns}}),
        "parameter_uncertainty": r.parameter_uncertainty,
        "extended_form": None if r.extended_form is None else r.extended_form.to_json(),
        "generalised_forms": [f.to_json() for f in r.generalised_forms],
        "reasons": list(r.reasons),
        "columns": list(r.columns),
        "noise_model": noise_model_json(r.noise_final or r.noise, r.columns),
        "noise_sigma": dict(r.noise.sigma),
        "noise_sigma_source": {c: r.noise.describe(c) for c in r.columns},
        "nuisance": {"names": list(r.nuisance.names),
                     "bounds": {n: [float(a), float(b)] for n, (a, b) in r.nuisance.bounds.items()},
                     "baseline": r.nuisance.baseline, "extended": r.nuisance.extended},
        "residuals": {"baseline": r.residuals_baseline, "extended": r.residuals_extended,
                      "baseline_structure": bool(r.baseline_structure)},
        "best_partial": (None if r.best_partial is None else
                         {"effect": r.best_partial.effect,
                          "parameters": r.best_partial.parameters,
                          "residuals": r.best_partial.residuals}),
        "lookalike": r.lookalike,
        "joint_fits": {k: j.to_json() for k, j in r.joint_fits.items()},
        "separating_tests": r.separating_tests,
        "not_identifiable": r.not_identifiable,
        "heldout": {"blocks": int(r.heldout_blocks), "method": HELDOUT_METHOD},
        "heldout_untestable": list(r.heldout_untestable),
        "thresholds": dict(r.thresholds),
        "notes": list(r.notes),
        "spikes": dict(r.spikes),
        "n_rows": int(r.n_rows),
        "n_predict_calls": int(r.cost.n_predict_calls),
        "predict_calls_by_phase": dict(r.cost.calls_by_phase),
        "seconds": {"total": r.cost.seconds_total, "predict": r.cost.seconds_predict},
        "seconds_by_phase": r.cost.seconds_by_phase,
        "open_world": None if r.open_world is None else r.open_world.to_json(),
    }
    return jsonable(out)


def noise_model_json(noise, columns) -> dict:
    """diagnosis.json `noise_model` (docs/cli.md) of the final noise model (the one
    re-estimated from the residual of the accepted causes, else the baseline's): per compared
    column its source ("stated":
    `--noise`, "column": `sigma_<column>`, "estimated": from the data alone), the statement
    (`rel`: share of the reading, 0.015 for 1.5 %; `abs`: column unit; null for a column
    source), whether the data's level agrees with it (`consistent`, null when estimated), the
    data's marginal level `sigma` (column unit; at a row of RMS stated uncertainty for a stated
    column), the stated level `stated_sigma` (RMS over the compared rows) and their `ratio` with
    its interval."""
    out = {}
    for c in columns:
        st = noise.stated.get(c)
        if st is None:
            out[c] = {"source": "estimated", "rel": None, "abs": None, "consistent": None,
                      "sigma": noise.sigma[c]}
            continue
        chk = noise.consistency.get(c)
        out[c] = {"source": st.source,
                  "rel": st.rel if st.source == "stated" else None,
                  "abs": st.abs_unit if st.source == "stated" else None,
                  "consistent": None if chk is None else chk.consistent,
                  "sigma": noise.sigma[c], "stated_sigma": noise.stated_sigma.get(c),
                  "ratio": None if chk is None else chk.ratio,
                  "ratio_interval": None if chk is None else [chk.ratio_lo, chk.ratio_hi],
                  "consistency_level": 1.0 - CONSISTENCY_ALPHA}
    return out
