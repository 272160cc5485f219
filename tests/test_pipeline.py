"""The FE -> bearing pipeline: superposed vs direct FE, closed-form uniform expansion, the
simulate command's contract."""
import csv
import dataclasses

import numpy as np
import pytest

from analytic.materials import get_material
from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_shipped
from studies.model.inputs import baseline_inputs
from studies.model.pipeline import Pipeline
from studies.model.columns import to_columns

CFG = str(CONFIG_DIR / "seed000_71807C_TC4.toml")


@pytest.fixture(scope="module")
def pl000():
    return Pipeline(load_shipped("seed000"), mesh_factor=2.0)


def _inp(asm, T, **cols):
    cols = {"T_ambient_C": np.asarray(T, float), **{k: np.asarray(v, float) for k, v in cols.items()}}
    return baseline_inputs(cols, len(cols["T_ambient_C"]), asm.T_ref_C, asm.preload.assembled_N,
                           asm.lubrication.speed_rpm)


def test_superposed_pipeline_equals_direct_fe_across_the_outer_fit_closing(pl000):
    T = np.linspace(-60.0, 80.0, 8)            # the outer clearance closes near 41 C
    inp = _inp(pl000.asm, T)
    sup, direct = to_columns(pl000.run(inp)), to_columns(pl000.run(inp, direct=True))
    assert direct["fit_pressure_outer_MPa"][0] == 0 and direct["fit_pressure_outer_MPa"][-1] > 0
    for k in ("torque_Nmm", "preload_N", "contact_angle_deg", "fit_pressure_inner_MPa",
              "fit_pressure_outer_MPa", "groove_shift_dr_A_um", "groove_shift_dz_B_um"):
        scale = np.abs(direct[k]).max()
        assert np.abs(sup[k] - direct[k]).max() <= 1e-8 * scale, k


@pytest.mark.parametrize("T", [-60.0, 80.0])     # outer fit open / closed
def test_row_field_equals_a_direct_fe_solve(pl000, T):
    """`Pipeline.field` (superposed unit solutions) against one direct contact solve of the same
    state: displacements relative to the largest, contact forces relative to the largest."""
    inp = _inp(pl000.asm, [T])
    f = pl000.field(inp)
    theta = pl000.thetas(inp)[0]
    load = pl000.model.unit_loads @ theta + pl000.omega2(inp)[0] * pl000.model.spin_load
    sol = pl000.solver.solve(load, pl000.deltas_mm(*pl000.fits_um(inp))[0])
    np.testing.assert_allclose(f.u_mm, sol.u, rtol=0, atol=1e-8 * np.abs(sol.u).max())
    np.testing.assert_allclose(f.force_N, sol.force_N, rtol=0, atol=1e-8 * np.abs(sol.force_N).max())
    # the raceway displacements the bearing model takes are this field's, probed
    np.testing.assert_allclose(pl000.probe @ f.u_mm, pl000.fe(inp).raceway_u_mm[0], rtol=0,
                               atol=1e-8 * np.abs(sol.u).max())


def test_free_interference_follows_the_cte_difference(pl000):
    a = pl000.asm
    T = np.array([-60.0, 0.0, 80.0])
    out = to_columns(pl000.run(_inp(a, T)))
    ti, ring, th = get_material("TC4"), get_material("9Cr18"), get_material("TC4")
    expect_i = a.fits.inner_interference_um + (ti.thermal_strain(T, 20) - ring.thermal_strain(T, 20)) * 35e3
    expect_o = a.fits.outer_interference_um + (ring.thermal_strain(T, 20) - th.thermal_strain(T, 20)) * 47e3
    assert np.allclose(out["interference_inner_um"], expect_i, rtol=1e-12)
    assert np.allclose(out["interference_outer_um"], expect_o, rtol=1e-12)


