"""Benchmark of `bearingfem diagnose` (issue 5 and 11 performance goal: a 500-row dataset with
every candidate effect diagnosed in under 10 s on 2 cores). Prints, never asserts.

Run: `bearingfem bench --diagnose` or `.venv/bin/python -m studies.runs.bench_diagnose` (add
`--mesh-factor 2` for the coarser mesh of the tests, `--rows 240 500` for several sizes,
`--workers 1` for one process). Per dataset it also prints the model calls and the wall seconds of
each phase with the seconds spent in model calls (summed over the worker processes).

Dataset: seed 000 (the shipped `seed000_71807C_TC4.toml`, full mesh as the CLI builds it),
alternating -60 <-> 80 C cycles from 20 C (2 K/min ramps, one-hour dwells) sampled every 60 s,
500 rows (`--rows`), torque (sigma 0.02 N mm) and preload (sigma 0.5 N) measured, the rig's
friction coefficient 1.25 x the configured one. Datasets: no effect, a thermal lag (tau 300 s), a
preload settling (5 N beyond 50 K) and a solid-film run-in (-0.004 over 10 krev), because the
engine's work depends on how many candidates pass, and two generalised forms (per-part lag
300 s / 360 s, settling creeping 3 N/h), where the engine also fits the generalised forms of the
family (`studies.diagnosis.generalised`); the column `form` gives the extended form reported;
two model forms of the ladder (grooved ring sections, a housing lot 3 % above the library's CTE),
made through the ladder's own route (`ladder.FormRoute`). The candidates are the CLI's
(`files.candidate_effects` and the ladder's `ladder.candidates`, after them), and so are the worker processes
(`--workers`, default every CPU the process may use, `studies.model.parallel.parallel_map`).
Times: the FE set-up (mesh from the cache, unit solutions) once; per dataset the engine alone
(`diagnose_full`, what the goal is about) and the whole `diagnose_files` (reading the CSV, the
engine, JSON and the report with its plots), with the set-up pipeline passed in; wall seconds
and CPU seconds (this process and its workers: on a loaded machine the CPU seconds move less).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")   # as the CLI: small dense solves, no threads

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from studies.diagnosis.designs import cycles  # noqa: E402

N_ROWS = 500
SIGMA = {"torque_Nmm": 0.02, "preload_N": 0.5}
MU_TRUE = 1.25
DATASETS = {"no effect": {}, "thermal_lag tau_s=300": {"thermal_lag": {"tau_s": 300.0}},
            "preload_settling loss_N=5 threshold_K=50":
                {"preload_settling": {"loss_N": 5.0, "threshold_K": 50.0}},
            "solid_film_runin dmu=-0.004 runin_krev=10":
                {"solid_film_runin": {"dmu": -0.004, "runin_krev": 10.0}},
            # generalised forms (issue 11): the engine then also fits the family's forms
            "thermal_lag.per_part tau_s=300 tau_shaft_s=360":
                {"thermal_lag.per_part": {"tau_s": 300.0, "tau_shaft_s": 360.0}},
            "preload_settling.creep 5 N, 50 K, 3 N/h":
                {"preload_settling.creep": {"loss_N": 5.0, "threshold_K": 50.0,
                                            "creep_N_per_h": 3.0}},
            # model forms of the ladder (issue 23): the FE set-up rung and an inputs rung
            "ring_section_grooved (model form)": {"ring_section_grooved": {"share": 1.0}},
            "material_lot housing CTE x 1.03": {"material_lot": {"cte_factor_housing": 1.03}}}


def main(argv=None) -> None:
    from studies.model.config import CONFIG_DIR, SHIPPED, load_shipped
    from studies.diagnosis.files import (NUISANCE, ModelPredictor, candidate_effects,
                                         diagnose_files)
    from studies.diagnosis.engine import diagnose_full
    from studies.diagnosis.ladder import candidates as ladder_candidates
    from studies.diagnosis.result import to_json
    from studies.model.parallel import available_workers
    from studies.runs.bench_clock import Clock
    from studies.model.pipeline import Pipeline
    from studies.model.table import write_table

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mesh-factor", type=float, default=1.0)
    ap.add_argument("--rows", type=int, nargs="+", default=[N_ROWS])
    ap.add_argument("--workers", type=int, default=None,
                    help="worker processes of the engine (default: as the CLI, every CPU)")
    args = ap.parse_args(argv)
    workers = available_workers() if args.workers is None else args.workers

    asm = load_shipped("seed000")
    t0 = time.perf_counter()
    pl = Pipeline(asm, mesh_factor=args.mesh_factor)
    t_setup = time.perf_counter() - t0
    cands = candidate_effects(asm) + ladder_candidates(asm)      # as the CLI: the ladder last
    print(f"FE set-up (once per run of the CLI): {t_setup:.2f} s")
    for n_rows in args.rows:
        cond = cycles(n_rows, 60.0)
        print(f"diagnose benchmark: seed000, {n_rows} rows (cycles -60..80 C), columns "
              f"{', '.join(SIGMA)}, {len(cands)} candidates, mesh factor {args.mesh_factor:g} "
              f"({pl.ndofs} DOF), OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, "
              f"{os.cpu_count()} CPUs, {workers} worker process(es), load {os.getloadavg()[0]:.1f}")
        print(f"{'dataset':<42} {'verdict':<15} {'cause':<18} {'engine s':>8} {'CPU s':>6} "
              f"{'calls':>6} {'model s':>8} {'CLI s':>6} {'CPU s':>6}  form")
        rng = np.random.default_rng(0)
        for label, effects in DATASETS.items():
            truth = ModelPredictor(pl, cond, tuple(SIGMA))(effects, {"mu_scale": MU_TRUE})
            meas = {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in SIGMA.items()}
            pred = ModelPredictor(pl, cond, tuple(SIGMA))
            with Clock() as engine:
                out = diagnose_full(pred, meas, cond, cands, NUISANCE, T_ref_C=asm.T_ref_C,
                                    predict_at=pred.at, workers=workers)
            r = to_json(out)
            with tempfile.TemporaryDirectory() as tmp:
                csv = Path(tmp) / "measured.csv"
                write_table(csv, {**cond, **meas})
                with Clock() as cli:
                    diagnose_files(CONFIG_DIR / SHIPPED["seed000"], csv, Path(tmp),
                                   progress=lambda s: None, pipeline=pl, workers=workers)
            form = (r.get("extended_form") or {}).get("name", "-")
            print(f"{label:<42} {r['verdict']:<15} {str(r['cause']):<18} {engine.wall_s:8.2f} "
                  f"{engine.cpu_s:6.2f} {r['n_predict_calls']:6d} {r['seconds']['predict']:8.2f} "
                  f"{cli.wall_s:6.2f} {cli.cpu_s:6.2f}  {form}  (load {cli.load_after:.1f})")
            print(f"    model calls by phase: {r['predict_calls_by_phase']}")
            # with workers the model seconds are summed over the processes (may exceed the wall)
            print("    wall seconds by phase (model seconds, summed over the workers): " + ", ".join(
                f"{k} {v['total']:.2f} ({v['predict']:.2f})"
                for k, v in r["seconds_by_phase"].items() if v["total"] >= 0.005)
                + f"; total {r['seconds']['total']:.2f} s ({r['seconds']['predict']:.2f} s)")


if __name__ == "__main__":
    main()
