"""Operating characteristics of the diagnosis: a confusion matrix over injected causes, the
false-alarm rate, and the look-alike matrix of each test design computed before any data.

Trials. For each design (conditions, a model, its candidate effects) a hidden cause is injected:
none, each listed effect at a fixed plausible setting (`SETTINGS`), or an unlisted cause (a
torque-sensor drift linear in time, `unlisted_drift`). The data are the model's prediction with the
cause (friction scale `MU_TRUE`), plus Gaussian noise whose level is scaled so that the cause's
visible change has the stated magnitude: the RMS over all compared entries of
(truth - best baseline) / sigma, the baseline refitted (nuisance only) to the noise-free data, so
that what the calibration absorbs does not count. Magnitudes are in noise sigmas (`MAGNITUDES`);
the noise of a null trial is the design's base noise. Each dataset is diagnosed with every
candidate (`studies.diagnosis.engine.diagnose`).

Rates. False alarm: a null trial whose verdict is not `no_discrepancy`. Stated level: the union
bound alpha_structure + alpha_lr of the engine's thresholds (a false alarm needs the residual
structure test or a candidate's likelihood-ratio test to fire), checked against the binomial
99 % upper quantile for the number of null trials. Hit: `explained` with the injected cause;
named: hit or `ambiguous` with the cause among the rivals; wrong: `explained` with another cause.

Look-alike matrix (before any data): the engine's screening phase run on the design with the
noise-free baseline prediction as data and the base noise given: the cosine of the smallest
principal angle between two candidates' sensitivities after removing the span of the nuisance
calibration (`stats.max_cosine`). It depends only on the design, the model and the noise ratio
between columns.
"""
from __future__ import annotations

import time
from collections import Counter
from dataclasses import asdict, dataclass, field
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy import optimize, stats

from studies.diagnosis import fitspec
from studies.diagnosis.core import DEFAULT_THRESHOLDS
from studies.diagnosis.decision import SENSOR_DRIFT
from studies.diagnosis.engine import diagnose_full, lookalike_matrix

#: a magnitude below the detection threshold of every design (`detection.threshold_sigma`:
#: 0.97 sigma per column on 240 rows, 0.90 on 300, 1.60 on 64): a cause changing one of two
#: columns by this RMS over both changes that column by sqrt(2) x 0.25 = 0.35 sigma RMS: its
#: chi-square excess is an eighth of the threshold's (delta^2 0.125 against 0.94; the change
#: estimate passes the threshold in 0.05 % of draws on 240 rows), so nothing may be claimed
BELOW_DETECTION_SIGMA = 0.25
#: magnitudes of the injected causes: RMS visible change in noise sigmas over the compared
#: entries. The below-threshold one (nothing may be claimed), then 1 and 2 sigma, where a cause
#: in one column changes it by 1.4 and 2.8 sigma RMS, above the threshold: the matrix measures
#: naming there (at 1 sigma in both columns alike, at the threshold itself, the change
#: estimate passes it in about half the draws)
MAGNITUDES = (BELOW_DETECTION_SIGMA, 1.0, 2.0)
#: the rig's friction coefficient relative to the configured one in every trial
MU_TRUE = 1.2
#: plausible settings of the listed effects (their shapes; the size is set by the noise scaling)
SETTINGS = {
    "thermal_lag": {"tau_s": 600.0},
    "preload_settling": {"loss_N": 5.0, "threshold_K": 40.0},
    "friction_temperature": {"dmu_per_K": 2e-5},
    "cte_nonlinearity": {"dalpha_per_K": 1e-8},
    "interference_error": {"inner_um": 2.0, "outer_um": 0.0},
    "radial_gradient": {"dT_K": 0.0, "dT_per_krpm_K": 0.6},
    "viscosity_temperature": {"slope_factor": 1.3},
}
NONE, UNLISTED = "none", "unlisted_drift"


#: a profiled parameter's injected value: the grid point nearest this share of the grid's top
PROFILE_SHARE = 0.3


