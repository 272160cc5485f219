"""Diagnosis of measured data: what the baseline model gets wrong, which named effect explains it,
how much the extended model gains on held-out data. Model-agnostic statistical engine.

The engine only sees a `predict(effects, nuisance) -> {column: array}` callable that evaluates the
model on the measured conditions with the given effects switched on (`{name: {param: value}}`) and
the nuisance calibration (`{name: value}`, e.g. a friction scale `mu_scale`), the measured outputs,
the conditions table, the candidate effect objects (`studies.model.effects`), the nuisance bounds and the
held-out block labels. It returns a typed `DiagnosisResult` (`studies.diagnosis.result`; its
JSON form has the keys of docs/cli.md "`diagnose` output": `verdict`, `cause`, `parameters`, `indistinguishable`,
`separating_test`, `baseline`, `extended`, `gain`, `candidates`, plus diagnostics).

Each phase below is a plain function (one module each) of the immutable `Problem`
(`studies.diagnosis.problem`) and the typed results of the phases before it; `run` calls them
in order and `assemble` builds the result.

Method (docs/diagnosis.md):

1. Calibrate the baseline (nuisance only, bounded least squares). Estimate the noise level of each
   output column from the data itself: second differences of the baseline residuals within
   contiguous blocks, robustly trimmed (they cancel any smooth model error). Residuals of all
   compared columns are standardised by these levels and stacked. Describe the residuals: bias
   (t test), reduced chi-square, lag-1 autocorrelation (von Neumann type test in row order),
   and a smoother (cubic polynomials in every varying condition and in time, plus the rates of
   change of the conditions) with its F test and its held-out (block cross-validated) gain. Structure = any of these tests significant after
   Bonferroni over tests and columns.
2. For every candidate, the finite-difference sensitivity of the predictions to its parameters at
   "off"; the part the baseline's calibration can produce (span of the nuisance Jacobian) is
   projected out. A candidate whose projected sensitivity keeps less than `min_remaining` of its
   norm, or cannot move the predictions by `min_reach_sigma` noise units anywhere inside its bounds,
   is "not identifiable here". Cosines of the principal angles between the projected
   sensitivities of two candidates form the look-alike matrix.
3. Each identifiable candidate is fitted (bounded least squares, nuisance refitted jointly; a few
   starting points for nonlinear parameters; parameters like a threshold are profiled over the
   finite set of values that give distinct predictions). Likelihood ratio vs the baseline with a
   chi-bar-square (half chi-square mixture) null when parameters sit on a bound at "off", Holm
   correction over the candidates tested, and a BIC margin.
4. Held-out gain: for each contiguous block, the parameters are refitted on the other blocks (one
   Gauss-Newton step from the full fit with the full-fit Jacobian restricted to the training rows;
   a candidate with a profiled parameter, a history effect, is refitted in full: the value
   re-selected over its grid, every other parameter refitted on the training rows), the held-out
   block is predicted with a real model call. Blocks the training rows cannot test (a one-off
   trigger inside the held-out block) are left out and reported (`heldout_untestable`). A paired block bootstrap of the held-out RMSE difference (baseline minus
   candidate) must exclude zero.
5. Candidates passing 3 and 4: the best (lowest BIC) is compared with every other candidate that
   fits nearly as well by a joint fit: it "clearly carries the weight" when adding it to the other
   is significant and adding the other to it is not. Otherwise the verdict is ambiguous, and the
   separating test is found by evaluating the fitted rivals where they differ most: unmeasured
   output columns, and (with `predict_at`) probe conditions (other speed, preload, temperature
   range, ramp rate).
6. Thresholds (`DEFAULT_THRESHOLDS`) were set and checked on simulated null and hidden-effect data
   (`tests/test_diagnosis_slow.py`, which prints the measured rates).

Verdicts (spec): `no_discrepancy` (no residual structure and no candidate passes), `explained`
(exactly one clear cause that leaves no structure), `ambiguous` (the best and at least one rival
explain equally well), `unexplained` (structure, but no candidate passes, or the best leaves
structure behind).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import numpy as np

from studies.diagnosis import staging
from studies.diagnosis.calibration import baseline_noise, calibrate, stated_noise_notes
from studies.diagnosis.candidate import Candidate
from studies.diagnosis.core import Baseline, Decision, Fit, Screening
from studies.diagnosis.decision import Separation, decide, separating
from studies.diagnosis.fitting import fit_all
from studies.diagnosis.generalised import ChosenForm, generalise
from studies.diagnosis.heldout import validate
from studies.diagnosis.interval import column_intervals, configured_intervals
from studies.diagnosis.ladder import is_form
from studies.diagnosis.openworld import characterise
from studies.diagnosis.problem import Problem, make_problem
from studies.diagnosis.result import (BestPartial, ColumnEvidence, Cost, DiagnosisResult,
                                      ModelRmse, NuisanceFit, to_json)
from studies.diagnosis.screening import screen
from studies.diagnosis.selection import Selection, select, select_past_drift


@dataclass
class _Clock:
    """Model calls and cumulative seconds at the end of each phase (the cost of the result)."""
    pb: Problem
    t0: float = field(default_factory=time.perf_counter)
    calls: dict[str, int] = field(default_factory=dict)
    marks: dict[str, dict[str, float]] = field(default_factory=dict)

    def phase(self, label: str) -> None:
        self.calls[label] = self.pb.model.calls - sum(self.calls.values())
        self.marks[label] = {"total": time.perf_counter() - self.t0,
                             "predict": self.pb.model.seconds}

    def cost(self) -> Cost:
        out, prev = {}, {"total": 0.0, "predict": 0.0}
        for label, c in self.marks.items():
            out[label] = {k: c[k] - prev[k] for k in ("total", "predict")}
            prev = c
        return Cost(int(self.pb.model.calls), dict(self.calls), time.perf_counter() - self.t0,
                    self.pb.model.seconds, out)


@dataclass(frozen=True)
class Pass:
    """One pass of phases 1-5b on a problem (the first on the data as given; later ones with
    the causes accepted so far in the baseline): the calibrated problem and every phase's
    result."""
    pb: Problem
    baseline: Baseline
    screening: Screening
    fits: dict[str, Fit]
    candidates: dict[str, Candidate]
    heldout: dict[str, np.ndarray]
    passing: list[str]
    decision: Decision
    forms: list
    chosen: ChosenForm | None


def one_pass(pb: Problem, rng: np.random.Generator, clock: "_Clock", tag: str = "",
             calibrated: tuple[Problem, Baseline] | None = None) -> Pass:
    """Phases 1-5b (module docstring) on `pb` (`calibrated`: phase 1's result when already
    computed); `tag` suffixes the clock's phase labels. A staged rung the residual indicates
    (`staging`) is held in a first stage and screened in a second only when the staging rules
    call for it."""
    pb, b = calibrated or calibrate(pb)
    clock.pb = pb
    clock.phase("baseline" + tag)
    held = staging.held(pb)
    s = screen(pb, b, held=held)
    clock.phase("sensitivities" + tag)
    pending = [n for n in s.held if held[n] == staging.PENDING]
    fitted = fit_all(pb, s, b, later=len(pending))
    clock.phase("fits" + tag)
    refits: dict = {}
    first = _judged(pb, b, s, fitted, rng, clock, tag, refits)
    if not pending:
        return first
    why = staging.lumped_explains(first)
    if why is not None:
        return staging.with_reasons(first, {n: first.candidates[n].with_status(
            "not_applicable", why) for n in pending})
    s2 = screen(pb, b, held={n: r for n, r in held.items() if n not in pending}, done=s)
    clock.phase("sensitivities_staged" + tag)
    fitted2 = fit_all(pb, s2, b, done=fitted)
    clock.phase("fits_staged" + tag)
    second = _judged(pb, b, s2, fitted2, rng, clock, tag + "_staged", refits)
    tie = staging.lumped_tie(second, pending)
    if tie is None:
        return second
    records = {n: second.candidates[n] for n in pending}
    return staging.with_reasons(first, {n: c.with_status("rejected", f"{c.reason}; but {tie}")
                                        if c.fitted else c for n, c in records.items()})


def _judged(pb: Problem, b: Baseline, s: Screening, fitted: tuple[dict, dict],
            rng: np.random.Generator, clock: "_Clock", tag: str,
            refits: dict | None = None) -> Pass:
    """Phases 4-5b on the screening `s` and the fits `fitted` (`fitting.fit_all`); `refits`:
    the held-out refits of an earlier stage of the pass (`heldout.validate`)."""
    fits, cands = fitted
    ho, passing, cands = validate(pb, cands, fits, b, rng, refits)
    clock.phase("heldout" + tag)
    d = decide(pb, cands, fits, passing, b, ho)
    clock.phase("compare" + tag)
    g = generalise(pb, cands, fits, ho, b, d, rng)
    clock.phase("generalised" + tag)
    return Pass(pb, b, s, fits, cands, ho, passing, g.decision, g.forms, g.chosen)


def run(pb: Problem, seed: int = 0, t0: float | None = None) -> DiagnosisResult:
    """The diagnosis in its phases (module docstring), each a function of the problem and the
    typed results before it, then the forward selection of further causes
    (`studies.diagnosis.selection`). `seed`: the bootstrap's random numbers (phase 4, 5b);
    `t0`: the clock's start (default now)."""
    clock = _Clock(pb) if t0 is None else _Clock(pb, t0)
    rng = np.random.default_rng(seed)
    first = one_pass(pb, rng, clock)
    d = first.decision
    sep = (separating(first.pb, d.best, d.rivals, first.fits, first.baseline.fit)
           if d.verdict == "ambiguous" else Separation(None, [], []))
    clock.phase("separating")
    nxt = lambda q, k, cal: one_pass(q, rng, clock, f"_cause{k}", cal)  # noqa: E731
    sel = select(first, nxt)
    past = select_past_drift(first, nxt) if sel.verdict is None else None
    if past is not None:            # two causes, the second taken for a drift at first
        first, sel = past
        sep = Separation(None, [], [])
    return assemble(first, sel, sep, clock.cost())


