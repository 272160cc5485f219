"""Thermal network: energy conservation, steady state vs a series/parallel resistor circuit,
the single-node exponential, backward-Euler first-order convergence against the exact matrix
exponential, BDF against the exact solution, the discrete maximum principle, and the resistance
and capacity helpers against their limits."""
import numpy as np
import pytest
from scipy.linalg import expm

from analytic.materials import get_material
from analytic.thermal_network import (NODES, ThermalNetwork, ball_raceway_resistance_K_W,
                                      ball_set_mass_kg, bearing_heat_W, bearing_network,
                                      cylinder_conduction_resistance_K_W, film_resistance_K_W,
                                      heat_capacity_J_K, ring_mass_kg, simulate_transient,
                                      steady_state_C)

# Order-of-magnitude values for a 25 mm ball-screw support (seed 003 lost its table): only the
# structure matters for these tests, not the numbers.
CAP = {"housing": 900.0, "outer_ring": 40.0, "ball": 8.0, "inner_ring": 30.0, "shaft": 300.0}
RES = {"housing_outer_ring": 0.4, "outer_ring_ball": 1.2, "ball_inner_ring": 1.0,
       "inner_ring_shaft": 0.5, "housing_ambient": 2.0, "shaft_ambient": 6.0}


def net():
    return bearing_network(CAP, RES)


def exact(network, P, Ta, T0, t):
    """Exact solution for constant inputs: T = T_ss + expm(-C^-1 K t)(T0 - T_ss)."""
    K = network.conductance_matrix()
    Tss = steady_state_C(network, P, Ta)
    return Tss + expm(-K / network.C[:, None] * t) @ (T0 - Tss)


def test_backward_euler_conserves_energy_exactly():
    """Stored + convected = input, to round-off, in the scheme's own quadrature (the internal
    conduction terms cancel because the Laplacian's columns sum to zero), with time-varying heat,
    ambient and uneven steps."""
    t = np.concatenate([[0.0], np.cumsum(np.linspace(5.0, 40.0, 120))])
    Q = 3.0 + 2.0 * np.sin(t / 300.0)
    P = bearing_heat_W(Q, 0.8 * Q)
    Ta = 25.0 + 3.0 * np.cos(t / 500.0)
    r = simulate_transient(net(), t, P, Ta)
    assert r.energy_stored_J + r.energy_convected_J == pytest.approx(r.energy_in_J, rel=1e-12)
    # recompute independently from the history
    g = np.array([1 / RES["housing_ambient"], 0, 0, 0, 1 / RES["shaft_ambient"]])
    dt = np.diff(t)
    e_in = (dt * P[1:].sum(axis=1)).sum()
    e_out = (dt * ((r.T_C[1:] - Ta[1:, None]) * g).sum(axis=1)).sum()
    e_st = (np.array([CAP[n] for n in NODES]) * (r.T_C[-1] - r.T_C[0])).sum()
    assert e_st + e_out == pytest.approx(e_in, rel=1e-12)


def test_bdf_conserves_energy_to_its_tolerance():
    t = np.linspace(0, 4000, 801)
    r = simulate_transient(net(), t, bearing_heat_W(4.0, 3.0), 25.0, method="bdf", rtol=1e-9)
    assert r.energy_stored_J + r.energy_convected_J == pytest.approx(r.energy_in_J, rel=1e-5)


def test_steady_state_equals_the_resistor_circuit():
    """Heat Q into the ball node only: two paths to ambient, R_out = R23 + R12 + R_air1 and
    R_in = R34 + R45 + R_air5 in parallel (Ohm's law analogy), so T_ball - T_amb = Q R_out R_in /
    (R_out + R_in) and the flow splits in the inverse ratio of the resistances."""
    Q, Ta = 5.0, 20.0
    P = np.zeros(5)
    P[NODES.index("ball")] = Q
    T = steady_state_C(net(), P, Ta)
    Ro = RES["outer_ring_ball"] + RES["housing_outer_ring"] + RES["housing_ambient"]
    Ri = RES["ball_inner_ring"] + RES["inner_ring_shaft"] + RES["shaft_ambient"]
    assert T[NODES.index("ball")] - Ta == pytest.approx(Q * Ro * Ri / (Ro + Ri), rel=1e-12)
    q_out = Q * Ri / (Ro + Ri)
    assert T[NODES.index("housing")] - Ta == pytest.approx(q_out * RES["housing_ambient"], rel=1e-12)
    assert T[NODES.index("outer_ring")] - Ta == pytest.approx(
        q_out * (RES["housing_ambient"] + RES["housing_outer_ring"]), rel=1e-12)


def test_long_transient_reaches_the_steady_state():
    P = bearing_heat_W(4.0, 3.0)
    t = np.concatenate([[0.0], np.geomspace(1.0, 1e7, 200)])
    for method in ("backward_euler", "bdf"):
        r = simulate_transient(net(), t, P, 25.0, method=method)
        assert r.T_C[-1] == pytest.approx(steady_state_C(net(), P, 25.0), abs=1e-6)


def test_single_node_is_the_analytic_exponential():
    """C dT/dt = P - g (T - Ta): T = Ta + P/g (1 - exp(-g t / C)) (first-order lumped body)."""
    C, g, P, Ta = 500.0, 0.25, 3.0, 20.0
    one = ThermalNetwork(("body",), (C,), {}, {"body": g})
    t = np.linspace(0, 10000, 401)
    T_exact = Ta + P / g * (1 - np.exp(-g * t / C))
    r = simulate_transient(one, t, [P], Ta, method="bdf", rtol=1e-10)
    assert r.node("body") == pytest.approx(T_exact, abs=1e-6)
    # backward Euler with N steps: exact recursion T_{n+1} - T_ss = (T_n - T_ss)/(1 + g dt / C)
    r = simulate_transient(one, t, [P], Ta)
    dt = t[1] - t[0]
    T_be = Ta + P / g * (1 - (1 + g * dt / C) ** -np.arange(t.size))
    assert r.node("body") == pytest.approx(T_be, rel=1e-12)


