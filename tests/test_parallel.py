"""The one parallel map (`studies.model.parallel`): a local Dask cluster's workers are forked from
a fork server with the model imported; `parallel_map` hands its `first` items to Dask's local
process scheduler first. Results equal to one process: tests/test_tolerances.py (Monte Carlo),
tests/test_stream.py (simulate), tests/test_diagnosis_workers.py (the diagnosis)."""
from __future__ import annotations

import os
import time

import pytest

from studies.model import parallel
from studies.model.parallel import Blocks, can_fork, parallel_map

def _seen() -> tuple:
    """In a worker: its process id, the start method's parent and whether the model's route is
    imported before the worker ran anything of it."""
    import multiprocessing
    import sys
    return os.getpid(), multiprocessing.parent_process() is not None, \
        "studies.model.tolerance_samples" in sys.modules


@pytest.mark.skipif(parallel.LOCAL_START_METHOD != "forkserver", reason="workers spawned here")
def test_local_cluster_workers_start_from_the_fork_server_with_the_model_imported():
    """Each worker is its own process (not this one), forked from the fork server that imported
    FORKSERVER_PRELOAD once: the model's route is there before any task ran."""
    with Blocks(workers=2) as where:
        seen = list(where.client.run(_seen).values())
    assert len(seen) == 2 and len({pid for pid, _, _ in seen} | {os.getpid()}) == 3
    assert all(imported for _, _, imported in seen)


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


@pytest.mark.skipif(not can_fork(), reason="no fork start method here")
def test_parallel_map_starts_the_first_items_first(tmp_path):
    """Two processes, five items, `first` = [4, 3]: Dask's scheduler hands out one task per free
    process, so items 4 and 3 start before any other (the one handed out next waits for one of
    them to end); the results keep the items' order."""
    path = str(tmp_path / "started.txt")
    items = [(path, i) for i in range(5)]
    assert parallel_map(_record, items, 2, first=[4, 3]) == [0, 1, 2, 3, 4]
    started = [int(v) for v in open(path).read().split()]
    assert sorted(started) == [0, 1, 2, 3, 4] and set(started[:2]) == {3, 4}
