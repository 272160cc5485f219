"""Hidden effects in data made by the REAL model (FE -> bearing pair -> torque), diagnosed by the
engine with the real predictor (`studies.diagnosis.files.ModelPredictor`): the tests that hide an
effect.

Measured data are made the way a rig would produce them: the shipped configuration is run on a
conditions table (temperature steps at a fixed preload, a preload sweep at several temperatures,
alternating -60 <-> 80 C cycles with time, temperature steps at several speeds), with one effect
switched on (the same `apply_effects` path as `bearingfem simulate --effect`; a test below holds the
two routes equal), and Gaussian noise is added to the measured columns. The rig's friction
coefficient is not the configured one (`MU_TRUE`): the baseline's nuisance calibration (`mu_scale`)
has to absorb that.

Noise levels (`SIGMA_*`, one standard deviation) are assumptions of a plausible rig: a torque
transducer resolving 0.02 N mm on the 1.5..4 N mm of the seed 000 pair (about 1 %), 1 N mm on the
30..1700 N mm of the oil-lubricated seed 001 pair and 2 N mm on the 200..700 N mm of seed 003
(below 1 %), and a preload load cell of 0.5 N (seed 000, 100 N) or 5 N (seed 003, 1500 N).

"Largest change" of a hidden effect (as in `test_diagnosis_slow.py`): the noise-free data with the
effect against the baseline refitted with its nuisance calibration, the largest absolute difference
in noise units over all measured columns. It is what the data can show; every hidden-effect test
asserts it is at least 8 sigma, so a miss is the engine's, not an invisible effect.

The pipelines are built with `mesh_factor=2.0` (a coarser FE mesh): data and model use the same
pipeline, so the mesh error is not a model error here.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize, stats

from studies.model.config import load_shipped
from studies.diagnosis.files import NUISANCE, ModelPredictor, candidate_effects
from studies.diagnosis.engine import diagnose_full
from studies.diagnosis.result import to_json
from studies.model.effects import EFFECTS, ORDER
from studies.model.pipeline import Pipeline
from studies.diagnosis import fitspec
from studies.diagnosis.designs import cycles
from studies.model.columns import to_columns
from studies.diagnosis.operating import stated_false_alarm_level

MESH_FACTOR = 2.0
MU_TRUE = 1.25          # the rig's friction coefficient / the configured one (nuisance, unknown)
SIGMA_000 = {"torque_Nmm": 0.02, "preload_N": 0.5}
SIGMA_000_TORQUE = {"torque_Nmm": 0.02}
SIGMA_001_TORQUE = {"torque_Nmm": 1.0}
SIGMA_003 = {"torque_Nmm": 2.0, "preload_N": 5.0}
MIN_CHANGE_SIGMA = 8.0  # the brief: hidden effects "at a magnitude a rig would see"

#: effect -> parameter names, exactly as in docs/cli.md (table "Effects")
SPEC_PARAMETERS = {
    "interference_error": {"inner_um", "outer_um"},
    "radial_gradient": {"dT_K", "dT_per_krpm_K"},
    "thermal_lag": {"tau_s"},
    "viscosity_temperature": {"slope_factor"},
    "friction_temperature": {"dmu_per_K"},
    "preload_settling": {"loss_N", "threshold_K"},
    "cte_nonlinearity": {"dalpha_per_K"},
    # this project's extensions beyond the spec's seven (names fixed in docs/cli.md)
    "solid_film_runin": {"dmu", "runin_krev"},
    "preload_path_compliance": {"extra_compliance_um_per_kN"},
}
#: top-level keys of diagnosis.json, docs/cli.md ("`diagnose` output"), in that order
SPEC_KEYS = ["verdict", "cause", "parameters", "indistinguishable", "separating_test", "baseline",
             "extended", "gain", "candidates"]
VERDICTS = {"no_discrepancy", "explained", "ambiguous", "unexplained"}


# ============================================================================ test designs


def temp_steps(levels=(-60, -40, -20, 0, 20, 40, 60, 80), per=20, dt=60.0, rate_K_min=2.0,
               time_col=True, speeds=None):
    """Temperature step series: the chamber moves to each set point at `rate_K_min` and holds it
    for `per` samples `dt` s apart; repeated at each speed when `speeds` is given (then with a
    `speed_rpm` column)."""
    target = np.repeat(np.asarray(levels, float), per)
    if speeds is not None:
        target = np.tile(target, len(speeds))
    n = target.size
    amb = np.empty(n)
    amb[0] = target[0]
    step = rate_K_min * dt / 60.0
    for i in range(1, n):
        amb[i] = amb[i - 1] + np.clip(target[i] - amb[i - 1], -step, step)
    cond = {"time_s": np.arange(n) * dt} if time_col else {}
    cond["T_ambient_C"] = amb
    if speeds is not None:
        cond["speed_rpm"] = np.repeat(np.asarray(speeds, float), n // len(speeds))
    return cond


def preload_sweep(temps=(-60, -20, 20, 60, 80), loads=tuple(range(50, 351, 50)), rep=3):
    """Seed 000 style preload sweep: assembled preload 50..350 N at several temperatures, each
    point repeated `rep` times, no time column (each point is its own steady test)."""
    T, P = np.meshgrid(np.asarray(temps, float), np.asarray(loads, float), indexing="ij")
    return {"T_ambient_C": np.repeat(T.ravel(), rep),
            "preload_assembled_N": np.repeat(P.ravel(), rep)}


def oil_speed_steps_001():
    """Seed 001 style: -20..40 C in 20 K steps (1 K/min, 12 samples of 2 min per level) at 3500,
    6000 and 9000 rpm (144 rows). 60 C is left out: the 7 N position preload is lost above about
    30 C, and the seed's -20/20/60 C comparison does not need more."""
    return temp_steps(levels=(-20, 0, 20, 40), per=12, dt=120.0, rate_K_min=1.0,
                      speeds=(3500, 6000, 9000))


def oil_speed_steps_003():
    """Seed 003 style: 15..45 C in 10 K steps about the 25 C ambient at 500, 1000 and 1500 rpm
    (144 rows, 2 min samples)."""
    return temp_steps(levels=(15, 25, 35, 45), per=12, dt=120.0, rate_K_min=1.0,
                      speeds=(500, 1000, 1500))


