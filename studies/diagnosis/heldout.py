"""Phase 4 of the diagnosis: held-out gain. Each contiguous block is predicted from parameters
refitted on the other blocks; a paired block bootstrap of the RMSE difference must exclude zero;
a candidate passes when its likelihood ratio, BIC and held-out gain all say so (module docstring
of `studies.diagnosis.engine`, step 4).

History effects (a profiled parameter such as a settling threshold) are refitted in full on the
kept blocks: the profiled value is re-selected over its whole grid (linearised about the full-data
fit), then every other parameter and the nuisance are refitted by nonlinear least squares on the
kept rows. A block the kept blocks cannot test is left out of the held-out gain and reported
(`heldout_untestable`): when a parameter does not move the kept rows' predictions (the trigger
never occurs there), or when another value of the profiled parameter predicts the kept rows
identically but the held-out block differently (the trigger falls inside the held-out block, so
where it falls cannot be learnt from the others). Cross-validation can only test what the
training folds identify (Arlot & Celisse 2010, A survey of cross-validation procedures, sec. 8 on
dependent data and blocks)."""
from __future__ import annotations

import math

import numpy as np

from scipy import optimize

from studies.diagnosis.core import Baseline, Fit, ModelFailure, Screening
from studies.diagnosis.stats import blsq

#: relative size below which two predictions (or sensitivities) count as equal: round-off of a
#: row-wise model evaluation, far below any noise level
SAME_RTOL = 1e-8


#: fewest testable held-out blocks for a held-out gain (a bootstrap over fewer is meaningless)
MIN_TESTABLE_BLOCKS = 3


