"""Fits as exact contact: constraint elimination, active set, unit solutions and superposition.

A closed fit node pair (master m on the inner member, slave s on the outer member) obeys

    u_r(s) - u_r(m) = delta_r          (delta_r = radial interference = diametral / 2, mm)

and for the bonded variant also u_z(s) = u_z(m); across clamped faces u_z is tied, except on a
face held as a contact (`meshes.section.Face`: a clamp with a force), whose pairs are the same
unilateral contact in u_z (u_z(s) - u_z(m) = delta, the clamp's axial overlap), possibly with a
spring in series (compliance c_p per pair: closed, the pair is that spring, k_p = 1 / c_p, with
force k_p (delta - u_z(s) + u_z(m)); its gap counts the spring, gap = u(s) - u(m) - delta + c_p
lambda). The slave DOFs are eliminated, u = T q + g, and
the reduced system T^T K T q = T^T (f - K g) is factorised once per contact status (scipy splu with
MMD_AT_PLUS_A ordering). The contact force on the outer member at a closed pair is the reaction
lambda = (K u - f)[s] (N, whole ring); compression is positive. Open pairs must have a gap
u_r(s) - u_r(m) - delta_r >= 0. The active set (primal-dual, node by node) is iterated until no
closed pair is in tension and no open pair penetrates: the solution is exact, not penalty-
approximate. Source: Wriggers, Computational Contact Mechanics, 2nd ed., ch. 6 (active set /
Lagrange multipliers); Hüeber & Wohlmuth (2005) primal-dual active set.

With the contact status fixed the response is linear in the part thermal strains theta_p, the
square of the rotor speed omega^2 (centrifugal body force rho omega^2 r on the spinning parts,
`StackModel.spin_load`) and the fit interferences delta_k: u = sum theta_p U_p + omega^2 U_w +
sum delta_k U_k. The "load columns" below are the n_parts thermal strains, then omega^2. `Superposition` keeps those
unit solutions per status, evaluates any number of states by small dense products, checks each
state's status (lambda >= 0 on closed pairs, gap >= 0 on open ones), and solves new statuses only
when a state leaves the known ones (for a fixed contact status the problem is linear in these loads,
so the superposition is exact).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np
import scipy.sparse as sp
from scipy.linalg import cho_factor, get_lapack_funcs
from scipy.sparse.linalg import splu
from threadpoolctl import ThreadpoolController

from infra.errors import BearingfemError
from infra.memo import Memo
from meshes.build import CONDENSE_BLOCK

if TYPE_CHECKING:                    # the model is only handed through here
    from fem.model import StackModel

_BLAS = ThreadpoolController()
#: LAPACK's Cholesky back-substitution for float64 (`scipy.linalg.cho_solve`'s routine)
_POTRS = get_lapack_funcs(("potrs",), (np.zeros((1, 1)), np.zeros((1, 1))))[0]


def single_thread_blas(fn):
    """Run `fn` with one BLAS thread: the superposition's dense solves are small (a few hundred
    unknowns), where threaded OpenBLAS only adds synchronisation (measured 20x slower on 2 cores).
    Applied inside the library, so a Python caller gets it too, not only the command line."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with _BLAS.limit(limits=1, user_api="blas"):
            return fn(*args, **kwargs)
    return wrapper


class SolveError(BearingfemError):
    """Singular system or an active set that does not settle; one-line message (the package's
    own error, a ValueError: the inputs (a part not held, a fit the solver cannot settle) are
    what to change, and the command exits 2 with it). `state`: the index of the state it failed
    on among those solved together (None: not one state's), for the caller to name its row
    (`studies.model.stages.fe.FEStage.solve_failure`)."""

    def __init__(self, message: str, state: int | None = None):
        super().__init__(message)
        self.state = state


@dataclass
class Solution:
    u: np.ndarray               # displacement DOFs (mm)
    force_N: np.ndarray         # contact force per pair (outer member, + = compression), 0 if open
    gap_mm: np.ndarray          # u_r(s) - u_r(m) - delta_r per pair (0 where closed)
    closed: np.ndarray          # bool per pair


