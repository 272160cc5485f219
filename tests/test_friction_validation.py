"""The minimal-oil law, the friction validation matrix and the model-form interval. References: the published numbers (studies/validation/data/friction_points.csv, each
row's tolerance its source's scatter), Palmgren's closed form and Hamrock-Dowson's film as the
flooded and starved limits, the normal predictive interval in closed form."""
from __future__ import annotations

import numpy as np
import pytest

from analytic.bearing import solve_pair
from analytic.friction import interval as iv
from analytic.friction import minimal_oil as mo
from analytic.lubrication import (ball_raceway_radii_mm, dynamic_viscosity_Pa_s, get_lubricant,
                                  hamrock_dowson_film, reduced_modulus_MPa)
from studies.validation import friction_validation as fv


@pytest.fixture(scope="module")
def lqf():
    return fv.cases()["LQF2018"]


def _factor(case, m, P=133.0, T=20.0, n=6000.0):
    lub = get_lubricant(case.lubricant)
    pair = solve_pair(case.g, "DB", preload_kind="spring", preload_assembled_N=np.array([P]))
    eta = dynamic_viscosity_Pa_s(lub.nu_mm2_s(np.array([T])), lub.density_kg_m3)
    return fv.minimal_oil_pair_ratios(case.g, pair, n, eta, lub.alpha_per_Pa, lub.density_kg_m3,
                                      m)[0], pair, eta


def test_minimal_oil_limits_are_palmgren_flooded_and_the_supply_layer_starved(lqf):
    """Flooded: an unlimited charge gives Palmgren's term exactly (factor 1 to 1e-12). Starved:
    for r << 1 Chevalier's h / h_ff -> r = h_in / h_ff, with h_ff recomputed here from
    Hamrock-Dowson at the inner contact's load and radii, and h_in = m / (rho A_wet) from the
    charge by hand: 0.01 mg on the 305 bearing, r ~ 1e-3, to 1e-3 relative (the next term of
    the law is r^(1+gamma) / gamma)."""
    f, _, _ = _factor(lqf, np.inf)
    np.testing.assert_allclose(f.ratio, 1.0, rtol=1e-12)
    m = 0.01
    f, pair, eta = _factor(lqf, m)
    g, lub = lqf.g, get_lubricant(lqf.lubricant)
    area = np.pi * g.Dw_mm * g.Z * g.Dw_mm + 2 * np.pi * g.dm_mm * g.Dw_mm
    h_in = 1e3 * (m / (lub.density_kg_m3 * 1e-3)) / area
    np.testing.assert_allclose(f.h_in_um, h_in, rtol=1e-12)
    a = float(pair.contact_angle_deg[0, 0])
    Rx, Ry = ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, a, g.f_i, "inner")
    from analytic.torque import ball_kinematics   # contact kinematics stay in analytic.torque
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, np.radians(a))
    u = 6000 * 2 * np.pi / 60 * 0.5 * g.dm_mm * kin.roll_inner
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    h_ff = hamrock_dowson_film(Rx, Ry, Ep, eta, lub.alpha_per_Pa, u,
                               pair.ball_load_N[0]).h_central_um
    np.testing.assert_allclose(f.supply_ratio_inner, h_in / h_ff, rtol=1e-9)
    assert f.supply_ratio_inner[0] < 2e-3
    np.testing.assert_allclose(f.ratio, 0.5 * (f.supply_ratio_inner + f.supply_ratio_outer),
                               rtol=1e-3)


def test_305_pair_torque_rises_with_oil_quantity_and_is_flat_when_flooded(lqf):
    """Issue 43 Done-when: on a 305-size pair (6000 rpm, 133 N, the Pennzane of the LQF rig,
    20 C) the torque rises at every step 5 -> 20 -> 50 -> 100 -> 130 mg, by more than the load
    term at 5 mg (the old `starved` law moved 0.1 % here), and beyond the charge of the rig it
    is flat: 130 mg against 100x that within 0.5 % (relative to the flooded torque)."""
    q = [5.0, 20.0, 50.0, 100.0, 130.0, 13000.0]
    M = np.array([fv.case_torque_Nmm(lqf, "minimal_oil", 133.0, 6000.0, 20.0, m)[0][0]
                  for m in q])
    P = fv.case_torque_Nmm(lqf, "palmgren", 133.0, 6000.0, 20.0)[0][0]
    assert np.all(np.diff(M[:5]) > 0), M
    assert M[4] - M[0] > 0.3 * P
    assert abs(M[4] - M[5]) < 5e-3 * M[5]
    np.testing.assert_allclose(M[5], P, rtol=1e-3)     # flooded: Palmgren's


