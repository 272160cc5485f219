"""Exact Hertz point contact: checked against Johnson's closed form for a sphere on a flat, against
the defining integrals of K and E evaluated by quadrature (not by scipy's ellipk/ellipe or the
module's series), against an independent surface-displacement calculation (Boussinesq kernel
integrated over the Hertz pressure, semi-analytically in polar coordinates), against Harris's
written-out curvature-difference formulas, and against the published approximations."""
import numpy as np
import pytest
from scipy.integrate import quad

from analytic import hertz

E_STEEL, NU_STEEL = 200e3, 0.30
E_STAR = float(hertz.contact_modulus_MPa(E_STEEL, NU_STEEL, E_STEEL, NU_STEEL))


def test_contact_modulus_identical_materials():
    # Johnson (1985, ch. 4) with equal bodies: E* = E / (2 (1 - nu^2))
    assert E_STAR == pytest.approx(E_STEEL / (2 * (1 - NU_STEEL ** 2)), rel=1e-15)


@pytest.mark.parametrize("Q", [1.0, 100.0, 5000.0])
@pytest.mark.requirement("R-HERTZ")
def test_sphere_on_flat_equals_johnson(Q):
    """Johnson, Contact Mechanics (1985) ch. 4 (sphere radius R on a flat, Rx = Ry = R):
    a = (3 Q R / (4 E*))^(1/3), delta = a^2 / R, p0 = 3 Q / (2 pi a^2)."""
    R = 5.0
    h = hertz.hertz_point_contact(Q, R, R, E_STAR)
    a = (3 * Q * R / (4 * E_STAR)) ** (1 / 3)
    assert h.kappa == pytest.approx(1.0, abs=1e-15)
    assert h.a_mm == pytest.approx(a, rel=1e-13)
    assert h.b_mm == pytest.approx(a, rel=1e-13)
    assert h.delta_mm == pytest.approx(a * a / R, rel=1e-13)
    assert h.p_max_MPa == pytest.approx(3 * Q / (2 * np.pi * a * a), rel=1e-13)
    # stiffness: Q = K delta^1.5 with Johnson's Q = (4/3) E* sqrt(R) delta^1.5
    assert h.K_N_per_mm15 == pytest.approx(4 / 3 * E_STAR * np.sqrt(R), rel=1e-13)


@pytest.mark.parametrize("eps", [1e-9, 1e-7, 1e-5])
def test_near_circular_contact_is_continuous(eps):
    """Curvature ratio 1 + eps: no cancellation blow-up; the result tends to the circular
    (Johnson) values linearly in eps, and kappa follows Greenwood's (1985) asymptote
    kappa = (Ry/Rx)^(2/3) to second order in eps."""
    R, Q = 5.0, 100.0
    h = hertz.hertz_point_contact(Q, R, R * (1 + eps), E_STAR)
    a_sphere = (3 * Q * R / (4 * E_STAR)) ** (1 / 3)
    assert np.isfinite([h.a_mm, h.b_mm, h.delta_mm, h.p_max_MPa, h.kappa]).all()
    assert h.kappa >= 1.0
    assert abs(h.kappa - (1 + eps) ** (2 / 3)) <= eps ** 2 + 1e-15
    # the ellipse is at most eps away from the circle (a, b, delta within a few eps)
    assert abs(h.a_mm / a_sphere - 1) <= 3 * eps
    assert abs(h.b_mm / a_sphere - 1) <= 3 * eps


@pytest.mark.parametrize("ratio", [1.0 + 1e-3, 1.5, 4.0, 10.0, 30.0, 300.0, 1e4])
@pytest.mark.requirement("R-HERTZ")
def test_ellipticity_solves_hertz_equation_by_quadrature(ratio):
    """(kappa^2 E - K)/(K - E) = Ry/Rx (Harris Vol. 1 ch. 6, rearranged), with K and E
    recomputed from their defining integrals by adaptive quadrature; the returned K and E equal
    those integrals."""
    kappa, K, E, _ = hertz.solve_ellipticity(ratio)
    m = 1.0 - 1.0 / kappa ** 2
    Kq = quad(lambda t: 1.0 / np.sqrt(1.0 - m * np.sin(t) ** 2), 0, np.pi / 2,
              epsabs=0, epsrel=1e-13, limit=200)[0]
    Eq = quad(lambda t: np.sqrt(1.0 - m * np.sin(t) ** 2), 0, np.pi / 2,
              epsabs=0, epsrel=1e-13, limit=200)[0]
    assert K == pytest.approx(Kq, rel=1e-12)
    assert E == pytest.approx(Eq, rel=1e-12)
    if ratio > 1.01:   # below, K - E ~ m cancels in this check itself (not in the solver)
        assert (kappa ** 2 * Eq - Kq) / (Kq - Eq) == pytest.approx(ratio, rel=1e-10)


