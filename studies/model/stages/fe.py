"""FE stage: conditions -> part thermal strains, fit interferences and rotor speed -> the FE
answer per row (`FEState`).

The FE runs through `fem.solver.Superposition`: unit solutions per part thermal strain, for the
centrifugal load of the rotor (shaft, inner rings, inner spacer, nut) at the row's `speed_rpm`
(scaled by omega^2; the assembly state is at rest) and per fit, combined exactly for every row
(the contact active set is solved per row on the condensed interface), so a sweep costs little
per point. `direct=True` solves every row with a full FE solve instead; tests hold the two equal.
The superposition's arrays and the preload-path compliance come from `fem.setup`: from the
on-disk cache when this stack was set up before. The full FE model (mesh, assembly,
factorisations) is built only when something needs it. Units mm, N, MPa, C.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from analytic.bearing import SIGNS, BearingGeometry
from analytic.materials import get_material
from fem.post import mean_pressures_MPa
from fem.setup import (CompliancePlan, FESetup, FullFE, SetupSpec, cached_setup, compute_setup,
                       full_fe)
from fem.solver import SolveError, Superposition
from studies.model.inputs import PhysicsInputs
from studies.model.stages.grooves import RINGS, GrooveCentres

#: which temperature of `PhysicsInputs.T_C` each FE part takes
FE_PART_GROUP = {"shaft": "shaft", "nut": "shaft", "inner_ring_A": "inner_ring",
                 "inner_ring_B": "inner_ring", "inner_spacer": "spacer", "outer_spacer": "spacer",
                 "outer_ring_A": "outer_ring", "outer_ring_B": "outer_ring", "housing": "housing",
                 "cover": "housing", "sleeve": "housing", "cartridge": "housing"}
#: fit-loosening speeds are searched up to here (rpm); a fit still closed there reports inf
SPEED_SEARCH_MAX_RPM = 1e6


@dataclass
class FEState:
    """Per-row FE results (n rows).

    fit_pressure_MPa (n, n_fits): mean contact pressure per FE fit (MPa; the fits in the order of
    `FESetup.fit_names`). interference_um (n, 2): free diametral overlap at the row's
    temperatures, inner and outer fit (um; NaN for a conduction-field state). dr_mm, dz_mm
    (2, n): inner minus outer groove-centre shift of bearings A and B, radial and axial (mm).
    raceway_u_mm (n, 8): u_r, u_z at the raceway points of RINGS (mm). face_force_N (n, n_faces):
    the axial force (N, + compression) across each face held as a contact (`Section.faces`, clamp
    = "force": the clamp's own face, then the stack's faces on its side), None without one; the faces' mean pressures are the last
    columns of fit_pressure_MPa. layer_interference_um (n, n_layers): free diametral overlap of
    each sleeve / cartridge fit (`Assembly.layers` order) at the row's temperatures (um); None
    without layers or for a conduction-field state."""
    fit_pressure_MPa: np.ndarray
    interference_um: np.ndarray
    dr_mm: np.ndarray
    dz_mm: np.ndarray
    raceway_u_mm: np.ndarray
    face_force_N: np.ndarray | None = None
    layer_interference_um: np.ndarray | None = None

    @property
    def n_rows(self) -> int:
        return self.fit_pressure_MPa.shape[0]

    def with_shifts(self, dr_mm: np.ndarray | None = None, dz_mm: np.ndarray | None = None) -> "FEState":
        """The same state with the radial and/or axial groove-centre shifts replaced (what
        `FEOptions.shifts` and `FEOptions.centres` do)."""
        return replace(self, dr_mm=self.dr_mm if dr_mm is None else dr_mm,
                       dz_mm=self.dz_mm if dz_mm is None else dz_mm)

    def take(self, rows: np.ndarray) -> "FEState":
        """The states of the given rows (an index array; rows may repeat): with
        `PhysicsInputs.take` and `FEOptions(states=...)`, the same FE answers evaluated under
        several bearing or torque settings in one `Pipeline.run`."""
        rows = np.asarray(rows, int)
        return FEState(self.fit_pressure_MPa[rows], self.interference_um[rows],
                       self.dr_mm[:, rows], self.dz_mm[:, rows], self.raceway_u_mm[rows],
                       None if self.face_force_N is None else self.face_force_N[rows],
                       None if self.layer_interference_um is None
                       else self.layer_interference_um[rows])


@dataclass(frozen=True)
class RowField:
    """The full FE answer of one row's state (field images, fit distributions, stresses)."""
    u_mm: np.ndarray            # displacement vector, every DOF of `FEStage.model`, mm
    force_N: np.ndarray         # contact force per interface pair (N, + compression)
    theta: np.ndarray           # thermal strain per FE part (`part_names` order)


