"""Friction torque of angular-contact ball bearings: solid-film (MoS2) and oil/grease models.

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

Oil/grease (seeds 001/002; Palmgren 1959, Harris Vol. 2 ch. "friction"): load term
M1 = f1 P1 dm (or mu P dm/2), viscous term M0 = 1e-7 f0 (nu n)^(2/3) dm^3 for nu n >= 2000 and
160e-7 f0 dm^3 below (nu in mm^2/s = cSt, n in rpm, dm in mm, M in N*mm), and the
GB/T 28878.2-2016 Annex B form M = f1 F dm + c f0 (nu n)^(2/3) dm^3.
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
# oil / grease (Palmgren)
def palmgren_f1_angular_contact(P0_N, C0_N):
    """Palmgren's load factor for angular-contact ball bearings f1 = 0.001 (P0/C0)^0.33 (-)
    (Palmgren 1959; Harris Vol. 2 table 'f1 for ball bearings')."""
    return 0.001 * (np.asarray(P0_N, float) / C0_N) ** 0.33


def palmgren_load_torque_Nmm(f1, P1_N, dm_mm):
    """Load-dependent torque M1 = f1 P1 dm, N*mm (Palmgren 1959; Harris Vol. 2); for an
    angular-contact bearing under axial load P1 = F_a (minus 0.1 F_r)."""
    return np.asarray(f1, float) * np.asarray(P1_N, float) * dm_mm


def coulomb_load_torque_Nmm(mu, F_N, lever_mm):
    """Load torque as an equivalent friction coefficient times load times lever, M1 = mu F r,
    N*mm (SKF's simplified M = 0.5 mu P d with r = dm/2; seed 001's load term, mu = 0.0029)."""
    return np.asarray(mu, float) * np.asarray(F_N, float) * lever_mm


def palmgren_viscous_torque_Nmm(f0, nu_mm2_s, n_rpm, dm_mm):
    """Viscous (load-independent) torque, N*mm (Palmgren 1959; Harris Vol. 2):
        M0 = 1e-7 f0 (nu n)^(2/3) dm^3     for nu n >= 2000
        M0 = 160e-7 f0 dm^3                for nu n <  2000
    nu kinematic viscosity mm^2/s (cSt), n rpm, dm mm.  The two branches meet within 0.8 %
    (2000^(2/3) = 158.7). Both are running torques: a bearing at rest (n = 0) has none."""
    n = np.abs(np.asarray(n_rpm, float))
    vn = np.asarray(nu_mm2_s, float) * n
    dm3 = np.asarray(dm_mm, float) ** 3
    M = np.where(vn >= 2000.0, 1e-7 * f0 * np.cbrt(vn) ** 2 * dm3, 160e-7 * f0 * dm3)
    return np.where(n > 0, M, 0.0)


GBT28878_VISCOUS_COEFF = 1e-7
"""Coefficient c of GB/T 28878.2-2016 eq. (B.4).  The seed's extraction reads '1.42 x 10^?' with the
exponent lost; until the standard's number is checked we use Palmgren's 1e-7 (N*mm = mN*m units),
which the standard's form reproduces with f1 F dm as its first term.  Pass c explicitly to use
another value."""


def gbt28878_torque_mNm(f1, F_N, dm_mm, f0, nu_mm2_s, n_rpm, c=GBT28878_VISCOUS_COEFF):
    """GB/T 28878.2-2016 Annex B eq. (B.4): M = f1 F dm + c f0 (nu n)^(2/3) dm^3, mN*m (= N*mm),
    F equivalent load N, dm mm, nu mm^2/s, n rpm."""
    vn = np.asarray(nu_mm2_s, float) * np.abs(np.asarray(n_rpm, float))
    return (np.asarray(f1, float) * np.asarray(F_N, float) * dm_mm
            + c * f0 * np.cbrt(vn) ** 2 * np.asarray(dm_mm, float) ** 3)


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


# ---------------------------------------------------------------------------------------------
def contact_inputs(pair, j: int) -> tuple[ContactInput, ContactInput]:
    """Inner and outer `ContactInput` of bearing j (0 = A, 1 = B) of a `bearing.PairState`
    (ball load N, ellipse semi-axes mm, E(e), Rx mm); with quasi-dynamic balls
    (`pair.dynamic`) each contact at its own load."""
    d = pair.dynamic
    Q = (pair.ball_load_N[j], pair.ball_load_N[j]) if d is None else (d.load_inner_N[j],
                                                                      d.load_outer_N[j])
    return tuple(ContactInput(q, c.a_mm[j], c.b_mm[j], c.E_ell[j], c.Rx_mm[j])
                 for q, c in zip(Q, (pair.inner, pair.outer)))


def contact_angles_rad(pair, j: int):
    """(inner, outer) contact angle of bearing j of a `bearing.PairState`, rad; the outer one is
    None for quasi-static balls (equal to the inner one)."""
    d = pair.dynamic
    if d is None:
        return np.radians(pair.contact_angle_deg[j]), None
    return np.radians(d.contact_angle_inner_deg[j]), np.radians(d.contact_angle_outer_deg[j])


def ball_contact_inputs(radial, j: int) -> tuple[ContactInput, ContactInput]:
    """Inner and outer `ContactInput` of every ball of bearing j, (Z, N), from the combined-load
    state (`bearing.RadialLoadState`: ball_loads_N, ball_inner, ball_outer; with quasi-dynamic
    balls the outer contacts at their own loads, ball_loads_outer_N)."""
    Q_i = radial.ball_loads_N[j]
    Q_o = Q_i if radial.ball_loads_outer_N is None else radial.ball_loads_outer_N[j]
    return tuple(ContactInput(Q, c.a_mm[j], c.b_mm[j], c.E_ell[j], c.Rx_mm[j])
                 for Q, c in ((Q_i, radial.ball_inner), (Q_o, radial.ball_outer)))


@dataclass(frozen=True)
class TorqueComponents:
    """Friction torque of a bearing pair (`pair_torque`), N*mm, arrays (n,) over operating points.

    model: "solid_film" or "oil" (which of the component fields are set; the others are None).
    torque_Nmm: the pair's torque (bearing A + bearing B); torque_A_Nmm, torque_B_Nmm: per bearing.
    heat_W: dissipated power of the pair, W (`power_W`; None when no speed was given).
    Solid film: hysteresis_Nmm, differential_Nmm, spin_Nmm (each dissipation, both bearings,
    inner + outer contacts), inner_contacts_Nmm, outer_contacts_Nmm (every component of the
    inner or of the outer contacts, both bearings).
    Oil: load_Nmm (the load term, both bearings; with viscous_model "skf2004" SKF's sliding
    term), viscous_Nmm (the viscous term of `viscous_model`, both bearings), viscosity_mm2_s
    (the kinematic viscosity the viscous term used, mm^2/s).
    Every model: rolling_Nmm, sliding_Nmm, drag_Nmm (their sum is torque_Nmm: oil,
    the viscous term, the load term and the drag; solid film, the hysteresis, the differential
    slip + spin, 0) and with a speed the heat by where it is made, heat_inner_W (the inner
    contacts), heat_outer_W (the outer contacts), heat_ball_W (in the oil around the balls: the
    drag), summing to heat_W. A term without a location of its own (Palmgren's viscous and load
    terms, SKF's rolling and sliding terms) is shared equally by the inner and outer contacts,
    as `analytic.heat.pair_heat_W` shares the viscous heat."""
    model: str
    torque_Nmm: np.ndarray
    torque_A_Nmm: np.ndarray
    torque_B_Nmm: np.ndarray
    heat_W: np.ndarray | None = None
    hysteresis_Nmm: np.ndarray | None = None
    differential_Nmm: np.ndarray | None = None
    spin_Nmm: np.ndarray | None = None
    inner_contacts_Nmm: np.ndarray | None = None
    outer_contacts_Nmm: np.ndarray | None = None
    load_Nmm: np.ndarray | None = None
    viscous_Nmm: np.ndarray | None = None
    viscosity_mm2_s: np.ndarray | None = None
    rolling_Nmm: np.ndarray | None = None
    sliding_Nmm: np.ndarray | None = None
    drag_Nmm: np.ndarray | None = None
    heat_inner_W: np.ndarray | None = None
    heat_outer_W: np.ndarray | None = None
    heat_ball_W: np.ndarray | None = None
    viscous_model: str = "palmgren"


def pair_torque(g, pair, *, model: str = "solid_film", mu=0.02, hysteresis_loss=0.0,
                speed_rpm=None, f0=0.0, nu_mm2_s=0.0, f1=None,
                load_term: str = "coulomb", friction=None) -> TorqueComponents:
    """Friction torque of a bearing pair from its `bearing.PairState`, vectorised, N*mm
    (`TorqueComponents`).

    model "solid_film": `solid_film_torque_Nmm` per bearing (mu: film friction coefficient,
      hysteresis_loss: alpha_h; with friction.shear_strength "pressure" each contact's own
      coefficient tau0 / p_mean + alpha, `analytic.friction.solid_film`, in place of mu); at
      points where the balls of a bearing carry unequal loads
      (radial load or tilt: `pair.radial`) the sum over every ball's own contacts and contact
      angle instead of Z times the representative ball; sets the hysteresis, differential and
      spin parts (both bearings, inner + outer), the inner- and outer-contact sums and the
      per-bearing totals.
    model "oil": load term per bearing (load_term "coulomb": mu F_a dm/2; "palmgren": f1 F_a dm;
      F_a = sum_k Q_k sin(alpha_k) the bearing's axial force, which under a radial load includes
      the axial component the radial load induces; Harris Vol. 2 gives P1 = F_a - 0.1 F_r for an
      angular-contact bearing, not applied here)
      plus the viscous term per bearing of friction.viscous_model: "palmgren" (f0, nu_mm2_s,
      speed_rpm), "starved" (Palmgren's times the starved-film ratio of the oil quantity,
      `analytic.friction.starved`), "ehl_rolling" (the EHL rolling resistance of each contact,
      `analytic.friction.ehl_rolling`); "skf2004" replaces both terms by SKF's rolling and
      sliding terms and adds its drag (`analytic.friction.skf2004`); sets the load and
      viscous terms (both bearings), the viscosity used and the per-bearing totals.
    With speed_rpm given, also heat_W (total dissipated power) and its split by location.
    g: `bearing.BearingGeometry`; friction: `analytic.friction.options.FrictionOptions`
    (default: Palmgren, constant shear strength: outputs unchanged from the Palmgren law).
    """
    from analytic.friction.options import FrictionOptions
    fr = FrictionOptions() if friction is None else friction
    if model == "solid_film":
        per, parts = _solid_film_pair(g, pair, mu, hysteresis_loss, fr)
        split = dict(rolling_Nmm=parts["hysteresis_Nmm"],
                     sliding_Nmm=parts["differential_Nmm"] + parts["spin_Nmm"],
                     drag_Nmm=np.zeros_like(parts["spin_Nmm"]))
        located = (parts["inner_contacts_Nmm"], parts["outer_contacts_Nmm"], None)
    elif model == "oil":
        per, parts, located = _oil_pair(g, pair, mu, speed_rpm, f0, nu_mm2_s, f1, load_term, fr)
        parts["viscosity_mm2_s"] = nu_mm2_s
        split = dict(rolling_Nmm=parts["viscous_Nmm"], sliding_Nmm=parts["load_Nmm"],
                     drag_Nmm=parts.pop("drag_Nmm"))
    else:
        raise ValueError(f"model must be 'solid_film' or 'oil', got {model!r}")
    total = per[0] + per[1]
    heat = None if speed_rpm is None else power_W(total, speed_rpm)
    if heat is not None:
        split.update(_located_heat_W(located, split["drag_Nmm"], speed_rpm))
    return TorqueComponents(model, total, per[0], per[1], heat, **parts, **split,
                            viscous_model=fr.viscous_model)


def _located_heat_W(located, drag_Nmm, speed_rpm) -> dict:
    """heat_inner_W, heat_outer_W, heat_ball_W from the torques made at the inner and outer
    contacts (N*mm) and the drag (at the balls); a contact's heat given directly in W (the
    third entry of `located`: (inner_W, outer_W) added to them) where a model computes it from
    the contact speeds (`ehl_rolling`)."""
    inner, outer, direct = located
    q_in, q_out = power_W(inner, speed_rpm), power_W(outer, speed_rpm)
    if direct is not None:
        q_in, q_out = q_in + direct[0], q_out + direct[1]
    return dict(heat_inner_W=q_in, heat_outer_W=q_out, heat_ball_W=power_W(drag_Nmm, speed_rpm))


def _solid_film_pair(g, pair, mu, hysteresis_loss, fr) -> tuple[list, dict]:
    """Per-bearing totals and the pair's solid-film components (`pair_torque`), N*mm."""
    from analytic.friction.solid_film import pressure_dependent_mu
    c_ring = (1.0 - g.ring.nu ** 2) / g.ring.E_MPa
    c_ball = (1.0 - g.ball.nu ** 2) / g.ball.E_MPa
    pressure = fr.shear_strength == "pressure"

    def coefficients(cin, cout):
        if not pressure:
            return mu, None
        return tuple(pressure_dependent_mu(fr.tau0_MPa, fr.alpha_shear, c.Q_N, c.a_mm, c.b_mm)
                     for c in (cin, cout))
    hyst = diff = spin = inner = outer = 0.0
    per = []
    for j in range(2):
        cin, cout = contact_inputs(pair, j)
        alpha, alpha_o = contact_angles_rad(pair, j)
        mu_i, mu_o = coefficients(cin, cout)
        c = solid_film_torque_Nmm(g.Z, g.Dw_mm, g.dm_mm, g.f_i, g.f_o, alpha, cin, cout,
                                  mu_i, hysteresis_loss, c_ring, c_ball, alpha_o, mu_o)
        r = pair.radial
        if r is not None and r.ball_inner is not None and np.any(r.unequal_balls):
            # balls with unequal loads: every ball's own contacts and kinematics, summed
            bin_, bout = ball_contact_inputs(r, j)
            a_o = (None if r.ball_contact_angles_outer_deg is None
                   else np.radians(r.ball_contact_angles_outer_deg[j]))
            mb_i, mb_o = coefficients(bin_, bout)
            balls = solid_film_torque_Nmm(
                1, g.Dw_mm, g.dm_mm, g.f_i, g.f_o, np.radians(r.ball_contact_angles_deg[j]),
                bin_, bout, mb_i, hysteresis_loss, c_ring, c_ball, a_o, mb_o)
            c = c.where(r.unequal_balls, balls)
        hyst = hyst + c.hysteresis_inner_Nmm + c.hysteresis_outer_Nmm
        diff = diff + c.differential_inner_Nmm + c.differential_outer_Nmm
        spin = spin + c.spin_inner_Nmm + c.spin_outer_Nmm
        inner = inner + c.hysteresis_inner_Nmm + c.differential_inner_Nmm + c.spin_inner_Nmm
        outer = outer + c.hysteresis_outer_Nmm + c.differential_outer_Nmm + c.spin_outer_Nmm
        per.append(c.total_Nmm)
    return per, dict(hysteresis_Nmm=hyst, differential_Nmm=diff, spin_Nmm=spin,
                     inner_contacts_Nmm=inner, outer_contacts_Nmm=outer)


