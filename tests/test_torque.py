"""Friction torque models: checked against the kinematic conditions they are built on, direct
numerical integration of the contact dissipation over the Hertz ellipse (second route for the
Heathcote and spin formulas), closed forms (circular spin moment), and scaling laws and limits
that follow from the formulas (2/3 power, low-speed branch, zero spin at zero contact angle,
linearity in mu, Q^(4/3) hysteresis)."""
import numpy as np
import pytest
from scipy.integrate import quad

from analytic import hertz, torque
from analytic.friction import pair as friction_pair
from analytic.friction import palmgren
from analytic.bearing import BearingGeometry, solve_pair

G = BearingGeometry.from_catalogue("71807C")


@pytest.mark.parametrize("alpha_deg", [0.0, 15.0, 40.0, 60.0])
def test_kinematics_equal_angles(alpha_deg):
    """Outer ring fixed, inner ring at omega: cage omega_c = omega (1 - gamma)/2 (Harris Vol. 2,
    ball bearing kinematics); outer-race control gives no outer spin and an inner spin equal to the
    ring's speed component along the common normal, omega sin(alpha); the contact travels over both
    races at the same speed (dm/4)(1 - gamma^2) omega."""
    a = np.radians(alpha_deg)
    gamma = G.Dw_mm * np.cos(a) / G.dm_mm
    k = torque.ball_kinematics(G.dm_mm, G.Dw_mm, a)
    assert k.cage == pytest.approx((1 - gamma) / 2, rel=1e-14)
    assert k.spin_inner == pytest.approx(np.sin(a), abs=1e-15)
    assert k.spin_outer == 0.0
    assert k.roll_inner == pytest.approx(k.roll_outer, rel=1e-14)
    assert k.roll_inner * G.dm_mm / 2 == pytest.approx(G.dm_mm / 4 * (1 - gamma ** 2), rel=1e-14)


def test_kinematics_unequal_angles_satisfy_rolling_and_control():
    """The three conditions the solution is built on, checked with the returned ball angular
    velocity: no slip at both contact centres, no spin at the outer contact."""
    ai, ao = np.radians(18.0), np.radians(13.0)
    q = G.dm_mm / G.Dw_mm
    k = torque.ball_kinematics(G.dm_mm, G.Dw_mm, ai, ao)
    Om = np.array([k.omega_r, k.omega_z])
    n_i, t_i = np.array([np.cos(ai), np.sin(ai)]), np.array([-np.sin(ai), np.cos(ai)])
    n_o, t_o = np.array([np.cos(ao), np.sin(ao)]), np.array([-np.sin(ao), np.cos(ao)])
    wc = k.cage
    assert Om @ t_i + (1 - wc) * (q - np.cos(ai)) == pytest.approx(0, abs=1e-12)
    assert Om @ t_o + wc * (q + np.cos(ao)) == pytest.approx(0, abs=1e-12)
    assert Om @ n_o + wc * np.sin(ao) == pytest.approx(0, abs=1e-12)
    assert k.spin_inner == pytest.approx(abs(Om @ n_i - (1 - wc) * np.sin(ai)), rel=1e-13)


def _contact(Q, alpha_deg, race):
    Rx, Ry = hertz.ball_raceway_radii_mm(G.Dw_mm, G.dm_mm, alpha_deg, G.f_i if race == "inner" else G.f_o, race)
    h = hertz.hertz_point_contact(Q, Rx, Ry, G.E_star_MPa)
    return torque.ContactInput(np.asarray(Q, float), h.a_mm, h.b_mm, h.E_elliptic, Rx)


def _solid(Q, alpha_deg, mu=0.02, loss=0.01):
    return torque.solid_film_torque_Nmm(G.Z, G.Dw_mm, G.dm_mm, G.f_i, G.f_o, np.radians(alpha_deg),
                                        _contact(Q, alpha_deg, "inner"), _contact(Q, alpha_deg, "outer"),
                                        mu, loss)


def test_zero_spin_at_zero_contact_angle():
    t0 = _solid(20.0, 0.0)
    assert t0.spin_inner_Nmm == 0.0 and t0.spin_outer_Nmm == 0.0
    assert _solid(20.0, 15.0).spin_inner_Nmm > 0.0


