"""The FE -> analytic pipeline: conditions -> part temperatures and fits -> FE (fit pressures,
groove-centre shifts) -> bearing pair (preload, contact angle, Hertz) -> friction torque.

The FE runs through `fem.solver.Superposition`: unit solutions per part thermal strain, for the
centrifugal load of the rotor (shaft, inner rings, inner spacer, nut) at the row's `speed_rpm`
(scaled by omega^2; the assembly state is at rest) and per fit,
combined exactly for every row (the contact active set is solved per row on the condensed
interface), so a sweep costs little per point. `direct=True` solves every row with a full FE solve
instead; tests hold the two equal.

Where an FE result feeds the bearing model, the closed-form value is carried beside it:
`fit_pressure_inner_lame_MPa` and `..._lame_plane_strain_MPa` (two-cylinder Lamé, shaft and inner
ring only: the two 2-D idealisations; the FE of a short ring tied to its neighbours need not lie
between them, seed 000's inner fit is 5 % above the plane-strain value) and
`raceway_u_r_inner_A_lame_um` (Lamé ring expansion + free thermal growth).
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace

import numpy as np

from analytic import lame
from analytic.bearing import SIGNS, BearingGeometry, PairState, solve_pair
from analytic.bearing.land import groove_centre_radius_mm, land_diameters_mm, land_margin_deg
from analytic.lubrication import get_lubricant
from analytic.materials import get_material
from analytic.safety import static_load_rating_C0_N, static_safety_from_contact_pressure
from analytic.torque import palmgren_f1_angular_contact, pair_torque
from fem.post import circle_centre_weights, groove_centre_shift, mean_pressures_MPa
from fem.setup import (CompliancePlan, FESetup, FullFE, SetupSpec, cached_setup, compute_setup,
                       full_fe)
from fem.solver import Superposition
from studies.model.stack import ROTOR_PARTS, section_from_assembly, stack_positions
from studies.model.config import Assembly
from studies.model.effects import resolve_friction_coefficient, resolve_interference_um
from studies.model.inputs import NO_CTE_SLOPE, PhysicsInputs
from studies.model.memo import Memo, inputs_key

#: which temperature of `PhysicsInputs.T_C` each FE part takes
FE_PART_GROUP = {"shaft": "shaft", "nut": "shaft", "inner_ring_A": "inner_ring",
                 "inner_ring_B": "inner_ring", "inner_spacer": "spacer", "outer_spacer": "spacer",
                 "outer_ring_A": "outer_ring", "outer_ring_B": "outer_ring", "housing": "housing",
                 "cover": "housing", "sleeve": "housing", "cartridge": "housing"}
RINGS = ("inner_ring_A", "inner_ring_B", "outer_ring_A", "outer_ring_B")
#: fit-loosening speeds are searched up to here (rpm); a fit still closed there reports inf
SPEED_SEARCH_MAX_RPM = 1e6

class ModelError(ValueError):
    """The model cannot give a finite answer for these inputs (one line: row and output)."""


#: outputs that must be finite in every row (the interferences of a conduction-field state are
#: not defined and are NaN by design)
CHECKED_OUTPUTS = ("torque_Nmm", "preload_N", "contact_angle_deg", "fit_pressure_inner_MPa",
                   "fit_pressure_outer_MPa", "max_contact_pressure_MPa")


def check_answers(out: dict[str, np.ndarray], converged: np.ndarray, first_row: int = 0) -> None:
    """Raise ModelError naming the first row (1-based, as in the conditions table; the arrays
    start at 0-based row `first_row` of it) whose bearing equilibrium did not converge or whose
    output is not finite; never a silent NaN."""
    bad = ~np.asarray(converged, bool)
    if bad.any():
        i = int(np.flatnonzero(bad)[0]) + first_row
        raise ModelError(f"row {i + 1}: the bearing equilibrium did not converge "
                         f"({int(bad.sum())} row(s)); check the loads and fits of that row")
    for k in CHECKED_OUTPUTS:
        v = np.asarray(out[k], float)
        if not np.all(np.isfinite(v)):
            i = int(np.flatnonzero(~np.isfinite(v))[0])
            raise ModelError(f"row {i + first_row + 1}: {k} is not finite ({v[i]}); the model "
                             "has no answer for these inputs")


@dataclass
class FEState:
    """Per-row FE results (arrays of length n)."""
    fit_pressure_MPa: np.ndarray        # (n, n_fits) mean pressure per fit
    interference_um: np.ndarray         # (n, 2) free diametral overlap at temperature: inner, outer
    dr_mm: np.ndarray                   # (2, n) inner minus outer groove-centre radial shift, A/B
    dz_mm: np.ndarray                   # (2, n) axial
    raceway_u_mm: np.ndarray            # (n, 8) u_r, u_z at the raceway points of RINGS

    def with_shifts(self, dr_mm: np.ndarray | None = None, dz_mm: np.ndarray | None = None) -> "FEState":
        """The same state with the radial and/or axial groove-centre shifts replaced (studies
        split the preload change into its radial and axial causes this way)."""
        return replace(self, dr_mm=self.dr_mm if dr_mm is None else dr_mm,
                       dz_mm=self.dz_mm if dz_mm is None else dz_mm)

    def take(self, rows: np.ndarray) -> "FEState":
        """The states of the given rows (an index array; rows may repeat): with
        `PhysicsInputs.take`, the same FE answers evaluated under several bearing or torque
        settings in one `Pipeline.run_from_fe` call."""
        rows = np.asarray(rows, int)
        return FEState(self.fit_pressure_MPa[rows], self.interference_um[rows],
                       self.dr_mm[:, rows], self.dz_mm[:, rows], self.raceway_u_mm[rows])


@dataclass(frozen=True)
class RowField:
    """The full FE answer of one row's state (field images, fit distributions, stresses)."""
    u_mm: np.ndarray            # displacement vector, every DOF of `Pipeline.model`, mm
    force_N: np.ndarray         # contact force per interface pair (N, + compression)
    theta: np.ndarray           # thermal strain per FE part (`model.part_names` order)


