"""The fit's stop on negligible steps (`studies.diagnosis.problem.NegligibleSteps`, Numerical
Recipes 3rd ed. ch. 15.5.2), on closed forms whose optimum is known exactly.

A curved valley (Rosenbrock's): residuals 10 (y - x^2) and w (1 - x) beside fixed unit-variance
noise e; the minimum is x = y = 1 with chi2 = e.e, whatever e, and the parameters' covariance
there is (J^T J)^-1 with J = [[-20, 10], [-w, 0]] (rows: the two valley residuals). With a weak
slope w = 0.3 along the floor, trust-region steps creep there, each lowering chi2 a little: the
stop must end the fit early yet within a small share of one standard uncertainty of the optimum
(a change of chi2 of 1 bounds the 68 % region of one parameter). A well-conditioned fit (two
decaying exponentials with noise) must end where the unstopped optimiser ends.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from scipy import optimize

from studies.diagnosis import problem
from studies.diagnosis.core import Space
from studies.diagnosis.problem import Problem

W_SLOPE = 0.3                      # the valley floor's slope residual per unit x (-)
NOISE = np.random.default_rng(1).standard_normal(50)   # fixed noise residuals (sigma 1)


def space_of(names, lo, hi):
    """A Space of plain parameters (off 0, scale 1: the scaled coordinate is the value)."""
    n = len(names)
    return Space([("toy", p) for p in names], {"toy": {p: 0.0 for p in names}}, [],
                 np.zeros(n), np.ones(n), np.asarray(lo, float), np.asarray(hi, float))


class Toy:
    """The least `Problem.fit` needs: residuals at a point of a Space, model calls counted."""
    fit = Problem.fit

    def __init__(self, residuals, names, lo, hi):
        self.residuals, self.calls = residuals, 0
        self.space = space_of(names, lo, hi)
        self.N = residuals(*lo).size
        self.nuisance = SimpleNamespace(names=())

    def eval(self, space, u):
        self.calls += 1
        z = self.residuals(*space.values(space.clip(u)))
        return z, {"z": z}


def valley(x, y):
    return np.concatenate([NOISE, [10.0 * (y - x * x), W_SLOPE * (1.0 - x)]])


def test_a_creeping_fit_stops_early_within_a_small_share_of_its_uncertainty(monkeypatch):
    pb = Toy(valley, ["x", "y"], [-5.0, -5.0], [5.0, 5.0])
    f = pb.fit(pb.space, np.array([-1.2, 1.0]))
    calls_stopped = pb.calls
    monkeypatch.setattr(problem, "DCHI2_STOP", -1.0)       # never negligible: scipy's tolerances
    pb.calls = 0
    full = pb.fit(pb.space, np.array([-1.2, 1.0]))
    assert np.allclose(full.u, [1.0, 1.0], atol=1e-5)      # the closed-form optimum
    chi2_min = float(NOISE @ NOISE)
    J = np.array([[-20.0, 10.0], [-W_SLOPE, 0.0]])
    sigma = np.sqrt(np.diag(np.linalg.inv(J.T @ J)))
    # within a quarter of a standard uncertainty, and chi2 within 5 % of the change of 1 that
    # bounds one parameter's 68 % region, in fewer than two thirds of the unstopped calls
    assert np.all(np.abs(f.u - 1.0) < 0.25 * sigma)
    assert 0.0 <= f.chi2 - chi2_min < 0.05
    assert calls_stopped < 2 / 3 * pb.calls


def test_a_well_conditioned_fit_ends_where_the_optimiser_ends():
    t = np.linspace(0.0, 10.0, 200)
    y = 50.0 * np.exp(-t) + 50.0 * np.exp(-t / 3.0) + np.random.default_rng(2).standard_normal(200)

    def decay(a1, t1, a2, t2):
        return a1 * np.exp(-t / t1) + a2 * np.exp(-t / t2) - y

    lo, hi = [0.0, 0.1, 0.0, 0.1], [200.0, 20.0, 200.0, 20.0]
    pb = Toy(decay, ["a1", "t1", "a2", "t2"], lo, hi)
    u0 = np.array([10.0, 0.5, 10.0, 8.0])
    f = pb.fit(pb.space, u0)
    ref = optimize.least_squares(lambda u: decay(*u), u0, bounds=(lo, hi), method="trf",
                                 diff_step=1e-3, ftol=1e-8, xtol=1e-8, gtol=1e-8)
    assert ref.status > 0
    sigma = np.sqrt(np.diag(np.linalg.inv(ref.jac.T @ ref.jac)))
    assert np.all(np.abs(f.u - ref.x) < 1e-3 * sigma)
    assert abs(f.chi2 - 2.0 * ref.cost) < 1e-6 * f.chi2
