"""Steady axisymmetric heat conduction on the section mesh (scalar P2), for non-uniform fields.

    -div(k grad T) = 0 in each part,   k dT/dn = q (heat input) or h (T_inf - T) (convection)
    or T = T_fixed on named boundary lines,

with perfect thermal contact across fits and clamped faces (the temperature DOFs of the unzipped
node pairs are tied) and, optionally, a lumped conductance G (W/K) between the mean temperatures
of each bearing's inner and outer raceway lines (the ball set: it is analytic, not meshed).
Units: k in W/(m K) and h in W/(m^2 K) as catalogues give them, converted to mm inside;
heat in W; temperatures in C. Source: Incropera & DeWitt, Fundamentals of Heat and Mass Transfer,
ch. 3 (radial conduction, convection boundary); the weak form with the ring measure 2 pi r.

The temperature feeds the elasticity as a thermal strain field theta(x) = integral alpha dT at the
quadrature points (`theta_field`), solved directly (not through the per-part unit solutions).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from skfem import FacetBasis, asm

from fem.forms import boundary_flux, conduction, convection
from fem.solver import _tie_representatives
from fem.model import StackModel, facets_on_line, line_split, node_pairs_on, nodes_on_line
from meshes.section import boundary_lines


@dataclass
class ThermalLoads:
    """Boundary conditions by line name (see `boundary_lines`)."""
    convection: dict[str, tuple[float, float]] = field(default_factory=dict)  # (h_W_m2K, T_inf_C)
    fixed_C: dict[str, float] = field(default_factory=dict)
    heat_W: dict[str, float] = field(default_factory=dict)
    ball_conductance_W_K: dict[str, float] = field(default_factory=dict)      # "A" / "B"


class ConductionModel:
    """Assembled steady conduction of a `StackModel`'s mesh; tied across all split lines."""

    def __init__(self, model: StackModel):
        self.model = model
        b = model.sbasis
        nq = b.X.shape[1]
        k = np.array([model.materials[p].conductivity_W_mK for p in model.part_of]) / 1000.0
        self.K = asm(conduction, b, k=np.repeat(k[:, None], nq, 1)).tocsr()
        x = b.doflocs
        ms, ss = [], []
        for s in model.section.splits:
            a, c = node_pairs_on(x, nodes_on_line(x, s), b.element_dofs, model.part_of, s.inner_parts,
                             s.outer_parts)
            ms.append(a)
            ss.append(c)
        self.tie_m = np.concatenate(ms) if ms else np.zeros(0, int)
        self.tie_s = np.concatenate(ss) if ss else np.zeros(0, int)
        self.lines = boundary_lines(model.section)

    def mean_temperature_C(self, T: np.ndarray, name: str) -> float:
        """Area-weighted mean of nodal temperatures T (C) on a named boundary line, C."""
        return float(self.mean_vector(name) @ T)

    def area_mm2(self, name: str) -> float:
        """Area of a named boundary line swept around the axis, int 2 pi r ds (mm^2)."""
        fb = FacetBasis(self.model.mesh, self.model.sbasis.elem, facets=facets_on_line(self.model, self._spec(name)))
        return float(asm(boundary_flux, fb, q=1.0).sum())

    def mean_vector(self, name: str) -> np.ndarray:
        """Vector a with a . T = area-weighted mean temperature (C) on a boundary line, for nodal
        temperatures T (C): a = int N 2 pi r ds / int 2 pi r ds."""
        fb = FacetBasis(self.model.mesh, self.model.sbasis.elem, facets=facets_on_line(self.model, self.lines[name]))
        a = asm(boundary_flux, fb, q=1.0)
        return a / a.sum()

    def solve(self, loads: ThermalLoads) -> np.ndarray:
        """Nodal temperatures (scalar P2 DOFs, C)."""
        m = self.model
        b = m.sbasis
        N = b.N
        A = self.K.copy()
        f = np.zeros(N)
        for name, (h, T_inf) in loads.convection.items():
            fb = FacetBasis(m.mesh, b.elem, facets=facets_on_line(m, self._spec(name)))
            A = A + asm(convection, fb, h=h / 1e6)
            f += asm(boundary_flux, fb, q=h / 1e6 * T_inf)
        for name, Q in loads.heat_W.items():
            f += Q * self.mean_vector(name)
        for j, G in loads.ball_conductance_W_K.items():
            d = self.mean_vector(f"raceway_inner_ring_{j}") - self.mean_vector(f"raceway_outer_ring_{j}")
            d = sp.csr_matrix(d[None, :])
            A = A + G * (d.T @ d)
        fixed = np.zeros(N, bool)
        T_fix = np.zeros(N)
        for name, T in loads.fixed_C.items():
            dofs = nodes_on_line(b.doflocs, line_split(name, self._spec(name)))
            fixed[dofs] = True
            T_fix[dofs] = T
        # elimination: tied slaves follow their masters; fixed DOFs are known
        # groups of tied DOFs (chains and loops, e.g. a ring corner paired with the shaft across
        # the seat and with the nut across the face: each the other's slave) -> one
        # representative each (fem.solver._tie_representatives)
        to = np.arange(N)
        sl, rep = _tie_representatives(N, self.tie_m, self.tie_s, np.zeros(N, bool))
        to[sl] = rep
        fixed_rep = np.zeros(N, bool)
        np.logical_or.at(fixed_rep, to, fixed)
        T_rep = np.zeros(N)
        T_rep[to[fixed]] = T_fix[fixed]
        reps = np.unique(to)
        free = reps[~fixed_rep[reps]]
        red = np.full(N, -1)
        red[free] = np.arange(free.size)
        rows = np.flatnonzero(red[to] >= 0)
        P = sp.csr_matrix((np.ones(rows.size), (rows, red[to[rows]])), shape=(N, free.size))
        g = np.where(fixed_rep[to], T_rep[to], 0.0)
        Ar = (P.T @ A @ P).tocsc()
        if free.size == 0:
            return g
        try:
            q = splu(Ar).solve(P.T @ (f - A @ g))
        except RuntimeError:
            raise ValueError("conduction problem is singular: give at least one fixed temperature "
                             "or convection boundary on every body") from None
        return P @ q + g

    def _spec(self, name: str):
        if name not in self.lines:
            raise ValueError(f"unknown thermal boundary '{name}' (known: {', '.join(self.lines)})")
        return self.lines[name]

    def theta_field(self, T_dofs: np.ndarray, T_ref_C: float) -> np.ndarray:
        """Thermal strain at the quadrature points (nel, nq), per element material."""
        m = self.model
        Tq = np.asarray(m.sbasis.interpolate(T_dofs))
        out = np.empty_like(Tq)
        for p in m.part_names:
            sel = m.part_of == p
            out[sel] = m.materials[p].thermal_strain(Tq[sel], T_ref_C)
        return out

    def vertex_temperatures(self, T_dofs: np.ndarray) -> np.ndarray:
        return T_dofs[self.model.sbasis.nodal_dofs[0]]
