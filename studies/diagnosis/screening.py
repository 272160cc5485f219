"""Phase 2 of the diagnosis: which candidates the data can see. For every candidate the
finite-difference sensitivity at its off value, the part the baseline calibration cannot produce,
its reach inside the physical bounds in noise units, and the look-alike cosines between
candidates (module docstring of `studies.diagnosis.engine`, step 2). A model form of the ladder
(`studies.diagnosis.ladder`) is screened only where the baseline residual points at a condition
it acts through (`ladder.indication`), else it is not applicable with the reason."""
from __future__ import annotations

from typing import Mapping

import numpy as np

from studies.diagnosis import fitspec, ladder
from studies.diagnosis.candidate import Candidate
from studies.diagnosis.core import Baseline, ModelFailure, Screening
from studies.diagnosis.problem import Problem, cpu_timed
from studies.diagnosis.stats import max_cosine, orth


def screen(pb: Problem, b: Baseline, held: Mapping[str, str] | None = None,
           done: Screening | None = None) -> Screening:
    """Every candidate with its identifiability (module docstring); the identifiable ones in
    the candidates' order with their projected sensitivities' look-alike cosines. `held`:
    {name: reason} of candidates held for a later stage of the pass
    (`studies.diagnosis.staging`): not applicable with that reason when the indication would
    screen them (an earlier reason stands). `done`: an earlier screening of the same
    calibrated problem whose records (all but the ones it held) are taken as they are."""
    held = dict(held or {})
    reuse = ({n: (c, done.bases.get(n)) for n, c in done.candidates.items()
              if n not in done.held} if done is not None else {})
    cands = {}
    proj = {}
    gate = ladder.indication(pb, b) if any(map(ladder.is_form, pb.candidates)) else None
    # the candidates' sensitivities are independent model calls: on the engine's workers
    # (`Problem.parallel`, the results those of a serial run), those that call the model only;
    # a profiled one (up to three grid points) first
    todo = [e for e in pb.candidates
            if e.name not in reuse and e.name not in held and _needs_model(pb, e, gate)]

    def one(e):
        """(candidate, basis), CPU seconds per model call of its sensitivities."""
        calls0 = pb.model.calls
        (out, seconds) = cpu_timed(lambda x: _screen_one(pb, x, b, gate))(e)
        return out, seconds / max(pb.model.calls - calls0, 1)

    got = pb.parallel(one, todo, first=[i for i, e in enumerate(todo) if fitspec.profile(e)])
    done_now = {e.name: r for e, (r, _) in zip(todo, got)}
    call_seconds = {**(done.call_seconds if done is not None else {}),
                    **{e.name: t for e, (_, t) in zip(todo, got)}}
    kept = []
    for e in pb.candidates:
        if e.name in reuse:
            cands[e.name], Q = reuse[e.name]
        elif e.name in done_now:
            cands[e.name], Q = done_now[e.name]
        else:
            cands[e.name], Q = _screen_one(pb, e, b, gate, held.get(e.name))
            if e.name in held and cands[e.name].reason == held[e.name]:
                kept.append(e.name)
        if Q is not None:
            proj[e.name] = Q
    names_id = list(proj)
    look = {a: {c: max_cosine(proj[a], proj[c]) for c in names_id} for a in names_id}
    return Screening(cands, names_id, look, call_seconds, proj, tuple(kept))


def _screen_one(pb: Problem, e, b: Baseline, gate=None, held: str | None = None
                ) -> tuple[Candidate, np.ndarray | None]:
    """The candidate of effect `e` after screening and, when identifiable, the orthonormal basis
    of its projected sensitivity (else None); `gate`: the model-form ladder's indication
    (`ladder.indication`), a model form only where the residual points; `held`: the reason
    it is not applicable when nothing before stops it (a later stage of the pass)."""
    kind = getattr(e, "kind", "effect")
    why, grid = _applicability(pb, e)
    if why is None and gate is not None:
        why = gate.why_not(e)
    if why is None:
        why = held
    if why is not None:
        return Candidate(e.name, kind, status="not_applicable", reason=why), None
    best = _sensitivity_kept(pb, e, grid, b)
    if not isinstance(best, tuple):
        return Candidate(e.name, kind, status="model_failed",
                         reason=f"model failed with the effect on: {best}"), None
    fixed, Jc, names, Jp, frac, raw, left = best
    reach = _reach_sigma(pb, e, names, left)
    ident = {"remaining_fraction": dict(zip(names, frac)), "reach_sigma": float(reach)}
    why = _not_identifiable(pb, raw, frac, reach)
    if why is not None:
        return Candidate(e.name, kind, status="not_identifiable", reason=why,
                         identifiability=ident), None
    Q = orth(Jp, 1e-6)
    return Candidate(e.name, kind, identifiability=ident, rank=int(Q.shape[1]), sensitivity=Jc,
                     profile_fixed=fixed, profile_grid=grid), Q