def test_lqf_rig_drag_over_palmgren_rises_with_mean_temperature_and_load(lqf):
    """Issue 43 Done-when, the LQF rig (Takeuchi et al., 44th AMS 2018): drag over Palmgren's
    (n nu)^(2/3) dm^3 (their lubricant quantity factor) at 100 mg, 6000 rpm, rises with the mean
    temperature over 12..35 C at every load 89..222 N, and with the load, as published; Palmgren's
    own ratio is the constant f0 (the reference: closed form, to 1e-12)."""
    T = np.array([12.0, 20.0, 28.0, 35.0])
    nu = get_lubricant(lqf.lubricant).nu_mm2_s(T)
    M0 = fv.palmgren_viscous_torque_Nmm(1.0, nu, 6000.0, lqf.g.dm_mm)
    for P in (89.0, 133.0, 222.0):
        _, V = fv.case_torque_Nmm(lqf, "minimal_oil", np.full(4, P), 6000.0, T)
        assert np.all(np.diff(V / M0) > 0), (P, V / M0)
        _, V0 = fv.case_torque_Nmm(lqf, "palmgren", np.full(4, P), 6000.0, T)
        np.testing.assert_allclose(V0 / M0, fv.F0_EXTERNAL, rtol=1e-12)
    _, V = fv.case_torque_Nmm(lqf, "minimal_oil", np.array([89.0, 133.0, 178.0, 222.0]), 6000.0,
                              20.0)
    assert np.all(np.diff(V) > 0)


def test_lost_preload_keeps_the_minimal_oil_loss(lqf):
    """A ball that lost its preload still rolls through the oil: at zero axial load the factor
    is that of the centrifugal load (between 0 and 1, finite), not the flooded 1 of `starved`."""
    f, _, _ = _factor(lqf, 5.0, P=0.0)
    assert 0.0 < float(f.ratio[0]) < 1.0


def test_interval_factors_are_the_normal_predictive_interval():
    """Closed form: e = (0.1, 0.3, -0.2): mean 0.0667, sd 0.2517, half = 1.6449 sd sqrt(4/3);
    fewer than two residuals state no interval."""
    e = np.array([0.1, 0.3, -0.2])
    half = 1.6448536269514722 * np.std(e, ddof=1) * np.sqrt(1 + 1 / 3)
    np.testing.assert_allclose(iv.interval_factors(e), np.exp([e.mean() - half, e.mean() + half]),
                               rtol=1e-12)
    assert np.isnan(iv.interval_factors([0.2])).all()
    assert iv.regime_of("solid_film") == "solid_film"
    assert iv.regime_of("oil", "oil_jet") == "oil_bath_jet"
    assert iv.regime_of("oil") == "minimal_oil"


# ------------------------------------------------------------------ the matrix, row by row
@pytest.fixture(scope="module")
def external():
    return fv.external_rows()


def _external_params():
    """(source, quantity, law) of the external rows, with the law-and-row pairs whose
    prediction lies outside the source's scatter marked xfail (not strict: a better law passes)."""
    misses = {("JPL2022", "*"): "every law is below the JPL torques (at rest 0.14-0.17 against "
                                "0.92 mN m; at 0.075 rpm 0.14-0.26 against 0.64): a boundary "
                                "torque no law carries (report, slow points)",
              ("OCI2018", "starting"): "Palmgren's f1 slope +55 %, SKF's M_sl +150 %",
              ("OCI2018", "running"): "the laws miss the cartridge's running torque by 20-60 %",
              ("OCI2018", "360"): "at 360 rpm Palmgren's f0 = 2 is 5.6x high (the paper's own "
                                  "design estimate takes LQF 0.3), SKF 2.8x, EHL +72 % (+52 % without its spin sliding)",
              ("LQF2018", "palmgren"): "Palmgren's LQF is a constant",
              ("LQF2018", "starved"): "the old starved law is flooded at 100 mg",
              ("LQF2018", "skf2004"): None}
    out = []
    for p in fv.published_points():
        if p["source"] not in ("JPL2022", "OCI2018", "LQF2018"):
            continue
        for law in fv.LAWS:
            reason = (misses.get((p["source"], "*"))
                      or ("360 rpm" in p["quantity"] and misses.get((p["source"], "360")))
                      or misses.get((p["source"], p["quantity"].split()[0]))
                      or misses.get((p["source"], law)))
            if p["source"] == "LQF2018" and law == "ehl_rolling" and "35 C" in p["quantity"]:
                reason = None
            if "hybrid" in p["quantity"] and law in ("palmgren", "skf2004", "starved"):
                reason = "the law sees neither the ball material nor (flooded) the charge"
            marks = [pytest.mark.xfail(reason=reason, strict=False)] if reason else []
            out.append(pytest.param(p["source"], p["quantity"], law, marks=marks,
                                    id=f"{p['source']}-{p['quantity'][:24]}-{law}"))
    return out


