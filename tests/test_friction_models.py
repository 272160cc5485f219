"""analytic/friction/: each friction model against its source's closed form, its limits, and
the law it reduces to (issue 33, item 1). Requirement names in each docstring."""
import numpy as np
import pytest
from scipy import integrate

from analytic.bearing import BearingGeometry, solve_pair
from analytic.friction import ehl_rolling, skf2004, solid_film, starved
from analytic.lubrication import reduced_modulus_MPa
from analytic.torque import ehl_rolling_pair, palmgren_viscous_torque_Nmm, power_W

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
    g1 = skf2004.rolling_variable(skf2004.SKF_72B, 43.5, 0.0, 1000.0)
    g2 = skf2004.rolling_variable(skf2004.SKF_72B, 43.5, 0.0, 8000.0)
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
    """M_drag = 0 with V_M = 0 (no oil bath); every component 0 at n = 0 (a running torque)."""
    t = skf2004.skf2004_torque(25.0, 62.0, 0.0, 1500.0, np.array([0.0, 3000.0]), 50.0)
    assert np.all(t.drag_Nmm == 0.0)
    assert t.total_Nmm[0] == 0.0 and t.total_Nmm[1] > 0.0


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
    """Issue 33 Done-when: the located heat (inner + outer contacts, each F_R u from the contact
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
