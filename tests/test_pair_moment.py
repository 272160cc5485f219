"""The pair under radial load and moment with the shaft free to tilt (`bearing.solve_pair(...,
moment_Nmm=..., bearing_span_mm=...)`), and the one contact model (full groove) of the axial-only
and the combined solver.

Checked against: the axial-only solver in the limit of a vanishing radial load or moment (a
deep-groove pair with clearance whose far bearing runs on the other groove flank, and a preloaded
angular-contact pair); the statics of the solved state written out ball by ball in 3-D Cartesian
vectors (rigid-body motion of the rotor, inner-minus-outer groove-centre vector, Hertz load along
it, forces and moments summed about the pair's mid-point: they must balance the applied loads);
the pressure-centre statics of a moment on an unpreloaded pair (equal and opposite radial
reactions M / L_eff, L_eff the distance of the contact-cone apexes, reached at the rate of the
neglected contact-angle change); the closed-form linearisation of a symmetric preloaded pair
(radial and tilting stiffness with every ball at the preload state); finite differences of the
solver."""
import numpy as np
import pytest

from analytic.bearing import SIGNS, BearingGeometry, solve_pair, thermal_geometry
from bearing_reference import flat, kn_direct

G = BearingGeometry.from_catalogue("71807C")          # Z = 24, alpha0 = 15 deg, dm 41 mm
SPAN = 14.0                                            # ball planes 14 mm apart (7 mm ring + spacer)


def deep_groove(clearance_mm):
    """A 6205-size deep-groove bearing (Dw 7.938 mm, Z 9, dm 38.5 mm, f 0.52/0.52) with the free
    radial clearance Pd/2 = clearance_mm / 2: cos alpha0 = 1 - Pd / (2 A0) (Harris & Kotzalas
    Vol. 1 ch. 2)."""
    A0 = (0.52 + 0.52 - 1.0) * 7.938
    a0 = np.degrees(np.arccos(1.0 - clearance_mm / (2.0 * A0)))
    return BearingGeometry(Dw_mm=7.938, Z=9, dm_mm=38.5, f_i=0.52, f_o=0.52, alpha0_deg=a0,
                           ring=G.ring, ball=G.ball, designation="6205-like")


# ---------------------------------------------------------------------------------------------
# (1) one contact model: the limit of a vanishing radial load / moment is the axial-only solver
#: even in the radial load / moment (unchanged to first order: rho -> -rho is a symmetry)
COMPARED = ("preload_N", "axial_force_N[A]", "axial_force_N[B]", "x_mm", "approach_mm[A]",
            "approach_mm[B]", "pair_axial_stiffness_N_per_um")
#: of the most loaded ball: ball 0 takes about 2 Fr / Z more (first order), so these move by a
#: relative 2 Fr / (Z Q) < 1e-7 for Fr = 1e-6 N and Q > 1 N
TOP_BALL = ("contact_angle_deg[A]", "contact_angle_deg[B]", "ball_load_N[A]", "ball_load_N[B]",
            "max_contact_pressure_MPa")


def assert_limit(out, ref):
    for k in COMPARED:
        assert np.allclose(out[k], ref[k], rtol=1e-9, atol=1e-12), k
    for k in TOP_BALL:
        assert np.allclose(out[k], ref[k], rtol=1e-7, atol=1e-12), k


