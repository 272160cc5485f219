"""Lamé thick-ring fits: checked against an independent numerical solution of radial equilibrium
(scipy solve_bvp, constitutive law written with Lamé constants, not with the plane-strain
substitution), identities (compatibility, traction continuity, free surfaces), limits (thin ring,
rigid shaft, solid shaft), and the fit-change rates published in seed 000."""
import numpy as np
import pytest
from scipy.integrate import solve_bvp

from analytic.lame import (effective_elastic, fit_pressure_MPa, fit_state, fit_displacement_mm,
                           hoop_stress_MPa, interference_at_temperature_um, multilayer_fit,
                           radial_displacement_mm, radial_stress_MPa)
from analytic.materials import get_material

STEEL = get_material("9Cr18")
TI = get_material("TC4")
AL = get_material("2A12")


def stiffness(E, nu, assumption):
    """(C11, C12) of sigma_rr = C11 eps_rr + C12 eps_tt, written from first principles:
    plane stress E/(1-nu^2)(1, nu); plane strain lambda + 2 mu, lambda (Lamé constants)."""
    if assumption == "plane_stress":
        return E / (1 - nu**2), nu * E / (1 - nu**2)
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    return lam + 2 * mu, lam


def bvp_layers(radii, E, nu, interf_um, assumption):
    """Solve radial equilibrium d(sigma_rr)/dr + (sigma_rr - sigma_tt)/r = 0 in every layer with
    scipy.solve_bvp (each layer mapped to s in [0, 1]); closed interfaces: sigma_rr continuous and
    u_out - u_in = delta/2; free outer surface; free bore or, for a solid core, the regular
    solution (u proportional to r, i.e. sigma_rr = (C11 + C12) u / r) imposed at a small radius.
    Returns the interface pressures (MPa) and a displacement evaluator."""
    R = np.array(radii, float)
    solid = R[0] == 0.0
    if solid:
        R[0] = 1e-3 * R[1]
    N = len(R) - 1
    C = [stiffness(E[k], nu[k], assumption) for k in range(N)]
    L = np.diff(R)

    def f(s, y):
        dy = np.zeros_like(y)
        for k in range(N):
            r = R[k] + s * L[k]
            u, sig = y[2 * k], y[2 * k + 1]
            C11, C12 = C[k]
            du = (sig - C12 * u / r) / C11
            sth = C12 * du + C11 * u / r
            dy[2 * k] = L[k] * du
            dy[2 * k + 1] = L[k] * (sth - sig) / r
        return dy

    def bc(ya, yb):
        inner = ya[1] - (C[0][0] + C[0][1]) * ya[0] / R[0] if solid else ya[1]
        res = [inner, yb[2 * N - 1]]
        for i in range(1, N):
            res.append(yb[2 * (i - 1) + 1] - ya[2 * i + 1])
            res.append(ya[2 * i] - yb[2 * (i - 1)] - 0.5e-3 * interf_um[i - 1])
        return np.array(res)

    s = np.linspace(0, 1, 41)
    sol = solve_bvp(f, bc, s, np.zeros((2 * N, s.size)), tol=1e-10, max_nodes=100000)
    assert sol.success, sol.message
    p = np.array([-sol.sol(1.0)[2 * (i - 1) + 1] for i in range(1, N)])

    def u(layer, r):
        return sol.sol((r - R[layer]) / L[layer])[2 * layer]
    return p, u


