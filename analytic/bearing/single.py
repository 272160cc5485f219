"""One bearing under radial (x, y), axial and moment (about x, y) load: the inner ring with five
degrees of freedom against a rigid outer ring, every ball at its own azimuth (the ISO/TS 16281
load-distribution problem; Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 7 and
Vol. 2 ch. 1 and 3; Jones 1960).  Units: mm, N, rad inside; names carry their units.

Coordinates.  z is the bearing axis, positive in the direction in which the inner ring carries
thrust at a positive contact angle (a positive axial_load_N pushes the inner ring that way);
x and y radial, ball k at azimuth psi_k = 2 pi k / Z from x towards y
(`contact.ball_azimuths_rad`).  The reference point of the inner ring is on the axis in the plane
of the outer groove curvature centres; at zero displacement the inner ring is centred: its groove
centres lie in that plane at radius R_i = dm/2 + (f_i - 1/2) Dw cos a0, A0 cos a0 radially outside
the outer ones (Harris Vol. 1 ch. 2; `land.groove_centre_radius_mm`).  Free contact angle and
diametral radial clearance P_d (ISO 5753) are one statement, cos a0 = 1 - P_d / (2 A0)
(`free_contact_angle_deg`).

Ring displacement q = (z, x, y, theta_x, theta_y) (mm, rad; small rotations, right-handed about
x and y).  The inner groove centre of ball k moves (u = theta x r, r at the groove centre):

    X_k = z + R_m (theta_x sin psi_k - theta_y cos psi_k)         (axial, from the centred position)
    Y_k = A0 cos a0 + x cos psi_k + y sin psi_k                   (radial)

with the moment arm R_m = R_i (convention "exact": the groove-centre locus) or dm/2 (convention
"iso16281": the pitch radius, ISO/TS 16281:2008).  Each ball's contact follows from (X_k, Y_k)
(quasi-static: delta = hypot(X, Y) - A0, Q = K_n delta^1.5 at alpha = atan2(X, Y),
`contact.axial_state`; quasi-dynamic: `ball_dynamics`, inner and outer contact apart, centrifugal
force and gyroscopic moment at speed_rpm).  Convention "exact" evaluates K_n at each ball's own
contact angle; "iso16281" at the nominal (free) contact angle for every ball.  Equilibrium of the
inner ring (virtual work; the loads the rings carry):

    F_z = sum_k Q_k sin a_k,   F_x = sum_k Q_k cos a_k cos psi_k,   F_y = sum_k Q_k cos a_k sin psi_k
    M_x = sum_k Q_k sin a_k R_m sin psi_k,   M_y = -sum_k Q_k sin a_k R_m cos psi_k

(Q_k, a_k the inner contact of ball k; with quasi-dynamic balls Q_k (sin a_k, cos a_k) stands for
the inner ring's whole load from ball k, Q_i n_i + f_i t_i, the inner raceway's gyroscopic friction
included (inner-race control), so that the ring's and the outer ring's force balance close; M_x
and M_y then also carry that friction's couple about the groove centre, r_i f_i e_t per ball,
`ball_dynamics.friction_couple_Nmm` and module docstring).  With K (and at speed the frozen ball
forces) held these are the stationarity conditions of the convex potential
sum_k W_k(X_k, Y_k) - (F - C).q (C the friction couples as generalised loads; W = (2/5) K_n
delta^2.5 quasi-statically, the condensed ball potential of `ball_dynamics` at speed),
minimised by `roots.newton_minimise`; an
outer loop refreshes K (and the centrifugal force, gyroscopic moment and friction directions) at
the new contact angles until the angles change by less than tol.  Axial displacement is reported
from the centred position in both conventions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing import ball_dynamics as bd
from analytic.bearing.ball_dynamics import BALL_MODELS
from analytic.bearing.axial import approach_for_force
from analytic.bearing.contact import axial_state, ball_azimuths_rad, contact_stiffness
from analytic.bearing.geometry import BearingGeometry, thermal_geometry
from analytic.bearing.land import groove_centre_radius_mm
from analytic.bearing.roots import Root, newton_direction
from analytic.bearing.state import ContactEllipses, contact_ellipses
from analytic.torque import ball_kinematics

CONVENTIONS = ("exact", "iso16281")


def free_contact_angle_deg(A0_mm: float, radial_internal_clearance_mm: float) -> float:
    """Free contact angle from the diametral radial internal clearance P_d (ISO 5753 sense):
    cos a0 = 1 - P_d / (2 A0), A0 = (f_i + f_o - 1) Dw (Harris & Kotzalas Vol. 1 ch. 2), deg.
    ValueError unless 0 <= P_d < 2 A0."""
    Pd = float(radial_internal_clearance_mm)
    if not 0.0 <= Pd < 2.0 * A0_mm:
        raise ValueError(f"clearance {1e3 * Pd:g} um must lie in 0 .. 2 A0 = {2e3 * A0_mm:.1f} um")
    return float(np.degrees(np.arccos(1.0 - Pd / (2.0 * A0_mm))))


def moment_arm_mm(g: BearingGeometry, convention: str = "exact") -> float:
    """R_m: the inner groove-centre radius R_i ("exact") or the pitch radius dm/2 ("iso16281")."""
    if convention not in CONVENTIONS:
        raise ValueError(f"convention must be one of {', '.join(CONVENTIONS)}, got {convention!r}")
    return groove_centre_radius_mm(g, "inner") if convention == "exact" else 0.5 * g.dm_mm


def _map(g: BearingGeometry, convention: str):
    """G (2, 5, Z): d(X_k, Y_k)/d(z, x, y, t_x, t_y) with t = R_m theta (all unknowns in mm)."""
    psi = ball_azimuths_rad(g.Z)
    c, s = np.cos(psi), np.sin(psi)
    o, i = np.zeros_like(psi), np.ones_like(psi)
    return np.array([[i, o, o, s, -c], [o, c, s, o, o]]), moment_arm_mm(g, convention)


@dataclass(frozen=True)
class BallsState:
    """Every ball's contact at a ring displacement, arrays (Z, N), ball k at psi_k."""
    contact_angle_inner_deg: np.ndarray
    contact_angle_outer_deg: np.ndarray
    load_inner_N: np.ndarray
    load_outer_N: np.ndarray
    approach_inner_mm: np.ndarray
    approach_outer_mm: np.ndarray
    centrifugal_force_N: np.ndarray
    gyroscopic_moment_Nmm: np.ndarray
    spin_to_roll: np.ndarray
    max_contact_pressure_MPa: np.ndarray     # of the ball's two contacts
    loads: np.ndarray                        # (5, N): F_z, F_x, F_y (N), M_x, M_y (N mm) they carry
    outer_control: np.ndarray | None = None  # quasi-dynamic: True where the outer raceway controls
    ellipse_inner: ContactEllipses | None = None   # Hertz ellipses of the inner contacts, (Z, N)
    ellipse_outer: ContactEllipses | None = None   # and of the outer contacts

    @property
    def max_ball_load_N(self) -> np.ndarray:
        return np.maximum(self.load_inner_N, self.load_outer_N).max(axis=0)


