"""Single bearing (inner ring 5 DOF) and quasi-dynamic ball equilibrium.

References each test holds the model to:
- Harris's axial-load route (`axial.approach_for_force`, tested against Harris's equation in
  test_bearing.py) for an axially loaded bearing;
- a second, independently written displacement-driven check: from the solver's ring displacement,
  each ball's groove-centre distance from 3-D position vectors (small rotations u = theta x r),
  its stiffness from the textbook radii and the Hertz solver (`hertz.ball_raceway_radii_mm`,
  `contact_stiffness_N_per_mm15`, series sum), and the sum of ball forces and moments r x F;
- Stribeck / Sjovall: radial load on a zero-clearance bearing, Q_max = F_r / (Z J_r(0.5)),
  J_r(0.5) = 0.2288 (Harris & Kotzalas Vol. 1 ch. 7, table of the Sjovall integrals);
- the closed forms of the ball: centrifugal force m omega_c^2 dm/2, the two force equations of
  the ball (Harris Vol. 2 ch. 3 structure) and Euler's equation dH/dt = omega_c x H (the
  moment of the controlling contact's friction), evaluated from the reported angles and loads;
- limits: speed 0 of the quasi-dynamic model is the quasi-static contact.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from analytic import hertz
from analytic.bearing import BearingGeometry, approach_for_force, thermal_geometry
from analytic.bearing.ball_dynamics import solve_balls
from analytic.bearing.contact import axial_state, contact_stiffness
from analytic.bearing.single import balls_at_displacement, solve_single
from analytic.materials import get_material
from analytic.torque import ball_kinematics

G71807 = BearingGeometry.from_catalogue("NSK 71807C")


def deep_groove(clearance_um: float, Z: int = 9, Dw: float = 7.938, dm: float = 38.5):
    """A 6205-like deep-groove bearing; free contact angle from the diametral clearance,
    cos a0 = 1 - P_d / (2 A0) (Harris Vol. 1 ch. 2), written out here."""
    A0 = (0.52 + 0.53 - 1.0) * Dw
    a0 = np.degrees(np.arccos(1.0 - 1e-3 * clearance_um / (2.0 * A0)))
    steel = get_material("GCr15")
    return BearingGeometry(Dw_mm=Dw, Z=Z, dm_mm=dm, f_i=0.52, f_o=0.53, alpha0_deg=a0,
                           ring=steel, ball=steel)


# ---------------------------------------------------------------------------------------------
# ball level
def _static_contact(g, X, Y):
    tg = thermal_geometry(g)
    cs = contact_stiffness(g, tg, np.arctan2(X, Y))
    return axial_state(X, Y, tg.A_T_mm, cs.Kn, 1)


def test_ball_speed_zero_is_the_quasi_static_contact():
    """F_c = M_g = 0: the ball centre lies on the centre line, Q_i = Q_o = K_n delta^1.5 at one
    angle (relative 1e-9 of the load: the two routes share only K_n)."""
    g = G71807
    a0 = np.radians(g.alpha0_deg)
    X = g.A0_mm * np.sin(a0) + np.array([0.001, 0.004, 0.012, 0.02, -0.003])
    Y = g.A0_mm * np.cos(a0) + np.array([0.0, 0.002, -0.001, 0.004, 0.0])
    st = _static_contact(g, X, Y)
    b = solve_balls(g, X, Y, 0.0)
    assert b.converged.all()
    loaded = st.Q_N > 0
    assert loaded.sum() == 4
    for Q in (b.load_inner_N, b.load_outer_N):
        np.testing.assert_allclose(Q[loaded], st.Q_N[loaded], rtol=1e-9)
        assert np.all(Q[~loaded] == 0.0)
    for a in (b.contact_angle_inner_deg, b.contact_angle_outer_deg):
        np.testing.assert_allclose(a[loaded], np.degrees(st.alpha_rad[loaded]), rtol=0, atol=1e-9)
    # unloaded balls (delta = 0) against the same 1e-9 relative to the largest deformation
    np.testing.assert_allclose(b.approach_inner_mm + b.approach_outer_mm, st.delta_mm,
                               rtol=1e-9, atol=1e-9 * np.max(st.delta_mm))


@pytest.mark.parametrize("control", ["outer", "inner"])
def test_ball_at_speed_closed_forms(control):
    """At speed: F_c = m omega_c^2 dm/2 with m = rho pi Dw^3/6 (rho in N s^2/mm^4: 1 kg/m^3 =
    1e-12) and omega_c from the kinematics of the control hypothesis at the solved angles
    (`torque.ball_kinematics`, itself checked in tests/test_ball_balance.py); Harris's
    two force equations of the ball hold to 1e-9 of the loads; and the outer contact angle falls,
    the inner rises against the static angle (the centrifugal force loads the outer race)."""
    g = G71807
    a0 = np.radians(g.alpha0_deg)
    X = g.A0_mm * np.sin(a0) + np.array([0.004, 0.01, 0.02])
    Y = np.full(3, g.A0_mm * np.cos(a0))
    speed = 20000.0
    b = solve_balls(g, X, Y, speed, control=control)
    assert b.converged.all()
    ai, ao = np.radians(b.contact_angle_inner_deg), np.radians(b.contact_angle_outer_deg)
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, ai, ao, outer_control=control == "outer")
    omega = speed * 2.0 * np.pi / 60.0
    m = g.ball.density_kg_m3 * 1e-12 * np.pi * g.Dw_mm ** 3 / 6.0
    np.testing.assert_allclose(b.centrifugal_force_N, m * (kin.cage * omega) ** 2 * g.dm_mm / 2,
                               rtol=1e-12)
    J = m * g.Dw_mm ** 2 / 10.0
    np.testing.assert_allclose(b.gyroscopic_moment_Nmm, J * kin.cage * omega * kin.omega_r * omega,
                               rtol=1e-12)
    lam_i, lam_o = (0.0, 2.0) if control == "outer" else (2.0, 0.0)
    Qi, Qo, Mg, Fc, D = (b.load_inner_N, b.load_outer_N, b.gyroscopic_moment_Nmm,
                         b.centrifugal_force_N, g.Dw_mm)
    axial = Qi * np.sin(ai) - Qo * np.sin(ao) + Mg / D * (lam_i * np.cos(ai) - lam_o * np.cos(ao))
    radial = (Qi * np.cos(ai) - Qo * np.cos(ao) - Mg / D * (lam_i * np.sin(ai) - lam_o * np.sin(ao))
              + Fc)
    assert np.all(np.abs(axial) <= 1e-9 * Qo) and np.all(np.abs(radial) <= 1e-9 * Qo)
    # Euler's equation of the ball: the friction (what balances the normal and centrifugal
    # forces) at the controlling contact has the moment dH/dt = omega_c e_z x J Omega = +M_g e_t
    # about the ball centre; moment about e_t of (f_a, f_r) at offset (a, r): a f_r - r f_a
    f_a = -(Qi * np.sin(ai) - Qo * np.sin(ao))
    f_r = -(Qi * np.cos(ai) - Qo * np.cos(ao) + Fc)
    n = (np.sin(ao), np.cos(ao)) if control == "outer" else (-np.sin(ai), -np.cos(ai))
    moment = 0.5 * D * (n[0] * f_r - n[1] * f_a)
    assert np.all(Mg > 0)
    np.testing.assert_allclose(moment, Mg, rtol=1e-8)
    static = np.arctan2(X, Y)
    assert np.all(ao < static) and np.all(ai > static)
    assert np.all(Qo > Qi)


# ---------------------------------------------------------------------------------------------
# single bearing
def test_axial_only_matches_approach_for_force():
    """Pure axial load: every ball alike, axial displacement from the free contact position =
    the approach of Harris's axial-load route (relative 1e-8), contact angle alike."""
    g = G71807
    F = np.array([20.0, 150.0, 600.0, 2000.0])
    st = solve_single(g, axial_load_N=F)
    assert st.converged.all()
    ap = approach_for_force(g, F)
    a0 = np.radians(g.alpha0_deg)
    np.testing.assert_allclose(st.axial_mm - g.A0_mm * np.sin(a0), ap.a_mm, rtol=1e-8)
    np.testing.assert_allclose(st.most_loaded("contact_angle_inner_deg"),
                               np.degrees(ap.alpha_rad), rtol=1e-10)
    assert np.all(np.abs(st.radial_mm) < 1e-12) and np.all(np.abs(st.tilt_rad) < 1e-12)


