"""Generalised forms of the listed effects: each reduces EXACTLY to its listed form at
its reducing value, is the baseline at `off`, keeps physical bounds, and adds the physics its
docstring states. Expected numbers come from closed forms stated beside them (first-order lag
response to a ramp and to a ramped step, the integral of a quadratic CTE law by quadrature, the
hand-counted time beyond a threshold of a stepped temperature programme, a pure exponential
friction law and its Taylor series at small rates)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from analytic.materials import MATERIALS, T_CTE_REF_C
from studies.model.effects import (EFFECTS, EffectError, apply_effects, get_effect,
                                   parse_effect_arg)
from studies.model.effects.generalised import GENERALISED, GeneralisedForm, forms_of
from studies.model.effects.preload_settling_creep import hours_beyond
from studies.model.inputs import PhysicsInputs, baseline_inputs

from test_effects import T_REF, assert_same_inputs, cycle_inputs

#: a physical value of every form's parameters away from its reducing value
ON = {
    "thermal_lag.per_part": {"tau_s": 900.0, "tau_shaft_s": 2400.0},
    "preload_settling.creep": {"loss_N": 12.0, "threshold_K": 30.0, "creep_N_per_h": 4.0},
    "preload_settling.gradual": {"loss_N": 12.0, "threshold_K": 30.0, "tau_settle_s": 3600.0},
    "cte_nonlinearity.curvature": {"dalpha_per_K": 5e-9, "d2alpha_per_K3": 1e-10},
    "radial_gradient.lag": {"dT_K": 3.0, "dT_per_krpm_K": 1.5, "tau_gradient_s": 600.0},
    "thermal_lag.series": {"tau_s": 600.0, "tau_shaft_s": 240.0},
    "friction_temperature.exponential": {"dmu_per_K": -1.8e-4, "b_per_K": 6e-3},
}


def assert_same_all(a: PhysicsInputs, b: PhysicsInputs):
    assert_same_inputs(a, b)
    assert a.d2alpha_per_K3 == b.d2alpha_per_K3


def test_registry_families_and_docs():
    assert set(GENERALISED) == set(ON)
    for name, f in GENERALISED.items():
        assert isinstance(f, GeneralisedForm) and name == f"{f.family}.{f.form}"
        listed = EFFECTS[f.family]
        assert get_effect(name) is f and f in forms_of(f.family)
        # the listed parameters keep their names, bounds and off values
        for p in listed.parameters:
            assert p in f.parameters and f.bounds[p] == listed.bounds[p] and f.off[p] == listed.off[p]
        assert set(f.extra) == set(f.parameters) - set(listed.parameters) and f.extra
        assert set(f.bounds) == set(f.off) == set(f.units) == set(f.parameters)
        doc = __import__(type(f).__module__, fromlist=["x"]).__doc__
        assert "Source" in doc and "Reduces to" in doc


@pytest.mark.parametrize("name", sorted(ON))
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_reduces_exactly_to_the_listed_form(name, seed):
    """At `from_listed(listed)` the form gives the listed effect's inputs, field by field, for
    random listed parameters inside the bounds (and with a measured part temperature)."""
    f = GENERALISED[name]
    listed = EFFECTS[f.family]
    rng = np.random.default_rng(seed)
    params = {p: float(rng.uniform(*listed.bounds[p])) for p in listed.parameters}
    if "tau_s" in params:
        params["tau_s"] = float(rng.uniform(30.0, 3000.0))    # lags the 60 s samples can show
    if "threshold_K" in params:
        params["threshold_K"] = float(rng.uniform(5.0, 60.0))
    for base in (cycle_inputs(), cycle_inputs(measured_part="housing")):
        a = f.apply(base, f.from_listed(params), T_REF)
        b = listed.apply(base, params, T_REF)
        assert_same_all(a, b)
        # and together with other effects through apply_effects (the family's place in ORDER)
        other = {"interference_error": {"inner_um": 1.0, "outer_um": 0.0}}
        assert_same_all(apply_effects(base, {name: f.from_listed(params), **other}, T_REF),
                        apply_effects(base, {f.family: params, **other}, T_REF))
    # and differs away from it (else the test above could not fail)
    on = f.apply(cycle_inputs(), ON[name], T_REF)
    off_listed = listed.apply(cycle_inputs(), {p: ON[name][p] for p in listed.parameters}, T_REF)
    with pytest.raises(AssertionError):
        assert_same_all(on, off_listed)


@pytest.mark.parametrize("name", sorted(ON))
def test_off_is_baseline_and_bounds(name):
    f = GENERALISED[name]
    base = cycle_inputs()
    assert_same_all(f.apply(base, f.off, T_REF), base)
    for p in f.extra:
        lo, hi = f.bounds[p]
        with pytest.raises(EffectError, match=p):
            f.validate({p: hi + abs(hi) + 1.0})
    assert parse_effect_arg(name + ":" + ",".join(f"{k}={v}" for k, v in ON[name].items())) \
        == (name, ON[name])


def test_per_part_lag_ramp_closed_form():
    """Ambient ramp u = u0 + s t from equilibrium: each group follows with its own lag,
    T(t) = u(t) - s tau (1 - exp(-t / tau)) (first-order ramp response, Incropera ch. 5)."""
    n, s = 120, 2.0 / 60.0
    t = np.arange(n) * 30.0
    inp = baseline_inputs({"time_s": t, "T_ambient_C": 20.0 + s * t}, n, T_REF, 100.0, 0.0)
    out = GENERALISED["thermal_lag.per_part"].apply(inp, {"tau_s": 900.0, "tau_shaft_s": 2400.0},
                                                    T_REF)
    for part, tau in (("housing", 900.0), ("outer_ring", 900.0), ("spacer", 900.0),
                      ("shaft", 2400.0), ("inner_ring", 2400.0), ("ball", 2400.0)):
        exact = 20.0 + s * t - s * tau * (1.0 - np.exp(-t / tau))
        np.testing.assert_allclose(out.T_C[part], exact, rtol=0, atol=1e-9)   # K, round-off


def _series_ramp(t, t1, t2):
    """Response of 1/((1 + p t1)(1 + p t2)) to a unit ramp from equilibrium: the integral of the
    step response 1 - (t1 e^{-t/t1} - t2 e^{-t/t2}) / (t1 - t2) (Ogata, Modern Control
    Engineering, ch. 5), t - (t1 + t2) + (t1^2 e^{-t/t1} - t2^2 e^{-t/t2}) / (t1 - t2); for
    t1 = t2 = tau the double pole's t - 2 tau + (2 tau + t) e^{-t/tau}."""
    t = np.maximum(t, 0.0)
    if t1 == t2:
        return t - 2 * t1 + (2 * t1 + t) * np.exp(-t / t1)
    return t - (t1 + t2) + (t1 ** 2 * np.exp(-t / t1) - t2 ** 2 * np.exp(-t / t2)) / (t1 - t2)


