"""Phase 3 of the diagnosis: fit every identifiable candidate (bounded least squares with the
nuisance refitted; profiled parameters over their distinct values), its likelihood ratio against
the baseline with the chi-bar-square null, Holm over the candidates, BIC (module docstring of
`studies.diagnosis.engine`, step 3)."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.candidate import Candidate
from studies.diagnosis.core import Baseline, Fit, Linearisation, ModelFailure, Screening
from studies.diagnosis.interval import parameter_covariance
from studies.diagnosis.problem import Problem, cpu_timed, longest_first
from studies.diagnosis.stats import blsq, chibar_pvalue


def fit_all(pb: Problem, s: Screening, b: Baseline,
            done: tuple[dict[str, Fit], dict[str, Candidate]] | None = None, later: int = 0
            ) -> tuple[dict[str, Fit], dict[str, Candidate]]:
    """Fit the identifiable candidates: their fits (those whose fit fails are left out) and
    every candidate, the fitted ones with their fit's numbers (new records). `done`: the fits
    and records of an earlier `fit_all` on the same calibrated problem (a staged pass,
    `studies.diagnosis.staging`): its candidates are taken as they are, the others fitted,
    and Holm's correction is made over all of them. `later`: candidates held for a later stage
    of the pass, counted in Holm's number of tests (a union bound over the stages)."""
    th = pb.th
    base, cands = b.fit, dict(s.candidates)
    lnN = math.log(pb.N)
    fits: dict[str, Fit] = {}
    prior_fits, prior = done or ({}, {})
    reused = [n for n in s.identifiable if n in prior_fits
              or (n in prior and prior[n].status == "model_failed")]
    for n in reused:
        cands[n] = prior[n]
        if n in prior_fits:
            fits[n] = prior_fits[n]

    def fit_one(name):
        """(fit or None, profile summary, failure message or None, model calls)."""
        e, info = pb.effect(name), cands[name]
        calls0 = pb.model.calls
        try:
            if fitspec.profile(e):
                f = fit_profiled(pb, e, info.profile_grid, base)
                profile = profile_summary(f, e, info.profile_grid)
            else:
                pre = searched.get(name)
                calls0 -= 0 if pre is None else pre.calls   # the search's calls count here
                f = fit_candidate(pb, e, info, base, None if pre is None else pre.scored)
                profile = None
        except ModelFailure as exc:
            return None, None, str(exc), pb.model.calls - calls0
        return f, profile, None, pb.model.calls - calls0

    # the candidates' fits are independent: on the engine's workers, the longest first; a
    # global search's starting points scored on the workers before (`searched_starts`)
    names = [n for n in s.identifiable if n not in reused]
    searched = searched_starts(pb, s, b, names)
    done = pb.parallel(cpu_timed(fit_one), names,
                       first=longest_first([fit_cost(pb, pb.effect(n), cands[n], s,
                                                     n in searched) for n in names]))
    seconds = {n: t + (searched[n].cpu_s if n in searched else 0.0)
               for n, (_, t) in zip(names, done)}
    for name, ((f, profile, failed, calls), _) in zip(names, done):
        e = pb.effect(name)
        info = cands[name]
        if failed is not None:
            cands[name] = info.with_status("model_failed", f"fit failed: {failed}")
            continue
        fits[name] = f
        lr = max(base.chi2 - f.chi2, 0.0)
        r = info.rank
        n_two = sum(1 for p in pb.free_params(e) if e.sign(p) == 0)
        n_free = min(r, n_two) + len(fitspec.profile(e))
        n_bound = r - min(r, n_two)
        k_eff = r + len(fitspec.profile(e))
        eff_vals, nuis_vals = f.space.unpack(f.u)
        held = list(fitspec.held_fixed(e, pb.conditions))
        cands[name] = replace(
            info, profile=profile, predict_calls_fit=calls, lr=lr,
            df={"free": n_free, "on_bound": n_bound}, p_lr=chibar_pvalue(lr, n_free, n_bound),
            delta_bic=-lr + k_eff * lnN, k=k_eff,
            parameters={p: eff_vals[name][p] for p in e.parameters},
            held_at_off={p: e.off[p] for p in held} if held else None,
            nuisance=nuis_vals, uncertainty=uncertainty(pb, f, e), rmse=pb.col_rmse(f.z),
            fit_cpu_s=seconds[name])
    fits = {n: fits[n] for n in s.identifiable if n in fits}      # in the candidates' order
    # Holm over the identifiable candidates
    order = sorted(fits, key=lambda n: cands[n].p_lr)
    m = len(order) + later
    still = True
    for j, name in enumerate(order):
        ok = still and cands[name].p_lr <= th["alpha_lr"] / (m - j)
        still = ok
        cands[name] = replace(cands[name], lr_significant=bool(ok))
    return fits, cands