def setting(effect, conditions: Mapping[str, np.ndarray] | None = None,
            T_ref_C: float = 20.0) -> dict[str, float]:
    """The injected setting of an effect: `SETTINGS`, else each parameter at off + 5 x its scale
    (clipped to the bounds) for effects added after this table, with a profiled parameter (a time
    or revolution constant) at the point of the effect's grid on these conditions nearest
    PROFILE_SHARE x the grid's largest value. The grid spans what the design can show (for the
    run-in constant: from the revolutions of the first rows to those of the whole table), so the
    injected effect completes about 97 % of its change (1 - exp(-1/0.3)) within the design
    instead of, e.g., a 15 krev run-in finishing in the first rows of a 3000 rpm table, where the
    friction calibration absorbs it."""
    if effect.name in SETTINGS:
        return dict(SETTINGS[effect.name])
    out = {p: float(np.clip(effect.off[p] + 5.0 * effect.scale[p], *effect.bounds[p]))
           for p in effect.parameters}
    if conditions is not None:
        for p, g in fitspec.grid(effect, conditions, T_ref_C).items():
            if len(g):
                g = np.asarray(g, float)
                out[p] = float(g[np.argmin(np.abs(np.log(g / (PROFILE_SHARE * g.max()))))])
    return out


def unlisted_drift(conditions: Mapping[str, np.ndarray], n: int) -> np.ndarray:
    """Shape of the unlisted cause: a torque-sensor drift linear in time from 0 at the start
    (unit at the end; rows in order when there is no time column)."""
    t = np.asarray(conditions["time_s"], float) if "time_s" in conditions else np.arange(n, float)
    return (t - t[0]) / (t[-1] - t[0])


@dataclass
class Design:
    """One test design: its conditions, the model on them and what the diagnosis is given."""
    name: str
    conditions: dict[str, np.ndarray]
    predictor: Callable       # conditions -> (predict(effects, nuisance), predict_at or None)
    candidates: list          # effect objects
    nuisance: dict
    sigma: dict[str, float]   # base noise per column (column unit)
    T_ref_C: float
    hidden: list[str] | None = None   # listed effects injected (None: every candidate the
                                      # design can identify, from the before-data screening)


@dataclass
class Trial:
    design: str
    hidden: str               # effect name, NONE or UNLISTED
    magnitude_sigma: float    # 0 for none
    rep: int
    verdict: str
    cause: str | None
    indistinguishable: list[str]
    open_world_lead: str | None     # first selected feature of the torque (unexplained only)
    seconds: float
    best_partial: str | None = None          # best candidate of an `unexplained` verdict
    drift_adds_p: float | None = None        # p of adding a sensor drift to the best candidate


@dataclass(frozen=True)
class FalseAlarm:
    """The null trials: how many, how many with a verdict other than `no_discrepancy`, how many
    with a cause claimed (`explained`, `explained_partly` or `ambiguous`), the rate, the stated
    level and its binomial 99 % upper quantile for this many trials."""
    trials: int
    false_alarms: int
    cause_claimed: int
    rate: float | None
    stated_level: float
    binomial_99_bound: int | None


@dataclass(frozen=True)
class Rate:
    """Outcomes of the trials of one design, hidden cause and magnitude (module docstring)."""
    design: str
    hidden: str
    magnitude_sigma: float
    trials: int
    explained_right: int
    named: int
    explained_wrong: int
    cause_claimed: int
    unexplained: int
    no_discrepancy: int
    open_world_time: int
    explained_partly: int = 0


@dataclass
class Matrix:
    """Every trial, the look-alike matrices and the summary rates (`summarise`)."""
    magnitudes_sigma: tuple
    trials: list[Trial]
    lookalike: dict[str, dict[str, dict[str, float]]]      # design -> a -> b -> cosine
    false_alarm: FalseAlarm | None = None
    not_visible: dict[str, list[str]] = field(default_factory=dict)   # design -> effects
    rates: list[Rate] = field(default_factory=list)

    def to_json(self) -> dict:
        return asdict(self)


def lookalike_before_data(d: Design) -> dict[str, dict[str, float]]:
    """The look-alike matrix of a design before any data (module docstring)."""
    predict, predict_at = d.predictor(d.conditions)
    truth = predict({}, {k: v[2] if len(v) > 2 else 1.0 for k, v in d.nuisance.items()})
    meas = {c: np.asarray(truth[c], float) for c in d.sigma}
    return lookalike_matrix(predict, meas, d.conditions, d.candidates, d.nuisance, d.sigma,
                            d.T_ref_C, predict_at)


