"""Study `confusion_matrix`: operating characteristics of `bearingfem diagnose` on the real model.

Two standard designs (`studies/diagnosis/designs.py`), each on a shipped assembly through the one
route (`Pipeline` behind `files.ModelPredictor`, the nuisance and assembly bounds of `diagnose`):

- `cycles`: seed 000 (MoS2 film, 71807C pair), alternating -60 <-> 80 C cycles, 240 rows x 120 s;
- `speed_steps`: seed 001 (oil, hybrid pair), chamber steps 0..60 C at 6000, 3000, 9000 rpm,
  240 rows x 120 s;
- `cycles_speeds`: seed 000 in the `cycles` programme with the speed held at 300, 60 and 600 rpm
  for a third of the rows each (revolutions then accumulate at different rates in time, so a
  run-in in revolutions and a drift in time differ): only the run-in, the unlisted drift and
  nulls are injected.

The candidates are exactly those of `bearingfem diagnose` on that assembly
(`files.candidate_effects`: assembly bounds and `Effect.for_assembly`), so e.g. the solid-film
run-in is a candidate on seed 000 (its configured speed gives the revolutions) and not on the
oil-lubricated seed 001.

Torque and preload are measured; the base noise of each column is 1 % of its mean baseline value
(a stated choice: a good rig's torque and load cells). Hidden causes: none (N_NULL trials per
design), every listed effect the design can identify (before-data screening), and an unlisted
torque-sensor drift, each at the magnitudes `operating.MAGNITUDES` (RMS visible change in noise
sigmas) with REPS trials. Method and rates: `studies.diagnosis.operating`.

Second source (`studies.validation.second_source`): beside the same-model matrix, the
same diagnosis on data made another way than the model it fits (finer mesh and direct FE, model
forms the config lacks, transient-FE and network temperatures, two causes, strongly correlated
noise, spikes, sensor drift and offsets), each trial judged against the case's truth label
(`second_source.judge`: right, named, partial, unexplained, missed, false_alarm, wrong).

Size. The default run is small enough for a loaded 2-core machine (`SMALL`: 1 trial per listed
cell, 6 nulls per design, the `cycles` and `speed_steps` designs, 2 trials per second-source case);
`python -m studies.validation.confusion_matrix --out DIR --full` runs the full rates (`FULL`).

Writes `confusion_matrix.json` (every trial, the rates, the look-alike matrices),
`confusion_matrix.csv` (one row per trial), `second_source.json` / `second_source.csv` (every
second-source trial) and `report.md` / `report.html`.
"""
from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from studies.diagnosis.designs import cycles, speed_steps
from studies.diagnosis.core import DEFAULT_THRESHOLDS
from studies.diagnosis.operating import (CLAIMS, MAGNITUDES, Design, markdown, run_matrix,
                                         stated_false_alarm_level)
from studies.model.table import write_table

REPS = 3
N_NULL = 20
#: run sizes: listed-cause trials per cell, nulls per design, same-model designs, mesh factor of
#: the diagnosed model, trials per second-source case
SMALL = {"reps": 1, "n_null": 6, "designs": ("cycles", "speed_steps"), "second_trials": 2,
         "mesh_factor": 1.0}
FULL = {"reps": REPS, "n_null": N_NULL, "designs": ("cycles", "speed_steps", "cycles_speeds"),
        "second_trials": 8, "mesh_factor": 1.0}
#: base noise: this share of the column's mean absolute baseline value
NOISE_SHARE = 0.01
COLUMNS = ("torque_Nmm", "preload_N")
DESIGNS = {"cycles": ("seed000", cycles), "speed_steps": ("seed001", speed_steps),
           "cycles_speeds": ("seed000", lambda: cycles(speeds_rpm=(300.0, 60.0, 600.0)))}
#: listed effects injected per design (None: every one the design can identify)
HIDDEN = {"cycles_speeds": ["solid_film_runin"]}