def _needs_model(pb: Problem, e, gate) -> bool:
    """Whether screening `e` calls the model (it is applicable and, a model form, indicated)."""
    why, _ = _applicability(pb, e)
    return why is None and (gate is None or gate.why_not(e) is None)


def _applicability(pb: Problem, e) -> tuple[str | None, dict]:
    """Why the effect cannot be tried on these conditions (None: it can) and the grid of its
    profiled parameter."""
    why = e.applicable(pb.conditions)
    grid = {}
    if why is None and fitspec.profile(e):
        grid = fitspec.grid(e, pb.conditions, pb.T_ref_C)
        if any(len(v) == 0 for v in grid.values()):
            why = ("no value of " + ", ".join(fitspec.profile(e))
                   + " changes the prediction here")
    return why, grid


def _sensitivity_kept(pb: Problem, e, grid: dict, b: Baseline):
    """(profiled values, sensitivity, parameter names, its part the calibration cannot produce,
    remaining fraction, raw and remaining norms), or the model's failure. A profiled parameter:
    the sensitivity at the grid's median and quartiles, the one the calibration absorbs least
    kept (a run-in that ends within the first rows is a constant change of mu; the same run-in
    slower is not)."""
    Qn = b.nuisance_span
    best = None
    prof = fitspec.profile(e)
    for q in ((0.5, 0.25, 0.75) if prof else (0.5,)):
        fixed = {p: float(np.quantile(grid[p], q, method="nearest")) for p in prof}
        try:
            Jc, names = sensitivity(pb, e, b, fixed)
        except ModelFailure as exc:
            best = best or exc
            continue
        Jp = Jc - Qn @ (Qn.T @ Jc)
        raw = np.linalg.norm(Jc, axis=0)
        left = np.linalg.norm(Jp, axis=0)
        frac = np.where(raw > 0, left / np.where(raw > 0, raw, 1.0), 0.0)
        if not isinstance(best, tuple) or frac.max(initial=0.0) > best[4].max(initial=0.0):
            best = (fixed, Jc, names, Jp, frac, raw, left)
        if frac.max(initial=0.0) >= pb.th["min_remaining"]:
            break
    return best


def _reach_sigma(pb: Problem, e, names: list[str], left: np.ndarray) -> float:
    """Largest projected change reachable inside the bounds, in noise units (norm)."""
    reach = 0.0
    for i, p in enumerate(names):
        lo, hi = e.bounds[p]
        h = float(fitspec.steps(e, pb.conditions).get(p, e.scale[p]))
        reach = max(reach, left[i] * max(abs(hi - e.off[p]), abs(lo - e.off[p])) / h)
    return reach


def _not_identifiable(pb: Problem, raw: np.ndarray, frac: np.ndarray, reach: float
                      ) -> str | None:
    if not np.any(raw > 1e-9):
        return "the measured outputs do not depend on it here"
    if frac.max() < pb.th["min_remaining"]:
        return "the baseline calibration (" + ", ".join(pb.nuisance.names) + ") absorbs it"
    if reach < pb.th["min_reach_sigma"]:
        return "too small inside its physical bounds to be seen at this noise"
    return None


def sensitivity(pb: Problem, e, b: Baseline, fixed: dict | None = None):
    """d(pred)/sigma per unit step of each non-profile parameter at off (N x k, stacked), about
    the calibrated baseline (with the causes already accepted at their fitted values)."""
    base_eff, base_nuis = b.fit.space.unpack(b.fit.u)
    steps = fitspec.steps(e, pb.conditions)
    cols = []
    names = []
    for p in pb.free_params(e):
        params = dict(e.off)
        params.update(fixed or {})
        lo, hi = e.bounds[p]
        h = float(steps.get(p, e.scale[p]))
        if e.off[p] + h > hi:
            h = -h
        params[p] = e.off[p] + h
        pred = pb.model({**base_eff, e.name: params}, base_nuis)
        # d(pred)/sigma per unit scaled step in the +u direction
        cols.append(-(pb.zvec(pred) - pb.zvec(b.fit.pred)) * np.sign(h))
        names.append(p)
    return (np.column_stack(cols) if cols else np.zeros((pb.N, 0))), names
