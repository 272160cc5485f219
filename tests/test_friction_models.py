"""analytic/friction/: each friction model against its source's closed form, its limits, and
the law it reduces to. Requirement names in each docstring."""
import numpy as np
import pytest
from scipy import integrate

from analytic.bearing import BearingGeometry, solve_pair
from analytic.friction import ehl_rolling, skf2004, solid_film, starved
from analytic.friction.options import FrictionOptions
from analytic.friction.pair import ehl_rolling_pair
from analytic.friction.palmgren import palmgren_viscous_torque_Nmm
from analytic.lubrication import reduced_modulus_MPa
from analytic.torque import power_W

G = BearingGeometry.from_catalogue("25TAC62B")
EPS = np.finfo(float).eps


# ----------------------------------------------------------------------------- SKF 2004
def test_skf_factors_are_one_in_their_limits():
    """SKF: phi_ish -> 1 at rest, phi_rs = 1 with K_rs = 0 or at rest, phi_bl = 1 at rest (the
    sliding coefficient is then the boundary one) and -> 0 at speed (mu_EHL)."""
    assert skf2004.inlet_shear_factor(0.0, 40.0, 68.0) == 1.0
    assert skf2004.replenishment_factor(5000.0, 68.0, 25.0, 62.0, K_rs=0.0) == 1.0
    assert skf2004.replenishment_factor(0.0, 68.0, 25.0, 62.0) == 1.0
    assert skf2004.sliding_coefficient(0.0, 68.0, 40.0) == skf2004.MU_BL
    assert skf2004.sliding_coefficient(2e4, 68.0, 40.0) == pytest.approx(skf2004.MU_EHL["mineral"],
                                                                        rel=1e-12)


def test_skf_inlet_shear_factor_closed_form():
    """phi_ish at n dm = 1e5, nu = 10: 1 / (1 + 1.84e-9 10^6.4 10^0.64) by hand (powers of ten
    exactly), the catalogue's constants."""
    expected = 1.0 / (1.0 + 1.84e-9 * 10 ** 6.4 * 10 ** 0.64)
    got = skf2004.inlet_shear_factor(2500.0, 40.0, 10.0)
    assert got == pytest.approx(expected, rel=4 * EPS)
    assert 0.97 < got < 0.99                      # a 2 % reduction at this modest speed


def test_skf_rolling_term_exponents():
    """M_rr / (phi_ish phi_rs) = G_rr (nu n)^0.6 (SKF): at fixed n the ratio over a 4x viscosity
    step is 4^0.6; G_rr grows as F_a^0.54 under pure axial load at rest-level F_g."""
    t1 = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, 1000.0, 20.0)
    t2 = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, 1000.0, 80.0)
    r = (t2.rolling_Nmm / (t2.phi_ish * t2.phi_rs)) / (t1.rolling_Nmm / (t1.phi_ish * t1.phi_rs))
    assert r == pytest.approx(4.0 ** 0.6, rel=1e-12)
    g1 = skf2004.rolling_variable(skf2004.SKF_SINGLE_ROW, 43.5, 0.0, 1000.0)
    g2 = skf2004.rolling_variable(skf2004.SKF_SINGLE_ROW, 43.5, 0.0, 8000.0)
    assert g2 / g1 == pytest.approx(8.0 ** 0.54, rel=1e-12)


def test_skf_low_speed_slope_is_0_6():
    """In the limit n -> 0 (phi_ish, phi_rs -> 1, F_g -> 0) M_rr ~ n^0.6: the log-slope between
    1e-3 and 2e-3 rpm is 0.6 within 1e-6 (1 - phi_rs there is K_rs nu n (d + D)
    sqrt(K_z / (2 (D - d))) = 3e-8 x 50 x 2e-3 x 87 x 0.24 = 3e-8, 1 - phi_ish smaller)."""
    n = np.array([1e-3, 2e-3])
    t = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, n, 50.0)
    slope = np.log(t.rolling_Nmm[1] / t.rolling_Nmm[0]) / np.log(2.0)
    assert slope == pytest.approx(0.6, abs=1e-6)


