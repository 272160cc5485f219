"""Contact-level friction of angular-contact ball bearings: ball kinematics and the solid-film (MoS2)
dissipations per contact. The bearing-level laws (Palmgren, SKF, EHL rolling, starved film) and
the pair's friction route (`pair_torque`) are in `analytic.friction`.

Units: N, mm, s; torques N*mm, powers N*mm/s unless the name says W; speeds rpm or rad/s as named.

Solid film (seed 000; Jones 1960, Snare 1968, Todd & Stevens ESA/ESTL; Johnson, Contact Mechanics
1985).  At low speed a film-lubricated bearing's torque is the sum of three dissipations per
contact, each computed as a friction power and divided by the shaft speed (so the torque is the
one that balances the dissipated power):

  elastic hysteresis   rolling resistance F_R = alpha_h (3/16) Q b / Rx (Johnson 1985 ch. 9,
                       hysteresis losses: the work the front half of the Hertz pressure does per
                       unit distance rolled is
                       M_front / Rx, M_front = (3/16) Q b for the ellipsoidal pressure; Johnson's
                       sphere-on-plane F = alpha (3/16) P a / R is the circular case), times the
                       speed at which the contact travels over the race;
  differential (Heathcote) slip
                       across the major axis the contact surface (radius R_c) is at different
                       distances from the ball's and the ring's axes; with full sliding outside two
                       rolling bands at y = +-u_c a, u_c = 2 cos(4 pi/9) = 0.3473 (zero net traction
                       for the ellipsoidal pressure: u - u^3/3 = 1/3), the slip is
                       k (y^2 - u_c^2 a^2) / (2 R_c) and the dissipated power
                       P = C_H mu |k| Q a^2 / R_c, C_H = (3/8) J = 0.0806 (Heathcote 1921;
                       Johnson 1985 ch. 8, ball in a conforming groove: "about 0.08");
  spin                 full-slip pivoting moment M_s = (3/8) mu Q a E(m) (Johnson 1985 ch. 8;
                       Harris Vol. 2: a circular contact gives 3 pi mu Q a / 16) times the spin
                       rate at the contact.

Ball kinematics (`ball_kinematics`): rolling without slip at the contact centres and the outer-race
control hypothesis (Jones 1960: no spin at the outer contact; at light load this is the limit the
seed uses), outer ring fixed, inner ring at omega.  With equal contact angles the cage runs at
omega (1 - gamma)/2, the inner spin is omega sin(alpha), and the differential-slip rates are
(omega - omega_c) dm/Dw (inner) and omega_c dm/Dw (outer).

The contact-level formulas are checked in tests/test_torque.py by integrating the dissipation over
the Hertz ellipse numerically.  What the bearing-level sum leaves out: cage friction, film
shear/ploughing of the MoS2 transfer film, and the interaction of spin and differential slip
(each is computed as if it acted alone, as in Todd & Stevens' additive model).
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from math import cos, pi

import numpy as np

RPM_TO_RAD_S = 2.0 * pi / 60.0
U_C_HEATHCOTE = 2.0 * cos(4.0 * pi / 9.0)     # root of u^3 - 3u + 1 = 0 in (0, 1)


def heathcote_coefficient() -> float:
    """C_H = (3/8) J with J = 2 int_0^1 (1 - u^2) |u^2 - u_c^2| du (closed form of the integral),
    the coefficient of the differential-slip power P = C_H mu |k| Q a^2 / R_c (~0.0806, Johnson's
    'about 0.08')."""
    uc = U_C_HEATHCOTE
    J = 2.0 * ((2.0 / 15.0 - 2.0 / 3.0 * uc ** 2) + 2.0 * (2.0 / 3.0 * uc ** 3 - 2.0 / 15.0 * uc ** 5))
    return 0.375 * J


C_HEATHCOTE = heathcote_coefficient()


# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BallKinematics:
    """Rates per unit inner-ring speed (outer ring fixed), cage frame; all dimensionless."""
    cage: np.ndarray             # omega_c / omega
    spin_inner: np.ndarray       # |omega_s,i| / omega (0 under inner-race control)
    spin_outer: np.ndarray       # |omega_s,o| / omega (0 under outer-race control)
    slip_inner: np.ndarray       # |k_i| / omega, differential-slip rate coefficient
    slip_outer: np.ndarray
    roll_inner: np.ndarray       # contact speed over the inner race / (omega dm/2)
    roll_outer: np.ndarray
    omega_r: np.ndarray          # ball angular velocity, radial component / omega
    omega_z: np.ndarray          # ball angular velocity, axial component / omega


def ball_kinematics(dm_mm, Dw_mm, alpha_i_rad, alpha_o_rad=None, outer_control=True) -> BallKinematics:
    """Kinematics of a ball under outer-race control (default) or inner-race control (where
    `outer_control` is False; a bool or an array broadcastable with the angles), outer ring fixed,
    inner ring at unit speed (Jones 1960; Harris & Kotzalas, Rolling Bearing Analysis 5th ed.,
    Vol. 2 ch. 2 "ball spin/roll ratio").  Cage frame, ball angular velocity Omega in the r-z
    plane, contact normals n_j = (cos a_j, sin a_j), tangents t_j = (-sin a_j, cos a_j):

      inner rolling   Omega.t_i + (1 - w_c)(dm/Dw - cos a_i) = 0
      outer rolling   Omega.t_o + w_c (dm/Dw + cos a_o) = 0
      outer control   Omega.n_o + w_c sin a_o = 0          (no spin at the outer contact)
      inner control   Omega.n_i - (1 - w_c) sin a_i = 0    (no spin at the inner contact)

    Outer control: w_c [sin a_o sin D + (dm/Dw + cos a_o) cos D + dm/Dw - cos a_i] = dm/Dw - cos a_i,
    D = a_o - a_i, Omega = -w_c [sin a_o n_o + (dm/Dw + cos a_o) t_o], tan(beta) = Omega_r/|Omega_z|
    = sin a_o / (cos a_o + Dw/dm); spin_i = Omega.n_i - (1 - w_c) sin a_i.
    Inner control: w_c = S / (S + dm/Dw + cos a_o), S = sin a_i sin D + (dm/Dw - cos a_i) cos D,
    Omega = (1 - w_c) [sin a_i n_i - (dm/Dw - cos a_i) t_i], i.e. Omega_r = (1 - w_c) (dm/Dw) sin a_i,
    Omega_z = (1 - w_c)(1 - (dm/Dw) cos a_i), tan(beta) = sin a_i / (cos a_i - Dw/dm) (Harris's
    inner-raceway-control spin-axis angle); spin_o = Omega.n_o + w_c sin a_o
    = (1 - w_c)(sin a_o - (dm/Dw) sin D) + w_c sin a_o.  Both: differential-slip rates
    k_i = Omega.t_i - (1 - w_c) cos a_i = -(1 - w_c) dm/Dw and k_o = Omega.t_o + w_c cos a_o = -w_c dm/Dw.
    With equal angles both hypotheses give w_c = (1 - (Dw/dm) cos a)/2.
    """
    ai = np.asarray(alpha_i_rad, float)
    ao = ai if alpha_o_rad is None else np.asarray(alpha_o_rad, float)
    q = np.asarray(dm_mm, float) / np.asarray(Dw_mm, float)
    D = ao - ai
    si, ci, so, co = np.sin(ai), np.cos(ai), np.sin(ao), np.cos(ao)
    wc = (q - ci) / (so * np.sin(D) + (q + co) * np.cos(D) + q - ci)
    # Omega = -wc [sin a_o n_o + (q + cos a_o) t_o]; Omega.n_i with n_o.n_i = cos D, t_o.n_i = -sin D
    om_ni = -wc * (so * np.cos(D) - (q + co) * np.sin(D))
    spin_i = om_ni - (1.0 - wc) * si
    om_r, om_z, spin_o = wc * q * so, -wc * (1.0 + q * co), np.zeros_like(spin_i)
    oc = np.asarray(outer_control, bool)
    if not oc.all():
        S = si * np.sin(D) + (q - ci) * np.cos(D)
        wc_i = S / (S + q + co)
        wc = np.where(oc, wc, wc_i)
        om_r = np.where(oc, om_r, (1.0 - wc_i) * q * si)
        om_z = np.where(oc, om_z, (1.0 - wc_i) * (1.0 - q * ci))
        spin_o = np.where(oc, spin_o, (1.0 - wc_i) * (so - q * np.sin(D)) + wc_i * so)
        spin_i = np.where(oc, spin_i, 0.0)
    return BallKinematics(cage=wc, spin_inner=np.abs(spin_i), spin_outer=np.abs(spin_o),
                          slip_inner=(1.0 - wc) * q, slip_outer=wc * q,
                          roll_inner=(1.0 - wc) * (1.0 - ci / q), roll_outer=wc * (1.0 + co / q),
                          omega_r=om_r, omega_z=om_z)


# ---------------------------------------------------------------------------------------------
# contact-level dissipation (per ball, per contact)
def contact_surface_radius_mm(Dw_mm, f, ring_compliance_per_MPa=1.0, ball_compliance_per_MPa=1.0):
    """Transverse radius R_c of the deformed contact surface between a ball (radius Dw/2) and a
    groove (radius f Dw): curvature 1/R_c = (c_r / R_b + c_b / r_g) / (c_r + c_b), c = (1-nu^2)/E
    (Hertz: the displacements of the two surfaces are in the ratio of their compliances, Johnson
    1985 ch. 4; equal materials give the mean curvature (1/R_b + 1/r_g)/2).  mm."""
    Rb = 0.5 * np.asarray(Dw_mm, float)
    rg = np.asarray(f, float) * np.asarray(Dw_mm, float)
    cr, cb = ring_compliance_per_MPa, ball_compliance_per_MPa
    return (cr + cb) / (cr / Rb + cb / rg)


def heathcote_power_per_rate(mu, Q_N, a_mm, Rc_mm):
    """Differential-slip power per unit slip rate |k| (N*mm per rad): C_H mu Q a^2 / R_c
    (Heathcote 1921; Johnson 1985 ch. 8), a the semi-major (transverse) axis."""
    return C_HEATHCOTE * mu * np.asarray(Q_N, float) * np.square(a_mm) / Rc_mm


def spin_moment_Nmm(mu, Q_N, a_mm, E_ell):
    """Full-slip spin (pivoting) moment of a Hertz contact M_s = (3/8) mu Q a E(m), N*mm
    (integral of mu p r over the ellipse; Harris Vol. 2 'spinning friction'; circle: 3 pi mu Q a/16)."""
    return 0.375 * mu * np.asarray(Q_N, float) * np.asarray(a_mm, float) * E_ell


def hysteresis_rolling_force_N(loss_factor, Q_N, b_mm, Rx_mm):
    """Elastic-hysteresis rolling resistance F_R = alpha_h (3/16) Q b / Rx, N (Johnson 1985 ch. 9;
    b semi-axis along rolling, Rx effective radius along rolling, alpha_h hysteresis loss fraction).
    Scales as Q^(4/3) through b."""
    return loss_factor * 0.1875 * np.asarray(Q_N, float) * np.asarray(b_mm, float) / Rx_mm


# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ContactInput:
    """Per-contact Hertz state for one bearing (arrays over operating points)."""
    Q_N: np.ndarray
    a_mm: np.ndarray             # semi-major (transverse) axis
    b_mm: np.ndarray             # semi-minor (rolling) axis
    E_ell: np.ndarray            # complete elliptic integral of the second kind
    Rx_mm: np.ndarray            # effective radius along rolling


@dataclass(frozen=True)
class ContactTorques:
    """Friction torque of one bearing (`solid_film_torque_Nmm`) by dissipation and contact, N*mm,
    arrays over operating points (or over (balls, points) for a per-ball evaluation).
    total_Nmm is the sum of the six components (stored: a per-ball sum sums the balls' totals)."""
    hysteresis_inner_Nmm: np.ndarray
    hysteresis_outer_Nmm: np.ndarray
    differential_inner_Nmm: np.ndarray
    differential_outer_Nmm: np.ndarray
    spin_inner_Nmm: np.ndarray
    spin_outer_Nmm: np.ndarray
    total_Nmm: np.ndarray

    def where(self, mask, other: "ContactTorques") -> "ContactTorques":
        """These torques, with `other`'s summed over its first axis (the balls) where `mask`."""
        return ContactTorques(*(np.where(mask, getattr(other, f.name).sum(axis=0),
                                         getattr(self, f.name)) for f in fields(self)))


def solid_film_torque_Nmm(Z: int, Dw_mm: float, dm_mm: float, f_i: float, f_o: float,
                          alpha_rad, inner: ContactInput, outer: ContactInput, mu,
                          hysteresis_loss, ring_compliance_per_MPa=1.0,
                          ball_compliance_per_MPa=1.0, alpha_outer_rad=None,
                          mu_outer=None) -> ContactTorques:
    """Friction torque of one solid-film (MoS2) lubricated bearing, N*mm, by components.

    Seed 000 structure (after Todd & Stevens / Snare): inner M_i = M_E,i + M_d,i + M_s,i,
    outer M_o = M_E,o + M_d,o (outer-race control: no outer spin).  Each component is Z times the
    contact's dissipated power divided by the inner-ring speed (kinematics from `ball_kinematics`):
      hysteresis  F_R v_contact / omega = F_R (dm/2) roll_j
      differential  C_H mu Q a^2 / R_c * slip_j
      spin        (3/8) mu Q a E(m) * spin_j
    alpha_rad: contact angle of the inner contact, alpha_outer_rad that of the outer one (default
    equal: quasi-static balls; quasi-dynamic balls at speed give two, and the kinematics follow
    them).  mu_outer: the outer contacts' coefficient where it differs from the inner ones' (a
    pressure-dependent shear strength, `analytic.friction.solid_film`; default mu).  Returns the
    `ContactTorques` (each component of each contact, and their total).
    """
    kin = ball_kinematics(dm_mm, Dw_mm, alpha_rad, alpha_outer_rad)
    Rc_i = contact_surface_radius_mm(Dw_mm, f_i, ring_compliance_per_MPa, ball_compliance_per_MPa)
    Rc_o = contact_surface_radius_mm(Dw_mm, f_o, ring_compliance_per_MPa, ball_compliance_per_MPa)
    half_dm = 0.5 * dm_mm
    mu_o = mu if mu_outer is None else mu_outer
    parts = (
        Z * hysteresis_rolling_force_N(hysteresis_loss, inner.Q_N, inner.b_mm,
                                       inner.Rx_mm) * half_dm * kin.roll_inner,
        Z * hysteresis_rolling_force_N(hysteresis_loss, outer.Q_N, outer.b_mm,
                                       outer.Rx_mm) * half_dm * kin.roll_outer,
        Z * heathcote_power_per_rate(mu, inner.Q_N, inner.a_mm, Rc_i) * kin.slip_inner,
        Z * heathcote_power_per_rate(mu_o, outer.Q_N, outer.a_mm, Rc_o) * kin.slip_outer,
        Z * spin_moment_Nmm(mu, inner.Q_N, inner.a_mm, inner.E_ell) * kin.spin_inner,
        Z * spin_moment_Nmm(mu_o, outer.Q_N, outer.a_mm, outer.E_ell) * kin.spin_outer,
    )
    return ContactTorques(*parts, sum(parts))


# ---------------------------------------------------------------------------------------------
def power_W(torque_Nmm, n_rpm):
    """Dissipated power P = M |omega|, W (M N*mm, n rpm): 2 pi n/60 * 1e-3 M = 1.047e-4 n M
    (seed 003 eq. 32); the sign of n is only the direction of rotation."""
    return np.asarray(torque_Nmm, float) * np.abs(np.asarray(n_rpm, float)) * RPM_TO_RAD_S * 1e-3


def friction_heat_W(components_Nmm, n_rpm) -> dict[str, np.ndarray]:
    """Heat (W) of each torque component at speed n_rpm for a thermal network, by name: the
    fields of a torque dataclass (`ContactTorques`, `SlidingSpinTorques`) or the keys of a
    mapping, renamed *_Nmm -> *_W (a display helper; None fields are left out).  The sliding (differential), spin and hysteresis parts of `solid_film_torque_Nmm`
    or of `sliding_spin_torque_Nmm` map to seed 003's H_B1 (sliding) and H_B3 (spin); the viscous
    term of `palmgren_viscous_torque_Nmm` to H_B2."""
    items = (components_Nmm.items() if isinstance(components_Nmm, dict)
             else ((f.name, getattr(components_Nmm, f.name)) for f in fields(components_Nmm)))
    return {k[:-4] + "_W" if k.endswith("_Nmm") else k + "_W": power_W(v, n_rpm)
            for k, v in items if v is not None}


@dataclass(frozen=True)
class SlidingSpinTorques:
    """Sliding (differential slip) and spin torques of one bearing's inner and outer contacts,
    N*mm (`sliding_spin_torque_Nmm`)."""
    sliding_inner_Nmm: np.ndarray
    sliding_outer_Nmm: np.ndarray
    spin_inner_Nmm: np.ndarray
    spin_outer_Nmm: np.ndarray


def sliding_spin_torque_Nmm(Z: int, Dw_mm, dm_mm, f_i, f_o, alpha_rad, inner: ContactInput,
                            outer: ContactInput, mu_slide, mu_spin=None,
                            ring_compliance_per_MPa=1.0, ball_compliance_per_MPa=1.0,
                            alpha_outer_rad=None) -> SlidingSpinTorques:
    """Sliding (differential slip) and spin torques of an oil-lubricated bearing with boundary /
    traction coefficients mu_slide, mu_spin (default mu_slide), N*mm (same contact models as
    `solid_film_torque_Nmm` without hysteresis).  Multiply by the speed (`friction_heat_W`) for
    seed 003's sliding and spin heat."""
    t = solid_film_torque_Nmm(Z, Dw_mm, dm_mm, f_i, f_o, alpha_rad, inner, outer, mu_slide, 0.0,
                              ring_compliance_per_MPa, ball_compliance_per_MPa, alpha_outer_rad)
    spin_i, spin_o = t.spin_inner_Nmm, t.spin_outer_Nmm
    if mu_spin is not None and mu_slide != 0:
        scale = mu_spin / mu_slide
        spin_i, spin_o = spin_i * scale, spin_o * scale
    return SlidingSpinTorques(t.differential_inner_Nmm, t.differential_outer_Nmm, spin_i, spin_o)
