"""`[lubrication] viscous_model` and `shear_strength` through the pipeline (issue 33): the default
keeps every existing column bit for bit, every model's torque and heat split adds up, and the
split columns come after the model columns with the names of docs/cli.md."""
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
    from analytic.torque import TorqueComponents
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
    ok = dict(shipped, viscous_model="starved", oil_quantity_mg=5.0) if name == "seed001" \
        else dict(shipped, shear_strength="pressure", tau0_MPa=20.0)
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