@pytest.mark.parametrize("assumption", ["plane_stress", "plane_strain"])
@pytest.mark.parametrize("case", [
    # (r_in, r_fit, r_out, inner material, outer material, interference_um)
    (5.0, 17.5, 21.0, TI, STEEL, 8.0),          # hollow TC4 shaft in a 9Cr18 ring
    (0.0, 17.5, 21.0, STEEL, STEEL, 5.0),       # solid steel shaft
    (23.5, 27.0, 40.0, STEEL, AL, 12.0),        # steel ring in an aluminium housing
])
def test_two_layer_fit_matches_numerical_equilibrium(case, assumption):
    """Closed form vs solve_bvp of the radial equilibrium ODE: tolerance 1e-6 relative
    (the BVP is solved to 1e-10; the difference is the BVP discretisation)."""
    a, c, b, mi, mo, d = case
    p = fit_pressure_MPa(a, c, b, mi.E_MPa, mi.nu, mo.E_MPa, mo.nu, d, assumption)
    p_num, u_num = bvp_layers([a, c, b], [mi.E_MPa, mo.E_MPa], [mi.nu, mo.nu], [d], assumption)
    assert p == pytest.approx(p_num[0], rel=1e-6)
    for member, layer, r in (("inner", 0, 0.5 * (max(a, 1.0) + c)), ("outer", 1, 0.5 * (c + b)),
                             ("outer", 1, b)):
        u = fit_displacement_mm(r, member, a, c, b, mi.E_MPa, mi.nu, mo.E_MPa, mo.nu, d, assumption)
        assert u == pytest.approx(u_num(layer, r), rel=1e-6)


def test_compatibility_traction_and_free_surfaces():
    """u_outer - u_inner at the fit = delta/2 (to round-off); sigma_rr continuous (= -p) at the
    fit and zero on the bore and the outside: identities of the solution."""
    a, c, b, d = 6.0, 17.5, 21.0, 7.0
    st = fit_state(a, c, b, TI.E_MPa, TI.nu, STEEL.E_MPa, STEEL.nu, d)
    p = float(st.fit_pressure_MPa)
    assert p > 0
    assert (st.u_outer_at_fit_mm - st.u_inner_at_fit_mm) * 1e3 == pytest.approx(d / 2, rel=1e-12)
    assert radial_stress_MPa(c, a, c, 0.0, p) == pytest.approx(-p, rel=1e-12)
    assert radial_stress_MPa(c, c, b, p, 0.0) == pytest.approx(-p, rel=1e-12)
    assert abs(radial_stress_MPa(a, a, c, 0.0, p)) < 1e-12 * p
    assert abs(radial_stress_MPa(b, c, b, p, 0.0)) < 1e-12 * p
    # equilibrium of the outer ring: integral of hoop stress over the wall = p * c (per unit width)
    r = np.linspace(c, b, 20001)
    assert np.trapezoid(hoop_stress_MPa(r, c, b, p, 0.0), r) == pytest.approx(p * c, rel=1e-7)


def test_open_fit_has_zero_pressure_and_no_displacement():
    for d in (-1.5, 0.0):
        st = fit_state(0.0, 23.5, 27.0, STEEL.E_MPa, STEEL.nu, TI.E_MPa, TI.nu, d)
        assert st.fit_pressure_MPa == 0.0 and bool(st.is_open)
        assert st.u_inner_at_fit_mm == 0.0 and st.u_outer_at_fit_mm == 0.0


def test_pressure_is_linear_in_interference_and_vectorised():
    d = np.array([-2.0, 0.0, 2.0, 4.0, 8.0])
    p = fit_pressure_MPa(0.0, 17.5, 21.0, STEEL.E_MPa, STEEL.nu, STEEL.E_MPa, STEEL.nu, d)
    assert p.shape == d.shape
    assert p[0] == 0 and p[1] == 0
    assert p[3] == pytest.approx(2 * p[2], rel=1e-14) and p[4] == pytest.approx(4 * p[2], rel=1e-14)


def test_thin_ring_on_rigid_shaft_limit():
    """Thin ring (wall t << r) on a rigid shaft: hoop stress p r / t = E delta_r / r, i.e.
    p = 2 E t delta_d / d^2 (membrane theory). The Lamé result differs by O(t/r): the relative
    error is checked to shrink proportionally with t."""
    c, d_um, E, nu = 20.0, 10.0, 200e3, 0.3
    errs = []
    for t in (0.2, 0.02, 0.002):
        p = fit_pressure_MPa(0.0, c, c + t, 1e15, 0.3, E, nu, d_um)
        p_thin = 2 * E * t * (d_um * 1e-3) / (2 * c) ** 2
        errs.append(abs(p / p_thin - 1))
    assert errs[2] < 2 * 0.002 / c
    assert errs[0] / errs[1] == pytest.approx(10, rel=0.05)


