"""Benchmark of `bearingfem diagnose` (the performance goal: a 500-row dataset with
every candidate effect diagnosed in under 10 s on 2 cores). Prints, never asserts.

Run: `bearingfem bench --diagnose` or `.venv/bin/python -m studies.bench.bench_diagnose` (add
`--mesh-factor 2` for the coarser mesh of the tests, `--rows 240 500` for several sizes,
`--workers 1` for one process). Per dataset it also prints the model calls and the wall seconds of
each phase with the seconds spent in model calls (summed over the worker processes), and each
fitted candidate's model calls and CPU seconds in its fit (phase 3), most calls first.

Dataset: seed 000 (the shipped `seed000_71807C_TC4.toml`, full mesh as the CLI builds it),
alternating -60 <-> 80 C cycles from 20 C (2 K/min ramps, one-hour dwells) sampled every 60 s,
500 rows (`--rows`), torque (sigma 0.02 N mm) and preload (sigma 0.5 N) measured, the rig's
friction coefficient 1.25 x the configured one. Datasets: no effect, a thermal lag (tau 300 s), a
preload settling (5 N beyond 50 K) and a solid-film run-in (-0.004 over 10 krev), because the
engine's work depends on how many candidates pass, and two generalised forms (per-part lag
300 s / 360 s, settling creeping 3 N/h), where the engine also fits the generalised forms of the
family (`studies.diagnosis.generalised`); the column `form` gives the extended form reported;
two model forms of the ladder (grooved ring sections, a housing lot 3 % above the library's CTE),
made through the ladder's own route (`ladder.FormRoute`); an unlogged load (a belt
pulley's 30 N pull with its 3000 N mm moment on seed 001's flywheel pair, `flywheel_steps`: the
speed steps with the assembled preload stepped 7 / 15 / 30 N, 1 % noise), which puts the pair's
5-DOF solve in every call of the `unlogged_load` rung; the `thermal_transient_fe` rung (issue
42: seed 000 in a 20 W/(m^2 K) film bolted to a 5 kJ/K mount, a 14 h history whatever the rows),
with the time of one of its trials (the reduced conduction alone, with its heat curve, and the whole model call). The
candidates are the CLI's
(`files.candidate_effects` and the ladder's `ladder.candidates`, after them), and so are the worker processes
(`--workers`, default every CPU the process may use, `studies.model.parallel.parallel_map`).
Last, one line per dataset kind, `<kind>: <rows> rows, wall <s> s` (docs/cli.md), the whole
`diagnose`'s wall seconds, slowest last, with the load average after it. Times: the FE set-up (mesh from the cache, unit solutions) once; per dataset the engine alone
(`diagnose_full`, what the goal is about) and the whole `diagnose_files` (reading the CSV, the
engine, JSON and the report with its plots), with the set-up pipeline passed in, both on the
measured CSV's numbers (the engine's read back with `files.read_measured`: the file holds 10
digits, and a fit can end elsewhere on numbers 1e-10 apart; a CLI verdict other than the
engine's is printed); wall seconds
and CPU seconds (this process and its workers: on a loaded machine the CPU seconds move less).

`--profile` (where the time goes; `--datasets` picks datasets by a part of their label): each
dataset's engine once more in one process, CPU seconds split into the FE superposition solves
(`FEStage.solve` of the assembly's pipeline), the pair equilibria (`BearingStage.solve`), the
rest of the model calls (effects, the model-form route, torque, checks, columns) and the engine
outside the model; and per parallel map of the engine (`Problem.parallel`, in phase order) its
items' CPU seconds, the longest item and the greedy schedule on `--workers` processes in the
order `parallel_map` starts them: the engine's CPU critical path on that many workers (a lower
bound of its wall time on idle cores, fork and pickling costs not counted).

`--fresh` (what a user's `bearingfem diagnose` costs): per dataset also the whole command in a
new Python process (`python -m studies.app.cli diagnose` on the same CSV, the same code), wall
and CPU seconds (the process and its workers), so imports, the assembly's FE set-up and the
ladder's set-ups read from the on-disk cache count, which the in-process CLI column reuses or
has in memory; `--cold` with it: that process on an empty cache folder (`BEARINGFEM_CACHE`),
so every mesh and FE set-up is built as on a machine's first run. The last lines then give
the fresh process's wall beside the in-process CLI's.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")   # as the CLI: small dense solves, no threads

import argparse  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from contextlib import contextmanager  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Callable  # noqa: E402

import numpy as np  # noqa: E402

from studies.diagnosis.designs import cycles, speed_steps  # noqa: E402

N_ROWS = 500
#: the thermal_transient_fe kind's history (s) and its hidden parameters
HISTORY_S = 14 * 3600.0
TRANSIENT_TRUTH = {"film_resistance_m2K_W": 0.05, "G_face_W_K": 5.0, "C_mount_J_K": 5000.0,
                   "G_env_W_K": 1.0}
SIGMA = {"torque_Nmm": 0.02, "preload_N": 0.5}
MU_TRUE = 1.25


def flywheel_steps(n: int) -> dict[str, np.ndarray]:
    """Seed 001's flywheel pair on a spindle rig: `designs.speed_steps` (chamber 0..60 C in
    20 K steps at 6000, 3000, 9000 rpm) over the same 8 h whatever `n`, the assembled preload
    stepped through 7, 15, 30 N row by row (an unlogged load changes the torque most at low
    preload: a rig that wants to see it varies the preload)."""
    out = speed_steps(n, 120.0 * 240 / n)
    out["preload_assembled_N"] = np.array([7.0, 15.0, 30.0])[np.arange(n) % 3]
    return out


@dataclass(frozen=True)
class Kind:
    """One dataset kind of the benchmark: label, shipped assembly, design (rows -> conditions),
    hidden effects ({name: parameters}), hidden condition columns (constant values the
    conditions given to the diagnosis do not log), measured noise (column -> sigma)."""
    label: str
    assembly: str = "seed000"
    design: Callable[[int], dict] = lambda n: cycles(n, 60.0)
    effects: dict = field(default_factory=dict)
    hidden: dict = field(default_factory=dict)
    sigma: dict = field(default_factory=lambda: dict(SIGMA))


DATASETS = [
    Kind("no effect"),
    Kind("thermal_lag tau_s=300", effects={"thermal_lag": {"tau_s": 300.0}}),
    Kind("preload_settling loss_N=5 threshold_K=50",
         effects={"preload_settling": {"loss_N": 5.0, "threshold_K": 50.0}}),
    Kind("solid_film_runin dmu=-0.004 runin_krev=10",
         effects={"solid_film_runin": {"dmu": -0.004, "runin_krev": 10.0}}),
    # generalised forms: the engine then also fits the family's forms
    Kind("thermal_lag.per_part tau_s=300 tau_shaft_s=360",
         effects={"thermal_lag.per_part": {"tau_s": 300.0, "tau_shaft_s": 360.0}}),
    Kind("preload_settling.creep 5 N, 50 K, 3 N/h",
         effects={"preload_settling.creep": {"loss_N": 5.0, "threshold_K": 50.0,
                                             "creep_N_per_h": 3.0}}),
    # model forms of the ladder: the FE set-up rung and an inputs rung
    Kind("ring_section_grooved (model form)", effects={"ring_section_grooved": {"share": 1.0}}),
    Kind("material_lot housing CTE x 1.03", effects={"material_lot": {"cte_factor_housing": 1.03}}),
    # the unlogged_load rung: a belt pulley's pull of 30 N, 100 mm beyond the
    # pair's mid-point, on seed 001's flywheel pair (the pair's 5-DOF solve in every call);
    # 1 % noise as the second source states it (the flywheel's torque is ~0.1 N mm)
    Kind("unlogged_load 30 N, 3000 N mm (flywheel)", assembly="seed001", design=flywheel_steps,
         hidden={"radial_load_N": 30.0, "moment_Nmm": 3000.0}, sigma={}),
    # the thermal_transient_fe rung: a 14 h history whatever the rows, the stack in
    # a 20 W/(m^2 K) film bolted to a 5 kJ/K mount
    Kind("thermal_transient_fe (mount, 14 h)", design=lambda n: cycles(n, HISTORY_S / n),
         effects={"thermal_transient_fe": TRANSIENT_TRUTH}),
]


@dataclass
class Profile:
    """CPU seconds of one engine run in one process (`--profile`): model calls, FE superposition
    solves and pair equilibria of the assembly's pipeline (count, seconds), the model's and the
    whole engine's seconds, and per top-level parallel map (label, item seconds, items started
    first)."""
    fe: list = field(default_factory=lambda: [0, 0.0])
    pair: list = field(default_factory=lambda: [0, 0.0])
    model: list = field(default_factory=lambda: [0, 0.0])
    maps: list = field(default_factory=list)
    engine_s: float = 0.0

    def schedule_s(self, times: list[float], first: list[int], workers: int) -> float:
        """Length of the greedy schedule of the items on `workers` processes, started in
        `parallel_map`'s order (`first`, then the items' order), each on the least loaded."""
        load = [0.0] * max(int(workers), 1)
        for i in dict.fromkeys(list(first) + list(range(len(times)))):
            k = load.index(min(load))
            load[k] += times[i]
        return max(load)

    def lines(self, workers: int) -> list[str]:
        in_maps = sum(sum(t) for _, t, _ in self.maps)
        crit = self.engine_s - in_maps + sum(self.schedule_s(t, f, workers)
                                             for _, t, f in self.maps)
        (calls, model_s), rest = self.model, self.model[1] - self.fe[1] - self.pair[1]
        out = [f"    CPU s in one process: engine {self.engine_s:.2f} = model "
               f"{model_s:.2f} ({calls} calls: FE superposition {self.fe[1]:.2f} in "
               f"{self.fe[0]} solves, pair {self.pair[1]:.2f} in {self.pair[0]} solves, rest "
               f"{rest:.2f}) + engine outside the model {self.engine_s - model_s:.2f}",
               f"    parallel maps (items, CPU s, longest item, on {workers} workers):"]
        for label, t, f in self.maps:
            out.append(f"      {label:<44} {len(t):3d} {sum(t):7.2f} {max(t, default=0):6.2f}"
                       f" {self.schedule_s(t, f, workers):6.2f}")
        out.append(f"    outside the maps {self.engine_s - in_maps:.2f} s; CPU critical path on "
                   f"{workers} workers {crit:.2f} s (of {self.engine_s:.2f} s in one process)")
        return out


def timed(fn, acc: list):
    """`fn` counting its calls and CPU seconds into acc = [calls, seconds]."""
    def run(*a, **k):
        t0 = time.process_time()
        try:
            return fn(*a, **k)
        finally:
            acc[0] += 1
            acc[1] += time.process_time() - t0
    return run


@contextmanager
def profiled(pl):
    """Time the FE superposition solves and pair equilibria of pipeline `pl` and every
    top-level `Problem.parallel` map's items (run in this process, in order, as one worker
    runs them) into a `Profile`; restored on exit."""
    from studies.diagnosis import problem

    prof, depth = Profile(), [0]
    fe_solve, pair_solve, parallel = pl.fe_stage.solve, pl.bearing.solve, problem.Problem.parallel

    def par(self, task, items, first=None):
        if depth[0]:                          # a map inside an item: serial, in its item's time
            return parallel(self, task, items, first)
        depth[0] += 1
        out, times = [], []
        try:
            for it in items:
                t0 = time.process_time()
                out.append(task(it))
                times.append(time.process_time() - t0)
        finally:
            depth[0] -= 1
        prof.maps.append((task.__qualname__.replace(".<locals>", ""), times, list(first or ())))
        return out

    pl.fe_stage.solve, pl.bearing.solve = timed(fe_solve, prof.fe), timed(pair_solve, prof.pair)
    problem.Problem.parallel = par
    try:
        yield prof
    finally:
        pl.fe_stage.solve, pl.bearing.solve = fe_solve, pair_solve
        problem.Problem.parallel = parallel


def trial_times(pred, effects: dict, cond: dict, repeat: int = 5) -> str:
    """One trial of the thermal_transient_fe rung: the reduced conduction alone
    (`transient_rung.part_temperatures_C`), with the pair's heat at the bearing's temperature
    (its `HeatCurve`, each row's heat balance solved, as a model call takes it) and the whole
    model call (the rung's temperatures through the pipeline), best of `repeat` (ms), at
    parameters moved off the truth (no memo)."""
    from studies.diagnosis.transient_rung import part_temperatures_C, rung_model
    from studies.model.inputs import baseline_inputs

    rung = pred.forms.rungs["thermal_transient_fe"].candidate
    rm = rung_model(pred.pl)
    p = rung.validate(effects["thermal_transient_fe"])
    asm = pred.pl.asm
    n = len(cond["time_s"])
    curve = rung.heat_curve(baseline_inputs(dict(cond), n, asm.T_ref_C, asm.preload.assembled_N,
                                            asm.lubrication.speed_rpm))
    thermal, heated, call = [], [], []
    for k in range(repeat):
        q = {**p, "film_resistance_m2K_W": p["film_resistance_m2K_W"] * (1.0 + 0.01 * (k + 1))}
        t0 = time.perf_counter()
        part_temperatures_C(rm, q, cond["time_s"], cond["T_ambient_C"], None)
        thermal.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        part_temperatures_C(rm, q, cond["time_s"], cond["T_ambient_C"], curve)
        heated.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        pred({"thermal_transient_fe": q}, {"mu_scale": MU_TRUE})
        call.append(time.perf_counter() - t0)
    return (f"thermal_transient_fe trial ({n} rows, {rm.m + 1} states): reduced "
            f"conduction {1e3 * min(thermal):.1f} ms, with its heat curve "
            f"{1e3 * min(heated):.1f} ms, whole model call {1e3 * min(call):.1f} ms "
            f"(load {os.getloadavg()[0]:.1f})")


def fresh_cli(config: Path, csv: Path, out: Path, cold: bool):
    """`bearingfem diagnose config csv --out out` in a new Python process importing this code
    (`--fresh`), timed (`bench_clock.Clock`: the process and its workers); on an empty cache
    folder when `cold`. Returns (Clock, the command's last output line)."""
    import studies
    from studies.bench.bench_clock import Clock

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(Path(studies.__file__).resolve().parents[1])]
        + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    with tempfile.TemporaryDirectory() as cache:
        if cold:
            env["BEARINGFEM_CACHE"] = cache
        with Clock() as clock:
            done = subprocess.run([sys.executable, "-m", "studies.app.cli", "diagnose",
                                   str(config), str(csv), "--out", str(out)], env=env,
                                  capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"fresh diagnose failed ({done.returncode}): {done.stderr[-500:]}")
    return clock, (done.stdout.strip().splitlines() or [""])[-1]


def main(argv=None) -> None:
    from studies.model.config import CONFIG_DIR, SHIPPED, load_shipped
    from studies.diagnosis.files import (NUISANCE, OUTPUT_NAMES, ModelPredictor,
                                         candidate_effects, diagnose_files, read_measured)
    from studies.validation.second_source import NOISE_SHARE
    from studies.diagnosis.engine import diagnose_full
    from studies.diagnosis.ladder import candidates as ladder_candidates
    from studies.diagnosis.result import to_json
    from studies.model.parallel import available_workers
    from studies.bench.bench_clock import Clock
    from studies.model.pipeline import Pipeline
    from studies.model.table import write_table

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mesh-factor", type=float, default=1.0)
    ap.add_argument("--rows", type=int, nargs="+", default=[N_ROWS])
    ap.add_argument("--workers", type=int, default=None,
                    help="worker processes of the engine (default: as the CLI, every CPU)")
    ap.add_argument("--datasets", nargs="+", default=None,
                    help="only the datasets whose label contains one of these")
    ap.add_argument("--profile", action="store_true",
                    help="also where the CPU time goes, in one process (module docstring)")
    ap.add_argument("--fresh", action="store_true",
                    help="also the whole diagnose in a new process per dataset (module docstring)")
    ap.add_argument("--cold", action="store_true",
                    help="with --fresh: that process on an empty cache folder")
    args = ap.parse_args(argv)
    if args.cold and not args.fresh:
        ap.error("--cold: only with --fresh")
    workers = available_workers() if args.workers is None else args.workers

    setups: dict = {}

    def setup(key):
        """(assembly, pipeline, the CLI's candidates) of a shipped assembly, built once."""
        if key not in setups:
            asm = load_shipped(key)
            t0 = time.perf_counter()
            pl = Pipeline(asm, mesh_factor=args.mesh_factor)
            print(f"FE set-up of {key} (once per run of the CLI): {time.perf_counter() - t0:.2f} s"
                  f" ({pl.ndofs} DOF)")
            # as the CLI: the listed effects, then the ladder
            setups[key] = (asm, pl, candidate_effects(asm) + ladder_candidates(asm))
        return setups[key]

    for n_rows in args.rows:
        print(f"diagnose benchmark: {n_rows} rows, mesh factor {args.mesh_factor:g}, "
              f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, "
              f"{os.cpu_count()} CPUs, {workers} worker process(es), load "
              f"{os.getloadavg()[0]:.1f}")
        print(f"{'dataset':<42} {'verdict':<15} {'cause':<18} {'engine s':>8} {'CPU s':>6} "
              f"{'calls':>6} {'model s':>8} {'CLI s':>6} {'CPU s':>6}  form")
        rng = np.random.default_rng(0)
        walls = []
        for kind in DATASETS:
            label = kind.label
            asm, pl, cands = setup(kind.assembly)
            cond = kind.design(n_rows)
            hidden = {k: np.full(n_rows, v) for k, v in kind.hidden.items()}
            cols = tuple(kind.sigma or SIGMA)
            truth = ModelPredictor(pl, {**cond, **hidden}, cols)(kind.effects,
                                                                  {"mu_scale": MU_TRUE})
            sigma = kind.sigma or {c: NOISE_SHARE * float(np.mean(np.abs(truth[c])))
                                   for c in cols}
            meas = {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in sigma.items()}
            if args.datasets and not any(d in label for d in args.datasets):
                continue                      # the noise draws stay those of the full list
            with tempfile.TemporaryDirectory() as tmp:
                csv = Path(tmp) / "measured.csv"
                write_table(csv, {**cond, **meas})
                # the engine on the numbers the CLI reads back (10 digits): the two diagnose
                # the same data, and the CLI's extra seconds are the files and the report
                cond, meas = read_measured(csv, OUTPUT_NAMES)
                pred = ModelPredictor(pl, cond, cols)
                with Clock() as engine:
                    out = diagnose_full(pred, meas, cond, cands, NUISANCE, T_ref_C=asm.T_ref_C,
                                        predict_at=pred.at, workers=workers)
                r = to_json(out)
                with Clock() as cli:
                    doc = diagnose_files(CONFIG_DIR / SHIPPED[kind.assembly], csv, Path(tmp),
                                         progress=lambda s: None, pipeline=pl, workers=workers)
                fresh = (fresh_cli(CONFIG_DIR / SHIPPED[kind.assembly], csv, Path(tmp) / "fresh",
                                   args.cold) if args.fresh else None)
            walls.append((cli.wall_s, label, cli.load_after, fresh))
            form = (r.get("extended_form") or {}).get("name", "-")
            print(f"{label:<42} {r['verdict']:<15} {str(r['cause']):<18} {engine.wall_s:8.2f} "
                  f"{engine.cpu_s:6.2f} {r['n_predict_calls']:6d} {r['seconds']['predict']:8.2f} "
                  f"{cli.wall_s:6.2f} {cli.cpu_s:6.2f}  {form}  (load {cli.load_after:.1f})")
            if (doc["verdict"], doc["cause"]) != (r["verdict"], r["cause"]):
                print(f"    the CLI's verdict differs: {doc['verdict']} {doc['cause']}")
            if fresh is not None:
                clock, said = fresh
                print(f"    fresh process{' (empty cache)' if args.cold else ''}: wall "
                      f"{clock.wall_s:.2f} s, CPU {clock.cpu_s:.2f} s (load "
                      f"{clock.load_after:.1f}); {said}")
            print(f"    model calls by phase: {r['predict_calls_by_phase']}")
            # with workers the model seconds are summed over the processes (may exceed the wall)
            print("    wall seconds by phase (model seconds, summed over the workers): " + ", ".join(
                f"{k} {v['total']:.2f} ({v['predict']:.2f})"
                for k, v in r["seconds_by_phase"].items() if v["total"] >= 0.005)
                + f"; total {r['seconds']['total']:.2f} s ({r['seconds']['predict']:.2f} s)")
            fitted = sorted((c for c in out.candidates if c.predict_calls_fit),
                            key=lambda c: -c.predict_calls_fit)
            print("    fit calls per candidate (CPU s): " + ", ".join(
                f"{c.effect} {c.predict_calls_fit} ({c.fit_cpu_s or 0.0:.2f})" for c in fitted))
            if "thermal_transient_fe" in kind.effects:
                print("    " + trial_times(pred, kind.effects, cond))
            if args.profile:
                pred = ModelPredictor(pl, cond, cols)
                with profiled(pl) as prof:
                    t0 = time.process_time()
                    diagnose_full(timed(pred, prof.model), meas, cond, cands, NUISANCE,
                                  T_ref_C=asm.T_ref_C, predict_at=pred.at, workers=1)
                    prof.engine_s = time.process_time() - t0
                print("\n".join(prof.lines(workers)))
        # docs/cli.md ("Added for turn 4"): one line per kind, the whole `diagnose` (CLI) wall,
        # slowest last; the load after each run beside it
        for wall, label, load, fresh in sorted(walls, key=lambda t: t[0]):
            print(f"{label}: {n_rows} rows, wall {wall:.2f} s (load {load:.1f})" + (
                "" if fresh is None else f"; fresh process{' (empty cache)' if args.cold else ''}"
                f" {fresh[0].wall_s:.2f} s, CPU {fresh[0].cpu_s:.2f} s (load "
                f"{fresh[0].load_after:.1f})"))


if __name__ == "__main__":
    main()
