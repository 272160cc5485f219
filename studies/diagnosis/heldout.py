"""Phase 4 of the diagnosis: held-out gain. Each contiguous block is predicted from parameters
refitted on the other blocks; a paired block bootstrap of the RMSE difference must exclude zero;
a candidate passes when its likelihood ratio, BIC and held-out gain all say so (module docstring
of `studies.diagnosis.engine`, step 4).

History effects (a profiled parameter such as a settling threshold) are refitted in full on the
kept blocks: the profiled value is re-selected over its whole grid (linearised about the full-data
fit), then every other parameter and the nuisance are refitted on the kept rows (chord iterations,
each step a real model call). A block the kept blocks cannot test is left out of the held-out gain and reported
(`heldout_untestable`): when a parameter does not move the kept rows' predictions (the trigger
never occurs there), or when another value of the profiled parameter predicts the kept rows
identically but the held-out block differently (the trigger falls inside the held-out block, so
where it falls cannot be learnt from the others). Cross-validation can only test what the
training folds identify (Arlot & Celisse 2010, A survey of cross-validation procedures for model
selection, Statistics Surveys 4, on dependent data and blocks)."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Mapping

import numpy as np
from scipy import special

from studies.diagnosis import fitspec
from studies.diagnosis.candidate import Candidate, HeldoutGain
from studies.diagnosis.core import Baseline, Fit, Linearisation, ModelFailure, Screening
from studies.diagnosis.problem import Problem, longest_first
from studies.diagnosis.stats import blsq

#: relative size below which two predictions (or sensitivities) count as equal: round-off of a
#: row-wise model evaluation, far below any noise level
SAME_RTOL = 1e-8


#: grid values (best on the kept rows by the baseline linearisation) linearised again about the
#: full fit in a held-out refit; the chord iteration's largest number of steps and the step (in
#: scaled parameter units) below which it has converged
TOP_VALUES = 3
CHORD_ITER = 8
CHORD_STEP = 1e-4


def _lin_sse(J, z, lo, hi) -> tuple[float, np.ndarray]:
    """Chi-square and step of the bounded linear fit z + J x on the given entries."""
    x = blsq(J, -z, lo, hi)
    return float(np.sum((z + J @ x) ** 2)), x


#: smallest held-out RMSE gain (standardised, i.e. noise units of the whitened residuals) of a
#: history effect (`is_history`) when some column's noise is AR(1): slowly correlated noise
#: lets a lag, settling or run-in win a little on held-out blocks by chance (measured on toy
#: AR(1) nulls at rho 0.95, 240 rows: largest such gain 0.017 in 6 draws, one of which passed
#: the bootstrap) while a lag of 600 s under rho 0.9 noise gains 1.2-1.3
#: (docs/diagnosis.md, "Noise under strong correlation")
MIN_HISTORY_GAIN = 0.05

#: fewest testable held-out blocks for a held-out gain (a bootstrap over fewer is meaningless;
#: all of them when the data have fewer blocks)
MIN_TESTABLE_BLOCKS = 3


def validate(pb: Problem, cands: Mapping[str, Candidate], fits: dict[str, Fit], b: Baseline,
             rng: np.random.Generator, refits: dict | None = None
             ) -> tuple[dict[str, np.ndarray], list[str], dict[str, Candidate]]:
    """Held-out residuals per fitted candidate, the names of the candidates that pass, and
    every candidate (the fitted ones with their held-out numbers, status and reason: new
    records). `refits`: {name: (fit, its refit)} of an earlier stage of the same pass
    (`studies.diagnosis.staging`), filled here: a candidate with the same fit is not refitted
    (the refits draw no random numbers; the bootstraps are drawn again)."""
    th = pb.th
    base_ho, names_id = b.heldout_z, list(fits)
    cands = dict(cands)
    ho = {}

    def refit(name):
        """(held-out residuals, chosen profiled values or None, untestable blocks, failure
        message or None): the model calls of one candidate, no random numbers."""
        e = pb.effect(name)
        try:
            if fitspec.profile(e):
                return (*heldout_profile(pb, fits[name], e, base_ho), None)
            return heldout_linear(pb, fits[name]), None, {}, None
        except ModelFailure as exc:
            return None, None, {}, str(exc)

    # the candidates' refits are independent: on the engine's workers; the bootstraps below
    # draw from the engine's random numbers in the candidates' order
    names = list(names_id)
    refits = {} if refits is None else refits
    todo = [n for n in names if n not in refits or refits[n][0] is not fits[n]]
    got = pb.parallel(refit, todo,              # the longest fits first: their refits too
                      first=longest_first([cands[n].fit_cpu_s for n in todo]))
    refits.update({n: (fits[n], r) for n, r in zip(todo, got)})
    done = [refits[n][1] for n in names]
    passing = []
    for name, (z_ho, chosen, untestable, failed) in zip(names, done):
        e = pb.effect(name)
        new = {}
        if failed is not None:
            # no honest held-out number: the candidate cannot pass
            new["heldout_failed"] = failed
            ho[name] = base_ho.copy()
        else:
            ho[name] = z_ho
            if fitspec.profile(e):
                new["heldout_profile_values"] = chosen
                new["heldout_untestable"] = [
                    {"block": int(bk) + 1, "rows": pb.block_rows(bk), "reason": why}
                    for bk, why in sorted(untestable.items())]
        keep = np.ones(pb.n_blocks, bool)
        keep[list(untestable)] = False
        c = replace(cands[name], heldout_rmse=pb.col_rmse(ho[name]),
                    heldout_gain=bootstrap_gain(pb, rng, base_ho, ho[name], keep), **new)
        reasons = _rejections(pb, c, e)
        cands[name] = c.with_status(
            "passed" if not reasons else "rejected",
            "; ".join(reasons) if reasons else "beats the baseline in sample and on held-out "
                                               "blocks")
    passing = [n for n in names_id if cands[n].status == "passed"]
    return ho, passing, cands


def _rejections(pb: Problem, c: Candidate, e) -> list[str]:
    """Why a fitted candidate with its held-out gain does not pass (empty: it passes)."""
    th = pb.th
    reasons = []
    if not c.lr_significant:
        reasons.append(f"likelihood ratio not significant (p = {c.p_lr:.2g}, Holm)")
    if not c.delta_bic < -th["bic_margin"]:
        reasons.append(f"BIC not better than the baseline (delta {c.delta_bic:.1f})")
    need = min(MIN_TESTABLE_BLOCKS, pb.n_blocks)
    g = c.heldout_gain
    if g.n_blocks < need:
        reasons.append(f"only {g.n_blocks} held-out blocks can test it (need {need})")
    elif not g.excludes_zero:
        reasons.append("no held-out gain beyond noise (bootstrap interval "
                       f"[{g.ci[0]:.3g}, {g.ci[1]:.3g}] includes 0)")
    elif (is_history(e) and max(pb.noise.rho.values(), default=0.0) > 0.0
          and g.rmse_gain < MIN_HISTORY_GAIN):
        reasons.append(f"held-out gain {g.rmse_gain:.3g} noise units, below the "
                       f"{MIN_HISTORY_GAIN:g} a history effect needs under correlated noise")
    return reasons


def is_history(e) -> bool:
    """A history effect: its prediction depends on the time order (a lag, a settling after an
    excursion, a run-in), which slowly correlated noise can imitate."""
    return "time_s" in tuple(getattr(e, "requires", ()))


def heldout_linear(pb: Problem, fit: Fit) -> np.ndarray:
    """Held-out standardised residual per stacked entry: per fold, one bounded Gauss-Newton
    step from `fit` on the training entries (halved once if it does not lower the training
    chi-square), then a real model call."""
    return heldout_linear_of(pb, [fit])[0]


def heldout_linear_of(pb: Problem, fits: list[Fit]) -> list[np.ndarray]:
    """`heldout_linear` of several fits, their folds in one map on the engine's workers."""

    def fold(item):
        """The held-out block's residuals (its model call from the training-rows step)."""
        fit, b = fits[item[0]], item[1]
        sp = fit.space
        te = pb.entry_block == b
        tr = ~te
        J, z = fit.J[tr], fit.z[tr]
        if J.shape[1]:
            lo = np.minimum(sp.lo - fit.u, 0.0)
            hi = np.maximum(sp.hi - fit.u, 0.0)
            du = blsq(J, -z, lo, hi)
        else:
            du = np.zeros(0)
        sse0 = float(z @ z)
        for damp in (1.0, 0.5):
            try:
                zz, _ = pb.eval(sp, sp.clip(fit.u + damp * du))
            except ModelFailure:
                continue
            if float(zz[tr] @ zz[tr]) <= sse0 * (1 + 1e-9):
                break
        else:
            zz = fit.z             # keep the full-data fit (no better training fit found)
        return zz[te]

    # the folds are independent: on the engine's workers (inside a worker: one by one)
    blocks = [b for b in range(pb.n_blocks) if (pb.entry_block == b).any()]
    items = [(j, b) for j in range(len(fits)) for b in blocks]
    out = [np.empty(pb.N) for _ in fits]
    for (j, b), z_te in zip(items, pb.parallel(fold, items)):
        out[j][pb.entry_block == b] = z_te
    return out