def test_rigid_shaft_limit_is_outer_ring_compliance_only():
    """Rigid shaft: p = (delta_d/2) E_o / (c ((b^2+c^2)/(b^2-c^2) + nu_o)) (Lamé, Timoshenko §28)."""
    c, b, d = 17.5, 21.0, 6.0
    p = fit_pressure_MPa(0.0, c, b, 1e18, 0.3, STEEL.E_MPa, STEEL.nu, d)
    p_ref = 0.5e-3 * d * STEEL.E_MPa / (c * ((b**2 + c**2) / (b**2 - c**2) + STEEL.nu))
    assert p == pytest.approx(p_ref, rel=1e-9)


def test_solid_shaft_is_the_limit_of_a_vanishing_bore():
    args = (17.5, 21.0, TI.E_MPa, TI.nu, STEEL.E_MPa, STEEL.nu, 5.0)
    p0 = fit_pressure_MPa(0.0, *args)
    assert fit_pressure_MPa(1e-4, *args) == pytest.approx(p0, rel=1e-7)


def test_plane_strain_substitution_reproduces_lame_constants():
    """Plane-stress formulas with E' = E/(1-nu^2), nu' = nu/(1-nu) must give the plane-strain
    stiffness lambda + 2 mu and lambda (identity, any E, nu)."""
    for E, nu in ((200e3, 0.3), (113.8e3, 0.342), (310e3, 0.27)):
        Ep, vp = effective_elastic(E, nu, "plane_strain")
        C11_ps, C12_ps = stiffness(Ep, vp, "plane_stress")
        C11, C12 = stiffness(E, nu, "plane_strain")
        assert C11_ps == pytest.approx(C11, rel=1e-13) and C12_ps == pytest.approx(C12, rel=1e-13)


def test_plane_strain_is_stiffer_than_plane_stress():
    args = (0.0, 17.5, 21.0, TI.E_MPa, TI.nu, STEEL.E_MPa, STEEL.nu, 5.0)
    assert fit_pressure_MPa(*args, assumption="plane_strain") > fit_pressure_MPa(*args)
    with pytest.raises(ValueError):
        fit_pressure_MPa(*args, assumption="plane_strian")


def test_verify_contract_keyword_names():
    """`bearingfem verify` echoes these exact names; the closed form must accept them."""
    inputs = dict(r_inner_mm=0.0, r_fit_mm=17.5, r_outer_mm=21.0, E_inner_MPa=113.8e3,
                  nu_inner=0.342, E_outer_MPa=200e3, nu_outer=0.3, interference_um=5.0,
                  assumption="plane_stress")
    assert fit_pressure_MPa(**inputs) > 0


@pytest.mark.requirement("R-SEED000-FITS")
def test_seed000_fit_change_rates():
    """Seed 000 quotes -0.05 um/C (inner: TC4 shaft in 9Cr18 ring, 35 mm) and +0.07 um/C (outer:
    9Cr18 ring in TC4 housing, 47 mm); the numbers are given to one significant digit, hence the
    0.005 um/C tolerance."""
    T = np.array([19.5, 20.5])
    di = interference_at_temperature_um(5.0, 35.0, TI, STEEL, T, 20.0)
    do = interference_at_temperature_um(-1.5, 47.0, STEEL, TI, T, 20.0)
    assert np.diff(di)[0] == pytest.approx(-0.05, abs=0.005)
    assert np.diff(do)[0] == pytest.approx(0.07, abs=0.005)
    # same materials: no change at any temperature
    same = interference_at_temperature_um(5.0, 35.0, STEEL, STEEL, np.array([-60.0, 80.0]), 20.0)
    assert np.allclose(same, 5.0, rtol=0, atol=1e-12)


