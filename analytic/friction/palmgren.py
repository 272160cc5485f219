"""Palmgren's load and viscous friction torques of oil- and grease-lubricated ball bearings
(and the GB/T 28878.2 form that combines them), bearing-level laws of `analytic.friction`.

Oil/grease (seeds 001/002; Palmgren 1959, Harris Vol. 2 ch. "friction"): load term
M1 = f1 P1 dm (or mu P dm/2), viscous term M0 = 1e-7 f0 (nu n)^(2/3) dm^3 for nu n >= 2000 and
160e-7 f0 dm^3 below (nu in mm^2/s = cSt, n in rpm, dm in mm, M in N*mm), and the
GB/T 28878.2-2016 Annex B form M = f1 F dm + c f0 (nu n)^(2/3) dm^3.

Units: N, mm, rpm, mm^2/s; torques N*mm.
"""
from __future__ import annotations

import numpy as np


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
