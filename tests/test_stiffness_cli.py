"""`bearingfem stiffness` (docs/cli.md "Bearing stiffness"): the column contract, the same
equilibrium as `simulate` (its axial stiffness is a second route to k_zz), the ROSS table's
layout, units and speed range, and bad input as one line, exit 2, no output."""
import json

import numpy as np
import pandas as pd
import pytest

from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline, table_inputs

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"
#: the names of docs/cli.md "Bearing stiffness", typed here: the first eight as they were, then
#: the other 17 entries of the 5 x 5, row by row, k_<load>_<motion>_<unit>
SPEC = ["k_xx_N_per_mm", "k_yy_N_per_mm", "k_zz_N_per_mm", "k_xy_N_per_mm", "k_yx_N_per_mm",
        "k_tx_Nmm_per_mrad", "k_ty_Nmm_per_mrad", "k_x_ty_N_per_mrad",
        "k_x_z_N_per_mm", "k_x_tx_N_per_mrad",
        "k_y_z_N_per_mm", "k_y_tx_N_per_mrad", "k_y_ty_N_per_mrad",
        "k_z_x_N_per_mm", "k_z_y_N_per_mm", "k_z_tx_N_per_mrad", "k_z_ty_N_per_mrad",
        "k_tx_x_Nmm_per_mm", "k_tx_y_Nmm_per_mm", "k_tx_z_Nmm_per_mm", "k_tx_ty_Nmm_per_mrad",
        "k_ty_x_Nmm_per_mm", "k_ty_y_Nmm_per_mm", "k_ty_z_Nmm_per_mm", "k_ty_tx_Nmm_per_mrad"]
PRELOAD = ["preload_N", "preload_lost"]
ROSS = ["frequency", "kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy", "cyx"]


