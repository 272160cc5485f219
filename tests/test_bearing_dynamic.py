"""The pair at speed (analytic/bearing/dynamic.py): quasi-dynamic balls in the pair equilibrium.

Independent statements held here: at speed 0 the quasi-static pair (`solve_pair_axial`); at speed,
every ball's two force equations (Harris & Kotzalas Vol. 2 ch. 3) with the centrifugal force and
gyroscopic moment recomputed from their closed forms, the pair's axial equilibrium, the geometry
of the groove centres rebuilt from Hertz approaches, and a second, separately written solver (one
bearing with 5 DOF of its inner ring, `single.solve_single`) carrying the same axial load.
Jones's raceway-control criterion is checked against the state it chose, the Hertz contacts
re-derived here from the curvatures (`_jones_spin_moment`)."""
import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from analytic.bearing import BearingGeometry, contact_stiffness, solve_pair, thermal_geometry
from analytic.bearing.ball_dynamics import solve_balls
from analytic.bearing.single import solve_single
from analytic.torque import ball_kinematics

G = BearingGeometry.from_catalogue("71807C")
N = 6
CASE = dict(dr_mm=np.linspace(-0.002, 0.003, N), dz_mm=np.linspace(0.0, 0.001, N),
            T_inner_ring_C=np.linspace(-40.0, 80.0, N), T_outer_ring_C=np.linspace(-40.0, 70.0, N),
            T_ball_C=np.linspace(-40.0, 75.0, N), preload_assembled_N=100.0,
            axial_load_N=np.linspace(-50.0, 80.0, N), compliance_mm_per_N=2e-5)


def _jones_spin_moment(Q_N, alpha_rad, f, outer):
    """Q a E(k) of a ball-raceway contact (the full-slip spin moment over 3/8 mu; Jones 1960,
    Harris & Kotzalas Vol. 2 ch. 3), built here from the curvatures alone (free geometry of G):
    rolling direction 1/Rx = (2/Dw)/(1 -+ gamma), gamma = Dw cos(alpha)/dm (- inner, + outer
    raceway), transverse 1/Ry = (2 f - 1)/(f Dw); ellipticity kappa = a/b from the curvature
    difference F = (1/Rx - 1/Ry)/(1/Rx + 1/Ry) = [(kappa^2 + 1) E - 2 K] / [(kappa^2 - 1) E]
    (m = 1 - 1/kappa^2, scipy's complete elliptic integrals, root by brentq); semi-major axis
    a = (6 kappa^2 E Q R / (pi E'))^(1/3), R = 1/(1/Rx + 1/Ry) (Harris Vol. 1 ch. 6).  E' is the
    same for both raceways and cancels in Jones's comparison: left out (set to 1)."""
    Dw, dm = G.Dw_mm, G.dm_mm
    out = np.zeros(np.shape(Q_N))
    for idx in np.ndindex(out.shape):
        Q, a = float(np.asarray(Q_N)[idx]), float(np.asarray(alpha_rad)[idx])
        gam = Dw * np.cos(a) / dm
        irx = (2.0 / Dw) / (1.0 + gam if outer else 1.0 - gam)
        iry = (2.0 * f - 1.0) / (f * Dw)
        F = (irx - iry) / (irx + iry)

        def eq(k):
            m = 1.0 - 1.0 / k ** 2
            return ((k * k + 1.0) * ellipe(m) - 2.0 * ellipk(m)) / ((k * k - 1.0) * ellipe(m)) - F
        kap = brentq(eq, 1.0 + 1e-9, 200.0, xtol=1e-15, rtol=1e-15)
        E = ellipe(1.0 - 1.0 / kap ** 2)
        a_mm = (6.0 * kap ** 2 * E * Q / (np.pi * (irx + iry))) ** (1.0 / 3.0)
        out[idx] = Q * a_mm * E
    return out


