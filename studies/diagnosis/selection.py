"""More than one cause: forward selection after the first cause is accepted.

A rig rarely has one cause. Once a pass of the diagnosis (phases 1-5b, `engine.one_pass`) has
accepted a cause (`explained` or `explained_partly`), the search goes on on what is left: the
accepted cause joins the baseline (its free parameters refitted with the nuisance in every later
model, a profiled one held at its accepted value: `problem.Accepted`), and the next pass runs the
same phases on the remaining candidates: the same calibration, screening, likelihood-ratio and
held-out rules, the same joint fits against rivals and against the unlisted sensor drift. The
noise level of the next pass is estimated from the residual of the model with the accepted
causes (`calibration.calibrate`), i.e. from what no candidate can absorb: a large first effect
that the conditions' smoother cannot follow otherwise shows up as strongly correlated noise of
inflated level (117 N mm against a true 17) and hides a second cause.

The search stops when a cause was accepted in a generalised form (the listed form left
structure; what the form leaves is its own mismatch, which other candidates imitate), when an
accepted cause has a parameter at its bound (what is left is the data
wanting more of that cause: an as-built fit outside its tolerance band is not a fit error plus a
path compliance), when the model of the accepted causes, calibrated with the noise re-estimated
from its residual, shows no structure and white noise (then no candidate is fitted again), when
a pass accepts
nothing (structure no candidate removes, or an ambiguous further cause), after MAX_CAUSES
causes, or when the first cause was
`explained` (leaves no structure) and the noise level estimated from its residual is within
NOISE_RTOL of the one the pass used (nothing was hiding under an inflated noise: no further
pass is run). The final verdict is `explained` when the model of the accepted causes leaves no
structure under the last noise estimate (`goodness.goodness`), else `explained_partly` with what
is left, but only when several causes were accepted; a single cause that leaves structure may be
a look-alike of a cause outside the list and the verdict is `unexplained` (with it as the best
partial candidate), as on an unlisted groove curvature on steady points.

Claim rules (`select` reads them as a table, one small function each, in order; their reasons:
docs/diagnosis.md, "The claim rules"). Before any fit: below the detection threshold in every
compared column (`detection.detection`: the change the calibrated baseline leaves against the
smallest change the data could show) the verdict is `no_discrepancy`, whatever fits. A cause the
data want at or beyond a bound (`goodness.at_bound`: the value on the bound, or the estimate
with the bounds released beyond it; the data wanting more than the candidate allows is evidence
against it, not a partial explanation: the sleeve in an aluminium housing was
`explained_partly: interference_error` at its +-20 um), or one whose model predicts a measured
column worse on held-out blocks than the model before it beyond the noise
(`heldout.worse_columns`: Holm over the columns, a minimum size), is never claimed: the first
such cause makes the verdict `unexplained` (`at_bound` / `worse_columns` say why), a later one
is not accepted (the causes before it stay), and a final joint model that pushes an accepted
cause to its bound claims nothing. A model form fitted at the edge of its stated scatter
(`scatter_edge`: a material lot at +-5 %) is one case of the rule. Each accepted cause is listed
in order with its own held-out gain: the held-out RMSE of the model with it against the model
before it, per column, under the noise of its pass.

A further cause must fit every held-out block in the same amount (`compensates`,
`blockscale.block_scale`): per block, the least-squares scale of its held-out change
against the model before it, and Cochran's Q of those scales (chi-square on blocks - 1 degrees
of freedom when the cause is there); with p below alpha_joint and Q above its degrees of
freedom by more than clear_chi2 it is not claimed and the causes before it stay. Two listed
causes can compose one outside the list, the second correcting the first's form error: an
inner groove curvature ratio of 0.54 on seed 000's steady grid, torque alone, was `explained`
as a path compliance plus a radial gradient whose change the cold blocks wanted about 2 times
and the hot ones 0.2-0.4 times (Q 117 and 273 on 7 degrees of freedom), while the further
cause of a true pair has Q at most 22.5 on 9 (the lag and settling reference, the pairs made
another way: docs/diagnosis.md, "Two listed causes composing an unlisted one").

A first cause refused for the sensor drift (`select_past_drift`): a second cause that
changes in time (a solid-film run-in at constant speed, a preload settling on the first
excursion) is what a zero drift of the sensors linear in time imitates, so the first pass's best
candidate, though it adds to the drift, is refused because the drift adds to it. Then the best is
taken as a provisional first cause and the selection runs as above; the causes are claimed only
when a further cause is accepted and the model of all of them clearly beats the drift itself
(the same joint test as for one cause), else the first pass's `unexplained` stands (a true
sensor drift: the causes do not add to it).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from studies.diagnosis import fitspec
from studies.diagnosis.blockscale import BlockScale, block_scale
from studies.diagnosis.calibration import baseline_noise, calibrate
from studies.diagnosis.candidate import HeldoutGain
from studies.diagnosis.core import Fit, ModelFailure
from studies.diagnosis.detection import ColumnDetection, below, detection
from studies.diagnosis.goodness import AtBound, GoodnessOfFit, Left, at_bound, goodness
from studies.diagnosis.heldout import WorseColumn, worse_columns
from studies.diagnosis.ladder import AlloyOffSheet, FormShare, MaterialLot, is_form
from studies.diagnosis.sleeve_rung import SleeveForm
from studies.diagnosis.problem import Accepted, Noise, Problem
from studies.diagnosis.stats import auto_blocks
from studies.diagnosis.generalised import kin_of
from studies.model.effects.generalised import forms_of

#: most causes accepted in one diagnosis
MAX_CAUSES = 3
#: relative drop of a column's noise level (re-estimated from the first cause's residual) above
#: which the first pass's noise counts as inflated by the effect (a further pass is run)
NOISE_RTOL = 0.2


@dataclass(frozen=True)
class AcceptedCause:
    """One accepted cause (an entry of `causes` in diagnosis.json): the listed effect, the
    generalised form when one explains it, the step of the selection (1 = first), the verdict
    of its pass, its parameters (in the model of every accepted cause) and their uncertainty
    (at its own step), its own held-out gain per column (held-out RMSE with it / before it)
    and the bootstrap of that gain (noise units), delta BIC and likelihood-ratio p against the
    model before it, and the noise level of its pass."""
    effect: str
    form: str | None
    step: int
    verdict: str
    parameters: dict[str, float]
    parameter_uncertainty: dict
    heldout_rmse_ratio: dict[str, float]
    heldout_gain: HeldoutGain | None
    delta_bic: float | None
    p_lr: float | None
    noise_sigma: dict[str, float]
    kind: str = "effect"


@dataclass(frozen=True)
class Selection:
    """The forward selection's outcome: the final verdict (with causes), the accepted causes
    in order, reasons, what is left, parameters at a bound, the final goodness of fit, the
    joint model of several causes (RMSE per column in-sample and held-out, predictions) and
    the passes run."""
    verdict: str | None = None
    causes: list[AcceptedCause] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    left: list[Left] = field(default_factory=list)
    at_bound: list[AtBound] = field(default_factory=list)
    goodness: GoodnessOfFit | None = None
    rmse: dict[str, float] | None = None
    heldout_rmse: dict[str, float] | None = None
    pred: dict | None = None
    passes: int = 1
    noise: Noise | None = None          # the last pass's noise model
    #: candidates stopped by the claim rules: a column made worse on held-out blocks
    worse_columns: list[WorseColumn] = field(default_factory=list)
    #: the claimed model's problem, fit and held-out residuals (the predictive interval's)
    problem: Problem | None = None
    fit: Fit | None = None
    heldout_z: np.ndarray | None = None
    #: per compared column, the smallest change the data could show and the change the
    #: configured model leaves (`detection.detection`, noise units)
    detection: dict[str, ColumnDetection] = field(default_factory=dict)


def _extended(p) -> tuple[Fit, np.ndarray, object]:
    """A pass's extended fit, its held-out residuals and the accepted effect object."""
    if p.chosen:
        return p.chosen.fit, p.chosen.heldout_z, p.chosen.form
    c = p.decision.cause
    return p.fits[c], p.heldout[c], p.pb.effect(c)


