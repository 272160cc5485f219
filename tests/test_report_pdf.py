"""`bearingfem report ... --pdf`: the margin table opens the report and its numbers are those of
results.csv (recomputed here from the CSV and the assembly's limits, not by the report's code),
PASS/FAIL follows the flag columns, report.pdf's first page holds the margin table, and the
command reproduces the report byte for byte (SOURCE_DATE_EPOCH fixing the date; without it
the date line is the time of the run)."""
import csv
import re

from types import SimpleNamespace

import numpy as np
import pytest

from studies.app.cli import main
from studies.model.checks import assembly_checks, evaluate_checks
from studies.model.columns import check_columns
from studies.model.config import CONFIG_DIR, load_assembly

TEMPLATE = CONFIG_DIR / "template.toml"
#: the template on the coarsest mesh the sizing rule allows (target 1 %): a cheap run
COARSE = (TEMPLATE.read_text().replace("target_error = 0.001 ", "target_error = 0.01  ")
          .replace('inner_shaft_class = ""  ', 'inner_shaft_class = "k5"')
          .replace('outer_housing_class = ""  ', 'outer_housing_class = "J6"'))


def _margins(md: str) -> dict[str, dict[str, str]]:
    """The margin table of report.md by item (the first word(s) before any parenthesis)."""
    lines = md.splitlines()
    i = lines.index("## Margins")
    start = next(k for k in range(i, len(lines)) if lines[k].startswith("| item |"))
    head = [c.strip() for c in lines[start].strip("|").split("|")]
    rows = {}
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        r = dict(zip(head, (c.strip() for c in line.strip("|").split("|"))))
        rows[r["item"].split(" (")[0]] = r
    return rows


