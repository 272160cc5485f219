"""Two effects beyond the spec's seven, against closed forms, through the real model:

- `solid_film_runin`: revolutions against the integral of the speed (constant speed: n t / 60;
  a linear ramp: (n0 t + a t^2 / 2) / 60), the friction change against the exponential closed form
  dmu (1 - exp(-n t / (60000 runin_krev))) at constant speed;
- `preload_path_compliance`: at the reference state the pair's axial stiffness against the
  series-spring arithmetic 1/k_eff = 1/k_bearing + c_path + c_x (per bearing, summed over the
  pair), the preload unchanged; a small temperature change's preload change against the loop of
  springs in series, dF = delta / (1/k_A + 1/k_B + 2 (c_path + c_x));
- each at its off value gives the model's outputs bit for bit;
- a hidden instance of each, made with the simulate route, is recovered by the diagnosis.
"""
from __future__ import annotations

import numpy as np
import pytest

from studies.diagnosis.designs import cycles
from studies.diagnosis.engine import diagnose_full
from studies.diagnosis.files import NUISANCE, ModelPredictor
from studies.diagnosis.fitspec import RUNIN_PER_DECADE
from studies.diagnosis.result import to_json
from studies.model.config import load_shipped
from studies.model.effects import EFFECTS, ORDER
from studies.model.effects.preload_path_compliance import UM_PER_KN
from studies.model.effects.solid_film_runin import revolutions
from studies.model.inputs import baseline_inputs
from studies.model.pipeline import Pipeline, simulate_table
from studies.model.columns import to_columns

T_REF = 20.0


@pytest.fixture(scope="module")
def pl000():
    return Pipeline(load_shipped("seed000"), mesh_factor=2.0)


@pytest.fixture(scope="module")
def pl001():
    return Pipeline(load_shipped("seed001"), mesh_factor=2.0)


# ------------------------------------------------------------------------ solid_film_runin
def test_revolutions_are_the_integral_of_the_speed():
    t = np.linspace(0.0, 3600.0, 37)
    np.testing.assert_allclose(revolutions(t, np.full(t.size, 60.0)), t, rtol=1e-14)   # 1 rev/s
    # a linear ramp 100 -> 1900 rpm: the trapezoidal rule is exact for a piecewise linear speed
    n = 100.0 + 0.5 * t
    np.testing.assert_allclose(revolutions(t, n), (100.0 * t + 0.25 * t ** 2) / 60.0, rtol=1e-13)


def test_runin_is_the_exponential_closed_form_at_constant_speed():
    t = np.arange(0.0, 20000.0, 100.0)
    inp = baseline_inputs({"time_s": t, "T_ambient_C": np.full(t.size, 20.0)}, t.size, T_REF,
                          100.0, speed_rpm=300.0)
    out = EFFECTS["solid_film_runin"].apply(inp, {"dmu": -0.01, "runin_krev": 25.0}, T_REF)
    expected = -0.01 * (1.0 - np.exp(-300.0 * t / 60.0 / 25000.0))
    # the first rows are near 0 (a relative tolerance alone is void there): round-off of the
    # change, 16 eps of its scale |dmu| = 0.01
    np.testing.assert_allclose(out.friction_coefficient, expected, rtol=1e-12,
                               atol=16 * np.finfo(float).eps * 0.01)
    assert out.friction_coefficient[0] == 0.0          # the film as configured at the first row


