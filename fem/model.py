"""The FE model of a section: mesh with fit interfaces unzipped, P2 basis, stiffness, unit loads.

Steps (each a small function):
1. `unzip`: along every split line the outer-side parts get their own copies of the shared nodes,
   so a fit can open, close or slide; everything else stays tied (shared nodes).
2. `StackModel`: scikit-fem MeshTri + vector P2 basis; stiffness K (whole-ring measure 2 pi r);
   one thermal load vector per part for unit thermal strain; node pairs of each fit (radial and
   axial DOFs of the inner member = master, of the outer member = slave) and of each clamped face
   held as a contact (`meshes.section.Face`: u_z across the face, a clamp with a force); Dirichlet DOFs: u_r = 0
   on the axis, rollers, and one u_z per free-floating body (rigid axial mode, statically
   determinate, so it adds no stress); a part held only by faces that are contacts (the stack's
   ring-shoulder and ring-spacer faces under a clamp with a force) is held by a weak spring
   across one of them instead (`HoldSprings`, `HOLD_RATIO`). `spin_load`: the centrifugal load of the spinning parts
   (`rotating_parts`, e.g. the rotor sub-assembly) at omega = 1 rad/s; at omega it scales by
   omega^2 (the load is linear in rho omega^2).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTriP2, ElementVector, MeshTri, asm

from analytic.materials import Material, get_material
from fem.forms import centrifugal_load, elasticity, lame_parameters, thermal_load
from meshes.section import Section, Split
from meshes.build import SectionMesh, section_mesh


def part_materials(section: Section, materials: dict[str, Material] | None = None
                   ) -> dict[str, Material]:
    """The material of every FE part of `section` (part order): `materials[part]` when given,
    else the library material the section names for it."""
    return {p: (materials or {}).get(p) or get_material(section.material_of(p))
            for p in section.parts()}


TOL_MM = 1e-7

#: the weak spring that holds a part of the stack whose faces all open, relative to a steel
#: part's axial stiffness E A / L (`meshes.section.Face.hold_ratio`). It is stretched only where
#: a part is pulled off its neighbour towards the shoulder (an axial load inside the stack, or a
#: face the fits dish partly open at the spring's node pair), and then carries this fraction of
#: what the closed part would over the same gap; closed, it carries nothing. Its inverse sets the
#: conditioning of the all-open system the superposition is condensed from, and the round-off of
#: the condensed arrays grows as its square (measured on seed 000's design family, parametric vs
#: own set-up: 1e-9 relative at 1e-3, 6e-8 at 1e-4, 7e-4 at 1e-6), which sets the value
HOLD_RATIO = 1e-3
#: the modulus (MPa) the weak spring is scaled with, whatever the part is made of (a bearing
#: steel's, 9Cr18 of the material library): the spring is then the same for every material of a
#: part (a design family's spacers, `fem.parametric`, keep it in the part they do not vary)
HOLD_E_MPA = get_material("9Cr18").E_MPa


def unzip(points: np.ndarray, tris: np.ndarray, part_of: np.ndarray, section: Section):
    """Duplicate the nodes on each split line for the elements of its outer-side parts.
    Returns new (points, tris). Pure function."""
    points, tris = points.copy(), tris.copy()
    for s in section.splits:
        on = nodes_on_line(points, s)
        outer_el = np.isin(part_of, s.outer_parts)
        inner_el = np.isin(part_of, s.inner_parts)
        used_in = np.unique(tris[:, inner_el])
        used_out = np.unique(tris[:, outer_el])
        shared = np.intersect1d(np.intersect1d(on, used_in), used_out)
        if shared.size == 0:
            continue
        new_index = np.arange(points.shape[1], points.shape[1] + shared.size)
        points = np.hstack([points, points[:, shared]])
        remap = np.arange(points.shape[1])
        remap[shared] = new_index
        tris[:, outer_el] = remap[tris[:, outer_el]]
    return points, tris


def nodes_on_line(x: np.ndarray, s) -> np.ndarray:
    """Indices of the points x (2, n) on a split line (axis "arc": on the circle about
    (at_mm, lo_mm) of radius hi_mm, a groove of `meshes.section.boundary_lines`)."""
    if s.axis == "arc":
        d = np.hypot(x[0] - s.at_mm, x[1] - s.lo_mm)
        return np.flatnonzero(np.abs(d - s.hi_mm) < TOL_MM * (1 + s.hi_mm))
    i, j = (0, 1) if s.axis == "r" else (1, 0)
    return np.flatnonzero((np.abs(x[i] - s.at_mm) < TOL_MM * (1 + abs(s.at_mm)))
                          & (x[j] >= s.lo_mm - TOL_MM) & (x[j] <= s.hi_mm + TOL_MM))


def node_pairs_on(x: np.ndarray, on: np.ndarray, el_dofs: np.ndarray, part_of: np.ndarray,
              side_a, side_b) -> tuple[np.ndarray, np.ndarray]:
    """Scalar DOFs on a line of side-a parts and side-b parts that sit at the same point."""
    a = np.intersect1d(on, el_dofs[:, np.isin(part_of, side_a)])
    b = np.intersect1d(on, el_dofs[:, np.isin(part_of, side_b)])
    a, b = np.setdiff1d(a, b), np.setdiff1d(b, a)     # shared (still tied) nodes are no pairs
    ka = {tuple(np.round(x[:, i], 9)): i for i in a}
    pa, pb = [], []
    for i in b:
        k = ka.get(tuple(np.round(x[:, i], 9)))
        if k is not None:
            pa.append(k)
            pb.append(i)
    return np.array(pa, int), np.array(pb, int)


@dataclass
class FitPairs:
    """DOF pairs of one fit, sorted by z. master = inner member, slave = outer member.

    A clamped face (`meshes.section.Face`, axis "z") is held the same way with the roles of the
    directions swapped: master_r / slave_r are then the u_z DOFs (the normal, the contact
    direction), master_z / slave_z the u_r DOFs, z_mm the nodes' radii (sorted), r_mm the mean
    radius and length_mm the radial width, so that sum(force) / (2 pi r_mm length_mm) is the mean
    face pressure. compliance_mm_per_N (n_pairs,): the spring in series with each pair's contact
    (0: none; a face's clamp layer, `face_weights`)."""
    name: str
    key: str
    r_mm: float
    length_mm: float
    z_mm: np.ndarray
    master_r: np.ndarray
    slave_r: np.ndarray
    master_z: np.ndarray
    slave_z: np.ndarray
    axis: str = "r"
    compliance_mm_per_N: np.ndarray | None = None

    def pair_compliance_mm_per_N(self) -> np.ndarray:
        """(n_pairs,) series compliance of each pair, mm/N (0: a rigid contact)."""
        c = self.compliance_mm_per_N
        return np.zeros(self.master_r.size) if c is None else c


@dataclass(frozen=True)
class HoldSprings:
    """The weak springs that hold the parts of a stack whose faces are contacts
    (`StackModel._hold_springs`): spring i between the u_z DOFs master[i] and slave[i] (the
    -z and +z side of a face), k_N_per_mm[i] its stiffness (N/mm, whole ring)."""
    master: np.ndarray
    slave: np.ndarray
    k_N_per_mm: np.ndarray

    def stiffness(self, ndofs: int) -> sp.csr_matrix:
        """(ndofs, ndofs) stiffness of the springs: k on (m, m), (s, s), -k on (m, s), (s, m)."""
        m, s, k = self.master, self.slave, self.k_N_per_mm
        return sp.csr_matrix((np.concatenate([k, k, -k, -k]),
                              (np.concatenate([m, s, m, s]), np.concatenate([m, s, s, m]))),
                             shape=(ndofs, ndofs))


def face_weights(r_mm: np.ndarray) -> np.ndarray:
    """Consistent nodal weights (mm^2) of a uniform pressure on a flat annular face meshed with
    quadratic line elements: w_i = integral of N_i 2 pi r dr. `r_mm`: the face's nodes sorted by
    radius, vertex, mid-side, vertex, ... (odd count). Per element of length h from r_a to r_b
    (mid r_m): 2 pi h (r_a / 6, 2 r_m / 3, r_b / 6), exact for the quadratic shape functions
    (N_0 = (1 - s)(1 - 2 s), N_1 = 4 s (1 - s), N_2 = s (2 s - 1), r linear in s; Zienkiewicz &
    Taylor, The Finite Element Method Vol. 1, 7th ed., ch. 6 (axisymmetric loads)). Their sum is
    the face area pi (r_1^2 - r_0^2)."""
    r = np.asarray(r_mm, float)
    if r.size < 3 or r.size % 2 == 0:
        raise RuntimeError(f"a face of {r.size} nodes is not a chain of quadratic elements")
    w = np.zeros(r.size)
    for e in range(0, r.size - 2, 2):
        h = r[e + 2] - r[e]
        w[e] += 2 * np.pi * h * r[e] / 6
        w[e + 1] += 2 * np.pi * h * 2 * r[e + 1] / 3
        w[e + 2] += 2 * np.pi * h * r[e + 2] / 6
    return w


def _components(tris: np.ndarray, n_nodes: int) -> np.ndarray:
    """Connected component label per node (elements sharing nodes are connected)."""
    rows = np.repeat(np.arange(tris.shape[1]), tris.shape[0])
    inc = sp.csr_matrix((np.ones(rows.size), (tris.T.ravel(), rows)), shape=(n_nodes, tris.shape[1]))
    adj = inc @ inc.T
    return sp.csgraph.connected_components(adj, directed=False)[1]


class StackModel:
    """Assembled axisymmetric thermo-elastic model of a section. Units: mm, N, MPa."""

    def __init__(self, section: Section, smesh: SectionMesh, contact: str = "frictionless",
                 materials: dict[str, Material] | None = None,
                 rotating_parts: tuple[str, ...] = ()):
        if contact not in ("frictionless", "bonded"):
            raise ValueError(f"contact must be 'frictionless' or 'bonded', got '{contact}'")
        unknown = sorted(set(rotating_parts) - set(section.parts()))
        if unknown:
            raise ValueError(f"rotating parts {unknown} are not parts of the section")
        self.rotating_parts = tuple(rotating_parts)
        self.section, self.contact = section, contact
        self.part_names = section.parts()
        self.part_of = np.asarray(smesh.part_of).astype(str)
        self.materials = part_materials(section, materials)
        pts, tris = unzip(smesh.points, smesh.triangles, self.part_of, section)
        self.mesh = MeshTri(pts, tris)
        self.basis = Basis(self.mesh, ElementVector(ElementTriP2()))
        self.sbasis = Basis(self.mesh, ElementTriP2())
        self.ndofs = self.basis.N
        nq = self.basis.X.shape[1]
        E = np.array([self.materials[p].E_MPa for p in self.part_of])
        nu = np.array([self.materials[p].nu for p in self.part_of])
        lam, mu = lame_parameters(E, nu)
        self.lam_e, self.mu_e = lam, mu
        self.lam_q, self.mu_q = np.repeat(lam[:, None], nq, 1), np.repeat(mu[:, None], nq, 1)
        self.K = asm(elasticity, self.basis, lam=self.lam_q, mu=self.mu_q).tocsr()
        self.unit_loads = np.column_stack([self.thermal_load_vector(self._indicator(p))
                                           for p in self.part_names])
        rho = np.array([self.materials[p].density_N_s2_mm4 if p in self.rotating_parts else 0.0
                        for p in self.part_of])
        self.spin_load = asm(centrifugal_load, self.basis,
                             rho_w2=np.repeat(rho[:, None], nq, 1))     # N per (rad/s)^2
        self.fits = ([self._fit_pairs(f) for f in section.fits]
                     + [self._face_pairs(f) for f in section.faces])
        self.hold = self._hold_springs()
        if self.hold.k_N_per_mm.size:
            self.K = (self.K + self.hold.stiffness(self.ndofs)).tocsr()
        self.tie_master, self.tie_slave = self._face_ties()
        self.dirichlet = self._dirichlet()

    # --- loads -----------------------------------------------------------------------------
    def _indicator(self, part: str) -> np.ndarray:
        ind = (self.part_of == part).astype(float)
        return np.repeat(ind[:, None], self.basis.X.shape[1], 1)

    def thermal_load_vector(self, theta_q: np.ndarray) -> np.ndarray:
        """Load vector of a thermal strain field theta at the quadrature points (nel, nq)."""
        return asm(thermal_load, self.basis, lam=self.lam_q, mu=self.mu_q, theta=theta_q)

    def theta_by_part(self, T_C: dict[str, float], T_ref_C: float) -> np.ndarray:
        """Thermal strain per part (in part order) for uniform part temperatures."""
        return np.array([self.materials[p].thermal_strain(T_C[p], T_ref_C)
                         for p in self.part_names])

    # --- constraints -----------------------------------------------------------------------
    def _fit_pairs(self, f) -> FitPairs:
        x = self.sbasis.doflocs
        on = np.flatnonzero((np.abs(x[0] - f.r_mm) < TOL_MM * (1 + f.r_mm))
                            & (x[1] >= f.z0_mm - TOL_MM) & (x[1] <= f.z1_mm + TOL_MM))
        el_dofs = self.sbasis.element_dofs
        inner = np.intersect1d(on, el_dofs[:, self.part_of == f.inner_part])
        outer = np.intersect1d(on, el_dofs[:, self.part_of == f.outer_part])
        inner = inner[np.argsort(x[1, inner])]
        outer = outer[np.argsort(x[1, outer])]
        if inner.size != outer.size or inner.size < 3 or not np.allclose(x[:, inner], x[:, outer]):
            raise RuntimeError(f"fit '{f.name}': {inner.size} inner and {outer.size} outer nodes do "
                               "not pair up (non-conforming interface)")
        return FitPairs(f.name, f.key, f.r_mm, f.z1_mm - f.z0_mm, x[1, inner],
                        2 * inner, 2 * outer, 2 * inner + 1, 2 * outer + 1)

    def _face_pairs(self, f) -> FitPairs:
        """The node pairs of a clamped face (`meshes.section.Face`) as a contact in u_z, its
        clamp layer spread as a uniform pressure (`face_weights`): pair i gets the compliance
        c_face W / w_i (W = sum w), so the layer's springs add up to 1 / c_face."""
        x, el = self.sbasis.doflocs, self.sbasis.element_dofs
        line = Split(f.name, "z", f.z_mm, f.r0_mm, f.r1_mm, (), ())
        a, b = node_pairs_on(x, nodes_on_line(x, line), el, self.part_of, f.inner_parts,
                             f.outer_parts)
        order = np.argsort(x[0, a], kind="stable")
        a, b = a[order], b[order]
        # where two parts on one side meet at the face (a ring's and a sleeve's corner on the
        # housing shoulder) both pair with the one node across: the first pair is kept
        keep = np.ones(a.size, bool)
        keep[1:] = (a[1:] != a[:-1]) & (b[1:] != b[:-1])
        a, b = a[keep], b[keep]
        if a.size < 3 or not np.allclose(x[:, a], x[:, b]):
            raise RuntimeError(f"face '{f.name}': {a.size} node pairs (is its split tied?)")
        r = x[0, a]
        w = face_weights(r)
        comp = (f.compliance_mm_per_N * w.sum() / w if f.compliance_mm_per_N > 0
                else np.zeros(a.size))
        r0, r1 = float(r[0]), float(r[-1])
        return FitPairs(f.name, f.key, 0.5 * (r0 + r1), r1 - r0, r, 2 * a + 1, 2 * b + 1,
                        2 * a, 2 * b, "z", comp)

    def _hold_springs(self) -> "HoldSprings":
        """The weak springs of the stack's faces (`meshes.section.Face.hold_ratio`): on each such
        face, for each part on its +z side, one spring in u_z across the face at that part's
        middle node pair (by radius), of stiffness hold_ratio E A / L (E = HOLD_E_MPA, a steel's
        modulus for every material, A the part's share of the face area, the sum of its pairs'
        `face_weights`, L its axial length)."""
        el = self.sbasis.element_dofs
        m_dof, s_dof, k_all = [], [], []
        for fp, f in zip(self.fits[len(self.section.fits):], self.section.faces):
            if f.hold_ratio <= 0:
                continue
            w = face_weights(fp.z_mm)
            for part in f.outer_parts:
                mine = np.isin(fp.slave_r // 2, el[:, self.part_of == part])
                if not mine.any():
                    continue
                rects = [rc for rc in self.section.rects if rc.part == part]
                L = max(rc.z1_mm for rc in rects) - min(rc.z0_mm for rc in rects)
                idx = np.flatnonzero(mine)
                mid = idx[np.argmin(np.abs(fp.z_mm[idx] - np.median(fp.z_mm[idx])))]
                m_dof.append(fp.master_r[mid])
                s_dof.append(fp.slave_r[mid])
                k_all.append(f.hold_ratio * HOLD_E_MPA * w[idx].sum() / L)
        return HoldSprings(np.array(m_dof, int), np.array(s_dof, int), np.array(k_all, float))

    def _face_ties(self) -> tuple[np.ndarray, np.ndarray]:
        """u_z DOF pairs (master, slave) across the clamped faces (axis-"z" splits)."""
        x, el = self.sbasis.doflocs, self.sbasis.element_dofs
        ms, ss = [], []
        for s in self.section.splits:
            if s.axis != "z" or not s.tied:
                continue
            a, b = node_pairs_on(x, nodes_on_line(x, s), el, self.part_of, s.inner_parts, s.outer_parts)
            ms.append(2 * a + 1)
            ss.append(2 * b + 1)
        if not ms:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(ms), np.concatenate(ss)

    def _dirichlet(self) -> np.ndarray:
        x = self.sbasis.doflocs
        fixed = [2 * np.flatnonzero(np.abs(x[0]) < TOL_MM)]          # u_r = 0 on the axis
        for z in self.section.rollers_z_mm:
            fixed.append(2 * np.flatnonzero(np.abs(x[1] - z) < TOL_MM * (1 + abs(z))) + 1)
        fixed_z = np.concatenate(fixed[1:]) if len(fixed) > 1 else np.array([], int)
        # one axial reference per free-floating body (bonded fits join bodies)
        n = self.sbasis.N
        comp = _components(self.sbasis.element_dofs, n)
        links = [np.vstack([self.tie_master // 2, self.tie_slave // 2]),
                 np.vstack([self.hold.master // 2, self.hold.slave // 2])]
        if self.contact == "bonded":
            links += [np.vstack([fp.master_r // 2, fp.slave_r // 2]) for fp in self.fits]
        links = np.hstack(links)
        if links.size:
            nc = comp.max() + 1
            g = sp.csr_matrix((np.ones(links.shape[1]), (comp[links[0]], comp[links[1]])),
                              shape=(nc, nc))
            comp = sp.csgraph.connected_components(g + g.T + sp.eye(nc), directed=False)[1][comp]
        slaves = set((self.tie_slave // 2).tolist())
        if self.contact == "bonded":
            slaves |= set(np.concatenate([fp.slave_z // 2 for fp in self.fits]).tolist())
        has_z = set(comp[fixed_z // 2].tolist())
        for c in np.unique(comp):
            if c in has_z:
                continue
            nodes = [i for i in np.flatnonzero(comp == c) if i not in slaves]
            i = min(nodes, key=lambda k: (x[1, k], x[0, k]))
            fixed.append(np.array([2 * i + 1]))
        return np.unique(np.concatenate(fixed))

    # --- probes ----------------------------------------------------------------------------
    def probe_matrix(self, pts_rz: np.ndarray) -> sp.csr_matrix:
        """(2 n_pts, ndofs) matrix mapping the displacement DOFs to (u_r, u_z) at the points,
        interleaved [u_r(p0), u_z(p0), u_r(p1), ...]."""
        S = sp.csr_matrix(self.sbasis.probes(np.asarray(pts_rz, float)))
        rows, cols = S.nonzero()
        vals = np.asarray(S[rows, cols]).ravel()
        R = sp.csr_matrix((vals, (2 * rows, 2 * cols)), shape=(2 * S.shape[0], self.ndofs))
        Z = sp.csr_matrix((vals, (2 * rows + 1, 2 * cols + 1)), shape=(2 * S.shape[0], self.ndofs))
        return (R + Z).tocsr()


def line_split(name, spec) -> Split:
    """A (axis, at, lo, hi) boundary line of `meshes.section.boundary_lines` as a `Split`."""
    axis, at, lo, hi = spec
    return Split(name, axis, at, lo, hi, (), ())


def facets_on_line(model: StackModel, spec) -> np.ndarray:
    """Boundary facets whose both end vertices lie on the line."""
    m = model.mesh
    bf = m.boundary_facets()
    on = np.zeros(m.p.shape[1], bool)
    on[nodes_on_line(m.p, line_split("", spec))] = True
    return bf[on[m.facets[0, bf]] & on[m.facets[1, bf]]]


def build_model(section: Section, contact: str = "frictionless",
                materials: dict[str, Material] | None = None,
                rotating_parts: tuple[str, ...] = ()) -> StackModel:
    """Mesh the section (cached) and assemble its model (`rotating_parts`: the parts that spin)."""
    return StackModel(section, section_mesh(section), contact, materials, rotating_parts)
