"""`[lubrication] viscous_model` and `shear_strength` through the pipeline: the default
keeps every existing column bit for bit, every model's torque and heat split adds up, and the
split columns come after the model columns with the names of docs/cli.md."""
import re
from dataclasses import replace

import numpy as np
import pytest

from studies.model.columns import friction_split_columns, to_columns
from studies.model.config import load_shipped
from studies.model.pipeline import Pipeline, table_inputs

MESH_FACTOR = 4.0            # the FE answer is the same for every friction model: coarse is enough
SPLIT = ["torque_rolling_Nmm", "torque_sliding_Nmm", "torque_drag_Nmm", "heat_inner_W",
         "heat_outer_W", "heat_ball_W"]                 # docs/cli.md, spec "Added for turn 4"
INTERVAL = ["torque_lo_Nmm", "torque_hi_Nmm", "heat_lo_W", "heat_hi_W"]   # spec "Added for turn 5"
COND = {"T_ambient_C": np.array([-20.0, 20.0, 40.0]), "speed_rpm": np.array([3500.0, 3500.0, 9000.0])}


def _columns(asm, **lub):
    a = replace(asm, lubrication=replace(asm.lubrication, **lub)) if lub else asm
    return to_columns(Pipeline.shared(a, mesh_factor=MESH_FACTOR).run(table_inputs(a, COND)),
                      friction_split=True)


@pytest.fixture(scope="module")
def seed001():
    return load_shipped("seed001")


def test_palmgren_default_keeps_every_column_and_appends_the_split(seed001):
    """seed001 (oil): viscous_model "palmgren" given explicitly = the shipped file (default), bit
    for bit in every column; to_columns without the split is the same dict minus the six
    columns, in the same order (the studies' CSVs are unchanged)."""
    base = _columns(seed001)
    explicit = _columns(seed001, viscous_model="palmgren", shear_strength="constant")
    assert list(base) == list(explicit)
    for k in base:
        assert np.array_equal(base[k], explicit[k]), k
    res = Pipeline.shared(seed001, mesh_factor=MESH_FACTOR).run(table_inputs(seed001, COND))
    plain = to_columns(res)
    assert list(plain) == [k for k in base if k not in SPLIT + INTERVAL]
    names = list(base)
    first_flag = next(i for i, k in enumerate(names) if k.startswith("flag_"))
    assert names[first_flag - 10:first_flag] == SPLIT + INTERVAL


@pytest.mark.parametrize("model", ["palmgren", "skf2004", "ehl_rolling", "starved"])
def test_every_oil_model_splits_its_torque_and_heat_whole(seed001, model):
    """Each viscous_model on seed001's rows: rolling + sliding + drag = torque_Nmm and
    heat_inner + heat_outer + heat_ball = heat_W, to 1e-9 relative of the row's torque / heat."""
    c = _columns(seed001, viscous_model=model, oil_quantity_mg=5.0)
    t, q = c["torque_Nmm"], c["heat_W"]
    assert np.all(np.abs(c["torque_rolling_Nmm"] + c["torque_sliding_Nmm"] + c["torque_drag_Nmm"]
                         - t) <= 1e-9 * t)
    assert np.all(np.abs(c["heat_inner_W"] + c["heat_outer_W"] + c["heat_ball_W"] - q) <= 1e-9 * q)


def test_solid_film_pressure_law_through_the_config():
    """seed000 (MoS2): shear_strength "pressure" with tau0 = 0 and alpha = the file's friction
    coefficient is the constant law (torque to 1e-13 relative); with tau0 > 0 the torque rises."""
    asm = load_shipped("seed000")
    mu = asm.lubrication.friction_coefficient
    const = _columns(asm)
    press = _columns(asm, shear_strength="pressure", tau0_MPa=0.0, alpha_shear=mu)
    assert np.allclose(press["torque_Nmm"], const["torque_Nmm"], rtol=1e-13, atol=0)
    more = _columns(asm, shear_strength="pressure", tau0_MPa=20.0, alpha_shear=mu)
    assert np.all(more["torque_Nmm"] > const["torque_Nmm"])


def test_split_column_names_are_the_contract():
    """friction_split_columns names exactly the six columns of the spec, in its order."""
    from analytic.friction.pair import TorqueComponents
    one = np.ones(2)
    t = TorqueComponents("oil", one, one, one, one, rolling_Nmm=one, sliding_Nmm=one,
                         drag_Nmm=one, heat_inner_W=one, heat_outer_W=one, heat_ball_W=one)
    assert list(friction_split_columns(t)) == SPLIT


