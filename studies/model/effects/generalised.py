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

from typing import Mapping

from . import Effect


class GeneralisedForm(Effect):
    """Base class of a generalised form. Subclasses set, besides the `Effect` attributes:

    family : name of the listed effect generalised (its parameters keep their names and meaning).
    form : short name of the form (`name` = family + "." + form).
    label : what the form adds, for reports ("per-part time constants").
    extra : the parameters the listed form does not have.
    reduces : extra parameter -> value at which the form is the listed one, or the name of a
        listed parameter whose value it then takes (per-part lag: tau_shaft_s = tau_s).
    """

    family: str = ""
    form: str = ""
    label: str = ""
    extra: tuple[str, ...] = ()
    reduces: dict[str, float | str] = {}

    def from_listed(self, listed: Mapping[str, float]) -> dict[str, float]:
        """The form's parameters at which it equals the listed form with parameters `listed`."""
        out = {p: float(listed[p]) for p in self.parameters if p not in self.extra}
        for p in self.extra:
            v = self.reduces[p]
            out[p] = float(listed[v]) if isinstance(v, str) else float(v)
        return out

    def on_bound(self, p: str) -> bool:
        """True when the reducing value of extra parameter p is a bound of p (one-sided test)."""
        v = self.reduces[p]
        return not isinstance(v, str) and v in self.bounds[p]

    def text(self, params: Mapping[str, float]) -> str:
        """One line for reports: "thermal_lag, per-part time constants: housing 900 s, ..."."""
        raise NotImplementedError

    def extra_starts(self, listed: Mapping[str, float], conditions) -> list[dict[str, float]]:
        """Starting values of the extra parameters (besides the reducing value) for a fit that
        begins at the listed fit."""
        return []


from .thermal_lag_per_part import ThermalLagPerPart  # noqa: E402
from .preload_settling_creep import PreloadSettlingCreep  # noqa: E402
from .cte_curvature import CteCurvature  # noqa: E402
from .radial_gradient_lag import RadialGradientLag  # noqa: E402

GENERALISED: dict[str, GeneralisedForm] = {f.name: f for f in (
    ThermalLagPerPart(), PreloadSettlingCreep(), CteCurvature(), RadialGradientLag())}


def forms_of(family: str) -> list[GeneralisedForm]:
    """The generalised forms of a listed effect (none for most)."""
    return [f for f in GENERALISED.values() if f.family == family]