def _jones_outer(Q_i, Q_o, a_i, a_o):
    """Jones's criterion from `_jones_spin_moment`: the outer raceway controls where
    Q_o a_o E_o cos(a_i - a_o) >= Q_i a_i E_i."""
    return (_jones_spin_moment(Q_o, a_o, G.f_o, True) * np.cos(a_i - a_o)
            >= _jones_spin_moment(Q_i, a_i, G.f_i, False))


@pytest.mark.parametrize("kind", ["position", "spring"])
def test_speed_zero_is_the_quasi_static_pair(kind):
    """Speed 0: no centrifugal force or gyroscopic moment, so the quasi-dynamic pair is the
    quasi-static one (forces, angles, loads, rotor position to 1e-10 of their scale).  The axial
    stiffness differs by the dK_n/dalpha term the frozen ball tangent leaves out, of relative
    size (F/k) dlnK_n/dalpha cos(alpha)/D ~ 1e-6 here: held to 1e-5."""
    st = solve_pair(G, "DB", preload_kind=kind, **CASE)
    dy = solve_pair(G, "DB", preload_kind=kind, ball_model="quasi_dynamic", speed_rpm=0.0, **CASE)
    assert st.converged.all() and dy.converged.all()
    for f in ("axial_force_N", "contact_angle_deg", "ball_load_N", "x_mm", "delta_mm",
              "max_contact_pressure_MPa", "preload_N"):
        a, b = getattr(st, f), getattr(dy, f)
        assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(a)), f
    np.testing.assert_allclose(dy.axial_stiffness_N_per_um, st.axial_stiffness_N_per_um, rtol=1e-5)
    d = dy.dynamic
    np.testing.assert_array_equal(d.centrifugal_force_N, 0.0)
    np.testing.assert_allclose(d.contact_angle_outer_deg, d.contact_angle_inner_deg, atol=1e-9)
    np.testing.assert_allclose(d.load_outer_N, d.load_inner_N, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("control", ["outer", "inner"])
def test_pair_at_speed_balls_and_pair_in_equilibrium(control):
    """20000 rpm, position preload 100 N, compliance, axial loads, no thermal growth: (1) each
    ball's axial and radial force equations with F_c = m omega_c^2 dm/2 (m = rho pi Dw^3/6) and
    M_g = J omega_c omega_R sin(beta) (J = m Dw^2/10) recomputed from the reported angles through
    the kinematics of the control hypothesis, to 1e-9 of the loads; (2) the bearing's axial force
    F = Z (Q_i sin(a_i) + f_i cos(a_i)) (f_i = 2 M_g/Dw, the inner raceway's friction, under
    inner control) and sum_j s_j F_j = axial load to 1e-9 of the preload; (3) the groove centres rebuilt from the contact normals and the Hertz approaches
    delta = (Q/K)^(2/3) (K at each contact's own angle) lie where the pair's kinematics put them:
    Y_j = A0 cos a0 + dr_j and X_j = A0 sin a0 + a_j, a_j = s_j (dz_j + x) + e - c F_j (1e-9 mm);
    and the outer contact angle below the inner one, the outer ball load above it."""
    speed = 20000.0
    c = 2e-5
    case = dict(dr_mm=CASE["dr_mm"], dz_mm=CASE["dz_mm"], preload_assembled_N=100.0,
                axial_load_N=CASE["axial_load_N"], compliance_mm_per_N=c)
    p = solve_pair(G, "DB", ball_model="quasi_dynamic", speed_rpm=speed, control=control, **case)
    assert p.converged.all()
    d = p.dynamic
    ai, ao = np.radians(d.contact_angle_inner_deg), np.radians(d.contact_angle_outer_deg)
    Qi, Qo = d.load_inner_N, d.load_outer_N
    kin = ball_kinematics(G.dm_mm, G.Dw_mm, ai, ao, outer_control=control == "outer")
    omega = speed * 2.0 * np.pi / 60.0
    m = G.ball.density_kg_m3 * 1e-12 * np.pi * G.Dw_mm ** 3 / 6.0
    Fc = m * (kin.cage * omega) ** 2 * G.dm_mm / 2.0
    Mg = m * G.Dw_mm ** 2 / 10.0 * kin.cage * omega * kin.omega_r * omega
    np.testing.assert_allclose(d.centrifugal_force_N, Fc, rtol=1e-12)
    lam_i, lam_o = (0.0, 2.0) if control == "outer" else (2.0, 0.0)
    w = Mg / G.Dw_mm
    axial = Qi * np.sin(ai) - Qo * np.sin(ao) + w * (lam_i * np.cos(ai) - lam_o * np.cos(ao))
    radial = Qi * np.cos(ai) - Qo * np.cos(ao) - w * (lam_i * np.sin(ai) - lam_o * np.sin(ao)) + Fc
    assert np.all(np.abs(axial) <= 1e-9 * Qo) and np.all(np.abs(radial) <= 1e-9 * Qo)
    s = np.array([1.0, -1.0])[:, None]
    F = G.Z * (Qi * np.sin(ai) + w * lam_i * np.cos(ai))
    np.testing.assert_allclose(p.axial_force_N, F, rtol=1e-12)
    assert np.all(np.abs((s * F).sum(axis=0) - case["axial_load_N"]) <= 1e-9 * 100.0)
    tg = thermal_geometry(G)
    Ki, Ko = contact_stiffness(G, tg, ai).K_i, contact_stiffness(G, tg, ao).K_o
    di, do = (Qi / Ki) ** (2.0 / 3.0), (Qo / Ko) ** (2.0 / 3.0)
    ri, ro = (G.f_i - 0.5) * G.Dw_mm + di, (G.f_o - 0.5) * G.Dw_mm + do
    X = ro * np.sin(ao) + ri * np.sin(ai)
    Y = ro * np.cos(ao) + ri * np.cos(ai)
    a0 = np.radians(G.alpha0_deg)
    np.testing.assert_allclose(Y, np.broadcast_to(G.A0_mm * np.cos(a0) + case["dr_mm"], Y.shape),
                               rtol=0, atol=1e-9)
    a = s * (case["dz_mm"] + p.x_mm) + p.preload_offset_mm - c * F
    np.testing.assert_allclose(X, G.A0_mm * np.sin(a0) + a, rtol=0, atol=1e-9)
    assert np.all(ao < ai) and np.all(Qo > Qi)


def test_pair_bearing_equals_single_bearing_at_speed():
    """A second route: the single-bearing solver (inner ring with 5 DOF, every ball at its own
    azimuth, `single.solve_single`, quasi-dynamic balls) under the axial load that bearing A
    carries in the pair at 15000 rpm gives the same inner and outer contact angles and ball
    loads (1e-7 relative; no radial shift, no thermal growth)."""
    speed = 15000.0
    p = solve_pair(G, "DB", ball_model="quasi_dynamic", speed_rpm=speed,
                   preload_assembled_N=np.array([30.0, 100.0, 300.0]),
                   axial_load_N=np.array([0.0, 40.0, -100.0]))
    assert p.converged.all()
    st = solve_single(G, axial_load_N=p.axial_force_N[0], speed_rpm=speed,
                      ball_model="quasi_dynamic")
    assert st.converged.all()
    b = st.balls
    d = p.dynamic
    np.testing.assert_allclose(b.contact_angle_inner_deg[0], d.contact_angle_inner_deg[0], rtol=1e-7)
    np.testing.assert_allclose(b.contact_angle_outer_deg[0], d.contact_angle_outer_deg[0], rtol=1e-7)
    np.testing.assert_allclose(b.load_inner_N[0], d.load_inner_N[0], rtol=1e-7)
    np.testing.assert_allclose(b.load_outer_N[0], d.load_outer_N[0], rtol=1e-7)


def test_jones_control_chooses_by_the_spin_moments():
    """Jones's criterion (Harris & Kotzalas Vol. 2 ch. 3): the chosen hypothesis holds at the
    state it gives, Q_o a_o E_o cos(a_i - a_o) >= Q_i a_i E_i where outer control was chosen and
    < where inner control was (semi-axes and E(k) re-derived here from the curvatures at the
    solved loads and angles, `_jones_spin_moment`); the balls then equal those of the fixed
    hypothesis chosen (1e-10); and the
    choice is inner control at 100 rpm (the inner contact of the 71807C, f_i < f_o, is the wider
    one) and outer control at 60000 rpm (the centrifugal force loads the outer contact)."""
    a0 = np.radians(G.alpha0_deg)
    X = np.full(4, G.A0_mm * np.sin(a0) + 0.005)
    Y = np.full(4, G.A0_mm * np.cos(a0))
    speed = np.array([100.0, 3000.0, 20000.0, 60000.0])
    b = solve_balls(G, X, Y, speed, control="jones")
    assert b.converged.all()
    assert not b.outer_control[0] and b.outer_control[-1]
    ai, ao = np.radians(b.contact_angle_inner_deg), np.radians(b.contact_angle_outer_deg)
    np.testing.assert_array_equal(_jones_outer(b.load_inner_N, b.load_outer_N, ai, ao),
                                  b.outer_control)
    for k in range(4):
        fixed = solve_balls(G, X[k], Y[k], speed[k],
                            control="outer" if b.outer_control[k] else "inner")
        np.testing.assert_allclose(fixed.contact_angle_outer_deg, b.contact_angle_outer_deg[k],
                                   rtol=1e-10)
        np.testing.assert_allclose(fixed.load_inner_N, b.load_inner_N[k], rtol=1e-10)


COMBINED = dict(preload_assembled_N=100.0, axial_load_N=np.array([0.0, 30.0, -20.0]),
                radial_load_N=np.array([50.0, 200.0, 120.0]),
                moment_Nmm=np.array([0.0, 1000.0, -500.0]), bearing_span_mm=20.0)


@pytest.mark.parametrize("kind, c", [("position", 0.0), ("position", 2e-5), ("spring", 0.0)])
def test_combined_load_at_speed_zero_is_the_quasi_static_pair(kind, c):
    """Radial load, moment and tilt, speed 0: the ball-by-ball pair with quasi-dynamic balls is
    the quasi-static combined-load pair (forces, angles, radial displacement, tilt, every ball's
    load to 1e-10 of their scale), for a rigid and a compliant position preload and a spring."""
    st = solve_pair(G, "DB", preload_kind=kind, compliance_mm_per_N=c, **COMBINED)
    dy = solve_pair(G, "DB", preload_kind=kind, compliance_mm_per_N=c, ball_model="quasi_dynamic",
                    speed_rpm=0.0, **COMBINED)
    assert st.converged.all() and dy.converged.all()
    for a, b, name in [(st.axial_force_N, dy.axial_force_N, "F"), (st.x_mm, dy.x_mm, "x"),
                       (st.contact_angle_deg, dy.contact_angle_deg, "alpha"),
                       (st.radial.rho_mm, dy.radial.rho_mm, "rho"),
                       (st.radial.tilt_rad, dy.radial.tilt_rad, "tilt"),
                       (st.radial.radial_force_N, dy.radial.radial_force_N, "Fr"),
                       (st.radial.ball_loads_N, dy.radial.ball_loads_N, "Q")]:
        assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(a)), name