def setup(name: str):
    """(assembly, conditions, candidates) of a design, the candidates exactly as `diagnose`
    builds them (`files.candidate_effects`); no model is built."""
    from studies.diagnosis.files import candidate_effects
    from studies.model.config import load_shipped

    key, make = DESIGNS[name]
    asm = load_shipped(key)
    return asm, make(), candidate_effects(asm)


def design(name: str) -> Design:
    """A standard design on its shipped assembly, with the candidates `diagnose` would try."""
    from studies.diagnosis.files import NUISANCE, ModelPredictor
    from studies.model.pipeline import Pipeline

    key = DESIGNS[name][0]
    asm, cond, cands = setup(name)
    pl = Pipeline.shared(asm, progress=lambda s: None)

    def predictor(c):
        p = ModelPredictor(pl, c, COLUMNS)
        return p, p.at
    base = predictor(cond)[0]({}, {"mu_scale": 1.0})
    sigma = {c: NOISE_SHARE * float(np.mean(np.abs(base[c]))) for c in COLUMNS}
    return Design(f"{name} ({key})", cond, predictor, cands, NUISANCE, sigma, asm.T_ref_C,
                  hidden=HIDDEN.get(name))


@dataclass
class SecondTrial:
    """One diagnosis of a second-source case (`second_source.Case`) and its outcome."""
    case: str
    kind: str
    design: str
    truth: str                # the truth labels joined by '+', 'none' for a null
    seed: int
    change_sigma: float       # largest visible change against the refitted baseline
    verdict: str
    cause: str | None
    indistinguishable: list[str]
    best_partial: str | None
    outcome: str              # second_source.OUTCOMES
    seconds: float
    #: the claimed model's 90 % predictive interval (`second_source.interval_coverage`): entries
    #: of a repeat draw inside and in all, and the held-out rows' share inside (None: no claim)
    interval_inside: int | None = None
    interval_entries: int | None = None
    interval_heldout: float | None = None


def second_trial(name: str, seed: int, mesh_factor: float, progress=print) -> SecondTrial:
    """One noise draw of a second-source case, diagnosed as `diagnose` does
    (`second_source.diagnose_case`) and judged against its truth."""
    from studies.validation import second_source as ss

    c = ss.make_case(name, seed, mesh_factor)
    t0 = time.perf_counter()
    r = ss.diagnose_case(c)
    secs = time.perf_counter() - t0
    cov = ss.interval_coverage(c, r)
    t = SecondTrial(name, c.kind, c.design, "+".join(c.truth) or "none", seed, c.change_sigma,
                    r.verdict, "+".join(ss.named_causes(r)) or None, list(r.indistinguishable),
                    r.best_partial.effect if r.best_partial else None, ss.judge_result(c, r),
                    secs, *(cov or (None, None)),
                    r.interval.coverage_heldout if r.interval is not None else None)
    progress(f"second source {name} #{seed}: {r.verdict} {r.cause} -> {t.outcome}")
    return t


def run_second_source(cases=None, trials: int = 2, mesh_factor: float = 1.0,
                      progress=print, workers: int = 1) -> list[SecondTrial]:
    """Every second-source case (default all of `second_source.CASES`) with `trials` noise draws
    (seeds 0..trials-1), on up to `workers` processes (`parallel_map`; results in case and seed
    order whatever the workers)."""
    from studies.model.parallel import parallel_map
    from studies.validation import second_source as ss

    items = [(name, seed) for name in (cases or list(ss.CASES)) for seed in range(trials)]
    return parallel_map(lambda it: second_trial(*it, mesh_factor, progress), items, workers)


#: stated levels (docs/diagnosis_rates.md): a cause claimed on a null (alpha_lr), any discrepancy
#: reported on a null (alpha_structure + alpha_lr, `operating.stated_false_alarm_level`)
CLAIM_LEVEL = DEFAULT_THRESHOLDS["alpha_lr"]
ALARM_LEVEL = stated_false_alarm_level()
#: the size of change (largest visible change, noise sigmas) from which a listed
#: cause must be named in 90 % of trials
LISTED_HIT_SIGMA = 5.0


