"""The position-preloaded pair's equilibrium (`axial.position_root`: one Newton iteration on the
rotor position x and both bearings' centre distances X_A, X_B, which replaced a Newton iteration
in x around a Newton iteration per bearing for X + c F(X) = X_nom) held against its own
equations, evaluated here independently of the solver: each bearing's force recomputed from its
approach with the grown geometry and K_n from the Hertz primitives (`bearing_reference.kn_direct`,
Harris & Kotzalas Vol. 1 ch. 7, F = Z K_n delta^1.5 sin(alpha)), then

    sum_j s_j F_j = F_ext                          (force balance on the rotor)
    a_j + c F_j = s_j (dz_j + x) + e               (approach and preload path in series)

over a spread of states: compliance 0, the FE preload path's (~6e-7 mm/N), 2e-5, 0.05 and 500 mm/N
(c k >> 1), external loads across the lift-off of one bearing (rows that just unload), rows
whose preload is lost (both bearings free: an interval of roots), hot and cold rings."""
import numpy as np
import pytest

from analytic.bearing import SIGNS, BearingGeometry, solve_pair, thermal_geometry
from bearing_reference import kn_direct

G = BearingGeometry.from_catalogue("71807C")
A0, ALPHA0 = G.A0_mm, np.radians(G.alpha0_deg)
P_N = 100.0
#: preload-path compliances (mm/N): none, the FE's order, a soft path, a spring-like path, the
#: design search's softest spring (1e-3 N/mm: 500 mm/N per bearing, c F ~ 5e4 mm)
COMPLIANCES = (0.0, 6.0e-7, 2.0e-5, 0.05, 500.0)


def _force_direct(approach_mm, dr_mm, tg):
    """F = Z K_n delta^1.5 sin(alpha) of one bearing (N) from its approach and radial shift, the
    grown geometry tg, K_n from the Hertz primitives (`kn_direct`)."""
    X = A0 * np.sin(ALPHA0) + approach_mm
    Y = A0 * np.cos(ALPHA0) + dr_mm
    alpha = np.arctan2(X, Y)
    delta = np.maximum(np.hypot(X, Y) - tg.A_T_mm, 0.0)
    Kn = kn_direct(G, alpha, Dw=tg.Dw_mm, dm=tg.dm_mm, f_i=tg.f_i, f_o=tg.f_o)
    return G.Z * Kn * delta ** 1.5 * np.sin(alpha)


def _lift_off_N(c):
    """External axial load at which bearing B of the DB pair just unloads (bisection on the
    solver's F_B; only used to place rows on both sides of it)."""
    lo, hi = 0.0, 10.0 * P_N
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        st = solve_pair(G, "DB", preload_assembled_N=P_N, axial_load_N=mid, compliance_mm_per_N=c)
        lo, hi = (mid, hi) if st.axial_force_N[1, 0] > 0.0 else (lo, mid)
    return 0.5 * (lo + hi)


#: rows whose preload is lost under no external load: a radial play (dr, mm) with the rings
#: shifted axially (dz, mm, A then B) so that one bearing is loaded at the reference position
LOST = dict(dr_mm=np.array([-0.008, -0.012, -0.008, -0.012]),
            dz_mm=np.array([[0.02, 0.05, 0.0, 0.0], [0.0, 0.0, -0.03, 0.0]]))


def _rows(c):
    """Operating points at compliance c: loads 0, +-40 N, across the lift-off (relative steps of
    1e-9 and 1e-6 either side) and beyond it, hot/cold rings, and the `LOST` rows."""
    lift = _lift_off_N(c)
    loads = [0.0, 40.0, -40.0, 3.0 * lift, -3.0 * lift]
    loads += [lift * (1.0 + k) for k in (-1e-6, -1e-9, 0.0, 1e-9, 1e-6)]
    loads += [-lift * (1.0 + k) for k in (-1e-9, 1e-9)]
    n = len(loads)
    T_in = [20.0] * n + [80.0, -40.0] + [20.0] * 4
    T_out = [20.0] * n + [20.0, 60.0] + [20.0] * 4
    dr = np.concatenate([np.zeros(n + 2), LOST["dr_mm"]])
    dz = np.concatenate([np.zeros((2, n + 2)), LOST["dz_mm"]], axis=1)
    loads += [0.0] * 6
    return dict(axial_load_N=np.array(loads), T_inner_ring_C=np.array(T_in),
                T_outer_ring_C=np.array(T_out), T_ball_C=np.array(T_in), dr_mm=dr, dz_mm=dz)