def _cause(p, step: int) -> AcceptedCause:
    """The cause a pass accepted (module docstring)."""
    fit, ho, eff = _extended(p)
    name = p.decision.cause
    cand = p.candidates[name]
    before = p.pb.col_rmse(p.baseline.heldout_z)
    after = p.pb.col_rmse(ho)
    ratio = {c: after[c] / before[c] if before[c] > 0 else 1.0 for c in p.pb.columns}
    if p.chosen:
        e = p.chosen.entry
        own = p.pb.effect(name).parameters
        params = {q: v for q, v in e.parameters.items() if q in own}
        unc = {q: v for q, v in e.parameter_uncertainty.items() if q in own}
        gain = e.heldout_gain_vs_baseline
    else:
        params, unc, gain = dict(cand.parameters), dict(cand.uncertainty), cand.heldout_gain
    return AcceptedCause(name, p.chosen.entry.name if p.chosen else None, step,
                         p.decision.verdict, params, unc, ratio, gain, cand.delta_bic,
                         cand.p_lr, dict(p.pb.noise.sigma), cand.kind)


def _next_problem(p) -> Problem:
    """The problem of the next pass: the pass's cause joins the accepted ones (every accepted
    cause at its value in this pass's fit), its family leaves the candidates, the nuisance
    starts at this fit's values."""
    fit, _, eff = _extended(p)
    pb = p.pb
    effects, nuis = fit.space.unpack(fit.u)
    base = tuple(Accepted(a.effect, dict(effects[a.effect.name]), a.free) for a in pb.base)
    base += (Accepted(eff, dict(effects[eff.name]), tuple(pb.free_params(eff))),)
    fam = p.decision.cause
    cands = tuple(e for e in pb.candidates
                  if e.name != fam and getattr(e, "family", e.name) != fam)
    nu = pb.nuisance
    x0 = np.clip(np.array([nuis[n] for n in nu.names], float), nu.lo, nu.hi)
    blocks = auto_blocks(pb.n, int(pb.th["n_blocks"])) if pb.auto_blocks else pb.blocks
    nxt = replace(pb, base=base, candidates=cands, nuisance=replace(nu, x0=x0), blocks=blocks)
    # the first fit of the next calibration already with the noise of what the accepted causes
    # leave (a noise inflated by the cause, e.g. AR(1) rho 0.99, makes that fit ill-conditioned)
    return replace(nxt, noise=baseline_noise(nxt, fit.pred))


