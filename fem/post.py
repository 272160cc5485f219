"""Post-processing: fit pressures from contact forces, pressure distributions, groove-centre
shifts, element stresses.

Fit pressures are taken from the contact forces (the reactions of the constraints), never from
extrapolated stresses: the mean pressure of a fit of radius R and length L is

    p_mean = sum_i lambda_i / (2 pi R L)      (lambda_i: whole-ring nodal contact forces, N)

which converges much faster than an interface stress average (the reactions are the weak form's
own nodal forces; `bearingfem verify` holds this pressure against Lame, docs/cli.md "verify").
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from fem.forms import stress_components, von_mises

if TYPE_CHECKING:                    # only the model's fits and basis are read here
    from fem.model import StackModel


@dataclass
class FitResult:
    name: str
    mean_pressure_MPa: float
    total_force_N: float
    status: str                    # "closed", "open" or "partial"
    z_mm: np.ndarray               # interface node positions
    pressure_MPa: np.ndarray       # pressure distribution at those nodes


def fit_mean_pressures(model: StackModel, fit_of_pair: np.ndarray, force_N: np.ndarray) -> np.ndarray:
    """Mean fit pressure (MPa) per fit for states force_N (n_states, n_pairs)."""
    return mean_pressures_MPa(force_N, fit_of_pair, [f.r_mm for f in model.fits],
                              [f.length_mm for f in model.fits])


def mean_pressures_MPa(force_N: np.ndarray, fit_of_pair: np.ndarray, r_mm, length_mm) -> np.ndarray:
    """Mean pressure (MPa) per fit k of radius r_mm[k] and length length_mm[k] (mm) for states
    force_N (n_states, n_pairs) of whole-ring pair forces (N): sum of the fit's forces / 2 pi R L."""
    F = np.atleast_2d(force_N)
    out = np.empty((F.shape[0], len(r_mm)))
    for k, (r, length) in enumerate(zip(r_mm, length_mm)):
        out[:, k] = F[:, fit_of_pair == k].sum(axis=1) / (2 * np.pi * r * length)
    return out


def pressure_distribution(z_mm: np.ndarray, nodal_force_N: np.ndarray, r_mm: float) -> np.ndarray:
    """Contact pressure p(z) (MPa) at the interface nodes from the nodal contact forces.

    The nodes of a P2 interface alternate vertex, mid-side, vertex along z. Each nodal force is
    divided by its tributary area 2 pi R w_i, with w_i the row sums of the quadratic line mass
    matrix (Simpson weights h/6, 4h/6, h/6 per element; Zienkiewicz & Taylor Vol. 1, lumped
    mass). Unlike inverting the consistent mass matrix this cannot oscillate: p >= 0 wherever the
    contact forces are compressive, and sum(p w) 2 pi R is the total force exactly."""
    n = z_mm.size
    w = np.zeros(n)
    for e in range(0, n - 2, 2):
        h = z_mm[e + 2] - z_mm[e]
        w[[e, e + 1, e + 2]] += np.array([1.0, 4.0, 1.0]) * h / 6.0
    return nodal_force_N / (2 * np.pi * r_mm * w)


def fit_results(model: StackModel, fit_of_pair: np.ndarray, force_N: np.ndarray) -> list[FitResult]:
    """Per-fit results of one state: mean pressure, status and pressure distribution."""
    out = []
    for k, f in enumerate(model.fits):
        lam = force_N[fit_of_pair == k]
        closed = lam > 0
        status = "closed" if closed.all() else "open" if not closed.any() else "partial"
        total = lam.sum()
        out.append(FitResult(f.name, total / (2 * np.pi * f.r_mm * f.length_mm), total, status,
                             f.z_mm, pressure_distribution(f.z_mm, lam, f.r_mm)))
    return out


