"""The `stiffness` CSV's full 5 x 5 and the rows that lost the preload:

- every one of the 25 columns against a central finite difference of the pair's equilibrium
  forces, computed here: the balls' forces at displaced groove centres (the model's ball force
  law, solved afresh), moved by this test's own rigid-body kinematics (u = t + theta x r at each
  inner groove centre) and summed into forces and moments about the pair's centre here, the
  preload paths re-equilibrated by a static condensation of the differenced 7 x 7, to 1e-4 of
  sqrt(k_ii k_jj);
- the matrix symmetric to round-off where the model is conservative;
- `--free-axial`'s k_xx_condensed against a central difference of `simulate`'s radial
  displacement with the radial load stepped (axial load and moment held);
- a lost preload: written beside the stiffness with one warning line; --ross refuses those rows.
"""
import dataclasses

import numpy as np
import pandas as pd
import pytest

import bearingfem
from analytic.bearing import BearingGeometry, solve_pair
from analytic.bearing import stiffness as stiffness_module
from analytic.bearing.stiffness import ball_tangents, pair_balls, pair_stiffness
from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline, table_inputs
from studies.usecases.stiffness import equilibrium

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"
#: seed 001 loses its preload between 20 and 50 C (measured: 7 N at 20 C, 0 at 50 C)
CFG_LOST = CONFIG_DIR / "seed001_flywheel_hybrid.toml"
#: the 25 names, typed here in matrix order (row: the load F_x, F_y, F_z, M_x, M_y; column: the
#: motion x, y, z, theta_x, theta_y); docs/cli.md "Bearing stiffness"
GRID = [
    ["k_xx_N_per_mm", "k_xy_N_per_mm", "k_x_z_N_per_mm", "k_x_tx_N_per_mrad", "k_x_ty_N_per_mrad"],
    ["k_yx_N_per_mm", "k_yy_N_per_mm", "k_y_z_N_per_mm", "k_y_tx_N_per_mrad", "k_y_ty_N_per_mrad"],
    ["k_z_x_N_per_mm", "k_z_y_N_per_mm", "k_zz_N_per_mm", "k_z_tx_N_per_mrad",
     "k_z_ty_N_per_mrad"],
    ["k_tx_x_Nmm_per_mm", "k_tx_y_Nmm_per_mm", "k_tx_z_Nmm_per_mm", "k_tx_Nmm_per_mrad",
     "k_tx_ty_Nmm_per_mrad"],
    ["k_ty_x_Nmm_per_mm", "k_ty_y_Nmm_per_mm", "k_ty_z_Nmm_per_mm", "k_ty_tx_Nmm_per_mrad",
     "k_ty_Nmm_per_mrad"],
]
#: per mrad = 1e-3 per rad (the columns of the tilts)
PER_MRAD = np.array([1.0, 1.0, 1.0, 1e-3, 1e-3])
#: combined loads and two temperatures: every entry of the matrix is in play
ROWS = {"T_ambient_C": np.array([20.0, 60.0, 40.0]), "speed_rpm": np.array([60.0, 60.0, 60.0]),
        "radial_load_N": np.array([200.0, 100.0, 0.0]),
        "axial_load_N": np.array([50.0, -30.0, 0.0]),
        "moment_Nmm": np.array([0.0, 1500.0, 0.0])}


