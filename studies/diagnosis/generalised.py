"""Phase 5b of the diagnosis: generalised forms of the listed effects.

When the verdict is `unexplained` because the listed form of a family leaves structure behind (or
does not pass), or `ambiguous` between look-alikes (then only the tied families: a form of one of
them may explain what neither listed form does alone; a CTE curvature truth was ambiguous between
the path compliance and the CTE slope), the generalised forms of the most promising families
(`studies.model.effects.generalised`) are fitted as NESTED models of their listed form. The
families are the significant listed candidates that have a form applicable to the conditions;
when there are more than MAX_FAMILIES of them, they are ranked by the BIC of their forms' best
starting point (step 1's scores, one model call a start), not by their listed form's BIC: a
listed form that approximates its own cause poorly (one lag for a shaft that lags behind the
housing: the listed lag came fourth) ranks low exactly when its form is needed. Every form
looked at counts in the Bonferroni adjustment of step 2. (All forms of a chosen family are
fitted: ordering a family's forms by their best start and stopping at the first that explains
was tried and fails: the per-part lag's denser start grid ranked it first on the two-node
network, where it explains at chi-square 492 against the series form's 249.)

1. the fit starts at the listed fit (the form's reducing value, `from_listed`, gives the listed
   form's predictions exactly) and from a few values of the extra parameters, nuisance refitted,
   profiled parameters (a settling threshold) held at the listed fit's value;
2. likelihood ratio against the LISTED fit, chi-bar-square null (one-sided where the reducing
   value is a bound), Bonferroni over the forms looked at, and a BIC margin for the extra
   parameters;
3. held-out gain against the LISTED form: the form's held-out residuals (`heldout_linear`, refit
   on the other blocks) against the listed form's held-out residuals of phase 4, paired block
   bootstrap (`bootstrap_gain`) excluding zero; and against the baseline likewise;
4. the form explains the data when it passes 2 and 3 and leaves no structure (`describe`, the
   `alpha_residual` threshold of the listed candidates);
5. and it is claimed only under the rules of any claim (`decision.form_carries_weight`): it
   clearly beats every other fitted candidate (the sensor look-alikes included) by joint fits
   and the unlisted sensor drift. Before 2026-11-25 a form could turn an `unexplained` that the
   drift check had decided into `explained` (a 0.5 K thermometer offset as a CTE curvature).
6. a form that passes every test but the held-out gain over its listed form
   (`unresolved_from_listed`) names its family only when the decision refused the listed form
   for the sensor drift alone and the form carries the weight by step 5's rules
   (`_family_past_drift`: the drift took up what separates the forms, and a difference
   confined to the hour after an onset lies in one held-out block, which the block bootstrap
   cannot resolve).

A form that explains the data turns the verdict into `explained` with `cause` = the family (the
listed cause) and `extended_form` = the form, its parameters, uncertainties, its one-line text
("thermal_lag, per-part time constants: housing 900 s, shaft 2400 s") and its gains. Data that a
listed form explains never reach this phase (the verdict is not `unexplained`), and a form must
beat its listed form out of sample (under 6: the listed form cannot be claimed at all), so a
listed effect that explains the data is never reported as an extended one.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Mapping

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.candidate import Candidate, HeldoutGain
from studies.diagnosis.core import Baseline, Decision, Fit, ModelFailure, Residuals
from studies.diagnosis.decision import form_carries_weight, refused_for_drift
from studies.diagnosis.goodness import GoodnessOfFit, goodness
from studies.diagnosis.fitting import fit_profiled, uncertainty
from studies.diagnosis.heldout import bootstrap_gain, heldout_linear, heldout_linear_of
from studies.diagnosis.problem import Problem
from studies.diagnosis.stats import chibar_pvalue
from studies.model.effects.generalised import forms_of

#: families (listed candidates, best BIC first) whose generalised forms are tried
MAX_FAMILIES = 2
#: the thermal kin: the listed effects and model forms whose change is the parts' temperatures
#: differing from the measured ones (`thermal_lag` and its `.per_part` and `.series` forms,
#: `radial_gradient` and its `.lag` form, the `thermal_transient_fe` rung). One member's form
#: may describe what another carries the weight for (a two-node network's lags: the rung and
#: `thermal_lag.series` within chi-square 10 of each other), so a further cause is held to the
#: kin's forms too (`selection._alternatives`)
THERMAL_KIN = ("thermal_lag", "radial_gradient", "thermal_transient_fe")


def kin_of(name: str) -> tuple[str, ...]:
    """The other members of `name`'s kin (THERMAL_KIN), () when it has none."""
    return tuple(k for k in THERMAL_KIN if k != name) if name in THERMAL_KIN else ()


