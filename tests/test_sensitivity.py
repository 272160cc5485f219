"""The assumptions that decide the answer (studies/usecases/sensitivity.py).

The clamp's sensitivity on the template's aluminium-housing stack is checked against a second
route: `bearingfem.simulate` of the assembly with its cover clamp switched (the Python API over the
pipeline, not the report's margin code), its extreme preloads taken directly. A flip is flagged
where PASS and FAIL trade places; sensitivity.csv has exactly the contract's columns.
"""
import csv
from dataclasses import replace

import numpy as np
import pytest

from studies.model.config import CONFIG_DIR, load_assembly
from studies.model.pipeline import Pipeline
from studies.usecases import sensitivity as S
from studies.usecases.report_margins import MarginRow

TEMPLATE = CONFIG_DIR / "template.toml"        # steel shaft, 6061 aluminium housing


def _row(key, value, status, item="x"):
    return MarginRow(item, "", "", "", status, None, "", key, value)


def test_compare_flags_a_flip_and_orders_flips_first():
    """PASS -> FAIL and FAIL -> PASS are flips, "no limit" never; flips come first, then the
    largest |change|, relative to the report's value."""
    base = [_row("preload_min_N", 100.0, "PASS"), _row("torque_max_Nmm", 10.0, "no limit"),
            _row("static_safety_min", 2.5, "FAIL (3 of 25)")]
    alt = [_row("preload_min_N", 60.0, "FAIL (2 of 25)"), _row("torque_max_Nmm", 30.0, "no limit"),
           _row("static_safety_min", 3.5, "PASS")]
    rows = S.order(S.compare("a", "b", base, alt))
    assert [r.margin for r in rows] == ["preload_min_N", "static_safety_min", "torque_max_Nmm"]
    assert [r.flips for r in rows] == [True, True, False]
    assert rows[0].change == pytest.approx(-0.4, rel=1e-12)
    assert rows[2].change == pytest.approx(2.0, rel=1e-12)
    lines = S.section_lines(S.Sensitivity(tuple(rows), (), long=False))
    warn = [x for x in lines if x.startswith("- **Warning**")]
    assert len(warn) == 2 and "from PASS to FAIL" in warn[0]
    assert "from FAIL (3 of 25) to PASS" in warn[1]


def test_a_margin_at_round_off_has_no_relative_change():
    """A clamp face's margin of -6e-9 N is 0: to 0 no change, to 5 N "from 0" (NaN)."""
    base = [_row("margin_clamp_min_N", -6.181e-09, "FAIL (1 of 9)")]
    same = S.compare("a", "b", base, [_row("margin_clamp_min_N", 0.0, "FAIL (1 of 9)")])
    up = S.compare("a", "b", base, [_row("margin_clamp_min_N", 5.0, "PASS")])
    assert same[0].change == 0.0 and not same[0].flips
    assert np.isnan(up[0].change) and up[0].flips


def test_csv_has_exactly_the_contract_columns(tmp_path):
    rows = S.order(S.compare("[cover] clamp = rigid (default)", "compliant",
                             [_row("preload_min_N", 100.0, "PASS")],
                             [_row("preload_min_N", 0.0, "FAIL (1 of 2)")]))
    S.write_csv(tmp_path / "sensitivity.csv", S.Sensitivity(tuple(rows), (), long=True))
    with open(tmp_path / "sensitivity.csv", newline="") as fh:
        table = list(csv.reader(fh))
    assert tuple(table[0]) == ("assumption", "alternative", "margin", "value",
                               "value_alternative", "change", "flips")
    assert table[1] == ["[cover] clamp = rigid (default)", "compliant", "preload_min_N", "100",
                        "0", "-1", "true"]


def test_the_choices_at_their_defaults_are_the_assumptions():
    """The template sets every modelling choice to its default: each is an assumption, with
    the other limit as its alternative; the short version leaves out the ring section."""
    asm = load_assembly(TEMPLATE)
    short, _ = S.alternatives(asm, TEMPLATE, long=False)
    names = {a.assumption.split(" =")[0]: a.alternative for a in short}
    assert names == {"[nut] clamp": "compliant", "[cover] clamp": "compliant",
                     "[fits] contact": "bonded", "[preload] path_compliance": "rigid",
                     "[operating] ball_model": "quasi_dynamic",
                     "[lubrication] viscous_model": "skf2004"}
    long, _ = S.alternatives(asm, TEMPLATE, long=True)
    assert {a.assumption.split(" =")[0] for a in long} == set(names) | {"[mesh] ring_section"}


