"""Generalised forms of the listed effects: the same physical cause with one more degree of freedom.

A generalised form belongs to a *family* (the listed effect it generalises, e.g. `thermal_lag`),
has its own parameters (units in the names, physical bounds, a docstring with the physics and the
source, like every effect) and reduces EXACTLY to the listed form at a known parameter value:
`form.from_listed(listed_params)` gives that value (the listed parameters plus the extra ones at
their `reduces` value) and `apply` then returns what the listed effect returns, field by field
(tests/test_generalised_forms.py holds every form to it). The diagnosis tries a form only when
the listed form of its family leaves structure behind, and reports it as the listed cause with an
extended form (`studies.diagnosis.generalised`), with its own held-out gain against the listed form
(nested models).

Names are `family.form` (e.g. `thermal_lag.per_part`); `apply_effects` applies a form at its
family's place in `ORDER`, and `simulate --effect thermal_lag.per_part:tau_s=900,tau_shaft_s=2400`
makes data with it.
"""
from __future__ import annotations

from .base import GeneralisedForm
from .thermal_lag_per_part import ThermalLagPerPart
from .thermal_lag_series import ThermalLagSeries
from .preload_settling_creep import PreloadSettlingCreep
from .preload_settling_gradual import PreloadSettlingGradual
from .cte_curvature import CteCurvature
from .radial_gradient_lag import RadialGradientLag
from .friction_temperature_exponential import FrictionTemperatureExponential

__all__ = ["GeneralisedForm", "GENERALISED", "forms_of"]

GENERALISED: dict[str, GeneralisedForm] = {f.name: f for f in (
    ThermalLagPerPart(), PreloadSettlingCreep(), CteCurvature(), RadialGradientLag(),
    ThermalLagSeries(), FrictionTemperatureExponential(), PreloadSettlingGradual())}


def forms_of(family: str) -> list[GeneralisedForm]:
    """The generalised forms of a listed effect (none for most)."""
    return [f for f in GENERALISED.values() if f.family == family]