def heldout_profile(pb: Problem, fit: Fit, e, base_ho: np.ndarray
                    ) -> tuple[np.ndarray, list, dict[int, str]]:
    """Held-out residuals for a candidate with a profiled parameter (a threshold), all its
    parameters refitted on the kept blocks (module docstring). Per held-out block:

    1. a global profile over the grid values the in-sample profile evaluated: each value's
       linearisation (at the baseline) is fitted to the kept rows; the TOP_VALUES best are
       linearised again about the full-data fit (cached across blocks) and the best of those
       on the kept rows is chosen;
    2. untestable (left out, see `_untestable`) or refined: every other parameter and the
       nuisance refitted on the kept rows by a chord (simplified Gauss-Newton) iteration to
       convergence with the Jacobian about the full fit, each step a real model call; the
       held-out block is predicted at the result.

    Returns the stacked held-out residuals (untestable blocks keep the baseline's: no gain
    claimed there), the chosen value per testable block and {block: reason} for the
    untestable ones."""
    (pp,) = fitspec.profile(e)
    grid_lin = fit.grid
    k = fit.space.k
    u = fit.u
    Jn = fit.J[:, k:]
    relin: dict[float, Linearisation | None] = {}

    def about_fit(g):
        v = g.value
        if v not in relin:
            space = g.space                   # same coordinates for every value of pp
            try:
                z0, _ = pb.eval(space, u)
                cols = []
                for i in range(k):
                    h = 1.0 if u[i] + 1.0 <= space.hi[i] else -1.0
                    du = np.zeros_like(u)
                    du[i] = h
                    cols.append((pb.eval(space, u + du)[0] - z0) / h)
                relin[v] = Linearisation(v, space, np.column_stack(cols + [Jn]), z0)
            except ModelFailure:
                relin[v] = None
        return relin[v]

    lo, hi = fit.space.lo - u, fit.space.hi - u
    z_ho = base_ho.copy()
    chosen, untestable = [], {}
    for b in range(pb.n_blocks):
        te = pb.entry_block == b
        tr = ~te
        if not te.any():
            continue
        ranked = sorted(grid_lin, key=lambda g: _lin_sse(g.J[tr], g.z[tr], g.lo, g.hi)[0])
        best = None
        for g in ranked[:TOP_VALUES]:
            L = about_fit(g)
            if L is None:
                continue
            sse, x = _lin_sse(L.J[tr], L.z[tr], lo, hi)
            if best is None or sse < best[0]:
                best = (sse, L, x, g)
        if best is None:
            raise ModelFailure(f"the model fails at every {pp} about the fit")
        _, L, x, g = best
        why = _untestable(g, grid_lin, tr, te, pp)
        if why:
            untestable[b] = why
            continue
        zz = _refit_rows(pb, L.space, u + x, tr, L.J, fallback=(u, L.z))
        z_ho[te] = zz[te]
        chosen.append(L.value)
    return z_ho, chosen, untestable