@dataclass(frozen=True)
class FEOptions:
    """How the route forms the FE answer the bearing sees (`Pipeline.run(..., fe_options=)`).

    shifts: "both" (the default: the FE's groove-centre shifts as solved), "radial_only" (the
      axial shifts held: what the fits and ring growth alone do to the preload) or "axial_only"
      (the radial shifts held: what the stack lengths alone do).
    held: what a held set of shifts is: "assembly" (the default: its value in the row's
      assembly state), "assembly_plus_free_growth" (that plus the bearing's own uniform thermal
      growth at the row's inner-ring temperature, `analytic.axial_stack.uniform_growth_shifts_mm`:
      a uniformly heated bearing keeps its contact angle) or "free_growth" (the uniform growth
      alone, in the rows and in their assembly states: the fits' raceway expansion at assembly
      also off).
    reference: the assembly state the position preload is set in, per row: "as_built" (the
      default: T_ref, at rest, at the row's own fits) or "nominal_fits" (at the assembly's
      `[fits]` values: a fit-tolerance sample assembled into the nominal stack).
    centres: None, or a function (pipeline, inputs) -> (dr_mm, dz_mm) (each (2, n), mm) giving
      the groove-centre shifts in place of the model's reconstruction, applied to the rows and
      to their assembly states (e.g. a study's free-radius circle fit).
    states: None, or the FE answers given instead of solved, (rows, assembly states) as two
      `FEState`s: an earlier result's `fe` and `fe_ref` (`FEState.take` repeats rows to evaluate
      them under other bearing or torque settings), or `Pipeline.fe_field`'s state of a
      non-uniform temperature field. `shifts` and `held` still apply; `centres` and `reference`
      do not.
    """
    shifts: str = "both"
    held: str = "assembly"
    reference: str = "as_built"
    centres: Callable | None = None
    states: tuple[FEState, FEState] | None = None

    def __post_init__(self):
        for name, allowed in (("shifts", ("both", "radial_only", "axial_only")),
                              ("held", ("assembly", "assembly_plus_free_growth", "free_growth")),
                              ("reference", ("as_built", "nominal_fits"))):
            if getattr(self, name) not in allowed:
                raise ValueError(f"FEOptions.{name} must be one of {', '.join(allowed)}, "
                                 f"got {getattr(self, name)!r}")

    def apply_shifts(self, fe: FEState, fe_ref: FEState,
                     growth=None, growth_ref=None) -> tuple[FEState, FEState]:
        """The rows' and assembly states with the shifts this option holds. growth, growth_ref:
        (dr_mm, dz_mm) of the bearing's uniform growth at the rows' and at the assembly
        temperature (each (2, n), mm; needed unless held = "assembly")."""
        if self.shifts == "both":
            return fe, fe_ref
        k = 1 if self.shifts == "radial_only" else 0          # the held set: 0 radial, 1 axial
        ref = (fe_ref.dr_mm, fe_ref.dz_mm)[k]
        if self.held == "assembly":
            held = ref
        elif self.held == "assembly_plus_free_growth":
            held = ref + growth[k]
        else:
            held, ref = growth[k], growth_ref[k]
            fe_ref = fe_ref.with_shifts(**{("dr_mm", "dz_mm")[k]: ref})
        return fe.with_shifts(**{("dr_mm", "dz_mm")[k]: held}), fe_ref


