"""Minimal-oil viscous (rolling) loss: Palmgren's viscous term weakened by the oil the bearing
holds, from a few mg up to flooded (`[lubrication] viscous_model = "minimal_oil"`,
`oil_quantity_mg`; the inlet share `supply_share` is an argument, not a file key).

Law. Palmgren's viscous term M0 = 1e-7 f0 (nu n)^(2/3) dm^3 (Harris & Kotzalas, Rolling Bearing
Analysis 5th ed., Vol. 2 ch. 2) is the hydrodynamic rolling loss of a flooded bearing; it grows
with the inlet film as h ~ (eta u)^0.67 does (Hamrock & Dowson 1977). A bearing with a few mg of
oil cannot build the flooded film: the inlet of each contact is fed only by the layer the balls
and the cage leave on the track. The film of a starved point contact (Chevalier, Lubrecht, Cann,
Colin & Dalmaz, J. Tribol. 120 (1998) 126; Damiens, Venner, Cann & Lubrecht, J. Tribol. 126
(2004) 105) is

    h / h_ff = r / (1 + r^gamma)^(1/gamma),   r = h_in / h_ff,   gamma = 2.62

with h_in the inlet supply layer and h_ff the fully flooded central film
(`analytic.friction.starved.starvation_ratio`, one route for the formula). The rolling loss
scales as the film, so M_v = M0 * mean over the bearing's inner and outer contacts of h / h_ff.

What differs from `starved` (whose supply is the whole charge spread over a track one contact
width wide, so it is flooded from ~20 mg on a 305-size pair): the oil of a minimal-oil bearing
is not on the track but spread over every surface the balls and the cage wipe and wet, and the
inlet is fed from that layer (replenishment by the rolling balls and the cage: Cann & Lubrecht
and Guangteng & Spikes, Tribol. Trans. 39 (1996) 441, show the track replenished from the oil
beside and around it, not from a reservoir of its own). The layer is the charge over the wetted
area

    h_res = (m / rho) / A_wet,   A_wet = pi Dw (Z Dw + 2 dm)

(the Z ball surfaces pi Dw^2 and the two ring bands, inner and outer, of width Dw swept by the
balls: an estimate of the surface within reach of the balls; the cage pockets and lands carry
oil too and are left out, so A_wet is a lower bound and h_res an upper bound), and the inlet
receives the share k of it, h_in = k h_res, with 0 < k <= 1 (`supply_share`, default 1: the
whole layer at every inlet, the upper bound; a diagnosis fits k). Bounds of r as the source's:
Chevalier et al. cover 0.01 <= r <= 10 (fully starved to flooded).

Flooded film h_ff: Hamrock-Dowson's central film (`analytic.lubrication.hamrock_dowson_film`) of
each contact at its load, radii (`ball_raceway_radii_mm`) and entrainment speed, the oil's
viscosity at the row. A contact that has lost its preload is still rolled through the oil: the
ball is pressed on the raceways at least by its centrifugal force F_c = m (dm/2) omega_c^2
(Harris & Kotzalas Vol. 2 ch. 1), so h_ff is taken at max(Q, F_c) (its load exponent is
-0.067: the choice of floor changes h_ff by a few per cent), and the loss follows the oil, not the
preload.

Consequences (the trends the Aerospace Corp. lubricant-quantity rig publishes, 44th AMS 2018):
starved (r << 1) M_v -> M0 h_in / h_ff ~ (nu n)^(2/3) / (eta u)^0.67: independent of the
viscosity, so the drag over Palmgren's (n nu)^(2/3) law (their lubricant quantity factor) rises
as the oil warms and thins (h_ff falls) and, weakly (W^-0.067), with the load; flooded (r >> 1)
M_v -> M0, exactly Palmgren's in the limit of an unlimited charge.
Units: oil mass mg, density kg/m^3, lengths mm, films um, speeds rpm, viscosity Pa s.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.friction.starved import GAMMA_CIRCULAR, R_RANGE, starvation_ratio

#: source range of the supply ratio r (Chevalier et al. 1998), shared with `starved`
SUPPLY_RATIO_RANGE = R_RANGE
#: bounds of the inlet share k of the wetted layer: at most the whole layer (1); below 1e-3 the
#: inlet layer of a 305-size bearing with 100 mg is under 20 nm, below the source's range
SUPPLY_SHARE_BOUNDS = (1e-3, 1.0)


def wetted_area_mm2(Z, Dw_mm, dm_mm):
    """Surface within reach of the balls, A_wet = pi Dw (Z Dw + 2 dm), mm^2: Z ball surfaces
    and the inner and outer ring bands of width Dw on the pitch circle (module docstring)."""
    Dw = np.asarray(Dw_mm, float)
    return np.pi * Dw * (np.asarray(Z, float) * Dw + 2.0 * np.asarray(dm_mm, float))


def reservoir_layer_um(oil_quantity_mg, density_kg_m3, Z, Dw_mm, dm_mm):
    """Layer h_res = (m / rho) / A_wet, um, of m mg of oil of density rho kg/m^3
    (1 kg/m^3 = 1e-3 mg/mm^3) spread over `wetted_area_mm2`."""
    volume_mm3 = np.asarray(oil_quantity_mg, float) / (np.asarray(density_kg_m3, float) * 1e-3)
    return 1e3 * volume_mm3 / wetted_area_mm2(Z, Dw_mm, dm_mm)


def centrifugal_force_N(ball_mass_N_s2_per_mm, dm_mm, speed_rpm, cage_ratio):
    """Centrifugal force of a ball on its orbit, F_c = m (dm/2) (omega w_c)^2, N (m in
    N s^2/mm, omega = 2 pi n / 60 the inner-ring speed, w_c the cage speed ratio; Harris &
    Kotzalas Vol. 2 ch. 1)."""
    w = 2.0 * np.pi * np.abs(np.asarray(speed_rpm, float)) / 60.0 * np.asarray(cage_ratio, float)
    return np.asarray(ball_mass_N_s2_per_mm, float) * 0.5 * np.asarray(dm_mm, float) * w * w


@dataclass(frozen=True)
class MinimalOilFactor:
    """Film ratio h / h_ff of one bearing's contacts (`minimal_oil_ratio`), arrays over rows.
    ratio: mean of the inner and outer contacts' (-), the factor on Palmgren's viscous term;
    supply_ratio_inner / _outer: r = h_in / h_ff (-); h_in_um: the inlet layer k h_res (um)."""
    ratio: np.ndarray
    supply_ratio_inner: np.ndarray
    supply_ratio_outer: np.ndarray
    h_in_um: np.ndarray


def contact_film_ratio(h_in_um, Rx_mm, Ry_mm, E_reduced_MPa, eta_Pa_s, alpha_per_Pa,
                       entrainment_speed_mm_s, load_N, gamma=GAMMA_CIRCULAR):
    """(h / h_ff, r) of one contact: r = h_in / h_ff with h_ff Hamrock-Dowson's flooded central
    film, um, and h / h_ff Chevalier et al.'s starved ratio (module docstring). A contact at rest
    (u = 0) has no film to starve: ratio 1."""
    from analytic.lubrication import hamrock_dowson_film
    u = np.asarray(entrainment_speed_mm_s, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        h_ff = hamrock_dowson_film(Rx_mm, Ry_mm, E_reduced_MPa, eta_Pa_s, alpha_per_Pa,
                                   u, load_N).h_central_um
        r = np.asarray(h_in_um, float) / h_ff
    moving = (u > 0) & np.isfinite(r) & (h_ff > 0)
    r = np.where(moving, r, np.inf)
    return np.where(moving, starvation_ratio(h_in_um, np.where(moving, h_ff, 1.0), gamma), 1.0), r


def minimal_oil_ratio(g, contact_angles_rad, loads_N, speed_rpm, eta_Pa_s, alpha_per_Pa,
                      density_kg_m3, oil_quantity_mg, supply_share=1.0) -> MinimalOilFactor:
    """The minimal-oil factor on Palmgren's viscous term of one bearing (module docstring).
    g: `analytic.bearing.BearingGeometry`; contact_angles_rad: (inner, outer) contact angles
    (rad, arrays over rows; the outer may be None = the inner); loads_N: (inner, outer) ball
    loads N; speed_rpm: inner-ring speed (outer fixed); eta_Pa_s: the oil's dynamic viscosity
    at the rows; alpha_per_Pa: its pressure-viscosity coefficient; density_kg_m3; the charge
    oil_quantity_mg of the bearing (mg; inf = flooded) and the inlet share k of its layer."""
    from analytic.bearing.ball_dynamics import ball_mass_N_s2_per_mm
    from analytic.lubrication import ball_raceway_radii_mm, reduced_modulus_MPa
    from analytic.torque import ball_kinematics
    k = np.asarray(supply_share, float)
    if np.any((k < SUPPLY_SHARE_BOUNDS[0]) | (k > SUPPLY_SHARE_BOUNDS[1])):
        raise ValueError(f"oil_supply_share must lie in {SUPPLY_SHARE_BOUNDS}, got {supply_share}")
    a_i = np.asarray(contact_angles_rad[0], float)
    a_o = a_i if contact_angles_rad[1] is None else np.asarray(contact_angles_rad[1], float)
    kin = ball_kinematics(g.dm_mm, g.Dw_mm, a_i, a_o)
    n = np.abs(np.asarray(speed_rpm, float))
    omega = 2.0 * np.pi * n / 60.0
    Fc = centrifugal_force_N(ball_mass_N_s2_per_mm(g), g.dm_mm, n, kin.cage)
    Ep = reduced_modulus_MPa(g.ring.E_MPa, g.ring.nu, g.ball.E_MPa, g.ball.nu)
    h_in = k * reservoir_layer_um(oil_quantity_mg, density_kg_m3, g.Z, g.Dw_mm, g.dm_mm)
    out = []
    for alpha, Q, f, race, roll in ((a_i, loads_N[0], g.f_i, "inner", kin.roll_inner),
                                    (a_o, loads_N[1], g.f_o, "outer", kin.roll_outer)):
        Rx, Ry = ball_raceway_radii_mm(g.Dw_mm, g.dm_mm, np.degrees(alpha), f, race)
        u = omega * 0.5 * g.dm_mm * roll
        out.append(contact_film_ratio(h_in, Rx, Ry, Ep, eta_Pa_s, alpha_per_Pa, u,
                                      np.maximum(np.asarray(Q, float), Fc)))
    (s_i, r_i), (s_o, r_o) = out
    return MinimalOilFactor(0.5 * (s_i + s_o), r_i, r_o, np.broadcast_to(h_in, np.shape(s_i)))


def minimal_oil_bearing_ratio(g, c, speed_rpm, fr):
    """(factor, range notes) of one bearing's contacts c (`analytic.friction.pair.
    BearingContacts`; the factor the mean over its balls where c.per_ball) with the options fr
    (`analytic.friction.options.FrictionOptions`: the oil's eta_Pa_s, alpha_per_Pa,
    density_kg_m3, oil_quantity_mg and oil_supply_share): the factor on Palmgren's viscous term
    and the rows whose supply ratio falls below the source's range (`analytic.friction.ranges`);
    the one route of the law for `pair_torque` (simulate) and `bearing`."""
    from analytic.friction.ranges import range_rows
    f = minimal_oil_ratio(g, (c.alpha_inner_rad, c.alpha_outer_rad), (c.inner.Q_N, c.outer.Q_N),
                          speed_rpm, fr.eta_Pa_s, fr.alpha_per_Pa, fr.density_kg_m3,
                          fr.oil_quantity_mg, fr.oil_supply_share)
    r = np.stack(np.broadcast_arrays(f.supply_ratio_inner, f.supply_ratio_outer))
    ranges = (range_rows("minimal_oil", "supply ratio h_in/h_ff",
                         f"r >= {SUPPLY_RATIO_RANGE[0]:g}, Chevalier et al. 1998", r,
                         r < SUPPLY_RATIO_RANGE[0]),)
    return (f.ratio.mean(axis=0) if c.per_ball else f.ratio), ranges
