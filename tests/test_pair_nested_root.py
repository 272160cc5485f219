"""Defect: `bearingfem study seed001` stopped at "row 165: the bearing equilibrium did not
converge". The pair's axial solver with a compliant preload path (position preload, 60 C,
compliance 0.015..0.032 mm/N) evaluates its residual in the rotor position x through a nested root
solve (then `axial._effective_X`; `dynamic._effective_X` still does), so the residual jumps by
~4.5e-12 N between neighbouring x (2e-14 mm apart); `roots.newton_increasing` then stepped from
one end of its bracket exactly onto the other and back, 200 times, without bisecting. The bracket
is now bisected when Newton returns to its far end (`roots.safeguarded_step`, which the axial
solver's single Newton iteration, `axial.position_root`, uses too). The references below are independent of the Newton iteration: scipy's brentq on the same
equation, and the pair's force balance written in the preload instead of the rotor position."""
from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from analytic.bearing import BearingGeometry, SIGNS, solve_pair
from analytic.bearing.axial import approach_for_force
from analytic.bearing.geometry import thermal_geometry
from analytic.bearing.roots import newton_increasing
from studies.model.config import load_shipped


def test_newton_on_a_jumping_residual_bisects_to_the_sign_change():
    """r(x) = k (x - x_r) + jump sign(x - x_r): increasing, with a step of 2 jump at x_r that a
    Newton step with slope k overshoots by exactly the other bracket end (the seed 001 cycle).
    Before the fix the iteration cycled between -h/2 and h/2 and reported not converged."""
    k, h = 111.6, 2.0 ** -45                     # slope N/mm; bracket width mm (dyadic: exact)
    jump = k * h                                 # so that x - r/k lands on the other end

    def fun(x):
        return jump * np.sign(x) + 0.0 * x, np.full_like(x, k)

    root = newton_increasing(fun, np.array([-0.5 * h]), step0=1e-3)
    assert root.converged.all()
    # brentq brackets the same sign change; both within the solver's xtol (1e-15 (1 + |x|) mm)
    ref = brentq(lambda x: float(fun(np.array([x]))[0][0]), -h, h, xtol=1e-18)
    assert abs(root.x[0] - ref) <= 2e-15


#: the rows of the seed 001 study that stopped the run (its ratio map: position preload 7 N, every
#: part at 60 C, preload-path compliance 0.0154 / 0.0178 / 0.0316 mm/N per bearing) with the
#: groove-centre shifts the shipped mesh gives them (mm; the FE output, copied at full precision)
_ROWS = dict(
    dr_mm=[[0.0007886208009704743, 0.0007886208009704743, 0.0007886208009704734],
           [0.0007951162510638063, 0.0007951162510638063, 0.0007951162510638063]],
    dz_mm=[[0.00013878810510973942] * 3, [7.351779240134283e-05] * 3],
    dr_ref_mm=[[0.000638353444906989, 0.000638353444906989, 0.0006383534449069894],
               [0.0006454246008400017, 0.0006454246008400017, 0.0006454246008400016]],
    dz_ref_mm=[[0.0002574447085384336, 0.0002574447085384336, 0.00025744470853843377],
               [0.0002283970549150174] * 3],
    compliance_mm_per_N=[0.01539926526059492, 0.01778279410038923, 0.03162277660168379])
_T_C, _T_REF_C, _P_N = 60.0, 20.0, 7.0


def test_seed001_compliant_rows_converge_to_the_force_balance():
    """The three rows solved together (as the study does) converge, and their preload is the
    root, by brentq, of the pair's compatibility written in the common force F (F_A = F_B = F
    without external load; position preload, Harris & Kotzalas Vol. 1 ch. 7 per bearing):
        a_A(F) + a_B(F) + 2 c F = s_A (dz_A - dz_B) + 2 e,
        2 e = a_A(P) + a_B(P) + 2 c P - s_A (dz_ref_A - dz_ref_B)   (the reference state),
    a_j(F) the approach of bearing j carrying F (`approach_for_force`, its own radial shift and
    grown geometry). The force-parametrised statement needs no nested solve."""
    asm = load_shipped("seed001")
    g = BearingGeometry.from_spec(asm.bearing, asm.materials)
    r = {k: np.asarray(v, float) for k, v in _ROWS.items()}
    n = r["compliance_mm_per_N"].size
    st = solve_pair(g, asm.arrangement, **{k: r[k] for k in _ROWS}, T_inner_ring_C=np.full(n, _T_C),
                    T_outer_ring_C=np.full(n, _T_C), T_ball_C=np.full(n, _T_C), T_ref_C=_T_REF_C,
                    preload_kind="position", preload_assembled_N=np.full(n, _P_N),
                    axial_load_N=np.zeros(n), speed_rpm=np.full(n, 6000.0))
    assert st.converged.all()
    s_A = SIGNS[asm.arrangement][0]
    tg, tg_ref = thermal_geometry(g, _T_C, _T_C, _T_C, _T_REF_C), thermal_geometry(g)

    def approach_sum(F, dr, geo):
        return sum(float(approach_for_force(g, F, dr[j], geo).a_mm) for j in (0, 1))

    for i in range(n):
        c = r["compliance_mm_per_N"][i]
        dr, dz = r["dr_mm"][:, i], r["dz_mm"][:, i]
        two_e = (approach_sum(_P_N, r["dr_ref_mm"][:, i], tg_ref) + 2 * c * _P_N
                 - s_A * (r["dz_ref_mm"][0, i] - r["dz_ref_mm"][1, i]))

        def gap(F):
            return approach_sum(F, dr, tg) + 2 * c * F - s_A * (dz[0] - dz[1]) - two_e
        F_ref = brentq(gap, 1e-3, 2 * _P_N, xtol=1e-13, rtol=1e-13)
        # relative to the preload: the nested solve resolves X to ~1e-15 mm, i.e. F to ~1e-11 N
        assert abs(st.preload_N[i] / F_ref - 1.0) <= 1e-9, (i, st.preload_N[i], F_ref)
        np.testing.assert_allclose(st.axial_force_N[:, i], F_ref, rtol=1e-9)
