"""Contact of the balls with both raceways: the load-deflection stiffness K_n(alpha) from exact
Hertz, the axial state of a bearing at given groove-centre distances, and the state of every ball
of a bearing under a radial displacement (Harris & Kotzalas Vol. 1 ch. 6-7; Jones 1960).
Units: mm, N; angles in radians."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import hertz
from analytic.bearing.geometry import BearingGeometry, ThermalGeometry


@dataclass
class ContactStiffness:
    """K_n of a bearing at a contact angle, with the pieces the torque model reuses."""
    Kn: np.ndarray               # N/mm^1.5, inner and outer contact in series
    dlnKn_dalpha: np.ndarray     # 1/rad
    K_i: np.ndarray              # inner contact stiffness N/mm^1.5
    K_o: np.ndarray
    kappa: np.ndarray            # shape (2, ...): [inner, outer]
    K_ell: np.ndarray            # first-kind elliptic integral, (2, ...)
    E_ell: np.ndarray            # second-kind elliptic integral, (2, ...)
    Rx_mm: np.ndarray            # (2, ...)
    R_mm: np.ndarray             # 1/curvature sum, (2, ...)
    u: np.ndarray                # ln kappa, (2, ...)
    converged: np.ndarray        # both ellipticity solves converged, (...)


def contact_stiffness(g: BearingGeometry, tg: ThermalGeometry, alpha_rad) -> ContactStiffness:
    """K_n(alpha) = [K_i^(-2/3) + K_o^(-2/3)]^(-3/2) (Harris Vol. 1 ch. 7) from the exact Hertz
    stiffness of each contact (`hertz.stiffness_from_kappa`) with the ball/raceway radii of
    `hertz.ball_raceway_radii_mm` at gamma = Dw cos(alpha)/dm, and its exact derivative in alpha
    (implicit differentiation of the ellipticity equation; d K/dm = (E - (1-m) K)/(2m(1-m)),
    d E/dm = (E - K)/(2m), DLMF 19.4.1)."""
    alpha = np.asarray(alpha_rad, float)
    Dw, dm = tg.Dw_mm, tg.dm_mm
    gamma = Dw * np.cos(alpha) / dm
    g_m, g_p = 1.0 - gamma, 1.0 + gamma
    Rx, f = np.empty((2,) + gamma.shape), np.empty((2,) + gamma.shape)   # [inner, outer]
    Rx[0], Rx[1] = 0.5 * Dw * g_m, 0.5 * Dw * g_p
    f[0], f[1] = tg.f_i, tg.f_o
    Ry = f * Dw / (2.0 * f - 1.0)
    rho = Ry / Rx
    shape = rho.shape
    ell = hertz.ellipticity_state(rho.ravel())
    kappa, K, E, u, A, B, dgdu, m1, ok = (v.reshape(shape) for v in (
        ell.kappa, ell.K_ell, ell.E_ell, ell.u, ell.A, ell.B, ell.dg_du, ell.m1, ell.converged))
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    Es = g.E_star_MPa
    Kc = hertz.stiffness_from_kappa(R, Es, kappa, K, E)
    # d ln Kc / d ln Rx: ln Kc = u + ln E/2 + ln R/2 - 3/2 ln K + const, du = -dlnRx / (dg/du)
    dlnK_dlnRx = -(1.0 - 0.5 * A * m1 / E - 1.5 * B * m1 / K) / dgdu + 0.5 * R / Rx
    tan_a = np.tan(alpha)
    gt = gamma * tan_a
    dlnRx_da = np.empty_like(Rx)
    dlnRx_da[0], dlnRx_da[1] = gt / g_m, -gt / g_p
    dlnK_da = dlnK_dlnRx * dlnRx_da
    w = Kc ** (-2.0 / 3.0)
    Kn = (w[0] + w[1]) ** -1.5
    dlnKn = (w[0] * dlnK_da[0] + w[1] * dlnK_da[1]) / (w[0] + w[1])
    return ContactStiffness(Kn, dlnKn, Kc[0], Kc[1], kappa, K, E, Rx, R, u, ok.all(axis=0))


@dataclass
class BearingState:
    """Axial state of one bearing (or of both, on a leading axis) at given centre distances."""
    F_N: np.ndarray              # axial force carried, >= 0
    Q_N: np.ndarray              # ball load
    delta_mm: np.ndarray         # total contact deformation (inner + outer), >= 0
    alpha_rad: np.ndarray        # contact angle
    k_N_per_mm: np.ndarray       # dF/dX at fixed K_n


def axial_state(X_mm, Y_mm, A_T_mm, Kn, Z: int, dlnKn_dalpha=None, alpha_lin=None) -> BearingState:
    """F = Z K_n delta^1.5 sin(alpha) with delta = sqrt(X^2 + Y^2) - A_T, alpha = atan2(X, Y)
    (Harris Vol. 1 ch. 7 with the centre distance written in components).  Full-groove contact,
    the same contact model as `ball_set_state`: a bearing pushed past its centred position
    (X < 0) touches the other flank of its grooves once |X| exceeds the axial play, at the
    negative angle atan2(X, Y), and carries a negative axial force (a deep-groove bearing
    under a load from either side).  F is odd and increasing in X.

    With dlnKn_dalpha and alpha_lin given, K_n is taken as K_n exp(dlnKn_dalpha (alpha - alpha_lin))
    (first-order model of its contact-angle dependence, used inside the solvers) and k includes
    its derivative; otherwise K_n is held fixed in k."""
    X, Y = np.asarray(X_mm, float), np.asarray(Y_mm, float)
    D = np.hypot(X, Y)
    delta = np.maximum(D - A_T_mm, 0.0)
    s = X / D
    c = Y / D
    alpha = np.arctan2(X, Y)
    if dlnKn_dalpha is not None:
        Kn = Kn * np.exp(dlnKn_dalpha * (alpha - alpha_lin))
    sd = np.sqrt(delta)
    Q = Kn * delta * sd
    F = Z * Q * s
    k = Z * Kn * (1.5 * sd * s * s + delta * sd * c * c / D)
    if dlnKn_dalpha is not None:
        k = k + F * dlnKn_dalpha * c / D
    return BearingState(F, Q, delta, alpha, k)


def ball_azimuths_rad(Z: int) -> np.ndarray:
    """Ball azimuths psi_k = 2 pi k / Z, k = 0..Z-1 (rad), measured from the direction of the
    radial load (ball 0 sits in the load direction)."""
    return 2.0 * np.pi * np.arange(Z) / Z


@dataclass
class BallSetState:
    """Ball loads of both bearings at given groove-centre distances (`ball_set_state`).
    Per ball: shape (2, Z, N); per bearing: (2, N).  The generalised coordinates of bearing j are
    its axial approach a, the rotor radial displacement rho and, with a tilt, the rotor tilt
    theta; the k_* are the derivatives of the generalised forces (F, Fr, M) in them."""
    Q_N: np.ndarray              # ball load
    delta_mm: np.ndarray         # contact deformation (inner + outer), >= 0
    alpha_rad: np.ndarray        # contact angle atan2(X, Y)
    F_N: np.ndarray              # axial force of each bearing, sum_k Q sin(alpha)
    Fr_N: np.ndarray             # radial force of each bearing, sum_k Q cos(alpha) cos(psi)
    V_Nmm: np.ndarray            # elastic energy (2/5) sum_k K_n delta^2.5 (K_n as given)
    k_aa: np.ndarray             # dF/da      (a: axial approach of the bearing)
    k_ar: np.ndarray             # dF/drho    (rho: radial displacement of the rotor)
    k_ra: np.ndarray             # dFr/da
    k_rr: np.ndarray             # dFr/drho
    QD_Nmm: np.ndarray           # sum_k Q D: scale of the rounding error of V (delta = D - A_T)
    M_Nmm: np.ndarray | None = None   # moment of the bearing's ball forces, conjugate to theta
    k_at: np.ndarray | None = None    # dF/dtheta   (N/rad)
    k_rt: np.ndarray | None = None    # dFr/dtheta
    k_ta: np.ndarray | None = None    # dM/da       (N mm/mm)
    k_tr: np.ndarray | None = None    # dM/drho
    k_tt: np.ndarray | None = None    # dM/dtheta   (N mm/rad)


def ball_set_state(X_mm, Y_mm, rho_mm, A_T_mm, Kn, cos_psi, dlnKn_dalpha=None, theta_rad=None,
                   gx_mm=None, gy_mm=None, angles: bool = True) -> BallSetState:
    """Loads of every ball of both bearings under a rotor radial displacement rho and, optionally,
    a rotor tilt theta (Harris & Kotzalas Vol. 1 ch. 7, Jones 1960, rigid rings, no centrifugal or
    gyroscopic terms):

        X_jk = X_j + theta gx_j cos(psi_k),  Y_jk = Y_j + (rho + theta gy_j) cos(psi_k)
        D = sqrt(X^2 + Y^2),  alpha = atan2(X, Y),  delta_jk = D - A_T (0 if negative)
        Q_jk = K_n,jk delta_jk^1.5
        F_j = sum_k Q sin(alpha),  Fr_j = sum_k Q cos(alpha) cos(psi_k)
        M_j = sum_k Q cos(psi_k) (gx_j sin(alpha) + gy_j cos(alpha))

    X_mm, Y_mm, A_T_mm: (2, N) (bearing axial and radial groove-centre distance components without
    rho and theta); rho_mm: (N,); Kn: (2, Z, N) (or broadcastable); cos_psi: (Z,).  Tilt (all
    three given): theta_rad (N,) and the lever arms gx_mm, gy_mm (2, N) of `combined.tilt_arms_mm`
    (the axial and radial motion of bearing j's inner groove centre at psi = 0 per radian of
    tilt); M_j is then the generalised force conjugate to theta (the moment of the ball forces
    on the rotor).  The ball force Q (sin a, cos a) is the gradient of V = (2/5) K_n delta^2.5 in
    (X, Y) at fixed K_n, so the loads derive from a convex potential (used by the solver).  The
    tangent in (X, Y) per ball is 1.5 K_n delta^0.5 n n^T + (Q/D) t t^T with n = (sin a, cos a),
    t = (cos a, -sin a); with dlnKn_dalpha given it also contains (Q/D) dlnK_n/dalpha n t^T (the
    contact-angle dependence of K_n; K_n itself is used as given); the k_* are its projections
    G^T T G on the generalised coordinates (G = d(X, Y)/d(a, rho, theta)).  A ball with X < 0
    touches the other flank of the groove at the negative angle (full groove: the contact model
    of `axial_state` too).  angles=False leaves alpha_rad None (a solver's inner iterations,
    which need forces and tangents only)."""
    X, Y, cpsi, gx, gy = ball_positions(X_mm, Y_mm, rho_mm, cos_psi, theta_rad, gx_mm, gy_mm)
    A_T = np.asarray(A_T_mm, float)[:, None, :]
    D = np.hypot(X, Y)
    delta = np.maximum(D - A_T, 0.0)
    nX, nY = X / D, Y / D
    sd = np.sqrt(delta)
    Q = Kn * delta * sd
    kn = 1.5 * Kn * sd
    kt = Q / D
    MXX = kn * nX * nX + kt * nY * nY
    MXY = (kn - kt) * nX * nY
    MYX = MXY
    MYY = kn * nY * nY + kt * nX * nX
    if dlnKn_dalpha is not None:
        w = kt * dlnKn_dalpha
        MXX, MXY, MYX, MYY = (MXX + w * nX * nY, MXY - w * nX * nX, MYX + w * nY * nY,
                              MYY - w * nX * nY)
    return project_balls(Q, delta, np.arctan2(X, Y) if angles else None, Q * nX, Q * nY, 0.4 * Q * delta, Q * D,
                         (MXX, MXY, MYX, MYY), cpsi, gx, gy)


def ball_positions(X_mm, Y_mm, rho_mm, cos_psi, theta_rad=None, gx_mm=None, gy_mm=None):
    """Every ball's groove-centre distance components (2, Z, N) under a rotor radial
    displacement rho (N,) and, with theta_rad, gx_mm, gy_mm, a tilt (the maps of
    `ball_set_state`): returns (X, Y, cos_psi (1, Z, 1), gx, gy), gx, gy the per-ball
    derivatives dX/dtheta, dY/dtheta (None without a tilt)."""
    X = np.asarray(X_mm, float)[:, None, :]
    cpsi = np.asarray(cos_psi, float)[None, :, None]
    Y = np.asarray(Y_mm, float)[:, None, :] + np.asarray(rho_mm, float)[None, None, :] * cpsi
    gx = gy = None
    if theta_rad is not None:
        th = np.asarray(theta_rad, float)[None, None, :]
        gx = np.asarray(gx_mm, float)[:, None, :] * cpsi      # dX/dtheta per ball
        gy = np.asarray(gy_mm, float)[:, None, :] * cpsi      # dY/dtheta per ball
        X = X + th * gx
        Y = Y + th * gy
    return np.broadcast_to(X, Y.shape), Y, cpsi, gx, gy


def project_balls(Q, delta, alpha, QX, QY, V, QD, tangent, cpsi, gx=None, gy=None) -> BallSetState:
    """A `BallSetState` from every ball's state (2, Z, N): load Q, deformation delta, angle alpha,
    force on the inner groove centre (QX, QY) = dV/d(X, Y), energy V, rounding scale QD and the
    tangent (MXX, MXY, MYX, MYY) = d(QX, QY)/d(X, Y); the generalised forces and stiffnesses are
    the projections G^T (QX, QY) and G^T T G on (a, rho[, theta]) with G = d(X, Y)/d(a, rho,
    theta) = [[1, 0, gx], [0, cos psi, gy]] (`ball_positions`)."""
    MXX, MXY, MYX, MYY = tangent
    out = BallSetState(Q, delta, alpha, QX.sum(axis=1), (QY * cpsi).sum(axis=1), V.sum(axis=1),
                       MXX.sum(axis=1), (MXY * cpsi).sum(axis=1), (MYX * cpsi).sum(axis=1),
                       (MYY * cpsi * cpsi).sum(axis=1), QD.sum(axis=1))
    if gx is None:
        return out
    # G = [[1, 0, gx], [0, c, gy]] per ball: column theta of T G and row theta of G^T T
    TXt, TYt = MXX * gx + MXY * gy, MYX * gx + MYY * gy
    return BallSetState(**{**out.__dict__,
                           "M_Nmm": (QX * gx + QY * gy).sum(axis=1),
                           "k_at": TXt.sum(axis=1), "k_rt": (TYt * cpsi).sum(axis=1),
                           "k_ta": (gx * MXX + gy * MYX).sum(axis=1),
                           "k_tr": ((gx * MXY + gy * MYY) * cpsi).sum(axis=1),
                           "k_tt": (gx * TXt + gy * TYt).sum(axis=1)})
