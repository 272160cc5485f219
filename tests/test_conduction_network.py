"""The independent conduction network of the stack (studies/validation/conduction_network.py)
against closed forms: a lumped body's exponential response, the steady state of a series of
resistances, energy conservation, and the spatial convergence rate in the shell count."""
from __future__ import annotations

import math

import numpy as np
import pytest

from studies.model.config import load_shipped
from studies.validation.conduction_network import (
    ENVIRONMENTS, AIR_K_W_MK, AIR_PR, BearingHeat, Network, Surface, annulus_shells,
    conduction_temperatures,
    film_W_m2K, series, stack_network)


@pytest.fixture(scope="module")
def seed000():
    return load_shipped("seed000")


def test_lumped_body_follows_the_exponential():
    """One node of capacity C with a film h A to an ambient stepped by 10 K at t = 0:
    T = 10 (1 - exp(-t h A / C)) (Incropera & DeWitt eq. 5.6); BDF within 1e-5 of the step."""
    C, hA = 500.0, 0.4                                      # J/K, W/K: tau = 1250 s
    net = Network(np.array([C]), np.zeros((1, 1)), [Surface(0, 1.0, hA)])
    t = np.linspace(0.0, 6000.0, 61)
    amb = np.full(t.size, 10.0)
    T, _ = net.integrate(t, amb, T0_C=0.0, rtol=1e-9, atol_K=1e-10)
    exact = 10.0 * (1.0 - np.exp(-t * hA / C))
    assert np.max(np.abs(T[:, 0] - exact)) < 1e-5 * 10.0


def test_series_steady_state_is_the_sum_of_resistances():
    """Two annuli (steel in titanium) in contact, a film outside, heat Q into the innermost shell:
    in steady state T_0 - T_amb = Q (ln(r1/rc0)/(2 pi k1 L) + 1/(hc 2 pi r1 L) + ln(r2/r1)/(2 pi k2 L)
    + 1/(h 2 pi r2 L)) (Incropera eq. 3.33 and 3.36: resistances in series), to 1e-9 relative."""
    L, r0, r1, r2 = 0.03, 0.01, 0.02, 0.03
    k1, k2, hc, h, Q = 24.0, 6.7, 5000.0, 20.0, 3.0
    a = annulus_shells(r0, r1, L, k1, 3.5e6, 5)
    b = annulus_shells(r1, r2, L, k2, 2.3e6, 7)
    n = 12
    net = Network(np.concatenate([a[1], b[1]]), np.zeros((n, n)))
    for k, g in enumerate(a[2]):
        net.link(k, k + 1, g)
    for k, g in enumerate(b[2]):
        net.link(5 + k, 6 + k, g)
    net.link(4, 5, series(a[4], hc * 2 * math.pi * r1 * L, b[3]))
    net.surfaces = [Surface(11, 1.0, series(b[4], h * 2 * math.pi * r2 * L))]
    share = np.zeros(n)
    share[0] = 1.0
    net.heat_share = share
    # steady state directly: L T + loss = Q share
    A = net.laplacian_W_K()
    A[11, 11] += net.surfaces[0].film
    T = np.linalg.solve(A, share * Q)                       # ambient 0 C
    rc0 = a[0][0]
    R = (math.log(r1 / rc0) / (2 * math.pi * k1 * L) + 1 / (hc * 2 * math.pi * r1 * L)
         + math.log(r2 / r1) / (2 * math.pi * k2 * L) + 1 / (h * 2 * math.pi * r2 * L))
    assert T[0] == pytest.approx(Q * R, rel=1e-9)
    # and the integrator reaches it (tau about C R: 40 time constants)
    t = np.linspace(0.0, 40 * net.capacity_J_K.sum() * R, 41)
    Tt, _ = net.integrate(t, np.zeros(t.size), Q, rtol=1e-7, atol_K=1e-8)
    assert Tt[-1, 0] == pytest.approx(Q * R, rel=1e-5)


def test_energy_is_conserved_on_the_stack(seed000):
    """Seed 000 bolted to its plate in forced air, 2 W of bearing heat over a -60..80 C cycle:
    energy put in = stored + lost to the environment, to 1e-6 of the largest of the three (a
    linear multistep method keeps a linear invariant to rounding, so this checks the network's
    assembly: symmetric links, heat shares summing to one, losses booked as removed)."""
    t = np.arange(0.0, 4 * 3600.0 + 1, 120.0)
    amb = 20.0 + 60.0 * np.sin(2 * np.pi * t / 14400.0)
    h = conduction_temperatures(seed000, t, amb, "mount_forced_air", heat_W=2.0, rtol=1e-6)
    scale = max(np.abs(h.energy_in_J).max(), np.abs(h.energy_lost_J).max(),
                np.abs(h.energy_stored_J).max())
    assert np.max(np.abs(h.energy_balance_J())) < 1e-6 * scale
    assert h.energy_in_J[-1] == pytest.approx(2.0 * t[-1], rel=1e-9)


def _viscous_law(H0_W, T0_C, a_K, n_rows, weights):
    """A `BearingHeat` of H0 exp(-(T - T0) / a) (W; the viscous heat of an oil as it warms) on a
    5 K grid: interpolated in ln(heat), it is that law exactly."""
    grid = np.arange(-100.0, 300.0, 5.0)
    return BearingHeat(grid, (np.log(H0_W) - (grid - T0_C) / a_K)[None, :],
                       np.zeros(n_rows, int), np.asarray(weights, float))


