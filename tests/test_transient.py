"""Transient conduction FE (fem/transient.py): its steady limit against the steady conduction FE
(fem/thermal.py), the energy balance of every step against independent quadratures, the lumped
network (analytic/thermal_network.py) as its limit for highly conducting parts, and the fit
contact conductance against a handbook range."""
from dataclasses import replace

import numpy as np
import pytest
from skfem import FacetBasis, Functional

from analytic.materials import get_material
from analytic.thermal_network import bearing_heat_W, bearing_network, simulate_transient
from fem.model import build_model
from fem.thermal import ConductionModel, ThermalLoads
from fem.transient import (KELVIN, PER_M2_TO_PER_MM2, SIGMA_W_MM2_K4, StepLoads, Stepper,
                           ThermalParameters, TransientConduction, contact_conductance_W_m2K,
                           radiation_h_W_mm2K)
from meshes.section import Fit, Rect, Section, Split


@pytest.fixture(scope="module")
def stack():
    """Seed 003's stack (the structural FE's section, mesh and parts)."""
    from studies.model.config import load_assembly
    from studies.model.pipeline import Pipeline

    return Pipeline(load_assembly("studies/configs/seed003_25TAC62B.toml")).model


RACEWAY_HEAT_W = {"raceway_inner_ring_A": 1.2, "raceway_outer_ring_A": 0.8,
                  "raceway_inner_ring_B": 1.1, "raceway_outer_ring_B": 0.9}


@pytest.mark.parametrize("ball_nodes", [False, True])
def test_steady_limit_equals_the_steady_conduction_fe(stack, ball_nodes):
    """Constant loads for a long time (backward Euler at dt = 1e7 s, three steps: each step
    shrinks the transient by dt/tau ~ 1e4) give the steady FE of fem/thermal.py to 1e-8 of the
    temperature rise: perfect contact on every interface (as the steady model has), films,
    raceway heat, a fixed shaft end and the ball set between the raceways (with ball nodes: two
    conductances in series through a node that takes no heat at steady state)."""
    G_i, G_o = 0.4, 0.7
    steady = ConductionModel(stack).solve(ThermalLoads(
        convection={"housing_outer": (15.0, 25.0)}, fixed_C={"shaft_end": 30.0},
        heat_W=RACEWAY_HEAT_W, ball_conductance_W_K={"A": G_i * G_o / (G_i + G_o),
                                                     "B": G_i * G_o / (G_i + G_o)}))
    tc = TransientConduction(stack, ball_capacity_J_K=8.0 if ball_nodes else None,
                             fixed_groups=("shaft_end",), perfect_contact=True)
    prm = ThermalParameters(film_W_m2K={"housing_outer": 15.0},
                            fit_conductance_W_m2K=(0.0,) * 4, ball_inner_W_K=G_i,
                            ball_outer_W_K=G_o)
    st = Stepper(tc, prm, 1e7, 25.0, "backward_euler")
    loads = StepLoads(25.0, heat_W=RACEWAY_HEAT_W, T_fixed_C={"shaft_end": 30.0})
    for _ in range(3):
        T = st.step(loads)
    rise = np.abs(steady - 25.0).max()
    assert np.abs(T[:tc.N] - steady).max() < 1e-8 * rise


def _face_integral(tc, group, values):
    """int values 2 pi r ds over a face group, by the face quadrature (not the assembled vector)."""
    m = tc.model
    fb = FacetBasis(m.mesh, m.sbasis.elem, facets=tc.groups[group])
    f = Functional(lambda w: 2 * np.pi * w.x[0] * w.u)
    return float(f.assemble(fb, u=fb.interpolate(values)))


