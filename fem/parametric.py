"""The FE set-up of many stacks that differ only in the materials of a few parts, from one
reference FE model (the design search's spacer materials).

Within a family (same section geometry, contact variant, probes, compliance plan and rotating
parts; only the materials of the `variable` parts and the fits the compliance is taken at differ)
the set-up of any member
(`fem.setup.FESetup`: the condensed contact problem and the preload-path compliance) follows from
the reference member's FE without a new mesh, assembly or factorisation:

- The reduced stiffness (ties and supports eliminated, every fit open, `fem.solver.FitSolver`) is
  K = K_rest + sum_p K_p(lam_p, mu_p), and the element stiffness of a part is linear in its Lamé
  constants, K_p = lam_p K_p^lam + mu_p K_p^mu (`fem.forms.elasticity`): the two matrices of each
  variable part are assembled once.
- The DOFs only a variable part touches (its interior I_p) are eliminated part by part (static
  condensation): the part's Schur complement on the DOFs it shares with the rest (b_p: the ring
  DOFs its clamped faces are tied to), S_p = K_bb - K_bI K_II^-1 K_Ib, and its loads condensed the
  same way. The rest of the stack sees a member as the reference plus the low-rank change
  dS = sum_p (S_p(member) - S_p(reference)) on b, whose inverse follows from the reference
  factorisation by the Sherman-Morrison-Woodbury identity:
      (H + dS)^-1 v = H^-1 v - Z (I + dS Z_b)^-1 dS (H^-1 v)_b,   Z = H^-1 E_b,
  H the reference stiffness condensed to the rest. Source: Golub & Van Loan, Matrix Computations,
  4th ed., section 2.1.4 (Sherman-Morrison-Woodbury) and 4.2 (Schur complements); Przemieniecki,
  Theory of Matrix Structural Analysis, ch. 9 (substructures / static condensation).
- The thermal load of a part scales with 3 lam + 2 mu (`fem.forms.thermal_load`), its centrifugal
  load with its density (`fem.forms.centrifugal_load`).
- The preload-path compliance (`fem.compliance`) is the response to the raceway unit loads with the
  contact status of the assembled fits held: from the condensed arrays, the assembled status by the
  same complementarity problem the superposition solves (`fem.solver.Superposition`), then the
  closed pairs' forces lambda_C = -A_CC^-1 b_C of the raceway load column (a clamp's face, clamp
  = "force", closed, as `fem.compliance` holds it).

The algebra is exact: a member's set-up equals the full set-up of its own spec to round-off
(tests/test_parametric.py holds the two equal). Only frictionless fits (the all-open system).
Units: mm, N, MPa.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, replace

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lu_factor, lu_solve
from scipy.sparse.linalg import splu

from analytic.materials import Material
from skfem import Basis, asm

from fem.forms import centrifugal_load, elasticity, lame_parameters, thermal_load
from fem.setup import FESetup, SetupSpec, full_fe
from fem.solver import Condensed, Superposition, _lu_solve, single_thread_blas


class FamilyError(ValueError):
    """A spec is not a member of the family (one line: what differs)."""


def family_key(spec: SetupSpec, variable: tuple[str, ...]) -> str:
    """Hex SHA-256 (24 digits) of the spec with the materials of the `variable` parts and the
    compliance plan's assembled interferences left out: equal for every member of one family (the
    interferences only choose the contact status the compliance is taken at, `_compliance`; the
    design search's fit classes change them and nothing else)."""
    sec = replace(spec.section, rects=tuple(replace(r, material="") if r.part in variable else r
                                            for r in spec.section.rects))
    mats = [[p, None if p in variable else asdict(m)] for p, m in spec.materials]
    plan = spec.compliance
    if plan is not None:
        plan = replace(plan, delta_assembled_mm=())
    data = {"spec": replace(spec, section=sec, materials=(), compliance=plan).key(),
            "materials": mats, "variable": list(variable)}
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:24]


@dataclass(frozen=True)
class _Part:
    """A variable part, on its local reduced DOFs (interior I then boundary b, `dofs`)."""
    name: str
    n_interior: int
    dofs: np.ndarray            # reduced DOF numbers: I_p then b_p
    b_pos: np.ndarray           # position of each b_p DOF in the family's b
    K_lam: sp.csr_matrix        # local stiffness per unit lam (MPa), per unit mu
    K_mu: sp.csr_matrix
    thermal: np.ndarray         # local thermal load per unit (3 lam + 2 mu) theta
    spin: np.ndarray            # local centrifugal load per unit rho omega^2 (zero if not spinning)


