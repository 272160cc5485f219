"""Angular-contact ball bearing pair: geometry, preload, contact angle, Hertz contact, stiffness.

Units: mm, N, MPa, C; angles in degrees at the interface, radians inside.

Model (balls are analytic, structures are FE: README.md, first paragraph).  A bearing's state is fixed by
the positions of its inner and outer groove curvature centres (Harris & Kotzalas, Rolling Bearing
Analysis 5th ed., Vol. 1 ch. 2 and 7; Jones 1960).  Free and unloaded, the centres are
A0 = (f_i + f_o - 1) Dw apart along the free contact angle alpha0.  With the FE shifts of the inner
relative to the outer groove centre, dr (radial) and dz (axial, global z), and the axial approach
a_j of bearing j,

    X_j = A0 sin(alpha0) + a_j                (axial component of the centre distance)
    Y_j = A0 cos(alpha0) + dr_j               (radial component)
    D_j = sqrt(X_j^2 + Y_j^2),  alpha_j = atan2(X_j, Y_j)
    A_T = Dw [f_i (1 + theta_ir) + f_o (1 + theta_or) - (1 + theta_b)]   (r_i + r_o - Dw, grown)
    delta_j = D_j - A_T                       (inner + outer contact deformation in series)
    Q_j = K_n(alpha_j) delta_j^1.5,  F_j = Z Q_j sin(alpha_j)   (Harris Vol. 1 ch. 7)

theta = Material.thermal_strain(T, T_ref) of the inner ring, outer ring and ball.  K_n combines the
inner and outer Hertz stiffnesses in series (`hertz.series_stiffness_N_per_mm15`), each from the
exact Hertz solution at the current contact angle and the thermally grown Dw, groove radii and pitch
diameter.  delta <= 0 means the bearing is unloaded (Q = 0), not an error.  One contact model in
every solver: full-groove contact, a ball whose centre-distance vector points to X < 0 touches the
other flank of its grooves at the negative angle atan2(X, Y) (a deep-groove bearing pushed past its
axial play; an angular-contact pair only far beyond its preload), so the limit of a vanishing
radial load or moment is the axial-only solution.  Without dr and thermal
strain, F = Z K_n A0^1.5 (cos alpha0/cos alpha - 1)^1.5 sin alpha: Harris's axial-load equation
(Vol. 1 ch. 7, thrust-loaded bearing); the tests hold the two equal.

Pair conventions (fixed; other code relies on them).  Bearings A (lower z) and B (higher z),
arrangement "DB" (back-to-back, s_A = +1, s_B = -1) or "DF" (face-to-face, s_A = -1, s_B = +1):

    a_j = s_j (dz_j + x) + e - c F_j         x: rotor axial displacement (unknown)
    sum_j s_j F_j = axial_load_N             external axial load on the rotor in +z

e is the position-preload offset: found once so that in the reference state (dr_ref, dz_ref, all
temperatures T_ref, no external load) F_A = F_B = preload_assembled_N, then kept fixed; c is an
optional compliance of the preload path (mm/N).  Spring preload: a constant force P on bearing B's
outer ring, F_B = P, F_A = s_A axial_load + P; if that is negative the preload is lost (F_A = 0).

Solution.  Eliminating the load-dependent K_n by an outer loop (K_n linearised in the contact
angle about the last pass's angles, refreshed until the linear model is exact to tol: two passes
as a rule), the inner problem is monotone in x: with a compliant preload path, one Newton
iteration on x and both bearings' X at once (`axial.position_root`, the series equations
eliminated from the step), kept inside a bracket on x from the signs of the balance (bisection
when Newton leaves it, doubling steps when both bearings are unloaded).  Everything is
vectorised over operating points, the two bearings on a leading axis of length 2.

Combined axial and radial load (`combined.solve_pair_combined`, chosen by `solve_pair` when a
radial load or a moment is given): the quasi-static load distribution around the ball set (Harris
& Kotzalas Vol. 1 ch. 7, Jones 1960; seed 003).  Ball k of Z sits at psi_k = 2 pi k / Z from the load
direction, the rigid rotor's radial displacement rho adds rho cos(psi_k) to Y_j, every ball has its
own delta, contact angle and K_n, and the radial equation
sum_j sum_k Q_jk cos(alpha_jk) cos(psi_k) = radial load joins the axial one.  With the bearing span
(distance of the ball planes) given, the rotor also tilts by theta about the mid-point of the pair
(`combined.tilt_arms_mm`: each inner groove centre moves axially by -theta R_i cos(psi) and radially
by theta l_j cos(psi)), the radial load acts at the mid-point and sum_j M_j = moment joins them;
without it the rotor is held against tilt (rho common to both bearings).  With K_n frozen the
equations are the stationarity conditions of a convex potential, solved by a safeguarded Newton
method, with the same outer K_n loop.

At speed (`ball_model="quasi_dynamic"`, `dynamic.solve_pair_dynamic`): the axial-only pair with
every ball in its quasi-dynamic equilibrium (`ball_dynamics.solve_balls`: centrifugal force,
gyroscopic moment, outer/inner/Jones raceway control), so inner and outer contact angles and loads
differ; the bearing's axial force is that of its inner contacts; under a radial load or moment
the combined-load solver takes the same balls ball by ball (`dynamic.DynamicBallSet`).  Not
modelled in the pair solvers: a moment about the radial load direction (loads in one plane),
shaft bending (rigid rotor).

Modules: geometry (free and grown geometry, pair conventions), contact (K_n from exact Hertz,
bearing and ball-set states), roots (root finders with convergence flags), axial (axial-only
equilibrium), combined (combined load), state (`PairState`, the one typed result),
ball_dynamics (quasi-dynamic ball), dynamic (the pair at speed), single (one bearing, 5 DOF).
"""
from __future__ import annotations

