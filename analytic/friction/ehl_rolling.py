"""Hydrodynamic (EHL) rolling resistance of the ball-raceway contacts, per contact, on the ball
loads of the pair's equilibrium (quasi-static or quasi-dynamic balls), so the viscous heat has a
location: the inner contacts, the outer contacts.

Rolling force of an isothermal, fully flooded EHL point contact (Houpert, "Numerical and
analytical calculations in ball bearings", 8th European Space Mechanisms and Tribology Symp.
(1999) and "Ball bearing and tapered roller bearing torque: analytical, numerical and
experimental results", Tribol. Trans. 45 (2002) 345; as Harris & Kotzalas, Rolling Bearing
Analysis 5th ed., Vol. 2 (Advanced Concepts), ch. "Friction in rolling element-raceway
contacts", give it; coefficient and exponents as the issue quotes them, not re-checked against a
copy of either source here: the tests check the dimensional form and the exponents' physics):

    F_R = 2.86 E' R_x^2 k^0.348 G^0.022 U^0.66 W^0.47                       [N]

U = eta0 u / (E' R_x), G = alpha E', W = Q / (E' R_x^2) (Hamrock-Dowson groups, as
`analytic.lubrication.hamrock_dowson_film`), k = a / b the ellipticity of the Hertz contact,
u the mean entrainment (rolling) speed of the contact, E' = 2 / ((1 - nu1^2)/E1 + (1 -
nu2^2)/E2). The force opposes rolling; the power it dissipates is F_R u, at the contact's
inlet. With the kinematics of `analytic.torque.ball_kinematics` (outer ring fixed, inner ring
at omega) u_j = omega (dm/2) roll_j, so the inner-ring torque that balances it is
F_R (dm/2) roll_j per contact, Z balls per bearing.
The pair's sum over both bearings on a `bearing.PairState`: `analytic.friction.pair.ehl_rolling_pair`.

Speed law (what the model predicts, not fitted): at fixed ball loads and viscosity F_R ~ U^0.66
~ n^0.66, so the torque grows as n^0.66 before the oil's heating lowers eta0 (the thermal
reduction, not modelled here) and before the balls' centrifugal load changes W.
A loss that does not vanish when the preload is lost: a ball whose contacts carry no load
(the pair's preload lost to a temperature excursion) still rides on the outer raceway under its
centrifugal force F_c = m omega_c^2 dm / 2, m = rho pi Dw^3 / 6 (Harris & Kotzalas, Rolling
Bearing Analysis 5th ed., Vol. 2 ch. "high-speed operation": the ball's centrifugal force on
the outer raceway; the same F_c as `analytic.bearing.ball_dynamics`), rolling through the oil
at the cage's speed. Where an outer contact is unloaded (Q_o = 0) the rolling force is taken at
Q = F_c (`CentrifugalFloor`: the outer contact's Rx and Hamrock-Dowson's ellipticity
k = 1.03 (Ry/Rx)^0.64 of the groove, no Hertz ellipse at zero load), the inner contact
(open) has none. Where a contact carries load the law is unchanged (the limit where it reduces
to the loaded law: identical bits). At rest F_c = 0 and u = 0: no loss. This W is far below the
Hamrock-Dowson fits' loads at low speed (the range warning says so).
Spin (pivoting) sliding, a loss term of this route (issue 43): a ball whose contact spins about
the contact normal at omega_s slides over its whole ellipse; with a uniform traction coefficient
mu over the Hertz pressure the moment resisting the spin is the full-slip pivoting moment

    M_s = (3/8) mu Q a E(m)                                                  [N mm]

(Harris & Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 ch. "Friction in rolling
element-raceway contacts", spinning moment of an elliptical contact; Johnson, Contact Mechanics
1985 ch. 8; a the semi-major axis, E(m) the complete elliptic integral of the second kind; a
circle, E = pi/2, gives 3 pi mu Q a / 16), `analytic.torque.spin_moment_Nmm`. Its power is
M_s |omega_s| and the inner-ring torque that balances it M_s |omega_s| / omega, per contact, Z
balls per bearing. The spin rates per unit ring speed |omega_s,j| / omega are the ball
kinematics' (`analytic.torque.ball_kinematics`) at the contact angles the balls solved for
(quasi-dynamic balls: both angles and each ball's raceway control; the controlling contact does
not spin). Traction coefficient: no traction measurement of the space oils (Pennzane, PFPE) is
reachable from here, so mu is bounded by SKF's full-film coefficient mu_EHL (SKF General
Catalogue 2004, "friction": 0.05 mineral, 0.04 synthetic; `skf2004.MU_EHL`, by the oil's
family), the coefficient of the full-film sliding that the SKF model charges against the same
contacts. At rest (no entrainment, no film) the term is 0 and the starting torque stays the
route's load term. Full slip at mu over the whole ellipse: an upper bound of the spin loss for that mu
(at low spin the micro-slip zone carries less). Zero where the kinematics give no spin (a
contact under its own raceway control; a contact angle of 0 under outer control: omega_s,i =
omega_R sin(a_i - beta) = 0 at a = beta = 0).
Gyroscopic sliding: the quasi-dynamic balls take the gyroscopic moment M_g on the controlling
contact's friction 2 M_g / Dw without pivoting (`analytic.bearing.ball_dynamics`, Harris Vol. 2
ch. 3), which dissipates nothing while the traction can supply it, 2 M_g / Dw <= mu_EHL Q
(Harris's condition for no gyroscopic pivoting). Beyond it the ball pivots at a rate the
quasi-dynamic model does not give, so that loss is not computed: those rows are reported
(`GYRO_NOTE`, one warning line).
Limits: isothermal, fully flooded (use `starved` for a finite oil quantity), Newtonian inlet;
k, U, W in the ranges of Hamrock-Dowson's fits (1 <= k <= 8). Units: E' MPa (N/mm^2), R_x mm,
eta0 Pa s (1e-6 N s/mm^2), alpha 1/Pa (1e6 1/MPa), u mm/s, Q N, F_R N, powers W.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.friction.skf2004 import MU_EHL
from analytic.torque import spin_moment_Nmm

#: the ellipticity range k = a/b of Hamrock-Dowson's fits, which the rolling force's groups follow
K_RANGE = (1.0, 8.0)


def ehl_rolling_force_N(Q_N, Rx_mm, k, E_reduced_MPa, eta0_Pa_s, alpha_per_Pa,
                        entrainment_speed_mm_s):
    """Hydrodynamic rolling force F_R = 2.86 E' Rx^2 k^0.348 G^0.022 U^0.66 W^0.47 of one
    contact, N (module docstring). 0 without load (an unloaded contact, whose ellipse and k are
    then undefined) or without rolling."""
    Rx = np.asarray(Rx_mm, float)
    Ep = np.asarray(E_reduced_MPa, float)
    Q = np.asarray(Q_N, float)
    G = np.asarray(alpha_per_Pa, float) * 1e6 * Ep
    with np.errstate(divide="ignore", invalid="ignore"):     # an unloaded contact: F = 0 below
        U = np.asarray(eta0_Pa_s, float) * 1e-6 * np.abs(np.asarray(entrainment_speed_mm_s,
                                                                   float)) / (Ep * Rx)
        W = np.maximum(Q, 0.0) / (Ep * Rx * Rx)
        F = 2.86 * Ep * Rx * Rx * np.asarray(k, float) ** 0.348 * G ** 0.022 * U ** 0.66 * W ** 0.47
    return np.where(Q > 0, F, 0.0)


@dataclass(frozen=True)
class CentrifugalFloor:
    """The load an unloaded outer contact rolls under (module docstring): F_c (N), the outer
    contact's Rx (mm) and ellipticity k (-), arrays broadcastable with the contact's."""
    Q_N: np.ndarray
    Rx_mm: np.ndarray
    k: np.ndarray


def centrifugal_force_N(density_N_s2_mm4, Dw_mm, dm_mm, cage_speed_rad_s):
    """Centrifugal force of a ball on the outer raceway F_c = m omega_c^2 dm / 2, m = rho pi
    Dw^3 / 6, N (rho N s^2/mm^4, lengths mm, omega_c rad/s; Harris & Kotzalas Vol. 2)."""
    m = density_N_s2_mm4 * np.pi * Dw_mm ** 3 / 6.0
    return m * np.square(np.asarray(cage_speed_rad_s, float)) * 0.5 * dm_mm


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


def ehl_rolling_bearing(Z: int, dm_mm: float, E_reduced_MPa, inner, outer, roll_inner,
                        roll_outer, speed_rpm, eta0_Pa_s, alpha_per_Pa,
                        outer_floor: CentrifugalFloor | None = None):
    """EHL rolling resistance of one bearing's contacts: inner, outer the contacts' Hertz states
    (`analytic.torque.ContactInput`: Q N, a, b, Rx mm), roll_inner, roll_outer the contact
    speeds over the races per unit (omega dm/2) (`analytic.torque.ball_kinematics`), speed_rpm
    the inner-ring speed (outer fixed). Returns (inner-ring torque of the inner contacts, of the
    outer contacts) N mm and (heat at the inner contacts, at the outer contacts) W, the heat
    computed as Z F_R u with u = omega (dm/2) roll the entrainment speed (mm/s). outer_floor:
    the centrifugal load an unloaded outer contact rolls under (module docstring; None: none)."""
    omega = np.abs(np.asarray(speed_rpm, float)) * 2.0 * np.pi / 60.0
    half_dm = 0.5 * dm_mm
    torques, heats = [], []
    for c, roll, floor in ((inner, roll_inner, None), (outer, roll_outer, outer_floor)):
        u = omega * half_dm * roll                                   # entrainment speed, mm/s
        with np.errstate(divide="ignore", invalid="ignore"):      # unloaded: F = 0 below
            k = np.asarray(c.a_mm, float) / np.asarray(c.b_mm, float)
        Q, Rx = np.asarray(c.Q_N, float), np.asarray(c.Rx_mm, float)
        if floor is not None:
            open_ = Q <= 0
            Q, Rx, k = (np.where(open_, f, x) for f, x in ((floor.Q_N, Q), (floor.Rx_mm, Rx),
                                                             (floor.k, k)))
        F = ehl_rolling_force_N(Q, Rx, k, E_reduced_MPa, eta0_Pa_s, alpha_per_Pa, u)
        torques.append(Z * F * half_dm * roll)
        heats.append(1e-3 * Z * F * u)
    return tuple(torques), tuple(heats)


#: where the gyroscopic moment exceeds what the controlling contact's traction supplies
#: (module docstring): the gyroscopic pivoting loss is not computed there
GYRO_NOTE = ("2 M_g / (Dw Q) <= mu_EHL at the controlling contact (Harris: no gyroscopic "
             "pivoting); beyond it the pivoting loss is not computed")


def spin_traction_coefficient(oil_family: str) -> float:
    """Traction coefficient of the spin sliding (-): SKF's full-film mu_EHL of the oil's family
    (`skf2004.MU_EHL`, SKF 2004 catalogue; module docstring)."""
    return MU_EHL[oil_family]


def spin_torque_bearing(Z: int, inner, outer, spin_inner, spin_outer, mu):
    """Inner-ring torque of one bearing's spin sliding, (inner contacts, outer contacts) N mm:
    Z M_s,j |omega_s,j| / omega with M_s = (3/8) mu Q a E(m) (`analytic.torque.spin_moment_Nmm`;
    module docstring), inner, outer the contacts' Hertz states (`analytic.torque.ContactInput`),
    spin_inner, spin_outer the spin rates per unit inner-ring speed (`ball_kinematics`), mu the
    traction coefficient (-). The power is this torque times the ring speed (`power_W`). An
    unloaded contact (Q = 0) has none."""
    out = []
    for c, s in ((inner, spin_inner), (outer, spin_outer)):
        Q = np.asarray(c.Q_N, float)
        M = spin_moment_Nmm(mu, np.maximum(Q, 0.0), np.where(Q > 0, c.a_mm, 0.0),
                            np.where(Q > 0, c.E_ell, 0.0))
        out.append(Z * np.nan_to_num(M) * np.asarray(s, float))
    return tuple(out)


def gyroscopic_traction_ratio(gyroscopic_moment_Nmm, Dw_mm, Q_control_N):
    """Traction the controlling contact must supply to hold the gyroscopic moment without
    pivoting, over its load: 2 M_g / (Dw Q) (-; `ball_dynamics`: lam = 2 at the controlling
    contact). inf where that contact is unloaded and M_g > 0, 0 where M_g = 0."""
    Mg = np.abs(np.asarray(gyroscopic_moment_Nmm, float))
    Q = np.asarray(Q_control_N, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = 2.0 * Mg / (Dw_mm * Q)
    return np.where(Mg > 0, np.where(Q > 0, r, np.inf), 0.0)
