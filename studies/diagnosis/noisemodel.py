"""A sensor's noise as the user states it (`diagnose --noise COLUMN=REL%[+ABS]`, or per-row
`sigma_<column>` columns of the measured file; docs/cli.md "diagnose"), and the check of a
statement against the data.

A stated noise model is a weight, not a verdict: the per-row standard
uncertainties give the likelihood's weights (weighted least squares; the AR(1) and spike handling
of the diagnosis act on the residual divided by them), while the overall level is still
estimated from the data and compared with the statement (`consistency`); a statement the data
contradict is reported, not trusted.

A statement `REL%+ABS` is the standard uncertainty of one reading y: u(y) = REL/100 |y| + ABS
(column unit), the two parts added as an instrument's data sheet adds "% of reading" and "% of
range / counts" (the bound of the sum of two fully correlated parts; JCGM 100:2008, GUM, 5.2.2
with correlation 1); `ABS` alone is an additive one. The reading is the measured value, in a
time series its running mean over a few rows (`calibration.stated_readings`): weights taken
from the noisy reading itself correlate with the noise and bias a weighted fit towards low
readings by about 2 REL^2 of the reading (Carroll & Ruppert, Transformation and Weighting in
Regression, Chapman & Hall 1988, ch. 2.3), 0.05 % at 1.5 %; the model's prediction, the usual
cure, is no reading when the model is what is in question (a baseline that misses a lag can be
5 x off in torque where the data are).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Mapping

import numpy as np
from scipy import stats

from studies.model.table import TableError

#: prefix of a measured file's per-row standard-uncertainty columns (`sigma_torque_Nmm`)
SIGMA_PREFIX = "sigma_"
#: two-sided level of the check of a stated noise level against the data's (`consistency`)
CONSISTENCY_ALPHA = 0.01
#: effective degrees of freedom per entry of the second-difference noise estimate of white noise
#: (`stats.noise_sigma`): the squared second differences d_t = e_t - 2 e_(t+1) + e_(t+2) have
#: correlations -2/3 (lag 1) and 1/6 (lag 2), so their mean has the variance of a chi-square
#: mean over n / (1 + 2 (2/3)^2 + 2 (1/6)^2) = n / 1.944 entries (Isserlis' theorem for the
#: squares of correlated Gaussians)
SECOND_DIFFERENCE_DOF_SHARE = 1.0 / (1.0 + 2.0 * (2.0 / 3.0) ** 2 + 2.0 * (1.0 / 6.0) ** 2)

_SPEC = re.compile(r"^\s*(?:(?P<rel>[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*%)?\s*"
                   r"(?:(?(rel)\+)\s*(?P<abs>[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?))?\s*$")


class NoiseSpecError(TableError):
    """A noise statement that cannot be used (one-line message naming the flag or file; a
    `TableError`, so the command line prints it and exits with code 2)."""


@dataclass(frozen=True)
class StatedNoise:
    """The standard uncertainty of one column's readings as stated: `source` "stated" (a share
    `rel` of the reading plus `abs_unit` in the column's unit) or "column" (per-row values
    `rows`, column unit, from the measured file's `sigma_<column>`)."""
    source: str
    rel: float = 0.0
    abs_unit: float = 0.0
    rows: np.ndarray | None = None

    def row_sigma(self, reading: np.ndarray) -> np.ndarray:
        """Per-row standard uncertainty (column unit) at the readings `reading` (column unit;
        ignored for a "column" statement): rel |reading| + abs (module docstring)."""
        if self.rows is not None:
            return np.asarray(self.rows, float)
        return self.rel * np.abs(np.asarray(reading, float)) + self.abs_unit


def parse_noise_spec(column: str, spec) -> StatedNoise:
    """One `--noise COLUMN=SPEC` value: "1.5%+0.2" (1.5 % of reading plus 0.2 column units),
    "1.5%", "0.5" (absolute), or a number (absolute). NoiseSpecError on anything else, on a
    negative part or on a statement of zero."""
    where = f"--noise {column}={spec}"
    if isinstance(spec, (int, float, np.floating, np.integer)) and not isinstance(spec, bool):
        rel, ab = 0.0, float(spec)
    else:
        m = _SPEC.match(str(spec))
        if m is None or (m.group("rel") is None and m.group("abs") is None):
            raise NoiseSpecError(f"{where}: not REL%[+ABS] or ABS (e.g. 1.5%+0.2: 1.5 % of "
                                 "reading plus 0.2 in the column's unit)")
        rel = float(m.group("rel")) / 100.0 if m.group("rel") is not None else 0.0
        ab = float(m.group("abs")) if m.group("abs") is not None else 0.0
    if not (math.isfinite(rel) and math.isfinite(ab)) or rel < 0.0 or ab < 0.0:
        raise NoiseSpecError(f"{where}: a standard uncertainty cannot be negative")
    if rel == 0.0 and ab == 0.0:
        raise NoiseSpecError(f"{where}: a standard uncertainty of zero would give the rows "
                             "infinite weight")
    return StatedNoise("stated", rel=rel, abs_unit=ab)