def test_skf_drag_zero_without_bath_and_at_rest():
    """M_drag = 0 without an oil bath (oil level 0); every component 0 at n = 0 (a running
    torque)."""
    t = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, np.array([0.0, 3000.0]), 50.0)
    assert np.all(t.drag_Nmm == 0.0)
    assert t.total_Nmm[0] == 0.0 and t.total_Nmm[1] > 0.0


def test_skf_drag_at_the_half_bath_closed_form_and_its_limits():
    """The oil-bath drag (catalogue 17000 form) written out at H = 0.6 dm, where t = pi, f_t = 1
    and R_s = 0.36 dm^2 pi f_A: M = 1.093e-7 n^2 dm^3 (n dm^2 / nu)^-1.379 R_s (to 1e-12
    relative); it rises with the level from 0 at H = 0 (as H^0.81 for a shallow bath, its
    series) and is flat above 1.2 dm (the catalogue's cap); at a fixed level it goes as n^0.621 and nu^1.379 (its exponents)."""
    d, D, n, nu = 25.0, 62.0, 3000.0, 20.0
    dm = 0.5 * (d + D)
    f_A = 0.05 * 4.4 * (D + d) / (D - d)
    R_s = 0.36 * dm ** 2 * np.pi * f_A
    expect = 1.093e-7 * n ** 2 * dm ** 3 * (n * dm ** 2 / nu) ** -1.379 * R_s
    got = skf2004.drag_torque_Nmm(0.6 * dm, d, D, n, nu)
    assert float(got) == pytest.approx(expect, rel=1e-12)
    levels = np.array([0.0, 1e-3, 0.1, 0.3, 0.6, 1.0, 1.2]) * dm
    m = skf2004.drag_torque_Nmm(levels, d, D, n, nu)
    assert m[0] == 0.0 and np.all(np.diff(m) > 0)
    # a shallow bath: t ~ 2 sqrt(2 H / (0.6 dm)), t - sin t ~ t^3/6, f_t ~ t/2, so M ~ t^(3 -
    # 1.379) ~ H^0.8105: it vanishes continuously as the level goes to 0
    low = skf2004.drag_torque_Nmm(np.array([1e-6, 1e-5]) * dm, d, D, n, nu)
    assert np.log(low[1] / low[0]) / np.log(10.0) == pytest.approx(0.5 * (3 - 1.379), rel=1e-4)
    assert float(skf2004.drag_torque_Nmm(2.0 * dm, d, D, n, nu)) == float(m[-1])
    h = 0.3 * dm
    s_n = np.log(skf2004.drag_torque_Nmm(h, d, D, 2 * n, nu) / skf2004.drag_torque_Nmm(h, d, D, n, nu))
    s_nu = np.log(skf2004.drag_torque_Nmm(h, d, D, n, 2 * nu) / skf2004.drag_torque_Nmm(h, d, D, n, nu))
    assert s_n / np.log(2) == pytest.approx(2 - 1.379, abs=1e-12)
    assert s_nu / np.log(2) == pytest.approx(1.379, abs=1e-12)
    t = skf2004.skf2004_torque(d, D, 0.0, 1500.0, n, nu, oil_level_mm=h)
    assert float(t.drag_Nmm) == pytest.approx(float(skf2004.drag_torque_Nmm(h, d, D, n, nu)))


#: a measured boundary friction coefficient of a PFPE-base grease between AISI 52100 balls in
#: vacuum (four-ball, 200 N, 0.029 m/s, initial mean Hertz pressure 3.5 GPa; 4 runs x 4 h): mean
#: 0.11, observed range 0.09..0.23 (Jones et al., "An Additive to Improve the Wear
#: Characteristics of Perfluoropolyether Based Greases", NASA/TM-1999-209064, Table 2, GXL-320A
#: base grease; as transcribed in ../shared/data/boundary_friction_coefficients.csv)
PFPE_BOUNDARY_MU = (0.11, 0.09, 0.23)


def test_skf_sliding_coefficient_at_rest_is_a_measured_boundary_coefficient():
    """Where the film is gone (n -> 0: phi_bl -> 1) SKF's sliding coefficient is its boundary
    coefficient mu_bl = 0.15; a boundary coefficient measured on bearing steel under a space
    lubricant in vacuum (PFPE grease, four-ball: mean 0.11, observed 0.09..0.23) holds it within
    its observed range, and mu_sl tends to it as the speed falls (to 1e-6 at 1e-3 rpm)."""
    _, lo, hi = PFPE_BOUNDARY_MU
    mu0 = float(skf2004.sliding_coefficient(1e-3, 20.0, 40.0))
    assert mu0 == pytest.approx(skf2004.MU_BL, abs=1e-6)
    assert lo <= mu0 <= hi


