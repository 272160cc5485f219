"""The staged thermal rung (`studies.diagnosis.staging`): the rules on small synthetic passes,
and on the toy bearing of `tests/test_diagnosis_engine.py` with a stand-in rung.

The stand-in rung has the transient rung's name, kind and conditions features, and predicts
what a lumped lag of its own time constant predicts (a perfect look-alike of `thermal_lag`):
the data are made by the toy's lag, so these tests check the staging logic (which stage
screens what, which pass stands), not the physics of either form."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import pytest

from studies.diagnosis import staging
from studies.diagnosis.core import Decision
from studies.diagnosis.engine import diagnose_full
from studies.diagnosis.problem import Accepted
from studies.diagnosis.transient_rung import NAME as RUNG
from studies.model.effects import EFFECTS
from tests.test_diagnosis_engine import NUISANCE, T_REF, ToyBearing, cycles, make_data

LAG = EFFECTS["thermal_lag"]


class StandInRung(type(LAG)):
    """The rung's name, kind and features; the lag's parameter and bounds."""
    name = RUNG
    kind = "model_form"
    acts_through = ("dTdt_K_per_s", "time_since_start_s", "temperature_C", "speed_rpm")
    change = "stand-in of the transient rung (a lumped lag)"


def _pb(*names, base=()):
    effects = {n: (StandInRung() if n == RUNG else EFFECTS[n]) for n in names}
    return SimpleNamespace(candidates=tuple(effects.values()), base=tuple(base))


@dataclass(frozen=True)
class _Pass:
    """The fields of `engine.Pass` the rules read."""
    pb: object
    decision: Decision
    chosen: object = None
    candidates: dict = field(default_factory=dict)


def _pass(pb, verdict, best, rivals=(), chosen=None):
    d = Decision(verdict, best if verdict in ("explained", "explained_partly", "ambiguous")
                 else None, best, list(rivals), None, {}, [])
    return _Pass(pb, d, chosen)


# ------------------------------------------------------------------ the rules
def test_only_the_kin_model_form_is_staged():
    assert staging.is_staged(StandInRung())
    assert not staging.is_staged(LAG)
    assert not staging.is_staged(EFFECTS["interference_error"])
    pb = _pb("thermal_lag", "radial_gradient", "interference_error", RUNG)
    assert staging.is_lumped(pb, "thermal_lag") and staging.is_lumped(pb, "radial_gradient")
    assert not staging.is_lumped(pb, RUNG) and not staging.is_lumped(pb, "interference_error")
    assert staging.held(pb) == {RUNG: staging.PENDING}


def test_a_lumped_cause_accepted_already_keeps_the_rung_out():
    pb = _pb("interference_error", RUNG, base=(Accepted(LAG, {"tau_s": 400.0}, ("tau_s",)),))
    why = staging.held(pb)[RUNG]
    assert why != staging.PENDING and "thermal_lag" in why
    pb = _pb("thermal_lag", RUNG,
             base=(Accepted(EFFECTS["interference_error"], {}, ()),))
    assert staging.held(pb) == {RUNG: staging.PENDING}


@pytest.mark.parametrize("verdict, best, rivals, at_its_noise, skipped", [
    ("explained", "thermal_lag", (), True, True),
    ("explained", "thermal_lag", (), False, False),     # the lag's misfit taken for noise
    ("explained", "interference_error", (), True, False),   # not a thermal form
    ("explained_partly", "thermal_lag", (), True, False),   # the lag leaves structure
    ("ambiguous", "interference_error", ("radial_gradient",), True, True),
    ("ambiguous", "interference_error", ("preload_path_compliance",), True, False),
    ("unexplained", "thermal_lag", ("radial_gradient",), True, False),
])
def test_the_rung_is_tried_only_where_no_lumped_form_explains(monkeypatch, verdict, best,
                                                              rivals, at_its_noise, skipped):
    asked = []

    def at_noise(p):
        asked.append(p.decision.cause)
        return at_its_noise

    monkeypatch.setattr(staging, "cause_explains_at_its_noise", at_noise)
    pb = _pb("thermal_lag", "radial_gradient", "interference_error", "preload_path_compliance",
             RUNG)
    why = staging.lumped_explains(_pass(pb, verdict, best, rivals))
    assert (why is not None) == skipped
    if skipped:
        assert why.startswith("a lumped lag leaves no structure")
        # the form judged at its own noise is the lumped one, also when it is a rival
        assert staging.is_lumped(pb, asked[-1])


def test_a_chosen_form_is_named_in_the_reason(monkeypatch):
    monkeypatch.setattr(staging, "cause_explains_at_its_noise", lambda p: True)
    pb = _pb("thermal_lag", RUNG)
    chosen = SimpleNamespace(entry=SimpleNamespace(text="thermal_lag, series: 600 s, 240 s"))
    why = staging.lumped_explains(_pass(pb, "explained", "thermal_lag", chosen=chosen))
    assert why == "a lumped lag leaves no structure (thermal_lag, series: 600 s, 240 s)"


@pytest.mark.parametrize("verdict, best, rivals, gives_way", [
    ("ambiguous", RUNG, ("thermal_lag",), True),
    ("ambiguous", "thermal_lag", (RUNG,), True),
    ("unexplained", RUNG, ("thermal_lag", "radial_gradient"), True),
    ("ambiguous", RUNG, ("thermal_lag", "interference_error"), False),
    ("ambiguous", "thermal_lag", ("radial_gradient",), False),     # the rung not tied
    ("explained", RUNG, (), False),
    ("unexplained", RUNG, (), False),
])
def test_a_tie_of_the_rung_with_lumped_forms_only_gives_way(verdict, best, rivals, gives_way):
    pb = _pb("thermal_lag", "radial_gradient", "interference_error", RUNG)
    why = staging.lumped_tie(_pass(pb, verdict, best, rivals), [RUNG])
    assert (why is not None) == gives_way
    if gives_way:
        assert "cheaper listed form" in why


# ------------------------------------------------------------------ on the toy
class _Counted(ToyBearing):
    """The toy with the stand-in rung evaluated as a lag, counting the calls with it on."""
    rung_calls = 0

    def evaluate(self, conditions, effects, nuisance):
        effects = dict(effects)
        if RUNG in effects:
            self.rung_calls += 1
            p = effects.pop(RUNG)
            lag = effects.get("thermal_lag", {"tau_s": 0.0})
            effects["thermal_lag"] = {"tau_s": lag["tau_s"] + p["tau_s"]}
        return super().evaluate(conditions, effects, nuisance)


def _diagnose(model, cond, meas):
    predict, predict_at = model.predictor(cond)
    cands = [*EFFECTS.values(), StandInRung()]
    return diagnose_full(predict, meas, cond, cands, NUISANCE, predict_at=predict_at,
                         T_ref_C=T_REF)


@pytest.mark.slow
def test_a_lag_that_explains_leaves_the_rung_unscreened():
    model = _Counted()
    cond = cycles()
    res = _diagnose(model, cond, make_data(model, cond, {"thermal_lag": {"tau_s": 400.0}}, 3))
    assert (res.verdict, res.cause) == ("explained", "thermal_lag"), res.reasons
    rung = next(c for c in res.candidates if c.effect == RUNG)
    assert rung.status == "not_applicable"
    assert rung.reason.startswith("a lumped lag leaves no structure (thermal_lag")
    assert model.rung_calls == 0


@pytest.mark.slow
def test_a_rung_that_ties_with_the_lag_gives_way_and_the_search_goes_on():
    """A lag and a fit error: the lag alone leaves the fit error, so the rung is screened; it
    fits exactly as the lag does (the stand-in), the first stage's pass stands and the fit
    error is found beside the lag."""
    model = _Counted()
    cond = cycles()
    meas = make_data(model, cond, {"thermal_lag": {"tau_s": 400.0},
                                   "interference_error": {"inner_um": 0.0, "outer_um": 2.0}}, 3)
    res = _diagnose(model, cond, meas)
    rung = next(c for c in res.candidates if c.effect == RUNG)
    assert [c.effect for c in res.causes] == ["thermal_lag", "interference_error"], res.reasons
    assert res.verdict == "explained"
    assert model.rung_calls > 0
    assert rung.status == "rejected" and "cheaper listed form" in rung.reason
