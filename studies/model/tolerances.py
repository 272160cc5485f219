"""Fit tolerances of an assembly: limit deviations, worst case and Monte Carlo through the exact
model (each sample's fits and contact state solved by the pipeline, nothing linearised).

Conventions (docs/cli.md "tolerance"). Deviations in um from the nominal diameters of the fits
(`Assembly.fit_diameter_mm`: shaft seat and bearing bore; the bore the outer rings sit in and the
bearing OD; a sleeve's or cartridge's outside and the bore it sits in). Diametral interference of
a sample:

    inner = fits.inner_interference_um + (shaft deviation - ring bore deviation)
    outer = fits.outer_interference_um + (ring OD deviation - housing deviation)
    <layer> = fits.<layer>_interference_um + (<layer>_shaft deviation - <layer>_bore deviation)

(<layer>: sleeve, cartridge; `<layer>_shaft` is the layer's outside, the member inside its fit.)

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

from dataclasses import MISSING, dataclass, fields

import numpy as np

from analytic.tolerances import iso286_limits_um, iso492_limits_um
from studies.model.config_schema import LAYERS, TOLERANCE_SURFACES

SURFACES = TOLERANCE_SURFACES
#: every fit an assembly may have, from the inside out (the layers only when present)
FITS = ("inner", "outer", *LAYERS)
#: sign of each surface's deviation in its fit's interference, and the fit
SURFACE_FIT = {"inner_shaft": ("inner", +1.0), "inner_ring_bore": ("inner", -1.0),
               "outer_ring_od": ("outer", +1.0), "outer_housing": ("outer", -1.0),
               **{f"{n}_shaft": (n, +1.0) for n in LAYERS},
               **{f"{n}_bore": (n, -1.0) for n in LAYERS}}
#: surfaces whose ISO 286 class is a shaft's (lower case); the other ISO 286 ones are holes
SHAFT_SURFACES = ("inner_shaft", *(f"{n}_shaft" for n in LAYERS))


@dataclass(frozen=True)
class SampleResults:
    """What the Monte Carlo keeps per sample and condition: (S, C) arrays, samples by
    conditions (`tolerance_samples.evaluate`); a sleeve's / cartridge's interference and fit
    pressure only for an assembly with that layer (None otherwise). Named columns only at the
    file edge (`columns`)."""
    interference_inner_um: np.ndarray
    interference_outer_um: np.ndarray
    fit_pressure_inner_MPa: np.ndarray
    fit_pressure_outer_MPa: np.ndarray
    preload_N: np.ndarray
    contact_angle_deg: np.ndarray
    max_contact_pressure_MPa: np.ndarray
    torque_Nmm: np.ndarray
    interference_sleeve_um: np.ndarray | None = None
    fit_pressure_sleeve_MPa: np.ndarray | None = None
    interference_cartridge_um: np.ndarray | None = None
    fit_pressure_cartridge_MPa: np.ndarray | None = None

    def present(self) -> tuple[str, ...]:
        """The quantities held: QUANTITIES, then the layers' when present."""
        return QUANTITIES + tuple(q for q in LAYER_QUANTITIES if getattr(self, q) is not None)

    def columns(self) -> dict[str, np.ndarray]:
        """{name: (S, C) array} of `present`, for the writers (tolerance.json, samples.csv)."""
        return {q: getattr(self, q) for q in self.present()}

    def fit_pressure_MPa(self, fit: str) -> np.ndarray:
        """(S, C) mean pressure of a fit (inner, outer, sleeve, cartridge), MPa."""
        return getattr(self, f"fit_pressure_{fit}_MPa")

    def interference_um(self, fit: str) -> np.ndarray:
        """(S, C) free diametral interference of a fit at the conditions, um."""
        return getattr(self, f"interference_{fit}_um")

    def map(self, fn) -> "SampleResults":
        """The same quantities with `fn(array)` applied to each (rows put in order, joined)."""
        return SampleResults(**{q: fn(getattr(self, q)) for q in self.present()})

    @staticmethod
    def concatenate(parts: "list[SampleResults]") -> "SampleResults":
        """The samples of `parts` one after the other (each quantity joined along the samples)."""
        return SampleResults(**{q: np.concatenate([getattr(p, q) for p in parts])
                                for q in parts[0].present()})


