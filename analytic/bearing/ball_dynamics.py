"""Quasi-dynamic equilibrium of one ball between its raceways: centrifugal force and gyroscopic
moment, so that the inner and outer contact angles and loads differ (Jones 1960; Harris &
Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 ch. 3).  Units: mm, N, s; radians inside,
degrees in the result.

Geometry (one ball, its plane through the bearing axis; coordinates (axial, radial), radial
outward, axial positive towards the side where the inner groove centre lies at a positive
contact angle).  The outer groove curvature centre is the origin; the inner one sits at
P = (X, Y) (`analytic.bearing` module docstring: X = A0 sin a0 + a, Y = A0 cos a0 + dr).  The
ball centre u = (u_a, u_r) is the unknown (2 per ball):

    d_o = |u|,        n_o = u / d_o = (sin a_o, cos a_o),   delta_o = d_o - (r_o - Dw/2)
    d_i = |P - u|,    n_i = (P - u) / d_i = (sin a_i, cos a_i),   delta_i = d_i - (r_i - Dw/2)
    Q_o = K_o(a_o) delta_o^1.5,   Q_i = K_i(a_i) delta_i^1.5   (0 where delta <= 0)

K_i, K_o: the exact Hertz stiffness of each contact at its own angle (`contact.contact_stiffness`,
Harris Vol. 1 ch. 6).  Forces on the ball (the structure of Harris Vol. 2 ch. 3's ball
equations, written as vectors):

    Q_i n_i - Q_o n_o + F_c e_r + (M_g / Dw) (lam_i t_i - lam_o t_o) = 0,   t = (cos a, -sin a)

    F_c = m omega_c^2 dm / 2          centrifugal force, m = rho pi Dw^3 / 6
    M_g = J omega_c omega_R,r         gyroscopic moment, J = m Dw^2 / 10,
                                      omega_R,r = omega_R sin(beta) (ball spin about its own
                                      axis, radial component, relative to the cage)

omega_c and omega_R sin(beta) come from `torque.ball_kinematics` at the current angles (outer
ring fixed, inner ring at speed_rpm) under the ball's own control hypothesis: outer-race control
tan(beta) = sin a_o / (cos a_o + Dw/dm), inner-race control tan(beta) = sin a_i / (cos a_i - Dw/dm)
(Jones 1960; Harris & Kotzalas Vol. 2 ch. 2, ball spin/roll kinematics).  lam_o = 2,
lam_i = 0 under outer-race control (the outer contact's friction takes the whole gyroscopic
moment, Jones; Harris Vol. 2 ch. 3), lam_i = 2, lam_o = 0 under inner-race control.  control
"jones" chooses per ball with Jones's criterion (Jones 1960; Harris & Kotzalas Vol. 2 ch. 3, raceway
control): the outer raceway controls where its spin-resisting moment is the larger,

    Q_o a_o E(k_o) cos(a_i - a_o) >= Q_i a_i E(k_i)        (a: semi-major axis, E: elliptic integral)

evaluated at the previous pass's state (outer control at the first); a ball's choice is frozen
after JONES_FREE_PASSES passes so that a ball at the switching point cannot cycle.  Direction of the
friction forces, derived here from Euler's equation of the ball: its angular momentum J Omega
precesses with the cage, so the contacts must apply dH/dt = omega_c e_z x J Omega =
+M_g e_t (e_r, e_t, e_z right-handed, e_t the orbit direction; Omega_r > 0 for a positive outer
contact angle), and a friction force f t at the outer contact point (Dw/2 along n_o) has the
moment -(Dw/2) f e_t, at the inner one (Dw/2 along -n_i) +(Dw/2) f e_t.  In components:

    Q_i sin a_i - Q_o sin a_o + (M_g/Dw)(lam_i cos a_i - lam_o cos a_o) = 0
    Q_i cos a_i - Q_o cos a_o - (M_g/Dw)(lam_i sin a_i - lam_o sin a_o) + F_c = 0

which the tests evaluate directly.  Sign convention of the gyroscopic friction: the force of the
inner raceway on the ball is +lam_i (M_g/Dw) t_i, that of the outer raceway -lam_o (M_g/Dw) t_o,
t = (cos a, -sin a), M_g > 0 (inner ring turning so that the ball's radial spin component
Omega_r is positive at a positive contact angle).  The common rendering of Harris's equations
(Harris & Kotzalas Vol. 2 ch. 3; seed 003 eq. 16: Q_i sin a_i - Q_o sin a_o - (lam_i M_g/Dw)
cos a_i + (lam_o M_g/Dw) cos a_o = 0) has the opposite sign on the friction terms.  The sign
there belongs to the senses its figure draws (direction of rotation, positive sense of M_g as
the inertial couple of the ball); here it is fixed by Euler's equation in the axes above with
the inner ring turning in the positive sense: M_g e_t is the moment the contacts exert on the
ball, dH/dt, whatever the rendering.  Physical check, the thrust limit a_i = a_o = 90 deg: the ball rolls with w_c = 1/2 and Omega_r = dm/(2 Dw)
per unit ring speed under either control, M_g = J omega^2 dm / (4 Dw), and the friction that
supplies +M_g e_t at the outer contact (Dw/2 along +e_z) points radially outwards, at the inner
contact (Dw/2 along -e_z) inwards, magnitude 2 M_g / Dw (tests/test_ball_balance.py evaluates
Euler's equation of the ball in three dimensions).

The rings carry what the ball exerts on them: the inner ring Q_i n_i + lam_i (M_g/Dw) t_i (its
friction included: `inner_force_N`), the outer ring Q_o n_o + lam_o (M_g/Dw) t_o, so that Z times
the sum over the balls of either equals the applied load (plus, for the outer ring, the balls'
centrifugal forces) in every control mode.  The friction is frozen with the other forces, so the
ring sees it as a dead load: at the inner groove centre, plus its couple about it, r_i f_i e_t per
ball (`friction_couple_Nmm`; the ring-level solvers with moments or tilt carry it).

At speed 0 (F_c = M_g = 0) the centres and the ball centre are collinear, a_i = a_o and
Q_i = Q_o = K_n delta^1.5 with K_n the series stiffness: the quasi-static contact of
`contact.axial_state` / `ball_set_state`.

Solution.  With K_i, K_o, F_c, M_g and the friction directions frozen, the ball equilibrium is
the stationarity of the convex potential (2/5)(K_o delta_o^2.5 + K_i delta_i^2.5) - b.u
(b the frozen forces), minimised by `roots.newton_minimise`; an outer loop refreshes the frozen
quantities at the new contact angles until the angles change by less than tol.  Its minimum plus
the work of the inner raceway's frozen friction, W(P) = min_u Pi + f_i.P (f_i = lam_i (M_g/Dw) t_i),
is a convex function of the inner groove centre P (partial minimisation of a jointly convex
function) whose gradient is the inner ring's load from the ball Q_i n_i + f_i (envelope theorem)
and whose Hessian is the inner and outer contact tangents in series, T_i (T_i + T_o)^-1 T_o: what
a ring-level solver (`single.py`, `dynamic.py`, `combined.py`) needs.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from analytic.bearing.contact import ContactStiffness, ball_azimuths_rad, contact_stiffness
from analytic.bearing.geometry import (BearingGeometry, ThermalGeometry, broadcast_geometry,
                                       thermal_geometry)
from analytic.bearing.roots import Root
from analytic.torque import RPM_TO_RAD_S, ball_kinematics

#: raceway control hypotheses: (lam_i, lam_o), the shares of 2 M_g / Dw taken by friction at the
#: inner and at the outer contact (Harris Vol. 2 ch. 3)
CONTROL = {"outer": (0.0, 2.0), "inner": (2.0, 0.0)}
#: ball models of the bearing solvers: quasi-static contact, or quasi-dynamic balls at speed
BALL_MODELS = ("static", "quasi_dynamic")
#: the control choices of `solve_balls`: a fixed hypothesis, or Jones's criterion per ball
CONTROLS = ("outer", "inner", "jones")
#: passes of the outer loop during which control "jones" may still switch a ball's control
JONES_FREE_PASSES = 8


def jones_outer_control(g: BearingGeometry, cs_inner: ContactStiffness,
                        cs_outer: ContactStiffness, Q_inner_N, Q_outer_N, alpha_i_rad,
                        alpha_o_rad) -> np.ndarray:
    """Jones's raceway-control criterion (Jones 1960; Harris & Kotzalas Vol. 2 ch. 3): True where
    the outer raceway controls, Q_o a_o E(k_o) cos(a_i - a_o) >= Q_i a_i E(k_i), i.e. the outer
    contact's full-slip spin moment (3/8) mu Q a E (`torque.spin_moment_Nmm`, equal mu) projected
    on the inner contact's normal is at least the inner one's.  Loads N, angles rad; semi-axes
    from the Hertz ellipses at the given loads (`state.contact_ellipses`)."""
    from analytic.bearing.state import contact_ellipses

    e_i = contact_ellipses(g, cs_inner, Q_inner_N, 0)
    e_o = contact_ellipses(g, cs_outer, Q_outer_N, 1)
    m_o = np.asarray(Q_outer_N) * e_o.a_mm * e_o.E_ell * np.cos(np.asarray(alpha_i_rad)
                                                                  - np.asarray(alpha_o_rad))
    return m_o >= np.asarray(Q_inner_N) * e_i.a_mm * e_i.E_ell


def jones_choice(g: BearingGeometry, tg: ThermalGeometry, balls: BallParts, alpha_i_rad,
                 alpha_o_rad) -> np.ndarray:
    """`jones_outer_control` at a solved ball state: `balls` the per-ball quantities of
    `frozen_equilibrium` (flat arrays Q_i, Q_o), angles in rad (any shape, flattened), exact
    Hertz stiffness at each angle of the grown geometry tg (flat)."""
    ai, ao = np.ravel(alpha_i_rad), np.ravel(alpha_o_rad)
    return jones_outer_control(g, contact_stiffness(g, tg, ai), contact_stiffness(g, tg, ao),
                               balls.Q_i, balls.Q_o, ai, ao)


def control_shares(control, outer_controls=None):
    """(lam_i, lam_o) of a control hypothesis: "outer", "inner", or with "jones" per ball from the
    boolean array outer_controls (True: outer-race control)."""
    if control == "jones":
        oc = np.asarray(outer_controls, bool)
        return np.where(oc, 0.0, 2.0), np.where(oc, 2.0, 0.0)
    return CONTROL[control]


def friction_couple_Nmm(g: BearingGeometry, tg: ThermalGeometry,
                        friction_inner_N) -> np.ndarray:
    """(M_x, M_y) in N mm, (2, N): the couples of the inner raceway's gyroscopic friction about the
    inner groove centres, summed over the balls.  Ball k's friction f_k t_i (N, the module
    docstring's sign convention; nonzero under inner-race control) acts on the ring at the
    contact point, r_i = f_i Dw (grown geometry tg) from the groove centre against n_i: the
    moment (-r_i n_i) x f_k t_i = r_i f_k e_t (n_i x t_i = -e_t, e_t = (-sin psi, cos psi) the
    orbit direction at psi_k) adds to the moment of f_k t_i placed at the groove centre.
    friction_inner_N: (Z, N), ball k at `contact.ball_azimuths_rad`[k]."""
    psi = ball_azimuths_rad(g.Z)[:, None]
    c = tg.f_i * tg.Dw_mm * np.asarray(friction_inner_N, float)
    return np.stack([-(c * np.sin(psi)).sum(axis=0), (c * np.cos(psi)).sum(axis=0)])


def relaxed_update(a_i, a_o, n_i, n_o, change, last, relax):
    """One pass of the frozen angles of the ring-level outer loops (`single`, `combined`): the new
    ball angles (n_i, n_o), under-relaxed per point once a pass changes them more than the one
    before (a lightly loaded controlling inner contact can make the plain update oscillate with
    a growing amplitude).  A mode that the update multiplies by lam < -1 grows by
    r = |1 - relax (1 - lam)| per pass; relax is then set to relax / (1 + r), the value that
    cancels it when r comes from that mode alone (floor 1/64).  change, last, relax: per point
    (last axis).  Returns (a_i, a_o, relax)."""
    grow = change > last
    r = np.where(grow, change / np.where(grow, last, 1.0), 0.0)
    relax = np.where(grow, np.maximum(relax / (1.0 + r), 1.0 / 64.0), relax)
    return a_i + relax * (n_i - a_i), a_o + relax * (n_o - a_o), relax


def ball_mass_N_s2_per_mm(g: BearingGeometry, Dw_mm=None) -> float:
    """Ball mass m = rho pi Dw^3 / 6 in N s^2/mm (density from `Material.density_N_s2_mm4`)."""
    Dw = g.Dw_mm if Dw_mm is None else Dw_mm
    return g.ball.density_N_s2_mm4 * np.pi * np.asarray(Dw, float) ** 3 / 6.0


def ball_inertia_N_s2_mm(g: BearingGeometry, Dw_mm=None) -> float:
    """Polar mass moment of inertia of the ball J = m Dw^2 / 10, N s^2 mm (solid sphere)."""
    Dw = g.Dw_mm if Dw_mm is None else Dw_mm
    return ball_mass_N_s2_per_mm(g, Dw) * np.asarray(Dw, float) ** 2 / 10.0


@dataclass(frozen=True)
class BallDynamics:
    """Quasi-dynamic state of every ball (arrays of the shape of the inputs X, Y)."""
    contact_angle_inner_deg: np.ndarray
    contact_angle_outer_deg: np.ndarray
    load_inner_N: np.ndarray
    load_outer_N: np.ndarray
    approach_inner_mm: np.ndarray        # Hertz deformation delta_i (0 when not in contact)
    approach_outer_mm: np.ndarray
    centrifugal_force_N: np.ndarray
    gyroscopic_moment_Nmm: np.ndarray
    spin_to_roll: np.ndarray             # inner contact: |omega_s,i| / omega_R (cage frame)
    cage_speed_rpm: np.ndarray
    ball_centre_mm: np.ndarray           # (2, ...): (axial, radial) from the outer groove centre
    inner_force_N: np.ndarray            # (2, ...): Q_i n_i + f_i t_i, the ball's force on the inner ring reversed
    tangent_N_per_mm: np.ndarray         # (2, 2, ...): d(inner_force_N)/dP, ball in equilibrium
    friction_inner_N: np.ndarray         # f_i: force of the inner raceway on the ball along t_i
    friction_outer_N: np.ndarray         # f_o: force of the outer raceway on the ball along t_o
    cs_inner: ContactStiffness           # Hertz data at the inner angle (ellipses: state.contact_ellipses)
    cs_outer: ContactStiffness
    outer_control: np.ndarray            # True where the outer raceway controls (the hypothesis)
    converged: np.ndarray


class BallParts(NamedTuple):
    """Both contacts of every ball at its centre u (`_ball_potential`; flat arrays over the
    balls, M entries; module docstring): the unit normals n_o = u / d_o and n_i = (P - u) / d_i
    (2, M), the contact loads Q (N), Hertz approaches delta (mm), normal stiffnesses
    kn = dQ/d(delta) (N/mm) and tangential ones kt = Q / d (N/mm)."""
    n_o: np.ndarray
    n_i: np.ndarray
    Q_o: np.ndarray
    Q_i: np.ndarray
    dl_o: np.ndarray
    dl_i: np.ndarray
    kn_o: np.ndarray
    kn_i: np.ndarray
    kt_o: np.ndarray
    kt_i: np.ndarray


class BallExtras(NamedTuple):
    """The speed terms of `frozen_forces` per ball (module docstring): centrifugal force F_c (N),
    gyroscopic moment M_g (N mm), the inner contact's spin-to-roll ratio, cage speed (rpm) and
    the raceway friction forces f_i, f_o along t_i, t_o (N)."""
    F_c: np.ndarray
    M_g: np.ndarray
    spin_to_roll: np.ndarray
    cage_rpm: np.ndarray
    f_i: np.ndarray
    f_o: np.ndarray


@dataclass
class _Frozen:
    """What the outer loop freezes for one pass (flat arrays over balls, M entries)."""
    K_i: np.ndarray
    K_o: np.ndarray
    c_i: np.ndarray              # r_i - Dw/2 (grown)
    c_o: np.ndarray              # r_o - Dw/2
    b: np.ndarray                # (2, M) centrifugal + friction forces on the ball
    f_ring: np.ndarray           # (2, M) the inner raceway's friction force on the ball, f_i t_i


def _contact(d, c, K):
    delta = np.maximum(d - c, 0.0)
    sd = np.sqrt(delta)
    Q = K * delta * sd
    return delta, Q, 1.5 * K * sd, 0.4 * Q * delta


def _tangent(n, kn, Q, d):
    """Contact tangent kn n n^T + (Q/d)(I - n n^T), (2, 2, M)."""
    kt = Q / d
    nn = n[:, None, :] * n[None, :, :]
    eye = np.eye(2)[:, :, None]
    return kn * nn + kt * (eye - nn)


def _ball_potential(P, u, fz: _Frozen):
    """(Pi, |terms|, grad, Hessian, parts) of the frozen ball problem at ball centres u (2, M)."""
    d_o = np.hypot(u[0], u[1])
    v = P - u
    d_i = np.hypot(v[0], v[1])
    n_o, n_i = u / d_o, v / d_i
    dl_o, Q_o, kn_o, V_o = _contact(d_o, fz.c_o, fz.K_o)
    dl_i, Q_i, kn_i, V_i = _contact(d_i, fz.c_i, fz.K_i)
    bu = (fz.b * u).sum(axis=0)
    T_o, T_i = _tangent(n_o, kn_o, Q_o, d_o), _tangent(n_i, kn_i, Q_i, d_i)
    grad = Q_o * n_o - Q_i * n_i - fz.b
    parts = BallParts(n_o, n_i, Q_o, Q_i, dl_o, dl_i, kn_o, kn_i, Q_o / d_o, Q_i / d_i)
    return V_o + V_i - bu, V_o + V_i + np.abs(bu), grad, T_o + T_i, parts


def _newton_ball(P, u0, fz: _Frozen, cap: float, max_iter: int = 100) -> Root:
    """Ball centres minimising the frozen ball potential: Newton steps on the 2 x 2 Hessian
    (plus 1e-12 of its largest diagonal and 1e-9 N/mm, so a ball touching nothing still gets a
    step along its free forces), capped to `cap` mm, halved while the potential rises above its
    rounding level (1e-13 of its terms).  A ball has converged when its residual force is below
    1e-12 of the largest force on it (contact loads, frozen forces) or its step below
    1e-15 (1 + |u|) mm; `converged` says so per ball."""
    u = np.array(u0, float, copy=True)
    M = u.shape[1]
    done = np.zeros(M, bool)
    conv = np.zeros(M, bool)
    Pi, Pabs, g, H, p = _ball_potential(P, u, fz)
    for _ in range(max_iter):
        scale = np.maximum.reduce([p.Q_i, p.Q_o, np.hypot(fz.b[0], fz.b[1])])
        conv |= np.hypot(g[0], g[1]) <= 1e-12 * scale
        done |= conv
        if done.all():
            break
        lam = 1e-12 * np.maximum(np.abs(H[0, 0]), np.abs(H[1, 1])) + 1e-9
        a, b_, c, d_ = H[0, 0] + lam, H[0, 1], H[1, 0], H[1, 1] + lam
        det = a * d_ - b_ * c
        step = -np.array([d_ * g[0] - b_ * g[1], a * g[1] - c * g[0]]) / det
        size = np.hypot(step[0], step[1])
        step *= np.where(size > cap, cap / np.where(size > 0, size, 1.0), 1.0)
        step[:, done] = 0.0
        t = np.ones(M)
        pending = ~done
        # a full Newton step whose predicted change of the potential is below its rounding level
        # is taken as it is (the line search could not judge it; near the minimum it is exact)
        flat = np.abs((g * step).sum(axis=0)) <= 1e-12 * Pabs
        for _ls in range(40):
            trial = u + t * step
            Pt, Pat, gt, Ht, pt = _ball_potential(P, trial, fz)
            ok = pending & ((Pt <= Pi + 1e-13 * (Pabs + Pat)) | (flat & (t == 1.0)))
            u[:, ok], Pi[ok], Pabs[ok], g[:, ok], H[..., ok] = (trial[:, ok], Pt[ok], Pat[ok],
                                                               gt[:, ok], Ht[..., ok])
            for mine, trial_k in zip(p, pt):
                mine[..., ok] = trial_k[..., ok]
            pending &= ~ok
            if not pending.any():
                break
            t = np.where(pending, 0.5 * t, t)
        conv |= ~done & (t == 1.0) & (size <= 1e-15 * (1.0 + np.hypot(u[0], u[1])))
        done |= conv | pending
    scale = np.maximum.reduce([p.Q_i, p.Q_o, np.hypot(fz.b[0], fz.b[1])])
    # a ball whose potential no step lowers any more is at its minimum to rounding: converged
    # when its residual is also within 1e-10 of its loads (the difference of two contact forces
    # of a heavily loaded ball carries their rounding)
    conv |= np.hypot(g[0], g[1]) <= 1e-10 * scale
    return Root(u, conv & np.isfinite(u).all(axis=0))


def series_tangent(n_i, kn_i, kt_i, n_o, kn_o, kt_o):
    """Condensed tangent T_i (T_i + T_o)^-1 T_o of the inner and outer contact in series through
    a ball in equilibrium, (2, 2, M), T = kn n n^T + kt t t^T.  Written in the frame (n_o, t_o)
    with T_i there [[A, B], [B, C]], A = kn_i c^2 + kt_i s^2, B = (kn_i - kt_i) c s,
    C = kn_i s^2 + kt_i c^2 (c = n_i.n_o, s = n_i.t_o), so that every term is free of
    cancellation: det(T_i + T_o) = kn_o kt_o + kn_o C + kt_o A + kn_i kt_i and
    T_i adj(T_i + T_o) T_o = [[kn_o (A kt_o + kn_i kt_i), B kn_o kt_o],
                              [B kn_o kt_o, kt_o (C kn_o + kn_i kt_i)]]
    (a near-singular sum, a lightly loaded ball, would otherwise lose every digit).  Zero where
    the ball touches at most one race."""
    t_o = np.stack([n_o[1], -n_o[0]])
    c = (n_i * n_o).sum(axis=0)
    s = (n_i * t_o).sum(axis=0)
    A = kn_i * c * c + kt_i * s * s
    B = (kn_i - kt_i) * c * s
    C = kn_i * s * s + kt_i * c * c
    det = kn_o * kt_o + kn_o * C + kt_o * A + kn_i * kt_i
    safe = np.where(det > 0.0, det, 1.0)
    knn = np.where(det > 0.0, kn_o * (A * kt_o + kn_i * kt_i) / safe, 0.0)
    knt = np.where(det > 0.0, B * kn_o * kt_o / safe, 0.0)
    ktt = np.where(det > 0.0, kt_o * (C * kn_o + kn_i * kt_i) / safe, 0.0)
    nn = n_o[:, None] * n_o[None, :]
    nt = n_o[:, None] * t_o[None, :]
    tt = t_o[:, None] * t_o[None, :]
    return knn * nn + knt * (nt + np.swapaxes(nt, 0, 1)) + ktt * tt


def frozen_equilibrium(P, u0, fz: _Frozen, Dw_mm: float):
    """Ball centres (2, M) in equilibrium with K, F_c and friction frozen, and the condensed
    potential W(P) = min_u Pi + f_i.P, its gradient Q_i n_i + f_i (the inner ring's load from the
    ball, its raceway's friction included) and Hessian T_i (T_i + T_o)^-1 T_o."""
    root = _newton_ball(P, u0, fz, cap=0.05 * Dw_mm)
    Pi, Pabs, _, _, p = _ball_potential(P, root.x, fz)
    Kt = series_tangent(p.n_i, p.kn_i, p.kt_i, p.n_o, p.kn_o, p.kt_o)
    work = (fz.f_ring * P).sum(axis=0)
    return root, Pi + work, Pabs + np.abs(work), p.Q_i * p.n_i + fz.f_ring, Kt, p


def frozen_forces(g: BearingGeometry, tg: ThermalGeometry, alpha_i, alpha_o, speed_rpm,
                  control, alpha_stiffness=None):
    """K_i, K_o at the contact angles (or at alpha_stiffness for both, the ISO 16281 convention),
    the kinematics at the angles under each ball's control (outer where lam_o > 0), F_c, M_g, the
    frozen force vector b on the ball and the inner raceway's friction f_i t_i (module docstring).
    control: "outer", "inner" or the shares (lam_i, lam_o) per ball (`control_shares`).
    Returns (_Frozen, BallExtras, cs_inner, cs_outer)."""
    lam_i, lam_o = CONTROL[control] if isinstance(control, str) else control
    ai = np.asarray(alpha_i, float)
    ao = np.asarray(alpha_o, float)
    if alpha_stiffness is None:
        cs_i, cs_o = contact_stiffness(g, tg, ai), contact_stiffness(g, tg, ao)
    else:
        cs_i = cs_o = contact_stiffness(g, tg, np.broadcast_to(alpha_stiffness, ai.shape))
    Dw, dm = tg.Dw_mm, tg.dm_mm
    kin = ball_kinematics(dm, Dw, ai, ao, outer_control=np.asarray(lam_o) > 0.0)
    omega = np.asarray(speed_rpm, float) * RPM_TO_RAD_S
    omega_c = kin.cage * omega
    F_c = ball_mass_N_s2_per_mm(g, Dw) * omega_c ** 2 * 0.5 * dm
    M_g = ball_inertia_N_s2_mm(g, Dw) * omega_c * kin.omega_r * omega
    w = M_g / Dw
    f_i, f_o = lam_i * w, -lam_o * w          # along t_i, t_o: module docstring, sign convention
    f_ring = np.stack(np.broadcast_arrays(f_i * np.cos(ai), -f_i * np.sin(ai)))
    b = np.stack([f_ring[0] + f_o * np.cos(ao), F_c + f_ring[1] - f_o * np.sin(ao)])
    om_R = np.hypot(kin.omega_r, kin.omega_z)
    extras = BallExtras(F_c, M_g, kin.spin_inner / np.where(om_R > 0, om_R, 1.0),
                        kin.cage * np.asarray(speed_rpm, float), f_i, f_o)
    fz = _Frozen(cs_i.K_i, cs_o.K_o, tg.f_i * Dw - 0.5 * Dw, tg.f_o * Dw - 0.5 * Dw, b, f_ring)
    return fz, extras, cs_i, cs_o


def static_split(P, fz: _Frozen):
    """Start: the ball centre of the quasi-static contact (collinear centres, deformations split
    so that K_i delta_i^1.5 = K_o delta_o^1.5; unloaded balls midway)."""
    D = np.hypot(P[0], P[1])
    delta = D - fz.c_i - fz.c_o
    r = (fz.K_i / fz.K_o) ** (2.0 / 3.0)
    d_o = np.where(delta > 0, delta * r / (1.0 + r), 0.5 * delta)
    return P / D * (fz.c_o + d_o)


def solve_balls(g: BearingGeometry, X_mm, Y_mm, speed_rpm=0.0, *, control: str = "outer",
                tg: ThermalGeometry | None = None, alpha_stiffness_rad=None,
                tol: float = 1e-12, max_outer: int = 60) -> BallDynamics:
    """Quasi-dynamic equilibrium of balls whose inner groove centre sits at (X_mm, Y_mm) from the
    outer groove centre (axial, radial; any common shape), inner ring at speed_rpm (outer fixed).

    Arguments: g bearing geometry (ball density from its ball material); X_mm, Y_mm in mm;
    speed_rpm scalar or broadcastable; control "outer" (default), "inner" raceway control or
    "jones" (Jones's criterion per ball; module docstring); tg grown geometry (default: free at
    T_ref; arrays broadcastable with X_mm); alpha_stiffness_rad: evaluate K_i and K_o at this
    fixed angle (ISO 16281 convention) instead of at each contact's angle.
    Returns `BallDynamics` (angles deg, loads N, approaches mm, F_c N, M_g N mm, spin-to-roll
    ratio, cage speed rpm, ball centre mm, inner contact force and its tangent, controlling
    raceway, convergence).  Formulas and sources: module docstring."""
    if control not in CONTROLS:
        raise ValueError(f"control must be one of {', '.join(CONTROLS)}, got {control!r}")
    tg0 = tg or thermal_geometry(g)
    X, Y, spd = np.broadcast_arrays(np.asarray(X_mm, float), np.asarray(Y_mm, float),
                                    np.asarray(speed_rpm, float))
    shape = X.shape
    tg = broadcast_geometry(tg0, shape)
    tg = ThermalGeometry(*(v.ravel() for v in (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    P = np.stack([X.ravel(), Y.ravel()])
    spd = spd.ravel()
    alpha = np.arctan2(P[0], P[1])
    a_i, a_o = alpha, alpha
    u = None
    ok_outer = np.zeros(P.shape[1], bool)
    outer_ctl = np.ones(P.shape[1], bool)
    for n_pass in range(max_outer):
        shares = control_shares(control, outer_ctl)
        fz, ex, cs_i, cs_o = frozen_forces(g, tg, a_i, a_o, spd, shares, alpha_stiffness_rad)
        if u is None:
            u = static_split(P, fz)
        root, _, _, F_in, Kt, p = frozen_equilibrium(P, u, fz, float(np.max(tg.Dw_mm)))
        u = root.x
        new_o = np.arctan2(p.n_o[0], p.n_o[1])
        new_i = np.arctan2(p.n_i[0], p.n_i[1])
        # angles of contacts that carry load (an open contact's direction is no state of it)
        change = np.maximum(np.where(p.Q_o > 0, np.abs(new_o - a_o), 0.0),
                            np.where(p.Q_i > 0, np.abs(new_i - a_i), 0.0))
        a_i, a_o = new_i, new_o
        ok_outer = change <= tol
        if control == "jones" and n_pass < JONES_FREE_PASSES:
            new_ctl = jones_choice(g, tg, p, a_i, a_o)
            ok_outer &= new_ctl == outer_ctl
            outer_ctl = new_ctl
        if np.all(ok_outer):
            break
    shares = control_shares(control, outer_ctl)
    fz, ex, cs_i, cs_o = frozen_forces(g, tg, a_i, a_o, spd, shares, alpha_stiffness_rad)
    root2, _, _, F_in, Kt, p = frozen_equilibrium(P, u, fz, float(np.max(tg.Dw_mm)))
    r = lambda a: a.reshape(shape)  # noqa: E731
    outer_ctl = outer_ctl if control == "jones" else np.full(outer_ctl.shape, control == "outer")
    return BallDynamics(
        contact_angle_inner_deg=r(np.degrees(a_i)), contact_angle_outer_deg=r(np.degrees(a_o)),
        load_inner_N=r(p.Q_i), load_outer_N=r(p.Q_o), approach_inner_mm=r(p.dl_i),
        approach_outer_mm=r(p.dl_o), centrifugal_force_N=r(np.broadcast_to(ex.F_c, a_i.shape)),
        gyroscopic_moment_Nmm=r(np.broadcast_to(ex.M_g, a_i.shape)),
        spin_to_roll=r(np.broadcast_to(ex.spin_to_roll, a_i.shape)),
        cage_speed_rpm=r(np.broadcast_to(ex.cage_rpm, a_i.shape)),
        ball_centre_mm=root2.x.reshape((2,) + shape),
        inner_force_N=F_in.reshape((2,) + shape), tangent_N_per_mm=Kt.reshape((2, 2) + shape),
        friction_inner_N=r(np.broadcast_to(ex.f_i, a_i.shape)),
        friction_outer_N=r(np.broadcast_to(ex.f_o, a_i.shape)),
        cs_inner=cs_i, cs_outer=cs_o, outer_control=r(outer_ctl),
        converged=r(ok_outer & root.converged & root2.converged))
