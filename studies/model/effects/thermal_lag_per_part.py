"""thermal_lag.per_part: generalised thermal_lag, one time constant for the housing side and one
for the shaft side of the assembly.

Physics added: the listed `thermal_lag` gives every ambient-following part the same lumped time
constant. Parts of very different mass and surface (a thick housing flange against a hollow
shaft reached only through its ends and the balls) heat at different rates: each group obeys its
own first-order law

    tau_s       dT/dt = T_ambient - T   for the housing, the outer ring and the spacers,
    tau_shaft_s dT/dt = T_ambient - T   for the shaft, the inner ring and the balls,

integrated exactly for a piecewise linear ambient (`thermal_lag.lag_response`, the listed form's
own integrator). Parts with their own measured temperature are left as they are.

Parameters:
    tau_s        housing-side time constant, s, bounds [0, 1e5], off 0 (the listed parameter)
    tau_shaft_s  shaft-side time constant, s, bounds [0, 1e5], off 0

Reduces to `thermal_lag` with tau_s exactly at tau_shaft_s = tau_s (the same integrator runs on
the same inputs). Needs `time_s` and `T_ambient_C`.

Source / rationale: lumped capacitance per body, tau = rho c V / (h A) (Incropera, Fundamentals of
Heat and Mass Transfer, ch. 5): a part's time constant scales with its volume-to-surface ratio and
its contact conductances, so housing and shaft differ by factors of 2-3 in thermal-vacuum and
chamber tests of mechanisms (housing 900 s, shaft 2400 s).
"""
from __future__ import annotations

import numpy as np

from .base import GeneralisedForm
from .thermal_lag import ThermalLag, lag_response

SHAFT_SIDE = ("shaft", "inner_ring", "ball")


def two_sided(inputs, T_housing_C: np.ndarray, T_shaft_C: np.ndarray):
    """`inputs` with every part that follows the ambient (no measured temperature of its own) at
    `T_shaft_C` on the shaft side (SHAFT_SIDE) and at `T_housing_C` elsewhere, C per row."""
    T = dict(inputs.T_C)
    for part in T:
        if part not in inputs.measured_parts:
            T[part] = np.array(T_shaft_C if part in SHAFT_SIDE else T_housing_C, float)
    return inputs.copy(T_C=T)


class TwoSidedLag(GeneralisedForm):
    """What the lag forms with a housing-side and a shaft-side time constant share (parameters,
    units, bounds, needs); each form says how the two sides follow the ambient."""
    family = "thermal_lag"
    parameters = ("tau_s", "tau_shaft_s")
    extra = ("tau_shaft_s",)
    units = {"tau_s": "s", "tau_shaft_s": "s"}
    bounds = {"tau_s": (0.0, 1e5), "tau_shaft_s": (0.0, 1e5)}
    off = {"tau_s": 0.0, "tau_shaft_s": 0.0}
    requires = ("time_s", "T_ambient_C")
    scale = {"tau_s": 60.0, "tau_shaft_s": 60.0}
    hint = ThermalLag.hint + "; measure the shaft (inner ring) and housing temperatures apart"


class ThermalLagPerPart(TwoSidedLag):
    form = "per_part"
    name = "thermal_lag.per_part"
    label = "per-part time constants"
    reduces = {"tau_shaft_s": "tau_s"}

    def _apply(self, inputs, p, T_ref_C):
        amb = np.asarray(inputs.T_ambient_C, float)
        lagged = {tau: lag_response(inputs.time_s, amb, tau)
                  for tau in {p["tau_s"], p["tau_shaft_s"]}}
        return two_sided(inputs, lagged[p["tau_s"]], lagged[p["tau_shaft_s"]])

    def text(self, params):
        return (f"thermal_lag, per-part time constants: housing {params['tau_s']:.0f} s, "
                f"shaft {params['tau_shaft_s']:.0f} s")
