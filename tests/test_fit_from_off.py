"""The fit from off (`studies.diagnosis.fitting.fit_from_off`), on closed forms: a form that jumps
at off (the configured model at off, a step away from it at any value inside the bounds, as the
`thermal_transient_fe` rung's interior lag at a finite film) answers off itself, without a local
fit; a form continuous at off is fitted from there as before."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from studies.diagnosis.core import Fit, Space
from studies.diagnosis.fitting import OFF_JUMP_CHI2, fit_from_off, jumps_at_off
from studies.diagnosis.problem import Problem

N = 40
X = np.linspace(0.0, 1.0, N)          # the rows' condition (-)
JUMP = 0.5                            # the jump's size (residual units, sigma 1)
P_TRUE = 2.0


class Toy:
    """The least `fit_from_off` needs of a `Problem`: residuals at a point of a one-parameter
    Space (bounds 0..10, off 0, no nuisance), its model calls counted."""
    fit = Problem.fit
    start = staticmethod(Problem.start)

    def __init__(self, form, y):
        self.form, self.y, self.N, self.calls = form, y, N, 0
        self.nuisance = SimpleNamespace(names=())
        self.space = Space([("toy", "p")], {"toy": {"p": 0.0}}, [], np.array([0.0]),
                           np.array([1.0]), np.array([0.0]), np.array([10.0]))

    def eval(self, space, u):
        self.calls += 1
        p = space.unpack(space.clip(u))[0]["toy"]["p"]
        pred = self.form(p)
        return pred - self.y, {"y": pred}

    def base(self):
        """The baseline: the form at off, no nuisance (an empty Jacobian)."""
        z, pred = self.eval(self.space, np.zeros(1))
        return Fit(Space([], {}, [], np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)),
                   np.zeros(0), z, np.zeros((N, 0)), float(z @ z), pred)

    def info(self, base):
        """The one-sided sensitivity at off (`screening.sensitivity`: minus the change of the
        residuals over one scaled unit)."""
        z1, _ = self.eval(self.space, np.ones(1))
        return SimpleNamespace(sensitivity=-(z1 - base.z)[:, None])


def jumping(p):
    """0 at off, JUMP + 0.1 p X at every p > 0 (a step at off)."""
    return np.zeros(N) if p == 0.0 else JUMP + 0.1 * p * X


def test_a_form_that_jumps_at_off_answers_off_without_a_local_fit():
    pb = Toy(jumping, np.zeros(N))                # data the configured model makes
    base = pb.base()
    info = pb.info(base)
    assert jumps_at_off(pb, pb.space, base)
    calls = pb.calls
    f = fit_from_off(pb, pb.space, info, base)
    assert N * JUMP ** 2 > OFF_JUMP_CHI2          # a jump the rule sees
    assert f.u.tolist() == [0.0] and f.chi2 == base.chi2 == 0.0
    assert pb.calls - calls == 2                  # its start and off: no least squares
    assert np.array_equal(f.J[:, 0], -info.sensitivity[:, 0])
    # the local fit from the start would end at the jump's edge, worse than off
    assert pb.fit(pb.space, np.zeros(1)).chi2 > N * JUMP ** 2 * 0.99


def test_a_form_continuous_at_off_is_fitted_from_off():
    """The bounded least-squares fit from off, the same as the engine's fit from there (and
    below the baseline: the data have the effect)."""
    form = lambda p: p * X                       # noqa: E731
    pb = Toy(form, form(P_TRUE))
    base = pb.base()
    assert not jumps_at_off(pb, pb.space, base)
    f = fit_from_off(pb, pb.space, pb.info(base), base)
    ref = pb.fit(pb.space, np.zeros(1))
    assert np.array_equal(f.u, ref.u) and f.chi2 == ref.chi2
    assert 0.0 < f.u[0] and f.chi2 < base.chi2