def _touched(m, T: sp.csr_matrix, contact_dofs: np.ndarray) -> dict[str, np.ndarray]:
    """The reduced DOFs (columns of the elimination T, ndofs x n_reduced) each part's elements
    touch, by part, and (key "") those of the contact pairs (`contact_dofs`): a part's face held
    as a contact (clamp = "force": the stack's faces) is shared with the rest through its pairs."""
    el = m.basis.element_dofs
    out = {p: np.unique(T[np.unique(el[:, m.part_of == p])].indices) for p in m.part_names}
    out[""] = np.unique(T[np.unique(contact_dofs)].indices)
    return out


def _interior_and_boundary(p: str, touched: dict[str, np.ndarray]):
    """(interior, boundary) reduced DOFs of part p: touched by p only, and shared with others."""
    mine = touched[p]
    others = np.unique(np.concatenate([v for q, v in touched.items() if q != p]))
    shared = np.isin(mine, others)
    return mine[~shared], mine[shared]


def _variable_part(m, T: sp.csr_matrix, p: str, dofs: np.ndarray, n_interior: int,
                   b_pos: np.ndarray, rotating: bool) -> _Part:
    """Part p's stiffness per unit lam and per unit mu, thermal load per unit (3 lam + 2 mu)
    theta and centrifugal load per unit rho omega^2, on its reduced DOFs `dofs` (interior first),
    assembled on its own elements (`fem.forms`)."""
    basis = Basis(m.mesh, m.basis.elem, elements=np.flatnonzero(m.part_of == p))
    shape = (basis.nelems, basis.X.shape[1])
    one, zero = np.ones(shape), np.zeros(shape)

    def local(M):
        return (T.T @ M @ T).tocsr()[dofs][:, dofs].tocsr()

    th = T.T @ asm(thermal_load, basis, lam=zero, mu=0.5 * one, theta=one)
    spin = T.T @ asm(centrifugal_load, basis, rho_w2=one) if rotating else np.zeros(T.shape[1])
    return _Part(p, n_interior, dofs, b_pos, local(asm(elasticity, basis, lam=one, mu=zero)),
                 local(asm(elasticity, basis, lam=zero, mu=one)), th[dofs], spin[dofs])