#: model calls of a local fit per fitted coordinate, the estimate `fit_cost` takes (about 10
#: iterations of a finite-difference Jacobian)
CALLS_PER_COORDINATE = 10


def fit_cost(pb: Problem, e, info: Candidate, s: Screening, scored: bool = False
             ) -> float | None:
    """Estimated CPU seconds of a candidate's fit (the order the fits are handed to the
    workers; None when its screening was not timed): its seconds per model call in the
    screening times the calls its fit makes: a start's score each (`fitspec.starts`; none when
    they were `scored` before the fits), a profiled grid's linearisations (rank + 1 calls a
    value, a long grid searched in about COARSE + 4 values), and CALLS_PER_COORDINATE per
    coordinate of up to three local fits."""
    t = s.call_seconds.get(info.effect)
    if t is None:
        return None
    k = (info.rank or 1) + len(pb.nuisance.names)
    grid = [len(v) for v in (info.profile_grid or {}).values()]
    n_grid = sum(min(g, COARSE + 4) for g in grid) * ((info.rank or 1) + 1)
    n_starts = 0 if scored else 1 + len(fitspec.starts(e, pb.conditions, pb.T_ref_C))
    return t * (n_starts + n_grid + 3 * CALLS_PER_COORDINATE * k)


def _start_points(pb: Problem, e, info, base: Fit, space, points: list[dict] | None = None
                  ) -> list[np.ndarray]:
    """Starting points of a candidate's fit (scaled coordinates): the Gauss-Newton step from off
    (first), then `points` (default the fit specification's starts, `fitspec.starts`) with the
    baseline's nuisance."""
    k = space.k
    Jc = -info.sensitivity            # d z / d u_effect at off (sensitivity is -dz)
    A = np.column_stack([Jc, base.J])
    d, *_ = np.linalg.lstsq(A, -base.z, rcond=None)
    starts = [np.concatenate([d[:k], base.u + d[k:]])]
    for s in (fitspec.starts(e, pb.conditions, pb.T_ref_C) if points is None else points):
        vals = [s.get(p, e.off[p]) for (_, p) in space.eff_params]
        starts.append(np.concatenate([(np.array(vals) - space.origin[:k]) / space.scale[:k],
                                      base.u]))
    return starts


def _search(pb: Problem, e, info, base: Fit, space, score) -> list[tuple]:
    """The ranked starts of a candidate's fit (`_ranked`): the Gauss-Newton step and the fit
    specification's starts, scored by `score` (a list of starts, clipped to the bounds -> their
    `_start_score`s in order; a start repeated is asked for once); for a search in two rounds
    (`fitspec.refine`), then the further starts the first round's scores call for, the whole
    list ranked in the order the specification gives it (the Gauss-Newton step first)."""
    pts = fitspec.starts(e, pb.conditions, pb.T_ref_C)
    known: dict[bytes, tuple | None] = {}

    def scored(points):
        us = [space.clip(u) for u in _start_points(pb, e, info, base, space, points)]
        keys = [u.tobytes() for u in us]
        new = {k: u for k, u in zip(keys, us) if k not in known}
        known.update(zip(new, score(list(new.values()))))
        return [known[k] for k in keys]

    got = scored(pts)
    more = fitspec.refine(e, [(p, None if g is None else g[0]) for p, g in zip(pts, got[1:])],
                          base.chi2)
    return _ranked(got if more is None else scored(more))


