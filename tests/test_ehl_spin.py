"""The spin sliding of the `ehl_rolling` route (issue 43, analytic/friction/ehl_rolling.py): the
moment against the integral of the Hertz pressure over the ellipse, zero where the kinematics
give no spin, and the power balance of the pair's route."""
from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate
from scipy.special import ellipe

from analytic.bearing import BearingGeometry, solve_pair
from analytic.friction.ehl_rolling import (spin_torque_bearing, spin_traction_coefficient,
                                           gyroscopic_traction_ratio)
from analytic.friction.options import FrictionOptions
from analytic.friction.pair import bearing_friction, pair_bearing_contacts, pair_torque
from analytic.friction.skf2004 import MU_EHL
from analytic.torque import RPM_TO_RAD_S, ContactInput, ball_kinematics, power_W

G = BearingGeometry.from_catalogue("25TAC62B")
N3 = np.array([1500.0, 6000.0, 12000.0])
NU3 = np.array([40.0, 25.0, 12.0])
FLUID = dict(eta_Pa_s=NU3 * 1e-6 * 860.0, alpha_per_Pa=2e-8, density_kg_m3=860.0)
OIL = dict(model="oil", mu=0.003, speed_rpm=N3, f0=1.7, nu_mm2_s=NU3)
QD = solve_pair(G, "DB", preload_assembled_N=np.full(3, 1500.0), speed_rpm=N3,
                ball_model="quasi_dynamic")
EHL = FrictionOptions(viscous_model="ehl_rolling", **FLUID)


def _pivot_moment_by_quadrature(mu, Q, a, b):
    """int mu p(x, y) sqrt(x^2 + y^2) dA over the Hertz ellipse, p = 3 Q / (2 pi a b)
    sqrt(1 - x^2/a^2 - y^2/b^2), in polar coordinates x = a r cos t, y = b r sin t."""
    p0 = 1.5 * Q / (np.pi * a * b)
    f = lambda r, t: (mu * p0 * np.sqrt(1.0 - r * r) * r * np.hypot(a * np.cos(t), b * np.sin(t))
                      * a * b * r)
    return integrate.dblquad(f, 0.0, 2.0 * np.pi, 0.0, 1.0, epsabs=0, epsrel=1e-11)[0]


def test_circular_contact_spin_moment_is_3pi_over_16_mu_Q_a():
    """A circle (a = b, E = pi/2): Z M_s omega_s/omega = Z (3 pi / 16) mu Q a spin (Harris &
    Kotzalas Vol. 2; closed form of int mu p r dA), and the same as the quadrature of the
    Hertz pressure, to 1e-9 relative (the quadrature's tolerance)."""
    mu, Q, a, Z, spin = 0.05, 120.0, 0.31, 11, 0.27
    c = ContactInput(np.array([Q]), np.array([a]), np.array([a]), np.array([np.pi / 2]),
                     np.array([4.0]))
    got, _ = spin_torque_bearing(Z, c, c, np.array([spin]), np.array([0.0]), mu)
    closed = Z * 3.0 * np.pi / 16.0 * mu * Q * a * spin
    assert got[0] == pytest.approx(closed, rel=1e-14)
    assert got[0] == pytest.approx(Z * spin * _pivot_moment_by_quadrature(mu, Q, a, a), rel=1e-9)


@pytest.mark.parametrize("ratio", [0.1, 0.3, 0.7])
def test_elliptic_contact_spin_moment_is_the_pressure_integral(ratio):
    """An ellipse b/a = ratio: (3/8) mu Q a E(m), m = 1 - (b/a)^2 (scipy's ellipe, independent of
    the Hertz solver's E), equals the quadrature of mu p r over the ellipse, 1e-9 relative."""
    mu, Q, a = 0.04, 300.0, 0.9
    b = ratio * a
    c = ContactInput(np.array([Q]), np.array([a]), np.array([b]),
                     np.array([ellipe(1.0 - ratio ** 2)]), np.array([4.0]))
    got, _ = spin_torque_bearing(1, c, c, np.array([1.0]), np.array([0.0]), mu)
    assert got[0] == pytest.approx(_pivot_moment_by_quadrature(mu, Q, a, b), rel=1e-9)


def test_no_spin_where_the_kinematics_give_none():
    """At a zero contact angle under outer-race control the inner contact does not spin
    (omega_s,i = omega_R sin(a - beta), a = beta = 0), and the controlling contact never does:
    the spin term is then exactly 0 and the ehl_rolling total is its load and rolling terms; the
    same balls under inner-race control spin at the outer contact only."""
    pair = solve_pair(G, "DB", preload_assembled_N=np.full(3, 1500.0))
    c = pair_bearing_contacts(pair, 0)
    zero = replace(c, alpha_inner_rad=np.zeros(3))
    args = dict(OIL, friction=EHL)
    f = bearing_friction(G, zero, **args)
    assert np.all(f.spin_inner_Nmm == 0.0) and np.all(f.spin_outer_Nmm == 0.0)
    assert np.array_equal(f.total_Nmm, f.load_Nmm + f.viscous_Nmm)
    inner_ctl = bearing_friction(G, replace(c, outer_control=False), **args)
    outer_ctl = bearing_friction(G, c, **args)
    assert np.all(outer_ctl.spin_outer_Nmm == 0.0) and np.all(outer_ctl.spin_inner_Nmm > 0)
    assert np.all(inner_ctl.spin_inner_Nmm == 0.0) and np.all(inner_ctl.spin_outer_Nmm > 0)


