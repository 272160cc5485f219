"""Every second-source case (studies/validation/second_source.py) through today's diagnosis, slow
(`make test-slow`; 18 diagnoses on the coarse mesh family member, about 10-30 s each on 2 idle
cores): no wrong cause claimed (`second_source.judge` != "wrong", issue 23 "Done when": 0 wrong
causes on the second-source data), two causes both named.

Every case passes since 2026-11-25 (measured on seed 0 of each case, mesh factor 2); before:
- `steel_sleeve` was `explained: interference_error` (a 2 mm steel sleeve changes the outer fit
  with temperature, no constant offset does); with the model-form ladder it is `unexplained`:
  the `material_lot` rung fits better than the offset but, at its bound, leaves structure, so
  nothing is claimed; the `sleeve` rung itself is not tried, its material and thickness not
  being bounded by a data sheet;
- `grooved_sections` was `explained: cte_nonlinearity`; with the model-form ladder
  `ring_section_grooved` explains it (tests/test_ladder.py);
- `chamber_offset` (a 0.5 K thermometer offset, largest change 0.8 sigma) was
  `explained: cte_nonlinearity` (the CTE curvature form claimed after the drift check had
  refused the listed candidates) or `ambiguous` between a fit error and a material lot; since
  2026-11-25 a generalised form is claimed only under the rules of any claim and every claim
  must beat the sensor look-alike `thermometer_offset` (`ladder.lookalikes`): `unexplained`;
- `fit_error_and_lag` was `explained: thermal_lag` only (`partial`) before item 5 (more than one
  cause, `studies/diagnosis/selection.py`).
The per-design rates over several draws are the confusion-matrix study's (docs/diagnosis.md).
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


def test_fit_outside_its_band_is_explained_partly_at_the_bound():
    """The inner fit 2.5 um tighter than its ISO band allows (13.9 sigma): the fit error is named
    and, held inside the band, leaves structure: `explained_partly`."""
    c = ss.make_case("fit_outside_band", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert res.verdict == "explained_partly" and ss.judge_result(c, res) == "right", \
        (res.verdict, ss.named_causes(res))
