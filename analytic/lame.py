"""Closed-form thick-ring (Lamé) press fits: the cross-check every FE fit is held against.

Units: radii and displacements mm, moduli and pressures MPa, interferences um (DIAMETRAL,
positive = interference, negative = clearance), temperatures C.

Thick cylinder under internal pressure p_in at r = a and external pressure p_out at r = b
(Timoshenko & Goodier, *Theory of Elasticity* 3rd ed. §28; Harris & Kotzalas, *Rolling Bearing
Analysis* 5th ed. Vol. 1 ch. 8 "Fits"; DIN 7190-1:2017 eq. for the elastic press fit):

    sigma_rr = C1 - C2 / r^2,      sigma_tt = C1 + C2 / r^2,
    C1 = (p_in a^2 - p_out b^2) / (b^2 - a^2),   C2 = (p_in - p_out) a^2 b^2 / (b^2 - a^2)

and, in plane stress (sigma_zz = 0, the free-ended short ring),

    u_r(r) = [(1 - nu) C1 r + (1 + nu) C2 / r] / E            (Lamé: u_r = A r + B / r).

Plane strain (eps_zz = 0, a long cylinder) is the same with E -> E / (1 - nu^2) and
nu -> nu / (1 - nu) (Timoshenko & Goodier §28, §14). A real ring of width comparable to its wall
lies between the two; the FE (axisymmetric, 3-D) sits between these bounds.

Fit pressure between an inner member (bore a, fit radius c) and an outer member (c, outer radius b),
from radial displacement compatibility u_out(c) - u_in(c) = delta_d / 2 (Harris & Kotzalas Vol. 1
eq. 8.x; DIN 7190):

    p = delta_d / ( d_fit [ (1/E_o) ((b^2 + c^2)/(b^2 - c^2) + nu_o)
                          + (1/E_i) ((c^2 + a^2)/(c^2 - a^2) - nu_i) ] ),   d_fit = 2 c

A solid inner member has a = 0 (the bracket becomes 1 - nu_i). A negative interference (clearance)
leaves the fit open: p = 0.

Temperature: the diametral interference of the FREE parts at T (free thermal growth of each part,
u = theta r with theta the integral of the CTE from T_ref, see analytic.materials) is

    delta_d(T) = delta_d(T_ref) + (theta_inner - theta_outer) d_fit.

Rotation (both members spinning at omega, body force rho omega^2 r): the rotating free ring
(Timoshenko & Goodier §32, "rotating disks"; plane stress for a thin disc, plane strain for a long
cylinder) superposed on the press fit: `rotating_displacement_mm`, `rotating_fit_pressure_MPa`,
`fit_open_speed_rad_s`. Density rho in N s^2/mm^4 (kg/m^3 x 1e-12, analytic.materials).

Multi-layer fits (shaft / inner ring / ... / housing): concentric layers, interface pressures solved
together from compatibility as a small linear complementarity problem (closed: pressure >= 0 and
overlap taken up exactly; open: pressure 0 and the free parts do not touch).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Literal

import numpy as np

from analytic.materials import Material

Assumption = Literal["plane_stress", "plane_strain"]
ASSUMPTIONS = ("plane_stress", "plane_strain")
UM_PER_MM = 1000.0


def effective_elastic(E_MPa, nu, assumption: Assumption = "plane_stress"):
    """(E, nu) to use in the plane-stress formulas for the given assumption.

    plane_stress: unchanged. plane_strain: E / (1 - nu^2), nu / (1 - nu)
    (Timoshenko & Goodier, Theory of Elasticity, §14 and §28). Units: E in MPa, nu (-).
    """
    if assumption == "plane_stress":
        return np.asarray(E_MPa, float), np.asarray(nu, float)
    if assumption == "plane_strain":
        E = np.asarray(E_MPa, float)
        v = np.asarray(nu, float)
        return E / (1.0 - v * v), v / (1.0 - v)
    raise ValueError(f"assumption must be one of {ASSUMPTIONS}, got {assumption!r}")


def lame_constants(r_in_mm, r_out_mm, p_in_MPa, p_out_MPa):
    """Lamé stress constants (C1 in MPa, C2 in MPa*mm^2) of a ring a <= r <= b.

    sigma_rr = C1 - C2/r^2, sigma_tt = C1 + C2/r^2 with
    C1 = (p_in a^2 - p_out b^2)/(b^2 - a^2), C2 = (p_in - p_out) a^2 b^2/(b^2 - a^2)
    (Timoshenko & Goodier §28). a = 0 (solid) gives C2 = 0, C1 = -p_out.
    """
    a2 = np.asarray(r_in_mm, float) ** 2
    b2 = np.asarray(r_out_mm, float) ** 2
    p_in = np.asarray(p_in_MPa, float)
    p_out = np.asarray(p_out_MPa, float)
    den = b2 - a2
    return (p_in * a2 - p_out * b2) / den, (p_in - p_out) * a2 * b2 / den


def radial_stress_MPa(r_mm, r_in_mm, r_out_mm, p_in_MPa=0.0, p_out_MPa=0.0):
    """Radial stress sigma_rr(r) = C1 - C2/r^2 in MPa (tension positive; Timoshenko §28)."""
    C1, C2 = lame_constants(r_in_mm, r_out_mm, p_in_MPa, p_out_MPa)
    r = np.asarray(r_mm, float)
    return C1 - C2 / r**2


def hoop_stress_MPa(r_mm, r_in_mm, r_out_mm, p_in_MPa=0.0, p_out_MPa=0.0):
    """Hoop stress sigma_tt(r) = C1 + C2/r^2 in MPa (tension positive; Timoshenko §28)."""
    C1, C2 = lame_constants(r_in_mm, r_out_mm, p_in_MPa, p_out_MPa)
    r = np.asarray(r_mm, float)
    return C1 + C2 / r**2


def radial_displacement_mm(r_mm, r_in_mm, r_out_mm, E_MPa, nu, p_in_MPa=0.0, p_out_MPa=0.0,
                           assumption: Assumption = "plane_stress"):
    """Radial displacement u_r(r) in mm of a ring a <= r <= b loaded by pressures on its faces.

    u_r = [(1 - nu) C1 r + (1 + nu) C2 / r] / E (plane stress, Timoshenko & Goodier §28; i.e.
    Lamé u = A r + B/r), with the plane-strain substitution of `effective_elastic`. Pressures in
    MPa (positive = compressive on the face), radii mm, E MPa. Vectorised over all arguments.
    """
    E, v = effective_elastic(E_MPa, nu, assumption)
    C1, C2 = lame_constants(r_in_mm, r_out_mm, p_in_MPa, p_out_MPa)
    r = np.asarray(r_mm, float)
    return ((1.0 - v) * C1 * r + (1.0 + v) * C2 / r) / E


def fit_compliance_mm_per_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                              E_outer_MPa, nu_outer, assumption: Assumption = "plane_stress"):
    """Radial compliance of a two-member fit: (u_out(c) - u_in(c)) per unit fit pressure, mm/MPa.

    c [ (1/E_o)((b^2 + c^2)/(b^2 - c^2) + nu_o) + (1/E_i)((c^2 + a^2)/(c^2 - a^2) - nu_i) ]
    (Harris & Kotzalas Vol. 1 ch. 8; DIN 7190-1). a = r_inner_mm (0 for a solid inner member).
    """
    Ei, vi = effective_elastic(E_inner_MPa, nu_inner, assumption)
    Eo, vo = effective_elastic(E_outer_MPa, nu_outer, assumption)
    a2 = np.asarray(r_inner_mm, float) ** 2
    c = np.asarray(r_fit_mm, float)
    b2 = np.asarray(r_outer_mm, float) ** 2
    c2 = c * c
    return c * (((b2 + c2) / (b2 - c2) + vo) / Eo + ((c2 + a2) / (c2 - a2) - vi) / Ei)


def fit_pressure_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa,
                     nu_outer, interference_um, assumption: Assumption = "plane_stress"):
    """Fit (contact) pressure in MPa of an inner member in an outer ring, from the DIAMETRAL
    interference in um; 0 when the fit is open (interference <= 0).

    p = max(0, delta_d / 2) / compliance (see `fit_compliance_mm_per_MPa`; Harris & Kotzalas
    Vol. 1 ch. 8, DIN 7190-1, Timoshenko & Goodier §28). r_inner_mm = 0 for a solid shaft.
    Vectorised (numpy broadcasting over every argument).
    """
    _check_radii(r_inner_mm, r_fit_mm, r_outer_mm)
    delta_r_mm = 0.5 * np.asarray(interference_um, float) / UM_PER_MM
    comp = fit_compliance_mm_per_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                     E_outer_MPa, nu_outer, assumption)
    return np.maximum(delta_r_mm, 0.0) / comp


@dataclass(frozen=True)
class FitState:
    """Two-member fit under its fit pressure. Displacements are radial, mm, at the fit radius
    (inner member contracts: u_inner <= 0; outer member expands: u_outer >= 0)."""
    fit_pressure_MPa: np.ndarray
    u_inner_at_fit_mm: np.ndarray
    u_outer_at_fit_mm: np.ndarray
    is_open: np.ndarray


def fit_state(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa, nu_outer,
              interference_um, assumption: Assumption = "plane_stress") -> FitState:
    """Fit pressure and the displacements of both members at the fit radius (Lamé, see module)."""
    p = fit_pressure_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa,
                         nu_outer, interference_um, assumption)
    u_in = radial_displacement_mm(r_fit_mm, r_inner_mm, r_fit_mm, E_inner_MPa, nu_inner, 0.0, p,
                                  assumption)
    u_out = radial_displacement_mm(r_fit_mm, r_fit_mm, r_outer_mm, E_outer_MPa, nu_outer, p, 0.0,
                                   assumption)
    return FitState(p, u_in, u_out, p <= 0.0)


def fit_displacement_mm(r_mm, member: Literal["inner", "outer"], r_inner_mm, r_fit_mm, r_outer_mm,
                        E_inner_MPa, nu_inner, E_outer_MPa, nu_outer, interference_um,
                        assumption: Assumption = "plane_stress"):
    """Radial displacement in mm at radius r of the inner member (r_inner <= r <= r_fit) or the
    outer member (r_fit <= r <= r_outer) under the fit pressure (Lamé u = A r + B/r).

    Example: the inner-ring raceway expansion from the shaft fit is member="outer" (the ring is
    the outer member of the shaft/ring fit) evaluated at the raceway radius.
    """
    p = fit_pressure_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa,
                         nu_outer, interference_um, assumption)
    if member == "inner":
        return radial_displacement_mm(r_mm, r_inner_mm, r_fit_mm, E_inner_MPa, nu_inner, 0.0, p,
                                      assumption)
    if member == "outer":
        return radial_displacement_mm(r_mm, r_fit_mm, r_outer_mm, E_outer_MPa, nu_outer, p, 0.0,
                                      assumption)
    raise ValueError(f"member must be 'inner' or 'outer', got {member!r}")


def rotating_displacement_mm(r_mm, r_in_mm, r_out_mm, E_MPa, nu, rho_N_s2_mm4, omega_rad_s,
                             assumption: Assumption = "plane_stress"):
    """Radial displacement u_r(r) in mm of a free ring a <= r <= b (a = 0: solid disc) spinning
    at omega about its axis, both faces free (sigma_rr(a) = sigma_rr(b) = 0).

    Plane stress (thin rotating disc; Timoshenko & Goodier, Theory of Elasticity 3rd ed. §32
    "Rotating disks", with u = r (sigma_tt - nu sigma_rr) / E):

        u_r = rho omega^2 r / (8 E) [ (3 + nu)(1 - nu)(a^2 + b^2)
                                      + (3 + nu)(1 + nu) a^2 b^2 / r^2 - (1 - nu^2) r^2 ]

    from sigma_rr = (3 + nu)/8 rho omega^2 (a^2 + b^2 - a^2 b^2/r^2 - r^2),
    sigma_tt = (3 + nu)/8 rho omega^2 (a^2 + b^2 + a^2 b^2/r^2 - (1 + 3 nu)/(3 + nu) r^2).
    Plane strain (long cylinder, eps_zz = 0; T&G §32, the rotating long cylinder): the same
    with the substitution of `effective_elastic` (E / (1 - nu^2), nu / (1 - nu)), which turns the
    plane-strain Navier equation (lam + 2 mu) d/dr(1/r d(r u)/dr) + rho omega^2 r = 0 into the
    plane-stress one. Units: radii mm, E MPa, rho N s^2/mm^4 (`Material.density_N_s2_mm4`:
    kg/m^3 x 1e-12), omega rad/s, u mm. Vectorised."""
    E, v = effective_elastic(E_MPa, nu, assumption)
    a2 = np.asarray(r_in_mm, float) ** 2
    b2 = np.asarray(r_out_mm, float) ** 2
    r = np.asarray(r_mm, float)
    w2 = np.asarray(rho_N_s2_mm4, float) * np.asarray(omega_rad_s, float) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):     # a solid disc: a = 0, a^2 b^2/r^2 = 0
        hole = np.where(a2 > 0, a2 * b2 / (r * r), 0.0)
    return w2 * r / (8.0 * E) * ((3 + v) * (1 - v) * (a2 + b2) + (3 + v) * (1 + v) * hole
                                 - (1 - v * v) * r * r)


def _spin_opening_mm_per_rad2_s2(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                 E_outer_MPa, nu_outer, rho_inner_N_s2_mm4, rho_outer_N_s2_mm4,
                                 assumption: Assumption):
    """Free radial separation at the fit radius per omega^2 (mm s^2): the outer member's bore
    grows more than the inner member's surface (`rotating_displacement_mm` of each at omega = 1)."""
    u_o = rotating_displacement_mm(r_fit_mm, r_fit_mm, r_outer_mm, E_outer_MPa, nu_outer,
                                   rho_outer_N_s2_mm4, 1.0, assumption)
    u_i = rotating_displacement_mm(r_fit_mm, r_inner_mm, r_fit_mm, E_inner_MPa, nu_inner,
                                   rho_inner_N_s2_mm4, 1.0, assumption)
    return u_o - u_i