@pytest.mark.parametrize("taus", [(600.0, 240.0), (240.0, 600.0), (900.0, 900.0),
                                  (900.0, 900.0 * (1 + 1e-9)), (900.0, 1e-3)])
def test_series_lag_ramp_closed_form(taus):
    """Ambient ramp u = u0 + s t from equilibrium, sampled at irregular instants: the housing
    side is the first-order ramp response, the shaft side the ramp response of two lags in series
    (`_series_ramp`); also at equal and nearly equal constants (the double pole) and a shaft
    constant far below the sample interval (the shaft side then is the housing side)."""
    t1, t2 = taus
    rng = np.random.default_rng(4)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(5.0, 90.0, 199))])
    n, s = t.size, 2.0 / 60.0
    inp = baseline_inputs({"time_s": t, "T_ambient_C": 20.0 + s * t}, n, T_REF, 100.0, 0.0)
    out = GENERALISED["thermal_lag.series"].apply(inp, {"tau_s": t1, "tau_shaft_s": t2}, T_REF)
    housing = 20.0 + s * t - s * t1 * (1.0 - np.exp(-t / t1))
    # the near-double pole against the double pole's closed form (the distinct-pole one cancels
    # there): they differ by at most s |t2 - t1| (a delay changes the ramp response by at most
    # the rate times its change); else round-off, 1e-9 K
    near = 0.0 < abs(t2 - t1) < 1e-6 * t1
    shaft = 20.0 + s * _series_ramp(t, t1, t1 if near else t2)
    atol = 1e-9 + (s * abs(t2 - t1) if near else 0.0)
    for part, exact in (("housing", housing), ("outer_ring", housing), ("spacer", housing),
                        ("shaft", shaft), ("inner_ring", shaft), ("ball", shaft)):
        np.testing.assert_allclose(out.T_C[part], exact, rtol=0, atol=atol, err_msg=part)


