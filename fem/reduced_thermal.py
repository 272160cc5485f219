"""A reduced model of the transient conduction FE (`fem.transient`) and of the structural response
to its temperature fields: the heat-up of a stack in hundreds of steps at sweep speed.

Thermal reduction (multi-point rational Krylov / moment matching, then a POD of the moments).
For training coefficients mu_i (films, fit and ball conductances) and shifts s_k (1/s), the
columns

    X_ik = (s_k M + A(mu_i))^-1 B(mu_i),   B = [ambient drive sum_g h_g b_g, heat inputs a_j]

match the transfer function from the inputs (ambient temperature, heat at raceways and ball
nodes) to the temperature field at s = s_k (s = 0: the steady state) for each mu_i; with the
uniform field (the initial state) they are compressed by a POD in the M inner product: the
eigen-decomposition of X^T M X, modes kept down to `tol` of the largest eigenvalue, ordered by
energy. Galerkin projection onto the M-orthonormal basis V keeps every term of the affine
operator apart (V^T K V, V^T F_g V per film group, V^T C_f V per fit, ball links, V^T b_g,
V^T a_j): changing film coefficients or contact conductances only re-sums small dense matrices,
no new reduction. Time stepping in the reduced space uses the FE's schemes (`fem.transient`,
backward Euler / BDF2, one dense LU per step size and coefficient set). Radiation's nonlinear
remainder is evaluated at the radiating faces' DOFs of V q (exact in the reduced space; the
basis carries the radiating faces' uniform drive only, so strong radiation needs it among the
training inputs).
Sources: Grimme, "Krylov projection methods for model reduction", PhD thesis, Univ. Illinois
1997 (rational Krylov, moment matching at several shifts); Baur, Beattie, Benner, Gugercin,
"Interpolatory projection methods for parameterized model reduction", SIAM J. Sci. Comput. 33
(2011) 2489 (multi-point parametric interpolation, affine parameter dependence kept);
Volkwein, "Proper orthogonal decomposition: theory and reduced-order modelling", lecture notes
2013, ch. 1 (POD in a weighted inner product).

Why by hand and not pyMOR: pyMOR (PyPI) has the same building blocks (LincombOperator for the
affine terms, reductors for parametric LTI systems), but it would wrap our scipy matrices into
its operator/vector-array framework for what is here ~40 lines of scipy (sparse LU, a dense
eigen-decomposition, projections), add a large dependency to `fem/`, and still not give the
structural projection below, which has to go through the contact superposition of
`fem.solver`. scikit-fem's examples have no model reduction.

Structural response per thermal mode. With a constant CTE per part (alpha), the thermal strain
theta = alpha (T - T_ref) is linear in the reduced coordinates: theta = alpha V (q - q_ref), with
q_ref the coordinates of the uniform field T_ref. Each mode's thermal load (`fem.forms.
thermal_load`) is one load column of the exact contact superposition (`fem.solver.
Superposition`): the gap per mode B_i and the probed displacements per mode are one
back-substitution each with the all-open factorisation; the flexibility A and the pair-force
columns come from the stack's condensed set-up. Fit pressures (exact contact status per state)
and groove-centre shifts then cost small dense products per step.
A-posteriori estimate (cheap): the same run with the leading half of the modes; the difference of
the outputs of the two estimates the error of the smaller model, and bounds the full model's
when the errors fall with the number of modes (the effectivity is measured on a check case in
`studies/bench/bench_transient.py`).
Units as in `fem.transient`: W, J, s, C, mm.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from skfem import BilinearForm, asm

from fem.forms import TWO_PI, strains
from fem.solver import Condensed, FitSolver, SuperposedStates, Superposition, condense
from fem.transient import (PER_M2_TO_PER_MM2, SCHEMES, StepLoads, ThermalParameters,
                           TransientConduction, element_average, radiation_h_W_mm2K,
                           radiation_remainder_W_mm2)


#: the shift (1/s) that stands for s = 0 when the stack is adiabatic outside (`krylov_basis`):
#: a time scale of ~12 days, far beyond any run, so its moment is the steady heat-up shape
#: to 1e-6 relative; small enough, not so small that removing its 1/s uniform part loses the shape
#: to round-off (1e6 of the 1e16 digits)
FLOATING_SHIFT_PER_S = 1e-6


@dataclass(frozen=True)
class ReducedBasis:
    """V (n_total, m): M-orthonormal modes, the uniform field first, then ordered by POD energy;
    energy (m,): the POD eigenvalues of the normalised moments (inf for the uniform field)."""
    V: np.ndarray
    energy: np.ndarray


def krylov_basis(tc: TransientConduction, training: Sequence[ThermalParameters],
                 inputs: Sequence[str], shifts_per_s: Sequence[float] = (0.0, 1e-3, 1e-2, 1e-1),
                 tol: float = 1e-12) -> ReducedBasis:
    """The reduced basis of `tc` (module docstring): moments at every training coefficient set
    and shift for the ambient drive and the named heat inputs (face groups, ball nodes), plus the
    uniform field; POD in the M inner product, eigenvalues below tol x the largest dropped.
    A stack adiabatic outside (no film, no radiation: no ambient drive) takes its s = 0 moments
    at FLOATING_SHIFT_PER_S (its steady state does not exist; without this its basis was the
    uniform field alone and the bearing's heat spread instantly over the whole stack)."""
    if tc.fixed_groups:
        raise ValueError("the reduced model has no fixed-temperature groups: use films")
    P, M = tc.P, tc.M
    cols = []
    for prm in training:
        A = tc.operator(prm)
        drive = tc.load(prm, StepLoads(1.0, 1.0))
        # a stack with no film and no radiation (adiabatic outside) has no ambient drive and a
        # singular A (the uniform field is its null space: heat is stored, never steady):
        # the drive is left out and s = 0 is replaced by FLOATING_SHIFT_PER_S, whose moment
        # beyond the uniform field is the shape of the steady heat-up (the uniform part, of
        # order 1/s, is removed below)
        floating = not np.any(drive)
        B = np.column_stack(([] if floating else [drive]) + [tc.a[name] for name in inputs])
        for s in shifts_per_s:
            if floating and s == 0.0:
                s = FLOATING_SHIFT_PER_S
            lu = splu((P.T @ (s * M + A) @ P).tocsc())
            cols.append(P @ lu.solve(np.asfortranarray(P.T @ B)))
    # the uniform field is the first mode, exactly (initial states and T_ref lie in the space)
    u0 = np.ones(tc.n_total)
    u0 /= np.sqrt(u0 @ (M @ u0))
    X = np.column_stack(cols)
    X = X - np.outer(u0, u0 @ (M @ X))
    norm = np.sqrt(np.einsum("ij,ij->j", X, M @ X))
    X = X[:, norm > 0] / norm[norm > 0][None, :]     # a moment that is all uniform adds nothing
    G = X.T @ (M @ X)
    w, U = np.linalg.eigh(0.5 * (G + G.T))
    order = np.argsort(w)[::-1]
    w, U = w[order], U[:, order]
    keep = w > tol * w[0]
    V = np.column_stack([u0, X @ (U[:, keep] / np.sqrt(w[keep]))])
    # one more M-orthogonalisation against u0 (round-off of the eigenvectors)
    V[:, 1:] -= np.outer(u0, u0 @ (M @ V[:, 1:]))
    return ReducedBasis(V, np.concatenate([[np.inf], w[keep]]))


class ReducedConduction:
    """The Galerkin projection of a `TransientConduction` onto a basis, term by term."""

    def __init__(self, tc: TransientConduction, basis: ReducedBasis):
        self.tc, self.V = tc, basis.V
        V = self.V
        proj = lambda A: V.T @ (A @ V)
        self.M = proj(tc.M)
        self.K = proj(tc.K)
        self.F = {g: proj(F) for g, F in tc.F.items()}
        self.C_fit = [proj(C) for C in tc.C_fit]
        self.C_bore = proj(tc.C_bore)
        self.ball_inner = [proj(C) for C in tc.ball_inner]
        self.ball_outer = [proj(C) for C in tc.ball_outer]
        self.b = {g: V.T @ v for g, v in tc.b.items()}
        self.a = {g: V.T @ v for g, v in tc.a.items()}
        # coordinates of the uniform field 1 (M-orthonormal basis: q = V^T M 1)
        self.q_one = V.T @ (tc.M @ np.ones(tc.n_total))
        self._face = {}

    @property
    def m(self) -> int:
        return self.V.shape[1]

    def truncated(self, m: int) -> "ReducedConduction":
        """The same model on the leading m modes (the projections are sub-blocks)."""
        out = ReducedConduction.__new__(ReducedConduction)
        out.tc, out.V = self.tc, self.V[:, :m]
        sub = lambda A: A[:m, :m]
        out.M, out.K, out.C_bore = sub(self.M), sub(self.K), sub(self.C_bore)
        out.F = {g: sub(F) for g, F in self.F.items()}
        out.C_fit = [sub(C) for C in self.C_fit]
        out.ball_inner = [sub(C) for C in self.ball_inner]
        out.ball_outer = [sub(C) for C in self.ball_outer]
        out.b = {g: v[:m] for g, v in self.b.items()}
        out.a = {g: v[:m] for g, v in self.a.items()}
        out.q_one = self.q_one[:m]
        out._face = {}
        return out

    def operator(self, prm: ThermalParameters) -> np.ndarray:
        """V^T A(prm) V from the projected terms (the FE's `TransientConduction.operator`)."""
        tc = self.tc
        A = self.K.copy()
        for g, h in prm.film_W_m2K.items():
            A += (h * PER_M2_TO_PER_MM2) * self.F[g]
        if not tc.perfect_contact:
            for h, C in zip(np.asarray(prm.fit_conductance_W_m2K, float), self.C_fit):
                A += (h * PER_M2_TO_PER_MM2) * C
            A += (prm.bore_conductance_W_m2K * PER_M2_TO_PER_MM2) * self.C_bore
        if tc.bearings:
            if tc.ball_nodes:
                for Ci, Co in zip(self.ball_inner, self.ball_outer):
                    A += prm.ball_inner_W_K * Ci + prm.ball_outer_W_K * Co
            else:
                gi, go = prm.ball_inner_W_K, prm.ball_outer_W_K
                G = gi * go / (gi + go) if gi > 0 and go > 0 else 0.0
                for Ci in self.ball_inner:
                    A += G * Ci
        h_r = radiation_h_W_mm2K(prm.T_rad_lin_C)
        for g, eps in prm.emissivity.items():
            A += (eps * h_r) * self.F[g]
        return A

    def load(self, prm: ThermalParameters, loads: StepLoads) -> np.ndarray:
        f = np.zeros(self.m)
        for g, h in prm.film_W_m2K.items():
            f += (h * PER_M2_TO_PER_MM2 * loads.T_ambient_C) * self.b[g]
        for name, Q in loads.heat_W.items():
            f += Q * self.a[name]
        if loads.source_W is not None:
            f += self.V.T @ loads.source_W
        h_r = radiation_h_W_mm2K(prm.T_rad_lin_C)
        for g, eps in prm.emissivity.items():
            f += (eps * h_r * loads.sink_C) * self.b[g]
        return f

    def radiation_terms(self, prm: ThermalParameters):
        """(dofs, V rows at them, V^T R restricted to them) of the radiating faces."""
        key = tuple(sorted(prm.emissivity.items()))
        if key not in self._face:
            R = self.tc.radiation_mass(prm)
            dofs = np.unique(R.nonzero()[0])
            self._face[key] = (dofs, self.V[dofs], (R[:, dofs].T @ self.V).T)
        return self._face[key]

    def field(self, q: np.ndarray) -> np.ndarray:
        """The FE temperatures (n_total,) of reduced coordinates q."""
        return self.V @ q


class ReducedStepper:
    """`fem.transient.Stepper` in the reduced space: the same schemes and loads; states are
    reduced coordinates q (`field` gives the temperatures)."""

    def __init__(self, rc: ReducedConduction, prm: ThermalParameters, dt_s: float, T0_C: float,
                 scheme: str = "bdf2"):
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got '{scheme}'")
        self.rc, self.dt, self.scheme = rc, float(dt_s), scheme
        self.q = float(T0_C) * rc.q_one
        self.q_prev: np.ndarray | None = None
        self.set_parameters(prm)

    def set_parameters(self, prm: ThermalParameters) -> None:
        self.prm = prm
        self.A = self.rc.operator(prm)
        self._lu = {}
        self._rad = self.rc.radiation_terms(prm) if prm.emissivity else None

    def _factor(self, c0: float):
        if c0 not in self._lu:
            self._lu[c0] = sla.lu_factor((c0 / self.dt) * self.rc.M + self.A, check_finite=False)
        return self._lu[c0]

    def step(self, loads: StepLoads) -> np.ndarray:
        rc, dt = self.rc, self.dt
        scheme = self.scheme if self.q_prev is not None else "backward_euler"
        c0, c1, c2 = SCHEMES[scheme]
        qn = self.q
        qm = self.q_prev if self.q_prev is not None else qn
        rhs = rc.M @ ((c1 * qn + c2 * qm) / dt) + rc.load(self.prm, loads)
        if self._rad is not None:
            dofs, Vd, VtR = self._rad
            q_ex = qn if scheme == "backward_euler" else 2.0 * qn - qm
            rhs -= VtR @ radiation_remainder_W_mm2(Vd @ q_ex, loads.sink_C, self.prm.T_rad_lin_C)
        q = sla.lu_solve(self._factor(c0), rhs, check_finite=False)
        self.q_prev, self.q = qn, q
        return q


# ------------------------------------------------------------------ structural response per mode
@dataclass(frozen=True)
class ModalStates(SuperposedStates):
    """`SuperposedStates` of reduced temperature states, and ring_strain (n_states, n_rings):
    each ring's mean thermal strain (-)."""
    ring_strain: np.ndarray | None = None


@dataclass(frozen=True)
class ModalStructure:
    """The exact contact superposition with the thermal modes as load columns.

    sup: `fem.solver.Superposition` whose first m load columns are the modes (coefficient
    q - q_ref, dimensionless reduced coordinates in K) and whose last is omega^2; ring_strain
    (n_rings, m): mean thermal strain of each named ring per unit coordinate (the mean over the
    ring's elements by area dx, as the structural FE's groove-centre offsets take it);
    q_ref: coordinates of the uniform reference field."""
    sup: Superposition
    ring_strain: np.ndarray
    q_ref: np.ndarray

    def evaluate(self, q: np.ndarray, delta_mm: np.ndarray, omega2_rad2_s2=None) -> ModalStates:
        """`Superposition.evaluate` of states q (n_states, m) (reduced temperature coordinates)
        at radial interferences delta_mm (n_states, n_fits), with the rings' mean strains
        (`ModalStates.ring_strain`, (n_states, n_rings))."""
        c = np.atleast_2d(q) - self.q_ref[None, :]
        out = self.sup.evaluate(c, delta_mm, omega2_rad2_s2)
        return ModalStates(out.force_N, out.gap_mm, out.status, out.closed_sets, out.probe,
                           c @ self.ring_strain.T)


def modal_structure(solver: FitSolver, probe: sp.csr_matrix, rc: ReducedConduction,
                    T_ref_C: float, rings: Sequence[str],
                    condensed: Condensed | None = None) -> ModalStructure:
    """The structural response per thermal mode of `rc` (frictionless fits): one back-
    substitution per mode with the all-open factorisation of `solver`, the flexibility and
    pair-force columns of `condensed` (the stack's set-up; computed when None). The CTE must be
    constant per part (theta linear in T): ValueError otherwise."""
    m = solver.model
    if solver.bonded:
        raise ValueError("the modal structural response needs frictionless fits")
    for p, mat in m.materials.items():
        if mat.dalpha_per_K2 != 0.0 or mat.d2alpha_per_K3 != 0.0:
            raise ValueError(f"part {p}: a temperature-dependent CTE is not linear in T")
    c = condensed if condensed is not None else condense(solver, probe)
    tc = rc.tc
    V = rc.V[:tc.N]
    loads = thermal_coupling(m) @ V
    # ring mean strains: the mean of alpha phi over the ring's elements by area dx
    b = m.sbasis
    dx = m.basis.dx
    ring_strain = np.empty((len(rings), rc.m))
    for k, r in enumerate(rings):
        s = m.part_of == r
        alpha = m.materials[r].alpha_per_K
        w = (dx[s] / dx[s].sum())
        ring_strain[k] = alpha * element_average(b, s, w) @ V
    T, lu = solver.factorize(np.zeros(solver.n_pairs, bool))
    U = T @ lu.solve(np.asfortranarray(T.T @ loads))
    B_modes = U[solver.slave] - U[solver.master]
    n_old = c.n_parts + 1
    B = np.hstack([B_modes, c.B[:, n_old - 1:n_old]])
    PU = np.hstack([probe @ U, c.probe_units[:, n_old - 1:]])
    cond = Condensed(False, rc.m, c.n_fits, c.fit_of_pair, np.ascontiguousarray(B), c.A,
                     np.ascontiguousarray(PU), np.zeros((0, 0)))
    sup = Superposition.from_condensed(cond, lambda: solver)
    q_ref = T_ref_C * rc.q_one
    return ModalStructure(sup, ring_strain, q_ref)


@BilinearForm
def _thermal_coupling_form(T, v, w):
    """int (3 lam + 2 mu) alpha T (eps_rr + eps_zz + eps_tt)(v) 2 pi r dA: `fem.forms.
    thermal_load` with theta = alpha T, as a matrix from scalar temperatures T to load vectors."""
    r = w.x[0]
    ev = strains(v, r)
    return TWO_PI * r * (3 * w.lam + 2 * w.mu) * w.alpha * T * (ev[0] + ev[1] + ev[2])


def thermal_coupling(model) -> sp.csr_matrix:
    """(ndofs, N) matrix G with G T = the thermal load vector (N) of theta = alpha (x) T for
    nodal temperature changes T (K) (constant CTE per part; `StackModel.thermal_load_vector`)."""
    nq = model.basis.X.shape[1]
    alpha = np.array([model.materials[p].alpha_per_K for p in model.part_of])
    return asm(_thermal_coupling_form, model.sbasis, model.basis, lam=model.lam_q,
               mu=model.mu_q, alpha=np.repeat(alpha[:, None], nq, 1)).tocsr()

