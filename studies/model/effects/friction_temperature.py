"""friction_temperature: the friction coefficient varies with temperature.

Physics added: the (load-dependent, sliding) friction coefficient becomes

    mu(T) = mu_config + dmu_per_K * (T_rings - T_ref)

with T_rings the mean of the inner- and outer-ring temperatures of the row. MoS2 films in vacuum
and boundary-lubricated contacts change their friction coefficient with temperature (water
desorption, film shear strength, additive activity). The coefficient is clipped at 0 by the
pipeline (`resolve_friction_coefficient`).

Parameters:
    dmu_per_K  slope of the friction coefficient, 1/K, bounds [-1e-3, 1e-3], off 0

Convention: written into `PhysicsInputs.friction_coefficient` as the *change* from the config's
coefficient per row (added to any change already present), see `studies.model.effects`.

Source / rationale: sputtered MoS2 friction coefficients of 0.01-0.05 change by tens of percent over
-60..80 C (ESTL / ESA tribology handbook data); seed 001 quotes mu = 0.0029 at 20 C for an oil. A
slope of 1e-3 /K would move mu by 0.14 over 140 K, which bounds any of these.
"""
from __future__ import annotations

import numpy as np

from .base import Effect


def ring_temperature(inputs) -> np.ndarray:
    """T_rings (C) per row: the mean of the inner- and outer-ring temperatures."""
    return 0.5 * (np.asarray(inputs.T_C["inner_ring"], float)
                  + np.asarray(inputs.T_C["outer_ring"], float))


class FrictionTemperature(Effect):
    name = "friction_temperature"
    parameters = ("dmu_per_K",)
    units = {"dmu_per_K": "1/K"}
    bounds = {"dmu_per_K": (-1e-3, 1e-3)}
    off = {"dmu_per_K": 0.0}
    scale = {"dmu_per_K": 1e-5}
    hint = ("measure the preload beside the torque (friction changes the torque only), or run the "
            "temperature series at a second preload (the friction torque scales with the load)")

    def _apply(self, inputs, p, T_ref_C):
        d = p["dmu_per_K"] * (ring_temperature(inputs) - T_ref_C)
        return inputs.copy(friction_coefficient=np.asarray(inputs.friction_coefficient, float) + d)
