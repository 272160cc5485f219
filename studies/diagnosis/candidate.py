"""What a candidate is: one effect tried as the cause, and everything the phases learn about it.

A `Candidate` is immutable: the screening phase makes it (identifiability, sensitivity), the fit
phase returns a copy with the fitted parameters and the likelihood-ratio statistics
(`dataclasses.replace`), the held-out phase one with the out-of-sample numbers and its status,
the decision's notes are added when the result is assembled. `to_json` gives the candidate's entry of `diagnosis.json` (keys of
docs/cli.md first; a field never set is left out); the working arrays never reach the file.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

import numpy as np

#: keys every candidate entry carries, set or not (docs/cli.md), then status and reason
ALWAYS = ("effect", "kind", "parameters", "delta_bic", "heldout_rmse", "status", "reason")
#: working state of the phases, not part of the result file
WORKING = ("sensitivity", "profile_fixed", "profile_grid", "fit_cpu_s")


@dataclass(frozen=True)
class HeldoutGain:
    """Paired block bootstrap of the held-out RMSE difference, baseline (or listed form) minus
    candidate, in noise units: the point value, the (q, 1 - q) interval, the blocks where the
    candidate is better, the blocks used and whether the interval excludes zero."""
    rmse_gain: float
    ci: list[float]
    blocks_improved: int
    n_blocks: int
    excludes_zero: bool


@dataclass(frozen=True)
class Candidate:
    effect: str
    kind: str = "effect"            # "effect" (listed) or "model_form" (studies.diagnosis.ladder)
    parameters: dict = field(default_factory=dict)          # fitted values (effect units)
    delta_bic: float | None = None                          # BIC(candidate) - BIC(baseline)
    heldout_rmse: dict = field(default_factory=dict)        # column -> held-out RMSE
    status: str | None = None       # not_applicable | model_failed | not_identifiable | passed | rejected
    reason: str = ""
    identifiability: dict | None = None                     # remaining_fraction, reach_sigma
    rank: int | None = None                                 # rank of the projected sensitivity
    profile: dict | None = None                             # profiled parameters: grid sizes
    predict_calls_fit: int | None = None
    lr: float | None = None                                 # likelihood ratio vs the baseline
    df: dict | None = None                                  # free / on_bound directions
    p_lr: float | None = None                               # chi-bar-square p value
    k: int | None = None                                    # parameters counted by the BIC
    held_at_off: dict | None = None                         # parameters the design cannot separate
    nuisance: dict | None = None                            # refitted nuisance values
    uncertainty: dict | None = None                         # parameter standard errors
    rmse: dict | None = None                                # in-sample RMSE per column
    lr_significant: bool | None = None                      # after Holm over the candidates
    heldout_profile_values: list | None = None
    heldout_failed: str | None = None
    heldout_untestable: list | None = None                  # blocks the kept blocks cannot test
    heldout_gain: HeldoutGain | None = None                 # paired block bootstrap
    # working state (WORKING): d(prediction)/d(parameter) at off, profiled parameters' values
    sensitivity: np.ndarray | None = field(default=None, repr=False)
    profile_fixed: dict | None = None
    profile_grid: dict | None = None
    fit_cpu_s: float | None = None          # CPU seconds of its fit (schedules the refits)

    def with_status(self, status: str, reason: str) -> "Candidate":
        """A copy with this status and reason."""
        return replace(self, status=status, reason=reason)

    @property
    def fitted(self) -> bool:
        return self.delta_bic is not None

    def to_json(self) -> dict:
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in WORKING or (v is None and f.name not in ALWAYS):
                continue
            out[f.name] = v
        return out
