"""Steady conduction FE against radial conduction closed forms and an energy balance."""
import numpy as np
import pytest

from analytic.materials import get_material
from fem.model import build_model
from fem.solver import FitSolver
from fem.thermal import ConductionModel, ThermalLoads
from meshes.section import two_cylinder_section

RI, RF, RO = 5.0, 10.0, 15.0


def _model(mi="TC4", mo="9Cr18", factor=1.0):
    sec = two_cylinder_section(RI, RF, RO, mi, mo, 10.0).scaled(factor)
    return ConductionModel(build_model(sec))


def _exact_two_layer(r, T1, T2, k1, k2):
    """Series radial conduction through two shells (Incropera eq. 3.28): T(r) piecewise log."""
    R1, R2 = np.log(RF / RI) / k1, np.log(RO / RF) / k2
    q = (T1 - T2) / (R1 + R2)                     # per 2 pi L
    Tf = T1 - q * R1
    return np.where(r <= RF, T1 - q * np.log(r / RI) / k1, Tf - q * np.log(r / RF) / k2)


@pytest.mark.requirement("R-FE-THERMAL")
def test_radial_conduction_through_a_fit_matches_log_profile_and_converges():
    k1, k2 = get_material("TC4").conductivity_W_mK, get_material("9Cr18").conductivity_W_mK
    errs = []
    for factor in (4.0, 0.5):
        cm = _model(factor=factor)
        T = cm.solve(ThermalLoads(fixed_C={"shaft_bore": 80.0, "raceway_inner_ring_A": 20.0}))
        r = cm.model.sbasis.doflocs[0]
        errs.append(np.abs(T - _exact_two_layer(r, 80.0, 20.0, k1, k2)).max() / 60.0)
    assert errs[1] < 2e-5
    # P2 max-norm error is O(h^2) at least; gmsh levels are not nested, so the order is measured
    # over three halvings (factor 8 in element size) rather than one
    assert np.log(errs[0] / errs[1]) / np.log(8.0) > 1.8


def test_heat_input_leaves_through_convection():
    """Energy balance: Q in at the bore = h A (T - T_inf) integrated over the outer surface."""
    cm = _model()
    h, T_inf, Q = 50.0, 20.0, 5.0
    T = cm.solve(ThermalLoads(convection={"raceway_inner_ring_A": (h, T_inf)}, heat_W={"shaft_bore": Q}))
    mean_out = cm.mean_vector("raceway_inner_ring_A") @ T
    area_mm2 = 2 * np.pi * RO * 10.0
    assert h / 1e6 * area_mm2 * (mean_out - T_inf) == pytest.approx(Q, rel=1e-9)


def test_uniform_field_gives_the_uniform_thermal_solution():
    cm = _model("9Cr18", "9Cr18")
    T = cm.solve(ThermalLoads(fixed_C={"shaft_bore": 70.0, "raceway_inner_ring_A": 70.0}))
    assert np.allclose(T, 70.0, atol=1e-10)
    m = cm.model
    sol = FitSolver(m).solve(m.thermal_load_vector(cm.theta_field(T, 20.0)), [0.0])
    x = m.sbasis.doflocs
    assert np.allclose(sol.u[0::2], get_material("9Cr18").thermal_strain(70.0, 20.0) * x[0], atol=1e-12)
