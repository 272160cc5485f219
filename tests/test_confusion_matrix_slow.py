"""Operating characteristics (slow; `make test-slow`): a reduced confusion matrix on the toy
bearing of `test_diagnosis_engine.py` in the standard designs of `studies/diagnosis/designs.py`.

Asserts: the false-alarm count of the nulls is within the binomial 99 % upper quantile of the stated
level (the union bound alpha_structure + alpha_lr of the engine's thresholds:
`operating.stated_false_alarm_level`); every listed effect injected at the larger magnitude
(RMS visible change 0.5 noise sigma) is named (explained, or ambiguous with it among the rivals);
the unlisted torque drift is never claimed as a listed cause. Prints the matrix."""
from __future__ import annotations

import pytest
from scipy import stats

from studies.diagnosis.designs import cycles, speed_steps
from studies.diagnosis.operating import (MAGNITUDES, NONE, UNLISTED, Design, markdown, run_matrix,
                                         stated_false_alarm_level)
from studies.model.effects import EFFECTS, ORDER

from test_diagnosis_engine import NUISANCE, SIGMA, T_REF, ToyBearing

pytestmark = pytest.mark.slow


def test_reduced_confusion_matrix():
    solid, oil = ToyBearing(), ToyBearing(c_visc=0.5, speed_rpm=6000.0)
    cands = [EFFECTS[n] for n in ORDER]
    designs = [Design("cycles", cycles(300, 96.0), solid.predictor, cands, NUISANCE, SIGMA, T_REF),
               Design("speed_steps", speed_steps(300, 96.0), oil.predictor, cands, NUISANCE,
                      SIGMA, T_REF)]
    mx = run_matrix(designs, MAGNITUDES, reps=2, n_null=15, seed=5)
    print("\n" + "\n".join(markdown(mx)))
    fa = mx.false_alarm
    level = stated_false_alarm_level()
    assert fa["false_alarms"] <= stats.binom.ppf(0.99, fa["trials"], level), fa
    top = max(MAGNITUDES)
    listed = [r for r in mx.rates if r["hidden"] not in (NONE, UNLISTED)]
    assert {r["hidden"] for r in listed} >= {"thermal_lag", "preload_settling",
                                             "friction_temperature", "viscosity_temperature"}
    for r in listed:
        if r["magnitude_sigma"] == top:
            assert r["named"] == r["trials"], r
    for r in mx.rates:
        if r["hidden"] == UNLISTED:
            assert r["cause_claimed"] == 0, r