#: local fits per form: from the listed fit and from the best other starting points
N_RUNS = 3


@dataclass
class FormEntry:
    """One generalised form tried (an entry of `generalised_forms` in diagnosis.json): the
    family (`effect`), the form's names, and unless the model failed its fitted parameters
    (units), uncertainties, the listed fit's parameters, the refitted nuisance, the tests
    against the listed form (chi-squares, likelihood ratio, degrees of freedom, Bonferroni-
    adjusted p, delta BIC, held-out gains against the listed form and the baseline), held-out
    and in-sample RMSE per column, the residual description; its status and why."""
    effect: str
    form: str
    name: str
    status: str            # explains | passes_but_leaves_structure | unresolved_from_listed
    #                        | rejected | model_failed
    reason: str
    label: str | None = None
    text: str | None = None
    parameters: dict[str, float] | None = None
    units: dict[str, str] | None = None
    parameter_uncertainty: dict | None = None
    listed_parameters: dict[str, float] | None = None
    nuisance: dict[str, float] | None = None
    chi2_listed: float | None = None
    chi2: float | None = None
    lr_vs_listed: float | None = None
    df_vs_listed: dict[str, int] | None = None
    p_vs_listed: float | None = None
    delta_bic_vs_listed: float | None = None
    heldout_gain_vs_listed: HeldoutGain | None = None
    heldout_gain_vs_baseline: HeldoutGain | None = None
    heldout_rmse: dict[str, float] | None = None
    rmse: dict[str, float] | None = None
    residuals: Residuals | None = None
    profiled: dict | None = None

    def to_json(self) -> dict:
        """The fields that are set (a form the model failed on: names, status, reason)."""
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) is not None}


@dataclass
class ChosenForm:
    """The generalised form that explains the data: its fit, held-out residuals, entry and the
    form's effect object."""
    fit: Fit
    heldout_z: np.ndarray
    entry: FormEntry
    form: object = None


@dataclass
class Generalisation:
    """Phase 5b: the (possibly new) decision, one entry per form tried, the chosen form."""
    decision: Decision
    forms: list[FormEntry]
    chosen: ChosenForm | None


def _families(cands: Mapping[str, Candidate], fits: dict[str, Fit], d: Decision,
              effects: Mapping[str, object] | None = None, structure: bool = False
              ) -> list[str]:
    """Listed families whose forms may be tried: the cause's own (explained), else the fitted
    candidates better than the baseline (delta BIC < 0, significant), best first; then, while
    the baseline leaves structure (`structure`) and no cause explains it, the families whose
    listed form fits at its off value (`at_off`; `effects`: name -> effect object): a listed
    form that cannot move from off may miss its own family's form (the shaft side
    900 s behind the hub, the listed single lag fitted at tau = 0, so its per-part form was
    never proposed)."""
    if d.verdict == "explained":        # the listed cause's own forms, nested in it
        return [d.cause] if forms_of(d.cause) else []
    tied = {d.best, *d.rivals} if d.verdict == "ambiguous" else set(fits)
    better = [n for n in sorted(fits, key=lambda n: cands[n].delta_bic)
              if n in tied and forms_of(n) and cands[n].delta_bic < 0
              and cands[n].lr_significant]
    if not structure or effects is None or d.verdict not in ("unexplained", "explained_partly"):
        return better
    return better + [n for n in fits if n not in better and forms_of(n)
                     and at_off(effects[n], cands[n])]


