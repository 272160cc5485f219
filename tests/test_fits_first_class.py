"""Every fit first-class: the sleeve's and cartridge's fits get their
interference column, their fit_open check and flag, tolerance bands in `[fits]` that `tolerance`
samples with the designed-state rule, and `verify --assembly` holds the FE of the assembly's own
fits and materials against Lamé.

Independent references: the multi-layer Lamé solution (analytic/lame.multilayer_fit, itself
tested against closed forms in tests/test_lame.py) for concentric cylinders with frictionless
fits, where plane-stress Lamé is exact; the free thermal mismatch of two cylinders,
(alpha_in - alpha_out) dT x diameter, by hand from the materials' CTE; ISO 286-2 table values."""
import tomllib

import numpy as np
import pytest

from analytic import lame
from analytic.materials import get_material
from studies.model import tolerance_samples as tsm
from studies.model import tolerances as tol
from studies.model.checks import assembly_checks
from studies.model.columns import to_columns
from studies.model.config import CONFIG_DIR, ConfigError, assembly_from_dict
from studies.model.pipeline import Pipeline, table_inputs
from studies.usecases.verify import assembly_fit_cases


def _template(**fits):
    raw = tomllib.loads((CONFIG_DIR / "template.toml").read_text())
    raw["fits"] = {**raw["fits"], **fits}
    return raw


def _with_layer(raw, name, t_mm, material):
    b = raw["bearing"]
    raw[name] = {"material": material, "radial_thickness_mm": t_mm,
                 "length_mm": 2 * b["width_mm"] + raw["outer_spacer"]["length_mm"]}
    t = sum(raw[n]["radial_thickness_mm"] for n in ("sleeve", "cartridge") if n in raw)
    raw["housing"] = {**raw["housing"], "bore_diameter_mm": b["outside_diameter_mm"] + 2 * t}
    return raw


@pytest.fixture(scope="module")
def sleeve_22C():
    """Template pair (6061 housing, outer rings with 2 um clearance) with a 3 mm 17-4PH sleeve
    fitted with +1 um: the aluminium grows away from the steel sleeve at (23.6 - 10.8)e-6 /K x
    48 mm = 0.61 um/K, so the sleeve's fit opens just above 21.6 C."""
    a = assembly_from_dict(_with_layer(_template(sleeve_interference_um=1.0), "sleeve", 3.0,
                                       "17-4PH"))
    T = np.array([0.0, 20.0, 21.0, 22.0, 23.0, 40.0])
    out = to_columns(Pipeline(a).run(table_inputs(a, {"T_ambient_C": T})))
    return a, T, out


def test_sleeve_fit_opening_at_22C_is_flagged(sleeve_22C):
    """Failed before: the sleeve's fit opened unflagged (no flag_fit_open_sleeve column). The
    flag is set exactly where the FE fit is open, the FE opens where the multi-layer Lamé
    neighbour does, and the fit is open at 22 C and closed at 20 and 21 C."""
    a, T, out = sleeve_22C
    p, flag = out["fit_pressure_sleeve_MPa"], out["flag_fit_open_sleeve"]
    assert np.array_equal(flag, (p <= 0).astype(float))
    assert np.array_equal(p > 0, out["fit_pressure_sleeve_lame_MPa"] > 0)
    assert list(flag) == [0, 0, 0, 1, 1, 1]
    assert "fit_open_sleeve" in [c.name for c in assembly_checks(a)]


def test_sleeve_interference_column_is_the_free_thermal_mismatch(sleeve_22C):
    """interference_sleeve_um = +1 um + (alpha_sleeve - alpha_housing) (T - 20) x 48 mm, the
    free mismatch of the two cylinders (CTE of analytic/materials.py at 20 C, and its slope)."""
    a, T, out = sleeve_22C
    s, h = get_material("17-4PH"), get_material("6061")
    want = 1.0 + (s.thermal_strain(T, 20.0) - h.thermal_strain(T, 20.0)) * 48.0 * 1e3
    assert out["interference_sleeve_um"] == pytest.approx(want, rel=1e-12, abs=1e-12)
    cols = list(out)           # right after the outer fit's, like the inner / outer pair
    assert cols.index("interference_sleeve_um") == cols.index("interference_outer_um") + 1


