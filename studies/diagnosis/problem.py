"""What one diagnosis works on, immutable: the measured data, the cached model, the nuisance, the
held-out blocks, the noise model, and the computations every phase shares on them (standardised
residuals, parameter spaces, a bounded least-squares fit, the residual description).

`make_problem` checks the inputs (one-line `DiagnosisError`s) and fixes the compared columns; the
calibration phase (`studies.diagnosis.calibration`) returns a new `Problem` with the noise model
estimated from the baseline residuals and any sensor spikes left out. No phase changes a
`Problem`: each gets it as an argument, with the typed results of the phases before it
(`Baseline`, `Screening`, `Fitting`, `Validation`, `Decision`, ...).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from functools import cached_property, wraps
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy import optimize, stats

from studies.diagnosis import fitspec
from studies.diagnosis.core import (FIRST_COLUMNS, CachedModel, ColumnResiduals, DiagnosisError,
                                    Fit, ModelFailure, Residuals, Space)
from studies.diagnosis.stats import (ar1_unwhiten, ar1_whiten, auto_blocks, noise_sigma,
                                     noise_sigma_steady, orth)
from studies.model.parallel import parallel_map

#: scaled coordinates below this size start a fit at exactly 0 (`Problem.fit`)
TINY_U = 1e-9

#: a fit stops after STOP_AFTER consecutive accepted steps that each lowered the chi-square (sum
#: of squared standardised residuals, dimensionless) by less than DCHI2_STOP (`Problem.fit`):
#: Press et al., Numerical Recipes, 3rd ed., ch. 15.5.2 (stop after the first or second time chi2
#: decreases by a negligible amount, less than 0.01 absolutely: the parameters' confidence
#: regions are set by changes of chi2 of order 1, so further steps move them by a small share of
#: a standard uncertainty). On the 14 h transient-FE history of `bench --diagnose` 290 of the
#: selection's recalibration's 311 model calls gained 0.28 chi2 in all.
DCHI2_STOP = 0.01
STOP_AFTER = 2

#: relative noise floor: a CSV keeps 10 significant digits (half a unit in the last is 5e-10 of the
#: value); twice that, so that round-off alone never looks like structure
ROUND_OFF = 1e-9


class NegligibleSteps:
    """`scipy.optimize.least_squares` callback that stops the fit (StopIteration) after
    STOP_AFTER consecutive accepted steps each lowering chi2 = 2 x cost (dimensionless) by less
    than DCHI2_STOP (Numerical Recipes ch. 15.5.2, module constants); `chi2_start` is the
    start's chi-square. The trust-region method calls it once per iteration, after the step
    and the Jacobian at the new point, so the fit it ends carries that point's Jacobian."""

    def __init__(self, chi2_start: float):
        self.chi2 = chi2_start
        self.negligible = 0

    def __call__(self, intermediate_result) -> None:
        chi2 = 2.0 * float(intermediate_result.cost)
        self.negligible = self.negligible + 1 if self.chi2 - chi2 < DCHI2_STOP else 0
        self.chi2 = chi2
        if self.negligible >= STOP_AFTER:
            raise StopIteration


@dataclass(frozen=True)
class Nuisance:
    """The nuisance calibration refitted with every model: names, bounds, start and scale."""
    names: tuple[str, ...]
    lo: np.ndarray
    hi: np.ndarray
    x0: np.ndarray
    scale: np.ndarray

    @classmethod
    def from_spec(cls, nuisance: Mapping[str, tuple]) -> "Nuisance":
        """{name: (lo, hi[, start[, scale]])}: start 1 when inside the bounds (a scale factor),
        else the middle; scale a tenth of the start (or 1e-4 of the range)."""
        lo, hi, x0, sc = [], [], [], []
        for name, spec in nuisance.items():
            spec = tuple(spec)
            a, b = float(spec[0]), float(spec[1])
            x = float(spec[2]) if len(spec) > 2 else (1.0 if a <= 1.0 <= b else 0.5 * (a + b))
            s = float(spec[3]) if len(spec) > 3 else 0.1 * max(abs(x), 1e-3 * (b - a))
            if not (a <= x <= b) or s <= 0:
                raise DiagnosisError(f"nuisance {name}: start {x} outside [{a}, {b}]")
            lo.append(a), hi.append(b), x0.append(x), sc.append(s)
        return cls(tuple(nuisance), np.array(lo), np.array(hi), np.array(x0), np.array(sc))

    @property
    def start(self) -> dict[str, float]:
        return dict(zip(self.names, self.x0))