# ============================================================================ fixtures, helpers
@pytest.fixture(scope="module")
def pl000():
    return Pipeline(load_shipped("seed000"), mesh_factor=MESH_FACTOR)


@pytest.fixture(scope="module")
def pl001():
    return Pipeline(load_shipped("seed001"), mesh_factor=MESH_FACTOR)


@pytest.fixture(scope="module")
def pl003():
    return Pipeline(load_shipped("seed003"), mesh_factor=MESH_FACTOR)


@pytest.fixture(scope="module")
def pipelines(pl000, pl001, pl003):
    return {"seed000": pl000, "seed001": pl001, "seed003": pl003}


def noise_free(pl, cond, effects, columns, mu_scale=MU_TRUE):
    """What the real model predicts with the effects on and the rig's friction coefficient."""
    return ModelPredictor(pl, cond, columns)(effects, {"mu_scale": mu_scale})


def largest_change_sigma(pl, cond, effects, sigma, mu_scale=MU_TRUE):
    """Largest change the effect makes that the baseline calibration cannot absorb, in noise units
    (max over rows and measured columns), see the module docstring."""
    cols = tuple(sigma)
    pred = ModelPredictor(pl, cond, cols)
    truth = pred(effects, {"mu_scale": mu_scale})
    lo, hi = NUISANCE["mu_scale"][:2]

    def res(x):
        b = pred({}, {"mu_scale": float(x[0])})
        return np.concatenate([(truth[c] - b[c]) / sigma[c] for c in cols])
    x = optimize.least_squares(res, [mu_scale], bounds=([lo], [hi]), diff_step=1e-4).x
    return float(np.max(np.abs(res(x))))


def baseline_error_rms(pl, cond, effects, sigma, mu_scale=MU_TRUE) -> dict[str, float]:
    """RMS per column (column unit) of what the calibrated baseline cannot reproduce of the
    noise-free data with the effects: the model error, from a least-squares fit of mu_scale
    alone (scipy, independent of the engine)."""
    cols = tuple(sigma)
    pred = ModelPredictor(pl, cond, cols)
    truth = pred(effects, {"mu_scale": mu_scale})
    lo, hi = NUISANCE["mu_scale"][:2]

    def res(x):
        b = pred({}, {"mu_scale": float(x[0])})
        return np.concatenate([(truth[c] - b[c]) / sigma[c] for c in cols])
    x = optimize.least_squares(res, [mu_scale], bounds=([lo], [hi]), diff_step=1e-4).x
    b = pred({}, {"mu_scale": float(x[0])})
    return {c: float(np.sqrt(np.mean((truth[c] - b[c]) ** 2))) for c in cols}


def assert_heldout_gain(pl, cond, effects, sigma, res, mu_scale=MU_TRUE):
    """The held-out RMSEs against what the known noise level and effect size give, in the first
    compared column: the extended (right) model predicts held-out rows to the noise level sigma
    (refitting k parameters on the other blocks inflates it by sqrt(1 + k/n) at most), the
    baseline no better than sigma and the model error e0 together, sqrt(sigma^2 + e0^2) (its
    in-sample best). A root-mean-square of n values with noise has a relative standard error
    of 1/sqrt(2 n): 4 of them are allowed. Hence the ratio is at most
    sigma sqrt(1 + k/n) / sqrt(sigma^2 + e0^2) x (1 + 4/sqrt(2n)) / (1 - 4/sqrt(2n))."""
    c0 = res["columns"][0]
    n = int(np.isfinite(np.asarray(cond[next(iter(cond))], float)).sum())
    s, e0 = sigma[c0], baseline_error_rms(pl, cond, effects, sigma, mu_scale)[c0]
    k = len(res["parameters"]) + 1
    rel = 4.0 / math.sqrt(2 * n)
    ext, base = res["extended"]["heldout_rmse"][c0], res["baseline"]["heldout_rmse"][c0]
    assert s * (1 - rel) <= ext <= s * math.sqrt(1 + k / n) * (1 + rel), (ext, s)
    assert base >= math.hypot(s, e0) * (1 - rel), (base, s, e0)
    bound = s * math.sqrt(1 + k / n) / math.hypot(s, e0) * (1 + rel) / (1 - rel)
    assert res["gain"]["heldout_rmse_ratio_first"] <= bound, (res["gain"], bound, e0)


def measured(pl, cond, effects, sigma, seed, mu_scale=MU_TRUE, drift=None):
    """Noisy measured columns: model + effects + N(0, sigma); `drift` (N mm over the whole test,
    linear in time) is added to the torque as a sensor drift."""
    rng = np.random.default_rng(seed)
    truth = noise_free(pl, cond, effects, tuple(sigma), mu_scale)
    meas = {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in sigma.items()}
    if drift:
        t = cond["time_s"]
        meas["torque_Nmm"] = meas["torque_Nmm"] + drift * (t - t[0]) / (t[-1] - t[0])
    return meas


def diagnose_real(pl, cond, meas):
    """The engine exactly as `bearingfem diagnose` calls it: every candidate in ORDER as the
    assembly sees it (`files.candidate_effects`), the mu_scale nuisance, probes through
    `predict.at`."""
    pred = ModelPredictor(pl, cond, meas.keys())
    out = diagnose_full(pred, meas, cond, candidate_effects(pl.asm), NUISANCE,
                        T_ref_C=pl.asm.T_ref_C, predict_at=pred.at)
    return to_json(out)


def summary(res):
    """Enough of the result to see why an assertion failed."""
    cands = [(c["effect"], c.get("status"), c.get("delta_bic"), c.get("parameters"),
              c.get("reason", "")[:90]) for c in res["candidates"]]
    return (f"verdict {res['verdict']} cause {res['cause']} {res['parameters']} "
            f"indistinguishable {res['indistinguishable']} reasons {res['reasons']} "
            f"candidates {cands}")


def candidate(res, name):
    return next(c for c in res["candidates"] if c["effect"] == name)


def onset_row(T, T_ref, threshold):
    """First row whose temperature deviates from the reference by more than `threshold`
    (the preload_settling definition in docs/cli.md "Effects": "after the first thermal excursion
    beyond +-threshold_K")."""
    return int(np.argmax(np.abs(np.asarray(T) - T_ref) > threshold))