@dataclass(frozen=True)
class SingleBearingState:
    """Equilibrium of one bearing at N load points; `convention` and `ball_model` name the model."""
    convention: str
    ball_model: str
    axial_mm: np.ndarray          # (N,) from the centred position
    radial_x_mm: np.ndarray
    radial_y_mm: np.ndarray
    tilt_x_rad: np.ndarray
    tilt_y_rad: np.ndarray
    balls: BallsState
    converged: np.ndarray

    @property
    def radial_mm(self) -> np.ndarray:
        return np.hypot(self.radial_x_mm, self.radial_y_mm)

    @property
    def tilt_rad(self) -> np.ndarray:
        return np.hypot(self.tilt_x_rad, self.tilt_y_rad)

    def most_loaded(self, field: str) -> np.ndarray:
        """A per-ball field of `balls` at the most loaded ball of each point, (N,)."""
        b = self.balls
        k = np.argmax(np.maximum(b.load_inner_N, b.load_outer_N), axis=0)
        return np.take_along_axis(getattr(b, field), k[None, :], axis=0)[0]


class _Problem:
    """Ring potential and its derivatives for one block of points (see module docstring)."""

    def __init__(self, g, tg, G, Yc, F, speed, ball_model, convention, control):
        self.g, self.tg, self.G, self.Yc, self.F = g, tg, G, Yc, F
        self.speed, self.ball_model, self.control = speed, ball_model, control
        self.alpha_K = np.radians(g.alpha0_deg) if convention == "iso16281" else None
        self.outer_ctl = None        # control "jones": the raceway that controls, per ball
        self.R_m = moment_arm_mm(g, convention)
        self.couple = None           # quasi-dynamic: generalised load of the friction couples

    def P(self, q):
        X = np.einsum("jk,jn->kn", self.G[0], q)
        Y = self.Yc + np.einsum("jk,jn->kn", self.G[1], q)
        return X, Y

    def freeze(self, X, Y, a_i, a_o):
        g, tg = self.g, self.tg
        if self.ball_model == "static":
            ak = a_i if self.alpha_K is None else np.broadcast_to(self.alpha_K, a_i.shape)
            self.Kn = contact_stiffness(g, tg, ak).Kn
        else:
            spd = np.broadcast_to(self.speed, a_i.shape)
            if self.outer_ctl is None:
                self.outer_ctl = np.ones(a_i.size, bool)
            shares = bd.control_shares(self.control, self.outer_ctl)
            self.fz, ex, _, _ = bd.frozen_forces(g, tg, a_i.ravel(), a_o.ravel(), spd.ravel(),
                                                 shares, self.alpha_K)
            f_i = np.broadcast_to(ex.f_i, a_i.size).reshape(a_i.shape)
            self.couple = np.zeros((5, a_i.shape[1]))
            self.couple[3:] = bd.friction_couple_Nmm(g, tg, f_i) / self.R_m

    def switch_control(self, a_i, a_o) -> bool:
        """Control "jones": re-choose each ball's controlling raceway by Jones's criterion at the
        balls' last state (`ball_dynamics.jones_outer_control`); True when any ball switched."""
        new = bd.jones_choice(self.g, self.tg, self.last, a_i, a_o)
        switched = bool(np.any(new != self.outer_ctl))
        self.outer_ctl = new
        return switched

    def balls(self, X, Y):
        """W (Z, N), grad (2, Z, N), Hessian (2, 2, Z, N), inner and outer angles."""
        if self.ball_model == "static":
            st = axial_state(X, Y, self.tg.A_T_mm, self.Kn, 1)
            n = np.stack([np.sin(st.alpha_rad), np.cos(st.alpha_rad)])
            D = np.hypot(X, Y)
            H = bd._tangent(n.reshape(2, -1), (1.5 * self.Kn * np.sqrt(st.delta_mm)).ravel(),
                            st.Q_N.ravel(), D.ravel()).reshape((2, 2) + X.shape)
            W = 0.4 * st.Q_N * st.delta_mm
            self.W_abs = W
            return W, st.Q_N * n, H, st.alpha_rad, st.alpha_rad
        P = np.stack([X.ravel(), Y.ravel()])
        # warm start: the ball centres of the previous evaluation (7x fewer ball iterations);
        # balls that do not converge from there start again from the quasi-static split
        u0 = getattr(self, "u_prev", None)
        cold = u0 is None
        if cold:
            u0 = bd.static_split(P, self.fz)
        root, W, W_abs, grad, Kt, p = bd.frozen_equilibrium(P, u0, self.fz, self.g.Dw_mm)
        if not cold and not root.converged.all():
            root, W, W_abs, grad, Kt, p = bd.frozen_equilibrium(P, bd.static_split(P, self.fz),
                                                                self.fz, self.g.Dw_mm)
        self.u_prev = root.x
        self.ball_ok = root.converged
        self.last = p
        self.W_abs = W_abs.reshape(X.shape)
        a_o = np.arctan2(p.n_o[0], p.n_o[1]).reshape(X.shape)
        a_i = np.arctan2(p.n_i[0], p.n_i[1]).reshape(X.shape)
        return (W.reshape(X.shape), grad.reshape((2,) + X.shape), Kt.reshape((2, 2) + X.shape),
                a_i, a_o)

    def __call__(self, q):
        X, Y = self.P(q)
        W, grad, H, _, _ = self.balls(X, Y)
        G = self.G
        F = self.F if self.couple is None else self.F - self.couple
        Fq = (F * q).sum(axis=0)
        gq = np.einsum("ajk,akn->jn", G, grad) - F
        Hq = np.einsum("ajk,abkn,blk->jln", G, H, G)
        self.scale = np.hypot(grad[0], grad[1]).sum(axis=0) + np.abs(self.F).max(axis=0)
        return W.sum(axis=0) - Fq, self.W_abs.sum(axis=0) + np.abs(Fq), gq, Hq


