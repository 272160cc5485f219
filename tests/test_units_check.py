"""The units check over the whole assembly: an assembly typed in inches (every
length 25.4x too small, its proportions those of a catalogue bearing) is refused with one line
naming inches, exit 2, no output; every shipped and test assembly passes."""
import re

import pytest

from studies.model.config import CONFIG_DIR, SHIPPED, ConfigError, load_assembly
from refusal import simulate_is_refused

TEMPLATE = CONFIG_DIR / "template.toml"
TEST_DATA = CONFIG_DIR.parents[1] / "tests" / "data"


def _in_inches(text: str, um_too: bool) -> str:
    """Every `*_mm` number divided by 25.4 (and, with um_too, every `*_um` number too: the fits
    in inches as well)."""
    suffix = "(?:_mm|_um)" if um_too else "_mm"

    def conv(m):
        return f"{m.group(1)} = {float(m.group(2)) / 25.4!r}"
    return re.sub(rf"^(\w+{suffix}) = (-?[0-9.]+(?:e-?[0-9]+)?)", conv, text, flags=re.M)


@pytest.mark.parametrize("um_too", [False, True])
def test_the_template_in_inches_is_refused_naming_inches(tmp_path, capsys, um_too):
    text = _in_inches(TEMPLATE.read_text(), um_too)
    assert "ball_diameter_mm = 0.25" in text       # 6.35 mm = 1/4 in
    cfg = tmp_path / "inch.toml"
    cfg.write_text(text)
    with pytest.raises(ConfigError, match="looks typed in inches"):
        load_assembly(cfg)
    simulate_is_refused(tmp_path, capsys, cfg, "inches", "x 25.4 = 6.35, 12, 42 mm")


def test_every_shipped_and_test_assembly_passes_the_units_check():
    """The check refuses none of the real designs: the shipped seeds, the template and every
    assembly file of the tests (the smallest ball among them is several mm)."""
    paths = [CONFIG_DIR / f for f in SHIPPED.values()] + [TEMPLATE]
    paths += [p for p in sorted(TEST_DATA.glob("*.toml")) if "[assembly]" in p.read_text()]
    assert len(paths) >= 5
    for p in paths:
        try:
            load_assembly(p)
        except ConfigError as exc:      # a test file made to fail for another reason is fine
            assert "inches" not in str(exc), p
