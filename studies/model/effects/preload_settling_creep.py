"""preload_settling.creep: generalised preload_settling, a loss that also grows with the time
spent beyond the threshold.

Physics added: the listed `preload_settling` loses `loss_N` at the first excursion beyond
+-threshold_K and nothing more. Embedding of clamped faces and creep of a soft film or of a
polymer spacer go on while the joint is held hot (or cold): the loss then grows with the time
spent beyond the threshold,

    preload_loss_N[i] = L[i] + min(creep_N_per_h * H[i], max(P_a[i] - L[i], 0)),
    L[i] = loss_N * settled[i],
    H[i] = sum_{k=1..i} (t_k - t_{k-1}) [ |T_k - T_ref| > threshold_K ] / 3600   (h),

`settled` as in `preload_settling` (the running excursion beyond the threshold), the interval
before a row counted as beyond the threshold when that row is (rectangle rule, exact for the
sampled indicator). T is `T_ambient_C`. The creep stops when the joint has lost the whole
assembled preload P_a (`preload_assembled_N` of the row): a pair cannot lose more preload than it
was assembled with (the listed form's `loss_N` is bounded by it, `assembly_bounds`), so the total
loss never exceeds P_a whatever the creep rate and the duration of the table.

Parameters:
    loss_N         step loss at the first excursion, N, bounds [0, 2000], off 0 (listed)
    threshold_K    excursion that triggers the loss, K, bounds [1, 150], default 20 (listed)
    creep_N_per_h  further loss per hour beyond the threshold, N/h, bounds [0, 500], off 0

Reduces to `preload_settling` exactly at creep_N_per_h = 0 (the creep term is then 0 * H = 0
added to the listed form's own loss). Needs `time_s` and `T_ambient_C`.

Source / rationale: embedding losses of clamped joints grow with time under load and
temperature (VDI 2230 Part 1, embedding and creep of joints); seed 000's repeated cycles lose
preload over more than one cycle. 500 N/h bounds the shipped preloads (7..1500 N) lost within
hours; the pipeline clips the preload at zero.
"""
from __future__ import annotations

import numpy as np

from .base import GeneralisedForm
from .preload_settling import PreloadSettling


def hours_beyond(t_s: np.ndarray, T: np.ndarray, T_ref_C: float, threshold_K: float) -> np.ndarray:
    """Accumulated time (h) spent beyond +-threshold_K from T_ref, per row (0 at the first row)."""
    hot = np.abs(np.asarray(T, float) - T_ref_C) > threshold_K
    dt = np.diff(np.asarray(t_s, float))
    return np.concatenate([[0.0], np.cumsum(dt * hot[1:])]) / 3600.0


class PreloadSettlingCreep(GeneralisedForm):
    family = "preload_settling"
    form = "creep"
    name = "preload_settling.creep"
    label = "loss growing with time beyond the threshold"
    parameters = ("loss_N", "threshold_K", "creep_N_per_h")
    extra = ("creep_N_per_h",)
    reduces = {"creep_N_per_h": 0.0}
    units = {"loss_N": "N", "threshold_K": "K", "creep_N_per_h": "N/h"}
    bounds = {"loss_N": (0.0, 2000.0), "threshold_K": (1.0, 150.0), "creep_N_per_h": (0.0, 500.0)}
    off = {"loss_N": 0.0, "threshold_K": 20.0, "creep_N_per_h": 0.0}
    requires = ("time_s", "T_ambient_C")
    scale = {"loss_N": 5.0, "threshold_K": 5.0, "creep_N_per_h": 1.0}
    hint = PreloadSettling.hint + "; hold the assembly hot for different durations"

    def active_parameters(self):
        return ("loss_N", "creep_N_per_h")

    def _apply(self, inputs, p, T_ref_C):
        listed = PreloadSettling()._apply(inputs, {"loss_N": p["loss_N"],
                                                   "threshold_K": p["threshold_K"]}, T_ref_C)
        H = hours_beyond(inputs.time_s, inputs.T_ambient_C, T_ref_C, p["threshold_K"])
        L = np.asarray(listed.preload_loss_N, float)
        room = np.maximum(np.asarray(inputs.preload_assembled_N, float) - L, 0.0)
        return listed.copy(preload_loss_N=L + np.minimum(p["creep_N_per_h"] * H, room))

    def text(self, params):
        return (f"preload_settling, loss growing with time beyond the threshold: "
                f"{params['loss_N']:.3g} N at the first excursion beyond {params['threshold_K']:.3g} K "
                f"+ {params['creep_N_per_h']:.3g} N per hour beyond it")
