"""End to end: `bearingfem verify` per the spec, and the studies write their reports, plots and
field images (the numbers inside are tested where they are computed; here each output's numbers
are held to a second derivation: the textbook closed forms, Roache's formulas, the CSV beside)."""
import csv
import functools
import json
import math

import numpy as np
import pytest

from studies.app.cli import main
from studies.usecases import verify
from studies.usecases.verify import TOLERANCE

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
    for c in spin:     # the lame_fit echo plus what the rotating closed form needs
        assert LAME_INPUTS | {"rho_inner_kg_m3", "rho_outer_kg_m3", "omega_rad_s"} <= set(c["inputs"])
        assert c["rel_error"] <= TOLERANCE, c["name"]
    conv = [c for c in cases if c["kind"] == "mesh_convergence"]
    assert conv and all("observed_order" in q and "gci_fine" in q
                        for c in conv for q in c["quantities"].values())
    smooth = next(c for c in conv if "lame" in c["name"])
    # P2 on the smooth Lamé case: fit pressure error falls at least as h^2 (quadratic elements)
    assert min(smooth["quantities"]["fit_pressure_MPa"]["order_vs_exact"]) > 1.8
    assert (out / "verification.md").exists() and (out / "mesh_convergence.png").exists()
    for c in lame:          # the closed form compared with is the textbook's
        assert c["closed_form"]["fit_pressure_MPa"] == pytest.approx(
            _shrink_fit_MPa(c["inputs"]), rel=1e-12, abs=1e-12), c["name"]
    for c in (c for c in cases if c["kind"] == "fit_open_speed"
              and c["inputs"]["assumption"] == "plane_stress" and c["inputs"]["r_inner_mm"] == 0
              and c["inputs"]["E_inner_MPa"] == c["inputs"]["E_outer_MPa"]):
        assert c["closed_form"]["fit_open_speed_rpm"] == pytest.approx(_open_speed_rpm(c["inputs"]),
                                                                       rel=1e-12), c["name"]
    # verification.md prints each case's numbers (6 significant digits) from the JSON
    rows = {r[0]: r for r in _md_rows((out / "verification.md").read_text(), "case")}
    for c in lame:
        fe = rows[c["name"]][2]
        assert fe.startswith("fit_pressure_MPa=")
        assert float(fe.split("=")[1]) == pytest.approx(c["fe"]["fit_pressure_MPa"], rel=5e-6, abs=1e-12)


def _shrink_fit_MPa(i: dict) -> float:
    """Contact pressure of a shrink fit (two cylinders, Shigley, Mechanical Engineering Design,
    ch. 3 "press and shrink fits"): p = delta / (b/E_o ((c^2 + b^2)/(c^2 - b^2) + nu_o) +
    b/E_i ((b^2 + a^2)/(b^2 - a^2) - nu_i)), delta the radial interference (0 when negative);
    plane strain through E/(1 - nu^2), nu/(1 - nu)."""
    a, b, c = i["r_inner_mm"], i["r_fit_mm"], i["r_outer_mm"]
    Ei, ni, Eo, no = i["E_inner_MPa"], i["nu_inner"], i["E_outer_MPa"], i["nu_outer"]
    if i["assumption"] == "plane_strain":
        Ei, ni, Eo, no = Ei / (1 - ni ** 2), ni / (1 - ni), Eo / (1 - no ** 2), no / (1 - no)
    delta = 0.5e-3 * i["interference_um"]
    comp = b / Eo * ((c * c + b * b) / (c * c - b * b) + no) + b / Ei * ((b * b + a * a) / (b * b - a * a) - ni)
    return max(delta / comp, 0.0)


def _open_speed_rpm(i: dict) -> float:
    """Speed at which a shrink fit of a ring on a solid shaft of one material opens (thin discs,
    plane stress; Timoshenko & Goodier ch. 4 §32): the ring's bore grows rho w^2 b ((3 + nu) c^2
    + (1 - nu) b^2) / (4 E), the shaft's surface (1 - nu) rho w^2 b^3 / (4 E); they differ by
    the radial interference delta when w^2 = 4 E delta / (rho b (3 + nu) c^2)."""
    b, c, E, nu = i["r_fit_mm"], i["r_outer_mm"], i["E_outer_MPa"], i["nu_outer"]
    rho = 1e-12 * i["rho_outer_kg_m3"]             # N s^2 / mm^4
    w = math.sqrt(4 * E * 0.5e-3 * i["interference_um"] / (rho * b * (3 + nu) * c ** 2))
    return w * 30 / math.pi