@pytest.mark.parametrize("source,quantity,law", _external_params())
def test_published_point_within_its_scatter(external, source, quantity, law):
    """Each published number against each law, tolerance the source's scatter (the CSV's
    rel_scatter: JPL < 10 % of 6 repeats, OCI 10 % / 20 % hash width); trend rows: the law's
    ratio must rise (> 1)."""
    r = next(r for r in external if (r.source, r.quantity, r.law) == (source, quantity, law))
    if r.kind == "trend":
        assert r.predicted > 1.0 + fv.TREND_TOL, r.predicted
    else:
        assert abs(r.error_rel) <= r.rel_scatter, (r.predicted, r.measured)


@pytest.fixture(scope="module")
def seed001_fits():
    return fv.seed001_minimal_oil_fit(mesh_factor=2.0)


@pytest.mark.slow
def test_seed001_minimal_oil_fitted_on_the_cold_ratio_predicts_the_hot_one(seed001_fits):
    """Issue 43 Done-when (positive branch): the minimal-oil law, its one parameter (the oil on
    the inlets) fitted on the cold ratio alone, predicts the held-out hot ratio within 5.9 % of
    the published 0.75 (the relative half-width of the published cold band), and its 90 %
    interval contains it, on the first root. The fit has a second root (the cold ratio has a
    minimum in the oil quantity) that predicts outside: the cold ratio alone does not identify
    the law's parameter (the report says so)."""
    from studies.validation import published_as_data as pad
    assert len(seed001_fits) == 2
    m, cold, hot, (lo, hi) = seed001_fits[0]
    np.testing.assert_allclose(cold, np.sqrt(np.prod(pad.SEED001_COLD_BAND)), rtol=1e-8)
    assert abs(hot - pad.SEED001_HOT) <= pad.SEED001_REL_TOL * pad.SEED001_HOT
    assert lo <= pad.SEED001_HOT <= hi
    m2, _, hot2, _ = seed001_fits[1]
    assert m2 > m and abs(hot2 - pad.SEED001_HOT) > pad.SEED001_REL_TOL * pad.SEED001_HOT
    # the same law through the pipeline (`[lubrication] viscous_model = "minimal_oil"`,
    # simulate's route) at the fitted quantity gives the same two ratios (1e-9)
    from studies.model.config import load_shipped
    asm = pad.seed001_with(load_shipped("seed001"), viscous_model="minimal_oil",
                           oil_quantity_mg=m)
    M = pad.seed001_torque_Nmm(asm, mesh_factor=2.0)
    np.testing.assert_allclose([M[0] / M[1], M[2] / M[1]], [cold, hot], rtol=1e-9)


def test_simulate_interval_columns_are_the_shipped_residuals_interval():
    """simulate's torque_lo/hi and heat_lo/hi (seed 001, oil without a method: minimal-oil
    regime, Palmgren's law) are the torque and heat times the normal predictive factors of the
    shipped residuals of (minimal_oil, palmgren), recomputed here by hand from the CSV with the
    standard normal quantile 1.6448536 (rtol 1e-9); a solid film (seed 000) has no interval
    stated (NaN: seed 000's changes give no residual)."""
    import csv
    from studies.model.columns import to_columns
    from studies.model.config import load_shipped
    from studies.model.pipeline import Pipeline, table_inputs
    with open(iv.RESIDUALS_CSV) as fh:
        e = np.array([float(r["log_residual"]) for r in csv.DictReader(
            x for x in fh if not x.startswith("#"))
            if r["regime"] == "minimal_oil" and r["law"] == "palmgren"])
    half = 1.6448536269514722 * np.std(e, ddof=1) * np.sqrt(1 + 1 / e.size)
    cond = {"T_ambient_C": np.array([20.0, 40.0]), "speed_rpm": np.array([3500.0, 6000.0])}
    asm = load_shipped("seed001")
    c = to_columns(Pipeline.shared(asm, mesh_factor=4.0).run(table_inputs(asm, cond)),
                   friction_split=True)
    np.testing.assert_allclose(c["torque_lo_Nmm"], c["torque_Nmm"] * np.exp(e.mean() - half),
                               rtol=1e-9)
    np.testing.assert_allclose(c["heat_hi_W"], c["heat_W"] * np.exp(e.mean() + half), rtol=1e-9)
    s0 = load_shipped("seed000")
    c0 = to_columns(Pipeline.shared(s0, mesh_factor=4.0).run(
        table_inputs(s0, {"T_ambient_C": np.array([20.0])})), friction_split=True)
    assert np.isnan(c0["torque_lo_Nmm"]).all()


@pytest.mark.slow
def test_shipped_residuals_are_the_study_s():
    """analytic/data/friction_residuals.csv is what the study computes (here on a coarser mesh:
    the seed 001 ratios move by < 1e-4 relative with the mesh; the external rows do not use
    the FE), to 1e-3 in the log."""
    import csv
    rows, _ = fv.matrix(mesh_factor=2.0)
    got = {(r["regime"], r["law"], r["source"], r["quantity"]): r["log_residual"] for r in rows
           if r["kind"] == "value" and np.isfinite(r["log_residual"])}
    with open(iv.RESIDUALS_CSV) as fh:
        shipped = {(r["regime"], r["law"], r["source"], r["quantity"]): float(r["log_residual"])
                   for r in csv.DictReader(x for x in fh if not x.startswith("#"))}
    assert set(got) == set(shipped)
    for k, v in shipped.items():
        assert abs(got[k] - v) < 1e-3, k