def _cause_values(p: Pass, cause: str | None) -> tuple[dict, dict, dict | None]:
    """The cause's parameters, their uncertainties and the nuisance refitted with it (None: no
    cause), from the generalised form when one explains the data. A pass may have chosen a
    form whose cause the claim rules then refused (`selection.blocked`: the form at a bound):
    no cause is named, so none of its values are reported."""
    if not cause:
        return {}, {}, None
    chosen, pb = p.chosen, p.pb
    if chosen:
        entry = chosen.entry
        own = pb.effect(cause).parameters
        return ({q: v for q, v in entry.parameters.items() if q in own},
                {q: v for q, v in entry.parameter_uncertainty.items() if q in own},
                entry.nuisance)
    c = p.candidates[cause]
    return dict(c.parameters), dict(c.uncertainty), c.nuisance


def _extended(p: Pass, cause: str | None) -> tuple[Fit, np.ndarray]:
    """The extended model's fit and held-out residuals: the chosen generalised form's, else the
    cause's, else the baseline's."""
    if not cause:
        return p.baseline.fit, p.baseline.heldout_z
    if p.chosen:
        return p.chosen.fit, p.chosen.heldout_z
    return p.fits[cause], p.heldout[cause]


def _ordered_candidates(p: Pass) -> list[Candidate]:
    """Fitted candidates first (passing ones, then by delta BIC), then the others; a passing
    candidate the best clearly beats with that note in its reason."""
    cands = {n: (replace(c, reason=c.reason + p.decision.beaten[n])
                 if n in p.decision.beaten else c) for n, c in p.candidates.items()}
    fitted = sorted((n for n in cands if cands[n].fitted),
                    key=lambda n: (n not in p.passing, cands[n].delta_bic))
    return [cands[n] for n in fitted + [n for n in cands if not cands[n].fitted]]


