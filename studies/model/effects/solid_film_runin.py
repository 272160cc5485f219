"""solid_film_runin: the solid-film friction coefficient changes as the film runs in with the
revolutions accumulated since the start of the table.

Physics added: a sputtered MoS2 film first transfers material to the balls and reorients its
basal planes; its friction coefficient moves from the as-deposited value towards a steady one as
the revolutions accumulate (run-in, a first-order approach to a steady state):

    mu(N) = mu_config + dmu * (1 - exp(-N / (1000 runin_krev)))

    N(t_i) = sum over the intervals before row i of (n_k + n_(k+1)) / 2 * (t_(k+1) - t_k) / 60

the revolutions since the first row (speed `n` in rpm taken piecewise linear between the samples,
integrated exactly by the trapezoidal rule; `time_s` in s). At the first row the film is as the
configuration describes it (mu_config).

Parameters:
    dmu         change of the friction coefficient after full run-in, dimensionless,
                bounds [-0.05, 0.05], off 0 (also switches the effect off)
    runin_krev  run-in constant, thousands of revolutions, bounds [0.01, 1e4], default 10
                (no effect while dmu = 0); profiled over a log grid by the diagnosis

Needs: `time_s` (strictly increasing). The speed is the `speed_rpm` column, else the configured
speed, exactly as the baseline takes it. Convention: written into
`PhysicsInputs.friction_coefficient` as a change added to any change present (see
`studies.model.effects`); the pipeline clips the coefficient at 0.

Source / rationale: seed 000 (after repeated -60..80 C cycles the torque maximum is 1.7 N·mm lower
and the minimum 0.9 N·mm higher than in the first cycle: the torque of a MoS2 pair changes with
accumulated running); run-in of sputtered MoS2 films in vacuum, friction falling over the first
10^3..10^5 revolutions towards 0.01..0.05 (E. W. Roberts, Thin solid lubricant films in space,
Tribology International 23 (1990) 95-104); a run-in curve approaching its steady value
exponentially (P. J. Blau, Friction and Wear Transitions of Materials: Break-in, Run-in, Wear-in,
Noyes 1989, ch. 2). |dmu| <= 0.05 bounds the as-deposited-to-steady change of such films; 10 revolutions
to 10^7 revolutions bounds any laboratory run-in.
"""
from __future__ import annotations

import numpy as np

from .base import Effect


def revolutions(t_s: np.ndarray, speed_rpm: np.ndarray) -> np.ndarray:
    """Revolutions since the first sample: the exact integral of a speed (rpm) piecewise linear in
    time (s) between the samples (trapezoidal rule), 0 at the first sample."""
    t = np.asarray(t_s, float)
    n = np.broadcast_to(np.asarray(speed_rpm, float), t.shape)
    out = np.zeros(t.shape)
    if t.size > 1:
        out[1:] = np.cumsum(0.5 * (n[1:] + n[:-1]) * np.diff(t) / 60.0)
    return out


class SolidFilmRunin(Effect):
    name = "solid_film_runin"
    parameters = ("dmu", "runin_krev")
    units = {"dmu": "-", "runin_krev": "1000 rev"}
    bounds = {"dmu": (-0.05, 0.05), "runin_krev": (0.01, 1e4)}
    off = {"dmu": 0.0, "runin_krev": 10.0}
    requires = ("time_s",)
    scale = {"dmu": 1e-3, "runin_krev": 1.0}
    hint = ("repeat the same temperature cycle several times (a run-in changes the torque from "
            "cycle to cycle and then settles; a temperature effect repeats), or run at constant "
            "temperature for many revolutions")

    def active_parameters(self):
        return ("dmu",)

    def _apply(self, inputs, p, T_ref_C):
        N = revolutions(inputs.time_s, inputs.speed_rpm)
        d = p["dmu"] * -np.expm1(-N / (1000.0 * p["runin_krev"]))
        return inputs.copy(friction_coefficient=np.asarray(inputs.friction_coefficient, float) + d)

    #: set by `for_assembly`: the configured speed (rpm) and lubrication kind
    speed_rpm: float | None = None
    lubrication: str | None = None

    def for_assembly(self, asm) -> "SolidFilmRunin":
        """A copy that knows the assembly's configured speed (used when the table has no
        `speed_rpm` column, as in the baseline) and its lubrication (a solid-film effect)."""
        import copy

        out = copy.copy(self)
        out.speed_rpm = float(asm.lubrication.speed_rpm)
        out.lubrication = str(asm.lubrication.kind)
        return out

    def applicable(self, conditions):
        why = super().applicable(conditions)
        if why is None and self.lubrication not in (None, "solid_film"):
            why = f"the assembly is {self.lubrication}-lubricated (a solid-film effect)"
        if why is None and "speed_rpm" not in conditions and self.speed_rpm is None:
            why = "needs the condition column speed_rpm (or the assembly's configured speed)"
        return why
