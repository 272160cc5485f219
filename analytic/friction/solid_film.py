"""Pressure-dependent interfacial shear strength of a solid lubricant film (MoS2):

    tau = tau0 + alpha p                                              [MPa]

(Bowden & Tabor, The Friction and Lubrication of Solids, Part II (1964); Briscoe & Tabor,
"Shear properties of thin polymeric films", J. Adhesion 9 (1978) 145; for sputtered MoS2:
Singer, Bolster, Wegand, Fayeulle & Stupp, "Hertzian stress contribution to low friction
behavior of thin MoS2 coatings", Appl. Phys. Lett. 57 (1990) 995, who fit the law to Hertzian
tests at 0.3-1 GPa: tau0 of order 20-25 MPa and alpha of order 0.001 as secondary literature
quotes them; the paper itself was not retrievable here, so no default is taken from it: the
assembly or a diagnosis gives tau0_MPa and alpha_shear). The friction coefficient then falls
with the contact pressure as mu = tau0 / p_mean + alpha.

Over a Hertz ellipse (semi-axes a, b; load Q; p(x, y) = (3Q / (2 pi a b)) sqrt(1 - x^2/a^2 -
y^2/b^2)) the friction force is the integral of tau over the contact area:

    F = tau0 pi a b + alpha Q,    mu = F / Q = tau0 pi a b / Q + alpha = tau0 / p_mean + alpha

so a lightly loaded contact (small p_mean) has a high coefficient, and mu -> alpha at high
pressure. Units: tau0 MPa (N/mm^2), a, b mm, Q N, alpha and mu dimensionless.

Used as the friction coefficient of each contact in the solid-film torque (differential slip
and spin: `analytic.torque.solid_film_torque_Nmm`). Approximation (stated): the slip and spin
integrals weight the local traction by the local slip; with a pressure-dependent law the
uniform tau0 part is weighted by area, not by pressure, so taking the contact's mean
coefficient is exact for the total friction force and an approximation for the moments
(spin of a circle: 2 pi tau0 a^3 / 3 by area against 3 pi^2 tau0 a^3 / 16 from the mean
coefficient, 12 % apart on the tau0 part).
Limit: alpha only (tau0 = 0) is the constant (Coulomb) law mu = alpha.
"""
from __future__ import annotations

import numpy as np


def mean_pressure_MPa(Q_N, a_mm, b_mm):
    """Mean Hertz pressure Q / (pi a b), MPa."""
    return np.asarray(Q_N, float) / (np.pi * np.asarray(a_mm, float) * np.asarray(b_mm, float))


def pressure_dependent_mu(tau0_MPa, alpha_shear, Q_N, a_mm, b_mm):
    """Friction coefficient of a Hertz contact with tau = tau0 + alpha p (module docstring):
    mu = tau0 pi a b / Q + alpha (-). A contact without load (Q = 0) gets alpha (no film
    shear without a contact area)."""
    Q = np.asarray(Q_N, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        shear = tau0_MPa * np.pi * np.asarray(a_mm, float) * np.asarray(b_mm, float) / Q
    return np.where(Q > 0, shear, 0.0) + alpha_shear
