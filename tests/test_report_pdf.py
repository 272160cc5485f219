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


def test_pdf_first_page_holds_the_margin_table(reports):
    from pypdf import PdfReader

    _, runs = reports
    pages = PdfReader(runs[0] / "report.pdf").pages
    first = pages[0].extract_text()
    assert "Margins" in first and "peak contact pressure" in first and "PASS" in first
    text = "".join(p.extract_text() for p in pages)
    for section in ("Credibility", "Environment", "Reproduce", "Assumptions"):
        assert section in text, section


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
