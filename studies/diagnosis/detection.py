"""A claim needs a detectable change: before any candidate is fitted, per compared column, the
smallest change the data could show and the change the configured model leaves, both in noise
units.

- The change the configured model leaves (`change_sigma`): the RMS of the calibrated
  baseline's misfit beyond the noise, sqrt(max(chi2 / dof - 1, 0)) of the column's standardised
  (whitened) residuals after the nuisance calibration (phase 1, `calibration.calibrate`; the
  same chi-square per degree of freedom as `goodness.goodness`). It estimates the RMS over the
  column's entries of (truth - calibrated model) / sigma: E[chi2] = dof + n delta^2 for a change
  of RMS delta on n entries.
- The smallest change the data could show (`threshold_sigma`): the minimum detectable effect
  (Cohen 1988, Statistical Power Analysis for the Behavioral Sciences, 2nd ed., ch. 9-10; Bloom
  1995, Minimum detectable effects, Evaluation Review 19(5)) of that chi-square: the RMS change
  delta which the column's test at alpha_structure (Bonferroni over the columns) finds with
  probability DETECTION_POWER (0.95). The statistic is noncentral with lambda = n delta^2:
  chi-square on dof degrees of freedom when the noise level is given, F(dof, nu) when it is
  estimated from the data, nu = `goodness.NU_SHARE` x n (the second-difference estimator's
  degrees of freedom, Satterthwaite 1946). It depends on the noise model and the number of entries only, not on any
  fit: it is stated before fitting.

Below the threshold in every column the answer is `no_discrepancy` whatever fits
(`selection.below_detection`): a change smaller than the one the test finds in 19 draws of 20
is one the data cannot tell from a noise level a little higher than estimated, and a candidate
that fits it fits noise and the model's form slop (a free contact angle 3 deg off,
0.75 sigma RMS after the friction scale, was claimed as an interference error). The power sets
how far above the noise's own level the threshold lies: on 240 entries with the noise estimated
the test's critical value is 0.72 sigma RMS, the threshold 0.97 (0.85 at Cohen's conventional
power 0.8, which a 0.75 sigma change estimated at 0.87 passed on a second-source draw). The rule
compares the estimate with the threshold, so a true change at the threshold passes in about half
the draws: on 240 entries (the estimate's chi-square per degree of freedom a noncentral
F(239, 120)) a true change of 0.75 sigma passes in 9 %, 0.97 in 52 %, 1.41 in 99.9 %.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from studies.diagnosis.goodness import NU_SHARE

#: the probability with which a change at the threshold is found (module docstring: with 0.8,
#: Cohen's convention, ch. 2.4, a true change at the level noise alone reaches, 0.72 sigma on
#: 240 entries, still passed the threshold of 0.85 in about a quarter of draws)
DETECTION_POWER = 0.95


@dataclass(frozen=True)
class ColumnDetection:
    """One compared column (noise units): the smallest change the data could show, the change
    the configured model leaves, and what they rest on (entries, degrees of freedom of the
    misfit and of the noise estimate, None for a given noise level; the test's level)."""
    column: str
    threshold_sigma: float
    change_sigma: float
    entries: int
    dof: float
    nu: float | None
    alpha: float

    @property
    def detectable(self) -> bool:
        return self.change_sigma >= self.threshold_sigma

    def to_json(self) -> dict:
        return {"threshold_sigma": self.threshold_sigma, "change_sigma": self.change_sigma}


def noise_model(pb):
    """The noise model the detection rests on: the calibrated problem's (`Problem.noise`,
    phase 1); the one accessor, so a stated noise model's weights enter here alone."""
    return pb.noise


def threshold_sigma(entries: int, dof: float, nu: float | None, alpha: float,
                    power: float = DETECTION_POWER) -> float:
    """The RMS change (noise units) over `entries` compared entries that the column's
    chi-square test at `alpha` (dof degrees of freedom; noise estimated on nu degrees of freedom,
    None: given) finds with probability `power` (module docstring): the delta with
    P(F'(dof, nu, entries delta^2) > F_crit) = power (noncentral chi-square when nu is None)."""
    if entries <= 0 or dof <= 0:
        return math.inf
    if nu is None:
        crit = stats.chi2.isf(alpha, dof)
        found = lambda lam: stats.ncx2.sf(crit, dof, lam) - power   # noqa: E731
    else:
        crit = stats.f.isf(alpha, dof, nu)
        found = lambda lam: stats.ncf.sf(crit, dof, nu, lam) - power   # noqa: E731
    hi = max(dof, 1.0)
    while found(hi) < 0.0:
        hi *= 2.0
    lam = optimize.brentq(found, 0.0, hi, xtol=1e-10 * hi)
    return math.sqrt(lam / entries)


def detection(pb, z: np.ndarray, n_params: int) -> dict[str, ColumnDetection]:
    """Per compared column of the calibrated problem `pb`: the detection threshold and the
    change of the calibrated baseline (standardised residuals `z`, stacked; `n_params` fitted
    nuisance parameters shared by the columns, counted per column by its share of the entries
    as in `goodness.goodness`)."""
    noise = noise_model(pb)
    m = len(pb.columns)
    alpha = pb.th["alpha_structure"] / max(m, 1)
    out = {}
    for j, c in enumerate(pb.columns):
        sel = pb.entry_col == j
        n = int(sel.sum())
        dof = max(n - n_params * n / max(pb.N, 1), 1.0)
        nu = None if c in noise.given else max(NU_SHARE * n, 1.0)
        chi2_red = float(z[sel] @ z[sel]) / dof
        out[c] = ColumnDetection(c, threshold_sigma(n, dof, nu, alpha),
                                 math.sqrt(max(chi2_red - 1.0, 0.0)), n, dof, nu, alpha)
    return out


def below(det: dict[str, ColumnDetection]) -> bool:
    """Is the change below the threshold in every compared column?"""
    return bool(det) and not any(d.detectable for d in det.values())
