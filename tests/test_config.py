"""Assembly config validation: every bad input gives one line naming file, key and problem; the
template and the docs' key tables say what the schema says."""
import re
import tomllib

import pytest

from studies.model.config import CONFIG_DIR, ConfigError, assembly_from_dict, load_assembly, load_shipped


TEMPLATE = CONFIG_DIR / "template.toml"


def _raw():
    with open(CONFIG_DIR / "seed000_71807C_TC4.toml", "rb") as fh:
        return tomllib.load(fh)


def _err(raw):
    with pytest.raises(ConfigError) as e:
        assembly_from_dict(raw, "x.toml")
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("x.toml: ")
    return msg


def test_shipped_config_loads():
    a = load_shipped("seed000")
    assert a.fits.inner_interference_um == 5.0 and a.fits.outer_interference_um == -1.5


@pytest.mark.parametrize("section,key,value,expect", [
    ("shaft", "seat_diameter_mm", -35.0, "shaft.seat_diameter_mm: must be positive"),
    ("shaft", "seat_diameter_mm", 0.0, "shaft.seat_diameter_mm: must be positive"),
    ("housing", "material", "unobtainium", "housing.material: unknown material 'unobtainium'"),
    ("bearing", "bore_mm", 30.0, "bearing.bore_mm: inner ring bore 30 mm does not sit on the shaft seat"),
    ("shaft", "shoulder_diameter_mm", 45.0, "shaft.shoulder_diameter_mm: shaft shoulder overlaps the outer ring"),
    ("fits", "contact", "glued", "fits.contact: 'glued' is not one of"),
    ("bearing", "ball_count", 2.5, "bearing.ball_count: must be an integer"),
    ("nut", "width_mm", "5", "nut.width_mm: must be a finite number"),
])
def test_bad_values(section, key, value, expect):
    raw = _raw()
    raw[section][key] = value
    assert expect in _err(raw)


