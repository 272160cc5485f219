"""Independent candidate work of a diagnosis on several processes (issue 11).

The model calls are bound by the interpreter lock, so a second core helps only through a second
process. `fork_map` runs one task per item (a candidate's fit, its held-out refits, a generalised
form's fits) in forked copies of the engine: a forked worker shares the parent's FE set-up,
pipeline and model cache as they are at the fork, without pickling or rebuilding anything. Each
task is a pure function of the engine state at the fork and its item (no random numbers: the
bootstrap stays in the parent, in the serial order), so every result is the one a serial run
computes, to the last bit; results come back in the items' order. Counted on the parent's
`CachedModel`: each task's model calls and seconds (summed over the workers, so the model
seconds can exceed the wall time) and the model results it computed (later phases find them in
the cache, as in a serial run).

Forking needs the "fork" start method (Linux; elsewhere, or inside a daemonic process such as a
process-pool worker, the tasks run serially in this process).
"""
from __future__ import annotations

import multiprocessing
import os
import signal
from typing import Callable, Sequence

#: the job of the forked workers: (cached model, task, items), set just before the fork
_JOB: tuple | None = None


def available_workers() -> int:
    """CPUs this process may run on (its affinity mask where the OS has one)."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:                  # not Linux
        return max(os.cpu_count() or 1, 1)


def can_fork() -> bool:
    """Whether worker processes can be forked here (fork start method, not a daemonic process)."""
    return ("fork" in multiprocessing.get_all_start_methods()
            and not multiprocessing.current_process().daemon)


def _worker_signals() -> None:
    """A worker ends quietly when the parent ends the pool (the parent's SIGTERM handler, e.g.
    the CLI's, is not inherited) and leaves Ctrl-C to the parent."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run(i: int):
    """One task in a worker: (("ok", value) or ("err", exception), model calls, model seconds,
    new model-cache entries)."""
    model, task, items = _JOB
    if model is None:
        calls0, sec0, known = 0, 0.0, set()
    else:
        calls0, sec0, known = model.calls, model.seconds, set(model.cache)
    try:
        out = ("ok", task(items[i]))
    except Exception as exc:                # re-raised in the parent, in the items' order
        out = ("err", exc)
    if model is None:
        return out, 0, 0.0, []
    new = [(k, v) for k, v in model.cache.items() if k not in known]
    return out, model.calls - calls0, model.seconds - sec0, new


def fork_map(model, task: Callable, items: Sequence, workers: int,
             first: Sequence[int] | None = None) -> list:
    """[task(item) for item in items], on up to `workers` forked processes when `workers` > 1,
    there are at least two items and `can_fork()`; else serially here. `model`: the engine's
    `CachedModel` (its counters and cache are updated with the workers' calls), or None. `first`: indices
    of items to start first (the longest tasks: better balance; results keep the items' order).
    An exception of a task is raised here, the first in the items' order."""
    items = list(items)
    n = min(int(workers), len(items))
    if n <= 1 or not can_fork():
        return [task(it) for it in items]
    global _JOB
    order = list(dict.fromkeys(list(first or ()) + list(range(len(items)))))
    _JOB = (model, task, items)
    pool = multiprocessing.get_context("fork").Pool(n, initializer=_worker_signals)
    try:
        got = dict(zip(order, pool.imap(_run, order, chunksize=1)))
        pool.close()                        # every task done: the workers exit by themselves
    except BaseException:
        pool.terminate()
        raise
    finally:
        pool.join()
        _JOB = None
    results = []
    for i in range(len(items)):
        (kind, value), calls, seconds, new = got[i]
        if model is not None:
            model.calls += calls
            model.seconds += seconds
            for k, v in new:
                model.remember(k, v)
        if kind == "err":
            raise value
        results.append(value)
    return results