@pytest.mark.requirement("R-PAIR-EQUILIBRIUM")
def test_equilibrium_and_compliance_hold_against_an_independent_force():
    """Every row converges, and its state satisfies the balance to 1e-12 of (P + |F_ext| + the
    bearings' forces) and each bearing's series equation to 1e-12 of the sum of the magnitudes
    of its terms (mm), with forces recomputed outside the solver: the solver's own tolerances
    (steps below 1e-15 (1 + |value|) mm, K_n's linear model exact to 1e-14) sit well inside."""
    s = SIGNS["DB"]
    checked = {"just_unloaded": 0, "lost": 0, "compliance_0": 0}
    for c in COMPLIANCES:
        rows = _rows(c)
        st = solve_pair(G, "DB", preload_assembled_N=P_N, compliance_mm_per_N=c, **rows)
        assert st.converged.all()
        tg = thermal_geometry(G, rows["T_inner_ring_C"], rows["T_outer_ring_C"],
                              rows["T_ball_C"], 20.0)
        F = np.array([_force_direct(st.approach_mm[j], rows["dr_mm"], tg) for j in (0, 1)])
        Fext = rows["axial_load_N"]
        balance = s[0] * F[0] + s[1] * F[1] - Fext
        assert np.all(np.abs(balance) <= 1e-12 * (P_N + np.abs(Fext) + np.abs(F).sum(axis=0)))
        for j in (0, 1):
            nominal = s[j] * (rows["dz_mm"][j] + st.x_mm) + st.preload_offset_mm
            terms = (np.abs(st.approach_mm[j]) + np.abs(c * F[j]) + np.abs(nominal)
                     + np.abs(st.preload_offset_mm))
            assert np.all(np.abs(st.approach_mm[j] + c * F[j] - nominal) <= 1e-12 * terms)
        # the solver's state is the same state: its forces equal the recomputed ones
        np.testing.assert_allclose(st.axial_force_N, F, rtol=1e-12, atol=1e-12 * P_N)
        checked["just_unloaded"] += int(np.sum((F.min(axis=0) > 0.0) & (F.min(axis=0) < 1e-3)))
        checked["lost"] += int(np.sum(st.preload_lost & (Fext == 0.0)))
        checked["compliance_0"] += int(c == 0.0) * F.shape[1]
    # the spread really contains the cases named above
    assert checked["just_unloaded"] >= 4 and checked["lost"] >= 4 and checked["compliance_0"] > 0


@pytest.mark.requirement("R-PAIR-EQUILIBRIUM")
def test_lost_preload_ends_on_a_first_contact():
    """A pair whose preload is lost under no external load has a whole interval of rotor
    positions in equilibrium (both bearings free). From a reference position where one bearing
    is loaded the iteration ends where that bearing just touches (the limit of its Newton steps,
    reached directly): its centre distance equals A_T to 1e-15 mm, and pushing it 1e-9 mm
    further loads it. Geometry from the module docstring of `analytic.bearing` (D = |(X, Y)|,
    delta = D - A_T)."""
    n_lost = 0
    for c in COMPLIANCES[:3]:             # the softest path keeps its preload at these shifts
        st = solve_pair(G, "DB", preload_assembled_N=P_N, compliance_mm_per_N=c, **LOST)
        assert st.converged.all()
        # the last row has both bearings free already at the reference position: it stays there
        lost = st.preload_lost & (np.arange(4) < 3)
        assert np.all(np.abs(st.axial_force_N[:, st.preload_lost]) <= 1e-12 * P_N)   # both free
        X = A0 * np.sin(ALPHA0) + st.approach_mm[:, lost]
        Y = A0 * np.cos(ALPHA0) + LOST["dr_mm"][lost]
        A_T = thermal_geometry(G).A_T_mm
        touching = np.abs(np.hypot(X, Y) - A_T) <= 1e-15
        assert touching.sum(axis=0).tolist() == [1] * int(lost.sum())
        assert np.all(np.hypot(X + 1e-9, Y)[touching] - A_T > 0.0)
        n_lost += int(lost.sum())
    assert n_lost >= 8
