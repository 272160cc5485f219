"""Bearing pair equilibrium: checked against Harris's axial-load equation, against a second route
(prescribe the rotor displacement, compute the forces directly from the geometry, then invert),
against symmetries and scaling laws (DB/DF mirror, uniform thermal growth = a scaled bearing,
series-spring response), finite-difference stiffness, and the qualitative physics the design
relies on (radial expansion raises preload, Si3N4 balls tighten when cold, spring preload is
independent of shifts, one bearing unloading is reported, not an error)."""
import numpy as np
import pytest

from analytic.bearing import (BearingGeometry, SIGNS, approach_for_force, bearing_axial_force,
                              solve_pair, thermal_geometry)
from analytic.materials import get_material
from bearing_reference import flat, kn_direct


def solve(*args, **kwargs):
    """`bearing.solve_pair`, every array of its state under one name (`bearing_reference.flat`)."""
    return flat(solve_pair(*args, **kwargs))


G = BearingGeometry.from_catalogue("71807C")
A0, ALPHA0 = G.A0_mm, np.radians(G.alpha0_deg)


def force_direct(g, approach, dr=0.0):
    """F = Z K_n delta^1.5 sin(alpha) from the centre-distance geometry (module docstring)."""
    X = A0 * np.sin(ALPHA0) + approach
    Y = A0 * np.cos(ALPHA0) + dr
    D = np.hypot(X, Y)
    alpha = np.arctan2(X, Y)
    delta = np.maximum(D - A0, 0.0)
    return g.Z * kn_direct(g, alpha) * delta ** 1.5 * np.sin(alpha)


@pytest.mark.parametrize("load", [0.0, 150.0, -80.0, 400.0])
@pytest.mark.requirement("R-PAIR-EQUILIBRIUM")
def test_harris_axial_load_equation(load):
    """Harris Vol. 1 ch. 7 (thrust-loaded bearing): Fa = Z K_n A^1.5 (cos a0/cos a - 1)^1.5 sin a, and the axial
    deflection delta_a = A sin(a - a0)/cos a (same chapter), for each loaded bearing of the pair."""
    out = solve(G, "DB", preload_assembled_N=120.0, axial_load_N=load)
    for j in "AB":
        F = out[f"axial_force_N[{j}]"][0]
        if F <= 0:
            continue
        a = np.radians(out[f"contact_angle_deg[{j}]"][0])
        Fa = G.Z * kn_direct(G, a) * A0 ** 1.5 * (np.cos(ALPHA0) / np.cos(a) - 1) ** 1.5 * np.sin(a)
        assert F == pytest.approx(float(Fa), rel=1e-10)
        assert out[f"approach_mm[{j}]"][0] == pytest.approx(A0 * np.sin(a - ALPHA0) / np.cos(a), rel=1e-10)
    # equilibrium
    s = SIGNS["DB"]
    assert s[0] * out["axial_force_N[A]"][0] + s[1] * out["axial_force_N[B]"][0] == pytest.approx(load, abs=1e-9)


@pytest.mark.parametrize("arrangement", ["DB", "DF"])
@pytest.mark.requirement("R-PAIR-EQUILIBRIUM")
def test_second_route_prescribed_displacement(arrangement):
    """Route 2: choose rotor displacements x, compute both bearings' forces directly from the
    geometry (force_direct), form the external load they balance, and give that load to the
    solver: it must return the same x and forces (1e-9)."""
    s = SIGNS[arrangement]
    dr = np.array([[0.6e-3], [-0.3e-3]])
    dz = np.array([[0.4e-3], [-0.9e-3]])
    ref = solve(G, arrangement, preload_assembled_N=100.0, dr_ref_mm=dr, dz_ref_mm=dz,
                     dr_mm=dr, dz_mm=dz)
    e = ref["preload_offset_mm"][0]
    x = ref["x_mm"][0] + np.array([-1.5e-2, -2e-3, -1e-4, 0.0, 3e-4, 2e-3, 1.5e-2])
    F = np.stack([force_direct(G, s[j] * (dz[j] + x) + e, dr[j]) for j in range(2)])
    load = s[0] * F[0] + s[1] * F[1]
    out = solve(G, arrangement, preload_assembled_N=100.0, dr_ref_mm=dr, dz_ref_mm=dz,
                     dr_mm=dr, dz_mm=dz, axial_load_N=load)
    assert np.allclose(out["x_mm"], x, rtol=0, atol=1e-12)
    assert np.allclose(out["axial_force_N[A]"], F[0], rtol=1e-9, atol=1e-9)
    assert np.allclose(out["axial_force_N[B]"], F[1], rtol=1e-9, atol=1e-9)
    assert out["preload_lost"][0] and out["preload_lost"][-1]   # the path unloads one bearing at each end


