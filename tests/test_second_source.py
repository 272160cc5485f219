"""The second source of measured data (studies/validation/second_source.py): data made
another way than the model the diagnosis fits, one case per kind in the default suite.

Each test first checks that the data really differ from the diagnosed model by the stated
mechanism, against a reference that is not the code under test:
- noise: the AR(1) generator's lag-1 autocorrelation against phi within its sampling error
  (Bartlett), its marginal standard deviation against sigma;
- history: the transient conduction FE's part temperatures against the lumped-capacitance lag
  with tau = C / (h A) (Incropera ch. 5; the stack's Biot number is about 0.01), and the parts
  lagging by different amounts, which the one-constant `thermal_lag` cannot do; the two-node
  network's ramp delays against the closed form (a series of first-order lags: delays add),
  and its temperatures against the `thermal_lag.series` form's recursion (a second method);
- model form: a spring preload holds its force (the truth's preload is the assembled one at
  every temperature) where the diagnosed position preload moves by many sigma; an exponential
  friction law is recovered with the rate the data were made with.
- sensor: a thermometer offset's fitted value against the offset injected.
Then today's diagnosis (`second_source.diagnose_case`, the CLI's candidates, coarse mesh family
member `MESH_FACTOR`) must not claim a wrong cause on it (`second_source.judge`), and on the
two-node network must name the lag with the constants the data were made with; every case over
several draws is the slow suite's and the confusion-matrix study's.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from studies.validation import second_source as ss

MESH_FACTOR = 2.0           # the diagnosed model and its truth on the coarse mesh family member


# ============================================================================ noise
@pytest.mark.parametrize("phi", [0.5, 0.9, 0.95])
def test_ar1_generator_has_the_stated_correlation_and_level(phi):
    """40 000 samples: r1 within 4 standard errors of phi (Bartlett: sqrt((1 - phi^2)/n), plus
    the O(1/n) small-sample bias (1 + 4 phi)/n, Box-Jenkins-Reinsel ch. 2.1.6) and the marginal
    standard deviation within 4 standard errors of sigma (the variance of an AR(1) sample
    variance: 2 sigma^4 (1 + phi^2) / (n (1 - phi^2)))."""
    n, sigma = 40_000, 0.7
    e = ss.ar1(np.random.default_rng(1), n, sigma, phi)
    se = math.sqrt((1 - phi ** 2) / n)
    assert abs(ss.lag1_autocorrelation(e) - phi) < 4 * se + (1 + 4 * phi) / n
    se_var = math.sqrt(2 * (1 + phi ** 2) / (n * (1 - phi ** 2))) * sigma ** 2
    assert abs(np.var(e) - sigma ** 2) < 4 * se_var


@pytest.fixture(scope="module")
def ar1_case():
    return ss.make_case("ar1_090_null", seed=0, mesh_factor=MESH_FACTOR)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_ar1_null_case_carries_its_noise_and_no_cause_is_claimed(ar1_case):
    """The case's noise (measured - noise-free, 240 rows) has r1 within 4 standard errors and the
    small-sample bias of 0.9 in every column; nothing is hidden, so the diagnosis must claim no
    cause (no `explained`, `explained_partly` or `ambiguous`; one claim in 8 draws was seen once,
    the rate is the study's)."""
    c = ar1_case
    n = len(c.measured["torque_Nmm"])
    for col in c.columns:
        r1 = ss.lag1_autocorrelation(c.measured[col] - c.noise_free[col])
        assert abs(r1 - 0.9) < 4 * math.sqrt((1 - 0.81) / n) + (1 + 3.6) / n, (col, r1)
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) in ("right", "false_alarm"), \
        (res.verdict, res.cause)


def test_spikes_and_quantisation_are_what_the_case_states():
    """`add_noise`: every reading on the quantum grid; the spikes where it says, 50..150 sigma."""
    rng = np.random.default_rng(3)
    truth = {"torque_Nmm": np.linspace(1.0, 2.0, 200), "preload_N": np.full(200, 100.0)}
    noise = ss.Noise(sigma={"torque_Nmm": 0.01, "preload_N": 0.5}, spikes=5,
                     quantum={"torque_Nmm": 0.015, "preload_N": 0.75})
    m, rows = ss.add_noise(truth, noise, rng)
    for c, q in noise.quantum.items():
        k = m[c] / q
        assert np.max(np.abs(k - np.round(k))) < 1e-9, c
    dev = np.abs(m["torque_Nmm"] - truth["torque_Nmm"]) / 0.01
    assert rows.size == 5 and np.all(dev[rows - 1] > 50 - 5 - 1.5)      # 5 sigma noise, q/2
    others = np.setdiff1d(np.arange(200), rows - 1)
    assert np.all(dev[others] < 6.0)


