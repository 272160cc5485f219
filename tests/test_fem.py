"""FE against closed forms, exact linearity, and the contact conditions.

Expected values come from Lamé (analytic/lame.py, itself tested against an ODE solve), from
free thermal expansion u = theta r, or from a second FE route (direct solve vs superposition)."""
import numpy as np
import pytest

from analytic import lame
from analytic.materials import get_material
from fem.model import build_model
from fem.post import element_stresses, fit_mean_pressures, theta_per_element
from fem.solver import FitSolver, Superposition
from meshes.section import two_cylinder_section
from studies.model.stack import section_from_assembly
from studies.model.config import load_shipped
from studies.usecases.verify import lame_cases, short_ring_case


def _two(ri, rf, ro, mi, mo, plane_strain=False, contact="frictionless", factor=1.0):
    sec = two_cylinder_section(ri, rf, ro, mi, mo, 10.0, plane_strain=plane_strain).scaled(factor)
    model = build_model(sec, contact)
    return sec, model, FitSolver(model)


def _lame(ri, rf, ro, mi, mo, d_um, assumption):
    a, b = get_material(mi), get_material(mo)
    return float(lame.fit_pressure_MPa(ri, rf, ro, a.E_MPa, a.nu, b.E_MPa, b.nu, d_um, assumption))


@pytest.fixture(scope="module")
def seed000_coarse():
    """Seed 000's section on a mesh coarsened 2x, its FE model and one solver shared by the
    tests below (the solver keeps a factorisation per contact status: built once here)."""
    sec = section_from_assembly(load_shipped("seed000")).scaled(2.0)
    model = build_model(sec)
    return sec, model, FitSolver(model)


@pytest.mark.requirement("R-FE-LAME")
def test_every_verify_lame_case_within_half_percent():
    for c in lame_cases(mesh_factor=2.0):   # coarser than the default mesh: still far inside
        if c.kind in ("lame_fit", "lame_displacement", "free_thermal"):
            assert c.rel_error < 1e-4, c.name


def test_free_thermal_growth_is_exact_and_stress_free():
    sec, model, solver = _two(0.0, 10.0, 15.0, "TC4", "TC4")
    theta = np.full(len(model.part_names), get_material("TC4").thermal_strain(120.0, 20.0))
    sol = solver.solve(model.unit_loads @ theta, [0.0])
    x = model.sbasis.doflocs
    # u_r = theta r and u_z = theta (z - z_fixed): P2 represents both exactly
    assert np.allclose(sol.u[0::2], theta[0] * x[0], atol=1e-12)
    vm = element_stresses(model, sol.u, theta_per_element(model, theta))["von_mises_MPa"]
    assert vm.max() < 1e-6


@pytest.mark.requirement("R-FE-LAME")
def test_bonded_with_rollers_equals_plane_strain_lame_including_tension():
    # with u_z = 0 everywhere the bonded and frictionless fits coincide, and a tied fit carries
    # tension: a clearance gives the Lamé pressure of the negative interference
    for d_um in (8.0, -8.0):
        sec, model, solver = _two(0.0, 10.0, 15.0, "52100", "9Cr18", plane_strain=True,
                                  contact="bonded")
        sol = solver.solve(np.zeros(model.ndofs), [d_um / 2000])
        p = fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0, 0]
        a, b = get_material("52100"), get_material("9Cr18")
        comp = lame.fit_compliance_mm_per_MPa(0.0, 10.0, 15.0, a.E_MPa, a.nu, b.E_MPa, b.nu,
                                              "plane_strain")
        assert p == pytest.approx(d_um / 2000 / comp, rel=1e-5)


@pytest.mark.requirement("R-FE-CONTACT")
def test_clearance_fit_stays_open_with_zero_force_and_the_right_gap():
    sec, model, solver = _two(22.1, 23.5, 30.0, "9Cr18", "TC4")
    sol = solver.solve(np.zeros(model.ndofs), [-1.5 / 2000])
    assert not sol.closed.any() and np.all(sol.force_N == 0)
    assert np.allclose(sol.gap_mm, 1.5 / 2000, rtol=1e-9)


def test_short_ring_pressure_between_plane_stress_and_plane_strain():
    c = short_ring_case(mesh_factor=1.5)
    assert c.bounds.within_bounds, c


