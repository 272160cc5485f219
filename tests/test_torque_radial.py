"""Friction torque of a pair whose balls carry unequal loads (radial load, moment): the sum over
every ball's own contacts (`friction.pair.pair_torque` with `PairState.radial`).

Checked against: the axial-only route in the limit of a vanishing radial load (every ball alike,
Z times one ball), and a second route to every ball's contact: the Hertz point contact solved from
the ball/raceway radii at the ball's own contact angle (`hertz.hertz_point_contact`,
`hertz.ball_raceway_radii_mm`) instead of the solver's ellipticity table, with the rolling-
resistance formula summed ball by ball."""
import numpy as np

from analytic import hertz
from analytic.bearing import BearingGeometry, solve_pair
from analytic.friction.pair import pair_torque
from analytic.torque import ball_kinematics, hysteresis_rolling_force_N

G = BearingGeometry.from_catalogue("71807C")
SPAN = 14.0
FILM = dict(model="solid_film", mu=0.02, hysteresis_loss=0.1)


def test_vanishing_radial_load_gives_the_axial_only_torque():
    """Fr = 1e-6 N on a 100 N preloaded pair: the per-ball sum equals Z times one ball of the
    axial-only state to the first-order change of the ball loads (2 Fr / Z / Q ~ 1e-8)."""
    axial = pair_torque(G, solve_pair(G, "DB", preload_assembled_N=[100.0, 300.0]), **FILM)
    tiny = solve_pair(G, "DB", preload_assembled_N=[100.0, 300.0], radial_load_N=1e-6,
                      bearing_span_mm=SPAN)
    assert tiny.radial.unequal_balls.all()
    radial = pair_torque(G, tiny, **FILM)
    for key in ("torque_Nmm", "hysteresis_Nmm", "spin_Nmm", "differential_Nmm"):
        np.testing.assert_allclose(getattr(radial, key), getattr(axial, key), rtol=1e-7,
                                   err_msg=key)


def _rolling_resistance_Nmm(Q, alpha_deg):
    """Hysteresis torque of balls with loads Q (N) at contact angles alpha_deg, summed over axis
    0, from Hertz point contacts at each ball's own radii (alpha_h = 0.1)."""
    kin = ball_kinematics(G.dm_mm, G.Dw_mm, np.radians(alpha_deg))
    total = 0.0
    for race, f, roll in (("inner", G.f_i, kin.roll_inner), ("outer", G.f_o, kin.roll_outer)):
        Rx, Ry = hertz.ball_raceway_radii_mm(G.Dw_mm, G.dm_mm, alpha_deg, f, race)
        hc = hertz.hertz_point_contact(Q, Rx, Ry, G.E_star_MPa)
        total = total + (hysteresis_rolling_force_N(0.1, Q, hc.b_mm, Rx) * 0.5 * G.dm_mm
                         * roll).sum(axis=0)
    return total


def test_rolling_resistance_under_radial_load_is_the_sum_over_every_balls_hertz_contact():
    """mu = 0 leaves the hysteresis term alone; rebuild it ball by ball from Hertz point contacts
    at each ball's load and contact angle (a second route to the ellipse) and the outer-race
    control kinematics at that angle. Z times the most loaded ball (what the pair reported before
    it summed the balls) is an overestimate at every load."""
    Fr = np.array([50.0, 200.0, 800.0])
    pair = solve_pair(G, "DB", preload_assembled_N=100.0, radial_load_N=Fr, bearing_span_mm=SPAN)
    got = pair_torque(G, pair, model="solid_film", mu=0.0, hysteresis_loss=0.1).torque_Nmm
    r = pair.radial
    want = sum(_rolling_resistance_Nmm(r.ball_loads_N[j], r.ball_contact_angles_deg[j])
               for j in range(2))
    # relative to the torque; the two Hertz routes agree to ~1e-10 (tests/test_hertz.py)
    np.testing.assert_allclose(got, want, rtol=1e-8)
    top = sum(G.Z * _rolling_resistance_Nmm(pair.ball_load_N[j][None], pair.contact_angle_deg[j][None])
              for j in range(2))
    assert np.all(got < top), (got, top)
