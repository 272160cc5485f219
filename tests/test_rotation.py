"""Rotating parts: the rotating-disc closed form, the FE centrifugal load
against it, superposition at speed against direct FE solves, and the fit-loosening speed."""
import dataclasses
import math

import numpy as np
import pytest

from analytic import lame
from analytic.materials import get_material
from fem.setup import SetupSpec
from meshes.section import two_cylinder_section
from studies.model.config import load_shipped
from studies.model.pipeline import Pipeline, table_inputs
from studies.usecases.verify import TOLERANCE, rotating_cases
from studies.model.columns import to_columns


def _hooke_stresses(u, r, h, E, nu, assumption):
    """sigma_rr, sigma_tt (MPa) of a radial displacement function u(r) by central differences:
    plane stress E/(1-nu^2)(eps_r + nu eps_t), ...; plane strain (lam + 2 mu) eps_r + lam eps_t."""
    du = (u(r + h) - u(r - h)) / (2 * h)
    er, et = du, u(r) / r
    if assumption == "plane_stress":
        c = E / (1 - nu * nu)
        return c * (er + nu * et), c * (et + nu * er)
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    return (lam + 2 * mu) * er + lam * et, lam * er + (lam + 2 * mu) * et


@pytest.mark.parametrize("assumption", ["plane_stress", "plane_strain"])
@pytest.mark.parametrize("a", [0.0, 6.0])
def test_rotating_ring_closed_form_is_in_equilibrium_with_free_faces(assumption, a):
    """u_r of `lame.rotating_displacement_mm` through Hooke's law (written out here) satisfies
    d sigma_rr/dr + (sigma_rr - sigma_tt)/r + rho omega^2 r = 0 and sigma_rr = 0 on the faces
    (Timoshenko & Goodier §32). Residuals relative to rho omega^2 b (the body force at the rim)
    and to the largest hoop stress; central differences with h = 1e-3 mm are exact to ~1e-7."""
    E, nu, rho, w, b = 200e3, 0.3, 7.8e-9, 5000.0, 20.0
    h = 1e-3

    def u(r):
        return lame.rotating_displacement_mm(r, a, b, E, nu, rho, w, assumption)

    def srr(r):
        return _hooke_stresses(u, r, h, E, nu, assumption)[0]

    r = np.linspace(max(a, 0.5) + 0.01, b - 0.01, 40)
    s_rr, s_tt = _hooke_stresses(u, r, h, E, nu, assumption)
    res = (srr(r + h) - srr(r - h)) / (2 * h) + (s_rr - s_tt) / r + rho * w * w * r
    assert np.abs(res).max() < 1e-6 * rho * w * w * b
    faces = [b] + ([a] if a > 0 else [])
    for rf in faces:        # one-sided: the face radius itself with the difference inside
        inside = rf - 2 * h if rf == b else rf + 2 * h
        assert abs(srr(np.array([inside]))[0]) < 1e-3 * np.abs(s_tt).max()


def test_hollow_disc_bore_hoop_stress_is_the_published_one():
    """Timoshenko & Goodier §32: the hoop stress at the bore of a thin rotating disc,
    sigma_tt(a) = (3 + nu)/4 rho omega^2 (b^2 + (1 - nu)/(3 + nu) a^2), from our u_r through
    Hooke's law at the free bore (sigma_rr = 0 there, so sigma_tt = E u_r / a); to round-off."""
    E, nu, rho, w, a, b = 196e3, 0.272, 7.8e-9, 3000.0, 8.0, 30.0
    s_tt = E * lame.rotating_displacement_mm(a, a, b, E, nu, rho, w) / a
    published = (3 + nu) / 4 * rho * w * w * (b * b + (1 - nu) / (3 + nu) * a * a)
    assert s_tt == pytest.approx(published, rel=1e-12)


