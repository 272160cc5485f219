"""Human-readable diagnosis report: `report.md` with PNG plots (matplotlib, Agg, no pyplot state).

`write_report(result, conditions, measured, out_dir)` writes

- `report.md`: verdict and cause with fitted parameters and uncertainties, held-out gain, what the
  baseline gets wrong (residual statistics per column), the candidate table, identifiability and
  look-alikes, the comparison of rivals, the separating test, method and thresholds;
- `fit_<column>.png`: measured vs baseline vs extended model against time (or row) and against every
  varying condition, with the claimed model's predictive interval as a band on the time axis;
- `residuals_<column>.png`: residuals of the baseline and of the extended model, same axes, with
  the noise band (+-2 sigma);
- `candidates.png`: delta BIC and held-out RMSE ratio per candidate.

`result` is the typed `DiagnosisResult` of `studies.diagnosis.engine.diagnose_full` (with the
baseline and extended predictions). Each section of report.md is one small function.
"""
from __future__ import annotations

import math
from functools import partial
from pathlib import Path
from typing import Mapping

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from studies.diagnosis.openworld import report_lines
from studies.diagnosis.result import HELDOUT_METHOD, DiagnosisResult
from studies.model.parallel import parallel_map

MAX_PANELS = 6


def _fmt(v, digits=4):
    if v is None:
        return "–"
    if isinstance(v, dict):
        if "interval" in v:
            a, b = v["interval"]
            return f"in [{_fmt(a)}, {_fmt(b)}]"
        return ", ".join(f"{k} {_fmt(x)}" for k, x in v.items())
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(x, digits) for x in v) + "]"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            return "–"
        if v == 0:
            return "0"
        if abs(v) >= 1e5 or abs(v) < 1e-3:
            return f"{v:.{digits - 1}e}"
        return f"{v:.{digits}g}"
    return str(v)


def _pm(value, unc):
    if isinstance(unc, dict) or unc is None:
        return f"{_fmt(value)}" + (f" ({_fmt(unc)})" if unc is not None else " (uncertainty: "
                                   "not separately identifiable)")
    return f"{_fmt(value)} ± {_fmt(unc, 2)}"


#: PNG compression of the plots: zlib level 1 (the files ~1.5x larger than at matplotlib's
#: default 6, written in about a third of the time; measured 2026-11-29 on the flywheel
#: diagnosis's four-panel plots: 0.47 -> 0.36 CPU s a plot with the fixed margins below)
PNG_COMPRESS_LEVEL = 1


def _save(fig: Figure, path: Path):
    FigureCanvasAgg(fig)
    fig.savefig(path, dpi=110, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})


#: margins (inches) of the one-row panel plots: fixed, because constrained layout lays each
#: figure out by drawing it once more (0.67 -> 0.47 CPU s a four-panel plot, measured as above)
PANEL_MARGINS_IN = {"left": 0.85, "right": 0.2, "bottom": 0.55, "top": 0.5, "between": 0.95}


def _panels(n: int, width_in: float = 5.0, height_in: float = 4.0):
    """A figure of `n` panels side by side, each `width_in` wide, with PANEL_MARGINS_IN; returns
    (figure, axes)."""
    m = PANEL_MARGINS_IN
    w = width_in * n
    fig = Figure(figsize=(w, height_in))
    inner = w - m["left"] - m["right"]
    axes = fig.subplots(1, n, squeeze=False)[0]
    fig.subplots_adjust(left=m["left"] / w, right=1.0 - m["right"] / w,
                        bottom=m["bottom"] / height_in, top=1.0 - m["top"] / height_in,
                        wspace=m["between"] * n / max(inner - m["between"] * (n - 1), 1e-9))
    return fig, axes


def _axes_keys(conditions: Mapping[str, np.ndarray]) -> tuple[str, list[str]]:
    xs = "time_s" if "time_s" in conditions else "row"
    varying = [k for k, v in conditions.items()
               if k != "time_s" and np.nanstd(np.asarray(v, float)) > 0]
    return xs, varying[:MAX_PANELS - 1]


def _x(conditions, key, n):
    return np.arange(n) if key == "row" else np.asarray(conditions[key], float)