def _lu_solve(lu, b) -> np.ndarray:
    """SuperLU solve; multi-column right-hand sides must be Fortran-ordered (10x faster)."""
    return lu.solve(np.asfortranarray(np.asarray(b)))


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
        #: series compliance (mm/N) of each pair's contact (a clamp layer; 0: a rigid contact)
        #: and whether the pair is on a clamped face (`meshes.section.Face`) rather than a fit
        self.compliance = (np.concatenate([f.pair_compliance_mm_per_N() for f in fits]) if fits
                           else np.zeros(0))
        self.face_pair = (np.concatenate([np.full(f.master_r.size, f.axis == "z") for f in fits])
                          if fits else np.zeros(0, bool))
        self.bonded = model.contact == "bonded"
        self._cache = Memo(max_items=None)    # factorisation per contact status (infra.memo)
        self.n_factorisations = 0

    @property
    def n_pairs(self) -> int:
        return self.master.size

    def clear_cache(self) -> None:
        """Forget the factorisations of every contact status (benchmarks time them afresh)."""
        self._cache.clear()

    def factorize(self, closed: np.ndarray):
        """The reduced system of a contact status (closed pairs), factorised (cached)."""
        return self._system(closed)

    def _system(self, closed: np.ndarray):
        key = np.packbits(closed).tobytes() + bytes([closed.size % 8])
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        m = self.model
        N = m.ndofs
        rigid = closed & (self.compliance == 0)   # closed springs are stiffness, not ties
        masters = [m.tie_master, self.master[rigid]]
        slaves = [m.tie_slave, self.slave[rigid]]
        if self.bonded:
            masters.append(self.master_z)
            slaves.append(self.slave_z)
        masters, slaves = np.concatenate(masters), np.concatenate(slaves)
        dir_mask = np.zeros(N, bool)
        dir_mask[m.dirichlet] = True
        keep = ~dir_mask[slaves]
        masters, slaves = masters[keep], slaves[keep]
        # ties form groups of DOFs that move together: chains of clamped faces, and closed loops
        # where a bonded fit and a clamped face meet at a corner (ring corner on a shoulder:
        # each DOF the other's slave). One DOF per group carries it: a fixed one if the group
        # holds one (the group is then fixed), else its lowest DOF.
        slaves, masters = _tie_representatives(N, masters, slaves, dir_mask)
        is_free = ~dir_mask
        is_free[slaves] = False
        free = np.flatnonzero(is_free)
        red = np.full(N, -1)
        red[free] = np.arange(free.size)
        ok = red[masters] >= 0
        rows = np.concatenate([free, slaves[ok]])
        cols = np.concatenate([np.arange(free.size), red[masters[ok]]])
        T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(N, free.size))
        Kr = (T.T @ self.stiffness(closed) @ T).tocsc()
        try:
            lu = splu(Kr, permc_spec="MMD_AT_PLUS_A")
        except RuntimeError as exc:
            raise SolveError(f"singular stiffness matrix ({exc}): a part is not held "
                             "(missing fit, tie or support)") from None
        self.n_factorisations += 1
        self._cache.put(key, (T, lu))
        return T, lu

    def _springs(self, closed: np.ndarray) -> np.ndarray:
        """The closed pairs whose contact has a spring in series (a clamp layer)."""
        return np.flatnonzero(closed & (self.compliance > 0))

    def stiffness(self, closed: np.ndarray) -> sp.csr_matrix:
        """The model's stiffness plus the springs of the closed spring pairs (N/mm): between
        master m and slave s of pair p, k_p = 1 / c_p on (m, m), (s, s) and -k_p on (m, s), (s, m)."""
        K = self.model.K
        p = self._springs(closed)
        if p.size == 0:
            return K
        k = 1.0 / self.compliance[p]
        m, s = self.master[p], self.slave[p]
        Ks = sp.csr_matrix((np.concatenate([k, k, -k, -k]),
                            (np.concatenate([m, s, m, s]), np.concatenate([m, s, s, m]))),
                           shape=K.shape)
        return (K + Ks).tocsr()

    def _g(self, closed: np.ndarray, delta_mm_by_fit: np.ndarray) -> np.ndarray:
        """Prescribed slave offsets: delta_r at closed radial slaves (columns: one per state);
        a closed pair with a spring in series is not prescribed (`_spring_loads`)."""
        delta = np.atleast_2d(delta_mm_by_fit)            # (n_states, n_fits)
        g = np.zeros((self.model.ndofs, delta.shape[0]))
        rigid = closed & (self.compliance == 0)
        g[self.slave[rigid], :] = delta[:, self.fit_of_pair[rigid]].T
        return g

    def _spring_loads(self, closed: np.ndarray, delta_mm_by_fit: np.ndarray) -> np.ndarray:
        """Loads (N) of the closed spring pairs' overlaps: the spring of pair p, compressed by
        delta_p when the faces meet, pushes the slave with +k_p delta_p and the master with
        -k_p delta_p (columns: one per state)."""
        delta = np.atleast_2d(delta_mm_by_fit)
        f = np.zeros((self.model.ndofs, delta.shape[0]))
        p = self._springs(closed)
        if p.size:
            kd = delta[:, self.fit_of_pair[p]].T / self.compliance[p][:, None]
            np.add.at(f, self.slave[p], kd)
            np.add.at(f, self.master[p], -kd)
        return f

    def solve_status(self, closed: np.ndarray, f: np.ndarray, delta_mm_by_fit: np.ndarray):
        """Solve with a fixed status. f: (N,) or (N, k); delta: (n_fits,) or (k, n_fits)."""
        T, lu = self._system(closed)
        F = f.reshape(self.model.ndofs, -1)
        g = self._g(closed, delta_mm_by_fit)
        if g.shape[1] != F.shape[1]:
            g = np.broadcast_to(g, (g.shape[0], F.shape[1])) if g.shape[1] == 1 else g
            F = np.broadcast_to(F, g.shape) if F.shape[1] == 1 else F
        fs = self._spring_loads(closed, delta_mm_by_fit)
        if fs.any():
            F = F + fs
        u = T @ _lu_solve(lu, T.T @ (F - self.stiffness(closed) @ g)) + g
        if not np.all(np.isfinite(u)):
            raise SolveError("the FE solve returned non-finite displacements (singular system)")
        return u

    def pair_values(self, u: np.ndarray, f: np.ndarray, delta_mm_by_fit: np.ndarray):
        """Contact force (N) and gap (mm) at every pair for solution(s) u under load f. The gap
        of a pair with a spring in series counts the spring's shortening, c_p force_p."""
        U = u.reshape(self.model.ndofs, -1)
        R = self.model.K @ U - f.reshape(self.model.ndofs, -1)
        delta = np.atleast_2d(delta_mm_by_fit)[:, self.fit_of_pair].T
        return (R[self.slave],
                U[self.slave] - U[self.master] - delta + self.compliance[:, None] * R[self.slave])

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
            scale_f = 1e-9 * max(np.abs(force).max(initial=0.0), 1e-6)
            # the gap is a difference of displacements: zero to round-off within
            # GAP_ROUNDOFF_REL of the largest displacement at a pair (a line-to-line fit)
            moved = max(np.abs(u[self.slave]).max(initial=0.0),
                        np.abs(u[self.master]).max(initial=0.0))
            scale_g = max(1e-9 * max(np.abs(delta).max(initial=0.0), 1e-6),
                          GAP_ROUNDOFF_REL * moved)
            open_bad = ~closed & (gap < -scale_g)
            closed_bad = closed & (force < -scale_f)
            if not open_bad.any() and not closed_bad.any():
                return Solution(u, np.where(closed, force, 0.0), np.where(closed, 0.0, gap), closed)
            closed = (closed | open_bad) & ~closed_bad
        raise SolveError(f"contact active set did not settle in {max_iter} iterations", 0)


