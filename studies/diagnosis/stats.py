"""Statistics of the diagnosis, as pure functions: the chi-bar-square null, the robust noise level
from second differences, contiguous blocks, orthonormal bases and principal-angle cosines, and
bounded least squares."""
from __future__ import annotations

import math

import numpy as np
from scipy import linalg, optimize, stats

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


def noise_sigma(r: np.ndarray, seg: np.ndarray, shape: np.ndarray | None = None) -> float:
    """Noise standard deviation from second differences within segments (robustly trimmed at 4
    sigma; unbiased for white noise, blind to smooth structure, insensitive to a few steps).
    shape: per-row relative noise level (heteroscedastic white noise of standard deviation
    sigma x shape): each second difference divided by its own standard deviation in units of
    sigma, sqrt((s_a^2 + 4 s_b^2 + s_c^2) / 6), so the smooth structure is removed before the
    division and a jitter of the shape cannot turn a large smooth residual into noise."""
    r = np.asarray(r, float)
    ok = np.isfinite(r)
    idx = np.flatnonzero(ok)
    if idx.size < 3:
        return float(np.nanstd(r)) if idx.size > 1 else 0.0
    a, b, c = idx[:-2], idx[1:-1], idx[2:]
    same = (seg[a] == seg[b]) & (seg[b] == seg[c])
    d2 = r[a[same]] - 2 * r[b[same]] + r[c[same]]
    if shape is not None:
        sh = np.asarray(shape, float)
        d2 = d2 / np.sqrt((sh[a[same]] ** 2 + 4 * sh[b[same]] ** 2 + sh[c[same]] ** 2) / 6.0)
    if d2.size < 5:
        return float(np.std(r[ok], ddof=1))
    d2 = d2 - np.median(d2)            # a steady curvature of the residuals is not noise
    s_rob = stats.median_abs_deviation(d2, scale="normal") / math.sqrt(6.0)
    if s_rob > 0:
        kept = d2[np.abs(d2) <= 4.0 * math.sqrt(6.0) * s_rob]
        d2 = kept if kept.size >= 5 else d2
    trunc = 1.0 - 2 * 4.0 * stats.norm.pdf(4.0) / (1 - 2 * stats.norm.sf(4.0))
    return float(math.sqrt(np.mean(d2 ** 2) / 6.0 / (trunc if s_rob > 0 else 1.0)))