@dataclass(frozen=True)
class FELoads:
    """What the FE of n rows is solved for: theta (n, n_parts) thermal strain per FE part,
    delta_mm (n, n_fits) radial interference per FE fit, omega2 (n,) rotor speed squared
    (rad^2/s^2), inner_um and outer_um (n,) the diametral fits at T_ref (um), layers_um
    (n, n_layers) those of the sleeve / cartridge (None without them)."""
    theta: np.ndarray
    delta_mm: np.ndarray
    omega2: np.ndarray
    inner_um: np.ndarray
    outer_um: np.ndarray
    layers_um: np.ndarray | None = None

    def key(self, direct: bool) -> bytes:
        """The exact inputs of the solve (cache key): SHA-1 of their bytes in turn (fed without
        joining them first)."""
        h = hashlib.sha1()
        for a in (self.theta, self.delta_mm, self.omega2):
            h.update(np.ascontiguousarray(a))
        h.update(bytes([direct]))
        return h.digest()


@dataclass(frozen=True)
class ClampState:
    """The preloaded clamps (clamp = "force") of n rows. names: the clamps ("nut", "cover"), in
    the order of the section's faces; force_N (n, n_clamps): the FE force across each clamped
    face at the row's state (N, + compression: the clamp force left after thermal growth, fits
    and speed); margin_N (n,): the smallest over every face held as a contact, the clamps' own and
    the stack's (ring-shoulder, ring-spacer: `studies.model.stack.STACK_FACES`), of its force -
    |axial_load_N| (N): the force left before a face of the stack separates under the row's
    external axial load, which the stack carries through its faces (a stack face that opens while
    the clamp still holds, beside a sleeve that outgrows the rings, counts). That takes the whole external load off the clamped
    faces: the bolted joint's separation load is F_i / (1 - C) >= F_i for any joint constant C
    (`analytic.clamp`), so the margin is on the safe side by C |axial_load_N| at most.
    open (n,): margin_N <= 0 (a face open in the FE has force 0, so its margin is <= 0)."""
    names: tuple[str, ...]
    force_N: np.ndarray
    margin_N: np.ndarray
    open: np.ndarray


@dataclass(frozen=True)
class FitOpenSpeeds:
    """The fit-loosening speeds of the inner (rotating) fits: names (the FE fits, `fit_inner_A`,
    ...) and speed_rpm (n, n_inner_fits), rpm (0: open at rest; inf: still closed at
    SPEED_SEARCH_MAX_RPM)."""
    names: tuple[str, ...]
    speed_rpm: np.ndarray

    def of(self, name: str) -> np.ndarray:
        """(n,) speeds of the FE fit `name`, rpm."""
        return self.speed_rpm[:, self.names.index(name)]