def test_skf_constants_by_lubrication_method_and_oil_family():
    """K_rs 3e-8 for an oil bath or jet, 6e-8 for oil-air, grease and minimal oil (catalogue's
    two values); mu_EHL 0.05 mineral, 0.04 synthetic. The replenishment factor of grease is the
    oil's squared (the exponent doubles with K_rs) and lowers the rolling term; the full-film
    sliding coefficient of a synthetic oil is 0.04 at speed (phi_bl -> 0)."""
    assert skf2004.constants_for("oil_jet") == {"K_rs": 3e-8, "mu_ehl": 0.05}
    assert skf2004.constants_for("grease", "synthetic") == {"K_rs": 6e-8, "mu_ehl": 0.04}
    for m in ("oil_air", "minimal_oil"):
        assert skf2004.constants_for(m)["K_rs"] == 6e-8
    oil = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, 6000.0, 50.0, **skf2004.constants_for("oil_bath"))
    grease = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, 6000.0, 50.0, **skf2004.constants_for("grease"))
    assert float(grease.phi_rs) == pytest.approx(float(oil.phi_rs) ** 2, rel=1e-12)
    assert grease.rolling_Nmm < oil.rolling_Nmm
    syn = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, 2e4, 68.0, **skf2004.constants_for("oil_jet", "synthetic"))
    assert float(syn.mu_sl) == pytest.approx(0.04, abs=1e-9)
    with pytest.raises(ValueError, match="lubrication_method"):
        skf2004.constants_for("splash")


def test_skf_without_a_bearing_is_one_line_not_a_zero_division():
    """skf2004 without bore and outside diameter (the API's FrictionOptions default 0): a
    ValueError naming them, not a bare ZeroDivisionError."""
    with pytest.raises(ValueError, match="bore_mm and outside_diameter_mm"):
        FrictionOptions(viscous_model="skf2004")
    with pytest.raises(ValueError, match="bore and outside diameter"):
        skf2004.skf2004_torque(0.0, 0.0, 0.0, 100.0, 1000.0, 20.0)


@pytest.mark.parametrize("options, match", [
    (dict(viscous_model="ehl_rolling", eta_Pa_s=0.0, alpha_per_Pa=1e-8), "eta_Pa_s > 0"),
    (dict(viscous_model="ehl_rolling", eta_Pa_s=0.05, alpha_per_Pa=0.0), "alpha_per_Pa > 0"),
    (dict(shear_strength="pressure", tau0_MPa=-5.0), "tau0_MPa >= 0"),
    (dict(lubrication_method="splash"), "lubrication_method"),
    (dict(oil_family="vegetable"), "oil family"),
])
def test_friction_options_refuse_nonsense_in_one_line(options, match):
    """A zero viscosity or pressure-viscosity coefficient for ehl_rolling (it gave a zero
    viscous torque), a negative tau0 (a negative torque), an unknown method or oil family: one
    ValueError line."""
    with pytest.raises(ValueError, match=match) as e:
        FrictionOptions(**options)
    assert "\n" not in str(e.value)


# ----------------------------------------------------------------------------- solid film
def test_pressure_shear_alpha_only_is_constant_law():
    """tau = alpha p: mu = alpha whatever the load and ellipse (Coulomb, the existing law)."""
    mu = solid_film.pressure_dependent_mu(0.0, 0.03, np.array([10.0, 100.0, 1000.0]),
                                          np.array([0.2, 0.4, 0.9]), np.array([0.05, 0.1, 0.2]))
    assert np.all(mu == 0.03)