def second_source_rates(trials: list[SecondTrial]) -> list[str]:
    """The stated rates on second-source trials, one sentence each: wrong causes
    over all trials (with the exact one-sided 95 % upper bound of the rate, Clopper & Pearson
    1934), claims and any discrepancy on the nulls against the binomial 99 % upper quantile at
    the stated levels (a count above it rejects the level at 1 %), and model-form truths
    explained by a right rung."""
    from scipy import stats

    n = len(trials)
    wrong = sum(t.outcome == "wrong" for t in trials)
    ub = float(stats.beta.ppf(0.95, wrong + 1, n - wrong)) if n else float("nan")
    nulls = [t for t in trials if t.truth == "none"]
    m = len(nulls)
    claims = sum(t.verdict in CLAIMS for t in nulls)
    alarms = sum(t.verdict != "no_discrepancy" for t in nulls)
    from studies.diagnosis.ladder import ladder
    from studies.model.effects import EFFECTS
    from studies.validation.second_source import CASES, design_assembly

    def claimable(design: str) -> set[str]:
        """Names a diagnosis of the design can claim: listed effects and tried rungs."""
        rungs = ladder(design_assembly(design))
        return set(EFFECTS) | {r.name for r in rungs if r.candidate is not None}

    listed = [t for t in trials if t.truth != "none" and t.change_sigma >= LISTED_HIT_SIGMA
              and all(x in EFFECTS for x in t.truth.split("+"))]
    hits = sum(t.outcome == "right" for t in listed)
    forms = [t for t in trials if t.kind == "model_form" and t.truth != "none"]
    # a truth beyond its candidate's bound (`CaseSpec.lead`) is nameable too: right when not
    # claimed and the candidate named in `at_bound`
    nameable = [t for t in forms if set(CASES[t.case].right) & claimable(t.design)
                or CASES[t.case].lead]
    form_right = sum(t.outcome == "right" and (t.verdict in ("explained", "explained_partly")
                                               or CASES[t.case].lead is not None)
                     for t in nameable)
    iv, inside, entries, per = interval_totals(trials)
    return [
        f"wrong causes: {wrong} of {n} trials (95 % upper bound of the rate {100 * ub:.1f} %)",
        f"nulls (nothing hidden, {m} trials): cause claimed {claims} (stated level "
        f"{100 * CLAIM_LEVEL:g} %: binomial 99 % upper quantile "
        f"{int(stats.binom.ppf(0.99, m, CLAIM_LEVEL))}), any discrepancy {alarms} (level "
        f"{100 * ALARM_LEVEL:g} %: quantile {int(stats.binom.ppf(0.99, m, ALARM_LEVEL))})",
        f"listed causes changing the data by {LISTED_HIT_SIGMA:g} sigma or more "
        f"({len(listed)} trials): every true cause named {hits} "
        f"({100 * hits / max(len(listed), 1):.0f} %)",
        f"model-form truths a candidate can name ({len(nameable)} trials): explained or "
        f"explained_partly by a right name, or beyond its candidate's bound and named in "
        f"at_bound, {form_right} "
        f"({100 * form_right / max(len(nameable), 1):.0f} %); the {len(forms) - len(nameable)} "
        "trials of truths no candidate names (" + ", ".join(
            f"`{c}`" for c in dict.fromkeys(t.case for t in forms if t not in nameable))
        + ") are right only when not claimed",
        f"90 % predictive interval ({len(iv)} trials with an interval): a "
        f"repeat draw of the truth inside {inside} of {entries} entries "
        f"({100 * inside / max(entries, 1):.1f} %; per trial "
        + (f"{100 * min(per):.0f}-{100 * max(per):.0f} %" if per else "-")
        + "); held-out rows inside "
        + (f"{100 * float(np.mean([t.interval_heldout for t in iv])):.1f} %" if iv else "-")
        + " (goal 85-95 %)"]


