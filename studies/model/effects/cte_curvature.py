"""cte_nonlinearity.curvature: generalised cte_nonlinearity, a CTE with a second-order term in T.

Physics added: the listed `cte_nonlinearity` lets the CTE of the shaft and the housing (and nut
and cover) vary linearly with temperature. Over a wide range (-60..80 C and beyond) the CTE of
metals bends (it follows the heat capacity, Grueneisen relation, and falls towards zero at 0 K):

    alpha(T) = alpha + dalpha_per_K (T - 20) + d2alpha_per_K3 (T - 20)^2,

so the thermal strain gains d2alpha_per_K3 ((T - 20)^3 - (T_ref - 20)^3) / 3, a cubic in T
(`analytic.materials.Material.thermal_strain`, exact; the FE stays linear in the strains).

Parameters:
    dalpha_per_K    CTE slope, 1/K^2, bounds [-3e-8, 3e-8], off 0 (the listed parameter)
    d2alpha_per_K3  CTE curvature, 1/K^3, bounds [-5e-10, 5e-10], off 0

Reduces to `cte_nonlinearity` exactly at d2alpha_per_K3 = 0 (the strain's cubic term is then not
added at all). Convention: added to `PhysicsInputs.d2alpha_per_K3["shaft"]` and `["housing"]`.

Source / rationale: Ti-6Al-4V CTE 8.0e-6 /K at -50 C, 8.6e-6 at 20 C, 9.2e-6 at 100 C with a
visible bend below 0 C (MMPDS; Touloukian et al., Thermophysical Properties of Matter vol. 12,
thermal expansion of metallic elements and alloys); a curvature of 1e-11 /K^3 changes the slope
by 1.6e-9 /K^2 over 80 K. 5e-10 /K^3 bounds structural metals between -100 and 150 C.
"""
from __future__ import annotations

from .cte_nonlinearity import PARTS, CteNonlinearity
from .base import GeneralisedForm


class CteCurvature(GeneralisedForm):
    family = "cte_nonlinearity"
    form = "curvature"
    name = "cte_nonlinearity.curvature"
    label = "CTE curvature (second-order term in T)"
    parameters = ("dalpha_per_K", "d2alpha_per_K3")
    extra = ("d2alpha_per_K3",)
    reduces = {"d2alpha_per_K3": 0.0}
    units = {"dalpha_per_K": "1/K^2", "d2alpha_per_K3": "1/K^3"}
    bounds = {"dalpha_per_K": (-3e-8, 3e-8), "d2alpha_per_K3": (-5e-10, 5e-10)}
    off = {"dalpha_per_K": 0.0, "d2alpha_per_K3": 0.0}
    scale = {"dalpha_per_K": 1e-9, "d2alpha_per_K3": 2e-11}
    hint = CteNonlinearity.hint

    def _apply(self, inputs, p, T_ref_C):
        out = CteNonlinearity()._apply(inputs, {"dalpha_per_K": p["dalpha_per_K"]}, T_ref_C)
        if p["d2alpha_per_K3"] == 0.0:
            return out
        d2 = dict(out.d2alpha_per_K3)
        for part in PARTS:
            d2[part] = d2[part] + p["d2alpha_per_K3"]
        return out.copy(d2alpha_per_K3=d2)

    def text(self, params):
        return (f"cte_nonlinearity, CTE curvature: slope {params['dalpha_per_K']:.3g} 1/K^2, "
                f"curvature {params['d2alpha_per_K3']:.3g} 1/K^3")
