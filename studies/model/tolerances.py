"""Fit tolerances of an assembly: limit deviations, worst case and Monte Carlo through the exact
model (each sample's fits and contact state solved by the pipeline, nothing linearised).

Conventions (docs/cli.md "tolerance"). Deviations in um from the nominal diameters (shaft seat
and bearing bore: `shaft.seat_diameter_mm`; housing bore and bearing OD:
`housing.bore_diameter_mm`). Diametral interference of a sample:

    inner = fits.inner_interference_um + (shaft deviation - ring bore deviation)
    outer = fits.outer_interference_um + (ring OD deviation - housing deviation)

each deviation drawn independently: uniform within its limits, or normal with the limits at
+-3 sigma (`[fits] distribution`). The position preload `[preload] assembled_N` is the design
value for the mean fits (every deviation at the middle of its band): the spacers are ground for
the expected fits, not for the actual ones, so the assembly state that fixes the preload offset
uses the mid-band interferences, and a sample's fits then move its preload.

The linear estimate beside the Monte Carlo is what a tolerance-stack tool gives: each output
linearised at the mid-band fits (central differences over one tenth of each band), its standard
deviation from the summed variances, a normal distribution, P(output beyond a limit) = Phi(-z).

The samples' evaluation through the pipeline is `studies/model/tolerance_samples.py` (above the
pipeline; this module sits below it, beside the config that reads its bands).
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from analytic.tolerances import iso286_limits_um, iso492_limits_um

SURFACES = ("inner_shaft", "inner_ring_bore", "outer_housing", "outer_ring_od")
#: sign of each surface's deviation in its fit's interference, and the fit
SURFACE_FIT = {"inner_shaft": ("inner", +1.0), "inner_ring_bore": ("inner", -1.0),
               "outer_ring_od": ("outer", +1.0), "outer_housing": ("outer", -1.0)}


@dataclass(frozen=True)
class SampleResults:
    """What the Monte Carlo keeps per sample and condition: (S, C) arrays, samples by
    conditions (`tolerance_samples.evaluate`). Named columns only at the file edge (`columns`)."""
    interference_inner_um: np.ndarray
    interference_outer_um: np.ndarray
    fit_pressure_inner_MPa: np.ndarray
    fit_pressure_outer_MPa: np.ndarray
    preload_N: np.ndarray
    contact_angle_deg: np.ndarray
    max_contact_pressure_MPa: np.ndarray
    torque_Nmm: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """{QUANTITIES name: (S, C) array}, for the writers (tolerance.json, samples.csv)."""
        return {q: getattr(self, q) for q in QUANTITIES}

    def map(self, fn) -> "SampleResults":
        """The same quantities with `fn(array)` applied to each (rows put in order, joined)."""
        return SampleResults(**{q: fn(getattr(self, q)) for q in QUANTITIES})

    @staticmethod
    def concatenate(parts: "list[SampleResults]") -> "SampleResults":
        """The samples of `parts` one after the other (each quantity joined along the samples)."""
        return SampleResults(**{q: np.concatenate([getattr(p, q) for p in parts])
                                for q in QUANTITIES})


#: quantities the Monte Carlo keeps per sample and condition (the fields of `SampleResults`)
QUANTITIES = tuple(f.name for f in fields(SampleResults))


def deviation_limits_um(asm) -> dict[str, tuple[float, float]]:
    """(lower, upper) limit deviation in um of every toleranced surface (others absent)."""
    f = asm.fits
    d_in, d_out = asm.shaft.seat_diameter_mm, asm.outer_seat_diameter_mm
    out = {}
    for s in SURFACES:
        cls, lim = getattr(f, f"{s}_class"), getattr(f, f"{s}_deviation_um")
        d = d_in if s.startswith("inner") else d_out
        if lim:
            out[s] = (float(lim[0]), float(lim[1]))
        elif cls:
            key = f"fits.{s}_class"
            try:
                if s in ("inner_ring_bore", "outer_ring_od"):
                    out[s] = iso492_limits_um(cls, d, "bore" if s == "inner_ring_bore" else "od")
                else:
                    lo, hi = iso286_limits_um(cls, d)
                    if (s == "inner_shaft") != cls[0].islower():
                        raise ValueError(f"'{cls}' is a {'hole' if cls[0].isupper() else 'shaft'} "
                                         "class (shafts lower case, holes upper case)")
                    out[s] = (lo, hi)
            except ValueError as exc:
                raise ValueError(f"{key}: {exc.args[0]}") from None
    return out


def has_tolerances(asm) -> bool:
    return bool(deviation_limits_um(asm))


@dataclass(frozen=True)
class InterferenceBand:
    """Worst-case limits of a fit's diametral interference (um) from the limit deviations."""
    fit: str
    nominal_um: float
    lower_um: float
    upper_um: float