def test_torque_linear_in_mu_and_loss_factor():
    """Sliding and spin dissipation are Coulomb (proportional to mu); hysteresis is proportional
    to the loss factor and independent of mu."""
    t1, t2 = _solid(30.0, 16.0, mu=0.02, loss=0.01), _solid(30.0, 16.0, mu=0.05, loss=0.03)
    for key in ("differential_inner_Nmm", "differential_outer_Nmm", "spin_inner_Nmm"):
        assert getattr(t2, key) / getattr(t1, key) == pytest.approx(2.5, rel=1e-14)
    for key in ("hysteresis_inner_Nmm", "hysteresis_outer_Nmm"):
        assert getattr(t2, key) / getattr(t1, key) == pytest.approx(3.0, rel=1e-14)


def test_hysteresis_scales_with_load_to_four_thirds():
    """F_R = alpha_h (3/16) Q b / Rx with b ~ Q^(1/3) (Hertz): 8x the load gives 16x the force."""
    c1, c8 = _contact(10.0, 15.0, "inner"), _contact(80.0, 15.0, "inner")
    F1 = torque.hysteresis_rolling_force_N(0.01, c1.Q_N, c1.b_mm, c1.Rx_mm)
    F8 = torque.hysteresis_rolling_force_N(0.01, c8.Q_N, c8.b_mm, c8.Rx_mm)
    assert F8 / F1 == pytest.approx(16.0, rel=1e-12)


@pytest.mark.requirement("R-TORQUE")
def test_hysteresis_force_is_work_of_front_half_pressure():
    """Johnson 1985 ch. 9: the work per unit distance rolled is the moment of the front half of the
    pressure about the contact centre over Rx; the moment integrated numerically equals (3/16) Q b."""
    a, b, Q = 0.25, 0.03, 15.0
    p0 = 1.5 * Q / (np.pi * a * b)
    M = quad(lambda x: x * quad(lambda y: p0 * np.sqrt(max(1 - x * x / b ** 2 - y * y / a ** 2, 0.0)),
                                -a * np.sqrt(1 - x * x / b ** 2), a * np.sqrt(1 - x * x / b ** 2),
                                epsabs=0, epsrel=1e-12)[0], 0, b, epsabs=0, epsrel=1e-12)[0]
    assert torque.hysteresis_rolling_force_N(1.0, Q, b, 1.0) == pytest.approx(M, rel=1e-8)


def test_heathcote_rolling_bands():
    """The rolling bands sit where the net traction of full sliding vanishes:
    int_0^1 (1 - u^2) sign(u^2 - u_c^2) du = 0 (ellipsoidal pressure integrated across the minor
    axis is ~ 1 - u^2), and that position minimises the dissipated power."""
    uc = torque.U_C_HEATHCOTE
    net = quad(lambda u: (1 - u * u), uc, 1)[0] - quad(lambda u: (1 - u * u), 0, uc)[0]
    assert net == pytest.approx(0.0, abs=1e-14)

    def power(u1):
        return (quad(lambda u: (1 - u * u) * (u1 ** 2 - u * u), 0, u1)[0]
                + quad(lambda u: (1 - u * u) * (u * u - u1 ** 2), u1, 1)[0])
    assert power(uc) < power(uc - 0.01) and power(uc) < power(uc + 0.01)
    assert torque.C_HEATHCOTE == pytest.approx(0.08, abs=0.001)   # Johnson: "about 0.08"


@pytest.mark.requirement("R-TORQUE")
def test_heathcote_power_by_direct_integration():
    """Power = mu int int p |k (y^2 - y_c^2)| / (2 R_c) dA over the ellipse (y along the major
    axis a), integrated numerically in 2-D, equals C_H mu |k| Q a^2 / R_c."""
    a, b, Q, Rc, mu, k = 0.3, 0.035, 20.0, 2.03, 0.03, 7.0
    p0 = 1.5 * Q / (np.pi * a * b)
    yc = torque.U_C_HEATHCOTE * a

    def strip(y):
        xm = b * np.sqrt(1 - y * y / a ** 2)
        return quad(lambda x: p0 * np.sqrt(max(1 - x * x / b ** 2 - y * y / a ** 2, 0.0)), -xm, xm,
                    epsabs=0, epsrel=1e-12)[0] * abs(y * y - yc * yc)
    P = 2 * mu * k / (2 * Rc) * (quad(strip, 0, yc, epsabs=0, epsrel=1e-11)[0]
                                 + quad(strip, yc, a, epsabs=0, epsrel=1e-11)[0])
    assert torque.heathcote_power_per_rate(mu, Q, a, Rc) * k == pytest.approx(P, rel=1e-8)


