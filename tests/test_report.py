"""`bearingfem report` for a user's assembly (the template): every part of the report is there,
the HTML is self-contained, the result table is the simulate route's, its numbers are the CSV's
and agree with closed forms (free thermal expansion, the Lamé fit, a ball's centrifugal force),
bad input is one line."""
import csv
import math

import numpy as np
import pytest

from studies.app.cli import main
from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline, simulate_table
from studies.usecases import assembly_report
from studies.model.columns import to_columns

TEMPLATE = CONFIG_DIR / "template.toml"


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
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
    _check_numbers(asm, md, {k: np.array([float(r[k]) for r in rows]) for k in rows[0]})
    # the safety table names each governing point by its condition
    for r in _md_table(md, "check"):
        k = int(r["governing point"].split(":")[0].removeprefix("row "))
        assert r["governing point"] == f"row {k}: T_ambient_C = {cond['T_ambient_C'][k - 1]:g}"


def _md_table(md: str, first: str) -> list[dict[str, str]]:
    """The rows of the markdown table whose header starts with `| first |`, by column."""
    lines = md.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(f"| {first} |"))
    head = [c.strip() for c in lines[i].strip("|").split("|")]
    rows = []
    for line in lines[i + 2:]:
        if not line.startswith("|"):
            break
        rows.append(dict(zip(head, (c.strip() for c in line.strip("|").split("|")))))
    return rows


def _check_numbers(asm, md, csv_cols):
    """The report's numbers: its results table is the CSV's (printed to 4 significant digits:
    at most 5e-4 relative), and the CSV agrees with closed forms computed here from the
    config and the material data alone."""
    from analytic.materials import get_material

    T = csv_cols["T_ambient_C"]
    results = _md_table(md, "ambient temperature (C)")
    assert [float(r["ambient temperature (C)"]) for r in results] == list(T)
    for col in results[0]:
        if col in csv_cols:
            printed = np.array([float(r[col]) for r in results])
            np.testing.assert_allclose(printed, csv_cols[col], rtol=5e-4, atol=1e-9, err_msg=col)
    shaft, ring, housing = (get_material(n) for n in (asm.shaft.material,
                                                      asm.bearing.ring_material,
                                                      asm.housing.material))
    assert shaft.dalpha_per_K2 == ring.dalpha_per_K2 == housing.dalpha_per_K2 == 0.0
    dT = T - asm.T_ref_C
    # free thermal expansion: diametral interference + d (alpha_shaft - alpha_ring) dT, and for
    # the outer fit d (alpha_ring - alpha_housing) dT, in um (every part at the ambient)
    d_i, d_o = asm.shaft.seat_diameter_mm, asm.housing.bore_diameter_mm
    delta_i = asm.fits.inner_interference_um + 1e3 * d_i * (shaft.alpha_per_K - ring.alpha_per_K) * dT
    delta_o = asm.fits.outer_interference_um + 1e3 * d_o * (ring.alpha_per_K - housing.alpha_per_K) * dT
    np.testing.assert_allclose(csv_cols["interference_inner_um"], delta_i, rtol=1e-9)
    np.testing.assert_allclose(csv_cols["interference_outer_um"], delta_o, rtol=1e-9)
    # the Lamé column: two cylinders in plane stress (Shigley, Mechanical Engineering Design,
    # ch. 3 "press and shrink fits"), the radial interference less what the rotation at the
    # report's speed takes (spinning discs, Timoshenko & Goodier ch. 4 §32: the free ring's
    # bore grows rho w^2 b ((3 + nu) c^2 + (1 - nu) b^2) / (4 E), the solid shaft's surface
    # (1 - nu) rho w^2 b^3 / (4 E)); MPa from mm and MPa
    b, c = d_i / 2, asm.bearing.inner_ring_outer_diameter_mm / 2
    w = asm.lubrication.speed_rpm * math.pi / 30
    rw2 = 1e-12 * w ** 2            # kg/m^3 rad^2/s^2 -> N/mm^4 per kg/m^3
    grow = (ring.density_kg_m3 * rw2 * b * ((3 + ring.nu) * c ** 2 + (1 - ring.nu) * b ** 2)
            / (4 * ring.E_MPa) - (1 - shaft.nu) * shaft.density_kg_m3 * rw2 * b ** 3 / (4 * shaft.E_MPa))
    compliance = (b / ring.E_MPa * ((c * c + b * b) / (c * c - b * b) + ring.nu)
                  + b / shaft.E_MPa * (1 - shaft.nu))
    p_lame = np.maximum((0.5e-3 * delta_i - grow) / compliance, 0.0)
    np.testing.assert_allclose(csv_cols["fit_pressure_inner_lame_MPa"], p_lame, rtol=1e-6)
    # the speed table: at rest at T_ref the position preload is the assembled one (the config's)
    speed = _md_table(md, "state")
    rest = next(r for r in speed if r["state"] == "at rest")
    assert float(rest["preload (N)"]) == pytest.approx(asm.preload.assembled_N, rel=5e-4)
    # a ball's centrifugal force m w_c^2 dm / 2, m = rho pi Dw^3 / 6, cage speed
    # w_c = w (1 - Dw cos a / dm) / 2 (inner ring turning; Harris & Kotzalas Vol. 1 ch. 8), at
    # the contact angle the table gives (printed to 3 digits: 2e-3 relative)
    dyn = next(r for r in speed if "quasi-dynamic" in r["state"])
    alpha = math.radians(float(dyn["A inner angle (deg)"]))
    Dw, dm = asm.bearing.ball_diameter_mm, asm.bearing.pitch_diameter_mm
    ball = get_material(asm.bearing.ball_material)
    m_kg = ball.density_kg_m3 * math.pi * (1e-3 * Dw) ** 3 / 6
    w_c = 0.5 * w * (1 - Dw * math.cos(alpha) / dm)
    F_c = m_kg * w_c ** 2 * 0.5e-3 * dm
    assert float(dyn["centrifugal force per ball (N)"]) == pytest.approx(F_c, rel=2e-3)


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


