"""Claim rules that hold at any signal, one test (or more) per rule.

- the detection threshold (`studies.diagnosis.detection`) against a Monte Carlo of the test it
  is the minimum detectable effect of (an independent route: noise drawn, the F test counted);
  and on the closed-form toy bearing of `test_diagnosis_engine.py`: a change below it is not
  claimed, one well above it is (the real model on data made by plain simulate with another
  contact angle: `test_claim_rules_slow.py`);
- at a bound only where the data want the bound: the refusal rate of a weakly identified true
  cause (10 +- 8 on [-20, 20]) against the normal tail it must equal, with fits made by scipy's
  bounded least squares;
- exact bound comparisons over many random rescalings;
- the "worse column" test: its family-wise rate on nulls over many columns, and its minimum size;
- the rule table of `selection.select`, rule by rule on stand-in passes.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy import optimize, stats

from studies.diagnosis.core import Fit, Space
from studies.model.effects import EFFECTS

CLAIMS = ("explained", "explained_partly")


# ============================================================================ detection threshold
@pytest.mark.parametrize("nu", [120.0, None])
def test_detection_threshold_is_found_four_times_in_five(nu):
    """The threshold (240 entries, alpha 0.005, the noise level estimated on 120 degrees of
    freedom or given) is the RMS change the chi-square test finds with DETECTION_POWER: counted
    over 6000 draws of a change of that RMS plus unit Gaussian noise, the noise level's estimate
    an independent chi-square(nu) / nu (binomial standard error of the share 0.003; tolerance 4
    of them)."""
    from studies.diagnosis.detection import DETECTION_POWER, threshold_sigma

    n, alpha, draws = 240, 0.005, 6000
    delta = threshold_sigma(n, float(n), nu, alpha)
    rng = np.random.default_rng(42)
    shape = np.sin(np.linspace(0.0, 7.0, n))
    shape /= np.sqrt(np.mean(shape ** 2))                        # RMS 1
    z = delta * shape + rng.normal(size=(draws, n))
    stat = np.sum(z ** 2, axis=1) / n
    if nu is None:
        found = stat > stats.chi2.isf(alpha, n) / n
    else:
        found = stat / (rng.chisquare(nu, draws) / nu) > stats.f.isf(alpha, n, nu)
    se = np.sqrt(DETECTION_POWER * (1 - DETECTION_POWER) / draws)
    assert abs(found.mean() - DETECTION_POWER) < 4 * se, (delta, found.mean())
    assert 0.3 < delta < 1.2


def _toy_case(amount_um: float, rms_sigma: float, seed: int, n: int = 120):
    """Toy bearing data with an inner fit error of `amount_um`, the noise scaled so that the RMS
    change after the friction scale (bounded least squares of the scale alone, independent of
    the engine) is `rms_sigma` noise units in the column that changes most."""
    from test_diagnosis_engine import NUISANCE, SIGMA, ToyBearing, cycles

    model = ToyBearing()
    cond = cycles(n=n, dt=28800.0 / n)
    truth = model.evaluate(cond, {"interference_error": {"inner_um": amount_um,
                                                         "outer_um": 0.0}}, {"mu_scale": 1.2})

    def res(x):
        b = model.evaluate(cond, {}, {"mu_scale": float(x[0])})
        return np.concatenate([(truth[c] - b[c]) / SIGMA[c] for c in SIGMA])
    lo, hi = NUISANCE["mu_scale"][:2]
    x = optimize.least_squares(res, [1.2], bounds=([lo], [hi])).x
    r = res(x).reshape(len(SIGMA), n)
    k = float(np.max(np.sqrt(np.mean(r ** 2, axis=1)))) / rms_sigma
    rng = np.random.default_rng(seed)
    meas = {c: truth[c] + rng.normal(0.0, k * s, n) for c, s in SIGMA.items()}
    return model, cond, meas


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_change_below_the_detection_threshold_is_not_claimed(seed):
    """An inner fit error whose change after the friction scale is 0.75 sigma RMS (120 rows over
    8 h; the threshold there 1.24 sigma): `no_discrepancy` and no cause, whatever fits (before:
    `explained: interference_error`, the likelihood ratio on 240 entries finds it easily); the
    detection block states both numbers per column."""
    from test_diagnosis_engine import run_full

    model, cond, meas = _toy_case(4.0, 0.75, seed)
    r = run_full(model, cond, meas, candidates=["interference_error", "thermal_lag",
                                                "friction_temperature"])
    assert r.verdict == "no_discrepancy" and r.cause is None and not r.causes, (
        r.verdict, r.cause, r.reasons, r.detection)
    assert all(d.change_sigma < d.threshold_sigma for d in r.detection.values())
    from studies.diagnosis.result import to_json
    doc = to_json(r)["detection"]
    assert set(doc) == {"torque_Nmm", "preload_N"}
    assert all(set(v) == {"threshold_sigma", "change_sigma"} for v in doc.values())
    # nothing claimed, and still the configured model's interval in diagnosis.json and .csv
    from test_configured_interval import assert_written
    assert_written(r, meas)


def test_a_change_well_above_the_detection_threshold_is_still_claimed():
    """The same fit error at 4 sigma RMS: claimed as the fit error, its detection above."""
    from test_diagnosis_engine import run_full

    model, cond, meas = _toy_case(4.0, 4.0, 0)
    r = run_full(model, cond, meas, candidates=["interference_error", "thermal_lag",
                                                "friction_temperature"])
    assert r.verdict in CLAIMS and r.cause == "interference_error", (r.verdict, r.reasons)
    assert any(d.change_sigma > d.threshold_sigma for d in r.detection.values())


# ============================================================================ at a bound
def _linear_fit(A, y, lo, hi, effect="interference_error", param="inner_um", origin=0.0,
                scale=1.0):
    """The bounded least-squares fit (scipy `lsq_linear`, BVLS) of y = A theta + unit noise,
    theta = origin + scale u, as the diagnosis's `Fit` (z = y - A theta, J = dz/du)."""
    As = A * scale
    r = optimize.lsq_linear(As, y - A @ np.full(A.shape[1], origin), bounds=(lo, hi),
                            method="bvls")
    u = r.x
    z = y - A @ (origin + scale * u)
    space = Space([(effect, param)], {}, [], np.array([origin]), np.array([scale]),
                  np.array([lo], float), np.array([hi], float))
    return Fit(space, u, z, -As, float(z @ z), {})