def test_db_df_mirror_symmetry():
    """With a_j = s_j (dz_j + x) + e and sum s_j F_j = F_ext, flipping every s_j is undone by
    dz -> -dz, x -> -x, F_ext -> -F_ext: DF with mirrored inputs gives the DB forces."""
    rng = np.random.default_rng(3)
    dr = rng.uniform(-1e-3, 1e-3, (2, 6))
    dz = rng.uniform(-2e-3, 2e-3, (2, 6))
    load = rng.uniform(-200, 200, 6)
    db = solve(G, "DB", dr_mm=dr, dz_mm=dz, axial_load_N=load, preload_assembled_N=90.0)
    df = solve(G, "DF", dr_mm=dr, dz_mm=-dz, axial_load_N=-load, preload_assembled_N=90.0)
    for k in ("axial_force_N[A]", "axial_force_N[B]", "contact_angle_deg[A]", "contact_angle_deg[B]"):
        assert np.allclose(db[k], df[k], rtol=1e-11, atol=1e-9)
    # x is a difference of groove-centre positions of size A0 (and dz): round-off relative to them
    assert np.allclose(db["x_mm"], -df["x_mm"], rtol=0, atol=1e-12 * (A0 + np.abs(dz).max()))


@pytest.mark.parametrize("compliance", [0.0, 2e-5])
def test_reference_state_reproduces_assembled_preload(compliance):
    """The offset e is defined by F_A = F_B = P at the reference state: evaluating the reference
    shifts at T_ref must return P exactly, for any per-point P and shifts."""
    P = np.array([10.0, 100.0, 350.0])
    dr = np.array([[1e-3, -5e-4, 0.0], [2e-4, 0.0, -1e-3]])
    dz = np.array([[3e-3, 0.0, -2e-3], [-1e-3, 1e-3, 0.0]])
    out = solve(G, "DB", preload_assembled_N=P, dr_ref_mm=dr, dz_ref_mm=dz, dr_mm=dr,
                     dz_mm=dz, T_inner_ring_C=20.0, T_outer_ring_C=20.0, T_ball_C=20.0,
                     T_ref_C=20.0, compliance_mm_per_N=compliance)
    assert np.allclose(out["axial_force_N[A]"], P, rtol=1e-12)
    assert np.allclose(out["axial_force_N[B]"], P, rtol=1e-12)
    assert np.allclose(out["preload_N"], P, rtol=1e-12)
    assert not out["preload_lost"].any()