def _oil_pair(g, pair, mu, speed_rpm, f0, nu_mm2_s, f1, load_term, fr) -> tuple[list, dict, tuple]:
    """Per-bearing totals, the pair's load, viscous and drag terms (`pair_torque`), N*mm, and
    where they are made: (torque at the inner contacts, at the outer contacts, heat computed at
    the contacts in W or None)."""
    n = 0.0 if speed_rpm is None else speed_rpm
    model = fr.viscous_model
    if model == "skf2004":
        return _skf_pair(g, pair, n, nu_mm2_s, fr)
    visc = palmgren_viscous_torque_Nmm(f0, nu_mm2_s, n, g.dm_mm)
    visc_j, direct = (visc, visc), None
    if model == "starved" and fr.oil_quantity_mg > 0:
        visc_j = tuple(visc * _starvation_ratio(g, pair, j, n, fr) for j in (0, 1))
    elif model == "ehl_rolling":
        e = ehl_rolling_pair(g, pair, n, fr.eta_Pa_s, fr.alpha_per_Pa)
        visc_j = e.per_bearing_Nmm
        direct = (e.heat_inner_W, e.heat_outer_W) if speed_rpm is not None else None
    load = 0.0
    per = []
    for j in range(2):
        Fa = pair.axial_force_N[j]
        if load_term == "coulomb":
            m1 = coulomb_load_torque_Nmm(mu, Fa, 0.5 * g.dm_mm)
        elif load_term == "palmgren":
            m1 = palmgren_load_torque_Nmm(f1, Fa, g.dm_mm)
        else:
            raise ValueError(f"load_term must be 'coulomb' or 'palmgren', got {load_term!r}")
        load = load + m1
        per.append(m1 + visc_j[j])
    if model in ("palmgren", "starved"):
        viscous = (2.0 * visc * np.ones_like(load) if visc_j[0] is visc
                   else (visc_j[0] + visc_j[1]) * np.ones_like(load))
        located = (0.5 * (load + viscous), 0.5 * (load + viscous), None)
    else:                                   # ehl_rolling: its heat located at each contact
        viscous = (visc_j[0] + visc_j[1]) * np.ones_like(load)
        located = (0.5 * load, 0.5 * load, direct)
    return per, dict(load_Nmm=load, viscous_Nmm=viscous, drag_Nmm=np.zeros_like(viscous)), located