def write(tmp_path, text, name="c.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_columns_equal_simulate_and_ross_table(tmp_path, capsys):
    """Five rows at 0..12000 rpm and 20..60 C (quasi-dynamic balls as seed 000 says).
    Columns: the condition columns, then the 25 names, the preload (with --per-bearing the 25
    suffixed _A, _B).  k_zz equals a central difference of the rotor's axial position at the
    model's equilibrium (`Pipeline.run`, the axial load stepped by +-1 N about 0: no radial load,
    so x and the tilt are unloaded by symmetry and the held-DOF k_zz is the force-controlled one)
    to 1e-6 (truncation (1 N / 100 N preload)^2 times the curvature of the Hertz law, ~1e-5 of
    the step's own term: measured 2.5e-7);
    pair = A + B for k_xx, k_zz (translations: the same about any point; the CSV's 10
    significant digits).  ROSS table: SI units (rad/s from rpm, N/m
    from N/mm), one row per speed sorted, no damping, the speed range in its sidecar and on
    stdout, no warning with 5 speeds."""
    T = [60.0, 20.0, 40.0, 40.0, 20.0]
    rpm = [12000.0, 0.0, 6000.0, 9000.0, 3000.0]
    cond = write(tmp_path, "T_ambient_C,speed_rpm\n"
                 + "".join(f"{t},{s}\n" for t, s in zip(T, rpm)))
    out, ross = tmp_path / "k.csv", tmp_path / "ross.csv"
    assert main(["stiffness", str(CFG), str(cond), "-o", str(out), "--per-bearing",
                 "--ross", str(ross)]) == 0
    cap = capsys.readouterr()
    assert cap.err == "" and "0..12000 rpm" in cap.out
    df = pd.read_csv(out)
    assert list(df.columns) == ["T_ambient_C", "speed_rpm"] + SPEC + PRELOAD + [
        f"{c}_{J}" for J in "AB" for c in SPEC]
    asm = load_assembly(CFG)
    x = [Pipeline.shared(asm).run(table_inputs(asm, {
        "T_ambient_C": np.array(T), "speed_rpm": np.array(rpm),
        "axial_load_N": np.full(5, dF)})).pair.x_mm for dF in (1.0, -1.0)]
    np.testing.assert_allclose(df["k_zz_N_per_mm"], np.abs(2.0 / (x[0] - x[1])), rtol=1e-6)
    for c in ("k_xx_N_per_mm", "k_zz_N_per_mm"):
        np.testing.assert_allclose(df[c], df[c + "_A"] + df[c + "_B"], rtol=1e-9)  # 10 digits
    r = pd.read_csv(ross)
    assert list(r.columns) == ROSS
    order = np.argsort(rpm)
    np.testing.assert_allclose(r["frequency"], np.array(rpm)[order] * 2 * np.pi / 60, rtol=1e-9)
    np.testing.assert_allclose(r["kxx"], 1e3 * df["k_xx_N_per_mm"].to_numpy()[order], rtol=1e-9)
    assert (r[["cxx", "cyy", "cxy", "cyx"]] == 0).all().all()
    side = json.loads((tmp_path / "ross.csv.json").read_text())
    assert side["ross"]["interpolated_range_rpm"] == [0.0, 12000.0]


def test_fewer_than_five_speeds_warns_once(tmp_path, capsys):
    cond = write(tmp_path, "T_ambient_C,speed_rpm\n20,0\n20,5000\n")
    out, ross = tmp_path / "k.csv", tmp_path / "ross.csv"
    assert main(["stiffness", str(CFG), str(cond), "-o", str(out), "--ross", str(ross)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "warning" in err[0] and "2 speed(s)" in err[0] \
        and "0..5000 rpm" in err[0], err
    assert list(pd.read_csv(out).columns) == ["T_ambient_C", "speed_rpm"] + SPEC + PRELOAD


@pytest.mark.parametrize("content,extra,fragment", [
    ("T_ambient_C,speed_rpm\n20,0\n40,0\n", ["--ross", "R"],
     "rows 1 and 2 have the same speed_rpm 0"),
    ("T_ambient_C,bogus\n20,1\n", [], "bogus"),
    ("T_ambient_C\n20\nabc\n", [], "'abc' is not a number"),
    ("T_ambient_C\n", [], "empty table"),
])
def test_bad_input_is_one_line_exit_2_and_no_output(tmp_path, capsys, content, extra, fragment):
    cond = write(tmp_path, content)
    out = tmp_path / "k.csv"
    extra = [str(tmp_path / "r.csv") if e == "R" else e for e in extra]
    code = main(["stiffness", str(CFG), str(cond), "-o", str(out), *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and fragment in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.csv"]


def test_ross_output_may_not_be_the_table(tmp_path, capsys):
    cond = write(tmp_path, "T_ambient_C\n20\n")
    out = tmp_path / "k.csv"
    out.write_text("mine\n")
    code = main(["stiffness", str(CFG), str(cond), "-o", str(out), "--ross", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "is the input file" in err[0]
    assert out.read_text() == "mine\n"


def test_chunks_give_the_same_numbers(tmp_path, monkeypatch):
    """Rows are evaluated in chunks (bounded memory): chunks of 2 rows give the numbers of one
    chunk to round-off, 1e-12 of the row's sqrt(k_ii k_jj) (sums over the balls are ordered by
    the array shapes: the entries that are 0 by symmetry, k_xy ~ 1e-11 N/mm, differ in their
    noise)."""
    import studies.usecases.stiffness as stiffness

    cond = write(tmp_path, "T_ambient_C,speed_rpm,radial_load_N\n20,0,0\n30,1000,100\n"
                           "40,2000,0\n50,3000,200\n60,4000,50\n")
    one, two = tmp_path / "one.csv", tmp_path / "two.csv"
    assert main(["stiffness", str(CFG), str(cond), "-o", str(one)]) == 0
    monkeypatch.setattr(stiffness, "CHUNK_ROWS", 2)
    assert main(["stiffness", str(CFG), str(cond), "-o", str(two)]) == 0
    a, b = pd.read_csv(one), pd.read_csv(two)
    kx, kt = a["k_xx_N_per_mm"], a["k_ty_Nmm_per_mrad"] * 1e3
    scale = {"k_xx_N_per_mm": kx, "k_yy_N_per_mm": kx, "k_zz_N_per_mm": a["k_zz_N_per_mm"],
             "k_xy_N_per_mm": kx, "k_yx_N_per_mm": kx, "k_tx_Nmm_per_mrad": kt / 1e3,
             "k_ty_Nmm_per_mrad": kt / 1e3, "k_x_ty_N_per_mrad": np.sqrt(kx * kt) / 1e3}
    for c, sc in scale.items():
        assert np.all(np.abs(a[c] - b[c]) <= 1e-12 * sc), c


def test_the_route_equilibrium_is_the_one_differentiated():
    """The balls placed from the pipeline's `PairState` and its solver arguments (FE groove
    shifts, temperatures, preload path) carry exactly the rows' loads: F_x = radial load,
    F_z = axial load, M_y = moment, F_y = M_x = 0, to 1e-9 of Z x preload (the order of a
    bearing's ball-load sum; moments over the span).  A wrong shift or temperature would leave
    a residual of the order of the preload."""
    from studies.model.pipeline import Pipeline, table_inputs
    from studies.usecases.stiffness import stiffness_at

    asm = load_assembly(CFG)
    rows = {"T_ambient_C": np.array([-40.0, 20.0, 80.0]),
            "speed_rpm": np.array([0.0, 6000.0, 12000.0]),
            "radial_load_N": np.array([0.0, 300.0, 150.0]),
            "axial_load_N": np.array([0.0, 40.0, -60.0]),
            "moment_Nmm": np.array([0.0, 0.0, 2500.0])}
    k = stiffness_at(Pipeline.shared(asm), table_inputs(asm, rows))
    applied = np.stack([rows["radial_load_N"], np.zeros(3), rows["axial_load_N"], np.zeros(3),
                        rows["moment_Nmm"]])
    span = Pipeline.shared(asm).bearing_span_mm
    err = np.abs(k.loads_N_mm - applied)
    err[3:] /= span
    preload = asm.preload.assembled_N
    assert np.all(err <= 1e-9 * 24 * preload), err
