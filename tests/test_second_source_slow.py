"""Every second-source case (studies/validation/second_source.py) through today's diagnosis, slow
(`make test-slow`; 18 diagnoses on the coarse mesh family member, about 10-30 s each on 2 idle
cores): no wrong cause claimed (`second_source.judge` != "wrong": 0 wrong
causes on the second-source data), two causes both named.

Every case passes since 2026-11-25 (measured on seed 0 of each case, mesh factor 2); before:
- `steel_sleeve` was `explained: interference_error` (a 2 mm steel sleeve changes the outer fit
  with temperature, no constant offset does); with the model-form ladder it is `unexplained`:
  the `material_lot` rung fits better than the offset but, at its bound, leaves structure, so
  nothing is claimed; the `sleeve` rung is tried (GCr15 / 17-4PH / Invar36 / TC4,
  1.5 or 3 mm) but a TC4 housing with a CTE 6 % high fits the 2 mm 9Cr18 sleeve as well, so it is
  still not claimed (`selection.sleeve_lookalike`); the 3 mm 17-4PH sleeve in aluminium is named;
- `grooved_sections` was `explained: cte_nonlinearity`; with the model-form ladder
  `ring_section_grooved` explains it (tests/test_ladder.py);
- `chamber_offset` (a 0.5 K thermometer offset, largest change 0.8 sigma) was
  `explained: cte_nonlinearity` (the CTE curvature form claimed after the drift check had
  refused the listed candidates) or `ambiguous` between a fit error and a material lot; since
  2026-11-25 a generalised form is claimed only under the rules of any claim and every claim
  must beat the sensor look-alike `thermometer_offset` (`ladder.lookalikes`): `unexplained`;
- `fit_error_and_lag` was `explained: thermal_lag` only (`partial`) before item 5 (more than one
  cause, `studies/diagnosis/selection.py`).
The per-design rates over several draws are the confusion-matrix study's (docs/diagnosis_rates.md).
"""
from __future__ import annotations

import pytest

from studies.validation import second_source as ss

pytestmark = pytest.mark.slow

MESH_FACTOR = 2.0


#: cases left out here: `shaft_lag_numpy`'s truth (the thin-section rig on the finer mesh with
#: direct solves) takes about 11 GB (measured 2026-11-29; its outcome, right, is in
#: docs/diagnosis.md "A lag the listed form fits at off")
HEAVY = ("shaft_lag_numpy",)


@pytest.mark.parametrize("name", [n for n in ss.CASES if n not in HEAVY])
def test_no_wrong_cause_on_second_source_data(name):
    """Seed 0 of the case: the diagnosis names a right cause, says it cannot (unexplained), or
    finds nothing (on a null or an invisible truth); never a wrong cause."""
    c = ss.make_case(name, seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) != "wrong", \
        (name, res.verdict, ss.named_causes(res), list(res.indistinguishable))


def test_two_causes_are_both_named():
    """A 4 um inner fit error and a 1500 s lag on the cycle (81.6 sigma): both causes named."""
    c = ss.make_case("fit_error_and_lag", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right", (res.verdict, ss.named_causes(res))


def test_quasi_dynamic_balls_are_explained_by_their_rung():
    """Quasi-dynamic balls under a static config on seed 001's speed steps (72 sigma): the
    model-form ladder names `ball_model_quasi_dynamic`."""
    c = ss.make_case("quasi_dynamic_balls", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right", (res.verdict, ss.named_causes(res))


def test_fit_outside_its_band_is_not_claimed_and_named_at_the_bound():
    """The inner fit 2.5 um tighter than its ISO band allows (13.9 sigma), made on the finer
    mesh with direct FE solves: the fit error, bounded to the band, can only reach its edge.
    A parameter at its bound is evidence against the candidate, so nothing is claimed
    and `at_bound` names interference_error's inner error at the band's upper edge."""
    c = ss.make_case("fit_outside_band", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert res.verdict not in ("explained", "explained_partly") and res.cause is None, \
        (res.verdict, ss.named_causes(res), res.reasons)
    hit = [b for b in res.at_bound if b.effect == "interference_error"
           and b.parameter == "inner_um"]
    assert hit and hit[0].bound > 0 and abs(hit[0].value - hit[0].bound) < 0.1, res.at_bound
    assert ss.judge_result(c, res) == "right"


def test_sleeve_in_aluminium_is_named_by_the_sleeve_rung_and_never_claimed_without_it():
    """A hidden sleeve made on the finer mesh with direct FE solves: a 3 mm 17-4PH sleeve
    between the outer rings and a 6061 housing the file has without a sleeve (557 sigma). With
    the ladder's sleeve rung: explained by `sleeve`, its variant the 3 mm 17-4PH (the data were
    made with it), its share within 0.05 of 1 (the form itself). Without the rung (the ladder
    without it): no cause claimed (a fit error would need more than its +-20 um, a material
    lot more than its +-5 %), and the reason lists what stopped the best candidate (a bound or
    a column made worse)."""
    from studies.diagnosis.engine import diagnose_full
    from studies.diagnosis.files import NUISANCE, ModelPredictor, candidate_effects
    from studies.diagnosis.ladder import candidates as ladder_candidates

    c = ss.make_case("sleeve_in_aluminium", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert res.verdict == "explained" and res.cause == "sleeve", (res.verdict, res.reasons)
    sleeve = next(e for e in ladder_candidates(c.assembly) if e.name == "sleeve")
    assert sleeve.variant(res.parameters) == ("17-4PH", 3.0), res.parameters
    assert abs(res.parameters["share"] - 1.0) < 0.05, res.parameters

    pred = ModelPredictor(ss._pipeline(c.assembly, c.mesh_factor), c.conditions, c.columns)
    cands = candidate_effects(c.assembly) + [e for e in ladder_candidates(c.assembly)
                                             if e.name != "sleeve"]
    old = diagnose_full(pred, c.measured, c.conditions, cands, NUISANCE,
                        T_ref_C=c.assembly.T_ref_C, predict_at=pred.at, seed=c.seed)
    assert old.verdict not in ("explained", "explained_partly") and old.cause is None, \
        (old.verdict, old.cause, old.reasons)
    if old.best_partial is not None and old.verdict == "unexplained":
        assert old.at_bound or old.worse_columns or any(
            "leaves structure" in x or "does not clearly beat" in x for x in old.reasons), \
            old.reasons