def _start_score(pb: Problem, space, uu: np.ndarray, Jn: np.ndarray
                 ) -> tuple[float, np.ndarray] | None:
    """(chi-square with the nuisance corrected linearly, the corrected start) of one start
    (clipped to the bounds; one model call), None when the model fails there."""
    k, nq = space.k, len(pb.nuisance.names)
    uu = space.clip(uu)
    try:
        z, _ = pb.eval(space, uu)
    except ModelFailure:
        return None
    if nq:
        dn, *_ = np.linalg.lstsq(Jn, -z, rcond=None)
        uu = space.clip(np.concatenate([uu[:k], uu[k:] + dn]))
        zc = z + Jn @ dn
    else:
        zc = z
    return float(zc @ zc), uu


def _ranked(scores: list[tuple[float, np.ndarray] | None]) -> list[tuple]:
    """(chi-square, index, start) of the starts the model evaluated (`_start_score`), indexed
    in their order among those, best first; ModelFailure when it evaluated none."""
    scored = [(sse, i, uu) for i, (sse, uu) in enumerate(t for t in scores if t is not None)]
    if not scored:
        raise ModelFailure("the model fails at every starting point")
    scored.sort(key=lambda t: t[:2])
    return scored


def _score_starts(pb: Problem, space, starts: list[np.ndarray], Jn: np.ndarray) -> list[tuple]:
    """(chi-square with the nuisance corrected linearly, index, start) of every start the model
    evaluates, best first."""
    return _ranked([_start_score(pb, space, uu, Jn) for uu in starts])


def _scored_here(pb: Problem, space, Jn: np.ndarray):
    """A `_search` scorer in this process: each start's `_start_score` in turn."""
    return lambda starts: [_start_score(pb, space, uu, Jn) for uu in starts]


#: a candidate with at least this many starting points (a global search: `interference_error`'s
#: ~40 in its first round and ~25 in its second over its band, `fitspec.interference_starts`)
#: has them scored on the workers before the fits (`searched_starts`), SCORE_CHUNK starts a
#: task: alone in one fit task its search was the longest task of the fits (4-6 CPU s of 8-12
#: on seed 000's cycles, 2026-11-29, when it scored ~100 starts in one round)
GLOBAL_SEARCH_STARTS = 20
SCORE_CHUNK = 8


def searched_starts(pb: Problem, s: Screening, b: Baseline, names: list[str]
                    ) -> dict[str, "Searched"]:
    """The ranked starts (`_search`, best first; or the ModelFailure of a model that fails at
    every start) of the candidates among `names` whose fit is a global search (at least
    GLOBAL_SEARCH_STARTS starting points, no profiled parameter), each round of each search
    scored in one map on the engine's workers, SCORE_CHUNK starts a task: the same scores, in
    the same order, as in their fit task (`_scored_here`)."""
    out: dict[str, Searched] = {}
    for n in names:
        e = pb.effect(n)
        if fitspec.profile(e) or 1 + len(fitspec.starts(e, pb.conditions,
                                                        pb.T_ref_C)) < GLOBAL_SEARCH_STARTS:
            continue
        space = pb.space([e])
        cost = [0, 0.0]

        def score(starts, space=space, cost=cost):
            def chunk(i0):
                calls0 = pb.model.calls
                got = [_start_score(pb, space, uu, b.fit.J) for uu in starts[i0:i0 + SCORE_CHUNK]]
                return got, pb.model.calls - calls0

            got = []
            for (part, calls), t in pb.parallel(cpu_timed(chunk),
                                                list(range(0, len(starts), SCORE_CHUNK))):
                got += part
                cost[0] += calls
                cost[1] += t
            return got

        try:
            ranked = _search(pb, e, s.candidates[n], b.fit, space, score)
        except ModelFailure as exc:
            ranked = exc
        out[n] = Searched(ranked, *cost)
    return out


