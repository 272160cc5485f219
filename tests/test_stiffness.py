"""The pair's tangent stiffness at its equilibrium (`analytic.bearing.stiffness`).

Requirements proved here, each against something independent of the analytic tangent:
- R1 central finite differences of the equilibrium force (the balls solved afresh at displaced
  rotor positions, quasi-static and quasi-dynamic, rigid / compliant / spring preload paths, DB
  and DF) to 1e-6 of sqrt(K_ii K_jj);
- R2 the loads the balls carry at the reconstructed equilibrium are the applied loads;
- R3 Harris's axial-load equation differentiated (contact-angle change included) for a single
  bearing under axial preload, and the equal-ball-load radial and tilting stiffness, to 1e-4,
  with K_n from the textbook Hertz formulas written out in this file (`harris_contact_constant`,
  nothing of the code's contact model);
  springs in series / in parallel for the pair's axial stiffness;
- R4 the pair solvers' own stiffness outputs (axial.py's dF/dx, combined.py's condensed radial
  and tilting stiffness): a second implementation, one plane, other unknowns;
- R5 the quasi-dynamic tangent at speed 0 equals the quasi-static one (two derivations: implicit
  function through the ball's own equilibrium vs. the series K_n law).
"""
import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from analytic.bearing import BearingGeometry, solve_pair
from analytic.bearing.stiffness import (bearing_tangents, condense, generalised_loads,
                                        pair_balls, pair_stiffness)

G = BearingGeometry.from_catalogue("71807C")     # Z = 24, alpha0 = 15 deg, dm 41 mm
SPAN = 14.0

#: three points: axial only, radial + axial load, radial + axial load + moment (shafts tilt)
LOADS = dict(axial_load_N=np.array([0.0, 50.0, 30.0]), radial_load_N=np.array([0.0, 300.0, 100.0]),
             moment_Nmm=np.array([0.0, 0.0, 2000.0]))
#: FE-like inputs: groove-centre shifts of A and B, ring and ball temperatures
SHIFTS = dict(dr_mm=np.array([[0.002], [0.001]]), dz_mm=np.array([[0.0005], [-0.0003]]),
              T_inner_ring_C=40.0, T_outer_ring_C=30.0, T_ball_C=35.0)


def case(ball_model="static", c=0.0, kind="position", arrangement="DB", speed=12000.0,
         control="outer"):
    args = dict(SHIFTS, **LOADS, preload_assembled_N=200.0, bearing_span_mm=SPAN,
                compliance_mm_per_N=c, preload_kind=kind, ball_model=ball_model,
                speed_rpm=speed if ball_model == "quasi_dynamic" else 0.0, control=control)
    st = solve_pair(G, arrangement, **args)
    assert st.converged.all()
    return st, args


def fd_tangent(balls, frame, h_mm):
    """Central differences of `generalised_loads` in (x, y, z, theta_x, theta_y, w), (2, N, 6, 6);
    rotations stepped by h / R_i so that every step moves a groove centre by about h."""
    N = balls.n_points
    steps = np.array([h_mm] * 3 + [h_mm / float(balls.R_i_mm.max())] * 2 + [h_mm])
    out = np.zeros((2, N, 6, 6))
    for d in range(6):
        F = []
        for sgn in (1.0, -1.0):
            q, w = np.zeros((5, N)), np.zeros((2, N))
            if d < 5:
                q[d] = sgn * steps[d]
            else:
                w[:] = sgn * steps[d]
            F.append(generalised_loads(balls, q, w, frame))
        out[..., :, d] = np.moveaxis((F[0] - F[1]) / (2.0 * steps[d]), 0, -1)
    return out


FD_CASES = [("static", 0.0, "position", "DB", "outer"), ("static", 2e-5, "position", "DB", "outer"),
            ("static", 0.0, "spring", "DB", "outer"), ("static", 0.0, "position", "DF", "outer"),
            ("quasi_dynamic", 0.0, "position", "DB", "outer"),
            ("quasi_dynamic", 2e-5, "position", "DF", "outer"),
            ("quasi_dynamic", 0.0, "spring", "DB", "outer"),
            ("quasi_dynamic", 0.0, "position", "DB", "jones")]


