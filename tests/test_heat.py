"""analytic/heat.py: the heat split of a pair against independent statements: what the contacts
generate is what the mechanisms generate (the split into inner and outer loses nothing), the
viscous part is M |omega| with omega = 2 pi n / 60, and sliding and spin heat scale with the
traction coefficient."""
import numpy as np
import pytest

from analytic.bearing import BearingGeometry, solve_pair
from analytic.heat import pair_heat_W

G = BearingGeometry.from_catalogue("25TAC62B")
PAIR = solve_pair(G, "DB", preload_assembled_N=np.array([500.0, 1500.0, 3000.0]))
N_RPM = np.array([1000.0, 1500.0, -1500.0])          # the sign is only the direction


def test_split_by_side_equals_split_by_mechanism():
    h = pair_heat_W(G, PAIR, N_RPM, 0.03, np.array([20.0, 25.0, 25.0]))
    total = h.sliding_W + h.spin_W + h.viscous_W
    # round-off of sums of a few non-negative terms: 16 eps of the sum of their magnitudes
    tol = 16 * np.finfo(float).eps * total
    assert np.all(np.abs(h.inner_W + h.outer_W - total) <= tol)
    assert np.all(np.abs(h.total_W - total) <= tol)
    assert np.all(h.sliding_W > 0) and np.all(h.spin_W > 0)
    assert np.all(np.diff(h.sliding_W[:2]) > 0)       # more preload, more sliding heat


def test_viscous_heat_is_torque_times_angular_speed():
    M = np.array([20.0, 25.0, 25.0])                   # N mm
    h = pair_heat_W(G, PAIR, N_RPM, 0.0, M)
    omega = 2 * np.pi * np.abs(N_RPM) / 60.0           # rad/s
    np.testing.assert_allclose(h.viscous_W, 1e-3 * M * omega, rtol=1e-14)
    assert np.all(h.sliding_W == 0) and np.all(h.spin_W == 0)
    np.testing.assert_allclose(h.inner_W, h.outer_W, rtol=1e-14)     # shared half and half


def test_sliding_and_spin_heat_proportional_to_traction():
    a = pair_heat_W(G, PAIR, N_RPM, 0.02, 0.0)
    b = pair_heat_W(G, PAIR, N_RPM, 0.06, 0.0)
    np.testing.assert_allclose(b.sliding_W, 3 * a.sliding_W, rtol=1e-13)
    np.testing.assert_allclose(b.spin_W, 3 * a.spin_W, rtol=1e-13)


# ------------------------------------------------------------------ rolling contact conductance
from analytic.heat import (ContactConductance, moving_contact_resistance_K_W,  # noqa: E402
                           rolling_contact_conductance)
from analytic.materials import MATERIALS  # noqa: E402

K, KAPPA = 46.6, 12.56          # W/(m K), mm^2/s: bearing steel


def test_moving_contact_at_rest_is_the_stationary_isoflux_disc():
    """V = 0, circle of radius a: the mean rise of a uniform flux on a half-space is
    8 Q / (3 pi^2 k a) (Carslaw & Jaeger sec. 10.5; Yovanovich's isoflux disc), to 1e-9."""
    a = 0.3
    R = moving_contact_resistance_K_W(a, a, 0.0, K, KAPPA)
    assert R == pytest.approx(8.0 / (3.0 * np.pi ** 2 * K * 1e-3 * a), rel=1e-9)


@pytest.mark.parametrize("pe", [100.0, 1000.0])
def test_moving_contact_at_high_peclet_is_jaegers_penetration_limit(pe):
    """Pe = V b / (2 kappa) >> 1: each surface point takes the flux for the time it is in the
    contact (1-D penetration, Jaeger 1942): mean rise (4/3) q sqrt(2 kappa l / (pi V)) / k on a
    chord of half-length l, averaged over the ellipse's chords (the weight B(1/2, 7/4) / (pi/2)
    from int (1 - s^2)^(3/4) ds against int (1 - s^2)^(1/2) ds); the relative correction of the
    lateral conduction is O(1/sqrt(Pe)): within 2 % at Pe = 100, 0.5 % at Pe = 1000."""
    from scipy.special import beta
    a, b = 0.5, 0.1
    V = pe * 2.0 * KAPPA / b
    R = moving_contact_resistance_K_W(a, b, V, K, KAPPA, n_phi=2048, n_d=128)
    w = beta(0.5, 1.75) / (np.pi / 2)
    A = np.pi * a * b
    R_jaeger = w * (4.0 / 3.0) * np.sqrt(2 * KAPPA * b / (np.pi * V)) / (K * 1e-3) / A
    assert R == pytest.approx(R_jaeger, rel=0.2 / np.sqrt(pe))