def _minimise(prob, q0, cap: float, max_iter: int = 60) -> Root:
    """Minimise the ring potential of `prob` for every point: Newton steps on the 5 x 5 Hessian
    (plus 1e-12 of its largest diagonal and 1e-6 N/mm for directions no ball holds), capped to
    `cap` mm, halved while the potential rises above its rounding level (1e-13 of its terms).
    A point has converged when every generalised residual force is below 1e-13 of the sum of
    its ball forces and loads, or its full step below 1e-15 (1 + max|q|) mm (or, once no step
    lowers the potential, the residual below 1e-10 of them); a full Newton step whose predicted
    change is below the potential's rounding is taken as it is.  (A criterion on the
    residual rather than on the potential: with the ball equilibria solved inside it, the
    potential carries their rounding.)"""
    q = np.array(q0, float, copy=True)
    N = q.shape[1]
    Pi, Pabs, g, H = prob(q)
    done = np.zeros(N, bool)
    conv = np.zeros(N, bool)
    for _ in range(max_iter):
        conv |= np.abs(g).max(axis=0) <= 1e-13 * prob.scale
        done |= conv
        if done.all():
            break
        d = newton_direction(g, H)
        size = np.abs(d).max(axis=0)
        d *= np.where(size > cap, cap / np.where(size > 0, size, 1.0), 1.0)
        d[:, done] = 0.0
        t = np.ones(N)
        pending = ~done
        scale = prob.scale.copy()
        flat = np.abs((g * d).sum(axis=0)) <= 1e-12 * Pabs   # as in ball_dynamics._newton_ball
        for _ls in range(30):
            trial = q + t * d
            Pt, Pat, gt, Ht = prob(trial)
            ok = pending & ((Pt <= Pi + 1e-13 * (Pabs + Pat)) | (flat & (t == 1.0)))
            q[:, ok], Pi[ok], Pabs[ok], g[:, ok], H[..., ok] = (trial[:, ok], Pt[ok], Pat[ok],
                                                               gt[:, ok], Ht[..., ok])
            scale[ok] = prob.scale[ok]
            pending &= ~ok
            if not pending.any():
                break
            t = np.where(pending, 0.5 * t, t)
        prob.scale = scale
        conv |= ~done & (t == 1.0) & (np.abs(d).max(axis=0) <= 1e-15 * (1.0 + np.abs(q).max(axis=0)))
        done |= conv | pending
    # no step lowers the potential any more: at its minimum to rounding when the residual is
    # also within 1e-10 of the forces (the ball equilibria inside carry their own rounding)
    conv |= np.abs(g).max(axis=0) <= 1e-10 * prob.scale
    return Root(q, conv & np.isfinite(q).all(axis=0))