def test_minimal_oil_every_ball_summed_is_z_times_the_representative_ball():
    """`bearing` takes the law over every ball's own contacts, simulate's pair route a
    representative ball: on the same state under a pure axial load (every ball alike) the
    minimal-oil torque is the same both ways (1e-12 relative), and below Palmgren's with 5 mg
    (the factor < 1) while the same law with an unlimited charge is Palmgren's exactly."""
    from analytic.friction.options import FrictionOptions
    from analytic.friction.pair import bearing_friction
    from bearing_reference import seed001_axial_contacts

    asm, g, speed, every, one, oil, nu = seed001_axial_contacts()
    out = {}
    for law, m in (("minimal_oil", 5.0), ("minimal_oil", np.inf), ("palmgren", 0.0)):
        fr = FrictionOptions(viscous_model=law, oil_quantity_mg=m,
                             eta_Pa_s=dynamic_viscosity_Pa_s(nu, oil.density_kg_m3),
                             alpha_per_Pa=oil.alpha_per_Pa, density_kg_m3=oil.density_kg_m3)
        args = dict(model="oil", mu=0.0029, speed_rpm=speed, f0=1.7, nu_mm2_s=nu, friction=fr)
        a, b = bearing_friction(g, every, **args), bearing_friction(g, one, **args)
        np.testing.assert_allclose(a.total_Nmm, b.total_Nmm, rtol=1e-12)
        out[(law, m)] = a.total_Nmm
    np.testing.assert_allclose(out[("minimal_oil", np.inf)], out[("palmgren", 0.0)], rtol=1e-12)
    assert np.all(out[("minimal_oil", 5.0)] < out[("palmgren", 0.0)])


def test_minimal_oil_needs_a_charge_and_its_key_is_refused_elsewhere(tmp_path):
    """Config: viscous_model = "minimal_oil" without oil_quantity_mg is refused in one line
    naming the key; with it, accepted; oil_quantity_mg with palmgren still refused."""
    import tomllib
    from studies.model.config import CONFIG_DIR, SHIPPED, ConfigError, assembly_from_dict
    raw = tomllib.loads((CONFIG_DIR / SHIPPED["seed001"]).read_text())
    raw["lubrication"]["viscous_model"] = "minimal_oil"
    with pytest.raises(ConfigError, match=r"^x\.toml: lubrication\.viscous_model: .*oil_quantity_mg"):
        assembly_from_dict(raw, "x.toml")
    raw["lubrication"]["oil_quantity_mg"] = 20.0
    assert assembly_from_dict(raw, "x.toml").lubrication.viscous_model == "minimal_oil"
    raw["lubrication"]["viscous_model"] = "palmgren"
    with pytest.raises(ConfigError, match=r"^x\.toml: lubrication\.oil_quantity_mg: "):
        assembly_from_dict(raw, "x.toml")


def test_interval_factors_meet_the_diagnosis_predictive_interval():
    """Where the two interval routes meet they agree: the friction interval of n log residuals
    is the diagnosis's predictive interval (`studies.diagnosis.interval.predictive_interval`)
    of their mean as a one-parameter fit (Jacobian 1, parameter variance sd^2 / n) with the
    residuals' spread as its discrepancy, exponentiated (1e-12)."""
    from studies.diagnosis.interval import predictive_interval
    e = np.array([0.4, -0.1, 0.25, -0.6, 0.05])
    sd = np.std(e, ddof=1)
    p = predictive_interval([e.mean()], [[1.0]], [[sd ** 2 / e.size]], 0.0, sd, iv.LEVEL)
    np.testing.assert_allclose(iv.interval_factors(e), np.exp([p.lo[0], p.hi[0]]), rtol=1e-12)


