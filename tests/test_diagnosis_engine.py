"""Diagnosis engine on a toy bearing model: hidden effects found, null data left alone, look-alikes
called ambiguous, an effect outside the list not claimed.

The toy model evaluates a `PhysicsInputs` transformed by the real effects (so the effects' shapes
are the real ones) with closed-form stand-ins for the FE and the bearing model:

    fit_inner_um = 5 + d_i + 35e3 (a_s dT_s + da/2 dT_s^2 - a_r dT_ir)        (-0.05 um/K, seed 000)
    fit_outer_um = -1.5 + d_o + 47e3 (a_r dT_or - a_h dT_h - da/2 dT_h^2)       (+0.07 um/K)
    preload_N    = P_a - loss + 2 (max(fit_i, 0) - 5) + 3 max(fit_o, 0) + 0.4 (T_mean - T_ref)
                   + 6 (T_ir - T_or) + 3 (T_ball - T_or)
    torque_Nmm   = mu_scale mu(T) preload + 0.004 preload + c_visc (speed/1000 nu(T_ball)/nu_40)^(2/3)
    nu/nu_40     = exp(-0.035 slope_factor (T_ball - 40))

with a_s = a_h = 8.6e-6 /K (TC4), a_r = 10.1e-6 /K (9Cr18), mu = 0.02 (MoS2). The numbers only
give realistic orders of magnitude (torque ~2.4 N mm at 100 N; preload +-30 N over -60..80 C).
"""
from __future__ import annotations


import numpy as np
import pytest

from studies.diagnosis import fitspec
from studies.diagnosis.engine import diagnose, diagnose_full
from studies.diagnosis.result import to_json
from studies.diagnosis.stats import chibar_pvalue, noise_sigma
from studies.model.effects import (EFFECTS, apply_effects, resolve_friction_coefficient,
                             resolve_interference_um)
from studies.model.inputs import baseline_inputs

T_REF = 20.0
NUISANCE = {"mu_scale": (0.2, 5.0, 1.0)}
SIGMA = {"torque_Nmm": 0.02, "preload_N": 0.5}
SPEC_KEYS = ["verdict", "cause", "parameters", "indistinguishable", "separating_test", "baseline",
             "extended", "gain", "candidates"]


class ToyBearing:
    """Closed-form stand-in for the pipeline (see the module docstring)."""

    def __init__(self, c_visc=0.0, preload_N=100.0, speed_rpm=60.0, mu=0.02):
        self.c_visc, self.P, self.speed, self.mu = c_visc, preload_N, speed_rpm, mu

    def evaluate(self, conditions, effects, nuisance):
        n = len(next(iter(conditions.values())))
        pi = baseline_inputs(conditions, n, T_REF, self.P, self.speed)
        pi = apply_effects(pi, effects, T_REF)
        T = {k: np.asarray(v, float) - T_REF for k, v in pi.T_C.items()}
        da_s = pi.dalpha_per_K2.get("shaft", 0.0)
        da_h = pi.dalpha_per_K2.get("housing", 0.0)
        fi0, fo0 = resolve_interference_um(pi, 5.0, -1.5)
        fit_i = fi0 + 35e3 * (8.6e-6 * T["shaft"] + 0.5 * da_s * T["shaft"] ** 2
                              - 10.1e-6 * T["inner_ring"])
        fit_o = fo0 + 47e3 * (10.1e-6 * T["outer_ring"] - 8.6e-6 * T["housing"]
                              - 0.5 * da_h * T["housing"] ** 2)
        loss = 0.0 if pi.preload_loss_N is None else pi.preload_loss_N
        T_mean = np.mean([T[p] for p in ("shaft", "inner_ring", "ball", "outer_ring", "housing")],
                         axis=0)
        preload = (pi.preload_assembled_N - loss + 2.0 * (np.maximum(fit_i, 0) - 5.0)
                   + 3.0 * np.maximum(fit_o, 0) + 0.4 * T_mean
                   + 6.0 * (T["inner_ring"] - T["outer_ring"]) + 3.0 * (T["ball"] - T["outer_ring"]))
        preload = np.maximum(preload, 0.0)
        mu = nuisance.get("mu_scale", 1.0) * resolve_friction_coefficient(pi, self.mu)
        nu = np.exp(-0.035 * pi.viscosity_slope_factor * (T["ball"] + T_REF - 40.0))
        torque = (mu * preload + 0.004 * preload
                  + self.c_visc * (pi.speed_rpm / 1000.0 * nu) ** (2.0 / 3.0))
        return {"torque_Nmm": torque, "preload_N": preload, "interference_inner_um": fit_i,
                "interference_outer_um": fit_o}

    def assembly(self):
        """The assembly the toy stands for, as `diagnose` reads it: seed 000 (MoS2 film) with the
        toy's preload and speed, oil-lubricated when the toy has a viscous term. Candidates are
        built from it exactly as the CLI builds them (`files.candidate_effects`)."""
        from dataclasses import replace
        from studies.model.config import load_shipped
        a = load_shipped("seed000")
        kind = "oil" if self.c_visc > 0 else "solid_film"
        return replace(a, preload=replace(a.preload, assembled_N=self.P),
                       lubrication=replace(a.lubrication, kind=kind, speed_rpm=self.speed,
                                           friction_coefficient=self.mu))

    def predictor(self, conditions):
        def predict(effects, nuisance):
            return self.evaluate(conditions, effects, nuisance)

        def predict_at(effects, nuisance, cond):
            return self.evaluate(cond, effects, nuisance)
        return predict, predict_at


