"""Operating characteristics of `bearingfem diagnose` on data made by the REAL model (slow: run with
`.venv/bin/python -m pytest -m slow -s tests/test_diagnose_pipeline_slow.py`; prints the rates).

Goals: false claims <= 5 % over at least 20 null datasets; hits >= 90 % over at least 10
datasets per effect where the effect's largest change is at least 5 noise standard deviations.

- A *claim* is a verdict that names a cause (`explained` or `ambiguous`); on null data every claim
  is false. A *hit* is `explained` with the hidden effect as the cause; `explained` with another
  cause is a wrong claim (never allowed: "never the wrong one with confidence").
- Datasets vary the shipped configuration, the test design (temperature steps with or without
  time, preload sweep, -60 <-> 80 C cycles, temperature steps at several speeds; their length and
  sampling), the measured columns, the rig's friction coefficient (`mu_scale` 0.7..1.5, the
  nuisance), the noise level and the noise draw.
- Largest change (as in `test_diagnose_pipeline.py`): noise-free data with the effect against the
  baseline refitted with its nuisance, max over rows and measured columns, in noise units. The noise
  of each hidden-effect dataset is scaled so that it is drawn uniformly between 5 and 20 sigma; the
  effect parameters are drawn from physically plausible ranges (sign and size at random).
- Pipelines at `mesh_factor=2.0` (data and model alike).
"""
from __future__ import annotations

import time
import zlib

import numpy as np
import pytest
from scipy import stats

from studies.diagnosis.operating import stated_false_alarm_level
from studies.model.config import load_shipped
from studies.model.effects import ORDER
from studies.model.pipeline import Pipeline

from test_diagnose_pipeline import (MESH_FACTOR, cycles, diagnose_real, largest_change_sigma,
                                    measured, oil_speed_steps_001, oil_speed_steps_003,
                                    preload_sweep, temp_steps)

pytestmark = pytest.mark.slow

GOAL_FALSE_CLAIMS = 0.05
GOAL_HITS = 0.90             # where the largest change >= 5 sigma
SNR_RANGE = (5.0, 20.0)      # brief: largest change 5..20 sigma

#: base noise per configuration (the same rig assumptions as the fast tests); scaled per dataset
BASE_SIGMA = {"seed000": {"torque_Nmm": 0.02, "preload_N": 0.5},
              "seed001": {"torque_Nmm": 1.0, "preload_N": 0.5},
              "seed003": {"torque_Nmm": 2.0, "preload_N": 5.0}}


@pytest.fixture(scope="module")
def pipelines():
    return {n: Pipeline(load_shipped(n), mesh_factor=MESH_FACTOR)
            for n in ("seed000", "seed001", "seed003")}


# ============================================================================ designs
def design(kind, rng):
    """(configuration, conditions) of one randomised test design."""
    if kind == "cycles":                        # seed 000: -60 <-> 80 C with time
        return "seed000", cycles(n=int(rng.integers(180, 301)), dt=float(rng.choice([90, 120, 150])))
    if kind == "steps":                         # seed 000: temperature steps, fixed preload
        return "seed000", temp_steps(per=int(rng.integers(12, 25)), time_col=bool(rng.integers(2)))
    if kind == "steps_time":                    # seed 000: steps from 20 C with time and dwells
        levels = (20, 40, 60, 80, 60, 40, 20, 0, -20, -40, -60, -40, -20, 0, 20)
        return "seed000", temp_steps(levels=levels, per=int(rng.integers(10, 17)), dt=120.0)
    if kind == "sweep":                         # seed 000: preload sweep at several temperatures
        return "seed000", preload_sweep(rep=int(rng.integers(2, 5)))
    if kind == "speeds001":                     # seed 001: steps at 3500/6000/9000 rpm
        return "seed001", oil_speed_steps_001()
    if kind == "speeds003":                     # seed 003: steps at 500/1000/1500 rpm
        return "seed003", oil_speed_steps_003()
    raise ValueError(kind)


def columns_for(seed_name, rng, allow_torque_only=True):
    """Measured columns: torque, with the preload cell in most datasets."""
    base = BASE_SIGMA[seed_name]
    if allow_torque_only and rng.uniform() < 0.3:
        return {"torque_Nmm": base["torque_Nmm"]}
    return dict(base)


