"""Assembly config validation: every bad input gives one line naming file, key and problem."""
import tomllib

import pytest

from studies.model.config import CONFIG_DIR, ConfigError, assembly_from_dict, load_assembly, load_shipped


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


def test_template_names_every_key_with_a_comment_and_loads():
    """studies/configs/template.toml is the user's starting point: every section and key the
    loader reads appears in it with a comment on its line (unit, allowed values, default), and
    it loads as a valid assembly."""
    import tomllib

    from studies.model.config import CONFIG_DIR, LAYERS, SECTIONS, load_assembly

    path = CONFIG_DIR / "template.toml"
    raw = tomllib.loads(path.read_text())
    assert set(raw) == {"assembly", *SECTIONS} - set(LAYERS)
    assert set(raw["assembly"]) == {"name", "arrangement", "T_ref_C", "source"}
    for name, (cls, _) in SECTIONS.items():
        if name in LAYERS:       # optional parts: a commented-out table names their keys
            text = path.read_text()
            assert f"# [{name}]" in text or f"[{name}]" in text, name
            for key in cls.__dataclass_fields__:
                assert f"# {key} = " in text, (name, key)
            continue
        assert set(raw[name]) == set(cls.__dataclass_fields__), name
    for line in path.read_text().splitlines():
        if "=" in line and not line.startswith("#"):
            assert "#" in line, line                  # every key says what it is
    load_assembly(path)


def test_a_byte_order_mark_is_accepted(tmp_path):
    """Windows editors save UTF-8 with a byte order mark (EF BB BF); the TOML parser refuses it,
    the loader reads past it: the same assembly as the file without it (issue 25)."""
    src = CONFIG_DIR / "template.toml"
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + src.read_bytes())
    assert load_assembly(p) == load_assembly(src)