class Superposition:
    """Exact superposition through the interface (static condensation of the contact problem).

    One factorisation of the unconstrained stiffness (supports only) serves every state. Columns:
    the unit thermal loads of the parts (U_p), the centrifugal load at omega = 1 rad/s (U_w) and
    unit pair forces (W_i: +1 N on the outer member, -1 N on the inner member at pair i). With
    pair forces lambda and a state c = (theta, omega^2, delta), L = (theta, omega^2):

        gap = B L - delta_pair + A lambda,   A_ij = W_j[s_i] - W_j[m_i]  (flexibility, SPD)

    and the contact conditions lambda >= 0, gap >= 0, lambda . gap = 0 form a small linear
    complementarity problem solved exactly by an active set on A (dense, a few hundred pairs).
    Each active set met is kept (`ActiveSet`: the Cholesky factor of A_CC and the set's
    response to the state columns); `evaluate` finds every state's set by those responses
    (`_search`) and solves the states of each set together. The per-state cost is independent
    of the mesh size; a new active set costs one small dense factorisation, never a new FE
    solve.
    Bonded fits: every radial and axial pair is always closed (tension allowed).
    Source: the reduction is the classical Schur complement of the contact interface (Wriggers,
    Computational Contact Mechanics, 2nd ed., section 6.2; Johnson, Contact Mechanics, ch. 5
    for the complementarity conditions)."""

    @single_thread_blas
    def __init__(self, solver: FitSolver, probe: sp.csr_matrix | None = None):
        self._set(condense(solver, probe), lambda: solver)

    @classmethod
    def from_condensed(cls, condensed: "Condensed", solver_of: Callable[[], FitSolver]
                       ) -> "Superposition":
        """A superposition of stored condensed arrays (`fem.setup`): `evaluate` needs nothing
        else; `solver_of()` (called once, by `field` only) gives the full FE model when a whole
        displacement field is asked for."""
        sup = cls.__new__(cls)
        sup._set(condensed, solver_of)
        return sup

    def _set(self, c: "Condensed", solver_of: Callable[[], FitSolver]) -> None:
        self.condensed, self._solver_of = c, solver_of
        self.n_parts, self.n_fits = c.n_parts, c.n_fits
        self._chol = Memo(max_items=None)     # `ActiveSet` per closed set (infra.memo)
        self.pfit, self.B, self.A = c.fit_of_pair, c.B, c.A
        self.n_loads = c.n_parts + 1          # load columns: thermal strain per part, omega^2
        #: the free gap of every pair per state column (thermal strains, omega^2, then the
        #: fits' interferences): G0 = H c = B L - delta_pair, mm per unit column
        self.H = (np.hstack([c.B, -(c.fit_of_pair[:, None] == np.arange(c.n_fits)).astype(float)])
                  if not c.bonded else np.zeros((0, 0)))
        #: (fit, slice) per run of consecutive pairs of one fit (a fit's pairs are one run)
        cut = np.flatnonzero(np.diff(c.fit_of_pair)) + 1
        self._fit_runs = [(int(c.fit_of_pair[a]), slice(a, b)) for a, b in
                          zip(np.r_[0, cut], np.r_[cut, c.fit_of_pair.size]) if b > a]
        #: states a set is tried on at first (`_search`; doubled while a set takes every state
        #: tried). Measured 2026-11-29 on seed 000's per-part lag states (500 a call, about 17
        #: sets in a chain, each one pair more open than the last): 32, 64, 128, 256 and all
        #: states within the timing noise (8.7-9.7 ms a call, then at load 1.5)
        self.window = 64
        self.PU = c.probe_units if c.probe_units.shape[0] else None
        self._bonded_units = None
        if not c.bonded:
            #: per state column, the largest free gap it makes at any pair (mm per unit), and the
            #: smallest flexibility of a pair (mm/N): the scales of `ContactTolerance`
            self._column_reach_mm = np.abs(self.H).max(axis=0, initial=0.0)
            self._stiffest_mm_per_N = float(np.diag(c.A).min(initial=np.inf)) if c.A.size else 1.0

    @functools.cached_property
    def solver(self) -> FitSolver:
        """The full FE solver (built on first use when this superposition came from stored
        arrays)."""
        return self._solver_of()

    @property
    def model(self) -> "StackModel":
        return self.solver.model

    @property
    def ps(self) -> np.ndarray:
        """Slave (outer member) radial DOF of every contact pair."""
        return self.solver.slave

    @property
    def pm(self) -> np.ndarray:
        """Master (inner member) radial DOF of every contact pair."""
        return self.solver.master

    @property
    def n_pairs(self) -> int:
        return self.pfit.size

    def _active_set(self, closed: np.ndarray) -> "ActiveSet":
        """The `ActiveSet` of a closed set, made on first use and kept (`_chol`): the numbers
        are the same whether made now or kept, so the cache never changes a result."""
        key = np.packbits(closed).tobytes()
        return self._chol.get_or_make(key, lambda: ActiveSet.of(self.A, self.H, closed))

    def clear_cache(self) -> None:
        """Forget the active sets met so far (their Cholesky factors and responses; benchmarks)."""
        self._chol.clear()

    def _search(self, C: np.ndarray, tol: "ContactTolerance", closed: np.ndarray
                ) -> tuple[list, list]:
        """Every state's active set: (the `ActiveSet`s, the states of each, as positions in C).
        C (n, n_cols): the states' columns (`H`) in the order they are tried (`state_order`);
        tol: their gap and force tolerances (`ContactTolerance`, same order); closed: the
        first set tried.

        A set is tried on the next `window` states not yet placed, by its `response` (one small
        product per state); the states it satisfies (`ActiveSet.satisfied`) take it. The next
        set is one primal-dual step (`ActiveSet.step`) of the first state left, from its own
        forces and gaps under the set just tried, so that state's sets are those of its own
        active-set iteration from the set before: it ends in a set it satisfies, and sorted
        states, being alike, mostly share it."""
        todo = np.arange(C.shape[0])
        found: dict[bytes, int] = {}
        sets: list[ActiveSet] = []
        members: list[list] = []
        steps, window = 0, self.window
        while todo.size:
            s = self._active_set(closed)
            tried = todo[:window]
            V = C[tried] @ s.response
            ok = s.satisfied(V, tol.accept_gap_mm[tried], tol.force_N[tried])
            if ok.any():
                k = found.setdefault(closed.tobytes(), len(sets))
                if k == len(sets):
                    sets.append(s)
                    members.append([])
                members[k].append(tried[ok])
                todo = np.concatenate([tried[~ok], todo[tried.size:]])
                steps = 0
                if not todo.size:
                    break
                # a set that took every state tried is tried on twice as many next
                window = 2 * window if ok.all() else self.window
            steps += 1
            if steps > MAX_ACTIVE_SET_STEPS:
                raise SolveError(f"contact active set did not settle in {MAX_ACTIVE_SET_STEPS} "
                                 "iterations", int(tried[np.argmin(ok)]))
            first = np.argmin(ok)                      # the first state left
            closed = s.step(V[first], tol.step_gap_mm[tried[first]], tol.force_N[tried[first]])
        return sets, [np.sort(np.concatenate(m)) for m in members]

    @single_thread_blas
    def evaluate(self, theta: np.ndarray, delta_mm: np.ndarray,
                 omega2_rad2_s2=None) -> "SuperposedStates":
        """theta: (n_states, n_parts), delta_mm: (n_states, n_fits), omega2_rad2_s2: (n_states,)
        the square of the rotor speed (rad^2/s^2; None = at rest). Returns per state the
        contact force (N, + compression) and gap (mm) per pair, probe values, and the index of
        the active set of each state (states sharing an active set are solved together): a
        `SuperposedStates`."""
        theta, delta = np.atleast_2d(theta), np.atleast_2d(delta_mm)
        theta = load_columns(theta, omega2_rad2_s2)
        if self.condensed.bonded:
            C = np.hstack([theta, delta])
            n = self.n_pairs
            return SuperposedStates(C @ self.condensed.bonded_force.T, np.zeros((C.shape[0], n)),
                                    np.zeros(C.shape[0], int), [np.ones(n, bool)],
                                    None if self.PU is None else C @ self.PU.T)
        # the free gaps G0 (n_states, n_pairs), mm; each fit's pairs are a run of columns, so
        # the interferences are subtracted in place (arrays of n_states x n_pairs are made
        # only for the results: this is called for hundreds of states at a time)
        G0 = theta @ self.B.T
        for k, run in self._fit_runs:
            G0[:, run] -= delta[:, k:k + 1]
        n = G0.shape[0]
        lam, gap = np.zeros_like(G0), G0
        which = np.empty(n, int)
        sets: list[ActiveSet] = []
        if n:
            # states alike in their overlap count and summed free gap mostly share an active set
            order = state_order(G0.T)
            C = np.hstack([theta, delta])[order]
            tol = ContactTolerance.of(G0[order], C, self._column_reach_mm, self._stiffest_mm_per_N)
            try:
                sets, members = self._search(C, tol, G0[order[0]] < -tol.step_gap_mm[0])
            except SolveError as exc:       # the state by its place in the caller's rows
                raise SolveError(str(exc), None if exc.state is None
                                 else int(order[exc.state])) from None
            for k, (s, at) in enumerate(zip(sets, members)):
                idx = order[at]
                which[idx] = k
                s.solve(G0, idx, self.A, lam)
        probe = (None if self.PU is None
                 else theta @ self.PU[:, :self.n_loads].T + lam @ self.PU[:, self.n_loads:].T)
        return SuperposedStates(lam, gap, which, [s.closed.copy() for s in sets], probe)

    def field(self, theta: np.ndarray, delta_mm: np.ndarray, omega2_rad2_s2: float = 0.0
              ) -> np.ndarray:
        """Full displacement vector (mm) of one state: one back-substitution with the
        factorisation of the all-open system (bonded: the unit solutions of the tied system,
        solved on first use)."""
        s = self.solver
        if self.condensed.bonded:
            if self._bonded_units is None:
                self._bonded_units = s.solve_status(np.ones(s.n_pairs, bool), *_bonded_units_load(s))
            return self._bonded_units @ np.concatenate([theta, [omega2_rad2_s2], delta_mm])
        res = self.evaluate(theta[None, :], delta_mm[None, :], np.array([omega2_rad2_s2]))
        lam = res.force_N[0]
        f = self.model.unit_loads @ theta + omega2_rad2_s2 * self.model.spin_load
        np.add.at(f, self.ps, lam)
        np.add.at(f, self.pm, -lam)
        T, lu = s.factorize(np.zeros(s.n_pairs, bool))
        return T @ _lu_solve(lu, T.T @ f)


