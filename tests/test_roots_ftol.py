"""The residual tolerance of `roots.newton_increasing` (issue 34, speed): a root where the
slope vanishes converges only linearly in x, so iterating to xtol (1e-15 (1 + |x|) mm) takes twice
the evaluations of every point; with `ftol` a point stops once its residual is within ftol. The
references are closed forms (the root of r = x |x|^0.5 is 0) and the pair's force balance, a
statement of the equilibrium that does not use the iteration."""
from __future__ import annotations

import numpy as np

from analytic.bearing import SIGNS, BearingGeometry, solve_pair
from analytic.bearing.axial import FTOL_REL
from analytic.bearing.roots import newton_increasing
from studies.model.config import load_shipped


def _hertz_like(calls):
    """r = x |x|^0.5 (a Hertz contact's F ~ delta^1.5 either side of touching: increasing, slope
    1.5 |x|^0.5, zero at the root x = 0), counting the evaluations."""
    def fun(x):
        calls.append(1)
        return x * np.sqrt(np.abs(x)), 1.5 * np.sqrt(np.abs(x))
    return fun


def test_ftol_stops_a_flat_root_within_its_residual_tolerance_sooner():
    plain, tol = [], []
    x0 = np.array([0.3, -0.2, 1e-3])
    r0 = newton_increasing(_hertz_like(plain), x0, step0=1e-3)
    r1 = newton_increasing(_hertz_like(tol), x0, step0=1e-3, ftol=1e-10)
    assert r0.converged.all() and r1.converged.all()
    # the closed-form root is 0: |r(x)| <= ftol means |x| <= ftol^(2/3)
    assert np.all(np.abs(r1.x) ** 1.5 <= 1e-10)
    assert np.all(np.abs(r1.x) <= (1e-10) ** (2.0 / 3.0))
    assert len(tol) < len(plain)


def test_ftol_zero_is_the_exact_zero_rule():
    """Default ftol = 0: the iterates are those of before (a point stops only at r == 0)."""
    x0 = np.array([0.3, -0.2, 1e-3])
    a = newton_increasing(_hertz_like([]), x0, step0=1e-3)
    b = newton_increasing(_hertz_like([]), x0, step0=1e-3, ftol=0.0)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.converged, b.converged)


def test_pair_force_balance_within_ftol_where_the_preload_is_lost():
    """Seed 001's pair (position preload 7 / 30 N, a compliant preload path: the nested root
    solve) under an external axial load rising until the 7 N rows lose their preload: every point
    converges and balances the load, s_A (F_A - F_B) = F_ext (the rotor's axial equilibrium,
    Harris & Kotzalas Vol. 1 ch. 7; s_A the arrangement's sign), to FTOL_REL of the preload
    plus the load."""
    asm = load_shipped("seed001")
    g = BearingGeometry.from_spec(asm.bearing, asm.materials)
    n = 40
    P = np.where(np.arange(n) % 2 == 0, 7.0, 30.0)
    Fext = np.linspace(0.0, 16.0, n)
    st = solve_pair(g, asm.arrangement, T_ref_C=asm.T_ref_C, preload_kind="position",
                    preload_assembled_N=P, axial_load_N=Fext, compliance_mm_per_N=0.02)
    assert st.converged.all()
    assert st.preload_lost.any() and not st.preload_lost.all()   # the range crosses the loss
    FA, FB = st.axial_force_N
    s_A = SIGNS[asm.arrangement][0]
    assert np.all(np.abs(s_A * (FA - FB) - Fext) <= FTOL_REL * (P + Fext))