def pair_forces(balls, q, w):
    """(5, N) loads the balls exert on the rotor about the pair's centre, F_x, F_y, F_z (N),
    M_x, M_y (N mm), and (2, N) the axial loads on the two preload paths, when the rotor moves by
    q = (x, y, z, theta_x, theta_y) (5, N) and the paths give by w (2, N).  Kinematics here: the
    inner groove centre of ball k at r = (R cos psi, R sin psi, z_c) moves by u = t + theta x r
    (theta = (theta_x, theta_y, 0)); its axial distance from the outer groove centre changes by
    s u_z - w, its radial one by u . e_r.  The ball's force (f_X axial, f_Y radial; the model's
    law at the new distances, `ball_tangents`) acts on the rotor as F = f_Y e_r + s f_X e_z at r,
    moment r x F."""
    Z = balls.g.Z
    psi = 2.0 * np.pi * np.arange(Z) / Z
    c, sn = np.cos(psi)[None, :, None], np.sin(psi)[None, :, None]
    R, zc = balls.R_i_mm[:, None, :], balls.z_c_mm[:, None, :]
    s = balls.s[:, :, None]
    x, y, z, tx, ty = (v[None, None, :] for v in q)
    ux, uy, uz = x + ty * zc, y - tx * zc, z + tx * R * sn - ty * R * c
    bt = ball_tangents(balls, balls.X_mm + s * uz - w[:, None, :],
                       balls.Y_mm + ux * c + uy * sn)
    Fx, Fy, Fz = bt.f_Y_N * c, bt.f_Y_N * sn, s * bt.f_X_N
    Mx = R * sn * Fz - zc * Fy
    My = zc * Fx - R * c * Fz
    F = np.stack([v.sum(axis=(0, 1)) for v in (Fx, Fy, Fz, Mx, My)])
    return F, -bt.f_X_N.sum(axis=1)


def fd_matrix(balls, h_mm=1e-5):
    """(N, 5, 5): central differences of `pair_forces` in (q, w_A, w_B), then the paths
    re-equilibrated: the path's own spring 1/c on w (rigid path: w held; a floating path, 1/c = 0,
    holds nothing beyond its balls) and w condensed out, K_qq - K_qw (K_ww + 1/c)^+ K_wq (static
    condensation; Guyan 1965).  Tilt steps h / R (every groove centre moves by about h)."""
    N = balls.n_points
    steps = np.array([h_mm] * 3 + [h_mm / float(balls.R_i_mm.max())] * 2 + [h_mm] * 2)
    K7 = np.zeros((N, 7, 7))
    for d in range(7):
        F = []
        for sg in (1.0, -1.0):
            q, w = np.zeros((5, N)), np.zeros((2, N))
            if d < 5:
                q[d] = sg * steps[d]
            else:
                w[d - 5] = sg * steps[d]
            F.append(np.concatenate(pair_forces(balls, q, w)))
        K7[:, :, d] = ((F[0] - F[1]) / (2.0 * steps[d])).T
    out = np.empty((N, 5, 5))
    for n in range(N):
        free = [j for j in range(2) if np.isfinite(balls.inv_c_N_per_mm[j, n])]
        wi = [5 + j for j in free]
        Kww = K7[n][np.ix_(wi, wi)] + np.diag(balls.inv_c_N_per_mm[free, n])
        out[n] = K7[n, :5, :5] - K7[n][:5, wi] @ np.linalg.pinv(Kww) @ K7[n][wi, :5]
    return out