def state_order(G0: np.ndarray) -> np.ndarray:
    """The order in which `Superposition.evaluate` tries its states (columns of the free gaps
    G0, (n_pairs, n_states), mm): by the number of pairs that overlap without contact forces
    (G0 < 0: the first guess of the closed set), then by the summed free gap; stable. A
    programme's rows come as a cycle or a random sample, where neighbours in row order often
    differ in their active set (seed 000's 500-row cycles: 31 active-set passes in row order, 19
    in this order, the superposition 46 -> 21 ms). Each state's contact forces are those of its
    own active set whatever the order (the same set to 5e-14 of the largest force: the
    back-substitution of another group of columns rounds differently)."""
    return np.lexsort((G0.sum(axis=0), (G0 < 0).sum(axis=0)))


#: states solved together by `ActiveSet.solve` (arrays of SOLVE_BLOCK x n_pairs: measured
#: 2026-11-29, 274 states of 212 closed pairs 2.1 ms in blocks of 64, 3.0 ms at once, 3.2 ms in
#: blocks of 16: large temporaries cost page faults on this machine)
SOLVE_BLOCK = 64

#: relative round-off of a gap: a free gap is a sum of displacements (the state columns times
#: their unit responses) that cancel in a line-to-line fit (a 0 / 0 um fit in a one-material
#: stack at a uniform temperature: free gaps up to 1.9e-15 mm at 0 C on the template's section
#: in 440C, where the displacements summed reach 0.026 mm (`ContactTolerance.reach_mm`), 7e-14
#: of them, the unit solutions' own round-off; measured 2026-12-01). Gaps and overlaps below
#: GAP_ROUNDOFF_REL of those displacements are zero: 1e-10 of 0.026 mm is 2.6e-12 mm, over a
#: thousand times the round-off and six decades below a micrometre
GAP_ROUNDOFF_REL = 1e-10