def at_off(effect, cand: Candidate) -> bool:
    """True when the fitted listed candidate sits at its off value: every parameter within
    its standard uncertainty of off, or within 1e-3 of its scale when the uncertainty is not
    known (e.g. a lag fitted at exactly tau = 0)."""
    for p, v in (cand.parameters or {}).items():
        u = (cand.uncertainty or {}).get(p)
        tol = max(u if isinstance(u, float) and math.isfinite(u) else 0.0,
                  1e-3 * float(effect.scale.get(p, 1.0)))
        if abs(float(v) - float(effect.off[p])) > tol:
            return False
    return bool(cand.parameters)


def _bounded(pb: Problem, fam: str, form):
    """The form with its listed parameters' bounds narrowed as its listed effect's are."""
    listed = pb.effect(fam)
    return form.with_bounds(**{p: listed.bounds[p] for p in form.parameters
                               if p in listed.bounds})


def _screened(pb: Problem, cands: Mapping[str, Candidate], fits: dict[str, Fit],
              families: list[str]) -> tuple[list[tuple[str, list[tuple]]], int]:
    """The families whose forms are fitted, each with its applicable forms (bounded) and their
    scored starts (None: scored when fitted), and the number of forms looked at (the Bonferroni
    count of the tests against the listed forms: a form ranked out was looked at with the data
    too).

    The families are the first MAX_FAMILIES of `families` that have a form applicable to the
    conditions. With more such families than that, every form's starts are scored
    (`_scored_starts_of`, one model call a start) and the families are ranked by their forms' best
    start (BIC = chi-square + number of parameters x ln N) instead of by the listed form's BIC:
    a listed form that approximates its own cause poorly (one lag for a shaft that lags behind
    the housing) ranks low exactly when its form is needed (a two-node network's
    lags, the listed lag fourth by BIC)."""
    fams = [(fam, [_bounded(pb, fam, f) for f in forms_of(fam)
                   if f.applicable(pb.conditions) is None]) for fam in families]
    fams = [(fam, forms) for fam, forms in fams if forms]
    rank = len(fams) > MAX_FAMILIES

    # with ranking, every form's starts are scored, all in one map (`_scored_starts_of`)
    every = [(fam, f) for fam, forms in fams for f in forms] if rank else []
    scores = _scored_starts_of(pb, [(f, _space(pb, f, cands[fam]), dict(cands[fam].parameters),
                                     fits[fam]) for fam, f in every])
    scores = {id(f): (None if isinstance(sc, ModelFailure) else sc)
              for (_, f), sc in zip(every, scores)}

    def bic(form, sc):
        return math.inf if sc is None else sc[0][0] + len(form.parameters) * math.log(pb.N)

    groups = []
    for i, (fam, forms) in enumerate(fams):
        got = [(f, scores[id(f)] if rank else None) for f in forms]
        groups.append((min(bic(*x) for x in got) if rank else 0.0, i, fam, got))
    if rank:
        groups.sort(key=lambda t: t[:2])
    return ([(fam, got) for _, _, fam, got in groups[:MAX_FAMILIES]],
            sum(len(forms) for _, forms in fams))


def _space(pb: Problem, form, cand: Candidate):
    """The form's parameter space, a profiled parameter held at the listed fit's value."""
    vals_listed = dict(cand.parameters)
    return pb.space([form], {form.name: {p: vals_listed[p] for p in fitspec.profile(form)}})


