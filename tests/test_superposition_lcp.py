"""The superposition's contact forces are the solution of the condensed contact problem, checked
by another method: scipy's non-negative least squares (Lawson & Hanson, Solving Least Squares
Problems, 1974, ch. 23) on the equivalent problem.

The condensed problem of `fem.solver.Superposition` is the linear complementarity problem

    lambda >= 0,   gap = G0 + A lambda >= 0,   lambda . gap = 0      (A SPD, mm/N)

whose solution minimises 1/2 lambda^T A lambda + G0^T lambda over lambda >= 0 (Cottle, Pang &
Stone, The Linear Complementarity Problem, 1992, section 1.2). With A = L L^T (Cholesky) that is
min |L^T lambda + L^-1 G0|^2 over lambda >= 0: `scipy.optimize.nnls(L^T, -L^-1 G0)`, which
knows nothing of active sets, blocks, state order or the superposition's caches.

The states: seed 000's stack (mesh coarsened 2x, as in tests/test_fem.py) under random part
temperatures, interferences and speeds (fits opening and closing anywhere), and a programme's
rows (a -60..160 C cycle with each part lagging the ambient by its own time constant)."""
import numpy as np
import pytest
from scipy.linalg import cholesky, solve_triangular
from scipy.optimize import nnls

from fem.model import build_model
from fem.solver import FitSolver, Superposition, load_columns
from studies.model.config import load_shipped
from studies.model.stack import section_from_assembly


@pytest.fixture(scope="module")
def stack():
    asm = load_shipped("seed000")
    model = build_model(section_from_assembly(asm).scaled(2.0))
    return model, Superposition(FitSolver(model))


def _random_states(model, n, seed):
    """Part temperatures -60..160 C each on its own, interferences -2..+6 um radial per fit,
    speeds 0..30000 rpm: every fit opens and closes across the states."""
    rng = np.random.default_rng(seed)
    T = rng.uniform(-60.0, 160.0, (n, len(model.part_names)))
    theta = np.array([[model.materials[p].thermal_strain(t, 20.0)
                       for p, t in zip(model.part_names, row)] for row in T])
    delta = rng.uniform(-0.002, 0.006, (n, len(model.fits)))
    omega2 = (rng.uniform(0.0, 30000.0, n) * np.pi / 30.0) ** 2
    return theta, delta, omega2


def _programme_states(model, n):
    """A -60..160..-60 C ambient cycle; each part follows it with its own first-order lag
    (time constants 200..900 s, 20 s rows), as the diagnosis's lag candidates make them."""
    t = np.arange(n) * 20.0
    ambient = 50.0 - 110.0 * np.cos(2 * np.pi * t / t[-1])
    tau = np.linspace(200.0, 900.0, len(model.part_names))
    T = np.empty((n, tau.size))
    T[0] = ambient[0]
    for i in range(1, n):
        T[i] = T[i - 1] + (ambient[i] - T[i - 1]) * (1.0 - np.exp(-20.0 / tau))
    theta = np.array([[model.materials[p].thermal_strain(x, 20.0)
                       for p, x in zip(model.part_names, row)] for row in T])
    delta = np.tile([0.0025, 0.0025, -0.00075, -0.00075][:len(model.fits)], (n, 1))
    return theta, delta, np.zeros(n)


def _nnls_forces(sup, G0):
    """lambda (n_pairs,) of the LCP with free gaps G0 by NNLS on the Cholesky form."""
    L = cholesky(sup.A, lower=True)
    lam, _ = nnls(L.T, -solve_triangular(L, G0, lower=True), maxiter=50 * G0.size)
    return lam


@pytest.mark.requirement("R-FE-CONTACT")
@pytest.mark.parametrize("kind", ["random", "programme"])
def test_superposed_forces_solve_the_contact_lcp_as_nnls_does(stack, kind):
    """Every state: lambda >= 0 and gap >= 0 to 1e-8 of its largest force / free gap (the
    superposition's acceptance tolerance), lambda_i gap_i = 0 exactly (a closed pair's gap and
    an open pair's force are 0 by construction), and the forces equal NNLS's to 1e-8 of the
    largest force (the acceptance tolerance; measured 2026-11-29: 3e-13)."""
    model, sup = stack
    theta, delta, w2 = (_random_states(model, 240, 7) if kind == "random"
                        else _programme_states(model, 240))
    res = sup.evaluate(theta, delta, w2)
    G0 = (sup.B @ load_columns(theta, w2).T - delta[:, sup.pfit].T).T
    lam, gap = res.force_N, res.gap_mm
    f_scale = np.abs(lam).max(axis=1, keepdims=True)
    g_scale = np.abs(G0).max(axis=1, keepdims=True)
    assert (lam >= -1e-8 * f_scale).all()
    assert (gap >= -1e-8 * g_scale).all()
    assert (lam * gap == 0.0).all()
    # the gaps are those of the forces: gap = G0 + A lambda (to rounding, 1e-12 of |G0|)
    assert np.abs(gap - (G0 + lam @ sup.A)).max(initial=0.0) <= 1e-12 * g_scale.max()
    n_sets = len({tuple(s) for s in res.closed_sets})
    assert n_sets >= (4 if kind == "random" else 2)       # fits open and close across them
    worst = max(np.abs(lam[i] - _nnls_forces(sup, G0[i])).max() / max(f_scale[i, 0], 1e-12)
                for i in range(0, lam.shape[0], 3))
    assert worst <= 1e-8


def test_a_state_gets_the_same_forces_alone_or_among_others(stack):
    """A state's forces do not depend on the states evaluated with it: each state evaluated
    alone (a search of its own) gets the forces it got among 240 others, to 1e-12 of the largest
    (rounding of the back-substitution of another group of states). Its active set is unique
    unless a pair is within the 1e-8 acceptance tolerance of changing status, which no state
    of these is."""
    model, sup = stack
    theta, delta, w2 = _random_states(model, 240, 11)
    together = sup.evaluate(theta, delta, w2)
    G0 = (sup.B @ load_columns(theta, w2).T - delta[:, sup.pfit].T).T
    for i in range(0, 240, 20):
        closed = together.closed_sets[together.status[i]]
        f, g = together.force_N[i][closed], together.gap_mm[i][~closed]
        margin = min(f.min(initial=np.inf) / max(np.abs(f).max(initial=0.0), 1e-12),
                     g.min(initial=np.inf) / np.abs(G0[i]).max())
        assert margin > 1e-6          # no pair near a change of status (its set is unique)
        alone = sup.evaluate(theta[i:i + 1], delta[i:i + 1], w2[i:i + 1])
        scale = max(np.abs(together.force_N[i]).max(), 1e-12)
        assert np.abs(alone.force_N[0] - together.force_N[i]).max() <= 1e-12 * scale
