"""Pair under combined axial and radial load (`bearing.solve_pair(radial_load_N=...)`, the
quasi-static load distribution around the ball set, Harris & Kotzalas Vol. 1 ch. 7, Jones 1960).

Checked against: the axial-only solver (radial load zero: identical outputs; tiny radial load:
continuous), the radial ball bearing limits (alpha0 = 0: zero clearance, Stribeck's 4.37 and
Sjovall's J_r(0.5) = 0.2288; a bearing held at zero contact angle with its free clearance: Sjovall's
integral J_r(epsilon) by quadrature), the equilibrium equations evaluated ball by ball with K_n
rebuilt from the Hertz primitives (independent of bearing.py's solver), finite differences of the
stiffnesses (through the solver and through a direct force evaluation), and the symmetries of the
ball set (mirror about the load direction, load reversal for an even ball count)."""
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import gamma

from analytic.bearing import (BearingGeometry, SIGNS, ball_azimuths_rad, solve_pair,
                              thermal_geometry)
from bearing_reference import flat, kn_direct


def solve(*args, **kwargs):
    """`bearing.solve_pair`, every array of its state under one name (`bearing_reference.flat`)."""
    return flat(solve_pair(*args, **kwargs))


G = BearingGeometry.from_catalogue("71807C")          # Z = 24, alpha0 = 15 deg


def ball_loads_direct(g, approach, rho, dr=0.0, tg=None):
    """Ball loads of one bearing written out from the model statement (issue/brief):
    X = A0 sin a0 + a, Y = A0 cos a0 + dr + rho cos psi_k, delta = |(X, Y)| - A_T,
    Q = K_n(alpha) delta^1.5.  Returns (Q, alpha, psi), each (Z,)."""
    a0 = np.radians(g.alpha0_deg)
    psi = 2 * np.pi * np.arange(g.Z) / g.Z
    X = g.A0_mm * np.sin(a0) + approach + 0 * psi
    Y = g.A0_mm * np.cos(a0) + dr + rho * np.cos(psi)
    alpha = np.arctan2(X, Y)
    if tg is None:
        A_T, kw = g.A0_mm, {}
    else:
        A_T, kw = tg.A_T_mm, dict(Dw=tg.Dw_mm, dm=tg.dm_mm, f_i=tg.f_i, f_o=tg.f_o)
    delta = np.maximum(np.hypot(X, Y) - A_T, 0.0)
    return kn_direct(g, alpha, **kw) * delta ** 1.5, alpha, psi


def pair_forces_direct(g, s, x, rho, e, dz, dr):
    """(external axial load, external radial load) balanced by the rigid pair at rotor position
    (x, rho) under position preload without compliance: a_j = s_j (dz_j + x) + e."""
    Fa = Fr = 0.0
    for j in range(2):
        Q, alpha, psi = ball_loads_direct(g, s[j] * (dz[j] + x) + e, rho, dr[j])
        Fa += s[j] * np.sum(Q * np.sin(alpha))
        Fr += np.sum(Q * np.cos(alpha) * np.cos(psi))
    return Fa, Fr


# ---------------------------------------------------------------------------------------------
# (1) radial load zero: the axial-only solver, exactly
CASES = [dict(arrangement="DB", preload_assembled_N=120.0, axial_load_N=[-80.0, 0.0, 150.0, 2000.0]),
         dict(arrangement="DF", preload_assembled_N=90.0, axial_load_N=[30.0, -300.0],
              dr_mm=np.array([[4e-4], [-2e-4]]), dz_mm=np.array([[1e-4], [-3e-4]]),
              T_inner_ring_C=[45.0, 60.0], T_ball_C=40.0),
         dict(arrangement="DB", preload_assembled_N=100.0, axial_load_N=[0.0, 250.0],
              compliance_mm_per_N=2e-5),
         dict(arrangement="DB", preload_kind="spring", preload_assembled_N=60.0,
              axial_load_N=[-100.0, 0.0, 40.0], dr_mm=5e-4)]