class Pipeline:
    """One assembly: FE set-up, unit solutions and bearing geometry, built once.

    The superposition's arrays and the preload-path compliance come from `fem.setup`: from the
    on-disk cache when this stack was set up before (`cache=False`: always computed;
    `setup_of(spec)`: from elsewhere, e.g. `fem.parametric` for a design search's family). The full
    FE model (`model`, `solver`, `probe`: mesh, assembly, factorisations) is built only when
    something needs it: a set-up not cached yet, `direct` solves, whole fields."""

    #: pipelines built in this process, by (assembly, mesh factor): a few, oldest dropped first
    _shared: dict = {}
    SHARED_MAX = 4

    @classmethod
    def shared(cls, asm: Assembly, mesh_factor: float = 1.0, progress=None) -> "Pipeline":
        """The pipeline of this assembly, built once per process: commands run from Python
        (a notebook, the tests) after the first pay nothing for the FE set-up of the same
        assembly. Assemblies are frozen values, so equal files give the same key."""
        key = (asm, float(mesh_factor))
        hit = cls._shared.get(key)
        if hit is None:
            hit = cls(asm, mesh_factor=mesh_factor, progress=progress)
            if len(cls._shared) >= cls.SHARED_MAX:
                cls._shared.pop(next(iter(cls._shared)))
            cls._shared[key] = hit
        return hit

    def __init__(self, asm: Assembly, mesh_factor: float = 1.0, progress=None,
                 superpose: bool = True, cache: bool = True, setup_of=None):
        self._say = progress or (lambda s: None)
        self.asm = asm
        self.mesh_factor = float(mesh_factor)
        self.section = section_from_assembly(asm).scaled(mesh_factor)
        pts = np.array([self.section.raceway_points[r] for r in RINGS]).T
        if self.section.grooves:        # + the groove points whose circle fit gives each centre
            grooves = [self.section.groove_of(r) for r in RINGS]
            self.centre_weights = [circle_centre_weights(np.array(g.points_rz_mm).T, (g.r_mm, g.z_mm))
                                   for g in grooves]
            pts = np.hstack([pts] + [np.array(g.points_rz_mm).T for g in grooves])
        else:
            self.centre_weights = None
        plan = None
        if asm.preload.path_compliance == "fe":
            inner, outer = asm.mean_fits_um()
            delta = self.deltas_mm(np.array([inner]), np.array([outer]))[0]
            plan = CompliancePlan(tuple(float(v) for v in SIGNS[asm.arrangement]),
                                  tuple(float(v) for v in delta))
        rotor = tuple(p for p in ROTOR_PARTS if p in self.section.parts())
        mats = {p: get_material(self.section.material_of(p), asm.materials)
                for p in self.section.parts()}
        self.spec = SetupSpec.of(self.section, asm.fits.contact, pts, plan, materials=mats,
                                 rotating_parts=rotor)
        self.materials = dict(self.spec.materials)
        self._full: FullFE | None = None
        self.setup: FESetup = (setup_of(self.spec) if setup_of is not None   # fem.parametric
                               else cached_setup(self.spec, self.full_fe, progress=self._say) if cache
                               else compute_setup(self.spec, self.full_fe()))
        self.part_names = self.setup.part_names
        self.sup = (Superposition.from_condensed(self.setup.condensed, lambda: self.solver)
                    if superpose else None)
        self.geom = BearingGeometry.from_spec(asm.bearing, asm.materials)
        self.land_diameters_mm = land_diameters_mm(asm.bearing, asm.materials)[:2]
        # distance of the ball planes (inner ring mid-planes) of bearings A and B: the lever of
        # the rotor tilt under a moment or an off-centre radial load
        z = stack_positions(asm)
        self.bearing_span_mm = 0.5 * (sum(z["inner_ring_B"]) - sum(z["inner_ring_A"]))
        self._centre_offsets(pts[:, :4])
        self._fe_cache: dict[bytes, FEState] = {}
        self._pair_memo = Memo()        # pair equilibria by their exact inputs (run_from_fe)
        self.lubricant = get_lubricant(asm.lubrication.lubricant) if asm.lubrication.kind == "oil" else None
        self.compliance_mm_per_N = self.setup.compliance_mm_per_N if plan is not None else 0.0

    # ------------------------------------------------------------------ the full FE, on demand
    def full_fe(self) -> FullFE:
        """The full FE model of the section (mesh from its cache, assembly), built on first use."""
        if self._full is None:
            self._say(f"meshing and assembling the FE model of {self.asm.name} ...")
            self._full = full_fe(self.spec)
        return self._full

    @property
    def model(self):
        """The assembled `fem.model.StackModel` (built on first use)."""
        return self.full_fe().model

    @property
    def solver(self):
        """The `fem.solver.FitSolver` of the model (built on first use)."""
        return self.full_fe().solver

    @property
    def probe(self):
        """(8, ndofs) matrix: u_r, u_z at the raceway points of RINGS (built on first use)."""
        return self.full_fe().probe[:8]

    @property
    def ndofs(self) -> int:
        """Displacement DOFs of the FE model."""
        return self.setup.ndofs

    # ------------------------------------------------------------------ geometry
    def _centre_offsets(self, pts: np.ndarray) -> None:
        """Groove-centre position minus raceway point, per ring (r, z), mm.
        Inner centre: r = dm/2 + (f_i - 1/2) Dw cos a0, z = z_mid + s_j (f_i - 1/2) Dw sin a0;
        outer centre: r = dm/2 - (f_o - 1/2) Dw cos a0, z = z_mid - s_j (f_o - 1/2) Dw sin a0
        (Harris & Kotzalas Vol. 1 ch. 2: both centres on the contact line through the ball
        centre; s_j the arrangement sign of bearing j)."""
        g = self.geom
        a0 = np.radians(g.alpha0_deg)
        s = SIGNS[self.asm.arrangement]
        off = np.zeros((4, 2))
        for k, ring in enumerate(RINGS):
            j = 0 if ring.endswith("A") else 1
            inner = ring.startswith("inner")
            f = g.f_i if inner else g.f_o
            sgn = 1.0 if inner else -1.0
            rc = groove_centre_radius_mm(g, "inner" if inner else "outer")
            zc = pts[1, k] + sgn * s[j] * (f - 0.5) * g.Dw_mm * np.sin(a0)
            off[k] = (rc - pts[0, k], zc - pts[1, k])
        self.centre_offset_mm = off

    # ------------------------------------------------------------------ FE
    def thetas(self, inputs: PhysicsInputs) -> np.ndarray:
        """(n, n_parts) thermal strain per FE part; the cte_nonlinearity effect changes the CTE
        slope of the shaft (and nut) and housing (and cover)."""
        cols = []
        for part in self.part_names:
            group = FE_PART_GROUP[part]
            mat = self.materials[part]
            if group in inputs.dalpha_per_K2:          # shaft (and nut), housing (and cover)
                mat = mat.with_dalpha(inputs.dalpha_per_K2[group],
                                      inputs.d2alpha_per_K3.get(group, 0.0))
            cols.append(mat.thermal_strain(np.asarray(inputs.T_C[group], float), self.asm.T_ref_C))
        return np.column_stack(cols)

    @staticmethod
    def omega2(inputs: PhysicsInputs) -> np.ndarray:
        """(n,) square of the rotor speed, rad^2/s^2: omega = 2 pi speed_rpm / 60."""
        return (np.asarray(inputs.speed_rpm, float) * (2.0 * np.pi / 60.0)) ** 2

    def fits_um(self, inputs: PhysicsInputs) -> tuple[np.ndarray, np.ndarray]:
        return resolve_interference_um(inputs, *self.asm.mean_fits_um())

    def deltas_mm(self, inner_um: np.ndarray, outer_um: np.ndarray) -> np.ndarray:
        """(n, n_fits) radial interference (mm) per FE fit (a sleeve's or cartridge's fit: its
        `[fits]` value on every row)."""
        n = np.broadcast(inner_um, outer_um).shape
        um = {"inner": inner_um, "outer": outer_um,
              "sleeve": np.full(n, self.asm.fits.sleeve_interference_um),
              "cartridge": np.full(n, self.asm.fits.cartridge_interference_um)}
        return np.column_stack([um[f.key] / 2000.0 for f in self.section.fits])

    def fe(self, inputs: PhysicsInputs, direct: bool = False, remember: bool = True) -> FEState:
        """The FE answers of the rows (superposed, or direct solves). `remember`: keep the result
        for the next call with the same states (a table streamed in chunks does not)."""
        theta = self.thetas(inputs)
        inner_um, outer_um = self.fits_um(inputs)
        delta = self.deltas_mm(inner_um, outer_um)
        w2 = np.broadcast_to(self.omega2(inputs), (theta.shape[0],)).copy()
        # a diagnosis re-evaluates the same FE states many times (friction, viscosity and preload
        # effects leave the structure alone): keep the last few results by their exact inputs
        key = hashlib.sha1(theta.tobytes() + delta.tobytes() + w2.tobytes()
                           + bytes([direct])).digest()
        hit = self._fe_cache.get(key)
        if hit is not None:
            return hit
        state = self._fe_solve(theta, delta, inner_um, outer_um, direct, w2)
        if not remember:
            return state
        if len(self._fe_cache) >= 16:
            self._fe_cache.pop(next(iter(self._fe_cache)))
        self._fe_cache[key] = state
        return state

    def _fe_solve(self, theta, delta, inner_um, outer_um, direct, w2) -> FEState:
        n = theta.shape[0]
        if direct or self.sup is None:
            force, probe = [], []
            m = self.model
            for i in range(n):
                sol = self.solver.solve(m.unit_loads @ theta[i] + w2[i] * m.spin_load, delta[i])
                force.append(sol.force_N)
                probe.append(self.full_fe().probe @ sol.u)
            force, probe = np.array(force), np.array(probe)
        else:
            res = self.sup.evaluate(theta, delta, w2)
            force, probe = res["force_N"], res["probe"]
        p = self.fit_pressures(force)
        idx = {p: i for i, p in enumerate(self.part_names)}
        centre = self._centres(probe, theta[:, [idx[r] for r in RINGS]])
        dr = np.stack([centre[:, 0, 0] - centre[:, 2, 0], centre[:, 1, 0] - centre[:, 3, 0]])
        dz = np.stack([centre[:, 0, 1] - centre[:, 2, 1], centre[:, 1, 1] - centre[:, 3, 1]])
        a = self.asm
        d_seat, d_bore = a.shaft.seat_diameter_mm, a.outer_seat_diameter_mm
        seat = ([n for n, _ in a.layers()] + ["housing"])[0]     # what the outer rings sit in
        interf = np.column_stack([
            inner_um + (theta[:, idx["shaft"]] - theta[:, idx["inner_ring_A"]]) * d_seat * 1e3,
            outer_um + (theta[:, idx["outer_ring_A"]] - theta[:, idx[seat]]) * d_bore * 1e3])
        return FEState(p, interf, dr, dz, probe[:, :8])

    def _centres(self, probe: np.ndarray, theta_rings: np.ndarray) -> np.ndarray:
        """(n, 4, 2) groove-centre displacements (mm) of RINGS from the probed displacements
        (n, n_probe): grooved rings, the circle of the ring's thermally grown groove radius
        fitted to the displaced groove points (`fem.post.circle_centre_weights`); rectangular
        rings, the raceway point's displacement + the ring's thermal strain (n, 4) x the centre
        offset (`fem.post.groove_centre_shift`)."""
        n = probe.shape[0]
        centre = np.empty((n, 4, 2))
        m = 0 if self.centre_weights is None else self.centre_weights[0][0].shape[1]
        for k in range(4):
            if self.centre_weights is None:
                centre[:, k, :] = groove_centre_shift(probe[:, 2 * k:2 * k + 2], theta_rings[:, k],
                                                      self.centre_offset_mm[k])
            else:
                cols = slice(8 + k * m, 8 + (k + 1) * m)
                W, w_theta = self.centre_weights[k]
                centre[:, k, :] = probe[:, cols] @ W.T + theta_rings[:, k, None] * w_theta
        return centre

    def fit_open_speed_rpm(self, inputs: PhysicsInputs) -> dict[str, np.ndarray]:
        """The speed (rpm) at which each inner (rotating) fit opens, per row at the row's part
        temperatures and fits (`fem.loosening.fit_open_omega2` on the superposition): 0 when
        already open at rest, inf when still closed at SPEED_SEARCH_MAX_RPM. {FE fit name: (n,)}."""
        from fem.loosening import RPM2_TO_RAD2_S2, fit_open_omega2

        sup = self.sup if self.sup is not None else Superposition(self.solver, self.probe)
        theta = self.thetas(inputs)
        delta = self.deltas_mm(*self.fits_um(inputs))
        w2_max = SPEED_SEARCH_MAX_RPM ** 2 * RPM2_TO_RAD2_S2
        return {f.name: np.sqrt(fit_open_omega2(sup, theta, delta, k, w2_max) / RPM2_TO_RAD2_S2)
                for k, f in enumerate(self.section.fits) if f.key == "inner"}

    def fit_pressures(self, force_N: np.ndarray) -> np.ndarray:
        """(n, n_fits) mean pressure (MPa) per FE fit from the pair forces (n, n_pairs) in N."""
        st = self.setup
        return mean_pressures_MPa(force_N, st.condensed.fit_of_pair, st.fit_r_mm, st.fit_length_mm)

    def field(self, inputs: PhysicsInputs, row: int = 0) -> RowField:
        """Displacement field and contact forces of one row (superposed, or a direct solve when
        the pipeline was built without unit solutions)."""
        theta = self.thetas(inputs)[row]
        delta = self.deltas_mm(*self.fits_um(inputs))[row]
        w2 = float(np.broadcast_to(self.omega2(inputs), (inputs.n_rows,))[row])
        if self.sup is None:
            sol = self.solver.solve(self.model.unit_loads @ theta + w2 * self.model.spin_load, delta)
            return RowField(sol.u, sol.force_N, theta)
        force = self.sup.evaluate(theta[None, :], delta[None, :], np.array([w2]))["force_N"][0]
        return RowField(self.sup.field(theta, delta, w2), force, theta)

    def fe_field(self, theta_q: np.ndarray, inputs: PhysicsInputs):
        """One state with a non-uniform thermal strain field (nel, nq) from a conduction solution:
        a direct FE solve (not superposed). The groove-centre offsets take each ring's mean
        thermal strain. Returns (FEState, displacement vector)."""
        m = self.model
        inner_um, outer_um = self.fits_um(inputs)
        delta = self.deltas_mm(inner_um, outer_um)[0]
        w2 = float(np.atleast_1d(self.omega2(inputs))[0])
        sol = self.solver.solve(m.thermal_load_vector(theta_q) + w2 * m.spin_load, delta)
        probe = self.full_fe().probe @ sol.u
        p = self.fit_pressures(sol.force_N)
        w = m.basis.dx
        th = np.array([[float((theta_q[m.part_of == r] * w[m.part_of == r]).sum()
                              / w[m.part_of == r].sum()) for r in RINGS]])
        centre = self._centres(probe[None, :], th)[0]
        dr = np.array([[centre[0, 0] - centre[2, 0]], [centre[1, 0] - centre[3, 0]]])
        dz = np.array([[centre[0, 1] - centre[2, 1]], [centre[1, 1] - centre[3, 1]]])
        return FEState(p, np.full((1, 2), np.nan), dr, dz, probe[None, :8]), sol.u

    def lame_beside(self, fe: FEState, inputs: PhysicsInputs) -> dict[str, np.ndarray]:
        """Closed-form neighbours of the FE values (two-cylinder Lamé, plane stress; the inner fit
        spinning at the row's speed, `lame.rotating_fit_pressure_MPa`, which is the static Lamé
        value at rest)."""
        a, b = self.asm, self.asm.bearing
        ms, mr, mh = (self.materials[p] for p in ("shaft", "inner_ring_A", "housing"))
        inner = dict(r_inner_mm=a.shaft.bore_diameter_mm / 2, r_fit_mm=a.shaft.seat_diameter_mm / 2,
                     r_outer_mm=b.inner_ring_outer_diameter_mm / 2, E_inner_MPa=ms.E_MPa,
                     nu_inner=ms.nu, E_outer_MPa=mr.E_MPa, nu_outer=mr.nu)
        outer = dict(r_inner_mm=b.outer_ring_inner_diameter_mm / 2,
                     r_fit_mm=a.housing.bore_diameter_mm / 2,
                     r_outer_mm=a.housing.outer_diameter_mm / 2, E_inner_MPa=mr.E_MPa,
                     nu_inner=mr.nu, E_outer_MPa=mh.E_MPa, nu_outer=mh.nu)
        th_ring = mr.thermal_strain(np.asarray(inputs.T_C["inner_ring"], float), a.T_ref_C)
        r_race = b.inner_ring_outer_diameter_mm / 2
        spin = dict(rho_inner_N_s2_mm4=ms.density_N_s2_mm4, rho_outer_N_s2_mm4=mr.density_N_s2_mm4,
                    omega_rad_s=np.sqrt(self.omega2(inputs)))
        di, do = fe.interference_um[:, 0], fe.interference_um[:, 1]
        u_lame = lame.rotating_fit_displacement_mm(r_race, "outer", **inner, interference_um=di,
                                                   **spin) + th_ring * r_race
        if a.layers():      # ring / sleeve / cartridge / housing: the multi-layer Lamé solution
            p_out = {k: self._layers_lame_MPa(fe, inputs, k) for k in ("plane_stress", "plane_strain")}
        else:
            p_out = {k: np.atleast_1d(lame.fit_pressure_MPa(**outer, interference_um=do,
                                                            assumption=k))[:, None]
                     for k in ("plane_stress", "plane_strain")}
        return {"fit_pressure_inner_lame_MPa":
                    lame.rotating_fit_pressure_MPa(**inner, interference_um=di, **spin),
                "fit_pressure_inner_lame_plane_strain_MPa":
                    lame.rotating_fit_pressure_MPa(**inner, interference_um=di, **spin,
                                                   assumption="plane_strain"),
                "fit_pressure_outer_lame_MPa": p_out["plane_stress"][:, 0],
                "fit_pressure_outer_lame_plane_strain_MPa": p_out["plane_strain"][:, 0],
                **{f"fit_pressure_{n}_lame_MPa": p_out["plane_stress"][:, k + 1]
                   for k, (n, _) in enumerate(a.layers())},
                "raceway_u_r_inner_A_um": 1e3 * fe.raceway_u_mm[:, 0],
                "raceway_u_r_inner_A_lame_um": 1e3 * u_lame}

    def _layers_lame_MPa(self, fe: FEState, inputs: PhysicsInputs, assumption: str) -> np.ndarray:
        """(n, 1 + n_layers) interface pressures (MPa) of the concentric outer ring (effective
        section) / sleeve / cartridge / housing (`lame.multilayer_pressures_MPa`), at the rows'
        free interferences: the outer fit's `interference_um[:, 1]`, each layer's `[fits]` value
        plus its thermal mismatch with the part outside it (thermal strain x diameter)."""
        a, b = self.asm, self.asm.bearing
        parts = ["outer_ring_A"] + [n for n, _ in a.layers()] + ["housing"]
        radii = [b.outer_ring_inner_diameter_mm / 2, b.outside_diameter_mm / 2]
        for _, layer in a.layers():
            radii.append(radii[-1] + layer.radial_thickness_mm)
        radii.append(a.housing.outer_diameter_mm / 2)
        theta = self.thetas(inputs)
        idx = {p: i for i, p in enumerate(self.part_names)}
        d_um = [fe.interference_um[:, 1]]
        for k, (name, _) in enumerate(a.layers()):
            d_um.append(getattr(a.fits, f"{name}_interference_um")
                        + (theta[:, idx[name]] - theta[:, idx[parts[k + 2]]]) * 2 * radii[k + 2] * 1e3)
        mats = [self.materials[p] for p in parts]
        return lame.multilayer_pressures_MPa(radii, [m.E_MPa for m in mats], [m.nu for m in mats],
                                             np.column_stack(d_um), assumption)

    # ------------------------------------------------------------------ whole chain
    def reference_inputs(self, inputs: PhysicsInputs) -> PhysicsInputs:
        """The assembly state of every row: T_ref everywhere, at rest, the row's as-built fits."""
        T_ref = self.asm.T_ref_C
        return inputs.copy(T_C={k: np.full(inputs.n_rows, T_ref) for k in inputs.T_C},
                           dalpha_per_K2=dict(NO_CTE_SLOPE), d2alpha_per_K3=dict(NO_CTE_SLOPE),
                           speed_rpm=np.zeros(inputs.n_rows))

    def run(self, inputs: PhysicsInputs, direct: bool = False,
            compliance_mm_per_N=None, viscous_factor_f0=None,
            return_pair: bool = False, first_row: int = 0, remember: bool = True,
            ball_model: str | None = None):
        """All outputs per row (spec columns first, then the rest): the FE at the rows' states and
        at their assembly states (`fe`, which documents `remember`), then `run_from_fe` (which
        documents the other keyword arguments)."""
        fe = self.fe(inputs, direct, remember)
        fe_ref = self.fe(self.reference_inputs(inputs), direct, remember)
        return self.run_from_fe(inputs, fe, fe_ref, compliance_mm_per_N, viscous_factor_f0,
                                return_pair, first_row, ball_model, remember=remember)

    def run_from_fe(self, inputs: PhysicsInputs, fe: FEState, fe_ref: FEState,
                    compliance_mm_per_N=None, viscous_factor_f0=None,
                    return_pair: bool = False, first_row: int = 0,
                    ball_model: str | None = None, *, remember: bool = True):
        """Bearing pair, torque and checks from given FE states (the rows' and their assembly
        states). Studies use it to switch parts of the FE answer off (e.g. only the radial
        groove-centre shifts) or to feed a non-uniform temperature field (`fe_field`).

        compliance_mm_per_N: preload-path compliance per bearing (mm/N; scalar or one per row);
        default the assembly's (`[preload] path_compliance`); the inputs'
        `extra_compliance_mm_per_N` (the preload_path_compliance effect) is added in series
        (compliances of springs in series add). viscous_factor_f0: Palmgren's f0 in
        place of the assembly's (oil lubrication; scalar or one per row). With `return_pair`, also the raw
        pair state (`analytic.bearing.PairState`: contact ellipses for heat models). first_row:
        the 0-based row of the whole table the inputs start at (rows named in errors).
        ball_model: "static" or "quasi_dynamic" in place of the assembly's `[operating]
        ball_model` (the report sets both side by side; the FE does not depend on it).
        remember: keep the pair equilibrium for the next call with the same inputs (a table
        streamed in chunks does not)."""
        a = self.asm
        with np.errstate(all="ignore"):     # a row without an answer is reported below, by name
            # friction-only changes (a diagnosis's friction scale) leave the equilibrium alone:
            # the last few are reused by their exact inputs (`studies.model.memo`)
            args = self.pair_arguments(inputs, fe, fe_ref, compliance_mm_per_N, ball_model)
            key = inputs_key(args)
            pair = self._pair_memo.get(key)
            if pair is None:
                pair = solve_pair(self.geom, a.arrangement, **args)
                if remember:
                    self._pair_memo.put(key, pair, inputs.n_rows)
            mu = resolve_friction_coefficient(inputs, a.lubrication.friction_coefficient)
            torque = self.torque(pair, inputs, mu, viscous_factor_f0)
        names = list(self.setup.fit_names)
        nf = len(names)
        p_in = fe.fit_pressure_MPa[:, [k for k in range(nf) if names[k].startswith("fit_inner")]]
        p_out = fe.fit_pressure_MPa[:, [k for k in range(nf) if names[k].startswith("fit_outer")]]
        out = {"torque_Nmm": torque.pop("torque_Nmm"), "preload_N": pair.preload_N,
               "contact_angle_deg": _weighted_angle(pair),
               "interference_inner_um": fe.interference_um[:, 0],
               "interference_outer_um": fe.interference_um[:, 1],
               "fit_pressure_inner_MPa": p_in.mean(axis=1),
               "fit_pressure_outer_MPa": p_out.mean(axis=1),
               "max_contact_pressure_MPa": pair.max_contact_pressure_MPa}
        out.update(torque)
        for k, name in enumerate(names):
            out[f"{name.replace('fit_', 'fit_pressure_')}_MPa"] = fe.fit_pressure_MPa[:, k]
        out.update(self.lame_beside(fe, inputs))
        for j, J in enumerate("AB"):
            out[f"groove_shift_dr_{J}_um"] = 1e3 * fe.dr_mm[j]
            out[f"groove_shift_dz_{J}_um"] = 1e3 * fe.dz_mm[j]
        for j, J in enumerate("AB"):
            out[f"axial_force_{J}_N"] = pair.axial_force_N[j]
        for j, J in enumerate("AB"):
            out[f"contact_angle_{J}_deg"] = pair.contact_angle_deg[j]
        for j, J in enumerate("AB"):
            out[f"ball_load_{J}_N"] = pair.ball_load_N[j]
        out.update(_ball_outputs(pair))
        out["axial_stiffness_N_per_um"] = pair.pair_axial_stiffness_N_per_um
        out.update(_load_outputs(pair))
        for side, d_land, ell in (("inner", self.land_diameters_mm[0], pair.inner),
                                  ("outer", self.land_diameters_mm[1], pair.outer)):
            out[f"land_margin_{side}_deg"] = land_margin_deg(
                self.geom, side, d_land, pair.contact_angle_deg, ell.a_mm).min(axis=0)
        out["preload_lost"] = pair.preload_lost.astype(float)
        with np.errstate(divide="ignore"):      # an unloaded pair has infinite static safety
            out["static_safety"] = static_safety_from_contact_pressure(pair.max_contact_pressure_MPa)
        out["friction_coefficient"] = mu
        check_answers(out, pair.converged, first_row)
        return (out, pair) if return_pair else out

    def pair_arguments(self, inputs: PhysicsInputs, fe: FEState, fe_ref: FEState,
                       compliance_mm_per_N=None, ball_model: str | None = None) -> dict:
        """The keyword arguments of `analytic.bearing.solve_pair` for these rows (arguments as
        `run_from_fe`): what the pair's equilibrium, and its stiffness
        (`analytic.bearing.stiffness.pair_stiffness`), are evaluated with."""
        a = self.asm
        preload = np.maximum(np.asarray(inputs.preload_assembled_N, float)
                             - np.asarray(inputs.preload_loss_N, float), 0.0)
        return dict(dr_mm=fe.dr_mm, dz_mm=fe.dz_mm, T_inner_ring_C=inputs.T_C["inner_ring"],
                    T_outer_ring_C=inputs.T_C["outer_ring"], T_ball_C=inputs.T_C["ball"],
                    T_ref_C=a.T_ref_C, preload_kind=a.preload.kind,
                    preload_assembled_N=preload, axial_load_N=inputs.axial_load_N,
                    radial_load_N=_zeros_if_none(inputs.radial_load_N),
                    moment_Nmm=_zeros_if_none(inputs.moment_Nmm),
                    bearing_span_mm=self.bearing_span_mm,
                    speed_rpm=np.asarray(inputs.speed_rpm, float),
                    ball_model=a.operating.ball_model if ball_model is None else ball_model,
                    control=a.operating.raceway_control,
                    dr_ref_mm=fe_ref.dr_mm, dz_ref_mm=fe_ref.dz_mm,
                    compliance_mm_per_N=(self.compliance_mm_per_N if compliance_mm_per_N is None
                                         else compliance_mm_per_N)
                    + inputs.extra_compliance_mm_per_N)

    def torque(self, pair: PairState, inputs: PhysicsInputs, mu: np.ndarray,
               viscous_factor_f0=None) -> dict[str, np.ndarray]:
        """Friction torque of the pair (analytic/torque.py). Oil: viscosity of the configured
        lubricant (ASTM D341 fit of its datasheet points, slope scaled by the
        viscosity_temperature effect) at the mean of the ring and ball temperatures."""
        lub = self.asm.lubrication
        speed = np.asarray(inputs.speed_rpm, float)
        if lub.kind == "solid_film":
            return pair_torque(self.geom, pair, model="solid_film", mu=mu,
                               hysteresis_loss=lub.hysteresis_loss_factor, speed_rpm=speed)
        T_oil = (np.asarray(inputs.T_C["inner_ring"], float) + inputs.T_C["outer_ring"]
                 + inputs.T_C["ball"]) / 3.0
        nu = self.lubricant.nu_mm2_s(T_oil, slope_factor=inputs.viscosity_slope_factor)
        f1 = None
        if lub.load_term == "palmgren":
            # Palmgren's f1 = 0.001 (P0/C0)^0.33 with C0 from ISO 76 and P0 the axial force of the
            # more loaded bearing (a pure axial preload)
            g = self.geom
            C0 = static_load_rating_C0_N(g.Z, g.Dw_mm, g.dm_mm, g.alpha0_deg)
            P0 = pair.axial_force_N.max(axis=0)
            f1 = palmgren_f1_angular_contact(P0, C0)
        out = pair_torque(self.geom, pair, model="oil", mu=mu, speed_rpm=speed,
                          f0=lub.viscous_factor_f0 if viscous_factor_f0 is None else viscous_factor_f0,
                          nu_mm2_s=nu, load_term=lub.load_term, f1=f1)
        out["viscosity_mm2_s"] = nu
        return out


