"""`ladder.FormRoute.columns` evaluates each distinct input row once (`PhysicsInputs.
distinct_rows`): on a table whose rows repeat, its columns are the whole table's evaluation row
by row (the route is row by row: each row's numbers its own to round-off), and a table without
repeats is evaluated as it is. The reference is the route's own evaluation of every row
(`FormRoute._columns`), the second way of computing the same columns."""
from __future__ import annotations

import numpy as np
import pytest

from studies.diagnosis.ladder import FormRoute
from studies.model.config import load_shipped
from studies.model.inputs import baseline_inputs
from studies.model.pipeline import Pipeline

MESH_FACTOR = 2.0
COLUMNS = ("preload_N", "torque_Nmm", "fit_pressure_inner_MPa", "contact_angle_deg",
           "axial_stiffness_N_per_um")


@pytest.fixture(scope="module")
def pl():
    return Pipeline(load_shipped("seed000"), mesh_factor=MESH_FACTOR)


def _inputs(pl, amb, speed):
    asm = pl.asm
    n = len(amb)
    inp = baseline_inputs({"T_ambient_C": np.asarray(amb, float), "time_s": 60.0 * np.arange(n),
                           "speed_rpm": np.asarray(speed, float)}, n, asm.T_ref_C,
                          asm.preload.assembled_N, asm.lubrication.speed_rpm)
    return inp


def test_repeated_rows_are_evaluated_once_and_equal_the_whole_table(pl):
    """Cycles sampled so that temperatures and speeds repeat (as a table sampled every minute
    does): the distinct rows are found in row order, and the columns equal the evaluation of
    every row to 1e-12 of each column's scale."""
    amb = [20.0, 35.0, 50.0, 35.0, 20.0, 35.0, 50.0, 20.0]
    speed = [3000.0, 3000.0, 6000.0, 3000.0, 3000.0, 6000.0, 6000.0, 3000.0]
    inp = _inputs(pl, amb, speed)
    first, inverse = inp.distinct_rows()
    # the distinct (ambient, speed) pairs in order of their first row
    assert first.tolist() == [0, 1, 2, 5]
    assert inverse.tolist() == [0, 1, 2, 1, 0, 3, 2, 0]
    route = FormRoute(pl)
    got = route.columns(inp, {}, COLUMNS)
    ref = route._columns(inp, {}, COLUMNS)
    for c in COLUMNS:
        scale = np.max(np.abs(ref[c]))
        assert scale > 0.0, c
        assert np.max(np.abs(got[c] - ref[c])) <= 1e-12 * scale, c
        # rows with the same inputs answer the same numbers
        assert np.array_equal(got[c][[0, 4, 7]], np.full(3, got[c][0])), c


def test_a_table_without_repeats_takes_the_plain_path(pl):
    """No row repeats another (the time alone differs between rows, and the route does not read
    it: every other input distinct): no distinct-row evaluation, the columns bit for bit the
    whole table's."""
    inp = _inputs(pl, [20.0, 30.0, 40.0], [3000.0, 3000.0, 3000.0])
    assert inp.distinct_rows() is None
    route = FormRoute(pl)
    got = route.columns(inp, {}, COLUMNS)
    ref = route._columns(inp, {}, COLUMNS)
    for c in COLUMNS:
        assert np.array_equal(got[c], ref[c]), c


def test_rows_differing_in_one_input_alone_are_distinct(pl):
    """A per-row input the route reads (here the fit's offset of one row) makes its row
    distinct: the distinct rows are compared on every such input, not the temperatures alone."""
    inp = _inputs(pl, [20.0, 20.0, 20.0], [3000.0, 3000.0, 3000.0])
    off = np.zeros(3)
    off[2] = 1.0
    inp = inp.copy(interference_inner_um=off)
    first, inverse = inp.distinct_rows()
    assert first.tolist() == [0, 2] and inverse.tolist() == [0, 0, 1]
