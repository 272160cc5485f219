"""Hydrodynamic (EHL) rolling resistance of the ball-raceway contacts, per contact, on the ball
loads of the pair's equilibrium (quasi-static or quasi-dynamic balls), so the viscous heat has a
location: the inner contacts, the outer contacts.

Rolling force of an isothermal, fully flooded EHL point contact (Houpert, "Numerical and
analytical calculations in ball bearings", 8th European Space Mechanisms and Tribology Symp.
(1999) and "Ball bearing and tapered roller bearing torque: analytical, numerical and
experimental results", Tribol. Trans. 45 (2002) 345; as Harris & Kotzalas, Rolling Bearing
Analysis 5th ed., Vol. 2 (Advanced Concepts), ch. "Friction in rolling element-raceway
contacts", give it):

    F_R = 2.86 E' R_x^2 k^0.348 G^0.022 U^0.66 W^0.47                       [N]

U = eta0 u / (E' R_x), G = alpha E', W = Q / (E' R_x^2) (Hamrock-Dowson groups, as
`analytic.lubrication.hamrock_dowson_film`), k = a / b the ellipticity of the Hertz contact,
u the mean entrainment (rolling) speed of the contact, E' = 2 / ((1 - nu1^2)/E1 + (1 -
nu2^2)/E2). The force opposes rolling; the power it dissipates is F_R u, at the contact's
inlet. With the kinematics of `analytic.torque.ball_kinematics` (outer ring fixed, inner ring
at omega) u_j = omega (dm/2) roll_j, so the inner-ring torque that balances it is
F_R (dm/2) roll_j per contact, Z balls per bearing.

Speed law (what the model predicts, not fitted): at fixed ball loads and viscosity F_R ~ U^0.66
~ n^0.66, so the torque grows as n^0.66 before the oil's heating lowers eta0 (the thermal
reduction, not modelled here) and before the balls' centrifugal load changes W.
Limits: isothermal, fully flooded (use `starved` for a finite oil quantity), Newtonian inlet;
k, U, W in the ranges of Hamrock-Dowson's fits (1 <= k <= 8). Units: E' MPa (N/mm^2), R_x mm,
eta0 Pa s (1e-6 N s/mm^2), alpha 1/Pa (1e6 1/MPa), u mm/s, Q N, F_R N, powers W.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.lubrication import reduced_modulus_MPa


def ehl_rolling_force_N(Q_N, Rx_mm, k, E_reduced_MPa, eta0_Pa_s, alpha_per_Pa,
                        entrainment_speed_mm_s):
    """Hydrodynamic rolling force F_R = 2.86 E' Rx^2 k^0.348 G^0.022 U^0.66 W^0.47 of one
    contact, N (module docstring). 0 without load or without rolling."""
    Rx = np.asarray(Rx_mm, float)
    Ep = np.asarray(E_reduced_MPa, float)
    U = np.asarray(eta0_Pa_s, float) * 1e-6 * np.abs(np.asarray(entrainment_speed_mm_s, float)) / (Ep * Rx)
    G = np.asarray(alpha_per_Pa, float) * 1e6 * Ep
    W = np.maximum(np.asarray(Q_N, float), 0.0) / (Ep * Rx * Rx)
    return 2.86 * Ep * Rx * Rx * np.asarray(k, float) ** 0.348 * G ** 0.022 * U ** 0.66 * W ** 0.47


@dataclass(frozen=True)
class EHLRollingTorque:
    """EHL rolling resistance of a pair (both bearings), arrays over operating points:
    the inner-ring torque of the inner and of the outer contacts (N mm) and the heat made at
    each (W, the power F_R u of each contact, computed from the contact speeds)."""
    inner_Nmm: np.ndarray
    outer_Nmm: np.ndarray
    heat_inner_W: np.ndarray
    heat_outer_W: np.ndarray
    per_bearing_Nmm: tuple[np.ndarray, np.ndarray]

    @property
    def total_Nmm(self) -> np.ndarray:
        return self.inner_Nmm + self.outer_Nmm


def ehl_rolling_pair(g, pair, speed_rpm, eta0_Pa_s, alpha_per_Pa) -> EHLRollingTorque:
    """EHL rolling resistance of each contact of a pair (`bearing.PairState`; quasi-dynamic
    balls: each contact at its own load and angle), every ball of a bearing at the
    representative ball's state (a radial load's ball-to-ball variation is not resolved here).
    g: `bearing.BearingGeometry`; speed_rpm: inner-ring speed (outer fixed); eta0_Pa_s: the
    oil's dynamic viscosity at the contact inlet; alpha_per_Pa: its pressure-viscosity
    coefficient. Torques N mm, heats W."""
    from analytic.torque import ball_kinematics, contact_angles_rad, contact_inputs
    n = np.abs(np.asarray(speed_rpm, float))
    omega = n * 2.0 * np.pi / 60.0
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    half_dm = 0.5 * g.dm_mm
    t_in = t_out = q_in = q_out = 0.0
    per = []
    for j in (0, 1):
        cin, cout = contact_inputs(pair, j)
        a_i, a_o = contact_angles_rad(pair, j)
        kin = ball_kinematics(g.dm_mm, g.Dw_mm, a_i, a_o)
        parts = []
        for c, roll in ((cin, kin.roll_inner), (cout, kin.roll_outer)):
            u = omega * half_dm * roll                       # entrainment speed, mm/s
            F = ehl_rolling_force_N(c.Q_N, c.Rx_mm, np.asarray(c.a_mm) / np.asarray(c.b_mm), Ep,
                                    eta0_Pa_s, alpha_per_Pa, u)
            parts.append((g.Z * F * half_dm * roll, 1e-3 * g.Z * F * u))
        (ti, qi), (to, qo) = parts
        t_in, t_out, q_in, q_out = t_in + ti, t_out + to, q_in + qi, q_out + qo
        per.append(ti + to)
    return EHLRollingTorque(t_in, t_out, q_in, q_out, tuple(per))
