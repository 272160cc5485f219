"""Requirement (issue 42, the predictive interval's coverage): the confusion-matrix study prints
the 90 % interval's coverage per second-source case and over all draws
(`confusion_matrix.interval_coverage_markdown`, the table of docs/diagnosis.md "An interval
for every verdict"), so the measurement is one command
(`python -m studies.validation.confusion_matrix --part second ...`).

Fast: trials made by hand, the expected numbers counted by hand from them."""
from __future__ import annotations

from studies.validation.confusion_matrix import SecondTrial, interval_coverage_markdown


def _trial(case: str, seed: int, verdict: str, inside: int | None, entries: int | None,
           heldout: float | None) -> SecondTrial:
    return SecondTrial(case, "noise", "cycles", "none", seed, 0.0, verdict, None, [], None,
                       "right", 1.0, inside, entries, heldout)


def test_the_table_gives_each_draw_and_the_totals():
    trials = [_trial("a", 1, "no_discrepancy", 95, 100, 0.90),
              _trial("a", 0, "no_discrepancy", 80, 100, 0.80),
              _trial("b", 0, "unexplained", 180, 200, 0.95),
              _trial("c", 0, "no_discrepancy", None, None, None)]     # no interval: left out
    rows = interval_coverage_markdown(trials)
    # per draw in seed order: a's seed 0 (80 of 100) before its seed 1 (95 of 100)
    assert rows[2] == "| `a` | `no_discrepancy` x 2 | 80.0, 95.0 % | 80.0, 90.0 % |"
    assert rows[3] == "| `b` | `unexplained` x 1 | 90.0 % | 95.0 % |"
    # all draws: (80 + 95 + 180) / 400 = 88.75 %; held-out mean (0.80 + 0.90 + 0.95) / 3
    assert rows[4] == ("| all 3 draws | | 88.8 % (355 of 400; 80.0 to 95.0 %) | 88.3 % "
                       "(mean; 80.0 to 95.0 %) |")
    assert not any("`c`" in r for r in rows)


def test_no_interval_no_table():
    assert interval_coverage_markdown([_trial("c", 0, "no_discrepancy", None, None, None)]) == []
