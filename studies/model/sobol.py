"""Sobol' sensitivity indices of a model output to independent inputs (SALib).

For Y = f(X_1 .. X_k) with independent X_i, the first-order index S_i = Var(E[Y | X_i]) / Var(Y)
(the share of the variance X_i causes alone) and the total index ST_i = E[Var(Y | X_~i)] / Var(Y)
(its share with all its interactions); for an additive model S_i = ST_i and sum S_i = 1.
Sobol', "Global sensitivity indices for nonlinear mathematical models and their Monte Carlo
estimates", Math. Comput. Simul. 55 (2001) 271-280; estimators and sampling (Sobol' sequence,
N (k + 2) model runs without second-order indices) of Saltelli et al., "Variance based sensitivity
analysis of model output. Design and estimator for the total sensitivity index", Comput. Phys.
Commun. 181 (2010) 259-270, as implemented by SALib (`SALib.sample.sobol`, `SALib.analyze.sobol`);
the confidence half-widths are SALib's bootstrap at 95 %.

`preload_indices` applies it to the fit tolerances: the inputs are the toleranced surfaces'
deviations (um; uniform within their limits, or normal with the limits at +-3 sigma, as
`tolerances.sample_deviations_um` draws them), the output the preload (N) of the exact model at
each condition (`tolerances.run_samples`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class SobolIndices:
    """Per input name: first-order S1 and total ST indices (dimensionless, shares of Var(Y))
    and their 95 % confidence half-widths."""
    names: tuple[str, ...]
    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray


def resolved(value, conf) -> np.ndarray:
    """Whether an index estimate is resolved: its 95 % interval value +- conf excludes 0
    (conf < |value|). An interval that spans the value's own size (0.869 +- 2.067) says the
    estimate is noise of the bootstrap, not a share of the variance."""
    return np.abs(np.asarray(conf, float)) < np.abs(np.asarray(value, float))


def display(value: float, conf: float) -> str:
    """An index for a report: `0.512 +- 0.031` when resolved, else `- (+- 2.07)`: the value
    hidden, the half-width kept so the reader sees why (more samples narrow it)."""
    if resolved(value, conf):
        return f"{value:.3f} +- {conf:.3f}"
    return f"- (+- {conf:.3g})"


def _problem(inputs: dict[str, tuple[str, float, float]]) -> dict:
    """SALib problem of inputs name -> ('uniform', low, high) or ('normal', mean, sd)."""
    dists = {"uniform": "unif", "normal": "norm"}
    return {"num_vars": len(inputs), "names": list(inputs),
            "bounds": [[a, b] for _, a, b in inputs.values()],
            "dists": [dists[d] for d, _, _ in inputs.values()]}


def sample(inputs: dict[str, tuple[str, float, float]], n_base: int, seed: int) -> dict[str, np.ndarray]:
    """The N (k + 2) input rows (N = n_base, a power of 2) of the estimators, per input name."""
    from SALib.sample import sobol as sobol_sample

    X = sobol_sample.sample(_problem(inputs), n_base, calc_second_order=False, seed=seed)
    return {n: X[:, i] for i, n in enumerate(inputs)}


def analyse(inputs: dict[str, tuple[str, float, float]], Y: np.ndarray, seed: int) -> SobolIndices:
    """The indices from the outputs Y of the rows of `sample` (same inputs, same order). An
    output that does not vary has no variance to share: all indices 0."""
    from SALib.analyze import sobol as sobol_analyze

    if np.ptp(Y) == 0:
        z = np.zeros(len(inputs))
        return SobolIndices(tuple(inputs), z, z, z, z)

    r = sobol_analyze.analyze(_problem(inputs), np.asarray(Y, float), calc_second_order=False,
                              seed=seed, print_to_console=False)
    return SobolIndices(tuple(inputs), np.asarray(r["S1"]), np.asarray(r["S1_conf"]),
                        np.asarray(r["ST"]), np.asarray(r["ST_conf"]))


def indices(inputs: dict[str, tuple[str, float, float]],
            model: Callable[[dict[str, np.ndarray]], np.ndarray], n_base: int = 1024,
            seed: int = 1) -> list[SobolIndices]:
    """Sobol' indices of every output column of `model` (inputs per name -> (rows,) or
    (rows, m) outputs): one SobolIndices per column."""
    X = sample(inputs, n_base, seed)
    Y = np.asarray(model(X), float)
    Y = Y[:, None] if Y.ndim == 1 else Y
    return [analyse(inputs, Y[:, j], seed) for j in range(Y.shape[1])]


def surface_inputs(asm) -> dict[str, tuple[str, float, float]]:
    """The toleranced surfaces as Sobol' inputs: their deviation distributions (um)."""
    from studies.model.tolerances import deviation_limits_um

    out = {}
    for s, (lo, hi) in deviation_limits_um(asm).items():
        out[s] = (("normal", 0.5 * (lo + hi), (hi - lo) / 6.0) if asm.fits.distribution == "normal"
                  else ("uniform", lo, hi))
    return out


def preload_indices(asm, conditions: dict[str, np.ndarray], n_base: int = 1024, seed: int = 1,
                    workers: int | None = None, scheduler: str | None = None,
                    where=None) -> list[SobolIndices]:
    """Sobol' indices of the preload (exact model) to each toleranced surface, per condition;
    the samples here, on Dask (`workers` / `scheduler`) or on an open `parallel.Blocks` (`where`)."""
    from studies.model import tolerance_samples as tsm
    from studies.model import tolerances as tol

    def model(dev):
        n = len(next(iter(dev.values())))
        di, do = tol.interference_offsets_um(dev, n)
        return tsm.run_samples(asm, conditions, di, do, workers=workers, scheduler=scheduler,
                               where=where, d_layers_um=tol.layer_offsets_um(asm, dev, n)).preload_N
    return indices(surface_inputs(asm), model, n_base, seed)