@pytest.mark.parametrize("name, lub, key", [
    ("seed000", {"viscous_model": "skf2004"}, "viscous_model"),
    ("seed001", {"shear_strength": "pressure", "tau0_MPa": 20.0}, "shear_strength"),
    ("seed001", {"oil_quantity_mg": 5.0}, "oil_quantity_mg"),
    ("seed000", {"tau0_MPa": 20.0}, "tau0_MPa"),
    ("seed000", {"shear_strength": "pressure"}, "shear_strength"),
])
def test_friction_keys_of_the_wrong_kind_are_refused_in_one_line(name, lub, key):
    """A friction key that the assembly's lubrication would not use: one line naming the file
    and the key (ConfigError), as for the clamp's keys."""
    import tomllib

    from studies.model.config import CONFIG_DIR, SHIPPED, ConfigError, assembly_from_dict
    with open(CONFIG_DIR / SHIPPED[name], "rb") as fh:
        raw = tomllib.load(fh)
    shipped = dict(raw["lubrication"])
    raw["lubrication"].update(lub)
    with pytest.raises(ConfigError, match=rf"^x\.toml: lubrication\.{key}: ") as e:
        assembly_from_dict(raw, "x.toml")
    assert "\n" not in str(e.value)
    film = {k: v for k, v in shipped.items() if k != "friction_coefficient"}  # unused by "pressure"
    ok = dict(shipped, viscous_model="starved", oil_quantity_mg=5.0) if name == "seed001" \
        else dict(film, shear_strength="pressure", tau0_MPa=20.0)
    raw["lubrication"] = ok
    assembly_from_dict(raw, "x.toml")                 # the same keys where they belong: accepted


def test_diagnose_accepts_every_column_simulate_writes(seed001):
    """A `simulate` CSV fed back to `diagnose` as measured data: every column it writes with the
    split is a comparable output, an accepted one or a check flag (before: the six split columns
    were refused as unknown, exit 2 on the model's own output)."""
    from studies.diagnosis.files import COMPARABLE, OUTPUT_NAMES

    unknown = [k for k in _columns(seed001) if k not in OUTPUT_NAMES and k not in COMPARABLE
               and k not in COND]
    assert unknown == []


# ------------------------------------------- one friction route for `simulate` and `bearing`
def _section_text(text: str, name: str) -> str:
    """The text of TOML table [name] of `text` (header to the next header)."""
    import re
    m = re.search(rf"^\[{re.escape(name)}\][^\n]*\n(.*?)(?=^\[|\Z)", text, re.S | re.M)
    return f"[{name}]\n{m.group(1)}"


def _seed001_bearing_file(tmp_path, **lub):
    """seed001's [bearing] and [lubrication] as a `bearing` file, with `lub` set in it (with
    skf2004 without the friction coefficient, which its sliding term replaces: refused)."""
    import re

    from studies.model.config import CONFIG_DIR, SHIPPED
    text = (CONFIG_DIR / SHIPPED["seed001"]).read_text()
    lubrication = _section_text(text, "lubrication")
    if lub.get("viscous_model") == "skf2004":
        lubrication = re.sub(r"^friction_coefficient = .*\n", "", lubrication, flags=re.M)
    lubrication = lubrication + "".join(
        f'{k} = {v!r}\n'.replace("'", '"') for k, v in lub.items())
    b = tmp_path / "b.toml"
    b.write_text(_section_text(text, "bearing") + lubrication)
    return b


