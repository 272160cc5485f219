"""A config's own oil (`[lubricants.NAME]` tables): the Walther (ASTM D341) fit
through the user's points against the published points (analytic/data/space_oil_viscosity.csv,
the project copy of the reference data), its stated range and the warning outside it; library
oils with one viscosity point and bad tables refused at config time with one line, exit 2."""
from pathlib import Path

import numpy as np
import pytest

import bearingfem
from analytic.lubrication import get_lubricant, lubricant_from_table
from studies.app.cli import main
from studies.model.checks import plausibility_warnings
from studies.model.config import CONFIG_DIR, ConfigError, load_assembly
from refusal import simulate_is_refused

TEMPLATE = CONFIG_DIR / "template.toml"


def _points(name):
    lub = get_lubricant(name)
    return [[float(T), float(nu)] for T, nu in zip(lub.T_points_C, lub.nu_points_mm2_s)]


def _with_oil(tmp_path, oil: str, table: str = "") -> "Path":
    text = TEMPLATE.read_text().replace('lubricant = "Nye 2001a (Pennzane MAC)"',
                                        f'lubricant = "{oil}"', 1)
    assert f'lubricant = "{oil}"' in text
    p = tmp_path / "asm.toml"
    p.write_text(text + "\n" + table)
    return p


def _table(name, pts, density=840.0, alpha=10.0, source="test"):
    rows = ", ".join(f"[{T!r}, {nu!r}]" for T, nu in pts)
    return (f'[lubricants.{name}]\nkinematic_viscosity_cSt = [{rows}]\ndensity_kg_m3 = {density}\n'
            f'pressure_viscosity_per_GPa = {alpha}\nsource = "{source}"\n')


def test_walther_fit_reproduces_fomblin_z25_within_the_printed_precision():
    """Fomblin Z25 (ESTL2018 Table 8: 263, 157, 49 mm^2/s at 20, 40, 100 C; printed to the unit,
    no uncertainty given, so the stated precision is +-0.5 mm^2/s): the least-squares Walther fit
    of a user table with these points gives each back within 0.5 mm^2/s, and states 20..100 C
    as its range. For Nye 2001a and Fomblin Z60 the three points are not on one Walther line:
    the fit misses them by up to 2 % (recorded here, not hidden: 1.8 % and 1.9 %)."""
    lub = lubricant_from_table("Z25own", {"kinematic_viscosity_cSt": _points("Fomblin Z25"),
                                          "density_kg_m3": 1850.0,
                                          "pressure_viscosity_per_GPa": 15.0})
    law = lub.walther()
    assert law.fit_range_C == (20.0, 100.0)
    np.testing.assert_allclose(law.nu_mm2_s([20.0, 40.0, 100.0]), [263.0, 157.0, 49.0], atol=0.5)
    for name in ("Nye 2001a", "Z60"):
        pts = np.array(_points(name))
        own = lubricant_from_table("x", {"kinematic_viscosity_cSt": pts.tolist(),
                                         "density_kg_m3": 900.0, "pressure_viscosity_per_GPa": 10.0})
        rel = own.walther().nu_mm2_s(pts[:, 0]) / pts[:, 1] - 1
        assert 0.01 < np.abs(rel).max() < 0.02, (name, rel)


