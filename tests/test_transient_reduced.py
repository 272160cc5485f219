"""Reduced transient conduction and its structural response per mode (fem/reduced_thermal.py)
against the full FE (fem/transient.py, fem/solver.py direct contact solves); the heat split of
the bearing into FE heat inputs (fem/transient.bearing_heat_inputs_W)."""
from dataclasses import replace

import numpy as np
import pytest

from analytic.heat import PairHeat
from fem.reduced_thermal import ReducedConduction, ReducedStepper, krylov_basis, modal_structure
from fem.transient import (StepLoads, Stepper, ThermalParameters, TransientConduction,
                           bearing_heat_inputs_W)

RINGS = ("inner_ring_A", "inner_ring_B", "outer_ring_A", "outer_ring_B")
INPUTS = [f"raceway_{r}" for r in RINGS] + ["ball_A", "ball_B"]


@pytest.fixture(scope="module")
def setup():
    from studies.model.config import load_assembly
    from studies.model.pipeline import Pipeline

    pl = Pipeline(load_assembly("studies/configs/seed003_25TAC62B.toml"))
    tc = TransientConduction(pl.model, ball_capacity_J_K=15.0)
    films = {"housing_outer": 15.0, "free_housing": 15.0, "free_cover": 15.0, "shaft_end": 60.0,
             "free_shaft": 60.0, "free_nut": 60.0}
    nominal = ThermalParameters(film_W_m2K=films, fit_conductance_W_m2K=(4e3, 4e3, 1e3, 1e3),
                                ball_inner_W_K=0.5, ball_outer_W_K=0.7)
    scale = lambda s, c: replace(nominal, film_W_m2K={k: s * v for k, v in films.items()},
                                 fit_conductance_W_m2K=tuple(c * np.array(nominal.fit_conductance_W_m2K)))
    # the housing's outer face as an input too: a uniform flux there carries the radiation
    # exchange of the second case (its sink and the nonlinear remainder)
    basis = krylov_basis(tc, [scale(0.5, 0.3), scale(2.0, 3.0)], INPUTS + ["housing_outer"],
                         shifts_per_s=(0.0, 3e-3, 3e-2))
    return pl, tc, ReducedConduction(tc, basis), scale


