"""The one parallel map of the project: independent pieces of work here, on worker processes
forked from this one, or on a Dask cluster, with the same results in every mode.

One route (`_in_order`: submit, keep at most `ahead` results pending, yield them in order) for
two kinds of work:

- Blocks that are pure functions of their arguments (`map_blocks`, `Blocks`: the tolerance Monte
  Carlo, the streamed `simulate`, the design search): with `workers=N` on N single-threaded
  worker processes forked from this one (`_Pool`), with `scheduler="tcp://host:port"` on an
  existing Dask cluster (`dask.distributed`; another machine's workers too: docs/cli.md,
  `--workers` / `--scheduler`), without either here, one block after the other.
  `map_blocks(fn, blocks)` calls `fn(*block)` for every block and returns the results in block
  order. `Blocks` is the same as a context manager that keeps its workers for several calls:
  `imap` yields the results in block order while later blocks still run, with at most `ahead`
  blocks submitted and not yet yielded (memory bounded for any number of blocks; a streamed
  `simulate`). The blocks and their boundaries are the same in every mode and each block is
  computed by the same function, so the results are identical bit for bit; the caller chooses
  blocks that do not depend on one another. Per-assembly set-up inside `fn` (the FE model, its
  unit solutions) is done once per process (`Pipeline.shared` keeps it): a forked worker starts
  with this process's (a command builds it before its blocks), else reads it from the FE cache.
- Work that shares this process's state (`parallel_map(task, items, workers)`: the diagnosis's
  candidate fits and plots, with the FE set-up, the pipeline and the model cache as they are
  now): [task(item) for item in items] on the same forked workers, set up with the task and the
  items before they fork, so that nothing is pickled but the items' indices and the results,
  and the task may be a closure. Each task is a pure function of the state at the fork and its
  item, so every result is the one a serial run computes, to the last bit; results come back in
  the items' order. A `state` object (e.g. the diagnosis's `CachedModel`) can carry what the
  tasks add to it back to this process (`snapshot` / `delta` in the worker, `merge` here).

Why local workers are not a local Dask cluster (`distributed.LocalCluster`, the route before
2026-11-25): its start cost 1.3 s wall on an idle 2-core machine (a fork server that imports
distributed, 0.77 s, and the model; the scheduler and a nanny per worker) and its scheduler and
client ran on threads of this process, 1.2..1.7 CPU s over 1e6 tolerance samples, beside two
workers on two cores (`bench --tolerance`: the cold 2-worker run was 1.60x one process). The
forked pool starts in 0.03..0.07 s (at a load of 11..16, where the cluster took 4.2..4.9 s), its
workers start with this process's imports and warm pipeline, and this process spends only what
handing out blocks costs (docs/cli.md, "Benchmarks"). No thread of a cluster exists when the
pool forks, and concurrent.futures forks all workers before it starts its own thread (a worker
forked by distributed's nanny while a scheduler thread held a lock hung at start, twice in the
test suite; the local route imports no distributed).

Dask's local process scheduler (`dask.multiprocessing.get`, the diagnosis's map before) computes
a whole graph at once and cannot stream `simulate`'s unbounded chunks, so the local route is a
`concurrent.futures` pool of forked processes; Dask stays the route to other machines.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
from collections import deque
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any, Callable, Iterable, Iterator, Protocol, Sequence

#: seconds to wait for an existing scheduler (`--scheduler`) before giving up
CONNECT_TIMEOUT_S = 20.0


class SchedulerError(ValueError):
    """The Dask scheduler given cannot be reached: one line naming its address."""


# ------------------------------------------------------------------------------ worker processes
#: the job of `parallel_map`'s forked workers: (task, items, state), set just before they fork
_JOB: tuple | None = None
#: True in a worker process: its tasks' own maps run serially there (no pool in a pool)
_IN_WORKER = False
#: in a worker: the barrier of its pool (`_Pool.on_every_worker`), one party per worker
_BARRIER = None
#: in a worker: the BLAS / OpenMP thread limit it set (kept so that it stays set)
_THREADS = None


def available_workers() -> int:
    """CPUs this process may run on (its affinity mask where the OS has one)."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:                  # not Linux
        return max(os.cpu_count() or 1, 1)