def _untestable(g: Linearisation, grid_lin: list[Linearisation], tr, te, pp: str) -> str | None:
    """Why the kept entries (`tr`) cannot test the held-out block (`te`) at the chosen value
    (`g`, its linearisation at the baseline: the effect's sensitivity per parameter), or
    None: a parameter whose sensitivity vanishes on the kept rows (the effect acts only in
    this block), or another value whose sensitivity equals the chosen one's on the kept rows
    but not on this block (where the trigger falls inside this block cannot be learnt)."""
    k = g.space.k
    Jg = g.J[:, :k]
    ref = max(float(np.max(np.abs(Jg), initial=0.0)), 1e-300)
    for i, (_, p) in enumerate(g.space.eff_params):
        full = float(np.max(np.abs(Jg[:, i])))
        if full > 0 and float(np.max(np.abs(Jg[tr, i]), initial=0.0)) <= SAME_RTOL * full:
            return (f"{p} does not change the predictions of the other blocks (at {pp} = "
                    f"{g.value:g} the effect acts only in this block)")
    for h in grid_lin:
        if h is g:
            continue
        Jh = h.J[:, :k]
        if (np.max(np.abs(Jh[tr] - Jg[tr]), initial=0.0) <= SAME_RTOL * ref
                and np.max(np.abs(Jh[te] - Jg[te]), initial=0.0) > SAME_RTOL * ref):
            a, c = sorted((g.value, h.value))
            return (f"{pp} = {a:g} and {c:g} act identically on the other blocks but not on "
                    "this one: the trigger falls inside this block, and where cannot be "
                    "learnt from the others")
    return None