def test_uniform_thermal_growth_is_a_scaled_bearing():
    """All-steel bearing, every part at the same temperature, groove centres moving with the
    ring (dr = theta A0 cos a0, dz = s_j theta A0 sin a0): the bearing is the reference one scaled
    by (1 + theta) with the same approach e.  Hertz scaling (forces ~ length^2 at equal strain)
    gives P' = (1 + theta)^2 F_ref(e / (1 + theta)) exactly; the change is O(theta)."""
    T, Tref = 80.0, 20.0
    theta = get_material("9Cr18").thermal_strain(T, Tref)
    s = SIGNS["DB"][:, None]
    dr = theta * A0 * np.cos(ALPHA0) * np.ones((2, 1))
    dz = s * theta * A0 * np.sin(ALPHA0)
    out = solve(G, "DB", preload_assembled_N=100.0, dr_mm=dr, dz_mm=dz, T_inner_ring_C=T,
                     T_outer_ring_C=T, T_ball_C=T, T_ref_C=Tref)
    e = out["preload_offset_mm"][0]
    expected = (1 + theta) ** 2 * force_direct(G, e / (1 + theta))
    assert out["preload_N"][0] == pytest.approx(float(expected), rel=1e-10)
    assert abs(out["preload_N"][0] / 100.0 - 1) < 3 * theta


def test_inner_ring_radial_expansion_raises_preload():
    """A larger inner groove-centre radius (fit expansion, thermal growth of the inner ring)
    reduces the clearance: the position preload rises monotonically (Harris Vol. 1 ch. 8)."""
    dr = np.linspace(0.0, 3e-3, 7)
    out = solve(G, "DB", preload_assembled_N=100.0, dr_mm=dr)
    assert out["preload_N"][0] == pytest.approx(100.0, rel=1e-12)
    assert np.all(np.diff(out["preload_N"]) > 0)


def test_axial_stack_direction_db_vs_df():
    """Inner groove centres spreading axially relative to the outer ones (shaft growing more than
    the housing): a back-to-back pair loses preload, a face-to-face pair gains it."""
    d = 1e-3
    dz = np.array([[-d / 2], [d / 2]])
    db = solve(G, "DB", preload_assembled_N=100.0, dz_mm=dz)["preload_N"][0]
    df = solve(G, "DF", preload_assembled_N=100.0, dz_mm=dz)["preload_N"][0]
    assert db < 100.0 < df


def test_spring_preload_independent_of_shifts():
    rng = np.random.default_rng(7)
    N = 8
    dr = rng.uniform(-2e-3, 2e-3, (2, N))
    dz = rng.uniform(-3e-3, 3e-3, (2, N))
    T = rng.uniform(-60, 80, N)
    load = rng.uniform(-50, 50, N)
    out = solve(G, "DB", preload_kind="spring", preload_assembled_N=60.0, dr_mm=dr, dz_mm=dz,
                     T_inner_ring_C=T, T_outer_ring_C=T, T_ball_C=T, axial_load_N=load)
    assert np.allclose(out["axial_force_N[B]"], 60.0, rtol=1e-12)
    assert np.allclose(out["axial_force_N[A]"], 60.0 + load, rtol=1e-12)   # s_A = +1 (DB)
    assert np.allclose(out["preload_N"], np.minimum(60.0, 60.0 + load), rtol=1e-12)


@pytest.mark.parametrize("kind", ["position", "spring"])
def test_one_bearing_unloading_is_reported(kind):
    """Position preload: a load beyond the preload unloads the opposite bearing (either sign).
    Spring preload (spring on B, DB): a load towards A only adds to F_A; a load towards B larger
    than the spring force would need F_A < 0: lost."""
    load = np.array([0.0, 2000.0, -2000.0])
    out = solve(G, "DB", preload_kind=kind, preload_assembled_N=100.0, axial_load_N=load)
    assert np.all(np.isfinite(out["x_mm"])) and np.all(np.isfinite(out["loaded_contact_angle_deg"]))
    assert out["preload_N"][2] == 0.0
    if kind == "position":   # the other bearing carries the whole load
        assert list(out["preload_lost"]) == [False, True, True]
        assert out["preload_N"][1] == 0.0
        assert out["axial_force_N[A]"][1] == pytest.approx(2000.0, rel=1e-12)
        assert out["axial_force_N[B]"][1] == 0.0
        assert out["axial_force_N[B]"][2] == pytest.approx(2000.0, rel=1e-12)
    else:
        assert list(out["preload_lost"]) == [False, False, True]
        assert out["axial_force_N[A]"][1] == pytest.approx(2100.0, rel=1e-12)
        assert out["axial_force_N[A]"][2] == 0.0
    assert out["pair_axial_stiffness_N_per_um"][1] > 0