def test_a_weakly_identified_cause_inside_its_bounds_is_refused_only_as_often_as_it_fits_beyond():
    """A true inner fit error of 10 um, standard uncertainty 8 um, bounds [-20, 20] um (issue
    42): a cause is refused for its bound only where the data want it at or beyond the bound,
    i.e. where the unbounded estimate lies beyond 20 um: P(N(10, 8) > 20) = 10.6 % (and 3.75
    sigma below -20). Counted over 1000 draws of bounded least-squares fits (binomial standard
    error 1 %; tolerance 3.5 %). Before: within one standard uncertainty of a bound refused it
    in P(N(10, 8) > 12) = 40 %."""
    from studies.diagnosis.goodness import at_bound

    n, sd, truth = 20, 8.0, 10.0
    A = np.full((n, 1), 1.0 / (sd * np.sqrt(n)))          # sum A^2 = 1 / sd^2
    pb = SimpleNamespace(candidates=[EFFECTS["interference_error"]], base=[])
    rng = np.random.default_rng(7)
    draws = 1000
    refused = sum(bool(at_bound(pb, _linear_fit(A, A[:, 0] * truth + rng.normal(size=n),
                                                -20.0, 20.0)))
                  for _ in range(draws))
    expect = stats.norm.sf(20.0, truth, sd) + stats.norm.cdf(-20.0, truth, sd)
    assert abs(refused / draws - expect) < 0.035, (refused / draws, expect)


def test_a_cause_the_data_push_beyond_its_bound_is_at_the_bound():
    """A true inner fit error of 30 um, +- 1 um, bounds [-20, 20]: on the bound in every draw,
    listed with the bound itself (20 exactly) and the tolerance-band sentence."""
    from studies.diagnosis.goodness import at_bound

    n = 20
    A = np.full((n, 1), 1.0 / np.sqrt(n))
    pb = SimpleNamespace(candidates=[EFFECTS["interference_error"]], base=[])
    rng = np.random.default_rng(3)
    for _ in range(50):
        hit = at_bound(pb, _linear_fit(A, A[:, 0] * 30.0 + rng.normal(size=n), -20.0, 20.0))
        assert [(b.parameter, b.bound) for b in hit] == [("inner_um", 20.0)]
        assert "more than the tolerance band allows" in hit[0].text