@dataclass(frozen=True)
class Searched:
    """A global search's scored starts (best first) or the ModelFailure of a model failing at
    every start, and the model calls and CPU seconds it took (counted with its fit's)."""
    scored: list[tuple] | ModelFailure
    calls: int
    cpu_s: float


def fit_candidate(pb: Problem, e, info, base: Fit,
                  scored: list[tuple] | ModelFailure | None = None) -> Fit:
    """A candidate without a profiled parameter: bounded least squares from the two most
    promising starts (`_search`; `scored`: already scored, `searched_starts`) and from
    the Gauss-Newton step; never worse than the baseline."""
    space = pb.space([e])
    if isinstance(scored, ModelFailure):
        raise scored
    if scored is None:
        scored = _search(pb, e, info, base, space, _scored_here(pb, space, base.J))
    # local optimisation from the two most promising starts (fits that open or close, lags
    # and thresholds make the problem non-convex)
    # the Gauss-Newton step from "off" (index 0) is refined too when the fits so far ended flat
    # in an effect parameter (`_flat`: a grid start can sit where a fit is open and the
    # outputs do not depend on a parameter, a flat local minimum), else when it is promising
    # where the form jumps at off (`jumps_at_off`, asked once a start scores worse than off), a
    # start worse than off is not refined: its local fit descends to the jump's edge, not below
    # off (the `thermal_transient_fe` rung's fits from such starts: 90-590 calls, set by
    # round-off, each ending worse than off)
    gn = [t for t in scored if t[1] == 0 and t not in scored[:2]]
    f, jump = None, None
    for sse0, idx, uu in scored[:2] + gn:
        if (f is not None and not (idx == 0 and _flat(f))
                and sse0 > f.chi2 + max(10.0, 0.2 * (base.chi2 - f.chi2))):
            continue                  # not promising enough
        if sse0 > base.chi2:
            jump = jumps_at_off(pb, space, base) if jump is None else jump
            if jump:
                continue
        try:
            fi = pb.fit(space, uu)
        except ModelFailure:
            continue
        if f is None or fi.chi2 < f.chi2:
            f = fi
    if f is None and not jump:
        raise ModelFailure("the fits fail from every starting point")
    if f is None or f.chi2 > base.chi2:     # never worse than the baseline (off is admissible)
        f2 = fit_from_off(pb, space, info, base, jump)
        f = f2 if f is None or f2.chi2 < f.chi2 else f
    return restart_even(pb, e, f)


#: a fit from off whose start (`Problem.start`: 1e-10 of each span inside the bounds) is worse
#: than off itself by more than this (chi-square units) starts beyond a jump of the form at off
#: (`fit_from_off`); a form continuous at off moves the chi-square there by ~1e-10 of its slope
OFF_JUMP_CHI2 = 1.0


def jumps_at_off(pb: Problem, space, base: Fit) -> bool:
    """Whether the form jumps at off: the start of a fit from off (the effect at off, the
    baseline's nuisance; `Problem.start`, 1e-10 of each span inside the bounds) worse than the
    baseline by more than OFF_JUMP_CHI2 (one model call)."""
    u_off = space.clip(np.concatenate([np.zeros(space.k), base.u]))
    z0, _ = pb.eval(space, pb.start(space, u_off))
    return float(z0 @ z0) > base.chi2 + OFF_JUMP_CHI2


def fit_from_off(pb: Problem, space, info, base: Fit, jump: bool | None = None) -> Fit:
    """The fit from off (the effect at off, the baseline's nuisance): the bounded least-squares
    fit from there, or, where the form jumps at off (its start, `Problem.start`, is worse than
    off by more than OFF_JUMP_CHI2), off itself with the one-sided sensitivity at off beside
    the baseline's Jacobian (`screening.sensitivity`, as `_start_points` takes it). Why: the
    `thermal_transient_fe` rung is the configured model at film resistance 0 (every part at
    the ambient) but at any finite film its stack's interior still lags the faces by
    conduction (0.3 K on seed 000's cycles at 1e-10 m^2 K/W); a local fit from 1e-10 of the
    span descends to the jump's edge, never to off, in a number of calls set by round-off (54
    to 877 on one dataset) and ends worse than off. `jump`: `jumps_at_off` when known."""
    u_off = space.clip(np.concatenate([np.zeros(space.k), base.u]))
    if not (jumps_at_off(pb, space, base) if jump is None else jump):
        return pb.fit(space, u_off)
    z, pred = pb.eval(space, u_off)
    J = np.column_stack([-np.asarray(info.sensitivity, float), base.J])
    return Fit(space, u_off, z, J, float(z @ z), pred)