def test_fit_from_40_and_100C_is_wrong_at_minus_40C_and_the_warning_fires(tmp_path):
    """Pennzane SHF X-2000 (BESSETTE1997): a user table of the 40 and 100 C points (107, 14.3
    mm^2/s) fits 40..100 C exactly, and at -40 C gives 1.26e5 mm^2/s against the measured 80500
    (+57 %): the reference data's own case of a law wrong outside its range (its README). A row
    at -40 C gets one warning line naming the oil and the range; rows inside get none."""
    cfg = _with_oil(tmp_path, "X2000own", _table("X2000own", [[40.0, 107.0], [100.0, 14.3]]))
    asm = load_assembly(cfg)
    law = asm.oil().walther()
    assert law.fit_range_C == (40.0, 100.0)
    assert law.nu_mm2_s([40.0, 100.0]) == pytest.approx([107.0, 14.3], rel=1e-12)
    assert law.nu_mm2_s(-40.0) / 80500.0 - 1 > 0.5
    warn = [w for w in plausibility_warnings(asm, None, {"viscosity_mm2_s": law.nu_mm2_s([-40.0, 60.0])})
            if "Walther" in w]
    assert len(warn) == 1 and "X2000own" in warn[0] and "40..100 C" in warn[0] \
        and "-40.0..-40.0 C in 1 of 2 rows" in warn[0]
    assert not [w for w in plausibility_warnings(asm, None, {"viscosity_mm2_s": law.nu_mm2_s([40.0, 99.0])})
                if "Walther" in w]
    # end to end: the simulate run of the user's oil says it once on stderr
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n-40\n60\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", str(cfg), str(cond), "-o", str(out)]) == 0
    assert out.exists()


def test_user_oil_reaches_the_torque(tmp_path):
    """Two points give the Walther law exactly through them: at a uniform 20 C the viscosity of
    every row is the table's 20 C value, and the viscous torque is Palmgren's
    1e-7 f0 (nu n)^(2/3) dm^3 per bearing (two bearings) with it."""
    cfg = _with_oil(tmp_path, "MyOil", _table("MyOil", [[20.0, 250.0], [100.0, 20.0]]))
    asm = load_assembly(cfg)
    out = bearingfem.simulate(asm, {"T_ambient_C": [20.0], "speed_rpm": [1000.0]})
    assert out["viscosity_mm2_s"][0] == pytest.approx(250.0, rel=1e-12)
    from studies.model.pipeline import Pipeline
    dm = Pipeline.shared(asm).geom.dm_mm
    f0 = asm.lubrication.viscous_factor_f0
    expected = 2 * 1e-7 * f0 * (250.0 * 1000.0) ** (2 / 3) * dm ** 3
    assert out["torque_viscous_Nmm"][0] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("oil", ["815Z", "Brayco 814"])
