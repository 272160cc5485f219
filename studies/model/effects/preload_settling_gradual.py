"""preload_settling.gradual: generalised preload_settling, a loss that settles over a time
constant after the first excursion instead of at once.

Physics added: the listed `preload_settling` loses `loss_N` at the first excursion beyond
+-threshold_K, at that row. Embedding of clamped faces and the relaxation of a joint held at
an overload do not happen in an instant: the preload relaxes towards its settled value over
the time the joint is held (short-term relaxation of a clamped joint, first order), so from
the first row beyond the threshold, at time t_0,

    preload_loss_N[i] = loss_N (1 - exp(-(t_i - t_0) / tau_settle_s))   for t_i >= t_0,

and 0 before; `settled` and t_0 as in `preload_settling` (the running excursion of
`T_ambient_C` beyond the threshold, rows in time order). At tau_settle_s = 0 the loss is the
listed step (the factor is then 1 from t_0 on).

Parameters:
    loss_N         settled loss, N, bounds [0, 2000], off 0 (listed)
    threshold_K    excursion that triggers the loss, K, bounds [1, 150], default 20 (listed)
    tau_settle_s   time constant of the settling, s, bounds [0, 36000], 0: the listed step

Reduces to `preload_settling` exactly at tau_settle_s = 0. Needs `time_s` and `T_ambient_C`.

Source / rationale: embedding and short-term relaxation of clamped joints settle within the
first hours under load and temperature and approach a final loss (VDI 2230 Part 1:2015,
sec. 5.4.2.1, embedding; Bickford, Introduction to the Design and Behavior of Bolted Joints,
4th ed. 2008, ch. 6, short-term relaxation); the first-order approach is the simplest form
with a final value, an assumption stated as such. 36000 s (10 h) bounds a settling seen within
a test of hours; beyond it the creep form (`preload_settling.creep`) is the one that fits.
"""
from __future__ import annotations

import numpy as np

from .base import GeneralisedForm
from .preload_settling import PreloadSettling, excursion


class PreloadSettlingGradual(GeneralisedForm):
    family = "preload_settling"
    form = "gradual"
    name = "preload_settling.gradual"
    label = "loss settling over a time constant after the first excursion"
    parameters = ("loss_N", "threshold_K", "tau_settle_s")
    extra = ("tau_settle_s",)
    reduces = {"tau_settle_s": 0.0}
    units = {"loss_N": "N", "threshold_K": "K", "tau_settle_s": "s"}
    bounds = {"loss_N": (0.0, 2000.0), "threshold_K": (1.0, 150.0),
              "tau_settle_s": (0.0, 36000.0)}
    off = {"loss_N": 0.0, "threshold_K": 20.0, "tau_settle_s": 0.0}
    requires = ("time_s", "T_ambient_C")
    scale = {"loss_N": 5.0, "threshold_K": 5.0, "tau_settle_s": 600.0}
    hint = PreloadSettling.hint + "; log the preload through the first hours after it"

    def active_parameters(self):
        return ("loss_N", "tau_settle_s")

    def _apply(self, inputs, p, T_ref_C):
        settled = excursion(np.asarray(inputs.T_ambient_C, float), T_ref_C) > p["threshold_K"]
        loss = np.zeros(settled.size)
        if settled.any():
            t = np.asarray(inputs.time_s, float)
            dt = np.clip(t - t[int(np.argmax(settled))], 0.0, None)     # 0 before t_0
            tau = float(p["tau_settle_s"])
            share = -np.expm1(-dt / tau) if tau > 0.0 else np.ones_like(dt)
            loss = np.where(settled, p["loss_N"] * share, 0.0)
        return inputs.copy(preload_loss_N=np.asarray(inputs.preload_loss_N, float) + loss)

    def text(self, params):
        return (f"preload_settling, {self.label}: {params['loss_N']:.3g} N after the first "
                f"excursion beyond {params['threshold_K']:.3g} K, time constant "
                f"{params['tau_settle_s']:.3g} s")