def test_a_heat_at_the_body_s_own_temperature_settles_at_the_lambert_w_balance():
    """One node (C, film h A to an ambient u) heated by H0 exp(-(T - T0) / a) at its own
    temperature: it settles where h A (T - u) = H(T), x = (T - u) / a = W(H0 e^{-(u - T0)/a} /
    (h A a)) (Lambert's W, scipy.special.lambertw); BDF within 1e-6 of the rise after 20 time
    constants; the energy put in is the heat at the node's temperature, integrated
    (put in = stored + lost, 1e-7 of the largest)."""
    from scipy.special import lambertw

    C, hA, u, H0, T0, a = 500.0, 0.4, -40.0, 30.0, 20.0, 12.0
    net = Network(np.array([C]), np.zeros((1, 1)), [Surface(0, 1.0, hA)])
    net.heat_share = np.array([1.0])
    t = np.linspace(0.0, 20 * C / hA, 201)
    law = _viscous_law(H0, T0, a, t.size, [1.0])
    T, ledger = net.integrate(t, np.full(t.size, u), law, rtol=1e-10, atol_K=1e-10)
    x = float(np.real(lambertw(H0 * np.exp(-(u - T0) / a) / (hA * a))))
    rise = a * x
    assert abs(T[-1, 0] - (u + rise)) < 1e-6 * rise
    assert rise > 20.0                                    # the heat warms it far off the ambient
    bal = ledger[:, 0] - ledger[:, 1] - ledger[:, 2]
    assert np.max(np.abs(bal)) < 1e-7 * np.abs(ledger).max()


def test_a_heat_at_the_bearing_s_temperature_conserves_energy_on_the_stack(seed000):
    """Seed 000 in forced air over a -60..80 C cycle with a heat falling steeply as its rings and
    balls warm (H0 exp(-(T - 20 C) / 10 K), 5 W at 20 C): put in = stored + lost (1e-6 of the
    largest) and the heat put in over each row interval is the law at the bearing's
    temperature (the rows' trapezoid within 2 % of the ledger's increment)."""
    t = np.arange(0.0, 4 * 3600.0 + 1, 120.0)
    amb = 20.0 + 60.0 * np.sin(2 * np.pi * t / 14400.0)
    law = _viscous_law(5.0, 20.0, 10.0, t.size, np.zeros(0))
    h = conduction_temperatures(seed000, t, amb, "forced_air", heat_W=law, rtol=1e-7)
    scale = max(np.abs(h.energy_in_J).max(), np.abs(h.energy_lost_J).max(),
                np.abs(h.energy_stored_J).max())
    assert np.max(np.abs(h.energy_balance_J())) < 1e-6 * scale
    oil = np.mean([h.columns[c] for c in ("T_inner_ring_C", "T_ball_C", "T_outer_ring_C")], axis=0)
    Q = 5.0 * np.exp(-(oil - 20.0) / 10.0)
    trap = 0.5 * (Q[1:] + Q[:-1]) * np.diff(t)
    assert np.max(np.abs(np.diff(h.energy_in_J) - trap)) < 0.02 * trap.max()


def test_vacuum_steady_state_radiates_the_heat(seed000):
    """In vacuum with no mount the bearing heat leaves by radiation only: at the steady state
    the housing's outer faces radiate Q, eps sigma A (T^4 - T_amb^4) = Q (Incropera eq. 1.7)."""
    sn = stack_network(seed000, ENVIRONMENTS["vacuum"], 3)
    t = np.linspace(0.0, 4e5, 81)                           # 20 x the housing's time constant
    T, _ = sn.network.integrate(t, np.zeros(t.size), 1.0, rtol=1e-7)
    lost = sn.network.losses_W(T[-1], 0.0).sum()
    assert lost == pytest.approx(1.0, rel=1e-4)


def test_stack_converges_at_second_order(seed000):
    """The whole stack (forced air, a ramp then a hold): the part means with 2, 4, 8 shells
    converge at the observed order 2 within 0.3 (the shared faces condensed exactly,
    `conduction_network.condensed`), and 4 shells (the cases' default) lie within 1e-3 K of the
    Richardson extrapolation, against differences between parts of some K."""
    t = np.arange(0.0, 3600.0 + 1, 120.0)
    amb = np.minimum(t / 60.0, 40.0)
    runs = [conduction_temperatures(seed000, t, amb, "forced_air", shells=n, rtol=1e-10).columns
            for n in (2, 4, 8)]
    for col in ("T_shaft_C", "T_ball_C", "T_spacer_C", "T_housing_C"):
        T = [r[col][-1] for r in runs]
        p = math.log2(abs(T[1] - T[0]) / abs(T[2] - T[1]))
        assert abs(p - 2.0) < 0.3, (col, T, p)
        extrapolated = T[2] + (T[2] - T[1]) / (2.0 ** p - 1.0)
        assert abs(T[1] - extrapolated) < 1e-3, (col, T)


def test_films_against_handbook_numbers():
    """Churchill-Bernstein at Re = 7550 (a 60 mm cylinder in air at 2 m/s) gives Nu about 46
    (Incropera Fig. 7.9's range at that Re: 40..50); natural convection about a 60 mm
    cylinder at 10 K gives 4..6 W/(m^2 K) (Incropera Example 9.3's order for a pipe), growing
    as dT^(1/4) in the laminar range."""
    h = film_W_m2K("cylinder_forced", 0.06, 2.0)
    assert 40.0 < h * 0.06 / AIR_K_W_MK < 50.0
    h10 = film_W_m2K("cylinder_natural", 0.06, 0.0, 10.0)
    h40 = film_W_m2K("cylinder_natural", 0.06, 0.0, 40.0)
    assert 3.5 < h10 < 6.0
    assert h40 / h10 == pytest.approx(4 ** 0.25, rel=0.1)
    with pytest.raises(ValueError, match="air_speed_m_s"):
        film_W_m2K("plate_forced", 0.1, 0.0)
    assert AIR_PR == pytest.approx(0.707)
