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
   profiled parameters are re-selected on the training rows), the held-out block is predicted with
   a real model call. A paired block bootstrap of the held-out RMSE difference (baseline minus
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
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy import optimize, stats

from studies.diagnosis.candidate import Candidate

DEFAULT_THRESHOLDS = {
    "alpha_structure": 0.01,    # residual-structure tests, Bonferroni over tests x columns
    "alpha_lr": 0.01,           # likelihood-ratio test, Holm over the candidates tested
    "bic_margin": 0.0,          # a candidate needs delta_bic < -bic_margin
    "heldout_quantile": 0.025,  # lower bootstrap quantile of the held-out RMSE gain must be > 0
    "n_boot": 2000,             # bootstrap resamples of the blocks
    "min_remaining": 0.10,      # share of the sensitivity left after projecting out the nuisance
    "min_reach_sigma": 3.0,     # projected change reachable inside the bounds (noise units, norm)
    "alpha_joint": 0.01,        # conditional likelihood-ratio tests of the joint fits
    "clear_chi2": 25.0,         # a rival whose chi-square is this much worse is beaten outright
    "alpha_residual": 0.001,    # structure left behind by the best candidate
    "lookalike_cos": 0.95,      # cosine above which two candidates are reported as look-alikes
    "n_blocks": 10,             # automatic contiguous blocks when no labels are given
}

FIRST_COLUMNS = ("torque_Nmm",)


class DiagnosisError(ValueError):
    """Unusable input to the engine (one-line message)."""


class ModelFailure(RuntimeError):
    """The model could not be evaluated (exception or non-finite output) at some parameters."""


# ============================================================================ small utilities
def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_jsonable(v) for v in x.tolist()]
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        x = float(x)
        return x if math.isfinite(x) else None
    return x


def chibar_pvalue(lr: float, n_free: int, n_bound: int) -> float:
    """P(chi-bar-square > lr): n_free unconstrained directions plus n_bound directions on a bound
    (each half chi-square with one df, taken as independent: binomial weights)."""
    lr = max(float(lr), 0.0)
    if n_free + n_bound == 0:
        return 1.0
    p = 0.0
    for j in range(n_bound + 1):
        w = math.comb(n_bound, j) / 2.0 ** n_bound
        df = n_free + j
        p += w * (stats.chi2.sf(lr, df) if df > 0 else (0.0 if lr > 0 else 1.0))
    return float(min(p, 1.0))


def noise_sigma(r: np.ndarray, seg: np.ndarray) -> float:
    """Noise standard deviation from second differences within segments (robustly trimmed at 4
    sigma; unbiased for white noise, blind to smooth structure, insensitive to a few steps)."""
    r = np.asarray(r, float)
    ok = np.isfinite(r)
    idx = np.flatnonzero(ok)
    if idx.size < 3:
        return float(np.nanstd(r)) if idx.size > 1 else 0.0
    a, b, c = idx[:-2], idx[1:-1], idx[2:]
    same = (seg[a] == seg[b]) & (seg[b] == seg[c])
    d2 = r[a[same]] - 2 * r[b[same]] + r[c[same]]
    if d2.size < 5:
        return float(np.std(r[ok], ddof=1))
    d2 = d2 - np.median(d2)            # a steady curvature of the residuals is not noise
    s_rob = 1.4826 * np.median(np.abs(d2)) / math.sqrt(6.0)
    if s_rob > 0:
        kept = d2[np.abs(d2) <= 4.0 * math.sqrt(6.0) * s_rob]
        d2 = kept if kept.size >= 5 else d2
    trunc = 1.0 - 2 * 4.0 * stats.norm.pdf(4.0) / (1 - 2 * stats.norm.sf(4.0))
    return float(math.sqrt(np.mean(d2 ** 2) / 6.0 / (trunc if s_rob > 0 else 1.0)))


