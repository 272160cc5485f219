"""Angular-contact ball bearing pair: geometry, preload, contact angle, Hertz contact, stiffness.

Units: mm, N, MPa, C; angles in degrees at the interface, radians inside.

Model (DESIGN.md section 2: "balls are analytic, structures are FE").  A bearing's state is fixed by
the positions of its inner and outer groove curvature centres (Harris & Kotzalas, Rolling Bearing
Analysis 5th ed., Vol. 1 ch. 2 and 7; Jones 1960).  Free and unloaded, the centres are
A0 = (f_i + f_o - 1) Dw apart along the free contact angle alpha0.  With the FE shifts of the inner
relative to the outer groove centre, dr (radial) and dz (axial, global z), and the axial approach
a_j of bearing j,

    X_j = A0 sin(alpha0) + a_j                (axial component of the centre distance)
    Y_j = A0 cos(alpha0) + dr_j               (radial component)
    D_j = sqrt(X_j^2 + Y_j^2),  alpha_j = atan2(X_j, Y_j)
    A_T = Dw [f_i (1 + theta_ir) + f_o (1 + theta_or) - (1 + theta_b)]   (r_i + r_o - Dw, grown)
    delta_j = D_j - A_T                       (inner + outer contact deformation in series)
    Q_j = K_n(alpha_j) delta_j^1.5,  F_j = Z Q_j sin(alpha_j)   (Harris Vol. 1 ch. 7)

theta = Material.thermal_strain(T, T_ref) of the inner ring, outer ring and ball.  K_n combines the
inner and outer Hertz stiffnesses in series (`hertz.series_stiffness_N_per_mm15`), each from the
exact Hertz solution at the current contact angle and the thermally grown Dw, groove radii and pitch
diameter.  delta <= 0 means the bearing is unloaded (Q = 0), not an error.  Without dr and thermal
strain, F = Z K_n A0^1.5 (cos alpha0/cos alpha - 1)^1.5 sin alpha: Harris's axial-load equation
(Vol. 1 ch. 7, thrust-loaded bearing); the tests hold the two equal.

Pair conventions (fixed; other code relies on them).  Bearings A (lower z) and B (higher z),
arrangement "DB" (back-to-back, s_A = +1, s_B = -1) or "DF" (face-to-face, s_A = -1, s_B = +1):

    a_j = s_j (dz_j + x) + e - c F_j         x: rotor axial displacement (unknown)
    sum_j s_j F_j = axial_load_N             external axial load on the rotor in +z

e is the position-preload offset: found once so that in the reference state (dr_ref, dz_ref, all
temperatures T_ref, no external load) F_A = F_B = preload_assembled_N, then kept fixed; c is an
optional compliance of the preload path (mm/N).  Spring preload: a constant force P on bearing B's
outer ring, F_B = P, F_A = s_A axial_load + P; if that is negative the preload is lost (F_A = 0).

Solution.  Eliminating the load-dependent K_n by an outer fixed-point loop (K_n varies by parts per
thousand per degree of contact angle, the loop contracts by about that factor per pass), the inner
problem is a monotone scalar equation in x, solved by Newton's method inside a bracket that is
kept from the signs of the residual (bisection when Newton leaves it, doubling steps when both
bearings are unloaded).  Everything is vectorised over operating points, the two bearings on a
leading axis of length 2.

Combined axial and radial load (`solve_pair_combined`, called by `solve_pair` when a radial load
is given): the quasi-static load distribution around the ball set (Harris & Kotzalas Vol. 1 ch. 7,
Jones 1960; seed 003).  Ball k of Z sits at psi_k = 2 pi k / Z from the load direction, the rigid
rotor's radial displacement rho (common to both bearings, no tilt) adds rho cos(psi_k) to Y_j, every
ball has its own delta, contact angle and K_n, and the radial equation
sum_j sum_k Q_jk cos(alpha_jk) cos(psi_k) = radial load joins the axial one.  With K_n frozen the
equations are the stationarity conditions of a convex potential, solved by a safeguarded Newton
method, with the same outer K_n loop.

Not modelled here: moment loads and shaft tilt, centrifugal and gyroscopic ball loads, and
different inner and outer contact angles.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import hertz
from analytic.materials import Material, get_material


@dataclass(frozen=True)
class BearingGeometry:
    """Internal geometry of one angular-contact ball bearing (Harris Vol. 1 ch. 2 notation)."""
    Dw_mm: float                 # ball diameter
    Z: int                       # number of balls
    dm_mm: float                 # pitch diameter
    f_i: float                   # inner groove radius ratio r_i / Dw
    f_o: float                   # outer groove radius ratio r_o / Dw
    alpha0_deg: float            # free (unloaded) contact angle
    ring: Material               # inner and outer ring material
    ball: Material
    designation: str = ""

    @classmethod
    def from_spec(cls, spec) -> "BearingGeometry":
        """From a `studies.model.config.BearingSpec`."""
        return cls(Dw_mm=spec.ball_diameter_mm, Z=int(spec.ball_count),
                   dm_mm=spec.pitch_diameter_mm, f_i=spec.inner_groove_ratio,
                   f_o=spec.outer_groove_ratio, alpha0_deg=spec.contact_angle_free_deg,
                   ring=get_material(spec.ring_material), ball=get_material(spec.ball_material),
                   designation=spec.designation)

    @classmethod
    def from_catalogue(cls, name: str) -> "BearingGeometry":
        """From `analytic.catalogue` (designation or alias)."""
        from analytic.catalogue import get_entry
        c = get_entry(name)
        return cls(Dw_mm=c.ball_diameter_mm, Z=c.ball_count, dm_mm=c.pitch_diameter_mm,
                   f_i=c.inner_groove_ratio, f_o=c.outer_groove_ratio,
                   alpha0_deg=c.contact_angle_free_deg, ring=get_material(c.ring_material),
                   ball=get_material(c.ball_material), designation=c.designation)

    @property
    def A0_mm(self) -> float:
        """Free distance of the groove curvature centres A0 = (f_i + f_o - 1) Dw (Harris Vol. 1 ch. 2)."""
        return (self.f_i + self.f_o - 1.0) * self.Dw_mm

    @property
    def radial_clearance_mm(self) -> float:
        """Free radial clearance Pd/2 = A0 (1 - cos alpha0) (Harris Vol. 1 ch. 2: cos alpha0 = 1 - Pd/(2 A0)), mm."""
        return self.A0_mm * (1.0 - np.cos(np.radians(self.alpha0_deg)))

    @property
    def E_star_MPa(self) -> float:
        """Contact modulus of ball on ring, MPa (`hertz.contact_modulus_MPa`)."""
        return float(hertz.contact_modulus_MPa(self.ring.E_MPa, self.ring.nu,
                                               self.ball.E_MPa, self.ball.nu))


@dataclass(frozen=True)
class ThermalGeometry:
    """Thermally grown bearing geometry at one set of part temperatures (arrays broadcast)."""
    A_T_mm: np.ndarray           # r_i + r_o - Dw (grown): centre distance at first contact
    Dw_mm: np.ndarray            # grown ball diameter
    f_i: np.ndarray              # grown r_i / grown Dw
    f_o: np.ndarray
    dm_mm: np.ndarray            # pitch diameter grown with the mean ring strain


def thermal_geometry(g: BearingGeometry, T_inner_ring_C=None, T_outer_ring_C=None,
                     T_ball_C=None, T_ref_C=20.0) -> ThermalGeometry:
    """Grown geometry: groove radii r = f Dw (1 + theta_ring), ball Dw (1 + theta_ball),
    A_T = r_i + r_o - Dw_ball (DESIGN.md section 2; seed 001 eq. 1 is the radial projection of the
    same statement), pitch diameter dm (1 + (theta_ir + theta_or)/2) (used only in the Hertz
    curvature, where it is a second-order effect).  theta = Material.thermal_strain (-)."""
    Tr = T_ref_C
    th_i = 0.0 if T_inner_ring_C is None else g.ring.thermal_strain(np.asarray(T_inner_ring_C, float), Tr)
    th_o = 0.0 if T_outer_ring_C is None else g.ring.thermal_strain(np.asarray(T_outer_ring_C, float), Tr)
    th_b = 0.0 if T_ball_C is None else g.ball.thermal_strain(np.asarray(T_ball_C, float), Tr)
    Dw = g.Dw_mm * (1.0 + np.asarray(th_b, float))
    r_i = g.f_i * g.Dw_mm * (1.0 + np.asarray(th_i, float))
    r_o = g.f_o * g.Dw_mm * (1.0 + np.asarray(th_o, float))
    dm = g.dm_mm * (1.0 + 0.5 * (np.asarray(th_i, float) + np.asarray(th_o, float)))
    return ThermalGeometry(A_T_mm=r_i + r_o - Dw, Dw_mm=Dw, f_i=r_i / Dw, f_o=r_o / Dw, dm_mm=dm)


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


def contact_stiffness(g: BearingGeometry, tg: ThermalGeometry, alpha_rad) -> ContactStiffness:
    """K_n(alpha) = [K_i^(-2/3) + K_o^(-2/3)]^(-3/2) (Harris Vol. 1 ch. 7) from the exact Hertz
    stiffness of each contact (`hertz.stiffness_from_kappa`) with the ball/raceway radii of
    `hertz.ball_raceway_radii_mm` at gamma = Dw cos(alpha)/dm, and its exact derivative in alpha
    (implicit differentiation of the ellipticity equation; d K/dm = (E - (1-m) K)/(2m(1-m)),
    d E/dm = (E - K)/(2m), DLMF 19.4.1)."""
    alpha = np.asarray(alpha_rad, float)
    Dw, dm = tg.Dw_mm, tg.dm_mm
    gamma = Dw * np.cos(alpha) / dm
    Rx = np.stack(np.broadcast_arrays(0.5 * Dw * (1.0 - gamma), 0.5 * Dw * (1.0 + gamma)))
    f = np.stack(np.broadcast_arrays(tg.f_i * np.ones_like(gamma), tg.f_o * np.ones_like(gamma)))
    Ry = f * Dw / (2.0 * f - 1.0)
    rho = Ry / Rx
    shape = rho.shape
    kappa, K, E, u, A, B, dgdu, m1 = hertz._solve(rho.ravel())
    kappa, K, E, u, A, B, dgdu, m1 = (v.reshape(shape) for v in (kappa, K, E, u, A, B, dgdu, m1))
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    Es = g.E_star_MPa
    Kc = hertz.stiffness_from_kappa(R, Es, kappa, K, E)
    # d ln Kc / d ln Rx: ln Kc = u + ln E/2 + ln R/2 - 3/2 ln K + const, du = -dlnRx / (dg/du)
    dlnK_dlnRx = -(1.0 - 0.5 * A * m1 / E - 1.5 * B * m1 / K) / dgdu + 0.5 * R / Rx
    tan_a = np.tan(alpha)
    dlnRx_da = np.stack([gamma * tan_a / (1.0 - gamma), -gamma * tan_a / (1.0 + gamma)])
    dlnK_da = dlnK_dlnRx * dlnRx_da
    w = Kc ** (-2.0 / 3.0)
    Kn = (w[0] + w[1]) ** -1.5
    dlnKn = (w[0] * dlnK_da[0] + w[1] * dlnK_da[1]) / (w[0] + w[1])
    return ContactStiffness(Kn, dlnKn, Kc[0], Kc[1], kappa, K, E, Rx, R, u)


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
    (Harris Vol. 1 ch. 7 with the centre distance written in components).  A bearing whose
    contact angle would be <= 0 carries no axial load (F = 0, k = 0).

    With dlnKn_dalpha and alpha_lin given, K_n is taken as K_n exp(dlnKn_dalpha (alpha - alpha_lin))
    (first-order model of its contact-angle dependence, used inside the solvers) and k includes
    its derivative; otherwise K_n is held fixed in k."""
    X, Y = np.asarray(X_mm, float), np.asarray(Y_mm, float)
    D = np.hypot(X, Y)
    delta = np.maximum(D - A_T_mm, 0.0)
    s = np.maximum(X, 0.0) / D
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