def rotating_fit_pressure_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                              E_outer_MPa, nu_outer, interference_um, rho_inner_N_s2_mm4,
                              rho_outer_N_s2_mm4, omega_rad_s,
                              assumption: Assumption = "plane_stress"):
    """Fit pressure (MPa) of two members spinning together at omega (frictionless fit); 0 when
    the fit has opened.

    Superposition of the rotating free rings and the Lamé press fit (both linear; T&G §28, §32;
    Harris & Kotzalas Vol. 1 ch. 8 "fit loosening at speed"): with s(c) = u_rot,outer(c) -
    u_rot,inner(c) the free separation at the fit radius c from rotation alone,

        p = max(0, delta_d / 2 - s(c)) / compliance     (`fit_compliance_mm_per_MPa`).

    Units as `fit_pressure_MPa`; rho in N s^2/mm^4 (kg/m^3 x 1e-12), omega in rad/s."""
    _check_radii(r_inner_mm, r_fit_mm, r_outer_mm)
    s = _spin_opening_mm_per_rad2_s2(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                     E_outer_MPa, nu_outer, rho_inner_N_s2_mm4, rho_outer_N_s2_mm4,
                                     assumption) * np.asarray(omega_rad_s, float) ** 2
    delta_r_mm = 0.5 * np.asarray(interference_um, float) / UM_PER_MM
    comp = fit_compliance_mm_per_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                     E_outer_MPa, nu_outer, assumption)
    return np.maximum(delta_r_mm - s, 0.0) / comp