def test_pressure_shear_integral_over_hertz_ellipse():
    """int tau dA / Q over the Hertz ellipse, by scipy's dblquad of tau0 + alpha p(x, y), equals
    the closed form tau0 pi a b / Q + alpha (to the quadrature's 1e-9)."""
    tau0, alpha, Q, a, b = 22.0, 0.002, 50.0, 0.30, 0.08
    p0 = 1.5 * Q / (np.pi * a * b)

    def tau(y, x):
        return tau0 + alpha * p0 * np.sqrt(max(0.0, 1 - (x / a) ** 2 - (y / b) ** 2))
    F, _ = integrate.dblquad(tau, -a, a, lambda x: -b * np.sqrt(1 - (x / a) ** 2),
                             lambda x: b * np.sqrt(1 - (x / a) ** 2), epsabs=1e-12, epsrel=1e-11)
    mu = solid_film.pressure_dependent_mu(tau0, alpha, Q, a, b)
    assert F / Q == pytest.approx(float(mu), rel=1e-9)
    # the tau0 part alone is tau0 pi a b / Q = tau0 / p_mean
    assert float(mu) - alpha == pytest.approx(tau0 / solid_film.mean_pressure_MPa(Q, a, b), rel=1e-14)


# ----------------------------------------------------------------------------- starved
def test_starved_flooded_limit_is_palmgren():
    """Infinite oil: the starved viscous torque equals Palmgren's exactly; 1e9 times the flooded
    film: within 1e-12 relative (r^-gamma/gamma)."""
    M0 = palmgren_viscous_torque_Nmm(1.7, np.array([30.0, 300.0]), 5000.0, 40.0)
    assert np.array_equal(starved.starved_viscous_torque_Nmm(M0, np.inf, 0.2), M0)
    near = starved.starved_viscous_torque_Nmm(M0, 0.2e9, 0.2)
    assert np.all(np.abs(near / M0 - 1.0) < 1e-12)


def test_starved_ratio_closed_form_and_starved_limit():
    """h/h_ff = r / (1 + r^g)^(1/g) (Chevalier et al. 1998): at r = 1 it is 2^(-1/g); for
    r -> 0 it tends to r, so the starved torque no longer depends on viscosity x speed: two
    viscosities 10x apart (h_ff ~ (nu n)^0.67, M0 ~ (nu n)^(2/3)) give torques within 1 %
    of each other at r <= 1e-3 against a factor 10^(2/3) = 4.6 flooded."""
    g = starved.GAMMA_CIRCULAR
    assert starved.starvation_ratio(1.0, 1.0) == pytest.approx(2.0 ** (-1.0 / g), rel=4 * EPS)
    nu = np.array([20.0, 200.0])
    M0 = palmgren_viscous_torque_Nmm(1.7, nu, 5000.0, 40.0)
    h_ff = 0.3 * (nu / 20.0) ** 0.67                   # um, the film's viscosity law
    M = starved.starved_viscous_torque_Nmm(M0, 1e-4, h_ff)
    assert M0[1] / M0[0] == pytest.approx(10 ** (2 / 3), rel=1e-12)
    assert M[1] / M[0] == pytest.approx(1.0, abs=0.01)


def test_supply_layer_units():
    """h_oil = (m / rho) / (2 pi dm 2 a): 9 mg of a 900 kg/m^3 oil (10 mm^3) on two tracks of
    2 x 0.25 mm over pi x 40 mm (125.66 mm^2) is 79.6 um."""
    h = starved.supply_layer_um(9.0, 900.0, 40.0, 0.25)
    assert h == pytest.approx(1e3 * 10.0 / (2 * np.pi * 40.0 * 0.5), rel=1e-14)


# ----------------------------------------------------------------------------- EHL rolling
def test_ehl_rolling_force_dimensional_form():
    """F_R = 2.86 E' Rx^2 k^0.348 G^0.022 U^0.66 W^0.47 rewritten in dimensional variables
    (SI units, by hand): 2.86 k^0.348 alpha^0.022 (eta u)^0.66 Q^0.47 E'^-0.108 Rx^0.4 (the
    exponents of E' and Rx summed: 1 + 0.022 - 0.66 - 0.47 and 2 - 0.66 - 0.94)."""
    Q, Rx, k, Ep, eta, alpha, u = 300.0, 3.2, 6.0, 2.26e5, 0.05, 2e-8, 8000.0
    si = (2.86 * k ** 0.348 * alpha ** 0.022 * (eta * u * 1e-3) ** 0.66 * Q ** 0.47
          * (Ep * 1e6) ** (1 + 0.022 - 0.66 - 0.47) * (Rx * 1e-3) ** (2 - 0.66 - 0.94))
    got = ehl_rolling.ehl_rolling_force_N(Q, Rx, k, Ep, eta, alpha, u)
    assert got == pytest.approx(si, rel=1e-12)


