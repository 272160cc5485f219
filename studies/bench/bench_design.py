"""`bearingfem bench --design [--workers W]`: the design search of the seed 000 stack over
-60..80 C (every stack its own FE, `design_search.run` with its defaults: 324 stacks x 5
preloads x 15 temperatures on the screening mesh, the best re-evaluated on the assembly's
mesh), printed with wall and CPU seconds and the machine load (`bench_clock`).

Twice with a fresh FE cache folder (BEARINGFEM_CACHE): cold and warm, printed as the lines
`cold: N stacks in S s` and `warm: N stacks in S s` (wall seconds; docs/cli.md) with CPU seconds
and load beside them. The screening's FE set-ups come from one reference FE per stack family
(`fem.parametric`: per spacer length and clamp scheme, built once per worker process; every
other member by a static condensation of the spacers and a low-rank update, no mesh or
factorisation of its own), so cold differs from warm by the meshes and the reference set-ups of
the families and by the confirm step's full set-ups (the assembly's mesh, cached). Default 2
worker processes (forked from this one); `--workers 0` runs in this process.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from studies.bench.bench_clock import Clock

#: stacks the memory line runs, and after how many the first reading is taken
MEMORY_STACKS = 1000
MEMORY_WARMUP = 100
#: the same on the full set-up route, cold (each stack meshed and factorised: ~1 s a stack)
FULL_STACKS = 60
FULL_WARMUP = 10


def rss_MB() -> float:
    """This process's resident memory, MB (Linux /proc/self/statm; nan elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2 ** 20
    except (OSError, ValueError, IndexError):
        return float("nan")


def _rss_everywhere(where) -> list[float]:
    """RSS (MB) of every worker process (of this process with no workers)."""
    return [float(v) for v in where.on_every_worker(rss_MB)]


def memory_per_stack(asm, workers: int | None, n_stacks: int = MEMORY_STACKS,
                     warmup: int = MEMORY_WARMUP,
                     parametric: bool = True) -> tuple[float, float, float]:
    """(RSS after the warm-up, RSS at the end, growth per stack), MB, the workers' mean: the
    screening task of the design search over n_stacks of the `--clamps` candidates
    (`parametric=False`: every stack's own full set-up, the route of fits that are not
    frictionless; cold when BEARINGFEM_CACHE is an empty folder)."""
    import numpy as np

    from studies.model.parallel import Blocks
    from studies.usecases import design_search as ds

    stacks = ds.candidates(asm, clamps=True)
    settings = (ds.Setting.given(asm),)
    T = np.linspace(-60.0, 80.0, ds.N_TEMPERATURES)
    P0 = asm.preload.assembled_N * np.array(ds.PRELOAD_FACTORS)
    order = sorted(range(len(stacks)), key=lambda i: ds._family_of(stacks[i]))
    blocks = [(asm, stacks[order[k % len(order)]], settings, T, P0, ds.SCREEN_MESH_FACTOR,
               parametric) for k in range(n_stacks)]
    with Blocks(workers) as where:
        where.map(ds.evaluate_settings, blocks[:warmup])
        before = _rss_everywhere(where)
        where.map(ds.evaluate_settings, blocks[warmup:])
        after = _rss_everywhere(where)
    per_worker = (n_stacks - warmup) / len(after)
    growth = sum(b - a for a, b in zip(before, after)) / len(after) / per_worker
    return sum(before) / len(before), sum(after) / len(after), growth


def main(workers: int | None = 2) -> None:
    from infra.version import __version__
    from studies.model.config import load_shipped
    from studies.usecases import design_search

    asm = load_shipped("seed000")
    w = None if not workers else workers
    old = os.environ.get("BEARINGFEM_CACHE")
    with tempfile.TemporaryDirectory(prefix="bearingfem-bench-design-") as tmp:
        os.environ["BEARINGFEM_CACHE"] = str(Path(tmp) / "cache")   # inherited by the workers
        try:
            for label in ("cold FE cache", "warm FE cache"):
                out = Path(tmp) / label.split()[0]
                out.mkdir()
                with Clock() as c:
                    res = design_search.run(asm, -60.0, 80.0, out,
                                            {"command": "bench --design", "version": __version__},
                                            workers=w,
                                            progress=lambda s: None)
                print(f"{label.split()[0]}: {res.n_stacks} stacks in {c.wall_s:.1f} s", flush=True)
                print(f"  ({res.n_designs} designs, "
                      f"{'this process' if w is None else f'{w} workers'}, {label}: {c.line()})",
                      flush=True)
            memory = memory_per_stack(asm, w)      # the warm cache of this temporary folder
            os.environ["BEARINGFEM_CACHE"] = str(Path(tmp) / "cache-full")     # empty: cold
            memory_full = memory_per_stack(asm, w, FULL_STACKS, FULL_WARMUP, parametric=False)
        finally:
            if old is None:
                os.environ.pop("BEARINGFEM_CACHE", None)
            else:
                os.environ["BEARINGFEM_CACHE"] = old
    best = res.designs[0]
    print(f"best: {best.stack.inner_spacer_material} / {best.stack.outer_spacer_material} spacers, "
          f"{best.stack.spacer_length_mm} mm, preload {best.metrics.preload_assembled_N:.0f} N: "
          f"variation {100 * best.metrics.preload_variation:.1f} % (given "
          f"{100 * res.given.metrics.preload_variation:.1f} %)")
    print(f"Pareto set (screening): {len(res.pareto)} designs, preload ranges "
          + ", ".join(f"{d.metrics.preload_range_N:.4f}" for d in res.pareto[:5])
          + (" ..." if len(res.pareto) > 5 else "") + " N")
    a, b, g = memory
    print(f"memory: {MEMORY_STACKS} stacks, worker RSS {a:.0f} -> {b:.0f} MB after the first "
          f"{MEMORY_WARMUP}, {g:.3f} MB per stack", flush=True)
    a, b, g = memory_full
    print(f"memory, full set-up route (cold): {FULL_STACKS} stacks, worker RSS {a:.0f} -> "
          f"{b:.0f} MB after the first {FULL_WARMUP}, {g:.3f} MB per stack", flush=True)
