"""The interference error's global search in two rounds (`fitspec.interference_starts`, then
`fitspec.interference_refine`) against the search it replaced, every point of the 1 um lines
and the grid (`fitspec.interference_search`) scored: the same best starts, bit for bit, in
fewer model calls. Toy model tests/test_diagnosis_workers.py's `opening_fit_toy`: the torque of an inner fit
that opens in the heat, so the scores are piecewise smooth over the band as on the real
pipeline; the hidden error at three places (inside a coarse interval, on a coarse point, near
the origin), and in a band narrowed by the assembly's tolerances off the lattice of whole um
(`assembly_bounds`: the lines then miss the origin)."""
import numpy as np
import pytest

from studies.diagnosis.designs import cycles
from studies.diagnosis.files import NUISANCE
from test_diagnosis_workers import opening_fit_toy


@pytest.mark.parametrize("inner_um, band", [(-3.0, None), (6.4, None), (0.6, None),
                                             (-3.0, ((-7.5, 12.25), (-3.3, 5.0)))])
def test_two_rounds_find_the_full_searchs_best_starts(inner_um, band):
    from studies.diagnosis import fitspec
    from studies.diagnosis.calibration import calibrate
    from studies.diagnosis.fitting import (_score_starts, _scored_here, _search,
                                           _start_points)
    from studies.diagnosis.problem import make_problem
    from studies.diagnosis.screening import screen
    from studies.model.effects import EFFECTS

    cond = cycles(n=120)
    T = cond["T_ambient_C"]
    toy = opening_fit_toy(T)

    truth = toy({"interference_error": {"inner_um": inner_um, "outer_um": 0.0}},
                {"mu_scale": 1.2})
    meas = {"torque_Nmm": truth["torque_Nmm"]
            + np.random.default_rng(5).normal(0.0, 0.002, T.size)}
    effect = EFFECTS["interference_error"]
    if band is not None:
        effect = effect.with_bounds(inner_um=band[0], outer_um=band[1])
    pb, b = calibrate(make_problem(toy, meas, cond, [effect], NUISANCE, workers=1))
    s = screen(pb, b)
    e = pb.effect("interference_error")
    info = s.candidates["interference_error"]
    space = pb.space([e])
    calls0 = pb.model.calls
    full = _score_starts(pb, space, _start_points(pb, e, info, b.fit, space,
                                                  fitspec.interference_search(e)), b.fit.J)
    n_full = pb.model.calls - calls0
    pb.model.cache.clear()
    calls0 = pb.model.calls
    two = _search(pb, e, info, b.fit, space, _scored_here(pb, space, b.fit.J))
    n_two = pb.model.calls - calls0
    for (sse2, _, u2), (sse1, _, u1) in zip(two[:2], full[:2]):
        assert sse2 == sse1 and np.array_equal(u2, u1)
    assert [i == 0 for _, i, _ in two[:2]] == [i == 0 for _, i, _ in full[:2]]  # the GN step
    assert n_two < (0.7 if band is None else 0.9) * n_full    # a narrow band saves less