def test_a_sleeve_designed_with_clearance_is_not_flagged_and_plain_stacks_have_no_layer_columns():
    a = assembly_from_dict(_with_layer(_template(sleeve_interference_um=-2.0), "sleeve", 3.0,
                                       "17-4PH"))
    assert "fit_open_sleeve" not in [c.name for c in assembly_checks(a)]
    plain = assembly_from_dict(_template())
    out = to_columns(Pipeline.shared(plain).run(table_inputs(plain, {"T_ambient_C": np.array([20.0])})))
    assert not [k for k in out if "sleeve" in k or "cartridge" in k]


def test_cartridge_fit_is_checked_and_tolerance_keys_need_their_layer():
    raw = _with_layer(_with_layer(_template(sleeve_interference_um=3.0,
                                            cartridge_interference_um=2.0), "sleeve", 2.0,
                                  "17-4PH"), "cartridge", 3.0, "TC4")
    a = assembly_from_dict(raw)
    names = [c.name for c in assembly_checks(a)]
    assert "fit_open_sleeve" in names and "fit_open_cartridge" in names
    assert a.fit_diameter_mm("sleeve") == pytest.approx(42.0 + 4.0)
    assert a.fit_diameter_mm("cartridge") == pytest.approx(42.0 + 10.0)
    raw = _template(cartridge_shaft_deviation_um=[0.0, 5.0])
    with pytest.raises(ConfigError) as e:
        assembly_from_dict(raw, "x.toml")
    assert "fits.cartridge_shaft_deviation_um: given, but the assembly has no [cartridge]" in str(e.value)
    assert "\n" not in str(e.value)
    raw = _with_layer(_template(sleeve_shaft_class="k5", sleeve_shaft_deviation_um=[0.0, 5.0]),
                      "sleeve", 3.0, "17-4PH")
    with pytest.raises(ConfigError, match="give the class or sleeve_shaft_deviation_um, not both"):
        assembly_from_dict(raw, "x.toml")


def test_sleeve_tolerance_classes_are_iso286_at_the_fit_diameter():
    """ISO 286-2 tables, 30..50 mm: k5 = +2 / +13 um, H6 = 0 / +16 um: at the sleeve's 48 mm fit
    the sleeve fit's band is 2 - 16 = -14 .. 13 - 0 = +13 um about its nominal."""
    raw = _with_layer(_template(sleeve_interference_um=1.0, sleeve_shaft_class="k5",
                                sleeve_bore_class="H6"), "sleeve", 3.0, "17-4PH")
    a = assembly_from_dict(raw)
    lim = tol.deviation_limits_um(a)
    assert lim["sleeve_shaft"] == (2.0, 13.0) and lim["sleeve_bore"] == (0.0, 16.0)
    band = {b.fit: b for b in tol.worst_case_bands(a)}["sleeve"]
    assert (band.lower_um, band.upper_um) == (1.0 - 14.0, 1.0 + 13.0)
    assert a.mean_fit_um("sleeve") == pytest.approx(1.0 + 7.5 - 8.0)


#: the mesh factor of the `banded` tests (see there)
BANDED_MESH = 4.0


@pytest.fixture(scope="module")
def banded():
    """The cartridge-in-sleeve band of the rig in this tool's names (its inner layer is the
    [sleeve]): 0 .. 7.62 um interference, given as the sleeve OD's limits over a line-to-line
    nominal; a 17-4PH sleeve in the template's 6061 housing. Its tests run on a mesh coarsened
    4x (BANDED_MESH): what they assert (the interference column, the pressure's order, no pressure
    line to line, the corners) holds on any mesh."""
    raw = _with_layer(_template(sleeve_interference_um=0.0,
                                sleeve_shaft_deviation_um=[0.0, 7.62]), "sleeve", 3.0, "17-4PH")
    return assembly_from_dict(raw)


