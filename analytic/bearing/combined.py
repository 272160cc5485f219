"""The pair under combined axial and radial load: the quasi-static load distribution around the
ball set (Harris & Kotzalas Vol. 1 ch. 7; Jones 1960; module docstring of `analytic.bearing`).
Units: mm, N; radians inside."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from analytic.bearing.axial import solve_pair_axial
from analytic.bearing.dynamic import DynamicBallSet, DynamicContacts, solve_pair_dynamic
from analytic.bearing import ball_dynamics as bd
from analytic.bearing.contact import (BallSetState, ball_azimuths_rad, ball_positions,
                                      ball_set_state, contact_stiffness)
from analytic.bearing.geometry import (SIGNS, BearingGeometry, ThermalGeometry, n_points,
                                       pair_array, pair_thermal_geometry)
from analytic.bearing.roots import newton_direction, newton_minimise
from analytic.bearing.state import (ContactEllipses, PairState, RadialLoadState, contact_ellipses,
                                    pair_state, with_rows)


#: contact-angle change (rad) below which the quasi-dynamic balls' frozen forces are converged
BALL_ANGLE_TOL_RAD = 1e-12


def tilt_arms_mm(g: BearingGeometry, tg: ThermalGeometry, s, span_mm):
    """Lever arms of a rotor tilt theta (rad, about the axis normal to the radial load, positive
    when it moves the rotor at higher z towards psi = 0) at the inner groove curvature centre of
    bearing j, ball at psi = 0, per radian:

        gx_j = -s_j R_i            (axial approach change, along the bearing's contact sense)
        gy_j = l_j                 (radial motion)
        R_i = dm/2 + (f_i - 1/2) Dw cos(alpha0)          (Harris & Kotzalas Vol. 1 ch. 7: locus
                                                          of the inner groove curvature centres)
        l_j = z_j - z_mid + s_j (f_i - 1/2) Dw sin(alpha0)

    z_j is the plane of bearing j's ball centres (bearing A at -span/2, B at +span/2 from the
    mid-point z_mid, about which the moment is taken) and the last term the axial offset of the
    inner groove centre from the ball centre (contact line at the free angle).  A rigid rotation
    u = theta e_y x (r - r_mid) of the rotor gives these (small rotations); the moment M of the
    ball forces about z_mid is the generalised force conjugate to theta.  Arrays (2, N), mm."""
    a0 = np.radians(g.alpha0_deg)
    off = (tg.f_i - 0.5) * tg.Dw_mm
    R_i = 0.5 * tg.dm_mm + off * np.cos(a0)
    half = 0.5 * np.asarray(span_mm, float)
    z = np.array([-half, half])[:, None]
    gx = -s * R_i
    gy = z + s * off * np.sin(a0)
    return np.broadcast_to(gx, np.broadcast_shapes(gx.shape, gy.shape)), gy * np.ones_like(gx)


class CombinedProblem:
    """Unknowns u (n, N) and total potential of the pair under combined load, one preload mode:

      "rigid"     position preload, c = 0:  u = (x, rho),  a_j = s_j (dz_j + x) + e
                  Pi = V - Fa x - Fr rho
      "compliant" position preload, c > 0:  u = (x, rho, a_A, a_B),  a_j^nom = s_j (dz_j + x) + e
                  Pi = V + sum_j (a_j - a_j^nom)^2 / (2c) - Fa x - Fr rho
      "spring"    spring preload:  u = (a_A, a_B, rho)
                  Pi = V - sum_j F_j^req a_j - Fr rho,  F_A^req = max(s_A Fa + P, 0), F_B^req = P

    With tilt arms (gx, gy of `tilt_arms_mm`, shaft free to tilt) one more unknown is appended,
    t = Lam theta (mm; Lam a fixed length so that all unknowns are displacements), and Pi gets
    - M theta.  V = sum of the ball energies (`ball_set_state`).  Stationarity of Pi is the
    equilibrium of the module docstring with the radial equation added: sum_j s_j F_j = Fa,
    sum_j Fr_j = Fr, sum_j M_j = M (and a_j = a_j^nom - c F_j, or F_j = F_j^req).  With K_n
    frozen Pi is convex (delta is a norm minus a constant, V an increasing convex function of it,
    the maps to X, Y affine)."""

    def __init__(self, mode, s, X0, Ynom, A_T, cos_psi, Fa, Fr, dz, e=None, c=None, Freq=None,
                 gx=None, gy=None, M=None, lam=1.0):
        self.mode, self.s, self.X0, self.Ynom, self.A_T = mode, s, X0, Ynom, A_T
        self.cos_psi, self.Fa, self.Fr, self.dz, self.e, self.c, self.Freq = (
            cos_psi, Fa, Fr, dz, e, c, Freq)
        self.tilt = gx is not None
        self.gx, self.gy, self.lam = gx, gy, lam
        self.M = M
        self.n = {"rigid": 2, "compliant": 4, "spring": 3}[mode] + int(self.tilt)
        self.i_ax, self.i_rad = {"rigid": (0, 1), "compliant": (0, 1), "spring": (0, 2)}[mode]
        self.i_tilt = self.n - 1 if self.tilt else None

    def split(self, u):
        """(a (2, N), rho (N,), x (N,))."""
        s = self.s
        if self.mode == "rigid":
            x, rho = u[0], u[1]
            return s * (self.dz + x) + self.e, rho, x
        if self.mode == "compliant":
            return u[2:4], u[1], u[0]
        a = u[0:2]
        return a, u[2], s[0, 0] * a[0] - self.dz[0]

    def theta(self, u):
        """Rotor tilt (rad), (N,); zero without tilt arms."""
        return u[self.i_tilt] / self.lam if self.tilt else np.zeros(u.shape[1])

    def _maps(self, u):
        a, rho, _ = self.split(u)
        if not self.tilt:
            return (self.X0 + a, self.Ynom, rho, self.cos_psi)
        return (self.X0 + a, self.Ynom, rho, self.cos_psi, u[self.i_tilt], self.gx / self.lam,
                self.gy / self.lam)

    def positions(self, u):
        """Every ball's (X, Y, cos psi, gx, gy) (`contact.ball_positions`)."""
        return ball_positions(*self._maps(u))

    def state(self, u, Kn, dlnKn_dalpha=None, angles: bool = True) -> BallSetState:
        """The balls at u (`contact.ball_set_state`; angles=False: without their angles)."""
        m = self._maps(u)
        return ball_set_state(*m[:3], self.A_T, Kn, m[3], dlnKn_dalpha, *m[4:], angles=angles)

    def alpha(self, u):
        """Angle of every ball's groove-centre line, atan2(X, Y), (2, Z, N)."""
        X, Y = self.positions(u)[:2]
        return np.arctan2(X, Y)

    def assemble(self, u, st: BallSetState):
        """Pi, a magnitude scale of its terms, gradient (n, N) and Hessian/tangent (n, n, N)."""
        s, N = self.s, u.shape[1]
        a, rho, x = self.split(u)
        H = np.zeros((self.n, self.n, N))
        V, QD = st.V_Nmm.sum(axis=0), st.QD_Nmm.sum(axis=0)
        Rsum = st.Fr_N.sum(axis=0) - self.Fr
        krr = st.k_rr.sum(axis=0)
        if self.mode == "rigid":
            Pi_ext = self.Fa * x + self.Fr * rho
            Pi, Pabs = V - Pi_ext, QD + np.abs(self.Fa * x) + np.abs(self.Fr * rho)
            g = [(s * st.F_N).sum(axis=0) - self.Fa, Rsum]
            H[0, 0] = st.k_aa.sum(axis=0)
            H[0, 1] = (s * st.k_ar).sum(axis=0)
            H[1, 0] = (s * st.k_ra).sum(axis=0)
            H[1, 1] = krr
        elif self.mode == "compliant":
            c = self.c
            gap = a - (s * (self.dz + x) + self.e)
            Es = (gap * gap).sum(axis=0) / (2.0 * c)
            Pi = V + Es - self.Fa * x - self.Fr * rho
            Pabs = QD + Es + np.abs(self.Fa * x) + np.abs(self.Fr * rho)
            g = [-(s * gap).sum(axis=0) / c - self.Fa, Rsum,
                 st.F_N[0] + gap[0] / c, st.F_N[1] + gap[1] / c]
            H[0, 0] = 2.0 / c
            for j in range(2):
                H[0, 2 + j] = H[2 + j, 0] = -s[j, 0] / c
                H[2 + j, 2 + j] = st.k_aa[j] + 1.0 / c
                H[2 + j, 1] = st.k_ar[j]
                H[1, 2 + j] = st.k_ra[j]
            H[1, 1] = krr
        else:
            work = (self.Freq * a).sum(axis=0) + self.Fr * rho
            Pi = V - work
            Pabs = QD + np.abs(self.Freq * a).sum(axis=0) + np.abs(self.Fr * rho)
            g = [st.F_N[0] - self.Freq[0], st.F_N[1] - self.Freq[1], Rsum]
            for j in range(2):
                H[j, j] = st.k_aa[j]
                H[j, 2] = st.k_ar[j]
                H[2, j] = st.k_ra[j]
            H[2, 2] = krr
        if self.tilt:
            # theta-row and -column: d/d(a_j) enters through s_j (rigid: via x) or directly
            t, i_r = self.i_tilt, self.i_rad
            Mt = self.M / self.lam
            Pi = Pi - Mt * u[t]
            Pabs = Pabs + np.abs(Mt * u[t])
            g.append(st.M_Nmm.sum(axis=0) - Mt)
            if self.mode == "rigid":
                H[0, t] = (s * st.k_at).sum(axis=0)
                H[t, 0] = (s * st.k_ta).sum(axis=0)
            else:
                ia = (2, 3) if self.mode == "compliant" else (0, 1)
                for j in range(2):
                    H[ia[j], t] = st.k_at[j]
                    H[t, ia[j]] = st.k_ta[j]
            H[i_r, t] = st.k_rt.sum(axis=0)
            H[t, i_r] = st.k_tr.sum(axis=0)
            H[t, t] = st.k_tt.sum(axis=0)
        return Pi, Pabs, np.stack(g), H



