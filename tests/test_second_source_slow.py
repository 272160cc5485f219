"""Every second-source case (studies/runs/second_source.py) through today's diagnosis, slow
(`make test-slow`; 18 diagnoses on the coarse mesh family member, about 10-30 s each on 2 idle
cores): no wrong cause claimed (`second_source.judge` != "wrong", issue 23 "Done when": 0 wrong
causes on the second-source data), two causes both named.

Cases where today's diagnosis does claim a wrong cause are `xfail(strict=True)` with the issue 23
item that fixes them (measured 2026-11-25 on seed 0 of each case, mesh factor 2):
- (`steel_sleeve` was `explained: interference_error` (a 2 mm steel sleeve changes the outer fit
  with temperature, no constant offset does); with the model-form ladder it is `unexplained`:
  the `material_lot` rung fits better than the offset but, at its bound, leaves structure, so
  nothing is claimed; the `sleeve` rung itself is not tried, its material and thickness not
  being bounded by a data sheet)
- (`grooved_sections` was `explained: cte_nonlinearity`; with the model-form ladder, item 2,
  `ring_section_grooved` explains it: tests/test_ladder.py)
- `chamber_offset` -> `explained: cte_nonlinearity` (a 0.5 K thermometer offset within its class,
  largest change 0.8 sigma: a claim on what is practically a null): items 3 and 4;
- `fit_error_and_lag` -> `explained: thermal_lag` only (`partial`): item 5, more than one cause.
The per-design rates over several draws are the confusion-matrix study's (docs/diagnosis.md).
"""
from __future__ import annotations

import pytest

from studies.runs import second_source as ss

pytestmark = pytest.mark.slow

MESH_FACTOR = 2.0
WRONG_TODAY = {
    "chamber_offset": "issue 23 items 3 and 4: goodness of fit and a false-claim level that holds "
                      "(today: explained: cte_nonlinearity on a 0.5 K thermometer offset whose "
                      "largest change is 0.8 sigma)",
}


def _params():
    for name in ss.CASES:
        marks = [pytest.mark.xfail(strict=True, reason=WRONG_TODAY[name])] \
            if name in WRONG_TODAY else []
        yield pytest.param(name, marks=marks, id=name)


@pytest.mark.parametrize("name", list(_params()))
def test_no_wrong_cause_on_second_source_data(name):
    """Seed 0 of the case: the diagnosis names a right cause, says it cannot (unexplained), or
    finds nothing (on a null or an invisible truth); never a wrong cause."""
    c = ss.make_case(name, seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) != "wrong", \
        (name, res.verdict, ss.named_causes(res), list(res.indistinguishable))


@pytest.mark.xfail(strict=True, reason="issue 23 item 5: forward selection after the first cause "
                                       "(today: explained: thermal_lag alone)")
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


@pytest.mark.xfail(strict=True, reason="issue 23 item 3: explained_partly with the offset at its "
                                       "bound (today: unexplained)")
def test_fit_outside_its_band_is_explained_partly_at_the_bound():
    """The inner fit 2.5 um tighter than its ISO band allows (13.9 sigma): the fit error is named
    and, held inside the band, leaves structure: `explained_partly`."""
    c = ss.make_case("fit_outside_band", seed=0, mesh_factor=MESH_FACTOR)
    res = ss.diagnose_case(c)
    assert res.verdict == "explained_partly" and ss.judge_result(c, res) == "right", \
        (res.verdict, ss.named_causes(res))