#: restart values of a parameter whose response is even about off (`fitspec.even`), as
#: fractions of the distance from off to its bound (the bound on the side of the larger one),
#: log-spaced as `ladder.unlogged_load_starts`' starts
EVEN_RESTARTS = (1e-3, 1e-2, 1e-1)
#: a fitted parameter within this many scaled units of off (`fitspec.steps`) is at off
AT_OFF_U = 1e-3


def restart_even(pb: Problem, e, f: Fit) -> Fit:
    """Fit `f`, or a better one restarted off a stationary point of symmetry: for each effect
    parameter whose response is even about off (`fitspec.even`) and that ended at off
    (within AT_OFF_U scaled units), the fit's point with that parameter moved to each of
    EVEN_RESTARTS (scored with the nuisance corrected linearly, one model call each) and one
    bounded least-squares fit from the best of them, kept where its chi-square is lower.

    Why: where the response is even in p about off, d chi2 / d p = 0 at off whatever the data
    (the chi-square is a function of (p - off)^2 there), so a gradient fit that reaches off
    stops there as at a minimum even where the chi-square falls away from it (a maximum in p:
    a true nonzero value). Moving off it is the only way out for a local method."""
    even = [i for i, (_, p) in enumerate(f.space.eff_params)
            if p in fitspec.even(e) and abs(f.u[i]) < AT_OFF_U]
    if not even:
        return f
    space = f.space
    k = space.k
    Jn = f.J[:, k:]
    best = f
    for i in even:
        side = space.hi[i] if abs(space.hi[i]) >= abs(space.lo[i]) else space.lo[i]
        starts = []
        for x in EVEN_RESTARTS:
            uu = best.u.copy()
            uu[i] = x * side
            starts.append(uu)
        try:
            _, _, uu = _score_starts(pb, space, starts, Jn)[0]
            fi = pb.fit(space, uu)
        except ModelFailure:
            continue
        if fi.chi2 < best.chi2:
            best = fi
    return best


#: an effect parameter's column of a fit's Jacobian (standardised residuals per scaled unit)
#: whose norm is below this: the chi-square moves by less than FLAT_COLUMN^2 over a whole
#: scaled unit (one `fitspec.steps` step), so the outputs do not depend on the parameter there
FLAT_COLUMN = 1e-3


def _flat(f: Fit) -> bool:
    """Whether fit `f` ended where the outputs do not depend on one of its effect parameters
    (a Jacobian column below FLAT_COLUMN: a fit left open, a lag far shorter than a row)."""
    k = len(f.space.eff_params)
    return bool(k and np.linalg.norm(f.J[:, :k], axis=0).min() < FLAT_COLUMN)


def _linearised(pb: Problem, e, pp: str, value: float, base: Fit) -> Linearisation | None:
    """The candidate at profiled value `value`, linearised about the baseline (one model call
    per parameter), and its bounded linear fit; None when the model fails."""
    space = pb.space([e], fixed={e.name: {pp: value}})
    k = space.k
    nq = len(pb.nuisance.names)
    cols = []
    try:
        for i in range(k):
            du = np.zeros(k + nq)
            du[i] = 1.0 if space.hi[i] >= 1.0 else -1.0
            z, _ = pb.eval(space, np.concatenate([du[:k], base.u]))
            cols.append((z - base.z) / du[i])
    except ModelFailure:
        return None
    J = np.column_stack(cols + [base.J])
    u0 = np.concatenate([np.zeros(k), base.u])
    lo, hi = space.lo - u0, space.hi - u0
    x = blsq(J, -base.z, lo, hi)
    sse = float(np.sum((base.z + J @ x) ** 2))
    return Linearisation(value, space, J, base.z, u0, lo, hi, sse, x)