def test_bounds_are_compared_in_the_parameters_own_units():
    """A bound rescaled to the fit's coordinates and back (origin + scale x (b - origin) /
    scale) is not b for some origins and scales (counted below: the test exercises that). Over
    1000 random rescalings: the preload path's compliance at its soft bound is the
    `preload_spring` rung, never listed at a bound; a fit error pushed beyond its band is
    listed with the band's edge exactly (20.0, the effect's own number)."""
    from studies.diagnosis.goodness import at_bound

    rng = np.random.default_rng(11)
    comp = EFFECTS["preload_path_compliance"]
    b_hi = comp.bounds["extra_compliance_um_per_kN"][1]
    fe = EFFECTS["interference_error"]
    off_round_trip = 0
    for _ in range(1000):
        origin = float(rng.uniform(-1e3, 1e3))
        scale = float(10.0 ** rng.uniform(-3, 3))
        hi_u = (b_hi - origin) / scale
        off_round_trip += origin + scale * hi_u != b_hi
        J = np.zeros((5, 1))
        J[0, 0] = 1.0
        sp = Space([(comp.name, "extra_compliance_um_per_kN")], {}, [], np.array([origin]),
                   np.array([scale]), np.array([(0.0 - origin) / scale]), np.array([hi_u]))
        fit = Fit(sp, np.array([hi_u]), np.r_[-1.0, np.zeros(4)], J, 1.0, {})
        assert at_bound(SimpleNamespace(candidates=[comp], base=[]), fit) == []
        sp = Space([(fe.name, "inner_um")], {}, [], np.array([origin]), np.array([scale]),
                   np.array([(-20.0 - origin) / scale]), np.array([(20.0 - origin) / scale]))
        fit = Fit(sp, np.array([(20.0 - origin) / scale]), np.r_[-1.0, np.zeros(4)], J, 1.0, {})
        hit = at_bound(SimpleNamespace(candidates=[fe], base=[]), fit)
        assert [(b.parameter, b.bound) for b in hit] == [("inner_um", 20.0)]
    assert off_round_trip > 0


# ============================================================================ worse columns
def _columns_problem(m: int, n: int):
    """A problem of m measured columns of n rows (10 contiguous held-out blocks, unit noise
    given), for the held-out residual tests."""
    from studies.diagnosis.problem import make_problem

    cols = [f"c{j}_N" for j in range(m)]
    cond = {"time_s": np.arange(n, dtype=float)}
    return make_problem(lambda e, nu: {c: np.zeros(n) for c in cols},
                        {c: np.zeros(n) for c in cols}, cond, [], {"mu_scale": (0.5, 2.0)},
                        noise_sigma={c: 1.0 for c in cols})


def test_worse_columns_keeps_its_level_over_many_columns():
    """Nulls over 8 columns (the candidate's held-out residuals as good as the baseline's, both
    unit noise, 10 blocks): some column is called worse in at most the family level 2.5 % of
    400 draws (binomial 99 % upper quantile 18 at 2.5 %; each column tested at 2.5 %, some
    column in 15 % of the draws)."""
    from studies.diagnosis.heldout import worse_columns

    m, n = 8, 200
    pb = _columns_problem(m, n)
    rng = np.random.default_rng(5)
    hits = sum(bool(worse_columns(pb, "x", rng.normal(size=m * n), rng.normal(size=m * n)))
               for _ in range(400))
    assert hits <= stats.binom.ppf(0.99, 400, 0.025), hits


def test_worse_columns_needs_a_minimum_size():
    """One of two columns worse in every block by 0.05 noise units (held-out RMSE 1.05 against
    1: certain, but below the 0.1 minimum) is not called worse; by 0.3 it is, with its ratio."""
    from studies.diagnosis.heldout import worse_columns

    m, n = 2, 2000
    pb = _columns_problem(m, n)
    rng = np.random.default_rng(9)
    e = rng.normal(size=n)
    base = np.concatenate([e, rng.normal(size=n)])
    for extra, listed in ((0.05, False), (0.3, True)):
        cand = base.copy()
        cand[:n] = e * (1.0 + extra)
        w = worse_columns(pb, "x", base, cand)
        assert bool(w) == listed, (extra, w)
        if listed:
            assert w[0].column == "c0_N" and w[0].gain == pytest.approx(1.0 + extra, rel=1e-9)


# ============================================================================ the rule table
def _det(changes, threshold=1.0):
    from studies.diagnosis.detection import ColumnDetection
    return {c: ColumnDetection(c, threshold, v, 100, 100.0, 50.0, 0.005)
            for c, v in changes.items()}


