"""The published measurements of seeds 001 and 000 as data (studies/validation/published_as_data.py):
one-parameter candidates fitted on one published number, the other held out and compared with
the published value. References: the published numbers themselves, Palmgren's viscous torque in
closed form with the oil's Walther law, and the timing of the cycle design."""
from __future__ import annotations

import numpy as np
import pytest

from analytic.lubrication import get_lubricant, lubricant_library
from studies.model.config import load_shipped
from studies.model.effects import get_effect
from studies.validation import published_as_data as pad

#: a coarser FE mesh than the shipped one (the ratios depend on the mesh through the groove-centre
#: shifts only, far below the 5.9 % tolerance); the study report runs the shipped mesh
MESH = 2.0


@pytest.fixture(scope="module")
def s001():
    return pad.seed001(MESH)


def _palmgren_ratio(lub, T1_C, T2_C, slope_factor=1.0):
    """Palmgren's viscous torque ratio at the same speed, f0 and dm: (nu1 / nu2)^(2/3)
    (Harris & Kotzalas Vol. 2 ch. 2; nu from the oil's ASTM D341 law)."""
    return float((lub.nu_mm2_s(T1_C, slope_factor=slope_factor)
                  / lub.nu_mm2_s(T2_C, slope_factor=slope_factor)) ** (2.0 / 3.0))


def test_seed001_viscous_term_follows_palmgren_and_no_oil_side_change_reaches_the_band(s001):
    """Why no candidate fits: the configured torque is Palmgren's viscous term, whose cold ratio is
    (nu(-20) / nu(20))^(2/3) in closed form; at the viscosity slope's bound and for every oil of
    the project's table that ratio alone stays above the band's top (1.5). The cold ratio of the
    whole torque is at least the viscous ratio times the viscous share at 20 C:
    (Mv1 + Ml1) / (Mv2 + Ml2) >= Mv1 / M2 (Ml >= 0)."""
    asm = load_shipped("seed001")
    lub = get_lubricant(asm.lubrication.lubricant)
    out = pad.seed001_torques(asm, mesh_factor=MESH)
    Mv = out.torque.viscous_Nmm
    np.testing.assert_allclose(Mv[0] / Mv[1], _palmgren_ratio(lub, -20.0, 20.0), rtol=1e-9)
    lo_slope = get_effect("viscosity_temperature").bounds["slope_factor"][0]
    assert _palmgren_ratio(lub, -20.0, 20.0, lo_slope) > pad.SEED001_COLD_BAND[1]
    for name, oil in lubricant_library().items():
        try:
            oil.walther()
        except ValueError:
            continue
        assert _palmgren_ratio(oil, -20.0, 20.0) > pad.SEED001_COLD_BAND[1], name
    lower = Mv[0] / out.torque_Nmm[1]
    assert s001.configured[0] >= lower * (1 - 1e-12)
    for f in s001.fits:    # every candidate that keeps Palmgren's term stays above the band
        if pad.replaces_viscous_law(f.candidate):
            continue
        assert f.fitted > pad.SEED001_COLD_BAND[1], f.candidate
        if f.parameter:                      # and a fit that misses sits on a bound or a plateau
            assert not f.reaches


def test_seed001_skf_rung_is_the_blend_of_the_two_laws(s001):
    """The SKF rung of the ladder (share of the way from Palmgren to the SKF model) on seed 001's
    published ratios: its fitted cold ratio and its held-out hot ratio are those of the blend
    P + share (S - P) of the two assemblies' torques through `simulate_table` (an independent
    computation of the same rung, to 1e-9), the share inside 0..1 where the fit reaches the
    band. What the hot prediction is worth against the published 0.75 is measured, not locked
    in here (`bearingfem study published_as_data`): a better law must be free to pass."""
    from dataclasses import replace

    f = next(f for f in s001.fits if f.candidate == "ladder: torque_model_skf")
    asm = load_shipped("seed001")
    skf = replace(asm, lubrication=replace(asm.lubrication, viscous_model="skf2004"))
    P = pad.seed001_torques(asm, mesh_factor=MESH).torque_Nmm
    S = pad.seed001_torques(skf, mesh_factor=MESH).torque_Nmm
    M = P + f.value * (S - P)
    np.testing.assert_allclose([f.fitted, f.predicted], [M[0] / M[1], M[2] / M[1]], rtol=1e-9)
    if f.reaches:
        assert 0.0 < f.value < 1.0