def interval_totals(trials: list[SecondTrial]) -> tuple[list[SecondTrial], int, int,
                                                          list[float]]:
    """The trials with a predictive interval (`SecondTrial.interval_entries`), their entries of a
    repeat draw inside and in all (summed) and each one's share inside."""
    iv = [t for t in trials if t.interval_entries]
    return (iv, sum(t.interval_inside for t in iv), sum(t.interval_entries for t in iv),
            [t.interval_inside / t.interval_entries for t in iv])


def interval_coverage_markdown(trials: list[SecondTrial]) -> list[str]:
    """The 90 % predictive interval's coverage per case (docs/diagnosis.md, "An interval for
    every verdict"): the verdicts, the share of a repeat draw's entries inside
    (`second_source.interval_coverage`) and of the held-out rows inside
    (`Intervals.coverage_heldout`, block cross-validation), per draw in seed order; then all
    draws: entries inside of all entries (and the range per draw), held-out rows inside on
    average (and the range). Trials without an interval are left out."""
    iv, inside, entries, per = interval_totals(trials)
    if not iv:
        return []
    L = ["| case | verdict (draws) | entries of a repeat draw inside, per draw | held-out rows "
         "inside (`coverage_heldout`), per draw |", "| --- | --- | --- | --- |"]
    for name in dict.fromkeys(t.case for t in iv):
        sub = sorted((t for t in iv if t.case == name), key=lambda t: t.seed)
        verdicts = Counter(t.verdict for t in sub)
        L.append(f"| `{name}` | " + ", ".join(f"`{v}` x {k}" for v, k in verdicts.items())
                 + " | " + ", ".join(f"{100 * t.interval_inside / t.interval_entries:.1f}"
                                     for t in sub)
                 + " % | " + ", ".join(f"{100 * t.interval_heldout:.1f}" for t in sub) + " % |")
    held = [t.interval_heldout for t in iv]
    L.append(f"| all {len(iv)} draws | | {100 * inside / entries:.1f} % ({inside} of {entries}; "
             f"{100 * min(per):.1f} to {100 * max(per):.1f} %) | {100 * float(np.mean(held)):.1f} "
             f"% (mean; {100 * min(held):.1f} to {100 * max(held):.1f} %) |")
    return L + [""]


#: the goal for two causes at once, each 5 sigma or more: both named in this share of
#: the trials or more, a wrong cause in none
TWO_CAUSE_GOAL = 0.8


def two_cause_rates(trials: list[SecondTrial]) -> list[str]:
    """The two-cause cases made another way (`second_source.PAIRS`): per case and over all,
    how often both causes are named (`right`), one (`partial`), a wrong one (`wrong`), or
    none (any other outcome); empty without such trials."""
    from studies.validation.second_source import PAIRS

    ts = [t for t in trials if t.case in PAIRS]
    if not ts:
        return []

    def line(label, sub):
        n = len(sub)
        c = Counter(t.outcome for t in sub)
        none = n - c["right"] - c["partial"] - c["wrong"]
        return (f"{label} ({n} trials): both named {c['right']} ({100 * c['right'] / n:.0f} %), "
                f"one {c['partial']}, a wrong one {c['wrong']}, none {none}")

    out = [line(f"two causes at once made another way, each 5 sigma or more (goal: both "
                f">= {100 * TWO_CAUSE_GOAL:.0f} %, wrong 0)", ts)]
    out += ["  " + line(f"`{name}`", [t for t in ts if t.case == name])
            for name in dict.fromkeys(t.case for t in ts)]
    return out