def test_density_conversion_gives_the_si_body_force():
    """rho omega^2 r for 52100 (7810 kg/m^3) at 1000 rad/s and r = 0.1 m: 7.81e8 N/m^3 in SI,
    i.e. 0.781 N/mm^3 (1 N/m^3 = 1e-9 N/mm^3); internally N s^2/mm^4 x rad^2/s^2 x mm."""
    m = get_material("52100")
    si_N_m3 = m.density_kg_m3 * 1000.0 ** 2 * 0.1
    assert m.density_N_s2_mm4 * 1000.0 ** 2 * 100.0 == pytest.approx(si_N_m3 * 1e-9, rel=1e-14)


@pytest.fixture(scope="module")
def cases():
    return rotating_cases()


@pytest.mark.requirement("R-FE-ROTATION")
def test_rotating_fit_cases_agree_with_the_closed_form_within_half_a_percent(cases):
    """Every rotating case within 0.5 % of its closed form; the fit
    pressure of each rotating_fit case is also recomputed here from the echoed inputs alone
    (T&G §28, §32 written out again: p = (delta/2 - s(c) omega^2) / compliance)."""
    kinds = {c.kind for c in cases}
    assert {"rotating_fit", "rotating_displacement", "rotating_free", "fit_open_speed"} <= kinds
    for c in cases:
        assert c.rel_error <= TOLERANCE, c.name
    for c in (c for c in cases if c.kind == "rotating_fit"):
        i = c.inputs
        Ei, vi, Eo, vo = i["E_inner_MPa"], i["nu_inner"], i["E_outer_MPa"], i["nu_outer"]
        if i["assumption"] == "plane_strain":
            Ei, vi, Eo, vo = Ei / (1 - vi ** 2), vi / (1 - vi), Eo / (1 - vo ** 2), vo / (1 - vo)
        a, c_, b, w = i["r_inner_mm"], i["r_fit_mm"], i["r_outer_mm"], i["omega_rad_s"]
        ri, ro = 1e-12 * i["rho_inner_kg_m3"], 1e-12 * i["rho_outer_kg_m3"]

        def u_spin(r, r0, r1, E, v, rho):
            return rho * w * w * r / (8 * E) * ((3 + v) * (1 - v) * (r0 ** 2 + r1 ** 2)
                                                + (3 + v) * (1 + v) * r0 ** 2 * r1 ** 2 / r ** 2
                                                - (1 - v * v) * r * r)

        s = u_spin(c_, c_, b, Eo, vo, ro) - u_spin(c_, a, c_, Ei, vi, ri)
        comp = c_ * (((b * b + c_ * c_) / (b * b - c_ * c_) + vo) / Eo
                     + ((c_ * c_ + a * a) / (c_ * c_ - a * a) - vi) / Ei)
        p = (i["interference_um"] / 2000.0 - s) / comp
        assert c.closed_form["fit_pressure_MPa"] == pytest.approx(p, rel=1e-12)
        assert 0 < p < i["interference_um"] / 2000.0 / comp      # loosened, not open


@pytest.fixture(scope="module")
def pl001():
    return Pipeline(load_shipped("seed001"), mesh_factor=3.0)


def test_superposition_at_speed_equals_direct_fe(pl001):
    """One more unit solution scaled by omega^2 per row, contact solved per row: the same FE
    answers as a full direct solve at speed, at rest, at speed and beyond the inner fits'
    opening (active sets change), relative to each quantity's largest value."""
    a = pl001.asm
    T = np.repeat([-20.0, 60.0], 4)
    n = np.tile([0.0, 9000.0, 40000.0, 70000.0], 2)
    inp = table_inputs(a, {"T_ambient_C": T, "speed_rpm": n})
    sup, direct = pl001.fe(inp), pl001.fe(inp, direct=True)
    assert (sup.fit_pressure_MPa[n == 70000.0][:, :2] == 0).all()     # inner fits open
    for name in ("fit_pressure_MPa", "dr_mm", "dz_mm", "raceway_u_mm"):
        x, y = getattr(sup, name), getattr(direct, name)
        assert np.abs(x - y).max() <= 1e-8 * np.abs(y).max(), name