@pytest.mark.parametrize("kind, c, control", [("position", 2e-5, "outer"),
                                               ("spring", 0.0, "outer"),
                                               ("position", 2e-5, "inner")])
def test_combined_load_at_speed_against_the_single_bearing_balls(kind, c, control):
    """A second route for the pair at 15000 rpm under radial load and moment (shaft free to
    tilt): each bearing's inner ring displacement read from the pair's solution (axial approach
    a_j, radial rho + theta l_j, tilt s_j theta; `combined.tilt_arms_mm`) is handed to the
    single-bearing code (`single.balls_at_displacement`, which solves every ball on its own):
    its balls equal the pair's ball by ball (1e-8), and the loads those balls carry add up to
    the external ones: sum_j s_j F_z,j = axial load, sum_j F_x,j = radial load, and the moment
    about the pair's mid-point (1e-8 of the preload, and of the preload times half the span).
    Outer- and inner-race control (the latter with the inner raceway's friction and its couples
    about the groove centres on the rings)."""
    from analytic.bearing.combined import tilt_arms_mm
    from analytic.bearing.single import balls_at_displacement

    speed = 15000.0
    p = solve_pair(G, "DB", preload_kind=kind, compliance_mm_per_N=c, ball_model="quasi_dynamic",
                   speed_rpm=speed, control=control, **COMBINED)
    assert p.converged.all()
    r = p.radial
    s = np.array([1.0, -1.0])
    a0 = np.radians(G.alpha0_deg)
    gx, gy = tilt_arms_mm(G, thermal_geometry(G), s[:, None], COMBINED["bearing_span_mm"])
    loads = []
    for j in range(2):
        b = balls_at_displacement(G, G.A0_mm * np.sin(a0) + p.approach_mm[j],
                                  r.rho_mm + r.tilt_rad * gy[j], 0.0, 0.0, s[j] * r.tilt_rad, speed,
                                  ball_model="quasi_dynamic", control=control)
        np.testing.assert_allclose(b.load_inner_N, r.ball_loads_N[j], rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(b.load_outer_N, r.ball_loads_outer_N[j], rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(b.contact_angle_outer_deg, r.ball_contact_angles_outer_deg[j],
                                   rtol=1e-8)
        loads.append(b.loads)
    P = COMBINED["preload_assembled_N"]
    assert np.all(np.abs(s[0] * loads[0][0] + s[1] * loads[1][0] - COMBINED["axial_load_N"])
                  <= 1e-8 * P)
    assert np.all(np.abs(loads[0][1] + loads[1][1] - COMBINED["radial_load_N"]) <= 1e-8 * P)
    # moment about the mid-point: each bearing's moment of its axial ball forces (about y, tilt
    # sense s_j) plus its radial force acting at its inner groove centres, l_j from the mid-point
    # (z_j = -+span/2 plus the groove centre's axial offset from the ball plane)
    M = sum(s[j] * loads[j][4] + gy[j] * loads[j][1] for j in range(2))
    half = 0.5 * COMBINED["bearing_span_mm"]
    assert np.all(np.abs(M - COMBINED["moment_Nmm"]) <= 1e-8 * P * half)


def test_single_bearing_jones_control_holds_at_the_state_it_chose():
    """One bearing under combined radial + axial load at speed with control "jones": every
    ball's controlling raceway satisfies Jones's criterion at the solved state (the contacts
    re-derived here from the curvatures, `_jones_spin_moment`), the state equals the fixed hypothesis where all balls chose the same one, and at low
    speed the inner raceway controls while at high speed the outer one does (as for one ball)."""
    speed = np.array([100.0, 60000.0])
    st = solve_single(G, axial_load_N=200.0, radial_load_x_N=150.0, speed_rpm=speed,
                      ball_model="quasi_dynamic", control="jones")
    assert st.converged.all()
    b = st.balls
    ai, ao = np.radians(b.contact_angle_inner_deg), np.radians(b.contact_angle_outer_deg)
    loaded = b.load_inner_N > 0
    chosen = _jones_outer(b.load_inner_N, b.load_outer_N, ai, ao)
    assert np.array_equal(chosen[loaded], b.outer_control[loaded])
    assert not b.outer_control[loaded[:, 0], 0].any() and b.outer_control[loaded[:, 1], 1].all()
    for k, ctl in ((0, "inner"), (1, "outer")):
        fixed = solve_single(G, axial_load_N=200.0, radial_load_x_N=150.0, speed_rpm=speed[k],
                             ball_model="quasi_dynamic", control=ctl)
        np.testing.assert_allclose(fixed.axial_mm, st.axial_mm[k], rtol=1e-9)
        np.testing.assert_allclose(fixed.radial_x_mm, st.radial_x_mm[k], rtol=1e-9)
