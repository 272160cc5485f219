"""The pair at speed: the axial-only pair equilibrium of `axial.solve_pair_axial` with every ball in
its quasi-dynamic equilibrium (`ball_dynamics.solve_balls`: centrifugal force, gyroscopic moment,
raceway control; Jones 1960; Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 ch. 3).
Units: mm, N, rpm; radians inside.

Same conventions as the quasi-static pair (`analytic.bearing` module docstring): bearing j's inner
groove centre sits at (X_j, Y_j) from its outer one,

    X_j = A0 sin(alpha0) + a_j,   a_j = s_j (dz_j + x) + e - c F_j,   Y_j = A0 cos(alpha0) + dr_j

and the rotor position x solves sum_j s_j F_j = axial_load_N.  What changes at speed is the
bearing's axial force: F_j = Z (Q_i,j sin(alpha_i,j) + f_i,j cos(alpha_i,j)), the axial component of
the INNER ring's load from a ball in its own equilibrium between the raceways (the inner ring
carries the shaft's loads; f_i the inner raceway's gyroscopic friction, nonzero under inner-race
control: `ball_dynamics` module docstring, so that the outer rings carry the same load);
the outer contact additionally carries the centrifugal force, so alpha_o < alpha_i and Q_o > Q_i.
dF_j/dX_j = Z (d(Q_i n_i)/dP)_aa, the series tangent of the ball (`ball_dynamics` module docstring).

The position-preload offset e is set at the assembly state, at rest (`axial.reference_state`):
at speed 0 the balls' equilibrium is the quasi-static contact, so this solver reproduces
`solve_pair_axial` there (tests: 1e-9).  Spring preload: F_B = P, F_A = s_A axial_load + P as in
the quasi-static pair, each bearing's X found for its force.

Solution.  Nested safeguarded Newton iterations (`roots.newton_increasing`) on monotone scalar
equations, each evaluation solving every ball to convergence: x for the pair's axial equilibrium;
inside it, with a preload-path compliance c, X_j + c F_j(X_j) = X_nom,j per bearing.  The
derivative used is the frozen tangent (K, F_c, M_g and friction directions held), so Newton
converges linearly at the rate of their dependence on the angles; the bracket keeps it safe.

Not modelled: radial load and moment at speed (the pair's combined-load solver is quasi-static;
one bearing at speed under any load: `single.solve_single`), cage and lubricant drag forces on
the ball, ring centrifugal growth beyond what the FE gives (the FE spins the rotor's parts).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from analytic.bearing.axial import reference_state
from analytic.bearing.ball_dynamics import BallDynamics, solve_balls
from analytic.bearing import ball_dynamics as bd
from analytic.bearing.contact import project_balls
from analytic.bearing.geometry import (SIGNS, BearingGeometry, ThermalGeometry, broadcast_geometry,
                                       pair_array, pair_thermal_geometry)
from analytic.bearing.roots import Root, newton_increasing
from analytic.bearing.state import PairState, contact_ellipses, pair_state

#: step tolerance (mm) of the Newton iterations on the rotor and groove-centre positions
XTOL_MM = 1e-13


@dataclass(frozen=True)
class DynamicContacts:
    """What the quasi-dynamic balls add to a `PairState`, per bearing (2, N).  Every ball of a
    bearing alike (axial-only pair).  With speed 0 the inner and outer values coincide."""
    contact_angle_inner_deg: np.ndarray
    contact_angle_outer_deg: np.ndarray
    load_inner_N: np.ndarray
    load_outer_N: np.ndarray
    centrifugal_force_N: np.ndarray      # per ball, m omega_c^2 dm / 2
    gyroscopic_moment_Nmm: np.ndarray    # per ball, J omega_c omega_R sin(beta)
    spin_to_roll: np.ndarray             # inner contact
    cage_speed_rpm: np.ndarray
    outer_control: np.ndarray            # bool: the outer raceway controls


class _Balls:
    """Axial force of each bearing and its derivative at given X (2, N): the balls solved at
    speed, the last solution kept for the final state."""

    def __init__(self, g: BearingGeometry, tg: ThermalGeometry, Y, speed, control: str):
        self.g, self.tg, self.Y, self.speed, self.control = g, tg, Y, speed, control
        self.last: BallDynamics | None = None

    def __call__(self, X):
        b = solve_balls(self.g, X, self.Y, self.speed, control=self.control, tg=self.tg)
        self.last = b
        Z = self.g.Z
        return Z * b.inner_force_N[0], Z * b.tangent_N_per_mm[0, 0]


def _effective_X(balls: _Balls, Xnom, c) -> tuple[Root, np.ndarray, np.ndarray]:
    """X with X + c F(X) = X_nom per bearing (compliance c in series, F increasing in X);
    returns (Root, F, dF/dX) at the solution."""
    F0, k0 = balls(Xnom)
    if np.all(c == 0.0):
        return Root(Xnom, np.ones(np.shape(Xnom), bool)), F0, k0

    def fun(X):
        F, k = balls(X)
        return X + c * F - Xnom, 1.0 + c * k
    root = newton_increasing(fun, Xnom - c * F0 / (1.0 + c * k0), lo=Xnom - c * np.maximum(F0, 0.0),
                             hi=Xnom + c * np.maximum(-F0, 0.0), step0=1e-4, xtol=XTOL_MM)
    F, k = balls(root.x)
    return root, F, k


def solve_pair_dynamic(g: BearingGeometry, arrangement: str, N: int, *, dr_mm, dz_mm,
                       T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref_C: float,
                       preload_kind: str, preload_assembled_N, axial_load_N, dr_ref_mm,
                       dz_ref_mm, compliance_mm_per_N, speed_rpm, control: str = "outer",
                       tol: float = 1e-14) -> PairState:
    """Axial-only equilibrium of the pair at N points with quasi-dynamic balls at speed_rpm
    (scalar or (N,); inner rings rotate, outer rings fixed), raceway control "outer", "inner" or
    "jones" (`ball_dynamics`).  Other inputs as `analytic.bearing.solve_pair`.  Returns a
    `PairState` whose per-bearing contact angle, ball load and Hertz ellipses are those of the
    inner contact (the outer ellipses at the outer contact's load and angle) and whose
    `dynamic` part carries both contacts (`DynamicContacts`)."""
    s = SIGNS[arrangement][:, None]
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    P = np.broadcast_to(np.asarray(preload_assembled_N, float), (N,))
    Fext = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
    dr, dz = pair_array(dr_mm, N), pair_array(dz_mm, N)
    tg = pair_thermal_geometry(g, T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref_C, N)
    Y = Y0 + dr
    speed = pair_array(speed_rpm, N)
    balls = _Balls(g, tg, Y, speed, control)

    if preload_kind == "position":
        e, x_ref, _, _, ok = reference_state(g, s, P, c, pair_array(dr_ref_mm, N),
                                             pair_array(dz_ref_mm, N), tol)

        def residual(xx):
            root, F, k = _effective_X(balls, X0 + s * (dz + xx) + e, c)
            keff = k / (1.0 + c * k)
            return (s * F).sum(axis=0) - Fext, keff.sum(axis=0)

        root_x = newton_increasing(residual, x_ref, step0=1e-3 * g.Dw_mm, xtol=XTOL_MM)
        x = root_x.x
        eff, F, k = _effective_X(balls, X0 + s * (dz + x) + e, c)
        X = eff.x
        ok = ok & root_x.converged & eff.converged.all(axis=0)
        e_out = e
        k_eff = k / (1.0 + c * k)
        k_pair = k_eff.sum(axis=0)
        lost = (F <= 0.0).any(axis=0)
    else:
        FA = s[0, 0] * Fext + P
        lost_spring = FA < 0.0
        Freq = np.stack([np.maximum(FA, 0.0), P])

        def fun(XX):
            F, k = balls(XX)
            return F - Freq, k
        root = newton_increasing(fun, np.full((2, N), X0), step0=1e-3 * g.Dw_mm, xtol=XTOL_MM)
        X = root.x
        F, k = balls(X)
        ok = root.converged.all(axis=0)
        x = s[0, 0] * (X[0] - X0) - dz[0]
        e_out = np.full(N, np.nan)
        k_eff = k
        k_pair = np.where(F[0] > 0.0, k[0], 0.0)
        lost = lost_spring | (F[0] <= 0.0)

    b = balls.last
    ai, ao = np.radians(b.contact_angle_inner_deg), np.radians(b.contact_angle_outer_deg)
    inner = contact_ellipses(g, _shaped(b.cs_inner, (2, N)), b.load_inner_N, 0)
    outer = contact_ellipses(g, _shaped(b.cs_outer, (2, N)), b.load_outer_N, 1)
    dyn = DynamicContacts(
        contact_angle_inner_deg=b.contact_angle_inner_deg,
        contact_angle_outer_deg=b.contact_angle_outer_deg, load_inner_N=b.load_inner_N,
        load_outer_N=b.load_outer_N, centrifugal_force_N=b.centrifugal_force_N,
        gyroscopic_moment_Nmm=b.gyroscopic_moment_Nmm, spin_to_roll=b.spin_to_roll,
        cage_speed_rpm=b.cage_speed_rpm, outer_control=b.outer_control)
    return pair_state(F_N=F, alpha_rad=ai, Q_N=b.load_inner_N,
                      delta_mm=b.approach_inner_mm + b.approach_outer_mm, inner=inner, outer=outer,
                      max_contact_pressure_MPa=np.maximum(inner.p_max_MPa, outer.p_max_MPa).max(axis=0),
                      k_bearing_N_per_mm=k_eff, k_pair_N_per_mm=k_pair, lost=lost, x_mm=x,
                      offset_mm=e_out, approach_mm=X - X0,
                      converged=ok & b.converged.all(axis=0) & np.isfinite(F).all(axis=0)
                      & np.isfinite(ao).all(axis=0),
                      dynamic=dyn)


class DynamicBallSet:
    """Every ball of both bearings at speed for the combined-load pair solver
    (`combined._combined_group`): the ball equilibria of `ball_dynamics` with K, F_c, M_g and the
    friction directions frozen by `freeze`, condensed to each ball's inner groove centre (its
    potential W, force Q_i n_i and series tangent), then projected on the pair's generalised
    coordinates like the quasi-static balls (`contact.project_balls`).  Shapes (2, Z, N)."""

    def __init__(self, g: BearingGeometry, tg: ThermalGeometry, speed_rpm, control: str, shape):
        self.g, self.control, self.shape = g, control, shape
        bg = broadcast_geometry(tg, shape)
        self.tg = ThermalGeometry(*(v.ravel() for v in (bg.A_T_mm, bg.Dw_mm, bg.f_i, bg.f_o,
                                                         bg.dm_mm)))
        self.speed = np.broadcast_to(np.asarray(speed_rpm, float), shape).ravel()
        self.outer_ctl = np.ones(self.speed.size, bool)
        self.u_prev = None
        self.tilt_sign = None    # with a rotor tilt: s_j (2, 1), the bearings' contact senses

    def set_tilt(self, s, lam: float) -> None:
        """A rotor tilt theta is an unknown, as u_t = lam theta (`combined.CombinedProblem`), s the
        bearings' contact senses (2, 1): the inner raceway friction's couples
        (`ball_dynamics.friction_couple_Nmm`, about the bearing's own y axis) then enter the tilt
        equation as s_j M_y,j."""
        self.tilt_sign, self.lam = np.asarray(s, float), float(lam)

    def freeze(self, a_i, a_o) -> None:
        """Freeze K, F_c, M_g and the friction directions at the contact angles (2, Z, N)."""
        shares = bd.control_shares(self.control, self.outer_ctl)
        self.fz, ex, self.cs_i, self.cs_o = bd.frozen_forces(self.g, self.tg, a_i.ravel(),
                                                             a_o.ravel(), self.speed, shares)
        self.f_i = np.broadcast_to(ex.f_i, self.speed.shape).reshape(self.shape)

    def state(self, X, Y, cpsi, gx=None, gy=None, theta_rad=None):
        """`contact.BallSetState` of the balls at groove-centre distances X, Y (2, Z, N); with a
        tilt (gx, gy and theta_rad given, `set_tilt` called) the moment and the potential carry
        the frozen friction couples, s_j M_y,j theta."""
        P = np.stack([X.ravel(), Y.ravel()])
        u0 = bd.static_split(P, self.fz) if self.u_prev is None else self.u_prev
        Dw = float(np.max(self.tg.Dw_mm))
        root, W, W_abs, F_in, Kt, p = bd.frozen_equilibrium(P, u0, self.fz, Dw)
        if self.u_prev is not None and not root.converged.all():
            root, W, W_abs, F_in, Kt, p = bd.frozen_equilibrium(P, bd.static_split(P, self.fz),
                                                                self.fz, Dw)
        self.u_prev, self.ball_ok, self.p = root.x, root.converged, p
        r = lambda v: np.asarray(v).reshape(self.shape)  # noqa: E731
        tangent = tuple(r(Kt[i, j]) for i, j in ((0, 0), (0, 1), (1, 0), (1, 1)))
        st = project_balls(r(p.Q_i), r(p.dl_i + p.dl_o), self.angles()[0],
                           r(F_in[0]), r(F_in[1]), r(W), r(W_abs), tangent, cpsi, gx, gy)
        if gx is None or self.tilt_sign is None:
            return st
        tg = self.tg
        Mc = np.stack([self.tilt_sign[j] * bd.friction_couple_Nmm(
            self.g, ThermalGeometry(*(v.reshape(self.shape)[j, :1] for v in (
                tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm))), self.f_i[j])[1]
            for j in range(2)])
        if theta_rad is None:
            raise ValueError("DynamicBallSet.state: a tilt (set_tilt) needs theta_rad")
        th = np.asarray(theta_rad, float)
        return replace(st, M_Nmm=st.M_Nmm + Mc / self.lam, V_Nmm=st.V_Nmm + Mc * th,
                       QD_Nmm=st.QD_Nmm + np.abs(Mc * th))

    def angles(self):
        """(inner, outer) contact angles of the last state, rad, (2, Z, N)."""
        p = self.p
        return (np.arctan2(p.n_i[0], p.n_i[1]).reshape(self.shape),
                np.arctan2(p.n_o[0], p.n_o[1]).reshape(self.shape))

    def loads(self):
        """(inner, outer) contact loads of the last state, N, (2, Z, N)."""
        return self.p.Q_i.reshape(self.shape), self.p.Q_o.reshape(self.shape)

    def outer_control(self) -> np.ndarray:
        """True where the outer raceway controls the ball (the hypothesis in force), (2, Z, N)."""
        ctl = self.outer_ctl if self.control == "jones" else np.full(self.outer_ctl.shape,
                                                                      self.control == "outer")
        return ctl.reshape(self.shape)

    def switch_control(self, a_i, a_o) -> bool:
        """Control "jones": re-choose every ball's controlling raceway at the last state; True
        when any ball switched."""
        new = bd.jones_choice(self.g, self.tg, self.p, a_i, a_o)
        switched = bool(np.any(new != self.outer_ctl))
        self.outer_ctl = new
        return switched

    def contacts(self) -> tuple:
        """(inner, outer) `ContactEllipses` of every ball at the last state, (2, Z, N)."""
        Qi, Qo = self.loads()
        return (contact_ellipses(self.g, _shaped(self.cs_i, self.shape), Qi, 0),
                contact_ellipses(self.g, _shaped(self.cs_o, self.shape), Qo, 1))

    def extras(self) -> bd.BallExtras:
        """Centrifugal force, gyroscopic moment, spin-to-roll ratio, cage speed and raceway
        friction forces per ball at the frozen state, (2, Z, N)."""
        fz_i, fz_o = self.angles()
        _, ex, _, _ = bd.frozen_forces(self.g, self.tg, fz_i.ravel(), fz_o.ravel(), self.speed,
                                       bd.control_shares(self.control, self.outer_ctl))
        return bd.BallExtras(*(np.broadcast_to(v, self.speed.shape).reshape(self.shape)
                               for v in ex))


def _shaped(cs, shape):
    """A `ContactStiffness` of flat arrays (M,) / (2, M) reshaped to `shape` / (2,) + shape."""
    from dataclasses import fields, replace

    out = {}
    for f in fields(cs):
        v = np.asarray(getattr(cs, f.name))
        out[f.name] = v.reshape((2,) + shape) if v.ndim == 2 else v.reshape(shape)
    return replace(cs, **out)
