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
from studies.diagnosis.noisemodel import CONSISTENCY_ALPHA, consistency
from studies.diagnosis.problem import ROUND_OFF, Noise, Problem, data_sigma, with_stated_shape
from studies.diagnosis.stats import (ar1_regression_reml, ar1_whiten, auto_blocks, noise_sigma,
                                     orth)
from studies.model.effects.thermal_lag import lag_response

#: likelihood-ratio statistic (chi-square, 1 df) of AR(1) errors against white ones, with the
#: conditions' smoother as the regression, above which a column's noise is taken as AR(1) and
#: whitened (slowly drifting sensors); 9 = a 3-sigma level
AR1_LR = 9.0
#: a residual this many robust standard deviations from the smoother is a spike (P = 2e-9 for
#: Gaussian noise), if such entries are at most MAX_SPIKE_SHARE of the column
SPIKE_SIGMA = 6.0
MAX_SPIKE_SHARE = 0.05
#: in a time series, a run of more than this many consecutive flagged entries is a model error,
#: not spikes: k independent spikes among n entries form a run of three about k^3 / n^2 times
#: (0.03 at MAX_SPIKE_SHARE of 240 rows), while a misfit at a column's lowest stated readings
#: is a run (seed 000's forced-air history with 1.5 % of reading: 5 rows at the hot end)
MAX_SPIKE_RUN = 2
#: time constants of the first-order lags of the temperature conditions held in the AR(1) test's
#: regression (`history_basis`): this many, geometric from HISTORY_TAU_FROM sample intervals to
#: HISTORY_TAU_TO of the record
HISTORY_TAUS = 6
HISTORY_TAU_FROM = 2.0
HISTORY_TAU_TO = 0.25
#: rows per regressor the AR(1) test's regression asks for before the history basis is added (as
#: the conditions' smoother: `Problem.features`, 12 rows per column)
ROWS_PER_REGRESSOR = 12


def calibrate(pb: Problem) -> tuple[Problem, Baseline]:
    """Nuisance-only fit in two passes (noise from the measured data, then from the baseline
    residuals), its residual description and held-out residuals."""
    bspace = pb.space([])
    base = pb.fit(bspace, np.zeros(bspace.lo.size))
    if pb.noise.stated:     # a stated noise's readings, a column's values smoothed alike
        noise = replace(pb.noise, stated=stated_columns_smoothed(pb))
        pb = replace(pb, noise=with_stated_shape(noise, pb.measured, pb.valid,
                                                 stated_readings(pb)))
        base = pb.fit(bspace, base.u)
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


#: rows of the running mean of the measured values a stated noise is evaluated at in a time
#: series (`stated_readings`)
READING_ROWS = 5


def stated_readings(pb: Problem) -> dict[str, np.ndarray]:
    """The readings a stated noise is evaluated at (`noisemodel` module docstring): in a time
    series the running mean of READING_ROWS consecutive measured values of the column (centred;
    fewer at the ends): a row's own noise then carries 1 / READING_ROWS of its weight, so the
    weights' correlation with the noise, and the bias of about 2 REL^2 of the reading it gives a
    weighted fit (Carroll & Ruppert 1988, ch. 2.3), shrinks that much; elsewhere the measured
    values. Not the baseline's prediction: a model that misses a lag by a factor 5 in torque at
    the cold end would put the weights wrong by that factor. Rows not compared: the measured
    value (NaN)."""
    return {c: _running_mean(pb, c, pb.measured[c]) for c in pb.noise.stated}


def stated_columns_smoothed(pb: Problem) -> dict:
    """The statements of `pb.noise.stated` with each `sigma_<column>` statement's per-row values
    replaced by their running mean over READING_ROWS rows in a time series (`_running_mean`),
    the same as a `--noise` statement's readings (`stated_readings`). Per-row uncertainties are
    mostly a share of each row's own reading, so they carry its noise; a weight that carries
    noise multiplies the configured model's misfit by it: on the flywheel's two decades of
    torque with a 1500 s lag (the configured model 5 x the measured torque at the cold end),
    1.5 % of each measured value as `sigma_torque_Nmm` divides a misfit of 4 readings by a
    weight 1.5 % noisy, which adds white noise of 4 stated sigma to the standardised residual
    there: the data's level contradicted the statement (13 x) and the lag came back
    `unexplained`. The running mean divides that noise by sqrt(5). A step of the stated values
    (a range switch) is spread over the READING_ROWS - 1 rows about it."""
    out = {}
    for c, st in pb.noise.stated.items():
        if st.rows is not None:
            st = replace(st, rows=_running_mean(pb, c, st.rows))
        out[c] = st
    return out