def column_evidence(pb: Problem, base: ModelRmse, ext: ModelRmse, z_base: np.ndarray,
                    z_ext: np.ndarray) -> dict[str, ColumnEvidence]:
    """Per compared column: the baseline's misfit in noise units (RMS / sigma), the held-out
    RMSE ratio and gain (noise units) of the extended model, and its share of the in-sample
    chi-square drop (standardised residuals `z_base`, `z_ext` of the same problem)."""
    drops = {}
    for j, c in enumerate(pb.columns):
        sel = pb.entry_col == j
        drops[c] = float(z_base[sel] @ z_base[sel] - z_ext[sel] @ z_ext[sel])
    total = sum(max(v, 0.0) for v in drops.values())
    out = {}
    for c in pb.columns:
        s = pb.noise.sigma[c]
        bh = base.heldout_rmse[c]
        out[c] = ColumnEvidence(base.rmse[c] / s, ext.heldout_rmse[c] / bh if bh > 0 else 1.0,
                                (bh - ext.heldout_rmse[c]) / s, drops[c],
                                max(drops[c], 0.0) / total if total > 0 else 0.0)
    return out


def _interval(first: Pass, sel: Selection, cause: str | None, ext_fit: Fit, ext_ho: np.ndarray):
    """The predictive intervals of the claimed model (`interval.column_intervals`) and the fit
    they are about: the selection's final model of the accepted causes, else the first pass's
    extended fit, under the noise re-estimated from that fit's own residual
    (`calibration.baseline_noise`: a first noise estimate inflated by the cause, AR(1) rho 0.99,
    would give intervals many times too wide). Without a claimed cause: the configured model's
    interval with the discrepancy the data show (`interval.configured_intervals` of the
    calibrated baseline) and no fit."""
    if not cause or sel.verdict not in ("explained", "explained_partly"):
        return configured_intervals(first.pb, first.baseline.fit), None
    pb, fit, ho = ((sel.problem, sel.fit, sel.heldout_z) if sel.fit is not None
                   else (first.pb, ext_fit, ext_ho))
    return column_intervals(pb, fit, ho, noise=baseline_noise(pb, fit.pred)), fit