def generalise(pb: Problem, cands: Mapping[str, Candidate], fits: dict[str, Fit], ho: dict,
               b: Baseline, d: Decision, rng: np.random.Generator) -> Generalisation:
    """Try the generalised forms (module docstring; `explained_partly` as `unexplained`: the
    forms of the two best families; `ambiguous`: the forms of the tied families, so that a form
    of one of two look-alikes that explains what neither listed form does alone, and carries
    the weight over the other, breaks the tie)."""
    if not pb.try_generalised or d.verdict not in ("unexplained", "explained",
                                                    "explained_partly", "ambiguous"):
        return Generalisation(d, [], None)
    tried, m = _screened(pb, cands, fits, _families(
        cands, fits, d, {n: pb.effect(n) for n in fits}, bool(b.structure)))
    entries, ok = [], []
    forms = [(fam, form, scored) for fam, got in tried for form, scored in got]
    f_exts = _local_fits(pb, forms, cands, fits, b)
    # the forms' held-out folds in one map (no random numbers: the bootstraps below draw in
    # the forms' order)
    fitted = [f for f in f_exts if not isinstance(f, ModelFailure)]
    hos = dict(zip(map(id, fitted), heldout_linear_of(pb, fitted) if fitted else []))
    for (fam, form, _), f_ext in zip(forms, f_exts):
        try:
            if isinstance(f_ext, ModelFailure):
                raise f_ext
            entry, f_ext, ho_ext, gof = fit_form(pb, form, fits[fam], ho[fam], cands[fam], b,
                                                 m, rng, f_ext=f_ext, ho_ext=hos[id(f_ext)])
        except ModelFailure as exc:
            entries.append(FormEntry(fam, form.form, form.name, "model_failed", str(exc)))
            continue
        entries.append(entry)
        if entry.status in ("explains", "unresolved_from_listed"):
            ok.append((f_ext.chi2, entry, f_ext, ho_ext, gof, form))
    ok.sort(key=lambda t: t[:1])
    got = _carrying(pb, [t for t in ok if t[1].status == "explains"], cands, fits, b)
    if got is not None:
        entry, f_ext, ho_ext, gof, form, joint = got
        why = (f"the generalised form {entry.text} beats the listed form {entry.effect} in "
               f"sample (p = {entry.p_vs_listed:.2g}) and on held-out blocks and leaves no "
               "structure")
    else:
        got = _family_past_drift(pb, d, ok, cands, fits, b)
        if got is None:
            return Generalisation(d, entries, None)
        entry, f_ext, ho_ext, gof, form, joint = got
        g = entry.heldout_gain_vs_listed
        why = (f"{entry.effect} is named in the generalised form {entry.text}: its listed "
               f"form did not clearly beat the sensor drift, this form beats the listed one "
               f"in sample (p = {entry.p_vs_listed:.2g}), the baseline on held-out blocks and "
               "the drift, and leaves no structure; its held-out gain over the listed form is "
               f"not resolved (interval [{g.ci[0]:.3g}, {g.ci[1]:.3g}]), so the family is the "
               "cause and which of its forms is not told apart out of sample")
    new = Decision("explained", entry.effect, entry.effect, [], entry.residuals,
                   {**d.joint_fits, **joint}, list(d.reasons) + [why], gof, d.beaten)
    return Generalisation(new, entries, ChosenForm(f_ext, ho_ext, entry, form))


def _carrying(pb: Problem, ok: list[tuple], cands: Mapping[str, Candidate],
              fits: dict[str, Fit], b: Baseline) -> tuple | None:
    """The first of the forms `ok` ((chi-square, entry, fit, held-out residuals, goodness,
    form), lowest chi-square first) that the rules of a claim let through
    (`decision.form_carries_weight`): (entry, fit, held-out residuals, goodness, form, its joint
    fits), or None; a form that does not carry the weight is marked rejected with why."""
    for _, entry, f_ext, ho_ext, gof, form in ok:
        df = {"n_free": cands[entry.effect].df["free"] + entry.df_vs_listed["free"],
              "n_bound": cands[entry.effect].df["on_bound"] + entry.df_vs_listed["on_bound"]}
        why, joint = form_carries_weight(pb, entry.effect, form, f_ext, df, cands, fits, b)
        if why is None:
            return entry, f_ext, ho_ext, gof, form, joint
        entry.status, entry.reason = "rejected", f"{entry.reason}; but {why}"
    return None