def test_deep_groove_pair_far_bearing_on_the_other_flank():
    """Deep-groove pair with 5 um radial clearance, no preload (both bearings just touching, the rotor centred
    in its axial play), axial loads up to well past the point where the rotor has moved 2 A0
    sin(alpha0) and the far bearing's balls reach the other flank of their grooves.  Radial load
    1e-6 N (or a moment of 1e-6 N mm): the axial outputs equal the axial-only ones to 1e-9
    relative, those of the most loaded ball to its first-order share (`assert_limit`).  Before the one contact model
    the axial solver gave the far bearing no force there.  Independently:
    the solved x balances Fa through both bearings, written out with K_n from the Hertz
    primitives, the far bearing at a negative contact angle carrying a negative force."""
    g = deep_groove(0.005)
    Fa = np.array([200.0, 2000.0, 5000.0, 10000.0])
    kw = dict(preload_assembled_N=0.0, axial_load_N=Fa)
    ref = flat(solve_pair(g, "DB", **kw))
    for extra in (dict(radial_load_N=1e-6), dict(moment_Nmm=1e-6, bearing_span_mm=30.0)):
        out = flat(solve_pair(g, "DB", **kw, **extra))
        assert out["converged"].all()
        assert_limit(out, ref)
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    x = ref["x_mm"]
    assert x[0] < 2 * X0 < x[-1]                              # both regimes covered
    for i in range(Fa.size):
        F = []
        for s in SIGNS["DB"]:
            X = X0 + s * x[i]                                 # e = 0: no preload, no shifts
            alpha = np.arctan2(X, Y0)
            delta = max(np.hypot(X, Y0) - g.A0_mm, 0.0)
            F.append(g.Z * kn_direct(g, alpha) * delta ** 1.5 * np.sin(alpha))
        assert SIGNS["DB"] @ np.array(F) == pytest.approx(Fa[i], rel=1e-9)
        assert ref["axial_force_N[B]"][i] == pytest.approx(F[1], rel=1e-9, abs=1e-9 * Fa[i])
    assert ref["axial_force_N[B]"][-1] < 0 and ref["contact_angle_deg[B]"][-1] < 0


@pytest.mark.parametrize("arrangement,preload", [
    ("DB", {}), ("DF", {}), ("DB", dict(compliance_mm_per_N=2e-5)),
    ("DB", dict(preload_kind="spring"))])
def test_tiny_radial_load_and_moment_preloaded_pair(arrangement, preload):
    """Preloaded angular-contact pair (71807C, 100 N position preload, rigid or with a compliant
    preload path, or a 100 N spring; groove shifts and a warm ball): a radial load or a moment of
    1e-6 (N, N mm) leaves the outputs at the axial-only values (`assert_limit`), and the tilt and
    radial displacement are of order load / stiffness."""
    kw = dict(preload_assembled_N=100.0, axial_load_N=[-60.0, 0.0, 80.0], dr_mm=3e-4,
              dz_mm=np.array([[1e-4], [-2e-4]]), T_ball_C=35.0, **preload)
    ref = flat(solve_pair(G, arrangement, **kw))
    for extra in (dict(radial_load_N=1e-6, bearing_span_mm=SPAN),
                  dict(moment_Nmm=1e-6, bearing_span_mm=SPAN)):
        out = flat(solve_pair(G, arrangement, **kw, **extra))
        assert out["converged"].all()
        assert_limit(out, ref)
        assert np.all(np.abs(out["radial.rho_mm"]) < 1e-6 / 1e4)       # k_r > 1e4 N/mm
        assert np.all(np.abs(out["radial.tilt_rad"]) < 1e-6 / 1e5)      # k_theta > 1e5 N mm/rad


def test_moment_needs_a_positive_span():
    with pytest.raises(ValueError, match="bearing_span_mm"):
        solve_pair(G, "DB", preload_assembled_N=100.0, moment_Nmm=10.0)
    with pytest.raises(ValueError, match="bearing_span_mm must be positive"):
        solve_pair(G, "DB", preload_assembled_N=100.0, radial_load_N=10.0, bearing_span_mm=0.0)


