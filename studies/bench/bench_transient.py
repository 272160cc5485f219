"""Benchmark: a 30-minute heat-up of seed 003's stack (25TAC62B pair, 1500 rpm), 900 steps of 2 s,
through the transient conduction FE (`fem.transient`) and its reduced model
(`fem.reduced_thermal`), with fit pressures, groove-centre shifts and preload at every step.

Printed: the one-off cost of the reduction (basis, projection, structural response per mode),
the reduced transient (thermal steps, structural response, pair equilibrium of every step), the
full-FE transient (thermal steps and a direct contact solve of the structure per step), and the
largest relative errors of the reduced model against the full FE in preload, groove-centre
shifts and fit pressures, with the a-posteriori estimate beside them.

The check case is not a training point: the reduction is built from unit heat inputs at the
raceways and the ball nodes and films at 0.5 and 2 times nominal (fit conductances 0.3 and 3
times); the check runs films at 1.35 times nominal, fit conductances at 1.7 (inner) and 0.6
(outer) times, and the torque model's heat (at the assembled state) modulated in time
(+-30 %, 10-minute period) and split 60/40 between the bearings.

Heat and conductances are held per run (the coupling loop temperature -> fits -> preload ->
torque -> heat is wired into `simulate` separately); the bench's fits and preload are the
outputs of each step's temperature field.

    python -m studies.bench.bench_transient [--steps N] [--stride K]
"""
from __future__ import annotations

import argparse
from dataclasses import dataclass, replace

import numpy as np

from analytic import thermal_network as tn
from analytic.heat import pair_heat_W
from fem.reduced_thermal import ReducedConduction, ReducedStepper, krylov_basis, modal_structure
from fem.transient import (StepLoads, Stepper, ThermalParameters, TransientConduction,
                           bearing_heat_inputs_W, fit_conductances_W_m2K)
from studies.model.config import CONFIG_DIR, SHIPPED, load_assembly
from studies.model.inputs import baseline_inputs
from studies.model.pipeline import RINGS, FEOptions, FEState, Pipeline
from studies.model.transient_route import ball_contacts
from studies.bench.bench_clock import Clock

SPEED_RPM = 1500.0
MU_TRACTION = 0.03          # as the seed 003 study (sliding and spin traction, EHL)
#: films (W/m^2K): housing outside and cover (natural convection + radiation, as seed 003),
#: shaft end and journal (rotating shaft in air, as seed 003), the bearing cavity (air
#: churned by the cage, Harris & Kotzalas Vol. 2 ch. 7 order: assumption)
H_HOUSING, H_SHAFT, H_CAVITY = 15.0, 60.0, 30.0


def films(tc: TransientConduction, scale: float = 1.0) -> dict[str, float]:
    out = {}
    for g in tc.groups:
        if g.startswith("raceway_"):
            h = H_CAVITY
        elif g in ("housing_outer", "free_housing", "free_cover"):
            h = H_HOUSING
        elif g in ("shaft_end", "free_shaft", "free_nut"):
            h = H_SHAFT
        else:
            h = H_CAVITY
        out[g] = scale * h
    return out


def _inputs(pl: Pipeline, T_inner, T_outer, T_ball):
    n = len(T_inner)
    a = pl.asm
    cols = {"T_inner_ring_C": np.asarray(T_inner, float), "T_outer_ring_C": np.asarray(T_outer, float),
            "T_ball_C": np.asarray(T_ball, float), "speed_rpm": np.full(n, SPEED_RPM)}
    return baseline_inputs(cols, n, a.T_ref_C, a.preload.assembled_N, SPEED_RPM)


def _state(pl: Pipeline, force_N, probe, ring_strain) -> FEState:
    """FEState of rows from pair forces, probed displacements and ring strains (as
    `Pipeline.fe_field` builds it for a conduction field)."""
    p = pl.fe_stage.fit_pressures(force_N)
    dr, dz = pl.fe_stage.grooves.shifts_mm(probe, ring_strain)
    return FEState(p, np.full((p.shape[0], 2), np.nan), dr, dz, probe[:, :8])


def _cat(states: list[FEState]) -> FEState:
    return FEState(np.vstack([s.fit_pressure_MPa for s in states]),
                   np.vstack([s.interference_um for s in states]),
                   np.hstack([s.dr_mm for s in states]), np.hstack([s.dz_mm for s in states]),
                   np.vstack([s.raceway_u_mm for s in states]))


@dataclass(frozen=True)
class BenchResult:
    """Times (wall s) and the reduced model's largest relative errors against the full FE (and
    their a-posteriori estimates: half the modes against all), over the compared steps."""
    modes: int
    reduction_s: float
    reduced_s: float
    full_s: float
    compared_steps: int
    heat_W: float
    preload_N: tuple[float, float]
    preload_range_N: float
    preload_err: float
    preload_est: float
    preload_err_range: float
    shift_err: float
    shift_est: float
    pressure_err: float
    pressure_est: float


