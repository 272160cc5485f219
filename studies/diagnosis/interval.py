"""Predictive intervals of a fitted model: how far a new measurement at a row may lie
from the extended model's prediction, at a stated level (90 % by default).

Three variance components per row, added (independent sources):

- the parameters' uncertainty, by the delta method: g' C g, with g = d prediction / d parameters
  (the fit's own Jacobian, already computed by the least-squares fit) and C the parameters'
  covariance s^2 (J' J)^-1 of the linearised fit in noise units (Seber & Wild, Nonlinear
  Regression, Wiley 1989, ch. 2.1.2 and ch. 5.1: linearised confidence and prediction intervals;
  s^2 = max(1, chi^2 / (N - k)), the reduced chi-square when it exceeds 1, as the stated standard
  uncertainties of the parameters (`parameter_covariance`));
- the measurement noise of the row: its marginal level sigma (the AR(1) noise model the
  diagnosis estimates, `problem.Noise`: an AR(1) series of innovation level sigma_w and
  coefficient rho has the marginal level sigma_w / sqrt(1 - rho^2); Box, Jenkins & Reinsel, Time
  Series Analysis, ch. 3.2.4);
- the model's inadequacy (discrepancy), a variance component in the spirit of Kennedy &
  O'Hagan (2001), Bayesian calibration of computer models, J. R. Statist. Soc. B 63(3),
  425-464: the model with its best parameters still misses the truth by a term delta(x); here
  no Gaussian process, only its variance, estimated from the calibration rows as the excess of
  their residual variance (per degree of freedom) over the noise variance, floored at 0
  (`discrepancy_sd`; a method-of-moments estimate of a variance component, Searle, Casella &
  McCulloch, Variance Components, Wiley 1992, ch. 3).

The interval is prediction +- q sqrt(var), q the standard normal quantile of (1 + level) / 2
(1.645 for 90 %). Units: those of the column.

Public: `predictive_interval(prediction, jacobian, param_cov, noise_sd, discrepancy_sd, level)`
(any model: the diagnosis's columns, the friction helper's held-out predictions),
`parameter_covariance(J, chi2)`, `discrepancy_sd(residual, noise_sd, dof)` and, for one fit of a
diagnosis problem, `column_intervals(pb, fit, heldout_z, level)`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats


#: the level of the diagnosis's predictive intervals (docs/cli.md: `interval.level`)
LEVEL = 0.9
#: singular values of the Jacobian below this share of the largest are directions the data do
#: not determine (left out of the covariance; a parameter along one has no stated uncertainty)
SINGULAR_RTOL = 1e-8


@dataclass(frozen=True)
class PredictiveInterval:
    """lo, hi: the interval per row (column unit); sd: the predictive standard deviation per row
    and its parts (parameters, noise, discrepancy: column unit); level: its coverage level."""
    lo: np.ndarray
    hi: np.ndarray
    sd: np.ndarray
    sd_parameters: np.ndarray
    sd_noise: np.ndarray
    sd_discrepancy: np.ndarray
    level: float


def quantile(level: float) -> float:
    """The two-sided standard normal quantile of a central interval of `level`."""
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must lie in (0, 1), got {level}")
    return float(stats.norm.ppf(0.5 + 0.5 * level))


def parameter_covariance(J: np.ndarray, chi2: float) -> tuple[np.ndarray, np.ndarray]:
    """(covariance, identifiable) of the fitted parameters of a least-squares fit whose
    standardised residual (noise units) has Jacobian J (entries x parameters, in the fit's own
    coordinates) and chi-square chi2: C = s^2 V diag(1 / s_j^2) V' over the singular directions
    the data determine (s_j >= SINGULAR_RTOL s_0), s^2 = max(1, chi2 / (N - k)) (Seber & Wild
    1989, ch. 2.1.2; the reduced chi-square scales it when the fit is worse than the noise).
    identifiable[i] is False when parameter i has a component along a direction the data do
    not determine (its variance is then not stated)."""
    J = np.asarray(J, float)
    k = J.shape[1]
    if k == 0:
        return np.zeros((0, 0)), np.zeros(0, bool)
    dof = max(J.shape[0] - k, 1)
    s2 = max(1.0, float(chi2) / dof)
    _, s, Vt = np.linalg.svd(J, full_matrices=False)
    tiny = s < SINGULAR_RTOL * (s[0] if s.size else 1.0)
    inv = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, s) ** 2)
    cov = s2 * (Vt.T * inv) @ Vt
    identifiable = ~np.any(tiny[:, None] & (np.abs(Vt) > 1e-6), axis=0)
    return cov, identifiable


def discrepancy_sd(residual: np.ndarray, noise_sd, dof: float) -> float:
    """Standard deviation of the model's discrepancy (column unit) from the calibration rows'
    residuals (measured - fitted model): sqrt(max(0, sum r^2 / dof - mean sigma^2)), dof the
    rows less the parameters' share, sigma the noise level (scalar, or per row for a stated
    noise) (module docstring: Kennedy & O'Hagan 2001 in spirit; a method-of-moments variance
    component)."""
    r = np.asarray(residual, float)
    ok = np.isfinite(r)
    if not ok.any():
        return 0.0
    var_noise = (float(noise_sd) ** 2 if np.ndim(noise_sd) == 0
                 else float(np.mean(np.asarray(noise_sd, float)[ok] ** 2)))
    r = r[ok]
    ms = float(r @ r) / max(float(dof), 1.0)
    return math.sqrt(max(ms - var_noise, 0.0))


def predictive_interval(prediction, jacobian, param_cov, noise_sd, discrepancy_sd=0.0,
                        level: float = LEVEL) -> PredictiveInterval:
    """The predictive interval of a new measurement at each row (module docstring).

    prediction: (n,) the fitted model's prediction (column unit); jacobian: (n, k) d prediction /
    d parameters (column unit per parameter unit) at the fit; param_cov: (k, k) the parameters'
    covariance (parameter units squared); noise_sd: the measurement noise's marginal standard
    deviation (column unit, scalar or (n,)); discrepancy_sd: the model discrepancy's standard
    deviation (column unit, scalar or (n,)); level: the coverage level (0.9)."""
    y = np.asarray(prediction, float)
    G = np.asarray(jacobian, float).reshape(y.size, -1)
    C = np.asarray(param_cov, float)
    var_p = np.maximum(np.einsum("ij,jk,ik->i", G, C, G), 0.0) if G.shape[1] else np.zeros(y.size)
    sn = np.broadcast_to(np.asarray(noise_sd, float), y.shape).copy()
    sd_d = np.broadcast_to(np.asarray(discrepancy_sd, float), y.shape).copy()
    sd = np.sqrt(var_p + sn ** 2 + sd_d ** 2)
    q = quantile(level)
    return PredictiveInterval(y - q * sd, y + q * sd, sd, np.sqrt(var_p), sn, sd_d, float(level))


@dataclass(frozen=True)
class ColumnInterval:
    """One measured column's interval on every row (NaN where the column is not measured), its
    discrepancy and noise levels (column unit; with a stated noise at a row of RMS stated
    uncertainty, both scaling with the stated per-row shape), and the share of the calibration rows inside it
    (the fit's own rows) and of the held-out rows inside it (the held-out prediction's residual
    within the half-width)."""
    column: str
    lo: np.ndarray
    hi: np.ndarray
    discrepancy_sd: float
    noise_sd: float
    coverage_calibration: float
    coverage_heldout: float


#: `Intervals.method` of the claimed model's interval (`column_intervals`)
CLAIMED_METHOD = ("delta method on the fit's Jacobian (parameter covariance) + AR(1) noise "
                  "(marginal level) + discrepancy variance from the calibration rows (Kennedy & "
                  "O'Hagan 2001 in spirit); normal quantile")
#: `Intervals.method` of the configured model's interval (`configured_intervals`)
CONFIGURED_METHOD = ("the calibrated configured model plus its discrepancy as the data show it: "
                     "the conditions' smoother fitted to the baseline residual (generalised "
                     "least squares under the noise model), delta method on the nuisance and "
                     "smoother coefficients jointly + noise (marginal level) + the discrepancy "
                     "variance the smoother leaves; normal quantile")


@dataclass(frozen=True)
class Intervals:
    """The predictive intervals of a model (diagnosis.json `interval`): level, the share of
    calibration rows inside (every column's entries together), the same on held-out rows, per
    column `ColumnInterval`, what model they are about (`model`: "extended" for a claimed cause,
    "configured" with the discrepancy the data show otherwise) and how they were obtained."""
    level: float
    coverage_calibration: float
    coverage_heldout: float
    columns: dict[str, ColumnInterval]
    model: str = "extended"
    method: str = CLAIMED_METHOD

    def to_json(self) -> dict:
        return {"level": self.level, "coverage_calibration": self.coverage_calibration,
                "coverage_heldout": self.coverage_heldout,
                "model": self.model, "method": self.method,
                "columns": {c: {"discrepancy_sd": ci.discrepancy_sd, "noise_sd": ci.noise_sd,
                                "coverage_calibration": ci.coverage_calibration,
                                "coverage_heldout": ci.coverage_heldout}
                            for c, ci in self.columns.items()}}


def column_intervals(pb, fit, heldout_z: np.ndarray, level: float = LEVEL,
                     noise=None) -> Intervals:
    """The predictive interval of every measured column of diagnosis problem `pb`
    (`studies.diagnosis.problem.Problem`) for its fit `fit` (`core.Fit`: standardised residual
    z, its Jacobian J = dz/du in the fit's scaled coordinates u, predictions), with the fit's
    held-out standardised residuals `heldout_z` (under pb's noise model) for the held-out
    coverage; `noise`: the noise model of the interval (`problem.Noise`, default pb's; e.g. the
    one re-estimated from the fit's own residual, `calibration.baseline_noise`).

    z = W (measured - prediction) / sigma_w, W the AR(1) whitening after the stated per-row
    weights (`Problem.standardise`), so d prediction / du = -W^-1 J sigma_w
    (`Problem.prediction_jacobian`); under the interval's noise model the standardised residual and
    its Jacobian are W' r / sigma_w' and -W' (d prediction / du) / sigma_w', whose
    `parameter_covariance` is the parameters'; noise: the column's marginal level per row;
    discrepancy: `discrepancy_sd` of the fit's residual with dof = entries less the column's
    share of the parameters (as `goodness.goodness`)."""
    nz = pb.noise if noise is None else noise
    per, Js, zs = [], [], []
    for j, c in enumerate(pb.columns):
        sel = pb.entry_col == j
        m = np.asarray(pb.valid[c], bool)
        G = pb.prediction_jacobian(c, fit.J[sel])
        pred = np.asarray(fit.pred[c], float)[m]
        r = np.asarray(pb.measured[c], float)[m] - pred
        Js.append(-pb.standardise(c, G, nz))
        zs.append(pb.standardise(c, r, nz))
        r_ho = pb.unstandardise(c, np.asarray(heldout_z, float)[sel])
        per.append((c, m, G, pred, r, r_ho))
    J, z = np.vstack(Js), np.concatenate(zs)
    cov, _ = parameter_covariance(J, float(z @ z))
    return _assemble(pb, nz, per, cov, int(fit.u.size), level)


def _assemble(pb, nz, per, cov: np.ndarray, k: int, level: float, model: str = "extended",
              method: str = CLAIMED_METHOD) -> Intervals:
    """`Intervals` from each column's (name, compared rows m, d prediction / d parameters G,
    prediction, calibration residual r, held-out residual r_ho) and the parameters' covariance
    (k parameters shared by the columns)."""
    q = quantile(level)
    cols, inside_cal, inside_ho, total = {}, 0, 0, 0
    for c, m, G, pred, r, r_ho in per:
        n = int(m.sum())
        dof = max(n - k * n / pb.N, 1.0)
        if c in nz.shape:       # a stated noise: the discrepancy scales with it, as the noise
            sh = np.asarray(nz.shape[c], float)[m]
            d_level = discrepancy_sd(r / sh, float(nz.sigma[c]), dof)
            sg, d_sd = float(nz.sigma[c]) * sh, d_level * sh
        else:
            sg = float(nz.sigma[c])
            d_sd = d_level = discrepancy_sd(r, sg, dof)
        pi = predictive_interval(pred, G, cov, sg, d_sd, level)
        in_cal = int(np.sum(np.abs(r) <= q * pi.sd))
        in_ho = int(np.sum(np.abs(r_ho) <= q * pi.sd))
        lo = np.full(m.size, np.nan)
        hi = np.full(m.size, np.nan)
        lo[m], hi[m] = pi.lo, pi.hi
        cols[c] = ColumnInterval(c, lo, hi, d_level, float(nz.sigma[c]), in_cal / max(n, 1),
                                 in_ho / max(n, 1))
        inside_cal, inside_ho, total = inside_cal + in_cal, inside_ho + in_ho, total + n
    return Intervals(float(level), inside_cal / max(total, 1), inside_ho / max(total, 1), cols,
                     model, method)


def configured_intervals(pb, fit, level: float = LEVEL) -> Intervals:
    """The configured model's predictive interval with the discrepancy the data show, for a
    verdict that claims no cause (`unexplained`, `no_discrepancy`, `ambiguous`): `fit` is the
    calibrated baseline (`core.Baseline.fit`: nuisance only) of problem `pb`.

    The discrepancy delta(x) of Kennedy & O'Hagan (2001) is represented by the conditions'
    smoother (`Problem.features`: powers of the varying conditions and their rates of change, a
    constant) fitted to each column's baseline residual by generalised least squares under the
    diagnosis's noise model (`Problem.standardise`); the interval is about baseline + delta.
    Its variance per row: the delta method on the nuisance and every column's smoother
    coefficients fitted jointly (the stacked standardised Jacobian [J_nuisance, -W X_c]:
    `parameter_covariance`; Seber & Wild 1989, ch. 5.1), the noise's marginal level, and the
    discrepancy variance the smoother leaves (`discrepancy_sd`). Held-out coverage: each
    contiguous held-out block's smoother fitted on the other blocks (block cross-validation).
    With no structure the smoother is near zero and the interval is the noise's with the
    nuisance's and smoother's uncertainty."""
    kn = int(fit.u.size)
    p = 1 + pb.features.shape[1]
    blocks, Js, zs = [], [], []
    offset = kn
    for j, c in enumerate(pb.columns):
        sel = pb.entry_col == j
        m = np.asarray(pb.valid[c], bool)
        Xc = pb.smoother(c)
        r0 = np.asarray(pb.measured[c], float)[m] - np.asarray(fit.pred[c], float)[m]
        A = pb.standardise(c, Xc)
        delta = pb.smooth_residual(c, fit.pred[c])[0]
        Gn = pb.prediction_jacobian(c, fit.J[sel])
        Jc = np.zeros((int(m.sum()), kn + p * len(pb.columns)))
        Jc[:, :kn] = fit.J[sel]
        Jc[:, offset:offset + p] = -A
        Js.append(Jc)
        zs.append(pb.standardise(c, r0 - delta))
        blocks.append((c, m, Xc, A, r0, delta, Gn, offset))
        offset += p
    cov, _ = parameter_covariance(np.vstack(Js), float(np.concatenate(zs) @ np.concatenate(zs)))
    per = []
    for c, m, Xc, A, r0, delta, Gn, off in blocks:
        G = np.zeros((Xc.shape[0], cov.shape[0]))
        G[:, :kn] = Gn
        G[:, off:off + p] = Xc
        pred = np.asarray(fit.pred[c], float)[m] + delta
        per.append((c, m, G, pred, r0 - delta, r0 - _heldout_smooth(pb, c, m, A, Xc, r0)))
    return _assemble(pb, pb.noise, per, cov, cov.shape[0], level, "configured",
                     CONFIGURED_METHOD)


def _heldout_smooth(pb, c: str, m: np.ndarray, A: np.ndarray, X: np.ndarray,
                    r0: np.ndarray) -> np.ndarray:
    """Column c's smoother (standardised regressors A, column-unit regressors X, residual r0 on
    its compared rows m) predicted on each held-out block from the other blocks' rows."""
    b = pb.blocks[m]
    y = pb.standardise(c, r0)
    out = np.zeros(r0.size)
    for k in np.unique(b):
        tr = b != k
        coef, *_ = np.linalg.lstsq(A[tr], y[tr], rcond=None)
        out[~tr] = X[~tr] @ coef
    return out