def ehl_rolling_pair(g, pair, speed_rpm, eta0_Pa_s, alpha_per_Pa):
    """EHL rolling resistance of each contact of a pair (`analytic.friction.ehl_rolling`) on its
    `bearing.PairState` (quasi-dynamic balls: each contact at its own load and angle, the
    kinematics from both angles), every ball of a bearing at the representative ball's state (a
    radial load's ball-to-ball variation is not resolved here). g: `bearing.BearingGeometry`;
    speed_rpm: inner-ring speed (outer fixed); eta0_Pa_s: the oil's dynamic viscosity at the
    inlet (scalar or per point); alpha_per_Pa: its pressure-viscosity coefficient. Returns the
    `analytic.friction.ehl_rolling.EHLRollingTorque` (torques N mm, heats W)."""
    from analytic.friction.ehl_rolling import EHLRollingTorque, ehl_rolling_bearing
    from analytic.lubrication import reduced_modulus_MPa
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    t_in = t_out = q_in = q_out = 0.0
    per = []
    for j in (0, 1):
        cin, cout = contact_inputs(pair, j)
        kin = ball_kinematics(g.dm_mm, g.Dw_mm, *contact_angles_rad(pair, j))
        (ti, to), (qi, qo) = ehl_rolling_bearing(g.Z, g.dm_mm, Ep, cin, cout, kin.roll_inner,
                                                 kin.roll_outer, speed_rpm, eta0_Pa_s,
                                                 alpha_per_Pa)
        t_in, t_out, q_in, q_out = t_in + ti, t_out + to, q_in + qi, q_out + qo
        per.append(ti + to)
    return EHLRollingTorque(t_in, t_out, q_in, q_out, tuple(per))