def test_seed001_self_heating_fitted_on_the_cold_ratio_predicts_the_hot_one():
    """Held out: the rings-and-balls offset fitted on the cold ratio alone (bound lifted) predicts
    the hot ratio within the tolerance of the published 0.75 (5.9 %, the relative half-width of
    the published cold band), but only through a preload far above the assembled 7 N (the
    report's reason to reject it). The whole stack warmer does not reach the band's centre
    within the 150 K searched: then the ratio is the configured one at shifted temperatures, all
    viscous (the preload is lost hot), and Palmgren's closed form at the largest shift,
    (nu(130 C) / nu(170 C))^(2/3), is still above the centre."""
    h = pad.self_heating_unbounded("bearing", MESH)
    assert pad.SELF_HEATING_MAX_K < h.dT_K < 150.0
    assert abs(h.ratio_hot - pad.SEED001_HOT) <= pad.SEED001_REL_TOL * pad.SEED001_HOT
    assert h.preload_20C_N > 100 * load_shipped("seed001").preload.assembled_N
    s = pad.self_heating_unbounded("stack", MESH)
    assert np.isnan(s.dT_K)
    lub = get_lubricant(load_shipped("seed001").lubrication.lubricant)
    assert _palmgren_ratio(lub, 130.0, 170.0) > np.sqrt(np.prod(pad.SEED001_COLD_BAND))


@pytest.fixture(scope="module")
def s000():
    return pad.seed000("max", MESH), pad.seed000("min", MESH)


def test_seed000_settling_cannot_move_the_minimum(s000):
    """A one-off preload loss at the first excursion beyond 70 K comes, in the cycle design,
    after the first cycle's maximum (the +60 K dwell) and before its minimum (the -80 K dwell):
    both minima carry the loss, so the held-out minimum change is zero whatever the loss, against
    the published +0.9 N mm."""
    cols = pad.seed000_design()
    t, T = cols["time_s"], cols["T_ambient_C"]
    first = t < 60.0 * pad.SEED000_CYCLE_MIN
    trigger = t[np.flatnonzero(np.abs(T - 20.0) > 70.0)[0]]
    assert trigger > t[first][np.argmax(T[first])]
    assert trigger <= t[first][np.argmin(T[first])]
    on_max, _ = s000
    f = next(f for f in on_max.fits if f.candidate.startswith("preload_settling ("))
    assert f.fit_in_band and abs(f.fitted - pad.SEED000_MAX_CHANGE_NMM) <= pad.SEED000_TOL_NMM
    assert abs(f.predicted) <= 1e-9


def test_seed000_history_candidates_move_the_cycle_extremes_as_their_physics_says(s000):
    """Each history candidate's (max, min) cycle changes, fitted on either published change,
    have the signs its physics dictates (a solid-film torque rises with the contact loads, hence
    with the preload, and is linear in the film's coefficient): creep only loses preload, so
    both extremes fall or stay (<= 0); a run-in change dmu moves both extremes with the sign of
    dmu; a softer preload path in series (k_eff = 1 / (1/k + c) < k) shrinks the thermal preload
    swing, so the maximum falls and the minimum rises (the sign pattern published, -1.7 / +0.9
    N mm). Whether the held-out value is reached is measured in the study's report, not locked
    in here (round-off 1e-9 N mm)."""
    tol = 1e-9
    for r, i_fit in zip(s000, (0, 1)):
        for f in r.fits:
            ch = [0.0, 0.0]
            ch[i_fit], ch[1 - i_fit] = f.fitted, f.predicted
            if f.candidate.startswith("preload_settling.creep"):
                assert ch[0] <= tol and ch[1] <= tol, (f.candidate, ch)
            elif f.candidate.startswith("solid_film_runin"):
                assert all(np.sign(c) in (0.0, np.sign(f.value)) for c in ch), (f.candidate, ch)
            elif f.candidate.startswith("preload path softened"):
                assert ch[0] <= tol and ch[1] >= -tol, (f.candidate, ch)
                if f.value > 0:
                    assert ch[0] < 0 < ch[1], (f.candidate, ch)