#: grids longer than this are searched coarse first (COARSE points), then bisected
LONG_GRID = 16
COARSE = 12


def _bisected(values: list, lin) -> list[Linearisation]:
    """A long grid's linearisations: COARSE points, then bisect towards the best onset on both
    sides until neighbours are evaluated."""
    lins = {int(i): lin(values[i])
            for i in np.unique(np.linspace(0, len(values) - 1, COARSE).round().astype(int))}
    new = _bisection(lins)
    while new:
        for m in new:
            lins[m] = lin(values[m])
        new = _bisection(lins)
    return [lins[i] for i in sorted(lins) if lins[i] is not None]


def _bisection(lins: dict[int, Linearisation | None]) -> list[int]:
    """Grid indices halfway from the best evaluated one to its evaluated neighbours, not yet
    evaluated (none when every neighbour is adjacent or nothing evaluates)."""
    ok = sorted(i for i in lins if lins[i] is not None)
    if not ok:
        return []
    ib = min(ok, key=lambda i: lins[i].sse)
    left = max([i for i in lins if i < ib], default=None)
    right = min([i for i in lins if i > ib], default=None)
    mids = []
    if left is not None:
        mids.append((left + ib) // 2)
    if right is not None:
        mids.append((ib + right + 1) // 2)
    return [m for m in mids if m not in lins]


def fit_profiled(pb: Problem, e, profile_grid: dict, base: Fit) -> Fit:
    """Profile the `profile` parameter (one) over its grid (`profile_grid`: {parameter:
    values}) with a linearised inner fit, then refine the best value with a full bounded
    least-squares fit."""
    (pp,) = fitspec.profile(e)
    values = list(profile_grid[pp])

    def lin(value):
        return _linearised(pb, e, pp, value, base)

    grid_lin = (_bisected(values, lin) if len(values) > LONG_GRID
                else [g for g in map(lin, values) if g is not None])
    if not grid_lin:
        raise ModelFailure(f"the model fails for every {pp} on the grid")
    ranked = sorted(grid_lin, key=lambda g: g.sse)
    ranked = [g for g in ranked[:2] if g.sse <= ranked[0].sse + 1.0]
    best = None
    for g in ranked:
        try:
            f = pb.fit(g.space, g.u0 + g.du)
        except ModelFailure:
            continue
        if best is None or f.chi2 < best.chi2:
            best = replace(f, profile_value=g.value)
    if best is None:
        raise ModelFailure(f"the fits at the best values of {pp} fail")
    # profile interval: values whose linearised chi-square is within 1 of the best
    sse_min = min(g.sse for g in grid_lin)
    near = [g.value for g in grid_lin if g.sse <= sse_min + 1.0]
    return replace(best, grid=grid_lin, interval=[min(near), max(near)])


def profile_summary(f: Fit, e, profile_grid: dict) -> dict:
    """The profiled parameter's grid size, values evaluated and chi-square-1 interval."""
    (pp,) = fitspec.profile(e)
    return {pp: {"grid_size": len(profile_grid[pp]), "evaluated": len(f.grid),
                 "interval_chi2_1": list(f.interval)}}


def uncertainty(pb: Problem, f: Fit, e) -> dict:
    """Standard uncertainty of the fitted effect parameters (linearised, scaled by the
    reduced chi-square when above 1: `interval.parameter_covariance`); None when not
    separately identifiable."""
    cov, ok = parameter_covariance(f.J, f.chi2)
    out = {}
    for i, (en, p) in enumerate(f.space.eff_params):
        out[p] = float(math.sqrt(cov[i, i]) * f.space.scale[i]) if ok[i] else None
    if f.interval is not None:
        for p in fitspec.profile(e):
            out[p] = {"interval": f.interval}
    return out