def _gap_um(pl: Pipeline, gap_mm: np.ndarray) -> np.ndarray:
    """(n, n_fits) mean radial gap (um) of each fit's open pairs (closed pairs count 0)."""
    fop = pl.setup.condensed.fit_of_pair
    g = np.maximum(np.atleast_2d(gap_mm), 0.0)
    return 1e3 * np.column_stack([g[:, fop == k].mean(axis=1) for k in range(fop.max() + 1)])


def run(n_steps: int = 900, dt_s: float = 2.0, stride: int = 1, update_every: int = 30
        ) -> BenchResult:
    """The heat-up through the reduced and the full model (module docstring). The fit
    conductances follow each model's own fit pressures and gaps every `update_every` steps
    (`fem.transient.fit_conductances_W_m2K`; the reduced model re-sums its affine terms, the full
    FE factorises again); the full FE's structure is solved at every `stride`-th step."""
    asm = load_assembly(CONFIG_DIR / SHIPPED["seed003"])
    pl = Pipeline(asm)
    m, g = pl.model, pl.geom
    T_ref = asm.T_ref_C
    # heat, ball conductances and fit conductances at the assembled state
    inp0 = _inputs(pl, [T_ref], [T_ref], [T_ref])
    out0 = pl.run(inp0)
    pair0 = out0.pair
    heat0 = pair_heat_W(g, pair0, np.array([SPEED_RPM]), MU_TRACTION, out0.torque.viscous_Nmm)
    # the route's ball-raceway contacts (moving-source constriction, EHL film) at the speed
    G_i, G_o = (c.G_W_K for c in ball_contacts(pl, pair0, SPEED_RPM, T_ref))
    C_ball = float(tn.heat_capacity_J_K(tn.ball_set_mass_kg(g.Dw_mm, g.Z, g.ball), g.ball))
    delta0 = pl.deltas_mm(*pl.fits_um(inp0))[0]
    w2 = (SPEED_RPM * 2 * np.pi / 60) ** 2
    res0 = pl.sup.evaluate(pl.thetas(inp0), delta0[None, :], np.array([w2]))
    h_fit = fit_conductances_W_m2K(m, pl.fe_stage.fit_pressures(res0.force_N)[0],
                                   _gap_um(pl, res0.gap_mm)[0])

    tc = TransientConduction(m, ball_capacity_J_K=C_ball)
    nominal = ThermalParameters(film_W_m2K=films(tc), fit_conductance_W_m2K=tuple(h_fit),
                                ball_inner_W_K=G_i, ball_outer_W_K=G_o)
    inputs = [f"raceway_{r}" for r in RINGS] + ["ball_A", "ball_B"]
    training = [replace(nominal, film_W_m2K=films(tc, s), fit_conductance_W_m2K=tuple(h_fit * c))
                for s, c in ((0.5, 0.3), (2.0, 3.0), (0.5, 3.0), (2.0, 0.3))]
    check = replace(nominal, film_W_m2K=films(tc, 1.35))
    t = dt_s * np.arange(1, n_steps + 1)
    mod = 1.0 + 0.3 * np.sin(2 * np.pi * t / 600.0)
    heat = [{k: v * f for k, v in bearing_heat_inputs_W(heat0, share_A=0.6).items()} for f in mod]
    loads = [StepLoads(T_ref, heat_W=h) for h in heat]
    delta = np.broadcast_to(delta0, (n_steps, delta0.size))
    w2s = np.full(n_steps, w2)
    probe = pl.full_fe().probe
    fe_ref = pl.fe(pl.reference_inputs(_inputs(pl, *[np.full(n_steps, T_ref)] * 3)))

    # --- the one-off reduction
    with Clock() as c_red:
        basis = krylov_basis(tc, training, inputs)
        rc = ReducedConduction(tc, basis)
        ms = modal_structure(pl.solver, probe, rc, T_ref, RINGS, pl.setup.condensed)
    half = rc.truncated(rc.m // 2)
    ms_half = modal_structure(pl.solver, probe, half, T_ref, RINGS, pl.setup.condensed)

    def means(rcm):
        """(3, m): inner ring A, outer ring A means and ball A node per reduced coordinate."""
        rows = tc.part_mean_rows()[[m.part_names.index(p) for p in ("inner_ring_A", "outer_ring_A")]]
        return np.vstack([rows @ rcm.V, rcm.V[tc.N:tc.N + 1]])

    def reduced_run(rcm, msm):
        st = ReducedStepper(rcm, check, dt_s, T_ref)
        Q = []
        for i, ld in enumerate(loads):
            if i and i % update_every == 0:
                r = msm.evaluate(Q[-1][None, :], delta[:1], w2s[:1])
                st.set_parameters(check.with_fits(fit_conductances_W_m2K(
                    m, pl.fe_stage.fit_pressures(r.force_N)[0], _gap_um(pl, r.gap_mm)[0])))
            Q.append(st.step(ld))
        Q = np.array(Q)
        r = msm.evaluate(Q, delta, w2s)
        fe = _state(pl, r.force_N, r.probe, r.ring_strain)
        T3 = Q @ means(rcm).T
        return fe, pl.run(_inputs(pl, T3[:, 0], T3[:, 1], T3[:, 2]),
                          fe_options=FEOptions(states=(fe, fe_ref)))

    with Clock() as c_run:
        fe_r, out_r = reduced_run(rc, ms)
    fe_h, out_h = reduced_run(half, ms_half)

    # --- the full FE: every step's thermal solve, the structure at every `stride`-th step (and
    #     at the conductance updates)
    rows = np.arange(stride - 1, n_steps, stride)
    want = set(rows.tolist()) | {i - 1 for i in range(update_every, n_steps, update_every)}
    sv = pl.solver
    with Clock() as c_full:
        st = Stepper(tc, check, dt_s, T_ref)
        states, T3 = {}, []
        for i, ld in enumerate(loads):
            if i and i % update_every == 0:
                fe_i, gap_i = states[i - 1]
                st.set_parameters(check.with_fits(fit_conductances_W_m2K(
                    m, fe_i.fit_pressure_MPa[0], gap_i)))
            T = st.step(ld)
            if i in want:
                pm = tc.part_mean_C(T)
                inp = _inputs(pl, [pm["inner_ring_A"]], [pm["outer_ring_A"]], [T[tc.N]])
                fe_i, u = pl.fe_field(tc.theta_field(T, T_ref), inp)
                gap = u[sv.slave] - u[sv.master] - delta0[sv.fit_of_pair]
                states[i] = (fe_i, _gap_um(pl, gap)[0])
                if i in rows:
                    T3.append((pm["inner_ring_A"], pm["outer_ring_A"], T[tc.N]))
        fe_f = _cat([states[i][0] for i in rows])
        T3 = np.array(T3)
        out_f = pl.run(_inputs(pl, T3[:, 0], T3[:, 1], T3[:, 2]),
                       fe_options=FEOptions(states=(fe_f, fe_ref.take(rows))))
    P_f, P_r, P_h = out_f.preload_N, out_r.preload_N[rows], out_h.preload_N[rows]
    shift = lambda fe: np.vstack([fe.dr_mm, fe.dz_mm])
    s_f, s_r, s_h = shift(fe_f), shift(fe_r)[:, rows], shift(fe_h)[:, rows]
    p_f, p_r, p_h = (fe_f.fit_pressure_MPa, fe_r.fit_pressure_MPa[rows], fe_h.fit_pressure_MPa[rows])
    rel = lambda a, b, ref: float(np.abs(a - b).max() / np.abs(ref).max())
    return BenchResult(
        modes=rc.m, reduction_s=c_red.wall_s, reduced_s=c_run.wall_s, full_s=c_full.wall_s,
        compared_steps=rows.size, heat_W=float(heat0.total_W[0]),
        preload_N=(float(P_f[0]), float(P_f[-1])), preload_range_N=float(np.ptp(P_f)),
        preload_err=float(np.max(np.abs(P_r - P_f) / np.abs(P_f))),
        preload_est=float(np.max(np.abs(P_h - P_r) / np.abs(P_f))),
        preload_err_range=float(np.abs(P_r - P_f).max() / np.ptp(P_f)),
        shift_err=rel(s_r, s_f, s_f), shift_est=rel(s_h, s_r, s_f),
        pressure_err=rel(p_r, p_f, p_f), pressure_est=rel(p_h, p_r, p_f))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=900)
    ap.add_argument("--stride", type=int, default=1,
                    help="full-FE structural solve every K-th step (thermal: every step)")
    ap.add_argument("--update-every", type=int, default=30,
                    help="fit conductances from the fit state every K steps")
    a = ap.parse_args(argv)
    r = run(a.steps, 2.0, a.stride, a.update_every)
    print(f"seed003 transient, {a.steps} steps of 2 s at {SPEED_RPM:.0f} rpm, heat {r.heat_W:.2f} W "
          f"(x 1 +- 0.3), {r.modes} thermal modes")
    print(f"reduction (one-off): {r.reduction_s:.2f} s")
    print(f"reduced transient: {r.reduced_s:.3f} s (thermal steps, fits, groove shifts, preload "
          "and torque at every step)")
    print(f"full-FE transient: {r.full_s:.2f} s (structure solved at {r.compared_steps} steps)")
    print(f"preload {r.preload_N[0]:.1f} N -> {r.preload_N[1]:.1f} N "
          f"(range {r.preload_range_N:.1f} N)")
    print(f"max relative preload error reduced vs full: {r.preload_err:.2e}")
    print(f"a-posteriori estimate of it (half the modes vs all): {r.preload_est:.2e}; the "
          f"error relative to the preload's range: {r.preload_err_range:.2e}")
    print(f"max relative groove-shift error: {r.shift_err:.2e} (estimate {r.shift_est:.2e}); "
          f"fit pressure: {r.pressure_err:.2e} (estimate {r.pressure_est:.2e}); "
          "each relative to the largest value of the full FE")


if __name__ == "__main__":
    main()