@pytest.mark.parametrize("model", ["palmgren", "skf2004"])
def test_bearing_gives_simulates_torque_for_the_same_bearing_load_and_law(seed001, tmp_path,
                                                                          model):
    """`bearing` on seed001's bearing under the axial force bearing A carries in `simulate`, at
    the row's speed and oil temperature (the rows are isothermal: the oil at T_ambient), gives
    simulate's torque of bearing A to 1e-9 relative, for a law that depends on the bearing's
    loads, speed and viscosity only (palmgren, skf2004: their torque does not depend on the
    contact angle, which the pair's fits change); and skf2004 differs from Palmgren (before
    this, `bearing` gave Palmgren's torque whatever viscous_model said)."""
    import pandas as pd

    from studies.app.cli import main
    a = replace(seed001, lubrication=replace(seed001.lubrication, viscous_model=model))
    res = Pipeline.shared(a, mesh_factor=MESH_FACTOR).run(table_inputs(a, COND))
    nu = a.oil().nu_mm2_s(COND["T_ambient_C"])
    assert np.allclose(res.torque.viscosity_mm2_s, nu, rtol=1e-12)   # isothermal rows
    Fa = res.pair.axial_force_N[0]
    loads = tmp_path / "loads.csv"
    pd.DataFrame({"axial_load_N": Fa, "speed_rpm": COND["speed_rpm"],
                  "T_oil_C": COND["T_ambient_C"]}).to_csv(loads, index=False)
    out = tmp_path / f"{model}.csv"
    assert main(["bearing", str(_seed001_bearing_file(tmp_path, viscous_model=model)), str(loads),
                 "-o", str(out)]) == 0
    got = pd.read_csv(out)["torque_Nmm"].to_numpy()
    np.testing.assert_allclose(got, res.torque.torque_A_Nmm, rtol=1e-9)
    if model == "skf2004":
        palm = replace(seed001, lubrication=replace(seed001.lubrication, viscous_model="palmgren"))
        p = Pipeline.shared(palm, mesh_factor=MESH_FACTOR).run(table_inputs(palm, COND))
        assert np.all(np.abs(got / p.torque.torque_A_Nmm - 1.0) > 0.05)


@pytest.mark.parametrize("model", ["palmgren", "skf2004", "ehl_rolling", "starved"])
def test_every_ball_summed_is_z_times_the_representative_ball(model):
    """`bearing` sums the law over every ball's own contacts (`single_bearing_contacts`), the
    pair route takes Z times a representative ball (`pair_bearing_contacts`): on the same
    bearing state under a pure axial load (every ball alike) the two give the same torque for
    every law, to 1e-12 relative (the same state, the same law, two ways of counting balls)."""
    from analytic.friction.options import FrictionOptions
    from analytic.friction.pair import bearing_friction
    from analytic.lubrication import dynamic_viscosity_Pa_s
    from bearing_reference import seed001_axial_contacts

    asm, g, speed, every, one, oil, nu = seed001_axial_contacts()
    fr = FrictionOptions(viscous_model=model, oil_quantity_mg=5.0 if model == "starved" else 0.0,
                         eta_Pa_s=dynamic_viscosity_Pa_s(nu, oil.density_kg_m3),
                         alpha_per_Pa=oil.alpha_per_Pa, density_kg_m3=oil.density_kg_m3,
                         bore_mm=asm.bearing.bore_mm,
                         outside_diameter_mm=asm.bearing.outside_diameter_mm)
    args = dict(model="oil", mu=0.0029, speed_rpm=speed, f0=1.7, nu_mm2_s=nu, friction=fr)
    a, b = bearing_friction(g, every, **args), bearing_friction(g, one, **args)
    np.testing.assert_allclose(a.total_Nmm, b.total_Nmm, rtol=1e-12)
    assert np.all(a.total_Nmm > 0)


# ------------------------------------------------ the drag term and the lubrication method
def test_drag_column_carries_the_bath_and_is_zero_without_one(seed001):
    """skf2004 on seed001 with lubrication_method = "oil_bath" and an oil level: torque_drag_Nmm
    and heat_ball_W positive, the drag the SKF form of each bearing's own speed and viscosity
    (both bearings: twice `drag_torque_Nmm`, to 1e-12 relative), the rolling + sliding parts
    unchanged by the bath; without a level (oil jet) both columns are 0."""
    from analytic.friction.skf2004 import drag_torque_Nmm
    level = 5.0
    bath = _columns(seed001, viscous_model="skf2004", lubrication_method="oil_bath",
                    oil_level_mm=level)
    jet = _columns(seed001, viscous_model="skf2004", lubrication_method="oil_jet")
    b = seed001.bearing
    expect = 2.0 * drag_torque_Nmm(level, b.bore_mm, b.outside_diameter_mm, COND["speed_rpm"],
                                   bath["viscosity_mm2_s"])
    np.testing.assert_allclose(bath["torque_drag_Nmm"], expect, rtol=1e-12)
    assert np.all(bath["torque_drag_Nmm"] > 0) and np.all(bath["heat_ball_W"] > 0)
    assert np.all(jet["torque_drag_Nmm"] == 0) and np.all(jet["heat_ball_W"] == 0)
    np.testing.assert_allclose(bath["torque_rolling_Nmm"] + bath["torque_sliding_Nmm"],
                               jet["torque_rolling_Nmm"] + jet["torque_sliding_Nmm"], rtol=1e-12)


