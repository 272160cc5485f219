"""Thermal speed limits of a rolling bearing: the thermal reference speed (ISO 15312:2018) and the
thermally permissible speed (DIN 732:2010, friction after ISO/TR 14179-2).

Units: mm, N, rpm, W, C; torques N*mm, viscosities mm^2/s (cSt), heat flow densities W/mm^2
(1 kW/m^2 = 1e-3 W/mm^2).

Both speeds are the speed n at which the bearing's friction heat equals the heat it can give off
(ISO 15312 clause 5, DIN 732 clause 4): with Palmgren's friction torque (Palmgren 1959; Harris &
Kotzalas, Rolling Bearing Analysis 5th ed., Vol. 2 ch. "friction"; the form ISO 15312 and
ISO/TR 14179-2 use)

    (pi n / 30e3) [M0(n) + M1] = Q,   M0 = 1e-7 f0 (nu n)^(2/3) dm^3 (nu n >= 2000),
                                      M0 = 160e-7 f0 dm^3 (nu n < 2000),  M1 = f1 P1 dm,

the left side the power of `analytic.torque.power_W` (W for M in N*mm, n in rpm), solved for n
(it rises monotonically in n, so the root is unique: `heat_balance_speed_rpm`).

Thermal reference speed n_theta_r (ISO 15312:2018, reference conditions for radial bearings):
bearing (stationary outer ring) at 70 C in 20 C ambient (Delta T_r = 50 K); oil bath with the
reference viscosity nu_r = 12 mm^2/s (ISO VG 32 at 70 C); reference load P1r = 0.05 C0r (radial);
the coefficients f0r, f1r of the bearing type (ISO 15312 Annex A, or the maker's); heat given off
through the reference heat-emitting surface A_r = pi B (D + d) with the reference heat flow density
    q_r = 16 kW/m^2                          for A_r <= 50 000 mm^2,
    q_r = 16 (A_r / 50 000)^-0.34 kW/m^2     for A_r >  50 000 mm^2   (radial bearings),
so Q_r = q_r A_r.

Thermally permissible speed n_perm (DIN 732:2010): n_perm = f_n n_theta_r with the speed ratio
f_n the root of
    K_L f_n^(5/3) + K_P f_n = 1,
    K_L = (pi n_theta_r / 30e3) 1e-7 f0 (nu n_theta_r)^(2/3) dm^3 / Q,
    K_P = (pi n_theta_r / 30e3) f1 P1 dm / Q,
i.e. the same heat balance under the actual lubricant (f0 of the lubrication method, nu at the
operating temperature), the actual load (M1 = f1 P1 dm, ISO/TR 14179-2: for angular-contact ball
bearings f1 = 0.001 (P0/C0)^0.33) and the actual heat given off,
    Q = k_q A_S (T_bearing - T_ambient) + Q_extra,
k_q the heat transfer coefficient of the bearing seat surface A_S (= A_r for a radial bearing).
At the reference conditions (f0 = f0r, f1 P1 = f1r P1r, nu = nu_r, Q = Q_r) f_n = 1: n_perm =
n_theta_r, the limit that ties the two standards together (tests/test_thermal_speed.py).
DIN 732 writes the viscous term without the nu n < 2000 branch; here it is kept (one route to the
Palmgren torque): it matters only below nu n = 2000 mm^2/s rpm, where no thermal limit is near.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import pi

import numpy as np
from scipy.optimize import brentq

from analytic.friction.palmgren import palmgren_load_torque_Nmm, palmgren_viscous_torque_Nmm
from analytic.torque import power_W

#: ISO 15312:2018 reference conditions (radial bearings)
REFERENCE_BEARING_TEMPERATURE_C = 70.0
REFERENCE_AMBIENT_TEMPERATURE_C = 20.0
REFERENCE_VISCOSITY_MM2_S = 12.0           # ISO VG 32 at 70 C
REFERENCE_LOAD_FRACTION_OF_C0 = 0.05       # P1r = 0.05 C0r
REFERENCE_HEAT_FLOW_DENSITY_W_PER_MM2 = 16e-3   # 16 kW/m^2
REFERENCE_SURFACE_LIMIT_MM2 = 50_000.0
REFERENCE_SURFACE_EXPONENT = -0.34
#: above this speed a heat balance is called unbounded (no thermal limit): 1e9 rpm
MAX_SPEED_RPM = 1e9


@dataclass(frozen=True)
class ThermalReference:
    """ISO 15312 thermal reference speed of one bearing and the reference quantities it used.
    speed_rpm: n_theta_r; surface_mm2: A_r; heat_flow_density_W_per_mm2: q_r; heat_W: Q_r = q_r A_r;
    load_N: P1r; viscous_torque_Nmm, load_torque_Nmm: M0r, M1r at n_theta_r."""
    speed_rpm: float
    surface_mm2: float
    heat_flow_density_W_per_mm2: float
    heat_W: float
    load_N: float
    viscous_torque_Nmm: float
    load_torque_Nmm: float


@dataclass(frozen=True)
class ThermalPermissible:
    """DIN 732 thermally permissible speed, arrays over operating points. speed_rpm: n_perm;
    speed_ratio: f_n = n_perm / n_theta_r; K_L, K_P: the standard's viscous and load shares of the
    heat balance at n_theta_r (K_L f_n^(5/3) + K_P f_n = 1); heat_W: the heat given off, Q."""
    speed_rpm: np.ndarray
    speed_ratio: np.ndarray
    K_L: np.ndarray
    K_P: np.ndarray
    heat_W: np.ndarray


def reference_surface_mm2(bore_mm: float, outside_diameter_mm: float, width_mm: float) -> float:
    """Reference heat-emitting surface of a radial bearing A_r = pi B (D + d), mm^2
    (ISO 15312:2018; DIN 732: the bearing seat surface A_S of a radial bearing, the same area)."""
    return pi * width_mm * (outside_diameter_mm + bore_mm)


def reference_heat_flow_density_W_per_mm2(surface_mm2):
    """Reference heat flow density of a radial bearing, W/mm^2 (ISO 15312:2018): 16 kW/m^2 up to
    A_r = 50 000 mm^2, 16 (A_r / 50 000)^-0.34 kW/m^2 above (continuous at 50 000 mm^2)."""
    a = np.asarray(surface_mm2, float)
    return REFERENCE_HEAT_FLOW_DENSITY_W_PER_MM2 * np.minimum(
        1.0, (a / REFERENCE_SURFACE_LIMIT_MM2) ** REFERENCE_SURFACE_EXPONENT)


def reference_heat_transfer_W_per_mm2_K(surface_mm2):
    """The heat transfer coefficient of the seat surface the reference conditions imply,
    k_q = q_r / (70 C - 20 C), W/(mm^2 K) (ISO 15312 reference: Q_r = q_r A_r at Delta T = 50 K;
    DIN 732's Q_S = k_q A_S Delta T then gives f_n = 1 at the reference state): 3.2e-4 up to
    A_r = 50 000 mm^2, inside the 0.2e-3 .. 1e-3 W/(mm^2 K) range makers quote for k_q."""
    return reference_heat_flow_density_W_per_mm2(surface_mm2) / (
        REFERENCE_BEARING_TEMPERATURE_C - REFERENCE_AMBIENT_TEMPERATURE_C)


def heat_balance_speed_rpm(f0, nu_mm2_s, dm_mm: float, load_torque_Nmm, heat_W):
    """The speed n (rpm) at which Palmgren's friction power (pi n / 30e3)(M0(n) + M1) equals the
    heat given off, Q (module docstring; M0 by `analytic.friction.palmgren.palmgren_viscous_torque_Nmm`).
    Arrays broadcast; Q <= 0 gives 0 rpm, a friction too small to reach Q below MAX_SPEED_RPM
    gives inf (no thermal limit).  f0 (-), nu (mm^2/s), dm (mm), M1 (N*mm), Q (W)."""
    f0, nu, m1, q = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                          (f0, nu_mm2_s, load_torque_Nmm, heat_W)))
    out = np.zeros(q.shape)
    for k in np.ndindex(q.shape):
        if q[k] <= 0.0:
            continue
        excess = lambda n, k=k: float(power_W(  # noqa: E731
            palmgren_viscous_torque_Nmm(f0[k], nu[k], n, dm_mm) + m1[k], n)) - q[k]
        hi = 1e3
        while excess(hi) < 0.0 and hi < MAX_SPEED_RPM:
            hi *= 4.0
        out[k] = (np.inf if excess(hi) < 0.0
                  else brentq(excess, 0.0, hi, xtol=1e-9, rtol=1e-12))
    return out


def thermal_reference_speed(bore_mm: float, outside_diameter_mm: float, width_mm: float,
                            C0_N: float, f0r: float, f1r: float,
                            surface_mm2: float | None = None) -> ThermalReference:
    """ISO 15312:2018 thermal reference speed of a radial bearing (module docstring), with
    dm = (d + D)/2, P1r = 0.05 C0r, nu_r = 12 mm^2/s and A_r = pi B (D + d) unless
    `surface_mm2` is given.  d, D, B in mm, C0 in N."""
    dm = 0.5 * (bore_mm + outside_diameter_mm)
    area = (reference_surface_mm2(bore_mm, outside_diameter_mm, width_mm)
            if surface_mm2 is None else float(surface_mm2))
    q = float(reference_heat_flow_density_W_per_mm2(area))
    P1r = REFERENCE_LOAD_FRACTION_OF_C0 * C0_N
    m1 = float(palmgren_load_torque_Nmm(f1r, P1r, dm))
    n = float(heat_balance_speed_rpm(f0r, REFERENCE_VISCOSITY_MM2_S, dm, m1, q * area))
    m0 = float(palmgren_viscous_torque_Nmm(f0r, REFERENCE_VISCOSITY_MM2_S, n, dm))
    return ThermalReference(n, area, q, q * area, P1r, m0, m1)


def dissipated_heat_W(heat_transfer_W_per_mm2_K, surface_mm2, T_bearing_C, T_ambient_C,
                      extra_W=0.0):
    """Heat a bearing gives off, W (DIN 732:2010): through its seat surface
    Q_S = k_q A_S (T_bearing - T_ambient), plus what a lubricant flow or a cooler takes away
    (Q_extra, W)."""
    return (np.asarray(heat_transfer_W_per_mm2_K, float) * surface_mm2
            * (np.asarray(T_bearing_C, float) - np.asarray(T_ambient_C, float))
            + np.asarray(extra_W, float))


def thermally_permissible_speed(reference_speed_rpm: float, f0, nu_mm2_s, dm_mm: float,
                                load_torque_Nmm, heat_W) -> ThermalPermissible:
    """DIN 732:2010 thermally permissible speed n_perm = f_n n_theta_r (module docstring):
    f_n from K_L f_n^(5/3) + K_P f_n = 1, solved as the heat balance under the actual f0 (-),
    viscosity nu (mm^2/s), load torque M1 = f1 P1 dm (N*mm, ISO/TR 14179-2) and heat given off
    Q (W).  Arrays broadcast over operating points."""
    n = heat_balance_speed_rpm(f0, nu_mm2_s, dm_mm, load_torque_Nmm, heat_W)
    nr = float(reference_speed_rpm)
    q = np.asarray(heat_W, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        w = pi * nr / 30e3
        K_L = w * 1e-7 * np.asarray(f0, float) * (np.asarray(nu_mm2_s, float) * nr) ** (2.0 / 3.0) \
            * dm_mm ** 3 / q
        K_P = w * np.asarray(load_torque_Nmm, float) / q
    return ThermalPermissible(n, n / nr, K_L, K_P, q * np.ones_like(n))
