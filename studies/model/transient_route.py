"""`simulate` in transient mode (`[thermal] mode = "transient"`): the part temperatures of every
row are computed by the transient conduction FE of the stack, not given.

The loop, closed at every time step (docs/cli.md "Transient conduction"):

    temperature field (reduced coordinates q) -> fit pressures, groove-centre shifts (the
    structural response per thermal mode, `fem.reduced_thermal.ModalStructure`) -> pair
    equilibrium -> torque -> heat split (`analytic.heat.pair_heat_W`) -> heat at the raceways
    and ball nodes (`fem.transient.bearing_heat_inputs_W`) -> next step

The conduction FE (`fem.transient.TransientConduction`, one ball node per bearing) is reduced once
per assembly (`fem.reduced_thermal.krylov_basis`, kept affine in films and conductances, so the
rows' `film_scale` and the fit conductances updated from the fit pressures need no new reduction)
and stepped with BDF2 (`ReducedStepper`) on a fixed grid: step DT_S, longer when the table spans
more than MAX_STEPS of them, the last step ending at the last row. The heat of a step is taken at
the state at its start (explicit coupling, as seed 003's network does; the heat changes over
minutes, the step is seconds). Conditions between rows are interpolated linearly in time; the
state at a row between grid points is the linear interpolation of the two neighbours' reduced
coordinates. Every row is then evaluated through the pipeline's one route for given FE states
(`Pipeline.run` with `FEOptions(states=...)`) with the computed part temperatures (volume means of the FE parts by
`stages.fe.FE_PART_GROUP`, the ball nodes for the balls).

The initial state is uniform at the first row's environment temperature. A stack with no films
and no radiation is adiabatic outside: it runs (the reduction takes its own moments,
`fem.reduced_thermal.krylov_basis`), the heat is stored, and a warning line says so
(`checks.plausibility_warnings`). The ball-raceway
conductances and the partition of each contact's heat between ball and ring
(`analytic.heat.rolling_contact_conductance`: moving-source constriction on both sides at the
rolling speed, the EHL film's conduction in series for an oil, Blok's partition) are refreshed
with the heat from the contact state (`ball_contacts`). Sliding and spin traction coefficient
MU_TRACTION = 0.03 (assumption for EHL traction, as the seed 003 study).

`coupling_at` gives the coupling at a state after a run (e.g. a ball node's heat balance);
`equilibrium` the steady state of the same loop under fixed conditions as a fixed point, without
time stepping (where a long run ends).

`reduction_error_est` (per row): |P_m - P_m/2| / |P_m|, the preload of the reduced model against
the same run with the leading half of its modes (`fem.reduced_thermal` module docstring; the bench
`bearingfem bench --transient` measures the error against the full FE on a check case).
Units: mm, N, s, C, W inside; film coefficients and conductances in W/(m^2 K).
"""
from __future__ import annotations

import fnmatch
from dataclasses import dataclass, replace

import numpy as np

from analytic import lubrication as lub
from analytic import thermal_network as tn
from analytic.heat import (ContactConductance, located_pair_heat_W, pair_heat_W,
                           rolling_contact_conductance, solid_film_pair_heat_W)
from fem.reduced_thermal import (ModalStructure, ReducedConduction, ReducedStepper, krylov_basis,
                                 modal_structure)
from fem.solver import single_thread_blas
from fem.transient import (OPEN_FIT_SPOT_W_M2K, StepLoads, SurfacePair, ThermalParameters,
                           TransientConduction, bearing_heat_inputs_W, fit_conductances_W_m2K,
                           radiation_remainder_W_mm2)
from studies.model.config import Assembly, ConfigError
from studies.model.inputs import PARTS, PhysicsInputs, baseline_inputs
from studies.model.columns import to_columns
from studies.model.pipeline import RINGS, FEOptions, FEState, Pipeline
from studies.model.result import SimulationResult
from studies.model.stages.fe import FE_PART_GROUP
from studies.model.table import TableError

#: sliding and spin traction coefficient of the heat split (assumption: EHL traction, as seed 003)
MU_TRACTION = 0.03
#: time step of the reduced transient (s) and the most steps a table gets (longer steps beyond)
DT_S = 2.0
MAX_STEPS = 20_000
#: the coupling (pair equilibrium, torque, heat, fit conductances) is refreshed every this many
#: steps (10 s at DT_S): the pair's equilibrium costs ~30 ms, a reduced step ~0.1 ms; the heat
#: changes over minutes (tests/test_transient_route.py holds every step and every 5th close)
COUPLE_EVERY = 5
#: condition columns of transient mode (part temperatures are computed, not given)
TRANSIENT_COLUMNS = ("time_s", "T_ambient_C", "T_sink_C", "film_scale", "heat_W", "speed_rpm",
                     "preload_assembled_N", "axial_load_N", "radial_load_N", "moment_Nmm")
#: training of the reduction: film, fit-conductance and ball-conductance factors about the
#: nominal set (the ball conductances follow the speed and the contact state)
TRAINING = ((0.5, 0.3, 3.0), (2.0, 3.0, 0.3), (0.5, 3.0, 0.3), (2.0, 0.3, 3.0))
#: modes of the estimate's smaller model: this fraction of the modes
HALF = 0.5


@dataclass(frozen=True)
class ThermalModel:
    """The reduced transient model of one assembly's stack (built once per pipeline).

    nominal: coefficients at film_scale 1 (fit conductances at the assembled state);
    group_rows (len(PARTS), n_total): volume mean of each `inputs.PARTS` group (ball: the mean
    of the ball nodes); inputs: the heat inputs of the basis."""
    tc: TransientConduction
    rc: ReducedConduction
    half: ReducedConduction
    ms: ModalStructure
    ms_half: ModalStructure
    nominal: ThermalParameters
    group_rows: np.ndarray
    pressure_conductance: bool
    surfaces: SurfacePair = SurfacePair()

    def groups_per_mode(self, rc: ReducedConduction) -> np.ndarray:
        """(len(PARTS), m): the group means per reduced coordinate of rc (NaN rows: a group the
        stack lacks)."""
        key = rc.m
        cache = self.__dict__.setdefault("_per_mode", {})
        if key not in cache:
            cache[key] = self.group_rows @ rc.V
        return cache[key]


