"""Phase 2 of the diagnosis: which candidates the data can see. For every candidate the
finite-difference sensitivity at its off value, the part the baseline calibration cannot produce,
its reach inside the physical bounds in noise units, and the look-alike cosines between
candidates (module docstring of `studies.diagnosis.engine`, step 2)."""
from __future__ import annotations

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.candidate import Candidate
from studies.diagnosis.core import Baseline, ModelFailure, Screening
from studies.diagnosis.stats import max_cosine, orth


class ScreeningPhase:
    def screen(self, b: Baseline) -> Screening:
        th = self.th
        base, base_nuis, Qn = b.fit, b.nuisance, b.nuisance_span
        cands = {}
        proj = {}
        for e in self.candidates:
            info = Candidate(e.name)
            cands[e.name] = info
            why = e.applicable(self.conditions)
            grid = {}
            if why is None and fitspec.profile(e):
                grid = fitspec.grid(e, self.conditions, self.T_ref_C)
                if any(len(v) == 0 for v in grid.values()):
                    why = "no value of " + ", ".join(fitspec.profile(e)) + " changes the prediction here"
            if why is not None:
                info.set_status("not_applicable", why)
                continue
            # a profiled parameter: the sensitivity at the grid's quartiles and median, the one
            # the calibration absorbs least kept (a run-in that ends within the first rows is a
            # constant change of mu; the same run-in slower is not)
            best = None
            for q in ((0.5, 0.25, 0.75) if fitspec.profile(e) else (0.5,)):
                fixed = {p: float(np.quantile(grid[p], q, method="nearest")) for p in fitspec.profile(e)}
                try:
                    Jc, names = self.sensitivity(e, base_nuis, base.pred, fixed)
                except ModelFailure as exc:
                    best = best or exc
                    continue
                Jp = Jc - Qn @ (Qn.T @ Jc)
                raw = np.linalg.norm(Jc, axis=0)
                left = np.linalg.norm(Jp, axis=0)
                frac = np.where(raw > 0, left / np.where(raw > 0, raw, 1.0), 0.0)
                if not isinstance(best, tuple) or frac.max(initial=0.0) > best[4].max(initial=0.0):
                    best = (fixed, Jc, names, Jp, frac, raw, left)
                if frac.max(initial=0.0) >= th["min_remaining"]:
                    break
            if not isinstance(best, tuple):
                info.set_status("model_failed", f"model failed with the effect on: {best}")
                continue
            fixed, Jc, names, Jp, frac, raw, left = best
            reach = 0.0
            for i, p in enumerate(names):
                lo, hi = e.bounds[p]
                h = float(fitspec.steps(e, self.conditions).get(p, e.scale[p]))
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
            Q = orth(Jp, 1e-6)
            proj[e.name] = Q
            info.sensitivity = Jc
            info.profile_fixed = fixed
            info.profile_grid = grid
            info.rank = int(Q.shape[1])
        names_id = list(proj)
        look = {a: {c: max_cosine(proj[a], proj[c]) for c in names_id} for a in names_id}

        return Screening(cands, names_id, look)

    def free_params(self, e) -> list[str]:
        """Parameters fitted by gradients: not profiled, not held at "off" for these conditions
        (e.g. a speed-proportional part when every row has the same speed)."""
        held = set(fitspec.held_fixed(e, self.conditions))
        return [p for p in e.parameters if p not in fitspec.profile(e) and p not in held]


    def sensitivity(self, e, base_nuis: dict, base_pred: dict, fixed: dict | None = None):
        """d(pred)/sigma per unit step of each non-profile parameter at off (N x k, stacked)."""
        steps = fitspec.steps(e, self.conditions)
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