def _broadcast_ellipses(c: ContactEllipses, shape) -> ContactEllipses:
    """Every field of `c` as an array of the ball-set shape (2, Z, N)."""
    return ContactEllipses(*(np.array(np.broadcast_to(getattr(c, f), shape))
                             for f in ContactEllipses.__dataclass_fields__))


def _combined_group(g: BearingGeometry, mode: str, s, dr, dz, tg: ThermalGeometry, Fa, Fr, c, e,
                    Freq, lost_spring, u0, tol, max_outer, solve=True,
                    M=None, span=None, speed_rpm=None, control: str = "outer"):
    """Solve (or, with solve=False, only evaluate at u0, where rho = theta = 0) one group of
    points of one preload mode and return their `PairState` (with its `radial` part).  With a
    bearing span the rotor tilt is an unknown (moment M).  With speed_rpm ((N,)) every ball is
    quasi-dynamic (`dynamic.DynamicBallSet`, raceway control `control`): the outer loop
    refreshes the frozen ball forces instead of K_n, until the contact angles change by less
    than `ball_dynamics` tolerance (1e-12 rad)."""
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    psi = ball_azimuths_rad(g.Z)
    tilt = {}
    if span is not None:
        gx, gy = tilt_arms_mm(g, tg, s, span)
        lam = float(np.max(np.hypot(gx, gy)))
        tilt = dict(gx=gx, gy=gy, M=M, lam=lam)
        u0 = np.vstack([u0, np.zeros(u0.shape[1])])
    prob = CombinedProblem(mode, s, X0, Y0 + dr, tg.A_T_mm, np.cos(psi), Fa, Fr, dz, e, c, Freq,
                           **tilt)
    tg3 = ThermalGeometry(*(v[:, None, :] for v in
                            (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    u = u0
    dyn = None
    if speed_rpm is not None:
        shape = (2, g.Z, u.shape[1])
        dyn = DynamicBallSet(g, tg3, np.asarray(speed_rpm, float)[None, None, :], control, shape)
        if prob.tilt:
            dyn.set_tilt(s, prob.lam)
        u, ok, st = _solve_dynamic(prob, dyn, u, 0.1 * g.A0_mm, max_outer, control)
        inner, outer = dyn.contacts()
        ok = ok & dyn.ball_ok.reshape(shape).all(axis=(0, 1))
    else:
        # at u0 (no radial motion, no tilt) every ball of a bearing has the same angle: K_n once
        cs = contact_stiffness(g, tg3, prob.alpha(u)[:, :1, :])
        ok = np.ones(u.shape[1], bool)
        if solve:
            cap = 0.1 * g.A0_mm
            u, cs = _full_newton_start(prob, g, tg3, cs, u, cap)
            for _ in range(max_outer):
                Kn = cs.Kn
                root = newton_minimise(lambda uu: prob.assemble(uu, prob.state(uu, Kn, angles=False)), u, cap)
                u = root.x
                cs_new = contact_stiffness(g, tg3, prob.alpha(u))
                done = bool(np.all(np.abs(cs_new.Kn / cs.Kn - 1.0) <= tol))
                cs = cs_new
                if done:  # u solves the equilibrium with K_n matching the exact K_n at its angles to tol
                    break
            ok = root.converged & done
        ok = ok & cs.converged.all(axis=(0, 1))
        # final state: K_n exact at the final angles, full tangent (with dK_n/dalpha)
        st = prob.state(u, cs.Kn, cs.dlnKn_dalpha)
    _, _, _, J = prob.assemble(u, st)
    a, rho, x = prob.split(u)
    Jm = np.moveaxis(J, -1, 0)

    def condensed(i):
        """d(load)/d(u_i) with the other unknowns free: J_ii - J_ir J_rr^+ J_ri (= 1/(J^-1)_ii;
        the pseudo-inverse gives 0 along a displacement no loaded ball resists).  J_rr^+ J_ri by
        a linear solve where J_rr is well conditioned (1-norm condition number below 1e10, from
        its inverse; Golub & Van Loan ch. 2.6 and 3.5: the two then agree to that number times
        the rounding unit) and by the SVD pseudo-inverse elsewhere."""
        r = [m for m in range(prob.n) if m != i]
        Jrr, Jri = Jm[:, r][:, :, r], Jm[:, r, i]
        eye = np.eye(len(r))
        with np.errstate(all="ignore"):
            try:
                inv = np.linalg.inv(Jrr)
            except np.linalg.LinAlgError:               # an exactly singular block somewhere
                inv = np.full_like(Jrr, np.nan)
            cond = np.abs(Jrr).sum(axis=1).max(axis=1) * np.abs(inv).sum(axis=1).max(axis=1)
        bad = ~(cond <= 1e10)                           # (NaN: not finite)
        y = np.linalg.solve(np.where(bad[:, None, None], eye, Jrr), Jri[..., None])[..., 0]
        if bad.any():
            y[bad] = np.einsum("nrs,ns->nr", np.linalg.pinv(Jrr[bad]), Jri[bad])
        return Jm[:, i, i] - np.einsum("nr,nr->n", Jm[:, i, r], y)
    k_ax, k_rad = condensed(prob.i_ax), condensed(prob.i_rad)
    if prob.tilt:
        theta = prob.theta(u)
        k_tilt = condensed(prob.i_tilt) * prob.lam ** 2        # dM/dtheta, N mm/rad
        # bearing j's own moment about its ball plane: M_j - z_j Fr_j (z_j = -+span/2)
        zj = np.array([-0.5 * span, 0.5 * span])[:, None]
        M_own = st.M_Nmm * prob.lam - zj * st.Fr_N
        rho_j = rho + theta * zj
    else:
        theta = np.zeros(u.shape[1])
        k_tilt = np.full(u.shape[1], np.nan)
        M_own = np.zeros_like(st.Fr_N)
        rho_j = np.broadcast_to(rho, st.Fr_N.shape)

    Q, alpha, delta = st.Q_N, st.alpha_rad, st.delta_mm
    FA_, FB_ = st.F_N
    if mode == "spring":
        lost = lost_spring | (FA_ <= 0.0)
        k_eff = st.k_aa
        k_pair = np.where(FA_ > 0.0, k_ax, 0.0)
        e_out = np.full(u.shape[1], np.nan)
    else:
        lost = (st.F_N <= 0.0).any(axis=0)
        cc = 0.0 if mode == "rigid" else c
        k_eff = st.k_aa / (1.0 + cc * st.k_aa)
        k_pair = k_ax
        e_out = e
    im = np.argmax(Q, axis=1)[:, None, :]

    def top(v):                               # value at the most loaded ball of each bearing
        return np.take_along_axis(np.broadcast_to(v, Q.shape), im, axis=1)[:, 0, :]

    loaded = delta > 1e-12 * tg3.A_T_mm
    dynamic, outer_balls = None, {}
    if dyn is None:
        inner, outer = (contact_ellipses(g, cs, Q, side) for side in (0, 1))
    else:
        a_o = dyn.angles()[1]
        Q_o = dyn.loads()[1]
        ex = dyn.extras()
        outer_balls = dict(ball_loads_outer_N=Q_o, ball_contact_angles_outer_deg=np.degrees(a_o),
                           ball_outer_control=dyn.outer_control())
        dynamic = DynamicContacts(
            contact_angle_inner_deg=np.degrees(top(alpha)), contact_angle_outer_deg=np.degrees(top(a_o)),
            load_inner_N=top(Q), load_outer_N=top(Q_o), centrifugal_force_N=top(ex.F_c),
            gyroscopic_moment_Nmm=top(ex.M_g), spin_to_roll=top(ex.spin_to_roll),
            cage_speed_rpm=top(ex.cage_rpm),
            outer_control=top(dyn.outer_control()))
    radial = RadialLoadState(
        rho_mm=rho, radial_force_N=st.Fr_N, max_ball_load_N=Q.max(axis=1),
        loaded_zone=loaded.mean(axis=1), radial_stiffness_N_per_um=1e-3 * k_rad,
        tilt_rad=theta, bearing_rho_mm=rho_j, bearing_moment_Nmm=M_own,
        moment_stiffness_Nmm_per_mrad=1e-3 * k_tilt,
        max_contact_pressure_MPa=np.maximum(inner.p_max_MPa, outer.p_max_MPa).max(axis=1),
        ball_loads_N=Q, ball_contact_angles_deg=np.degrees(alpha),
        ball_inner=_broadcast_ellipses(inner, Q.shape), ball_outer=_broadcast_ellipses(outer, Q.shape),
        **outer_balls)
    top_inner, top_outer = (ContactEllipses(*(top(getattr(c, f)) for f in ContactEllipses.__dataclass_fields__))
                            for c in (inner, outer))
    return pair_state(F_N=st.F_N, alpha_rad=top(alpha), Q_N=top(Q), delta_mm=top(delta),
                      inner=top_inner, outer=top_outer,
                      max_contact_pressure_MPa=np.maximum(inner.p_max_MPa, outer.p_max_MPa).max(axis=(0, 1)),
                      k_bearing_N_per_mm=k_eff, k_pair_N_per_mm=k_pair, lost=lost, x_mm=x,
                      offset_mm=e_out, approach_mm=a,
                      converged=ok & np.isfinite(st.F_N).all(axis=0),
                      radial=radial, dynamic=dynamic)


#: full Newton step (mm, relative to 1 + max|u|) below which the next one is at rounding level
FULL_NEWTON_STOP = 1e-9


def _full_newton_start(prob: CombinedProblem, g: BearingGeometry, tg3: ThermalGeometry,
                       cs, u, cap, max_iter: int = 6):
    """A start for the K_n refresh loop of `_combined_group` close to the equilibrium with K_n
    exact at every ball's angle: the potential with K_n frozen at u's angles minimised to a loose
    tolerance (`roots.newton_minimise`, full steps below 1e-6 (1 + max|u|) mm: the frozen K_n
    is off by far more), then Newton's method on the full equations, K_n exact at the current
    angles and the tangent with dK_n/dalpha (`CombinedProblem.state`; Dennis & Schnabel 1983
    ch. 5: quadratic convergence, so a step below FULL_NEWTON_STOP leaves the next one at rounding
    level).  A point whose full step is not finite or exceeds `cap` stays where it is (the refresh
    loop takes it from there, as before).  Returns (u, `ContactStiffness` at u's angles: after a
    last step below FULL_NEWTON_STOP its K_n from the first-order model about the angles before
    that step; the refresh loop then checks K_n exactly, as for every pass)."""
    u = newton_minimise(lambda uu: prob.assemble(uu, prob.state(uu, cs.Kn, angles=False)), u, cap,
                        xtol=1e-6).x
    for _ in range(max_iter):
        alpha = prob.alpha(u)
        cs = contact_stiffness(g, tg3, alpha)
        _, _, gr, J = prob.assemble(u, prob.state(u, cs.Kn, cs.dlnKn_dalpha, angles=False))
        d = newton_direction(gr, J)
        step = np.abs(d).max(axis=0)
        take = np.isfinite(step) & (step <= cap)
        u = u + np.where(take, d, 0.0)
        if np.all(~take | (step <= FULL_NEWTON_STOP * (1.0 + np.abs(u).max(axis=0)))):
            # the last step was below FULL_NEWTON_STOP: K_n at the new angles from its linear
            # model (the error, second order in the angle change, is below rounding level)
            dalpha = prob.alpha(u) - alpha
            return u, replace(cs, Kn=cs.Kn * np.exp(cs.dlnKn_dalpha * dalpha))
    return u, contact_stiffness(g, tg3, prob.alpha(u))


def _solve_dynamic(prob: CombinedProblem, dyn: "DynamicBallSet", u, cap, max_outer, control):
    """The outer loop of the quasi-dynamic ball set: freeze the ball forces at the contact
    angles, minimise the pair's potential (`roots.newton_minimise`), re-read the angles; for
    control "jones" the controlling raceway is re-chosen during the first passes
    (`ball_dynamics.JONES_FREE_PASSES`).  Returns (u, converged per point, the balls' state at u
    with the final frozen forces)."""
    a_i = a_o = prob.alpha(u)
    done = np.zeros(u.shape[1], bool)
    relax, last = np.ones(u.shape[1]), np.full(u.shape[1], np.inf)
    for n_pass in range(max_outer):
        dyn.freeze(a_i, a_o)
        u = newton_minimise(lambda uu: prob.assemble(uu, dyn.state(*prob.positions(uu),
                                                                   prob.theta(uu))), u, cap,
                            max_iter=60).x
        dyn.state(*prob.positions(u), prob.theta(u))     # the balls at u: their angles and loads
        n_i, n_o = dyn.angles()
        Q_i, Q_o = dyn.loads()
        change = np.maximum(np.where(Q_o > 0, np.abs(n_o - a_o), 0.0),
                            np.where(Q_i > 0, np.abs(n_i - a_i), 0.0)).max(axis=(0, 1))
        a_i, a_o, relax = bd.relaxed_update(a_i, a_o, n_i, n_o, change, last, relax)
        last = change
        done = change <= BALL_ANGLE_TOL_RAD
        if (control == "jones" and n_pass < bd.JONES_FREE_PASSES
                and dyn.switch_control(a_i, a_o)):
            done[:] = False
            last[:] = np.inf         # the next pass's change comes from the switch
        if done.all():
            break
    dyn.freeze(a_i, a_o)
    # converged: the generalised residual forces within 1e-10 of the forces involved (the ball
    # equilibria inside carry their own rounding, so the potential cannot judge the last digits)
    st = dyn.state(*prob.positions(u), prob.theta(u))
    g = prob.assemble(u, st)[2]
    scale = st.Q_N.sum(axis=(0, 1)) + np.abs(prob.Fa) + np.abs(prob.Fr)
    if prob.tilt:
        scale = scale + np.abs(prob.M / prob.lam)
    return u, done & (np.abs(g).max(axis=0) <= 1e-10 * scale), st


def solve_pair_combined(g: BearingGeometry, arrangement: str = "DB", *, dr_mm=0.0, dz_mm=0.0,
                        T_inner_ring_C=None, T_outer_ring_C=None, T_ball_C=None,
                        T_ref_C: float = 20.0, preload_kind: str = "position",
                        preload_assembled_N=100.0, axial_load_N=0.0, radial_load_N=0.0,
                        dr_ref_mm=0.0, dz_ref_mm=0.0, compliance_mm_per_N=0.0,
                        tol: float = 1e-14, max_outer: int = 30, chunk: int = 8192,
                        moment_Nmm=0.0,
                        bearing_span_mm=None, speed_rpm=None,
                        control: str = "outer") -> PairState:
    """Pair equilibrium under combined axial and radial load with the quasi-static load
    distribution around the ball set (Harris & Kotzalas Vol. 1 ch. 7; Jones 1960), vectorised
    over N operating points.  `analytic.bearing.solve_pair` calls this when a radial load is given.

    Model: each bearing j has Z balls at psi_k = 2 pi k / Z from the radial load direction.  The
    rigid rotor moves radially by rho (mm, along psi = 0) and axially by x; without a bearing span
    it does not tilt (rho common to both bearings, the radial load shared according to that
    common displacement), with one it also tilts (below):

        X_jk = A0 sin(a0) + a_j,  Y_jk = A0 cos(a0) + dr_j + rho cos(psi_k)
        delta_jk = sqrt(X^2 + Y^2) - A_T,  Q_jk = K_n(alpha_jk) delta_jk^1.5 (0 if delta <= 0)
        sum_j s_j sum_k Q_jk sin(alpha_jk) = axial_load_N
        sum_j sum_k Q_jk cos(alpha_jk) cos(psi_k) = radial_load_N

    with a_j, e, c and the spring preload exactly as in `solve_pair` (module docstring), K_n of
    every ball at its own contact angle.  No centrifugal or gyroscopic ball loads, rigid rings.

    Solution: with K_n of every ball frozen the equations are the stationarity conditions of a
    convex potential (`CombinedProblem`), minimised by Newton's method with a capped step and
    Armijo backtracking (`roots.newton_minimise`); an outer loop refreshes K_n at the new contact
    angles until it changes by less than tol.  Start: the axial-only solution
    (`axial.solve_pair_axial`, which also gives the position-preload offset e), rho = 0, taken
    close to the solution first (`_full_newton_start`: the frozen-K_n minimisation to a loose
    tolerance, then Newton on the full equations with K_n exact and dK_n/dalpha in the tangent),
    so that the refresh loop usually ends after one pass.

    Tilt and moment (bearing_span_mm given: the distance between the two bearings' ball planes,
    B minus A, mm): the rotor is a rigid body free to tilt by theta about the axis normal to the
    load plane, the radial load acts at the mid-point between the ball planes and moment_Nmm
    (N mm, scalar or (N,); tilting the rotor at higher z towards psi = 0) about it.  Each ball
    then also moves with the tilt (`tilt_arms_mm`: axial at the inner groove-centre radius, radial
    at its distance from the mid-point), and sum_j M_j = moment_Nmm joins the equations.  Without
    a span the rotor is held against tilt (a moment is refused).

    Inputs: those of `solve_pair`, plus radial_load_N (N, scalar or (N,); negative values point
    to psi = 180 deg).  Points with zero radial load and moment keep the axial-only state
    unchanged (the radial part evaluated at that state, rho = theta = 0).

    Returns a `PairState` whose per-bearing ball quantities (ball load, deflection, contact angle,
    ellipses) refer to the most loaded ball of that bearing, axial_force_N = sum_k Q sin(alpha),
    axial_stiffness_N_per_um = dF_j/da_j at fixed rho, pair_axial_stiffness_N_per_um = dF_ext/dx
    at constant radial load, max_contact_pressure_MPa the largest over all balls and both
    contacts; and its `radial` part (`RadialLoadState`): rho_mm, radial_force_N, max_ball_load_N,
    loaded_zone (fraction of balls with delta > 1e-12 A_T), radial_stiffness_N_per_um (dF_r/drho
    at constant axial load, x free, including dK_n/dalpha), tilt_rad, bearing_rho_mm,
    bearing_moment_Nmm (each bearing's moment about its own ball plane),
    moment_stiffness_Nmm_per_mrad, max_contact_pressure_MPa per bearing and every ball's state,
    ball_loads_N, ball_contact_angles_deg and its inner and outer contact ellipses (ball_inner,
    ball_outer), of shape (2, Z, N), ball k at `contact.ball_azimuths_rad(Z)[k]`.

    Balls at speed (speed_rpm given, scalar or (N,)): every ball quasi-dynamic
    (`dynamic.DynamicBallSet`: centrifugal force, gyroscopic moment, raceway control `control`),
    its inner contact carrying the ring's loads; start and position-preload offset from the
    quasi-dynamic axial pair (`dynamic.solve_pair_dynamic`); every point is solved (also those
    without radial load or moment), and the state gains `dynamic` (the most loaded ball's
    contacts) and every ball's outer contact in `radial`.
    """
    N = n_points(dr_mm, dz_mm, T_inner_ring_C, T_outer_ring_C, T_ball_C, preload_assembled_N,
                 axial_load_N, dr_ref_mm, dz_ref_mm, compliance_mm_per_N, radial_load_N,
                 moment_Nmm)
    M = np.broadcast_to(np.asarray(moment_Nmm, float), (N,))
    if bearing_span_mm is None and np.any(M != 0.0):
        raise ValueError("a moment load needs bearing_span_mm (the rotor tilts about the pair)")
    span = None if bearing_span_mm is None else float(bearing_span_mm)
    if span is not None and not span > 0.0:
        raise ValueError(f"bearing_span_mm must be positive, got {bearing_span_mm!r}")
    axial = dict(dr_mm=dr_mm, dz_mm=dz_mm, T_inner_ring_C=T_inner_ring_C,
                 T_outer_ring_C=T_outer_ring_C, T_ball_C=T_ball_C, T_ref_C=T_ref_C,
                 preload_kind=preload_kind, preload_assembled_N=preload_assembled_N,
                 axial_load_N=np.broadcast_to(np.asarray(axial_load_N, float), (N,)),
                 dr_ref_mm=dr_ref_mm, dz_ref_mm=dz_ref_mm,
                 compliance_mm_per_N=compliance_mm_per_N, tol=tol)
    if speed_rpm is None:
        base = solve_pair_axial(g, arrangement, N, max_outer=max_outer, **axial)
        speed = None
    else:
        speed = np.broadcast_to(np.asarray(speed_rpm, float), (N,))
        base = solve_pair_dynamic(g, arrangement, N, speed_rpm=speed, control=control, **axial)
    Fr = np.broadcast_to(np.asarray(radial_load_N, float), (N,))
    s = SIGNS[arrangement][:, None]
    P = np.broadcast_to(np.asarray(preload_assembled_N, float), (N,))
    Fa = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
    dr, dz = pair_array(dr_mm, N), pair_array(dz_mm, N)
    tg = pair_thermal_geometry(g, T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref_C, N)
    e = base.preload_offset_mm
    x0 = base.x_mm
    ap0 = base.approach_mm
    if preload_kind == "spring":
        FA_req = s[0, 0] * Fa + P
        Freq = np.stack([np.maximum(FA_req, 0.0), P])
        lost_spring = FA_req < 0.0
        modes = {"spring": np.ones(N, bool)}
    else:
        Freq, lost_spring = None, None
        modes = {"rigid": c == 0.0, "compliant": c != 0.0}

    Zb = (2, g.Z, N)
    out = replace(base, radial=RadialLoadState(
        rho_mm=np.zeros(N), radial_force_N=np.zeros((2, N)), max_ball_load_N=np.zeros((2, N)),
        loaded_zone=np.zeros((2, N)), radial_stiffness_N_per_um=np.zeros(N),
        tilt_rad=np.zeros(N), bearing_rho_mm=np.zeros((2, N)), bearing_moment_Nmm=np.zeros((2, N)),
        moment_stiffness_Nmm_per_mrad=np.zeros(N), max_contact_pressure_MPa=np.zeros((2, N)),
        ball_loads_N=np.zeros(Zb), ball_contact_angles_deg=np.zeros(Zb),
        ball_inner=ContactEllipses(*(np.zeros(Zb) for _ in range(5))),
        ball_outer=ContactEllipses(*(np.zeros(Zb) for _ in range(5))),
        **({} if speed is None else dict(ball_loads_outer_N=np.zeros(Zb),
                                         ball_contact_angles_outer_deg=np.zeros(Zb),
                                         ball_outer_control=np.ones(Zb, bool)))))
    for mode, mmask in modes.items():
        loaded = (Fr != 0.0) | (M != 0.0) | (speed is not None)
        for solve, smask in ((False, ~loaded), (True, loaded)):
            ids = np.flatnonzero(mmask & smask)
            for i0 in range(0, ids.size, chunk):
                ii = ids[i0:i0 + chunk]
                zero = np.zeros(ii.size)
                if mode == "rigid":
                    u0 = np.stack([x0[ii], zero])
                elif mode == "compliant":
                    u0 = np.stack([x0[ii], zero, ap0[0, ii], ap0[1, ii]])
                else:
                    u0 = np.stack([ap0[0, ii], ap0[1, ii], zero])
                res = _combined_group(
                    g, mode, s, dr[:, ii], dz[:, ii],
                    ThermalGeometry(*(v[:, ii] for v in (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm))),
                    Fa[ii], Fr[ii], c[ii], e[ii], None if Freq is None else Freq[:, ii],
                    None if lost_spring is None else lost_spring[ii], u0, tol, max_outer,
                    solve=solve, M=M[ii], span=span,
                    speed_rpm=None if speed is None else speed[ii], control=control)
                if solve:
                    out = with_rows(out, ii, res)
                else:           # the axial solution stands; add the radial outputs at it
                    out = replace(out, radial=with_rows(out.radial, ii, res.radial))
    return out