def resolve_films(patterns: dict[str, float], groups) -> dict[str, float]:
    """Film coefficient (W/(m^2 K)) per face group from `[thermal.films]`: an exact name wins,
    else the longest matching fnmatch pattern; groups nothing matches are adiabatic. A name that
    matches no group is a ConfigError (one line, the groups listed)."""
    groups = list(groups)
    for name in patterns:
        if not fnmatch.filter(groups, name):
            raise ConfigError(f"thermal.films.{name}: matches no face group of this stack "
                              f"(groups: {', '.join(sorted(groups))})")
    out = {}
    for g in groups:
        if g in patterns:
            out[g] = float(patterns[g])
            continue
        hits = sorted((p for p in patterns if fnmatch.fnmatchcase(g, p)), key=len)
        if hits:
            out[g] = float(patterns[hits[-1]])
    return out


def _gap_um(pl: Pipeline, gap_mm: np.ndarray) -> np.ndarray:
    """(n, n_fits) mean radial gap (um) of each fit's open pairs (closed pairs count 0)."""
    fop = pl.setup.condensed.fit_of_pair
    g = np.maximum(np.atleast_2d(gap_mm), 0.0)
    return 1e3 * np.column_stack([g[:, fop == k].mean(axis=1) for k in range(len(pl.setup.fit_names))])


def fe_states(pl: Pipeline, ms: ModalStructure, q: np.ndarray, delta_mm: np.ndarray,
              omega2: np.ndarray) -> tuple[FEState, np.ndarray]:
    """FE states (fit pressures, groove-centre shifts) of reduced temperature coordinates q
    (n, m) and the mean open gap per fit (n, n_fits, um): the modal superposition (exact contact
    per state); the interferences of a conduction field are not defined (NaN)."""
    r = ms.evaluate(q, delta_mm, omega2)
    p = pl.fe_stage.fit_pressures(r.force_N)
    dr, dz = pl.fe_stage.grooves.shifts_mm(r.probe, r.ring_strain)
    fe = FEState(p, np.full((p.shape[0], 2), np.nan), dr, dz, r.probe[:, :8])
    return fe, _gap_um(pl, r.gap_mm)


def group_rows(tc: TransientConduction) -> np.ndarray:
    """(len(PARTS), n_total) rows giving each PARTS group's volume mean (ring measure) of T."""
    m = tc.model
    b = m.sbasis
    w = b.dx * b.mapping.F(b.quadrature[0])[0]
    vol = {p: float(w[m.part_of == p].sum()) for p in m.part_names}
    rows = tc.part_mean_rows()
    out = np.zeros((len(PARTS), tc.n_total))
    for i, g in enumerate(PARTS):
        if g == "ball":
            balls = [k for k in ("ball_A", "ball_B") if k in tc.a]
            out[i] = sum(tc.a[k] for k in balls) / len(balls)
            continue
        parts = [p for p in m.part_names if FE_PART_GROUP[p] == g]
        if not parts:        # no such part in the stack: its neighbours' mean is not it; NaN
            out[i] = np.nan
            continue
        tot = sum(vol[p] for p in parts)
        out[i] = sum(vol[p] / tot * rows[m.part_names.index(p)] for p in parts)
    return out


def stack_conduction(pl: Pipeline) -> TransientConduction:
    """The transient conduction FE of `pl`'s stack with one ball node per bearing (the ball
    set's capacity, `analytic.thermal_network.heat_capacity_J_K`)."""
    g = pl.geom
    C_ball = float(tn.heat_capacity_J_K(tn.ball_set_mass_kg(g.Dw_mm, g.Z, g.ball), g.ball))
    return TransientConduction(pl.model, ball_capacity_J_K=C_ball)


@dataclass(frozen=True)
class Contacts:
    """The stack's contact coefficients at the assembled state (`contacts`): fit_W_m2K (n_fits,)
    per fit (from its pressure or the file's value), ball_W_K (inner, outer) ball set to
    raceway per bearing, bore_W_m2K the spacer bores', surfaces the fits' `SurfacePair`,
    pressure: the fits' conductance follows their pressure."""
    fit_W_m2K: np.ndarray
    ball_W_K: tuple
    bore_W_m2K: float
    surfaces: SurfacePair
    pressure: bool


def contacts(pl: Pipeline, tc: TransientConduction) -> Contacts:
    """The contact coefficients of `pl`'s stack at the assembled state at T_ref, as `[thermal]`
    gives them (`fit_conductance`, `gas`): the ball-raceway conductances of the pair at the
    configured speed (`ball_contacts`), the fits' from their pressure (Yovanovich,
    `fem.transient.fit_conductances_W_m2K`) or the file's number; in vacuum no gas in the fits
    and spacer bores; open fits and the spacer bores conduct through their solid spots as well
    (`fem.transient.OPEN_FIT_SPOT_W_M2K`, Incropera Table 3.1: in vacuum their only path)."""
    asm, m = pl.asm, pl.model
    th, T_ref = asm.thermal, asm.T_ref_C
    inp0 = baseline_inputs({}, 1, T_ref, asm.preload.assembled_N, asm.lubrication.speed_rpm)
    pair0 = pl.run(inp0).pair
    G = [c.G_W_K for c in ball_contacts(pl, pair0, asm.lubrication.speed_rpm, T_ref)]
    pressure = th.fit_conductance == "pressure"
    vacuum = th.gas == "vacuum"
    # open fits and spacer bores rest on their solid spots in any gas (`SurfacePair.spot_W_m2K`)
    spot = OPEN_FIT_SPOT_W_M2K
    surf = SurfacePair(gas_conductivity_W_mK=0.0 if vacuum else SurfacePair.gas_conductivity_W_mK,
                       spot_W_m2K=spot)
    if pressure:
        delta0 = pl.deltas_mm(*pl.fits_um(inp0))
        r0 = pl.sup.evaluate(pl.thetas(inp0), delta0, np.zeros(1))
        h_fit = fit_conductances_W_m2K(m, pl.fe_stage.fit_pressures(r0.force_N)[0],
                                       _gap_um(pl, r0.gap_mm)[0], surf)
    else:
        h_fit = np.full(len(m.section.fits), float(th.fit_conductance))
    bore = (0.0 if vacuum else ThermalParameters.bore_conductance_W_m2K) + spot
    return Contacts(np.asarray(h_fit, float), (float(G[0]), float(G[1])), bore, surf, pressure)