@pytest.mark.parametrize("ball_model,c,kind,arrangement,control", FD_CASES)
def test_R1_tangent_equals_central_differences_of_the_equilibrium_force(ball_model, c, kind,
                                                                       arrangement, control):
    """R1.  Step h = 1e-7 mm (groove-centre motion; rotations h / R_i): the ball deformations
    are ~1e-3 mm, so the truncation error of the central difference is ~(h/delta)^2 = 1e-8 of
    the term, while the ball equilibria at speed (converged to 1e-12 of their forces) add
    ~1e-12 delta / h = 1e-8 (measured: below 1e-9).  Speed 20000 rpm (with Jones's control
    every ball is then under inner-race control).  Each entry against
    1e-6 sqrt(K_ii K_jj) (the dimensionally consistent scale of an off-diagonal entry), both
    frames (pair's centre, each bearing's ball plane), before the condensation of the preload
    path (the condensation is checked in R3/R4)."""
    st, args = case(ball_model, c, kind, arrangement, speed=20000.0, control=control)
    balls = pair_balls(G, arrangement, st, **args)
    for frame in ("pair", "bearing"):
        K = bearing_tangents(balls, frame)
        F = fd_tangent(balls, frame, 1e-7)
        d = np.sqrt(np.abs(np.diagonal(K, axis1=-2, axis2=-1)))
        scale = d[..., :, None] * d[..., None, :]
        assert np.all(np.abs(K - F) <= 1e-6 * scale), (frame, np.max(np.abs(K - F) / scale))


@pytest.mark.parametrize("ball_model", ["static", "quasi_dynamic"])
def test_R2_balls_at_the_reconstructed_equilibrium_carry_the_applied_loads(ball_model):
    """R2.  (F_x, F_y, F_z, M_x, M_y) of the balls about the pair's centre equal (Fr, 0, Fa, 0,
    M) to 1e-10 of the ball loads' sum (the solvers' own residual tolerance)."""
    for c in (0.0, 2e-5):
        st, args = case(ball_model, c)
        k = pair_stiffness(G, "DB", st, **args)
        assert k.converged.all()
        applied = np.stack([LOADS["radial_load_N"], np.zeros(3), LOADS["axial_load_N"],
                            np.zeros(3), LOADS["moment_Nmm"]])
        scale = st.radial.ball_loads_N.sum(axis=(0, 1))
        err = np.abs(k.loads_N_mm - applied)
        err[3:] /= SPAN
        assert np.all(err <= 1e-10 * scale)


# ---------------------------------------------------------------------------------------------
# R3: closed forms for a bearing under pure axial preload (every ball alike)
P_N = 200.0


def harris_contact_constant(alpha, f, race):
    """K of one ball-raceway contact, Q = K delta^1.5 (N/mm^1.5), written out here from the
    textbook (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1): the curvature sum
    and difference of a ball on its groove at contact angle alpha (ch. 2; gamma = Dw cos a / dm,
    upper signs inner raceway)
        Sum rho = (1/Dw) (4 - 1/f +- 2 gamma / (1 -+ gamma)),
        F(rho) = (1/f +- 2 gamma / (1 -+ gamma)) / (4 - 1/f +- 2 gamma / (1 -+ gamma)),
    the ellipticity kappa from F(rho) = [(kappa^2 + 1) E - 2 K] / [(kappa^2 - 1) E] with the
    complete elliptic integrals K, E of the parameter m = 1 - 1/kappa^2 (scipy.special), and
    the Hertz deflection (ch. 6)
        delta* = (2 K / pi) (pi / (2 kappa^2 E))^(1/3),
        delta = delta* (3 Q eta / (2 Sum rho))^(2/3) Sum rho / 2,
        eta = (1 - nu_I^2) / E_I + (1 - nu_II^2) / E_II,
    so K = (2 Sum rho / (3 eta)) (2 / (delta* Sum rho))^1.5 (for steel, Harris's
    2.15e5 Sum rho^-0.5 delta*^-1.5).  The ring and ball moduli are the catalogue's materials."""
    sg = 1.0 if race == "inner" else -1.0
    gam = G.Dw_mm * np.cos(alpha) / G.dm_mm
    c = sg * 2.0 * gam / (1.0 - sg * gam)
    sum_rho = (4.0 - 1.0 / f + c) / G.Dw_mm
    F_rho = (1.0 / f + c) / (4.0 - 1.0 / f + c)

    def ell(kappa):
        m = 1.0 - 1.0 / kappa ** 2
        return ellipk(m), ellipe(m)

    def g(kappa):
        K, E = ell(kappa)
        return ((kappa ** 2 + 1.0) * E - 2.0 * K) / ((kappa ** 2 - 1.0) * E) - F_rho
    kappa = brentq(g, 1.0 + 1e-6, 100.0, xtol=1e-14, rtol=1e-15)
    K, E = ell(kappa)
    d_star = 2.0 * K / np.pi * (np.pi / (2.0 * kappa ** 2 * E)) ** (1.0 / 3.0)
    eta = sum((1.0 - m.nu ** 2) / m.E_MPa for m in (G.ring, G.ball))
    return 2.0 * sum_rho / (3.0 * eta) * (2.0 / (d_star * sum_rho)) ** 1.5