def test_sleeve_band_is_sampled_and_its_design_state_is_closed(banded):
    """The band 0 .. 7.62 um: designed closed (mean +3.81 um). Samples through the exact model:
    each sample's interference at T_ref is its drawn value (the column), the fit pressure rises
    with it, and at the band's lower end (line to line) the fit carries no pressure."""
    a = banded
    assert tol.designed_closed(a) == {"inner": True, "outer": False, "sleeve": True}
    assert a.mean_fit_um("sleeve") == pytest.approx(3.81)
    band = {b.fit: b for b in tol.worst_case_bands(a)}["sleeve"]
    assert (band.lower_um, band.upper_um) == (0.0, 7.62)
    dev = {"sleeve_shaft": np.array([0.0, 2.0, 5.0, 7.62])}
    S = 4
    di, do = tol.interference_offsets_um(dev, S)
    r = tsm.evaluate(Pipeline.shared(a, mesh_factor=BANDED_MESH), {"T_ambient_C": np.array([a.T_ref_C])}, di, do,
                     tol.layer_offsets_um(a, dev, S))
    assert r.interference_sleeve_um[:, 0] == pytest.approx(dev["sleeve_shaft"], abs=1e-9)
    p = r.fit_pressure_sleeve_MPa[:, 0]
    assert p[0] == 0.0 and np.all(np.diff(p) > 0)


def test_tolerance_counts_a_sleeve_fit_failed_only_when_it_leaves_its_designed_state(banded):
    """`tolerance`'s events: the designed-closed sleeve fails by opening; designed with a
    clearance band (-7.62 .. 0) it fails by closing, not by being open."""
    from studies.usecases.tolerance_report import failures

    one = np.ones((2, 1))
    r = tol.SampleResults(one, one, one, 0 * one, 100 * one, 15 * one, 1000 * one, one,
                          interference_sleeve_um=one,
                          fit_pressure_sleeve_MPa=np.array([[0.0], [0.5]]))
    assert failures(banded, r)["fit_open_sleeve"][:, 0].tolist() == [True, False]
    raw = _with_layer(_template(sleeve_interference_um=0.0,
                                sleeve_shaft_deviation_um=[-7.62, 0.0]), "sleeve", 3.0, "17-4PH")
    clear = assembly_from_dict(raw)
    assert failures(clear, r)["fit_open_sleeve"][:, 0].tolist() == [False, True]


def test_worst_case_takes_the_corners_of_every_band(banded):
    """Inner (none here), outer (none) and sleeve bands: 2^3 corners; the sleeve's extremes at
    T_ref are its band's ends."""
    from studies.usecases.tolerance_report import worst_case

    wc = worst_case(Pipeline.shared(banded, mesh_factor=BANDED_MESH),
                    {"T_ambient_C": np.array([banded.T_ref_C])})
    assert wc.interference_sleeve_um.shape == (8, 1)
    assert wc.interference_sleeve_um.min() == pytest.approx(0.0, abs=1e-9)
    assert wc.interference_sleeve_um.max() == pytest.approx(7.62, abs=1e-9)
    assert "fit_pressure_sleeve_MPa" in wc.columns() and wc.interference_cartridge_um is None


