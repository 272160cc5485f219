"""Goodness of fit of an explanation: does the extended model leave structure, where,
and does a fitted parameter sit at its bound?

An explanation that carries weight (it beats the baseline and every rival) can still leave
structure. Besides the residual tests of `Problem.describe` (bias, lag-1 autocorrelation, the
conditions' smoother), two tests compare the extended model's misfit with the noise level:

- in sample: the column's chi-square of the standardised (whitened) residuals per degree of
  freedom against an F distribution F(dof, nu): the noise level is itself estimated from the
  data (second differences, replicates), with nu = NU_SHARE x the column's entries degrees of
  freedom (Satterthwaite 1946, An approximate distribution of estimates of variance components,
  Biometrics Bulletin 2: the variance of the second-difference estimator of a white noise's
  variance is about 3.9 sigma^4 / n, against 2 sigma^4 / n for a chi-square with n degrees of
  freedom, so nu ~ 0.51 n); a given noise level: chi-square with dof degrees of freedom;
- out of sample, reported but not decided on: the held-out mean square of the standardised
  residuals against F(n, nu). Held-out residuals of parameters refitted on the other blocks are
  noise of variance 1 + O(k / n) only when the refit is good; the refit is one Gauss-Newton step
  for most candidates, and near a fit that opens (a strongly nonlinear parameter) that step leaves
  held-out residuals well above the noise on a true cause (seed 000, a fit error near opening:
  held-out p 3e-7 with the in-sample chi-square at the noise,
  `tests/test_diagnose_pipeline.py::test_a_fit_error_near_opening_is_found_by_the_global_search`).

Bonferroni over the columns; the model leaves structure when this adjusted p or the residual
tests' (`Residuals.p_min_adjusted`) is below `alpha_residual`. What is left is
described per column: which test, the RMS misfit beyond the noise in noise units
(sqrt(max(chi2_reduced - 1, 0))), and the named condition the residual depends on most (the
open-world forward selection, `openworld.characterise_column`) with its range in noise units.

A fitted parameter the data want at or beyond a bound that is not its "off" value (the value on
the bound, or the estimate with the bounds released beyond it: `at_bound`) is listed in
`at_bound` with a sentence: the data want more than the bound allows (an as-built fit outside
its tolerance band, a larger effect than the physics bound, or another cause).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from studies.diagnosis.core import Fit, Residuals
from studies.diagnosis.interval import (LEVEL, SINGULAR_RTOL, parameter_covariance,
                                        quantile)
from studies.diagnosis.ladder import FormShare
from studies.diagnosis.sleeve_rung import SleeveForm
from studies.diagnosis.openworld import characterise_column, named_features
from studies.diagnosis.problem import Problem
from studies.model.effects.generalised import GENERALISED

#: degrees of freedom of an estimated noise variance per compared entry (module docstring)
NU_SHARE = 0.5
#: a fitted value within this share of its parameter's range from a bound is at the bound
AT_BOUND_RTOL = 1e-6


@dataclass(frozen=True)
class ColumnFit:
    """One column of the extended model: reduced chi-square and its p (F against the estimated
    noise), held-out RMSE in noise units and its p, the smallest p of the residual tests
    (bias, lag-1, smoother)."""
    column: str
    chi2_reduced: float
    chi2_p: float
    heldout_rmse_sigma: float
    heldout_p: float
    residual_tests_p: float


@dataclass(frozen=True)
class Left:
    """Structure the extended model leaves in one column: the test that finds it, its adjusted
    p, the RMS misfit beyond the noise (noise units), the condition the residual depends on most
    and the residual's range along it (noise units), one sentence."""
    column: str
    test: str
    p_adjusted: float
    size_sigma: float
    against: str | None
    range_sigma: float | None
    text: str


@dataclass(frozen=True)
class AtBound:
    """A fitted parameter the data want at or beyond a bound that is not its off value
    (`at_bound`): its value, the bound (the parameter's own number), one sentence, and its
    standard uncertainty (None when not stated)."""
    effect: str
    parameter: str
    value: float
    bound: float
    text: str
    uncertainty: float | None = None


