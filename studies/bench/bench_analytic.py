"""Benchmark of the analytic chain: pair equilibrium + Hertz + friction torque per operating point.

`main()` builds N operating points of the seed 000 bearing pair (random groove-centre shifts, part
temperatures -60..80 C, external axial loads, preloads), solves them with `bearing.solve_pair`
and `friction.pair.pair_torque`, and prints evaluations per second, single-threaded and split over
worker threads (numpy and scipy.special release the GIL inside their loops).  Not a test: timings
depend on the machine and its load.
"""
from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from analytic.bearing import BearingGeometry, solve_pair
from analytic.friction.pair import pair_torque


def make_inputs(n: int, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    T = rng.uniform(-60.0, 80.0, n)
    return dict(dr_mm=rng.uniform(-1e-3, 1e-3, (2, n)), dz_mm=rng.uniform(-2e-3, 2e-3, (2, n)),
                T_inner_ring_C=T, T_outer_ring_C=T + rng.uniform(-2, 2, n), T_ball_C=T,
                T_ref_C=20.0, preload_assembled_N=100.0, axial_load_N=rng.uniform(-150, 150, n))


def evaluate(g: BearingGeometry, inputs: dict):
    """Pair state and torque components of the pair (`bearing.solve_pair`, `friction.pair.pair_torque`)."""
    pair = solve_pair(g, "DB", **inputs)
    return pair, pair_torque(g, pair, model="solid_film", mu=0.02, hysteresis_loss=0.01,
                             speed_rpm=60.0)


def _chunk(inputs: dict, sl: slice) -> dict:
    out = {}
    for k, v in inputs.items():
        a = np.asarray(v)
        out[k] = a[..., sl] if a.ndim >= 1 else v
    return out


def run(n: int = 100_000, threads: int = 1, repeat: int = 3) -> float:
    """Best-of-`repeat` evaluations per second for n points on `threads` worker threads."""
    g = BearingGeometry.from_catalogue("71807C")
    inputs = make_inputs(n)
    evaluate(g, _chunk(inputs, slice(0, 10)))          # build the Hertz start table once
    bounds = np.linspace(0, n, threads + 1).astype(int)
    parts = [_chunk(inputs, slice(bounds[i], bounds[i + 1])) for i in range(threads)]
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        if threads == 1:
            evaluate(g, parts[0])
        else:
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(lambda p: evaluate(g, p), parts))
        best = min(best, time.perf_counter() - t0)
    return n / best


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--threads", type=int, default=min(2, os.cpu_count() or 1))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    one = run(args.points, 1, args.repeat)
    print(f"analytic pair+Hertz+torque, {args.points} points, 1 thread: {one:,.0f} evaluations/s")
    if args.threads > 1:
        many = run(args.points, args.threads, args.repeat)
        print(f"analytic pair+Hertz+torque, {args.points} points, {args.threads} threads: "
              f"{many:,.0f} evaluations/s")


if __name__ == "__main__":
    main()