def rotating_fit_displacement_mm(r_mm, member: Literal["inner", "outer"], r_inner_mm, r_fit_mm,
                                 r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa, nu_outer,
                                 interference_um, rho_inner_N_s2_mm4, rho_outer_N_s2_mm4,
                                 omega_rad_s, assumption: Assumption = "plane_stress"):
    """Radial displacement (mm) at radius r of a member of a fit spinning at omega: the member's
    rotating free-ring displacement plus its Lamé displacement under the rotating fit pressure
    (`rotating_fit_pressure_MPa`; T&G §28, §32). Units as `rotating_fit_pressure_MPa`."""
    p = rotating_fit_pressure_MPa(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                  E_outer_MPa, nu_outer, interference_um, rho_inner_N_s2_mm4,
                                  rho_outer_N_s2_mm4, omega_rad_s, assumption)
    if member == "inner":
        return (radial_displacement_mm(r_mm, r_inner_mm, r_fit_mm, E_inner_MPa, nu_inner, 0.0, p,
                                       assumption)
                + rotating_displacement_mm(r_mm, r_inner_mm, r_fit_mm, E_inner_MPa, nu_inner,
                                           rho_inner_N_s2_mm4, omega_rad_s, assumption))
    if member == "outer":
        return (radial_displacement_mm(r_mm, r_fit_mm, r_outer_mm, E_outer_MPa, nu_outer, p, 0.0,
                                       assumption)
                + rotating_displacement_mm(r_mm, r_fit_mm, r_outer_mm, E_outer_MPa, nu_outer,
                                           rho_outer_N_s2_mm4, omega_rad_s, assumption))
    raise ValueError(f"member must be 'inner' or 'outer', got {member!r}")


