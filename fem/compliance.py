"""Axial compliance of the preload path from the FE: how far the inner and outer raceways of each
bearing move apart per newton of ball force.

Each bearing's balls push its inner raceway with -s_j F and its outer raceway with +s_j F (axial
line loads spread uniformly over the raceway line, s_j the arrangement sign of bearing j). With
F = 1 N the loss of approach of bearing j is -s_j d(dz_j), dz_j = u_z(inner raceway) - u_z(outer
raceway); the compliance is the mean over the bearings. The response is linear on top of the
assembled contact state (its active set held fixed). Source: the superposition principle of
linear elasticity; the pair model uses it as a_j = s_j (dz_j + x) + e - c F_j (analytic/bearing).
Units: mm/N.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import FacetBasis, asm

from fem.forms import axial_traction
from fem.model import StackModel, facets_on_line
from fem.solver import Condensed, FitSolver, Superposition
from meshes.section import boundary_lines


def raceway_unit_loads(model: StackModel, ring_signs: dict[str, float]) -> np.ndarray:
    """Load vector (N) of axial line loads on the raceway lines: ring -> resultant (N, +z)."""
    lines = boundary_lines(model.section)
    F = np.zeros(model.ndofs)
    for ring, sign in ring_signs.items():
        fb = FacetBasis(model.mesh, model.basis.elem,
                        facets=facets_on_line(model, lines[f"raceway_{ring}"]))
        f = asm(axial_traction, fb)
        F += sign * f / f.sum()
    return F


def assembled_closed_set(condensed: Condensed, solver: FitSolver,
                         delta_assembled_mm: np.ndarray) -> np.ndarray | None:
    """The contact status at assembly (no load, the fits' interferences) by the condensed
    problem (`fem.solver.Superposition`: a small dense active set on the set-up's flexibility,
    no FE factorisation): the start of the full FE's active-set iteration, which then factorises
    that one state instead of one per iteration (the compliance: 2 factorisations instead of 10
    on the shipped rigs with a clamp force, measured). None for bonded fits (their status never
    changes)."""
    if condensed.bonded:
        return None
    sup = Superposition.from_condensed(condensed, lambda: solver)
    st = sup.evaluate(np.zeros((1, condensed.n_parts)), np.asarray(delta_assembled_mm)[None, :])
    return st.closed_sets[st.status[0]].copy()


def preload_path_compliance_mm_per_N(solver: FitSolver, probe: sp.csr_matrix,
                                     signs: np.ndarray, delta_assembled_mm: np.ndarray,
                                     first_closed: np.ndarray | None = None) -> float:
    """Compliance c (mm/N) per bearing of the preload path.

    Arguments: `solver` of the stack; `probe` (8, ndofs) maps u to (u_r, u_z) at the raceway
    points of inner_ring_A, inner_ring_B, outer_ring_A, outer_ring_B; `signs` the arrangement
    signs (s_A, s_B); `delta_assembled_mm` the radial interference per FE fit at assembly (sets
    the contact state); `first_closed` the status the assembled state's active-set iteration
    starts from (`assembled_closed_set`; None: the closed fits). Returns c = mean_j(-s_j d(dz_j))
    for 1 N per bearing."""
    m = solver.model
    ring_signs = {"inner_ring_A": -signs[0], "inner_ring_B": -signs[1],
                  "outer_ring_A": signs[0], "outer_ring_B": signs[1]}
    F = raceway_unit_loads(m, ring_signs)
    zero_delta = np.zeros(len(m.fits))
    # a face held as a contact (the clamp's and, under it, the stack's) is closed at assembly:
    # the clamp is tightened on the stack (the whole face, as the tied faces of a rigid clamp)
    closed = (solver.solve(np.zeros(m.ndofs), delta_assembled_mm, closed=first_closed).closed
              | solver.face_pair)
    u = (solver.solve_status(closed, F, zero_delta)[:, 0]
         - solver.solve_status(closed, np.zeros(m.ndofs), zero_delta)[:, 0])
    pz = (probe @ u)[1::2]                              # u_z at the 4 raceway points
    d_dz = np.array([pz[0] - pz[2], pz[1] - pz[3]])     # inner minus outer, A and B
    return float(np.mean(-np.asarray(signs) * d_dz))
