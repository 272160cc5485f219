"""Run independent blocks of work in this process or on a Dask cluster, with the same results.

`map_blocks(fn, blocks)` calls `fn(*block)` for every block and returns the results in block
order. Without `workers` or `scheduler` it runs here, one block after the other; with
`workers=N` it starts a local Dask cluster (N single-threaded worker processes), with
`scheduler="tcp://host:port"` it uses an existing one (dask.distributed). The blocks and their
boundaries are the same in every mode and each block is computed by the same function, so the
results are identical bit for bit; the caller chooses blocks that do not depend on one another.

`Blocks` is the same as a context manager that keeps its cluster for several calls: `imap`
yields the results in block order while later blocks still run, with at most `ahead` blocks
submitted and not yet yielded (memory bounded for any number of blocks; a streamed `simulate`).

Per-assembly set-up inside `fn` (the FE model, its unit solutions) is done once per worker
process: `Pipeline.shared` keeps it for the life of the process.
"""
from __future__ import annotations

from collections import deque
from typing import Callable, Iterable, Iterator, Sequence

#: environment of every local worker process (and pre-spawn environment of any nanny):
#: - one BLAS/OpenMP thread per worker process: the workers share the cores already;
#: - MALLOC_TRIM_THRESHOLD_: distributed's nanny sets 64 KiB so workers return memory early;
#:   the pipeline allocates many mid-size arrays per block and ran 1.6x slower with it (measured);
#: - MALLOC_MMAP_THRESHOLD_ = 32 MiB: glibc's default serves arrays over 128 kB..32 MB by fresh
#:   mmap, and every block's temporaries then page-fault anew (a worker's minor page faults over
#:   19 tolerance blocks of 1e4 samples: 2.4e6 without it, 1.3e4 with it, measured 2026-11-24;
#:   glibc mallopt(3) M_MMAP_THRESHOLD). Set before the worker process starts (the nanny's
#:   pre-spawn environment): glibc reads it once, at start.
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
              "MALLOC_TRIM_THRESHOLD_": str(2 ** 30), "MALLOC_MMAP_THRESHOLD_": str(2 ** 25)}

#: Dask configuration of the local workers (set before the cluster starts; a nanny hands its
#: configuration to the worker process it spawns): the worker's own monitors run on its event
#: loop between the blocks' work and cost CPU per second of wall time, not per sample. The
#: statistical profiler samples every thread's stack every 10 ms, the GIL monitor every 1 ms,
#: the memory monitor every 100 ms. With them off or slowed a worker process spent 3.86 s CPU
#: on 10 tolerance blocks of 1e4 samples whose own work took 3.77 s (2 %), with the defaults
#: 4.53 s for 3.92 s (15 %; measured 2026-11-25 on a loaded 2-core machine, bench --tolerance).
#: The dashboard's task-stream and profile pages lose their data; an existing scheduler's
#: workers (`--scheduler`) keep their own configuration.
WORKER_CONFIG = {"distributed.worker.profile.enabled": False,
                 "distributed.admin.system-monitor.gil.enabled": False,
                 "distributed.admin.system-monitor.interval": "2s",
                 "distributed.admin.tick.interval": "500ms",
                 "distributed.worker.memory.monitor-interval": "1s"}


#: seconds to wait for an existing scheduler (`--scheduler`) before giving up
CONNECT_TIMEOUT_S = 20.0


class SchedulerError(ValueError):
    """The Dask scheduler given cannot be reached: one line naming its address."""


class Blocks:
    """Where blocks run: here (no workers, no scheduler), a local Dask cluster of `workers`
    single-threaded processes, or the Dask scheduler at `scheduler`. Use as a context manager."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None):
        self.workers, self.scheduler = workers, scheduler
        self.client = self.cluster = None

    @property
    def here(self) -> bool:
        return self.workers is None and self.scheduler is None

    def __enter__(self) -> "Blocks":
        if self.here:
            return self
        import dask
        from dask.distributed import Client, LocalCluster

        dask.config.set({f"distributed.nanny.pre-spawn-environ.{k}": v
                         for k, v in WORKER_ENV.items() if k.startswith("MALLOC")})
        dask.config.set(WORKER_CONFIG)
        if self.scheduler is not None:
            try:
                self.client = Client(self.scheduler, timeout=CONNECT_TIMEOUT_S)
            except (OSError, TimeoutError, ValueError) as exc:
                raise SchedulerError(f"--scheduler {self.scheduler}: cannot connect "
                                     f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
                                     ) from None
        else:
            self.cluster = LocalCluster(n_workers=int(self.workers), threads_per_worker=1,
                                        processes=True, dashboard_address=None, env=WORKER_ENV)
            self.client = Client(self.cluster)
        return self

    def __exit__(self, *exc) -> bool:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        self.client = self.cluster = None
        return False

    def on_every_worker(self, fn: Callable, *args) -> None:
        """fn(*args) once in every worker process (here: once in this process), e.g. to build
        the per-process FE set-up before timing blocks (`bench --tolerance`)."""
        if self.client is None:
            fn(*args)
        else:
            self.client.run(fn, *args)

    def slots(self) -> int:
        """Worker threads available (1 here)."""
        if self.client is None:
            return 1
        return max(1, sum(self.client.nthreads().values()))

    def imap(self, fn: Callable, blocks: Iterable[tuple], ahead: int | None = None) -> Iterator:
        """fn(*b) for each block, yielded in block order; on Dask at most `ahead` blocks
        (default 2 per worker thread) are submitted and not yet yielded."""
        if self.client is None:
            for b in blocks:
                yield fn(*b)
            return
        ahead = ahead or 2 * self.slots()
        pending: deque = deque()
        for b in blocks:
            pending.append(self.client.submit(fn, *b, pure=False))
            if len(pending) >= ahead:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()

    def map(self, fn: Callable, blocks: Sequence[tuple],
            progress: Callable[[int, int], None] | None = None) -> list:
        """[fn(*b) for b in blocks], all submitted at once on Dask."""
        total = len(blocks)
        if self.client is None:
            out = []
            for i, b in enumerate(blocks):
                out.append(fn(*b))
                if progress is not None:
                    progress(i + 1, total)
            return out
        from dask.distributed import as_completed

        futures = [self.client.submit(fn, *b, pure=False) for b in blocks]
        index = {f.key: i for i, f in enumerate(futures)}
        results = [None] * total
        for done, fut in enumerate(as_completed(futures), start=1):
            results[index[fut.key]] = fut.result()
            if progress is not None:
                progress(done, total)
        return results


def map_blocks(fn: Callable, blocks: Sequence[tuple], workers: int | None = None,
               scheduler: str | None = None, progress: Callable[[int, int], None] | None = None,
               where: Blocks | None = None) -> list:
    """[fn(*b) for b in blocks], here or on Dask (see the module docstring); `where`: an open
    `Blocks` to use (and leave open) instead of workers / scheduler."""
    if where is not None:
        return where.map(fn, blocks, progress)
    with Blocks(workers, scheduler) as opened:
        return opened.map(fn, blocks, progress)