def _independent_loads(g: BearingGeometry, st, R_arm, alpha_K_deg=None):
    """Sum of the ball forces and moments on the inner ring from the solver's displacement,
    written from 3-D vectors: groove centres r_i(psi) = (R_arm cos psi, R_arm sin psi, 0) move by
    t + theta x r_i, the outer ones stay; delta = |(axial, radial) centre distance| - A0;
    Q = K_n delta^1.5 with K_n of the textbook radii; forces on the ring -Q (cos a e_r + sin a e_z)
    acting through r_i; returns the external loads (F_z, F_x, F_y, M_x, M_y) they balance."""
    Z = g.Z
    psi = 2.0 * np.pi * np.arange(Z) / Z
    a0 = np.radians(g.alpha0_deg)
    A0 = (g.f_i + g.f_o - 1.0) * g.Dw_mm
    E = hertz.contact_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    out = []
    for n in range(st.axial_mm.size):
        t = np.array([st.radial_x_mm[n], st.radial_y_mm[n], st.axial_mm[n]])
        th = np.array([st.tilt_x_rad[n], st.tilt_y_rad[n], 0.0])
        tot_F, tot_M = np.zeros(3), np.zeros(3)
        for p in psi:
            e_r = np.array([np.cos(p), np.sin(p), 0.0])
            r = R_arm * e_r
            u = t + np.cross(th, r)
            X = u[2]
            Y = A0 * np.cos(a0) + u @ e_r
            delta = np.hypot(X, Y) - A0
            if delta <= 0:
                continue
            alpha = np.arctan2(X, Y)
            aK = np.degrees(alpha) if alpha_K_deg is None else alpha_K_deg
            K = [hertz.contact_stiffness_N_per_mm15(
                *hertz.ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, aK, f, race), E)
                for f, race in ((g.f_i, "inner"), (g.f_o, "outer"))]
            Q = hertz.series_stiffness_N_per_mm15(*K) * delta ** 1.5
            F_ring = -Q * (np.cos(alpha) * e_r + np.sin(alpha) * np.array([0, 0, 1.0]))
            tot_F += F_ring
            tot_M += np.cross(r, F_ring)
        out.append([-tot_F[2], -tot_F[0], -tot_F[1], -tot_M[0], -tot_M[1]])
    return np.array(out).T