def _family_past_drift(pb: Problem, d: Decision, ok: list[tuple],
                       cands: Mapping[str, Candidate], fits: dict[str, Fit],
                       b: Baseline) -> tuple | None:
    """The family named through a form its held-out blocks do not resolve from the listed one
    (as `_carrying`, or None). When the decision refused its best candidate only for the sensor
    drift (`decision.refused_for_drift`), a form of that family that passes every test but the
    held-out gain over the listed form (`unresolved_from_listed`: significant against it in
    sample, a held-out gain over the baseline, no structure left) and clearly beats the drift
    and every rival is claimed. The drift took up what separates the two forms (a settling over
    an hour fitted as a step: 12 N, tau 3600 s on 240 rows of 120 s), so the listed form's
    refusal says its form is wrong, not that the family is; and a difference confined to the
    hour after an onset lies in one of 6-10 held-out blocks, which a block bootstrap misses in
    a third of its resamples and cannot resolve."""
    if not refused_for_drift(d, pb.th["alpha_joint"]):
        return None
    return _carrying(pb, [t for t in ok if t[1].status == "unresolved_from_listed"
                          and t[1].effect == d.best], cands, fits, b)


def _scored_starts_of(pb: Problem, plans: list[tuple]) -> list:
    """The scored starts of several forms ((form, space, listed values, listed fit) each), all
    in one map on the workers: per form its (chi-square with the nuisance refitted linearly,
    the step kept only where the model fits better there, index, start) of each start, best
    first (the listed fit's reducing value first, then the fit specification's extra starts; two
    model calls each), or the ModelFailure of a model failing at every start."""
    items = []
    for j, (form, space, vals_listed, f_listed) in enumerate(plans):
        start_vals = [form.from_listed(vals_listed)]
        start_vals += [{**start_vals[0], **x}
                       for x in fitspec.extra_starts(form, vals_listed, pb.conditions)]
        items += [(j, i, v) for i, v in enumerate(start_vals)]

    def score(item):
        j, i, v = item
        _, space, _, f_listed = plans[j]
        k, nq = space.k, len(pb.nuisance.names)
        u_nuis = f_listed.u[f_listed.space.k:]
        Jn = f_listed.J[:, f_listed.space.k:]       # d z / d u_nuisance at the listed fit
        x = np.array([v[p] for (_, p) in space.eff_params], float)
        u = space.clip(np.concatenate([(x - space.origin[:k]) / space.scale[:k], u_nuis]))
        try:
            z, _ = pb.eval(space, u)
        except ModelFailure:
            return None
        if nq:                                   # linearised nuisance refit for the score
            dn, *_ = np.linalg.lstsq(Jn, -z, rcond=None)
            u_step = space.clip(np.concatenate([u[:k], u[k:] + dn]))
            # the step is taken when the model itself says it fits better: with accepted
            # causes in the baseline their free parameters are in Jn too, and a linear step
            # across a nonlinear one (a rung's mount) can land far off (th_mount_settling seed
            # 4: linear 361 from the listed 379, the model there thousands, and the gradual
            # settling's local fit from it ended at 6205)
            try:
                z_step, _ = pb.eval(space, u_step)
            except ModelFailure:
                z_step = None
            if z_step is not None and float(z_step @ z_step) < float(z @ z):
                u, z = u_step, z_step
        return float(z @ z), i, u

    got = pb.parallel(score, items)
    out = []
    for j in range(len(plans)):
        scored = [t for (jj, _, _), t in zip(items, got) if jj == j and t is not None]
        if not scored:
            out.append(ModelFailure("the model fails at every start of the generalised form"))
            continue
        scored.sort(key=lambda t: t[:2])
        out.append(scored)
    return out