def test_speed_loosens_the_inner_fit_as_omega_squared_and_leaves_the_outer(pl001):
    """With the contact status unchanged, the FE is linear in omega^2: the pressure drop at
    2 n is 4 times the drop at n (to round-off); the stator does not spin: the outer fits do not
    change; the drop has the sign and about the size of the two-cylinder rotating Lamé drop
    (a short ring tied to its neighbours: within 10 %; measured 3.6 % at mesh x3)."""
    a = pl001.asm
    n = np.array([0.0, 3000.0, 6000.0])
    out = to_columns(pl001.run(table_inputs(a, {"T_ambient_C": np.full(3, 20.0), "speed_rpm": n})))
    p = out["fit_pressure_inner_MPa"]
    assert p[2] - p[0] == pytest.approx(4 * (p[1] - p[0]), rel=1e-7)
    assert p[2] < p[0]
    po = out["fit_pressure_outer_MPa"]
    assert np.abs(po - po[0]).max() <= 1e-9 * max(abs(po[0]), 1.0)
    lam = out["fit_pressure_inner_lame_MPa"]
    assert (p[2] - p[0]) == pytest.approx(lam[2] - lam[0], rel=0.1)


def test_fit_open_speed_brackets_the_opening(pl001):
    """At the fit-loosening speed the inner fit A is wholly open, 1e-6 below it still closed;
    and it lies within 10 % of the two-cylinder Lamé value (plane stress), its neighbour."""
    a = pl001.asm
    inp = table_inputs(a, {"T_ambient_C": np.array([20.0])})
    n_open = pl001.fit_open_speed_rpm(inp).of("fit_inner_A")[0]
    k = [f.name for f in pl001.section.fits].index("fit_inner_A")
    probe = table_inputs(a, {"T_ambient_C": np.full(2, 20.0),
                             "speed_rpm": n_open * np.array([1 - 1e-6, 1 + 1e-6])})
    p = pl001.fe(probe).fit_pressure_MPa[:, k]
    assert p[0] > 0 and p[1] == 0
    ms, mr = pl001.materials["shaft"], pl001.materials["inner_ring_A"]
    d_um = to_columns(pl001.run(inp))["interference_inner_um"][0]
    w = lame.fit_open_speed_rad_s(a.shaft.bore_diameter_mm / 2, a.shaft.seat_diameter_mm / 2,
                                  a.bearing.inner_ring_outer_diameter_mm / 2, ms.E_MPa, ms.nu,
                                  mr.E_MPa, mr.nu, d_um, ms.density_N_s2_mm4, mr.density_N_s2_mm4)
    assert n_open == pytest.approx(60 * w / (2 * math.pi), rel=0.1)


def test_set_up_key_follows_density_and_rotating_parts():
    """The centrifugal unit solution depends on the densities and on which parts spin: the
    stored set-up's key must change with either (and not without)."""
    sec = two_cylinder_section(0.0, 10.0, 15.0, "52100", "52100", 10.0)
    pts = np.array([[15.0], [5.0]])
    base = SetupSpec.of(sec, "frictionless", pts, None, rotating_parts=("shaft", "inner_ring_A"))
    same = SetupSpec.of(sec, "frictionless", pts, None, rotating_parts=("shaft", "inner_ring_A"))
    heavy = dataclasses.replace(get_material("52100"), density_kg_m3=8000.0)
    denser = SetupSpec.of(sec, "frictionless", pts, None, {"shaft": heavy},
                          rotating_parts=("shaft", "inner_ring_A"))
    shaft_only = SetupSpec.of(sec, "frictionless", pts, None, rotating_parts=("shaft",))
    assert base.key() == same.key()
    assert len({base.key(), denser.key(), shaft_only.key()}) == 3