def noise_inflated(pb: Problem, fit: Fit) -> bool:
    """Is the noise level the pass used more than NOISE_RTOL above the one estimated from the
    residual of `fit` (its cause taken out) in some column?"""
    new = baseline_noise(pb, fit.pred)
    return any(new.sigma[c] < (1.0 - NOISE_RTOL) * pb.noise.sigma[c] for c in pb.columns
               if c not in pb.noise.given)


def _n_params(pb: Problem, fit: Fit) -> int:
    return int(fit.u.size)


def _misfit(pb: Problem, b) -> bool:
    """Does the calibrated model of the accepted causes miss the data beyond the re-estimated
    noise (chi-square or held-out RMSE against it, `goodness`, at alpha_structure)?"""
    g = goodness(pb, b.fit, b.heldout_z, _n_params(pb, b.fit), b.residuals)
    return g.p_adjusted < pb.th["alpha_structure"]


def _alternatives(pb: Problem, a: Accepted, nxt) -> list[tuple[object, list[dict]]]:
    """The other forms of accepted cause `a`, each (form, its starting values): its family's
    generalised forms from its reducing value (`GeneralisedForm.from_listed`), and those of
    its kin (`generalised.kin_of`: the rung's are the lags' forms) from the kin's listed fit of
    pass `nxt` (its off value when not fitted) and the fit specification's extra starts
    (`fitspec.extra_starts`: the series lag's grid), bounded as their listed effects are."""
    own = getattr(a.effect, "family", "") or a.effect.name
    listed = {e.name: e for e in pb.candidates}
    out = []
    for fam in (own, *kin_of(own)):
        e = a.effect if fam == own else listed.get(fam)
        if e is None:
            continue
        c = nxt.candidates.get(fam) if fam != own else None
        vals = dict(a.values) if fam == own else (
            dict(c.parameters) if c is not None and c.parameters else dict(e.off))
        for form in forms_of(fam):
            if form.name == a.effect.name or form.applicable(pb.conditions) is not None:
                continue
            form = form.with_bounds(**{q: e.bounds[q] for q in form.parameters
                                       if q in e.bounds})
            x0 = form.from_listed(vals)
            extra = [] if fam == own else fitspec.extra_starts(form, vals, pb.conditions)
            out.append((form, [x0] + [{**x0, **x} for x in extra]))
    return out


#: local fits per other form of an accepted cause (`_alternative_fits`): from its starts of
#: lowest chi-square (one model call each)
N_ALTERNATIVE_FITS = 2


def _alternative_fits(pb: Problem, nxt) -> list[tuple[str, str, Problem, Fit]]:
    """Per accepted cause and other form of it (`_alternatives`): (form, the cause it replaces,
    the problem with the form in the cause's place, its best fit with the other accepted
    causes and the nuisance under the same noise, from its N_ALTERNATIVE_FITS best starts)."""
    out = []
    for i, a in enumerate(pb.base):
        for form, starts in _alternatives(pb, a, nxt):
            qs = [replace(pb, base=pb.base[:i] + (Accepted(form, v, tuple(pb.free_params(form))),)
                          + pb.base[i + 1:]) for v in starts]
            if len(qs) > N_ALTERNATIVE_FITS:
                chi2 = []
                for q in qs:
                    sp = q.space([])
                    try:
                        z, _ = q.eval(sp, np.zeros(sp.lo.size))
                    except ModelFailure:
                        z = np.array([np.inf])
                    chi2.append(float(z @ z))
                qs = [qs[k] for k in np.argsort(chi2, kind="stable")[:N_ALTERNATIVE_FITS]
                      if np.isfinite(chi2[k])]
            best = None
            for q in qs:
                sp = q.space([])
                try:
                    f = q.fit(sp, np.zeros(sp.lo.size))
                except ModelFailure:
                    continue
                if best is None or f.chi2 < best[1].chi2:
                    best = (q, f)
            if best is not None:
                out.append((form.name, a.effect.name, *best))
    return out


def _own_form_fits_as_well(pb: Problem, nxt, alts) -> tuple[str, str] | None:
    """(form, the accepted cause it replaces) for a generalised form of an accepted cause or of
    its kin (`alts`: `_alternative_fits`) that, in that cause's place, fits the data about as
    well as the accepted causes plus the further cause of pass `nxt` (chi-square within
    `clear_chi2` of it), or None: a further cause must clearly beat the accepted causes' own
    other forms, else what it fits is the misfit of their listed form (a part-by-part lag from
    the transient FE is one lag of another form, not a lag plus a second cause)."""
    fit_c = _extended(nxt)[0]
    for form, cause, _, f in alts:
        if f.chi2 <= fit_c.chi2 + pb.th["clear_chi2"]:
            return form, cause
    return None