@pytest.mark.parametrize("kind,compliance", [("position", 0.0), ("position", 1e-5), ("spring", 0.0)])
def test_axial_stiffness_matches_finite_difference(kind, compliance):
    """d F_ext / d x of the solved pair (central difference over the external load) equals the
    reported pair stiffness, which includes dK_n/dalpha."""
    h = 1e-3
    kw = dict(preload_kind=kind, preload_assembled_N=150.0, compliance_mm_per_N=compliance,
              dr_mm=4e-4, dz_mm=np.array([[2e-4], [-1e-4]]), T_ball_C=40.0)
    out = solve(G, "DB", axial_load_N=np.array([-h, 0.0, h]), **kw)
    x = out["x_mm"]
    k_fd = 2 * h / (x[2] - x[0]) * 1e-3       # N/um
    assert out["pair_axial_stiffness_N_per_um"][1] == pytest.approx(k_fd, rel=1e-6)


def test_preload_change_is_series_spring_response():
    """A small change dS of the available interference (dz_A - dz_B in DB) changes the preload
    by dS / (1/k_A + 1/k_B + 2c) (two bearings and two compliances in series)."""
    c = 1e-5
    d = 1e-6
    dz = np.array([[0.0, d / 2], [0.0, -d / 2]])
    out = solve(G, "DB", preload_assembled_N=100.0, dz_mm=dz, compliance_mm_per_N=c)
    kA = out["axial_stiffness_N_per_um[A]"][0] * 1e3
    kB = out["axial_stiffness_N_per_um[B]"][0] * 1e3
    # reported stiffnesses include the compliance: k_eff = 1/(1/k + c)
    expected = d / (1 / kA + 1 / kB)
    assert out["preload_N"][1] - out["preload_N"][0] == pytest.approx(expected, rel=2e-3)


def test_ceramic_balls_tighten_when_cold():
    """Si3N4 balls (CTE 3.2e-6/K) in steel rings (10.5e-6/K): rings shrinking more than balls when
    cold reduce the clearance, so a position preload rises when cold and falls when hot; the same
    temperatures in an all-steel bearing change it only by the scale effect."""
    hyb = BearingGeometry.from_catalogue("flywheel")
    steel = BearingGeometry(**{**hyb.__dict__, "ball": hyb.ring})
    T = np.array([-20.0, 20.0, 60.0])
    res = {}
    for name, g in (("hybrid", hyb), ("steel", steel)):
        th = g.ring.thermal_strain(T, 20.0)
        a0 = np.radians(g.alpha0_deg)
        s = SIGNS["DF"][:, None]
        out = solve(g, "DF", preload_assembled_N=30.0, T_inner_ring_C=T, T_outer_ring_C=T,
                         T_ball_C=T, dr_mm=th * g.A0_mm * np.cos(a0),
                         dz_mm=s * th * g.A0_mm * np.sin(a0))
        res[name] = out["preload_N"]
    assert res["hybrid"][0] > 30.0 * 1.5 and res["hybrid"][2] < 30.0 * 0.7
    assert np.all(np.abs(res["steel"] / 30.0 - 1) < 3e-3)


def test_single_bearing_inversion_round_trip():
    """approach_for_force inverts bearing_axial_force (with a radial shift and grown geometry)."""
    tg = thermal_geometry(G, 50.0, 30.0, 45.0, 20.0)
    F = np.array([1.0, 50.0, 500.0, 3000.0])
    ap = approach_for_force(G, F, 1e-3, tg)
    a, alpha = ap.a_mm, ap.alpha_rad
    assert ap.converged.all()
    st, _ = bearing_axial_force(G, a, 1e-3, tg)
    assert np.allclose(st.F_N, F, rtol=1e-11)
    assert np.allclose(st.alpha_rad, alpha, rtol=1e-12)