def _plot_fits(col, conditions, measured, base, ext, cause, out: Path, n, band=None):
    """band: (lo, hi) of the extended model's predictive interval (None: no claim)."""
    xs, varying = _axes_keys(conditions)
    keys = [xs] + varying
    fig, axes = _panels(len(keys))
    ext_label = f"extended ({cause})" if cause else "extended (= baseline)"
    for ax, key in zip(axes, keys):
        x = _x(conditions, key, n)
        if key == xs:
            ax.plot(x, measured, ".", ms=3, color="0.55", label="measured")
            ax.plot(x, base, "-", lw=1.3, color="tab:red", label="baseline (calibrated)")
            if cause:
                ax.plot(x, ext, "-", lw=1.3, color="tab:blue", label=ext_label)
            if band is not None:
                ax.fill_between(x, band[0], band[1], color="tab:blue", alpha=0.2, lw=0,
                                label=_band_label(band))
        else:
            ax.plot(x, measured, ".", ms=3, color="0.55", label="measured")
            ax.plot(x, base, "x", ms=3, color="tab:red", label="baseline (calibrated)")
            if cause:
                ax.plot(x, ext, "+", ms=4, color="tab:blue", label=ext_label)
        ax.set_xlabel(key)
        ax.set_ylabel(col)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{col}: measured vs baseline vs extended model")
    _save(fig, out)


def _band_label(band) -> str:
    return f"{100 * band[2]:g} % predictive interval"


def _plot_residuals(col, conditions, measured, base, ext, cause, sigma, out: Path, n,
                    band=None):
    """band: (lo, hi, level) of the extended model's predictive interval (None: no claim),
    drawn about the extended model (hi - ext, lo - ext) on the time (or row) axis."""
    xs, varying = _axes_keys(conditions)
    keys = [xs] + varying
    fig, axes = _panels(len(keys))
    rb = measured - base
    re = measured - ext
    for ax, key in zip(axes, keys):
        x = _x(conditions, key, n)
        style = "-" if key == xs else "."
        ax.plot(x, rb, style, lw=0.9, ms=3, color="tab:red", label="baseline residual")
        if cause:
            ax.plot(x, re, style, lw=0.9, ms=3, color="tab:blue", alpha=0.8,
                    label=f"after {cause}")
        if sigma:
            ax.axhspan(-2 * sigma, 2 * sigma, color="0.85", zorder=0, label="±2 noise sigma")
        if band is not None and key == xs:
            ax.fill_between(x, band[0] - ext, band[1] - ext, color="tab:blue", alpha=0.15,
                            lw=0, label=_band_label(band))
        ax.axhline(0, color="k", lw=0.6)
        ax.set_xlabel(key)
        ax.set_ylabel(f"measured - model, {col}")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{col}: residuals before and after")
    _save(fig, out)