def test_series_lag_ramped_step_closed_form():
    """Ambient 20 -> 80 C ramped over one 60 s interval, then held: the shaft side is
    (dT / h) [R(t - t0) - R(t - t0 - h)] with R the series ramp response (superposition of two
    ramps), and it starts with zero slope where the housing side starts with the ramp's
    first-order response (two lags in series, not in parallel)."""
    h, t1, t2, dT = 60.0, 600.0, 240.0, 60.0
    t = np.arange(400) * h
    i0 = 20
    t0 = t[i0]
    u = 20.0 + dT * np.clip((t - t0) / h, 0.0, 1.0)
    inp = baseline_inputs({"time_s": t, "T_ambient_C": u}, t.size, T_REF, 100.0, 0.0)
    out = GENERALISED["thermal_lag.series"].apply(inp, {"tau_s": t1, "tau_shaft_s": t2}, T_REF)
    shaft = 20.0 + dT / h * (_series_ramp(t - t0, t1, t2) - _series_ramp(t - t0 - h, t1, t2))
    np.testing.assert_allclose(out.T_C["shaft"], shaft, rtol=0, atol=1e-9)     # K, round-off
    # one interval after the step the housing side has risen dT h / (2 t1) and the shaft side
    # dT h^2 / (6 t1 t2) to leading order: a ratio h / (3 t2) = 0.083 (two parallel lags would
    # give t1 / t2 = 2.5)
    rise_shaft = out.T_C["shaft"][i0 + 1] - 20.0
    rise_housing = out.T_C["housing"][i0 + 1] - 20.0
    assert rise_shaft < 0.1 * rise_housing


def test_settling_creep_hours_counted_by_hand():
    """Stepped programme, 10 min samples: 20 C for 3 rows, 80 C for 6 rows, 20 C for 3 rows.
    Threshold 30 K: rows 3..8 beyond; intervals ending at rows 4..8 count (5 x 600 s = 5/6 h),
    the interval ending at row 3 too (the programme steps within it): 6 x 600 s = 1 h."""
    T = np.array([20.0] * 3 + [80.0] * 6 + [20.0] * 3)
    t = np.arange(T.size) * 600.0
    H = hours_beyond(t, T, T_REF, 30.0)
    # a running sum of up to T.size intervals: T.size eps of the largest sum (1 h)
    np.testing.assert_allclose(H, [0, 0, 0, 1 / 6, 2 / 6, 3 / 6, 4 / 6, 5 / 6, 1, 1, 1, 1],
                               rtol=0, atol=T.size * np.finfo(float).eps * 1.0)
    inp = baseline_inputs({"time_s": t, "T_ambient_C": T}, T.size, T_REF, 100.0, 0.0)
    out = GENERALISED["preload_settling.creep"].apply(
        inp, {"loss_N": 5.0, "threshold_K": 30.0, "creep_N_per_h": 3.0}, T_REF)
    expect = np.where(np.arange(T.size) >= 3, 5.0, 0.0) + 3.0 * np.array(H)
    # round-off relative to the terms: the step and the creep part (5 N + 3 N/h x 1 h)
    np.testing.assert_allclose(out.preload_loss_N, expect, rtol=0, atol=1e-13 * (5.0 + 3.0 * 1.0))


