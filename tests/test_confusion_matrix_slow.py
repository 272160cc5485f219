"""Operating characteristics (slow; `make test-slow`): a reduced confusion matrix on the toy
bearing of `test_diagnosis_engine.py` in the standard designs of `studies/diagnosis/designs.py`.

The candidates are built exactly as `bearingfem diagnose` builds them (`files.candidate_effects`
on the assembly the toy stands for), so the solid-film run-in is a candidate on the MoS2 toy
(its configured 60 rpm gives the revolutions) and not on the oil-lubricated one.

Asserts: the false-alarm count of the nulls is within the binomial 99 % upper quantile of the stated
level (the union bound alpha_structure + alpha_lr of the engine's thresholds:
`operating.stated_false_alarm_level`); every listed effect injected at the largest magnitude
(RMS visible change 2 noise sigma, above the detection threshold) is named (explained, or
ambiguous with it among the rivals), but for chance firings of the sensor-drift check on the true
cause within their binomial bound (`_named_and_unlisted`); nothing is claimed at the magnitude
below the detection threshold (`operating.BELOW_DETECTION_SIGMA`, 0.25 sigma);
the unlisted torque drift is never claimed as a listed cause, also in a design where the run-in
(a history in revolutions) is a candidate at three speeds; the look-alike pairs the toy's physics
implies. Prints the matrices."""
from __future__ import annotations

import pytest
from scipy import stats

from studies.diagnosis.core import DEFAULT_THRESHOLDS
from studies.diagnosis.designs import cycles, speed_steps
from studies.diagnosis.files import candidate_effects
from studies.diagnosis.operating import (BELOW_DETECTION_SIGMA, MAGNITUDES, NONE, UNLISTED, Design,
                                         markdown, run_matrix, stated_false_alarm_level)

from test_diagnosis_engine import NUISANCE, SIGMA, T_REF, ToyBearing

pytestmark = pytest.mark.slow


def _named_and_unlisted(mx):
    """Every listed effect at the larger magnitude is named, except trials where the engine's
    check against an unlisted sensor drift fires on the true cause: `unexplained` with the
    injected effect as the best candidate and adding a drift to it significant at alpha_joint.
    Under the truth (no drift) that check is a level-alpha_joint test, so their count must stay
    within the binomial 99 % upper quantile of alpha_joint over the trials; any other miss fails.
    The unlisted drift is never claimed."""
    top = max(MAGNITUDES)
    a = DEFAULT_THRESHOLDS["alpha_joint"]
    listed = [t for t in mx.trials if t.hidden not in (NONE, UNLISTED) and t.magnitude_sigma == top]
    named = [t.verdict in ("explained", "ambiguous") and (t.cause == t.hidden
                                                          or t.hidden in t.indistinguishable)
             for t in listed]
    chance = [t for t, ok in zip(listed, named) if not ok and t.verdict == "unexplained"
              and t.best_partial == t.hidden and t.drift_adds_p is not None
              and t.drift_adds_p < a]
    other = [t for t, ok in zip(listed, named) if not ok and t not in chance]
    assert not other, other
    assert len(chance) <= stats.binom.ppf(0.99, len(listed), a), chance
    for r in mx.rates:
        if r.hidden == UNLISTED:
            assert r.cause_claimed == 0, r


def _nothing_claimed_below_detection(mx):
    """At the magnitude below every design's detection threshold no cause is claimed, listed or
    unlisted (the detection rule: `no_discrepancy` whatever fits)."""
    below = [r for r in mx.rates if r.magnitude_sigma == BELOW_DETECTION_SIGMA]
    assert below and all(r.cause_claimed == 0 and r.explained_partly == 0 for r in below), [
        r for r in below if r.cause_claimed]


