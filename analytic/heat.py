"""Friction heat of a bearing pair, split by mechanism and by contact side, for a thermal network.

Sliding (differential slip) and spin heat come from the per-contact Hertz states of the pair
equilibrium (`torque.sliding_spin_torque_Nmm` with a traction coefficient); the viscous heat from
the pair's viscous (Palmgren) torque, shared equally between the inner and the outer contacts.
Heat of a torque component M (N*mm) at n (rpm): P = M |omega| (`torque.power_W`; seed 003 eq. 32:
H_B1 sliding, H_B2 viscous, H_B3 spin).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.torque import contact_angles_rad, contact_inputs, power_W, sliding_spin_torque_Nmm


@dataclass(frozen=True)
class PairHeat:
    """Heat of the pair per operating point, W (both bearings)."""
    sliding_W: np.ndarray        # differential slip, inner + outer contacts
    spin_W: np.ndarray           # spin, inner + outer contacts
    viscous_W: np.ndarray        # viscous (lubricant) losses
    inner_W: np.ndarray          # everything generated at the inner contacts (half the viscous part)
    outer_W: np.ndarray          # everything generated at the outer contacts (half the viscous part)

    @property
    def total_W(self) -> np.ndarray:
        return self.sliding_W + self.spin_W + self.viscous_W


def pair_heat_W(g, pair, speed_rpm, mu_traction: float, viscous_torque_Nmm) -> PairHeat:
    """Heat generated in the pair at speed_rpm (rpm), W.

    g: `bearing.BearingGeometry`; pair: `bearing.PairState` (ball loads N, contact angles deg,
    Hertz ellipses mm; with quasi-dynamic balls each contact at its own load and angle, and the
    kinematics from both angles); mu_traction: traction coefficient for sliding and spin (-);
    viscous_torque_Nmm: viscous torque of the pair (both bearings), N*mm.
    Sliding and spin torques per contact: Harris & Kotzalas Vol. 2 ch. 6 (Heathcote slip and spin
    moment over the Hertz ellipse), via `torque.sliding_spin_torque_Nmm`; power P = M |omega|.
    inner_W + outer_W = sliding_W + spin_W + viscous_W.
    """
    n = np.asarray(speed_rpm, float)
    sl_i = sl_o = sp_i = sp_o = 0.0         # both bearings' torques per contact, N*mm
    for j in (0, 1):
        cin, cout = contact_inputs(pair, j)
        alpha_i, alpha_o = contact_angles_rad(pair, j)
        t = sliding_spin_torque_Nmm(g.Z, g.Dw_mm, g.dm_mm, g.f_i, g.f_o, alpha_i, cin, cout,
                                    mu_traction, alpha_outer_rad=alpha_o)
        sl_i, sl_o = sl_i + t.sliding_inner_Nmm, sl_o + t.sliding_outer_Nmm
        sp_i, sp_o = sp_i + t.spin_inner_Nmm, sp_o + t.spin_outer_Nmm
    visc = np.asarray(viscous_torque_Nmm, float)
    return PairHeat(
        sliding_W=power_W(sl_i + sl_o, n),
        spin_W=power_W(sp_i + sp_o, n),
        viscous_W=power_W(visc, n),
        inner_W=power_W(sl_i + sp_i + 0.5 * visc, n),
        outer_W=power_W(sl_o + sp_o + 0.5 * visc, n))