def _first(verdict="explained", cause="a"):
    return SimpleNamespace(decision=SimpleNamespace(verdict=verdict, cause=cause, goodness=None),
                           pb=SimpleNamespace(noise=None))


def test_rule_below_detection():
    """Every column below its threshold: `no_discrepancy` whatever the first pass says; one
    column above: the rule does not apply."""
    from studies.diagnosis.selection import below_detection
    for verdict in ("explained", "ambiguous", "unexplained"):
        sel = below_detection(_first(verdict), _det({"t": 0.5, "p": 0.9}))
        assert sel.verdict == "no_discrepancy" and "below the smallest change" in sel.reasons[0]
    assert below_detection(_first(), _det({"t": 0.5, "p": 1.1})) is None


def test_rule_not_a_claim():
    """A first pass that claims nothing keeps its verdict (an empty selection)."""
    from studies.diagnosis.selection import not_a_claim
    for verdict in ("no_discrepancy", "ambiguous", "unexplained"):
        assert not_a_claim(_first(verdict), {}).verdict is None
    assert not_a_claim(_first("explained"), {}) is None


def test_rule_table_order():
    """The rules are read in order: the detection before the first pass's verdict, the claim
    rules before the sleeve's look-alike; the final rules end with the claim."""
    from studies.diagnosis import selection as s
    assert s.FIRST_RULES == (s.below_detection, s.not_a_claim, s.claim_blocked,
                             s.sleeve_not_clear)
    assert s.FINAL_RULES[-1] is s.causes_claimed and s.FURTHER_RULES[-1] is s.further_none


def _search(n_causes=1, chosen=None, verdict="explained", leaves=False, candidates=("b",)):
    from studies.diagnosis.selection import _Search
    cur = SimpleNamespace(chosen=chosen, decision=SimpleNamespace(verdict=verdict, cause="a"))
    s = _Search(first=SimpleNamespace(decision=SimpleNamespace(verdict=verdict)),
                run_pass=None, cur=cur,
                causes=[SimpleNamespace(effect=f"e{i}") for i in range(n_causes)],
                final=SimpleNamespace(leaves_structure=leaves, left=[]),
                final_pb=SimpleNamespace(noise="noise"))
    s._next = SimpleNamespace(candidates=list(candidates))
    return s


def test_stop_rules():
    """A further pass is not run after MAX_CAUSES causes, without candidates, or after a cause
    in a generalised form."""
    from studies.diagnosis import selection as s
    assert s.enough_causes(_search(s.MAX_CAUSES)) and not s.enough_causes(_search(1))
    assert s.no_candidates_left(_search(candidates=())) and not s.no_candidates_left(_search())
    assert s.form_chosen(_search(chosen=object())) and not s.form_chosen(_search())


def test_final_rules():
    """One cause leaving structure is not claimed (`unexplained`); several causes leaving
    structure are `explained_partly`; no structure left: `explained`."""
    from studies.diagnosis import selection as s
    sel = s.Selection()
    one = s.one_cause_leaves_structure(_search(1, leaves=True), sel)
    assert one.verdict == "unexplained" and "outside the list" in one.reasons[-1]
    assert s.one_cause_leaves_structure(_search(2, leaves=True), sel) is None
    assert s.causes_claimed(_search(2, leaves=True), sel).verdict == "explained_partly"
    assert s.causes_claimed(_search(1, leaves=False), sel).verdict == "explained"


def _pass_at(value_true: float):
    """A stand-in pass whose cause, the inner fit error, is fitted by bounded least squares to
    a truth of `value_true` um (+- 1 um) on [-20, 20] um."""
    n = 20
    A = np.full((n, 1), 1.0 / np.sqrt(n))
    fit = _linear_fit(A, A[:, 0] * value_true + np.random.default_rng(1).normal(size=n),
                      -20.0, 20.0)
    eff = EFFECTS["interference_error"]
    pb = SimpleNamespace(candidates=[eff], base=[], effect=lambda name: eff, noise=None)
    return SimpleNamespace(chosen=None, pb=pb, fits={eff.name: fit}, heldout={eff.name: None},
                           decision=SimpleNamespace(cause=eff.name, verdict="explained")), fit


def test_stop_rule_after_a_cause_at_its_bound():
    """No further cause is sought after a cause the data want beyond its bound (30 um on
    [-20, 20]); after one inside (5 um) the rule does not stop the search."""
    from studies.diagnosis import selection as s
    for truth, stop in ((30.0, True), (5.0, False)):
        cur, _ = _pass_at(truth)
        search = _search()
        search.cur = cur
        assert s.last_cause_at_bound(search) == stop