def second_source_markdown(trials: list[SecondTrial]) -> list[str]:
    """The second-source confusion matrices (one per design) and the outcome totals."""
    from studies.validation.second_source import OUTCOMES

    L = []
    tot = Counter(t.outcome for t in trials)
    L.append("Outcomes over all second-source trials: " + ", ".join(
        f"{o} {tot.get(o, 0)}" for o in OUTCOMES) + f" (of {len(trials)}).\n")
    L += [f"- {line}" for line in second_source_rates(trials) + two_cause_rates(trials)] + [""]
    cov = interval_coverage_markdown(trials)
    if cov:
        L += ["### The 90 % predictive interval per case\n"] + cov
    for dn in dict.fromkeys(t.design for t in trials):
        ts = [t for t in trials if t.design == dn]
        cols = sorted({(f"explained: {t.cause}" if t.verdict == "explained" else t.verdict)
                       for t in ts}, key=lambda c: (not c.startswith("no_"),
                                                    c.startswith("unexpl"), c))
        L.append(f"### Second source, design `{dn}` (rows: case and its truth, columns: verdict / "
                 "cause; counts)\n")
        L.append("| case | kind | truth | change sigma | " + " | ".join(cols)
                 + " | outcomes |")
        L.append("| --- | --- | --- | ---: |" + " --- |" * (len(cols) + 1))
        for name in dict.fromkeys(t.case for t in ts):
            sub = [t for t in ts if t.case == name]
            cnt = Counter(f"explained: {t.cause}" if t.verdict == "explained" else t.verdict
                          for t in sub)
            oc = Counter(t.outcome for t in sub)
            L.append(f"| `{name}` | {sub[0].kind} | {sub[0].truth} | {sub[0].change_sigma:.1f} | "
                     + " | ".join(str(cnt.get(c, "")) for c in cols) + " | "
                     + ", ".join(f"{o} {k}" for o, k in oc.items()) + " |")
        L.append("")
    return L


def run(out_dir: Path, progress=print, designs=None, reps: int | None = None,
        n_null: int | None = None, full: bool = False, parts=("same", "second"),
        second_trials: int | None = None, mesh_factor: float | None = None,
        cases: list[str] | None = None, workers: int = 1) -> dict:
    """Run the matrices and write the files (module docstring); returns the JSON dict of the
    same-model matrix (with the second-source trials under `second_source`). Sizes default to
    SMALL (FULL with `full`); `parts`: "same" (the same-model matrix), "second" (the second
    source) or both; `cases`: the second-source cases (default all)."""
    from studies.usecases.report_tools import write_report_files

    size = dict(FULL if full else SMALL)
    for k, v in (("designs", designs), ("reps", reps), ("n_null", n_null),
                 ("second_trials", second_trials), ("mesh_factor", mesh_factor)):
        if v is not None:
            size[k] = v
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    L = ["# Operating characteristics of the diagnosis (confusion matrix)\n",
         __doc__.split("\n\n", 1)[1].split("Writes")[0].strip() + "\n"]
    data: dict = {"size": {k: list(v) if isinstance(v, tuple) else v for k, v in size.items()}}
    if "same" in parts:
        data.update(_run_same(out_dir, progress, size, L))
    if "second" in parts:
        t0 = time.perf_counter()
        tr = run_second_source(cases, trials=size["second_trials"],
                               mesh_factor=size["mesh_factor"], progress=progress,
                               workers=workers)
        data["second_source"] = [asdict(t) for t in tr]
        (out_dir / "second_source.json").write_text(json.dumps(data["second_source"], indent=1))
        write_table(out_dir / "second_source.csv", {
            "case": np.array([t.case for t in tr], str), "kind": np.array([t.kind for t in tr], str),
            "design": np.array([t.design for t in tr], str),
            "truth": np.array([t.truth for t in tr], str),
            "seed": np.array([t.seed for t in tr], float),
            "change_sigma": np.array([t.change_sigma for t in tr], float),
            "verdict": np.array([t.verdict for t in tr], str),
            "cause": np.array([t.cause or "" for t in tr], str),
            "indistinguishable": np.array([";".join(t.indistinguishable) for t in tr], str),
            "best_partial": np.array([t.best_partial or "" for t in tr], str),
            "outcome": np.array([t.outcome for t in tr], str),
            "seconds": np.array([t.seconds for t in tr], float),
            "interval_coverage": np.array([t.interval_inside / t.interval_entries
                                           if t.interval_entries else np.nan for t in tr],
                                          float)})
        L.append(f"## Second source: {size['second_trials']} trials per case, diagnosed model on "
                 f"mesh factor {size['mesh_factor']:g}; {len(tr)} diagnoses, "
                 f"{np.mean([t.seconds for t in tr]):.1f} s each on average "
                 f"({time.perf_counter() - t0:.0f} s with the truths)\n")
        L += second_source_markdown(tr)
    write_report_files(out_dir, L, "confusion matrix")
    return data


