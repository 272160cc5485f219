"""The Python API: three lines reproduce `bearingfem simulate` on the same rows; bad input raises
the same one-line errors; the version is the installed one."""
import csv
from importlib import metadata

import numpy as np
import pandas as pd
import pytest

import bearingfem
from studies.app.cli import main
from studies.model.config import CONFIG_DIR

CFG = CONFIG_DIR / "seed000_71807C_TC4.toml"


def test_three_lines_reproduce_simulate(tmp_path):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,preload_assembled_N\n-40,100\n20,150\n80,200\n")
    assert main(["simulate", str(CFG), str(cond), "-o", str(tmp_path / "o.csv")]) == 0
    with open(tmp_path / "o.csv") as f:
        reader = csv.DictReader(r for r in f if not r.startswith("#"))
        rows = list(reader)

    asm = bearingfem.load_assembly(CFG)
    out = bearingfem.simulate(asm, {"T_ambient_C": [-40, 20, 80], "preload_assembled_N": [100, 150, 200]})
    # the file's table: its condition columns first, then the outputs, in the file's order
    assert isinstance(out, pd.DataFrame) and len(out) == 3
    assert list(out.columns) == reader.fieldnames

    for k in ("preload_N", "torque_Nmm", "contact_angle_deg", "fit_pressure_inner_MPa",
              "max_contact_pressure_MPa", "interference_outer_um"):
        # the CSV keeps 10 significant digits: at most 5e-10 relative
        np.testing.assert_allclose(out[k], [float(r[k]) for r in rows], rtol=1e-9, err_msg=k)
    # a path works as well as an Assembly; an effect at its off value changes nothing (same
    # arithmetic; only the batch size differs, so agreement is to round-off of the preload)
    via_path = bearingfem.simulate(CFG, {"T_ambient_C": [-40]})
    off = bearingfem.simulate(asm, {"T_ambient_C": [-40]}, {"radial_gradient": {"dT_K": 0.0}})
    np.testing.assert_allclose([via_path["preload_N"][0], off["preload_N"][0]], out["preload_N"][0],
                               rtol=1e-12)


@pytest.mark.parametrize("conditions,message", [
    ({"T_ambient_C": [20, float("nan")]}, "row 2, column 'T_ambient_C': value is nan"),
    ({"T_ambient_C": [20], "bogus": [1]}, "column 'bogus': unknown column"),
    ({"T_ambient_C": [20, 30], "speed_rpm": [1]}, "different lengths"),
    ({"T_ambient_C": [20, 400]}, "row 2, column 'T_ambient_C': 400 outside"),
])
def test_bad_conditions_raise_one_line(conditions, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        bearingfem.simulate(CFG, conditions)


def test_version_is_the_installed_one(capsys):
    assert bearingfem.__version__ == metadata.version("bearingfem")
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"bearingfem {bearingfem.__version__}"