class Family:
    """The reference FE of a family and the arrays a member's set-up is computed from."""

    @single_thread_blas
    def __init__(self, spec: SetupSpec, variable: tuple[str, ...]):
        if spec.contact != "frictionless":
            raise FamilyError(f"contact '{spec.contact}': only frictionless fits")
        self.key = family_key(spec, variable)
        self.spec, self.variable = spec, tuple(variable)
        fe = full_fe(spec)
        m, s = fe.model, fe.solver
        self.ndofs, self.part_names = int(m.ndofs), tuple(m.part_names)
        self.fit_names = tuple(f.name for f in m.fits)
        self.fit_r_mm = np.array([f.r_mm for f in m.fits], float)
        self.fit_length_mm = np.array([f.length_mm for f in m.fits], float)
        self.fit_of_pair = s.fit_of_pair.copy()
        #: a clamp's spring in series with its face's pairs (`fem.solver.condense`) and which
        #: pairs are clamped faces (closed at assembly, `fem.compliance`)
        self.pair_compliance, self.face_pair = s.compliance.copy(), s.face_pair.copy()
        npair = s.n_pairs
        T, lu = s.factorize(np.zeros(npair, bool))
        T = sp.csr_matrix(T)
        nred = T.shape[1]
        touched = _touched(m, T, np.concatenate([s.master, s.slave, s.master_z, s.slave_z]))
        split = [(p, *_interior_and_boundary(p, touched)) for p in self.variable]
        self.b = (np.unique(np.concatenate([bound for _, _, bound in split])) if split
                  else np.zeros(0, int))
        pos = np.full(T.shape[1], -1)
        pos[self.b] = np.arange(self.b.size)
        self.parts = [_variable_part(m, T, p, np.concatenate([interior, bound]), interior.size,
                                     pos[bound], p in spec.rotating_parts)
                      for p, interior, bound in split]
        # fixed load columns: unit thermal strain of every other part, the spin of the other
        # rotating parts, the raceway unit loads (compliance), unit pair forces
        self.fixed_parts = tuple(p for p in self.part_names if p not in self.variable)
        cols = [m.unit_loads[:, self.part_names.index(p)] for p in self.fixed_parts]
        rho = dict(spec.materials)
        rest_rho = np.array([rho[p].density_N_s2_mm4
                             if p in spec.rotating_parts and p not in self.variable else 0.0
                             for p in m.part_of])
        nq = m.basis.X.shape[1]
        cols.append(asm(centrifugal_load, m.basis, rho_w2=np.repeat(rest_rho[:, None], nq, 1)))
        if spec.compliance is not None:
            from fem.compliance import raceway_unit_loads
            sg = spec.compliance.signs
            cols.append(raceway_unit_loads(m, {"inner_ring_A": -sg[0], "inner_ring_B": -sg[1],
                                               "outer_ring_A": sg[0], "outer_ring_B": sg[1]}))
        E = np.zeros((m.ndofs, npair))
        E[s.slave, np.arange(npair)] = 1.0
        E[s.master, np.arange(npair)] -= 1.0
        F = T.T @ np.column_stack(cols + [E])
        interior_all = np.concatenate([p.dofs[:p.n_interior] for p in self.parts]) \
            if self.parts else np.zeros(0, int)
        if interior_all.size and np.abs(F[interior_all]).max() > 0:
            raise FamilyError("a fixed load reaches a variable part's interior")
        self.n_fixed_cols = len(cols)
        # outputs: the relative radial displacement of every pair, then the probes
        Q = sp.vstack([T[s.slave] - T[s.master], fe.probe @ T]).tocsr()
        if interior_all.size and abs(Q[:, interior_all]).max() > 0:
            raise FamilyError("a probe or contact pair lies in a variable part's interior")
        self.n_pairs, self.n_probe = npair, fe.probe.shape[0]
        Eb = np.zeros((nred, self.b.size))
        Eb[self.b, np.arange(self.b.size)] = 1.0
        # interior rows zeroed: H^-1 v is the rest part of K0^-1 [v; 0]
        Z = _lu_solve(lu, np.hstack([Eb, F]))
        self.QZ, self.Zb = Q @ Z[:, :self.b.size], Z[self.b, :self.b.size]
        self.QY, self.Yb = Q @ Z[:, self.b.size:], Z[self.b, self.b.size:]
        self.ref_materials = dict(spec.materials)
        self._S_ref = {p.name: self._condensed_part(p, self.ref_materials[p.name])[0]
                       for p in self.parts}

    def _condensed_part(self, p: _Part, mat: Material):
        """(S, thermal, spin) of a variable part of material `mat` condensed on its b DOFs:
        S = K_bb - K_bI K_II^-1 K_Ib, loads f_b - K_bI K_II^-1 f_I (thermal per unit theta)."""
        lam, mu = lame_parameters(mat.E_MPa, mat.nu)
        K = (lam * p.K_lam + mu * p.K_mu).tocsc()
        n = p.n_interior
        f = np.column_stack([(3 * lam + 2 * mu) * p.thermal, mat.density_N_s2_mm4 * p.spin])
        Kbb, Kbi = K[n:, n:].toarray(), K[n:, :n]
        if n == 0:
            return Kbb, f[n:, 0], f[n:, 1]
        lu = splu(K[:n, :n].tocsc(), permc_spec="MMD_AT_PLUS_A")
        X = _lu_solve(lu, np.hstack([K[:n, n:].toarray(), f[:n]]))
        S = Kbb - Kbi @ X[:, :-2]
        g = f[n:] - Kbi @ X[:, -2:]
        return 0.5 * (S + S.T), g[:, 0], g[:, 1]

    def member_materials(self, spec: SetupSpec) -> dict[str, Material]:
        """The variable parts' materials of `spec` (FamilyError when `spec` is not a member)."""
        if family_key(spec, self.variable) != self.key:
            raise FamilyError("the spec differs from the family's in more than the materials of "
                              f"{', '.join(self.variable)}")
        mats = dict(spec.materials)
        return {p: mats[p] for p in self.variable}

    @single_thread_blas
    def setup(self, spec: SetupSpec) -> FESetup:
        """The FE set-up of member `spec` (see the module docstring)."""
        mats = self.member_materials(spec)
        nb = self.b.size
        dS = np.zeros((nb, nb))
        C = np.zeros((nb, 2 * len(self.parts)))       # the variable parts' condensed loads
        for k, p in enumerate(self.parts):
            S, th, spin = self._condensed_part(p, mats[p.name])
            dS[np.ix_(p.b_pos, p.b_pos)] += S - self._S_ref[p.name]
            C[p.b_pos, 2 * k], C[p.b_pos, 2 * k + 1] = th, spin
        Yb = np.hstack([self.Yb, self.Zb @ C])
        QY = np.hstack([self.QY, self.QZ @ C])
        if np.any(dS):
            W = lu_solve(lu_factor(np.eye(nb) + dS @ self.Zb, check_finite=False), dS @ Yb,
                         check_finite=False)
            QY = QY - self.QZ @ W
        # columns: fixed parts' thermal, rest spin, [raceway], pairs, then per variable part
        # (thermal, spin)
        nf = len(self.fixed_parts)
        var = QY[:, -2 * len(self.parts):] if self.parts else np.zeros((QY.shape[0], 0))
        by_part = {p: QY[:, i] for i, p in enumerate(self.fixed_parts)}
        spin = QY[:, nf].copy()
        for k, p in enumerate(self.parts):
            by_part[p.name] = var[:, 2 * k]
            spin += var[:, 2 * k + 1]
        loads = np.column_stack([by_part[p] for p in self.part_names] + [spin])
        pairs = QY[:, self.n_fixed_cols:self.n_fixed_cols + self.n_pairs]
        npair = self.n_pairs
        B, A = loads[:npair], pairs[:npair]
        PU = np.hstack([loads[npair:], pairs[npair:]])
        cond = Condensed(False, len(self.part_names), len(self.fit_names), self.fit_of_pair.copy(),
                         np.ascontiguousarray(B), 0.5 * (A + A.T) + np.diag(self.pair_compliance),
                         np.ascontiguousarray(PU),
                         np.zeros((0, 0)))
        comp = np.nan
        if spec.compliance is not None:        # the member's own plan (its assembled fits)
            comp = _compliance(cond, QY[:, nf + 1], spec.compliance, self.face_pair)
        return FESetup(spec.key(), self.ndofs, self.part_names, self.fit_names,
                       self.fit_r_mm.copy(), self.fit_length_mm.copy(), cond, float(comp))


