"""Manufactured solutions (MMS) for the axisymmetric operators of `fem.forms`: code verification.

A smooth field is chosen, the source terms that make it the exact solution are derived from the
strong form, the FE solves with those sources on a sequence of refined meshes, and the error
against the chosen field must fall at the order of the element: for P2, h^3 in L2 and h^2 in the
energy norm (Roache, Verification and Validation in Computational Science and Engineering, 1998,
ch. 3; Salari & Knupp, Code Verification by the Method of Manufactured Solutions, Sandia
SAND2000-1444, 2000; Ciarlet, The Finite Element Method for Elliptic Problems, 1978, sections
3.1-3.2 for the orders).

Strong forms (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., ch. 12 for the equilibrium of
a solid of revolution, ch. 13 for the thermal strain; Zienkiewicz & Taylor Vol. 1, 6th ed.,
section 6.3),
r, z in mm, u in mm, stresses in MPa, body force in N/mm^3, theta the thermal strain (-):

    eps_rr = u_r,r   eps_zz = u_z,z   eps_tt = u_r / r   gamma_rz = u_r,z + u_z,r
    sigma_ii = lam tr(eps) + 2 mu eps_ii - beta theta,  tau_rz = mu gamma_rz,  beta = 3 lam + 2 mu
    f_r = -(sigma_rr,r + tau_rz,z + (sigma_rr - sigma_tt) / r)
    f_z = -(tau_rz,r + sigma_zz,z + tau_rz / r)

with, expanded (lam, mu constant inside a material),

    tr,r = u_r,rr + u_z,rz + u_r,r / r - u_r / r^2,   tr,z = u_r,rz + u_z,zz + u_r,z / r
    sigma_rr,r = lam tr,r + 2 mu u_r,rr - beta theta,r     tau_rz,z = mu (u_r,zz + u_z,rz)
    sigma_rr - sigma_tt = 2 mu (u_r,r - u_r / r)           tau_rz,r = mu (u_r,rz + u_z,rr)
    sigma_zz,z = lam tr,z + 2 mu u_z,zz - beta theta,z

Steady conduction (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, ch. 2, the heat
equation in cylindrical coordinates without the theta terms), T in C, k in W/(mm K), source
q''' in W/mm^3:   q''' = -k (T,rr + T,r / r + T,zz).

The sections are two materials meeting at a fit r = a (inner part r0 < r < a, outer part
a < r < R, 0 < z < L; structured triangulations so each level halves h exactly). Across the fit
the manufactured fields satisfy the interface conditions exactly, so no line source is needed:
- elasticity, frictionless fit (`fem.solver.FitSolver`, closed): u_r jumps by the constant radial
  interference delta, u_z jumps freely (slip), the shear tau_rz is zero on both sides and the
  normal stress sigma_rr is continuous and compressive. With s = r - a the fields are
      u_r = c_k + s (P0_k + P1_k g(z)) + A_k s^2 sin(w r) e^{z / Lz}
      u_z = W_k G(z) + B_k s^2 cos(w r) sin(k2 z),      g = cos(kz), G = sin(kz) / kz
  so at r = a: u_r,z = 0 and u_z,r = 0 (no shear), u_r = c_k (c_2 - c_1 = delta) and
  sigma_rr = S0 + S1 g(z) on both sides when the theta of both sides is D0_k + D1_k g(z) there;
  P0_k and P1_k are solved from the chosen S0 < -|S1| (compression everywhere) per material.
  u_z = 0 on z = 0, where `StackModel` fixes one u_z per floating body.
  On a solid inner part (r0 = 0: the axis, u_r = 0 there) the inner fields are regular at the
  axis (u_r odd, u_z and theta even in r): u_r = P0 r + A (r^2 - a^2)^2 sin(w r) e^{z / Lz},
  u_z = W G(z) + B (r^2 - a^2)^2 cos(w r) sin(k2 z), theta from D0 + D1 cos(w r)/cos(w a) g(z);
  then P1 = 0 inside, c = a P0 and S1 = lam W - beta alpha D1 of the inner material.
- conduction, perfect thermal contact (the tie of `fem.thermal.ConductionModel`): T continuous
  and k T,r continuous at r = a:
      T = Ta(z) + s F(z) / k_k + C_k s^2 cos(w r) e^{-z / Lz}
Sources and boundary tractions/fluxes are evaluated from these closed forms at the quadrature
points of the FE; the fit interface gets nothing (the exact field satisfies it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import Basis, BilinearForm, FacetBasis, LinearForm, MeshTri, asm, condense, solve
from skfem import ElementTriP2, ElementVector

from analytic.materials import Material, get_material
from fem.forms import TWO_PI, boundary_flux, lame_parameters

# ------------------------------------------------------------------------------ fields


@dataclass(frozen=True)
class Derivs:
    """A scalar field and its first and second derivatives in r and z at points (arrays)."""
    v: np.ndarray
    r: np.ndarray
    z: np.ndarray
    rr: np.ndarray
    rz: np.ndarray
    zz: np.ndarray

    def __add__(self, o: "Derivs") -> "Derivs":
        return Derivs(self.v + o.v, self.r + o.r, self.z + o.z, self.rr + o.rr, self.rz + o.rz,
                      self.zz + o.zz)


def product(R: tuple, Z: tuple, coef: float = 1.0) -> Derivs:
    """coef R(r) Z(z) from the 1-D factors R = (R, R', R''), Z = (Z, Z', Z'')."""
    return Derivs(coef * R[0] * Z[0], coef * R[1] * Z[0], coef * R[0] * Z[1],
                  coef * R[2] * Z[0], coef * R[1] * Z[1], coef * R[0] * Z[2])


def poly(s, n: int) -> tuple:
    """s^n and its two derivatives (n = 0, 1, 2)."""
    one = np.ones_like(s)
    return ((one, 0 * s, 0 * s), (s, one, 0 * s), (s * s, 2 * s, 2 * one))[n]


def s2_sin(r, a: float, w: float) -> tuple:
    """(r - a)^2 sin(w r) and its two r-derivatives."""
    s, S, C = r - a, np.sin(w * r), np.cos(w * r)
    return s * s * S, 2 * s * S + s * s * w * C, 2 * S + 4 * s * w * C - s * s * w * w * S


def s2_cos(r, a: float, w: float) -> tuple:
    """(r - a)^2 cos(w r) and its two r-derivatives."""
    s, S, C = r - a, np.sin(w * r), np.cos(w * r)
    return s * s * C, 2 * s * C - s * s * w * S, 2 * C - 4 * s * w * S - s * s * w * w * C


def q2_sin(r, a: float, w: float) -> tuple:
    """(r^2 - a^2)^2 sin(w r) and its two r-derivatives: odd in r, zero with its slope at a."""
    Q, S, C = r * r - a * a, np.sin(w * r), np.cos(w * r)
    return (Q * Q * S, 4 * r * Q * S + Q * Q * w * C,
            (4 * Q + 8 * r * r) * S + 8 * r * Q * w * C - Q * Q * w * w * S)


def q2_cos(r, a: float, w: float) -> tuple:
    """(r^2 - a^2)^2 cos(w r) and its two r-derivatives: even in r, zero with its slope at a."""
    Q, S, C = r * r - a * a, np.sin(w * r), np.cos(w * r)
    return (Q * Q * C, 4 * r * Q * C - Q * Q * w * S,
            (4 * Q + 8 * r * r) * C - 8 * r * Q * w * S - Q * Q * w * w * C)


def cos_ratio(r, a: float, w: float) -> tuple:
    """cos(w r) / cos(w a) and its two derivatives: even in r, 1 at a."""
    c = np.cos(w * a)
    return np.cos(w * r) / c, -w * np.sin(w * r) / c, -w * w * np.cos(w * r) / c


def cos_(z, k: float) -> tuple:
    return np.cos(k * z), -k * np.sin(k * z), -k * k * np.cos(k * z)


def sin_(z, k: float) -> tuple:
    return np.sin(k * z), k * np.cos(k * z), -k * k * np.sin(k * z)


def sin_over_k(z, k: float) -> tuple:
    """sin(k z) / k: the antiderivative of cos(k z)."""
    return np.sin(k * z) / k, np.cos(k * z), -k * np.sin(k * z)


def exp_(x, L: float) -> tuple:
    """e^{x / L} and its two derivatives."""
    e = np.exp(x / L)
    return e, e / L, e / (L * L)


# ------------------------------------------------------------------------------ strong forms


def elastic_body_force(ur: Derivs, uz: Derivs, r, lam, mu, th: Derivs):
    """(f_r, f_z) N/mm^3 that make (u_r, u_z) an equilibrium with thermal strain theta (module
    docstring: Timoshenko & Goodier ch. 12-13)."""
    beta = 3 * lam + 2 * mu
    tr_r = ur.rr + uz.rz + ur.r / r - ur.v / (r * r)
    tr_z = ur.rz + uz.zz + ur.z / r
    srr_r = lam * tr_r + 2 * mu * ur.rr - beta * th.r
    trz_z = mu * (ur.zz + uz.rz)
    trz_r = mu * (ur.rz + uz.rr)
    szz_z = lam * tr_z + 2 * mu * uz.zz - beta * th.z
    fr = -(srr_r + trz_z + 2 * mu * (ur.r - ur.v / r) / r)
    fz = -(trz_r + szz_z + mu * (ur.z + uz.r) / r)
    return fr, fz


def elastic_stress(ur: Derivs, uz: Derivs, r, lam, mu, th: Derivs):
    """sigma_rr, sigma_zz, sigma_tt, tau_rz (MPa) of the field (`fem.forms.stress_components`
    with exact derivatives)."""
    tr = ur.r + uz.z + ur.v / r
    b = (3 * lam + 2 * mu) * th.v
    return (lam * tr + 2 * mu * ur.r - b, lam * tr + 2 * mu * uz.z - b,
            lam * tr + 2 * mu * ur.v / r - b, mu * (ur.z + uz.r))


def conduction_source(T: Derivs, r, k):
    """q''' (W/mm^3) with -div(k grad T) = q''' (module docstring: Incropera & DeWitt ch. 2)."""
    return -k * (T.rr + T.r / r + T.zz)


# ------------------------------------------------------------------------------ the cases


@dataclass(frozen=True)
class TwoMaterialBox:
    """The section of a case: inner material r0..a, outer a..R, 0..L (mm)."""
    r0_mm: float = 5.0
    a_mm: float = 10.0
    R_mm: float = 15.0
    L_mm: float = 10.0
    inner: str = "TC4"
    outer: str = "9Cr18"


@dataclass(frozen=True)
class SideCoefficients:
    """The constants of one side of the fit (`ElasticFitField.coefficients`): u_r at the fit c
    (mm), the slopes P0, P1 of u_r across it (-), the axial amplitude W (mm), the Lamé constants
    lam, mu (MPa) and the CTE alpha (1/K)."""
    c: float
    P0: float
    P1: float
    W: float
    lam: float
    mu: float
    alpha: float


@dataclass(frozen=True)
class ElasticFitField:
    """The manufactured thermo-elastic field with a closed frictionless fit at r = a (module
    docstring). Amplitudes in mm (displacements), MPa (S0, S1), 1/mm (wave numbers); the
    temperature rise T - T_ref = D0 + D1 e^{(r - a)/lt} cos(k z) (K), continuous."""
    box: TwoMaterialBox
    delta_mm: float = 2.0e-3          # radial interference (u_r outer - u_r inner at the fit)
    c1_mm: float = 1.0e-3             # u_r of the inner part at the fit
    S0_MPa: float = -60.0             # normal stress at the fit: S0 + S1 cos(k z), compressive
    S1_MPa: float = 20.0
    W_mm: tuple = (1.0e-3, -0.6e-3)   # axial amplitudes inner, outer (slip: they differ)
    A_per_mm: tuple = (4.0e-5, -3.0e-5)   # u_r bulk terms
    B_per_mm: tuple = (3.0e-5, 5.0e-5)    # u_z bulk terms
    w_per_mm: float = 0.3
    k_per_mm: float = 0.25
    Lz_mm: float = 8.0
    k2_per_mm: float = 0.2
    D0_K: float = 40.0
    D1_K: float = 15.0
    lt_mm: float = 6.0

    def materials(self) -> tuple[Material, Material]:
        return get_material(self.box.inner), get_material(self.box.outer)

    @property
    def on_axis(self) -> bool:
        """The inner part is solid (r0 = 0): its fields are the axis-regular ones."""
        return self.box.r0_mm == 0.0

    def coefficients(self) -> list[SideCoefficients]:
        """Per material the constants c, P0, P1 that give sigma_rr = S0 + S1 g(z) at r = a."""
        a = self.box.a_mm
        mats = self.materials()
        lame = [lame_parameters(m.E_MPa, m.nu) for m in mats]
        beta = [3 * lam + 2 * mu for lam, mu in lame]
        S0, S1, c1 = self.S0_MPa, self.S1_MPa, self.c1_mm
        if self.on_axis:        # u_r = P0 r inside: P1 = 0, c = a P0, S1 follows from W and D1
            (lam, mu), al = lame[0], mats[0].alpha_per_K
            P0 = (S0 + beta[0] * al * self.D0_K) / (2 * lam + 2 * mu)
            c1 = a * P0
            S1 = lam * self.W_mm[0] - beta[0] * al * self.D1_K
        out = []
        for k, m in enumerate(mats):
            (lam, mu), al = lame[k], m.alpha_per_K
            c = c1 + (self.delta_mm if k == 1 else 0.0)
            W = self.W_mm[k]
            P0 = (S0 - lam * c / a + beta[k] * al * self.D0_K) / (lam + 2 * mu)
            P1 = (S1 - lam * W + beta[k] * al * self.D1_K) / (lam + 2 * mu)
            out.append(SideCoefficients(c, P0, P1, W, lam, mu, al))
        return out

    def fields(self, r, z, k: int):
        """(u_r, u_z, theta) as `Derivs` of material k (0 inner, 1 outer) at points r, z."""
        a = self.box.a_mm
        co = self.coefficients()[k]
        s = r - a
        g = cos_(z, self.k_per_mm)
        if k == 0 and self.on_axis:
            ur = (product(poly(r, 1), poly(z, 0), co.P0)
                  + product(q2_sin(r, a, self.w_per_mm), exp_(z, self.Lz_mm), self.A_per_mm[k]))
            uz = (product(poly(r, 0), sin_over_k(z, self.k_per_mm), co.W)
                  + product(q2_cos(r, a, self.w_per_mm), sin_(z, self.k2_per_mm), self.B_per_mm[k]))
            dT = (product(poly(r, 0), poly(z, 0), self.D0_K)
                  + product(cos_ratio(r, a, 1.0 / self.lt_mm), g, self.D1_K))
        else:
            ur = (product(poly(s, 0), poly(z, 0), co.c) + product(poly(s, 1), poly(z, 0), co.P0)
                  + product(poly(s, 1), g, co.P1)
                  + product(s2_sin(r, a, self.w_per_mm), exp_(z, self.Lz_mm), self.A_per_mm[k]))
            uz = (product(poly(s, 0), sin_over_k(z, self.k_per_mm), co.W)
                  + product(s2_cos(r, a, self.w_per_mm), sin_(z, self.k2_per_mm), self.B_per_mm[k]))
            dT = (product(poly(s, 0), poly(z, 0), self.D0_K)
                  + product(exp_(s, self.lt_mm), g, self.D1_K))
        al = co.alpha
        th = Derivs(al * dT.v, al * dT.r, al * dT.z, al * dT.rr, al * dT.rz, al * dT.zz)
        return ur, uz, th


@dataclass(frozen=True)
class ConductionField:
    """The manufactured temperature (C) with perfect thermal contact at r = a (module
    docstring): T = T0 + Ta e^{z/Lz} + s Fa sin(k z) / k_k + C_k s^2 cos(w r) e^{-z/Lz}."""
    box: TwoMaterialBox
    T0_C: float = 20.0
    Ta_K: float = 30.0
    Fa_W_mm2: float = 0.05            # k T,r at the fit (W/mm^2)
    C_K_per_mm2: tuple = (0.4, -0.3)
    w_per_mm: float = 0.3
    k_per_mm: float = 0.25
    Lz_mm: float = 8.0

    def conductivity_W_mmK(self, k: int) -> float:
        m = (get_material(self.box.inner), get_material(self.box.outer))[k]
        return m.conductivity_W_mK / 1000.0

    def field(self, r, z, k: int) -> Derivs:
        a = self.box.a_mm
        s = r - a
        kk = self.conductivity_W_mmK(k)
        return (product(poly(s, 0), poly(z, 0), self.T0_C)
                + product(poly(s, 0), exp_(z, self.Lz_mm), self.Ta_K)
                + product(poly(s, 1), sin_(z, self.k_per_mm), self.Fa_W_mm2 / kk)
                + product(s2_cos(r, a, self.w_per_mm), exp_(z, -self.Lz_mm), self.C_K_per_mm2[k]))


#: the solid-shaft section and field of the axis case: a TC4 shaft (r < 6 mm) in a 9Cr18 ring
AXIS_BOX = TwoMaterialBox(r0_mm=0.0, a_mm=6.0, R_mm=10.0, L_mm=10.0)


def axis_field() -> ElasticFitField:
    """The manufactured field of the solid-shaft case (axis-regular inside; bulk amplitudes
    scaled so the (r^2 - a^2)^2 terms stay of the size of the others)."""
    return ElasticFitField(AXIS_BOX, W_mm=(0.5e-3, -0.6e-3), A_per_mm=(1.2e-6, -3.0e-5),
                           B_per_mm=(1.0e-6, 5.0e-5))


def structured_box_mesh(box: TwoMaterialBox, n: int):
    """(points, triangles, part_of) of a structured triangulation with n cells across each
    material and h = (a - r0) / n along z too; parts "shaft" (inner) and "inner_ring_A"."""
    h = (box.a_mm - box.r0_mm) / n
    nr2 = max(1, round((box.R_mm - box.a_mm) / h))
    nz = max(1, round(box.L_mm / h))
    r = np.concatenate([np.linspace(box.r0_mm, box.a_mm, n + 1),
                        np.linspace(box.a_mm, box.R_mm, nr2 + 1)[1:]])
    z = np.linspace(0.0, box.L_mm, nz + 1)
    m = MeshTri.init_tensor(r, z)
    centre_r = m.p[0, m.t].mean(axis=0)
    part_of = np.where(centre_r < box.a_mm, "shaft", "inner_ring_A")
    return m.p, m.t, part_of, h


def _box_model(box: TwoMaterialBox, n: int, contact: str = "frictionless"):
    """A `fem.model.StackModel` of the box (the section of `meshes.section.two_cylinder_section`,
    free ends) on the structured mesh of level n."""
    from fem.model import StackModel
    from meshes.build import SectionMesh
    from meshes.section import two_cylinder_section

    sec = two_cylinder_section(box.r0_mm, box.a_mm, box.R_mm, box.inner, box.outer, box.L_mm)
    p, t, part_of, h = structured_box_mesh(box, n)
    return StackModel(sec, SectionMesh(p, t, part_of, {}, None), contact), h


@dataclass(frozen=True)
class MMSLevel:
    """One mesh level of a manufactured-solution case: element size (mm), DOFs, the relative
    errors in the L2 norm and in the energy norm (error norm / norm of the exact field)."""
    h_mm: float
    dofs: int
    l2_rel: float
    energy_rel: float


def _quadrature(basis: Basis):
    """Global quadrature points (r, z), each (nel, nq), and weights 2 pi r dA (mm^3)."""
    x = np.asarray(basis.global_coordinates())
    r, z = x[0], x[1]
    return r, z, TWO_PI * r * basis.dx


def _material_index(part_of: np.ndarray) -> np.ndarray:
    return (np.asarray(part_of) != "shaft").astype(int)


@LinearForm
def _vector_load(v, w):
    """int (f_r v_r + f_z v_z) 2 pi r dA: a body force (N/mm^3) or, on facets, a traction (MPa)."""
    return TWO_PI * w.x[0] * (w.fr * v[0] + w.fz * v[1])


def elastic_fit_level(field: ElasticFitField, n: int) -> tuple[MMSLevel, np.ndarray]:
    """Solve the manufactured thermo-elastic fit problem on level n (frictionless exact contact,
    `fem.solver.FitSolver`); returns the level's errors and the closed flag of every pair."""
    from fem.model import facets_on_line
    from fem.solver import FitSolver

    box = field.box
    model, h = _box_model(box, n)
    b = model.basis
    mat = _material_index(model.part_of)
    r, z, dV = _quadrature(b)
    fr, fz = np.zeros_like(r), np.zeros_like(r)
    theta = np.zeros_like(r)
    for k in (0, 1):
        sel = mat == k
        co = field.coefficients()[k]
        ur, uz, th = field.fields(r[sel], z[sel], k)
        fr[sel], fz[sel] = elastic_body_force(ur, uz, r[sel], co.lam, co.mu, th)
        theta[sel] = th.v
    f = model.thermal_load_vector(theta) + asm(_vector_load, b, fr=fr, fz=fz)
    # tractions sigma . n on the outer boundary (the fit is not loaded: the field satisfies it)
    sides = [("r", box.R_mm, 0.0, box.L_mm), ("z", 0.0, box.r0_mm, box.R_mm),
             ("z", box.L_mm, box.r0_mm, box.R_mm)]
    if not field.on_axis:                  # the axis carries no traction (u_r = 0 there)
        sides.append(("r", box.r0_mm, 0.0, box.L_mm))
    for spec in sides:
        facets = facets_on_line(model, spec)
        fb = FacetBasis(model.mesh, b.elem, facets=facets)
        x = np.asarray(fb.global_coordinates())
        nrm = fb.normals
        tr_r, tr_z = np.zeros_like(x[0]), np.zeros_like(x[0])
        mid_r = model.mesh.p[0, model.mesh.facets[:, facets]].mean(axis=0)
        fk = (mid_r > box.a_mm).astype(int)
        for k in (0, 1):
            sel = fk == k
            if not sel.any():
                continue
            co = field.coefficients()[k]
            ur, uz, th = field.fields(x[0][sel], x[1][sel], k)
            srr, szz, _, trz = elastic_stress(ur, uz, x[0][sel], co.lam, co.mu, th)
            tr_r[sel] = srr * nrm[0][sel] + trz * nrm[1][sel]
            tr_z[sel] = trz * nrm[0][sel] + szz * nrm[1][sel]
        f += asm(_vector_load, fb, fr=tr_r, fz=tr_z)
    solver = FitSolver(model)
    sol = solver.solve(f, [field.delta_mm])
    uh = b.interpolate(sol.u)
    e_l2 = n_l2 = e_en = n_en = 0.0
    for k in (0, 1):
        sel = mat == k
        co = field.coefficients()[k]
        ur, uz, _ = field.fields(r[sel], z[sel], k)
        er = ur.v - np.asarray(uh)[0][sel]
        ez = uz.v - np.asarray(uh)[1][sel]
        G = uh.grad[:, :, sel]
        e_l2 += float(np.sum((er ** 2 + ez ** 2) * dV[sel]))
        n_l2 += float(np.sum((ur.v ** 2 + uz.v ** 2) * dV[sel]))
        rk = r[sel]
        e_en += float(np.sum(_strain_energy_density(ur.r - G[0, 0], uz.z - G[1, 1], er / rk,
                                                    ur.z - G[0, 1] + uz.r - G[1, 0],
                                                    co.lam, co.mu) * dV[sel]))
        n_en += float(np.sum(_strain_energy_density(ur.r, uz.z, ur.v / rk, ur.z + uz.r,
                                                    co.lam, co.mu) * dV[sel]))
    level = MMSLevel(h, int(model.ndofs), math.sqrt(e_l2 / n_l2), math.sqrt(e_en / n_en))
    return level, sol.closed