def heat_inputs(tc: TransientConduction) -> list[str]:
    """The heat inputs of the stack's reduced basis: the raceways and the ball nodes."""
    return ([f"raceway_{r}" for r in RINGS if f"raceway_{r}" in tc.a]
            + [k for k in ("ball_A", "ball_B") if k in tc.a])


@single_thread_blas
def thermal_model(pl: Pipeline, progress=None) -> ThermalModel:
    """The reduced transient model of `pl`'s assembly (module docstring), built on first use and
    kept on the pipeline."""
    hit = getattr(pl, "_thermal_model", None)
    if hit is not None:
        return hit
    say = progress or (lambda s: None)
    asm, m = pl.asm, pl.model
    th = asm.thermal
    T_ref = asm.T_ref_C
    say("transient conduction: the reduced model of the stack ...")
    tc = stack_conduction(pl)
    films = resolve_films(th.films_W_m2K(), tc.groups)
    c = contacts(pl, tc)
    h_fit, G = c.fit_W_m2K, c.ball_W_K
    emis = ({k: th.emissivity for k in tc.groups if not k.startswith("raceway_")}
            if th.emissivity > 0 else {})
    nominal = ThermalParameters(film_W_m2K=films, fit_conductance_W_m2K=tuple(h_fit),
                                ball_inner_W_K=G[0], ball_outer_W_K=G[1], emissivity=emis,
                                T_rad_lin_C=T_ref, bore_conductance_W_m2K=c.bore_W_m2K)
    training = [replace(nominal, film_W_m2K={k: s * v for k, v in films.items()},
                        fit_conductance_W_m2K=tuple(h_fit * f), ball_inner_W_K=G[0] * b,
                        ball_outer_W_K=G[1] * b) for s, f, b in TRAINING]
    rc = ReducedConduction(tc, cached_basis(pl, tc, training, heat_inputs(tc), say))
    half = rc.truncated(max(1, int(HALF * rc.m)))
    probe = pl.full_fe().probe
    try:
        ms = modal_structure(pl.solver, probe, rc, T_ref, RINGS, pl.setup.condensed)
    except ValueError as exc:     # a CTE slope or bonded fits: not linear in the modes
        raise ConfigError(f'thermal.mode = "transient": {exc}') from None
    ms_half = modal_structure(pl.solver, probe, half, T_ref, RINGS, pl.setup.condensed)
    out = ThermalModel(tc, rc, half, ms, ms_half, nominal, group_rows(tc), c.pressure,
                       c.surfaces)
    pl._thermal_model = out
    return out


#: format of the cached reduced basis (raise when the file layout or the basis changes; 2: one
#: energy per mode, the files of 1 held one per moment; 3: a stack with no films has its own
#: moments, the files of 2 held the uniform field alone for it)
BASIS_FORMAT = 3


class BasisCacheError(RuntimeError):
    """A cached reduced basis that is not sound for its key (one line)."""


def basis_key(pl: Pipeline, tc: TransientConduction, training, inputs) -> str:
    """SHA-256 (24 hex digits) of what the basis depends on: the FE set-up's key (section,
    materials, code versions), the model's size, the training coefficient sets, the inputs,
    the capacities (ball nodes included) and BASIS_FORMAT."""
    import hashlib
    import json

    data = {"format": BASIS_FORMAT, "setup": pl.setup.key, "n_total": int(tc.n_total),
            "training": [repr(prm) for prm in training], "inputs": list(inputs),
            "capacity_J_K": float(tc.M.diagonal().sum())}     # the ball nodes' included
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()[:24]


def cached_basis(pl: Pipeline, tc: TransientConduction, training, inputs, say=None):
    """`fem.reduced_thermal.krylov_basis` of the stack, cached beside the FE set-ups
    (`meshes.cache`: hash-named .npz, atomic write, checked on read, rebuilt with a warning)."""
    from fem.reduced_thermal import ReducedBasis
    from meshes.cache import cache_dir, cached_file, npz_arrays

    d = cache_dir("setups", "reduced thermal basis")
    key = basis_key(pl, tc, training, inputs)

    def make(tmp):
        if say:
            say("transient conduction: reducing the stack (once; cached) ...")
        b = krylov_basis(tc, training, inputs)
        with open(tmp, "wb") as fh:
            np.savez(fh, key=np.array(key), V=b.V, energy=b.energy)

    def read(path):
        a = npz_arrays(path, BasisCacheError)
        if set(a) != {"key", "V", "energy"} or str(a["key"]) != key:
            raise BasisCacheError("not the basis of this stack")
        V, e = a["V"], a["energy"]
        if (V.ndim != 2 or V.shape[0] != tc.n_total or e.shape != (V.shape[1],)
                or not np.all(np.isfinite(V))):
            raise BasisCacheError("its arrays are not sound")
        return ReducedBasis(V, e)

    return cached_file(d / f"thermal_{key}.npz", make, read, what="reduced thermal basis",
                       writer="bearingfem", error=BasisCacheError)