def _auto_blocks(n: int, k: int) -> np.ndarray:
    k = max(2, min(k, n // 8 if n >= 16 else 2))
    return np.minimum((np.arange(n) * k) // n, k - 1)


def _orth(A: np.ndarray, rtol: float = 1e-8) -> np.ndarray:
    if A.size == 0 or A.shape[1] == 0:
        return np.zeros((A.shape[0], 0))
    U, s, _ = np.linalg.svd(A, full_matrices=False)
    if s.size == 0 or s[0] == 0:
        return np.zeros((A.shape[0], 0))
    return U[:, s > rtol * s[0]]


def _blsq(A: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """min ||A x - b|| subject to lo <= x <= hi (small dense problems; exact active set)."""
    x, *_ = np.linalg.lstsq(A, b, rcond=None)
    if np.all(x >= lo) and np.all(x <= hi):
        return x
    hi = np.maximum(hi, lo + 1e-15)
    return optimize.lsq_linear(A, b, bounds=(lo, hi), method="bvls").x


# ============================================================================ the model wrapper
class _Model:
    """predict() with a call counter and a small LRU cache."""

    def __init__(self, predict, n_rows, maxsize=512):
        self.predict = predict
        self.n = n_rows
        self.calls = 0
        self.seconds = 0.0
        self.cache: OrderedDict = OrderedDict()
        self.maxsize = maxsize

    def __call__(self, effects: dict, nuisance: dict) -> dict[str, np.ndarray]:
        key = (tuple(sorted((e, tuple(sorted((k, float(v)) for k, v in p.items())))
                            for e, p in effects.items())),
               tuple(sorted((k, float(v)) for k, v in nuisance.items())))
        hit = self.cache.get(key)
        if hit is not None:
            self.cache.move_to_end(key)
            return hit
        t0 = time.perf_counter()
        try:
            raw = self.predict({e: dict(p) for e, p in effects.items()}, dict(nuisance))
        except Exception as exc:  # the model's own failure at these parameters
            raise ModelFailure(f"{type(exc).__name__}: {exc}") from exc
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        out = {}
        for k, v in raw.items():
            a = np.asarray(v, dtype=float) if not isinstance(v, str) else None
            if a is not None and a.ndim == 1 and a.size == self.n:
                out[k] = a
        self.cache[key] = out
        if len(self.cache) > self.maxsize:
            self.cache.popitem(last=False)
        return out


# ============================================================================ parameter spaces
@dataclass
class _Space:
    """Fitted parameters in scaled coordinates u: value = origin + scale * u."""
    eff_params: list[tuple[str, str]]          # (effect name, parameter)
    fixed: dict[str, dict[str, float]]        # effect -> all its parameters at their fixed values
    nuis: list[str]
    origin: np.ndarray
    scale: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    def unpack(self, u) -> tuple[dict, dict]:
        v = self.origin + self.scale * np.asarray(u, float)
        v = np.clip(v, self.lo * self.scale + self.origin, self.hi * self.scale + self.origin)
        effects = {e: dict(p) for e, p in self.fixed.items()}
        k = len(self.eff_params)
        for (e, p), x in zip(self.eff_params, v[:k]):
            effects[e][p] = float(x)
        nuis = {n: float(x) for n, x in zip(self.nuis, v[k:])}
        return effects, nuis

    def values(self, u) -> np.ndarray:
        return self.origin + self.scale * np.asarray(u, float)

    def to_u(self, values) -> np.ndarray:
        return (np.asarray(values, float) - self.origin) / self.scale

    def clip(self, u) -> np.ndarray:
        return np.clip(u, self.lo, self.hi)

    @property
    def k(self):
        return len(self.eff_params)


@dataclass
class _Fit:
    space: _Space
    u: np.ndarray
    z: np.ndarray               # standardised residual (stacked), at u
    J: np.ndarray               # d z / d u at u
    chi2: float
    pred: dict
    extra: dict = field(default_factory=dict)


# ============================================================================ the engine
class _Engine:
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
        self.model = _Model(predict, self.n)
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
            self.blocks = _auto_blocks(self.n, int(th["n_blocks"]))
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
        self.entry_row = np.concatenate([np.flatnonzero(self.valid[c]) for c in self.columns])
        self.entry_col = np.concatenate([np.full(self.valid[c].sum(), j)
                                         for j, c in enumerate(self.columns)])
        self.entry_block = self.blocks[self.entry_row]
        self.N = self.entry_row.size
        self.user_sigma = dict(noise_sigma_ or {})
        self.sigma = {c: self._initial_sigma(c) for c in self.columns}
        self.notes: list[str] = []
        self.calls_by_phase: dict[str, int] = {}

    # ------------------------------------------------------------------ residuals
    def _initial_sigma(self, c):
        if c in self.user_sigma:
            return float(self.user_sigma[c])
        s = noise_sigma(self.measured[c], self.blocks)
        return s if s > 0 else 1.0

    def zvec(self, pred: dict) -> np.ndarray:
        parts = []
        for c in self.columns:
            m = self.valid[c]
            parts.append((self.measured[c][m] - pred[c][m]) / self.sigma[c])
        z = np.concatenate(parts)
        if not np.all(np.isfinite(z)):
            raise ModelFailure("the model returned non-finite values")
        return z

    # ------------------------------------------------------------------ spaces
    def space(self, effects: Sequence, fixed: dict | None = None) -> _Space:
        """Space fitting the non-profile parameters of `effects` (effect objects) + nuisance;
        `fixed` gives values for profiled parameters."""
        fixed = fixed or {}
        eff_params, origin, scale, lo, hi = [], [], [], [], []
        fx = {}
        for e in effects:
            steps = e.steps(self.conditions)
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
        return _Space(eff_params, fx, list(self.nuis_names), np.array(origin, float),
                      np.array(scale, float), np.array(lo, float), np.array(hi, float))

    def eval(self, space: _Space, u) -> tuple[np.ndarray, dict]:
        pred = self.model(*space.unpack(space.clip(u)))
        return self.zvec(pred), pred

    def fit(self, space: _Space, u0, max_nfev=None) -> _Fit:
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
        return _Fit(space, res.x, z, np.asarray(res.jac, float), float(z @ z), pred)

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
            z = r / s
            nn = z.size
            bias = float(np.mean(r))
            bias_p = float(2 * stats.norm.sf(abs(np.mean(z)) * math.sqrt(nn)))
            chi2_red = float(z @ z / max(nn - n_params, 1))
            # lag-1 autocorrelation within blocks, in row order
            seg = self.blocks[m]
            zc = z - z.mean()
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
            A = np.column_stack([np.ones(nn), X])
            q = _orth(A)
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
                sse_0 += float(np.sum((z[te] - z[tr].mean()) ** 2))
            cv_gain = 1.0 - sse_cv / sse_0 if sse_0 > 0 else 0.0
            out[c] = {"bias": bias, "bias_p": bias_p, "rmse": float(np.sqrt(np.mean(r ** 2))),
                      "noise_sigma": s, "chi2_reduced": chi2_red, "lag1_autocorr": r1,
                      "lag1_p": auto_p, "smoother_F": float(Fst), "smoother_p": F_p,
                      "smoother_heldout_gain": float(cv_gain)}
            pvals += [bias_p, auto_p, F_p]
        p_min = min(pvals)
        p_adj = min(1.0, p_min * len(pvals))
        return {"columns": out, "p_min_adjusted": p_adj}

    # ------------------------------------------------------------------ sensitivities
    def free_params(self, e) -> list[str]:
        """Parameters fitted by gradients: not profiled, not held at "off" for these conditions
        (e.g. a speed-proportional part when every row has the same speed)."""
        held = set(e.held_fixed(self.conditions))
        return [p for p in e.parameters if p not in e.profile and p not in held]

    def sensitivity(self, e, base_nuis: dict, base_pred: dict, fixed: dict | None = None):
        """d(pred)/sigma per unit step of each non-profile parameter at off (N x k, stacked)."""
        steps = e.steps(self.conditions)
        cols = []
        names = []
        for p in self.free_params(e):
            params = dict(e.off)
            params.update(fixed or {})
            lo, hi = e.bounds[p]
            h = float(steps.get(p, e.scale[p]))
            if e.off[p] + h > hi:
                h = -h
            params[p] = e.off[p] + h
            pred = self.model({e.name: params}, base_nuis)
            # d(pred)/sigma per unit scaled step in the +u direction
            cols.append(-(self.zvec(pred) - self.zvec(base_pred)) * np.sign(h))
            names.append(p)
        return (np.column_stack(cols) if cols else np.zeros((self.N, 0))), names

    # ------------------------------------------------------------------ held-out
    def heldout_linear(self, fit: _Fit) -> np.ndarray:
        """Held-out standardised residual per stacked entry: per fold, one bounded Gauss-Newton
        step from `fit` on the training entries (halved once if it does not lower the training
        chi-square), then a real model call."""
        z_ho = np.empty(self.N)
        sp = fit.space
        for b in range(self.n_blocks):
            te = self.entry_block == b
            tr = ~te
            if not te.any():
                continue
            J, z = fit.J[tr], fit.z[tr]
            if J.shape[1]:
                lo = np.minimum(sp.lo - fit.u, 0.0)
                hi = np.maximum(sp.hi - fit.u, 0.0)
                du = _blsq(J, -z, lo, hi)
            else:
                du = np.zeros(0)
            sse0 = float(z @ z)
            for damp in (1.0, 0.5):
                try:
                    zz, _ = self.eval(sp, sp.clip(fit.u + damp * du))
                except ModelFailure:
                    continue
                if float(zz[tr] @ zz[tr]) <= sse0 * (1 + 1e-9):
                    break
            else:
                zz = fit.z             # keep the full-data fit (no better training fit found)
            z_ho[te] = zz[te]
        return z_ho

    def heldout_profile(self, grid_lin: list[dict], e) -> tuple[np.ndarray, list]:
        """Held-out residuals for a profiled candidate: re-select the profiled value per fold from
        the linearisations stored for every grid value."""
        z_ho = np.empty(self.N)
        chosen = []
        for b in range(self.n_blocks):
            te = self.entry_block == b
            tr = ~te
            if not te.any():
                continue
            best = None
            for g in grid_lin:
                x = _blsq(g["J"][tr], -g["z"][tr], g["lo"], g["hi"])
                sse = float(np.sum((g["z"][tr] + g["J"][tr] @ x) ** 2))
                if best is None or sse < best[0]:
                    best = (sse, g, x)
            _, g, du = best
            zz, _ = self.eval(g["space"], g["u0"] + du)     # ModelFailure -> candidate fails
            z_ho[te] = zz[te]
            chosen.append(g["value"])
        return z_ho, chosen

    def bootstrap_gain(self, z_base_ho, z_cand_ho) -> dict:
        """Paired block bootstrap of RMSE(baseline) - RMSE(candidate), standardised, held-out."""
        B = int(self.th["n_boot"])
        sb = np.bincount(self.entry_block, weights=z_base_ho ** 2, minlength=self.n_blocks)
        sc = np.bincount(self.entry_block, weights=z_cand_ho ** 2, minlength=self.n_blocks)
        nb = np.bincount(self.entry_block, minlength=self.n_blocks).astype(float)
        idx = self.rng.integers(0, self.n_blocks, size=(B, self.n_blocks))
        cnt = np.zeros((B, self.n_blocks))
        np.add.at(cnt, (np.repeat(np.arange(B), self.n_blocks), idx.ravel()), 1.0)
        nn = cnt @ nb
        d = np.sqrt(cnt @ sb / nn) - np.sqrt(cnt @ sc / nn)
        q = float(self.th["heldout_quantile"])
        point = math.sqrt(sb.sum() / nb.sum()) - math.sqrt(sc.sum() / nb.sum())
        lo, hi = np.quantile(d, [q, 1 - q])
        return {"rmse_gain": float(point), "ci": [float(lo), float(hi)],
                "blocks_improved": int(np.sum(sb > sc)), "n_blocks": int(self.n_blocks),
                "excludes_zero": bool(lo > 0)}

    def col_rmse(self, z_stacked) -> dict[str, float]:
        out = {}
        for j, c in enumerate(self.columns):
            zz = z_stacked[self.entry_col == j]
            out[c] = float(np.sqrt(np.mean(zz ** 2)) * self.sigma[c])
        return out

    # ------------------------------------------------------------------ run
    def run(self):
        th = self.th
        # ---- 1. baseline calibration (two passes: sigma from the measured data, then from the
        #         baseline residuals)
        bspace = self.space([])
        base = self.fit(bspace, np.zeros(bspace.k + len(self.nuis_names)))
        for c in self.columns:
            if c not in self.user_sigma:
                s = noise_sigma(self.measured[c] - base.pred[c], self.blocks)
                scale = max(np.nanmax(np.abs(self.measured[c])), 1e-300)
                self.sigma[c] = max(s, 1e-12 * scale)
        base = self.fit(bspace, base.u)
        base_nuis = bspace.unpack(base.u)[1]
        n_nuis = len(self.nuis_names)
        desc_base = self.describe(base.pred, n_nuis)
        structure = desc_base["p_min_adjusted"] < th["alpha_structure"]
        lnN = math.log(self.N)
        base_ho = self.heldout_linear(base)
        Qn = _orth(base.J)

        self._phase("baseline")
        # ---- 2. sensitivities, identifiability, look-alikes
        cands = {}
        proj = {}
        for e in self.candidates:
            info = Candidate(e.name)
            cands[e.name] = info
            why = e.applicable(self.conditions)
            grid = {}
            if why is None and e.profile:
                grid = e.grid(self.conditions, self.T_ref_C)
                if any(len(v) == 0 for v in grid.values()):
                    why = "no value of " + ", ".join(e.profile) + " changes the prediction here"
            if why is not None:
                info.set_status("not_applicable", why)
                continue
            fixed = {p: float(np.median(grid[p])) for p in e.profile}
            try:
                Jc, names = self.sensitivity(e, base_nuis, base.pred, fixed)
            except ModelFailure as exc:
                info.set_status("model_failed", f"model failed with the effect on: {exc}")
                continue
            Jp = Jc - Qn @ (Qn.T @ Jc)
            raw = np.linalg.norm(Jc, axis=0)
            left = np.linalg.norm(Jp, axis=0)
            frac = np.where(raw > 0, left / np.where(raw > 0, raw, 1.0), 0.0)
            reach = 0.0
            for i, p in enumerate(names):
                lo, hi = e.bounds[p]
                h = float(e.steps(self.conditions).get(p, e.scale[p]))
                reach = max(reach, left[i] * max(abs(hi - e.off[p]), abs(lo - e.off[p])) / h)
            info.identifiability = {"remaining_fraction": dict(zip(names, frac)),
                                       "reach_sigma": float(reach)}
            if not np.any(raw > 1e-9):
                info.set_status("not_identifiable",
                                "the measured outputs do not depend on it here")
                continue
            if frac.max() < th["min_remaining"]:
                info.set_status("not_identifiable",
                                "the baseline calibration (" + ", ".join(self.nuis_names)
                                + ") absorbs it")
                continue
            if reach < th["min_reach_sigma"]:
                info.set_status("not_identifiable",
                                "too small inside its physical bounds to be seen at this noise")
                continue
            Q = _orth(Jp, 1e-6)
            proj[e.name] = Q
            info.sensitivity = Jc
            info.profile_fixed = fixed
            info.profile_grid = grid
            info.rank = int(Q.shape[1])
        names_id = list(proj)
        look = {a: {b: (float(np.linalg.svd(proj[a].T @ proj[b], compute_uv=False).max())
                        if proj[a].shape[1] and proj[b].shape[1] else 0.0)
                    for b in names_id} for a in names_id}

        self._phase("sensitivities")
        # ---- 3. fits
        fits: dict[str, _Fit] = {}
        for name in list(names_id):
            e = self._effect(name)
            info = cands[name]
            calls0 = self.model.calls
            try:
                if e.profile:
                    fits[name] = self.fit_profiled(e, info, base, base_nuis)
                else:
                    fits[name] = self.fit_candidate(e, info, base)
            except ModelFailure as exc:
                info.set_status("model_failed", f"fit failed: {exc}")
                names_id.remove(name)
                continue
            f = fits[name]
            info.predict_calls_fit = self.model.calls - calls0
            lr = max(base.chi2 - f.chi2, 0.0)
            r = info.rank
            n_two = sum(1 for p in self.free_params(e) if e.sign(p) == 0)
            n_free = min(r, n_two) + len(e.profile)
            n_bound = r - min(r, n_two)
            k_eff = r + len(e.profile)
            info.lr = lr
            info.df = {"free": n_free, "on_bound": n_bound}
            info.p_lr = chibar_pvalue(lr, n_free, n_bound)
            info.delta_bic = -lr + k_eff * lnN
            info.k = k_eff
            eff_vals, nuis_vals = f.space.unpack(f.u)
            info.parameters = {p: eff_vals[name][p] for p in e.parameters}
            held = list(e.held_fixed(self.conditions))
            if held:
                info.held_at_off = {p: e.off[p] for p in held}
            info.nuisance = nuis_vals
            info.uncertainty = self.uncertainty(f, e)
            info.rmse = self.col_rmse(f.z)
        # Holm over the identifiable candidates
        order = sorted(names_id, key=lambda n: cands[n].p_lr)
        m = len(order)
        still = True
        for j, name in enumerate(order):
            ok = still and cands[name].p_lr <= th["alpha_lr"] / (m - j)
            still = ok
            cands[name].lr_significant = bool(ok)

        self._phase("fits")
        # ---- 4. held-out gains
        ho = {}
        for name in list(names_id):
            e = self._effect(name)
            try:
                if e.profile:
                    ho[name], chosen = self.heldout_profile(fits[name].extra["grid_lin"], e)
                    cands[name].heldout_profile_values = chosen
                else:
                    ho[name] = self.heldout_linear(fits[name])
            except ModelFailure as exc:
                # no honest held-out number: the candidate cannot pass
                cands[name].heldout_failed = str(exc)
                ho[name] = base_ho.copy()
            cands[name].heldout_rmse = self.col_rmse(ho[name])
            cands[name].heldout_gain = self.bootstrap_gain(base_ho, ho[name])
        passing = []
        for name in names_id:
            c = cands[name]
            reasons = []
            if not c.lr_significant:
                reasons.append(f"likelihood ratio not significant (p = {c.p_lr:.2g}, Holm)")
            if not c.delta_bic < -th["bic_margin"]:
                reasons.append(f"BIC not better than the baseline (delta {c.delta_bic:.1f})")
            if not c.heldout_gain["excludes_zero"]:
                reasons.append("no held-out gain beyond noise (bootstrap interval "
                               f"[{c.heldout_gain['ci'][0]:.3g}, "
                               f"{c.heldout_gain['ci'][1]:.3g}] includes 0)")
            c.status = "passed" if not reasons else "rejected"
            c.reason = "; ".join(reasons) if reasons else "beats the baseline in sample and " \
                                                             "on held-out blocks"
            if not reasons:
                passing.append(name)

        self._phase("heldout")
        # ---- 5. decide
        verdict, cause, rivals, best_desc, joint = "no_discrepancy", None, [], None, {}
        best = min(passing, key=lambda n: cands[n].delta_bic) if passing else None
        reasons = []
        if best is None:
            if structure:
                verdict = "unexplained"
                reasons.append("the baseline residuals show structure beyond noise "
                               f"(adjusted p = {desc_base['p_min_adjusted']:.2g}) but no "
                               "candidate passes")
                cols = desc_base["columns"].values()
                if all(d["smoother_heldout_gain"] <= 0 and d["bias_p"] > 0.01 for d in cols):
                    reasons.append("the structure is serial correlation that a smooth function "
                                   "of the conditions does not predict on held-out blocks: it may "
                                   "be correlated noise, a drift in time or a history effect "
                                   "outside the candidate list")
            else:
                reasons.append("the baseline residuals are consistent with the noise estimated "
                               "from the data and no candidate passes")
        else:
            best_desc = self.describe(fits[best].pred, n_nuis + cands[best].k)
            if best_desc["p_min_adjusted"] < th["alpha_residual"]:
                verdict = "unexplained"
                reasons.append(f"the best candidate, {best}, passes but leaves structure in the "
                               f"residuals (adjusted p = {best_desc['p_min_adjusted']:.2g})")
            else:
                rivals, joint = self.compare(best, fits, cands, names_id)
                for o in passing:
                    if o != best and o not in rivals:
                        cands[o].reason += (f"; but clearly beaten by {best} (chi-square "
                                               f"{fits[o].chi2 - fits[best].chi2:+.1f})")
                verdict = "ambiguous" if rivals else "explained"
                cause = best
                if rivals:
                    reasons.append(f"{best} and {', '.join(rivals)} explain the data about "
                                   "equally well")
                else:
                    reasons.append(f"{best} beats the baseline on held-out blocks and clearly "
                                   "beats every other candidate")
        self.verdict, self.cause, self.best = verdict, cause, best
        self._phase("compare")
        # ---- separating test
        sep, sep_items = None, []
        if verdict == "ambiguous":
            sep, sep_items = self.separating(best, rivals, fits, base)

        self._phase("separating")
        # ---- assemble
        ext_fit = fits[cause] if cause else base
        ext_ho = ho[cause] if cause else base_ho
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
            "parameters": dict(cands[cause].parameters) if cause else {},
            "indistinguishable": list(rivals),
            "separating_test": sep,
            "baseline": {"rmse": base_rmse, "heldout_rmse": base_ho_rmse},
            "extended": {"rmse": ext_rmse, "heldout_rmse": ext_ho_rmse},
            "gain": {"heldout_rmse_ratio": float(ratio)},
            "candidates": cand_list,
            # ---- extras
            "parameter_uncertainty": dict(cands[cause].uncertainty) if cause else {},
            "reasons": reasons,
            "columns": list(self.columns),
            "noise_sigma": dict(self.sigma),
            "noise_sigma_source": {c: ("given" if c in self.user_sigma else
                                       "second differences of the baseline residuals")
                                   for c in self.columns},
            "nuisance": {"names": list(self.nuis_names),
                         "bounds": {n: [float(a), float(b)] for n, a, b in
                                    zip(self.nuis_names, self.nuis_lo, self.nuis_hi)},
                         "baseline": base_nuis,
                         "extended": (cands[cause].nuisance if cause else base_nuis)},
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
                        "refitted on the other blocks (one Gauss-Newton step from the full fit); "
                        "paired block bootstrap of the RMSE difference"},
            "thresholds": dict(th),
            "notes": list(self.notes),
            "n_rows": int(self.n),
            "n_predict_calls": int(self.model.calls),
            "predict_calls_by_phase": dict(self.calls_by_phase),
            "seconds": {"total": time.perf_counter() - self.t0, "predict": self.model.seconds},
        }
        self.base_fit, self.ext_fit, self.fits = base, ext_fit, fits
        return _jsonable(result)

    # ------------------------------------------------------------------ pieces of run
    def _phase(self, label):
        done = sum(self.calls_by_phase.values())
        self.calls_by_phase[label] = self.model.calls - done

    def _effect(self, name):
        return next(e for e in self.candidates if e.name == name)

    def _nuis_correct(self, z, Jn):
        """Residual after the best linear nuisance correction (for choosing starts)."""
        if Jn.shape[1] == 0:
            return z
        d, *_ = np.linalg.lstsq(Jn, -z, rcond=None)
        return z + Jn @ d

    def fit_candidate(self, e, info, base: _Fit) -> _Fit:
        space = self.space([e])
        k = space.k
        nq = len(self.nuis_names)
        Jn = base.J                       # d z / d u_nuisance at the baseline
        Jc = -info.sensitivity                 # d z / d u_effect at off (sensitivity is -dz)
        u_nuis = base.u
        starts = []
        # Gauss-Newton step from off
        A = np.column_stack([Jc, Jn])
        d, *_ = np.linalg.lstsq(A, -base.z, rcond=None)
        starts.append(np.concatenate([d[:k], u_nuis + d[k:]]))
        for s in e.starts(self.conditions, self.T_ref_C):
            vals = [s.get(p, e.off[p]) for (_, p) in space.eff_params]
            uu = np.concatenate([(np.array(vals) - space.origin[:k]) / space.scale[:k], u_nuis])
            starts.append(uu)
        scored = []
        for uu in starts:
            uu = space.clip(uu)
            try:
                z, _ = self.eval(space, uu)
            except ModelFailure:
                continue
            if nq:
                dn, *_ = np.linalg.lstsq(Jn, -z, rcond=None)
                uu = space.clip(np.concatenate([uu[:k], uu[k:] + dn]))
                zc = z + Jn @ dn
            else:
                zc = z
            scored.append((float(zc @ zc), len(scored), uu))
        if not scored:
            raise ModelFailure("the model fails at every starting point")
        scored.sort(key=lambda t: t[:2])
        # local optimisation from the two most promising starts (fits that open or close, lags
        # and thresholds make the problem non-convex)
        # the Gauss-Newton step from "off" (index 0) is always refined too: a grid start can sit
        # where a fit is open and the outputs do not depend on a parameter (a flat local minimum)
        gn = [t for t in scored if t[1] == 0 and t not in scored[:2]]
        f = None
        for sse0, idx, uu in scored[:2] + gn:
            if f is not None and idx != 0 and sse0 > f.chi2 + max(10.0, 0.2 * (base.chi2 - f.chi2)):
                continue                  # not promising enough
            try:
                fi = self.fit(space, uu)
            except ModelFailure:
                continue
            if f is None or fi.chi2 < f.chi2:
                f = fi
        if f is None:
            raise ModelFailure("the fits fail from every starting point")
        if f.chi2 > base.chi2:           # never worse than the baseline (off is admissible)
            f2 = self.fit(space, np.concatenate([np.zeros(k), base.u]))
            f = f2 if f2.chi2 < f.chi2 else f
        return f

    def fit_profiled(self, e, info, base: _Fit, base_nuis) -> _Fit:
        """Profile the `profile` parameter (one) over its grid with a linearised inner fit, then
        refine the best value with a full bounded least-squares fit."""
        (pp,) = e.profile
        values = list(info.profile_grid[pp])
        nq = len(self.nuis_names)

        def lin(value):
            space = self.space([e], fixed={e.name: {pp: value}})
            k = space.k
            cols = []
            for i in range(k):
                du = np.zeros(k + nq)
                du[i] = 1.0 if space.hi[i] >= 1.0 else -1.0
                z, _ = self.eval(space, np.concatenate([du[:k], base.u]))
                cols.append((z - base.z) / du[i])
            J = np.column_stack(cols + [base.J])
            u0 = np.concatenate([np.zeros(k), base.u])
            lo, hi = space.lo - u0, space.hi - u0
            x = _blsq(J, -base.z, lo, hi)
            sse = float(np.sum((base.z + J @ x) ** 2))
            return {"value": value, "space": space, "J": J, "z": base.z, "u0": u0, "lo": lo,
                    "hi": hi, "sse": sse, "du": x}

        def lin_safe(value):
            try:
                return lin(value)
            except ModelFailure:
                return None

        if len(values) > 16:
            # coarse grid, then bisect towards the best onset on both sides
            lins = {int(i): lin_safe(values[i])
                    for i in np.unique(np.linspace(0, len(values) - 1, 12).round().astype(int))}
            while True:
                ok = sorted(i for i in lins if lins[i] is not None)
                if not ok:
                    break
                ib = min(ok, key=lambda i: lins[i]["sse"])
                left = max([i for i in lins if i < ib], default=None)
                right = min([i for i in lins if i > ib], default=None)
                new = [m for m in ((None if left is None else (left + ib) // 2),
                                   (None if right is None else (ib + right + 1) // 2))
                       if m is not None and m not in lins]
                if not new:
                    break
                for m in new:
                    lins[m] = lin_safe(values[m])
            grid_lin = [lins[i] for i in sorted(lins) if lins[i] is not None]
        else:
            grid_lin = [g for g in map(lin_safe, values) if g is not None]
        if not grid_lin:
            raise ModelFailure(f"the model fails for every {pp} on the grid")
        ranked = sorted(grid_lin, key=lambda g: g["sse"])
        ranked = [g for g in ranked[:2] if g["sse"] <= ranked[0]["sse"] + 1.0]
        best = None
        for g in ranked:
            try:
                f = self.fit(g["space"], g["u0"] + g["du"])
            except ModelFailure:
                continue
            if best is None or f.chi2 < best.chi2:
                best = f
                best.extra["value"] = g["value"]
        if best is None:
            raise ModelFailure(f"the fits at the best values of {pp} fail")
        # profile interval: values whose linearised chi-square is within 1 of the best
        sse_min = min(g["sse"] for g in grid_lin)
        near = [g["value"] for g in grid_lin if g["sse"] <= sse_min + 1.0]
        best.extra.update(grid_lin=grid_lin, interval=[min(near), max(near)])
        info.profile = {pp: {"grid_size": len(values), "evaluated": len(grid_lin),
                                "interval_chi2_1": [min(near), max(near)]}}
        return best

    def uncertainty(self, f: _Fit, e) -> dict:
        """Standard uncertainty of the fitted effect parameters (linearised, scaled by the
        reduced chi-square when above 1); None when not separately identifiable."""
        J = f.J
        dof = max(self.N - J.shape[1], 1)
        s2 = max(1.0, f.chi2 / dof)
        out = {}
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        tiny = s < 1e-8 * (s[0] if s.size else 1.0)
        with np.errstate(divide="ignore"):
            inv = np.where(tiny, np.inf, 1.0 / np.where(tiny, 1.0, s) ** 2)
        for i, (en, p) in enumerate(f.space.eff_params):
            v = Vt[:, i]
            if np.any(tiny & (np.abs(v) > 1e-6)):
                out[p] = None
            else:
                out[p] = float(math.sqrt(s2 * np.sum(v ** 2 * np.where(tiny, 0.0, inv)))
                               * f.space.scale[i])
        if "interval" in f.extra:
            for p in e.profile:
                out[p] = {"interval": f.extra["interval"]}
        return out

    def compare(self, best, fits, cands, names_id):
        """Rivals of `best`: fitted candidates it does not clearly beat (joint fits)."""
        th = self.th
        rivals, joint = [], {}
        eb = self._effect(best)
        fb = fits[best]
        for o in names_id:
            if o == best:
                continue
            fo = fits[o]
            if fo.chi2 - fb.chi2 > th["clear_chi2"]:
                continue
            eo = self._effect(o)
            fixed = {}
            for e, f in ((eb, fb), (eo, fo)):
                if e.profile:
                    fixed[e.name] = {p: f.extra["value"] for p in e.profile}
            space = self.space([eb, eo], fixed)
            kb = fb.space.k
            ko = fo.space.k
            starts = [np.concatenate([fb.u[:kb], np.zeros(ko), fb.u[kb:]]),
                      np.concatenate([np.zeros(kb), fo.u[:ko], fo.u[ko:]])]
            try:
                zs = []
                for s0 in starts:
                    try:
                        z0 = self.eval(space, s0)[0]
                        zs.append(float(z0 @ z0))
                    except ModelFailure:
                        zs.append(math.inf)
                fj = self.fit(space, starts[int(np.argmin(zs))])
            except ModelFailure as exc:    # cannot show that best carries the weight
                joint[o] = {"error": str(exc), "best_carries_weight": False}
                rivals.append(o)
                continue
            chi_j = min(fj.chi2, fb.chi2, fo.chi2)
            lr_o_given_b = max(fb.chi2 - chi_j, 0.0)
            lr_b_given_o = max(fo.chi2 - chi_j, 0.0)
            p_o = chibar_pvalue(lr_o_given_b, **_df(cands[o]))
            p_b = chibar_pvalue(lr_b_given_o, **_df(cands[best]))
            beaten = p_b < th["alpha_joint"] and p_o >= th["alpha_joint"]
            joint[o] = {"chi2_best": fb.chi2, "chi2_other": fo.chi2, "chi2_joint": chi_j,
                        "p_add_other_to_best": p_o, "p_add_best_to_other": p_b,
                        "best_carries_weight": bool(beaten)}
            if not beaten:
                rivals.append(o)
        rivals.sort(key=lambda n: cands[n].delta_bic)
        return rivals, joint

    # ------------------------------------------------------------------ separating test
    def probes(self):
        c = self.conditions
        T0 = self.T_ref_C
        out = []
        for col, label in (("speed_rpm", "speed"), ("preload_assembled_N", "preload"),
                           ("axial_load_N", "axial load")):
            if col in c and np.any(c[col] != 0):
                for f in (0.5, 2.0):
                    d = dict(c)
                    d[col] = c[col] * f
                    out.append((f"repeat at {f:g} x the {label} ({col} {_rng(d[col])})", d))
        if "T_ambient_C" in c:
            d = dict(c)
            d["T_ambient_C"] = T0 + 1.5 * (c["T_ambient_C"] - T0)
            out.append(("extend the temperature range by 50 % about the reference temperature "
                        f"(T_ambient_C {_rng(d['T_ambient_C'])})", d))
            d = dict(c)
            d["T_ambient_C"] = T0 - (c["T_ambient_C"] - T0)
            out.append(("mirror the temperature programme about the reference temperature "
                        f"(T_ambient_C {_rng(d['T_ambient_C'])})", d))
        if "time_s" in c:
            for f, txt in ((0.25, "4 x faster"), (4.0, "4 x slower")):
                d = dict(c)
                d["time_s"] = c["time_s"][0] + f * (c["time_s"] - c["time_s"][0])
                out.append((f"run the temperature programme {txt} (time_s scaled by {f:g})", d))
        return out

    def separating(self, best, rivals, fits, base):
        items = []
        fb = fits[best]
        eb_eff, eb_nuis = fb.space.unpack(fb.u)
        for o in rivals:
            fo = fits[o]
            eo_eff, eo_nuis = fo.space.unpack(fo.u)
            # a) within the measured conditions
            zb = fb.pred
            zo = fo.pred
            best_row, best_d, best_col = None, -1.0, None
            for c in self.columns:
                d = np.abs(zb[c] - zo[c]) / self.sigma[c]
                i = int(np.argmax(d))
                if d[i] > best_d:
                    best_row, best_d, best_col = i, float(d[i]), c
            items.append({"pair": [best, o], "kind": "measured_conditions",
                          "max_diff_sigma": best_d, "column": best_col,
                          "at": {k: float(v[best_row]) for k, v in self.conditions.items()},
                          "text": f"within the measured conditions {best} and {o} differ by at "
                                  f"most {best_d:.2g} sigma in {best_col}"})
            # b) unmeasured outputs
            for c in zb:
                if c in self.columns or c not in zo or c not in base.pred:
                    continue
                d = np.abs(zb[c] - zo[c])
                ref = np.abs(base.pred[c])
                mag = max(float(np.max(ref)), 1e-12)
                if d.max() > 0.01 * mag:
                    i = int(np.argmax(d))
                    items.append({"pair": [best, o], "kind": "unmeasured_output", "column": c,
                                  "max_diff": float(d[i]), "relative": float(d[i] / mag),
                                  "at": {k: float(v[i]) for k, v in self.conditions.items()},
                                  "text": f"measure {c}: {best} and {o} predict values that "
                                          f"differ by up to {d[i]:.3g} ({100 * d[i] / mag:.0f} % "
                                          "of its size)"})
            # c) probe conditions
            if self.predict_at is not None:
                for text, cond in self.probes():
                    try:
                        pb = self.predict_at(eb_eff, eb_nuis, cond)
                        po = self.predict_at(eo_eff, eo_nuis, cond)
                        if not all(np.all(np.isfinite(np.asarray(x[c], float)))
                                   for x in (pb, po) for c in self.columns):
                            raise ValueError("non-finite prediction")
                    except Exception as exc:  # a probe outside the model's range: skip it
                        self.notes.append(f"probe skipped ({text}): {exc}")
                        continue
                    dmax, col = 0.0, None
                    for c in self.columns:
                        d = float(np.max(np.abs(np.asarray(pb[c], float)
                                                - np.asarray(po[c], float))) / self.sigma[c])
                        if d > dmax:
                            dmax, col = d, c
                    items.append({"pair": [best, o], "kind": "probe", "max_diff_sigma": dmax,
                                  "column": col, "text": f"{text}: {best} and {o} then differ "
                                  f"by up to {dmax:.2g} sigma in {col}"})
        # summary text: best probe, best unmeasured output, the physics hints
        parts = []
        probes = sorted((i for i in items if i["kind"] == "probe"),
                        key=lambda i: -i["max_diff_sigma"])
        if probes and probes[0]["max_diff_sigma"] >= 2.0:
            parts.append(probes[0]["text"])
        unmeas = sorted((i for i in items if i["kind"] == "unmeasured_output"),
                        key=lambda i: -i["relative"])
        if unmeas:
            parts.append(unmeas[0]["text"])
        hints = [f"{n}: {self._effect(n).hint}" for n in [best] + list(rivals)
                 if self._effect(n).hint]
        if not parts:
            meas = [i for i in items if i["kind"] == "measured_conditions"]
            parts.append(meas[0]["text"] + " (not separable with this test design)")
        text = "; or ".join(parts) + ". Physics: " + " | ".join(hints)
        return text, items


def _df(c):
    return {"n_free": c.df["free"], "n_bound": c.df["on_bound"]}


def _rng(a):
    a = np.asarray(a, float)
    return f"{a.min():.4g}..{a.max():.4g}" if a.min() != a.max() else f"{a.min():.4g}"


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
                  seed: int = 0, columns: Sequence[str] | None = None) -> DiagnosisOutcome:
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
    """
    th = dict(DEFAULT_THRESHOLDS)
    th.update(thresholds or {})
    eng = _Engine(predict, measured, conditions, candidates, nuisance, blocks, noise_sigma,
                  T_ref_C, predict_at, th, seed, columns)
    result = eng.run()
    return DiagnosisOutcome(result, eng.base_fit.pred, eng.ext_fit.pred,
                            {n: f.pred for n, f in eng.fits.items()})


def diagnose(*args, **kwargs) -> dict:
    """`diagnose_full(...)`.result: the JSON-ready dict."""
    return diagnose_full(*args, **kwargs).result
