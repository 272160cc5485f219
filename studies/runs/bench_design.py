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
workers (a local Dask cluster); `--workers 0` runs in this process.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from studies.runs.bench_clock import Clock


def main(workers: int | None = 2) -> None:
    from infra.version import __version__
    from studies.model.config import load_shipped
    from studies.runs import design_search

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
                print(f"{label.split()[0]}: {res['n_stacks']} stacks in {c.wall_s:.1f} s", flush=True)
                print(f"  ({res['n_designs']} designs, "
                      f"{'this process' if w is None else f'{w} workers'}, {label}: {c.line()})",
                      flush=True)
        finally:
            if old is None:
                os.environ.pop("BEARINGFEM_CACHE", None)
            else:
                os.environ["BEARINGFEM_CACHE"] = old
    best = res["designs"][0]
    print(f"best: {best['inner_spacer_material']} / {best['outer_spacer_material']} spacers, "
          f"{best['spacer_length_mm']} mm, preload {best['preload_assembled_N']:.0f} N: variation "
          f"{100 * best['preload_variation']:.1f} % (given {100 * res['given']['preload_variation']:.1f} %)")
    print(f"Pareto set (screening): {len(res['pareto'])} designs, preload ranges "
          + ", ".join(f"{d['preload_range_N']:.4f}" for d in res["pareto"][:5])
          + (" ..." if len(res["pareto"]) > 5 else "") + " N")
