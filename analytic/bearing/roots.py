"""Vectorised root finders of the bearing solvers. Each returns the solution and, per point,
whether it converged; a solver never hands back an unconverged iterate silently."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Root:
    """Solution per point and its convergence flag (bool, same trailing shape)."""
    x: np.ndarray
    converged: np.ndarray


def safeguarded_step(x, cand, r, dr, lo, hi, step, xtol):
    """The next iterate of a safeguarded Newton iteration on an increasing residual r (slope dr)
    at x, with the Newton candidate `cand` and the bracket [lo, hi] of the root (updated by the
    caller from the residual signs): `cand` where dr > 0 and it lies inside the bracket; else the
    bracket's mid-point when both ends are known; else a step of `step` towards the root (the
    step doubles each time, away from a flat side).  Returns (next iterate, next step)."""
    inside = (dr > 0.0) & (cand > lo) & (cand < hi)      # (NaN compares False)
    if inside.all():                  # the usual case: every Newton step inside its bracket
        return cand, step
    # a Newton step onto the far end of the bracket returns to a point already evaluated
    # (its residual has the other sign): from there Newton may step straight back, a
    # two-cycle that never shrinks the bracket (a residual that jumps by more than
    # dr * xtol, e.g. one evaluated through a nested root solve). Bisect instead, unless
    # the step is already within the tolerance.
    back = ((cand == lo) & (x != lo)) | ((cand == hi) & (x != hi))
    back &= np.abs(cand - x) > xtol * (1.0 + np.abs(x))
    ok = (dr > 0.0) & np.isfinite(cand) & (cand >= lo) & (cand <= hi) & ~back
    both = np.isfinite(lo) & np.isfinite(hi)
    new = np.where(ok, cand, np.where(both, 0.5 * (lo + hi),
                                      np.where(r < 0.0, x + step, x - step)))
    return new, np.where(ok | both, step, 2.0 * step)


def newton_increasing(fun, x0, lo=None, hi=None, step0=1e-3, xtol=1e-15, max_iter=200) -> Root:
    """Vectorised root of an increasing function: fun(x) -> (r, dr/dx).  Newton's method inside a
    bracket kept from the residual signs; bisection when Newton leaves it; doubling steps away
    from a flat (dr = 0) side while one bracket end is still open.  A point has converged when
    its step is below xtol (1 + |x|) (a point whose residual is exactly zero stops there)."""
    x = np.array(x0, dtype=float, copy=True)
    lo = np.full_like(x, -np.inf) if lo is None else np.array(np.broadcast_to(lo, x.shape), float)
    hi = np.full_like(x, np.inf) if hi is None else np.array(np.broadcast_to(hi, x.shape), float)
    step = np.array(np.broadcast_to(step0, x.shape), float)
    done = np.zeros(x.shape, bool)
    for _ in range(max_iter):
        r, dr = fun(x)
        lo = np.where(r <= 0.0, np.maximum(lo, x), lo)
        hi = np.where(r >= 0.0, np.minimum(hi, x), hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            cand = x - r / dr
        new, step = safeguarded_step(x, cand, r, dr, lo, hi, step, xtol)
        new = np.where(r == 0.0, x, new)
        done = np.abs(new - x) <= xtol * (1.0 + np.abs(x))
        x = new
        if done.all():
            break
    return Root(x, done & np.isfinite(x))


def newton_direction(g: np.ndarray, H: np.ndarray) -> np.ndarray:
    """Newton's direction d = -(H + lam I)^-1 g of N points at once, g (n, N) the gradients and
    H (n, n, N) the Hessians (or Jacobians), lam = 1e-12 of each Hessian's largest diagonal plus
    1e-6 N/mm, so that a flat direction without contact still gives a step (Nocedal & Wright,
    Numerical Optimization, 2nd ed., ch. 3.4: a shifted Hessian). Returns d (n, N), mm."""
    A = np.moveaxis(H, -1, 0)
    lam = 1e-12 * np.abs(np.diagonal(A, axis1=1, axis2=2)).max(axis=1) + 1e-6
    eye = np.eye(A.shape[1])
    return -np.linalg.solve(A + lam[:, None, None] * eye, np.moveaxis(g, -1, 0)[..., None])[..., 0].T


def newton_minimise(fun, u0, cap, max_iter: int = 200, xtol: float = 1e-15) -> Root:
    """Vectorised minimisation of convex functions fun(u) -> (Pi, |terms|, grad, Hessian), u of
    shape (n, N): Newton steps on the Hessian (plus 1e-12 of its largest diagonal and 1e-6 N/mm,
    so that flat directions without contact still give a step), capped to `cap` mm per component,
    with Armijo backtracking on Pi (decreases below the rounding level of Pi, 1e-13 of the sum of
    the magnitudes of its terms, are accepted).  A point is converged when a full Newton step is
    below xtol (1 + max|u|) mm (default 1e-15) (taken without evaluating it: it changes Pi far below the rounding
    level at which it would be accepted), or when no step decreases Pi any more (at the
    rounding level of Pi: the minimum to machine precision); `converged` is False for points still
    moving after max_iter iterations."""
    u = np.array(u0, float, copy=True)
    N = u.shape[1]
    Pi, Pabs, g, H = fun(u)
    done = np.zeros(N, bool)
    for _ in range(max_iter):
        d = newton_direction(g, H)
        step = np.abs(d).max(axis=0)
        full = step <= cap
        d = d * np.where(full, 1.0, cap / np.where(full, 1.0, step))
        d[:, done] = 0.0
        # a full step below the tolerance is taken without evaluating it: it changes Pi by
        # g.d + d.H.d/2, orders below Pi's rounding level, so the test below would accept it
        tiny = ~done & full & (step <= xtol * (1.0 + np.abs(u).max(axis=0)))
        if tiny.any():
            u[:, tiny] += d[:, tiny]
            d[:, tiny] = 0.0
            done |= tiny
            if done.all():
                break
        slope = (g * d).sum(axis=0)
        t = np.ones(N)
        pending = ~done
        for _ls in range(60):
            trial = u + t * d
            Pt, Pat, gt, Ht = fun(trial)
            ok = pending & (Pt <= Pi + 1e-4 * t * slope + 1e-13 * (Pabs + Pat))
            if (ok | done).all():      # (a done point's trial is u itself: d = 0 there)
                u, Pi, Pabs, g, H = trial, Pt, Pat, gt, Ht
            else:
                u[:, ok], Pi[ok], Pabs[ok], g[:, ok], H[..., ok] = trial[:, ok], Pt[ok], Pat[ok], gt[:, ok], Ht[..., ok]
            pending &= ~ok
            if not pending.any():
                break
            t = np.where(pending, 0.5 * t, t)
        small = full & (t == 1.0) & (step <= xtol * (1.0 + np.abs(u).max(axis=0)))
        done |= small | pending
        if done.all():
            break
    return Root(u, done & np.isfinite(u).all(axis=0))

