"""The pair under axial load (and thermal and fit shifts of the groove centres): the axial-only
equilibrium of `solve_pair` (module docstring of `analytic.bearing` for the model and conventions).
Harris & Kotzalas Vol. 1 ch. 7 (axial-load equation); Jones 1960. Units: mm, N; radians inside."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.bearing.contact import ContactStiffness, axial_state, contact_stiffness
from analytic.bearing.geometry import (SIGNS, BearingGeometry, ThermalGeometry, pair_array,
                                       pair_thermal_geometry, thermal_geometry)
from analytic.bearing.roots import newton_increasing, safeguarded_step
from analytic.bearing.state import PairState, contact_ellipses, pair_state
from infra.memo import Memo


@dataclass(frozen=True)
class Approach:
    """Axial approach of a bearing carrying a given axial force (`approach_for_force`)."""
    a_mm: np.ndarray
    alpha_rad: np.ndarray
    cs: ContactStiffness
    converged: np.ndarray


def _onset_X(Y, A_T):
    """Axial centre-distance component at first contact, sqrt(A_T^2 - Y^2) (0 if radially loaded)."""
    return np.sqrt(np.maximum(A_T * A_T - Y * Y, 0.0))


def _solve_X_for_force(F_N, Y, A_T, cs: "ContactStiffness", Z, alpha_lin, x0=None):
    """X with Z K_n(alpha) delta^1.5 sin(alpha) = F, K_n linearised about alpha_lin; from x0
    (default: delta = (F / (Z K_n sin(alpha)))^(2/3) at alpha_lin, then once more at the angle
    of that delta, X = sqrt((A_T + delta)^2 - Y^2))."""
    Xc = _onset_X(Y, A_T)
    sa = np.sin(np.maximum(alpha_lin, 0.05))
    Fp = np.maximum(F_N, 0.0)
    d_est = (Fp / (Z * cs.Kn * sa)) ** (2.0 / 3.0)
    if x0 is None:
        D = A_T + d_est
        X1 = np.sqrt(np.maximum(D * D - Y * Y, 0.0))
        a1 = np.arctan2(X1, Y)
        Kn1 = cs.Kn * np.exp(cs.dlnKn_dalpha * (a1 - alpha_lin))
        d1 = (Fp / (Z * Kn1 * np.maximum(np.sin(a1), 0.05))) ** (2.0 / 3.0)
        x0 = np.sqrt(np.maximum((A_T + d1) ** 2 - Y * Y, 0.0))

    def fun(X):
        st = axial_state(X, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
        return st.F_N - F_N, st.k_N_per_mm
    return newton_increasing(fun, x0, lo=Xc, step0=np.maximum(d_est, 1e-6))


def _kn_ratio(cs_new: "ContactStiffness", cs_old: "ContactStiffness", alpha, alpha_lin):
    """Exact K_n at the new angle over its linear model about the old one."""
    return cs_new.Kn / (cs_old.Kn * np.exp(cs_old.dlnKn_dalpha * (alpha - alpha_lin)))


def _kn_converged(cs_new: "ContactStiffness", cs_old: "ContactStiffness", alpha, alpha_lin, tol):
    """Exact K_n at the new angle against its linear model about the old one, to tol."""
    return bool((np.abs(_kn_ratio(cs_new, cs_old, alpha, alpha_lin) - 1.0) <= tol).all())


def approach_for_force(g: BearingGeometry, F_N, dr_mm=0.0, tg: ThermalGeometry | None = None,
                       tol: float = 1e-14, max_outer: int = 30, alpha_start=None):
    """Axial approach a (mm) at which one bearing carries the axial force F_N, with radial centre
    shift dr_mm and grown geometry tg (default: free geometry at T_ref).  Harris's equation solved
    for the contact angle with the radial shift kept: returns an `Approach` (a_mm, alpha_rad,
    ContactStiffness, converged)."""
    tg = tg or thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    F = np.asarray(F_N, float)
    Y = g.A0_mm * np.cos(a0) + np.asarray(dr_mm, float)
    shape = np.broadcast_shapes(F.shape, Y.shape, np.shape(tg.A_T_mm))
    F, Y = np.broadcast_to(F, shape), np.broadcast_to(Y, shape)
    A_T = np.broadcast_to(tg.A_T_mm, shape)
    alpha_lin = np.full(shape, a0) if alpha_start is None else np.broadcast_to(alpha_start, shape)
    cs = contact_stiffness(g, tg, alpha_lin)
    X = None
    for _ in range(max_outer):
        # from the second pass on, from the last pass's X (K_n's model moved by its last change)
        root = _solve_X_for_force(F, Y, A_T, cs, g.Z, alpha_lin, X)
        X = root.x
        alpha = np.arctan2(X, Y)
        cs_new = contact_stiffness(g, tg, alpha)
        done = _kn_converged(cs_new, cs, alpha, alpha_lin, tol)
        cs, alpha_lin = cs_new, alpha
        if done:      # X carries F with a K_n model matching the exact K_n at alpha to tol
            break
    ok = root.converged & cs.converged & done
    return Approach(X - g.A0_mm * np.sin(a0), alpha, cs, ok)


def bearing_axial_force(g: BearingGeometry, approach_mm, dr_mm=0.0, tg: ThermalGeometry | None = None):
    """Axial force (N) of one bearing at axial approach a (mm) and radial centre shift dr (mm),
    K_n evaluated exactly at the resulting contact angle: returns (BearingState, ContactStiffness)."""
    tg = tg or thermal_geometry(g)
    a0 = np.radians(g.alpha0_deg)
    X = g.A0_mm * np.sin(a0) + np.asarray(approach_mm, float)
    Y = g.A0_mm * np.cos(a0) + np.asarray(dr_mm, float)
    X, Y = np.broadcast_arrays(X, Y)
    cs = contact_stiffness(g, tg, np.arctan2(X, Y))
    return axial_state(X, Y, tg.A_T_mm, cs.Kn, g.Z), cs


# ---------------------------------------------------------------------------------------------
@dataclass
class _LinearKn:
    """First-order model of K_n(alpha) about some angle (the solvers' working copy)."""
    Kn: np.ndarray
    dlnKn_dalpha: np.ndarray


#: the reference states' approaches (`approach_for_force` at T_ref) by their exact inputs: a
#: diagnosis solves the pair hundreds of times with the same assembled preload and reference
#: shifts, and this one-point solve (Python overhead) was a third of seed 000's pair solve
#: (measured 2026-11-29: 1.2 of 3.8 CPU s in the bench's per-part lag kind); a pure function of
#: its key, so a kept value is the value made anew (`infra.memo`, read-only)
_REFERENCE_APPROACHES = Memo(max_items=32, read_only=True)   # 32: a diagnosis meets a few preloads


def reference_state(g: BearingGeometry, s, P, c, dr_ref, dz_ref, tol):
    """Position-preload offset e and rotor position x at the reference state (free geometry at
    T_ref, shifts dr_ref/dz_ref, no external load, F_A = F_B = P):
        a_j* = approach of bearing j carrying P;  a_j* + c P = s_j (dz_j + x) + e
    Two equations for e and x (s_A = -s_B):  e = (a_A + a_B - s_A (dz_A - dz_B))/2 + c P.
    Computed once per distinct (P, dr_ref) combination (usually one)."""
    N = P.shape[0]
    keys = np.column_stack([P, dr_ref[0], dr_ref[1]])
    if np.all(keys == keys[0]):
        uniq, inv = keys[:1], np.zeros(N, dtype=int)
    else:
        uniq, inv = np.unique(keys, axis=0, return_inverse=True)
        inv = inv.ravel()
    ap = _REFERENCE_APPROACHES.get_or_make(
        (g, uniq.shape, uniq.tobytes(), float(tol)),
        lambda: approach_for_force(g, uniq[:, 0][None, :], uniq[:, 1:].T, thermal_geometry(g),
                                   tol))
    a_u, alpha_u, cs_u = ap.a_mm, ap.alpha_rad, ap.cs
    a_ref = a_u[:, inv]
    a_nom = a_ref + c * P
    e = 0.5 * (a_nom[0] + a_nom[1] - s[0, 0] * (dz_ref[0] - dz_ref[1]))
    x = s[0, 0] * (a_nom[0] - e) - dz_ref[0]
    lin = _LinearKn(cs_u.Kn[:, inv], cs_u.dlnKn_dalpha[:, inv])
    return e, x, alpha_u[:, inv], lin, ap.converged.all(axis=0)[inv]



@dataclass(frozen=True)
class PairRoot:
    """Rotor position x (N,) and the bearings' centre-distance components X (2, N) of a position-
    preloaded pair (`position_root`), with the convergence flag per point, and the forces and
    their derivatives (2, N) at the last evaluation (within the last step of X)."""
    x_mm: np.ndarray
    X_mm: np.ndarray
    converged: np.ndarray
    F_N: np.ndarray
    k_N_per_mm: np.ndarray


def position_root(force, X0, s, dz, e, Fext, c, x0, X_start, step0, X_onset=None,
                  xtol: float = 1e-15, max_iter: int = 200) -> PairRoot:
    """Equilibrium of a position-preloaded pair (pair conventions of the module docstring of
    `analytic.bearing`; Harris & Kotzalas Vol. 1 ch. 7 per bearing):

        X_j + c F_j(X_j) = X0 + s_j (dz_j + x) + e       (j = A, B: preload path in series)
        sum_j s_j F_j(X_j) = F_ext

    three unknowns per point, x (mm) and X_j (mm); force(X) -> (F (N), dF/dX (N/mm)), each
    (2, N), F increasing in X; X0 (mm) the free axial component, s (2, 1) the arrangement signs,
    dz (2, N) (mm), e (mm), Fext (N), c (mm/N, >= 0), each (N,); x0 (N,) and X_start (2, N) the
    start, step0 (mm) the first step away from a flat side.  Newton's method on all three
    unknowns at once (Dennis & Schnabel 1983 ch. 5), the series equations eliminated from the
    linear step (its Schur complement):

        x_j = s_j (X_j + c F_j - X0 - e) - dz_j     (the rotor position X_j is consistent with)
        w_j = 1 / (1 + c k_j),  k_eff = sum_j w_j k_j
        x_new = (sum_j w_j k_j x_j - R) / k_eff,    R = sum_j s_j F_j - F_ext
        X_j,new = X_j + s_j w_j (x_new - x_j)

    Safeguarded on x as `roots.newton_increasing` is (`roots.safeguarded_step`): s_j F_j is an
    increasing function of the rotor position through the exact compliance solve, and X_j is the
    exact solve at x_j, so R <= 0 puts the root above min_j x_j and R >= 0 below max_j x_j (a
    bracket without an inner solve).  A point has converged when the step of every unknown is
    below xtol (1 + |value|) mm (the criterion of the Newton iteration in x around one in X per
    bearing that this replaced), x's below xtol max(1 + |x|, c |F_j|) (x is the difference of
    terms of size c F_j: a soft spring's 5e4 mm at c = 500 mm/N) and X_j's, beyond its own, by
    w_j times that excess (x's rounding reaches X_j through its step); a point whose bearings carry nothing (R = 0, k_eff = 0) stays at
    its x.

    X_onset (2, N), optional: X at each bearing's first contact (F = 0 for |X| <= X_onset).  With
    F_ext = 0 a pair whose preload is lost has a whole interval of roots (both bearings free);
    Newton reaches its end only linearly while one bearing still carries the residual alone
    (F ~ delta^1.5: each step leaves a third of delta).  Where that bearing's first contact is a
    root (the other bearing free there too) and Newton's step falls short of it, the iterate
    goes there directly: x at X_j = X_onset_j, the other bearing at its nominal X (the limit the
    Newton steps converge to).  Returns a `PairRoot`."""
    sA, sB = float(s[0, 0]), float(s[1, 0])
    x = np.array(x0, dtype=float, copy=True)
    X = np.array(X_start, dtype=float, copy=True)
    lo, hi = np.full_like(x, -np.inf), np.full_like(x, np.inf)
    step = np.full(x.shape, step0, float)
    done = np.zeros(x.shape, bool)
    Xc = X0 + e
    flat = None
    if X_onset is not None and (Fext == 0.0).any():
        # rotor position at each bearing's first contact (F_j = 0 there, so X_j = X_nom,j) and
        # whether the other bearing is free there too (then it is a root)
        x_on = s * (X_onset - Xc) - dz
        X_other = Xc + s[::-1] * (dz[::-1] + x_on)
        flat = (Fext == 0.0) & (X_onset > 0.0) & (np.abs(X_other) < X_onset[::-1])
        if not flat.any():
            flat = None
    for _ in range(max_iter):
        F, k = force(X)
        xj = s * (X + c * F - Xc) - dz
        w = 1.0 / (1.0 + c * k)
        kw = k * w
        (xA, xB), (kA, kB) = xj, kw
        keff = kA + kB
        R = sA * F[0] + sB * F[1] - Fext
        lo = np.where(R <= 0.0, np.maximum(lo, np.minimum(xA, xB)), lo)
        hi = np.where(R >= 0.0, np.minimum(hi, np.maximum(xA, xB)), hi)
        free = not keff.all()
        with np.errstate(divide="ignore", invalid="ignore"):      # keff = 0: both bearings free
            cand = (kA * xA + kB * xB - R) / keff
        jump = None
        if flat is not None:
            # bearing j alone loaded (on its own flank) and Newton's step short of its first contact
            alone = flat & (F > 0.0) & (kw[::-1] == 0.0) & ((cand - xj) * (x_on - cand) > 0.0)
            if alone.any():
                jump = alone
                cand = np.where(alone[0], x_on[0], np.where(alone[1], x_on[1], cand))
        new, step = safeguarded_step(x, cand, R, keff, lo, hi, step, xtol)
        if free:
            new = np.where((R == 0.0) & (keff == 0.0), x, new)
        X_new = X + s * w * (new - xj)
        if jump is not None:
            jump &= new == x_on
            X_new = np.where(jump, X_onset, np.where(jump[::-1], Xc + s * (dz + new), X_new))
        # x is resolved only to the rounding of x_j's terms: c F_j (mm) reaches 5e4 mm on a
        # spring of 1e-3 N/mm (c = 500 mm/N at 100 N), against |x| ~ 1e-3 mm; that rounding
        # reaches X_j through its step, weighted w_j (a free bearing's X follows x one to one)
        x_scale = np.maximum(1.0 + np.abs(x), (c * np.abs(F)).max(axis=0))
        x_round = xtol * (x_scale - (1.0 + np.abs(x)))
        done = ((np.abs(new - x) <= xtol * x_scale)
                & (np.abs(X_new - X) <= xtol * (1.0 + np.abs(X)) + w * x_round).all(axis=0))
        x, X = new, X_new
        if done.all():
            break
    return PairRoot(x, X, done & np.isfinite(x) & np.isfinite(X).all(axis=0), F, k)


def solve_pair_axial(g: BearingGeometry, arrangement: str, N: int, *, dr_mm, dz_mm,
                     T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref_C: float, preload_kind: str,
                     preload_assembled_N, axial_load_N, dr_ref_mm, dz_ref_mm,
                     compliance_mm_per_N, tol: float, max_outer: int) -> PairState:
    """Axial-only equilibrium of the pair at N points (inputs as `analytic.bearing.solve_pair`)."""
    s = SIGNS[arrangement][:, None]
    a0 = np.radians(g.alpha0_deg)
    X0, Y0 = g.A0_mm * np.sin(a0), g.A0_mm * np.cos(a0)
    Z = g.Z
    P = np.broadcast_to(np.asarray(preload_assembled_N, float), (N,))
    Fext = np.broadcast_to(np.asarray(axial_load_N, float), (N,))
    c = np.broadcast_to(np.asarray(compliance_mm_per_N, float), (N,))
    dr, dz = pair_array(dr_mm, N), pair_array(dz_mm, N)
    T_ref = float(T_ref_C)
    tg = pair_thermal_geometry(g, T_inner_ring_C, T_outer_ring_C, T_ball_C, T_ref, N)
    Y = Y0 + dr
    A_T = tg.A_T_mm

    if preload_kind == "position":
        e, x, alpha_lin, cs, ok = reference_state(g, s, P, c, pair_array(dr_ref_mm, N),
                                                   pair_array(dz_ref_mm, N), tol)
        # operating state: K_n linearised about alpha_lin (first pass: the reference state's),
        # refreshed at the operating geometry until the linear model is exact to tol; start:
        # x and the compliance deflection c P of the reference state
        scale = 1e-3 * g.Dw_mm
        X = X0 + s * (dz + x) + e - c * P
        X_onset = _onset_X(Y, A_T)
        for _ in range(max_outer):
            lin, at = cs, alpha_lin

            def force(XX):
                st = axial_state(XX, Y, A_T, lin.Kn, Z, lin.dlnKn_dalpha, at)
                return st.F_N, st.k_N_per_mm
            root = position_root(force, X0, s, dz, e, Fext, c, x, X, scale, X_onset)
            x, X = root.x_mm, root.X_mm
            alpha = np.arctan2(X, Y)
            cs_new = contact_stiffness(g, tg, alpha)
            ratio = _kn_ratio(cs_new, cs, alpha, alpha_lin)
            done = bool((np.abs(ratio - 1.0) <= tol).all())
            cs, alpha_lin = cs_new, alpha
            if done:
                break
            # the next pass from X moved by one Newton step of its series equation under the
            # refreshed model, which scales the force at X by `ratio`: X + c ratio F(X) = X_nom
            F, k = ratio * root.F_N, ratio * root.k_N_per_mm
            X = X - c * (F - root.F_N) / (1.0 + c * k)
        ok = ok & root.converged & cs.converged.all(axis=0) & done
        # converged: x solves the equilibrium with a K_n model that matches the exact K_n at the
        # final angle to tol, so the state below (exact K_n) balances the load to tol
        e_out = e
    else:
        FA = s[0, 0] * Fext + P
        lost_spring = FA < 0.0
        Freq = np.stack([np.maximum(FA, 0.0), P])
        ap = approach_for_force(g, Freq, dr, tg, tol)
        a_op, alpha_lin, cs, ok = ap.a_mm, ap.alpha_rad, ap.cs, ap.converged.all(axis=0)
        X = X0 + a_op
        x = s[0, 0] * a_op[0] - dz[0]                  # rotor position implied by bearing A (e = 0)
        e_out = np.full(N, np.nan)

    # final state with K_n exact at alpha_lin (converged: alpha = alpha_lin to tol) and the full
    # axial stiffness dF/dX including dK_n/dalpha
    st = axial_state(X, Y, A_T, cs.Kn, Z, cs.dlnKn_dalpha, alpha_lin)
    alpha = st.alpha_rad
    k_full = st.k_N_per_mm
    if preload_kind == "position":
        k_eff = k_full / (1.0 + c * k_full)
        k_pair = k_eff.sum(axis=0)
        lost = (st.F_N <= 0.0).any(axis=0)
    else:
        k_eff = k_full
        k_pair = np.where(st.F_N[0] > 0.0, k_full[0], 0.0)   # the spring side adds ~nothing
        lost = lost_spring | (st.F_N[0] <= 0.0)

    inner, outer = (contact_ellipses(g, cs, st.Q_N, side) for side in (0, 1))
    return pair_state(F_N=st.F_N, alpha_rad=alpha, Q_N=st.Q_N, delta_mm=st.delta_mm, inner=inner,
                      outer=outer,
                      max_contact_pressure_MPa=np.maximum(inner.p_max_MPa, outer.p_max_MPa).max(axis=0),
                      k_bearing_N_per_mm=k_eff, k_pair_N_per_mm=k_pair, lost=lost, x_mm=x,
                      offset_mm=e_out, approach_mm=X - X0, converged=ok & np.isfinite(st.F_N).all(axis=0))