PAIR = solve_pair(G, "DB", preload_assembled_N=np.array([1500.0, 1500.0]))


def test_ehl_heat_split_sums_to_total_heat():
    """The located heat (inner + outer contacts, each F_R u from the contact
    speeds) equals the pair's torque x omega to 1e-9 relative."""
    n = np.array([1500.0, 12000.0])
    t = ehl_rolling_pair(G, PAIR, n, 0.03, 2e-8)
    total = power_W(t.total_Nmm, n)
    assert np.all(np.abs(t.heat_inner_W + t.heat_outer_W - total) <= 1e-9 * total)
    assert np.all(t.heat_inner_W > 0) and np.all(t.heat_outer_W > 0)
    assert np.allclose(t.per_bearing_Nmm[0] + t.per_bearing_Nmm[1], t.total_Nmm, rtol=1e-14)


def test_ehl_torque_speed_exponent_is_0_66():
    """At fixed ball loads and viscosity the EHL rolling torque grows as U^0.66 ~ n^0.66 (the
    physics of F_R; no thermal reduction): log-slope between 6 and 48 krpm is 0.66 to 1e-12."""
    n = np.array([6000.0, 48000.0])
    t = ehl_rolling_pair(G, PAIR, n, 0.01, 1.5e-8)
    slope = np.log(t.total_Nmm[1] / t.total_Nmm[0]) / np.log(8.0)
    assert slope == pytest.approx(0.66, abs=1e-12)


def test_ehl_uses_reduced_modulus_of_ring_and_ball():
    """A hybrid bearing (stiffer balls) has a higher E' and, through E'^-0.108, a lower rolling
    force at the same contact state (the modulus enters as the source's groups make it)."""
    Ep = reduced_modulus_MPa(G.ring.E_MPa, G.ring.nu, G.ball.E_MPa, G.ball.nu)
    f1 = ehl_rolling.ehl_rolling_force_N(100.0, 3.0, 6.0, Ep, 0.03, 2e-8, 5000.0)
    f2 = ehl_rolling.ehl_rolling_force_N(100.0, 3.0, 6.0, 1.5 * Ep, 0.03, 2e-8, 5000.0)
    assert f2 / f1 == pytest.approx(1.5 ** -0.108, rel=1e-12)


# ----------------------------------------------------------------------------- the pair's torque
from analytic.heat import located_pair_heat_W                     # noqa: E402
from analytic.friction.pair import TorqueComponents, pair_torque  # noqa: E402
from fem.transient import bearing_heat_inputs_W                  # noqa: E402

N3 = np.array([1500.0, 6000.0, 12000.0])
NU3 = np.array([40.0, 25.0, 12.0])
OIL = dict(model="oil", mu=0.003, speed_rpm=N3, f0=1.7, nu_mm2_s=NU3)
FLUID = dict(eta_Pa_s=NU3 * 1e-6 * 860.0, alpha_per_Pa=2e-8, density_kg_m3=860.0,
             bore_mm=25.0, outside_diameter_mm=62.0)
QD = solve_pair(G, "DB", preload_assembled_N=np.full(3, 1500.0), speed_rpm=N3,
                ball_model="quasi_dynamic")


def _same(a: TorqueComponents, b: TorqueComponents):
    from dataclasses import fields
    for f in fields(TorqueComponents):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, str) or x is None:
            assert x == y, f.name
        else:
            assert np.array_equal(np.asarray(x), np.asarray(y)), f.name


def test_default_options_are_palmgren_bit_for_bit():
    """No options, FrictionOptions() and "starved" without an oil quantity (the flooded limit)
    give the same numbers, bit for bit (the shipped outputs' law)."""
    base = pair_torque(G, QD, **OIL)
    _same(base, pair_torque(G, QD, **OIL, friction=FrictionOptions()))
    starved0 = pair_torque(G, QD, **OIL, friction=FrictionOptions(viscous_model="starved", **FLUID))
    for k in ("torque_Nmm", "torque_A_Nmm", "load_Nmm", "viscous_Nmm", "heat_W"):
        assert np.array_equal(getattr(base, k), getattr(starved0, k)), k
    base_sf = pair_torque(G, QD, model="solid_film", mu=0.05, speed_rpm=N3)
    _same(base_sf, pair_torque(G, QD, model="solid_film", mu=0.05, speed_rpm=N3,
                               friction=FrictionOptions(shear_strength="constant")))


