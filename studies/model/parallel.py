"""The one parallel map of the project (Dask): independent pieces of work here, on forked
processes of this machine, or on a Dask cluster, with the same results in every mode.

Two kinds of work, one library (Dask graphs of independent tasks; no second pool):

- Blocks that are pure functions of their arguments (`map_blocks`, `Blocks`: the tolerance Monte
  Carlo, the streamed `simulate`, the design search): with `workers=N` on a local
  `dask.distributed` cluster of N single-threaded processes, with `scheduler="tcp://host:port"`
  on an existing one (another machine's workers too: docs/cli.md, `--workers` / `--scheduler`),
  without either here, one block after the other. `map_blocks(fn, blocks)` calls `fn(*block)`
  for every block and returns the results in block order. `Blocks` is the same as a context
  manager that keeps its cluster for several calls: `imap` yields the results in block order
  while later blocks still run, with at most `ahead` blocks submitted and not yet yielded
  (memory bounded for any number of blocks; a streamed `simulate`). The blocks and their
  boundaries are the same in every mode and each block is computed by the same function, so
  the results are identical bit for bit; the caller chooses blocks that do not depend on one
  another. Per-assembly set-up inside `fn` (the FE model, its unit solutions) is done once per
  process (`Pipeline.shared` keeps it); a local cluster's workers are forked from a fork server
  with the model's modules imported (`LOCAL_START_METHOD`) and read the set-up from the cache.
- Work that shares this process's state (`parallel_map(task, items, workers)`: the diagnosis's
  candidate fits and plots, with the FE set-up, the pipeline and the model cache as they are
  now): [task(item) for item in items] as a Dask graph on Dask's local process scheduler, over
  processes forked from this one, so that nothing is pickled but the items' indices and the
  results, and the task may be a closure (a cluster would need the state pickled to every
  worker). Each task is a pure function of the state at the fork and its item, so every result
  is the one a serial run computes, to the last bit; results come back in the items' order. A
  `state` object (e.g. the diagnosis's `CachedModel`) can carry what the tasks add to it back to
  this process (`snapshot` / `delta` in the worker, `merge` here).
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import uuid
from collections import deque
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Callable, Iterable, Iterator, Protocol, Sequence

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


#: how a local cluster's nanny starts its worker process. "forkserver" (Linux, macOS): a server
#: process, started once with the modules of FORKSERVER_PRELOAD imported, forks each worker, so a
#: worker imports nothing and reads the FE set-up from the cache (0.04 CPU s). Not "fork": the
#: cluster's scheduler and nannies run on threads of this process, and a worker forked while
#: another thread held a lock hung at start (seen twice in the test suite, under pytest-xdist).
#: "spawn" (distributed's default) starts a new interpreter that imports distributed, then the
#: task's modules, then sets up the FE model. Measured 2026-11-25, 2 workers, seed 000 tolerance
#: case, loaded 2-core machine (load ~11): spawn: cluster start 4.3-5.5 s wall, 0.9 CPU s in the
#: workers; their set-up 3.4-4.2 s wall, 0.9 CPU s; closing 1.8 s; fork: start 1.0-1.7 s wall,
#: set-up 0.02-0.07 s, closing 0.04-0.12 s (forkserver: `bench --tolerance` prints it). An
#: existing scheduler's workers (`--scheduler`) start as their own configuration says.
LOCAL_START_METHOD = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
#: what the fork server imports once (distributed's own list: the library and its dependencies;
#: here the model's route too, so that a worker's first block imports nothing)
FORKSERVER_PRELOAD = ("distributed", "numpy", "scipy.sparse.linalg", "pandas", "skfem",
                      "studies.model.pipeline", "studies.model.tolerance_samples")


def _preload_fork_server() -> None:
    """Set the fork server's imports before distributed starts it (distributed sets its own list
    once per process in `get_mp_context`; a list set after that and before the server's first
    start wins; a server already running keeps its imports)."""
    from distributed.utils import get_mp_context

    ctx = get_mp_context()
    if LOCAL_START_METHOD == "forkserver":
        ctx.set_forkserver_preload(list(FORKSERVER_PRELOAD))

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
            dask.config.set({"distributed.worker.multiprocessing-method": LOCAL_START_METHOD})
            _preload_fork_server()
            # dashboard_address ":0": the scheduler's HTTP endpoint on a free port (None still
            # tries 8787 and warns on stderr when another cluster holds it)
            self.cluster = LocalCluster(n_workers=int(self.workers), threads_per_worker=1,
                                        processes=True, dashboard_address=":0", env=WORKER_ENV)
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


# ---------------------------------------------------------------------- work sharing this process
class SharedState(Protocol):
    """What a forked task adds to shared state (a cache, counters), carried back to the parent."""

    def snapshot(self) -> Any: ...

    def delta(self, snapshot: Any) -> Any: ...

    def merge(self, delta: Any) -> None: ...


#: the job of the forked workers: (task, items, state), set just before the pool forks
_JOB: tuple | None = None
#: True in a forked worker: a task's own `parallel_map` runs serially there (no pool in a pool)
_IN_WORKER = False


def available_workers() -> int:
    """CPUs this process may run on (its affinity mask where the OS has one)."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:                  # not Linux
        return max(os.cpu_count() or 1, 1)