def test_forward_equation_round_trip():
    """Harris's F(rho) = [(kappa^2+1)E - 2K]/[(kappa^2-1)E] evaluated from the solved kappa equals
    the curvature difference (Ry - Rx)/(Ry + Rx) that went in (Harris Vol. 1 ch. 2)."""
    ratio = np.array([1.2, 2.0, 7.5, 25.0, 120.0])
    kappa = hertz.ellipticity(ratio)
    assert np.allclose(hertz.curvature_difference_from_kappa(kappa), (ratio - 1) / (ratio + 1),
                       rtol=1e-12, atol=0)


def _boussinesq_displacement(x0, y0, a, b, p0, E_star, n_theta=1024):
    """Combined normal surface displacement at (x0, y0) under p = p0 sqrt(1 - x^2/b^2 - y^2/a^2):
    w = 1/(pi E*) int int p / r dA (Johnson 1985 ch. 3, point load on a half-space, summed over both bodies).  Polar coordinates
    about (x0, y0): the radial integral of sqrt(quadratic) is done in closed form, the angular one
    by the trapezoidal rule (spectrally accurate for a smooth periodic integrand)."""
    th = np.linspace(0, 2 * np.pi, n_theta, endpoint=False)
    c, s = np.cos(th), np.sin(th)
    A = c ** 2 / b ** 2 + s ** 2 / a ** 2
    B = x0 * c / b ** 2 + y0 * s / a ** 2
    C = 1 - x0 ** 2 / b ** 2 - y0 ** 2 / a ** 2
    root = np.sqrt(B * B + A * C)
    sp, sm = (-B + root) / A, (-B - root) / A          # q(s) = A (sp - s)(s - sm)
    c0, hw = 0.5 * (sp + sm), 0.5 * (sp - sm)
    radial = np.pi * hw ** 2 / 4 + c0 * np.sqrt(hw ** 2 - c0 ** 2) / 2 + hw ** 2 / 2 * np.arcsin(c0 / hw)
    return p0 / (np.pi * E_star) * (np.sqrt(A) * radial).mean() * 2 * np.pi


@pytest.mark.parametrize("Rx,Ry", [(5.0, 5.0), (4.0, 6.8), (1.8, 45.0)])
@pytest.mark.requirement("R-HERTZ")
def test_surface_displacement_matches_gap_condition(Rx, Ry):
    """Inside the contact the surfaces conform: w(x, y) = delta - x^2/(2Rx) - y^2/(2Ry) (Johnson
    1985 ch. 4), with w from the Boussinesq integral of the Hertz pressure.  This checks the
    approach delta, the semi-axes and p_max without any elliptic integral."""
    Q = 80.0
    h = hertz.hertz_point_contact(Q, Rx, Ry, E_STAR)
    a, b, p0, delta = float(h.a_mm), float(h.b_mm), float(h.p_max_MPa), float(h.delta_mm)
    for fx, fy in [(0.0, 0.0), (0.5, 0.3), (-0.2, 0.8), (0.9, 0.0)]:
        x0, y0 = fx * b, fy * a
        w = _boussinesq_displacement(x0, y0, a, b, p0, E_STAR)
        assert w == pytest.approx(delta - x0 ** 2 / (2 * Rx) - y0 ** 2 / (2 * Ry), rel=1e-12)


def test_ball_raceway_curvature_matches_harris():
    """Harris Vol. 1 ch. 2 written out: inner F = (1/f + 2g/(1-g))/(4 - 1/f + 2g/(1-g)),
    outer F = (1/f - 2g/(1+g))/(4 - 1/f - 2g/(1+g)), sum_rho = (4 - 1/f +- 2g/(1 -+ g))/Dw."""
    Dw, dm, alpha, f = 3.969, 41.0, np.array([0.0, 15.0, 40.0]), 0.52
    g = Dw * np.cos(np.radians(alpha)) / dm
    si, Fi = hertz.ball_raceway_curvature(Dw, dm, alpha, f, "inner")
    so, Fo = hertz.ball_raceway_curvature(Dw, dm, alpha, f, "outer")
    assert np.allclose(Fi, (1 / f + 2 * g / (1 - g)) / (4 - 1 / f + 2 * g / (1 - g)), rtol=1e-14)
    assert np.allclose(Fo, (1 / f - 2 * g / (1 + g)) / (4 - 1 / f - 2 * g / (1 + g)), rtol=1e-14)
    assert np.allclose(si, (4 - 1 / f + 2 * g / (1 - g)) / Dw, rtol=1e-14)
    assert np.allclose(so, (4 - 1 / f - 2 * g / (1 + g)) / Dw, rtol=1e-14)