@pytest.mark.parametrize("lub, key, words", [
    ({"oil_level_mm": 5.0, "viscous_model": "skf2004"}, "oil_level_mm", "oil_bath"),
    ({"oil_level_mm": 5.0, "lubrication_method": "oil_bath"}, "oil_level_mm", "skf2004"),
    ({"lubrication_method": "splash"}, "lubrication_method", "not one of"),
])
def test_lubrication_method_keys_without_effect_are_refused(lub, key, words):
    """An oil level without a bath or with a law that has no drag term, an unknown method: one
    line naming file and key."""
    import tomllib

    from studies.model.config import CONFIG_DIR, SHIPPED, ConfigError, assembly_from_dict
    with open(CONFIG_DIR / SHIPPED["seed001"], "rb") as fh:
        raw = tomllib.load(fh)
    raw["lubrication"].update(lub)
    with pytest.raises(ConfigError, match=rf"^x\.toml: lubrication\.{key}: .*{words}") as e:
        assembly_from_dict(raw, "x.toml")
    assert "\n" not in str(e.value)


def test_tau0_typed_in_pa_and_a_film_with_an_oil_method_are_refused():
    """tau0 = 1.7e7 (Pa typed for MPa: 1.7e7 N mm of torque before) and a lubrication method on a
    solid film: one line each."""
    import tomllib

    from studies.model.config import CONFIG_DIR, SHIPPED, ConfigError, assembly_from_dict
    with open(CONFIG_DIR / SHIPPED["seed000"], "rb") as fh:
        raw = tomllib.load(fh)
    for lub, key, words in (({"shear_strength": "pressure", "tau0_MPa": 1.7e7}, "tau0_MPa", "in Pa"),
                            ({"lubrication_method": "oil_jet"}, "lubrication_method", "solid_film")):
        r = {**raw, "lubrication": {**raw["lubrication"], **lub}}
        with pytest.raises(ConfigError, match=rf"^x\.toml: lubrication\.{key}: .*{words}"):
            assembly_from_dict(r, "x.toml")


def test_lubricant_family_sets_skfs_full_film_coefficient():
    """A [lubricants.NAME] family: "synthetic" gives mu_EHL 0.04, "mineral" (the default) 0.05;
    the library's PFPE and MAC oils are synthetic; another word is one line."""
    from analytic.lubrication import get_lubricant, lubricant_from_table
    base = {"kinematic_viscosity_cSt": [[40.0, 100.0], [100.0, 10.0]], "density_kg_m3": 860.0,
            "pressure_viscosity_per_GPa": 20.0}
    assert lubricant_from_table("A", base).oil_family == "mineral"
    assert lubricant_from_table("A", {**base, "family": "synthetic"}).oil_family == "synthetic"
    assert get_lubricant("Nye 2001a").oil_family == "synthetic"
    with pytest.raises(ValueError, match="lubricants.A.family"):
        lubricant_from_table("A", {**base, "family": "vegetable"})


# ------------------------------------------------------------------ range warnings (one line)
def test_a_law_outside_its_source_range_warns_once_through_simulate(seed001, tmp_path):
    """skf2004 on seed001 at 3500 rpm (n dm = 1.1e5 mm/min) and at 40 000 rpm (1.24e6, beyond the
    model's n dm <= 1e6): `simulate_file` (chunks of 1 row: the notes of separate chunks
    merged) gives exactly one warning line naming the law, its bound and 1 row of 3; Palmgren
    on the same rows none."""
    from studies.model.stream import simulate_file
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n20,3500\n20,40000\n40,3500\n")
    runs = {}
    for model in ("skf2004", "palmgren"):
        a = replace(seed001, lubrication=replace(seed001.lubrication, viscous_model=model))
        runs[model] = simulate_file(a, cond, tmp_path / f"{model}.csv", chunk_rows=1,
                                    pipeline=Pipeline.shared(a, mesh_factor=MESH_FACTOR))
    lines = [w for w in runs["skf2004"].warnings if w.startswith("friction law")]
    assert len(lines) == 1 and "skf2004" in lines[0] and "1 of 3 rows" in lines[0], lines
    assert "\n" not in lines[0] and "n dm <= 1e+06" in lines[0]
    assert not [w for w in runs["palmgren"].warnings if w.startswith("friction law")]