@dataclass(frozen=True)
class Noise:
    """Noise model per compared column: marginal level `sigma`, AR(1) coefficient `rho` (0 for
    white noise), innovation level `sigma_w` (= sigma for white noise), how it was obtained.

    A column with a stated noise (`studies.diagnosis.noisemodel`: `--noise`, `sigma_<column>`)
    has a per-row `shape` (dimensionless, every row; RMS 1 over the compared rows): the row's
    standard uncertainty is `sigma` x `shape` (`row_sigma`), the residual divided by the shape
    is what the AR(1) model and the spike test see (weighted least squares). Its `stated` level
    (column unit, RMS over the compared rows) and the check of `sigma` against it
    (`consistency`) are kept beside. Without a statement there is no shape (every row 1)."""
    sigma: Mapping[str, float]
    sigma_w: Mapping[str, float]
    rho: Mapping[str, float]
    source: Mapping[str, str]
    given: frozenset[str] = frozenset()
    #: 99.9 % upper profile-likelihood bound of rho (AR(1) columns; `describe_column`'s bias test)
    rho_hi: Mapping[str, float] = field(default_factory=dict)
    #: per-row relative standard uncertainty of a stated column (RMS 1 over its compared rows)
    shape: Mapping[str, np.ndarray] = field(default_factory=dict)
    #: the statement of a stated column (`noisemodel.StatedNoise`)
    stated: Mapping[str, object] = field(default_factory=dict)
    #: the stated level of a stated column (column unit, RMS over its compared rows)
    stated_sigma: Mapping[str, float] = field(default_factory=dict)
    #: the data's level against the stated one (`noisemodel.Consistency`), once estimated
    consistency: Mapping[str, object] = field(default_factory=dict)

    def describe(self, c: str) -> str:
        if c in self.given:
            return "given"
        what = self.source[c] + (f", AR(1) rho {self.rho[c]:.2f}" if self.rho[c] else "")
        if c in self.stated:
            what = f"weights from the {_STATED_TEXT[self.stated[c].source]}; level {what}"
        return what

    def row_shape(self, c: str, n: int) -> np.ndarray:
        """Column c's per-row relative standard uncertainty (every row; ones without a
        statement)."""
        s = self.shape.get(c)
        return np.ones(n) if s is None else np.asarray(s, float)

    def row_sigma(self, c: str, n: int) -> np.ndarray:
        """Column c's marginal standard uncertainty per row (column unit, every row of n):
        `sigma` x the stated shape (`sigma` on every row without a statement)."""
        return float(self.sigma[c]) * self.row_shape(c, n)


_STATED_TEXT = {"stated": "stated noise (--noise)", "column": "sigma_ column"}


