"""ROSS round trip: the table `bearingfem stiffness --ross` writes, loaded into real
`ross.BearingElement`s (its constructor from the CSV columns and its own Excel reader
`BearingElement.from_table`), and a small rotor's modes at the table's speeds (a Campbell
diagram at those speeds) against closed-form bounds.  `make setup` installs ROSS (the extra
'ross') and `make test` sets BEARINGFEM_REQUIRE_ROSS, under which a missing ROSS fails its tests;
elsewhere skipped with the reason when ROSS is not installed (`pip install -e '.[ross]'`)."""
import contextlib
import io
import os
import warnings

import numpy as np
import pandas as pd
import pytest
import scipy.linalg

from studies.app.cli import main
from studies.model.config import CONFIG_DIR


def _import_ross():
    """ROSS prints CoolProp/REFPROP notices on import: keep them out of the test output."""
    try:
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross
    except Exception as exc:           # absent, or an incompatible plotly (ROSS 2.3 needs < 7)
        first = str(exc).splitlines()[0] if str(exc) else ""
        why = (f"ross (ross-rotordynamics, the optional extra 'ross') not importable: "
               f"{type(exc).__name__}: {first}")
        if os.environ.get("BEARINGFEM_REQUIRE_ROSS"):      # `make test`: installed by its set-up
            pytest.fail(why, pytrace=False)
        pytest.skip(why)
    return ross


@pytest.fixture(scope="module")
def rs():
    """ROSS, imported by the first test that needs it, not at collection: its import (CoolProp,
    plotly, numba) costs ~13 s of CPU, which every xdist worker would pay while collecting."""
    return _import_ross()


CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"
#: steel shaft of the test rotor (SI, as ROSS takes it)
RHO, E, G_S = 7810.0, 211e9, 81.2e9
L_M, D_M, N_EL = 0.1, 0.06, 4


@pytest.fixture(scope="module")
def table(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ross")
    cond = tmp / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n20,0\n20,3000\n40,6000\n40,9000\n60,12000\n")
    ross_csv = tmp / "ross.csv"
    assert main(["stiffness", str(CFG), str(cond), "-o", str(tmp / "k.csv"),
                 "--ross", str(ross_csv)]) == 0
    return ross_csv


def test_table_loads_into_ross_bearing_elements(rs, table, tmp_path):
    """The CSV's columns are BearingElement's arguments; the same table through ROSS's own
    reader (an .xlsx copy: `from_table` reads Excel) gives the same coefficients; ROSS's
    interpolation returns the table's stiffness at the table's speeds (1e-6: its smoothing
    spline, residual <= 1 N/m per point on ~1e8 N/m)."""
    df = pd.read_csv(table)
    b = rs.BearingElement(n=0, **{c: df[c].to_numpy() for c in df})
    xlsx = tmp_path / "ross.xlsx"
    df.to_excel(xlsx, index=False)
    bx = rs.BearingElement.from_table(0, str(xlsx))
    for elem in (b, bx):
        np.testing.assert_allclose(elem.kxx_interpolated(df["frequency"]), df["kxx"], rtol=1e-6)
        np.testing.assert_allclose(elem.kyy_interpolated(df["frequency"]), df["kyy"], rtol=1e-6)


def first_mode_rad_s(rotor, speed_rad_s):
    """The rotor's lowest natural frequency (rad/s) at a speed: the eigenvalues of ROSS's own
    state-space matrix `Rotor.A(speed)` (scipy.linalg.eigvals; no damping: +-i w), the axial and
    torsional rigid-body modes (ROSS's bearing element holds x and y only: |w| ~ 1e-3 rad/s here)
    left out below 1 rad/s.  The frequencies of `Rotor.run_modal` (measured: 9422.032 rad/s both
    on this shaft at 1e8 N/m), without its mode shapes, whose numba kernels take ~20 s of CPU to
    compile in each process."""
    ev = scipy.linalg.eigvals(rotor.A(speed=speed_rad_s))
    w = np.abs(ev.imag[ev.imag > 0.0])
    return float(np.min(w[w > 1.0]))


def test_small_rotor_first_mode_between_dunkerley_and_its_limits(rs, table):
    """A steel shaft (0.1 m, diameter 60 mm, 4 Timoshenko elements) on one bearing pair at each
    end whose stiffness is the table's.  At each table speed its first mode (the bounce mode:
    the conical ones sit 1.5x higher, gyroscopic splitting a few %) must lie between Dunkerley's
    lower bound 1/w^2 = 1/w_b^2 + 1/w_s^2 and min(w_b, w_s) (Dunkerley 1894; e.g. Rao,
    Mechanical Vibrations, ch. 7), with w_b^2 = 2 k / M the rigid shaft on the two bearings
    (k from the table, M = rho pi D^2 L / 4 computed here) and w_s the shaft on rigid supports
    (ROSS, bearings at 1e15 N/m).  A unit or column error in the table would move w_1 out of this
    band (2 % wide here)."""
    df = pd.read_csv(table)
    steel = rs.Material(name="steel_stiffness_test", rho=RHO, E=E, G_s=G_S)
    shaft = [rs.ShaftElement(L=L_M / N_EL, idl=0.0, odl=D_M, material=steel)
             for _ in range(N_EL)]
    cols = {c: df[c].to_numpy() for c in df}
    rotor = rs.Rotor(shaft, [], [rs.BearingElement(n=0, **cols),
                                 rs.BearingElement(n=N_EL, **cols)])
    pinned = rs.Rotor(shaft, [], [rs.BearingElement(n=0, kxx=1e15, cxx=0.0),
                                  rs.BearingElement(n=N_EL, kxx=1e15, cxx=0.0)])
    M = RHO * np.pi * D_M ** 2 / 4 * L_M
    for w_speed, k in zip(df["frequency"], df["kxx"]):
        w1, ws = first_mode_rad_s(rotor, w_speed), first_mode_rad_s(pinned, w_speed)
        wb = np.sqrt(2.0 * k / M)
        w_dunkerley = 1.0 / np.sqrt(1.0 / wb ** 2 + 1.0 / ws ** 2)
        assert w_dunkerley <= w1 <= min(wb, ws), (w_speed, w_dunkerley, w1, wb, ws)