# ---------------------------------------------------------------------------------------------
# (2) displacement-driven statics, ball by ball in 3-D
def statics_3d(g, arrangement, out, i, dr, dz, span, tg=None):
    """Forces and moment of the balls on the rotor for the solved displacements of point i,
    from vectors: the rotor moves rigidly by (rho, 0, .) and tilts by theta about e_y through
    the mid-point; each inner groove curvature centre sits at radius R_i = dm/2 + (f_i - 1/2) Dw
    cos(alpha0) (Harris & Kotzalas Vol. 1 ch. 7), axially (f_i - 1/2) Dw sin(alpha0) from its
    ball plane along the bearing's contact sense; its axial position relative to the outer
    groove centre is the solved approach a_j.  The inner-minus-outer centre vector d (radial and
    axial parts; the tangential part does not load a ball in a torus groove) gives
    alpha = atan2(s d_z, d_r), delta = |d| - A_T, Q = K_n delta^1.5 (K_n from the Hertz
    primitives), and the force -Q (cos alpha e_r + s sin alpha e_z) on the rotor at the centre.
    Returns (sum F_x, sum F_y, sum F_z, M_x, M_y) about the mid-point."""
    a0 = np.radians(g.alpha0_deg)
    Dw, dm, fi, fo = g.Dw_mm, g.dm_mm, g.f_i, g.f_o
    A_T = g.A0_mm
    if tg is not None:
        Dw, dm, fi, fo, A_T = (float(np.ravel(v)[0]) for v in (tg.Dw_mm, tg.dm_mm, tg.f_i, tg.f_o, tg.A_T_mm))
    kw = {} if tg is None else dict(Dw=Dw, dm=dm, f_i=fi, f_o=fo)
    R_i = dm / 2 + (fi - 0.5) * Dw * np.cos(a0)
    rho, theta = out["radial.rho_mm"][i], out["radial.tilt_rad"][i]
    F, Mom = np.zeros(3), np.zeros(3)
    for j, name in enumerate("AB"):
        s = SIGNS[arrangement][j]
        z_c = (-0.5 if j == 0 else 0.5) * span + s * (fi - 0.5) * Dw * np.sin(a0)
        a_j = out[f"approach_mm[{name}]"][i]
        for psi in 2 * np.pi * np.arange(g.Z) / g.Z:
            e_r = np.array([np.cos(psi), np.sin(psi), 0.0])
            e_z = np.array([0.0, 0.0, 1.0])
            p = R_i * e_r + z_c * e_z                              # inner groove centre
            u = np.array([rho, 0.0, 0.0]) + theta * np.cross([0.0, 1.0, 0.0], p)
            d = ((g.A0_mm * np.cos(a0) + dr[j] + u @ e_r) * e_r
                 + (s * (g.A0_mm * np.sin(a0) + a_j) + u @ e_z) * e_z)
            dR, dZ = d @ e_r, s * (d @ e_z)
            alpha = np.arctan2(dZ, dR)
            delta = max(np.hypot(dR, dZ) - A_T, 0.0)
            Q = float(kn_direct(g, alpha, **kw)) * delta ** 1.5
            f = -Q * (np.cos(alpha) * e_r + s * np.sin(alpha) * e_z)
            F += f
            Mom += np.cross(p, f)
    return F[0], F[1], F[2], Mom[0], Mom[1]


CASES = [("DB", "position", 0.0, None), ("DF", "position", 0.0, None),
         ("DB", "position", 2e-5, None), ("DB", "spring", 0.0, None),
         ("DB", "position", 0.0, (55.0, 35.0, 45.0))]


@pytest.mark.parametrize("arrangement,kind,c,temps", CASES)
def test_displacement_driven_statics(arrangement, kind, c, temps):
    """Impose the solved displacements, sum the ball forces and moments from the geometry
    (`statics_3d`): they balance the applied axial load, radial load and moment to 1e-8 of the
    load scale (N, N mm over the span), with no force across the load plane and no moment about
    the load direction."""
    dr = np.array([3e-4, -2e-4])
    dz = np.array([2e-4, -4e-4])
    Fa = np.array([0.0, 120.0, -60.0, 300.0])
    Fr = np.array([400.0, 0.0, 1500.0, -800.0])
    M = np.array([0.0, 5000.0, -8000.0, 12000.0])
    kw = dict(preload_kind=kind, preload_assembled_N=150.0, axial_load_N=Fa, radial_load_N=Fr,
              moment_Nmm=M, dr_mm=dr[:, None], dz_mm=dz[:, None], compliance_mm_per_N=c,
              bearing_span_mm=SPAN)
    tg = None
    if temps is not None:
        kw.update(T_inner_ring_C=temps[0], T_outer_ring_C=temps[1], T_ball_C=temps[2])
        tg = thermal_geometry(G, *temps, 20.0)
    out = flat(solve_pair(G, arrangement, **kw))
    assert out["converged"].all()
    for i in range(Fa.size):
        Fx, Fy, Fz, Mx, My = statics_3d(G, arrangement, out, i, dr, dz, SPAN, tg)
        scale = max(abs(Fa[i]), abs(Fr[i]), abs(M[i]) / SPAN, 150.0)
        assert -Fx == pytest.approx(Fr[i], abs=1e-8 * scale)
        assert -Fz == pytest.approx(Fa[i], abs=1e-8 * scale)
        assert -My == pytest.approx(M[i], abs=1e-8 * scale * SPAN)
        assert abs(Fy) <= 1e-8 * scale and abs(Mx) <= 1e-8 * scale * SPAN
        # the reactions the solver reports are the same sums, bearing by bearing
        assert out["radial.radial_force_N[A]"][i] + out["radial.radial_force_N[B]"][i] == \
            pytest.approx(Fr[i], abs=1e-8 * scale)


