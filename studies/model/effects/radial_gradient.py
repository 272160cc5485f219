"""radial_gradient: the inner parts (shaft, inner rings, balls) run warmer than the outer parts.

Physics added: in a running bearing the heat is generated at the contacts and leaves mainly through
the housing, so the shaft, the inner rings and the balls run warmer than the outer rings and the
housing. The effect adds

    dT = dT_K + dT_per_krpm_K * speed_rpm / 1000

to the temperatures of the shaft, the inner ring and the ball, and leaves the outer ring, the
housing and the spacers as they are. The speed-proportional part stands for frictional heating
(heat rate ~ torque x speed with a constant thermal resistance).

Parameters:
    dT_K           constant part, K, bounds [-10, 30], off 0 (negative: inner parts cooler, e.g.
                   a shaft heat sink)
    dT_per_krpm_K  part proportional to speed, K per 1000 rpm, bounds [0, 10], off 0 (frictional
                   heat only warms the inner parts)

Source / rationale: seed 003 (5-node network housing - outer ring - balls - inner ring - shaft:
balls hottest, inner ring warmer than outer) and seed 001 (radial clearance change from the ring
temperature difference); Harris & Kotzalas, Vol. 2 (heat generation and thermal networks). Measured
inner/outer ring differences of spindle bearings are a few K per 1000 rpm; 30 K bounds a hot spindle.
"""
from __future__ import annotations

import numpy as np

from .base import Effect

INNER_PARTS = ("shaft", "inner_ring", "ball")


class RadialGradient(Effect):
    name = "radial_gradient"
    parameters = ("dT_K", "dT_per_krpm_K")
    units = {"dT_K": "K", "dT_per_krpm_K": "K/krpm"}
    bounds = {"dT_K": (-10.0, 30.0), "dT_per_krpm_K": (0.0, 10.0)}
    off = {"dT_K": 0.0, "dT_per_krpm_K": 0.0}
    scale = {"dT_K": 1.0, "dT_per_krpm_K": 1.0}
    hint = ("measure the inner-ring (or shaft) temperature beside the outer-ring temperature, or "
            "repeat the test at a second speed (the gradient grows with speed)")

    def _apply(self, inputs, p, T_ref_C):
        dT = p["dT_K"] + p["dT_per_krpm_K"] * np.asarray(inputs.speed_rpm, float) / 1000.0
        T = dict(inputs.T_C)
        for part in INNER_PARTS:
            T[part] = np.asarray(T[part], float) + dT
        return inputs.copy(T_C=T)
