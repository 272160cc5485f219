"""Open-world characterisation: when no listed effect removes the structure from the residuals,
say what the residual depends on, how much a small data-driven correction on those conditions
gains on held-out data, and which class of cause fits that dependence (a hypothesis, with the
test that would confirm it).

Method (per compared column):

1. Named features from the conditions, each a physical quantity with its unit
   (`named_features`): time since the start, temperature, its rate of change dT/dt, accumulated
   thermal cycles, accumulated revolutions, speed, preload and external loads, whichever the data
   have and which vary. A feature proportional to an earlier one (|correlation| > ALIAS_CORR, e.g.
   revolutions at constant speed = time) is not a separate feature and is reported as its alias.
2. The residual in noise units (whitened for the column's AR(1) noise, as in the engine) is
   regressed on an intercept plus the features by forward selection: at each step the feature that
   lowers the residual sum of squares most is added while the Bayesian information criterion
   BIC = n ln(SSE / n) + k ln n falls (Schwarz 1978, Ann. Statist. 6, 461; the Gaussian
   log-likelihood with the variance profiled out), at most MAX_FEATURES features.
3. Held-out gain by nested block cross-validation: for each held-out block the whole selection
   (step 2) is repeated on the other blocks, the chosen correction predicts the held-out block, and
   gain = 1 - SSE_heldout(correction) / SSE_heldout(mean of the training residual) (Hastie,
   Tibshirani & Friedman, The Elements of Statistical Learning, 2nd ed., sec. 7.10.2: the selection
   belongs inside the cross-validation loop). The residual is said to depend on the selected
   features only when the gain is positive.
4. The class of cause is named from the feature that moves the residual most over its range in
   the data (`HYPOTHESES`), as a hypothesis with a confirming test; features too correlated with it
   in this design (|correlation| > SEPARABLE_CORR) are named as not separable here.

Units: features as named (s, C, K/s, cycles, rev, rpm, N); slopes in column unit per feature unit;
`range_effect` in the column's unit (slope x the feature's range in the data); gains dimensionless.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Mapping

import numpy as np

from studies.diagnosis.stats import ar1_whiten

#: at most this many features in the correction (a sparse, readable model)
MAX_FEATURES = 4
#: a feature this correlated with an earlier one is the same quantity in this design
ALIAS_CORR = 0.999
#: a selected feature this correlated with another cannot be told apart from it in this design
SEPARABLE_CORR = 0.95

#: feature -> (class of cause, the test that would confirm it)
HYPOTHESES = {
    "time_since_start_s": (
        "sensor drift (or a slow change with elapsed time, e.g. ageing or creep)",
        "hold every condition constant for as long as the test lasted, and re-zero or calibrate "
        "the sensor against a reference before and after: a drift keeps growing at constant "
        "conditions and disappears after re-zeroing"),
    "temperature_C": (
        "a temperature dependence the model lacks (a material property, friction or fit law)",
        "a steady temperature sweep with long dwells at one speed and preload, in both directions: "
        "a property of temperature gives the same residual up and down"),
    "dTdt_K_per_s": (
        "a thermal lag (parts not at the chamber temperature while it changes)",
        "repeat the ramps at a different rate (e.g. half and double) or measure the ring "
        "temperatures: a lag's residual scales with the ramp rate and vanishes in dwells"),
    "thermal_cycles": (
        "run-in or wear with accumulated thermal cycles (e.g. solid-film transfer)",
        "repeat the same cycle several times and compare with one dwell of the same total "
        "duration: run-in changes from cycle to cycle and settles; elapsed time alone does not"),
    "revolutions": (
        "run-in or wear with accumulated revolutions (film transfer, raceway polishing)",
        "run the same duration at two speeds: run-in follows the revolutions, a drift the time"),
    "speed_rpm": (
        "speed-dependent heat (churning or viscous heating raising the part temperatures)",
        "measure the ring temperatures at several speeds at one chamber temperature: the "
        "residual should follow the temperature rise with speed"),
    "preload_assembled_N": (
        "a load dependence the model lacks (contact stiffness, friction law or clamp compliance)",
        "a preload sweep at one temperature and speed, measuring the axial stiffness"),
    "axial_load_N": (
        "an axial-load dependence the model lacks (contact or mounting compliance)",
        "an axial-load sweep at one temperature and speed"),
    "radial_load_N": (
        "a radial-load dependence the model lacks (ring or housing compliance)",
        "a radial-load sweep at one temperature and speed"),
}


@dataclass
class ColumnCharacterisation:
    """What one column's residual depends on (units: module docstring)."""
    column: str
    selected: list[str]                       # features in the order chosen
    slopes: dict[str, float]                  # column unit per feature unit
    range_effect: dict[str, float]            # column unit: slope x feature range in the data
    bic_path: list[dict]                      # [{"feature": ..., "bic": ...}] from intercept only
    heldout_gain: float                       # nested block cross-validation, 1 - SSE ratio
    heldout_selected: list[list[str]]         # the selection made on each training set
    depends: bool                             # selected features and positive held-out gain
    not_separable: dict[str, list[str]] = field(default_factory=dict)
    hypothesis: str | None = None
    confirming_test: str | None = None
    model_forms: list[str] = field(default_factory=list)   # the ladder's forms through the lead