def test_seed001_ladder_rungs_are_its_model_forms(s001):
    """The model forms tried on seed 001 are the diagnosis's ladder (one route): every rung with
    a candidate appears, one parameter at a time, and the rungs the ladder does not try are
    stated with its reason. Independent check of the route: the quasi-dynamic switch at its
    bound (share 1, where the fit on the cold ratio ends: no share reaches the band) predicts
    what the assembly with `ball_model = "quasi_dynamic"` gives through `simulate_table`, to
    round-off of the blend base + 1 (form - base) (1e-12 relative)."""
    from dataclasses import replace

    from studies.diagnosis.ladder import ladder

    asm = load_shipped("seed001")
    names = {f.candidate for f in s001.fits}
    for rung in ladder(asm):
        if rung.candidate is None or "time_s" in rung.candidate.requires:
            assert any(t.startswith(rung.name) for t in pad.ladder_not_tried(asm)), rung.name
            continue
        for p in rung.candidate.parameters:
            label = rung.name if len(rung.candidate.parameters) == 1 else f"{rung.name} ({p})"
            assert f"ladder: {label}" in names
    assert not any("spring" in n.lower() for n in names)      # the ladder's: carried, not tried
    qd = next(f for f in s001.fits if f.candidate == "ladder: ball_model_quasi_dynamic")
    assert qd.value == 1.0 and not qd.reaches
    form = replace(asm, operating=replace(asm.operating, ball_model="quasi_dynamic"))
    M = pad.seed001_torques(form, mesh_factor=MESH).torque_Nmm
    np.testing.assert_allclose([qd.fitted, qd.predicted], [M[0] / M[1], M[2] / M[1]], rtol=1e-12)


@pytest.fixture(scope="module")
def friction_models():
    return pad.seed001_friction_models(MESH)


def test_seed001_starved_fits_reproduce_the_cold_ratio_and_predict_through_the_pipeline(
        friction_models):
    """The starved film's oil quantity fitted on seed 001's cold ratio (through the pipeline's
    `viscous_model = "starved"`): every fit lands on the published band's centre (to 1e-6), and
    its held-out hot ratio is the pipeline's own torque ratio at that oil quantity, recomputed
    (a second evaluation, to 1e-9). The published hot ratio is the measurement the law is
    judged against in the study's report, not an expected failure here."""
    scans, _ = friction_models
    target = np.sqrt(np.prod(pad.SEED001_COLD_BAND))
    asm = load_shipped("seed001")
    for s in scans:
        assert s.fits, s.candidate
        for f in s.fits:
            assert f.fit_in_band and abs(f.fitted - target) < 1e-6 * target
            M = pad.seed001_torque_Nmm(pad.seed001_with(asm, viscous_model="starved",
                                                        oil_quantity_mg=f.value), mesh_factor=MESH)
            np.testing.assert_allclose([f.fitted, f.predicted], [M[0] / M[1], M[2] / M[1]],
                                       rtol=1e-9)


