"""SKF four-component frictional moment of an angular-contact ball bearing (the "SKF model for
calculating the frictional moment", SKF General Catalogue 6000 EN (2005) / Rolling Bearings
catalogue 10000 EN, section "Friction"):

    M = phi_ish phi_rs M_rr + M_sl + M_seal + M_drag                       [N mm]

    M_rr    = G_rr (nu n)^0.6                                   rolling
    M_sl    = G_sl mu_sl                                        sliding
    phi_ish = 1 / (1 + 1.84e-9 (n dm)^1.28 nu^0.64)             inlet shear heating reduction
    phi_rs  = 1 / exp(K_rs nu n (d + D) sqrt(K_z / (2 (D - d))))  kinematic replenishment /
                                                                 starvation reduction
    mu_sl   = phi_bl mu_bl + (1 - phi_bl) mu_EHL,  phi_bl = 1 / exp(2.6e-8 (n nu)^1.4 dm)
    M_drag  = 1.093e-7 n^2 dm^3 (n dm^2 f_t / nu)^-1.379 R_s                (oil bath, below)

Angular-contact ball bearings (catalogue table "geometric and load dependent variables"):

    G_rr = R1 dm^1.97 (F_r + F_g + R2 F_a)^0.54,             F_g = R3 dm^4 n^2
    G_sl = S1 dm^0.26 ((F_r + F_g)^(4/3) + S2 F_a^(4/3)),    F_g = S3 dm^4 n^2

n rpm, nu mm^2/s (the oil at the operating temperature), dm = (d + D)/2, d, D mm, forces N,
torques N mm. Constants as the catalogue tabulates them (stated at each constant below).
Checked against the catalogue's own pages (SKF "Rolling bearings", section Friction, "The SKF
model for calculating the frictional moment", as published on yumpu.com, document 55668573,
pp. 105-106): table 2a (G_rr = R1 dm^1.97 [F_r + F_g + R2 F_a]^0.54, F_g = R3 dm^4 n^2,
G_sl = S1 dm^0.26 [(F_r + F_g)^(4/3) + S2 F_a^(4/3)], F_g = S3 dm^4 n^2 for angular-contact ball
bearings), the sliding coefficient (phi_bl = 1/e^(2.6e-8 (n nu)^1.4 dm), mu_bl "generally
~0.15", mu_EHL 0.05 mineral, 0.04 synthetic oils, 0.1 transmission fluids); phi_ish and phi_rs
with K_z = 4.4 (angular-contact ball bearings) and K_rs = 3e-8 (oil jet, low-level oil bath),
6e-8 (grease, oil-air) as an independent open implementation of the same SKF document takes
them. The constants R1..S3 are table 2b's row "angular contact ball bearings, single row" of the
General Catalogue 6000 (2005) as recalled (5.03e-7, 1.97, 1.90e-12, 1.30e-2, 0.68, 1.91e-12; an
open implementation, dozersim, uses the same six numbers for every angular-contact bearing).
No copy of table 2b was retrievable here to re-check their digits (searched 2026-11-29). The
later catalogue (10000 / 17000) tabulates them per series; an open transcription of it
(GitHub JRaposo-m/SKF-Bearing-Selection-Tool) gives for 72 B 4.33e-7, 2.02, 2.44e-12,
1.82e-2, 0.71, 2.44e-12: under a pure axial load 13 % lower in G_rr (R1 R2^0.54) and 46 %
higher in G_sl (S1 S2) than the single-row set. Neither set is a test's expected value.

Limits (what the catalogue states): steady running, full-film to mixed lubrication of a
mineral or synthetic oil, loads not below the minimum load, speeds below the limiting speed;
the constants are for SKF's standard internal designs of each series. No seals here
(M_seal = 0: the project's bearings are open). Range of the speed (stated, `NDM_LIMIT`): the
model's speeds end at the bearing's limiting speed, which the catalogue tabulates per bearing
(its oil limiting speeds of 72 / 73 B bearings are n dm of about 0.6e6 to 1.0e6 mm/min); the
project takes n dm <= 1.0e6 as the model's range and warns beyond it.

Lubrication method and oil family (`[lubrication] lubrication_method`, the lubricant's
`family`; `constants_for`): K_rs = 3e-8 for an oil jet and a low-level oil bath, 6e-8 for grease
and oil-air (the catalogue's two values; a few mg of oil, "minimal_oil", is taken as oil-air:
a small quantity replenished by the balls); mu_EHL 0.05 mineral, 0.04 synthetic oil; K_z = 4.4
and R1..S3 are the bearing type's (angular-contact ball bearing) whatever the method.

Drag in an oil bath (SKF Rolling bearings catalogue 17000 (2018), "Drag losses in oil bath
lubrication", ball bearings; formula recalled, the catalogue's own page not reached here, see
docs/friction_sources.md): the rolling elements' drag

    M_drag = 1.093e-7 n^2 dm^3 (n dm^2 f_t / nu)^-1.379 R_s                      [N mm]
    R_s    = 0.36 dm^2 (t - sin t) f_A,    f_A = 0.05 K_z (D + d) / (D - d)
    t      = 2 arccos((0.6 dm - H) / (0.6 dm)),  H <= 1.2 dm (a higher level taken as 1.2 dm)
    f_t    = sin(t / 2) for t <= pi, 1 above

H the oil level above the lowest point of the outer raceway (mm; 0: no bath, no drag). The
catalogue adds a bulk churning term 0.4 V_M K_ball dm^5 n^2 whose factor V_M is read from a
diagram (H / dm); the diagram was not reachable, so that term is left out: the drag here is the
rolling elements' part, a lower bound of the catalogue's. Without a bath (oil jet, oil-air,
grease, a few mg of oil) the drag is 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: inlet shear heating reduction: phi_ish = 1 / (1 + ISH_COEFF (n dm)^1.28 nu^0.64)
ISH_COEFF = 1.84e-9
#: boundary weighting: phi_bl = exp(-BL_COEFF (n nu)^1.4 dm)
BL_COEFF = 2.6e-8
#: replenishment / starvation constant K_rs: oil jet and low-level oil bath
K_RS_OIL = 3e-8
#: K_rs for grease and oil-air lubrication
K_RS_GREASE = 6e-8
#: K_rs by `[lubrication] lubrication_method` (module docstring; "" = not stated: the oil value)
K_RS_BY_METHOD = {"oil_bath": K_RS_OIL, "oil_jet": K_RS_OIL, "oil_air": K_RS_GREASE,
                  "grease": K_RS_GREASE, "minimal_oil": K_RS_GREASE, "": K_RS_OIL}
#: the model's speed range, n dm in mm/min (rpm mm) (module docstring: stated)
NDM_LIMIT = 1.0e6
#: drag of the rolling elements in an oil bath (catalogue 17000): coefficient, exponent, the
#: the drag formula's coefficient and exponent (module docstring)
DRAG_COEFF = 1.093e-7
DRAG_EXPONENT = -1.379
#: oil level (in units of dm) above which the bath is taken as 1.2 dm: the formula's range
DRAG_LEVEL_MAX_DM = 1.2
#: bearing type constant K_z, single-row angular-contact ball bearings
K_Z_ANGULAR_CONTACT = 4.4
#: boundary friction coefficient mu_bl ("approximately 0.15")
MU_BL = 0.15
#: full-film friction coefficient mu_EHL: 0.05 mineral oil, 0.04 synthetic oil,
#: 0.1 transmission fluid (catalogue)
MU_EHL = {"mineral": 0.05, "synthetic": 0.04, "transmission": 0.1}


@dataclass(frozen=True)
class SkfConstants:
    """Geometry constants of one bearing series (catalogue table of R1..S3), SKF's units
    (torques N mm, forces N, lengths mm, n rpm)."""
    series: str
    R1: float
    R2: float
    R3: float
    S1: float
    S2: float
    S3: float


#: single-row angular-contact ball bearings (GC 6000, table 2b, one row for every series; the
#: six numbers recalled, module docstring). Before 2026-11-29 this was labelled "72 B" and a
#: second set (6.34e-7, 1.41, ...) "73 B": that set is, as recalled, the double-row row of the
#: same table, so it was removed (it was used nowhere).
SKF_SINGLE_ROW = SkfConstants("single row", R1=5.03e-7, R2=1.97, R3=1.90e-12, S1=1.30e-2,
                              S2=0.68, S3=1.91e-12)


def inlet_shear_factor(n_rpm, dm_mm, nu_mm2_s):
    """phi_ish = 1 / (1 + 1.84e-9 (n dm)^1.28 nu^0.64) (-): the rolling torque's reduction by
    the heating of the oil sheared in the contact inlet (SKF). 1 at rest."""
    nd = np.abs(np.asarray(n_rpm, float)) * np.asarray(dm_mm, float)
    return 1.0 / (1.0 + ISH_COEFF * nd ** 1.28 * np.asarray(nu_mm2_s, float) ** 0.64)


def replenishment_factor(n_rpm, nu_mm2_s, d_mm, D_mm, K_rs=K_RS_OIL, K_z=K_Z_ANGULAR_CONTACT):
    """phi_rs = exp(-K_rs nu n (d + D) sqrt(K_z / (2 (D - d)))) (-): kinematic replenishment /
    starvation reduction of the rolling torque (SKF); d bore, D outside diameter (mm). 1 at
    rest or with K_rs = 0."""
    n = np.abs(np.asarray(n_rpm, float))
    return np.exp(-K_rs * np.asarray(nu_mm2_s, float) * n * (d_mm + D_mm)
                  * np.sqrt(K_z / (2.0 * (D_mm - d_mm))))


def boundary_weight(n_rpm, nu_mm2_s, dm_mm):
    """phi_bl = exp(-2.6e-8 (n nu)^1.4 dm) (-): the share of boundary friction in the sliding
    coefficient (SKF); 1 at rest (boundary), -> 0 at speed (full film)."""
    nv = np.abs(np.asarray(n_rpm, float)) * np.asarray(nu_mm2_s, float)
    return np.exp(-BL_COEFF * nv ** 1.4 * np.asarray(dm_mm, float))


def sliding_coefficient(n_rpm, nu_mm2_s, dm_mm, mu_bl=MU_BL, mu_ehl=MU_EHL["mineral"]):
    """mu_sl = phi_bl mu_bl + (1 - phi_bl) mu_EHL (-) (SKF)."""
    w = boundary_weight(n_rpm, nu_mm2_s, dm_mm)
    return w * mu_bl + (1.0 - w) * mu_ehl


def rolling_variable(c: SkfConstants, dm_mm, Fr_N, Fa_N, n_rpm=0.0):
    """G_rr = R1 dm^1.97 (F_r + F_g + R2 F_a)^0.54, F_g = R3 dm^4 n^2 (SKF, angular-contact
    ball bearings); the rolling torque M_rr = G_rr (nu n)^0.6 in N mm."""
    dm = np.asarray(dm_mm, float)
    Fg = c.R3 * dm ** 4 * np.square(np.asarray(n_rpm, float))
    return c.R1 * dm ** 1.97 * (np.asarray(Fr_N, float) + Fg + c.R2 * np.asarray(Fa_N, float)) ** 0.54


def sliding_variable(c: SkfConstants, dm_mm, Fr_N, Fa_N, n_rpm=0.0):
    """G_sl = S1 dm^0.26 ((F_r + F_g)^(4/3) + S2 F_a^(4/3)), F_g = S3 dm^4 n^2 (SKF,
    angular-contact ball bearings); the sliding torque M_sl = G_sl mu_sl in N mm."""
    dm = np.asarray(dm_mm, float)
    Fg = c.S3 * dm ** 4 * np.square(np.asarray(n_rpm, float))
    return c.S1 * dm ** 0.26 * ((np.asarray(Fr_N, float) + Fg) ** (4.0 / 3.0)
                                + c.S2 * np.asarray(Fa_N, float) ** (4.0 / 3.0))


def drag_torque_Nmm(oil_level_mm, d_mm, D_mm, n_rpm, nu_mm2_s, K_z=K_Z_ANGULAR_CONTACT):
    """Drag of the rolling elements in an oil bath, N mm (module docstring, catalogue 17000):
    M_drag = 1.093e-7 n^2 dm^3 (n dm^2 f_t / nu)^-1.379 R_s, R_s = 0.36 dm^2 (t - sin t) f_A,
    f_A = 0.05 K_z (D + d)/(D - d), t = 2 arccos((0.6 dm - H)/(0.6 dm)) with H the oil level
    (mm, capped at 1.2 dm), f_t = sin(t/2) up to t = pi, 1 above. 0 without a bath (H = 0) or
    at rest; n rpm, nu mm^2/s, d, D mm."""
    dm = 0.5 * (d_mm + D_mm)
    H = np.minimum(np.asarray(oil_level_mm, float), DRAG_LEVEL_MAX_DM * dm)
    t = 2.0 * np.arccos(np.clip((0.6 * dm - H) / (0.6 * dm), -1.0, 1.0))
    f_t = np.where(t <= np.pi, np.sin(0.5 * t), 1.0)
    f_A = 0.05 * K_z * (D_mm + d_mm) / (D_mm - d_mm)
    R_s = 0.36 * dm * dm * (t - np.sin(t)) * f_A
    n = np.abs(np.asarray(n_rpm, float))
    nu = np.asarray(nu_mm2_s, float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        M = DRAG_COEFF * n * n * dm ** 3 * (n * dm * dm * f_t / nu) ** DRAG_EXPONENT * R_s
    return np.where((n > 0) & (H > 0), M, 0.0)


def constants_for(lubrication_method: str = "", oil_family: str = "mineral") -> dict:
    """K_rs and mu_EHL of the SKF model for a lubrication method (one of K_RS_BY_METHOD) and an
    oil family ("mineral" or "synthetic"), as `skf2004_torque`'s keyword arguments (module
    docstring). ValueError for an unknown method or family."""
    if lubrication_method not in K_RS_BY_METHOD:
        raise ValueError(f"lubrication_method must be one of {sorted(K_RS_BY_METHOD)[1:]}, "
                         f"got {lubrication_method!r}")
    if oil_family not in ("mineral", "synthetic"):
        raise ValueError(f"oil family must be 'mineral' or 'synthetic', got {oil_family!r}")
    return dict(K_rs=K_RS_BY_METHOD[lubrication_method], mu_ehl=MU_EHL[oil_family])


@dataclass(frozen=True)
class SkfTorque:
    """SKF frictional moment of one bearing by component, N mm, and its factors (-)."""
    rolling_Nmm: np.ndarray      # phi_ish phi_rs G_rr (nu n)^0.6
    sliding_Nmm: np.ndarray      # G_sl mu_sl
    drag_Nmm: np.ndarray
    phi_ish: np.ndarray
    phi_rs: np.ndarray
    mu_sl: np.ndarray

    @property
    def total_Nmm(self) -> np.ndarray:
        return self.rolling_Nmm + self.sliding_Nmm + self.drag_Nmm


def skf2004_torque(d_mm: float, D_mm: float, Fr_N, Fa_N, n_rpm, nu_mm2_s,
                   constants: SkfConstants = SKF_SINGLE_ROW, K_rs: float = K_RS_OIL,
                   K_z: float = K_Z_ANGULAR_CONTACT, mu_bl: float = MU_BL,
                   mu_ehl: float = MU_EHL["mineral"], oil_level_mm=0.0) -> SkfTorque:
    """Frictional moment of one angular-contact ball bearing by the SKF model (module
    docstring), N mm: d bore and D outside diameter mm, F_r radial and F_a axial load N, n rpm,
    nu mm^2/s, oil_level_mm the bath's level H (0: no bath, no drag). No seals. A bearing at
    rest has no running torque (every component 0 at n = 0, like
    `analytic.friction.palmgren.palmgren_viscous_torque_Nmm`). ValueError without a bearing
    (d and D > 0, D > d: the model's dm and D - d)."""
    if not (np.all(np.asarray(d_mm) > 0) and np.all(np.asarray(D_mm) > np.asarray(d_mm))):
        raise ValueError(f"skf2004 needs the bearing's bore and outside diameter (0 < d < D), "
                         f"got d = {d_mm!r} mm, D = {D_mm!r} mm")
    dm = 0.5 * (d_mm + D_mm)
    n = np.abs(np.asarray(n_rpm, float))
    nu = np.asarray(nu_mm2_s, float)
    ish = inlet_shear_factor(n, dm, nu)
    rs = replenishment_factor(n, nu, d_mm, D_mm, K_rs, K_z)
    M_rr = ish * rs * rolling_variable(constants, dm, Fr_N, Fa_N, n) * (nu * n) ** 0.6
    mu = sliding_coefficient(n, nu, dm, mu_bl, mu_ehl)
    M_sl = np.where(n > 0, sliding_variable(constants, dm, Fr_N, Fa_N, n) * mu, 0.0)
    M_drag = drag_torque_Nmm(oil_level_mm, d_mm, D_mm, n, nu, K_z) * np.ones_like(M_rr)
    return SkfTorque(M_rr, M_sl, M_drag, ish, rs, mu)


def skf2004_starting_torque_Nmm(d_mm: float, D_mm: float, Fr_N, Fa_N,
                                constants: SkfConstants = SKF_SINGLE_ROW, mu_bl: float = MU_BL):
    """Starting torque of one angular-contact ball bearing by the SKF model, N mm: the
    catalogue's rule M_start = M_sl + M_seal (SKF Rolling bearings catalogue, section Friction,
    "Starting torque": only the sliding moment and the seals' at 20-30 C), with M_seal = 0 (open
    bearings) and M_sl = G_sl mu_sl at n = 0, where phi_bl = 1 and mu_sl = mu_bl:
    G_sl(n = 0) mu_bl (d, D mm, F_r, F_a N). The running torque `skf2004_torque` tends to this
    sliding part as n -> 0 (its rolling part ~ (nu n)^0.6 vanishes)."""
    dm = 0.5 * (d_mm + D_mm)
    return sliding_variable(constants, dm, Fr_N, Fa_N, 0.0) * mu_bl
