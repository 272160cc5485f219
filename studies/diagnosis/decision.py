"""Phase 5 of the diagnosis: the verdict. The best passing candidate is compared with every
rival by joint fits; ambiguous causes get a separating test (module docstring of
`studies.diagnosis.engine`, step 5)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.candidate import Candidate
from studies.diagnosis.core import Baseline, Decision, Fit, JointFit, ModelFailure
from studies.diagnosis.goodness import goodness
from studies.diagnosis.ladder import is_lookalike
from studies.diagnosis.problem import Problem
from studies.diagnosis.stats import chibar_pvalue


#: the unlisted look-alike every claim must beat (`DecisionPhase.versus_sensor_drift`), as named
#: in the joint fits of the result
SENSOR_DRIFT = "unlisted: sensor zero drift linear in time"


def decide(pb: Problem, cands: Mapping[str, Candidate], fits: dict[str, Fit],
           passing: list[str], b: Baseline, ho: Mapping[str, np.ndarray]) -> Decision:
    """Phase 5: the verdict (module docstring of `studies.diagnosis.engine`, step 5). The
    passing candidates beaten by the best get a note (`Decision.beaten`) for their reason.

    The best passing candidate (lowest BIC) that can be a cause is compared with its rivals
    (joint fits) and with the unlisted sensor drift; then its goodness of fit
    (`goodness.goodness`): `explained` when it carries the weight and leaves no structure,
    `explained_partly` when it carries the weight but leaves structure, `ambiguous` when rivals
    fit as well (`unexplained` when they also leave structure), `unexplained` when it does not
    beat the drift or an unlisted sensor look-alike (`ladder.is_lookalike`: a thermometer offset
    within its class) fits about as well or better: a look-alike is fitted and compared like a
    candidate but never claimed."""
    claimable = [n for n in passing if not is_lookalike(pb.effect(n))]
    if not claimable:
        if passing:                 # only a sensor look-alike passes
            lk = min(passing, key=lambda n: cands[n].delta_bic)
            return Decision("unexplained", None, lk, [], pb.describe(fits[lk].pred, len(
                pb.nuisance.names) + cands[lk].k), {}, [
                f"only an unlisted sensor error passes: {lk} ({pb.effect(lk).change}); no "
                f"listed cause or model form explains the data. {pb.effect(lk).hint}"])
        return _nothing_passes(b)
    best = min(claimable, key=lambda n: cands[n].delta_bic)
    n_par = len(pb.nuisance.names) + cands[best].k
    best_desc = pb.describe(fits[best].pred, n_par)
    gof = goodness(pb, fits[best], ho[best], n_par, best_desc)
    rivals, joint = compare(pb, best, fits, cands, list(fits))
    beaten = {o: (f"; but clearly beaten by {best} (chi-square "
                  f"{fits[o].chi2 - fits[best].chi2:+.1f})")
              for o in passing if o != best and o not in rivals}
    drift = versus_sensor_drift(pb, fits[best], _df(cands[best]), b)
    if drift is not None:
        joint[SENSOR_DRIFT] = drift
    why = unlisted_lookalike(pb, best, rivals, drift)
    if why is not None:
        return Decision("unexplained", None, best, [r for r in rivals if not is_lookalike(
            pb.effect(r))], best_desc, joint, [why], gof, beaten)
    left = "; ".join(x.text for x in gof.left)
    if rivals and gof.leaves_structure:
        return Decision("unexplained", None, best, rivals, best_desc, joint, [
            f"the best candidate, {best}, passes but leaves structure ({left}) and "
            f"{', '.join(rivals)} fit about as well"], gof, beaten)
    if rivals:
        return Decision("ambiguous", best, best, rivals, best_desc, joint, [
            f"{best} and {', '.join(rivals)} explain the data about equally well"], gof, beaten)
    if gof.leaves_structure:
        return Decision("explained_partly", best, best, rivals, best_desc, joint, [
            f"{best} beats the baseline on held-out blocks and clearly beats every other "
            f"candidate, but leaves structure: {left}"], gof, beaten)
    return Decision("explained", best, best, rivals, best_desc, joint, [
        f"{best} beats the baseline on held-out blocks and clearly beats every other "
        "candidate"], gof, beaten)


def unlisted_lookalike(pb: Problem, best: str, rivals: list[str],
                       drift: JointFit | None) -> str | None:
    """Why `best` cannot be claimed over an unlisted look-alike (None: it can): it does not
    clearly beat the sensor drift (`versus_sensor_drift`), or a sensor look-alike among its
    rivals fits about as well (`compare`)."""
    look = [r for r in rivals if is_lookalike(pb.effect(r))]
    if look:
        e = pb.effect(look[0])
        return (f"the best candidate, {best}, does not clearly beat an unlisted sensor error, "
                f"{e.name} ({e.change}), which fits the data about as well or better: "
                f"{e.hint}")
    if drift is not None and not drift.best_carries_weight:
        a = pb.th["alpha_joint"]
        return (f"the best candidate, {best}, does not clearly beat a zero drift of the "
                "sensors linear in time, a cause outside the list that a history effect "
                f"resembles (adding {best} to that drift: p = {drift.p:.2g}, needs < "
                f"{a:g}; adding the drift to {best}: p = "
                f"{drift.p_add_other_to_best:.2g}, needs >= {a:g}); "
                "a test at other speeds or a repeat of the programme separates a drift "
                "in time from the effect")
    return None


def refused_for_drift(d: Decision, alpha: float) -> bool:
    """Was decision `d` `unexplained` only because its best candidate did not clearly beat the
    unlisted sensor drift (`versus_sensor_drift`): no rival, adding it to the drift significant
    at `alpha` while adding the drift to it is too? That is what a second cause that changes in
    time does to a first one (a run-in at constant speed), and what a listed form does to a
    cause of the same family in another form (a step for a settling over an hour: the drift
    takes up the difference)."""
    j = d.joint_fits.get(SENSOR_DRIFT)
    return (d.verdict == "unexplained" and d.best is not None and not d.rivals
            and j is not None and not j.best_carries_weight and j.p is not None
            and j.p < alpha and j.p_add_other_to_best is not None
            and j.p_add_other_to_best < alpha)


def form_carries_weight(pb: Problem, family: str, form, f_form: Fit, df: dict,
                        cands: Mapping[str, Candidate], fits: dict[str, Fit],
                        b: Baseline) -> tuple[str | None, dict[str, JointFit]]:
    """The rules of a claim (`decide`) for a generalised form of `family` in its listed form's
    place (`studies.diagnosis.generalised`): it must clearly beat every other fitted candidate
    (the sensor look-alikes included) by joint fits, and the sensor drift. Returns (None, joint
    fits) when it does, else (why not, joint fits). df: {"n_free", "n_bound"} of the form."""
    rivals, joint = compare(pb, family, fits, cands, [n for n in fits if n != family],
                            effect=form, fit=f_form, df=df)
    drift = versus_sensor_drift(pb, f_form, df, b)
    if drift is not None:
        joint[SENSOR_DRIFT] = drift
    why = unlisted_lookalike(pb, form.name, rivals, drift)
    if why is None and rivals:
        why = f"{form.name} does not clearly beat {', '.join(rivals)}"
    return why, joint


def _nothing_passes(b: Baseline) -> Decision:
    """No candidate passes: unexplained when the baseline residuals show structure (with a note
    when it is only serial correlation a smoother cannot predict), else no discrepancy."""
    desc = b.residuals
    if not b.structure:
        return Decision("no_discrepancy", None, None, [], None, {}, [
            "the baseline residuals are consistent with the noise estimated from the data and "
            "no candidate passes"])
    reasons = ["the baseline residuals show structure beyond noise "
               f"(adjusted p = {desc.p_min_adjusted:.2g}) but no candidate passes"]
    if all(d.smoother_heldout_gain <= 0 and d.bias_p > 0.01 for d in desc.columns.values()):
        reasons.append("the structure is serial correlation that a smooth function of the "
                       "conditions does not predict on held-out blocks: it may be correlated "
                       "noise, a drift in time or a history effect outside the candidate list")
    return Decision("unexplained", None, None, [], None, {}, reasons)


def versus_sensor_drift(pb: Problem, f: Fit, df: dict, b: Baseline) -> JointFit | None:
    """Does the fitted candidate carry weight over an unlisted look-alike, a zero drift of
    every compared sensor linear in time (the commonest unlisted cause on a rig, and what a
    history effect in time or revolutions resembles, e.g. a run-in at constant speed)?

    Likelihood ratio of adding the candidate to baseline + drift: chi2(baseline + drift) -
    chi2(candidate + drift), every chi2 linearised at its own fit (the drift is linear in its
    slopes; nuisance and candidate take one Gauss-Newton step with their fit's Jacobian),
    chi-bar-square p with the candidate's degrees of freedom; and of adding the drift to the
    candidate (chi2(candidate) - chi2(candidate + drift), one free slope per column). As in
    the joint fits of two candidates (`compare`), the candidate carries the weight when
    adding it to the drift is significant at alpha_joint and adding the drift to it is not.
    The drift's residual columns are whitened and scaled exactly as the data (`zvec`). None
    without a strictly increasing `time_s` (a table of steady points has no time order)."""
    t = pb.conditions.get("time_s")
    if t is None or t.size < 3 or not np.all(np.diff(t) > 0):
        return None
    ramp = (t - t[0]) / (t[-1] - t[0])
    D = np.zeros((pb.N, len(pb.columns)))
    i0 = 0
    for j, c in enumerate(pb.columns):
        m = pb.valid[c]
        k = int(m.sum())
        D[i0:i0 + k, j] = pb.standardise(c, ramp[m])
        i0 += k

    def chi2_lin(fit: Fit, drift: bool) -> float:
        """chi2 after one Gauss-Newton step of the fit's own parameters (and the drift's
        slopes): every chi2 compared is linearised the same way, so an unfinished fit's own
        step is not credited to the drift."""
        A = np.column_stack([fit.J, D]) if drift else fit.J
        coef, *_ = np.linalg.lstsq(A, fit.z, rcond=None)
        r = fit.z - A @ coef
        return float(r @ r)
    chi_0 = chi2_lin(b.fit, True)                    # baseline + drift
    chi_c = min(chi2_lin(f, False), f.chi2)          # candidate
    chi_j = min(chi2_lin(f, True), chi_0, chi_c)     # candidate + drift
    p = chibar_pvalue(max(chi_0 - chi_j, 0.0), **df)
    p_drift = chibar_pvalue(max(chi_c - chi_j, 0.0), len(pb.columns), 0)
    # the keys of a joint fit of two candidates (`compare`, the report's table)
    a = pb.th["alpha_joint"]
    return JointFit(bool(p < a and p_drift >= a), chi_c, chi_0, chi_j, p_drift, p, p)

def compare(pb: Problem, best, fits, cands, names_id, effect=None, fit=None, df=None):
    """Rivals of `best`: fitted candidates it does not clearly beat (joint fits). effect, fit,
    df: another effect object, its fit and {"n_free", "n_bound"} in the place of `best`'s (a
    generalised form of `best`)."""
    th = pb.th
    alpha = th["alpha_joint"]
    rivals, joint = [], {}
    eb = pb.effect(best) if effect is None else effect
    fb = fits[best] if fit is None else fit
    df_b = _df(cands[best]) if df is None else df
    for o in names_id:
        if o == best:
            continue
        fo = fits[o]
        if fo.chi2 - fb.chi2 > th["clear_chi2"]:
            continue
        eo = pb.effect(o)
        fixed = {}
        for e, f in ((eb, fb), (eo, fo)):
            if fitspec.profile(e):
                fixed[e.name] = {p: (f.profile_value if f.profile_value is not None
                                     else f.space.fixed[e.name][p]) for p in fitspec.profile(e)}
        space = pb.space([eb, eo], fixed)
        kb = fb.space.k
        ko = fo.space.k
        starts = [np.concatenate([fb.u[:kb], np.zeros(ko), fb.u[kb:]]),
                  np.concatenate([np.zeros(kb), fo.u[:ko], fo.u[ko:]])]
        try:
            zs = []
            for s0 in starts:
                try:
                    z0 = pb.eval(space, s0)[0]
                    zs.append(float(z0 @ z0))
                except ModelFailure:
                    zs.append(math.inf)
            fj = pb.fit(space, starts[int(np.argmin(zs))])
        except ModelFailure as exc:    # cannot show that best carries the weight
            joint[o] = JointFit(False, error=str(exc))
            rivals.append(o)
            continue
        chi_j = min(fj.chi2, fb.chi2, fo.chi2)
        lr_o_given_b = max(fb.chi2 - chi_j, 0.0)
        lr_b_given_o = max(fo.chi2 - chi_j, 0.0)
        p_o = chibar_pvalue(lr_o_given_b, **_df(cands[o]))
        p_b = chibar_pvalue(lr_b_given_o, **df_b)
        beaten = p_b < alpha and p_o >= alpha
        joint[o] = JointFit(bool(beaten), fb.chi2, fo.chi2, chi_j, p_o, p_b)
        if not beaten:
            rivals.append(o)
    rivals.sort(key=lambda n: cands[n].delta_bic)
    return rivals, joint


def probes(pb: Problem):
    c = pb.conditions
    T0 = pb.T_ref_C
    out = []
    for col, label in (("speed_rpm", "speed"), ("preload_assembled_N", "preload"),
                       ("axial_load_N", "axial load")):
        if col in c and np.any(c[col] != 0):
            for f in (0.5, 2.0):
                d = dict(c)
                d[col] = c[col] * f
                out.append((f"repeat at {f:g} x the {label} ({col} {_rng(d[col])})", d))
    if "T_ambient_C" in c:
        T = c["T_ambient_C"]
        for text, T_new in (("extend the temperature range by 50 % about the reference "
                             "temperature", T0 + 1.5 * (T - T0)),
                            ("mirror the temperature programme about the reference temperature",
                             T0 - (T - T0))):
            out.append((f"{text} (T_ambient_C {_rng(T_new)})", {**c, "T_ambient_C": T_new}))
    if "time_s" in c:
        t = c["time_s"]
        for f, txt in ((0.25, "4 x faster"), (4.0, "4 x slower")):
            out.append((f"run the temperature programme {txt} (time_s scaled by {f:g})",
                        {**c, "time_s": t[0] + f * (t - t[0])}))
    return out


@dataclass
class Separation:
    """How to separate an ambiguous cause from its rivals: the summary text, one item per
    finding (`measured_conditions`, `unmeasured_output`, `probe`) and notes on probes the model
    could not evaluate."""
    text: str
    items: list[dict]
    notes: list[str]


def separating(pb: Problem, best: str, rivals: list[str], fits: dict[str, Fit],
               base: Fit) -> Separation:
    """The separating test of `best` and its rivals: where their fits differ most within the
    measured conditions, in unmeasured outputs and at probe conditions (`probes`)."""
    items, notes = [], []
    fb = fits[best]
    for o in rivals:
        fo = fits[o]
        items.append(_within_measured(pb, best, o, fb.pred, fo.pred))
        items += _unmeasured_outputs(pb, best, o, fb.pred, fo.pred, base.pred)
        if pb.predict_at is not None:
            items += _at_probes(pb, best, o, fb, fo, notes)
    return Separation(_summary(pb, best, rivals, items), items, notes)


def _within_measured(pb: Problem, best: str, o: str, zb: dict, zo: dict) -> dict:
    """Where, within the measured conditions, the two fits differ most (noise units)."""
    best_row, best_d, best_col = None, -1.0, None
    for c in pb.columns:
        d = np.abs(zb[c] - zo[c]) / pb.noise.sigma[c]
        i = int(np.argmax(d))
        if d[i] > best_d:
            best_row, best_d, best_col = i, float(d[i]), c
    return {"pair": [best, o], "kind": "measured_conditions",
            "max_diff_sigma": best_d, "column": best_col,
            "at": {k: float(v[best_row]) for k, v in pb.conditions.items()},
            "text": f"within the measured conditions {best} and {o} differ by at "
                    f"most {best_d:.2g} sigma in {best_col}"}


def _unmeasured_outputs(pb: Problem, best: str, o: str, zb: dict, zo: dict,
                        base_pred: dict) -> list[dict]:
    """Outputs not measured where the two fits differ by more than 1 % of the output's size."""
    items = []
    for c in zb:
        if c in pb.columns or c not in zo or c not in base_pred:
            continue
        d = np.abs(zb[c] - zo[c])
        ref = np.abs(base_pred[c])
        mag = max(float(np.max(ref)), 1e-12)
        if d.max() > 0.01 * mag:
            i = int(np.argmax(d))
            items.append({"pair": [best, o], "kind": "unmeasured_output", "column": c,
                          "max_diff": float(d[i]), "relative": float(d[i] / mag),
                          "at": {k: float(v[i]) for k, v in pb.conditions.items()},
                          "text": f"measure {c}: {best} and {o} predict values that "
                                  f"differ by up to {d[i]:.3g} ({100 * d[i] / mag:.0f} % "
                                  "of its size)"})
    return items


