"""thermal_lag.series: generalised thermal_lag in which the heat reaches the shaft side THROUGH
the housing side (two first-order lags in series).

Physics added: the listed `thermal_lag` lets every ambient-following part exchange heat with the
chamber directly, with one time constant. In a chamber (and more so in vacuum) a shaft sees the
chamber mainly through the housing: heat flows chamber -> housing, outer ring -> balls -> inner
ring -> shaft. A two-node lumped network with the housing side loaded only by the chamber (its
heat capacity large against the shaft side's, so the shaft side does not load it) gives

    tau_s       dT_h/dt = T_ambient - T_h   for the housing, the outer ring and the spacers,
    tau_shaft_s dT_r/dt = T_h       - T_r   for the shaft, the inner ring and the balls,

with tau = C / G per node (heat capacity over the conductance to the node it exchanges with).
Unlike two parallel lags (`thermal_lag.per_part`) the shaft side's response is of second order:
it starts with zero slope after a change of the chamber's rate, and on a ramp of rate a the
housing side trails by a tau_s and the shaft side by a (tau_s + tau_shaft_s) (delays of lags in
series add), so the housing-to-shaft difference on a ramp is -a tau_shaft_s.

Integration: `T_ambient_C` piecewise linear between the samples, both nodes exact over each
interval (no time-step error), starting in equilibrium at the first sample. The housing side is
the listed form's own integrator (`thermal_lag.lag_response`); the shaft side, over an interval
of length h with ambient slope s (particular solutions u - tau_s s and u - (tau_s + tau_shaft_s) s,
homogeneous modes exp(-t/tau_s) and exp(-t/tau_shaft_s)):

    d_h = T_h,k - u_k + tau_s s,   d_r = T_r,k - u_k + (tau_s + tau_shaft_s) s,
    T_r,k+1 = u_k+1 - (tau_s + tau_shaft_s) s + d_r exp(-h/tau_shaft_s) + d_h g,
    g = tau_s (exp(-h/tau_s) - exp(-h/tau_shaft_s)) / (tau_s - tau_shaft_s)
      = (h/tau_shaft_s) exp(-h/tau_shaft_s) expm1(x)/x,   x = h (1/tau_shaft_s - 1/tau_s),

the second expression free of cancellation at tau_s ~ tau_shaft_s (g -> (h/tau) exp(-h/tau)).
Parts with their own measured temperature are left as they are (a measured housing does not
drive the shaft side here: the form stays the listed effect's generalisation, which lags from
the chamber only).

Parameters:
    tau_s        housing side from the chamber, s, bounds [0, 1e5], off 0 (the listed parameter)
    tau_shaft_s  shaft side from the housing side, s, bounds [0, 1e5], off 0

Reduces to `thermal_lag` with tau_s exactly at tau_shaft_s = 0 (the shaft side is then the
housing side: the same integrator runs on the same inputs). Needs `time_s` and `T_ambient_C`.

Source / rationale: lumped capacitance per body, tau = rho c V / (h A) (Incropera & DeWitt,
Fundamentals of Heat and Mass Transfer, ch. 5.1-5.3); lumped thermal networks of bearing
assemblies, nodes linked by conductances (Harris & Kotzalas, Rolling Bearing Analysis, 5th ed.,
Vol. 2, ch. 4 "Heat generation and thermal networks"; Gilmore, Spacecraft Thermal Control
Handbook, ch. 15 on thermal network models). Series first-order systems: Ogata, Modern Control
Engineering, ch. 5 (step response 1 - (t1 e^{-t/t1} - t2 e^{-t/t2}) / (t1 - t2)).
"""
from __future__ import annotations

import numpy as np

from .thermal_lag import lag_response
from .thermal_lag_per_part import TwoSidedLag, two_sided

#: |x| = h |1/tau_shaft - 1/tau| above which g is evaluated as a difference of exponentials
#: (no cancellation there; below, expm1(x)/x avoids it)
_X_DIRECT = 1.0


def series_lag_response(t_s: np.ndarray, u: np.ndarray, tau_s: float,
                        tau_shaft_s: float) -> tuple[np.ndarray, np.ndarray]:
    """(T_h, T_r): exact responses of tau_s dT_h/dt = u - T_h and tau_shaft_s dT_r/dt = T_h - T_r
    to u piecewise linear between samples, both in equilibrium at the first sample (module
    docstring). tau_shaft_s = 0 gives T_r = T_h; tau_s = 0 gives T_h = u."""
    t = np.asarray(t_s, float)
    u = np.asarray(u, float)
    Th = lag_response(t, u, tau_s)
    if tau_shaft_s <= 0.0 or u.size == 0:
        return Th, Th.copy()
    if tau_s <= 0.0:
        return Th, lag_response(t, u, tau_shaft_s)
    h = np.diff(t)
    s = np.diff(u) / h
    with np.errstate(over="ignore", under="ignore"):
        e_h = np.exp(-h / tau_s)
        e_r = np.exp(-h / tau_shaft_s)
        x = h * (1.0 / tau_shaft_s - 1.0 / tau_s)
        small = np.abs(x) < _X_DIRECT
        xs = np.where(small & (x != 0.0), x, 1.0)
        phi = np.where(x == 0.0, 1.0, np.expm1(xs) / xs)
        g_small = (h / tau_shaft_s) * e_r * phi
        d = tau_s - tau_shaft_s
        g_direct = tau_s * (e_h - e_r) / np.where(small, 1.0, d)
    g = np.where(small, g_small, g_direct)
    ts = (tau_s + tau_shaft_s) * s
    Tr = np.empty_like(u)
    # the recursion on Python floats (the same IEEE double operations as on numpy's scalars)
    uu, ss, tss, ee, gg, hh = (v.tolist() for v in (u, s, ts, e_r, g, Th))
    y = uu[0]
    out = [y]
    for k in range(h.size):
        dh = hh[k] - uu[k] + tau_s * ss[k]
        dr = y - uu[k] + tss[k]
        y = uu[k + 1] - tss[k] + dr * ee[k] + dh * gg[k]
        out.append(y)
    Tr[:] = out
    return Th, Tr


class ThermalLagSeries(TwoSidedLag):
    form = "series"
    name = "thermal_lag.series"
    label = "shaft side lagging behind the housing side (two lags in series)"
    reduces = {"tau_shaft_s": 0.0}

    def _apply(self, inputs, p, T_ref_C):
        amb = np.asarray(inputs.T_ambient_C, float)
        return two_sided(inputs, *series_lag_response(inputs.time_s, amb, p["tau_s"],
                                                      p["tau_shaft_s"]))

    def text(self, params):
        return (f"thermal_lag, shaft side through the housing side: housing {params['tau_s']:.0f} "
                f"s from the chamber, shaft {params['tau_shaft_s']:.0f} s from the housing")