def assemble(first: Pass, sel: Selection, sep: Separation, cost: Cost) -> DiagnosisResult:
    """The typed result of the phases and the forward selection."""
    pb, b, s, d = first.pb, first.baseline, first.screening, first.decision
    verdict = sel.verdict or d.verdict
    # a first cause the selection turned down (it leaves structure it cannot own, or the change
    # is below what the data could show): no cause
    cause = d.cause if verdict not in ("unexplained", "no_discrepancy") else None
    ext_fit, ext_ho = _extended(first, cause)
    params, unc, nuis_ext = _cause_values(first, cause)
    base = ModelRmse(pb.col_rmse(b.fit.z), pb.col_rmse(b.heldout_z))
    ext = ModelRmse(pb.col_rmse(ext_fit.z), pb.col_rmse(ext_ho))
    z_ext = ext_fit.z
    if sel.rmse is not None:          # the joint model of every accepted cause
        ext = ModelRmse(sel.rmse, sel.heldout_rmse)
        params = dict(sel.causes[0].parameters)
        z_ext = pb.zvec(sel.pred)
    c0 = pb.columns[0]
    ratio = ext.heldout_rmse[c0] / base.heldout_rmse[c0] if base.heldout_rmse[c0] > 0 else 1.0
    ratios = {c: (ext.heldout_rmse[c] / base.heldout_rmse[c] if base.heldout_rmse[c] > 0
                  else 1.0) for c in pb.columns}
    evidence = column_evidence(pb, base, ext, b.fit.z, z_ext)
    decisive = max(pb.columns, key=lambda c: evidence[c].baseline_misfit_sigma)
    nu = pb.nuisance
    reasons = list(d.reasons) + list(sel.reasons)
    best_partial = (None if verdict != "unexplained" or d.best is None else
                    BestPartial(d.best, first.candidates[d.best].parameters, d.best_residuals))
    open_world = (characterise({c: pb.scaled_residual(c, b.fit.pred[c]) for c in pb.columns},
                               pb.valid, pb.conditions, pb.blocks, pb.noise.sigma_w,
                               pb.noise.rho, forms={e.name: e.acts_through
                                                    for e in pb.candidates if is_form(e)})
                  if verdict == "unexplained" else None)
    chosen = first.chosen if cause else None
    interval, iv_fit = _interval(first, sel, cause, ext_fit, ext_ho)
    return DiagnosisResult(
        verdict=verdict, cause=cause, parameters=params, parameter_uncertainty=unc,
        indistinguishable=list(d.rivals) if cause else [], separating_test=sep.text, baseline=base, extended=ext,
        heldout_rmse_ratio=ratios, heldout_rmse_ratio_first=float(ratio),
        decisive_column=decisive, evidence=evidence,
        candidates=_ordered_candidates(first),
        extended_form=chosen.entry if chosen else None, generalised_forms=list(first.forms),
        reasons=reasons, columns=list(pb.columns), noise=pb.noise,
        nuisance=NuisanceFit(list(nu.names),
                             {n: (float(a), float(c)) for n, a, c in zip(nu.names, nu.lo, nu.hi)},
                             b.nuisance, nuis_ext if nuis_ext is not None else b.nuisance),
        residuals_baseline=b.residuals, residuals_extended=d.best_residuals if cause else None,
        baseline_structure=bool(b.structure), best_partial=best_partial, lookalike=s.lookalike,
        joint_fits=d.joint_fits, separating_tests=sep.items,
        heldout_blocks=pb.n_blocks,
        heldout_untestable=(list(first.candidates[cause].heldout_untestable or [])
                            if cause else []),
        thresholds=dict(pb.th),
        notes=list(pb.notes) + sep.notes + list(stated_noise_notes(sel.noise or pb.noise)), spikes=dict(pb.spikes),
        n_rows=pb.n, cost=cost, open_world=open_world,
        causes=list(sel.causes), left=list(sel.left), at_bound=list(sel.at_bound),
        worse_columns=list(sel.worse_columns),
        interval=interval,
        row_blocks=np.asarray(pb.blocks, int).copy(),
        goodness=sel.goodness, noise_final=sel.noise, detection=dict(sel.detection),
        baseline_pred=b.fit.pred,
        extended_pred=(iv_fit.pred if iv_fit is not None else sel.pred if sel.pred
                       else ext_fit.pred),
        candidate_preds={n: f.pred for n, f in first.fits.items()})