def _zeros_if_none(v):
    return 0.0 if v is None else v


def _load_outputs(pair: PairState) -> dict[str, np.ndarray]:
    """Columns of the pair under radial load and moment (`analytic.bearing.RadialLoadState`),
    present in every row: rotor radial displacement at the pair's mid-point (um) and tilt
    (mrad), each bearing's radial reaction (N) and its largest Hertz pressure over all balls
    (MPa).  Rows without radial load and moment: zero displacement, tilt and reactions, and the
    axial state's pressures (every ball alike)."""
    r = pair.radial
    if r is None:
        n = pair.preload_N.shape[0]
        z = np.zeros(n)
        rho, tilt, Fr = z, z, np.zeros((2, n))
        p = np.maximum(pair.inner.p_max_MPa, pair.outer.p_max_MPa)
    else:
        rho, tilt, Fr, p = r.rho_mm, r.tilt_rad, r.radial_force_N, r.max_contact_pressure_MPa
    out = {"radial_displacement_um": 1e3 * rho, "tilt_mrad": 1e3 * tilt}
    for j, J in enumerate("AB"):
        out[f"radial_force_{J}_N"] = Fr[j]
    for j, J in enumerate("AB"):
        out[f"max_contact_pressure_{J}_MPa"] = p[j]
    return out