def _wanted_only_by_its_form(pb: Problem, nxt, alts) -> tuple[str, str, float] | None:
    """(form, the accepted cause it replaces, chi-square the further cause gains with it) for
    another form of an accepted cause (`alts`) that fits at least about as well as the accepted
    causes (chi-square within `clear_chi2` of the pass's baseline) and with which the further
    cause of pass `nxt`, fitted beside it, gains less than `clear_chi2`; else None. Such a
    further cause compensates the accepted form's own error, not a cause of its own: on
    `network_lag` (a two-node network) a 0.355 um/kN path compliance took 70 from the rung's
    581.7, while beside `thermal_lag.series` (572.5, at the network's time constants) it fitted
    at 1e-13 um/kN and gained nothing."""
    fit_c, _, eff = _extended(nxt)
    # the further cause from its fit in pass `nxt`, a profiled parameter held there (as in the
    # joint fits of `decision.compare`)
    fixed = ({eff.name: {p: (fit_c.profile_value if fit_c.profile_value is not None
                             else fit_c.space.fixed[eff.name][p]) for p in fitspec.profile(eff)}}
             if fitspec.profile(eff) else {})
    clear = pb.th["clear_chi2"]
    for form, cause, q, f in alts:
        if f.chi2 > nxt.baseline.fit.chi2 + clear:
            continue
        sp = q.space([eff], fixed)
        u0 = np.concatenate([fit_c.u[:fit_c.space.k], f.u])
        try:
            f2 = q.fit(sp, u0 if u0.size == sp.lo.size else np.zeros(sp.lo.size))
        except ModelFailure:
            continue
        gain = f.chi2 - f2.chi2
        if gain < clear:
            return form, cause, gain
    return None


def scatter_edge(pb: Problem, bound: list[AtBound]) -> list[AtBound]:
    """The entries of `bound` that are a model form's parameter at the edge of its stated
    scatter (`material_lot`'s CTE factor at 1 +- 5 %, `unlogged_load` at the static rating): the
    form is defined inside that range, so a fit at its edge says the data want a lot or a load
    outside the data sheet, i.e. not this form (a 2 mm steel sleeve, which the config
    lacks, was `explained: material_lot` with the housing's factor at 1.05). A switch's `share`
    at 1 is the form itself, not an edge."""
    out = []
    for x in bound:
        e = next((e for e in pb.candidates if e.name == x.effect), None) or next(
            (a.effect for a in pb.base if a.effect.name == x.effect), None)
        if e is not None and is_form(e) and not isinstance(e, FormShare):
            out.append(x)
    return out


def blocked(p) -> tuple[list[AtBound], list[WorseColumn]]:
    """Why the cause a pass would accept cannot be claimed (empty lists: it can): its
    parameters the data want at or beyond a bound (`goodness.at_bound`),
    and the measured columns its extended model predicts worse on held-out blocks than the
    pass's baseline beyond the noise (`heldout.worse_columns`, over the blocks that test it)."""
    fit, ho, _ = _extended(p)
    return (at_bound(p.pb, fit),
            worse_columns(p.pb, p.decision.cause, p.baseline.heldout_z, ho, _testing_blocks(p)))


def _testing_blocks(p) -> np.ndarray:
    """The held-out blocks that test the cause a pass would accept (True), i.e. all but those
    its held-out refit could not test (`heldout_untestable`: a one-off trigger in the block)."""
    keep = np.ones(p.pb.n_blocks, bool)
    if not p.chosen:
        for u in p.candidates[p.decision.cause].heldout_untestable or []:
            keep[u["block"] - 1] = False
    return keep


def compensates(p) -> BlockScale | None:
    """The block-by-block amount of the further cause a pass would accept
    (`blockscale.block_scale`: its held-out change against the model before it, over the blocks
    that test it) when the blocks clearly want it in different amounts (Cochran's Q with p
    below alpha_joint and above its degrees of freedom by more than clear_chi2, as a rival is
    beaten outright), else None: such a cause compensates the misfit of the causes before it and
    is not claimed (module docstring). The margin: a strong cause's per-block amounts carry more
    than their noise, the parameter error of the other blocks' refit and the model's own form
    slop (a 4 um fit error with a 1500 s lag, both listed and present, 48 standard errors: Q
    22.5 on 9 degrees of freedom, p 0.0075; the unlisted groove's pair: Q 117 and 273 on 7)."""
    _, ho, _ = _extended(p)
    bs = block_scale(p.pb, p.decision.cause, p.baseline.heldout_z, ho, _testing_blocks(p))
    th = p.pb.th
    clear = bs is not None and bs.p < th["alpha_joint"] and bs.q > bs.dof + th["clear_chi2"]
    return bs if clear else None