def test_starved_pair_flooded_limit_and_less_torque_with_less_oil():
    """Starved, 1e9 mg of oil: the viscous term equals Palmgren's to 1e-12 relative; 1 mg gives
    a smaller viscous term than 100 mg, which is below Palmgren (starvation only removes film)."""
    pal = pair_torque(G, QD, **OIL)
    v = {m: pair_torque(G, QD, **OIL, friction=FrictionOptions(
        viscous_model="starved", oil_quantity_mg=m, **FLUID)).viscous_Nmm for m in (1e9, 100.0, 1.0)}
    assert np.all(np.abs(v[1e9] / pal.viscous_Nmm - 1.0) < 1e-12)
    assert np.all(v[1.0] < v[100.0]) and np.all(v[100.0] <= pal.viscous_Nmm)


def test_skf_pair_is_the_sum_of_its_bearings():
    """viscous_model "skf2004": each bearing's torque is `skf2004_torque` at its own axial force
    (pure preload: F_r = 0), load term = SKF's sliding, viscous term = its rolling term."""
    t = pair_torque(G, QD, **OIL, friction=FrictionOptions(viscous_model="skf2004", **FLUID))
    ref = [skf2004.skf2004_torque(25.0, 62.0, 0.0, QD.axial_force_N[j], N3, NU3) for j in (0, 1)]
    assert np.allclose(t.torque_A_Nmm, ref[0].total_Nmm, rtol=1e-14)
    assert np.allclose(t.load_Nmm, ref[0].sliding_Nmm + ref[1].sliding_Nmm, rtol=1e-14)
    assert np.allclose(t.viscous_Nmm, ref[0].rolling_Nmm + ref[1].rolling_Nmm, rtol=1e-14)


@pytest.mark.parametrize("options", [
    dict(viscous_model="palmgren"), dict(viscous_model="skf2004"),
    dict(viscous_model="ehl_rolling"), dict(viscous_model="starved", oil_quantity_mg=5.0)])
def test_oil_split_sums_to_torque_and_heat(options):
    """Every oil model: rolling + sliding + drag = torque and heat_inner + heat_outer + heat_ball
    = heat_W (= torque x omega) to 1e-9 relative (the heat split loses nothing), on
    quasi-dynamic balls (each contact at its own load, angle and speed)."""
    t = pair_torque(G, QD, **OIL, friction=FrictionOptions(**options, **FLUID))
    assert np.all(np.abs(t.rolling_Nmm + t.sliding_Nmm + t.drag_Nmm - t.torque_Nmm)
                  <= 1e-9 * t.torque_Nmm)
    q = t.heat_inner_W + t.heat_outer_W + t.heat_ball_W
    assert np.all(np.abs(q - t.heat_W) <= 1e-9 * t.heat_W)
    assert np.all(np.abs(t.heat_W - power_W(t.torque_Nmm, N3)) <= 1e-12 * t.heat_W)


@pytest.mark.parametrize("friction", [FrictionOptions(), FrictionOptions(
    shear_strength="pressure", tau0_MPa=22.0, alpha_shear=0.002)])
def test_solid_film_split_sums_to_torque_and_heat(friction):
    """Solid film, constant or pressure-dependent shear: hysteresis + slip + spin = torque, the
    inner and outer contacts' heat = heat_W to 1e-9 relative, no heat at the balls."""
    t = pair_torque(G, QD, model="solid_film", mu=0.05, hysteresis_loss=0.01, speed_rpm=N3,
                    friction=friction)
    assert np.all(np.abs(t.rolling_Nmm + t.sliding_Nmm + t.drag_Nmm - t.torque_Nmm)
                  <= 1e-9 * t.torque_Nmm)
    assert np.all(np.abs(t.heat_inner_W + t.heat_outer_W + t.heat_ball_W - t.heat_W)
                  <= 1e-9 * t.heat_W)
    assert np.all(t.heat_ball_W == 0.0)