def _at_probes(pb: Problem, best: str, o: str, fb: Fit, fo: Fit, notes: list[str]) -> list[dict]:
    """The two fits evaluated at the probe conditions (`probes`): the largest difference in
    noise units per probe; a probe the model cannot evaluate is noted and skipped."""
    eb_eff, eb_nuis = fb.space.unpack(fb.u)
    eo_eff, eo_nuis = fo.space.unpack(fo.u)
    items = []
    for text, cond in probes(pb):
        try:
            p_best = pb.predict_at(eb_eff, eb_nuis, cond)
            p_other = pb.predict_at(eo_eff, eo_nuis, cond)
            if not all(np.all(np.isfinite(np.asarray(x[c], float)))
                       for x in (p_best, p_other) for c in pb.columns):
                raise ValueError("non-finite prediction")
        except Exception as exc:  # a probe outside the model's range: skip it
            notes.append(f"probe skipped ({text}): {exc}")
            continue
        dmax, col = 0.0, None
        for c in pb.columns:
            d = float(np.max(np.abs(np.asarray(p_best[c], float)
                                    - np.asarray(p_other[c], float))) / pb.noise.sigma[c])
            if d > dmax:
                dmax, col = d, c
        items.append({"pair": [best, o], "kind": "probe", "max_diff_sigma": dmax,
                      "column": col, "text": f"{text}: {best} and {o} then differ "
                      f"by up to {dmax:.2g} sigma in {col}"})
    return items