def harris_Kn(alpha):
    """The two contacts of a ball in series, K_n = [K_i^(-2/3) + K_o^(-2/3)]^(-3/2) (Harris &
    Kotzalas Vol. 1 ch. 7), from `harris_contact_constant`."""
    return (harris_contact_constant(alpha, G.f_i, "inner") ** (-2.0 / 3.0)
            + harris_contact_constant(alpha, G.f_o, "outer") ** (-2.0 / 3.0)) ** -1.5


def harris_axial_preload(P):
    """Harris & Kotzalas Vol. 1 ch. 7 (thrust-loaded bearing): Fa = Z K_n A0^1.5 sin a
    (cos a0 / cos a - 1)^1.5, solved for a by brentq (scipy); K_n(a) of `harris_Kn` (the free
    geometry at the reference temperature; nothing of the code's contact model).  Returns
    (alpha, K_n, dlnK_n/dalpha), the last by a central difference of ln K_n (step 1e-6 rad:
    truncation ~1e-12 relative)."""
    a0 = np.radians(G.alpha0_deg)

    def Fa(a):
        return G.Z * harris_Kn(a) * G.A0_mm ** 1.5 * np.sin(a) * (
            np.cos(a0) / np.cos(a) - 1.0) ** 1.5 - P
    a = brentq(Fa, a0 + 1e-9, np.radians(60.0), xtol=1e-15, rtol=1e-15)
    h = 1e-6
    dlnK = (np.log(harris_Kn(a + h)) - np.log(harris_Kn(a - h))) / (2.0 * h)
    return a, float(harris_Kn(a)), float(dlnK)


def axial_stiffness_closed_form(P):
    """K_a = dFa/d(delta_a) with delta_a = A0 sin(a - a0) / cos a (Harris Vol. 1 ch. 7):
    dFa/da = Fa [dlnK_n/da + cot a + 1.5 cos a0 sin a / (cos^2 a (cos a0/cos a - 1))],
    d(delta_a)/da = A0 cos a0 / cos^2 a."""
    a, _, dlnK = harris_axial_preload(P)
    a0 = np.radians(G.alpha0_deg)
    r = np.cos(a0) / np.cos(a) - 1.0
    dF = P * (dlnK + 1.0 / np.tan(a) + 1.5 * np.cos(a0) * np.sin(a) / (np.cos(a) ** 2 * r))
    return dF / (G.A0_mm * np.cos(a0) / np.cos(a) ** 2)


def ball_tangent_closed_form(P):
    """One ball at the preload state: Q = P / (Z sin a), delta = A0 (cos a0/cos a - 1),
    D = A0 + delta; normal stiffness kn = 1.5 K_n delta^0.5 = 1.5 Q / delta, tangential
    kt = Q / D (the contact line turns about the outer groove centre: de Mul, Vree & Maas 1989),
    with dK_n/da: T = kn n n^T + kt (t t^T + dlnK_n/da n t^T), n = (sin a, cos a),
    t = (cos a, -sin a) in (axial, radial)."""
    a, Kn, dlnK = harris_axial_preload(P)
    a0 = np.radians(G.alpha0_deg)
    delta = G.A0_mm * (np.cos(a0) / np.cos(a) - 1.0)
    Q = P / (G.Z * np.sin(a))
    kn, kt = 1.5 * Q / delta, Q / (G.A0_mm + delta)
    n, t = np.array([np.sin(a), np.cos(a)]), np.array([np.cos(a), -np.sin(a)])
    return kn * np.outer(n, n) + kt * (np.outer(t, t) + dlnK * np.outer(n, t))


