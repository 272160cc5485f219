"""Sleeve and cartridge parts between the outer rings and the housing (studies/model/stack.py,
config `[sleeve]` / `[cartridge]`), and the bonded-fit ties they rely on (fem/solver.py).

Independent references: a bonded sleeve of the housing's material with no interference is the
housing itself (same answers as no sleeve, up to the two meshes' discretisation errors, each
sized for 0.1 %); a stack of one material heated uniformly is stress free (u = theta x); the
three-cylinder Lamé solution (analytic/lame.multilayer_fit, tested against closed forms in
tests/test_lame.py) for concentric cylinders of equal length with frictionless fits and free ends,
where plane-stress Lamé is exact (sigma_r + sigma_theta constant per layer, axial sliding free)."""
import tomllib

import numpy as np
import pytest

from analytic import lame
from analytic.materials import get_material
from fem.model import build_model
from fem.post import element_stresses, fit_mean_pressures, theta_per_element
from fem.solver import FitSolver
from meshes.section import Fit, Rect, Section, Split
from studies.model.config import CONFIG_DIR, ConfigError, assembly_from_dict
from studies.model.pipeline import Pipeline, table_inputs
from studies.model.columns import to_columns


def _template(**changes):
    raw = tomllib.loads((CONFIG_DIR / "template.toml").read_text())
    for table, values in changes.items():
        raw[table] = {**raw.get(table, {}), **values}
    return raw


def _with_sleeve(raw, t_mm, material, **fits):
    b = raw["bearing"]
    raw["sleeve"] = {"material": material, "radial_thickness_mm": t_mm,
                     "length_mm": 2 * b["width_mm"] + raw["outer_spacer"]["length_mm"]}
    raw["housing"] = {**raw["housing"], "bore_diameter_mm": b["outside_diameter_mm"] + 2 * t_mm}
    raw["fits"] = {**raw["fits"], **fits}
    return raw


def test_bonded_sleeve_of_housing_material_is_the_housing():
    """Template pair (6061 housing) with bonded fits, at -40, 20 and 80 C: a 3 mm 6061 sleeve
    with zero interference gives the outer fit pressures and the preload of the same housing
    without a sleeve, within 2e-3 of the pressure scale (each mesh is sized for 1e-3)."""
    T = {"T_ambient_C": np.array([-40.0, 20.0, 80.0])}
    outs = []
    for sleeve in (False, True):
        raw = _template(fits={"contact": "bonded"})
        if sleeve:
            raw = _with_sleeve(raw, 3.0, raw["housing"]["material"], sleeve_interference_um=0.0)
        a = assembly_from_dict(raw)
        outs.append(to_columns(Pipeline(a).run(table_inputs(a, T))))
    plain, sleeved = outs
    scale = np.abs(plain["fit_pressure_outer_MPa"]).max()
    for k in ("fit_pressure_outer_A_MPa", "fit_pressure_outer_B_MPa", "fit_pressure_inner_MPa"):
        assert np.abs(sleeved[k] - plain[k]).max() <= 2e-3 * scale, k
    assert sleeved["preload_N"] == pytest.approx(plain["preload_N"], rel=2e-3, abs=1e-6)
    assert "fit_pressure_sleeve_MPa" in sleeved and "fit_pressure_sleeve_MPa" not in plain


def test_one_material_stack_with_bonded_fits_and_a_sleeve_is_stress_free_when_heated():
    """Every part 52100, bonded fits, no interference, 80 C everywhere, at rest: u = theta x satisfies
    every fit, clamped face and corner, so the FE is stress free (a tie loop at a ring corner
    held axially would not be)."""
    raw = _template(fits={"contact": "bonded", "inner_interference_um": 0.0,
                          "outer_interference_um": 0.0})
    for table in ("shaft", "housing", "nut", "cover", "inner_spacer", "outer_spacer"):
        raw[table]["material"] = "52100"
    raw["bearing"]["ring_material"] = "52100"
    raw = _with_sleeve(raw, 2.0, "52100")
    a = assembly_from_dict(raw)
    pl = Pipeline(a, superpose=False)
    f = pl.field(table_inputs(a, {"T_ambient_C": np.array([80.0]), "speed_rpm": np.array([0.0])}))
    vm = element_stresses(pl.model, f.u_mm, theta_per_element(pl.model, f.theta))["von_mises_MPa"]
    E = get_material("52100").E_MPa
    assert vm.max() < 1e-9 * E * abs(f.theta[0])