# ============================================================================ public API
def diagnose_full(predict: Callable[[dict, dict], Mapping[str, np.ndarray]],
                  measured: Mapping[str, np.ndarray], conditions: Mapping[str, np.ndarray],
                  candidates: Sequence, nuisance: Mapping[str, tuple], blocks=None, *,
                  noise_sigma: Mapping[str, float] | None = None, T_ref_C: float = 20.0,
                  predict_at: Callable | None = None, thresholds: Mapping | None = None,
                  seed: int = 0, columns: Sequence[str] | None = None,
                  generalised: bool = True, workers: int = 1,
                  noise_model: Mapping | None = None) -> DiagnosisResult:
    """Run the diagnosis (see the module docstring) and return the typed result.

    predict(effects, nuisance) -> {column: array(n_rows)} on the measured conditions.
    measured: {output column: array(n_rows)} (NaN = not measured in that row).
    conditions: {condition column: array(n_rows)} (used for residual structure, profiles, probes).
    candidates: effect objects (`studies.model.effects.EFFECTS[name]`).
    nuisance: {name: (lo, hi[, start[, scale]])}, refitted with every model (e.g. mu_scale).
    blocks: held-out block label per row (contiguous time or test segments); None -> n_blocks
        contiguous blocks in row order.
    noise_sigma: known noise levels per column (default: estimated from the data).
    noise_model: {column: `noisemodel.StatedNoise`}: a sensor's stated noise (`--noise`,
        `sigma_<column>`): the per-row weights, the level still estimated and checked.
    predict_at(effects, nuisance, conditions) -> outputs at other conditions (optional; used to
        find the separating test).
    generalised: try the generalised forms of the listed effects when the verdict would be
        `unexplained` (`studies.diagnosis.generalised`).
    workers: processes for the independent candidate work (fits, held-out refits, the local
        fits of a generalised form; `studies.model.parallel.parallel_map`): the result does not
        depend on it, only the wall time (1: all in this process).
    """
    t0 = time.perf_counter()
    pb = make_problem(predict, measured, conditions, candidates, nuisance, blocks,
                      noise_sigma=noise_sigma, T_ref_C=T_ref_C, predict_at=predict_at,
                      thresholds=thresholds, columns=columns, workers=workers,
                      generalised=generalised, noise_model=noise_model)
    return run(pb, seed, t0)


def diagnose(*args, **kwargs) -> dict:
    """`diagnose_full(...)` as the JSON-ready dict of diagnosis.json (`result.to_json`)."""
    return to_json(diagnose_full(*args, **kwargs))


def lookalike_matrix(predict: Callable, measured: Mapping[str, np.ndarray],
                     conditions: Mapping[str, np.ndarray], candidates: Sequence, nuisance: Mapping,
                     noise_sigma: Mapping[str, float], T_ref_C: float,
                     predict_at: Callable | None = None) -> dict[str, dict[str, float]]:
    """Phases 1-2 only (baseline calibration and screening) on `measured`: the look-alike matrix
    {a: {b: largest cosine between the candidates' sensitivity subspaces}} of the identifiable
    candidates. On the model's own noise-free output it is a property of the test design alone
    (`studies.diagnosis.operating.lookalike_before_data`)."""
    pb = make_problem(predict, measured, conditions, candidates, nuisance, None,
                      noise_sigma=noise_sigma, T_ref_C=T_ref_C, predict_at=predict_at)
    pb, b = calibrate(pb)
    return screen(pb, b).lookalike