def _ball_outputs(pair: PairState) -> dict[str, np.ndarray]:
    """Columns of the outer contact and of the ball's speed loads, present in every row:
    contact angle and load of the outer contact of each bearing (equal to the inner ones,
    `contact_angle_{J}_deg` and `ball_load_{J}_N`, with quasi-static balls), and the centrifugal
    force (N) and gyroscopic moment (N mm) on a ball of bearing A (0 with quasi-static balls)."""
    d = pair.dynamic
    if d is None:
        angle_o, load_o = pair.contact_angle_deg, pair.ball_load_N
        z = np.zeros(pair.preload_N.shape)
        fc, mg = z, z
    else:
        angle_o, load_o = d.contact_angle_outer_deg, d.load_outer_N
        fc, mg = d.centrifugal_force_N[0], d.gyroscopic_moment_Nmm[0]
    out = {f"contact_angle_outer_{J}_deg": angle_o[j] for j, J in enumerate("AB")}
    out.update({f"ball_load_outer_{J}_N": load_o[j] for j, J in enumerate("AB")})
    out["centrifugal_force_N"] = fc
    out["gyroscopic_moment_Nmm"] = mg
    return out


def _weighted_angle(pair: PairState) -> np.ndarray:
    """Contact angle of the pair (deg): the axial-force-weighted mean of bearings A and B (equal
    weights when both are unloaded). Continuous, unlike "the angle of the more loaded bearing",
    which jumps between two values when the forces are equal up to round-off."""
    FA, FB = pair.axial_force_N
    tot = FA + FB
    wA = np.where(tot > 0, FA / np.where(tot > 0, tot, 1.0), 0.5)
    return wA * pair.contact_angle_deg[0] + (1 - wA) * pair.contact_angle_deg[1]


def table_inputs(asm: Assembly, columns: dict, effects: dict | None = None) -> PhysicsInputs:
    """The physical inputs of a conditions table (column name -> array, names of docs/cli.md),
    effects switched on by name ({name: {parameter: value}})."""
    from studies.model.effects import apply_effects
    from studies.model.inputs import baseline_inputs

    n = len(next(iter(v for k, v in columns.items() if not k.startswith("_"))))
    inputs = baseline_inputs(columns, n, asm.T_ref_C, asm.preload.assembled_N,
                             asm.lubrication.speed_rpm)
    return apply_effects(inputs, effects, asm.T_ref_C)


def simulate_table(asm: Assembly, columns: dict, effects: dict | None = None,
                   direct: bool = False, pipeline: Pipeline | None = None) -> dict[str, np.ndarray]:
    """Model outputs for a conditions table (`table_inputs`): what `bearingfem simulate`
    computes (the command evaluates a file in chunks, `studies.model.stream`)."""
    return (pipeline or Pipeline.shared(asm)).run(table_inputs(asm, columns, effects),
                                                  direct=direct)
