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

Writes `confusion_matrix.json` (every trial, the rates, the look-alike matrices),
`confusion_matrix.csv` (one row per trial) and `report.md` / `report.html`.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from studies.diagnosis.designs import cycles, speed_steps
from studies.diagnosis.operating import MAGNITUDES, Design, markdown, run_matrix
from studies.model.table import write_table

REPS = 3
N_NULL = 20
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


def run(out_dir: Path, progress=print, designs=tuple(DESIGNS), reps: int = REPS,
        n_null: int = N_NULL) -> dict:
    """Run the matrix and write the files (module docstring); returns the JSON dict."""
    from studies.runs.report_tools import write_report_files

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ds = [design(n) for n in designs]
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
    L = ["# Operating characteristics of the diagnosis (confusion matrix)\n",
         __doc__.split("\n\n", 1)[1].split("Writes")[0].strip() + "\n",
         "Noise sigma per design (column unit): " + "; ".join(
             f"{d.name}: " + ", ".join(f"{c} {s:.3g}" for c, s in d.sigma.items()) for d in ds)
         + ".\n",
         f"Magnitudes: {', '.join(f'{m:g}' for m in MAGNITUDES)} sigma (RMS visible change); "
         f"{reps} trials per cell, {n_null} nulls per design; {len(mx.trials)} diagnoses, "
         f"{np.mean(secs):.2f} s each on average.\n",
         "`named` = explained with the hidden cause or ambiguous with it among the rivals; "
         "`wrong` = explained with another cause.\n"]
    L += markdown(mx)
    write_report_files(out_dir, L, "confusion matrix")
    return data