def test_backward_euler_is_first_order_against_the_matrix_exponential():
    """Errors at t = 600 s for dt = 20, 10, 5, 2.5 s: observed order log2(e_h/e_h/2) in
    [0.95, 1.05] (backward Euler is first order)."""
    network = net()
    P = bearing_heat_W(4.0, 3.0)
    T0 = np.full(5, 25.0)
    ref = exact(network, P, 25.0, T0, 600.0)
    errs = []
    for n in (30, 60, 120, 240):
        r = simulate_transient(network, np.linspace(0, 600, n + 1), P, 25.0, T0)
        errs.append(np.abs(r.T_C[-1] - ref).max())
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 0.95) & (orders < 1.05)), orders
    # and BDF at tight tolerance agrees with the exact solution
    r = simulate_transient(network, np.linspace(0, 600, 61), P, 25.0, T0, method="bdf", rtol=1e-10)
    assert r.T_C[-1] == pytest.approx(ref, abs=1e-6)


def test_maximum_principle_and_seed003_ordering():
    """Heat entering only at the ball node: the ball is the hottest node at every time (discrete
    maximum principle of an M-matrix network, starting from ambient). With the contact heat
    split equally (seed 003), the balls are hottest and the inner ring is warmer than the outer
    ring when the outer ring sits on the better-cooled housing path, as seed 003 reports."""
    P = np.zeros(5)
    P[NODES.index("ball")] = 5.0
    t = np.linspace(0, 5000, 201)
    r = simulate_transient(net(), t, P, 25.0)
    assert np.all(r.T_C[1:].argmax(axis=1) == NODES.index("ball"))
    r = simulate_transient(net(), t, bearing_heat_W(4.0, 4.0), 25.0)
    T = r.T_C[-1]
    assert T.argmax() == NODES.index("ball")
    assert T[NODES.index("inner_ring")] > T[NODES.index("outer_ring")]
    # housing: rises then levels off (monotone, decreasing rate) for a constant heat input
    h = r.node("housing")
    assert np.all(np.diff(h) > 0) and np.diff(h)[-1] < 0.2 * np.diff(h).max()


def test_heat_split_conserves_the_contact_heat():
    P = bearing_heat_W(np.array([1.0, 2.0]), np.array([3.0, 0.5]), 0.3, 0.6)
    assert P.shape == (2, 5)
    assert P.sum(axis=1) == pytest.approx([4.0, 2.5], rel=1e-14)
    assert P[0, NODES.index("inner_ring")] == pytest.approx(0.3)
    assert P[0, NODES.index("ball")] == pytest.approx(0.7 + 0.4 * 3.0)
    with pytest.raises(ValueError):
        bearing_heat_W(1.0, 1.0, inner_ring_share=1.5)


def test_cylinder_resistance_tends_to_the_plane_wall():
    """Thin wall t << d: ln(d_o/d_i)/(2 pi k L) -> t/(k A), A = pi d L (plane wall, Incropera
    eq. 3.6); relative difference O(t/d)."""
    d, t, L, k = 50.0, 0.01, 20.0, 24.0
    R = cylinder_conduction_resistance_K_W(d, d + 2 * t, L, k)
    R_plane = (t * 1e-3) / (k * np.pi * d * 1e-3 * L * 1e-3)
    assert R == pytest.approx(R_plane, rel=2 * t / d)
    assert film_resistance_K_W(10.0, 1e6) == pytest.approx(0.1)   # 1 m^2 at 10 W/m^2K


def test_constriction_resistance_scales():
    """R = (1/k1 + 1/k2)/(4 sqrt(ab) Z): halves with twice the balls, scales as 1/sqrt(ab)."""
    R = ball_raceway_resistance_K_W(0.5, 0.1, 30.0, 24.0, 10)
    assert ball_raceway_resistance_K_W(0.5, 0.1, 30.0, 24.0, 20) == pytest.approx(R / 2)
    assert ball_raceway_resistance_K_W(2.0, 0.4, 30.0, 24.0, 10) == pytest.approx(R / 4)
    assert R == pytest.approx((1 / 30 + 1 / 24) / (4 * np.sqrt(0.05) * 1e-3) / 10, rel=1e-14)


def test_capacities_from_masses():
    """Steel ring 25x62x15 mm: pi/4 (62^2 - 25^2) 15 mm^3 x 7700 kg/m^3; C = m c_p."""
    steel = get_material("9Cr18")
    m = ring_mass_kg(25.0, 62.0, 15.0, steel)
    assert m == pytest.approx(np.pi / 4 * (62**2 - 25**2) * 15e-9 * 7700, rel=1e-14)
    assert heat_capacity_J_K(m, steel) == pytest.approx(m * 460.0, rel=1e-14)
    assert ball_set_mass_kg(10.0, 12, steel) == pytest.approx(12 * np.pi / 6 * 1e-6 * 7700)


def test_bad_inputs_are_rejected():
    with pytest.raises(ValueError):
        bearing_network(CAP, {k: v for k, v in RES.items() if k != "shaft_ambient"})
    with pytest.raises(ValueError):
        simulate_transient(net(), [0.0, 0.0], np.zeros(5), 25.0)
    with pytest.raises(ValueError):
        ThermalNetwork(("a",), (0.0,), {}, {})