def can_fork() -> bool:
    """Whether worker processes can be forked here (fork start method, not a worker of
    `parallel_map` or `Blocks` or another daemonic process)."""
    return "fork" in multiprocessing.get_all_start_methods() and not _nested()


def _nested() -> bool:
    return _IN_WORKER or multiprocessing.current_process().daemon


def _worker_init(barrier) -> None:
    """A worker process's start: one BLAS / OpenMP thread (threadpoolctl: the workers share the
    cores already; the superposition's solves limit themselves too, `fem.solver`), ends quietly
    when the parent ends the pool (the parent's SIGTERM handler, e.g. the CLI's, is not
    inherited), leaves Ctrl-C to the parent and runs its tasks' own maps serially."""
    global _IN_WORKER, _BARRIER, _THREADS
    import numpy  # noqa: F401, PLC0415 -- its BLAS loaded before the limit (a spawned worker)
    from threadpoolctl import threadpool_limits  # noqa: PLC0415

    _IN_WORKER, _BARRIER = True, barrier
    _THREADS = threadpool_limits(limits=1)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _once_in_this_worker(fn: Callable, args: tuple) -> Any:
    """fn(*args), then wait until every worker of the pool has done the same (so that each of
    the pool's n calls runs in another worker)."""
    try:
        return fn(*args)
    finally:
        _BARRIER.wait()


class _Pool:
    """`n` single-threaded worker processes forked from this process when it is set up (spawned
    where the OS cannot fork: they then import the modules and read the FE set-up themselves).
    `job`: what `parallel_map`'s workers read (`_JOB`) from the fork."""

    def __init__(self, n: int, job: tuple | None = None):
        global _JOB
        method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
        ctx = multiprocessing.get_context(method)
        self.n = n
        barrier = ctx.Barrier(n)
        self.executor = ProcessPoolExecutor(n, mp_context=ctx, initializer=_worker_init,
                                            initargs=(barrier,))
        _JOB = job
        try:
            # with fork, the first task forks all n workers now (concurrent.futures forks them
            # at once, before its own manager thread starts); it returns when one has run it
            self.executor.submit(int).result()
        except BaseException:
            self.close(cancel=True)
            raise
        finally:
            _JOB = None

    def submit(self, fn: Callable, *args) -> Future:
        return self.executor.submit(fn, *args)

    def on_every_worker(self, fn: Callable, *args) -> list:
        futures = [self.executor.submit(_once_in_this_worker, fn, args) for _ in range(self.n)]
        return [f.result() for f in futures]

    def close(self, cancel: bool = False) -> None:
        """Wait for the workers to end (they are then reaped: their CPU counts in this process's
        RUSAGE_CHILDREN); `cancel`: end the workers now and drop the tasks not started. Either
        way the pool's own thread has ended when this returns (no thread of it is left to hold
        a lock when this process forks again)."""
        if cancel:               # no public terminate in concurrent.futures
            for proc in list((getattr(self.executor, "_processes", None) or {}).values()):
                proc.terminate()
        self.executor.shutdown(wait=True, cancel_futures=cancel)


def _in_order(submit: Callable[[Any], Future], items: Iterable, ahead: int) -> Iterator:
    """submit(item) for each item, the results yielded in the items' order, with at most
    `ahead` items submitted and not yet yielded."""
    pending: deque = deque()
    for item in items:
        pending.append(submit(item))
        if len(pending) >= ahead:
            yield pending.popleft().result()
    while pending:
        yield pending.popleft().result()