def sleeve_lookalike(p) -> str | None:
    """Why the sleeve rung (`sleeve_rung.SleeveForm`) a pass would accept cannot be claimed over
    a housing alloy off its data sheet (`ladder.AlloyOffSheet`, CTE factors +-20 %), or None: a
    sleeve the drawing lacks makes the outer rings' seat follow the temperature as a housing of
    another CTE would (a 1.5 mm 17-4PH sleeve in seed 000's TC4 housing as a housing CTE 6 %
    high), so the sleeve is claimed only when that look-alike, fitted in its place with the
    nuisance, is worse by more than `clear_chi2` (as a rival a candidate clearly beats)."""
    name = p.decision.cause
    if not isinstance(p.pb.effect(name), SleeveForm):
        return None
    fit_s = _extended(p)[0]
    alloy = AlloyOffSheet()
    pb = p.pb
    space = pb.space([alloy])
    nu = fit_s.u[fit_s.space.k + len(fit_s.space.base_params):]
    starts = [np.concatenate([np.zeros(space.k), nu])]
    lot = p.fits.get(MaterialLot.name)
    if lot is not None and lot.space.k == space.k:
        starts.append(np.concatenate([lot.u[:space.k], nu]))
    best = None
    for u0 in starts:
        try:
            f = pb.fit(space, u0)
        except ModelFailure:
            continue
        best = f if best is None or f.chi2 < best.chi2 else best
    if best is None or best.chi2 > fit_s.chi2 + pb.th["clear_chi2"]:
        return None
    vals = space.unpack(best.u)[0][alloy.name]
    form = p.pb.effect(name).text(p.candidates[name].parameters)
    return (f"{name} ({form}) is not claimed: a housing alloy off its data sheet (CTE x "
            f"{vals['cte_factor_housing']:.3f}, shaft x {vals['cte_factor_shaft']:.3f}) fits "
            f"about as well (chi-square {best.chi2 - fit_s.chi2:+.1f}, a clear win needs more "
            f"than {pb.th['clear_chi2']:g}): check the drawing for a sleeve or measure the "
            "housing's CTE (dilatometer, ASTM E228)")


def not_claimed(name: str, bound: list[AtBound], worse: list[WorseColumn], form: bool) -> str:
    """The sentence of a cause the claim rules stop (`blocked`)."""
    why = []
    if bound:
        why.append("a parameter at its bound (" + "; ".join(x.text for x in bound)
                   + "): the data want more than the candidate allows, which is evidence "
                   "against it, not a partial explanation")
    if worse:
        why.append("it makes a measured column worse (" + "; ".join(x.text for x in worse)
                   + ")")
    tail = (": a part or a lot the file lacks that acts the same way (a sleeve, a lot outside "
            "the data sheet) would" if form and bound else "")
    return f"{name} carries the weight but is not claimed: " + " and ".join(why) + tail


# ============================================================================ the claim rules
# `select` reads the rules below in order: first the rules on the first pass (FIRST_RULES: the
# first that answers decides), then, while no stop rule holds (STOP_RULES), another pass and
# the rules on its further cause (FURTHER_RULES: the first that answers decides whether the
# search goes on), then the rules on the model of the accepted causes (FINAL_RULES). One small
# function per rule; docs/diagnosis.md, "The claim rules", gives each one's reason.

CLAIMS = ("explained", "explained_partly")


def below_detection(first, det: dict[str, ColumnDetection]) -> Selection | None:
    """Rule 1: the change the configured model leaves is below the smallest change the data
    could show in every compared column (`detection`, computed from the calibration before any
    fit): `no_discrepancy`, whatever fits."""
    if not below(det):
        return None
    cols = "; ".join(f"{c} {d.change_sigma:.2g} sigma RMS (threshold {d.threshold_sigma:.2g})"
                     for c, d in det.items())
    return Selection(verdict="no_discrepancy", reasons=[
        "the change the configured model leaves is below the smallest change these data could "
        f"show in every column ({cols}): no discrepancy is claimed, whatever fits"],
        goodness=first.decision.goodness, noise=first.pb.noise)


def not_a_claim(first, det) -> Selection | None:
    """Rule 2: the first pass claims nothing (`no_discrepancy`, `ambiguous`, `unexplained`):
    its verdict stands (an empty selection)."""
    return None if first.decision.verdict in CLAIMS else Selection()


def claim_blocked(first, det) -> Selection | None:
    """Rule 3: the first cause has a parameter the data want at or beyond its bound, or makes a
    measured column worse on held-out blocks (`blocked`): `unexplained`, with why."""
    bound, worse = blocked(first)
    if not (bound or worse):
        return None
    name = first.decision.cause
    return Selection(verdict="unexplained", reasons=[not_claimed(
        name, bound, worse, is_form(first.pb.effect(name)))], at_bound=bound,
        worse_columns=worse, goodness=first.decision.goodness, noise=first.pb.noise)


def sleeve_not_clear(first, det) -> Selection | None:
    """Rule 4: a sleeve rung that a housing alloy off its data sheet fits about as well
    (`sleeve_lookalike`): `unexplained`."""
    alike = sleeve_lookalike(first)
    if not alike:
        return None
    return Selection(verdict="unexplained", reasons=[alike],
                     goodness=first.decision.goodness, noise=first.pb.noise)


FIRST_RULES = (below_detection, not_a_claim, claim_blocked, sleeve_not_clear)