@dataclass(frozen=True)
class ContactTolerance:
    """What counts as zero in the contact conditions of n states (`Superposition.evaluate`).

    reach_mm (n,): the displacement scale of each state, sum_j |c_j| max_i |H_ij| (mm): its
    state columns c (thermal strains, omega^2, interferences) times the largest free gap each
    makes at any pair (`Superposition.H`), an upper bound of every term its free gaps sum.
    accept_gap_mm (n,): an open pair may overlap this much and the set still solves the state
    (1e-8 of the state's largest free gap, as before, or GAP_ROUNDOFF_REL x reach, the larger);
    step_gap_mm (n,): an open pair overlapping more closes in an active-set step (1e-10 of the
    largest free gap or the same round-off floor; never above accept_gap_mm, so a state a set
    does not solve always changes set). force_N (n,): closed pairs in tension below it are in
    contact (the force closing the round-off gap at the stiffest pair, GAP_ROUNDOFF_REL x reach
    / min_i A_ii; the relative tolerances of `ActiveSet` apply above it). Without these floors a
    state whose free gaps are all round-off (a line-to-line fit) has no scale but its own noise,
    and its active set cycles (0 / 0 um fits of a single-material stack at 0, 40, 60 C)."""
    reach_mm: np.ndarray
    accept_gap_mm: np.ndarray
    step_gap_mm: np.ndarray
    force_N: np.ndarray

    @classmethod
    def of(cls, G0: np.ndarray, C: np.ndarray, column_reach_mm: np.ndarray,
           flexibility_min_mm_per_N: float) -> "ContactTolerance":
        """Tolerances of states with free gaps G0 (n, n_pairs, mm) and state columns C (n,
        n_cols); column_reach_mm (n_cols,) = max_i |H_ij|; flexibility_min_mm_per_N: the
        smallest diagonal of the flexibility A."""
        largest = np.maximum(G0.max(axis=1, initial=0.0), -G0.min(axis=1, initial=0.0))
        largest = np.maximum(largest, 1e-12)                # each state's largest free gap, mm
        reach = np.abs(C) @ column_reach_mm
        floor = GAP_ROUNDOFF_REL * reach
        return cls(reach, np.maximum(1e-8 * largest, floor), np.maximum(1e-10 * largest, floor),
                   floor / flexibility_min_mm_per_N)