def test_seed001_starved_film_limits(friction_models):
    """Limits of the starved film through the pipeline against Palmgren's closed form: with an
    oil quantity 1e6 x the upper bound the torque is the configured (flooded Palmgren) one to
    1e-9; at 60 C, where the configured preload is lost (0 N, no Hertz contact), the torque is
    Palmgren's viscous term f0 (nu n)^(2/3) dm^3 1e-7 per bearing, for any oil quantity."""
    from analytic.friction.palmgren import palmgren_viscous_torque_Nmm

    (s,), _ = friction_models
    asm = load_shipped("seed001")
    flooded = pad.seed001_torque_Nmm(pad.seed001_with(asm, viscous_model="starved",
                                                      oil_quantity_mg=1e6 * s.bounds[1]),
                                     mesh_factor=MESH)
    np.testing.assert_allclose(flooded, pad.seed001_torque_Nmm(asm, mesh_factor=MESH), rtol=1e-9)
    out = pad.seed001_torques(asm, mesh_factor=MESH)
    assert out.preload_N[2] == 0.0
    lub, b = asm.lubrication, asm.bearing
    nu60 = get_lubricant(lub.lubricant).nu_mm2_s(60.0)
    palm = 2.0 * 1e-7 * lub.viscous_factor_f0 * (nu60 * lub.speed_rpm) ** (2.0 / 3.0) \
        * b.pitch_diameter_mm ** 3
    np.testing.assert_allclose(palmgren_viscous_torque_Nmm(lub.viscous_factor_f0, nu60,
                                                           lub.speed_rpm, b.pitch_diameter_mm),
                               palm / 2.0, rtol=1e-12)
    for m in (s.bounds[0], s.fits[0].value, s.bounds[1]):
        M = pad.seed001_torque_Nmm(pad.seed001_with(asm, viscous_model="starved",
                                                    oil_quantity_mg=m), mesh_factor=MESH)
        np.testing.assert_allclose(M[2], palm, rtol=1e-9)


def test_seed001_hot_interval_is_the_delta_method_on_a_linear_model():
    """The held-out interval route against its closed form: for ratios linear in the parameter,
    cold = a + b p and hot = c + d p, fitted on the cold ratio with sd s_c, the hot ratio's
    predictive sd is sqrt((d / b)^2 s_c^2 + s_h^2) exactly (Seber & Wild ch. 5.1), the 90 %
    interval +-1.645 sd (standard normal quantile 0.95 = 1.6448536)."""
    a, b, c, d = 0.9, 0.02, 1.1, -0.015
    target = np.sqrt(np.prod(pad.SEED001_COLD_BAND))
    p = (target - a) / b
    lo, hi = pad.seed001_hot_interval(lambda x: (a + b * x, c + d * x), p)
    s_c = pad.SEED001_REL_SD * target
    s_h = pad.SEED001_REL_SD * pad.SEED001_HOT
    half = 1.6448536269514722 * np.sqrt((d / b) ** 2 * s_c ** 2 + s_h ** 2)
    np.testing.assert_allclose([lo, hi], [c + d * p - half, c + d * p + half], rtol=1e-9)


def test_seed001_friction_model_intervals_hold_their_prediction(friction_models):
    """Each friction-model fit's 90 % interval of the held-out hot ratio (fit uncertainty and the
    published scatter) holds its own prediction and is at least the published scatter alone
    wide (+-1.645 x the relative sd of the published ratio: the parameter's part only adds)."""
    s_h = pad.SEED001_REL_SD * pad.SEED001_HOT
    for s in friction_models[0]:
        assert len(s.intervals) == len(s.fits)
        for f, (lo, hi) in zip(s.fits, s.intervals):
            assert lo < f.predicted < hi
            assert hi - lo >= 2 * 1.6448536269514722 * s_h * (1 - 1e-9)


def test_seed000_solid_film_laws_follow_the_preload():
    """Seed 000's trend steps (0..80 C at 100 N) through the solid-film laws: the constant
    coefficient, Singer et al.'s pressure-dependent shear strength and its two limits. Closed
    form every such law must meet: the film's friction force over a Hertz contact,
    tau0 pi a b + alpha Q, increases with the ball load Q for tau0, alpha >= 0, so each law's
    torque changes with the sign of the preload's change at every step. Independent check of the
    pressure route: with tau0 = 0 the law is Coulomb's mu = alpha, so alpha = 0.02 gives the
    configured constant coefficient 0.02 exactly (1e-9)."""
    laws = pad.seed000_trend(MESH)
    assert load_shipped("seed000").lubrication.friction_coefficient == 0.02
    np.testing.assert_allclose(laws[3].torque_Nmm, laws[0].torque_Nmm, rtol=1e-9)
    for t in laws:
        assert t.follows_preload, t.law