# ============================================================================ history
def test_network_ramp_delays_add():
    """A ramp of rate a from equilibrium: after many time constants the outer node trails the
    chamber by a tau_o and the rotor by a (tau_o + tau_r) (series of first-order lags; Laplace
    transform of a ramp through 1/((1 + s tau_o)(1 + s tau_r))), to 1e-6 of the delay."""
    t = np.linspace(0.0, 40_000.0, 4001)
    a = 2.0 / 60.0
    T = ss.network_temperatures(t, 20.0 + a * t, tau_outer_s=600.0, tau_rotor_s=240.0)
    late = t > 20_000.0
    amb = 20.0 + a * t
    np.testing.assert_allclose((amb - T["T_housing_C"])[late], a * 600.0, rtol=1e-6)
    np.testing.assert_allclose((amb - T["T_shaft_C"])[late], a * 840.0, rtol=1e-6)


@pytest.fixture(scope="module")
def network_case():
    return ss.make_case("network_lag", seed=0, mesh_factor=MESH_FACTOR)


def test_network_temperatures_are_the_series_lag_form():
    """The two-node network (`network_temperatures`, scipy's matrix-exponential `lsim`) and the
    `thermal_lag.series` form (its own exact recursion) are two integrations of the same two
    lags in series: housing and shaft agree on seed 000's cycles to round-off (1e-9 K of
    temperatures of order 100 C)."""
    from studies.diagnosis.designs import cycles
    from studies.model.effects.thermal_lag_series import series_lag_response

    c = cycles()
    T = ss.network_temperatures(c["time_s"], c["T_ambient_C"])
    Th, Tr = series_lag_response(c["time_s"], c["T_ambient_C"], 600.0, 240.0)
    np.testing.assert_allclose(Th, T["T_housing_C"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(Tr, T["T_shaft_C"], rtol=0, atol=1e-9)


@pytest.mark.slow     # 10-25 s; the rates over 10 draws are the confusion-matrix study's
def test_network_lag_is_explained_by_thermal_lag_in_series(network_case):
    """A housing side 600 s behind the chamber and a shaft side 240 s behind the housing side
    (138 sigma against the baseline): `explained` by `thermal_lag` in its series form
    (`thermal_lag.series`), both constants within 10 % of the values the data were made with.
    Why 10 %: the data put the balls and the spacer at the mean of the two nodes, where the form
    puts them on the shaft and the housing side; the form's best fit to the noise-free data is
    621 / 221 s (+3.6 %, -7.8 %), exactly 600 / 240 s when the data group the parts as the form
    does; the noise moves the fit by about 1 % (seeds 0-9: 599-623 s and 221-223 s)."""
    c = network_case
    assert c.change_sigma > 5.0
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right" and res.verdict == "explained", \
        (res.verdict, ss.named_causes(res))
    ext = res.extended_form
    assert ext is not None and ext.name == "thermal_lag.series", res.generalised_forms
    assert abs(ext.parameters["tau_s"] / 600.0 - 1.0) < 0.10, ext.parameters
    assert abs(ext.parameters["tau_shaft_s"] / 240.0 - 1.0) < 0.10, ext.parameters


@pytest.fixture(scope="module")
def transient_case():
    return ss.make_case("transient_fe_lag", seed=0, mesh_factor=MESH_FACTOR)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_transient_fe_temperatures_are_a_lumped_lag_per_part(transient_case):
    """The transient conduction FE's part temperatures on the -60 <-> 80 C cycle against the
    lumped-capacitance lag tau = C / (h A) of the whole stack (C = the stack's heat capacity,
    h A = the film conductance of its faces; Incropera ch. 5.1, valid for Biot numbers below
    0.1: here h L / k = 15 x 6.5e-3 / 6.7 = 0.015): every part within 8 % of the largest lag
    (measured 0.5..4 %). And the parts lag differently, which the one-constant `thermal_lag`
    cannot make: shaft and housing differ by more than 0.5 K on the ramps (measured ~1.2 K),
    i.e. by more than the lumped law's own error would allow if they were one body."""
    from studies.model.effects.thermal_lag import lag_response
    from studies.model.pipeline import Pipeline
    from studies.model.transient_route import thermal_model

    c = transient_case
    pl = Pipeline.shared(ss.transient_asm(c.assembly), mesh_factor=MESH_FACTOR)
    tm = thermal_model(pl)
    C_J_K = float(tm.tc.M.sum())            # 1^T M 1 = integral of rho c over the stack
    hA_W_K = sum(h * 1e-6 * tm.tc.area_mm2[g] for g, h in tm.nominal.film_W_m2K.items())
    t, amb = c.conditions["time_s"], c.conditions["T_ambient_C"]
    T = ss.transient_fe_temperatures(c.assembly, t, amb, MESH_FACTOR)
    lumped = lag_response(t, amb, C_J_K / hA_W_K)
    largest = float(np.max(np.abs(lumped - amb)))
    assert largest > 10.0                                   # the lag is large on 2 K/min ramps
    for k, v in T.items():
        assert np.max(np.abs(v - lumped)) < 0.08 * largest, k
    assert np.max(np.abs(T["T_shaft_C"] - T["T_housing_C"])) > 0.5


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_transient_fe_lag_is_not_a_wrong_cause(transient_case):
    """Lagged temperatures made by the conduction FE (57 sigma against the baseline on the
    coarse mesh): the diagnosis names the lag family or says it cannot (never another cause)."""
    c = transient_case
    assert c.change_sigma > ss.VISIBLE_SIGMA
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) != "wrong", \
        (res.verdict, res.cause)


# ============================================================================ model form
@pytest.fixture(scope="module")
def spring_case():
    return ss.make_case("spring_preload", seed=0, mesh_factor=MESH_FACTOR)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_spring_preload_truth_holds_its_force_and_is_not_a_wrong_cause(spring_case):
    """A spring preload (force-controlled) keeps the assembled 100 N at every temperature of the
    cycle (the closed form: the spring's force, its stiffness negligible), to 1e-9; the diagnosed
    position preload moves by more than 10 sigma over the cycle. The diagnosis then names the
    spring (or a path compliance, its finite form) or no cause; never another one."""
    from studies.diagnosis.files import ModelPredictor
    from studies.model.pipeline import Pipeline

    c = spring_case
    P0 = c.assembly.preload.assembled_N
    np.testing.assert_allclose(c.noise_free["preload_N"], P0, rtol=1e-9)
    pred = ModelPredictor(Pipeline.shared(c.assembly, mesh_factor=MESH_FACTOR), c.conditions,
                          ("preload_N",))
    position = pred({}, {"mu_scale": ss.MU_TRUE})["preload_N"]
    assert np.ptp(position) > 10 * c.sigma["preload_N"]
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) != "wrong", \
        (res.verdict, res.cause)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_exponential_friction_law_is_explained_with_the_rate_it_was_made_with():
    """The rig's friction is mu_cal exp(-b (T_rings - T_ref)) with b = 6e-3 /K (38 sigma against
    the baseline); the listed `friction_temperature` is linear and leaves structure. The
    diagnosis must explain it by the friction family through its exponential form, with the
    rate b and the slope at T_ref the data were made with: b_per_K = 6e-3 /K (the case's law,
    `second_source._friction_exp`) and dmu_per_K = -b mu_config (the exponential member of the
    form: mu_config + dmu (1 - exp(-b x)) / b = mu_config exp(-b x) when dmu = -b mu_config; the
    rig's factor MU_TRUE is the friction scale's) within 3 of their stated standard
    uncertainties. Over 10 draws b came out 5.72..6.13e-3 with u = 2.7..3.7e-4 (all within
    1 u); the uncertainty must also be small against b itself (< b / 5), so that the test cannot
    pass by an uninformative fit."""
    c = ss.make_case("friction_law_exp", seed=0, mesh_factor=MESH_FACTOR)
    assert c.change_sigma > ss.VISIBLE_SIGMA
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right", (res.verdict, ss.named_causes(res))
    assert res.verdict == "explained" and ss.named_causes(res) == ["friction_temperature"]
    form = res.extended_form
    assert form is not None and form.name == "friction_temperature.exponential"
    b_true = 6e-3                                           # 1/K, the case's law
    mu_config = c.assembly.lubrication.friction_coefficient
    b, u_b = form.parameters["b_per_K"], form.parameter_uncertainty["b_per_K"]
    assert 0 < u_b < b_true / 5 and abs(b - b_true) <= 3 * u_b, (b, u_b)
    dmu, u_dmu = form.parameters["dmu_per_K"], form.parameter_uncertainty["dmu_per_K"]
    assert abs(dmu - (-b_true * mu_config)) <= 3 * u_dmu, (dmu, u_dmu)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_housing_lot_inside_its_scatter_is_named_with_its_cte():
    """A TC4 housing lot whose CTE is 3 % below the library's (inside the data sheets' spread,
    the material_lot rung's +-5 %): the diagnosis names `material_lot` and fits the housing's
    CTE factor within 3 standard uncertainties and 0.005 of the 0.97 the data were made with,
    the shaft's (a lot of the library value) within the same of 1."""
    c = ss.make_case("housing_lot", seed=0, mesh_factor=MESH_FACTOR)
    assert c.change_sigma > ss.VISIBLE_SIGMA
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right", (res.verdict, ss.named_causes(res))
    lot = next(x for x in res.candidates if x.effect == "material_lot")
    for name, truth in (("cte_factor_housing", 0.97), ("cte_factor_shaft", 1.0)):
        got, u = lot.parameters[name], lot.uncertainty[name]
        assert abs(got - truth) <= min(3.0 * u, 0.005), (name, got, u)