#: primal-dual steps of one state, with no state satisfied on the way, before
#: `Superposition.evaluate` gives up (a one-state active set settles in a few)
MAX_ACTIVE_SET_STEPS = 100


def _potrs(factor, b: np.ndarray) -> np.ndarray:
    """x = A^-1 b from A's Cholesky factor (`scipy.linalg.cho_factor`'s (c, lower)) by LAPACK's
    potrs, the routine `scipy.linalg.cho_solve` calls, called directly: the same numbers without
    cho_solve's per-call checks. b (n, k) should be Fortran-ordered (no copy)."""
    x, info = _POTRS(factor[0], b, lower=factor[1])
    if info != 0:
        raise SolveError(f"illegal value in argument {-info} of LAPACK potrs")
    return x


@dataclass(frozen=True)
class ActiveSet:
    """One contact status of the condensed contact problem (`Superposition`): its closed pairs C
    and open pairs O, the Cholesky factor of A_CC and its response to the state columns.

    For a fixed status the problem is linear (Wriggers, Computational Contact Mechanics, 2nd ed.,
    section 6.2): with the free gaps G0 = H c of a state c (`Superposition.H`, mm),

        A_CC lambda_C = -G0_C,    gap_O = G0_O + A_OC lambda_C

    so per state column, lambda_C = -A_CC^-1 H_C (N) and gap_O = H_O - A_OC A_CC^-1 H_C (mm):
    `response` (n_cols, n_pairs), columns in `rows` order (the closed pairs, then the open ones),
    gives both for any state by one product with its n_cols numbers. `satisfied` and `step` use
    it to find each state's set; `solve` gives the forces and gaps from the state's own free
    gaps (a back-substitution per state, as a direct solve of the set would)."""
    closed: np.ndarray          # bool (n_pairs,)
    rows: np.ndarray            # the closed pairs, then the open pairs (indices, ascending each)
    n_closed: int
    factor: tuple | None        # (c, lower) of A_CC (scipy.linalg.cho_factor); None: none closed
    response: np.ndarray        # (n_cols, n_pairs): N on the closed pairs, mm on the open ones

    @classmethod
    def of(cls, A: np.ndarray, H: np.ndarray, closed: np.ndarray) -> "ActiveSet":
        """The set `closed` of flexibility A (n_pairs, n_pairs, mm/N) and state columns H
        (n_pairs, n_cols, mm): one Cholesky factorisation and n_cols back-substitutions."""
        C, O = np.flatnonzero(closed), np.flatnonzero(~closed)
        factor, R = None, np.empty((H.shape[1], closed.size))
        R[:, C.size:] = H[O].T
        if C.size:
            A_C = A[C]                                  # rows, then columns: faster than ix_
            factor = cho_factor(A_C[:, C], check_finite=False)
            M = _potrs(factor, np.asfortranarray(H[C]))
            R[:, :C.size] = -M.T
            R[:, C.size:] -= M.T @ A_C[:, O]            # A symmetric: (A_OC M)^T = M^T A_CO
        return cls(closed.copy(), np.concatenate([C, O]), C.size, factor, R)

    def satisfied(self, V: np.ndarray, tol_gap_mm: np.ndarray, tol_force_N: np.ndarray
                  ) -> np.ndarray:
        """Which states this set solves, V (k, n_pairs) their forces and gaps under it (the
        state columns times `response`): no closed pair in tension beyond 1e-8 of the state's
        largest force or beyond tol_force_N (k,, round-off: `ContactTolerance`), no open pair
        overlapping beyond tol_gap_mm (k,)."""
        nc = self.n_closed
        ok = np.ones(V.shape[0], bool)
        if nc:
            lo, hi = np.minimum.reduce(V[:, :nc], axis=1), np.maximum.reduce(V[:, :nc], axis=1)
            ok &= lo >= -np.maximum(1e-8 * np.maximum(hi, -lo), tol_force_N)
        if nc < V.shape[1]:
            ok &= np.minimum.reduce(V[:, nc:], axis=1) >= -tol_gap_mm
        return ok

    def step(self, v: np.ndarray, tol_gap_mm: float, tol_force_N: float = 0.0) -> np.ndarray:
        """The next closed set of a state not solved by this one, v (n_pairs,) its forces and
        gaps under it: one primal-dual active-set step (Hueber & Wohlmuth 2005): an open pair
        overlapping beyond tol_gap_mm closes, a closed pair in tension beyond 1e-10 of the
        state's largest force (and beyond tol_force_N, round-off) opens."""
        x = np.empty(v.size)
        x[self.rows] = v
        tol_f = max(1e-10 * max(np.abs(v[:self.n_closed]).max(initial=0.0), 1e-12), tol_force_N)
        return np.where(self.closed, x >= -tol_f, x < -tol_gap_mm)

    def solve(self, G: np.ndarray, idx: np.ndarray, A: np.ndarray, lam: np.ndarray) -> None:
        """The forces (N) and gaps (mm) of states `idx` under this set, in place: G (n, n_pairs)
        holds their free gaps and is overwritten by their gaps, lam (n, n_pairs) receives their
        forces. A_CC lambda_C = -G0_C by back-substitution on the factor (LAPACK potrs), then
        gap = G0 + A lambda on the open pairs, 0 on the closed ones; gaps under 1e-15 mm are 0.
        States are taken SOLVE_BLOCK at a time (small arrays: this runs for every state)."""
        C = self.rows[:self.n_closed]
        every = self.n_closed == G.shape[1]     # every pair closed: no column gathers
        A_C = A[C] if self.factor is not None and not every else None
        for at in range(0, idx.size, SOLVE_BLOCK):
            rows = idx[at:at + SOLVE_BLOCK]
            g = G[rows]
            if self.factor is not None:
                # (g or g[:, C]).T is Fortran-ordered: potrs takes it without a copy
                x = -_potrs(self.factor, (g if every else g[:, C]).T).T       # (k, n_closed)
                if every:
                    lam[rows] = x
                    G[rows] = 0.0
                    continue
                L = np.zeros_like(g)
                L[:, C] = x
                lam[rows] = L
                g += x @ A_C
                g[:, C] = 0.0
            g[(g < 1e-15) & (g > -1e-15)] = 0.0
            G[rows] = g


