"""Generalised forms in the diagnosis, on data made by the REAL model with the project's
own designs, configurations and noise levels (`test_diagnose_pipeline`, whose module docstring
describes how the data are made; the generalised forms go through the same `apply_effects` path).

- per-part thermal lag (housing 900 s, shaft 2400 s) in seed 001's speed/temperature steps: the
  listed thermal_lag takes most of the structure (chi-square 2.8e6 -> ~7.6e3 at torque noise
  1 N mm); the verdict is thermal_lag with the per-part form and both time constants recovered
  within 3 of their standard uncertainties (and 15 %);
- preload settling that creeps with time hot (5 N at 50 K + 3 N per hour beyond it) in seed 000's
  -60 <-> 80 C cycles: preload_settling with the creep form, parameters within 3 u;
- data made with the LISTED forms (thermal_lag 900 s; preload_settling 5 N at 50 K; a linear
  friction law, -4e-5 /K): the listed form, no extension claimed (the nested test must not fire);
- null data: no_discrepancy and no form tried;
- (slow) a CTE with curvature (3e-10 /K^3, no slope) in seed 000's -60..80 C steps, and a radial
  gradient whose speed part lags 1200 s behind seed 003's speed steps: the listed family with its
  curvature / lag form, the added parameter within 3 u and 15 %.
"""
from __future__ import annotations

import pytest

from test_diagnose_pipeline import (SIGMA_000, SIGMA_001_TORQUE, SIGMA_003, cycles, diagnose_real,
                                    largest_change_sigma, measured, oil_speed_steps_001,
                                    oil_speed_steps_003, summary, temp_steps,
                                    MIN_CHANGE_SIGMA, pl000, pl001, pl003)  # noqa: F401 (fixtures)

#: 3 standard uncertainties (the engine's linearised ones): a miss beyond is a wrong fit
K_U = 3.0


def _check_params(ext, truth, rel):
    for p, v in truth.items():
        got, u = ext["parameters"][p], ext["parameter_uncertainty"][p]
        assert u is not None and abs(got - v) <= K_U * u, (p, got, v, u)
        assert got == pytest.approx(v, rel=rel), (p, got, v)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_per_part_lag_is_thermal_lag_extended(pl001):
    cond = oil_speed_steps_001()
    truth = {"tau_s": 900.0, "tau_shaft_s": 2400.0}
    eff = {"thermal_lag.per_part": truth}
    assert largest_change_sigma(pl001, cond, eff, SIGMA_001_TORQUE) >= MIN_CHANGE_SIGMA
    res = diagnose_real(pl001, cond, measured(pl001, cond, eff, SIGMA_001_TORQUE, seed=17))
    assert (res["verdict"], res["cause"]) == ("explained", "thermal_lag"), summary(res)
    ext = res["extended_form"]
    assert ext is not None and ext["name"] == "thermal_lag.per_part", res["generalised_forms"]
    assert ext["status"] == "explains"
    # nested: it beats the listed form out of sample, not only in sample
    assert ext["heldout_gain_vs_listed"]["excludes_zero"] and ext["chi2"] < ext["chi2_listed"]
    # 15 %: at ~350 sigma of change the time constants are determined to ~10 % (their u)
    _check_params(ext, truth, rel=0.15)
    assert ext["text"].startswith("thermal_lag, per-part time constants: housing ")
    assert set(res["parameters"]) == {"tau_s"}       # the listed cause's own parameter names


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_settling_creep_is_preload_settling_extended(pl000):
    cond = cycles()
    truth = {"loss_N": 5.0, "creep_N_per_h": 3.0}
    eff = {"preload_settling.creep": {**truth, "threshold_K": 50.0}}
    assert largest_change_sigma(pl000, cond, eff, SIGMA_000) >= MIN_CHANGE_SIGMA
    res = diagnose_real(pl000, cond, measured(pl000, cond, eff, SIGMA_000, seed=17))
    assert (res["verdict"], res["cause"]) == ("explained", "preload_settling"), summary(res)
    ext = res["extended_form"]
    assert ext is not None and ext["name"] == "preload_settling.creep", res["generalised_forms"]
    assert ext["heldout_gain_vs_listed"]["excludes_zero"]
    _check_params(ext, truth, rel=0.10)


@pytest.mark.slow
@pytest.mark.parametrize("which", ["thermal_lag", "preload_settling", "friction_temperature"])
def test_listed_form_stays_listed(pl000, pl001, which):
    if which == "thermal_lag":
        pl, cond, sigma, eff = (pl001, oil_speed_steps_001(), SIGMA_001_TORQUE,
                                {"thermal_lag": {"tau_s": 900.0}})
    elif which == "friction_temperature":      # the linear law, the slope of 20 % per 100 K
        pl, cond, sigma, eff = (pl000, cycles(), SIGMA_000,
                                {"friction_temperature": {"dmu_per_K": -4e-5}})
    else:
        pl, cond, sigma, eff = (pl000, cycles(), SIGMA_000,
                                {"preload_settling": {"loss_N": 5.0, "threshold_K": 50.0}})
    res = diagnose_real(pl, cond, measured(pl, cond, eff, sigma, seed=17))
    assert (res["verdict"], res["cause"]) == ("explained", which), summary(res)
    assert res["extended_form"] is None, res["generalised_forms"]
    # the forms of the family were tried (nested) and rejected against the listed form
    assert res["generalised_forms"] and all(g["status"] != "explains"
                                            for g in res["generalised_forms"])


def test_null_stays_no_discrepancy(pl001):
    cond = oil_speed_steps_001()
    res = diagnose_real(pl001, cond, measured(pl001, cond, {}, SIGMA_001_TORQUE, seed=17))
    assert res["verdict"] == "no_discrepancy", summary(res)
    assert res["extended_form"] is None and res["generalised_forms"] == []


@pytest.mark.slow
@pytest.mark.parametrize("which", ["cte_nonlinearity.curvature", "radial_gradient.lag"])
def test_curvature_and_gradient_lag_are_their_family_extended(pl000, pl003, which):
    if which == "cte_nonlinearity.curvature":
        pl, cond, sigma = pl000, temp_steps(), SIGMA_000
        truth = {"d2alpha_per_K3": 3e-10}
        eff = {which: {"dalpha_per_K": 0.0, **truth}}
        rel = 0.15     # u(d2alpha) is about 4 % here (108 sigma of change)
    else:
        pl, cond, sigma = pl003, oil_speed_steps_003(), SIGMA_003
        truth = {"dT_K": 1.0, "dT_per_krpm_K": 2.0, "tau_gradient_s": 1200.0}
        eff = {which: truth}
        # seed 003's torque noise (2 N mm) leaves 23 sigma of change: u(tau) is about 16 % of it,
        # so the 3 u check binds; 30 % still catches a fit in the wrong basin (tau -> 0 or 1e5)
        rel = 0.30
    family = which.split(".")[0]
    assert largest_change_sigma(pl, cond, eff, sigma) >= MIN_CHANGE_SIGMA
    res = diagnose_real(pl, cond, measured(pl, cond, eff, sigma, seed=17))
    assert (res["verdict"], res["cause"]) == ("explained", family), summary(res)
    ext = res["extended_form"]
    assert ext is not None and ext["name"] == which, res["generalised_forms"]
    assert ext["heldout_gain_vs_listed"]["excludes_zero"]
    _check_params(ext, truth, rel=rel)
