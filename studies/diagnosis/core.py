"""The small typed core of the diagnosis: its errors, thresholds, the cached model, a parameter
space, a fit, and what the phases hand to each other (`Baseline`, `Screening`, `Decision`).
A candidate is `studies.diagnosis.candidate.Candidate`."""
from __future__ import annotations

import dataclasses
import math
import time
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from infra.errors import BearingfemError
from studies.diagnosis.candidate import Candidate

DEFAULT_THRESHOLDS = {
    "alpha_structure": 0.01,    # residual-structure tests, Bonferroni over tests x columns
    "alpha_lr": 0.01,           # likelihood-ratio test, Holm over the candidates tested
    "bic_margin": 0.0,          # a candidate needs delta_bic < -bic_margin
    "heldout_quantile": 0.025,  # lower bootstrap quantile of the held-out RMSE gain must be > 0
    "n_boot": 2000,             # bootstrap resamples of the blocks
    "min_remaining": 0.10,      # share of the sensitivity left after projecting out the nuisance
    "min_reach_sigma": 3.0,     # projected change reachable inside the bounds (noise units, norm)
    "alpha_joint": 0.01,        # conditional likelihood-ratio tests of the joint fits
    "clear_chi2": 25.0,         # a rival whose chi-square is this much worse is beaten outright
    "alpha_residual": 0.001,    # structure left behind by the best candidate
    "lookalike_cos": 0.95,      # cosine above which two candidates are reported as look-alikes
    "n_blocks": 10,             # automatic contiguous blocks when no labels are given
}

FIRST_COLUMNS = ("torque_Nmm",)


class DiagnosisError(ValueError):
    """Unusable input to the engine (one-line message)."""


class ModelFailure(BearingfemError):
    """The model could not be evaluated (exception or non-finite output) at some parameters
    (the package's own error, a ValueError, when it reaches the caller)."""



def jsonable(x):
    """Numbers, arrays, containers and dataclasses as plain JSON values (non-finite floats ->
    null)."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return jsonable({f.name: getattr(x, f.name) for f in dataclasses.fields(x)})
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return [jsonable(v) for v in x.tolist()]
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        x = float(x)
        return x if math.isfinite(x) else None
    return x



class CachedModel:
    """predict() with a call counter and a small LRU cache."""

    def __init__(self, predict, n_rows, maxsize=512):
        self.predict = predict
        self.n = n_rows
        self.calls = 0
        self.seconds = 0.0
        self.cache: OrderedDict = OrderedDict()
        self.maxsize = maxsize

    def __call__(self, effects: dict, nuisance: dict) -> dict[str, np.ndarray]:
        key = (tuple(sorted((e, tuple(sorted((k, float(v)) for k, v in p.items())))
                            for e, p in effects.items())),
               tuple(sorted((k, float(v)) for k, v in nuisance.items())))
        hit = self.cache.get(key)
        if hit is not None:
            self.cache.move_to_end(key)
            return hit
        t0 = time.perf_counter()
        try:
            raw = self.predict({e: dict(p) for e, p in effects.items()}, dict(nuisance))
        except Exception as exc:  # the model's own failure at these parameters
            raise ModelFailure(f"{type(exc).__name__}: {exc}") from exc
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        out = {}
        for k, v in raw.items():
            a = np.asarray(v, dtype=float) if not isinstance(v, str) else None
            if a is not None and a.ndim == 1 and a.size == self.n:
                out[k] = a
        self.remember(key, out)
        return out

    # the state a forked worker's calls add (`studies.model.parallel.parallel_map`)
    def snapshot(self) -> tuple[int, float, set]:
        return self.calls, self.seconds, set(self.cache)

    def delta(self, snapshot: tuple[int, float, set]) -> tuple[int, float, list]:
        """Calls, model seconds and new cache entries since `snapshot`."""
        calls0, sec0, known = snapshot
        return (self.calls - calls0, self.seconds - sec0,
                [(k, v) for k, v in self.cache.items() if k not in known])

    def merge(self, delta: tuple[int, float, list]) -> None:
        calls, seconds, new = delta
        self.calls += calls
        self.seconds += seconds
        for k, v in new:
            self.remember(k, v)

    def remember(self, key, out: dict) -> None:
        """Keep a result (the newest; the least recently used goes beyond `maxsize`)."""
        self.cache[key] = out
        self.cache.move_to_end(key)
        if len(self.cache) > self.maxsize:
            self.cache.popitem(last=False)


@dataclass
class Space:
    """Fitted parameters in scaled coordinates u: value = origin + scale * u. The candidate's
    effect parameters (`eff_params`, `k` of them) come first, then the parameters of causes
    already accepted (`base_params`, refitted with every model like the nuisance), then the
    nuisance: everything after the first `k` is "the baseline's" part of u."""
    eff_params: list[tuple[str, str]]          # (effect name, parameter)
    fixed: dict[str, dict[str, float]]        # effect -> all its parameters at their fixed values
    nuis: list[str]
    origin: np.ndarray
    scale: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    base_params: list[tuple[str, str]] = dataclasses.field(default_factory=list)

    def unpack(self, u) -> tuple[dict, dict]:
        v = self.origin + self.scale * np.asarray(u, float)
        v = np.clip(v, self.lo * self.scale + self.origin, self.hi * self.scale + self.origin)
        effects = {e: dict(p) for e, p in self.fixed.items()}
        k = len(self.eff_params)
        kb = k + len(self.base_params)
        for (e, p), x in zip(self.eff_params + self.base_params, v[:kb]):
            effects[e][p] = float(x)
        nuis = {n: float(x) for n, x in zip(self.nuis, v[kb:])}
        return effects, nuis

    def values(self, u) -> np.ndarray:
        return self.origin + self.scale * np.asarray(u, float)

    def to_u(self, values) -> np.ndarray:
        return (np.asarray(values, float) - self.origin) / self.scale

    def clip(self, u) -> np.ndarray:
        return np.clip(u, self.lo, self.hi)

    @property
    def k(self):
        return len(self.eff_params)


@dataclass
class Linearisation:
    """A candidate at one value of its profiled parameter, linearised: the standardised
    residual z and its Jacobian J (effect parameters, then nuisance) in `space`; for a grid
    point of the in-sample profile also the start u0, the step bounds lo / hi, the bounded
    linear fit's step du and chi-square sse."""
    value: float
    space: Space
    J: np.ndarray
    z: np.ndarray
    u0: np.ndarray | None = None
    lo: np.ndarray | None = None
    hi: np.ndarray | None = None
    sse: float = math.inf
    du: np.ndarray | None = None