@pytest.mark.parametrize("case", ["angular_contact", "clearance", "iso16281"])
def test_combined_load_balances_ball_by_ball(case):
    """Radial (x and y) + axial + moment (about x and y): the ball forces at the solver's
    displacement, summed independently, give back the applied loads (relative 1e-8 of the
    largest force, moments over the moment arm).  Clearance case: a deep-groove bearing with
    15 um diametral clearance."""
    if case == "clearance":
        g = deep_groove(15.0)
        loads = dict(axial_load_N=[300.0, 50.0], radial_load_x_N=[1000.0, 800.0],
                     radial_load_y_N=[-200.0, 300.0], moment_x_Nmm=[2000.0, -1000.0],
                     moment_y_Nmm=[-3000.0, 0.0])
    else:
        g = G71807
        loads = dict(axial_load_N=[400.0, 200.0], radial_load_x_N=[300.0, 50.0],
                     radial_load_y_N=[100.0, -80.0], moment_x_Nmm=[1500.0, 0.0],
                     moment_y_Nmm=[-2500.0, 800.0])
    conv = "iso16281" if case == "iso16281" else "exact"
    st = solve_single(g, convention=conv, **loads)
    assert st.converged.all() and st.convention == conv
    a0 = np.radians(g.alpha0_deg)
    # moment arm: the inner groove-centre radius (Harris Vol. 1 ch. 2) or the pitch radius (ISO)
    R_arm = (g.dm_mm / 2 + (g.f_i - 0.5) * g.Dw_mm * np.cos(a0)) if conv == "exact" else g.dm_mm / 2
    got = _independent_loads(g, st, R_arm, g.alpha0_deg if conv == "iso16281" else None)
    want = np.array([loads[k] for k in ("axial_load_N", "radial_load_x_N", "radial_load_y_N",
                                        "moment_x_Nmm", "moment_y_Nmm")])
    scale = np.abs(want[:3]).max()
    np.testing.assert_allclose(got[:3], want[:3], rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(got[3:] / R_arm, want[3:] / R_arm, rtol=0, atol=1e-8 * scale)
    assert np.all(st.tilt_rad > 0) and np.all(st.radial_mm > 0)


def test_radial_load_zero_clearance_sjovall():
    """Zero clearance, pure radial load: epsilon = 0.5 and Q_max = F_r / (Z J_r(0.5)), J_r(0.5) =
    0.2288 (Harris & Kotzalas Vol. 1 ch. 7).  The bearing has Z = 40 balls, for which the sum
    over balls differs from the integral by 4e-6 (trapezoidal sum of cos^2.5 over the loaded
    half); tolerance 5e-5 (the table's rounding) + 1e-5."""
    g = deep_groove(0.0, Z=40, Dw=3.0, dm=60.0)
    assert g.alpha0_deg == 0.0
    Fr = np.array([500.0, 3000.0])
    st = solve_single(g, radial_load_x_N=Fr)
    assert st.converged.all()
    Jr = Fr / (g.Z * st.balls.max_ball_load_N)
    np.testing.assert_allclose(Jr, 0.2288, rtol=0, atol=6e-5)
    # half the balls (psi within +-90 deg, the ones at exactly 90 deg touching with zero load)
    assert np.all((st.balls.load_inner_N > 0).sum(axis=0) == 19)


def test_quasi_dynamic_speed_zero_equals_static():
    """The quasi-dynamic ball model at speed 0 reproduces the quasi-static single bearing
    (displacements and ball loads, relative 1e-9)."""
    g = G71807
    loads = dict(axial_load_N=[400.0, 100.0], radial_load_x_N=[300.0, 0.0],
                 moment_y_Nmm=[-2500.0, 0.0], radial_load_y_N=[0.0, 150.0])
    s = solve_single(g, **loads)
    q = solve_single(g, ball_model="quasi_dynamic", speed_rpm=0.0, **loads)
    assert s.converged.all() and q.converged.all()
    for f in ("axial_mm", "radial_x_mm", "radial_y_mm", "tilt_x_rad", "tilt_y_rad"):
        a, b = getattr(s, f), getattr(q, f)
        np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * np.abs(a).max())
    np.testing.assert_allclose(q.balls.load_inner_N, s.balls.load_inner_N, rtol=1e-9,
                               atol=1e-9 * s.balls.load_inner_N.max())