@dataclass(frozen=True)
class Environment:
    """The transient conditions of a table (arrays per row): films' fluid temperature, radiation
    sink, film factor, extra heat into the pair (W)."""
    T_ambient_C: np.ndarray
    T_sink_C: np.ndarray
    film_scale: np.ndarray
    heat_W: np.ndarray


def environment(asm: Assembly, cols: dict, where: str = "conditions") -> Environment:
    """The environment columns of a transient table, checked (TableError, one line)."""
    n = len(cols["time_s"]) if "time_s" in cols else 0
    if "time_s" not in cols:
        raise TableError(f"{where}: column 'time_s': required in transient mode "
                         "([thermal] mode = \"transient\")")
    for c in cols:
        if c.startswith("T_") and c.endswith("_C") and c not in ("T_ambient_C", "T_sink_C"):
            raise TableError(f"{where}: column '{c}': part temperatures are computed in transient "
                             "mode; give T_ambient_C or T_sink_C")
    if "T_ambient_C" not in cols and "T_sink_C" not in cols:
        raise TableError(f"{where}: needs the column T_ambient_C or T_sink_C in transient mode")
    amb = np.asarray(cols.get("T_ambient_C", cols.get("T_sink_C")), float)
    sink_default = asm.thermal.sink_C if np.isfinite(asm.thermal.sink_C) else amb
    sink = np.asarray(cols.get("T_sink_C", np.broadcast_to(sink_default, (n,))), float)
    scale = np.asarray(cols.get("film_scale", np.ones(n)), float)
    heat = np.asarray(cols.get("heat_W", np.zeros(n)), float)
    for name, v, lo in (("T_ambient_C", amb, -273.15), ("T_sink_C", sink, -273.15),
                        ("film_scale", scale, 0.0), ("heat_W", heat, 0.0)):
        bad = np.flatnonzero(~np.isfinite(v) | (v < lo))
        if bad.size:
            raise TableError(f"{where}: row {bad[0] + 1}, column '{name}': {v[bad[0]]:g} below "
                             f"{lo:g}")
    return Environment(amb, sink, scale, heat)


@dataclass(frozen=True)
class RowTemperatures:
    """What the transient route adds to the rows (docs/cli.md "Transient conduction").

    T_parts_C (n, len(PARTS)): computed volume mean of each `inputs.PARTS` group (NaN where the
    stack has no such part); T_max_C, T_min_C (n,): extremes of the field (ball nodes included);
    heat_bearing_W (n,): the pair's friction heat at the row's state plus the extra heat_W;
    reduction_error_est (n,): |P_m - P_m/2| / |P_m| (module docstring)."""
    T_parts_C: np.ndarray
    T_max_C: np.ndarray
    T_min_C: np.ndarray
    heat_bearing_W: np.ndarray
    reduction_error_est: np.ndarray

    def part_columns(self) -> dict[str, np.ndarray]:
        return {f"T_{p}_C": self.T_parts_C[:, i] for i, p in enumerate(PARTS)
                if not np.isnan(self.T_parts_C[:, i]).any()}


@dataclass(frozen=True)
class TransientRun:
    """A transient table's answer. outputs: the one route's `SimulationResult` of the rows at
    their computed states; rows: `RowTemperatures`; grid_s, q:
    the time grid and the reduced states on it; heat_W (n_steps,): heat into the stack at each
    step (the pair's at the coupling plus the extra)."""
    outputs: SimulationResult
    rows: RowTemperatures
    grid_s: np.ndarray
    q: np.ndarray
    heat_W: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """The output columns of `simulate` in transient mode: the computed part temperatures,
        T_max_C, T_min_C, the route's columns (`columns.to_columns`, flags and margins last;
        not its heat_W, the name of the conditions' extra heat), heat_bearing_W,
        reduction_error_est before the flags."""
        r = self.rows
        cols = to_columns(self.outputs, friction_split=True)
        # the route's heat_W (the torque's dissipated power) would overwrite the conditions'
        # column of the same name (the extra heat); the heat into the stack is heat_bearing_W
        cols.pop("heat_W", None)
        flags = {k: cols.pop(k) for k in list(cols) if k.startswith(("flag_", "margin_"))}
        return {**r.part_columns(), "T_max_C": r.T_max_C, "T_min_C": r.T_min_C, **cols,
                "heat_bearing_W": r.heat_bearing_W, "reduction_error_est": r.reduction_error_est,
                **flags}


def _grid(t: np.ndarray, dt_s: float = DT_S) -> np.ndarray:
    """The time grid from the first to the last row: equal steps of dt_s or a little less
    (longer when the table spans more than MAX_STEPS of them)."""
    span = float(t[-1] - t[0])
    if span <= 0:
        return t[:1].astype(float)
    k = int(np.ceil(span / max(dt_s, span / MAX_STEPS) - 1e-9))
    return t[0] + span * np.arange(k + 1) / k