def test_assume_tagged_numbers_are_varied(tmp_path):
    """A number whose comment carries [assume] gets +10 %, a diameter +1 %; an untagged one
    is not varied."""
    text = TEMPLATE.read_text()
    for line in ("assembled_N = 100.0                # ", "outer_diameter_mm = 60.0           # "):
        text = text.replace(line, line + "[assume] ")
    p = tmp_path / "a.toml"
    p.write_text(text)
    alts, _ = S.alternatives(load_assembly(p), p, long=True)
    nums = [a for a in alts if a.number]
    assert [a.assumption for a in nums] == ["[housing] outer_diameter_mm = 60 [assume]",
                                            "[preload] assembled_N = 100 [assume]"]
    assert nums[0].asm.housing.outer_diameter_mm == pytest.approx(60.6, rel=1e-12)
    assert nums[1].asm.preload.assembled_N == pytest.approx(110.0, rel=1e-12)


@pytest.mark.slow       # two FE set-ups of the template: 10-35 s
def test_clamp_sensitivity_is_a_direct_simulate_with_the_clamp_switched():
    """On the aluminium-housing template, the cover clamp rigid -> compliant moves the preload
    extremes as `bearingfem.simulate` of the switched assembly gives them (the Python API's
    table, not the report's margin code: equal to 1e-12 relative), and the change is large
    (the issue's point: a default that moves the hot preload by tens of per cent; measured
    -23 % on the smallest preload, at 80 C)."""
    import bearingfem

    asm = load_assembly(TEMPLATE)
    alt_asm = replace(asm, cover=replace(asm.cover, clamp="compliant"))
    cond = {"T_ambient_C": np.array([-40.0, 20.0, 80.0])}
    rows = S.compare("cover", "compliant", S.margins_of(asm, cond, Pipeline.shared(asm)),
                     S.margins_of(alt_asm, cond, Pipeline.shared(alt_asm)))
    by = {r.margin: r for r in rows}
    for a, side in ((asm, "value"), (alt_asm, "value_alternative")):
        p = bearingfem.simulate(a, cond)["preload_N"]
        assert getattr(by["preload_min_N"], side) == pytest.approx(float(p.min()), rel=1e-12)
        assert getattr(by["preload_max_N"], side) == pytest.approx(float(p.max()), rel=1e-12)
    assert by["preload_min_N"].change < -0.1


@pytest.mark.slow       # two FE set-ups of the template: 5-15 s
def test_a_flip_is_the_simulated_flags_trading_places():
    """Bonded fits in the template's aluminium housing lose the preload when hot: the report's
    route flags the preload band as a flip, and `bearingfem.simulate` of both assemblies (the
    `flag_preload_lost` column, a second route) shows PASS turning into FAIL."""
    import bearingfem

    asm = load_assembly(TEMPLATE)
    alt_asm = replace(asm, fits=replace(asm.fits, contact="bonded"))
    cond = {"T_ambient_C": np.array([-40.0, 20.0, 80.0])}
    rows = S.compare("fits", "bonded", S.margins_of(asm, cond, Pipeline.shared(asm)),
                     S.margins_of(alt_asm, cond, Pipeline.shared(alt_asm)))
    by = {r.margin: r for r in rows}
    lost = [bearingfem.simulate(a, cond)["flag_preload_lost"].to_numpy() for a in (asm, alt_asm)]
    assert not lost[0].any() and lost[1].any()
    assert by["preload_min_N"].flips and by["preload_min_N"].status == "PASS"
    assert by["preload_min_N"].status_alternative.startswith("FAIL")
    assert [r.margin for r in S.order(rows)][0] == "preload_min_N"


def test_a_materials_table_and_the_reference_temperature_are_numbers_too():
    """The cartridge rig tags its superduplex's CTE and T_ref_C [assume]: the CTE gets +10 % in
    the assembly's material (every part of that material), T_ref_C +5 K (no relative step in C)."""
    path = CONFIG_DIR / "rig_cartridge_sleeve.toml"
    asm = load_assembly(path)
    alts = {a.assumption: a for a in S.alternatives(asm, path, long=True)[0]}
    cte = alts["[materials.SAF2507] cte_per_K = 1.3e-05 [assume]"]
    mat = next(m for m in cte.asm.materials if m.name == "SAF2507")
    assert mat.alpha_per_K == pytest.approx(1.43e-5, rel=1e-12)
    assert cte.asm.material("cartridge").alpha_per_K == mat.alpha_per_K
    assert alts["[assembly] T_ref_C = 20 [assume]"].asm.T_ref_C == 25.0
