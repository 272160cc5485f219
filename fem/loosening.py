"""Fit-loosening speed: the rotor speed at which a fit opens, on the superposition.

A rotating shaft and the rings on it grow under the centrifugal body force rho omega^2 r; a ring's
bore grows more than the shaft's surface, so an interference fit loosens with speed and opens at
the fit-loosening speed (Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 1 ch. 8, fits
at speed; the two-cylinder closed form is `analytic.lame.fit_open_speed_rad_s`). Here it is found
on the exact contact problem (`fem.solver.Superposition`) of each state (part temperatures, fits):
the smallest omega^2 at which every contact pair of the fit is open (its mean pressure is zero,
the `fit_open` check of `simulate`).

Method: Illinois regula falsi (Dahlquist & Björck, Numerical Methods, section 6.2.2) on omega^2,
all states at once, of the signed opening function

    h(omega^2) = F_k                     while some pair of fit k is closed (total force, N)
               = -c_k min_i gap_i        once all of them are open (c_k in N/mm, > 0)

which is continuous, positive below and negative above the opening and piecewise linear (linear
while the active set stays), so the iteration ends in a few superposition evaluations. c_k (the
pair count over the mean diagonal flexibility of the fit) only sets the scale of the open branch;
the root does not depend on it.
"""
from __future__ import annotations

import numpy as np

from fem.solver import Superposition

#: omega^2 (rad^2/s^2) of 1 rpm^2
RPM2_TO_RAD2_S2 = (2.0 * np.pi / 60.0) ** 2


def _opening(sup: Superposition, theta, delta, k: int, c_k: float, w2: np.ndarray) -> np.ndarray:
    """h(omega^2) of fit k for every state (see the module docstring)."""
    res = sup.evaluate(theta, delta, w2)
    sel = sup.pfit == k
    F = res.force_N[:, sel].sum(axis=1)
    closed = (res.force_N[:, sel] > 0).any(axis=1)
    return np.where(closed, F, -c_k * res.gap_mm[:, sel].min(axis=1))


def fit_open_omega2(sup: Superposition, theta: np.ndarray, delta_mm: np.ndarray, fit: int,
                    omega2_max: float, rtol: float = 1e-9, max_iter: int = 100) -> np.ndarray:
    """(n_states,) smallest omega^2 (rad^2/s^2) at which FE fit `fit` is wholly open, for states
    theta (n, n_parts) and delta_mm (n, n_fits) as `Superposition.evaluate` takes them: 0 when it
    is open at rest, inf when it is still closed at omega2_max (and for bonded fits). Converged
    to rtol relative in omega^2, or to |h| <= rtol h(0) (h's slope is about h(0) / omega^2_open,
    so the root is then within about rtol relative too).

    Bracketing: secant steps from the closed side (h is linear while the active set stays, so the
    first step from rest lands at or just beyond the opening unless pairs open on the way), then
    Illinois regula falsi inside the bracket. c_k = 1' A_kk^-1 1 (N/mm): the force that closes a
    uniform gap of 1 mm over fit k, so both branches of h have the same scale."""
    theta, delta = np.atleast_2d(theta), np.atleast_2d(delta_mm)
    n = theta.shape[0]
    if sup.condensed.bonded:
        return np.full(n, np.inf)
    sel = np.flatnonzero(sup.pfit == fit)
    c_k = float(np.linalg.solve(sup.A[np.ix_(sel, sel)], np.ones(sel.size)).sum())

    def h(rows, w2):
        return _opening(sup, theta[rows], delta[rows], fit, c_k, w2)

    lo, hi = np.zeros(n), np.full(n, np.inf)
    h_lo, h_hi = h(np.arange(n), lo), np.full(n, -np.inf)
    h_tol = rtol * h_lo
    out = np.where(h_lo <= 0, 0.0, np.nan)
    # phase 1: secant extrapolation from the closed side until h <= 0 (or omega2_max)
    todo = np.flatnonzero(h_lo > 0)
    w_prev, h_prev = lo.copy(), h_lo.copy()
    step = np.full(n, 1e-6 * omega2_max)          # first probe: a small speed, for the slope
    for _ in range(max_iter):
        if todo.size == 0:
            break
        a, fa = lo[todo], h_lo[todo]
        slope = (fa - h_prev[todo]) / np.where(a > w_prev[todo], a - w_prev[todo], 1.0)
        first = a <= w_prev[todo]
        w = np.where(first, a + step[todo],
                     np.where(slope < 0, a - 1.05 * fa / np.where(slope < 0, slope, -1.0), 4 * a))
        w = np.minimum(np.maximum(w, a * 1.01), omega2_max)
        fw = h(todo, w)
        w_prev[todo], h_prev[todo] = a, fa
        up = fw > 0
        lo[todo[up]], h_lo[todo[up]] = w[up], fw[up]
        hi[todo[~up]], h_hi[todo[~up]] = w[~up], fw[~up]
        never = up & (w >= omega2_max)
        out[todo[never]] = np.inf
        todo = todo[up & ~never]
    # phase 2: Illinois regula falsi in [lo, hi]
    todo = np.flatnonzero(np.isnan(out))
    side = np.zeros(n, int)               # Illinois: which end was replaced last time
    for _ in range(max_iter):
        if todo.size == 0:
            break
        a, b, fa, fb = lo[todo], hi[todo], h_lo[todo], h_hi[todo]
        w = b - fb * (b - a) / (fb - fa)
        w = np.where((w > a) & (w < b), w, 0.5 * (a + b))
        fw = h(todo, w)
        pos = fw > 0
        # root in (w, b]: the low end moves; else in (a, w]: the high end moves
        lo[todo] = np.where(pos, w, a)
        h_lo[todo] = np.where(pos, fw, np.where(side[todo] == -1, 0.5 * fa, fa))
        hi[todo] = np.where(pos, b, w)
        h_hi[todo] = np.where(pos, np.where(side[todo] == 1, 0.5 * fb, fb), fw)
        side[todo] = np.where(pos, 1, -1)
        near = np.abs(fw) <= h_tol[todo]
        done = (hi[todo] - lo[todo] <= rtol * hi[todo]) | near
        out[todo[done]] = np.where(near[done], w[done], hi[todo[done]])
        todo = todo[~done]
    if todo.size:
        out[todo] = hi[todo]          # within the last bracket; reached only if max_iter is hit
    return out