def test_settling_creep_never_loses_more_than_the_assembled_preload():
    """Seed 001's pair is assembled with 7 N. A 5 N step at 30 K plus creep at the bound
    (500 N/h) over the stepped programme above: without a limit the loss would reach
    5 + 500 x 1 h = 505 N. The pair cannot lose more than it has: the total loss is
    min(5 + 500 H, 7) N per row (a pair without preload loses nothing more), exact."""
    from studies.model.config import load_shipped

    P_a = load_shipped("seed001").preload.assembled_N
    assert P_a == 7.0
    T = np.array([20.0] * 3 + [80.0] * 6 + [20.0] * 3)
    t = np.arange(T.size) * 600.0
    H = hours_beyond(t, T, T_REF, 30.0)
    inp = baseline_inputs({"time_s": t, "T_ambient_C": T}, T.size, T_REF, P_a, 0.0)
    out = GENERALISED["preload_settling.creep"].apply(
        inp, {"loss_N": 5.0, "threshold_K": 30.0, "creep_N_per_h": 500.0}, T_REF)
    loss = np.asarray(out.preload_loss_N, float)
    assert loss.max() <= P_a
    expect = np.minimum(np.where(np.arange(T.size) >= 3, 5.0, 0.0) + 500.0 * H, P_a)
    np.testing.assert_allclose(loss, expect, rtol=0, atol=1e-12)   # N, round-off
    assert loss[-1] == P_a                                          # the whole preload is gone


@pytest.mark.parametrize("T_ref", [20.0, 25.0])
def test_cte_curvature_strain_is_the_integral_of_alpha(T_ref):
    """theta(T) = integral_{T_ref}^{T} alpha(T') dT' with alpha = alpha0 + a1 (T' - 20) +
    a2 (T' - 20)^2, by adaptive quadrature (an independent method), -60..150 C."""
    m = MATERIALS["TC4"].with_dalpha(8e-9, 2e-10)

    def alpha(T):
        d = T - T_CTE_REF_C
        return m.alpha_per_K + 8e-9 * d + 2e-10 * d * d

    for T in (-60.0, 0.0, 20.0, 80.0, 150.0):
        ref = integrate.quad(alpha, T_ref, T, epsabs=1e-16, epsrel=1e-13)[0]
        # 1e-15 absolute: round-off of strains of order 1e-3
        assert m.thermal_strain(np.array(T), T_ref) == pytest.approx(ref, abs=1e-15)


def test_cte_curvature_reaches_the_pipeline_strains():
    """The form writes the curvature of the shaft and housing; the strains the pipeline hands
    the FE (`Pipeline.thetas`, per FE part) then follow the quadratic law: the shaft's and the
    cover's (TC4, seed 000) equal the integral of alpha0 + a1 (T' - 20) + a2 (T' - 20)^2 by
    adaptive quadrature (an independent method), the rings' (9Cr18) are the baseline's."""
    from studies.model.config import load_shipped
    from studies.model.pipeline import Pipeline

    f = GENERALISED["cte_nonlinearity.curvature"]
    base = cycle_inputs(n=12)
    out = f.apply(base, ON["cte_nonlinearity.curvature"], T_REF)
    assert out.d2alpha_per_K3 == {"shaft": 1e-10, "housing": 1e-10}
    assert out.dalpha_per_K2 == {"shaft": 5e-9, "housing": 5e-9}
    pl = Pipeline(load_shipped("seed000"), mesh_factor=2.0)
    theta, theta0 = pl.thetas(out), pl.thetas(base)
    a0 = MATERIALS["TC4"].alpha_per_K
    T_ref = pl.asm.T_ref_C
    for part in ("shaft", "cover"):
        j = pl.part_names.index(part)
        T = out.T_C["shaft" if part == "shaft" else "housing"]
        ref = [integrate.quad(lambda x: a0 + 5e-9 * (x - T_CTE_REF_C)
                              + 1e-10 * (x - T_CTE_REF_C) ** 2, T_ref, Ti,
                              epsabs=1e-16, epsrel=1e-13)[0] for Ti in T]
        # round-off: 16 eps of the largest strain of the part (strains of order 1e-3)
        tol = 16 * np.finfo(float).eps * np.abs(ref).max()
        np.testing.assert_allclose(theta[:, j], ref, rtol=0, atol=tol, err_msg=part)
    j = pl.part_names.index("inner_ring_A")
    np.testing.assert_array_equal(theta[:, j], theta0[:, j])