def test_runin_changes_only_the_friction_torque(pl000):
    """Through the model: at dmu = 0 the outputs are the baseline's bit for bit; with a run-in
    the preload is untouched and the torque falls by the friction part only (a lower mu, the
    same load): the torque change has the sign of dmu and grows with the revolutions."""
    cond = cycles(n=60, dt=600.0)
    base = to_columns(simulate_table(pl000.asm, cond, {}, pipeline=pl000))
    off = to_columns(simulate_table(pl000.asm, cond, {"solid_film_runin": {"dmu": 0.0}}, pipeline=pl000))
    for c in ("torque_Nmm", "preload_N"):
        np.testing.assert_array_equal(off[c], base[c])
    on = to_columns(simulate_table(pl000.asm, cond, {"solid_film_runin": {"dmu": -0.005, "runin_krev": 5.0}},
                        pipeline=pl000))
    np.testing.assert_array_equal(on["preload_N"], base["preload_N"])
    d = on["torque_Nmm"] - base["torque_Nmm"]
    assert d[0] == 0.0 and np.all(d[1:] < 0)


# ------------------------------------------------------------------------ preload_path_compliance
def _ref_state(pl, effects, dT_K=0.01):
    cond = {"T_ambient_C": np.array([T_REF, T_REF + dT_K, T_REF + 10 * dT_K]),
            "speed_rpm": np.zeros(3)}                                       # at rest
    return to_columns(simulate_table(pl.asm, cond, effects, pipeline=pl))


@pytest.mark.parametrize("cx_um_per_kN", [50.0, 500.0, 5000.0])
def test_compliance_is_a_spring_in_series(pl001, cx_um_per_kN):
    """Seed 001 (7 N position preload). At the reference temperature the preload is the
    assembled one whatever the compliance; the pair stiffness is the sum over both bearings of
    1 / (1/k_j + c_path + c_x), with k_j the bearing's own contact stiffness recovered from the
    baseline's effective stiffness (1/k_j = 1/k_eff,j - c_path)."""
    c0 = float(pl001.compliance_mm_per_N)
    cx = cx_um_per_kN * UM_PER_KN
    base = _ref_state(pl001, {})
    on = _ref_state(pl001, {"preload_path_compliance": {"extra_compliance_um_per_kN": cx_um_per_kN}})
    P = pl001.asm.preload.assembled_N
    # the preload at T_ref: the assembled one (the solver's tolerance, 1e-9 relative)
    assert on["preload_N"][0] == pytest.approx(P, rel=1e-9)
    assert base["preload_N"][0] == pytest.approx(P, rel=1e-9)
    kA0, kB0 = 1e3 * bearing_stiffness_N_per_um(pl001)                      # N/mm
    assert 1e3 * base["axial_stiffness_N_per_um"][0] == pytest.approx(kA0 + kB0, rel=1e-12)
    kA, kB = 1.0 / (1.0 / kA0 - c0), 1.0 / (1.0 / kB0 - c0)                 # contact only
    expected = 1.0 / (1.0 / kA + c0 + cx) + 1.0 / (1.0 / kB + c0 + cx)
    assert 1e3 * on["axial_stiffness_N_per_um"][0] == pytest.approx(expected, rel=1e-9)
    # a small temperature step: the preload change is the thermal mismatch over the loop
    # compliance, so its ratio to the baseline's is (1/kA + 1/kB + 2 c0) / (1/kA + 1/kB +
    # 2 (c0 + cx)) to first order; the Hertz nonlinearity leaves an error proportional to the
    # step: it must shrink ~10x from 0.1 K to 0.01 K (first order) and be below 0.2 % at 0.01 K
    loop0 = 1.0 / kA + 1.0 / kB + 2 * c0
    expected = loop0 / (loop0 + 2 * cx)
    err = []
    for i in (2, 1):                               # 0.1 K, then 0.01 K
        dF0 = base["preload_N"][i] - base["preload_N"][0]
        dF = on["preload_N"][i] - on["preload_N"][0]
        assert abs(dF0) > 1e-4
        err.append(abs(dF / dF0 / expected - 1.0))
    assert err[1] < 2e-3 and 5.0 < err[0] / err[1] < 20.0, err


