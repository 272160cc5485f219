"""Diagnosis of measured data: what the baseline model gets wrong, which named effect explains it,
how much the extended model gains on held-out data. Model-agnostic statistical engine.

The engine only sees a `predict(effects, nuisance) -> {column: array}` callable that evaluates the
model on the measured conditions with the given effects switched on (`{name: {param: value}}`) and
the nuisance calibration (`{name: value}`, e.g. a friction scale `mu_scale`), the measured outputs,
the conditions table, the candidate effect objects (`studies.model.effects`), the nuisance bounds and the
held-out block labels. It returns a JSON-ready dict with the keys of `spec/cli.md` (`verdict`,
`cause`, `parameters`, `indistinguishable`, `separating_test`, `baseline`, `extended`, `gain`,
`candidates`) plus diagnostics.

Method (DESIGN.md section 5):

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

import math
import time
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy import optimize, stats

from studies.diagnosis import fitspec
from studies.diagnosis.core import (DEFAULT_THRESHOLDS, FIRST_COLUMNS, Baseline, CachedModel,
                                    Decision, DiagnosisError, Fit, ModelFailure, Screening, Space,
                                    jsonable)
from studies.diagnosis.decision import DecisionPhase
from studies.diagnosis.fitting import FittingPhase
from studies.diagnosis.generalised import GeneralisedPhase
from studies.diagnosis.heldout import HeldoutPhase
from studies.diagnosis.openworld import characterise
from studies.diagnosis.screening import ScreeningPhase
from studies.diagnosis.stats import (ar1_regression_ml, ar1_unwhiten, ar1_whiten, auto_blocks,
                                     noise_sigma, noise_sigma_steady, orth)
from studies.diagnosis.workers import fork_map


#: relative noise floor: a CSV keeps 10 significant digits (half a unit in the last is 5e-10 of the
#: value); twice that, so that round-off alone never looks like structure
ROUND_OFF = 1e-9
#: likelihood-ratio statistic (chi-square, 1 df) of AR(1) errors against white ones, with the
#: conditions' smoother as the regression, above which a column's noise is taken as AR(1) and
#: whitened (slowly drifting sensors); 9 = a 3-sigma level
AR1_LR = 9.0
#: with AR(1) noise the whitening uses an estimated rho and the in-sample F test of the smoother
#: is anti-conservative; the smoother must then also predict the held-out blocks (block cross-
#: validation gain above this share of the residual variance) to count as structure
AR1_MIN_CV_GAIN = 0.1
#: a residual this many robust standard deviations from the smoother is a spike (P = 2e-9 for
#: Gaussian noise), if such entries are at most MAX_SPIKE_SHARE of the column
SPIKE_SIGMA = 6.0
MAX_SPIKE_SHARE = 0.05


class _Engine(ScreeningPhase, FittingPhase, HeldoutPhase, DecisionPhase, GeneralisedPhase):
    """One diagnosis: the data, the cached model and the phases (mixins, one module each)."""

    def __init__(self, predict, measured, conditions, candidates, nuisance, blocks, noise_sigma_,
                 T_ref_C, predict_at, th, seed, columns):
        self.t0 = time.perf_counter()
        self.th = th
        self.rng = np.random.default_rng(seed)
        self.T_ref_C = float(T_ref_C)
        self.predict_at = predict_at
        self.conditions = {k: np.asarray(v, float) for k, v in conditions.items()}
        self.candidates = list(candidates)
        names = [c.name for c in self.candidates]
        if len(set(names)) != len(names):
            raise DiagnosisError("candidate effects must have distinct names")
        meas = {k: np.asarray(v, float) for k, v in measured.items()}
        if not meas:
            raise DiagnosisError("no measured output columns")
        sizes = {v.size for v in meas.values()} | {v.size for v in self.conditions.values()}
        if len(sizes) != 1:
            raise DiagnosisError(f"columns have different lengths: {sorted(sizes)}")
        self.n = sizes.pop()
        if self.n < 8:
            raise DiagnosisError(f"too few rows to diagnose ({self.n}; need at least 8)")
        # nuisance
        self.nuis_names = list(nuisance)
        lo, hi, x0, sc = [], [], [], []
        for name, spec in nuisance.items():
            spec = tuple(spec)
            l, h = float(spec[0]), float(spec[1])
            x = float(spec[2]) if len(spec) > 2 else (1.0 if l <= 1.0 <= h else 0.5 * (l + h))
            s = float(spec[3]) if len(spec) > 3 else 0.1 * max(abs(x), 1e-3 * (h - l))
            if not (l <= x <= h) or s <= 0:
                raise DiagnosisError(f"nuisance {name}: start {x} outside [{l}, {h}]")
            lo.append(l), hi.append(h), x0.append(x), sc.append(s)
        self.nuis_lo, self.nuis_hi = np.array(lo), np.array(hi)
        self.nuis_x0, self.nuis_scale = np.array(x0), np.array(sc)
        self.model = CachedModel(predict, self.n)
        # first call: which columns can be compared
        pred0 = self.model({}, dict(zip(self.nuis_names, self.nuis_x0)))
        common = [c for c in meas if c in pred0]
        if columns is not None:
            common = [c for c in columns if c in common]
        if not common:
            raise DiagnosisError("no measured column is predicted by the model (measured: "
                                 f"{', '.join(meas)})")
        first = [c for c in FIRST_COLUMNS if c in common]
        self.columns = first + [c for c in common if c not in first]
        self.measured = {c: meas[c] for c in self.columns}
        # blocks (held-out) and segments (where differences are taken)
        if blocks is None:
            self.blocks = auto_blocks(self.n, int(th["n_blocks"]))
        else:
            b = np.asarray(blocks)
            if b.size != self.n:
                raise DiagnosisError("block labels must have one entry per row")
            _, self.blocks = np.unique(b, return_inverse=True)
        self.n_blocks = int(self.blocks.max()) + 1
        if self.n_blocks < 2:
            raise DiagnosisError("need at least two held-out blocks")
        # stacked layout
        self.valid = {c: np.isfinite(self.measured[c]) for c in self.columns}
        self.spikes: dict[str, list[int]] = {}
        self._layout()
        self.user_sigma = dict(noise_sigma_ or {})
        self.sigma_source: dict[str, str] = {}
        self.sigma = {c: self._initial_sigma(c) for c in self.columns}   # marginal noise level
        self.rho = {c: 0.0 for c in self.columns}                        # AR(1) coefficient
        self.sigma_w = dict(self.sigma)                                  # innovation level
        self.notes: list[str] = []
        self.calls_by_phase: dict[str, int] = {}
        self.seconds_by_phase: dict[str, dict] = {}     # cumulative clocks at each phase's end

    def _layout(self) -> None:
        """The stacked layout of the compared entries (valid rows of every column)."""
        self.entry_row = np.concatenate([np.flatnonzero(self.valid[c]) for c in self.columns])
        self.entry_col = np.concatenate([np.full(self.valid[c].sum(), j)
                                         for j, c in enumerate(self.columns)])
        self.entry_block = self.blocks[self.entry_row]
        self.N = self.entry_row.size

    def _drop_spikes(self, pred: dict) -> bool:
        """Isolated outliers (sensor spikes): entries whose baseline residual, after the
        conditions' smoother, lies beyond SPIKE_SIGMA robust standard deviations (1.4826 MAD) are
        left out of every fit and test and reported; a model error is smooth in the conditions
        and stays. Returns True when some were dropped."""
        X = self.features()
        dropped = False
        for c in self.columns:
            m = self.valid[c]
            rows = np.flatnonzero(m)
            if rows.size < 20:
                continue
            r = (self.measured[c] - pred[c])[m]
            A = np.column_stack([np.ones(rows.size), X[m]])
            coef, *_ = np.linalg.lstsq(A, r, rcond=None)
            e = r - A @ coef
            s = stats.median_abs_deviation(e, scale="normal")
            bad = np.abs(e - np.median(e)) > SPIKE_SIGMA * s if s > 0 else np.zeros(e.size, bool)
            if bad.any() and bad.sum() <= MAX_SPIKE_SHARE * rows.size:
                self.valid[c] = m.copy()
                self.valid[c][rows[bad]] = False
                self.spikes[c] = [int(i) + 1 for i in rows[bad]]      # 1-based, as in the file
                dropped = True
        if dropped:
            self._layout()
            self.notes.append("spikes left out (row numbers): " + "; ".join(
                f"{c}: {', '.join(map(str, v))}" for c, v in self.spikes.items()))
        return dropped

    # ------------------------------------------------------------------ residuals
    def _initial_sigma(self, c):
        """The column's noise level: given, or from the data (second differences), but never
        below round-off (ROUND_OFF x its largest value): a file written with 10 significant
        digits carries 5e-10 of relative noise, and residuals at that level are no discrepancy."""
        if c in self.user_sigma:
            return float(self.user_sigma[c])
        floor = ROUND_OFF * float(np.nanmax(np.abs(self.measured[c]), initial=0.0))
        s = max(self._data_sigma(c, self.measured[c]), floor)
        return s if s > 0 else 1.0     # a column of zeros

    def _data_sigma(self, c: str, r: np.ndarray) -> float:
        """Noise level of column c from residuals r: in a time series from second differences in
        time (within blocks); in a table of steady points from the design (replicates, or
        second differences along each condition: `stats.noise_sigma_steady`)."""
        t = self.conditions.get("time_s")
        if t is None or not np.all(np.diff(t) > 0):
            m = self.valid[c]
            s, how = noise_sigma_steady(r[m], {k: v[m] for k, v in self.conditions.items()})
            if s > 0:
                self.sigma_source[c] = how
                return s
        self.sigma_source[c] = "second differences of the baseline residuals"
        return noise_sigma(r, self.blocks)

    def zvec(self, pred: dict) -> np.ndarray:
        """Standardised residuals, stacked: per column whitened for its AR(1) noise (within the
        held-out blocks) and divided by the innovation level; plain r / sigma for white noise."""
        parts = []
        for c in self.columns:
            m = self.valid[c]
            r = self.measured[c][m] - pred[c][m]
            parts.append(ar1_whiten(r, self.blocks[m], self.rho[c]) / self.sigma_w[c])
        z = np.concatenate(parts)
        if not np.all(np.isfinite(z)):
            raise ModelFailure("the model returned non-finite values")
        return z

    # ------------------------------------------------------------------ spaces
    def space(self, effects: Sequence, fixed: dict | None = None) -> Space:
        """Space fitting the non-profile parameters of `effects` (effect objects) + nuisance;
        `fixed` gives values for profiled parameters."""
        fixed = fixed or {}
        eff_params, origin, scale, lo, hi = [], [], [], [], []
        fx = {}
        for e in effects:
            steps = fitspec.steps(e, self.conditions)
            fx[e.name] = dict(e.off)
            fx[e.name].update(fixed.get(e.name, {}))
            for p in self.free_params(e):
                s = float(steps.get(p, e.scale[p]))
                eff_params.append((e.name, p))
                origin.append(e.off[p]), scale.append(s)
                lo.append((e.bounds[p][0] - e.off[p]) / s), hi.append((e.bounds[p][1] - e.off[p]) / s)
        origin += list(self.nuis_x0)
        scale += list(self.nuis_scale)
        lo += list((self.nuis_lo - self.nuis_x0) / self.nuis_scale)
        hi += list((self.nuis_hi - self.nuis_x0) / self.nuis_scale)
        return Space(eff_params, fx, list(self.nuis_names), np.array(origin, float),
                      np.array(scale, float), np.array(lo, float), np.array(hi, float))

    def eval(self, space: Space, u) -> tuple[np.ndarray, dict]:
        pred = self.model(*space.unpack(space.clip(u)))
        return self.zvec(pred), pred

    def fit(self, space: Space, u0, max_nfev=None) -> Fit:
        u0 = space.clip(np.asarray(u0, float))
        # strictly inside the bounds for trf
        lo, hi = space.lo, space.hi
        span = hi - lo
        u0 = np.clip(u0, lo + 1e-10 * np.maximum(span, 1), hi - 1e-10 * np.maximum(span, 1))
        dim = u0.size

        big = np.full(self.N, 1e6)
        self.eval(space, u0)              # the start must evaluate (else ModelFailure)

        def fun(u):
            try:
                return self.eval(space, u)[0]
            except ModelFailure:          # outside the model's range: steer the optimiser back
                return big

        res = optimize.least_squares(fun, u0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                                     x_scale=1.0, ftol=1e-8, xtol=1e-8, gtol=1e-8,
                                     max_nfev=max_nfev or 40 * (dim + 1))
        z, pred = self.eval(space, res.x)
        return Fit(space, res.x, z, np.asarray(res.jac, float), float(z @ z), pred)

    # ------------------------------------------------------------------ describe residuals
    def features(self) -> np.ndarray:
        if getattr(self, "_features", None) is not None:
            return self._features
        cols = []
        keys = [k for k in self.conditions if np.nanstd(self.conditions[k]) > 0]
        if "time_s" not in keys:
            cols.append(("row", np.arange(self.n, dtype=float)))
        cols += [(k, self.conditions[k]) for k in keys]
        deg = 3 if self.n >= 12 * 3 * len(cols) + 10 else 1
        F = []
        for _, x in cols:
            x = (x - np.mean(x)) / (np.std(x) or 1.0)
            for d in range(1, deg + 1):
                F.append(x ** d)
        # rates of change (history effects: lags, hysteresis), linear terms only
        if "time_s" in self.conditions and self.n >= 12 * 4 * len(cols) + 10:
            t = self.conditions["time_s"]
            if np.all(np.diff(t) > 0):
                for k, x in cols:
                    if k in ("time_s", "row"):
                        continue
                    g = np.gradient(x, t)
                    if np.std(g) > 0:
                        F.append((g - g.mean()) / g.std())
        self._features = np.array(F).T if F else np.zeros((self.n, 0))
        return self._features

    def describe(self, pred: dict, n_params: int) -> dict:
        """Residual statistics per column and the structure decision inputs."""
        X_all = self.features()
        out = {}
        pvals = []
        for c in self.columns:
            m = self.valid[c]
            r = (self.measured[c] - pred[c])[m]
            s = self.sigma[c]
            seg = self.blocks[m]
            rho = self.rho[c]
            # generalised least squares for AR(1) noise: whiten residuals and regressors alike
            # (identical to the white-noise statistics when rho = 0)
            z = ar1_whiten(r, seg, rho) / self.sigma_w[c]
            one = ar1_whiten(np.ones_like(r), seg, rho)
            nn = z.size
            bias = float(np.mean(r))
            b_hat = float(one @ z) / float(one @ one)
            bias_p = float(2 * stats.norm.sf(abs(b_hat) * math.sqrt(float(one @ one))))
            chi2_red = float(z @ z / max(nn - n_params, 1))
            # lag-1 autocorrelation within blocks, in row order (of the whitened residuals)
            zc = z - one * b_hat
            same = seg[1:] == seg[:-1]
            den = float(zc @ zc) or 1.0
            num = float(np.sum(zc[1:][same] * zc[:-1][same]))
            r1 = num / den
            npairs = max(int(same.sum()), 1)
            # significant only if it is both (self-normalised autocorrelation, and the lag-1
            # product sum in units of the noise level: structure far below the noise is none)
            auto_p = float(max(stats.norm.sf(r1 * math.sqrt(npairs)),
                               stats.norm.sf(num / math.sqrt(npairs))))
            # smoother: polynomials in the varying conditions (and time / row order)
            X = X_all[m]
            A = ar1_whiten(np.column_stack([np.ones(nn), X]), seg, rho)
            q = orth(A)
            fitted = q @ (q.T @ zc)
            ss1 = float(np.sum((zc - fitted) ** 2))
            p_feat = q.shape[1] - 1
            if p_feat > 0 and nn - p_feat - 1 > 0 and ss1 > 0:
                Fst = ((den - ss1) / p_feat) / (ss1 / (nn - p_feat - 1))
                F_p = float(max(stats.f.sf(Fst, p_feat, nn - p_feat - 1),
                                stats.chi2.sf(den - ss1, p_feat)))     # F and known-sigma
            elif p_feat > 0 and nn - p_feat - 1 > 0:
                Fst = math.inf
                F_p = float(stats.chi2.sf(den - ss1, p_feat))
            else:
                Fst, F_p = 0.0, 1.0
            # smoother's held-out gain (block cross-validation)
            sse_cv = 0.0
            sse_0 = 0.0
            blocks = self.blocks[m]
            for b in np.unique(blocks):
                tr, te = blocks != b, blocks == b
                if tr.sum() <= A.shape[1] + 1:
                    continue
                coef, *_ = np.linalg.lstsq(A[tr], z[tr], rcond=None)
                sse_cv += float(np.sum((z[te] - A[te] @ coef) ** 2))
                b_tr = float(one[tr] @ z[tr]) / float(one[tr] @ one[tr])
                sse_0 += float(np.sum((z[te] - one[te] * b_tr) ** 2))
            cv_gain = 1.0 - sse_cv / sse_0 if sse_0 > 0 else 0.0
            out[c] = {"bias": bias, "bias_p": bias_p, "rmse": float(np.sqrt(np.mean(r ** 2))),
                      "noise_sigma": s, "noise_ar1": rho, "chi2_reduced": chi2_red,
                      "lag1_autocorr": r1,
                      "lag1_p": auto_p, "smoother_F": float(Fst), "smoother_p": F_p,
                      "smoother_heldout_gain": float(cv_gain)}
            if rho > 0.0 and cv_gain < AR1_MIN_CV_GAIN:
                F_p = 1.0      # AR(1) noise: the smoother must also predict held-out blocks
            out[c]["smoother_p_used"] = F_p
            pvals += [bias_p, auto_p, F_p]
        p_min = min(pvals)
        p_adj = min(1.0, p_min * len(pvals))
        return {"columns": out, "p_min_adjusted": p_adj}

    # ------------------------------------------------------------------ sensitivities
    def col_rmse(self, z_stacked) -> dict[str, float]:
        """RMSE per column in its own unit (the standardised residuals un-whitened)."""
        out = {}
        for j, c in enumerate(self.columns):
            zz = z_stacked[self.entry_col == j]
            r = ar1_unwhiten(zz * self.sigma_w[c], self.blocks[self.valid[c]], self.rho[c])
            out[c] = float(np.sqrt(np.mean(r ** 2)))
        return out

    # ------------------------------------------------------------------ run
    def run(self) -> dict:
        """The diagnosis in its phases (module docstring); returns the JSON-ready result."""
        b = self.calibrate_baseline()
        self._phase("baseline")
        s = self.screen(b)
        self._phase("sensitivities")
        fits = self.fit_all(s, b)
        self._phase("fits")
        ho, passing = self.validate(s, fits, b)
        self._phase("heldout")
        d = self.decide(s, fits, passing, b)
        self._phase("compare")
        d, self.generalised_forms, self.chosen_form = self.generalise(s, fits, ho, b, d)
        self._phase("generalised")
        self.verdict, self.cause, self.best = d.verdict, d.cause, d.best
        sep, sep_items = (self.separating(d.best, d.rivals, fits, b.fit)
                          if d.verdict == "ambiguous" else (None, []))
        self._phase("separating")
        result = self.assemble(b, s, fits, ho, passing, d, sep, sep_items)
        result["open_world"] = (jsonable(characterise(
            {c: self.measured[c] - b.fit.pred[c] for c in self.columns}, self.valid,
            self.conditions, self.blocks, self.sigma_w, self.rho).to_json())
            if d.verdict == "unexplained" else None)
        return result

    def calibrate_baseline(self) -> Baseline:
        """Phase 1: nuisance-only fit in two passes (noise from the measured data, then from the
        baseline residuals), its residual description and held-out residuals."""
        bspace = self.space([])
        base = self.fit(bspace, np.zeros(bspace.k + len(self.nuis_names)))
        if self._drop_spikes(base.pred):
            base = self.fit(bspace, base.u)
        for c in self.columns:
            if c not in self.user_sigma:
                s = self._data_sigma(c, self.measured[c] - base.pred[c])
                scale = max(np.nanmax(np.abs(self.measured[c])), 1e-300)
                self.sigma[c] = self.sigma_w[c] = max(s, ROUND_OFF * scale)
                self._noise_ar1(c, base.pred[c], ROUND_OFF * scale)
        base = self.fit(bspace, base.u)
        base_nuis = bspace.unpack(base.u)[1]
        n_nuis = len(self.nuis_names)
        desc_base = self.describe(base.pred, n_nuis)
        structure = desc_base["p_min_adjusted"] < self.th["alpha_structure"]
        base_ho = self.heldout_linear(base)
        Qn = orth(base.J)
        return Baseline(base, base_nuis, desc_base, bool(structure), base_ho, Qn)

    def _noise_ar1(self, c: str, pred: np.ndarray, floor: float) -> None:
        """Serial correlation of column c's noise: the maximum-likelihood AR(1) coefficient of the
        baseline residuals regressed on the smoother in the conditions (what a model error would
        look like is taken out first; `stats.ar1_regression_ml`). When significant (likelihood
        ratio > AR1_LR) the noise is taken as AR(1): rho, the innovation level from the whitened
        residuals' second differences, and the marginal level sigma_w / sqrt(1 - rho^2).
        Only for time series (`time_s` increasing): in a table of steady points the row order
        means nothing, and neighbouring rows of a grid share a model error, not a noise."""
        t = self.conditions.get("time_s")
        if t is None or t.size < 3 or not np.all(np.diff(t) > 0):
            return
        m = self.valid[c]
        r = (self.measured[c] - pred)[m]
        seg = self.blocks[m]
        A = np.column_stack([np.ones(r.size), self.features()[m]])
        rho, lr = ar1_regression_ml(r, A, seg)
        if lr <= AR1_LR or rho <= 0.0:
            return
        u = ar1_whiten(r, seg, rho)
        s_w = max(noise_sigma(u, seg), floor * math.sqrt(1 - rho * rho))
        self.rho[c], self.sigma_w[c] = rho, s_w
        self.sigma[c] = s_w / math.sqrt(1 - rho * rho)

    def assemble(self, b: Baseline, s: Screening, fits, ho, passing, d: Decision, sep,
                 sep_items) -> dict:
        """The result dict: spec keys first, then the diagnostics."""
        th, cands = self.th, s.candidates
        base, base_ho, base_nuis, desc_base, structure = (b.fit, b.heldout_z, b.nuisance,
                                                          b.residuals, b.structure)
        verdict, cause, best, rivals, best_desc, joint, reasons = (
            d.verdict, d.cause, d.best, d.rivals, d.best_residuals, d.joint_fits, d.reasons)
        look = s.lookalike
        gen = self.chosen_form          # a generalised form of the cause (phase 5b) or None
        ext_fit = gen["fit"] if gen else fits[cause] if cause else base
        ext_ho = gen["heldout_z"] if gen else ho[cause] if cause else base_ho
        cause_params = ({p: v for p, v in gen["entry"]["parameters"].items()
                         if p in self.effect(cause).parameters} if gen else
                        dict(cands[cause].parameters) if cause else {})
        cause_unc = ({p: v for p, v in gen["entry"]["parameter_uncertainty"].items()
                      if p in self.effect(cause).parameters} if gen else
                     dict(cands[cause].uncertainty) if cause else {})
        base_rmse, base_ho_rmse = self.col_rmse(base.z), self.col_rmse(base_ho)
        ext_rmse, ext_ho_rmse = self.col_rmse(ext_fit.z), self.col_rmse(ext_ho)
        c0 = self.columns[0]
        ratio = ext_ho_rmse[c0] / base_ho_rmse[c0] if base_ho_rmse[c0] > 0 else 1.0

        fitted = sorted((n for n in cands if cands[n].fitted),
                        key=lambda n: (n not in passing, cands[n].delta_bic))
        rest = [n for n in cands if not cands[n].fitted]
        cand_list = [cands[n].to_json() for n in fitted + rest]
        result = {
            "verdict": verdict,
            "cause": cause,
            "parameters": cause_params,
            "indistinguishable": list(rivals),
            "separating_test": sep,
            "baseline": {"rmse": base_rmse, "heldout_rmse": base_ho_rmse},
            "extended": {"rmse": ext_rmse, "heldout_rmse": ext_ho_rmse},
            "gain": {"heldout_rmse_ratio": float(ratio)},
            "candidates": cand_list,
            # ---- extras
            "parameter_uncertainty": cause_unc,
            "extended_form": gen["entry"] if gen else None,
            "generalised_forms": list(self.generalised_forms),
            "reasons": reasons,
            "columns": list(self.columns),
            "noise_sigma": dict(self.sigma),
            "noise_sigma_source": {c: ("given" if c in self.user_sigma else
                                       self.sigma_source[c] + (f", AR(1) rho {self.rho[c]:.2f}"
                                                               if self.rho[c] else ""))
                                   for c in self.columns},
            "nuisance": {"names": list(self.nuis_names),
                         "bounds": {n: [float(a), float(b)] for n, a, b in
                                    zip(self.nuis_names, self.nuis_lo, self.nuis_hi)},
                         "baseline": base_nuis,
                         "extended": (gen["entry"]["nuisance"] if gen else
                                      cands[cause].nuisance if cause else base_nuis)},
            "residuals": {"baseline": desc_base, "extended": best_desc if cause else None,
                          "baseline_structure": bool(structure)},
            "best_partial": (None if verdict != "unexplained" or best is None else
                             {"effect": best, "parameters": cands[best].parameters,
                              "residuals": best_desc}),
            "lookalike": look,
            "joint_fits": joint,
            "separating_tests": sep_items,
            "not_identifiable": {n: cands[n].reason for n in cands
                                 if cands[n].status in ("not_identifiable", "not_applicable")},
            "heldout": {"blocks": int(self.n_blocks), "method": "contiguous blocks; parameters "
                        "refitted on the other blocks (one Gauss-Newton step from the full fit; "
                        "a profiled threshold re-selected over its grid, then all parameters "
                        "refitted by nonlinear least squares); paired block bootstrap of the "
                        "RMSE difference over the blocks that can test the effect"},
            "heldout_untestable": list(cands[cause].heldout_untestable or []) if cause else [],
            "thresholds": dict(th),
            "notes": list(self.notes),
            "spikes": dict(self.spikes),
            "n_rows": int(self.n),
            "n_predict_calls": int(self.model.calls),
            "predict_calls_by_phase": dict(self.calls_by_phase),
            "seconds": {"total": time.perf_counter() - self.t0, "predict": self.model.seconds},
            "seconds_by_phase": _phase_seconds(self.seconds_by_phase),
        }
        self.base_fit, self.ext_fit, self.fits = base, ext_fit, fits
        return jsonable(result)

    def _phase(self, label):
        done = sum(self.calls_by_phase.values())
        self.calls_by_phase[label] = self.model.calls - done
        self.seconds_by_phase[label] = {"total": time.perf_counter() - self.t0,
                                        "predict": self.model.seconds}

    def effect(self, name):
        return next(e for e in self.candidates if e.name == name)

    def parallel(self, task, items, first=None) -> list:
        """[task(item) for item in items] on the engine's `workers` processes
        (`studies.diagnosis.workers.fork_map`: the same results as serially)."""
        return fork_map(self.model, task, items, getattr(self, "workers", 1), first)



def _phase_seconds(cum: dict) -> dict:
    """Seconds spent in each phase (total and in model calls), from the cumulative clocks."""
    out, prev = {}, {"total": 0.0, "predict": 0.0}
    for label, c in cum.items():
        out[label] = {k: c[k] - prev[k] for k in ("total", "predict")}
        prev = c
    return out


# ============================================================================ public API
@dataclass
class DiagnosisOutcome:
    """Result dict (JSON-ready, spec keys first) plus the prediction tables for the report."""
    result: dict
    baseline_pred: dict[str, np.ndarray]
    extended_pred: dict[str, np.ndarray]
    candidate_preds: dict[str, dict[str, np.ndarray]]


def diagnose_full(predict: Callable[[dict, dict], Mapping[str, np.ndarray]],
                  measured: Mapping[str, np.ndarray], conditions: Mapping[str, np.ndarray],
                  candidates: Sequence, nuisance: Mapping[str, tuple], blocks=None, *,
                  noise_sigma: Mapping[str, float] | None = None, T_ref_C: float = 20.0,
                  predict_at: Callable | None = None, thresholds: Mapping | None = None,
                  seed: int = 0, columns: Sequence[str] | None = None,
                  generalised: bool = True, workers: int = 1) -> DiagnosisOutcome:
    """Run the diagnosis (see the module docstring) and return the result with predictions.

    predict(effects, nuisance) -> {column: array(n_rows)} on the measured conditions.
    measured: {output column: array(n_rows)} (NaN = not measured in that row).
    conditions: {condition column: array(n_rows)} (used for residual structure, profiles, probes).
    candidates: effect objects (`studies.model.effects.EFFECTS[name]`).
    nuisance: {name: (lo, hi[, start[, scale]])}, refitted with every model (e.g. mu_scale).
    blocks: held-out block label per row (contiguous time or test segments); None -> n_blocks
        contiguous blocks in row order.
    noise_sigma: known noise levels per column (default: estimated from the data).
    predict_at(effects, nuisance, conditions) -> outputs at other conditions (optional; used to
        find the separating test).
    generalised: try the generalised forms of the listed effects when the verdict would be
        `unexplained` (`studies.diagnosis.generalised`).
    workers: processes for the independent candidate work (fits, held-out refits, the local
        fits of a generalised form; `studies.diagnosis.workers`): the result does not depend on
        it, only the wall time (1: all in this process).
    """
    th = dict(DEFAULT_THRESHOLDS)
    th.update(thresholds or {})
    eng = _Engine(predict, measured, conditions, candidates, nuisance, blocks, noise_sigma,
                  T_ref_C, predict_at, th, seed, columns)
    eng.try_generalised = bool(generalised)
    eng.workers = int(workers)
    result = eng.run()
    return DiagnosisOutcome(result, eng.base_fit.pred, eng.ext_fit.pred,
                            {n: f.pred for n, f in eng.fits.items()})


def diagnose(*args, **kwargs) -> dict:
    """`diagnose_full(...)`.result: the JSON-ready dict."""
    return diagnose_full(*args, **kwargs).result


def lookalike_matrix(predict: Callable, measured: Mapping[str, np.ndarray],
                     conditions: Mapping[str, np.ndarray], candidates: Sequence, nuisance: Mapping,
                     noise_sigma: Mapping[str, float], T_ref_C: float,
                     predict_at: Callable | None = None) -> dict[str, dict[str, float]]:
    """Phases 1-2 only (baseline calibration and screening) on `measured`: the look-alike matrix
    {a: {b: largest cosine between the candidates' sensitivity subspaces}} of the identifiable
    candidates. On the model's own noise-free output it is a property of the test design alone
    (`studies.diagnosis.operating.lookalike_before_data`)."""
    eng = _Engine(predict, measured, conditions, candidates, nuisance, None, noise_sigma,
                  T_ref_C, predict_at, dict(DEFAULT_THRESHOLDS), 0, None)
    return eng.screen(eng.calibrate_baseline()).lookalike