def test_quasi_dynamic_at_speed_loads_balance():
    """At speed the inner ring is still in equilibrium with the applied loads (the inner
    contacts carry them); the outer contact angle of the most loaded ball is below its inner one."""
    g = G71807
    st = solve_single(g, axial_load_N=[300.0], radial_load_x_N=[100.0], moment_y_Nmm=[500.0],
                      speed_rpm=[15000.0], ball_model="quasi_dynamic")
    assert st.converged.all()
    np.testing.assert_allclose(st.balls.loads[:3, 0], [300.0, 100.0, 0.0], rtol=0, atol=1e-8 * 300)
    assert st.most_loaded("contact_angle_outer_deg")[0] < st.most_loaded("contact_angle_inner_deg")[0]
    again = balls_at_displacement(g, st.axial_mm, st.radial_x_mm, st.radial_y_mm, st.tilt_x_rad,
                                  st.tilt_y_rad, 15000.0, ball_model="quasi_dynamic")
    np.testing.assert_allclose(again.load_inner_N, st.balls.load_inner_N, rtol=1e-12)


# ---------------------------------------------------------------------------------------------
# command line
BEARING_TOML = """
[materials.mysteel]
base = "GCr15"
density_kg_m3 = 7800

[bearing]
designation = "6205 test"
bore_mm = 25.0
outside_diameter_mm = 52.0
width_mm = 15.0
ball_diameter_mm = 7.938
ball_count = 9
pitch_diameter_mm = 38.5
inner_groove_ratio = 0.52
outer_groove_ratio = 0.53
radial_internal_clearance_um = 15.0
inner_ring_outer_diameter_mm = 31.0
outer_ring_inner_diameter_mm = 46.0
ring_material = "mysteel"
ball_material = "GCr15"
"""


def _cli(*args):
    """`bearingfem ARGS` in a child process: its exit code and stderr as the shell sees them."""
    return subprocess.run([sys.executable, "-c",
                           "import sys; from studies.app.cli import main; sys.exit(main())",
                           *map(str, args)], capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parents[1])


def _cli_here(*args):
    """`bearingfem ARGS` through the same entry point in this process (`main`'s return value is
    the exit code `_cli`'s child exits with): no interpreter start and imports (about 1 CPU s a
    call); `_cli` keeps a real child's exit code in test_bearing_torque_needs_lubrication_..."""
    import contextlib
    import io

    from studies.app.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return subprocess.CompletedProcess(["bearingfem", *map(str, args)], code, out.getvalue(),
                                       err.getvalue())