@pytest.mark.requirement("R-SEED000-FITS")
def test_outer_fit_of_seed000_closes_on_heating():
    """-1.5 um clearance closes where 1.5 um = 1.5e-6/K * 47 mm * (T - 20 C), i.e. near 41 C
    (TC4's CTE slope moves it by about 2 K): open at 20 and 35 C, closed at
    45 and 80 C."""
    T = np.array([20.0, 35.0, 45.0, 80.0])
    d = interference_at_temperature_um(-1.5, 47.0, STEEL, TI, T, 20.0)
    p = fit_pressure_MPa(20.0, 23.5, 35.0, STEEL.E_MPa, STEEL.nu, TI.E_MPa, TI.nu, d)
    assert list(p > 0) == [False, False, True, True]


@pytest.mark.parametrize("assumption", ["plane_stress", "plane_strain"])
def test_three_layer_stack_matches_numerical_equilibrium(assumption):
    """Hollow TC4 shaft / 9Cr18 ring / 2A12 housing, both fits closed: pressures and
    displacements vs solve_bvp (1e-6 relative)."""
    radii = [4.0, 12.5, 16.0, 30.0]
    E = [TI.E_MPa, STEEL.E_MPa, AL.E_MPa]
    nu = [TI.nu, STEEL.nu, AL.nu]
    d = [6.0, 10.0]
    fit = multilayer_fit(radii, E, nu, d, assumption)
    assert fit.closed.all()
    p_num, u_num = bvp_layers(radii, E, nu, d, assumption)
    assert fit.pressures_MPa == pytest.approx(p_num, rel=1e-6)
    for layer, r in ((0, 8.0), (1, 14.0), (2, 30.0)):
        assert fit.displacement_mm(layer, r) == pytest.approx(u_num(layer, r), rel=1e-6)
    # compatibility at both interfaces and free outer surface (identities)
    for i in (1, 2):
        du = fit.displacement_mm(i, radii[i]) - fit.displacement_mm(i - 1, radii[i])
        assert du * 1e3 == pytest.approx(d[i - 1] / 2, rel=1e-10)
    assert abs(fit.stress_rr_MPa(2, 30.0)) < 1e-10 * fit.pressures_MPa.max()


def test_three_layer_sharing_raises_each_pressure_and_reduces_to_two_layer_when_open():
    """With the outer fit open (clearance), the inner fit is the two-member fit; closing the outer
    fit squeezes the shared ring, raising the inner pressure (superposition of Lamé solutions)."""
    radii, E, nu = [0.0, 12.5, 16.0, 30.0], [STEEL.E_MPa] * 3, [0.3] * 3
    open_ = multilayer_fit(radii, E, nu, [6.0, -6.0])
    assert list(open_.closed) == [True, False]
    p2 = fit_pressure_MPa(0.0, 12.5, 16.0, STEEL.E_MPa, 0.3, STEEL.E_MPa, 0.3, 6.0)
    assert open_.pressures_MPa[0] == pytest.approx(p2, rel=1e-12)
    assert open_.pressures_MPa[1] == 0.0
    # remaining diametral gap = clearance - ring's outer expansion from the inner fit
    u_ring_out = radial_displacement_mm(16.0, 12.5, 16.0, STEEL.E_MPa, 0.3, p2, 0.0)
    assert open_.gap_um[1] == pytest.approx(6.0 - 2e3 * u_ring_out, rel=1e-10)
    closed = multilayer_fit(radii, E, nu, [6.0, 3.0])
    assert closed.closed.all() and closed.pressures_MPa[0] > p2


def test_three_layer_clearance_smaller_than_ring_growth_closes():
    """Outer clearance smaller than the ring's expansion from the inner fit: the outer fit
    closes (the open assumption would violate the no-overlap condition)."""
    radii, E, nu = [0.0, 12.5, 16.0, 30.0], [STEEL.E_MPa] * 3, [0.3] * 3
    p2 = fit_pressure_MPa(0.0, 12.5, 16.0, STEEL.E_MPa, 0.3, STEEL.E_MPa, 0.3, 6.0)
    growth_um = 2e3 * radial_displacement_mm(16.0, 12.5, 16.0, STEEL.E_MPa, 0.3, p2, 0.0)
    fit = multilayer_fit(radii, E, nu, [6.0, -0.5 * growth_um])
    assert fit.closed.all() and fit.pressures_MPa[1] > 0