def _refit_rows(pb: Problem, space, u0, rows, J, fallback=None) -> np.ndarray:
    """Bounded least squares on the stacked entries `rows` only: chord iterations (the
    Jacobian `J` held, each step a real model call, halved while it does not lower the
    kept rows' chi-square) until the step or the gain is negligible. `fallback`: (u, its
    standardised residuals) of a point already evaluated (the full-data fit at the chosen
    profiled value, `heldout_profile`): the iterations start from it instead of `u0` when `u0`
    fits the kept rows worse, as `heldout_linear` keeps the full-data fit when its step does
    not lower the training chi-square (a linearised step across a strongly nonlinear
    parameter, a rung's mount going from well coupled to none, can land far from both: th_
    mount_preload_loss seed 1 started at 40 times the full fit's training chi-square, which
    the held chord steps never left). Returns the stacked standardised residuals at the
    result (all entries)."""
    u = space.clip(np.asarray(u0, float))
    z, _ = pb.eval(space, u)
    sse = float(z[rows] @ z[rows])
    if fallback is not None:
        uf, zf = fallback
        ssef = float(zf[rows] @ zf[rows])
        if ssef < sse:
            u, z, sse = space.clip(np.asarray(uf, float)), np.asarray(zf, float), ssef
    Jr = J[rows]
    for _ in range(CHORD_ITER):
        du = blsq(Jr, -z[rows], space.lo - u, space.hi - u)
        if not np.any(np.abs(du) > CHORD_STEP):
            break
        for damp in (1.0, 0.5, 0.25):
            un = space.clip(u + damp * du)
            zn, _ = pb.eval(space, un)
            ssen = float(zn[rows] @ zn[rows])
            if ssen <= sse:
                break
        else:
            break
        gain = sse - ssen
        u, z, sse = un, zn, ssen
        if gain <= 1e-6 * max(sse, 1.0):
            break
    return z

def bootstrap_gain(pb: Problem, rng: np.random.Generator, z_base_ho, z_cand_ho,
                   keep=None, entries=None) -> HeldoutGain:
    """Paired block bootstrap of RMSE(baseline) - RMSE(candidate), standardised, held-out,
    over the blocks `keep` (boolean per block; default all) and the stacked entries `entries`
    (boolean per entry, e.g. one column's; default all)."""
    B = int(pb.th["n_boot"])
    keep = np.ones(pb.n_blocks, bool) if keep is None else np.asarray(keep, bool)
    w = np.ones(pb.N) if entries is None else np.asarray(entries, float)
    sb = np.bincount(pb.entry_block, weights=w * z_base_ho ** 2, minlength=pb.n_blocks)[keep]
    sc = np.bincount(pb.entry_block, weights=w * z_cand_ho ** 2, minlength=pb.n_blocks)[keep]
    nb = (np.bincount(pb.entry_block, minlength=pb.n_blocks).astype(float) if entries is None
          else np.bincount(pb.entry_block, weights=w, minlength=pb.n_blocks))[keep]
    if entries is not None:          # blocks without the entries' rows tell nothing
        used = nb > 0
        sb, sc, nb = sb[used], sc[used], nb[used]
    m = int(sb.size)
    if m == 0:
        return HeldoutGain(0.0, [0.0, 0.0], 0, 0, False)
    idx = rng.integers(0, m, size=(B, m))
    cnt = np.zeros((B, m))
    np.add.at(cnt, (np.repeat(np.arange(B), m), idx.ravel()), 1.0)
    nn = cnt @ nb
    d = np.sqrt(cnt @ sb / nn) - np.sqrt(cnt @ sc / nn)
    q = float(pb.th["heldout_quantile"])
    point = math.sqrt(sb.sum() / nb.sum()) - math.sqrt(sc.sum() / nb.sum())
    lo, hi = np.quantile(d, [q, 1 - q])
    return HeldoutGain(float(point), [float(lo), float(hi)], int(np.sum(sb > sc)), m,
                       bool(lo > 0))


#: the smallest held-out RMSE difference (noise units) by which a column counts as made worse
#: (`worse_columns`): a column's held-out RMSE, about 1 noise unit at a good model, changed by
#: less than a tenth moves its 90 % predictive interval by less than the tolerance that
#: interval's coverage is held to (85-95 %: half-widths 1.44-1.96 sigma about 1.645, -12 % and
#: +19 %)
WORSE_MIN_SIGMA = 0.1


