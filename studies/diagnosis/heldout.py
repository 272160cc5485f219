"""Phase 4 of the diagnosis: held-out gain. Each contiguous block is predicted from parameters
refitted on the other blocks; a paired block bootstrap of the RMSE difference must exclude zero;
a candidate passes when its likelihood ratio, BIC and held-out gain all say so (module docstring
of `studies.diagnosis.engine`, step 4)."""
from __future__ import annotations

import math

import numpy as np

from studies.diagnosis.core import Baseline, Fit, ModelFailure, Screening
from studies.diagnosis.stats import blsq


class HeldoutPhase:
    def validate(self, s: Screening, fits: dict[str, Fit], b: Baseline):
        """Held-out residuals per candidate and the names of the candidates that pass."""
        th = self.th
        base_ho, cands, names_id = b.heldout_z, s.candidates, s.identifiable
        ho = {}
        for name in list(names_id):
            e = self.effect(name)
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
                x = blsq(g["J"][tr], -g["z"][tr], g["lo"], g["hi"])
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