def _run_same(out_dir: Path, progress, size: dict, L: list[str]) -> dict:
    """The same-model matrix (`operating.run_matrix`): its files and report lines."""
    ds = [design(n) for n in size["designs"]]
    reps, n_null = size["reps"], size["n_null"]
    t0 = time.perf_counter()
    mx = run_matrix(ds, MAGNITUDES, reps=reps, n_null=n_null, progress=progress)
    data = mx.to_json()
    data["noise_sigma"] = {d.name: d.sigma for d in ds}
    (out_dir / "confusion_matrix.json").write_text(json.dumps(data, indent=1))
    tr = mx.trials
    write_table(out_dir / "confusion_matrix.csv", {     # the one CSV dialect (as `simulate`)
        "design": np.array([t.design for t in tr], str),
        "hidden": np.array([t.hidden for t in tr], str),
        "magnitude_sigma": np.array([t.magnitude_sigma for t in tr], float),
        "rep": np.array([t.rep for t in tr], float), "verdict": np.array([t.verdict for t in tr], str),
        "cause": np.array([t.cause or "" for t in tr], str),
        "indistinguishable": np.array([";".join(t.indistinguishable) for t in tr], str),
        "open_world_lead": np.array([t.open_world_lead or "" for t in tr], str),
        "seconds": np.array([t.seconds for t in tr], float)})
    secs = [t.seconds for t in mx.trials]
    L += ["## Same model\n",
          "Noise sigma per design (column unit): " + "; ".join(
              f"{d.name}: " + ", ".join(f"{c} {s:.3g}" for c, s in d.sigma.items()) for d in ds)
          + ".\n",
          f"Magnitudes: {', '.join(f'{m:g}' for m in MAGNITUDES)} sigma (RMS visible change); "
          f"{reps} trials per cell, {n_null} nulls per design; {len(mx.trials)} diagnoses, "
          f"{np.mean(secs):.2f} s each on average ({time.perf_counter() - t0:.0f} s in all).\n",
          "`named` = explained with the hidden cause or ambiguous with it among the rivals; "
          "`wrong` = explained with another cause.\n"]
    L += markdown(mx)
    return data


def main(argv=None) -> int:
    """`python -m studies.validation.confusion_matrix --out DIR [--full] [--part same|second]
    [--mesh-factor F] [--trials N] [--cases A,B,...] [--workers N]`."""
    ap = argparse.ArgumentParser(prog="python -m studies.validation.confusion_matrix",
                                 description="confusion matrices of the diagnosis (module "
                                             "docstring): same model and second source")
    ap.add_argument("--out", required=True, type=Path)
    ap.add_argument("--full", action="store_true", help="the full rates (FULL), not SMALL")
    ap.add_argument("--part", choices=("same", "second"), action="append",
                    help="only this part (repeatable; default both)")
    ap.add_argument("--mesh-factor", type=float, default=None)
    ap.add_argument("--trials", type=int, default=None,
                    help="noise draws per second-source case (seeds 0..N-1)")
    ap.add_argument("--cases", default=None,
                    help="comma-separated second-source cases (default all)")
    ap.add_argument("--workers", type=int, default=1,
                    help="processes for the second-source trials (default 1)")
    a = ap.parse_args(argv)
    run(a.out, full=a.full, parts=tuple(a.part or ("same", "second")), mesh_factor=a.mesh_factor,
        second_trials=a.trials, cases=a.cases.split(",") if a.cases else None,
        workers=a.workers)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