def _compliance(cond: Condensed, raceway: np.ndarray, plan, face_pair: np.ndarray) -> float:
    """The preload-path compliance (mm/N, `fem.compliance`) from the condensed problem: the
    assembled fits' contact status (the complementarity problem at zero load, the assembled
    interferences), then the raceway unit loads' response with that status held: gap on the
    closed pairs zero, lambda_C = -A_CC^-1 b_C, probes = p + PU_pairs lambda."""
    from scipy.linalg import cho_factor, cho_solve

    npair = cond.fit_of_pair.size
    sup = Superposition.from_condensed(cond, lambda: None)
    res = sup.evaluate(np.zeros((1, cond.n_parts)), np.array([plan.delta_assembled_mm]))
    closed = res.closed_sets[res.status[0]] | face_pair    # clamped faces: closed at assembly
    b, p = raceway[:npair], raceway[npair:]
    lam = np.zeros(npair)
    if closed.any():
        lam[closed] = -cho_solve(cho_factor(cond.A[np.ix_(closed, closed)]), b[closed])
    n_loads = cond.n_parts + 1
    u = p + cond.probe_units[:, n_loads:] @ lam
    pz = u[:8][1::2]
    d_dz = np.array([pz[0] - pz[2], pz[1] - pz[3]])
    return float(np.mean(-np.asarray(plan.signs) * d_dz))


#: families built in this process, by family key (a design search's worker builds each once; a
#: family keeps the reduced arrays, not the FE model: seed 000 1.7 MB on the screening mesh,
#: 3.5 MB on the assembly's; `--clamps` makes 16 families of 4 lengths x 4 clamp schemes)
_FAMILIES: dict[str, Family] = {}
FAMILIES_MAX = 32


def member_spec(spec: SetupSpec, materials: dict[str, Material]) -> SetupSpec:
    """`spec` with the parts of `materials` made of those (the same family)."""
    sec = replace(spec.section, rects=tuple(replace(r, material=materials[r.part].name)
                                            if r.part in materials else r
                                            for r in spec.section.rects))
    return replace(spec, section=sec, materials=tuple((p, materials.get(p, m))
                                                      for p, m in spec.materials))


def parametric_setup(spec: SetupSpec, variable: tuple[str, ...],
                     reference: dict[str, Material] | None = None) -> FESetup:
    """The set-up of `spec` through its family, built on first use in this process with the
    variable parts made of `reference` (default: `spec`'s own materials). A fixed reference
    makes the numbers independent of the order in which members are asked for (Dask workers)."""
    key = family_key(spec, variable)
    fam = _FAMILIES.get(key)
    if fam is None:
        fam = Family(member_spec(spec, reference or {}), variable)
        while _FAMILIES and len(_FAMILIES) >= FAMILIES_MAX:      # the bound, even if lowered
            _FAMILIES.pop(next(iter(_FAMILIES)))
        _FAMILIES[key] = fam
    return fam.setup(spec)
