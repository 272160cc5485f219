"""`bearingfem tolerance`: worst case and Monte Carlo of the fit tolerances through the exact model.

Conditions: the given table, or the assembly's operating range (`[operating]`) on round
temperature steps at its speed and preload. Every sample's fits are solved with the contact
state they produce (a fit that flips between interference and clearance is exact, not
linearised); `studies/model/tolerances.py` states the conventions. Writes `tolerance.json`
(keys in docs/cli.md), `samples.csv` (deviations and results per sample and condition),
plots and `report.md` / `report.html`.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import stats

from studies.model import sobol
from studies.model import tolerance_samples as tsm
from studies.model import tolerances as tol
from studies.model.checks import assembly_checks
from studies.model.parallel import Blocks
from studies.model.pipeline import Pipeline
from studies.model.table import write_table
from studies.usecases.report_tools import line_plot, md_table, nice_step, write_report_files

N_CONDITIONS = 8          # about this many temperatures in the default conditions
SOBOL_BASE_SAMPLES = 512  # Sobol' design: 512 x (surfaces + 2) samples (studies/model/sobol.py)
PERCENTILES = {"p01": 1.0, "p50": 50.0, "p99": 99.0}


class ToleranceError(ValueError):
    """The assembly cannot be toleranced as given (one line)."""


def default_conditions(asm) -> dict[str, np.ndarray]:
    op = asm.operating
    step = nice_step(op.T_max_C - op.T_min_C, N_CONDITIONS)
    grid = step * np.arange(np.ceil(op.T_min_C / step), np.floor(op.T_max_C / step) + 1)
    T = np.unique(np.concatenate([[op.T_min_C, op.T_max_C, asm.T_ref_C], grid]))
    return {"T_ambient_C": T[(T >= op.T_min_C) & (T <= op.T_max_C)]}


def failures(asm, r: tol.SampleResults) -> dict[str, np.ndarray]:
    """Boolean (S, C) events: each fit out of its designed state (`fit_open_<fit>`: a fit
    designed with interference open, pressure 0; a fit designed with clearance closed, pressure
    > 0; `tolerances.designed_closed`), preload lost, contact pressure above the limit `simulate`
    checks against."""
    limit = next(c.allowable for c in assembly_checks(asm) if c.name == "max_contact_pressure_MPa")
    closed = tol.designed_closed(asm)
    pressure_MPa = {fit: r.fit_pressure_MPa(fit) for fit in tol.fits_of(asm)}
    ev = {f"fit_open_{fit}": (p <= 0.0) if closed[fit] else (p > 0.0)
          for fit, p in pressure_MPa.items()}
    return {**ev, "preload_lost": r.preload_N <= 0.0,
            "contact_pressure_over_limit": r.max_contact_pressure_MPa > limit}


def worst_case(pl, cond: dict[str, np.ndarray]) -> tol.SampleResults:
    """The corners of the interference bands (`tol.worst_case_bands`: four of the inner and
    outer bands, times two per sleeve / cartridge band) at every condition through the pipeline:
    (corners, C) arrays."""
    import itertools

    bands = tol.worst_case_bands(pl.asm)
    off = np.array([[c - b.nominal_um for c, b in zip(corner, bands)] for corner in
                    itertools.product(*((b.lower_um, b.upper_um) for b in bands))])
    return tsm.evaluate(pl, cond, off[:, 0], off[:, 1], off[:, 2:] if len(bands) > 2 else None)


def _linear(asm, pl, cond, limit_p):
    """Linear-normal estimate per condition: gradients by central differences at the mid-band
    fits (one tenth of each band), variances summed."""
    lim = tol.deviation_limits_um(asm)
    sig = tol.surface_sigma_um(asm)
    names = list(lim)
    n = len(names)
    dev = {s: np.full(2 * n + 1, 0.5 * (lim[s][0] + lim[s][1])) for s in names}   # mid-band
    h = {s: 0.05 * (lim[s][1] - lim[s][0]) or 0.05 for s in names}
    for k, s in enumerate(names):
        dev[s][1 + 2 * k] += h[s]
        dev[s][2 + 2 * k] -= h[s]
    di, do = tol.interference_offsets_um(dev, 2 * n + 1)
    r = tsm.evaluate(pl, cond, di, do, tol.layer_offsets_um(asm, dev, 2 * n + 1))

    def gradient(v: np.ndarray) -> np.ndarray:                      # (n_surfaces, C)
        return np.array([(v[1 + 2 * k] - v[2 + 2 * k]) / (2 * h[s]) for k, s in enumerate(names)])
    sigma = np.array([sig[s] for s in names])
    C = len(next(iter(cond.values())))
    closed = tol.designed_closed(asm)       # out of the designed state: open, or closed
    events = {**{f"fit_open_{fit}": (r.interference_um(fit), 0.0, not closed[fit])
                 for fit in tol.fits_of(asm)},
              "preload_lost": (r.preload_N, 0.0, False),
              "contact_pressure_over_limit": (r.max_contact_pressure_MPa, limit_p, True)}
    out = {}
    for e, (v, limit, upper) in events.items():
        g = gradient(v)
        out[e] = np.array([tol.linear_probability(v[0, c], g[:, c], sigma, limit, upper)
                           for c in range(C)])
    return out


@dataclass(frozen=True)
class ToleranceSummary:
    """What `tolerance` prints: the samples, each fit's probability of leaving its designed state
    (by fit name, over every sample and condition) and the probability of losing the preload."""
    samples: int
    fit_leaves_design: dict[str, float]
    preload_lost: float
    json: dict = field(default_factory=dict, compare=False, repr=False)   # tolerance.json
    columns: dict = field(default_factory=dict, compare=False, repr=False)  # samples.csv
    #: the plausibility warnings of the inputs (`checks.plausibility_warnings`), one line each
    warnings: tuple[str, ...] = ()

    def to_frame(self):
        """samples.csv's columns (one row per sample and condition) as a `pandas.DataFrame`."""
        import pandas as pd

        return pd.DataFrame(self.columns)


