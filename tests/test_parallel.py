"""The one parallel map (`studies.model.parallel`): local workers are processes forked from this
one, single-threaded, each its own; a block's error is raised here and ends the workers; `imap`
draws blocks no further than `ahead` past the results it yielded; `parallel_map` hands its
`first` items out first. Results equal to one process: tests/test_tolerances.py (Monte Carlo),
tests/test_stream.py (simulate), tests/test_parametric.py (design screening),
tests/test_diagnosis_workers.py (the diagnosis)."""
from __future__ import annotations

import os
import time

import pytest

from studies.model.parallel import Blocks, can_fork, parallel_map

needs_fork = pytest.mark.skipif(not can_fork(), reason="no fork start method here")


def _seen() -> tuple:
    """In a worker: its process id, its parent's, whether the model's route is imported before
    the worker ran anything of it, the BLAS / OpenMP threads of every loaded library, and
    whether a `Blocks` of 2 workers opened there would run here (no pool in a pool)."""
    import sys

    from threadpoolctl import threadpool_info

    return (os.getpid(), os.getppid(), "studies.model.tolerance_samples" in sys.modules,
            {lib["num_threads"] for lib in threadpool_info()}, Blocks(workers=2).here)


@needs_fork
def test_local_workers_are_forked_from_this_process_single_threaded():
    """`on_every_worker` runs once in each of the 2 workers: two processes other than this one,
    whose parent is this process, with the model's modules this process imported, one thread
    per BLAS / OpenMP library (threadpoolctl, whatever this process has), and nested `Blocks`
    that run in the worker itself."""
    import studies.model.tolerance_samples  # noqa: F401 -- imported here before the fork

    with Blocks(workers=2) as where:
        assert not where.here and where.slots() == 2
        seen = where.on_every_worker(_seen)
    assert len(seen) == 2 and len({pid for pid, *_ in seen} | {os.getpid()}) == 3
    assert all(parent == os.getpid() and imported and threads <= {1} and nested_here
               for _, parent, imported, threads, nested_here in seen), seen


def _running(pid: int) -> bool:
    """Whether the process exists and is not a zombie (Linux /proc; elsewhere: assumed ended)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def _fail_on_three(i: int) -> int:
    if i == 3:
        raise ValueError(f"block {i} failed")
    time.sleep(0.05)
    return i


@needs_fork
def test_a_failing_block_is_raised_here_and_ends_the_workers():
    """The block's own exception comes back from `map`; leaving the `with` on it ends the
    workers without waiting for the blocks still queued (20 more of 0.05 s each), and the
    workers' processes are gone."""
    with pytest.raises(ValueError, match="block 3 failed"):
        with Blocks(workers=2) as where:
            pids = {pid for pid, *_ in where.on_every_worker(_seen)}
            where.map(_fail_on_three, [(i,) for i in range(24)])
    deadline = time.monotonic() + 10.0      # terminated, then reaped by the pool's thread
    while time.monotonic() < deadline and any(_running(p) for p in pids):
        time.sleep(0.05)
    alive = [p for p in pids if _running(p)]
    assert not alive, alive


def _square(x: int) -> int:
    return x * x


@needs_fork
def test_imap_draws_at_most_ahead_blocks_past_its_results():
    """`imap(ahead=3)` over a generator of 12 blocks: when the k-th result (k = 1, 2, ...) is
    yielded, at most 3 + k - 1 blocks have been drawn (memory bounded for any number of blocks),
    and the results are the blocks' squares in block order."""
    drawn = []

    def blocks():
        for i in range(12):
            drawn.append(i)
            yield (i,)
    got = []
    with Blocks(workers=2) as where:
        for k, r in enumerate(where.imap(_square, blocks(), ahead=3), start=1):
            assert len(drawn) <= 3 + k - 1, (k, len(drawn))
            got.append(r)
    assert got == [i * i for i in range(12)]


def _record(path_and_item) -> int:
    """Append the item to the file (O_APPEND: one line per task, in start order); items 3 and 4
    then wait (up to 60 s) until two lines are there, so that no task ends, and none is handed
    out after it, before both have started."""
    path, item = path_and_item
    with open(path, "a") as f:
        f.write(f"{item}\n")
    deadline = time.monotonic() + 60.0
    while item in (3, 4) and len(open(path).read().split()) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    return item


@needs_fork
def test_parallel_map_starts_the_first_items_first(tmp_path):
    """Two processes, five items, `first` = [4, 3]: the items are handed out in that order, one
    per free process, so items 4 and 3 start before any other (the one handed out next waits for
    one of them to end); the results keep the items' order."""
    path = str(tmp_path / "started.txt")
    items = [(path, i) for i in range(5)]
    assert parallel_map(_record, items, 2, first=[4, 3]) == [0, 1, 2, 3, 4]
    started = [int(v) for v in open(path).read().split()]
    assert sorted(started) == [0, 1, 2, 3, 4] and set(started[:2]) == {3, 4}