def _numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?", text)]


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The same command twice, SOURCE_DATE_EPOCH fixing the date."""
    d = tmp_path_factory.mktemp("pdf")
    asm_path, cond_path = d / "pair.toml", d / "cond.csv"
    asm_path.write_text(COARSE)
    cond_path.write_text("T_ambient_C\n-40\n-10\n20\n50\n80\n")
    out = d / "report"
    runs = []
    mp = pytest.MonkeyPatch()
    mp.setenv("SOURCE_DATE_EPOCH", "1700000000")
    for _ in range(2):
        assert main(["report", str(asm_path), str(cond_path), "--out", str(out), "--pdf"]) == 0
        runs.append(out.rename(d / f"run{len(runs)}"))
    mp.undo()
    return asm_path, runs


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_margin_table_is_the_csv_and_the_checks(reports):
    asm_path, runs = reports
    asm = load_assembly(asm_path)
    md = (runs[0] / "report.md").read_text()
    assert md.index("## Margins") < md.index("## Inputs and their sources") < \
        md.index("## Assumptions") < md.index("## Credibility") < md.index("## Environment") < \
        md.index("## Reproduce")
    with open(runs[0] / "results.csv", newline="") as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    col = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    m = _margins(md)
    rel = 5e-4                       # the table prints 4 significant digits
    # preload band: min .. max of the CSV's preload column
    lo, hi = _numbers(m["preload band"]["over the operating range"])[:2]
    assert lo == pytest.approx(col["preload_N"].min(), rel=rel)
    assert hi == pytest.approx(col["preload_N"].max(), rel=rel)
    # peak contact pressure against the assembly's [limits] value (2500 MPa in the template):
    # margin = allowable / actual - 1 at the largest pressure
    p = col["max_contact_pressure_MPa"].max()
    row = m["peak contact pressure"]
    assert _numbers(row["over the operating range"])[0] == pytest.approx(p, rel=rel)
    assert _numbers(row["allowable"])[0] == asm.limits.max_contact_pressure_MPa == 2500.0
    assert _numbers(row["margin"])[0] == pytest.approx(2500.0 / p - 1.0, abs=1e-3)
    # static safety: the smallest s0 against [limits] min_static_safety (2): s0 / 2 - 1
    s0 = col["static_safety"].min()
    row = m["static safety s0"]
    assert _numbers(row["over the operating range"])[0] == pytest.approx(s0, rel=rel)
    assert _numbers(row["margin"])[0] == pytest.approx(s0 / 2.0 - 1.0, abs=1e-3)
    # fits: range of the pressure, open/closed from it, the smallest pressure as the margin
    for fit in ("inner", "outer"):
        pf = col[f"fit_pressure_{fit}_MPa"]
        key = f"{fit} fit"
        r = m[key]
        assert _numbers(r["over the operating range"])[:2] == pytest.approx(
            [pf.min(), pf.max()], rel=rel, abs=1e-9)
        n_open = int(np.sum(pf <= 0))
        assert (n_open == 0) == ("closed" in next(line for line in md.splitlines()
                                                  if line.startswith(f"| {key} (")))
    assert _numbers(m["friction torque"]["over the operating range"])[:2] == pytest.approx(
        [col["torque_Nmm"].min(), col["torque_Nmm"].max()], rel=rel)
    # PASS/FAIL: the flag columns of the CSV
    for item, flag in (("preload band", "flag_preload_lost"),
                       ("peak contact pressure", "flag_max_contact_pressure_MPa"),
                       ("static safety s0", "flag_static_safety")):
        assert m[item]["PASS/FAIL"].startswith("PASS" if col[flag].sum() == 0 else "FAIL"), item
    assert m["inner fit"]["PASS/FAIL"].startswith(
        "PASS" if col["flag_fit_open_inner"].sum() == 0 else "FAIL")
    # every headline number carries its mesh error
    for item in ("preload band", "peak contact pressure", "static safety s0", "friction torque"):
        assert m[item]["mesh error"].endswith("%"), item


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_tolerance_worst_case_brackets_the_mid_band_result(reports):
    """The assembly has ISO classes (k5 shaft, J6 housing): the report gives the worst case of
    the interference bands, and the mid-band preload and fit pressures of results.csv lie within
    it (each grows monotonically with its fit's interference, so the band's corners bound it)."""
    asm_path, runs = reports
    asm = load_assembly(asm_path)
    assert (asm.fits.inner_shaft_class, asm.fits.outer_housing_class) == ("k5", "J6")
    md = (runs[0] / "report.md").read_text()
    with open(runs[0] / "results.csv", newline="") as f:
        rows = list(csv.DictReader(r for r in f if not r.startswith("#")))
    lines = md.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("| quantity | mid-band"))
    for line in lines[i + 2:i + 7]:
        q, _, lo, hi = (c.strip() for c in line.strip("|").split("|"))
        v = np.array([float(r[q]) for r in rows])
        assert float(lo) <= v.min() * (1 + 5e-4) + 1e-9 and v.max() * (1 - 5e-4) - 1e-9 <= float(hi), q
        if q == "preload_N":
            assert float(hi) - float(lo) > v.max() - v.min()      # the tolerances widen the band


def test_a_violated_check_is_a_fail_with_its_count():
    """A contact pressure above the allowable in 2 of 3 rows: FAIL (2 of 3), and the margin is
    allowable / actual - 1 at the worst row."""
    from studies.usecases.report_margins import margin_rows

    asm = load_assembly(TEMPLATE)
    res = {"preload_N": np.array([50.0, 80.0, 120.0]),
           "max_contact_pressure_MPa": np.array([2000.0, 2600.0, 3000.0]),
           "fit_pressure_inner_MPa": np.array([3.0, 0.0, 1.0]),
           "fit_pressure_outer_MPa": np.array([0.0, 0.0, 2.0]),
           "static_safety": np.array([5.0, 1.5, 1.0]), "torque_Nmm": np.array([1.0, 2.0, 3.0])}
    # what the checks read of a result (`studies.model.checks`), from these columns
    quantities = SimpleNamespace(
        pair=SimpleNamespace(max_contact_pressure_MPa=res["max_contact_pressure_MPa"],
                             preload_N=res["preload_N"]),
        summary=SimpleNamespace(static_safety=res["static_safety"]),
        fits=SimpleNamespace(inner_MPa=res["fit_pressure_inner_MPa"],
                             outer_MPa=res["fit_pressure_outer_MPa"]))
    flags = check_columns(evaluate_checks(quantities, assembly_checks(asm)))
    rows = {r.item.split(" (")[0]: r for r in margin_rows(asm, res, flags, {})}
    assert rows["peak contact pressure"].status == "FAIL (2 of 3)"
    assert _numbers(rows["peak contact pressure"].margin_text)[0] == pytest.approx(
        2500.0 / 3000.0 - 1.0, abs=1e-3)
    assert rows["static safety s0"].status == "FAIL (2 of 3)"
    assert rows["inner fit"].status == "FAIL (1 of 3)" and "open in 1 of 3" in rows["inner fit"].item
    assert rows["preload band"].status == "PASS"


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_pdf_first_page_holds_the_margin_table(reports):
    from pypdf import PdfReader

    _, runs = reports
    pages = PdfReader(runs[0] / "report.pdf").pages
    first = pages[0].extract_text()
    assert "Margins" in first and "peak contact pressure" in first and "PASS" in first
    text = "".join(p.extract_text() for p in pages)
    for section in ("Credibility", "Environment", "Reproduce", "Assumptions"):
        assert section in text, section


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
def test_the_command_reproduces_the_report(reports):
    """Same date (SOURCE_DATE_EPOCH): report.md, report.html and report.pdf byte-identical."""
    _, runs = reports
    for name in ("report.md", "report.html", "report.pdf"):
        assert (runs[0] / name).read_bytes() == (runs[1] / name).read_bytes(), name
    md = (runs[0] / "report.md").read_text()
    assert "Date: 2023-11-14 22:13 UTC" in md              # 1700000000 s after 1970, UTC
    assert "`bearingfem report " in md and "--pdf`" in md


def test_the_date_is_now_without_source_date_epoch(monkeypatch):
    """Without SOURCE_DATE_EPOCH the date line is the time of the run (the only line that
    changes between runs)."""
    from datetime import datetime, timezone

    from studies.usecases.report_margins import report_date

    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    before = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    got = report_date()
    after = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    assert got in (before, after)


def test_margins_name_the_governing_condition_and_the_thermal_speed():
    """A governing point is named by its condition (the row's
    temperature and speed, not the row number alone), and each bearing has a thermal speed row
    whose margin is DIN 732's permissible speed minus the speed at the governing row: there the
    standard's friction torque (f1 P1 dm + 1e-7 f0 (nu n)^(2/3) dm^3 with f1 = 0.001 (P1/C0)^0.33,
    P1 = F_a, C0 of ISO 76 and nu at the permissible temperature 70 C, written out here) times
    omega equals k_q pi B (D + d) (70 - 20) with k_q = 16e-3/50 W/(mm^2 K) (the default)."""
    from math import pi

    from analytic.safety import static_load_rating_C0_N
    from studies.usecases.report_margins import margin_rows

    asm = load_assembly(TEMPLATE)
    res = {"preload_N": np.array([50.0, 80.0, 120.0]),
           "max_contact_pressure_MPa": np.array([2000.0, 2100.0, 2200.0]),
           "fit_pressure_inner_MPa": np.array([3.0, 2.0, 1.0]),
           "fit_pressure_outer_MPa": np.array([1.0, 1.0, 2.0]),
           "static_safety": np.array([5.0, 4.0, 3.0]), "torque_Nmm": np.array([1.0, 2.0, 3.0]),
           "axial_force_A_N": np.array([50.0, 80.0, 120.0]),
           "axial_force_B_N": np.array([50.0, 80.0, 120.0])}
    cond = {"T_ambient_C": np.array([-20.0, 20.0, 60.0]),
            "speed_rpm": np.array([1000.0, 2000.0, 3000.0])}
    quantities = SimpleNamespace(
        pair=SimpleNamespace(max_contact_pressure_MPa=res["max_contact_pressure_MPa"],
                             preload_N=res["preload_N"]),
        summary=SimpleNamespace(static_safety=res["static_safety"]),
        fits=SimpleNamespace(inner_MPa=res["fit_pressure_inner_MPa"],
                             outer_MPa=res["fit_pressure_outer_MPa"]))
    flags = check_columns(evaluate_checks(quantities, assembly_checks(asm)))
    rows = {r.item: r for r in margin_rows(asm, res, flags, {}, cond)}
    assert "row 3: T_ambient_C = 60, speed_rpm = 3000" in rows["static safety s0"].margin_text
    assert "row 1: T_ambient_C = -20" in rows["preload band"].margin_text
    r = rows["thermal speed, bearing A"]
    margin, = _numbers(r.margin_text.split(" (")[0])
    i = int(re.search(r"row (\d)", r.margin_text).group(1)) - 1
    b, lub = asm.bearing, asm.lubrication
    dm = 0.5 * (b.bore_mm + b.outside_diameter_mm)
    n = margin + cond["speed_rpm"][i]
    nu = float(asm.oil().nu_mm2_s(70.0))
    P1 = res["axial_force_A_N"][i]
    C0 = static_load_rating_C0_N(b.ball_count, b.ball_diameter_mm, b.pitch_diameter_mm,
                                 b.contact_angle_free_deg)
    M = (0.001 * (P1 / C0) ** 0.33 * P1 * dm
         + 1e-7 * lub.viscous_factor_f0 * (nu * n) ** (2 / 3) * dm ** 3)
    Q = 16e-3 / 50.0 * pi * b.width_mm * (b.outside_diameter_mm + b.bore_mm) * 50.0
    # the margin text carries 4 significant digits: n to +-0.05 %, the power (~ n^(5/3)) to 0.1 %
    assert M * n * pi / 30e3 == pytest.approx(Q, rel=1e-3)
    assert "ISO 15312" in r.value_text and "defaults" in r.source


def test_margins_hold_the_land_and_the_preload_upper_limit():
    """The Margins table has the contact ellipse's land margin (inner and outer,
    FAIL where it is negative: the ellipse truncated) and the preload's upper limit, the static
    load rating C0 of ISO 76 (`analytic.safety`, tested against ISO 76 in tests/test_safety.py),
    with margin C0 / max preload - 1 at the hottest row here."""
    from analytic.safety import static_load_rating_C0_N
    from studies.usecases.report_margins import margin_rows

    asm = load_assembly(TEMPLATE)
    res = {"preload_N": np.array([50.0, 80.0, 120.0]),
           "max_contact_pressure_MPa": np.array([2000.0, 2100.0, 2200.0]),
           "fit_pressure_inner_MPa": np.array([3.0, 2.0, 1.0]),
           "fit_pressure_outer_MPa": np.array([1.0, 1.0, 2.0]),
           "static_safety": np.array([5.0, 4.0, 3.0]), "torque_Nmm": np.array([1.0, 2.0, 3.0]),
           "land_margin_inner_deg": np.array([3.0, 1.0, -0.5]),
           "land_margin_outer_deg": np.array([4.0, 3.0, 2.5])}
    cond = {"T_ambient_C": np.array([-20.0, 20.0, 60.0])}
    quantities = SimpleNamespace(
        pair=SimpleNamespace(max_contact_pressure_MPa=res["max_contact_pressure_MPa"],
                             preload_N=res["preload_N"]),
        summary=SimpleNamespace(static_safety=res["static_safety"]),
        fits=SimpleNamespace(inner_MPa=res["fit_pressure_inner_MPa"],
                             outer_MPa=res["fit_pressure_outer_MPa"]))
    flags = check_columns(evaluate_checks(quantities, assembly_checks(asm)))
    rows = {r.item.split(" (")[0]: r for r in margin_rows(asm, res, flags, {}, cond)}
    inner, outer = rows["inner land"], rows["outer land"]
    assert inner.status == "FAIL (1 of 3)" and "T_ambient_C = 60" in inner.margin_text
    assert _numbers(inner.margin_text)[0] == -0.5
    assert outer.status == "PASS" and _numbers(outer.margin_text)[0] == 2.5
    b = asm.bearing
    C0 = float(static_load_rating_C0_N(b.ball_count, b.ball_diameter_mm, b.pitch_diameter_mm,
                                       b.contact_angle_free_deg))
    up = rows["preload upper limit"]
    assert up.status == "PASS" and _numbers(up.allowable_text)[-1] == pytest.approx(C0, rel=1e-3)
    assert _numbers(up.margin_text)[0] == pytest.approx(C0 / 120.0 - 1.0, abs=1e-3)


def test_stress_colour_range_is_not_set_by_a_singular_corner():
    """A von Mises field of 0..100 MPa with a re-entrant corner's singular value
    (944 MPa in a few elements, 0.3 % of them) is drawn from its minimum to its 99th percentile
    (about 99 MPa: the section keeps its colours), the range marked clipped with the true
    maximum; a field without an outlier keeps (nearly) its full range."""
    from fem.fields import colour_range

    v = np.linspace(0.0, 100.0, 2000)
    v[:6] = [944.0, 700.0, 500.0, 400.0, 300.0, 250.0]
    r = colour_range(v)
    assert r.clipped and r.max_value == 944.0 and r.lo == pytest.approx(0.0, abs=0.5)
    assert 95.0 < r.hi <= 100.0
    full = colour_range(v, None)
    assert not full.clipped and full.hi == 944.0
    # a mesh graded into the corner: 300 tiny elements (0.1 % of the area) at 500..944 MPa would
    # be 13 % of the elements; weighted by area they stay out of the colour range
    w = np.concatenate([np.full(300, 1e-3 / 300 * 2000 / 0.999), np.ones(2000)])
    vv = np.concatenate([np.linspace(500.0, 944.0, 300), np.linspace(0.0, 100.0, 2000)])
    assert colour_range(vv).hi > 500.0                            # by count: the corner wins
    assert 95.0 < colour_range(vv, weights=w).hi <= 100.0         # by area: the section does


def test_wide_tables_split_so_no_header_breaks_inside_a_word():
    """The results table of a rig with three fits (15 columns) is wider than
    the page; the PDF draws it as column groups, each within the text width at the width its
    longest unbreakable piece needs (a header wraps only after an underscore or a space), the
    row label repeated, every column once."""
    from studies.usecases.report_pdf import TEXT_WIDTH_PT, column_groups, column_width_pt

    head = ["ambient temperature (C)", "preload_N", "contact_angle_deg", "torque_Nmm",
            "max_contact_pressure_MPa", "interference_inner_um", "fit_pressure_inner_MPa",
            "fit_pressure_inner_lame_MPa", "interference_outer_um", "fit_pressure_outer_MPa",
            "fit_pressure_outer_lame_MPa", "interference_sleeve_um", "fit_pressure_sleeve_MPa",
            "fit_pressure_sleeve_lame_MPa", "axial_stiffness_N_per_um"]
    rows = [head] + [["-45", "1.327e+04", "12.97", "3392", "2840", "-37.6", "0", "0", "96.96",
                      "4.842", "3.134", "-82.32", "0", "0", "385.2"]]
    w = [column_width_pt([r[j] for r in rows]) for j in range(len(head))]
    assert sum(w) > TEXT_WIDTH_PT                       # one table would not fit
    groups = column_groups(rows)
    assert len(groups) > 1 and all(g[0] == 0 for g in groups)
    assert sorted(j for g in groups for j in g[1:]) == list(range(1, len(head)))
    assert all(sum(w[j] for j in g) <= TEXT_WIDTH_PT for g in groups)
    # "interference_" (13 characters) needs about 13 x 0.58 x 6.5 pt + insets = 54 pt
    assert column_width_pt(["interference_inner_um"]) == pytest.approx(13 * 0.58 * 6.5 + 5.0)