# -------------------------------------------------------------------------- pure blocks: Blocks
class Blocks:
    """Where blocks run: here (no workers, no scheduler; also inside a worker), `workers`
    single-threaded processes forked from this one, or the Dask scheduler at `scheduler`. Use
    as a context manager: the workers are forked (or the scheduler connected) on entering."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None):
        self.workers, self.scheduler = workers, scheduler
        self._pool: _Pool | None = None
        self._client = None

    @property
    def here(self) -> bool:
        return self.scheduler is None and (self.workers is None or _nested())

    def __enter__(self) -> "Blocks":
        if self.scheduler is not None:
            from dask.distributed import Client  # noqa: PLC0415 -- only for a cluster

            try:
                self._client = Client(self.scheduler, timeout=CONNECT_TIMEOUT_S)
            except (OSError, TimeoutError, ValueError) as exc:
                raise SchedulerError(f"--scheduler {self.scheduler}: cannot connect "
                                     f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
                                     ) from None
        elif not self.here:
            self._pool = _Pool(max(1, int(self.workers)))
        return self

    def __exit__(self, exc_type, *exc) -> bool:
        if self._client is not None:
            self._client.close()
        if self._pool is not None:
            self._pool.close(cancel=exc_type is not None)
        self._pool = self._client = None
        return False

    def on_every_worker(self, fn: Callable, *args) -> list:
        """[fn(*args)] once in every worker process (here: once in this process), e.g. to
        build the per-process FE set-up or read a worker's CPU time (`bench --tolerance`)."""
        if self._pool is not None:
            return self._pool.on_every_worker(fn, *args)
        if self._client is not None:
            return list(self._client.run(fn, *args).values())
        return [fn(*args)]

    def slots(self) -> int:
        """Worker processes (threads on a Dask cluster) available; 1 here."""
        if self._pool is not None:
            return self._pool.n
        if self._client is not None:
            return max(1, sum(self._client.nthreads().values()))
        return 1

    def imap(self, fn: Callable, blocks: Iterable[tuple], ahead: int | None = None) -> Iterator:
        """fn(*b) for each block, yielded in block order; with workers at most `ahead` blocks
        (default 2 per worker) are submitted and not yet yielded."""
        if self._pool is not None:
            submit = lambda b: self._pool.submit(fn, *b)  # noqa: E731
        elif self._client is not None:
            submit = lambda b: self._client.submit(fn, *b, pure=False)  # noqa: E731
        else:
            for b in blocks:
                yield fn(*b)
            return
        yield from _in_order(submit, blocks, ahead or 2 * self.slots())

    def map(self, fn: Callable, blocks: Sequence[tuple],
            progress: Callable[[int, int], None] | None = None) -> list:
        """[fn(*b) for b in blocks], all submitted at once to the workers; `progress(done,
        total)` as the results come back in block order."""
        total = len(blocks)
        out = []
        for r in self.imap(fn, blocks, ahead=max(total, 1)):
            out.append(r)
            if progress is not None:
                progress(len(out), total)
        return out


def map_blocks(fn: Callable, blocks: Sequence[tuple], workers: int | None = None,
               scheduler: str | None = None, progress: Callable[[int, int], None] | None = None,
               where: Blocks | None = None) -> list:
    """[fn(*b) for b in blocks], here, on forked workers or on Dask (see the module docstring);
    `where`: an open `Blocks` to use (and leave open) instead of workers / scheduler."""
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
    the items' order): the items are handed to the workers in that order, one at a time per
    free worker. `state`: merged with each task's delta, in the items' order. An exception of a
    task is raised here, the first in the items' order."""
    items = list(items)
    n = min(int(workers), len(items))
    if n <= 1 or not can_fork():
        return [task(it) for it in items]
    order = list(dict.fromkeys(list(first or ()) + list(range(len(items)))))
    pool = _Pool(n, job=(task, items, state))
    try:
        got = dict(zip(order, _in_order(lambda i: pool.submit(_run_item, i), order, len(order))))
    except BaseException:
        pool.close(cancel=True)
        raise
    pool.close()
    results = []
    for i in range(len(items)):
        (kind, value), delta = got[i]
        if state is not None:
            state.merge(delta)
        if kind == "err":
            raise value
        results.append(value)
    return results