def bearing_stiffness_N_per_um(pl):
    """Each bearing's effective axial stiffness (N/um, path in series) at the reference state,
    from the pair state the pipeline returns."""
    inp = baseline_inputs({"T_ambient_C": np.array([T_REF])}, 1, T_REF,
                          pl.asm.preload.assembled_N, speed_rpm=0.0)
    pair = pl.run(inp).pair
    return np.asarray(pair.axial_stiffness_N_per_um, float)[:, 0]


def test_compliance_off_is_baseline_exactly(pl001):
    cond = {"T_ambient_C": np.array([-20.0, 20.0, 40.0])}
    base = to_columns(simulate_table(pl001.asm, cond, {}, pipeline=pl001))
    off = to_columns(simulate_table(pl001.asm, cond, {"preload_path_compliance": {}}, pipeline=pl001))
    for c in ("torque_Nmm", "preload_N", "axial_stiffness_N_per_um"):
        np.testing.assert_array_equal(off[c], base[c])


# ------------------------------------------------------------------------ hidden instances
def _diagnose(pl, cond, meas):
    pred = ModelPredictor(pl, cond, meas.keys())
    cands = [EFFECTS[n].for_assembly(pl.asm) for n in ORDER]
    return to_json(diagnose_full(pred, meas, cond, cands, NUISANCE, T_ref_C=pl.asm.T_ref_C,
                                 predict_at=pred.at))


def _noisy(pl, cond, eff, sigma, seed, mu_scale=1.25):
    pred = ModelPredictor(pl, cond, tuple(sigma))
    truth = pred(eff, {"mu_scale": mu_scale})
    rng = np.random.default_rng(seed)
    return {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in sigma.items()}


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_hidden_runin_is_recovered(pl000):
    """Seed 000 at its configured 60 rpm, three -60 <-> 80 C cycles (246 rows, 73.8 krev), a
    run-in of the MoS2 film by -0.004 with a 10 krev constant, torque noise 0.02 N mm: explained
    by solid_film_runin, dmu within 3 of its standard uncertainties, the run-in constant inside
    the profile's interval widened by one grid step (the grid is 12 % per step)."""
    cond = cycles(n=246, dt=300.0)
    eff = {"solid_film_runin": {"dmu": -0.004, "runin_krev": 10.0}}
    res = _diagnose(pl000, cond, _noisy(pl000, cond, eff, {"torque_Nmm": 0.02}, seed=4))
    assert (res["verdict"], res["cause"]) == ("explained", "solid_film_runin"), res["reasons"]
    u = res["parameter_uncertainty"]
    assert abs(res["parameters"]["dmu"] + 0.004) <= 3 * u["dmu"], (res["parameters"], u)
    lo, hi = u["runin_krev"]["interval"]
    step = 10 ** (1 / RUNIN_PER_DECADE)
    assert lo / step <= 10.0 <= hi * step, (res["parameters"], u)


@pytest.mark.slow
def test_hidden_path_compliance_is_recovered(pl001):
    """Seed 001 (oil, 7 N position preload), temperature steps -20..40 C at 3500/6000/9000 rpm,
    torque (1 N mm) and preload (0.05 N) measured, a preload path 300 um/kN softer than the FE's:
    explained by preload_path_compliance, the compliance within 3 standard uncertainties."""
    from tests.test_diagnose_pipeline import oil_speed_steps_001

    cond = oil_speed_steps_001()
    eff = {"preload_path_compliance": {"extra_compliance_um_per_kN": 300.0}}
    res = _diagnose(pl001, cond, _noisy(pl001, cond, eff, {"torque_Nmm": 1.0, "preload_N": 0.05},
                                        seed=3))
    assert (res["verdict"], res["cause"]) == ("explained", "preload_path_compliance"), \
        (res["verdict"], res["cause"], res["indistinguishable"], res["reasons"])
    got = res["parameters"]["extra_compliance_um_per_kN"]
    u = res["parameter_uncertainty"]["extra_compliance_um_per_kN"]
    assert abs(got - 300.0) <= 3 * u, (got, u)
