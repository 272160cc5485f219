"""Phase 1 of the diagnosis: the calibrated baseline and the noise model (module docstring of
`studies.diagnosis.engine`, step 1).

`calibrate(problem)` fits the nuisance alone, leaves isolated sensor spikes out, estimates each
column's noise level from the baseline residuals (and its AR(1) coefficient in a time series),
refits, and describes the residuals. It returns the calibrated `Problem` (the noise model and
the compared entries the later phases use) with the `Baseline`.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy import stats

from studies.diagnosis.core import Baseline
from studies.diagnosis.heldout import heldout_linear
from studies.diagnosis.problem import ROUND_OFF, Noise, Problem, data_sigma
from studies.diagnosis.stats import (ar1_regression_reml, ar1_whiten, auto_blocks, noise_sigma,
                                     orth)

#: likelihood-ratio statistic (chi-square, 1 df) of AR(1) errors against white ones, with the
#: conditions' smoother as the regression, above which a column's noise is taken as AR(1) and
#: whitened (slowly drifting sensors); 9 = a 3-sigma level
AR1_LR = 9.0
#: a residual this many robust standard deviations from the smoother is a spike (P = 2e-9 for
#: Gaussian noise), if such entries are at most MAX_SPIKE_SHARE of the column
SPIKE_SIGMA = 6.0
MAX_SPIKE_SHARE = 0.05


def calibrate(pb: Problem) -> tuple[Problem, Baseline]:
    """Nuisance-only fit in two passes (noise from the measured data, then from the baseline
    residuals), its residual description and held-out residuals."""
    bspace = pb.space([])
    base = pb.fit(bspace, np.zeros(bspace.lo.size))
    spiked = drop_spikes(pb, base.pred)
    if spiked is not pb:
        pb = spiked
        base = pb.fit(bspace, base.u)
    pb = replace(pb, noise=baseline_noise(pb, base.pred))
    longer = blocks_for_correlation(pb)
    if longer is not pb:
        pb = replace(longer, noise=baseline_noise(longer, base.pred))
    base = pb.fit(bspace, base.u)
    base_nuis = bspace.unpack(base.u)[1]
    desc_base = pb.describe(base.pred, len(pb.nuisance.names))
    structure = desc_base.p_min_adjusted < pb.th["alpha_structure"]
    return pb, Baseline(base, base_nuis, desc_base, bool(structure), heldout_linear(pb, base),
                        orth(base.J))


#: fewest automatic held-out blocks when their length follows the noise's correlation time
MIN_BLOCKS_CORRELATED = 5


def blocks_for_correlation(pb: Problem) -> Problem:
    """Automatic held-out blocks at least as long as the noise's integrated correlation time
    (1 + rho) / (1 - rho) rows of AR(1) noise (Sokal 1997, Monte Carlo methods in statistical
    mechanics, eq. 2.19; the block bootstrap needs nearly independent blocks: Kuensch 1989, The
    jackknife and the bootstrap for general stationary observations, Ann. Statist. 17): fewer
    blocks (not below MIN_BLOCKS_CORRELATED nor above the present number) when the largest
    coefficient of the columns asks for it; the same problem when the blocks were given or are
    long enough."""
    rho = max(pb.noise.rho.values(), default=0.0)
    if not pb.auto_blocks or rho <= 0.0:
        return pb
    length = math.ceil((1.0 + rho) / (1.0 - rho))
    k = max(min(pb.n // length, pb.n_blocks), min(MIN_BLOCKS_CORRELATED, pb.n_blocks))
    if k >= pb.n_blocks:
        return pb
    note = (f"held-out blocks: {k} instead of {pb.n_blocks}, each at least the noise's "
            f"correlation time ({length} rows at AR(1) rho {rho:.2f}) where the data allow")
    return replace(pb, blocks=auto_blocks(pb.n, k), notes=pb.notes + (note,))


def drop_spikes(pb: Problem, pred: dict) -> Problem:
    """Isolated outliers (sensor spikes): entries whose baseline residual, after the
    conditions' smoother, lies beyond SPIKE_SIGMA robust standard deviations (1.4826 MAD) are
    left out of every fit and test and reported; a model error is smooth in the conditions
    and stays. Returns the problem without them (the same object when there are none)."""
    X = pb.features
    valid, spikes = dict(pb.valid), {}
    for c in pb.columns:
        m = valid[c]
        rows = np.flatnonzero(m)
        if rows.size < 20:
            continue
        r = (pb.measured[c] - pred[c])[m]
        A = np.column_stack([np.ones(rows.size), X[m]])
        coef, *_ = np.linalg.lstsq(A, r, rcond=None)
        e = r - A @ coef
        s = stats.median_abs_deviation(e, scale="normal")
        bad = np.abs(e - np.median(e)) > SPIKE_SIGMA * s if s > 0 else np.zeros(e.size, bool)
        if bad.any() and bad.sum() <= MAX_SPIKE_SHARE * rows.size:
            valid[c] = m.copy()
            valid[c][rows[bad]] = False
            spikes[c] = [int(i) + 1 for i in rows[bad]]      # 1-based, as in the file
    if not spikes:
        return pb
    note = "spikes left out (row numbers): " + "; ".join(
        f"{c}: {', '.join(map(str, v))}" for c, v in spikes.items())
    return replace(pb, valid=valid, spikes=spikes, notes=pb.notes + (note,))


def baseline_noise(pb: Problem, pred: dict) -> Noise:
    """Each column's noise level from the baseline residuals (given levels kept), never below
    round-off (ROUND_OFF x its largest value), and its AR(1) coefficient (`noise_ar1`)."""
    sigma, sigma_w = dict(pb.noise.sigma), dict(pb.noise.sigma_w)
    rho, source = dict(pb.noise.rho), dict(pb.noise.source)
    rho_hi = {c: v for c, v in pb.noise.rho_hi.items() if c in pb.noise.given}
    for c in pb.columns:
        if c in pb.noise.given:
            continue
        s, source[c] = data_sigma(pb, c, pb.measured[c] - pred[c])
        floor = ROUND_OFF * max(np.nanmax(np.abs(pb.measured[c])), 1e-300)
        sigma[c] = sigma_w[c] = max(s, floor)
        rho[c] = 0.0
        ar1 = noise_ar1(pb, c, pred[c], floor)
        if ar1 is not None:
            rho[c], sigma_w[c], sigma[c], rho_hi[c] = ar1
    return Noise(sigma, sigma_w, rho, source, pb.noise.given, rho_hi)


def noise_ar1(pb: Problem, c: str, pred: np.ndarray, floor: float
              ) -> tuple[float, float, float] | None:
    """Serial correlation of column c's noise: the restricted maximum-likelihood AR(1)
    coefficient of the baseline residuals regressed on the smoother in the conditions, over the
    whole series as one AR(1) chain (what a model error would look like is taken out first; the
    restricted likelihood does not charge the smoother's degrees of freedom to the noise:
    `stats.ar1_regression_reml`). When significant (restricted likelihood ratio > AR1_LR):
    (rho, the innovation level from the second differences of the whitened residuals over the
    whole series, the marginal level sigma_w / sqrt(1 - rho^2), the 99.9 % upper profile bound
    of rho); else None (white noise).
    Only for time series (`time_s` increasing): in a table of steady points the row order
    means nothing, and neighbouring rows of a grid share a model error, not a noise."""
    if not pb.is_time_series:
        return None
    m = pb.valid[c]
    r = (pb.measured[c] - pred)[m]
    whole = np.zeros(r.size, int)
    A = np.column_stack([np.ones(r.size), pb.features[m]])
    rho, lr, rho_hi = ar1_regression_reml(r, A)
    if lr <= AR1_LR or rho <= 0.0:
        return None
    u = ar1_whiten(r, whole, rho)
    s_w = max(noise_sigma(u, whole), floor * math.sqrt(1 - rho * rho))
    return rho, s_w, s_w / math.sqrt(1 - rho * rho), rho_hi