@pytest.mark.parametrize("radiation", [False, True])
def test_reduced_transient_follows_the_full_fe_off_the_training_points(setup, radiation):
    """Films at 1.35 x and fit conductances at 1.7 x nominal (no training point), raceway and
    ball heat varying in time (and, in the second case, the housing radiating with emissivity
    0.8 to a sink at -20 C: the training saw a uniform flux on that face, not radiation): the reduced temperatures stay
    within 1e-3 of the temperature change of the full FE (BDF2, 150 steps of 4 s), and the
    coarser half of the basis is further off than the whole (the error falls with the modes:
    what the estimate relies on)."""
    pl, tc, rc, scale = setup
    prm = scale(1.35, 1.7)
    if radiation:
        prm = replace(prm, emissivity={"housing_outer": 0.8}, T_rad_lin_C=0.0)
    full = Stepper(tc, prm, 4.0, 25.0)
    red = ReducedStepper(rc, prm, 4.0, 25.0)
    half = ReducedStepper(rc.truncated(rc.m // 2), prm, 4.0, 25.0)
    err, err_half, rise = 0.0, 0.0, 0.0
    for i in range(150):
        f = 1 + 0.4 * np.sin(i / 10)
        ld = StepLoads(25.0, T_sink_C=-20.0, heat_W={"raceway_inner_ring_A": 2.0 * f, "raceway_outer_ring_B": 1.0,
                                     "ball_A": 3.0 * f, "ball_B": 2.5})
        T = full.step(ld)
        err = max(err, np.abs(rc.field(red.step(ld)) - T).max())
        err_half = max(err_half, np.abs(half.rc.field(half.step(ld)) - T).max())
        rise = max(rise, np.abs(T - 25.0).max())
    assert err < 1e-3 * rise
    assert err_half > err


def test_reduced_operator_is_the_projection_of_the_fe_operator(setup):
    """The reduced matrices re-summed for new coefficients equal V^T A(prm) V of the FE's
    operator assembled for them (affine in films, conductances, ball links): to 1e-12 of its
    largest entry."""
    pl, tc, rc, scale = setup
    prm = replace(scale(0.8, 2.2), ball_inner_W_K=0.9, emissivity={"housing_outer": 0.7})
    A = rc.V.T @ (tc.operator(prm) @ rc.V)
    assert np.abs(rc.operator(prm) - A).max() < 1e-12 * np.abs(A).max()


def test_modal_structure_equals_the_direct_contact_solve(setup):
    """For a temperature field of the reduced space the structural superposition per mode gives
    the pair forces and probed displacements of a direct FE solve with its exact active set
    (fem.solver.FitSolver.solve on the field's thermal load), to 1e-8 of their largest value;
    at speed (centrifugal column) and with the as-built interferences (inner fits closed, outer
    fits with clearance)."""
    pl, tc, rc, scale = setup
    ms = modal_structure(pl.solver, pl.full_fe().probe, rc, 25.0, RINGS, pl.setup.condensed)
    st = ReducedStepper(rc, scale(1.0, 1.0), 20.0, 25.0)
    for _ in range(30):
        q = st.step(StepLoads(25.0, heat_W={"ball_A": 8.0, "raceway_inner_ring_B": 4.0}))
    w2 = (1500.0 * 2 * np.pi / 60) ** 2
    delta = np.array([1.5e-3, 1.5e-3, -2.5e-3, -2.5e-3])
    res = ms.evaluate(q[None, :], delta[None, :], np.array([w2]))
    m = pl.model
    T = rc.field(q)
    sol = pl.solver.solve(m.thermal_load_vector(tc.theta_field(T, 25.0)) + w2 * m.spin_load, delta)
    assert np.abs(res.force_N[0] - sol.force_N).max() < 1e-8 * np.abs(sol.force_N).max()
    probe = pl.full_fe().probe @ sol.u
    assert np.abs(res.probe[0] - probe).max() < 1e-8 * np.abs(probe).max()
    # ring mean strains: the mean of alpha (T - T_ref) over the ring elements by area
    dx = m.basis.dx
    th = tc.theta_field(T, 25.0)
    for k, r in enumerate(RINGS):
        sel = m.part_of == r
        assert res.ring_strain[0, k] == pytest.approx((th[sel] * dx[sel]).sum() / dx[sel].sum(),
                                                         rel=1e-9)


def test_bearing_heat_is_deposited_without_loss():
    """The heat inputs add up to the pair's heat (inner + outer contacts = sliding + spin +
    viscous) to round-off, with the ring/ball and A/B shares as asked; without ball nodes the
    rings take it all."""
    h = PairHeat(np.array([3.0]), np.array([1.0]), np.array([2.0]), np.array([3.5]), np.array([2.5]))
    q = bearing_heat_inputs_W(h, ring_share=0.4, share_A=0.7)
    assert sum(q.values()) == pytest.approx(float(h.total_W[0]), rel=1e-14)
    assert q["raceway_inner_ring_A"] == pytest.approx(0.4 * 3.5 * 0.7, rel=1e-14)
    assert q["ball_B"] == pytest.approx(0.6 * 6.0 * 0.3, rel=1e-14)
    q2 = bearing_heat_inputs_W(h, ball_nodes=False)
    assert sum(q2.values()) == pytest.approx(6.0, rel=1e-14) and "ball_A" not in q2
    assert q2["raceway_outer_ring_B"] == pytest.approx(2.5 * 0.5, rel=1e-14)


def test_basis_energy_has_one_value_per_mode_and_is_the_kept_pod_spectrum(setup):
    """`ReducedBasis.energy` holds one POD eigenvalue per column of V (inf for the uniform field
    first), non-increasing, every kept one above tol x the largest: with a tolerance that drops
    modes (1e-2 here) the lengths must still agree, and the kept modes are those the eigenvalues
    of the moments' Gram matrix in the M inner product select (a second, dense computation)."""
    pl, tc, rc, scale = setup
    tol = 1e-2
    b = krylov_basis(tc, [scale(1.0, 1.0)], ["ball_A", "raceway_outer_ring_B"],
                     shifts_per_s=(0.0, 1e-2), tol=tol)
    assert b.energy.shape == (b.V.shape[1],)
    assert np.isinf(b.energy[0]) and np.all(np.isfinite(b.energy[1:]))
    e = b.energy[1:]
    assert np.all(np.diff(e) <= 0) and e[-1] > tol * e[0]
    # the POD spectrum recomputed: moments without the uniform part, normalised, Gram in M
    from scipy.sparse.linalg import splu
    A = tc.operator(scale(1.0, 1.0))
    B = np.column_stack([tc.load(scale(1.0, 1.0), StepLoads(1.0, 1.0)), tc.a["ball_A"],
                         tc.a["raceway_outer_ring_B"]])     # the ambient drive, the inputs
    X = []
    for s in (0.0, 1e-2):
        lu = splu((tc.P.T @ (s * tc.M + A) @ tc.P).tocsc())
        X.append(tc.P @ lu.solve(np.asfortranarray(tc.P.T @ B)))
    X = np.column_stack(X)
    u0 = np.ones(tc.n_total) / np.sqrt(np.ones(tc.n_total) @ (tc.M @ np.ones(tc.n_total)))
    X = X - np.outer(u0, u0 @ (tc.M @ X))
    X = X / np.sqrt(np.einsum("ij,ij->j", X, tc.M @ X))
    w = np.sort(np.linalg.eigvalsh(X.T @ (tc.M @ X)))[::-1]
    kept = w[w > tol * w[0]]
    assert kept.size < w.size, "the case must drop modes"
    assert np.allclose(e, kept, rtol=1e-8, atol=1e-12 * w[0])


def test_bearing_heat_with_a_partition_per_raceway_is_deposited_without_loss():
    """Ring shares per raceway (inner 0.4, outer 0.7, as `analytic.heat.
    rolling_contact_conductance` gives them for unlike materials): the inputs still add up to
    the pair's heat, each raceway takes its share, the balls the rest."""
    h = PairHeat(np.array([3.0]), np.array([1.0]), np.array([2.0]), np.array([3.5]), np.array([2.5]))
    q = bearing_heat_inputs_W(h, ring_share=(0.4, 0.7))
    assert sum(q.values()) == pytest.approx(6.0, rel=1e-14)
    assert q["raceway_inner_ring_B"] == pytest.approx(0.4 * 3.5 * 0.5, rel=1e-14)
    assert q["raceway_outer_ring_A"] == pytest.approx(0.7 * 2.5 * 0.5, rel=1e-14)
    assert q["ball_A"] == pytest.approx((0.6 * 3.5 + 0.3 * 2.5) * 0.5, rel=1e-14)
    with pytest.raises(ValueError):
        bearing_heat_inputs_W(h, ring_share=(0.4, 1.2))


def test_a_stack_with_no_films_keeps_its_field_and_stores_every_watt(setup):
    """No film and no radiation (adiabatic outside, the space pair without
    [thermal.films]): the ambient drive is zero and the steady state does not exist. The reduced
    model must still follow the full FE's field (raceway and ball heat; before, its basis was
    the uniform field alone: every part at one temperature, 3.5 K off here) to 1e-3 of the full
    FE's spread, and store every joule: the heat-capacity-weighted mean rise equals the closed
    form of a lumped adiabatic body, sum(Q) t / sum(C) (energy balance: heat in = stored), to
    1e-9 of the rise."""
    pl, tc, _, scale = setup
    adiabatic = replace(scale(1.0, 1.0), film_W_m2K={})
    rc = ReducedConduction(tc, krylov_basis(tc, [replace(adiabatic, fit_conductance_W_m2K=tuple(
        c * np.array(adiabatic.fit_conductance_W_m2K))) for c in (0.3, 3.0)], INPUTS))
    prm = replace(adiabatic, fit_conductance_W_m2K=tuple(1.7 * np.array(adiabatic.fit_conductance_W_m2K)))
    full, red = Stepper(tc, prm, 4.0, -40.0), ReducedStepper(rc, prm, 4.0, -40.0)
    ld = StepLoads(20.0, heat_W={"raceway_inner_ring_A": 2.0, "ball_A": 3.0, "raceway_outer_ring_B": 1.0})
    err = 0.0
    for _ in range(150):
        T = full.step(ld)
        Tr = rc.field(red.step(ld))
        err = max(err, np.abs(Tr - T).max())
    C = tc.M @ np.ones(tc.n_total)            # J/K per DOF (ball nodes included)
    rise = 6.0 * 150 * 4.0 / C.sum()          # K: 6 W for 600 s into a lumped adiabatic body
    assert C @ (Tr + 40.0) / C.sum() == pytest.approx(rise, rel=1e-9)
    assert C @ (T + 40.0) / C.sum() == pytest.approx(rise, rel=1e-9)
    assert T.max() - T.min() > 1.0            # the heat is not spread instantly: a field
    assert err < 1e-3 * (T.max() - T.min())