@pytest.mark.parametrize("ratio", [1.0, 4.0, 25.0])
@pytest.mark.requirement("R-TORQUE")
def test_spin_moment_by_direct_integration(ratio):
    """M_s = int int mu p sqrt(x^2 + y^2) dA (full slip about the centre) equals (3/8) mu Q a E(m);
    the circular contact gives Johnson's 3 pi mu Q a / 16."""
    Q, mu, Rx = 12.0, 0.05, 2.0
    h = hertz.hertz_point_contact(Q, Rx, Rx * ratio, G.E_star_MPa)
    a, b, p0 = float(h.a_mm), float(h.b_mm), float(h.p_max_MPa)
    # polar coordinates on the unit disc after x = b r cos t, y = a r sin t
    M = quad(lambda t: quad(lambda r: p0 * np.sqrt(1 - r * r) * r * a * b
                            * r * np.hypot(b * np.cos(t), a * np.sin(t)), 0, 1,
                            epsabs=0, epsrel=1e-12)[0], 0, 2 * np.pi, epsabs=0, epsrel=1e-11)[0] * mu
    Ms = torque.spin_moment_Nmm(mu, Q, a, float(h.E_elliptic))
    assert Ms == pytest.approx(M, rel=1e-8)
    if ratio == 1.0:
        assert Ms == pytest.approx(3 * np.pi * mu * Q * a / 16, rel=1e-14)


def test_contact_surface_radius_limits():
    """Equal compliances: mean curvature (1/R_b + 1/r_g)/2 (Johnson 1985 ch. 4); a rigid ball keeps
    its own radius."""
    Dw, f = 4.0, 0.52
    Rc = torque.contact_surface_radius_mm(Dw, f, 1.0, 1.0)
    assert 1 / Rc == pytest.approx(0.5 * (2 / Dw + 1 / (f * Dw)), rel=1e-15)
    assert torque.contact_surface_radius_mm(Dw, f, 1.0, 0.0) == pytest.approx(Dw / 2, rel=1e-15)


def test_viscous_two_thirds_power_and_dm_cubed():
    """Palmgren: M0 ~ (nu n)^(2/3) dm^3 above nu n = 2000 (8x nu n -> 4x torque)."""
    M = palmgren.palmgren_viscous_torque_Nmm(1.7, np.array([10.0, 80.0]), 3000.0, 31.0)
    assert M[1] / M[0] == pytest.approx(4.0, rel=1e-13)
    M2 = palmgren.palmgren_viscous_torque_Nmm(1.7, 10.0, 3000.0, 62.0)
    assert M2 / M[0] == pytest.approx(8.0, rel=1e-13)
    assert M[0] == pytest.approx(1e-7 * 1.7 * 30000.0 ** (2 / 3) * 31.0 ** 3, rel=1e-13)


def test_viscous_low_speed_branch():
    """Below nu n = 2000 the torque is the constant 160e-7 f0 dm^3; the branches nearly meet:
    160 / 2000^(2/3) = 1.0079."""
    low = palmgren.palmgren_viscous_torque_Nmm(1.0, np.array([0.0, 1.0, 19.99]), 100.0, 40.0)
    assert np.allclose(low, 160e-7 * 40.0 ** 3, rtol=1e-15)
    hi = palmgren.palmgren_viscous_torque_Nmm(1.0, 20.0, 100.0, 40.0)
    assert low[-1] / hi == pytest.approx(160.0 / 2000.0 ** (2 / 3), rel=1e-12)
    assert abs(low[-1] / hi - 1) < 0.01


def test_gbt_form_is_load_plus_viscous():
    """GB/T 28878.2 B.4 with Palmgren's coefficient: f1 F dm + c f0 (nu n)^(2/3) dm^3 equals the sum
    of the two Palmgren terms above nu n = 2000 and is linear in F."""
    args = dict(dm_mm=31.0, f0=1.7, nu_mm2_s=20.0, n_rpm=6000.0)
    M1 = palmgren.gbt28878_torque_mNm(0.001, 10.0, **args)
    M2 = palmgren.gbt28878_torque_mNm(0.001, 20.0, **args)
    Mv = palmgren.palmgren_viscous_torque_Nmm(1.7, 20.0, 6000.0, 31.0)
    assert M1 == pytest.approx(palmgren.palmgren_load_torque_Nmm(0.001, 10.0, 31.0) + Mv, rel=1e-14)
    assert M2 - M1 == pytest.approx(0.001 * 10.0 * 31.0, rel=1e-12)