def fit_open_speed_rad_s(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner, E_outer_MPa,
                         nu_outer, interference_um, rho_inner_N_s2_mm4, rho_outer_N_s2_mm4,
                         assumption: Assumption = "plane_stress"):
    """Speed (rad/s) at which a two-member fit spinning as one opens (fit-loosening speed):
    omega_open = sqrt(delta_d / 2 / s1) with s1 the free separation per omega^2 (see
    `rotating_fit_pressure_MPa`); 0 for a fit without interference, inf when rotation does not
    separate the members (s1 <= 0). Units as `rotating_fit_pressure_MPa`."""
    s1 = _spin_opening_mm_per_rad2_s2(r_inner_mm, r_fit_mm, r_outer_mm, E_inner_MPa, nu_inner,
                                      E_outer_MPa, nu_outer, rho_inner_N_s2_mm4,
                                      rho_outer_N_s2_mm4, assumption)
    d = np.maximum(0.5 * np.asarray(interference_um, float) / UM_PER_MM, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(s1 > 0, np.sqrt(d / np.where(s1 > 0, s1, 1.0)),
                        np.where(d > 0, np.inf, 0.0))


def interference_at_temperature_um(interference_um, d_fit_mm, inner: Material, outer: Material,
                                   T_C, T_ref_C=20.0):
    """Diametral interference (um) of the free parts at a uniform temperature T_C.

    delta_d(T) = delta_d(T_ref) + (theta_inner - theta_outer) d_fit, theta = integral of the
    instantaneous CTE from T_ref to T (`Material.thermal_strain`, exact for a linear CTE law).
    Free thermal growth u = theta r of each part (plane stress / free axial ends).
    Seed 000: TC4 shaft in a 9Cr18 ring on 35 mm gives about -0.05 um/C.
    """
    th_i = inner.thermal_strain(np.asarray(T_C, float), T_ref_C)
    th_o = outer.thermal_strain(np.asarray(T_C, float), T_ref_C)
    return np.asarray(interference_um, float) + (th_i - th_o) * np.asarray(d_fit_mm, float) * UM_PER_MM


@dataclass(frozen=True)
class MultilayerFit:
    """Concentric layers k = 0..N-1 spanning radii_mm[k]..radii_mm[k+1]; interface i (1..N-1) at
    radii_mm[i]. pressures_MPa[i-1] is the contact pressure at interface i (0 when open)."""
    radii_mm: np.ndarray
    E_MPa: np.ndarray
    nu: np.ndarray
    interferences_um: np.ndarray
    assumption: str
    pressures_MPa: np.ndarray
    closed: np.ndarray
    gap_um: np.ndarray   # diametral gap left at open interfaces (0 where closed), um

    def layer_pressures_MPa(self, layer: int) -> tuple[float, float]:
        """(pressure on the inner face, pressure on the outer face) of a layer, MPa."""
        p = np.concatenate([[0.0], self.pressures_MPa, [0.0]])
        return float(p[layer]), float(p[layer + 1])

    def displacement_mm(self, layer: int, r_mm):
        """Radial displacement (mm) at radius r in the given layer (Lamé, module docstring)."""
        p_in, p_out = self.layer_pressures_MPa(layer)
        return radial_displacement_mm(r_mm, self.radii_mm[layer], self.radii_mm[layer + 1],
                                      self.E_MPa[layer], self.nu[layer], p_in, p_out,
                                      self.assumption)

    def stress_rr_MPa(self, layer: int, r_mm):
        p_in, p_out = self.layer_pressures_MPa(layer)
        return radial_stress_MPa(r_mm, self.radii_mm[layer], self.radii_mm[layer + 1], p_in, p_out)


def multilayer_fit(radii_mm, E_MPa, nu, interferences_um,
                   assumption: Assumption = "plane_stress") -> MultilayerFit:
    """Interface pressures of N concentric layers with N-1 fits solved together.

    radii_mm: N+1 increasing radii (radii_mm[0] = 0 for a solid core); E_MPa, nu: N values;
    interferences_um: N-1 diametral interferences (+ interference, - clearance) of the free parts.
    Compatibility at interface i (radius R_i, between layers i-1 and i), when closed:
        u_i(R_i) - u_{i-1}(R_i) = delta_i / 2,
    with each layer's u linear in its face pressures (Lamé). With M the matrix of
    d(u_i - u_{i-1})/dp_j this is the linear complementarity problem
        p >= 0,  w = M p - delta/2 >= 0,  p . w = 0
    (w > 0: open interface with a gap), solved by enumerating the closed sets (N-1 is small;
    M is a P-matrix by reciprocity so the solution is unique). Example: shaft / inner ring / housing
    with a 3-layer stack (the inner ring touching the housing directly) or shaft / ring / housing
    with the ring shared between two fits.
    """
    R = np.asarray(radii_mm, float)
    E = np.asarray(E_MPa, float)
    v = np.asarray(nu, float)
    d = np.asarray(interferences_um, float)
    n_layers = len(R) - 1
    if len(d) != n_layers - 1:
        raise ValueError("need N+1 radii, N moduli and Poisson ratios, N-1 interferences (N >= 2)")
    M = multilayer_matrix(R, E, v, assumption)
    n = n_layers - 1
    q = 0.5 * d / UM_PER_MM
    q_tol = 1e-12 * max(float(np.max(np.abs(q))), 1e-30)
    p_tol = q_tol / float(np.min(np.diag(M)))
    best = None
    for k in range(n, -1, -1):
        for S in itertools.combinations(range(n), k):
            S = list(S)
            p = np.zeros(n)
            if S:
                p[S] = np.linalg.solve(M[np.ix_(S, S)], q[S])
            w = M @ p - q
            if np.all(p >= -p_tol) and np.all(w >= -q_tol):
                closed = np.isin(np.arange(n), S)
                best = (np.maximum(p, 0.0), closed,
                        np.where(closed, 0.0, 2.0 * w * UM_PER_MM))
                break
        if best is not None:
            break
    if best is None:   # pragma: no cover - a P-matrix LCP always has a solution
        raise RuntimeError("multilayer_fit: no consistent open/closed set found")
    p, closed, gap = best
    return MultilayerFit(R, E, v, d, assumption, p, closed, gap)


def multilayer_pressures_MPa(radii_mm, E_MPa, nu, interferences_um,
                             assumption: Assumption = "plane_stress") -> np.ndarray:
    """`multilayer_fit`'s interface pressures (MPa) for many states at once: interferences_um
    (n_rows, N-1) diametral per interface, geometry and materials shared. Returns (n_rows, N-1).
    The same complementarity problem and enumeration of closed sets (most closed first), each
    row taking the first consistent set."""
    M = multilayer_matrix(radii_mm, E_MPa, nu, assumption)
    n = M.shape[0]
    q = 0.5 * np.atleast_2d(np.asarray(interferences_um, float)) / UM_PER_MM
    q_tol = 1e-12 * np.maximum(np.abs(q).max(axis=1), 1e-30)
    p_tol = q_tol / float(np.min(np.diag(M)))
    out = np.full(q.shape, np.nan)
    todo = np.ones(q.shape[0], bool)
    for k in range(n, -1, -1):
        for S in itertools.combinations(range(n), k):
            S = list(S)
            p = np.zeros_like(q)
            if S:
                p[:, S] = np.linalg.solve(M[np.ix_(S, S)], q[:, S].T).T
            w = p @ M.T - q
            ok = todo & np.all(p >= -p_tol[:, None], axis=1) & np.all(w >= -q_tol[:, None], axis=1)
            out[ok] = np.maximum(p[ok], 0.0)
            todo &= ~ok
    return out


def multilayer_matrix(radii_mm, E_MPa, nu, assumption: Assumption = "plane_stress") -> np.ndarray:
    """(N-1, N-1) matrix M of `multilayer_fit`: M[i-1, j-1] = d(u_i - u_{i-1})(R_i) / d p_j in
    mm/MPa, the opening of interface i per unit pressure at interface j (Lamé, module docstring)."""
    R = np.asarray(radii_mm, float)
    E = np.asarray(E_MPa, float)
    v = np.asarray(nu, float)
    n_layers = len(R) - 1
    if n_layers < 2 or len(E) != n_layers or len(v) != n_layers:
        raise ValueError("need N+1 radii, N moduli and Poisson ratios, N-1 interferences (N >= 2)")
    if R[0] < 0 or np.any(np.diff(R) <= 0):
        raise ValueError("radii must be >= 0 and strictly increasing")
    n = n_layers - 1
    M = np.zeros((n, n))

    def u(layer, r, p_in, p_out):
        return radial_displacement_mm(r, R[layer], R[layer + 1], E[layer], v[layer], p_in, p_out,
                                      assumption)

    for i in range(1, n_layers):          # interface i at R[i], row i-1
        r = R[i]
        # outer member (layer i): inner face pressure p_i, outer face p_{i+1}
        M[i - 1, i - 1] += u(i, r, 1.0, 0.0)
        if i + 1 < n_layers:
            M[i - 1, i] += u(i, r, 0.0, 1.0)
        # inner member (layer i-1): outer face p_i, inner face p_{i-1}
        M[i - 1, i - 1] -= u(i - 1, r, 0.0, 1.0)
        if i - 1 >= 1:
            M[i - 1, i - 2] -= u(i - 1, r, 1.0, 0.0)
    return M


def _check_radii(a, c, b) -> None:
    a, c, b = (np.asarray(x, float) for x in (a, c, b))
    if np.any(a < 0) or np.any(c <= a) or np.any(b <= c):
        raise ValueError("radii must satisfy 0 <= r_inner_mm < r_fit_mm < r_outer_mm")