def groove_centre_shift(u_point_mm: np.ndarray, theta_ring: np.ndarray,
                        offset_rz_mm: np.ndarray) -> np.ndarray:
    """Displacement of a groove curvature centre that lies at `offset_rz_mm` from a raceway point
    P of the ring: u_c = u(P) + theta_ring * (X_c - P).

    The centre is not a material point of the section (it lies in the ball space); it moves with
    the raceway as a rigid body plus the ring's own uniform thermal strain of the groove radius
    (the groove radius f*Dw grows with the ring material, the fit strain over the short distance
    f*Dw is neglected, O(strain * Dw) ~ 1e-3 um). Units mm."""
    return np.asarray(u_point_mm) + np.asarray(theta_ring)[..., None] * np.asarray(offset_rz_mm)


def circle_centre_weights(points_rz_mm: np.ndarray, centre_rz_mm,
                          free_radius: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(W (2, 2n), w_theta (2,)): the shift (dr, dz) in mm of the circle fitted to n displaced
    points of a circular arc is W @ [u_r(p0), u_z(p0), u_r(p1), ...] + theta_ring w_theta
    (displacements in mm, theta_ring the ring's thermal strain).

    The geometric least-squares circle fit (Gander, Golub & Strebel, "Least-squares fitting of
    circles and ellipses", BIT 34 (1994) 558-578) linearised about the nominal circle (centre c,
    radius R): with n_i the unit normal (X_i - c)/R, the distance of the displaced point to the
    shifted circle is n_i . (u_i - dc) - dR to first order.  The bearing model takes the groove
    radius as f Dw grown with the ring's thermal strain only (`bearing.thermal_geometry`), so
    by default the radius change is held at that growth, dR = theta_ring R, and

        min over dc of  sum_i (n_i . u_i - n_i . dc - theta_ring R)^2

    places the centre so that the circle of the model's radius lies where the displaced groove
    surface is near the contact (an elastic change of the groove radius, e.g. the ring stretched
    by its fit, then shows as the surface's normal motion, which is what the ball meets).
    free_radius=True fits dR too (rows G_i = (n_i^T, 1); w_theta = 0): the centre of the best
    circle of any radius.  Both are exact for a rigid translation (dc = the translation) and
    for a uniform dilation u = theta X (dc = theta c).  points_rz_mm: (2, n) points on the arc,
    n >= 3 spanning an angle; units mm."""
    X = np.asarray(points_rz_mm, float)
    c = np.asarray(centre_rz_mm, float).reshape(2, 1)
    d = X - c
    R = np.hypot(*d)
    nrm = d / R
    N = np.zeros((X.shape[1], 2 * X.shape[1]))
    idx = np.arange(X.shape[1])
    N[idx, 2 * idx], N[idx, 2 * idx + 1] = nrm[0], nrm[1]
    if free_radius:
        G = np.column_stack([nrm.T, np.ones(X.shape[1])])
        return (np.linalg.pinv(G) @ N)[:2], np.zeros(2)
    pinv = np.linalg.pinv(nrm.T)
    return pinv @ N, -pinv @ R


def element_stresses(model: StackModel, u: np.ndarray, theta_e: np.ndarray) -> dict[str, np.ndarray]:
    """Element-mean stresses (MPa): sigma_rr, sigma_zz, sigma_tt (hoop), tau_rz, von_mises.
    theta_e: thermal strain per element (uniform per part)."""
    b = model.basis
    uf = b.interpolate(u)
    r = b.mapping.F(b.quadrature[0])[0]
    th = np.repeat(theta_e[:, None], r.shape[1], 1)
    srr, szz, stt, trz = stress_components(uf.grad, np.asarray(uf), r, model.lam_q, model.mu_q, th)
    w = b.dx / b.dx.sum(axis=1, keepdims=True)
    avg = {k: (v * w).sum(axis=1) for k, v in
           (("sigma_rr_MPa", srr), ("sigma_zz_MPa", szz), ("sigma_hoop_MPa", stt),
            ("tau_rz_MPa", trz))}
    avg["von_mises_MPa"] = (von_mises(srr, szz, stt, trz) * w).sum(axis=1)
    return avg


def theta_per_element(model: StackModel, theta_by_part: np.ndarray) -> np.ndarray:
    """Expand thermal strain per part (part order of the model) to the elements."""
    idx = {p: i for i, p in enumerate(model.part_names)}
    return np.asarray(theta_by_part)[[idx[p] for p in model.part_of]]
