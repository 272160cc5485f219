"""Static safety of ball bearings and the lubrication-film check, for reports and the per-row
checks of studies/model/checks.py (which apply the limits below to every operating point).

- static safety: s0 = C0 / P0 (ISO 76:2006 clause 3.6 and GB/T 28878.2-2016 Annex B.4 eq. B.6)
  against a required value. GB/T 28878.2 eq. B.7 forms the requirement from a launch-environment
  safety factor "generally 3" and an overload amplification factor K; the product 3 K is our
  reading of the (garbled) equation, the factor that amplifies the load raising the requirement.
- film_parameter: lambda >= 1 for oil-lubricated bearings (GB/T 28878.2 Annex B.1: lambda < 1 is
  boundary lubrication); not applicable to solid-film bearings. Reported at the worst point.

Basic static radial load rating of radial and angular-contact ball bearings (ISO 76:2006, 6.1.1):
    C0r = f0 i Z Dw^2 cos(alpha)
with f0 from ISO 76 Table 1 (raceway groove radii <= 0.52 Dw inner, <= 0.53 Dw outer), linearly
interpolated in gamma = Dw cos(alpha) / Dpw. The table corresponds to a Hertz contact pressure of
4200 MPa at the most loaded contact with Q_max = 5 F_r / (Z cos alpha) (ISO/TR 10657); the test
suite checks this with an exact Hertz calculation.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# ISO 76:2006 Table 1, radial and angular contact ball bearings: gamma = Dw cos(a)/Dpw -> f0
_F0_GAMMA = np.round(np.arange(0.0, 0.4001, 0.01), 2)
_F0_VALUES = np.array([
    14.7, 14.9, 15.1, 15.3, 15.5, 15.7, 15.9, 16.1, 16.3, 16.5,
    16.4, 16.1, 15.9, 15.6, 15.4, 15.2, 14.9, 14.7, 14.4, 14.2,
    14.0, 13.7, 13.5, 13.2, 13.0, 12.8, 12.5, 12.3, 12.1, 11.8,
    11.6, 11.4, 11.2, 10.9, 10.7, 10.5, 10.3, 10.0, 9.8, 9.6, 9.4])

# ISO 76:2006 Table 3 (single-row angular contact ball bearings): X0 = 0.5, Y0 by contact angle
_Y0_ALPHA_DEG = np.array([15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0])
_Y0_VALUES = np.array([0.46, 0.42, 0.38, 0.33, 0.29, 0.26, 0.22])

ISO76_CONTACT_PRESSURE_MPa = 4200.0   # ball bearings, ISO 76:2006 clause 3.1
GBT_LAUNCH_SAFETY = 3.0               # GB/T 28878.2-2016 B.4: "generally 3"


@dataclass(frozen=True)
class SafetyFlag:
    """One check: `value` of the worst operating point against `limit`; ok is False when the
    limit is violated. `worst_index` is the row of the worst value (None for a scalar)."""
    name: str
    value: float
    limit: float
    ok: bool
    message: str
    unit: str = ""
    worst_index: int | None = None


def iso76_f0(gamma):
    """f0 of ISO 76:2006 Table 1 (radial and angular-contact ball bearings), linear interpolation
    in gamma = Dw cos(alpha) / Dpw; ValueError outside 0..0.4 (the table's range)."""
    g = np.asarray(gamma, float)
    if np.any(g < 0) or np.any(g > 0.4 + 1e-12):
        raise ValueError("gamma = Dw cos(alpha)/Dpw must lie in [0, 0.4] (ISO 76 Table 1)")
    return np.interp(g, _F0_GAMMA, _F0_VALUES)


def static_load_rating_C0_N(n_balls, ball_diameter_mm, pitch_diameter_mm, contact_angle_deg=0.0,
                            rows: int = 1):
    """Basic static radial load rating C0r = f0 i Z Dw^2 cos(alpha), N (ISO 76:2006 eq. 1;
    Dw in mm). For groove radii <= 0.52 Dw (inner) and <= 0.53 Dw (outer)."""
    c = np.cos(np.radians(contact_angle_deg))
    Dw = np.asarray(ball_diameter_mm, float)
    gamma = Dw * c / np.asarray(pitch_diameter_mm, float)
    return iso76_f0(gamma) * rows * np.asarray(n_balls) * Dw**2 * c


def static_equivalent_load_P0_N(radial_N, axial_N, contact_angle_deg):
    """Static equivalent radial load of a single-row ball bearing (ISO 76:2006 6.2):
    P0 = max(Fr, X0 Fr + Y0 Fa) with X0 = 0.6, Y0 = 0.5 for alpha = 0 (deep groove) and
    X0 = 0.5, Y0 from Table 3 (interpolated between 15 and 45 deg) for angular contact."""
    Fr = np.asarray(radial_N, float)
    Fa = np.asarray(axial_N, float)
    a = float(contact_angle_deg)
    if a == 0.0:
        X0, Y0 = 0.6, 0.5
    elif 15.0 <= a <= 45.0:
        X0, Y0 = 0.5, float(np.interp(a, _Y0_ALPHA_DEG, _Y0_VALUES))
    else:
        raise ValueError("ISO 76 Table 3 covers alpha = 0 or 15..45 deg")
    return np.maximum(Fr, X0 * Fr + Y0 * Fa)


def static_safety_factor(C0_N, P0_N):
    """s0 = C0 / P0 (ISO 76:2006 3.6; GB/T 28878.2-2016 eq. B.6)."""
    return np.asarray(C0_N, float) / np.asarray(P0_N, float)


def static_safety_from_contact_pressure(max_contact_pressure_MPa,
                                        reference_MPa: float = ISO76_CONTACT_PRESSURE_MPa):
    """s0 from the computed Hertz pressure of the most loaded contact: the load scales as p^3 in
    Hertz contact, so s0 = (4200 MPa / p_max)^3 (ISO 76 basis). Useful when the actual (preloaded,
    combined) ball loads are known from the pair model rather than an equivalent load."""
    return (reference_MPa / np.asarray(max_contact_pressure_MPa, float)) ** 3


def required_static_safety(launch_factor: float = GBT_LAUNCH_SAFETY,
                           overload_factor_K: float = 1.0) -> float:
    """Required s0 per GB/T 28878.2-2016 eq. B.7 as read here: launch-environment safety factor
    (generally 3) times the overload amplification factor K (see module docstring)."""
    return float(launch_factor) * float(overload_factor_K)


def film_parameter_flag(film_parameter, minimum: float = 1.0) -> SafetyFlag:
    """film_parameter: not ok when the smallest lambda is below `minimum` (boundary lubrication,
    GB/T 28878.2 Annex B.1); reports the worst point and its row (0-based)."""
    a = np.asarray(film_parameter, float)
    i = None if a.ndim == 0 else int(np.nanargmin(a))
    v = float(a) if i is None else float(a.flat[i])
    ok = v >= minimum
    where = "" if i is None else f" (worst at row {i + 1})"
    msg = (f"film parameter lambda = {v:.3g} >= {minimum:g}" if ok else
           f"FILM PARAMETER lambda = {v:.3g} below {minimum:g} (boundary lubrication){where}")
    return SafetyFlag("film_parameter", v, float(minimum), ok, msg, "", i)
