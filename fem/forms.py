"""Weak forms of axisymmetric linear thermo-elasticity and steady heat conduction (scikit-fem).

Coordinates x[0] = r, x[1] = z (mm). Displacement u = (u_r, u_z) in mm. Strains in the order
(rr, zz, theta-theta, rz engineering shear):

    eps_rr = du_r/dr, eps_zz = du_z/dz, eps_tt = u_r / r, gamma_rz = du_r/dz + du_z/dr

Isotropic Hooke's law with a volumetric thermal strain theta = integral alpha dT:

    sigma_ii = lam tr(eps) + 2 mu eps_ii - (3 lam + 2 mu) theta,  tau_rz = mu gamma_rz

Every volume integral carries the full ring measure 2 pi r dr dz, so nodal forces and reactions are
forces on the whole ring (N) and energies are whole-body energies (N mm). Quadrature points lie
inside the elements, so the u_r / r term is never evaluated on the axis; u_r = 0 is imposed there.
A spinning part carries the body force rho omega^2 r (radial, N/mm^3; `centrifugal_load`).
Source: Zienkiewicz & Taylor, The Finite Element Method, Vol. 1, 6th ed., section 6.3
(axisymmetric stress analysis); Timoshenko & Goodier, Theory of Elasticity, ch. 13 (thermal stress),
§32 (rotating disks).
"""
from __future__ import annotations

import numpy as np
from skfem import BilinearForm, LinearForm

TWO_PI = 2.0 * np.pi


def lame_parameters(E_MPa, nu):
    """3-D Lamé constants lam, mu (MPa) from Young's modulus and Poisson's ratio."""
    return E_MPa * nu / ((1 + nu) * (1 - 2 * nu)), E_MPa / (2 * (1 + nu))


def strains(u, r):
    """(eps_rr, eps_zz, eps_tt, gamma_rz) of a vector field u at radius r."""
    return u.grad[0, 0], u.grad[1, 1], u[0] / r, u.grad[0, 1] + u.grad[1, 0]


@BilinearForm
def elasticity(u, v, w):
    """a(u, v) = int sigma(u) : eps(v) 2 pi r dA (axisymmetric Hooke, lam/mu per element)."""
    r = w.x[0]
    eu, ev = strains(u, r), strains(v, r)
    tr = eu[0] + eu[1] + eu[2]
    lam, mu = w.lam, w.mu
    return TWO_PI * r * (lam * tr * (ev[0] + ev[1] + ev[2])
                         + 2 * mu * (eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2])
                         + mu * eu[3] * ev[3])


@LinearForm
def thermal_load(v, w):
    """l(v) = int (3 lam + 2 mu) theta (eps_rr + eps_zz + eps_tt)(v) 2 pi r dA."""
    r = w.x[0]
    ev = strains(v, r)
    return TWO_PI * r * (3 * w.lam + 2 * w.mu) * w.theta * (ev[0] + ev[1] + ev[2])


@LinearForm
def centrifugal_load(v, w):
    """l(v) = int rho omega^2 r v_r 2 pi r dA: the centrifugal body force of a part spinning at
    omega about the z axis (N/mm^3 for rho in N s^2/mm^4 and omega in rad/s; w.rho_w2 is
    rho omega^2 per element, zero on parts that do not spin). Source: Timoshenko & Goodier,
    Theory of Elasticity, §32 (rotating disks: body force rho omega^2 r, radial);
    Zienkiewicz & Taylor Vol. 1, section 6.3 (axisymmetric body forces)."""
    r = w.x[0]
    return TWO_PI * r * w.rho_w2 * r * v[0]


@LinearForm
def axial_traction(v, w):
    """int 1 * v_z 2 pi r ds: unit axial traction (MPa) on a boundary (its integral is the force)."""
    return TWO_PI * w.x[0] * v[1]


@BilinearForm
def conduction(T, v, w):
    """int k grad T . grad v 2 pi r dA (k in W/(mm K) gives W)."""
    return TWO_PI * w.x[0] * w.k * (T.grad[0] * v.grad[0] + T.grad[1] * v.grad[1])


@BilinearForm
def convection(T, v, w):
    """Robin term int h T v 2 pi r ds on a boundary (h in W/(mm^2 K))."""
    return TWO_PI * w.x[0] * w.h * T * v


@LinearForm
def boundary_flux(v, w):
    """int q v 2 pi r ds: heat flux q (W/mm^2) into the body, or h T_inf for convection."""
    return TWO_PI * w.x[0] * w.q * v


def stress_components(grad, value, r, lam, mu, theta):
    """sigma_rr, sigma_zz, sigma_tt, tau_rz (MPa) from displacement gradients at points."""
    err, ezz, ett = grad[0, 0], grad[1, 1], value[0] / r
    grz = grad[0, 1] + grad[1, 0]
    tr = err + ezz + ett
    th = (3 * lam + 2 * mu) * theta
    return (lam * tr + 2 * mu * err - th, lam * tr + 2 * mu * ezz - th,
            lam * tr + 2 * mu * ett - th, mu * grz)


def von_mises(srr, szz, stt, trz):
    """Von Mises equivalent stress (MPa) of an axisymmetric stress state."""
    return np.sqrt(0.5 * ((srr - szz) ** 2 + (szz - stt) ** 2 + (stt - srr) ** 2) + 3 * trz ** 2)


@BilinearForm
def heat_capacity(T, v, w):
    """m(T, v) = int rho c T v 2 pi r dA (rho c in J/(mm^3 K) gives J/K)."""
    return TWO_PI * w.x[0] * w.rho_c * T * v


@LinearForm
def volume_source(v, w):
    """l(v) = int s v 2 pi r dA: a heat source s (W/mm^3) spread over a part."""
    return TWO_PI * w.x[0] * w.s * v