def _running_mean(pb: Problem, c: str, values) -> np.ndarray:
    """Column c's `values` (one per row) as their centred running mean over READING_ROWS of its
    compared rows (fewer at the ends) in a time series; as they are elsewhere and on rows not
    compared."""
    y = np.asarray(values, float).copy()
    m = pb.valid[c]
    if pb.is_time_series and m.sum() >= READING_ROWS:
        k = np.ones(READING_ROWS)
        v = y[m]
        y[m] = np.convolve(v, k, "same") / np.convolve(np.ones(v.size), k, "same")
    return y


def stated_noise_notes(noise: Noise) -> tuple[str, ...]:
    """One note per column whose stated noise the data contradict (`noisemodel.consistency`):
    the data's level against the stated one; the weights keep the stated shape, the level used
    is the data's."""
    out = []
    for c, chk in noise.consistency.items():
        if not chk.consistent:
            out.append(f"stated noise of {c} contradicted by the data: its level is "
                       f"{chk.ratio:.3g} x the stated one ({100 * (1 - CONSISTENCY_ALPHA):g} % "
                       f"interval {chk.ratio_lo:.3g}..{chk.ratio_hi:.3g}); the rows keep the "
                       "stated weights, the level used is the data's")
    return tuple(out)


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
    and stays, and in a time series so does a run of more than MAX_SPIKE_RUN consecutive such
    entries (`without_runs`: a spike is one reading). Returns the problem without them (the
    same object when there are none)."""
    X = pb.features
    valid, spikes = dict(pb.valid), {}
    for c in pb.columns:
        m = valid[c]
        rows = np.flatnonzero(m)
        if rows.size < 20:
            continue
        r = pb.scaled_residual(c, pred[c])[m]
        A = np.column_stack([np.ones(rows.size), X[m]])
        coef, *_ = np.linalg.lstsq(A, r, rcond=None)
        e = r - A @ coef
        s = stats.median_abs_deviation(e, scale="normal")
        bad = np.abs(e - np.median(e)) > SPIKE_SIGMA * s if s > 0 else np.zeros(e.size, bool)
        if pb.is_time_series:
            bad = without_runs(bad, MAX_SPIKE_RUN)
        if bad.any() and bad.sum() <= MAX_SPIKE_SHARE * rows.size:
            valid[c] = m.copy()
            valid[c][rows[bad]] = False
            spikes[c] = [int(i) + 1 for i in rows[bad]]      # 1-based, as in the file
    if not spikes:
        return pb
    note = "spikes left out (row numbers): " + "; ".join(
        f"{c}: {', '.join(map(str, v))}" for c, v in spikes.items())
    return replace(pb, valid=valid, spikes=spikes, notes=pb.notes + (note,))


def without_runs(flags: np.ndarray, longest: int) -> np.ndarray:
    """`flags` (bool, entries in time order) with every run of more than `longest` consecutive
    True entries set False."""
    f = np.asarray(flags, bool)
    edge = np.diff(np.concatenate([[0], f.astype(int), [0]]))
    out = f.copy()
    for a, b in zip(np.flatnonzero(edge == 1), np.flatnonzero(edge == -1)):
        if b - a > longest:
            out[a:b] = False
    return out


def baseline_noise(pb: Problem, pred: dict) -> Noise:
    """Each column's noise level from the baseline residuals (given levels kept), never below
    round-off (ROUND_OFF x its largest value), and its AR(1) coefficient (`noise_ar1`, with the
    history basis in its regression in every column when a history effect shows in one:
    `history_in_residuals`). A column with a stated noise: the same on the residual divided by
    its per-row shape (the level at a row of RMS stated uncertainty), checked against the
    stated level (`noisemodel.consistency`)."""
    sigma, sigma_w = dict(pb.noise.sigma), dict(pb.noise.sigma_w)
    rho, source = dict(pb.noise.rho), dict(pb.noise.source)
    rho_hi = {c: v for c, v in pb.noise.rho_hi.items() if c in pb.noise.given}
    history = history_in_residuals(pb, pred)
    for c in pb.columns:
        if c in pb.noise.given:
            continue
        s, source[c] = data_sigma(pb, c, pb.measured[c] - pred[c])
        floor = ROUND_OFF * max(np.nanmax(np.abs(pb.measured[c])), 1e-300)
        sigma[c] = sigma_w[c] = max(s, floor)
        rho[c] = 0.0
        if c in pb.noise.stated and white_statement_holds(pb, c, sigma[c]):
            continue
        ar1 = noise_ar1(pb, c, pred[c], floor, history)
        if ar1 is not None:
            rho[c], sigma_w[c], sigma[c], rho_hi[c] = ar1
    checks = {c: consistency(sigma[c] / pb.noise.stated_sigma[c], int(pb.valid[c].sum()), rho[c])
              for c in pb.noise.stated}
    return replace(pb.noise, sigma=sigma, sigma_w=sigma_w, rho=rho, source=source,
                   rho_hi=rho_hi, consistency=checks)


def white_statement_holds(pb: Problem, c: str, s_white: float) -> bool:
    """Does the data's white-noise level `s_white` of stated column c (second differences of
    the residual divided by the stated shape: blind to a smooth model error) agree with the
    stated level (`noisemodel.consistency`)? Then the statement's white noise stands and no
    AR(1) model is fitted: what the AR(1) test would see in the baseline residual beyond it is a
    model error, not the sensor (a drifting sensor of stated marginal level shows a
    second-difference level well below it, sqrt((1 - rho)(3 - rho) / 3) of it, 0.26 at rho
    0.9: it fails this check and gets its AR(1) model)."""
    return consistency(s_white / pb.noise.stated_sigma[c], int(pb.valid[c].sum())).consistent


def history_basis(pb: Problem) -> np.ndarray:
    """What a history effect of the temperatures would leave in the baseline residuals, for the
    AR(1) test's regression (`noise_ar1`): for each varying temperature condition T (`T_*_C`)
    and HISTORY_TAUS time constants tau (geometric, HISTORY_TAU_FROM median sample intervals to
    HISTORY_TAU_TO of the record), the first-order lag's departure L_tau[T] - T (the exact
    response to T piecewise linear, `thermal_lag.lag_response`; Incropera ch. 5.3 lumped body)
    and its product with the standardised T (a sensitivity changing across the range), each
    standardised. A lag of another time constant lies between its neighbours (the family is
    smooth in log tau); the rate dT/dt of `Problem.features` is its limit tau -> 0. Empty
    (n x 0) outside a time series or when the rows cannot carry ROWS_PER_REGRESSOR per column
    beside the smoother."""
    keys = [k for k in pb.conditions
            if k.startswith("T_") and k.endswith("_C") and np.nanstd(pb.conditions[k]) > 0]
    n_cols = 2 * HISTORY_TAUS * len(keys)
    if (not pb.is_time_series or not keys
            or pb.n < ROWS_PER_REGRESSOR * (n_cols + pb.features.shape[1] + 1)):
        return np.zeros((pb.n, 0))
    t = np.asarray(pb.conditions["time_s"], float)
    taus = np.geomspace(HISTORY_TAU_FROM * float(np.median(np.diff(t))),
                        HISTORY_TAU_TO * float(t[-1] - t[0]), HISTORY_TAUS)
    z = lambda x: (x - np.mean(x)) / (np.std(x) or 1.0)     # noqa: E731
    cols = []
    for k in keys:
        T = np.asarray(pb.conditions[k], float)
        for tau in taus:
            d = z(lag_response(t, T, float(tau)) - T)
            cols += [d, z(d * z(T))]
    return np.column_stack(cols)


def history_explains(r: np.ndarray, A: np.ndarray, H: np.ndarray, rho: float) -> bool:
    """Does the history basis H explain the residuals r beyond the regression A under AR(1)
    errors of coefficient rho (the one estimated without H)? The generalised least-squares F
    test of the added columns on the Prais-Winsten whitened rows (`stats.ar1_whiten`; Greene,
    Econometric Analysis, 7th ed., ch. 5: the F test of added regressors; ch. 20: feasible GLS
    with AR(1) disturbances): F = ((SSE_A - SSE_AH) / q) / (SSE_AH / (n - p)),
    q and p the ranks added and in all, significant at the level of AR1_LR (chi-square with one
    degree of freedom: P = 2.7e-3). Judged under the correlated noise it would replace, the test
    keeps real AR(1) noise: no switch in 96 columns of AR(1) 0.9-0.95 noise on 240-row cycles
    (measured 2026-11-29), where the likelihood-ratio test of the two models each at its own
    maximum-likelihood rho (few effective rows at rho 0.95) switched often and biased rho low."""
    seg = np.zeros(r.size, int)
    u = ar1_whiten(r, seg, rho)

    def sse(X):
        B = ar1_whiten(X, seg, rho)
        coef, *_ = np.linalg.lstsq(B, u, rcond=None)
        return float(np.sum((u - B @ coef) ** 2)), int(np.linalg.matrix_rank(B))

    (s0, p0), (s1, p1) = sse(A), sse(np.column_stack([A, H]))
    q, dof = p1 - p0, r.size - p1
    if q <= 0 or dof <= 0 or s1 <= 0:
        return False
    return bool(stats.f.sf((s0 - s1) / q / (s1 / dof), q, dof) < stats.chi2.sf(AR1_LR, 1))


def history_in_residuals(pb: Problem, pred: dict) -> bool:
    """Does a history effect of the temperatures show in the baseline residuals? True when in
    some column whose noise is estimated the AR(1) coefficient of the residuals regressed on the
    smoother is significant (`noise_ar1`'s test) and the lagged temperatures (`history_basis`)
    explain them beyond the smoother under that AR(1) (`history_explains`). One answer for
    every column: the columns share the conditions, and a lag moves all of them."""
    if not pb.is_time_series:
        return False
    H = history_basis(pb)
    if not H.shape[1]:
        return False
    for c in pb.columns:
        if c in pb.noise.given:
            continue
        m = pb.valid[c]
        r = pb.scaled_residual(c, pred[c])[m]
        A = ar1_regressors(pb, m, False)
        rho, lr, _ = ar1_regression_reml(r, A)
        if lr > AR1_LR and rho > 0.0 and history_explains(r, A, H[m], rho):
            return True
    return False


def ar1_regressors(pb: Problem, m: np.ndarray, history: bool) -> np.ndarray:
    """The AR(1) test's regression on the rows m: a constant and the conditions' smoother
    (`Problem.features`), with the history basis (`history_basis`) when `history`."""
    return np.column_stack([np.ones(int(m.sum())), pb.features[m]]
                           + ([history_basis(pb)[m]] if history else []))


def noise_ar1(pb: Problem, c: str, pred: np.ndarray, floor: float, history: bool = False
              ) -> tuple[float, float, float] | None:
    """Serial correlation of column c's noise: the restricted maximum-likelihood AR(1)
    coefficient of the baseline residuals regressed on the smoother in the conditions (and on
    the lagged temperatures, `history_basis`, when `history`), over the whole series as one
    AR(1) chain (what a model error would look like is taken out first; the restricted
    likelihood does not charge the regressors' degrees of freedom to the noise:
    `stats.ar1_regression_reml`). A smooth effect the regression cannot represent is taken for
    AR(1) noise of coefficient near 1 (smoothing and serial correlation are confounded unless
    the smooth part is modelled: Opsomer, Wang & Yang 2001, Nonparametric regression with
    correlated errors, Statist. Sci. 16): a shaft 900 s behind the hub, whose residual is not a
    function of the conditions' levels, was read as AR(1) 0.99 at 7-15 x the noise;
    so the AR(1) estimate is tested against a history effect (`history_in_residuals`) and, when
    the lagged temperatures explain the residuals, they join the regression.
    When significant (restricted likelihood ratio > AR1_LR):
    (rho, the innovation level from the second differences of the whitened residuals over the
    whole series, the marginal level sigma_w / sqrt(1 - rho^2), the 99.9 % upper profile bound
    of rho); else None (white noise).
    Only for time series (`time_s` increasing): in a table of steady points the row order
    means nothing, and neighbouring rows of a grid share a model error, not a noise."""
    if not pb.is_time_series:
        return None
    m = pb.valid[c]
    r = pb.scaled_residual(c, pred)[m]
    whole = np.zeros(r.size, int)
    rho, lr, rho_hi = ar1_regression_reml(r, ar1_regressors(pb, m, history))
    if lr <= AR1_LR or rho <= 0.0:
        return None
    u = ar1_whiten(r, whole, rho)
    s_w = max(noise_sigma(u, whole), floor * math.sqrt(1 - rho * rho))
    return rho, s_w, s_w / math.sqrt(1 - rho * rho), rho_hi