def _interp_rows(grid: np.ndarray, t: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Q (n_grid, m) linearly interpolated to the times t."""
    return np.column_stack([np.interp(t, grid, Q[:, j]) for j in range(Q.shape[1])])


@single_thread_blas
def run_transient(pl: Pipeline, cols: dict, progress=None, first_row: int = 0,
                  couple_every: int = COUPLE_EVERY, dt_s: float = DT_S) -> TransientRun:
    """Every row of a transient conditions table (column -> array, TRANSIENT_COLUMNS) through
    the reduced transient loop (module docstring); the coupling refreshed every `couple_every`
    steps, the step dt_s (s; `_grid`)."""
    asm = pl.asm
    env = environment(asm, cols)
    tm = thermal_model(pl, progress)
    t = np.asarray(cols["time_s"], float)
    base, delta, ref1, _ = _row_setup(pl, cols, 0)
    grid = _grid(t, dt_s)
    at = lambda v: np.interp(grid, t, np.asarray(v, float))        # noqa: E731
    amb, sink, scale, extra = at(env.T_ambient_C), at(env.T_sink_C), at(env.film_scale), at(env.heat_W)
    speed, preload = at(base.speed_rpm), at(base.preload_assembled_N)
    axial, radial, moment = at(base.axial_load_N), at(base.radial_load_N), at(base.moment_Nmm)
    w2 = (speed * (2.0 * np.pi / 60.0)) ** 2
    steppers = []
    for rc in (tm.rc, tm.half):
        st = ReducedStepper(rc, _params(tm, 1.0, None), grid[1] - grid[0] if grid.size > 1 else DT_S,
                            float(amb[0]))
        steppers.append(st)
    Q = [steppers[0].q.copy()]
    Qh = [steppers[1].q.copy()]
    heat_in = np.zeros(grid.size)
    h_pair: dict[str, float] = {}
    fits_W_m2K = tm.nominal.fit_conductance_W_m2K
    balls = (tm.nominal.ball_inner_W_K, tm.nominal.ball_outer_W_K)
    pair_W = 0.0
    for k in range(1, grid.size):
        if (k - 1) % couple_every == 0:
            # the coupling at the state at the start of the step
            c = _couple(pl, tm, Q[-1], base, delta, w2[k - 1:k], ref1, speed[k - 1],
                        preload[k - 1], axial[k - 1], radial[k - 1], moment[k - 1])
            pair_W = float(c.heat.total_W[0])
            balls = (c.contacts[0].G_W_K, c.contacts[1].G_W_K)
            h_pair = c.heat_inputs_W
            if c.fit_conductance_W_m2K is not None:
                fits_W_m2K = c.fit_conductance_W_m2K
        h = _with_extra(h_pair, float(extra[k]))
        heat_in[k] = pair_W + float(extra[k])
        loads = StepLoads(float(amb[k]), float(sink[k]), heat_W=h)
        prm = _params(tm, float(scale[k]), fits_W_m2K, balls)
        for st, QQ in ((steppers[0], Q), (steppers[1], Qh)):
            if prm != st.prm:
                st.set_parameters(prm)
            QQ.append(st.step(loads).copy())
        if progress and k % 500 == 0:
            progress(f"transient: step {k} of {grid.size - 1}")
    Q, Qh = np.array(Q), np.array(Qh)
    heat_in[0] = heat_in[1] if grid.size > 1 else 0.0
    q_rows, qh_rows = _interp_rows(grid, t, Q), _interp_rows(grid, t, Qh)
    T, out, heat_W = _evaluate_rows(pl, tm, tm.rc, tm.ms, q_rows, base, first_row)
    _, out_h, _ = _evaluate_rows(pl, tm, tm.half, tm.ms_half, qh_rows, base, first_row)
    P, Ph = _preload_N(out), _preload_N(out_h)
    with np.errstate(divide="ignore", invalid="ignore"):
        est = np.where(np.abs(P) > 0, np.abs(P - Ph) / np.abs(P), 0.0)
    if tm.half.m == tm.rc.m:          # one mode: nothing to compare with, no estimate (not 0)
        est = np.full(est.shape, np.nan)
    field = q_rows @ tm.rc.V.T              # (n, n_total) nodal temperatures and ball nodes
    rows = RowTemperatures(T, field.max(axis=1), field.min(axis=1), heat_W + env.heat_W, est)
    return TransientRun(out, rows, grid, Q, heat_in)


@dataclass(frozen=True)
class Coupling:
    """The loop's coupling at one state (what a step takes from the bearing): result (the one
    route's `SimulationResult` of the row), heat (`analytic.heat.PairHeat`, W), contacts ((inner,
    outer) `analytic.heat.ContactConductance`, per bearing), heat_inputs_W (heat input -> W, the
    raceways' and ball nodes' shares, `fem.transient.bearing_heat_inputs_W`),
    fit_conductance_W_m2K (per fit from its pressure or gap; None: fixed in the assembly)."""
    result: SimulationResult
    heat: object
    contacts: tuple
    heat_inputs_W: dict
    fit_conductance_W_m2K: np.ndarray | None


def _couple(pl: Pipeline, tm: ThermalModel, q: np.ndarray, base: PhysicsInputs, delta, w2_1,
            ref1: FEState, speed, preload, axial, radial, moment,
            heat_factor: float = 1.0) -> Coupling:
    """The coupling at reduced state q (m,) under one row's conditions (module docstring); the
    bearing's heat x heat_factor (-; 1: as the friction law gives it)."""
    fe, gap = fe_states(pl, tm.ms, q[None, :], delta, w2_1)
    T3 = _groups_C(tm, tm.rc, q[None, :])
    inp = _inputs(base, T3, speed, preload, axial, radial, moment)
    res, heat = _route(pl, inp, fe, ref1)
    if heat_factor != 1.0:
        heat = heat.scaled(heat_factor)
    T_oil = float(np.mean(T3[0, [PARTS.index(p) for p in ("inner_ring", "outer_ring", "ball")]]))
    cc = ball_contacts(pl, res.pair, float(speed), T_oil)
    h = bearing_heat_inputs_W(heat, ring_share=(cc[0].ring_share, cc[1].ring_share),
                              ball_nodes=bool(tm.tc.ball_nodes))
    fits = (fit_conductances_W_m2K(pl.model, fe.fit_pressure_MPa[0], gap[0], tm.surfaces)
            if tm.pressure_conductance else None)
    return Coupling(res, heat, cc, h, fits)


def _row_setup(pl: Pipeline, cols: dict, row: int):
    """(base inputs, the fits' deltas, the reference FE state, the row's inputs) of row `row` of
    a transient conditions table, as `run_transient` sets them up."""
    asm = pl.asm
    n = len(cols["time_s"])
    base = baseline_inputs({k: v for k, v in cols.items() if k not in ("T_ambient_C",)}, n,
                           asm.T_ref_C, asm.preload.assembled_N, asm.lubrication.speed_rpm)
    delta = pl.deltas_mm(*pl.fits_um(base))[:1]
    ref1 = pl.fe(pl.reference_inputs(base.take(np.zeros(1, int))))
    return base, delta, ref1, base.take(np.array([row % n]))