def random_params(name, rng):
    """A physically plausible setting of the effect (sign and size at random); ranges from the
    effects' docstrings (typical values, well inside the physical bounds)."""
    s = float(rng.choice([-1.0, 1.0]))
    return {
        "interference_error": {"inner_um": float(rng.uniform(-3, 3)),
                               "outer_um": float(rng.uniform(-1.5, 3))},
        "radial_gradient": {"dT_K": float(rng.uniform(0, 2)),
                            "dT_per_krpm_K": float(rng.uniform(0.2, 2.0))},
        "thermal_lag": {"tau_s": float(rng.uniform(120, 1500))},
        "viscosity_temperature": {"slope_factor": float(rng.choice([rng.uniform(0.8, 0.97),
                                                                     rng.uniform(1.03, 1.25)]))},
        "friction_temperature": {"dmu_per_K": s * float(rng.uniform(0.5e-5, 5e-5))},
        "preload_settling": {"loss_N": float(rng.uniform(2, 20)),
                             "threshold_K": float(rng.uniform(25, 75))},
        "cte_nonlinearity": {"dalpha_per_K": s * float(rng.uniform(3e-9, 2e-8))},
        "solid_film_runin": {"dmu": s * float(rng.uniform(0.002, 0.006)),
                             "runin_krev": float(rng.uniform(3, 30))},
        "preload_path_compliance": {"extra_compliance_um_per_kN": float(rng.uniform(50, 500))},
    }[name]


#: designs in which each effect is identifiable (time for the lag and the settling, several
#: speeds for the speed part of the gradient, an oil bearing for the viscosity law); torque-only
#: datasets only where one column is enough to separate the effect from its look-alikes
DESIGNS_FOR = {
    "interference_error": (("sweep", "cycles", "steps"), False),
    "radial_gradient": (("speeds001", "speeds003"), False),
    "thermal_lag": (("cycles", "steps_time"), True),
    "viscosity_temperature": (("speeds001", "speeds003"), True),
    "friction_temperature": (("steps", "sweep", "cycles"), False),
    "preload_settling": (("cycles", "steps_time"), False),
    "cte_nonlinearity": (("steps", "sweep", "cycles"), False),
    "solid_film_runin": (("cycles", "steps_time"), True),
    # on seed 001's speed steps (7 N preload) a softer preload path and an interference error are
    # near look-alikes: measured 2026-11-24, 7 of 10 ambiguous between the two, never a wrong
    # cause; the hit rate is asked of seed 000's cycles, where they separate
    "preload_path_compliance": (("cycles",), False),
}
NULL_DESIGNS = ("cycles", "steps", "steps_time", "sweep", "speeds001", "speeds003")


def _rate_line(label, k, n):
    return f"{label} {k}/{n} = {k / n:.1%}"


# ============================================================================ null data
N_NULL = 40


def test_false_claim_rate_on_null_data(pipelines):
    rng = np.random.default_rng(zlib.crc32(b"null"))
    rows = []
    t0 = time.perf_counter()
    for i in range(N_NULL):
        seed_name, cond = design(NULL_DESIGNS[i % len(NULL_DESIGNS)], rng)
        sigma = {c: s * float(rng.uniform(0.5, 2.0))
                 for c, s in columns_for(seed_name, rng).items()}
        mu = float(rng.uniform(0.7, 1.5))
        pl = pipelines[seed_name]
        res = diagnose_real(pl, cond, measured(pl, cond, {}, sigma, int(rng.integers(1 << 31)),
                                               mu_scale=mu))
        rows.append((NULL_DESIGNS[i % len(NULL_DESIGNS)], tuple(sigma), res["verdict"],
                     res["cause"], res["indistinguishable"]))
    claims = sum(v in ("explained", "ambiguous") for _, _, v, *_ in rows)
    not_null = sum(v != "no_discrepancy" for _, _, v, *_ in rows)
    verdicts = dict(zip(*np.unique([r[2] for r in rows], return_counts=True)))
    print(f"\nNULL (real model): {N_NULL} datasets in {time.perf_counter() - t0:.0f} s; "
          + _rate_line("cause claimed (false claims)", claims, N_NULL) + "; "
          + _rate_line("any discrepancy reported", not_null, N_NULL)
          + f"; verdicts {verdicts}")
    for d, cols, v, c, ind in rows:
        if v != "no_discrepancy":
            print(f"    {d} {cols}: {v} {c} {ind}")
    assert claims / N_NULL <= GOAL_FALSE_CLAIMS
    # any discrepancy reported on null data is a false alarm: at most the binomial 99 % upper
    # quantile of the stated level (alpha_structure + alpha_lr = 2 %, docs/diagnosis.md) over
    # N_NULL datasets (0.8 of 40 expected, at most 3 here)
    bound = stats.binom.ppf(0.99, N_NULL, stated_false_alarm_level())
    assert not_null <= bound, (not_null, bound, verdicts)


# ============================================================================ hidden effects
N_HIT = 20


