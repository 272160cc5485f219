"""`bearingfem bench --tolerance N [--workers W]`: Monte Carlo throughput of the fit tolerances,
printed with wall and CPU seconds and the machine load (`bench_clock`).

N samples of the seed 000 stack with realistic classes (k5 / P4 inner, J6 / P4 outer, fits 0 / 0
um at the nominal diameters) at one temperature (80 C) through the exact model
(`tolerances.run_samples`, blocks of 1e4 samples). With `--workers W`: on a local Dask cluster of
W workers only (cluster start and per-worker FE set-up, read from the cache, included, and
printed apart from the blocks' own time). Without: in this process, then on 1 and on 2 workers,
the speed-up of 2 workers over 1 (wall, whole and blocks alone) and a check that all three give
the same numbers bit for bit. Per mode the CPU seconds per sample of the blocks: this process's,
or the worker processes' (all their threads) while the blocks ran, which a loaded machine
inflates much less than the wall time.
"""
from __future__ import annotations

import numpy as np

from studies.runs.bench_clock import Clock

TOLERANCES = {"inner_shaft_class": "k5", "inner_ring_bore_class": "P4",
              "outer_housing_class": "J6", "outer_ring_od_class": "P4"}


def _assembly():
    from dataclasses import replace

    from studies.model.config import load_shipped

    a = load_shipped("seed000")
    return replace(a, fits=replace(a.fits, inner_interference_um=0.0, outer_interference_um=0.0,
                                   **TOLERANCES))


def _process_cpu_s() -> float:
    """User + system CPU seconds of the calling process (all its threads)."""
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _workers_cpu_s(where) -> float:
    """Summed CPU seconds of the worker processes so far (0 when the blocks run here)."""
    if where.client is None:
        return 0.0
    return float(sum(where.client.run(_process_cpu_s).values()))


def main(samples: int, workers: int | None = None) -> None:
    from studies.model import tolerance_samples as tsm
    from studies.model import tolerances as tol
    from studies.model.parallel import Blocks
    from studies.model.pipeline import Pipeline

    asm = _assembly()
    cond = {"T_ambient_C": np.array([80.0])}
    with Clock() as c:
        dev = tol.sample_deviations_um(asm, samples, seed=1)
        di, do = tol.interference_offsets_um(dev, samples)
    print(f"{'draw samples':>16}: {c.line()}")
    modes = [("this process", None), ("Dask, 1 worker", 1), ("Dask, 2 workers", 2)]
    if workers is not None:
        modes = [(f"Dask, {workers} worker{'s' if workers > 1 else ''}", workers)]
    else:
        with Clock() as c:
            Pipeline.shared(asm)
        print(f"{'FE set-up':>16}: {c.line()}")
    runs, clocks, blocks_s, cpu_us = {}, {}, {}, {}
    for label, w in modes:
        with Clock() as c:
            with Blocks(workers=w) as where:
                where.on_every_worker(tsm.warm, asm)
                before = _workers_cpu_s(where)
                with Clock() as c_blocks:
                    runs[label] = tsm.run_samples(asm, cond, di, do, where=where)
                # CPU of the blocks: this process's, or the worker processes' (every thread:
                # the task and the worker's own event loop and monitors) during the blocks
                cpu = (c_blocks.cpu_s if where.client is None
                       else _workers_cpu_s(where) - before)
        clocks[label], blocks_s[label] = c, c_blocks.wall_s
        cpu_us[label] = 1e6 * cpu / samples
        print(f"{label:>16}: {samples} samples at 80 C, {c.line()}, "
              f"{samples / c.wall_s:8.0f} samples/s", flush=True)
        if w is not None:
            print(f"{'':>16}  of which cluster start and FE set-up per worker "
                  f"{c.wall_s - c_blocks.wall_s:.2f} s wall, the blocks {c_blocks.wall_s:.2f} s "
                  f"wall ({samples / c_blocks.wall_s:.0f} samples/s)", flush=True)
        print(f"{'':>16}  CPU per sample of the blocks: {cpu_us[label]:.1f} us "
              f"({'this process' if w is None else 'the worker processes, every thread'})",
              flush=True)
    if workers is None:
        one, two = clocks["Dask, 1 worker"], clocks["Dask, 2 workers"]
        print(f"speed-up of 2 workers over 1: wall {one.wall_s / two.wall_s:.2f}x "
              f"(CPU {one.cpu_s:.1f} s vs {two.cpu_s:.1f} s); the blocks alone "
              f"{blocks_s['Dask, 1 worker'] / blocks_s['Dask, 2 workers']:.2f}x")
        same = all(np.array_equal(v, runs["this process"].columns()[q])
                   for k in ("Dask, 1 worker", "Dask, 2 workers")
                   for q, v in runs[k].columns().items())
        print(f"identical results in all three: {same}")
        print(f"CPU per sample, one worker / this process: "
              f"{cpu_us['Dask, 1 worker'] / cpu_us['this process']:.3f}; two workers / this "
              f"process: {cpu_us['Dask, 2 workers'] / cpu_us['this process']:.3f}")
    r = next(iter(runs.values()))
    p, se = tol.probability(r.fit_pressure_inner_MPa[:, 0] <= 0)
    print(f"P(inner fit open at 80 C) = {p:.4g} +- {se:.2g}; preload mean "
          f"{r.preload_N.mean():.2f} N, sd {r.preload_N.std():.2f} N")
