"""thermal_lag: part temperatures follow the ambient (chamber) temperature with a first-order lag.

Physics added: the baseline puts every part without its own temperature column at `T_ambient_C`
(no lag). With this effect each such part obeys

    tau_s dT/dt = T_ambient(t) - T(t),

one lumped thermal time constant for the whole assembly (Biot number << 1 for thin rings and a
hollow shaft in a chamber). `T_ambient_C` is taken piecewise linear between the samples and the
equation is integrated exactly over each interval (no time-step error):

    s_k = (u_{k+1} - u_k) / h_k,   a_k = exp(-h_k / tau_s)
    T_{k+1} = u_{k+1} - tau_s s_k + a_k (T_k - u_k + tau_s s_k),

starting in equilibrium at the first sample (T_0 = u_0). Parts with their own measured temperature
(`PhysicsInputs.measured_parts`, flagged from the conditions table) are left as they are, even
when they read the ambient. Apply it before `radial_gradient`
(`apply_effects` does).

Parameters:
    tau_s  thermal time constant, s, bounds [0, 1e5], off 0 (no lag)

Needs: `time_s` (strictly increasing) and `T_ambient_C`.

Source / rationale: lumped-capacitance heating of a body (Incropera, Fundamentals of Heat and Mass
Transfer, ch. 5); seed 003's housing temperature rises quickly and levels off (a first-order shape);
thermal-vacuum tests of mechanisms show time constants from minutes to hours. 1e5 s (28 h) bounds
any laboratory assembly.
"""
from __future__ import annotations

import numpy as np

from .base import Effect


def lag_response(t_s: np.ndarray, u: np.ndarray, tau_s: float) -> np.ndarray:
    """Exact response of tau dy/dt = u - y to u piecewise linear between samples, y(t0) = u(t0)."""
    t = np.asarray(t_s, float)
    u = np.asarray(u, float)
    y = np.empty_like(u)
    if u.size == 0:
        return y
    if tau_s <= 0.0:
        return u.copy()
    h = np.diff(t)
    s = np.diff(u) / h
    with np.errstate(over="ignore", under="ignore"):   # tau -> 0 (an optimiser probing) is fine
        a = np.exp(-h / tau_s)
    ts = tau_s * s
    c1 = u[1:] - ts                 # particular solution at the end of each interval
    c2 = ts - u[:-1]                # T_k - u_k + tau s_k = T_k + c2
    # linear recursion with varying coefficients, on Python floats (the same IEEE double
    # operations as on numpy's scalars, without their per-element overhead)
    yk = float(u[0])
    out = [yk]
    for c1k, ak, c2k in zip(c1.tolist(), a.tolist(), c2.tolist()):
        yk = c1k + ak * (yk + c2k)
        out.append(yk)
    y[:] = out
    return y


class ThermalLag(Effect):
    name = "thermal_lag"
    parameters = ("tau_s",)
    units = {"tau_s": "s"}
    bounds = {"tau_s": (0.0, 1e5)}
    off = {"tau_s": 0.0}
    requires = ("time_s", "T_ambient_C")
    scale = {"tau_s": 60.0}
    hint = ("vary the rate of temperature change (a faster ramp or a step with a dwell: a lag "
            "grows with the rate and decays during the dwell) or measure a part temperature")

    def _apply(self, inputs, p, T_ref_C):
        amb = np.asarray(inputs.T_ambient_C, float)
        lagged = lag_response(inputs.time_s, amb, p["tau_s"])
        T = dict(inputs.T_C)
        for part in T:
            if part not in inputs.measured_parts:              # follows the ambient
                T[part] = lagged.copy()
        return inputs.copy(T_C=T)
