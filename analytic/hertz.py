"""Exact Hertz point contact (elliptical contact of two elastic bodies), vectorised.

Units: lengths mm, forces N, moduli and pressures MPa (= N/mm^2); stiffness N/mm^1.5.

Geometry (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 2 and 6; Hamrock 1983;
Johnson, Contact Mechanics, 1985, ch. 4).  Two bodies touch at a point; in principal coordinates the
initial gap is  h(x, y) = x^2 / (2 Rx) + y^2 / (2 Ry)  with the effective radii
1/Rx = rho_I1 + rho_II1 and 1/Ry = rho_I2 + rho_II2 (curvatures rho, convex positive).  Harris's
curvature sum and curvature difference are

    sum_rho = 1/Rx + 1/Ry                       [1/mm]
    F(rho)  = |1/Rx - 1/Ry| / (1/Rx + 1/Ry)     [-]

Exact solution (Hertz 1882; Harris & Kotzalas Vol. 1 ch. 6; Hamrock & Brewe 1983).  With
kappa = a/b >= 1 the ellipticity (a semi-major axis, along the direction of the larger effective
radius), m = 1 - 1/kappa^2 the parameter of the complete elliptic integrals K(m), E(m) (scipy's
convention: argument m = k^2), the ellipticity solves

    F(rho) = [(kappa^2 + 1) E - 2 K] / [(kappa^2 - 1) E]     equivalently
    Ry/Rx  = (kappa^2 E - K) / (K - E)                         (Ry >= Rx)

and, with R = 1/sum_rho and the contact modulus E* = [(1-nu1^2)/E1 + (1-nu2^2)/E2]^-1
(Johnson 1985 ch. 4; Hamrock's E' = 2 E*):

    a     = (3 kappa^2 E Q R / (pi E*))^(1/3)
    b     = (3 E Q R / (pi kappa E*))^(1/3)
    delta = K [ (9 / (2 E R)) (Q / (2 pi kappa E*))^2 ]^(1/3)      (mutual approach)
    p_max = 3 Q / (2 pi a b)
    Q     = K_c delta^1.5,   K_c = 2 pi kappa E* sqrt(2 E R / (9 K^3))

For a sphere on a flat (kappa = 1, K = E = pi/2) these reduce to Johnson's (1985, ch. 4)
a = (3 Q R' / (4 E*))^(1/3), delta = a^2 / R' with R' the sphere radius (R = R'/2).

Numerics.  The root equation is rewritten with Carlson's symmetric integral R_D (DLMF 19.25.1):
K - E = (m/3) R_D(0, 1-m, 1) and E - (1-m) K = (m (1-m)/3) R_D(0, 1, 1-m), so

    Ry/Rx = B(m) / A(m),   A = (K - E)/m,   B = (E - (1-m) K) / (m (1-m))

where A and B are smooth and tend to pi/4 as m -> 0: nothing cancels near a circular contact.
For m < 0.1 A and B come from their hypergeometric series (DLMF 19.5.1-19.5.2, coefficients
c_n = ((1/2)_n / n!)^2); above, from scipy's ellipk/ellipe (ellipkm1 near m = 1).  The root is
found by Newton's method on u = ln kappa (kappa^2 = 1/(1-m)) with the bracket
0 <= u <= ln(Ry/Rx), started from a cubic-Hermite table of the exact solution (built once with the
same solver from Hamrock & Brewe's kappa = (Ry/Rx)^(2/pi)), so one step usually suffices.

Approximations (each its own function, for comparison and for speed where accuracy allows):
Brewe & Hamrock (1977), Hamrock & Brewe (1983), and Greenwood's (1985) near-circular asymptote.
The Moes / Antoine et al. (2006) explicit fit is not included: its coefficients could not be
checked against the paper here, and an unverified fit is worse than none.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import factorial, pi

import numpy as np
from scipy import special

ArrayLike = np.ndarray | float

# ---------------------------------------------------------------------------------------------
# series of A(m) = (K - E)/m and Bt(m) = (E - (1 - m) K)/m for small m (DLMF 19.5.1-19.5.2)
_N_SERIES = 30
_C = np.array([(factorial(2 * n) / (4.0 ** n * factorial(n) ** 2)) ** 2 for n in range(_N_SERIES + 1)])
# K = pi/2 sum c_n m^n ; E = pi/2 sum c_n m^n / (1 - 2n)
_A_COEF = np.array([_C[n] * 2 * n / (2 * n - 1) for n in range(1, _N_SERIES + 1)]) * (pi / 2)
_BT_COEF = np.array([_C[n - 1] - _C[n] * 2 * n / (2 * n - 1) for n in range(1, _N_SERIES + 1)]) * (pi / 2)
_M_SERIES = 0.1  # below: series (truncation error ~ 0.1^30); above: scipy ellipk/ellipe


def _poly(coef: np.ndarray, m: np.ndarray):
    """Value and derivative of sum coef[j] m^j (Horner)."""
    p = np.full_like(m, coef[-1])
    dp = np.zeros_like(m)
    for c in coef[-2::-1]:
        dp = dp * m + p
        p = p * m + c
    return p, dp


def _AB(m: np.ndarray, m1: np.ndarray):
    """A = (K-E)/m, B = (E-(1-m)K)/(m(1-m)), their m-derivatives, and K, E (m1 = 1 - m)."""
    small = m < _M_SERIES
    if not small.any():                       # the usual case for ball/raceway contacts
        k = special.ellipkm1(m1)
        e = special.ellipe(m)
        mm1 = m * m1
        a = (k - e) / m
        b = (e - m1 * k) / mm1
        return a, b, e / (2 * mm1) - a / m, (0.5 * k - b * (1 - 2 * m)) / mm1, k, e
    A = np.empty_like(m)
    B = np.empty_like(m)
    dA = np.empty_like(m)
    dB = np.empty_like(m)
    K = np.empty_like(m)
    E = np.empty_like(m)
    if np.any(small):
        ms, m1s = m[small], m1[small]
        a, da = _poly(_A_COEF, ms)
        bt, dbt = _poly(_BT_COEF, ms)
        A[small], dA[small] = a, da
        B[small] = bt / m1s
        dB[small] = dbt / m1s + bt / m1s ** 2
        K[small] = special.ellipk(ms)
        E[small] = special.ellipe(ms)
    big = ~small
    if np.any(big):
        mb, m1b = m[big], m1[big]
        k = special.ellipkm1(m1b)
        e = special.ellipe(mb)
        a = (k - e) / mb
        b = (e - m1b * k) / (mb * m1b)
        A[big], B[big], K[big], E[big] = a, b, k, e
        dA[big] = e / (2 * mb * m1b) - a / mb
        dB[big] = k / (2 * mb * m1b) - b * (1 - 2 * mb) / (mb * m1b)
    return A, B, dA, dB, K, E


def _newton(rho: np.ndarray, u: np.ndarray, tol: float, max_iter: int, quadratic_exit: bool):
    """Safeguarded Newton on g(u) = ln(B/A) - ln(rho), u = ln kappa in [0, ln rho].

    Exit when a step is below tol * u, or (quadratic_exit) when every step is below 1e-7 * u:
    the step is then taken and the values moved along with it to first order (Newton's error
    after such a step is ~ (g''/2g') du^2, below 1e-14 relative), saving one evaluation."""
    ln_rho = np.log(rho)
    lo = np.zeros_like(rho)
    hi = ln_rho.copy()
    u = np.clip(u, lo, hi)
    for _ in range(max_iter):
        m1 = np.exp(-2.0 * u)
        m = -np.expm1(-2.0 * u)
        A, B, dA, dB, K, E = _AB(m, m1)
        g = np.log(B / A) - ln_rho              # increasing in u
        dg = (dB / B - dA / A) * 2.0 * m1      # d g / d u
        lo = np.where(g < 0, u, lo)
        hi = np.where(g > 0, u, hi)
        step = np.where(dg > 0, g / np.where(dg > 0, dg, 1.0), 0.0)
        new = u - step
        bad = (new < lo) | (new > hi) | ~np.isfinite(new)
        new = np.where(bad, 0.5 * (lo + hi), new)
        du = new - u
        size = np.abs(du) / np.maximum(u, 1e-300)
        if np.all(size <= tol):
            # converged: the values at u are exact to the size of this last step
            return EllipticityState(np.exp(u), K, E, u, A, B, dg, m1, np.ones(u.shape, bool))
        if quadratic_exit and np.all(size <= 1e-7):
            t = 2.0 * m1 * du                   # dm along the step
            return EllipticityState(np.exp(new), K + 0.5 * B * t, E - 0.5 * A * t, new, A + dA * t,
                                    B + dB * t, dg, np.exp(-2.0 * new), np.ones(u.shape, bool))
        u = new
    # out of iterations: the last iterate, flagged where its step was not yet small
    m1 = np.exp(-2.0 * u)
    m = -np.expm1(-2.0 * u)
    A, B, dA, dB, K, E = _AB(m, m1)
    dg = (dB / B - dA / A) * 2.0 * m1
    return EllipticityState(np.exp(u), K, E, u, A, B, dg, m1,
                            (size <= (1e-7 if quadratic_exit else tol)) & np.isfinite(u))


# Starting values: u(ln rho) tabulated once (cubic Hermite with exact slopes du/dln(rho) = 1/g'),
# interpolation error < 1e-12 relative, so that one Newton step reaches machine precision.
_TABLE_H = 0.01
_TABLE_T_MAX = 14.0            # ln(rho) up to ~1.2e6; beyond, Hamrock & Brewe's start is used
_table: np.ndarray | None = None


def _start_table() -> np.ndarray:
    """Per-interval cubic coefficients c0..c3 of u(s), s in [0, 1) the position in the interval."""
    global _table
    if _table is None:
        t = np.arange(0.0, _TABLE_T_MAX + 2 * _TABLE_H, _TABLE_H)
        st = _newton(np.exp(t), (2.0 / pi) * t, 1e-15, 80, False)
        u, d = st.u, _TABLE_H / st.dg_du
        u0, u1, d0, d1 = u[:-1], u[1:], d[:-1], d[1:]
        _table = np.column_stack([u0, d0, 3 * (u1 - u0) - 2 * d0 - d1, 2 * (u0 - u1) + d0 + d1])
    return _table


def _start(ln_rho: np.ndarray) -> np.ndarray:
    c = _start_table()
    x = np.minimum(ln_rho, _TABLE_T_MAX) * (1.0 / _TABLE_H)
    i = x.astype(np.int64)
    s = x - i
    ci = c[i]
    u = ci[:, 0] + s * (ci[:, 1] + s * (ci[:, 2] + s * ci[:, 3]))
    return u if np.all(ln_rho <= _TABLE_T_MAX) else np.where(ln_rho <= _TABLE_T_MAX, u,
                                                              (2.0 / pi) * ln_rho)


@dataclass(frozen=True)
class EllipticityState:
    """Solution of the ellipticity equation per contact (flat arrays, dimensionless), with the
    pieces the bearing model differentiates: kappa = a/b, K_ell and E_ell the complete elliptic
    integrals at m = 1 - 1/kappa^2, u = ln kappa, A = (K - E)/m, B = (E - (1-m) K)/(m (1-m)),
    dg_du the derivative of g(u) = ln(B/A) - ln(rho), m1 = 1 - m, and `converged` per entry."""
    kappa: np.ndarray
    K_ell: np.ndarray
    E_ell: np.ndarray
    u: np.ndarray
    A: np.ndarray
    B: np.ndarray
    dg_du: np.ndarray
    m1: np.ndarray
    converged: np.ndarray


def ellipticity_state(rho: np.ndarray, u0=None, tol: float = 1e-15,
                      max_iter: int = 60) -> EllipticityState:
    """Ellipticity for a flat array of radius ratios rho = Ry/Rx >= 1 (-): Ry/Rx = B/A, i.e.
    (kappa^2 E - K)/(K - E) (Harris Vol. 1 ch. 6; Hamrock & Brewe 1983). Fast path: from the
    tabulated start one Newton step, the values moved along it to first order; anything else goes
    to the safeguarded loop (`_newton`), whose convergence is reported per entry."""
    ln_rho = np.log(rho)
    u = _start(ln_rho) if u0 is None else np.broadcast_to(np.asarray(u0, float), rho.shape).ravel()
    m1 = np.exp(-2.0 * u)
    m = 1.0 - m1
    if np.all(m >= _M_SERIES):
        A, B, dA, dB, K, E = _AB(m, m1)
        g = np.log(B / A)
        g -= ln_rho
        dg = (dB / B - dA / A) * (2.0 * m1)
        du = -g / dg
        if np.all((dg > 0) & (np.abs(du) <= 1e-7 * u)):
            t = 2.0 * m1 * du
            return EllipticityState(np.exp(u) * (1.0 + du), K + 0.5 * B * t, E - 0.5 * A * t,
                                    u + du, A + dA * t, B + dB * t, dg, m1 * (1.0 - 2.0 * du),
                                    np.ones(u.shape, bool))
    return _newton(rho, u, tol, max_iter, True)


def solve_ellipticity(radius_ratio: ArrayLike, u0: ArrayLike | None = None,
                      tol: float = 1e-15, max_iter: int = 60):
    """Exact Hertz ellipticity from the ratio of effective radii rho = Ry/Rx >= 1 (a ratio below 1
    is inverted: the semi-major axis always lies along the larger radius).

    Solves Ry/Rx = (kappa^2 E - K)/(K - E) (Harris Vol. 1 ch. 6, rearranged; Hamrock & Brewe
    1983) by safeguarded Newton on u = ln kappa; see the module docstring for the
    cancellation-free form used near a circular contact.

    Returns (kappa, K, E, u): ellipticity a/b (-), complete elliptic integrals of the first and
    second kind at m = 1 - 1/kappa^2 (-), and u = ln kappa (`u0`: optional starting value; by
    default an interpolated exact solution).  Relative accuracy about 1e-14.
    """
    rho = np.asarray(radius_ratio, dtype=float)
    rho = np.where(rho < 1.0, 1.0 / rho, rho)
    shape = rho.shape
    st = ellipticity_state(np.atleast_1d(rho).ravel(), u0, tol, max_iter)
    return st.kappa.reshape(shape), st.K_ell.reshape(shape), st.E_ell.reshape(shape), st.u.reshape(shape)


def ellipticity(radius_ratio: ArrayLike) -> np.ndarray:
    """Exact ellipticity kappa = a/b (-) for Ry/Rx (see `solve_ellipticity`)."""
    return solve_ellipticity(radius_ratio)[0]


def curvature_difference_from_kappa(kappa: ArrayLike) -> np.ndarray:
    """Forward Hertz relation F(rho) = [(kappa^2+1) E - 2K] / [(kappa^2-1) E] (Harris Vol. 1
    ch. 6), evaluated directly with scipy's ellipk/ellipe (the textbook route; it loses digits
    as kappa -> 1, which is why the solver does not use it).  kappa > 1."""
    k2 = np.asarray(kappa, dtype=float) ** 2
    m = 1.0 - 1.0 / k2
    K, E = special.ellipk(m), special.ellipe(m)
    return ((k2 + 1.0) * E - 2.0 * K) / ((k2 - 1.0) * E)


# ---------------------------------------------------------------------------------------------
def contact_modulus_MPa(E1_MPa: ArrayLike, nu1: ArrayLike, E2_MPa: ArrayLike, nu2: ArrayLike):
    """Contact (plane-strain) modulus E* = [(1-nu1^2)/E1 + (1-nu2^2)/E2]^-1, MPa (Johnson,
    Contact Mechanics 1985, ch. 4; Hamrock's effective modulus E' = 2 E*)."""
    return 1.0 / ((1.0 - np.square(nu1)) / E1_MPa + (1.0 - np.square(nu2)) / E2_MPa)


def curvature_sum_per_mm(Rx_mm: ArrayLike, Ry_mm: ArrayLike) -> np.ndarray:
    """Curvature sum sum_rho = 1/Rx + 1/Ry, 1/mm (Harris Vol. 1 ch. 2)."""
    return 1.0 / np.asarray(Rx_mm, float) + 1.0 / np.asarray(Ry_mm, float)


def curvature_difference(Rx_mm: ArrayLike, Ry_mm: ArrayLike) -> np.ndarray:
    """Curvature difference F(rho) = |1/Rx - 1/Ry| / (1/Rx + 1/Ry), - (Harris Vol. 1 ch. 2)."""
    cx, cy = 1.0 / np.asarray(Rx_mm, float), 1.0 / np.asarray(Ry_mm, float)
    return np.abs(cx - cy) / (cx + cy)


def ball_raceway_radii_mm(Dw_mm: ArrayLike, dm_mm: ArrayLike, alpha_deg: ArrayLike,
                          f: ArrayLike, race: str):
    """Effective radii (Rx along rolling, Ry transverse), mm, of a ball on a raceway groove.

    Harris Vol. 1 ch. 2 with gamma = Dw cos(alpha) / dm and groove ratio
    f = r_groove / Dw:  inner race  1/Rx = (2/Dw) / (1 - gamma),  outer race 1/Rx = (2/Dw) / (1 + gamma),
    both 1/Ry = 2/Dw - 1/(f Dw) = (2 f - 1)/(f Dw).  Hence Rx_i = Dw (1 - gamma)/2,
    Rx_o = Dw (1 + gamma)/2, Ry = f Dw / (2 f - 1) (Hamrock 1983, ball-bearing radii).
    race: "inner" or "outer".
    """
    Dw = np.asarray(Dw_mm, float)
    gamma = Dw * np.cos(np.radians(alpha_deg)) / np.asarray(dm_mm, float)
    if race == "inner":
        Rx = 0.5 * Dw * (1.0 - gamma)
    elif race == "outer":
        Rx = 0.5 * Dw * (1.0 + gamma)
    else:
        raise ValueError(f"race must be 'inner' or 'outer', got {race!r}")
    f = np.asarray(f, float)
    Ry = f * Dw / (2.0 * f - 1.0)
    return Rx, Ry


def ball_raceway_curvature(Dw_mm, dm_mm, alpha_deg, f, race: str):
    """Harris's curvature sum (1/mm) and curvature difference F(rho) (-) of a ball/raceway contact
    (Harris Vol. 1 ch. 2): inner F = (1/f + 2g/(1-g)) / (4 - 1/f + 2g/(1-g)),
    outer F = (1/f - 2g/(1+g)) / (4 - 1/f - 2g/(1+g)), sum_rho = (4 - 1/f +- 2g/(1 -+ g)) / Dw."""
    Rx, Ry = ball_raceway_radii_mm(Dw_mm, dm_mm, alpha_deg, f, race)
    return curvature_sum_per_mm(Rx, Ry), curvature_difference(Rx, Ry)


@dataclass(frozen=True)
class HertzContact:
    """Result of a Hertz point contact (arrays broadcast over operating points)."""
    a_mm: np.ndarray                 # semi-major axis (along the larger effective radius)
    b_mm: np.ndarray                 # semi-minor axis
    delta_mm: np.ndarray             # mutual approach of distant points
    p_max_MPa: np.ndarray            # maximum (central) pressure
    kappa: np.ndarray                # ellipticity a/b
    K_N_per_mm15: np.ndarray         # contact stiffness, Q = K delta^1.5
    K_elliptic: np.ndarray           # complete elliptic integral of the first kind K(m)
    E_elliptic: np.ndarray           # complete elliptic integral of the second kind E(m)


def stiffness_from_kappa(R_mm, E_star_MPa, kappa, K, E):
    """Contact stiffness K_c = 2 pi kappa E* sqrt(2 E R / (9 K^3)), N/mm^1.5, with R = 1/sum_rho
    (Hamrock & Brewe 1983, approach solved for Q; Harris Vol. 1 ch. 6 in other notation)."""
    return 2.0 * pi * kappa * E_star_MPa * np.sqrt(2.0 * E * R_mm / (9.0 * K ** 3))


def contact_stiffness_N_per_mm15(Rx_mm, Ry_mm, E_star_MPa):
    """Hertz contact stiffness K_c (N/mm^1.5, Q = K_c delta^1.5) of a point contact with effective
    radii Rx_mm, Ry_mm and contact modulus E_star_MPa.  Formula: `stiffness_from_kappa`."""
    Rx, Ry = np.asarray(Rx_mm, float), np.asarray(Ry_mm, float)
    kappa, K, E, _ = solve_ellipticity(Ry / Rx)
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    return stiffness_from_kappa(R, E_star_MPa, kappa, K, E)


def hertz_from_kappa(Q_N, R_mm, E_star_MPa, kappa, K, E) -> HertzContact:
    """Semi-axes, approach, maximum pressure and stiffness for a known ellipticity (Hamrock &
    Brewe 1983 with E' = 2 E*; Harris Vol. 1 ch. 6).  Q_N >= 0; Q = 0 gives zeros."""
    Q = np.maximum(np.asarray(Q_N, float), 0.0)
    c = Q * R_mm / (pi * E_star_MPa)
    a = np.cbrt(3.0 * kappa ** 2 * E * c)
    b = np.cbrt(3.0 * E * c / kappa)
    delta = K * np.cbrt(9.0 / (2.0 * E * R_mm) * (Q / (2.0 * pi * kappa * E_star_MPa)) ** 2)
    ab = a * b
    p = np.divide(1.5 * Q, pi * ab, out=np.zeros_like(ab), where=ab > 0)
    Kc = stiffness_from_kappa(R_mm, E_star_MPa, kappa, K, E)
    return HertzContact(a, b, delta, p, np.broadcast_to(kappa, a.shape), Kc,
                        np.broadcast_to(K, a.shape), np.broadcast_to(E, a.shape))


def hertz_point_contact(Q_N, Rx_mm, Ry_mm, E_star_MPa) -> HertzContact:
    """Exact Hertz solution for a normal load Q_N (N) between bodies with effective radii Rx_mm,
    Ry_mm (mm, convex positive; conforming grooves enter through Ry = f Dw/(2f-1)) and contact
    modulus E_star_MPa (MPa, `contact_modulus_MPa`).  Formulas and sources: module docstring."""
    Rx, Ry = np.asarray(Rx_mm, float), np.asarray(Ry_mm, float)
    kappa, K, E, _ = solve_ellipticity(Ry / Rx)
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    return hertz_from_kappa(Q_N, R, E_star_MPa, kappa, K, E)


def series_stiffness_N_per_mm15(K_i, K_o):
    """Stiffness of two Hertz contacts in series (inner + outer through one ball):
    K_n = [K_i^(-2/3) + K_o^(-2/3)]^(-3/2), N/mm^1.5 (Harris Vol. 1 ch. 7: delta = delta_i + delta_o)."""
    return (np.asarray(K_i, float) ** (-2.0 / 3.0) + np.asarray(K_o, float) ** (-2.0 / 3.0)) ** -1.5


# ---------------------------------------------------------------------------------------------
# approximations
def ellipticity_brewe_hamrock_1977(radius_ratio):
    """Brewe & Hamrock (1977), J. Lubr. Technol. 99, 485-487, curve fits for 1 <= Ry/Rx <= 100:
    kappa = 1.0339 (Ry/Rx)^0.6360, E = 1.0003 + 0.5968 Rx/Ry, K = 1.5277 + 0.6023 ln(Ry/Rx).
    Returns (kappa, K, E), all dimensionless."""
    r = np.asarray(radius_ratio, float)
    return 1.0339 * r ** 0.6360, 1.5277 + 0.6023 * np.log(r), 1.0003 + 0.5968 / r


def ellipticity_hamrock_brewe_1983(radius_ratio):
    """Hamrock & Brewe (1983), J. Lubr. Technol. 105, 171-177 (also Hamrock, Fundamentals of Fluid
    Film Lubrication, ch. 3): kappa = (Ry/Rx)^(2/pi), E = 1 + (pi/2 - 1) Rx/Ry,
    K = pi/2 + (pi/2 - 1) ln(Ry/Rx).  Exact at the circular contact.  Returns (kappa, K, E)."""
    r = np.asarray(radius_ratio, float)
    q = pi / 2.0 - 1.0
    return r ** (2.0 / pi), pi / 2.0 + q * np.log(r), 1.0 + q / r


def ellipticity_greenwood_1985(radius_ratio):
    """Greenwood (1985), J. Tribol. 107, 501-504: asymptotic ellipticity for moderately elliptical
    contacts, a/b = (Ry/Rx)^(2/3) (the exact first-order behaviour as Ry/Rx -> 1)."""
    return np.asarray(radius_ratio, float) ** (2.0 / 3.0)