def _couple_row(pl, tm, q, setup, heat_factor: float = 1.0) -> Coupling:
    base, delta, ref1, r = setup
    w2 = (np.asarray(r.speed_rpm, float) * (2.0 * np.pi / 60.0)) ** 2
    return _couple(pl, tm, np.asarray(q, float), base, delta, w2[:1], ref1,
                   float(r.speed_rpm[0]), float(r.preload_assembled_N[0]),
                   float(r.axial_load_N[0]), float(r.radial_load_N[0]), float(r.moment_Nmm[0]),
                   heat_factor)


def coupling_at(pl: Pipeline, cols: dict, q: np.ndarray, row: int = -1) -> Coupling:
    """The coupling the loop of `run_transient` computes at reduced state q (m,) of
    `thermal_model(pl)` under row `row` of the conditions table cols (its speed, preload and
    loads): e.g. at the end of a run (`TransientRun.q[-1]`), for the heat balance of a ball
    node."""
    return _couple_row(pl, thermal_model(pl), q, _row_setup(pl, cols, row))


@dataclass(frozen=True)
class Equilibrium:
    """The steady state of the coupled loop under fixed conditions (`equilibrium`): q the
    reduced coordinates, T_parts_C the `inputs.PARTS` group means (C, NaN for a group the stack
    lacks), coupling at q (`Coupling`), iterations taken, change_K the last iteration's largest
    change of the field (K)."""
    q: np.ndarray
    T_parts_C: np.ndarray
    coupling: Coupling
    iterations: int
    change_K: float


@single_thread_blas
def equilibrium(pl: Pipeline, cols: dict, row: int = -1, tol_K: float = 1e-6,
                max_iter: int = 100, heat_factor: float = 1.0) -> Equilibrium:
    """Where the transient run under row `row` of cols, held for ever, ends: the steady state of
    the same reduced model and coupling, found without time stepping as the fixed point

        q = A(prm(q))^-1 f(heat(q), T_ambient),

    prm the film factor, fit and ball conductances and heat the bearing's heat inputs of the
    coupling at q (`coupling_at`; the extra heat_W split as in the run), A and f the reduced
    operator and load (`fem.reduced_thermal.ReducedConduction`; radiation's remainder at the
    current iterate). Starts uniform at the row's ambient; stops when the field changes by less
    than tol_K (K) at every node, else after max_iter iterations (`change_K` says how far it
    got). A second method for the end of a long run (tests/test_heatup.py). heat_factor (-)
    scales the bearing's heat at every iterate (the steady state at an end of the friction's
    model-form interval: `analytic.friction.interval`); the extra heat_W is not scaled."""
    tm = thermal_model(pl)
    rc = tm.rc
    env = environment(pl.asm, cols)
    k = row % len(cols["time_s"])
    amb, sink = float(env.T_ambient_C[k]), float(env.T_sink_C[k])
    scale, extra = float(env.film_scale[k]), float(env.heat_W[k])
    setup = _row_setup(pl, cols, row)
    q = amb * rc.q_one
    change, it = np.inf, 0
    while it < max_iter:
        it += 1
        c = _couple_row(pl, tm, q, setup, heat_factor)
        h = _with_extra(c.heat_inputs_W, extra)
        prm = _params(tm, scale, c.fit_conductance_W_m2K,
                      (c.contacts[0].G_W_K, c.contacts[1].G_W_K))
        f = rc.load(prm, StepLoads(amb, sink, heat_W=h))
        if prm.emissivity:
            _, Vd, VtR = rc.radiation_terms(prm)
            f = f - VtR @ radiation_remainder_W_mm2(Vd @ q, sink, prm.T_rad_lin_C)
        q_new = np.linalg.solve(rc.operator(prm), f)
        change = float(np.max(np.abs(rc.field(q_new - q))))
        q = q_new
        if change < tol_K:
            break
    c = _couple_row(pl, tm, q, setup, heat_factor)
    return Equilibrium(q, _groups_C(tm, rc, q[None, :])[0], c, it, change)


@dataclass(frozen=True)
class PartTemperatures:
    """Part temperatures over time from the transient conduction FE (`part_temperatures`).

    time_s (n,): the instants; T_C (n, len(parts)): volume mean temperature of each part group
    (C); parts: the group names (`inputs.PARTS`: shaft, inner_ring, ball, outer_ring, housing,
    spacer; a group the stack lacks is left out); reduction_error_est (n,): the reduced model's
    estimated relative preload error (`TransientRun.rows`)."""
    time_s: np.ndarray
    T_C: np.ndarray
    parts: tuple
    reduction_error_est: np.ndarray

    def of(self, part: str) -> np.ndarray:
        """(n,) temperatures (C) of one part group."""
        return self.T_C[:, self.parts.index(part)]