def can_fork() -> bool:
    """Whether worker processes can be forked here (fork start method, not a worker of
    `parallel_map` or another daemonic process)."""
    return ("fork" in multiprocessing.get_all_start_methods() and not _IN_WORKER
            and not multiprocessing.current_process().daemon)


def _worker_init() -> None:
    """A worker ends quietly when the parent ends the pool (the parent's SIGTERM handler, e.g.
    the CLI's, is not inherited), leaves Ctrl-C to the parent and runs its tasks' own maps
    serially."""
    global _IN_WORKER
    _IN_WORKER = True
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run_item(i: int) -> tuple:
    """One task in a worker: ("ok", value) or ("err", exception), and the state's delta."""
    task, items, state = _JOB
    before = None if state is None else state.snapshot()
    try:
        out = ("ok", task(items[i]))
    except Exception as exc:                # re-raised in the parent, in the items' order
        out = ("err", exc)
    return out, (None if state is None else state.delta(before))


def parallel_map(task: Callable, items: Sequence, workers: int, first: Sequence[int] | None = None,
                 state: SharedState | None = None) -> list:
    """[task(item) for item in items], on up to `workers` forked processes when `workers` > 1,
    there are at least two items and `can_fork()`; else serially here (module docstring).
    `first`: indices of items to start first (the longest tasks: better balance; results keep
    the items' order). `state`: merged with each task's delta, in the items' order. An exception
    of a task is raised here, the first in the items' order.

    The tasks are a Dask graph computed by Dask's local process scheduler
    (`dask.multiprocessing.get`, one task at a time per process: chunksize 1) on a pool of
    processes forked from this one (Dask's own pool would spawn fresh interpreters, without
    this process's state). Independent tasks start in the order `dask.order` gives them, the
    greatest key first: the keys count down along `first` and then the items' order."""
    items = list(items)
    n = min(int(workers), len(items))
    if n <= 1 or not can_fork():
        return [task(it) for it in items]
    import dask.multiprocessing

    global _JOB
    order = list(dict.fromkeys(list(first or ()) + list(range(len(items)))))
    name = f"parallel_map-{uuid.uuid4().hex}"
    graph = {(name, len(order) - rank): (_run_item, i) for rank, i in enumerate(order)}
    keys = [(name, len(order) - rank) for rank in range(len(order))]
    _JOB = (task, items, state)
    pool = ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("fork"),
                               initializer=_worker_init)
    try:
        got = dict(zip(order, dask.multiprocessing.get(graph, keys, pool=pool, chunksize=1,
                                                       optimize_graph=False)))
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in list(getattr(pool, "_processes", {}).values()):   # no public terminate
            proc.terminate()
        raise
    finally:
        _JOB = None
    pool.shutdown(wait=True)
    results = []
    for i in range(len(items)):
        (kind, value), delta = got[i]
        if state is not None:
            state.merge(delta)
        if kind == "err":
            raise value
        results.append(value)
    return results
