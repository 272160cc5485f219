"""`bearingfem bench --tolerance N [--workers W]`: Monte Carlo throughput of the fit tolerances,
printed with wall and CPU seconds and the machine load (`bench_clock`).

N samples of the seed 000 stack with realistic classes (k5 / P4 inner, J6 / P4 outer, fits 0 / 0
um at the nominal diameters) at one temperature (80 C) through the exact model
(`tolerance_samples.run_samples`, blocks of 1e4 samples). First this process's FE set-up (the
pipeline from the FE cache and one sample through it, `tolerance_samples.warm`: what
`bearingfem tolerance` does before its Monte Carlo), then the blocks in each mode: in this
process, on 1 and on 2 worker processes (`--workers`, `parallel.Blocks`; with `--workers W`:
W workers only; the worker modes run first, so that no mode inherits the caches another one
filled). Per worker mode the breakdown: the workers' start (forked from this process after its
set-up), the workers' set-up (`warm` in each: they have this process's pipeline from the fork),
the blocks, closing the workers; "whole" is the FE set-up plus all of these, what a command
spends. Then the speed-up of 2 workers over this process (whole and the blocks alone; the
goal: >= 1.7x whole on an idle 2-core machine), the CPU seconds per sample of the blocks (this
process's, or the worker processes' while the blocks ran; a worker within 10 % of the
process), the CPU this process spent meanwhile (handing out blocks, taking results), and a
check that every mode gives the same numbers bit for bit. On a loaded machine the CPU seconds
move much less than the wall times.
"""
from __future__ import annotations

import numpy as np

from studies.bench.bench_clock import Clock

TOLERANCES = {"inner_shaft_class": "k5", "inner_ring_bore_class": "P4",
              "outer_housing_class": "J6", "outer_ring_od_class": "P4"}
HERE = "this process"


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
    if where.here:
        return 0.0
    return float(sum(where.on_every_worker(_process_cpu_s)))


def _label(w: int | None) -> str:
    return HERE if w is None else f"{w} worker{'s' if w > 1 else ''}"


def main(samples: int, workers: int | None = None) -> None:
    import time

    from studies.model import tolerance_samples as tsm
    from studies.model import tolerances as tol
    from studies.model.parallel import Blocks

    asm = _assembly()
    cond = {"T_ambient_C": np.array([80.0])}
    with Clock() as c:
        dev = tol.sample_deviations_um(asm, samples, seed=1)
        di, do = tol.interference_offsets_um(dev, samples)
    print(f"{'draw samples':>16}: {c.line()}")
    with Clock() as c_setup:
        tsm.warm(asm)
    print(f"{'FE set-up':>16}: {c_setup.line()} (this process: the pipeline from the FE cache "
          f"and one sample)")
    # the worker modes first, then this process: every mode starts from the state right after
    # the set-up (no mode reuses the caches another one filled: the workers fork from it)
    modes = [2, 1, None] if workers is None else [workers]
    runs, whole, blocks, cpu_us, parent_cpu = {}, {}, {}, {}, {}
    for w in modes:
        label = _label(w)
        with Clock() as c:
            t0 = time.perf_counter()
            with Blocks(workers=w) as where:
                t_start = time.perf_counter() - t0
                t0 = time.perf_counter()
                where.on_every_worker(tsm.warm, asm)
                t_warm = time.perf_counter() - t0
                before, here_before = _workers_cpu_s(where), _process_cpu_s()
                with Clock() as c_blocks:
                    runs[label] = tsm.run_samples(asm, cond, di, do, where=where)
                # CPU of the blocks: this process's, or the worker processes' (every thread:
                # the task and the worker's own event loop and monitors) during the blocks
                cpu = (c_blocks.cpu_s if where.here
                       else _workers_cpu_s(where) - before)
                parent_cpu[label] = _process_cpu_s() - here_before
                t0 = time.perf_counter()
            t_close = time.perf_counter() - t0
        whole[label], blocks[label] = c_setup.wall_s + c.wall_s, c_blocks.wall_s
        cpu_us[label] = 1e6 * cpu / samples
        print(f"{label:>16}: {samples} samples at 80 C, {c.line()}, "
              f"{samples / c_blocks.wall_s:8.0f} samples/s in the blocks", flush=True)
        if w is not None:
            print(f"{'':>16}  workers' start {t_start:.2f} s (forked), the workers' "
                  f"set-up {t_warm:.2f} s, the blocks {c_blocks.wall_s:.2f} s, closing "
                  f"{t_close:.2f} s (wall)", flush=True)
        print(f"{'':>16}  whole (FE set-up {c_setup.wall_s:.2f} s + the above) "
              f"{whole[label]:.2f} s wall", flush=True)
        print(f"{'':>16}  CPU per sample of the blocks: {cpu_us[label]:.1f} us "
              f"({HERE if w is None else 'the worker processes, every thread'})"
              + ("" if w is None else f"; this process meanwhile (handing out blocks) "
                                      f"{parent_cpu[label]:.2f} s CPU"), flush=True)
    if workers is None:
        two = _label(2)
        print(f"speed-up of 2 workers over this process: whole {whole[HERE] / whole[two]:.2f}x "
              f"({whole[HERE]:.2f} s vs {whole[two]:.2f} s; >= 1.7x on an idle "
              f"machine), the blocks alone {blocks[HERE] / blocks[two]:.2f}x")
        print(f"speed-up of 2 workers over 1: whole {whole[_label(1)] / whole[two]:.2f}x, "
              f"the blocks alone {blocks[_label(1)] / blocks[two]:.2f}x")
        print(f"CPU per sample, one worker / this process: "
              f"{cpu_us[_label(1)] / cpu_us[HERE]:.3f}; two workers / this process: "
              f"{cpu_us[two] / cpu_us[HERE]:.3f} (within 10 %)")
        ref = runs[HERE].columns()
        same = all(np.array_equal(v, ref[q]) for k in (_label(1), two)
                   for q, v in runs[k].columns().items())
        print(f"identical results in all three: {same}")
    r = next(iter(runs.values()))
    p, se = tol.probability(r.fit_pressure_inner_MPa[:, 0] <= 0)
    print(f"P(inner fit open at 80 C) = {p:.4g} +- {se:.2g}; preload mean "
          f"{r.preload_N.mean():.2f} N, sd {r.preload_N.std():.2f} N")