def preloaded_pair(c=0.0, kind="position"):
    args = dict(preload_assembled_N=P_N, bearing_span_mm=SPAN, compliance_mm_per_N=c,
                preload_kind=kind)
    st = solve_pair(G, "DB", **args)
    return pair_stiffness(G, "DB", st, **args)


def test_R3_single_bearing_axial_stiffness_is_harris_differentiated():
    """R3.  Each bearing of a position-preloaded pair (no shifts, T_ref) is a single bearing
    under the axial preload P: its k_zz equals K_a of Harris's equation to 1e-4 (measured
    ~1e-12); the pair: both in parallel, 2 K_a; with a preload-path compliance c per bearing,
    springs in series, 2 / (1/K_a + c); spring preload: bearing A alone (B floats), K_a."""
    Ka = axial_stiffness_closed_form(P_N)
    k = preloaded_pair()
    assert np.allclose(k.bearing_N_mm_rad[:, 0, 2, 2], Ka, rtol=1e-4)
    assert np.isclose(k.pair_N_mm_rad[0, 2, 2], 2.0 * Ka, rtol=1e-4)
    c = 1e-5
    assert np.isclose(preloaded_pair(c).pair_N_mm_rad[0, 2, 2], 2.0 / (1.0 / Ka + c), rtol=1e-4)
    ks = preloaded_pair(kind="spring")
    assert np.isclose(ks.pair_N_mm_rad[0, 2, 2], Ka, rtol=1e-4)
    assert abs(ks.bearing_N_mm_rad[1, 0, 2, 2]) <= 1e-9 * Ka


def test_R3_equal_ball_loads_radial_and_tilting_stiffness():
    """R3.  With every ball at the preload state (T of `ball_tangent_closed_form`) and
    sum_k cos^2 psi_k = sum_k sin^2 psi_k = Z/2 (Z >= 3), one bearing about its ball plane:
        k_xx = k_yy = (Z/2) T_rr                                     (de Mul et al. 1989)
        k_tx = k_ty = (Z/2) [R^2 T_aa - s R z' (T_ar + T_ra) + z'^2 T_rr]
        k_x_ty = (Z/2) [z' T_rr - s R T_ra]
    R = dm/2 + (f_i - 1/2) Dw cos a0 (the inner groove-centre circle), z' = s (f_i - 1/2) Dw
    sin a0 its axial offset from the ball plane (Harris Vol. 1 ch. 2), s = +1 for bearing A of
    a DB pair; to 1e-4."""
    T = ball_tangent_closed_form(P_N)
    k = preloaded_pair().bearing_N_mm_rad[0, 0]
    half = G.Z / 2.0
    off = (G.f_i - 0.5) * G.Dw_mm
    R, zp, s = 0.5 * G.dm_mm + off * np.cos(np.radians(G.alpha0_deg)), \
        off * np.sin(np.radians(G.alpha0_deg)), 1.0
    k_rr = half * T[1, 1]
    k_tt = half * (R ** 2 * T[0, 0] - s * R * zp * (T[0, 1] + T[1, 0]) + zp ** 2 * T[1, 1])
    k_x_ty = half * (zp * T[1, 1] - s * R * T[1, 0])
    assert np.allclose([k[0, 0], k[1, 1]], k_rr, rtol=1e-4)
    assert np.allclose([k[3, 3], k[4, 4]], k_tt, rtol=1e-4)
    assert np.isclose(k[0, 4], k_x_ty, rtol=1e-4)
    assert np.isclose(k[1, 3], -k_x_ty, rtol=1e-4)    # theta_x moves y the other way


# ---------------------------------------------------------------------------------------------
def _condensed(K, keep, load):
    """d(load)/d(dof `load`) with the dofs `keep` free (others held): 1 / (K_sub^-1)_ll."""
    sub = K[np.ix_(keep, keep)]
    return 1.0 / np.linalg.inv(sub)[keep.index(load), keep.index(load)]