def _solve_block(g, tg, G, R_m, Yc, F, speed, q0, ball_model, convention, control, tol,
                 max_outer):
    prob = _Problem(g, tg, G, Yc, F, speed, ball_model, convention, control)
    q = q0
    X, Y = prob.P(q)
    a_i = a_o = np.arctan2(X, Y)
    done = np.zeros(q.shape[1], bool)
    relax, last = np.ones(q.shape[1]), np.full(q.shape[1], np.inf)
    for n_pass in range(max_outer):
        prob.freeze(X, Y, a_i, a_o)
        root = _minimise(prob, q, cap=0.05 * g.Dw_mm)
        q = root.x
        X, Y = prob.P(q)
        _, _, _, n_i, n_o = prob.balls(X, Y)
        change = np.maximum(np.abs(n_i - a_i), np.abs(n_o - a_o)).max(axis=0)
        if ball_model == "static":
            a_i, a_o = n_i, n_o
        else:
            a_i, a_o, relax = bd.relaxed_update(a_i, a_o, n_i, n_o, change, last, relax)
            last = change
        done = change <= tol
        if (control == "jones" and ball_model != "static" and n_pass < bd.JONES_FREE_PASSES
                and prob.switch_control(a_i, a_o)):
            done[:] = False
            last[:] = np.inf         # the next pass's change comes from the switch
        if done.all():
            break
    prob.freeze(X, Y, a_i, a_o)
    ok = done & root.converged
    if ball_model != "static":
        prob.balls(X, Y)
        ok &= prob.ball_ok.reshape(X.shape).all(axis=0)
    return q, ok