@dataclass(frozen=True)
class GoodnessOfFit:
    """The extended model's goodness of fit (module docstring)."""
    columns: dict[str, ColumnFit]
    p_adjusted: float              # chi-square tests, Bonferroni over the columns
    leaves_structure: bool         # this or the residual tests below alpha_residual
    left: list[Left]


def _f_sf(x: float, d1: float, d2: float | None) -> float:
    """P(F(d1, d2) > x); d2 None: a known noise level, P(chi2(d1) / d1 > x)."""
    if d2 is None:
        return float(stats.chi2.sf(x * d1, d1))
    return float(stats.f.sf(x, d1, d2))


def goodness(pb: Problem, fit: Fit, heldout_z: np.ndarray, n_params: int,
             desc: Residuals) -> GoodnessOfFit:
    """The goodness of fit of `fit` (its held-out standardised residuals `heldout_z`, its
    residual description `desc`, `n_params` fitted parameters shared by the columns)."""
    cols, pvals = {}, []
    for j, c in enumerate(pb.columns):
        sel = pb.entry_col == j
        n = int(sel.sum())
        dof = max(n - n_params * n / pb.N, 1.0)
        nu = None if c in pb.noise.given else max(NU_SHARE * n, 1.0)
        chi2_red = float(fit.z[sel] @ fit.z[sel]) / dof
        ms_ho = float(heldout_z[sel] @ heldout_z[sel]) / n
        d = desc.columns[c]
        cf = ColumnFit(c, chi2_red, _f_sf(chi2_red, dof, nu), math.sqrt(ms_ho),
                       _f_sf(ms_ho, n, nu), min(d.bias_p, d.lag1_p, d.smoother_p_used))
        cols[c] = cf
        pvals.append(cf.chi2_p)
    m = len(pvals)
    p_adj = min(1.0, min(pvals) * m) if pvals else 1.0
    a = pb.th["alpha_residual"]
    leaves = bool(p_adj < a or desc.p_min_adjusted < a)
    left = _left(pb, fit, cols, m, len(pb.columns) * 3, a) if leaves else []
    return GoodnessOfFit(cols, p_adj, leaves, left)


def _left(pb: Problem, fit: Fit, cols: dict[str, ColumnFit], m_fit: int, m_res: int,
          a: float) -> list[Left]:
    """Per column whose tests fire (adjusted p below `a`): what is left and where."""
    feats, _, _ = named_features(pb.conditions)
    out = []
    for c, cf in cols.items():
        tests = [("chi-square against the noise", cf.chi2_p * m_fit),
                 ("residual tests (bias, lag-1, smoother)", cf.residual_tests_p * m_res)]
        test, p = min(tests, key=lambda t: t[1])
        if p >= a:
            continue
        m = pb.valid[c]
        r = pb.scaled_residual(c, fit.pred[c])[m]
        ch = characterise_column(c, r, {k: v[m] for k, v in feats.items()}, pb.blocks[m],
                                 float(pb.noise.sigma_w[c]), float(pb.noise.rho[c]))
        size = math.sqrt(max(cf.chi2_reduced - 1.0, 0.0))
        against = ch.selected[0] if ch.selected else None
        rng = (abs(ch.range_effect[against]) / pb.noise.sigma[c]) if against else None
        where = (f", mostly against {against} ({rng:.2g} sigma over the data)" if against
                 else ", not along any named condition")
        out.append(Left(c, test, float(min(p, 1.0)), size, against, rng,
                        f"{c}: {test} (adjusted p = {p:.2g}); misfit beyond the noise "
                        f"{size:.2g} sigma RMS{where}"))
    return out