def test_rolling_contact_resistance_falls_with_speed_and_the_film_adds_in_series():
    """Faster rolling: a thinner heated layer, a lower resistance (monotone); at rest the
    constriction is the stationary one (within 1e-12 of V = 0); an EHL film of h um adds
    h / (k_oil pi a b) in series; equal materials share the heat equally (Burton & Staph)."""
    st = MATERIALS["GCr15"]
    Rs = [rolling_contact_conductance(0.55, 0.08, v, st, st, 14).R_ring_K_W
          for v in (0.0, 100.0, 1000.0, 3000.0)]
    assert all(x > y for x, y in zip(Rs, Rs[1:]))
    dry = rolling_contact_conductance(0.55, 0.08, 1700.0, st, st, 14)
    wet = rolling_contact_conductance(0.55, 0.08, 1700.0, st, st, 14, film_um=0.3)
    assert isinstance(wet, ContactConductance)
    assert wet.R_film_K_W == pytest.approx(0.3e-6 / (0.14 * np.pi * 0.55 * 0.08e-6), rel=1e-12)
    assert 14.0 / wet.G_W_K == pytest.approx(14.0 / dry.G_W_K + wet.R_film_K_W, rel=1e-12)
    assert wet.ring_share == pytest.approx(0.5, abs=1e-15) and dry.ring_share == pytest.approx(0.5, abs=1e-15)
    # a Si3N4 ball (k 30 against 46.6 W/(m K), kappa 13.8 against 12.6 mm2/s): its side
    # resists more (sqrt(kappa)/k at high Pe), so the ring takes more than half
    hyb = rolling_contact_conductance(0.55, 0.08, 1700.0, MATERIALS["Si3N4"], st, 14)
    assert hyb.ring_share > 0.5


def test_solid_film_heat_is_the_torque_times_the_speed():
    """A solid-film pair's heat is its friction torque times |omega| (omega = 2 pi n / 60), the
    contact split adding up to it (nothing lost, nothing viscous)."""
    from analytic.friction.pair import pair_torque
    t = pair_torque(G, PAIR, model="solid_film", mu=0.02, hysteresis_loss=0.01, speed_rpm=N_RPM)
    from analytic.heat import solid_film_pair_heat_W
    h = solid_film_pair_heat_W(t, N_RPM)
    w = 2 * np.pi * np.abs(N_RPM) / 60.0 * 1e-3          # N mm/s -> W
    assert np.allclose(h.total_W, t.torque_Nmm * w, rtol=1e-12)
    assert np.allclose(h.inner_W + h.outer_W, h.total_W, rtol=1e-12)
    assert np.all(h.viscous_W == 0.0)


def test_oil_conductivity_under_hertz_pressure_matches_the_closed_form_mean():
    """The film's mean conductivity ratio over a Hertz ellipse against the closed form of
    int_0^1 (1 + A p0 s / (1 + B p0 s)) 2 s ds = 1 + 2 A p0 (c^2/2 - c + ln(1 + c)) / c^3,
    c = B p0 (p0 in GPa, below the cap of the fit), to 1e-10 of the ratio; at ambient pressure
    the ratio is 1 and the film resistance is the ambient one; under 1.0 GPa peak the film
    resistance falls by exactly that mean ratio (everything else unchanged)."""
    from analytic.heat import (K_OIL_PRESSURE_A_PER_GPA as A, K_OIL_PRESSURE_B_PER_GPA as B,
                               hertz_mean_conductivity_ratio, oil_conductivity_ratio)
    for p0 in (0.3, 0.7, 1.0):
        c = B * p0
        exact = 1.0 + 2.0 * A * p0 * (c * c / 2.0 - c + np.log1p(c)) / c ** 3
        assert hertz_mean_conductivity_ratio(1e3 * p0) == pytest.approx(exact, rel=1e-10)
    assert oil_conductivity_ratio(0.0) == 1.0 and hertz_mean_conductivity_ratio(0.0) == 1.0
    st = MATERIALS["GCr15"]
    amb = rolling_contact_conductance(0.55, 0.08, 1700.0, st, st, 14, film_um=0.3)
    hp = rolling_contact_conductance(0.55, 0.08, 1700.0, st, st, 14, film_um=0.3, p_max_MPa=1000.0)
    assert amb.R_film_K_W / hp.R_film_K_W == pytest.approx(hertz_mean_conductivity_ratio(1000.0),
                                                           rel=1e-12)
    assert hp.R_ball_K_W == amb.R_ball_K_W and hp.R_ring_K_W == amb.R_ring_K_W