# ============================================================================ the data route
def test_predictor_is_simulate(pl000):
    """The data of these tests (ModelPredictor at mu_scale = 1) is what `simulate --effect` writes
    (`studies.model.pipeline.simulate_table`): same conditions, same effects, same numbers."""
    from studies.model.pipeline import simulate_table

    cond = cycles(n=60)
    eff = {"thermal_lag": {"tau_s": 300.0}, "friction_temperature": {"dmu_per_K": 2e-5}}
    cols = ("torque_Nmm", "preload_N", "interference_inner_um")
    a = noise_free(pl000, cond, eff, cols, mu_scale=1.0)
    b = to_columns(simulate_table(pl000.asm, cond, eff, pipeline=pl000))
    for c in cols:
        np.testing.assert_allclose(a[c], b[c], rtol=1e-12, atol=0)
    # and the effects do change the data (else every test below would be vacuous)
    base = noise_free(pl000, cond, {}, cols, mu_scale=1.0)
    assert np.max(np.abs(a["torque_Nmm"] - base["torque_Nmm"])) > 0.1


# ============================================================================ 1. hidden effects
# (effect, parameters, config, design, measured columns + noise). Each design is one where the
# effect is identifiable: time for the lag and the settling, several speeds for the speed part of
# the radial gradient, an oil bearing for the viscosity law.
SLOW = pytest.mark.slow      # the whole list runs in `make test-slow` (hit rates there as well)
HIDDEN = [
    ("interference_error", {"inner_um": -1.0, "outer_um": 0.5}, "seed000", preload_sweep,
     SIGMA_000),
    pytest.param("radial_gradient", {"dT_K": 1.0, "dT_per_krpm_K": 2.0}, "seed003",
                 oil_speed_steps_003, SIGMA_003, marks=SLOW),
    pytest.param("thermal_lag", {"tau_s": 300.0}, "seed000", cycles, SIGMA_000_TORQUE, marks=SLOW),
    pytest.param("viscosity_temperature", {"slope_factor": 1.01}, "seed001",
                 oil_speed_steps_001, SIGMA_001_TORQUE, marks=SLOW),
    pytest.param("friction_temperature", {"dmu_per_K": 4e-5}, "seed000",
                 lambda: temp_steps(time_col=False), SIGMA_000, marks=SLOW),
    pytest.param("preload_settling", {"loss_N": 5.0, "threshold_K": 50.0}, "seed000", cycles,
                 SIGMA_000, marks=SLOW),
    pytest.param("cte_nonlinearity", {"dalpha_per_K": 4e-9}, "seed000", temp_steps, SIGMA_000,
                 marks=SLOW),
]
#: relative tolerance on a fitted parameter: at >= 8 sigma over >= 100 rows the statistical error
#: of a magnitude is a few per cent (the engine's own uncertainty is checked separately, 5 u);
#: 10 % catches a wrong fit without depending on the noise draw
REL_TOL = 0.10


@pytest.mark.parametrize("name, params, seed_name, design, sigma", HIDDEN,
                         ids=[getattr(h, "values", h)[0] for h in HIDDEN])
def test_hidden_effect_is_named(pipelines, name, params, seed_name, design, sigma):
    pl = pipelines[seed_name]
    cond = design()
    eff = {name: params}
    change = largest_change_sigma(pl, cond, eff, sigma)
    assert change >= MIN_CHANGE_SIGMA, f"test set-up: largest change only {change:.1f} sigma"
    res = diagnose_real(pl, cond, measured(pl, cond, eff, sigma, seed=17))

    assert (res["verdict"], res["cause"]) == ("explained", name), summary(res)
    assert res["indistinguishable"] == [] and res["separating_test"] is None
    assert res["candidates"][0]["effect"] == name
    assert_heldout_gain(pl, cond, eff, sigma, res)
    assert set(res["parameters"]) == SPEC_PARAMETERS[name]
    unc = res["parameter_uncertainty"]
    for p, v in params.items():
        got = res["parameters"][p]
        if p in fitspec.profile(EFFECTS[name]):
            # a profiled threshold is only determined up to the rows it switches: the fitted
            # value must switch at the same row as the true one
            T = cond["T_ambient_C"]
            assert onset_row(T, pl.asm.T_ref_C, got) == onset_row(T, pl.asm.T_ref_C, v), (p, got)
            continue
        assert got == pytest.approx(v, rel=REL_TOL), (p, res["parameters"])
        assert unc[p] is not None and abs(got - v) <= 5 * unc[p], (p, got, v, unc[p])
    # the nuisance calibration found the rig's friction coefficient (the friction effect itself
    # trades against mu_scale near the reference temperature: a looser check there)
    tol = 0.05 if name != "friction_temperature" else 0.15
    assert res["nuisance"]["extended"]["mu_scale"] == pytest.approx(MU_TRUE, rel=tol)
    if seed_name == "seed000":
        # solid film (MoS2): the viscosity law does not enter the model at all
        assert candidate(res, "viscosity_temperature")["status"] == "not_identifiable"


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_interference_error_in_preload_sweep_local_minimum(pl000):
    """A tighter inner fit (-2.4 um) and a nearly nominal outer fit in a preload sweep, rig friction
    0.85 x the config. Regression test: the slow hit-rate test found the fit stuck at the start
    inner = outer = -5 um (outer fit open in every row, so no gradient in outer_um; chi-square
    ~3800 against ~250 at the truth, verdict `unexplained`) after f0294c8; fixed in 69dc0f4."""
    cond = preload_sweep(rep=4)
    params = {"inner_um": -2.4, "outer_um": 0.1}
    sigma = {"torque_Nmm": 0.13, "preload_N": 3.3}
    eff = {"interference_error": params}
    assert largest_change_sigma(pl000, cond, eff, sigma, mu_scale=0.85) >= MIN_CHANGE_SIGMA
    meas = measured(pl000, cond, eff, sigma, seed=1, mu_scale=0.85)
    res = diagnose_real(pl000, cond, meas)
    # the two fits trade against each other in this design (a valley in inner/outer), so only the
    # verdict and the quality of the fit are required, not the parameters
    assert (res["verdict"], res["cause"]) == ("explained", "interference_error"), summary(res)
    assert_heldout_gain(pl000, cond, eff, sigma, res, mu_scale=0.85)


