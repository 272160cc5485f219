"""analytic/heat.py: the heat split of a pair against independent statements: what the contacts
generate is what the mechanisms generate (the split into inner and outer loses nothing), the
viscous part is M |omega| with omega = 2 pi n / 60, and sliding and spin heat scale with the
traction coefficient."""
import numpy as np

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