def solve_single(g: BearingGeometry, *, axial_load_N=0.0, radial_load_x_N=0.0,
                 radial_load_y_N=0.0, moment_x_Nmm=0.0, moment_y_Nmm=0.0, speed_rpm=0.0,
                 ball_model: str = "static", convention: str = "exact", control: str = "outer",
                 tol: float = 1e-12, max_outer: int = 60, chunk: int = 1024) -> SingleBearingState:
    """Equilibrium of one bearing (inner ring 5 DOF, outer ring rigid and fixed) under the given
    loads (N, N mm; scalars or arrays (N,)) at speed_rpm of the inner ring.

    ball_model "static" (quasi-static contact, inner = outer angle) or "quasi_dynamic"
    (`ball_dynamics`: centrifugal force and gyroscopic moment; identical to "static" at speed 0);
    convention "exact" or "iso16281"; control "outer", "inner" or "jones" raceway control
    (quasi-dynamic; "jones": Jones's criterion per ball, `ball_dynamics.jones_outer_control`).
    The free contact angle of g sets the internal clearance (`free_contact_angle_deg` converts a
    clearance).  Formulas: module docstring.  Returns `SingleBearingState` (displacements mm and
    rad, every ball's state, `converged` per point)."""
    if ball_model not in BALL_MODELS:
        raise ValueError(f"ball_model must be one of {', '.join(BALL_MODELS)}, got {ball_model!r}")
    if control not in bd.CONTROLS:
        raise ValueError(f"control must be one of {', '.join(bd.CONTROLS)}, got {control!r}")
    G, R_m = _map(g, convention)
    loads = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, float)) for v in
                                  (axial_load_N, radial_load_x_N, radial_load_y_N, moment_x_Nmm,
                                   moment_y_Nmm, speed_rpm)))
    Fz, Fx, Fy, Mx, My, spd = loads
    N = Fz.size
    F = np.stack([Fz, Fx, Fy, Mx / R_m, My / R_m])
    tg = thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    Yc = g.A0_mm * np.cos(a0)
    # start: the axial-only solution (Harris's axial-load equation), centred radially
    sign = np.where(Fz < 0.0, -1.0, 1.0)
    ap = approach_for_force(g, np.abs(Fz))
    q0 = np.zeros((5, N))
    q0[0] = sign * (g.A0_mm * np.sin(a0) + np.where(np.isfinite(ap.a_mm), ap.a_mm, 0.0))
    q = np.zeros((5, N))
    ok = np.zeros(N, bool)
    for i0 in range(0, N, chunk):
        sl = slice(i0, min(N, i0 + chunk))
        q[:, sl], ok[sl] = _solve_block(g, tg, G, R_m, Yc, F[:, sl], spd[sl], q0[:, sl],
                                        ball_model, convention, control, tol, max_outer)
    for i in np.flatnonzero(~ok):
        # a point that did not converge with its block gets a block of its own (the block's
        # shared warm starts and outer passes can hold one point back; rare, seen at a few rpm)
        sl = slice(i, i + 1)
        q[:, sl], ok[sl] = _solve_block(g, tg, G, R_m, Yc, F[:, sl], spd[sl], q0[:, sl],
                                        ball_model, convention, control, tol, max_outer)
    balls = balls_at_displacement(g, q[0], q[1], q[2], q[3] / R_m, q[4] / R_m, spd,
                                  ball_model=ball_model, convention=convention, control=control)
    return SingleBearingState(convention, ball_model, q[0], q[1], q[2], q[3] / R_m, q[4] / R_m,
                              balls, ok)