# ============================================================================ 2. null data
#: noise draws of every null test: the first three of a fixed sequence, the same for every design
NULL_DRAWS = (101, 102, 103)
NULL = [
    pytest.param("seed000", cycles, SIGMA_000, marks=SLOW),
    pytest.param("seed000", preload_sweep, SIGMA_000_TORQUE, marks=SLOW),
    pytest.param("seed001", oil_speed_steps_001, SIGMA_001_TORQUE, marks=SLOW),
    pytest.param("seed003", oil_speed_steps_003, SIGMA_003, marks=SLOW),
]


@pytest.mark.parametrize("seed_name, design, sigma", NULL,
                         ids=[(lambda v: f"{v[0]}-{v[1].__name__}")(getattr(n, "values", n))
                              for n in NULL])
def test_null_data_no_discrepancy(pipelines, seed_name, design, sigma):
    """Null data (the model with the rig's friction, plus noise) on NULL_DRAWS noise draws of a
    fixed sequence (not chosen by their outcome): a false alarm (any verdict but
    `no_discrepancy`) is allowed on at most as many draws as the 99.5 % binomial quantile at the
    stated false-alarm level (alpha_structure + alpha_lr: at most 1 of 3), so the test does not
    depend on the draws; every draw without a false alarm reports no cause and the baseline as
    the extended model. The rate over many draws is measured by the slow test."""
    pl = pipelines[seed_name]
    cond = design()
    allowed = int(stats.binom.ppf(0.995, len(NULL_DRAWS), stated_false_alarm_level()))
    alarms = []
    for seed in NULL_DRAWS:
        res = diagnose_real(pl, cond, measured(pl, cond, {}, sigma, seed=seed))
        assert res["nuisance"]["baseline"]["mu_scale"] == pytest.approx(MU_TRUE, rel=0.05)
        for c, s in sigma.items():
            # the noise level is estimated from the data (second differences): within 20 % of
            # the truth at >= 105 rows (relative standard error of a variance estimate ~ sqrt(2/n)
            # ~ 14 % of the variance, half that of sigma; plus the trimming)
            assert res["noise_sigma"][c] == pytest.approx(s, rel=0.2)
        if res["verdict"] != "no_discrepancy":
            alarms.append(summary(res))
            continue
        assert res["cause"] is None and res["parameters"] == {} and res["indistinguishable"] == []
        assert res["gain"]["heldout_rmse_ratio_first"] == 1.0      # extended model = the baseline
    assert len(alarms) <= allowed, alarms


@pytest.mark.slow
def test_viscosity_law_on_solid_film_is_never_claimed(pl000):
    """Seed 000 runs on a MoS2 film: the viscosity law is not part of its torque, so a changed
    law gives exactly the baseline data and the candidate cannot be claimed."""
    cond = temp_steps(time_col=False)
    eff = {"viscosity_temperature": {"slope_factor": 2.0}}
    a = noise_free(pl000, cond, eff, ("torque_Nmm", "preload_N"))
    b = noise_free(pl000, cond, {}, ("torque_Nmm", "preload_N"))
    for c in a:
        np.testing.assert_array_equal(a[c], b[c])
    res = diagnose_real(pl000, cond, measured(pl000, cond, eff, SIGMA_000, seed=8))
    assert res["verdict"] == "no_discrepancy", summary(res)
    assert candidate(res, "viscosity_temperature")["status"] == "not_identifiable"
    assert "viscosity_temperature" in res["not_identifiable"]


# ============================================================================ 3. look-alikes
def best_rival_chi2(pl, cond, truth, rival, sigma):
    """Chi-square (noise units) of the best fit of `rival` + mu_scale to noise-free data: how far
    apart the two explanations are in this design (independent of the engine). `rival=None`: the
    baseline (mu_scale only)."""
    cols = tuple(sigma)
    pred = ModelPredictor(pl, cond, cols)
    e = EFFECTS[rival] if rival else None
    names = list(e.parameters) if e else []
    sc = np.array([e.scale[p] for p in names] + [0.05])
    lo = np.array([e.bounds[p][0] for p in names] + [NUISANCE["mu_scale"][0]]) / sc
    hi = np.array([e.bounds[p][1] for p in names] + [NUISANCE["mu_scale"][1]]) / sc

    def res(u):
        x = u * sc
        effects = {rival: dict(zip(names, x[:-1]))} if e else {}
        out = pred(effects, {"mu_scale": float(x[-1])})
        return np.concatenate([(truth[c] - out[c]) / sigma[c] for c in cols])
    x0 = np.array([e.off[p] for p in names] + [1.0]) / sc
    sol = optimize.least_squares(res, x0, bounds=(lo, hi), diff_step=1e-3)
    return float(2.0 * sol.cost)


# Torque alone (no preload cell) at one speed over 0..40 C (seed 000, solid film): a constant
# radial gradient (inner parts 1 K warmer) and an inner-fit error (about +7 um) both expand the
# inner raceway by a constant amount and shift the preload and so the torque by the same function
# of temperature; the test verifies that the best fit of either to the other's noise-free data is
# within a small fraction of one noise unit of chi-square, while both are far from the baseline.
LOOKALIKE_COND = dict(levels=(0, 10, 20, 30, 40), per=20, time_col=False)


@pytest.mark.parametrize("truth_name, params, rival", [
    pytest.param("radial_gradient", {"dT_K": 1.0}, "interference_error", marks=SLOW),
    pytest.param("interference_error", {"inner_um": 7.0}, "radial_gradient", marks=SLOW),
])
def test_lookalike_pair_is_ambiguous(pl000, truth_name, params, rival):
    cond = temp_steps(**LOOKALIKE_COND)
    sigma = SIGMA_000_TORQUE
    eff = {truth_name: params}
    truth = noise_free(pl000, cond, eff, tuple(sigma))
    chi2_rival = best_rival_chi2(pl000, cond, truth, rival, sigma)
    chi2_base = best_rival_chi2(pl000, cond, truth, None, sigma)
    # precondition: the rival reproduces the data to a small fraction of one unit of chi-square
    # (no design-independent test could tell them apart), the baseline is far off
    assert chi2_rival < 0.5, chi2_rival
    assert chi2_base > 100.0, chi2_base
    res = diagnose_real(pl000, cond, measured(pl000, cond, eff, sigma, seed=23))
    named = {res["cause"], *res["indistinguishable"]}
    assert res["verdict"] == "ambiguous", summary(res)
    assert {truth_name, rival} <= named, summary(res)
    assert res["separating_test"]
    # what separates them physically: the inner part temperatures / a second speed, or measuring
    # the fit or the preload (the effects' hints and the engine's probes)
    assert any(k in res["separating_test"] for k in ("speed", "inner", "preload")), \
        res["separating_test"]