def worst_case_bands(asm) -> list[InterferenceBand]:
    """Each fit's interference range: nominal + the extreme deviations (hand arithmetic of the
    limits: shaft upper - bore lower is the tightest inner fit, and so on)."""
    lim = deviation_limits_um(asm)
    bands = []
    for fit, nominal in (("inner", asm.fits.inner_interference_um),
                         ("outer", asm.fits.outer_interference_um)):
        lo = hi = float(nominal)
        for s, (f, sign) in SURFACE_FIT.items():
            if f == fit and s in lim:
                a, b = (sign * lim[s][0], sign * lim[s][1])
                lo, hi = lo + min(a, b), hi + max(a, b)
        bands.append(InterferenceBand(fit, float(nominal), lo, hi))
    return bands


def designed_closed(asm) -> dict[str, bool]:
    """The design intent of each fit (inner, outer) at the reference temperature: closed (True)
    when the mean assembly (every deviation at mid-band, `Assembly.mean_fits_um`) has
    interference, open (False) when it is designed with clearance (or line-to-line). `tolerance`
    counts a fit as failed only when it leaves this state (the rule of `simulate`'s
    fit_open checks, studies/model/checks.py, which flag only a fit assembled with interference)."""
    return {fit: bool(v > 0.0) for fit, v in zip(("inner", "outer"), asm.mean_fits_um())}


def sample_deviations_um(asm, n: int, seed: int) -> dict[str, np.ndarray]:
    """n independent draws per toleranced surface (numpy PCG64 with `seed`)."""
    rng = np.random.default_rng(seed)
    out = {}
    for s, (lo, hi) in deviation_limits_um(asm).items():
        if asm.fits.distribution == "normal":
            out[s] = rng.normal(0.5 * (lo + hi), (hi - lo) / 6.0, n)
        else:
            out[s] = rng.uniform(lo, hi, n)
    return out


def interference_offsets_um(deviations: dict[str, np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
    """Offsets of the inner and outer interference from their nominal values (um)."""
    off = {"inner": np.zeros(n), "outer": np.zeros(n)}
    for s, dev in deviations.items():
        fit, sign = SURFACE_FIT[s]
        off[fit] = off[fit] + sign * dev
    return off["inner"], off["outer"]


def mid_band_offsets_um(asm) -> tuple[float, float]:
    """Interference offsets (inner, outer) with every deviation at the middle of its band."""
    mid = {s: np.array([0.5 * (lo + hi)]) for s, (lo, hi) in deviation_limits_um(asm).items()}
    i, o = interference_offsets_um(mid, 1)
    return float(i[0]), float(o[0])


def probability(flags: np.ndarray) -> tuple[float, float]:
    """Monte Carlo probability of a boolean event per sample and its standard error
    sqrt(p (1 - p) / S) (binomial)."""
    flags = np.asarray(flags, bool)
    p = float(flags.mean())
    return p, float(np.sqrt(p * (1 - p) / flags.size))


def linear_probability(value_nominal: float, gradient: np.ndarray, sigma: np.ndarray,
                       limit: float, upper: bool) -> float:
    """P(output beyond `limit`) of the linear-normal estimate: output ~ N(value, sum (g s)^2)."""
    sd = float(np.sqrt(np.sum((np.asarray(gradient) * np.asarray(sigma)) ** 2)))
    if sd == 0.0:
        return float((value_nominal > limit) if upper else (value_nominal <= limit))
    from scipy import stats         # here, not at the top: every assembly load imports this module

    z = (limit - value_nominal) / sd
    return float(stats.norm.sf(z) if upper else stats.norm.cdf(z))


def surface_sigma_um(asm) -> dict[str, float]:
    """Standard deviation of each surface's deviation: width/sqrt(12) uniform, width/6 normal."""
    k = 6.0 if asm.fits.distribution == "normal" else np.sqrt(12.0)
    return {s: (hi - lo) / k for s, (lo, hi) in deviation_limits_um(asm).items()}
