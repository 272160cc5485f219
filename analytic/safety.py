"""Safety checks of a bearing pair, returned as flags with their values (for reports).

Each check takes scalars or arrays over operating points and reports the WORST point (and its
index). Units in names: N, MPa, um, (-).

Checks:
- preload_lost: the pair's preload must stay above a minimum (default 0 N: a bearing unloaded).
- fit_open_inner / fit_open_outer: a fit pressure of 0 means the fit has opened (Lamé/FE).
- contact_pressure: maximum Hertz pressure against a configured limit (e.g. a MoS2 film limit;
  `Limits.max_contact_pressure_MPa` of the assembly config).
- static_safety: s0 = C0 / P0 (ISO 76:2006 clause 3.6 and GB/T 28878.2-2016 Annex B.4 eq. B.6)
  against a required value. GB/T 28878.2 eq. B.7 forms the requirement from a launch-environment
  safety factor "generally 3" and an overload amplification factor K; the product 3 K is our
  reading of the (garbled) equation, the factor that amplifies the load raising the requirement.
- film_parameter: lambda >= 1 for oil-lubricated bearings (GB/T 28878.2 Annex B.1: lambda < 1 is
  boundary lubrication); not applicable to solid-film bearings.

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


def _worst(x, kind: str):
    a = np.asarray(x, float)
    if a.ndim == 0:
        return float(a), None
    i = int(np.nanargmin(a) if kind == "min" else np.nanargmax(a))
    return float(a.flat[i]), i


def _where(i):
    return "" if i is None else f" (worst at row {i})"


def preload_flag(preload_N, min_preload_N: float = 0.0) -> SafetyFlag:
    """preload_lost: not ok when the smallest preload is <= min_preload_N (default 0 N: a bearing of
    the pair has unloaded, the position preload is lost)."""
    v, i = _worst(preload_N, "min")
    ok = v > min_preload_N
    msg = (f"preload {v:.4g} N stays above {min_preload_N:g} N" if ok else
           f"PRELOAD LOST: preload {v:.4g} N <= {min_preload_N:g} N{_where(i)}")
    return SafetyFlag("preload_lost", v, float(min_preload_N), ok, msg, "N", i)


def fit_open_flag(fit_pressure_MPa, which: str = "inner") -> SafetyFlag:
    """fit_open_<which>: not ok when the smallest fit pressure is 0 (the fit has opened)."""
    v, i = _worst(fit_pressure_MPa, "min")
    ok = v > 0.0
    msg = (f"{which} fit stays closed (min pressure {v:.4g} MPa)" if ok else
           f"{which.upper()} FIT OPEN: fit pressure {v:.4g} MPa{_where(i)}")
    return SafetyFlag(f"fit_open_{which}", v, 0.0, ok, msg, "MPa", i)


def contact_pressure_flag(max_contact_pressure_MPa, limit_MPa: float = np.inf) -> SafetyFlag:
    """contact_pressure: not ok when the largest Hertz pressure exceeds limit_MPa (inf: no limit)."""
    v, i = _worst(max_contact_pressure_MPa, "max")
    ok = v <= limit_MPa
    msg = (f"max contact pressure {v:.4g} MPa within the limit {limit_MPa:g} MPa" if ok else
           f"CONTACT PRESSURE {v:.4g} MPa above the limit {limit_MPa:g} MPa{_where(i)}")
    return SafetyFlag("contact_pressure", v, float(limit_MPa), ok, msg, "MPa", i)


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


def static_safety_flag(s0, required: float = GBT_LAUNCH_SAFETY) -> SafetyFlag:
    """static_safety: not ok when the smallest s0 is below the required value."""
    v, i = _worst(s0, "min")
    ok = v >= required
    msg = (f"static safety s0 = {v:.3g} >= {required:g}" if ok else
           f"STATIC SAFETY s0 = {v:.3g} below {required:g}{_where(i)}")
    return SafetyFlag("static_safety", v, float(required), ok, msg, "-", i)


def film_parameter_flag(film_parameter, minimum: float = 1.0) -> SafetyFlag:
    """film_parameter: not ok when the smallest lambda is below `minimum` (1: boundary
    lubrication, GB/T 28878.2-2016 Annex B.1)."""
    v, i = _worst(film_parameter, "min")
    ok = v >= minimum
    msg = (f"film parameter lambda = {v:.3g} >= {minimum:g}" if ok else
           f"FILM PARAMETER lambda = {v:.3g} below {minimum:g} (boundary lubrication){_where(i)}")
    return SafetyFlag("film_parameter", v, float(minimum), ok, msg, "-", i)


def evaluate_safety(*, preload_N=None, fit_pressure_inner_MPa=None, fit_pressure_outer_MPa=None,
                    max_contact_pressure_MPa=None, contact_pressure_limit_MPa: float = np.inf,
                    static_safety=None, min_static_safety: float = 0.0,
                    film_parameter=None, lubrication_kind: str = "oil",
                    min_preload_N: float = 0.0) -> list[SafetyFlag]:
    """All checks whose inputs are given (None: skipped). min_static_safety <= 0 means the
    GB/T 28878.2 default of 3 (launch factor with K = 1). The film parameter is only checked for
    lubrication_kind == 'oil'."""
    flags = []
    if preload_N is not None:
        flags.append(preload_flag(preload_N, min_preload_N))
    if fit_pressure_inner_MPa is not None:
        flags.append(fit_open_flag(fit_pressure_inner_MPa, "inner"))
    if fit_pressure_outer_MPa is not None:
        flags.append(fit_open_flag(fit_pressure_outer_MPa, "outer"))
    if max_contact_pressure_MPa is not None:
        flags.append(contact_pressure_flag(max_contact_pressure_MPa, contact_pressure_limit_MPa))
    if static_safety is not None:
        req = min_static_safety if min_static_safety > 0 else required_static_safety()
        flags.append(static_safety_flag(static_safety, req))
    if film_parameter is not None and lubrication_kind == "oil":
        flags.append(film_parameter_flag(film_parameter))
    return flags