def test_pressure_shear_with_alpha_only_is_the_constant_law():
    """shear_strength "pressure" with tau0 = 0 is the constant law at mu = alpha (to round-off:
    the coefficient enters each contact's product in another order)."""
    a = pair_torque(G, QD, model="solid_film", mu=0.004, speed_rpm=N3)
    b = pair_torque(G, QD, model="solid_film", mu=0.9, speed_rpm=N3, friction=FrictionOptions(
        shear_strength="pressure", tau0_MPa=0.0, alpha_shear=0.004))
    assert np.allclose(b.torque_Nmm, a.torque_Nmm, rtol=1e-14, atol=0)


def test_pressure_shear_torque_falls_in_ratio_with_load():
    """tau0 / p_mean makes a lightly loaded film's coefficient high: with alpha = 0 the
    pressure-law torque per unit of the constant-law torque at mu = 1 is the contact's
    tau0 pi a b / Q, which falls as the preload (and p_mean) rises."""
    pairs = solve_pair(G, "DB", preload_assembled_N=np.array([100.0, 1000.0]))
    n = np.full(2, 100.0)
    p = pair_torque(G, pairs, model="solid_film", mu=0.0, speed_rpm=n,
                    friction=FrictionOptions(shear_strength="pressure", tau0_MPa=20.0))
    c = pair_torque(G, pairs, model="solid_film", mu=1.0, speed_rpm=n)
    ratio = p.torque_Nmm / c.torque_Nmm
    assert ratio[1] < ratio[0]


def test_ehl_pair_quasi_dynamic_speed_exponent_from_physics():
    """ehl_rolling on quasi-dynamic balls of a 25TAC62B pair at 1500 N position preload, one
    viscosity (no thermal reduction): at low speed, where the centrifugal force is small, the
    torque's log-slope is the EHL exponent 0.66 (within 0.005; measured 0.662 between 1.5 and
    3 krpm); at 6..12 krpm the balls' centrifugal force loads the outer contacts (W^0.47) and
    the slope rises above it (measured 0.804). Static balls give 0.66 exactly (above)."""
    n = np.array([1500.0, 3000.0, 6000.0, 12000.0])
    pr = solve_pair(G, "DB", preload_assembled_N=np.full(4, 1500.0), speed_rpm=n,
                    ball_model="quasi_dynamic")
    t = ehl_rolling_pair(G, pr, n, 0.02, 2e-8)
    slope = np.diff(np.log(t.total_Nmm)) / np.diff(np.log(n))
    assert abs(slope[0] - 0.66) < 0.005
    assert slope[2] > 0.7


def test_located_heat_reaches_the_transient_inputs_whole():
    """The located heat of the torque (`located_pair_heat_W`) is the torque's heat; the transient
    heat inputs of a split with heat at the balls (drag) add up to it, to 1e-12 relative, with
    and without ball nodes, and the drag goes to the ball nodes."""
    from analytic.heat import PairHeat
    t = pair_torque(G, QD, **OIL, friction=FrictionOptions(viscous_model="skf2004", **FLUID))
    h = located_pair_heat_W(t, N3)
    assert np.all(np.abs(h.total_W - t.heat_W) <= 1e-12 * t.heat_W)
    z = np.zeros(3)
    # 7 W made at the contacts (4 inner, 3 outer), 1 W at the balls: 8 W in all
    drag = PairHeat(sliding_W=z, spin_W=z, viscous_W=z + 7.0, inner_W=z + 4.0, outer_W=z + 3.0,
                    drag_W=z + 1.0)
    assert np.all(drag.total_W == 8.0)
    for nodes in (True, False):
        q = bearing_heat_inputs_W(drag, row=2, ring_share=0.5, ball_nodes=nodes)
        assert sum(q.values()) == pytest.approx(8.0, rel=1e-12)
    q = bearing_heat_inputs_W(drag, row=2, ring_share=1.0)
    assert q["ball_A"] + q["ball_B"] == pytest.approx(1.0, rel=1e-12)