# ------------------------------------------------------------------------ test designs
def cycles(n=500, dt=60.0, speeds=(60.0,)):
    """Alternating -60 <-> 80 C cycles (ramps of 2 K/min with dwells), seed 000 style; the speed
    changes between cycles when several are given."""
    t = np.arange(n) * dt
    pattern = [(20, 0), (80, 30), (80, 40), (-60, 70), (-60, 40), (80, 70), (80, 40), (20, 30)]
    knots_t, knots_T = [0.0], [20.0]
    while knots_t[-1] < t[-1]:
        for T, mins in pattern[1:]:
            knots_t.append(knots_t[-1] + mins * 60.0)
            knots_T.append(float(T))
    amb = np.interp(t, knots_t, knots_T)
    speed = np.asarray(speeds, float)[(np.arange(n) * len(speeds)) // n]
    return {"time_s": t, "T_ambient_C": amb, "speed_rpm": speed}


def speed_steps(n=480, dt=60.0):
    """Temperature steps (0, 20, 40, 60 C with dwells) repeated at 3000, 6000, 9000 rpm."""
    t = np.arange(n) * dt
    levels = np.array([0.0, 20.0, 40.0, 60.0])
    k = (np.arange(n) * 12) // n
    target = levels[k % 4]
    amb = np.empty(n)
    amb[0] = target[0]
    for i in range(1, n):                     # the chamber follows its set point at 3 K/min
        step = np.clip(target[i] - amb[i - 1], -3.0, 3.0)
        amb[i] = amb[i - 1] + step
    speed = np.array([3000.0, 6000.0, 9000.0])[k // 4]
    return {"time_s": t, "T_ambient_C": amb, "speed_rpm": speed}


def make_data(model, cond, effects, seed, sigma=SIGMA, drift=None, mu_scale=1.0):
    rng = np.random.default_rng(seed)
    out = model.evaluate(cond, effects, {"mu_scale": mu_scale})
    meas = {c: out[c] + rng.normal(0.0, s, out[c].size) for c, s in sigma.items()}
    if drift:
        meas["torque_Nmm"] = meas["torque_Nmm"] + drift * cond["time_s"] / cond["time_s"][-1]
    return meas


def run_full(model, cond, meas, candidates=None, **kw):
    """The typed `DiagnosisResult`."""
    predict, predict_at = model.predictor(cond)
    cands = [EFFECTS[n] for n in (candidates or EFFECTS)]
    return diagnose_full(predict, meas, cond, cands, NUISANCE, predict_at=predict_at,
                         T_ref_C=T_REF, **kw)


def run(model, cond, meas, candidates=None, **kw):
    """The result as diagnosis.json holds it."""
    return to_json(run_full(model, cond, meas, candidates, **kw))


# ------------------------------------------------------------------------ unit pieces
def test_noise_sigma_estimator_ignores_smooth_structure_and_steps():
    rng = np.random.default_rng(1)
    x = np.linspace(0, 1, 2000)
    noise = rng.normal(0, 0.3, x.size)
    signal = 5 * np.sin(6 * x) + np.where(x > 0.5, 4.0, 0.0)
    s = noise_sigma(signal + noise, np.zeros(x.size, int))
    assert abs(s - 0.3) < 0.03            # sampling error of the estimate ~ 2-3 % at 2000 rows


def test_chibar_pvalue():
    from scipy import stats
    assert chibar_pvalue(3.0, 1, 0) == pytest.approx(stats.chi2.sf(3.0, 1))
    assert chibar_pvalue(3.0, 0, 1) == pytest.approx(0.5 * stats.chi2.sf(3.0, 1))
    assert chibar_pvalue(0.0, 0, 1) == 1.0 * 0.5 + 0.5 * 1.0


# ------------------------------------------------------------------------ verdicts
@pytest.fixture(scope="module")
def solid():
    return ToyBearing()


def test_null_data_no_discrepancy(solid):
    cond = cycles()
    for seed in (11, 12):
        res = run(solid, cond, make_data(solid, cond, {}, seed, mu_scale=1.3))
        assert list(res)[:len(SPEC_KEYS)] == SPEC_KEYS
        assert res["verdict"] == "no_discrepancy", res["reasons"]
        assert res["cause"] is None and res["parameters"] == {} and res["indistinguishable"] == []
        assert res["separating_test"] is None
        assert res["nuisance"]["baseline"]["mu_scale"] == pytest.approx(1.3, rel=0.02)
        assert res["gain"]["heldout_rmse_ratio_first"] == 1.0
        # the noise level was estimated from the data
        assert res["noise_sigma"]["torque_Nmm"] == pytest.approx(0.02, rel=0.15)
        # solid film: the viscosity law cannot matter
        assert "viscosity_temperature" in res["not_identifiable"]


@pytest.mark.parametrize("name, params, design", [
    ("thermal_lag", {"tau_s": 400.0}, "cycles"),
    ("preload_settling", {"loss_N": 4.0, "threshold_K": 50.0}, "cycles"),
    ("friction_temperature", {"dmu_per_K": 2e-5}, "cycles"),
    ("cte_nonlinearity", {"dalpha_per_K": 1e-8}, "cycles"),
    ("interference_error", {"inner_um": 0.0, "outer_um": 2.0}, "cycles"),
    ("radial_gradient", {"dT_K": 0.0, "dT_per_krpm_K": 0.6}, "speeds"),
    ("viscosity_temperature", {"slope_factor": 1.4}, "speeds"),
])
def test_hidden_effect_is_named(name, params, design):
    model = ToyBearing() if design == "cycles" else ToyBearing(c_visc=0.5, speed_rpm=6000.0)
    cond = cycles() if design == "cycles" else speed_steps()
    meas = make_data(model, cond, {name: params}, seed=3)
    res = run(model, cond, meas)
    assert res["verdict"] == "explained", (res["verdict"], res["cause"], res["reasons"],
                                           res["indistinguishable"])
    assert res["cause"] == name
    for p, v in params.items():
        if p in fitspec.profile(EFFECTS[name]):
            continue
        unc = res["parameter_uncertainty"][p]
        assert abs(res["parameters"][p] - v) < 5 * unc + 1e-12 * abs(v), (p, res["parameters"], unc)
    assert res["gain"]["heldout_rmse_ratio_first"] < 0.9
    assert res["candidates"][0]["effect"] == name


def test_lookalike_pair_is_ambiguous_or_right(solid):
    # one speed, torque and preload measured: an inner-fit error and a constant radial gradient
    # both shift the preload by a constant -> the same residual shape
    cond = cycles(n=400)
    meas = make_data(solid, cond, {"interference_error": {"inner_um": 3.0}}, seed=5)
    res = run(solid, cond, meas, candidates=["interference_error", "radial_gradient",
                                             "thermal_lag", "friction_temperature"])
    assert res["verdict"] in ("ambiguous", "explained"), res["reasons"]
    if res["verdict"] == "explained":
        assert res["cause"] == "interference_error"
    else:
        assert {res["cause"], *res["indistinguishable"]} >= {"interference_error",
                                                            "radial_gradient"}
        assert res["separating_test"]
        assert res["lookalike"]["interference_error"]["radial_gradient"] > 0.95
        # the separating test names a speed change or a fit measurement
        assert "speed" in res["separating_test"] or "interference_inner_um" in res["separating_test"]


def test_effect_outside_the_list_not_claimed(solid):
    # a sensor drift of the torque in time (2.5 % of the torque over the test, 5 sigma)
    cond = cycles()
    meas = make_data(solid, cond, {}, seed=7, drift=0.1)
    res = run(solid, cond, meas)
    assert res["verdict"] in ("unexplained", "no_discrepancy"), (res["verdict"], res["cause"],
                                                                  res["reasons"])
    assert res["cause"] is None
    # nothing claimed: the configured model's interval (test_configured_interval.py)
    assert res["interval"]["model"] == "configured" and res["interval"]["level"] == 0.9


def test_requires_time_and_json_ready(solid):
    cond = cycles(n=200)
    cond_no_time = {k: v for k, v in cond.items() if k != "time_s"}
    meas = make_data(solid, cond, {"friction_temperature": {"dmu_per_K": 3e-5}}, seed=2)
    predict, _ = solid.predictor(cond_no_time)
    res = diagnose(predict, meas, cond_no_time, list(EFFECTS.values()), NUISANCE)
    for n in ("thermal_lag", "preload_settling"):
        c = next(c for c in res["candidates"] if c["effect"] == n)
        assert c["status"] == "not_applicable" and "time_s" in c["reason"]
    import json
    json.dumps(res, allow_nan=False)
    assert res["cause"] == "friction_temperature"


def test_report_written(solid, tmp_path):
    from studies.diagnosis.report import write_report
    cond = cycles(n=300)
    meas = make_data(solid, cond, {"preload_settling": {"loss_N": 5.0, "threshold_K": 40.0}}, 4)
    predict, predict_at = solid.predictor(cond)
    out = diagnose_full(predict, meas, cond, list(EFFECTS.values()), NUISANCE,
                        predict_at=predict_at)
    path = write_report(out, cond, meas, tmp_path)
    text = path.read_text()
    assert out.cause == "preload_settling"
    assert "Verdict: `explained`" in text and "`loss_N`" in text
    # the loss the report states is the injected 5 N within 5 of its stated uncertainties
    row = next(line for line in text.splitlines() if line.startswith("| `loss_N` |"))
    value, unc = (float(x) for x in row.split("|")[2].split("±"))
    assert abs(value - 5.0) < 5 * unc, row
    for c in ("torque_Nmm", "preload_N"):
        for f in (f"fit_{c}.png", f"residuals_{c}.png"):
            assert f"({f})" in text and (tmp_path / f).stat().st_size > 1000
    assert (tmp_path / "candidates.png").exists()
    # the profiled threshold brackets the true onset (the largest excursion before it)
    thr = out.parameter_uncertainty["threshold_K"]["interval"]
    assert thr[0] - 5 <= 40.0 <= thr[1] + 5


def test_noiseless_data(solid):
    # simulate without noise: the noise level is estimated as (almost) zero; round-off residuals
    # of the right effect are not "structure"
    cond = cycles(n=300)
    truth = solid.evaluate(cond, {"thermal_lag": {"tau_s": 500.0}}, {"mu_scale": 1.0})
    res = run(solid, cond, {c: truth[c] for c in SIGMA})
    assert (res["verdict"], res["cause"]) == ("explained", "thermal_lag")
    assert res["parameters"]["tau_s"] == pytest.approx(500.0, rel=1e-6)
    base = solid.evaluate(cond, {}, {"mu_scale": 1.2})
    assert run(solid, cond, {c: base[c] for c in SIGMA})["verdict"] == "no_discrepancy"


def test_missing_values_and_given_blocks(solid):
    cond = cycles(n=300)
    meas = make_data(solid, cond, {"cte_nonlinearity": {"dalpha_per_K": 1e-8}}, seed=1)
    meas["torque_Nmm"][::7] = np.nan             # torque not logged in some rows
    res = run(solid, cond, meas, blocks=np.arange(300) // 60)      # 5 test segments
    assert (res["verdict"], res["cause"]) == ("explained", "cte_nonlinearity")
    assert res["heldout"]["blocks"] == 5
    assert res["parameters"]["dalpha_per_K"] == pytest.approx(1e-8, rel=0.1)


def test_model_failure_marks_candidate_only(solid):
    cond = cycles(n=300)
    meas = make_data(solid, cond, {"friction_temperature": {"dmu_per_K": 3e-5}}, seed=1)

    def predict(effects, nuisance):
        if effects.get("cte_nonlinearity", {}).get("dalpha_per_K", 0.0) != 0.0:
            raise RuntimeError("CTE slope not supported")
        out = solid.evaluate(cond, effects, nuisance)
        if effects.get("thermal_lag", {}).get("tau_s", 0.0) > 2000.0:
            out["torque_Nmm"] = out["torque_Nmm"] * np.nan      # outside the model's range
        return out
    res = diagnose(predict, meas, cond, list(EFFECTS.values()), NUISANCE)
    assert (res["verdict"], res["cause"]) == ("explained", "friction_temperature")
    c = next(c for c in res["candidates"] if c["effect"] == "cte_nonlinearity")
    assert c["status"] == "model_failed" and "CTE slope not supported" in c["reason"]


def test_ar1_statistics_recover_the_coefficient_and_invert():
    """Prais-Winsten whitening inverts exactly; on simulated AR(1) noise (phi 0.7, 20 segments of
    250) the maximum-likelihood estimate recovers phi within 4 standard errors
    (sqrt((1 - phi^2) / n)), and white noise gives no AR(1)."""
    from studies.diagnosis.stats import ar1_regression_ml, ar1_unwhiten, ar1_whiten

    rng = np.random.default_rng(0)
    seg = np.repeat(np.arange(20), 250)
    n, phi = seg.size, 0.7
    e = np.empty(n)
    for i in range(n):
        start = i == 0 or seg[i] != seg[i - 1]
        e[i] = rng.normal() if start else phi * e[i - 1] + rng.normal() * np.sqrt(1 - phi ** 2)
    w = ar1_whiten(e, seg, phi)
    np.testing.assert_allclose(ar1_unwhiten(w, seg, phi), e, rtol=0, atol=1e-12 * np.abs(e).max())
    se = np.sqrt((1 - phi ** 2) / n)
    rho_ml, lr = ar1_regression_ml(e, np.ones((n, 1)), seg, grid=np.linspace(0, 0.95, 191))
    assert abs(rho_ml - phi) < 4 * se + 0.005 and lr > 100          # grid step 0.005
    white = rng.normal(size=n)
    assert ar1_regression_ml(white, np.ones((n, 1)), seg)[1] < 9.0