@pytest.mark.parametrize("case", CASES)
def test_zero_radial_load_is_the_axial_solver(case):
    """radial_load_N = 0 (scalar or array) returns today's dict (same keys, bit-identical
    values); with return_ball_loads the old keys stay bit-identical, rho = 0 and every ball
    carries the axial solver's ball load; a mixed call leaves its zero-radial points identical."""
    case = dict(case)
    arr = case.pop("arrangement")
    ref = solve(G, arr, **case)
    n = ref["x_mm"].size
    for fr in (0.0, np.zeros(n)):
        out = solve(G, arr, radial_load_N=fr, **case)
        assert list(out) == list(ref)
        for k in ref:
            assert np.array_equal(out[k], ref[k], equal_nan=True), k
    ext = solve(G, arr, return_ball_loads=True, **case)
    for k in ref:
        assert np.array_equal(ext[k], ref[k], equal_nan=True), k
    assert np.all(ext["radial.rho_mm"] == 0.0)
    for j in "AB":
        assert np.allclose(ext[f"radial.ball_loads_N[{j}]"], ref[f"ball_load_N[{j}]"], rtol=1e-12, atol=0)
        assert np.array_equal(ext[f"radial.max_ball_load_N[{j}]"], np.max(ext[f"radial.ball_loads_N[{j}]"], axis=0))
        assert np.array_equal(ext[f"radial.loaded_zone[{j}]"], (ref[f"ball_load_N[{j}]"] > 0).astype(float))
    fr = np.zeros(n)
    fr[0] = 300.0
    mixed = solve(G, arr, radial_load_N=fr, **case)
    for k in ref:
        assert np.array_equal(mixed[k][1:], ref[k][1:], equal_nan=True), k
    assert mixed["radial.rho_mm"][0] > 0 and np.all(mixed["radial.rho_mm"][1:] == 0)


def test_tiny_radial_load_is_continuous_with_the_axial_solver():
    """A radial load of 1e-6 N moves the solution by O(1e-6 N / k_r): the outputs agree with the
    axial-only solver to 1e-8 relative (the path change itself is invisible)."""
    kw = dict(preload_assembled_N=100.0, axial_load_N=[-60.0, 0.0, 80.0], dr_mm=3e-4, T_ball_C=35.0)
    ref = solve(G, "DB", **kw)
    out = solve(G, "DB", radial_load_N=1e-6, **kw)
    for k in ("preload_N", "axial_force_N[A]", "axial_force_N[B]", "contact_angle_deg[A]",
              "ball_load_N[A]", "ball_load_N[B]", "inner.p_max_MPa[A]", "x_mm",
              "pair_axial_stiffness_N_per_um", "axial_stiffness_N_per_um[A]"):
        assert np.allclose(out[k], ref[k], rtol=1e-8, atol=1e-12), k
    assert np.all(out["radial.loaded_zone[A]"] == 1.0)


# ---------------------------------------------------------------------------------------------
# (2) radial ball bearing limits
SJOVALL_JR_HALF = 0.2288    # Sjovall (1933) radial integral J_r(epsilon = 0.5), Harris & Kotzalas Vol. 1 ch. 7
STRIBECK = 4.37             # Stribeck: Q_max = 4.37 Fr / (Z cos a), zero clearance (same chapter; = 1/J_r(0.5))


def sjovall_jr(eps):
    """J_r(eps) = (1/2pi) int [1 - (1 - cos psi)/(2 eps)]^1.5 cos psi dpsi over the loaded zone
    (Sjovall 1933; Harris & Kotzalas Vol. 1 ch. 7), by adaptive quadrature."""
    lim = np.arccos(1 - 2 * eps) if eps < 1 else np.pi
    f = lambda p: max(1 - (1 - np.cos(p)) / (2 * eps), 0.0) ** 1.5 * np.cos(p)
    return quad(f, -lim, lim, epsabs=1e-13, epsrel=1e-12, limit=200)[0] / (2 * np.pi)