def test_permissible_speed_at_the_interval_s_upper_end_closes_the_heat_balance():
    """DIN 732 at the upper end of the friction interval: at the speed n_hi the friction
    heat k_hi (M0(nu_perm, n_hi) + M1) omega equals the dissipated heat Q of the nominal balance
    (each term recomputed here from Palmgren's closed forms, 1e-6 relative), and n_hi < n
    (more friction, a lower permissible speed)."""
    from analytic.bearing import BearingGeometry
    from analytic.friction.palmgren import (palmgren_f1_angular_contact,
                                            palmgren_load_torque_Nmm,
                                            palmgren_viscous_torque_Nmm)
    from analytic.safety import static_load_rating_C0_N
    from analytic.thermal_speed import (dissipated_heat_W, reference_heat_transfer_W_per_mm2_K)
    from analytic.torque import power_W
    from studies.model.config import load_shipped
    from studies.usecases.bearing_single import thermal_speeds
    asm = load_shipped("seed001")
    g = BearingGeometry.from_spec(asm.bearing, asm.materials)
    lub, oil = asm.lubrication, asm.oil()
    Fa = np.array([7.0, 50.0])
    ts = thermal_speeds(asm.bearing, g, lub, oil, Fa, np.array([6000.0, 6000.0]))
    k_hi = iv.lubrication_interval(lub).factor_hi
    assert np.isfinite(k_hi) and k_hi > 1
    n_hi = ts.permissible_speed_hi_rpm
    assert np.all(n_hi < ts.permissible_speed_rpm)
    C0 = static_load_rating_C0_N(g.Z, g.Dw_mm, g.dm_mm, g.alpha0_deg)
    M1 = palmgren_load_torque_Nmm(palmgren_f1_angular_contact(Fa, C0), Fa, g.dm_mm)
    nu = oil.nu_mm2_s(lub.permissible_temperature_C)
    k_q = lub.heat_transfer_W_per_mm2_K or reference_heat_transfer_W_per_mm2_K(
        ts.reference.surface_mm2)
    Q = dissipated_heat_W(k_q, ts.reference.surface_mm2, lub.permissible_temperature_C,
                          lub.ambient_temperature_C)
    heat = k_hi * power_W(palmgren_viscous_torque_Nmm(lub.viscous_factor_f0, nu, n_hi, g.dm_mm)
                          + M1, n_hi)
    np.testing.assert_allclose(heat, Q, rtol=1e-6)


def test_minimal_oil_notes_rows_below_its_source_range(lqf):
    """0.01 mg on the 305 bearing (supply ratio ~1e-3, below Chevalier et al.'s 0.01) is noted
    as outside the law's range, row by row; 130 mg (r ~ 7) is not."""
    from analytic.friction.options import FrictionOptions
    from analytic.friction.pair import bearing_friction, pair_bearing_contacts
    lub = get_lubricant(lqf.lubricant)
    pair = solve_pair(lqf.g, "DB", preload_kind="spring", preload_assembled_N=np.array([133.0]))
    eta = dynamic_viscosity_Pa_s(lub.nu_mm2_s(np.array([20.0])), lub.density_kg_m3)
    outside = []
    for m in (0.01, 130.0):
        fr = FrictionOptions(viscous_model="minimal_oil", oil_quantity_mg=m, eta_Pa_s=eta,
                             alpha_per_Pa=lub.alpha_per_Pa, density_kg_m3=lub.density_kg_m3)
        b = bearing_friction(lqf.g, pair_bearing_contacts(pair, 0), model="oil", mu=0.0,
                             speed_rpm=np.array([6000.0]), f0=2.0,
                             nu_mm2_s=lub.nu_mm2_s(np.array([20.0])), friction=fr)
        (r,) = b.ranges
        outside.append(bool(r.outside[0]))
    assert outside == [True, False]


# ------------------------------------------- starting torque, slow points, LOSO coverage target
def test_skf_starting_torque_is_the_sliding_moment_at_rest():
    """SKF's M_start = M_sl: by hand S1 dm^0.26 S2 F_a^(4/3) mu_bl (pure axial load, no F_g at
    rest) with the single-row constants, and the limit of the running model's sliding moment
    as n -> 0+ (1e-9 rpm: phi_bl = 1 to 1e-20), both to 1e-9."""
    from analytic.friction import skf2004 as skf
    d, D, Fa = 40.0, 68.0, np.array([44.5, 445.0])
    c = skf.SKF_SINGLE_ROW
    by_hand = c.S1 * (0.5 * (d + D)) ** 0.26 * c.S2 * Fa ** (4.0 / 3.0) * 0.15
    np.testing.assert_allclose(skf.skf2004_starting_torque_Nmm(d, D, 0.0, Fa), by_hand,
                               rtol=1e-9)
    run = skf.skf2004_torque(d, D, 0.0, Fa, 1e-9, 100.0)
    np.testing.assert_allclose(run.sliding_Nmm, by_hand, rtol=1e-9)


def test_coulomb_contact_estimate_brackets_the_oci_papers_own_codes():
    """Second method: OCI2018 Table 5 prints the load torque of its pair at mu = 0.08 and 60 lb
    preload from two independent codes (BRGS10 6.9, ORBIS 6.8 mN m). The project's Coulomb
    contact estimate (Heathcote slip + spin) at mu = 0.08 over the geometry the paper leaves
    open (raceway curvature 0.52/0.53 or 0.56/0.56, contact angle 15 or 25 deg) brackets both
    (the tolerance: that geometry's spread, 5.9..12.7 mN m)."""
    pts = [p for p in fv.slow_point_rows()
           if p.source == "OCI2018" and p.quantity.startswith("running")]
    M = np.array([p.predicted * fv.OCI_TABLE5_MU / p.mu_ref for p in pts])
    assert len(M) == 4
    assert M.min() <= min(fv.OCI_TABLE5_LOAD_TORQUE_mNm), M
    assert max(fv.OCI_TABLE5_LOAD_TORQUE_mNm) <= M.max(), M


