"""The friction model's options (`[lubrication]` keys viscous_model, oil_quantity_mg,
shear_strength, tau0_MPa, alpha_shear) with the lubricant and bearing data the models need, as
one typed value handed to `analytic.friction.pair.pair_torque`. The default is today's law: Palmgren's
viscous term and a constant film friction coefficient."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

VISCOUS_MODELS = ("palmgren", "skf2004", "ehl_rolling", "starved", "minimal_oil")
SHEAR_STRENGTHS = ("constant", "pressure")


@dataclass(frozen=True)
class FrictionOptions:
    """viscous_model: one of VISCOUS_MODELS (oil). oil_quantity_mg: oil in one bearing, mg
    ("starved", "minimal_oil"; 0 = flooded). oil_supply_share: the inlet share of the oil's
    layer ("minimal_oil", `analytic.friction.minimal_oil`; default 1). eta_Pa_s: the oil's dynamic viscosity at the rows' temperature,
    Pa s, and alpha_per_Pa its pressure-viscosity coefficient, 1/Pa ("ehl_rolling", "starved",
    "minimal_oil"). density_kg_m3: the oil's density ("starved", "minimal_oil"). bore_mm, outside_diameter_mm: d and D of the
    bearing ("skf2004"). shear_strength: one of SHEAR_STRENGTHS (solid film), tau0_MPa and
    alpha_shear its law tau = tau0 + alpha p ("pressure")."""
    viscous_model: str = "palmgren"
    oil_quantity_mg: float = 0.0
    oil_supply_share: float = 1.0
    eta_Pa_s: np.ndarray | float = 0.0
    alpha_per_Pa: float = 0.0
    density_kg_m3: float = 0.0
    bore_mm: float = 0.0
    outside_diameter_mm: float = 0.0
    shear_strength: str = "constant"
    tau0_MPa: float = 0.0
    alpha_shear: float = 0.0

    def __post_init__(self):
        if self.viscous_model not in VISCOUS_MODELS:
            raise ValueError(f"viscous_model must be one of {VISCOUS_MODELS}, "
                             f"got {self.viscous_model!r}")
        if self.shear_strength not in SHEAR_STRENGTHS:
            raise ValueError(f"shear_strength must be one of {SHEAR_STRENGTHS}, "
                             f"got {self.shear_strength!r}")