@dataclass
class _Search:
    """The forward selection in progress: the pass whose cause was accepted last (`cur`), the
    accepted causes, reasons, passes run, what stopped a further cause at a bound or for a
    worse column, and the model the final rules judge (problem, fit, held-out residuals, its
    goodness)."""
    first: object
    run_pass: Callable
    cur: object
    causes: list[AcceptedCause]
    reasons: list[str] = field(default_factory=list)
    passes: int = 1
    stopped_bound: list[AtBound] = field(default_factory=list)
    stopped_worse: list[WorseColumn] = field(default_factory=list)
    final: GoodnessOfFit | None = None
    final_pb: Problem | None = None
    final_fit: Fit | None = None
    final_ho: np.ndarray | None = None
    _next: Problem | None = None

    @classmethod
    def start(cls, first, run_pass) -> "_Search":
        fit, ho, _ = _extended(first)
        return cls(first, run_pass, first, [_cause(first, 1)], final=first.decision.goodness,
                   final_pb=first.pb, final_fit=fit, final_ho=ho)

    @property
    def next_problem(self) -> Problem:
        """The problem of the next pass (`_next_problem` of `cur`, made once per cause)."""
        if self._next is None:
            self._next = _next_problem(self.cur)
        return self._next

    @property
    def names(self) -> str:
        return ", ".join(c.effect for c in self.causes)

    def judge_baseline_of(self, p) -> None:
        """The final model is pass `p`'s baseline (the accepted causes without its cause)."""
        b = p.baseline
        self.final = goodness(p.pb, b.fit, b.heldout_z, _n_params(p.pb, b.fit), b.residuals)
        self.final_pb, self.final_fit, self.final_ho = p.pb, b.fit, b.heldout_z


# ---------------------------------------------------------------- stop rules (before a pass)
def enough_causes(s: _Search) -> bool:
    """Stop after MAX_CAUSES causes."""
    return len(s.causes) >= MAX_CAUSES


def no_candidates_left(s: _Search) -> bool:
    """Stop when no candidate is left for a further pass."""
    return not s.next_problem.candidates


def last_cause_at_bound(s: _Search) -> bool:
    """Stop after a cause at its bound: what it leaves is the data wanting more of it, not a
    further cause (another candidate would only imitate its excess)."""
    return bool(at_bound(s.cur.pb, _extended(s.cur)[0]))


def form_chosen(s: _Search) -> bool:
    """Stop after a cause accepted in a generalised form: its listed form left structure, and
    what the form leaves is its own mismatch, which other candidates imitate (a transient FE's
    part-by-part lags took a 0.6 um fit error as a second cause)."""
    return s.cur.chosen is not None


def sleeve_accepted(s: _Search) -> bool:
    """Stop after a sleeve: its variants are a short list of materials and two
    thicknesses; what it leaves is its own mismatch, which a material lot imitated as a second
    cause (a 2 mm 9Cr18 sleeve as a 1.5 mm 17-4PH one plus a housing lot)."""
    return isinstance(s.cur.pb.effect(s.cur.decision.cause), SleeveForm)


def explained_at_its_noise(s: _Search) -> bool:
    """Stop when the cause was `explained` (no structure left) and the noise level estimated
    from its residual is within NOISE_RTOL of the one its pass used (nothing was hiding under
    an inflated noise)."""
    return (s.cur.decision.verdict == "explained"
            and not noise_inflated(s.cur.pb, _extended(s.cur)[0]))


STOP_RULES = (enough_causes, no_candidates_left, last_cause_at_bound, form_chosen,
              sleeve_accepted, explained_at_its_noise)


def leaves_nothing(pb_c: Problem, b_c) -> bool:
    """Does the model of the accepted causes, calibrated with the noise re-estimated from its
    residual (`pb_c`, `b_c`: `calibration.calibrate` of the next problem), show no structure,
    white noise and no misfit?"""
    white = not any(v > 0.0 for v in pb_c.noise.rho.values())
    return white and not b_c.structure and not _misfit(pb_c, b_c)


def cause_explains_at_its_noise(p) -> bool:
    """Does the cause of pass `p` (its decision's cause, the chosen form when there is one),
    which leaves no structure under the pass's noise, leave none under the noise re-estimated
    from its own residual? Yes when that noise is not NOISE_RTOL below the pass's
    (`noise_inflated`), else when the model with the cause accepted, calibrated under it, leaves
    nothing (`leaves_nothing`): a lag's misfit taken for noise (AR(1) rho 0.99) hides what the
    lag leaves."""
    if not noise_inflated(p.pb, _extended(p)[0]):
        return True
    return leaves_nothing(*calibrate(_next_problem(p)))


def nothing_left(s: _Search, pb_c: Problem, b_c) -> bool:
    """Stop when the model of the accepted causes, calibrated with the noise re-estimated from
    its residual, shows no structure and white noise (no candidate is fitted again); it is then
    the model the final rules judge."""
    if not leaves_nothing(pb_c, b_c):
        return False
    s.final = goodness(pb_c, b_c.fit, b_c.heldout_z, _n_params(pb_c, b_c.fit), b_c.residuals)
    s.final_pb, s.final_fit, s.final_ho = pb_c, b_c.fit, b_c.heldout_z
    return True


# ---------------------------------------------------------------- rules on a further cause
# each (search, pass, calibrated problem) -> None (does not apply), True (accepted: search on)
# or False (not accepted: stop, the causes before it stay)
def own_form_further(s: _Search, nxt, pb_c: Problem) -> bool | None:
    """A generalised form of an accepted cause or of its thermal kin fits what is left about as
    well as the further cause (`_own_form_fits_as_well`): the structure left is that cause's
    other form; or the further cause is wanted only beside the accepted cause's listed form,
    not beside another form of it that fits as well (`_wanted_only_by_its_form`)."""
    d = nxt.decision
    if d.verdict not in CLAIMS:
        return None
    alts = _alternative_fits(pb_c, nxt)
    alt = _own_form_fits_as_well(pb_c, nxt, alts)
    if alt is not None:
        form, cause = alt
        s.reasons.append(f"with {s.names} in the model, {d.cause} fits what is left, but so "
                         f"does {form} in place of {cause}: the structure left is that "
                         "cause's other form, not a further cause")
        s.judge_baseline_of(nxt)
        return False
    only = _wanted_only_by_its_form(pb_c, nxt, alts)
    if only is None:
        return None
    form, cause, gain = only
    clear = pb_c.th["clear_chi2"]
    s.reasons.append(f"with {s.names} in the model, {d.cause} fits what is left, but beside "
                     f"{form} in place of {cause}, which fits as well, it gains only "
                     f"chi-square {max(gain, 0.0):.1f} (a clear gain needs {clear:g}): "
                     f"it compensates the error of {cause}'s form, not a further cause")
    s.judge_baseline_of(nxt)
    return False