@dataclass
class OpenWorld:
    """The characterisation of the residual (the `open_world` key of diagnosis.json)."""
    residual_of: str                          # which model's residual was characterised
    features: dict[str, str]                  # name -> what it is
    aliases: dict[str, str]                   # feature left out -> the feature it equals here
    columns: list[ColumnCharacterisation]
    summary: str

    def to_json(self) -> dict:
        return asdict(self)


def _temperature(conditions: Mapping[str, np.ndarray]) -> np.ndarray | None:
    """The temperature of the test: the ambient (chamber) column, or the mean of the part
    temperature columns when only those are given (C)."""
    if "T_ambient_C" in conditions:
        return np.asarray(conditions["T_ambient_C"], float)
    parts = [np.asarray(v, float) for k, v in conditions.items()
             if k.startswith("T_") and k.endswith("_C")]
    return np.mean(parts, axis=0) if parts else None


def named_features(conditions: Mapping[str, np.ndarray]) -> tuple[dict[str, np.ndarray],
                                                                  dict[str, str], dict[str, str]]:
    """Physically named features of the conditions (module docstring, step 1).

    Formulas (t time s, T temperature C, n speed rpm):
    time_since_start_s = t - t_0; dTdt_K_per_s = dT/dt (central differences, `numpy.gradient`);
    thermal_cycles = sum |dT| / (2 (T_max - T_min)) (one full cycle travels the range twice);
    revolutions = sum n/60 dt (trapezoidal).

    Returns (features, descriptions, aliases): features that do not vary are left out; a feature
    proportional to an earlier one is left out and named in aliases."""
    c = {k: np.asarray(v, float) for k, v in conditions.items()}
    feats: dict[str, np.ndarray] = {}
    desc: dict[str, str] = {}
    aliases: dict[str, str] = {}
    for name, x, what in _candidate_features(c):
        if not np.all(np.isfinite(x)) or np.std(x) == 0:
            continue
        same = next((k for k, y in feats.items()
                     if abs(np.corrcoef(x, y)[0, 1]) > ALIAS_CORR), None)
        if same is not None:
            aliases[name] = same
            continue
        feats[name], desc[name] = x, what
    return feats, desc, aliases


def _candidate_features(c: Mapping[str, np.ndarray]) -> list[tuple[str, np.ndarray, str]]:
    """(name, values, description) of every named feature these conditions give (formulas:
    `named_features`), in the order they are preferred when two are the same quantity."""
    t = c.get("time_s")
    timed = t is not None and t.size > 2 and np.all(np.diff(t) > 0)
    T = _temperature(c)
    cand: list[tuple[str, np.ndarray, str]] = []
    if timed:
        cand.append(("time_since_start_s", t - t[0], "time since the start of the test (s)"))
    if T is not None:
        cand.append(("temperature_C", T, "test temperature (C; chamber, or mean of the parts)"))
        if timed:
            cand.append(("dTdt_K_per_s", np.gradient(T, t), "rate of change of the temperature "
                         "(K/s)"))
            span = float(np.ptp(T))
            if span > 0:
                travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(T)))])
                cand.append(("thermal_cycles", travel / (2.0 * span),
                             "accumulated thermal cycles (temperature travel / twice the range)"))
    if "speed_rpm" in c:
        if timed:
            rev = np.concatenate([[0.0], np.cumsum(0.5 * (c["speed_rpm"][1:] + c["speed_rpm"][:-1])
                                                   / 60.0 * np.diff(t))])
            cand.append(("revolutions", rev, "accumulated revolutions (rev)"))
        cand.append(("speed_rpm", c["speed_rpm"], "shaft speed (rpm)"))
    for k, what in (("preload_assembled_N", "assembled preload (N)"),
                    ("axial_load_N", "external axial load (N)"),
                    ("radial_load_N", "external radial load (N)")):
        if k in c:
            cand.append((k, c[k], what))
    return cand