@dataclass(frozen=True)
class Accepted:
    """A cause accepted by an earlier step of the forward selection: its effect object (a
    listed effect or a generalised form), all its parameters at their accepted values, and the
    ones refitted in later models (the profiled ones stay at their accepted value)."""
    effect: object
    values: Mapping[str, float]
    free: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class Problem:
    """One diagnosis's data and model (module docstring). Arrays are never modified."""
    model: CachedModel
    conditions: Mapping[str, np.ndarray]
    measured: Mapping[str, np.ndarray]          # compared columns only
    columns: tuple[str, ...]
    candidates: tuple
    nuisance: Nuisance
    blocks: np.ndarray                          # held-out block per row, 0..n_blocks-1
    valid: Mapping[str, np.ndarray]             # entries compared per column
    noise: Noise
    th: Mapping[str, float]
    T_ref_C: float
    predict_at: Callable | None = None
    workers: int = 1
    try_generalised: bool = True
    spikes: Mapping[str, list[int]] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    #: causes already accepted (forward selection, `studies.diagnosis.selection`): in every
    #: model, their free parameters refitted with the nuisance from their accepted values
    base: tuple["Accepted", ...] = ()
    #: the held-out blocks were chosen here (no labels given): their number may follow the
    #: noise's correlation time (`calibration.blocks_for_correlation`)
    auto_blocks: bool = False

    # ------------------------------------------------------------------ layout
    @property
    def n(self) -> int:
        return int(self.blocks.size)

    @property
    def n_blocks(self) -> int:
        return int(self.blocks.max()) + 1

    @cached_property
    def entry_row(self) -> np.ndarray:
        """Row of each stacked entry (valid rows of every column, column after column)."""
        return np.concatenate([np.flatnonzero(self.valid[c]) for c in self.columns])

    @cached_property
    def entry_col(self) -> np.ndarray:
        return np.concatenate([np.full(self.valid[c].sum(), j)
                               for j, c in enumerate(self.columns)])

    @cached_property
    def entry_block(self) -> np.ndarray:
        return self.blocks[self.entry_row]

    @property
    def N(self) -> int:
        return int(self.entry_row.size)

    @cached_property
    def features(self) -> np.ndarray:
        """The conditions' smoother: powers (cubic with enough rows) of every varying condition
        standardised (and of the row number without time), plus the rates of change of the
        conditions (history effects: lags, hysteresis) in a time series."""
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
        if "time_s" in self.conditions and self.n >= 12 * 4 * len(cols) + 10:
            F += _rates(cols, self.conditions["time_s"])
        return np.array(F).T if F else np.zeros((self.n, 0))

    @property
    def is_time_series(self) -> bool:
        """Rows in time order (`time_s` strictly increasing)."""
        t = self.conditions.get("time_s")
        return t is not None and t.size >= 3 and bool(np.all(np.diff(t) > 0))

    def block_rows(self, b: int) -> list[int]:
        """First and last row (1-based, as in the file) of held-out block b."""
        rows = np.flatnonzero(self.blocks == b)
        return [int(rows[0]) + 1, int(rows[-1]) + 1]

    # ------------------------------------------------------------------ candidates
    def effect(self, name: str):
        return next(e for e in self.candidates if e.name == name)

    def free_params(self, e) -> list[str]:
        """Parameters fitted by gradients: not profiled, not held at "off" for these conditions
        (e.g. a speed-proportional part when every row has the same speed)."""
        held = set(fitspec.held_fixed(e, self.conditions))
        prof = fitspec.profile(e)
        return [p for p in e.parameters if p not in prof and p not in held]

    # ------------------------------------------------------------------ residuals
    def chain(self, c: str) -> np.ndarray:
        """Segment labels of column c's compared entries for the AR(1) whitening: one chain over
        the whole series (AR(1) noise is only estimated in a time series, whose held-out blocks
        are contiguous in time: restarting the chain at every block would count each block's
        first entry as a fresh draw of the marginal noise and overstate what the data say about
        a constant offset by up to twice at rho 0.9)."""
        return np.zeros(int(self.valid[c].sum()), int)

    def row_sigma(self, c: str) -> np.ndarray:
        """Column c's marginal noise level per row (column unit, every row): the estimated level
        times the stated per-row shape (`Noise.row_sigma`; the same on every row without a
        stated noise)."""
        return self.noise.row_sigma(c, self.n)

    def shape(self, c: str) -> np.ndarray:
        """Column c's stated per-row relative uncertainty on its compared rows (ones without a
        statement)."""
        return self.noise.row_shape(c, self.n)[self.valid[c]]

    def scaled_residual(self, c: str, pred_c: np.ndarray) -> np.ndarray:
        """(measured - pred) / shape of column c on every row (column unit at a row of RMS
        uncertainty; the plain residual without a stated noise): the heteroscedastic part of the
        noise divided out, what the AR(1), spike and level estimates work on."""
        r = self.measured[c] - np.asarray(pred_c, float)
        s = self.noise.shape.get(c)
        return r if s is None else r / s

    def standardise(self, c: str, r: np.ndarray, noise: Noise | None = None) -> np.ndarray:
        """Column c's residual-like values r (column unit, its compared rows, or rows x k) in
        noise units: divided by the stated shape, whitened for the AR(1) noise (one chain,
        `chain`), divided by the innovation level (generalised least squares: r / sigma for
        white noise of one level). noise: another noise model than this problem's."""
        nz = self.noise if noise is None else noise
        r = np.asarray(r, float)
        s = nz.shape.get(c)
        if s is not None:
            sh = np.asarray(s, float)[self.valid[c]]
            r = r / (sh if r.ndim == 1 else sh[:, None])
        return ar1_whiten(r, self.chain(c), nz.rho[c]) / nz.sigma_w[c]

    def unstandardise(self, c: str, z: np.ndarray) -> np.ndarray:
        """Inverse of `standardise` (column unit, column c's compared rows, or rows x k)."""
        r = ar1_unwhiten(np.asarray(z, float) * self.noise.sigma_w[c], self.chain(c),
                         self.noise.rho[c])
        return self._times_shape(c, r)

    def prediction_jacobian(self, c: str, J: np.ndarray) -> np.ndarray:
        """d prediction / du of column c (column unit per scaled unit, its compared rows) from
        the rows of the standardised residual's Jacobian J = dz/du that belong to it: z =
        `standardise`(measured - prediction), so d prediction / du = -`unstandardise`(J)."""
        G = -float(self.noise.sigma_w[c]) * ar1_unwhiten(np.asarray(J, float), self.chain(c),
                                                         float(self.noise.rho[c]))
        return self._times_shape(c, G)

    def _times_shape(self, c: str, r: np.ndarray) -> np.ndarray:
        s = self.noise.shape.get(c)
        if s is None:
            return r
        sh = np.asarray(s, float)[self.valid[c]]
        return r * (sh if r.ndim == 1 else sh[:, None])

    def smoother(self, c: str) -> np.ndarray:
        """The conditions' smoother on column c's compared rows, in the column's unit: a
        constant and `features` (compared rows x (1 + features))."""
        return np.column_stack([np.ones(self.n), self.features])[self.valid[c]]

    def smooth_residual(self, c: str, pred_c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Column c's residual measured - pred_c on its compared rows as the conditions' smoother
        shows it (`smoother`, fitted by generalised least squares under this noise model,
        `standardise`): (the smooth part, column unit; the coefficients)."""
        m = self.valid[c]
        X = self.smoother(c)
        r = self.measured[c][m] - np.asarray(pred_c, float)[m]
        coef, *_ = np.linalg.lstsq(self.standardise(c, X), self.standardise(c, r), rcond=None)
        return X @ coef, coef

    def zvec(self, pred: Mapping[str, np.ndarray]) -> np.ndarray:
        """Standardised residuals, stacked (`standardise` per column: stated weights, AR(1)
        whitening, innovation level; plain r / sigma for white noise without a statement)."""
        parts = []
        for c in self.columns:
            m = self.valid[c]
            parts.append(self.standardise(c, self.measured[c][m] - pred[c][m]))
        z = np.concatenate(parts)
        if not np.all(np.isfinite(z)):
            raise ModelFailure("the model returned non-finite values")
        return z

    def col_rmse(self, z_stacked: np.ndarray) -> dict[str, float]:
        """RMSE per column in its own unit (the standardised residuals un-whitened)."""
        out = {}
        for j, c in enumerate(self.columns):
            r = self.unstandardise(c, z_stacked[self.entry_col == j])
            out[c] = float(np.sqrt(np.mean(r ** 2)))
        return out

    # ------------------------------------------------------------------ spaces and fits
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
        base_params = []
        for a in self.base:
            fx[a.effect.name] = dict(a.values)
            steps = fitspec.steps(a.effect, self.conditions)
            for p in a.free:
                s = float(steps.get(p, a.effect.scale[p]))
                b_lo, b_hi = a.effect.bounds[p]
                base_params.append((a.effect.name, p))
                origin.append(a.values[p]), scale.append(s)
                lo.append((b_lo - a.values[p]) / s), hi.append((b_hi - a.values[p]) / s)
        nu = self.nuisance
        origin += list(nu.x0)
        scale += list(nu.scale)
        lo += list((nu.lo - nu.x0) / nu.scale)
        hi += list((nu.hi - nu.x0) / nu.scale)
        return Space(eff_params, fx, list(nu.names), np.array(origin, float),
                     np.array(scale, float), np.array(lo, float), np.array(hi, float),
                     base_params)

    def eval(self, space: Space, u) -> tuple[np.ndarray, dict]:
        """Standardised residuals and predictions at u (clipped to the bounds)."""
        pred = self.model(*space.unpack(space.clip(u)))
        return self.zvec(pred), pred

    @staticmethod
    def start(space: Space, u0) -> np.ndarray:
        """Where a fit from u0 starts (`fit`): u0 clipped to the bounds, coordinates below TINY_U
        at 0, then 1e-10 of each span (at least 1e-10) inside the bounds (the trust-region
        method starts strictly inside)."""
        u0 = space.clip(np.asarray(u0, float))
        # scipy's relative finite-difference step is relative to |u| (exactly 0 excepted): at
        # |u| ~ 1e-14 it is below the model's resolution and the Jacobian column vanishes;
        # start such a coordinate at 0 (one scaled unit is a physically meaningful step)
        u0 = np.where(np.abs(u0) < TINY_U, 0.0, u0)
        lo, hi = space.lo, space.hi
        span = hi - lo
        return np.clip(u0, lo + 1e-10 * np.maximum(span, 1), hi - 1e-10 * np.maximum(span, 1))

    def fit(self, space: Space, u0, max_nfev=None) -> Fit:
        """Bounded least squares (trust-region reflective) from u0, stopped once its steps lower
        the chi-square by a negligible amount (`NegligibleSteps`) or by scipy's tolerances; a
        model failure during the search steers it back (a large residual), at the start it is
        raised."""
        u0 = Problem.start(space, u0)
        lo, hi = space.lo, space.hi
        dim = u0.size
        big = np.full(self.N, 1e6)
        z0 = self.eval(space, u0)[0]      # the start must evaluate (else ModelFailure)

        def fun(u):
            try:
                return self.eval(space, u)[0]
            except ModelFailure:          # outside the model's range: steer the optimiser back
                return big

        res = optimize.least_squares(fun, u0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                                     x_scale=1.0, ftol=1e-8, xtol=1e-8, gtol=1e-8,
                                     max_nfev=max_nfev or 40 * (dim + 1),
                                     callback=NegligibleSteps(float(z0 @ z0)))
        z, pred = self.eval(space, res.x)
        return Fit(space, res.x, z, np.asarray(res.jac, float), float(z @ z), pred)

    def parallel(self, task: Callable, items: Sequence, first: Sequence[int] | None = None
                 ) -> list:
        """[task(item) for item in items] on this diagnosis's `workers` processes
        (`studies.model.parallel.parallel_map`, the model's calls and results counted here):
        the same results as serially."""
        return parallel_map(task, items, self.workers, first=first, state=self.model)


    # ------------------------------------------------------------------ residual description
    def describe(self, pred: Mapping[str, np.ndarray], n_params: int) -> Residuals:
        """Residual statistics per column (`describe_column`) and the smallest p value,
        Bonferroni-adjusted over the tests and columns."""
        out = {}
        pvals = []
        for c in self.columns:
            out[c] = self.describe_column(c, pred[c], n_params)
            pvals += [out[c].bias_p, out[c].lag1_p, out[c].smoother_p_used]
        p_adj = min(1.0, min(pvals) * len(pvals))
        return Residuals(out, p_adj)

    def describe_column(self, c: str, pred_c: np.ndarray, n_params: int) -> ColumnResiduals:
        """Bias (t test), reduced chi-square, lag-1 autocorrelation, the conditions' smoother
        (F test and held-out gain) of column c's residuals, generalised least squares for AR(1)
        noise (residuals and regressors whitened alike; the white-noise statistics at rho 0)."""
        m = self.valid[c]
        r = (self.measured[c] - pred_c)[m]
        seg = self.blocks[m]
        rho = self.noise.rho[c]
        ch = self.chain(c)
        # a stated noise: residual and regressors divided by the per-row shape (weighted least
        # squares; the bias and smoother are still a constant and a smooth curve in column unit)
        inv = 1.0 / self.shape(c) if c in self.noise.shape else None
        r_w = r if inv is None else r * inv
        z = ar1_whiten(r_w, ch, rho) / self.noise.sigma_w[c]
        one = ar1_whiten(np.ones_like(r) if inv is None else inv, ch, rho)
        nn = z.size
        b_hat = float(one @ z) / float(one @ one)
        bias_p = float(2 * stats.norm.sf(abs(b_hat) * math.sqrt(float(one @ one))))
        if rho > 0.0 and c in self.noise.rho_hi:
            bias_p = _bias_p_bound(r_w, self.noise.rho_hi[c], bias_p, inv)
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
        A = np.column_stack([np.ones(nn), self.features[m]])
        A = ar1_whiten(A if inv is None else A * inv[:, None], ch, rho)
        Fst, F_p = _smoother_test(A, zc, den)
        cv_gain = _smoother_cv_gain(A, z, one, seg)
        # AR(1) noise: the smoother must also predict held-out blocks
        p_used = 1.0 if rho > 0.0 and cv_gain < AR1_MIN_CV_GAIN else F_p
        return ColumnResiduals(float(np.mean(r)), bias_p, float(np.sqrt(np.mean(r ** 2))),
                               self.noise.sigma[c], rho, float(z @ z / max(nn - n_params, 1)),
                               r1, auto_p, float(Fst), F_p, float(cv_gain), p_used)


#: confidence level spent on the AR coefficient in the bias test (`_bias_p_bound`)
RHO_CI_GAMMA = 0.001


def _bias_p_bound(r: np.ndarray, rho_hi: float, p_at_rho: float,
                  inv_shape: np.ndarray | None = None) -> float:
    """The bias test's p under AR(1) noise maximised over rho's 1 - RHO_CI_GAMMA confidence set,
    plus RHO_CI_GAMMA (Berger & Boos 1994, P values maximized over a confidence set for the
    nuisance parameter, JASA 89): the variance of a mean grows with rho, so the largest p is at
    the set's upper bound `rho_hi`, where the test is the generalised-least-squares t test of a
    constant with the innovation variance estimated from the whitened residuals. Near rho = 1 an
    AR coefficient estimated 0.05 low halves the variance of the mean and a constant offset of the
    noise looks like a bias (toy AR(1) nulls at phi 0.95). With a stated noise, r is the
    residual divided by the per-row shape and the constant is `inv_shape` (1 / shape)."""
    ch = np.zeros(r.size, int)
    u = ar1_whiten(r, ch, rho_hi)
    one = ar1_whiten(np.ones_like(r) if inv_shape is None else inv_shape, ch, rho_hi)
    oo = float(one @ one)
    b = float(one @ u) / oo
    dof = max(r.size - 1, 1)
    s2 = float(np.sum((u - one * b) ** 2)) / dof
    if s2 <= 0.0:
        return p_at_rho
    t = abs(b) * math.sqrt(oo / s2)
    return float(min(1.0, max(p_at_rho, 2 * stats.t.sf(t, dof)) + RHO_CI_GAMMA))


def _rates(cols: list[tuple[str, np.ndarray]], t: np.ndarray) -> list[np.ndarray]:
    """Standardised rates of change d x / d t of the varying conditions (not of time itself) in
    a time series (`t` strictly increasing; else none)."""
    if not np.all(np.diff(t) > 0):
        return []
    out = []
    for k, x in cols:
        if k in ("time_s", "row"):
            continue
        g = np.gradient(x, t)
        if np.std(g) > 0:
            out.append((g - g.mean()) / g.std())
    return out


#: with AR(1) noise the whitening uses an estimated rho and the in-sample F test of the smoother
#: is anti-conservative; the smoother must then also predict the held-out blocks (block cross-
#: validation gain above this share of the residual variance) to count as structure
AR1_MIN_CV_GAIN = 0.1


def _smoother_test(A: np.ndarray, zc: np.ndarray, den: float) -> tuple[float, float]:
    """F statistic of the smoother (columns of A beyond the constant) on the centred residuals
    zc (sum of squares den) and its p value: the larger of the F test's and the known-sigma
    chi-square test's."""
    nn = zc.size
    q = orth(A)
    fitted = q @ (q.T @ zc)
    ss1 = float(np.sum((zc - fitted) ** 2))
    p_feat = q.shape[1] - 1
    if p_feat > 0 and nn - p_feat - 1 > 0 and ss1 > 0:
        Fst = ((den - ss1) / p_feat) / (ss1 / (nn - p_feat - 1))
        return Fst, float(max(stats.f.sf(Fst, p_feat, nn - p_feat - 1),
                              stats.chi2.sf(den - ss1, p_feat)))
    if p_feat > 0 and nn - p_feat - 1 > 0:
        return math.inf, float(stats.chi2.sf(den - ss1, p_feat))
    return 0.0, 1.0


def _smoother_cv_gain(A: np.ndarray, z: np.ndarray, one: np.ndarray, blocks: np.ndarray) -> float:
    """The smoother's held-out gain: 1 - SSE(smoother) / SSE(constant), each held-out block
    predicted from the others (block cross-validation)."""
    sse_cv = 0.0
    sse_0 = 0.0
    for b in np.unique(blocks):
        tr, te = blocks != b, blocks == b
        if tr.sum() <= A.shape[1] + 1:
            continue
        coef, *_ = np.linalg.lstsq(A[tr], z[tr], rcond=None)
        sse_cv += float(np.sum((z[te] - A[te] @ coef) ** 2))
        b_tr = float(one[tr] @ z[tr]) / float(one[tr] @ one[tr])
        sse_0 += float(np.sum((z[te] - one[te] * b_tr) ** 2))
    return 1.0 - sse_cv / sse_0 if sse_0 > 0 else 0.0


# ---------------------------------------------------------------------- construction
def make_problem(predict: Callable, measured: Mapping[str, np.ndarray],
                 conditions: Mapping[str, np.ndarray], candidates: Sequence,
                 nuisance: Mapping[str, tuple], blocks=None, *,
                 noise_sigma: Mapping[str, float] | None = None, T_ref_C: float = 20.0,
                 predict_at: Callable | None = None, thresholds: Mapping | None = None,
                 columns: Sequence[str] | None = None, workers: int = 1,
                 generalised: bool = True,
                 noise_model: Mapping[str, object] | None = None) -> Problem:
    """The problem as given (noise from the measured data, before the baseline calibration);
    one-line `DiagnosisError` for unusable input. One model call (the columns it predicts).
    noise_model: {column: `noisemodel.StatedNoise`}, the stated noise of some columns (their
    per-row weights; the level is still estimated: `Noise`); a column both in `noise_sigma`
    and here, or not compared, is a DiagnosisError."""
    from studies.diagnosis.core import DEFAULT_THRESHOLDS

    th = dict(DEFAULT_THRESHOLDS)
    th.update(thresholds or {})
    cond = {k: np.asarray(v, float) for k, v in conditions.items()}
    cands = tuple(candidates)
    names = [c.name for c in cands]
    if len(set(names)) != len(names):
        raise DiagnosisError("candidate effects must have distinct names")
    meas = {k: np.asarray(v, float) for k, v in measured.items()}
    n = _row_count(meas, cond)
    nu = Nuisance.from_spec(nuisance)
    model = CachedModel(predict, n)
    cols = _compared_columns(meas, model({}, nu.start), columns)
    labels = _block_labels(blocks, n, int(th["n_blocks"]))
    meas = {c: meas[c] for c in cols}
    valid = {c: np.isfinite(meas[c]) for c in cols}
    given = {c: float(v) for c, v in (noise_sigma or {}).items()}
    stated = dict(noise_model or {})
    for c in stated:
        if c not in cols:
            raise DiagnosisError(f"stated noise of {c}: not a compared column "
                                 f"({', '.join(cols)})")
        if c in given:
            raise DiagnosisError(f"stated noise of {c}: its noise level is given as well")
    first = with_stated_shape(Noise({}, {}, {}, {}, frozenset(given), stated=stated), meas,
                              valid, meas)
    pb = Problem(model, cond, meas, cols, cands, nu, labels, valid, first, th, float(T_ref_C),
                 predict_at, int(workers), bool(generalised))
    sigma, source = {}, {}
    for c in cols:
        if c in given:
            sigma[c] = given[c]
            continue
        floor = ROUND_OFF * float(np.nanmax(np.abs(meas[c]), initial=0.0))
        s, source[c] = data_sigma(pb, c, meas[c])
        s = max(s, floor)
        sigma[c] = s if s > 0 else 1.0     # a column of zeros
    noise = replace(first, sigma=sigma, sigma_w=dict(sigma), rho={c: 0.0 for c in cols},
                    source=source)
    return Problem(model, cond, meas, cols, cands, nu, labels, valid, noise, th, float(T_ref_C),
                   predict_at, int(workers), bool(generalised), auto_blocks=blocks is None)


def with_stated_shape(noise: Noise, measured: Mapping[str, np.ndarray],
                      valid: Mapping[str, np.ndarray], reading: Mapping[str, np.ndarray]) -> Noise:
    """`noise` with the per-row shape and stated level of each stated column (`noise.stated`)
    evaluated at the readings `reading` (column -> values, column unit: the measured values for
    the first estimate, `calibration.stated_readings` after it; `noisemodel` module
    docstring): the stated per-row uncertainty s (never below the round-off floor ROUND_OFF x
    the column's largest value), the level sqrt(mean s^2) over the compared rows, the shape
    s / level (1 on rows not compared)."""
    if not noise.stated:
        return noise
    shape, level = dict(noise.shape), dict(noise.stated_sigma)
    for c, st in noise.stated.items():
        m = valid[c]
        floor = ROUND_OFF * float(np.nanmax(np.abs(measured[c]), initial=0.0))
        s = np.maximum(np.asarray(st.row_sigma(reading[c]), float), max(floor, 1e-300))
        level[c] = float(np.sqrt(np.mean(s[m] ** 2)))
        shape[c] = np.where(m, s / level[c], 1.0)
    return replace(noise, shape=shape, stated_sigma=level)


def data_sigma(pb: Problem, c: str, r: np.ndarray) -> tuple[float, str]:
    """Noise level of column c from residuals r (column unit, every row), and how: in a time
    series from second differences in time (within blocks; with a stated noise each divided by
    its own stated standard deviation, `stats.noise_sigma`'s shape); in a table of steady
    points from the design (replicates, or second differences along each condition:
    `stats.noise_sigma_steady`, of r divided by the stated shape). With a stated noise the
    level is that of a row of RMS stated uncertainty."""
    t = pb.conditions.get("time_s")
    shape = pb.noise.shape.get(c)
    if t is None or not np.all(np.diff(t) > 0):
        m = pb.valid[c]
        rs = r if shape is None else r / shape
        s, how = noise_sigma_steady(rs[m], {k: v[m] for k, v in pb.conditions.items()})
        if s > 0:
            return s, how
    return noise_sigma(r, pb.blocks, shape), "second differences of the baseline residuals"


def _row_count(meas: Mapping[str, np.ndarray], cond: Mapping[str, np.ndarray]) -> int:
    if not meas:
        raise DiagnosisError("no measured output columns")
    sizes = {v.size for v in meas.values()} | {v.size for v in cond.values()}
    if len(sizes) != 1:
        raise DiagnosisError(f"columns have different lengths: {sorted(sizes)}")
    n = sizes.pop()
    if n < 8:
        raise DiagnosisError(f"too few rows to diagnose ({n}; need at least 8)")
    return n


def _compared_columns(meas: Mapping, pred0: Mapping, columns: Sequence[str] | None
                      ) -> tuple[str, ...]:
    """Measured columns the model predicts (restricted to `columns` when given), FIRST_COLUMNS
    first."""
    common = [c for c in meas if c in pred0]
    if columns is not None:
        common = [c for c in columns if c in common]
    if not common:
        raise DiagnosisError("no measured column is predicted by the model (measured: "
                             f"{', '.join(meas)})")
    first = [c for c in FIRST_COLUMNS if c in common]
    return tuple(first + [c for c in common if c not in first])


def _block_labels(blocks, n: int, n_auto: int) -> np.ndarray:
    """Held-out block per row, 0..k-1: the given labels, or n_auto contiguous blocks."""
    if blocks is None:
        labels = auto_blocks(n, n_auto)
    else:
        b = np.asarray(blocks)
        if b.size != n:
            raise DiagnosisError("block labels must have one entry per row")
        _, labels = np.unique(b, return_inverse=True)
    if int(labels.max()) + 1 < 2:
        raise DiagnosisError("need at least two held-out blocks")
    return labels


def longest_first(costs: Sequence[float | None]) -> list[int]:
    """Indices of the items by their estimated cost, largest first (unknown costs last, in
    their order): the order `Problem.parallel` starts them in. Handing the longest tasks out
    first is the LPT rule (Graham 1969, Bounds on multiprocessing timing anomalies, SIAM J.
    Appl. Math. 17: at most 4/3 of the best schedule); the results do not depend on it."""
    known = [i for i, c in enumerate(costs) if c is not None]
    return (sorted(known, key=lambda i: -float(costs[i]))
            + [i for i, c in enumerate(costs) if c is None])


def cpu_timed(task: Callable) -> Callable:
    """`task` returning (its result, the CPU seconds of the process it ran in) (a task on a
    forked worker: that worker's seconds); named as `task` (the maps of `bench --diagnose
    --profile`)."""
    @wraps(task)
    def run(item):
        t0 = time.process_time()
        out = task(item)
        return out, time.process_time() - t0
    return run