def _md_rows(md: str, first: str) -> list[list[str]]:
    """The cells of the rows of the markdown table whose header starts with `| first |`."""
    lines = md.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(f"| {first} |"))
    rows = []
    for line in lines[i + 2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip("|").split("|")])
    return rows


@pytest.fixture
def coarse_mms(monkeypatch):
    """`verify.run` with its manufactured-solution table on the coarse levels of test_verify.py
    (h = 1.25 .. 0.31 mm): nothing here reads that table (its keys: test_verify.py, its orders:
    test_mms.py, at the command's levels in the slow test_mms.py::test_orders_on_finer_levels),
    and at the command's levels it was 14 of the 16 CPU s of each verify run below. The same for
    the transient manufactured solution (two mesh levels, three steps; its orders:
    test_transient_mms.py, its keys: test_verify.py)."""
    monkeypatch.setattr(verify, "mms_cases", functools.partial(verify.mms_cases, (4, 8, 16)))
    monkeypatch.setattr(verify, "transient_mms_cases",
                        functools.partial(verify.transient_mms_cases, (1.0, 0.5), (0.4, 0.2, 0.1)))


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
@pytest.mark.requirement("R-FE-LAME")
def test_verify_cases_contract_and_tolerance(tmp_path, coarse_mms):
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
    _check_study_numbers(name, out, report)


def _md_dicts(md: str, first: str) -> list[dict[str, str]]:
    lines = md.splitlines()
    head = next(line for line in lines if line.startswith(f"| {first} |"))
    names = [c.strip() for c in head.strip("|").split("|")]
    return [dict(zip(names, r)) for r in _md_rows(md, first)]


def _check_study_numbers(name: str, out, report: str) -> None:
    """A study's report: its results table is its results.csv (printed to 4 significant digits:
    5e-4 relative), the fits there follow free thermal expansion (every part at the ambient; the
    shipped materials have constant CTEs), and the rig's own numbers their closed forms."""
    from studies.model.config import load_shipped

    asm = load_shipped(name)
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    table = _md_dicts(report, "ambient temperature (C)")      # some of the CSV's rows
    at = [int(np.flatnonzero(cols["T_ambient_C"] == float(r["ambient temperature (C)"]))[0])
          for r in table]
    for col in table[0]:
        if col in cols:
            np.testing.assert_allclose([float(r[col]) for r in table], cols[col][at], rtol=5e-4,
                                       atol=1e-9, err_msg=col)
    shaft, ring, housing = (asm.material(p) for p in ("shaft", "inner_ring", "housing"))
    assert shaft.dalpha_per_K2 == ring.dalpha_per_K2 == housing.dalpha_per_K2 == 0.0
    dT = cols["T_ambient_C"] - asm.T_ref_C
    rate_i = 1e3 * asm.shaft.seat_diameter_mm * (shaft.alpha_per_K - ring.alpha_per_K)   # um/C
    rate_o = 1e3 * asm.housing.bore_diameter_mm * (ring.alpha_per_K - housing.alpha_per_K)
    np.testing.assert_allclose(cols["interference_inner_um"],
                               asm.fits.inner_interference_um + rate_i * dT, rtol=1e-9)
    np.testing.assert_allclose(cols["interference_outer_um"],
                               asm.fits.outer_interference_um + rate_o * dT, rtol=1e-9)
    if name == "seed000":     # the published rates and the clearance's closing temperature
        rig = {r["quantity"]: r for r in _md_dicts(report, "quantity")}
        assert float(rig["inner fit rate (um/C)"]["this model"]) == pytest.approx(rate_i, abs=5e-5)
        assert float(rig["outer fit rate (um/C)"]["this model"]) == pytest.approx(rate_o, abs=5e-5)
        closes = asm.T_ref_C - asm.fits.outer_interference_um / rate_o
        assert float(rig["outer clearance closes (C)"]["this model"].split()[0]) == \
            pytest.approx(closes, abs=0.05)
    if name == "seed003":     # the heat of each speed's steady state is its three sources
        for r in _md_dicts(report, "speed (rpm)"):
            parts = sum(float(r[k]) for k in ("sliding (W)", "spin (W)", "viscous (W)"))
            assert float(r["total (W)"]) == pytest.approx(parts, rel=2e-3), r   # 4 digits each