def _starvation_ratio(g, pair, j, n_rpm, fr):
    """Mean over bearing j's inner and outer contacts of the starved-film ratio h / h_ff
    (`analytic.friction.starved`) of the oil quantity fr.oil_quantity_mg: the flooded central
    film h_ff by Hamrock-Dowson at each contact's load, ellipticity a/b and entrainment speed."""
    from analytic.friction.starved import starvation_ratio, supply_layer_um
    from analytic.lubrication import hamrock_dowson_film, reduced_modulus_MPa
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    omega = np.abs(np.asarray(n_rpm, float)) * RPM_TO_RAD_S
    cin, cout = contact_inputs(pair, j)
    a_i, a_o = contact_angles_rad(pair, j)
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, a_i, a_o)
    ratios = []
    with np.errstate(divide="ignore", invalid="ignore"):
        for c, roll in ((cin, kin.roll_inner), (cout, kin.roll_outer)):
            u = omega * 0.5 * g.dm_mm * roll
            h_ff = hamrock_dowson_film(c.Rx_mm, c.Rx_mm, Ep, fr.eta_Pa_s, fr.alpha_per_Pa, u,
                                       c.Q_N, k=np.asarray(c.a_mm) / np.asarray(c.b_mm)).h_central_um
            h_oil = supply_layer_um(fr.oil_quantity_mg, fr.density_kg_m3, g.dm_mm, c.a_mm)
            # an unloaded contact (no ellipse) or a bearing at rest: no film to starve
            loaded = (np.asarray(c.Q_N) > 0) & (h_ff > 0) & np.isfinite(h_ff)
            ratios.append(np.where(loaded, starvation_ratio(h_oil, h_ff), 1.0))
    return 0.5 * (ratios[0] + ratios[1])


def _skf_pair(g, pair, n_rpm, nu_mm2_s, fr) -> tuple[list, dict, tuple]:
    """The SKF model per bearing (`analytic.friction.skf2004.skf2004_torque`: F_a the bearing's
    axial force, F_r its radial reaction or 0): load term = SKF's sliding term, viscous term =
    its rolling term, and its drag (0 without an oil bath)."""
    from analytic.friction.skf2004 import skf2004_torque
    r = pair.radial
    sl = rr = dr = 0.0
    per = []
    for j in range(2):
        Fr = 0.0 if r is None else np.abs(r.radial_force_N[j])
        t = skf2004_torque(fr.bore_mm, fr.outside_diameter_mm, Fr, pair.axial_force_N[j], n_rpm,
                           nu_mm2_s)
        sl, rr, dr = sl + t.sliding_Nmm, rr + t.rolling_Nmm, dr + t.drag_Nmm
        per.append(t.total_Nmm)
    return per, dict(load_Nmm=sl, viscous_Nmm=rr, drag_Nmm=dr), (0.5 * (sl + rr), 0.5 * (sl + rr), None)