def _summary(pb: Problem, best: str, rivals: list[str], items: list[dict]) -> str:
    """The best probe (at least 2 sigma), the best unmeasured output, the physics hints."""
    parts = []
    by_probe = sorted((i for i in items if i["kind"] == "probe"),
                      key=lambda i: -i["max_diff_sigma"])
    if by_probe and by_probe[0]["max_diff_sigma"] >= 2.0:
        parts.append(by_probe[0]["text"])
    unmeas = sorted((i for i in items if i["kind"] == "unmeasured_output"),
                    key=lambda i: -i["relative"])
    if unmeas:
        parts.append(unmeas[0]["text"])
    hints = [f"{n}: {pb.effect(n).hint}" for n in [best] + list(rivals)
             if pb.effect(n).hint]
    if not parts:
        meas = [i for i in items if i["kind"] == "measured_conditions"]
        parts.append(meas[0]["text"] + " (not separable with this test design)")
    return "; or ".join(parts) + ". Physics: " + " | ".join(hints)


def _df(c):
    return {"n_free": c.df["free"], "n_bound": c.df["on_bound"]}


def _rng(a):
    a = np.asarray(a, float)
    return f"{a.min():.4g}..{a.max():.4g}" if a.min() != a.max() else f"{a.min():.4g}"