def test_reduced_confusion_matrix():
    solid, oil = ToyBearing(), ToyBearing(c_visc=0.5, speed_rpm=6000.0)
    designs = [Design("cycles", cycles(300, 96.0), solid.predictor,
                      candidate_effects(solid.assembly()), NUISANCE, SIGMA, T_REF),
               Design("speed_steps", speed_steps(300, 96.0), oil.predictor,
                      candidate_effects(oil.assembly()), NUISANCE, SIGMA, T_REF)]
    mx = run_matrix(designs, MAGNITUDES, reps=2, n_null=15, seed=5)
    print("\n" + "\n".join(markdown(mx)))
    fa = mx.false_alarm
    level = stated_false_alarm_level()
    assert fa.false_alarms <= stats.binom.ppf(0.99, fa.trials, level), fa
    injected = {d: {r.hidden for r in mx.rates if r.design == d} - {NONE, UNLISTED}
                for d in ("cycles", "speed_steps")}
    # the run-in is physical (and identifiable) on the solid film only; preload settling at its
    # 40 K threshold is reached by the -60..80 C cycles, not by 0..60 C steps from 20 C
    assert injected["cycles"] >= {"thermal_lag", "preload_settling", "friction_temperature",
                                  "solid_film_runin"}
    assert injected["speed_steps"] >= {"thermal_lag", "friction_temperature",
                                       "viscosity_temperature"}
    assert "solid_film_runin" not in mx.lookalike["speed_steps"]
    _named_and_unlisted(mx)
    _nothing_claimed_below_detection(mx)
    # look-alikes the toy's physics implies: at one speed the radial gradient is a constant ring
    # temperature difference, i.e. a constant change of both fits, as an interference error
    # (cosine near 1, above the engine's 0.95); a lag (a history in the temperature rate) and a
    # run-in (a history in revolutions) resemble no temperature-state effect (below 0.5)
    for d in ("cycles", "speed_steps"):
        look = mx.lookalike[d]
        assert look["interference_error"]["radial_gradient"] > 0.95, d
        assert max(v for k, v in look["thermal_lag"].items() if k != "thermal_lag") < 0.5, d
    look = mx.lookalike["cycles"]
    assert max(v for k, v in look["solid_film_runin"].items() if k != "solid_film_runin") < 0.5


def test_unlisted_drift_is_not_run_in_at_several_speeds():
    """The run-in counts revolutions, the drift time: with 300, 60 and 600 rpm a third of the rows
    each they differ, and a torque drift linear in time is never claimed (as the run-in or any
    listed cause) at any of `MAGNITUDES`. The injected run-in's rate is printed, not asserted:
    near the threshold a zero drift of the sensors can explain it in this design (its
    revolutions grow nearly linearly in time), and the engine then reports `unexplained` with
    the run-in as the best partial candidate (docs/diagnosis.md); measured 2026-12-02: explained
    in 4 of 4 at 1 sigma and at 2 sigma."""
    solid = ToyBearing()
    cond = cycles(300, 96.0, speeds_rpm=(300.0, 60.0, 600.0))
    d = Design("cycles_speeds", cond, solid.predictor, candidate_effects(solid.assembly()),
               NUISANCE, SIGMA, T_REF, hidden=["solid_film_runin"])
    mx = run_matrix([d], MAGNITUDES, reps=4, n_null=5, seed=11)
    print("\n" + "\n".join(markdown(mx)))
    assert "solid_film_runin" in mx.lookalike["cycles_speeds"]
    drift = [r for r in mx.rates if r.hidden == UNLISTED]
    assert sorted(r.magnitude_sigma for r in drift) == sorted(MAGNITUDES)
    for r in drift:
        assert r.cause_claimed == 0, r
    _nothing_claimed_below_detection(mx)


def test_real_model_lookalikes_stated_in_the_docs():
    """The look-alike pairs docs/diagnosis.md states for the study's designs on the real model
    (before any data, `operating.lookalike_before_data`, cosine above the engine's 0.95):
    `cycles` (seed 000) interference_error ~ preload_path_compliance (a fit error and a softer
    preload path both change the preload by a nearly temperature-independent amount) and
    radial_gradient ~ preload_settling; `speed_steps` (seed 001) interference_error ~
    cte_nonlinearity ~ preload_path_compliance (0..60 C steps: a fit offset, a CTE slope and a
    path compliance move the 7 N preload alike). The history effects are look-alikes of nothing
    (thermal_lag, and solid_film_runin on seed 000: below 0.5). The study's candidates are the
    CLI's (`files.candidate_effects`)."""
    from studies.diagnosis.operating import lookalike_before_data
    from studies.validation.confusion_matrix import design, setup

    th = 0.95
    for name, pairs, history in (
            ("cycles", [("interference_error", "preload_path_compliance"),
                        ("radial_gradient", "preload_settling")],
             ("thermal_lag", "solid_film_runin")),
            ("speed_steps", [("interference_error", "cte_nonlinearity"),
                             ("interference_error", "preload_path_compliance"),
                             ("cte_nonlinearity", "preload_path_compliance")],
             ("thermal_lag",))):
        asm, cond, cands = setup(name)
        assert [(e.name, e.bounds, e.applicable(cond)) for e in cands] == \
            [(e.name, e.bounds, e.applicable(cond)) for e in candidate_effects(asm)]
        look = lookalike_before_data(design(name))
        print(name, {a: {b: round(v, 2) for b, v in row.items()} for a, row in look.items()})
        for a, b in pairs:
            assert look[a][b] > th, (name, a, b, look[a][b])
        for h in history:
            assert max(v for k, v in look[h].items() if k != h) < 0.5, (name, h, look[h])