def test_verify_assembly_runs_lame_on_the_users_own_material_and_sleeve_fit():
    """`verify --assembly` with a [materials.NAME] sleeve (E = 190 GPa, CTE 10.1e-6 /K on 17-4PH)
    fitted +4 um in the 6061 housing: every fit at -40, 20 and 80 C, FE against Lamé, within the
    verify tolerance; at 20 C the closed form is the three-layer solution with the user's
    modulus (outer ring / sleeve / housing), recomputed here."""
    raw = _with_layer(_template(sleeve_interference_um=4.0), "sleeve", 3.0, "MyMaraging")
    raw["materials"] = {"MyMaraging": {"base": "17-4PH", "E_MPa": 1.9e5, "cte_per_K": 1.01e-5}}
    a = assembly_from_dict(raw)
    cases = assembly_fit_cases(a)
    assert {c.inputs["fit"] for c in cases} == {"inner", "outer", "sleeve"}
    assert {c.kind for c in cases} == {"lame_multilayer"}
    assert all(c.passed for c in cases), [(c.name, c.rel_error) for c in cases]
    c = next(c for c in cases if c.inputs["fit"] == "sleeve" and c.inputs["T_C"] == 20.0)
    assert c.inputs["E_MPa"][1] == 1.9e5
    b = a.bearing
    r = (b.outer_ring_inner_diameter_mm / 2, 21.0, 24.0, a.housing.outer_diameter_mm / 2)
    m = [get_material(b.ring_material), None, get_material("6061")]
    ref = lame.multilayer_fit(r, [m[0].E_MPa, 1.9e5, m[2].E_MPa], [m[0].nu, get_material("17-4PH").nu,
                                                                 m[2].nu], [-2.0, 4.0])
    assert c.closed_form["fit_pressure_MPa"] == pytest.approx(ref.pressures_MPa[1], rel=1e-12)
    assert c.fe["fit_pressure_MPa"] == pytest.approx(ref.pressures_MPa[1], rel=1e-3)
    assert ref.pressures_MPa[1] > 0


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_report_shows_every_fit_with_its_flag_and_the_naming_picture(tmp_path):
    """The report of the sleeve design (coarse mesh): the margin table has the sleeve's fit
    with its failures (open at 40 C, closed at 20 C), the results table its interference,
    pressure and Lamé neighbour, the fit plots its curves, and the naming picture is there."""
    from studies.usecases import assembly_report

    a = assembly_from_dict(_with_layer(_template(sleeve_interference_um=1.0), "sleeve", 3.0,
                                       "17-4PH"))
    cond = {"T_ambient_C": np.array([20.0, 40.0])}
    prov = {"version": "test", "inputs": {}}
    warnings = assembly_report.run(a, cond, tmp_path, prov, progress=lambda s: None,
                                   mesh_factor=3.0)
    md = (tmp_path / "report.md").read_text()
    row = next(line for line in md.splitlines() if line.startswith("| sleeve fit"))
    assert "FAIL (1 of 2)" in row and "a fit assembled with interference" in row
    head = next(line for line in md.splitlines() if line.startswith("| ambient temperature"))
    for col in ("interference_sleeve_um", "fit_pressure_sleeve_MPa", "fit_pressure_sleeve_lame_MPa"):
        assert col in head, col
    assert "## Fits and their names" in md and (tmp_path / "fit_naming.png").stat().st_size > 1000
    assert any("fit_open_sleeve" in w for w in warnings.warnings)


@pytest.mark.slow
def test_thin_section_hub_rig_runs_and_its_report_shows_every_fit(tmp_path):
    """The second rig (studies/configs/rig_thin_section_hub.toml) runs through `report`
    (coarse mesh): its three fits (inner, outer, the hub in the gear) each have a margin row and
    their columns in the results table; the aluminium shaft and hub shrink away from the steel
    rings and gear when cold, so the inner and hub fits open at -45 C (flagged), by at least the
    free mismatch of the nominal mean fits, (23.6 - 11.5)e-6 /K x 65 K x 101.6 mm = 80 um > the
    inner fit's 25.4 um."""
    from studies.model.config import load_assembly
    from studies.usecases import assembly_report

    a = load_assembly(CONFIG_DIR / "rig_thin_section_hub.toml")
    assert tol.fits_of(a) == ("inner", "outer", "sleeve")
    assert all(tol.designed_closed(a).values())
    cond = {"T_ambient_C": np.array([-45.0, 20.0, 70.0])}
    warnings = assembly_report.run(a, cond, tmp_path, {"version": "test", "inputs": {}},
                                   progress=lambda s: None, mesh_factor=3.0)
    md = (tmp_path / "report.md").read_text()
    for fit in ("inner", "outer", "sleeve"):
        row = next(line for line in md.splitlines() if line.startswith(f"| {fit} fit"))
        assert "a fit assembled with interference" in row, row
        assert f"fit_pressure_{fit}_MPa" in md
    assert any("fit_open_inner" in w for w in warnings.warnings)
    assert any("fit_open_sleeve" in w for w in warnings.warnings)


def test_diagnosis_bounds_of_an_assembly_with_a_sleeve_band_stay_the_inner_and_outer_ones(banded):
    """The interference_error effect has inner_um / outer_um only: a sleeve band does not add a
    parameter it does not have (this raised KeyError before)."""
    from studies.model.effects import assembly_bounds

    raw = _with_layer(_template(sleeve_interference_um=0.0, sleeve_shaft_deviation_um=[0.0, 7.62],
                                inner_shaft_deviation_um=[2.0, 13.0]), "sleeve", 3.0, "17-4PH")
    b = assembly_bounds(assembly_from_dict(raw))["interference_error"]
    assert set(b) == {"inner_um", "outer_um"}
    assert b["inner_um"] == pytest.approx((-5.5, 5.5))