@dataclass(frozen=True)
class SuperposedStates:
    """What `Superposition.evaluate` returns for n states with n_pairs contact node pairs.

    force_N (n, n_pairs): contact force per pair, N (+ compression); gap_mm (n, n_pairs): the gap
    of each pair, mm (0 where closed); status (n,): the index into closed_sets of the active set
    each state was solved with; closed_sets: the active sets (bool (n_pairs,) each, True =
    closed); probe (n, n_probe): the probed displacements, mm (None without a probe matrix)."""
    force_N: np.ndarray
    gap_mm: np.ndarray
    status: np.ndarray
    closed_sets: list
    probe: np.ndarray | None


@dataclass(frozen=True)
class Condensed:
    """A `FitSolver`'s contact problem condensed to its fit interface: everything
    `Superposition.evaluate` needs, independent of the mesh size once built (`fem.setup` stores
    it across runs).

    bonded: the fits are tied (their status never changes). n_parts, n_fits: FE parts and fits.
    The n_loads = n_parts + 1 load columns: unit thermal strain of each part, then the
    centrifugal load of the spinning parts at omega^2 = 1 rad^2/s^2.
    fit_of_pair (n_pairs,): the fit of each contact node pair. Frictionless fits: B (n_pairs,
    n_loads) the gap (mm) per unit load column with every pair open; A (n_pairs,
    n_pairs) the flexibility (mm/N), gap change per newton of pair force, symmetric;
    probe_units (n_probe, n_loads + n_pairs) the probed displacements (mm) per unit load column
    and per newton of pair force. Bonded fits: probe_units (n_probe, n_loads + n_fits) per unit
    load column and per mm of radial interference, bonded_force (n_pairs, n_loads + n_fits) the
    pair forces (N) per the same units. Arrays a variant does not use have size 0; n_probe is 0
    without a probe matrix."""
    bonded: bool
    n_parts: int
    n_fits: int
    fit_of_pair: np.ndarray
    B: np.ndarray
    A: np.ndarray
    probe_units: np.ndarray
    bonded_force: np.ndarray