def at_bound(pb: Problem, fit: Fit) -> list[AtBound]:
    """The fitted effect parameters of `fit` (its candidate's and the accepted causes') the data
    want at or beyond a bound that is not their off value (module docstring): the value on the
    bound (within AT_BOUND_RTOL of the parameter's range), or the estimate with the bounds
    released (`released_estimate`: one Gauss-Newton step from the fit over the directions the
    data determine) at or beyond it. A value inside its bounds at a converged fit is where the
    data put it, however wide its interval (within one standard uncertainty of a
    bound refused a weakly identified true cause, 10 +- 8 on [-20, 20], in about 40 % of
    draws); the step only catches a fit stopped short of the bound it is pushing against. A
    parameter whose interval at the stated level (`interval.LEVEL`) holds its off value is not
    moved by the data (an unlogged moment's radial load fitted 0.03 +- 1.1e4 N on 0..6013 N),
    so only the value itself counts for it, and so for a parameter along a direction the data do
    not determine. Bounds in the parameter's own units (`_own_bounds`); a switch's `share` at 1
    is the form itself (`ladder.FormShare`), not a bound the data push against."""
    sp = fit.space
    k = len(sp.eff_params) + len(sp.base_params)
    u = np.clip(fit.u, sp.lo, sp.hi)
    cov, ok = parameter_covariance(fit.J, fit.chi2)
    released = released_estimate(fit)
    q = quantile(LEVEL)
    out = []
    for i, (name, p) in enumerate(sp.eff_params + sp.base_params):
        lo, hi = _own_bounds(pb, sp, i, name, p)
        value = float(sp.origin[i] + sp.scale[i] * u[i])
        off = _off(pb, name, p)
        sd = float(math.sqrt(cov[i, i]) * abs(sp.scale[i])) if ok[i] else None
        tol = AT_BOUND_RTOL * max(hi - lo, 1e-300)
        moved = sd is not None and (off is None or abs(value - off) > q * sd)
        want = (float(sp.origin[i] + sp.scale[i] * released[i])
                if moved and np.isfinite(released[i]) else value)
        for side, bound in enumerate((lo, hi)):
            if _is_form_itself(pb, name, p, side) or (off is not None and abs(bound - off) <= tol):
                continue
            beyond = (want <= bound + tol) if side == 0 else (want >= bound - tol)
            if abs(value - bound) <= tol or beyond:
                out.append(AtBound(name, p, value, bound,
                                   _bound_text(name, p, lo, hi, side, value, sd), sd))
    return out


def released_estimate(fit: Fit) -> np.ndarray:
    """The fit's scaled coordinates with every bound released, to first order: one Gauss-Newton
    step u - J+ z from the fit (Nocedal & Wright, Numerical Optimization, 2nd ed., ch. 10.3),
    J+ the pseudo-inverse over the singular directions the data determine (those of
    `interval.parameter_covariance`, s_j >= SINGULAR_RTOL s_0); NaN for a coordinate with a
    component along a direction they do not. At a converged fit inside the bounds the step is
    zero (J' z = 0); at a bound the data push against it carries the coordinate beyond."""
    J = np.asarray(fit.J, float)
    u = np.asarray(fit.u, float)
    if J.size == 0:
        return u.copy()
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    tiny = s < SINGULAR_RTOL * s[0] if s.size and s[0] > 0 else np.ones(s.size, bool)
    inv = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, s))
    step = -(Vt.T * inv) @ (U.T @ np.asarray(fit.z, float))
    out = u + step
    out[np.any(tiny[:, None] & (np.abs(Vt) > 1e-6), axis=0)] = np.nan
    return out


def _own_bounds(pb: Problem, sp, i: int, name: str, p: str) -> tuple[float, float]:
    """Bounds of parameter i of the fit's space in the parameter's own units: the effect's own
    `bounds[p]` when the space's rescaled bounds (origin + scale x lo, which does not round-trip
    for some values) are those within rounding (the space of `Problem.space` takes them from
    there), else the rescaled ones (a space of its own)."""
    lo = float(sp.origin[i] + sp.scale[i] * sp.lo[i])
    hi = float(sp.origin[i] + sp.scale[i] * sp.hi[i])
    e = _effect(pb, name)
    own = getattr(e, "bounds", {}).get(p) if e is not None else None
    if own is not None:
        rnd = 1e-9 * max(abs(hi - lo), abs(lo), abs(hi), 1e-300)
        if abs(own[0] - lo) <= rnd and abs(own[1] - hi) <= rnd:
            return float(own[0]), float(own[1])
    return lo, hi


