"""The pair stage solves each distinct row once (`studies.model.stages.bearing.distinct_rows`):
requirement (speed): the pair state of a table with repeated rows equals, bit for bit,
the state of the same table solved row by row (every row through `analytic.bearing.solve_pair`),
for the axial-only, the combined-load (radial load and moment, tilting rotor) and the
quasi-dynamic solvers, position and spring preload. The reference is the unchanged solver on
every row; the rows in each block are chosen so that the repeated rows sit among distinct ones
(the stopping rules of the iterations take the largest over the rows)."""
from __future__ import annotations

from dataclasses import fields, replace

import numpy as np
import pytest

from analytic.bearing import solve_pair
from studies.model.config import load_shipped
from studies.model.stages import bearing as stage


def _arguments(asm, n_distinct: int, repeats: int, radial: bool, seed: int = 0) -> dict:
    """`solve_pair` arguments of a table of n_distinct rows, each repeated `repeats` times in a
    shuffled order: groove-centre shifts of a few um, temperatures -40..60 C, preloads."""
    rng = np.random.default_rng(seed)
    idx = rng.permutation(np.repeat(np.arange(n_distinct), repeats))
    T = rng.uniform(-40.0, 60.0, n_distinct)[idx]
    dr = rng.uniform(-2e-3, 2e-3, (2, n_distinct))[:, idx]
    dz = rng.uniform(-1e-3, 1e-3, (2, n_distinct))[:, idx]
    P = rng.choice([0.5, 1.0, 2.0], n_distinct)[idx] * asm.preload.assembled_N
    zeros = np.zeros(idx.size)
    return dict(dr_mm=dr, dz_mm=dz, T_inner_ring_C=T, T_outer_ring_C=T - 1.0, T_ball_C=T - 0.5,
                T_ref_C=asm.T_ref_C, preload_kind=asm.preload.kind, preload_assembled_N=P,
                axial_load_N=zeros, radial_load_N=zeros + (0.3 * asm.preload.assembled_N
                                                           if radial else 0.0),
                moment_Nmm=zeros + (20.0 * asm.preload.assembled_N if radial else 0.0),
                bearing_span_mm=20.0, speed_rpm=zeros + asm.lubrication.speed_rpm,
                ball_model=asm.operating.ball_model, control=asm.operating.raceway_control,
                dr_ref_mm=np.zeros((2, 1)), dz_ref_mm=np.zeros((2, 1)), compliance_mm_per_N=2e-5)


def _assert_equal(a, b, path="state"):
    if a is None or b is None:
        assert a is None and b is None, path
        return
    if hasattr(a, "__dataclass_fields__"):
        for f in fields(a):
            _assert_equal(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
        return
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, path
    assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), path


@pytest.mark.parametrize("key, radial, dynamic, kind", [
    ("seed001", False, False, "position"), ("seed001", True, False, "position"),
    ("seed000", False, False, "position"), ("seed000", True, False, "spring"),
    ("seed001", False, True, "position")])
def test_distinct_rows_give_the_row_by_row_state_bit_for_bit(key, radial, dynamic, kind):
    asm = load_shipped(key)
    asm = replace(asm, preload=replace(asm.preload, kind=kind))
    if dynamic:
        asm = replace(asm, operating=replace(asm.operating, ball_model="quasi_dynamic"))
    st = stage.BearingStage(asm, 20.0)
    args = _arguments(asm, 8, 3, radial)
    n = args["T_inner_ring_C"].size
    first, inverse = stage.distinct_rows(args, n)
    assert first.size == 8 and np.array_equal(args["T_inner_ring_C"][first][inverse],
                                               args["T_inner_ring_C"])
    calls = []
    solve = stage.solve_pair

    def counted(g, arr, **kw):
        calls.append(np.shape(kw["T_inner_ring_C"])[-1])
        return solve(g, arr, **kw)

    stage.solve_pair = counted
    try:
        got = st.solve(args)
    finally:
        stage.solve_pair = solve
    assert calls == [8]                         # the distinct rows only, once
    _assert_equal(got, solve_pair(st.geom, asm.arrangement, **args))


def test_rows_compared_by_their_bits():
    """-0.0 and 0.0 are different rows (a solver may take the sign); mostly distinct rows are
    solved as they are (None)."""
    a = {"x": np.array([0.0, -0.0, 0.0, 1.0, 1.0]), "setting": "outer"}
    first, inverse = stage.distinct_rows(a, 5)
    assert list(first) == [0, 1, 3] and list(inverse) == [0, 1, 0, 2, 2]
    assert stage.distinct_rows({"x": np.arange(10.0)}, 10) is None