def test_sjovall_reference_values():
    """The quadrature and the closed form at eps = 0.5, (1/2pi) sqrt(pi) Gamma(7/4)/Gamma(9/4)
    (int_0^{pi/2} cos^n = sqrt(pi) Gamma((n+1)/2) / (2 Gamma(n/2+1)), n = 2.5), against the
    published 4-digit values."""
    closed = gamma(1.75) / gamma(2.25) / (2 * np.sqrt(np.pi))
    assert sjovall_jr(0.5) == pytest.approx(closed, rel=1e-10)
    assert closed == pytest.approx(SJOVALL_JR_HALF, abs=5e-5)
    assert 1 / closed == pytest.approx(STRIBECK, abs=5e-3)


def test_zero_clearance_radial_bearing_stribeck():
    """alpha0 = 0 is the zero-clearance radial ball bearing (free radial clearance
    A0 (1 - cos a0) = 0).  Without preload and axial load both bearings sit at zero contact angle
    and share Fr equally; with rigid rings delta_k = rho cos psi_k (Harris Vol. 1 ch. 7), so
    exactly  Q_k = Q_max cos^1.5 psi_k,  Fr/2 = Q_max sum_{cos psi_k > 0} cos^2.5 psi_k,
    Q_max = K_n(0) rho^1.5.  Z Q_max / (Fr/2) is the discrete Stribeck number (4.3696 for
    Z = 24, -> 1/J_r(0.5) = 4.3701 as Z grows); half the balls (11 of 24: those at +-90 deg touch
    with zero load) are loaded."""
    g = BearingGeometry(**{**G.__dict__, "alpha0_deg": 0.0})
    Fr = np.array([20.0, 500.0, 4000.0])
    out = solve(g, "DB", preload_assembled_N=0.0, radial_load_N=Fr, return_ball_loads=True)
    psi = ball_azimuths_rad(g.Z)
    cpos = np.clip(np.cos(psi), 0.0, None)
    S = np.sum(cpos ** 2.5)
    for j in "AB":
        Q = out[f"radial.ball_loads_N[{j}]"]
        assert np.allclose(out[f"radial.radial_force_N[{j}]"], Fr / 2, rtol=1e-12)
        assert np.allclose(out[f"radial.max_ball_load_N[{j}]"], Fr / 2 / S, rtol=1e-9)
        assert np.allclose(Q, out[f"radial.max_ball_load_N[{j}]"] * cpos[:, None] ** 1.5, rtol=0,
                           atol=1e-9 * Fr.max())
        # A_T = r_i + r_o - Dw and A0 = (f_i + f_o - 1) Dw differ by rounding: the balls touch at
        # X = sqrt(A_T^2 - A0^2) ~ 1e-8 mm, i.e. a contact angle of a few 1e-6 deg (cos = 1 - 1e-15)
        assert np.allclose(out[f"radial.ball_contact_angles_deg[{j}]"], 0.0, atol=1e-4)
        assert np.all(out[f"radial.loaded_zone[{j}]"] == 11 / 24)
    assert np.allclose(out["radial.max_ball_load_N[A]"], kn_direct(g, 0.0) * out["radial.rho_mm"] ** 1.5, rtol=1e-9)
    stribeck = g.Z * out["radial.max_ball_load_N[A]"] / (Fr / 2)
    assert np.allclose(stribeck, g.Z / S, rtol=1e-9)
    assert np.allclose(stribeck, STRIBECK, atol=5e-3)
    assert np.allclose(stribeck, 1 / SJOVALL_JR_HALF, rtol=2e-3)      # Z = 24 vs the continuum


