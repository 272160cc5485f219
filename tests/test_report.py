"""`bearingfem report` for a user's assembly (the template): every part of the report is there,
the HTML is self-contained, the result table is the simulate route's, bad input is one line."""
import csv

import numpy as np

from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline, simulate_table
from studies.runs import assembly_report
from studies.model.columns import to_columns

TEMPLATE = CONFIG_DIR / "template.toml"


def test_report_of_a_users_assembly(tmp_path):
    asm = load_assembly(TEMPLATE)
    cond = {"T_ambient_C": np.array([-40.0, 20.0, 80.0])}
    prov = {"version": "test", "inputs": {"assembly": {"path": str(TEMPLATE), "sha256": "0" * 64}}}
    assembly_report.run(asm, cond, tmp_path, prov, progress=lambda s: None, mesh_factor=3.0)
    md = (tmp_path / "report.md").read_text()
    for section in ("## Inputs", "## Results", "## Safety checks", "## Field images",
                    "## Discretisation error of this mesh"):
        assert section in md, section
    assert "17-4PH" in md and "ASM-52100" in md                      # materials with sources
    # the mesh's discretisation error: the target its sizes were chosen for and what it achieves
    assert "chosen for a target error of 0.1 %" in md and "**Achieved: " in md
    for png in ("fits.png", "fit_pressure.png", "preload.png", "torque.png",
                "field_-40C_von_mises_MPa.png", "field_+80C_displacement_um.png"):
        assert (tmp_path / png).stat().st_size > 1000, png
    assert (tmp_path / "field_+20C.vtu").exists()
    html = (tmp_path / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= 8 and 'src="fits.png"' not in html
    with open(tmp_path / "results.csv") as f:
        rows = list(csv.DictReader(f))
    ref = to_columns(simulate_table(asm, cond, pipeline=Pipeline(asm, mesh_factor=3.0)))
    np.testing.assert_allclose([float(r["preload_N"]) for r in rows], ref["preload_N"], rtol=1e-9)
    assert "flag_max_contact_pressure_MPa" in rows[0]


def test_report_default_conditions_span_the_operating_range():
    asm = load_assembly(TEMPLATE)
    T = assembly_report.default_conditions(asm)["T_ambient_C"]
    assert T[0] == asm.operating.T_min_C and T[-1] == asm.operating.T_max_C
    assert asm.T_ref_C in T and np.all(np.diff(T) > 0)


def test_report_bad_conditions_is_one_line(tmp_path, capsys):
    bad = tmp_path / "c.csv"
    bad.write_text("T_ambient_C\nabc\n")
    assert main(["report", str(TEMPLATE), str(bad), "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not a number" in err[0] and not (tmp_path / "r").exists()