def visible_rms_sigma(predict, truth: dict, sigma: dict, nuisance: dict) -> float:
    """RMS over the compared entries of (truth - best baseline) / sigma, the baseline's nuisance
    refitted by bounded least squares (module docstring)."""
    names = list(nuisance)
    lo = [nuisance[k][0] for k in names]
    hi = [nuisance[k][1] for k in names]
    x0 = [MU_TRUE if lo[i] <= MU_TRUE <= hi[i] else 0.5 * (lo[i] + hi[i]) for i in range(len(names))]

    def res(x):
        b = predict({}, dict(zip(names, x)))
        return np.concatenate([(truth[c] - b[c]) / s for c, s in sigma.items()])
    r = optimize.least_squares(res, x0, bounds=(lo, hi), diff_step=1e-4).fun
    return float(np.sqrt(np.mean(r ** 2)))


def dataset(d: Design, hidden: str, magnitude: float, rng) -> dict[str, np.ndarray] | None:
    """Noisy data of one trial (module docstring); None when the hidden cause at its setting
    changes nothing the calibrated baseline cannot reproduce (RMS below 1e-9 sigma)."""
    predict, _ = d.predictor(d.conditions)
    nuis = {k: MU_TRUE for k in d.nuisance}
    n = len(next(iter(d.conditions.values())))
    if hidden == NONE:
        truth = predict({}, nuis)
        sig = dict(d.sigma)
    else:
        if hidden == UNLISTED:
            truth = {c: np.array(v, float) for c, v in predict({}, nuis).items()}
            c0 = next(iter(d.sigma))
            truth[c0] = truth[c0] + d.sigma[c0] * unlisted_drift(d.conditions, n)
        else:
            eff = next(e for e in d.candidates if e.name == hidden)
            truth = predict({hidden: setting(eff, d.conditions, d.T_ref_C)}, nuis)
        v = visible_rms_sigma(predict, truth, d.sigma, d.nuisance)
        if v < 1e-9:
            return None
        f = v / magnitude
        sig = {c: s * f for c, s in d.sigma.items()}
    return {c: np.asarray(truth[c], float) + rng.normal(0.0, s, n) for c, s in sig.items()}


def run_matrix(designs: Sequence[Design], magnitudes=MAGNITUDES, reps: int = 3, n_null: int = 10,
               seed: int = 0, progress=lambda s: None) -> Matrix:
    """Every design x hidden cause x magnitude x repetition (n_null repetitions of none)."""
    rng = np.random.default_rng(seed)
    trials: list[Trial] = []
    look = {}
    skipped: dict[str, list[str]] = {}
    for d in designs:
        look[d.name] = lookalike_before_data(d)
        hidden = list(look[d.name]) if d.hidden is None else list(d.hidden)
        plan = [(NONE, 0.0, k) for k in range(n_null)]
        plan += [(h, m, k) for h in [*hidden, UNLISTED] for m in magnitudes for k in range(reps)]
        predict, predict_at = d.predictor(d.conditions)
        for hidden, m, k in plan:
            if hidden in skipped.get(d.name, []):
                continue
            meas = dataset(d, hidden, m, rng)
            if meas is None:
                skipped.setdefault(d.name, []).append(hidden)
                progress(f"{d.name}: {hidden} at its setting is not visible here; left out")
                continue
            t0 = time.perf_counter()
            res = diagnose_full(predict, meas, d.conditions, d.candidates, d.nuisance,
                                predict_at=predict_at, T_ref_C=d.T_ref_C, seed=k)
            ow_columns = res.open_world.columns if res.open_world is not None else []
            lead = next((c.selected[0] for c in ow_columns
                         if c.depends and c.column == next(iter(d.sigma))), None)
            drift = res.joint_fits.get(SENSOR_DRIFT)
            trials.append(Trial(d.name, hidden, m, k, res.verdict, res.cause,
                                list(res.indistinguishable), lead,
                                time.perf_counter() - t0,
                                res.best_partial.effect if res.best_partial else None,
                                drift.p_add_other_to_best if drift else None))
            progress(f"{d.name}: {hidden} at {m:g} sigma #{k}: {res.verdict} {res.cause}")
    out = Matrix(tuple(magnitudes), trials, look, not_visible=skipped)
    summarise(out)
    return out


def stated_false_alarm_level(th: Mapping = DEFAULT_THRESHOLDS) -> float:
    """Union bound of the gates a false alarm must pass: alpha_structure + alpha_lr."""
    return float(th["alpha_structure"] + th["alpha_lr"])


#: verdicts that claim a cause
CLAIMS = ("explained", "explained_partly", "ambiguous")


