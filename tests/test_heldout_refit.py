"""The held-out refit of a profiled candidate (`heldout._refit_rows`) starts from the better of
its linearised step and the full-data fit on the kept rows: a linearised step across a strongly
nonlinear parameter can land far from both, and chord steps with the Jacobian held then never
leave it (th_mount_preload_loss seed 1: a 12 N preload loss beside the rung started its held-out
refits at 40 times the full fit's training chi-square and was refused with a held-out gain of
-3.4 noise units).

On the linear toy of tests/test_diagnosis_phases.py (y = mu (1 + x) + k x^2, sigma given) the
full-data fit is the least-squares solution (numpy lstsq); a chord Jacobian of the wrong sign
makes every step rise, so the refit stays at its start: at the far start alone, or at the full
fit when it is given as the fallback."""
from __future__ import annotations

import numpy as np

from studies.diagnosis.heldout import _refit_rows
from tests.test_diagnosis_phases import CANDIDATES, SIGMA, X, problem


def _setup():
    rng = np.random.default_rng(3)
    y = 1.2 * (1.0 + X) + 0.3 * X ** 2 + rng.normal(0.0, SIGMA, X.size)
    pb = problem(y)
    sq = next(c for c in CANDIDATES if c.name == "square")
    space = pb.space([sq])
    fit = pb.fit(space, np.zeros(space.lo.size))
    A = np.column_stack([X ** 2, 1.0 + X])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    sse_lstsq = float(np.sum((y - A @ coef) ** 2)) / SIGMA ** 2
    return pb, space, fit, sse_lstsq


def test_the_full_fit_is_the_least_squares_solution():
    pb, space, fit, sse_lstsq = _setup()
    assert abs(fit.chi2 - sse_lstsq) <= 1e-6 * sse_lstsq


def test_a_far_start_gives_way_to_the_full_fit_on_the_kept_rows():
    pb, space, fit, _ = _setup()
    rows = np.arange(pb.N) >= pb.N // 5                  # the first fifth held out
    far = fit.u + np.array([30.0, 0.0])                  # k 0.3 higher than the fit (scale 0.01)
    kept = lambda z: float(z[rows] @ z[rows])            # noqa: E731
    at_fit = kept(fit.z)
    z_far = _refit_rows(pb, space, far, rows, -fit.J)
    z_fb = _refit_rows(pb, space, far, rows, -fit.J, fallback=(fit.u, fit.z))
    z_far0, _ = pb.eval(space, space.clip(far))
    assert kept(z_far) == kept(z_far0) > 10.0 * at_fit    # stuck at the far start
    assert kept(z_fb) <= at_fit                            # never worse than the full fit
    # a start better than the fallback is kept (the fallback only replaces a worse one)
    z_own = _refit_rows(pb, space, fit.u, rows, fit.J, fallback=(far, z_far0))
    assert kept(z_own) <= at_fit
