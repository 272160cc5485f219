"""Starved (minimal-oil) viscous torque for bearings running on a few mg of oil (space
mechanisms; seeds 001 and 002).

Palmgren's viscous term M0 = 1e-7 f0 (nu n)^(2/3) dm^3 assumes a flooded inlet: the rolling
(hydrodynamic) loss grows with the film the inlet builds, h ~ (eta u)^0.67 (Hamrock & Dowson),
as M0 does with (nu n)^(2/3). With a finite oil quantity the inlet is starved: the film cannot
exceed what the supply layer on the track holds. The starved film of a point contact
(Chevalier, Lubrecht, Cann, Colin & Dalmaz, "Film thickness in starved EHL point contacts",
J. Tribol. 120 (1998) 126; Damiens, Venner, Cann & Lubrecht, "Starved lubrication of elliptical
EHD contacts", J. Tribol. 126 (2004) 105):

    h / h_ff = r / (1 + r^gamma)^(1/gamma),    r = h_oil / h_ff

with h_oil the supply layer thickness (volume of oil per unit track area, their h_oil,inf) and
gamma = 2.62 for circular contacts (Chevalier et al. 1998, fitted over their measured and
computed starved films; Damiens et al. give gamma of the same order for elliptical contacts;
the value as recalled, not re-checked against the paper here: the flooded and fully starved
limits below do not depend on it).
The hydrodynamic rolling loss scales as the film (both ~ (eta u)^0.67), so the viscous torque
is taken as Palmgren's times the same ratio:

    M0_starved = M0 * r / (1 + r^gamma)^(1/gamma)

Flooded (r >> 1): M0_starved -> M0 (Palmgren, exactly in the limit of infinite oil).
Starved (r << 1): M0_starved -> M0 h_oil / h_ff, independent of viscosity and speed (M0 and h_ff
both ~ (nu n)^(2/3)): the weakening of the viscous term's temperature and speed dependence
that space-bearing torque measurements show (Kingsbury, "Tribology in slow rolling bearings";
Jones et al., NASA oil-quantity tests).

Supply layer: the oil quantity m (mg) of one bearing at density rho spread over the two
raceway tracks, each of circumference pi d_track and width the Hertz contact width 2 a:
h_oil = (m / rho) / (2 pi dm 2 a) (dm the pitch diameter as the mean track diameter). Only part
of a bearing's oil sits on the tracks (the rest wets the cage and the lands), so this h_oil is
an upper bound: the fitted oil quantity of a diagnosis is the effective on-track quantity,
bounded above by the quantity put in the bearing.
Bound of r where the law is fitted: Chevalier et al. cover 0.01 <= r <= 10 (fully starved
to flooded); below 0.01 the film is a few nm, no longer continuum EHL.
Units: m mg, rho kg/m^3, lengths mm, film thicknesses um.
"""
from __future__ import annotations

import numpy as np

#: exponent gamma of the starved-film law for circular contacts (Chevalier et al. 1998)
GAMMA_CIRCULAR = 2.62
#: range of the supply ratio r = h_oil / h_ff covered by the source (Chevalier et al. 1998)
R_RANGE = (0.01, 10.0)


def supply_layer_um(oil_quantity_mg, density_kg_m3, dm_mm, a_mm):
    """Supply layer h_oil on the raceway tracks, um: (m / rho) / (2 pi dm 2 a) with m mg,
    rho kg/m^3 (1 kg/m^3 = 1e-3 mg/mm^3), dm pitch diameter and a the contact semi-width mm
    (module docstring)."""
    volume_mm3 = np.asarray(oil_quantity_mg, float) / (np.asarray(density_kg_m3, float) * 1e-3)
    area_mm2 = 2.0 * np.pi * np.asarray(dm_mm, float) * 2.0 * np.asarray(a_mm, float)
    return 1e3 * volume_mm3 / area_mm2


def starvation_ratio(h_oil_um, h_ff_um, gamma=GAMMA_CIRCULAR):
    """h / h_ff = r / (1 + r^gamma)^(1/gamma), r = h_oil / h_ff (Chevalier et al. 1998) (-);
    1 for an infinite supply (h_oil = inf)."""
    r = np.asarray(h_oil_um, float) / np.asarray(h_ff_um, float)
    with np.errstate(over="ignore", invalid="ignore"):
        s = r / (1.0 + r ** gamma) ** (1.0 / gamma)
        # large r: r / (1 + r^g)^(1/g) = (1 + r^-g)^(-1/g), written so it is exact at r = inf
        s_large = (1.0 + r ** -gamma) ** (-1.0 / gamma)
    return np.where(r > 1.0, s_large, s)


def starved_viscous_torque_Nmm(palmgren_Nmm, h_oil_um, h_ff_um, gamma=GAMMA_CIRCULAR):
    """Viscous torque of a starved bearing, N mm: Palmgren's (`analytic.friction.palmgren.
    palmgren_viscous_torque_Nmm`) times `starvation_ratio` (module docstring)."""
    return np.asarray(palmgren_Nmm, float) * starvation_ratio(h_oil_um, h_ff_um, gamma)