@pytest.fixture(scope="module")
def seed000_csv(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("k")
    cond = tmp / "c.csv"
    pd.DataFrame(ROWS).to_csv(cond, index=False)
    out = tmp / "k.csv"
    assert main(["stiffness", str(CFG), str(cond), "-o", str(out), "--free-axial"]) == 0
    return pd.read_csv(out)


def test_every_entry_of_the_csv_against_central_differences_of_the_pair_forces(seed000_csv):
    """Seed 000 (quasi-static balls, a compliant preload path from the FE), three rows (radial
    + axial load, radial + negative axial load + moment, preload only): each of the 25 columns
    (back to N, mm, rad) against `fd_matrix` at the equilibrium of the same rows, to 1e-4 of
    sqrt(|k_ii k_jj|) (the scale an off-diagonal entry is measured on; truncation of the step
    1e-5 mm against ball approaches ~1e-3 mm: ~1e-4 of a term at most, measured 1.1e-6;
    the CSV's 10 digits)."""
    asm = load_assembly(CFG)
    pipe = Pipeline.shared(asm)
    eq = equilibrium(pipe, table_inputs(asm, ROWS))
    balls = pair_balls(pipe.geom, asm.arrangement, eq.pair, **eq.pair_args)
    assert np.isfinite(balls.inv_c_N_per_mm).all()     # the path's condensation is in play
    K = fd_matrix(balls)
    d = np.sqrt(np.abs(np.diagonal(K, axis1=1, axis2=2)))
    for i in range(5):
        for j in range(5):
            col = seed000_csv[GRID[i][j]].to_numpy() / PER_MRAD[j]
            err = np.abs(col - K[:, i, j]) / (d[:, i] * d[:, j])
            assert np.all(err <= 1e-4), (GRID[i][j], err, col, K[:, i, j])
    # the couplings the new columns carry are not all zero (k_x_z, k_z_ty under load)
    assert abs(seed000_csv["k_x_z_N_per_mm"][0]) > 1e-3 * seed000_csv["k_xx_N_per_mm"][0]
    assert abs(seed000_csv["k_z_ty_N_per_mrad"][1]) > 1e-3 * np.sqrt(
        seed000_csv["k_zz_N_per_mm"][1] * seed000_csv["k_ty_Nmm_per_mrad"][1])


G = BearingGeometry.from_catalogue("71807C")


@pytest.mark.parametrize("c,kind", [(2e-5, "position"), (0.0, "spring")])
def test_quasi_dynamic_matrix_against_central_differences(c, kind):
    """Quasi-dynamic balls at 20000 rpm (71807C pair, DB, span 14 mm, 200 N preload, combined
    loads; a compliant path and a spring preload whose B path floats): the pair's 5 x 5 against
    `fd_matrix` to 1e-4 of sqrt(|k_ii k_jj|) (measured 0.7e-6 and 1.3e-6)."""
    args = dict(axial_load_N=np.array([0.0, 50.0, 30.0]),
                radial_load_N=np.array([0.0, 300.0, 100.0]),
                moment_Nmm=np.array([0.0, 0.0, 2000.0]), preload_assembled_N=200.0,
                bearing_span_mm=14.0, compliance_mm_per_N=c, preload_kind=kind,
                ball_model="quasi_dynamic", speed_rpm=20000.0, control="outer",
                dr_mm=np.array([[0.002], [0.001]]), dz_mm=np.array([[0.0005], [-0.0003]]),
                T_inner_ring_C=40.0, T_outer_ring_C=30.0, T_ball_C=35.0)
    st = solve_pair(G, "DB", **args)
    assert st.converged.all()
    K = pair_stiffness(G, "DB", st, **args).pair_N_mm_rad
    F = fd_matrix(pair_balls(G, "DB", st, **args))
    d = np.sqrt(np.abs(np.diagonal(F, axis1=1, axis2=2)))
    err = np.abs(K - F) / (d[:, :, None] * d[:, None, :])
    assert np.all(err <= 1e-4), err.max()


def test_matrix_symmetric_to_round_off_where_the_model_is_conservative(monkeypatch):
    """Quasi-static balls with each ball's K_n held at its value (the contact force then derives
    from the potential sum_k (2/5) K_n,k delta_k^2.5): the pair's matrix and each bearing's are
    symmetric to 1e-12 of sqrt(|k_ii k_jj|) (round-off of sums of ~1e3 terms).  The model's
    K_n(alpha) (the raceways' curvature at the contact moves with the angle) makes the force
    non-conservative by kt dlnK_n/dalpha n t^T: measured 2.3e-7 of that scale (docs/cli.md), and
    the quasi-dynamic balls' friction and gyroscopic forces more (measured up to 2.6e-4)."""
    real = stiffness_module.contact_stiffness

    def frozen(*a, **kw):
        cs = real(*a, **kw)
        return dataclasses.replace(cs, dlnKn_dalpha=np.zeros_like(cs.dlnKn_dalpha))

    monkeypatch.setattr(stiffness_module, "contact_stiffness", frozen)
    asm = load_assembly(CFG)
    pipe = Pipeline.shared(asm)
    eq = equilibrium(pipe, table_inputs(asm, ROWS))
    k = pair_stiffness(pipe.geom, asm.arrangement, eq.pair, **eq.pair_args)
    for K in (k.pair_N_mm_rad, k.bearing_N_mm_rad[0], k.bearing_N_mm_rad[1]):
        d = np.sqrt(np.abs(np.diagonal(K, axis1=-2, axis2=-1)))
        asym = np.abs(K - np.swapaxes(K, -1, -2)) / (d[..., :, None] * d[..., None, :])
        assert asym.max() <= 1e-12, asym.max()


def test_condensed_radial_stiffness_is_simulate_force_controlled(seed000_csv):
    """k_xx_condensed_N_per_mm (--free-axial) against `simulate`: the radial load stepped by
    +-1 N about each row's (axial load and moment held), 2 N / the change of
    radial_displacement_um, to 1e-4 of k_xx_condensed (central difference: truncation
    ~(1 N / load scale)^2; the solvers converge to 1e-10 of their loads).  Where the load is
    combined, k_xx (the held-DOF entry) differs from it by more than 1e-3 (the axial position and
    the tilt move)."""
    asm = load_assembly(CFG)
    disp = []
    for dF in (1.0, -1.0):
        rows = dict(ROWS, radial_load_N=ROWS["radial_load_N"] + dF)
        disp.append(1e-3 * np.asarray(bearingfem.simulate(asm, rows)["radial_displacement_um"]))
    k_fd = 2.0 / (disp[0] - disp[1])
    k_c = seed000_csv["k_xx_condensed_N_per_mm"].to_numpy()
    assert np.all(np.abs(k_c - k_fd) <= 1e-4 * k_c), (k_c, k_fd)
    k_held = seed000_csv["k_xx_N_per_mm"].to_numpy()
    assert np.all(np.abs(k_held - k_c)[:2] > 1e-3 * k_c[:2]), (k_held, k_c)


def test_lost_preload_is_written_beside_the_stiffness_with_one_warning(tmp_path, capsys):
    """Seed 001 at 20 C keeps a preload (7 N), at 50 and 60 C loses it (no external load: every
    ball unloaded, the k columns 0, the condensed one too): preload_N and preload_lost beside the
    stiffness, one warning line naming the rows; the preload column equals `simulate`'s."""
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n20,0\n50,0\n60,0\n")
    out = tmp_path / "k.csv"
    assert main(["stiffness", str(CFG_LOST), str(cond), "-o", str(out), "--free-axial"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning" in err[0] and "preload is lost in 2 of 3" in err[0] \
        and "3, 4" in err[0], err
    df = pd.read_csv(out)
    sim = bearingfem.simulate(load_assembly(CFG_LOST),
                              {"T_ambient_C": [20.0, 50.0, 60.0], "speed_rpm": [0.0] * 3})
    np.testing.assert_array_equal(df["preload_lost"], [0.0, 1.0, 1.0])
    np.testing.assert_allclose(df["preload_N"], np.asarray(sim["preload_N"]), rtol=1e-9)
    assert df["preload_N"][0] > 0.0 and (df["preload_N"][1:] == 0.0).all()
    assert (df["k_xx_N_per_mm"][1:] == 0.0).all()
    assert (df["k_xx_condensed_N_per_mm"][1:] == 0.0).all()   # a loose rotor: 0, not NaN
    assert df["k_xx_condensed_N_per_mm"][0] > 0.0


def test_ross_refuses_rows_that_lost_the_preload(tmp_path, capsys):
    """--ross with a row that lost the preload: exit 2, one line naming the row and its speed,
    nothing written (docs/cli.md: a pair without preload has no stiffness that is a function of
    speed)."""
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n20,0\n20,1000\n50,2000\n20,3000\n20,4000\n")
    code = main(["stiffness", str(CFG_LOST), str(cond), "-o", str(tmp_path / "k.csv"),
                 "--ross", str(tmp_path / "r.csv")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "line 4 (speed_rpm 2000)" in err[0] \
        and "preload is lost" in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.csv"]