@pytest.mark.parametrize("scheme", ["backward_euler", "bdf2"])
def test_energy_balance_closes_every_step(stack, scheme):
    """Heat in = stored + convected + radiated, per step, to round-off (1e-11 of the largest
    term): finite fit conductances, films, radiation to a cold sink, ball nodes. For backward
    Euler the terms are also computed independently: stored = int rho c (T1 - T0)/dt dV by
    volume quadrature plus the ball sets' C dT/dt, convected = int h (T - T_amb) dA and radiated
    = int eps (h_r (T - T_s) + remainder) dA by face quadrature."""
    tc = TransientConduction(stack, ball_capacity_J_K=8.0)
    films = {"housing_outer": 12.0, "shaft_end": 40.0, "free_cover": 8.0}
    prm = ThermalParameters(film_W_m2K=films, fit_conductance_W_m2K=(4e3, 5e3, 2e3, 3e3),
                            ball_inner_W_K=0.4, ball_outer_W_K=0.6,
                            emissivity={"housing_outer": 0.8, "free_housing": 0.3},
                            T_rad_lin_C=20.0)
    st = Stepper(tc, prm, 5.0, 20.0, scheme)
    heat = dict(RACEWAY_HEAT_W, ball_A=1.5, ball_B=1.4)
    m = stack
    b = m.sbasis
    mats = m.materials
    rc = np.array([mats[p].density_kg_m3 * mats[p].specific_heat_J_kgK for p in m.part_of]) * 1e-9
    vol = Functional(lambda w: 2 * np.pi * w.x[0] * w.rc * w.u)
    for k in range(6):
        T0 = st.T.copy()
        T = st.step(StepLoads(25.0, T_sink_C=-40.0, heat_W=heat))
        bal = st.balance
        assert abs(bal.residual_W) < 1e-11 * bal.scale_W
        assert bal.heat_in_W == pytest.approx(sum(heat.values()), rel=1e-14)
        if scheme != "backward_euler":
            continue
        dT = (T - T0) / 5.0
        stored = float(vol.assemble(b, u=b.interpolate(dT[:tc.N]),
                                    rc=np.repeat(rc[:, None], b.X.shape[1], 1)))
        stored += 8.0 * dT[tc.N:].sum()
        conv = sum(h * PER_M2_TO_PER_MM2 * _face_integral(tc, g, T[:tc.N] - 25.0)
                   for g, h in films.items())
        h_r = radiation_h_W_mm2K(20.0)
        T_ex = T0[:tc.N]        # backward Euler: the remainder from the last state
        rem = (SIGMA_W_MM2_K4 * ((T_ex + KELVIN) ** 4 - (-40.0 + KELVIN) ** 4)
               - h_r * (T_ex + 40.0))
        rad = sum(eps * (h_r * _face_integral(tc, g, T[:tc.N] + 40.0) + _face_integral(tc, g, rem))
                  for g, eps in prm.emissivity.items())
        scale = max(stored, conv, rad, sum(heat.values()))
        assert bal.stored_W == pytest.approx(stored, abs=1e-10 * scale)
        assert bal.convected_W == pytest.approx(conv, abs=1e-10 * scale)
        assert bal.radiated_W == pytest.approx(rad, abs=1e-10 * scale)


# ------------------------------------------------------------------ the lumped-network limit
K_SCALE = 1e4       # conductivities x 1e4: Biot numbers of the parts ~1e-4


def _network_section():
    """Shaft, inner ring, (ball gap), outer ring, housing, all 10 mm long; two fits."""
    L = 10.0
    rects = (Rect("shaft", 0.0, 10.0, 0.0, L, "GCr15"), Rect("inner_ring_A", 10.0, 14.0, 0.0, L, "GCr15"),
             Rect("outer_ring_A", 18.0, 22.0, 0.0, L, "GCr15"), Rect("housing", 22.0, 30.0, 0.0, L, "6061"))
    splits = (Split("seat", "r", 10.0, 0.0, L, ("shaft",), ("inner_ring_A",)),
              Split("bore", "r", 22.0, 0.0, L, ("outer_ring_A",), ("housing",)))
    fits = (Fit("fit_inner_A", "shaft", "inner_ring_A", 10.0, 0.0, L, "inner"),
            Fit("fit_outer_A", "outer_ring_A", "housing", 22.0, 0.0, L, "outer"))
    return Section(rects, splits, fits, (), (), {"inner_ring_A": (14.0, 5.0),
                                                  "outer_ring_A": (18.0, 5.0)}, 1.0, 0.5)