# ============================================================================ sensor
@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_thermometer_offset_is_not_claimed_as_a_cause():
    """The chamber thermometer reads 0.5 K high (inside IEC 60751 class B): every part runs
    0.5 K colder than logged (the truth on the finer mesh with direct FE solves, not the
    superposed route the look-alike is evaluated on). The largest change is below a sigma, but over 240 rows it is a
    strong signal that a fit error, a CTE slope or curvature, a material lot or a share of the
    grooved section all imitate (before 2026-11-25 seed 0 was `explained: cte_nonlinearity`
    through its curvature form, other draws `interference_error`). The diagnosis must claim no
    cause; the sensor look-alike `thermometer_offset` fits the offset within 3 standard
    uncertainties (and 0.1 K) of the injected 0.5 K."""
    c = ss.make_case("chamber_offset", seed=0, mesh_factor=MESH_FACTOR)
    assert c.change_sigma < ss.VISIBLE_SIGMA
    res = ss.diagnose_case(c)
    assert ss.judge_result(c, res) == "right", (res.verdict, ss.named_causes(res))
    look = next(x for x in res.candidates if x.effect == "thermometer_offset")
    assert look.status == "passed"
    dT, u = look.parameters["dT_K"], look.uncertainty["dT_K"]
    assert abs(dT - 0.5) <= min(3.0 * u, 0.1), (dT, u)


