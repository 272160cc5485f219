"""The base class of an effect and the two helpers the pipeline resolves effect-written fields
with (`studies.model.effects` has the conventions and the registry).

An effect carries its physics only: name, parameters, units, bounds, off values, the conditions
it needs and `apply`. How the diagnosis fits it (finite-difference steps, starting points, the
grid of a profiled parameter, parameters held at off) is the diagnosis's per-effect fit
specification, `studies.diagnosis.fitspec`.
"""
from __future__ import annotations

import copy
import math
import sys
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
    hint : physics-based advice on what measurement separates this effect from look-alikes.
    """

    name: str = ""
    parameters: tuple[str, ...] = ()
    units: dict[str, str] = {}
    bounds: dict[str, tuple[float, float]] = {}
    off: dict[str, float] = {}
    requires: tuple[str, ...] = ()
    scale: dict[str, float] = {}
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

    # ------------------------------------------------------------------ conditions
    def applicable(self, conditions: Mapping[str, np.ndarray]) -> str | None:
        """None if the conditions table allows the effect, else the reason why not."""
        for f in self.requires:
            if f not in conditions:
                return f"needs the condition column {f}"
        return None

    def for_assembly(self, asm) -> "Effect":
        """The effect as one assembly sees it (e.g. its configured speed); default: itself."""
        return self

    def describe(self) -> str:
        """First paragraph of the module docstring."""
        doc = (sys.modules[type(self).__module__].__doc__ or "").strip()
        return doc.split("\n\n")[0].replace("\n", " ")

    def __repr__(self):
        return f"<effect {self.name}>"


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
