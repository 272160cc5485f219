"""cte_nonlinearity: the CTE of the shaft and housing material varies linearly with temperature.

Physics added: alpha(T) = alpha(T_ref) + dalpha_per_K * (T - T_ref) for the shaft and the housing
(and the nut and cover that follow them), so the thermal strain becomes
alpha(T_ref) (T - T_ref) + dalpha_per_K (T - T_ref)^2 / 2. The FE stays exact because it is linear
in the thermal strains. Titanium (TC4) and steel CTEs are not constant over -60..80 C; a wrong
slope shows up as fit and preload changes that are quadratic in temperature.

Parameters:
    dalpha_per_K  CTE slope, 1/K^2, bounds [-3e-8, 3e-8], off 0

Convention: added to `PhysicsInputs.dalpha_per_K2["shaft"]` and `["housing"]` (0 when absent).

Source / rationale: Ti-6Al-4V CTE rises from about 8.0e-6 /K at -50 C to 9.2e-6 /K at 100 C
(MMPDS; ASM handbook), i.e. about 8e-9 /K^2; martensitic steels show 3-6e-9 /K^2 near room
temperature, more when cryogenic. +-3e-8 /K^2 bounds any structural metal between -100 and 150 C.
"""
from __future__ import annotations

from .base import Effect

PARTS = ("shaft", "housing")


class CteNonlinearity(Effect):
    name = "cte_nonlinearity"
    parameters = ("dalpha_per_K",)
    units = {"dalpha_per_K": "1/K^2"}
    bounds = {"dalpha_per_K": (-3e-8, 3e-8)}
    off = {"dalpha_per_K": 0.0}
    scale = {"dalpha_per_K": 1e-9}
    hint = ("extend the temperature range on both sides of the reference temperature (the effect "
            "is quadratic in T - T_ref) or measure the fits / preload at the extremes")

    def _apply(self, inputs, p, T_ref_C):
        d = dict(inputs.dalpha_per_K2)
        for part in PARTS:
            d[part] = d[part] + p["dalpha_per_K"]
        return inputs.copy(dalpha_per_K2=d)