def _local_fits(pb: Problem, forms: list[tuple], cands: Mapping[str, Candidate],
                fits: dict[str, Fit], b: Baseline) -> list:
    """The best local fit of each (family, form, scored starts or None) of `forms`, or the
    ModelFailure that stopped it: local fits from the listed fit (index 0) and the two most
    promising other starts (another start only when its score already beats the listed fit:
    otherwise the data give the extra parameter nothing to do, and a listed effect costs one
    local fit), and with a profiled parameter the profiled fit over the listed grid; the best.
    The local fits of all forms are independent: one map on the workers (the profiled ones
    first), so one form's long fit runs beside another's, not after it."""
    plans, items, first = [], [], []
    spaces = [_space(pb, form, cands[fam]) for fam, form, _ in forms]
    # the starts of the forms not scored yet: in one map (`_scored_starts_of`)
    todo = [k for k, (_, _, scored) in enumerate(forms) if scored is None]
    fresh = dict(zip(todo, _scored_starts_of(pb, [
        (forms[k][1], spaces[k], dict(cands[forms[k][0]].parameters), fits[forms[k][0]])
        for k in todo]))) if todo else {}
    for k, (fam, form, scored) in enumerate(forms):
        cand, f_listed = cands[fam], fits[fam]
        space = spaces[k]
        scored = fresh.get(k, scored)
        if isinstance(scored, ModelFailure):
            plans.append(scored)
            continue
        runs = [t for t in scored if t[1] == 0] + [
            t for t in scored if t[1] != 0 and t[0] < f_listed.chi2][:N_RUNS - 1]
        profiled = bool(fitspec.profile(form) and cand.profile_grid)
        plans.append((len(items), len(runs), profiled))
        items += [(k, space, u) for _, _, u in runs]
        if profiled:
            first.append(len(items))
            items.append((k, space, None))

    def local_fit(item):
        """The local fit from start u (None: the profiled fit over the listed grid), or None
        when the model fails."""
        k, space, u = item
        fam, form, _ = forms[k]
        try:
            if u is None:
                return fit_profiled(pb, form, cands[fam].profile_grid, b.fit)
            return pb.fit(space, u)
        except ModelFailure:
            return None

    got = pb.parallel(local_fit, items, first=first or None)
    out = []
    for plan in plans:
        if isinstance(plan, ModelFailure):
            out.append(plan)
            continue
        i0, n, profiled = plan
        # the best of the local fits, then the profiled one only when strictly better
        f_ext = _lowest(got[i0:i0 + n])
        if profiled:
            f_ext = _lowest([f_ext, got[i0 + n]])
        out.append(f_ext if f_ext is not None else
                   ModelFailure("the fits of the generalised form fail from every start"))
    return out


def _lowest(fits: list[Fit | None]) -> Fit | None:
    """The fit of lowest chi-square (the first of equals), None when none succeeded."""
    best = None
    for f in fits:
        if f is not None and (best is None or f.chi2 < best.chi2):
            best = f
    return best


def _form_status(th, m: int, p_adj: float, dbic: float, g_listed: HeldoutGain,
                 g_base: HeldoutGain, desc: Residuals,
                 gof: GoodnessOfFit) -> tuple[str, list[str]]:
    """explains | passes_but_leaves_structure | unresolved_from_listed | rejected, and why
    (module docstring, 2-4). `unresolved_from_listed`: every test passes and no structure is
    left but the held-out gain over the listed form (`_family_past_drift` may name the family
    through it)."""
    reasons = []
    if not p_adj < th["alpha_lr"]:
        reasons.append(f"not significant against the listed form (p = {p_adj:.2g}, "
                       f"Bonferroni over {m})")
    if not dbic < -th["bic_margin"]:
        reasons.append(f"BIC not better than the listed form (delta {dbic:.1f})")
    if not g_listed.excludes_zero:
        reasons.append("no held-out gain over the listed form (bootstrap interval "
                       f"[{g_listed.ci[0]:.3g}, {g_listed.ci[1]:.3g}] includes 0)")
    if not g_base.excludes_zero:
        reasons.append("no held-out gain over the baseline")
    if not reasons and gof.leaves_structure:
        reasons.append("beats the listed form but leaves structure (adjusted p = "
                       f"{min(desc.p_min_adjusted, gof.p_adjusted):.2g})")
        return "passes_but_leaves_structure", reasons
    if len(reasons) == 1 and not g_listed.excludes_zero and not gof.leaves_structure:
        return "unresolved_from_listed", reasons
    return ("rejected" if reasons else "explains"), reasons


