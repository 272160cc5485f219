"""Friction heat of a bearing pair, split by mechanism and by contact side, for a thermal network;
the thermal conductance of the rolling ball-raceway contacts and the partition of a contact's heat
between ball and ring.

Sliding (differential slip) and spin heat come from the per-contact Hertz states of the pair
equilibrium (`torque.sliding_spin_torque_Nmm` with a traction coefficient); the viscous heat from
the pair's viscous (Palmgren) torque, shared equally between the inner and the outer contacts.
Heat of a torque component M (N*mm) at n (rpm): P = M |omega| (`torque.power_W`; seed 003 eq. 32:
H_B1 sliding, H_B2 viscous, H_B3 spin).
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from functools import lru_cache

import numpy as np

from analytic.materials import Material
from analytic.friction.pair import contact_angles_rad, contact_inputs
from analytic.torque import power_W, sliding_spin_torque_Nmm

#: thermal conductivity of a mineral / synthetic hydrocarbon oil at ambient pressure, W/(m K)
#: (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, 6th ed., Table A.5: unused engine
#: oil 0.145 at 300 K, 0.138 at 350 K). Under the Hertz pressure it is higher
#: (`oil_conductivity_ratio`).
K_OIL_W_MK = 0.14
#: pressure rise of a lubricant's thermal conductivity, k(p) / k(0) = 1 + A p / (1 + B p) with p
#: in GPa: Larsson, Larsson, Eriksson, Sjoberg, Hoglund, "Lubricant properties for input to
#: hydrodynamic and elastohydrodynamic lubrication analyses", Proc. IMechE Part J 214 (2000)
#: 17-27, the fit of their polyalphaolefin (PAO B, a synthetic hydrocarbon like the project's
#: oils): A = 1.40 /GPa, B = 0.34 /GPa, k(0) = 0.154 W/(m K) (the coefficients as the open
#: thermal EHL code github.com/cmeveritt/EHL, Lubrication_def.f90, takes them from the paper).
#: k doubles by 1 GPa (2.04 x), within the 1.5-2.5 x the same group reports for mineral and
#: synthetic oils (Larsson & Andersson, Proc. IMechE J 214 (2000) 337).
K_OIL_PRESSURE_A_PER_GPA = 1.40
K_OIL_PRESSURE_B_PER_GPA = 0.34
#: the highest pressure of the measurements behind the fit, GPa (the same code caps its use of
#: the fit there); above it the ratio is held at its value there (no extrapolation: the film's
#: conductance is then a lower bound)
K_OIL_PRESSURE_MAX_GPA = 1.1


@dataclass(frozen=True)
class PairHeat:
    """Heat of the pair per operating point, W (both bearings)."""
    sliding_W: np.ndarray        # differential slip, inner + outer contacts
    spin_W: np.ndarray           # spin, inner + outer contacts
    viscous_W: np.ndarray        # viscous (lubricant) losses
    inner_W: np.ndarray          # everything generated at the inner contacts (half the viscous part)
    outer_W: np.ndarray          # everything generated at the outer contacts (half the viscous part)
    hysteresis_W: np.ndarray | float = 0.0   # elastic hysteresis (solid-film model)
    drag_W: np.ndarray | float = 0.0         # made in the oil around the balls (SKF drag), at the balls

    @property
    def total_W(self) -> np.ndarray:
        return self.sliding_W + self.spin_W + self.viscous_W + self.hysteresis_W + self.drag_W

    def scaled(self, factor: float) -> "PairHeat":
        """Every term x factor (-): the heat of a torque x factor, e.g. at an end of its
        model-form interval (`analytic.friction.interval`)."""
        return PairHeat(*(factor * np.asarray(getattr(self, f.name), float) for f in fields(self)))


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


def solid_film_pair_heat_W(torque, speed_rpm) -> PairHeat:
    """Heat of a solid-film lubricated pair (W) from its torque components (`analytic.torque.
    pair_torque` with model "solid_film": differential slip, spin and hysteresis, each summed
    over both bearings, and the same torque split into inner and outer contacts): P = M |omega|
    per component (`torque.power_W`); no viscous part. inner_W + outer_W = total_W."""
    if torque.model != "solid_film":
        raise ValueError(f"solid_film_pair_heat_W needs a solid-film torque, got '{torque.model}'")
    n = np.asarray(speed_rpm, float)
    return PairHeat(sliding_W=power_W(torque.differential_Nmm, n), spin_W=power_W(torque.spin_Nmm, n),
                    viscous_W=np.zeros_like(power_W(torque.spin_Nmm, n)),
                    inner_W=power_W(torque.inner_contacts_Nmm, n),
                    outer_W=power_W(torque.outer_contacts_Nmm, n),
                    hysteresis_W=power_W(torque.hysteresis_Nmm, n))


def located_pair_heat_W(torque, speed_rpm) -> PairHeat:
    """Heat of an oil-lubricated pair (W) from its torque's own split by location (`analytic.
    friction.pair.pair_torque` with a friction model of analytic/friction: `heat_inner_W`, `heat_outer_W`,
    `heat_ball_W`): the sliding part is the torque's sliding term, the viscous part its rolling
    term, the drag the heat at the balls; inner_W + outer_W + drag_W = total_W = the torque's
    heat. Unlike `pair_heat_W` (Palmgren: sliding and spin from a traction coefficient beside the
    torque model) the heat is the torque's own dissipation."""
    if torque.heat_inner_W is None:
        raise ValueError("located_pair_heat_W needs a torque computed with a speed")
    n = np.asarray(speed_rpm, float)
    return PairHeat(sliding_W=power_W(torque.sliding_Nmm, n),
                    spin_W=np.zeros_like(power_W(torque.sliding_Nmm, n)),
                    viscous_W=power_W(torque.rolling_Nmm, n), inner_W=torque.heat_inner_W,
                    outer_W=torque.heat_outer_W, drag_W=torque.heat_ball_W)


# ------------------------------------------------------------------ rolling contact conductance
@lru_cache(maxsize=None)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights of n points on [-1, 1] (numpy's `leggauss`, read-only),
    computed once per n: `leggauss` solves an n x n eigenvalue problem each call (25 ms at 512)."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = w.flags.writeable = False
    return x, w


def oil_conductivity_ratio(pressure_MPa):
    """k(p) / k(0) of a lubricant at pressure p (MPa): 1 + A p / (1 + B p), p in GPa, held at
    its value at K_OIL_PRESSURE_MAX_GPA above that (Larsson et al. 2000, the constants above);
    1 at p <= 0."""
    p = np.clip(np.asarray(pressure_MPa, float) * 1e-3, 0.0, K_OIL_PRESSURE_MAX_GPA)
    return 1.0 + K_OIL_PRESSURE_A_PER_GPA * p / (1.0 + K_OIL_PRESSURE_B_PER_GPA * p)


def hertz_mean_conductivity_ratio(p_max_MPa: float, n: int = 32) -> float:
    """Area mean of `oil_conductivity_ratio` over a Hertz ellipse with peak pressure p_max (MPa):
    the film's conductance across a film of uniform thickness h is int k(p(x, y)) / h dA =
    (A / h) <k>, with the Hertz distribution p = p_max sqrt(1 - rho^2) (Johnson, Contact
    Mechanics, 1985, eq. 4.34; rho the normalised elliptic radius, dA ~ 2 rho d rho):
    <k>/k(0) = int_0^1 ratio(p_max s) 2 s ds (s = sqrt(1 - rho^2)); Gauss-Legendre with n nodes
    (the integrand is smooth below the cap and has one kink at it: n = 32 is within 1e-4)."""
    x, w = _gauss_legendre(n)
    s = 0.5 * (1.0 + x)
    return float(np.sum(0.5 * w * oil_conductivity_ratio(p_max_MPa * s) * 2.0 * s))


def moving_contact_resistance_K_W(a_mm: float, b_mm: float, speed_mm_s: float, k_W_mK: float,
                                  diffusivity_mm2_s: float, n_phi: int = 512,
                                  n_d: int = 64) -> float:
    """Mean surface temperature rise per unit heat (K/W) of a uniform heat flux over an elliptical
    contact (semi-axes a across and b along the motion, mm) on a half-space whose surface passes
    through it at speed V (mm/s): the constriction resistance of one side of a rolling contact.

    Steady moving point source on a half-space (Carslaw & Jaeger, Conduction of Heat in Solids,
    2nd ed., sec. 10.7; Rosenthal 1946): theta = Q exp(-V (R + xi) / (2 kappa)) / (2 pi k R),
    xi along the motion. Averaged over the source for a uniform flux q = Q/A, A = pi a b:

        theta_m / Q = 1 / (2 pi k A^2) int g(s) exp(-V (|s| + s_x) / (2 kappa)) / |s| d^2 s,

    g(s) the overlap area of the ellipse with its translate by s; in polar coordinates the 1/|s|
    cancels, and with the ellipse mapped to the unit circle g = a b (2 acos(d/2) - (d/2)
    sqrt(4 - d^2)), d = |s| c(phi), c^2 = cos^2 phi / b^2 + sin^2 phi / a^2. Gauss-Legendre in d
    on [0, 2] and phi on [0, pi] (the integrand is even in phi). Limits (tests/test_heat.py): V = 0
    gives the stationary isoflux disc 8 / (3 pi^2 k a) for a = b (Yovanovich; 1.08 x Holm's
    isothermal 1 / (4 k a)); Peclet number Pe = V b / (2 kappa) >> 1 gives Jaeger's
    penetration limit (Jaeger, Proc. R. Soc. NSW 76 (1942) 203; Archard, Wear 2 (1959) 438):
    theta_m = 0.9153 (4/3) q sqrt(2 kappa b / (pi V)) / k for the ellipse (the strip's
    (4/3) q l / (k sqrt(pi Pe)) averaged over the chords). k in W/(m K) (-> W/(mm K) inside),
    kappa = k / (rho c) in mm^2/s."""
    k = k_W_mK * 1e-3
    xd, wd = _gauss_legendre(n_d)
    d = 1.0 + xd                                   # [0, 2]
    overlap = 2.0 * np.arccos(0.5 * d) - 0.5 * d * np.sqrt(4.0 - d * d)
    xp, wp = _gauss_legendre(n_phi)
    phi = 0.5 * np.pi * (1.0 + xp)                 # [0, pi]
    wphi = 0.5 * np.pi * wp
    c = np.sqrt(np.cos(phi) ** 2 / b_mm ** 2 + np.sin(phi) ** 2 / a_mm ** 2)
    e = np.exp(-speed_mm_s * d[None, :] * (1.0 + np.cos(phi))[:, None]
               / (2.0 * diffusivity_mm2_s * c[:, None]))
    integral = 2.0 * a_mm * b_mm * np.sum(wphi / c * ((e * overlap) @ wd))
    area = np.pi * a_mm * b_mm
    return float(integral / (2.0 * np.pi * k * area * area))


@dataclass(frozen=True)
class ContactConductance:
    """Heat transfer of the Z ball-raceway contacts of one raceway of a bearing.

    G_W_K: ball set to raceway conductance (all Z contacts in parallel), W/K; ring_share: share
    of the heat generated in a contact that goes into the ring (the rest into the ball), -;
    R_ball_K_W, R_film_K_W, R_ring_K_W: one contact's resistances in series (ball side, lubricant
    film, ring side), K/W."""
    G_W_K: float
    ring_share: float
    R_ball_K_W: float
    R_film_K_W: float
    R_ring_K_W: float


def rolling_contact_conductance(a_mm: float, b_mm: float, rolling_speed_mm_s: float,
                                ball: Material, ring: Material, n_balls: int,
                                film_um: float = 0.0,
                                k_film_W_mK: float = K_OIL_W_MK,
                                p_max_MPa: float = 0.0) -> ContactConductance:
    """Conductance between a bearing's ball set and one raceway, and the partition of the heat
    generated in the contacts, from the Hertz ellipse (semi-axes a across, b along the rolling
    direction, mm), the rolling speed (mm/s: the speed at which ball and ring surfaces pass
    through the contact, `analytic.lubrication.entrainment_speed_mm_s`) and the lubricant film.

    Per contact three resistances in series: the ball side and the ring side are moving-source
    constrictions (`moving_contact_resistance_K_W`, each surface passes through the contact at
    the rolling speed; at rest they are the stationary isoflux constriction, close to Holm's
    1/(4 k a) the lumped network uses), and a full EHL film of thickness h (um) conducts across
    it, R_film = h / (<k_film> pi a b) (1-D conduction: across a 0.3 um film heat equalises in
    h^2/kappa_oil ~ 1 us, the transit time 2b/V is ~ 100 us), <k_film> the oil's conductivity
    (k_film_W_mK, W/(m K), at ambient pressure) raised by the Hertz pressure (peak p_max_MPa, MPa;
    0: ambient pressure) and averaged over the ellipse (`hertz_mean_conductivity_ratio`); h = 0
    (solid film, boundary or dry contact): no film term. G = Z / (R_ball + R_film + R_ring).
    Partition: the heat is generated in the film's mid-plane (or at the interface, h = 0) and
    flows into both bodies, which see the same contact temperature (Blok's partition, Proc.
    Gen. Disc. Lubrication, IMechE 1937; Archard 1959): ring share = (R_ball + R_film/2) /
    (R_ball + R_film + R_ring); 1/2 for equal materials (Burton & Staph 1967, seed 003).
    Together with G this is the lumped form of the contact: heat to the ring = share x generated
    + G/Z (T_ball - T_ring) per contact, exactly (linear superposition of the two sources)."""
    Rb = moving_contact_resistance_K_W(a_mm, b_mm, rolling_speed_mm_s, ball.conductivity_W_mK,
                                       _diffusivity_mm2_s(ball))
    Rr = moving_contact_resistance_K_W(a_mm, b_mm, rolling_speed_mm_s, ring.conductivity_W_mK,
                                       _diffusivity_mm2_s(ring))
    k_f = k_film_W_mK * hertz_mean_conductivity_ratio(p_max_MPa)
    Rf = float(film_um) * 1e-6 / (k_f * np.pi * a_mm * b_mm * 1e-6)
    R = Rb + Rf + Rr
    return ContactConductance(float(n_balls) / R, (Rb + 0.5 * Rf) / R, Rb, Rf, Rr)


def _diffusivity_mm2_s(m: Material) -> float:
    """kappa = k / (rho c_p), mm^2/s (k W/(m K), rho kg/m^3, c_p J/(kg K))."""
    return m.conductivity_W_mK / (m.density_kg_m3 * m.specific_heat_J_kgK) * 1e6