# ---------------------------------------------------------------------------------------------
# (3) moment only: pressure-centre statics
@pytest.mark.parametrize("alpha0,arrangement", [(0.0, "DB"), (15.0, "DB"), (15.0, "DF")])
def test_moment_only_reactions_at_the_pressure_centres(alpha0, arrangement):
    """A pure moment M on a rigid shaft in an unpreloaded pair: the radial reactions are equal and
    opposite (force balance, to 1e-9) and, while every contact line of a bearing passes through
    one point on the axis (the apex of its contact cone at z_ball -+ (dm/2) tan(alpha0): the load
    centre of catalogues), M = Fr_B L_eff with L_eff = span + s_A dm tan(alpha0) (statics).  The
    contact lines turn with the load by delta/D (Hertz: delta ~ Q^(2/3)), so the relative error
    goes to zero as M^(2/3): checked on M = 1e-4, 1e-2, 1 N mm (observed order 2/3 +- 0.05 and
    below 1e-3 at the smallest moment)."""
    g = BearingGeometry(**{**G.__dict__, "alpha0_deg": alpha0})
    M = np.array([1e-4, 1e-2, 1.0])
    out = flat(solve_pair(g, arrangement, preload_assembled_N=0.0, moment_Nmm=M,
                          bearing_span_mm=SPAN))
    assert out["converged"].all()
    FA, FB = out["radial.radial_force_N[A]"], out["radial.radial_force_N[B]"]
    assert np.allclose(FA, -FB, rtol=1e-9)
    L_eff = SPAN + SIGNS[arrangement][0] * g.dm_mm * np.tan(np.radians(alpha0))
    err = np.abs(FB * L_eff / M - 1.0)
    order = np.log(err[1:] / err[:-1]) / np.log(M[1:] / M[:-1])
    assert np.allclose(order, 2.0 / 3.0, atol=0.05)
    assert err[0] < 1e-3
    assert np.all(out["radial.tilt_rad"] > 0)


# ---------------------------------------------------------------------------------------------
# (4) symmetric preloaded pair: closed-form linearisation
def preload_state(g, P):
    """Every ball of a symmetric position-preloaded pair at the preload P (no external load):
    Harris's axial-load equation P = Z K_n delta^1.5 sin(alpha), delta = A0 (cos a0 / cos a - 1),
    solved for alpha by bisection with K_n from the Hertz primitives.  Returns alpha, Q, delta, D."""
    a0 = np.radians(g.alpha0_deg)
    lo, hi = a0, a0 + 0.5
    for _ in range(200):
        a = 0.5 * (lo + hi)
        d = g.A0_mm * (np.cos(a0) / np.cos(a) - 1.0)
        if g.Z * kn_direct(g, a) * d ** 1.5 * np.sin(a) > P:
            hi = a
        else:
            lo = a
    a = 0.5 * (lo + hi)
    d = g.A0_mm * (np.cos(a0) / np.cos(a) - 1.0)
    return a, float(kn_direct(g, a)) * d ** 1.5, d, g.A0_mm + d