# ---------------------------------------------------------------------------------------------
def _newton_increasing(fun, x0, lo=None, hi=None, step0=1e-3, xtol=1e-15, max_iter=200):
    """Vectorised root of an increasing function: fun(x) -> (r, dr/dx).  Newton's method inside a
    bracket kept from the residual signs; bisection when Newton leaves it; doubling steps away
    from a flat (dr = 0) side while one bracket end is still open."""
    x = np.array(x0, dtype=float, copy=True)
    lo = np.full_like(x, -np.inf) if lo is None else np.array(np.broadcast_to(lo, x.shape), float)
    hi = np.full_like(x, np.inf) if hi is None else np.array(np.broadcast_to(hi, x.shape), float)
    step = np.array(np.broadcast_to(step0, x.shape), float)
    for _ in range(max_iter):
        r, dr = fun(x)
        lo = np.where(r <= 0.0, np.maximum(lo, x), lo)
        hi = np.where(r >= 0.0, np.minimum(hi, x), hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            cand = x - r / dr
        ok = (dr > 0.0) & np.isfinite(cand) & (cand >= lo) & (cand <= hi)
        both = np.isfinite(lo) & np.isfinite(hi)
        new = np.where(ok, cand, np.where(both, 0.5 * (lo + hi),
                                          np.where(r < 0.0, x + step, x - step)))
        step = np.where(ok | both, step, 2.0 * step)
        new = np.where(r == 0.0, x, new)
        done = np.abs(new - x) <= xtol * (1.0 + np.abs(x))
        x = new
        if np.all(done):
            break
    return x


def _onset_X(Y, A_T):
    """Axial centre-distance component at first contact, sqrt(A_T^2 - Y^2) (0 if radially loaded)."""
    return np.sqrt(np.maximum(A_T * A_T - Y * Y, 0.0))


def _solve_X_for_force(F_N, Y, A_T, cs: "ContactStiffness", Z, alpha_lin):
    """X with Z K_n(alpha) delta^1.5 sin(alpha) = F, K_n linearised about alpha_lin."""
    Xc = _onset_X(Y, A_T)
    sa = np.sin(np.maximum(alpha_lin, 0.05))
    d_est = (np.maximum(F_N, 0.0) / (Z * cs.Kn * sa)) ** (2.0 / 3.0)
    x0 = Xc + d_est / sa

    def fun(X):
        st = axial_state(X, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
        return st.F_N - F_N, st.k_N_per_mm
    return _newton_increasing(fun, x0, lo=Xc, step0=np.maximum(d_est, 1e-6))


def _kn_converged(cs_new: "ContactStiffness", cs_old: "ContactStiffness", alpha, alpha_lin, tol):
    """Exact K_n at the new angle against its linear model about the old one."""
    lin = cs_old.Kn * np.exp(cs_old.dlnKn_dalpha * (alpha - alpha_lin))
    return bool(np.all(np.abs(cs_new.Kn / lin - 1.0) <= tol))


def approach_for_force(g: BearingGeometry, F_N, dr_mm=0.0, tg: ThermalGeometry | None = None,
                       tol: float = 1e-14, max_outer: int = 30, alpha_start=None):
    """Axial approach a (mm) at which one bearing carries the axial force F_N, with radial centre
    shift dr_mm and grown geometry tg (default: free geometry at T_ref).  Harris's equation solved
    for the contact angle with the radial shift kept: returns (a_mm, alpha_rad, ContactStiffness)."""
    tg = tg or thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    F = np.asarray(F_N, float)
    Y = g.A0_mm * np.cos(a0) + np.asarray(dr_mm, float)
    shape = np.broadcast_shapes(F.shape, Y.shape, np.shape(tg.A_T_mm))
    F, Y = np.broadcast_to(F, shape), np.broadcast_to(Y, shape)
    A_T = np.broadcast_to(tg.A_T_mm, shape)
    alpha_lin = np.full(shape, a0) if alpha_start is None else np.broadcast_to(alpha_start, shape)
    cs = contact_stiffness(g, tg, alpha_lin)
    for _ in range(max_outer):
        X = _solve_X_for_force(F, Y, A_T, cs, g.Z, alpha_lin)
        alpha = np.arctan2(X, Y)
        cs_new = contact_stiffness(g, tg, alpha)
        done = _kn_converged(cs_new, cs, alpha, alpha_lin, tol)
        cs, alpha_lin = cs_new, alpha
        if done:      # X carries F with a K_n model matching the exact K_n at alpha to tol
            break
    return X - g.A0_mm * np.sin(a0), alpha, cs


def bearing_axial_force(g: BearingGeometry, approach_mm, dr_mm=0.0, tg: ThermalGeometry | None = None):
    """Axial force (N) of one bearing at axial approach a (mm) and radial centre shift dr (mm),
    K_n evaluated exactly at the resulting contact angle: returns (BearingState, ContactStiffness)."""
    tg = tg or thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    X = g.A0_mm * np.sin(a0) + np.asarray(approach_mm, float)
    Y = g.A0_mm * np.cos(a0) + np.asarray(dr_mm, float)
    X, Y = np.broadcast_arrays(X, Y)
    cs = contact_stiffness(g, tg, np.arctan2(X, Y))
    return axial_state(X, Y, tg.A_T_mm, cs.Kn, g.Z), cs


# ---------------------------------------------------------------------------------------------
@dataclass
class _LinearKn:
    """First-order model of K_n(alpha) about some angle (the solvers' working copy)."""
    Kn: np.ndarray
    dlnKn_dalpha: np.ndarray


def _reference_state(g: BearingGeometry, s, P, c, dr_ref, dz_ref, tol):
    """Position-preload offset e and rotor position x at the reference state (free geometry at
    T_ref, shifts dr_ref/dz_ref, no external load, F_A = F_B = P):
        a_j* = approach of bearing j carrying P;  a_j* + c P = s_j (dz_j + x) + e
    Two equations for e and x (s_A = -s_B):  e = (a_A + a_B - s_A (dz_A - dz_B))/2 + c P.
    Computed once per distinct (P, dr_ref) combination (usually one)."""
    N = P.shape[0]
    keys = np.column_stack([P, dr_ref[0], dr_ref[1]])
    if np.all(keys == keys[0]):
        uniq, inv = keys[:1], np.zeros(N, dtype=int)
    else:
        uniq, inv = np.unique(keys, axis=0, return_inverse=True)
        inv = inv.ravel()
    tg_ref = thermal_geometry(g)
    a_u, alpha_u, cs_u = approach_for_force(g, uniq[:, 0][None, :], uniq[:, 1:].T, tg_ref, tol)
    a_ref = a_u[:, inv]
    a_nom = a_ref + c * P
    e = 0.5 * (a_nom[0] + a_nom[1] - s[0, 0] * (dz_ref[0] - dz_ref[1]))
    x = s[0, 0] * (a_nom[0] - e) - dz_ref[0]
    lin = _LinearKn(cs_u.Kn[:, inv], cs_u.dlnKn_dalpha[:, inv])
    return e, x, alpha_u[:, inv], lin


SIGNS = {"DB": np.array([1.0, -1.0]), "DF": np.array([-1.0, 1.0])}


def _pair_array(v, N: int) -> np.ndarray:
    """Broadcast an input to shape (2, N): scalars and (N,) arrays apply to both bearings; give
    per-bearing values as shape (2, N) or (2, 1)."""
    a = np.asarray(v, dtype=float)
    if a.ndim == 2:
        return np.broadcast_to(a, (2, N))
    return np.broadcast_to(a.reshape(1, -1) if a.ndim == 1 else a, (2, N))


def _n_points(*vals) -> int:
    n = 1
    for v in vals:
        a = np.asarray(v)
        if a.ndim >= 1 and a.shape[-1] != 1:
            if n not in (1, a.shape[-1]):
                raise ValueError(f"inconsistent numbers of operating points: {n} and {a.shape[-1]}")
            n = a.shape[-1]
    return n


def _effective_X(Xnom, Y, A_T, cs, Z, c, alpha_lin):
    """Solve X + c F(X) = X_nom (compliance c in series with the bearing; F increasing in X)."""
    if np.all(c == 0.0):
        return Xnom
    F0 = axial_state(Xnom, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin).F_N

    def fun(X):
        st = axial_state(X, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
        return X + c * st.F_N - Xnom, 1.0 + c * st.k_N_per_mm
    return _newton_increasing(fun, Xnom, lo=Xnom - c * F0, hi=Xnom)


def solve_pair(g: BearingGeometry, arrangement: str = "DB", *, dr_mm=0.0, dz_mm=0.0,
               T_inner_ring_C=None, T_outer_ring_C=None, T_ball_C=None, T_ref_C: float = 20.0,
               preload_kind: str = "position", preload_assembled_N=100.0, axial_load_N=0.0,
               dr_ref_mm=0.0, dz_ref_mm=0.0, compliance_mm_per_N=0.0,
               tol: float = 1e-14, max_outer: int = 30, chunk: int = 8192,
               radial_load_N=0.0, return_ball_loads: bool = False) -> dict[str, np.ndarray]:
    """Equilibrium of a preloaded pair of identical bearings, vectorised over N operating points.

    Inputs (mm, C, N), scalars or arrays of shape (N,) (both bearings) or (2, N) (A, B):
      dr_mm, dz_mm      inner minus outer groove-centre shift, radial and axial (global z), relative
                        to the free unmounted bearing at T_ref (from the FE: fits, thermal growth)
      T_*_C, T_ref_C    part temperatures (ring and ball growth of groove radii and ball), default T_ref
      preload_kind      "position" (offset e fixed at the reference state) or "spring" (F_B = P)
      preload_assembled_N   P, set at the reference state (position) or the spring force
      axial_load_N      external axial load on the rotor, +z
      dr_ref_mm, dz_ref_mm  shifts of the reference (assembled) state
      compliance_mm_per_N   axial compliance c of the preload path (position preload)
    Conventions and formulas: module docstring.

    Returns a dict of (N,) arrays: preload_N (= min(F_A, F_B), 0 when lost), axial_force_A_N,
    axial_force_B_N, contact_angle_A_deg, contact_angle_B_deg (for an unloaded bearing: the angle
    of its groove-centre line, no contact), contact_angle_deg (of the more loaded bearing),
    ball_load_A_N, ball_load_B_N, delta_A_mm, delta_B_mm, for j in A, B and c in inner, outer:
    a_{c}_{j}_mm, b_{c}_{j}_mm, p_max_{c}_{j}_MPa, E_ell_{c}_{j} (second-kind elliptic integral),
    Rx_{c}_{j}_mm; max_contact_pressure_MPa, axial_stiffness_A_N_per_um, axial_stiffness_B_N_per_um,
    axial_stiffness_N_per_um (pair), preload_lost (bool), x_mm, preload_offset_mm (e; NaN for a
    spring), approach_A_mm, approach_B_mm.

    Large N is processed in blocks of `chunk` points (working arrays stay in cache; the result
    does not depend on it).

    radial_load_N (scalar or (N,), N, along the azimuth of ball 0): with a non-zero radial load at
    any point, or return_ball_loads=True, the combined-load solver `solve_pair_combined` runs
    instead (load distribution around the ball set; its docstring lists the extra outputs and what
    the per-bearing outputs above then refer to).  Points with zero radial load keep exactly the
    outputs of this axial-only solver.
    """
    if arrangement not in SIGNS:
        raise ValueError(f"arrangement must be 'DB' or 'DF', got {arrangement!r}")
    if preload_kind not in ("position", "spring"):
        raise ValueError(f"preload_kind must be 'position' or 'spring', got {preload_kind!r}")
    if return_ball_loads or np.any(np.asarray(radial_load_N, float) != 0.0):
        return solve_pair_combined(
            g, arrangement, dr_mm=dr_mm, dz_mm=dz_mm, T_inner_ring_C=T_inner_ring_C,
            T_outer_ring_C=T_outer_ring_C, T_ball_C=T_ball_C, T_ref_C=T_ref_C,
            preload_kind=preload_kind, preload_assembled_N=preload_assembled_N,
            axial_load_N=axial_load_N, radial_load_N=radial_load_N, dr_ref_mm=dr_ref_mm,
            dz_ref_mm=dz_ref_mm, compliance_mm_per_N=compliance_mm_per_N, tol=tol,
            max_outer=max_outer, chunk=chunk, return_ball_loads=return_ball_loads)
    args = dict(dr_mm=dr_mm, dz_mm=dz_mm, T_inner_ring_C=T_inner_ring_C,
                T_outer_ring_C=T_outer_ring_C, T_ball_C=T_ball_C,
                preload_assembled_N=preload_assembled_N, axial_load_N=axial_load_N,
                dr_ref_mm=dr_ref_mm, dz_ref_mm=dz_ref_mm, compliance_mm_per_N=compliance_mm_per_N)
    N = _n_points(*args.values())
    if N > chunk:
        parts = []
        for i0 in range(0, N, chunk):
            sl = slice(i0, min(N, i0 + chunk))
            sub = {k: (np.asarray(v)[..., sl] if v is not None and np.ndim(v) >= 1
                       and np.shape(v)[-1] == N else v) for k, v in args.items()}
            parts.append(solve_pair(g, arrangement, T_ref_C=T_ref_C, preload_kind=preload_kind,
                                    tol=tol, max_outer=max_outer, chunk=chunk, **sub))
        return {k: np.concatenate([p[k] for p in parts], axis=-1) for k in parts[0]}
    s = SIGNS[arrangement][:, None]
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    Z = g.Z
    P = np.broadcast_to(np.asarray(preload_assembled_N, float), (N,))
    Fext = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
    dr, dz = _pair_array(dr_mm, N), _pair_array(dz_mm, N)
    T_ref = float(T_ref_C)
    temps = [None if T is None else _pair_array(T, N)
             for T in (T_inner_ring_C, T_outer_ring_C, T_ball_C)]
    tg = thermal_geometry(g, *temps, T_ref_C=T_ref)
    tg = ThermalGeometry(*(np.broadcast_to(v, (2, N)) for v in
                           (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    Y = Y0 + dr
    A_T = tg.A_T_mm

    if preload_kind == "position":
        e, x, alpha_lin, cs = _reference_state(g, s, P, c, _pair_array(dr_ref_mm, N),
                                               _pair_array(dz_ref_mm, N), tol)
        # operating state: K_n linearised about alpha_lin (first pass: the reference state's),
        # refreshed at the operating geometry until the linear model is exact to tol
        scale = 1e-3 * g.Dw_mm

        def residual(xx):
            Xn = X0 + s * (dz + xx) + e
            Xe = _effective_X(Xn, Y, A_T, cs, Z, c, alpha_lin)
            st = axial_state(Xe, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
            keff = st.k_N_per_mm / (1.0 + c * st.k_N_per_mm)
            return (s * st.F_N).sum(axis=0) - Fext, keff.sum(axis=0)

        for _ in range(max_outer):
            x = _newton_increasing(residual, x, step0=scale)
            X = _effective_X(X0 + s * (dz + x) + e, Y, A_T, cs, Z, c, alpha_lin)
            alpha = np.arctan2(X, Y)
            cs_new = contact_stiffness(g, tg, alpha)
            done = _kn_converged(cs_new, cs, alpha, alpha_lin, tol)
            cs, alpha_lin = cs_new, alpha
            if done:
                break
        # converged: x solves the equilibrium with a K_n model that matches the exact K_n at the
        # final angle to tol, so the state below (exact K_n) balances the load to tol
        e_out = e
    else:
        FA = s[0, 0] * Fext + P
        lost_spring = FA < 0.0
        Freq = np.stack([np.maximum(FA, 0.0), P])
        a_op, alpha_lin, cs = approach_for_force(g, Freq, dr, tg, tol)
        X = X0 + a_op
        x = s[0, 0] * a_op[0] - dz[0]                  # rotor position implied by bearing A (e = 0)
        e_out = np.full(N, np.nan)

    # final state with K_n exact at alpha_lin (converged: alpha = alpha_lin to tol) and the full
    # axial stiffness dF/dX including dK_n/dalpha
    st = axial_state(X, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
    alpha = st.alpha_rad
    k_full = st.k_N_per_mm
    if preload_kind == "position":
        k_eff = k_full / (1.0 + c * k_full)
        k_pair = k_eff.sum(axis=0)
        lost = (st.F_N <= 0.0).any(axis=0)
    else:
        k_eff = k_full
        k_pair = np.where(st.F_N[0] > 0.0, k_full[0], 0.0)   # the spring side adds ~nothing
        lost = lost_spring | (st.F_N[0] <= 0.0)

    out: dict[str, np.ndarray] = {}
    FA_, FB_ = st.F_N
    out["preload_N"] = np.where(lost, 0.0, np.minimum(FA_, FB_))
    out["axial_force_A_N"], out["axial_force_B_N"] = FA_, FB_
    adeg = np.degrees(alpha)
    out["contact_angle_A_deg"], out["contact_angle_B_deg"] = adeg
    out["contact_angle_deg"] = np.where(FA_ >= FB_, adeg[0], adeg[1])
    out["ball_load_A_N"], out["ball_load_B_N"] = st.Q_N
    out["delta_A_mm"], out["delta_B_mm"] = st.delta_mm
    Es = g.E_star_MPa
    pmax = []
    for ic, cname in enumerate(("inner", "outer")):
        hc = hertz.hertz_from_kappa(st.Q_N, cs.R_mm[ic], Es, cs.kappa[ic], cs.K_ell[ic], cs.E_ell[ic])
        for j, bname in enumerate("AB"):
            out[f"a_{cname}_{bname}_mm"] = hc.a_mm[j]
            out[f"b_{cname}_{bname}_mm"] = hc.b_mm[j]
            out[f"p_max_{cname}_{bname}_MPa"] = hc.p_max_MPa[j]
            out[f"E_ell_{cname}_{bname}"] = cs.E_ell[ic][j]
            out[f"Rx_{cname}_{bname}_mm"] = cs.Rx_mm[ic][j]
        pmax.append(hc.p_max_MPa)
    out["max_contact_pressure_MPa"] = np.max(np.stack(pmax), axis=(0, 1))
    out["axial_stiffness_A_N_per_um"], out["axial_stiffness_B_N_per_um"] = 1e-3 * k_eff
    out["axial_stiffness_N_per_um"] = 1e-3 * k_pair
    out["preload_lost"] = lost
    out["x_mm"] = x
    out["preload_offset_mm"] = e_out
    out["approach_A_mm"], out["approach_B_mm"] = X - X0
    return out


# ---------------------------------------------------------------------------------------------
# Combined axial and radial load: quasi-static load distribution around the ball set
def ball_azimuths_rad(Z: int) -> np.ndarray:
    """Ball azimuths psi_k = 2 pi k / Z, k = 0..Z-1 (rad), measured from the direction of the
    radial load (ball 0 sits in the load direction)."""
    return 2.0 * np.pi * np.arange(Z) / Z


@dataclass
class BallSetState:
    """Ball loads of both bearings at given groove-centre distances (`ball_set_state`).
    Per ball: shape (2, Z, N); per bearing: (2, N)."""
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


def ball_set_state(X_mm, Y_mm, rho_mm, A_T_mm, Kn, cos_psi, dlnKn_dalpha=None) -> BallSetState:
    """Loads of every ball of both bearings under a rotor radial displacement rho (Harris &
    Kotzalas Vol. 1 ch. 7, Jones 1960, rigid rings, no centrifugal or gyroscopic terms):

        X_jk = X_j,  Y_jk = Y_j + rho cos(psi_k),  D = sqrt(X^2 + Y^2),  alpha = atan2(X, Y)
        delta_jk = D - A_T (0 if negative),  Q_jk = K_n,jk delta_jk^1.5
        F_j = sum_k Q sin(alpha),  Fr_j = sum_k Q cos(alpha) cos(psi_k)

    X_mm, Y_mm, A_T_mm: (2, N) (bearing axial and radial groove-centre distance components without
    rho); rho_mm: (N,); Kn: (2, Z, N) (or broadcastable); cos_psi: (Z,).  The ball force Q (sin a,
    cos a) is the gradient of V = (2/5) K_n delta^2.5 in (X, Y) at fixed K_n, so the loads derive
    from a convex potential (used by the solver).  The tangent in (X, Y) per ball is
    1.5 K_n delta^0.5 n n^T + (Q/D) t t^T with n = (sin a, cos a), t = (cos a, -sin a); with
    dlnKn_dalpha given it also contains (Q/D) dlnK_n/dalpha n t^T (the contact-angle dependence of
    K_n; K_n itself is used as given).  A ball with X < 0 is taken to touch the other side of the
    groove at the negative angle (full groove); `axial_state` instead gives such a bearing no axial
    force.  They differ only for a bearing withdrawn beyond zero contact angle with radial
    interference."""
    X = np.asarray(X_mm, float)[:, None, :]
    cpsi = np.asarray(cos_psi, float)[None, :, None]
    Y = np.asarray(Y_mm, float)[:, None, :] + np.asarray(rho_mm, float)[None, None, :] * cpsi
    X = np.broadcast_to(X, Y.shape)
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
    return BallSetState(Q, delta, np.arctan2(X, Y), (Q * nX).sum(axis=1),
                        (Q * nY * cpsi).sum(axis=1), (0.4 * Q * delta).sum(axis=1),
                        MXX.sum(axis=1), (MXY * cpsi).sum(axis=1), (MYX * cpsi).sum(axis=1),
                        (MYY * cpsi * cpsi).sum(axis=1), (Q * D).sum(axis=1))


class _CombinedProblem:
    """Unknowns u (n, N) and total potential of the pair under combined load, one preload mode:

      "rigid"     position preload, c = 0:  u = (x, rho),  a_j = s_j (dz_j + x) + e
                  Pi = V - Fa x - Fr rho
      "compliant" position preload, c > 0:  u = (x, rho, a_A, a_B),  a_j^nom = s_j (dz_j + x) + e
                  Pi = V + sum_j (a_j - a_j^nom)^2 / (2c) - Fa x - Fr rho
      "spring"    spring preload:  u = (a_A, a_B, rho)
                  Pi = V - sum_j F_j^req a_j - Fr rho,  F_A^req = max(s_A Fa + P, 0), F_B^req = P

    V = sum of the ball energies (`ball_set_state`).  Stationarity of Pi is the equilibrium of the
    module docstring with the radial equation added: sum_j s_j F_j = Fa, sum_j Fr_j = Fr (and
    a_j = a_j^nom - c F_j, or F_j = F_j^req).  With K_n frozen Pi is convex (delta is a norm minus
    a constant, V an increasing convex function of it, the maps to X, Y affine)."""

    def __init__(self, mode, s, X0, Ynom, A_T, cos_psi, Fa, Fr, dz, e=None, c=None, Freq=None):
        self.mode, self.s, self.X0, self.Ynom, self.A_T = mode, s, X0, Ynom, A_T
        self.cos_psi, self.Fa, self.Fr, self.dz, self.e, self.c, self.Freq = (
            cos_psi, Fa, Fr, dz, e, c, Freq)
        self.n = {"rigid": 2, "compliant": 4, "spring": 3}[mode]
        self.i_ax, self.i_rad = {"rigid": (0, 1), "compliant": (0, 1), "spring": (0, 2)}[mode]

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

    def state(self, u, Kn, dlnKn_dalpha=None) -> BallSetState:
        a, rho, _ = self.split(u)
        return ball_set_state(self.X0 + a, self.Ynom, rho, self.A_T, Kn, self.cos_psi, dlnKn_dalpha)

    def alpha(self, u):
        """Angle of every ball's groove-centre line, atan2(X, Y), (2, Z, N)."""
        a, rho, _ = self.split(u)
        Y = self.Ynom[:, None, :] + rho[None, None, :] * self.cos_psi[None, :, None]
        return np.arctan2(np.broadcast_to((self.X0 + a)[:, None, :], Y.shape), Y)

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
            g = np.stack([(s * st.F_N).sum(axis=0) - self.Fa, Rsum])
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
            g = np.stack([-(s * gap).sum(axis=0) / c - self.Fa, Rsum,
                          st.F_N[0] + gap[0] / c, st.F_N[1] + gap[1] / c])
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
            g = np.stack([st.F_N[0] - self.Freq[0], st.F_N[1] - self.Freq[1], Rsum])
            for j in range(2):
                H[j, j] = st.k_aa[j]
                H[j, 2] = st.k_ar[j]
                H[2, j] = st.k_ra[j]
            H[2, 2] = krr
        return Pi, Pabs, g, H


def _newton_minimise(fun, u0, cap, max_iter: int = 200):
    """Vectorised minimisation of convex functions fun(u) -> (Pi, |terms|, grad, Hessian), u of
    shape (n, N): Newton steps on the Hessian (plus 1e-12 of its largest diagonal and 1e-6 N/mm,
    so that flat directions without contact still give a step), capped to `cap` mm per component,
    with Armijo backtracking on Pi (decreases below the rounding level of Pi, 1e-13 of the sum of
    the magnitudes of its terms, are accepted).  A point is converged when a full Newton step is
    accepted that is below 1e-15 (1 + max|u|) mm, or when no step decreases Pi any more."""
    u = np.array(u0, float, copy=True)
    n, N = u.shape
    Pi, Pabs, g, H = fun(u)
    done = np.zeros(N, bool)
    eye = np.eye(n)
    for _ in range(max_iter):
        A = np.moveaxis(H, -1, 0)
        lam = 1e-12 * np.abs(np.diagonal(A, axis1=1, axis2=2)).max(axis=1) + 1e-6
        d = -np.linalg.solve(A + lam[:, None, None] * eye, np.moveaxis(g, -1, 0)[..., None])[..., 0].T
        step = np.abs(d).max(axis=0)
        full = step <= cap
        d = d * np.where(full, 1.0, cap / np.where(full, 1.0, step))
        d[:, done] = 0.0
        slope = (g * d).sum(axis=0)
        t = np.ones(N)
        pending = ~done
        for _ls in range(60):
            trial = u + t * d
            Pt, Pat, gt, Ht = fun(trial)
            ok = pending & (Pt <= Pi + 1e-4 * t * slope + 1e-13 * (Pabs + Pat))
            u[:, ok], Pi[ok], Pabs[ok], g[:, ok], H[..., ok] = trial[:, ok], Pt[ok], Pat[ok], gt[:, ok], Ht[..., ok]
            pending &= ~ok
            if not pending.any():
                break
            t = np.where(pending, 0.5 * t, t)
        small = full & (t == 1.0) & (step <= 1e-15 * (1.0 + np.abs(u).max(axis=0)))
        done |= small | pending
        if done.all():
            break
    return u


def _combined_group(g: BearingGeometry, mode: str, s, dr, dz, tg: ThermalGeometry, Fa, Fr, c, e,
                    Freq, lost_spring, u0, tol, max_outer, solve=True, ball_loads=False):
    """Solve (or, with solve=False, only evaluate at u0) one group of points of one preload mode
    and return the output dict of `solve_pair_combined` for them."""
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    psi = ball_azimuths_rad(g.Z)
    prob = _CombinedProblem(mode, s, X0, Y0 + dr, tg.A_T_mm, np.cos(psi), Fa, Fr, dz, e, c, Freq)
    tg3 = ThermalGeometry(*(v[:, None, :] for v in
                            (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    u = u0
    cs = contact_stiffness(g, tg3, prob.alpha(u))
    if solve:
        cap = 0.1 * g.A0_mm

        for _ in range(max_outer):
            Kn = cs.Kn
            u = _newton_minimise(lambda uu: prob.assemble(uu, prob.state(uu, Kn)), u, cap)
            cs_new = contact_stiffness(g, tg3, prob.alpha(u))
            done = bool(np.all(np.abs(cs_new.Kn / cs.Kn - 1.0) <= tol))
            cs = cs_new
            if done:      # u solves the equilibrium with K_n matching the exact K_n at its angles to tol
                break
    # final state: K_n exact at the final angles, full tangent (with dK_n/dalpha)
    st = prob.state(u, cs.Kn, cs.dlnKn_dalpha)
    _, _, _, J = prob.assemble(u, st)
    a, rho, x = prob.split(u)
    Jm = np.moveaxis(J, -1, 0)

    def condensed(i):
        """d(load)/d(u_i) with the other unknowns free: J_ii - J_ir J_rr^+ J_ri (= 1/(J^-1)_ii;
        the pseudo-inverse gives 0 along a displacement no loaded ball resists)."""
        r = [m for m in range(prob.n) if m != i]
        Jrr = Jm[:, r][:, :, r]
        return Jm[:, i, i] - np.einsum("nr,nrs,ns->n", Jm[:, i, r], np.linalg.pinv(Jrr), Jm[:, r, i])
    k_ax, k_rad = condensed(prob.i_ax), condensed(prob.i_rad)

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

    out: dict[str, np.ndarray] = {}
    out["preload_N"] = np.where(lost, 0.0, np.minimum(FA_, FB_))
    out["axial_force_A_N"], out["axial_force_B_N"] = FA_, FB_
    adeg = np.degrees(top(alpha))
    out["contact_angle_A_deg"], out["contact_angle_B_deg"] = adeg
    out["contact_angle_deg"] = np.where(FA_ >= FB_, adeg[0], adeg[1])
    out["ball_load_A_N"], out["ball_load_B_N"] = top(Q)
    out["delta_A_mm"], out["delta_B_mm"] = top(delta)
    Es = g.E_star_MPa
    pmax = []
    for ic, cname in enumerate(("inner", "outer")):
        hc = hertz.hertz_from_kappa(Q, cs.R_mm[ic], Es, cs.kappa[ic], cs.K_ell[ic], cs.E_ell[ic])
        for j, bname in enumerate("AB"):
            out[f"a_{cname}_{bname}_mm"] = top(hc.a_mm)[j]
            out[f"b_{cname}_{bname}_mm"] = top(hc.b_mm)[j]
            out[f"p_max_{cname}_{bname}_MPa"] = top(hc.p_max_MPa)[j]
            out[f"E_ell_{cname}_{bname}"] = top(cs.E_ell[ic])[j]
            out[f"Rx_{cname}_{bname}_mm"] = top(cs.Rx_mm[ic])[j]
        pmax.append(hc.p_max_MPa.max(axis=1))
    out["max_contact_pressure_MPa"] = np.max(np.stack(pmax), axis=(0, 1))
    out["axial_stiffness_A_N_per_um"], out["axial_stiffness_B_N_per_um"] = 1e-3 * k_eff
    out["axial_stiffness_N_per_um"] = 1e-3 * k_pair
    out["preload_lost"] = lost
    out["x_mm"] = x
    out["preload_offset_mm"] = e_out
    out["approach_A_mm"], out["approach_B_mm"] = a
    # combined-load outputs
    out["rho_mm"] = rho
    out["radial_force_A_N"], out["radial_force_B_N"] = st.Fr_N
    out["max_ball_load_A_N"], out["max_ball_load_B_N"] = Q.max(axis=1)
    loaded = delta > 1e-12 * tg3.A_T_mm
    out["loaded_zone_A"], out["loaded_zone_B"] = loaded.mean(axis=1)
    out["radial_stiffness_N_per_um"] = 1e-3 * k_rad
    if ball_loads:
        out["ball_loads_A_N"], out["ball_loads_B_N"] = Q
        out["ball_contact_angles_A_deg"], out["ball_contact_angles_B_deg"] = np.degrees(alpha)
    return out


COMBINED_KEYS = ("rho_mm", "radial_force_A_N", "radial_force_B_N", "max_ball_load_A_N",
                 "max_ball_load_B_N", "loaded_zone_A", "loaded_zone_B", "radial_stiffness_N_per_um")
BALL_KEYS = ("ball_loads_A_N", "ball_loads_B_N", "ball_contact_angles_A_deg",
             "ball_contact_angles_B_deg")


def solve_pair_combined(g: BearingGeometry, arrangement: str = "DB", *, dr_mm=0.0, dz_mm=0.0,
                        T_inner_ring_C=None, T_outer_ring_C=None, T_ball_C=None,
                        T_ref_C: float = 20.0, preload_kind: str = "position",
                        preload_assembled_N=100.0, axial_load_N=0.0, radial_load_N=0.0,
                        dr_ref_mm=0.0, dz_ref_mm=0.0, compliance_mm_per_N=0.0,
                        tol: float = 1e-14, max_outer: int = 30, chunk: int = 8192,
                        return_ball_loads: bool = False) -> dict[str, np.ndarray]:
    """Pair equilibrium under combined axial and radial load with the quasi-static load
    distribution around the ball set (Harris & Kotzalas Vol. 1 ch. 7; Jones 1960), vectorised
    over N operating points.  `solve_pair` calls this when a radial load is given.

    Model: each bearing j has Z balls at psi_k = 2 pi k / Z from the radial load direction.  The
    rigid rotor moves radially by rho (mm, along psi = 0, common to both bearings; no tilt, so the
    radial load is shared according to that common displacement) and axially by x:

        X_jk = A0 sin(a0) + a_j,  Y_jk = A0 cos(a0) + dr_j + rho cos(psi_k)
        delta_jk = sqrt(X^2 + Y^2) - A_T,  Q_jk = K_n(alpha_jk) delta_jk^1.5 (0 if delta <= 0)
        sum_j s_j sum_k Q_jk sin(alpha_jk) = axial_load_N
        sum_j sum_k Q_jk cos(alpha_jk) cos(psi_k) = radial_load_N

    with a_j, e, c and the spring preload exactly as in `solve_pair` (module docstring), K_n of
    every ball at its own contact angle.  No centrifugal or gyroscopic ball loads, rigid rings.

    Solution: with K_n of every ball frozen the equations are the stationarity conditions of a
    convex potential (`_CombinedProblem`), minimised by Newton's method with a capped step and
    Armijo backtracking (`_newton_minimise`); an outer loop refreshes K_n at the new contact
    angles until it changes by less than tol.  Start: the axial-only solution of `solve_pair`
    (which also gives the position-preload offset e), rho = 0.

    Inputs: those of `solve_pair`, plus radial_load_N (N, scalar or (N,); negative values point
    to psi = 180 deg).  Points with zero radial load return the `solve_pair` outputs unchanged
    (the extra outputs below evaluated at that state, rho = 0).

    Returns the `solve_pair` dict, where per-bearing ball quantities (ball_load_*, delta_*,
    contact_angle_*, the Hertz a_/b_/p_max_/E_ell_/Rx_ outputs) now refer to the most loaded
    ball of that bearing, axial_force_* = sum_k Q sin(alpha), axial_stiffness_A/B = dF_j/da_j at
    fixed rho, axial_stiffness_N_per_um = dF_ext/dx at constant radial load, and
    max_contact_pressure_MPa is the largest over all balls and both contacts; plus
      rho_mm                      rotor radial displacement along the load
      radial_force_A_N, _B_N      radial load share of each bearing
      max_ball_load_A_N, _B_N     largest ball load of each bearing
      loaded_zone_A, _B           fraction of balls in contact (delta > 1e-12 A_T)
      radial_stiffness_N_per_um   dF_r/drho at constant axial load (x free), including dK_n/dalpha
    and with return_ball_loads: ball_loads_A_N, ball_loads_B_N, ball_contact_angles_A_deg,
    ball_contact_angles_B_deg, each of shape (Z, N), ball k at `ball_azimuths_rad(Z)[k]`.

    Note: `torque.pair_torque` multiplies one ball's friction by Z; under a radial load it then
    treats every ball as the most loaded one (an upper bound), not the load distribution.
    """
    if arrangement not in SIGNS:
        raise ValueError(f"arrangement must be 'DB' or 'DF', got {arrangement!r}")
    if preload_kind not in ("position", "spring"):
        raise ValueError(f"preload_kind must be 'position' or 'spring', got {preload_kind!r}")
    common = dict(dr_mm=dr_mm, dz_mm=dz_mm, T_inner_ring_C=T_inner_ring_C,
                  T_outer_ring_C=T_outer_ring_C, T_ball_C=T_ball_C, T_ref_C=T_ref_C,
                  preload_kind=preload_kind, preload_assembled_N=preload_assembled_N,
                  axial_load_N=axial_load_N, dr_ref_mm=dr_ref_mm, dz_ref_mm=dz_ref_mm,
                  compliance_mm_per_N=compliance_mm_per_N, tol=tol, max_outer=max_outer,
                  chunk=chunk)
    N = _n_points(dr_mm, dz_mm, T_inner_ring_C, T_outer_ring_C, T_ball_C, preload_assembled_N,
                  axial_load_N, dr_ref_mm, dz_ref_mm, compliance_mm_per_N, radial_load_N)
    common["axial_load_N"] = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    base = solve_pair(g, arrangement, **common)          # axial-only path (radial_load_N = 0)
    Fr = np.broadcast_to(np.asarray(radial_load_N, float), (N,))
    s = SIGNS[arrangement][:, None]
    P = np.broadcast_to(np.asarray(preload_assembled_N, float), (N,))
    Fa = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
    dr, dz = _pair_array(dr_mm, N), _pair_array(dz_mm, N)
    temps = [None if T is None else _pair_array(T, N)
             for T in (T_inner_ring_C, T_outer_ring_C, T_ball_C)]
    tg = thermal_geometry(g, *temps, T_ref_C=float(T_ref_C))
    tg = ThermalGeometry(*(np.broadcast_to(v, (2, N)) for v in
                           (tg.A_T_mm, tg.Dw_mm, tg.f_i, tg.f_o, tg.dm_mm)))
    e = base["preload_offset_mm"]
    x0 = base["x_mm"]
    ap0 = np.stack([base["approach_A_mm"], base["approach_B_mm"]])
    if preload_kind == "spring":
        FA_req = s[0, 0] * Fa + P
        Freq = np.stack([np.maximum(FA_req, 0.0), P])
        lost_spring = FA_req < 0.0
        modes = {"spring": np.ones(N, bool)}
    else:
        Freq, lost_spring = None, None
        modes = {"rigid": c == 0.0, "compliant": c != 0.0}

    out = {k: np.array(v, copy=True) for k, v in base.items()}
    extra = list(COMBINED_KEYS) + (list(BALL_KEYS) if return_ball_loads else [])
    for k in extra:
        out[k] = np.zeros((g.Z, N)) if k in BALL_KEYS else np.zeros(N)
    for mode, mmask in modes.items():
        for solve, smask in ((False, Fr == 0.0), (True, Fr != 0.0)):
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
                    solve=solve, ball_loads=return_ball_loads)
                for k, v in res.items():
                    if solve or k in extra:
                        out[k][..., ii] = v
    return out