@dataclass(frozen=True)
class WorseColumn:
    """A measured column the candidate predicts worse on held-out blocks than the model before
    it, beyond the noise (`worse_columns`): its held-out RMSE ratio (`gain`, candidate / before,
    column units), the mean over held-out blocks of the RMSE difference before minus candidate
    (noise units, `HeldoutGain`: its t interval at the column's Holm level lies below 0), one
    sentence."""
    effect: str
    column: str
    gain: float
    difference: HeldoutGain
    text: str


def worse_columns(pb: Problem, effect: str, z_base_ho: np.ndarray, z_cand_ho: np.ndarray,
                  keep=None) -> list[WorseColumn]:
    """The measured columns whose held-out residual the candidate `effect` makes worse than the
    model before it beyond the noise, corrected for the number of columns and with a
    minimum size. Per compared column and held-out block (over the blocks `keep`
    that test the candidate), the held-out RMSE before minus with the candidate (noise units);
    over the blocks, taken as independent as the block bootstrap takes them (Kunsch 1989, Ann.
    Statist. 17), the one-sided paired t test of "not worse" (Student 1908, Biometrika 6; its
    p values hold their level where the percentile bootstrap over 10 blocks does not: at a
    nominal 2.5 % it called a column of a null worse in 4 % of 300 draws, so a correction for
    several columns built on it kept the family near 9 % over 8 columns). Holm's step-down
    over the m compared columns at the family level `heldout_quantile` (Holm 1979, A simple
    sequentially rejective multiple test procedure, Scand. J. Statist. 6: the i-th smallest p
    against level / (m - i + 1), stopping at the first that is not below) keeps the chance
    that noise alone makes some column look worse at that level whatever the number of
    columns. A column it rejects is worse when its held-out RMSE ratio (candidate / before,
    column units) is above 1 and its mean difference is at least WORSE_MIN_SIGMA noise units
    (the minimum size). The interval reported is the t interval at the level of the column's
    Holm step (entirely below zero). Held-out standardised residuals of the same problem (noise
    model) for both."""
    before, after = pb.col_rmse(z_base_ho), pb.col_rmse(z_cand_ho)
    tests = {c: _block_t(pb, z_base_ho, z_cand_ho, keep, pb.entry_col == j)
             for j, c in enumerate(pb.columns)}
    level = float(pb.th["heldout_quantile"])
    m = len(tests)
    out = []
    for i, c in enumerate(sorted(tests, key=lambda c: tests[c][0])):
        a = level / (m - i)
        p, mean, se, used = tests[c]
        if not p < a:
            break                    # Holm: no later (larger) p is rejected either
        ratio = after[c] / before[c] if before[c] > 0 else 1.0
        half = float(special.stdtrit(used - 1, 1.0 - a)) * se
        g = HeldoutGain(mean, [mean - half, mean + half], 0, used, False)
        if not (ratio > 1.0 and -mean >= WORSE_MIN_SIGMA):
            continue
        out.append(WorseColumn(effect, c, float(ratio), g, (
            f"{effect} makes {c} worse on held-out blocks: held-out RMSE x {ratio:.4g} "
            f"({-mean:.3g} noise units worse per block, interval of the gain "
            f"[{g.ci[0]:.3g}, {g.ci[1]:.3g}] below 0 at the Holm level {a:.3g} over {m} "
            "columns)")))
    return sorted(out, key=lambda w: list(pb.columns).index(w.column))


def _block_t(pb: Problem, z_base_ho, z_cand_ho, keep, entries) -> tuple[float, float, float, int]:
    """(p of "not worse", mean difference, its standard error, blocks used) of the paired t
    test over held-out blocks of RMSE before minus RMSE with the candidate (noise units), on
    the stacked `entries` over the blocks `keep` (`worse_columns`); p = 1 with fewer than 2
    blocks or no spread."""
    keep = np.ones(pb.n_blocks, bool) if keep is None else np.asarray(keep, bool)
    w = np.asarray(entries, float)
    nb = np.bincount(pb.entry_block, weights=w, minlength=pb.n_blocks)[keep]
    sb = np.bincount(pb.entry_block, weights=w * z_base_ho ** 2, minlength=pb.n_blocks)[keep]
    sc = np.bincount(pb.entry_block, weights=w * z_cand_ho ** 2, minlength=pb.n_blocks)[keep]
    used = nb > 0
    d = np.sqrt(sb[used] / nb[used]) - np.sqrt(sc[used] / nb[used])
    k = int(d.size)
    if k < 2:
        return 1.0, float(d.mean()) if k else 0.0, math.inf, k
    mean, se = float(d.mean()), float(d.std(ddof=1) / math.sqrt(k))
    if not se > 0:
        return (0.0 if mean < 0 else 1.0), mean, 0.0, k
    return float(special.stdtr(k - 1, mean / se)), mean, se, k