@pytest.mark.parametrize("name", ORDER)
def test_hit_rate_per_effect(pipelines, name):
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    kinds, torque_only_ok = DESIGNS_FOR[name]
    rows = []
    t0 = time.perf_counter()
    for i in range(N_HIT):
        kind = kinds[i % len(kinds)]
        seed_name, cond = design(kind, rng)
        pl = pipelines[seed_name]
        base = columns_for(seed_name, rng, allow_torque_only=torque_only_ok)
        params = random_params(name, rng)
        mu = float(rng.uniform(0.7, 1.5))
        snr = float(rng.uniform(*SNR_RANGE))
        change = largest_change_sigma(pl, cond, {name: params}, base, mu_scale=mu)
        sigma = {c: s * change / snr for c, s in base.items()}    # largest change = snr sigma
        res = diagnose_real(pl, cond, measured(pl, cond, {name: params}, sigma,
                                               int(rng.integers(1 << 31)), mu_scale=mu))
        rows.append((kind, tuple(sigma), snr, params, res["verdict"], res["cause"],
                     res["indistinguishable"]))
    hit = sum(v == "explained" and c == name for *_, v, c, _ in rows)
    named = sum(v in ("explained", "ambiguous") and (c == name or name in ind)
                for *_, v, c, ind in rows)
    wrong = sum(v == "explained" and c != name for *_, v, c, _ in rows)
    print(f"\nHIT {name} (real model, largest change {SNR_RANGE[0]:g}..{SNR_RANGE[1]:g} sigma): "
          + _rate_line("explained with the right cause", hit, N_HIT)
          + f"; named incl. ambiguous {named}/{N_HIT}; explained with a wrong cause "
            f"{wrong}/{N_HIT} ({time.perf_counter() - t0:.0f} s)")
    for kind, cols, snr, p, v, c, ind in rows:
        if not (v == "explained" and c == name):
            print(f"    miss: {kind} {cols} {snr:.1f} sigma {p} -> {v} {c} {ind}")
    assert wrong == 0
    assert hit / N_HIT >= GOAL_HITS


# ============================================================================ outside the list
N_DRIFT = 12


def test_sensor_drift_claim_rate(pipelines):
    """A torque-sensor drift linear in time (5..20 sigma over the test; no listed effect): a
    claimed cause is a false claim, so the same goal applies."""
    rng = np.random.default_rng(zlib.crc32(b"drift"))
    kinds = ("cycles", "steps_time", "speeds001", "speeds003")
    rows = []
    for i in range(N_DRIFT):
        kind = kinds[i % len(kinds)]
        seed_name, cond = design(kind, rng)
        pl = pipelines[seed_name]
        sigma = {c: s * float(rng.uniform(0.5, 2.0))
                 for c, s in columns_for(seed_name, rng).items()}
        drift = float(rng.uniform(*SNR_RANGE)) * sigma["torque_Nmm"] * float(rng.choice([-1, 1]))
        res = diagnose_real(pl, cond, measured(pl, cond, {}, sigma, int(rng.integers(1 << 31)),
                                               mu_scale=float(rng.uniform(0.7, 1.5)),
                                               drift=drift))
        rows.append((kind, drift / sigma["torque_Nmm"], res["verdict"], res["cause"],
                     res["indistinguishable"]))
    claims = sum(v in ("explained", "ambiguous") for _, _, v, *_ in rows)
    verdicts = dict(zip(*np.unique([r[2] for r in rows], return_counts=True)))
    print("\nDRIFT (torque sensor, linear in time): " + _rate_line("cause claimed", claims, N_DRIFT)
          + f"; verdicts {verdicts}")
    for kind, d, v, c, ind in rows:
        if v in ("explained", "ambiguous"):
            print(f"    claim: {kind} drift {d:+.1f} sigma -> {v} {c} {ind}")
    assert claims / N_DRIFT <= GOAL_FALSE_CLAIMS


def test_correlated_noise_null_rate(pipelines):
    """AR(1) noise alone (phi 0.8, 2 % of the mean torque; a slowly drifting torque sensor) on
    -60 <-> 80 C cycles: 20 draws, no claim at all and at least 18 no_discrepancy (measured on
    this machine: 20 of 20)."""
    from test_diagnose_pipeline import _ar1_noise, noise_free

    pl = pipelines["seed000"]
    cond = cycles(n=240)
    truth = noise_free(pl, cond, {}, ("torque_Nmm",))
    sig = 0.02 * float(np.mean(np.abs(truth["torque_Nmm"])))
    verdicts = []
    for seed in range(20):
        e = _ar1_noise(np.random.default_rng(seed), 240, sig, 0.8)
        verdicts.append(diagnose_real(pl, cond, {"torque_Nmm": truth["torque_Nmm"] + e})["verdict"])
    print(f"\nAR(1) nulls: {verdicts.count('no_discrepancy')} of 20 no_discrepancy, "
          f"{sum(v in ('explained', 'ambiguous') for v in verdicts)} claims")
    assert not any(v in ("explained", "ambiguous") for v in verdicts)
    assert verdicts.count("no_discrepancy") >= 18