class HeldoutPhase:
    def validate(self, s: Screening, fits: dict[str, Fit], b: Baseline):
        """Held-out residuals per candidate and the names of the candidates that pass."""
        th = self.th
        base_ho, cands, names_id = b.heldout_z, s.candidates, s.identifiable
        ho = {}
        for name in list(names_id):
            e = self.effect(name)
            untestable = {}
            try:
                if e.profile:
                    ho[name], chosen, untestable = self.heldout_profile(fits[name], e, base_ho)
                    cands[name].heldout_profile_values = chosen
                    cands[name].heldout_untestable = [
                        {"block": int(bk) + 1, "rows": self._block_rows(bk), "reason": why}
                        for bk, why in sorted(untestable.items())]
                else:
                    ho[name] = self.heldout_linear(fits[name])
            except ModelFailure as exc:
                # no honest held-out number: the candidate cannot pass
                cands[name].heldout_failed = str(exc)
                ho[name] = base_ho.copy()
            cands[name].heldout_rmse = self.col_rmse(ho[name])
            keep = np.ones(self.n_blocks, bool)
            keep[list(untestable)] = False
            cands[name].heldout_gain = self.bootstrap_gain(base_ho, ho[name], keep)
        passing = []
        for name in names_id:
            c = cands[name]
            reasons = []
            if not c.lr_significant:
                reasons.append(f"likelihood ratio not significant (p = {c.p_lr:.2g}, Holm)")
            if not c.delta_bic < -th["bic_margin"]:
                reasons.append(f"BIC not better than the baseline (delta {c.delta_bic:.1f})")
            if c.heldout_gain["n_blocks"] < MIN_TESTABLE_BLOCKS:
                reasons.append(f"only {c.heldout_gain['n_blocks']} held-out blocks can test it "
                               f"(need {MIN_TESTABLE_BLOCKS})")
            elif not c.heldout_gain["excludes_zero"]:
                reasons.append("no held-out gain beyond noise (bootstrap interval "
                               f"[{c.heldout_gain['ci'][0]:.3g}, "
                               f"{c.heldout_gain['ci'][1]:.3g}] includes 0)")
            c.status = "passed" if not reasons else "rejected"
            c.reason = "; ".join(reasons) if reasons else "beats the baseline in sample and " \
                                                             "on held-out blocks"
            if not reasons:
                passing.append(name)

        return ho, passing

    def heldout_linear(self, fit: Fit) -> np.ndarray:
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
                du = blsq(J, -z, lo, hi)
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


    def heldout_profile(self, fit: Fit, e, base_ho: np.ndarray
                        ) -> tuple[np.ndarray, list, dict[int, str]]:
        """Held-out residuals for a candidate with a profiled parameter (a threshold), all its
        parameters refitted on the kept blocks (module docstring):

        1. every grid value evaluated by the in-sample profile is linearised about the full-data
           fit (its other parameters and nuisance; one model call per parameter and value);
        2. per held-out block, the value with the least linearised chi-square on the kept rows is
           chosen (a global profile over the bounded grid), then the other parameters and the
           nuisance are refitted by bounded nonlinear least squares on the kept rows from that
           linear solution, and the held-out block is predicted by a real model call;
        3. a block is untestable when a parameter does not move the kept rows' predictions, or
           when another value predicts (and moves) the kept rows exactly as the chosen one but not
           the held-out block. Its entries keep the baseline's held-out residual (no gain claimed)
           and the bootstrap leaves it out.

        Returns the stacked held-out residuals, the chosen value per testable block and
        {block: reason} for the untestable ones."""
        (pp,) = e.profile
        sp0 = fit.space
        k = sp0.k
        u = fit.u
        lins = []
        for g in fit.extra["grid_lin"]:
            space = g["space"]                    # same coordinates for every value of pp
            try:
                z0, _ = self.eval(space, u)
                cols = []
                for i in range(k):
                    h = 1.0 if u[i] + 1.0 <= space.hi[i] else -1.0
                    du = np.zeros_like(u)
                    du[i] = h
                    cols.append((self.eval(space, u + du)[0] - z0) / h)
            except ModelFailure:
                continue
            lins.append({"value": g["value"], "space": space, "z": z0,
                         "Je": np.column_stack(cols) if cols else np.zeros((self.N, 0))})
        if not lins:
            raise ModelFailure(f"the model fails at every {pp} about the fit")
        Jn = fit.J[:, k:]
        lo, hi = sp0.lo - u, sp0.hi - u
        z_ho = base_ho.copy()
        chosen, untestable = [], {}
        for b in range(self.n_blocks):
            te = self.entry_block == b
            tr = ~te
            if not te.any():
                continue
            best = None
            for L in lins:
                J = np.column_stack([L["Je"][tr], Jn[tr]])
                x = blsq(J, -L["z"][tr], lo, hi)
                sse = float(np.sum((L["z"][tr] + J @ x) ** 2))
                if best is None or sse < best[0]:
                    best = (sse, L, x)
            _, L, x = best
            why = self._untestable(L, lins, tr, te, e, pp)
            if why:
                untestable[b] = why
                continue
            uu = self._refit_rows(L["space"], u + x, tr)
            zz, _ = self.eval(L["space"], uu)        # ModelFailure -> candidate fails
            z_ho[te] = zz[te]
            chosen.append(L["value"])
        return z_ho, chosen, untestable

    def _untestable(self, L: dict, lins: list[dict], tr, te, e, pp: str) -> str | None:
        """Why the kept rows (`tr`) cannot test the held-out block (`te`) at the chosen value
        (linearisation `L`), or None."""
        ref = max(float(np.max(np.abs(L["z"]))), 1.0)
        for i, (_, p) in enumerate(L["space"].eff_params):
            col = L["Je"][:, i]
            full = float(np.max(np.abs(col)))
            if full > 0 and float(np.max(np.abs(col[tr]))) <= SAME_RTOL * full:
                return (f"{p} does not change the predictions of the other blocks (at {pp} = "
                        f"{L['value']:g} the effect acts only in this block)")
        for M in lins:
            if M is L:
                continue
            same_tr = (np.max(np.abs(M["z"][tr] - L["z"][tr]), initial=0.0) <= SAME_RTOL * ref
                       and np.allclose(M["Je"][tr], L["Je"][tr], rtol=SAME_RTOL,
                                       atol=SAME_RTOL * ref))
            if not same_tr:
                continue
            if (np.max(np.abs(M["z"][te] - L["z"][te]), initial=0.0) > SAME_RTOL * ref
                    or not np.allclose(M["Je"][te], L["Je"][te], rtol=SAME_RTOL,
                                       atol=SAME_RTOL * ref)):
                a, c = sorted((L["value"], M["value"]))
                return (f"{pp} = {a:g} and {c:g} predict the other blocks identically but this "
                        "block differently: the trigger falls inside this block, and where "
                        "cannot be learnt from the others")
        return None

    def _refit_rows(self, space, u0, rows) -> np.ndarray:
        """Bounded nonlinear least squares (as `fit`) on the stacked entries `rows` only."""
        lo, hi = space.lo, space.hi
        span = np.maximum(hi - lo, 1)
        u0 = np.clip(space.clip(np.asarray(u0, float)), lo + 1e-10 * span, hi - 1e-10 * span)
        big = np.full(int(np.sum(rows)), 1e6)

        def fun(uu):
            try:
                return self.eval(space, uu)[0][rows]
            except ModelFailure:
                return big

        res = optimize.least_squares(fun, u0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                                     x_scale=1.0, ftol=1e-8, xtol=1e-8, gtol=1e-8,
                                     max_nfev=20 * (u0.size + 1))
        return res.x

    def _block_rows(self, b: int) -> list[int]:
        """First and last row (1-based, as in the file) of held-out block b."""
        rows = np.flatnonzero(self.blocks == b)
        return [int(rows[0]) + 1, int(rows[-1]) + 1]

    def bootstrap_gain(self, z_base_ho, z_cand_ho, keep=None) -> dict:
        """Paired block bootstrap of RMSE(baseline) - RMSE(candidate), standardised, held-out,
        over the blocks `keep` (boolean per block; default all)."""
        B = int(self.th["n_boot"])
        keep = np.ones(self.n_blocks, bool) if keep is None else np.asarray(keep, bool)
        sb = np.bincount(self.entry_block, weights=z_base_ho ** 2, minlength=self.n_blocks)[keep]
        sc = np.bincount(self.entry_block, weights=z_cand_ho ** 2, minlength=self.n_blocks)[keep]
        nb = np.bincount(self.entry_block, minlength=self.n_blocks).astype(float)[keep]
        m = int(keep.sum())
        if m == 0:
            return {"rmse_gain": 0.0, "ci": [0.0, 0.0], "blocks_improved": 0, "n_blocks": 0,
                    "excludes_zero": False}
        idx = self.rng.integers(0, m, size=(B, m))
        cnt = np.zeros((B, m))
        np.add.at(cnt, (np.repeat(np.arange(B), m), idx.ravel()), 1.0)
        nn = cnt @ nb
        d = np.sqrt(cnt @ sb / nn) - np.sqrt(cnt @ sc / nn)
        q = float(self.th["heldout_quantile"])
        point = math.sqrt(sb.sum() / nb.sum()) - math.sqrt(sc.sum() / nb.sum())
        lo, hi = np.quantile(d, [q, 1 - q])
        return {"rmse_gain": float(point), "ci": [float(lo), float(hi)],
                "blocks_improved": int(np.sum(sb > sc)), "n_blocks": m,
                "excludes_zero": bool(lo > 0)}

