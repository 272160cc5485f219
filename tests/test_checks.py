"""Checks in every run: `simulate` writes flag and margin columns for the assembly's limits and
the built-in checks, one stderr line per violated check, and exits 1 with --strict."""
import csv

import numpy as np
import pytest

from studies.app.cli import main
from studies.model.config import CONFIG_DIR

CFG000 = CONFIG_DIR / "seed000_71807C_TC4.toml"
CFG001 = CONFIG_DIR / "seed001_flywheel_hybrid.toml"


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def with_limit(tmp_path, p_max):
    text = CFG000.read_text()
    start = text.index("[limits]")
    end = text.find("\n[", start + 1)
    end = len(text) if end < 0 else end
    path = tmp_path / "asm.toml"
    path.write_text(text[:start] + f"[limits]\nmax_contact_pressure_MPa = {p_max!r}\n" + text[end:])
    return path


def test_contact_pressure_limit_flags_margins_summary_and_strict(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C,preload_assembled_N\n20,50\n20,200\n20,350\n")
    ref = tmp_path / "ref.csv"
    assert main(["simulate", str(CFG000), str(cond), "-o", str(ref)]) == 0
    p = read(ref)["max_contact_pressure_MPa"]
    limit = float(0.5 * (p[0] + p[1]))                  # between the first two rows
    asm = with_limit(tmp_path, limit)
    capsys.readouterr()
    out = tmp_path / "o.csv"
    assert main(["simulate", str(asm), str(cond), "-o", str(out)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    t = read(out)
    np.testing.assert_array_equal(t["flag_max_contact_pressure_MPa"], (p > limit).astype(float))
    # margin = limit/p - 1 from values the CSV keeps to 10 digits: round-off relative to the
    # terms (limit/p and 1), not to their difference
    np.testing.assert_allclose(t["margin_max_contact_pressure_MPa"], limit / p - 1, rtol=0,
                               atol=1e-9 * np.max(limit / p))
    assert len(err) == 1 and "2 of 3 rows violate max_contact_pressure_MPa" in err[0], err
    assert "at row 3" in err[0] and "[limits] max_contact_pressure_MPa" in err[0]
    assert main(["simulate", str(asm), str(cond), "-o", str(out), "--strict"]) == 1
    assert out.exists()                                  # the results are written all the same


def test_preload_lost_is_flagged_and_a_designed_clearance_is_not(tmp_path, capsys):
    # seed 001: position preload 7 N in a hybrid pair, lost when hot; seed 000's outer fit is a
    # designed clearance (-1.5 um): no fit_open_outer check for it
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n-20\n20\n60\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", str(CFG001), str(cond), "-o", str(out)]) == 0
    t = read(out)
    np.testing.assert_array_equal(t["flag_preload_lost"], (t["preload_N"] <= 0).astype(float))
    assert t["flag_preload_lost"][2] == 1.0 and t["flag_preload_lost"][1] == 0.0
    assert "rows violate preload_lost" in capsys.readouterr().err
    out0 = tmp_path / "o0.csv"
    assert main(["simulate", str(CFG000), str(cond), "-o", str(out0)]) == 0
    t0 = read(out0)
    assert "flag_fit_open_inner" in t0 and "flag_fit_open_outer" not in t0
    # the fit's margin in MPa: the pressure left before it opens, where it is checked only
    np.testing.assert_array_equal(t0["margin_fit_inner_MPa"], t0["fit_pressure_inner_MPa"])
    np.testing.assert_array_equal(t0["flag_fit_open_inner"], (t0["margin_fit_inner_MPa"] <= 0))
    assert "margin_fit_outer_MPa" not in t0


def test_diagnose_reads_simulate_output_with_its_check_columns(tmp_path, capsys):
    from studies.diagnosis.files import OUTPUT_NAMES
    from studies.model.checks import CHECK_COLUMNS, assembly_checks
    from studies.model.config import load_assembly

    for cfg in (CFG000, CFG001):
        for c in assembly_checks(load_assembly(cfg)):
            assert f"flag_{c.name}" in CHECK_COLUMNS and f"flag_{c.name}" in OUTPUT_NAMES
            assert c.strict or f"margin_{c.name}" in OUTPUT_NAMES
            assert not c.margin_column or c.margin_column in CHECK_COLUMNS & OUTPUT_NAMES


def test_limit_behaviour_of_every_check():
    """At the limit: a contact pressure equal to its limit and a static safety equal to the
    required one pass; a preload or fit pressure of exactly 0 is lost / open."""
    from operator import itemgetter

    from studies.model.checks import Check, evaluate_checks

    checks = [Check("max_contact_pressure_MPa", "p", 1500.0, True, "MPa", "test", itemgetter("p")),
              Check("static_safety", "s", 3.0, False, "", "test", itemgetter("s")),
              Check("preload_lost", "P", 0.0, False, "N", "test", itemgetter("P"), strict=True),
              Check("fit_open_inner", "f", 0.0, False, "MPa", "test", itemgetter("f"), strict=True)]
    out = {"p": np.array([1200.0, 1500.0, 1600.0]), "s": np.array([3.0, 2.99, 4.0]),
           "P": np.array([120.0, 0.0, 1e-9]), "f": np.array([0.0, 2.0, 0.5])}
    res = evaluate_checks(out, checks)
    viol = res.violations()
    cols = {f"flag_{o.check.name}": o.violated.astype(float) for o in res.outcomes}
    cols.update({f"margin_{o.check.name}": o.margin for o in res.outcomes if o.margin is not None})
    assert cols["flag_max_contact_pressure_MPa"].tolist() == [0, 0, 1]
    assert cols["flag_static_safety"].tolist() == [0, 1, 0]
    assert cols["flag_preload_lost"].tolist() == [0, 1, 0]
    assert cols["flag_fit_open_inner"].tolist() == [1, 0, 0]
    np.testing.assert_allclose(cols["margin_static_safety"], [0.0, 2.99 / 3 - 1, 4 / 3 - 1], rtol=1e-15)
    assert {v.check.name: v.worst_row for v in viol} == {
        "max_contact_pressure_MPa": 2, "static_safety": 1, "preload_lost": 1, "fit_open_inner": 0}


def _edit(tmp_path, section, key, value):
    import re
    text = CFG000.read_text()
    start = text.index(f"[{section}]")
    end = text.find("\n[", start + 1)
    body = re.sub(rf"(?m)^{key}\s*=\s*[^#\n]*", f"{key} = {value} ", text[start:end], count=1)
    path = tmp_path / "asm.toml"
    path.write_text(text[:start] + body + text[end:])
    return path


@pytest.mark.parametrize("section,key,value,conditions,fragment", [
    ("bearing", "contact_angle_free_deg", "0.26", "T_ambient_C\n20\n", "looks like radians"),
    ("fits", "inner_interference_um", "0.003", "T_ambient_C\n20\n", "looks like millimetres"),
    (None, None, None, "T_ambient_C\n233\n293\n", "kelvin typed as Celsius"),
])
def test_implausible_but_legal_input_gives_one_warning_line(tmp_path, capsys, section, key, value,
                                                             conditions, fragment):
    asm = _edit(tmp_path, section, key, value) if section else CFG000
    cond = tmp_path / "c.csv"
    cond.write_text(conditions)
    assert main(["simulate", str(asm), str(cond), "-o", str(tmp_path / "o.csv")]) == 0
    err = [l for l in capsys.readouterr().err.splitlines() if fragment in l]
    assert len(err) == 1 and err[0].startswith("bearingfem simulate: warning:"), err


def test_an_oil_bath_f0_on_a_lightly_lubricated_pair_is_questioned(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n-20\n20\n")
    assert main(["simulate", str(CFG001), str(cond), "-o", str(tmp_path / "o.csv")]) == 0
    assert "is an oil-bath value" in capsys.readouterr().err


def test_land_angle_agrees_with_the_ball_geometry():
    # independent statement: unloaded at the free contact angle, the ball (radius Dw/2 about the
    # pitch circle) touches each groove at r = dm/2 -+ (Dw/2) cos(alpha0); a land placed at that
    # diameter ends the groove exactly at alpha0, and a land at the groove bottom at 0 deg
    from analytic.bearing.geometry import BearingGeometry
    from analytic.bearing.land import groove_bottom_diameter_mm, land_angle_deg
    from analytic.catalogue import get_entry

    for name in ("NSK 71807C", "NSK 25TAC62B"):
        g = BearingGeometry.from_spec(get_entry(name).spec)
        c = np.cos(np.radians(g.alpha0_deg))
        for side, sign in (("inner", -1.0), ("outer", 1.0)):
            d_contact = g.dm_mm + sign * g.Dw_mm * c
            assert land_angle_deg(g, side, d_contact) == pytest.approx(g.alpha0_deg, abs=1e-9)
            # arccos(1 - e) = sqrt(2 e): a few ulp of round-off in the cosine (e <= 8 eps) show
            # as sqrt(16 eps) rad
            assert land_angle_deg(g, side, groove_bottom_diameter_mm(g, side)) == \
                pytest.approx(0.0, abs=np.degrees(np.sqrt(16 * np.finfo(float).eps)))


def _with_land(tmp_path, d_inner):
    text = CFG000.read_text().replace("[bearing]\n", f"[bearing]\ninner_land_diameter_mm = {d_inner}\n"
                                      "outer_land_diameter_mm = 43.4\n", 1)
    path = tmp_path / "asm.toml"
    path.write_text(text)
    return path


def test_a_low_land_truncates_the_contact_ellipse_and_says_so(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n60\n")
    # seed 000 (71807C, dm 41, Dw 3.969, f_i 0.52): inner groove bottom 37.03 mm; a land at
    # 37.2 mm ends the groove about 17 deg from the bottom, inside a 15 deg contact's ellipse
    out = tmp_path / "o.csv"
    assert main(["simulate", str(_with_land(tmp_path, 37.2)), str(cond), "-o", str(out)]) == 0
    err = [l for l in capsys.readouterr().err.splitlines() if "truncated by the land" in l]
    assert len(err) == 1 and err[0].startswith("bearingfem simulate: warning: inner"), err
    assert "inferred" not in err[0]             # the land was given
    assert np.all(read(out)["land_margin_inner_deg"] < 0)
    # the shipped land (inferred, about 51 deg) leaves a wide margin and no warning
    assert main(["simulate", str(CFG000), str(cond), "-o", str(out)]) == 0
    assert "truncated" not in capsys.readouterr().err
    assert np.all(read(out)["land_margin_inner_deg"] > 20)


def test_a_truncation_at_an_inferred_land_asks_for_the_land_diameter(tmp_path, capsys):
    """Seed 003 (60 deg contact) states no land diameters; the land inferred from its effective
    ring sections ends the groove at about 53 deg, below the contact angle itself: the warning
    says the land was inferred and names the key that states it."""
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", str(CONFIG_DIR / "seed003_25TAC62B.toml"), str(cond), "-o", str(out)]) == 0
    err = [l for l in capsys.readouterr().err.splitlines() if "truncated by the land" in l]
    assert len(err) == 2 and all("inferred" in l for l in err), err
    assert "[bearing] inner_land_diameter_mm" in err[0] and "outer_land_diameter_mm" in err[1]


def test_a_land_outside_the_groove_is_refused(tmp_path, capsys):
    cond = tmp_path / "c.csv"
    cond.write_text("T_ambient_C\n20\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", str(_with_land(tmp_path, 42.0)), str(cond), "-o", str(out)]) == 2
    assert not out.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bearing.inner_land_diameter_mm" in err[0] and "pitch" in err[0]