def test_lumped_network_is_the_limit_of_highly_conducting_parts():
    """Parts whose conductivity is 1e4 times their material's are isothermal to O(Bi) ~ 1e-4:
    the FE's part means then follow the 5-node network (housing, outer ring, balls, inner ring,
    shaft) whose capacities are rho c V of the rectangles (by hand), whose links are the fit
    conductances times the fit areas and the ball conductances, and whose ambient links are the
    films times their areas (2 pi r L and pi r^2 by hand). Both by backward Euler at the same
    step; agreement to 1e-3 of the temperature rise (ten times the Biot numbers)."""
    sec = _network_section()
    mats = {p: replace(get_material(sec.material_of(p)),
                       conductivity_W_mK=K_SCALE * get_material(sec.material_of(p)).conductivity_W_mK)
            for p in sec.parts()}
    tc = TransientConduction(build_model(sec, materials=mats), ball_capacity_J_K=6.0)
    h_fit, h_house, h_shaft, G_i, G_o = (3000.0, 2000.0), 25.0, 60.0, 0.5, 0.8
    prm = ThermalParameters(film_W_m2K={"housing_outer": h_house, "shaft_end": h_shaft},
                            fit_conductance_W_m2K=h_fit, ball_inner_W_K=G_i, ball_outer_W_K=G_o)
    L = 1e-2       # m
    V = {"shaft": np.pi * 0.010 ** 2 * L, "inner_ring_A": np.pi * (0.014 ** 2 - 0.010 ** 2) * L,
         "outer_ring_A": np.pi * (0.022 ** 2 - 0.018 ** 2) * L,
         "housing": np.pi * (0.030 ** 2 - 0.022 ** 2) * L}
    C = {p: V[p] * mats[p].density_kg_m3 * mats[p].specific_heat_J_kgK for p in V}
    cap = {"housing": C["housing"], "outer_ring": C["outer_ring_A"], "ball": 6.0,
           "inner_ring": C["inner_ring_A"], "shaft": C["shaft"]}
    R = {"housing_outer_ring": 1 / (h_fit[1] * 2 * np.pi * 0.022 * L),
         "outer_ring_ball": 1 / G_o, "ball_inner_ring": 1 / G_i,
         "inner_ring_shaft": 1 / (h_fit[0] * 2 * np.pi * 0.010 * L),
         "housing_ambient": 1 / (h_house * 2 * np.pi * 0.030 * L),
         "shaft_ambient": 1 / (h_shaft * np.pi * 0.010 ** 2)}
    net = bearing_network(cap, R)
    dt, n = 20.0, 60
    P = bearing_heat_W(2.0, 1.5)            # W per node: inner/outer contact heat split 50/50
    res = simulate_transient(net, np.arange(n + 1) * dt, P, 20.0)
    heat = {"raceway_inner_ring_A": P[3], "raceway_outer_ring_A": P[1], "ball_A": P[2]}
    st = Stepper(tc, prm, dt, 20.0, "backward_euler")
    fe = []
    for _ in range(n):
        T = st.step(StepLoads(20.0, heat_W=heat))
        pm = tc.part_mean_C(T)
        fe.append([pm["housing"], pm["outer_ring_A"], tc.mean_C(T, "ball_A"), pm["inner_ring_A"],
                   pm["shaft"]])
    rise = np.abs(res.T_C - 20.0).max()
    assert np.abs(np.array(fe) - res.T_C[1:]).max() < 1e-3 * rise


def test_contact_conductance_in_the_handbook_range():
    """Stainless steel on stainless steel, ground, in vacuum at 10 MPa: Incropera & DeWitt
    Table 3.1 gives R'' = 0.7-4.0e-4 m^2 K/W, h = 2500-14300 W/m^2K. The correlation with
    k = 16 W/mK, sigma = 1 um and H_c = 3.4 GPa (no gas) lands inside; an open fit in vacuum
    conducts nothing, in air k_air / (gap + M)."""
    from fem.transient import SurfacePair

    vac = SurfacePair(roughness_um=1.0, microhardness_MPa=3.4e3, gas_conductivity_W_mK=0.0)
    h = contact_conductance_W_m2K(10.0, 0.0, 16.0, 16.0, vac)
    assert 2500.0 < h < 14300.0
    assert contact_conductance_W_m2K(-1.0, 5.0, 16.0, 16.0, vac) == 0.0
    air = SurfacePair()
    assert contact_conductance_W_m2K(-1.0, 10.0, 16.0, 16.0, air) == pytest.approx(
        0.026 / (10e-6 + 0.37e-6), rel=1e-12)


def test_heat_through_fixed_faces_closes_the_balance():
    """A bore whose temperature ramps (a fixed face group) feeding a ring that convects: the heat
    entering through the fixed face (the reactions there) equals stored + convected every step,
    to 1e-11 of the largest term, and the ring's outside lags the bore (heat flows outwards)."""
    from meshes.section import two_cylinder_section

    sec = two_cylinder_section(5.0, 10.0, 15.0, "TC4", "9Cr18", 10.0)
    tc = TransientConduction(build_model(sec), fixed_groups=("shaft_bore",))
    prm = ThermalParameters(film_W_m2K={"raceway_inner_ring_A": 50.0},
                            fit_conductance_W_m2K=(3e3,))
    st = Stepper(tc, prm, 2.0, 20.0, "bdf2")
    for k in range(1, 21):
        T = st.step(StepLoads(20.0, T_fixed_C={"shaft_bore": 20.0 + 2.0 * k}))
        bal = st.balance
        assert bal.fixed_in_W > 0
        assert abs(bal.residual_W) < 1e-11 * bal.scale_W
    assert tc.mean_C(T, "raceway_inner_ring_A") < tc.mean_C(T, "shaft_bore") == pytest.approx(60.0)