def run(asm, conditions: dict | None, out: Path, provenance: dict, samples: int, seed: int,
        progress=print, workers: int | None = None, scheduler: str | None = None,
        bar=None) -> ToleranceSummary:
    """Write the tolerance analysis into `out` (tolerance.json is its whole content); returns the
    summary the command prints. The Monte
    Carlo runs here, or on `workers` processes forked from this one, or on the Dask cluster at
    `scheduler`, with the same numbers (`studies.model.parallel`); `bar(done, total)` follows
    its blocks (the command line's progress bar)."""
    if not tol.has_tolerances(asm):
        raise ToleranceError("[fits] has no tolerances: give <surface>_class or "
                             "<surface>_deviation_um keys (docs/cli.md, tolerance)")
    cond = dict(conditions) if conditions is not None else default_conditions(asm)
    cond = {k: np.asarray(v, float) for k, v in cond.items() if not k.startswith("_")}
    C = len(next(iter(cond.values())))
    pl = Pipeline.shared(asm, progress=progress)
    lim = tol.deviation_limits_um(asm)
    bands = tol.worst_case_bands(asm)

    wc = worst_case(pl, cond)

    progress(f"tolerance: {samples} samples x {C} conditions through the exact model ...")
    dev = tol.sample_deviations_um(asm, samples, seed)
    di, do = tol.interference_offsets_um(dev, samples)
    # one cluster (or none) for the Monte Carlo and the Sobol' samples (its workers read the
    # pipeline's set-up above from the FE cache)
    with Blocks(workers, scheduler) as where:
        mc = tsm.run_samples(asm, cond, di, do, where=where, progress=bar or (
            lambda done, total: progress(f"  block {done} of {total}")),
            d_layers_um=tol.layer_offsets_um(asm, dev, samples))
        # Sobol' indices of the preload per surface (studies/model/sobol.py): their own design
        sob = sobol.preload_indices(asm, cond, SOBOL_BASE_SAMPLES, seed, where=where)
    fail = failures(asm, mc)
    limit_p = next(c.allowable for c in assembly_checks(asm) if c.name == "max_contact_pressure_MPa")
    lin = _linear(asm, pl, cond, limit_p)

    probs, ses, per_cond = {}, {}, {}
    for e, f in fail.items():
        probs[e], ses[e] = tol.probability(f.any(axis=1))
        pc = [tol.probability(f[:, c]) for c in range(C)]
        per_cond[e] = {"probability": [p for p, _ in pc], "standard_error": [s for _, s in pc],
                       "linear_estimate": [float(v) for v in lin[e]]}
    mc_cols, wc_cols = mc.columns(), wc.columns()           # the JSON's names (file edge)
    pct = {q: {k: float(np.percentile(v_q, v)) for k, v in PERCENTILES.items()}
           for q, v_q in mc_cols.items()}
    pct_c = {q: {k: [float(x) for x in np.percentile(v_q, v, axis=0)] for k, v in PERCENTILES.items()}
             for q, v_q in mc_cols.items()}
    # sensitivity of the preload to each surface: Spearman rank correlation per condition
    sens = {s: [float(stats.spearmanr(dev[s], mc.preload_N[:, c]).statistic)
                if np.ptp(mc.preload_N[:, c]) > 0 else 0.0 for c in range(C)] for s in dev}
    sobol_json = {s: {k: [float(getattr(r, k)[i]) for r in sob]
                      for k in ("S1", "S1_conf", "ST", "ST_conf")} for i, s in enumerate(sob[0].names)}
    result = {
        "samples": int(samples), "seed": int(seed), "distribution": asm.fits.distribution,
        "conditions": {k: [float(x) for x in v] for k, v in cond.items()},
        "deviation_limits_um": {s: list(v) for s, v in lim.items()},
        "interference_bands_um": {b.fit: {"nominal": b.nominal_um, "lower": b.lower_um,
                                          "upper": b.upper_um} for b in bands},
        "probabilities": probs, "standard_errors": ses,
        "per_condition": per_cond,
        "percentiles": pct, "percentiles_per_condition": pct_c,
        "fit_design": {f: "interference" if c else "clearance"
                       for f, c in tol.designed_closed(asm).items()},
        "worst_case": {q: {"min": float(w.min()), "max": float(w.max())}
                       for q, w in wc_cols.items()},
        "worst_case_per_condition": {q: {"min": [float(v) for v in w.min(axis=0)],
                                         "max": [float(v) for v in w.max(axis=0)]}
                                     for q, w in wc_cols.items()},
        "preload_rank_correlation": sens,
        "preload_sobol": sobol_json, "sobol_base_samples": SOBOL_BASE_SAMPLES,
        "provenance": provenance,
    }
    (out / "tolerance.json").write_text(json.dumps(result, indent=1) + "\n")
    cols = {"sample": np.repeat(np.arange(1, samples + 1, dtype=float), C)}
    cols.update({k: np.tile(v, samples) for k, v in cond.items()})
    cols.update({f"{s}_deviation_um": np.repeat(v, C) for s, v in dev.items()})
    cols.update({q: v.ravel() for q, v in mc_cols.items()})
    if samples * C <= 2_000_000:
        write_table(out / "samples.csv", cols, provenance=provenance)
    _report(asm, out, cond, result, mc, fail, lin)
    return ToleranceSummary(int(samples), {f: float(probs[f"fit_open_{f}"])
                                           for f in tol.designed_closed(asm)},
                            float(probs["preload_lost"]), result, cols)