@pytest.mark.parametrize("Fr", [30.0, 300.0, 3000.0])
def test_radial_bearing_with_clearance_sjovall(Fr):
    """A spring-preloaded pair with zero spring force and no axial load holds both bearings at zero
    axial force; the symmetric solution is X = 0 (contact angle 0): each bearing is a radial ball
    bearing with the free radial clearance Pd/2 = A0 (1 - cos a0) (Harris Vol. 1 ch. 2).  Then
    delta_max = rho - Pd/2, the load distribution factor is eps = (1/2)(1 - Pd/(2 rho)), and
    Fr/2 = Z Q_max J_r(eps) (Sjovall; Harris Vol. 1 ch. 7) in the continuum limit, taken here with
    Z = 720 balls: the ball sum equals Z Q_max J_r(eps) up to the Riemann-sum error of the kink at
    the zone edge, ~ (ball spacing / loaded half-arc)^2.5 (< 1e-4 here).  The discrete form of the
    same sum, sum_k Q_max [1 - (1 - cos psi_k)/(2 eps)]_+^1.5 cos psi_k = Fr/2, holds to 1e-9."""
    g = BearingGeometry(**{**G.__dict__, "Z": 720})
    out = solve(g, "DB", preload_kind="spring", preload_assembled_N=0.0, radial_load_N=Fr,
                     return_ball_loads=True)
    half_pd = g.radial_clearance_mm
    rho = out["radial.rho_mm"][0]
    assert rho > half_pd
    assert np.allclose(out["radial.ball_contact_angles_deg[A]"], 0.0, atol=1e-9)
    Qmax = out["radial.max_ball_load_N[A]"][0]
    assert Qmax == pytest.approx(float(kn_direct(g, 0.0)) * (rho - half_pd) ** 1.5, rel=1e-9)
    eps = 0.5 * (1 - half_pd / rho)
    psi = ball_azimuths_rad(g.Z)
    shape = np.clip(1 - (1 - np.cos(psi)) / (2 * eps), 0.0, None) ** 1.5
    assert Qmax * np.sum(shape * np.cos(psi)) == pytest.approx(Fr / 2, rel=1e-9)
    assert np.allclose(out["radial.ball_loads_N[A]"][:, 0], Qmax * shape, rtol=0, atol=1e-9 * Qmax)
    assert Fr / 2 / (g.Z * Qmax) == pytest.approx(sjovall_jr(eps), rel=1e-4)
    # loaded arc 2 psi_l with cos psi_l = Pd / (2 rho) (Harris Vol. 1 ch. 7)
    psi_l = np.arccos(half_pd / rho)
    assert out["radial.loaded_zone[A]"][0] == pytest.approx(psi_l / np.pi, abs=2 / g.Z)


# ---------------------------------------------------------------------------------------------
# (3) equilibrium, ball by ball, from the model statement
EQ_CASES = [("DB", "position", 0.0, None), ("DF", "position", 0.0, None),
            ("DB", "position", 1.5e-5, None), ("DB", "spring", 0.0, None),
            ("DB", "position", 0.0, (55.0, 35.0, 45.0))]


@pytest.mark.parametrize("arrangement,kind,c,temps", EQ_CASES)
def test_equilibrium_residuals(arrangement, kind, c, temps):
    """Ball loads recomputed from the solver's a_j and rho with K_n from the Hertz primitives
    (`ball_loads_direct`): they equal the reported ones, and sum_j s_j sum_k Q sin a = Fa,
    sum_j sum_k Q cos a cos psi = Fr to 1e-9 of the load scale; the preload path closes
    (a_j + c F_j = s_j (dz_j + x) + e, or F_B = P and F_A = s_A Fa + P for the spring)."""
    s = SIGNS[arrangement]
    dr = np.array([[3e-4], [-2e-4]])
    dz = np.array([[2e-4], [-4e-4]])
    Fa = np.array([0.0, 120.0, -90.0, 40.0, 600.0])
    Fr = np.array([50.0, 400.0, 1500.0, 3000.0, 200.0])
    kw = dict(preload_kind=kind, preload_assembled_N=110.0, axial_load_N=Fa, radial_load_N=Fr,
              dr_mm=dr, dz_mm=dz, compliance_mm_per_N=c)
    tg = None
    if temps is not None:
        kw.update(T_inner_ring_C=temps[0], T_outer_ring_C=temps[1], T_ball_C=temps[2])
        tg = thermal_geometry(G, *temps, 20.0)
    out = solve(G, arrangement, return_ball_loads=True, **kw)
    for i in range(Fa.size):
        sumA = sumR = 0.0
        F = []
        for j, name in enumerate("AB"):
            Q, alpha, psi = ball_loads_direct(G, out[f"approach_mm[{name}]"][i], out["radial.rho_mm"][i],
                                              dr[j, 0], tg)
            scale = max(abs(Fa[i]), Fr[i], 110.0)
            assert np.allclose(out[f"radial.ball_loads_N[{name}]"][:, i], Q, rtol=1e-9, atol=1e-12 * scale)
            sumA += s[j] * np.sum(Q * np.sin(alpha))
            sumR += np.sum(Q * np.cos(alpha) * np.cos(psi))
            F.append(np.sum(Q * np.sin(alpha)))
        if not (kind == "spring" and 110.0 + s[0] * Fa[i] < 0):
            assert abs(sumA - Fa[i]) <= 1e-9 * scale
        assert abs(sumR - Fr[i]) <= 1e-9 * scale
        if kind == "position":
            e, x = out["preload_offset_mm"][i], out["x_mm"][i]
            for j, name in enumerate("AB"):
                nominal = s[j] * (dz[j, 0] + x) + e
                assert out[f"approach_mm[{name}]"][i] + c * F[j] == pytest.approx(
                    nominal, abs=1e-9 * c * scale + 1e-15)
        else:
            assert F[1] == pytest.approx(110.0, rel=1e-9)
            assert F[0] == pytest.approx(110.0 + s[0] * Fa[i], rel=1e-9)


