"""friction_temperature.exponential: generalised friction_temperature, a friction law whose slope
in temperature changes exponentially (a thermally activated, Arrhenius-type law).

Physics added: the listed `friction_temperature` gives the friction coefficient a constant slope
in the ring temperature. Boundary and solid-film friction is thermally activated: the shear
strength of the film follows an Arrhenius (Eyring) law, tau ~ exp(E / (k_B T)), so the friction
coefficient falls with temperature at a rate that is itself largest in the cold (MoS2 films in
vacuum: friction rises by about x1.5 from 20 to -100 C). Linearising 1/T about T_ref gives
mu ~ exp(-b (T - T_ref)) with b = E / (k_B T_ref^2) (T_ref in kelvin). The form keeps the listed
slope at T_ref and lets the slope change exponentially:

    dmu/dT = dmu_per_K exp(-b_per_K (T_rings - T_ref)),
    mu(T)  = mu_config + dmu_per_K (1 - exp(-b_per_K x)) / b_per_K
           = mu_config + dmu_per_K x exprel(-b_per_K x),        x = T_rings - T_ref,

with T_rings the mean of the inner- and outer-ring temperatures of the row and exprel(z) =
(exp(z) - 1) / z (`scipy.special.exprel`, exactly 1 at z = 0: no division by b). A pure
exponential law mu_config exp(-b x) is the member dmu_per_K = -b mu_config; a constant part of
the friction (mu_config - dmu_per_K / b) is allowed beside it. b_per_K > 0: the slope is
steepest in the cold (Arrhenius); b_per_K < 0: steepest in the heat. The coefficient is clipped
at 0 by the pipeline (`resolve_friction_coefficient`), as the listed form's.

Parameters:
    dmu_per_K  slope of the friction coefficient at T_ref, 1/K, bounds [-1e-3, 1e-3], off 0
               (the listed parameter)
    b_per_K    exponential rate of the slope, 1/K, bounds [-0.03, 0.03], off 0

Reduces to `friction_temperature` exactly at b_per_K = 0 (exprel(0) = 1: the same product
dmu_per_K x is added). Convention: written into `PhysicsInputs.friction_coefficient` as the
change from the config's coefficient, as the listed form.

Source / rationale: thermally activated shear of boundary films, tau = tau_0 exp(E / (k_B T))
(Eyring model; Briscoe & Evans, Proc. R. Soc. Lond. A 380 (1982) 389-407); MoS2 friction about
x1.5 from 20 to -100 C in vacuum (Roberts, Tribology International 23 (1990) 95-104), i.e.
b = ln 1.5 / 120 K = 3.4e-3 /K; temperature dependence of MoS2 friction reviewed in
Vazirisereshk et al., Lubricants 7 (2019) 57, sec. 5. Bounds: |b_per_K| <= 0.03 /K is an
activation energy of 0.22 eV at 293 K (b = E / (k_B T^2)), about 9 x the rate of Roberts' data;
over -60..80 C (x from -80 to +60 K) it lets the slope change by a factor up to exp(2.4) = 11.
"""
from __future__ import annotations

import numpy as np
from scipy.special import exprel

from .base import GeneralisedForm
from .friction_temperature import FrictionTemperature, ring_temperature


class FrictionTemperatureExponential(GeneralisedForm):
    family = "friction_temperature"
    form = "exponential"
    name = "friction_temperature.exponential"
    label = "exponential (Arrhenius-type) temperature law"
    parameters = ("dmu_per_K", "b_per_K")
    extra = ("b_per_K",)
    reduces = {"b_per_K": 0.0}
    units = {"dmu_per_K": "1/K", "b_per_K": "1/K"}
    bounds = {"dmu_per_K": FrictionTemperature.bounds["dmu_per_K"], "b_per_K": (-0.03, 0.03)}
    off = {"dmu_per_K": 0.0, "b_per_K": 0.0}
    scale = {"dmu_per_K": FrictionTemperature.scale["dmu_per_K"], "b_per_K": 1e-3}
    hint = FrictionTemperature.hint + "; measure the torque at more temperatures in the cold"

    def _apply(self, inputs, p, T_ref_C):
        x = ring_temperature(inputs) - T_ref_C
        d = p["dmu_per_K"] * (x * exprel(-p["b_per_K"] * x))
        return inputs.copy(friction_coefficient=np.asarray(inputs.friction_coefficient, float) + d)

    def text(self, params):
        return (f"friction_temperature, exponential law: slope {params['dmu_per_K']:.3g} 1/K at "
                f"T_ref, rate {params['b_per_K']:.3g} 1/K")
