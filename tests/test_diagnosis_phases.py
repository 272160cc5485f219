"""Each diagnosis phase is a function of an immutable `Problem` and typed results: here one phase
at a time on a small linear model whose answers are closed forms (numpy least squares, principal
angles), independent of the engine's own numbers.

The model: rows x in [-1, 1], prediction y = mu (1 + x) + a (1 + x) + b x^2 + c (x^2 + x^3 / 2)
with the nuisance mu (a friction-like scale) and three one-parameter candidates a, b, c that act
additively; the noise level is given (sigma = 0.01), so the standardised residuals are
(measured - y) / sigma exactly and every sensitivity is a fixed vector.
"""
from __future__ import annotations

import numpy as np
import pytest

from studies.diagnosis.core import Baseline
from studies.diagnosis.fitting import fit_all
from studies.diagnosis.problem import make_problem
from studies.diagnosis.screening import screen
from studies.diagnosis.stats import orth
from studies.model.effects.base import Effect

N = 60
X = np.linspace(-1.0, 1.0, N)
SIGMA = 0.01
SHAPES = {"same_as_mu": 1.0 + X, "square": X ** 2, "square_cube": X ** 2 + 0.5 * X ** 3}
NUISANCE = {"mu": (0.5, 2.0, 1.0, 0.05)}


class Linear(Effect):
    """A one-parameter additive candidate (the diagnosis only sees it through `predict`)."""
    parameters = ("k",)
    units = {"k": "-"}
    bounds = {"k": (-1.0, 1.0)}
    off = {"k": 0.0}
    scale = {"k": 0.01}

    def __init__(self, name):
        self.name = name


CANDIDATES = [Linear(n) for n in SHAPES]


def predict(effects, nuisance):
    y = nuisance["mu"] * (1.0 + X)
    for name, p in effects.items():
        y = y + p["k"] * SHAPES[name]
    return {"y": y}


def problem(measured_y):
    return make_problem(predict, {"y": measured_y}, {"x": X}, CANDIDATES, NUISANCE,
                        noise_sigma={"y": SIGMA})


def baseline_of(pb) -> Baseline:
    """The nuisance-only fit as phase 1 hands it on (built here from `Problem.fit`, so that the
    phase under test runs alone)."""
    space = pb.space([])
    f = pb.fit(space, np.zeros(1))
    return Baseline(f, space.unpack(f.u)[1], pb.describe(f.pred, 1), False, f.z, orth(f.J))


def projected(v, basis):
    """v with its least-squares projection on span(basis) removed."""
    coef, *_ = np.linalg.lstsq(basis, v, rcond=None)
    return v - basis @ coef


def test_screening_alone_remaining_fractions_and_lookalike_are_the_closed_forms():
    """Screening: a candidate whose shape the nuisance produces (1 + x) keeps nothing after the
    projection (not identifiable, absorbed); the others keep |P v| / |v| of their shape, P the
    projection off span(1 + x); the look-alike cosine of two one-dimensional candidates is
    |<P v, P w>| / (|P v| |P w|). All by numpy least squares on the shapes themselves."""
    rng = np.random.default_rng(1)
    pb = problem(1.2 * (1.0 + X) + 0.3 * X ** 2 + rng.normal(0.0, SIGMA, N))
    s = screen(pb, baseline_of(pb))
    base = (1.0 + X)[:, None]
    assert s.candidates["same_as_mu"].status == "not_identifiable"
    assert "absorbs it" in s.candidates["same_as_mu"].reason
    pv = {n: projected(SHAPES[n], base) for n in ("square", "square_cube")}
    for n, v in pv.items():
        frac = s.candidates[n].identifiability["remaining_fraction"]["k"]
        # finite differences of a linear model: exact up to round-off of the differences
        assert frac == pytest.approx(np.linalg.norm(v) / np.linalg.norm(SHAPES[n]), rel=1e-6)
    cos = abs(pv["square"] @ pv["square_cube"]) / (np.linalg.norm(pv["square"])
                                                    * np.linalg.norm(pv["square_cube"]))
    assert s.identifiable == ["square", "square_cube"]
    assert s.lookalike["square"]["square_cube"] == pytest.approx(cos, rel=1e-6)


def test_fitting_alone_is_the_linear_least_squares_solution():
    """Fitting: on data made with b = 0.3 and mu = 1.2 plus noise, each identifiable
    candidate's fit is the ordinary least-squares solution of the linear model (numpy lstsq of
    the measured y on the shapes), its likelihood ratio is the drop of the residual sum of
    squares over sigma^2 from the nuisance-only least squares, and the uncertainty of k is
    sigma sqrt((A^T A)^-1)_kk (the chi-square per degree of freedom is near 1 here, and the
    engine scales by it only above 1)."""
    rng = np.random.default_rng(2)
    y = 1.2 * (1.0 + X) + 0.3 * X ** 2 + rng.normal(0.0, SIGMA, N)
    pb = problem(y)
    b = baseline_of(pb)
    s = screen(pb, b)
    fits, cands = fit_all(pb, s, b)
    assert set(fits) == {"square", "square_cube"}
    one = (1.0 + X)[:, None]
    sse0 = float(np.sum((y - one @ np.linalg.lstsq(one, y, rcond=None)[0]) ** 2))
    for n in fits:
        A = np.column_stack([SHAPES[n], 1.0 + X])
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        sse = float(np.sum((y - A @ coef) ** 2))
        c = cands[n]
        # bounded trust-region fit of a linear model to the optimum: 1e-6 of the parameter
        assert c.parameters["k"] == pytest.approx(coef[0], abs=1e-6)
        assert c.nuisance["mu"] == pytest.approx(coef[1], abs=1e-6)
        assert c.lr == pytest.approx((sse0 - sse) / SIGMA ** 2, rel=1e-6)
        cov = SIGMA ** 2 * np.linalg.inv(A.T @ A)
        dof_scale = max(1.0, sse / SIGMA ** 2 / (N - 2))
        assert c.uncertainty["k"] == pytest.approx(np.sqrt(cov[0, 0] * dof_scale), rel=1e-4)
    # the true shape is recovered within 5 standard uncertainties
    c = cands["square"]
    assert abs(c.parameters["k"] - 0.3) < 5 * c.uncertainty["k"]
