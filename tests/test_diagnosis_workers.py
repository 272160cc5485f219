"""The diagnosis on worker processes (`studies.model.parallel.parallel_map`, for
speed): the same result as in one process, to the last bit; the map keeps the items' order,
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


def opening_fit_toy(T_C):
    """A toy model of the torque of an inner fit that opens in the heat (its interference
    4 um + inner_um - 0.1 um/K above 20 C, the torque 1 + 0.05 per um of it, times mu_scale,
    plus a small outer-fit term): scores piecewise smooth over the band as on the real
    pipeline. T_C: the rows' ambient (C)."""
    def toy(effects, nuisance):
        p = effects.get("interference_error", {"inner_um": 0.0, "outer_um": 0.0})
        d = np.maximum(4.0 + p["inner_um"] - 0.1 * (T_C - 20.0), 0.0)
        return {"torque_Nmm": nuisance["mu_scale"] * (1.0 + 0.05 * d
                                                      + 1e-4 * p["outer_um"] * T_C)}
    return toy


@needs_fork
def test_global_search_on_workers_scores_as_its_fit_task():
    """`fitting.searched_starts` (a global search's rounds scored on two workers before the
    fits) against the route of its fit task, `fitting._search` scoring in one process: the same
    ranked (chi-square, index, start) list to the last bit, and as many model calls (the starts
    the grid and the lines share scored once, as the one task's cache does). Toy model: the
    torque of an inner fit that opens in the heat (its interference 4 um + inner_um - 0.1 um/K
    above 20 C), so the scores are piecewise smooth over the band as on the real pipeline."""
    from studies.diagnosis.calibration import calibrate
    from studies.diagnosis.fitting import _scored_here, _search, searched_starts
    from studies.diagnosis.problem import make_problem
    from studies.diagnosis.screening import screen
    from studies.model.effects import EFFECTS

    cond = cycles(n=120)
    T = cond["T_ambient_C"]
    toy = opening_fit_toy(T)

    truth = toy({"interference_error": {"inner_um": -3.0, "outer_um": 0.0}}, {"mu_scale": 1.2})
    meas = {"torque_Nmm": truth["torque_Nmm"]
            + np.random.default_rng(5).normal(0.0, 0.002, T.size)}
    got = {}
    for workers in (2, 1):
        pb, b = calibrate(make_problem(toy, meas, cond, [EFFECTS["interference_error"]],
                                       NUISANCE, workers=workers))
        s = screen(pb, b)
        assert s.identifiable == ["interference_error"]
        calls0 = pb.model.calls
        if workers == 2:
            res = searched_starts(pb, s, b, ["interference_error"])["interference_error"]
            got[2] = (res.scored, res.calls, pb.model.calls - calls0)
        else:
            e = pb.effect("interference_error")
            space = pb.space([e])
            ranked = _search(pb, e, s.candidates["interference_error"], b.fit, space,
                             _scored_here(pb, space, b.fit.J))
            got[1] = (ranked, pb.model.calls - calls0)
    (scored2, calls2, counted2), (scored1, calls1) = got[2], got[1]
    assert calls2 == counted2 == calls1 < len(scored1)        # repeated starts: one call each
    assert len(scored2) == len(scored1)
    for (sse2, i2, u2), (sse1, i1, u1) in zip(scored2, scored1):
        assert sse2 == sse1 and i2 == i1 and np.array_equal(u2, u1)