def load_columns(theta: np.ndarray, omega2_rad2_s2=None) -> np.ndarray:
    """(n_states, n_parts + 1): the thermal strains, then omega^2 (rad^2/s^2; None = 0)."""
    theta = np.atleast_2d(theta)
    w2 = (np.zeros(theta.shape[0]) if omega2_rad2_s2 is None
          else np.broadcast_to(np.asarray(omega2_rad2_s2, float), (theta.shape[0],)))
    return np.column_stack([theta, w2])


def _unit_loads(m: "StackModel") -> np.ndarray:
    """(ndofs, n_parts + 1): the load vector of every load column (see `Condensed`)."""
    return np.column_stack([m.unit_loads, m.spin_load])


def _tie_representatives(N: int, masters: np.ndarray, slaves: np.ndarray,
                         fixed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(slaves, representatives): every tied DOF but one per connected group of ties, each
    with the DOF that carries its group (a fixed DOF of the group if any, else its lowest).
    Connected groups by scipy.sparse.csgraph.connected_components; loops of ties are allowed."""
    if slaves.size == 0:
        return slaves, masters
    g = sp.csr_matrix((np.ones(slaves.size), (masters, slaves)), shape=(N, N))
    label = sp.csgraph.connected_components(g, directed=False)[1]
    tied = np.unique(np.concatenate([masters, slaves]))
    lab = label[tied]
    # lowest key per group: fixed DOFs first (key -N + dof), then the lowest DOF
    key = np.where(fixed[tied], tied - N, tied)
    rep_key = np.full(label.max() + 1, np.iinfo(np.int64).max)
    np.minimum.at(rep_key, lab, key)
    rep = np.where(rep_key < 0, rep_key + N, rep_key)[lab]
    other = tied != rep
    return tied[other], rep[other]


def _bonded_units_load(s: FitSolver) -> tuple[np.ndarray, np.ndarray]:
    """Loads and interferences of the bonded unit solutions: unit thermal strain of each part,
    omega^2 = 1 rad^2/s^2, then 1 mm radial interference of each fit."""
    m = s.model
    n_loads, n_fits = len(m.part_names) + 1, len(m.fits)
    return (np.hstack([_unit_loads(m), np.zeros((m.ndofs, n_fits))]),
            np.vstack([np.zeros((n_loads, n_fits)), np.eye(n_fits)]))


@single_thread_blas
def condense(solver: FitSolver, probe: sp.csr_matrix | None = None) -> Condensed:
    """The condensed contact problem of `solver` (see `Superposition`): one factorisation of the
    system with every pair open and one solve per load column (part, spin) and per contact pair;
    bonded fits: the tied system, one solve per load column and per fit. `probe` (n_probe, ndofs)
    maps displacements to the values `evaluate` returns as "probe"."""
    m, s = solver.model, solver
    n_parts, n_fits, npair = len(m.part_names), len(m.fits), s.n_pairs
    n_loads = n_parts + 1
    none = np.zeros((0, 0))
    if s.bonded:
        F, D = _bonded_units_load(s)
        U = s.solve_status(np.ones(npair, bool), F, D)
        PU = np.zeros((0, n_loads + n_fits)) if probe is None else probe @ U
        return Condensed(True, n_parts, n_fits, s.fit_of_pair.copy(), none, none,
                         np.ascontiguousarray(PU), np.ascontiguousarray(s.pair_values(U, F, D)[0]))
    T, lu = s.factorize(np.zeros(npair, bool))
    loads = _unit_loads(m)
    n_cols = n_loads + npair
    rel = np.empty((npair, n_cols))
    PU = np.empty((0 if probe is None else probe.shape[0], n_cols))
    # the load columns, then a unit pair force per pair (+1 on its slave, -1 on its master DOF),
    # solved CONDENSE_BLOCK columns at a time: only the pair rows and the probes of each block's
    # displacements are kept, so memory is DOFs x CONDENSE_BLOCK, not DOFs x pairs
    for c0 in range(0, n_cols, CONDENSE_BLOCK):
        cols = np.arange(c0, min(c0 + CONDENSE_BLOCK, n_cols))
        F = np.zeros((m.ndofs, cols.size))
        is_load = cols < n_loads
        F[:, is_load] = loads[:, cols[is_load]]
        at, pair = np.flatnonzero(~is_load), cols[~is_load] - n_loads
        F[s.slave[pair], at] = 1.0
        F[s.master[pair], at] -= 1.0
        U = T @ _lu_solve(lu, T.T @ F)
        rel[:, cols] = U[s.slave] - U[s.master]
        if probe is not None:
            PU[:, cols] = probe @ U
    A = rel[:, n_loads:] + np.diag(s.compliance)     # a pair's series spring: c_p on its diagonal
    return Condensed(False, n_parts, n_fits, s.fit_of_pair.copy(), np.ascontiguousarray(rel[:, :n_loads]),
                     0.5 * (A + A.T), np.ascontiguousarray(PU), none)
