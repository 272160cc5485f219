"""docs/cli.md is the contract only (commands, keys, columns, JSON, exit codes, limits): the
measurements and their history live in docs/benchmarks.md (the latest per benchmark with the
command that reproduces it) and docs/diagnosis_rates.md."""
import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"

#: what a dated measurement diary looks like: a calendar date, a load before -> after, a
#: re-measurement, a wall-time table or a "measured <date/day>" note
DIARY = {
    "a date": re.compile(r"\b20\d\d-\d\d-\d\d\b"),
    "a load before -> after": re.compile(r"\bload (?:of )?[0-9.]+ ?(?:->|→)"),
    "a re-measurement": re.compile(r"\bre-measured\b", re.I),
    "a wall-time table": re.compile(r"\|\s*wall s\s*\|"),
    "a measured day": re.compile(r"\bmeasured (?:the same day|today|idle)\b", re.I),
}


def test_the_contract_holds_no_dated_measurement():
    text = (DOCS / "cli.md").read_text()
    found = [f"line {text.count(chr(10), 0, m.start()) + 1}: {what} ({m.group(0)!r})"
             for what, rx in DIARY.items() for m in rx.finditer(text)]
    assert not found, "docs/cli.md: measurements belong in docs/benchmarks.md: " + "; ".join(found)


def test_the_benchmarks_page_gives_each_benchmark_its_command():
    """Every `bench` mode the contract lists has a row in docs/benchmarks.md's latest table, with
    the command that reproduces it."""
    text = (DOCS / "benchmarks.md").read_text()
    latest = text[text.index("## Latest per benchmark"):text.index("\n## ", text.index("## Latest"))]
    for mode in ("--quick", "--tolerance", "--design", "--transient", "--diagnose", "--friction",
                 "--simulate"):
        assert f"`bearingfem bench {mode}" in latest, mode


def test_the_diary_patterns_find_a_diary():
    """The patterns that keep measurements out of docs/cli.md are not vacuous: each finds the
    kind of line a dated measurement diary has."""
    diary = {"a date": "2026-11-29", "a load before -> after": "at load 1.2 -> 1.35",
             "a re-measurement": "Re-measured on an idle machine",
             "a wall-time table": "| run | wall s | CPU s |",
             "a measured day": "measured the same day"}
    assert set(diary) == set(DIARY)
    assert all(DIARY[what].search(line) for what, line in diary.items())