def _bic(sse: float, n: int, k: int) -> float:
    """Schwarz (1978) BIC of a Gaussian linear model with k coefficients, variance profiled out."""
    return n * math.log(max(sse, 1e-300) / n) + k * math.log(n)


def _sse(A: np.ndarray, y: np.ndarray) -> tuple[float, np.ndarray]:
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    e = y - A @ coef
    return float(e @ e), coef


def forward_select(y: np.ndarray, X: np.ndarray, one: np.ndarray,
                   max_features: int = MAX_FEATURES) -> tuple[list[int], list[float]]:
    """Forward selection by BIC (module docstring, step 2): y ~ one + X[:, selected].
    Returns the selected column indices in order and the BIC after each step (the first entry is
    the intercept-only model)."""
    n = y.size
    chosen: list[int] = []
    A = one[:, None]
    sse, _ = _sse(A, y)
    path = [_bic(sse, n, 1)]
    while len(chosen) < min(max_features, X.shape[1]):
        best = None
        for j in range(X.shape[1]):
            if j in chosen:
                continue
            s, _ = _sse(np.column_stack([A, X[:, j]]), y)
            if best is None or s < best[1]:
                best = (j, s)
        if best is None:
            break
        bic = _bic(best[1], n, A.shape[1] + 1)
        if bic >= path[-1]:
            break
        chosen.append(best[0])
        A = np.column_stack([A, X[:, best[0]]])
        path.append(bic)
    return chosen, path


def characterise_column(column: str, residual: np.ndarray, feats: Mapping[str, np.ndarray],
                        blocks: np.ndarray, sigma_w: float, rho: float = 0.0
                        ) -> ColumnCharacterisation:
    """One column: residual (column unit, valid rows only), features on the same rows, held-out
    block labels, the noise innovation level sigma_w (column unit) and its AR(1) coefficient rho
    (0 = white). Steps 2-4 of the module docstring."""
    names = list(feats)
    r = np.asarray(residual, float)
    n = r.size
    Xraw = np.column_stack([feats[k] for k in names]) if names else np.zeros((n, 0))
    mu, sd = Xraw.mean(axis=0), Xraw.std(axis=0)
    sd = np.where(sd > 0, sd, 1.0)
    Xs = (Xraw - mu) / sd
    y = ar1_whiten(r, blocks, rho) / sigma_w
    X = ar1_whiten(Xs, blocks, rho) if names else Xs
    one = ar1_whiten(np.ones(n), blocks, rho)
    chosen, path = forward_select(y, X, one)
    sel = [names[j] for j in chosen]
    A = np.column_stack([one] + [X[:, j] for j in chosen])
    _, coef = _sse(A, y)
    slopes = {names[j]: float(coef[i + 1] * sigma_w / sd[j]) for i, j in enumerate(chosen)}
    ranges = {k: float(slopes[k] * np.ptp(feats[k])) for k in sel}
    gain, ho_sel = _nested_cv_gain(y, X, one, blocks, names)
    depends = bool(sel) and gain > 0.0
    out = ColumnCharacterisation(column, sel, slopes, ranges,
                                 [{"feature": None, "bic": path[0]}]
                                 + [{"feature": k, "bic": v} for k, v in zip(sel, path[1:])],
                                 float(gain), ho_sel, depends)
    if depends:
        _name_hypothesis(out, feats)
    return out


def _nested_cv_gain(y: np.ndarray, X: np.ndarray, one: np.ndarray, blocks: np.ndarray,
                    names: list[str]) -> tuple[float, list[list[str]]]:
    """Nested block cross-validation (step 3): per held-out block the selection redone on the
    other blocks; 1 - SSE / SSE(intercept only) over the held-out blocks, and the selections."""
    sse_cv = sse_0 = 0.0
    ho_sel: list[list[str]] = []
    for b in np.unique(blocks):
        tr, te = blocks != b, blocks == b
        if tr.sum() < 10 or te.sum() == 0:
            continue
        ch, _ = forward_select(y[tr], X[tr], one[tr])
        ho_sel.append([names[j] for j in ch])
        At = np.column_stack([one] + [X[:, j] for j in ch])
        _, c = _sse(At[tr], y[tr])
        sse_cv += float(np.sum((y[te] - At[te] @ c) ** 2))
        c0 = float(one[tr] @ y[tr]) / float(one[tr] @ one[tr])
        sse_0 += float(np.sum((y[te] - one[te] * c0) ** 2))
    return (1.0 - sse_cv / sse_0 if sse_0 > 0 else 0.0), ho_sel