# ============================================================================ the judge
def test_judge_outcomes():
    """The outcome table of `judge` (its docstring), on the labels of three cases."""
    lag, null, drift = ss.CASES["transient_fe_lag"], ss.CASES["ar1_090_null"], ss.CASES["torque_drift"]
    two = ss.CASES["fit_error_and_lag"]
    assert ss.judge(lag, "explained", "thermal_lag.per_part") == "right"
    assert ss.judge(lag, "explained_partly", "thermal_lag") == "right"
    assert ss.judge(lag, "explained", "solid_film_runin") == "wrong"
    assert ss.judge(lag, "ambiguous", "radial_gradient", ["thermal_lag"]) == "named"
    assert ss.judge(lag, "ambiguous", "radial_gradient", ["cte_nonlinearity"]) == "wrong"
    assert ss.judge(lag, "unexplained", None) == "unexplained"
    assert ss.judge(lag, "no_discrepancy", None) == "missed"
    assert ss.judge(null, "no_discrepancy", None) == "right"
    assert ss.judge(null, "unexplained", None) == "false_alarm"
    assert ss.judge(null, "explained", "preload_settling") == "wrong"
    assert ss.judge(drift, "unexplained", None) == "right"
    assert ss.judge(drift, "explained", "solid_film_runin") == "wrong"
    assert ss.judge(two, "explained", "thermal_lag") == "partial"
    assert ss.judge(two, "explained", ["thermal_lag", "interference_error"]) == "right"
    assert ss.judge(two, "explained", ["thermal_lag", "preload_settling"]) == "wrong"
    spring = ss.CASES["spring_preload"]
    assert ss.judge(spring, "explained", "preload_path_compliance") == "right"
    assert ss.judge(spring, "explained", "interference_error") == "wrong"
