"""The combined-load pair solver (`bearing.solve_pair` with a radial load, a moment and the shaft
free to tilt) meets its equilibrium equations to machine precision, checked outside the solver.

Independent check: from the solved displacements (rotor radial motion rho, tilt theta, each
bearing's axial approach a_j) every ball's force is recomputed in 3-D Cartesian vectors (rigid-
body motion of the inner groove curvature centre, inner-minus-outer centre vector d, Hertz load
Q = K_n delta^1.5 along it with K_n from the Hertz primitives, `bearing_reference.kn_direct`;
Harris & Kotzalas Vol. 1 ch. 7) and summed into the equations the solver must satisfy:

    sum F_z + Fa = 0,  sum F_x + Fr = 0,  sum M_y + M = 0     (forces on the rotor, moments about
                                                                the mid-point between ball planes)
    position preload with compliance c:  a_j + c F_j - s_j (dz_j + x) - e = 0   (j = A, B)
    spring preload:                      F_A = max(s_A Fa + P, 0),  F_B = P

Each residual is held to 1e-12 of the sum of the magnitudes of its terms (the rounding level of
such a sum is ~1e-16 of it; the solvers stop at Newton steps of 1e-15 of the unknowns), over
radial loads and moments of both signs, compliance 0 and > 0, a spring preload, and light
preloads under a large moment where balls unload (checked: some balls carry nothing)."""
import numpy as np
import pytest

from analytic.bearing import SIGNS, BearingGeometry, solve_pair
from bearing_reference import flat, kn_direct

G = BearingGeometry.from_catalogue("71807C")          # Z = 24, alpha0 = 15 deg
SPAN = 20.0
REL = 1e-12


def ball_sums(g, arrangement, out, i, dr, dz, span):
    """Per bearing j: (F_j axial along its contact sense, and per point the totals and the sums
    of magnitudes of the rotor force x, z and moment y about the mid-point), from vectors."""
    a0 = np.radians(g.alpha0_deg)
    Dw, dm, fi = g.Dw_mm, g.dm_mm, g.f_i
    R_i = dm / 2 + (fi - 0.5) * Dw * np.cos(a0)
    rho, theta = out["radial.rho_mm"][i], out["radial.tilt_rad"][i]
    psi = 2 * np.pi * np.arange(g.Z) / g.Z
    e_r = np.stack([np.cos(psi), np.sin(psi), np.zeros_like(psi)], axis=1)      # (Z, 3)
    e_z = np.array([0.0, 0.0, 1.0])
    tot, mag, F_ax = np.zeros(3), np.zeros(3), []
    for j, name in enumerate("AB"):
        s = SIGNS[arrangement][j]
        z_c = (-0.5 if j == 0 else 0.5) * span + s * (fi - 0.5) * Dw * np.sin(a0)
        p = R_i * e_r + z_c * e_z                                 # inner groove centres (Z, 3)
        u = np.array([rho, 0.0, 0.0]) + theta * np.cross([0.0, 1.0, 0.0], p)
        dR = g.A0_mm * np.cos(a0) + dr[j] + (u * e_r).sum(axis=1)
        dZ = g.A0_mm * np.sin(a0) + out[f"approach_mm[{name}]"][i] + s * u[:, 2]
        alpha = np.arctan2(dZ, dR)
        delta = np.maximum(np.hypot(dR, dZ) - g.A0_mm, 0.0)
        Q = np.asarray(kn_direct(g, alpha), float) * delta ** 1.5
        f = -(Q * np.cos(alpha))[:, None] * e_r - (s * Q * np.sin(alpha))[:, None] * e_z
        m = np.cross(p, f)
        comp = np.stack([f[:, 0], f[:, 2], m[:, 1]], axis=1)
        tot += comp.sum(axis=0)
        mag += np.abs(comp).sum(axis=0)
        F_ax.append(((Q * np.sin(alpha)).sum(), np.abs(Q * np.sin(alpha)).sum()))
        assert out[f"radial.ball_loads_N[{name}]"][:, i] == pytest.approx(Q, rel=1e-12, abs=1e-12 * Q.max())
    return tot, mag, F_ax


CASES = [("DB", "position", 0.0), ("DF", "position", 0.0), ("DB", "position", 2e-5),
         ("DF", "position", 4.25e-7), ("DB", "spring", 0.0)]


@pytest.mark.parametrize("arrangement,kind,c", CASES)
def test_equilibrium_equations_recomputed_to_1e12(arrangement, kind, c):
    dr = np.array([5.8e-4, 5.8e-4])
    dz = np.array([3e-4, -1e-4])
    P = np.array([7.0, 15.0, 30.0, 150.0, 150.0, 60.0, 7.0])
    Fa = np.array([0.0, 0.0, 40.0, -60.0, 120.0, 0.0, 0.0])
    Fr = np.array([30.0, 30.0, -30.0, 1500.0, 400.0, 0.0, 300.0])
    M = np.array([3000.0, -3000.0, 3000.0, -8000.0, 0.0, 5000.0, 0.0])
    out = flat(solve_pair(G, arrangement, preload_kind=kind, preload_assembled_N=P,
                          axial_load_N=Fa, radial_load_N=Fr, moment_Nmm=M, dr_mm=dr[:, None],
                          dz_mm=dz[:, None], compliance_mm_per_N=c, bearing_span_mm=SPAN))
    assert out["converged"].all()
    unloaded = 0
    for i in range(P.size):
        tot, mag, F_ax = ball_sums(G, arrangement, out, i, dr, dz, SPAN)
        for k, load in enumerate((Fr[i], Fa[i], M[i])):             # x, z, y-moment
            assert abs(tot[k] + load) <= REL * (mag[k] + abs(load)), (i, k)
        s = SIGNS[arrangement]
        if kind == "position":
            x, e = out["x_mm"][i], out["preload_offset_mm"][i]
            for j, name in enumerate("AB"):
                a = out[f"approach_mm[{name}]"][i]
                terms = np.array([a, c * F_ax[j][0], -s[j] * (dz[j] + x), -e])
                mags = abs(a) + c * F_ax[j][1] + abs(s[j] * dz[j]) + abs(s[j] * x) + abs(e)
                assert abs(terms.sum()) <= REL * mags, (i, name)
        else:
            req = (max(s[0] * Fa[i] + P[i], 0.0), P[i])
            for j in range(2):
                assert abs(F_ax[j][0] - req[j]) <= REL * (F_ax[j][1] + req[j]), (i, j)
        unloaded += int((out["radial.ball_loads_N[A]"][:, i] == 0).any()
                        or (out["radial.ball_loads_N[B]"][:, i] == 0).any())
    assert unloaded >= 1                                     # rows where balls unload are covered