# ============================================================================ 4. outside the list
@pytest.mark.parametrize("seed_name, design, sigma, drift_sigma", [
    pytest.param("seed000", cycles, SIGMA_000, 10.0, marks=SLOW),
    pytest.param("seed001", oil_speed_steps_001, SIGMA_001_TORQUE, 15.0, marks=SLOW),
])
def test_sensor_drift_is_not_claimed(pipelines, seed_name, design, sigma, drift_sigma):
    """A torque-sensor drift linear in time (not a listed effect; `drift_sigma` noise units over
    the test): no listed effect may be claimed."""
    pl = pipelines[seed_name]
    cond = design()
    drift = drift_sigma * sigma["torque_Nmm"]
    res = diagnose_real(pl, cond, measured(pl, cond, {}, sigma, seed=31, drift=drift))
    assert res["verdict"] in ("unexplained", "no_discrepancy"), summary(res)
    assert res["cause"] is None and res["indistinguishable"] == []
    # the drift is far beyond the noise: the baseline residuals must show it
    assert res["verdict"] == "unexplained", summary(res)


def steady_grid():
    """Seed 000 steady points without time: T_ambient -60..80 C in 20 K steps x assembled preload
    50, 100, 200, 350 N, every point measured twice (64 rows)."""
    T, P = np.meshgrid(np.arange(-60.0, 81.0, 20.0), np.array([50.0, 100.0, 200.0, 350.0]),
                       indexing="ij")
    return {"T_ambient_C": np.repeat(T.ravel(), 2), "preload_assembled_N": np.repeat(P.ravel(), 2)}


@pytest.fixture(scope="module")
def pl000_groove():
    """Seed 000 whose inner groove curvature ratio is 0.54 instead of the configured one: a
    geometry error no listed effect describes (a tighter or looser groove changes the contact
    stiffness and the spin, with preload and temperature, not a fit or a temperature field)."""
    from dataclasses import replace

    a = load_shipped("seed000")
    return Pipeline(replace(a, bearing=replace(a.bearing, inner_groove_ratio=0.54)),
                    mesh_factor=MESH_FACTOR)


def unlisted_on_steady_grid(pl000, pl_truth, sigma, seed):
    """(result, largest change in sigma) of one noisy draw of the unlisted groove on the grid."""
    cond = steady_grid()
    truth = noise_free(pl_truth, cond, {}, tuple(sigma))
    pred = ModelPredictor(pl000, cond, tuple(sigma))
    lo, hi = NUISANCE["mu_scale"][:2]

    def res(x):
        b = pred({}, {"mu_scale": float(x[0])})
        return np.concatenate([(truth[c] - b[c]) / sigma[c] for c in sigma])
    x = optimize.least_squares(res, [MU_TRUE], bounds=([lo], [hi]), diff_step=1e-4).x
    change = float(np.max(np.abs(res(x))))
    rng = np.random.default_rng(seed)
    meas = {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in sigma.items()}
    return diagnose_real(pl000, cond, meas), change


def assert_unlisted_verdict(res):
    """No cause claimed (not explained, not ambiguous), and the open-world characterisation ties
    the residual to a condition of the grid (temperature or preload)."""
    assert res["verdict"] == "unexplained", summary(res)
    assert res["cause"] is None and res["indistinguishable"] == [], summary(res)
    ow = res["open_world"]
    lead = {f for c in ow["columns"] if c["depends"] for f in c["selected"]}
    assert any(("T_" in f or "preload" in f or "temperature" in f) for f in lead), ow


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_unlisted_groove_on_a_steady_grid_is_unexplained(pl000, pl000_groove):
    """A cause outside the listed effects on steady points (no time column, so no drift or
    history can be blamed; the model-form ladder, not among these candidates, has a rung that
    names it: tests/test_groove_conformity.py): the data come from seed 000 with the inner groove ratio 0.54 (the candidates' model
    has the configured ratio), torque and preload measured at the SIGMA_000 levels, friction
    1.25 x the configured one. The change is at least 8 sigma (not invisible); the verdict must
    be `unexplained` with no cause and no ambiguous claim."""
    res, change = unlisted_on_steady_grid(pl000, pl000_groove, SIGMA_000, seed=1)
    assert change >= MIN_CHANGE_SIGMA, change
    assert_unlisted_verdict(res)


@pytest.mark.slow          # 12 diagnoses of 64 rows (about 45 s)
@pytest.mark.parametrize("sigma", [SIGMA_000, SIGMA_000_TORQUE], ids=["torque+preload", "torque"])
def test_unlisted_groove_on_a_steady_grid_rate(pl000, pl000_groove, sigma):
    """The same unlisted groove over six noise draws, with torque and preload or torque alone
    (change 21.9 and 12.4 sigma): never a claimed cause, always `unexplained` (measured 6/6 each,
    2026-11-25). With torque alone, draws 1 and 4 were claimed by the forward selection as
    `preload_path_compliance` + `radial_gradient` until a further cause had to fit
    every held-out block in the same amount (`blockscale.block_scale`: Cochran's Q 273 and 117
    on 7 degrees of freedom; docs/diagnosis_rates.md). At a groove ratio of 0.525 the
    torque-only change is 4.5 sigma, below the 8 sigma this file asks of a visible cause: there a small listed effect (a CTE slope change of
    -8e-10 /K or a path compliance of 0.9 um/kN) fits it within the noise in 3 of 6 draws
    (docs/diagnosis.md), a limit of any closed list, not asserted here."""
    for seed in range(1, 7):
        res, change = unlisted_on_steady_grid(pl000, pl000_groove, sigma, seed=seed)
        assert change >= MIN_CHANGE_SIGMA, change
        assert_unlisted_verdict(res)


# ============================================================================ 5. the CLI
CFG_000 = Path(__file__).resolve().parents[1] / "studies" / "configs" / "seed000_71807C_TC4.toml"