def further_blocked(s: _Search, nxt, pb_c: Problem) -> bool | None:
    """The further cause is at its bound or makes a column worse (`blocked`, as rule 3)."""
    d = nxt.decision
    if d.verdict not in CLAIMS:
        return None
    nb, nw = blocked(nxt)
    if not (nb or nw):
        return None
    s.reasons.append(f"with {s.names} in the model, "
                     + not_claimed(d.cause, nb, nw, is_form(nxt.pb.effect(d.cause))))
    s.stopped_bound, s.stopped_worse = nb, nw
    s.judge_baseline_of(nxt)
    return False


def further_compensates(s: _Search, nxt, pb_c: Problem) -> bool | None:
    """The held-out blocks clearly want the further cause in different amounts
    (`compensates`): it compensates the misfit of the causes before it."""
    if nxt.decision.verdict not in CLAIMS:
        return None
    comp = compensates(nxt)
    if comp is None:
        return None
    s.reasons.append(f"with {s.names} in the model, {nxt.decision.cause} is not claimed as a "
                     f"further cause: {comp.text}")
    s.judge_baseline_of(nxt)
    return False


def further_accepted(s: _Search, nxt, pb_c: Problem) -> bool | None:
    """A further cause the pass explains (as the first) and no rule above stops: accepted."""
    d = nxt.decision
    if d.verdict not in CLAIMS:
        return None
    s.causes.append(_cause(nxt, len(s.causes) + 1))
    s.reasons.append(f"with {', '.join(c.effect for c in s.causes[:-1])} in the model "
                     f"(noise re-estimated from its residual), {d.reasons[-1]}")
    s.cur, s.final, s._next = nxt, d.goodness, None
    s.final_pb, (s.final_fit, s.final_ho, _) = nxt.pb, _extended(nxt)
    return True


def further_none(s: _Search, nxt, pb_c: Problem) -> bool:
    """The pass accepts nothing (an ambiguous further cause, structure no candidate removes,
    or nothing left): the search stops with the causes before it."""
    s.judge_baseline_of(nxt)
    d = nxt.decision
    if d.verdict == "ambiguous":
        s.reasons.append(f"with {s.names} in the model a further cause is ambiguous: "
                         f"{d.cause} or {', '.join(d.rivals)}")
    elif d.verdict == "unexplained" and s.final.leaves_structure:
        s.reasons.append(f"with {s.names} in the model (noise re-estimated from its residual) "
                         "structure is left that no other candidate removes")
    return False


FURTHER_RULES = (own_form_further, further_blocked, further_compensates, further_accepted,
                 further_none)


# ---------------------------------------------------------------- rules on the final model
def _joint(s: _Search) -> Selection:
    """The selection's common part; with several causes their parameters in the joint model
    and its RMSE per column (in-sample, held-out) and predictions."""
    sel = Selection(passes=s.passes, worse_columns=s.stopped_worse, problem=s.final_pb,
                    fit=s.final_fit)
    if len(s.causes) > 1:
        effects, _ = s.final_fit.space.unpack(s.final_fit.u)
        fam = {c.effect: (c.form or c.effect) for c in s.causes}
        s.causes = [replace(c, parameters={q: effects[fam[c.effect]][q] for q in c.parameters})
                    for c in s.causes]
        sel = replace(sel, rmse=s.final_pb.col_rmse(s.final_fit.z),
                      heldout_rmse=s.final_pb.col_rmse(s.final_ho), pred=s.final_fit.pred)
    return sel


def joint_at_bound(s: _Search, sel: Selection) -> Selection | None:
    """The model of the accepted causes, refitted together, pushes one to its bound (as rule
    3): nothing is claimed."""
    bound = at_bound(s.final_pb, s.final_fit)
    if not bound:
        return None
    form = len(s.causes) == 1 and is_form(s.first.pb.effect(s.causes[0].effect))
    return replace(sel, verdict="unexplained", reasons=s.reasons + [not_claimed(
        s.names, bound, [], form)], goodness=s.final, noise=s.final_pb.noise,
        at_bound=bound + s.stopped_bound)


def one_cause_leaves_structure(s: _Search, sel: Selection) -> Selection | None:
    """A single cause that leaves structure, no parameter at a bound: it may be a look-alike
    of a cause outside the list (`unexplained`, it is the best partial candidate)."""
    if len(s.causes) > 1 or not s.final.leaves_structure:
        return None
    left = "; ".join(x.text for x in s.final.left)
    return replace(sel, verdict="unexplained", reasons=s.reasons + [
        f"{s.causes[0].effect} carries the weight but leaves structure ({left}) and none of "
        "its parameters is at a bound: the structure may come from a cause outside the "
        "list, which the best candidate only imitates"], goodness=s.final,
        noise=s.final_pb.noise, at_bound=s.stopped_bound)