def test_three_cylinder_fe_equals_multilayer_lame():
    """Ring (9Cr18) in a sleeve (17-4PH) in a housing (6061), 10 mm long, frictionless fits of
    +6 and +4 um, free ends: FE fit pressures = three-layer plane-stress Lamé within 1e-3."""
    r, L = (22.0, 23.5, 26.0, 34.0), 10.0
    mats = ("9Cr18", "17-4PH", "6061")
    names = ("outer_ring_A", "sleeve", "housing")
    rects = tuple(Rect(n, r[k], r[k + 1], 0.0, L, m) for k, (n, m) in enumerate(zip(names, mats)))
    splits = (Split("bore", "r", r[1], 0.0, L, (names[0],), names[1:]),
              Split("outside", "r", r[2], 0.0, L, (names[1],), (names[2],)))
    fits = (Fit("fit_outer_A", names[0], names[1], r[1], 0.0, L, "outer"),
            Fit("fit_sleeve", names[1], names[2], r[2], 0.0, L, "sleeve"))
    h = (r[3] - r[0]) / 16
    sec = Section(rects, splits, fits, (), tuple((f.r_mm, 0.0, f.r_mm, L) for f in fits),
                  {"outer_ring_A": (r[0], L / 2)}, h, h / 2)
    model = build_model(sec)
    solver = FitSolver(model)
    d_um = np.array([6.0, 4.0])
    sol = solver.solve(np.zeros(model.ndofs), d_um / 2000)
    p_fe = fit_mean_pressures(model, solver.fit_of_pair, sol.force_N)[0]
    m = [get_material(x) for x in mats]
    ref = lame.multilayer_fit(r, [x.E_MPa for x in m], [x.nu for x in m], d_um)
    assert p_fe == pytest.approx(ref.pressures_MPa, rel=1e-3)


@pytest.mark.parametrize("change,message", [
    (lambda raw: raw["housing"].update(bore_diameter_mm=44.0),
     "housing.bore_diameter_mm: 44 mm must be the bearing OD + 2 x (sleeve radial thickness)"),
    (lambda raw: raw["sleeve"].update(length_mm=30.0), "sleeve.length_mm: 30 mm must equal"),
    (lambda raw: raw["sleeve"].update(material="unobtainium"), "sleeve.material: unknown material"),
    (lambda raw: raw["fits"].update(cartridge_interference_um=3.0),
     "fits.cartridge_interference_um: given, but the assembly has no [cartridge]"),
    (lambda raw: raw["sleeve"].update(radial_thickness_mm=-1.0),
     "sleeve.radial_thickness_mm: must be positive"),
])
def test_bad_sleeve_is_one_line(change, message):
    raw = _with_sleeve(_template(), 3.0, "17-4PH")
    change(raw)
    with pytest.raises(ConfigError) as e:
        assembly_from_dict(raw, "x.toml")
    assert message in str(e.value) and "\n" not in str(e.value)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_sleeve_and_cartridge_together_mesh_and_report_their_fits():
    raw = _with_sleeve(_template(), 2.0, "17-4PH")
    raw["cartridge"] = {**raw["sleeve"], "material": "TC4", "radial_thickness_mm": 3.0}
    raw["housing"]["bore_diameter_mm"] = raw["bearing"]["outside_diameter_mm"] + 10.0
    raw["fits"]["sleeve_interference_um"] = 3.0
    a = assembly_from_dict(raw)
    pl = Pipeline(a)
    assert pl.setup.fit_names[-2:] == ("fit_sleeve", "fit_cartridge")
    out = to_columns(pl.run(table_inputs(a, {"T_ambient_C": np.array([20.0])})))
    assert out["fit_pressure_sleeve_MPa"][0] > 0          # 3 um interference: closed


def test_multilayer_pressures_vectorised_equal_the_scalar_solution():
    """Rows of interferences through open, closed and mixed states: the vectorised solver gives
    `multilayer_fit`'s pressures row by row."""
    radii, E, nu = (10.0, 21.0, 24.0, 30.0), (2.0e5, 1.97e5, 7.0e4), (0.3, 0.27, 0.33)
    d = np.array([[6.0, 4.0], [6.0, -6.0], [-3.0, 5.0], [-1.0, -1.0], [8.0, -0.5]])
    p = lame.multilayer_pressures_MPa(radii, E, nu, d)
    for row, got in zip(d, p):
        assert got == pytest.approx(lame.multilayer_fit(radii, E, nu, row).pressures_MPa,
                                    rel=1e-12, abs=1e-12)


def test_sleeve_fit_pressures_have_their_multilayer_lame_neighbours():
    """The closed-form neighbours `simulate` writes with a sleeve (17-4PH, +4 um in the 6061
    housing of the template): the three-layer Lamé solution opens and closes the sleeve fit
    where the FE contact does: closed at 20 C, open at 60 C (the aluminium grows away by
    (23.6 - 10.8)e-6 /K x 40 K x 48 mm = 25 um, six times the 4 um: on a mesh coarsened 2x)."""
    a = assembly_from_dict(_with_sleeve(_template(), 3.0, "17-4PH", sleeve_interference_um=4.0))
    pl = Pipeline(a, mesh_factor=2.0)
    out = to_columns(pl.run(table_inputs(a, {"T_ambient_C": np.array([20.0, 60.0])})))
    for k in ("outer", "sleeve"):
        assert np.all(np.isfinite(out[f"fit_pressure_{k}_lame_MPa"])), k
    fe, cf = out["fit_pressure_sleeve_MPa"], out["fit_pressure_sleeve_lame_MPa"]
    assert fe[0] > 0 and cf[0] > 0 and fe[1] == 0 and cf[1] == 0, (fe, cf)
