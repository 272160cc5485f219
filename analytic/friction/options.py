"""The friction model's options (`[lubrication]` keys viscous_model, oil_quantity_mg,
lubrication_method, oil_level_mm, shear_strength, tau0_MPa, alpha_shear; the lubricant's
family) with the lubricant and bearing data the models need, as
one typed value handed to `analytic.friction.pair.pair_torque`. The default is today's law: Palmgren's
viscous term and a constant film friction coefficient."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

VISCOUS_MODELS = ("palmgren", "skf2004", "ehl_rolling", "starved", "minimal_oil")
SHEAR_STRENGTHS = ("constant", "pressure")
#: `[lubrication] lubrication_method` ("" = not stated)
LUBRICATION_METHODS = ("oil_bath", "oil_jet", "oil_air", "grease", "minimal_oil")
#: a lubricant's `family` for the SKF model's full-film coefficient
OIL_FAMILIES = ("mineral", "synthetic")


@dataclass(frozen=True)
class FrictionOptions:
    """viscous_model: one of VISCOUS_MODELS (oil). oil_quantity_mg: oil in one bearing, mg
    ("starved", "minimal_oil"; 0 = flooded). oil_supply_share: the inlet share of the oil's
    layer ("minimal_oil", `analytic.friction.minimal_oil`; default 1). eta_Pa_s: the oil's
    dynamic viscosity at the rows' temperature, Pa s, and alpha_per_Pa its pressure-viscosity
    coefficient, 1/Pa ("ehl_rolling", "starved", "minimal_oil"). density_kg_m3: the oil's
    density ("starved", "minimal_oil"). bore_mm, outside_diameter_mm: d and D of the
    bearing ("skf2004"). lubrication_method: one of LUBRICATION_METHODS or "" (not stated; the
    SKF K_rs), oil_level_mm: an oil bath's level above the lowest point of the outer raceway
    (0: no bath; the SKF drag), oil_family: one of OIL_FAMILIES (the SKF mu_EHL).
    shear_strength: one of SHEAR_STRENGTHS (solid film), tau0_MPa and alpha_shear its law
    tau = tau0 + alpha p ("pressure")."""
    viscous_model: str = "palmgren"
    oil_quantity_mg: float = 0.0
    oil_supply_share: float = 1.0
    eta_Pa_s: np.ndarray | float = 0.0
    alpha_per_Pa: float = 0.0
    density_kg_m3: float = 0.0
    bore_mm: float = 0.0
    outside_diameter_mm: float = 0.0
    lubrication_method: str = ""
    oil_level_mm: float = 0.0
    oil_family: str = "mineral"
    shear_strength: str = "constant"
    tau0_MPa: float = 0.0
    alpha_shear: float = 0.0

    def __post_init__(self):
        if self.viscous_model not in VISCOUS_MODELS:
            raise ValueError(f"viscous_model must be one of {VISCOUS_MODELS}, "
                             f"got {self.viscous_model!r}")
        if self.lubrication_method not in ("", *LUBRICATION_METHODS):
            raise ValueError(f"lubrication_method must be one of {LUBRICATION_METHODS}, "
                             f"got {self.lubrication_method!r}")
        if self.oil_family not in OIL_FAMILIES:
            raise ValueError(f"oil family must be one of {OIL_FAMILIES}, got {self.oil_family!r}")
        if self.viscous_model in ("ehl_rolling", "starved") and not (
                np.all(np.asarray(self.eta_Pa_s) > 0) and self.alpha_per_Pa > 0):
            raise ValueError(f"viscous_model {self.viscous_model!r} needs the oil's dynamic "
                             f"viscosity eta_Pa_s > 0 and pressure-viscosity coefficient "
                             f"alpha_per_Pa > 0, got {np.min(self.eta_Pa_s):g} Pa s, "
                             f"{self.alpha_per_Pa:g} 1/Pa")
        if self.viscous_model == "starved" and self.oil_quantity_mg > 0 and not self.density_kg_m3 > 0:
            raise ValueError("viscous_model 'starved' needs the oil's density_kg_m3 > 0")
        if self.viscous_model == "skf2004" and not 0 < self.bore_mm < self.outside_diameter_mm:
            raise ValueError(f"viscous_model 'skf2004' needs the bearing's bore_mm and "
                             f"outside_diameter_mm (0 < d < D), got {self.bore_mm:g}, "
                             f"{self.outside_diameter_mm:g} mm")
        if self.oil_quantity_mg < 0 or self.oil_level_mm < 0:
            raise ValueError("oil_quantity_mg and oil_level_mm must be >= 0")
        if self.tau0_MPa < 0 or not 0 <= self.alpha_shear <= 1:
            raise ValueError(f"shear strength tau = tau0 + alpha p needs tau0_MPa >= 0 and "
                             f"0 <= alpha_shear <= 1, got {self.tau0_MPa:g}, {self.alpha_shear:g}")
        if self.shear_strength not in SHEAR_STRENGTHS:
            raise ValueError(f"shear_strength must be one of {SHEAR_STRENGTHS}, "
                             f"got {self.shear_strength!r}")