def _x(cond):
    k = "T_ambient_C" if "T_ambient_C" in cond else next(iter(cond))
    return cond[k], ("ambient temperature (C)" if k == "T_ambient_C" else k)


def _report(asm, out, cond, res, mc, fail, lin):
    x, xlabel = _x(cond)
    C = len(x)
    S = res["samples"]
    pc = res["percentiles_per_condition"]
    plots = {}
    for q, label in (("preload_N", "preload (N)"),
                     *((f"fit_pressure_{fit}_MPa", f"{fit} fit pressure (MPa)")
                       for fit in tol.fits_of(asm)),
                     ("max_contact_pressure_MPa", "max contact pressure (MPa)"),
                     ("torque_Nmm", "friction torque (N mm)")):
        plots[q] = line_plot(out / f"band_{q}.png", x, {
            "p01": np.array(pc[q]["p01"]), "median": np.array(pc[q]["p50"]),
            "p99": np.array(pc[q]["p99"]),
            "worst case (min over corners)": np.array(res["worst_case_per_condition"][q]["min"]),
            "worst case (max over corners)": np.array(res["worst_case_per_condition"][q]["max"])},
            xlabel, label,
            f"{label}: Monte Carlo percentiles ({S} samples)")
    series = {}
    for e in fail:
        p = np.array(res["per_condition"][e]["probability"])
        if p.max() > 0 or np.max(lin[e]) > 1e-6:
            series[f"{e} (Monte Carlo)"] = p
            series[f"{e} (linear-normal)"] = np.array(lin[e])
    plots["probability"] = line_plot(out / "failure_probability.png", x, series or
                                     {"no failure in any sample": np.zeros(C)}, xlabel,
                                     "probability", "Failure probability: exact Monte Carlo and the "
                                     "linear estimate", markers=True)
    _histogram(out / "preload_histogram.png", x, mc.preload_N, xlabel)
    lines = [f"# Tolerance analysis: {asm.name}", "",
             f"bearingfem {res['provenance']['version']}; {S} samples (seed {res['seed']}, "
             f"{res['distribution']} within the limits{', limits at +-3 sigma' if res['distribution'] == 'normal' else ''}) "
             f"x {C} conditions, every sample through the exact model (fits and contact state "
             "solved, nothing linearised). The assembled preload is the design value for the mid-band "
             "fits; a sample's fits then move it.", "",
             "## Limit deviations and interference bands", "",
             md_table(["surface", "lower (um)", "upper (um)"],
                      [[s, v[0], v[1]] for s, v in res["deviation_limits_um"].items()]), "",
             md_table(["fit", "nominal (um)", "worst-case lower (um)", "worst-case upper (um)"],
                      [[f, b["nominal"], b["lower"], b["upper"]]
                       for f, b in res["interference_bands_um"].items()]), "",
             "## Failure probabilities", "",
             "A fit fails when it leaves its designed state at the reference temperature "
             f"({', '.join(f'{k}: {v}' for k, v in res['fit_design'].items())}; the mean "
             "assembly): a fit designed with interference by opening, one designed with clearance "
             "by closing (`fit_open_<fit>` counts either).", "",
             "Anywhere over the conditions (a sample fails if it fails at one of them), with the "
             "Monte Carlo standard error sqrt(p(1-p)/N); per condition in the plot and in "
             "`tolerance.json`, beside the linear-normal estimate a stack-up tool gives (outputs "
             "linearised at the mid-band fits, normal distribution). The linear estimate is "
             "called wrong where it lies more than 3 standard errors from the Monte Carlo value "
             "(with at least 1/N as the standard error where no sample failed).", "",
             md_table(["event", "probability", "standard error", "largest linear estimate",
                       "where the linear estimate is wrong"],
                      [[e, f"{res['probabilities'][e]:.4g}", f"{res['standard_errors'][e]:.2g}",
                        f"{np.max(lin[e]):.3g}", _wrong(res['per_condition'][e], S)]
                       for e in fail]), "",
             f"![probability]({plots['probability'].name})", "",
             "## Distributions", "",
             "Percentiles over all samples and conditions; the worst case (the four corners of "
             "the interference bands) over all conditions here, per condition in the plots and in "
             "`tolerance.json` (`worst_case_per_condition`).", "",
             md_table(["quantity", "p01", "median", "p99", "worst-case min", "worst-case max"],
                      [[q, v["p01"], v["p50"], v["p99"], res["worst_case"][q]["min"],
                        res["worst_case"][q]["max"]] for q, v in res["percentiles"].items()]), "",
             "![preload histogram](preload_histogram.png)", ""]
    lines += [f"![{q}]({p.name})" for q, p in plots.items() if q != "probability"] + [""]
    sens = res["preload_rank_correlation"]
    lines += ["## What drives the preload", "",
              "Spearman rank correlation of the preload with each surface's deviation, per "
              "condition (+1: a larger deviation always gives a larger preload).", "",
              md_table([xlabel] + list(sens), [[float(x[c])] + [sens[s][c] for s in sens]
                                                for c in range(C)]), ""]
    sob = res["preload_sobol"]
    lines += [f"Sobol' indices of the preload (first order S1: the share of its variance a surface "
              f"causes alone; total ST: with its interactions; +- the 95 % bootstrap half-width; "
              f"{res['sobol_base_samples']} x (surfaces + 2) model runs, Saltelli et al. 2010 "
              f"with SALib). An index whose interval reaches zero (half-width at least its value) "
              f"is not resolved by these runs and shown as `-` with its half-width.", "",
              md_table([xlabel] + [f"{s} {k}" for s in sob for k in ("S1", "ST")],
                       [[float(x[c])] + [sobol.display(sob[s][k][c], sob[s][k + '_conf'][c])
                                         for s in sob for k in ("S1", "ST")] for c in range(C)]), ""]
    write_report_files(out, lines, f"Tolerance analysis: {asm.name}")


def _wrong(pc, samples: int) -> str:
    """Conditions where the linear estimate lies outside the Monte Carlo value +- 3 SE (at least
    1/N where no sample failed: the rule of three puts the 95 % bound at 3/N)."""
    p, se, lin = (np.array(pc[k]) for k in ("probability", "standard_error", "linear_estimate"))
    bad = np.abs(lin - p) > 3 * np.maximum(se, 1.0 / samples)
    return "nowhere" if not bad.any() else f"{int(bad.sum())} of {bad.size} conditions"


def _histogram(path, x, values, xlabel):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    picks = np.unique(np.linspace(0, len(x) - 1, min(4, len(x))).round().astype(int))
    for c in picks:
        ax.hist(values[:, c], bins=60, histtype="step", label=f"{xlabel.split(' (')[0]} {x[c]:g}")
    ax.set_xlabel("preload (N)")
    ax.set_ylabel("samples")
    ax.set_title("Preload distribution", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