@dataclass
class Fit:
    space: Space
    u: np.ndarray
    z: np.ndarray               # standardised residual (stacked), at u
    J: np.ndarray               # d z / d u at u
    chi2: float
    pred: dict
    # a profiled fit: the profiled value, the grid's linearisations, the chi-square-1 interval
    profile_value: float | None = None
    grid: list[Linearisation] | None = None
    interval: list[float] | None = None


@dataclass(frozen=True)
class ColumnResiduals:
    """Residual statistics of one column (`Problem.describe_column`): bias (column unit) and
    its p value, RMSE, the noise level and AR(1) coefficient used, reduced chi-square, lag-1
    autocorrelation and its p, the smoother's F statistic, p and held-out gain, and the p the
    structure decision uses (1 for AR(1) noise when the smoother does not predict held-out
    blocks)."""
    bias: float
    bias_p: float
    rmse: float
    noise_sigma: float
    noise_ar1: float
    chi2_reduced: float
    lag1_autocorr: float
    lag1_p: float
    smoother_F: float
    smoother_p: float
    smoother_heldout_gain: float
    smoother_p_used: float


@dataclass(frozen=True)
class Residuals:
    """Residual statistics per compared column and the smallest p value, Bonferroni-adjusted
    over the tests and columns."""
    columns: dict[str, ColumnResiduals]
    p_min_adjusted: float


@dataclass(frozen=True)
class Baseline:
    """Phase 1: the calibrated baseline."""
    fit: Fit
    nuisance: dict               # fitted nuisance values
    residuals: Residuals         # `describe` of its residuals
    structure: bool              # residual structure beyond noise
    heldout_z: np.ndarray        # held-out standardised residuals
    nuisance_span: np.ndarray    # orthonormal basis of what the calibration can produce


@dataclass(frozen=True)
class Screening:
    """Phase 2: every candidate with its identifiability; the identifiable ones in order."""
    candidates: dict[str, Candidate]
    identifiable: list[str]
    lookalike: dict[str, dict[str, float]]
    #: CPU seconds per model call of each screened candidate's sensitivities (the cost the fits
    #: are scheduled by, `fitting.fit_all`; not part of the result)
    call_seconds: dict[str, float] = dataclasses.field(default_factory=dict)
    #: orthonormal bases of the identifiable candidates' projected sensitivities (the
    #: look-alike cosines of a candidate screened later, `screening.screen`'s `done`)
    bases: dict[str, np.ndarray] = dataclasses.field(default_factory=dict)
    #: candidates held for a later stage of the pass (`studies.diagnosis.staging`)
    held: tuple[str, ...] = ()


@dataclass(frozen=True)
class JointFit:
    """The best candidate fitted jointly with another (or with the unlisted sensor drift):
    chi-squares of each alone and of both, the p values of adding one to the other, whether the
    best carries the weight; `p` the drift check's p of adding the best to the drift; `error`
    when the joint fit failed (the best cannot be shown to carry the weight)."""
    best_carries_weight: bool
    chi2_best: float | None = None
    chi2_other: float | None = None
    chi2_joint: float | None = None
    p_add_other_to_best: float | None = None
    p_add_best_to_other: float | None = None
    p: float | None = None
    error: str | None = None

    def to_json(self) -> dict:
        """The fields that are set (a failed joint fit: its error)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class Decision:
    """Phase 5: the verdict. `goodness`: the best candidate's goodness of fit
    (`studies.diagnosis.goodness.GoodnessOfFit`, None when nothing passes); `beaten`: a note
    for the reason of each passing candidate the best clearly beats."""
    verdict: str
    cause: str | None
    best: str | None
    rivals: list
    best_residuals: Residuals | None
    joint_fits: dict[str, JointFit]
    reasons: list[str]
    goodness: object | None = None
    beaten: dict[str, str] = dataclasses.field(default_factory=dict)