def _effect(pb: Problem, name: str):
    """The effect object of `name` among the problem's candidates and accepted causes (None)."""
    return next((e for e in pb.candidates if e.name == name), None) or next(
        (a.effect for a in pb.base if a.effect.name == name), None)


#: bounds of listed effects that are a rung of the model-form ladder, not a limit the data push
#: against: the preload path's compliance at its soft bound, 5e4 um/kN, is the `preload_spring`
#: rung (`ladder.ladder`: a spring preload is carried by preload_path_compliance, "as soft as a
#: wave spring"); (effect, parameter) -> which bound (0 lower, 1 upper)
FORM_LIMITS = {("preload_path_compliance", "extra_compliance_um_per_kN"): 1,
               # the transient conduction rung (`transient_rung`): a shaft bore without a film
               # (a closed cavity), and a mount joined as one body with the housing (the joint's
               # bound, 1e4 W/(m^2 K) over the face, against the housing's own conduction across
               # its wall: seed 000's titanium housing 2 pi k L / ln(r_o / r_i) = 5.2 W/K, the
               # bound 55 W/K: beyond it the joint changes nothing)
               ("thermal_transient_fe", "bore_film_ratio"): 0,
               ("thermal_transient_fe", "G_face_W_K"): 1,
               # the mount's capacity at its top, C_MOUNT_MAX_J_K (500 kg of cast iron), and its
               # conductance to the environment at its top (1 m^2 in natural convection, 25 W/K):
               # no file states the mount, and more of either is physical (a machine bed or floor;
               # a base plate held at the chamber's temperature): the same form towards its limit
               # (a mount at its start temperature; a mount at the ambient), not another cause.
               # Not a limit reached: on seed 000's cycles (G_face a tenth of its top) 100 x the
               # bound still moves the parts by 1.6 K (capacity) and 5.1 K (G_env)
               ("thermal_transient_fe", "C_mount_J_K"): 1,
               ("thermal_transient_fe", "G_env_W_K"): 1}


def _is_form_itself(pb: Problem, name: str, p: str, side: int) -> bool:
    """A switch rung's `share` at its upper bound 1: the form exactly (`ladder.FormShare`,
    `sleeve_rung.SleeveForm`); a listed effect's bound that is a ladder form (`FORM_LIMITS`).
    Told by the side of the bound (0 lower, 1 upper), never by comparing rescaled values."""
    e = _effect(pb, name)
    if e is None:
        return False
    if FORM_LIMITS.get((getattr(e, "family", None) or e.name, p)) == side:
        return True
    return isinstance(e, (FormShare, SleeveForm)) and p == "share" and side == 1


def _off(pb: Problem, name: str, p: str) -> float | None:
    """The off value of parameter p of effect `name` (an accepted cause, a candidate or a
    generalised form), None when unknown."""
    effects = [a.effect for a in pb.base] + list(pb.candidates) + list(GENERALISED.values())
    e = next((e for e in effects if e.name == name), None)
    return None if e is None else float(e.off[p])


def _bound_text(effect: str, p: str, lo: float, hi: float, side: int,
                value: float | None = None, sd: float | None = None) -> str:
    bound = (lo, hi)[side]
    more = "more" if side == 1 else "less"
    at = ("" if value is None else
          f" (fitted {value:.4g}" + (f" +- {sd:.2g}" if sd is not None else "") + ")")
    if effect.startswith("interference_error"):
        return (f"{effect}.{p} = {bound:.4g}{at} at the edge of the tolerance band [{lo:.4g}, "
                f"{hi:.4g}]: the fit wants {more} than the tolerance band allows: as-built error "
                "outside the band?")
    return (f"{effect}.{p} = {bound:.4g}{at} at its bound [{lo:.4g}, {hi:.4g}]: the fit wants "
            f"{more} than the bound allows: a larger effect than the physics or data sheet "
            "allow, or another cause?")