def part_temperatures(asm: Assembly, time_s, T_environment_C, speed_rpm=None, *,
                      sink: bool = False, pipeline: Pipeline | None = None,
                      progress=None) -> PartTemperatures:
    """Part temperatures over time from the transient conduction FE for an assembly and a time
    series: the second source of lagged temperatures for the diagnosis (a helper such as
    `studies/validation/second_source.py` calls it in place of the first-order `thermal_lag` effect).

    asm: the assembly; its `[thermal]` section gives the films, emissivity, sink and gas (mode
    "given" is taken as "transient" here: the films must be set for the environment to reach
    the stack). time_s (n,): strictly increasing instants (s); T_environment_C (n,): the
    chamber's temperature (C), the films' fluid (sink=False, `T_ambient_C`) or the radiation
    sink (sink=True, `T_sink_C`); speed_rpm (n,) or None (the assembly's speed): the bearing's
    friction heat is fed back as in `simulate`. pipeline: an existing `Pipeline` of the same
    assembly in transient mode (its reduced model is built once and kept on it).
    The route is `run_transient` (one route: the rows' part temperatures are those `simulate`
    in transient mode writes as T_<part>_C).

        from studies.model.transient_route import part_temperatures
        pt = part_temperatures(asm, data["time_s"], data["T_ambient_C"], data["speed_rpm"])
        lagged = {f"T_{p}_C": pt.of(p) for p in pt.parts}
    """
    if asm.thermal.mode != "transient":
        asm = replace(asm, thermal=replace(asm.thermal, mode="transient"))
    if not asm.thermal.films and asm.thermal.emissivity == 0:
        raise ConfigError("thermal: no films and no emissivity: the environment cannot reach the "
                          "stack (set [thermal.films] or emissivity)")
    t = np.asarray(time_s, float)
    cols = {"time_s": t, ("T_sink_C" if sink else "T_ambient_C"):
            np.broadcast_to(np.asarray(T_environment_C, float), t.shape).copy()}
    if speed_rpm is not None:
        cols["speed_rpm"] = np.broadcast_to(np.asarray(speed_rpm, float), t.shape).copy()
    pl = pipeline if pipeline is not None else Pipeline.shared(asm, progress=progress)
    run = run_transient(pl, cols, progress)
    keep = [i for i in range(len(PARTS)) if not np.isnan(run.rows.T_parts_C[:, i]).any()]
    return PartTemperatures(t, run.rows.T_parts_C[:, keep], tuple(PARTS[i] for i in keep),
                            run.rows.reduction_error_est)


def _with_extra(h: dict, extra_W: float) -> dict:
    """The heat inputs h (input -> W) with the extra heat extra_W (W) split by `extra_share`."""
    return {key: v + extra_W * extra_share(key, h) for key, v in h.items()}


def extra_share(key: str, h: dict) -> float:
    """Share of the extra heat (heat_W) of one heat input: like the pair's own split (half to
    the raceways, half to the balls, equally per bearing); without ball nodes all to the
    raceways."""
    balls = [k for k in h if k.startswith("ball_")]
    races = [k for k in h if k.startswith("raceway_")]
    if balls:
        return 0.5 / len(balls) if key in balls else 0.5 / len(races)
    return 1.0 / len(races)


def _params(tm: ThermalModel, film_scale: float, fit_W_m2K, balls_W_K=None) -> ThermalParameters:
    prm = replace(tm.nominal, film_W_m2K={k: film_scale * v for k, v in tm.nominal.film_W_m2K.items()})
    if balls_W_K is not None:
        prm = replace(prm, ball_inner_W_K=float(balls_W_K[0]), ball_outer_W_K=float(balls_W_K[1]))
    return prm if fit_W_m2K is None else prm.with_fits(fit_W_m2K)


def ball_contacts(pl: Pipeline, pair, speed_rpm: float, T_oil_C: float
                  ) -> tuple[ContactConductance, ContactConductance]:
    """(inner, outer) ball set-to-raceway conductance (W/K, per bearing) and heat partition of a
    pair state (`analytic.bearing.PairState`, first row, the two bearings' mean ellipse) at
    speed_rpm (rpm): `analytic.heat.rolling_contact_conductance` at the rolling speed
    (`analytic.lubrication.entrainment_speed_mm_s`), with the central EHL film of an oil
    (`analytic.lubrication.hamrock_dowson_film` at the oil temperature T_oil_C, C: the mean of
    rings and balls, as the torque stage takes it) in series, its conductivity raised by the
    contacts' Hertz peak pressure (`analytic.heat.hertz_mean_conductivity_ratio`); a solid film:
    no film term."""
    g = pl.geom
    alpha = float(np.mean(np.asarray(pair.contact_angle_deg)[:, 0]))
    u = float(lub.entrainment_speed_mm_s(speed_rpm, g.Dw_mm, g.dm_mm, alpha))
    ring = pl.materials["inner_ring_A"]
    oil = pl.lubricant if pl.asm.lubrication.kind == "oil" else None
    out = []
    for c, side, f, r in ((pair.inner, "inner", g.f_i, ring),
                          (pair.outer, "outer", g.f_o, pl.materials["outer_ring_A"])):
        a, b = float(np.mean(c.a_mm[:, 0])), float(np.mean(c.b_mm[:, 0]))
        h = 0.0
        if oil is not None and u > 0:
            Rx, Ry = lub.ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, alpha, f, side)
            Ep = lub.reduced_modulus_MPa(r.E_MPa, r.nu, g.ball.E_MPa, g.ball.nu)
            Q = max(float(np.mean(np.asarray(pair.ball_load_N)[:, 0])), 1e-6)
            h = float(lub.hamrock_dowson_film(Rx, Ry, Ep, oil.eta_Pa_s(T_oil_C), oil.alpha_per_Pa,
                                              u, Q).h_central_um)
        p0 = float(np.mean(np.asarray(c.p_max_MPa)[:, 0]))
        out.append(rolling_contact_conductance(a, b, u, g.ball, r, g.Z, film_um=h, p_max_MPa=p0))
    return out[0], out[1]


def _groups_C(tm: ThermalModel, rc: ReducedConduction, q: np.ndarray) -> np.ndarray:
    """(n, len(PARTS)) group mean temperatures (C) of reduced states q (n, m)."""
    return q @ tm.groups_per_mode(rc).T


def _inputs(base: PhysicsInputs, T: np.ndarray, speed, preload, axial, radial, moment) -> PhysicsInputs:
    """One row of inputs at group temperatures T (1, len(PARTS)) and the step's conditions."""
    one = base.take(np.zeros(1, int))
    Tc = {p: T[:, i] for i, p in enumerate(PARTS)}
    for p in PARTS:          # a group the stack lacks (no spacer): not used by the FE state
        if np.isnan(Tc[p]).any():
            Tc[p] = Tc["shaft"]
    return one.copy(T_C=Tc, speed_rpm=np.array([speed]), preload_assembled_N=np.array([preload]),
                    axial_load_N=np.array([axial]), radial_load_N=np.array([radial]),
                    moment_Nmm=np.array([moment]))


