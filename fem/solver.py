"""Fits as exact contact: constraint elimination, active set, unit solutions and superposition.

A closed fit node pair (master m on the inner member, slave s on the outer member) obeys

    u_r(s) - u_r(m) = delta_r          (delta_r = radial interference = diametral / 2, mm)

and for the bonded variant also u_z(s) = u_z(m). The slave DOFs are eliminated, u = T q + g, and
the reduced system T^T K T q = T^T (f - K g) is factorised once per contact status (scipy splu with
MMD_AT_PLUS_A ordering). The contact force on the outer member at a closed pair is the reaction
lambda = (K u - f)[s] (N, whole ring); compression is positive. Open pairs must have a gap
u_r(s) - u_r(m) - delta_r >= 0. The active set (primal-dual, node by node) is iterated until no
closed pair is in tension and no open pair penetrates: the solution is exact, not penalty-
approximate. Source: Wriggers, Computational Contact Mechanics, 2nd ed., ch. 6 (active set /
Lagrange multipliers); Hüeber & Wohlmuth (2005) primal-dual active set.

With the contact status fixed the response is linear in the part thermal strains theta_p and the
fit interferences delta_k: u = sum theta_p U_p + sum delta_k U_k. `Superposition` keeps those
unit solutions per status, evaluates any number of states by small dense products, checks each
state's status (lambda >= 0 on closed pairs, gap >= 0 on open ones), and solves new statuses only
when a state leaves the known ones (DESIGN.md section 2, "linearity is a resource").
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from fem.model import StackModel


class SolveError(RuntimeError):
    """Singular system or an active set that does not settle; one-line message."""


@dataclass
class Solution:
    u: np.ndarray               # displacement DOFs (mm)
    force_N: np.ndarray         # contact force per pair (outer member, + = compression), 0 if open
    gap_mm: np.ndarray          # u_r(s) - u_r(m) - delta_r per pair (0 where closed)
    closed: np.ndarray          # bool per pair


class FitSolver:
    """Constrained solves of a `StackModel` with its fits; factorisations cached per status."""

    def __init__(self, model: StackModel):
        self.model = model
        fits = model.fits
        self.master = np.concatenate([f.master_r for f in fits]) if fits else np.zeros(0, int)
        self.slave = np.concatenate([f.slave_r for f in fits]) if fits else np.zeros(0, int)
        self.fit_of_pair = np.concatenate([np.full(f.master_r.size, k) for k, f in
                                           enumerate(fits)]) if fits else np.zeros(0, int)
        self.master_z = np.concatenate([f.master_z for f in fits]) if fits else np.zeros(0, int)
        self.slave_z = np.concatenate([f.slave_z for f in fits]) if fits else np.zeros(0, int)
        self.bonded = model.contact == "bonded"
        self._cache: dict[bytes, tuple] = {}
        self.n_factorisations = 0

    @property
    def n_pairs(self) -> int:
        return self.master.size

    def _system(self, closed: np.ndarray):
        key = np.packbits(closed).tobytes() + bytes([closed.size % 8])
        if key in self._cache:
            return self._cache[key]
        m = self.model
        N = m.ndofs
        masters, slaves = list(self.master[closed]), list(self.slave[closed])
        if self.bonded:
            masters += list(self.master_z)
            slaves += list(self.slave_z)
        masters, slaves = np.array(masters, int), np.array(slaves, int)
        dir_mask = np.zeros(N, bool)
        dir_mask[m.dirichlet] = True
        keep = ~dir_mask[slaves]
        masters, slaves = masters[keep], slaves[keep]
        is_free = ~dir_mask
        is_free[slaves] = False
        free = np.flatnonzero(is_free)
        red = np.full(N, -1)
        red[free] = np.arange(free.size)
        ok = red[masters] >= 0
        rows = np.concatenate([free, slaves[ok]])
        cols = np.concatenate([np.arange(free.size), red[masters[ok]]])
        T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(N, free.size))
        Kr = (T.T @ m.K @ T).tocsc()
        try:
            lu = splu(Kr, permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:
            raise SolveError(f"singular stiffness matrix ({exc}): a part is not held "
                             "(missing fit, tie or support)") from None
        self.n_factorisations += 1
        self._cache[key] = (T, lu)
        return T, lu

    def _g(self, closed: np.ndarray, delta_mm_by_fit: np.ndarray) -> np.ndarray:
        """Prescribed slave offsets: delta_r at closed radial slaves (columns: one per state)."""
        delta = np.atleast_2d(delta_mm_by_fit)            # (n_states, n_fits)
        g = np.zeros((self.model.ndofs, delta.shape[0]))
        g[self.slave[closed], :] = delta[:, self.fit_of_pair[closed]].T
        return g

    def solve_status(self, closed: np.ndarray, f: np.ndarray, delta_mm_by_fit: np.ndarray):
        """Solve with a fixed status. f: (N,) or (N, k); delta: (n_fits,) or (k, n_fits)."""
        T, lu = self._system(closed)
        F = f.reshape(self.model.ndofs, -1)
        g = self._g(closed, delta_mm_by_fit)
        if g.shape[1] != F.shape[1]:
            g = np.broadcast_to(g, (g.shape[0], F.shape[1])) if g.shape[1] == 1 else g
            F = np.broadcast_to(F, g.shape) if F.shape[1] == 1 else F
        u = T @ lu.solve(np.asarray(T.T @ (F - self.model.K @ g))) + g
        if not np.all(np.isfinite(u)):
            raise SolveError("the FE solve returned non-finite displacements (singular system)")
        return u

    def pair_values(self, u: np.ndarray, f: np.ndarray, delta_mm_by_fit: np.ndarray):
        """Contact force (N) and gap (mm) at every pair for solution(s) u under load f."""
        U = u.reshape(self.model.ndofs, -1)
        R = self.model.K @ U - f.reshape(self.model.ndofs, -1)
        delta = np.atleast_2d(delta_mm_by_fit)[:, self.fit_of_pair].T
        return R[self.slave], U[self.slave] - U[self.master] - delta

    def solve(self, f: np.ndarray, delta_mm_by_fit, closed: np.ndarray | None = None,
              max_iter: int = 60) -> Solution:
        """Direct solve with the active set iterated to convergence (exact contact)."""
        delta = np.asarray(delta_mm_by_fit, float)
        if closed is None:
            closed = np.ones(self.n_pairs, bool) if self.bonded else delta[self.fit_of_pair] > 0
        closed = closed.copy()
        for _ in range(max_iter):
            u = self.solve_status(closed, f, delta)[:, 0]
            force, gap = (x[:, 0] for x in self.pair_values(u, f, delta))
            if self.bonded:
                return Solution(u, force, np.zeros_like(gap), closed)
            scale_f = 1e-9 * max(np.abs(force).max(), 1e-6)
            scale_g = 1e-9 * max(np.abs(delta).max(), 1e-6)
            open_bad = ~closed & (gap < -scale_g)
            closed_bad = closed & (force < -scale_f)
            if not open_bad.any() and not closed_bad.any():
                return Solution(u, np.where(closed, force, 0.0), np.where(closed, 0.0, gap), closed)
            closed = (closed | open_bad) & ~closed_bad
        raise SolveError(f"contact active set did not settle in {max_iter} iterations")


class Superposition:
    """Unit solutions per contact status; exact evaluation of many states.

    A state is (theta per part, delta_mm per fit). `units` are the columns: first the parts (unit
    thermal strain in that part), then the fits (1 mm radial interference in that fit)."""

    def __init__(self, solver: FitSolver, probe: sp.csr_matrix | None = None):
        self.solver = solver
        self.model = solver.model
        self.n_parts = len(self.model.part_names)
        self.n_fits = len(self.model.fits)
        self.probe = probe
        self.statuses: list[dict] = []

    def _units(self, closed: np.ndarray) -> dict:
        for st in self.statuses:
            if np.array_equal(st["closed"], closed):
                return st
        s, m = self.solver, self.model
        F = np.hstack([m.unit_loads, np.zeros((m.ndofs, self.n_fits))])
        D = np.vstack([np.zeros((self.n_parts, self.n_fits)), np.eye(self.n_fits)])
        U = s.solve_status(closed, F, D)
        force, gap_u = s.pair_values(U, F, D)
        st = {"closed": closed.copy(), "U": U, "force": force, "gap": gap_u,
              "probe": (self.probe @ U) if self.probe is not None else None}
        self.statuses.append(st)
        return st

    def _feasible(self, st: dict, C: np.ndarray) -> np.ndarray:
        force = C @ st["force"].T
        gap = C @ st["gap"].T
        cl = st["closed"]
        sf = 1e-7 * np.maximum(np.abs(force).max(axis=1, keepdims=True), 1e-6)
        sg = 1e-7 * np.maximum(np.abs(C[:, self.n_parts:]).max(axis=1, keepdims=True), 1e-9)
        if self.solver.bonded:
            return np.ones(C.shape[0], bool)
        return ~((force[:, cl] < -sf).any(axis=1) | (gap[:, ~cl] < -sg).any(axis=1))

    def evaluate(self, theta: np.ndarray, delta_mm: np.ndarray) -> dict:
        """theta: (n_states, n_parts), delta_mm: (n_states, n_fits). Returns per state: contact
        force and gap per pair, probe values, and the status index used."""
        C = np.hstack([np.atleast_2d(theta), np.atleast_2d(delta_mm)])
        n = C.shape[0]
        which = np.full(n, -1)
        for i, st in enumerate(self.statuses):
            todo = np.flatnonzero(which < 0)
            if todo.size == 0:
                break
            ok = self._feasible(st, C[todo])
            which[todo[ok]] = i
        while (which < 0).any():
            j = np.flatnonzero(which < 0)[0]
            f = self.model.unit_loads @ C[j, :self.n_parts]
            sol = self.solver.solve(f, C[j, self.n_parts:])
            st = self._units(sol.closed)
            i = next(k for k, s in enumerate(self.statuses) if s is st)
            todo = np.flatnonzero(which < 0)
            ok = self._feasible(st, C[todo])
            ok[todo == j] = True
            which[todo[ok]] = i
        force = np.empty((n, self.solver.n_pairs))
        gap = np.empty_like(force)
        probe = None if self.probe is None else np.empty((n, self.probe.shape[0]))
        for i, st in enumerate(self.statuses):
            sel = which == i
            if not sel.any():
                continue
            cl = st["closed"]
            force[sel] = np.where(cl, C[sel] @ st["force"].T, 0.0)
            gap[sel] = np.where(cl, 0.0, C[sel] @ st["gap"].T)
            if probe is not None:
                probe[sel] = C[sel] @ st["probe"].T
        return {"force_N": force, "gap_mm": gap, "probe": probe, "status": which}

    def field(self, theta: np.ndarray, delta_mm: np.ndarray) -> np.ndarray:
        """Full displacement vector of one state."""
        res = self.evaluate(theta[None, :], delta_mm[None, :])
        st = self.statuses[res["status"][0]]
        return st["U"] @ np.concatenate([theta, delta_mm])