def test_rigid_body_fix_adds_no_force(seed000_coarse):
    sec, model, solver = seed000_coarse
    theta = np.array([model.materials[p].thermal_strain(80.0, 20.0) for p in model.part_names])
    f = model.unit_loads @ theta
    sol = solver.solve(f, [0.0025, 0.0025, -0.00075, -0.00075])
    R = model.K @ sol.u - f
    z_fixed = [d for d in model.dirichlet if d % 2 == 1 and model.sbasis.doflocs[0, d // 2] > 0]
    assert len(z_fixed) == 2    # one axial reference each for rotor and stator
    assert np.abs(R[z_fixed]).max() < 1e-9 * np.abs(f).max()


@pytest.mark.requirement("R-FE-CONTACT")
def test_superposition_equals_direct_across_fit_opening_and_closing(seed000_coarse):
    """TC4 shaft in a 9Cr18 ring (+5 um) opens near 120 C; the outer clearance (-1.5 um) closes
    near 41 C (CTE difference): sweep across both, superposed vs direct to 1e-8."""
    sec, model, solver = seed000_coarse
    probe = model.probe_matrix(np.array(list(sec.raceway_points.values())).T)
    sup = Superposition(solver, probe)
    T = np.linspace(-60.0, 160.0, 23)
    theta = np.array([[model.materials[p].thermal_strain(t, 20.0) for p in model.part_names] for t in T])
    delta = np.tile([0.0025, 0.0025, -0.00075, -0.00075], (T.size, 1))
    res = sup.evaluate(theta, delta)
    p_sup = fit_mean_pressures(model, solver.fit_of_pair, res.force_N)
    assert p_sup[0, 0] > 0 and p_sup[-1, 0] == 0          # inner fit opened
    assert p_sup[0, 2] == 0 and p_sup[-1, 2] > 0          # outer fit closed
    for i in range(T.size):
        d = solver.solve(model.unit_loads @ theta[i], delta[i])
        scale = np.abs(d.force_N).max() + 1e-30
        assert np.abs(res.force_N[i] - d.force_N).max() <= 1e-8 * max(scale, 1.0)
        up = probe @ d.u
        assert np.abs(res.probe[i] - up).max() <= 1e-8 * np.abs(up).max()
    u_field = sup.field(theta[5], delta[5])
    d = solver.solve(model.unit_loads @ theta[5], delta[5])
    assert np.abs(u_field - d.u).max() <= 1e-8 * np.abs(d.u).max()


def test_superposition_of_a_shuffled_cycle_matches_direct_solves_in_any_order(seed000_coarse):
    """The superposition tries its states sorted (`fem.solver.state_order`), not in row order:
    a shuffled -60..160 C programme (fits opening and closing, several active sets) gives each
    state the direct FE solve's contact forces (a second route) to 1e-8, and the same forces in
    any order of the rows to 1e-12 of the largest (only the rounding of the back-substitution
    may differ)."""
    sec, model, solver = seed000_coarse
    sup = Superposition(solver)
    T = np.random.default_rng(3).permutation(np.tile(np.linspace(-60.0, 160.0, 12), 3))
    theta = np.array([[model.materials[p].thermal_strain(t, 20.0) for p in model.part_names]
                      for t in T])
    delta = np.tile([0.0025, 0.0025, -0.00075, -0.00075], (T.size, 1))
    res = sup.evaluate(theta, delta)
    assert len(res.closed_sets) >= 2
    for i in range(0, T.size, 5):
        d = solver.solve(model.unit_loads @ theta[i], delta[i])
        assert np.abs(res.force_N[i] - d.force_N).max() <= 1e-8 * max(np.abs(d.force_N).max(), 1.0)
    rev = sup.evaluate(theta[::-1], delta[::-1])
    assert np.abs(rev.force_N[::-1] - res.force_N).max() <= 1e-12 * np.abs(res.force_N).max()


def test_fit_rates_follow_the_cte_difference():
    """Seed 000: the free interference changes by (alpha_TC4 - alpha_9Cr18) d per kelvin; the FE
    fit pressure changes with the Lamé compliance of that interference (two-cylinder model)."""
    sec, model, solver = _two(12.5, 17.5, 18.9, "TC4", "9Cr18", factor=2.0)
    ps = []
    for T in (0.0, 40.0):
        theta = np.array([model.materials[p].thermal_strain(T, 20.0) for p in model.part_names])
        sol = solver.solve(model.unit_loads @ theta, [5.0 / 2000])
        ps.append(fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0, 0])
    a, b = get_material("TC4"), get_material("9Cr18")
    eff = [lame.interference_at_temperature_um(5.0, 35.0, a, b, T, 20.0) for T in (0.0, 40.0)]
    expect = [_lame(12.5, 17.5, 18.9, "TC4", "9Cr18", e, "plane_stress") for e in eff]
    assert ps == pytest.approx(expect, rel=1e-5)


def test_pressure_distribution_of_a_lame_fit_is_uniform_and_sums_to_the_force():
    """Plane-stress Lamé: uniform pressure along the fit; the tributary areas add to 2 pi R L."""
    from fem.post import fit_results

    sec, model, solver = _two(12.5, 17.5, 18.9, "TC4", "9Cr18")
    sol = solver.solve(np.zeros(model.ndofs), [5.0 / 2000])
    fr = fit_results(model, solver.fit_of_pair, sol.force_N)[0]
    p_lame = _lame(12.5, 17.5, 18.9, "TC4", "9Cr18", 5.0, "plane_stress")
    assert fr.status == "closed"
    assert np.allclose(fr.pressure_MPa, p_lame, rtol=5e-4)    # nodal tractions of a P2 solution: ~1.5e-4 here
    assert fr.mean_pressure_MPa == pytest.approx(p_lame, rel=1e-6)