def test_power_from_torque_matches_seed003_constant():
    """Seed 003 eq. 32: H = 1.047e-4 n M (W, n rpm, M N*mm); 2 pi/60e3 = 1.0472e-4, so the
    seed's 4-digit constant agrees to 2e-4."""
    assert torque.power_W(2.0, 1500.0) == pytest.approx(1.047e-4 * 1500.0 * 2.0, rel=3e-4)
    heat = torque.friction_heat_W({"spin_inner_Nmm": np.array([1.0])}, 1000.0)
    assert list(heat) == ["spin_inner_W"]


def test_pair_torque_of_symmetric_pair_is_twice_one_bearing():
    pair = solve_pair(G, "DB", preload_assembled_N=np.array([50.0, 200.0]))
    t = friction_pair.pair_torque(G, pair, mu=0.02, hysteresis_loss=0.01, speed_rpm=60.0)
    assert np.allclose(t.torque_A_Nmm, t.torque_B_Nmm, rtol=1e-12)
    one = [_solid(pair.ball_load_N[0][i], pair.contact_angle_deg[0][i]).total_Nmm for i in range(2)]
    assert np.allclose(t.torque_Nmm, 2 * np.array(one, float).ravel(), rtol=1e-9)
    parts = t.hysteresis_Nmm + t.differential_Nmm + t.spin_Nmm
    assert np.allclose(parts, t.torque_Nmm, rtol=1e-14)
    assert np.all(np.diff(t.torque_Nmm) > 0)        # more preload, more torque (seed 000)
    assert np.allclose(t.heat_W, torque.power_W(t.torque_Nmm, 60.0), rtol=1e-15)


def test_oil_pair_torque_terms():
    """Load term mu F dm/2 per bearing (linear in the preload) plus Palmgren's viscous term per
    bearing (independent of the load)."""
    hyb = BearingGeometry.from_catalogue("flywheel")
    pair = solve_pair(hyb, "DF", preload_assembled_N=np.array([7.0, 14.0]))
    t = friction_pair.pair_torque(hyb, pair, model="oil", mu=0.0029, f0=1.7, nu_mm2_s=30.0, speed_rpm=6000.0)
    assert np.allclose(t.load_Nmm, 2 * 0.0029 * np.array([7.0, 14.0]) * hyb.dm_mm / 2, rtol=1e-12)
    M0 = palmgren.palmgren_viscous_torque_Nmm(1.7, 30.0, 6000.0, hyb.dm_mm)
    assert np.allclose(t.viscous_Nmm, 2 * M0, rtol=1e-14)
    assert np.allclose(t.torque_Nmm, t.load_Nmm + t.viscous_Nmm, rtol=1e-14)


def test_sliding_spin_heat_for_thermal_network():
    """Oil-bearing sliding and spin parts are the solid-film differential and spin parts with the
    traction coefficient (no hysteresis); mu_spin rescales only the spin; heat = torque x speed."""
    base = _solid(40.0, 20.0, mu=0.04, loss=0.0)
    cin, cout = _contact(40.0, 20.0, "inner"), _contact(40.0, 20.0, "outer")
    oil = torque.sliding_spin_torque_Nmm(G.Z, G.Dw_mm, G.dm_mm, G.f_i, G.f_o, np.radians(20.0),
                                         cin, cout, mu_slide=0.04, mu_spin=0.02)
    assert oil.sliding_inner_Nmm == pytest.approx(base.differential_inner_Nmm, rel=1e-14)
    assert oil.sliding_outer_Nmm == pytest.approx(base.differential_outer_Nmm, rel=1e-14)
    assert oil.spin_inner_Nmm == pytest.approx(0.5 * base.spin_inner_Nmm, rel=1e-14)
    heat = torque.friction_heat_W(oil, 1500.0)
    assert heat["spin_inner_W"] == pytest.approx(oil.spin_inner_Nmm * 1500 * 2 * np.pi / 60e3, rel=1e-14)