def _plot_candidates(result: DiagnosisResult, out: Path):
    cands = [c for c in result.candidates if c.delta_bic is not None]
    if not cands:
        return False
    c0 = result.columns[0]
    base_ho = result.baseline.heldout_rmse[c0]
    names = [c.effect for c in cands]
    dbic = [c.delta_bic for c in cands]
    ratio = [c.heldout_rmse[c0] / base_ho if base_ho else 1.0 for c in cands]
    colors = ["tab:green" if c.status == "passed" else "0.6" for c in cands]
    fig = Figure(figsize=(10, 0.5 * len(cands) + 1.8), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    y = np.arange(len(cands))[::-1]
    a1.barh(y, dbic, color=colors)
    a1.set_yticks(y, names)
    a1.axvline(0, color="k", lw=0.6)
    a1.set_xscale("symlog", linthresh=10)
    a1.set_xlabel("delta BIC vs baseline (negative = better)")
    a2.barh(y, ratio, color=colors)
    a2.set_yticks(y, names)
    a2.axvline(1, color="k", lw=0.6)
    a2.set_xlabel(f"held-out RMSE / baseline ({c0})")
    fig.suptitle("candidates (green: passed the tests)")
    _save(fig, out)
    return True


def _draw_plots(result: DiagnosisResult, conditions, measured, out: Path, workers: int
                ) -> tuple[list[tuple[str, str, str]], bool]:
    """The PNG plots (on `workers` processes, the same files): per column (column, fit plot,
    residual plot) and whether the candidates' plot was drawn."""
    n = result.n_rows
    figs, plots = [], []
    for c in result.columns:
        m = np.asarray(measured[c], float)
        b = np.asarray(result.baseline_pred[c], float)
        e = np.asarray(result.extended_pred[c], float)
        safe = c.replace("/", "_")
        iv = result.interval.columns.get(c) if result.interval is not None else None
        band = None if iv is None else (iv.lo, iv.hi, result.interval.level)
        plots.append(partial(_plot_fits, c, conditions, m, b, e, result.cause,
                             out / f"fit_{safe}.png", n, band))
        plots.append(partial(_plot_residuals, c, conditions, m, b, e, result.cause,
                             result.noise.sigma.get(c), out / f"residuals_{safe}.png", n, band))
        figs.append((c, f"fit_{safe}.png", f"residuals_{safe}.png"))
    plots.append(partial(_plot_candidates, result, out / "candidates.png"))
    # the candidates' plot first: the longest (constrained layout for its names; 0.85 CPU s of
    # the flywheel diagnosis's 2.6), so that it does not end alone on one worker
    return figs, parallel_map(lambda plot: plot(), plots, workers, first=[len(plots) - 1])[-1]


def _headline(r: DiagnosisResult) -> list[str]:
    headline = {
        "no_discrepancy": "**No discrepancy**: the baseline residuals are consistent with the "
                          "noise level estimated from the data.",
        "explained": f"**Explained** by `{r.cause}`."
                     + (" Further causes: " + ", ".join(f"`{c.effect}`" for c in r.causes[1:])
                        + "." if len(r.causes) > 1 else ""),
        "explained_partly": f"**Explained in part** by `{r.cause}`"
                            + (" and " + ", ".join(f"`{c.effect}`" for c in r.causes[1:])
                               if len(r.causes) > 1 else "")
                            + ": it carries weight, but the extended model leaves structure "
                              "(below).",
        "ambiguous": f"**Ambiguous**: `{r.cause}` and "
                     + ", ".join(f"`{x}`" for x in r.indistinguishable)
                     + " explain the data about equally well.",
        "unexplained": "**Unexplained**: the baseline is clearly wrong, but no candidate effect "
                       "removes the structure from the residuals.",
    }[r.verdict]
    return ["# Diagnosis report\n", f"Verdict: `{r.verdict}`. {headline}\n",
            *(f"- {x}" for x in r.reasons), ""]


def _cause_section(r: DiagnosisResult) -> list[str]:
    if not r.cause:
        return []
    L = ["## Cause and fitted parameters\n", "| parameter | value ± standard uncertainty |",
         "| --- | --- |"]
    L += [f"| `{p}` | {_pm(v, r.parameter_uncertainty.get(p))} |" for p, v in r.parameters.items()]
    L.append("")
    ext = r.extended_form
    if ext:
        g = ext.heldout_gain_vs_listed
        L.append(f"Extended form: **{ext.text}** (`{ext.name}`), beats the listed form "
                 f"in sample (p = {ext.p_vs_listed:.2g}) and on held-out blocks (RMSE gain "
                 f"{g.rmse_gain:.3g} noise units, interval [{g.ci[0]:.3g}, "
                 f"{g.ci[1]:.3g}]).\n")
        L += ["| parameter | value ± standard uncertainty |", "| --- | --- |"]
        L += [f"| `{p}` | {_pm(v, ext.parameter_uncertainty.get(p))} {ext.units[p]} |"
              for p, v in ext.parameters.items()]
        L.append("")
    return L


def _gain_section(r: DiagnosisResult) -> list[str]:
    L = ["## Gain on held-out data, per column\n",
         "Held-out RMSE ratio (extended / baseline): "
         + ", ".join(f"`{c}` **{_fmt(v)}**" for c, v in r.heldout_rmse_ratio.items())
         + f"; decisive column (largest baseline misfit in noise units): "
           f"`{r.decisive_column}`.\n",
         "| column | noise sigma (est.) | baseline RMSE | baseline held-out | extended RMSE | "
         "extended held-out | baseline misfit (sigma) | held-out ratio | held-out gain (sigma) "
         "| chi² drop (share) |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for c in r.columns:
        ev = r.evidence[c]
        L.append(f"| `{c}` | {_fmt(r.noise.sigma[c])} | {_fmt(r.baseline.rmse[c])} | "
                 f"{_fmt(r.baseline.heldout_rmse[c])} | {_fmt(r.extended.rmse[c])}"
                 f" | {_fmt(r.extended.heldout_rmse[c])} | {_fmt(ev.baseline_misfit_sigma, 3)} | "
                 f"{_fmt(ev.heldout_rmse_ratio, 3)} | {_fmt(ev.heldout_gain_sigma, 3)} | "
                 f"{_fmt(ev.chi2_drop, 4)} ({ev.chi2_drop_share:.0%}) |")
    L += ["", f"Held-out rows: {r.heldout_blocks} {HELDOUT_METHOD}.\n"]
    if r.heldout_untestable:
        L.append(f"Blocks that cannot test `{r.cause}` (left out of its held-out gain; their "
                 "rows keep the baseline's held-out residual):\n")
        L += [f"- block {u['block']} (rows {u['rows'][0]}..{u['rows'][1]}): {u['reason']}"
              for u in r.heldout_untestable]
        L.append("")
    return L


def _causes_section(r: DiagnosisResult) -> list[str]:
    """The accepted causes in order with their own gain, what is left, parameters at a bound."""
    L = []
    if len(r.causes) > 1:
        L += ["## Causes, in the order accepted\n",
              "Each after the ones before it are in the model (noise re-estimated from their "
              "residual); own gain = held-out RMSE with it / before it.\n",
              "| step | cause | parameters | own held-out RMSE ratio | held-out gain (sigma) "
              "[interval] | noise sigma of its step |", "| --- | --- | --- | --- | --- | --- |"]
        for c in r.causes:
            g = c.heldout_gain
            gain = (f"{_fmt(g.rmse_gain, 3)} [{_fmt(g.ci[0], 3)}, {_fmt(g.ci[1], 3)}]"
                    if g else "–")
            L.append(f"| {c.step} | `{c.form or c.effect}` | "
                     + ", ".join(f"{k}={_fmt(v)}" for k, v in c.parameters.items())
                     + " | " + ", ".join(f"`{k}` {_fmt(v, 3)}"
                                         for k, v in c.heldout_rmse_ratio.items())
                     + f" | {gain} | " + ", ".join(f"`{k}` {_fmt(v, 3)}"
                                                    for k, v in c.noise_sigma.items()) + " |")
        L.append("")
    if r.left:
        L.append("## What is left\n")
        L += [f"- {x.text}" for x in r.left]
        L.append("")
    if r.at_bound:
        L.append("## Parameters at a bound (not claimed)\n")
        L += [f"- {x.text}" for x in r.at_bound]
        L.append("")
    if r.worse_columns:
        L += ["## Columns made worse (not claimed)\n",
              "A candidate that predicts a measured column worse on held-out blocks than the "
              "model before it, beyond the noise, is not claimed.\n",
              "| candidate | column | held-out RMSE ratio | worse by (noise units) | bootstrap "
              "interval of the gain |", "| --- | --- | --- | --- | --- |"]
        L += [f"| `{w.effect}` | `{w.column}` | {_fmt(w.gain)} | "
              f"{_fmt(-w.difference.rmse_gain, 3)} | [{_fmt(w.difference.ci[0], 3)}, "
              f"{_fmt(w.difference.ci[1], 3)}] |" for w in r.worse_columns]
        L.append("")
    return L


def _interval_section(r: DiagnosisResult) -> list[str]:
    """The predictive interval (`studies.diagnosis.interval`): the claimed model's, or the
    configured model's with the discrepancy the data show."""
    iv = r.interval
    if iv is None:
        return []
    how = ("the parameters' covariance through the fit's Jacobian (delta method), the "
           "noise (its AR(1) model's marginal level) and a discrepancy term, the excess of the "
           "calibration residuals' variance over the noise (Kennedy & O'Hagan 2001 in spirit)"
           if iv.model == "extended" else
           "no cause is claimed, so it is the configured model's with the discrepancy the data "
           "show: the calibrated baseline plus the conditions' smoother fitted to its residual, "
           "the nuisance's and smoother's covariance (delta method), the noise and the "
           "discrepancy variance the smoother leaves")
    L = ["## Predictive interval\n",
         f"{100 * iv.level:g} % predictive interval of every measured column on every row "
         "(diagnosis.csv `predicted_lo_<column>`, `predicted_hi_<column>`; the band in the "
         f"plots): {how}. "
         f"Inside: {100 * iv.coverage_calibration:.1f} % of the calibration rows, "
         f"{100 * iv.coverage_heldout:.1f} % of the held-out predictions.\n",
         "| column | noise sigma | discrepancy sigma | calibration rows inside | held-out rows "
         "inside |", "| --- | --- | --- | --- | --- |"]
    L += [f"| `{c}` | {_fmt(ci.noise_sd)} | {_fmt(ci.discrepancy_sd)} | "
          f"{100 * ci.coverage_calibration:.1f} % | {100 * ci.coverage_heldout:.1f} % |"
          for c, ci in iv.columns.items()]
    L.append("")
    return L


def _nuisance_line(r: DiagnosisResult) -> str:
    nu = r.nuisance
    allowed = ", ".join(f"`{k}` in [{_fmt(a)}, {_fmt(b)}]" for k, (a, b) in nu.bounds.items())
    ext = ("; with the extended model: " + ", ".join(f"`{k}` = {_fmt(v)}" for k, v in
                                                     nu.extended.items()) if r.cause else "")
    return (f"The baseline was allowed the calibration {allowed or '(none)'}; fitted: "
            + ", ".join(f"`{k}` = {_fmt(v)}" for k, v in nu.baseline.items()) + ext + ".\n")


def _baseline_section(r: DiagnosisResult, figs) -> list[str]:
    L = ["## What the baseline gets wrong\n", _nuisance_line(r),
         "| column | bias | reduced chi² | lag-1 autocorr. (p) | smoother F test p | "
         "smoother held-out gain | bias p |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for c in r.columns:
        d = r.residuals_baseline.columns[c]
        L.append(f"| `{c}` | {_fmt(d.bias)} | {_fmt(d.chi2_reduced)} | "
                 f"{_fmt(d.lag1_autocorr, 2)} ({_fmt(d.lag1_p, 2)}) | "
                 f"{_fmt(d.smoother_p, 2)} | {_fmt(d.smoother_heldout_gain, 2)} | "
                 f"{_fmt(d.bias_p, 2)} |")
    L += ["", f"Structure beyond noise: **{_fmt(r.baseline_structure)}** "
          f"(smallest p, Bonferroni-adjusted over tests and columns: "
          f"{_fmt(r.residuals_baseline.p_min_adjusted, 2)}; threshold "
          f"{_fmt(r.thresholds['alpha_structure'])}). The reduced chi² uses the noise level "
          "estimated from second differences of the residuals; the smoother is a cubic polynomial "
          "in each varying condition and in time plus the rates of change of the conditions, its "
          "gain measured on held-out blocks.\n"]
    if r.residuals_extended:
        L.append(f"After `{r.cause}`: smallest adjusted p of the same tests "
                 f"{_fmt(r.residuals_extended.p_min_adjusted, 2)} (structure left if below "
                 f"{_fmt(r.thresholds['alpha_residual'])}).\n")
    bp = r.best_partial
    if bp:
        L.append(f"Best partial candidate: `{bp.effect}` ({_fmt(bp.parameters)}); it leaves "
                 f"structure (adjusted p {_fmt(bp.residuals.p_min_adjusted, 2)}).\n")
    for c, f1, f2 in figs:
        L += [f"![{c}: measured vs models]({f1})\n", f"![{c}: residuals]({f2})\n"]
    return L


def _candidate_note(c) -> str:
    note = c.reason
    if c.heldout_untestable:
        note += ("; " if note else "") + "held-out blocks it cannot test: " + ", ".join(
            f"{u['block']} (rows {u['rows'][0]}..{u['rows'][1]})" for u in c.heldout_untestable)
    if c.held_at_off:
        note += (("; " if note else "") + "held at its off value (not separable in this data): "
                 + ", ".join(c.held_at_off))
    return note


def _candidate_row(c, c0: str) -> str:
    hg = c.heldout_gain
    gain = (f"{_fmt(hg.rmse_gain, 3)} [{_fmt(hg.ci[0], 3)}, {_fmt(hg.ci[1], 3)}]"
            if hg else "–")
    ho = c.heldout_rmse[c0] if c.heldout_rmse else None
    params = ", ".join(f"{k}={_fmt(v)}" for k, v in c.parameters.items()) or "–"
    return (f"| `{c.effect}` | {c.status} | {params} | {_fmt(c.delta_bic)} | "
            f"{_fmt(c.p_lr, 2)} | {_fmt(ho)} | {gain} | {_candidate_note(c)} |")


def _candidates_section(r: DiagnosisResult, has_plot: bool) -> list[str]:
    c0 = r.columns[0]
    L = ["## Candidates\n",
         "Sorted best first. `delta BIC` is relative to the calibrated baseline (negative = "
         "better); `p (LR)` is the likelihood-ratio p-value (half-chi-square mixture for "
         "parameters with a sign), before the Holm correction; the held-out gain is the baseline "
         "minus candidate held-out RMSE in noise units with its paired block-bootstrap "
         "interval.\n",
         f"| effect | status | parameters | delta BIC | p (LR) | held-out RMSE `{c0}` | "
         "held-out gain [interval] | note |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    L += [_candidate_row(c, c0) for c in r.candidates]
    L.append("")
    if has_plot:
        L.append("![candidates](candidates.png)\n")
    if r.not_identifiable:
        L.append("Not testable with this data:\n")
        L += [f"- `{k}`: {v}" for k, v in r.not_identifiable.items()]
        L.append("")
    return L


def _lookalike_section(r: DiagnosisResult) -> list[str]:
    look = r.lookalike or {}
    if len(look) <= 1:
        return []
    names = list(look)
    cut = r.thresholds["lookalike_cos"]
    L = ["### Look-alike matrix\n",
         "Cosine of the smallest principal angle between the candidates' sensitivities after "
         "removing what the baseline calibration can produce (1 = same residual shape; "
         f"reported as look-alike above {_fmt(cut)}).\n",
         "| | " + " | ".join(f"`{x}`" for x in names) + " |", "| --- " * (len(names) + 1) + "|"]
    for a in names:
        L.append(f"| `{a}` | " + " | ".join(
            (f"**{look[a][b]:.2f}**" if a != b and look[a][b] >= cut else f"{look[a][b]:.2f}")
            for b in names) + " |")
    L.append("")
    return L


def _joint_fits_section(r: DiagnosisResult) -> list[str]:
    if not r.joint_fits:
        return []
    L = ["### Comparison with the best candidate (joint fits)\n",
         "| other | chi² best | chi² other | chi² joint | p (add other to best) | "
         "p (add best to other) | best carries the weight |",
         "| --- | --- | --- | --- | --- | --- | --- |"]
    for o, j in r.joint_fits.items():
        L.append(f"| `{o}` | {_fmt(j.chi2_best)} | {_fmt(j.chi2_other)} | "
                 f"{_fmt(j.chi2_joint)} | {_fmt(j.p_add_other_to_best, 2)} | "
                 f"{_fmt(j.p_add_best_to_other, 2)} | {_fmt(j.best_carries_weight)} |")
    L.append("")
    return L


def _separating_section(r: DiagnosisResult) -> list[str]:
    if not r.separating_test:
        return []
    L = ["## Separating test\n", r.separating_test + "\n"]
    items = [i for i in r.separating_tests if i["kind"] != "measured_conditions"]
    if items:
        L += [f"- {i['text']}" for i in items[:10]]
        L.append("")
    return L


def _method_section(r: DiagnosisResult) -> list[str]:
    L = ["## Method and thresholds\n",
         "1. Baseline calibrated (nuisance only); noise level per column from second differences "
         "of the residuals; residual structure tested (bias, lag-1 autocorrelation, smoother F "
         "test).",
         "2. Each candidate's sensitivity at 'off', with the part the calibration can produce "
         "projected out: too little left = not identifiable; overlaps = look-alike matrix.",
         "3. Bounded least-squares fit of each candidate with the nuisance; likelihood ratio "
         "(Holm over candidates) and a BIC margin.",
         "4. Held-out gain on contiguous blocks with a paired block bootstrap interval excluding "
         "0 (history effects refitted in full on the kept blocks; blocks they cannot test left "
         "out).",
         "5. Several passing: joint fits; ambiguous unless the best clearly carries the "
         "weight.\n",
         "| threshold | value |", "| --- | --- |"]
    L += [f"| `{k}` | {_fmt(v)} |" for k, v in r.thresholds.items()]
    cost = r.cost
    L += ["", f"{r.n_rows} rows, columns compared: {', '.join(f'`{c}`' for c in r.columns)}; "
          f"{cost.n_predict_calls} model evaluations, {_fmt(cost.seconds_total, 3)} s "
          f"({_fmt(cost.seconds_predict, 3)} s in the model).\n"]
    return L


def write_report(result: DiagnosisResult, conditions: Mapping[str, np.ndarray],
                 measured: Mapping[str, np.ndarray], out_dir, workers: int = 1) -> Path:
    """Write report.md and the PNG plots into out_dir; return the path of report.md. workers:
    processes drawing the plots (`studies.model.parallel.parallel_map`; the files are the
    same)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figs, has_cand_plot = _draw_plots(result, conditions, measured, out, workers)
    L = (_headline(result) + _cause_section(result) + _causes_section(result)
         + _gain_section(result) + _interval_section(result)
         + _baseline_section(result, figs)
         + report_lines(result.open_world)          # unexplained: what it depends on
         + _candidates_section(result, has_cand_plot) + _lookalike_section(result)
         + _joint_fits_section(result) + _separating_section(result) + _method_section(result))
    path = out / "report.md"
    path.write_text("\n".join(L), encoding="utf-8")
    return path
