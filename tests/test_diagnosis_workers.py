"""The diagnosis on worker processes (`studies.model.parallel.parallel_map`, issue 11
performance): the same result as in one process, to the last bit; the map keeps the items' order,
counts the workers' model calls and raises a task's exception."""
from __future__ import annotations

import json

import numpy as np
import pytest

from studies.diagnosis.core import CachedModel
from studies.diagnosis.designs import cycles
from studies.diagnosis.engine import diagnose_full
from studies.diagnosis.files import NUISANCE, ModelPredictor, candidate_effects
from studies.diagnosis.result import to_json
from studies.model.parallel import can_fork, parallel_map
from studies.model.config import load_shipped
from studies.model.pipeline import Pipeline

needs_fork = pytest.mark.skipif(not can_fork(), reason="no fork start method here")

#: timings and call counts depend on the processes (the cache of a worker is its own)
VARYING = ("seconds", "seconds_by_phase", "n_predict_calls", "predict_calls_by_phase",
           "predict_calls_fit")


def _without(x, keys=VARYING):
    if isinstance(x, dict):
        return {k: _without(v, keys) for k, v in x.items() if k not in keys}
    if isinstance(x, list):
        return [_without(v, keys) for v in x]
    return x


@needs_fork
@pytest.mark.parametrize("workers", [1, 2])
def test_parallel_map_order_counts_and_errors(workers):
    model = CachedModel(lambda eff, nuis: {"y": np.full(3, nuis["a"])}, 3)

    def task(a):
        if a == 3.0:
            raise ValueError("three")
        return float(model({}, {"a": a})["y"].sum())

    assert parallel_map(task, [0.0, 1.0, 2.0], workers, first=[2], state=model) == [0.0, 3.0, 6.0]
    assert model.calls == 3 and len(model.cache) == 3     # the workers' calls and results
    assert model({}, {"a": 1.0})["y"][0] == 1.0 and model.calls == 3     # a cache hit here
    with pytest.raises(ValueError, match="three"):
        parallel_map(task, [4.0, 3.0], workers, state=model)


@pytest.mark.slow        # over 4 s: runs in `make test-slow`
@needs_fork
def test_diagnosis_on_two_workers_equals_one_process():
    """A settling that creeps (profiled threshold: profiled fits and held-out refits, and the
    generalised forms' phase with its profiled local fit) on 120 rows of cycles: every number
    of the result is the same with two worker processes as in one."""
    pl = Pipeline(load_shipped("seed000"), mesh_factor=2.0)
    cond = cycles(n=120)
    sigma = {"torque_Nmm": 0.02, "preload_N": 0.5}
    truth = ModelPredictor(pl, cond, tuple(sigma))(
        {"preload_settling.creep": {"loss_N": 5.0, "threshold_K": 50.0, "creep_N_per_h": 3.0}},
        {"mu_scale": 1.25})
    rng = np.random.default_rng(3)
    meas = {c: truth[c] + rng.normal(0.0, s, truth[c].size) for c, s in sigma.items()}
    out = {}
    for workers in (1, 2):
        pred = ModelPredictor(pl, cond, tuple(sigma))
        res = diagnose_full(pred, meas, cond, candidate_effects(pl.asm), NUISANCE,
                            T_ref_C=pl.asm.T_ref_C, predict_at=pred.at, workers=workers)
        out[workers] = json.dumps(_without(to_json(res)), sort_keys=True)
    assert json.loads(out[1])["verdict"] == "explained"
    assert out[2] == out[1]