def test_library_oil_with_one_point_refused_at_config_time(tmp_path, capsys, oil):
    """Brayco 815Z and 814 have one viscosity point in the library (SNC2018, -54 C): refused at
    config time, one line, exit 2, no output (it was a 31-line traceback, exit 1)."""
    cfg = _with_oil(tmp_path, oil)
    with pytest.raises(ConfigError, match="lubrication.lubricant: .*fewer than two viscosity points"):
        load_assembly(cfg)
    simulate_is_refused(tmp_path, capsys, cfg, "[lubricants.NAME]")
    assert main(["report", str(cfg), "--out", str(tmp_path / "rep")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert not (tmp_path / "rep").exists() or not any((tmp_path / "rep").iterdir())


@pytest.mark.parametrize("table, message", [
    (_table("MyOil", [[40.0, 100.0]]), "lubricants.MyOil.kinematic_viscosity_cSt: needs at least two points"),
    (_table("MyOil", [[40.0, 100.0], [40.0, 90.0]]), "lubricants.MyOil.kinematic_viscosity_cSt: needs at least two points"),
    (_table("MyOil", [[40.0, 100.0], [100.0, 1.5]]), "lubricants.MyOil.kinematic_viscosity_cSt: 1.5 cSt at 100 C is below 2 cSt"),
    (_table("MyOil", [[40.0, 100.0], [100.0, 10.0]], density=-1), "lubricants.MyOil.density_kg_m3: must be a finite number > 0"),
    ('[lubricants.MyOil]\nkinematic_viscosity_cSt = [[40.0, 100.0], [100.0, 10.0]]\n', "lubricants.MyOil: missing density_kg_m3, pressure_viscosity_per_GPa"),
    (_table("MyOil", [[40.0, 100.0], [100.0, 10.0]]) + "viscosity_index = 3\n", "lubricants.MyOil.viscosity_index: unknown key"),
    ('[lubricants.MyOil]\nkinematic_viscosity_cSt = [40.0, 100.0]\ndensity_kg_m3 = 900.0\n'
     'pressure_viscosity_per_GPa = 10.0\n', "lubricants.MyOil.kinematic_viscosity_cSt: give [[T_C, nu_cSt], ...]"),
    ('[lubricants]\nMyOil = 3\n', "[lubricants]: give one table per oil"),
    ("", "unknown lubricant 'MyOil'"),
])
def test_bad_lubricant_tables_one_line_exit_2(tmp_path, capsys, table, message):
    cfg = _with_oil(tmp_path, "MyOil", table)
    with pytest.raises(ConfigError) as exc:
        load_assembly(cfg)
    assert message in str(exc.value) and str(exc.value).startswith(str(cfg))
    simulate_is_refused(tmp_path, capsys, cfg, message)


def test_a_table_may_take_a_library_name_and_wins():
    """Like [materials.NAME]: the file's own oil of a library name is the one used."""
    own = lubricant_from_table("Fomblin Z25", {"kinematic_viscosity_cSt": [[20.0, 300.0], [100.0, 50.0]],
                                               "density_kg_m3": 1850.0, "pressure_viscosity_per_GPa": 15.0})
    assert get_lubricant("Fomblin Z25", (own,)) is own
    assert get_lubricant("Z60", (own,)).name == "Fomblin Z60"


def test_the_report_states_the_fit_and_its_range(tmp_path):
    """The report's inputs name the oil's Walther fit, its points and its range."""
    cfg = _with_oil(tmp_path, "X2000own", _table("X2000own", [[40.0, 107.0], [100.0, 14.3]],
                                                 source="Bessette 1997"))
    text = load_assembly(cfg).oil().statement()
    assert "Walther (ASTM D341)" in text and "valid 40..100 C" in text
    assert "107 cSt at 40 C, 14.3 cSt at 100 C" in text and "Bessette 1997" in text


def test_lubricant_name_alias_is_the_lubrication_key(tmp_path):
    """`[lubricant] name = "X"` (the CLI contract's spelling) loads the same assembly as
    `[lubrication] lubricant = "X"`; another key in [lubricant], or the oil given both ways, is
    one line naming [lubricant]."""
    base = load_assembly(_with_oil(tmp_path, "Fomblin Z25"))
    text = _with_oil(tmp_path, "Fomblin Z25").read_text()
    moved = text.replace('lubricant = "Fomblin Z25"', "", 1) + '\n[lubricant]\nname = "Fomblin Z25"\n'
    p = tmp_path / "alias.toml"
    p.write_text(moved)
    assert load_assembly(p) == base
    p.write_text(text.replace('lubricant = "Fomblin Z25"', "", 1)
                 + '\n[lubricant]\nname = "Fomblin Z25"\nspeed_rpm = 3000\n')
    with pytest.raises(ConfigError, match=r"\[lubricant\] speed_rpm: only `name`"):
        load_assembly(p)
    p.write_text(text + '\n[lubricant]\nname = "Fomblin Z25"\n')
    with pytest.raises(ConfigError, match="give it once"):
        load_assembly(p)


def test_a_viscosity_far_outside_its_fit_says_what_the_rows_then_mean(tmp_path):
    """An oil temperature 80 K below a 40..100 C fit (-40 C) gets, in the same one
    line, how far beyond (40 - (-40) = 80 K, the fit's own range) and that the rows' viscosity,
    viscous torque and film are the law's guess; 10 K below (30 C) only the range warning."""
    cfg = _with_oil(tmp_path, "X2000own", _table("X2000own", [[40.0, 107.0], [100.0, 14.3]]))
    asm = load_assembly(cfg)
    law = asm.oil().walther()
    far = [w for w in plausibility_warnings(asm, None, {"viscosity_mm2_s": law.nu_mm2_s([-40.0, 60.0])})
           if "Walther" in w]
    assert len(far) == 1 and "up to 80 K beyond it" in far[0] and "guess, not data" in far[0]
    near = [w for w in plausibility_warnings(asm, None, {"viscosity_mm2_s": law.nu_mm2_s([30.0, 60.0])})
            if "Walther" in w]
    assert len(near) == 1 and "beyond it" not in near[0]