# ---------------------------------------------------------------------------------------------
# (4) stiffness
@pytest.mark.parametrize("kind,c", [("position", 0.0), ("position", 1e-5), ("spring", 0.0)])
def test_stiffness_matches_solver_finite_difference(kind, c):
    """dFr/drho at constant axial load (central difference of the solved rho over Fr +- h) and
    dFa/dx at constant radial load equal the reported radial and pair axial stiffnesses."""
    kw = dict(preload_kind=kind, preload_assembled_N=150.0, compliance_mm_per_N=c, dr_mm=4e-4,
              dz_mm=np.array([[2e-4], [-1e-4]]), T_ball_C=40.0)
    for Fr0, Fa0 in ((300.0, 50.0), (2500.0, -30.0)):
        h = 1e-2
        out = solve(G, "DB", radial_load_N=[Fr0 - h, Fr0, Fr0 + h, Fr0, Fr0],
                         axial_load_N=[Fa0, Fa0, Fa0, Fa0 - h, Fa0 + h], **kw)
        kr = 2 * h / (out["radial.rho_mm"][2] - out["radial.rho_mm"][0]) * 1e-3
        ka = 2 * h / (out["x_mm"][4] - out["x_mm"][3]) * 1e-3
        assert out["radial.radial_stiffness_N_per_um"][1] == pytest.approx(kr, rel=1e-6)
        assert out["pair_axial_stiffness_N_per_um"][1] == pytest.approx(ka, rel=1e-6)


def test_radial_stiffness_against_direct_perturbation():
    """Independent route: perturb the rotor position (x, rho) about the solution, evaluate the
    forces directly from the geometry (`pair_forces_direct`, K_n from the Hertz primitives), form
    the 2x2 stiffness matrix by central differences and condense x at constant axial load:
    k_r = K_rr - K_rx K_xr / K_xx.  Also K_rr alone (x held) against the fixed-x solve."""
    s = SIGNS["DB"]
    dr, dz = np.array([3e-4, -1e-4]), np.array([1e-4, -2e-4])
    out = solve(G, "DB", preload_assembled_N=120.0, axial_load_N=80.0,
                     radial_load_N=[200.0, 1200.0, 4000.0], dr_mm=dr[:, None], dz_mm=dz[:, None])
    e = out["preload_offset_mm"][0]
    h = 1e-7
    for i in range(3):
        x, rho = out["x_mm"][i], out["radial.rho_mm"][i]
        fa0, fr0 = pair_forces_direct(G, s, x, rho, e, dz, dr)
        assert fa0 == pytest.approx(80.0, rel=1e-9)
        assert fr0 == pytest.approx([200.0, 1200.0, 4000.0][i], rel=1e-9)
        Kxx, Krx = (np.subtract(pair_forces_direct(G, s, x + h, rho, e, dz, dr),
                                pair_forces_direct(G, s, x - h, rho, e, dz, dr)) / (2 * h))
        Kxr, Krr = (np.subtract(pair_forces_direct(G, s, x, rho + h, e, dz, dr),
                                pair_forces_direct(G, s, x, rho - h, e, dz, dr)) / (2 * h))
        kr = (Krr - Krx * Kxr / Kxx) * 1e-3
        assert out["radial.radial_stiffness_N_per_um"][i] == pytest.approx(kr, rel=1e-6)
        assert Krx == pytest.approx(Kxr, rel=1e-3)      # K_n(alpha) makes it only nearly symmetric
        assert out["pair_axial_stiffness_N_per_um"][i] == pytest.approx((Kxx - Kxr * Krx / Krr) * 1e-3, rel=1e-6)