def test_gradient_lag_after_a_speed_step_closed_form():
    """Speed 1000 -> 3000 rpm ramped over one sample interval h (from t1): the speed part of the
    gradient G follows the ramp-then-hold response of a first-order lag,
    G(t) = Gs0 + dG [1 - (tau/h)(exp(h/tau) - 1) exp(-(t - t1)/tau)] for t >= t1 + h."""
    n, h, tau, k = 200, 30.0, 600.0, 1.5
    t = np.arange(n) * h
    i1 = 50
    speed = np.where(np.arange(n) <= i1, 1000.0, 3000.0)
    inp = baseline_inputs({"time_s": t, "T_ambient_C": np.full(n, 20.0), "speed_rpm": speed}, n,
                          T_REF, 100.0, 0.0)
    out = GENERALISED["radial_gradient.lag"].apply(
        inp, {"dT_K": 0.0, "dT_per_krpm_K": k, "tau_gradient_s": tau}, T_REF)
    G = out.T_C["shaft"] - 20.0
    t1 = t[i1]
    after = t >= t1 + h
    exact = 1.5 + 3.0 * (1.0 - (tau / h) * math.expm1(h / tau) * np.exp(-(t[after] - t1) / tau))
    np.testing.assert_allclose(G[after], exact, rtol=0, atol=1e-9)      # K, round-off
    np.testing.assert_allclose(G[t <= t1], 1.5, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(out.T_C["housing"], inp.T_C["housing"])


def test_friction_exponential_is_the_exponential_law():
    """The member dmu_per_K = -b mu0 is the pure law mu0 exp(-b (T_rings - T_ref)) (numpy's exp,
    an independent evaluation), through the pipeline's resolution of the coefficient; and at
    small rates the form follows its Taylor series mu0 + dmu (x - b x^2 / 2 + b^2 x^3 / 6) to
    the next term's size (dmu b^3 x^4 / 24), continuous into the listed law at b = 0."""
    from studies.model.effects import resolve_friction_coefficient

    f = GENERALISED["friction_temperature.exponential"]
    base = cycle_inputs()
    x = 0.5 * (base.T_C["inner_ring"] + base.T_C["outer_ring"]) - T_REF
    assert x.min() < -50.0 and x.max() > 40.0              # a wide range of the law
    mu0, b = 0.03, 6e-3
    out = f.apply(base, {"dmu_per_K": -b * mu0, "b_per_K": b}, T_REF)
    # round-off of coefficients of order mu0 (a few eps of exp(0.5) mu0)
    np.testing.assert_allclose(resolve_friction_coefficient(out, mu0), mu0 * np.exp(-b * x),
                               rtol=0, atol=8 * np.finfo(float).eps * mu0)
    dmu = 2e-4
    for b in (1e-6, -1e-6, 1e-9):
        d = f.apply(base, {"dmu_per_K": dmu, "b_per_K": b}, T_REF).friction_coefficient
        series = dmu * (x - b * x ** 2 / 2 + b ** 2 * x ** 3 / 6)
        tol = dmu * abs(b) ** 3 * np.max(np.abs(x)) ** 4 / 24 + 8 * np.finfo(float).eps * dmu * 80
        np.testing.assert_allclose(d, series, rtol=0, atol=tol)


def test_settling_gradual_follows_its_first_order_approach():
    """Stepped programme, 10 min samples: 20 C for 3 rows, then 80 C. Threshold 30 K: the loss
    starts at row 3 (t_0 = 1800 s) and approaches 12 N as 1 - exp(-(t - t_0) / 3600 s), the
    closed form of a first-order settling (e^-1 of the way left one time constant after t_0:
    7.585 N at row 9); 0 before t_0."""
    T = np.array([20.0] * 3 + [80.0] * 9)
    t = np.arange(T.size) * 600.0
    inp = baseline_inputs({"time_s": t, "T_ambient_C": T}, T.size, T_REF, 100.0, 0.0)
    out = GENERALISED["preload_settling.gradual"].apply(
        inp, {"loss_N": 12.0, "threshold_K": 30.0, "tau_settle_s": 3600.0}, T_REF)
    expect = np.where(t >= 1800.0, 12.0 * (1.0 - np.exp(-(t - 1800.0) / 3600.0)), 0.0)
    np.testing.assert_allclose(out.preload_loss_N, expect, rtol=0, atol=1e-12 * 12.0)
    assert out.preload_loss_N[9] == pytest.approx(12.0 * (1.0 - math.exp(-1.0)), rel=1e-12)