def _strain_energy_density(err, ezz, ett, grz, lam, mu):
    """sigma : eps (twice the strain energy density, MPa) of a mechanical strain."""
    tr = err + ezz + ett
    return lam * tr * tr + 2 * mu * (err * err + ezz * ezz + ett * ett) + mu * grz * grz


@BilinearForm
def _unit_mass(u, v, w):
    return TWO_PI * w.x[0] * u * v


def conduction_level(field: ConductionField, n: int) -> MMSLevel:
    """Solve the manufactured conduction problem on level n: the conduction matrix and the
    temperature ties of `fem.thermal.ConductionModel` (perfect contact across the fit), the
    source q''' in the volume, the exact temperature on r = r0 and r = R, the exact flux
    -k dT/dn... into the body on z = 0 and z = L (`fem.forms.boundary_flux`)."""
    import scipy.sparse as sp
    from fem.model import facets_on_line, nodes_on_line, line_split
    from fem.thermal import ConductionModel

    box = field.box
    model, h = _box_model(box, n)
    cm = ConductionModel(model)
    b = model.sbasis
    mat = _material_index(model.part_of)
    r, z, dV = _quadrature(b)
    q = np.zeros_like(r)
    for k in (0, 1):
        sel = mat == k
        q[sel] = conduction_source(field.field(r[sel], z[sel], k), r[sel],
                                   field.conductivity_W_mmK(k))
    f = asm(boundary_flux, b, q=q)
    for zc in (0.0, box.L_mm):
        facets = facets_on_line(model, ("z", zc, box.r0_mm, box.R_mm))
        fb = FacetBasis(model.mesh, b.elem, facets=facets)
        x = np.asarray(fb.global_coordinates())
        mid_r = model.mesh.p[0, model.mesh.facets[:, facets]].mean(axis=0)
        fk = (mid_r > box.a_mm).astype(int)
        flux = np.zeros_like(x[0])
        for k in (0, 1):
            sel = fk == k
            T = field.field(x[0][sel], x[1][sel], k)
            kk = field.conductivity_W_mmK(k)
            flux[sel] = kk * (T.r * fb.normals[0][sel] + T.z * fb.normals[1][sel])
        f += asm(boundary_flux, fb, q=flux)
    # the ties of the conduction model: each tied slave DOF follows its master
    N = b.N
    to = np.arange(N)
    to[cm.tie_s] = cm.tie_m
    reps = np.unique(to)
    col = np.full(N, -1)
    col[reps] = np.arange(reps.size)
    P = sp.csr_matrix((np.ones(N), (np.arange(N), col[to])), shape=(N, reps.size))
    x_d = b.doflocs
    dirichlet = np.concatenate([nodes_on_line(x_d, line_split("", ("r", rc, 0.0, box.L_mm)))
                                for rc in (box.r0_mm, box.R_mm)])
    T_exact = np.zeros(N)
    for k in (0, 1):
        # DOFs of material k's elements (the fit's DOFs are duplicated, one copy per side)
        dofs = np.unique(b.element_dofs[:, mat == k])
        T_exact[dofs] = field.field(x_d[0, dofs], x_d[1, dofs], k).v
    Kr, fr = P.T @ cm.K @ P, P.T @ f
    D = np.unique(col[to[dirichlet]])
    xr = np.zeros(reps.size)
    xr[D] = T_exact[reps[D]]
    T_h = P @ solve(*condense(Kr.tocsr(), fr, x=xr, D=D))
    Th = b.interpolate(T_h)
    e_l2 = n_l2 = e_en = n_en = 0.0
    for k in (0, 1):
        sel = mat == k
        T = field.field(r[sel], z[sel], k)
        kk = field.conductivity_W_mmK(k)
        e_l2 += float(np.sum((T.v - np.asarray(Th)[sel]) ** 2 * dV[sel]))
        n_l2 += float(np.sum(T.v ** 2 * dV[sel]))
        e_en += float(np.sum(kk * ((T.r - Th.grad[0][sel]) ** 2 + (T.z - Th.grad[1][sel]) ** 2)
                             * dV[sel]))
        n_en += float(np.sum(kk * (T.r ** 2 + T.z ** 2) * dV[sel]))
    return MMSLevel(h, int(N), math.sqrt(e_l2 / n_l2), math.sqrt(e_en / n_en))


def observed_order(levels: list[MMSLevel], norm: str, last: int = 3) -> float:
    """Least-squares slope of log(error) against log(h) over the `last` finest levels."""
    lv = levels[-last:]
    h = np.log([x.h_mm for x in lv])
    e = np.log([x.l2_rel if norm == "L2" else x.energy_rel for x in lv])
    return float(np.polyfit(h, e, 1)[0])