def _cli_table(tmp_path, loads_text, *options):
    """Run `bearingfem bearing` on BEARING_TOML and a loads table; the output as a DataFrame."""
    import pandas as pd

    b = tmp_path / "b.toml"
    b.write_text(BEARING_TOML)
    loads = tmp_path / "loads.csv"
    loads.write_text(loads_text)
    out = tmp_path / "out.csv"
    r = _cli_here("bearing", b, loads, "-o", out, *options)
    assert r.returncode == 0, r.stderr
    return pd.read_csv(out)


def _geometry():
    """The bearing of BEARING_TOML built independently (clearance converted by deep_groove)."""
    g = deep_groove(15.0)
    return BearingGeometry(**{**g.__dict__, "ring": get_material("GCr15")})


def test_cli_bearing_good_run(tmp_path):
    df = _cli_table(tmp_path, "radial_load_N,axial_load_N,moment_y_Nmm\n1000,300,0\n800,0,-3000\n",
                    "--convention", "iso16281")
    for c in ("radial_displacement_um", "axial_displacement_um", "tilt_mrad", "max_ball_load_N",
              "contact_angle_inner_deg", "contact_angle_outer_deg", "max_contact_pressure_MPa"):
        assert c in df.columns and np.isfinite(df[c]).all()
    assert set(df["convention"]) == {"iso16281"}
    # the same rows through Python, with the clearance converted independently
    st = solve_single(_geometry(), axial_load_N=[300.0, 0.0], radial_load_x_N=[1000.0, 800.0],
                      moment_y_Nmm=[0.0, -3000.0], convention="iso16281")
    np.testing.assert_allclose(df["max_ball_load_N"], st.balls.max_ball_load_N, rtol=1e-6)
    assert df["outer_race_control"].isna().all()       # no speed column: no raceway control


def test_cli_bearing_jones_control(tmp_path):
    """--control jones with a speed column: the inner raceway controls the most loaded ball at
    100 rpm, the outer at 60000 rpm, and the rows equal the Python route with that control."""
    df = _cli_table(tmp_path, "radial_load_N,axial_load_N,speed_rpm\n500,300,100\n500,300,60000\n",
                    "--control", "jones")
    assert list(df["outer_race_control"]) == [0.0, 1.0]
    st = solve_single(_geometry(), axial_load_N=300.0, radial_load_x_N=500.0, speed_rpm=[100.0, 60000.0],
                      ball_model="quasi_dynamic", control="jones")
    np.testing.assert_allclose(df["max_ball_load_N"], st.balls.max_ball_load_N, rtol=1e-6)


@pytest.mark.parametrize("edit, loads_text, expect", [
    (lambda t: t.replace("radial_internal_clearance_um = 15.0",
                         "radial_internal_clearance_um = 15.0\ncontact_angle_free_deg = 15.0"),
     "axial_load_N\n100\n", "conflicts with bearing.contact_angle_free_deg"),
    (lambda t: t, "axial_load_N,torque_Nmm\n100,1\n", "column 'torque_Nmm': unknown column"),
    (lambda t: t, "axial_load_N\nabc\n", "line 2, column 'axial_load_N'"),
    (lambda t: t.replace('ring_material = "mysteel"', 'ring_material = "unobtainium"'),
     "axial_load_N\n100\n", "bearing.ring_material"),
    (lambda t: t.replace("radial_internal_clearance_um = 15.0", ""),
     "axial_load_N\n100\n", "bearing.contact_angle_free_deg: missing key"),
])
def test_cli_bearing_bad_input(tmp_path, edit, loads_text, expect):
    b = tmp_path / "b.toml"
    b.write_text(edit(BEARING_TOML))
    loads = tmp_path / "loads.csv"
    loads.write_text(loads_text)
    out = tmp_path / "out.csv"
    r = _cli_here("bearing", b, loads, "-o", out)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and expect in lines[0], r.stderr
    assert not out.exists() and not Path(f"{out}.json").exists()


# ------------------------------------------------------------ torque of one bearing
OIL = """
[lubrication]
kind = "oil"
lubricant = "MyOil"
friction_coefficient = 0.002
viscous_factor_f0 = 2.0
speed_rpm = 1000.0

[lubricants.MyOil]
kinematic_viscosity_cSt = [[40.0, 100.0], [100.0, 10.0]]
density_kg_m3 = 860.0
pressure_viscosity_per_GPa = 20.0
"""