def causes_claimed(s: _Search, sel: Selection) -> Selection:
    """Otherwise the causes are claimed: `explained` when their model leaves no structure under
    the last noise estimate, else `explained_partly` with what is left."""
    reasons = list(s.reasons)
    verdict = "explained_partly" if s.final.leaves_structure else "explained"
    if verdict == "explained" and s.first.decision.verdict == "explained_partly":
        reasons.append("the structure left under the first noise estimate is noise once the "
                       "noise is estimated from the residual of the accepted causes")
    if verdict == "explained_partly" and s.final.left:
        reasons.append("left: " + "; ".join(x.text for x in s.final.left))
    return replace(sel, verdict=verdict, causes=s.causes, reasons=reasons,
                   left=list(s.final.left), at_bound=s.stopped_bound, goodness=s.final,
                   noise=s.final_pb.noise, problem=s.final_pb, fit=s.final_fit,
                   heldout_z=s.final_ho)


FINAL_RULES = (joint_at_bound, one_cause_leaves_structure, causes_claimed)


def select(first, run_pass: Callable) -> Selection:
    """Forward selection after the first pass `first` (module docstring), by the claim rules in
    order (FIRST_RULES, STOP_RULES with `nothing_left`, FURTHER_RULES, FINAL_RULES);
    `run_pass(problem, step, calibrated)` runs phases 1-5b on a problem (phase 1 already done:
    `calibrated`) and returns its pass. The detection of the first pass's calibration
    (`detection.detection`) is in the selection whatever the verdict."""
    det = detection(first.pb, first.baseline.fit.z, len(first.pb.nuisance.names))
    for rule in FIRST_RULES:
        sel = rule(first, det)
        if sel is not None:
            return replace(sel, detection=det)
    s = _Search.start(first, run_pass)
    while not any(rule(s) for rule in STOP_RULES):
        pb_c, b_c = calibrate(s.next_problem)
        if nothing_left(s, pb_c, b_c):
            break
        nxt = run_pass(s.next_problem, len(s.causes) + 1, (pb_c, b_c))
        s.passes += 1
        if not next(r for r in (rule(s, nxt, pb_c) for rule in FURTHER_RULES) if r is not None):
            break
    sel = _joint(s)
    return replace(next(r for r in (rule(s, sel) for rule in FINAL_RULES) if r is not None),
                   detection=det)


def refused_for_drift(first) -> bool:
    """Was the first pass `unexplained` only because its best candidate did not clearly beat
    the unlisted sensor drift, with the drift adding to it (p of adding the drift below
    alpha_joint) while it adds to the drift (p below alpha_joint), and no rival? That is what a
    second cause that changes in time (a run-in at constant speed, a settling on the first
    excursion) does to the first: the drift takes up the second cause."""
    from studies.diagnosis.decision import refused_for_drift as refused

    d = first.decision
    return (refused(d, first.pb.th["alpha_joint"]) and first.candidates[d.best].fitted
            and d.best in first.passing)


def select_past_drift(first, run_pass: Callable):
    """Two causes where the first pass refused its best candidate for the sensor drift
    (`refused_for_drift`): the best is taken as a provisional first cause and the
    forward selection (`select`) runs; a claim is made only when it accepts a further cause and
    the model of the accepted causes clearly beats the drift itself (`decision.
    versus_sensor_drift` on that model, under its last noise estimate: adding the causes to the
    drift significant at alpha_joint, adding the drift to them not). Returns (the first pass
    with the provisional decision, the selection) or None (the first pass's verdict stands)."""
    from types import SimpleNamespace

    from studies.diagnosis.decision import SENSOR_DRIFT, versus_sensor_drift

    if not refused_for_drift(first):
        return None
    d = first.decision
    prov = replace(first, decision=replace(d, verdict="explained_partly", cause=d.best))
    sel = select(prov, run_pass)
    if len(sel.causes) < 2 or sel.fit is None:
        return None
    q = replace(sel.problem, base=())
    sp = q.space([])
    try:
        base = q.fit(sp, np.zeros(sp.lo.size))
    except ModelFailure:
        return None
    k = int(sel.fit.u.size - len(q.nuisance.names))
    drift = versus_sensor_drift(q, sel.fit, {"n_free": k, "n_bound": 0},
                                SimpleNamespace(fit=base))
    if drift is None or not drift.best_carries_weight:
        return None
    names = " and ".join(c.effect for c in sel.causes)
    reasons = [f"{d.best} alone did not clearly beat a zero drift of the sensors linear in "
               f"time, but with a further cause in the model the drift is not needed: "
               f"{names} together clearly beat the drift (adding them to it: p = "
               f"{drift.p:.2g}; adding it to them: p = {drift.p_add_other_to_best:.2g})"]
    prov = replace(prov, decision=replace(prov.decision, joint_fits={
        **d.joint_fits, SENSOR_DRIFT + " (against the accepted causes)": drift}))
    return prov, replace(sel, reasons=list(sel.reasons) + reasons)