@pytest.mark.parametrize("arrangement", ["DB", "DF"])
@pytest.mark.parametrize("P", [50.0, 300.0])
def test_symmetric_pair_radial_and_tilting_stiffness(arrangement, P):
    """A symmetric preloaded pair (no shifts, no axial load) at a small radial load or moment.
    With every ball at the preload state (alpha, Q, delta, D of `preload_state`), a ball's
    stiffness along its contact line is k_n = 1.5 Q / delta (Hertz), across it k_t = Q / D (the
    line turns about the groove centre) plus the change of K_n with angle,
    kappa = d ln K_n / d alpha (finite difference of the Hertz primitives).  Summing over the
    balls (sum cos^2 psi = Z/2; the couplings with the axial motion vanish by sum cos psi = 0 and
    those between radial motion and tilt by the mirror symmetry of the pair):

        k_r     = Z [k_n cos^2 a + k_t sin^2 a - k_t kappa sin a cos a]
        k_theta = Z [k_n p^2 + k_t q^2 + k_t kappa p q]
        p = l cos a - s R_i sin a,  q = -s R_i cos a - l sin a   (lever arms of the normal and
        the tangential ball stiffness about the mid-point; l, R_i of the groove centres)

    The solver's stiffnesses (condensed tangent) and the secant k from a load of 1e-3 agree with
    these to 1e-6.  The classical form keeps only k_n (fixed contact directions): k_r = Z k_n cos^2 a
    and k_theta = 2 (Z/2) k_n cos^2 a (L_eff/2)^2 = radial stiffness at the load centres times
    their half-distance squared; checked as the k_n part of the above."""
    a, Q, d, D = preload_state(G, P)
    h = 1e-6
    kappa = float(np.log(kn_direct(G, a + h) / kn_direct(G, a - h)) / (2 * h))
    kn, kt = 1.5 * Q / d, Q / D
    s = SIGNS[arrangement][0]
    a0 = np.radians(G.alpha0_deg)
    off = (G.f_i - 0.5) * G.Dw_mm
    R_i = G.dm_mm / 2 + off * np.cos(a0)
    l = -SPAN / 2 + s * off * np.sin(a0)                     # bearing A
    p = l * np.cos(a) - s * R_i * np.sin(a)
    q = -s * R_i * np.cos(a) - l * np.sin(a)
    k_r = G.Z * (kn * np.cos(a) ** 2 + kt * np.sin(a) ** 2 - kt * kappa * np.sin(a) * np.cos(a))
    k_t = G.Z * (kn * p * p + kt * q * q + kt * kappa * p * q)
    eps = 1e-3
    out = flat(solve_pair(G, arrangement, preload_assembled_N=P, radial_load_N=[eps, 0.0],
                          moment_Nmm=[0.0, eps], bearing_span_mm=SPAN))
    assert out["radial.radial_stiffness_N_per_um"][0] * 1e3 == pytest.approx(k_r, rel=1e-6)
    assert out["radial.moment_stiffness_Nmm_per_mrad"][1] * 1e3 == pytest.approx(k_t, rel=1e-6)
    assert eps / out["radial.rho_mm"][0] == pytest.approx(k_r, rel=1e-6)
    assert eps / out["radial.tilt_rad"][1] == pytest.approx(k_t, rel=1e-6)
    assert abs(out["radial.tilt_rad"][0]) * SPAN < 1e-6 * out["radial.rho_mm"][0]   # centred load: no tilt
    # the classical (normal-stiffness) part: radial stiffness at the load centres
    L_eff = SPAN + s * G.dm_mm * np.tan(a) + 2 * s * off * (np.cos(a0) * np.tan(a) - np.sin(a0))
    assert G.Z * kn * p * p == pytest.approx(2 * (G.Z / 2) * kn * np.cos(a) ** 2 * (L_eff / 2) ** 2,
                                             rel=1e-12)


def test_moment_stiffness_matches_solver_finite_difference():
    """dM/dtheta reported at a loaded, asymmetric state (axial and radial load, shifts) equals
    the central difference of the solved tilt over M +- 0.1 N mm (Fa, Fr held)."""
    kw = dict(preload_assembled_N=120.0, axial_load_N=90.0, radial_load_N=600.0,
              dr_mm=np.array([[3e-4], [-1e-4]]), dz_mm=np.array([[1e-4], [-2e-4]]),
              bearing_span_mm=SPAN)
    for kind, c in (("position", 0.0), ("position", 2e-5), ("spring", 0.0)):
        hM = 0.1
        out = flat(solve_pair(G, "DB", preload_kind=kind, compliance_mm_per_N=c,
                              moment_Nmm=[3000.0 - hM, 3000.0, 3000.0 + hM], **kw))
        k_fd = 2 * hM / (out["radial.tilt_rad"][2] - out["radial.tilt_rad"][0]) * 1e-3
        assert out["radial.moment_stiffness_Nmm_per_mrad"][1] == pytest.approx(k_fd, rel=1e-6)