def test_range_notes_merge_rows_and_extremes():
    """Two bearings of the same rows: a row outside in either counts once; two chunks of a
    table: their rows add; the extremes are the extremes of all."""
    from analytic.friction.ranges import combine, merge, notes, range_rows
    a = range_rows("x", "q", "q <= 1", [0.5, 2.0, 3.0], [False, True, True])
    b = range_rows("x", "q", "q <= 1", [[4.0, 0.1, 0.2], [0.1, 0.1, 1.5]],
                   [[True, False, False], [False, False, True]])
    (n,) = notes(combine((a,), (b,)))
    assert (n.rows, n.lo, n.hi) == (3, 1.5, 4.0)
    (m,) = merge((n,), (n,))
    assert (m.rows, m.lo, m.hi) == (6, 1.5, 4.0)
    assert notes((range_rows("x", "q", "q <= 1", [0.5], [False]),)) == ()


def test_bearing_warns_when_ehl_rolling_leaves_its_ellipticity_range(tmp_path):
    """`bearing` with ehl_rolling on seed001's bearing (groove ratios 0.52 / 0.53: the inner
    contact's k = a/b is about 9, above Hamrock-Dowson's 8): one warning line naming the law
    and the ellipticity, through the command's warning route."""
    import pandas as pd

    from studies.usecases.api import bearing
    loads = tmp_path / "loads.csv"
    pd.DataFrame({"axial_load_N": [50.0, 100.0], "speed_rpm": [3500.0, 6000.0],
                  "T_oil_C": [20.0, 20.0]}).to_csv(loads, index=False)
    res = bearing(_seed001_bearing_file(tmp_path, viscous_model="ehl_rolling"), loads,
                  tmp_path / "o.csv")
    lines = [w for w in res.warnings if "friction law" in w]
    assert len(lines) == 1 and "ehl_rolling" in lines[0] and "ellipticity" in lines[0], res.warnings


def test_a_bearing_files_friction_keys_are_checked_as_an_assemblys(tmp_path):
    """`bearing` refuses a friction key without effect as `simulate` does (one line naming the
    file and key): an oil quantity without the starved law, an oil level without a bath."""
    from studies.model.config import ConfigError, load_bearing
    for lub, key in (({"oil_quantity_mg": 5.0}, "oil_quantity_mg"),
                     ({"viscous_model": "skf2004", "oil_level_mm": 4.0}, "oil_level_mm")):
        path = _seed001_bearing_file(tmp_path, **lub)
        with pytest.raises(ConfigError, match=rf"lubrication\.{key}: ") as e:
            load_bearing(path)
        assert str(path) in str(e.value) and "\n" not in str(e.value)


@pytest.mark.parametrize("name, lub, key", [
    ("seed001", {"viscous_model": "skf2004"}, "friction_coefficient"),     # SKF's sliding term
    ("seed001", {"load_term": "palmgren"}, "friction_coefficient"),         # f1 F dm
    ("seed001", {"hysteresis_loss_factor": 0.01}, "hysteresis_loss_factor"),
    ("seed001", {"viscous_model": "starved"}, "viscous_model"),             # 0 mg: Palmgren's
    ("seed000", {"shear_strength": "pressure", "tau0_MPa": 20.0}, "friction_coefficient"),
    ("seed000", {"viscous_factor_f0": 1.5}, "viscous_factor_f0"),
    ("seed000", {"load_term": "palmgren"}, "load_term"),
    ("seed000", {"heat_transfer_W_per_mm2_K": 3e-4}, "heat_transfer_W_per_mm2_K"),
])
def test_a_typed_key_the_files_law_does_not_use_is_refused(name, lub, key, tmp_path):
    """A key typed in a file that its own law does not use (docs/cli.md: "friction_coefficient
    then unused", SKF "replaces the load term"): `simulate` exits 2 with one line naming file and
    key and writes nothing."""
    import contextlib
    import io
    import re

    from studies.app.cli import main
    from studies.model.config import CONFIG_DIR, SHIPPED
    text = (CONFIG_DIR / SHIPPED[name]).read_text()
    for k, v in lub.items():
        line = f"{k} = {v!r}".replace("'", '"')
        text, n = re.subn(rf"^{k} = .*$", line, text, count=1, flags=re.M)
        if not n:
            text = text.replace("[lubrication]\n", f"[lubrication]\n{line}\n", 1)
    bad = tmp_path / "x.toml"
    bad.write_text(text)
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    out = tmp_path / "o.csv"
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        assert main(["simulate", str(bad), str(cond), "-o", str(out)]) == 2
    msg = err.getvalue().strip()
    assert "\n" not in msg and f"x.toml: lubrication.{key}: " in msg, msg
    assert not out.exists()