def _write_csv(path, cols):
    from studies.model.table import write_table
    write_table(path, cols)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_cli_diagnose_end_to_end(tmp_path, capsys):
    """simulate --effect (CLI) -> noise -> diagnose (CLI): exit 0, the spec's JSON, a report."""
    from studies.app.cli import main
    from studies.model.table import read_table

    cond = cycles(n=200)
    _write_csv(tmp_path / "conditions.csv", cond)
    assert main(["simulate", str(CFG_000), str(tmp_path / "conditions.csv"), "-o",
                 str(tmp_path / "sim.csv"), "--effect", "thermal_lag:tau_s=400"]) == 0
    sim = read_table(tmp_path / "sim.csv")
    rng = np.random.default_rng(3)
    meas = {"time_s": sim["time_s"], "T_ambient_C": sim["T_ambient_C"]}
    for c, s in SIGMA_000.items():
        meas[c] = sim[c] + rng.normal(0.0, s, sim[c].size)
    _write_csv(tmp_path / "measured.csv", meas)
    out = tmp_path / "diag"
    capsys.readouterr()
    code = main(["diagnose", str(CFG_000), str(tmp_path / "measured.csv"), "--out", str(out)])
    cap = capsys.readouterr()
    assert code == 0, cap.err
    assert "diagnosis: explained (thermal_lag)" in cap.out

    res = json.loads((out / "diagnosis.json").read_text())
    assert list(res)[:len(SPEC_KEYS)] == SPEC_KEYS
    assert res["verdict"] in VERDICTS
    assert (res["verdict"], res["cause"]) == ("explained", "thermal_lag"), summary(res)
    assert set(res["parameters"]) == {"tau_s"}
    assert res["parameters"]["tau_s"] == pytest.approx(400.0, rel=REL_TOL)
    assert res["indistinguishable"] == [] and res["separating_test"] is None
    cols = ["torque_Nmm", "preload_N"]               # every measured output column, torque first
    for part in ("baseline", "extended"):
        assert set(res[part]) >= {"rmse", "heldout_rmse"}
        for k in ("rmse", "heldout_rmse"):
            assert list(res[part][k]) == cols
            assert all(isinstance(v, float) and v >= 0 for v in res[part][k].values())
    ratio = res["extended"]["heldout_rmse"]["torque_Nmm"] / res["baseline"]["heldout_rmse"]["torque_Nmm"]
    assert res["gain"]["heldout_rmse_ratio_first"] == pytest.approx(ratio, rel=1e-9)
    assert res["gain"]["heldout_rmse_ratio_first"] < 1.0
    # the listed effects, then the model-form ladder's rungs (studies/diagnosis/ladder.py)
    assert {c["effect"] for c in res["candidates"] if c["kind"] == "effect"} == set(ORDER)
    from studies.diagnosis.ladder import ladder
    assert ({c["effect"] for c in res["candidates"] if c["kind"] == "model_form"}
            == {r.name for r in ladder(load_shipped("seed000"))})
    for c in res["candidates"]:
        assert set(c) >= {"effect", "parameters", "delta_bic", "heldout_rmse"}
        if c["delta_bic"] is not None and c["kind"] == "effect":   # the spec's parameter names
            assert set(c["parameters"]) == SPEC_PARAMETERS[c["effect"]]
    # sorted best first: candidates that pass by delta BIC, then the other fitted ones by delta
    # BIC, then those not fitted (not applicable / not identifiable here)
    assert res["candidates"][0]["effect"] == "thermal_lag"
    key = [(c.get("status") != "passed", c["delta_bic"]) for c in res["candidates"]
           if c["delta_bic"] is not None]
    assert key == sorted(key)
    n_fit = len(key)
    assert all(c["delta_bic"] is None for c in res["candidates"][n_fit:])
    report = out / "report.md"
    assert report.exists() and "thermal_lag" in report.read_text()
    pngs = list(out.glob("*.png"))
    assert pngs and all(p.stat().st_size > 1000 for p in pngs)
    text = report.read_text()
    assert all(f"({p.name})" in text for p in pngs if p.name.startswith(("fit_", "residuals_")))
    # the 90 % predictive interval in diagnosis.csv on every row, in the JSON and the
    # report; a fresh noise draw of the simulated truth (another run of the rig) falls inside
    # it in 84-96 % of the 400 entries (binomial spread 1.5 % about 90 %)
    assert res["interval"]["level"] == 0.9 and "## Predictive interval" in text
    assert 0.8 <= res["interval"]["coverage_calibration"] <= 1.0
    table = read_table(out / "diagnosis.csv")
    assert np.array_equal(table["row"], np.arange(1, sim["time_s"].size + 1))
    rng = np.random.default_rng(4)
    inside = 0
    for c in cols:
        lo, mid, hi = (table[f"predicted_{x}{c}"] for x in ("lo_", "", "hi_"))
        assert np.all(lo < mid) and np.all(mid < hi)
        again = sim[c] + rng.normal(0.0, SIGMA_000[c], sim[c].size)
        inside += int(np.sum((again >= lo) & (again <= hi)))
    assert 0.84 <= inside / (2 * sim["time_s"].size) <= 0.96, inside


def _bad_inputs(tmp):
    """(label, measured file) pairs with one problem each, and what the message must name."""
    good = {"time_s": np.arange(10.0) * 60, "T_ambient_C": np.linspace(20, 60, 10),
            "torque_Nmm": np.full(10, 1.5)}
    cases = []

    def write(name, text):
        p = tmp / name
        p.write_text(text)
        return p

    def csv_text(cols):
        keys = list(cols)
        rows = [",".join(keys)] + [",".join(f"{cols[k][i]:g}" for k in keys)
                                   for i in range(len(cols[keys[0]]))]
        return "\n".join(rows) + "\n"

    bad = dict(good, vibration_g=np.zeros(10))
    cases.append(("unknown column", write("unknown.csv", csv_text(bad)), "vibration_g"))
    text = csv_text(good).splitlines()
    text[4] = text[4].rsplit(",", 1)[0] + ",nan"
    cases.append(("NaN", write("nan.csv", "\n".join(text) + "\n"), "torque_Nmm"))
    noout = {k: v for k, v in good.items() if k != "torque_Nmm"}
    cases.append(("no output column", write("noout.csv", csv_text(noout)), "output"))
    t = good["time_s"].copy()
    t[6] = t[5]
    cases.append(("time not increasing", write("time.csv", csv_text(dict(good, time_s=t))),
                  "time_s"))
    cases.append(("missing file", tmp / "does_not_exist.csv", "not found"))
    text = csv_text(good).splitlines()
    text[3] = text[3].replace("1.5", "1.5x")
    cases.append(("non-numeric", write("text.csv", "\n".join(text) + "\n"), "not a number"))
    cases.append(("empty", write("empty.csv", "time_s,T_ambient_C,torque_Nmm\n"), "empty"))
    return cases