def fit_form(pb: Problem, form, f_listed: Fit, ho_listed: np.ndarray, cand, b: Baseline,
             m: int, rng: np.random.Generator, f_ext: Fit | None = None,
             ho_ext: np.ndarray | None = None
             ) -> tuple[FormEntry, Fit, np.ndarray, GoodnessOfFit]:
    """Nested fit of one generalised form from the listed fit and its tests (module
    docstring, steps 1-4); `f_ext`: its best local fit when already made (`_local_fits`),
    `ho_ext`: that fit's held-out residuals when already computed (`heldout_linear`).
    Returns (entry, fit, held-out residuals, goodness of fit)."""
    vals_listed = dict(cand.parameters)
    if f_ext is None:
        f_ext = _local_fits(pb, [(form.family, form, None)], {form.family: cand},
                            {form.family: f_listed}, b)[0]
        if isinstance(f_ext, ModelFailure):
            raise f_ext
    eff_vals, nuis_vals = f_ext.space.unpack(f_ext.u)
    params = dict(eff_vals[form.name])
    n_bound = sum(1 for p in form.extra if form.on_bound(p))
    n_free = len(form.extra) - n_bound
    lr = max(f_listed.chi2 - f_ext.chi2, 0.0)
    p_adj = min(1.0, chibar_pvalue(lr, n_free, n_bound) * m)
    dbic = -lr + len(form.extra) * math.log(pb.N)
    if ho_ext is None:
        ho_ext = heldout_linear(pb, f_ext)
    g_listed = bootstrap_gain(pb, rng, ho_listed, ho_ext)
    g_base = bootstrap_gain(pb, rng, b.heldout_z, ho_ext)
    n_par = len(pb.nuisance.names) + (cand.k or 0) + len(form.extra)
    desc = pb.describe(f_ext.pred, n_par)
    gof = goodness(pb, f_ext, ho_ext, n_par, desc)
    status, reasons = _form_status(pb.th, m, p_adj, dbic, g_listed, g_base, desc, gof)
    reason = ("; ".join(reasons) if reasons else
              "beats the listed form in sample and on held-out blocks, no structure left")
    profiled = ({q: {"value": params[q], "listed_fit": vals_listed[q]}
                 for q in fitspec.profile(form)} if fitspec.profile(form) else None)
    entry = FormEntry(
        form.family, form.form, form.name, status, reason, label=form.label,
        text=form.text(params), parameters=params,
        units={q: form.units[q] for q in form.parameters},
        parameter_uncertainty=uncertainty(pb, f_ext, form), listed_parameters=vals_listed,
        nuisance=nuis_vals, chi2_listed=f_listed.chi2, chi2=f_ext.chi2, lr_vs_listed=lr,
        df_vs_listed={"free": n_free, "on_bound": n_bound}, p_vs_listed=p_adj,
        delta_bic_vs_listed=dbic, heldout_gain_vs_listed=g_listed,
        heldout_gain_vs_baseline=g_base, heldout_rmse=pb.col_rmse(ho_ext),
        rmse=pb.col_rmse(f_ext.z), residuals=desc, profiled=profiled)
    return entry, f_ext, ho_ext, gof
