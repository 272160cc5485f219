"""Candidate model extensions ("effects"): registry, common behaviour and conventions.

An effect is a small object that transforms a `studies.model.inputs.PhysicsInputs` (part temperatures,
fits, CTE slope, viscosity law, friction coefficient, preload loss); it never touches model outputs.
One module per effect, each with a docstring giving the physics it adds, its parameters (units in
the names), their physical bounds and the source or rationale. Every effect has a null setting
(`off`) at which `apply` returns the baseline inputs exactly (a test says so).

Public interface of an effect `e` (see `Effect`):

- `e.name`, `e.parameters` (ordered names, units in the names, exactly as in `spec/cli.md`),
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

import math
from typing import Mapping

import numpy as np

from studies.model.inputs import PhysicsInputs


class EffectError(ValueError):
    """Bad effect name, parameter or value, or missing conditions: one-line message."""


class Effect:
    """Base class. Subclasses set the class attributes and implement `_apply`.

    Attributes
    ----------
    name : spec name of the effect.
    parameters : ordered parameter names, units in the names.
    units : parameter -> unit text (for reports).
    bounds : parameter -> (lo, hi), physical bounds (inclusive).
    off : parameter -> value at which the effect is exactly the baseline (and default value).
    requires : condition fields (`PhysicsInputs` attributes) that must not be None.
    scale : parameter -> typical magnitude (finite-difference steps, starting points, reports).
    profile : parameters fitted by profiling over a finite grid (`grid`) instead of by gradients.
    hint : physics-based advice on what measurement separates this effect from look-alikes.
    """

    name: str = ""
    parameters: tuple[str, ...] = ()
    units: dict[str, str] = {}
    bounds: dict[str, tuple[float, float]] = {}
    off: dict[str, float] = {}
    requires: tuple[str, ...] = ()
    scale: dict[str, float] = {}
    profile: tuple[str, ...] = ()
    hint: str = ""

    # ------------------------------------------------------------------ parameters
    def validate(self, params: Mapping[str, float] | None) -> dict[str, float]:
        """Complete `params` with the `off` values and check names, finiteness and bounds."""
        params = dict(params or {})
        unknown = [k for k in params if k not in self.parameters]
        if unknown:
            raise EffectError(f"effect {self.name}: unknown parameter {unknown[0]!r} "
                              f"(parameters: {', '.join(self.parameters)})")
        out = {}
        for p in self.parameters:
            v = params.get(p, self.off[p])
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise EffectError(f"effect {self.name}: parameter {p} = {v!r} is not a number") \
                    from None
            lo, hi = self.bounds[p]
            if not math.isfinite(v):
                raise EffectError(f"effect {self.name}: parameter {p} = {v} is not finite")
            if v < lo or v > hi:
                raise EffectError(f"effect {self.name}: parameter {p} = {v:g} outside physical "
                                  f"bounds [{lo:g}, {hi:g}] {self.units.get(p, '')}".rstrip())
            out[p] = v
        return out

    def with_bounds(self, **bounds: tuple[float, float]) -> "Effect":
        """A copy whose bounds are narrowed to what one assembly allows (each new range inside the
        physical one and containing the `off` value); the class stays as it is."""
        import copy

        new = dict(self.bounds)
        for p, (lo, hi) in bounds.items():
            plo, phi = self.bounds[p]
            lo, hi = max(float(lo), plo), min(float(hi), phi)
            if not lo <= self.off[p] <= hi:
                raise EffectError(f"effect {self.name}: bounds [{lo:g}, {hi:g}] for {p} exclude "
                                  f"its off value {self.off[p]:g}")
            new[p] = (lo, hi)
        out = copy.copy(self)
        out.bounds = new
        return out

    def active_parameters(self) -> tuple[str, ...]:
        """Parameters whose off value switches the effect off (default: all)."""
        return self.parameters

    def sign(self, p: str) -> int:
        """+1 (-1) when `off[p]` is the lower (upper) bound: the effect has a sign in p; else 0."""
        lo, hi = self.bounds[p]
        if self.off[p] == lo:
            return 1
        if self.off[p] == hi:
            return -1
        return 0

    def check_requires(self, inputs: PhysicsInputs) -> None:
        for f in self.requires:
            if getattr(inputs, f, None) is None:
                raise EffectError(f"effect {self.name} needs the condition column {f}")
        if "time_s" in self.requires:
            t = np.asarray(inputs.time_s, float)
            if t.size > 1 and not np.all(np.diff(t) > 0):
                raise EffectError(f"effect {self.name}: time_s must be strictly increasing")

    # ------------------------------------------------------------------ physics
    def apply(self, inputs: PhysicsInputs, params: Mapping[str, float] | None,
              T_ref_C: float) -> PhysicsInputs:
        """Return new inputs with the effect applied (validated parameters). Every effect runs its
        own code at every parameter value; at `off` that code returns the inputs unchanged field
        by field (a test holds each one to it)."""
        p = self.validate(params)
        self.check_requires(inputs)
        return self._apply(inputs, p, float(T_ref_C))

    def _apply(self, inputs: PhysicsInputs, p: dict[str, float], T_ref_C: float) -> PhysicsInputs:
        raise NotImplementedError

    # ------------------------------------------------------------------ fitting aids
    def applicable(self, conditions: Mapping[str, np.ndarray]) -> str | None:
        """None if the conditions table allows the effect, else the reason why not."""
        for f in self.requires:
            if f not in conditions:
                return f"needs the condition column {f}"
        return None

    def held_fixed(self, conditions: Mapping[str, np.ndarray]) -> tuple[str, ...]:
        """Parameters these conditions cannot separate from the others: held at `off` in a fit
        (default: none)."""
        return ()

    def steps(self, conditions: Mapping[str, np.ndarray]) -> dict[str, float]:
        """Finite-difference step per (non-profile) parameter, in parameter units."""
        return dict(self.scale)

    def starts(self, conditions: Mapping[str, np.ndarray], T_ref_C: float) -> list[dict]:
        """Extra starting points for a fit (nonlinear parameters), as parameter dicts."""
        return []

    def grid(self, conditions: Mapping[str, np.ndarray], T_ref_C: float) -> dict[str, list]:
        """Values to profile over for each parameter in `profile`."""
        return {}

    def for_assembly(self, asm) -> "Effect":
        """The effect as one assembly sees it (e.g. its configured speed); default: itself."""
        return self

    def describe(self) -> str:
        """First paragraph of the module docstring."""
        import sys
        doc = (sys.modules[type(self).__module__].__doc__ or "").strip()
        return doc.split("\n\n")[0].replace("\n", " ")

    def __repr__(self):
        return f"<effect {self.name}>"


# ---------------------------------------------------------------------- helpers for the pipeline
def resolve_interference_um(inputs: PhysicsInputs, inner_config_um: float,
                            outer_config_um: float) -> tuple[np.ndarray, np.ndarray]:
    """As-built diametral fits (um, at the reference temperature) per row: config + offsets."""
    n = inputs.n_rows
    inner = np.full(n, float(inner_config_um)) + np.asarray(inputs.interference_inner_um, float)
    outer = np.full(n, float(outer_config_um)) + np.asarray(inputs.interference_outer_um, float)
    return inner, outer


def resolve_friction_coefficient(inputs: PhysicsInputs, mu_config: float) -> np.ndarray:
    """Friction coefficient per row: config value + change written by effects, clipped at 0."""
    mu = np.full(inputs.n_rows, float(mu_config))
    return np.maximum(mu + np.asarray(inputs.friction_coefficient, float), 0.0)


# ---------------------------------------------------------------------- registry
from .interference_error import InterferenceError  # noqa: E402
from .thermal_lag import ThermalLag  # noqa: E402
from .radial_gradient import RadialGradient  # noqa: E402
from .cte_nonlinearity import CteNonlinearity  # noqa: E402
from .viscosity_temperature import ViscosityTemperature  # noqa: E402
from .friction_temperature import FrictionTemperature  # noqa: E402
from .preload_settling import PreloadSettling  # noqa: E402
from .solid_film_runin import SolidFilmRunin  # noqa: E402
from .preload_path_compliance import PreloadPathCompliance  # noqa: E402

#: order in which `apply_effects` applies effects (the lag first: it acts on the ambient-following
#: part temperatures; the radial gradient then adds to them; friction reads the final temperatures).
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
                                     for b in worst_case_bands(asm)}
    return out


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
    from .generalised import GENERALISED
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


__all__ = ["Effect", "EffectError", "EFFECTS", "ORDER", "get_effect", "parse_effect_arg",
           "apply_effects", "resolve_interference_um", "resolve_friction_coefficient"]