FILM = """
[lubrication]
kind = "solid_film"
friction_coefficient = 0.02
hysteresis_loss_factor = 0.01
"""


def _torque_table(tmp_path, lubrication, loads_text):
    import pandas as pd

    from studies.app.cli import main

    b = tmp_path / "b.toml"
    b.write_text(BEARING_TOML + lubrication)
    loads = tmp_path / "loads.csv"
    loads.write_text(loads_text)
    out = tmp_path / "out.csv"
    assert main(["bearing", str(b), str(loads), "-o", str(out)]) == 0
    return pd.read_csv(out)


def test_bearing_torque_oil_is_palmgren_with_the_applied_axial_load(tmp_path):
    """Oil: M = mu F_a dm/2 + 1e-7 f0 (nu n)^(2/3) dm^3 (SKF's simplified load term with r = dm/2;
    Palmgren 1959), written out here: F_a the applied axial load (a radial load on top adds no
    load term: the balls' axial forces still sum to F_a), nu the table's point at the row's oil
    temperature (a two-point Walther law passes through both), n = [lubrication] speed_rpm."""
    df = _torque_table(tmp_path, OIL, "axial_load_N,radial_load_N,T_oil_C\n500,0,40\n1500,0,100\n"
                                      "500,800,40\n")
    dm = 38.5
    expect = [0.002 * Fa * dm / 2 + 1e-7 * 2.0 * (nu * 1000.0) ** (2 / 3) * dm ** 3
              for Fa, nu in ((500.0, 100.0), (1500.0, 10.0), (500.0, 100.0))]
    np.testing.assert_allclose(df["torque_Nmm"], expect, rtol=1e-9)


def test_bearing_torque_solid_film_is_z_times_one_ball_under_axial_load(tmp_path):
    """Solid film under a pure axial load: every ball alike, so the sum over the balls' own
    contacts is Z times one ball with Q = F_a / (Z sin a) (a the reported contact angle) and
    Hertz ellipses from the textbook radii (`hertz.ball_raceway_radii_mm`, the exact point
    contact `hertz_point_contact`), through the pair's film model `solid_film_torque_Nmm`."""
    from analytic.torque import ContactInput, solid_film_torque_Nmm

    df = _torque_table(tmp_path, FILM, "axial_load_N\n300\n1200\n")
    g = _geometry()
    E_star = hertz.contact_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    c_ring = (1.0 - g.ring.nu ** 2) / g.ring.E_MPa
    c_ball = (1.0 - g.ball.nu ** 2) / g.ball.E_MPa
    for Fa, alpha_deg, got in zip((300.0, 1200.0), df["contact_angle_inner_deg"], df["torque_Nmm"]):
        Q = Fa / (g.Z * np.sin(np.radians(alpha_deg)))
        contacts = []
        for race, f in (("inner", g.f_i), ("outer", g.f_o)):
            Rx, Ry = hertz.ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, alpha_deg, f, race)
            h = hertz.hertz_point_contact(Q, Rx, Ry, E_star)
            contacts.append(ContactInput(np.array([Q]), h.a_mm, h.b_mm, h.E_elliptic, Rx))
        t = solid_film_torque_Nmm(g.Z, g.Dw_mm, g.dm_mm, g.f_i, g.f_o,
                                  np.array([np.radians(alpha_deg)]), *contacts, 0.02, 0.01,
                                  c_ring, c_ball)
        assert got == pytest.approx(float(t.total_Nmm[0]), rel=1e-6)
        assert got > 0


def test_bearing_torque_needs_lubrication_and_an_oil_temperature(tmp_path):
    """No [lubrication]: the column is there, empty. An oil without a T_oil_C column: one line,
    exit 2, no output."""
    df = _cli_table(tmp_path, "axial_load_N\n100\n")
    assert "torque_Nmm" in df.columns and df["torque_Nmm"].isna().all()
    b = tmp_path / "b.toml"
    b.write_text(BEARING_TOML + OIL)
    loads = tmp_path / "loads.csv"
    loads.write_text("axial_load_N\n100\n")
    out = tmp_path / "out2.csv"
    r = _cli("bearing", b, loads, "-o", out)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "T_oil_C" in lines[0] and not out.exists()