@pytest.mark.parametrize("key, value, words, converted", [
    ("pressure_viscosity_per_GPa", 2e-8, "typed in 1/Pa", "20 1/GPa"),
    ("density_kg_m3", 0.86, "typed in g/cm^3", "860 kg/m^3"),
])
def test_a_lubricant_value_typed_in_another_unit_is_one_line(key, value, words, converted):
    """A user oil's pressure-viscosity coefficient typed in 1/Pa (2e-8: a film law would take
    alpha 2e-17 1/Pa, the minimal-oil film ~ alpha^0.49 some 4e4 times too thin) or its density
    in g/cm^3 (0.86: the oil layer 1000 times too thick): one line naming the key, the unit
    suspected and the value converted (1e9 and 1e3, the units' ratios)."""
    from analytic.lubrication import lubricant_from_table
    base = {"kinematic_viscosity_cSt": [[40.0, 100.0], [100.0, 10.0]], "density_kg_m3": 860.0,
            "pressure_viscosity_per_GPa": 20.0}
    with pytest.raises(ValueError, match=rf"lubricants\.A\.{key}: .*{re.escape(words)}") as e:
        lubricant_from_table("A", {**base, key: value})
    assert converted in str(e.value) and "\n" not in str(e.value)
    assert lubricant_from_table("A", base).alpha_per_Pa == pytest.approx(2e-8)


def test_the_oil_bath_f0_warning_is_palmgren_s_only(seed001):
    """The warning that Palmgren's f0 is an oil-bath value (viscous over load torque above
    VISCOUS_TO_LOAD_WARN) is given on seed 001's Palmgren rows, where the ratio is above the
    limit, and not where the law takes no f0 (skf2004: its rolling over sliding term is above the
    same limit on the same rows) nor on a bearing that does run in an oil bath."""
    from studies.model.checks import VISCOUS_TO_LOAD_WARN, plausibility_warnings

    def warned(**lub):
        a = replace(seed001, lubrication=replace(seed001.lubrication, **lub))
        out = _columns(a)
        ratio = np.max(out["torque_viscous_Nmm"] / out["torque_load_Nmm"])
        return ratio, any("is an oil-bath value" in w for w in plausibility_warnings(a, COND, out))
    for lub, expect in (({}, True), ({"viscous_model": "skf2004"}, False),
                        ({"lubrication_method": "oil_bath"}, False)):
        ratio, w = warned(**lub)
        assert ratio > VISCOUS_TO_LOAD_WARN and w is expect, (lub, ratio)


def test_an_oil_level_above_the_drag_formulas_range_warns_once_and_is_capped(seed001, tmp_path):
    """skf2004 in an oil bath 2 dm deep (above the catalogue formula's H <= 1.2 dm): the drag is
    the formula's at 1.2 dm (`drag_torque_Nmm` at the cap, both bearings, 1e-12) and `simulate`
    says so in one warning line naming the law and the level, in every row; 1 dm: no line."""
    from analytic.friction.skf2004 import DRAG_LEVEL_MAX_DM, drag_torque_Nmm
    from studies.model.stream import simulate_file
    b = seed001.bearing
    dm = 0.5 * (b.bore_mm + b.outside_diameter_mm)
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,speed_rpm\n20,3500\n40,3500\n")
    lines = {}
    for depth in (2.0, 1.0):
        a = replace(seed001, lubrication=replace(seed001.lubrication, viscous_model="skf2004",
                                                 lubrication_method="oil_bath",
                                                 oil_level_mm=depth * dm))
        run = simulate_file(a, cond, tmp_path / f"{depth}.csv", chunk_rows=1,
                            pipeline=Pipeline.shared(a, mesh_factor=MESH_FACTOR))
        lines[depth] = [w for w in run.warnings if "oil level" in w]
        if depth == 2.0:
            c = _columns(a)
            cap = 2.0 * drag_torque_Nmm(DRAG_LEVEL_MAX_DM * dm, b.bore_mm, b.outside_diameter_mm,
                                        COND["speed_rpm"], c["viscosity_mm2_s"])
            np.testing.assert_allclose(c["torque_drag_Nmm"], cap, rtol=1e-12)
    assert len(lines[2.0]) == 1 and "skf2004" in lines[2.0][0] and "2 of 2 rows" in lines[2.0][0]
    assert lines[1.0] == []