def test_assembly_max_speed():
    """seed001's flywheel runs up to 9000 rpm ([operating] speed_max_rpm); seed000 gives none and
    takes its [lubrication] speed."""
    a1, a0 = load_shipped("seed001"), load_shipped("seed000")
    assert a1.operating.max_speed_rpm(a1.lubrication.speed_rpm) == 9000.0
    assert a0.operating.max_speed_rpm(a0.lubrication.speed_rpm) == a0.lubrication.speed_rpm


def test_row_field_at_speed_equals_a_direct_fe_solve(pl001):
    """`Pipeline.field` (superposed, omega^2 column) against one direct contact solve with the
    centrifugal load at 9000 rpm: displacements and contact forces relative to their largest."""
    inp = table_inputs(pl001.asm, {"T_ambient_C": np.array([-20.0]), "speed_rpm": np.array([9000.0])})
    f = pl001.field(inp)
    load = pl001.model.unit_loads @ f.theta + pl001.omega2(inp)[0] * pl001.model.spin_load
    sol = pl001.solver.solve(load, pl001.deltas_mm(*pl001.fits_um(inp))[0])
    np.testing.assert_allclose(f.u_mm, sol.u, rtol=0, atol=1e-8 * np.abs(sol.u).max())
    np.testing.assert_allclose(f.force_N, sol.force_N, rtol=0, atol=1e-8 * np.abs(sol.force_N).max())


def test_bonded_superposition_at_speed_equals_direct_fe():
    """Bonded fits: the tied unit solutions with the omega^2 column reproduce a direct solve at
    speed (pair forces relative to the largest); a bonded fit never opens (inf)."""
    from fem.loosening import fit_open_omega2
    from fem.model import build_model
    from fem.solver import FitSolver, Superposition

    sec = two_cylinder_section(5.0, 10.0, 15.0, "TC4", "9Cr18", 10.0)
    model = build_model(sec, "bonded", rotating_parts=("shaft", "inner_ring_A"))
    solver = FitSolver(model)
    sup = Superposition(solver)
    theta = np.array([[2e-4, 1e-4]])
    w2 = (2 * np.pi * 20000 / 60) ** 2
    res = sup.evaluate(theta, np.array([[0.002]]), np.array([w2]))
    sol = solver.solve(model.unit_loads @ theta[0] + w2 * model.spin_load, [0.002])
    np.testing.assert_allclose(res.force_N[0], sol.force_N, rtol=0,
                               atol=1e-8 * np.abs(sol.force_N).max())
    assert np.isinf(fit_open_omega2(sup, theta, np.array([[0.002]]), 0, 1e12)).all()


def test_report_shows_the_balls_at_speed(pl001):
    """The report's "The balls at speed" table (seed 001, 9000 rpm): at rest the assembled
    preload; at speed the quasi-dynamic row has the outer contact angle below the inner one and
    a centrifugal force m omega_c^2 dm/2 > 0, the quasi-static row equal angles and none."""
    from studies.usecases.assembly_report import ball_speed_lines

    asm = pl001.asm
    lines = ball_speed_lines(asm, pl001, 9000.0)
    assert lines[0] == "### The balls at speed"
    rows = [ln for ln in "\n".join(lines).splitlines()
            if ln.startswith("| at rest") or ln.startswith("| 9000 rpm")]
    cells = {r.split("|")[1].strip(): [c.strip() for c in r.split("|")[2:-1]] for r in rows}
    rest = cells["at rest"]
    assert float(rest[0]) == pytest.approx(asm.preload.assembled_N, rel=1e-3)
    qs, qd = cells["9000 rpm, quasi-static balls"], cells["9000 rpm, quasi-dynamic balls"]
    assert qs[1] == qs[2] and float(qs[5]) == 0.0
    assert float(qd[2]) < float(qd[1]) and float(qd[5]) > 0.0
