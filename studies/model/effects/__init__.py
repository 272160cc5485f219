"""Candidate model extensions ("effects"): registry, common behaviour and conventions.

An effect is a small object that transforms a `studies.model.inputs.PhysicsInputs` (part temperatures,
fits, CTE slope, viscosity law, friction coefficient, preload loss); it never touches model outputs.
One module per effect, each with a docstring giving the physics it adds, its parameters (units in
the names), their physical bounds and the source or rationale. Every effect has a null setting
(`off`) at which `apply` returns the baseline inputs exactly (a test says so).

Public interface of an effect `e` (see `Effect`):

- `e.name`, `e.parameters` (ordered names, units in the names, exactly as in docs/cli.md "Effects"),
  `e.bounds[p] = (lo, hi)` (physical; values outside raise a one-line `EffectError`),
  `e.off[p]` (baseline values; also the default of a parameter left out), `e.requires`
  (condition fields the effect needs, e.g. `time_s`),
- `e.apply(inputs, params, T_ref_C) -> PhysicsInputs` (a new object; inputs are never mutated).

Conventions for the fields that the baseline leaves at `None` ("config value"):

- `interference_inner_um`, `interference_outer_um`: an effect writes the *offset from the config's
  nominal diametral fit*, in um, at the reference temperature (positive = more interference).
  `None` means no offset. The pipeline resolves the as-built fit with `resolve_interference_um`.
- `friction_coefficient`: an effect writes the *change of the friction coefficient from the
  config's value* (dimensionless) per row. `None` means no change. The pipeline resolves the
  coefficient with `resolve_friction_coefficient` (clipped at 0 so that a temperature slope can
  never produce a negative coefficient).

Several effects are combined with `apply_effects`, which applies them in the fixed order `ORDER`
(the lag acts on the ambient-following part temperatures before a radial gradient is added).
"""
from __future__ import annotations

from typing import Mapping

from studies.model.inputs import PhysicsInputs

from .base import (Effect, EffectError, GeneralisedForm, resolve_friction_coefficient,
                   resolve_interference_um)
from .interference_error import InterferenceError
from .thermal_lag import ThermalLag
from .radial_gradient import RadialGradient
from .cte_nonlinearity import CteNonlinearity
from .viscosity_temperature import ViscosityTemperature
from .friction_temperature import FrictionTemperature
from .preload_settling import PreloadSettling
from .solid_film_runin import SolidFilmRunin
from .preload_path_compliance import PreloadPathCompliance
from .generalised import GENERALISED


# ---------------------------------------------------------------------- registry
def assembly_bounds(asm) -> dict[str, dict[str, tuple[float, float]]]:
    """Parameter bounds an assembly implies (the diagnosis fits inside them):
    - preload_settling.loss_N <= the assembled preload (a pair cannot lose more than it has);
    - interference_error.inner_um / outer_um inside the fit's tolerance band around the mean fit,
      where `[fits]` gives tolerances (`studies/model/tolerances.py`)."""
    from studies.model.tolerances import has_tolerances, worst_case_bands

    out = {"preload_settling": {"loss_N": (0.0, float(asm.preload.assembled_N))}}
    if has_tolerances(asm):
        mean = dict(zip(("inner", "outer"), asm.mean_fits_um()))
        out["interference_error"] = {f"{b.fit}_um": (b.lower_um - mean[b.fit], b.upper_um - mean[b.fit])
                                     for b in worst_case_bands(asm) if b.fit in mean}
    return out


#: order in which `apply_effects` applies effects (the lag first: it acts on the ambient-following
#: part temperatures; the radial gradient then adds to them; friction reads the final temperatures).
ORDER = ("interference_error", "thermal_lag", "radial_gradient", "cte_nonlinearity",
         "viscosity_temperature", "friction_temperature", "preload_settling", "solid_film_runin",
         "preload_path_compliance")

EFFECTS: dict[str, Effect] = {e.name: e for e in (
    InterferenceError(), RadialGradient(), ThermalLag(), ViscosityTemperature(),
    FrictionTemperature(), PreloadSettling(), CteNonlinearity(), SolidFilmRunin(),
    PreloadPathCompliance())}
assert set(EFFECTS) == set(ORDER)


def get_effect(name: str) -> Effect:
    """A listed effect, or a generalised form `family.form` (`studies.model.effects.generalised`)."""
    try:
        return EFFECTS[name] if name in EFFECTS else GENERALISED[name]
    except KeyError:
        raise EffectError(f"unknown effect {name!r} (known: {', '.join(EFFECTS)}; generalised "
                          f"forms: {', '.join(GENERALISED)})") from None


def parse_effect_arg(text: str) -> tuple[str, dict[str, float]]:
    """Parse `NAME:key=value[,key=value]` (the `simulate --effect` syntax) and validate it."""
    name, _, rest = text.strip().partition(":")
    effect = get_effect(name.strip())
    params: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in rest.split(","))):
        key, eq, value = item.partition("=")
        if not eq:
            raise EffectError(f"effect {effect.name}: expected key=value, got {item!r}")
        key = key.strip()
        if key in params:
            raise EffectError(f"effect {effect.name}: parameter {key} given twice")
        try:
            params[key] = float(value)
        except ValueError:
            raise EffectError(f"effect {effect.name}: parameter {key} = {value.strip()!r} is not "
                              "a number") from None
    return effect.name, effect.validate(params)


def apply_effects(inputs: PhysicsInputs, effects: Mapping[str, Mapping[str, float]] | None,
                  T_ref_C: float) -> PhysicsInputs:
    """Apply several effects (name -> parameters) in the order `ORDER` (a generalised form at its
    family's place); no effects -> a copy."""
    effects = dict(effects or {})
    objs = {name: get_effect(name) for name in effects}
    out = inputs.copy()
    for name in sorted(effects, key=lambda n: ORDER.index(getattr(objs[n], "family", "") or n)):
        out = objs[name].apply(out, effects[name], T_ref_C)
    return out


__all__ = ["Effect", "EffectError", "GeneralisedForm", "EFFECTS", "ORDER", "get_effect", "parse_effect_arg",
           "apply_effects", "resolve_interference_um", "resolve_friction_coefficient"]