def test_cli_diagnose_bad_input_exits_2(tmp_path, capsys):
    from studies.app.cli import main

    for label, path, must in _bad_inputs(tmp_path):
        out = tmp_path / "runs" / f"out_{label.replace(' ', '_')}"
        capsys.readouterr()
        code = main(["diagnose", str(CFG_000), str(path), "--out", str(out)])
        cap = capsys.readouterr()
        lines = [ln for ln in cap.err.splitlines() if ln.strip()]
        assert code == 2, (label, cap.err)
        assert len(lines) == 1, (label, cap.err)
        assert str(path) in lines[0] and must in lines[0], (label, lines[0])
        assert "Traceback" not in cap.err
        assert not out.exists(), label
        # no temporary folder left beside it either
        leftovers = [p.name for p in out.parent.iterdir()] if out.parent.exists() else []
        assert leftovers == [], (label, leftovers)
    # a missing assembly file too
    out = tmp_path / "runs" / "out_cfg"
    capsys.readouterr()
    code = main(["diagnose", str(tmp_path / "nope.toml"), str(_bad_inputs(tmp_path)[0][1]),
                 "--out", str(out)])
    cap = capsys.readouterr()
    assert code == 2 and len(cap.err.strip().splitlines()) == 1 and "nope.toml" in cap.err
    assert not out.exists()


@pytest.mark.slow          # a full diagnosis of 240 rows (about 8 s)
def test_noise_free_model_output_is_no_discrepancy(tmp_path):
    """simulate's own output, written with 10 significant digits and diagnosed against the same
    model: the residuals are round-off of the CSV, which is no discrepancy (it once came out as
    'explained' by an interference error of 9e-12 um)."""
    import json

    from studies.app.cli import main
    from studies.model.config import CONFIG_DIR

    cfg = CONFIG_DIR / "seed000_71807C_TC4.toml"
    t = np.arange(0.0, 12 * 3600.0 + 1, 900.0)
    T = 20 + 60 * np.sin(2 * np.pi * t / (4 * 3600.0))
    cond = tmp_path / "c.csv"
    cond.write_text("time_s,T_ambient_C\n" + "".join(f"{a:.1f},{b:.6f}\n" for a, b in zip(t, T)))
    sim = tmp_path / "sim.csv"
    assert main(["simulate", str(cfg), str(cond), "-o", str(sim)]) == 0
    assert main(["diagnose", str(cfg), str(sim), "--out", str(tmp_path / "d")]) == 0
    result = json.loads((tmp_path / "d" / "diagnosis.json").read_text())
    assert result["verdict"] == "no_discrepancy", (result["verdict"], result.get("cause"))


def test_fitted_parameters_stay_inside_what_the_assembly_allows():
    """A settling loss cannot exceed the assembled preload (seed 001: 7 N); an interference
    error stays inside the fit's tolerance band around the mean fit where one is given."""
    from dataclasses import replace

    from studies.model.effects import EFFECTS, assembly_bounds

    a001 = load_shipped("seed001")
    b = assembly_bounds(a001)
    assert b["preload_settling"]["loss_N"] == (0.0, a001.preload.assembled_N)
    eff = EFFECTS["preload_settling"].with_bounds(**b["preload_settling"])
    assert eff.bounds["loss_N"] == (0.0, 7.0) and EFFECTS["preload_settling"].bounds["loss_N"][1] == 2000.0
    a000 = load_shipped("seed000")
    tol = replace(a000, fits=replace(a000.fits, inner_interference_um=0.0,
                                     inner_shaft_deviation_um=(2.0, 13.0),
                                     inner_ring_bore_deviation_um=(-6.0, 0.0)))
    # band 2..19 um around the mean 10.5 um
    assert assembly_bounds(tol)["interference_error"]["inner_um"] == (-8.5, 8.5)


def test_cli_candidates_carry_the_assembly_bounds():
    """The candidates `diagnose` fits (`files.candidate_effects`) carry the assembly's bounds:
    seed 001 (7 N assembled) a settling loss in [0, 7] N; on a toleranced seed 000 (shaft
    +2..+13 um, bore -6..0 um on a 0 um nominal fit: fits 2..19 um, mean 10.5 um) an inner
    interference error in [-8.5, +8.5] um around the mean fit, none on the outer fit (its
    deviations are 0: a band of zero width); the run-in knows the configured speed and lubrication."""
    from dataclasses import replace

    by = {e.name: e for e in candidate_effects(load_shipped("seed001"))}
    assert by["preload_settling"].bounds["loss_N"] == (0.0, 7.0)
    assert by["solid_film_runin"].applicable({"time_s": np.arange(10.0)}) is not None  # oil
    a000 = load_shipped("seed000")
    tol = replace(a000, fits=replace(a000.fits, inner_interference_um=0.0,
                                     inner_shaft_deviation_um=(2.0, 13.0),
                                     inner_ring_bore_deviation_um=(-6.0, 0.0)))
    by = {e.name: e for e in candidate_effects(tol)}
    assert by["interference_error"].bounds["inner_um"] == (-8.5, 8.5)
    # the outer fit's deviations are left at 0 in this assembly: its band is the nominal fit
    assert by["interference_error"].bounds["outer_um"] == (0.0, 0.0)
    assert by["preload_settling"].bounds["loss_N"] == (0.0, a000.preload.assembled_N)
    assert by["solid_film_runin"].speed_rpm == a000.lubrication.speed_rpm == 60.0
    assert by["solid_film_runin"].applicable({"time_s": np.arange(10.0)}) is None


