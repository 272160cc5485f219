"""The model's one route: conditions -> part temperatures and fits -> FE (fit pressures,
groove-centre shifts) -> bearing pair (preload, contact angle, Hertz) -> friction torque -> checks.

`Pipeline` keeps one assembly's set-up (the FE stage's unit solutions, the bearing geometry) and
two caches (FE answers and pair equilibria by their exact inputs), and `run` calls the stages of
`studies.model.stages` in order, returning a typed `studies.model.result.SimulationResult`. What a
study changes in the route (only the radial or only the axial groove-centre shifts, the assembly
state at the nominal fits, its own groove-centre reconstruction, FE answers given: a non-uniform
temperature field, or earlier answers under other settings) is a named option, `FEOptions`.
Named columns are made from the result by `studies.model.columns.to_columns` only.

Where an FE result feeds the bearing model, the closed-form value is carried beside it
(`studies.model.stages.lame`).
"""
from __future__ import annotations

from dataclasses import replace
from functools import partial

import numpy as np

from analytic.axial_stack import uniform_growth_shifts_mm
from analytic.bearing import PairState
from fem.solver import SolveError
from studies.model.checks import assembly_checks, evaluate_checks
from studies.model.config import Assembly
from studies.model.effects import resolve_friction_coefficient, resolve_interference_um
from studies.model.inputs import NO_CTE_SLOPE, PhysicsInputs
from studies.model.memo import Memo, inputs_key
from studies.model.result import FitPressures, SimulationResult
from studies.model.stack import ROTOR_PARTS, section_from_assembly, stack_positions
from studies.model.stages.bearing import BearingStage
from studies.model.stages.fe import (SPEED_SEARCH_MAX_RPM, FEOptions, FEStage,  # noqa: F401
                                     FEState, FitOpenSpeeds, RowField)
from studies.model.stages.grooves import RINGS  # noqa: F401  (re-exported for the studies)
from studies.model.stages.lame import lame_neighbours
from studies.model.stages.torque import pair_friction_torque


class ModelError(ValueError):
    """The model cannot give a finite answer for these inputs (one line: row and output)."""


#: outputs that must be finite in every row (the interferences of a conduction-field state are
#: not defined and are NaN by design)
CHECKED_OUTPUTS = ("torque_Nmm", "preload_N", "contact_angle_deg", "fit_pressure_inner_MPa",
                   "fit_pressure_outer_MPa", "max_contact_pressure_MPa")


def check_answers(out, converged: np.ndarray, first_row: int = 0) -> None:
    """Raise ModelError naming the first row (1-based, as in the conditions table; the arrays
    start at 0-based row `first_row` of it) whose bearing equilibrium did not converge or whose
    output is not finite; never a silent NaN. out: {name: (n,) array} of CHECKED_OUTPUTS (the
    names the message gives)."""
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


def _checked_outputs(r: SimulationResult) -> dict[str, np.ndarray]:
    """The values of CHECKED_OUTPUTS of a result (for `check_answers`' messages)."""
    return {"torque_Nmm": r.torque.torque_Nmm, "preload_N": r.pair.preload_N,
            "contact_angle_deg": r.summary.contact_angle_deg,
            "fit_pressure_inner_MPa": r.fits.inner_MPa, "fit_pressure_outer_MPa": r.fits.outer_MPa,
            "max_contact_pressure_MPa": r.pair.max_contact_pressure_MPa}