def _name_hypothesis(out: ColumnCharacterisation, feats: Mapping[str, np.ndarray]) -> None:
    """Step 4: the class of cause from the selected feature that moves the residual most, and
    the features each selected one cannot be separated from here."""
    sel, names = out.selected, list(feats)
    lead = max(sel, key=lambda k: abs(out.range_effect[k]))
    out.hypothesis, out.confirming_test = HYPOTHESES.get(
        lead, (f"a dependence on {lead} the model lacks", f"vary {lead} alone"))
    for k in sel:
        near = [m for m in names if m != k
                and abs(np.corrcoef(feats[k], feats[m])[0, 1]) > SEPARABLE_CORR]
        if near:
            out.not_separable[k] = near


def _name_forms(out: ColumnCharacterisation, forms: Mapping[str, tuple[str, ...]]) -> None:
    """The model forms acting through the lead feature (or one not separable from it), named in
    front of the generic hypothesis (the model's own forms first)."""
    if not out.depends or not forms:
        return
    lead = max(out.selected, key=lambda k: abs(out.range_effect[k]))
    near = {lead, *out.not_separable.get(lead, [])}
    out.model_forms = [f for f, acts in forms.items() if near & set(acts)]
    if out.model_forms:
        out.hypothesis = (f"a model form acting through {lead} ({', '.join(out.model_forms)}: "
                          f"see their entries among the candidates), else {out.hypothesis}")


def characterise(residuals: Mapping[str, np.ndarray], valid: Mapping[str, np.ndarray],
                 conditions: Mapping[str, np.ndarray], blocks: np.ndarray,
                 sigma_w: Mapping[str, float], rho: Mapping[str, float],
                 residual_of: str = "baseline",
                 forms: Mapping[str, tuple[str, ...]] | None = None) -> OpenWorld:
    """Characterise the residuals (measured - model, column unit, all rows) of every column on the
    valid rows; `blocks` are the held-out block labels per row, `sigma_w` and `rho` the noise
    innovation level and AR(1) coefficient per column (as the engine estimated them). `forms`:
    the model forms of the ladder tried ({name: the features it acts through},
    `studies.diagnosis.ladder`): the hypothesis names those acting through the lead feature (or
    one not separable from it) before the generic class of cause."""
    feats, desc, aliases = named_features(conditions)
    cols = []
    for c, r in residuals.items():
        m = np.asarray(valid[c], bool)
        cols.append(characterise_column(c, np.asarray(r, float)[m],
                                        {k: v[m] for k, v in feats.items()}, np.asarray(blocks)[m],
                                        float(sigma_w[c]), float(rho.get(c, 0.0))))
    for cc in cols:
        _name_forms(cc, forms or {})
    hits = [cc for cc in cols if cc.depends]
    if not feats:
        summary = "no condition varies: nothing to characterise the residual by"
    elif not hits:
        summary = ("the residual does not depend on any named condition in a way that predicts "
                   "held-out blocks")
    else:
        summary = "; ".join(
            f"{cc.column} depends on {', '.join(cc.selected)} (held-out gain "
            f"{cc.heldout_gain:.2f}): hypothesis {cc.hypothesis}" for cc in hits)
    return OpenWorld(residual_of, desc, aliases, cols, summary)


def report_lines(ow: OpenWorld | None) -> list[str]:
    """The report section (markdown lines) for the open-world characterisation of a result."""
    if ow is None:
        return []
    L = ["## What the residual depends on (open world)\n",
         f"No listed effect removes the structure, so the {ow.residual_of} residual was "
         "regressed on named conditions (forward selection by BIC, nested block "
         "cross-validation). **Hypotheses, not findings**: confirm with the test named.\n",
         f"Summary: {ow.summary}.\n",
         "| column | depends on | change over the data (column unit) | held-out gain | "
         "hypothesis | confirming test |",
         "| --- | --- | --- | --- | --- | --- |"]
    for c in ow.columns:
        dep = ", ".join(f"`{k}`" for k in c.selected) or "–"
        rng = ", ".join(f"{k}: {v:+.3g}" for k, v in c.range_effect.items()) or "–"
        hyp = c.hypothesis or "–"
        if c.not_separable:
            hyp += " (not separable here from: " + "; ".join(
                f"{k} ~ {', '.join(v)}" for k, v in c.not_separable.items()) + ")"
        L.append(f"| `{c.column}` | {dep} | {rng} | {c.heldout_gain:.3f} | {hyp} | "
                 f"{c.confirming_test or '–'} |")
    L.append("")
    if ow.aliases:
        L.append("Same quantity in this design (left out): " + ", ".join(
            f"`{a}` = `{b}`" for a, b in ow.aliases.items()) + ".\n")
    return L