# ---------------------------------------------------------------------------------------------
# (5) symmetry of the load distribution
@pytest.mark.parametrize("Z", [24, 13])
def test_load_distribution_symmetric_about_load_direction(Z):
    """Ball k at psi_k and ball Z - k at -psi_k see the same geometry: Q_k = Q_(Z-k) (to rounding),
    and the largest load sits on ball 0 (psi = 0).  Even Z: reversing the radial load turns the
    distribution by half a turn, Q_k(-Fr) = Q_(k + Z/2)(Fr), and rho changes sign; odd Z has no
    ball at psi = 180 deg: the two balls next to it share the largest load."""
    g = BearingGeometry(**{**G.__dict__, "Z": Z})
    Fr = np.array([100.0, 1000.0, 5000.0])
    kw = dict(preload_assembled_N=100.0, axial_load_N=[30.0, -120.0, 500.0], return_ball_loads=True)
    out = solve(g, "DB", radial_load_N=Fr, **kw)
    k = np.arange(Z)
    for j in "AB":
        Q = out[f"radial.ball_loads_N[{j}]"]
        tol = 1e-12 * Q.max(axis=0)
        assert np.all(np.abs(Q - Q[(Z - k) % Z]) <= tol)
        assert np.all(np.argmax(Q, axis=0) == 0)
        assert np.all(np.diff(Q[: Z // 2 + 1], axis=0) <= tol)      # decreasing from psi = 0 to 180 deg
    rev = solve(g, "DB", radial_load_N=-Fr, **kw)
    if Z % 2 == 0:
        assert np.allclose(rev["radial.rho_mm"], -out["radial.rho_mm"], rtol=1e-12)
        for j in "AB":
            Q = out[f"radial.ball_loads_N[{j}]"]
            assert np.allclose(rev[f"radial.ball_loads_N[{j}]"], Q[(k + Z // 2) % Z], rtol=0,
                               atol=1e-12 * Q.max())
    else:
        assert np.all(rev["radial.rho_mm"] < 0)
        for j in "AB":
            Q = rev[f"radial.ball_loads_N[{j}]"]
            tol = 1e-12 * Q.max(axis=0)
            assert np.all(np.abs(Q - Q[(Z - k) % Z]) <= tol)
            assert np.allclose(Q.max(axis=0), Q[Z // 2], rtol=1e-12)


def test_chunked_combined_equals_one_block():
    rng = np.random.default_rng(5)
    N = 7
    kw = dict(dr_mm=rng.uniform(-1e-3, 1e-3, (2, N)), dz_mm=rng.uniform(-2e-3, 2e-3, (2, N)),
              T_inner_ring_C=rng.uniform(-40, 60, N), axial_load_N=rng.uniform(-200, 200, N),
              radial_load_N=np.where(np.arange(N) % 3 == 0, 0.0, rng.uniform(10, 3000, N)),
              preload_assembled_N=100.0, return_ball_loads=True)
    one = solve(G, "DB", **kw)
    many = solve(G, "DB", chunk=3, **kw)
    assert list(one) == list(many)
    for k, v in one.items():
        # Round-off is relative to the largest term of the same output over the rows (a force
        # that is zero in one row is ~1e-14 N next to a 1e3 N force in another).
        scale = np.nanmax(np.abs(v)) if np.any(np.isfinite(v)) else 0.0
        assert np.allclose(many[k], v, rtol=1e-12, atol=1e-12 * scale, equal_nan=True), k
