"""`bearingfem bench --tolerance N`: Monte Carlo throughput of the fit tolerances, printed.

N samples of the seed 000 stack with realistic classes (k5 / P4 inner, J6 / P4 outer, fits 0 / 0
um at the nominal diameters) at one temperature (80 C) through the exact model: in this process
and on a local Dask cluster of 1 and 2 workers (cluster start and per-worker FE set-up included),
with the speed-up of 2 workers over 1 and a check that all three give the same numbers.
"""
from __future__ import annotations

import time

import numpy as np

TOLERANCES = {"inner_shaft_class": "k5", "inner_ring_bore_class": "P4",
              "outer_housing_class": "J6", "outer_ring_od_class": "P4"}


def _assembly():
    from dataclasses import replace

    from studies.model.config import load_shipped

    a = load_shipped("seed000")
    return replace(a, fits=replace(a.fits, inner_interference_um=0.0, outer_interference_um=0.0,
                                   **TOLERANCES))


def main(samples: int) -> None:
    from studies.model import tolerances as tol
    from studies.model.pipeline import Pipeline

    asm = _assembly()
    cond = {"T_ambient_C": np.array([80.0])}
    dev = tol.sample_deviations_um(asm, samples, seed=1)
    di, do = tol.interference_offsets_um(dev, samples)
    t0 = time.perf_counter()
    Pipeline.shared(asm)
    print(f"FE set-up (seed 000 stack): {time.perf_counter() - t0:.2f} s")
    runs = {}
    for label, workers in (("this process", None), ("Dask, 1 worker", 1), ("Dask, 2 workers", 2)):
        t0 = time.perf_counter()
        runs[label] = tol.run_samples(asm, cond, di, do, workers=workers)
        dt = time.perf_counter() - t0
        print(f"{label:>16}: {samples} samples at 80 C in {dt:7.2f} s "
              f"({samples / dt:9.0f} samples/s)")
        runs[label + " s"] = dt
    print(f"speed-up of 2 workers over 1: {runs['Dask, 1 worker s'] / runs['Dask, 2 workers s']:.2f}x")
    same = all(np.array_equal(runs[k]["preload_N"], runs["this process"]["preload_N"])
               for k in ("Dask, 1 worker", "Dask, 2 workers"))
    p, se = tol.probability(runs["this process"]["fit_pressure_inner_MPa"][:, 0] <= 0)
    print(f"identical results in all three: {same}; P(inner fit open at 80 C) = {p:.4f} +- {se:.4f}")