def _slow_params():
    reasons = {"JPL2022": "the Coulomb estimate at the PFPE four-ball mu 0.11 gives 0.19-0.24 "
                          "mN m; the JPL torques need mu 0.30-0.53 (report)",
               "OCI2018": "the OCI slope needs mu 0.031-0.067 and SN006 0.071-0.15 against "
                          "0.11 (report)"}
    return [pytest.param(src, q, marks=pytest.mark.xfail(reason=reasons[src], strict=False),
                         id=f"{src}-{q}") for src, q in (("JPL2022", "starting"),
                                                         ("JPL2022", "running"),
                                                         ("OCI2018", "starting"),
                                                         ("OCI2018", "running"))]


@pytest.mark.parametrize("source,start", _slow_params())
def test_slow_point_within_its_scatter_at_the_published_boundary_coefficient(source, start):
    """The boundary-regime points against the Coulomb contact estimate at the published PFPE
    vacuum four-ball coefficient (GXL320A, 0.11) with the case's own inputs (curvature
    0.52/0.53, 15 deg): within the source's scatter (the CSV's rel_scatter)."""
    p = next(p for p in fv.slow_point_rows() if p.source == source
             and p.quantity.startswith(start))
    scatter = float(fv._point(source, start)["rel_scatter"])
    assert abs(p.predicted / p.measured - 1.0) <= scatter, (p.predicted, p.measured)


def test_loso_coverage_counts_against_the_other_sources_interval():
    """Closed form: sources A (0.0), B (0.1), C (0.5, 0.6). C against A + B: mean 0.05, sd
    0.0707, half 1.645 sd sqrt(3/2) = 0.142: both C rows outside; A against B + C: mean 0.4,
    half 0.503: inside; B against A + C: mean 0.367, half 0.611: inside. 2 of 4 judged."""
    res = [("r", "l", "A", 0.0), ("r", "l", "B", 0.1), ("r", "l", "C", 0.5),
           ("r", "l", "C", 0.6), ("r", "l", "D", float("nan"))]
    c = iv.loso_coverage(res)[("r", "l")]
    assert (c.inside, c.judged) == (2, 4)
    e = np.array([0.0, 0.1])
    half = 1.6448536269514722 * np.std(e, ddof=1) * np.sqrt(1.5)
    assert sum(np.isclose(w, np.exp(2 * half), rtol=1e-12) for w in c.width_ratios) == 2


def test_narrowest_loso_ratio_is_the_spread_with_the_other_sources():
    """Closed form: sources A (0.0), B (0.1), C (0.5, 0.6): C's rows need exp(0.5 - 0.0) and
    exp(0.6 - 0.0); A's exp(0.6 - 0.0); B's likewise; D (NaN) is not judged; a source whose
    others give one residual is not judged."""
    res = [("r", "l", "A", "a", 0.0), ("r", "l", "B", "b", 0.1), ("r", "l", "C", "c1", 0.5),
           ("r", "l", "C", "c2", 0.6), ("r", "l", "D", "d", float("nan")),
           ("s", "l", "A", "a", 0.0), ("s", "l", "B", "b", 5.0)]
    need = iv.narrowest_loso_ratio(res)
    np.testing.assert_allclose([need[("r", "l", "C", "c1")], need[("r", "l", "C", "c2")],
                                need[("r", "l", "A", "a")], need[("r", "l", "B", "b")]],
                               np.exp([0.5, 0.6, 0.6, 0.6]), rtol=1e-12)
    assert ("r", "l", "D", "d") not in need and not any(k[0] == "s" for k in need)


def test_no_interval_from_the_held_sources_reaches_coverage_and_width():
    """Issue 43 Done-when, negative branch with its proof: leaving one source out, no interval
    from the other sources can hold the held-out points at the stated rate with upper / lower
    <= 3. Premise: a 90 % interval estimated from fewer than 10 residuals holds all of them
    (checked here for the study's own rule, `interval_factors`, on every judged (regime, law,
    source): lo <= every residual of the others <= hi). Then an interval that holds a held-out
    residual too spans at least exp(max - min) of the two (`narrowest_loso_ratio`), and for every
    published point under EVERY law (the law chosen per point with hindsight) that exceeds 3, so
    fewer than 90 % (none) of the points can be inside an interval that says something; and
    every interval of upper / lower <= 3 misses its point, so with the median <= 3 at least half
    miss: coverage <= 50 %. Reason:
    the sources' log errors differ by more than ln 3 from source to source (JPL2022 +0.9 .. +1.9
    for every law, OCI2018 -1.7 .. -0.2; the report's table)."""
    res = iv.shipped_residual_rows()
    for reg, law, src, q, e in res:
        others = [r[4] for r in res if (r[0], r[1]) == (reg, law) and r[2] != src]
        if len(others) < iv.MIN_RESIDUALS:
            continue
        assert len(others) < 10
        lo, hi = iv.interval_factors(others)
        assert np.log(lo) <= min(others) and max(others) <= np.log(hi), (law, src)
    need = iv.narrowest_loso_ratio(res)
    best = {}
    for (reg, law, src, q), w in need.items():
        best[(src, q)] = min(best.get((src, q), np.inf), w)
    assert len(best) == 7
    narrow = sum(w <= fv.WIDTH_TARGET for w in best.values())
    assert narrow < iv.LEVEL * len(best), best
    # and what the shipped coverage measures is consistent with the bound: every point that is
    # inside its LOSO interval is inside one wider than 3
    for c in iv.shipped_coverage().values():
        assert sum(w > fv.WIDTH_TARGET for w in c.width_ratios) >= c.inside