def parse_noise_arg(arg: str) -> tuple[str, str]:
    """`--noise COLUMN=SPEC` -> (COLUMN, SPEC); NoiseSpecError without the '='."""
    col, eq, spec = str(arg).partition("=")
    if not eq or not col.strip() or not spec.strip():
        raise NoiseSpecError(f"--noise {arg}: need COLUMN=REL%[+ABS] (e.g. torque_Nmm=1.5%+0.2)")
    return col.strip(), spec.strip()


def stated_noise(noise: Mapping[str, object] | None, columns, sigma_columns: Mapping[str, np.ndarray],
                 where) -> dict[str, StatedNoise]:
    """The stated noise of the measured columns `columns`: from `noise` ({column: spec},
    `parse_noise_spec`) and from the per-row `sigma_columns` ({column: values}, already checked
    by `check_sigma_columns`). A column named in `noise` that is not measured, or stated both
    ways, is a NoiseSpecError (`where` names the measured table)."""
    out: dict[str, StatedNoise] = {}
    for c, spec in (noise or {}).items():
        if c not in columns:
            raise NoiseSpecError(f"--noise {c}={spec}: {c} is not a measured output column "
                                 f"(measured: {', '.join(columns)})")
        if c in sigma_columns:
            raise NoiseSpecError(f"--noise {c}={spec}: {where} also has {SIGMA_PREFIX}{c}; "
                                 "state the noise one way")
        out[c] = parse_noise_spec(c, spec)
    for c, v in sigma_columns.items():
        out[c] = StatedNoise("column", rows=np.asarray(v, float))
    return out


def check_sigma_columns(cols: Mapping[str, np.ndarray], measured_names, where) -> dict[str, np.ndarray]:
    """The `sigma_<column>` columns of a checked measured table (finite already: `check_columns`)
    as {column: values}: each must name a measured output column and be > 0 in every row
    (a zero would give its row infinite weight). One-line NoiseSpecError naming the table, the
    line (file rows) or row, and the column."""
    line = cols.get("_line")
    label = (lambda i: f"line {int(line[i])}") if line is not None else (lambda i: f"row {i + 1}")
    out = {}
    for name, v in cols.items():
        if not name.startswith(SIGMA_PREFIX):
            continue
        c = name[len(SIGMA_PREFIX):]
        if c not in measured_names:
            raise NoiseSpecError(f"{where}: column '{name}': no measured column '{c}' beside it")
        v = np.asarray(v, float)
        bad = np.flatnonzero(~(v > 0.0))
        if bad.size:
            raise NoiseSpecError(f"{where}: {label(bad[0])}, column '{name}': {v[bad[0]]:g}: a "
                                 "standard uncertainty must be > 0")
        out[c] = v
    return out


@dataclass(frozen=True)
class Consistency:
    """A stated level against the data: `ratio` = the data's noise level / the stated one (RMS
    over the compared rows), its (1 - CONSISTENCY_ALPHA) interval `ratio_lo` .. `ratio_hi`, the
    effective degrees of freedom of the data's estimate, and whether 1 lies inside."""
    ratio: float
    ratio_lo: float
    ratio_hi: float
    dof: float
    consistent: bool


def consistency(ratio: float, n_entries: int, rho: float = 0.0,
                alpha: float = CONSISTENCY_ALPHA) -> Consistency:
    """Is a data's noise level `ratio` times the stated one consistent with the statement? The
    second-difference estimate s^2 of a noise of variance sigma^2 is about sigma^2 chi2(nu) / nu
    with nu = SECOND_DIFFERENCE_DOF_SHARE n entries (white noise), and nu (1 - rho) / (1 + rho)
    for AR(1) noise of coefficient rho (the effective sample size of a variance estimate, Bayley
    & Hammersley 1946, J. R. Statist. Soc. Suppl. 8); the statement stands when the ratio's
    two-sided 1 - alpha interval sqrt(nu / chi2_(1-a/2, nu)) .. sqrt(nu / chi2_(a/2, nu))
    times `ratio` holds 1."""
    rho = min(max(float(rho), 0.0), 0.99)
    nu = max(SECOND_DIFFERENCE_DOF_SHARE * int(n_entries) * (1.0 - rho) / (1.0 + rho), 1.0)
    lo = ratio * math.sqrt(nu / stats.chi2.ppf(1.0 - alpha / 2.0, nu))
    hi = ratio * math.sqrt(nu / stats.chi2.ppf(alpha / 2.0, nu))
    return Consistency(float(ratio), float(lo), float(hi), float(nu), bool(lo <= 1.0 <= hi))