def _ar1_noise(rng, n, sigma, phi):
    """Stationary AR(1) noise of marginal standard deviation sigma (a slowly drifting sensor)."""
    e = np.empty(n)
    e[0] = rng.normal(0.0, sigma)
    for i in range(1, n):
        e[i] = phi * e[i - 1] + rng.normal(0.0, sigma * np.sqrt(1 - phi ** 2))
    return e


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_correlated_noise_alone_is_no_discrepancy(pl000):
    """AR(1) noise (phi 0.8, 2 % of the torque) on a -60 <-> 80 C cycle with nothing hidden: the
    engine finds the serial correlation, whitens it and says no_discrepancy (it said 'unexplained:
    the baseline is clearly wrong'). The rate over 20 draws is in the slow suite."""
    cond = cycles(n=240)
    truth = noise_free(pl000, cond, {}, ("torque_Nmm",))
    sig = 0.02 * float(np.mean(np.abs(truth["torque_Nmm"])))
    meas = {"torque_Nmm": truth["torque_Nmm"] + _ar1_noise(np.random.default_rng(3), 240, sig, 0.8)}
    res = diagnose_real(pl000, cond, meas)
    assert res["verdict"] == "no_discrepancy", summary(res)
    assert res["residuals"]["baseline"]["columns"]["torque_Nmm"]["noise_ar1"] > 0.5


@pytest.mark.slow          # a full diagnosis of 240 rows (about 8 s)
def test_hidden_effect_is_found_through_correlated_noise(pl000):
    """The whitening does not hide a real cause: a thermal lag (300 s) under the same AR(1) noise
    (phi 0.8, 0.02 N mm) is still explained, and by the lag."""
    cond = cycles(n=240)
    truth = noise_free(pl000, cond, {"thermal_lag": {"tau_s": 300.0}}, ("torque_Nmm",))
    meas = {"torque_Nmm": truth["torque_Nmm"] + _ar1_noise(np.random.default_rng(1), 240, 0.02, 0.8)}
    res = diagnose_real(pl000, cond, meas)
    assert res["verdict"] == "explained" and res["cause"] == "thermal_lag", summary(res)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_noise_level_of_a_steady_grid_comes_from_the_design(pl000):
    """Temperature x preload grid (no time, no replicates) with a model error (inner fit 3.5 um
    smaller): estimated along each condition of the design, the torque noise level is within
    0.7..1.5 of the true one (row-order second differences gave 3.4..4.0x: the jump between grid
    lines is model error, not noise)."""
    T, P = np.meshgrid(np.arange(0.0, 81, 10), np.array([50.0, 100, 200, 350]), indexing="ij")
    cond = {"T_ambient_C": T.ravel(), "preload_assembled_N": P.ravel()}
    truth = noise_free(pl000, cond, {"interference_error": {"inner_um": -3.5, "outer_um": 0.0}},
                       ("torque_Nmm",))
    sig = 0.02 * float(np.mean(np.abs(truth["torque_Nmm"])))
    rng = np.random.default_rng(2)
    res = diagnose_real(pl000, cond, {"torque_Nmm": truth["torque_Nmm"] + rng.normal(0, sig, 36)})
    assert 0.7 < res["noise_sigma"]["torque_Nmm"] / sig < 1.5, res["noise_sigma"]
    assert "design" in res["noise_sigma_source"]["torque_Nmm"]
    assert res["verdict"] != "explained" or res["cause"] == "interference_error", summary(res)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_a_fit_error_near_opening_is_found_by_the_global_search(pl000):
    """The fit that nearly opens: seed 000's inner fit 4 um smaller than built (5 -> 1 um), a
    T x preload grid without time, 1.5 % noise. The residual of the fit error is piecewise smooth
    with a narrow valley; the global search along each fit finds it: explained by
    interference_error, the inner offset within 1 um (a local fit from a few starts ended on the
    -20 um bound and the verdict was a wrong cause or unexplained)."""
    T, P = np.meshgrid(np.arange(-20.0, 81, 20), np.array([60.0, 120, 240]), indexing="ij")
    cond = {"T_ambient_C": T.ravel(), "preload_assembled_N": P.ravel()}
    truth = noise_free(pl000, cond, {"interference_error": {"inner_um": -4.0, "outer_um": 0.0}},
                       ("torque_Nmm", "preload_N"))
    rng = np.random.default_rng(5)
    meas = {c: v + rng.normal(0, 0.015 * float(np.mean(np.abs(v))), v.size) for c, v in truth.items()}
    res = diagnose_real(pl000, cond, meas)
    assert res["verdict"] == "explained" and res["cause"] == "interference_error", summary(res)
    assert abs(res["parameters"]["inner_um"] + 4.0) < 1.0, res["parameters"]


@pytest.mark.slow          # a full diagnosis of 240 rows (about 8 s)
def test_spikes_are_flagged_not_fitted(pl000):
    """Six torque spikes of 1..3 N mm (50..150 sigma; solid-film bearings show them) on a
    thermal-lag cycle: the spikes are found (their rows reported) and left out, and the lag is
    still explained (with them in the fit the verdict was 'unexplained')."""
    cond = cycles(n=240)
    truth = noise_free(pl000, cond, {"thermal_lag": {"tau_s": 300.0}}, ("torque_Nmm",))
    rng = np.random.default_rng(0)
    t = truth["torque_Nmm"] + rng.normal(0, 0.02, 240)
    idx = rng.choice(240, 6, replace=False)
    t[idx] += rng.choice([-1, 1], 6) * rng.uniform(1.0, 3.0, 6)
    res = diagnose_real(pl000, cond, {"torque_Nmm": t})
    assert sorted(res["spikes"]["torque_Nmm"]) == sorted(int(i) + 1 for i in idx)
    assert res["verdict"] == "explained" and res["cause"] == "thermal_lag", summary(res)


@pytest.mark.slow          # 4 diagnoses of 64 rows plus the finer-mesh truth (about 60 s)
def test_unlisted_groove_made_another_way_is_not_claimed_by_listed_causes(pl000):
    """The same unlisted groove (inner ratio 0.54) with its data made another way: the
    second-source truth on the finer mesh (0.7 x) with direct FE solves
    (`second_source.make_case("groove_curvature")`, the case's own noise), torque alone,
    diagnosed with the listed candidates only (no ladder, so no rung can name it): no cause may
    be claimed (the block rule against two listed causes composing it; without it
    seed 0 was `explained` by a path compliance of 3.5 um/kN plus a radial gradient)."""
    from studies.validation import second_source as ss

    for seed in range(4):
        case = ss.make_case("groove_curvature", seed=seed, mesh_factor=MESH_FACTOR)
        meas = {"torque_Nmm": case.measured["torque_Nmm"]}
        res = diagnose_real(pl000, case.conditions, meas)
        assert res["verdict"] not in ("explained", "explained_partly", "ambiguous"), summary(res)
        assert res["cause"] is None, summary(res)