def test_missing_key_and_wrong_unit_name():
    raw = _raw()
    del raw["housing"]["bore_diameter_mm"]
    assert "housing.bore_diameter_mm: missing key" in _err(raw)
    raw = _raw()
    raw["housing"]["bore_diameter_in"] = raw["housing"].pop("bore_diameter_mm")
    assert "housing.bore_diameter_in: unknown key (wrong unit name? expected 'bore_diameter_mm')" in _err(raw)


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(ConfigError, match="file not found"):
        load_assembly(tmp_path / "nope.toml")
    p = tmp_path / "bad.toml"
    p.write_text("[shaft\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_assembly(p)


def _template_keys() -> dict[tuple[str, str], tuple[str, str]]:
    """(table, key) -> (value, comment) of every key line of the template, the commented-out
    optional tables included ([materials.NAME], which has its own schema, left out)."""
    out, table = {}, None
    for line in TEMPLATE.read_text().splitlines():
        if m := re.match(r"^(?:# )?\[([A-Za-z_.]+)\]", line):
            table = m.group(1)
        elif (m := re.match(r"^(?:# )?(\w+) = (.+?)\s+#\s*(.*)$", line)) and table:
            if not table.startswith(("materials", "lubricants")):
                assert (table, m.group(1)) not in out, (table, m.group(1))
                out[(table, m.group(1))] = (m.group(2), m.group(3))
    return out


def test_template_states_each_schema_key_with_its_unit_bounds_and_default():
    """studies/configs/template.toml is the user's starting point. Every key of the schema is in
    it and every key in it is in the schema (a layer's keys once, in the commented-out [sleeve]:
    [cartridge] has the same); the comment on each key starts with what the schema says of it
    (unit, allowed values or bounds, default: `Key.summary`); each value, the commented-out ones
    too, passes its key; and the file loads as a valid assembly."""
    from studies.model.config import LAYERS, SECTIONS
    from studies.model.config_schema import ASSEMBLY_KEYS, keys_of, parse_value

    schema = {("assembly", k): key for k, key in ASSEMBLY_KEYS.items()}
    for name, cls in SECTIONS.items():
        if name != "cartridge":
            schema.update({(name, k): key for k, key in keys_of(cls).items()})
    assert SECTIONS["cartridge"] is SECTIONS["sleeve"]
    found = _template_keys()
    assert set(found) == set(schema)
    for (name, k), key in schema.items():
        value, comment = found[(name, k)]
        summary = key.summary()
        assert comment == summary or comment.startswith(summary + ";"), (name, k, comment, summary)
        parse_value("template", f"{name}.{k}", key, tomllib.loads(f"v = {value}")["v"])
    raw = tomllib.loads(TEMPLATE.read_text())
    assert set(raw) == {"assembly", *SECTIONS} - set(LAYERS)     # the layers commented out
    assert load_assembly(TEMPLATE).name == "my_pair"


def test_schema_declares_every_field_once_with_the_dataclass_default():
    """The schema of a section is its dataclass's fields (BearingSpec, analytic's, by a table
    of the same names and defaults); a key's default is what the loader fills in when the file
    leaves it out; the mesh target's bounds are the range the size rule was measured over."""
    import dataclasses

    from studies.model.config import SECTIONS, Mesh
    from studies.model.config_schema import keys_of
    from studies.model.mesh_size import TARGET_RANGE

    for name, cls in SECTIONS.items():
        keys = keys_of(cls)
        fields = dataclasses.fields(cls)
        assert list(keys) == [f.name for f in fields], name
        for f in fields:
            if keys[f.name].required:
                assert f.default is dataclasses.MISSING, (name, f.name)
            else:
                assert f.default == keys[f.name].default, (name, f.name)
    bounds = keys_of(Mesh)["target_error"].bounds
    assert (bounds.lo, bounds.hi) == TARGET_RANGE
    # a key left out takes the schema's default: the seed 000 file gives no [mesh], no tolerances
    a = load_shipped("seed000")
    assert a.mesh == Mesh() and a.fits.inner_shaft_deviation_um == () and a.nut.clamp == "rigid"


def test_docs_key_tables_are_the_schemas():
    """docs/cli.md carries every table's key table as generated from the schema (regenerate with
    `python -m studies.model.config_docs docs/cli.md`)."""
    from studies.model.config_docs import section_tables, with_tables

    doc = (CONFIG_DIR.parents[1] / "docs" / "cli.md").read_text()
    assert with_tables(doc) == doc, "run: python -m studies.model.config_docs docs/cli.md"
    for name, table in section_tables().items():
        assert f"<!-- keys [{name}]: generated from studies/model/config_schema.py -->\n{table}\n" \
            in doc, name


def test_a_byte_order_mark_is_accepted(tmp_path):
    """Windows editors save UTF-8 with a byte order mark (EF BB BF); the TOML parser refuses it,
    the loader reads past it: the same assembly as the file without it."""
    src = CONFIG_DIR / "template.toml"
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + src.read_bytes())
    assert load_assembly(p) == load_assembly(src)


def test_a_bearing_file_with_a_clearance_names_a_bad_groove_ratio(tmp_path):
    """A single bearing's file: the groove ratio is checked as a key before the clearance turns
    into a contact angle through A0 = (f_i + f_o - 1) Dw (which a ratio below 0.5 makes
    negative: the clearance was blamed before the schema held the ratio's bounds)."""
    from studies.model.config import load_bearing

    raw = _raw()["bearing"]
    del raw["contact_angle_free_deg"]
    raw["inner_groove_ratio"] = 0.3
    lines = ["[bearing]", "radial_internal_clearance_um = 10"]
    lines += [f"{k} = {v!r}" if not isinstance(v, str) else f'{k} = "{v}"' for k, v in raw.items()]
    p = tmp_path / "b.toml"
    p.write_text("\n".join(lines))
    with pytest.raises(ConfigError, match=r"bearing.inner_groove_ratio: 0.3 is outside 0.5..0.6"):
        load_bearing(p)