class FEStage:
    """The FE of one assembly's section: set-up (from the cache, or computed), loads of a row,
    solves. `cache=False`: the set-up is always computed; `setup_of(spec)`: the set-up from
    elsewhere (`fem.parametric`); `superpose=False`: rows are solved directly."""

    def __init__(self, asm, section, geom: BearingGeometry, rotating_parts: tuple[str, ...],
                 fits_of: Callable, progress=None, superpose: bool = True, cache: bool = True,
                 setup_of=None):
        """asm: the `studies.model.config.Assembly`; section: its `meshes.section` (scaled);
        rotating_parts: the rotor's parts (centrifugal load); fits_of(inputs) -> (inner_um,
        outer_um): the rows' diametral fits at T_ref (`effects.resolve_interference_um`)."""
        self._say = progress or (lambda s: None)
        self.asm = asm
        self.section = section
        self._fits_of = fits_of
        self.grooves = GrooveCentres.of(section, geom, asm.arrangement)
        #: axial overlap (mm) each clamp is tightened with (`tighten`): its face key -> delta
        #: (0 until tightened; the compliance plan closes the faces whatever it is)
        self.clamp_delta_mm = {f.key: 0.0 for f in section.faces}
        plan = None
        if asm.preload.path_compliance == "fe":
            inner, outer = asm.mean_fits_um()
            delta = self.deltas_mm(np.array([inner]), np.array([outer]))[0]
            plan = CompliancePlan(tuple(float(v) for v in SIGNS[asm.arrangement]),
                                  tuple(float(v) for v in delta))
        rotor = tuple(p for p in rotating_parts if p in section.parts())
        mats = {p: get_material(section.material_of(p), asm.materials) for p in section.parts()}
        self.spec = SetupSpec.of(section, asm.fits.contact, self.grooves.probe_points_rz_mm, plan,
                                 materials=mats, rotating_parts=rotor)
        self.materials = dict(self.spec.materials)
        self._full: FullFE | None = None
        self.setup: FESetup = (setup_of(self.spec) if setup_of is not None   # fem.parametric
                               else cached_setup(self.spec, self.full_fe, progress=self._say) if cache
                               else compute_setup(self.spec, self.full_fe()))
        self.part_names = self.setup.part_names
        self.sup = (Superposition.from_condensed(self.setup.condensed, lambda: self.solver)
                    if superpose else None)
        if section.faces:
            self.clamp_delta_mm = self.tighten()
        #: preload-path compliance per bearing from the FE (mm/N); 0 for a rigid path
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

    # ------------------------------------------------------------------ loads of the rows
    def thetas(self, inputs: PhysicsInputs) -> np.ndarray:
        """(n, n_parts) thermal strain per FE part; the cte_nonlinearity effect changes the CTE
        slope of the shaft (and nut) and housing (and cover); `inputs.cte_factor` scales a part's
        strain (a material lot's CTE). Parts of one temperature group and one material (the
        two inner rings, the spacers, ...) share their strain: computed once per such pair."""
        cols, strains = [], {}
        for part in self.part_names:
            group = FE_PART_GROUP[part]
            mat = self.materials[part]
            if group in inputs.dalpha_per_K2:          # shaft (and nut), housing (and cover)
                mat = mat.with_dalpha(inputs.dalpha_per_K2[group],
                                      inputs.d2alpha_per_K3.get(group, 0.0))
            theta = strains.get((group, mat))
            if theta is None:
                theta = strains[group, mat] = mat.thermal_strain(
                    np.asarray(inputs.T_C[group], float), self.asm.T_ref_C)
            if part in inputs.cte_factor:               # a material lot (diagnosis ladder)
                theta = inputs.cte_factor[part] * theta
            cols.append(theta)
        return np.column_stack(cols)

    @staticmethod
    def omega2(inputs: PhysicsInputs) -> np.ndarray:
        """(n,) square of the rotor speed, rad^2/s^2: omega = 2 pi speed_rpm / 60."""
        return (np.asarray(inputs.speed_rpm, float) * (2.0 * np.pi / 60.0)) ** 2

    def fits_um(self, inputs: PhysicsInputs) -> tuple[np.ndarray, np.ndarray]:
        """(inner, outer) diametral fit (um) of each row at T_ref: the `[fits]` values plus the
        inputs' offsets (effects, tolerance samples)."""
        return self._fits_of(inputs)

    def layer_fits_um(self, inputs: PhysicsInputs) -> np.ndarray | None:
        """(n, n_layers) diametral fit (um) of each sleeve / cartridge at T_ref: the mean
        assembly's (`Assembly.mean_fit_um`) plus the inputs' offsets (tolerance samples); None
        without layers."""
        layers = self.asm.layers()
        if not layers:
            return None
        cols = []
        for name, _ in layers:
            off = getattr(inputs, f"interference_{name}_um")
            cols.append(np.full(inputs.n_rows, self.asm.mean_fit_um(name))
                        + (0.0 if off is None else np.asarray(off, float)))
        return np.column_stack(cols)

    def deltas_mm(self, inner_um: np.ndarray, outer_um: np.ndarray,
                  layers_um: np.ndarray | None = None) -> np.ndarray:
        """(n, n_fits) radial interference (mm) per FE fit; a sleeve's or cartridge's fit from
        `layers_um` (n, n_layers), by default the mean assembly's on every row."""
        n = np.broadcast(inner_um, outer_um).shape
        um = {"inner": inner_um, "outer": outer_um}
        for k, (name, _) in enumerate(self.asm.layers()):
            um[name] = (np.full(n, self.asm.mean_fit_um(name)) if layers_um is None
                        else layers_um[:, k])
        return np.column_stack([um[f.key] / 2000.0 for f in self.section.fits]
                               + [np.full(n, self.clamp_delta_mm[f.key]) for f in self.section.faces])

    # ------------------------------------------------------------------ clamps with a force
    def face_columns(self) -> list[int]:
        """The contact interfaces (columns of `deltas_mm`, `FESetup.fit_names`) that are faces."""
        n_fits = len(self.section.fits)
        return list(range(n_fits, n_fits + len(self.section.faces)))

    def face_forces_N(self, force_N: np.ndarray) -> np.ndarray:
        """(n, n_faces) total force across each clamped face (N) from the pair forces (n,
        n_pairs)."""
        fop = self.setup.condensed.fit_of_pair
        return np.column_stack([force_N[:, fop == k].sum(axis=1) for k in self.face_columns()])

    def clamp_faces(self) -> list[tuple[int, "object"]]:
        """(index among the section's faces, face) of each clamp's own face (key "clamp_<name>");
        the other faces are the stack's (key "stack", no overlap: `studies.model.stack`)."""
        return [(j, f) for j, f in enumerate(self.section.faces) if f.key.startswith("clamp_")]

    def tighten(self) -> dict[str, float]:
        """The axial overlap delta (mm) of each clamp with a force: the one at which its face
        carries `clamp_force_N` in the nominal assembly (T_ref, at rest, the `[fits]` values
        at mid-band): a clamp is tightened to its force once, at assembly. Each face's force is
        monotone in its own delta; the root is bracketed and found by Brent's method (scipy)
        to 1e-13 of delta. Raises ValueError when a face cannot carry the force."""
        from scipy.optimize import brentq

        inner, outer = self.asm.mean_fits_um()
        theta = np.zeros((1, len(self.part_names)))
        delta = dict(self.clamp_delta_mm)
        sup = self.sup if self.sup is not None else Superposition(self.solver, self.probe)
        for j, face in self.clamp_faces():
            F = getattr(self.asm, face.key.removeprefix("clamp_")).clamp_force_N

            def residual(d):
                delta[face.key] = d
                self.clamp_delta_mm = delta
                row = self.deltas_mm(np.array([inner]), np.array([outer]))
                lam = sup.evaluate(theta, row, np.zeros(1)).force_N
                return float(self.face_forces_N(lam)[0, j]) - F

            hi, hi_max = 1e-6, 10.0 + 10.0 * F * face.compliance_mm_per_N   # mm
            while residual(hi) < 0:
                hi *= 4
                if hi > hi_max:
                    raise ValueError(f"the {face.key} face cannot be tightened to {F:g} N")
            lo = -hi
            while residual(lo) > 0:
                lo *= 4
                if lo < -10.0:
                    raise ValueError(f"the {face.key} face carries {F:g} N untightened")
            delta[face.key] = brentq(residual, lo, hi, xtol=1e-15, rtol=1e-13, maxiter=200)
            self.clamp_delta_mm = delta
        return delta

    def clamp_state(self, fe: FEState, axial_load_N) -> ClampState | None:
        """The clamps of the rows (`ClampState`) from their FE state and external axial load
        (N); None without a clamp with a force."""
        if fe.face_force_N is None:
            return None
        clamps = self.clamp_faces()
        names = tuple(f.key.removeprefix("clamp_") for _, f in clamps)
        load = np.abs(np.broadcast_to(np.asarray(axial_load_N, float), (fe.n_rows,)))
        margin = (fe.face_force_N - load[:, None]).min(axis=1)      # every face: clamp and stack
        return ClampState(names, fe.face_force_N[:, [j for j, _ in clamps]], margin, margin <= 0)

    def row_deltas_mm(self, inputs: PhysicsInputs) -> np.ndarray:
        """(n, n_fits) radial interference (mm) per FE fit of the rows of `inputs`."""
        return self.deltas_mm(*self.fits_um(inputs), self.layer_fits_um(inputs))

    def loads(self, inputs: PhysicsInputs) -> FELoads:
        """What the FE of the rows is solved for (`FELoads`)."""
        theta = self.thetas(inputs)
        inner_um, outer_um = self.fits_um(inputs)
        layers_um = self.layer_fits_um(inputs)
        delta = self.deltas_mm(inner_um, outer_um, layers_um)
        w2 = np.broadcast_to(self.omega2(inputs), (theta.shape[0],)).copy()
        return FELoads(theta, delta, w2, inner_um, outer_um, layers_um)

    # ------------------------------------------------------------------ solves
    def solve(self, loads: FELoads, direct: bool = False) -> FEState:
        """The FE answers of the rows: superposed, or direct solves (`direct`, or a stage built
        without unit solutions)."""
        theta, delta, w2 = loads.theta, loads.delta_mm, loads.omega2
        n = theta.shape[0]
        if direct or self.sup is None:
            force, probe = [], []
            m = self.model
            for i in range(n):
                try:
                    sol = self.solver.solve(m.unit_loads @ theta[i] + w2[i] * m.spin_load,
                                            delta[i])
                except SolveError as exc:           # the row by its place among these
                    raise SolveError(str(exc), None if exc.state is None else i) from None
                force.append(sol.force_N)
                probe.append(self.full_fe().probe @ sol.u)
            force, probe = np.array(force), np.array(probe)
        else:
            res = self.sup.evaluate(theta, delta, w2)
            force, probe = res.force_N, res.probe
        p = self.fit_pressures(force)
        faces = self.face_forces_N(force) if self.section.faces else None
        idx = {p: i for i, p in enumerate(self.part_names)}
        dr, dz = self.grooves.shifts_mm(probe, theta[:, [idx[r] for r in RINGS]])
        a = self.asm
        d_seat, d_bore = a.shaft.seat_diameter_mm, a.outer_seat_diameter_mm
        seat = ([n for n, _ in a.layers()] + ["housing"])[0]     # what the outer rings sit in
        interf = np.column_stack([
            loads.inner_um + (theta[:, idx["shaft"]] - theta[:, idx["inner_ring_A"]]) * d_seat * 1e3,
            loads.outer_um + (theta[:, idx["outer_ring_A"]] - theta[:, idx[seat]]) * d_bore * 1e3])
        return FEState(p, interf, dr, dz, probe[:, :8], faces,
                       self._layer_interference_um(loads, theta))

    def solve_failure(self, exc: SolveError, inputs: PhysicsInputs, first_row: int = 0
                      ) -> SolveError:
        """The solver's failure on a state of the rows of `inputs` (0-based `first_row` of the
        table) as the one line a user can act on: the row (1-based, as in the conditions table),
        its fits (the `[fits]` keys, um at T_ref) and temperatures, and what to try."""
        if exc.state is None:
            return exc
        i = int(exc.state)
        inner, outer = (np.broadcast_to(np.asarray(v, float), (inputs.n_rows,))[i]
                        for v in self.fits_um(inputs))
        fits = [f"inner_interference_um = {inner:g}", f"outer_interference_um = {outer:g}"]
        layers = self.layer_fits_um(inputs)
        fits += [f"{name}_interference_um = {layers[i, k]:g}"
                 for k, (name, _) in enumerate(self.asm.layers())]
        temps = sorted({float(np.broadcast_to(np.asarray(t, float), (inputs.n_rows,))[i])
                        for t in inputs.T_C.values()})
        at = f"{temps[0]:g} C" if len(temps) == 1 else f"{temps[0]:g}..{temps[-1]:g} C"
        return SolveError(f"row {first_row + i + 1} ({at}, {', '.join(fits)}): {exc}; try that "
                          "fit 0.1 um either side (the answer is continuous across it), or "
                          "`simulate --direct`", first_row + i)

    def _layer_interference_um(self, loads: FELoads, theta: np.ndarray) -> np.ndarray | None:
        """(n, n_layers) free diametral overlap of each layer's fit at the rows' temperatures
        (um): its fit at T_ref plus the thermal mismatch with the part outside it (the next
        layer or the housing), (theta_layer - theta_outside) x the fit diameter."""
        a = self.asm
        names = [n for n, _ in a.layers()]
        if not names:
            return None
        idx = {p: i for i, p in enumerate(self.part_names)}
        outside = names[1:] + ["housing"]
        return np.column_stack([
            loads.layers_um[:, k] + (theta[:, idx[name]] - theta[:, idx[outside[k]]])
            * a.fit_diameter_mm(name) * 1e3 for k, name in enumerate(names)])

    def fit_pressures(self, force_N: np.ndarray) -> np.ndarray:
        """(n, n_fits) mean pressure (MPa) per FE fit from the pair forces (n, n_pairs) in N."""
        st = self.setup
        return mean_pressures_MPa(force_N, st.condensed.fit_of_pair, st.fit_r_mm, st.fit_length_mm)

    def fit_open_speed_rpm(self, inputs: PhysicsInputs) -> "FitOpenSpeeds":
        """The speed (rpm) at which each inner (rotating) fit opens, per row at the row's part
        temperatures and fits (`fem.loosening.fit_open_omega2` on the superposition): 0 when
        already open at rest, inf when still closed at SPEED_SEARCH_MAX_RPM."""
        from fem.loosening import RPM2_TO_RAD2_S2, fit_open_omega2

        sup = self.sup if self.sup is not None else Superposition(self.solver, self.probe)
        theta = self.thetas(inputs)
        delta = self.row_deltas_mm(inputs)
        w2_max = SPEED_SEARCH_MAX_RPM ** 2 * RPM2_TO_RAD2_S2
        fits = [(k, f.name) for k, f in enumerate(self.section.fits) if f.key == "inner"]
        rpm = [np.sqrt(fit_open_omega2(sup, theta, delta, k, w2_max) / RPM2_TO_RAD2_S2)
               for k, _ in fits]
        return FitOpenSpeeds(tuple(n for _, n in fits), np.column_stack(rpm))

    def field(self, inputs: PhysicsInputs, row: int = 0) -> RowField:
        """Displacement field and contact forces of one row (superposed, or a direct solve when
        the stage was built without unit solutions)."""
        theta = self.thetas(inputs)[row]
        delta = self.row_deltas_mm(inputs)[row]
        w2 = float(np.broadcast_to(self.omega2(inputs), (inputs.n_rows,))[row])
        if self.sup is None:
            sol = self.solver.solve(self.model.unit_loads @ theta + w2 * self.model.spin_load, delta)
            return RowField(sol.u, sol.force_N, theta)
        force = self.sup.evaluate(theta[None, :], delta[None, :], np.array([w2])).force_N[0]
        return RowField(self.sup.field(theta, delta, w2), force, theta)

    def fe_field(self, theta_q: np.ndarray, inputs: PhysicsInputs) -> tuple[FEState, np.ndarray]:
        """One state with a non-uniform thermal strain field (nel, nq) from a conduction solution:
        a direct FE solve (not superposed). The groove-centre offsets take each ring's mean
        thermal strain. Returns (FEState, displacement vector (ndofs,), mm); pass the state to
        `Pipeline.run` with `FEOptions(states=...)`."""
        m = self.model
        delta = self.row_deltas_mm(inputs)[0]
        w2 = float(np.atleast_1d(self.omega2(inputs))[0])
        sol = self.solver.solve(m.thermal_load_vector(theta_q) + w2 * m.spin_load, delta)
        probe = self.full_fe().probe @ sol.u
        p = self.fit_pressures(sol.force_N)
        w = m.basis.dx
        th = np.array([[float((theta_q[m.part_of == r] * w[m.part_of == r]).sum()
                              / w[m.part_of == r].sum()) for r in RINGS]])
        dr, dz = self.grooves.shifts_mm(probe[None, :], th)
        faces = self.face_forces_N(sol.force_N[None, :]) if self.section.faces else None
        return FEState(p, np.full((1, 2), np.nan), dr, dz, probe[None, :8], faces), sol.u