def test_vectorised_equals_pointwise():
    Q = np.array([10.0, 50.0, 200.0])
    Rx = np.array([1.8, 2.0, 5.0])
    Ry = np.array([26.0, 2.0 * (1 + 1e-9), 5.5])
    hv = hertz.hertz_point_contact(Q, Rx, Ry, E_STAR)
    for i in range(3):
        hs = hertz.hertz_point_contact(Q[i], Rx[i], Ry[i], E_STAR)
        for name in ("a_mm", "b_mm", "delta_mm", "p_max_MPa", "kappa"):
            assert getattr(hv, name)[i] == pytest.approx(float(getattr(hs, name)), rel=1e-14)


def test_ratio_below_one_is_the_same_ellipse_turned():
    h1 = hertz.hertz_point_contact(50.0, 2.0, 30.0, E_STAR)
    h2 = hertz.hertz_point_contact(50.0, 30.0, 2.0, E_STAR)
    for name in ("a_mm", "b_mm", "delta_mm", "p_max_MPa"):
        assert float(getattr(h2, name)) == pytest.approx(float(getattr(h1, name)), rel=1e-14)


def test_hamrock_brewe_1983_exact_for_circle():
    """Hamrock & Brewe (1983) forms reduce to kappa = 1, K = E = pi/2 at Ry/Rx = 1 exactly."""
    k, K, E = hertz.ellipticity_hamrock_brewe_1983(1.0)
    assert (k, K, E) == (1.0, np.pi / 2, np.pi / 2)


@pytest.mark.parametrize("fn,tol_kappa,tol_KE", [
    # The simplified formulas are quoted as accurate to "a few percent" over 1 <= Ry/Rx <= 100
    # (Brewe & Hamrock 1977; Hamrock & Brewe 1983; Hamrock, Fundamentals of Fluid Film
    # Lubrication, ch. 3).  Brewe & Hamrock's power law drifts to ~6 % at Ry/Rx = 100.
    (hertz.ellipticity_brewe_hamrock_1977, 0.07, 0.03),
    (hertz.ellipticity_hamrock_brewe_1983, 0.04, 0.03),
])
def test_approximations_within_published_accuracy(fn, tol_kappa, tol_KE):
    ratio = np.geomspace(1.0, 100.0, 200)
    kappa, K, E, _ = hertz.solve_ellipticity(ratio)
    ka, Ka, Ea = fn(ratio)
    assert np.max(np.abs(ka / kappa - 1)) < tol_kappa
    assert np.max(np.abs(Ka / K - 1)) < tol_KE
    assert np.max(np.abs(Ea / E - 1)) < tol_KE


def test_greenwood_asymptote_is_first_order_exact():
    """Greenwood (1985): a/b -> (Ry/Rx)^(2/3) as Ry/Rx -> 1, so the relative error is o(Ry/Rx - 1);
    asserted as below (Ry/Rx - 1)^2, while the error of kappa = 1 is ~ (2/3)(Ry/Rx - 1)."""
    eps = np.array([1e-2, 1e-3, 1e-4])
    kappa = hertz.ellipticity(1 + eps)
    err = np.abs(kappa / hertz.ellipticity_greenwood_1985(1 + eps) - 1)
    assert np.all(err < eps ** 2)
    assert np.allclose((kappa - 1) / eps, 2 / 3, rtol=2 * eps.max())


def test_series_stiffness_is_two_springs_in_series():
    """delta = delta_i + delta_o at the same Q (Harris Vol. 1 ch. 7)."""
    Ki, Ko, Q = 5.0e5, 3.0e5, 40.0
    Kn = hertz.series_stiffness_N_per_mm15(Ki, Ko)
    assert (Q / Kn) ** (2 / 3) == pytest.approx((Q / Ki) ** (2 / 3) + (Q / Ko) ** (2 / 3), rel=1e-14)