# ------------------------------------------- the case that drives the design
def test_design_rows_are_the_governing_points_of_a_gradient_table():
    """With a part's own temperature column the report draws its fields and speed effects at the
    rows of the lowest and highest preload and of the highest contact pressure; a uniform sweep
    keeps the coldest / reference / hottest temperatures (None)."""
    res = {"preload_N": np.array([300.0, 50.0, 900.0, 400.0]),
           "max_contact_pressure_MPa": np.array([1000.0, 800.0, 1500.0, 1600.0])}
    grad = {"T_ambient_C": np.zeros(4), "T_inner_ring_C": np.full(4, 12.0)}
    assert assembly_report.design_rows(grad, res) == [1, 2, 3]
    assert assembly_report.design_rows({"T_ambient_C": np.zeros(4)}, res) is None


def test_field_images_and_speed_rows_carry_the_gradient(tmp_path):
    """A gradient row (inner ring and shaft 12 K above the rest): its VTU holds each part at its
    own temperature (inner rings and shaft at +12 K, housing at the ambient), and the speed
    section's row at rest is the simulate route's result for that row at speed 0 (the uniform
    temperature would give another preload: the gradient moves the preload)."""
    import meshio

    from studies.usecases.report_tools import field_images

    asm = load_assembly(TEMPLATE)
    pl = Pipeline.shared(asm, mesh_factor=3.0, progress=lambda s: None)
    row = {"T_ambient_C": np.array([40.0]), "T_inner_ring_C": np.array([52.0]),
           "T_shaft_C": np.array([52.0])}
    paths = field_images(tmp_path, pl, row, "grad", "gradient")
    assert any(p.name == "grad_von_mises_MPa.png" for p in paths)
    m = meshio.read(tmp_path / "grad.vtu")
    T = np.asarray(m.point_data["temperature_C"], float)
    part = pl.model.part_of
    tri = pl.model.mesh.t
    inner_only = np.setdiff1d(tri[:, part == "inner_ring_A"], tri[:, part != "inner_ring_A"])
    housing_only = np.setdiff1d(tri[:, part == "housing"], tri[:, part != "housing"])
    assert np.all(T[inner_only] == 52.0) and np.all(T[housing_only] == 40.0)
    lines = assembly_report.speed_lines(asm, pl, row, ["row 7"])
    table = _md_table("\n".join(lines), "operating point")
    ref = to_columns(simulate_table(asm, {**row, "speed_rpm": np.zeros(1)}, pipeline=pl))
    uni = to_columns(simulate_table(asm, {"T_ambient_C": np.array([40.0]),
                                          "speed_rpm": np.zeros(1)}, pipeline=pl))
    assert table[0]["operating point"] == "row 7"   # the label given
    assert float(table[0]["preload at rest (N)"]) == pytest.approx(ref["preload_N"][0], rel=1e-3)
    assert abs(ref["preload_N"][0] - uni["preload_N"][0]) > 1e-2 * ref["preload_N"][0]
