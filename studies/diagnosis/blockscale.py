"""Does every held-out block want a further cause in the amount fitted?

Two listed causes can compose a cause outside the list: on seed 000's steady grid (torque
alone) an inner groove curvature ratio of 0.54 was claimed as a path compliance plus a radial
gradient, the gradient correcting the compliance's form error; the pair leaves little structure
and gains on held-out blocks overall. What separates it from a pair that is really there is how
the further cause's change fares block by block: a cause that is present improves every block
by its own amount, a compensating one buys its gain in some blocks with a loss in others.

Statistic (per held-out block b of the forward selection's pass, `selection.select`): with
z0_b and z1_b the held-out standardised (AR(1)-whitened, `Problem.zvec`) residuals of the
model before the further cause and with it (each refitted without block b), the change the
cause makes in predicting the block is d_b = z0_b - z1_b, and the amount of it the block wants
is the least-squares scale

    lambda_b = (z0_b . d_b) / (d_b . d_b),     standard error  1 / |d_b|   (noise units).

If the cause is present in the fitted form, z1_b is the noise and lambda_b = 1 + (e_b . d_b) /
|d_b|^2 scatters about a common value with that error (the calibration slope of a prediction:
Cox 1958, Two further applications of a model for binary regression, Biometrika 45, 562-565;
here of the held-out change, in the spirit of Stone 1974, Cross-validatory choice and assessment
of statistical predictions, J. R. Statist. Soc. B 36). Their heterogeneity over the m blocks
the cause changes is Cochran's Q (Cochran 1954, The combination of estimates from different
experiments, Biometrics 10, 101-129):

    Q = sum_b w_b (lambda_b - lambda_bar)^2,   w_b = |d_b|^2,   lambda_bar = sum w_b lambda_b / sum w_b,

chi-square with m - 1 degrees of freedom when every block wants the same amount. A small p
says the blocks want the cause in different amounts (more in some, less or its reverse in
others): its change has the wrong form for these data, i.e. it compensates the misfit of the
causes before it rather than being a cause itself. The test uses no model call (the held-out
residuals the pass already has). Blocks the cause does not change (|d_b| = 0) or cannot test
(a one-off trigger in the block, `heldout_untestable`) are left out.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from studies.diagnosis.problem import Problem


@dataclass(frozen=True)
class BlockScale:
    """The block-by-block amount of a further cause's change (module docstring): per tested
    block (1-based) the amount wanted `scale` (lambda_b, 1 = as fitted) and its standard error
    `scale_se` (noise units), the common amount `pooled`, Cochran's Q with `dof` degrees of
    freedom and its p, and one sentence."""
    effect: str
    scale: dict[int, float]
    scale_se: dict[int, float]
    pooled: float
    q: float
    dof: int
    p: float
    text: str


def block_scale(pb: Problem, effect: str, z_before_ho: np.ndarray, z_with_ho: np.ndarray,
                keep: np.ndarray | None = None) -> BlockScale | None:
    """Cochran's Q of the amount of `effect`'s change each held-out block wants (module
    docstring) from the held-out standardised residuals of the model before it and with it
    (the same problem and noise model); `keep`: the blocks that test it (default all). None
    when fewer than two blocks are changed."""
    z0 = np.asarray(z_before_ho, float)
    z1 = np.asarray(z_with_ho, float)
    scale, se = {}, {}
    for b in range(pb.n_blocks):
        if keep is not None and not keep[b]:
            continue
        sel = pb.entry_block == b
        d = z0[sel] - z1[sel]
        w = float(d @ d)
        if not w > 0.0:
            continue
        scale[b + 1] = float(z0[sel] @ d) / w
        se[b + 1] = 1.0 / np.sqrt(w)
    if len(scale) < 2:
        return None
    lam = np.array(list(scale.values()))
    w = 1.0 / np.array(list(se.values())) ** 2
    pooled = float(w @ lam / w.sum())
    q = float(w @ (lam - pooled) ** 2)
    dof = lam.size - 1
    p = float(stats.chi2.sf(q, dof))
    lo, hi = min(scale, key=scale.get), max(scale, key=scale.get)
    text = (f"the held-out blocks want {effect}'s change in different amounts (from "
            f"{scale[lo]:.2f} +- {se[lo]:.2f} of the fitted one in block {lo} to "
            f"{scale[hi]:.2f} +- {se[hi]:.2f} in block {hi}; Cochran's Q {q:.1f} on {dof} "
            f"degrees of freedom, p = {p:.2g}): its change has the wrong form for these data, "
            "it compensates the misfit of the causes before it")
    return BlockScale(effect, scale, se, pooled, q, dof, p, text)