#: quantities the Monte Carlo keeps per sample and condition (the fields of `SampleResults`
#: every assembly has), and those of a sleeve / cartridge
QUANTITIES = tuple(f.name for f in fields(SampleResults) if f.default is MISSING)
LAYER_QUANTITIES = tuple(f.name for f in fields(SampleResults) if f.default is not MISSING)


def fits_of(asm) -> tuple[str, ...]:
    """The fits of an assembly, from the inside out: inner, outer and its sleeve / cartridge."""
    return ("inner", "outer", *(n for n, _ in asm.layers()))


def deviation_limits_um(asm) -> dict[str, tuple[float, float]]:
    """(lower, upper) limit deviation in um of every toleranced surface (others absent)."""
    f = asm.fits
    present = fits_of(asm)
    out = {}
    for s in SURFACES:
        fit = SURFACE_FIT[s][0]
        if fit not in present:               # a layer's keys without the layer: config_checks
            continue
        cls, lim = getattr(f, f"{s}_class"), getattr(f, f"{s}_deviation_um")
        d = asm.fit_diameter_mm(fit)
        if lim:
            out[s] = (float(lim[0]), float(lim[1]))
        elif cls:
            key = f"fits.{s}_class"
            try:
                if s in ("inner_ring_bore", "outer_ring_od"):
                    out[s] = iso492_limits_um(cls, d, "bore" if s == "inner_ring_bore" else "od")
                else:
                    lo, hi = iso286_limits_um(cls, d)
                    if (s in SHAFT_SURFACES) != cls[0].islower():
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
    for fit in fits_of(asm):
        nominal = getattr(asm.fits, f"{fit}_interference_um")
        lo = hi = float(nominal)
        for s, (f, sign) in SURFACE_FIT.items():
            if f == fit and s in lim:
                a, b = (sign * lim[s][0], sign * lim[s][1])
                lo, hi = lo + min(a, b), hi + max(a, b)
        bands.append(InterferenceBand(fit, float(nominal), lo, hi))
    return bands


def designed_closed(asm) -> dict[str, bool]:
    """The design intent of each fit of the assembly (inner, outer, its sleeve / cartridge) at
    the reference temperature: closed (True) when the mean assembly (every deviation at mid-band,
    `Assembly.mean_fit_um`) has interference, open (False) when it is designed with clearance (or
    line-to-line). `tolerance` counts a fit as failed only when it leaves this state; `simulate`'s
    fit_open checks (studies/model/checks.py) flag only the fits designed closed."""
    return {fit: bool(asm.mean_fit_um(fit) > 0.0) for fit in fits_of(asm)}


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


def fit_offsets_um(deviations: dict[str, np.ndarray], n: int) -> dict[str, np.ndarray]:
    """Offsets of every fit's interference (FITS) from its nominal value (um), (n,) each."""
    off = {fit: np.zeros(n) for fit in FITS}
    for s, dev in deviations.items():
        fit, sign = SURFACE_FIT[s]
        off[fit] = off[fit] + sign * dev
    return off


def interference_offsets_um(deviations: dict[str, np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
    """Offsets of the inner and outer interference from their nominal values (um)."""
    off = fit_offsets_um(deviations, n)
    return off["inner"], off["outer"]


def layer_offsets_um(asm, deviations: dict[str, np.ndarray], n: int) -> np.ndarray | None:
    """(n, n_layers) offsets of the sleeve's / cartridge's interference from their nominal values
    (um; the layers of `Assembly.layers`), or None for an assembly without them."""
    if not asm.layers():
        return None
    off = fit_offsets_um(deviations, n)
    return np.column_stack([off[name] for name, _ in asm.layers()])


def mid_band_fit_offsets_um(asm) -> dict[str, float]:
    """Interference offset of every fit (FITS) with every deviation at the middle of its band."""
    mid = {s: np.array([0.5 * (lo + hi)]) for s, (lo, hi) in deviation_limits_um(asm).items()}
    return {fit: float(v[0]) for fit, v in fit_offsets_um(mid, 1).items()}


def mid_band_offsets_um(asm) -> tuple[float, float]:
    """Interference offsets (inner, outer) with every deviation at the middle of its band."""
    mid = mid_band_fit_offsets_um(asm)
    return mid["inner"], mid["outer"]


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