def test_ehl_rolling_keeps_the_centrifugal_loss_where_the_preload_is_lost():
    """A bearing whose contacts carry no load (preload lost) at speed: its balls ride on the
    outer raceway under F_c = m omega_c^2 dm / 2 and still roll through oil. The torque, written
    out: Z F_R (dm/2) roll_o with F_R = 2.86 E' Rx^2 k^0.348 G^0.022 U^0.66 W^0.47 at Q = F_c,
    Rx = Dw (1 + gamma)/2, k = 1.03 (Ry/Rx)^0.64, Ry = f_o Dw/(2 f_o - 1), omega_c =
    omega (1 - gamma)/2, u = omega (dm/2) roll_o, roll_o = (1 - gamma)(1 + gamma)/2 (gamma =
    Dw cos a / dm, equal angles; to 1e-12 relative). The inner contact (open) has none; at rest
    nothing; where the contacts are loaded the floor changes no bit (the loaded law's limit)."""
    from analytic.friction.pair import BearingContacts, bearing_friction
    from analytic.torque import ContactInput
    n = np.array([0.0, 6000.0, 12000.0])
    nu = np.array([25.0, 25.0, 25.0])
    eta, alpha = nu * 1e-6 * 860.0, 2e-8
    zero = np.zeros(3)
    a = np.radians(np.full(3, G.alpha0_deg))
    open_ = ContactInput(zero, zero, zero, zero, zero)
    c = BearingContacts(open_, open_, a, None, zero)
    fr = FrictionOptions(viscous_model="ehl_rolling", eta_Pa_s=eta, alpha_per_Pa=alpha)
    t = bearing_friction(G, c, model="oil", mu=0.0, speed_rpm=n, f0=1.7, nu_mm2_s=nu, friction=fr)
    Dw, dm, f_o = G.Dw_mm, G.dm_mm, G.f_o
    gam = Dw * np.cos(a) / dm
    omega = n * np.pi / 30.0
    omega_c = omega * (1 - gam) / 2
    Fc = G.ball.density_N_s2_mm4 * np.pi * Dw ** 3 / 6 * omega_c ** 2 * dm / 2
    Rx, Ry = Dw * (1 + gam) / 2, f_o * Dw / (2 * f_o - 1)
    k = 1.03 * (Ry / Rx) ** 0.64
    roll_o = (1 - gam) / 2 * (1 + gam)           # omega_c/omega (1 + cos a / (dm/Dw))
    u = omega * dm / 2 * roll_o
    Ep = reduced_modulus_MPa(G.ring.E_MPa, G.ring.nu, G.ball.E_MPa, G.ball.nu)
    U, Gp, W = eta * 1e-6 * u / (Ep * Rx), alpha * 1e6 * Ep, Fc / (Ep * Rx ** 2)
    F = 2.86 * Ep * Rx ** 2 * k ** 0.348 * Gp ** 0.022 * U ** 0.66 * W ** 0.47
    expect = G.Z * F * dm / 2 * roll_o
    assert t.total_Nmm[0] == 0.0 and np.all(t.total_Nmm[1:] > 0)
    np.testing.assert_allclose(t.total_Nmm[1:], expect[1:], rtol=1e-12)
    assert np.all(t.heat_inner_W == 0)
    # loaded contacts: the floor is not used (the same bits as the loaded law without it)
    from analytic.friction.pair import contact_inputs
    ci, co = contact_inputs(QD, 0)
    kin = ball_kinematics_for(QD)
    args = (G.Z, G.dm_mm, Ep, ci, co, kin.roll_inner, kin.roll_outer, N3, FLUID["eta_Pa_s"], 2e-8)
    floor = ehl_rolling.CentrifugalFloor(np.full(3, 1e3), np.full(3, 1.0), np.full(3, 2.0))
    with_floor, without = ehl_rolling.ehl_rolling_bearing(*args, floor), ehl_rolling.ehl_rolling_bearing(*args)
    assert np.all(QD.outer.a_mm[0] > 0)
    for x, y in zip(with_floor[0] + with_floor[1], without[0] + without[1]):
        assert np.array_equal(x, y)


def ball_kinematics_for(pair):
    """Bearing A's kinematics of a pair state (both contact angles)."""
    from analytic.friction.pair import contact_angles_rad
    from analytic.torque import ball_kinematics
    return ball_kinematics(G.dm_mm, G.Dw_mm, *contact_angles_rad(pair, 0))