@pytest.mark.parametrize("c,kind", [(0.0, "position"), (2e-5, "position"), (0.0, "spring")])
def test_R4_agrees_with_the_pair_solvers_own_stiffness(c, kind):
    """R4.  Quasi-static balls.  Axial-only row: k_zz = the axial solver's
    pair_axial_stiffness (dF_ext/dx).  Every row: the combined solver's radial stiffness
    (dF_r/drho with z and theta_y free) and tilting stiffness (dM/dtheta with x and z free),
    from its own one-plane unknowns, equal the 5x5's condensations to 1e-9."""
    st, args = case("static", c, kind)
    K = pair_stiffness(G, "DB", st, **args).pair_N_mm_rad
    ax = solve_pair(G, "DB", **{**args, "radial_load_N": 0.0, "moment_Nmm": 0.0})
    assert np.isclose(K[0, 2, 2], 1e3 * ax.pair_axial_stiffness_N_per_um[0], rtol=1e-9)
    for i in range(3):
        kr = _condensed(K[i], [0, 2, 4], 0)
        kt = _condensed(K[i], [0, 2, 4], 4)
        assert np.isclose(kr, 1e3 * st.radial.radial_stiffness_N_per_um[i], rtol=1e-9), i
        assert np.isclose(kt, 1e3 * st.radial.moment_stiffness_Nmm_per_mrad[i], rtol=1e-9), i


def test_R5_quasi_dynamic_at_rest_is_quasi_static():
    """R5.  At speed 0 the quasi-dynamic ball is the quasi-static contact (ball_dynamics module
    docstring); its tangent (implicit function through the ball's equilibrium, K_i and K_o
    apart) equals the series-K_n tangent to 1e-8 of the diagonal scale."""
    st_s, args_s = case("static", 2e-5)
    Ks = pair_stiffness(G, "DB", st_s, **args_s).pair_N_mm_rad
    st, args = case("quasi_dynamic", 2e-5, speed=0.0)
    Kd = pair_stiffness(G, "DB", st, **args).pair_N_mm_rad
    d = np.sqrt(np.abs(np.diagonal(Ks, axis1=-2, axis2=-1)))
    assert np.all(np.abs(Kd - Ks) <= 1e-8 * d[:, :, None] * d[:, None, :])


def test_condense_rigid_floating_and_series():
    """The condensation of the preload path's give: 1/c = inf leaves K_qq; a path spring in
    series with a bearing of axial stiffness k gives k c^-1 / (k + c^-1) on z."""
    K6 = np.zeros((6, 6))
    k = 3.0
    K6[2, 2], K6[2, 5], K6[5, 2], K6[5, 5] = k, -k, -k, k    # z and w act on the same spring
    assert condense(K6, np.inf)[2, 2] == k
    assert np.isclose(condense(K6, 2.0)[2, 2], k * 2.0 / (k + 2.0), rtol=1e-15)
    assert condense(K6, 0.0)[2, 2] == 0.0


@pytest.mark.parametrize("ball_model,c", [("static", 2e-5), ("quasi_dynamic", 0.0)])
def test_pair_matrix_is_the_bearings_moved_to_the_pair_centre(ball_model, c):
    """Rigid-body transfer (statics): with bearing j's ball plane at z_j = -+span/2 from the
    pair's centre, its DOFs are x_j = x + z_j theta_y, y_j = y - z_j theta_x (the rest equal),
    so K_pair = sum_j T_j^T K_j T_j, to 1e-9 of sqrt(K_ii K_jj): the two frames are computed
    from different lever arms, not by this transfer."""
    st, args = case(ball_model, c)
    k = pair_stiffness(G, "DB", st, **args)
    moved = np.zeros_like(k.pair_N_mm_rad)
    for j, zj in enumerate((-0.5 * SPAN, 0.5 * SPAN)):
        T = np.eye(5)
        T[0, 4], T[1, 3] = zj, -zj
        moved += np.einsum("ai,nab,bj->nij", T, k.bearing_N_mm_rad[j], T)
    d = np.sqrt(np.abs(np.diagonal(k.pair_N_mm_rad, axis1=-2, axis2=-1)))
    assert np.all(np.abs(moved - k.pair_N_mm_rad) <= 1e-9 * d[:, :, None] * d[:, None, :])