def _evaluate_rows(pl: Pipeline, tm: ThermalModel, rc: ReducedConduction, ms: ModalStructure,
                   q: np.ndarray, base: PhysicsInputs, first_row: int):
    """The rows at reduced states q through the one route: (group temperatures (n,
    len(PARTS)), the route's outputs, the pair's friction heat (n,) W)."""
    T = _groups_C(tm, rc, q)
    Tc = {p: T[:, i] for i, p in enumerate(PARTS)}
    for p in PARTS:
        if np.isnan(Tc[p]).any():
            Tc[p] = Tc["shaft"]
    inputs = base.copy(T_C=Tc)
    delta = pl.deltas_mm(*pl.fits_um(inputs))
    fe, _ = fe_states(pl, ms, q, delta, pl.fe_stage.omega2(inputs))
    ref = pl.fe(pl.reference_inputs(inputs), remember=False)
    out, heat = _route(pl, inputs, fe, ref, first_row)
    return T, out, np.asarray(heat.total_W, float).reshape(q.shape[0])


def _route(pl: Pipeline, inputs: PhysicsInputs, fe: FEState, ref: FEState, first_row: int = 0):
    """The one route from given FE states (rows, assembly states): (its outputs, the pair's heat
    split, `pair_heat`)."""
    res = pl.run(inputs, first_row=first_row, remember=False,
                 fe_options=FEOptions(states=(fe, ref)))
    return res, pair_heat(pl, res, inputs)


def pair_heat(pl: Pipeline, res: SimulationResult, inputs: PhysicsInputs):
    """The pair's heat split (`analytic.heat.PairHeat`, W per row) of a route result at its
    inputs: Palmgren's viscous heat with sliding and spin at MU_TRACTION; a solid film's own
    dissipation (its friction coefficient); with any other `viscous_model` the torque's own
    heat where it is made (`analytic.heat.located_pair_heat_W`)."""
    if res.torque.model == "solid_film":
        return solid_film_pair_heat_W(res.torque, inputs.speed_rpm)
    if res.torque.viscous_model != "palmgren":
        return located_pair_heat_W(res.torque, inputs.speed_rpm)
    return pair_heat_W(pl.geom, res.pair, inputs.speed_rpm, MU_TRACTION, res.torque.viscous_Nmm)


def _preload_N(out: SimulationResult) -> np.ndarray:
    return out.pair.preload_N


def condition_columns() -> set[str]:
    """The columns a conditions file may have in transient mode (the part temperatures among
    them only to be refused with their reason, `environment`)."""
    from studies.model.inputs import CONDITION_COLUMNS
    return set(CONDITION_COLUMNS) | set(TRANSIENT_COLUMNS)


def simulate_transient_file(asm: Assembly, conditions, out, effects: dict | None = None,
                            provenance: dict | None = None, direct: bool = False,
                            pipeline: Pipeline | None = None, progress=None,
                            workers: int | None = None, scheduler: str | None = None,
                            n_rows: int | None = None):
    """`bearingfem simulate` of an assembly in transient mode: the whole conditions file (rows
    are successive instants, evaluated in order) through `simulate_transient_columns`, one
    atomic output file (`table.TableWriter`). n_rows: not needed (the whole table is read at
    once), accepted as `stream.simulate_file` takes it."""
    from studies.model.table import TableWriter, read_table

    _refuse(effects, direct, workers, scheduler)
    cols = read_table(conditions, allowed=condition_columns())
    run, res = simulate_transient_columns(asm, cols, str(conditions), pipeline=pipeline,
                                          progress=progress)
    with TableWriter(out, provenance) as w:
        w.write(res)
    return run


def simulate_transient_columns(asm: Assembly, cols: dict, where: str = "conditions",
                               effects: dict | None = None, direct: bool = False,
                               pipeline: Pipeline | None = None, progress=None,
                               workers: int | None = None, scheduler: str | None = None):
    """The transient `simulate` of a checked conditions table in memory: (`stream.SimulateRun`,
    the columns `simulate_transient_file` writes: the conditions, then `TransientRun.columns`),
    the checks of `studies.model.checks` per row. Effects, direct solves and Dask workers are
    refused (one line): the route has its own temperatures and runs in time order."""
    from studies.model.checks import assembly_checks, plausibility_warnings
    from studies.model.stream import WARNING_OUTPUTS, CheckTally, SimulateRun

    _refuse(effects, direct, workers, scheduler)
    cols = {k: v for k, v in cols.items() if not k.startswith("_")}
    environment(asm, cols, where)                     # bad input before any FE work
    pl = pipeline or Pipeline.shared(asm, progress=progress)
    run = run_transient(pl, cols, progress)
    tally = CheckTally(assembly_checks(asm))
    outputs = run.columns()
    tally.add(run.outputs.checks, 0)
    res = dict(cols)
    res.update(outputs)
    is_T = lambda k: k.startswith("T_") and k.endswith("_C")           # noqa: E731
    temps = {k: np.asarray(v, float) for k, v in res.items() if is_T(k)}
    given = {k: v for k, v in temps.items() if k in cols}     # the warnings read the inputs
    warn_cols = {k: outputs[k] for k in WARNING_OUTPUTS if k in outputs}
    n = len(cols["time_s"])
    ranges = [r.message(n) for r in run.outputs.torque.range_notes]    # the friction law's
    return SimulateRun(n, tally.violations(), plausibility_warnings(asm, given, warn_cols) + ranges,
                       temps), res


def _refuse(effects, direct, workers, scheduler) -> None:
    """ConfigError (one line) for what the transient route cannot take."""
    for bad, what in ((effects, "--effect"), (direct, "--direct"),
                      (workers is not None or scheduler is not None, "--workers/--scheduler")):
        if bad:
            raise ConfigError(f"{what}: not available with [thermal] mode = \"transient\"")