def test_a_boundary_shear_law_cannot_bring_jpl_and_oci_together():
    """The slow and starting points are the only boundary-regime points held (JPL2022, OCI2018).
    A boundary shear strength tau = tau0 + alpha p over each contact's Hertz area (Coulomb at
    tau0 = 0, Briscoe-Tabor's constant shear at alpha = 0) does not reconcile them: for every
    tau0 / alpha and every pairing of the geometry variants, the narrowest interval holding all
    four points' log residuals has upper / lower > 3. Why (second check): the contacts' mean Hertz
    pressures Q / (pi a b) are alike (JPL's lies inside OCI's range over its slope), so an area
    law scales both sources alike. The torque is linear in (tau0, alpha): at (2 MPa, 0.05) it is
    0.05 C + 2 S of the unit torques (1e-9)."""
    spans = fv.boundary_law_spans()
    assert len(spans) == 8
    assert min(np.exp(sp) for *_, sp, _ in spans) > fv.WIDTH_TARGET
    pr = fv.boundary_pressures_MPa()
    assert pr["OCI2018"][0] <= pr["JPL2022"][0] <= pr["JPL2022"][1] <= pr["OCI2018"][1]
    c = fv.cases()
    gj, go = c["JPL2022"].g, c["OCI2018"].g
    C = fv._boundary_unit_torques(gj, go, 1.0, 0.0)
    S = fv._boundary_unit_torques(gj, go, 0.0, 1.0)
    np.testing.assert_allclose(fv._boundary_unit_torques(gj, go, 0.05, 2.0), 0.05 * C + 2.0 * S,
                               rtol=1e-9)


@pytest.mark.parametrize("regime", ["solid_film", "oil_bath_jet"])
def test_regimes_without_published_points_state_no_interval(regime):
    """No published value row of a solid film has a residual (seed 000's cycle changes are
    predicted 0) and no oil bath or jet point is held: those regimes state no interval (NaN
    factors), rather than one borrowed from another regime."""
    law = "solid_film" if regime == "solid_film" else "palmgren"
    i = iv.model_form_interval(regime, law)
    assert not i.stated and i.n_residuals == 0
    assert not any(reg == regime for reg, *_ in iv.shipped_residual_rows())


def test_matrix_in_interval_column_agrees_with_loso_coverage(external):
    """The CSV's per-row `in_interval` (the study's `with_intervals`) and the coverage table
    (`interval.loso_coverage`) count the same rows inside, law by law, on the external rows."""
    rows = fv.with_intervals(external)
    cov = fv.coverage(rows)
    for (reg, law), c in cov.items():
        mine = [r for r in rows if (r["regime"], r["law"]) == (reg, law) and r["kind"] == "value"
                and np.isfinite(r["log_residual"]) and r["in_interval"] != ""]
        assert (sum(bool(r["in_interval"]) for r in mine), len(mine)) == (c.inside, c.judged)