def summarise(mx: Matrix) -> None:
    """Fill the false-alarm entry and the per-(design, hidden, magnitude) rates. A cause is
    claimed by `explained`, `explained_partly` (the cause carries weight) and `ambiguous`; a
    wrong explanation is `explained` or `explained_partly` with another cause."""
    nulls = [t for t in mx.trials if t.hidden == NONE]
    level = stated_false_alarm_level()
    fa = sum(t.verdict != "no_discrepancy" for t in nulls)
    claims = sum(t.verdict in CLAIMS for t in nulls)
    mx.false_alarm = FalseAlarm(len(nulls), fa, claims, fa / len(nulls) if nulls else None,
                                level, (int(stats.binom.ppf(0.99, len(nulls), level))
                                        if nulls else None))
    groups: dict[tuple, list[Trial]] = {}
    for t in mx.trials:
        groups.setdefault((t.design, t.hidden, t.magnitude_sigma), []).append(t)
    explains = ("explained", "explained_partly")
    mx.rates = [Rate(
        dn, h, m, len(ts),
        explained_right=sum(t.verdict in explains and t.cause == h for t in ts),
        named=sum(t.verdict in CLAIMS and (t.cause == h or h in t.indistinguishable)
                  for t in ts),
        explained_wrong=sum(t.verdict in explains and t.cause != h for t in ts),
        cause_claimed=sum(t.verdict in CLAIMS for t in ts),
        unexplained=sum(t.verdict == "unexplained" for t in ts),
        no_discrepancy=sum(t.verdict == "no_discrepancy" for t in ts),
        open_world_time=sum(t.open_world_lead == "time_since_start_s" for t in ts),
        explained_partly=sum(t.verdict == "explained_partly" for t in ts))
        for (dn, h, m), ts in groups.items()]


def column_label(t: Trial) -> str:
    """The confusion-matrix column of a trial's outcome."""
    if t.verdict in ("explained", "explained_partly"):
        return f"{t.verdict}: {t.cause}"
    return t.verdict


def markdown(mx: Matrix) -> list[str]:
    """The confusion matrices (one per design), rates and look-alike matrices as markdown."""
    L = []
    fa = mx.false_alarm
    L.append(f"False alarms on nulls (verdict other than `no_discrepancy`): {fa.false_alarms}/"
             f"{fa.trials} = {fa.rate:.1%} (stated level {fa.stated_level:.0%}, binomial "
             f"99 % bound {fa.binomial_99_bound}); cause claimed on nulls: "
             f"{fa.cause_claimed}/{fa.trials}.\n")
    for dn in dict.fromkeys(t.design for t in mx.trials):
        ts = [t for t in mx.trials if t.design == dn]
        cols = sorted({column_label(t) for t in ts},
                      key=lambda c: (not c.startswith("no_"), c.startswith("unexpl"), c))
        L.append(f"### Design `{dn}`: confusion matrix (rows: hidden cause at magnitude, "
                 "columns: verdict / cause; counts)\n")
        L.append("| hidden | sigma | " + " | ".join(cols) + " | named | wrong |")
        L.append("| --- | --- |" + " --- |" * (len(cols) + 2))
        for r in (r for r in mx.rates if r.design == dn):
            sub = [t for t in ts if t.hidden == r.hidden
                   and t.magnitude_sigma == r.magnitude_sigma]
            cnt = Counter(column_label(t) for t in sub)
            extra = (f"{r.named}/{r.trials} | {r.explained_wrong}"
                     if r.hidden not in (NONE, UNLISTED)
                     else f"– | {r.cause_claimed} claimed")
            L.append(f"| `{r.hidden}` | {r.magnitude_sigma:g} | "
                     + " | ".join(str(cnt.get(c, "")) for c in cols) + f" | {extra} |")
        L.append("")
        if mx.not_visible.get(dn):
            L.append("Not injected (no visible change at its setting in this design): "
                     + ", ".join(f"`{x}`" for x in mx.not_visible[dn]) + ".\n")
        look = mx.lookalike.get(dn) or {}
        if look:
            names = list(look)
            L.append(f"Look-alike matrix of `{dn}` before any data (max cosine):\n")
            L.append("| | " + " | ".join(f"`{x}`" for x in names) + " |")
            L.append("| --- " * (len(names) + 1) + "|")
            for a in names:
                L.append(f"| `{a}` | " + " | ".join(f"{look[a][b]:.2f}" for b in names) + " |")
            L.append("")
    return L