def test_from_spec_matches_config():
    from pathlib import Path
    from studies.model.config import load_assembly
    cfg = Path(__file__).parents[1] / "studies" / "configs" / "seed000_71807C_TC4.toml"
    spec = load_assembly(cfg).bearing
    g = BearingGeometry.from_spec(spec)
    assert (g.Dw_mm, g.Z, g.dm_mm, g.f_i, g.f_o, g.alpha0_deg) == (
        spec.ball_diameter_mm, spec.ball_count, spec.pitch_diameter_mm, spec.inner_groove_ratio,
        spec.outer_groove_ratio, spec.contact_angle_free_deg)
    assert g.ring.name == spec.ring_material and g.ball.name == spec.ball_material


def test_free_radial_clearance_relation():
    """Harris Vol. 1 ch. 2: cos a0 = 1 - Pd/(2 A0).  With the axial component removed (X = 0),
    taking up the free radial clearance Pd/2 = A0 (1 - cos a0) brings the balls just into contact
    at zero contact angle: delta = 0, no axial force."""
    st, _ = bearing_axial_force(G, -A0 * np.sin(ALPHA0), G.radial_clearance_mm)
    assert st.delta_mm == pytest.approx(0.0, abs=1e-15)
    assert st.F_N == 0.0
    st, _ = bearing_axial_force(G, -A0 * np.sin(ALPHA0), G.radial_clearance_mm + 1e-3)
    assert st.delta_mm == pytest.approx(1e-3, rel=1e-9) and st.F_N == 0.0


def test_chunked_evaluation_equals_one_block():
    rng = np.random.default_rng(11)
    N = 9
    kw = dict(dr_mm=rng.uniform(-1e-3, 1e-3, (2, N)), dz_mm=rng.uniform(-2e-3, 2e-3, (2, N)),
              T_inner_ring_C=rng.uniform(-60, 80, N), axial_load_N=rng.uniform(-300, 300, N),
              preload_assembled_N=100.0)
    one = solve(G, "DB", **kw)
    many = solve(G, "DB", chunk=4, **kw)
    for k, v in one.items():
        # Round-off is relative to the largest term of the same output over the rows (a force
        # that is zero in one row is ~1e-14 N next to a 1e3 N force in another).
        scale = np.nanmax(np.abs(v)) if np.any(np.isfinite(v)) else 0.0
        assert np.allclose(many[k], v, rtol=1e-12, atol=1e-12 * scale, equal_nan=True), k


def test_pair_with_clearance_everywhere_is_unloaded_not_an_error():
    """Inner groove centres pulled 20 um apart axially (DB): both bearings lose contact without
    external load; with a load one of them takes it all."""
    dz = np.array([[-0.02, -0.02], [0.02, 0.02]])
    out = solve(G, "DB", preload_assembled_N=100.0, dz_mm=dz, axial_load_N=[0.0, 50.0])
    assert out["preload_lost"].all()
    assert out["axial_force_N[A]"][0] == 0.0 and out["axial_force_N[B]"][0] == 0.0
    assert out["axial_force_N[A]"][1] == pytest.approx(50.0, rel=1e-12)
    assert out["pair_axial_stiffness_N_per_um"][0] == 0.0


def test_convergence_is_reported_not_hidden():
    """Every row reports whether its root finders converged: the default solve does; one pass of
    the outer K_n loop (K_n changes with the contact angle under 300 N) does not, and says so."""
    kw = dict(preload_assembled_N=100.0, axial_load_N=[0.0, 300.0], dr_mm=[0.0, 2e-3])
    assert solve_pair(G, "DB", **kw).converged.all()
    one_pass = solve_pair(G, "DB", max_outer=1, **kw)
    assert not one_pass.converged[1]