def test_final_rule_joint_model_at_a_bound():
    """The model of the accepted causes pushed beyond a bound claims nothing (`unexplained`,
    `at_bound` with the bound); inside its bounds the rule does not apply."""
    from studies.diagnosis import selection as s
    for truth, applies in ((30.0, True), (5.0, False)):
        cur, fit = _pass_at(truth)
        search = _search()
        search.final_pb, search.final_fit = cur.pb, fit
        search.first = SimpleNamespace(pb=cur.pb)
        sel = s.joint_at_bound(search, s.Selection())
        assert (sel is not None) == applies
        if applies:
            assert sel.verdict == "unexplained" and sel.at_bound[0].bound == 20.0


def test_kin_alternatives_of_the_rung():
    """The other forms of an accepted `thermal_transient_fe` (`selection._alternatives`) are its
    kin's: the lag's series form from the listed lag's fit of the pass and over the series grid
    (SERIES_GRID^2 starts), its per-part form, the radial gradient's lag (the speed changes);
    an accepted cause outside the kin with no form of its own has none."""
    from studies.diagnosis import fitspec
    from studies.diagnosis import selection as s
    from studies.diagnosis.problem import Accepted

    t = np.linspace(0.0, 14 * 3600.0, 240)
    cond = {"time_s": t, "T_ambient_C": 20.0 + 40.0 * np.sin(t / 3600.0),
            "speed_rpm": np.where(t > 7 * 3600.0, 3000.0, 1500.0)}
    listed = [EFFECTS[n] for n in ("thermal_lag", "radial_gradient", "interference_error")]
    pb = SimpleNamespace(candidates=listed, conditions=cond)
    nxt = SimpleNamespace(candidates={"thermal_lag": SimpleNamespace(parameters={"tau_s": 116.0})})
    rung = Accepted(SimpleNamespace(name="thermal_transient_fe", bounds={}), {}, ())
    alt = {f.name: starts for f, starts in s._alternatives(pb, rung, nxt)}
    assert {"thermal_lag.series", "thermal_lag.per_part"} <= set(alt)
    assert any(n.startswith("radial_gradient.") for n in alt)
    series = alt["thermal_lag.series"]
    assert series[0] == {"tau_s": 116.0, "tau_shaft_s": 0.0}
    assert len(series) == 1 + fitspec.SERIES_GRID ** 2
    fit_error = Accepted(EFFECTS["interference_error"], {"inner_um": 1.0, "outer_um": 0.0}, ())
    assert s._alternatives(pb, fit_error, nxt) == []


def test_further_cause_wanted_only_by_the_accepted_form():
    """`_wanted_only_by_its_form` on stand-ins (chi-squares of `network_lag` seed 0): a further
    cause that gains less than clear_chi2 beside another form of the accepted cause fitting as
    well is stopped; one that gains clearly, or beside a form that fits worse, is not."""
    from studies.diagnosis import selection as s

    def alt(chi2_alone, chi2_with):
        q = SimpleNamespace(space=lambda effects, fixed=None: SimpleNamespace(lo=np.zeros(2)),
                            fit=lambda sp, u0: SimpleNamespace(chi2=chi2_with))
        return ("thermal_lag.series", "thermal_transient_fe", q,
                SimpleNamespace(chi2=chi2_alone, u=np.zeros(1)))

    pb = SimpleNamespace(th={"clear_chi2": 25.0})
    fit_c = SimpleNamespace(u=np.zeros(1), space=SimpleNamespace(k=1), profile_value=None)
    nxt = SimpleNamespace(chosen=None, fits={"preload_path_compliance": fit_c},
                          heldout={"preload_path_compliance": None},
                          pb=SimpleNamespace(effect=lambda n: EFFECTS[n]),
                          decision=SimpleNamespace(cause="preload_path_compliance"),
                          baseline=SimpleNamespace(fit=SimpleNamespace(chi2=581.7)))
    got = s._wanted_only_by_its_form(pb, nxt, [alt(572.5, 572.5)])
    assert got[:2] == ("thermal_lag.series", "thermal_transient_fe") and got[2] == 0.0
    assert s._wanted_only_by_its_form(pb, nxt, [alt(572.5, 500.0)]) is None   # gains 72.5
    assert s._wanted_only_by_its_form(pb, nxt, [alt(620.0, 620.0)]) is None   # fits worse