def test_spin_power_balances_the_torque_times_the_shaft_speed():
    """Quasi-dynamic pair: the spin power computed at the contacts, Z M_s |omega_s| with omega_s
    in rad/s from the ball kinematics, summed over both bearings and contacts, equals the route's
    spin torque times the shaft speed (1e-12 relative); the route's heat by location sums to
    torque times speed (conservation, 1e-12); the torque split sums to the total."""
    t = pair_torque(G, QD, friction=EHL, **OIL)
    omega = N3 * RPM_TO_RAD_S
    P = 0.0
    for j in (0, 1):
        c = pair_bearing_contacts(QD, j)
        kin = ball_kinematics(G.dm_mm, G.Dw_mm, c.alpha_inner_rad, c.alpha_outer_rad)
        for k, s in ((c.inner, kin.spin_inner), (c.outer, kin.spin_outer)):
            Ms = 0.375 * MU_EHL["mineral"] * k.Q_N * k.a_mm * k.E_ell        # N mm
            P = P + G.Z * Ms * s * omega * 1e-3                             # W
    np.testing.assert_allclose(power_W(t.spin_Nmm, N3), P, rtol=1e-12)
    assert np.all(t.spin_Nmm > 0)
    np.testing.assert_allclose(t.heat_inner_W + t.heat_outer_W + t.heat_ball_W, t.heat_W,
                               rtol=1e-12)
    np.testing.assert_allclose(t.rolling_Nmm + t.sliding_Nmm + t.drag_Nmm, t.torque_Nmm,
                               rtol=1e-12)
    np.testing.assert_allclose(t.load_Nmm + t.viscous_Nmm + t.spin_Nmm, t.torque_Nmm, rtol=1e-12)


def test_traction_bound_follows_the_oil_family_and_only_ehl_rolling_spins():
    """The spin torque is linear in mu_EHL: a synthetic oil's is 0.04 / 0.05 of a mineral one's
    (1e-12); Palmgren's route carries no spin term and is unchanged by the family (exactly)."""
    m = pair_torque(G, QD, friction=EHL, **OIL)
    s = pair_torque(G, QD, friction=replace(EHL, oil_family="synthetic"), **OIL)
    assert spin_traction_coefficient("synthetic") == MU_EHL["synthetic"]
    np.testing.assert_allclose(s.spin_Nmm, 0.8 * m.spin_Nmm, rtol=1e-12)
    p = pair_torque(G, QD, friction=FrictionOptions(**FLUID), **OIL)
    ps = pair_torque(G, QD, friction=FrictionOptions(oil_family="synthetic", **FLUID), **OIL)
    assert p.spin_Nmm is None and np.array_equal(p.torque_Nmm, ps.torque_Nmm)


def test_no_spin_loss_at_rest():
    """At rest there is no entrainment and no EHL film: the spin term is 0 and the ehl_rolling
    starting torque is its load term alone."""
    pair = solve_pair(G, "DB", preload_assembled_N=np.full(3, 1500.0))
    t = pair_torque(G, pair, friction=EHL, **dict(OIL, speed_rpm=np.zeros(3)))
    assert np.all(t.spin_Nmm == 0.0)
    np.testing.assert_array_equal(t.torque_Nmm, t.load_Nmm)


def test_gyroscopic_note_where_the_traction_cannot_hold_the_moment():
    """The thrust limit a = 90 deg (every ball rolls at w_c = 1/2, Omega_r = dm / (2 Dw) per unit
    ring speed): M_g = J omega^2 dm / (4 Dw), J = m Dw^2 / 10 (`ball_dynamics` docstring), so the
    traction ratio 2 M_g / (Dw Q) is m omega^2 dm / (20 Q) by hand; and the route warns on the
    quasi-dynamic rows where the ratio the balls give exceeds mu_EHL and on no others."""
    m, om, dm, Dw, Q = 2.0e-6, 2000.0, 40.0, 8.0, 50.0
    Mg = 0.1 * m * Dw ** 2 * om ** 2 * dm / (4.0 * Dw)
    assert gyroscopic_traction_ratio(Mg, Dw, Q) == pytest.approx(m * om ** 2 * dm / (20.0 * Q),
                                                                 rel=1e-14)
    n = np.array([1000.0, 40000.0])
    light = solve_pair(G, "DB", preload_assembled_N=np.full(2, 20.0), speed_rpm=n,
                       ball_model="quasi_dynamic")
    t = pair_torque(G, light, friction=replace(EHL, eta_Pa_s=0.02), **dict(
        OIL, speed_rpm=n, nu_mm2_s=np.full(2, 25.0)))
    d = light.dynamic
    r = gyroscopic_traction_ratio(d.gyroscopic_moment_Nmm, G.Dw_mm,
                                  np.where(d.outer_control, d.load_outer_N, d.load_inner_N))
    expect = (r > MU_EHL["mineral"]).any(axis=0)
    note = [x for x in t.range_notes if "gyroscopic" in x.quantity]
    assert expect.any() and not expect.all()        # the test spans both sides of the bound
    assert len(note) == 1 and note[0].rows == int(expect.sum())