def test_uniform_expansion_of_a_one_material_stack_is_a_pure_scale_change():
    """All parts 9Cr18, no fits: the FE must move every groove centre by theta * position, so
    dr = theta (r_ci - r_co) and dz_j = s_j theta A0 sin(a0) exactly (closed form), and the preload
    changes only by the scale of the geometry (e is fixed in mm). At rest (no centrifugal load)."""
    a = load_shipped("seed000")
    same = {f: dataclasses.replace(getattr(a, f), material="9Cr18") for f in
            ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer")}
    a = dataclasses.replace(a, fits=dataclasses.replace(a.fits, inner_interference_um=0.0,
                                                        outer_interference_um=0.0), **same)
    pl = Pipeline(a, mesh_factor=2.0)
    T = np.array([-40.0, 20.0, 70.0])
    out = to_columns(pl.run(_inp(a, T, speed_rpm=np.zeros(3))))
    g = pl.geom
    th = get_material("9Cr18").thermal_strain(T, 20.0)
    a0 = np.radians(g.alpha0_deg)
    assert np.allclose(out["groove_shift_dr_A_um"], 1e3 * th * g.A0_mm * np.cos(a0), atol=1e-9)
    assert np.allclose(out["groove_shift_dz_A_um"], 1e3 * th * g.A0_mm * np.sin(a0), atol=1e-9)
    assert np.allclose(out["groove_shift_dz_B_um"], -1e3 * th * g.A0_mm * np.sin(a0), atol=1e-9)
    assert np.abs(out["fit_pressure_inner_MPa"]).max() < 1e-9       # round-off of a zero fit
    assert abs(out["preload_N"][0] / 100.0 - 1) < 0.01 and abs(out["preload_N"][2] / 100.0 - 1) < 0.01


def test_part_columns_override_the_ambient(pl000):
    a = pl000.asm
    both = to_columns(pl000.run(_inp(a, [20.0, 20.0], T_shaft_C=[20.0, 60.0])))
    hot = to_columns(pl000.run(_inp(a, [60.0])))
    # a hot shaft in a cold ring tightens the inner fit; a uniform 60 C loosens it (TC4 < 9Cr18)
    assert both["interference_inner_um"][1] > both["interference_inner_um"][0] > hot["interference_inner_um"][0]


def _csv(path, header, rows):
    path.write_text(",".join(header) + "\n" + "\n".join(",".join(map(str, r)) for r in rows) + "\n")


def _read(path):
    with open(path) as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def test_simulate_command_writes_every_spec_column(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    _csv(cond, ["T_ambient_C", "speed_rpm"], [[-60, 60], [20, 0], [80, 60]])
    out = tmp_path / "o.csv"
    assert main(["simulate", CFG, str(cond), "-o", str(out)]) == 0
    rows = _read(out)
    for col in ("T_ambient_C", "speed_rpm", "torque_Nmm", "preload_N", "contact_angle_deg",
                "interference_inner_um", "interference_outer_um", "fit_pressure_inner_MPa",
                "fit_pressure_outer_MPa", "max_contact_pressure_MPa"):
        assert col in rows[0]
    assert float(rows[1]["preload_N"]) == pytest.approx(100.0, rel=1e-9)   # assembled: 20 C, at rest
    # an effect at its off value is the baseline exactly
    out2 = tmp_path / "o2.csv"
    assert main(["simulate", CFG, str(cond), "-o", str(out2), "--effect", "radial_gradient:dT_K=0"]) == 0
    assert [r["torque_Nmm"] for r in _read(out2)] == [r["torque_Nmm"] for r in rows]


@pytest.mark.parametrize("content,effect,expect", [
    ("T_ambient_C,bogus\n1,2\n", None, "column 'bogus': unknown column"),
    ("T_ambient_C\n1\nabc\n", None, "line 3, column 'T_ambient_C': 'abc' is not a number"),
    ("T_ambient_C\n1\nnan\n", None, "value is nan"),
    ("time_s,T_ambient_C\n0,1\n0,2\n", None, "time not increasing"),
    ("# only a comment\n", None, "empty table"),
    ("T_ambient_C\n20\n", "nope:x=1", "unknown effect 'nope'"),
    ("T_ambient_C\n20\n", "radial_gradient:dT_K=999", "outside physical bounds"),
    ("T_ambient_C\n20\n", "radial_gradient:bad=1", "unknown parameter 'bad'"),
    ("T_ambient_C\n20\n", "thermal_lag:tau_s=10", "needs the condition column time_s"),
    ("T_ambient_C,axial_load_N\n20,0\n20,1e300\n", None, "line 3, column 'axial_load_N': 1e+300 outside"),
])
def test_simulate_bad_input_exits_2_with_one_line_and_no_output(tmp_path, capsys, content, effect, expect):
    cond = tmp_path / "c.csv"
    cond.write_text(content)
    out = tmp_path / "o.csv"
    argv = ["simulate", CFG, str(cond), "-o", str(out)] + (["--effect", effect] if effect else [])
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and expect in err[0], err
    assert not out.exists() and not list(tmp_path.glob(".o.csv*"))


def test_missing_and_bad_config_exit_2(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    assert main(["simulate", str(tmp_path / "none.toml"), str(cond), "-o", str(tmp_path / "o.csv")]) == 2
    assert "file not found" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text(open(CFG).read().replace('material = "TC4"                   # [paper]\nseat',
                                            'material = "Unobtainium"\nseat'))
    assert main(["simulate", str(bad), str(cond), "-o", str(tmp_path / "o.csv")]) == 2
    assert "shaft.material: unknown material 'Unobtainium'" in capsys.readouterr().err


def test_diagnose_accepts_every_column_simulate_writes(pl000):
    """`diagnose` must read a `simulate` file: every output is comparable or a known extra."""
    from studies.diagnosis.files import COMPARABLE, OUTPUT_NAMES

    out = to_columns(pl000.run(_inp(pl000.asm, [20.0])))
    assert set(out) <= set(COMPARABLE) | OUTPUT_NAMES, set(out) - set(COMPARABLE) - OUTPUT_NAMES


def test_out_folder_not_written_by_bearingfem_is_refused(tmp_path, capsys):
    keep = tmp_path / "mine"
    keep.mkdir()
    (keep / "notes.txt").write_text("precious")
    assert main(["study", "lubricant_viscosity", "--out", str(keep)]) == 2
    assert "holds files bearingfem did not write (notes.txt)" in capsys.readouterr().err
    assert (keep / "notes.txt").read_text() == "precious"
    out = tmp_path / "new"
    assert main(["study", "lubricant_viscosity", "--out", str(out)]) == 0
    assert main(["study", "lubricant_viscosity", "--out", str(out)]) == 0   # its own folder: replaced
    assert (out / "report.md").exists()


def test_unconverged_or_non_finite_rows_raise_model_error_naming_the_row():
    from studies.model.pipeline import CHECKED_OUTPUTS, ModelError, check_answers

    out = {k: np.ones(3) for k in CHECKED_OUTPUTS}
    check_answers(out, np.ones(3, bool))                  # a sound table passes
    with pytest.raises(ModelError, match="row 2: the bearing equilibrium did not converge"):
        check_answers(out, np.array([True, False, True]))
    out["preload_N"] = np.array([1.0, 1.0, np.nan])
    with pytest.raises(ModelError, match="row 3: preload_N is not finite"):
        check_answers(out, np.ones(3, bool))


def test_quasi_dynamic_balls_through_the_pipeline(pl000):
    """`[operating] ball_model = "quasi_dynamic"` (here the run's override): rows at rest give
    the quasi-static answer, with and without radial load and moment (1e-10 of each column's
    scale: no centrifugal force or gyroscopic moment at speed 0); at 20000 rpm the centrifugal force per ball equals m omega_c^2 dm/2 with
    m = rho pi Dw^3/6 and omega_c from the kinematics at the reported angles, and the outer
    contact angle lies below the inner one (closed forms recomputed here)."""
    from analytic.torque import ball_kinematics

    for radial in ([0.0] * 4, [0.0, 150.0, 40.0, 0.0]):
        inp = _inp(pl000.asm, [-40.0, 20.0, 80.0, 20.0], speed_rpm=[0.0, 0.0, 0.0, 20000.0],
                   radial_load_N=radial, moment_Nmm=[0.0, 0.0, 800.0, 0.0])
        st = to_columns(pl000.run(inp, ball_model="static"))
        dy = to_columns(pl000.run(inp, ball_model="quasi_dynamic"))
        for k in ("torque_Nmm", "preload_N", "contact_angle_deg", "contact_angle_outer_A_deg",
                  "ball_load_outer_B_N", "max_contact_pressure_MPa", "heat_W", "tilt_mrad",
                  "radial_force_A_N"):
            a, b = st[k][:3], dy[k][:3]
            assert np.max(np.abs(a - b)) <= 1e-10 * max(np.max(np.abs(a)), 1e-300), k
    g = pl000.geom
    ai, ao = np.radians(dy["contact_angle_A_deg"][3]), np.radians(dy["contact_angle_outer_A_deg"][3])
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, ai, ao)
    m = g.ball.density_kg_m3 * 1e-12 * np.pi * g.Dw_mm ** 3 / 6.0
    omega_c = kin.cage * 20000.0 * 2.0 * np.pi / 60.0
    assert dy["centrifugal_force_N"][3] == pytest.approx(m * omega_c ** 2 * g.dm_mm / 2.0, rel=1e-12)
    assert ao < ai and st["centrifugal_force_N"][3] == 0.0


def test_fe_options_split_the_preload_change_into_its_causes_to_first_order(pl000):
    """`FEOptions(shifts=...)` holds one set of groove-centre shifts at its assembly-state value
    (exactly); `FEOptions(states=...)` evaluates given FE answers. The preload P(dr, dz, T) of
    the pair is smooth, so its change from T_ref splits into the radial-shift, axial-shift and
    temperature-only (both shifts held) parts to first order (Taylor):
    dP_full - dP_radial - dP_axial + dP_neither = O(dT^2), i.e. relative to dP_full O(dT): the
    remainder falls 10x (8..12x) from 2 K to 0.2 K. An option that kept or dropped the wrong
    shifts leaves a first-order remainder that does not fall so."""
    from studies.model.pipeline import FEOptions

    a = pl000.asm
    P0 = pl000.run(_inp(a, [a.T_ref_C])).preload_N[0]
    rel = []
    for dT in (2.0, 0.2):
        inp = _inp(a, [a.T_ref_C + dT])
        full = pl000.run(inp)
        radial = pl000.run(inp, fe_options=FEOptions(shifts="radial_only"))
        axial = pl000.run(inp, fe_options=FEOptions(shifts="axial_only"))
        neither = pl000.run(inp, fe_options=FEOptions(states=(full.fe_ref, full.fe_ref)))
        np.testing.assert_array_equal(radial.fe.dz_mm, full.fe_ref.dz_mm)
        np.testing.assert_array_equal(radial.fe.dr_mm, full.fe.dr_mm)
        np.testing.assert_array_equal(axial.fe.dr_mm, full.fe_ref.dr_mm)
        np.testing.assert_array_equal(axial.fe.dz_mm, full.fe.dz_mm)
        d = [r.preload_N[0] - P0 for r in (full, radial, axial, neither)]
        rel.append(abs((d[0] - d[1] - d[2] + d[3]) / d[0]))
    assert rel[0] < 0.01 and 8.0 < rel[0] / rel[1] < 12.0, rel


def test_lame_neighbours_are_computed_on_first_read_by_their_one_route(pl000):
    """Requirement (speed): a run computes the Lamé neighbours only when they are
    read, and then the same values as `stages.lame.lame_neighbours` on the run's FE state;
    `to_columns(only=...)` gives the full table's columns bit for bit without computing them
    unless one of theirs is asked for."""
    from studies.model.columns import lame_column_names
    from studies.model.stages.lame import lame_neighbours

    inp = _inp(pl000.asm, [-40.0, 20.0, 80.0], speed_rpm=[0.0, 6000.0, 12000.0])
    res = pl000.run(inp)
    calls = []
    lame_of = res.lame_of
    lazy = dataclasses.replace(res, lame_of=lambda: calls.append(1) or lame_of())
    full = to_columns(res)
    wanted = ("preload_N", "torque_Nmm", "interference_inner_um", "axial_stiffness_N_per_um")
    some = to_columns(lazy, flags=False, only=wanted)
    assert calls == [] and tuple(some) == wanted
    assert all(np.array_equal(some[c], full[c]) for c in wanted)
    names = lame_column_names(res.layer_names)
    both = to_columns(lazy, only=names)
    assert calls == [1] and all(np.array_equal(both[c], full[c], equal_nan=True) for c in names)
    direct = lame_neighbours(pl000.fe_stage, res.fe, inp)
    for f in dataclasses.fields(direct):
        assert np.array_equal(getattr(lazy.lame, f.name), getattr(direct, f.name))
    assert calls == [1]                                     # kept after the first read


def test_a_pickled_result_carries_its_lame_neighbours(pl000):
    """Requirement: a result sent back by a worker process (pickled) carries the Lamé neighbours
    as values, the same as the route computes (not the FE stage that computes them)."""
    import pickle

    inp = _inp(pl000.asm, [-40.0, 80.0], speed_rpm=[0.0, 12000.0])
    res = pl000.run(inp)
    back = pickle.loads(pickle.dumps(res))
    for f in dataclasses.fields(res.lame):
        assert np.array_equal(getattr(back.lame, f.name), getattr(res.lame, f.name))
    assert back.lame_of.func.__name__ == "_given"
