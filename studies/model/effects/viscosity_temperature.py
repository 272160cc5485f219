"""viscosity_temperature: the lubricant's viscosity-temperature law differs from the nominal one.

Physics added: the slope B of the Walther (ASTM D341) line log10 log10(nu + 0.7) = A - B log10(T_K)
is multiplied by `slope_factor`, keeping the viscosity at the reference point of the lubricant
data (the pipeline's choice, normally 40 C) fixed. A factor above 1 makes the oil thicken faster
when cold (the typical failure of a two-point 40/100 C Walther fit at -40..-54 C, see the
`lubricant_viscosity` study); below 1 the opposite. Only the viscous torque and the film thickness
feel it; solid-film (MoS2) bearings do not.

Parameters:
    slope_factor  multiplies the Walther slope, dimensionless, bounds [0.3, 3], off 1

Convention: written into `PhysicsInputs.viscosity_slope_factor` (multiplying any factor present).

Source / rationale: ASTM D341; measured low-temperature viscosities of space oils (Pennzane SHF
X-2000 at -40 C, Brayco 815Z at -54 C) deviate from two-point Walther extrapolations by factors that
correspond to slope changes of tens of percent; [0.3, 3] bounds any mineral, PAO, ester, MAC or PFPE
oil.
"""
from __future__ import annotations

from .base import Effect


class ViscosityTemperature(Effect):
    name = "viscosity_temperature"
    parameters = ("slope_factor",)
    units = {"slope_factor": "-"}
    bounds = {"slope_factor": (0.3, 3.0)}
    off = {"slope_factor": 1.0}
    scale = {"slope_factor": 0.1}
    hint = ("repeat at a second speed (the viscous torque grows with speed, the load-dependent "
            "friction does not) or measure the oil's viscosity at the test temperatures")

    def _apply(self, inputs, p, T_ref_C):
        return inputs.copy(viscosity_slope_factor=inputs.viscosity_slope_factor * p["slope_factor"])
