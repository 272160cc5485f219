"""Torque stage: the friction torque of the pair (`analytic.friction.pair.pair_torque` ->
`TorqueComponents`) with the assembly's lubrication.

Solid film: the film friction coefficient of the row and the hysteresis loss factor. Oil: the
viscosity of the configured lubricant (ASTM D341 fit of its datasheet points, slope scaled by the
viscosity_temperature effect) at the mean of the ring and ball temperatures, Palmgren's f0 (the
assembly's or a run's), the load term as configured; with load_term "palmgren", f1 = 0.001
(P0/C0)^0.33 (Palmgren 1959) with C0 from ISO 76 and P0 the axial force of the more loaded
bearing (a pure axial preload). The friction model's options (`[lubrication] viscous_model`,
`oil_quantity_mg`, `shear_strength`, `tau0_MPa`, `alpha_shear`; analytic/friction/) with the
oil's dynamic viscosity (its density) and pressure-viscosity coefficient and the bearing's bore
and outside diameter. Units N, mm, rpm, mm^2/s, C.
"""
from __future__ import annotations

import numpy as np

from analytic.bearing import BearingGeometry, PairState
from analytic.friction.options import FrictionOptions
from analytic.lubrication import dynamic_viscosity_Pa_s
from analytic.safety import static_load_rating_C0_N
from analytic.friction.pair import TorqueComponents, pair_torque
from analytic.friction.palmgren import palmgren_f1_angular_contact
from studies.model.inputs import PhysicsInputs


def pair_friction_torque(asm, geom: BearingGeometry, lubricant, pair: PairState,
                         inputs: PhysicsInputs, mu: np.ndarray,
                         viscous_factor_f0=None) -> TorqueComponents:
    """Friction torque of the pair at the rows' speeds and temperatures (see the module
    docstring). asm: the `studies.model.config.Assembly`; lubricant: the oil's `analytic.lubrication` lubricant (None for a solid film);
    mu: friction coefficient per row (-); viscous_factor_f0: Palmgren's f0 in place of the
    assembly's (scalar or per row)."""
    lub = asm.lubrication
    speed = np.asarray(inputs.speed_rpm, float)
    if lub.kind == "solid_film":
        return pair_torque(geom, pair, model="solid_film", mu=mu,
                           hysteresis_loss=lub.hysteresis_loss_factor, speed_rpm=speed,
                           friction=friction_options(lub, None, asm.bearing, None))
    T_oil = (np.asarray(inputs.T_C["inner_ring"], float) + inputs.T_C["outer_ring"]
             + inputs.T_C["ball"]) / 3.0
    nu = lubricant.nu_mm2_s(T_oil, slope_factor=inputs.viscosity_slope_factor)
    f1 = None
    if lub.load_term == "palmgren":
        C0 = static_load_rating_C0_N(geom.Z, geom.Dw_mm, geom.dm_mm, geom.alpha0_deg)
        P0 = pair.axial_force_N.max(axis=0)
        f1 = palmgren_f1_angular_contact(P0, C0)
    return pair_torque(geom, pair, model="oil", mu=mu, speed_rpm=speed,
                       f0=lub.viscous_factor_f0 if viscous_factor_f0 is None else viscous_factor_f0,
                       nu_mm2_s=nu, load_term=lub.load_term, f1=f1,
                       friction=friction_options(lub, lubricant, asm.bearing, nu))


def friction_options(lub, lubricant, spec, nu_mm2_s) -> FrictionOptions:
    """The friction law's options (`analytic.friction.options.FrictionOptions`) of a
    `[lubrication]` section `lub` with its oil `lubricant` (None for a solid film) at the
    kinematic viscosity nu_mm2_s (per row): the oil's dynamic viscosity (its density), its
    pressure-viscosity coefficient, density and family (mineral / synthetic), the bearing
    `spec`'s bore and outside diameter, the lubrication method and a bath's oil level. The one place `simulate` and `bearing` turn the file's keys into the law."""
    if lub.kind == "solid_film":
        return FrictionOptions(shear_strength=lub.shear_strength, tau0_MPa=lub.tau0_MPa,
                               alpha_shear=lub.alpha_shear)
    return FrictionOptions(viscous_model=lub.viscous_model, oil_quantity_mg=lub.oil_quantity_mg,
                           eta_Pa_s=dynamic_viscosity_Pa_s(nu_mm2_s, lubricant.density_kg_m3),
                           alpha_per_Pa=lubricant.alpha_per_Pa,
                           density_kg_m3=lubricant.density_kg_m3, bore_mm=spec.bore_mm,
                           outside_diameter_mm=spec.outside_diameter_mm,
                           lubrication_method=lub.lubrication_method,
                           oil_level_mm=lub.oil_level_mm, oil_family=lubricant.oil_family)