def test_unknown_study_exits_2(tmp_path, capsys):
    assert main(["study", "nope", "--out", str(tmp_path / "x")]) == 2
    assert "unknown" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_verify_runs_the_mesh_convergence_of_a_users_assembly(tmp_path, capsys, coarse_mms):
    """`verify --assembly`: the user's own stack gets its observed order and GCI (coarse levels
    here; the command runs the default ones)."""
    from studies.model.config import CONFIG_DIR, load_assembly
    from studies.usecases import verify

    asm = load_assembly(CONFIG_DIR / "template.toml")
    result = verify.run(tmp_path / "v", progress=lambda s: None, mesh_factor=2.0, assembly=asm)
    mine = [c for c in result.convergence if asm.name in c.name]
    assert len(mine) == 1
    q = {name: r.richardson for name, r in mine[0].quantities.items()}
    assess = mine[0].assessment
    assert q and all(np.isfinite(r.gci_fine) for r in q.values())
    md = (tmp_path / "v" / "verification.md").read_text()
    assert asm.name in md and "**Achieved: " in md and "target error of 0.1 %" in md
    assert assess.target_error == 1e-3 and np.isfinite(assess.error_max)
    # Roache (1998) from the three finest levels, r = 2: observed order p = ln(e32 / e21) / ln 2
    # kept within 1..4, Richardson value f3 + e21 / (2^p - 1), GCI = 1.25 |e21| / |f3| / (2^p - 1);
    # the error of the mesh used: its fit pressure against the Richardson value
    levels, used = [lv.values for lv in mine[0].levels], mine[0].used.values
    checked = 0
    for name, r in q.items():
        f1, f2, f3 = (lv[name] for lv in levels[-3:])
        if not r.monotone or (f2 - f1) * (f3 - f2) <= 0:
            continue
        p = math.log((f2 - f1) / (f3 - f2)) / math.log(2.0)
        pu = min(max(p, 1.0), 4.0)
        rich = f3 + (f3 - f2) / (2 ** pu - 1)
        assert r.observed_order == pytest.approx(p, rel=1e-9), name
        assert r.extrapolated == pytest.approx(rich, rel=1e-12), name
        assert r.gci_fine == pytest.approx(1.25 * abs(f3 - f2) / abs(f3) / (2 ** pu - 1), rel=1e-9)
        if name.startswith("fit_pressure"):
            err = abs(used[name] - rich) / abs(rich)
            assert assess.errors[name] == pytest.approx(err, rel=1e-9), name
            checked += 1
    assert checked >= 2
    worst = max(assess.errors.values())
    assert assess.error_max == worst and f"**Achieved: {100 * worst:.2g} % " in md
    assert main(["verify", "--out", str(tmp_path / "w"), "--assembly", str(tmp_path / "none.toml")]) == 2
    assert "file not found" in capsys.readouterr().err and not (tmp_path / "w").exists()


def test_confusion_matrix_candidates_are_the_cli_candidates():
    """The confusion-matrix study diagnoses with exactly the candidates `bearingfem diagnose`
    builds (`files.candidate_effects`: assembly bounds, configured speed and lubrication): same
    names in order, bounds and applicability on each design. Physics: the solid-film run-in is a
    candidate on the MoS2 seed 000 (the configured 60 rpm gives the revolutions, no speed column
    needed) and not on the oil-lubricated seed 001; seed 001's settling loss is at most its 7 N."""
    from studies.diagnosis.files import candidate_effects
    from studies.validation.confusion_matrix import DESIGNS, setup

    for name in DESIGNS:
        asm, cond, cands = setup(name)
        assert [(e.name, e.bounds, e.applicable(cond)) for e in cands] == \
            [(e.name, e.bounds, e.applicable(cond)) for e in candidate_effects(asm)]
        runin = next(e for e in cands if e.name == "solid_film_runin")
        assert (runin.applicable(cond) is None) == (asm.lubrication.kind == "solid_film"), name
    asm, cond, cands = setup("speed_steps")
    assert next(e for e in cands if e.name == "preload_settling").bounds["loss_N"] == (0.0, 7.0)