def test_bearing_sidecar_states_the_interval_level_and_its_measured_coverage(tmp_path):
    """`bearing`'s OUT.csv.json names what its interval columns are: level 0.9, regime and law,
    factors equal to the written columns' torque_hi / torque and torque_lo / torque (rtol 1e-9:
    the CSV's printed digits),
    and the leave-one-source-out coverage of that (regime, law) recounted here by hand from the
    shipped residuals CSV (each residual against mean +- 1.6448536 sd sqrt(1 + 1/n) of the other
    sources' residuals); and the report's interval line carries the same numbers."""
    import csv
    import json
    import re

    import pandas as pd

    from studies.app.cli import main
    from studies.model.config import CONFIG_DIR, SHIPPED
    text = (CONFIG_DIR / SHIPPED["seed001"]).read_text()
    part = {n: re.search(rf"^\[{n}\][^\n]*\n(.*?)(?=^\[|\Z)", text, re.S | re.M).group(0)
            for n in ("bearing", "lubrication")}
    b = tmp_path / "b.toml"
    b.write_text(part["bearing"] + part["lubrication"])
    loads = tmp_path / "loads.csv"
    loads.write_text("axial_load_N,speed_rpm,T_oil_C\n50,6000,20\n")
    out = tmp_path / "o.csv"
    assert main(["bearing", str(b), str(loads), "-o", str(out)]) == 0
    rec = json.loads((tmp_path / "o.csv.json").read_text())["friction_interval"]
    o = pd.read_csv(out)
    assert (rec["level"], rec["regime"], rec["law"]) == (0.9, "minimal_oil", "palmgren")
    np.testing.assert_allclose([rec["factor_lo"], rec["factor_hi"]],
                               [o.torque_lo_Nmm[0] / o.torque_Nmm[0],
                                o.torque_hi_Nmm[0] / o.torque_Nmm[0]], rtol=1e-9)
    with open(iv.RESIDUALS_CSV) as fh:
        rows = [(r["source"], float(r["log_residual"])) for r in csv.DictReader(
            x for x in fh if not x.startswith("#"))
            if r["regime"] == "minimal_oil" and r["law"] == "palmgren"]
    inside = judged = 0
    for src, e in rows:
        others = np.array([x for s, x in rows if s != src])
        if others.size < 2:
            continue
        half = 1.6448536269514722 * np.std(others, ddof=1) * np.sqrt(1 + 1 / others.size)
        judged += 1
        inside += int(abs(e - others.mean()) <= half)
    assert (rec["loso_inside"], rec["loso_judged"]) == (inside, judged)
    line = iv.interval_text(iv.model_form_interval("minimal_oil", "palmgren"))
    assert f"left one source out {inside} of {judged}" in line and "90% nominal" in line
    from studies.model.config import load_shipped
    from studies.usecases.report_margins import _torque_interval_text
    text = _torque_interval_text(load_shipped("seed001"), 40.0, 1000.0, np.array([20.0, 800.0]))
    assert (f"heat {20.0 * rec['factor_lo']:.4g} .. {800.0 * rec['factor_hi']:.4g} W" in text
            and line in text)


def test_slow_points_flooded_film_follows_hamrock_dowson_speed_exponent():
    """The slow points' flooded films (`boundary_films_nm`): OCI's cartridge at 2 rpm over 0.5
    rpm is (2 / 0.5)^0.67 (Hamrock-Dowson's speed exponent, the ball loads unchanged at these
    speeds) to 1e-3; every film is below 10 nm, the report's boundary-regime premise."""
    films = fv.boundary_films_nm()
    lo, hi = films["OCI2018"]
    assert hi / lo == pytest.approx(4.0 ** 0.67, rel=1e-3)
    assert max(max(v) for v in films.values()) < 10.0


def test_report_sentences_follow_their_tables():
    """The LQF and regime sentences of the study's report are computed from their tables: a
    share table whose k = 1 supply ratio is below 1 says the contacts starve, one above says
    flooded; the largest LQF rise and its share are the table's; a coverage in which every
    regime has judged points says so."""
    f = np.array([0.9, 0.95, 0.99])
    flooded = [(1.0, f, 1.1, (5.6, 13.6)), (0.1, f, 1.76, (0.56, 1.36))]
    starved = [(1.0, f, 1.3, (0.5, 0.9)), (0.1, f, 2.2, (0.05, 0.09))]
    assert "flooded" in fv.lqf_share_text(flooded) and "x1.760 (k = 0.1" in fv.lqf_share_text(flooded)
    assert "starve" in fv.lqf_share_text(starved) and "x2.200 (k = 0.1" in fv.lqf_share_text(starved)
    cov = {(reg, "palmgren"): iv.Coverage(reg, "palmgren", 2, 3, (2.0, 4.0)) for reg in iv.REGIMES}
    assert fv.no_interval_text(cov).startswith("Every regime")
    del cov[("oil_bath_jet", "palmgren")]
    assert "(oil_bath_jet)" in fv.no_interval_text(cov)


def test_film_split_counts_the_two_parts_of_the_matrix():
    """`film_split_coverage` on a hand-made matrix: two boundary sources whose residuals sit at
    +1 and -1 (each judged against the other's interval alone: outside) and a running part of
    one source (no interval judged): 0 / 4 and 0 / 0, two and one sources."""
    def row(src, q, e):
        return dict(kind="value", regime="minimal_oil", law="palmgren", source=src, quantity=q,
                    log_residual=e)
    rows = [row("JPL2022", "starting x", 1.0), row("JPL2022", "running x", 1.1),
            row("OCI2018", "starting x", -1.0), row("OCI2018", "running torque cartridge", -1.1),
            row("OCI2018", "running torque at 360 rpm", 0.3)]
    split = fv.film_split_coverage(rows)
    assert split["boundary"][:2] == (0, 4) and split["boundary"][3] == 2
    assert split["running"][:2] == (0, 0) and split["running"][3] == 1
