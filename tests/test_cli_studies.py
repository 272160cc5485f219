"""End to end: `bearingfem verify` per the spec, and the studies write their reports, plots and
field images (the numbers inside are tested where they are computed)."""
import json

import numpy as np
import pytest

from studies.app.cli import main
from studies.runs import verify
from studies.runs.verify import TOLERANCE

LAME_INPUTS = {"r_inner_mm", "r_fit_mm", "r_outer_mm", "E_inner_MPa", "nu_inner", "E_outer_MPa",
               "nu_outer", "interference_um", "assumption"}


def _check_verification(out, cases):
    lame = [c for c in cases if c["kind"] == "lame_fit"]
    assert len(lame) >= 8
    for c in lame:
        assert LAME_INPUTS <= set(c["inputs"]) and "fit_pressure_MPa" in c["fe"] \
            and "fit_pressure_MPa" in c["closed_form"]
        assert c["rel_error"] <= TOLERANCE, c["name"]
    spin = [c for c in cases if c["kind"] == "rotating_fit"]
    assert spin
    for c in spin:     # issue 12: the lame_fit echo plus what the rotating closed form needs
        assert LAME_INPUTS | {"rho_inner_kg_m3", "rho_outer_kg_m3", "omega_rad_s"} <= set(c["inputs"])
        assert c["rel_error"] <= TOLERANCE, c["name"]
    conv = [c for c in cases if c["kind"] == "mesh_convergence"]
    assert conv and all("observed_order" in q and "gci_fine" in q
                        for c in conv for q in c["quantities"].values())
    smooth = next(c for c in conv if "lame" in c["name"])
    # P2 on the smooth Lamé case: fit pressure error falls at least as h^2 (quadratic elements)
    assert min(smooth["quantities"]["fit_pressure_MPa"]["order_vs_exact"]) > 1.8
    assert (out / "verification.md").exists() and (out / "mesh_convergence.png").exists()


@pytest.mark.requirement("R-FE-LAME")
def test_verify_cases_contract_and_tolerance(tmp_path):
    """The verification cases with the assembly's mesh-convergence levels twice as coarse (the
    Lamé cases and the Lamé convergence case as shipped); the command at full levels is slow."""
    out = tmp_path / "v"
    verify.run(out, progress=lambda s: None, mesh_factor=2.0)
    _check_verification(out, json.loads((out / "verification.json").read_text())["cases"])


@pytest.mark.slow
def test_verify_command_contract_and_tolerance(tmp_path):
    out = tmp_path / "v"
    assert main(["verify", "--out", str(out)]) == 0
    _check_verification(out, json.loads((out / "verification.json").read_text())["cases"])


@pytest.mark.slow          # the coarse-mesh runs in test_studies_equal_simulate.py cover the default suite
@pytest.mark.parametrize("name,expect", [
    ("seed000", ["fits.png", "preload_vs_temperature.png", "torque_vs_preload.png",
                 "cycles.png", "published_trend_search.json",
                 "field_-60C_von_mises_MPa.png", "field_+80C_displacement_um.png",
                 "field_+20C.vtu", "temperature_sweep.csv"]),
    ("seed001", ["torque_vs_temperature.png", "ratio_map.png", "film_parameter.png"]),
    ("seed003", ["temperatures_1000rpm.png", "heat_split_1500rpm.png", "housing_temperature.png"]),
])
def test_study_writes_report_plots_and_images(tmp_path, name, expect):
    out = tmp_path / name
    assert main(["study", name, "--out", str(out)]) == 0
    report = (out / "report.md").read_text()
    assert "published measurement" in report and "| quantity |" in report
    assert "seed" not in report.lower().replace("seed00", "")   # "this rig", not "the seed"
    assert "## Discretisation error of this mesh" in report and (out / "report.html").exists()
    for f in expect:
        assert (out / f).stat().st_size > 1000, f
    assert not list(tmp_path.glob(f".{name}.*"))      # no temporary folder left behind


def test_unknown_study_exits_2(tmp_path, capsys):
    assert main(["study", "nope", "--out", str(tmp_path / "x")]) == 2
    assert "unknown" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_verify_runs_the_mesh_convergence_of_a_users_assembly(tmp_path, capsys):
    """`verify --assembly`: the user's own stack gets its observed order and GCI (coarse levels
    here; the command runs the default ones)."""
    from studies.model.config import CONFIG_DIR, load_assembly
    from studies.runs import verify

    asm = load_assembly(CONFIG_DIR / "template.toml")
    result = verify.run(tmp_path / "v", progress=lambda s: None, mesh_factor=2.0, assembly=asm)
    mine = [c for c in result.convergence if asm.name in c["name"]]
    assert len(mine) == 1
    q = mine[0]["quantities"]
    assert q and all(np.isfinite(r["gci_fine"]) for r in q.values())
    md = (tmp_path / "v" / "verification.md").read_text()
    assert asm.name in md and "**Achieved: " in md and "target error of 0.1 %" in md
    assert mine[0]["target_error"] == 1e-3 and np.isfinite(mine[0]["error_max"])
    assert main(["verify", "--out", str(tmp_path / "w"), "--assembly", str(tmp_path / "none.toml")]) == 2
    assert "file not found" in capsys.readouterr().err and not (tmp_path / "w").exists()


def test_confusion_matrix_candidates_are_the_cli_candidates():
    """The confusion-matrix study diagnoses with exactly the candidates `bearingfem diagnose`
    builds (`files.candidate_effects`: assembly bounds, configured speed and lubrication): same
    names in order, bounds and applicability on each design. Physics: the solid-film run-in is a
    candidate on the MoS2 seed 000 (the configured 60 rpm gives the revolutions, no speed column
    needed) and not on the oil-lubricated seed 001; seed 001's settling loss is at most its 7 N."""
    from studies.diagnosis.files import candidate_effects
    from studies.runs.confusion_matrix import DESIGNS, setup

    for name in DESIGNS:
        asm, cond, cands = setup(name)
        assert [(e.name, e.bounds, e.applicable(cond)) for e in cands] == \
            [(e.name, e.bounds, e.applicable(cond)) for e in candidate_effects(asm)]
        runin = next(e for e in cands if e.name == "solid_film_runin")
        assert (runin.applicable(cond) is None) == (asm.lubrication.kind == "solid_film"), name
    asm, cond, cands = setup("speed_steps")
    assert next(e for e in cands if e.name == "preload_settling").bounds["loss_N"] == (0.0, 7.0)
