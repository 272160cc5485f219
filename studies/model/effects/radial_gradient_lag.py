"""radial_gradient.lag: generalised radial_gradient, whose speed-driven part builds up with its own
time constant after every speed change.

Physics added: the listed `radial_gradient` adds dT_K + dT_per_krpm_K * n/1000 to the shaft, inner
ring and balls at once. The frictional heat reaches its steady gradient only after the inner parts
have warmed up: the speed part follows the speed through a first-order lag,

    tau_gradient_s dG/dt = dT_per_krpm_K * n(t)/1000 - G,   dT = dT_K + G,

integrated exactly for a piecewise linear speed history (`thermal_lag.lag_response`), starting in
equilibrium at the first sample.

Parameters:
    dT_K            constant part, K, bounds [-10, 30], off 0 (listed)
    dT_per_krpm_K   steady speed part, K per 1000 rpm, bounds [0, 10], off 0 (listed)
    tau_gradient_s  time constant of the speed part, s, bounds [0, 1e5], off 0

Reduces to `radial_gradient` exactly at tau_gradient_s = 0 (`lag_response` returns the input
itself). Needs `time_s` (strictly increasing) and a speed that changes.

Source / rationale: lumped thermal network of a bearing (Harris & Kotzalas, Vol. 2, heat
generation and thermal networks; seed 003's 5-node network): the inner parts' heat capacity over
the conductance to the housing gives minutes to an hour for spindle bearings.
"""
from __future__ import annotations

import numpy as np

from .base import GeneralisedForm
from .radial_gradient import INNER_PARTS, RadialGradient
from .thermal_lag import lag_response


class RadialGradientLag(GeneralisedForm):
    family = "radial_gradient"
    form = "lag"
    name = "radial_gradient.lag"
    label = "gradient with its own time constant after speed changes"
    parameters = ("dT_K", "dT_per_krpm_K", "tau_gradient_s")
    extra = ("tau_gradient_s",)
    reduces = {"tau_gradient_s": 0.0}
    units = {"dT_K": "K", "dT_per_krpm_K": "K/krpm", "tau_gradient_s": "s"}
    bounds = {"dT_K": (-10.0, 30.0), "dT_per_krpm_K": (0.0, 10.0), "tau_gradient_s": (0.0, 1e5)}
    off = {"dT_K": 0.0, "dT_per_krpm_K": 0.0, "tau_gradient_s": 0.0}
    requires = ("time_s",)
    scale = {"dT_K": 1.0, "dT_per_krpm_K": 1.0, "tau_gradient_s": 60.0}
    hint = RadialGradient.hint + "; hold each speed longer and watch the torque settle"

    def applicable(self, conditions):
        why = super().applicable(conditions)
        if why is None and ("speed_rpm" not in conditions
                            or np.ptp(np.asarray(conditions["speed_rpm"], float)) == 0):
            why = "needs a speed_rpm column that changes"
        return why

    def _apply(self, inputs, p, T_ref_C):
        # the listed form's expression with the speed replaced by its lagged value (at
        # tau_gradient_s = 0 `lag_response` returns the speed itself: the same numbers)
        n_lag = lag_response(inputs.time_s, np.asarray(inputs.speed_rpm, float), p["tau_gradient_s"])
        dT = p["dT_K"] + p["dT_per_krpm_K"] * n_lag / 1000.0
        T = dict(inputs.T_C)
        for part in INNER_PARTS:
            T[part] = np.asarray(T[part], float) + dT
        return inputs.copy(T_C=T)

    def text(self, params):
        return (f"radial_gradient, own time constant after speed changes: {params['dT_K']:.3g} K "
                f"+ {params['dT_per_krpm_K']:.3g} K/krpm, building up with "
                f"{params['tau_gradient_s']:.0f} s")