class Pipeline:
    """One assembly: the stages' set-up (FE unit solutions, bearing geometry), built once, and
    two caches; `run` is the route.

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
        self.asm = asm
        self.mesh_factor = float(mesh_factor)
        self.section = section_from_assembly(asm).scaled(mesh_factor)
        z = stack_positions(asm)        # the ball planes: inner ring mid-planes of A and B
        self.bearing = BearingStage(asm, 0.5 * (sum(z["inner_ring_B"]) - sum(z["inner_ring_A"])))
        mean_fits_um = asm.mean_fits_um()       # of the frozen assembly: once
        self.fe_stage = FEStage(asm, self.section, self.bearing.geom, ROTOR_PARTS,
                                lambda inputs: resolve_interference_um(inputs, *mean_fits_um),
                                progress, superpose, cache, setup_of)
        self.bearing.compliance_mm_per_N = self.fe_stage.compliance_mm_per_N
        self.lubricant = asm.oil()
        self.checks = assembly_checks(asm)
        self._fe_cache: dict[bytes, FEState] = {}
        self._pair_memo = Memo()        # pair equilibria by their exact inputs

    # ------------------------------------------------------------------ what the stages hold
    geom = property(lambda self: self.bearing.geom, doc="`analytic.bearing.BearingGeometry`")
    compliance_mm_per_N = property(lambda self: self.bearing.compliance_mm_per_N,
                                   doc="the assembly's preload-path compliance per bearing, mm/N")
    bearing_span_mm = property(lambda self: self.bearing.bearing_span_mm,
                               doc="distance of the ball planes of bearings A and B, mm")
    land_diameters_mm = property(lambda self: self.bearing.land_diameters_mm,
                                 doc="inner and outer land diameters, mm")
    setup = property(lambda self: self.fe_stage.setup, doc="the FE set-up (`fem.setup.FESetup`)")
    spec = property(lambda self: self.fe_stage.spec, doc="what the set-up is of (`fem.setup.SetupSpec`)")
    sup = property(lambda self: self.fe_stage.sup, doc="the `fem.solver.Superposition` (or None)")
    part_names = property(lambda self: self.fe_stage.part_names, doc="the FE parts, in order")
    materials = property(lambda self: self.fe_stage.materials, doc="material per FE part")
    model = property(lambda self: self.fe_stage.model, doc="`fem.model.StackModel` (on first use)")
    solver = property(lambda self: self.fe_stage.solver, doc="`fem.solver.FitSolver` (on first use)")
    probe = property(lambda self: self.fe_stage.probe, doc="(8, ndofs) raceway probe matrix")
    ndofs = property(lambda self: self.fe_stage.setup.ndofs, doc="displacement DOFs of the FE model")
    _full = property(lambda self: self.fe_stage._full)

    def full_fe(self):
        """The full FE model of the section (`FEStage.full_fe`)."""
        return self.fe_stage.full_fe()

    def thetas(self, inputs: PhysicsInputs) -> np.ndarray:
        """(n, n_parts) thermal strain per FE part (`FEStage.thetas`)."""
        return self.fe_stage.thetas(inputs)

    omega2 = staticmethod(FEStage.omega2)

    def fits_um(self, inputs: PhysicsInputs) -> tuple[np.ndarray, np.ndarray]:
        """(inner, outer) diametral fits at T_ref, um (`FEStage.fits_um`)."""
        return self.fe_stage.fits_um(inputs)

    def deltas_mm(self, inner_um: np.ndarray, outer_um: np.ndarray) -> np.ndarray:
        """(n, n_fits) radial interference per FE fit, mm (`FEStage.deltas_mm`)."""
        return self.fe_stage.deltas_mm(inner_um, outer_um)

    def field(self, inputs: PhysicsInputs, row: int = 0) -> RowField:
        """Displacement field and contact forces of one row (`FEStage.field`)."""
        return self.fe_stage.field(inputs, row)

    def fe_field(self, theta_q: np.ndarray, inputs: PhysicsInputs) -> tuple[FEState, np.ndarray]:
        """One state of a non-uniform thermal strain field and its displacements
        (`FEStage.fe_field`)."""
        return self.fe_stage.fe_field(theta_q, inputs)

    def fit_open_speed_rpm(self, inputs: PhysicsInputs) -> FitOpenSpeeds:
        """The speed (rpm) at which each inner fit opens (`FEStage.fit_open_speed_rpm`)."""
        return self.fe_stage.fit_open_speed_rpm(inputs)

    # ------------------------------------------------------------------ FE stage, cached
    def fe(self, inputs: PhysicsInputs, direct: bool = False, remember: bool = True) -> FEState:
        """The FE answers of the rows (superposed, or direct solves). `remember`: keep the result
        for the next call with the same states (a table streamed in chunks does not)."""
        loads = self.fe_stage.loads(inputs)
        # a diagnosis re-evaluates the same FE states many times (friction, viscosity and preload
        # effects leave the structure alone): keep the last few results by their exact inputs,
        # the least recently used leaving first (the reference state is asked for all along)
        key = loads.key(direct)
        hit = self._fe_cache.pop(key, None)
        if hit is not None:
            self._fe_cache[key] = hit
            return hit
        state = self.fe_stage.solve(loads, direct)
        if not remember:
            return state
        if len(self._fe_cache) >= 16:
            self._fe_cache.pop(next(iter(self._fe_cache)))
        self._fe_cache[key] = state
        return state

    def reference_inputs(self, inputs: PhysicsInputs, nominal_fits: bool = False) -> PhysicsInputs:
        """The assembly state of every row: T_ref everywhere, at rest, the row's as-built fits
        (`nominal_fits`: the assembly's `[fits]` values, no offsets)."""
        T_ref = self.asm.T_ref_C
        n = inputs.n_rows
        ref = inputs.copy(T_C={k: np.full(n, T_ref) for k in inputs.T_C},
                          dalpha_per_K2=dict(NO_CTE_SLOPE), d2alpha_per_K3=dict(NO_CTE_SLOPE),
                          speed_rpm=np.zeros(n))
        if nominal_fits:
            ref = ref.copy(interference_inner_um=np.zeros(n), interference_outer_um=np.zeros(n))
        return ref

    def fe_states(self, inputs: PhysicsInputs, options: FEOptions, direct: bool = False,
                  remember: bool = True) -> tuple[FEState, FEState]:
        """The FE answers the bearing sees: the rows' and their assembly states', as `options`
        (`FEOptions`) forms them."""
        if options.states is not None:
            fe, fe_ref = options.states
        else:
            ref_inputs = self.reference_inputs(inputs, options.reference == "nominal_fits")
            fe = self.fe(inputs, direct, remember)
            fe_ref = self.fe(ref_inputs, direct, remember)
            if options.centres is not None:
                fe = fe.with_shifts(*options.centres(self, inputs))
                fe_ref = fe_ref.with_shifts(*options.centres(self, ref_inputs))
        growth = growth_ref = None
        if options.held != "assembly":
            arr, T_ref = self.asm.arrangement, self.asm.T_ref_C
            growth = uniform_growth_shifts_mm(self.geom, arr, inputs.T_C["inner_ring"], T_ref)
            growth_ref = uniform_growth_shifts_mm(self.geom, arr, np.full(inputs.n_rows, T_ref),
                                                  T_ref)
        return options.apply_shifts(fe, fe_ref, growth, growth_ref)

    # ------------------------------------------------------------------ the route
    def run(self, inputs: PhysicsInputs, direct: bool = False,
            compliance_mm_per_N=None, viscous_factor_f0=None, first_row: int = 0,
            remember: bool = True, ball_model: str | None = None,
            fe_options: FEOptions | None = None) -> SimulationResult:
        """Every stage for the rows of `inputs` -> `SimulationResult`.

        direct: full FE solves instead of the superposition. compliance_mm_per_N: preload-path
        compliance per bearing (mm/N; scalar or one per row) in place of the assembly's
        (`[preload] path_compliance`); the inputs' `extra_compliance_mm_per_N` is added in series.
        viscous_factor_f0: Palmgren's f0 in place of the assembly's (oil lubrication; scalar or
        one per row). first_row: the 0-based row of the whole table the inputs start at (rows
        named in errors). remember: keep the FE answers and the pair equilibrium for the next
        call with the same inputs (a table streamed in chunks does not). ball_model: "static" or
        "quasi_dynamic" in place of the assembly's `[operating] ball_model` (the FE does not
        depend on it). fe_options: how the FE answer is formed (`FEOptions`; default: as solved).
        Raises ModelError naming the first row without a converged, finite answer."""
        try:
            fe, fe_ref = self.fe_states(inputs, fe_options or FEOptions(), direct, remember)
        except SolveError as exc:           # named by its row and fits (one line)
            raise self.fe_stage.solve_failure(exc, inputs, first_row) from None
        with np.errstate(all="ignore"):     # a row without an answer is reported below, by name
            pair = self._pair(inputs, fe, fe_ref, compliance_mm_per_N, ball_model, remember)
            mu = resolve_friction_coefficient(inputs, self.asm.lubrication.friction_coefficient)
            torque = pair_friction_torque(self.asm, self.geom, self.lubricant, pair, inputs, mu,
                                          viscous_factor_f0)
        fits = FitPressures.of(self.setup.fit_names, fe)
        result = SimulationResult(fe, fe_ref, fits, tuple(n for n, _ in self.asm.layers()),
                                  partial(lame_neighbours, self.fe_stage, fe, inputs),
                                  pair, self.bearing.summary(pair), torque, mu, None,
                                  self.fe_stage.clamp_state(fe, inputs.axial_load_N))
        check_answers(_checked_outputs(result), pair.converged, first_row)
        return replace(result, checks=evaluate_checks(result, self.checks))

    def pair_arguments(self, inputs: PhysicsInputs, fe: FEState, fe_ref: FEState,
                       compliance_mm_per_N=None, ball_model: str | None = None) -> dict:
        """The keyword arguments of `analytic.bearing.solve_pair` for these rows (arguments as
        `run`; `BearingStage.arguments`): what the pair's equilibrium, and its stiffness
        (`analytic.bearing.stiffness.pair_stiffness`), are evaluated with."""
        return self.bearing.arguments(inputs, fe, fe_ref, compliance_mm_per_N, ball_model)

    def _pair(self, inputs: PhysicsInputs, fe: FEState, fe_ref: FEState, compliance_mm_per_N,
              ball_model: str | None, remember: bool) -> PairState:
        """The pair equilibrium (bearing stage); friction-only changes (a diagnosis's friction
        scale) leave it alone: the last few are reused by their exact inputs
        (`studies.model.memo`)."""
        args = self.pair_arguments(inputs, fe, fe_ref, compliance_mm_per_N, ball_model)
        key = inputs_key(args)
        pair = self._pair_memo.get(key)
        if pair is None:
            pair = self.bearing.solve(args)
            if remember:        # read-only from here on (studies.model.memo), as a hit would be
                pair = self._pair_memo.put(key, pair, inputs.n_rows)
        return pair


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
                   direct: bool = False, pipeline: Pipeline | None = None) -> SimulationResult:
    """The model's result for a conditions table (`table_inputs`): what `bearingfem simulate`
    computes (the command evaluates a file in chunks, `studies.model.stream`)."""
    return (pipeline or Pipeline.shared(asm)).run(table_inputs(asm, columns, effects),
                                                  direct=direct)
