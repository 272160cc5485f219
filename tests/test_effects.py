"""Effects: off == baseline exactly, physical bounds, and the physics each one adds.

Expected numbers come from closed forms stated beside them (exponential step response, ramp
response of a first-order lag, the formulas in each effect's docstring)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from studies.model.effects import (EFFECTS, ORDER, EffectError, apply_effects, get_effect,
                             parse_effect_arg, resolve_friction_coefficient,
                             resolve_interference_um)
from studies.diagnosis.fitspec import settling_grid
from studies.model.effects.thermal_lag import lag_response
from studies.model.inputs import PARTS, PhysicsInputs, baseline_inputs

T_REF = 20.0
SPEC_PARAMETERS = {  # docs/cli.md "Effects", exactly
    "interference_error": ("inner_um", "outer_um"),
    "radial_gradient": ("dT_K", "dT_per_krpm_K"),
    "thermal_lag": ("tau_s",),
    "viscosity_temperature": ("slope_factor",),
    "friction_temperature": ("dmu_per_K",),
    "preload_settling": ("loss_N", "threshold_K"),
    "cte_nonlinearity": ("dalpha_per_K",),
    # this project's extensions beyond the spec's seven, names fixed in docs/cli.md
    "solid_film_runin": ("dmu", "runin_krev"),
    "preload_path_compliance": ("extra_compliance_um_per_kN",),
}
ON = {  # a physical "on" value for every effect
    "interference_error": {"inner_um": 2.0, "outer_um": -1.0},
    "radial_gradient": {"dT_K": 3.0, "dT_per_krpm_K": 1.5},
    "thermal_lag": {"tau_s": 900.0},
    "viscosity_temperature": {"slope_factor": 1.3},
    "friction_temperature": {"dmu_per_K": 5e-5},
    "preload_settling": {"loss_N": 12.0, "threshold_K": 30.0},
    "cte_nonlinearity": {"dalpha_per_K": 5e-9},
    "solid_film_runin": {"dmu": -0.005, "runin_krev": 50.0},
    "preload_path_compliance": {"extra_compliance_um_per_kN": 200.0},
}


def cycle_inputs(n=200, measured_part=None):
    t = np.arange(n) * 60.0
    amb = 10.0 + 70.0 * np.sin(2 * np.pi * t / (n * 60.0 / 2))
    cols = {"time_s": t, "T_ambient_C": amb, "speed_rpm": np.where(t < t[n // 2], 1000., 3000.)}
    if measured_part:
        cols[f"T_{measured_part}_C"] = amb + 1.0
    return baseline_inputs(cols, n, T_REF, preload_N=100.0, speed_rpm=60.0)


def assert_same_inputs(a: PhysicsInputs, b: PhysicsInputs):
    assert a.n_rows == b.n_rows
    for f in ("speed_rpm", "preload_assembled_N", "axial_load_N", "time_s", "T_ambient_C",
              "interference_inner_um", "interference_outer_um", "friction_coefficient",
              "preload_loss_N"):
        x, y = getattr(a, f), getattr(b, f)
        assert (x is None) == (y is None), f
        if x is not None:
            np.testing.assert_array_equal(x, y, err_msg=f)
    assert a.T_C.keys() == b.T_C.keys()
    for p in a.T_C:
        np.testing.assert_array_equal(a.T_C[p], b.T_C[p], err_msg=p)
    assert a.dalpha_per_K2 == b.dalpha_per_K2
    assert a.viscosity_slope_factor == b.viscosity_slope_factor
    assert a.extra_compliance_mm_per_N == b.extra_compliance_mm_per_N


def test_registry_matches_spec():
    assert set(EFFECTS) == set(SPEC_PARAMETERS) == set(ORDER)
    for name, params in SPEC_PARAMETERS.items():
        e = get_effect(name)
        assert e.name == name and e.parameters == params
        assert set(e.bounds) == set(e.off) == set(params)
        for p in params:
            lo, hi = e.bounds[p]
            assert lo <= e.off[p] <= hi and lo < hi
        doc = type(e).__module__
        assert "Source" in __import__(doc, fromlist=["x"]).__doc__


@pytest.mark.parametrize("name", sorted(EFFECTS))
def test_off_is_baseline_exactly(name):
    base = cycle_inputs()
    out = EFFECTS[name].apply(base, EFFECTS[name].off, T_REF)
    assert out is not base
    assert_same_inputs(out, base)
    assert_same_inputs(EFFECTS[name].apply(base, {}, T_REF), base)   # defaults are off


def test_all_off_together_is_baseline_exactly():
    base = cycle_inputs()
    assert_same_inputs(apply_effects(base, {n: e.off for n, e in EFFECTS.items()}, T_REF), base)
    assert_same_inputs(apply_effects(base, {}, T_REF), base)


@pytest.mark.parametrize("name", sorted(EFFECTS))
def test_on_never_mutates_input(name):
    base = cycle_inputs()
    snapshot = {p: a.copy() for p, a in base.T_C.items()}
    out = EFFECTS[name].apply(base, ON[name], T_REF)
    for p in PARTS:
        np.testing.assert_array_equal(base.T_C[p], snapshot[p])
    for f in ("interference_inner_um", "interference_outer_um", "friction_coefficient",
              "preload_loss_N"):
        assert not np.any(getattr(base, f)), f                 # the baseline's zero changes
    assert base.dalpha_per_K2 == {"shaft": 0.0, "housing": 0.0}
    assert base.viscosity_slope_factor == 1.0
    assert base.extra_compliance_mm_per_N == 0.0
    assert out is not base


@pytest.mark.parametrize("name", sorted(EFFECTS))
def test_bounds_rejected_with_clear_message(name):
    e = EFFECTS[name]
    for p in e.parameters:
        lo, hi = e.bounds[p]
        for bad in (hi + abs(hi - lo) * 0.1 + 1e-12, lo - abs(hi - lo) * 0.1 - 1e-12):
            with pytest.raises(ValueError) as err:
                e.apply(cycle_inputs(), {p: bad}, T_REF)
            msg = str(err.value)
            assert "\n" not in msg
            assert name in msg and p in msg and "bounds" in msg
            assert f"{lo:g}" in msg and f"{hi:g}" in msg
    with pytest.raises(EffectError, match="unknown parameter"):
        e.validate({"nonsense_K": 1.0})
    with pytest.raises(EffectError, match="not finite"):
        e.validate({e.parameters[0]: math.nan})


def test_parse_effect_arg():
    assert parse_effect_arg("radial_gradient:dT_K=2,dT_per_krpm_K=0.5") == (
        "radial_gradient", {"dT_K": 2.0, "dT_per_krpm_K": 0.5})
    assert parse_effect_arg("preload_settling:loss_N=5")[1] == {"loss_N": 5.0, "threshold_K": 20.0}
    with pytest.raises(EffectError, match="unknown effect 'nope'"):
        parse_effect_arg("nope:x=1")
    with pytest.raises(EffectError, match="not a number"):
        parse_effect_arg("thermal_lag:tau_s=abc")
    with pytest.raises(EffectError, match="outside physical bounds"):
        parse_effect_arg("viscosity_temperature:slope_factor=5")


@pytest.mark.parametrize("name", ["thermal_lag", "preload_settling", "solid_film_runin"])
def test_time_required(name):
    base = baseline_inputs({"T_ambient_C": np.array([20.0, 50.0, 60.0])}, 3, T_REF, 100.0, 60.0)
    with pytest.raises(EffectError, match=f"effect {name} needs the condition column time_s"):
        EFFECTS[name].apply(base, ON[name], T_REF)
    bad = baseline_inputs({"T_ambient_C": np.array([20.0, 50.0, 60.0]),
                           "time_s": np.array([0.0, 10.0, 5.0])}, 3, T_REF, 100.0, 60.0)
    with pytest.raises(EffectError, match="strictly increasing"):
        EFFECTS[name].apply(bad, ON[name], T_REF)


# ------------------------------------------------------------------------ physics of each effect
def test_interference_offsets_and_resolution():
    base = cycle_inputs()
    out = EFFECTS["interference_error"].apply(base, {"inner_um": 2.5, "outer_um": -1.0}, T_REF)
    inner, outer = resolve_interference_um(out, 5.0, -1.5)
    np.testing.assert_array_equal(inner, 7.5)
    np.testing.assert_array_equal(outer, -2.5)
    inner0, outer0 = resolve_interference_um(base, 5.0, -1.5)
    np.testing.assert_array_equal(inner0, 5.0)
    np.testing.assert_array_equal(outer0, -1.5)
    # offsets add up when applied twice
    twice = EFFECTS["interference_error"].apply(out, {"inner_um": 1.0}, T_REF)
    np.testing.assert_array_equal(twice.interference_inner_um, 3.5)
    np.testing.assert_array_equal(twice.interference_outer_um, -1.0)


def test_radial_gradient_sign_and_speed():
    base = cycle_inputs()
    out = EFFECTS["radial_gradient"].apply(base, {"dT_K": 2.0, "dT_per_krpm_K": 1.5}, T_REF)
    expect = 2.0 + 1.5 * base.speed_rpm / 1000.0        # 3.5 K at 1000 rpm, 6.5 K at 3000 rpm
    for p in ("shaft", "inner_ring", "ball"):
        np.testing.assert_allclose(out.T_C[p] - base.T_C[p], expect, rtol=0, atol=1e-12)
    for p in ("outer_ring", "housing", "spacer"):
        np.testing.assert_array_equal(out.T_C[p], base.T_C[p])
    d = out.T_C["inner_ring"] - out.T_C["outer_ring"]
    assert np.all(d > 0) and d[-1] > d[0]                 # warmer inside, more at higher speed


def test_lag_exact_step_response():
    # closed form for a step of height A at t = 0+: T(t) = A (1 - exp(-t/tau)); with the ambient
    # jumping between two samples 1e-6 s apart the piecewise-linear input is a step to 1e-5.
    tau, A = 300.0, 40.0
    t = np.concatenate([[0.0, 1e-6], np.linspace(1.0, 3000.0, 200)])
    u = np.where(t > 0, A, 0.0)
    y = lag_response(t, u, tau)
    np.testing.assert_allclose(y[2:], A * (1 - np.exp(-(t[2:] - 1e-6) / tau)), rtol=1e-5,
                               atol=1e-4)


def test_lag_ramp_exact_and_steady_value():
    # ramp u = r t from equilibrium: y = r (t - tau (1 - exp(-t/tau))) exactly (any sampling),
    # steady lag r tau; then a hold: the lag decays to zero (steady value = ambient).
    tau, r = 500.0, 0.02
    t = np.sort(np.concatenate([np.linspace(0, 6000, 37), [13.0, 1234.5]]))
    y = lag_response(t, r * t, tau)
    np.testing.assert_allclose(y, r * (t - tau * (1 - np.exp(-t / tau))), rtol=1e-12, atol=1e-10)
    t2 = np.concatenate([t, 6000 + np.linspace(100, 20000, 50)])
    u2 = np.concatenate([r * t, np.full(50, r * 6000)])
    y2 = lag_response(t2, u2, tau)
    assert abs(y2[-1] - r * 6000) < 1e-9          # lag r tau decays as exp(-19900/500)


def test_thermal_lag_acts_on_ambient_following_parts_only():
    base = cycle_inputs(measured_part="housing")
    out = EFFECTS["thermal_lag"].apply(base, {"tau_s": 600.0}, T_REF)
    np.testing.assert_array_equal(out.T_C["housing"], base.T_C["housing"])   # measured
    expect = lag_response(base.time_s, base.T_ambient_C, 600.0)
    for p in ("shaft", "inner_ring", "ball", "outer_ring", "spacer"):
        np.testing.assert_array_equal(out.T_C[p], expect)
    np.testing.assert_array_equal(out.T_ambient_C, base.T_ambient_C)
    assert out.T_C["ball"][0] == base.T_ambient_C[0]                  # starts in equilibrium
    # on a heating ramp the lag r tau (1 - exp(-t/tau)) grows with tau: the parts are cooler
    t = np.arange(50) * 60.0
    ramp = baseline_inputs({"time_s": t, "T_ambient_C": 20 + 0.01 * t}, 50, T_REF, 100.0, 60.0)
    lags = [ramp.T_ambient_C[-1] - EFFECTS["thermal_lag"].apply(ramp, {"tau_s": tau}, T_REF)
            .T_C["ball"][-1] for tau in (100.0, 1000.0, 5000.0)]
    assert 0 < lags[0] < lags[1] < lags[2]


def test_thermal_lag_leaves_a_measured_part_at_the_ambient_alone():
    """A part whose temperature column was given is measured even when its readings equal the
    ambient's (a sensor beside the chamber's): the lag must not replace them. The lagged parts
    follow the closed-form first-order response (`lag_response`, tested against the ramp
    solution above)."""
    t = np.arange(40) * 60.0
    amb = 20.0 + 0.05 * t
    base = baseline_inputs({"time_s": t, "T_ambient_C": amb, "T_housing_C": amb.copy()}, t.size,
                           T_REF, 100.0, 60.0)
    assert base.measured_parts == {"housing"}
    for name, params in (("thermal_lag", {"tau_s": 600.0}),
                         ("thermal_lag.per_part", {"tau_s": 600.0, "tau_shaft_s": 900.0})):
        out = get_effect(name).apply(base, params, T_REF)
        np.testing.assert_array_equal(out.T_C["housing"], amb, err_msg=name)      # measured
        np.testing.assert_array_equal(out.T_C["outer_ring"], lag_response(t, amb, 600.0),
                                      err_msg=name)
        # on a heating ramp the lagged part is cooler than the ambient by r tau (1 - e^-t/tau)
        assert out.T_C["outer_ring"][-1] < amb[-1] - 0.05 * 600.0 * 0.9


def test_friction_temperature_linear_in_ring_mean():
    base = cycle_inputs()
    T = dict(base.T_C)
    T["inner_ring"] = T["inner_ring"] + 4.0
    warm = base.copy(T_C=T)
    out = EFFECTS["friction_temperature"].apply(warm, {"dmu_per_K": 1e-4}, T_REF)
    ring_mean = 0.5 * (warm.T_C["inner_ring"] + warm.T_C["outer_ring"])
    change = 1e-4 * (ring_mean - T_REF)
    # round-off relative to the terms: the largest change, and the coefficient 0.02 it adds to
    np.testing.assert_allclose(out.friction_coefficient, change, rtol=0,
                               atol=1e-13 * np.abs(change).max())
    mu = resolve_friction_coefficient(out, 0.02)
    np.testing.assert_allclose(mu, np.maximum(0.02 + change, 0), rtol=0,
                               atol=1e-13 * (0.02 + np.abs(change).max()))
    np.testing.assert_array_equal(resolve_friction_coefficient(base, 0.02), 0.02)
    # clipped at zero for a strong negative slope at high temperature
    neg = EFFECTS["friction_temperature"].apply(warm, {"dmu_per_K": -1e-3}, T_REF)
    assert resolve_friction_coefficient(neg, 0.02).min() == 0.0


def test_preload_settling_only_after_first_excursion():
    t = np.arange(8) * 10.0
    amb = np.array([20.0, 35.0, 45.0, 52.0, 20.0, 10.0, 60.0, 20.0])   # |dT|: 0 15 25 32 0 10 40 0
    base = baseline_inputs({"time_s": t, "T_ambient_C": amb}, 8, T_REF, 100.0, 60.0)
    out = EFFECTS["preload_settling"].apply(base, {"loss_N": 12.0, "threshold_K": 30.0}, T_REF)
    np.testing.assert_array_equal(out.preload_loss_N, [0, 0, 0, 12, 12, 12, 12, 12])
    out = EFFECTS["preload_settling"].apply(base, {"loss_N": 12.0, "threshold_K": 35.0}, T_REF)
    np.testing.assert_array_equal(out.preload_loss_N, [0, 0, 0, 0, 0, 0, 12, 12])
    out = EFFECTS["preload_settling"].apply(base, {"loss_N": 12.0, "threshold_K": 45.0}, T_REF)
    np.testing.assert_array_equal(out.preload_loss_N, 0.0)     # never exceeded
    # cold excursions count too (|T - T_ref|)
    cold = baseline_inputs({"time_s": t, "T_ambient_C": 40.0 - amb}, 8, T_REF, 100.0, 60.0)
    out = EFFECTS["preload_settling"].apply(cold, {"loss_N": 3.0, "threshold_K": 30.0}, T_REF)
    np.testing.assert_array_equal(out.preload_loss_N, [0, 0, 0, 3, 3, 3, 3, 3])
    # the grid gives one threshold per distinct onset row
    g = settling_grid(EFFECTS["preload_settling"], {"time_s": t, "T_ambient_C": amb}, T_REF,
                      min_rows=1)
    assert g["threshold_K"] == [7.5, 20.0, 28.5, 36.0]


def test_viscosity_and_cte():
    base = cycle_inputs()
    out = EFFECTS["viscosity_temperature"].apply(base, {"slope_factor": 1.3}, T_REF)
    assert out.viscosity_slope_factor == 1.3
    out = EFFECTS["cte_nonlinearity"].apply(base, {"dalpha_per_K": 5e-9}, T_REF)
    assert out.dalpha_per_K2 == {"shaft": 5e-9, "housing": 5e-9}
    for p in PARTS:
        np.testing.assert_array_equal(out.T_C[p], base.T_C[p])


def test_apply_effects_order_lag_then_gradient():
    base = cycle_inputs()
    out = apply_effects(base, {"radial_gradient": {"dT_K": 5.0}, "thermal_lag": {"tau_s": 600.0}},
                        T_REF)
    lagged = lag_response(base.time_s, base.T_ambient_C, 600.0)
    np.testing.assert_allclose(out.T_C["inner_ring"], lagged + 5.0, atol=1e-12)
    np.testing.assert_array_equal(out.T_C["outer_ring"], lagged)