def balls_at_displacement(g: BearingGeometry, axial_mm, radial_x_mm=0.0, radial_y_mm=0.0,
                          tilt_x_rad=0.0, tilt_y_rad=0.0, speed_rpm=0.0, *,
                          ball_model: str = "static", convention: str = "exact",
                          control: str = "outer") -> BallsState:
    """Every ball's contact state for a given inner-ring displacement against the outer ring
    (mm, rad; scalars or (N,)): axial from the centred position, radial x and y, tilts about x
    and y (module docstring), inner ring at speed_rpm.  Returns `BallsState` ((Z, N) per ball,
    with the loads (5, N) the balls carry: F_z, F_x, F_y in N, M_x, M_y in N mm)."""
    G, R_m = _map(g, convention)
    arrs = np.broadcast_arrays(*(np.atleast_1d(np.asarray(v, float)) for v in
                                 (axial_mm, radial_x_mm, radial_y_mm, tilt_x_rad, tilt_y_rad,
                                  speed_rpm)))
    q = np.stack([arrs[0], arrs[1], arrs[2], R_m * arrs[3], R_m * arrs[4]])
    spd = arrs[5]
    tg = thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    X = np.einsum("jk,jn->kn", G[0], q)
    Y = g.A0_mm * np.cos(a0) + np.einsum("jk,jn->kn", G[1], q)
    alpha_K = a0 if convention == "iso16281" else None
    if ball_model == "static":
        alpha = np.arctan2(X, Y)
        cs = contact_stiffness(g, tg, alpha if alpha_K is None else np.full(X.shape, alpha_K))
        st = axial_state(X, Y, tg.A_T_mm, cs.Kn, 1)
        a_i = a_o = st.alpha_rad
        Q_i = Q_o = st.Q_N
        cs_i = cs_o = cs
        # series split of the approach: K_i d_i^1.5 = K_o d_o^1.5 = Q
        d_i = np.where(Q_i > 0, (Q_i / cs.K_i) ** (2.0 / 3.0), 0.0)
        d_o = np.where(Q_o > 0, (Q_o / cs.K_o) ** (2.0 / 3.0), 0.0)
        zeros = np.zeros(X.shape)
        kin = ball_kinematics(tg.dm_mm, tg.Dw_mm, a_i)
        Fc, Mg = zeros, zeros
        sr = kin.spin_inner / np.hypot(kin.omega_r, kin.omega_z)
        ctl = None
        Fa_k, Fr_k = Q_i * np.sin(a_i), Q_i * np.cos(a_i)
        couple = np.zeros((2, X.shape[1]))
    elif ball_model == "quasi_dynamic":
        b = bd.solve_balls(g, X, Y, np.broadcast_to(spd, X.shape), control=control, tg=tg,
                           alpha_stiffness_rad=alpha_K)
        a_i, a_o = np.radians(b.contact_angle_inner_deg), np.radians(b.contact_angle_outer_deg)
        Q_i, Q_o = b.load_inner_N, b.load_outer_N
        d_i, d_o = b.approach_inner_mm, b.approach_outer_mm
        cs_i, cs_o = b.cs_inner, b.cs_outer
        Fc, Mg, sr = b.centrifugal_force_N, b.gyroscopic_moment_Nmm, b.spin_to_roll
        ctl = b.outer_control
        Fa_k, Fr_k = b.inner_force_N          # Q_i n_i + the inner raceway's friction
        couple = bd.friction_couple_Nmm(g, tg, b.friction_inner_N)
    else:
        raise ValueError(f"ball_model must be one of {', '.join(BALL_MODELS)}, got {ball_model!r}")

    def ell(cs, Q, side):
        e = contact_ellipses(g, cs, Q.reshape(np.shape(cs.Kn)), side)
        return ContactEllipses(*(np.broadcast_to(getattr(e, f), np.shape(e.a_mm)).reshape(X.shape)
                                 for f in ("a_mm", "b_mm", "p_max_MPa", "E_ell", "Rx_mm")))
    e_i, e_o = ell(cs_i, Q_i, 0), ell(cs_o, Q_o, 1)
    p = np.maximum(e_i.p_max_MPa, e_o.p_max_MPa)
    psi = ball_azimuths_rad(g.Z)[:, None]
    sa, ca = Fa_k, Fr_k
    loads = np.stack([sa.sum(axis=0), (ca * np.cos(psi)).sum(axis=0),
                      (ca * np.sin(psi)).sum(axis=0),
                      (sa * R_m * np.sin(psi)).sum(axis=0) + couple[0],
                      -(sa * R_m * np.cos(psi)).sum(axis=0) + couple[1]])
    return BallsState(np.degrees(a_i), np.degrees(a_o), Q_i, Q_o, d_i, d_o, Fc, Mg, sr, p, loads,
                      ctl, e_i, e_o)