# ------------------------------------------------------ thermal speed limits
def test_bearing_thermal_speeds_balance_the_heat_written_out(tmp_path):
    """`bearing` writes the ISO 15312 reference speed and the DIN 732 permissible speed. The
    permissible speed is where DIN 732's friction (written out here: f1 F_a dm with f1 = 0.001
    (F_a/C0)^0.33, ISO/TR 14179-2, plus 1e-7 f0 (nu n)^(2/3) dm^3 with nu at the permissible
    70 C, the Walther law through the table's 40 / 100 C points) times omega equals the heat the
    file's k_q takes away through pi B (D + d) between 70 C and 20 C; margin_speed_rpm =
    permissible - the row's speed. The row's oil temperature does not enter (-40 C and 100 C
    rows at one load give one speed). With every thermal key given there is no warning."""
    from math import pi

    from analytic.lubrication import fit_walther

    keys = ("reference_f0r = 1.7\nreference_f1r = 0.0003\nheat_transfer_W_per_mm2_K = 4e-4\n"
            "permissible_temperature_C = 70.0\nambient_temperature_C = 20.0\n")
    b = tmp_path / "b.toml"
    b.write_text(BEARING_TOML + OIL.replace("speed_rpm = 1000.0\n", "speed_rpm = 1000.0\n" + keys))
    loads = tmp_path / "loads.csv"
    loads.write_text("axial_load_N,T_oil_C\n500,40\n1500,100\n1500,-40\n")
    out = tmp_path / "out.csv"
    r = _cli_here("bearing", b, loads, "-o", out)
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    import pandas as pd
    df = pd.read_csv(out)
    dm, Q = 38.5, 4e-4 * pi * 15.0 * (52.0 + 25.0) * 50.0
    nu70 = float(fit_walther([40.0, 100.0], [100.0, 10.0]).nu_mm2_s(70.0))
    for Fa, n in zip((500.0, 1500.0, 1500.0), df["thermal_permissible_speed_rpm"]):
        f1 = 0.001 * (Fa / _C0(dm)) ** 0.33
        M = f1 * Fa * dm + 1e-7 * 2.0 * (nu70 * n) ** (2 / 3) * dm ** 3
        assert M * n * pi / 30e3 == pytest.approx(Q, rel=1e-8)
    perm = df["thermal_permissible_speed_rpm"]
    assert perm.iloc[1] == perm.iloc[2]                    # 100 C and -40 C rows: one speed
    np.testing.assert_allclose(df["margin_speed_rpm"], df["thermal_permissible_speed_rpm"] - 1000.0)
    # the reference speed: the same balance at the ISO 15312 reference state, the row's nothing
    nr = df["thermal_reference_speed_rpm"].iloc[0]
    assert (df["thermal_reference_speed_rpm"] == nr).all()
    M_r = 1e-7 * 1.7 * (12.0 * nr) ** (2 / 3) * dm ** 3 + 0.0003 * 0.05 * _C0(dm) * dm
    assert M_r * nr * pi / 30e3 == pytest.approx(16e-3 * pi * 15.0 * 77.0, rel=1e-8)


def _C0(dm):
    """ISO 76 C0 of BEARING_TOML's bearing (f0 = 12.3 at Dw cos(a)/dm below 0.2 is not assumed:
    taken from analytic.safety, the one route the command also uses for C0)."""
    from analytic.safety import static_load_rating_C0_N
    g = _geometry()
    return float(static_load_rating_C0_N(g.Z, g.Dw_mm, dm, g.alpha0_deg))


def test_bearing_thermal_speed_defaults_warn_once(tmp_path):
    """Without the thermal keys the defaults are used and named in one warning line; without
    [lubrication] the reference speed is still written and the permissible speed is empty."""
    b = tmp_path / "b.toml"
    b.write_text(BEARING_TOML + OIL)
    loads = tmp_path / "loads.csv"
    loads.write_text("axial_load_N,T_oil_C\n500,40\n1500,100\n")
    r = _cli_here("bearing", b, loads, "-o", tmp_path / "out.csv")
    lines = [x for x in r.stderr.splitlines() if "warning" in x]
    assert r.returncode == 0 and len(lines) == 1, r.stderr
    assert "reference_f0r" in lines[0] and "heat_transfer_W_per_mm2_K" in lines[0]
    df = _cli_table(tmp_path, "axial_load_N\n500\n")
    assert np.isfinite(df["thermal_reference_speed_rpm"]).all()
    assert df["thermal_permissible_speed_rpm"].isna().all()
