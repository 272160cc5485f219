"""The claim rules on the real model with data made another way (`studies/validation/
second_source.py`'s machinery): a change below the detection threshold is not claimed; a listed
cause well above it still is.

The hidden case: an unlisted free contact angle 3 deg off, its change after the
friction scale 0.75 sigma RMS, was claimed as `interference_error`. Here the truth is the
shipped seed 000 assembly with its free contact angle 3 deg larger, run through the plain
pipeline (`second_source._run`: `Pipeline.run`, no effect code, the rig's friction 1.2 x the
configured one), the noise scaled so that the RMS change after the friction scale (bounded
least squares of the scale alone) is 0.75 sigma in the column that changes most; the diagnosis
is `diagnose`'s own (`second_source.diagnose_case`: the CLI's candidates and ladder).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy import optimize

pytestmark = pytest.mark.slow

MESH_FACTOR = 2.0
CLAIMS = ("explained", "explained_partly")


def _contact_angle_case(rms_sigma: float, seed: int):
    """A second-source `Case` of the `cycles` design whose truth has the free contact angle
    3 deg off (module docstring), the noise scaled to `rms_sigma` RMS change."""
    from studies.diagnosis.files import NUISANCE, ModelPredictor
    from studies.validation import second_source as ss

    asm = ss.design_assembly("cycles")
    cond = ss.DESIGNS["cycles"][1]()
    b = asm.bearing
    truth_asm = replace(asm, bearing=replace(b, contact_angle_free_deg=b.contact_angle_free_deg
                                             + 3.0))
    truth = ss._run(truth_asm, MESH_FACTOR, cond)
    sigma = ss.stated_sigma(truth)
    pred = ModelPredictor(ss._pipeline(asm, MESH_FACTOR), cond, tuple(truth))
    lo, hi = NUISANCE["mu_scale"][:2]

    def res(x):
        base = pred({}, {"mu_scale": float(x[0])})
        return np.stack([(truth[c] - base[c]) / sigma[c] for c in truth])
    x = optimize.least_squares(lambda x: res(x).ravel(), [ss.MU_TRUE], bounds=([lo], [hi]),
                               diff_step=1e-4).x
    k = float(np.max(np.sqrt(np.mean(res(x) ** 2, axis=1)))) / rms_sigma
    sigma = {c: k * s for c, s in sigma.items()}
    noise = ss.Noise(sigma=sigma)
    measured, _ = ss.add_noise(truth, noise, np.random.default_rng([seed, 42]), cond["time_s"])
    return ss.Case("contact_angle_3deg", "model_form", "cycles", seed, ("contact_angle",), (),
                   asm, {k: np.asarray(v, float) for k, v in cond.items()}, measured, truth,
                   sigma, noise, rms_sigma, "free contact angle 3 deg off",
                   mesh_factor=MESH_FACTOR)


@pytest.mark.parametrize("seed", [0, 1])
def test_an_unlisted_contact_angle_at_075_sigma_is_not_claimed(seed):
    """0.75 sigma RMS after the friction scale (below the cycles design's threshold, 0.97 sigma
    on 240 rows; the change estimate passes it in about 9 % of draws): no cause is claimed (the
    hidden case was `explained: interference_error`; seed 1 was `explained: material_lot` at the
    power 0.8)."""
    from studies.validation import second_source as ss

    case = _contact_angle_case(0.75, seed)
    r = ss.diagnose_case(case)
    assert r.verdict not in CLAIMS + ("ambiguous",) and r.cause is None, (
        r.verdict, r.cause, r.reasons, r.detection)
    assert set(r.detection) == set(case.columns)


def test_a_listed_cause_well_above_the_threshold_is_still_claimed():
    """The inner fit 5 um tighter made on a finer mesh with direct FE solves
    (`fit_error_finer_mesh`, 7.4 sigma at most): its change is above the threshold and the fit
    error is claimed."""
    from studies.validation import second_source as ss

    case = ss.make_case("fit_error_finer_mesh", 0, MESH_FACTOR)
    r = ss.diagnose_case(case)
    assert ss.judge_result(case, r) == "right" and r.cause == "interference_error", (
        r.verdict, r.reasons)
    assert any(d.change_sigma > d.threshold_sigma for d in r.detection.values())
