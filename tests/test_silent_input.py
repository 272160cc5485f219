"""Legal but implausible input says so in one warning line, a
mistyped name gets the nearest valid one (studies/model/checks.py `plausibility_warnings`,
infra/names.py)."""
from pathlib import Path

import numpy as np
import pytest

from studies.model.checks import plausibility_warnings
from studies.model.config import ConfigError, assembly_from_dict, load_assembly
from studies.model.table import TableError, read_table

THIN = Path("studies/configs/rig_thin_section_hub.toml")      # [operating] -45..70 C
SLEEVE = Path("studies/configs/rig_cartridge_sleeve.toml")


def _raw(path):
    import tomllib
    return tomllib.loads(path.read_text())


def test_fahrenheit_in_a_celsius_column_is_warned_and_celsius_is_not():
    """The rig's own range -45..70 C typed in Fahrenheit (-49..158 F, 9/5 C + 32, NIST SP 811
    B.8): one line naming the column and the values read back as Celsius (-45.0..70.0 C); the
    same range in Celsius, none; 200 C (above any bearing steel's stabilisation) also warned."""
    asm = load_assembly(THIN)
    T_C = np.linspace(-45.0, 70.0, 12)
    warn = [w for w in plausibility_warnings(asm, {"T_ambient_C": 9 / 5 * T_C + 32})
            if "Fahrenheit" in w]
    assert len(warn) == 1 and "T_ambient_C" in warn[0] and "-45.0..70.0 C" in warn[0]
    assert not [w for w in plausibility_warnings(asm, {"T_ambient_C": T_C}) if "Fahrenheit" in w]
    assert [w for w in plausibility_warnings(asm, {"T_housing_C": np.array([20.0, 200.0])})
            if "Fahrenheit" in w]


def test_conditions_without_ambient_name_the_default_they_run_on():
    """No T_ambient_C: the parts without their own column run at assembly.T_ref_C; one line
    naming them and the value. With every part given, or with T_ambient_C, no line."""
    asm = load_assembly(THIN)
    warn = [w for w in plausibility_warnings(asm, {"T_housing_C": np.array([30.0])})
            if "T_ambient_C" in w]
    assert len(warn) == 1 and f"T_ref_C = {asm.T_ref_C:g} C" in warn[0]
    assert "shaft" in warn[0] and "housing" not in warn[0]
    assert not [w for w in plausibility_warnings(asm, {"T_ambient_C": np.array([30.0])})
                if "no column T_ambient_C" in w]
    every = {f"T_{p}_C": np.array([30.0]) for p in
             ("shaft", "inner_ring", "ball", "outer_ring", "housing", "spacer")}
    assert not [w for w in plausibility_warnings(asm, every) if "no column T_ambient_C" in w]
    assert not [w for w in plausibility_warnings(asm, None) if "no column T_ambient_C" in w]


@pytest.mark.parametrize("section, typo, right", [("sleeve", "radial_thicknes_mm", "radial_thickness_mm"),
                                                  ("preload", "assembled_n", "assembled_N"),
                                                  ("assembly", "T_reff_C", "T_ref_C")])
def test_a_mistyped_key_names_the_nearest_valid_one(section, typo, right):
    raw = _raw(SLEEVE)
    raw[section][typo] = raw[section].pop(right)
    with pytest.raises(ConfigError) as e:
        assembly_from_dict(raw, "x.toml")
    assert "unknown key" in str(e.value) and f"'{right}'" in str(e.value)


def test_a_mistyped_section_and_column_name_the_nearest_valid_one(tmp_path):
    raw = _raw(SLEEVE)
    raw["lubricaton"] = raw.pop("lubrication")
    with pytest.raises(ConfigError, match="did you mean 'lubrication'"):
        assembly_from_dict(raw, "x.toml")
    p = tmp_path / "c.csv"
    p.write_text("T_ambiant_C,speed_rpm\n20,100\n")
    from studies.model.inputs import CONDITION_COLUMNS
    with pytest.raises(TableError, match="did you mean 'T_ambient_C'"):
        read_table(p, allowed=set(CONDITION_COLUMNS))


def test_a_transient_stack_with_no_films_and_no_radiation_is_warned():
    """`[thermal] mode = "transient"` without `[thermal.films]` or emissivity: one line
    saying the stack is adiabatic outside (the ambient only starts it); with a film, none."""
    raw = _raw(SLEEVE)
    raw["cover"].update(clamp="compliant")
    raw["cover"].pop("clamp_force_N")
    raw["thermal"] = {"mode": "transient"}
    warn = [w for w in plausibility_warnings(assembly_from_dict(raw, "x.toml")) if "adiabatic" in w]
    assert len(warn) == 1 and "thermal.films" in warn[0]
    raw["thermal"]["films"] = {"housing_outer": 10.0}
    assert not [w for w in plausibility_warnings(assembly_from_dict(raw, "x.toml")) if "adiabatic" in w]