import numpy as np

from analytic.bearing.axial import approach_for_force, bearing_axial_force, solve_pair_axial
from analytic.bearing.ball_dynamics import BALL_MODELS
from analytic.bearing.combined import solve_pair_combined
from analytic.bearing.dynamic import DynamicContacts, solve_pair_dynamic
from analytic.bearing.contact import (axial_state, ball_azimuths_rad, ball_set_state,
                                      contact_stiffness)
from analytic.bearing.geometry import (SIGNS, BearingGeometry, ThermalGeometry, n_points,
                                       thermal_geometry)
from analytic.bearing.state import ContactEllipses, PairState, RadialLoadState, concatenate_states


def solve_pair(g: BearingGeometry, arrangement: str = "DB", *, dr_mm=0.0, dz_mm=0.0,
               T_inner_ring_C=None, T_outer_ring_C=None, T_ball_C=None, T_ref_C: float = 20.0,
               preload_kind: str = "position", preload_assembled_N=100.0, axial_load_N=0.0,
               dr_ref_mm=0.0, dz_ref_mm=0.0, compliance_mm_per_N=0.0,
               tol: float = 1e-14, max_outer: int = 30, chunk: int = 8192,
               radial_load_N=0.0, return_ball_loads: bool = False, moment_Nmm=0.0,
               bearing_span_mm=None, speed_rpm=0.0, ball_model: str = "static",
               control: str = "outer") -> PairState:
    """Equilibrium of a preloaded pair of identical bearings, vectorised over N operating points.

    Inputs (mm, C, N), scalars or arrays of shape (N,) (both bearings) or (2, N) (A, B):
      dr_mm, dz_mm      inner minus outer groove-centre shift, radial and axial (global z), relative
                        to the free unmounted bearing at T_ref (from the FE: fits, thermal growth)
      T_*_C, T_ref_C    part temperatures (ring and ball growth of groove radii and ball), default T_ref
      preload_kind      "position" (offset e fixed at the reference state) or "spring" (F_B = P)
      preload_assembled_N   P, set at the reference state (position) or the spring force
      axial_load_N      external axial load on the rotor, +z
      dr_ref_mm, dz_ref_mm  shifts of the reference (assembled) state
      compliance_mm_per_N   axial compliance c of the preload path (position preload)
      radial_load_N     (scalar or (N,), along the azimuth of ball 0): with a non-zero radial
                        load at any point, or return_ball_loads=True (every ball's state in
                        `PairState.radial`), the combined-load solver runs (`combined.solve_pair_combined`; points without radial load keep
                        the axial-only state); otherwise the axial-only one
                        (`axial.solve_pair_axial`).
      moment_Nmm        (scalar or (N,)) tilting moment on the rotor about the mid-point of the
                        pair, in the plane of the radial load; a non-zero moment also runs the
                        combined-load solver and needs bearing_span_mm
      bearing_span_mm   distance between the ball planes of bearings A and B (mm): with it the
                        rotor is free to tilt in the combined-load solver (radial load at the
                        mid-point); without it the rotor is held against tilt
      ball_model        "static" (quasi-static balls, speed ignored) or "quasi_dynamic": every
                        ball in its own equilibrium at speed_rpm (scalar or (N,), inner rings
                        rotating) with centrifugal force and gyroscopic moment, raceway control
                        `control` ("outer", "inner", "jones"): `dynamic.solve_pair_dynamic`,
                        or with a radial load or moment `combined.solve_pair_combined` with
                        quasi-dynamic balls
    Conventions and formulas: module docstring.

    Returns a `PairState` (`state.py`: per-bearing arrays (2, N), A first; `converged` per point).
    Large N is processed in blocks of `chunk` points (working arrays stay in cache; the result
    does not depend on it).
    """
    if arrangement not in SIGNS:
        raise ValueError(f"arrangement must be 'DB' or 'DF', got {arrangement!r}")
    if preload_kind not in ("position", "spring"):
        raise ValueError(f"preload_kind must be 'position' or 'spring', got {preload_kind!r}")
    if ball_model not in BALL_MODELS:
        raise ValueError(f"ball_model must be one of {', '.join(BALL_MODELS)}, got {ball_model!r}")
    args = dict(dr_mm=dr_mm, dz_mm=dz_mm, T_inner_ring_C=T_inner_ring_C,
                T_outer_ring_C=T_outer_ring_C, T_ball_C=T_ball_C,
                preload_assembled_N=preload_assembled_N, axial_load_N=axial_load_N,
                dr_ref_mm=dr_ref_mm, dz_ref_mm=dz_ref_mm, compliance_mm_per_N=compliance_mm_per_N)
    combined = (return_ball_loads or np.any(np.asarray(radial_load_N, float) != 0.0)
                or np.any(np.asarray(moment_Nmm, float) != 0.0))
    if ball_model == "quasi_dynamic" and combined:
        return solve_pair_combined(g, arrangement, T_ref_C=T_ref_C, preload_kind=preload_kind,
                                   radial_load_N=radial_load_N, tol=tol, max_outer=max_outer,
                                   chunk=chunk, moment_Nmm=moment_Nmm,
                                   bearing_span_mm=bearing_span_mm, speed_rpm=speed_rpm,
                                   control=control, **args)
    if ball_model == "quasi_dynamic":
        solver = lambda n, **sub: solve_pair_dynamic(  # noqa: E731
            g, arrangement, n, T_ref_C=T_ref_C, preload_kind=preload_kind, control=control,
            tol=tol, **sub)
        args["speed_rpm"] = speed_rpm
    elif combined:
        return solve_pair_combined(g, arrangement, T_ref_C=T_ref_C, preload_kind=preload_kind,
                                   radial_load_N=radial_load_N, tol=tol, max_outer=max_outer,
                                   chunk=chunk,
                                   moment_Nmm=moment_Nmm, bearing_span_mm=bearing_span_mm, **args)
    else:
        solver = lambda n, **sub: solve_pair_axial(  # noqa: E731
            g, arrangement, n, T_ref_C=T_ref_C, preload_kind=preload_kind, tol=tol,
            max_outer=max_outer, **sub)
    N = n_points(*args.values())
    blocks = []
    for i0 in range(0, N, chunk):
        sl = slice(i0, min(N, i0 + chunk))
        sub = {k: (np.asarray(v)[..., sl] if v is not None and np.ndim(v) >= 1
                   and np.shape(v)[-1] == N else v) for k, v in args.items()}
        blocks.append(solver(sl.stop - sl.start, **sub))
    return blocks[0] if len(blocks) == 1 else concatenate_states(blocks)


__all__ = ["BALL_MODELS", "DynamicContacts", "solve_pair_dynamic", "BearingGeometry", "ThermalGeometry", "PairState", "ContactEllipses", "RadialLoadState",
           "SIGNS", "solve_pair", "solve_pair_combined", "solve_pair_axial", "thermal_geometry",
           "contact_stiffness", "axial_state", "ball_set_state", "ball_azimuths_rad",
           "approach_for_force", "bearing_axial_force"]