def auto_blocks(n: int, k: int) -> np.ndarray:
    """Labels of k contiguous blocks of n rows (at least 2, at most n // 8 for n >= 16)."""
    k = max(2, min(k, n // 8 if n >= 16 else 2))
    return np.minimum((np.arange(n) * k) // n, k - 1)


def orth(A: np.ndarray, rtol: float = 1e-8) -> np.ndarray:
    """Orthonormal basis of the range of A (columns), singular values below rtol times the
    largest dropped (`scipy.linalg.orth`); an empty basis for an empty or zero A."""
    if A.size == 0 or A.shape[1] == 0 or not np.any(A):
        return np.zeros((A.shape[0], 0))
    return linalg.orth(A, rcond=rtol)


def max_cosine(Qa: np.ndarray, Qb: np.ndarray) -> float:
    """Cosine of the smallest principal angle between two subspaces (orthonormal bases Qa, Qb;
    `scipy.linalg.subspace_angles`): 1 when they share a direction, 0 when orthogonal or empty."""
    if Qa.shape[1] == 0 or Qb.shape[1] == 0:
        return 0.0
    return float(np.cos(linalg.subspace_angles(Qa, Qb).min()))


def blsq(A: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """min ||A x - b|| subject to lo <= x <= hi (small dense problems; exact active set)."""
    x, *_ = np.linalg.lstsq(A, b, rcond=None)
    if np.all(x >= lo) and np.all(x <= hi):
        return x
    hi = np.maximum(hi, lo + 1e-15)
    return optimize.lsq_linear(A, b, bounds=(lo, hi), method="bvls").x




def _segment_starts(seg: np.ndarray) -> np.ndarray:
    """True at the first row of each run of equal labels."""
    seg = np.asarray(seg)
    return np.concatenate([[True], seg[1:] != seg[:-1]]) if seg.size else np.zeros(0, bool)


def ar1_whiten(r: np.ndarray, seg: np.ndarray, rho: float) -> np.ndarray:
    """Prais-Winsten transform of an AR(1) series within segments: u_t = r_t - rho r_(t-1), the
    first row of a segment r_0 sqrt(1 - rho^2); white noise of the innovation variance when r is
    AR(1) with coefficient rho (Prais & Winsten 1954). rho = 0 returns r."""
    r = np.asarray(r, float)
    if rho == 0.0:
        return r.copy()
    start = _segment_starts(seg)
    u = np.empty_like(r)
    u[1:] = r[1:] - rho * r[:-1]            # every row after the first; segment starts next
    u[start] = r[start] * math.sqrt(1.0 - rho * rho)
    return u


def ar1_unwhiten(u: np.ndarray, seg: np.ndarray, rho: float) -> np.ndarray:
    """Inverse of `ar1_whiten` (same segments and rho)."""
    u = np.asarray(u, float)
    if rho == 0.0:
        return u.copy()
    start = _segment_starts(seg)
    r = np.empty_like(u)
    for i in range(u.shape[0]):
        r[i] = u[i] / math.sqrt(1.0 - rho * rho) if start[i] else u[i] + rho * r[i - 1]
    return r


def ar1_coefficient(e: np.ndarray, seg: np.ndarray) -> tuple[float, float]:
    """Lag-1 autocorrelation of e within segments (Cochrane & Orcutt 1949 on the residuals of a
    regression) and its z score rho sqrt(pairs) under white noise."""
    e = np.asarray(e, float) - np.mean(e)
    start = _segment_starts(seg)
    pairs = ~start
    den = float(e @ e)
    if den == 0.0 or pairs.sum() < 3:
        return 0.0, 0.0
    rho = float(np.sum(e[pairs] * np.roll(e, 1)[pairs]) / den)
    return rho, rho * math.sqrt(float(pairs.sum()))


def ar1_regression_ml(r: np.ndarray, A: np.ndarray, seg: np.ndarray,
                      grid: np.ndarray = np.linspace(0.0, 0.95, 96)) -> tuple[float, float]:
    """Maximum-likelihood AR(1) coefficient of the errors of the regression r ~ A (exact
    Prais-Winsten likelihood profiled over rho on a grid; Beach & MacKinnon 1978): returns rho and
    the likelihood-ratio statistic against rho = 0 (chi-square with one degree of freedom under
    white noise). Less biased than the lag-1 autocorrelation of OLS residuals, which the
    regression's smooth terms pull towards zero."""
    r = np.asarray(r, float)
    n = r.size
    n_seg = int(_segment_starts(seg).sum())
    best, ll0, ll_best = 0.0, None, -np.inf
    for rho in grid:
        u = ar1_whiten(r, seg, float(rho))
        B = ar1_whiten(A, seg, float(rho))
        coef, *_ = np.linalg.lstsq(B, u, rcond=None)
        sse = float(np.sum((u - B @ coef) ** 2))
        if sse <= 0:
            continue
        ll = -0.5 * n * math.log(sse / n) + 0.5 * n_seg * math.log(1.0 - rho * rho)
        if rho == 0.0:
            ll0 = ll
        if ll > ll_best:
            best, ll_best = float(rho), ll
    return best, (2.0 * (ll_best - ll0) if ll0 is not None else 0.0)



#: AR(1) coefficients searched by `ar1_regression_reml` (a strongly correlated torque cell at
#: 120 s has phi 0.9-0.95; the grid reaches 0.99)
AR1_GRID = np.round(np.linspace(0.0, 0.99, 100), 2)


def ar1_regression_reml(r: np.ndarray, A: np.ndarray, grid: np.ndarray = AR1_GRID,
                        ci_lr: float = 10.83) -> tuple[float, float, float]:
    """Restricted maximum-likelihood AR(1) coefficient of the errors of the regression r ~ A
    over the whole series (one AR(1) chain, Prais-Winsten transform; the REML log likelihood
    -(n - p)/2 log(SSE_w / (n - p)) + 1/2 log(1 - rho^2) - 1/2 log det(B^T B), B the whitened
    regressors, profiled over rho on a grid; Harville 1977, Maximum likelihood approaches to
    variance component estimation, JASA 72; Cooper & Thompson 1977, A note on the estimation of
    the parameters of the autoregressive-moving average process, Biometrika 64): returns rho and
    the restricted likelihood-ratio statistic against rho = 0 (chi-square with one degree of
    freedom under white noise). ML (`ar1_regression_ml`) is biased low by about
    (1 + 3 rho + p (1 + rho)) / n when the regression has p columns; REML removes most of the
    part due to the regressors (measured: `tests/test_diagnosis_fit.py`)."""
    r = np.asarray(r, float)
    n = r.size
    seg = np.zeros(n, int)
    p = int(np.linalg.matrix_rank(A)) if A.size else 0
    best, ll0, ll_best = 0.0, None, -np.inf
    lls = []
    for rho in grid:
        rho = float(rho)
        u = ar1_whiten(r, seg, rho)
        B = ar1_whiten(A, seg, rho)
        coef, *_ = np.linalg.lstsq(B, u, rcond=None)
        sse = float(np.sum((u - B @ coef) ** 2))
        if sse <= 0 or n - p <= 0:
            continue
        sv = np.linalg.svd(B, compute_uv=False)
        sv = sv[sv > 1e-10 * sv[0]] if sv.size else sv
        logdet = float(2.0 * np.sum(np.log(sv)))
        ll = (-0.5 * (n - p) * math.log(sse / (n - p)) + 0.5 * math.log(1.0 - rho * rho)
              - 0.5 * logdet)
        lls.append((rho, ll))
        if rho == 0.0:
            ll0 = ll
        if ll > ll_best:
            best, ll_best = rho, ll
    hi = max((x for x, ll in lls if 2.0 * (ll_best - ll) <= ci_lr), default=best)
    return best, (2.0 * (ll_best - ll0) if ll0 is not None else 0.0), float(hi)


def noise_sigma_steady(r: np.ndarray, conditions: dict[str, np.ndarray]) -> tuple[float, str]:
    """Noise standard deviation of a table of steady points (no time order), from the structure
    of the design rather than the row order:

    - replicates (rows with identical conditions): the pooled within-group standard deviation
      (pure error; Box, Hunter & Hunter, Statistics for Experimenters, ch. 10);
    - otherwise second differences along each varying condition with the others held fixed (the
      grid lines of the design), pooled and robustly trimmed as in `noise_sigma`, weighted
      (1, -2, 1) / sqrt(6) so that white noise gives its sigma; a model error smooth in the
      conditions cancels to second order, whatever the row order.

    Returns (sigma, how) or (0.0, "") when the design has neither replicates nor lines of three."""
    r = np.asarray(r, float)
    keys = [k for k, v in conditions.items() if np.nanstd(np.asarray(v, float)) > 0]
    if not keys:
        return 0.0, ""
    X = np.column_stack([np.asarray(conditions[k], float) for k in keys])
    _, group = np.unique(X, axis=0, return_inverse=True)
    group = group.ravel()
    counts = np.bincount(group)
    if np.sum(counts[counts > 1] - 1) >= 5:                       # replicates
        means = np.bincount(group, weights=r) / counts
        dev = r - means[group]
        dof = int(np.sum(counts - 1))
        return float(np.sqrt(np.sum(dev ** 2) / dof)), "replicates (pure error)"
    d2 = []
    for j, k in enumerate(keys):
        others = np.delete(X, j, axis=1)
        _, line = (np.unique(others, axis=0, return_inverse=True) if others.shape[1]
                   else (None, np.zeros(len(r), int)))
        line = np.asarray(line).ravel()
        for g in np.unique(line):
            idx = np.flatnonzero(line == g)
            idx = idx[np.argsort(X[idx, j], kind="stable")]
            if idx.size < 3:
                continue
            x, y = X[idx, j], r[idx]
            # second divided difference scaled to unit weights on an even grid: for uneven
            # spacing the weights (h2, -(h1 + h2), h1) / ... keep a linear trend exactly cancelled
            h1, h2 = np.diff(x)[:-1], np.diff(x)[1:]
            a, b, c = h2, -(h1 + h2), h1
            norm = np.sqrt(a ** 2 + b ** 2 + c ** 2)
            d2.append((a * y[:-2] + b * y[1:-1] + c * y[2:]) / norm)
    if not d2:
        return 0.0, ""
    d = np.concatenate(d2)
    if d.size < 5:
        return 0.0, ""
    d = d - np.median(d)
    s_rob = stats.median_abs_deviation(d, scale="normal")
    if s_rob > 0:
        kept = d[np.abs(d) <= 4.0 * s_rob]
        d = kept if kept.size >= 5 else d
    trunc = 1.0 - 2 * 4.0 * stats.norm.pdf(4.0) / (1 - 2 * stats.norm.sf(4.0))
    return float(math.sqrt(np.mean(d ** 2) / (trunc if s_rob > 0 else 1.0))), \
        "second differences along each condition of the design"
