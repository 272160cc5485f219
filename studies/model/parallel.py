"""Run independent blocks of work in this process or on a Dask cluster, with the same results.

`map_blocks(fn, blocks)` calls `fn(*block)` for every block and returns the results in block
order. Without `workers` or `scheduler` it runs here, one block after the other; with
`workers=N` it starts a local Dask cluster (N single-threaded worker processes), with
`scheduler="tcp://host:port"` it uses an existing one (dask.distributed). The blocks and their
boundaries are the same in every mode and each block is computed by the same function, so the
results are identical bit for bit; the caller chooses blocks that do not depend on one another.

Per-assembly set-up inside `fn` (the FE model, its unit solutions) is done once per worker
process: `Pipeline.shared` keeps it for the life of the process.
"""
from __future__ import annotations

from typing import Callable, Sequence


def map_blocks(fn: Callable, blocks: Sequence[tuple], workers: int | None = None,
               scheduler: str | None = None, progress: Callable[[int, int], None] | None = None
               ) -> list:
    """[fn(*b) for b in blocks], here or on Dask (see the module docstring)."""
    total = len(blocks)
    if workers is None and scheduler is None:
        out = []
        for i, b in enumerate(blocks):
            out.append(fn(*b))
            if progress is not None:
                progress(i + 1, total)
        return out
    import dask
    from dask.distributed import Client, LocalCluster, as_completed

    # distributed's nanny sets MALLOC_TRIM_THRESHOLD_=64 KiB so workers return memory early;
    # the pipeline allocates many mid-size arrays per block and ran 1.6x slower with it (measured)
    dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": 2 ** 30})

    if scheduler is not None:
        client, cluster = Client(scheduler), None
    else:
        # one BLAS/OpenMP thread per worker process: the workers share the cores already
        one = {k: "1" for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                               dashboard_address=None, env=one)
        client = Client(cluster)
    try:
        futures = [client.submit(fn, *b, pure=False) for b in blocks]
        index = {f.key: i for i, f in enumerate(futures)}
        results = [None] * total
        for done, fut in enumerate(as_completed(futures), start=1):
            results[index[fut.key]] = fut.result()
            if progress is not None:
                progress(done, total)
        return results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
