"""Transient axisymmetric heat conduction on the stack's section mesh (scalar P2, scikit-fem).

    rho c dT/dt - div(k grad T) = s            in each part (r-z section, ring measure 2 pi r)
    -k dT/dn = h_g (T - T_amb)                 on face group g (convection, film coefficient h_g)
    -k dT/dn = eps sigma (T_K^4 - T_sink,K^4)  on radiating face groups (T_K = T + 273.15)
    -k dT/dn = -q                              heat input Q (W) spread uniformly over a face group
    T = T_fixed(t)                             on fixed face groups
    -k1 dT1/dn = h_c (T1 - T2) = k2 dT2/dn     across every fit (thermal contact conductance h_c)

Weak form, with every integral over the whole ring (2 pi r dr dz, 2 pi r ds), so that the matrices
are whole-body quantities: M (J/K), K (W/K), loads in W:

    M dT/dt + (K + sum_g h_g F_g + sum_f h_f C_f + ...) T = sum_g h_g T_amb b_g + sum Q a + ...

Everything is affine in the film coefficients h_g, the fit conductances h_f and the ball
conductances (`TransientConduction.operator`): one matrix per coefficient, assembled once. The
reduced model (`fem.reduced_thermal`) projects each term separately.

Interfaces. The mesh is unzipped along every split line (`fem.model.unzip`). Clamped faces
(axis "z" splits) are tied (perfect thermal contact, as in the steady `fem.thermal`: the clamp
presses them together). Every radial split line (seats and bores) carries a contact conductance:
on a fit the fit's h_f, elsewhere (a spacer bore on the shaft, a spacer in the housing bore) the
bore conductance; the interface term int h (T_out - T_in)(v_out - v_in) 2 pi r ds is assembled on
the outer member's facets with its P2 trace paired node by node to the inner member's (the meshes
are conforming across the line). `perfect_contact=True` ties the radial lines too (the steady
`fem.thermal.ConductionModel` in the steady limit, a test holds them equal).
Contact conductance of a closed fit from its pressure, of an open one from its gap:
`contact_conductance_W_m2K` (Yovanovich's plastic correlation; gas gap conduction).

Balls. Optionally one lumped node per bearing ("ball_A", "ball_B": capacity of the ball set,
J/K) linked by conductances (W/K) to the mean temperature of its inner and its outer raceway line;
without ball nodes the two raceways are linked directly (the steady model's ball conductance).

Time integration (`Stepper`): backward Euler (order 1) or BDF2 (order 2, started by one backward
Euler step), fixed step dt, one sparse LU of (c0 M + A) per scheme reused for every step (a new
one only when a coefficient changes). Radiation is semi-implicit: the linear part
h_r (T - T_sink) with h_r = 4 eps sigma T_lin,K^3 at a fixed linearisation temperature is implicit
(in the factorised matrix), the remainder eps sigma (T_K^4 - T_sink,K^4) - h_r (T - T_sink) is
taken from the extrapolated state (T^n with backward Euler, 2 T^n - T^(n-1) with BDF2, so the
scheme keeps its order) at the nodes (nodal interpolation of the nonlinear flux). Every step
returns its energy balance: heat in = stored + convected + radiated (+ through fixed faces),
which holds to round-off for both schemes in their own quadrature (`StepBalance`).

Units: mm, s, W, J, C inside. Film and contact coefficients in W/(m^2 K) as catalogues give
them, converted with 1e-6 (W/(mm^2 K)); k in W/(m K) -> /1000; rho c in J/(m^3 K) -> 1e-9
J/(mm^3 K). Sources: Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., ch. 2
(heat equation), ch. 3.1.4 (contact resistance), ch. 12 (radiation exchange with a large
enclosure); Zienkiewicz & Taylor, The Finite Element Method Vol. 1, 6th ed., ch. 16/17
(semi-discrete heat equation, time stepping); Hairer & Wanner, Solving ODEs II, ch. V.1 (BDF2,
A- and L-stable, order 2).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from skfem import FacetBasis, asm

from fem.forms import boundary_flux, conduction, convection, heat_capacity
from fem.model import TOL_MM, StackModel, facets_on_line, node_pairs_on, nodes_on_line
from fem.solver import _tie_representatives
from meshes.section import boundary_lines

#: Stefan-Boltzmann constant, W/(mm^2 K^4) (CODATA 2018: 5.670374419e-8 W/(m^2 K^4))
SIGMA_W_MM2_K4 = 5.670374419e-14
KELVIN = 273.15
#: W/(m^2 K) -> W/(mm^2 K)
PER_M2_TO_PER_MM2 = 1e-6
#: solid-spot conductance of a clearance / slip fit's metallic contact at light pressure
#: (W/(m^2 K)): Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., Table
#: 3.1, stainless steel interfaces in vacuum at 100 kN/m^2 (0.1 MPa, a light contact):
#: R'' = 6..25e-4 m^2 K/W, h = 400..1670 W/(m^2 K) (OPEN_FIT_SPOT_RANGE_W_M2K); the nominal
#: is the range's geometric mean, 816 W/(m^2 K). A clearance fit's spots carry no more than
#: that light pressure; the aluminium and magnesium of that table (R'' 1.5..5e-4) conduct more
OPEN_FIT_SPOT_RANGE_W_M2K = (1.0 / 25e-4, 1.0 / 6e-4)
OPEN_FIT_SPOT_W_M2K = float(np.sqrt(OPEN_FIT_SPOT_RANGE_W_M2K[0] * OPEN_FIT_SPOT_RANGE_W_M2K[1]))


# ------------------------------------------------------------------------ contact conductance
@dataclass(frozen=True)
class SurfacePair:
    """Surface data of a fit's two faces for the contact conductance.

    roughness_um: combined RMS roughness sigma = sqrt(sigma_1^2 + sigma_2^2) (um); ground bearing
    seats and bores Ra 0.2-0.4 um (ISO 1302 N4-N5; RMS ~ 1.25 Ra), both faces -> ~0.5 um.
    slope: combined mean absolute asperity slope m = sqrt(m_1^2 + m_2^2) (-); None: from the
    roughness by the Antonetti correlation m = 0.125 (sigma/1 um)^0.402 (Madhusudana, Thermal
    Contact Conductance, 2nd ed. 2014, eq. 3.30).
    microhardness_MPa: of the softer face; hardened bearing steel HV 700 ~ 6.9 GPa,
    17-4PH H1025 HV ~ 350 ~ 3.4 GPa, Ti-6Al-4V HV ~ 350, aluminium 2024-T3 HV ~ 140 (ASM Handbook
    Vol. 1; Vickers number x 9.81 MPa).
    gas_conductivity_W_mK: the interstitial gas (air 0.026 at 20 C, Incropera Table A.4;
    0 in vacuum). gas_jump_um: the gas rarefaction parameter M = alpha beta Lambda (air at
    1 atm ~ 0.37 um, Madhusudana ch. 5).
    spot_W_m2K: the solid-spot conductance of an open (clearance, slip) fit (W/(m^2 K)): the
    ring or spacer rests on its seat at contact spots (its weight, the radial load, the
    fit's out-of-roundness), which the axisymmetric mean gap does not hold; in parallel with
    the gas across the gap. 0: no spots (the mean gap's gas alone); a stack's fits take
    OPEN_FIT_SPOT_W_M2K (`studies.model.transient_route.contacts`).
    """
    roughness_um: float = 0.5
    slope: float | None = None
    microhardness_MPa: float = 3.4e3
    gas_conductivity_W_mK: float = 0.026
    gas_jump_um: float = 0.37
    spot_W_m2K: float = 0.0

    @property
    def m(self) -> float:
        return self.slope if self.slope is not None else 0.125 * self.roughness_um ** 0.402


def contact_conductance_W_m2K(pressure_MPa, gap_um, k1_W_mK: float, k2_W_mK: float,
                              surf: SurfacePair = SurfacePair()) -> np.ndarray:
    """Thermal conductance of a fit (W/(m^2 K)) at contact pressure p (MPa) or, where p <= 0, at
    the radial gap g >= 0 (um).

    Closed (p > 0): solid spot conductance of plastically deformed asperities (Yovanovich, "Thermal
    contact correlations", AIAA paper 81-1164, 1981; Madhusudana 2014, eq. 3.39)

        h_s = 1.25 k_s (m / sigma) (p / H_c)^0.95,   k_s = 2 k1 k2 / (k1 + k2)

    (no less than the spots of a light contact, `SurfacePair.spot_W_m2K`)

    plus the gas in the gaps between the asperities (Yovanovich 1981, the mean plane separation
    Y = 1.53 sigma (p / H_c)^-0.097, Madhusudana eq. 5.12): h_g = k_g / (Y + M).
    Open (p <= 0): conduction across the gas gap, h = k_g / (g + M) (Incropera ch. 3.1.4; the
    temperature jump M as above), plus the solid spots the open fit rests on
    (`SurfacePair.spot_W_m2K`, in parallel); radiation across the gap is left out (a few
    W/(m^2 K) below 150 C). Vacuum (k_g = 0): an open fit conducts through its spots alone
    (nothing without them). Units: sigma and M in um -> m inside.
    """
    p = np.asarray(pressure_MPa, float)
    g = np.maximum(np.asarray(gap_um, float), 0.0)
    ks = 2.0 * k1_W_mK * k2_W_mK / (k1_W_mK + k2_W_mK)
    sig_m, M_m = surf.roughness_um * 1e-6, surf.gas_jump_um * 1e-6
    ratio = np.maximum(p, 1e-12) / surf.microhardness_MPa
    h_solid = 1.25 * ks * surf.m / sig_m * ratio ** 0.95
    h_gas_closed = surf.gas_conductivity_W_mK / (1.53 * sig_m * ratio ** -0.097 + M_m)
    h_open = surf.gas_conductivity_W_mK / (g * 1e-6 + M_m) + surf.spot_W_m2K
    # a closed fit conducts at least as the light contact of its spots: continuous where it opens
    return np.where(p > 0, np.maximum(h_solid, surf.spot_W_m2K) + h_gas_closed, h_open)


def fit_conductances_W_m2K(model: StackModel, pressure_MPa, gap_um,
                           surf: SurfacePair = SurfacePair()) -> np.ndarray:
    """(n_fits,) contact conductance (W/(m^2 K)) of every fit of `model` (model order) from its
    mean pressure (MPa) and, where open, its mean radial gap (um), with the conductivities of its
    two parts (`contact_conductance_W_m2K`): the typed input `ThermalParameters.
    fit_conductance_W_m2K` of a step, updated from the structural FE's fit state."""
    p = np.asarray(pressure_MPa, float)
    g = np.broadcast_to(np.asarray(gap_um, float), p.shape)
    mats = model.materials
    return np.array([float(contact_conductance_W_m2K(p[k], g[k], mats[f.inner_part].conductivity_W_mK,
                                                     mats[f.outer_part].conductivity_W_mK, surf))
                     for k, f in enumerate(model.section.fits)])


# ------------------------------------------------------------------------ face groups
def face_groups(model: StackModel) -> dict[str, np.ndarray]:
    """Exterior boundary facets of the section by group name: the named lines of
    `meshes.section.boundary_lines` (raceways, housing_outer, shaft_end, shaft_bore) and, for the
    rest of each part's exterior, "free_<part>". Interfaces of unzipped split lines (a facet with a
    twin at the same place) and the axis r = 0 are no exterior."""
    m = model.mesh
    bf = m.boundary_facets()
    mid = m.p[:, m.facets[:, bf]].mean(axis=1)
    key = np.round(mid.T / (TOL_MM * 100), 0)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    ext = (counts[inv.ravel()] == 1) & (np.abs(mid[0]) > TOL_MM)
    ext_f = bf[ext]
    taken = np.zeros(m.facets.shape[1], bool)
    groups: dict[str, np.ndarray] = {}
    for name, spec in boundary_lines(model.section).items():
        f = np.intersect1d(facets_on_line(model, spec), ext_f)
        if f.size:
            groups[name] = f
            taken[f] = True
    part_of_facet = model.part_of[m.f2t[0]]
    for p in model.part_names:
        f = ext_f[(part_of_facet[ext_f] == p) & ~taken[ext_f]]
        if f.size:
            groups[f"free_{p}"] = f
    return groups


# ------------------------------------------------------------------------ parameters, loads
@dataclass(frozen=True)
class ThermalParameters:
    """The coefficients of the affine operator (SI-style units as catalogues give them).

    film_W_m2K: face group -> film coefficient (groups not named: adiabatic).
    fit_conductance_W_m2K: (n_fits,) contact conductance per fit in `model.fits` order.
    bore_conductance_W_m2K: radial interfaces that are no fit (spacer bores); default the gap
    conduction of air across 10 um, 0.026 / 10e-6 (Incropera ch. 3.1.4).
    ball_inner_W_K, ball_outer_W_K: ball set to inner / outer raceway of each bearing (with ball
    nodes); without ball nodes the raceways are linked by the two in series.
    emissivity: face group -> hemispherical emissivity of the radiating groups.
    T_rad_lin_C: the temperature about which radiation is linearised in the implicit part."""
    film_W_m2K: dict = field(default_factory=dict)
    fit_conductance_W_m2K: tuple = ()
    bore_conductance_W_m2K: float = 2600.0
    ball_inner_W_K: float = 0.0
    ball_outer_W_K: float = 0.0
    emissivity: dict = field(default_factory=dict)
    T_rad_lin_C: float = 20.0

    def __post_init__(self):
        for name, v in [*((f"film_W_m2K[{k}]", h) for k, h in self.film_W_m2K.items()),
                        *((f"fit_conductance_W_m2K[{k}]", h)
                          for k, h in enumerate(self.fit_conductance_W_m2K)),
                        ("bore_conductance_W_m2K", self.bore_conductance_W_m2K),
                        ("ball_inner_W_K", self.ball_inner_W_K),
                        ("ball_outer_W_K", self.ball_outer_W_K)]:
            if not np.isfinite(v) or v < 0:
                raise ValueError(f"{name}: must be a finite number >= 0, got {v}")
        for k, e in self.emissivity.items():
            if not 0.0 <= e <= 1.0:
                raise ValueError(f"emissivity[{k}]: must lie in [0, 1], got {e}")

    def with_fits(self, fit_conductance_W_m2K) -> "ThermalParameters":
        """The same coefficients with new fit conductances (W/(m^2 K), one per fit)."""
        from dataclasses import replace
        return replace(self, fit_conductance_W_m2K=tuple(float(v) for v in fit_conductance_W_m2K))


@dataclass(frozen=True)
class StepLoads:
    """What drives one step (values at the end of the step). T_ambient_C: the fluid temperature
    of every film; T_sink_C: the radiation sink (None: T_ambient_C); heat_W: face group or ball
    node ("ball_A", "ball_B") -> heat input (W); T_fixed_C: fixed face group -> temperature;
    source_W: a load vector (W per DOF, (n_total,)) added as it is, e.g. a volume source field
    assembled with `fem.forms.volume_source` (its total is counted as heat in)."""
    T_ambient_C: float = 20.0
    T_sink_C: float | None = None
    heat_W: dict = field(default_factory=dict)
    T_fixed_C: dict = field(default_factory=dict)
    source_W: np.ndarray | None = None

    @property
    def sink_C(self) -> float:
        return self.T_ambient_C if self.T_sink_C is None else self.T_sink_C


@dataclass(frozen=True)
class StepBalance:
    """Energy rates of one step (W), each in the scheme's own quadrature: heat_in (sources),
    fixed_in (through fixed-temperature faces), stored (capacity x discrete dT/dt), convected and
    radiated (out). heat_in + fixed_in = stored + convected + radiated to round-off."""
    heat_in_W: float
    fixed_in_W: float
    stored_W: float
    convected_W: float
    radiated_W: float

    @property
    def residual_W(self) -> float:
        return self.heat_in_W + self.fixed_in_W - self.stored_W - self.convected_W - self.radiated_W

    @property
    def scale_W(self) -> float:
        return max(abs(self.heat_in_W), abs(self.fixed_in_W), abs(self.stored_W),
                   abs(self.convected_W), abs(self.radiated_W))


# ------------------------------------------------------------------------ the assembled model
class TransientConduction:
    """Assembled transient conduction of a `StackModel`: capacity M, conduction K and one matrix
    (or vector) per affine coefficient; the elimination of ties and fixed groups. Temperatures are
    vectors of all P2 DOFs followed by the ball nodes (`n_total`).

    ball_capacity_J_K: capacity of each bearing's ball set (a node per bearing "A", "B" whose
    raceways the section has), None: no ball nodes. fixed_groups: face groups with prescribed
    temperature. perfect_contact: tie the radial interfaces too (no contact conductance)."""

    def __init__(self, model: StackModel, ball_capacity_J_K: float | None = None,
                 fixed_groups: tuple[str, ...] = (), perfect_contact: bool = False):
        self.model = model
        b = model.sbasis
        self.N = b.N
        nq = b.X.shape[1]
        mats = model.materials
        k = np.array([mats[p].conductivity_W_mK for p in model.part_of]) / 1000.0
        rc = np.array([mats[p].density_kg_m3 * mats[p].specific_heat_J_kgK
                       for p in model.part_of]) * 1e-9
        self.groups = face_groups(model)
        lines = boundary_lines(model.section)
        self.bearings = tuple(j for j in "AB" if f"raceway_inner_ring_{j}" in lines
                              and f"raceway_outer_ring_{j}" in lines)
        self.ball_nodes = ball_capacity_J_K is not None
        nb = len(self.bearings) if self.ball_nodes else 0
        self.n_total = self.N + nb
        self.node_names = tuple(f"ball_{j}" for j in self.bearings) if self.ball_nodes else ()
        pad = lambda A: sp.block_diag([A, sp.csr_matrix((nb, nb))]).tocsr() if nb else A.tocsr()
        self.K = pad(asm(conduction, b, k=np.repeat(k[:, None], nq, 1)))
        M = asm(heat_capacity, b, rho_c=np.repeat(rc[:, None], nq, 1))
        self.M = (sp.block_diag([M, sp.diags(np.full(nb, float(ball_capacity_J_K or 0.0)))]).tocsr()
                  if nb else M.tocsr())
        # face groups: film / radiation matrix with unit coefficient, load of unit T, unit heat
        self.F, self.b, self.a = {}, {}, {}
        for name, facets in self.groups.items():
            fb = FacetBasis(model.mesh, b.elem, facets=facets)
            self.F[name] = pad(asm(convection, fb, h=1.0))
            v = np.concatenate([asm(boundary_flux, fb, q=1.0), np.zeros(nb)])
            self.b[name] = v
            self.a[name] = v / v.sum()
        for i, name in enumerate(self.node_names):
            e = np.zeros(self.n_total)
            e[self.N + i] = 1.0
            self.a[name] = e
        self.area_mm2 = {name: float(v.sum()) for name, v in self.b.items()}
        # ball links: (e_ball - a_race)(e_ball - a_race)^T per unit conductance
        self.ball_inner, self.ball_outer = self._ball_links()
        # radial interfaces: one matrix per fit and one for the other bore lines
        self.C_fit, self.C_bore = self._interfaces()
        self._part_rows: np.ndarray | None = None
        self.fixed_groups = tuple(fixed_groups)
        self.perfect_contact = bool(perfect_contact)
        self._eliminate(perfect_contact)

    # --- assembly helpers -------------------------------------------------------------------
    def _race_mean(self, name: str) -> np.ndarray:
        return self.a[f"raceway_{name}"]

    def _ball_links(self) -> tuple[list[sp.csr_matrix], list[sp.csr_matrix]]:
        inner, outer = [], []
        for i, j in enumerate(self.bearings):
            ai, ao = self._race_mean(f"inner_ring_{j}"), self._race_mean(f"outer_ring_{j}")
            if self.ball_nodes:
                e = np.zeros(self.n_total)
                e[self.N + i] = 1.0
                di, do = e - ai, e - ao
            else:           # a direct link raceway to raceway (the series conductance is applied)
                di, do = ai - ao, ai - ao
            di, do = sp.csr_matrix(di[None, :]), sp.csr_matrix(do[None, :])
            inner.append((di.T @ di).tocsr())
            outer.append((do.T @ do).tocsr())
        return inner, outer

    def _interfaces(self):
        """Per fit and for the other radial split lines: sum over the outer member's facets of
        int (T_out - T_in)(v_out - v_in) 2 pi r ds, as E^T M_line E with (E T)_s = T_s - T_m(s)."""
        m, b = self.model, self.model.sbasis
        mesh, x = m.mesh, b.doflocs
        bf = mesh.boundary_facets()
        part_of_facet = m.part_of[mesh.f2t[0]]
        fits = m.section.fits
        n = self.n_total
        C_fit = [sp.csr_matrix((n, n)) for _ in fits]
        C_bore = sp.csr_matrix((n, n))
        for s in m.section.splits:
            if s.axis != "r":
                continue
            ma, sl = node_pairs_on(x, nodes_on_line(x, s), b.element_dofs, m.part_of,
                                   s.inner_parts, s.outer_parts)
            partner = np.full(self.N, -1)
            partner[sl] = ma
            on = np.zeros(mesh.p.shape[1], bool)
            on[nodes_on_line(mesh.p, s)] = True
            f_line = bf[on[mesh.facets[0, bf]] & on[mesh.facets[1, bf]]
                        & np.isin(part_of_facet[bf], s.outer_parts)]
            if f_line.size == 0:
                continue
            zmid = mesh.p[1, mesh.facets[:, f_line]].mean(axis=0)
            owner = np.full(f_line.size, -1)
            for k, f in enumerate(fits):
                if abs(f.r_mm - s.at_mm) < TOL_MM * (1 + f.r_mm):
                    owner[(zmid > f.z0_mm) & (zmid < f.z1_mm)] = k
            E = sp.csr_matrix((np.concatenate([np.ones(sl.size), -np.ones(sl.size)]),
                               (np.concatenate([sl, sl]), np.concatenate([sl, ma]))),
                              shape=(n, n))
            for k in range(-1, len(fits)):
                sel = f_line[owner == k]
                if sel.size == 0:
                    continue
                fb = FacetBasis(mesh, b.elem, facets=sel)
                L = asm(convection, fb, h=1.0).tocsr()
                # the element DOFs off the facet give round-off entries only: drop them
                L = L.multiply(abs(L) > 1e-12 * abs(L).max()).tocsr()
                used = np.unique(L.nonzero()[0])
                if np.any(partner[used] < 0):
                    raise RuntimeError(f"split '{s.name}': interface nodes without a partner "
                                       "(non-conforming interface)")
                L = sp.block_diag([L, sp.csr_matrix((n - self.N, n - self.N))]).tocsr() \
                    if n > self.N else L.tocsr()
                C = (E.T @ L @ E).tocsr()
                if k < 0:
                    C_bore = C_bore + C
                else:
                    C_fit[k] = C_fit[k] + C
        return C_fit, C_bore

    def _eliminate(self, perfect_contact: bool) -> None:
        """T = P q + D tau: tied DOFs follow their representative, fixed groups take tau."""
        m, b = self.model, self.model.sbasis
        x = b.doflocs
        ms, ss = [], []
        for s in m.section.splits:
            if s.axis == "z" or perfect_contact:
                a, c = node_pairs_on(x, nodes_on_line(x, s), b.element_dofs, m.part_of,
                                     s.inner_parts, s.outer_parts)
                ms.append(a)
                ss.append(c)
        n = self.n_total
        masters = np.concatenate(ms) if ms else np.zeros(0, int)
        slaves = np.concatenate(ss) if ss else np.zeros(0, int)
        fixed = np.zeros(n, bool)
        group_of = np.full(n, -1)
        for gi, name in enumerate(self.fixed_groups):
            if name not in self.groups:
                raise ValueError(f"unknown face group '{name}' (known: {', '.join(self.groups)})")
            dofs = self._facet_dofs(self.groups[name])
            fixed[dofs] = True
            group_of[dofs] = gi
        sl, rep = _tie_representatives(n, masters, slaves, fixed)
        to = np.arange(n)
        to[sl] = rep
        self.tie_to = to
        free = np.flatnonzero((to == np.arange(n)) & ~fixed)
        red = np.full(n, -1)
        red[free] = np.arange(free.size)
        rows = np.flatnonzero(red[to] >= 0)
        self.P = sp.csr_matrix((np.ones(rows.size), (rows, red[to[rows]])), shape=(n, free.size))
        fixed_rows = np.flatnonzero(fixed[to])
        self.D = sp.csr_matrix((np.ones(fixed_rows.size), (fixed_rows, group_of[to[fixed_rows]])),
                               shape=(n, len(self.fixed_groups)))
        self.n_free = free.size

    def _facet_dofs(self, facets: np.ndarray) -> np.ndarray:
        """The P2 DOFs on the given facets (vertices and mid-sides)."""
        return np.unique(self.model.sbasis.get_dofs(facets).flatten())

    # --- the affine operator ----------------------------------------------------------------
    def operator(self, prm: ThermalParameters) -> sp.csr_matrix:
        """A(prm) = K + sum_g h_g F_g + sum_f h_f C_f + h_bore C_bore + ball links
        + sum_g eps_g h_r F_g (W/K), the implicit part of radiation included."""
        A = self.K.copy()
        for name, h in prm.film_W_m2K.items():
            A = A + (h * PER_M2_TO_PER_MM2) * self._F(name)
        hf = np.asarray(prm.fit_conductance_W_m2K, float)
        if hf.size != len(self.C_fit):
            raise ValueError(f"fit_conductance_W_m2K: {hf.size} values for {len(self.C_fit)} fits")
        if not self.perfect_contact:        # tied radial lines: the terms vanish
            for h, C in zip(hf, self.C_fit):
                A = A + (h * PER_M2_TO_PER_MM2) * C
            A = A + (prm.bore_conductance_W_m2K * PER_M2_TO_PER_MM2) * self.C_bore
        A = A + self._ball_part(prm)
        h_r = radiation_h_W_mm2K(prm.T_rad_lin_C)
        for name, eps in prm.emissivity.items():
            A = A + (eps * h_r) * self._F(name)
        return A.tocsr()

    def _ball_part(self, prm: ThermalParameters):
        n = self.n_total
        out = sp.csr_matrix((n, n))
        if not self.bearings:
            return out
        if self.ball_nodes:
            for Ci, Co in zip(self.ball_inner, self.ball_outer):
                out = out + prm.ball_inner_W_K * Ci + prm.ball_outer_W_K * Co
        else:
            gi, go = prm.ball_inner_W_K, prm.ball_outer_W_K
            G = gi * go / (gi + go) if gi > 0 and go > 0 else 0.0
            for Ci in self.ball_inner:
                out = out + G * Ci
        return out

    def _F(self, name: str) -> sp.csr_matrix:
        if name not in self.F:
            raise ValueError(f"unknown face group '{name}' (known: {', '.join(self.F)})")
        return self.F[name]

    def load(self, prm: ThermalParameters, loads: StepLoads) -> np.ndarray:
        """The linear part of the load (W): films to T_ambient, heat inputs, the linearised
        radiation's sink term h_r T_sink (the remainder is added by the stepper)."""
        f = np.zeros(self.n_total)
        for name, h in prm.film_W_m2K.items():
            self._F(name)
            f += (h * PER_M2_TO_PER_MM2 * loads.T_ambient_C) * self.b[name]
        for name, Q in loads.heat_W.items():
            if name not in self.a:
                raise ValueError(f"unknown heat input '{name}' (known: {', '.join(self.a)})")
            f += Q * self.a[name]
        if loads.source_W is not None:
            f += loads.source_W
        h_r = radiation_h_W_mm2K(prm.T_rad_lin_C)
        for name, eps in prm.emissivity.items():
            f += (eps * h_r * loads.sink_C) * self.b[name]
        return f

    def fixed_values(self, loads: StepLoads) -> np.ndarray:
        missing = [g for g in self.fixed_groups if g not in loads.T_fixed_C]
        if missing:
            raise ValueError(f"no temperature given for fixed face group '{missing[0]}'")
        return np.array([float(loads.T_fixed_C[g]) for g in self.fixed_groups])

    def radiation_mass(self, prm: ThermalParameters) -> sp.csr_matrix:
        """sum_g eps_g F_g: the face mass that carries the nodal radiation remainder (mm^2)."""
        R = sp.csr_matrix((self.n_total, self.n_total))
        for name, eps in prm.emissivity.items():
            R = R + eps * self._F(name)
        return R.tocsr()

    # --- reading results --------------------------------------------------------------------
    def mean_C(self, T: np.ndarray, group: str) -> float:
        """Area-weighted mean temperature (C) of a face group, or a ball node's temperature."""
        return float(self.a[group] @ T)

    def part_mean_C(self, T: np.ndarray) -> dict[str, float]:
        """Volume (ring-measure) mean temperature per part (C)."""
        v = self.part_mean_rows() @ T
        return {p: float(x) for p, x in zip(self.model.part_names, v)}

    def part_mean_rows(self) -> np.ndarray:
        """(n_parts, n_total): row p . T = the volume mean of T over part p (ring measure
        2 pi r dA), in `model.part_names` order (cached)."""
        if self._part_rows is None:
            b = self.model.sbasis
            w = b.dx * _r(b)
            rows = np.zeros((len(self.model.part_names), self.n_total))
            for i, p in enumerate(self.model.part_names):
                sel = self.model.part_of == p
                rows[i, :self.N] = element_average(b, sel, w[sel] / w[sel].sum())
            self._part_rows = rows
        return self._part_rows

    def theta_field(self, T: np.ndarray, T_ref_C: float) -> np.ndarray:
        """Thermal strain at the quadrature points (nel, nq) of temperatures T, per material."""
        m = self.model
        Tq = np.asarray(m.sbasis.interpolate(T[:self.N]))
        out = np.empty_like(Tq)
        for p in m.part_names:
            sel = m.part_of == p
            out[sel] = m.materials[p].thermal_strain(Tq[sel], T_ref_C)
        return out


def element_average(b, sel: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Row vector a with a . T = sum over the selected elements and their quadrature points of
    w x T(x_q) (w (n_sel, nq) weights) for nodal values T of the scalar basis b."""
    phi = np.array([np.asarray(b.basis[i][0]) for i in range(len(b.basis))])   # (nloc, nel, nq)
    vals = (phi[:, sel, :] * w[None, :, :]).sum(axis=2)                       # (nloc, n_sel)
    out = np.zeros(b.N)
    np.add.at(out, b.element_dofs[:, sel].ravel(), vals.ravel())
    return out


def _r(b) -> np.ndarray:
    return b.mapping.F(b.quadrature[0])[0]


def radiation_h_W_mm2K(T_lin_C: float) -> float:
    """Linearised radiation coefficient per unit emissivity, 4 sigma T_K^3 (W/(mm^2 K)) at T_lin
    (Incropera eq. 1.9: h_r = eps sigma (T + T_s)(T^2 + T_s^2) -> 4 eps sigma T^3 for T_s -> T)."""
    return 4.0 * SIGMA_W_MM2_K4 * (T_lin_C + KELVIN) ** 3


def radiation_remainder_W_mm2(T_C: np.ndarray, T_sink_C: float, T_lin_C: float) -> np.ndarray:
    """sigma (T_K^4 - T_sink,K^4) - h_r (T - T_sink) per unit emissivity (W/mm^2): the part of the
    radiated flux not in the implicit linear term."""
    return (SIGMA_W_MM2_K4 * ((T_C + KELVIN) ** 4 - (T_sink_C + KELVIN) ** 4)
            - radiation_h_W_mm2K(T_lin_C) * (T_C - T_sink_C))


# ------------------------------------------------------------------------ time stepping
#: (c0, c1, c2) of dT/dt ~ c0 T^(n+1) - c1 T^n - c2 T^(n-1), per unit 1/dt
SCHEMES = {"backward_euler": (1.0, 1.0, 0.0), "bdf2": (1.5, 2.0, -0.5)}
ORDER = {"backward_euler": 1, "bdf2": 2}


class Stepper:
    """Fixed-step time integration of a `TransientConduction` (see the module docstring).

    T0: initial temperatures (scalar or (n_total,)); prm: the coefficients (change them with
    `set_parameters`: the matrix is factorised again only then); dt_s: step (s); scheme:
    "backward_euler" or "bdf2". `step(loads)` advances one step and returns the temperatures
    (C, (n_total,)); `balance` holds the last step's `StepBalance`."""

    def __init__(self, tc: TransientConduction, prm: ThermalParameters, dt_s: float, T0,
                 scheme: str = "bdf2"):
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got '{scheme}'")
        if not dt_s > 0:
            raise ValueError(f"dt_s must be > 0, got {dt_s}")
        self.tc, self.dt, self.scheme = tc, float(dt_s), scheme
        self.T = np.broadcast_to(np.asarray(T0, float), (tc.n_total,)).copy()
        self.T_prev: np.ndarray | None = None
        self.n_steps = 0
        self.n_factorisations = 0
        self._lu: dict[float, object] = {}
        self.set_parameters(prm)
        self.balance: StepBalance | None = None

    def set_parameters(self, prm: ThermalParameters) -> None:
        self.prm = prm
        self.A = self.tc.operator(prm)
        self.R = self.tc.radiation_mass(prm)
        self._radiating = bool(prm.emissivity)
        self._lu = {}

    def _factor(self, c0: float):
        if c0 not in self._lu:
            P = self.tc.P
            S = (P.T @ ((c0 / self.dt) * self.tc.M + self.A) @ P).tocsc()
            self._lu[c0] = splu(S)
            self.n_factorisations += 1
        return self._lu[c0]

    def step(self, loads: StepLoads) -> np.ndarray:
        tc, dt = self.tc, self.dt
        scheme = self.scheme if self.T_prev is not None else "backward_euler"
        c0, c1, c2 = SCHEMES[scheme]
        Tn = self.T
        Tm = self.T_prev if self.T_prev is not None else Tn
        hist = (c1 * Tn + c2 * Tm) / dt
        f = tc.load(self.prm, loads)
        if self._radiating:          # extrapolated remainder: order 1 (BE) or 2 (BDF2)
            T_ex = Tn if scheme == "backward_euler" else 2.0 * Tn - Tm
            rem = radiation_remainder_W_mm2(T_ex, loads.sink_C, self.prm.T_rad_lin_C)
            f = f - self.R @ rem
        else:
            rem = None
        g = tc.D @ tc.fixed_values(loads) if tc.fixed_groups else np.zeros(tc.n_total)
        Ac = (c0 / dt) * tc.M + self.A
        rhs = tc.M @ hist + f - Ac @ g
        q = self._factor(c0).solve(tc.P.T @ rhs)
        T_new = tc.P @ q + g
        self.balance = self._balance(T_new, Tn, Tm, c0, c1, c2, loads, rem)
        self.T_prev, self.T = Tn, T_new
        self.n_steps += 1
        return T_new

    def _balance(self, T, Tn, Tm, c0, c1, c2, loads, rem) -> StepBalance:
        tc, prm = self.tc, self.prm
        stored = float(np.sum(tc.M @ (c0 * T - c1 * Tn - c2 * Tm)) / self.dt)
        conv = sum(h * PER_M2_TO_PER_MM2 * float(tc.b[name] @ T - tc.b[name].sum() * loads.T_ambient_C)
                   for name, h in prm.film_W_m2K.items())
        rad = 0.0
        if rem is not None:
            h_r = radiation_h_W_mm2K(prm.T_rad_lin_C)
            rad = sum(eps * h_r * float(tc.b[name] @ T - tc.b[name].sum() * loads.sink_C)
                      for name, eps in prm.emissivity.items()) + float(np.sum(self.R @ rem))
        heat = float(sum(loads.heat_W.values()))
        if loads.source_W is not None:
            heat += float(np.sum(loads.source_W))
        fixed_in = 0.0
        if tc.fixed_groups:
            r = tc.M @ (c0 * T - c1 * Tn - c2 * Tm) / self.dt + self.A @ T - tc.load(prm, loads)
            if rem is not None:
                r = r + self.R @ rem
            fixed_in = float(r.sum())      # P^T r = 0: the free rows sum to zero
        return StepBalance(heat, fixed_in, stored, conv, rad)


# ------------------------------------------------------------------------ heat from the bearing
def bearing_heat_inputs_W(heat, row: int = 0, ring_share=0.5, share_A: float = 0.5,
                          bearings: tuple[str, ...] = ("A", "B"), ball_nodes: bool = True
                          ) -> dict[str, float]:
    """Heat inputs (W) of one step from the torque model's heat split of the pair
    (`analytic.heat.PairHeat`, row `row`: everything generated at the inner and at the outer
    contacts, sliding + spin + half the viscous loss each), for `StepLoads.heat_W`.

    Each contact's heat is split between the ring (ring_share, spread uniformly over its raceway
    face group) and the ball (the rest, into the bearing's ball node), equally by default
    (Burton & Staph 1967, as seed 003 and `analytic.thermal_network.bearing_heat_W` take it);
    ring_share may be a pair (inner contacts, outer contacts), e.g. the partitions of
    `analytic.heat.rolling_contact_conductance`;
    without ball nodes the balls' share goes to the same ring's raceway (the ball passes it on
    within a revolution). The pair's heat is split between the bearings by share_A (default
    equal: a back-to-back or face-to-face pair under pure preload loads both alike; the torque
    model sums the two). Updated every step from the current contact state by the caller
    (`analytic.heat.pair_heat_W`). Heat made at the balls themselves (`PairHeat.drag_W`, the SKF
    drag; 0 otherwise) goes to the ball nodes, or without them half to each raceway.
    Keys: raceway_<inner|outer>_ring_<j>, ball_<j>."""
    s_in, s_out = (ring_share, ring_share) if np.ndim(ring_share) == 0 else ring_share
    if not (0.0 <= s_in <= 1.0 and 0.0 <= s_out <= 1.0 and 0.0 <= share_A <= 1.0):
        raise ValueError(f"ring_share and share_A must lie in [0, 1], got {ring_share}, {share_A}")
    q_in = float(np.atleast_1d(heat.inner_W)[row])
    q_out = float(np.atleast_1d(heat.outer_W)[row])
    drag = getattr(heat, "drag_W", 0.0)
    q_ball = float(np.atleast_1d(drag)[row]) if np.ndim(drag) else float(drag)
    share = {"A": share_A, "B": 1.0 - share_A}
    out: dict[str, float] = {}
    for j in bearings:
        s = share[j] if len(bearings) == 2 else 1.0
        ball = ((1.0 - s_in) * q_in + (1.0 - s_out) * q_out) * s + q_ball * s
        r_in, r_out = (s_in, s_out) if ball_nodes else (1.0, 1.0)
        d_ring = 0.0 if ball_nodes else 0.5 * q_ball * s
        out[f"raceway_inner_ring_{j}"] = r_in * q_in * s + d_ring
        out[f"raceway_outer_ring_{j}"] = r_out * q_out * s + d_ring
        if ball_nodes:
            out[f"ball_{j}"] = ball
    return out
