"""Tangent stiffness of a preloaded bearing pair at its equilibrium, for rotordynamics: the 5 x 5
matrix of the rigid rotor about the pair's centre, and of each bearing about its own centre
(Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 7; de Mul, Vree & Maas 1989,
J. Tribology 111; Lim & Singh 1990, J. Sound Vib. 139).  Units: mm, N, rad inside; the matrices
in N/mm (translation), N/rad = N mm/mm (coupling) and N mm/rad (tilt).

Degrees of freedom q = (x, y, z, theta_x, theta_y): rotor translation (x along the azimuth of
ball 0, the direction of the pair's radial load; z the pair's axis, + towards bearing B) and small
rotations about x and y (right-handed), about the reference point: the pair's centre (mid-point
of the two ball planes, where the pair solvers put the radial load and moment) or bearing j's own
ball plane.  A rigid rotation u = theta x r moves the inner groove curvature centre of ball k of
bearing j (azimuth psi_k, radius R_i, axial position z_c,j from the reference point) by

    dX_jk = s_j [dz + R_i (theta_x sin psi_k - theta_y cos psi_k)] - w_j          (axial)
    dY_jk = (dx + theta_y z_c,j) cos psi_k + (dy - theta_x z_c,j) sin psi_k      (radial)

(s_j the arrangement sign; R_i and z_c,j of `combined.tilt_arms_mm`, the maps the pair solvers use,
generalised to both planes), w_j the axial give of bearing j's preload path (compliance c_j:
energy w_j^2 / (2 c_j); a spring-preloaded bearing's outer ring floats, 1/c = 0; a rigid path has
w_j = 0).  The loads the balls carry are the generalised forces F_q = sum_k G^T f_k (f_k the ball's
force on its inner groove centre, (axial, radial)), and the tangent is

    K = sum_k G_k^T T_k G_k,      T_k = d f_k / d(X, Y)

followed by the static condensation of each w_j, K_qq - K_qw K_wq / (K_ww + 1/c_j) (springs in
series).  Rings rigid (the FE's ring compliance enters through c only); the FE groove-centre
shifts fix the equilibrium positions (X, Y) and do not change with q.

Ball tangent T_k.  Quasi-static balls: the exact tangent of f = K_n(alpha) delta^1.5 n
(`contact.ball_set_state`: 1.5 K_n delta^0.5 n n^T + (Q/D)(t t^T + dlnK_n/dalpha n t^T), K_n of
each ball at its own contact angle).  Quasi-dynamic balls (`ball_dynamics`): the ball centre u
solves g(u, P) = Q_o n_o - Q_i n_i - b(alpha_i, alpha_o) = 0 (P the inner groove centre, b the
centrifugal and gyroscopic friction forces, K_i, K_o at the contact angles), so by the implicit
function theorem

    dF_in/dP = (T_i + f_ai t_i^T / d_i)(I + A^-1 B) - f_ao t_o^T / d_o A^-1 B,
               A = dg/du = T_o + T_i + b_ai t_i^T / d_i - b_ao t_o^T / d_o,
               B = dg/dP = -T_i - b_ai t_i^T / d_i

(F_in = Q_i n_i + f, f the inner raceway's frozen friction on the ring, nonzero under inner-race
control, a function of both angles: `ball_dynamics` module docstring) with T = kn n n^T + (Q/d)(t t^T + dlnK/dalpha n t^T) per contact and b_a = db/dalpha; the
derivatives of K_i, K_o and b in the angles (smooth functions of one angle each, from
`ball_dynamics.frozen_forces`) by central differences with step ANGLE_STEP_RAD (truncation
O(h^2) and rounding O(eps/h): ~1e-10 of those terms, themselves small corrections).  Without
the b and dK terms this is the series tangent T_i (T_i + T_o)^-1 T_o of
`ball_dynamics.series_tangent`; at speed 0 it is the quasi-static one (tests).  Raceway
control: held at the equilibrium's choice.  Not included: the velocity-dependent (damping,
cross-coupled) terms of lubricated contacts.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing import ball_dynamics as bd
from analytic.bearing.combined import tilt_arms_mm
from analytic.bearing.contact import ball_azimuths_rad, ball_set_state, contact_stiffness
from analytic.bearing.geometry import (SIGNS, BearingGeometry, ThermalGeometry, pair_array,
                                       pair_thermal_geometry)
from analytic.bearing.state import PairState

#: order of the degrees of freedom of every matrix
DOFS = ("x", "y", "z", "theta_x", "theta_y")
#: central-difference step (rad) of the angle derivatives of K_i, K_o and the ball's frozen forces
ANGLE_STEP_RAD = 1e-5


@dataclass(frozen=True)
class PairBalls:
    """Every ball of the pair at its equilibrium and what maps rotor motion to it (arrays
    (2, Z, N) per ball, (2, N) per bearing, bearing A first)."""
    g: BearingGeometry
    tg: ThermalGeometry          # grown geometry, arrays (2, 1, N)
    s: np.ndarray                # (2, 1) arrangement signs
    X_mm: np.ndarray             # (2, Z, N) axial groove-centre distance at the equilibrium
    Y_mm: np.ndarray             # (2, Z, N) radial
    R_i_mm: np.ndarray           # (2, N) inner groove-centre radius
    z_c_mm: np.ndarray           # (2, N) axial position of the inner groove centres from the
    #                              pair's centre
    z_ball_mm: np.ndarray        # (2, N) ball plane of each bearing from the pair's centre
    inv_c_N_per_mm: np.ndarray   # (2, N) 1 / preload-path compliance (inf: rigid, 0: floating)
    speed_rpm: np.ndarray | None  # (N,); None: quasi-static balls
    control: str = "outer"

    @property
    def n_points(self) -> int:
        return self.X_mm.shape[-1]


@dataclass(frozen=True)
class BallTangents:
    """Ball forces on their inner groove centres and their tangents, (2, Z, N) each."""
    f_X_N: np.ndarray
    f_Y_N: np.ndarray
    T: tuple                     # (TXX, TXY, TYX, TYY) in N/mm
    converged: np.ndarray        # (N,)


@dataclass(frozen=True)
class PairStiffness:
    """Tangent stiffness at N equilibria.  DOF order `DOFS`; entries in N/mm, N/rad, N mm/rad.

    pair_N_mm_rad:    (N, 5, 5) of the rotor about the pair's centre
    bearing_N_mm_rad: (2, N, 5, 5) of each bearing about its own ball plane (A, B)
    loads_N_mm:       (5, N) loads the balls carry at the equilibrium about the pair's centre
                      (F_x, F_y, F_z in N; M_x, M_y in N mm): the applied loads, a check
    converged:        (N,) every ball state behind the matrices converged."""
    pair_N_mm_rad: np.ndarray
    bearing_N_mm_rad: np.ndarray
    loads_N_mm: np.ndarray
    converged: np.ndarray


def pair_balls(g: BearingGeometry, arrangement: str, state: PairState, *, dr_mm=0.0,
               T_inner_ring_C=None, T_outer_ring_C=None, T_ball_C=None, T_ref_C: float = 20.0,
               preload_kind: str = "position", compliance_mm_per_N=0.0, bearing_span_mm=None,
               speed_rpm=0.0, ball_model: str = "static", control: str = "outer",
               **_solver_only) -> PairBalls:
    """The balls of the pair at the equilibrium `state` that `analytic.bearing.solve_pair` found
    with these keyword arguments (the same dict may be passed; the arguments that only fix the
    loads and the reference state are not needed here).  Ball k of bearing j sits at

        X_jk = A0 sin a0 + a_j + theta gx_j cos psi_k
        Y_jk = A0 cos a0 + dr_j + (rho + theta gy_j) cos psi_k

    (`combined.solve_pair_combined`; rho, theta = 0 without `state.radial`).  bearing_span_mm is
    needed (the tilt arms)."""
    if bearing_span_mm is None or not float(bearing_span_mm) > 0.0:
        raise ValueError("the pair's stiffness needs bearing_span_mm > 0 (the tilt lever arms), "
                         f"got {bearing_span_mm!r}")
    N = state.preload_N.shape[0]
    s = SIGNS[arrangement][:, None]
    tg = pair_thermal_geometry(g, T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref_C, N)
    span = float(bearing_span_mm)
    gx, gy = tilt_arms_mm(g, tg, s, span)
    a0 = np.radians(g.alpha0_deg)
    cpsi = np.cos(ball_azimuths_rad(g.Z))[None, :, None]
    X = g.A0_mm * np.sin(a0) + np.asarray(state.approach_mm, float)
    Y = g.A0_mm * np.cos(a0) + pair_array(dr_mm, N)
    rho = theta = np.zeros(N)
    if state.radial is not None:
        rho, theta = state.radial.rho_mm, state.radial.tilt_rad
    Xk = X[:, None, :] + (theta * gx)[:, None, :] * cpsi
    Yk = Y[:, None, :] + (rho[None, :] + theta * gy)[:, None, :] * cpsi
    if preload_kind == "spring":        # bearing A holds the rotor, B's outer ring floats
        inv_c = np.stack([np.full(N, np.inf), np.zeros(N)])
    else:
        c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
        with np.errstate(divide="ignore"):
            inv_c = np.broadcast_to(np.where(c > 0.0, 1.0 / c, np.inf), (2, N))
    z_ball = np.stack([np.full(N, -0.5 * span), np.full(N, 0.5 * span)])
    tg3 = ThermalGeometry(*(np.asarray(v)[:, None, :] for v in
                            (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    speed = (None if ball_model == "static"
             else np.broadcast_to(np.asarray(speed_rpm, float), (N,)).copy())
    return PairBalls(g, tg3, s, np.broadcast_to(Xk, Yk.shape).copy(), Yk, -s * gx,
                     np.broadcast_to(gy, (2, N)).copy(), z_ball, np.asarray(inv_c, float),
                     speed, control)


def ball_tangents(balls: PairBalls, X_mm=None, Y_mm=None) -> BallTangents:
    """Every ball's force on its inner groove centre and its tangent at groove-centre distances
    X_mm, Y_mm (2, Z, N; default the equilibrium's), solved afresh with the pair's ball model
    (module docstring)."""
    X = balls.X_mm if X_mm is None else np.asarray(X_mm, float)
    Y = balls.Y_mm if Y_mm is None else np.asarray(Y_mm, float)
    if balls.speed_rpm is None:
        return _static_tangents(balls, X, Y)
    return _dynamic_tangents(balls, X, Y)


def _static_tangents(balls: PairBalls, X, Y) -> BallTangents:
    """Quasi-static balls: K_n exact at each ball's angle, `contact.ball_set_state` per ball
    (each ball as a set of one at psi = 0: its loads are (Q sin a, Q cos a), its k_* the
    tangent's entries)."""
    shape = X.shape
    cs = contact_stiffness(balls.g, balls.tg, np.arctan2(X, Y))
    M = shape[1] * shape[2]
    flat = lambda v: np.broadcast_to(v, shape).reshape(2, 1, M)  # noqa: E731
    st = ball_set_state(X.reshape(2, M), Y.reshape(2, M), np.zeros(M),
                        np.broadcast_to(balls.tg.A_T_mm, shape).reshape(2, M), flat(cs.Kn),
                        np.ones(1), flat(cs.dlnKn_dalpha))
    r = lambda v: v.reshape(shape)  # noqa: E731
    return BallTangents(r(st.F_N), r(st.Fr_N), (r(st.k_aa), r(st.k_ar), r(st.k_ra), r(st.k_rr)),
                        np.broadcast_to(cs.converged, shape).all(axis=(0, 1)))


def _dynamic_tangents(balls: PairBalls, X, Y) -> BallTangents:
    """Quasi-dynamic balls (`ball_dynamics.solve_balls`) and the full tangent of the module
    docstring."""
    g, shape = balls.g, X.shape
    speed = np.broadcast_to(balls.speed_rpm, shape)
    b = bd.solve_balls(g, X, Y, speed, control=balls.control, tg=balls.tg)
    M = X.size
    P = np.stack([X.ravel(), Y.ravel()])
    u = b.ball_centre_mm.reshape(2, M)
    v = P - u
    d_i, d_o = np.hypot(v[0], v[1]), np.hypot(u[0], u[1])
    n_i, n_o = v / d_i, u / d_o
    t_i, t_o = np.stack([n_i[1], -n_i[0]]), np.stack([n_o[1], -n_o[0]])
    a_i, a_o = np.arctan2(n_i[0], n_i[1]), np.arctan2(n_o[0], n_o[1])
    Q_i, Q_o = b.load_inner_N.ravel(), b.load_outer_N.ravel()
    dl_i, dl_o = b.approach_inner_mm.ravel(), b.approach_outer_mm.ravel()
    bg = ThermalGeometry(*(np.broadcast_to(getattr(balls.tg, f), shape).ravel()
                           for f in ThermalGeometry.__dataclass_fields__))
    shares = bd.control_shares(balls.control, b.outer_control.ravel())
    spd = speed.ravel()
    h = ANGLE_STEP_RAD
    fi_p, fi_m, fo_p, fo_m = (bd.frozen_forces(g, bg, ai, ao, spd, shares)[0]
                              for ai, ao in ((a_i + h, a_o), (a_i - h, a_o),
                                             (a_i, a_o + h), (a_i, a_o - h)))
    fz = bd.frozen_forces(g, bg, a_i, a_o, spd, shares)[0]
    dlnK_i = (fi_p.K_i - fi_m.K_i) / (2.0 * h * fz.K_i)
    dlnK_o = (fo_p.K_o - fo_m.K_o) / (2.0 * h * fz.K_o)
    b_ai = (fi_p.b - fi_m.b) / (2.0 * h)
    b_ao = (fo_p.b - fo_m.b) / (2.0 * h)
    T_i = _contact_tangent(n_i, t_i, 1.5 * fz.K_i * np.sqrt(dl_i), Q_i / d_i, dlnK_i)
    T_o = _contact_tangent(n_o, t_o, 1.5 * fz.K_o * np.sqrt(dl_o), Q_o / d_o, dlnK_o)
    Bi = b_ai[:, None, :] * t_i[None, :, :] / d_i
    A = T_o + T_i + Bi - b_ao[:, None, :] * t_o[None, :, :] / d_o
    B = -T_i - Bi
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    ok_det = np.abs(det) > 0.0
    sdet = np.where(ok_det, det, 1.0)
    inv = np.array([[A[1, 1], -A[0, 1]], [-A[1, 0], A[0, 0]]]) / sdet
    AB = np.einsum("ikm,kjm->ijm", inv, B)
    # the inner raceway's friction on the ring (inner-race control) through both angles
    f_ai = (fi_p.f_ring - fi_m.f_ring) / (2.0 * h)
    f_ao = (fo_p.f_ring - fo_m.f_ring) / (2.0 * h)
    T = (np.einsum("ikm,kjm->ijm", T_i + f_ai[:, None, :] * t_i[None, :, :] / d_i,
                   np.eye(2)[:, :, None] + AB)
         - np.einsum("ikm,kjm->ijm", f_ao[:, None, :] * t_o[None, :, :] / d_o, AB))
    T = np.where(ok_det & (Q_i > 0.0), T, 0.0)
    r = lambda v: v.reshape(shape)  # noqa: E731
    F = b.inner_force_N
    return BallTangents(F[0], F[1], (r(T[0, 0]), r(T[0, 1]), r(T[1, 0]), r(T[1, 1])),
                        b.converged.all(axis=(0, 1)))


def _contact_tangent(n, t, kn, kt, dlnK):
    """d(Q n)/dw of one contact, Q = K(alpha) delta^1.5, alpha = atan2(w_a, w_r), w its centre
    distance: kn n n^T + kt (t t^T + dlnK/dalpha n t^T), kn = 1.5 K delta^0.5, kt = Q/|w|
    (Harris Vol. 1 ch. 7, the contact law differentiated), (2, 2, M)."""
    nn = n[:, None] * n[None, :]
    return kn * nn + kt * (t[:, None] * t[None, :] + dlnK * n[:, None] * t[None, :])


def _maps(balls: PairBalls, z_c):
    """G_X, G_Y (6, 2, Z, N): d(X_jk, Y_jk)/d(x, y, z, theta_x, theta_y, w_j) with the inner
    groove centres at axial positions z_c (2, N) from the reference point."""
    psi = ball_azimuths_rad(balls.g.Z)[None, :, None]
    c, sn = np.cos(psi), np.sin(psi)
    s = balls.s[:, :, None]
    R = balls.R_i_mm[:, None, :]
    zc = z_c[:, None, :]
    shape = balls.X_mm.shape
    o, one = np.zeros(shape), np.ones(shape)
    GX = np.stack([o, o, s * one, s * R * sn, -s * R * c, -one])
    GY = np.stack([c * one, sn * one, o, -zc * sn, zc * c, o])
    return GX, GY


def generalised_loads(balls: PairBalls, q=None, w_mm=None, frame: str = "pair"):
    """Loads the balls of each bearing carry when the rotor is displaced by q (5, N: mm, mm, mm,
    rad, rad) from the equilibrium and the preload paths give by w_mm (2, N): (6, 2, N) per
    bearing, (F_x, F_y, F_z, M_x, M_y, F_w) with F_w = -F_j the force on the path (moments about
    the pair's centre, frame "pair", or each bearing's ball plane, frame "bearing"), the balls
    solved afresh there (`ball_tangents`).  The equilibrium force function whose derivative
    `pair_stiffness` is."""
    N = balls.n_points
    q = np.zeros((5, N)) if q is None else np.asarray(q, float)
    w = np.zeros((2, N)) if w_mm is None else np.asarray(w_mm, float)
    GX, GY = _maps(balls, _frame_zc(balls, frame))
    dX = np.einsum("dbkn,dn->bkn", GX[:5], q) + GX[5] * w[:, None, :]
    dY = np.einsum("dbkn,dn->bkn", GY[:5], q)
    return _loads(GX, GY, ball_tangents(balls, balls.X_mm + dX, balls.Y_mm + dY))


def _loads(GX, GY, bt: BallTangents) -> np.ndarray:
    """(6, 2, N): the generalised loads sum_k G^T f_k of each bearing."""
    return (GX * bt.f_X_N + GY * bt.f_Y_N).sum(axis=2)


def _frame_zc(balls: PairBalls, frame: str):
    if frame == "pair":
        return balls.z_c_mm
    if frame == "bearing":
        return balls.z_c_mm - balls.z_ball_mm
    raise ValueError(f"frame must be 'pair' or 'bearing', got {frame!r}")


def bearing_tangents(balls: PairBalls, frame: str = "pair",
                     tangents: BallTangents | None = None) -> np.ndarray:
    """(2, N, 6, 6) tangent of each bearing in (x, y, z, theta_x, theta_y, w_j), before the
    condensation of w_j: sum_k G^T T G (module docstring)."""
    bt = tangents or ball_tangents(balls)
    GX, GY = _maps(balls, _frame_zc(balls, frame))
    TXX, TXY, TYX, TYY = bt.T
    proj = "dbkn,bkn,ebkn->bnde"
    return (np.einsum(proj, GX, TXX, GX) + np.einsum(proj, GX, TXY, GY)
            + np.einsum(proj, GY, TYX, GX) + np.einsum(proj, GY, TYY, GY))


def condense(K6: np.ndarray, inv_c) -> np.ndarray:
    """(..., 5, 5): the preload path's give w condensed out of (..., 6, 6),
    K_qq - K_qw K_wq / (K_ww + 1/c) (1/c = inf: rigid path, K_qq; a floating, unloaded path
    with K_ww + 1/c = 0 holds nothing: its row and column drop)."""
    inv_c = np.asarray(inv_c, float)[..., None, None]
    Kqq, Kqw, Kwq, Kww = K6[..., :5, :5], K6[..., :5, 5:], K6[..., 5:, :5], K6[..., 5:, 5:]
    den = Kww + inv_c
    safe = np.where(np.isfinite(den) & (den != 0.0), den, 1.0)
    corr = np.where(np.isfinite(den) & (den != 0.0), Kqw @ Kwq / safe, 0.0)
    return Kqq - corr


def force_controlled(K: np.ndarray, dof: int = 0) -> np.ndarray:
    """(...,): the stiffness of DOF `dof` when the loads on every other DOF are held (they move
    freely): 1 / (K^-1)_dd, computed as the static condensation K_dd - K_dr K_rr^+ K_rd of the
    other DOFs r (Guyan, AIAA J. 3 (1965) 380; the pseudo-inverse drops a DOF that holds nothing,
    e.g. every entry 0 when the preload is lost and no ball is loaded: 0).  K (..., n, n) in
    consistent units; the result in the units of K_dd.  For the pair: the radial stiffness
    dF_x/dx with the axial load and the moment held, which is what stepping the radial load of
    `simulate` and reading its radial displacement measures (axial position and tilt free)."""
    K = np.asarray(K, float)
    rest = [i for i in range(K.shape[-1]) if i != dof]
    K_dr = K[..., dof, rest][..., None, :]
    K_rd = K[..., rest, dof][..., :, None]
    K_rr = K[..., rest, :][..., :, rest]
    return K[..., dof, dof] - (K_dr @ np.linalg.pinv(K_rr) @ K_rd)[..., 0, 0]


def pair_stiffness(g: BearingGeometry, arrangement: str, state: PairState,
                   **pair_args) -> PairStiffness:
    """Tangent stiffness of the pair (about its centre) and of each bearing (about its ball
    plane) at the equilibrium `state` that `analytic.bearing.solve_pair(g, arrangement,
    **pair_args)` returned (module docstring for the model; `pair_balls` for the arguments)."""
    balls = pair_balls(g, arrangement, state, **pair_args)
    bt = ball_tangents(balls)
    K_pair = condense(bearing_tangents(balls, "pair", bt), balls.inv_c_N_per_mm).sum(axis=0)
    K_own = condense(bearing_tangents(balls, "bearing", bt), balls.inv_c_N_per_mm)
    loads = _loads(*_maps(balls, balls.z_c_mm), bt)
    return PairStiffness(K_pair, K_own, loads[:5].sum(axis=1), bt.converged & state.converged)
